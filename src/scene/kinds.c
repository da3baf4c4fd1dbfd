/* SPDX-License-Identifier: MIT */
/*
** kinds.c -- what the scene does by kind of primitive, generated from the
** one list of kinds (RAY__PRIM_KINDS, prim.h): each dispatch below is a
** switch over ray__kind with a case for every kind and no default, each
** case calling the kind's own function (box_NAME, hit_NAME) or returning
** its column of the list.  The library is built with -Wswitch-enum, so a
** kind added to the list without them does not compile.
*/
#include "scene/candidate.h"

/* ray_stats.tests_by_kind holds RAY_PRIM_KINDS_MAX counters (ray.h). */
typedef char ray__counters_fit[RAY_PRIM_KINDS <= RAY_PRIM_KINDS_MAX ? 1 : -1];

/* ------------------------------------------------------------ the boxes */

static void box_SPHERE(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                       ray_vec3 *hi)
{
    (void)s;
    *lo = v3(p->a.x - p->radius, p->a.y - p->radius, p->a.z - p->radius);
    *hi = v3(p->a.x + p->radius, p->a.y + p->radius, p->a.z + p->radius);
}

/* Unbounded: the whole space (never asked: planes are not in a BVH). */
static void box_PLANE(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                      ray_vec3 *hi)
{
    (void)s;
    (void)p;
    *lo = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    *hi = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
}

/* The box of n points. */
static void points_box(const ray_vec3 *v, size_t n, ray_vec3 *lo,
                       ray_vec3 *hi)
{
    size_t i;

    *lo = *hi = v[0];
    for (i = 1; i < n; i++) {
        *lo = v3(fmin(lo->x, v[i].x), fmin(lo->y, v[i].y),
                 fmin(lo->z, v[i].z));
        *hi = v3(fmax(hi->x, v[i].x), fmax(hi->y, v[i].y),
                 fmax(hi->z, v[i].z));
    }
}

/* The box of triangle slots first .. first + count - 1 (never asked:
** triangles are boxed one by one for the triangle BVH, and only before
** commit reorders the slots). */
static void triangles_box(const ray_scene *s, const ray__prim *p,
                          ray_vec3 *lo, ray_vec3 *hi)
{
    ray_vec3 tlo, thi;
    size_t i;

    *lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    *hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (i = p->first; i < p->first + p->count; i++) {
        ray__tri t = ray__tri_of(s, i);
        points_box(&t.a, 3, &tlo, &thi);
        *lo = v3(fmin(lo->x, tlo.x), fmin(lo->y, tlo.y), fmin(lo->z, tlo.z));
        *hi = v3(fmax(hi->x, thi.x), fmax(hi->y, thi.y), fmax(hi->z, thi.z));
    }
}

static void box_TRIANGLE(const ray_scene *s, const ray__prim *p,
                         ray_vec3 *lo, ray_vec3 *hi)
{
    triangles_box(s, p, lo, hi);
}

static void box_MESH(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                     ray_vec3 *hi)
{
    triangles_box(s, p, lo, hi);
}

static void box_POLYGON(const ray_scene *s, const ray__prim *p,
                        ray_vec3 *lo, ray_vec3 *hi)
{
    points_box(s->verts + p->first, p->count, lo, hi);
}

/* The curved surfaces keep the box they were added with in a, b. */
static void stored_box(const ray__prim *p, ray_vec3 *lo, ray_vec3 *hi)
{
    *lo = p->a;
    *hi = p->b;
}

/* A shape (RAY__SHAPES, prim.h): the box its check gave, and its
** primitive on the parameters the scene keeps. */
#define SHAPE_FUNCTIONS(X, NAME, name, type, counted_as)                   \
    static void box_##NAME(const ray_scene *s, const ray__prim *p,          \
                           ray_vec3 *lo, ray_vec3 *hi)                      \
    {                                                                       \
        (void)s;                                                            \
        stored_box(p, lo, hi);                                              \
    }                                                                       \
    static int hit_##NAME(const ray_scene *s, const ray__prim *p,           \
                          const ray_ray *r, ray_hit *hit, ray__counts *qc)  \
    {                                                                       \
        (void)qc;                                                           \
        return ray_##name(r, &s->surfaces[p->surface].name, hit);          \
    }
RAY__SHAPES(SHAPE_FUNCTIONS, _)

static void box_TORUS(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                      ray_vec3 *hi)
{
    (void)s;
    stored_box(p, lo, hi);
}

static void box_IMPLICIT(const ray_scene *s, const ray__prim *p,
                         ray_vec3 *lo, ray_vec3 *hi)
{
    (void)s;
    stored_box(p, lo, hi);
}

static void box_PARAMETRIC(const ray_scene *s, const ray__prim *p,
                           ray_vec3 *lo, ray_vec3 *hi)
{
    (void)s;
    stored_box(p, lo, hi);
}

static void box_BEZIER(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                       ray_vec3 *hi)
{
    (void)s;
    stored_box(p, lo, hi);
}

/* An instance: its world box, taken at commit from its child's. */
static void box_INSTANCE(const ray_scene *s, const ray__prim *p,
                         ray_vec3 *lo, ray_vec3 *hi)
{
    *lo = s->instances[p->surface].lo;
    *hi = s->instances[p->surface].hi;
}

/* User geometry: the box its bounds callback gave when it was added
** (ray__user_box, which a scene that refits would call here instead). */
static void box_USER(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                     ray_vec3 *hi)
{
    (void)s;
    stored_box(p, lo, hi);
}

/* ----------------------------------------------------- the intersections */

/*
** Fill a sphere's (u, v) -- an atan2 and an acos, the dearest part of its
** record?  Always for ray_intersect (uv 1); in a render (uv 0) only when
** the sphere's own material reads them (RAY_EFFECT_TEXTURE): the effect
** analysis of API-NOTES 14, per material.
*/
static int sphere_uv(const ray_scene *s, const ray__prim *p, int uv)
{
    return uv || (p->material < s->n_materials &&
                  (s->materials[p->material].effects & RAY_EFFECT_TEXTURE));
}

/* ray_sphere, its (u, v) only where they are read (sphere_uv). */
static int hit_SPHERE(const ray_scene *s, const ray__prim *p,
                      const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    double t;

    if (!ray__sphere_t(r, p->a, p->radius, &t))
        return 0;
    return ray__sphere_fill(r, p->a, p->radius, t, sphere_uv(s, p, qc->uv),
                            hit);
}

static int hit_PLANE(const ray_scene *s, const ray__prim *p,
                     const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    (void)s;
    return ray_plane(r, p->a, p->b, hit);
}

/* Triangles are in the triangle BVH, which the queries test inline, so
** their geometry is never asked (and after commit its slots are
** reordered): a miss. */
static int in_triangle_bvh(void)
{
    return 0;
}

static int hit_TRIANGLE(const ray_scene *s, const ray__prim *p,
                        const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    (void)s, (void)p, (void)r, (void)hit;
    return in_triangle_bvh();
}

static int hit_MESH(const ray_scene *s, const ray__prim *p,
                    const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    (void)s, (void)p, (void)r, (void)hit;
    return in_triangle_bvh();
}

static int hit_POLYGON(const ray_scene *s, const ray__prim *p,
                       const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    /* ray_polygon, its plane made when the polygon was added (p->a the
    ** centroid, p->b the Newell normal). */
    return ray__polygon_at(r, s->verts + p->first, p->count, p->a, p->b, hit);
}

static int hit_TORUS(const ray_scene *s, const ray__prim *p,
                     const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    return ray_torus(r, &s->surfaces[p->surface].torus, hit);
}

static int hit_IMPLICIT(const ray_scene *s, const ray__prim *p,
                        const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    return ray_implicit(r, &s->surfaces[p->surface].implicit, hit);
}

static int hit_PARAMETRIC(const ray_scene *s, const ray__prim *p,
                          const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    return ray_parametric(r, &s->surfaces[p->surface].parametric, hit);
}

/* A Bezier patch from its control points in the scene. */
static int hit_BEZIER(const ray_scene *s, const ray__prim *p,
                      const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    ray_parametric_surface ps;

    if (ray_bezier_surface(s->verts + p->first, &ps) != RAY_OK)
        return 0;          /* cannot happen: checked when added */
    return ray_parametric(r, &ps, hit);
}

/* Instances are the query layer's: meeting one, a query moves the ray
** into its child's space and descends into the child's trees itself
** (query/traverse.h), so it never asks here: a miss, as for triangles. */
static int query_descends(void)
{
    return 0;
}

static int hit_INSTANCE(const ray_scene *s, const ray__prim *p,
                        const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    (void)s, (void)p, (void)r, (void)hit;
    return query_descends();
}

/* The callback's answer, checked (user.c): a hit that breaks the
** contract is -1, a failure ray__prim_intersect counts. */
static int hit_USER(const ray_scene *s, const ray__prim *p,
                    const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    return ray__user_hit(&s->surfaces[p->surface].user, r, hit);
}

/* ------------------------------------------- candidates and deferred fills */

/*
** cand_NAME: hit_NAME for a query that fills only its nearest hit's
** record (ray__prim_candidate): RAY__HIT_T with hit->t alone where the
** kind can fill later (fill_NAME), else hit_NAME's answer (1 is
** RAY__HIT_FULL).  A sphere or plane hit whose fill might fail (numbers
** near overflow, a point rounding onto the centre) is filled now, as
** ray_sphere / ray_plane fill it, so a failed fill stays the miss it is
** there.
*/
int ray__sphere_candidate(const ray_scene *s, unsigned i,
                          const ray__sphere_ray *sr, const ray_ray *r,
                          ray_hit *hit, int uv)
{
    const ray__prim *p = &s->prims[i];
    double t;

    if (!ray__sphere_t_near(sr, r, p->a, p->radius, &t))
        return 0;
    if (!ray__sphere_fills(r, p->a, p->radius, t)) {
        if (!ray__sphere_fill(r, p->a, p->radius, t, sphere_uv(s, p, uv),
                              hit))
            return 0;
        return ray__full_record(i, hit);
    }
    hit->t = t;
    return RAY__HIT_T;
}

static int cand_SPHERE(const ray_scene *s, const ray__prim *p,
                       const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    ray__sphere_ray sr;

    if (!ray__sphere_ray_init(r, &sr) ||
        ray__sphere_surely_missed(v3_sub(r->org, p->a), sr.d, sr.a,
                                  p->radius))
        return 0;
    return ray__sphere_candidate(s, (unsigned)(p - s->prims), &sr, r, hit,
                                 qc->uv);
}

static int fill_SPHERE(const ray_scene *s, const ray__prim *p,
                       const ray_ray *r, double t, int uv, ray_hit *hit)
{
    return ray__sphere_fill(r, p->a, p->radius, t, sphere_uv(s, p, uv), hit);
}

static int cand_PLANE(const ray_scene *s, const ray__prim *p,
                      const ray_ray *r, ray_hit *hit, ray__counts *qc)
{
    (void)qc;
    return ray__plane_candidate(s, (unsigned)(p - s->prims), r, hit);
}

static int fill_PLANE(const ray_scene *s, const ray__prim *p,
                      const ray_ray *r, double t, int uv, ray_hit *hit)
{
    (void)s;
    (void)uv;                    /* cheap, and they decide the hit */
    return ray__plane_fill_prim(p, r, t, hit);
}

/* The other kinds fill their record on every candidate: hit_NAME. */
#define EAGER_CANDIDATE(NAME)                                              \
    static int cand_##NAME(const ray_scene *s, const ray__prim *p,          \
                           const ray_ray *r, ray_hit *hit,                  \
                           ray__counts *qc)                                 \
    {                                                                       \
        int ok = hit_##NAME(s, p, r, hit, qc);                              \
        return ok > 0 ? RAY__HIT_FULL : ok;                                 \
    }                                                                       \
    static int fill_##NAME(const ray_scene *s, const ray__prim *p,          \
                           const ray_ray *r, double t, int uv,              \
                           ray_hit *hit)                                    \
    {                                                                       \
        (void)s, (void)p, (void)r, (void)t, (void)uv, (void)hit;            \
        return 0;                    /* never deferred */                   \
    }
EAGER_CANDIDATE(TRIANGLE)
EAGER_CANDIDATE(MESH)
EAGER_CANDIDATE(POLYGON)
EAGER_CANDIDATE(TORUS)
EAGER_CANDIDATE(IMPLICIT)
EAGER_CANDIDATE(PARAMETRIC)
EAGER_CANDIDATE(BEZIER)
EAGER_CANDIDATE(INSTANCE)
EAGER_CANDIDATE(USER)
#define SHAPE_CANDIDATE(X, NAME, name, type, counted_as) EAGER_CANDIDATE(NAME)
RAY__SHAPES(SHAPE_CANDIDATE, _)
#undef SHAPE_CANDIDATE

/* ---------------------------------------------------------- the dispatch */

ray__class ray__kind_class(ray__kind kind)
{
    switch (kind) {
#define CLASS_OF(name, counted_as, class)                                  \
    case RAY__KIND_##name:                                                 \
        return RAY__CLASS_##class;
        RAY__PRIM_KINDS(CLASS_OF)
#undef CLASS_OF
    }
    return RAY__CLASS_BOUNDED;      /* not a ray__kind: cannot happen */
}

/* Inline here, where the intersection counts its tests. */
static inline int counter_of(ray__kind kind)
{
    switch (kind) {
#define COUNTER_OF(name, counted_as, class)                                \
    case RAY__KIND_##name:                                                 \
        return counted_as;
        RAY__PRIM_KINDS(COUNTER_OF)
#undef COUNTER_OF
    }
    return RAY_PRIM_TRIANGLE;       /* not a ray__kind: cannot happen */
}

int ray__kind_counter(ray__kind kind)
{
    return counter_of(kind);
}

void ray__prim_box(const ray_scene *s, const ray__prim *p, ray_vec3 *lo,
                   ray_vec3 *hi)
{
    switch (p->kind) {
#define BOX_OF(name, counted_as, class)                                    \
    case RAY__KIND_##name:                                                 \
        box_##name(s, p, lo, hi);                                          \
        break;
        RAY__PRIM_KINDS(BOX_OF)
#undef BOX_OF
    }
}

/* The answer "ok" of geometry i's test, as the queries see it: a failure
** (negative) counted and a miss; the ids of a full record set. */
static inline int prim_answer(unsigned i, int ok, ray_hit *hit,
                              ray__counts *qc)
{
    if (ok < 0) {
        qc->failures++;
        return 0;
    }
    if (ok == RAY__HIT_FULL)
        ray__full_record(i, hit);
    return ok;
}

int ray__prim_intersect(const ray_scene *s, unsigned i, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc)
{
    const ray__prim *p = &s->prims[i];
    int ok = 0;

    ray__count_tests(qc, counter_of(p->kind), 1);
    switch (p->kind) {
#define HIT_OF(name, counted_as, class)                                    \
    case RAY__KIND_##name:                                                 \
        ok = hit_##name(s, p, r, hit, qc);                                 \
        break;
        RAY__PRIM_KINDS(HIT_OF)
#undef HIT_OF
    }
    return prim_answer(i, ok > 0 ? RAY__HIT_FULL : ok, hit, qc);
}

int ray__prim_candidate(const ray_scene *s, unsigned i, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc)
{
    const ray__prim *p = &s->prims[i];
    int ok = 0;

    ray__count_tests(qc, counter_of(p->kind), 1);
    switch (p->kind) {
#define CAND_OF(name, counted_as, class)                                   \
    case RAY__KIND_##name:                                                 \
        ok = cand_##name(s, p, r, hit, qc);                                \
        break;
        RAY__PRIM_KINDS(CAND_OF)
#undef CAND_OF
    }
    return prim_answer(i, ok, hit, qc);
}

int ray__prim_fill(const ray_scene *s, unsigned i, const ray_ray *r,
                   double t, int uv, ray_hit *hit)
{
    const ray__prim *p = &s->prims[i];
    int ok = 0;

    switch (p->kind) {
#define FILL_OF(name, counted_as, class)                                   \
    case RAY__KIND_##name:                                                 \
        ok = fill_##name(s, p, r, t, uv, hit);                             \
        break;
        RAY__PRIM_KINDS(FILL_OF)
#undef FILL_OF
    }
    if (ok)                      /* a sphere or a plane */
        ray__full_record(i, hit);
    return ok;
}

/* ------------------------------------------------------ ray cones' data */

/* A sphere's (u, v) per unit length at latitude v pi - pi/2 (ray_sphere):
** du = dphi / 2pi over r cos(lat) dphi, dv = dlat / pi over r dlat, so
** the area ratio is 1 / (2 pi^2 r^2 cos(lat)); cos(lat) = sin(pi v). */
static double sphere_uv_scale(const ray__prim *p, const ray_hit *hit)
{
    double c = sin(RAY__PI * hit->v);

    if (!(c > 0))
        return HUGE_VAL;              /* a pole: u's footprint unbounded */
    return 1.0 / (RAY__PI * p->radius * sqrt(2.0 * c));
}

double ray__prim_uv_scale(const ray_scene *s, const ray__prim *p,
                          const ray_hit *hit)
{
    const ray__mesh *m;

    switch (p->kind) {
    case RAY__KIND_SPHERE:
        return sphere_uv_scale(p, hit);
    case RAY__KIND_PLANE:
    case RAY__KIND_POLYGON:
        return 1.0;                   /* ray_plane's tangent-axis lengths */
    case RAY__KIND_TRIANGLE:          /* barycentrics: half a unit square */
        return ray__triangle_uv_scale(p->a, p->b, p->c, 1.0);
    case RAY__KIND_MESH:
        m = &s->meshes[p->mesh];
        return m->uv_scale != NULL && hit->prim_id < m->n_tris
                   ? m->uv_scale[hit->prim_id] : 0.0;
    case RAY__KIND_TORUS:
    case RAY__KIND_IMPLICIT:
    case RAY__KIND_PARAMETRIC:
    case RAY__KIND_BEZIER:
    case RAY__KIND_INSTANCE:
    case RAY__KIND_USER:
#define UV_SCALE_UNKNOWN(X, NAME, name, type, counted_as) \
    case RAY__KIND_##NAME:
        RAY__SHAPES(UV_SCALE_UNKNOWN, _)
#undef UV_SCALE_UNKNOWN
        return 0.0;
    }
    return 0.0;                       /* not a ray__kind: cannot happen */
}

double ray__prim_curvature(const ray_scene *s, const ray__prim *p,
                           const ray_hit *hit)
{
    (void)s;
    (void)hit;
    switch (p->kind) {
    case RAY__KIND_SPHERE:
        return 1.0 / p->radius;
    case RAY__KIND_PLANE:
    case RAY__KIND_POLYGON:
    case RAY__KIND_TRIANGLE:
        return 0.0;                   /* flat */
    case RAY__KIND_MESH:              /* no curvature data: as flat */
    case RAY__KIND_TORUS:
    case RAY__KIND_IMPLICIT:
    case RAY__KIND_PARAMETRIC:
    case RAY__KIND_BEZIER:
    case RAY__KIND_INSTANCE:
    case RAY__KIND_USER:
#define CURVATURE_UNKNOWN(X, NAME, name, type, counted_as) \
    case RAY__KIND_##NAME:
        RAY__SHAPES(CURVATURE_UNKNOWN, _)
#undef CURVATURE_UNKNOWN
        return 0.0;
    }
    return 0.0;                       /* not a ray__kind: cannot happen */
}
