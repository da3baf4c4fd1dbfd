/* SPDX-License-Identifier: MIT */
/*
** check_png.c -- ray_image_to_srgb8 and ray_write_png, checked by reading
** the file back with libpng and comparing bytes (stb's image_write_test
** idea: a tiny asymmetric image, different colours on R and B so a channel
** swap or a flip shows).  In a library built without libpng (RAY_TEST_PNG
** 0, make PNG=0) only the sRGB encoding is tested here (check_texture.c
** checks RAY_ENOTSUP).
**
** The file cases run on POSIX and on Windows (doc/PLATFORMS.md), each
** with its platform's equivalent where the case is about the platform:
** /dev/null or NUL, a FIFO or a named pipe, a full disk (a file size
** limit) or a target in use.  What has no equivalent (/dev/full, POSIX
** permission bits, symbolic links, an unwritable directory) is skipped
** on Windows with a SKIP line.
*/
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#else
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include "tempfiles.h"
#include "tests.h"

#ifndef RAY_TEST_PNG
#define RAY_TEST_PNG 1
#endif
#if RAY_TEST_PNG
#include <png.h>
#endif

#define W 5
#define H 3

#if RAY_TEST_PNG
/* An 'L' of red on blue, plus one grey pixel and out-of-range values. */
static void test_image(float *rgb)
{
    int x, y;

    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            float *p = rgb + 3 * (y * W + x);
            int on = x == 0 || y == H - 1;
            p[0] = on ? 1.0f : 0.0f;
            p[1] = 0.0f;
            p[2] = on ? 0.0f : 1.0f;
        }
    rgb[3 * 7 + 0] = 0.5f;    /* (2,1): mid grey, NaN, over-range */
    rgb[3 * 7 + 1] = NAN;
    rgb[3 * 7 + 2] = 7.0f;
}

static char *temp_path(const char *tag)
{
    static char buf[512];
    char name[64];
    snprintf(name, sizeof name, "libray-check-%s-%ld.png", tag,
             (long)getpid());
    test_tmp_path(buf, sizeof buf, name);
    return buf;
}
#endif

START_TEST(srgb8_should_follow_the_srgb_curve)
{
    float in[12] = {0.0f, 1.0f, 0.5f, 0.0031308f, 0.18f, -1.0f,
                    2.0f, NAN, INFINITY, -INFINITY, 0.001f, 0.9f};
    unsigned char out[12];

    ck_assert_int_eq(ray_image_to_srgb8(in, 4, out), RAY_OK);
    /* Reference values: 255 * srgb(x) rounded, computed by hand from
    ** IEC 61966-2-1 (0.5 -> 0.73536 -> 187.5 -> 188; 0.18 -> 0.46135 ->
    ** 117.6 -> 118; 0.0031308 -> 0.04045 -> 10.3 -> 10; 0.001 ->
    ** 0.01292 -> 3.29 -> 3; 0.9 -> 0.95477 -> 243.5 -> 243 or 244). */
    ck_assert_uint_eq(out[0], 0);
    ck_assert_uint_eq(out[1], 255);
    ck_assert_uint_eq(out[2], 188);
    ck_assert_uint_eq(out[3], 10);
    ck_assert_uint_eq(out[4], 118);
    ck_assert_uint_eq(out[5], 0);
    ck_assert_uint_eq(out[6], 255);
    ck_assert_uint_eq(out[7], 0);
    ck_assert_uint_eq(out[8], 255);
    ck_assert_uint_eq(out[9], 0);
    ck_assert_uint_eq(out[10], 3);
    ck_assert(out[11] == 243 || out[11] == 244);
    ck_assert_int_eq(ray_image_to_srgb8(NULL, 1, out), RAY_EINVAL);
    ck_assert_int_eq(ray_image_to_srgb8(in, 1, NULL), RAY_EINVAL);
}
END_TEST

/*
** The pow formula ray_image_to_srgb8 was written as, and is now a table
** of thresholds for (src/image/srgb8.c): the IEC 61966-2-1 curve in
** double, rounded to the byte.  The reference the table must equal
** exactly: no tolerance, bytes are compared.
*/
static unsigned srgb8_formula(float x)
{
    double l = !(x > 0.0f) ? 0.0 : x < 1.0f ? (double)x : 1.0;
    double e = l <= 0.0031308 ? 12.92 * l
                              : 1.055 * pow(l, 1.0 / 2.4) - 0.055;

    return (unsigned char)(e * 255.0 + 0.5);
}

/* The least float whose formula byte is k (1 .. 255): the decoding
** curve's value at (k - 0.5) / 255 as a first guess, then moved a float
** at a time until the float below has byte k - 1 and it has k. */
static float srgb8_threshold(unsigned k)
{
    double e = (k - 0.5) / 255.0;
    float x = (float)(e <= 0.04045 ? e / 12.92
                                   : pow((e + 0.055) / 1.055, 2.4));

    while (srgb8_formula(x) >= k)
        x = nextafterf(x, 0.0f);
    while (srgb8_formula(x) < k)
        x = nextafterf(x, 2.0f);
    return x;
}

/* The library's byte of one value. */
static unsigned srgb8_library(float x)
{
    float rgb[3] = {x, x, x};
    unsigned char out[3];

    ck_assert_int_eq(ray_image_to_srgb8(rgb, 1, out), RAY_OK);
    ck_assert(out[0] == out[1] && out[1] == out[2]);
    return out[0];
}

/*
** The same bytes as the pow formula for every input: at each of the 255
** thresholds where the byte changes and 8 floats either side of it
** (where a pow rounding differently could move a step; elsewhere
** E(x) 255 + 0.5 is farther from an integer than pow's error, since a
** float step moves it by about 2^-24 / 2.4 of itself), around the
** curve's joint at 0.0031308, and over a sweep of every 127th float of
** [0, 1] (8.4 million) in blocks of 4096 (one call each), plus the
** values beyond: negative, over 1, infinite, NaN.
*/
START_TEST(srgb8_should_give_the_pow_formulas_bytes_for_every_float)
{
    static float in[3 * 4096];
    static unsigned char out[3 * 4096];
    const float beyond[] = {-0.0f, -1e-30f, -1.0f, 1.0f, 1.5f, 1e30f,
                            INFINITY, -INFINITY, NAN};
    float x;
    uint32_t bits;
    unsigned k, i, n = 0, wrong = 0;
    int j;

    for (k = 1; k <= 255; k++) {
        float t = srgb8_threshold(k), y = t;
        ck_assert_uint_eq(srgb8_library(t), k);
        ck_assert_uint_eq(srgb8_library(nextafterf(t, 0.0f)), k - 1);
        for (j = 0; j < 8; j++)
            y = nextafterf(y, 0.0f);
        for (j = 0; j < 17; j++, y = nextafterf(y, 2.0f))
            ck_assert_uint_eq(srgb8_library(y), srgb8_formula(y));
    }
    x = 0.0031308f;
    for (j = 0; j < 64; j++)
        x = nextafterf(x, 0.0f);
    for (j = 0; j < 129; j++, x = nextafterf(x, 2.0f))
        ck_assert_uint_eq(srgb8_library(x), srgb8_formula(x));
    for (i = 0; i < sizeof beyond / sizeof beyond[0]; i++)
        ck_assert_uint_eq(srgb8_library(beyond[i]), srgb8_formula(beyond[i]));
    /* Floats of [0, 1] by their bit patterns, 0 .. 0x3f800000. */
    for (bits = 0; bits <= 0x3f800000u; bits += 127) {
        memcpy(&in[n], &bits, sizeof bits);
        if (++n == 3 * 4096 || bits + 127 > 0x3f800000u) {
            ck_assert_int_eq(ray_image_to_srgb8(in, n / 3 + (n % 3 != 0), out), RAY_OK);
            for (k = 0; k < n; k++)
                wrong += out[k] != srgb8_formula(in[k]);
            n = 0;
        }
    }
    ck_assert_uint_eq(wrong, 0);
}
END_TEST

#if RAY_TEST_PNG
START_TEST(png8_should_read_back_identical_bytes)
{
    float rgb[3 * W * H];
    unsigned char expect[3 * W * H], got[3 * W * H];
    png_image img;
    char *path = temp_path("8");

    test_image(rgb);
    ray_image_to_srgb8(rgb, W * H, expect);
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 8), RAY_OK);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    ck_assert(png_image_begin_read_from_file(&img, path));
    ck_assert_uint_eq(img.width, W);
    ck_assert_uint_eq(img.height, H);
    img.format = PNG_FORMAT_RGB;
    ck_assert(png_image_finish_read(&img, NULL, got, 0, NULL));
    ck_assert_mem_eq(got, expect, sizeof got);
    /* Spot checks: top-left red, top-right blue, bottom row red. */
    ck_assert_uint_eq(got[0], 255);
    ck_assert_uint_eq(got[2], 0);
    ck_assert_uint_eq(got[3 * 4 + 0], 0);
    ck_assert_uint_eq(got[3 * 4 + 2], 255);
    ck_assert_uint_eq(got[3 * (2 * W + 3) + 0], 255);
    remove(path);
}
END_TEST

START_TEST(png16_should_keep_linear_values)
{
    float rgb[3 * W * H];
    png_uint_16 got[3 * W * H];
    png_image img;
    char *path = temp_path("16");

    test_image(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 16), RAY_OK);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    ck_assert(png_image_begin_read_from_file(&img, path));
    img.format = PNG_FORMAT_LINEAR_RGB;
    ck_assert(png_image_finish_read(&img, NULL, got, 0, NULL));
    ck_assert_uint_eq(got[0], 65535);
    ck_assert_uint_eq(got[2], 0);
    /* 0.5 -> 32768 (0.5 * 65535 + 0.5 rounds down to 32768). */
    ck_assert_uint_eq(got[3 * 7 + 0], 32768);
    ck_assert_uint_eq(got[3 * 7 + 1], 0);
    ck_assert_uint_eq(got[3 * 7 + 2], 65535);
    remove(path);
}
END_TEST

START_TEST(png_should_report_bad_arguments_and_io_errors)
{
    float rgb[3 * W * H];
    const char *bad = "/nonexistent-dir-libray/x.png";

    test_image(rgb);
    ck_assert_int_eq(ray_write_png(NULL, rgb, W, H, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", NULL, W, H, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, 0, H, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, W, 0, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, W, H, 12), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, 0x7fffffffu, 0x7fffffffu, 8),
                     RAY_EINVAL);
    errno = 0;
    ck_assert_int_eq(ray_write_png(bad, rgb, W, H, 8), RAY_EIO);
    ck_assert_int_eq(errno, ENOENT);
}
END_TEST

/* ------------------------------------------- failures leave files alone */

/* A fresh directory of this test's own, so that leftovers can be counted. */
static void make_dir(char *dir, size_t size, const char *tag)
{
    ck_assert(test_make_dir(dir, size, tag));
}

static char *in_dir(const char *dir, const char *name)
{
    static char buf[600];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

/* The entries of dir but . and .., and the directory removed if empty. */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;

    ck_assert_ptr_nonnull(d);
    while ((e = readdir(d)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static void write_text(const char *path, const char *text)
{
    FILE *fp = fopen(path, "wb");
    ck_assert_ptr_nonnull(fp);
    fputs(text, fp);
    ck_assert_int_eq(fclose(fp), 0);
}

/* The file's first bytes (at most size - 1), NUL-terminated. */
static void read_text(const char *path, char *buf, size_t size)
{
    FILE *fp = fopen(path, "rb");
    size_t n;

    ck_assert_ptr_nonnull(fp);
    n = fread(buf, 1, size - 1, fp);
    buf[n] = '\0';
    fclose(fp);
}

static const unsigned char png_signature[8] = {137, 80, 78, 71, 13, 10, 26,
                                               10};

/*
** Devices are written in place and never removed: /dev/full fails with
** ENOSPC at flush time and stays (the old code then removed the path: as
** root, /dev/full itself); /dev/null takes the file.  Only where they
** exist, as on Linux.  Windows: NUL, its null device, takes the file
** (GetFileType: a character device); it has no /dev/full.
*/
START_TEST(png_write_should_leave_devices_in_place)
{
    float rgb[3 * W * H];
#if defined(_WIN32)
    test_image(rgb);
    ck_assert_int_eq(ray_write_png("NUL", rgb, W, H, 16), RAY_OK);
    ck_assert_int_eq(ray_write_png("nul", rgb, W, H, 8), RAY_OK);
    test_skip("png_write_should_leave_devices_in_place",
              "Windows has no /dev/full (a device that is always full): "
              "the failing device is not tested, NUL is");
#else
    struct stat st;

    test_image(rgb);
    if (access("/dev/full", W_OK) == 0) {
        errno = 0;
        ck_assert_int_eq(ray_write_png("/dev/full", rgb, W, H, 8), RAY_EIO);
        ck_assert_int_eq(errno, ENOSPC);
        ck_assert_int_eq(stat("/dev/full", &st), 0);
        ck_assert(S_ISCHR(st.st_mode));
    }
    if (access("/dev/null", W_OK) == 0) {
        ck_assert_int_eq(ray_write_png("/dev/null", rgb, W, H, 16), RAY_OK);
        ck_assert_int_eq(stat("/dev/null", &st), 0);
        ck_assert(S_ISCHR(st.st_mode));
    }
#endif
}
END_TEST

#if defined(_WIN32)
/*
** Windows' FIFO is a named pipe, \\.\pipe\NAME: written in place (no
** temporary file beside it, no rename), the reader gets the PNG, and
** the pipe is still there.  The server end is made first, with a buffer
** the file (about 100 bytes) fits, so the writer's connection and write
** do not wait for the read.
*/
START_TEST(png_write_should_stream_into_a_fifo)
{
    float rgb[3 * W * H];
    unsigned char got[8];
    char name[64];
    HANDLE pipe;
    DWORD n = 0;

    test_image(rgb);
    snprintf(name, sizeof name, "\\\\.\\pipe\\libray-check-%lu",
             (unsigned long)GetCurrentProcessId());
    pipe = CreateNamedPipeA(name, PIPE_ACCESS_INBOUND,
                            PIPE_TYPE_BYTE | PIPE_READMODE_BYTE | PIPE_WAIT,
                            1, 0, 65536, 0, NULL);
    ck_assert(pipe != INVALID_HANDLE_VALUE);
    ck_assert_int_eq(ray_write_png(name, rgb, W, H, 8), RAY_OK);
    ck_assert(ReadFile(pipe, got, sizeof got, &n, NULL));
    ck_assert_uint_eq(n, sizeof got);
    ck_assert_mem_eq(got, png_signature, sizeof got);
    CloseHandle(pipe);
}
END_TEST
#else
/* A FIFO is written in place too: the reader gets the PNG, the FIFO stays.
** The read end is opened first, non-blocking, so the writer's open does
** not wait; the file (about 100 bytes) fits the pipe's buffer. */
START_TEST(png_write_should_stream_into_a_fifo)
{
    float rgb[3 * W * H];
    unsigned char got[8];
    char dir[512];
    const char *fifo;
    struct stat st;
    int fd;

    test_image(rgb);
    make_dir(dir, sizeof dir, "fifo");
    fifo = in_dir(dir, "pipe.png");
    ck_assert_int_eq(mkfifo(fifo, 0600), 0);
    fd = open(fifo, O_RDONLY | O_NONBLOCK);
    ck_assert_int_ge(fd, 0);
    ck_assert_int_eq(ray_write_png(fifo, rgb, W, H, 8), RAY_OK);
    ck_assert_int_eq(read(fd, got, sizeof got), (ssize_t)sizeof got);
    ck_assert_mem_eq(got, png_signature, sizeof got);
    close(fd);
    ck_assert_int_eq(stat(fifo, &st), 0);
    ck_assert(S_ISFIFO(st.st_mode));
    ck_assert_int_eq(entries(dir), 1);     /* no temporary file */
    unlink(fifo);
    rmdir(dir);
}
END_TEST
#endif

/* A directory, or a path through a missing one: RAY_EIO, nothing made. */
START_TEST(png_write_should_refuse_directories)
{
    float rgb[3 * W * H];
    char dir[512];
    struct stat st;

    test_image(rgb);
    make_dir(dir, sizeof dir, "dir");
    errno = 0;
    ck_assert_int_eq(ray_write_png(dir, rgb, W, H, 8), RAY_EIO);
    ck_assert_int_eq(errno, EISDIR);
    ck_assert_int_eq(stat(dir, &st), 0);
    ck_assert(S_ISDIR(st.st_mode));
    errno = 0;
    ck_assert_int_eq(ray_write_png(in_dir(dir, "missing/x.png"), rgb, W, H,
                                   8),
                     RAY_EIO);
    ck_assert_int_eq(errno, ENOENT);
    ck_assert_int_eq(entries(dir), 0);
    rmdir(dir);
}
END_TEST

/* A noise image, compressing to about 12 KiB. */
enum { N = 64 };

static void noise_image(float *noise)
{
    unsigned seed = 12345;
    int i;

    for (i = 0; i < 3 * N * N; i++) {
        seed = seed * 1103515245u + 12345u;  /* any spread of values */
        noise[i] = (float)(seed >> 16 & 0x7fff) / 32767.0f;
    }
}

#if defined(_WIN32)
/*
** A failed write leaves the old file byte for byte.  On Windows the
** failure is the replacement's: the target held open by another handle
** that does not share deletion (an image viewer, say), so MoveFileExW
** cannot replace it: RAY_EIO, errno EACCES, the old file as it was and no
** temporary file left.  Once it is closed the PNG replaces it.  (POSIX
** permission bits, which the POSIX run checks are kept, are not
** Windows'.)  The disk-full failure of the POSIX run has no equivalent
** here: no per-process file size limit.
*/
START_TEST(png_write_should_keep_the_old_file_on_failure)
{
    static float noise[3 * N * N];
    char dir[512], got[64], path[600];
    HANDLE held;

    noise_image(noise);
    make_dir(dir, sizeof dir, "keep");
    snprintf(path, sizeof path, "%s", in_dir(dir, "old.png"));
    write_text(path, "the old contents");
    held = CreateFileA(path, GENERIC_READ, FILE_SHARE_READ, NULL,
                       OPEN_EXISTING, FILE_ATTRIBUTE_NORMAL, NULL);
    ck_assert(held != INVALID_HANDLE_VALUE);
    errno = 0;
    ck_assert_int_eq(ray_write_png(path, noise, N, N, 8), RAY_EIO);
    ck_assert_int_eq(errno, EACCES);
    CloseHandle(held);
    read_text(path, got, sizeof got);
    ck_assert_str_eq(got, "the old contents");
    ck_assert_int_eq(entries(dir), 1);
    ck_assert_int_eq(ray_write_png(path, noise, N, N, 8), RAY_OK);
    read_text(path, got, 9);
    ck_assert_mem_eq(got, png_signature, 8);
    ck_assert_int_eq(entries(dir), 1);
    test_skip("png_write_should_keep_the_old_file_on_failure",
              "Windows has no file size limit (RLIMIT_FSIZE) to fill the "
              "disk with, nor POSIX permission bits to keep: the failure "
              "tested is a target in use");
    remove(path);
    rmdir(dir);
}
END_TEST

START_TEST(png_write_should_replace_a_link_not_its_target)
{
    test_skip("png_write_should_replace_a_link_not_its_target",
              "symbolic links on Windows need a privilege (or developer "
              "mode) that a test cannot assume");
}
END_TEST

START_TEST(png_write_should_fail_in_an_unwritable_directory)
{
    test_skip("png_write_should_fail_in_an_unwritable_directory",
              "Windows has ACLs, not POSIX permission bits (and Wine does "
              "not enforce either); the missing directory of "
              "png_write_should_refuse_directories stands in");
}
END_TEST
#else
/*
** A failed write leaves the old file byte for byte.  The full disk is a
** file size limit (RLIMIT_FSIZE of 1 KiB, SIGXFSZ ignored so the write
** fails with EFBIG instead of killing), set in a child process so the
** limit stays there: the 64 x 64 noise image compresses to about 12 KiB.
** Then a successful write replaces the file, keeping its mode 0600, and
** leaves no temporary file.
*/
START_TEST(png_write_should_keep_the_old_file_on_failure)
{
    static float noise[3 * N * N];
    char dir[512], got[64], path[600];
    struct stat st;
    pid_t child;
    int status;

    noise_image(noise);
    make_dir(dir, sizeof dir, "keep");
    snprintf(path, sizeof path, "%s", in_dir(dir, "old.png"));
    write_text(path, "the old contents");
    ck_assert_int_eq(chmod(path, 0600), 0);
    child = fork();
    ck_assert_int_ge(child, 0);
    if (child == 0) {
        struct rlimit lim = {1024, 1024};
        int rc;
        signal(SIGXFSZ, SIG_IGN);
        setrlimit(RLIMIT_FSIZE, &lim);
        errno = 0;
        rc = ray_write_png(path, noise, N, N, 8);
        _exit(rc == RAY_EIO && errno == EFBIG ? 0 : 1);
    }
    ck_assert_int_eq(waitpid(child, &status, 0), child);
    ck_assert(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    read_text(path, got, sizeof got);
    ck_assert_str_eq(got, "the old contents");
    ck_assert_int_eq(entries(dir), 1);
    /* Success: the PNG replaces it, with the old permissions. */
    ck_assert_int_eq(ray_write_png(path, noise, N, N, 8), RAY_OK);
    read_text(path, got, 9);
    ck_assert_mem_eq(got, png_signature, 8);
    ck_assert_int_eq(stat(path, &st), 0);
    ck_assert_uint_eq(st.st_mode & 0777, 0600);
    ck_assert_int_eq(entries(dir), 1);
    unlink(path);
    rmdir(dir);
}
END_TEST

/* A symbolic link is replaced by the new file, like the file it named
** would be by rename(2): the file it named is left as it was. */
START_TEST(png_write_should_replace_a_link_not_its_target)
{
    float rgb[3 * W * H];
    char dir[512], target[600], link[600], got[64];
    struct stat st;

    test_image(rgb);
    make_dir(dir, sizeof dir, "link");
    snprintf(target, sizeof target, "%s", in_dir(dir, "target"));
    snprintf(link, sizeof link, "%s", in_dir(dir, "link.png"));
    write_text(target, "kept");
    ck_assert_int_eq(symlink(target, link), 0);
    ck_assert_int_eq(ray_write_png(link, rgb, W, H, 8), RAY_OK);
    ck_assert_int_eq(lstat(link, &st), 0);
    ck_assert(S_ISREG(st.st_mode));
    read_text(target, got, sizeof got);
    ck_assert_str_eq(got, "kept");
    ck_assert_int_eq(entries(dir), 2);
    unlink(link);
    unlink(target);
    rmdir(dir);
}
END_TEST

/* Without write permission on the directory (not for root, whom
** permissions do not stop: then the missing directory above stands in). */
START_TEST(png_write_should_fail_in_an_unwritable_directory)
{
    float rgb[3 * W * H];
    char dir[512], path[600], got[64];

    if (geteuid() == 0)
        return;
    test_image(rgb);
    make_dir(dir, sizeof dir, "ro");
    snprintf(path, sizeof path, "%s", in_dir(dir, "x.png"));
    write_text(path, "old");
    ck_assert_int_eq(chmod(dir, 0500), 0);
    errno = 0;
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 8), RAY_EIO);
    ck_assert_int_eq(errno, EACCES);
    read_text(path, got, sizeof got);
    ck_assert_str_eq(got, "old");
    ck_assert_int_eq(chmod(dir, 0700), 0);
    ck_assert_int_eq(entries(dir), 1);
    unlink(path);
    rmdir(dir);
}
END_TEST
#endif

/*
** A path in UTF-8 with characters outside ASCII (two-, three- and
** four-byte sequences: e acute, a CJK character, an emoji) is written
** and read back by that name; on Windows the library converts it to
** UTF-16 for the wide calls, so the name is the same whatever the ANSI
** code page; the directory holds that one file.
*/
START_TEST(png_should_take_utf8_paths)
{
    float rgb[3 * W * H];
    char dir[512], path[600];
    ray_image *img = NULL;
    unsigned w = 0, h = 0;

    test_image(rgb);
    make_dir(dir, sizeof dir, "utf8");
    snprintf(path, sizeof path, "%s",
             in_dir(dir, "caf\xc3\xa9-\xe6\x97\xa5-\xf0\x9f\x8c\x88.png"));
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 16), RAY_OK);
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 8), RAY_OK);
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_OK);
    ray_image_size(img, &w, &h);
    ck_assert_uint_eq(w, W);
    ck_assert_uint_eq(h, H);
    ray_image_free(img);
    ck_assert_int_eq(entries(dir), 1);
#if defined(_WIN32)
    {
        wchar_t wpath[600];
        size_t n = mbstowcs(wpath, dir, 500);
        ck_assert(n < 500);
        /* U+1F308 as its UTF-16 surrogate pair. */
        wcscpy(wpath + n, L"/caf\u00e9-\u65e5-\xd83c\xdf08.png");
        ck_assert_int_eq(_wremove(wpath), 0);
    }
#else
    ck_assert_int_eq(remove(path), 0);
#endif
    ck_assert_int_eq(entries(dir), 0);
    rmdir(dir);
}
END_TEST
#endif

Suite *png_suite(void)
{
    Suite *s = suite_create("png");
    TCase *tc = tcase_create("io");

    tcase_add_test(tc, srgb8_should_follow_the_srgb_curve);
    tcase_add_test(tc, srgb8_should_give_the_pow_formulas_bytes_for_every_float);
#if RAY_TEST_PNG
    tcase_add_test(tc, png8_should_read_back_identical_bytes);
    tcase_add_test(tc, png16_should_keep_linear_values);
    tcase_add_test(tc, png_should_report_bad_arguments_and_io_errors);
    tcase_add_test(tc, png_write_should_leave_devices_in_place);
    tcase_add_test(tc, png_write_should_stream_into_a_fifo);
    tcase_add_test(tc, png_write_should_refuse_directories);
    tcase_add_test(tc, png_write_should_keep_the_old_file_on_failure);
    tcase_add_test(tc, png_write_should_replace_a_link_not_its_target);
    tcase_add_test(tc, png_write_should_fail_in_an_unwritable_directory);
    tcase_add_test(tc, png_should_take_utf8_paths);
#else
    fprintf(stderr, "png: built with PNG=0: the 10 PNG writing tests "
                    "skipped (check_texture.c checks RAY_ENOTSUP)\n");
#endif
    suite_add_tcase(s, tc);
    return s;
}
