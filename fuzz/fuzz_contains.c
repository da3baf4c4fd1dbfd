/* SPDX-License-Identifier: MIT */
/*
** fuzz_contains.c -- ray_contains, ray_signed_distance and
** ray_distance_grid (issue 39) on a mesh the input builds: 4 to 11
** vertices and 1 to 16 triangles with arbitrary coordinates (NaN, +-Inf,
** subnormals, 1e300) and indices (closed or not, degenerate or not), and
** up to 8 arbitrary points.  Checked:
**
**   * ray_contains answers a count in 0 .. n or -RAY_EINVAL (exactly for
**     a point that is not finite or unknown flags), -RAY_EDEGENERATE
**     (never with RAY_CONTAINS_WINDING), writing nothing then; the count
**     is the number of out[i].inside; inside and on_surface are 0 or 1,
**     on_surface only with inside; one call per point gives the batch's
**     answers bit for bit;
**   * exactness: where every coordinate is 0 or within 2^-100 .. 2^100
**     in magnitude (the predicates' exact range, with margin), the
**     answers are the same for the mesh and points with their axes
**     rotated (x, y, z) -> (y, z, x) and mirrored x -> -x: exact
**     answers do not depend on the direction of the ray counted along;
**   * ray_signed_distance's sign agrees with ray_contains; a 2 x 2 x 2
**     ray_distance_grid answers RAY_OK or a documented status.
*/
#include <string.h>

#include "fuzz.h"

#define MAX_V 11
#define MAX_T 16
#define MAX_P 8
/* A flag ray_contains does not know (RAY_CONTAINS_WINDING_EXACT took 2u):
** -RAY_EINVAL. */
#define UNKNOWN_FLAG 0x100u

static int in_range(double x)
{
    double a = fabs(x);

    return a == 0 || (a >= 0x1p-100 && a <= 0x1p100);
}

static ray_vec3 rotate(ray_vec3 v, int how)
{
    ray_vec3 r = v;

    if (how == 1) {
        r.x = v.y;
        r.y = v.z;
        r.z = v.x;
    } else if (how == 2) {
        r.x = -v.x;
    }
    return r;
}

static ray_scene *build(const ray_vec3 *v, size_t nv, const unsigned *idx,
                        size_t nt, int how)
{
    ray_vec3 w[MAX_V];
    ray_scene *s = NULL;
    ray_mesh m;
    size_t i;

    for (i = 0; i < nv; i++)
        w[i] = rotate(v[i], how);
    if (ray_scene_new(&s, NULL, NULL) != RAY_OK)
        return NULL;
    memset(&m, 0, sizeof m);
    m.vertices = w;
    m.vertex_count = nv;
    m.indices = idx;
    m.triangle_count = nt;
    if (ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL) != RAY_OK ||
        ray_scene_commit(s) != RAY_OK) {
        ray_scene_free(s);
        return NULL;
    }
    return s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_of(data, size);
    ray_vec3 v[MAX_V], p[MAX_P], q[MAX_P];
    unsigned idx[3 * MAX_T];
    ray_inside out[MAX_P], one, other[MAX_P];
    ray_contains_options o = {0};
    size_t nv = 4 + fuzz_below(&in, MAX_V - 3);
    size_t nt = 1 + fuzz_below(&in, MAX_T), np, i;
    ray_scene *s;
    int rc, bad = 0, exact = 1, how, count = 0;
    unsigned sel = fuzz_below(&in, 4);

    for (i = 0; i < nv; i++) {
        v[i] = fuzz_vec3(&in);
        exact &= in_range(v[i].x) && in_range(v[i].y) && in_range(v[i].z);
    }
    for (i = 0; i < 3 * nt; i++)
        idx[i] = fuzz_below(&in, (unsigned)nv);
    o.flags = sel == 1 ? RAY_CONTAINS_WINDING : sel == 2 ? UNKNOWN_FLAG : 0u;
    np = fuzz_below(&in, MAX_P + 1);
    for (i = 0; i < np; i++) {
        p[i] = fuzz_vec3(&in);
        bad |= !(isfinite(p[i].x) && isfinite(p[i].y) && isfinite(p[i].z));
        exact &= in_range(p[i].x) && in_range(p[i].y) && in_range(p[i].z);
    }
    s = build(v, nv, idx, nt, 0);
    if (s == NULL)
        return 0;
    fuzz_sentinel(out, sizeof out);
    rc = ray_contains(s, p, np, &o, out);
    if (rc < 0) {
        FUZZ_CHECK(rc == -RAY_EINVAL || rc == -RAY_EDEGENERATE,
                   "ray_contains: a documented status");
        FUZZ_CHECK((rc == -RAY_EINVAL) == (bad || o.flags == UNKNOWN_FLAG),
                   "ray_contains: -RAY_EINVAL exactly for bad points, flags");
        FUZZ_CHECK(rc != -RAY_EDEGENERATE ||
                       (o.flags & RAY_CONTAINS_WINDING) == 0,
                   "ray_contains: the winding number is always answered");
        FUZZ_CHECK(fuzz_untouched(out, sizeof out),
                   "ray_contains: nothing written on failure");
        ray_scene_free(s);
        return 0;
    }
    FUZZ_CHECK(!bad && o.flags != UNKNOWN_FLAG, "ray_contains: bad input refused");
    for (i = 0; i < np; i++) {
        FUZZ_CHECK(out[i].inside == 0 || out[i].inside == 1,
                   "ray_contains: inside 0 or 1");
        FUZZ_CHECK(out[i].on_surface == 0 ||
                       (out[i].on_surface == 1 && out[i].inside == 1),
                   "ray_contains: on_surface 0, or 1 and inside");
        count += out[i].inside;
        FUZZ_CHECK(ray_contains(s, &p[i], 1, &o, &one) == out[i].inside &&
                       one.on_surface == out[i].on_surface &&
                       memcmp(&one.winding, &out[i].winding,
                              sizeof one.winding) == 0,
                   "ray_contains: one point answers as in the batch");
    }
    FUZZ_CHECK(rc == count, "ray_contains: the count of points inside");
    if (np > 0) {
        double d = 0;
        int sd = ray_signed_distance(s, p[0], HUGE_VAL, &o, &d, NULL);
        FUZZ_CHECK(sd == 0 || sd == 1, "ray_signed_distance: 1 or 0");
        FUZZ_CHECK(out[0].on_surface ? d == 0
                                     : out[0].inside ? !(d > 0) : !(d < 0),
                   "ray_signed_distance: the sign of ray_contains");
    }
    {
        float g[8];
        int gr = ray_distance_grid(s, v[0], v[1], 2, 2, 2, NULL, g);
        FUZZ_CHECK(gr == RAY_OK || gr == RAY_EINVAL || gr == RAY_EDEGENERATE,
                   "ray_distance_grid: a documented status");
    }
    ray_scene_free(s);
    if (!exact || o.flags != 0)
        return 0;
    for (how = 1; how <= 2; how++) {
        ray_scene *t = build(v, nv, idx, nt, how);
        if (t == NULL)
            continue;
        for (i = 0; i < np; i++)
            q[i] = rotate(p[i], how);
        FUZZ_CHECK(ray_contains(t, q, np, &o, other) == rc,
                   "ray_contains: the same count for the turned mesh");
        for (i = 0; i < np; i++)
            FUZZ_CHECK(other[i].inside == out[i].inside &&
                           other[i].on_surface == out[i].on_surface,
                       "ray_contains: exact whatever the ray's direction");
        ray_scene_free(t);
    }
    return 0;
}
