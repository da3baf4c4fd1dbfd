/* SPDX-License-Identifier: MIT */
/*
** sdf.c -- bake a model's signed distance field with ray_distance_grid
** and write a slice through it as a picture: inside and outside in two
** colours, a contour every 1/16 of the model's size, the surface white.
**
**     sdf [out.png]
**
** The model is data/bunny.obj (scripts/fetch-bunny.sh) when it is there,
** or the file RAY_SDF_MODEL names; else a generated icosphere (a closed
** mesh), and the program says so.  It also bakes the whole 32^3 field,
** to show what a 3-D grid costs.  A model that is not closed (a hole)
** is answered by the winding number, slower: the program says that too.
*/
#include <stdlib.h>

#include "common.h"
#include "obj.h"

#define SIDE 256u                 /* the slice's pixels */
#define GRID 32u                  /* the 3-D field's samples per axis */

/* An icosphere of radius 1: the icosahedron with every triangle split
** in four "level" times, midpoints pushed out to the sphere and shared
** through a search of the edges made so far (closed: every edge shared). */
typedef struct ico {
    ray_vec3 v[2562];             /* 10 4^4 + 2, for level 4 */
    unsigned t[3 * 5120];
    unsigned nv, nt;
    unsigned edge[3 * 7680];      /* lo, hi, midpoint */
    unsigned ne;
} ico;

static unsigned midpoint(ico *m, unsigned a, unsigned b)
{
    unsigned lo = a < b ? a : b, hi = a < b ? b : a, i;
    ray_vec3 p;
    double l;

    for (i = 0; i < m->ne; i++)
        if (m->edge[3 * i] == lo && m->edge[3 * i + 1] == hi)
            return m->edge[3 * i + 2];
    p = vec((m->v[a].x + m->v[b].x) / 2, (m->v[a].y + m->v[b].y) / 2,
            (m->v[a].z + m->v[b].z) / 2);
    l = sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    m->v[m->nv] = vec(p.x / l, p.y / l, p.z / l);
    m->edge[3 * m->ne] = lo;
    m->edge[3 * m->ne + 1] = hi;
    m->edge[3 * m->ne + 2] = m->nv;
    m->ne++;
    return m->nv++;
}

static void icosphere(ico *m, int level)
{
    static const unsigned f20[60] = {
        0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
        11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
        3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    const double g = 1.6180339887498949;
    const double base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0},
                                {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                {0, -1, -g}, {0, 1, -g}, {g, 0, -1},
                                {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    unsigned i, *next = malloc(sizeof m->t);
    int lv;

    m->nv = 12;
    m->nt = 20;
    for (i = 0; i < 12; i++) {
        double l = sqrt(1 + g * g);
        m->v[i] = vec(base[i][0] / l, base[i][1] / l, base[i][2] / l);
    }
    memcpy(m->t, f20, sizeof f20);
    for (lv = 0; lv < level && next != NULL; lv++) {
        m->ne = 0;
        for (i = 0; i < m->nt; i++) {
            unsigned a = m->t[3 * i], b = m->t[3 * i + 1], c = m->t[3 * i + 2];
            unsigned ab = midpoint(m, a, b), bc = midpoint(m, b, c);
            unsigned ca = midpoint(m, c, a), *o = next + 12 * i, k;
            const unsigned q[12] = {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca};
            for (k = 0; k < 12; k++)
                o[k] = q[k];
        }
        m->nt *= 4;
        memcpy(m->t, next, 3 * m->nt * sizeof *next);
    }
    free(next);
}

/* A pixel's colour from its signed distance d at contour spacing h and
** pixel size px: orange outside, blue inside, darker on the contours,
** white within a pixel of the surface. */
static void shade(double d, double h, double px, float *out)
{
    double f = fabs(d) / h, line = fabs(f - floor(f + 0.5)) * h;
    double k = line < px ? 0.55 : 1.0;

    if (fabs(d) < px) {
        out[0] = out[1] = out[2] = 1;
        return;
    }
    out[0] = (float)(k * (d < 0 ? 0.10 : 0.95));
    out[1] = (float)(k * (d < 0 ? 0.35 : 0.55));
    out[2] = (float)(k * (d < 0 ? 0.80 : 0.15));
}

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "sdf", .output_default = "sdf.png", .width = SIDE,
        .height = SIDE,
        .what = "Bakes the signed distance field of the bunny (or an "
                "icosphere) and writes a slice through it."};
    static ico sphere;
    example_args args;
    const char *path = getenv("RAY_SDF_MODEL");
    ray_distance_grid_options opt = {0};
    ray_scene *scene;
    ray_mesh mesh;
    obj_mesh obj;
    ray_vec3 lo, hi, centre, a, b;
    double diag, t0;
    float *slice, *field, *rgb;
    char err[600];
    unsigned i;
    int rc = example_start(&cli, argc, argv, &args), have_obj = 0;

    if (rc != 0)
        return rc;
    if (path == NULL)
        path = "data/bunny.obj";
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    if (obj_load(path, &obj, err, sizeof err) == 0) {
        have_obj = 1;
        obj_bounds(&obj, &lo, &hi, &centre, &diag);
        mesh = obj_as_ray_mesh(&obj);
        printf("sdf: %s: %zu triangles\n", path, obj.triangle_count);
    } else {
        icosphere(&sphere, 3);
        memset(&mesh, 0, sizeof mesh);
        mesh.vertices = sphere.v;
        mesh.vertex_count = sphere.nv;
        mesh.indices = sphere.t;
        mesh.triangle_count = sphere.nt;
        lo = vec(-1, -1, -1);
        hi = vec(1, 1, 1);
        centre = vec(0, 0, 0);
        diag = sqrt(12.0);
        printf("sdf: no %s (scripts/fetch-bunny.sh fetches it): a generated "
               "icosphere of %u triangles instead\n", path, sphere.nt);
    }
    check(ray_scene_add_mesh(scene, &mesh, RAY_NO_MATERIAL, NULL),
          "ray_scene_add_mesh");
    check(ray_scene_commit(scene), "ray_scene_commit");
    if (have_obj)
        obj_free(&obj);
    if (ray_contains(scene, NULL, 0, NULL, NULL) == -RAY_EDEGENERATE) {
        printf("sdf: the model is not closed: its inside is the winding "
               "number's (slower)\n");
        opt.contains.flags = RAY_CONTAINS_WINDING;
    }
    /* The box grown by a tenth of the diagonal each way, and the slice
    ** through the centre at constant z. */
    a = vec(lo.x - 0.1 * diag, lo.y - 0.1 * diag, centre.z);
    b = vec(hi.x + 0.1 * diag, hi.y + 0.1 * diag, centre.z);
    slice = malloc(SIDE * SIDE * sizeof *slice);
    field = malloc(GRID * GRID * GRID * sizeof *field);
    rgb = malloc(3 * SIDE * SIDE * sizeof *rgb);
    if (slice == NULL || field == NULL || rgb == NULL) {
        fprintf(stderr, "sdf: out of memory\n");
        return 1;
    }
    t0 = now_seconds();
    check(ray_distance_grid(scene, vec(a.x, a.y, lo.z - 0.1 * diag),
                            vec(b.x, b.y, hi.z + 0.1 * diag), GRID, GRID,
                            GRID, &opt, field), "ray_distance_grid");
    printf("sdf: the %u^3 field in %.3f s\n", GRID, now_seconds() - t0);
    t0 = now_seconds();
    check(ray_distance_grid(scene, a, b, SIDE, SIDE, 1, &opt, slice),
          "ray_distance_grid");
    printf("sdf: the %u x %u slice in %.3f s\n", SIDE, SIDE,
           now_seconds() - t0);
    /* Rows top to bottom: y decreasing. */
    for (i = 0; i < SIDE * SIDE; i++) {
        unsigned x = i % SIDE, y = SIDE - 1 - i / SIDE;
        shade((double)slice[y * SIDE + x], diag / 16, (b.x - a.x) / SIDE,
              rgb + 3 * i);
    }
    rc = example_write_png(&args, rgb);
    free(slice);
    free(field);
    free(rgb);
    ray_scene_free(scene);
    return rc;
}
