/* SPDX-License-Identifier: MIT */
/*
** mesh.c -- indexed triangle meshes: validated, then copied into the
** scene's flat triangle array (for traversal) and, when the mesh has
** normals or texture coordinates, kept indexed for shading.
*/
#include <string.h>

#include "scene.h"

/* The arrays are there and not empty: RAY_OK, or the failure. */
static int mesh_arrays_check(ray_scene *s, const ray_mesh *m)
{
    if (m->vertices == NULL)
        return ray__fail(s, RAY_EINVAL, "vertices is NULL");
    if (m->indices == NULL)
        return ray__fail(s, RAY_EINVAL, "indices is NULL");
    if (m->vertex_count == 0)
        return ray__fail(s, RAY_EINVAL, "no vertices (vertex_count 0)");
    if (m->triangle_count == 0)
        return ray__fail(s, RAY_EINVAL, "no triangles (triangle_count 0)");
    return RAY_OK;
}

/* Vertex i and its attributes are finite: RAY_OK, or the failure. */
static int mesh_vertex_check(ray_scene *s, const ray_mesh *m, size_t i)
{
    if (!v3_isfinite(m->vertices[i]))
        return ray__fail(s, RAY_EINVAL, "vertex %zu " RAY__V3FMT " is not "
                         "finite", i, RAY__V3ARGS(m->vertices[i]));
    if (m->normals != NULL && !v3_isfinite(m->normals[i]))
        return ray__fail(s, RAY_EINVAL, "normal %zu " RAY__V3FMT " is not "
                         "finite", i, RAY__V3ARGS(m->normals[i]));
    if (m->texcoords != NULL && (!isfinite(m->texcoords[2 * i]) ||
                                 !isfinite(m->texcoords[2 * i + 1])))
        return ray__fail(s, RAY_EINVAL, "texture coordinates %zu (%g, %g) "
                         "are not finite", i, m->texcoords[2 * i],
                         m->texcoords[2 * i + 1]);
    return RAY_OK;
}

/* Every index in range, every vertex and attribute finite: RAY_OK, or the
** first failure, named by triangle and corner, or by vertex. */
static int mesh_check(ray_scene *s, const ray_mesh *m)
{
    size_t i;
    int rc = mesh_arrays_check(s, m);

    if (rc != RAY_OK)
        return rc;
    for (i = 0; i < 3 * m->triangle_count; i++)
        if (m->indices[i] >= m->vertex_count)
            return ray__fail(s, RAY_EINVAL, "triangle %zu index %u out of "
                             "range (%zu vertices)", i / 3, m->indices[i],
                             m->vertex_count);
    for (i = 0; i < m->vertex_count; i++) {
        rc = mesh_vertex_check(s, m, i);
        if (rc != RAY_OK)
            return rc;
    }
    return RAY_OK;
}

/* Copy "count" elements of "size" bytes (NULL stays NULL). */
static int copy_array(const ray_scene *s, const void *src, size_t count,
                      size_t size, void **dst)
{
    *dst = NULL;
    if (src == NULL)
        return RAY_OK;
    if (count > (size_t)-1 / size)
        return RAY_ENOMEM;
    *dst = ray__alloc(s, count * size);
    if (*dst == NULL)
        return RAY_ENOMEM;
    memcpy(*dst, src, count * size);
    return RAY_OK;
}

/* The shading data of a mesh with normals or texture coordinates. */
static int mesh_shading_copy(const ray_scene *s, const ray_mesh *m,
                             ray__mesh *out)
{
    void *idx, *nrm, *tex;

    memset(out, 0, sizeof *out);
    if (m->normals == NULL && m->texcoords == NULL)
        return RAY_OK;
    if (copy_array(s, m->indices, 3 * m->triangle_count, sizeof(unsigned),
                   &idx) != RAY_OK)
        return RAY_ENOMEM;
    if (copy_array(s, m->normals, m->vertex_count, sizeof(ray_vec3), &nrm) !=
        RAY_OK) {
        ray__free(s, idx, 3 * m->triangle_count * sizeof(unsigned));
        return RAY_ENOMEM;
    }
    if (copy_array(s, m->texcoords, 2 * m->vertex_count, sizeof(double),
                   &tex) != RAY_OK) {
        ray__free(s, idx, 3 * m->triangle_count * sizeof(unsigned));
        ray__free(s, nrm, m->vertex_count * sizeof(ray_vec3));
        return RAY_ENOMEM;
    }
    out->indices = idx;
    out->normals = nrm;
    out->texcoords = tex;
    out->n_vertices = m->vertex_count;
    out->n_tris = m->triangle_count;
    return RAY_OK;
}

int ray_scene_add_mesh(ray_scene *s, const ray_mesh *m, unsigned material,
                       unsigned *geom_id)
{
    ray__mesh shading;
    unsigned id;
    size_t i;
    int rc = ray__begin(s, "ray_scene_add_mesh");

    if (rc != RAY_OK)
        return rc;
    if (m == NULL)
        return ray__fail(s, RAY_EINVAL, "mesh is NULL");
    if (m->triangle_count > ((size_t)-1) / 3 / sizeof(unsigned))
        return ray__fail(s, RAY_ENOMEM, "%zu triangles: the index count "
                         "overflows size_t", m->triangle_count);
    rc = mesh_check(s, m);
    if (rc == RAY_OK)
        rc = ray__material_known(s, material);
    if (rc == RAY_OK)
        rc = ray__reserve_tris(s, m->triangle_count);
    if (rc != RAY_OK)
        return rc;
    rc = mesh_shading_copy(s, m, &shading);
    if (rc != RAY_OK)
        return ray__fail(s, rc, "out of memory (copying the normals or "
                         "texture coordinates of %zu vertices)",
                         m->vertex_count);
    rc = ray__add_mesh_prim(s, material, s->n_tris, m->triangle_count,
                            &shading, &id);
    if (rc != RAY_OK) {
        ray__free(s, shading.indices, 3 * shading.n_tris * sizeof(unsigned));
        ray__free(s, shading.normals, shading.n_vertices * sizeof(ray_vec3));
        ray__free(s, shading.texcoords,
                  2 * shading.n_vertices * sizeof(double));
        return rc;
    }
    for (i = 0; i < m->triangle_count; i++) {
        const unsigned *t = m->indices + 3 * i;
        ray__tri *tri = &s->tris[s->n_tris + i];
        tri->a = m->vertices[t[0]];
        tri->b = m->vertices[t[1]];
        tri->c = m->vertices[t[2]];
        s->tri_ids[s->n_tris + i].geom_id = id;
        s->tri_ids[s->n_tris + i].prim_id = (unsigned)i;
    }
    s->n_tris += m->triangle_count;
    if (geom_id != NULL)
        *geom_id = id;
    return RAY_OK;
}

/*
** New positions for a mesh: every slot of its triangles (wherever the
** last commit put them: tri_ids name them) rewritten from "m", its
** shading data replaced, and the triangle BVH refitted at the next
** commit.  The triangle count stays: that is what makes a refit enough.
*/
int ray_scene_update_mesh(ray_scene *s, unsigned geom_id, const ray_mesh *m)
{
    ray__mesh shading;
    ray__prim *p;
    size_t i;
    int rc = ray__begin(s, "ray_scene_update_mesh");

    if (rc != RAY_OK)
        return rc;
    if (m == NULL)
        return ray__fail(s, RAY_EINVAL, "mesh is NULL");
    if (geom_id >= s->n_prims || s->prims[geom_id].removed)
        return ray__fail(s, RAY_EINVAL, "no geometry %u", geom_id);
    p = &s->prims[geom_id];
    if (p->kind != RAY__KIND_MESH)
        return ray__fail(s, RAY_EINVAL, "geometry %u is not a mesh",
                         geom_id);
    if (m->triangle_count != p->count)
        return ray__fail(s, RAY_EINVAL, "triangle_count %zu: the mesh has "
                         "%zu (an update keeps the count: remove it and add "
                         "another)", m->triangle_count, p->count);
    if ((rc = mesh_check(s, m)) != RAY_OK)
        return rc;
    if (mesh_shading_copy(s, m, &shading) != RAY_OK)
        return ray__fail(s, RAY_ENOMEM, "out of memory (copying the "
                         "normals or texture coordinates of %zu vertices)",
                         m->vertex_count);
    ray__mesh_release(s, &s->meshes[p->mesh]);
    s->meshes[p->mesh] = shading;
    for (i = 0; i < s->n_tris; i++)
        if (s->tri_ids[i].geom_id == geom_id) {
            const unsigned *t = m->indices + 3 * (size_t)s->tri_ids[i].prim_id;
            s->tris[i].a = m->vertices[t[0]];
            s->tris[i].b = m->vertices[t[1]];
            s->tris[i].c = m->vertices[t[2]];
        }
    ray__touch(s, p->enabled ? RAY__DIRTY_REFIT : 0u);
    return RAY_OK;
}
