/* SPDX-License-Identifier: MIT */
/*
** render.c -- the image: rows handed to tasks (core/tasks.h: the built-in
** threads or the program's scheduler) in contiguous bands from a shared
** counter (dynamic scheduling: rows of a Whitted scene differ in cost by
** orders of magnitude), supersampled, deterministic.
*/
#include <string.h>

#include "core/platform.h"
#include "core/tasks.h"
#include "render/camera.h"

/*
** A pixel value as the float the image stores: always finite.  Accepted
** input can exceed float's range -- a background of 1e300, a point light
** 1e-20 from a surface (1/dist^2 = 1e40) -- and a plain conversion would
** store +Inf; such values are clamped to +-FLT_MAX (the brightest value
** the image can hold), and a NaN, which only a user material can produce,
** becomes 0.  ray_render(3) documents the rule.
*/
static float to_pixel(double x)
{
    if (!(x == x))
        return 0.0f;
    if (x > (double)FLT_MAX)
        return FLT_MAX;
    if (x < -(double)FLT_MAX)
        return -FLT_MAX;
    return (float)x;
}

/*
** What every worker shares.  "lock" guards next_row and cancelled, and is
** held only to take a row; "progress_lock" serialises the progress
** callback and guards rows_done and stopped, so a slow callback (a
** progress bar printing) does not keep the other threads from their rows.
** Nothing is shared in the pixel loop.
*/
typedef struct render_job {
    const ray_scene *scene;
    const ray_render_options *opt;
    ray__cam cam;
    unsigned y0, y1;
    unsigned side;           /* k if samples = k*k, else 0 */
    unsigned lattice;        /* n-rooks lattice generator (side == 0) */
    unsigned long long frame;  /* ray__frame_hash(opt->seed), made once */
    float *rgb;
    void *workers;           /* one per task (worker_at) */
    ray__mutex *lock, *progress_lock;
    unsigned threads;        /* tasks, for next_row's band size */
    unsigned next_row, rows_done;
    int cancelled, stopped;
} render_job;

typedef struct render_worker {
    ray_ctx ctx;
    unsigned band_next, band_end;  /* the rest of the worker's band */
    /* Adaptive antialiasing's lattice cache (lattice_get): two rows of
    ** lattice points at the finest level, width * 2^depth + 1 each, one
    ** for each parity of the lattice row of pixel corners they lie on,
    ** and the points inside the current pixel, (2^depth + 1)^2.  A key
    ** names what an entry holds -- the row's lattice y + 1, the pixel's
    ** serial number -- 0 nothing. */
    ray_rgb *row[2], *cell;
    unsigned long long *row_key[2], *cell_key;
    unsigned long long pixel;      /* serial number of the current pixel */
    unsigned long long x0, y0;     /* its top-left lattice point */
} render_worker;

/*
** Workers are laid out WORKER_STRIDE bytes apart: sizeof(render_worker)
** plus a spare cache line, rounded to 64, so one worker's counters (written
** on every ray) never share a cache line with another's (false sharing),
** whatever the alignment of the block.
*/
#define CACHE_LINE 64
#define WORKER_STRIDE \
    ((sizeof(render_worker) + 2 * CACHE_LINE - 1) / CACHE_LINE * CACHE_LINE)

static render_worker *worker_at(void *block, unsigned i)
{
    return (render_worker *)(void *)((char *)block + (size_t)i * WORKER_STRIDE);
}

/* Render threads get at least this much stack: each level of the ray tree
** nests ray_trace, the material callback and its locals (a few hundred
** bytes), and some C libraries (musl: 128 KiB) default to little. */
#define WORKER_STACK (4u << 20)

/*
** The stratum of sample s of n, as cell (cx, cy) of a grid of cells of
** size 1/kx x 1/ky.  A square n = k*k uses the k x k grid.  Any other n
** uses n-rooks strata (Shirley, "Discrepancy as a Quality Measure for
** Sample Distributions", Eurographics 1991): x stratum s, y stratum
** s*g mod n for a generator g coprime with n near n/phi (a rank-1 lattice
** in the spirit of the Fibonacci lattice), so every row and every column
** of an n x n grid holds exactly one sample and none is left empty --
** filling the first n cells of a ceil(sqrt n)^2 grid would leave part of
** the pixel unsampled.
*/
static void sample_cell(const render_job *job, unsigned s, double *cx,
                        double *cy, double *cells)
{
    unsigned n = job->opt->samples;

    if (job->side) {
        *cx = (double)(s % job->side);
        *cy = (double)(s / job->side);
        *cells = (double)job->side;
    } else {
        *cx = (double)s;
        *cy = (double)((unsigned long long)s * job->lattice % n);
        *cells = (double)n;
    }
}

static unsigned gcd(unsigned a, unsigned b)
{
    while (b != 0) {
        unsigned t = a % b;
        a = b;
        b = t;
    }
    return a;
}

/* The lattice generator for n samples: the integer nearest n/phi that is
** coprime with n (1 always is). */
static unsigned lattice_generator(unsigned n)
{
    unsigned g = (unsigned)((double)n * 0.6180339887498949 + 0.5);

    while (g > 1 && gcd(g, n) != 1)
        g--;
    return g ? g : 1;
}

/* One more pixel that took n samples, in the histogram. */
static void count_pixel(ray_stats *st, unsigned long long n)
{
    st->pixels++;
    st->samples_hist[n < RAY_HIST_BINS - 1 ? n : RAY_HIST_BINS - 1]++;
}

/*
** One pixel.  Sample s of pixel (x, y) is seeded from (seed, x, y, s)
** alone, so the value does not depend on the thread or the region.  One
** sample looks through the pixel centre; several are jittered inside
** their strata.
*/
static void render_pixel(render_job *job, ray_ctx *ctx, unsigned x,
                         unsigned y, float *out)
{
    const ray_render_options *o = job->opt;
    ray_rgb sum = {0, 0, 0};
    unsigned s;

    for (s = 0; s < o->samples; s++) {
        double sx = 0.5, sy = 0.5, lx = 0, ly = 0;
        ray_ray r;
        ray_rgb c;

        ray__ctx_start(ctx, ray__pixel_seed_from(job->frame, x, y, s));
        if (o->samples > 1) {
            double cx, cy, cells;
            sample_cell(job, s, &cx, &cy, &cells);
            sx = (cx + ray_ctx_random(ctx)) / cells;
            sy = (cy + ray_ctx_random(ctx)) / cells;
        }
        if (job->cam.lens_radius > 0) {
            lx = 2 * ray_ctx_random(ctx) - 1;
            ly = 2 * ray_ctx_random(ctx) - 1;
        }
        ray__camera_ray(&job->cam, x + sx, y + sy, lx, ly, &r);
        if (ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c) == RAY_OK) {
            sum.r += c.r;
            sum.g += c.g;
            sum.b += c.b;
        }
    }
    /* The mean: sum / samples, or sum * 2^-k where samples = 2^k (one
    ** sample: 1), the same bits without the three divisions (issue 35):
    ** x / 2^k and x * 2^-k are both the exact x 2^-k rounded once (IEEE
    ** 754, 4.3: every operation is the exact result rounded), whether
    ** or not it is subnormal, since 2^-k >= 2^-16 is exact. */
    if ((o->samples & (o->samples - 1)) == 0) {
        double inv = 1.0 / o->samples;
        out[0] = to_pixel(sum.r * inv);
        out[1] = to_pixel(sum.g * inv);
        out[2] = to_pixel(sum.b * inv);
    } else {
        out[0] = to_pixel(sum.r / o->samples);
        out[1] = to_pixel(sum.g / o->samples);
        out[2] = to_pixel(sum.b / o->samples);
    }
    count_pixel(&ctx->stats, o->samples);
}

/* ------------------------------------------------ adaptive antialiasing */

/*
** Whitted's adaptive supersampling ("An Improved Illumination Model for
** Shaded Display", CACM 23(6), 1980): sample the corners of the pixel and
** subdivide only where they differ.  Samples lie on a lattice of 2^depth
** points per pixel side; lattice point (lx, ly) always gets the same ray
** and the same random numbers, seeded from its position, whoever
** computes it -- so neighbouring pixels, rows taken by other threads and
** separately rendered regions all agree bit for bit.
*/
static ray_rgb lattice_sample(render_job *job, ray_ctx *ctx,
                              unsigned long long lx, unsigned long long ly)
{
    double scale = 1.0 / (double)(1u << job->opt->adaptive_depth);
    double lens_x = 0, lens_y = 0;
    ray_ray r;
    ray_rgb c = {0, 0, 0};

    /* The lattice coordinates, folded into the 32-bit hash inputs; the
    ** sample index 0xA0000000 + depth keeps these apart from the uniform
    ** sampler's streams. */
    ray__ctx_start(ctx, ray__pixel_seed_from(job->frame,
                                             (unsigned)(lx ^ (lx >> 32)),
                                             (unsigned)(ly ^ (ly >> 32)),
                                             0xA0000000u +
                                                 job->opt->adaptive_depth));
    if (job->cam.lens_radius > 0) {
        lens_x = 2 * ray_ctx_random(ctx) - 1;
        lens_y = 2 * ray_ctx_random(ctx) - 1;
    }
    ray__camera_ray(&job->cam, (double)lx * scale, (double)ly * scale, lens_x,
                    lens_y, &r);
    if (ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c) != RAY_OK)
        c.r = c.g = c.b = 0;
    return c;
}

/* Do the four corners differ, in any channel, by more than the threshold?
** ray__fmin and ray__fmax: libm's bits without its calls (core/vec.h). */
static int corners_differ(const ray_rgb c[4], double threshold)
{
    double lo[3], hi[3];
    int k;

    lo[0] = hi[0] = c[0].r;
    lo[1] = hi[1] = c[0].g;
    lo[2] = hi[2] = c[0].b;
    for (k = 1; k < 4; k++) {
        lo[0] = ray__fmin(lo[0], c[k].r);
        hi[0] = ray__fmax(hi[0], c[k].r);
        lo[1] = ray__fmin(lo[1], c[k].g);
        hi[1] = ray__fmax(hi[1], c[k].g);
        lo[2] = ray__fmin(lo[2], c[k].b);
        hi[2] = ray__fmax(hi[2], c[k].b);
    }
    return hi[0] - lo[0] > threshold || hi[1] - lo[1] > threshold ||
           hi[2] - lo[2] > threshold;
}

static ray_rgb rgb_mean4(const ray_rgb c[4])
{
    ray_rgb m;
    m.r = 0.25 * (c[0].r + c[1].r + c[2].r + c[3].r);
    m.g = 0.25 * (c[0].g + c[1].g + c[2].g + c[3].g);
    m.b = 0.25 * (c[0].b + c[1].b + c[2].b + c[3].b);
    return m;
}

/* Where lattice point (lx, ly) of the current pixel is cached: on the
** pixel row's top or bottom edge, a row; else the pixel's cell grid. */
static void lattice_slot(const render_job *job, render_worker *w,
                         unsigned long long lx, unsigned long long ly,
                         ray_rgb **value, unsigned long long **key,
                         unsigned long long *want)
{
    unsigned long long side = 1ull << job->opt->adaptive_depth;

    if (ly == w->y0 || ly == w->y0 + side) {
        unsigned parity = (unsigned)((ly >> job->opt->adaptive_depth) & 1);
        *value = w->row[parity] + lx;
        *key = w->row_key[parity] + lx;
        *want = ly + 1;
    } else {
        size_t i = (size_t)((ly - w->y0) * (side + 1) + (lx - w->x0));
        *value = w->cell + i;
        *key = w->cell_key + i;
        *want = w->pixel;
    }
}

/*
** Lattice point (lx, ly) of the current pixel (lx within [x0, x0 + side],
** ly within [y0, y0 + side]): from the cache if it holds it, else traced
** and cached.  So a point is traced once however many squares use it: a
** point on the edge between two refined squares, on the edge between two
** pixels of the row (the left column comes from the previous pixel,
** render_row_adaptive), on the edge between two rows (kept when the
** worker takes the next row).  A cached value is the one a fresh trace
** gives, as lattice_sample depends on the position alone, so the image is
** the same bytes whichever worker traced what.
*/
static ray_rgb lattice_get(render_job *job, render_worker *w,
                           unsigned long long lx, unsigned long long ly)
{
    ray_rgb *value;
    unsigned long long *key, want;

    lattice_slot(job, w, lx, ly, &value, &key, &want);
    if (*key != want) {
        *value = lattice_sample(job, &w->ctx, lx, ly);
        *key = want;
    }
    return *value;
}

/*
** The mean over the square of side "size" lattice steps at (lx, ly),
** corners c = (top-left, top-right, bottom-left, bottom-right): the mean
** of the corners, or, where they differ and the lattice allows, the mean of
** the four quarter squares, for which the edge midpoints and the centre
** are needed (5 more samples, counted in *n whether traced or cached).
*/
static ray_rgb adaptive_square(render_job *job, render_worker *w,
                               unsigned long long lx, unsigned long long ly,
                               unsigned long long size, const ray_rgb c[4],
                               unsigned long long *n)
{
    unsigned long long h = size / 2;
    ray_rgb top, left, mid, right, bottom, q[4], sub[4];

    if (size < 2 || !corners_differ(c, job->opt->adaptive_threshold))
        return rgb_mean4(c);
    top = lattice_get(job, w, lx + h, ly);
    left = lattice_get(job, w, lx, ly + h);
    mid = lattice_get(job, w, lx + h, ly + h);
    right = lattice_get(job, w, lx + size, ly + h);
    bottom = lattice_get(job, w, lx + h, ly + size);
    *n += 5;
    q[0] = c[0], q[1] = top, q[2] = left, q[3] = mid;
    sub[0] = adaptive_square(job, w, lx, ly, h, q, n);
    q[0] = top, q[1] = c[1], q[2] = mid, q[3] = right;
    sub[1] = adaptive_square(job, w, lx + h, ly, h, q, n);
    q[0] = left, q[1] = mid, q[2] = c[2], q[3] = bottom;
    sub[2] = adaptive_square(job, w, lx, ly + h, h, q, n);
    q[0] = mid, q[1] = right, q[2] = bottom, q[3] = c[3];
    sub[3] = adaptive_square(job, w, lx + h, ly + h, h, q, n);
    return rgb_mean4(sub);
}

/*
** One row, adaptively: the corners along its top and bottom edges, then
** each pixel refined from its four corners.  Every lattice point goes
** through the cache (lattice_get): a worker that rendered the row above
** finds this row's top edge there, corners and refined points alike, so
** where nothing varies a row costs one camera ray per pixel (plus one
** lattice row per band of rows, next_row).  A pixel's sample count is the
** lattice points its estimate uses, a shared one counted by each square
** that uses it: 4 to 4 + 5 (4^d - 1) / 3.
*/
static void render_row_adaptive(render_job *job, render_worker *w,
                                unsigned row, float *out)
{
    unsigned long long side = 1ull << job->opt->adaptive_depth;
    unsigned x, width = job->opt->width;
    size_t j, stride = (size_t)side + 1;

    w->y0 = row * side;
    w->x0 = 0;
    for (x = 0; x <= width; x++) {
        (void)lattice_get(job, w, x * side, w->y0);
        (void)lattice_get(job, w, x * side, w->y0 + side);
    }
    for (x = 0; x < width; x++) {
        unsigned long long n = 4;
        ray_rgb c[4], m;
        /* A new serial number voids the cell grid; the previous pixel's
        ** right column, if cached, is this one's left. */
        w->pixel++;
        if (x > 0)
            for (j = 1; j + 1 < stride; j++)
                if (w->cell_key[j * stride + side] == w->pixel - 1) {
                    w->cell[j * stride] = w->cell[j * stride + side];
                    w->cell_key[j * stride] = w->pixel;
                }
        w->x0 = x * side;
        c[0] = lattice_get(job, w, w->x0, w->y0);
        c[1] = lattice_get(job, w, w->x0 + side, w->y0);
        c[2] = lattice_get(job, w, w->x0, w->y0 + side);
        c[3] = lattice_get(job, w, w->x0 + side, w->y0 + side);
        m = adaptive_square(job, w, w->x0, w->y0, side, c, &n);
        out[3 * (size_t)x] = to_pixel(m.r);
        out[3 * (size_t)x + 1] = to_pixel(m.g);
        out[3 * (size_t)x + 2] = to_pixel(m.b);
        count_pixel(&w->ctx.stats, n);
    }
}

/*
** Take the next row, or return 0 when none is left or the render was
** cancelled.  Rows go out in contiguous bands, each a quarter of the
** remaining rows' share per thread, at least one ("guided" scheduling,
** Polychronopoulos and Kuck, IEEE Trans. Computers 36(12), 1987): a
** worker mostly takes consecutive rows, which adaptive antialiasing needs
** to reuse a row's bottom edge as the next row's top, and the bands
** shrink toward the end, so the threads still finish together.  The band
** sizes depend only on the rows left, never on which thread asks.
*/
static int next_row(render_job *job, render_worker *w, unsigned *row)
{
    int ok;

    ray__mutex_lock(job->lock);
    ok = !job->cancelled;
    if (ok && w->band_next == w->band_end) {
        unsigned left = job->y1 - job->next_row;
        unsigned band = left / job->threads / 4;
        if (band < 1)
            band = left < 1 ? left : 1;
        w->band_next = job->next_row;
        w->band_end = job->next_row += band;
    }
    ok = ok && w->band_next < w->band_end;
    if (ok)
        *row = w->band_next++;
    ray__mutex_unlock(job->lock);
    return ok;
}

static void row_finished(render_job *job)
{
    const ray_render_options *o = job->opt;
    int cancel = 0;

    ray__mutex_lock(job->progress_lock);
    job->rows_done++;
    if (o->progress != NULL && !job->stopped &&
        o->progress(o->progress_ud, job->rows_done, job->y1 - job->y0) != 0)
        cancel = job->stopped = 1;
    ray__mutex_unlock(job->progress_lock);
    if (cancel) {
        ray__mutex_lock(job->lock);
        job->cancelled = 1;
        ray__mutex_unlock(job->lock);
    }
}

/* Task "index": its worker takes rows until none is left.  Each worker
** is one task's, so no two threads share one. */
static void render_task(void *ud, unsigned index)
{
    render_job *job = ud;
    render_worker *w = worker_at(job->workers, index);
    unsigned row, x;

    while (next_row(job, w, &row)) {
        float *out = job->rgb + (size_t)(row - job->y0) * job->opt->width * 3;
        if (job->opt->adaptive_threshold > 0)
            render_row_adaptive(job, w, row, out);
        else
            for (x = 0; x < job->opt->width; x++)
                render_pixel(job, &w->ctx, x, row, out + 3 * (size_t)x);
        row_finished(job);
    }
}

/* The lattice cache's sizes (render_worker): entries in a row, 0 if a
** row's arrays would not fit in a size_t; entries in the cell grid. */
static size_t cache_row(const ray_render_options *o)
{
    size_t side = (size_t)1 << o->adaptive_depth;
    size_t most = (size_t)-1 / sizeof(ray_rgb);

    return o->width < (most - 1) / side ? o->width * side + 1 : 0;
}

static size_t cache_cell(const ray_render_options *o)
{
    size_t side = ((size_t)1 << o->adaptive_depth) + 1;   /* 257 at most */
    return side * side;
}

/* Each worker's lattice cache for adaptive antialiasing, keys zeroed. */
static int alloc_caches(const ray_scene *s, void *workers, unsigned n,
                        const ray_render_options *o)
{
    size_t row = cache_row(o), cell = cache_cell(o);
    unsigned i, k;

    if (row == 0)
        return RAY_ENOMEM;
    for (i = 0; i < n; i++) {
        render_worker *w = worker_at(workers, i);
        for (k = 0; k < 2; k++) {
            w->row[k] = ray__alloc(s, row * sizeof(ray_rgb));
            w->row_key[k] = ray__alloc(s, row * sizeof(unsigned long long));
            if (w->row[k] == NULL || w->row_key[k] == NULL)
                return RAY_ENOMEM;
            memset(w->row_key[k], 0, row * sizeof(unsigned long long));
        }
        w->cell = ray__alloc(s, cell * sizeof(ray_rgb));
        w->cell_key = ray__alloc(s, cell * sizeof(unsigned long long));
        if (w->cell == NULL || w->cell_key == NULL)
            return RAY_ENOMEM;
        memset(w->cell_key, 0, cell * sizeof(unsigned long long));
    }
    return RAY_OK;
}

/* Release what alloc_caches got (NULLs included: ray__free takes them). */
static void free_caches(const ray_scene *s, void *workers, unsigned n,
                        const ray_render_options *o)
{
    size_t row = cache_row(o), cell = cache_cell(o);
    unsigned i, k;

    for (i = 0; i < n; i++) {
        render_worker *w = worker_at(workers, i);
        for (k = 0; k < 2; k++) {
            ray__free(s, w->row[k], row * sizeof(ray_rgb));
            ray__free(s, w->row_key[k], row * sizeof(unsigned long long));
            w->row[k] = NULL;
            w->row_key[k] = NULL;
        }
        ray__free(s, w->cell, cell * sizeof(ray_rgb));
        ray__free(s, w->cell_key, cell * sizeof(unsigned long long));
        w->cell = NULL;
        w->cell_key = NULL;
    }
}

/* Sum the workers' counters (each thread counted into its own). */
static void sum_stats(void *workers, unsigned n, ray_stats *out)
{
    unsigned i, k;

    memset(out, 0, sizeof *out);
    for (i = 0; i < n; i++) {
        const ray_stats *s = &worker_at(workers, i)->ctx.stats;
        for (k = 0; k < RAY_KIND_COUNT; k++)
            out->rays[k] += s->rays[k];
        out->tests += s->tests;
        for (k = 0; k < RAY_PRIM_KINDS; k++)
            out->tests_by_kind[k] += s->tests_by_kind[k];
        for (k = 0; k < RAY_HIST_BINS; k++)
            out->samples_hist[k] += s->samples_hist[k];
        out->pixels += s->pixels;
        out->cut_depth += s->cut_depth;
        out->cut_weight += s->cut_weight;
        out->cut_fanout += s->cut_fanout;
        out->root_failures += s->root_failures;
        out->photon_lookups += s->photon_lookups;
        out->filter_calls += s->filter_calls;
        out->shadows_undeclared += s->shadows_undeclared;
        out->traces_undeclared += s->traces_undeclared;
        if (s->max_depth > out->max_depth)
            out->max_depth = s->max_depth;
    }
}

/*
** Make the job's two mutexes, run its n tasks over its rows (on the
** scheduler, or the calling thread and n - 1 started ones: if one cannot
** be started the render goes on with fewer, the image the same), sum
** their counters into *stats (if any).  RAY_ENOMEM if a mutex cannot be
** made, RAY_ECANCELED if the progress callback cancelled, else RAY_OK.
*/
static int run_job(render_job *job, const ray_scheduler *sched, unsigned n,
                   ray_stats *stats)
{
    const ray__allocator *a = &job->scene->alloc;

    if (ray__mutex_new(a, &job->lock) != RAY_OK)
        return RAY_ENOMEM;
    if (ray__mutex_new(a, &job->progress_lock) != RAY_OK) {
        ray__mutex_free(a, job->lock);
        return RAY_ENOMEM;
    }
    job->next_row = job->y0;
    job->rows_done = 0;
    job->cancelled = 0;
    job->stopped = 0;
    ray__tasks_run(sched, a, n, WORKER_STACK, n, render_task, job);
    ray__mutex_free(a, job->progress_lock);
    ray__mutex_free(a, job->lock);
    if (stats != NULL)
        sum_stats(job->workers, n, stats);
    return job->cancelled ? RAY_ECANCELED : RAY_OK;
}

/*
** A camera ray's cone spread (unless ray_render_options.no_cones): one
** pixel's angle, atan(2 tan(vfov/2) / height) (Akenine-Moller et al., Ray Tracing Gems,
** 2019, eq. 20.30), per sample the angle of its stratum: / sqrt(samples).
** Adaptive antialiasing's lattice points take the whole pixel's.
*/
static double pixel_spread(const render_job *job)
{
    const ray_render_options *o = job->opt;
    double pixel = atan(2.0 * job->cam.half_h / (double)o->height);

    if (o->adaptive_threshold > 0)
        return pixel;
    return pixel / sqrt((double)o->samples);
}

/* Can a material of s read a ray's cone (ray__material_reads_cone)? */
static int materials_read_cone(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_materials; i++)
        if (ray__material_reads_cone(&s->materials[i]))
            return 1;
    return 0;
}

/*
** Can a material of s, or of a scene it instances, read a ray's cone?
** Only then does a render's camera ray carry one: the cone's width and
** spread, carried through every hit and bend of the ray tree (trace.c,
** cone_at_hit, secondary_cone: lengths, a curvature, a square root and
** divisions at each hit), are work only a material that reads them
** needs.  Whitted's scene declares RAY_EFFECT_TEXTURE for its
** checkerboard, which reads (u, v) alone: its cones were 6% of the
** render's instructions (693.6M -> 650.3M, callgrind of examples/whitted
** at 512 x 384, one sample, one thread; issue 35), for the same image,
** byte for byte.  The materials are asked, not the geometry (a material
** no geometry uses counts too), and a child once for a run of its
** instances: the cost is the materials' and instances' count, not the
** geometry's, at every call (a banded render calls often).  A child with
** instances of its own (instance.c refuses them) counts as "may read".
*/
static int scene_reads_cone(const ray_scene *s)
{
    const ray_scene *seen = NULL;
    size_t i;

    if (materials_read_cone(s))
        return 1;
    for (i = 0; i < s->n_instances; i++) {
        const ray__instance *in = &s->instances[i];
        if (in->removed || in->child == seen)
            continue;              /* a removed one's child may be gone */
        if (in->child->n_instances > 0 || materials_read_cone(in->child))
            return 1;
        seen = in->child;
    }
    return 0;
}

int ray_render(const ray_scene *scene, const ray_camera *camera_in,
               const ray_render_options *opt_in, float *rgb, ray_stats *stats)
{
    ray_render_options o;
    const ray_render_options *opt = &o;
    ray_camera cam;
    const ray_camera *camera = &cam;
    render_job job;
    ray_photon_map *map = NULL;
    const ray_scheduler *sched;
    double spread;
    void *workers;
    unsigned n, i;
    int rc;

    /* The argument checks, all in ray_render_check (check.c), which
    ** a caller runs again with a buffer to learn why. */
    rc = ray_render_check(scene, camera_in, opt_in, NULL, NULL, 0);
    if (rc != RAY_OK)
        return rc;
    if (rgb == NULL)
        return RAY_EINVAL;
    /* Zero is the default: the render reads the values zeros stand for
    ** (the checks above read the same, ray__render_defaults). */
    ray__render_defaults(opt_in, camera_in, &o, &cam);
    job.y1 = opt->y1 ? opt->y1 : opt->height;
    job.scene = scene;
    job.opt = opt;
    job.frame = ray__frame_hash(opt->seed);
    job.y0 = opt->y0;
    rc = ray__camera_setup(&job.cam, camera, opt->width, opt->height);
    if (rc != RAY_OK)
        return rc;
    job.side = ray__strata_side(opt->samples);
    if (job.side * job.side != opt->samples)
        job.side = 0;
    job.lattice = lattice_generator(opt->samples);
    sched = ray__scheduler_pick(opt->scheduler, &scene->scheduler);
    n = ray__task_count(opt->threads, sched);
    if (n > job.y1 - job.y0)
        n = job.y1 - job.y0;
    if (WORKER_STRIDE > (size_t)-1 / n)        /* n >= 1 here */
        return RAY_ENOMEM;
    job.threads = n;
    workers = ray__alloc(scene, n * WORKER_STRIDE);
    if (workers == NULL)
        return RAY_ENOMEM;
    memset(workers, 0, n * WORKER_STRIDE);
    job.workers = workers;
    /* No cone where nothing reads it: the tracer carries one only for
    ** a scene that declared RAY_EFFECT_TEXTURE (trace.c). */
    spread = !opt->no_cones && (scene->effects & RAY_EFFECT_TEXTURE) &&
                     scene_reads_cone(scene)
                 ? pixel_spread(&job)
                 : 0.0;
    for (i = 0; i < n; i++) {
        worker_at(workers, i)->ctx.scene = scene;
        worker_at(workers, i)->ctx.cone_spread = spread;
    }
    job.rgb = rgb;
    /* Caustics: the photon pass first, on as many threads as asked for
    ** (not capped by the rows), and only where a caustic can exist. */
    if (opt->photons > 0 && (scene->effects & RAY_EFFECT_CAUSTICS)) {
        rc = ray__photon_map_make(scene, opt, &map);
        if (rc != RAY_OK) {
            ray__free(scene, workers, n * WORKER_STRIDE);
            return rc;
        }
        for (i = 0; i < n; i++)
            worker_at(workers, i)->ctx.photons = map;
    }
    rc = RAY_ENOMEM;
    if (opt->adaptive_threshold <= 0)
        rc = run_job(&job, sched, n, stats);
    else {
        if (alloc_caches(scene, workers, n, opt) == RAY_OK)
            rc = run_job(&job, sched, n, stats);
        free_caches(scene, workers, n, opt);
    }
    if (map != NULL) {
        if (stats != NULL && rc != RAY_ENOMEM)
            ray__photon_map_counts(map, stats);
        ray_photon_map_free(map);
    }
    ray__free(scene, workers, n * WORKER_STRIDE);
    return rc;
}
