/* SPDX-License-Identifier: MIT */
/*
** scene.h -- the scene: its records, struct ray_scene, its allocation
** helpers and error messages, the per-kind dispatch (kinds.c) and the
** queries (intersect.c over traverse.h).
*/
#ifndef RAY_SCENE_H
#define RAY_SCENE_H

#include "bvh.h"

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
** centre; plane: a = point, b = unit normal; triangle and mesh: tris[first
** .. first+count-1] of the scene (until commit reorders them), and for a
** mesh meshes[mesh]; polygon: verts[first .. first+count-1]; torus,
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

/* A light as added, with the unit vector every sample of it needs
** computed once when it is added: the direction toward a directional
** light (-direction) or the emitting normal of a rect light
** (edge1 x edge2); unused by the other kinds. */
typedef struct ray__light {
    ray_light desc;
    ray_vec3 axis;
} ray__light;

struct ray_scene {
    ray__allocator alloc;    /* the user's, or libc's */
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
*/
typedef enum ray__class {
    RAY__CLASS_TRIANGLES,    /* in tri_bvh: traverse.h tests them inline */
    RAY__CLASS_BOUNDED,      /* in prim_bvh */
    RAY__CLASS_UNBOUNDED     /* in planes: tested on every ray */
} ray__class;

/* What one query counts: tests by kind, and the curved-surface and user
** tests that failed (iteration limit, a callback's invalid answer) and
** were taken as misses. */
typedef struct ray__counts {
    unsigned long long tests[RAY_PRIM_KINDS];
    unsigned long long failures;
} ray__counts;

ray__class ray__kind_class(ray__kind kind);
int ray__kind_counter(ray__kind kind);
void ray__prim_box(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                   ray_vec3 *hi);
int ray__prim_intersect(const ray_scene *s, unsigned i, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc);

/* ------------------------------------------------------------ the queries */

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

#endif /* RAY_SCENE_H */
