/* SPDX-License-Identifier: MIT */
/*
** fuzz_primitives.c -- the bare primitives, optics and secondary rays
** with arbitrary doubles, their documented guarantees as checks:
**
**   * the intersection functions return 1 or 0; a hit lies in
**     (tmin, tmax) with nothing NaN or Inf, a unit normal, p_err >= 0 and
**     the primitive's (u, v) range; a miss leaves *hit untouched; NULL
**     pointers are misses (ray.h, the conventions; defect 7 for the
**     functions that do not yet say so);
**   * a ray spawned off a flat primitive (or outward off a sphere) never
**     hits that primitive again (ray_spawn: no acne);
**   * ray_barycentric, ray_spawn*, ray_refract: statuses as documented,
**     outputs untouched on failure, finite on success.
**
** Input: a sequence of operations, each an opcode byte then its values.
*/
#include "fuzz.h"

/* The last hit found, for ray_spawn and the re-hit checks. */
typedef struct prim_state {
    int have_hit;
    ray_hit hit;
    int kind;                    /* OP_SPHERE, OP_TRIANGLE, OP_PLANE */
    ray_vec3 a, b, c;            /* the primitive: vertices, or point and
                                    normal, or centre and (radius, 0, 0) */
} prim_state;

enum {
    OP_SPHERE, OP_TRIANGLE, OP_WATERTIGHT, OP_PLANE, OP_POLYGON, OP_TORUS,
    OP_BARYCENTRIC, OP_SPAWN, OP_SPAWN_TO, OP_REFLECT, OP_REFRACT,
    OP_FRESNEL, OP_COUNT
};

/* Bits of a flags byte: which pointer to pass as NULL. */
#define NULL_RAY 1u
#define NULL_HIT 2u

/*
** The common part of every intersection call: "rc" is its answer for
** ray r with output *hit, which was prefilled with the sentinel.
*/
static void check_answer(int rc, const ray_ray *r, const ray_hit *hit,
                         int flat, const char *what)
{
    FUZZ_CHECK(rc == 0 || rc == 1, what);
    if (rc == 0) {
        FUZZ_CHECK(fuzz_untouched(hit, sizeof *hit), what);
        return;
    }
    fuzz_check_hit(r, hit, flat, what);
    FUZZ_CHECK(hit->geom_id == RAY_INVALID_ID &&
                   hit->prim_id == RAY_INVALID_ID, what);
}

/* Whether NULL pointers may be passed to function "op" today. */
static int null_allowed(int op)
{
    (void)op;
    return 1;
}

static const ray_ray *maybe_null_ray(unsigned flags, int op, const ray_ray *r)
{
    return (flags & NULL_RAY) && null_allowed(op) ? NULL : r;
}

static ray_hit *maybe_null_hit(unsigned flags, int op, ray_hit *h)
{
    return (flags & NULL_HIT) && null_allowed(op) ? NULL : h;
}

/* Remember a hit for the spawn operations. */
static void keep_hit(prim_state *st, int kind, const ray_hit *h, ray_vec3 a,
                     ray_vec3 b, ray_vec3 c)
{
    st->have_hit = 1;
    st->hit = *h;
    st->kind = kind;
    st->a = a;
    st->b = b;
    st->c = c;
}

static void op_sphere(fuzz_input *in, prim_state *st)
{
    unsigned flags = fuzz_u8(in);
    ray_ray r = fuzz_ray(in);
    ray_vec3 c = fuzz_vec3(in), rad;
    double radius = fuzz_double(in);
    const ray_ray *rp = maybe_null_ray(flags, OP_SPHERE, &r);
    ray_hit hit, *hp = maybe_null_hit(flags, OP_SPHERE, &hit);
    int rc;

    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_sphere(rp, c, radius, hp);
    if (rp == NULL || hp == NULL) {
        FUZZ_CHECK(rc == 0, "ray_sphere: NULL is a miss");
        return;
    }
    check_answer(rc, &r, &hit, 0, "ray_sphere");
    if (rc == 1) {
        FUZZ_CHECK(hit.u >= 0 && hit.u <= 1 && hit.v >= 0 && hit.v <= 1,
                   "ray_sphere: u, v in [0, 1]");
        rad.x = radius;
        rad.y = rad.z = 0;
        keep_hit(st, OP_SPHERE, &hit, c, rad, rad);
    }
}

/*
** Barycentrics from a hit: u, v >= 0 and u + v <= 1 up to the rounding of
** two divisions and their sum (a few ulps of 1; Higham, section 2.2).
*/
#define BARY_SUM_TOL (4 * DBL_EPSILON)

static void op_triangle(fuzz_input *in, prim_state *st, int watertight)
{
    int op = watertight ? OP_WATERTIGHT : OP_TRIANGLE;
    const char *what = watertight ? "ray_triangle_watertight" : "ray_triangle";
    unsigned flags = fuzz_u8(in);
    ray_ray r = fuzz_ray(in);
    ray_vec3 a = fuzz_vec3(in), b = fuzz_vec3(in), c = fuzz_vec3(in);
    const ray_ray *rp = maybe_null_ray(flags, op, &r);
    ray_hit hit, *hp = maybe_null_hit(flags, op, &hit);
    int rc;

    fuzz_sentinel(&hit, sizeof hit);
    rc = watertight ? ray_triangle_watertight(rp, a, b, c, hp)
                    : ray_triangle(rp, a, b, c, hp);
    if (rp == NULL || hp == NULL) {
        FUZZ_CHECK(rc == 0, what);
        return;
    }
    check_answer(rc, &r, &hit, 0, what);
    if (rc == 1) {
        FUZZ_CHECK(hit.u >= 0 && hit.v >= 0 && hit.u + hit.v <= 1 + BARY_SUM_TOL,
                   what);
        keep_hit(st, OP_TRIANGLE, &hit, a, b, c);
    }
}

static void op_plane(fuzz_input *in, prim_state *st)
{
    unsigned flags = fuzz_u8(in);
    ray_ray r = fuzz_ray(in);
    ray_vec3 point = fuzz_vec3(in), normal = fuzz_vec3(in);
    const ray_ray *rp = maybe_null_ray(flags, OP_PLANE, &r);
    ray_hit hit, *hp = maybe_null_hit(flags, OP_PLANE, &hit);
    int rc;

    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_plane(rp, point, normal, hp);
    if (rp == NULL || hp == NULL) {
        FUZZ_CHECK(rc == 0, "ray_plane: NULL is a miss");
        return;
    }
    check_answer(rc, &r, &hit, 1, "ray_plane");
    if (rc == 1)
        keep_hit(st, OP_PLANE, &hit, point, normal, normal);
}

#define MAX_POLY 9

static void op_polygon(fuzz_input *in)
{
    unsigned flags = fuzz_u8(in);
    ray_ray r = fuzz_ray(in);
    size_t n = fuzz_below(in, MAX_POLY + 1), i;
    ray_vec3 v[MAX_POLY];
    const ray_ray *rp = maybe_null_ray(flags, OP_POLYGON, &r);
    ray_hit hit, *hp = maybe_null_hit(flags, OP_POLYGON, &hit);
    int rc;

    for (i = 0; i < n; i++)
        v[i] = fuzz_vec3(in);
    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_polygon(rp, flags & 4 ? NULL : v, n, hp);
    if (rp == NULL || hp == NULL || (flags & 4) || n < 3) {
        FUZZ_CHECK(rc == 0, "ray_polygon: NULL or n < 3 is a miss");
        return;
    }
    check_answer(rc, &r, &hit, 1, "ray_polygon");
}

static void op_torus(fuzz_input *in)
{
    unsigned flags = fuzz_u8(in);
    ray_ray r = fuzz_ray(in);
    ray_torus_params t;
    const ray_ray *rp = maybe_null_ray(flags, OP_TORUS, &r);
    ray_hit hit, *hp = maybe_null_hit(flags, OP_TORUS, &hit);
    int rc;

    t.center = fuzz_vec3(in);
    t.axis = fuzz_vec3(in);
    t.major = fuzz_double(in);
    t.minor = fuzz_double(in);
    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_torus(rp, flags & 4 ? NULL : &t, hp);
    if (rp == NULL || hp == NULL || (flags & 4) ||
        !(t.minor > 0 && t.minor < t.major)) {
        FUZZ_CHECK(rc == 0, "ray_torus: NULL or not a ring torus: a miss");
        FUZZ_CHECK(fuzz_untouched(&hit, sizeof hit), "ray_torus: miss");
        return;
    }
    check_answer(rc, &r, &hit, 0, "ray_torus");
    if (rc == 1)
        FUZZ_CHECK(hit.u >= 0 && hit.u <= 1 && hit.v >= 0 && hit.v <= 1,
                   "ray_torus: u, v in [0, 1]");
}

/*
** alpha + beta + gamma = 1 "to within a few ulps" (ray.h): 8 ulps of 1.
** Defect 6: far from a small triangle the sum is off by 3e-8.
*/
#define BARY_ONE_TOL (8 * DBL_EPSILON)

static void op_barycentric(fuzz_input *in)
{
    unsigned flags = fuzz_u8(in);
    ray_vec3 p = fuzz_vec3(in), a = fuzz_vec3(in), b = fuzz_vec3(in),
             c = fuzz_vec3(in);
    double abg[3];
    int inside, rc;

    fuzz_sentinel(abg, sizeof abg);
    fuzz_sentinel(&inside, sizeof inside);
    rc = ray_barycentric(p, a, b, c, flags & 1 ? NULL : abg,
                         flags & 2 ? NULL : &inside);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL || rc == RAY_EDEGENERATE ||
                   rc == RAY_ERANGE, "ray_barycentric: status");
    if (rc != RAY_OK || (flags & 1)) {
        FUZZ_CHECK((flags & 1) == 0 || rc == RAY_EINVAL,
                   "ray_barycentric: NULL abg is RAY_EINVAL");
        FUZZ_CHECK(fuzz_untouched(abg, sizeof abg) &&
                       fuzz_untouched(&inside, sizeof inside),
                   "ray_barycentric: nothing written on error");
        return;
    }
    FUZZ_CHECK(isfinite(abg[0]) && isfinite(abg[1]) && isfinite(abg[2]),
               "ray_barycentric: finite coordinates");
    FUZZ_CHECK(fabs(abg[0] + abg[1] + abg[2] - 1) <=
                   3 * DBL_EPSILON *
                       (fabs(abg[0]) + fabs(abg[1]) + fabs(abg[2])),
               "ray_barycentric: |alpha + beta + gamma - 1| <= 3 eps "
               "(|alpha| + |beta| + |gamma|)");
    if (flags & 2)
        FUZZ_CHECK(fuzz_untouched(&inside, sizeof inside),
                   "ray_barycentric: inside NULL");
    else
        FUZZ_CHECK(inside == (abg[0] >= 0 && abg[1] >= 0 && abg[2] >= 0),
                   "ray_barycentric: inside iff all three >= 0");
}

/*
** The no-acne promise, where it is exact: a flat primitive cannot be hit
** again by a ray that leaves it (from either side), nor a sphere by one
** that leaves it outward.  Only for directions clearly off the tangent
** plane: the side is decided by the rounded dot(dir, n), whose error is
** below gamma(3) sum |dir_i n_i| (Higham, section 3.1); a grazing ray
** sent to the wrong side may cross the surface at a real distance.
*/
static void check_no_rehit(const prim_state *st, const ray_ray *s, ray_vec3 dir)
{
    const ray_hit *h = &st->hit;
    double dn = dir.x * h->n.x + dir.y * h->n.y + dir.z * h->n.z;
    double mag = fabs(dir.x * h->n.x) + fabs(dir.y * h->n.y) +
                 fabs(dir.z * h->n.z);
    ray_hit again;
    int rc = 0;

    /* The unit normal's components are exact only to a subnormal: one
    ** that underflowed (a triangle spanning 1e-150 to 5e216: its true
    ** normal has components ~1e-367) is 0, so dot(dir, n) is uncertain
    ** by |dir|_1 times the smallest subnormal too; within that, the side
    ** dir leaves to is undecided and a re-hit may be real. */
    if (!(fabs(dn) > 4 * DBL_EPSILON * mag +
                     4 * 0x1p-1074 * (fabs(dir.x) + fabs(dir.y) +
                                      fabs(dir.z))))
        return;
    if (st->kind == OP_TRIANGLE)
        rc = ray_triangle_watertight(s, st->a, st->b, st->c, &again) |
             ray_triangle(s, st->a, st->b, st->c, &again);
    else if (st->kind == OP_PLANE)
        rc = ray_plane(s, st->a, st->b, &again);
    else if (st->kind == OP_SPHERE && dn > 0)
        rc = ray_sphere(s, st->a, st->b.x, &again);
    FUZZ_CHECK(rc == 0, "ray_spawn: the spawned ray hits its own surface");
}

static ray_hit spawn_source(fuzz_input *in, const prim_state *st, int *real)
{
    ray_hit h;
    *real = st->have_hit && (fuzz_u8(in) & 1);
    if (*real)
        return st->hit;
    memset(&h, 0, sizeof h);
    h.p = fuzz_vec3(in);
    h.n = fuzz_vec3(in);
    h.p_err = fuzz_vec3(in);
    return h;
}

static void op_spawn(fuzz_input *in, const prim_state *st, int to)
{
    int real;
    ray_hit h = spawn_source(in, st, &real);
    ray_vec3 v = fuzz_vec3(in);
    ray_ray out;
    int rc;

    fuzz_sentinel(&out, sizeof out);
    rc = to ? ray_spawn_to(&h, v, &out) : ray_spawn(&h, v, &out);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL, "ray_spawn: status");
    if (rc != RAY_OK) {
        FUZZ_CHECK(fuzz_untouched(&out, sizeof out), "ray_spawn: untouched");
        return;
    }
    FUZZ_CHECK(fuzz_finite3(out.org) && fuzz_finite3(out.dir) &&
                   (out.dir.x != 0 || out.dir.y != 0 || out.dir.z != 0),
               "ray_spawn: a finite ray");
    FUZZ_CHECK(out.tmin == 0 && out.tmax == (to ? 1.0 : HUGE_VAL),
               "ray_spawn: tmin = 0, tmax = +Inf (1 for ray_spawn_to)");
    if (real && !to)
        check_no_rehit(st, &out, out.dir);
    fuzz_sentinel(&out, sizeof out);
    FUZZ_CHECK((to ? ray_spawn_to(NULL, v, &out) : ray_spawn(NULL, v, &out)) ==
                       RAY_EINVAL &&
                   (to ? ray_spawn_to(&h, v, NULL) : ray_spawn(&h, v, NULL)) ==
                       RAY_EINVAL &&
                   fuzz_untouched(&out, sizeof out),
               "ray_spawn: NULL is RAY_EINVAL");
}

static void op_optics(fuzz_input *in, int op)
{
    ray_vec3 d = fuzz_vec3(in), n = fuzz_vec3(in), out;
    double eta = fuzz_double(in);

    if (op == OP_REFLECT) {
        (void)ray_reflect(d, n);        /* no promise beyond no crash */
    } else if (op == OP_REFRACT) {
        double n2 = n.x * n.x + n.y * n.y + n.z * n.z;
        int rc;
        fuzz_sentinel(&out, sizeof out);
        rc = ray_refract(d, n, eta, &out);
        FUZZ_CHECK(rc == 0 || rc == 1, "ray_refract: 1 or 0");
        if (rc == 0)
            FUZZ_CHECK(fuzz_untouched(&out, sizeof out),
                       "ray_refract: nothing written on 0");
        else if (fabs(n2 - 1) <= FUZZ_UNIT_TOL)
            /* For a unit normal, as documented: a unit direction. */
            FUZZ_CHECK(fuzz_finite3(out) &&
                           fabs(out.x * out.x + out.y * out.y +
                                out.z * out.z - 1) <= FUZZ_UNIT_TOL,
                       "ray_refract: a unit direction");
        FUZZ_CHECK(ray_refract(d, n, eta, NULL) == 0,
                   "ray_refract: NULL out is 0");
    } else {
        double cos_i = fuzz_double(in);
        double f = ray_fresnel(cos_i, eta);
        if (cos_i >= 0 && cos_i <= 1 && eta > 0 && isfinite(eta))
            FUZZ_CHECK(f >= 0 && f <= 1, "ray_fresnel: a reflectance");
    }
}

/* Operations per input: enough for a hit and its spawned rays. */
#define MAX_OPS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_of(data, size);
    prim_state st;
    int ops = 0;

    memset(&st, 0, sizeof st);
    while (fuzz_more(&in) && ops++ < MAX_OPS) {
        int op = (int)fuzz_below(&in, OP_COUNT);
        switch (op) {
        case OP_SPHERE: op_sphere(&in, &st); break;
        case OP_TRIANGLE: op_triangle(&in, &st, 0); break;
        case OP_WATERTIGHT: op_triangle(&in, &st, 1); break;
        case OP_PLANE: op_plane(&in, &st); break;
        case OP_POLYGON: op_polygon(&in); break;
        case OP_TORUS: op_torus(&in); break;
        case OP_BARYCENTRIC: op_barycentric(&in); break;
        case OP_SPAWN: op_spawn(&in, &st, 0); break;
        case OP_SPAWN_TO: op_spawn(&in, &st, 1); break;
        default: op_optics(&in, op); break;
        }
    }
    return 0;
}
