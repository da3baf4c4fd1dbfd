/* SPDX-License-Identifier: MIT */
/*
** fuzz_bpt.c -- the examples' Bezier patch reader (examples/bpt.h) on any
** bytes: it promises an error naming the line, never a crash, and patches
** whose points ray_scene_add_bezier takes.
**
** Checked: bpt_parse returns 0 or -1; on -1 a "line N: " message and an
** empty result; on 0 a positive count of patches with finite control
** points, each accepted by ray_bezier_surface and ray_scene_add_bezier,
** and a ray through the first patch's box answered 1, 0 or -RAY_ELIMIT.
*/
#include "fuzz.h"
#include "bpt.h"

static void black(void *ud, ray_ctx *ctx, const ray_shade_args *args,
                  ray_rgb *out)
{
    (void)ud, (void)ctx, (void)args, (void)out;
}

/* Patches fed to a scene: at most this many (the reader allows 10^6). */
#define MAX_SCENE_PATCHES 4

static void check_patches(const bpt_patches *b)
{
    ray_scene *scene;
    ray_material mat;
    ray_parametric_surface s;
    ray_vec3 lo, hi;
    ray_ray r;
    ray_hit hit;
    size_t k;
    int c, rc;

    FUZZ_CHECK(b->count > 0 && b->patches != NULL, "bpt_parse: patches");
    for (k = 0; k < b->count; k++)
        for (c = 0; c < 16; c++)
            FUZZ_CHECK(fuzz_finite3(b->patches[k][c]),
                       "bpt_parse: finite control points");
    FUZZ_CHECK(ray_bezier_surface(b->patches[0], &s) == RAY_OK,
               "ray_bezier_surface takes what bpt_parse reads");
    /* A ray down the middle of the first patch's box. */
    bpt_bounds(b, &lo, &hi);
    r.org.x = lo.x / 2 + hi.x / 2;
    r.org.y = lo.y / 2 + hi.y / 2;
    r.org.z = hi.z + 1;
    r.dir.x = r.dir.y = 0;
    r.dir.z = -1;
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_parametric(&r, &s, &hit);
    FUZZ_CHECK(rc == 1 || rc == 0 || rc == -RAY_ELIMIT,
               "ray_parametric: status on a read patch");
    if (rc == 1)
        fuzz_check_hit(&r, &hit, 0, "ray_parametric");
    else
        FUZZ_CHECK(fuzz_untouched(&hit, sizeof hit), "ray_parametric");
    if (ray_scene_new(&scene, NULL, NULL) != RAY_OK)
        return;
    mat.shade = black;
    mat.ud = NULL;
    mat.effects = 0;
    mat.scatter = NULL;
    FUZZ_CHECK(ray_scene_add_material(scene, &mat, NULL) == RAY_OK,
               "ray_scene_add_material");
    for (k = 0; k < b->count && k < MAX_SCENE_PATCHES; k++) {
        rc = ray_scene_add_bezier(scene, b->patches[k], 0, NULL);
        FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM,
                   "ray_scene_add_bezier takes what bpt_parse reads");
    }
    rc = ray_scene_commit(scene);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM, "ray_scene_commit");
    ray_scene_free(scene);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bpt_patches b;
    char err[256];
    int rc;

    fuzz_sentinel(err, sizeof err);
    rc = bpt_parse((const char *)data, size, &b, err, sizeof err);
    FUZZ_CHECK(rc == 0 || rc == -1, "bpt_parse: 0 or -1");
    if (rc != 0) {
        FUZZ_CHECK(memchr(err, '\0', sizeof err) != NULL &&
                       strncmp(err, "line ", 5) == 0,
                   "bpt_parse: a message naming the line");
        FUZZ_CHECK(b.patches == NULL && b.count == 0,
                   "bpt_parse: nothing kept on error");
        return 0;
    }
    check_patches(&b);
    bpt_free(&b);
    return 0;
}
