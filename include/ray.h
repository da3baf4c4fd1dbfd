/*
** ray.h -- the whole public interface of libray, a small C99 ray-tracing
** library.
**
** This header is the reference documentation; the man pages (ray(7) and
** the ray_*(3) pages) are derived from it.
**
** Conventions that hold for every function below:
**
**   * Precision is double throughout.
**   * A ray is p(t) = org + t*dir on the OPEN interval tmin < t < tmax.
**     "dir" need not be normalised, so t is measured in units of |dir|.
**     Results exactly at tmin or tmax are not hits.
**   * The intersection functions (ray_sphere, ray_triangle,
**     ray_triangle_watertight, ray_plane, ray_polygon) return 1 for a hit
**     and 0 for a miss.  They never fail:
**     NaN or infinite input, a zero-length direction, tmin > tmax and
**     degenerate geometry are all misses; tmax = +Inf (HUGE_VAL) is
**     allowed and is the usual unbounded ray.  On a hit they fill *hit;
**     on a miss they leave it untouched.  No NaN or Inf reaches *hit.
**   * Every other fallible function returns an int status: RAY_OK (0) on
**     success, one of the RAY_E* codes otherwise, and then leaves its
**     outputs untouched.
**   * No function keeps global state: all are reentrant and may be called
**     concurrently from any number of threads.
*/
#ifndef RAY_H
#define RAY_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(RAY_BUILD) && defined(__GNUC__)
#define RAY_API __attribute__((visibility("default")))
#else
#define RAY_API
#endif

/* ---------------------------------------------------------------- version */

#define RAY_VERSION_MAJOR 0
#define RAY_VERSION_MINOR 1
#define RAY_VERSION_PATCH 0
/* major*10000 + minor*100 + patch, for compile-time comparisons. */
#define RAY_VERSION_NUMBER 100
#define RAY_VERSION_STRING "0.1.0"

/*
** The version of the library actually linked, to compare with
** RAY_VERSION_NUMBER / RAY_VERSION_STRING of the header compiled against.
** The string is static and must not be freed.
*/
RAY_API int ray_version_number(void);
RAY_API const char *ray_version_string(void);

/* ----------------------------------------------------------------- errors */

enum {
    RAY_OK = 0,          /* success */
    RAY_EINVAL,          /* invalid argument: NULL, NaN, Inf, out of domain */
    RAY_EDEGENERATE,     /* degenerate geometry: zero area or length */
    RAY_ERANGE,          /* a result would overflow double */
    RAY_ENOMEM,          /* an allocation failed */
    RAY_EIO,             /* an I/O call failed (see errno) */
    RAY_EPNG,            /* libpng reported an error */
    RAY_ESTATE,          /* call not allowed in the object's current state */
    RAY_ECANCELED,       /* the caller's progress callback cancelled */
    RAY_ELIMIT,          /* a ray-tree limit (depth, weight, fan-out) */
    RAY_EEFFECT          /* a material asked for an undeclared effect */
};

/*
** A static, English, one-line description of status code "code"; an
** unknown code gives "unknown error".  Never NULL; do not free.
*/
RAY_API const char *ray_strerror(int code);

/* ------------------------------------------------------------ value types */

typedef struct ray_vec3 {
    double x, y, z;
} ray_vec3;

/* The ray p(t) = org + t*dir, valid for tmin < t < tmax. */
typedef struct ray_ray {
    ray_vec3 org;
    ray_vec3 dir;
    double tmin, tmax;
} ray_ray;

/* An identifier that names no geometry (hits from the bare primitives). */
#define RAY_INVALID_ID 0xffffffffu

/*
** What an intersection reports.  Everything a robust secondary ray needs is
** here: the geometric normal (never a shading normal) and a bound on the
** rounding error of the hit point -- the box p +- p_err (per component)
** contains a point of the exact surface -- so an offset can be scaled to
** it rather than to a fixed epsilon (pbrt-v4 section 6.8, "pError").
*/
typedef struct ray_hit {
    double t;          /* ray parameter of the hit, tmin < t < tmax */
    ray_vec3 p;        /* hit point, computed on the surface (see p_err) */
    ray_vec3 n;        /* geometric unit normal (orientation: see each fn) */
    double u, v;       /* the primitive's own parametric coordinates */
    ray_vec3 p_err;    /* the exact surface passes within p +- p_err */
    unsigned geom_id;  /* which geometry; RAY_INVALID_ID from primitives */
    unsigned prim_id;  /* which primitive inside it; likewise */
} ray_hit;

/* --------------------------------------------- the lecture's primitives */

/*
** ray_sphere -- ray against the sphere |p - center| = radius.
**
** Solves the lecture's quadratic (d.d)t^2 + 2d.(e-c)t + (e-c).(e-c) - R^2
** in a cancellation-free arrangement (Ray Tracing Gems ch. 7): the
** discriminant is taken from the distance between the centre and the ray's
** line, and the two roots from q = b' + sign(b')sqrt(a*disc): t0 = c/q,
** t1 = q/a.  Discriminant < 0: miss; = 0: tangent (one root); > 0: two
** roots.  Returns the nearest root in (tmin, tmax), so a ray starting
** inside the sphere hits the far side.
**
** On a hit: n = (p - center)/radius (outward, also from inside); p is
** projected back onto the sphere; u = longitude in [0, 1] around +y
** (atan2(n.x, n.z)/2pi + 1/2), v = latitude in [0, 1] from -y (0) to +y (1).
** A radius that is not finite and > 0 is a miss.
*/
RAY_API int ray_sphere(const ray_ray *r, ray_vec3 center, double radius,
                       ray_hit *hit);

/*
** ray_triangle -- ray against triangle (a, b, c).
**
** Shirley's Cramer's-rule formulation: solve
**     [a-b, a-c, dir] [beta gamma t]^T = a - org
** and hit iff beta >= 0, gamma >= 0, beta + gamma <= 1, tmin < t < tmax.
** Edges and vertices are inclusive.  Only an exactly singular system is
** rejected (no epsilon on the determinant): tiny triangles still hit;
** parallel rays and zero-area triangles miss.
**
** On a hit: u = beta, v = gamma, so p = (1-u-v)*a + u*b + v*c (p is
** computed this way, on the triangle, not as org + t*dir);
** n = normalize((b-a) x (c-a)), i.e. counter-clockwise is the front.
*/
RAY_API int ray_triangle(const ray_ray *r, ray_vec3 a, ray_vec3 b,
                         ray_vec3 c, ray_hit *hit);

/*
** ray_triangle_watertight -- the same contract, by Woop, Benthin and
** Wald's watertight test ("Watertight Ray/Triangle Intersection", JCGT
** 2(1), 2013): the vertices are moved into the ray's frame (translated,
** permuted, sheared so the ray is the z axis) one by one, and the hit is
** decided by 2-D edge functions that two triangles sharing an edge compute
** from the same two vertices.  So a ray through a shared edge or vertex of
** a closed mesh hits at least one of its triangles, always -- which
** Cramer's rule does not promise (it leaks some rays aimed exactly at
** shared vertices and edges, see ray-numerics(7)).  Scenes use it by default
** (ray_scene_set_watertight).  Same (u, v), normal and p as ray_triangle.
*/
RAY_API int ray_triangle_watertight(const ray_ray *r, ray_vec3 a, ray_vec3 b,
                                    ray_vec3 c, ray_hit *hit);

/*
** ray_plane -- ray against the plane through "point" with normal "normal"
** (any non-zero length).
**
** t = (point - org).n / (dir.n).  A ray parallel to the plane or lying in
** it (dir.n == 0) misses.  On a hit: n = normal/|normal| (as given, not
** flipped toward the ray); p is projected back onto the plane; (u, v) are
** the coordinates of p - point along two unit tangents t1, t2 such that
** (t1, t2, n) is a right-handed orthonormal frame (Duff et al., "Building
** an Orthonormal Basis, Revisited", JCGT 6(1), 2017): for n = +y,
** t1 = +x and t2 = -z.
*/
RAY_API int ray_plane(const ray_ray *r, ray_vec3 point, ray_vec3 normal,
                      ray_hit *hit);

/*
** ray_polygon -- ray against the planar polygon v[0..n-1] (n >= 3).
**
** The polygon's plane passes through the vertex centroid with the area
** (Newell) normal, which is robust for concave polygons.  After the plane
** hit, the inside test is made in the projection ALONG THE RAY: the
** polygon as seen from the ray origin, where the ray is the point (0, 0)
** and each vertex is transformed on its own (the translate-permute-shear
** of Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
** 2(1), 2013).  So the test does not depend on the rounded plane hit.
**
** Inside rule: EVEN-ODD (Haines' crossings test, Graphics Gems IV), so a
** self-intersecting polygon has holes where it overlaps itself.  Ties are
** broken as if the ray were moved by an infinitesimal amount: the
** half-open rule for vertices on the test line, and a point exactly on an
** edge counts as lying left of it.  Each edge is evaluated from its two
** vertices in an order that does not depend on the polygon's winding, so
** polygons sharing an edge decide it identically: a ray through a shared
** edge or vertex of a polygon mesh hits an odd number of its polygons
** (exactly one across an edge), never none.
**
** On a hit: n = the unit Newell normal (counter-clockwise front); u, v as
** for ray_plane with point = v[0].  Fewer than 3 vertices, v == NULL or a
** zero-area polygon: miss.  The array is only read during the call.
*/
RAY_API int ray_polygon(const ray_ray *r, const ray_vec3 *v, size_t n,
                        ray_hit *hit);

/*
** ray_barycentric -- barycentric coordinates of "p" in triangle (a, b, c).
**
** By signed areas, as in the lecture: with N = (b-a) x (c-a),
**     alpha ~ ((c-b) x (p-b)).N,  beta ~ ((a-c) x (p-c)).N,
**     gamma ~ ((b-a) x (p-a)).N,
** each divided by their sum (which is N.N in exact arithmetic), so the
** sign of each area comes from its dot product with N and
** alpha + beta + gamma = 1 to within a few ulps.  A point off the plane is
** treated as its orthogonal projection onto it.  The convention matches
** ray_triangle: beta = hit.u, gamma = hit.v, p = alpha*a + beta*b + gamma*c.
**
** Writes abg[0..2] = (alpha, beta, gamma) and, if "inside" is not NULL,
** *inside = 1 when all three are >= 0 (edges included), else 0.
** Returns RAY_OK; RAY_EINVAL if abg is NULL or an input is not finite;
** RAY_EDEGENERATE for a zero-area triangle; RAY_ERANGE if the areas
** overflow.  On error nothing is written.
*/
RAY_API int ray_barycentric(ray_vec3 p, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                            double abg[3], int *inside);

/* ----------------------------------------------------- secondary rays */

/*
** ray_spawn -- the ray leaving hit "hit" in direction "dir", with its
** origin moved off the surface so it cannot hit that surface again
** ("acne") nor skip geometry thicker than the hit point's own rounding
** error.  The origin is p offset along the geometric normal, to the side
** "dir" points to, by the error bound dot(|n|, p_err) times 2, then rounded
** one more ulp away from p per component (pbrt-v4 OffsetRayOrigin, which
** follows the same argument).  out->tmin = 0, out->tmax = +Inf.
**
** ray_spawn_to -- the same for a segment toward the point "target" (a
** shadow ray): out->dir = target - origin, tmax = 1, so only geometry
** strictly between the surface and the target blocks it.
**
** Both return RAY_OK, or RAY_EINVAL (nothing written) for NULL pointers,
** non-finite input or a zero direction.  Thread-safe, no state.
*/
RAY_API int ray_spawn(const ray_hit *hit, ray_vec3 dir, ray_ray *out);
RAY_API int ray_spawn_to(const ray_hit *hit, ray_vec3 target, ray_ray *out);

/*
** Optics helpers for material callbacks.  "d" is the incident direction
** (toward the surface, any length) and "n" a unit normal on either side.
**
** ray_reflect: the mirror direction d - 2(d.n)n.
** ray_refract: Snell's law for relative index eta = n_incident /
**   n_transmitted, with n flipped to face d if needed.  Writes the unit
**   transmitted direction and returns 1, or returns 0 (nothing written)
**   on total internal reflection or bad input.
** ray_fresnel: the unpolarised Fresnel reflectance of a dielectric
**   interface for cos_i = cosine of the incidence angle (|d.n|/|d|) and
**   eta = n_incident / n_transmitted; 1 on total internal reflection.
*/
RAY_API ray_vec3 ray_reflect(ray_vec3 d, ray_vec3 n);
RAY_API int ray_refract(ray_vec3 d, ray_vec3 n, double eta, ray_vec3 *out);
RAY_API double ray_fresnel(double cos_i, double eta);

/* ------------------------------------------------------------------ scene */

/* Linear RGB radiance or reflectance. */
typedef struct ray_rgb {
    double r, g, b;
} ray_rgb;

/*
** An allocator, realloc-style (Lua's lua_Alloc): free when nsize == 0
** (return NULL), else (re)allocate ptr of osize bytes (ptr NULL, osize 0
** for a new block) to nsize bytes, returning NULL on failure with ptr
** untouched.  "ud" is the pointer given with it.  NULL means libc.
*/
typedef void *(*ray_alloc_fn)(void *ud, void *ptr, size_t osize,
                              size_t nsize);

typedef struct ray_scene ray_scene;  /* geometry, materials, lights */
typedef struct ray_ctx ray_ctx;      /* one thread's trace state */

/* Kinds of rays, for statistics and effect declarations. */
enum {
    RAY_KIND_PRIMARY = 0,
    RAY_KIND_SHADOW,
    RAY_KIND_REFLECTION,
    RAY_KIND_REFRACTION,
    RAY_KIND_COUNT
};

/* What a material may ask for: the tracer refuses anything else. */
#define RAY_EFFECT_REFLECTION 1u   /* may call ray_trace(.., REFLECTION) */
#define RAY_EFFECT_REFRACTION 2u   /* may call ray_trace(.., REFRACTION) */
#define RAY_EFFECT_SHADOW     4u   /* ray_light_visible casts shadow rays */
#define RAY_EFFECT_TEXTURE    8u   /* reads args->u, v: without any such
                                      material the scene skips
                                      interpolating mesh (s, t) */

/*
** Everything a material callback gets to shade one hit.  Read-only; valid
** during the call only.  New fields are added only at the end.
*/
typedef struct ray_shade_args {
    const ray_scene *scene;
    const ray_ray *ray;      /* the incoming ray */
    const ray_hit *hit;      /* where it hit (geometric normal in hit->n) */
    ray_vec3 normal;         /* hit->n turned to face the incoming ray */
    int entering;            /* 1 if the ray hit the side hit->n points to */
    double u, v;             /* texture coordinates: a mesh's interpolated
                                (s, t) if it has them and some material of
                                the scene declared RAY_EFFECT_TEXTURE, else
                                hit->u, v */
    unsigned depth;          /* 0 for a primary ray, +1 per bounce */
    double weight;           /* path weight: product of the attenuations */
    ray_rgb ambient;         /* the scene's ambient light */
    ray_vec3 shading_normal; /* interpolated vertex normal of a mesh with
                                normals, turned to the side of "normal";
                                else equal to "normal" */
    int prune;               /* 1 (default): skip what cannot contribute
                                (zero weights, lights behind the surface);
                                0: the scene's naive mode, spawn every
                                effect the material declared, whatever
                                its weight (for comparisons) */
} ray_shade_args;

/*
** A material's shading function: write the radiance leaving the hit
** toward the incoming ray into *out (preset to black).  Called
** CONCURRENTLY from the render threads: touch only "ud" read-only, or
** synchronise.  "ctx" is the calling thread's context, to pass to
** ray_trace, ray_light_sample_at and ray_light_visible.
*/
typedef void (*ray_shade_fn)(void *ud, ray_ctx *ctx,
                             const ray_shade_args *args, ray_rgb *out);

typedef struct ray_material {
    ray_shade_fn shade;
    void *ud;                /* borrowed: must outlive the scene */
    unsigned effects;        /* RAY_EFFECT_* bits it may request */
} ray_material;

/*
** Lights.  "intensity" is what arrives at distance 1 (point and area
** lights, which fall off as 1/r^2) or everywhere (directional).  An area
** light spreads it over its samples.  A sphere light looks the same from
** every side; a rect light emits only from the side edge1 x edge2 points
** to, with the cosine falloff of a Lambertian emitter.
*/
enum {
    RAY_LIGHT_POINT = 0,     /* at position */
    RAY_LIGHT_DIRECTIONAL,   /* travelling along direction, from infinity */
    RAY_LIGHT_SPHERE,        /* ball of radius at position: soft shadows */
    RAY_LIGHT_RECT           /* parallelogram position + s*edge1 + t*edge2 */
};

typedef struct ray_light {
    int kind;                /* RAY_LIGHT_* */
    ray_vec3 position;
    ray_vec3 direction;      /* directional lights */
    ray_vec3 edge1, edge2;   /* rectangular lights */
    double radius;           /* spherical lights */
    ray_rgb intensity;
    unsigned samples;        /* area lights: shadow rays per shading
                                point, rounded up to a square; 0 = 16;
                                at most RAY_MAX_LIGHT_SAMPLES (checked
                                for every kind) */
} ray_light;

/* Bounds on settings, so that no setting can overflow a counter or the
** stack: 256 x 256 samples per light or per pixel, and a ray tree at most
** 64 levels deep (each level nests a few hundred bytes of stack). */
#define RAY_MAX_LIGHT_SAMPLES 65536u
#define RAY_MAX_PIXEL_SAMPLES 65536u
#define RAY_MAX_DEPTH 64u

/* The ray tree's bounds (the lecture: "bound tree depth & fan-out"). */
typedef struct ray_limits {
    unsigned max_depth;      /* deepest bounce traced; primary = 0;
                                at most RAY_MAX_DEPTH */
    double min_weight;       /* rays whose path weight falls below: cut;
                                in [0, 1] */
    unsigned max_fanout;     /* secondary rays one hit may spawn */
} ray_limits;

#define RAY_DEFAULT_MAX_DEPTH 8
#define RAY_DEFAULT_MIN_WEIGHT (1.0 / 256)  /* below one 8-bit level */
#define RAY_DEFAULT_MAX_FANOUT 2            /* a reflection + a refraction */

/*
** ray_scene_new -- create an empty scene in *out.  "alloc" (NULL: libc)
** serves every allocation the scene makes, with "alloc_ud", including
** those of ray_ctx_new and ray_render on it: these may run on several
** threads at once after commit, so a shared allocator must then be
** thread-safe.  Returns RAY_OK, RAY_EINVAL (out NULL) or RAY_ENOMEM.
** ray_scene_free -- release it; NULL is a no-op.  Free every context made
** on a scene (ray_ctx_free) before the scene itself.
**
** A scene is built single-threaded, then ray_scene_commit makes it
** read-only: after that any number of threads may trace it at once, and
** every ray_scene_add_* / _set_* returns RAY_ESTATE.
*/
RAY_API int ray_scene_new(ray_scene **out, ray_alloc_fn alloc,
                          void *alloc_ud);
RAY_API void ray_scene_free(ray_scene *scene);

/*
** Materials are copied into the scene (the ud they point to is borrowed).
** *id, if not NULL, receives the material's id, counted from 0.
** RAY_EINVAL for a NULL scene, material or shade function, or unknown
** effect bits; RAY_ENOMEM; RAY_ESTATE after commit.
*/
RAY_API int ray_scene_add_material(ray_scene *scene, const ray_material *m,
                                   unsigned *id);

/*
** Geometry, each with a material id.  Copied into the scene.  *geom_id,
** if not NULL, receives the id that hits report in ray_hit.geom_id
** (counted from 0 over all geometry).  Errors, with nothing added:
** RAY_EINVAL for NaN/Inf coordinates, a radius not > 0, a zero normal, an
** unknown material or fewer than 3 polygon vertices; RAY_EDEGENERATE for
** a zero-area triangle or polygon; RAY_ENOMEM; RAY_ESTATE after commit.
*/
RAY_API int ray_scene_add_sphere(ray_scene *scene, ray_vec3 center,
                                 double radius, unsigned material,
                                 unsigned *geom_id);
RAY_API int ray_scene_add_plane(ray_scene *scene, ray_vec3 point,
                                ray_vec3 normal, unsigned material,
                                unsigned *geom_id);
RAY_API int ray_scene_add_triangle(ray_scene *scene, ray_vec3 a, ray_vec3 b,
                                   ray_vec3 c, unsigned material,
                                   unsigned *geom_id);
RAY_API int ray_scene_add_polygon(ray_scene *scene, const ray_vec3 *v,
                                  size_t n, unsigned material,
                                  unsigned *geom_id);

/*
** ray_scene_add_mesh -- an indexed triangle mesh: triangle i has vertices
** vertices[indices[3i]], vertices[indices[3i+1]], vertices[indices[3i+2]]
** (counter-clockwise is the front).  Optional per-vertex normals (smooth
** shading: interpolated with the hit's barycentrics into
** ray_shade_args.shading_normal) and per-vertex texture coordinates (s, t)
** (two doubles per vertex, interpolated into ray_shade_args.u, v).
** Everything is COPIED: the arrays may be freed when the call returns.
** Hits report the mesh's geom_id and prim_id = i.  Triangles that have no
** normal (zero area, or a cross product that overflows) are kept in the
** count but can never be hit.
**
** Errors, with nothing added: RAY_EINVAL for NULL pointers, no triangles,
** an index >= vertex_count, a NaN/Inf vertex, normal or texture coordinate,
** or an unknown material; RAY_ENOMEM (also for more than 2^31 - 1
** triangles in the scene); RAY_ESTATE after commit.
**
** Memory: each triangle costs 80 bytes (its three vertices, flattened for
** traversal, and its ids) plus about 32 bytes of BVH after commit (112 in
** all on a million-triangle grid, 118 on the Stanford bunny: bench/mesh),
** plus 12 bytes of indices and the per-vertex attributes when normals or
** texture coordinates are given.  ray_scene_commit briefly needs about
** 180 bytes per triangle (205 on the bunny).
*/
typedef struct ray_mesh {
    const ray_vec3 *vertices;
    size_t vertex_count;
    const unsigned *indices;     /* 3 per triangle */
    size_t triangle_count;
    const ray_vec3 *normals;     /* NULL, or vertex_count normals */
    const double *texcoords;     /* NULL, or 2 * vertex_count values */
} ray_mesh;

RAY_API int ray_scene_add_mesh(ray_scene *scene, const ray_mesh *mesh,
                               unsigned material, unsigned *geom_id);

/*
** Lights (copied).  RAY_EINVAL for an unknown kind, non-finite or
** negative intensity, a zero direction (directional), a radius not > 0
** (sphere), parallel edges (rect) or samples > RAY_MAX_LIGHT_SAMPLES.
*/
RAY_API int ray_scene_add_light(ray_scene *scene, const ray_light *light,
                                unsigned *id);

/* The background: a constant colour (default black), or a function of
** the escaping ray (NULL fn restores the colour), called CONCURRENTLY from
** the render threads like materials.  The ambient light given to
** materials (default black).  Tree limits (NULL: defaults); RAY_EINVAL
** for max_depth > RAY_MAX_DEPTH or min_weight outside [0, 1].  Colours
** must be finite and >= 0 (else RAY_EINVAL). */
typedef void (*ray_background_fn)(void *ud, const ray_ray *r, ray_rgb *out);
RAY_API int ray_scene_set_background(ray_scene *scene, ray_rgb color);
RAY_API int ray_scene_set_background_fn(ray_scene *scene,
                                        ray_background_fn fn, void *ud);
RAY_API int ray_scene_set_ambient(ray_scene *scene, ray_rgb ambient);
RAY_API int ray_scene_set_limits(ray_scene *scene, const ray_limits *limits);

/*
** ray_scene_set_pruning -- 1 (the default): the tracer cuts rays whose
** path weight falls below min_weight, and materials are told (args->prune)
** to spawn nothing that cannot contribute.  0: a naive mode that traces
** every declared effect up to max_depth, for measuring what pruning saves
** (the bench does).  RAY_EINVAL (NULL), RAY_ESTATE after commit.
**
** ray_scene_effects -- after commit, the RAY_EFFECT_* bits the scene can
** ever need: the union of the effects of the materials its geometry uses,
** without RAY_EFFECT_SHADOW when it has no lights.  0 before commit.
*/
RAY_API int ray_scene_set_pruning(ray_scene *scene, int enabled);
RAY_API unsigned ray_scene_effects(const ray_scene *scene);

/*
** ray_scene_set_watertight -- 1 (the default): the scene's triangles and
** meshes are intersected with ray_triangle_watertight, so no ray passes
** between the triangles of a closed mesh (measured: Cramer's rule in
** double lets 0.1 to 10% of the rays aimed exactly at shared vertices and
** edges through, see ray-numerics(7)).  0: with ray_triangle, the
** lecture's Cramer's rule, the fast path (bench/RESULTS.md gives both
** speeds on the bunny).
** RAY_EINVAL (NULL), RAY_ESTATE after commit.
*/
RAY_API int ray_scene_set_watertight(ray_scene *scene, int enabled);

/*
** ray_scene_commit -- finish building: the scene becomes read-only and
** safe to share between threads.  Returns RAY_OK, RAY_EINVAL (NULL),
** RAY_ENOMEM (acceleration structures), or RAY_ESTATE if already
** committed.
*/
RAY_API int ray_scene_commit(ray_scene *scene);

/*
** Queries on a committed scene, from any thread.  ray_intersect: the
** nearest hit in (tmin, tmax), with geom_id set and prim_id the
** triangle's index for a mesh, 0 otherwise (1), or a miss (0, *hit
** untouched).  ray_occluded: 1 if anything lies in (tmin, tmax) (any-hit,
** stops at the first).  Both return 0 for an uncommitted scene or NULLs.
*/
RAY_API int ray_intersect(const ray_scene *scene, const ray_ray *r,
                          ray_hit *hit);
RAY_API int ray_occluded(const ray_scene *scene, const ray_ray *r);

/* ---------------------------------------------------------------- tracing */

/* Kinds of primitives, for the intersection-test counters. */
enum {
    RAY_PRIM_SPHERE = 0,
    RAY_PRIM_PLANE,
    RAY_PRIM_TRIANGLE,           /* triangles and mesh triangles */
    RAY_PRIM_POLYGON,
    RAY_PRIM_KINDS
};

/* samples_hist[n] counts the pixels that took n samples (n < 64);
** samples_hist[64], those that took 64 or more. */
#define RAY_HIST_BINS 65

/* Counters of one context or one render (summed over its threads). */
typedef struct ray_stats {
    unsigned long long rays[RAY_KIND_COUNT];  /* traced, by RAY_KIND_* */
    unsigned long long tests;       /* ray-primitive intersection tests */
    unsigned long long tests_by_kind[RAY_PRIM_KINDS];  /* the same, split */
    unsigned long long cut_depth;   /* rays refused by max_depth */
    unsigned long long cut_weight;  /* rays refused by min_weight */
    unsigned long long cut_fanout;  /* rays refused by max_fanout */
    unsigned max_depth;             /* deepest level reached */
    unsigned long long pixels;      /* pixels rendered (ray_render) */
    unsigned long long samples_hist[RAY_HIST_BINS];
} ray_stats;

/*
** ray_ctx_new -- a trace context for tracing outside ray_render (which
** makes its own, one per thread).  One context per thread; it holds the
** recursion state, the random sequence and the counters.  "seed" seeds
** its sampler.  Returns RAY_OK, RAY_EINVAL (NULL, or scene not committed)
** or RAY_ENOMEM.  ray_ctx_free(NULL) is a no-op.  ray_ctx_stats copies
** the counters accumulated so far.
*/
RAY_API int ray_ctx_new(const ray_scene *scene, unsigned long long seed,
                        ray_ctx **out);
RAY_API void ray_ctx_free(ray_ctx *ctx);
RAY_API void ray_ctx_stats(const ray_ctx *ctx, ray_stats *out);

/*
** ray_trace -- trace ray "r" and write the radiance it brings back into
** *out: the shade of the material it hits, or the background.
**
** "kind" is RAY_KIND_PRIMARY outside a material callback; inside one it is
** RAY_KIND_REFLECTION or RAY_KIND_REFRACTION, and "attenuation" is the
** factor this ray's result will be multiplied by (e.g. the reflectance),
** so the tree can be pruned by weight.  The tracer enforces the scene's
** limits: a ray deeper than max_depth, with path weight below min_weight,
** or beyond max_fanout rays for the current hit is not traced.
**
** Returns RAY_OK; RAY_ELIMIT when a limit stopped it; RAY_EEFFECT when
** the calling material did not declare that kind in its effects;
** RAY_EINVAL for NULL pointers or a bad kind.  On anything but RAY_OK,
** *out is untouched.
*/
RAY_API int ray_trace(ray_ctx *ctx, const ray_ray *r, unsigned kind,
                      double attenuation, ray_rgb *out);

/*
** One light as seen from a shading point.
**
** ray_light_sample_at fills *out for light "light" (0 ..
** ray_scene_light_count - 1) and sample "index" (0 .. n - 1, n =
** ray_light_samples: 1 for point and directional lights, the light's
** sample count for area lights, whose sample positions are stratified and
** jittered from the context's per-pixel random sequence).  It casts no ray.
**
** ray_light_visible answers whether the sample is unoccluded.  When the
** calling material declared RAY_EFFECT_SHADOW it casts one shadow ray
** (any-hit, from ray_spawn_to, or ray_spawn toward a directional light); otherwise it casts nothing and answers 1:
** unshadowed light, a documented no-op (also outside any callback).  So a
** material asks only for the samples that would contribute (n.l > 0), and
** only those cost a ray.
**
** ray_light_sample_at returns RAY_OK or RAY_EINVAL, writing nothing (NULLs,
** light or index out of range, a shading point so close to the light that
** 1/dist^2 overflows).  ray_light_visible
** returns 1 or 0 (0 also for NULL arguments).
*/
typedef struct ray_light_sample {
    ray_vec3 dir;            /* unit vector from the hit toward the light */
    double dist;             /* distance to the sample, +Inf if directional */
    ray_rgb radiance;        /* arriving intensity (before visibility),
                                already divided by the sample count */
    ray_vec3 point;          /* the sample's position (unused if +Inf) */
} ray_light_sample;

RAY_API unsigned ray_scene_light_count(const ray_scene *scene);
RAY_API unsigned ray_light_samples(const ray_scene *scene, unsigned light);
RAY_API int ray_light_sample_at(ray_ctx *ctx, const ray_shade_args *args,
                                unsigned light, unsigned index,
                                ray_light_sample *out);
RAY_API int ray_light_visible(ray_ctx *ctx, const ray_shade_args *args,
                              const ray_light_sample *sample);

/* A uniform random number in [0, 1) from the context's per-pixel
** sequence: deterministic for a given pixel, sample and frame seed. */
RAY_API double ray_ctx_random(ray_ctx *ctx);

/* ------------------------------------------------------ built-in materials */

/*
** Written with the public callback API only (src/materials.c): read them
** as examples.  Each constructor returns a ray_material whose ud is the
** given parameter block, which is BORROWED and must outlive the scene.
**
** ray_material_phong: ambient*diffuse + sum over lights of diffuse *
**   max(0, n.l) + specular * max(0, r.v)^shininess (Phong) or
**   max(0, n.h)^shininess (Blinn-Phong if blinn != 0), each light sample
**   shadowed; plus a mirror term if reflect is non-zero.  Lambert is
**   specular = reflect = 0.
** ray_material_mirror: perfect mirror, reflectance per channel.
** ray_material_glass: dielectric: Fresnel-weighted reflection and
**   refraction (Snell; total internal reflection), optional Beer-Lambert
**   absorption per unit distance inside.
** ray_material_checker: picks "even" or "odd" by the parity of
**   floor(u*scale) + floor(v*scale) and shades with it (with the union of
**   the two materials' effects).
**
** The effects are fixed when the material is made, from the parameter
** block as it is then (Phong declares RAY_EFFECT_REFLECTION only if
** reflect is non-zero).  Glass blocks shadow rays like any surface.
*/
typedef struct ray_phong_params {
    ray_rgb diffuse;
    ray_rgb specular;
    double shininess;
    int blinn;
    ray_rgb reflect;
} ray_phong_params;

typedef struct ray_glass_params {
    double ior;              /* index of refraction inside, e.g. 1.5 */
    ray_rgb absorption;      /* Beer-Lambert coefficient per unit length */
} ray_glass_params;

typedef struct ray_checker_params {
    ray_material even, odd;
    double scale;
} ray_checker_params;

RAY_API ray_material ray_material_phong(const ray_phong_params *p);
RAY_API ray_material ray_material_mirror(const ray_rgb *reflectance);
RAY_API ray_material ray_material_glass(const ray_glass_params *p);
RAY_API ray_material ray_material_checker(const ray_checker_params *p);

/* --------------------------------------------------------------- rendering */

/*
** A pinhole camera at "position" looking at "look_at", "up" giving the
** roll, "vfov" the vertical field of view in degrees.  aperture > 0 makes
** it a thin lens of that diameter focused at focus_distance (0: the
** distance to look_at), for depth of field.
*/
typedef struct ray_camera {
    ray_vec3 position, look_at, up;
    double vfov;
    double aperture;
    double focus_distance;
} ray_camera;

/* Called after each finished row: return non-zero to cancel the render. */
typedef int (*ray_progress_fn)(void *ud, unsigned rows_done,
                               unsigned rows_total);

typedef struct ray_render_options {
    unsigned width, height;  /* the whole frame, in pixels */
    unsigned y0, y1;         /* render rows y0 <= y < y1 only (y1 = 0:
                                height); rows are counted from the top */
    unsigned threads;        /* 0 = one per online CPU */
    unsigned samples;        /* per pixel, 1 .. RAY_MAX_PIXEL_SAMPLES;
                                1 = the pixel centre; a square k*k:
                                jittered k x k strata; otherwise n-rooks
                                strata on a rank-1 lattice, jittered */
    unsigned long long seed; /* frame seed of every pixel's sampler */
    ray_progress_fn progress;
    void *progress_ud;
    /* Adaptive antialiasing (Whitted 1980), used when adaptive_threshold
    ** > 0 (then "samples" is not used, but must still be valid): the
    ** pixel's four corners are sampled; where any channel differs between
    ** them by more than the threshold the square is split in four, down to
    ** adaptive_depth levels (1 .. 8), so a pixel takes 4 to
    ** 4 + 5 (4^depth - 1) / 3 samples (a point on an edge shared by two
    ** split quarters is traced for each).  +Inf samples the corners only.
    ** Samples sit on a fixed lattice of the frame and are seeded by their
    ** position: any thread count or region split gives the same bytes. */
    double adaptive_threshold;
    unsigned adaptive_depth;
} ray_render_options;

/* Defaults: the whole frame, all CPUs, 1 sample, seed 0, no callback,
** no adaptive antialiasing (threshold 0, depth 2 if it is turned on). */
RAY_API void ray_render_options_init(ray_render_options *o, unsigned width,
                                     unsigned height);

/*
** ray_render -- render rows [y0, y1) of the frame into "rgb": linear float
** RGB, 3 floats per pixel, width pixels per row, row y0 first.  Rows are
** handed to the threads one at a time from a shared counter; every pixel's
** samples are seeded from (seed, x, y, sample), so the bytes are the same
** whatever the thread count or region split.  "stats", if not NULL,
** receives the counters summed over the threads.
**
** The progress callback is called from the render threads, one call at a
** time, and never again after it asked to cancel.  Returns RAY_OK;
** RAY_ECANCELED if it cancelled (finished rows are kept, the rest is
** unspecified); RAY_EINVAL for NULLs, an uncommitted scene, zero sizes,
** samples outside 1 .. RAY_MAX_PIXEL_SAMPLES, an adaptive threshold that
** is NaN or negative or an adaptive depth outside 1 .. 8, y0 >= y1 or
** y1 > height, or
** a degenerate camera (eye at look_at, up parallel to the view, vfov not
** in (0, 180)); RAY_ENOMEM.  If fewer threads than asked can be started,
** the render goes on with those it has: the image is the same.
*/
RAY_API int ray_render(const ray_scene *scene, const ray_camera *camera,
                       const ray_render_options *options, float *rgb,
                       ray_stats *stats);

/* ------------------------------------------------------------------ images */

/*
** ray_image_to_srgb8 -- encode "count" linear RGB float pixels (3 floats
** each) as 8-bit sRGB (IEC 61966-2-1 transfer curve, rounded to nearest).
** Values are clamped to [0, 1]; NaN becomes 0.  "out" receives 3*count
** bytes.  Returns RAY_OK, or RAY_EINVAL for a NULL pointer.
*/
RAY_API int ray_image_to_srgb8(const float *rgb, size_t count,
                               unsigned char *out);

/*
** ray_write_png -- write a width x height image of linear RGB floats
** (3 per pixel, rows top to bottom, no padding) to the file "path" through
** libpng.  bits = 8 writes 8-bit sRGB (with an sRGB chunk); bits = 16
** writes 16-bit LINEAR samples with gAMA 1.0, for tools that want the
** unquantised data.  Values are clamped to [0, 1]; NaN becomes 0.
**
** Returns RAY_OK; RAY_EINVAL for NULL arguments, a zero or too large size
** or bits other than 8 and 16; RAY_ENOMEM; RAY_EIO if the file cannot be
** created or written (errno tells why); RAY_EPNG if libpng fails.  A file
** that failed is removed.  Thread-safe; the image is only read.
*/
RAY_API int ray_write_png(const char *path, const float *rgb,
                          unsigned width, unsigned height, int bits);

#ifdef __cplusplus
}
#endif

#endif /* RAY_H */
