/* SPDX-License-Identifier: MIT */
/*
** fuzz_obj.c -- the examples' OBJ reader (examples/obj.h) on any bytes,
** and what it reads fed to a scene: it promises an error naming the line,
** never a crash, and a mesh that ray_scene_add_mesh takes.
**
** Checked: obj_parse returns 0 or -1; on -1 the message is a "line N: "
** string and the mesh is empty; on 0 every index is below the vertex
** count, every number finite, and ray_scene_add_mesh accepts the mesh
** (RAY_OK, or RAY_ENOMEM) and commits; obj_free leaves nothing.
*/
#include "fuzz.h"
#include "obj.h"

static int all_finite(const double *x, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

static void black(void *ud, ray_ctx *ctx, const ray_shade_args *args,
                  ray_rgb *out)
{
    (void)ud, (void)ctx, (void)args, (void)out;
}

static void check_mesh(const obj_mesh *m)
{
    size_t i;
    ray_scene *scene;
    ray_material mat;
    ray_mesh rm = obj_as_ray_mesh(m);
    int rc;

    FUZZ_CHECK(m->vertex_count > 0 && m->triangle_count > 0,
               "obj_parse: a mesh has triangles");
    for (i = 0; i < 3 * m->triangle_count; i++)
        FUZZ_CHECK(m->indices[i] < m->vertex_count, "obj_parse: index range");
    FUZZ_CHECK(all_finite((const double *)m->vertices, 3 * m->vertex_count),
               "obj_parse: finite vertices");
    if (m->normals != NULL)
        FUZZ_CHECK(all_finite((const double *)m->normals,
                              3 * m->vertex_count), "obj_parse: normals");
    if (m->texcoords != NULL)
        FUZZ_CHECK(all_finite(m->texcoords, 2 * m->vertex_count),
                   "obj_parse: texture coordinates");
    if (ray_scene_new(&scene, NULL, NULL) != RAY_OK)
        return;
    mat.shade = black;
    mat.ud = NULL;
    mat.effects = 0;
    mat.scatter = NULL;
    rc = ray_scene_add_material(scene, &mat, NULL);
    FUZZ_CHECK(rc == RAY_OK, "ray_scene_add_material");
    rc = ray_scene_add_mesh(scene, &rm, 0, NULL);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM,
               "ray_scene_add_mesh takes what obj_parse reads");
    rc = ray_scene_commit(scene);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM, "ray_scene_commit");
    ray_scene_free(scene);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    obj_mesh m;
    char err[256];
    int rc;

    fuzz_sentinel(err, sizeof err);
    rc = obj_parse((const char *)data, size, &m, err, sizeof err);
    FUZZ_CHECK(rc == 0 || rc == -1, "obj_parse: 0 or -1");
    if (rc != 0) {
        FUZZ_CHECK(memchr(err, '\0', sizeof err) != NULL &&
                       strncmp(err, "line ", 5) == 0,
                   "obj_parse: a message naming the line");
        FUZZ_CHECK(m.vertices == NULL && m.indices == NULL &&
                       m.normals == NULL && m.texcoords == NULL,
                   "obj_parse: nothing kept on error");
        return 0;
    }
    check_mesh(&m);
    obj_free(&m);
    return 0;
}
