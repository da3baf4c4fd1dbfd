/* SPDX-License-Identifier: MIT */
/*
** numerics.c -- the stability suite's hard cases measured, naive against
** robust, on the same inputs (tests/hardcases.h; tests/check_numerics.c
** asserts the bounds).  Prints Markdown; asserts nothing.
*/
#include <stdio.h>

#include "bench.h"
#include "hardcases.h"

int main(void)
{
    static const double radii[] = {1e-2, 1.0}, dists[] = {1e4, 1e6};
    ray_vec3 centres[3];
    int level = bench_level(), i, j, k;
    long rays = level == BENCH_SMOKE ? 200 : level ? 20000 : 125000;
    int grid = level == BENCH_SMOKE ? 21 : 201;

    centres[0] = v3(0, 0, 0);
    centres[1] = v3(1e5, 1e5, 1e5);
    centres[2] = v3(148376, 1234, -223423);
    printf("## Hard cases: naive against robust\n\n");
    printf("Sphere far from the ray origin: %dx%d orthographic rays over "
           "the silhouette; wrong hit/miss, and the largest error of t in "
           "ulps, against long double.\n\n", grid, grid);
    printf("| radius | distance | naive wrong | naive max ulps | robust wrong "
           "| robust max ulps |\n|---|---|---|---|---|---|\n");
    for (i = 0; i < 2; i++)
        for (j = 0; j < 2; j++) {
            hc_sphere_result n = hc_sphere_far(radii[i], dists[j], grid, 1);
            hc_sphere_result r = hc_sphere_far(radii[i], dists[j], grid, 0);
            printf("| %g | %g | %ld of %ld | %.3g | %ld | %.3g |\n", radii[i],
                   dists[j], n.wrong, n.rays, n.max_ulps, r.wrong, r.max_ulps);
        }
    printf("\nHuge sphere as a ground (radius 1e6), camera at height h, rays "
           "1 to 1e-3 below the horizon: largest relative error of t (for "
           "scale: the sphere's own coordinates are quantised at ulp(1e6) = "
           "1.2e-10, so at h = 1e-6 a relative error below 1e-4 is below "
           "that quantum).\n\n");
    printf("| h | naive | robust |\n|---|---|---|\n");
    for (k = 0; k < 3; k++) {
        double h = k == 0 ? 1.0 : (k == 1 ? 1e-3 : 1e-6);
        printf("| %g | %.3g | %.3g |\n", h, hc_ground(1e6, h, 1),
               hc_ground(1e6, h, 0));
    }
    printf("\nClosed meshes, rays from inside aimed exactly at vertices and at "
           "points of edges (%ld each): leaks (rays that hit nothing).\n\n",
           rays);
    printf("| mesh | centre | aimed at | float Cramer | double Cramer | "
           "watertight |\n|---|---|---|---|---|---|\n");
    for (k = 0; k < 3; k++) {
        hc_mesh meshes[2];
        const char *names[2] = {"cube (12)", "icosphere (320)"};
        int m, e;
        meshes[0] = hc_cube(centres[k]);
        meshes[1] = hc_icosphere(centres[k], 2);
        for (m = 0; m < 2; m++)
            for (e = 0; e < 2; e++)
                printf("| %s | (%g, %g, %g) | %s | %ld | %ld | %ld |\n",
                       names[m], centres[k].x, centres[k].y, centres[k].z,
                       e ? "edges" : "vertices",
                       hc_leaks(&meshes[m], centres[k], rays, e, HC_CRAMER_FLOAT, 1),
                       hc_leaks(&meshes[m], centres[k], rays, e, HC_CRAMER, 1),
                       hc_leaks(&meshes[m], centres[k], rays, e, HC_WATERTIGHT, 1));
        hc_mesh_free(&meshes[0]);
        hc_mesh_free(&meshes[1]);
    }
    printf("\nFalse hits: rays aimed at points a relative distance outside "
           "an edge (%ld rays).\n\n| gap | float Cramer | double Cramer | "
           "watertight |\n|---|---|---|---|\n", rays);
    for (k = 0; k < 3; k++) {
        double gap = k == 0 ? 1e-6 : (k == 1 ? 1e-9 : 1e-12);
        printf("| %g | %ld | %ld | %ld |\n", gap,
               hc_false_hits(gap, rays, HC_CRAMER_FLOAT),
               hc_false_hits(gap, rays, HC_CRAMER),
               hc_false_hits(gap, rays, HC_WATERTIGHT));
    }
    printf("\nSelf-intersection: secondary rays leaving a unit sphere at "
           "distance X (%ld rays): self-hits with no offset, with a fixed "
           "offset of 1e-4 along the normal, and with ray_spawn.\n\n| X | no "
           "offset | fixed 1e-4 | ray_spawn |\n|---|---|---|---|\n", rays / 4);
    for (k = 0; k < 4; k++) {
        double X = k == 0 ? 0 : (k == 1 ? 1e3 : (k == 2 ? 1e5 : 1e6));
        printf("| %g | %ld | %ld | %ld |\n", X,
               hc_sphere_acne(X, rays / 4, HC_NO_OFFSET),
               hc_sphere_acne(X, rays / 4, HC_FIXED_EPSILON),
               hc_sphere_acne(X, rays / 4, HC_SPAWN));
    }
    printf("\nThin sheet: shadow rays from a plane toward a light through a "
           "parallel plane \"gap\" above (%ld rays): leaks (a fixed offset "
           "larger than the gap jumps over the sheet).\n\n| X | gap | no offset "
           "| fixed 1e-4 | ray_spawn |\n|---|---|---|---|---|\n", rays / 4);
    for (k = 0; k < 6; k++) {
        double X = (k % 3) == 0 ? 0 : ((k % 3) == 1 ? 1e5 : 1e6);
        double gap = k < 3 ? 1e-3 : 1e-5;
        printf("| %g | %g | %ld | %ld | %ld |\n", X, gap,
               hc_thin_sheet_leaks(X, gap, rays / 4, HC_NO_OFFSET),
               hc_thin_sheet_leaks(X, gap, rays / 4, HC_FIXED_EPSILON),
               hc_thin_sheet_leaks(X, gap, rays / 4, HC_SPAWN));
    }
    printf("\nBarycentric coordinates of points inside random triangles "
           "(%ld): largest |alpha + beta + gamma - 1|, dividing by N.N (the "
           "lecture) and by the sum of the areas (ray_barycentric).\n\n"
           "| N.N | sum of areas |\n|---|---|\n| %.3g | %.3g |\n\n", rays,
           hc_bary_drift(rays, 1), hc_bary_drift(rays, 0));
    return 0;
}
