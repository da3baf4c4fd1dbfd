/* SPDX-License-Identifier: MIT */
/*
** fuzz_surfaces.c -- ray_implicit and ray_parametric (and the surfaces
** the library builds for them: ray__implicit_torus, ray_implicit_blobs,
** ray_bezier_surface) with hostile callbacks: fields that turn NaN, Inf
** or huge in part of the box, lie about their Lipschitz bound, or vanish
** on a slab; gradients that are NaN, zero or huge; (u, v) callbacks that
** give NaN; surfaces whose partials vanish or are NaN, boxes that are
** NaN, inverted, too small or enormous; any descriptor settings.
**
** Checked: the answer is 1, 0, -RAY_ELIMIT or -RAY_EINVAL; *hit untouched
** unless 1; a hit keeps the hit contract (finite, unit normal, in
** (tmin, tmax)) and, for ray_parametric, (u, v) in the domain; the field
** is evaluated at most max_iterations times (plus a fixed allowance for
** the hit's normal), so a slow callback cannot run without bound.
*/
#include "fuzz.h"
#include "prim/prim.h"         /* ray__implicit_torus (internal) */

/*
** Subdivision levels as decoded: ray_parametric bounds its work per ray
** (its descent budget), so even 12 levels cost at most ~2^18 boxes.
*/
static unsigned capped_levels(unsigned levels)
{
    return levels;
}

/* --------------------------------------------------------- the fields */

enum { BASE_SPHERE, BASE_PLANE, BASE_TORUS, BASE_BLOBS, BASE_COUNT };
enum {
    HOSTILE_NONE, HOSTILE_NAN, HOSTILE_INF, HOSTILE_HUGE, HOSTILE_STEEP,
    HOSTILE_FLAT, HOSTILE_WIGGLE, HOSTILE_TINY, HOSTILE_COUNT
};
enum { GRAD_NONE, GRAD_TRUE, GRAD_NAN, GRAD_ZERO, GRAD_HUGE, GRAD_COUNT };

typedef struct field {
    int base, hostile, grad, uv_nan;
    ray_vec3 c;                   /* centre, or point of the plane */
    double r;                     /* radius */
    double cut;                   /* where the hostility starts (x >) */
    double amount;                /* its size */
    ray_implicit_surface inner;   /* torus or blobs, from the library */
    ray_torus_params torus;
    ray_blob blobs[2];
    ray_blobs_params blob_params;
    unsigned long evals;          /* calls of f */
} field;

static double base_f(field *fd, ray_vec3 p)
{
    double x = p.x - fd->c.x, y = p.y - fd->c.y, z = p.z - fd->c.z;
    switch (fd->base) {
    case BASE_SPHERE: return sqrt(x * x + y * y + z * z) - fd->r;
    case BASE_PLANE: return y;
    default: return fd->inner.f(fd->inner.ud, p);
    }
}

static double hostile_f(void *ud, ray_vec3 p)
{
    field *fd = (field *)ud;
    double f = base_f(fd, p);

    fd->evals++;
    if (!(p.x > fd->cut))
        return f;
    switch (fd->hostile) {
    case HOSTILE_NAN: return (double)NAN;
    case HOSTILE_INF: return f < 0 ? -HUGE_VAL : HUGE_VAL;
    case HOSTILE_HUGE: return f * 1e300;
    case HOSTILE_STEEP: return f * fd->amount;  /* above the Lipschitz bound */
    case HOSTILE_FLAT: return 0;
    case HOSTILE_WIGGLE: return f + fd->amount * sin(1e3 * p.x);
    case HOSTILE_TINY: return f * 1e-310;
    default: return f;
    }
}

static ray_vec3 hostile_gradient(void *ud, ray_vec3 p)
{
    field *fd = (field *)ud;
    ray_vec3 g = {0, 0, 0};
    double x = p.x - fd->c.x, y = p.y - fd->c.y, z = p.z - fd->c.z;

    switch (fd->grad) {
    case GRAD_TRUE:
        if (fd->base == BASE_SPHERE) {
            g.x = x;
            g.y = y;
            g.z = z;
        } else if (fd->base == BASE_PLANE) {
            g.y = 1;
        } else if (fd->inner.gradient != NULL) {
            g = fd->inner.gradient(fd->inner.ud, p);
        }
        break;
    case GRAD_NAN: g.x = g.y = g.z = (double)NAN; break;
    case GRAD_HUGE: g.x = 1e308; g.y = -1e308; g.z = 1e308; break;
    default: break;
    }
    return g;
}

static void hostile_uv(void *ud, ray_vec3 p, ray_vec3 n, double *u, double *v)
{
    const field *fd = (const field *)ud;
    (void)n;
    *u = fd->uv_nan ? (double)NAN : p.x;
    *v = fd->uv_nan ? (double)NAN : p.y;
}

/* The hit contract of the iterative functions (ray.h). */
static void check_iterative(int rc, const ray_ray *r, const ray_hit *hit,
                            const char *what)
{
    FUZZ_CHECK(rc == 1 || rc == 0 || rc == -RAY_ELIMIT || rc == -RAY_EINVAL,
               what);
    if (rc != 1) {
        FUZZ_CHECK(fuzz_untouched(hit, sizeof *hit), what);
        return;
    }
    fuzz_check_hit(r, hit, 0, what);
}

/*
** Evaluations of f beyond max_iterations: the hit's normal by central
** differences (6 calls) and the decision at the hit (a few more).  The
** bound is the fuzzer's, generous; ray.h says "max_iterations
** evaluations of f per ray".
*/
#define EVAL_ALLOWANCE 16

/* The effective budget: ray.h's default when the field is 0. */
#define IMPLICIT_DEFAULT_ITERATIONS 100000u

static void op_implicit(fuzz_input *in)
{
    field fd;
    ray_implicit_surface s;
    ray_ray r;
    ray_hit hit;
    unsigned how;
    int rc;

    memset(&fd, 0, sizeof fd);
    fd.base = (int)fuzz_below(in, BASE_COUNT);
    fd.hostile = (int)fuzz_below(in, HOSTILE_COUNT);
    fd.grad = (int)fuzz_below(in, GRAD_COUNT);
    fd.uv_nan = (int)(fuzz_u8(in) & 1);
    fd.c = fuzz_vec3(in);
    fd.r = fuzz_double(in);
    fd.cut = fuzz_double(in);
    fd.amount = fuzz_double(in);
    memset(&s, 0, sizeof s);
    if (fd.base == BASE_TORUS) {
        fd.torus.center = fd.c;
        fd.torus.axis = fuzz_vec3(in);
        fd.torus.major = fd.r;
        fd.torus.minor = fuzz_double(in);
        rc = ray__implicit_torus(&fd.torus, &fd.inner);
        FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL, "ray__implicit_torus");
        if (rc != RAY_OK)
            return;
        s = fd.inner;
    } else if (fd.base == BASE_BLOBS) {
        fd.blobs[0].center = fd.c;
        fd.blobs[0].radius = fd.r;
        fd.blobs[0].strength = fuzz_double(in);
        fd.blobs[1].center = fuzz_vec3(in);
        fd.blobs[1].radius = fuzz_double(in);
        fd.blobs[1].strength = fuzz_double(in);
        fd.blob_params.blobs = fd.blobs;
        fd.blob_params.count = 1 + (fuzz_u8(in) & 1);
        fd.blob_params.threshold = fuzz_double(in);
        rc = ray_implicit_blobs(&fd.blob_params, &fd.inner);
        FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL, "ray_implicit_blobs");
        if (rc != RAY_OK)
            return;
        s = fd.inner;
    }
    /* The callbacks are always the fuzzer's, over the library's field. */
    s.f = hostile_f;
    s.gradient = fd.grad == GRAD_NONE ? NULL : hostile_gradient;
    s.uv = fuzz_u8(in) & 1 ? hostile_uv : NULL;
    s.ud = &fd;
    how = fuzz_u8(in);
    if (fd.base < BASE_TORUS || (how & 1)) {
        s.lo = fuzz_vec3(in);
        s.hi = fuzz_vec3(in);
    }
    if (how & 2)
        s.lipschitz = fuzz_double(in);
    if (how & 4)
        s.step = fuzz_double(in);
    if (how & 8)
        s.tolerance = fuzz_double(in);
    /* Mostly small budgets, sometimes the default (0): 100,000. */
    s.max_iterations = (how & 48) == 48 ? 0 : 1 + fuzz_below(in, 1024);
    r = fuzz_ray(in);
    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_implicit(&r, &s, &hit);
    check_iterative(rc, &r, &hit, "ray_implicit");
    FUZZ_CHECK(fd.evals <= (s.max_iterations ? s.max_iterations
                                             : IMPLICIT_DEFAULT_ITERATIONS) +
                               EVAL_ALLOWANCE,
               "ray_implicit: at most max_iterations evaluations of f");
    if (rc == 1 && s.uv != NULL)
        FUZZ_CHECK(!fd.uv_nan, "ray_implicit: NaN (u, v) is -RAY_EINVAL");
    FUZZ_CHECK(ray_implicit(NULL, &s, &hit) == -RAY_EINVAL &&
                   ray_implicit(&r, NULL, &hit) == -RAY_EINVAL &&
                   ray_implicit(&r, &s, NULL) == -RAY_EINVAL,
               "ray_implicit: NULL is -RAY_EINVAL");
}

/* ------------------------------------------------------- parametric */

enum {
    EVAL_TRUE, EVAL_NAN, EVAL_INF, EVAL_HUGE, EVAL_FLAT_PARTIALS,
    EVAL_NAN_PARTIALS, EVAL_COUNT
};
enum {
    BOX_TRUE, BOX_NAN, BOX_INVERTED, BOX_SMALL, BOX_ENORMOUS, BOX_COUNT
};

typedef struct patch {
    int eval, box;
    ray_vec3 c;
    double r;
    double cut;                   /* hostility for u > cut */
    unsigned long evals, boxes;
} patch;

/* A sphere as S(u, v), or its hostile variants. */
static void patch_eval(void *ud, double u, double v, ray_vec3 *s,
                       ray_vec3 *su, ray_vec3 *sv)
{
    patch *p = (patch *)ud;
    double pi = 3.141592653589793, cu = cos(2 * pi * u), snu = sin(2 * pi * u);
    double cv = cos(pi * v), snv = sin(pi * v);

    p->evals++;
    s->x = p->c.x + p->r * cu * snv;
    s->y = p->c.y - p->r * cv;
    s->z = p->c.z + p->r * snu * snv;
    su->x = -2 * pi * p->r * snu * snv;
    su->y = 0;
    su->z = 2 * pi * p->r * cu * snv;
    sv->x = pi * p->r * cu * cv;
    sv->y = pi * p->r * snv;
    sv->z = pi * p->r * snu * cv;
    if (!(u > p->cut))
        return;
    switch (p->eval) {
    case EVAL_NAN: s->x = (double)NAN; break;
    case EVAL_INF: s->y = HUGE_VAL; break;
    case EVAL_HUGE: s->z *= 1e300; break;
    case EVAL_FLAT_PARTIALS: su->x = su->y = su->z = 0; break;
    case EVAL_NAN_PARTIALS: sv->x = sv->y = sv->z = (double)NAN; break;
    default: break;
    }
}

static void patch_bounds(void *ud, double u0, double u1, double v0,
                         double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    patch *p = (patch *)ud;
    double r = fabs(p->r), k = 1;

    (void)u0, (void)u1, (void)v0, (void)v1;
    p->boxes++;
    if (p->box == BOX_SMALL)
        k = 0.25;
    else if (p->box == BOX_ENORMOUS)
        k = 1e300;
    lo->x = p->c.x - k * r;
    lo->y = p->c.y - k * r;
    lo->z = p->c.z - k * r;
    hi->x = p->c.x + k * r;
    hi->y = p->c.y + k * r;
    hi->z = p->c.z + k * r;
    if (p->box == BOX_NAN)
        lo->y = (double)NAN;
    else if (p->box == BOX_INVERTED) {
        double t = lo->x;
        lo->x = hi->x;
        hi->x = t - 1;
    }
}

static void check_parametric(int rc, const ray_ray *r,
                             const ray_parametric_surface *s,
                             const ray_hit *hit, const char *what)
{
    double d[4];

    check_iterative(rc, r, hit, what);
    if (rc != 1)
        return;
    if (s->u0 == 0 && s->u1 == 0 && s->v0 == 0 && s->v1 == 0) {
        d[0] = d[2] = 0;
        d[1] = d[3] = 1;
    } else {
        d[0] = s->u0;
        d[1] = s->u1;
        d[2] = s->v0;
        d[3] = s->v1;
    }
    FUZZ_CHECK(hit->u >= fmin(d[0], d[1]) && hit->u <= fmax(d[0], d[1]) &&
                   hit->v >= fmin(d[2], d[3]) && hit->v <= fmax(d[2], d[3]),
               "ray_parametric: (u, v) inside the domain");
}

static void op_parametric(fuzz_input *in)
{
    patch p;
    ray_parametric_surface s;
    ray_ray r;
    ray_hit hit;
    unsigned how;
    int rc;

    memset(&p, 0, sizeof p);
    memset(&s, 0, sizeof s);
    p.eval = (int)fuzz_below(in, EVAL_COUNT);
    p.box = (int)fuzz_below(in, BOX_COUNT);
    p.c = fuzz_vec3(in);
    p.r = fuzz_double(in);
    p.cut = fuzz_double(in);
    s.eval = patch_eval;
    s.bounds = patch_bounds;
    s.ud = &p;
    how = fuzz_u8(in);
    if (how & 1) {
        s.u0 = fuzz_double(in);
        s.u1 = fuzz_double(in);
        s.v0 = fuzz_double(in);
        s.v1 = fuzz_double(in);
    }
    s.subdivisions = capped_levels(fuzz_below(in, 14));  /* 13: too many */
    if (how & 2)
        s.tolerance = fuzz_double(in);
    s.max_iterations = fuzz_below(in, 64);
    r = fuzz_ray(in);
    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_parametric(&r, &s, &hit);
    check_parametric(rc, &r, &s, &hit, "ray_parametric");
    if (s.subdivisions > 12)
        FUZZ_CHECK(rc == -RAY_EINVAL || rc == 0,
                   "ray_parametric: subdivisions > 12 is -RAY_EINVAL");
}

static void op_bezier(fuzz_input *in)
{
    ray_vec3 cp[16];
    ray_parametric_surface s;
    ray_ray r;
    ray_hit hit;
    unsigned i, mode = fuzz_u8(in);
    double h = fuzz_double(in);
    int rc;

    /* A bumpy 4 x 4 grid, or any 16 points. */
    for (i = 0; i < 16; i++) {
        if (mode & 1) {
            cp[i] = fuzz_vec3(in);
        } else {
            cp[i].x = h * (i % 4);
            cp[i].y = h * (i / 4);
            cp[i].z = (double)(int)(fuzz_u8(in) % 5) - 2;
        }
    }
    fuzz_sentinel(&s, sizeof s);
    rc = ray_bezier_surface(cp, &s);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL, "ray_bezier_surface");
    if (rc != RAY_OK) {
        FUZZ_CHECK(fuzz_untouched(&s, sizeof s), "ray_bezier_surface");
        return;
    }
    s.subdivisions = capped_levels(fuzz_below(in, 13));
    s.max_iterations = fuzz_below(in, 64);
    if (mode & 2)
        s.tolerance = fuzz_double(in);
    r = fuzz_ray(in);
    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_parametric(&r, &s, &hit);
    check_parametric(rc, &r, &s, &hit, "ray_parametric (Bezier)");
}

#define MAX_OPS 4

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = fuzz_input_of(data, size);
    int ops = 0;

    while (fuzz_more(&in) && ops++ < MAX_OPS) {
        switch (fuzz_below(&in, 3)) {
        case 0: op_implicit(&in); break;
        case 1: op_parametric(&in); break;
        default: op_bezier(&in); break;
        }
    }
    return 0;
}
