/* SPDX-License-Identifier: MIT */
/*
** mpi_render.c -- one frame rendered by several processes, on one machine
** or many, with MPI (issue 20).  Built only where mpicc exists (make
** mpi-demo, make check); run under mpirun or srun:
**
**     mpirun -np 3 mpi_render [scene [out.png [width height [samples
**                             [threads]]]]]
**
** scene: whitted, cornell, teapot (data/teapot.bpt, scripts/fetch-
** teapot.sh) or another Newell .bpt file (the teapot example's scene), or
** a Wavefront .obj file (the mesh example's; the bunny:
** scripts/fetch-bunny.sh).  Defaults: whitted,
** mpi_render.png, 640 x 480, 4 samples, all CPUs of each rank.
**
** Rank 0 hands out bands of rows on demand: each rank (rank 0 too,
** between its answers) renders one band at a time with all its threads
** through ray_render's region (y0, y1), sends the rows back, and gets the
** next band, so a fast machine simply takes more bands and all finish
** together.  A worker holds two bands, the one it renders and the next,
** so it does not wait for rank 0's answer, which comes after the band
** rank 0 may be rendering.  The band is RAY_MPI_BAND rows (default: the height / (16 x
** ranks), at least 1): small enough that the last band costs little idle
** time, large enough that a band's message is not mostly latency.  Every
** pixel is seeded by its position (ray_render(3)), so the picture is
** byte-identical to the one-process examples' at any rank count and band
** size, provided every node runs the same libray, scene and options.
**
** A rank whose scene cannot be set up, or whose render fails, sends rank
** 0 the reason; rank 0 stops handing out bands, tells every rank to stop,
** prints "mpi_render: rank N: why", writes no PNG and exits 1.  MPI errors
** are returned (MPI_ERRORS_RETURN), not fatal, and reported the same way.
**
** Test hook: RAY_MPI_FAIL_RANK=N makes rank N fail its scene setup, as a
** missing scene file on one node would (scripts/check-mpi.sh uses it).
** --help prints the usage and exits 0, bad arguments print it and exit 2
** (common.h), before
** MPI is started.
*/
#include <limits.h>
#include <mpi.h>

#include "scenes.h"
#include "teapot_scene.h"

enum {
    TAG_READY = 1,  /* worker -> 0: set up, give me a band */
    TAG_RESULT,     /* worker -> 0: the band's rows; give me another */
    TAG_FAIL,       /* worker -> 0: the reason, a string; stopping */
    TAG_WORK        /* 0 -> worker: unsigned {y0, y1}; y1 = 0: stop */
};

#define REASON_MAX 256

/* A name ending in "suffix". */
static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);

    return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* The scene by name: whitted, cornell, teapot (data/teapot.bpt), a
** Newell .bpt file or an OBJ file; NULL with the reason in "why". */
static ray_scene *setup_scene(const char *name, int rank, ray_camera *cam,
                              char *why, size_t size)
{
    const char *hook = getenv("RAY_MPI_FAIL_RANK");
    ray_scene *scene;
    size_t triangles;
    FILE *f;

    if (hook != NULL && hook[0] != '\0' && atoi(hook) == rank) {
        snprintf(why, size, "scene setup failed (RAY_MPI_FAIL_RANK=%s, the "
                            "test hook)", hook);
        return NULL;
    }
    if (strcmp(name, "whitted") == 0)
        return whitted_scene(cam, 1, NULL);
    if (strcmp(name, "cornell") == 0)
        return cornell_scene(cam, 1, NULL);
    if (strcmp(name, "teapot") == 0)
        name = "data/teapot.bpt";
    /* An OBJ: opened here first, so the reason is errno's text. */
    f = fopen(name, "rb");
    if (f == NULL) {
        snprintf(why, size, "cannot read scene %s: %s", name, strerror(errno));
        return NULL;
    }
    fclose(f);
    if (ends_with(name, ".bpt")) {
        bpt_patches model;
        char err[600];

        if (bpt_load(name, &model, err, sizeof err) != 0) {
            snprintf(why, size, "%.200s", err);
            return NULL;
        }
        scene = teapot_scene(&model, cam);
        bpt_free(&model);               /* the scene copied the patches */
        return scene;
    }
    scene = mesh_scene(name, cam, 1, NULL, &triangles);
    if (scene == NULL)
        snprintf(why, size, "cannot load scene %s (its message above)", name);
    return scene;
}

/* Render rows [y0, y1) into rgb; 0, or -1 with the reason in "why". */
static int render_band(const ray_scene *scene, const ray_camera *cam,
                       const example_args *a, unsigned y0, unsigned y1,
                       float *rgb, char *why, size_t size)
{
    ray_render_options opt;
    int rc;

    opt = (ray_render_options){.width = a->width, .height = a->height};
    opt.y0 = y0;
    opt.y1 = y1;
    opt.samples = a->samples;
    opt.threads = a->threads;
    if (a->adaptive_threshold > 0)
        opt.adaptive_threshold = a->adaptive_threshold;
    if (a->adaptive_depth > 0)
        opt.adaptive_depth = a->adaptive_depth;
    rc = ray_render(scene, cam, &opt, rgb, NULL);
    if (rc == RAY_OK)
        return 0;
    snprintf(why, size, "ray_render rows %u..%u: %s", y0, y1,
             ray_strerror(rc));
    return -1;
}

static void mpi_why(int err, char *why, size_t size, const char *what)
{
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;

    if (MPI_Error_string(err, text, &len) != MPI_SUCCESS)
        snprintf(text, sizeof text, "MPI error %d", err);
    snprintf(why, size, "%s: %.200s", what, text);
}

/* A message that is not what its sender was asked for (a band of another
** size): received and dropped, so that it does not stay first in the queue;
** MPI_ERR_TRUNCATE, to stop the render. */
static int discard(const MPI_Status *st)
{
    int bytes = 0;
    char *scratch;

    MPI_Get_count(st, MPI_BYTE, &bytes);
    scratch = malloc(bytes > 0 ? (size_t)bytes : 1);
    if (scratch != NULL)
        MPI_Recv(scratch, bytes, MPI_BYTE, st->MPI_SOURCE, st->MPI_TAG,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    free(scratch);
    return MPI_ERR_TRUNCATE;
}

/* A worker (rank > 0): set up, then bands until told to stop. */
static int worker(const example_args *a, const char *scene_name, int rank,
                  unsigned band)
{
    char why[REASON_MAX] = "";
    ray_camera cam;
    ray_scene *scene = setup_scene(scene_name, rank, &cam, why, sizeof why);
    float *rgb = NULL;
    unsigned cur[2] = {0, 0}, next[2] = {0, 0};
    int err;

    if (scene != NULL) {
        rgb = malloc(3 * sizeof(float) * a->width * band);
        if (rgb == NULL)
            snprintf(why, sizeof why, "out of memory for a band of %u rows",
                     band);
    }
    if (rgb == NULL) {
        err = MPI_Send(why, (int)strlen(why) + 1, MPI_CHAR, 0, TAG_FAIL,
                       MPI_COMM_WORLD);
        ray_scene_free(scene);
        return err == MPI_SUCCESS ? 0 : 1;
    }
    /* Two bands in hand: the one being rendered and the next, so that a
    ** worker never waits while rank 0 finishes a band of its own before
    ** answering.  Rank 0 answers READY twice and each RESULT once. */
    err = MPI_Send(rgb, 0, MPI_FLOAT, 0, TAG_READY, MPI_COMM_WORLD);
    if (err == MPI_SUCCESS)
        err = MPI_Recv(cur, 2, MPI_UNSIGNED, 0, TAG_WORK, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE);
    if (err == MPI_SUCCESS)
        err = MPI_Recv(next, 2, MPI_UNSIGNED, 0, TAG_WORK, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE);
    while (err == MPI_SUCCESS && cur[1] != 0) {
        if (render_band(scene, &cam, a, cur[0], cur[1], rgb, why,
                        sizeof why) != 0) {
            err = MPI_Send(why, (int)strlen(why) + 1, MPI_CHAR, 0, TAG_FAIL,
                           MPI_COMM_WORLD);
            break;
        }
        err = MPI_Send(rgb, (int)(3 * a->width * (cur[1] - cur[0])),
                       MPI_FLOAT, 0, TAG_RESULT, MPI_COMM_WORLD);
        memcpy(cur, next, sizeof cur);
        if (err == MPI_SUCCESS)
            err = MPI_Recv(next, 2, MPI_UNSIGNED, 0, TAG_WORK,
                           MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    free(rgb);
    ray_scene_free(scene);
    return err == MPI_SUCCESS ? 0 : 1;
}

/* Rank 0: hand out bands, render some itself, gather; the exit status. */
static int coordinator(example_args *a, const char *scene_name, int ranks,
                       unsigned band)
{
    char why[REASON_MAX] = "", error[REASON_MAX + 32] = "";
    /* Per worker, the bands it holds, oldest first (up to 2: y0, y1 each)
    ** and how many. */
    unsigned *given = calloc((size_t)ranks, 4 * sizeof(unsigned));
    unsigned *held = calloc((size_t)ranks, sizeof(unsigned));
    unsigned *bands = calloc((size_t)ranks, sizeof(unsigned));
    unsigned next = 0, y0;
    int active = ranks - 1, rank;
    size_t row = 3 * (size_t)a->width;
    float *image = NULL;
    ray_camera cam;
    ray_scene *scene;
    double t = now_seconds();

    if ((size_t)a->height <= SIZE_MAX / (3 * sizeof(float)) / a->width)
        image = malloc(3 * sizeof(float) * a->width * a->height);
    scene = setup_scene(scene_name, 0, &cam, why, sizeof why);
    if (scene == NULL)
        snprintf(error, sizeof error, "rank 0: %.*s", REASON_MAX, why);
    else if (image == NULL || given == NULL || held == NULL || bands == NULL)
        snprintf(error, sizeof error, "rank 0: out of memory for a %u x %u "
                 "picture", a->width, a->height);
    while (active > 0 || (error[0] == '\0' && next < a->height)) {
        MPI_Status st;
        int flag = 0, count = 0, err = MPI_SUCCESS, replies;
        unsigned job[2] = {0, 0};

        /* Answer the workers first; render a band here only when none is
        ** waiting (each holds a second band meanwhile). */
        if (active > 0) {
            if (error[0] == '\0' && next < a->height)
                err = MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD,
                                 &flag, &st);
            else
                err = MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD,
                                &st), flag = 1;
        }
        if (err != MPI_SUCCESS) {
            mpi_why(err, why, sizeof why, "MPI_Probe");
            snprintf(error, sizeof error, "rank 0: %.*s", REASON_MAX, why);
            break;
        }
        if (!flag) {            /* nobody waiting: a band here */
            y0 = next;
            next = y0 + band < a->height ? y0 + band : a->height;
            bands[0]++;
            if (render_band(scene, &cam, a, y0, next, image + y0 * row, why,
                            sizeof why) != 0)
                snprintf(error, sizeof error, "rank 0: %.*s", REASON_MAX, why);
            continue;
        }
        rank = st.MPI_SOURCE;
        if (st.MPI_TAG == TAG_FAIL) {
            MPI_Get_count(&st, MPI_CHAR, &count);
            if (count < 1 || count > REASON_MAX)
                count = REASON_MAX;
            err = MPI_Recv(why, count, MPI_CHAR, rank, TAG_FAIL,
                           MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            why[REASON_MAX - 1] = '\0';
            if (error[0] == '\0')
                snprintf(error, sizeof error, "rank %d: %s", rank,
                         err == MPI_SUCCESS ? why : "failed");
            held[rank] = 0;
            active--;           /* it stops by itself */
            continue;
        }
        MPI_Get_count(&st, MPI_FLOAT, &count);
        if (st.MPI_TAG == TAG_RESULT && held[rank] > 0 &&
            (size_t)count == row * (given[4 * rank + 1] - given[4 * rank])) {
            err = MPI_Recv(image + given[4 * rank] * row, count, MPI_FLOAT,
                           rank, TAG_RESULT, MPI_COMM_WORLD,
                           MPI_STATUS_IGNORE);
            given[4 * rank] = given[4 * rank + 2];
            given[4 * rank + 1] = given[4 * rank + 3];
            held[rank]--;
            replies = 1;
        } else if (st.MPI_TAG == TAG_READY && count == 0) {
            err = MPI_Recv(NULL, 0, MPI_FLOAT, rank, TAG_READY,
                           MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            replies = 2;
        } else {
            err = discard(&st);
            replies = st.MPI_TAG == TAG_READY ? 2 : 1;
            if (held[rank] > 0 && st.MPI_TAG == TAG_RESULT)
                held[rank]--;   /* the band it was for, lost */
        }
        if (err != MPI_SUCCESS && error[0] == '\0') {
            mpi_why(err, why, sizeof why, "receiving its rows");
            snprintf(error, sizeof error, "rank %d: %.*s", rank, REASON_MAX, why);
        }
        while (replies-- > 0) {
            job[0] = job[1] = 0;        /* y1 = 0: stop */
            if (error[0] == '\0' && next < a->height) {
                size_t k = 4 * (size_t)rank + 2 * (size_t)held[rank];

                job[0] = next;
                job[1] = next = next + band < a->height ? next + band
                                                        : a->height;
                given[k] = job[0];
                given[k + 1] = job[1];
                held[rank]++;
                bands[rank]++;
            }
            err = MPI_Send(job, 2, MPI_UNSIGNED, rank, TAG_WORK,
                           MPI_COMM_WORLD);
            if (err != MPI_SUCCESS && error[0] == '\0') {
                mpi_why(err, why, sizeof why, "sending it a band");
                snprintf(error, sizeof error, "rank %d: %.*s", rank,
                         REASON_MAX, why);
            }
        }
        /* Holding nothing, it has just been sent a stop: it is done. */
        if (held[rank] == 0)
            active--;
    }
    t = now_seconds() - t;
    ray_scene_free(scene);
    if (error[0] == '\0' && example_write_png(a, image) != 0)
        snprintf(error, sizeof error, "rank 0: the PNG was not written");
    else if (error[0] == '\0') {
        printf("mpi_render: wrote %s (%ux%u, %u samples per pixel) with %d "
               "ranks, bands of %u rows, in %.3f s\n", a->output, a->width,
               a->height, a->samples, ranks, band, t);
        for (rank = 0; rank < ranks; rank++)
            printf("mpi_render: rank %d rendered %u bands\n", rank,
                   bands[rank]);
    }
    free(image);
    free(given);
    free(held);
    free(bands);
    if (error[0] == '\0')
        return 0;
    fprintf(stderr, "mpi_render: %s; no picture written\n", error);
    return 1;
}

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "mpi_render", .input = "scene",
        .input_what = "whitted, cornell, teapot, a .bpt or an .obj file",
        .input_default = "whitted", .output_default = "mpi_render.png",
        .sized = 1, .width = 640, .height = 480, .samples = 4,
        .what = "Renders one frame with MPI: rank 0 hands out bands of rows "
                "(RAY_MPI_BAND rows,\ndefault height / (16 x ranks)) to "
                "every rank and writes the picture.\nTest hook: "
                "RAY_MPI_FAIL_RANK=N makes rank N fail its scene setup."};
    example_args args;
    const char *band_env = getenv("RAY_MPI_BAND");
    unsigned band = 0, max_band;
    int rc = example_parse(&cli, argc, argv, &args), rank = 0, ranks = 1;

    if (rc != 0)
        return rc;
    if (band_env != NULL && band_env[0] != '\0' &&
        (rc = example_number(&cli, "RAY_MPI_BAND", band_env, 1,
                             EXAMPLE_MAX_SIDE, &band)) != 0)
        return rc;
    if (MPI_Init(&argc, &argv) != MPI_SUCCESS) {
        fprintf(stderr, "mpi_render: MPI_Init failed\n");
        return 1;
    }
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    /* Every rank computes the same band: same arguments, same size. */
    if (band == 0)
        band = args.height / (16u * (unsigned)ranks);
    /* A band's message counts floats in an int. */
    max_band = (unsigned)(INT_MAX / 3 / args.width);
    band = band < 1 ? 1 : band > max_band ? max_band : band;
    band = band > args.height ? args.height : band;
    /* The output is checked on rank 0 only (the other nodes may not have
    ** its directory), and every rank learns the verdict. */
    if (rank == 0)
        rc = example_output_check(cli.name, args.output);
    if (MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD) != MPI_SUCCESS)
        rc = 1;
    if (rc == 0)
        rc = rank == 0 ? coordinator(&args, args.input, ranks, band)
                       : worker(&args, args.input, rank, band);
    MPI_Finalize();
    return rc;
}
