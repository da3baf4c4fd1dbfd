/* SPDX-License-Identifier: MIT */
/*
** ray.h -- the whole public interface of libray, a small C99 ray-tracing
** library.
**
** This header is the reference documentation.  The man pages (ray(7) and
** the ray_*(3) pages) are written by hand from it, and "make check"
** (docs-test, scripts/check-docs.sh) holds them to it: every RAY_API
** prototype below, with the same return type and parameter types and
** names, in the SYNOPSIS of one page; every public type and constant
** named in some page; each copy of a struct here in a page declaring the
** same members.  The prose of both is kept in step by hand.
**
** Conventions that hold for every function below:
**
**   * Precision is double throughout.
**   * A ray is p(t) = org + t*dir on the OPEN interval tmin < t < tmax.
**     "dir" need not be normalised, so t is measured in units of |dir|.
**     Results exactly at tmin or tmax are not hits.
**   * The intersection functions (ray_sphere, ray_triangle,
**     ray_triangle_watertight, ray_plane, ray_polygon, ray_torus,
**     ray_box, ray_capsule) return 1
**     for a hit and 0 for a miss.  They never fail:
**     NaN or infinite input, a zero-length direction, tmin > tmax and
**     degenerate geometry are all misses; tmax = +Inf (HUGE_VAL) is
**     allowed and is the usual unbounded ray.  On a hit they fill *hit;
**     on a miss they leave it untouched.  No NaN or Inf reaches *hit.
**     The iterative ones (ray_implicit, ray_parametric) may also fail,
**     returning a negated status instead of guessing.
**   * Every other fallible function returns an int status: RAY_OK (0) on
**     success, one of the RAY_E* codes otherwise, and then leaves its
**     outputs untouched.
**   * NULL, one rule for every function (ray(7), "NULL arguments"): a NULL
**     where an object is required is never a crash and never a write: a
**     status is RAY_EINVAL, an intersection is a miss (0, or -RAY_EINVAL
**     where the function can report misuse: ray_implicit, ray_parametric,
**     ray_intersect, ray_occluded, ray_intersect_all and
**     ray_closest_point), a void function does nothing, and a query
**     answers its neutral value (0, no
**     texture, a fixed string).
**     Outputs documented as optional ("may be NULL") are skipped.
**   * No function keeps global or static state.  Threads: a scene is
**     built and changed by one thread at a time (its ray_scene_add_*,
**     ray_scene_set_*, ray_scene_update_mesh, ray_scene_remove,
**     ray_scene_commit, ray_scene_errmsg and ray_scene_free calls must not
**     overlap one another, nor any query or render of that scene or of a
**     scene that instances it); once committed, and until its next
**     change, any number of threads may query and render it at once; a
**     ray_ctx belongs to one thread at a time; the functions that take no
**     object (the primitives, optics, ray_strerror) are reentrant.
**     ray(7), "Threads" and "Dynamic scenes", states the rule in full.
*/
/*
** Contents, in the order a program meets them: README's first example
** tests a ray against a sphere alone (1, 2); doc/GUIDE.md's first render
** builds a scene, renders it and writes a PNG (3 to 10); README's second,
** picking in a game, queries a scene (11, 12); a material of one's own
** traces rays (13, 14); the other surfaces come next (15), and then the
** shapes a game moves through its world, which stand on them (16).
**    1. values              ray_vec3, ray_ray, ray_hit, ids
**    2. primitives          the lecture's ray / object tests
**    3. errors              status codes, ray_strerror
**    4. version
**    5. scene               materials, lights, geometry, settings, the
**                           program's job system (ray_scheduler), commit
**    6. textures            images as textures
**    7. built-in materials  Phong, mirror, glass, checker
**    8. counters            ray_stats
**    9. rendering           camera, ray_render, caustics
**   10. images              PNG output
**   11. queries             nearest hit, any hit, closest point
**   12. games and tools     instances, changes, masks, filters, batches
**   13. tracing             contexts, ray_trace, lights, direct light
**   14. secondary rays      ray_spawn, reflection, refraction
**   15. more surfaces       implicit, torus, box, capsule, blobs,
**                           parametric, Bezier, the caller's own
**   16. shapes in the world one shape type (sphere, capsule, box): its
**                           sweeps and overlaps; rays from surface points
*/
#ifndef RAY_H
#define RAY_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
** RAY_API marks the exported functions.  On Windows (doc/PLATFORMS.md)
** libray.dll is built with RAY_BUILD and RAY_DLL defined: dllexport, so
** the DLL exports these and nothing else; a program using the DLL may
** define RAY_DLL for dllimport (a direct call through the import table;
** without it the import library's stubs still link); the static library
** and its programs define neither.  Elsewhere, GCC and Clang build the
** library with -fvisibility=hidden and export these.
*/
#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(RAY_DLL) && defined(RAY_BUILD)
#define RAY_API __declspec(dllexport)
#elif defined(RAY_DLL)
#define RAY_API __declspec(dllimport)
#else
#define RAY_API
#endif
#elif defined(RAY_BUILD) && defined(__GNUC__)
#define RAY_API __attribute__((visibility("default")))
#else
#define RAY_API
#endif

/* ------------------------------------------------------------ 1. values */

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
** The material of geometry that is only queried (ray_intersect,
** ray_occluded): any ray_scene_add_* geometry call accepts it, and the
** scene needs no material at all.  Rendering (ray_trace, ray_render) such
** geometry shades it black: it emits and reflects nothing and traces no
** ray of its own, but it is still geometry, so it hides what lies behind
** it and blocks shadow rays.  It adds nothing to ray_scene_effects.
*/
#define RAY_NO_MATERIAL RAY_INVALID_ID

/*
** What an intersection reports.  Everything a robust secondary ray needs is
** here: the geometric normal (never a shading normal) and a bound on the
** rounding error of the hit point -- the box p +- p_err (per component)
** contains a point of the exact surface -- so an offset can be scaled to
** it rather than to a fixed epsilon (pbrt-v4 section 6.8, "pError").
*/
typedef struct ray_hit {
    double t;          /* ray parameter of the hit, tmin < t < tmax; t
                          minus its rounding-error bound is still > tmin
                          (no acne: ray-numerics(7)) */
    ray_vec3 p;        /* hit point, computed on the surface (see p_err) */
    ray_vec3 n;        /* geometric unit normal (orientation: see each fn) */
    double u, v;       /* the primitive's own parametric coordinates */
    ray_vec3 p_err;    /* the exact surface passes within p +- p_err */
    unsigned geom_id;  /* which geometry; RAY_INVALID_ID from primitives */
    unsigned prim_id;  /* which primitive inside it; likewise */
    unsigned inst_id;  /* the instance it was hit through (its geom_id in
                          the scene queried), RAY_INVALID_ID if none */
} ray_hit;

/* ----------------------------------------- 2. primitives: the lecture's */

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
** |alpha + beta + gamma - 1| <= 3 DBL_EPSILON (|alpha| + |beta| + |gamma|):
** a few ulps inside or near the triangle, relative to the coordinates'
** size far outside it.  A point off the plane is
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

/* ------------------------------------------------------------ 3. errors */

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
    RAY_ELIMIT,          /* a limit was reached: ray tree (depth,
                            weight, fan-out), iterations, image load */
    RAY_EEFFECT,         /* a material asked for an undeclared effect */
    RAY_ENOTSUP,         /* not supported by this build (PNG I/O in a
                            library built with make PNG=0) */
    RAY_EKIND            /* the geometry's or shape's kind has no such
                            thing (a box's surface points, a box shape's
                            sweep) */
};

/*
** A static, English, one-line description of status code "code", or of
** its negation (-RAY_ELIMIT reads as RAY_ELIMIT: the queries and the
** iterative intersections return negated statuses); an unknown code gives
** "unknown error".  Never NULL; do not free.
**
** Statuses are not answers.  A function returns either a status (RAY_OK
** or a RAY_E* code, all >= 0) or an answer: a query's or intersection's
** hit (1), miss (0) or hit count, with misuse as a negated status (< 0).
** Only statuses and negated statuses are codes for ray_strerror: a
** positive answer is a hit, and ray_strerror(1) reads as RAY_EINVAL's
** text.  Log an answer n as n < 0 ? ray_strerror(n) : "hit" (or its
** count).  The codes stay small positive integers, as errno's, rather
** than moving to a range of their own: a program compares a status with
** RAY_OK or a named code, never by value, and the sign of a query's
** result already tells an answer from misuse (ray_strerror(3)).
*/
RAY_API const char *ray_strerror(int code);

/* ----------------------------------------------------------- 4. version */

/* The version, set here alone: the Makefile, CMakeLists.txt and what they
** write read these three lines (make version-test). */
#define RAY_VERSION_MAJOR 1
#define RAY_VERSION_MINOR 0
#define RAY_VERSION_PATCH 0
/* major*10000 + minor*100 + patch, for compile-time comparisons. */
#define RAY_VERSION_NUMBER \
    (RAY_VERSION_MAJOR * 10000 + RAY_VERSION_MINOR * 100 + RAY_VERSION_PATCH)
/* "major.minor.patch" (make version-test holds it to the three). */
#define RAY_VERSION_STRING "1.0.0"

/*
** The version of the library actually linked, to compare with
** RAY_VERSION_NUMBER / RAY_VERSION_STRING of the header compiled against.
** The string is static and must not be freed.
*/
RAY_API int ray_version_number(void);
RAY_API const char *ray_version_string(void);

/* ------------------------------------------------------------- 5. scene */

/* Linear RGB radiance or reflectance. */
typedef struct ray_rgb {
    double r, g, b;
} ray_rgb;

/*
** Vector and colour helpers, static inline: no symbol in the library, so
** they cost no ABI and work in C99 and C++ alike.  Plain component-wise
** arithmetic in the order written (a.x*b.x + a.y*b.y + a.z*b.z for the
** dot product), nothing else: no normalisation (the directions a material
** gets are unit already), no clamping.  ray_rgb_mul is the component-wise
** product (a reflectance times the light it reflects); ray_rgb_madd
** returns acc + a*b, the accumulation every shading sum does.
*/
static inline ray_vec3 ray_vec3_make(double x, double y, double z)
{
    ray_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

static inline ray_vec3 ray_vec3_add(ray_vec3 a, ray_vec3 b)
{
    return ray_vec3_make(a.x + b.x, a.y + b.y, a.z + b.z);
}

static inline ray_vec3 ray_vec3_sub(ray_vec3 a, ray_vec3 b)
{
    return ray_vec3_make(a.x - b.x, a.y - b.y, a.z - b.z);
}

static inline ray_vec3 ray_vec3_scale(ray_vec3 a, double s)
{
    return ray_vec3_make(a.x * s, a.y * s, a.z * s);
}

static inline double ray_vec3_dot(ray_vec3 a, ray_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline ray_vec3 ray_vec3_cross(ray_vec3 a, ray_vec3 b)
{
    return ray_vec3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
                         a.x * b.y - a.y * b.x);
}

static inline ray_rgb ray_rgb_make(double r, double g, double b)
{
    ray_rgb c;
    c.r = r;
    c.g = g;
    c.b = b;
    return c;
}

static inline ray_rgb ray_rgb_add(ray_rgb a, ray_rgb b)
{
    return ray_rgb_make(a.r + b.r, a.g + b.g, a.b + b.b);
}

static inline ray_rgb ray_rgb_mul(ray_rgb a, ray_rgb b)
{
    return ray_rgb_make(a.r * b.r, a.g * b.g, a.b * b.b);
}

static inline ray_rgb ray_rgb_scale(ray_rgb c, double s)
{
    return ray_rgb_make(c.r * s, c.g * s, c.b * s);
}

static inline ray_rgb ray_rgb_madd(ray_rgb acc, ray_rgb a, ray_rgb b)
{
    return ray_rgb_make(acc.r + a.r * b.r, acc.g + a.g * b.g,
                        acc.b + a.b * b.b);
}

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
                                      interpolating mesh (s, t); a
                                      sphere whose material lacks it
                                      gets no (u, v) (0) in a render */
#define RAY_EFFECT_CAUSTICS  16u   /* reads ray_caustics_at: photons are
                                      stored on its surfaces (a render
                                      with photons > 0 traces them only
                                      if the scene can make a caustic:
                                      ray_scene_effects) */
#define RAY_EFFECT_SCATTER   32u   /* scatters photons: its "scatter"
                                      function is called (not NULL);
                                      without this bit the field is
                                      ignored, whatever it holds */

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
                                0: the scene's naive mode
                                (ray_limits.no_pruning), spawn every
                                effect the material declared, whatever
                                its weight (for comparisons) */
    /* Ray cones (Akenine-Moller et al., "Texture Level of Detail
    ** Strategies for Real-Time Ray Tracing", Ray Tracing Gems, 2019),
    ** set only in a scene whose effects include RAY_EFFECT_TEXTURE and
    ** for a ray that carries a cone (ray_render_options.no_cones 0,
    ** ray_ctx_set_cone), else 0: */
    double cone_width;       /* the cone's width at the hit, across the
                                ray, in world units */
    double footprint;        /* its footprint in texture units (u, v):
                                cone_width / |cos incidence| times the
                                surface's (u, v) per world unit, when the
                                hit's material declared RAY_EFFECT_TEXTURE
                                and that scale is known (ray_trace(3),
                                "Ray cones"); +Inf at grazing incidence;
                                0 = unknown: sample unfiltered */
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

/*
** A material's photon scattering function, for caustics (forward
** tracing: light -> specular surfaces -> a diffuse one).  Called at a
** photon's hit with the shade args a camera ray would get there
** (args->ray is the photon's ray, args->depth its specular bounces so
** far, args->weight 1); CONCURRENTLY from the photon threads, like
** "shade".  Return 1 and write the direction the photon goes on in (any
** length, not zero) and the per-channel factor its power is multiplied
** by (finite, >= 0), when it goes on specularly; return 0 (nothing
** read) when it stops here.  It may draw ray_ctx_random(ctx), which is
** seeded per photon (a dielectric picks reflection with probability F
** and refraction with 1 - F, both with weight 1: Russian roulette keeps
** the power unbiased without splitting the photon); it must not call
** ray_trace (refused: RAY_EEFFECT) nor cast shadow rays.  The built-in
** mirror, glass and Phong with reflect > 0 have one (ray_material_mirror).
*/
typedef int (*ray_scatter_fn)(void *ud, ray_ctx *ctx,
                              const ray_shade_args *args, ray_vec3 *dir,
                              ray_rgb *weight);

/*
** A material.  "scatter" was added after the first three fields (no
** release was tagged before it) and is read only when "effects" has
** RAY_EFFECT_SCATTER: a material written as { shade, ud, effects }, or
** filled field by field by code older than the field, stops photons.
*/
typedef struct ray_material {
    ray_shade_fn shade;
    void *ud;                /* borrowed: must outlive the scene */
    unsigned effects;        /* RAY_EFFECT_* bits it may request */
    ray_scatter_fn scatter;  /* with RAY_EFFECT_SCATTER: how photons go
                                on from its surfaces (specular) */
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
    int kind;                /* RAY_LIGHT_*; 0: a point light */
    ray_vec3 position;
    ray_vec3 direction;      /* directional lights; (0, 0, 0): (0, -1, 0),
                                straight down */
    ray_vec3 edge1, edge2;   /* rectangular lights; (0, 0, 0): (1, 0, 0)
                                and (0, 0, 1), the unit square that
                                emits downward */
    double radius;           /* spherical lights; 0: 1 */
    ray_rgb intensity;       /* no default: (0, 0, 0) is a dark light */
    unsigned samples;        /* area lights: shadow rays per shading
                                point, rounded up to a square; 0 = 16;
                                at most RAY_MAX_LIGHT_SAMPLES (checked
                                for every kind) */
} ray_light;

/*
** Zero is the default of every field whose zero was no light at all (a
** zero direction, radius or edge, which ray_scene_add_light refused
** before 1.0), so {.kind = RAY_LIGHT_RECT, .position = p, .intensity =
** c} is a unit square light.  The intensity is the one field without a
** default: it is a colour, and a colour's zero is black everywhere in
** libray (a light dimmed to 0 stays dark; ray_render_check warns,
** RAY_RENDER_WARN_UNLIT, when every light is).
**
** ray_light_init -- *l as a light of "kind" (RAY_LIGHT_*) with every
** other field at its default: at the origin, intensity (1, 1, 1),
** direction (0, -1, 0) (straight down), radius 1, edges (1, 0, 0) and
** (0, 0, 1) (a unit square emitting downward), 16 samples: the zeros'
** defaults, and a white light.  Optional, as every init function is
** (ray(7), "Versions and ABI"); fields added later default to what init
** sets, which is what their zeros mean.
*/
RAY_API void ray_light_init(ray_light *l, int kind);

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
    int no_pruning;          /* 0 (the default): the tracer cuts rays whose
                                path weight falls below min_weight, and
                                materials are told (ray_shade_args.prune)
                                to spawn nothing that cannot contribute;
                                non-zero: the naive mode, every declared
                                effect traced up to max_depth, to measure
                                what pruning saves (the bench does) */
} ray_limits;

#define RAY_DEFAULT_MAX_DEPTH 8
#define RAY_DEFAULT_MIN_WEIGHT (1.0 / 256)  /* below one 8-bit level */
#define RAY_DEFAULT_MAX_FANOUT 2            /* a reflection + a refraction */

/*
** ray_limits_init -- *l set to the defaults above, pruning on.  The one
** struct whose zeros are all values, kept so: max_depth 0 traces the
** eye's rays alone (no bounce), min_weight 0 cuts no path by its weight,
** max_fanout 0 lets a hit spawn no secondary ray; each is a setting a
** program may want (a depth-0 preview, a reference render without the
** weight cut), and no other value of the field means the same.  So
** {0} is not the defaults here: ray_scene_set_limits(scene, NULL) is,
** and ray_limits_init fills a struct to change one field of them
** (no_pruning, whose zero is pruning on, is a default as usual).
*/
RAY_API void ray_limits_init(ray_limits *l);

/*
** ray_scene_new -- create an empty scene in *out.  "alloc" (NULL: libc,
** on Linux with blocks of 4 MiB or more on whole huge pages:
** doc/PLATFORMS.md) serves every allocation the scene makes, with
** "alloc_ud", including
** those of ray_ctx_new and ray_render on it: these may run on several
** threads at once after commit, so a shared allocator must then be
** thread-safe (a commit allocates on its calling thread only, even one
** that builds on several: ray_scene_set_build_threads; ray_render without
** photons too; the photon pass of ray_render and ray_photon_map_build
** allocates from its threads, unless given threads = 1).  Returns RAY_OK,
** RAY_EINVAL (out NULL) or RAY_ENOMEM.
** ray_scene_free -- release it; NULL is a no-op.  Free every context made
** on a scene (ray_ctx_free) before the scene itself; a photon map
** (ray_photon_map_build) may be freed before or after it.
**
** A scene is built by one thread at a time, then ray_scene_commit makes
** it queryable: any number of threads may then trace it at once, until
** it is changed.  Every ray_scene_add_* / _set_* (and
** ray_scene_update_mesh, ray_scene_remove) is allowed after a commit
** too: the change is STAGED, and the scene answers no query until it is
** committed again (ray_intersect and the other queries -RAY_ESTATE;
** ray_trace, ray_ctx_new and ray_render RAY_ESTATE; its effects 0).  A
** change must never overlap a query or a render of the
** scene on another thread: nothing can detect that race ("Changing a
** committed scene" below; ray(7), "Dynamic scenes").
*/
RAY_API int ray_scene_new(ray_scene **out, ray_alloc_fn alloc,
                          void *alloc_ud);
RAY_API void ray_scene_free(ray_scene *scene);

/*
** ray_scene_errmsg -- what went wrong in the scene's most recent building
** call (ray_scene_add_*, ray_scene_set_*, ray_scene_update_mesh,
** ray_scene_remove, ray_scene_commit), as
** sqlite3_errmsg: the function's name, then which argument, index or value
** failed, e.g. "ray_scene_add_mesh: triangle 0 index 7 out of range (3
** vertices)".  The empty string "" when that call succeeded, or before
** any.  For a NULL scene, the static text "no scene (NULL)" (a call on a
** NULL scene has nowhere to leave a message).  The string is owned by the
** scene: valid until its next building call or ray_scene_free; do not
** free it.  Like those calls, not to be called concurrently with them.
*/
RAY_API const char *ray_scene_errmsg(const ray_scene *scene);

/*
** Materials are copied into the scene (the ud they point to is borrowed).
** *id, if not NULL, receives the material's id, counted from 0.
** RAY_EINVAL for a NULL scene, material or shade function, or unknown
** effect bits; RAY_ENOMEM.
*/
RAY_API int ray_scene_add_material(ray_scene *scene, const ray_material *m,
                                   unsigned *id);

/*
** Geometry, each with a material id.  Copied into the scene.  *geom_id,
** if not NULL, receives the id that hits report in ray_hit.geom_id
** (counted from 0 over all geometry, never reused).  Added after a
** commit, geometry is staged for the next one (ray_scene_new).  Errors,
** with nothing added: RAY_EINVAL for NaN/Inf coordinates, a radius not
** > 0, a zero normal, an unknown material (RAY_NO_MATERIAL is always
** known) or fewer than 3 polygon vertices; RAY_EDEGENERATE for a
** zero-area triangle or polygon; RAY_ENOMEM.
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
** Positions and indices may instead come as games keep them: float or
** double positions with a byte stride (an interleaved vertex buffer, no
** alignment needed) in positions, 16- or 32-bit indices in index_data,
** each used when vertices (indices) is NULL, in the host's byte order.
** Floats convert exactly to double (every float is a double), so a
** float-sourced mesh is the mesh of the doubles of its floats: the same
** hits, bit for bit, and the same guarantees (no leaks, no acne).
** Hits report the mesh's geom_id and prim_id = i.  Triangles that have no
** normal (zero area, or a cross product that overflows) are kept in the
** count but can never be hit.
**
** Errors, with nothing added: RAY_EINVAL for NULL pointers (vertices and
** positions both NULL, or indices and index_data), no vertices or
** triangles, an index >= vertex_count, a NaN/Inf vertex (position),
** normal or texture coordinate, an unknown material, an unknown
** position_type or index_type (when read), a position_stride other
** than 0 smaller than a position (12 bytes of floats, 24 of doubles), or
** flags other than RAY_MESH_BORROW; RAY_ENOMEM (also for more than
** 2^31 - 1 triangles in the scene).
**
** Memory: the scene keeps a mesh's positions as doubles (24 bytes a
** vertex, about 12 a triangle in a closed mesh) and its indices (12 bytes
** a triangle), which the exact triangle test reads; after commit each
** triangle adds its ids (8 bytes), a float copy of its corners in the
** BVH's leaves (36 bytes, what the float filter in front of the exact
** test reads) and about 10 bytes of BVH: 78 bytes in all on a
** million-triangle grid and on the Stanford bunny (bench/mesh,
** bench/filter) when every position is a float (RAY_FLOAT32 input, or
** doubles that are floats): the exact test then reads the leaves' floats
** too.  Positions that are not floats add a double copy of each
** triangle's corners in leaf order (72 bytes), which the exact test reads
** instead of the positions through the indices: 150 bytes in all.
** Plus the per-vertex attributes when normals or texture
** coordinates are given (the caller's own when borrowed,
** RAY_MESH_BORROW); after its first refit (ray_scene_update_mesh) the
** scene keeps 4 bytes a leaf and 12 a triangle more (every live
** triangle's vertex indices in the tree's order, which each refit reads).
** ray_scene_commit briefly needs about 133 bytes per triangle.
*/
/* Element types of ray_mesh's positions (RAY_FLOAT*) and index_data
** (RAY_UINT*); 0 is none of them. */
enum {
    RAY_FLOAT32 = 1,             /* float */
    RAY_FLOAT64,                 /* double */
    RAY_UINT16,                  /* uint16_t */
    RAY_UINT32                   /* uint32_t */
};

typedef struct ray_mesh {
    const ray_vec3 *vertices;
    size_t vertex_count;
    const unsigned *indices;     /* 3 per triangle */
    size_t triangle_count;
    const ray_vec3 *normals;     /* NULL, or vertex_count normals */
    const double *texcoords;     /* NULL, or 2 * vertex_count values */
    /* Vertex input as games keep it, read when vertices (indices) is
    ** NULL: position i is 3 values of position_type starting
    ** i * position_stride bytes into positions (stride 0: packed). */
    const void *positions;
    size_t position_stride;
    int position_type;           /* RAY_FLOAT32 or RAY_FLOAT64 */
    const void *index_data;      /* 3 per triangle */
    int index_type;              /* RAY_UINT16 or RAY_UINT32 */
    unsigned flags;              /* RAY_MESH_BORROW, or 0: copied */
} ray_mesh;
/* Zero is the default: fill a ray_mesh from {0} or by a designated
** initializer; a field left 0 (NULL) is absent (stride 0: packed; flags
** 0: copied), and so is one a later version adds. */

/*
** RAY_MESH_BORROW: the scene keeps the caller's arrays instead of copying
** its shading data (indices, normals, texture coordinates: 12 bytes a
** triangle and up to 40 a vertex saved), and ray_scene_update_mesh(scene,
** id, NULL) reads the positions again from them after the caller changed
** them in place (Embree's shared buffers).  The traversal keeps its own
** flattened copy of the triangles either way.  Lifetime: every array the
** mesh names must stay valid and unchanged while the scene may shade or
** update the mesh, until the mesh is removed or updated from other arrays
** or the scene is freed; changing positions in place is seen only at
** ray_scene_update_mesh and the commit after it.
*/
#define RAY_MESH_BORROW 1u

RAY_API int ray_scene_add_mesh(ray_scene *scene, const ray_mesh *mesh,
                               unsigned material, unsigned *geom_id);

/*
** Lights (copied).  RAY_EINVAL for an unknown kind, non-finite or
** negative intensity, a zero direction (directional), a radius not > 0
** (sphere), parallel edges (rect) or samples > RAY_MAX_LIGHT_SAMPLES.
*/
RAY_API int ray_scene_add_light(ray_scene *scene, const ray_light *light,
                                unsigned *id);

/* The background (default black): "color", or with a function "fn" (NULL:
** none) what fn(ud, ray, out) makes of it for each escaping ray, *out
** preset to the colour; fn is called CONCURRENTLY from the render threads
** like materials, and "ud" is borrowed.  The ambient light given to
** materials (default black).  Tree limits (NULL: the defaults, pruning
** on; the naive mode is a field of the limits, no_pruning); RAY_EINVAL
** for max_depth > RAY_MAX_DEPTH or min_weight outside [0, 1].  Colours
** must be finite and >= 0 (else RAY_EINVAL). */
typedef void (*ray_background_fn)(void *ud, const ray_ray *r, ray_rgb *out);
RAY_API int ray_scene_set_background(ray_scene *scene, ray_rgb color,
                                     ray_background_fn fn, void *ud);
RAY_API int ray_scene_set_ambient(ray_scene *scene, ray_rgb ambient);
RAY_API int ray_scene_set_limits(ray_scene *scene, const ray_limits *limits);

/*
** ray_scene_effects -- after commit, the RAY_EFFECT_* bits the scene can
** ever need: the union of the effects of the materials its enabled
** geometry uses (its instances' children's included), without
** RAY_EFFECT_SHADOW when it has no lights, and without
** RAY_EFFECT_CAUSTICS and RAY_EFFECT_SCATTER unless it can make a caustic
** (a light, a material that scatters photons and one that gathers
** them: then photons are traced when asked for).  0 while not committed
** (before the first commit, or with a change staged).
*/
RAY_API unsigned ray_scene_effects(const ray_scene *scene);

/*
** ray_scene_set_watertight -- 1 (the default): the scene's triangles and
** meshes are intersected with ray_triangle_watertight, so no ray passes
** between the triangles of a closed mesh (measured: Cramer's rule in
** double lets 0.1 to 10% of the rays aimed exactly at shared vertices and
** edges through, see ray-numerics(7)).  0: with ray_triangle, the
** lecture's Cramer's rule, the fast path (bench/RESULTS.md gives both
** speeds on the bunny).  The setting of an instanced scene applies to its
** own triangles.  RAY_EINVAL (NULL).
*/
RAY_API int ray_scene_set_watertight(ray_scene *scene, int enabled);

/*
** ray_scene_set_build_threads -- how many threads ray_scene_commit builds
** the BVHs on: 1 (the default), the calling thread alone, so that the
** library never starts a thread a program did not ask for (a game may
** have its own threads busy); 0, one per online CPU; n, up to n (the
** calling thread and n - 1 started inside the commit and joined before
** it returns; no more than the build can use, at most 64).  The tree is
** the same, bit for bit, at every thread count, so are the queries'
** answers; a thread that cannot be started only means fewer threads.
** Besides the subtrees, a large mesh's triangle boxes, the binning of
** the top nodes (16,384 items and more) and the leaves' rows run on the
** threads.
** A commit that refits (after ray_scene_update_mesh) fits the leaves of
** a large mesh (2,048 leaves or more) on the same threads: the same
** boxes.  The scene's allocator is still called on the committing thread
** only, and the threads call nothing of the program's (user geometry's bounds
** callback runs when it is added, not at commit).  A scene given the
** program's scheduler (ray_scene_set_scheduler) builds on it instead.  Like every
** ray_scene_set_*, a call after a commit stages a change (the scene
** answers no query until it is committed again), but that commit
** rebuilds nothing for it: the setting takes effect at the next build.
** RAY_EINVAL (NULL).
*/
RAY_API int ray_scene_set_build_threads(ray_scene *scene, unsigned threads);

/*
** The program's own job system -- a game engine's workers -- to run the
** library's parallel work instead of threads of its own, as PhysX's CPU
** dispatcher and Jolt's job system take theirs.  The work comes as
** tasks: run(ud, count, task, task_ud) must call task(task_ud, i) once
** for every i in 0 .. count - 1, in any order, on any threads, at once
** or one after another, and return only when all have returned.  Tasks
** never wait for one another, so running them all on the calling thread
** is correct too (what run may do when no worker is free); run may be
** called from one of its own workers (a render inside a job) and must
** not then wait for a worker that only this call could free.  Every
** answer is the same, byte for byte, whichever order and threads run
** the tasks.  The tasks call the program back only as the built-in
** threads do: a render's materials, backgrounds, filters and progress
** callback, the photon pass's materials (and its scene's allocator).
**
** "threads": how many tasks the scheduler runs at once (its workers), 0
** if it does not say: ray_render and the photon pass split their work
** into that many tasks when their options' threads is 0 (and into one
** per online CPU if this is 0 too).  A render task runs materials and
** their ray trees: its workers want the stack the built-in threads get
** (4 MiB), or what the materials need.
**
** Zero is the default: a scheduler whose run is NULL (a zeroed one)
** means the built-in threads, and a field added later is 0 in {0} or a
** designated initializer (doc/DESIGN.md, "Versions and ABI").
*/
typedef void (*ray_task_fn)(void *task_ud, unsigned index);

typedef struct ray_scheduler {
    void (*run)(void *ud, unsigned count, ray_task_fn task, void *task_ud);
    void *ud;                /* run's first argument */
    unsigned threads;        /* tasks it runs at once; 0: not said */
} ray_scheduler;

/*
** ray_scene_set_scheduler -- run the scene's parallel work on the
** program's job system: "scheduler" is COPIED (its ud is BORROWED: it
** must outlive every use), NULL (the default) for the built-in threads.
** ray_scene_commit's BVH builds then hand it all their parallel work
** (the subtrees; for a large mesh also the triangles' boxes, the top
** nodes' binning and the leaves' rows; a refit's leaves), where the
** build threads setting no longer applies: the scheduler chooses the
** threads, and ray_render and ray_photon_map_build use it unless their
** options name one.  Both are needed: a commit has no options to carry
** one, while a committed scene may be rendered from several threads at
** once, each render on its own pool, which a setting cannot give (a
** setting stages a change: the scene answers nothing until the next
** commit).  The tree and every image are the same bytes with or without
** a scheduler.  RAY_EINVAL (NULL scene); a change staged like any
** setting's, which the next commit rebuilds nothing for.
*/
RAY_API int ray_scene_set_scheduler(ray_scene *scene,
                                    const ray_scheduler *scheduler);

/*
** ray_scene_commit -- make what was built or changed take effect: the
** first commit builds the acceleration structures (on the calling thread,
** or on those ray_scene_set_build_threads asks for: the same tree), a
** later one refits or rebuilds only what changed since ("Changing a
** committed scene" below) and takes the new boxes of instanced scenes
** committed again since.
** The scene then answers queries, from any number of threads, until its
** next change.  A commit with nothing staged (and no instanced scene
** committed again) does nothing and returns RAY_OK.  Returns RAY_OK,
** RAY_EINVAL (NULL, or an instanced scene that now has planes or
** instances), RAY_ESTATE (an instanced scene changed and not committed
** again: commit it first), RAY_ENOMEM (acceleration structures) or
** RAY_ECANCELED (the progress callback cancelled the build:
** ray_scene_set_progress); on failure the changes stay staged and the
** commit may be retried.
*/
RAY_API int ray_scene_commit(ray_scene *scene);

/*
** Progress of long work, and its cancel: called with how much is done of
** how much there is, and returns non-zero to cancel.  A render calls it
** after each finished row (ray_render_options: its counts are rows), and
** before the rows as its photon pass traces caustics' photons, as
** ray_photon_map_build does (its counts are photons); a commit as it
** builds its BVHs (ray_scene_set_progress: its counts are primitives).
*/
typedef int (*ray_progress_fn)(void *ud, unsigned rows_done,
                               unsigned rows_total);

/*
** ray_scene_set_progress -- report a commit's BVH builds to "fn" (with
** "ud" first), and let it cancel them (NULL: no callback, the default),
** as Embree's build progress monitor: for a large mesh, a progress bar
** and a Cancel button.  A commit that rebuilds a BVH calls fn(ud, done,
** total) with done the primitives placed in the trees so far and total
** those the commit builds over (the live triangles of a changed mesh
** set and the other bounded geometry, when each is rebuilt), every 4096
** or more, done rising, and last with done == total once every tree is
** built; a commit that rebuilds nothing (a refit, a no-op) does not call
** it.  The calls come from the committing thread, or from the build's
** threads (ray_scene_set_build_threads, ray_scene_set_scheduler) one at
** a time, never again once fn has returned non-zero.  Non-zero cancels:
** the build stops at its threads' next report and the commit returns
** RAY_ECANCELED (ray_scene_errmsg says where), leaving the scene as
** before the commit -- not committed, its changes staged, queries
** -RAY_ESTATE -- so that a later commit builds the same trees and the
** same answers, bit for bit.  The callback costs one call per 4096
** primitives or more; it must not change or query the scene.  A setting
** like the others: staged, rebuilding nothing.  RAY_OK, RAY_EINVAL (NULL
** scene).
*/
RAY_API int ray_scene_set_progress(ray_scene *scene, ray_progress_fn fn,
                                   void *ud);

/* ---------------------------------------------------------- 6. textures */

/*
** Texture coordinates (s, t) reach a material as ray_shade_args.u, v:
** sphere: longitude and latitude (ray_sphere); plane and polygon: the
** projected tangent axes (ray_plane); triangle: the barycentrics; mesh:
** its per-vertex (s, t) interpolated by the barycentrics; torus: its two
** angles; box: the position on the face (ray_box); capsule: the angle
** around its axis and the meridian's arc (ray_capsule); Bezier and
** parametric: (u, v); implicit: the surface's uv callback.
**
** A texture is a function of the shading point, called CONCURRENTLY from
** the render threads: write the colour at args (usually at args->u, v)
** into *out.  Materials that take one (ray_phong_params.texture) declare
** RAY_EFFECT_TEXTURE.
*/
typedef void (*ray_texture_fn)(void *ud, const ray_shade_args *args,
                               ray_rgb *out);

typedef struct ray_texture {
    ray_texture_fn fn;           /* NULL: no texture */
    void *ud;                    /* borrowed */
} ray_texture;

/*
** Images for textures.  ray_image_load_png reads a PNG file through libpng
** (any bit depth and colour type, interlaced or not: palette and grey are
** expanded, alpha composed on black in linear light) and stores it as
** linear RGB floats.  An sRGB chunk, or no gamma information in an 8-bit
** file, means the exact IEC 61966-2-1 curve; a gAMA chunk g means
** linear = code^(1/g); a 16-bit file without either is linear (as
** ray_write_png's 16-bit files are).
** RAY_OK; RAY_EINVAL (NULLs); RAY_EIO (the file cannot be opened or read:
** errno); RAY_EPNG (not a PNG, corrupt or truncated); RAY_ENOMEM;
** RAY_ELIMIT (over a load limit, refused from the headers before the
** image or the chunk is allocated); RAY_ENOTSUP in a library built
** without libpng (make PNG=0), after the RAY_EINVAL checks.  *out is
** untouched on failure.
**
** "opt" sets limits for files from untrusted sources (opt NULL, or a
** field 0: the default, 16384 pixels a side, 64 MiB a chunk: a 193-byte
** file cannot ask for gigabytes).  Memory grows with the rows decoded, so a file that declares a large image and then fails
** costs little; a decoded image takes 12 bytes per pixel.
**
** Both constructors build the image's mip pyramid when it is made (the
** exact area-weighted box filter: each level half the one below in each
** dimension, rounded down, down to 1 x 1; an odd side is reduced with
** weights by overlap, e.g. 5 texels to 2 with (0.4 0.4 0.2) and (0.2 0.4
** 0.4), so every level keeps the image's mean colour; a 1 x N image
** halves only N).  The pyramid takes about 1/3 more memory (a square
** image: 16 bytes per pixel in all; at most twice the image for a 1 x N
** strip).
**
** ray_image_new -- an image of width x height texels copied from "rgb":
** linear RGB floats, 3 per texel, rows top to bottom (as ray_write_png
** takes them), for procedural textures.  RAY_OK; RAY_EINVAL (NULLs, a
** zero size, a value that is NaN or infinite); RAY_ELIMIT (a side over
** 16384, ray_image_load_png's default limit); RAY_ENOMEM.  *out is
** untouched on failure.
**
** ray_image_free(NULL) is a no-op.  ray_image_size writes width and
** height (either pointer may be NULL).
**
** ray_image_sample -- the image at texture coordinates (s, t), s from the
** left edge (0) to the right (1), t from the BOTTOM row (0) to the top (1),
** repeating outside [0, 1) (wrap), filtered over a footprint "width" wide
** in texture units (1: the whole image; usually ray_shade_args.footprint).
** Width 0, or any width within one texel: filtered bilinearly between the
** four nearest texel centres of the image itself.  Wider: trilinear
** mip-mapping, level lambda = log2(width * max(image width, height))
** blended between the two levels around it; a width beyond the image
** (+Inf included) gives the 1 x 1 level, the mean colour.  RAY_OK, or
** RAY_EINVAL (NULL, s or t not finite, width NaN or negative: nothing
** written).
**
** ray_texture_image -- a texture that samples "img" at (args->u, args->v),
** filtered over args->footprint when it is positive (the ray carried a
** cone, ray_render_options.no_cones 0), else bilinearly (width 0).
** The image is BORROWED: it must outlive every scene that uses it.
** Loaded images are read-only and may be shared between threads.
*/
typedef struct ray_image ray_image;

typedef struct ray_image_load_options {
    unsigned max_width;      /* pixels; 0: 16384 */
    unsigned max_height;     /* pixels; 0: 16384 */
    size_t max_pixels;       /* width * height; 0: 16384 * 16384 */
    size_t max_chunk_bytes;  /* the largest chunk but IDAT; 0: 64 MiB */
} ray_image_load_options;

RAY_API int ray_image_load_png(const char *path,
                               const ray_image_load_options *opt,
                               ray_image **out);
RAY_API int ray_image_new(unsigned width, unsigned height, const float *rgb,
                          ray_image **out);
RAY_API void ray_image_free(ray_image *img);
RAY_API void ray_image_size(const ray_image *img, unsigned *width,
                            unsigned *height);
RAY_API int ray_image_sample(const ray_image *img, double s, double t,
                             double width, ray_rgb *out);
RAY_API ray_texture ray_texture_image(const ray_image *img);

/* ------------------------------------------------ 7. built-in materials */

/*
** Written with the public callback API only (src/trace/materials.c): read them
** as examples.  Each constructor returns a ray_material whose ud is the
** given parameter block, which is BORROWED and must outlive the scene.
**
** ray_material_phong: ambient*diffuse + sum over lights of diffuse *
**   max(0, n.l) + specular * max(0, r.v)^shininess (Phong) or
**   max(0, n.h)^shininess (Blinn-Phong if blinn != 0), each light sample
**   shadowed; plus a mirror term if reflect is non-zero.  Lambert is
**   specular = reflect = 0.  With a texture, diffuse is multiplied by
**   the texture's colour at the hit (and RAY_EFFECT_TEXTURE declared).
** ray_material_mirror: perfect mirror, reflectance per channel.
** ray_material_glass: dielectric: Fresnel-weighted reflection and
**   refraction (Snell; total internal reflection), optional Beer-Lambert
**   absorption per unit distance inside.
** ray_material_checker: picks "even" or "odd" by the parity of
**   floor(u*scale) + floor(v*scale) (scale 0: 1) and shades with it
**   (with the union of the two materials' effects).
**
** The effects are fixed when the material is made, from the parameter
** block as it is then (Phong declares RAY_EFFECT_REFLECTION only if
** reflect is non-zero).  Glass blocks shadow rays like any surface.
*/
typedef struct ray_phong_params {
    ray_rgb diffuse;         /* no default: (0, 0, 0) is black */
    ray_rgb specular;        /* (0, 0, 0): no highlight */
    double shininess;        /* the lobe's exponent; 0:
                                RAY_DEFAULT_SHININESS */
    int blinn;               /* 0: Phong's lobe; non-zero: Blinn's */
    ray_rgb reflect;         /* (0, 0, 0): no mirror term */
    ray_texture texture;     /* fn != NULL: diffuse is multiplied by it */
} ray_phong_params;

/* The specular lobe's exponent where shininess is 0: a cos^0 lobe, as
** bright at grazing angles as head-on, is no highlight at all (an
** exponent of 1e-9 still gives it, to the eye), so zero is a default. */
#define RAY_DEFAULT_SHININESS 32

typedef struct ray_glass_params {
    double ior;              /* index of refraction inside; 0: 1.5,
                                window glass (the default) */
    ray_rgb absorption;      /* Beer-Lambert coefficient per unit length */
} ray_glass_params;

/* ray_phong_params_init -- a grey Lambertian surface: diffuse (0.8, 0.8,
** 0.8), no specular (shininess RAY_DEFAULT_SHININESS if one is set),
** Phong's lobe, no reflection, no texture.  Its one value that {0} does
** not give is the diffuse colour: a colour's zero is black (a glossy
** black surface is specular alone), so a surface names its colour, or
** starts here.  A glass's zeros are its defaults: ior 0 is 1.5 (window
** glass), absorption 0 none, so {0} is window glass. */
RAY_API void ray_phong_params_init(ray_phong_params *p);

typedef struct ray_checker_params {
    ray_material even, odd;
    double scale;            /* squares per unit of u and v; 0: 1 (a
                                zero scale would be one square, never
                                a checkerboard) */
} ray_checker_params;

RAY_API ray_material ray_material_phong(const ray_phong_params *p);
RAY_API ray_material ray_material_mirror(const ray_rgb *reflectance);
RAY_API ray_material ray_material_glass(const ray_glass_params *p);
RAY_API ray_material ray_material_checker(const ray_checker_params *p);

/* ---------------------------------------------------------- 8. counters */

/*
** Kinds of primitives, for the intersection-test counters.
** RAY_PRIM_KINDS is the number in use; ray_stats.tests_by_kind has room
** for RAY_PRIM_KINDS_MAX, so that a kind added later (numbered after the
** last, before RAY_PRIM_KINDS) leaves ray_stats' size and layout as they
** are.  The counters from RAY_PRIM_KINDS up stay 0.
*/
enum {
    RAY_PRIM_SPHERE = 0,
    RAY_PRIM_PLANE,
    RAY_PRIM_TRIANGLE,           /* triangles and mesh triangles */
    RAY_PRIM_POLYGON,
    RAY_PRIM_TORUS,
    RAY_PRIM_IMPLICIT,
    RAY_PRIM_PARAMETRIC,           /* parametric surfaces and Bezier patches */
    RAY_PRIM_BOX,
    RAY_PRIM_CAPSULE,
    RAY_PRIM_INSTANCE,           /* instances entered (ray_scene_add_instance);
                                    their geometry's tests count by kind */
    RAY_PRIM_USER,               /* ray_scene_add_user geometry */
    RAY_PRIM_KINDS
};
#define RAY_PRIM_KINDS_MAX 16

/* samples_hist[n] counts the pixels that took n samples (n < 64);
** samples_hist[64], those that took 64 or more. */
#define RAY_HIST_BINS 65

/* Counters of one context or one render (summed over its threads). */
typedef struct ray_stats {
    unsigned long long rays[RAY_KIND_COUNT];  /* traced, by RAY_KIND_* */
    unsigned long long tests;       /* ray-primitive intersection tests */
    unsigned long long tests_by_kind[RAY_PRIM_KINDS_MAX];  /* the same, by
                                       RAY_PRIM_*; RAY_PRIM_KINDS in use */
    unsigned long long cut_depth;   /* rays refused by max_depth */
    unsigned long long cut_weight;  /* rays refused by min_weight */
    unsigned long long cut_fanout;  /* rays refused by max_fanout */
    unsigned max_depth;             /* deepest level reached */
    unsigned long long pixels;      /* pixels rendered (ray_render) */
    unsigned long long samples_hist[RAY_HIST_BINS];
    unsigned long long root_failures;  /* implicit, parametric or user
                                          tests that failed (iteration
                                          limit, or a callback giving NaN,
                                          Inf or an invalid hit) and were
                                          taken as misses */
    unsigned long long filter_calls;   /* filter callbacks called
                                          (ray_scene_set_filter) */
    unsigned long long photons_emitted; /* photons traced from the lights
                                           (ray_render, caustics) */
    unsigned long long photons_stored;  /* photon hits stored after >= 1
                                           specular bounce */
    unsigned long long photon_lookups;  /* ray_caustics_at density
                                           estimates over a photon map */
    unsigned long long batch_packets;   /* rays of ray_intersect_batch and
                                           ray_occluded_batch traced eight
                                           together through the BVH */
    unsigned long long batch_single;    /* and those traced one by one */
    unsigned long long shadows_undeclared; /* shadow rays a material asked
                                           for (ray_light_visible,
                                           ray_shade_direct) without
                                           declaring RAY_EFFECT_SHADOW:
                                           not cast, the light taken as
                                           unoccluded.  Not 0: a material
                                           forgot the flag, and the image
                                           lacks its shadows */
    unsigned long long traces_undeclared; /* reflection and refraction
                                           rays a material asked for
                                           (ray_trace) without declaring
                                           RAY_EFFECT_REFLECTION or
                                           RAY_EFFECT_REFRACTION: refused
                                           with RAY_EEFFECT.  Not 0: a
                                           material forgot a flag, and
                                           the image lacks what it
                                           asked for */
} ray_stats;

/* --------------------------------------------------------- 9. rendering */

/*
** A pinhole camera at "position" looking at "look_at", "up" giving the
** roll, "vfov" the vertical field of view in degrees.  aperture > 0 makes
** it a thin lens of that diameter focused at focus_distance (0: the
** distance to look_at), for depth of field.  Zero is the default: up
** (0, 0, 0) means (0, 1, 0) and vfov 0 means 60 degrees, so that
** { .position = eye, .look_at = target } is a camera; position and
** look_at are the two fields with no default (they must differ).
*/
typedef struct ray_camera {
    ray_vec3 position, look_at, up;
    double vfov;
    double aperture;
    double focus_distance;
} ray_camera;

typedef struct ray_render_options {
    unsigned width, height;  /* the whole frame, in pixels */
    unsigned y0, y1;         /* render rows y0 <= y < y1 only (y1 = 0:
                                height); rows are counted from the top */
    unsigned threads;        /* tasks to render on; 0 = the scheduler's
                                threads, or one per online CPU */
    unsigned samples;        /* per pixel, 1 .. RAY_MAX_PIXEL_SAMPLES;
                                0: 1, the default;
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
    ** adaptive_depth levels (1 .. 8; 0: 2, the default), so a pixel takes 4 to
    ** 4 + 5 (4^depth - 1) / 3 samples (samples_hist; a point on an edge
    ** shared by two split squares counts for each, but a thread traces
    ** it once, and a row's top edge once with the row above).  +Inf
    ** samples the corners only.  Samples sit on a fixed lattice of the
    ** frame and are seeded by their position: any thread count or region
    ** split gives the same bytes. */
    double adaptive_threshold;
    unsigned adaptive_depth;
    /* Ray cones (ray_ctx_set_cone): unless no_cones is set (0, the
    ** default: cones on), camera rays carry a cone of width 0 at
    ** the eye and spread atan(2 tan(vfov/2) / height)
    ** (one pixel's angle), divided by sqrt(samples) with several samples
    ** per pixel (each sample stands for its stratum, 1/sqrt(samples) of
    ** the pixel across: a sample filtered over the whole pixel would blur
    ** the image twice); the whole pixel's angle with adaptive
    ** antialiasing (a lattice point's value does not depend on the square
    ** it serves).  A textured hit then filters its texture over the
    ** cone's footprint (ray_texture_image).  no_cones non-zero: rays are
    ** lines, footprint 0, textures sampled bilinearly (ray_image_sample's
    ** width 0).  The cone models the pixel, not a lens's defocus.  Only
    ** where the scene's effects include RAY_EFFECT_TEXTURE (as
    ** ray_trace's cones) and some material can read the cone: a scene
    ** whose materials (an instanced child's included) are the built-in
    ** mirror, glass, Phong without a texture function and checkers of
    ** these (a checker reads (u, v), not the cone) renders as with
    ** no_cones, the same image for less work; with a user's material or
    ** a texture function among them, camera rays get the cone.  (libray
    ** 0.1 called it
    ** "cones", on when non-zero, so that {0} turned it off.) */
    int no_cones;
    /* Caustics (ray_caustics_at): photons emitted from the lights before
    ** the frame, 0 (the default) for none, at most RAY_MAX_PHOTONS; they
    ** are traced only if ray_scene_effects has RAY_EFFECT_CAUSTICS.  The
    ** gather radius in world units, 0 for the automatic one (ray(7),
    ** "Caustics"): r = D / 100 * (photons / 100000)^(-1/6), D the
    ** diagonal of the box of the geometry whose material scatters
    ** photons (progressive photon mapping's shrinking radius, alpha =
    ** 2/3: the estimate converges as photons grow; D is the scene's
    ** bounded geometry's diagonal when some scattering geometry is a
    ** plane). */
    unsigned long long photons;
    double photon_radius;
    /* The program's job system (ray_scheduler, BORROWED for the call) for
    ** this render and its photon pass; NULL: the scene's
    ** (ray_scene_set_scheduler), or else the built-in threads. */
    const ray_scheduler *scheduler;
} ray_render_options;

/* Photons per frame: 2^26 (about 67 million), so the photon map (48
** bytes a stored photon, up to max_depth stores a photon) stays within
** a few GiB. */
#define RAY_MAX_PHOTONS (1ull << 26)

/*
** Zero is the default: every field 0 (a zeroed struct, the fields a
** designated initializer leaves out) means the whole frame, all CPUs, 1
** sample, seed 0, no callback, no adaptive antialiasing (threshold 0,
** depth 2 if it is turned on), ray cones on, no photons (caustics off),
** automatic photon radius, no scheduler (the scene's).  width and height
** are the two fields with no default: { .width = 640, .height = 480 }.
*/

/*
** ray_render -- render rows [y0, y1) of the frame into "rgb": linear float
** RGB, 3 floats per pixel, width pixels per row, row y0 first; always
** finite (values beyond float's range are clamped to +-FLT_MAX, a NaN
** from a user material is stored as 0).  The render runs as "threads"
** tasks, on the built-in threads (the calling thread and threads - 1
** started and joined before it returns) or on a scheduler's workers
** (options->scheduler, else the scene's: ray_scene_set_scheduler); each
** task takes rows in contiguous bands from a shared counter (guided: each
** band a quarter of the remaining rows' share per task, at least one);
** every pixel's samples are seeded from (seed, x, y, sample), so the bytes
** are the same whatever the thread count, task order or region split.
** "stats", if not NULL, receives the counters summed over the tasks.
**
** The progress callback is called from the render's threads, one call at
** a time, and never again after it asked to cancel.  A render that
** traces photons (below) reports its photon pass first, done the photons
** traced of total = options->photons (a call per 4096, last done ==
** total), then its rows, done 1 .. y1 - y0.  Returns RAY_OK;
** RAY_ECANCELED if it cancelled (finished rows are kept, the rest is
** unspecified; cancelled in the photon pass, before any row: rgb and
** *stats untouched); RAY_ESTATE, before anything is rendered, for a scene not
** committed (never, or changed since), as the queries answer, or one
** that instances a scene changed since its own commit (commit the scene
** after its instanced scenes); RAY_EINVAL for NULLs, zero sizes,
** samples above RAY_MAX_PIXEL_SAMPLES, an adaptive threshold that is
** NaN or negative or an adaptive depth above 8, y0 >= y1 or y1 >
** height, or a degenerate camera (eye at look_at, up within 3.6e-15 rad
** of the view axis, vfov not in (0, 180); zeros are the defaults first), photons above
** RAY_MAX_PHOTONS or a photon_radius NaN, negative, infinite or whose
** pi r^2 under- or overflows (ray_caustics_at): ray_render_check says
** which and why; RAY_ENOMEM.  If fewer threads than asked can be
** started, the render goes on with those it has: the image is the same.
*/
RAY_API int ray_render(const ray_scene *scene, const ray_camera *camera,
                       const ray_render_options *options, float *rgb,
                       ray_stats *stats);

/*
** ray_render_check -- the checks ray_render makes of its arguments before
** it renders, with the reason in words: returns what ray_render would
** return for them (RAY_OK, RAY_EINVAL or RAY_ESTATE; a NULL rgb, its one
** other refusal, is not seen here) and writes into "msg" (at most "size"
** bytes, NUL-terminated, truncated if need be; msg NULL or size 0: not
** written) which argument or field failed, with its value and the rule,
** e.g. "ray_render: options samples 100000: must be 0 (1) ..
** RAY_MAX_PIXEL_SAMPLES (65536), also with adaptive antialiasing"; ""
** on RAY_OK without warnings.  ray_render runs these very checks, so the
** two cannot disagree; it can still fail later for RAY_ENOMEM,
** RAY_ECANCELED, or an automatic photon radius that overflows in a scene
** of extreme size.
**
** Warnings: arguments ray_render accepts and renders, but into an image
** that is black, or nearly.  With "warnings" not NULL and RAY_OK, it
** writes *warnings, the RAY_RENDER_WARN_* bits below (0: none), and msg
** names each, "ray_render: warning: " and their reasons joined by "; ";
** on a refusal *warnings is left untouched.  They never change the
** status: a warning is not an error, and ray_render renders the scene.
** With warnings NULL none is looked for (ray_render's own call: it pays
** nothing for them), and msg is "" on RAY_OK.  What no check can see
** (a material's callback asking for an effect it did not declare) the
** render counts instead: ray_stats.shadows_undeclared and
** traces_undeclared.
**
** Why a buffer of the caller's and not ray_scene_errmsg, where the
** building calls leave their reasons: ray_render takes a const scene
** that any number of threads may render at once, so a message written
** into the scene would be a data race between them and one render's
** reason could overwrite another's; a message buffer in the options
** would turn an input struct, often shared between threads, into an
** output.  A pure function of its arguments is reentrant and costs
** nothing on the render's path: call it after a failed ray_render (or
** before, to vet options a user typed, or a scene for the warnings).
** ray_render leaves ray_scene_errmsg as it was.
*/
/* No light of non-zero intensity (a light whose intensity is 0 in every
** channel counts as none) and a black ambient: every surface that the
** built-in materials shade is black; a material of the caller's that
** gives light of its own is not seen. */
#define RAY_RENDER_WARN_UNLIT      1u
/* No geometry a camera ray can hit (none enabled with a non-zero mask;
** an instance counts as geometry) and a constant black background: every
** pixel is black. */
#define RAY_RENDER_WARN_EMPTY      2u
/* The camera's position is inside a solid or on its surface: a sphere,
** box, capsule or closed mesh, through instances, counted as ray_contains
** counts them without RAY_CONTAINS_WINDING (by parity: a point inside
** two overlapping solids is inside neither), the boundary included (for
** a sphere, |position - center|^2 <= radius^2 as rounded).  Open meshes,
** triangles and the other kinds bound no solid: not looked at.  A room
** modelled as a closed solid around the camera sets it too, lit or not:
** it says every camera ray starts inside, not that the image is wrong.
** With a lens (aperture > 0) the test is of position, the lens's centre. */
#define RAY_RENDER_WARN_EYE_INSIDE 4u

RAY_API int ray_render_check(const ray_scene *scene, const ray_camera *camera,
                             const ray_render_options *options,
                             unsigned *warnings, char *msg, size_t size);

/*
** Caustics: light that reaches a diffuse surface through specular ones
** (L S+ D E), which tracing from the eye cannot find.  With
** options->photons > 0 and a scene whose ray_scene_effects has
** RAY_EFFECT_CAUSTICS (a light, enabled geometry with a scattering
** material, enabled geometry with a material declaring
** RAY_EFFECT_CAUSTICS), ray_render first emits that many photons from
** the lights (chosen in proportion to their power, aimed at the box of
** the scattering geometry, each photon's power scaled by the fraction of
** the light's emission it stands for, so the estimate stays unbiased),
** traces them through the scattering materials (ray_scatter_fn) and
** stores them where they land on a RAY_EFFECT_CAUSTICS material after
** at least one specular bounce.  Photon i is seeded from (seed, i) alone
** and the map is kept in photon order: the same bytes at any thread
** count.  Other scenes trace no photon (photons_emitted = 0) and render
** the same bytes as with photons = 0.
**
** ray_caustics_at -- called from a material declaring
** RAY_EFFECT_CAUSTICS: the irradiance the photon map gives at the hit,
** E = (sum of the power of the photons within the radius r of hit->p
** that arrive at the front of args->normal) / (pi r^2) (the plain disk
** kernel), in the units of the direct term of ray_shade_direct
** (intensity * cos / dist^2), so diffuse * E is the caustic's radiance
** as Phong's diffuse * n.l * intensity / dist^2 is the direct light's.
** Writes zero when there is no photon map: no photons asked for, a scene
** without caustics, outside ray_render without ray_ctx_set_photon_map,
** or a material that did not declare RAY_EFFECT_CAUSTICS.  RAY_OK, or
** RAY_EINVAL (NULL ctx, args, args->hit or irradiance; nothing written).
**
** ray_photon_map_build -- the same photon pass outside ray_render, for
** programs that call ray_trace themselves: options->photons (1 ..
** RAY_MAX_PHOTONS; 0 is refused here), photon_radius, seed, threads,
** scheduler, progress and progress_ud are read, the rest ignored.  A
** scene without caustics gives an empty map.  The progress callback
** (NULL: none) hears done photons traced of total = photons, from the
** pass's threads one call at a time, after every 4096 (a chunk) and last
** with done == total; a pass that traces nothing (no caustics, no light
** of any power) does not call it.  Non-zero cancels: each thread stops
** at its next report, never calling it again, and the pass returns
** RAY_ECANCELED, keeping nothing; the map of a pass not cancelled is the
** same bits with or without the callback.  RAY_OK; RAY_EINVAL (NULLs,
** photons 0 or above the cap, a radius NaN, negative, infinite or whose
** pi r^2 under- or overflows); RAY_ESTATE (the scene not committed,
** never or since a change, or an instanced scene changed since the
** commit); RAY_ECANCELED; RAY_ENOMEM.  *out is untouched on failure.
** ray_ctx_set_photon_map -- make ray_caustics_at read "map" (BORROWED:
** it must outlive the use; NULL: none) in this context.  RAY_OK, or
** RAY_EINVAL (ctx NULL, or a map built for another scene).
** ray_photon_map_free -- release it (NULL: no-op), after every context
** using it is done, before or after its scene (it keeps a copy of the
** scene's allocator).  A map is read-only once built: any number of
** contexts on any threads may share it.  The photon pass allocates from
** its threads (ray_scene_new; threads = 1 and no scheduler keeps it on
** the caller's).
*/
typedef struct ray_photon_map ray_photon_map;

RAY_API int ray_caustics_at(ray_ctx *ctx, const ray_shade_args *args,
                            ray_rgb *irradiance);
RAY_API int ray_photon_map_build(const ray_scene *scene,
                                 const ray_render_options *options,
                                 ray_photon_map **out);
RAY_API int ray_ctx_set_photon_map(ray_ctx *ctx, const ray_photon_map *map);
RAY_API void ray_photon_map_free(ray_photon_map *map);

/* ----------------------------------------------------------- 10. images */

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
** A regular file (or none yet) is written as "<path>.<pid>-<n>.tmp" beside
** it, flushed to the disk, and renamed over it only when complete: on
** failure only that file is removed and an existing file is left as it
** was (its permission bits are kept on success; a symbolic link is
** replaced, not followed).  A device
** or FIFO is written in place and never removed; a directory is RAY_EIO.
** On Windows "path" is UTF-8 (not UTF-8: RAY_EIO, errno EILSEQ), an
** existing file is replaced by MoveFileExW, and a device or pipe (NUL,
** \\.\pipe\name) is written in place (doc/PLATFORMS.md).
**
** Returns RAY_OK; RAY_EINVAL for NULL arguments, a zero or too large size
** or bits other than 8 and 16; RAY_ENOMEM; RAY_EIO if the file cannot be
** created or written (errno tells why); RAY_EPNG if libpng fails;
** RAY_ENOTSUP in a library built without libpng (make PNG=0), after the
** RAY_EINVAL checks, with no file created.
** Thread-safe; the image is only read.
*/
RAY_API int ray_write_png(const char *path, const float *rgb,
                          unsigned width, unsigned height, int bits);

/* ---------------------------------------------------------- 11. queries */

/*
** A query's options (the last argument of ray_intersect, ray_occluded and
** the other queries; masks and filters: section 12), zero by default: a
** zeroed ray_query ({0}, a designated initializer naming only query_ud,
** or a NULL pointer) sees every geometry and hands filters a NULL
** query_ud.  The mask is given as the bits to IGNORE, the complement of
** the geometry mask it is compared with, so that its zero, which a caller
** who only sets query_ud leaves there, hides nothing (a zero visibility
** mask would hide everything, silently: libray 0.1's trap).  The same
** spelling as ray_contains_options.ignore_mask.
**
** Why a query refused: a query that returns a negated status (misuse:
** -RAY_EINVAL, -RAY_ESTATE, -RAY_EKIND ...; the batch calls and
** ray_distance_grid: a status other than RAY_OK) writes the reason in words
** into why[0 .. why_size - 1] when why is not NULL: "ray_intersect_sweep:
** sweep->shape.radius is -1: negative or not finite", naming the call,
** the argument (for an array, the index: "points[3]"), and the value it
** was given, at every digit.  Cut to fit, always terminated; 256 bytes
** hold every reason.  Nothing is written on any other return (a hit, a
** miss, a count), so the buffer costs a query that answers nothing: read
** it only after a negative return.  Queries without options give no
** reason; neither do ray_closest_point and ray_surface_point, whose
** reasons are those of ray.h's lists (a NULL or a value out of range).
**
** Why a buffer of the caller's reached through the options, and not
** ray_scene_errmsg or a check call as ray_render_check: a committed
** scene is const and queried by any number of threads at once, so a
** message kept in it would be a race and one query's reason could
** overwrite another's; and a check call would have to take every
** query's arguments again.  The buffer is written by the refused call
** alone, from its thread: give each thread its own ray_query (or its
** own why) where several may refuse at once, as several threads must not
** write one buffer.  ray_batch and ray_contains_options carry a why of
** their own, for the batch calls and for ray_contains, ray_signed_distance
** and ray_distance_grid.
*/
typedef struct ray_query {
    unsigned ignore_mask;    /* geometry whose mask has no bit outside
                                these is unseen; 0: all geometry seen */
    void *query_ud;          /* handed to every filter this query calls */
    char *why;               /* a refusal's reason goes here (NULL: none) */
    size_t why_size;         /* why's size in bytes */
} ray_query;

/*
** Queries on a committed scene, from any thread (while no thread changes
** it), with options q (NULL: the defaults, as a zeroed ray_query; one
** call whether or not options are given, as Embree 4's rtcIntersect1).
** ray_intersect: the nearest hit in (tmin, tmax), with geom_id set
** and prim_id the triangle's index for a mesh, 0 otherwise (1), or a
** miss (0, *hit untouched).  ray_occluded: 1 if anything lies in (tmin,
** tmax) (any-hit, stops at the first), else 0.  Misuse is a NEGATED
** status, never taken for a miss: -RAY_EINVAL for a NULL scene, r or
** hit, -RAY_ESTATE for a scene not committed (never, or changed since its
** last commit) or when the ray meets an instance whose scene was changed
** since this scene's commit (*hit untouched).  So test "> 0" for a hit:
** a negative value is true in C.  Of two triangles of the scene itself
** (not reached through an instance) hit at the same t (a ray through a
** shared edge or vertex), the one with the lower (geom_id, prim_id) is
** the nearest, whatever order the search met them in.
*/
RAY_API int ray_intersect(const ray_scene *scene, const ray_ray *r,
                          ray_hit *hit, const ray_query *q);
RAY_API int ray_occluded(const ray_scene *scene, const ray_ray *r,
                         const ray_query *q);

/*
** ray_closest_point -- the nearest point of a committed scene's surfaces
** to the point q, within distance "radius" (a closest-point query, as
** Embree's rtcPointQuery): for snapping a point to the world, and for
** collision (how deep a point is, and which way to push it out).
**
** Returns 1 and fills *out when some surface point lies within distance
** <= radius of q (compared on the computed distance); radius = +Inf
** (HUGE_VAL) asks for the nearest point of the whole scene.  Returns 0,
** *out untouched, when no surface point is that near, or the scene has
** none.  Misuse is a NEGATED status, as for ray_intersect, with *out
** untouched: -RAY_EINVAL for a NULL scene or out, a q that is not finite,
** or a radius that is NaN or negative; -RAY_ESTATE for a scene not
** committed (or changed since), or one whose search met an instance of a
** scene changed since.
**
** It is the nearest point of the SURFACE: a q inside a sphere, box,
** capsule or closed mesh gets the nearest point of its boundary, not
** distance 0.  Triangles and meshes, spheres, planes, polygons (the
** region inside their outline, even-odd as ray_polygon), boxes and
** capsules are searched; tori, implicit and parametric surfaces, Bezier
** patches and user geometry have no closest-point routine and are
** skipped.  Of points at the same distance, which is reported is
** unspecified.  Instances are searched through their transform (inst_id
** names the instance, geom_id and prim_id the child's geometry) and
** answer the world's nearest point for any transform the scene accepts:
** the child's boxes are searched within the radius times |L^-1|_2, and
** every candidate is measured in world space (a sphere through a
** non-uniform scale or a shear is an ellipsoid, a box a parallelepiped,
** a capsule an ellipsoid swept along a segment; for a q inside such a
** capsule, the nearest point of the ellipsoid it is deepest in).
** Masks and filters do not apply.
**
** geom_id names the geometry as for ray_intersect; prim_id is the
** triangle's index within a mesh, 0 for every other kind.  n is the
** geometric unit normal at p, never a shading normal: a triangle's or a
** polygon's face normal (as ray_triangle and ray_polygon orient it) even
** where p is on an edge or a vertex; a sphere's and a capsule's outward
** normal; a plane's normal as given; a box's outward face normal, at an
** edge or corner the face whose plane q lies farthest outside of.
** Accuracy (ray_closest_point(3)): p lies on the primitive to within a
** few ulps of the coordinates involved, and distance is |p - q| to
** within a few ulps of |q|, the primitive's size and the distance.
** Any number of threads may query a committed scene at once (while
** nothing changes it); the call allocates nothing.
*/
typedef struct ray_closest {
    ray_vec3 p;                  /* the nearest surface point found */
    double distance;             /* |p - q| */
    ray_vec3 n;                  /* the geometric unit normal at p */
    unsigned geom_id, prim_id;   /* as ray_intersect's */
    unsigned inst_id;            /* the instance it was found through,
                                    RAY_INVALID_ID if none */
} ray_closest;

RAY_API int ray_closest_point(const ray_scene *scene, ray_vec3 q,
                              double radius, ray_closest *out);

/*
** ray_contains -- whether points lie inside the solid a committed
** scene's geometry bounds: point-in-mesh for voxelizers, collision and
** navmesh bakers, slicers and signed distance fields.
**
** Closed meshes (every edge, by vertex index, shared by an even number
** of the mesh's triangles: closed surfaces, several in one mesh,
** triangles flipped against their neighbours) answer EXACTLY: the parity
** of the crossings of one ray from the point, decided by exact
** orientation predicates with a symbolic perturbation of the ray (Edels-
** brunner and Muecke's simulation of simplicity), so a ray through a
** vertex or an edge counts every crossing once and no point leaks.  A
** point exactly on such a mesh's surface (its vertices, edges and faces
** included) is reported on_surface = 1, inside = 1: the solid is closed,
** and on_surface tells it apart as CGAL's Side_of_triangle_mesh tells
** ON_BOUNDARY.  Meshes that are not closed (cracks, holes, soups) and
** single triangles are answered by the generalized winding number
** (Jacobson, Kavan and Sorkine-Hornung 2013), the sum of their
** triangles' signed solid angles over 4 pi: inside where it exceeds 1/2
** (1 inside a closed outward-facing surface, 0 outside it, 1/2 on it).
** Spheres, boxes and capsules are solids too; planes, polygons, tori,
** implicit, parametric, Bezier and user geometry bound nothing and are
** not counted.  The solids combine as the crossings do: a point inside
** two overlapping closed meshes of one scene is inside neither (their
** parities cancel, as in CGAL's test over one mesh of several parts);
** for a union, keep solids apart or test them in scenes of their own.
** Instances count their child's geometry, the point taken into the
** child's space.  options->ignore_mask is a query's (ray_query):
** geometry is counted when its mask has a bit outside ignore_mask
** (through an instance, the instance's mask and the child
** geometry's both), so 0 counts all geometry but that of mask 0, and a
** bit set there leaves out the geometry whose mask has that bit alone;
** disabled geometry is not counted; filters are not called.
**
** options (NULL: the defaults; a zeroed struct is the defaults):
** RAY_CONTAINS_WINDING in flags answers every mesh and triangle by the
** winding number, closed or not (without it, the open meshes and single
** triangles only).  To tell inside from outside, the winding number is
** computed fast through the BVH (Barill et al., "Fast Winding Numbers
** for Soups and Clouds", 2018: a cluster of triangles farther than twice
** its radius is taken by its order-2 far-field expansion), in about
** O(log triangles) per point away from the surface, and a point whose
** fast winding number lies within 0.2 of 1/2 is summed again exactly,
** so that the approximation never decides its side.  The winding number
** ITSELF is asked for with RAY_CONTAINS_WINDING_EXACT: every triangle's
** solid angle is summed, O(triangles) per point, and out[i].winding is
** within 1e-9 of a long double sum wherever the number is well
** conditioned (off the edges: at vertices, on and an ulp off faces, far
** from the origin), inside following from it.  (The expansions come
** within 1e-9 only when a cluster must be some 200 radii away, not 2,
** and are then slower than the plain sum: ray_contains(3).)  Without
** it, out[i].winding is the estimate that decided the point's side (the
** exact sum for a point summed again): within 5e-2 of the winding
** number wherever measured, a hint, not the number.  A query whose
** ignore_mask leaves out some of the triangles the winding number
** answers sums every triangle too.
**
** Returns the number of points inside (on_surface ones included), after
** writing out[i] for each of points[0 .. n-1] (out NULL: only the
** count), or a NEGATED status, nothing written: -RAY_EINVAL for a NULL
** scene, a NULL points with n > 0, n > INT_MAX, a point that is not
** finite or unknown bits in flags; -RAY_ESTATE for a scene not
** committed (or changed since) or one with an instance whose scene
** changed since; -RAY_EDEGENERATE when, without RAY_CONTAINS_WINDING,
** the scene has no closed mesh and no sphere, box or capsule (nothing it
** can answer exactly: ask for the winding number); -RAY_ENOMEM when
** memory runs out finding which meshes are closed (a later call tries
** again).  Thread-safe.  The first call after a commit that changed a
** mesh finds which meshes are closed, without RAY_CONTAINS_WINDING
** builds the scene's grid of labels, and where the winding number is
** needed (without RAY_CONTAINS_WINDING_EXACT) the expansions, 240 bytes
** per node of the triangle BVH (once, under a lock of the scene's;
** -RAY_ENOMEM when memory runs out there too): the calls after it
** allocate nothing.  Exact for coordinates within
** about 2^-480 .. 2^480 (the predicates' range); a point is taken into
** an instance's space with the transform's rounding.
*/
#define RAY_CONTAINS_WINDING 1u
#define RAY_CONTAINS_WINDING_EXACT 2u

typedef struct ray_contains_options {
    unsigned flags;              /* RAY_CONTAINS_*; 0: the defaults */
    unsigned ignore_mask;        /* as ray_query's: the mask's bits turned
                                    off; 0: all geometry seen */
    char *why;                   /* as ray_query's: a refusal's reason */
    size_t why_size;             /* why's size in bytes */
} ray_contains_options;

typedef struct ray_inside {
    int inside;                  /* 1 inside (or on the surface), else 0 */
    int on_surface;              /* 1: exactly on a closed mesh */
    double winding;              /* the winding number: within 1e-9 with
                                    RAY_CONTAINS_WINDING_EXACT, else the
                                    fast estimate (see above); 0: none */
} ray_inside;

RAY_API int ray_contains(const ray_scene *scene, const ray_vec3 *points,
                         size_t n, const ray_contains_options *options,
                         ray_inside *out);

/*
** ray_signed_distance -- the distance from q to the scene's surfaces as
** ray_closest_point(scene, q, radius, closest) finds it, negative where
** ray_contains(scene, &q, 1, options, ..) says q is inside (0 on the
** surface).  Returns 1 with *distance set (and *closest, when not NULL)
** when a surface point lies within radius; 0 when none does, with
** *distance = +radius or -radius by the same sign (for narrow bands:
** radius HUGE_VAL asks for the whole scene; an empty scene then gives
** +-HUGE_VAL; a q on the surface 0); or ray_contains' and ray_closest_point's negated statuses
** (also -RAY_EINVAL for a NULL distance), nothing written.
*/
RAY_API int ray_signed_distance(const ray_scene *scene, ray_vec3 q,
                                double radius,
                                const ray_contains_options *options,
                                double *distance, ray_closest *closest);

/*
** ray_distance_grid -- bake the scene's signed distance field into the
** caller's nx * ny * nz floats: out[(k ny + j) nx + i] is
** ray_signed_distance at lo + (hi - lo) * (i / (nx - 1), j / (ny - 1),
** k / (nz - 1)) (an axis of one sample: lo's), rounded to float.
** options NULL or zeroed: the defaults.  band > 0 is a narrow band:
** the closest-point search is bounded by it and a sample farther from
** the surface holds +-band (faster: the far samples pay only the sign);
** 0 searches the whole scene.  The z slices are tasks on the options'
** scheduler, else the scene's (ray_scene_set_scheduler), else the
** built-in threads (threads of them; 0: one per online CPU, or the
** scheduler's count); every sample is a pure function of its position,
** so the array is the same bytes at any thread count and task order.
** Returns RAY_OK; RAY_EINVAL (NULL scene or out, lo or hi not finite, a
** count 0 or nx ny nz overflowing size_t, band NaN, negative or
** infinite, unknown contains flags); RAY_ESTATE (not committed, or a
** stale instance); RAY_EDEGENERATE as ray_contains.  Nothing is written
** on failure.
*/
typedef struct ray_distance_grid_options {
    double band;                 /* > 0: narrow band of that width */
    unsigned threads;            /* 0: one per online CPU */
    const ray_scheduler *scheduler; /* NULL: the scene's, or threads */
    ray_contains_options contains;  /* the sign's options */
} ray_distance_grid_options;

RAY_API int ray_distance_grid(const ray_scene *scene, ray_vec3 lo,
                              ray_vec3 hi, unsigned nx, unsigned ny,
                              unsigned nz,
                              const ray_distance_grid_options *options,
                              float *out);

/* --------------------------------------------------- 12. games and tools:
** the scene as a live, queried world (instances, updates, masks, filters,
** batches) */

/*
** An affine transform, 3 rows of 4: p' = m[.][0..2] . p + m[.][3], i.e.
** a 3x3 linear part L (rotation, scale, shear) and a translation c.
** ray_transform_identity sets *t to the identity.
*/
typedef struct ray_transform {
    double m[3][4];
} ray_transform;

RAY_API void ray_transform_identity(ray_transform *t);

/*
** ray_scene_add_instance -- place the committed scene "child" in "scene"
** with transform "xfm" (a two-level hierarchy: Embree's instances).
** The child's geometry is stored once however often it is placed; an
** instance costs about 450 to 600 bytes on x86-64 (its record, its share
** of the BVH and the arrays' room to grow: measured with a counting
** allocator over 1,000 and 100,000 instances).  Hits
** through it report the child's geom_id and prim_id and, in
** ray_hit.inst_id, the instance's own geom_id in "scene"; t is the
** world ray's; p and n are in world space (n transformed by the inverse
** transpose of L, renormalised), p_err grows by the transform's rounding
** both ways, so ray_spawn stays free of self-hits (ray-numerics(7)).  An
** identity transform gives bit-identical t, p, n, u and v to the child's
** own answer.  Rendering shades with the child's materials (and its
** meshes' normals and texture coordinates) and tests its triangles as
** its ray_scene_set_watertight says; the child's lights, background,
** ambient light and limits (pruning included) are not used: the scene's are.
**
** The child is BORROWED: it must outlive "scene" (or the instance's
** removal).  It may be changed and re-committed later (an animated mesh):
** "scene" must then be committed again before its next query, which
** otherwise fails with -RAY_ESTATE when it meets the instance (ray_trace:
** RAY_ESTATE; ray_render and ray_intersect_all check every instance
** first and refuse with RAY_ESTATE, -RAY_ESTATE).  A change to the child
** counts as a change to every scene that instances it: never while one
** of them is queried.  Errors, with nothing added: RAY_EINVAL for
** NULLs, child == scene, a non-finite transform, a singular L (|det L|
** below 8 ulps of the product of its row lengths: not invertible to
** working precision; the test is scale-free), an L whose inverse has an
** entry beyond DBL_MAX (diag(1e-310, 1, 1): its inverse holds 1e310;
** diag(1e-300, 1, 1) is accepted), a transform that maps the child's
** box beyond +-2^1016 (about 7e305), where a hit's point or error bound
** could overflow (refused rather than such hits counted as misses, so
** that no query hands out a field that is not finite; a commit fails the
** same way once the child has grown out of range), a child that has
** instances itself (two levels only) or unbounded planes; RAY_ESTATE
** for a child not committed; RAY_ENOMEM.
*/
RAY_API int ray_scene_add_instance(ray_scene *scene, const ray_scene *child,
                                   const ray_transform *xfm,
                                   unsigned *geom_id);

/*
** Changing a committed scene (ray(7), "Dynamic scenes").  After a commit
** every building call is allowed again: a change is STAGED and takes
** effect at the next ray_scene_commit, which refits or rebuilds only what
** changed.  A scene has two BVHs: one over its triangles (triangles and
** meshes) and one over the rest of its bounded geometry (spheres,
** polygons, curved surfaces, boxes, capsules and instances, with the
** list of planes beside it).  Added, removed, enabled or disabled
** geometry rebuilds the one that holds its kind, and so does a moved
** instance (or an instanced scene committed again: the second one); the
** other is kept.  Updated mesh vertices refit the triangle BVH in place
** (new boxes, same tree: no rebuild).  Materials, lights, settings,
** masks and filters rebuild nothing, but still need the commit.  Between
** the change and that commit the scene answers no query (-RAY_ESTATE;
** ray_trace, ray_ctx_new and ray_render RAY_ESTATE): one
** writer at a time, and never while a query or render runs on another
** thread (that race cannot be detected).  A failed call changes nothing,
** and a committed scene stays committed.
**
** ray_scene_set_transform -- a new transform for instance "geom_id".
** ray_scene_update_mesh -- new positions for mesh "geom_id": "mesh" is
**   read (and copied, or borrowed) as ray_scene_add_mesh reads it, with
**   the same triangle_count (the vertex count may differ, the triangles
**   may index other vertices than before, and the normals and texture
**   coordinates are replaced: a mesh without them drops them); a NULL
**   "mesh" reads a borrowed mesh's own arrays (RAY_MESH_BORROW) again,
**   after the caller changed its positions in place.
** ray_scene_set_enabled -- 0 hides geometry "geom_id" from every query
**   (and from shading and effects) until it is enabled again; 1 shows it.
**   Setting the state it already has stages nothing.
** ray_scene_remove -- removes it for good; its id is not reused, its
**   triangles are freed at the next commit.
** Errors: RAY_EINVAL for NULLs, an id that names no geometry (or removed
** geometry), the wrong kind (set_transform on anything but an instance,
** update_mesh on anything but a mesh), another triangle count, or
** invalid data as the add functions check it; RAY_ENOMEM.
*/
RAY_API int ray_scene_set_transform(ray_scene *scene, unsigned geom_id,
                                    const ray_transform *xfm);
RAY_API int ray_scene_update_mesh(ray_scene *scene, unsigned geom_id,
                                  const ray_mesh *mesh);
RAY_API int ray_scene_set_enabled(ray_scene *scene, unsigned geom_id,
                                  int enabled);
RAY_API int ray_scene_remove(ray_scene *scene, unsigned geom_id);

/*
** Masks and filters.  Every geometry has a 32-bit visibility mask (all
** bits by default); a query sees only geometry whose mask has a bit
** outside its ray_query.ignore_mask (0 for a query whose options are
** NULL and the renderer's rays: all geometry seen), i.e. that shares a bit
** with ~ignore_mask: layers ("the player's own geometry", "shadow
** casters only"); a geometry mask 0 hides it from every query.  For an
** instance both its own mask and the child geometry's must pass.  Masks are checked per primitive as the traversal
** meets it (a triangle after its test, other geometry before), not in
** the BVH's boxes: hidden geometry still costs its traversal.
**
** A filter is called for every CANDIDATE hit of its geometry, in world
** space, before the query accepts it, and answers non-zero (keep) or 0
** (reject: the query goes on as if that surface were not there), with
** the query's ray, its tmax lowered to the nearest hit kept so far but
** always holding the candidate (tmin < candidate->t < tmax: a triangle
** tying the kept hit comes with tmax the next double above its t): alpha
** cut-outs, ignoring the shooter, transparent shadows.  "queries" says
** which queries call it: RAY_FILTER_INTERSECT (nearest hit:
** ray_intersect, ray_trace's and ray_render's rays),
** RAY_FILTER_OCCLUDED (any hit: ray_occluded, shadow
** rays), or both; ray_intersect_all calls both kinds.  "query_ud" is the
** ray_query's user pointer (NULL from a query without options and the
** renderer).  A filter runs CONCURRENTLY from query threads; it must be a
** pure function of its arguments (and of data nobody changes meanwhile),
** or answers stop being reproducible.  Candidates are offered in
** traversal order, not in order of t; a kept candidate need not be the
** answer (a nearer one may come later), and a candidate farther than a
** kept hit may never be offered.  A curved surface whose hit is rejected
** is asked again past it (its far side): at most 16 times per surface and
** ray.  Each call counts in ray_stats.filter_calls; geometry without a
** filter costs no call, and a scene without masks or filters takes the
** ungated path, at no cost.  ray_scene_set_filter with fn NULL removes
** it.  Filters on instances are refused (RAY_EINVAL): set them on the
** child's geometry.  Masks and filters are changes like the others:
** staged until the next commit, which rebuilds nothing for them.
** Errors: RAY_EINVAL (NULL scene, unknown or removed geometry, queries
** with unknown bits or 0 with a filter); RAY_ENOMEM never.
*/
#define RAY_FILTER_INTERSECT 1u
#define RAY_FILTER_OCCLUDED  2u

typedef int (*ray_filter_fn)(void *ud, const ray_ray *r,
                             const ray_hit *candidate, void *query_ud);

RAY_API int ray_scene_set_mask(ray_scene *scene, unsigned geom_id,
                               unsigned mask);
RAY_API int ray_scene_set_filter(ray_scene *scene, unsigned geom_id,
                                 ray_filter_fn fn, void *ud,
                                 unsigned queries);

/*
** ray_intersect_all -- every hit along the ray in (tmin, tmax), nearest
** first (ties in t by geom_id, then prim_id, then inst_id), through masks
** and filters: line of sight through glass, counting layers.  Writes the
** "cap" nearest of them into hits[] and their total into *count (may be
** more than cap: call again with more room; cap 0 only counts); returns
** the total (>= 0, at most INT_MAX: *count is exact) or a negated status
** as the other queries (-RAY_EINVAL for NULL r or count, or hits NULL
** with cap > 0; -RAY_ESTATE also when any instance's scene changed
** since the commit, checked first: on failure nothing is written).  A
** curved surface reports each of
** its hits (both sides of a sphere: at most 16 per surface and ray); a
** hit exactly on a shared edge of a mesh may be reported by both
** triangles.
*/
RAY_API int ray_intersect_all(const ray_scene *scene, const ray_ray *r,
                              const ray_query *q, ray_hit *hits, size_t cap,
                              size_t *count);

/*
** ray_intersect_batch, ray_occluded_batch -- many rays at once, for bulk
** queries (a game's line-of-sight and AI rays, a tool's picking or
** baking, a renderer's camera rays): b->results[i] receives what
** ray_intersect(scene, &b->rays[i], &b->hits[i], qi) or
** ray_occluded(scene, &b->rays[i], qi) returns (1, 0, or -RAY_ESTATE for
** a ray that meets a stale instance), and b->hits[i] what it writes, bit
** for bit, whatever n and the order of the rays.  qi, ray i's options, is
** &b->queries[i] when queries is not NULL, each ray its own (AI agents'
** lines of sight that each hide their own shooter with a mask bit per
** agent, or hand their own query_ud to a filter); else b->query, one set
** for every ray (NULL: the defaults; a zeroed ray_batch asks for none).
**
** Where the CPU has AVX2 and the scene holds triangles alone (no planes,
** other kinds or instances; for ray_occluded_batch, planes and up to
** four spheres beside them too, each ray testing those on its own first)
** without masks or filters that the rays' options can see, each group
** of eight (rays[0..7], rays[8..15], ...)
** whose directions lie within about 8 degrees of their mean is traced
** through the BVH together: faster, as such eight (a 4x2 block of pixels,
** shadow rays from nearby points to one light) visit the same nodes; a
** group that scatters, and any scene or options the packets do not take,
** goes one ray at a time (doc/BENCHMARKS.md measures a batch against a
** loop of ray_intersect: 0.83 to 1.04 of its time).  A group goes in a
** packet when every ray of it could,
** whatever its options: a mask or query_ud that no geometry of the scene
** reads changes nothing.  The batch's counters are added to *stats when
** it is not NULL: its intersection tests, and how many rays went through
** the BVH in packets of eight (batch_packets) and how many one at a time
** (batch_single).
**
** Returns RAY_OK, or RAY_EINVAL (scene or b NULL; rays, results or, for
** ray_intersect_batch, hits NULL with n > 0) or RAY_ESTATE (not
** committed), writing nothing.  ray_occluded_batch does not read hits,
** which may be NULL.
*/
typedef struct ray_batch {
    const ray_ray *rays;         /* n rays */
    const ray_query *queries;    /* n options, one a ray, or NULL: query */
    size_t n;
    ray_hit *hits;               /* n records (ray_intersect_batch) */
    int *results;                /* n answers */
    ray_stats *stats;            /* counters added here; may be NULL */
    const ray_query *query;      /* every ray's options when queries is
                                    NULL; NULL: the defaults */
    char *why;                   /* as ray_query's: why the batch was
                                    refused (the rays' why are not used) */
    size_t why_size;             /* why's size in bytes */
} ray_batch;

RAY_API int ray_intersect_batch(const ray_scene *scene, const ray_batch *b);
RAY_API int ray_occluded_batch(const ray_scene *scene, const ray_batch *b);

/* ---------------------------------------------------------- 13. tracing */

/*
** ray_ctx_new -- a trace context for tracing outside ray_render (which
** makes its own, one per thread).  One context per thread; it holds the
** recursion state, the random sequence and the counters.  "seed" seeds
** its sampler.  Returns RAY_OK, RAY_EINVAL (NULL), RAY_ESTATE (scene not
** committed: never, or changed since) or RAY_ENOMEM.  A context outlives the
** scene's changes and commits (ray_trace).  ray_ctx_free(NULL) is a
** no-op.  ray_ctx_stats copies the counters accumulated so far.
*/
RAY_API int ray_ctx_new(const ray_scene *scene, unsigned long long seed,
                        ray_ctx **out);
RAY_API void ray_ctx_free(ray_ctx *ctx);
RAY_API void ray_ctx_stats(const ray_ctx *ctx, ray_stats *out);

/*
** ray_ctx_set_cone -- give the context's next primary rays (ray_trace
** outside a material callback) a cone: "width" across the ray at its
** origin (world units; 0 for a pinhole) and "spread", the cone's whole
** angle in radians (a camera's pixel: about vfov / height).  The cone
** widens with distance, and the tracer carries it through the rays
** materials trace: a reflection widens it by the curvature of the mirror
** (a sphere; other surfaces reflect it as flat), a refraction bends it as
** Snell's law bends the light (a glass ball focuses it; the ratio of
** indices is read from the two directions, so within 2^-30 rad of normal
** incidence it goes on unchanged).  At each hit, a material sees its width and its footprint
** in texture units (ray_shade_args.cone_width, footprint), from which
** ray_texture_image picks a mip level.  Only in a scene whose effects
** include RAY_EFFECT_TEXTURE; width = spread = 0 (a new context's
** default) means no cone.  ray_render sets its own contexts' cones
** (ray_render_options.no_cones 0).  RAY_OK, or RAY_EINVAL (ctx NULL, width
** negative, NaN or infinite, spread negative, NaN or not below pi, a
** cone's whole angle: the cone unchanged).
*/
RAY_API int ray_ctx_set_cone(ray_ctx *ctx, double width, double spread);

/*
** ray_trace -- trace ray "r" and write the radiance it brings back into
** *out: the shade of the material it hits, or the background; geometry
** added with RAY_NO_MATERIAL shades exactly black (0, 0, 0).
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
** RAY_EINVAL for NULL pointers or a bad kind; RAY_ESTATE when the scene
** was changed (since the context was made, or since its last commit) and
** not committed again, or when the ray met an instance whose scene was
** changed since this scene's commit; the outermost call (outside any
** material callback) also when any ray of its tree (a material's shadow
** or reflection ray) met one (the context stays usable: commit and trace
** again).  On anything but RAY_OK, *out is untouched.
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
** unshadowed light, a documented no-op (also outside any callback), and
** counts the request in ray_stats.shadows_undeclared, so that a material
** that forgot the flag shows in the counters instead of only in an image
** without shadows.  So a
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

/*
** Direct light without the loop: ray_shade_direct adds to *out the light
** that reaches the hit straight from every sample of every light, each
** weighted by the material's "brdf":
**
**     *out += sum over lights and samples of  f * radiance * visible
**
** in the order light 0 sample 0, 0 1, ..., 1 0, ... (the order of a
** hand-written loop, so a material moved onto it renders the same bits,
** as long as brdf draws no random numbers from the context, through ud:
** an area light's samples are drawn up to 16 at a time, before their
** brdf calls).
** "brdf" is called with "ud" and one ray_brdf_args per sample and returns
** f, the factor that multiplies the sample's radiance: the BRDF TIMES the
** cosine cos_light (so Lambert is color * cos_light, and models that are
** not a BRDF, like Phong's lobe, fit too).  It is called only for samples
** in front of the shading normal (cos_light > 0).  A sample behind it, or
** one whose f has no positive channel, adds nothing, and casts no shadow
** ray when args->prune is set (the default; the naive mode, prune 0,
** still casts it, to measure what pruning saves).  Visibility is
** ray_light_visible's, so the effect analysis still decides: without
** RAY_EFFECT_SHADOW declared by the calling material no shadow ray is
** cast and every sample counts as lit.  An area light's shadow rays from
** one hit are asked together, eight at a time through the BVH where
** ray_occluded_batch would take them in packets (the same answers; the
** intersection tests then counted in the packet's order, so ray_stats'
** tests may differ from a hand-written loop's).  Samples
** ray_light_sample_at refuses (a shading point too close to a light)
** are skipped.  Called from a material callback with its "ctx"
** and "args"; "brdf" runs on the same thread, before ray_shade_direct
** returns, so "ud" may point to the callback's locals.
**
** Returns RAY_OK, or RAY_EINVAL (ctx, args, args->ray, args->hit, brdf or
** out NULL) with *out untouched.
*/
typedef struct ray_brdf_args {
    const ray_shade_args *shade;      /* the hit being shaded */
    const ray_light_sample *sample;   /* the light sample */
    unsigned light;                   /* its light, 0 .. light count - 1 */
    ray_vec3 to_light;                /* unit, toward the sample
                                         (sample->dir) */
    ray_vec3 to_eye;                  /* unit, back along the incoming
                                         ray: -dir / |dir| */
    double cos_light;                 /* shade->shading_normal . to_light,
                                         > 0 */
} ray_brdf_args;

typedef ray_rgb (*ray_brdf_fn)(void *ud, const ray_brdf_args *args);

RAY_API int ray_shade_direct(ray_ctx *ctx, const ray_shade_args *args,
                             ray_brdf_fn brdf, void *ud, ray_rgb *out);

/* A uniform random number in [0, 1) from the context's per-pixel
** sequence: deterministic for a given pixel, sample and frame seed. */
RAY_API double ray_ctx_random(ray_ctx *ctx);

/* --------------------------------------------------- 14. secondary rays */

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
** strictly between the surface and the target blocks it.  A target that
** lies on a surface is within its own p_err of it, on either side: pass
** the origin ray_spawn(&target_hit, p - target) gives instead, so that
** the surface it lies on cannot block the segment (ray_spawn(3)).
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

/* ---------------------------------------------------- 15. more surfaces */

/*
** ray_implicit -- ray against the implicit surface f(p) = 0, as root
** finding on g(t) = f(org + t*dir) (the lecture's "ray ∩ implicit").
**
** f is the user's callback: f < 0 inside, f > 0 outside.  Only roots in
** the box [lo, hi] are searched: the ray is clipped to it first.  Then:
**
**   * lipschitz = L > 0 promises |f(p) - f(q)| <= L |p - q| in the box, so
**     no root lies within |f(p)| / L of p: the march steps by that much
**     (sphere tracing: Hart, "Sphere Tracing", The Visual Computer 12(10),
**     1996), never less than the tolerance.  A thin feature cannot be
**     skipped, and a double root (a ray tangent to the surface) is found:
**     where the step falls to the tolerance the gradient step
**     p - f grad f / |grad f|^2 is probed, and a surface point of the
**     other sign within the tolerance of the ray counts as a hit.
**   * lipschitz = 0 (no bound known): the march samples g every "step"
**     (world units) and detects sign changes, so features thinner than the
**     step, and double roots, can be missed.
**
** A sign change brackets a root; it is refined by safeguarded Newton (on
** g'(t) = grad f . dir, when a gradient callback is given) or else the
** Illinois variant of regula falsi, both falling back to bisection,
** until the bracket is narrower than "tolerance" (world units along the
** ray) or no double lies inside it.  The hit is the
** root of the first bracket along the ray: it is REAL (f changes sign
** within the tolerance of hit->p), never a guess.
**
** On a hit: n = the unit gradient at p (outward: toward f > 0), from the
** "gradient" callback or central differences; (u, v) from the "uv"
** callback, else 0; p_err covers the tolerance and p's rounding.
**
** Returns 1 (hit), 0 (miss, also for an invalid ray), or a NEGATED status
** with *hit untouched: -RAY_ELIMIT when max_iterations evaluations of f
** ran out before the march decided (a grazing ray can need many small
** steps), -RAY_EINVAL for NULL pointers, an invalid descriptor (NULL f, a
** box that is not finite or has lo > hi, negative or non-finite settings),
** or callbacks that misbehave: f NaN or Inf at a point of the box, a zero
** or non-finite gradient at the hit, a non-finite (u, v).
**
** Defaults (a field left 0): step = box diagonal / 128; tolerance =
** 1e-9 * box diagonal + 64 * DBL_EPSILON * largest |coordinate| of the
** box (the surface's size, and the coarseness of coordinates far from
** the origin); max_iterations = 100000 (sphere tracing
** needs ~3 sqrt(2 R / tolerance) steps to bring a ray tangent to a
** surface of curvature radius R within the tolerance: 63,000 for a
** sphere filling its box).
** Thread-safe if the callbacks are.
*/
typedef double (*ray_field_fn)(void *ud, ray_vec3 p);
typedef ray_vec3 (*ray_gradient_fn)(void *ud, ray_vec3 p);
typedef void (*ray_uv_fn)(void *ud, ray_vec3 p, ray_vec3 n, double *u,
                          double *v);

typedef struct ray_implicit_surface {
    ray_field_fn f;              /* f(p): < 0 inside, > 0 outside */
    ray_gradient_fn gradient;    /* grad f, or NULL: central differences */
    ray_uv_fn uv;                /* texture coordinates, or NULL: 0, 0 */
    void *ud;                    /* passed to the three; borrowed */
    ray_vec3 lo, hi;             /* a box containing the surface */
    double lipschitz;            /* > 0: a bound on |grad f|; 0: none */
    double step;                 /* without a bound: the sampling step */
    double tolerance;            /* of the hit along the ray, world units */
    unsigned max_iterations;     /* evaluations of f per ray */
} ray_implicit_surface;

RAY_API int ray_implicit(const ray_ray *r, const ray_implicit_surface *s,
                         ray_hit *hit);

/*
** ray_torus -- ray against the ring torus of "major" radius R (centre to
** tube centre) and "minor" radius r, 0 < r < R, around the axis through
** "center" along "axis" (any length).  (A spindle torus, r >= R, crosses
** itself: its quartic has an inner surface that this contract does not
** cover, so it is refused.)
**
** Exact: the quartic g(t) = (|q|^2 + R^2 - r^2)^2 - 4R^2|q - (q.a)a|^2 = 0
** in the torus's own frame, with the ray origin first moved to the point
** of the ray nearest the centre (so far-away rays keep their digits, as in
** ray_sphere).  Its real roots are isolated by the roots of its
** derivatives (cubic, then quadratic, solved the same way) and each is
** refined by safeguarded Newton inside its monotone interval (Yuksel,
** "High-Performance Polynomial Root Finding for Graphics", HPG 2022): no
** closed formula, so no catastrophic cancellation of Ferrari's method.
** Tangent rays (double roots) hit where the polynomial touches zero in
** floating point.
**
** On a hit: n = outward unit normal; u = angle around the axis / 2pi,
** v = angle around the tube / 2pi, both in [0, 1].  Returns 1 or 0 (*hit
** untouched); invalid input (NULL, NaN, Inf, zero axis, radii not > 0) is
** a miss (also r >= R).
*/
typedef struct ray_torus_params {
    ray_vec3 center;
    ray_vec3 axis;
    double major, minor;
} ray_torus_params;

RAY_API int ray_torus(const ray_ray *r, const ray_torus_params *t,
                      ray_hit *hit);

/*
** ray_box -- ray against the oriented box of half-extents h =
** half_extents (each > 0 and finite) about "center", whose local x axis
** is axis_x and whose local y axis is axis_y, both in world space, of any
** length and not parallel: the frame is ex = axis_x / |axis_x|, ey =
** axis_y made orthogonal to ex (Gram-Schmidt) and normalised, ez = ex x
** ey (right-handed), computed by the same operations on every call.  An
** axis-aligned box: axis_x = (1, 0, 0), axis_y = (0, 1, 0).  The axes
** are refused as parallel when axis_y's part orthogonal to axis_x is
** within the rounding error of computing it (an angle under ~2e-15
** rad); keep them at a clear angle: the frame's error is about 1e-15 /
** sin(angle), a few ulps for orthogonal axes.
**
** The slab method in the box's frame, the ray's origin taken relative to
** the centre (so a box far from the origin keeps its digits) and its
** direction scaled by a power of two (any length gives the same hit).
** The box is closed: a ray through an edge or a corner hits, and so does
** a ray lying in a face's plane within the face (at the edge where it
** enters).  A ray starting inside hits the face it leaves through.
**
** On a hit: n = the face's OUTWARD unit normal, +-ex, +-ey or +-ez (also
** from inside); t passes the conservative tmin test of every primitive;
** (u, v) in [0, 1]^2 on the face: for the face +-e_k, u runs along
** e_(k+1) (cyclically: x -> y -> z -> x), reversed on the negative face,
** and v along e_(k+2), from the face's edge at -h to the one at +h, so
** that (dp/du, dp/dv, n) is right-handed on every face: a texture reads
** unmirrored from outside.  At an edge or a corner, where two faces'
** slabs tie, the face of the lower axis (x, then y, then z) is reported.
** Returns 1 or 0 (*hit untouched); invalid params (NULL, NaN, Inf, a
** half-extent not > 0 or above 2^1021, about 2.2e307, where a ray's t
** across the box could overflow, a zero or parallel axis, a box reaching
** beyond the largest double) are a miss.
**
** ray_scene_add_box -- copies the params; hits as ray_box, prim_id 0.
** RAY_EINVAL (with a message naming the field) for params ray_box
** refuses, or an unknown material; RAY_ENOMEM.
*/
typedef struct ray_box_params {
    ray_vec3 center;
    ray_vec3 half_extents;       /* along the local x, y, z; each > 0 */
    ray_vec3 axis_x;             /* the local x axis, any length */
    ray_vec3 axis_y;             /* the local y axis, not parallel to x */
} ray_box_params;

RAY_API int ray_box(const ray_ray *r, const ray_box_params *b,
                    ray_hit *hit);

/*
** ray_capsule -- ray against the capsule of radius "radius" around the
** segment [a, b]: every point at distance radius from the segment, a
** cylinder around it closed by two hemispheres (the shape games use for
** characters' collision and picking).  a == b is allowed: a sphere.
**
** Exact, to rounding: the cylinder's quadratic and the caps' are solved
** as ray_sphere's (closest-approach discriminant, q = b + sign(b) sqrt,
** roots c/q and q/a) relative to the segment's midpoint, so far-away
** capsules keep their digits; a ray parallel to the axis meets the caps
** (no epsilon).  The nearest crossing in (tmin, tmax) whose error bound
** also lies past tmin is the hit (ray-numerics(7)).
**
** On a hit: n = outward unit normal; p on the surface, within p_err.
** With w the unit axis from a to b and (t1, t2) ray_plane's tangents for
** the normal w (a == b: w = +y):
**   u = atan2(n.t1, -n.t2) / 2pi + 1/2 in [0, 1], the angle around the
**       axis (1/2 toward -t2, 3/4 toward t1; for w = +y, ray_sphere's u);
**   v = the arc length along the meridian from a's pole (v = 0) through
**       the cylinder to b's pole (v = 1) over its length pi radius +
**       |b - a|: continuous across the seams (a == b: ray_sphere's v).
** Returns 1 or 0 (*hit untouched); invalid input (NULL, NaN or Inf, a
** radius not > 0 and finite, a capsule whose box overflows) is a miss.
*/
typedef struct ray_capsule_params {
    ray_vec3 a, b;               /* the segment's ends (a == b: a sphere) */
    double radius;               /* > 0 */
} ray_capsule_params;

RAY_API int ray_capsule(const ray_ray *r, const ray_capsule_params *c,
                        ray_hit *hit);

/*
** ray_implicit_blobs -- metaballs (Blinn's "blobby molecules", with
** Wyvill's compact falloff): f(p) = threshold - sum of strength_i *
** (1 - |p - c_i|^2 / radius_i^2)^2 over the blobs whose radius reaches p.
** Strengths may be negative (a blob that carves).  Fills *out with f, its
** exact gradient, the box of the positive blobs (where f < threshold is
** possible), (u, v) = the normal's longitude and latitude as ray_sphere
** gives them, and the Lipschitz bound
** sum |strength_i| * 8 / (3 sqrt(3) radius_i) (the falloff's steepest
** slope), so ray_implicit sphere-traces it.  The params and the blob
** array are BORROWED.  RAY_OK, or RAY_EINVAL (NULL, no blobs, a
** non-finite value, a radius not > 0, a threshold not > 0).
*/
typedef struct ray_blob {
    ray_vec3 center;
    double radius;               /* of influence */
    double strength;
} ray_blob;

typedef struct ray_blobs_params {
    const ray_blob *blobs;
    size_t count;
    double threshold;            /* e.g. 0.5 */
} ray_blobs_params;

RAY_API int ray_implicit_blobs(const ray_blobs_params *p,
                               ray_implicit_surface *out);

/*
** ray_parametric -- ray against the parametric surface S(u, v), u in
** [u0, u1], v in [v0, v1] (the lecture's "ray ∩ parametric"): solve
** org + t*dir = S(u, v) for (t, u, v) by Newton's method, each step's
** 3x3 system [dir, -S_u, -S_v] [dt du dv]^T = S(u, v) - org - t*dir solved
** by Cramer's rule.
**
** Starting guesses come from subdividing the (u, v) domain: the "bounds"
** callback gives a box containing S over a sub-rectangle; sub-rectangles
** whose box the ray misses (or enters beyond the nearest hit so far) are
** dropped, the others split in four down to "subdivisions" levels, and
** Newton starts at the centre of each remaining one, at the t where the
** ray enters its box.  Iterates stay in that sub-rectangle grown by 1/16
** of its size (so roots on its border are not lost) and in the domain: a
** step out is cut at the border, and from the border the iterate slides
** along it (that parameter held, the others solved by least squares), as
** it does where S does not move along a parameter (a collapsed edge).  An
** iterate is accepted when |org + t*dir - S(u, v)| <= tolerance and
** tmin < t < tmax.  A sub-rectangle whose start finds no root is split
** again, up to 8 more levels and 4096 boxes per ray; one whose start finds
** a root is split too, unless the normals at its corners, centre and root
** all face the ray the same way with a margin larger than their spread
** (the ray then crosses it once) (Sweeney and Bartels's refinement:
** smaller boxes prove a miss or give better starts, and a grazing ray's
** nearer crossing is not lost).  A singular
** system (a ray parallel to the tangent plane) is a miss.  The nearest
** accepted root is the hit.
** For a surface made by ray_bezier_surface over its own domain [0, 1]^2,
** the bounds callback is called once, for the whole patch: the boxes of
** sub-rectangles come from the parent's control net halved by de
** Casteljau, grown by gamma(6L + 2) * (max |cp| + 2 DBL_MIN) per axis at
** level L, and contain the sub-patch like the callback's (twice as fast).
**
** On a hit: n = normalize(S_u x S_v) (the parameterisation's orientation),
** taken 1e-6 (then 1e-4, 1e-2) of the domain's size toward its centre
** where that cross product vanishes or is rounding noise (the collapsed
** edges of a Bezier patch), else -dir/|dir|; (u, v) as found, inside the
** domain; p = S(u, v); p_err = tolerance + gamma(18) * the box's largest
** |coordinate| per axis (the rounding of a Bezier evaluation).
**
** Returns 1, 0 (miss), or -RAY_ELIMIT (*hit untouched) when no root was
** accepted and some Newton start at the deepest refinement neither
** converged nor left within max_iterations steps, or the refinement ran
** out of boxes (non-convergence, reported rather than taken for a miss),
** or -- whether or not a root was found -- the descent to "subdivisions"
** levels asked for more than 262,144 boxes (a ray lying in a flat patch
** of a 12-level tree: its work per ray is bounded);
** -RAY_EINVAL for NULL r, s or hit, an invalid descriptor (NULL
** callbacks, an empty or non-finite domain, subdivisions > 12, a negative
** or non-finite tolerance), or non-finite values or a box with lo > hi
** from the callbacks.  An invalid ray is a miss, decided before any
** callback runs.
** Defaults (a field left 0): the domain [0, 1]^2 when u0 = u1 = v0 = v1 =
** 0; subdivisions = 4; tolerance = 1e-9 * diagonal + 64 * DBL_EPSILON *
** largest |coordinate| of the whole surface's box (as ray_implicit);
** max_iterations = 16.
*/
typedef void (*ray_surface_fn)(void *ud, double u, double v, ray_vec3 *s,
                               ray_vec3 *s_u, ray_vec3 *s_v);
typedef void (*ray_surface_bounds_fn)(void *ud, double u0, double u1,
                                      double v0, double v1, ray_vec3 *lo,
                                      ray_vec3 *hi);

typedef struct ray_parametric_surface {
    ray_surface_fn eval;         /* S(u, v) and its partials S_u, S_v */
    ray_surface_bounds_fn bounds;/* a box containing S over a rectangle */
    void *ud;                    /* passed to both; borrowed */
    double u0, u1, v0, v1;       /* the domain */
    unsigned subdivisions;       /* levels of the domain's quad tree */
    double tolerance;            /* |e + td - S(u, v)| at a root */
    unsigned max_iterations;     /* Newton steps per start */
} ray_parametric_surface;

RAY_API int ray_parametric(const ray_ray *r,
                           const ray_parametric_surface *s, ray_hit *hit);

/*
** ray_bezier_surface -- the bicubic Bezier patch with control points
** cp[4*i + j] (row i along v, column j along u, so cp[0], cp[3], cp[12],
** cp[15] are the corners at (u, v) = (0,0), (1,0), (0,1), (1,1)) as a
** ray_parametric_surface over [0, 1]^2.  Its bounds are the boxes of the
** control points of the sub-patch (de Casteljau subdivision; the convex
** hull property makes them contain it), grown by gamma(22) * max |cp| for
** rounding; rectangles are clamped to [0, 1]^2.  The 16 points are BORROWED.
** RAY_OK, or RAY_EINVAL (NULL, a non-finite point).
*/
RAY_API int ray_bezier_surface(const ray_vec3 cp[16],
                               ray_parametric_surface *out);

/*
** Curved surfaces in a scene, inside its BVH through their boxes.
**
** ray_scene_add_implicit: copies the descriptor (its ud stays BORROWED and
** must outlive the scene); hits as ray_implicit.  ray_scene_add_torus:
** copies the params, intersected with the quartic of ray_torus.
** ray_scene_add_parametric: copies the descriptor (ud borrowed); the box
** is its bounds over the whole domain.  ray_scene_add_bezier: copies the
** 16 control points (as ray_bezier_surface lays them out).  Their hits
** report prim_id 0 and (u, v) as the functions do.  A ray for which
** ray_implicit or ray_parametric fails (a negative answer) counts as a
** miss of that surface and adds 1 to ray_stats.root_failures.
**
** Errors, with nothing added: RAY_EINVAL (NULLs, an invalid descriptor or
** torus, a non-finite control point, an unknown material), RAY_ENOMEM.
*/
RAY_API int ray_scene_add_implicit(ray_scene *scene,
                                   const ray_implicit_surface *s,
                                   unsigned material, unsigned *geom_id);
RAY_API int ray_scene_add_torus(ray_scene *scene, const ray_torus_params *t,
                                unsigned material, unsigned *geom_id);
RAY_API int ray_scene_add_parametric(ray_scene *scene,
                                     const ray_parametric_surface *s,
                                     unsigned material, unsigned *geom_id);
RAY_API int ray_scene_add_bezier(ray_scene *scene, const ray_vec3 cp[16],
                                 unsigned material, unsigned *geom_id);
RAY_API int ray_scene_add_box(ray_scene *scene, const ray_box_params *b,
                              unsigned material, unsigned *geom_id);

/*
** ray_scene_add_capsule: copies the params; hits as ray_capsule, through
** the BVH (the box: the segment's grown by radius).  RAY_EINVAL (with a
** message naming the field: ray_scene_errmsg) for what ray_capsule
** refuses, RAY_ENOMEM; nothing added.
*/
RAY_API int ray_scene_add_capsule(ray_scene *scene,
                                  const ray_capsule_params *c,
                                  unsigned material, unsigned *geom_id);

/*
** ray_scene_add_user -- the caller's own geometry (a character's capsule
** set, a voxel chunk, a signed distance field) in the scene's BVH like
** the built-in kinds: a box and an intersection callback.  The
** descriptor is copied; its ud is BORROWED and must outlive the scene.
**
** User geometry: the scene calls these, never concurrently with a
** building call, but CONCURRENTLY from query threads (intersect).
** "bounds" is called once, by ray_scene_add_user, and the box kept: it
** must hold every hit the intersection reports (a hit outside it may be
** missed).  "intersect" gets the ray in the scene's (world) space, its
** tmax already shrunk to the nearest hit found so far; it must be
** reentrant.  It answers 1 with *hit filled (t, p, n, u, v, p_err) for
** the nearest hit in (r->tmin, r->tmax), 0 for a miss, or a negative
** status for a failure (ray_implicit's, passed on).  Like the built-in
** tests it must report a hit only when t minus its rounding error still
** exceeds tmin (no acne, ray-numerics(7)), and fill p_err (0 leaves
** ray_spawn nothing to offset by).  The library checks the answer: t
** outside (tmin, tmax) or NaN, a non-finite p, u or v, a p_err not
** finite and >= 0, a normal not finite and non-zero, or an answer other
** than 0 and 1, is a miss counted in ray_stats.root_failures; n is
** normalised when it is not unit; geom_id and prim_id (0) are the
** library's, whatever the callback wrote.  Tests count under
** RAY_PRIM_USER.
**
** Errors, with nothing added: RAY_EINVAL (scene, g, bounds or intersect
** NULL; a box not finite or with lo > hi, the axis named by
** ray_scene_errmsg; an unknown material), RAY_ENOMEM.  In an instanced
** scene the callback gets the ray in that scene's own space.
*/
typedef void (*ray_user_bounds_fn)(void *ud, ray_vec3 *lo, ray_vec3 *hi);
typedef int (*ray_user_intersect_fn)(void *ud, const ray_ray *r,
                                     ray_hit *hit);
typedef struct ray_user_geometry {
    ray_user_bounds_fn bounds;       /* the box holding the geometry */
    ray_user_intersect_fn intersect; /* 1 and *hit filled (t, p, n, u, v,
                                        p_err) for the nearest hit in
                                        (r->tmin, r->tmax), else 0 */
    void *ud;                        /* borrowed: must outlive the scene */
} ray_user_geometry;
RAY_API int ray_scene_add_user(ray_scene *scene,
                               const ray_user_geometry *g,
                               unsigned material, unsigned *geom_id);

/* ------------------------------------------------ 16. shapes in the world:
** one shape type for the sweeps and the overlaps, rays from points of the
** scene's own surfaces */
/*
** ray_shape -- a shape of the shape queries (ray_intersect_sweep,
** ray_overlap_shape): a capsule of radius "radius" around the segment
** [a, b] (kind RAY_SHAPE_CAPSULE, 0: a sphere when a == b), or the
** oriented box "box" (kind RAY_SHAPE_BOX, as ray_box_params; a, b and
** radius are then not read).  Zero is the default: ray_shape s = {0} is
** a sphere of radius 0 at the origin (a point).
*/
#define RAY_SHAPE_CAPSULE 0u     /* a, b, radius: a sphere when a == b */
#define RAY_SHAPE_BOX     1u     /* box: an oriented box (ray_box_params) */

typedef struct ray_shape {
    unsigned kind;               /* RAY_SHAPE_*; 0: capsule / sphere */
    ray_vec3 a, b;               /* the capsule's segment (a == b: sphere) */
    double radius;               /* >= 0 */
    ray_box_params box;          /* RAY_SHAPE_BOX */
} ray_shape;

/*
** ray_intersect_sweep -- the first contact of a sphere or a capsule moved
** along a line through a committed scene: Unity's SphereCast and
** CapsuleCast, Bullet's convexSweepTest, Jolt's CastShape, on the scene's
** own BVHs (a character controller sliding along walls, a camera kept
** out of walls, a thick bullet).  Shape queries are rays with a radius:
** the same masks, filters (RAY_FILTER_INTERSECT: a sweep is a nearest
** query), instances and statuses as ray_intersect.
**
** The shape at t is sweep->shape moved by t dir: the capsule of radius
** "radius" around the segment [a + t dir, b + t dir] (a == b: a
** sphere), for t in [tmin, tmax].  Returns 1 with *c filled for the
** first contact, 0 when the shape touches nothing over the interval (*c
** untouched), or a negated status: -RAY_EINVAL for a NULL scene, sweep
** or c, a shape kind that is not RAY_SHAPE_*, a non-finite a, b or dir,
** a b - a or a tmin dir that overflows, a radius that is negative or
** not finite, a tmin that is not finite, tmax NaN or not above tmin
** (after tmax 0 is taken as 1); -RAY_EKIND for a RAY_SHAPE_BOX shape
** (a box is not swept, moving or not, in any build: its arguments are checked as
** ray_box checks them, -RAY_EINVAL first); -RAY_ESTATE for a scene not
** committed (or changed since), or a sweep that meets an instance whose
** scene was changed.
**
**   * dir 0 (no motion) is an overlap test at t = tmin: 1 with the
**     deepest overlap (RAY_CONTACT_OVERLAP, its depth and the normal n
**     that frees the shape: moved by depth along n it touches at most;
**     a character standing in a wall asks this to get out), or 0 when
**     the shape overlaps nothing (touching within rounding is no
**     overlap).  The overlap is the moving sweep's at tmin (below),
**     with its rules and its conservative bound; a radius-0 point
**     overlaps only solids it is inside.
**
**   * radius 0 with a == b (and dir not 0) is a ray: the answer is ray_intersect's
**     for the ray (a, dir, tmin, tmax), its t, p, ids as the hit's and n
**     the hit's normal turned against dir; on the open interval.
**   * Already touching or overlapping at tmin: an overlap (the shape's
**     core, its centre or segment, nearer a surface than its radius, or
**     inside a solid) is a contact at t = tmin with RAY_CONTACT_OVERLAP,
**     its depth (radius minus the signed distance: how far to move the
**     shape along n to free it) and n, the direction that frees it
**     fastest; of several, the deepest.  A shape touching within
**     rounding is a contact at tmin only if it moves into the surface:
**     sliding along a wall at exactly the radius is no contact.
**   * Conservative (ray_intersect_sweep(3) derives the bound): the
**     shape at any t from tmin to the contact's is nowhere more than 2
**     eps inside a surface, and at t it is within 2 eps of touching the
**     one it meets, eps = gamma(64) (M + radius + |b - a| + |tmin dir|),
**     M the largest coordinate of the features met, relative to a
**     (gamma(n) = n u / (1 - n u), u = 2^-53): moving the shape to t
**     never puts it inside.  A shape that only grazes an edge or a
**     vertex (never more than eps into it: sliding over a flat mesh at
**     its radius) touches nothing there.  No shape gets through a closed
**     mesh at its shared edges and vertices (the sweep's watertightness,
**     tested at 0, 1e5 and 1e6 from the origin).
**   * Per kind: triangles, meshes, polygons and planes are surfaces;
**     spheres, boxes and capsules are solids (a shape inside one
**     overlaps it).  All exact as above, through any transform an
**     instance has but two: a sphere or capsule through a transform that
**     is not a similarity (uniform scale, rotation, reflection,
**     translation) is an ellipsoid or a swept ellipsoid, found by
**     conservative Newton steps (as exact); a capsule sweep against such
**     a capsule, and every sweep against tori, implicit, parametric and
**     Bezier surfaces and user geometry, answers against the
**     primitive's box instead (the box through the instance's
**     transform), flagged RAY_CONTACT_BOUNDS: conservative, never a
**     miss of the surface inside it.
**   * Ties in t: the deeper overlap, then the lower (inst_id, geom_id,
**     prim_id).  A filter rejecting a sweep's candidate removes that
**     primitive from the sweep; it is handed the path (a, dir, tmin,
**     tmax) as a ray, its tmin lowered to the double below a contact at
**     tmin so that the open interval holds it.
** Any number of threads may sweep a committed scene at once; the call
** allocates nothing.
**
** Zero is the default: tmax 0 means 1, the whole motion dir, so a
** sweep written as { .shape = { .a = p, .b = p, .radius = r }, .dir = d }
** (tmin 0) moves the shape from p to p + d.  A sweep meant to end at t =
** 0 is written with dir reversed.
*/
typedef struct ray_sweep {
    ray_shape shape;             /* the shape at t = 0 */
    ray_vec3 dir;                /* the motion: at t the shape moved t dir
                                    (0: an overlap test) */
    double tmin, tmax;           /* the part of the motion swept;
                                    tmax 0: 1 */
} ray_sweep;

#define RAY_CONTACT_OVERLAP 1u   /* overlapping at tmin: depth > 0 */
#define RAY_CONTACT_BOUNDS  2u   /* against the primitive's box, not its
                                    surface (see above) */

typedef struct ray_contact {
    double t;                    /* the first contact, tmin <= t <= tmax */
    ray_vec3 p;                  /* the contact point on the scene */
    ray_vec3 n;                  /* unit normal, from the scene toward the
                                    shape */
    double depth;                /* RAY_CONTACT_OVERLAP: how deep, else 0 */
    unsigned flags;              /* RAY_CONTACT_* */
    unsigned geom_id, prim_id;   /* as ray_intersect's */
    unsigned inst_id;            /* the instance, RAY_INVALID_ID if none */
} ray_contact;

RAY_API int ray_intersect_sweep(const ray_scene *scene,
                                const ray_sweep *sweep, const ray_query *q,
                                ray_contact *c);

/*
** ray_overlap_shape -- every primitive of a committed scene that meets a
** shape (a sphere, a capsule or an oriented box): triggers, AI
** perception, a broad phase (Unity's OverlapSphere, OverlapCapsule and
** OverlapBox, Bullet's contactTest, Jolt's CollideShape).  Each one
** found is handed to "fn" (with "ud" first), once, in no particular
** order, as a ray_overlap: its geom_id, prim_id (the triangle's index in
** a mesh, else 0) and inst_id as a ray's hit would name it.  fn returns
** 0 to go on, non-zero to stop the search.  The function returns how
** many were handed to fn (>= 0, at most INT_MAX), or a negated status:
** -RAY_EINVAL for a NULL scene, shape or fn, a kind that is not
** RAY_SHAPE_*, a capsule's a or b that is not finite (or b - a that
** overflows), a radius that is negative or not finite, a box ray_box
** refuses; -RAY_ESTATE for a scene not committed or changed since, or
** one that instances a scene changed since (checked before fn is first
** called).  A box shape is the oriented box of ray_box_params (an
** axis-aligned one: axis_x = (1, 0, 0), axis_y = (0, 1, 0)).
**
** ray_overlap_shape_all -- the same into the
** caller's array, like ray_intersect_all: the "cap" first of them in
** (inst_id, geom_id, prim_id) order into found[] (so the answer does not
** depend on the BVH), their total into *count (may exceed cap: call
** again with more room; cap 0 only counts); returns the total (at most
** INT_MAX) or a negated status as above (-RAY_EINVAL also for a NULL
** count, or found NULL with cap > 0), writing nothing then.
**
** What meets: triangles, meshes (triangle by triangle), polygons (the
** region inside their outline, even-odd) and planes are surfaces: a
** sphere or box inside a closed mesh but clear of its triangles does
** not meet it.  Spheres, boxes and capsules are solids: a query inside
** one meets it.  All exact to rounding (a pair that touches within a
** few ulps of their coordinates may be reported either way): distances
** for the sphere (the nearest point of each primitive, as
** ray_closest_point finds it, within the radius, inclusive) and for the
** capsule (the nearest points of its segment and the primitive, within
** the radius, inclusive), separating axes for the box; through an
** instance's transform, whatever it is, in world space (a box through it
** is a parallelepiped; a sphere an ellipsoid and a capsule a swept
** ellipsoid, tested by their nearest points or in their own space) but
** for one pair: a capsule shape (a != b) against a capsule through a
** transform that is not a similarity is answered by that capsule's box
** (through the transform), flagged RAY_CONTACT_BOUNDS.  Tori, implicit, parametric and Bezier
** surfaces and user geometry are found by their boxes (through the
** transform: the box's image), flagged RAY_CONTACT_BOUNDS: a superset,
** never a miss.  Masks apply as for ray_intersect (q NULL or its
** ignore_mask 0: all geometry); filters do not (fn sees every primitive and may skip it).  Any
** number of threads may query a committed scene at once; the calls
** allocate nothing.
*/
typedef struct ray_overlap {
    unsigned geom_id, prim_id;   /* as ray_intersect's */
    unsigned inst_id;            /* the instance, RAY_INVALID_ID if none */
    unsigned flags;              /* RAY_CONTACT_BOUNDS: found by its box */
} ray_overlap;

typedef int (*ray_overlap_fn)(void *ud, const ray_overlap *found);

RAY_API int ray_overlap_shape(const ray_scene *scene, const ray_shape *shape,
                              const ray_query *q, ray_overlap_fn fn,
                              void *ud);
RAY_API int ray_overlap_shape_all(const ray_scene *scene,
                                  const ray_shape *shape, const ray_query *q,
                                  ray_overlap *found, size_t cap,
                                  size_t *count);

/*
** ray_surface_point -- the hit record of a point of the scene's own
** geometry, given by its primitive and its own coordinates (u, v) as a
** ray's hit would report them: for a baker's rays from lightmap texels,
** ambient occlusion from interpolated points.  p and its error bound
** p_err are computed from the stored geometry by the formulas of a hit
** (the box p +- p_err holds a point of the exact surface), n is the
** geometric normal a hit there reports, t is 0, so ray_spawn (and
** ray_spawn_to) start rays from it that never meet the surface they
** leave.  An interpolated point with no offset starts on the wrong side
** of its triangle about as often as not (bench/selfhit.c measures the
** self-hits on the 59k bunny: ray-numerics(7)).
**
** Ids as ray_hit's: geom_id, and prim_id (a mesh's triangle; 0 for every
** other kind), of "scene" itself when inst_id is RAY_INVALID_ID; else
** inst_id is an instance of "scene" and geom_id, prim_id name geometry
** of its scene, and the record is in world space (p_err grown by the
** transform's rounding, as a hit through the instance).  (u, v) by
** kind: a triangle's or a mesh triangle's barycentrics (u, v >= 0, u + v
** <= 1: p = (1-u-v) a + u b + v c); a sphere's longitude and latitude
** in [0, 1] (ray_sphere's); a plane's coordinates along ray_plane's
** tangents from its point; a polygon's the same from its first vertex,
** inside it.  Returns RAY_OK with *hit filled, else (*hit untouched)
** RAY_EINVAL for NULLs, ids that name nothing (or removed geometry, or
** an instance where geometry was asked for), (u, v) not finite or
** outside the primitive; RAY_EKIND for boxes, capsules, tori,
** implicit, parametric and Bezier surfaces and user geometry, which have
** no surface points here (a status of its own, not RAY_ENOTSUP: no
** build of the library has them); RAY_ESTATE for a scene not committed, or an
** instance whose scene changed since.  Any number of threads may call
** it on a committed scene; it allocates nothing.
*/
RAY_API int ray_surface_point(const ray_scene *scene, unsigned geom_id,
                              unsigned prim_id, unsigned inst_id, double u,
                              double v, ray_hit *hit);

#ifdef __cplusplus
}
#endif

#endif /* RAY_H */
