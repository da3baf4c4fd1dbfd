/* SPDX-License-Identifier: MIT */
/*
** photons.c -- caustics by photon tracing (Jensen, "Global Illumination
** using Photon Maps", EGWR 1996): photons leave the lights, bounce off
** the materials that scatter them (ray_scatter_fn: mirror, glass, ...)
** and are stored where they land on a material that gathers them
** (RAY_EFFECT_CAUSTICS) after at least one specular bounce: the light
** paths L S+ D that tracing from the eye never finds.  A hash grid over
** the stored photons answers the density estimate (ray_caustics_at).
**
** Determinism: photon i draws its random numbers from a sequence seeded
** by (seed, i) alone; the photons are traced in fixed chunks of CHUNK
** indices, chunk c by task c mod tasks (core/tasks.h: the built-in
** threads or the program's scheduler), each into its own buffer, and the
** buffers are joined in chunk order: the same map, bit for bit, at any
** thread count, in any task order.  The grid's cells list their photons in that order,
** so a gather sums them in the same order every time.
** Progress (ray_render_options.progress): a task reports each chunk it
** has traced and stops at its next report once the callback cancelled;
** a cancelled pass keeps nothing, so the reports never change a map.
*/
#include <float.h>
#include <math.h>
#include <string.h>

#include "core/platform.h"
#include "core/tasks.h"
#include "trace/trace.h"

/* A stored photon: where it landed, its power (in the units of
** ray_caustics_at's irradiance times area) and its unit direction of
** travel (to keep only the photons arriving at the front of a surface). */
typedef struct photon {
    ray_vec3 p;
    float power[3];
    float dir[3];
} photon;

struct ray_photon_map {
    const ray_scene *scene;      /* compared, never read: the map may
                                    outlive it (ray.h) */
    ray__allocator alloc;        /* a copy of the scene's, to free with */
    photon *ph;                  /* sorted by grid bucket, stably */
    size_t n;
    size_t *start;               /* bucket b: ph[start[b] .. start[b+1]) */
    size_t buckets;              /* a power of two; 0 when n == 0 */
    double radius, r2, inv_area; /* r, r^2, 1 / (pi r^2) */
    double cell;                 /* the grid's cell size, >= 2r */
    ray_vec3 lo, hi;             /* the stored photons' box */
    unsigned long long emitted, tests;
};

/* Photons per chunk: large enough that a chunk's bookkeeping is nothing
** beside tracing it, small enough that 2 to 64 threads share the work. */
#define CHUNK 4096u

/* The automatic radius (ray.h): D / RADIUS_DIV at RADIUS_REF photons,
** shrinking as N^(-1/6).  Chosen on examples/caustics.c (glass sphere of
** radius 1 in a scene 6 across): the caustic's core, about 0.15 across,
** is resolved at 100 000 photons; bench/caustics.c measures the error. */
#define RADIUS_DIV 100.0
#define RADIUS_REF 100000.0

/* Grid cells per axis at most 2^40 over the photons' box, so a cell's
** integer coordinates fit a long long whatever the radius (a tiny radius
** over a large box gets larger cells: slower, never wrong). */
#define MAX_CELLS_LOG2 40

static double max3(ray_rgb c)
{
    return fmax(c.r, fmax(c.g, c.b));
}

/* 0 (automatic), or a radius whose disk area pi r^2 and its inverse are
** finite: the density estimate divides by that area. */
int ray__photon_radius_valid(double r)
{
    double area = RAY__PI * r * r;

    return r == 0 || (r > 0 && area < HUGE_VAL && 1.0 / area < HUGE_VAL);
}

/* ------------------------------------------------------------ emission */

/*
** What the emission of a pass aims at: the sphere around the box of the
** geometry whose material scatters photons (aim: 1), or nothing when some
** such geometry is unbounded (a plane: aim 0, photons go everywhere); and
** the sphere around the scene's bounded geometry, where directional
** photons start from.  Each light's selection weight is its power.
*/
typedef struct emitter {
    const ray_scene *s;
    int aim;
    ray_vec3 c;                  /* the target sphere */
    double R;
    ray_vec3 sc;                 /* the scene's sphere */
    double sR;
    double diag;                 /* the target box's diagonal (radius) */
    double *cdf;                 /* n_lights, cumulative, last = total */
    double total;
    double per_photon;           /* 1 / photons */
} emitter;

static void grow_box(ray_vec3 *lo, ray_vec3 *hi, ray_vec3 a, ray_vec3 b)
{
    lo->x = fmin(lo->x, a.x);
    lo->y = fmin(lo->y, a.y);
    lo->z = fmin(lo->z, a.z);
    hi->x = fmax(hi->x, b.x);
    hi->y = fmax(hi->y, b.y);
    hi->z = fmax(hi->z, b.z);
}

/* The sphere around box [lo, hi]: its centre and half-diagonal, grown by
** 2^-30 of itself so that rounding the half-diagonal cannot leave a
** corner outside (its error is a few ulps, 2^-50 relative). */
static void box_sphere(ray_vec3 lo, ray_vec3 hi, ray_vec3 *c, double *R)
{
    *c = v3_scale(v3_add(lo, hi), 0.5);
    *R = 0.5 * v3_length(v3_sub(hi, lo)) * (1.0 + 0x1p-30);
}

/* The target: the box of the enabled geometry with a scattering material
** (an instance's whole box if its scene has one). */
static void find_target(emitter *e)
{
    const ray_scene *s = e->s;
    ray_vec3 lo = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    ray_vec3 hi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    int any = 0, unbounded = 0;
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        ray_vec3 a, b;
        if (!p->enabled || p->removed)
            continue;
        if (p->kind == RAY__KIND_INSTANCE) {
            const ray__instance *in = &s->instances[p->surface];
            if (!(in->child->material_effects & RAY_EFFECT_SCATTER))
                continue;
            a = in->lo;
            b = in->hi;
        } else {
            if (p->material == RAY_NO_MATERIAL ||
                s->materials[p->material].scatter == NULL)
                continue;
            if (ray__kind_class(p->kind) == RAY__CLASS_UNBOUNDED) {
                unbounded = 1;
                continue;
            }
            ray__prim_box(s, p, &a, &b);
        }
        grow_box(&lo, &hi, a, b);
        any = 1;
    }
    box_sphere(s->lo, s->hi, &e->sc, &e->sR);
    if (!(e->sR < HUGE_VAL))                 /* planes only: no box */
        e->sc = v3(0, 0, 0), e->sR = 1.0;
    e->aim = any && !unbounded;
    if (e->aim) {
        box_sphere(lo, hi, &e->c, &e->R);
        e->diag = 2 * e->R;
    } else {
        e->c = e->sc;
        e->R = e->sR;
        e->diag = 2 * e->sR;
    }
    if (!(e->R > 0 && e->R < HUGE_VAL)) {    /* a point-like target */
        e->R = e->R > 0 ? e->R : 1e-300;
        e->diag = 1.0;
    }
}

/* A light's power (summed over the channels), for choosing among them:
** point and sphere lights 4 pi I, a rect light pi I (a Lambertian
** emitter of intensity I cos), a directional one I times the area of
** the disk that covers its target. */
static double light_power(const emitter *e, const ray_light *l)
{
    double i = l->intensity.r + l->intensity.g + l->intensity.b;

    switch (l->kind) {
    case RAY_LIGHT_RECT:
        return RAY__PI * i;
    case RAY_LIGHT_DIRECTIONAL:
        return RAY__PI * e->R * e->R * i;
    default:
        return 4 * RAY__PI * i;
    }
}

/* A uniform direction in the cone around unit w with cosine cos_max,
** from two uniform numbers (cos_max = -1: the whole sphere). */
static ray_vec3 cone_dir(ray_vec3 w, double cos_max, double u1, double u2)
{
    double c = 1 - u1 * (1 - cos_max);
    double sn = sqrt(fmax(0.0, 1 - c * c)), phi = 2 * RAY__PI * u2;
    ray_vec3 t1, t2;

    ray__tangent_frame(w, &t1, &t2);
    return v3_add(v3_scale(w, c),
                  v3_add(v3_scale(t1, sn * cos(phi)),
                         v3_scale(t2, sn * sin(phi))));
}

/*
** A direction from x toward the target sphere, uniform over the cone it
** subtends (the whole sphere of directions when x is inside it or
** nothing is aimed at), and that cone's solid angle.
*/
static ray_vec3 aimed_dir(ray_ctx *ctx, const emitter *e, ray_vec3 x,
                          double *omega)
{
    ray_vec3 w, to = v3_sub(e->c, x);
    double d = v3_length(to), cos_max = -1;
    double u1 = ray_ctx_random(ctx), u2 = ray_ctx_random(ctx);

    if (e->aim && d > e->R && v3_normalize(to, &w)) {
        /* sqrt(1 - (R/d)^2) without the cancellation of 1 - x^2, nor
        ** the overflow of d^2 for a light beyond 1e154. */
        double q = e->R / d;
        cos_max = sqrt((1 - q) * (1 + q));
    } else
        w = v3(0, 1, 0);
    *omega = 2 * RAY__PI * (1 - cos_max);
    return cone_dir(w, cos_max, u1, u2);
}

/*
** Photon emission from light sl: its origin, direction and power, the
** light's emission in that direction divided by the density it was
** drawn with and by the probability of choosing the light (pl) and the
** photon count -- so each photon's expected power is the light's share
** of the total, whatever the aim.  Returns 0 for a photon that carries
** nothing (behind a rect light).
**   point:  intensity I in every direction: I * omega.
**   sphere: a uniform point of its surface (density 1/A), Lambertian
**           radiance I / (pi r^2) (its total power 4 pi I): I / (pi r^2)
**           * cos * A * omega = 4 I cos omega.
**   rect:   a uniform point of it, intensity I cos (ray_light_sample_at's
**           falloff) spread over the area: I cos * omega.
**   directional: a uniform point of the disk of radius R across the
**           target, started outside the scene: I pi R^2.
*/
static int emit(ray_ctx *ctx, const emitter *e, const ray__light *sl,
                double pl, ray_ray *r, ray_rgb *power)
{
    const ray_light *l = &sl->desc;
    double f, omega = 1;
    ray_vec3 x, d;

    switch (l->kind) {
    case RAY_LIGHT_DIRECTIONAL: {
        double dx, dy, back;
        ray_vec3 t1, t2;
        d = v3_scale(sl->axis, -1.0);
        ray__concentric_disk(2 * ray_ctx_random(ctx) - 1,
                             2 * ray_ctx_random(ctx) - 1, &dx, &dy);
        ray__tangent_frame(d, &t1, &t2);
        back = v3_length(v3_sub(e->c, e->sc)) + e->sR + e->R;
        x = v3_add(v3_sub(e->c, v3_scale(d, back)),
                   v3_add(v3_scale(t1, e->R * dx), v3_scale(t2, e->R * dy)));
        f = RAY__PI * e->R * e->R;
        break;
    }
    case RAY_LIGHT_RECT: {
        double su = ray_ctx_random(ctx), sv = ray_ctx_random(ctx);
        x = v3_add(l->position, v3_add(v3_scale(l->edge1, su),
                                       v3_scale(l->edge2, sv)));
        d = aimed_dir(ctx, e, x, &omega);
        f = v3_dot(d, sl->axis) * omega;
        break;
    }
    case RAY_LIGHT_SPHERE: {
        ray_vec3 n = cone_dir(v3(0, 1, 0), -1, ray_ctx_random(ctx),
                              ray_ctx_random(ctx));
        x = v3_add(l->position, v3_scale(n, l->radius));
        d = aimed_dir(ctx, e, x, &omega);
        f = 4 * v3_dot(d, n) * omega;
        break;
    }
    default:
        x = l->position;
        d = aimed_dir(ctx, e, x, &omega);
        f = omega;
        break;
    }
    if (!(f > 0))
        return 0;
    f *= e->per_photon / pl;
    *power = ray_rgb_scale(l->intensity, f);
    r->org = x;
    r->dir = d;
    r->tmin = 0;
    r->tmax = HUGE_VAL;
    return 1;
}

/* The light of a uniform number u: the first whose cumulative power
** exceeds u * total (binary search). */
static unsigned pick_light(const emitter *e, double u, double *pl)
{
    size_t lo = 0, hi = e->s->n_lights - 1;
    double x = u * e->total, before;

    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (e->cdf[mid] > x)
            hi = mid;
        else
            lo = mid + 1;
    }
    before = lo > 0 ? e->cdf[lo - 1] : 0.0;
    *pl = (e->cdf[lo] - before) / e->total;
    return (unsigned)lo;
}

/* ---------------------------------------------------------- the pass */

typedef struct chunk {
    photon *ph;
    size_t n, cap;
    int failed;                  /* an allocation failed */
} chunk;

typedef struct pass {
    const ray_scene *s;
    emitter e;
    unsigned long long photons, seed;
    chunk *chunks;
    size_t n_chunks;
    unsigned threads;            /* tasks */
    struct pass_worker *workers; /* one per task */
    ray__progress *prog;         /* NULL: no callback */
} pass;

typedef struct pass_worker {
    ray_ctx ctx;
} pass_worker;

/* A photon's power (finite, >= 0) as a float: clamped to FLT_MAX, since
** converting a double beyond float's range is undefined (C99 6.3.1.5). */
static float to_float(double x)
{
    return x < (double)FLT_MAX ? (float)x : FLT_MAX;
}

static int store(const ray_scene *s, chunk *c, const ray_hit *hit,
                 ray_vec3 dir, ray_rgb power)
{
    photon *q;

    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 256;
        void *p = ray__realloc(s, c->ph, c->cap * sizeof *c->ph,
                               cap * sizeof *c->ph);
        if (p == NULL)
            return 0;
        c->ph = p;
        c->cap = cap;
    }
    q = &c->ph[c->n++];
    q->p = hit->p;
    q->power[0] = to_float(power.r);
    q->power[1] = to_float(power.g);
    q->power[2] = to_float(power.b);
    q->dir[0] = (float)dir.x;
    q->dir[1] = (float)dir.y;
    q->dir[2] = (float)dir.z;
    return 1;
}

/* Is w a weight a photon may carry on with (finite, >= 0)? */
static int weight_ok(ray_rgb w)
{
    return w.r >= 0 && w.g >= 0 && w.b >= 0 && w.r < HUGE_VAL &&
           w.g < HUGE_VAL && w.b < HUGE_VAL;
}

/*
** Photon i: emitted, traced through the scattering materials up to
** max_depth bounces (and, with pruning, until its power falls below
** min_weight of what it left the light with), stored at every hit on a
** gathering material after the first bounce.  Its first hit on a
** material that does not scatter ends it unstored: that light is the
** direct term the renderer traces itself.
*/
static void trace_photon(pass *job, ray_ctx *ctx, unsigned long long i,
                         chunk *c)
{
    const ray_scene *s = job->s;
    const ray__light *sl;
    unsigned bounces = 0;
    double pl, start;
    ray_rgb power;
    ray_ray r;

    ray__ctx_start(ctx, ray__mix64(ray__mix64(job->seed ^
                                              0x70686f746f6e73ull) + i));
    sl = &s->lights[pick_light(&job->e, ray_ctx_random(ctx), &pl)];
    if (!(pl > 0) || !emit(ctx, &job->e, sl, pl, &r, &power))
        return;
    start = max3(power);
    for (;;) {
        const ray_scene *owner;
        const ray_material *m;
        ray_shade_args args;
        ray_vec3 dir;
        ray_rgb w;
        unsigned mat;
        ray_hit hit;

        if (ray__intersect(s, &r, 0, &hit, &ctx->stats) <= 0)
            return;          /* gone (a stale instance was refused first) */
        owner = ray__hit_owner(s, &hit);
        mat = owner->prims[hit.geom_id].material;
        if (mat == RAY_NO_MATERIAL)
            return;
        m = &owner->materials[mat];
        ray__shade_args(s, &r, &hit, bounces, 1.0, &args);
        if (bounces > 0 && (m->effects & RAY_EFFECT_CAUSTICS)) {
            ray_vec3 u;
            if (v3_normalize(r.dir, &u) && !store(s, c, &hit, u, power)) {
                c->failed = 1;
                return;
            }
        }
        if (m->scatter == NULL || bounces >= s->limits.max_depth)
            return;
        /* The callback may draw random numbers; it may not trace:
        ** effects 0 makes ray_trace answer RAY_EEFFECT. */
        ctx->in_shade = 1;
        ctx->effects = 0;
        ctx->depth = bounces;
        if (!m->scatter(m->ud, ctx, &args, &dir, &w) || !weight_ok(w)) {
            ctx->in_shade = 0;
            return;
        }
        ctx->in_shade = 0;
        power = ray_rgb_mul(power, w);
        bounces++;
        if (!(max3(power) > 0) ||
            (s->prune && !(max3(power) >= s->limits.min_weight * start)))
            return;
        if (ray_spawn(&hit, dir, &r) != RAY_OK)
            return;
    }
}

/* Task "index": chunks index, index + tasks, ..., with its own context
** (its counters); no two tasks share a chunk or a context. */
static void pass_task(void *ud, unsigned index)
{
    pass *job = ud;
    pass_worker *w = &job->workers[index];
    size_t k;

    for (k = index; k < job->n_chunks; k += job->threads) {
        unsigned long long first = (unsigned long long)k * CHUNK, i;
        unsigned long long end = first + CHUNK < job->photons
                                     ? first + CHUNK : job->photons;
        for (i = first; i < end && !job->chunks[k].failed; i++)
            trace_photon(job, &w->ctx, i, &job->chunks[k]);
        if (job->prog != NULL &&
            ray__progress_add(job->prog, (size_t)(end - first)))
            return;          /* cancelled: the pass keeps nothing */
    }
}

/* The pass's progress record in *p, if there is a callback: every photon
** its total, a lock when tasks share it.  RAY_OK or RAY_ENOMEM. */
static int progress_start(pass *job, const ray_render_options *o,
                          ray__progress *p)
{
    memset(p, 0, sizeof *p);
    job->prog = NULL;
    if (o->progress == NULL)
        return RAY_OK;
    p->fn = o->progress;
    p->ud = o->progress_ud;
    p->total = (size_t)job->photons;       /* <= RAY_MAX_PHOTONS, 2^26 */
    if (job->threads > 1 &&
        ray__mutex_new(&job->s->alloc, &p->lock) != RAY_OK)
        return RAY_ENOMEM;
    job->prog = p;
    return RAY_OK;
}

/* Trace every chunk as job->threads tasks: on the scheduler, or on as
** many threads, the caller's one of them (a task whose thread could not
** start is run by the caller too). */
static int run_pass(pass *job, const ray_scene *s,
                    const ray_scheduler *sched,
                    const ray_render_options *o, unsigned long long *tests)
{
    ray__progress record;
    pass_worker *w;
    unsigned n = job->threads, i;
    size_t k;
    int rc = RAY_OK;

    if (progress_start(job, o, &record) != RAY_OK)
        return RAY_ENOMEM;
    w = ray__alloc(s, n * sizeof *w);
    if (w == NULL) {
        ray__mutex_free(&s->alloc, record.lock);
        return RAY_ENOMEM;
    }
    memset(w, 0, n * sizeof *w);
    for (i = 0; i < n; i++)
        w[i].ctx.scene = s;
    job->workers = w;
    ray__tasks_run(sched, &s->alloc, n, 0, n, pass_task, job);
    for (i = 0; i < n; i++)
        *tests += w[i].ctx.stats.tests;
    for (k = 0; k < job->n_chunks; k++)
        if (job->chunks[k].failed)
            rc = RAY_ENOMEM;
    if (record.cancelled)
        rc = RAY_ECANCELED;  /* the caller's word wins: nothing is kept */
    ray__mutex_free(&s->alloc, record.lock);
    ray__free(s, w, n * sizeof *w);
    return rc;
}

/* ---------------------------------------------------------- the grid */

/* Cell coordinates of p (floor((p - lo) / cell) per axis). */
static void cell_of(const ray_photon_map *m, ray_vec3 p, long long c[3])
{
    c[0] = (long long)floor((p.x - m->lo.x) / m->cell);
    c[1] = (long long)floor((p.y - m->lo.y) / m->cell);
    c[2] = (long long)floor((p.z - m->lo.z) / m->cell);
}

static size_t bucket_of(const ray_photon_map *m, const long long c[3])
{
    unsigned long long h = ray__mix64((unsigned long long)c[0]);
    h = ray__mix64(h ^ (unsigned long long)c[1]);
    h = ray__mix64(h ^ (unsigned long long)c[2]);
    return (size_t)(h & (m->buckets - 1));
}

/* The grid bucket of a stored photon. */
static size_t photon_bucket(const ray_photon_map *m, const photon *q)
{
    long long c[3];

    cell_of(m, q->p, c);
    return bucket_of(m, c);
}

/* Sort the chunks' photons, read in chunk order, into the grid's buckets
** (a stable counting sort, so a bucket lists its photons in index
** order).  The map's radius is set. */
static int build_grid(ray_photon_map *m, const pass *job)
{
    const ray_scene *s = m->scene;
    size_t n = 0, k, j, b, *count;
    double extent;

    for (k = 0; k < job->n_chunks; k++)
        n += job->chunks[k].n;
    m->n = n;
    if (n == 0)
        return RAY_OK;
    for (m->buckets = 1; m->buckets < n; m->buckets *= 2)
        ;
    m->ph = ray__alloc(s, n * sizeof *m->ph);
    m->start = ray__alloc(s, (m->buckets + 1) * sizeof *m->start);
    if (m->ph == NULL || m->start == NULL)
        return RAY_ENOMEM;
    m->lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    m->hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (k = 0; k < job->n_chunks; k++)
        for (j = 0; j < job->chunks[k].n; j++)
            grow_box(&m->lo, &m->hi, job->chunks[k].ph[j].p,
                     job->chunks[k].ph[j].p);
    extent = fmax(m->hi.x - m->lo.x,
                  fmax(m->hi.y - m->lo.y, m->hi.z - m->lo.z));
    m->cell = fmax(2 * m->radius, ldexp(extent, -MAX_CELLS_LOG2));
    count = m->start;
    memset(count, 0, (m->buckets + 1) * sizeof *count);
    for (k = 0; k < job->n_chunks; k++)
        for (j = 0; j < job->chunks[k].n; j++)
            count[photon_bucket(m, &job->chunks[k].ph[j]) + 1]++;
    for (b = 0; b < m->buckets; b++)
        count[b + 1] += count[b];
    /* count[b] is now bucket b's start; place, then shift back. */
    for (k = 0; k < job->n_chunks; k++)
        for (j = 0; j < job->chunks[k].n; j++) {
            const photon *q = &job->chunks[k].ph[j];
            m->ph[count[photon_bucket(m, q)]++] = *q;
        }
    for (b = m->buckets; b > 0; b--)
        m->start[b] = m->start[b - 1];
    m->start[0] = 0;
    return RAY_OK;
}

static void free_map(ray_photon_map *m)
{
    ray__allocator a = m->alloc;

    ray__release(&a, m->ph, m->n * sizeof *m->ph);
    ray__release(&a, m->start,
                 m->start != NULL ? (m->buckets + 1) * sizeof *m->start : 0);
    ray__release(&a, m, sizeof *m);
}

int ray__photon_map_make(const ray_scene *s, const ray_render_options *o,
                         ray_photon_map **out)
{
    const ray_scheduler *sched = ray__scheduler_pick(o->scheduler,
                                                     &s->scheduler);
    unsigned long long photons = o->photons, seed = o->seed;
    double radius = o->photon_radius;
    ray_photon_map *m;
    pass job;
    size_t k, i;
    int rc = RAY_OK;

    m = ray__alloc(s, sizeof *m);
    if (m == NULL)
        return RAY_ENOMEM;
    memset(m, 0, sizeof *m);
    memset(&job, 0, sizeof job);
    m->scene = s;
    m->alloc = s->alloc;
    job.s = s;
    job.e.s = s;
    find_target(&job.e);
    /* The automatic radius: D / 100 at 100 000 photons, times
    ** (N / 100 000)^(-1/6) (ray.h). */
    m->radius = radius > 0 ? radius
                           : job.e.diag / RADIUS_DIV *
                                 pow((double)photons / RADIUS_REF,
                                     -1.0 / 6.0);
    if (!(m->radius > 0 && ray__photon_radius_valid(m->radius))) {
        free_map(m);
        return RAY_EINVAL;     /* a radius whose area over- or underflows */
    }
    m->r2 = m->radius * m->radius;
    m->inv_area = 1.0 / (RAY__PI * m->r2);
    if ((s->effects & RAY_EFFECT_CAUSTICS) == 0) {
        *out = m;              /* nothing can make a caustic: no photon */
        return RAY_OK;
    }
    job.photons = photons;
    job.seed = seed;
    job.e.per_photon = 1.0 / (double)photons;
    job.n_chunks = (size_t)((photons + CHUNK - 1) / CHUNK);
    job.threads = ray__task_count(o->threads, sched);
    if (job.threads > job.n_chunks)
        job.threads = (unsigned)job.n_chunks;
    job.e.cdf = ray__alloc(s, s->n_lights * sizeof *job.e.cdf);
    job.chunks = ray__alloc(s, job.n_chunks * sizeof *job.chunks);
    if (job.chunks != NULL)       /* empty, for the cleanup below too */
        memset(job.chunks, 0, job.n_chunks * sizeof *job.chunks);
    if (job.e.cdf == NULL || job.chunks == NULL)
        rc = RAY_ENOMEM;
    else {
        for (i = 0; i < s->n_lights; i++) {
            job.e.total += light_power(&job.e, &s->lights[i].desc);
            job.e.cdf[i] = job.e.total;
        }
        if (job.e.total > 0 && job.e.total < HUGE_VAL) {
            rc = run_pass(&job, s, sched, o, &m->tests);
            m->emitted = photons;
        }
        if (rc == RAY_OK)
            rc = build_grid(m, &job);
    }
    if (job.chunks != NULL)
        for (k = 0; k < job.n_chunks; k++)
            ray__free(s, job.chunks[k].ph,
                      job.chunks[k].cap * sizeof *job.chunks[k].ph);
    ray__free(s, job.chunks, job.n_chunks * sizeof *job.chunks);
    ray__free(s, job.e.cdf, s->n_lights * sizeof *job.e.cdf);
    if (rc != RAY_OK) {
        free_map(m);
        return rc;
    }
    *out = m;
    return RAY_OK;
}

void ray__photon_map_counts(const ray_photon_map *m, ray_stats *st)
{
    st->photons_emitted += m->emitted;
    st->photons_stored += m->n;
    st->tests += m->tests;
}

/* ---------------------------------------------------------- public */

int ray_photon_map_build(const ray_scene *scene,
                         const ray_render_options *o, ray_photon_map **out)
{
    if (scene == NULL || o == NULL || out == NULL)
        return RAY_EINVAL;
    if (!scene->committed || ray__scene_stale(scene))
        return RAY_ESTATE;     /* as the queries and ray_render answer */
    if (o->photons == 0 || o->photons > RAY_MAX_PHOTONS ||
        !ray__photon_radius_valid(o->photon_radius))
        return RAY_EINVAL;
    return ray__photon_map_make(scene, o, out);
}

void ray_photon_map_free(ray_photon_map *map)
{
    if (map != NULL)
        free_map(map);
}

int ray_ctx_set_photon_map(ray_ctx *ctx, const ray_photon_map *map)
{
    if (ctx == NULL || (map != NULL && map->scene != ctx->scene))
        return RAY_EINVAL;
    ctx->photons = map;
    return RAY_OK;
}

/*
** The disk estimate: the photons of map m within r of the hit point p
** that travel against the side of the surface being shaded (dir . n < 0,
** n the shading side's normal), their power summed, over pi r^2.  The
** cells the sphere of radius r around p overlaps (at most 2 per axis: a
** cell is >= 2r) are visited in a fixed order; a photon is counted only
** in its own cell, so two cells that share a bucket count nothing twice.
** Not static, and apart from ray_caustics_at: a call that finds no map
** (every render without photons, on every diffuse hit) then costs its
** few tests, not this loop's register saves (Whitted render, issue 35).
*/
void ray__caustics_gather(const ray_photon_map *m, ray_vec3 p, ray_vec3 n,
                          ray_rgb *irradiance)
{
    long long lo[3], hi[3], c[3];
    double sum[3] = {0, 0, 0};

    if (m->n == 0 || !(p.x + m->radius >= m->lo.x &&
                       p.x - m->radius <= m->hi.x &&
                       p.y + m->radius >= m->lo.y &&
                       p.y - m->radius <= m->hi.y &&
                       p.z + m->radius >= m->lo.z &&
                       p.z - m->radius <= m->hi.z)) {
        irradiance->r = irradiance->g = irradiance->b = 0.0;
        return;
    }
    cell_of(m, v3_sub(p, v3(m->radius, m->radius, m->radius)), lo);
    cell_of(m, v3_add(p, v3(m->radius, m->radius, m->radius)), hi);
    for (c[0] = lo[0]; c[0] <= hi[0]; c[0]++)
        for (c[1] = lo[1]; c[1] <= hi[1]; c[1]++)
            for (c[2] = lo[2]; c[2] <= hi[2]; c[2]++) {
                size_t b = bucket_of(m, c), j;
                for (j = m->start[b]; j < m->start[b + 1]; j++) {
                    const photon *q = &m->ph[j];
                    long long qc[3];
                    ray_vec3 d = v3_sub(q->p, p);
                    if (v3_dot(d, d) > m->r2 ||
                        (double)q->dir[0] * n.x + (double)q->dir[1] * n.y +
                                (double)q->dir[2] * n.z >= 0)
                        continue;
                    cell_of(m, q->p, qc);
                    if (qc[0] != c[0] || qc[1] != c[1] || qc[2] != c[2])
                        continue;
                    sum[0] += (double)q->power[0];
                    sum[1] += (double)q->power[1];
                    sum[2] += (double)q->power[2];
                }
            }
    /* Finite, so that a material's 0 * E is 0, not NaN. */
    irradiance->r = fmin(sum[0] * m->inv_area, DBL_MAX);
    irradiance->g = fmin(sum[1] * m->inv_area, DBL_MAX);
    irradiance->b = fmin(sum[2] * m->inv_area, DBL_MAX);
}

int ray_caustics_at(ray_ctx *ctx, const ray_shade_args *args,
                    ray_rgb *irradiance)
{
    const ray_photon_map *m;

    if (ctx == NULL || args == NULL || args->hit == NULL ||
        irradiance == NULL)
        return RAY_EINVAL;
    m = ctx->photons;
    if (m == NULL || !(ctx->effects & RAY_EFFECT_CAUSTICS)) {
        irradiance->r = irradiance->g = irradiance->b = 0.0;
        return RAY_OK;
    }
    ctx->stats.photon_lookups++;
    ray__caustics_gather(m, args->hit->p, args->normal, irradiance);
    return RAY_OK;
}
