/* SPDX-License-Identifier: MIT */
/*
** shapekit.h -- what the shape-query suites share (check_sweep.c,
** check_overlap.c): a mixed scene of every kind the sweeps and overlaps
** answer exactly, and its pieces in long double -- each a convex set
** whose signed distance to a point or a segment the tests compute on
** their own (ldgeom.h), so that a brute force over every piece is the
** reference.  Header-only, every function static.
*/
#ifndef RAY_SHAPEKIT_H
#define RAY_SHAPEKIT_H

#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"
#include "ldgeom.h"

/* A convex piece of the scene: a triangle, a sphere, a capsule, a plane
** (two-sided) or an oriented box (solid), with the ids that name it. */
enum { PIECE_TRI, PIECE_SPHERE, PIECE_CAPSULE, PIECE_PLANE, PIECE_BOX,
       PIECE_PARA };

typedef struct piece {
    int kind;
    lvec a, b, c;                /* corners; centre; segment; point, n */
    ld R;
    ray_box_params box;
    lvec corner[8];              /* a parallelepiped's: bit k, +e_k */
    lvec centre;                 /* of a bounding sphere ... */
    ld reach;                    /* ... of this radius (planes: +Inf) */
    unsigned geom_id, prim_id, inst_id;
} piece;

typedef struct kit {
    ray_scene *s;
    piece *p;
    size_t n, cap;
    ray_vec3 o;
} kit;

static inline void kit_push(kit *k, piece pc)
{
    if (k->n == k->cap) {
        k->cap = k->cap ? 2 * k->cap : 64;
        k->p = realloc(k->p, k->cap * sizeof *k->p);
        ck_assert_ptr_nonnull(k->p);
    }
    k->p[k->n++] = pc;
}

static inline piece kit_tri(lvec a, lvec b, lvec c, unsigned g, unsigned i)
{
    piece p;

    memset(&p, 0, sizeof p);
    p.inst_id = RAY_INVALID_ID;
    p.kind = PIECE_TRI;
    p.a = a;
    p.b = b;
    p.c = c;
    p.centre = lscale(ladd(ladd(a, b), c), 1.0L / 3);
    p.reach = fmaxl(ldist(p.centre, a), fmaxl(ldist(p.centre, b),
                                              ldist(p.centre, c)));
    p.geom_id = g;
    p.prim_id = i;
    return p;
}

/* A mesh's triangles as pieces and as geometry g of the scene. */
static inline void kit_mesh(kit *k, const hc_mesh *h, unsigned g)
{
    ray_mesh m = hc_ray_mesh(h);
    unsigned id;
    size_t i;

    ck_assert_int_eq(ray_scene_add_mesh(k->s, &m, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_uint_eq(id, g);
    for (i = 0; i < h->nt; i++)
        kit_push(k, kit_tri(lv(h->v[h->idx[3 * i]]),
                            lv(h->v[h->idx[3 * i + 1]]),
                            lv(h->v[h->idx[3 * i + 2]]), g, (unsigned)i));
}

/* The box's frame and half-extents in long double (ref_box_frame). */
static inline void kit_box_frame(const ray_box_params *b, lvec e[3], ld h[3])
{
    ref_box_frame(b, e);
    h[0] = (ld)b->half_extents.x;
    h[1] = (ld)b->half_extents.y;
    h[2] = (ld)b->half_extents.z;
}

/* The signed distance from x to a solid box (negative inside): outside,
** to its nearest surface point; inside, minus the distance to the
** nearest face. */
static inline ld kit_box_signed(const ray_box_params *b, lvec x)
{
    lvec e[3], rel = lsub(x, lv(b->center));
    ld h[3], o, out = 0, in = HUGE_VALL;
    int k, inside = 1;

    kit_box_frame(b, e, h);
    for (k = 0; k < 3; k++) {
        o = fabsl(ldot(rel, e[k])) - h[k];
        if (o > 0) {
            inside = 0;
            out += o * o;
        }
        if (-o < in)
            in = -o;
    }
    return inside ? -in : sqrtl(out);
}

/* The corners of face f of a parallelepiped (as box_face in the
** library's sweep.c orders them, which does not matter here). */
static inline void kit_para_face(const piece *p, int f, lvec q[4])
{
    int axis = f / 2, base = f % 2 ? 1 << axis : 0;
    int j = 1 << ((axis + 1) % 3), l = 1 << ((axis + 2) % 3);

    q[0] = p->corner[base];
    q[1] = p->corner[base | j];
    q[2] = p->corner[base | j | l];
    q[3] = p->corner[base | l];
}

/* The signed distance from the segment [x0, x1] (a point: x0 == x1) to
** a solid parallelepiped: the least distance to its 12 triangles, and
** negative (minus the nearest face's distance) for a point inside:
** its coordinates along the half-edges within [-1, 1] (Cramer). */
static inline ld kit_para_point(const piece *p, lvec x)
{
    lvec c = lscale(ladd(p->corner[0], p->corner[7]), 0.5L), e[3], q[4];
    ld best = HUGE_VALL, vol;
    int f, k, inside = 1;

    e[0] = lscale(lsub(p->corner[1], p->corner[0]), 0.5L);
    e[1] = lscale(lsub(p->corner[2], p->corner[0]), 0.5L);
    e[2] = lscale(lsub(p->corner[4], p->corner[0]), 0.5L);
    vol = ldot(e[0], lcross(e[1], e[2]));
    for (k = 0; k < 3; k++)
        inside &= fabsl(ldot(lsub(x, c), lcross(e[(k + 1) % 3],
                                                e[(k + 2) % 3])) / vol) <= 1;
    for (f = 0; f < 6; f++) {
        kit_para_face(p, f, q);
        best = fminl(best, ldist(ref_triangle(x, q[0], q[1], q[2]), x));
        best = fminl(best, ldist(ref_triangle(x, q[0], q[2], q[3]), x));
    }
    return inside ? -best : best;
}

static inline ld kit_para_segment(const piece *p, lvec x0, lvec x1)
{
    ld lo = 0, hi = 1, best;
    lvec q[4];
    int k, f;

    for (k = 0; k < 80; k++) {
        ld a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3;
        if (kit_para_point(p, ladd(x0, lscale(lsub(x1, x0), a))) <
            kit_para_point(p, ladd(x0, lscale(lsub(x1, x0), b))))
            hi = b;
        else
            lo = a;
    }
    best = kit_para_point(p, ladd(x0, lscale(lsub(x1, x0), (lo + hi) / 2)));
    best = fminl(best, fminl(kit_para_point(p, x0), kit_para_point(p, x1)));
    if (best < 0 || ldist(x0, x1) == 0)
        return best;
    for (f = 0; f < 6; f++) {
        kit_para_face(p, f, q);
        best = fminl(best, ref_segment_triangle(x0, x1, q[0], q[1], q[2]));
        best = fminl(best, ref_segment_triangle(x0, x1, q[0], q[2], q[3]));
    }
    return best;
}

/*
** Piece p's signed distance to the core: the point x0 (x1 == x0) or the
** segment [x0, x1]: negative inside a solid (for a segment, the least
** of its points' signed distances: convex along it, by ternary search).
*/
static inline ld kit_distance(const piece *p, lvec x0, lvec x1)
{
    int point = ldist(x0, x1) == 0;

    switch (p->kind) {
    case PIECE_TRI:
        return point ? ldist(ref_triangle(x0, p->a, p->b, p->c), x0)
                     : ref_segment_triangle(x0, x1, p->a, p->b, p->c);
    case PIECE_SPHERE:
        return ldist(ref_segment(p->a, x0, x1), p->a) - p->R;
    case PIECE_CAPSULE:
        return (point ? ldist(ref_segment(x0, p->a, p->b), x0)
                      : ref_segments(x0, x1, p->a, p->b)) - p->R;
    case PIECE_PLANE: {
        ld h0 = ldot(lsub(x0, p->a), p->b), h1 = ldot(lsub(x1, p->a), p->b);
        if ((h0 < 0) != (h1 < 0))
            return 0;
        return fminl(fabsl(h0), fabsl(h1));
    }
    case PIECE_PARA:
        return point ? kit_para_point(p, x0) : kit_para_segment(p, x0, x1);
    default: {
        ld lo = 0, hi = 1, best;
        int k;
        if (point)
            return kit_box_signed(&p->box, x0);
        for (k = 0; k < 80; k++) {
            ld a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3;
            if (kit_box_signed(&p->box, ladd(x0, lscale(lsub(x1, x0), a))) <
                kit_box_signed(&p->box, ladd(x0, lscale(lsub(x1, x0), b))))
                hi = b;
            else
                lo = a;
        }
        best = kit_box_signed(&p->box, ladd(x0, lscale(lsub(x1, x0),
                                                       (lo + hi) / 2)));
        best = fminl(best, fminl(kit_box_signed(&p->box, x0),
                                 kit_box_signed(&p->box, x1)));
        return best;
    }
    }
}

/*
** The mixed scene, moved by o: geometry
**   0  an icosphere mesh of radius 2 at o (level 1: 80 triangles),
**   1  a sphere of radius 1 at o + (5, 0, 0),
**   2  an oriented box at o + (0, 4, -3),
**   3  a capsule from o + (-3, -1, -2) to o + (-1, 1, -4), radius 0.6,
**   4  the L-shaped (concave) hexagon in the plane x - z = const,
**   5  the cube mesh [-1, 1]^3 + o + (6, 5, 4),
**   6  three lone triangles (6, 7, 8),
**   9  the plane through o + (0, -7, 0) with normal (0.1, 1, 0.2)
**      (only when "plane" is 1),
** all within 10 of o but the plane.  The L's pieces are its four
** triangles (its region is their union).
*/
static const double kit_lone[3][3][3] = {
    {{2, -2, 3}, {5, -1.5, 3.5}, {3, -1.9, 2.5}},
    {{-6, -1, 4}, {-2, -0.5, 4.2}, {-6, -0.3, 4.1}},
    {{1, 6, 1}, {3, 7, 3}, {0, 8, 2}}};
static const double kit_l_uv[6][2] = {{0, 0}, {2, 0}, {2, 1},
                                      {1, 1}, {1, 2}, {0, 2}};
static const int kit_l_tris[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4},
                                     {0, 4, 5}};

static inline ray_vec3 kit_at(ray_vec3 o, double x, double y, double z)
{
    return vec(o.x + x, o.y + y, o.z + z);
}

static inline void kit_build(kit *k, ray_vec3 o, int plane)
{
    hc_mesh ball = hc_icosphere(o, 1), cube = hc_cube(kit_at(o, 6, 5, 4));
    ray_box_params box;
    ray_capsule_params cap;
    ray_vec3 poly[6], sc = kit_at(o, 5, 0, 0);
    piece p;
    unsigned id;
    int i;

    memset(k, 0, sizeof *k);
    k->o = o;
    ck_assert_int_eq(ray_scene_new(&k->s, NULL, NULL), RAY_OK);
    kit_mesh(k, &ball, 0);
    ck_assert_int_eq(ray_scene_add_sphere(k->s, sc, 1, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    memset(&p, 0, sizeof p);
    p.inst_id = RAY_INVALID_ID;
    p.kind = PIECE_SPHERE;
    p.a = p.centre = lv(sc);
    p.R = p.reach = 1;
    p.geom_id = id;
    kit_push(k, p);
    box.center = kit_at(o, 0, 4, -3);
    box.half_extents = vec(1, 0.5, 0.75);
    box.axis_x = vec(1, 1, 0);
    box.axis_y = vec(-1, 1, 1);
    ck_assert_int_eq(ray_scene_add_box(k->s, &box, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    memset(&p, 0, sizeof p);
    p.inst_id = RAY_INVALID_ID;
    p.kind = PIECE_BOX;
    p.box = box;
    p.centre = lv(box.center);
    p.reach = 1.5L;
    p.geom_id = id;
    kit_push(k, p);
    cap.a = kit_at(o, -3, -1, -2);
    cap.b = kit_at(o, -1, 1, -4);
    cap.radius = 0.6;
    ck_assert_int_eq(ray_scene_add_capsule(k->s, &cap, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    memset(&p, 0, sizeof p);
    p.inst_id = RAY_INVALID_ID;
    p.kind = PIECE_CAPSULE;
    p.a = lv(cap.a);
    p.b = lv(cap.b);
    p.R = 0.6L;
    p.centre = lscale(ladd(p.a, p.b), 0.5L);
    p.reach = ldist(p.a, p.b) / 2 + p.R;
    p.geom_id = id;
    kit_push(k, p);
    for (i = 0; i < 6; i++)
        poly[i] = kit_at(o, 3 + kit_l_uv[i][0], 2 + kit_l_uv[i][1],
                         -2 + kit_l_uv[i][0]);
    ck_assert_int_eq(ray_scene_add_polygon(k->s, poly, 6, RAY_NO_MATERIAL,
                                           &id), RAY_OK);
    for (i = 0; i < 4; i++)
        kit_push(k, kit_tri(lv(poly[kit_l_tris[i][0]]),
                            lv(poly[kit_l_tris[i][1]]),
                            lv(poly[kit_l_tris[i][2]]), id, 0));
    kit_mesh(k, &cube, 5);
    for (i = 0; i < 3; i++) {
        ray_vec3 v[3];
        int j;
        for (j = 0; j < 3; j++)
            v[j] = kit_at(o, kit_lone[i][j][0], kit_lone[i][j][1],
                          kit_lone[i][j][2]);
        ck_assert_int_eq(ray_scene_add_triangle(k->s, v[0], v[1], v[2],
                                                RAY_NO_MATERIAL, &id),
                         RAY_OK);
        kit_push(k, kit_tri(lv(v[0]), lv(v[1]), lv(v[2]), id, 0));
    }
    if (plane) {
        ray_vec3 pp = kit_at(o, 0, -7, 0), pn = vec(0.1, 1, 0.2);
        ck_assert_int_eq(ray_scene_add_plane(k->s, pp, pn, RAY_NO_MATERIAL,
                                             &id), RAY_OK);
        memset(&p, 0, sizeof p);
    p.inst_id = RAY_INVALID_ID;
        p.kind = PIECE_PLANE;
        p.a = lv(pp);
        p.b = lunit(lv(pn));
        p.reach = HUGE_VALL;
        p.geom_id = id;
        kit_push(k, p);
    }
    ck_assert_int_eq(ray_scene_commit(k->s), RAY_OK);
    hc_mesh_free(&ball);
    hc_mesh_free(&cube);
}

/* Point v through t, in long double. */
static inline lvec kit_map_point(const ray_transform *t, lvec v)
{
    return lv3((ld)t->m[0][0] * v.x + (ld)t->m[0][1] * v.y +
                   (ld)t->m[0][2] * v.z + (ld)t->m[0][3],
               (ld)t->m[1][0] * v.x + (ld)t->m[1][1] * v.y +
                   (ld)t->m[1][2] * v.z + (ld)t->m[1][3],
               (ld)t->m[2][0] * v.x + (ld)t->m[2][1] * v.y +
                   (ld)t->m[2][2] * v.z + (ld)t->m[2][3]);
}

/* A rotation about a random axis times diag(s), with a shear of up to
** "shear" and a reflection every third time; at "at". */
static inline void kit_affine(rng *g, int k, double shear, ray_vec3 s, ray_vec3 at,
                   ray_transform *t)
{
    ray_vec3 ax = rng_dir(g);
    double th = rng_range(g, 0, 6.283185307179586), c = cos(th), sn = sin(th);
    double v = 1 - c, q[3][3], sc[3];
    int i, j;

    q[0][0] = c + ax.x * ax.x * v;
    q[0][1] = ax.x * ax.y * v - ax.z * sn;
    q[0][2] = ax.x * ax.z * v + ax.y * sn;
    q[1][0] = ax.y * ax.x * v + ax.z * sn;
    q[1][1] = c + ax.y * ax.y * v;
    q[1][2] = ax.y * ax.z * v - ax.x * sn;
    q[2][0] = ax.z * ax.x * v - ax.y * sn;
    q[2][1] = ax.z * ax.y * v + ax.x * sn;
    q[2][2] = c + ax.z * ax.z * v;
    sc[0] = s.x;
    sc[1] = s.y;
    sc[2] = s.z;
    if (k % 3 == 0)
        sc[0] = -sc[0];
    ray_transform_identity(t);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            t->m[i][j] = q[i][j] * sc[j];
    t->m[0][1] += shear * rng_range(g, -1, 1);
    t->m[2][0] += shear * rng_range(g, -1, 1);
    t->m[0][3] = at.x;
    t->m[1][3] = at.y;
    t->m[2][3] = at.z;
}

/*
** The instanced world of both suites' instance tests: 8 placements of a
** child of a mesh (an icosahedron), a box and the L polygon under random
** affine maps (scales 0.4 to 2.5 per axis, shears, reflections), and 4
** of a child of a sphere and a capsule under similarities (a rotation, a
** uniform scale, a reflection); k gets every piece taken to world space
** in long double.  child[0] and child[1] are the two children, for the
** caller to free after kit_free(k).
*/
static inline void kit_build_instanced(kit *k, rng *g, ray_scene *child[2])
{
    hc_mesh ico = hc_icosphere(vec(0, 0, 0), 0);
    ray_box_params box;
    ray_capsule_params cap;
    ray_vec3 l[6];
    ray_mesh m = hc_ray_mesh(&ico);
    int i;
    size_t t;

    box.center = vec(3, 0, 0);
    box.half_extents = vec(0.5, 0.8, 0.3);
    box.axis_x = vec(1, 0.5, 0);
    box.axis_y = vec(0, 1, 1);
    for (i = 0; i < 6; i++)
        l[i] = vec(-4 + kit_l_uv[i][0], kit_l_uv[i][1], 0.5 * kit_l_uv[i][1]);
    cap.a = vec(2, -1, 0);
    cap.b = vec(3, 1, 0.5);
    cap.radius = 0.4;
    ck_assert_int_eq(ray_scene_new(&child[0], NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child[0], &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(child[0], &box, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(child[0], l, 6, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child[0]), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&child[1], NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child[1], vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(child[1], &cap, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child[1]), RAY_OK);
    memset(k, 0, sizeof *k);
    ck_assert_int_eq(ray_scene_new(&k->s, NULL, NULL), RAY_OK);
    for (i = 0; i < 12; i++) {
        ray_transform xf;
        unsigned id;
        piece p;
        lvec e[3];
        ld h[3], sc = 1;
        int c;
        ray_vec3 at = rng_point(g, -12, 12);
        if (i < 8)
            kit_affine(g, i, 0.4, rng_point(g, 0.4, 2.5), at, &xf);
        else {
            sc = (ld)rng_range(g, 0.5, 2);
            kit_affine(g, i, 0, vec((double)sc, (double)sc, (double)sc), at, &xf);
        }
        ck_assert_int_eq(ray_scene_add_instance(k->s, child[i < 8 ? 0 : 1], &xf, &id), RAY_OK);
        if (i >= 8) {
            memset(&p, 0, sizeof p);
            p.kind = PIECE_SPHERE;
            p.a = p.centre = kit_map_point(&xf, lv3(0, 0, 0));
            p.R = p.reach = sc;
            p.geom_id = 0;
            p.inst_id = id;
            kit_push(k, p);
            p.kind = PIECE_CAPSULE;
            p.a = kit_map_point(&xf, lv(cap.a));
            p.b = kit_map_point(&xf, lv(cap.b));
            p.R = sc * (ld)cap.radius;
            p.centre = lscale(ladd(p.a, p.b), 0.5L);
            p.reach = ldist(p.a, p.b) / 2 + p.R;
            p.geom_id = 1;
            kit_push(k, p);
            continue;
        }
        for (t = 0; t < ico.nt; t++) {
            p = kit_tri(kit_map_point(&xf, lv(ico.v[ico.idx[3 * t]])),
                        kit_map_point(&xf, lv(ico.v[ico.idx[3 * t + 1]])),
                        kit_map_point(&xf, lv(ico.v[ico.idx[3 * t + 2]])), 0,
                        (unsigned)t);
            p.inst_id = id;
            kit_push(k, p);
        }
        memset(&p, 0, sizeof p);
        p.kind = PIECE_PARA;
        kit_box_frame(&box, e, h);
        for (c = 0; c < 8; c++) {
            lvec x = lv(box.center);
            x = ladd(x, lscale(e[0], c & 1 ? h[0] : -h[0]));
            x = ladd(x, lscale(e[1], c & 2 ? h[1] : -h[1]));
            x = ladd(x, lscale(e[2], c & 4 ? h[2] : -h[2]));
            p.corner[c] = kit_map_point(&xf, x);
        }
        p.centre = lscale(ladd(p.corner[0], p.corner[7]), 0.5L);
        p.reach = 0;
        for (c = 0; c < 8; c++)
            p.reach = fmaxl(p.reach, ldist(p.corner[c], p.centre));
        p.geom_id = 1;
        p.inst_id = id;
        kit_push(k, p);
        for (c = 0; c < 4; c++) {
            p = kit_tri(kit_map_point(&xf, lv(l[kit_l_tris[c][0]])),
                        kit_map_point(&xf, lv(l[kit_l_tris[c][1]])),
                        kit_map_point(&xf, lv(l[kit_l_tris[c][2]])), 2, 0);
            p.inst_id = id;
            kit_push(k, p);
        }
    }
    ck_assert_int_eq(ray_scene_commit(k->s), RAY_OK);
    hc_mesh_free(&ico);
}

static inline void kit_free(kit *k)
{
    ray_scene_free(k->s);
    free(k->p);
}

#endif
