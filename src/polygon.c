/*
** polygon.c -- ray / planar polygon: the plane hit, then an inside test.
*/
#include <stddef.h>

#include "internal.h"

/*
** The ray's frame: the axis kz of dir's largest component, the two others
** kx, ky, and the shear that maps dir onto that axis (Woop, Benthin, Wald,
** "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013, section 3).
*/
typedef struct ray_frame {
    int kx, ky, kz;
    double sx, sy;
    ray_vec3 org;
} ray_frame;

static double component(ray_vec3 v, int k)
{
    return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

static void frame_init(ray_frame *f, const ray_ray *r)
{
    ray_vec3 ad = v3_abs(r->dir);
    double dz;

    f->kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    f->kx = (f->kz + 1) % 3;
    f->ky = (f->kx + 1) % 3;
    dz = component(r->dir, f->kz);
    f->sx = component(r->dir, f->kx) / dz;
    f->sy = component(r->dir, f->ky) / dz;
    f->org = r->org;
}

/*
** Vertex v as seen along the ray: translated to the ray origin and
** sheared so the ray is the point (0, 0).  The result depends on v and the
** ray alone, so two polygons sharing v get bit-identical 2-D vertices.
*/
static void frame_project(const ray_frame *f, ray_vec3 v, double *x,
                          double *y)
{
    ray_vec3 a = v3_sub(v, f->org);
    double az = component(a, f->kz);

    *x = component(a, f->kx) - f->sx * az;
    *y = component(a, f->ky) - f->sy * az;
}

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

/* Even-odd count of the polygon's edges crossing the ray's +x half-line. */
static int inside_along_ray(const ray_ray *r, const ray_vec3 *v, size_t n)
{
    ray_frame f;
    double x0, y0, x1, y1, xf, yf;
    int inside = 0;
    size_t i;

    frame_init(&f, r);
    frame_project(&f, v[0], &xf, &yf);
    x0 = xf;
    y0 = yf;
    for (i = 1; i <= n; i++) {
        if (i < n)
            frame_project(&f, v[i], &x1, &y1);
        else {
            x1 = xf;
            y1 = yf;
        }
        inside ^= edge_crosses(x0, y0, x1, y1);
        x0 = x1;
        y0 = y1;
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

int ray_polygon(const ray_ray *r, const ray_vec3 *v, size_t count,
                ray_hit *hit)
{
    ray_vec3 c, normal, n;
    double denom, t;

    if (v == NULL || count < 3 || !polygon_plane(v, count, &c, &normal))
        return 0;
    denom = v3_dot(r->dir, normal);
    if (denom == 0)
        return 0;
    t = v3_dot(v3_sub(c, r->org), normal) / denom;
    if (!(t > r->tmin && t < r->tmax))
        return 0;
    if (!inside_along_ray(r, v, count) || !v3_normalize(normal, &n))
        return 0;
    return ray__plane_fill(r, c, n, v[0], t, hit);
}
