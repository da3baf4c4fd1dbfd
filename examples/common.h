/* SPDX-License-Identifier: MIT */
/*
** common.h -- small helpers shared by the examples: vectors, colours, a
** progress bar, the statistics printout and the command line (parsing,
** usage, output checks).  Not part of the library.
*/
#ifndef EXAMPLES_COMMON_H
#define EXAMPLES_COMMON_H

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <ray.h>

#include "parse.h"

/* Short names for ray.h's constructors, as the examples (and the tests,
** which include this header) write them. */
static inline ray_vec3 vec(double x, double y, double z)
{
    return ray_vec3_make(x, y, z);
}

static inline ray_rgb rgb(double r, double g, double b)
{
    return ray_rgb_make(r, g, b);
}

/* A progress bar on stderr, redrawn with '\r' when the percentage
** changes: for a terminal.  Never cancels; the renderer calls it one call
** at a time. */
static inline int progress_bar(void *ud, unsigned done, unsigned total)
{
    unsigned width = 40, filled = done * width / total, i;
    unsigned percent = (unsigned)((unsigned long long)done * 100 / total);

    (void)ud;
    if (done != total && percent ==
                         (unsigned)((unsigned long long)(done - 1) * 100 / total))
        return 0;
    fputs("\r[", stderr);
    for (i = 0; i < width; i++)
        fputc(i < filled ? '#' : ' ', stderr);
    fprintf(stderr, "] %3u%%", percent);
    if (done == total)
        fputc('\n', stderr);
    return 0;
}

/* What the progress callbacks are told of the render: the program's
** name, and whether the photon pass reports first (its counts are
** photons, until its last report, done == total; then the rows'). */
typedef struct example_progress {
    const char *name;
    int photons;
    unsigned quarter;        /* the last quarter printed (0: none) */
} example_progress;

/* The progress into a pipe or a log, where '\r' would pile up a line of
** bars: one plain line per quarter, "NAME: 25% (12 of 48 rows)" (or
** "photons" while the photon pass reports).  ud: an example_progress. */
static inline int progress_lines(void *ud, unsigned done, unsigned total)
{
    example_progress *p = ud;
    unsigned quarter = (unsigned)((unsigned long long)done * 4 / total);

    /* The photons come 4096 at a time: a report may pass a quarter. */
    if (quarter <= p->quarter)
        return 0;
    fprintf(stderr, "%s: %u%% (%u of %u %s)\n", p->name, 25 * quarter, done,
            total, p->photons ? "photons" : "rows");
    p->quarter = quarter;
    if (done == total)       /* the pass is over: the rows come next */
        p->photons = 0, p->quarter = 0;
    return 0;
}

/* The names of the RAY_EFFECT_* bits in "effects", blank-separated, into
** buf; "none" when there are none. */
static inline const char *effect_names(unsigned effects, char *buf,
                                       size_t size)
{
    static const struct {
        unsigned bit;
        const char *name;
    } names[] = {{RAY_EFFECT_SHADOW, "shadow"},
                 {RAY_EFFECT_REFLECTION, "reflection"},
                 {RAY_EFFECT_REFRACTION, "refraction"},
                 {RAY_EFFECT_TEXTURE, "texture"},
                 {RAY_EFFECT_CAUSTICS, "caustics"}};
    size_t k, used = 0;

    snprintf(buf, size, "none");
    for (k = 0; k < sizeof names / sizeof names[0]; k++) {
        int n;
        if ((effects & names[k].bit) == 0)
            continue;
        n = snprintf(buf + used, size - used, "%s%s", used ? " " : "",
                     names[k].name);
        if (n < 0 || (size_t)n >= size - used)
            break;
        used += (size_t)n;
    }
    return buf;
}

/* The render's counters, and which effects the committed scene needs
** (ray_scene_effects: what the analysis left the tracer to do). */
static inline void print_stats(const char *name, const ray_scene *scene,
                               const ray_stats *s, double seconds)
{
    char effects[64];
    unsigned long long total = s->rays[RAY_KIND_PRIMARY] +
                               s->rays[RAY_KIND_SHADOW] +
                               s->rays[RAY_KIND_REFLECTION] +
                               s->rays[RAY_KIND_REFRACTION];
    unsigned long long sum = 0;
    int k, lo = -1, hi = -1;

    printf("%s: rays primary %llu, shadow %llu, reflection %llu, "
           "refraction %llu (total %llu)\n", name,
           s->rays[RAY_KIND_PRIMARY], s->rays[RAY_KIND_SHADOW],
           s->rays[RAY_KIND_REFLECTION], s->rays[RAY_KIND_REFRACTION], total);
    printf("%s: effects the scene needs: %s\n", name,
           effect_names(ray_scene_effects(scene), effects, sizeof effects));
    printf("%s: intersection tests %llu (spheres %llu, planes %llu, "
           "triangles %llu, polygons %llu, tori %llu, implicit %llu, "
           "parametric %llu)\n", name, s->tests,
           s->tests_by_kind[RAY_PRIM_SPHERE], s->tests_by_kind[RAY_PRIM_PLANE],
           s->tests_by_kind[RAY_PRIM_TRIANGLE],
           s->tests_by_kind[RAY_PRIM_POLYGON], s->tests_by_kind[RAY_PRIM_TORUS],
           s->tests_by_kind[RAY_PRIM_IMPLICIT],
           s->tests_by_kind[RAY_PRIM_PARAMETRIC]);
    if (s->root_failures > 0)
        printf("%s: %llu implicit or parametric tests ran out of iterations "
               "(taken as misses)\n", name, s->root_failures);
    /* A material that shades with ray_shade_direct or ray_light_visible
    ** but forgot RAY_EFFECT_SHADOW renders without shadows: say so. */
    if (s->shadows_undeclared > 0)
        printf("%s: %llu shadow rays not cast: a material asked for them "
               "without declaring RAY_EFFECT_SHADOW (its light is "
               "unshadowed)\n", name, s->shadows_undeclared);
    /* And one that calls ray_trace for a reflection or refraction it did
    ** not declare gets RAY_EEFFECT, and the image lacks it: say so. */
    if (s->traces_undeclared > 0)
        printf("%s: %llu reflection or refraction rays refused: a material "
               "asked for them without declaring RAY_EFFECT_REFLECTION or "
               "RAY_EFFECT_REFRACTION\n", name, s->traces_undeclared);
    printf("%s: deepest level %u, rays cut by depth %llu, weight %llu, "
           "fan-out %llu\n", name, s->max_depth, s->cut_depth, s->cut_weight,
           s->cut_fanout);
    for (k = 0; k < RAY_HIST_BINS; k++) {
        if (s->samples_hist[k] == 0)
            continue;
        if (lo < 0)
            lo = k;
        hi = k;
        sum += s->samples_hist[k] * (unsigned long long)k;
    }
    if (s->pixels > 0)
        printf("%s: samples per pixel: min %d, mean %.2f, max %d%s\n", name,
               lo, (double)sum / (double)s->pixels, hi,
               hi == RAY_HIST_BINS - 1 ? " or more" : "");
    if (s->photons_emitted > 0)
        printf("%s: photons emitted %llu, stored %llu, lookups %llu\n", name,
               s->photons_emitted, s->photons_stored, s->photon_lookups);
    if (seconds > 0)
        printf("%s: %.3f s, %.2f Mrays/s\n", name, seconds,
               (double)total / seconds / 1e6);
}

/* A Blinn-Phong parameter block; the fields not named (the texture) are
** zero.  Built field by field, so fields added to the struct later stay
** zero. */
static inline ray_phong_params phong_params(ray_rgb diffuse, ray_rgb specular,
                                            double shininess, ray_rgb reflect)
{
    ray_phong_params p;

    memset(&p, 0, sizeof p);
    p.diffuse = diffuse;
    p.specular = specular;
    p.shininess = shininess;
    p.blinn = 1;
    p.reflect = reflect;
    return p;
}

/* A sky for ray_scene_set_background's function: base + delta * k, k going from 0
** for rays straight down to 1 straight up; ud is a sky_colors. */
typedef struct sky_colors {
    ray_rgb base, delta;
} sky_colors;

static inline void sky_gradient(void *ud, const ray_ray *r, ray_rgb *out)
{
    const sky_colors *c = ud;
    double len = r->dir.x * r->dir.x + r->dir.y * r->dir.y +
                 r->dir.z * r->dir.z;
    double up = len > 0 ? r->dir.y / sqrt(len) : 0;
    double k = 0.5 * (up + 1);

    *out = rgb(c->base.r + c->delta.r * k, c->base.g + c->delta.g * k,
               c->base.b + c->delta.b * k);
}

/* Die with a message naming the failed call. */
static inline void check(int rc, const char *what)
{
    if (rc != RAY_OK) {
        fprintf(stderr, "%s: %s\n", what, ray_strerror(rc));
        exit(1);
    }
}

static inline double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/*
** The examples' command line, one pattern parsed here for all of them:
**
**     NAME [INPUT] [out.png [width height [samples [threads]]]]
**
** (INPUT for those that read a file; the sizes for those that render a
** scene).  -h or --help prints the usage on stdout and exits 0, as asked
** for help is no failure (issue 37); a bad argument prints what is wrong
** and the usage on stderr and exits with status 2, as issue 18 asks, so
** that no script takes a usage message for a picture.
** Status 1 is a failure while running (a file that cannot be read or
** written, memory); 0, a picture written.  Numbers are whole decimal
** numbers with nothing after them ("12abc" is refused), within limits
** named in the message.  The output file is checked before the (long)
** render, without creating it: a missing directory or a path that is a
** directory fails at once, naming the file and errno's reason.
*/

/* Beyond these an argument is a typo, not a wish: 65536 pixels is 16
** times a 4K picture's width (and within libpng's 2^31-byte rows);
** samples are ray_render's own bound; threads beyond a machine's CPUs
** only cost memory, and 1024 is more than any machine this runs on. */
#define EXAMPLE_MAX_SIDE 65536u
#define EXAMPLE_MAX_THREADS 1024u

/* One example's command line: what its usage says, and its defaults. */
typedef struct example_cli {
    const char *name;           /* the program, for usage and messages */
    const char *what;           /* what it renders, one line */
    const char *input;          /* a file read first ("model.obj"), or NULL */
    const char *input_what;     /* what that file is, for the usage */
    const char *input_default;  /* NULL: the input must be given */
    const char *output_default; /* "NAME.png" */
    int sized;                  /* takes width height samples threads */
    unsigned width, height;     /* the size, fixed or default */
    unsigned samples;           /* default samples per pixel (if sized) */
} example_cli;

/*
** The axis-aligned box lo .. hi as a closed mesh of 12 triangles, wound
** outward, added to "scene" (vertex i takes x, y, z from hi where its bits
** 0, 1, 2 are set, else from lo; the vertices are copied).
*/
static inline int example_add_box_mesh(ray_scene *scene, ray_vec3 lo,
                                       ray_vec3 hi, unsigned material,
                                       unsigned *id)
{
    static const unsigned indices[36] = {
        0, 4, 6, 0, 6, 2,   1, 3, 7, 1, 7, 5,     /* x- and x+ faces */
        0, 1, 5, 0, 5, 4,   2, 6, 7, 2, 7, 3,     /* y- and y+ */
        0, 2, 3, 0, 3, 1,   4, 5, 7, 4, 7, 6};    /* z- and z+ */
    ray_vec3 v[8];
    ray_mesh m;
    unsigned i;

    for (i = 0; i < 8; i++)
        v[i] = vec(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y,
                   i & 4 ? hi.z : lo.z);
    memset(&m, 0, sizeof m);    /* zero is every field's default */
    m.vertices = v;
    m.vertex_count = 8;
    m.indices = indices;
    m.triangle_count = 12;
    return ray_scene_add_mesh(scene, &m, material, id);
}

/*
** The command line of an example that takes no arguments (it writes no
** file): 0 when there are none; -h or --help prints "usage: NAME (no
** arguments)" and "what" on stdout and exits 0; anything else is refused
** on stderr with the usage, returning 2, the status to exit with.
*/
static inline int example_no_arguments(int argc, char **argv,
                                       const char *name, const char *what)
{
    int help;

    if (argc <= 1)
        return 0;
    help = strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0;
    if (!help)
        fprintf(stderr, "%s: %s '%s'\n", name,
                argv[1][0] == '-' ? "unknown option" : "unexpected argument",
                argv[1]);
    fprintf(help ? stdout : stderr, "usage: %s (no arguments)\n%s\n", name,
            what);
    if (help)
        exit(0);                 /* help asked for and given: no failure */
    return 2;
}

/* What a command line asked for. */
typedef struct example_args {
    const char *name;           /* the program's name */
    const char *input;          /* the input file (cli->input), or NULL */
    const char *output;         /* the PNG to write */
    unsigned width, height, samples, threads;   /* threads 0: all CPUs */
    double adaptive_threshold;  /* RAY_ADAPTIVE's threshold, 0: off */
    unsigned adaptive_depth;    /* RAY_ADAPTIVE's depth, 0: the default */
    unsigned long long photons; /* caustics' photons, 0: none (set by the
                                   example after example_start) */
} example_args;

static inline void example_usage(const example_cli *c, FILE *f)
{
    const char *out = c->sized ? "[out.png [width height [samples [threads]]]]"
                               : "[out.png]";

    if (c->input == NULL)
        fprintf(f, "usage: %s %s\n", c->name, out);
    else if (c->input_default == NULL)
        fprintf(f, "usage: %s %s %s\n", c->name, c->input, out);
    else
        fprintf(f, "usage: %s [%s %s]\n", c->name, c->input, out);
    fprintf(f, "%s\n", c->what);
    if (c->input != NULL)
        fprintf(f, "  %-13s %s (%s%s)\n", c->input, c->input_what,
                c->input_default ? "default " : "required",
                c->input_default ? c->input_default : "");
    fprintf(f, "  %-13s the PNG to write (default %s)\n", "out.png",
            c->output_default);
    if (c->sized) {
        fprintf(f, "  %-13s the size in pixels, 1 to %u each (default %u "
                   "%u)\n", "width height", EXAMPLE_MAX_SIDE, c->width,
                c->height);
        fprintf(f, "  %-13s per pixel, 1 to %u (default %u)\n", "samples",
                RAY_MAX_PIXEL_SAMPLES, c->samples);
        fprintf(f, "  %-13s render threads, 0 to %u; 0: one per CPU "
                   "(default 0)\n", "threads", EXAMPLE_MAX_THREADS);
        fprintf(f, "Environment: RAY_ADAPTIVE=threshold[,depth] turns "
                   "adaptive antialiasing on\n(threshold >= 0, depth 1 to "
                   "8).\n");
    } else {
        fprintf(f, "The picture is %u x %u pixels.\n", c->width, c->height);
    }
    fprintf(f, "Exit status: 0 written, or -h/--help; 1 a file or memory "
               "failed; 2 a bad argument.\n");
}

static inline int example_bad(const example_cli *c, const char *fmt, ...)
    PARSE_PRINTF_LIKE(2, 3);

/* A bad command line: the message, the usage, status 2. */
static inline int example_bad(const example_cli *c, const char *fmt, ...)
{
    va_list ap;

    fprintf(stderr, "%s: ", c->name);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    example_usage(c, stderr);
    return 2;
}

/* A file name argument: not empty, and not an option ("-x"; a file whose
** name starts with '-' is given as ./-x). */
static inline int example_path(const example_cli *c, const char *what,
                               const char *s)
{
    if (s[0] == '-')
        return example_bad(c, "unknown option '%s'", s);
    if (s[0] == '\0')
        return example_bad(c, "%s: an empty file name", what);
    return 0;
}

/* A whole decimal number from lo to hi, digits only: strtoul alone would
** take leading blanks, a sign (and wrap "-5" round), and stop at "12abc". */
static inline int example_number(const example_cli *c, const char *what,
                                 const char *s, unsigned lo, unsigned hi,
                                 unsigned *out)
{
    unsigned long v = 0;
    char *end = NULL;

    if (isdigit((unsigned char)s[0])) {
        errno = 0;
        v = strtoul(s, &end, 10);
    }
    if (end == NULL || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return example_bad(c, "%s must be a whole number from %u to %u, "
                              "not '%s'", what, lo, hi, s);
    *out = (unsigned)v;
    return 0;
}

/* RAY_ADAPTIVE=threshold[,depth]: unset or empty, off. */
static inline int example_adaptive(const example_cli *c, example_args *a)
{
    const char *s = getenv("RAY_ADAPTIVE");
    char *end = NULL;
    double t = 0;

    if (s == NULL || s[0] == '\0')
        return 0;
    if (isdigit((unsigned char)s[0]) || s[0] == '.' || s[0] == 'i' ||
        s[0] == 'I')
        t = strtod(s, &end);
    if (end != NULL && *end == ',' && isdigit((unsigned char)end[1])) {
        unsigned long d = strtoul(end + 1, &end, 10);
        a->adaptive_depth = d >= 1 && d <= 8 ? (unsigned)d : 0;
        if (a->adaptive_depth == 0)
            end = NULL;
    }
    if (end == NULL || *end != '\0' || isnan(t) || t < 0)
        return example_bad(c, "RAY_ADAPTIVE must be threshold[,depth], a "
                              "threshold >= 0 and a depth from 1 to 8, not "
                              "'%s'", s);
    a->adaptive_threshold = t;
    return 0;
}

/* Fill *a from argv; 0, or the exit status (2) after the usage; -h and
** --help print the usage and exit 0 here. */
static inline int example_parse(const example_cli *c, int argc, char **argv,
                                example_args *a)
{
    int i, pos = 1, rc = 0;

    for (i = 1; i < argc; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            example_usage(c, stdout);
            exit(0);             /* help asked for and given: no failure */
        }
    memset(a, 0, sizeof *a);
    a->name = c->name;
    a->input = c->input_default;
    a->output = c->output_default;
    a->width = c->width;
    a->height = c->height;
    a->samples = c->samples;
    if (c->input != NULL) {
        if (pos < argc)
            a->input = argv[pos++];
        else if (c->input_default == NULL)
            return example_bad(c, "%s is required", c->input);
        if ((rc = example_path(c, c->input, a->input)) != 0)
            return rc;
    }
    if (pos < argc && (rc = example_path(c, "out.png", argv[pos])) != 0)
        return rc;
    if (pos < argc)
        a->output = argv[pos++];
    if (c->sized && pos < argc) {
        if (pos + 1 == argc)
            return example_bad(c, "width '%s' without a height", argv[pos]);
        if ((rc = example_number(c, "width", argv[pos++], 1,
                                 EXAMPLE_MAX_SIDE, &a->width)) != 0 ||
            (rc = example_number(c, "height", argv[pos++], 1,
                                 EXAMPLE_MAX_SIDE, &a->height)) != 0)
            return rc;
    }
    if (c->sized && pos < argc &&
        (rc = example_number(c, "samples", argv[pos++], 1,
                             RAY_MAX_PIXEL_SAMPLES, &a->samples)) != 0)
        return rc;
    if (c->sized && pos < argc &&
        (rc = example_number(c, "threads", argv[pos++], 0,
                             EXAMPLE_MAX_THREADS, &a->threads)) != 0)
        return rc;
    if (pos < argc)
        return example_bad(c, "unexpected argument '%s'", argv[pos]);
    return c->sized ? example_adaptive(c, a) : 0;
}

/* "name: cannot write path: why" -- errno's reason for RAY_EIO (and for
** rc 0: a check before writing), the library's otherwise.  Returns 1. */
static inline int example_write_error(const char *name, const char *path,
                                      int rc)
{
    fprintf(stderr, "%s: cannot write %s: %s\n", name, path,
            rc == RAY_OK || rc == RAY_EIO ? strerror(errno)
                                          : ray_strerror(rc));
    return 1;
}

/*
** Whether ray_write_png can write "path", asked before the render and
** without creating or truncating anything: it writes a temporary file
** beside the target and renames it (ray_write_png(3)), so the directory
** must take new files; a device or FIFO is written in place; a directory
** never.  0, or 1 after the message.  Only a first check: the write
** reports its own errors after the render.
*/
static inline int example_output_check(const char *name, const char *path)
{
    const char *slash = strrchr(path, '/');
    struct stat st;
    char *dir;
    int ok;

    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            errno = EISDIR;
            return example_write_error(name, path, RAY_OK);
        }
        if (!S_ISREG(st.st_mode))
            return access(path, W_OK) == 0
                       ? 0 : example_write_error(name, path, RAY_OK);
    } else if (errno != ENOENT) {
        return example_write_error(name, path, RAY_OK);
    }
    if (slash == NULL)
        return access(".", W_OK | X_OK) == 0
                   ? 0 : example_write_error(name, path, RAY_OK);
    dir = malloc((size_t)(slash - path) + 2);
    if (dir == NULL) {
        errno = ENOMEM;
        return example_write_error(name, path, RAY_OK);
    }
    /* "/x.png" lives in "/", "a/x.png" in "a". */
    memcpy(dir, path, (size_t)(slash - path) + 1);
    dir[slash == path ? 1 : slash - path] = '\0';
    ok = access(dir, W_OK | X_OK) == 0;
    free(dir);
    return ok ? 0 : example_write_error(name, path, RAY_OK);
}

/* An example's start: its command line, then its output checked; 0 to go
** on, or the exit status. */
static inline int example_start(const example_cli *c, int argc, char **argv,
                                example_args *a)
{
    int rc = example_parse(c, argc, argv, a);

    return rc != 0 ? rc : example_output_check(c->name, a->output);
}

/* Write the picture; 0, or 1 after a message naming the file. */
static inline int example_write_png(const example_args *a, const float *rgb)
{
    int rc = ray_write_png(a->output, rgb, a->width, a->height, 8);

    return rc == RAY_OK ? 0 : example_write_error(a->name, a->output, rc);
}

/*
** Render "scene" as *a asks, with the progress on stderr (a bar on a
** terminal, plain lines elsewhere), write the PNG, print the statistics.
** Returns the process exit status.
*/
static inline int render_to_png(example_args *a, const ray_scene *scene,
                                const ray_camera *cam)
{
    ray_render_options opt;
    ray_stats stats;
    example_progress progress;
    float *image = NULL;
    double t;
    int rc;

    opt = (ray_render_options){.width = a->width, .height = a->height};
    opt.samples = a->samples;
    opt.threads = a->threads;
    opt.progress = isatty(fileno(stderr)) ? progress_bar : progress_lines;
    /* The pass reports only where it traces photons (ray_render(3)). */
    progress.name = a->name;
    progress.quarter = 0;
    progress.photons = a->photons > 0 &&
                       (ray_scene_effects(scene) & RAY_EFFECT_CAUSTICS);
    opt.progress_ud = &progress;
    if (a->adaptive_threshold > 0)
        opt.adaptive_threshold = a->adaptive_threshold;
    if (a->adaptive_depth > 0)
        opt.adaptive_depth = a->adaptive_depth;
    opt.photons = a->photons;
    if ((size_t)a->height <= SIZE_MAX / (3 * sizeof(float)) / a->width)
        image = malloc(3 * sizeof(float) * a->width * a->height);
    if (image == NULL) {
        fprintf(stderr, "%s: out of memory for a %u x %u picture (%.0f MB)\n",
                a->name, a->width, a->height,
                12.0 * a->width * a->height / 1e6);
        return 1;
    }
    {
        /* A valid scene can still render black (no light and a black
        ** ambient, the camera inside a solid): ray_render_check's
        ** warnings say so before the render, which goes ahead. */
        unsigned warnings = 0;
        char why[512];
        if (ray_render_check(scene, cam, &opt, &warnings, why,
                             sizeof why) == RAY_OK && warnings != 0)
            fprintf(stderr, "%s: %s\n", a->name, why);
    }
    t = now_seconds();
    rc = ray_render(scene, cam, &opt, image, &stats);
    if (rc != RAY_OK) {
        /* Which argument and why: ray_render_check, not the scene's
        ** message (ray_render's scene is const and shared). */
        char why[256];
        if (ray_render_check(scene, cam, &opt, NULL, why, sizeof why) ==
            RAY_OK)
            snprintf(why, sizeof why, "ray_render: %s", ray_strerror(rc));
        fprintf(stderr, "%s: %s\n", a->name, why);
        free(image);
        return 1;
    }
    t = now_seconds() - t;
    rc = example_write_png(a, image);
    free(image);
    if (rc != 0)
        return rc;
    printf("%s: wrote %s (%ux%u, %u samples per pixel)\n", a->name,
           a->output, a->width, a->height, opt.samples);
    print_stats(a->name, scene, &stats, t);
    return 0;
}

#endif
