/* SPDX-License-Identifier: MIT */
/*
** platform_cpu.c -- ray__cpu_has_avx2 (platform.h): the CPU asked
** through cpuid and xgetbv, in the compiler's spelling of each (MSVC's
** intrinsics; GCC's and Clang's <cpuid.h> and the instruction's bytes),
** so that the test of the bits is one code for every compiler and the
** one MinGW runs under Wine is the one MSVC builds.
*/
#include "core/platform.h"

#if defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
#include <intrin.h>
#define RAY__CPUID 1
static void cpuid(unsigned leaf, unsigned sub, unsigned r[4])
{
    int v[4];
    int k;

    __cpuidex(v, (int)leaf, (int)sub);
    for (k = 0; k < 4; k++)
        r[k] = (unsigned)v[k];
}

static unsigned long long xcr0(void)
{
    return _xgetbv(0);
}
#elif (defined(__GNUC__) || defined(__clang__)) && \
    (defined(__x86_64__) || defined(__i386__))
#include <cpuid.h>
#define RAY__CPUID 1
static void cpuid(unsigned leaf, unsigned sub, unsigned r[4])
{
    __cpuid_count(leaf, sub, r[0], r[1], r[2], r[3]);
}

/* xgetbv with ecx = 0, as its bytes (0f 01 d0): assemblers older than
** the instruction know it so too (GCC's own cpuinfo.c does the same). */
static unsigned long long xcr0(void)
{
    unsigned lo, hi;

    __asm__ __volatile__(".byte 0x0f, 0x01, 0xd0"
                         : "=a"(lo), "=d"(hi) : "c"(0));
    return (unsigned long long)hi << 32 | lo;
}
#else
#define RAY__CPUID 0
#endif

/*
** AVX2 as the Intel SDM (vol. 1, 14.7.1, "Detection of Intel AVX2")
** detects it: cpuid leaf 7 exists; leaf 1 has OSXSAVE (ecx bit 27: the
** OS enabled xgetbv) and AVX (ecx bit 28); XCR0 has the XMM and YMM
** state (bits 1 and 2: the OS saves the registers on a context switch);
** leaf 7 subleaf 0 has AVX2 (ebx bit 5).
*/
int ray__cpu_has_avx2(void)
{
#if RAY__CPUID
    unsigned r[4];

    cpuid(0, 0, r);
    if (r[0] < 7)
        return 0;
    cpuid(1, 0, r);
    if (!(r[2] >> 27 & 1) || !(r[2] >> 28 & 1))
        return 0;
    if ((xcr0() & 6) != 6)
        return 0;
    cpuid(7, 0, r);
    return (int)(r[1] >> 5 & 1);
#else
    return 0;
#endif
}
