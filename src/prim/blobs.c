/* SPDX-License-Identifier: MIT */
/*
** blobs.c -- metaballs as an implicit surface for ray_implicit: a field
** summed from blobs, each with Wyvill's compact falloff, and the
** Lipschitz bound that lets ray_implicit sphere-trace it.
*/
#include "core/vec.h"

/*
** Each blob adds strength * k(|p - c|^2 / radius^2) with k(x) = (1 - x)^2
** for x < 1, 0 beyond (Wyvill, McPheeters, Wyvill, "Data Structure for
** Soft Objects", The Visual Computer 2(4), 1986, use a sixth-degree
** polynomial of the same kind): smooth where it ends, and zero outside the
** radius, so far blobs cost nothing but the distance test.
*/
/* x = |p - c|^2 / r^2 as |w|^2 with w = (p - c) / r (into *wp if not
** NULL): dividing first keeps r^2 from overflowing or underflowing for
** radii like 1e200 or 1e-200. */
static double scaled_distance2(const ray_blob *b, ray_vec3 p, ray_vec3 *wp)
{
    ray_vec3 w = v3_scale(v3_sub(p, b->center), 1.0 / b->radius);

    if (wp != NULL)
        *wp = w;
    return v3_dot(w, w);
}

static double blobs_field(void *ud, ray_vec3 p)
{
    const ray_blobs_params *bp = ud;
    double sum = 0;
    size_t i;

    for (i = 0; i < bp->count; i++) {
        const ray_blob *b = &bp->blobs[i];
        double x = scaled_distance2(b, p, NULL);
        if (x < 1)
            sum += b->strength * (1 - x) * (1 - x);
    }
    return bp->threshold - sum;
}

/* grad of threshold - sum: each blob adds 4 s (1 - x)(p - c) / radius^2,
** pointing away from a positive blob, i.e. outward. */
static ray_vec3 blobs_gradient(void *ud, ray_vec3 p)
{
    const ray_blobs_params *bp = ud;
    ray_vec3 g = v3(0, 0, 0);
    size_t i;

    for (i = 0; i < bp->count; i++) {
        const ray_blob *b = &bp->blobs[i];
        ray_vec3 w;
        double x = scaled_distance2(b, p, &w);
        if (x < 1)   /* 4 s (1 - x) (p - c) / r^2 = 4 s (1 - x) w / r */
            g = v3_madd(g, 4 * b->strength * (1 - x) / b->radius, w);
    }
    return g;
}

/* The direction of the normal as longitude and latitude, as ray_sphere
** maps a sphere: a blob alone is textured like a sphere. */
static void blobs_uv(void *ud, ray_vec3 p, ray_vec3 n, double *u, double *v)
{
    double ny = n.y < -1.0 ? -1.0 : (n.y > 1.0 ? 1.0 : n.y);

    (void)ud;
    (void)p;
    *u = atan2(n.x, n.z) / (2.0 * RAY__PI) + 0.5;
    *v = acos(-ny) / RAY__PI;
}

/*
** The steepest slope of one blob's term: d/dr of (1 - r^2/R^2)^2 is
** -4 (r/R) (1 - r^2/R^2) / R, largest in size at r/R = 1/sqrt 3, where it
** is 8 / (3 sqrt 3 R).  Slopes add, so the sum over the blobs bounds
** |grad f| everywhere.  3 sqrt 3 = 5.196152422706632.
*/
#define BLOB_SLOPE_FACTOR (8.0 / 5.196152422706632)

static int blobs_valid(const ray_blobs_params *p)
{
    size_t i;

    if (p == NULL || p->blobs == NULL || p->count == 0 ||
        !(p->threshold > 0 && p->threshold < HUGE_VAL))
        return 0;
    for (i = 0; i < p->count; i++) {
        const ray_blob *b = &p->blobs[i];
        if (!v3_isfinite(b->center) || !(b->radius > 0) ||
            !(b->radius < HUGE_VAL) || !isfinite(b->strength))
            return 0;
    }
    return 1;
}

int ray_implicit_blobs(const ray_blobs_params *p, ray_implicit_surface *out)
{
    ray_implicit_surface s;
    int any_positive = 0;
    double lipschitz = 0;
    size_t i;

    if (out == NULL || !blobs_valid(p))
        return RAY_EINVAL;
    for (i = 0; i < p->count; i++)
        any_positive |= p->blobs[i].strength > 0;
    /* f < threshold needs a positive term, so the surface lies in the
    ** positive blobs' spheres; with none, f > 0 everywhere (no surface),
    ** and any box will do. */
    s.lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    s.hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (i = 0; i < p->count; i++) {
        const ray_blob *b = &p->blobs[i];
        ray_vec3 e = v3(b->radius, b->radius, b->radius);
        lipschitz += fabs(b->strength) * BLOB_SLOPE_FACTOR / b->radius;
        if (any_positive && !(b->strength > 0))
            continue;
        s.lo = v3(fmin(s.lo.x, b->center.x - e.x),
                  fmin(s.lo.y, b->center.y - e.y),
                  fmin(s.lo.z, b->center.z - e.z));
        s.hi = v3(fmax(s.hi.x, b->center.x + e.x),
                  fmax(s.hi.y, b->center.y + e.y),
                  fmax(s.hi.z, b->center.z + e.z));
    }
    if (!v3_isfinite(s.lo) || !v3_isfinite(s.hi) || !(lipschitz < HUGE_VAL))
        return RAY_EINVAL;
    s.f = blobs_field;
    s.gradient = blobs_gradient;
    s.uv = blobs_uv;
    s.ud = ray__unconst(p);
    s.lipschitz = lipschitz;
    s.step = 0;
    s.tolerance = 0;
    s.max_iterations = 0;
    *out = s;
    return RAY_OK;
}
