/* SPDX-License-Identifier: MIT */
/*
** png.c -- PNG files, the only file that includes <png.h>.
**
** Output goes through libpng's simplified API (libpng 1.6, png.h section
** 5): no setjmp, no callbacks.  The PNG is encoded in memory
** (png_image_write_to_memory: no FILE handed across to libpng, whose C
** runtime may not be ours on Windows) and written by the platform layer's
** safe write (core/platform.h: a temporary file beside the target,
** renamed over it only once complete).
**
** Input (ray_image_load_png) goes through the full read API, because the
** simplified one cannot bound what a hostile file costs: it reads every
** ancillary chunk and allocates the length a chunk declares (0x73737373
** bytes for a 193-byte file), since libpng's own chunk limit is only a
** benign error, a warning, when reading.  Here a watch on the bytes read
** refuses such chunks and over-sized images from their headers, before
** libpng or the loader allocates for them (watch_chunks), and the image
** grows with the rows actually decoded.  setjmp is confined to decode().
*/
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

#include "core/platform.h"
#include "image/image.h"

/* Clamp to [0, 1]; NaN goes to 0 (the comparison is false for NaN).  For
** the 16-bit linear encoding (the 8-bit sRGB one, srgb8.c, clamps by its
** table). */
static double linear16_clamp(float x)
{
    if (!(x > 0.0f))
        return 0.0;
    return x < 1.0f ? (double)x : 1.0;
}

static void to_linear16(const float *rgb, size_t count, png_uint_16 *out)
{
    size_t i;

    for (i = 0; i < 3 * count; i++)
        out[i] = (png_uint_16)(linear16_clamp(rgb[i]) * 65535.0 + 0.5);
}

/*
** The PNG of img in a buffer of *size bytes (malloc'd), or NULL with
** *status.  Its room is libpng's bound on the encoded size
** (PNG_IMAGE_PNG_SIZE_MAX: the pixels, deflate's worst case, the chunks),
** so one encoding is enough; should that bound wrap around (a size_t of
** 32 bits), libpng says what it needs and the second try has it.
*/
static void *encode(png_image *img, const void *pixels, size_t *size,
                    int *status)
{
    png_alloc_size_t room = PNG_IMAGE_PNG_SIZE_MAX(*img), need;
    int attempt;

    for (attempt = 0; attempt < 2; attempt++) {
        void *buf = malloc(room);
        if (buf == NULL) {
            *status = RAY_ENOMEM;
            return NULL;
        }
        need = room;
        if (png_image_write_to_memory(img, buf, &need, 0, pixels, 0, NULL)) {
            *size = need;
            return buf;
        }
        free(buf);
        if (need <= room)     /* a failure of libpng's own, not the room */
            break;
        room = need;
    }
    *status = RAY_EPNG;
    return NULL;
}

int ray_write_png(const char *path, const float *rgb, unsigned width,
                  unsigned height, int bits)
{
    png_image img;
    size_t count, bytes, size = 0;
    void *pixels, *file;
    int rc, saved_errno;

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
    file = encode(&img, pixels, &size, &rc);
    png_image_free(&img);
    free(pixels);
    if (file == NULL)
        return rc;
    rc = ray__file_write(path, file, size);
    saved_errno = errno;        /* free() must not hide the cause */
    free(file);
    errno = saved_errno;
    return rc;
}

/* ------------------------------------------------------------- reading */

/* The default limits of ray_image_load_options: 2^14 on a side (as
** before the options existed), 2^28 pixels (3 GiB of floats), and 64 MiB
** for any chunk but IDAT, which libpng streams through zlib instead. */
#define DEFAULT_MAX_SIDE 16384u
#define DEFAULT_MAX_PIXELS ((size_t)DEFAULT_MAX_SIDE * DEFAULT_MAX_SIDE)
#define DEFAULT_MAX_CHUNK_BYTES ((size_t)64 << 20)

/* 2^16 16-bit codes: the decoding table of a non-linear 16-bit file. */
#define CODES16 65536u

typedef struct png_load {
    FILE *fp;
    ray_image_load_options lim;  /* with the defaults filled in */
    int status;              /* why libpng stopped: set before png_error */
    png_byte chunk[4];       /* the type of the chunk being read */
    png_structp png;
    png_infop info;
    png_uint_32 width, height;
    int sixteen, alpha;      /* as decoded: 16-bit samples, RGBA */
    float lut8[256];         /* 8-bit code to linear */
    float *lut16;            /* 16-bit code to linear; NULL: v / 65535 */
    unsigned char *row;      /* one row as libpng delivers it */
    float *rgb;              /* the image, rows_ready rows allocated */
    size_t rows_ready;
} png_load;

static void on_png_error(png_structp png, png_const_charp msg)
{
    (void)msg;               /* the library never prints */
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* libpng's allocations, so that a failed one reads as RAY_ENOMEM. */
static png_voidp on_png_malloc(png_structp png, png_alloc_size_t size)
{
    png_load *ld = png_get_mem_ptr(png);
    void *p = malloc(size);

    if (p == NULL && ld != NULL)
        ld->status = RAY_ENOMEM;
    return p;
}

static void on_png_free(png_structp png, png_voidp p)
{
    (void)png;
    free(p);
}

/* width x height within the limits (0 is libpng's to refuse). */
static int size_within_limits(const png_load *ld, png_uint_32 width,
                              png_uint_32 height)
{
    if (width > ld->lim.max_width || height > ld->lim.max_height)
        return 0;
    return width == 0 || height <= ld->lim.max_pixels / width;
}

/*
** Sees every read as libpng makes it (png_get_io_state): a chunk header is
** read as 8 bytes in one call, IHDR's data as 13 (pngrutil.c,
** png_read_chunk_header and png_handle_IHDR), so a chunk over the limit
** and an image over the limits are refused from their headers, before
** libpng allocates for them.  libpng's own user limits, set too, are the
** fallback: they refuse the same files, as RAY_EPNG.
*/
static int watch_chunks(png_load *ld, png_uint_32 io_state,
                        png_const_bytep data, size_t n)
{
    png_uint_32 where = io_state & PNG_IO_MASK_LOC;

    if (where == PNG_IO_CHUNK_HDR && n == 8) {
        memcpy(ld->chunk, data + 4, 4);
        return memcmp(ld->chunk, "IDAT", 4) == 0 ||
               png_get_uint_32(data) <= ld->lim.max_chunk_bytes;
    }
    if (where == PNG_IO_CHUNK_DATA && n == 13 &&
        memcmp(ld->chunk, "IHDR", 4) == 0)
        return size_within_limits(ld, png_get_uint_32(data),
                                  png_get_uint_32(data + 4));
    return 1;
}

static void read_bytes(png_structp png, png_bytep data, size_t n)
{
    png_load *ld = png_get_io_ptr(png);

    if (fread(data, 1, n, ld->fp) != n) {
        /* End of file: a truncated PNG, which libpng would report. */
        ld->status = ferror(ld->fp) ? RAY_EIO : RAY_EPNG;
        png_error(png, "read failed");
    }
    if (!watch_chunks(ld, png_get_io_state(png), data, n)) {
        ld->status = RAY_ELIMIT;
        png_error(png, "over a load limit");
    }
}

/* The sRGB transfer function's inverse, IEC 61966-2-1:1999 section 5.2:
** a code in [0, 1] to linear light. */
static double srgb_decode(double encoded)
{
    if (encoded <= 0.04045)
        return encoded / 12.92;
    return pow((encoded + 0.055) / 1.055, 2.4);
}

/* code / (levels - 1) to linear: the sRGB curve for exponent 0, else the
** power law of a gAMA chunk. */
static float decode_code(unsigned code, unsigned levels, double exponent)
{
    double v = (double)code / (double)(levels - 1);

    return (float)(exponent == 0 ? srgb_decode(v) : pow(v, exponent));
}

/*
** How the file's codes map to light (PNG 1.2 sections 10.5-10.6, ISO/IEC
** 15948:2004 11.3.3): an sRGB chunk means the IEC curve; otherwise a gAMA
** chunk g means linear = code^(1/g); without either an 8-bit file is
** taken as sRGB and a 16-bit file as linear (ray_write_png's 16-bit files
** carry gAMA 1.0).  Tables of every code, computed exactly in double:
** libpng's own conversion approximates sRGB by a 2.2 power, up to 1% off
** in the mid-tones.  Returns RAY_OK or RAY_ENOMEM.
*/
static int choose_decoding(png_load *ld)
{
    double exponent = ld->sixteen ? 1.0 : 0.0;
    png_fixed_point gamma;
    int intent;
    unsigned i;

    if (png_get_sRGB(ld->png, ld->info, &intent))
        exponent = 0.0;
    else if (png_get_gAMA_fixed(ld->png, ld->info, &gamma) && gamma > 0)
        exponent = (double)PNG_FP_1 / (double)gamma;
    if (!ld->sixteen) {
        for (i = 0; i < 256; i++)
            ld->lut8[i] = decode_code(i, 256, exponent);
        return RAY_OK;
    }
    if (exponent == 1.0)
        return RAY_OK;           /* v / 65535 directly, as it always was */
    ld->lut16 = malloc(CODES16 * sizeof *ld->lut16);
    if (ld->lut16 == NULL)
        return RAY_ENOMEM;
    for (i = 0; i < CODES16; i++)
        ld->lut16[i] = decode_code(i, CODES16, exponent);
    return RAY_OK;
}

/* Sample k of the row from pixel p on, as linear light (alpha: as is). */
static double sample_at(const png_load *ld, png_const_bytep p, int k,
                        int is_alpha)
{
    if (ld->sixteen) {
        unsigned v = (unsigned)p[2 * k] << 8 | p[2 * k + 1];
        if (is_alpha || ld->lut16 == NULL)
            return (double)v / 65535.0;
        return (double)ld->lut16[v];
    }
    return is_alpha ? (double)p[k] / 255.0 : (double)ld->lut8[p[k]];
}

/*
** One decoded row of "cols" pixels into the image from "out" on, "step"
** floats apart.  Alpha is composed on black in linear light: the colour
** times its coverage (PNG 1.2 section 10.8).
*/
static void convert_row(const png_load *ld, png_uint_32 cols, float *out,
                        size_t step)
{
    int channels = ld->alpha ? 4 : 3;
    size_t bytes = (size_t)channels * (ld->sixteen ? 2 : 1);
    png_const_bytep p = ld->row;
    png_uint_32 x;
    int k;

    for (x = 0; x < cols; x++, p += bytes, out += step) {
        double a = ld->alpha ? sample_at(ld, p, 3, 1) : 1.0;
        for (k = 0; k < 3; k++)
            out[k] = (float)(sample_at(ld, p, k, 0) * a);
    }
}

/* Room for the first "rows" rows, grown by doubling: a file that declares
** a large image but fails to decode costs only the rows it delivered. */
static int reserve_rows(png_load *ld, size_t rows)
{
    size_t row_floats = 3 * (size_t)ld->width, grown;
    float *p;

    if (rows <= ld->rows_ready)
        return RAY_OK;
    grown = ld->rows_ready > ld->height / 2 ? ld->height : 2 * ld->rows_ready;
    if (grown < rows)
        grown = rows;
    p = realloc(ld->rgb, grown * row_floats * sizeof *p);
    if (p == NULL)
        return RAY_ENOMEM;
    ld->rgb = p;
    ld->rows_ready = grown;
    return RAY_OK;
}

/* Where a pass's pixels lie: columns x0 + i*dx, rows y0 + j*dy. */
typedef struct pass_grid {
    unsigned char x0, y0, dx, dy;
} pass_grid;

/* The seven passes of Adam7 (PNG 1.2 section 8.2), and a plain image. */
static const pass_grid adam7[PNG_INTERLACE_ADAM7_PASSES] = {
    {0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
    {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}
};
static const pass_grid no_interlace = {0, 0, 1, 1};

/* The count of i >= 0 with start + i*step < n. */
static png_uint_32 pass_count(png_uint_32 n, unsigned start, unsigned step)
{
    return n > start ? (n - start + step - 1) / step : 0;
}

/*
** Every row, pass by pass: without libpng's interlace handling an Adam7
** file comes as its seven sub-images, whose pixels are placed here
** straight into the image, so no second full-size buffer of libpng's
** samples is needed.  Empty passes are skipped, as libpng skips them.
*/
static int read_rows(png_load *ld, int interlaced)
{
    int pass, passes = interlaced ? PNG_INTERLACE_ADAM7_PASSES : 1;

    for (pass = 0; pass < passes; pass++) {
        const pass_grid *g = interlaced ? &adam7[pass] : &no_interlace;
        png_uint_32 cols = pass_count(ld->width, g->x0, g->dx);
        png_uint_32 rows = pass_count(ld->height, g->y0, g->dy);
        png_uint_32 j;

        for (j = 0; cols > 0 && j < rows; j++) {
            size_t y = g->y0 + (size_t)j * g->dy;
            if (reserve_rows(ld, y + 1) != RAY_OK)
                return RAY_ENOMEM;
            png_read_row(ld->png, ld->row, NULL);
            convert_row(ld, cols, ld->rgb + 3 * (y * ld->width + g->x0),
                        3 * (size_t)g->dx);
        }
    }
    return RAY_OK;
}

/* Only the chunks that decide the pixels are read; libpng skips every
** other one unread and unallocated (png_set_keep_unknown_chunks). */
static const png_byte chunks_to_read[] = {
    103, 65, 77, 65, '\0',   /* gAMA */
    115, 82, 71, 66, '\0'    /* sRGB */
};

/* libpng's limits, the fallback of watch_chunks (see there). */
static void set_png_limits(const png_load *ld)
{
    png_uint_32 w = ld->lim.max_width < PNG_UINT_31_MAX ? ld->lim.max_width
                                                         : PNG_UINT_31_MAX;
    png_uint_32 h = ld->lim.max_height < PNG_UINT_31_MAX
                        ? ld->lim.max_height : PNG_UINT_31_MAX;

    png_set_user_limits(ld->png, w, h);
    png_set_chunk_malloc_max(ld->png, ld->lim.max_chunk_bytes);
    /* Text, sPLT and unknown chunks: libpng counts down from this and
    ** stores none at 1 (pngrutil.c); they are skipped anyway. */
    png_set_chunk_cache_max(ld->png, 1);
    png_set_keep_unknown_chunks(ld->png, PNG_HANDLE_CHUNK_NEVER, NULL, -1);
    png_set_keep_unknown_chunks(ld->png, PNG_HANDLE_CHUNK_AS_DEFAULT,
                                chunks_to_read,
                                (int)(sizeof chunks_to_read / 5));
}

/*
** The header, the checks and the rows.  libpng's errors come back here by
** longjmp, with the status its callbacks set; every object they touch is
** in *ld, not in this function's variables (C99 7.13.2.1).
*/
static int decode(png_load *ld)
{
    int status;

    if (setjmp(png_jmpbuf(ld->png)))
        return ld->status;
    png_set_read_fn(ld->png, ld, read_bytes);
    set_png_limits(ld);
    png_read_info(ld->png, ld->info);
    ld->width = png_get_image_width(ld->png, ld->info);
    ld->height = png_get_image_height(ld->png, ld->info);
    if (!size_within_limits(ld, ld->width, ld->height))
        return RAY_ELIMIT;
    if ((size_t)ld->width * ld->height > SIZE_MAX / 3 / sizeof(float))
        return RAY_ENOMEM;
    /* Palette, grey and low depths to 8-bit RGB; tRNS to alpha. */
    png_set_expand(ld->png);
    png_set_gray_to_rgb(ld->png);
    png_read_update_info(ld->png, ld->info);
    ld->sixteen = png_get_bit_depth(ld->png, ld->info) == 16;
    ld->alpha = png_get_channels(ld->png, ld->info) == 4;
    status = choose_decoding(ld);
    if (status != RAY_OK)
        return status;
    ld->row = malloc(png_get_rowbytes(ld->png, ld->info));
    if (ld->row == NULL)
        return RAY_ENOMEM;
    return read_rows(ld, png_get_interlace_type(ld->png, ld->info) !=
                             PNG_INTERLACE_NONE);
}

static void resolve_limits(const ray_image_load_options *opt,
                           ray_image_load_options *lim)
{
    memset(lim, 0, sizeof *lim);
    if (opt != NULL)
        *lim = *opt;
    if (lim->max_width == 0)
        lim->max_width = DEFAULT_MAX_SIDE;
    if (lim->max_height == 0)
        lim->max_height = DEFAULT_MAX_SIDE;
    if (lim->max_pixels == 0)
        lim->max_pixels = DEFAULT_MAX_PIXELS;
    if (lim->max_chunk_bytes == 0)
        lim->max_chunk_bytes = DEFAULT_MAX_CHUNK_BYTES;
}

static int load_stream(png_load *ld, ray_image **out)
{
    ray_image *img;
    int status;

    ld->png = png_create_read_struct_2(PNG_LIBPNG_VER_STRING, ld,
                                       on_png_error, on_png_warning, ld,
                                       on_png_malloc, on_png_free);
    if (ld->png == NULL)
        return RAY_ENOMEM;
    ld->info = png_create_info_struct(ld->png);
    status = ld->info == NULL ? RAY_ENOMEM : decode(ld);
    png_destroy_read_struct(&ld->png, &ld->info, NULL);
    free(ld->row);
    free(ld->lut16);
    if (status != RAY_OK) {
        free(ld->rgb);
        return status;
    }
    img = ray__image_new(ld->width, ld->height, ld->rgb);
    if (img == NULL) {
        free(ld->rgb);
        return RAY_ENOMEM;
    }
    *out = img;
    return RAY_OK;
}

int ray_image_load_png(const char *path, const ray_image_load_options *opt,
                       ray_image **out)
{
    png_load ld;
    int status, saved_errno;

    if (path == NULL || out == NULL)
        return RAY_EINVAL;
    memset(&ld, 0, sizeof ld);
    resolve_limits(opt, &ld.lim);
    ld.status = RAY_EPNG;
    ld.fp = ray__file_open_read(path);
    if (ld.fp == NULL)            /* no memory for the name or the FILE */
        return errno == ENOMEM ? RAY_ENOMEM : RAY_EIO;
    status = load_stream(&ld, out);
    saved_errno = errno;        /* fclose() must not hide the cause */
    fclose(ld.fp);
    errno = saved_errno;
    return status;
}
