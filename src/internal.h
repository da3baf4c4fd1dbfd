/* SPDX-License-Identifier: MIT */
/*
** internal.h -- private declarations shared by the library's sources.
** Nothing here is part of the API; names are lower_snake_case and static
** inline, or carry the ray__ prefix when they must be linked.
*/
#ifndef RAY_INTERNAL_H
#define RAY_INTERNAL_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "ray.h"

/* pi, which strict C99 <math.h> does not define. */
#define RAY__PI 3.14159265358979323846

/* Let gcc and clang check the arguments of printf-like functions
** (-Wformat); other compilers ignore it. */
#if defined(__GNUC__)
#define RAY__PRINTF(fmt, first) __attribute__((format(printf, fmt, first)))
#else
#define RAY__PRINTF(fmt, first)
#endif

/* A scene's error message (ray_scene_errmsg): room for the longest one,
** a function name, two size_t and three %g vectors (about 150 bytes);
** snprintf cuts anything longer. */
#define RAY__ERRMSG_SIZE 256

/* A vector in a message: printf("at " RAY__V3FMT, RAY__V3ARGS(v)). */
#define RAY__V3FMT "(%g, %g, %g)"
#define RAY__V3ARGS(v) (v).x, (v).y, (v).z

/* ------------------------------------------------------- vector helpers */

static inline ray_vec3 v3(double x, double y, double z)
{
    ray_vec3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}

static inline ray_vec3 v3_add(ray_vec3 a, ray_vec3 b)
{
    return v3(a.x + b.x, a.y + b.y, a.z + b.z);
}

static inline ray_vec3 v3_sub(ray_vec3 a, ray_vec3 b)
{
    return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}

static inline ray_vec3 v3_scale(ray_vec3 a, double s)
{
    return v3(a.x * s, a.y * s, a.z * s);
}

/* a + s*b, in two roundings per component (no FMA: see the Makefile). */
static inline ray_vec3 v3_madd(ray_vec3 a, double s, ray_vec3 b)
{
    return v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}

static inline double v3_dot(ray_vec3 a, ray_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline ray_vec3 v3_cross(ray_vec3 a, ray_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
              a.x * b.y - a.y * b.x);
}

static inline ray_vec3 v3_abs(ray_vec3 a)
{
    return v3(fabs(a.x), fabs(a.y), fabs(a.z));
}

static inline double v3_length(ray_vec3 a)
{
    return sqrt(v3_dot(a, a));
}

/*
** a / |a| into *out, safe from overflow and underflow of |a|^2: a is first
** divided by its largest |component|, which brings that component to 1
** and |a| into [1, sqrt 3], so the normal of a 1e-150-sized triangle
** (|n|^2 ~ 1e-600), of a denormal one or of a 1e200-sized one still comes
** out unit.
** Returns 0, leaving *out untouched, for a zero or non-finite vector.
*/
static inline int v3_normalize(ray_vec3 a, ray_vec3 *out)
{
    double m = fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));
    double len;

    /* fmax ignores a NaN operand, so check every component: a cross
    ** product of huge vectors can hold Inf - Inf = NaN beside finite ones. */
    if (!(m > 0 && m < HUGE_VAL) || a.x != a.x || a.y != a.y || a.z != a.z)
        return 0;
    /* Divide by m rather than multiply by 1/m: for a denormal m, 1/m
    ** overflows to Inf, while each quotient here is at most 1. */
    a = v3(a.x / m, a.y / m, a.z / m);
    len = v3_length(a);
    *out = v3_scale(a, 1.0 / len);
    return 1;
}

/* Component k (0: x, 1: y, 2: z) of v. */
static inline double v3_axis(ray_vec3 v, int k)
{
    return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

/* 1 when every component is finite (neither NaN nor +-Inf). */
static inline int v3_isfinite(ray_vec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}

/* A borrowed const pointer as the plain void * of a callback's ud: the
** library only reads through it.  A union rather than a cast, so the
** compiler's -Wcast-qual still guards every other cast. */
static inline void *ray__unconst(const void *p)
{
    union {
        const void *c;
        void *m;
    } u;
    u.c = p;
    return u.m;
}

/* ------------------------------------------------------ rounding bounds */

/*
** gamma(n) = n*u / (1 - n*u), u = DBL_EPSILON/2: the relative error bound
** of n chained IEEE-754 roundings (Higham, "Accuracy and Stability of
** Numerical Algorithms", 2nd ed., Lemma 3.1; pbrt-v4 util/float.h uses the
** same name).  Used to build the hit records' p_err bounds.
*/
static inline double ray__gamma(int n)
{
    double nu = (double)n * (DBL_EPSILON * 0.5);
    return nu / (1.0 - nu);
}

/*
** a*b - c*d with one rounding's worth of error: the products' rounding
** errors e1 = a*b - p1 and e2 = c*d - p2 are exact doubles, computed by
** fma (correctly rounded on every C99 platform, hardware FMA or not, so
** the result is the same everywhere), and added back:
**
**     p1 = fl(a*b), p2 = fl(c*d), e1 = fma(a, b, -p1), e2 = fma(c, d, -p2),
**     result = fl(fl(p1 - p2) + fl(e1 - e2)).
**
** This is the symmetric form of Cornea, Harrison and Tang ("Scientific
** Computing on Itanium-based Systems", 2002), not Kahan's (pbrt-v4's
** DifferenceOfProducts, which rounds c*d first and is not symmetric in its
** two products).  Error, with u = 2^-53 and E = a*b - c*d (Jeannerod,
** Louvet, Muller, "Further analysis of Kahan's algorithm for the accurate
** computation of 2x2 determinants", Math. Comp. 82, 2013, do the same
** kind of case split):
**   - p1, p2 of one sign within a factor 2 of each other: p1 - p2 is
**     exact (Sterbenz), so the error is that of the two last roundings,
**     at most u |E| + u^2 (|ab| + |cd|), |e1 - e2| <= u (|ab| + |cd|);
**   - otherwise |p1 - p2| >= (|p1| + |p2|) / 4 and |e1 - e2| <= 4 u
**     |p1 - p2|: three roundings of quantities within 1 + 5u of |E|,
**     at most 2 u |E| (1 + O(u)).
** So |error| <= 2u |E| + u^2 (|ab| + |cd|): relative accuracy however much
** a*b and c*d cancel (the plain fl(fl(ab) - fl(cd)) has absolute error up
** to u (|ab| + |cd|) + u |E|, unbounded relative to E).  And the sign is
** E's or zero (in the first case by the monotonicity of rounding, in the
** second as the error is below |E|).  Products or errors in the subnormal
** range lose these bounds (the error terms round); libray's callers keep
** a fallback for that range.
**
** Exactly antisymmetric: ray__diff_of_products(c, d, a, b) swaps p1 with
** p2 and e1 with e2, and fl(x - y) = -fl(y - x), fl(-x + -y) = -fl(x + y)
** under round-to-nearest-even, so it returns exactly -result; and a*b =
** b*a, fma(a, b, z) = fma(b, a, z).  So two triangles sharing an edge
** still get opposite values for it -- and, the products being explicit
** statements and fma an explicit call, that holds even where a compiler
** would contract a*b - c*d into an FMA of its own choosing.
*/
static inline double ray__diff_of_products(double a, double b, double c,
                                           double d)
{
    double p1 = a * b, p2 = c * d;
    double e1 = fma(a, b, -p1), e2 = fma(c, d, -p2);

    return (p1 - p2) + (e1 - e2);
}

/*
** The default tolerance of ray_implicit and ray_parametric for a surface
** in the box [lo, hi] (ray.h): 1e-9 of the box's diagonal -- far below
** what a picture shows, far above the rounding of a reasonable field or
** S(u, v) of a surface that size -- plus 64 ulps of the box's largest
** |coordinate| (64 DBL_EPSILON m), because far from the origin the
** coordinates themselves, and f computed from them, are that coarse.
** (Relative to the coordinates alone, a unit sphere at 1e9 would get a
** tolerance of 1.)  The diagonal is formed from coordinates divided by
** the largest, so it neither overflows nor underflows.
*/
#define RAY__TOLERANCE_OF_DIAGONAL 1e-9
#define RAY__TOLERANCE_ULPS 64.0
static inline double ray__default_tolerance(ray_vec3 lo, ray_vec3 hi)
{
    double m = fmax(fmax(fabs(lo.x), fabs(hi.x)),
                    fmax(fmax(fabs(lo.y), fabs(hi.y)),
                         fmax(fabs(lo.z), fabs(hi.z))));
    ray_vec3 e;

    if (!(m > 0))
        return 0;
    e = v3(hi.x / m - lo.x / m, hi.y / m - lo.y / m, hi.z / m - lo.z / m);
    return m * (RAY__TOLERANCE_OF_DIAGONAL * v3_length(e) +
                RAY__TOLERANCE_ULPS * DBL_EPSILON);
}

/* ----------------------------------------------------- shared internals */

/*
** The ray's own frame (Woop, Benthin, Wald, "Watertight Ray/Triangle
** Intersection", JCGT 2(1), 2013, section 3): kz is the axis of dir's
** largest component, kx and ky the two others in cyclic order, and the
** shear (sx, sy) maps dir onto the kz axis.  A vertex is projected on its
** own, translated to the ray origin and sheared, so vertices shared by two
** primitives get bit-identical coordinates: what makes both the polygon
** test and the watertight triangle test watertight.
*/
typedef struct ray__frame {
    size_t at[3];            /* byte offsets of components kx, ky, kz */
    double o[3];             /* the origin's components kx, ky, kz */
    double dz;               /* dir's component along kz */
    double sx, sy;
} ray__frame;

/* Component "at" (a byte offset, as in ray__frame) of *v: a load from a
** per-ray offset, where v3_axis would branch on the axis. */
static inline const double *v3_ptr(const ray_vec3 *v, size_t at)
{
    return (const double *)(const void *)((const char *)v + at);
}

static inline double v3_at(const ray_vec3 *v, size_t at)
{
    return *v3_ptr(v, at);
}

/* The frame's axes kx, ky, kz (a permutation of 0, 1, 2) for origin org. */
static inline void ray__frame_axes(ray__frame *f, ray_vec3 org, int kx,
                                   int ky, int kz)
{
    static const size_t at[3] = {offsetof(ray_vec3, x),
                                 offsetof(ray_vec3, y),
                                 offsetof(ray_vec3, z)};
    f->at[0] = at[kx];
    f->at[1] = at[ky];
    f->at[2] = at[kz];
    f->o[0] = v3_at(&org, f->at[0]);
    f->o[1] = v3_at(&org, f->at[1]);
    f->o[2] = v3_at(&org, f->at[2]);
}

/* Set up the frame of r; 0 (frame unset) for a zero or NaN direction.
** Indexing instead of branches: which axis is largest is a coin toss for
** incoherent rays, and a mispredicted branch costs more than the lot. */
static inline int ray__frame_init(ray__frame *f, const ray_ray *r)
{
    static const int next_axis[3] = {1, 2, 0};
    ray_vec3 ad = v3_abs(r->dir);
    double d[3];
    int x_largest = (ad.x > ad.y) & (ad.x > ad.z);
    int y_largest = !(ad.x > ad.y) & (ad.y > ad.z);
    int kz = 2 - 2 * x_largest - y_largest, kx = next_axis[kz];
    int ky = next_axis[kx];

    d[0] = r->dir.x;
    d[1] = r->dir.y;
    d[2] = r->dir.z;
    f->dz = d[kz];
    if (f->dz == 0 || f->dz != f->dz)
        return 0;
    f->sx = d[kx] / f->dz;
    f->sy = d[ky] / f->dz;
    ray__frame_axes(f, r->org, kx, ky, kz);
    return 1;
}

/* Vertex v in the frame: p[0], p[1] sheared so the ray is (0, 0); p[2]
** the unsheared distance along kz (v - org)[kz]. */
static inline void ray__frame_project(const ray__frame *f, const ray_vec3 *v,
                                      double p[3])
{
    p[2] = v3_at(v, f->at[2]) - f->o[2];
    p[0] = (v3_at(v, f->at[0]) - f->o[0]) - f->sx * p[2];
    p[1] = (v3_at(v, f->at[1]) - f->o[1]) - f->sy * p[2];
}

/* A ray that can hit anything: finite origin and direction, a non-zero
** direction and tmin < tmax (a hit needs tmin < t < tmax); every other
** ray hits nothing, whatever the geometry. */
static inline int ray__ray_usable(const ray_ray *r)
{
    /* x - x is 0 for a finite x and NaN for an infinite or NaN one: one
    ** compare for all six components, and no branch but the last. */
    double finite = ((r->org.x - r->org.x) + (r->org.y - r->org.y)) +
                    ((r->org.z - r->org.z) + (r->dir.x - r->dir.x)) +
                    ((r->dir.y - r->dir.y) + (r->dir.z - r->dir.z));
    int nonzero = (r->dir.x != 0) | (r->dir.y != 0) | (r->dir.z != 0);

    return (finite == 0) & nonzero & (r->tmin < r->tmax);
}

/*
** The orthonormal tangents (t1, t2) of unit normal n, so that (t1, t2, n)
** is right-handed.  Duff, Burgess, Christensen, Hery, Kensler, Liani,
** Villemin, "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017,
** listing 3: branch-free and continuous except across n.z = 0's sign.
*/
void ray__tangent_frame(ray_vec3 n, ray_vec3 *t1, ray_vec3 *t2);

/*
** The textbook sphere test exactly as the lecture writes it (b^2 - ac on
** the raw coefficients, (-b -+ sqrt)/a).  Kept only so tests and the bench
** can show what the cancellation-free ray_sphere buys; not exported.
*/
int ray__sphere_naive(const ray_ray *r, ray_vec3 center, double radius,
                      ray_hit *hit);

/*
** Fill *hit for a hit at parameter t on the plane through "point" with
** UNIT normal n: the point is projected back onto the plane and given the
** tangent-frame (u, v) of ray_plane, measured from "origin".  Returns 0,
** leaving *hit untouched, if a result is not finite.
*/
double ray__plane_t_error(ray_vec3 po, ray_vec3 n, ray_vec3 dir,
                          double denom, double t);
int ray__plane_fill(const ray_ray *r, ray_vec3 point, ray_vec3 n,
                    ray_vec3 origin, double t, ray_hit *hit);

/*
** The real roots of the polynomial c[0] + c[1] x + ... + c[degree] x^degree
** in [lo, hi], ascending, into roots[] (room for degree + 1 needed):
** src/poly.c, after Yuksel (HPG 2022).  c[degree] must not be 0.
*/
#define RAY__POLY_MAX_DEGREE 4
int ray__poly_roots(const double *c, int degree, double lo, double hi,
                    double *roots);

/* 1 if ray_implicit accepts descriptor s (what it answers -RAY_EINVAL to
** whatever the ray); for the scene, which checks when a surface is added. */
int ray__implicit_valid(const ray_implicit_surface *s);

/* 1 if ray_parametric accepts descriptor s, with its domain (defaults
** applied) in d = {u0, u1, v0, v1}; 0 (d untouched) otherwise. */
int ray__parametric_domain(const ray_parametric_surface *s, double d[4]);

/* The tolerance ray_implicit uses for a valid descriptor (its own or
** the default); hits lie within it of the surface's box. */
double ray__implicit_tolerance(const ray_implicit_surface *s);

/* The box of a torus, rounded outward (0 for invalid params). */
int ray__torus_box(const ray_torus_params *t, ray_vec3 *lo, ray_vec3 *hi);

/* ------------------------------------------------------------ the scene */

enum {
    PRIM_SPHERE, PRIM_PLANE, PRIM_TRIANGLE, PRIM_POLYGON, PRIM_MESH,
    PRIM_TORUS, PRIM_IMPLICIT, PRIM_PARAMETRIC, PRIM_BEZIER
};

/* A curved surface's descriptor as added (the field of its kind). */
typedef struct ray__surface {
    ray_torus_params torus;
    ray_implicit_surface implicit;
    ray_parametric_surface parametric;
} ray__surface;

/* One piece of geometry (what a geom_id names).  By kind: sphere: a =
** centre; plane: a = point, b = unit normal; triangle and mesh: tris[first
** .. first+count-1] of the scene (until commit reorders them), and for a
** mesh meshes[mesh]; polygon: verts[first .. first+count-1]; torus,
** implicit and parametric: surfaces[surface], and Bezier: its 16 control
** points at verts[first ..]; all four keep their box in a (lo), b (hi). */
typedef struct ray__prim {
    int kind;
    unsigned material;
    ray_vec3 a, b, c;
    double radius;
    size_t first, count;
    unsigned mesh;
    unsigned surface;
} ray__prim;

/* Triangles are stored flat, three vertices each, whatever they came
** from; at commit they are reordered into BVH leaf order, so a leaf is a
** contiguous run.  Their ids live apart: only the nearest hit needs them. */
typedef struct ray__tri {
    ray_vec3 a, b, c;
} ray__tri;

typedef struct ray__tri_id {
    unsigned geom_id, prim_id;
} ray__tri_id;

/* What a mesh keeps for shading: its index triples, and its per-vertex
** normals and texture coordinates when it has them (else NULL). */
typedef struct ray__mesh {
    unsigned *indices;
    ray_vec3 *normals;
    double *texcoords;
    size_t n_vertices, n_tris;
} ray__mesh;

/*
** A node of the binary BVH that the build makes and collapses into wide
** nodes: its box, in float, rounded outward from the double geometry so
** it still contains it; an inner node (count == 0) has its two children
** side by side at nodes[first] and nodes[first + 1], a leaf holds items
** first .. first + count - 1.
*/
typedef struct ray__node {
    float lo[3], hi[3];
    unsigned first, count;
} ray__node;

/*
** The traversal's node: up to RAY__WIDTH children's boxes side by side,
** one float array per bound and axis, so four- or eight-lane arithmetic
** tests them all at once.  Eight children rather than four halve the
** depth a ray descends, and traversal is a chain of dependent node visits
** (each ~70 cycles, mostly latency); the two four-lane halves of a node
** are independent and overlap.  count[k] == 0: child[k] is the index of an
** inner node; else slot k is a leaf, count[k] == RAY__LEAF | n, of the n
** items from child[k].  An unused slot is a leaf of no items with an
** empty box (lo = +Inf, hi = -Inf), so even a ray that "entered" it would
** test nothing.  256 bytes: four cache lines.
*/
#define RAY__WIDTH 8
#define RAY__LEAF 0x80000000u
typedef struct ray__wnode {
    float lo[3][RAY__WIDTH], hi[3][RAY__WIDTH];
    unsigned child[RAY__WIDTH], count[RAY__WIDTH];
} ray__wnode;

typedef struct ray__bvh {
    ray__node *nodes;    /* binary BVH: built first, freed after collapse */
    size_t n_nodes, cap_nodes;
    ray__wnode *wide;    /* what traversal uses */
    size_t n_wide;
    unsigned *items;     /* leaf order -> item index */
    size_t n_items;
} ray__bvh;

/* A light as added, with the unit vector every sample of it needs
** computed once when it is added: the direction toward a directional
** light (-direction) or the emitting normal of a rect light
** (edge1 x edge2); unused by the other kinds. */
typedef struct ray__light {
    ray_light desc;
    ray_vec3 axis;
} ray__light;

struct ray_scene {
    ray_alloc_fn alloc;
    void *alloc_ud;
    ray__prim *prims;
    size_t n_prims, cap_prims;
    ray__tri *tris;
    ray__tri_id *tri_ids;
    size_t n_tris, cap_tris, cap_tri_ids;
    ray__mesh *meshes;
    size_t n_meshes, cap_meshes;
    ray__surface *surfaces;
    size_t n_surfaces, cap_surfaces;
    ray__bvh tri_bvh;        /* over tris, reordered to leaf order */
    ray__bvh prim_bvh;       /* over bounded prims: spheres, polygons */
    unsigned *planes;        /* the unbounded prims, tested apart */
    size_t n_planes;
    ray_vec3 *verts;
    size_t n_verts, cap_verts;
    ray_material *materials;
    size_t n_materials, cap_materials;
    ray__light *lights;
    size_t n_lights, cap_lights;
    ray_rgb background, ambient;
    ray_background_fn background_fn;
    void *background_ud;
    ray_limits limits;
    int prune;               /* ray_scene_set_pruning; 1 by default */
    int watertight;          /* ray_scene_set_watertight; 1 by default */
    unsigned effects;        /* what the scene can need, set by commit */
    int committed;
    /* ray_scene_errmsg: the building call now running (a function name,
    ** static) and the message of its failure, "" while none.  A fixed
    ** buffer, so that out of memory can be reported too. */
    const char *op;
    char errmsg[RAY__ERRMSG_SIZE];
};

/* Allocation through the scene's allocator (libc when it has none). */
void *ray__alloc(const ray_scene *s, size_t size);
void ray__free(const ray_scene *s, void *ptr, size_t size);
void *ray__realloc(const ray_scene *s, void *ptr, size_t osize, size_t nsize);

/* Append a validated primitive (checks its material; RAY_EINVAL,
** RAY_ENOMEM); *geom_id, if not NULL, receives its id. */
int ray__add_prim(ray_scene *s, const ray__prim *prim, unsigned *geom_id);

/*
** ray__begin -- the start of every building call ("op", its name, heads
** its messages): clears the last message (a success leaves none) and
** returns RAY_OK if the scene may still be changed, RAY_EINVAL for NULL,
** RAY_ESTATE (with its message) after commit.
** ray__fail -- record the failure of the running call: "op: " and the
** printf-formatted message, cut to the buffer; returns "code".
*/
int ray__begin(ray_scene *s, const char *op);
int ray__fail(ray_scene *s, int code, const char *fmt, ...)
    RAY__PRINTF(3, 4);

/* RAY_OK if "material" names a material of the scene, else RAY_EINVAL with
** its message. */
int ray__material_known(ray_scene *s, unsigned material);

/* Room for "more" vertices in the scene's verts array. */
int ray__reserve_verts(ray_scene *s, size_t more);

/* Grow an array of "size"-byte items through the scene's allocator so it
** holds used + 1; returns the (maybe moved) array or NULL. */
void *ray__grow(ray_scene *s, void *items, size_t *cap, size_t used,
                size_t size);

/* The geometry record of a mesh over tris[first .. first+count-1]. */
int ray__add_mesh_prim(ray_scene *s, unsigned material, size_t first,
                       size_t count, const ray__mesh *shading, unsigned *id);

/* Room for "more" triangles in the scene's tris/tri_ids arrays. */
int ray__reserve_tris(ray_scene *s, size_t more);

/* The triangle test alone (t, beta, gamma) and the hit record of a hit,
** split so a BVH can test many triangles and fill only the nearest. */
int ray__triangle_test(const ray_ray *r, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                       double *t, double *beta, double *gamma);
int ray__triangle_fill(ray_vec3 a, ray_vec3 b, ray_vec3 c, double t,
                       double beta, double gamma, ray_hit *hit);
int ray__triangle_watertight_test(const ray_ray *r, ray_vec3 a, ray_vec3 b,
                                  ray_vec3 c, double *t, double *beta,
                                  double *gamma);

/*
** Build a BVH over n items whose float boxes box(ud, i, lo, hi) writes
** (rounded outward), with the binned surface-area heuristic, collapsed to
** RAY__WIDTH-wide nodes.  On success *out holds the nodes and the item
** permutation (through the scene's allocator).  RAY_OK or RAY_ENOMEM
** (nothing kept).
*/
typedef void (*ray__box_fn)(const void *ud, size_t i, float lo[3],
                            float hi[3]);
typedef struct ray__bvh_costs {
    float traversal;         /* a split's cost, in item tests */
    unsigned leaf_items;     /* a node of this many items or fewer: a leaf */
} ray__bvh_costs;
int ray__bvh_build(const ray_scene *s, ray__box_fn box, const void *ud,
                   size_t n, const ray__bvh_costs *costs, ray__bvh *out);
void ray__bvh_free(const ray_scene *s, ray__bvh *bvh);

/*
** x rounded to a float no larger (down) or no smaller (up) than it, so a
** double interval becomes a float one that still contains it: the
** nearest float, moved one step of its IEEE-754 bit pattern (which orders
** like the value within a sign: an inline nextafterf) when it fell on the
** wrong side.  Branch-free, since the side is a coin toss for the ray
** origins of a traversal: the step is +1 or -1 on the bits by the sign,
** times 0 or 1.  A zero needs no special case: only -0 steps down (to
** -2^-149: an x below +0 rounds to -0) and only +0 steps up.  NaN stays
** NaN (both comparisons fail).
*/
static inline float ray__float_down(double x)
{
    float f = (float)x;
    uint32_t u, need = (double)f > x;

    memcpy(&u, &f, sizeof u);
    u += need * (2u * (u >> 31) - 1u);     /* f > 0: -1; f < 0 or -0: +1 */
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline float ray__float_up(double x)
{
    float f = (float)x;
    uint32_t u, need = (double)f < x;

    memcpy(&u, &f, sizeof u);
    u += need * (1u - 2u * (u >> 31));     /* f >= +0: +1; f < 0: -1 */
    memcpy(&f, &u, sizeof f);
    return f;
}

/*
** Nearest hit / any hit over the scene, counting intersection tests, in
** all and by kind of primitive, into *st (may be NULL).  The public
** ray_intersect/ray_occluded wrap these.
*/
int ray__intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                   ray_stats *st);
int ray__occluded(const ray_scene *s, const ray_ray *r, ray_stats *st);

/* The same queries for the baseline instruction set and for AVX2 (x86
** with GCC or Clang only, intersect_avx2.c: RAY__AVX2_COPY), which
** ray__intersect and ray__occluded choose between; the tests compare the
** two. */
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && \
    !defined(RAY_NO_SIMD) && !defined(RAY_NO_AVX2)
#define RAY__AVX2_COPY 1
#else
#define RAY__AVX2_COPY 0
#endif
int ray__intersect_base(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                        ray_stats *st);
int ray__occluded_base(const ray_scene *s, const ray_ray *r, ray_stats *st);
int ray__intersect_avx2(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                        ray_stats *st);
int ray__occluded_avx2(const ray_scene *s, const ray_ray *r, ray_stats *st);

/* ------------------------------------------------------------ trace state */

struct ray_ctx {
    const ray_scene *scene;
    ray_stats stats;
    unsigned long long rng;  /* splitmix64 state of the current sample */
    int in_shade;            /* inside a material callback */
    unsigned depth;          /* depth of the hit being shaded */
    double weight;           /* path weight of the ray being shaded */
    unsigned effects;        /* effects of the material being shaded */
    unsigned fanout;         /* secondary rays spawned by that hit so far */
};

/* splitmix64 (Steele, Lea, Flood, OOPSLA 2014): a tiny, fast, well-mixed
** generator whose state is a single counter, so a pixel's sequence can be
** started anywhere from a hash of its coordinates. */
static inline unsigned long long ray__mix64(unsigned long long z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* The sampler state of sample "s" of pixel (x, y) in a frame with "seed":
** a hash of all four, independent of which thread renders the pixel. */
static inline unsigned long long ray__pixel_seed(unsigned long long seed,
                                                 unsigned x, unsigned y,
                                                 unsigned s)
{
    unsigned long long h = ray__mix64(seed + 0x9e3779b97f4a7c15ull);
    h = ray__mix64(h ^ (((unsigned long long)y << 32) | x));
    return ray__mix64(h + s);
}

/* The least k with k * k >= n (n <= 65536): a square grid of strata. */
unsigned ray__strata_side(unsigned n);

/* (a, b) in [-1,1]^2 onto the unit disk, by the concentric map. */
void ray__concentric_disk(double a, double b, double *x, double *y);

/* Reset a context's per-sample state. */
void ray__ctx_start(ray_ctx *ctx, unsigned long long rng);

/* The naive variants the stability suite and the bench compare with
** (not exported): float Cramer, and barycentrics divided by N.N. */
int ray__triangle_float(const ray_ray *r, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                        double *t);
int ray__barycentric_naive(ray_vec3 p, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                           double abg[3]);

/*
** The bicubic Bezier fast path of ray_parametric (bezier.c), declared
** here for parametric.c: instead of one bounds call per rectangle, which
** rebuilds the sub-patch's control net from the whole patch, the
** traversal carries each quad-tree node's 4 x 4 net and halves it by de
** Casteljau.  ray__bezier_points: the 16 control points of a surface
** made by ray_bezier_surface, NULL for any other.  ray__bezier_magnitude:
** the "mag" the boxes are grown with.  ray__bezier_split: the net (row
** i, column j at net[stride*i + j]) split at u = v = 1/2 into the 7 x 7
** grid whose 4 x 4 corner blocks, at grid + ray__bezier_quarter(q), are
** the quarters' nets (q: bit 0 the upper u half, bit 1 the upper v
** half), and their boxes, grown to contain the exact sub-patches at
** "level" halvings below the patch.
*/
#define RAY__BEZIER_GRID 7
const ray_vec3 *ray__bezier_points(const ray_parametric_surface *s);
ray_vec3 ray__bezier_magnitude(const ray_vec3 cp[16]);
void ray__bezier_split(const ray_vec3 *net, int stride, ray_vec3 mag,
                       unsigned level,
                       ray_vec3 grid[RAY__BEZIER_GRID * RAY__BEZIER_GRID],
                       ray_vec3 lo[4], ray_vec3 hi[4]);
static inline int ray__bezier_quarter(unsigned q)
{
    return RAY__BEZIER_GRID * ((q & 2u) ? 3 : 0) + ((q & 1u) ? 3 : 0);
}

/* ------------------------------------------------------------- images */

/* A new image of width x height texels that takes over rgb (3 floats per
** texel, rows top to bottom), for png.c's loader; NULL when out of memory,
** rgb then still the caller's. */
ray_image *ray__image_new(unsigned width, unsigned height, float *rgb);

#endif /* RAY_INTERNAL_H */
