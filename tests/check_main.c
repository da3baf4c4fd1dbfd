/* SPDX-License-Identifier: MIT */
/*
** check_main.c -- runs every suite.  Fork mode stays on (Check's default),
** so a crash fails one test instead of the run.
*/
#include <stdlib.h>

#include "tests.h"

int main(void)
{
    SRunner *sr = srunner_create(version_suite());
    int failed;

    srunner_add_suite(sr, sphere_suite());
    srunner_add_suite(sr, triangle_suite());
    srunner_add_suite(sr, plane_suite());
    srunner_add_suite(sr, polygon_suite());
    srunner_add_suite(sr, barycentric_suite());
    srunner_add_suite(sr, png_suite());
    srunner_add_suite(sr, optics_suite());
    srunner_add_suite(sr, scene_suite());
    srunner_add_suite(sr, trace_suite());
    srunner_add_suite(sr, render_suite());
    srunner_add_suite(sr, bvh_suite());
    srunner_add_suite(sr, obj_suite());
    srunner_add_suite(sr, effects_suite());
    srunner_add_suite(sr, numerics_suite());
    srunner_add_suite(sr, implicit_suite());
    srunner_add_suite(sr, parametric_suite());
    srunner_add_suite(sr, texture_suite());
    srunner_add_suite(sr, bpt_suite());
    srunner_add_suite(sr, surfaces_suite());
    srunner_add_suite(sr, selfhit_suite());
    srunner_add_suite(sr, null_suite());
    srunner_add_suite(sr, defaults_suite());
    srunner_add_suite(sr, errmsg_suite());
    srunner_add_suite(sr, box_suite());
    srunner_add_suite(sr, direct_suite());
    srunner_add_suite(sr, capsule_suite());
    srunner_add_suite(sr, games_suite());
    srunner_add_suite(sr, instance_suite());
    srunner_add_suite(sr, dynamic_suite());
    srunner_add_suite(sr, user_suite());
    srunner_add_suite(sr, closest_suite());
    srunner_add_suite(sr, batch_suite());
    srunner_add_suite(sr, lazy_suite());
    srunner_add_suite(sr, cones_suite());
    srunner_add_suite(sr, caustics_suite());
    srunner_add_suite(sr, cones_caustics_hard_suite());
    srunner_add_suite(sr, scheduler_suite());
    srunner_add_suite(sr, platform_suite());
    srunner_run_all(sr, CK_NORMAL);
    failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
