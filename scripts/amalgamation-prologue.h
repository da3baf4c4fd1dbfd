/* SPDX-License-Identifier: MIT */
/*
** libray.c -- libray @VERSION@ in one file, the amalgamation: written by
** "make amalgamation" (scripts/amalgamate.c) from the sources in src/, so
** do not edit it, edit them.  With ray.h beside it, the PNG calls where
** pkg-config finds libpng (doc/EMBEDDING.md):
**
**   png=$(pkg-config --exists libpng && echo "-DRAY_PNG=1 $(pkg-config --cflags libpng)")
**   cc -std=c99 -O2 $png -c libray.c
**   cc -I. app.c libray.o ${png:+$(pkg-config --libs libpng)} -lm -lpthread
**
** Switches, each a -D on the command line (doc/EMBEDDING.md):
**   RAY_PNG=1    ray_write_png and ray_image_load_png on libpng (its header
**                on the include path, e.g. $(pkg-config --cflags libpng);
**                link -lpng).  RAY_PNG=0, the default: no dependency, and
**                those two calls return RAY_ENOTSUP, as make PNG=0 builds.
**   RAY_NO_SIMD  the portable C paths instead of the SSE box tests.
**   (-mavx2)     not a macro but the compiler's flag: the whole library is
**                then built for AVX2 (eight-wide box tests and the ray
**                packets of ray_intersect_batch), and needs a CPU with AVX2.
**                Without it, the library's AVX2 copies of the queries
**                and of the refit's leaf (src/query/intersect_avx2.c,
**                src/scene/refit_avx2.c, which the Makefile and CMake
**                build with -mavx2 alone) are the baseline code once
**                more: the same answers, bit for bit, at the baseline's
**                speed.
**   RAY_AMALGAMATION_INTERNALS  keeps the internal ray__* functions
**                external (libray's own tests link them); by default they
**                are static.
**
** Floating point: the library needs a*b+c rounded twice, never fused into
** one FMA (watertight triangles, ray-numerics(7)).  The pragmas below say
** so to GCC (in its GNU modes too, where -ffp-contract=fast is the
** default), Clang and MSVC, in place of -ffp-contract=off and /fp:precise;
** -ffast-math and /fp:fast are refused.
*/
#ifdef __FAST_MATH__
#error "libray must not be built with -ffast-math (ray-numerics(7))"
#endif
#ifdef _M_FP_FAST
#error "libray must not be built with /fp:fast (ray-numerics(7))"
#endif
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#elif defined(_MSC_VER)
#pragma fp_contract(off)
#else
#pragma STDC FP_CONTRACT OFF
#endif

/* One file sees every file's names: a local variable of one source may
** share its name with a type or a static of a header that source never
** included (src/prim/parametric_search.h's "job").  -Wshadow warns of
** that here only; the sources, compiled one by one, are held to it by the
** Makefile. */
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wshadow"
#endif

/* What the Makefile gives every source with -D.  Feature-test macros
** must come before the first system header, so a source's own ones
** belong here too: Apple's <unistd.h> hides _SC_NPROCESSORS_ONLN under
** _POSIX_C_SOURCE alone. */
#if !defined(_POSIX_C_SOURCE) && !defined(_WIN32)
#define _POSIX_C_SOURCE 200809L
#endif
#if defined(__APPLE__) && !defined(_DARWIN_C_SOURCE)
#define _DARWIN_C_SOURCE 1
#endif
#if defined(__linux__) && !defined(_GNU_SOURCE)
#define _GNU_SOURCE 1             /* madvise, MADV_HUGEPAGE, mremap */
#endif
#ifndef RAY_BUILD
#define RAY_BUILD 1
#endif
#ifndef RAY_PNG
#define RAY_PNG 0
#endif

/* The internal functions called across the library's files. */
#if defined(RAY_AMALGAMATION_INTERNALS)
#define RAY__STATIC
#elif defined(__GNUC__)
#define RAY__STATIC static __attribute__((unused))
#else
#define RAY__STATIC static
#endif
