/*
** ray.h -- the whole public interface of libray, a small C99 ray-tracing
** library.
**
** This header is the reference documentation; the man pages (ray(7) and
** the ray_*(3) pages) are derived from it.
**
** Conventions that hold for every function below:
**
**   * Precision is double throughout.
**   * A ray is p(t) = org + t*dir on the OPEN interval tmin < t < tmax.
**     "dir" need not be normalised, so t is measured in units of |dir|.
**     Results exactly at tmin or tmax are not hits.
**   * The intersection functions (ray_sphere, ray_triangle, ray_plane,
**     ray_polygon) return 1 for a hit and 0 for a miss.  They never fail:
**     NaN or infinite input, a zero-length direction, tmin > tmax and
**     degenerate geometry are all misses; tmax = +Inf (HUGE_VAL) is
**     allowed and is the usual unbounded ray.  On a hit they fill *hit;
**     on a miss they leave it untouched.  No NaN or Inf reaches *hit.
**   * Every other fallible function returns an int status: RAY_OK (0) on
**     success, one of the RAY_E* codes otherwise, and then leaves its
**     outputs untouched.
**   * No function keeps global state: all are reentrant and may be called
**     concurrently from any number of threads.
*/
#ifndef RAY_H
#define RAY_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(RAY_BUILD) && defined(__GNUC__)
#define RAY_API __attribute__((visibility("default")))
#else
#define RAY_API
#endif

/* ---------------------------------------------------------------- version */

#define RAY_VERSION_MAJOR 0
#define RAY_VERSION_MINOR 1
#define RAY_VERSION_PATCH 0
/* major*10000 + minor*100 + patch, for compile-time comparisons. */
#define RAY_VERSION_NUMBER 100
#define RAY_VERSION_STRING "0.1.0"

/*
** The version of the library actually linked, to compare with
** RAY_VERSION_NUMBER / RAY_VERSION_STRING of the header compiled against.
** The string is static and must not be freed.
*/
RAY_API int ray_version_number(void);
RAY_API const char *ray_version_string(void);

/* ----------------------------------------------------------------- errors */

enum {
    RAY_OK = 0,          /* success */
    RAY_EINVAL,          /* invalid argument: NULL, NaN, Inf, out of domain */
    RAY_EDEGENERATE,     /* degenerate geometry: zero area or length */
    RAY_ERANGE,          /* a result would overflow double */
    RAY_ENOMEM,          /* an allocation failed */
    RAY_EIO,             /* an I/O call failed (see errno) */
    RAY_EPNG,            /* libpng reported an error */
    RAY_ESTATE,          /* call not allowed in the object's current state */
    RAY_ECANCELED        /* the caller's progress callback cancelled */
};

/*
** A static, English, one-line description of status code "code"; an
** unknown code gives "unknown error".  Never NULL; do not free.
*/
RAY_API const char *ray_strerror(int code);

/* ------------------------------------------------------------ value types */

typedef struct ray_vec3 {
    double x, y, z;
} ray_vec3;

/* The ray p(t) = org + t*dir, valid for tmin < t < tmax. */
typedef struct ray_ray {
    ray_vec3 org;
    ray_vec3 dir;
    double tmin, tmax;
} ray_ray;

/* An identifier that names no geometry (hits from the bare primitives). */
#define RAY_INVALID_ID 0xffffffffu

/*
** What an intersection reports.  Everything a robust secondary ray needs is
** here: the geometric normal (never a shading normal) and a bound on the
** rounding error of the hit point -- the box p +- p_err (per component)
** contains a point of the exact surface -- so an offset can be scaled to
** it rather than to a fixed epsilon (pbrt-v4 section 6.8, "pError").
*/
typedef struct ray_hit {
    double t;          /* ray parameter of the hit, tmin < t < tmax */
    ray_vec3 p;        /* hit point, computed on the surface (see p_err) */
    ray_vec3 n;        /* geometric unit normal (orientation: see each fn) */
    double u, v;       /* the primitive's own parametric coordinates */
    ray_vec3 p_err;    /* the exact surface passes within p +- p_err */
    unsigned geom_id;  /* which geometry; RAY_INVALID_ID from primitives */
    unsigned prim_id;  /* which primitive inside it; likewise */
} ray_hit;

/* --------------------------------------------- the lecture's primitives */

/*
** ray_sphere -- ray against the sphere |p - center| = radius.
**
** Solves the lecture's quadratic (d.d)t^2 + 2d.(e-c)t + (e-c).(e-c) - R^2
** in a cancellation-free arrangement (Ray Tracing Gems ch. 7): the
** discriminant is taken from the distance between the centre and the ray's
** line, and the two roots from q = b' + sign(b')sqrt(a*disc): t0 = c/q,
** t1 = q/a.  Discriminant < 0: miss; = 0: tangent (one root); > 0: two
** roots.  Returns the nearest root in (tmin, tmax), so a ray starting
** inside the sphere hits the far side.
**
** On a hit: n = (p - center)/radius (outward, also from inside); p is
** projected back onto the sphere; u = longitude in [0, 1] around +y
** (atan2(n.x, n.z)/2pi + 1/2), v = latitude in [0, 1] from -y (0) to +y (1).
** A radius that is not finite and > 0 is a miss.
*/
RAY_API int ray_sphere(const ray_ray *r, ray_vec3 center, double radius,
                       ray_hit *hit);

/*
** ray_triangle -- ray against triangle (a, b, c).
**
** Shirley's Cramer's-rule formulation: solve
**     [a-b, a-c, dir] [beta gamma t]^T = a - org
** and hit iff beta >= 0, gamma >= 0, beta + gamma <= 1, tmin < t < tmax.
** Edges and vertices are inclusive.  Only an exactly singular system is
** rejected (no epsilon on the determinant): tiny triangles still hit;
** parallel rays and zero-area triangles miss.
**
** On a hit: u = beta, v = gamma, so p = (1-u-v)*a + u*b + v*c (p is
** computed this way, on the triangle, not as org + t*dir);
** n = normalize((b-a) x (c-a)), i.e. counter-clockwise is the front.
*/
RAY_API int ray_triangle(const ray_ray *r, ray_vec3 a, ray_vec3 b,
                         ray_vec3 c, ray_hit *hit);

/*
** ray_plane -- ray against the plane through "point" with normal "normal"
** (any non-zero length).
**
** t = (point - org).n / (dir.n).  A ray parallel to the plane or lying in
** it (dir.n == 0) misses.  On a hit: n = normal/|normal| (as given, not
** flipped toward the ray); p is projected back onto the plane; (u, v) are
** the coordinates of p - point along two unit tangents t1, t2 such that
** (t1, t2, n) is a right-handed orthonormal frame (Duff et al., "Building
** an Orthonormal Basis, Revisited", JCGT 6(1), 2017): for n = +y,
** t1 = +x and t2 = -z.
*/
RAY_API int ray_plane(const ray_ray *r, ray_vec3 point, ray_vec3 normal,
                      ray_hit *hit);

/*
** ray_polygon -- ray against the planar polygon v[0..n-1] (n >= 3).
**
** The polygon's plane passes through the vertex centroid with the area
** (Newell) normal, which is robust for concave polygons.  After the plane
** hit, the inside test is made in the projection ALONG THE RAY: the
** polygon as seen from the ray origin, where the ray is the point (0, 0)
** and each vertex is transformed on its own (the translate-permute-shear
** of Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
** 2(1), 2013).  So the test does not depend on the rounded plane hit.
**
** Inside rule: EVEN-ODD (Haines' crossings test, Graphics Gems IV), so a
** self-intersecting polygon has holes where it overlaps itself.  Ties are
** broken as if the ray were moved by an infinitesimal amount: the
** half-open rule for vertices on the test line, and a point exactly on an
** edge counts as lying left of it.  Each edge is evaluated from its two
** vertices in an order that does not depend on the polygon's winding, so
** polygons sharing an edge decide it identically: a ray through a shared
** edge or vertex of a polygon mesh hits an odd number of its polygons
** (exactly one across an edge), never none.
**
** On a hit: n = the unit Newell normal (counter-clockwise front); u, v as
** for ray_plane with point = v[0].  Fewer than 3 vertices, v == NULL or a
** zero-area polygon: miss.  The array is only read during the call.
*/
RAY_API int ray_polygon(const ray_ray *r, const ray_vec3 *v, size_t n,
                        ray_hit *hit);

/*
** ray_barycentric -- barycentric coordinates of "p" in triangle (a, b, c).
**
** By signed areas, as in the lecture: with N = (b-a) x (c-a),
**     alpha ~ ((c-b) x (p-b)).N,  beta ~ ((a-c) x (p-c)).N,
**     gamma ~ ((b-a) x (p-a)).N,
** each divided by their sum (which is N.N in exact arithmetic), so the
** sign of each area comes from its dot product with N and
** alpha + beta + gamma = 1 to within a few ulps.  A point off the plane is
** treated as its orthogonal projection onto it.  The convention matches
** ray_triangle: beta = hit.u, gamma = hit.v, p = alpha*a + beta*b + gamma*c.
**
** Writes abg[0..2] = (alpha, beta, gamma) and, if "inside" is not NULL,
** *inside = 1 when all three are >= 0 (edges included), else 0.
** Returns RAY_OK; RAY_EINVAL if abg is NULL or an input is not finite;
** RAY_EDEGENERATE for a zero-area triangle; RAY_ERANGE if the areas
** overflow.  On error nothing is written.
*/
RAY_API int ray_barycentric(ray_vec3 p, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                            double abg[3], int *inside);

/* ------------------------------------------------------------------ images */

/*
** ray_image_to_srgb8 -- encode "count" linear RGB float pixels (3 floats
** each) as 8-bit sRGB (IEC 61966-2-1 transfer curve, rounded to nearest).
** Values are clamped to [0, 1]; NaN becomes 0.  "out" receives 3*count
** bytes.  Returns RAY_OK, or RAY_EINVAL for a NULL pointer.
*/
RAY_API int ray_image_to_srgb8(const float *rgb, size_t count,
                               unsigned char *out);

/*
** ray_write_png -- write a width x height image of linear RGB floats
** (3 per pixel, rows top to bottom, no padding) to the file "path" through
** libpng.  bits = 8 writes 8-bit sRGB (with an sRGB chunk); bits = 16
** writes 16-bit LINEAR samples with gAMA 1.0, for tools that want the
** unquantised data.  Values are clamped to [0, 1]; NaN becomes 0.
**
** Returns RAY_OK; RAY_EINVAL for NULL arguments, a zero or too large size
** or bits other than 8 and 16; RAY_ENOMEM; RAY_EIO if the file cannot be
** created or written (errno tells why); RAY_EPNG if libpng fails.  A file
** that failed is removed.  Thread-safe; the image is only read.
*/
RAY_API int ray_write_png(const char *path, const float *rgb,
                          unsigned width, unsigned height, int bits);

#ifdef __cplusplus
}
#endif

#endif /* RAY_H */
