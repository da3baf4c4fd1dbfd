/* SPDX-License-Identifier: MIT */
/*
** mesh.c -- indexed triangle meshes: validated, then copied into the
** scene's flat triangle array (for traversal) and, when the mesh has
** normals or texture coordinates, kept indexed for shading.
*/
#include <string.h>

#include "internal.h"

/* Every index in range, every vertex and attribute finite. */
static int mesh_valid(const ray_mesh *m)
{
    size_t i;

    if (m->vertices == NULL || m->indices == NULL || m->vertex_count == 0 ||
        m->triangle_count == 0)
        return 0;
    for (i = 0; i < 3 * m->triangle_count; i++)
        if (m->indices[i] >= m->vertex_count)
            return 0;
    for (i = 0; i < m->vertex_count; i++) {
        if (!v3_isfinite(m->vertices[i]) ||
            (m->normals != NULL && !v3_isfinite(m->normals[i])) ||
            (m->texcoords != NULL && (!isfinite(m->texcoords[2 * i]) ||
                                      !isfinite(m->texcoords[2 * i + 1]))))
            return 0;
    }
    return 1;
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
    int rc;

    if (s == NULL || m == NULL)
        return RAY_EINVAL;
    if (s->committed)
        return RAY_ESTATE;
    if (m->triangle_count > ((size_t)-1) / 3 / sizeof(unsigned))
        return RAY_ENOMEM;                  /* the index count overflows */
    if (!mesh_valid(m) || material >= s->n_materials)
        return RAY_EINVAL;
    rc = ray__reserve_tris(s, m->triangle_count);
    if (rc != RAY_OK)
        return rc;
    rc = mesh_shading_copy(s, m, &shading);
    if (rc != RAY_OK)
        return rc;
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
