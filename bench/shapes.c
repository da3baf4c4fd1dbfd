/* SPDX-License-Identifier: MIT */
/*
** shapes.c -- the shape queries on real scenes (issue 30): sphere and
** capsule sweeps (ray_intersect_sweep) and sphere and box overlaps
** (ray_overlap_*) per second on the 59k-triangle bunny and on the game
** example's scene (its terrain and 200 crates, instances), against
** brute force (every triangle through the same narrow phase: the answer
** must be the same, the ratio is the BVH's), and against Bullet's
** convexSweepTest with a btSphereShape and its rayTest over a
** btBvhTriangleMeshShape on the same paths where Debian's libbullet-dev
** is installed (bench/bullet.cpp), counting Bullet's misses of contacts
** the reference finds; and the self-hits of rays leaving points of the
** bunny given by (triangle, u, v): from the interpolated point with no
** offset, and from ray_surface_point through ray_spawn.
**
**     shapes DATA_DIR     (bunny-2.obj; prints Markdown; BENCH_QUICK=1
**                          for fewer queries)
*/
#include <string.h>
#include <stdio.h>

#include "bench.h"
#include "obj.h"
#include "prim/overlap.h"
#include "shapes.h"
#include "terrain.h"

#if !defined(HAVE_BULLET)
/* Without Bullet: no rows of it (bench/bullet.cpp is not built). */
double bullet_sweeps(const double *v, size_t nv, const unsigned *idx,
                     size_t nt, double radius, bullet_path *paths, size_t n)
{
    (void)v, (void)nv, (void)idx, (void)nt, (void)radius, (void)paths;
    (void)n;
    return -1;
}
#endif

/* A scene's triangles in world space, for the brute force. */
typedef struct soup {
    ray_vec3 *v;             /* 3 per triangle */
    size_t n;
} soup;

static void soup_add(soup *s, ray_vec3 a, ray_vec3 b, ray_vec3 c)
{
    if ((s->n & (s->n - 1)) == 0 || s->n == 0) {
        size_t cap = s->n ? 2 * s->n : 1024;
        s->v = realloc(s->v, 3 * cap * sizeof *s->v);
        if (s->v == NULL) {
            fprintf(stderr, "shapes: out of memory\n");
            exit(1);
        }
    }
    s->v[3 * s->n] = a;
    s->v[3 * s->n + 1] = b;
    s->v[3 * s->n + 2] = c;
    s->n++;
}

/* The sweep by brute force: every triangle through the library's own
** narrow phase, in its frame, the lowest index winning ties (as the
** query's lowest ids do): the t of the first contact, or +Inf. */
static double brute_sweep(const soup *s, const ray_sweep *w)
{
    ray__sweep sw;
    ray__contact best;
    size_t i;

    ray__sweep_start(&sw, w->dir, vsub(w->shape.b, w->shape.a), w->shape.radius, w->tmin,
                     w->tmax);
    best.t = HUGE_VAL;
    best.depth = 0;
    for (i = 0; i < s->n; i++) {
        ray__contact c = best;
        c.depth = -1;
        if (ray__sweep_triangle(&sw, vsub(s->v[3 * i], w->shape.a),
                                vsub(s->v[3 * i + 1], w->shape.a),
                                vsub(s->v[3 * i + 2], w->shape.a), &c) &&
            (c.t < best.t || (c.t == best.t && c.depth > best.depth)))
            best = c;
    }
    return best.t < HUGE_VAL ? best.t * sw.t_unit : HUGE_VAL;
}

/* How many triangles a sphere (is_box 0) or box meets, by brute force. */
static size_t brute_overlap(const soup *s, int is_box, ray_vec3 c, double r,
                            const ray_box_params *b)
{
    ray__pped p;
    size_t i, n = 0;

    if (is_box)
        ray__pped_of_box(b, &p);
    for (i = 0; i < s->n; i++) {
        const ray_vec3 *t = s->v + 3 * i;
        if (is_box ? ray__pped_overlaps_triangle(&p, t[0], t[1], t[2])
                   : ray__distance(ray__triangle_closest(t[0], t[1], t[2], c),
                                   c) <= r)
            n++;
    }
    return n;
}

typedef struct row {
    const char *scene, *what;
    double lib_s, brute_s;
    size_t n, n_brute, hits, diff;
} row;

static void print_row(const row *r)
{
    printf("| %s | %s | %zu | %.0f | %.1f | %.0fx | %zu of %zu | %zu |\n",
           r->scene, r->what, r->n, (double)r->n / r->lib_s,
           (double)r->n_brute / r->brute_s,
           ((double)r->n / r->lib_s) / ((double)r->n_brute / r->brute_s),
           r->hits, r->n, r->diff);
}

/* Sweeps w[0 .. n-1] through scene s, the first nb also by brute force:
** the answers must agree (t bit for bit). */
static row sweep_row(const char *scene, const char *what, const ray_scene *s,
                     const soup *sp, const ray_sweep *w, size_t n, size_t nb,
                     double *t_out)
{
    row r;
    double t0 = now_seconds();
    size_t i;

    r.scene = scene;
    r.what = what;
    r.n = n;
    r.n_brute = nb;
    r.hits = r.diff = 0;
    for (i = 0; i < n; i++) {
        ray_contact c;
        int rc = ray_intersect_sweep(s, &w[i], NULL, &c);
        if (rc < 0) {
            fprintf(stderr, "shapes: sweep failed (%d)\n", rc);
            exit(1);
        }
        t_out[i] = rc ? c.t : HUGE_VAL;
        r.hits += rc == 1;
    }
    r.lib_s = now_seconds() - t0;
    t0 = now_seconds();
    for (i = 0; i < nb; i++)
        r.diff += brute_sweep(sp, &w[i]) != t_out[i];
    r.brute_s = now_seconds() - t0;
    return r;
}

/* Overlaps (is_box: boxes of half-extent h, else spheres of radius h) at
** the points c[0 .. n-1]; the first nb also by brute force (the same
** count of triangles). */
static row overlap_row(const char *scene, const char *what,
                       const ray_scene *s, const soup *sp, int is_box,
                       const ray_vec3 *c, double h, size_t n, size_t nb)
{
    row r;
    double t0 = now_seconds();
    size_t i, *got = malloc(n * sizeof *got);
    rng g = {7};

    r.scene = scene;
    r.what = what;
    r.n = n;
    r.n_brute = nb;
    r.hits = r.diff = 0;
    for (i = 0; i < n; i++) {
        ray_box_params b;
        size_t count;
        int rc;
        b.center = c[i];
        b.half_extents = vec(h, h, h);
        b.axis_x = vec(1, 0.3 * (double)(i % 5), 0.2);
        b.axis_y = vec(-0.1, 1, 0.4);
        ray_shape q;
        memset(&q, 0, sizeof q);
        if (is_box) {
            q.kind = RAY_SHAPE_BOX;
            q.box = b;
        } else {
            q.a = q.b = c[i];
            q.radius = h;
        }
        rc = ray_overlap_shape_all(s, &q, NULL, NULL, 0, &count);
        if (rc < 0) {
            fprintf(stderr, "shapes: overlap failed (%d)\n", rc);
            exit(1);
        }
        got[i] = count;
        r.hits += count > 0;
    }
    r.lib_s = now_seconds() - t0;
    (void)g;
    t0 = now_seconds();
    for (i = 0; i < nb; i++) {
        ray_box_params b;
        b.center = c[i];
        b.half_extents = vec(h, h, h);
        b.axis_x = vec(1, 0.3 * (double)(i % 5), 0.2);
        b.axis_y = vec(-0.1, 1, 0.4);
        r.diff += brute_overlap(sp, is_box, c[i], h, &b) != got[i];
    }
    r.brute_s = now_seconds() - t0;
    free(got);
    return r;
}

/* ------------------------------------------------------------ scenes */

/* The game example's scene at its first frame: the 48 x 48 terrain (4,608
** triangles) and 200 instances of a 12-triangle crate; and its triangles
** in world space. */
static ray_scene *game_scene(soup *sp, ray_scene **crate)
{
    static const unsigned box[36] = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5,
                                     0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3,
                                     0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
    ray_vec3 cv[8];
    ray_scene *s;
    ray_mesh m;
    unsigned i, j, k;
    size_t tri;

    terrain_mesh(&m);
    for (tri = 0; tri < m.triangle_count; tri++)
        soup_add(sp, m.vertices[m.indices[3 * tri]],
                 m.vertices[m.indices[3 * tri + 1]],
                 m.vertices[m.indices[3 * tri + 2]]);
    for (i = 0; i < 8; i++)
        cv[i] = vec(i & 1 ? 0.4 : -0.4, i & 2 ? 0.8 : 0, i & 4 ? 0.4 : -0.4);
    if (ray_scene_new(crate, NULL, NULL) != RAY_OK ||
        example_add_box_mesh(*crate, vec(-0.4, 0, -0.4), vec(0.4, 0.8, 0.4),
                             RAY_NO_MATERIAL, NULL) != RAY_OK ||
        ray_scene_commit(*crate) != RAY_OK || ray_scene_new(&s, NULL, NULL))
        exit(1);
    if (ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL) != RAY_OK)
        exit(1);
    for (k = 0; k < 200; k++) {
        double a = k, x = -22 + 2.2 * (k % 20) + 0.5 * cos(a);
        double z = -11 + 2.2 * (double)(k / 20) + 0.5 * sin(a);
        double c = cos(a), sn = sin(a), y = terrain_height(x, z) + 1.2;
        ray_transform t;
        ray_transform_identity(&t);
        t.m[0][0] = c, t.m[0][2] = sn, t.m[2][0] = -sn, t.m[2][2] = c;
        t.m[0][3] = x, t.m[1][3] = y, t.m[2][3] = z;
        if (ray_scene_add_instance(s, *crate, &t, NULL) != RAY_OK)
            exit(1);
        for (i = 0; i < 12; i++) {
            ray_vec3 w[3];
            for (j = 0; j < 3; j++) {
                ray_vec3 p = cv[box[3 * i + j]];
                w[j] = vec(c * p.x + sn * p.z + x, p.y + y,
                           -sn * p.x + c * p.z + z);
            }
            soup_add(sp, w[0], w[1], w[2]);
        }
    }
    if (ray_scene_commit(s) != RAY_OK)
        exit(1);
    return s;
}

/* ------------------------------------------------------------ Bullet */

/* Without Bullet (no /usr/include/bullet: HAVE_BULLET unset) nothing
** calls these, and -Werror would fail on them as unused. */
#if defined(HAVE_BULLET)
/* Bullet on the sweeps w (radius r, or rays: r 0) of a scene of triangle
** soup sp; the reference's t[i] (HUGE_VAL: no contact).  Prints a row:
** Bullet's time per query, its misses (the reference has a contact,
** Bullet none, or one later by more than 1e-3 of the path). */
/* The least clearance (distance to the scene less r) along path w, by
** 400 exact closest-point queries along it: how near a path the
** reference finds no contact for comes to touching. */
static double least_clearance(const ray_scene *s, const ray_sweep *w,
                              double r)
{
    double best = HUGE_VAL;
    int k;

    for (k = 0; k <= 400; k++) {
        ray_closest c;
        ray_vec3 x = vadd(w->shape.a, vscale(w->dir, w->tmax * k / 400));
        if (ray_closest_point(s, x, HUGE_VAL, &c) == 1 &&
            c.distance - r < best)
            best = c.distance - r;
    }
    return best;
}

static void bullet_row(const char *scene, const ray_scene *sc,
                       const soup *sp, const ray_sweep *w, size_t n, double r,
                       const double *t, double lib_s)
{
    double near_extra = 0;
    double *v = malloc(9 * sp->n * sizeof *v);
    unsigned *idx = malloc(3 * sp->n * sizeof *idx);
    bullet_path *p = malloc(n * sizeof *p);
    size_t i, missed = 0, late = 0, extra = 0, contacts = 0;
    double bt;

    if (v == NULL || idx == NULL || p == NULL)
        exit(1);
    for (i = 0; i < 3 * sp->n; i++) {
        v[3 * i] = sp->v[i].x;
        v[3 * i + 1] = sp->v[i].y;
        v[3 * i + 2] = sp->v[i].z;
        idx[i] = (unsigned)i;
    }
    for (i = 0; i < n; i++) {
        ray_vec3 to = vadd(w[i].shape.a, vscale(w[i].dir, w[i].tmax));
        p[i].from[0] = w[i].shape.a.x, p[i].from[1] = w[i].shape.a.y;
        p[i].from[2] = w[i].shape.a.z;
        p[i].to[0] = to.x, p[i].to[1] = to.y, p[i].to[2] = to.z;
    }
    bt = bullet_sweeps(v, 3 * sp->n, idx, sp->n, r, p, n);
    if (bt < 0) {
        free(v), free(idx), free(p);
        return;
    }
    for (i = 0; i < n; i++) {
        int ref = t[i] <= w[i].tmax;
        contacts += ref ? 1u : 0u;
        if (ref && !p[i].hit)
            missed++;
        else if (ref && p[i].fraction * w[i].tmax > t[i] + 1e-3 * w[i].tmax)
            late++;
        else if (!ref && p[i].hit) {
            double c = least_clearance(sc, &w[i], r);
            extra++;
            near_extra = c > near_extra ? c : near_extra;
        }
    }
    printf("| %s | %s | %zu | %.0f | %.0f | %.2f | %zu of %zu | %zu | %zu "
           "(%.2g) |\n", scene, r > 0 ? "sphere sweep" : "ray", n,
           (double)n / lib_s, (double)n / bt, lib_s / bt, missed, contacts,
           late, extra, near_extra);
    free(v), free(idx), free(p);
}
#endif /* HAVE_BULLET */

/* ---------------------------------------------------------- self-hits */

/*
** Rays from points of the bunny given by (triangle, u, v), 4 per
** triangle into the cosine hemisphere of its normal: from the
** interpolated point (1-u-v) a + u b + v c with tmin 0 (what a baker
** without a hit record does), and from ray_surface_point's record
** through ray_spawn.  A self-hit: the ray's nearest hit is the triangle
** it starts on.
*/
static void self_hits(const ray_scene *s, const obj_mesh *m, size_t every)
{
    rng g = {2718};
    size_t i, rays = 0, before = 0, after = 0, uniform = 0;
    int k;

    for (i = 0; i < m->triangle_count; i += every) {
        ray_vec3 a = m->vertices[m->indices[3 * i]];
        ray_vec3 b = m->vertices[m->indices[3 * i + 1]];
        ray_vec3 c = m->vertices[m->indices[3 * i + 2]];
        ray_vec3 n = vcross(vsub(b, a), vsub(c, a));
        double len = vlen(n);
        if (!(len > 0))
            continue;
        n = vscale(n, 1 / len);
        for (k = 0; k < 4; k++) {
            double u = rng_unit(&g), v = rng_unit(&g);
            ray_vec3 p, dir;
            ray_hit h, sp;
            ray_ray r;
            if (u + v > 1)
                u = 1 - u, v = 1 - v;
            p = vadd(vadd(vscale(a, 1 - u - v), vscale(b, u)), vscale(c, v));
            dir = bench_cosine_dir(n, rng_unit(&g), rng_unit(&g));
            r.org = p;
            r.dir = dir;
            r.tmin = 0;
            r.tmax = HUGE_VAL;
            rays++;
            if (ray_intersect(s, &r, &h, NULL) == 1 && h.prim_id == i)
                before++;
            /* The same from directions uniform over the hemisphere. */
            r.dir = rng_dir(&g);
            if (vdot(r.dir, n) < 0)
                r.dir = vscale(r.dir, -1);
            if (ray_intersect(s, &r, &h, NULL) == 1 && h.prim_id == i)
                uniform++;
            if (ray_surface_point(s, 0, (unsigned)i, RAY_INVALID_ID, u, v,
                                  &sp) != RAY_OK ||
                ray_spawn(&sp, dir, &r) != RAY_OK) {
                fprintf(stderr, "shapes: no surface point\n");
                exit(1);
            }
            if (ray_intersect(s, &r, &h, NULL) == 1 && h.prim_id == i)
                after++;
        }
    }
    printf("### Rays from surface points (bunny-2)\n\n"
           "%zu rays, 4 per triangle (every %zu of %zu), into the cosine "
           "hemisphere of its normal from a random (u, v) on it.  A "
           "self-hit: the ray's nearest hit is its own triangle.\n\n"
           "| start | self-hits | rate |\n|---|---|---|\n"
           "| interpolated point, tmin 0 | %zu | %.1f%% |\n"
           "| the same, directions uniform over the hemisphere | %zu | "
           "%.1f%% |\n"
           "| ray_surface_point + ray_spawn | %zu | %.1f%% |\n\n",
           rays, every, m->triangle_count, before,
           100.0 * (double)before / (double)rays, uniform,
           100.0 * (double)uniform / (double)rays, after,
           100.0 * (double)after / (double)rays);
}

/* ---------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    int level = bench_level(), quick = level != BENCH_FULL;
    int smoke = level == BENCH_SMOKE;
    size_t n = smoke ? 20 : quick ? 2000 : 20000, nb = smoke ? 4 : quick ? 20 : 100, i;
    char path[512], err[600];
    obj_mesh m;
    ray_scene *bunny, *game, *crate;
    soup bs = {NULL, 0}, gs = {NULL, 0};
    ray_vec3 lo, hi, centre, *pts;
    ray_sweep *w;
    double diag, *t;
    rng g = {42};
    row r[8];

    if (argc != 2) {
        fprintf(stderr, "usage: shapes DATA_DIR\n");
        return 2;
    }
    w = malloc(n * sizeof *w);
    t = malloc(n * sizeof *t);
    pts = malloc(n * sizeof *pts);
    if (w == NULL || t == NULL || pts == NULL)
        return 1;
    printf("## Shape queries: sweeps and overlaps\n\n");
    snprintf(path, sizeof path, "%s/bunny-2.obj", argv[1]);
    if (obj_load(path, &m, err, sizeof err) != 0) {
        printf("(no %s: scripts/fetch-bunny.sh; bunny rows skipped)\n\n",
               path);
        return 0;
    }
    {
        ray_mesh rm = obj_as_ray_mesh(&m);
        if (ray_scene_new(&bunny, NULL, NULL) != RAY_OK ||
            ray_scene_add_mesh(bunny, &rm, RAY_NO_MATERIAL, NULL) != RAY_OK ||
            ray_scene_commit(bunny) != RAY_OK)
            return 1;
    }
    for (i = 0; i < m.triangle_count; i++)
        soup_add(&bs, m.vertices[m.indices[3 * i]],
                 m.vertices[m.indices[3 * i + 1]],
                 m.vertices[m.indices[3 * i + 2]]);
    obj_bounds(&m, &lo, &hi, &centre, &diag);
    game = game_scene(&gs, &crate);

    printf("Per second on one thread (the whole batch timed); brute force: "
           "every triangle through the same narrow phase, on the first "
           "queries of the batch (its answers must be the same: "
           "\"differ\").  bunny-2: %zu triangles, diagonal %.3g; sweeps "
           "from 0.75 diagonals out toward the box's middle half, radius "
           "0.01 diagonal (capsules: 0.02 long); overlaps at points of "
           "the box, radius (half-extent) 0.02 diagonal.  Game: the "
           "terrain (4,608 triangles) and 200 instanced 12-triangle "
           "crates of examples/game.c; a character's capsule (radius "
           "0.4, 1.0 between its ends) moved 0.2 to 2 units from 1 to 3 "
           "above the terrain, and spheres of radius 0.1 to 0.5.\n\n"
           "| scene | query | queries | per second | brute force per "
           "second | speed-up | with a contact | differ |\n"
           "|---|---|---|---|---|---|---|---|\n", m.triangle_count, diag);
    for (i = 0; i < n; i++) {
        ray_vec3 from = vadd(centre, vscale(rng_dir(&g), 0.75 * diag));
        ray_vec3 to = vec(lo.x + (hi.x - lo.x) * rng_range(&g, 0.25, 0.75),
                          lo.y + (hi.y - lo.y) * rng_range(&g, 0.25, 0.75),
                          lo.z + (hi.z - lo.z) * rng_range(&g, 0.25, 0.75));
        memset(&w[i], 0, sizeof w[i]);
        w[i].shape.a = w[i].shape.b = from;
        w[i].shape.radius = 0.01 * diag;
        w[i].dir = vsub(to, from);
    }
    r[0] = sweep_row("bunny-2", "sphere sweep", bunny, &bs, w, n, nb, t);
    print_row(&r[0]);
    {
        double *tc = malloc(n * sizeof *tc);
        ray_sweep *wc = malloc(n * sizeof *wc);
        if (tc == NULL || wc == NULL)
            return 1;
        for (i = 0; i < n; i++) {
            wc[i] = w[i];
            wc[i].shape.b = vadd(w[i].shape.a, vscale(rng_dir(&g), 0.02 * diag));
        }
        r[1] = sweep_row("bunny-2", "capsule sweep", bunny, &bs, wc, n, nb,
                         tc);
        print_row(&r[1]);
        free(tc);
        free(wc);
    }
    for (i = 0; i < n; i++)
        pts[i] = vec(lo.x + (hi.x - lo.x) * rng_unit(&g),
                     lo.y + (hi.y - lo.y) * rng_unit(&g),
                     lo.z + (hi.z - lo.z) * rng_unit(&g));
    r[2] = overlap_row("bunny-2", "sphere overlap", bunny, &bs, 0, pts,
                       0.02 * diag, n, nb);
    print_row(&r[2]);
    r[3] = overlap_row("bunny-2", "box overlap", bunny, &bs, 1, pts,
                       0.02 * diag, n, nb);
    print_row(&r[3]);
    {
        ray_sweep *gw = malloc(n * sizeof *gw);
        double *gt = malloc(n * sizeof *gt);
        if (gw == NULL || gt == NULL)
            return 1;
        for (i = 0; i < n; i++) {
            double x = rng_range(&g, -23, 23), z = rng_range(&g, -23, 23);
            ray_vec3 from = vec(x, terrain_height(x, z) + rng_range(&g, 1, 3), z);
            ray_vec3 step = vscale(rng_dir(&g), rng_range(&g, 0.2, 2));
            memset(&gw[i], 0, sizeof gw[i]);
            gw[i].shape.a = gw[i].shape.b = from;
            gw[i].shape.radius = rng_range(&g, 0.1, 0.5);
            gw[i].dir = step;
        }
        r[4] = sweep_row("game", "sphere sweep", game, &gs, gw, n, nb, gt);
        print_row(&r[4]);
        for (i = 0; i < n; i++) {
            gw[i].shape.radius = 0.4;
            gw[i].shape.b = vadd(gw[i].shape.a, vec(0, 1, 0));
        }
        r[5] = sweep_row("game", "capsule sweep", game, &gs, gw, n, nb, gt);
        print_row(&r[5]);
        for (i = 0; i < n; i++)
            pts[i] = gw[i].shape.a;
        r[6] = overlap_row("game", "sphere overlap", game, &gs, 0, pts, 1.0,
                           n, nb);
        print_row(&r[6]);
        r[7] = overlap_row("game", "box overlap", game, &gs, 1, pts, 1.0, n,
                           nb);
        print_row(&r[7]);
        free(gw);
        free(gt);
    }
    printf("\n");

#if defined(HAVE_BULLET)
    printf("### Against Bullet\n\n"
           "Bullet %s (Debian's libbullet-dev, single precision) on the "
           "same paths: convexSweepTest with a btSphereShape, rayTest, "
           "over a btBvhTriangleMeshShape of the same triangles (the game's "
           "crates as world triangles), from the path's start to its end "
           "(tmax 1).  The reference is libray's answer (the brute force "
           "agrees, above; the tests hold both to long double).  Missed: "
           "a contact the reference finds and Bullet does not; late: "
           "Bullet's contact more than 1e-3 of the path after it; extra: "
           "a contact Bullet reports where the reference has none (in "
           "brackets: the most that any of those paths stays clear of "
           "the surface by, the least clearance along it from 400 exact "
           "closest-point queries).\n\n"
           "| scene | query | paths | libray per second | Bullet per second "
           "| libray / Bullet time | missed | late | extra |\n"
           "|---|---|---|---|---|---|---|---|---|\n", "3.24");
    bullet_row("bunny-2", bunny, &bs, w, n, 0.01 * diag, t, r[0].lib_s);
    {
        ray_sweep *gw = malloc(n * sizeof *gw);
        double *gt = malloc(n * sizeof *gt), s0;
        if (gw == NULL || gt == NULL)
            return 1;
        /* Starts clear of everything: Bullet's convexSweepTest does not
        ** report a shape that starts inside (libray reports the overlap),
        ** so those would count as misses without being any. */
        for (i = 0; i < n; i++) {
            size_t inside;
            do {
                double x = rng_range(&g, -23, 23), z = rng_range(&g, -23, 23);
                memset(&gw[i], 0, sizeof gw[i]);
                gw[i].shape.a = gw[i].shape.b = vec(x, terrain_height(x, z) + rng_range(&g, 1, 3),
                                        z);
                gw[i].shape.radius = 0.3;
                gw[i].dir = vscale(rng_dir(&g), rng_range(&g, 0.2, 4));
            } while (ray_overlap_shape_all(game, &gw[i].shape, NULL, NULL, 0,
                                           &inside) != 0);
        }
        s0 = now_seconds();
        for (i = 0; i < n; i++) {
            ray_contact c;
            gt[i] = ray_intersect_sweep(game, &gw[i], NULL, &c) == 1 ? c.t
                                                                     : HUGE_VAL;
        }
        bullet_row("game", game, &gs, gw, n, 0.3, gt, now_seconds() - s0);
        for (i = 0; i < n; i++)
            gw[i].shape.radius = 0;
        s0 = now_seconds();
        for (i = 0; i < n; i++) {
            ray_contact c;
            gt[i] = ray_intersect_sweep(game, &gw[i], NULL, &c) == 1 ? c.t
                                                                     : HUGE_VAL;
        }
        bullet_row("game", game, &gs, gw, n, 0, gt, now_seconds() - s0);
        free(gw);
        free(gt);
    }
    for (i = 0; i < n; i++)
        w[i].shape.radius = 0;
    {
        double s0 = now_seconds();
        for (i = 0; i < n; i++) {
            ray_contact c;
            t[i] = ray_intersect_sweep(bunny, &w[i], NULL, &c) == 1 ? c.t
                                                                    : HUGE_VAL;
        }
        bullet_row("bunny-2", bunny, &bs, w, n, 0, t, now_seconds() - s0);
    }
    printf("\n");
#else
    printf("(Bullet not installed: apt-get install libbullet-dev for the "
           "comparison rows)\n\n");
#endif
    self_hits(bunny, &m, smoke ? 16 : quick ? 8 : 1);
    ray_scene_free(game);
    ray_scene_free(crate);
    ray_scene_free(bunny);
    obj_free(&m);
    free(bs.v);
    free(gs.v);
    free(w);
    free(t);
    free(pts);
    return 0;
}
