/* SPDX-License-Identifier: MIT */
/*
** grid.c -- ray_distance_grid: a signed distance field baked over a box,
** one z slice per task (core/tasks.c: the program's scheduler or the
** built-in threads).  A sample is ray_signed_distance at its position,
** which is computed from (i, j, k) alone, so a slice's floats are the
** same whichever thread bakes it: the same bytes at any thread count.
** Each search starts from the row's previous sample's answer (below),
** which changes how much of the scene it must search, not what it finds.
*/
#include <limits.h>

#include "core/tasks.h"
#include "query/query.h"
#include "query/why.h"

typedef struct grid_job {
    const ray_scene *s;
    ray_vec3 lo, step;
    unsigned nx, ny, nz;
    double radius;
    ray_contains_options contains;
    float *out;
} grid_job;

/* Coordinate i of n samples from lo with spacing step: lo exactly at
** i = 0; an axis of one sample stays at lo. */
static double at(double lo, double step, unsigned i)
{
    return lo + step * (double)i;
}

/*
** The search radius for sample p whose row's previous sample found the
** surface point *prev (NULL: it found none): the distance from p to
** *prev, a surface point, so the nearest lies no farther -- grown by a
** millionth and by 2^-40 of the coordinates for the roundings of that
** point (within ulps of its primitive) and of both distances -- when it
** is below the grid's radius, which is otherwise kept.
**
** A search within a smaller radius visits the same boxes in the same
** order (nearest first) but for those wholly beyond it, whose points are
** all farther than the nearest: so it finds the same point, at the same
** computed distance, where it finds one (bit for bit: tests/
** check_contains.c bakes grids both ways).  Where the roundings put the
** nearest just past the smaller radius, it finds none and the sample is
** searched again within the grid's radius (ray_signed_distance's 0).
** Neighbouring samples lie a grid step apart, so the first search is
** bounded by the distance plus a step instead of the band (or the whole
** scene, band 0): a narrow band's samples search a few triangles, not
** the dozens within the band (issue 39: the band against OpenVDB).
*/
static double warm_radius(const grid_job *g, ray_vec3 p,
                          const ray_closest *prev)
{
    double d, m;

    if (prev == NULL)
        return g->radius;
    d = ray__distance(p, prev->p);
    m = fmax(fmax(fabs(prev->p.x), fabs(prev->p.y)), fabs(prev->p.z));
    d = d * (1 + 0x1p-20) + m * 0x1p-40;
    return d < g->radius ? d : g->radius;
}

static void grid_task(void *ud, unsigned k)
{
    const grid_job *g = ud;
    float *row = g->out + (size_t)k * g->ny * g->nx;
    unsigned i, j;

    for (j = 0; j < g->ny; j++) {
        ray_closest near;
        int have = 0;
        for (i = 0; i < g->nx; i++) {
            ray_vec3 p = v3(at(g->lo.x, g->step.x, i),
                            at(g->lo.y, g->step.y, j),
                            at(g->lo.z, g->step.z, k));
            double d = g->radius;
            double r = warm_radius(g, p, have ? &near : NULL);
            /* The checks below (ray_distance_grid) leave no failure for
            ** a finite point; a point that overflowed to Inf (a box near
            ** DBL_MAX) keeps +radius (have stays 0). */
            have = ray__signed_distance_at(g->s, p, r, &g->contains, &d,
                                       &near) > 0;
            if (!have && r < g->radius) {
                d = g->radius;
                have = ray__signed_distance_at(g->s, p, g->radius, &g->contains,
                                           &d, &near) > 0;
            }
            row[(size_t)j * g->nx + i] = (float)d;
        }
    }
}

/* The spacing of n samples over [lo, hi]: (hi - lo) / (n - 1), 0 for one
** sample. */
static double spacing(double lo, double hi, unsigned n)
{
    return n > 1 ? (hi - lo) / (double)(n - 1) : 0.0;
}

/*
** Why the grid refused (ray.h, ray_contains_options.why): the checks
** below again, in their order, on the refusal path only; the scene's
** statuses have their reason from ray__contains_run.
*/
static int grid_refused(const ray_distance_grid_options *o, const ray_scene *s,
                        ray_vec3 lo, ray_vec3 hi, unsigned nx, unsigned ny,
                        unsigned nz, const float *out)
{
    static const char op[] = "ray_distance_grid";
    char *why = o->contains.why;
    size_t size = o->contains.why_size;

    if (s == NULL || out == NULL)
        return ray__why(why, size, RAY_EINVAL, op, "%s is NULL",
                        s == NULL ? "scene" : "out");
    if (!v3_isfinite(lo) || !v3_isfinite(hi))
        return ray__why(why, size, RAY_EINVAL, op, "%s " RAY__WHY_V3
                        " is not finite", !v3_isfinite(lo) ? "lo" : "hi",
                        RAY__WHY_V3ARGS(!v3_isfinite(lo) ? lo : hi));
    if (nx == 0 || ny == 0 || nz == 0)
        return ray__why(why, size, RAY_EINVAL, op, "a count is 0 (nx %u, "
                        "ny %u, nz %u)", nx, ny, nz);
    if (!(o->band >= 0) || !(o->band < HUGE_VAL))
        return ray__why(why, size, RAY_EINVAL, op, "options->band is %.17g: "
                        "NaN, negative or infinite", o->band);
    return ray__why(why, size, RAY_EINVAL, op, "nx * ny * nz floats overflow "
                    "size_t (nx %u, ny %u, nz %u)", nx, ny, nz);
}

int ray_distance_grid(const ray_scene *s, ray_vec3 lo, ray_vec3 hi,
                      unsigned nx, unsigned ny, unsigned nz,
                      const ray_distance_grid_options *o, float *out)
{
    ray_distance_grid_options def;
    const ray_scheduler *sched;
    grid_job g;
    unsigned n;
    int rc;

    if (o == NULL) {
        memset(&def, 0, sizeof def);
        o = &def;
    }
    if (s == NULL || out == NULL || !v3_isfinite(lo) || !v3_isfinite(hi) ||
        nx == 0 || ny == 0 || nz == 0 || !(o->band >= 0) ||
        !(o->band < HUGE_VAL) ||
        (size_t)nx * ny > ((size_t)-1) / sizeof(float) / nz)
        return grid_refused(o, s, lo, hi, nx, ny, nz, out);
    /* The statuses every sample would share, asked once, before anything
    ** is written: bad flags, an uncommitted scene, a stale instance,
    ** nothing closed. */
    rc = ray__contains_run(s, NULL, 0, &o->contains, NULL,
                           "ray_distance_grid");
    if (rc < 0)
        return -rc;
    g.s = s;
    g.lo = lo;
    g.step = v3(spacing(lo.x, hi.x, nx), spacing(lo.y, hi.y, ny),
                spacing(lo.z, hi.z, nz));
    g.nx = nx;
    g.ny = ny;
    g.nz = nz;
    g.radius = o->band > 0 ? o->band : HUGE_VAL;
    g.contains = o->contains;
    /* The samples run on several threads: none may write a reason into
    ** the one buffer (a sample overflowed to Inf is refused, below). */
    g.contains.why = NULL;
    g.out = out;
    sched = ray__scheduler_pick(o->scheduler, &s->scheduler);
    n = ray__task_count(o->threads, sched);
    ray__tasks_run(sched, &s->alloc, n, 0, nz, grid_task, &g);
    return RAY_OK;
}
