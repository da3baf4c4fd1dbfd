/* SPDX-License-Identifier: MIT */
/*
** png.c -- PNG files, the only file that includes <png.h>.
**
** Output goes through libpng's simplified API (libpng 1.6, png.h section
** 5): no setjmp, no callbacks.  It is written to a temporary file beside
** the target and renamed over it only once complete (write_file).
*/
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>

#include "internal.h"

/* Clamp to [0, 1]; NaN goes to 0 (the comparison is false for NaN). */
static double unit_clamp(float x)
{
    if (!(x > 0.0f))
        return 0.0;
    return x < 1.0f ? (double)x : 1.0;
}

/* The sRGB transfer function, IEC 61966-2-1:1999 section 5.2. */
static double srgb_encode(double linear)
{
    if (linear <= 0.0031308)
        return 12.92 * linear;
    return 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

int ray_image_to_srgb8(const float *rgb, size_t count, unsigned char *out)
{
    size_t i;

    if (rgb == NULL || out == NULL)
        return RAY_EINVAL;
    for (i = 0; i < 3 * count; i++)
        out[i] = (unsigned char)(srgb_encode(unit_clamp(rgb[i])) * 255.0 + 0.5);
    return RAY_OK;
}

static void to_linear16(const float *rgb, size_t count, png_uint_16 *out)
{
    size_t i;

    for (i = 0; i < 3 * count; i++)
        out[i] = (png_uint_16)(unit_clamp(rgb[i]) * 65535.0 + 0.5);
}

/*
** The encoded image into fp, then a checked flush (and fsync when "sync"),
** and fclose: a full disk often shows only when the buffered data are
** written out, and a file renamed over another must be on the disk first
** or a crash could leave an empty file where the old one was.
*/
static int write_stream(FILE *fp, png_image *img, const void *pixels,
                        int sync)
{
    int ok = png_image_write_to_stdio(img, fp, 0, pixels, 0, NULL);
    int io_failed = fflush(fp) != 0 || ferror(fp);

    if (!io_failed && sync)
        io_failed = fsync(fileno(fp)) != 0;
    io_failed |= fclose(fp) != 0;
    if (io_failed)
        return RAY_EIO;
    return ok ? RAY_OK : RAY_EPNG;
}

/*
** A device or a FIFO (/dev/stdout into a pipe, /dev/null) is written in
** place: it cannot be replaced, and on failure nothing is removed.
*/
static int write_in_place(const char *path, png_image *img,
                          const void *pixels)
{
    FILE *fp = fopen(path, "wb");

    if (fp == NULL)
        return RAY_EIO;
    return write_stream(fp, img, pixels, 0);
}

/* Tries at a free temporary name: each EEXIST is another writer of the
** same path in this process, or the leftover of a crashed one. */
#define TEMP_ATTEMPTS 100
/* ".<pid>-<attempt>.tmp": a long's and an int's digits, signs, ".tmp". */
#define TEMP_SUFFIX_SIZE 48

/*
** A temporary file beside the target, "<path>.<pid>-<n>.tmp", created
** with O_EXCL (so two threads, or a planted file, never share it) and mode
** 0666 less the umask, as fopen would create the target itself; this
** avoids reading the umask, which only umask() can, by changing it for
** every thread.  Returns the descriptor, or -1 (errno set).
*/
static int create_temp(const char *target, char *temp, size_t size)
{
    int attempt, fd = -1;

    for (attempt = 0; attempt < TEMP_ATTEMPTS; attempt++) {
        snprintf(temp, size, "%s.%ld-%d.tmp", target, (long)getpid(),
                 attempt);
        fd = open(temp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            break;
    }
    return fd;
}

/*
** A regular file, or none yet: write a temporary file and rename it over
** the target only once it is complete, so a failure leaves the old file
** as it was (rename is atomic, POSIX.1-2008 rename()).  An existing file's
** permission bits are kept (owner and group become the caller's).  On any
** failure only the temporary file is removed, with errno kept.
*/
static int write_replacing(const char *path, const struct stat *old,
                           png_image *img, const void *pixels)
{
    size_t size = strlen(path) + TEMP_SUFFIX_SIZE;
    char *temp = malloc(size);
    FILE *fp = NULL;
    int fd, rc, saved_errno;

    if (temp == NULL)
        return RAY_ENOMEM;
    fd = create_temp(path, temp, size);
    if (fd < 0) {
        free(temp);
        return RAY_EIO;
    }
    if (old == NULL || fchmod(fd, old->st_mode & 0777) == 0)
        fp = fdopen(fd, "wb");
    if (fp == NULL) {
        rc = RAY_EIO;
        saved_errno = errno;
        close(fd);
        errno = saved_errno;
    } else {
        rc = write_stream(fp, img, pixels, 1);
    }
    if (rc == RAY_OK && rename(temp, path) != 0)
        rc = RAY_EIO;
    if (rc != RAY_OK) {
        saved_errno = errno;        /* unlink() must not hide the cause */
        unlink(temp);
        errno = saved_errno;
    }
    free(temp);
    return rc;
}

/*
** stat follows symbolic links: a link to a device is written through, a
** link to a regular file is replaced by the new file (the file it named
** is left as it was).  A directory fails at fopen (EISDIR).
*/
static int write_file(const char *path, png_image *img, const void *pixels)
{
    struct stat st;

    if (stat(path, &st) != 0)
        return write_replacing(path, NULL, img, pixels);
    if (S_ISREG(st.st_mode))
        return write_replacing(path, &st, img, pixels);
    return write_in_place(path, img, pixels);
}

int ray_write_png(const char *path, const float *rgb, unsigned width,
                  unsigned height, int bits)
{
    png_image img;
    size_t count, bytes;
    void *pixels;
    int rc;

    if (path == NULL || rgb == NULL || width == 0 || height == 0 ||
        (bits != 8 && bits != 16))
        return RAY_EINVAL;
    /* libpng limits rows to 2^31-1 bytes; also keep our sizes in size_t. */
    if (width > PNG_UINT_31_MAX / 6 || height > PNG_UINT_31_MAX ||
        (size_t)height > SIZE_MAX / 6 / width)
        return RAY_EINVAL;
    count = (size_t)width * height;
    bytes = count * 3 * (size_t)(bits / 8);
    pixels = malloc(bytes);
    if (pixels == NULL)
        return RAY_ENOMEM;
    if (bits == 8)
        ray_image_to_srgb8(rgb, count, (unsigned char *)pixels);
    else
        to_linear16(rgb, count, (png_uint_16 *)pixels);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = width;
    img.height = height;
    img.format = bits == 8 ? PNG_FORMAT_RGB : PNG_FORMAT_LINEAR_RGB;
    rc = write_file(path, &img, pixels);
    png_image_free(&img);
    free(pixels);
    return rc;
}

