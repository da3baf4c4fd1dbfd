/*
** render.c -- the image: rows handed to pthreads one at a time from a
** shared counter (dynamic scheduling: rows of a Whitted scene differ in
** cost by orders of magnitude), supersampled, deterministic.
*/
#include <pthread.h>
#include <string.h>
#include <unistd.h>

#include "camera.h"

/* What every worker shares.  The mutex guards next_row, rows_done,
** cancelled and the progress callback; nothing in the pixel loop. */
typedef struct render_job {
    const ray_scene *scene;
    const ray_render_options *opt;
    ray__cam cam;
    unsigned y0, y1, side;   /* side: strata per axis (side^2 >= samples) */
    float *rgb;
    pthread_mutex_t lock;
    unsigned next_row, rows_done;
    int cancelled;
} render_job;

typedef struct render_worker {
    render_job *job;
    ray_ctx ctx;
    pthread_t thread;
    int started;
} render_worker;

/*
** One pixel.  Sample s of pixel (x, y) is seeded from (seed, x, y, s)
** alone, so the value does not depend on the thread or the region.  One
** sample looks through the pixel centre; several are jittered in the
** cells of a side x side grid (stratified when samples is a square).
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

        ray__ctx_start(ctx, ray__pixel_seed(o->seed, x, y, s));
        if (o->samples > 1) {
            sx = ((double)(s % job->side) + ray_ctx_random(ctx)) / job->side;
            sy = ((double)(s / job->side % job->side) +
                  ray_ctx_random(ctx)) / job->side;
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
    out[0] = (float)(sum.r / o->samples);
    out[1] = (float)(sum.g / o->samples);
    out[2] = (float)(sum.b / o->samples);
}

/* Take the next row, or return 0 when none is left or the render was
** cancelled. */
static int next_row(render_job *job, unsigned *row)
{
    int ok;

    pthread_mutex_lock(&job->lock);
    ok = !job->cancelled && job->next_row < job->y1;
    if (ok)
        *row = job->next_row++;
    pthread_mutex_unlock(&job->lock);
    return ok;
}

static void row_finished(render_job *job)
{
    const ray_render_options *o = job->opt;

    pthread_mutex_lock(&job->lock);
    job->rows_done++;
    if (o->progress != NULL && !job->cancelled &&
        o->progress(o->progress_ud, job->rows_done, job->y1 - job->y0) != 0)
        job->cancelled = 1;
    pthread_mutex_unlock(&job->lock);
}

static void *worker_main(void *arg)
{
    render_worker *w = arg;
    render_job *job = w->job;
    unsigned row, x;

    while (next_row(job, &row)) {
        float *out = job->rgb + (size_t)(row - job->y0) * job->opt->width * 3;
        for (x = 0; x < job->opt->width; x++)
            render_pixel(job, &w->ctx, x, row, out + 3 * (size_t)x);
        row_finished(job);
    }
    return NULL;
}

static unsigned online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (unsigned)n : 1u;
}

void ray_render_options_init(ray_render_options *o, unsigned width,
                             unsigned height)
{
    if (o == NULL)
        return;
    memset(o, 0, sizeof *o);
    o->width = width;
    o->height = height;
    o->samples = 1;
}

static int options_valid(const ray_render_options *o, unsigned *y1)
{
    *y1 = o->y1 ? o->y1 : o->height;
    return o->width > 0 && o->height > 0 && o->samples > 0 &&
           o->y0 < *y1 && *y1 <= o->height &&
           o->width <= (size_t)-1 / 3 / sizeof(float) / o->height;
}

/* Sum the workers' counters (each thread counted into its own). */
static void sum_stats(const render_worker *w, unsigned n, ray_stats *out)
{
    unsigned i, k;

    memset(out, 0, sizeof *out);
    for (i = 0; i < n; i++) {
        const ray_stats *s = &w[i].ctx.stats;
        for (k = 0; k < RAY_KIND_COUNT; k++)
            out->rays[k] += s->rays[k];
        out->tests += s->tests;
        out->cut_depth += s->cut_depth;
        out->cut_weight += s->cut_weight;
        out->cut_fanout += s->cut_fanout;
        if (s->max_depth > out->max_depth)
            out->max_depth = s->max_depth;
    }
}

/*
** The calling thread is worker 0; threads - 1 more are started.  If one
** cannot be created, the render goes on with fewer: the image is the same.
*/
static void run_workers(render_worker *w, unsigned n)
{
    unsigned i;

    for (i = 1; i < n; i++)
        w[i].started = pthread_create(&w[i].thread, NULL, worker_main,
                                      &w[i]) == 0;
    worker_main(&w[0]);
    for (i = 1; i < n; i++)
        if (w[i].started)
            pthread_join(w[i].thread, NULL);
}

int ray_render(const ray_scene *scene, const ray_camera *camera,
               const ray_render_options *opt, float *rgb, ray_stats *stats)
{
    render_job job;
    render_worker *w;
    unsigned n, i;
    int rc;

    if (scene == NULL || camera == NULL || opt == NULL || rgb == NULL ||
        !scene->committed || !options_valid(opt, &job.y1))
        return RAY_EINVAL;
    job.scene = scene;
    job.opt = opt;
    job.y0 = opt->y0;
    rc = ray__camera_setup(&job.cam, camera, opt->width, opt->height);
    if (rc != RAY_OK)
        return rc;
    for (job.side = 1; job.side * job.side < opt->samples; job.side++)
        ;
    n = opt->threads ? opt->threads : online_cpus();
    if (n > job.y1 - job.y0)
        n = job.y1 - job.y0;
    w = ray__alloc(scene, n * sizeof *w);
    if (w == NULL)
        return RAY_ENOMEM;
    memset(w, 0, n * sizeof *w);
    for (i = 0; i < n; i++) {
        w[i].job = &job;
        w[i].ctx.scene = scene;
    }
    if (pthread_mutex_init(&job.lock, NULL) != 0) {
        ray__free(scene, w, n * sizeof *w);
        return RAY_ENOMEM;
    }
    job.rgb = rgb;
    job.next_row = job.y0;
    job.rows_done = 0;
    job.cancelled = 0;
    run_workers(w, n);
    pthread_mutex_destroy(&job.lock);
    if (stats != NULL)
        sum_stats(w, n, stats);
    ray__free(scene, w, n * sizeof *w);
    return job.cancelled ? RAY_ECANCELED : RAY_OK;
}
