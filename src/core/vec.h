/* SPDX-License-Identifier: MIT */
/*
** vec.h -- the bottom layer: vectors, rounding bounds and float
** bracketing, as static inline functions over the public ray_vec3.
** Depends on nothing but ray.h and libm; every other private header
** stands on it (vec.h < prim.h < bvh.h < scene.h < trace.h).
*/
#ifndef RAY_VEC_H
#define RAY_VEC_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "ray.h"

/*
** MinGW (doc/PLATFORMS.md).  Its isfinite and signbit choose a branch by
** the argument's type, and the float branch converts a double argument to
** float: a -Wfloat-conversion warning at every use, for a branch never
** taken.  GCC's builtins are the same tests without it.  And the library's messages (ray__fail, the
** shapes' checks) need C99's printf -- %zu, %g's two-digit exponents and
** "inf" -- which MinGW gives only with __USE_MINGW_ANSI_STDIO (msvcrt's
** own has none of them; MSVC's UCRT has all): the build must set it.
*/
#if defined(__MINGW32__) && defined(__GNUC__)
#undef isfinite
#define isfinite(x) __builtin_isfinite(x)
#undef signbit
#define signbit(x) __builtin_signbit(x)
#if !defined(__USE_MINGW_ANSI_STDIO) || !__USE_MINGW_ANSI_STDIO
#error "MinGW: build libray with -D__USE_MINGW_ANSI_STDIO=1 (C99 printf)"
#endif
#endif

/*
** SSE2, which the SIMD paths test (slab.h, watertight.h, sah.c): GCC and
** Clang say __SSE2__; MSVC does not, though every x64 CPU has SSE2 (on
** x86, /arch:SSE2 or above sets _M_IX86_FP to 2).  RAY_NO_SIMD turns the
** paths off: the portable C that other CPUs take.
*/
#if !defined(RAY_NO_SIMD) && \
    (defined(__SSE2__) || defined(_M_X64) || defined(_M_AMD64) || \
     (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#define RAY__SSE2 1
#else
#define RAY__SSE2 0
#endif

/*
** A small function a hot loop must not call: GCC and Clang keep one with
** several callers out of line once a file grows past their inlining
** budget, and a call there spills the loop's registers (the refit's
** corner reads, triangles.c: 11% more instructions out of line, issue
** 36).  Elsewhere "static inline", the compiler's choice.
*/
#if defined(__GNUC__)
#define RAY__HOT_INLINE static inline __attribute__((always_inline))
#else
#define RAY__HOT_INLINE static inline
#endif

/*
** A hint that *p will be read soon (query/slab.h's leaves, scene/slots.h's
** corners): GCC's and Clang's builtin, MSVC's SSE intrinsic on x86,
** nothing elsewhere.  Never a fault, whatever p points at, and no effect
** on any answer.
*/
#if defined(__GNUC__)
#define RAY__PREFETCH(p) __builtin_prefetch(p)
#elif defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
#include <emmintrin.h>
#define RAY__PREFETCH(p) _mm_prefetch((const char *)(p), _MM_HINT_T0)
#else
#define RAY__PREFETCH(p) ((void)(p))
#endif

/* pi, which strict C99 <math.h> does not define. */
#define RAY__PI 3.14159265358979323846

/* ------------------------------------------------------- vector helpers */

/* The public helpers of ray.h (ray_vec3_make ...) under the short names
** the library's code uses: one definition of the arithmetic, not two. */
#define v3 ray_vec3_make
#define v3_add ray_vec3_add
#define v3_sub ray_vec3_sub
#define v3_scale ray_vec3_scale

/* a + s*b, in two roundings per component (no FMA: see the Makefile). */
static inline ray_vec3 v3_madd(ray_vec3 a, double s, ray_vec3 b)
{
    return v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}

#define v3_dot ray_vec3_dot
#define v3_cross ray_vec3_cross

static inline ray_vec3 v3_abs(ray_vec3 a)
{
    return v3(fabs(a.x), fabs(a.y), fabs(a.z));
}

static inline double v3_length(ray_vec3 a)
{
    return sqrt(v3_dot(a, a));
}

/* 1 when v3_normalize(a, ...) succeeds: a finite, non-zero vector.
** Comparisons, not fmax (a libm call): they may drop or take a NaN
** operand, so every component is checked too -- a cross product of huge
** vectors can hold Inf - Inf = NaN beside finite ones.  For a vector
** without NaN, m is fmax's. */
static inline int v3_normalizable(ray_vec3 a)
{
    double ax = fabs(a.x), ay = fabs(a.y), az = fabs(a.z);
    double m = ax > ay ? ax : ay;

    m = m > az ? m : az;
    return m > 0 && m < HUGE_VAL && a.x == a.x && a.y == a.y && a.z == a.z;
}

/*
** a / |a| into *out, safe from overflow and underflow of |a|^2: a is first
** divided by its largest |component|, which brings that component to 1
** and |a| into [1, sqrt 3], so the normal of a 1e-150-sized triangle
** (|n|^2 ~ 1e-600), of a denormal one or of a 1e200-sized one still comes
** out unit.
** Returns 0, leaving *out untouched, for a zero or non-finite vector.
*/
static inline int v3_normalize(ray_vec3 a, ray_vec3 *out)
{
    double ax = fabs(a.x), ay = fabs(a.y), az = fabs(a.z);
    double m = ax > ay ? ax : ay;
    double len;

    m = m > az ? m : az;
    if (!v3_normalizable(a))
        return 0;
    /* Divide by m rather than multiply by 1/m: for a denormal m, 1/m
    ** overflows to Inf, while each quotient here is at most 1. */
    a = v3(a.x / m, a.y / m, a.z / m);
    len = v3_length(a);
    *out = v3_scale(a, 1.0 / len);
    return 1;
}

/* Component k (0: x, 1: y, 2: z) of v. */
static inline double v3_axis(ray_vec3 v, int k)
{
    return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

/* 1 when every component is finite (neither NaN nor +-Inf). */
static inline int v3_isfinite(ray_vec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}

/* ((x - x) + (y - y)) + (z - z): +0 for a finite vector, NaN where a
** component is infinite or NaN (x - x is then NaN).  A sum of these is
** 0 exactly when every number in it is finite: one compare for many
** numbers, not a classification of each (ray_spawn's twelve; a
** triangle's error bound, triangle.c). */
static inline double v3_off_finite(ray_vec3 a)
{
    return ((a.x - a.x) + (a.y - a.y)) + (a.z - a.z);
}

/* A borrowed const pointer as the plain void * of a callback's ud: the
** library only reads through it.  A union rather than a cast, so the
** compiler's -Wcast-qual still guards every other cast. */
static inline void *ray__unconst(const void *p)
{
    union {
        const void *c;
        void *m;
    } u;
    u.c = p;
    return u.m;
}

/* ------------------------------------------------------ rounding bounds */

/*
** gamma(n) = n*u / (1 - n*u), u = DBL_EPSILON/2: the relative error bound
** of n chained IEEE-754 roundings (Higham, "Accuracy and Stability of
** Numerical Algorithms", 2nd ed., Lemma 3.1; pbrt-v4 util/float.h uses the
** same name).  Used to build the hit records' p_err bounds.
*/
/*
** Underflow: gamma(n) bounds relative errors, which hold only while no
** result falls below DBL_MIN.  A product or quotient that underflows is
** off by at most half the smallest subnormal, 2^-1075, in absolute terms
** (sums and differences of subnormals are exact): IEEE 754's gradual
** underflow, Higham 2nd ed., section 2.1.  The error bounds add
** RAY__TINY (2^-1074, one whole subnormal) per product they cover, so
** they stay bounds for geometry with coordinates near 1e-308 or whose
** products underflow (found by fuzz/fuzz_primitives: a ray spawned off a
** triangle at z = 2e-312 re-hit it).
*/
#define RAY__TINY 0x1p-1074

static inline double ray__gamma(int n)
{
    double nu = (double)n * (DBL_EPSILON * 0.5);
    return nu / (1.0 - nu);
}

/*
** The rounding error of p = fl(a*b): a*b - p, exactly, from the four
** products of a's and b's 26-bit halves (Dekker, "A floating-point
** technique for extending the available precision", Numer. Math. 18,
** 1971: TwoProduct with Veltkamp's split, 2^27 + 1), in plain double
** arithmetic, so the same bits on every platform.  Not fma: C99 asks it
** to be correctly rounded, but MinGW's libm rounds it through the x87's
** 64-bit products and got about 1 in 10 wrong on random operands (doc/
** PLATFORMS.md); where fma is right the two agree bit for bit.  Exact
** while the product neither overflows nor underflows (Boldo, "Pitfalls
** of a full floating-point proof", IJCAR 2006: the exponents sum to at
** least -969); the split itself would overflow past 2^995, so a larger
** factor hands 2^512 to the other, which leaves the product as it was.
** The factors are taken larger first (then by value), so that b*a is
** computed as a*b, also where the error rounds (subnormal products).
*/
static inline double ray__product_error(double a, double b, double p)
{
    const double split = 134217729.0;              /* 2^27 + 1 */
    double ca, cb, ah, al, bh, bl;

    if (fabs(a) < fabs(b) || (fabs(a) == fabs(b) && a < b)) {
        double t = a;
        a = b;
        b = t;
    }
    if (fabs(a) > 0x1p995) {                      /* |a| >= |b| */
        a *= 0x1p-512;
        b *= 0x1p512;
    }
    ca = split * a;
    ah = ca - (ca - a);
    al = a - ah;
    cb = split * b;
    bh = cb - (cb - b);
    bl = b - bh;
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

/*
** a*b - c*d with one rounding's worth of error: the products' rounding
** errors e1 = a*b - p1 and e2 = c*d - p2 are exact doubles
** (ray__product_error above: the same everywhere), and added back:
**
**     p1 = fl(a*b), p2 = fl(c*d), e1 = a*b - p1, e2 = c*d - p2,
**     result = fl(fl(p1 - p2) + fl(e1 - e2)).
**
** This is the symmetric form of Cornea, Harrison and Tang ("Scientific
** Computing on Itanium-based Systems", 2002), not Kahan's (pbrt-v4's
** DifferenceOfProducts, which rounds c*d first and is not symmetric in its
** two products).  Error, with u = 2^-53 and E = a*b - c*d (Jeannerod,
** Louvet, Muller, "Further analysis of Kahan's algorithm for the accurate
** computation of 2x2 determinants", Math. Comp. 82, 2013, do the same
** kind of case split):
**   - p1, p2 of one sign within a factor 2 of each other: p1 - p2 is
**     exact (Sterbenz), so the error is that of the two last roundings,
**     at most u |E| + u^2 (|ab| + |cd|), |e1 - e2| <= u (|ab| + |cd|);
**   - otherwise |p1 - p2| >= (|p1| + |p2|) / 4 and |e1 - e2| <= 4 u
**     |p1 - p2|: three roundings of quantities within 1 + 5u of |E|,
**     at most 2 u |E| (1 + O(u)).
** So |error| <= 2u |E| + u^2 (|ab| + |cd|): relative accuracy however much
** a*b and c*d cancel (the plain fl(fl(ab) - fl(cd)) has absolute error up
** to u (|ab| + |cd|) + u |E|, unbounded relative to E).  And the sign is
** E's or zero (in the first case by the monotonicity of rounding, in the
** second as the error is below |E|).  Products or errors in the subnormal
** range lose these bounds (the error terms round); libray's callers keep
** a fallback for that range.
**
** Exactly antisymmetric: ray__diff_of_products(c, d, a, b) swaps p1 with
** p2 and e1 with e2, and fl(x - y) = -fl(y - x), fl(-x + -y) = -fl(x + y)
** under round-to-nearest-even, so it returns exactly -result; and a*b =
** b*a, and ray__product_error takes b, a as a, b.  So two triangles
** sharing an edge still get opposite values for it -- and, every product
** being an explicit statement, that holds even where a compiler would
** contract a*b - c*d into an FMA of its own choosing.
*/
static inline double ray__diff_of_products(double a, double b, double c,
                                           double d)
{
    double p1 = a * b, p2 = c * d;
    double e1 = ray__product_error(a, b, p1), e2 = ray__product_error(c, d, p2);

    return (p1 - p2) + (e1 - e2);
}

/* Component "at" (a byte offset, as in ray__frame) of *v: a load from a
** per-ray offset, where v3_axis would branch on the axis. */
static inline const double *v3_ptr(const ray_vec3 *v, size_t at)
{
    return (const double *)(const void *)((const char *)v + at);
}

static inline double v3_at(const ray_vec3 *v, size_t at)
{
    return *v3_ptr(v, at);
}

/*
** x rounded to a float no larger (down) or no smaller (up) than it, so a
** double interval becomes a float one that still contains it: the
** nearest float, moved one step of its IEEE-754 bit pattern (which orders
** like the value within a sign: an inline nextafterf) when it fell on the
** wrong side.  Branch-free, since the side is a coin toss for the ray
** origins of a traversal: the step is +1 or -1 on the bits by the sign,
** times 0 or 1.  A zero needs no special case: only -0 steps down (to
** -2^-149: an x below +0 rounds to -0) and only +0 steps up.  NaN stays
** NaN (both comparisons fail).
*/
static inline float ray__float_down(double x)
{
    float f = (float)x;
    uint32_t u, need = (double)f > x;

    memcpy(&u, &f, sizeof u);
    u += need * (2u * (u >> 31) - 1u);     /* f > 0: -1; f < 0 or -0: +1 */
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline float ray__float_up(double x)
{
    float f = (float)x;
    uint32_t u, need = (double)f < x;

    memcpy(&u, &f, sizeof u);
    u += need * (1u - 2u * (u >> 31));     /* f >= +0: +1; f < 0: -1 */
    memcpy(&f, &u, sizeof f);
    return f;
}

/*
** nextafter(x, HUGE_VAL) and nextafter(x, -HUGE_VAL), inline: libm's are
** calls in the hot path (ray_spawn steps every origin component; 1.1 % of
** the Whitted render, issue 35).  The same bits for every input (C99
** 7.12.11.3 and F.9.8.3; glibc's s_nextafter.c step the bit pattern as
** here): a finite non-zero x is one step of its IEEE-754 bit pattern away
** (the pattern orders like the magnitude within a sign, so +1 moves away
** from zero, -1 toward it: -2^-1074 up is -0, as in glibc, and DBL_MAX up
** is +Inf, -Inf up is -DBL_MAX); a zero of either sign goes to the
** smallest subnormal of the direction's sign; +Inf up (and -Inf down)
** stays, nextafter's x == y case; a NaN is x + y, as glibc returns it.
** tests/check_numerics.c compares both with libm's on the edge cases and
** on random bit patterns.
*/
static inline double ray__next_up(double x)
{
    uint64_t bits;

    if (x != x)
        return x + HUGE_VAL;
    if (x == HUGE_VAL)
        return x;
    if (x == 0)
        return 0x1p-1074;
    memcpy(&bits, &x, sizeof bits);
    bits += x > 0 ? 1 : (uint64_t)-1;
    memcpy(&x, &bits, sizeof x);
    return x;
}

static inline double ray__next_down(double x)
{
    uint64_t bits;

    if (x != x)
        return x + -HUGE_VAL;
    if (x == -HUGE_VAL)
        return x;
    if (x == 0)
        return -0x1p-1074;
    memcpy(&bits, &x, sizeof bits);
    bits += x < 0 ? 1 : (uint64_t)-1;
    memcpy(&x, &bits, sizeof x);
    return x;
}

/*
** fmax(a, b) and fmin(a, b), inline (libm's are calls: 1.4 % of the
** Whitted render, issue 35).  A NaN operand gives the other one (C99
** F.9.9.2), two NaNs the first; otherwise the larger (smaller).  Two
** equal operands give b, so +0 and -0 give b, as glibc's x86-64 fmax and
** fmin do (sysdeps/x86_64/fpu/s_fmax.S: maxsd keeps its second operand
** on a tie); C99 leaves the sign of that zero open.  Used only where
** the operands cannot be zeros of opposite signs or where the sign of a
** zero result is not seen, so the answers are libm's on every platform.
*/
static inline double ray__fmax(double a, double b)
{
    return a > b || b != b ? a : b;
}

static inline double ray__fmin(double a, double b)
{
    return a < b || b != b ? a : b;
}

/*
** 2^k for k in [-1074, 1023] (a subnormal below -1022), from its bits.
** x * ray__pow2(k) is ldexp(x, k), bit for bit: the exact x 2^k rounded
** once (exact unless it leaves the normal range), where ldexp is a libm
** call that costs more than the whole multiplication.
*/
static inline double ray__pow2(int k)
{
    uint64_t bits = k >= -1022 ? (uint64_t)(k + 1023) << 52
                               : (uint64_t)1 << (k + 1074);
    double x;

    memcpy(&x, &bits, sizeof x);
    return x;
}

/* The binary exponent of finite x > 0 (2^e <= x < 2^(e+1)), clamped to
** [-1022, 1023]: a subnormal gives -1022.  With ray__pow2, the scaling
** of a ray's direction (the traversal's) or of a query point (the
** closest-point search's) by a power of two, which is exact. */
static inline int ray__exponent_of(double x)
{
    uint64_t bits;
    int e;

    memcpy(&bits, &x, sizeof bits);
    e = (int)(bits >> 52 & 0x7ff) - 1023;
    return e < -1022 ? -1022 : e;
}

/* 1 when x is a float's value (what a mesh that came in as floats holds):
** within float's range, and its float converts back to x itself. */
static inline int ray__is_float(double x)
{
    return fabs(x) <= (double)FLT_MAX && (double)(float)x == x;
}

/*
** The orthonormal tangents (t1, t2) of unit normal n, so that (t1, t2, n)
** is right-handed.  Duff, Burgess, Christensen, Hery, Kensler, Liani,
** Villemin, "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017,
** listing 3: branch-free and continuous except across n.z = 0's sign.
*/
static inline void ray__tangent_frame(ray_vec3 n, ray_vec3 *t1,
                                      ray_vec3 *t2)
{
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double b = n.x * n.y * a;

    *t1 = v3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *t2 = v3(b, sign + n.y * n.y * a, -n.y);
}

#endif /* RAY_VEC_H */
