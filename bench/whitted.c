/* SPDX-License-Identifier: MIT */
/*
** whitted.c -- libray against POV-Ray 3.7 on Whitted's scene
** (examples/scenes.h whitted_scene; bench/whitted.pov is the same scene
** for POV-Ray, with what POV cannot match said in its header), in the
** same run.  Prints Markdown; asserts nothing.
**
**     whitted [SCENE.pov]        (default bench/whitted.pov, run from the
**                                 repository root as bench/run.sh does)
**
** 1. One and two threads, one sample per pixel, no antialiasing, 1024 x
**    768: the render time of libray (ray_render alone, the scene built before) and
**    of POV-Ray (its own "Trace Time" statistic, so its start-up, parsing
**    and bounding are left out; its wall time, start to PNG written, is
**    given too), the rays each traced (camera, reflected, refracted and
**    shadow, from ray_stats and from POV's statistics), rays per second
**    and the time of a ray, and how far the two images are apart.
** 2. Antialiasing at equal image error: libray's adaptive mode
**    (ray_render_options adaptive_threshold, depth 2, and one row at
**    depth 3) and POV-Ray's +A
**    (method 1, its defaults: +R3, jitter on) at several thresholds, one
**    thread each.  Each image's error is the RMSE against a reference of
**    the SAME renderer, in 8-bit sRGB levels (0-255, the PNG's values, as
**    one sees them): libray's is uniform 256 samples per pixel (16 x 16
**    jittered strata), POV-Ray's +A0.0 +AM1 +R9 (every pixel that differs
**    at all from its neighbours gets POV's largest grid, 9 x 9 jittered
**    samples -- POV's method 1 takes no more).  Camera rays per pixel:
**    libray's ray_stats primary rays, POV's "Pixels" + "Samples" (POV
**    traces a border of extra pixels around its blocks when
**    antialiasing; they count), over width x height.
**
** Method: every timing is the median of REPS repetitions after one
** warm-up of each; ours and POV's alternate within each repetition, so a
** noisy neighbour hits both, and the ratio is the median of the
** repetitions' own ratios (bench/mesh.c).  The references use 2 threads
** (only their image matters).  BENCH_QUICK=1: 320 x 240, 3 repetitions,
** references of 64 samples per pixel (libray) and +R8 (POV).
** Without povray on PATH (or built with PNG=0: POV's image is read with
** libpng) the libray rows are printed and POV-Ray's are skipped (Debian:
** apt-get install povray; make bench installs it as root).
*/
#if BENCH_PNG
#include <png.h>
#endif

#include "bench.h"
#include "scenes.h"

static int reps = 5;
/* Warm-ups (0 in the smoke run: POV-Ray sleeps 0.7 s a start, whatever
** the image's size). */
static int warm = 1;
/* Why POV-Ray's rows are missing, when they are. */
static const char *skip_why = "povray is not on PATH (Debian: `apt-get "
                              "install povray`; `make bench` installs it "
                              "when run as root)";
static unsigned width = 1024, height = 768;

/* ------------------------------------------------------------ libray */

typedef struct ours {
    ray_scene *scene;
    ray_camera cam;
    float *img;
    unsigned char *srgb;
} ours;

/* Render with the given adaptive threshold and depth (threshold 0:
** "samples" per pixel) and threads; the seconds ray_render took; the image into o->img and o->srgb,
** the counters into *st. */
static double ours_render(ours *o, double threshold, unsigned depth,
                          unsigned samples, unsigned threads, ray_stats *st)
{
    ray_render_options opt;
    double t0;

    opt = (ray_render_options){.width = width, .height = height};
    opt.threads = threads;
    opt.samples = samples;
    opt.adaptive_threshold = threshold;
    opt.adaptive_depth = depth;
    t0 = now_seconds();
    check(ray_render(o->scene, &o->cam, &opt, o->img, st), "ray_render");
    t0 = now_seconds() - t0;
    check(ray_image_to_srgb8(o->img, (size_t)width * height, o->srgb),
          "ray_image_to_srgb8");
    return t0;
}

/* ----------------------------------------------------------- POV-Ray */

typedef struct pov {
    const char *scene;
    char dir[64], png[96], log[96];
    unsigned char *srgb;
    char version[64];
} pov;

typedef struct pov_stats {
    double trace, wall;          /* seconds: POV's Trace Time, start to end */
    double pixels, samples;      /* its "Pixels:" and "Samples:" */
    double rays, saved, shadow, reflected, refracted;
} pov_stats;

static int have_povray(void)
{
    return system("command -v povray >/dev/null 2>&1") == 0;
}

/* The number after "key" in text, or -1. */
static double after(const char *text, const char *key)
{
    const char *p = strstr(text, key);
    double v;

    if (p == NULL || sscanf(p + strlen(key), " %lf", &v) != 1)
        return -1;
    return v;
}

/* Read all of a small file (POV's log); NULL on failure. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    size_t n = 0, cap = 0, got;

    if (f == NULL)
        return NULL;
    do {
        if (n + 4096 + 1 > cap) {
            char *b = realloc(buf, cap = 2 * cap + 4096 + 1);
            if (b == NULL) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = b;
        }
        got = fread(buf + n, 1, 4096, f);
        n += got;
    } while (got > 0);
    fclose(f);
    buf[n] = '\0';
    return buf;
}

/* Read POV's 8-bit PNG (sRGB, +FN8 File_Gamma=sRGB) into p->srgb. */
static int read_png(pov *p)
{
#if BENCH_PNG
    png_image im;
    int ok;

    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, p->png))
        return 0;
    im.format = PNG_FORMAT_RGB;
    if (im.width != width || im.height != height) {
        png_image_free(&im);
        return 0;
    }
    ok = png_image_finish_read(&im, NULL, p->srgb, 0, NULL);
    png_image_free(&im);
    return ok != 0;
#else
    (void)p;
    return 0;            /* built with PNG=0: POV-Ray's image unreadable */
#endif
}

/* Render with POV-Ray: "aa" its antialiasing switches ("-A" for none).
** 0 (with a message) if it failed. */
static int pov_render(pov *p, const char *aa, unsigned threads, pov_stats *st)
{
    char cmd[512], *log;
    double t0;
    int rc;

    snprintf(cmd, sizeof cmd,
             "povray '+I%s' +W%u +H%u %s +WT%u -D -V '+O%s' +FN8 "
             "File_Gamma=sRGB >/dev/null 2>'%s'",
             p->scene, width, height, aa, threads, p->png, p->log);
    t0 = now_seconds();
    rc = system(cmd);
    st->wall = now_seconds() - t0;
    log = slurp(p->log);
    if (rc != 0 || log == NULL || !read_png(p)) {
        fprintf(stderr, "whitted: povray failed (%s); its log: %s\n", cmd,
                p->log);
        skip_why = "povray failed (its command is on stderr)";
        free(log);
        return 0;
    }
    /* "Trace Time:  0 hours  0 minutes  0 seconds (0.055 seconds)". */
    st->trace = -1;
    {
        const char *t = strstr(log, "Trace Time:");
        if (t != NULL && (t = strchr(t, '(')) != NULL)
            st->trace = after(t, "(");
    }
    st->pixels = after(log, "Pixels:");
    st->samples = after(log, "Samples:");
    st->rays = after(log, "Rays:");
    st->saved = after(log, "Saved:");
    st->shadow = after(log, "Shadow Ray Tests:");
    st->reflected = after(log, "Reflected Rays:");
    st->refracted = after(log, "Refracted Rays:");
    free(log);
    if (st->trace < 0 || st->pixels < 0) {
        fprintf(stderr, "whitted: no Trace Time or Pixels in %s\n", p->log);
        skip_why = "its statistics had no Trace Time or Pixels";
        return 0;
    }
    return 1;
}

static void pov_version(pov *p)
{
    FILE *f = popen("povray --version 2>&1", "r");
    char line[256];

    snprintf(p->version, sizeof p->version, "POV-Ray");
    if (f == NULL)
        return;
    while (fgets(line, sizeof line, f) != NULL)
        if (strncmp(line, "POV-Ray ", 8) == 0) {
            line[strcspn(line, "\n")] = '\0';
            snprintf(p->version, sizeof p->version, "%.60s", line);
            break;
        }
    pclose(f);
}

/* ------------------------------------------------------------ helpers */

/* RMSE of two 8-bit images of n values, in levels. */
static double rmse8(const unsigned char *a, const unsigned char *b, size_t n)
{
    double sum = 0;
    size_t i;

    for (i = 0; i < n; i++) {
        double d = (double)a[i] - (double)b[i];
        sum += d * d;
    }
    return sqrt(sum / (double)n);
}

static unsigned long long secondary(const ray_stats *st)
{
    return st->rays[RAY_KIND_REFLECTION] + st->rays[RAY_KIND_REFRACTION];
}

/* ------------------------------------------------------------ tables */

/* Every ray ray_render traced: camera, reflected, refracted (those the
** cut refused are not traced) and shadow rays. */
static double ours_rays(const ray_stats *st)
{
    return (double)(st->rays[RAY_KIND_PRIMARY] + secondary(st) +
                    st->rays[RAY_KIND_SHADOW]);
}

/* POV-Ray's rays as its statistics count them: "Rays" (camera,
** reflected and refracted) and its shadow rays ("Shadow Ray Tests"). */
static double pov_rays(const pov_stats *ps)
{
    return ps->rays + ps->shadow;
}

/* One thread count's interleaved repetitions: medians of our render
** time, POV's trace and wall times and the ratios. */
typedef struct plain_times {
    double ours, pov, wall, ratio, wratio, ours_rays, pov_rays;
    ray_stats st;
    pov_stats ps;
    int with_pov;
} plain_times;

static void plain_run(ours *o, pov *p, int with_pov, unsigned threads,
                      plain_times *pt)
{
    double t_ours[16], t_pov[16], w_pov[16], ratio[16], wratio[16];
    int r;

    memset(pt, 0, sizeof *pt);
    (void)ours_render(o, 0, 2, 1, threads, &pt->st);        /* warm-up */
    if (warm && with_pov && !pov_render(p, "-A", threads, &pt->ps))
        with_pov = 0;
    for (r = 0; r < reps; r++) {
        t_ours[r] = ours_render(o, 0, 2, 1, threads, &pt->st);
        if (with_pov) {
            if (!pov_render(p, "-A", threads, &pt->ps)) {
                with_pov = 0;
                continue;
            }
            t_pov[r] = pt->ps.trace;
            w_pov[r] = pt->ps.wall;
            ratio[r] = pt->ps.trace / t_ours[r];
            wratio[r] = pt->ps.wall / t_ours[r];
        }
    }
    pt->with_pov = with_pov;
    pt->ours = median(t_ours, reps);
    pt->ours_rays = ours_rays(&pt->st);
    if (with_pov) {
        pt->pov = median(t_pov, reps);
        pt->wall = median(w_pov, reps);
        pt->ratio = median(ratio, reps);
        pt->wratio = median(wratio, reps);
        pt->pov_rays = pov_rays(&pt->ps);
    }
}

static void plain_render(ours *o, pov *p, int with_pov)
{
    static const unsigned threads[] = {1, 2};
    plain_times pt[2];
    double px = (double)width * height;
    size_t k;

    for (k = 0; k < 2; k++)
        plain_run(o, p, with_pov, threads[k], &pt[k]);
    with_pov = pt[0].with_pov && pt[1].with_pov;
    printf("### One sample per pixel\n\n");
    printf("%u x %u, no antialiasing, one and two threads each; times are "
           "medians of %d interleaved repetitions. Rays: camera, reflected, "
           "refracted and shadow rays traced (libray: ray_stats; POV-Ray: "
           "its \"Rays\" and \"Shadow Ray Tests\"); Mrays/s is rays over "
           "the render time.\n\n", width, height, reps);
    printf("| renderer | threads | render (s) | wall (s) | rays | Mrays/s | "
           "ns / ray (x threads) | camera rays / pixel | reflected + "
           "refracted rays | of which cut | shadow rays |\n");
    printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (k = 0; k < 2; k++) {
        const ray_stats *st = &pt[k].st;
        printf("| libray (ray_render) | %u | %.3f | | %.0f | %.2f | %.0f | "
               "%.2f | %llu | %llu | %llu |\n", threads[k], pt[k].ours,
               pt[k].ours_rays, pt[k].ours_rays / pt[k].ours / 1e6,
               pt[k].ours * 1e9 * threads[k] / pt[k].ours_rays,
               (double)st->rays[RAY_KIND_PRIMARY] / px,
               secondary(st) + st->cut_depth + st->cut_weight,
               st->cut_depth + st->cut_weight, st->rays[RAY_KIND_SHADOW]);
        if (with_pov) {
            const pov_stats *ps = &pt[k].ps;
            printf("| %s (Trace Time) | %u | %.3f | %.3f | %.0f | %.2f | "
                   "%.0f | %.2f | %.0f | %.0f | %.0f |\n", p->version,
                   threads[k], pt[k].pov, pt[k].wall, pt[k].pov_rays,
                   pt[k].pov_rays / pt[k].pov / 1e6,
                   pt[k].pov * 1e9 * threads[k] / pt[k].pov_rays,
                   (ps->pixels + ps->samples) / px,
                   ps->reflected + ps->refracted, ps->saved, ps->shadow);
        }
    }
    if (!with_pov) {
        printf("\nPOV-Ray skipped: %s.\n\n", skip_why);
        return;
    }
    printf("\nReflected and refracted rays count those the depth or weight "
           "cut refused (libray: ray_stats cut_depth + cut_weight; POV-Ray "
           "counts a ray before its adc_bailout test, \"Saved\").\n");
    for (k = 0; k < 2; k++)
        printf("\n%u thread%s: POV-Ray / libray, median of the repetitions' "
               "ratios: **%.2fx** (trace time), %.2fx (POV's wall time, "
               "start-up and PNG included); rays per second %.2fx "
               "POV-Ray's.\n", threads[k], threads[k] > 1 ? "s" : "",
               pt[k].ratio, pt[k].wratio,
               (pt[k].ours_rays / pt[k].ours) /
                   (pt[k].pov_rays / pt[k].pov));
    printf("\nThe images differ by an RMSE of %.2f 8-bit levels (the scene "
           "files agree up to what bench/whitted.pov lists).\n\n",
           rmse8(o->srgb, p->srgb, 3 * (size_t)px));
}

typedef struct aa_row {
    const char *name;
    double threshold;            /* libray's adaptive threshold ... */
    unsigned depth;              /* ... and depth */
    const char *pov;             /* POV-Ray's switches */
} aa_row;

static void antialiasing(ours *o, pov *p, int with_pov, unsigned ref_spp,
                         const char *pov_ref)
{
    static const aa_row ours_rows[] = {
        {"none (1 spp)", 0, 2, NULL}, {"adaptive 0.3", 0.3, 2, NULL},
        {"adaptive 0.1", 0.1, 2, NULL}, {"adaptive 0.05", 0.05, 2, NULL},
        {"adaptive 0.02", 0.02, 2, NULL},
        {"adaptive 0.1, depth 3", 0.1, 3, NULL}};
    static const aa_row pov_rows[] = {
        {"none (-A)", 0, 0, "-A"}, {"+A0.3", 0, 0, "+A0.3 +AM1"},
        {"+A0.1", 0, 0, "+A0.1 +AM1"}, {"+A0.05", 0, 0, "+A0.05 +AM1"}};
    enum { NO = sizeof ours_rows / sizeof ours_rows[0],
           NP = sizeof pov_rows / sizeof pov_rows[0] };
    size_t n = 3 * (size_t)width * height, k;
    double px = (double)width * height;
    unsigned char *ref_ours = malloc(n), *ref_pov = malloc(n);
    double t_o[NO][16], t_p[NP][16], e_o[NO], e_p[NP], c_o[NO], c_p[NP];
    pov_stats ps;
    ray_stats st;
    int r;

    if (ref_ours == NULL || ref_pov == NULL) {
        fprintf(stderr, "whitted: out of memory\n");
        exit(1);
    }
    (void)ours_render(o, 0, 2, ref_spp, 2, &st);
    memcpy(ref_ours, o->srgb, n);
    if (with_pov && pov_render(p, pov_ref, 2, &ps))
        memcpy(ref_pov, p->srgb, n);
    else
        with_pov = 0;
    for (r = warm ? -1 : 0; r < reps; r++) { /* r = -1: the warm-up */
        for (k = 0; k < NO || (with_pov && k < NP); k++) {
            if (k < NO) {
                double t = ours_render(o, ours_rows[k].threshold,
                                       ours_rows[k].depth, 1, 1, &st);
                if (r >= 0)
                    t_o[k][r] = t;
                e_o[k] = rmse8(o->srgb, ref_ours, n);
                c_o[k] = (double)st.rays[RAY_KIND_PRIMARY] / px;
            }
            if (with_pov && k < NP) {
                if (!pov_render(p, pov_rows[k].pov, 1, &ps)) {
                    with_pov = 0;
                    continue;
                }
                if (r >= 0)
                    t_p[k][r] = ps.trace;
                e_p[k] = rmse8(p->srgb, ref_pov, n);
                c_p[k] = (ps.pixels + ps.samples) / px;
            }
        }
    }
    printf("### Antialiasing at equal image error\n\n");
    printf("%u x %u, one thread. Error: RMSE in 8-bit sRGB levels against "
           "the same renderer's own reference (libray: uniform %u samples "
           "per pixel; POV-Ray: `%s`). libray's adaptive mode has depth 2 "
           "unless the row says otherwise; POV-Ray's +A is method 1 with its defaults (+R3, jitter 1). "
           "Times: medians of %d interleaved repetitions.\n\n",
           width, height, ref_spp, pov_ref, reps);
    printf("| renderer | antialiasing | render (s) | camera rays / pixel | "
           "RMSE (8-bit levels) |\n");
    printf("|---|---|---:|---:|---:|\n");
    for (k = 0; k < NO; k++)
        printf("| libray | %s | %.3f | %.2f | %.2f |\n", ours_rows[k].name,
               median(t_o[k], reps), c_o[k], e_o[k]);
    if (with_pov)
        for (k = 0; k < NP; k++)
            printf("| POV-Ray | %s | %.3f | %.2f | %.2f |\n",
                   pov_rows[k].name, median(t_p[k], reps), c_p[k], e_p[k]);
    else
        printf("\nPOV-Ray skipped: %s.\n", skip_why);
    printf("\n");
    free(ref_ours);
    free(ref_pov);
}

int main(int argc, char **argv)
{
    ours o;
    pov p;
    int with_pov;
    unsigned ref_spp = 256;
    const char *pov_ref = "+A0.0 +AM1 +R9";
    size_t n;

    if (bench_level() == BENCH_SMOKE) {
        width = 16, height = 12, reps = 1, warm = 0;
        ref_spp = 4;
        pov_ref = "+A0.0 +AM1 +R2";
    } else if (bench_level() == BENCH_QUICK_RUN) {
        width = 320, height = 240, reps = 3;
        ref_spp = 64;
        pov_ref = "+A0.0 +AM1 +R8";
    }
    memset(&p, 0, sizeof p);
    p.scene = argc > 1 ? argv[1] : "bench/whitted.pov";
    n = 3 * (size_t)width * height;
    o.scene = whitted_scene(&o.cam, 1, NULL);
    o.img = malloc(n * sizeof *o.img);
    o.srgb = malloc(n);
    p.srgb = malloc(n);
    if (o.img == NULL || o.srgb == NULL || p.srgb == NULL) {
        fprintf(stderr, "whitted: out of memory\n");
        return 1;
    }
    with_pov = have_povray();
    if (!BENCH_PNG && with_pov) {
        skip_why = "this bench was built with PNG=0, so it cannot read "
                   "POV-Ray's image";
        with_pov = 0;
    }
    if (with_pov) {
        snprintf(p.dir, sizeof p.dir, "/tmp/libray-whitted-XXXXXX");
        if (mkdtemp(p.dir) == NULL) {
            skip_why = "no scratch directory for its image";
            with_pov = 0;
            p.dir[0] = '\0';
        }
        snprintf(p.png, sizeof p.png, "%s/pov.png", p.dir);
        snprintf(p.log, sizeof p.log, "%s/pov.log", p.dir);
        if (with_pov && access(p.scene, R_OK) != 0) {
            skip_why = "its scene file is not readable (run from the "
                       "repository root, or pass bench/whitted.pov's path)";
            with_pov = 0;
        }
        pov_version(&p);
    }
    printf("## Whitted scene against POV-Ray\n\n");
    plain_render(&o, &p, with_pov);
    antialiasing(&o, &p, with_pov, ref_spp, pov_ref);
    if (p.dir[0] != '\0') {
        remove(p.png);
        remove(p.log);
        rmdir(p.dir);
    }
    ray_scene_free(o.scene);
    free(o.img);
    free(o.srgb);
    free(p.srgb);
    return 0;
}
