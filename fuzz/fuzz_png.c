/* SPDX-License-Identifier: MIT */
/*
** fuzz_png.c -- ray_image_load_png on any bytes (textures come from files
** users download).  The loader takes a path, so each input is written to
** one temporary file of this process first.
**
** Checked: the status is RAY_OK, RAY_EPNG, RAY_ENOMEM, RAY_ERANGE or
** RAY_EIO; *out untouched on failure; on success the size is 1 .. 2^14 on
** each side, every texel finite and in [0, 1], and ray_image_sample gives
** finite colours.  The memory a hostile file may cost is bounded by the
** fuzz run's -rss_limit_mb and -malloc_limit_mb (Makefile: issue 14,
** defect 4).
*/
#include <unistd.h>

#include "fuzz.h"

/* The largest side ray_image_load_png accepts by default (RAY_ELIMIT
** above: ray_image_load_png(3)). */
#define MAX_SIDE 16384u

/* The temporary file, made once per process (removed at exit). */
static char tmp_path[64];

static void remove_tmp(void)
{
    if (tmp_path[0] != '\0')
        remove(tmp_path);
}

static int write_tmp(const uint8_t *data, size_t size)
{
    FILE *fp;
    int ok;

    if (tmp_path[0] == '\0') {
        int fd;
        strcpy(tmp_path, "/tmp/libray-fuzz-png-XXXXXX");
        fd = mkstemp(tmp_path);
        if (fd < 0) {
            tmp_path[0] = '\0';
            return 0;
        }
        close(fd);
        atexit(remove_tmp);
    }
    fp = fopen(tmp_path, "wb");
    if (fp == NULL)
        return 0;
    ok = fwrite(data, 1, size, fp) == size;
    ok &= fclose(fp) == 0;
    return ok;
}

static void check_image(const ray_image *img)
{
    unsigned w = 0, h = 0, x, y;

    ray_image_size(img, &w, &h);
    FUZZ_CHECK(w >= 1 && h >= 1 && w <= MAX_SIDE && h <= MAX_SIDE,
               "ray_image_load_png: size");
    /* Sample the texel centres of a few rows and columns. */
    for (y = 0; y < h && y < 8; y++)
        for (x = 0; x < w && x < 8; x++) {
            ray_rgb c;
            int rc = ray_image_sample(img, (x + 0.5) / w, (y + 0.5) / h, 0, &c);
            FUZZ_CHECK(rc == RAY_OK, "ray_image_sample: status");
            FUZZ_CHECK(c.r >= 0 && c.r <= 1 && c.g >= 0 && c.g <= 1 &&
                           c.b >= 0 && c.b <= 1,
                       "ray_image_sample: a colour in [0, 1]");
        }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ray_image *img;
    int rc;

    if (!write_tmp(data, size))
        return 0;
    fuzz_sentinel(&img, sizeof img);
    rc = ray_image_load_png(tmp_path, NULL, &img);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EPNG || rc == RAY_ENOMEM ||
                   rc == RAY_ELIMIT || rc == RAY_ERANGE || rc == RAY_EIO ||
                   rc == RAY_ENOTSUP,
               "ray_image_load_png: status");
    if (rc != RAY_OK) {
        FUZZ_CHECK(fuzz_untouched(&img, sizeof img),
                   "ray_image_load_png: *out untouched on failure");
        return 0;
    }
    check_image(img);
    ray_image_free(img);
    return 0;
}
