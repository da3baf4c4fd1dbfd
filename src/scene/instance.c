/* SPDX-License-Identifier: MIT */
/*
** instance.c -- instances: a committed scene placed in another with an
** affine transform (ray_scene_add_instance), the two-level hierarchy of
** Embree and pbrt-v4: its record, its transforms and its world box,
** which the parent's BVH holds.  A query that enters the box moves the
** ray into the child's space and descends into the child itself (the
** query layer's query/traverse.h); the hit comes back to world space
** here, its error bound grown by the rounding of both transforms.
*/
#include <string.h>

#include "scene/scene.h"

void ray_transform_identity(ray_transform *t)
{
    if (t == NULL)
        return;
    memset(t, 0, sizeof *t);
    t->m[0][0] = t->m[1][1] = t->m[2][2] = 1.0;
}

/* Every component of v within [-limit, limit] (NaN fails). */
static int v3_within(ray_vec3 v, double limit)
{
    return fabs(v.x) <= limit && fabs(v.y) <= limit && fabs(v.z) <= limit;
}

/* Row k of the linear part applied to v (no translation). */
static double row_dot(const double m[3][4], int k, ray_vec3 v)
{
    return m[k][0] * v.x + m[k][1] * v.y + m[k][2] * v.z;
}

/* The bodies of ray__instance_point_to_world and ray__instance_normal,
** static so that ray__instance_to_world, once per instance hit, takes
** them inline rather than as two calls (gcc did not inline the exported
** ones): the game's frame 510.4M -> 507.8M instructions (callgrind,
** issue 36). */
static inline ray_vec3 point_to_world(const ray__instance *in, ray_vec3 p)
{
    const double (*m)[4] = in->xfm.m;

    return v3(row_dot(m, 0, p) + m[0][3], row_dot(m, 1, p) + m[1][3],
              row_dot(m, 2, p) + m[2][3]);
}

static inline ray_vec3 normal_to_world(const ray__instance *in, ray_vec3 n)
{
    ray_vec3 w;

    if (in->linear_identity)
        return n;
    /* Normals go by the inverse transpose: column k of L^-1. */
    w = v3(in->inv[0][0] * n.x + in->inv[1][0] * n.y + in->inv[2][0] * n.z,
           in->inv[0][1] * n.x + in->inv[1][1] * n.y + in->inv[2][1] * n.z,
           in->inv[0][2] * n.x + in->inv[1][2] * n.y + in->inv[2][2] * n.z);
    return v3_normalize(w, &w) ? w : n;
}

ray_vec3 ray__instance_point_to_world(const ray__instance *in, ray_vec3 p)
{
    return point_to_world(in, p);
}

/*
** The inverse of the linear part by its adjugate: INVERTED, or SINGULAR
** if L is singular to working precision: |det L| at most 8 ulps of the
** product of its row
** lengths (Hadamard's inequality bounds |det| by that product, reached by
** orthogonal rows; a ratio that small means the rows are parallel to
** within the rounding of the cofactors, and the inverse would be noise).
** Each row is first scaled by a power of two (exact) to bring its
** largest entry into [1, 2), so that neither the cofactors, the
** determinant nor the row lengths overflow or underflow whatever the
** transform's scale: L = D S with D = diag(2^e_i), so L^-1 = S^-1 D^-1,
** column j of S^-1 times 2^-e_j (exact again).  A zero row is singular.
** The test is scale-free: diag(1e-300, 1, 1) passes it, and so does
** diag(1e-310, 1, 1) -- but that one's inverse has an entry 1e310,
** beyond DBL_MAX: INVERSE_OVERFLOWS, refused too (issue 30), as is any L
** with an entry of L^-1 beyond DBL_MAX (a row of L whose largest entry is
** below about 1 / DBL_MAX = 5.6e-309 times the rest's conditioning).
*/
enum { INVERTED, SINGULAR, INVERSE_OVERFLOWS };

static int invert(const ray_transform *t, double inv[3][3])
{
    double m[3][3], c[3][3], det, rows = 1.0;
    int e[3], i, j;

    for (i = 0; i < 3; i++) {
        double big = fmax(fabs(t->m[i][0]),
                          fmax(fabs(t->m[i][1]), fabs(t->m[i][2])));
        if (!(big > 0))
            return SINGULAR;
        (void)frexp(big, &e[i]);            /* big in [2^(e-1), 2^e) */
        e[i] -= 1;
        for (j = 0; j < 3; j++)
            m[i][j] = ldexp(t->m[i][j], -e[i]);
    }
    c[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    c[0][1] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
    c[0][2] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
    c[1][0] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    c[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
    c[1][2] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
    c[2][0] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    c[2][1] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
    c[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    det = m[0][0] * c[0][0] + m[0][1] * c[1][0] + m[0][2] * c[2][0];
    for (i = 0; i < 3; i++)
        rows *= sqrt(m[i][0] * m[i][0] + m[i][1] * m[i][1] +
                     m[i][2] * m[i][2]);
    if (!(fabs(det) > 8.0 * DBL_EPSILON * rows))
        return SINGULAR;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            inv[i][j] = ldexp(c[i][j] / det, -e[j]);
            if (!isfinite(inv[i][j]))
                return INVERSE_OVERFLOWS;
        }
    return INVERTED;
}

/*
** L's singular value decomposition (ray__svd3: U and the values, the
** axes a sphere's image has), and |L^-1|_2, the largest singular value
** of L^-1 (computed from L^-1 itself, where the largest is the one a
** backward-stable method gets to a relative few ulps, whatever L's
** conditioning), rounded up by 2^-40 relative so that it bounds how much
** any distance can grow on its way into the child's space: a world ball
** of radius r holds no point whose object image lies farther than r
** |L^-1|_2 from the centre's.  The Frobenius norm stands in where the
** decomposition fails (it cannot for an L that invert accepted).
*/
static void singular_values(ray__instance *in)
{
    double l[3][3], u[3][3], s[3];
    int i, j;

    in->inv_spec = in->inv_norm;
    if (ray__svd3((const double(*)[3])in->inv, u, s))
        in->inv_spec = fmin(s[0] * (1 + 0x1p-40), in->inv_norm);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            l[i][j] = in->xfm.m[i][j];
    if (!ray__svd3((const double(*)[3])l, in->axes, in->sv))
        in->sv[0] = in->sv[1] = in->sv[2] = 0;
}

/*
** A bound on |M L - I|_2 for M = inv as rounded: what the closest-point
** search (query/closest.c) adds for a point mapped into the child's
** space by M, where the child's geometry was mapped out by L.  The
** product M L formed in double is within gamma(3) |M| |L| of the exact
** one, entry by entry (Higham, "Accuracy and Stability of Numerical
** Algorithms", 2nd ed., 2002, eq. 3.13); the 2-norm is at most the
** Frobenius norm, and the sums, squares and roots that form the two
** Frobenius norms round a few times more, which gamma(4) for gamma(3)
** and the final 1 + gamma(8) cover with room.  0 only where it is: an
** L of powers of two on the diagonal, say, still gets gamma(4)'s part.
*/
static void inverse_residual(ray__instance *in)
{
    double r2 = 0, a2 = 0;
    int i, j, k;

    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double p = 0, a = 0, r;
            for (k = 0; k < 3; k++) {
                p += in->inv[i][k] * in->xfm.m[k][j];
                a += fabs(in->inv[i][k]) * fabs(in->xfm.m[k][j]);
            }
            r = p - (i == j ? 1.0 : 0.0);
            r2 += r * r;
            a2 += a * a;
        }
    in->inv_residual = (sqrt(r2) + ray__gamma(4) * sqrt(a2)) *
                       (1 + ray__gamma(8));
}

/*
** Whether L is a rotation times a uniform scale s (L^T L = s^2 I): then
** distances scale by s exactly (to rounding) and a closest-point query
** through the instance is exact.  Within 64 ulps of s^2, entry by entry:
** an L assembled from a rotation matrix and a scale in double is that
** close.  Also |L^-1|_F, which bounds how much any distance grows on the
** way into the child's space.
*/
static void similarity(ray__instance *in)
{
    const double (*m)[4] = (const double (*)[4])in->xfm.m;
    double g[3][3], s2, f = 0;
    int i, j, k, ok = 1;

    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            g[i][j] = 0;
            for (k = 0; k < 3; k++)
                g[i][j] += m[k][i] * m[k][j];
            f += in->inv[i][j] * in->inv[i][j];
        }
    s2 = (g[0][0] + g[1][1] + g[2][2]) / 3;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            ok &= fabs(g[i][j] - (i == j ? s2 : 0.0)) <=
                  64 * DBL_EPSILON * s2;
    in->similarity = ok ? sqrt(s2) : 0.0;
    in->inv_norm = sqrt(f);
    singular_values(in);
}

/* RAY_OK and the instance's transform data, or RAY_EINVAL (message). */
static int transform_set(ray_scene *s, ray__instance *in,
                         const ray_transform *t)
{
    int i, j;

    if (t == NULL)
        return ray__fail(s, RAY_EINVAL, "xfm is NULL");
    for (i = 0; i < 3; i++)
        for (j = 0; j < 4; j++)
            if (!isfinite(t->m[i][j]))
                return ray__fail(s, RAY_EINVAL, "xfm m[%d][%d] is not "
                                 "finite (%g)", i, j, t->m[i][j]);
    switch (invert(t, in->inv)) {
    case SINGULAR:
        return ray__fail(s, RAY_EINVAL, "xfm is singular: its linear part "
                         "cannot be inverted to working precision");
    case INVERSE_OVERFLOWS:
        return ray__fail(s, RAY_EINVAL, "xfm's linear part has an inverse "
                         "beyond the largest double (a row of size "
                         "below about 1/DBL_MAX)");
    default:
        break;
    }
    in->xfm = *t;
    similarity(in);
    inverse_residual(in);
    in->linear_identity = 1;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            in->linear_identity &= t->m[i][j] == (i == j ? 1.0 : 0.0);
    return RAY_OK;
}

/* RAY_OK if "child" may be instanced, else the error (message). */
static int child_check(ray_scene *s, const ray_scene *child)
{
    if (child == NULL)
        return ray__fail(s, RAY_EINVAL, "child is NULL");
    if (child == s)
        return ray__fail(s, RAY_EINVAL, "a scene cannot instance itself");
    if (!child->committed)
        return ray__fail(s, RAY_ESTATE, "the child scene is not committed");
    if (child->has_instances)
        return ray__fail(s, RAY_EINVAL, "the child scene has instances "
                         "(two levels only)");
    if (child->n_planes > 0)
        return ray__fail(s, RAY_EINVAL, "the child scene has planes, which "
                         "are unbounded (instance bounded geometry)");
    return RAY_OK;
}

/*
** g (|r0| x0 + |r1| x1 + |r2| x2) for a row r of L^-1 and magnitudes
** x_i >= 0, as the error bounds below form it; where the unscaled sum
** overflows, each |r_i| is scaled by g before it meets x_i instead, so
** that a product such as 1e8 (2e300), which overflows before its
** scaling by gamma(6), does not make a bound of about 1e285 infinite and
** refuse a transform whose reach is far within range (issue 38, defect
** 4).  That second form is taken only where a term reached DBL_MAX, so
** that term is at least g DBL_MAX / 2 after scaling; what the others
** lose to underflow (under 2^-1075 each, times x_i) is below its last
** bit, and the bounds' own (1 + gamma(2)) covers the reordering.
*/
static double scaled_row_sum(double g, const double r[3], double x0,
                             double x1, double x2)
{
    double s = fabs(r[0]) * x0 + fabs(r[1]) * x1 + fabs(r[2]) * x2;

    if (s < HUGE_VAL)
        return g * s;
    return (g * fabs(r[0])) * x0 + (g * fabs(r[1])) * x1 +
           (g * fabs(r[2])) * x2;
}

/*
** The world box of an instance: its child's box (the union of the roots
** of its BVHs, rounded outward already) through the transform, corner by
** corner, grown by the rounding a world ray suffers on its way into the
** child's space (see ray__instance_to_world: the box must hold every
** point whose object-space image the child can hit).  An empty child
** gets the point at the translation: nothing there can be hit.
**
** Returns 0 when the transform takes the child out of range: a bound of
** the box, or one of the sums sum_j |m_kj| max |child_j| + |m_k3| that
** bound |L p' + c| for every point p' of the child, beyond
** RAY__INSTANCE_REACH (2^1016).  Within it a hit's p = L p' + c cannot
** overflow, and neither can its p_err (ray__instance_to_world): its
** terms are gamma(n) times sums no larger than this function's reach,
** fwd and back, formed from the same magnitudes at the box's largest
** (the box was grown by them, so they are within 2^1017 too), plus the
** child's own bound carried through L (below gamma(8) of the reach).  A
** transform accepted by the finiteness and singularity tests alone could
** map a child near DBL_MAX and give hits with p.z = -Inf and p_err NaN
** (issue 30): such a transform is refused instead.
*/
int ray__instance_box(ray__instance *in)
{
    const ray_scene *c = in->child;
    const double (*m)[4] = (const double (*)[4])in->xfm.m;
    ray_vec3 lo, hi;
    double big[3], g = ray__gamma(6);
    int k, corner, in_range = 1;

    if (!(c->lo.x <= c->hi.x)) {
        in->lo = in->hi = v3(m[0][3], m[1][3], m[2][3]);
        return 1;
    }
    lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (corner = 0; corner < 8; corner++) {
        ray_vec3 p = v3(corner & 1 ? c->hi.x : c->lo.x,
                        corner & 2 ? c->hi.y : c->lo.y,
                        corner & 4 ? c->hi.z : c->lo.z);
        ray_vec3 w = ray__instance_point_to_world(in, p);
        lo = v3(fmin(lo.x, w.x), fmin(lo.y, w.y), fmin(lo.z, w.z));
        hi = v3(fmax(hi.x, w.x), fmax(hi.y, w.y), fmax(hi.z, w.z));
    }
    /* The largest magnitude of each world coordinate in the box. */
    big[0] = fmax(fabs(lo.x), fabs(hi.x));
    big[1] = fmax(fabs(lo.y), fabs(hi.y));
    big[2] = fmax(fabs(lo.z), fabs(hi.z));
    for (k = 0; k < 3; k++) {
        /* Forward rounding of a corner, and the inverse's rounding of a
        ** world point mapped back (both gamma(6) bounds, generous). */
        double reach = fabs(m[k][0]) * fmax(fabs(c->lo.x), fabs(c->hi.x)) +
                       fabs(m[k][1]) * fmax(fabs(c->lo.y), fabs(c->hi.y)) +
                       fabs(m[k][2]) * fmax(fabs(c->lo.z), fabs(c->hi.z)) +
                       fabs(m[k][3]);
        double fwd = g * reach;
        double back = 0;
        int j;
        if (!(reach <= RAY__INSTANCE_REACH))
            in_range = 0;
        for (j = 0; j < 3; j++) {
            double d = scaled_row_sum(g, in->inv[j], big[0] + fabs(m[0][3]),
                                      big[1] + fabs(m[1][3]),
                                      big[2] + fabs(m[2][3]));
            back += fabs(m[k][j]) * d;
        }
        if (k == 0) {
            lo.x -= fwd + back;
            hi.x += fwd + back;
        } else if (k == 1) {
            lo.y -= fwd + back;
            hi.y += fwd + back;
        } else {
            lo.z -= fwd + back;
            hi.z += fwd + back;
        }
    }
    in->lo = lo;
    in->hi = hi;
    return in_range && v3_within(lo, RAY__INSTANCE_REACH) &&
           v3_within(hi, RAY__INSTANCE_REACH);
}

int ray_scene_add_instance(ray_scene *s, const ray_scene *child,
                           const ray_transform *xfm, unsigned *geom_id)
{
    int rc = ray__begin(s, "ray_scene_add_instance");
    ray__instance in, *grown;
    ray__prim p;

    if (rc != RAY_OK)
        return rc;
    memset(&in, 0, sizeof in);
    if ((rc = child_check(s, child)) != RAY_OK)
        return rc;
    if ((rc = transform_set(s, &in, xfm)) != RAY_OK)
        return rc;
    in.child = child;
    in.generation = child->generation;
    if (!ray__instance_box(&in))
        return ray__fail(s, RAY_EINVAL, "xfm maps the child scene beyond "
                         "+-2^1016 (about 7e305), where hits could not be "
                         "represented");
    grown = ray__grow(s, s->instances, &s->cap_instances, s->n_instances,
                      sizeof *s->instances);
    if (grown == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory");
    s->instances = grown;
    memset(&p, 0, sizeof p);
    p.kind = RAY__KIND_INSTANCE;
    p.material = RAY_NO_MATERIAL;
    p.surface = (unsigned)s->n_instances;
    rc = ray__add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    s->instances[s->n_instances++] = in;
    return RAY_OK;
}

/* The live instance named by geom_id, or NULL with the error recorded. */
static ray__instance *instance_of(ray_scene *s, unsigned geom_id)
{
    const ray__prim *p = ray__live_prim(s, geom_id);

    if (p == NULL)
        return NULL;
    if (p->kind != RAY__KIND_INSTANCE) {
        ray__fail(s, RAY_EINVAL, "geometry %u is not an instance", geom_id);
        return NULL;
    }
    return &s->instances[p->surface];
}

int ray_scene_set_transform(ray_scene *s, unsigned geom_id,
                            const ray_transform *xfm)
{
    int rc = ray__begin(s, "ray_scene_set_transform");
    ray__instance *in, next;

    if (rc != RAY_OK)
        return rc;
    if ((in = instance_of(s, geom_id)) == NULL)
        return RAY_EINVAL;
    next = *in;
    if ((rc = transform_set(s, &next, xfm)) != RAY_OK)
        return rc;
    if (!ray__instance_box(&next))
        return ray__fail(s, RAY_EINVAL, "xfm maps the child scene beyond "
                         "+-2^1016 (about 7e305), where hits could not be "
                         "represented");
    *in = next;
    ray__touch(s, RAY__DIRTY_PRIMS);
    return RAY_OK;
}

/* ----------------------------------------------------- for the queries */

ray_vec3 ray__instance_normal(const ray__instance *in, ray_vec3 n)
{
    return normal_to_world(in, n);
}

/*
** The hit's world point is p = L p' + c, rounded; its error bound adds,
** per axis k (pbrt-v4's Transform::ApplyError, section 6.8.6, with gamma
** widened for the sums of four terms):
**   |L| p_err'                    the child's own bound, carried over;
**   gamma(4) (|L| |p'| + |c|)     the rounding of p = L p' + c;
**   |L| gamma(5) |L^-1| (|p| + |c|)   the rounding a ray leaving p will
**                                 suffer on its way back into the child's
**                                 space (o - c, then L^-1), mapped to world:
** so a ray spawned by ray_spawn from p, offset by this bound, starts on
** the right side of the surface in the child's space too.  t, u, v and
** the ids are the child's.
*/
void ray__instance_to_world(const ray__instance *in, const ray_hit *obj,
                            ray_hit *world)
{
    const double (*m)[4] = in->xfm.m;
    ray_vec3 p = obj->p, e = obj->p_err, w, err;
    double back[3], bound[3], g4 = ray__gamma(4), g5 = ray__gamma(5);
    int j, k;

    *world = *obj;
    w = point_to_world(in, p);
    for (j = 0; j < 3; j++)
        back[j] = scaled_row_sum(g5, in->inv[j], fabs(w.x) + fabs(m[0][3]),
                                 fabs(w.y) + fabs(m[1][3]),
                                 fabs(w.z) + fabs(m[2][3]));
    for (k = 0; k < 3; k++) {
        double carried = fabs(m[k][0]) * e.x + fabs(m[k][1]) * e.y +
                         fabs(m[k][2]) * e.z;
        double fwd = g4 * (fabs(m[k][0]) * fabs(p.x) +
                           fabs(m[k][1]) * fabs(p.y) +
                           fabs(m[k][2]) * fabs(p.z) + fabs(m[k][3]));
        double ret = fabs(m[k][0]) * back[0] + fabs(m[k][1]) * back[1] +
                     fabs(m[k][2]) * back[2];
        /* The sum of three non-negative terms rounds up by at most 2
        ** ulps: one more gamma(2) keeps it a bound. */
        bound[k] = (carried + fwd + ret) * (1.0 + ray__gamma(2));
    }
    err = v3(bound[0], bound[1], bound[2]);
    world->p = w;
    world->p_err = err;
    world->n = normal_to_world(in, obj->n);
}

