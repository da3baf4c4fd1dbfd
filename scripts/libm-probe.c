/* SPDX-License-Identifier: MIT */
/*
** libm-probe.c -- what the C runtime's math functions answer, for make
** windows-check (doc/PLATFORMS.md): each function the library calls,
** on 20000 arguments from a fixed generator, in the ranges the library
** gives them, printed as the results' bits, one line per argument.  Run
** natively and under Wine, the two outputs compared (scripts/
** windows-check.sh) say how often, and by how many ulps, glibc's and
** MinGW's (or Wine's msvcrt's) answers differ.
**
**     libm-probe > results.txt
**     libm-probe --compare a.txt b.txt     the table of differences
**     libm-probe --markdown a.txt b.txt    the same as a Markdown table,
**                                          with what the library used
**                                          each function for
**     libm-probe --threads                 pow and exp on a new thread
**
** --threads: pow and exp on the main thread and on a thread started
** plainly (pthread_create, or _beginthreadex on Windows), in its default
** floating-point environment, how many of their results differ: none
** where threads inherit the environment (POSIX), many where the C
** runtime computes on the x87 and the main thread's precision is not a
** new thread's (MinGW; what src/core/tasks.c guards against).
*/
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#if defined(_WIN32)
#include <windows.h>
#include <process.h>
#else
#include <pthread.h>
#endif

/* xorshift64 (Marsaglia 2003): the same arguments on every platform. */
static uint64_t state = 88172645463325252ull;

static double unit(void)
{
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return (double)(state >> 11) * (1.0 / 9007199254740992.0);
}

static unsigned long long bits(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return (unsigned long long)b;
}

static const char *const names[12] = {"sin", "cos", "tan", "acos",
    "atan", "atan2", "exp", "pow", "log2", "cbrt", "hypot", "fma"};

/* What the library calls each function for (the Markdown table's last
** column); cbrt, hypot and fma are no longer called (doc/PLATFORMS.md,
** "Same answers everywhere"). */
static const char *const uses[12] = {
    "sampling directions, ray cones' texture scale",
    "sampling directions, ray cones' texture scale",
    "the camera's field of view", "spheres' and blobs' texture coordinates",
    "the ray cone's spread", "texture coordinates", "glass's absorption",
    "Phong's highlight, sRGB encoding and decoding",
    "the mip level of a texture lookup", "(no longer used)",
    "(no longer used)", "(no longer used)"};

/* The compared outputs' figures, as text or as a Markdown table. */
static void print_table(int markdown, long lines, const char *pa,
                        const char *pb, const long *differ,
                        const unsigned long long *most, const int *signs)
{
    int k;

    if (!markdown)
        printf("libm-probe: %ld arguments a function, %s against %s:\n",
               lines, pb, pa);
    else
        printf("| function | results that differ (of %ld) | by at most | "
               "used for |\n|---|---|---|---|\n", lines);
    for (k = 0; k < 12; k++)
        if (!markdown)
            printf("  %-6s %5ld differ (%5.2f%%), at most %llu ulp%s%s\n",
                   names[k], differ[k],
                   100.0 * (double)differ[k] / (double)lines, most[k],
                   most[k] == 1 ? "" : "s", signs[k] ? ", and in sign" : "");
        else
            printf("| `%s` | %.2f%% | %llu ulp%s%s | %s |\n", names[k],
                   100.0 * (double)differ[k] / (double)lines, most[k],
                   most[k] == 1 ? "" : "s", signs[k] ? ", and in sign" : "",
                   uses[k]);
}

/* Compare two outputs: per function, the arguments whose results differ
** and the most ulps apart (the bit patterns' distance: results of one
** sign; a sign change counts as "sign"). */
static int compare(const char *pa, const char *pb, int markdown)
{
    FILE *fa = fopen(pa, "r"), *fb = fopen(pb, "r");
    char la[512], lb[512];
    long differ[12] = {0}, lines = 0;
    unsigned long long most[12] = {0};
    int k, signs[12] = {0};

    if (fa == NULL || fb == NULL || !fgets(la, sizeof la, fa) ||
        !fgets(lb, sizeof lb, fb)) {
        fprintf(stderr, "libm-probe: cannot read %s and %s\n", pa, pb);
        return 2;
    }
    while (fgets(la, sizeof la, fa) && fgets(lb, sizeof lb, fb)) {
        const char *a = la, *b = lb;
        lines++;
        for (k = 0; k < 12; k++) {
            unsigned long long x, y;
            int na = 0, nb = 0;
            if (sscanf(a, "%llx%n", &x, &na) != 1 ||
                sscanf(b, "%llx%n", &y, &nb) != 1) {
                fprintf(stderr, "libm-probe: line %ld unreadable\n", lines);
                return 2;
            }
            a += na;
            b += nb;
            if (x == y)
                continue;
            differ[k]++;
            if ((x >> 63) != (y >> 63))
                signs[k] = 1;
            else if ((x > y ? x - y : y - x) > most[k])
                most[k] = x > y ? x - y : y - x;
        }
    }
    print_table(markdown, lines, pa, pb, differ, most, signs);
    fclose(fa);
    fclose(fb);
    return 0;
}

#define THREAD_ARGS 20000

/* pow and exp of THREAD_ARGS arguments into out[0 .. 2 THREAD_ARGS). */
static void pow_exp(double *out)
{
    uint64_t saved = state;
    int i;

    state = 88172645463325252ull;
    for (i = 0; i < THREAD_ARGS; i++) {
        double a = unit() * 4, b = unit() * 3;
        out[2 * i] = pow(a, b);
        out[2 * i + 1] = exp(-a * 4);
    }
    state = saved;
}

static double on_main[2 * THREAD_ARGS], on_thread[2 * THREAD_ARGS];

#if defined(_WIN32)
static unsigned __stdcall thread_main(void *arg)
{
    pow_exp(arg);
    return 0;
}
#else
static void *thread_main(void *arg)
{
    pow_exp(arg);
    return NULL;
}
#endif

static int threads(void)
{
    long differ[2] = {0, 0};
    int i;
#if defined(_WIN32)
    HANDLE h = (HANDLE)_beginthreadex(NULL, 0, thread_main, on_thread, 0,
                                      NULL);
    if (h == 0)
        return 2;
    WaitForSingleObject(h, INFINITE);
    CloseHandle(h);
#else
    pthread_t t;
    if (pthread_create(&t, NULL, thread_main, on_thread) != 0)
        return 2;
    pthread_join(t, NULL);
#endif
    pow_exp(on_main);
    for (i = 0; i < 2 * THREAD_ARGS; i++)
        differ[i % 2] += memcmp(&on_main[i], &on_thread[i], sizeof(double)) != 0;
    printf("libm-probe: on a new thread, %ld of %d pow results and %ld of "
           "%d exp results differ from the main thread's\n", differ[0],
           THREAD_ARGS, differ[1], THREAD_ARGS);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "--compare") == 0)
        return compare(argv[2], argv[3], 0);
    if (argc == 4 && strcmp(argv[1], "--markdown") == 0)
        return compare(argv[2], argv[3], 1);
    if (argc == 2 && strcmp(argv[1], "--threads") == 0)
        return threads();
    /* The names, in the order of each line's values. */
    printf("sin cos tan acos atan atan2 exp pow log2 cbrt hypot fma\n");
    for (int i = 0; i < 20000; i++) {
        double a = unit() * 6.3 - 3.15, b = unit() * 2 - 1, c = unit() * 4;
        double d = unit() * 1.2 + 0.001, e = unit() * 100;
        double v[12];
        v[0] = sin(a);                    /* sampling angles */
        v[1] = cos(a);
        v[2] = tan(a * 0.49);             /* the camera's field of view */
        v[3] = acos(b);                   /* texture coordinates */
        v[4] = atan(b * 3);               /* the cone's spread */
        v[5] = atan2(b, c - 2);
        v[6] = exp(-c * 2);               /* glass's absorption */
        v[7] = pow(d, i % 2 ? 1.0 / 2.4 : e); /* sRGB; Phong's exponent */
        v[8] = log2(e + 1);               /* mip level */
        v[9] = cbrt(b);
        v[10] = hypot(a, b);
        v[11] = fma(a * 1e3, c * 1e3, -(a * 1e3) * (c * 1e3));
        for (int k = 0; k < 12; k++)
            printf("%016llx%c", bits(v[k]), k == 11 ? '\n' : ' ');
    }
    return 0;
}
