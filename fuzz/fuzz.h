/* SPDX-License-Identifier: MIT */
/*
** fuzz.h -- what the fuzz targets share: reading values out of the
** fuzzer's bytes, the contracts of include/ray.h written as checks, and a
** counting allocator.
**
** Each target defines LLVMFuzzerTestOneInput.  "make fuzz" links it with
** libFuzzer (clang -fsanitize=fuzzer); "make check" links it with
** fuzz/replay.c, which runs it over the committed corpora and reproducers
** with any compiler.  A broken contract prints what broke and aborts, so
** libFuzzer saves the input and the replay fails.
*/
#ifndef RAY_FUZZ_H
#define RAY_FUZZ_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ray.h"

/*
** Every contract is checked: the defects these targets found (issue 14's
** 1, 3, 5, 6, 7; ray_fresnel's NaN; p_err and the t bounds under
** underflow; ray_parametric's unbounded descent) are fixed, and their
** reproducers in fuzz/crashes/ are replayed by make check.  A contract
** found broken before its fix lands may be switched off meanwhile by an
** #ifndef FUZZ_KNOWN_DEFECT_<name> around its check, defined here (and
** -DFUZZ_CHECK_ALL to check it anyway); none is today.
*/

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* ------------------------------------------------------------ failures */

static inline void fuzz_fail(const char *file, int line, const char *cond,
                      const char *what)
{
    fprintf(stderr, "fuzz: %s:%d: contract broken: %s: %s\n", file, line,
            what, cond);
    abort();
}

/* FUZZ_CHECK(cond, what): "what" names the function and the promise. */
#define FUZZ_CHECK(cond, what) \
    ((cond) ? (void)0 : fuzz_fail(__FILE__, __LINE__, #cond, what))

/* ------------------------------------------------------- reading values */

typedef struct fuzz_input {
    const uint8_t *data;
    size_t size, pos;
} fuzz_input;

static inline fuzz_input fuzz_input_of(const uint8_t *data, size_t size)
{
    fuzz_input in;
    in.data = data;
    in.size = size;
    in.pos = 0;
    return in;
}

static inline int fuzz_more(const fuzz_input *in)
{
    return in->pos < in->size;
}

/* The next byte; 0 once the input is used up (so every input decodes). */
static inline unsigned fuzz_u8(fuzz_input *in)
{
    return in->pos < in->size ? in->data[in->pos++] : 0u;
}

/* A number in [0, n) (n > 0), from one byte, or two if n > 256. */
static inline unsigned fuzz_below(fuzz_input *in, unsigned n)
{
    unsigned x = fuzz_u8(in);
    if (n > 256)
        x = x << 8 | fuzz_u8(in);
    return x % n;
}

/*
** The values where floating-point code breaks: signed zeros, the limits
** of the format (DBL_MAX, the smallest normal and subnormal), NaN and
** the infinities, values whose squares or products overflow or vanish
** (1e150, 1e300, 1e-150), and neighbours of 1 (issue 14, defect 1, came
** from 1 + 2^-52).
*/
static const double fuzz_special[] = {
    0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 2.0, 3.0, -8.0, 8.0, 10.0, 0.1,
    1.0 / 3.0, 1e5, 1e10, -1e10, 1e-10, 1e150, -1e150, 1e-150, 1e300,
    -1e300, 1e-300, DBL_MAX, -DBL_MAX, DBL_MIN, -DBL_MIN, 4.9406564584124654e-324,
    DBL_EPSILON, 1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON / 2, 3.141592653589793,
    HUGE_VAL, -HUGE_VAL
};
#define FUZZ_N_SPECIAL (sizeof fuzz_special / sizeof fuzz_special[0])

/*
** Any double: a selector byte picks a special value (NaN too), a small
** multiple of 1/4 (simple scenes that hit), a scaled one (every
** magnitude), or the next 8 bytes as they are (every bit pattern).
*/
static inline double fuzz_double(fuzz_input *in)
{
    unsigned sel = fuzz_u8(in);

    if (sel < 48) {
        if (sel == FUZZ_N_SPECIAL)
            return (double)NAN;
        if (sel == FUZZ_N_SPECIAL + 1)
            return -(double)NAN;
        return fuzz_special[sel % FUZZ_N_SPECIAL];
    }
    if (sel < 176)
        return (double)(int)(fuzz_u8(in) ^ 0x80u) / 4 - 32;
    if (sel < 224) {
        double m = (double)(int)(fuzz_u8(in) ^ 0x80u) - 128;
        return ldexp(m / 16, (int)fuzz_u8(in) * 8 - 1024);
    }
    {
        uint64_t bits = 0;
        double d;
        unsigned k;
        for (k = 0; k < 8; k++)
            bits = bits << 8 | fuzz_u8(in);
        memcpy(&d, &bits, sizeof d);
        return d;
    }
}

/* A finite double in [0, max] (material parameters, which the library
** borrows and does not check). */
static inline double fuzz_unit_range(fuzz_input *in, double max)
{
    return max * (double)fuzz_u8(in) / 255;
}

static inline ray_vec3 fuzz_vec3(fuzz_input *in)
{
    ray_vec3 v;
    v.x = fuzz_double(in);
    v.y = fuzz_double(in);
    v.z = fuzz_double(in);
    return v;
}

static inline ray_rgb fuzz_rgb(fuzz_input *in)
{
    ray_rgb c;
    c.r = fuzz_double(in);
    c.g = fuzz_double(in);
    c.b = fuzz_double(in);
    return c;
}

/* A ray; tmax is often +Inf (the usual unbounded ray), tmin often 0. */
static inline ray_ray fuzz_ray(fuzz_input *in)
{
    ray_ray r;
    unsigned how = fuzz_u8(in);
    r.org = fuzz_vec3(in);
    r.dir = fuzz_vec3(in);
    r.tmin = how & 1 ? fuzz_double(in) : 0.0;
    r.tmax = how & 2 ? fuzz_double(in) : HUGE_VAL;
    return r;
}

/* ------------------------------------------------------------ contracts */

static inline int fuzz_finite3(ray_vec3 v)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

static inline int fuzz_status_valid(int s)
{
    return s >= RAY_OK && s <= RAY_EEFFECT;
}

/* A byte pattern no routine writes, to see whether outputs were touched. */
#define FUZZ_SENTINEL 0xA5
static inline void fuzz_sentinel(void *p, size_t n)
{
    memset(p, FUZZ_SENTINEL, n);
}

static inline int fuzz_untouched(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    size_t i;
    for (i = 0; i < n; i++)
        if (b[i] != FUZZ_SENTINEL)
            return 0;
    return 1;
}

/*
** |n| = 1 within this: a normal is divided by its computed length, which
** leaves an error of a few ulps (Higham, "Accuracy and Stability of
** Numerical Algorithms", 2nd ed., section 3.1: gamma(n) bounds), far
** below 1e-12, the tolerance the issue asks for.
*/
#define FUZZ_UNIT_TOL 1e-12

/*
** What every hit promises (ray.h, struct ray_hit and the conventions):
** tmin < t < tmax, and no NaN or Inf anywhere; a unit normal; p_err >= 0.
** "flat" is 1 for hits that may come from a plane or polygon, whose (u, v)
** may still be infinite (defect 1).
*/
static inline void fuzz_check_hit(const ray_ray *r, const ray_hit *h,
                                  int flat, const char *what)
{
    double n2 = h->n.x * h->n.x + h->n.y * h->n.y + h->n.z * h->n.z;

    FUZZ_CHECK(h->t > r->tmin && h->t < r->tmax, what);
    FUZZ_CHECK(isfinite(h->t), what);
    FUZZ_CHECK(fuzz_finite3(h->p), what);
    FUZZ_CHECK(fuzz_finite3(h->n), what);
    FUZZ_CHECK(fabs(n2 - 1) <= FUZZ_UNIT_TOL, what);
    FUZZ_CHECK(fuzz_finite3(h->p_err), what);
    FUZZ_CHECK(h->p_err.x >= 0 && h->p_err.y >= 0 && h->p_err.z >= 0, what);
    (void)flat;
    FUZZ_CHECK(isfinite(h->u) && isfinite(h->v), what);
}

/* -------------------------------------------- a counting allocator */

/*
** Lua's l_alloc with ltests.c's accounting: every block carries its size
** in a header, so a wrong osize, a double free or a leak is caught.  The
** "fail_at"-th allocation (1-based; 0: none) fails once, to walk the
** error paths.  Not thread-safe: the scene fuzzer renders on one thread.
*/
typedef struct fuzz_alloc {
    size_t live_blocks, live_bytes;
    unsigned long calls, fail_at;
    unsigned long failures;
} fuzz_alloc;

/* The header keeps the block aligned for any type (C99 has no
** max_align_t). */
typedef union fuzz_block_header {
    size_t size;
    long double ld;
    long long ll;
    void *p;
} fuzz_block_header;

static inline void *fuzz_alloc_fn(void *ud, void *ptr, size_t osize, size_t nsize)
{
    fuzz_alloc *a = (fuzz_alloc *)ud;
    fuzz_block_header *h = ptr ? (fuzz_block_header *)ptr - 1 : NULL;
    fuzz_block_header *n;

    if (h != NULL)
        FUZZ_CHECK(h->size == osize, "alloc: osize is the block's size");
    if (nsize == 0) {
        if (h != NULL) {
            a->live_blocks--;
            a->live_bytes -= h->size;
            free(h);
        }
        return NULL;
    }
    if (++a->calls == a->fail_at) {
        a->failures++;
        return NULL;
    }
    if (nsize > SIZE_MAX - sizeof *h)
        return NULL;
    n = (fuzz_block_header *)realloc(h, sizeof *n + nsize);
    if (n == NULL)
        return NULL;
    if (h != NULL)
        a->live_bytes -= osize;
    else
        a->live_blocks++;
    a->live_bytes += nsize;
    n->size = nsize;
    return n + 1;
}

#endif
