/* SPDX-License-Identifier: MIT */
/*
** mesh.c -- indexed triangle meshes (double vertices and unsigned
** indices, or strided float or double positions and 16- or 32-bit
** indices, as games keep them): validated, then kept indexed: double
** positions and unsigned indices (what the exact triangle test reads),
** and normals and texture coordinates for shading.
*/
#include <stdint.h>
#include <string.h>

#include "scene/slots.h"

/* The bytes of one position of positions: 3 values of position_type. */
static size_t position_size(const ray_mesh *m)
{
    return m->position_type == RAY_FLOAT32 ? 3 * sizeof(float)
                                           : 3 * sizeof(double);
}

/*
** Vertex i, from vertices or from the strided positions (validated by
** mesh_positions_check).  memcpy: a stride need not keep the values
** aligned.  A float converts to double exactly (C99 6.3.1.5: every float
** value is a double value, signed zeros and subnormals included), so a
** float-sourced mesh is the mesh of the doubles of its floats, bit for
** bit.
*/
static ray_vec3 mesh_vertex(const ray_mesh *m, size_t i)
{
    const unsigned char *p;
    size_t stride;
    ray_vec3 v;

    if (m->vertices != NULL)
        return m->vertices[i];
    stride = m->position_stride != 0 ? m->position_stride
                                     : position_size(m);
    p = (const unsigned char *)m->positions + i * stride;
    if (m->position_type == RAY_FLOAT32) {
        float f[3];
        memcpy(f, p, sizeof f);
        v.x = (double)f[0];
        v.y = (double)f[1];
        v.z = (double)f[2];
    } else {
        double d[3];
        memcpy(d, p, sizeof d);
        v.x = d[0];
        v.y = d[1];
        v.z = d[2];
    }
    return v;
}

/*
** All the positions, as mesh_vertex reads them one by one, into pos: the
** array copied, or the strided floats converted in a loop of their own
** (a game's skinned mesh), where a call a vertex deciding the layout
** again was a seventh of a refit after ray_scene_update_mesh (callgrind,
** bench/game's frame, issue 36).
*/
static void positions_read(const ray_mesh *m, ray_vec3 *pos)
{
    size_t i, n = m->vertex_count, stride;
    const unsigned char *p;

    if (m->vertices != NULL) {
        memcpy(pos, m->vertices, n * sizeof *pos);
        return;
    }
    if (m->position_type != RAY_FLOAT32) {
        for (i = 0; i < n; i++)
            pos[i] = mesh_vertex(m, i);
        return;
    }
    stride = m->position_stride != 0 ? m->position_stride
                                     : position_size(m);
    p = m->positions;
    for (i = 0; i < n; i++) {
        float f[3];
        memcpy(f, p + i * stride, sizeof f);
        pos[i].x = (double)f[0];
        pos[i].y = (double)f[1];
        pos[i].z = (double)f[2];
    }
}

/* Index i (of 3 * triangle_count), from indices or from index_data. */
static unsigned mesh_index(const ray_mesh *m, size_t i)
{
    if (m->indices != NULL)
        return m->indices[i];
    if (m->index_type == RAY_UINT16) {
        uint16_t k;
        memcpy(&k, (const unsigned char *)m->index_data + i * sizeof k,
               sizeof k);
        return k;
    } else {
        uint32_t k;
        memcpy(&k, (const unsigned char *)m->index_data + i * sizeof k,
               sizeof k);
        return (unsigned)k;
    }
}

/* The strided positions, if used, are described consistently: a known
** type, a stride of at least one position, and every byte read,
** (vertex_count - 1) * stride + one position, addressable. */
static int mesh_positions_check(ray_scene *s, const ray_mesh *m)
{
    size_t size, stride;

    if (m->vertices != NULL)
        return RAY_OK;               /* positions is not read */
    if (m->positions == NULL)
        return ray__fail(s, RAY_EINVAL, "vertices and positions are both "
                         "NULL");
    if (m->position_type != RAY_FLOAT32 && m->position_type != RAY_FLOAT64)
        return ray__fail(s, RAY_EINVAL, "position_type %d is not "
                         "RAY_FLOAT32 or RAY_FLOAT64", m->position_type);
    size = position_size(m);
    if (m->position_stride != 0 && m->position_stride < size)
        return ray__fail(s, RAY_EINVAL, "position_stride %zu is smaller "
                         "than a position (%zu bytes)", m->position_stride,
                         size);
    stride = m->position_stride != 0 ? m->position_stride : size;
    if (m->vertex_count > 1 &&
        m->vertex_count - 1 > ((size_t)-1 - size) / stride)
        return ray__fail(s, RAY_EINVAL, "position_stride %zu: %zu "
                         "positions overflow size_t", m->position_stride,
                         m->vertex_count);
    return RAY_OK;
}

/* The indices come from indices or, when it is NULL, from index_data of
** a known type.  Their count, 3 * triangle_count, times 4 bytes is
** checked against size_t by the caller (triangle_count's limit). */
static int mesh_indices_check(ray_scene *s, const ray_mesh *m)
{
    if (m->indices != NULL)
        return RAY_OK;               /* index_data is not read */
    if (m->index_data == NULL)
        return ray__fail(s, RAY_EINVAL, "indices and index_data are both "
                         "NULL");
    if (m->index_type != RAY_UINT16 && m->index_type != RAY_UINT32)
        return ray__fail(s, RAY_EINVAL, "index_type %d is not RAY_UINT16 "
                         "or RAY_UINT32", m->index_type);
    return RAY_OK;
}

/* The arrays are there and not empty: RAY_OK, or the failure. */
static int mesh_arrays_check(ray_scene *s, const ray_mesh *m)
{
    int rc = mesh_positions_check(s, m);

    if (rc == RAY_OK)
        rc = mesh_indices_check(s, m);
    if (rc != RAY_OK)
        return rc;
    if (m->vertex_count == 0)
        return ray__fail(s, RAY_EINVAL, "no vertices (vertex_count 0)");
    if (m->triangle_count == 0)
        return ray__fail(s, RAY_EINVAL, "no triangles (triangle_count 0)");
    if ((m->flags & ~RAY_MESH_BORROW) != 0)
        return ray__fail(s, RAY_EINVAL, "unknown flags 0x%x (known: "
                         "RAY_MESH_BORROW)", m->flags & ~RAY_MESH_BORROW);
    return RAY_OK;
}

/* Vertex i and its attributes are finite: RAY_OK, or the failure. */
static int mesh_vertex_check(ray_scene *s, const ray_mesh *m, size_t i)
{
    ray_vec3 v = mesh_vertex(m, i);

    if (!v3_isfinite(v))
        return ray__fail(s, RAY_EINVAL, "%s %zu " RAY__V3FMT " is not "
                         "finite", m->vertices != NULL ? "vertex" :
                         "position", i, RAY__V3ARGS(v));
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

/*
** Infinite or NaN: the exponent field all ones.  Read from the bits, so
** that no floating-point exception is raised (a program that traps
** FE_INVALID must get RAY_EINVAL for an infinite vertex, not a signal),
** and without a branch: the exponent field plus one in its lowest place
** carries into the sign bit exactly when the field is all ones, so the
** loops below OR these over whole arrays and test one bit at the end.
** Testing each vertex (mesh_vertex_check) was two fifths of an update of
** positions (callgrind, bench/game's refit, issue 36); the vertex by
** vertex check runs only to name a failure.
*/
static inline uint64_t double_bad(double x)
{
    const uint64_t exponent = UINT64_C(0x7ff0000000000000);
    uint64_t u;

    memcpy(&u, &x, sizeof u);
    return (u & exponent) + (UINT64_C(1) << 52);
}

static inline uint64_t float_bad(float x)
{
    const uint32_t exponent = UINT32_C(0x7f800000);
    uint32_t u;

    memcpy(&u, &x, sizeof u);
    return (uint64_t)((u & exponent) + (UINT32_C(1) << 23)) << 32;
}

/* No value ORed into "bad" (double_bad, float_bad) was infinite or NaN. */
static inline int none_bad(uint64_t bad)
{
    return (bad >> 63) == 0;
}

/* Are the n vectors v all finite? */
static int vec3s_finite(const ray_vec3 *v, size_t n)
{
    uint64_t bad = 0;
    size_t i;

    for (i = 0; i < n; i++)
        bad |= double_bad(v[i].x) | double_bad(v[i].y) | double_bad(v[i].z);
    return none_bad(bad);
}

/* The same of strided positions: floats read in place, anything else
** through mesh_vertex. */
static int strided_finite(const ray_mesh *m)
{
    size_t i, stride = m->position_stride != 0 ? m->position_stride
                                               : position_size(m);
    const unsigned char *base = m->positions;
    uint64_t bad = 0;

    for (i = 0; i < m->vertex_count; i++) {
        if (m->position_type == RAY_FLOAT32) {
            float f[3];
            memcpy(f, base + i * stride, sizeof f);
            bad |= float_bad(f[0]) | float_bad(f[1]) | float_bad(f[2]);
        } else {
            ray_vec3 v = mesh_vertex(m, i);
            bad |= double_bad(v.x) | double_bad(v.y) | double_bad(v.z);
        }
    }
    return none_bad(bad);
}

/* The same of n pairs of texture coordinates. */
static int pairs_finite(const double *st, size_t n)
{
    uint64_t bad = 0;
    size_t i;

    for (i = 0; i < 2 * n; i++)
        bad |= double_bad(st[i]);
    return none_bad(bad);
}

/* Are every vertex and attribute of m finite, by the quick test? */
static int mesh_finite(const ray_mesh *m)
{
    size_t n = m->vertex_count;

    return (m->vertices != NULL ? vec3s_finite(m->vertices, n)
                                : strided_finite(m)) &&
           (m->normals == NULL || vec3s_finite(m->normals, n)) &&
           (m->texcoords == NULL || pairs_finite(m->texcoords, n));
}

/* Every index in range, every vertex and attribute finite: RAY_OK, or the
** first failure, named by triangle and corner, or by vertex. */
static int mesh_check(ray_scene *s, const ray_mesh *m, int indices_known)
{
    size_t i;
    int rc = mesh_arrays_check(s, m);

    if (rc != RAY_OK)
        return rc;
    for (i = 0; !indices_known && i < 3 * m->triangle_count; i++)
        if (mesh_index(m, i) >= m->vertex_count)
            return ray__fail(s, RAY_EINVAL, "%striangle %zu index %u out "
                             "of range (%zu vertices)", m->indices != NULL ?
                             "" : "index_data: ", i / 3, mesh_index(m, i),
                             m->vertex_count);
    if (mesh_finite(m))
        return RAY_OK;
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

/* The 3 * triangle_count indices as unsigned, whatever their input type
** (the shading data keeps them in one form). */
static int copy_indices(const ray_scene *s, const ray_mesh *m, void **dst)
{
    size_t n = 3 * m->triangle_count, i;
    unsigned *idx;

    if (m->indices != NULL)
        return copy_array(s, m->indices, n, sizeof(unsigned), dst);
    *dst = NULL;
    idx = ray__alloc(s, n * sizeof(unsigned));
    if (idx == NULL)
        return RAY_ENOMEM;
    for (i = 0; i < n; i++)
        idx[i] = mesh_index(m, i);
    *dst = idx;
    return RAY_OK;
}

/*
** Is every coordinate of the n = m->vertex_count positions pos a float
** (ray__is_float, in the caller's floating-point environment)?  Tested up
** to the first that is not, where a test of all was a fifth of an update
** of a double mesh (callgrind, bench/game's refit, issue 36).  Float
** positions are tested too: under flush-to-zero a subnormal float
** converts to 0, and its rows would not be its corners.
*/
static int positions_floats(const ray_vec3 *pos, const ray_mesh *m)
{
    size_t i;

    for (i = 0; i < m->vertex_count; i++)
        if (!(ray__is_float(pos[i].x) & ray__is_float(pos[i].y) &
              ray__is_float(pos[i].z)))
            return 0;
    return 1;
}

/* The positions as doubles, the scene's own copy: what the exact
** triangle test reads (through the indices), whatever the input type. */
static int copy_positions(const ray_scene *s, const ray_mesh *m,
                          ray_vec3 **dst, int *floats)
{
    if (m->vertex_count > (size_t)-1 / sizeof **dst)
        return RAY_ENOMEM;
    *dst = ray__alloc(s, m->vertex_count * sizeof **dst);
    if (*dst == NULL)
        return RAY_ENOMEM;
    positions_read(m, *dst);
    *floats = positions_floats(*dst, m);
    return RAY_OK;
}

/*
** What a mesh keeps (ray__mesh): a double copy of its positions, its
** index triples (the caller's own for a borrowed mesh with unsigned
** indices, else a copy), and its normals and texture coordinates (the
** caller's arrays for a borrowed mesh, else copies), with the caller's
** descriptor for a borrowed one.  RAY_ENOMEM keeps nothing.
*/
static int mesh_keep_arrays(const ray_scene *s, const ray_mesh *m,
                            ray__mesh *out)
{
    void *idx = NULL, *nrm = NULL, *tex = NULL;
    int borrow = (m->flags & RAY_MESH_BORROW) != 0;

    memset(out, 0, sizeof *out);
    out->n_vertices = m->vertex_count;
    out->n_tris = m->triangle_count;
    if (copy_positions(s, m, &out->pos, &out->pos_floats) != RAY_OK)
        return RAY_ENOMEM;
    if (borrow && m->indices != NULL)
        out->indices = m->indices;
    else if (copy_indices(s, m, &idx) != RAY_OK)
        goto fail;
    else {
        out->indices = idx;
        out->own_indices = 1;
    }
    if (borrow) {
        out->borrowed = 1;
        out->src = *m;
        out->normals = m->normals;
        out->texcoords = m->texcoords;
        return RAY_OK;
    }
    if (copy_array(s, m->normals, m->vertex_count, sizeof(ray_vec3), &nrm) !=
            RAY_OK ||
        copy_array(s, m->texcoords, 2 * m->vertex_count, sizeof(double),
                   &tex) != RAY_OK)
        goto fail;
    out->normals = nrm;
    out->texcoords = tex;
    return RAY_OK;
fail:
    ray__free(s, nrm, m->vertex_count * sizeof(ray_vec3));
    out->normals = NULL;
    ray__mesh_release(s, out);
    return RAY_ENOMEM;
}

/* Triangle i of mesh m, its three corners' positions. */
static void mesh_triangle(const ray_mesh *m, size_t i, ray__tri *t)
{
    t->a = mesh_vertex(m, mesh_index(m, 3 * i));
    t->b = mesh_vertex(m, mesh_index(m, 3 * i + 1));
    t->c = mesh_vertex(m, mesh_index(m, 3 * i + 2));
}

/*
** The per-triangle (s, t) scale of a mesh with texture coordinates, for
** ray cones' footprints (ray__prim_uv_scale): sqrt(st area / area), a
** degenerate triangle 0 (no filtering).  RAY_OK, RAY_ENOMEM.
*/
static void uv_scale_fill(const ray_mesh *m, double *uv_scale)
{
    size_t i;

    for (i = 0; i < m->triangle_count; i++) {
        const double *st = m->texcoords;
        ray__tri t;
        size_t a = 2 * (size_t)mesh_index(m, 3 * i);
        size_t b = 2 * (size_t)mesh_index(m, 3 * i + 1);
        size_t c = 2 * (size_t)mesh_index(m, 3 * i + 2);

        mesh_triangle(m, i, &t);
        uv_scale[i] = ray__triangle_uv_scale(
            t.a, t.b, t.c,
            fabs((st[b] - st[a]) * (st[c + 1] - st[a + 1]) -
                 (st[c] - st[a]) * (st[b + 1] - st[a + 1])));
    }
}

static int mesh_uv_scale(const ray_scene *s, const ray_mesh *m,
                         ray__mesh *out)
{
    if (m->texcoords == NULL)
        return RAY_OK;
    out->uv_scale = ray__alloc(s, m->triangle_count * sizeof(double));
    if (out->uv_scale == NULL)
        return RAY_ENOMEM;
    uv_scale_fill(m, out->uv_scale);
    return RAY_OK;
}

/*
** Are an update's indices those the mesh keeps, checked when they came,
** over as many vertices?  Then they need no check again: a game's update
** of the positions alone hands the same indices every frame, and their
** check was 40% of ray_scene_update_mesh's instructions where a memcmp
** costs about 2% of it (callgrind, bench/game's frame, issue 36).
** 16- and 32-bit index_data (a game's own format) compared as their
** values, which the mesh keeps as unsigned.  Borrowed unsigned indices
** (the caller's array itself, which it may have changed in place) are
** always checked.
*/
static int indices_kept(const ray__mesh *cur, const ray_mesh *m)
{
    size_t i, n = 3 * m->triangle_count;

    if (!cur->own_indices || m->vertex_count != cur->n_vertices ||
        m->triangle_count != cur->n_tris)
        return 0;
    if (m->indices != NULL)
        return memcmp(cur->indices, m->indices, n * sizeof *m->indices) == 0;
    if (m->index_data == NULL ||
        (m->index_type != RAY_UINT16 && m->index_type != RAY_UINT32))
        return 0;                   /* refused by the checks after */
    for (i = 0; i < n; i++)
        if (mesh_index(m, i) != cur->indices[i])
            return 0;
    return 1;
}

/*
** Can an update "m" be written over what mesh "cur" keeps, array for
** array, with nothing allocated or freed?  When it has as many vertices,
** is borrowed or not as before, and needs the same copies the mesh has
** (indices, normals, texture coordinates, their scales): a game's
** update of the positions alone.  A large array allocated afresh at each
** update is mapped and page-faulted in again each time (issue 36).
*/
static int mesh_rewritable(const ray__mesh *cur, const ray_mesh *m)
{
    int borrow = (m->flags & RAY_MESH_BORROW) != 0;

    if (m->vertex_count != cur->n_vertices || borrow != cur->borrowed ||
        (m->texcoords == NULL) != (cur->uv_scale == NULL))
        return 0;
    if (borrow && m->indices != NULL ? cur->own_indices : !cur->own_indices)
        return 0;
    return borrow || ((m->normals == NULL) == (cur->normals == NULL) &&
                      (m->texcoords == NULL) == (cur->texcoords == NULL));
}


/* The update written over the mesh's arrays (mesh_rewritable): the
** values mesh_keep would have copied, in the same arrays, but for
** indices the same as those kept (indices_same: indices_kept).  Cannot
** fail. */
static void mesh_rewrite(ray__mesh *cur, const ray_mesh *m,
                         int indices_same)
{
    size_t i, n = 3 * m->triangle_count;

    positions_read(m, cur->pos);
    cur->pos_floats = positions_floats(cur->pos, m);
    if (!cur->own_indices)
        cur->indices = m->indices;
    else if (indices_same)
        ;                       /* indices_kept: the same bytes */
    else if (m->indices != NULL)
        memcpy(ray__unconst(cur->indices), m->indices, n * sizeof(unsigned));
    else {
        unsigned *idx = ray__unconst(cur->indices);
        for (i = 0; i < n; i++)
            idx[i] = mesh_index(m, i);
    }
    if (cur->borrowed) {
        cur->src = *m;
        cur->normals = m->normals;
        cur->texcoords = m->texcoords;
    } else {
        if (m->normals != NULL)
            memcpy(ray__unconst(cur->normals), m->normals,
                   m->vertex_count * sizeof(ray_vec3));
        if (m->texcoords != NULL)
            memcpy(ray__unconst(cur->texcoords), m->texcoords,
                   2 * m->vertex_count * sizeof(double));
    }
    if (cur->uv_scale != NULL)
        uv_scale_fill(m, cur->uv_scale);
}

/* What the mesh keeps and the (s, t) scales; RAY_ENOMEM keeps nothing. */
static int mesh_keep(const ray_scene *s, const ray_mesh *m, ray__mesh *out)
{
    int rc = mesh_keep_arrays(s, m, out);

    /* out->closed: found by the first query that needs it
    ** (ray__closed_ensure), not by every add and update. */
    out->closed = 0;
    if (rc == RAY_OK && mesh_uv_scale(s, m, out) != RAY_OK) {
        ray__mesh_release(s, out);
        return RAY_ENOMEM;
    }
    return rc;
}

unsigned ray__mesh_corner(const ray__mesh *m, size_t k)
{
    return m->indices[k];
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
    rc = mesh_check(s, m, 0);
    if (rc == RAY_OK)
        rc = ray__material_known(s, material);
    if (rc == RAY_OK)
        rc = ray__reserve_tris(s, m->triangle_count);
    if (rc != RAY_OK)
        return rc;
    rc = mesh_keep(s, m, &shading);
    if (rc != RAY_OK)
        return ray__fail(s, rc, "out of memory (copying the positions, "
                         "indices, normals or texture coordinates of %zu "
                         "vertices)", m->vertex_count);
    rc = ray__add_mesh_prim(s, material, s->n_tris, m->triangle_count,
                            &shading, &id);
    if (rc != RAY_OK) {
        ray__mesh_release(s, &shading);
        return rc;
    }
    for (i = 0; i < m->triangle_count; i++) {
        s->tri_ids[s->n_tris + i].geom_id = id;
        s->tri_ids[s->n_tris + i].prim_id = (unsigned)i;
    }
    s->n_tris += m->triangle_count;
    if (geom_id != NULL)
        *geom_id = id;
    return RAY_OK;
}

/*
** New positions for a mesh (and indices, normals, texture coordinates):
** what the mesh keeps replaced from "m" (NULL: the borrowed arrays again,
** changed in place by the caller), and the triangle BVH refitted at the
** next commit, which reads the new positions through the mesh's slots.
** The triangle count stays: that is what makes a refit enough.
*/
int ray_scene_update_mesh(ray_scene *s, unsigned geom_id, const ray_mesh *m)
{
    ray__mesh shading;
    ray_mesh again;
    ray__prim *p;
    int kept, owned, rc = ray__begin(s, "ray_scene_update_mesh");

    if (rc != RAY_OK)
        return rc;
    if ((p = ray__live_prim(s, geom_id)) == NULL)
        return RAY_EINVAL;
    if (p->kind != RAY__KIND_MESH)
        return ray__fail(s, RAY_EINVAL, "geometry %u is not a mesh",
                         geom_id);
    if (m == NULL) {
        if (!s->meshes[p->mesh].borrowed)
            return ray__fail(s, RAY_EINVAL, "mesh is NULL and geometry %u "
                             "was not borrowed (RAY_MESH_BORROW)", geom_id);
        again = s->meshes[p->mesh].src;
        m = &again;
    }
    if (m->triangle_count != p->count)
        return ray__fail(s, RAY_EINVAL, "triangle_count %zu: the mesh has "
                         "%zu (an update keeps the count: remove it and add "
                         "another)", m->triangle_count, p->count);
    kept = indices_kept(&s->meshes[p->mesh], m);
    owned = s->meshes[p->mesh].own_indices;
    if ((rc = mesh_check(s, m, kept)) != RAY_OK)
        return rc;
    if (mesh_rewritable(&s->meshes[p->mesh], m))
        mesh_rewrite(&s->meshes[p->mesh], m, kept);
    else if (mesh_keep(s, m, &shading) != RAY_OK)
        return ray__fail(s, RAY_ENOMEM, "out of memory (copying the "
                         "positions, indices, normals or texture "
                         "coordinates of %zu vertices)", m->vertex_count);
    else {
        ray__mesh_release(s, &s->meshes[p->mesh]);
        s->meshes[p->mesh] = shading;
    }
    /* Other indices than those kept, in a mesh that keeps its own (or
    ** kept them before): the refit's copy of them is stale.  A mesh that
    ** reads the caller's array itself is never read through the copy
    ** (slots.h), so its updates leave the copy alone. */
    if (!kept && (owned || s->meshes[p->mesh].own_indices))
        ray__slot_vertices_drop(s);
    ray__touch(s, p->enabled ? RAY__DIRTY_REFIT : 0u);
    return RAY_OK;
}
