/* SPDX-License-Identifier: MIT */
/*
** winding.c -- the generalized winding number of ray_contains: exact,
** the sum of every triangle's signed solid angle, and fast, through the
** triangle BVH with Barill, Dickson, Schmidt, Levin and Jacobson's
** far-field expansion ("Fast Winding Numbers for Soups and Clouds", ACM
** Trans. Graph. 37(4), 2018, section 3).
**
** A triangle t of vector area a_t n_t (half the cross product of its
** edges) seen from q subtends (x - q) . n_t / |x - q|^3 per unit area,
** summed over the triangle: its solid angle.  About a centre p, with d =
** p - q and e = x - p, g(y) = y / |y|^3 expands as g(d) + J(d) e + ...,
** J(d) = I / |d|^3 - 3 d d^T / |d|^5 (symmetric), so a cluster of
** triangles subtends
**     g(d) . N  +  tr(M) / |d|^3 - 3 d^T M d / |d|^5  + O(r^2 / |d|^4)
** with N = sum a_t n_t (order 1) and M = sum a_t (c_t - p) n_t^T (order
** 2: n_t is constant over t, so the integral of x - p over t is a_t (c_t
** - p) exactly, c_t its centroid), r the radius of the cluster about p:
** Barill's eq. 9 and 10 with the tensor written as M.  The order-3 term
** (the second moments) is left out, as the brief of issue 39 asks for
** order 2; the error is measured (tests/check_contains.c, bench/contains.c)
** and ray_contains answers exactly where it could decide inside/outside
** (contains.c, WINDING_MARGIN).
**
** The expansion is kept per wide node of the triangle BVH (ray__wexp,
** scene.h), bottom up: a parent's N is its children's sum, its M their
** M moved to the new centre, M_p = M_c + (p_c - p) N_c^T (the same
** integral with x - p = (x - p_c) + (p_c - p)).  A query descends from
** the root: a child node whose centre is more than beta r from q
** answers by its expansion (Barill's beta = 2: WINDING_BETA), a nearer
** one is opened, a leaf's triangles are summed exactly.  Through an
** instance of linear part L the child's expansion is taken to world
** space exactly: the vector area of a patch maps by L's cofactor matrix
** cof(L) = det(L) L^-T, its points by L, so N' = cof(L) N, M' = L M
** cof(L)^T, p' = L p + c, and r' = |L|_2 r bounds the radius.
*/
#include <string.h>

#include "core/platform.h"
#include "core/predicates.h"
#include "query/query.h"

/* Barill et al.'s accuracy parameter (section 3.2, "beta = 2"): a node
** is expanded when q is farther than beta times its radius from its
** centre.  Their fig. 7 measures order 2 at beta 2 well under 1e-2 of
** error; the tests, fuzz/fuzz_winding.c and bench/contains.c measure
** ours.  The winding number itself (RAY_CONTAINS_WINDING_EXACT) is the
** plain sum instead, because no beta makes the expansions both within
** its 1e-9 and faster: on the 59k bunny (bench/contains.c built with
** -DWINDING_BETA) beta 16 leaves 6e-5, beta 64 4e-8 at the plain sum's
** speed, beta 256 2.6e-15 slower than it (the error falls as beta^-3, so
** 1e-9 needs about 200, where nearly every node is opened). */
#ifndef WINDING_BETA
#define WINDING_BETA 2.0
#endif

/* Triangle a, b, c's signed solid angle seen from q (world space), by
** Van Oosterom and Strackee: tan(omega / 2) = det[a b c] / (|a||b||c| +
** (a.b)|c| + (b.c)|a| + (c.a)|b|), with a, b, c taken from q.  Positive
** for a triangle seen clockwise from q (q behind an outward face); 0 for
** q in its plane (on the triangle: the mean of the two sides' +-2 pi). */
double ray__solid_angle(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 q)
{
    double det = ray__orient3d(a, b, c, q), la, lb, lc, den;
    ray_vec3 x, y, z;

    if (det == 0)
        return 0;
    x = v3_sub(a, q), y = v3_sub(b, q), z = v3_sub(c, q);
    la = v3_length(x), lb = v3_length(y), lc = v3_length(z);
    den = la * lb * lc + v3_dot(x, y) * lc + v3_dot(y, z) * la +
          v3_dot(z, x) * lb;
    return 2 * atan2(det, den);
}

/* Slot i's class: 1 for a closed mesh's triangle (parity answers it
** unless RAY_CONTAINS_WINDING), 0 for the others. */
static int slot_class(const ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];

    return p->kind == RAY__KIND_MESH && s->meshes[p->mesh].closed;
}

/* Slot i's solid angle at qw, its corners taken to world space through
** instance "in" (NULL: none). */
static double slot_angle(const ray_scene *s, size_t i,
                         const ray__instance *in, ray_vec3 qw)
{
    ray__tri t = ray__tri_of(s, i);

    if (in != NULL) {
        t.a = ray__instance_point_to_world(in, t.a);
        t.b = ray__instance_point_to_world(in, t.b);
        t.c = ray__instance_point_to_world(in, t.c);
    }
    return ray__solid_angle(t.a, t.b, t.c, qw);
}

double ray__winding_exact(const ray_scene *s, ray_vec3 qw,
                          const ray__instance *in, unsigned ignore, int all)
{
    double sum = 0;
    size_t i;

    for (i = 0; i < s->n_live_tris; i++) {
        const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];
        if ((!all && slot_class(s, i)) || !p->enabled || p->removed ||
            (p->mask & ~ignore) == 0)
            continue;
        sum += slot_angle(s, i, in, qw);
    }
    return sum;
}

/* ------------------------------------------------------- the expansions */

/* Triangle slot i's vector area (half its edges' cross product), area
** and centroid. */
static void tri_moments(const ray_scene *s, size_t i, ray_vec3 *an,
                        double *area, ray_vec3 *c)
{
    ray__tri t = ray__tri_of(s, i);

    *an = v3_scale(v3_cross(v3_sub(t.b, t.a), v3_sub(t.c, t.a)), 0.5);
    *area = v3_length(*an);
    *c = v3_scale(v3_add(v3_add(t.a, t.b), t.c), 1.0 / 3.0);
}

/* m += u v^T. */
static void outer_add(double m[9], ray_vec3 u, ray_vec3 v)
{
    double a[3] = {u.x, u.y, u.z}, b[3] = {v.x, v.y, v.z};
    int i, j;

    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            m[3 * i + j] += a[i] * b[j];
}

static ray_vec3 p_of(const ray__wexp *e)
{
    return v3(e->p[0], e->p[1], e->p[2]);
}

/* Wide node w's expansion, from its leaves' triangles and its inner
** children's expansions (made before it: children follow their parent
** in the array, bvh.h's collapse and accel/refit.c). */
static void node_expansion(const ray_scene *s, size_t w, ray__wexp *all)
{
    const ray__wnode *q = &s->tri_bvh.wide[w];
    ray__wexp *e = &all[w];
    ray_vec3 sum = v3(0, 0, 0), mean = v3(0, 0, 0), p;
    double area = 0, r = 0;
    size_t count = 0, i;
    int k, c;

    memset(e, 0, sizeof *e);
    /* The centre: the area-weighted centroid (the mean of the centroids
    ** where every triangle has area 0: any centre is valid, r covers). */
    for (k = 0; k < RAY__WIDTH; k++) {
        unsigned first = q->child[k], n = q->count[k] & ~RAY__LEAF;
        if (q->count[k] == 0) {
            const ray__wexp *ce = &all[first];
            sum = v3_add(sum, v3_scale(p_of(ce), ce->area));
            mean = v3_add(mean, p_of(ce));
            area += ce->area;
            count++;
            continue;
        }
        for (i = first; i < (size_t)first + n; i++) {
            ray_vec3 an, ct;
            double a;
            tri_moments(s, i, &an, &a, &ct);
            sum = v3_add(sum, v3_scale(ct, a));
            mean = v3_add(mean, ct);
            area += a;
            count++;
        }
    }
    if (count == 0)
        return;                 /* no triangle: classes 0, never read */
    p = area > 0 ? v3_scale(sum, 1 / area) : v3_scale(mean, 1.0 / (double)count);
    e->p[0] = p.x, e->p[1] = p.y, e->p[2] = p.z;
    e->area = area;
    for (k = 0; k < RAY__WIDTH; k++) {
        unsigned first = q->child[k], n = q->count[k] & ~RAY__LEAF;
        if (q->count[k] == 0) {
            const ray__wexp *ce = &all[first];
            ray_vec3 shift = v3_sub(p_of(ce), p);
            double reach = v3_length(shift) + ce->r;
            for (c = 0; c < 2; c++) {
                ray_vec3 cn = v3(ce->n[c][0], ce->n[c][1], ce->n[c][2]);
                for (i = 0; i < 3; i++) {
                    e->n[c][i] += ce->n[c][i];
                    e->m[c][i] += ce->m[c][i];
                    e->m[c][3 + i] += ce->m[c][3 + i];
                    e->m[c][6 + i] += ce->m[c][6 + i];
                }
                outer_add(e->m[c], shift, cn);
            }
            e->classes |= ce->classes;
            if (reach > r)
                r = reach;
            continue;
        }
        for (i = first; i < (size_t)first + n; i++) {
            ray__tri t = ray__tri_of(s, i);
            ray_vec3 an, ct;
            double a, d;
            int cl = slot_class(s, i);
            tri_moments(s, i, &an, &a, &ct);
            e->n[cl][0] += an.x, e->n[cl][1] += an.y, e->n[cl][2] += an.z;
            outer_add(e->m[cl], v3_sub(ct, p), an);
            e->classes |= 1u << cl;
            d = ray__distance(t.a, p);
            r = d > r ? d : r;
            d = ray__distance(t.b, p);
            r = d > r ? d : r;
            d = ray__distance(t.c, p);
            r = d > r ? d : r;
        }
    }
    e->r = r;
}

/* Whether s's query needs the expansions: it has triangles the winding
** number answers (all: any triangle at all). */
static int needs_wexp(const ray_scene *s, int all)
{
    size_t i;

    if (s->tri_bvh.n_wide == 0)
        return 0;
    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!p->enabled || p->removed)
            continue;
        if (p->kind == RAY__KIND_TRIANGLE ||
            (p->kind == RAY__KIND_MESH && (all || !s->meshes[p->mesh].closed)))
            return 1;
    }
    return 0;
}

int ray__wexp_ensure(const ray_scene *s, int all)
{
    ray_scene *w = ray__unconst(s);
    size_t i;
    int rc = RAY_OK;

    /* Without the lock (commit could not make it), none: summed whole. */
    if (w->cgrid_lock != NULL && needs_wexp(s, all)) {
        ray__mutex_lock(w->cgrid_lock);
        if (!w->wexp_known) {
            size_t n = s->tri_bvh.n_wide;
            ray__wexp *e = n <= ((size_t)-1) / sizeof *e
                               ? ray__alloc(s, n * sizeof *e) : NULL;
            if (e == NULL) {
                rc = RAY_ENOMEM;
            } else {
                for (i = n; i-- > 0;)
                    node_expansion(s, i, e);
                w->wexp = e;
                w->n_wexp = n;
                w->wexp_known = 1;
            }
        }
        ray__mutex_unlock(w->cgrid_lock);
    }
    for (i = 0; i < s->n_prims && rc == RAY_OK; i++) {
        const ray__prim *p = &s->prims[i];
        if (p->kind == RAY__KIND_INSTANCE && !p->removed)
            rc = ray__wexp_ensure(s->instances[p->surface].child, all);
    }
    return rc;
}

/* ----------------------------------------------------------- the query */

/* The frame an expansion is read in: world space through instance "in"
** (L, cof(L) = det(L) L^-T, the translation c, |L|_2 or a bound of it;
** id: L is the identity, only c moves it), or the scene's own (id, c
** 0). */
typedef struct wframe {
    int id;
    double l[3][3], cof[3][3], c[3], norm;
} wframe;

static void wind_frame_of(const ray__instance *in, wframe *f)
{
    int i, j;
    double det, fro = 0;

    f->id = in == NULL || in->linear_identity;
    f->c[0] = f->c[1] = f->c[2] = 0;
    if (in == NULL)
        return;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            f->l[i][j] = in->xfm.m[i][j];
            fro += f->l[i][j] * f->l[i][j];
        }
        f->c[i] = in->xfm.m[i][3];
    }
    det = f->l[0][0] * (f->l[1][1] * f->l[2][2] - f->l[1][2] * f->l[2][1]) -
          f->l[0][1] * (f->l[1][0] * f->l[2][2] - f->l[1][2] * f->l[2][0]) +
          f->l[0][2] * (f->l[1][0] * f->l[2][1] - f->l[1][1] * f->l[2][0]);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            f->cof[i][j] = det * in->inv[j][i];
    /* |L|_2: the largest singular value where the instance has it, else
    ** the Frobenius norm, which bounds it; only the radius test reads it
    ** (a larger radius opens more nodes, never fewer). */
    f->norm = in->sv[0] > 0 ? in->sv[0] : sqrt(fro);
}

/* Node e's expansion at qw: its solid angle (class mask "need"), when qw
** is farther than WINDING_BETA radii from its centre; else 0 with *far
** cleared. */
static double far_field(const ray__wexp *e, const wframe *f, ray_vec3 qw,
                        unsigned need, int *far)
{
    double n[3] = {0, 0, 0}, m[9] = {0}, d[3], r = e->r, dd, id3, tr, dmd;
    int i, j, k, c;

    if (f->id) {
        for (i = 0; i < 3; i++)
            d[i] = e->p[i] + f->c[i] - (i == 0 ? qw.x : i == 1 ? qw.y : qw.z);
    } else {
        for (i = 0; i < 3; i++)
            d[i] = f->l[i][0] * e->p[0] + f->l[i][1] * e->p[1] +
                   f->l[i][2] * e->p[2] + f->c[i] -
                   (i == 0 ? qw.x : i == 1 ? qw.y : qw.z);
        r *= f->norm;
    }
    dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (!(dd > WINDING_BETA * WINDING_BETA * r * r)) {
        *far = 0;
        return 0;
    }
    *far = 1;
    for (c = 0; c < 2; c++) {
        if (!(need & (1u << c)))
            continue;
        for (i = 0; i < 3; i++)
            n[i] += e->n[c][i];
        for (i = 0; i < 9; i++)
            m[i] += e->m[c][i];
    }
    if (!f->id) {
        /* N' = cof N, M' = L M cof^T. */
        double n2[3], lm[9], m2[9];
        for (i = 0; i < 3; i++)
            n2[i] = f->cof[i][0] * n[0] + f->cof[i][1] * n[1] +
                    f->cof[i][2] * n[2];
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                lm[3 * i + j] = f->l[i][0] * m[j] + f->l[i][1] * m[3 + j] +
                                f->l[i][2] * m[6 + j];
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                m2[3 * i + j] = 0;
                for (k = 0; k < 3; k++)
                    m2[3 * i + j] += lm[3 * i + k] * f->cof[j][k];
            }
        for (i = 0; i < 3; i++)
            n[i] = n2[i];
        for (i = 0; i < 9; i++)
            m[i] = m2[i];
    }
    /* g(d) . N + tr(M) / |d|^3 - 3 d^T M d / |d|^5, d = p - q. */
    id3 = 1 / (dd * sqrt(dd));
    tr = m[0] + m[4] + m[8];
    dmd = 0;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            dmd += d[i] * m[3 * i + j] * d[j];
    return (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) * id3 + tr * id3 -
           3 * dmd * id3 / dd;
}

int ray__winding_fast(const ray_scene *s, ray_vec3 qw,
                      const ray__instance *in, int all, double *angle)
{
    const ray__bvh *bvh = &s->tri_bvh;
    unsigned need = all ? 3u : 1u;
    unsigned stack[RAY__WIDTH * 64];
    double sum = 0;
    wframe f;
    int sp = 0, far;

    if (bvh->n_wide == 0) {
        *angle = 0;
        return 1;
    }
    if (!s->wexp_known || s->n_wexp != bvh->n_wide)
        return 0;               /* not made (no lock): sum every one */
    wind_frame_of(in, &f);
    if (!(s->wexp[0].classes & need)) {
        *angle = 0;
        return 1;
    }
    sum = far_field(&s->wexp[0], &f, qw, need, &far);
    if (!far)
        stack[sp++] = 0;
    /* At most RAY__WIDTH pushed and one popped a level, 64 levels at
    ** most (accel/build.h). */
    while (sp > 0) {
        const ray__wnode *w = &bvh->wide[stack[--sp]];
        int k;
        for (k = 0; k < RAY__WIDTH; k++) {
            unsigned first = w->child[k], n = w->count[k] & ~RAY__LEAF;
            size_t i;
            if (w->count[k] == 0) {
                const ray__wexp *e = &s->wexp[first];
                double a;
                if (!(e->classes & need))
                    continue;
                a = far_field(e, &f, qw, need, &far);
                if (far)
                    sum += a;
                else
                    stack[sp++] = first;
                continue;
            }
            for (i = first; i < (size_t)first + n; i++)
                if (all || !slot_class(s, i))
                    sum += slot_angle(s, i, in, qw);
        }
    }
    *angle = sum;
    return 1;
}
