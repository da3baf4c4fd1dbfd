/* SPDX-License-Identifier: MIT */
/*
** imgdiff.c -- how far apart two PNG pictures are, for make
** windows-check (doc/PLATFORMS.md): both read as 8-bit RGB (libpng's
** simplified API), then the number of channel values that differ and
** the largest difference, in 8-bit steps.  Exits 0 if they are the same
** pixels, 1 if not, 2 if they cannot be compared.
**
**     imgdiff a.png b.png
*/
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned char *load(const char *path, png_uint_32 *w, png_uint_32 *h)
{
    png_image img;
    unsigned char *rgb;

    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return NULL;
    img.format = PNG_FORMAT_RGB;
    rgb = malloc(PNG_IMAGE_SIZE(img));
    if (rgb == NULL || !png_image_finish_read(&img, NULL, rgb, 0, NULL)) {
        png_image_free(&img);
        free(rgb);
        return NULL;
    }
    *w = img.width;
    *h = img.height;
    return rgb;
}

int main(int argc, char **argv)
{
    png_uint_32 wa = 0, ha = 0, wb = 0, hb = 0;
    unsigned char *a, *b;
    size_t i, n, differ = 0;
    int most = 0;

    if (argc != 3) {
        fprintf(stderr, "usage: imgdiff a.png b.png\n");
        return 2;
    }
    a = load(argv[1], &wa, &ha);
    b = load(argv[2], &wb, &hb);
    if (a == NULL || b == NULL || wa != wb || ha != hb) {
        printf("imgdiff: %s and %s: not two PNGs of one size\n", argv[1],
               argv[2]);
        return 2;
    }
    n = 3 * (size_t)wa * ha;
    for (i = 0; i < n; i++) {
        int d = abs((int)a[i] - (int)b[i]);
        differ += d != 0;
        most = d > most ? d : most;
    }
    printf("%s: %lu x %lu, %lu of %lu channel values differ, by at most "
           "%d/255\n", argv[2], (unsigned long)wa, (unsigned long)ha,
           (unsigned long)differ, (unsigned long)n, most);
    free(a);
    free(b);
    return differ == 0 ? 0 : 1;
}
