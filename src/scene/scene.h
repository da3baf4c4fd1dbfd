/* SPDX-License-Identifier: MIT */
/*
** scene.h -- the scene: its records, struct ray_scene, its allocation
** helpers and error messages, and the per-kind dispatch (kinds.c).
*/
#ifndef RAY_SCENE_H
#define RAY_SCENE_H

#include "accel/bvh.h"
#include "prim/prim.h"

/* Let gcc and clang check the arguments of printf-like functions
** (-Wformat); other compilers ignore it.  MinGW's GCC takes "printf" as
** msvcrt's rules (no %zu); the library's printf there is C99's, MinGW's
** own (__USE_MINGW_ANSI_STDIO, which core/vec.h requires): gnu_printf. */
#if defined(__MINGW32__) && defined(__GNUC__)
#define RAY__PRINTF(fmt, first) __attribute__((format(gnu_printf, fmt, first)))
#elif defined(__GNUC__)
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

/* A curved surface's descriptor as added: the member of its geometry's
** kind (RAY__KIND_TORUS, _IMPLICIT, _PARAMETRIC, _USER, a shape's) is
** the live one. */
typedef union ray__surface {
    ray_torus_params torus;
    ray_implicit_surface implicit;
    ray_parametric_surface parametric;
    ray_user_geometry user;
#define RAY__SHAPE_MEMBER(X, NAME, name, type, counted_as) type name;
    RAY__SHAPES(RAY__SHAPE_MEMBER, _)
} ray__surface;

/* One piece of geometry (what a geom_id names).  By kind: sphere: a =
** centre; plane: a = point, b = unit normal, c = b normalised again (the
** hit records' normal: kinds.c plane_fill); triangle: its corners a, b,
** c; triangle and mesh: triangle slots first .. first+count-1 of the
** scene (until commit reorders them), and for a mesh meshes[mesh]; polygon: verts[first .. first+count-1]; torus,
** implicit, parametric, user geometry and the shapes: surfaces[surface],
** and Bezier: its 16 control points at verts[first ..]; all of these keep
** their box in a (lo), b (hi). */
typedef struct ray__prim {
    ray__kind kind;
    unsigned material;
    ray_vec3 a, b, c;
    double radius;
    size_t first, count;
    unsigned mesh;
    unsigned surface;        /* also an instance's index in instances */
    unsigned mask;           /* ray_scene_set_mask; all bits by default */
    unsigned filter_queries; /* RAY_FILTER_* bits its filter applies to */
    ray_filter_fn filter;    /* NULL: none */
    void *filter_ud;
    int enabled;             /* ray_scene_set_enabled; 1 by default */
    int removed;             /* ray_scene_remove: never seen again */
} ray__prim;

/*
** An instance (ray_scene_add_instance): the child scene, the transform
** and its inverse (L^-1, applied to p - c), the child's commit generation
** its box was taken at, and its box in world space.
*/
typedef struct ray__instance {
    const ray_scene *child;
    ray_transform xfm;       /* object -> world */
    double inv[3][3];        /* L^-1: world -> object, after - c */
    int linear_identity;     /* L == I exactly: normals need no transform */
    double similarity;       /* L = s R (R a rotation) to 64 ulps: s, the
                                scale distances take; 0 for other L */
    double inv_norm;         /* |L^-1| (Frobenius): no object distance is
                                more than this times the world one */
    double inv_spec;         /* |L^-1|_2 = 1 / L's smallest singular value,
                                rounded up: the least such factor */
    double inv_residual;     /* >= |inv L - I|_2: how far inv, as rounded,
                                is from L's exact inverse */
    double axes[3][3];       /* L = U diag(sv) V^T: U (its columns), what a */
    double sv[3];            /* sphere's ellipsoid has for axes; sv
                                descending (sv[0] = 0: none computed) */
    unsigned long long generation;
    ray_vec3 lo, hi;         /* world box, rounded outward */
    int removed;             /* ray_scene_remove: its child may be gone */
} ray__instance;

/*
** The triangles: a slot each, numbered in the triangle BVH's leaf order
** after a commit (a leaf is a contiguous run of slots).  A slot keeps its
** ids, (geom_id, prim_id), which name its corners -- a single triangle's
** a, b, c in its geometry record, a mesh triangle's through the mesh's
** own indices and double positions -- and, for slots in the BVH, a float
** copy of its corners in the leaf's block (ray__leaf_corners), which the
** queries' float filter reads.  No double copy per slot: the exact test
** reads the geometry's own vertices (issue 27: memory per triangle).
*/
typedef struct ray__tri_id {
    unsigned geom_id, prim_id;
} ray__tri_id;

/* A triangle's corners, as a value. */
typedef struct ray__tri {
    ray_vec3 a, b, c;
} ray__tri;

/*
** What a mesh keeps: its positions, as doubles (a copy the scene owns,
** what the exact triangle test reads), its index triples, and its
** per-vertex normals and texture coordinates when it has them (else
** NULL); copies the scene owns, or for a borrowed mesh (RAY_MESH_BORROW)
** the caller's own arrays (its indices the caller's when they are
** unsigned, else a copy), its descriptor in "src" (what
** ray_scene_update_mesh(.., NULL) reads again).
*/
typedef struct ray__mesh {
    ray_vec3 *pos;               /* n_vertices positions, the scene's */
    const unsigned *indices;     /* 3 n_tris: copied (or the caller's) */
    const ray_vec3 *normals;
    const double *texcoords;
    size_t n_vertices, n_tris;
    int borrowed;                /* the arrays are the caller's */
    int own_indices;             /* indices is the scene's copy */
    int pos_floats;              /* every coordinate of pos is a float:
                                    its float copy in the leaves is exact */
    ray_mesh src;                /* borrowed: the caller's descriptor */
    double *uv_scale;            /* with texcoords: per triangle, sqrt(its
                                    (s, t) area / its area), for ray
                                    cones' footprints; the scene's own
                                    even when borrowed; else NULL */
    int closed;                  /* every edge used an even number of
                                    times (closed.c): ray_contains counts
                                    its crossings' parity; known only
                                    while the scene's closed_known is 1 */
} ray__mesh;

/* *closed: whether the mesh of n_tris index triples is closed (closed.c).
** RAY_OK, or RAY_ENOMEM (*closed 0). */
int ray__mesh_closed(const ray_scene *s, const unsigned *indices,
                     size_t n_tris, int *closed);

/*
** ray__closed_ensure -- every mesh's "closed" known, in s and in the
** children of its instances, found by the first query that needs them
** after a commit that changed a mesh (ray_contains, ray_signed_distance,
** ray_distance_grid, ray_render_check's eye test), under the scene's
** cgrid_lock, rather than by ray_scene_add_mesh and every
** ray_scene_update_mesh: a game's refit does not pay for it (closed.c).
** RAY_OK, or RAY_ENOMEM (nothing known; a later call tries again).
** ray__closed_all -- the same for s's own meshes, unlocked (commit.c,
** when no lock could be made).
*/
int ray__closed_ensure(const ray_scene *s);
int ray__closed_all(ray_scene *s);

/*
** The closed meshes' part of ray_contains at q (parity.c): *parity, the
** parity of the exact crossings of the ray from q along +x perturbed
** symbolically (q + (0, e, e^2)) with the triangles of the enabled
** closed meshes whose mask meets ~ignore, and *on, whether q lies on one
** of them exactly (then *parity is not meaningful: the walk stops
** there).  all: every enabled closed mesh counts for this query (its
** mask is not tested), so that the grid's labels apply.
** ray__cgrid_build -- the grid (s->cgrid) over the committed triangle
** BVH: RAY_OK (no grid where there is no closed mesh or the marking
** would cost too much) or RAY_ENOMEM (none).  ray__cgrid_free frees it.
** ray__cgrid_ensure -- the grid built if it has not been tried since the
** last rebuild, under s->cgrid_lock: what a query calls before it reads
** s->cgrid (the lock orders the build before every read).
*/
void ray__closed_parity(const ray_scene *s, ray_vec3 q, unsigned ignore,
                        int all, unsigned *parity, int *on);
int ray__cgrid_build(ray_scene *s);
void ray__cgrid_free(ray_scene *s);
void ray__cgrid_ensure(const ray_scene *s);

/* Corner k (0 .. 3 n_tris - 1) of mesh m's triangles, for shading. */
unsigned ray__mesh_corner(const ray__mesh *m, size_t k);

/* A light as added, with the unit vector every sample of it needs
** computed once when it is added: the direction toward a directional
** light (-direction) or the emitting normal of a rect light
** (edge1 x edge2); unused by the other kinds. */
typedef struct ray__light {
    ray_light desc;
    ray_vec3 axis;
    unsigned side;           /* its samples a side x side grid (1: a point
                                or directional light), made when added:
                                every light sample asks (issue 35) */
} ray__light;

/*
** ray_contains' grid over the closed meshes (parity.c): n[0] n[1] n[2]
** cells between walls at doubles (wall[a][0 .. n[a]], non-decreasing,
** wall[a][0] and wall[a][n[a]] the box of the closed meshes' triangles),
** label[(k n[1] + j) n[0] + i] for cell (i, j, k): 0 where a closed
** triangle's box touches it, else 1 outside the solid and 2 inside.
** n[0] == 0: no grid (no closed mesh, or out of its limits).  One block
** of "bytes" (walls, then labels); built at commit, read-only after.
*/
typedef struct ray__cgrid {
    unsigned n[3];
    double *wall[3];
    double scale[3];             /* n / extent: the cell index's guess */
    int every;                   /* every live triangle slot is a closed
                                    mesh's */
    unsigned char *label;
    double *block;
    size_t bytes;
} ray__cgrid;

/*
** The far-field expansion of the winding number over the triangles under
** one wide node of tri_bvh (query/winding.c: Barill et al. 2018's order
** 2): the centre p (area-weighted centroid), a radius r that every corner
** under the node is within, and per class (0: the triangles the winding
** number answers by default, single triangles and open meshes'; 1: the
** closed meshes', which only RAY_CONTAINS_WINDING sums) the vector area
** sum n = sum a_t n_t and the tensor m[3 i + j] = sum a_t (c_t - p)_i
** n_t,j.  classes: bit c set where class c has a triangle there.
*/
typedef struct ray__wexp {
    double p[3], r, area;
    double n[2][3], m[2][9];
    unsigned classes;
} ray__wexp;

struct ray_scene {
    ray__allocator alloc;    /* the user's, or libc's */
    ray__prim *prims;
    size_t n_prims, cap_prims;
    ray__tri_id *tri_ids;    /* the triangle slots (ray__tri_id) */
    size_t n_tris, cap_tri_ids;
    size_t n_live_tris;      /* slots 0 .. n_live_tris - 1 are in tri_bvh
                                (enabled geometry), the rest wait */
    float *leaf_f;           /* the float corners of the live slots, in
                                leaf blocks (ray__leaf_corners) */
    size_t cap_leaf_f;       /* floats allocated there */
    int float_exact;         /* every live corner is a float: the filter's
                                vertex rounding is 0 (RAY__LEAF_ROWS) */
    ray__tri *leaf_tri;      /* the double corners of the live slots, in
                                leaf order, where they are not all floats
                                (NULL otherwise: ray__leaf_tri) */
    unsigned *slot_vertices; /* NULL, or a refit's copy of the live
                                slots' vertex indices (slots.h) */
    unsigned slot_geom;      /* the mesh of every live slot, if one */
    int tri_mode;            /* RAY__TRI_*: the filter on (default), off,
                                or its verdict final (bench only) */
    double filter_scale;     /* the filter's bound times this (1; tests) */
    ray__mesh *meshes;
    size_t n_meshes, cap_meshes;
    ray__surface *surfaces;
    size_t n_surfaces, cap_surfaces;
    ray__instance *instances;
    size_t n_instances, cap_instances;
    ray__bvh tri_bvh;        /* over the live triangle slots */
    ray__cgrid cgrid;        /* ray_contains' labels (parity.c), built by
                                the first query that needs them */
    struct ray__mutex *cgrid_lock; /* guards cgrid, cgrid_tried and the
                                meshes' closed, closed_known; made
                                at commit (NULL: none could be made,
                                no grid: whole rays, as exact) */
    int cgrid_tried;         /* the grid was built, or will not be, since
                                the last rebuild */
    int closed_known;        /* every mesh's "closed" found since the last
                                commit that changed a mesh (guarded by
                                cgrid_lock: ray__closed_ensure) */
    ray__wexp *wexp;         /* ray_contains' expansions, one per wide node
                                of tri_bvh (query/winding.c), made by the
                                first query that needs them after a commit
                                that changed a mesh (under cgrid_lock) */
    size_t n_wexp;           /* their count (0: none made) */
    int wexp_known;          /* wexp made since that commit */
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
    int prune;               /* !limits.no_pruning, read by the tracer;
                                1 by default */
    int watertight;          /* ray_scene_set_watertight; 1 by default */
    unsigned build_threads;  /* ray_scene_set_build_threads; 1 by default,
                                0: one per online CPU */
    ray_scheduler scheduler; /* ray_scene_set_scheduler; run NULL: the
                                built-in threads */
    ray_progress_fn progress; /* ray_scene_set_progress; NULL: none */
    void *progress_ud;
    unsigned effects;        /* what the scene can need, set by commit */
    unsigned material_effects; /* the effects of the materials its
                                  enabled geometry uses (what an instance
                                  of it adds to its parent's) */
    int committed;
    int avx2;                /* the queries take their AVX2 copy: the
                                CPU's answer (ray__cpu_has_avx2), asked
                                at commit rather than per query */
    /* Dynamic scenes (ray(7)): what the next commit must redo
    ** (RAY__DIRTY_*), the commits made so far (instances of this scene
    ** compare it with theirs), whether any geometry has a mask or a
    ** filter (else queries take the ungated path), and the box of the
    ** enabled bounded geometry (for instances of it). */
    unsigned dirty;
    unsigned long long generation;
    int gated;
    int has_instances;
    int few_spheres;         /* prim_bvh holds a few spheres alone, which
                                queries test one by one (query/few.h) */
    ray__few_spheres few;    /* those spheres as lanes, for the miss test */
    int instances_of_tris;   /* the scene holds instances alone (no
                                planes, no triangles, no other kind),
                                each of a child of triangles alone, and
                                nothing gates them: its plain queries
                                take the instances' walk (commit.c,
                                query/traverse.h) */
    ray_vec3 lo, hi;
    /* ray_scene_errmsg: the building call now running (a function name,
    ** static) and the message of its failure, "" while none.  A fixed
    ** buffer, so that out of memory can be reported too. */
    const char *op;
    char errmsg[RAY__ERRMSG_SIZE];
};

/* What a commit must redo: the triangle BVH (rebuild, or refit after
** vertex updates only), the BVH of the other bounded kinds and the plane
** list (PRIMS), instances' boxes. */
#define RAY__DIRTY_TRIS   1u
#define RAY__DIRTY_REFIT  2u
#define RAY__DIRTY_PRIMS  4u
#define RAY__DIRTY_ALL    (RAY__DIRTY_TRIS | RAY__DIRTY_PRIMS)

/*
** What changed since the commit (dirty.c).
** ray__touch -- mark what a successful building call changed (and that
** the scene needs a commit before its next query).
** ray__dirty_of -- what adding, removing, enabling or disabling geometry
** p makes the next commit rebuild: the triangle BVH or the other one
** (RAY__DIRTY_*).
** ray__instance_stale -- has instance in's child been changed (or not
** committed again) since its box was taken?  A query that meets it
** answers -RAY_ESTATE; the parent's next commit takes its box again.
*/
void ray__touch(ray_scene *s, unsigned dirty);
unsigned ray__dirty_of(const ray__prim *p);
static inline int ray__instance_stale(const ray__instance *in)
{
    /* Inline: every instance a query enters asks, and the call was 2% of
    ** a game's frame (bench/game.c, perf, issue 36). */
    return !in->child->committed || in->child->generation != in->generation;
}
/* Has a scene that s instances changed since s was committed (so that
** its queries would answer -RAY_ESTATE where they meet it)?  O(number of
** instances): for the calls that check once before a long run (a
** render, every hit along a ray) rather than per ray.  Disabled
** instances count too (their child must stay committed: the next commit
** checks it); removed ones do not (their child may be freed). */
int ray__scene_stale(const ray_scene *s);

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
** returns RAY_OK, or RAY_EINVAL for NULL.  A committed scene may be
** changed too: the call's success marks it (ray__touch), a failure
** leaves it committed.
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

/* The geometry record of a mesh over triangle slots first ..
** first+count-1. */
int ray__add_mesh_prim(ray_scene *s, unsigned material, size_t first,
                       size_t count, const ray__mesh *shading, unsigned *id);

/* Geometry geom_id of s if it exists and was not removed, else NULL with
** the error recorded (dynamic.c): what every call on an added geometry
** checks first. */
ray__prim *ray__live_prim(ray_scene *s, unsigned geom_id);

/* Free a mesh's shading data (its arrays NULL after). */
void ray__mesh_release(const ray_scene *s, ray__mesh *m);

/* A triangle that can be hit: its normal exists, i.e. its cross product
** has a non-zero finite component (what v3_normalize in triangle.c
** needs).  Comparisons, not fmax (a libm call under -std=c99): a NaN
** component (inf - inf) fails both tests, as it should. */
static inline int ray__corners_usable(ray_vec3 a, ray_vec3 b, ray_vec3 c)
{
    ray_vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    double x = fabs(n.x), y = fabs(n.y), z = fabs(n.z);
    return (x > 0 || y > 0 || z > 0) && x < HUGE_VAL && y < HUGE_VAL &&
           z < HUGE_VAL;
}

/*
** The corners of triangle prim_id of triangle geometry geom_id of s
** (ray__tri_by_id: what is handed a primitive rather than a ray, as
** ray_surface_point; the caller checks the ids), or of triangle slot i
** (leaf order after a commit: ray__tri_of, ray__tri_corners), in world
** space of s, from the geometry's own vertices: a single
** triangle's a, b, c; a mesh triangle's positions through its indices.
** Every reader goes through it, so that how the scene stores its
** triangles is written in one place.
**
** A triangle that has no normal (ray__corners_usable: a mesh's collinear
** or overflowing triangle; ray_scene_add_triangle refuses them) keeps
** its slot (a mesh update may give it an area again) and is read as the
** point at its first corner, so that every test misses it (no edge
** function is non-zero, so det is 0), its box stays finite, and no record
** is filled from it.
*/
/* A mesh triangle's corners (ray__tri_by_id's for a mesh), into *t: a
** small function that inlines where the refit reads every triangle,
** always (RAY__HOT_INLINE): with slots.h's refit_corners calling it
** too, gcc's choice changed the SSE2 refit_leaf's code, 0.4% more
** instructions in bench/filter --profile refit (callgrind, issue 36). */
RAY__HOT_INLINE void ray__mesh_tri(const ray__mesh *m, unsigned prim_id,
                                   ray__tri *t)
{
    const unsigned *k = m->indices + 3 * (size_t)prim_id;

    t->a = m->pos[k[0]];
    t->b = m->pos[k[1]];
    t->c = m->pos[k[2]];
    if (!ray__corners_usable(t->a, t->b, t->c))
        t->b = t->c = t->a;
}

static inline ray__tri ray__tri_by_id(const ray_scene *s, unsigned geom_id,
                                      unsigned prim_id)
{
    const ray__prim *p = &s->prims[geom_id];
    ray__tri t;

    if (p->kind == RAY__KIND_TRIANGLE) {
        t.a = p->a;
        t.b = p->b;
        t.c = p->c;
    } else
        ray__mesh_tri(&s->meshes[p->mesh], prim_id, &t);
    return t;
}

static inline ray__tri ray__tri_of(const ray_scene *s, size_t i)
{
    return ray__tri_by_id(s, s->tri_ids[i].geom_id, s->tri_ids[i].prim_id);
}

static inline void ray__tri_corners(const ray_scene *s, size_t i,
                                    ray_vec3 *a, ray_vec3 *b, ray_vec3 *c)
{
    ray__tri t = ray__tri_of(s, i);

    *a = t.a;
    *b = t.b;
    *c = t.c;
}

/*
** The float corners of the live triangle slots (leaf_f), for the
** queries' float filter (query/filter.h), laid out by the triangle BVH's
** leaves: a leaf of n slots (n <= RAY__LEAF_MAX) from slot "first" keeps
** its RAY__LEAF_ROWS n floats at leaf_f + RAY__LEAF_ROWS first, as nine
** rows of n -- row 3 v + k holds corner v (a, b, c) on axis k (x, y, z)
** of each slot in order -- so that one eight-lane load of a row takes
** the leaf's slots (and, past them, floats of the next rows, which the
** filter masks off; RAY__LEAF_PAD floats of padding after the last leaf
** keep those loads inside the array).  Each float is its double rounded
** to nearest; float_exact says whether every one is exact (a mesh that
** came in as floats).  A slot with a coordinate beyond
** RAY__LEAF_FLOAT_MAX in magnitude holds NaN in all nine, which the
** filter never rejects: the exact test decides it.
*/
#define RAY__LEAF_MAX 8
#define RAY__LEAF_ROWS 9
#define RAY__LEAF_PAD 8
#define RAY__LEAF_FLOAT_MAX 0x1p60

/*
** The corners of live slot i, which the exact test reads, from the
** leaf's own data rather than through the geometry (ray__tri_of: the
** slot's ids, its geometry, a mesh's indices, then its positions, four
** dependent reads that missed the cache in the ground query's profile,
** a third of its time, issue 34): the leaf's floats themselves when every
** live corner is a float (float_exact: each converts back to its double
** exactly, so these are ray__tri_of's bits; rows, stride n, as the
** filter reads them; NaN marks a slot whose floats were not kept), else
** the copy in leaf order (leaf_tri, made where the corners are not all
** floats, kept by refits); ray__tri_of where neither holds (a refit that
** turned float corners into doubles: leaf_tri is made at rebuilds).
*/
static inline ray__tri ray__leaf_tri(const ray_scene *s, size_t i,
                                     const float *rows, size_t n)
{
    if (s->float_exact && !isnan(rows[0])) {
        ray__tri t;
        t.a = ray_vec3_make((double)rows[0], (double)rows[n],
                            (double)rows[2 * n]);
        t.b = ray_vec3_make((double)rows[3 * n], (double)rows[4 * n],
                            (double)rows[5 * n]);
        t.c = ray_vec3_make((double)rows[6 * n], (double)rows[7 * n],
                            (double)rows[8 * n]);
        return t;
    }
    if (s->leaf_tri != NULL)
        return s->leaf_tri[i];
    return ray__tri_of(s, i);
}

/* The same corners without the copy where the scene keeps them in
** leaf_tri: a pointer to them there, else to *tmp, filled. */
static inline const ray__tri *ray__leaf_tri_at(const ray_scene *s, size_t i,
                                               const float *rows, size_t n,
                                               ray__tri *tmp)
{
    if (s->leaf_tri != NULL && !(s->float_exact && !isnan(rows[0])))
        return &s->leaf_tri[i];
    *tmp = ray__leaf_tri(s, i, rows, n);
    return tmp;
}

/*
** At commit (triangles.c): ray__triangles_rebuild builds the triangle
** BVH over the live slots, puts them in its leaf order and writes their
** float corners (RAY_OK, or RAY_ENOMEM or RAY_ECANCELED -- prog, NULL or
** the commit's progress, was cancelled -- with no triangle BVH, the scene
** left uncommitted); ray__triangles_live counts the slots it would build
** over; ray__triangles_refit fits the boxes and the float corners of the
** same tree to the vertices as they are now.
*/
int ray__triangles_rebuild(ray_scene *s, ray__progress *prog);
size_t ray__triangles_live(const ray_scene *s);
void ray__triangles_refit(ray_scene *s);

/*
** How the queries test triangles, for the tests and the bench (what
** accuracy costs): RAY__TRI_FILTERED, the float filter in front of the
** exact test (the default); RAY__TRI_EXACT, the exact test alone;
** RAY__TRI_FLOAT, the filter's float test as the verdict, with no bound
** (a float tracer: it leaks, and the hits are not the exact test's).
** ray__scene_set_filter_scale multiplies the filter's bound (1), so a
** test can show that half of it is not enough.  Both are read by the
** queries: set them before querying, as any setting (ray(7)).
*/
enum { RAY__TRI_FILTERED, RAY__TRI_EXACT, RAY__TRI_FLOAT };
void ray__scene_set_tri_mode(ray_scene *s, int mode);
void ray__scene_set_filter_scale(ray_scene *s, double scale);

/* Room for "more" triangles in the scene's tri_ids array. */
int ray__reserve_tris(ray_scene *s, size_t more);

/* ---------------------------------------------------- the kinds' dispatch */

/*
** What the scene does by kind (kinds.c), each a switch generated from the
** list of kinds (RAY__PRIM_KINDS, prim.h).
**
** ray__kind_class -- where a committed scene keeps geometry of a kind
** (the list's class column).
** ray__kind_counter -- the RAY_PRIM_* its tests count under.
** ray__prim_box -- the box of geometry p, in double (the BVH's float box
** is rounded outward from it); for the bounded kinds.
** ray__prim_intersect -- geometry i (of class BOUNDED or UNBOUNDED)
** against r, counted in qc->tests; fills *hit, with geom_id i and
** prim_id 0, on a hit.  A curved surface whose iteration failed, or
** user geometry whose callback broke its contract (a negative answer),
** is a miss, counted in qc->failures.
** ray__prim_candidate -- the same test for a query that wants the record
** of its nearest hit alone (or none, for any hit): 0 on a miss,
** RAY__HIT_FULL with *hit filled as ray__prim_intersect fills it, or
** RAY__HIT_T with hit->t alone, for a kind whose record can be filled
** later from t (a sphere, a plane: their t-only tests; the fill's success
** checked, so a t that could not be filled is a miss here as there).
** Same counts, same t, same hits and misses as ray__prim_intersect.
** ray__prim_fill -- the record of such a hit at t, as ray__prim_intersect
** would have filled it (the same formulas on the same t): 1, or 0 for a
** geometry whose kind never answers RAY__HIT_T (cannot happen).
** A sphere's texture coordinates are computed only for a query whose
** qc->uv (uv) is 1 or when its material reads them, else 0 (see
** ray__intersect).
*/
enum { RAY__HIT_FULL = 1, RAY__HIT_T = 2 };

typedef enum ray__class {
    RAY__CLASS_TRIANGLES,    /* in tri_bvh: query/leaf.h tests them inline */
    RAY__CLASS_BOUNDED,      /* in prim_bvh */
    RAY__CLASS_UNBOUNDED     /* in planes: tested on every ray */
} ray__class;

/*
** What one query counts and carries: tests by kind, the curved-surface
** tests that failed (iteration limit) and were taken as misses, filter
** calls; its gate (NULL: ungated, the fast path), whether it wants any
** hit (occluded) or the nearest, and while inside an instance the
** instance (its geom_id and record) through which candidates are seen;
** "stale" is set when an instance meets a child changed since the
** parent's commit.
*/
/* What one query counts: tests by kind, and the curved-surface and user
** tests that failed (iteration limit, a callback's invalid answer) and
** were taken as misses. */
typedef struct ray__counts {
    unsigned long long tests[RAY_PRIM_KINDS];
    unsigned kinds;          /* bit k set where tests[k] holds a count;
                                the others are not even zeroed, but
                                tests[RAY_PRIM_TRIANGLE] always is
                                (ray__count_tests) */
    unsigned long long failures;
    unsigned long long filter_calls;
    const struct ray__gate *gate;  /* the query layer's (query.h) */
    int any;
    int stale;
    unsigned inst_id;
    const ray__instance *inst;
    const ray_ray *world_ray;
    int uv;                  /* fill every sphere's (u, v): ray__intersect */
} ray__counts;

/* Count n tests of kind k (a RAY_PRIM_*) in qc: the first count of a
** kind starts its entry.  The triangles' hot loops add to
** tests[RAY_PRIM_TRIANGLE] directly, without the bit: a query zeroes that
** entry when it starts and add_counts reads it always, the others by
** the bits.  A query so zeroes two words, not the whole array, which was
** 1.5% of the Whitted render's instructions (callgrind, issue 35). */
static inline void ray__count_tests(ray__counts *qc, int k,
                                    unsigned long long n)
{
    unsigned bit = 1u << k;

    qc->tests[k] = ((qc->kinds & bit) ? qc->tests[k] : 0) + n;
    qc->kinds |= bit;
}

ray__class ray__kind_class(ray__kind kind);

/*
** For ray cones (trace.c), by kind, at a hit of geometry p of s (its
** owner; an instance's child in object space):
** ray__prim_uv_scale -- the surface's (u, v) per unit of length there,
** the isotropic estimate sqrt(|d(u, v)| / |dA|) of Akenine-Moller et al.
** (Ray Tracing Gems, 2019, chapter 20): plane, polygon 1 (their (u, v)
** are lengths); triangle sqrt((1/2) / area) (barycentrics); mesh with
** (s, t) its triangle's sqrt(st area / area), without 0; sphere
** 1 / (pi r sqrt(2 cos latitude)) (u = longitude / 2pi, v = latitude /
** pi), +Inf at a pole; every other kind 0: unknown, no filtering.
** ray__prim_curvature -- the surface's mean curvature there for the side
** its normal points to (convex > 0): sphere 1 / r, every other kind 0
** (flat, or unknown: a cone then reflects as off a flat mirror).
*/
double ray__prim_uv_scale(const ray_scene *s, const ray__prim *p,
                          const ray_hit *hit);

/* The (u, v) per unit length of triangle abc whose (u, v) span twice the
** area uv2: sqrt(uv area / area), the same estimate for a triangle's
** barycentrics (uv2 = 1) and a mesh's (s, t); 0 for a degenerate one (no
** filtering). */
static inline double ray__triangle_uv_scale(ray_vec3 a, ray_vec3 b,
                                            ray_vec3 c, double uv2)
{
    double q = uv2 / v3_length(v3_cross(v3_sub(b, a), v3_sub(c, a)));

    return q > 0 && q < HUGE_VAL ? sqrt(q) : 0.0;
}
double ray__prim_curvature(const ray_scene *s, const ray__prim *p,
                           const ray_hit *hit);
int ray__kind_counter(ray__kind kind);
void ray__prim_box(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                   ray_vec3 *hi);
int ray__prim_intersect(const ray_scene *s, unsigned i, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc);
int ray__prim_candidate(const ray_scene *s, unsigned i, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc);
int ray__prim_fill(const ray_scene *s, unsigned i, const ray_ray *r,
                   double t, int uv, ray_hit *hit);
/* ray__prim_candidate's answer for sphere i, with the ray's part of the
** test made once (ray__sphere_ray_init), and for plane i, uncounted and
** without the dispatch: for a query that tests a scene's few spheres and
** its planes one after another (query/traverse.h, analytic scenes).
** ray__sphere_candidate is for a sphere that ray__sphere_surely_missed
** did not rule out (it tests with ray__sphere_t_near). */
int ray__sphere_candidate(const ray_scene *s, unsigned i,
                          const ray__sphere_ray *sr, const ray_ray *r,
                          ray_hit *hit, int uv);
/* ray__plane_candidate: inline, in scene/candidate.h. */

/* ------------------------------------------------------------ instances */

/*
** An instance's record and transforms (instance.c); the query layer
** descends into its child (query/traverse.h).
** ray__instance_box -- its world box, from its child's box: 1, or 0
** when the transform maps the child beyond +-RAY__INSTANCE_REACH
** (2^1016), where a hit's point or error bound could overflow (such a
** transform is refused: ray_scene_add_instance, set_transform, commit).
** ray__instance_ray_to_object -- world ray r in the child's space: o' =
** L^-1 (o - c), d' = L^-1 d, the same interval (an affine map keeps
** ratios: t names the same point on both).
** ray__instance_to_world -- a hit of the child in object space as the
** world sees it: p and n transformed, p_err grown by the rounding of both
** transforms (instance.c explains the bound).
** ray__instance_normal -- a child's normal (a shading normal) in world
** space, unit.
*/
#define RAY__INSTANCE_REACH 0x1p1016
int ray__instance_box(ray__instance *in);
void ray__instance_to_world(const ray__instance *in, const ray_hit *obj,
                            ray_hit *world);
ray_vec3 ray__instance_normal(const ray__instance *in, ray_vec3 n);

/* A point of the child's space in the world's (L p + c), and back
** (L^-1 (q - c)). */
ray_vec3 ray__instance_point_to_world(const ray__instance *in, ray_vec3 p);

/* Inline, as the query's own arithmetic: every instance a ray enters
** moves it, and the call was 4% of a game's frame (bench/game.c,
** callgrind, issue 36).  inv row k applied to v. */
static inline double ray__instance_inv_dot(const ray__instance *in, int k,
                                           ray_vec3 v)
{
    return in->inv[k][0] * v.x + in->inv[k][1] * v.y + in->inv[k][2] * v.z;
}

static inline ray_vec3 ray__instance_point_to_object(const ray__instance *in,
                                                     ray_vec3 q)
{
    const double (*m)[4] = in->xfm.m;
    ray_vec3 o = v3(q.x - m[0][3], q.y - m[1][3], q.z - m[2][3]);

    return v3(ray__instance_inv_dot(in, 0, o), ray__instance_inv_dot(in, 1, o),
              ray__instance_inv_dot(in, 2, o));
}

static inline void ray__instance_ray_to_object(const ray__instance *in,
                                               const ray_ray *r,
                                               ray_ray *out)
{
    out->org = ray__instance_point_to_object(in, r->org);
    out->dir = v3(ray__instance_inv_dot(in, 0, r->dir),
                  ray__instance_inv_dot(in, 1, r->dir),
                  ray__instance_inv_dot(in, 2, r->dir));
    out->tmin = r->tmin;
    out->tmax = r->tmax;
}

/* The instance of s a hit came through, or NULL; and the scene that owns
** the geometry it names (s itself, or the instance's child).  Inline:
** the tracer asks three times a hit (issue 35). */
static inline const ray__instance *ray__hit_instance(const ray_scene *s,
                                                     const ray_hit *h)
{
    if (h->inst_id == RAY_INVALID_ID || h->inst_id >= s->n_prims)
        return NULL;
    return &s->instances[s->prims[h->inst_id].surface];
}

static inline const ray_scene *ray__hit_owner(const ray_scene *s,
                                              const ray_hit *h)
{
    const ray__instance *in = ray__hit_instance(s, h);

    return in != NULL ? in->child : s;
}

#endif /* RAY_SCENE_H */
