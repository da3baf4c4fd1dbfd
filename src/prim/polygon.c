/* SPDX-License-Identifier: MIT */
/*
** polygon.c -- ray / planar polygon: the plane hit, then an inside test.
*/
#include <stddef.h>

#include "prim/sweep.h"

/*
** Does edge (x0,y0)-(x1,y1) cross the ray from (0,0) toward +x?
** Half-open rule (Haines, Graphics Gems IV): an endpoint with y >= 0 is
** "above", so a vertex on the test line is counted once or, for a touch,
** not at all.  The crossing is right of the origin iff the origin lies left
** of the edge directed upward; the 2x2 orientation determinant is formed
** from (low, high) endpoints, an order that does not depend on the
** polygon's winding, so two polygons sharing the edge round it identically.
** A zero determinant (origin on the edge) counts as a crossing: the origin
** is treated as shifted infinitesimally toward -x.
*/
static int edge_crosses(double x0, double y0, double x1, double y1)
{
    double lx, ly, hx, hy;

    if ((y0 >= 0) == (y1 >= 0))
        return 0;
    if (y0 < y1) {
        lx = x0; ly = y0; hx = x1; hy = y1;
    } else {
        lx = x1; ly = y1; hx = x0; hy = y0;
    }
    return (hy - ly) * lx - (hx - lx) * ly >= 0;
}

/*
** Even-odd count of the polygon's edges crossing the ray's +x half-line,
** in the ray's frame (ray__frame: the ray is the point (0, 0), and every
** vertex is projected on its own).
*/
static int inside_along_ray(const ray_ray *r, const ray_vec3 *v, size_t n)
{
    ray__frame f;
    double p0[3], p1[3], first[3];
    int inside = 0;
    size_t i;

    if (!ray__frame_init(&f, r))
        return 0;
    ray__frame_project(&f, &v[0], first);
    p0[0] = first[0];
    p0[1] = first[1];
    for (i = 1; i <= n; i++) {
        if (i < n)
            ray__frame_project(&f, &v[i], p1);
        else {
            p1[0] = first[0];
            p1[1] = first[1];
        }
        inside ^= edge_crosses(p0[0], p0[1], p1[0], p1[1]);
        p0[0] = p1[0];
        p0[1] = p1[1];
    }
    return inside;
}

/*
** Plane of the polygon: through the vertex centroid c, with the normal
** sum_i (v_i - c) x (v_{i+1} - c), twice the vector area (Newell's method).
** Subtracting c first keeps the cross products from cancelling when the
** polygon is small and far from the origin.  Returns 0 for zero area.
*/
static int polygon_plane(const ray_vec3 *v, size_t n, ray_vec3 *c,
                         ray_vec3 *normal)
{
    ray_vec3 sum = v3(0, 0, 0), area = v3(0, 0, 0);
    size_t i;

    for (i = 0; i < n; i++)
        sum = v3_add(sum, v[i]);
    *c = v3_scale(sum, 1.0 / (double)n);
    for (i = 0; i < n; i++) {
        ray_vec3 a = v3_sub(v[i], *c), b = v3_sub(v[(i + 1) % n], *c);
        area = v3_add(area, v3_cross(a, b));
    }
    *normal = area;
    /* Any non-zero component will do: the normal is rescaled before use,
    ** so an area whose square underflows is not mistaken for zero. */
    return area.x != 0 || area.y != 0 || area.z != 0;
}

int ray__polygon_plane(const ray_vec3 *v, size_t count, ray_vec3 *c,
                       ray_vec3 *normal)
{
    if (!polygon_plane(v, count, c, normal)) {
        *normal = v3(0, 0, 0);
        return 0;
    }
    return 1;
}

int ray__polygon_at(const ray_ray *r, const ray_vec3 *v, size_t count,
                    ray_vec3 c, ray_vec3 normal, ray_hit *hit)
{
    ray_vec3 n, co;
    double denom, t;

    denom = v3_dot(r->dir, normal);
    if (denom == 0)            /* parallel, or a plane of no area */
        return 0;
    co = v3_sub(c, r->org);
    t = v3_dot(co, normal) / denom;
    if (!(t > r->tmin && t < r->tmax) ||
        !(t - ray__plane_t_error(co, normal, r->dir, denom, t) > r->tmin))
        return 0;
    if (!inside_along_ray(r, v, count) || !v3_normalize(normal, &n))
        return 0;
    return ray__plane_fill(r, c, n, v[0], t, hit);
}

int ray_polygon(const ray_ray *r, const ray_vec3 *v, size_t count,
                ray_hit *hit)
{
    ray_vec3 c, normal;

    if (r == NULL || hit == NULL || v == NULL || count < 3 ||
        !polygon_plane(v, count, &c, &normal))
        return 0;
    return ray__polygon_at(r, v, count, c, normal, hit);
}

/*
** The point of the polygon nearest q (ray_closest_point): the polygon is
** the region inside its outline (even-odd, as ray_polygon) on its plane
** (through the vertex centroid c with the Newell normal, as
** ray_polygon's).  q's foot on the plane has the coordinates (x, y) =
** ((q - c).t1, (q - c).t2) along the plane's tangents; if it is inside,
** it is the nearest point, formed as c + x t1 + y t2, which lies on the
** plane within a few ulps of |c| + |x| + |y| whatever q's distance from
** the plane.  Else the nearest point is on the outline: the nearest of
** the edges' nearest points (a vertex exactly, or a + t (b - a)).  The
** inside test is Haines' crossings test of polygon.c's edge_crosses in
** the plane's coordinates, each vertex taken relative to the foot on its
** own; a foot within rounding of the outline may go either way, where
** both answers are within rounding of each other.
*/
int ray__polygon_closest(const ray_vec3 *v, size_t count, ray_vec3 q,
                         ray_vec3 *p, ray_vec3 *n)
{
    return ray__polygon_closest_mapped(v, count, NULL, q, p, n);
}

/* Vertex i of the polygon, mapped by xf when it is not NULL. */
ray_vec3 ray__polygon_vertex(const ray_vec3 *v, size_t i,
                             const ray_transform *xf)
{
    const double (*m)[4];

    if (xf == NULL)
        return v[i];
    m = (const double (*)[4])xf->m;
    return v3(m[0][0] * v[i].x + m[0][1] * v[i].y + m[0][2] * v[i].z + m[0][3],
              m[1][0] * v[i].x + m[1][1] * v[i].y + m[1][2] * v[i].z + m[1][3],
              m[2][0] * v[i].x + m[2][1] * v[i].y + m[2][2] * v[i].z + m[2][3]);
}

/* polygon_plane of the mapped vertices. */
static int mapped_plane(const ray_vec3 *v, size_t n, const ray_transform *xf,
                        ray_vec3 *c, ray_vec3 *normal)
{
    ray_vec3 sum = v3(0, 0, 0), area = v3(0, 0, 0);
    size_t i;

    if (xf == NULL)
        return polygon_plane(v, n, c, normal);
    for (i = 0; i < n; i++)
        sum = v3_add(sum, ray__polygon_vertex(v, i, xf));
    *c = v3_scale(sum, 1.0 / (double)n);
    for (i = 0; i < n; i++) {
        ray_vec3 a = v3_sub(ray__polygon_vertex(v, i, xf), *c);
        ray_vec3 b = v3_sub(ray__polygon_vertex(v, (i + 1) % n, xf), *c);
        area = v3_add(area, v3_cross(a, b));
    }
    *normal = area;
    return area.x != 0 || area.y != 0 || area.z != 0;
}

int ray__polygon_closest_mapped(const ray_vec3 *v, size_t count,
                                const ray_transform *xf, ray_vec3 q,
                                ray_vec3 *p, ray_vec3 *n)
{
    ray_vec3 c, normal, nn, t1, t2, rel, best, pt;
    double x, y, x0, y0, best_d = HUGE_VAL;
    int inside = 0;
    size_t i;

    if (v == NULL || count < 3 || !mapped_plane(v, count, xf, &c, &normal) ||
        !v3_normalize(normal, &nn))
        return 0;
    rel = v3_sub(q, c);
    if (!v3_isfinite(rel))
        return 0;
    ray__tangent_frame(nn, &t1, &t2);
    x = v3_dot(rel, t1);
    y = v3_dot(rel, t2);
    rel = v3_sub(ray__polygon_vertex(v, count - 1, xf), c);
    x0 = v3_dot(rel, t1) - x;
    y0 = v3_dot(rel, t2) - y;
    for (i = 0; i < count; i++) {
        double x1, y1;
        rel = v3_sub(ray__polygon_vertex(v, i, xf), c);
        x1 = v3_dot(rel, t1) - x;
        y1 = v3_dot(rel, t2) - y;
        inside ^= edge_crosses(x0, y0, x1, y1);
        x0 = x1;
        y0 = y1;
    }
    if (inside)
        pt = v3_add(c, v3_add(v3_scale(t1, x), v3_scale(t2, y)));
    else {
        best = ray__polygon_vertex(v, 0, xf);
        for (i = 0; i < count; i++) {
            ray_vec3 a = ray__polygon_vertex(v, i, xf);
            ray_vec3 b = ray__polygon_vertex(v, (i + 1) % count, xf);
            ray_vec3 e = ray__segment_closest(q, a, b);
            double d = ray__distance(e, q);
            if (d < best_d) {
                best_d = d;
                best = e;
            }
        }
        pt = best;
    }
    if (!v3_isfinite(pt))
        return 0;
    *p = pt;
    *n = nn;
    return 1;
}

int ray__polygon_plane_mapped(const ray_vec3 *v, size_t count,
                              const ray_transform *xf, ray_vec3 *c,
                              ray_vec3 *n)
{
    ray_vec3 normal;

    return v != NULL && count >= 3 && mapped_plane(v, count, xf, c, &normal) &&
           v3_normalize(normal, n);
}

/*
** Is the foot of x on the (mapped) polygon's plane inside it?  The
** crossings test of ray__polygon_closest: x's coordinates along the
** plane's tangents, each vertex relative to them on its own.
*/
int ray__polygon_contains(const ray_vec3 *v, size_t count,
                          const ray_transform *xf, ray_vec3 x)
{
    ray_vec3 c, nn, t1, t2, rel;
    double px, py, x0, y0;
    int inside = 0;
    size_t i;

    if (!ray__polygon_plane_mapped(v, count, xf, &c, &nn))
        return 0;
    ray__tangent_frame(nn, &t1, &t2);
    rel = v3_sub(x, c);
    px = v3_dot(rel, t1);
    py = v3_dot(rel, t2);
    rel = v3_sub(ray__polygon_vertex(v, count - 1, xf), c);
    x0 = v3_dot(rel, t1) - px;
    y0 = v3_dot(rel, t2) - py;
    for (i = 0; i < count; i++) {
        double x1, y1;
        rel = v3_sub(ray__polygon_vertex(v, i, xf), c);
        x1 = v3_dot(rel, t1) - px;
        y1 = v3_dot(rel, t2) - py;
        inside ^= edge_crosses(x0, y0, x1, y1);
        x0 = x1;
        y0 = y1;
    }
    return inside;
}
