/* SPDX-License-Identifier: MIT */
/*
** selfhit.c -- acne per primitive kind: secondary rays (shadow,
** reflection, refraction) spawned with ray_spawn / ray_spawn_to that hit
** the surface they leave, counted by tests/selfhit.h over every placement
** (axis-aligned, rotated) and offset (0, 0.5, 1e5, 1e6), through the bare
** functions and through a one-primitive scene.  tests/check_selfhit.c
** asserts that every count is 0; this prints them, with the time per
** camera ray (its three secondary rays included).
**
**     selfhit            (prints Markdown; BENCH_QUICK=1 for fewer rays)
*/
#include <stdio.h>

#include "bench.h"
#include "selfhit.h"

static int slow_kind(sh_kind k)
{
    return k == SH_IMPLICIT || k == SH_BEZIER;
}

int main(void)
{
    int level = bench_level();
    int k, path;

    printf("### Self-hits per primitive kind\n\n"
           "Camera rays at steep (20-80 deg) and grazing (0.05-3 deg) "
           "angles, 2 placements x 4 offsets (0, 0.5, 1e5, 1e6); per hit a "
           "shadow, a reflection and a refraction ray from ray_spawn / "
           "ray_spawn_to.  A self-hit: the ray hits the surface it leaves "
           "(flat kinds: anywhere; curved: closer than tests/selfhit.h's "
           "SH_NEAR).  Every count should be 0.\n\n"
           "| kind | path | camera hits | shadow | reflection | refraction "
           "| worst offset | ns per hit |\n"
           "|---|---|---|---|---|---|---|---|\n");
    for (k = 0; k < SH_KINDS; k++)
        for (path = 0; path < 2; path++) {
            int n = level == BENCH_SMOKE ? 4
                    : slow_kind((sh_kind)k) ? (level ? 100 : 400)
                                            : (level ? 1000 : 10000);
            sh_counts sum = {0, 0, 0, 0};
            double worst_off = 0, t0 = now_seconds(), t;
            long worst = -1;
            int rot, o;
            for (rot = 0; rot < 2; rot++)
                for (o = 0; o < SH_OFFSETS; o++) {
                    sh_prim p;
                    sh_counts c;
                    ray_scene *s = NULL;
                    long self;
                    sh_place(&p, (sh_kind)k, sh_offsets[o], rot);
                    if (path == 1 && (s = sh_scene(&p)) == NULL) {
                        fprintf(stderr, "selfhit: scene failed\n");
                        return 1;
                    }
                    sh_run(&p, s, n, 1234 + (uint64_t)o, &c);
                    ray_scene_free(s);
                    sum.rays += c.rays, sum.shadow += c.shadow;
                    sum.reflect += c.reflect, sum.refract += c.refract;
                    self = c.shadow + c.reflect + c.refract;
                    if (self > worst)
                        worst = self, worst_off = sh_offsets[o];
                }
            t = now_seconds() - t0;
            printf("| %s | %s | %ld | %ld | %ld | %ld | %s | %.0f |\n",
                   sh_kind_name[k], path ? "scene" : "bare", sum.rays,
                   sum.shadow, sum.reflect, sum.refract,
                   worst > 0 ? (worst_off == 0 ? "0" : worst_off == 0.5 ? "0.5"
                                : worst_off == 1e5 ? "1e5" : "1e6") : "-",
                   sum.rays ? 1e9 * t / (double)sum.rays : 0.0);
        }
    printf("\n");
    return 0;
}
