/* SPDX-License-Identifier: MIT */
/*
** fuzz_scene.c -- the "scene program" fuzzer: the input is decoded into a
** sequence of public calls on one scene (made with a counting allocator
** that may fail one allocation), then commit, queries, a trace context
** and a 4 x 4 render at 1 sample on 1 thread, every value arbitrary
** (NaN, +-Inf, subnormals, 1e300, degenerate geometry).  Checked:
**
**   * every status is a documented code; a building call that succeeds
**     after commit stages a change (queries answer -RAY_ESTATE until the
**     next commit); ray_scene_errmsg is "" exactly after a success;
**   * disabled and removed geometry is never hit, and masks hide what
**     shares no bit with the query's;
**   * outputs are untouched on failure (ids, hits, pixels, statistics);
**     ids count from 0 on success;
**   * hits are in (tmin, tmax), finite, with a unit normal and ids that
**     name an added geometry; ray_occluded agrees with ray_intersect on
**     scenes of exact primitives;
**   * ray_closest_point from the ray's origin within tmax: -RAY_EINVAL
**     for a q or radius it refuses, else -RAY_ESTATE before commit, else
**     a finite point within the radius with a unit normal and ids that
**     name an added geometry, or 0 with *out untouched;
**   * light samples and material calls keep their contracts;
**   * pixels are finite (defect 5);
**   * a camera whose up is exactly parallel to its view is refused
**     (defect 3);
**   * after ray_scene_free the allocator holds nothing, and every osize
**     it was given was the block's size.
*/
#include <string.h>

#include "fuzz.h"
#include "prim/prim.h"         /* ray__implicit_torus (internal) */

#define MAX_OPS 40
#define MAX_SLOTS MAX_OPS            /* at most one object per operation */
#define MAX_POLY 8
#define MAX_MESH_VERTS 8
#define MAX_MESH_TRIS 6
#define MAX_QUERIES 8
#define IMG_SIZE 4

/* Borrowed data of the callbacks (they must outlive the scene). */
typedef struct sphere_ud {
    ray_vec3 c;
    double r;
} sphere_ud;

typedef struct flat_ud {
    ray_rgb colour;
    unsigned effects;
} flat_ud;

typedef struct prog {
    fuzz_input in;
    ray_scene *scene;
    fuzz_alloc alloc;
    int committed;
    unsigned n_materials, n_geoms, n_lights;
    size_t geom_tris[MAX_SLOTS];      /* triangles of a mesh, else 0 */
    unsigned char hidden[MAX_SLOTS];  /* disabled, removed or masked out
                                         (mask 0): never hit */
    unsigned char removed[MAX_SLOTS], disabled[MAX_SLOTS], masked[MAX_SLOTS];
    int mask_zero;                    /* the last op_dynamic mask was 0 */
    int curved;                       /* implicit or parametric added */
    /* Parameter blocks and callback data, one slot per operation. */
    ray_phong_params phong[MAX_SLOTS];
    ray_glass_params glass[MAX_SLOTS];
    ray_rgb mirror[MAX_SLOTS];
    ray_checker_params checker[MAX_SLOTS];
    flat_ud flat[MAX_SLOTS];
    sphere_ud sphere[MAX_SLOTS];
    ray_torus_params torus[MAX_SLOTS];
    ray_blob blobs[MAX_SLOTS][2];
    ray_blobs_params blob_params[MAX_SLOTS];
    ray_vec3 bezier[MAX_SLOTS][16];
    unsigned slot;
    ray_rgb background;
} prog;

/* ---------------------------------------------------------- callbacks */

/*
** A material that also exercises what a material may call: each light
** sample (whose contract it checks), a shadow ray, and a reflection ray
** (which must be refused with RAY_EEFFECT if not declared).
*/
static void flat_shade(void *ud, ray_ctx *ctx, const ray_shade_args *args,
                       ray_rgb *out)
{
    const flat_ud *f = (const flat_ud *)ud;
    unsigned nl = ray_scene_light_count(args->scene), l;
    ray_ray refl;
    ray_rgb c;
    int rc;

    *out = f->colour;
    for (l = 0; l < nl && l < 4; l++) {
        ray_light_sample s;
        fuzz_sentinel(&s, sizeof s);
        rc = ray_light_sample_at(ctx, args, l, 0, &s);
        FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL,
                   "ray_light_sample_at: status");
        if (rc != RAY_OK) {
            FUZZ_CHECK(fuzz_untouched(&s, sizeof s),
                       "ray_light_sample_at: untouched on error");
            continue;
        }
        FUZZ_CHECK(fuzz_finite3(s.dir) && s.dist > 0 &&
                       isfinite(s.radiance.r) && isfinite(s.radiance.g) &&
                       isfinite(s.radiance.b) && s.radiance.r >= 0 &&
                       s.radiance.g >= 0 && s.radiance.b >= 0,
                   "ray_light_sample_at: a finite sample");
        rc = ray_light_visible(ctx, args, &s);
        FUZZ_CHECK(rc == 0 || rc == 1, "ray_light_visible: 1 or 0");
        if (rc)
            out->r += 1e-3 * s.radiance.r;
    }
    if (ray_spawn(args->hit, ray_reflect(args->ray->dir, args->normal),
                  &refl) != RAY_OK)
        return;
    fuzz_sentinel(&c, sizeof c);
    rc = ray_trace(ctx, &refl, RAY_KIND_REFLECTION, 0.5, &c);
    if (!(f->effects & RAY_EFFECT_REFLECTION))
        FUZZ_CHECK(rc == RAY_EEFFECT, "ray_trace: undeclared effect refused");
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ELIMIT || rc == RAY_EEFFECT,
               "ray_trace: status in a material");
    if (rc != RAY_OK)
        FUZZ_CHECK(fuzz_untouched(&c, sizeof c), "ray_trace: untouched");
    else
        out->g += 0.5 * c.g;
}

static void background_fn(void *ud, const ray_ray *r, ray_rgb *out)
{
    const ray_rgb *c = (const ray_rgb *)ud;
    out->r = c->r;
    out->g = c->g * (r->dir.y > 0 ? 1.0 : 0.5);
    out->b = c->b;
}

static double sphere_f(void *ud, ray_vec3 p)
{
    const sphere_ud *s = (const sphere_ud *)ud;
    double x = p.x - s->c.x, y = p.y - s->c.y, z = p.z - s->c.z;
    return sqrt(x * x + y * y + z * z) - s->r;
}

/* A sphere as S(u, v): longitude 2 pi u, latitude pi v. */
static void sphere_eval(void *ud, double u, double v, ray_vec3 *s,
                        ray_vec3 *su, ray_vec3 *sv)
{
    const sphere_ud *q = (const sphere_ud *)ud;
    double pi = 3.141592653589793, cu = cos(2 * pi * u), snu = sin(2 * pi * u);
    double cv = cos(pi * v), snv = sin(pi * v);

    s->x = q->c.x + q->r * cu * snv;
    s->y = q->c.y - q->r * cv;
    s->z = q->c.z + q->r * snu * snv;
    su->x = -2 * pi * q->r * snu * snv;
    su->y = 0;
    su->z = 2 * pi * q->r * cu * snv;
    sv->x = pi * q->r * cu * cv;
    sv->y = pi * q->r * snv;
    sv->z = pi * q->r * snu * cv;
}

static void sphere_bounds(void *ud, double u0, double u1, double v0,
                          double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    const sphere_ud *q = (const sphere_ud *)ud;
    double r = fabs(q->r);
    (void)u0, (void)u1, (void)v0, (void)v1;
    lo->x = q->c.x - r;
    lo->y = q->c.y - r;
    lo->z = q->c.z - r;
    hi->x = q->c.x + r;
    hi->y = q->c.y + r;
    hi->z = q->c.z + r;
}

/* --------------------------------------------------- building calls */

/* A material id: mostly one that exists, sometimes one that does not. */
static unsigned decode_material(prog *p)
{
    unsigned b = fuzz_u8(&p->in);
    if (b < 224)
        return p->n_materials ? b % p->n_materials : 0;
    return b == 255 ? 0xffffffffu : p->n_materials + (b & 3);
}

/*
** The checks common to every building call: a documented status (never
** RAY_ESTATE: after commit a change is staged), the message rule, and
** the id untouched on failure or equal to "expect" on success.
*/
static int check_build(prog *p, int rc, const unsigned *id, unsigned expect,
                       const char *what)
{
    const char *msg = ray_scene_errmsg(p->scene);

    FUZZ_CHECK(fuzz_status_valid(rc), what);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL || rc == RAY_EDEGENERATE ||
                   rc == RAY_ENOMEM, what);
    if (rc == RAY_OK)
        p->committed = 0;             /* a change staged for the commit */
    FUZZ_CHECK(msg != NULL && (rc == RAY_OK) == (msg[0] == '\0'), what);
    if (id != NULL) {
        if (rc == RAY_OK)
            FUZZ_CHECK(*id == expect, what);
        else
            FUZZ_CHECK(fuzz_untouched(id, sizeof *id), what);
    }
    return rc == RAY_OK;
}

static void added_geometry(prog *p, int rc, const unsigned *id,
                           size_t tris, const char *what)
{
    if (check_build(p, rc, id, p->n_geoms, what))
        p->geom_tris[p->n_geoms++] = tris;
}

static void op_material(prog *p)
{
    unsigned kind = fuzz_u8(&p->in) % 7, s = p->slot, id;
    ray_material m;
    int rc;

    switch (kind) {
    case 0:
        p->phong[s].diffuse.r = fuzz_unit_range(&p->in, 1);
        p->phong[s].diffuse.g = fuzz_unit_range(&p->in, 1);
        p->phong[s].diffuse.b = fuzz_unit_range(&p->in, 1);
        p->phong[s].specular = p->phong[s].diffuse;
        p->phong[s].shininess = fuzz_unit_range(&p->in, 200);
        p->phong[s].blinn = (int)(fuzz_u8(&p->in) & 1);
        p->phong[s].reflect.r = p->phong[s].reflect.g =
            p->phong[s].reflect.b = fuzz_unit_range(&p->in, 1);
        p->phong[s].texture.fn = NULL;
        p->phong[s].texture.ud = NULL;
        m = ray_material_phong(&p->phong[s]);
        break;
    case 1:
        p->mirror[s].r = p->mirror[s].g = p->mirror[s].b =
            fuzz_unit_range(&p->in, 1);
        m = ray_material_mirror(&p->mirror[s]);
        break;
    case 2:
        p->glass[s].ior = 0.05 + fuzz_unit_range(&p->in, 4);
        p->glass[s].absorption.r = p->glass[s].absorption.g =
            p->glass[s].absorption.b = fuzz_unit_range(&p->in, 2);
        m = ray_material_glass(&p->glass[s]);
        break;
    case 3:
        p->flat[s].colour.r = p->flat[s].colour.g = p->flat[s].colour.b =
            fuzz_unit_range(&p->in, 1);
        p->checker[s].even = ray_material_mirror(&p->flat[s].colour);
        p->phong[s].diffuse = p->flat[s].colour;
        p->phong[s].specular = p->flat[s].colour;
        p->phong[s].shininess = 8;
        p->phong[s].blinn = 0;
        p->phong[s].reflect = p->flat[s].colour;
        p->phong[s].texture.fn = NULL;
        p->phong[s].texture.ud = NULL;
        p->checker[s].odd = ray_material_phong(&p->phong[s]);
        p->checker[s].scale = fuzz_double(&p->in);
        m = ray_material_checker(&p->checker[s]);
        break;
    default:
        /* The fuzzer's own material, with any effect bits (unknown ones
        ** must be refused), or no shade function at all. */
        p->flat[s].colour.r = p->flat[s].colour.g = p->flat[s].colour.b =
            fuzz_unit_range(&p->in, 1);
        p->flat[s].effects = fuzz_u8(&p->in);
        if (p->flat[s].effects >= 32)
            p->flat[s].effects &= 15;
        m.shade = kind == 6 ? NULL : flat_shade;
        m.ud = &p->flat[s];
        m.effects = p->flat[s].effects;
        m.scatter = NULL;
        break;
    }
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_material(p->scene, &m, &id);
    if (check_build(p, rc, &id, p->n_materials, "ray_scene_add_material"))
        p->n_materials++;
}

static void op_sphere_plane_triangle(prog *p, unsigned op)
{
    ray_vec3 a = fuzz_vec3(&p->in), b = a, c = a;
    double radius = 0;
    unsigned id, mat;
    int rc;

    if (op == 0)
        radius = fuzz_double(&p->in);
    else
        b = fuzz_vec3(&p->in);
    if (op == 2)
        c = fuzz_vec3(&p->in);
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    if (op == 0)
        rc = ray_scene_add_sphere(p->scene, a, radius, mat, &id);
    else if (op == 1)
        rc = ray_scene_add_plane(p->scene, a, b, mat, &id);
    else
        rc = ray_scene_add_triangle(p->scene, a, b, c, mat, &id);
    added_geometry(p, rc, &id, 0, "ray_scene_add_sphere/plane/triangle");
}

static void op_polygon(prog *p)
{
    size_t n = fuzz_below(&p->in, MAX_POLY + 1), i;
    ray_vec3 v[MAX_POLY];
    unsigned id, mat;
    int rc;

    for (i = 0; i < n; i++)
        v[i] = fuzz_vec3(&p->in);
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_polygon(p->scene, n ? v : NULL, n, mat, &id);
    if (n < 3)
        FUZZ_CHECK(rc != RAY_OK, "ray_scene_add_polygon: n < 3 refused");
    added_geometry(p, rc, &id, 0, "ray_scene_add_polygon");
}

/* The game layout of op_mesh: a float position among other floats
** (stride 20, not a multiple of 8: unaligned for doubles' sake too). */
typedef struct fuzz_vertex {
    float pos[3], other[2];
} fuzz_vertex;

static void op_mesh(prog *p)
{
    ray_vec3 v[MAX_MESH_VERTS], nrm[MAX_MESH_VERTS];
    double st[2 * MAX_MESH_VERTS];
    unsigned idx[3 * MAX_MESH_TRIS], id, mat, flags = fuzz_u8(&p->in);
    fuzz_vertex fv[MAX_MESH_VERTS];
    uint16_t idx16[3 * MAX_MESH_TRIS];
    ray_mesh m;
    size_t nv = 1 + fuzz_below(&p->in, MAX_MESH_VERTS);
    size_t nt = fuzz_below(&p->in, MAX_MESH_TRIS + 1), i;
    int rc;

    for (i = 0; i < nv; i++) {
        v[i] = fuzz_vec3(&p->in);
        nrm[i] = flags & 1 ? fuzz_vec3(&p->in) : v[i];
        st[2 * i] = fuzz_double(&p->in);
        st[2 * i + 1] = (double)i;
    }
    for (i = 0; i < 3 * nt; i++)   /* nv + 1: sometimes out of range */
        idx[i] = fuzz_below(&p->in, (unsigned)nv + (flags & 8 ? 1 : 0));
    memset(&m, 0, sizeof m);
    m.vertices = flags & 16 ? NULL : v;
    m.vertex_count = nv;
    m.indices = idx;
    m.triangle_count = nt;
    /* Without vertices, sometimes the positions as floats (a double
    ** beyond float's range becomes infinite: refused) and 16-bit
    ** indices, both as a game keeps them. */
    if (flags & 64) {
        for (i = 0; i < nv; i++) {
            fv[i].pos[0] = (float)v[i].x;
            fv[i].pos[1] = (float)v[i].y;
            fv[i].pos[2] = (float)v[i].z;
            fv[i].other[0] = fv[i].other[1] = 0;
        }
        m.positions = fv;
        m.position_stride = sizeof fv[0];
        m.position_type = RAY_FLOAT32;
    }
    if (flags & 128) {
        for (i = 0; i < 3 * nt; i++)
            idx16[i] = (uint16_t)idx[i];
        m.indices = NULL;
        m.index_data = idx16;
        m.index_type = RAY_UINT16;
    }
    m.normals = flags & 2 ? nrm : NULL;
    m.texcoords = flags & 4 ? st : NULL;
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_mesh(p->scene, flags & 32 ? NULL : &m, mat, &id);
    added_geometry(p, rc, &id, nt, "ray_scene_add_mesh");
}

static void op_torus(prog *p)
{
    ray_torus_params *t = &p->torus[p->slot];
    unsigned id, mat;
    int rc;

    t->center = fuzz_vec3(&p->in);
    t->axis = fuzz_vec3(&p->in);
    t->major = fuzz_double(&p->in);
    t->minor = fuzz_double(&p->in);
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_torus(p->scene, t, mat, &id);
    added_geometry(p, rc, &id, 0, "ray_scene_add_torus");
}

/* An implicit sphere (exact distance), torus or pair of blobs. */
static void op_implicit(prog *p)
{
    unsigned s = p->slot, kind = fuzz_u8(&p->in) % 3, id, mat;
    ray_implicit_surface surf;
    int rc = RAY_OK;

    memset(&surf, 0, sizeof surf);
    if (kind == 0) {
        p->sphere[s].c = fuzz_vec3(&p->in);
        p->sphere[s].r = fuzz_double(&p->in);
        surf.f = sphere_f;
        surf.ud = &p->sphere[s];
        surf.lo = fuzz_vec3(&p->in);
        surf.hi = fuzz_vec3(&p->in);
        surf.lipschitz = fuzz_u8(&p->in) & 1 ? 1.0 : 0.0;
    } else if (kind == 1) {
        p->torus[s].center = fuzz_vec3(&p->in);
        p->torus[s].axis = fuzz_vec3(&p->in);
        p->torus[s].major = fuzz_double(&p->in);
        p->torus[s].minor = fuzz_double(&p->in);
        rc = ray__implicit_torus(&p->torus[s], &surf);
        FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL, "ray__implicit_torus");
    } else {
        unsigned k;
        for (k = 0; k < 2; k++) {
            p->blobs[s][k].center = fuzz_vec3(&p->in);
            p->blobs[s][k].radius = fuzz_double(&p->in);
            p->blobs[s][k].strength = fuzz_double(&p->in);
        }
        p->blob_params[s].blobs = p->blobs[s];
        p->blob_params[s].count = 1 + (fuzz_u8(&p->in) & 1);
        p->blob_params[s].threshold = fuzz_double(&p->in);
        rc = ray_implicit_blobs(&p->blob_params[s], &surf);
        FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL, "ray_implicit_blobs");
    }
    if (rc != RAY_OK)
        return;
    /* Few evaluations: the fuzzer's inputs must stay fast. */
    surf.max_iterations = 1 + fuzz_below(&p->in, 2000);
    if (fuzz_u8(&p->in) & 1)
        surf.tolerance = fuzz_double(&p->in);
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_implicit(p->scene, &surf, mat, &id);
    added_geometry(p, rc, &id, 0, "ray_scene_add_implicit");
    if (rc == RAY_OK)
        p->curved = 1;
}

static void op_parametric(prog *p)
{
    unsigned s = p->slot, id, mat;
    ray_parametric_surface surf;
    int rc;

    memset(&surf, 0, sizeof surf);
    p->sphere[s].c = fuzz_vec3(&p->in);
    p->sphere[s].r = fuzz_double(&p->in);
    surf.eval = sphere_eval;
    surf.bounds = sphere_bounds;
    surf.ud = &p->sphere[s];
    if (fuzz_u8(&p->in) & 1) {
        surf.u0 = fuzz_double(&p->in);
        surf.u1 = fuzz_double(&p->in);
        surf.v0 = fuzz_double(&p->in);
        surf.v1 = fuzz_double(&p->in);
    }
    surf.subdivisions = fuzz_below(&p->in, 6);
    surf.max_iterations = fuzz_below(&p->in, 32);
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_parametric(p->scene, &surf, mat, &id);
    added_geometry(p, rc, &id, 0, "ray_scene_add_parametric");
    if (rc == RAY_OK)
        p->curved = 1;
}

/* A patch: a flat 4 x 4 grid of spacing h, each point nudged. */
static void op_bezier(prog *p)
{
    ray_vec3 *cp = p->bezier[p->slot], origin = fuzz_vec3(&p->in);
    double h = fuzz_double(&p->in);
    unsigned i, id, mat;
    int rc;

    for (i = 0; i < 16; i++) {
        cp[i].x = origin.x + h * (i % 4);
        cp[i].y = origin.y + h * (i / 4);
        cp[i].z = origin.z;
    }
    for (i = fuzz_below(&p->in, 4); i > 0; i--) {
        ray_vec3 d = fuzz_vec3(&p->in);
        unsigned k = fuzz_below(&p->in, 16);
        cp[k].x += d.x;
        cp[k].y += d.y;
        cp[k].z += d.z;
    }
    mat = decode_material(p);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_bezier(p->scene, cp, mat, &id);
    added_geometry(p, rc, &id, 0, "ray_scene_add_bezier");
    if (rc == RAY_OK)
        p->curved = 1;
}

static void op_light(prog *p)
{
    ray_light l;
    unsigned id;
    int rc;

    l.kind = (int)fuzz_below(&p->in, 5) - (fuzz_u8(&p->in) == 255);
    l.position = fuzz_vec3(&p->in);
    l.direction = fuzz_vec3(&p->in);
    l.edge1 = fuzz_vec3(&p->in);
    l.edge2 = fuzz_vec3(&p->in);
    l.radius = fuzz_double(&p->in);
    l.intensity = fuzz_rgb(&p->in);
    /* Few samples, or just over the documented bound. */
    l.samples = fuzz_u8(&p->in) == 255 ? RAY_MAX_LIGHT_SAMPLES + 1
                                        : fuzz_below(&p->in, 10);
    fuzz_sentinel(&id, sizeof id);
    rc = ray_scene_add_light(p->scene, fuzz_u8(&p->in) == 255 ? NULL : &l,
                             &id);
    if (check_build(p, rc, &id, p->n_lights, "ray_scene_add_light"))
        p->n_lights++;
}

static void op_setting(prog *p, unsigned which)
{
    ray_limits lim;
    int rc;

    switch (which) {
    case 0:
        p->background = fuzz_rgb(&p->in);
        rc = ray_scene_set_background(p->scene, p->background, NULL, NULL);
        break;
    case 1:
        p->background.r = p->background.g = p->background.b =
            fuzz_unit_range(&p->in, 1);
        rc = ray_scene_set_background(
            p->scene, p->background,
            fuzz_u8(&p->in) & 1 ? background_fn : NULL, &p->background);
        break;
    case 2:
        rc = ray_scene_set_ambient(p->scene, fuzz_rgb(&p->in));
        break;
    case 3:
        lim.max_depth = fuzz_below(&p->in, RAY_MAX_DEPTH + 4);
        lim.min_weight = fuzz_double(&p->in);
        lim.max_fanout = fuzz_below(&p->in, 6);
        lim.no_pruning = 0;
        rc = ray_scene_set_limits(p->scene, fuzz_u8(&p->in) & 1 ? NULL : &lim);
        break;
    case 4:
        /* The naive mode (the input's byte as before: the corpus keeps
        ** its meaning), with the default bounds. */
        ray_limits_init(&lim);
        lim.no_pruning = (int)fuzz_u8(&p->in) - 1;
        rc = ray_scene_set_limits(p->scene, &lim);
        break;
    default:
        rc = ray_scene_set_watertight(p->scene, (int)fuzz_u8(&p->in) - 1);
        break;
    }
    check_build(p, rc, NULL, 0, "ray_scene_set_*");
}

static void op_commit(prog *p)
{
    int rc = ray_scene_commit(p->scene);

    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM, "ray_scene_commit: status");
    FUZZ_CHECK(rc == RAY_OK || !p->committed,
               "ray_scene_commit: nothing staged, nothing to fail");
    if (rc == RAY_OK) {
        p->committed = 1;
        FUZZ_CHECK(ray_scene_light_count(p->scene) == p->n_lights,
                   "ray_scene_light_count");
    }
}

/* ------------------------------------------------------------ queries */

static void op_closest(prog *p, const ray_ray *r);

static void op_query(prog *p)
{
    ray_ray r = fuzz_ray(&p->in);
    ray_hit hit;
    int rc, occ;

    fuzz_sentinel(&hit, sizeof hit);
    rc = ray_intersect(p->scene, &r, &hit, NULL);
    occ = ray_occluded(p->scene, &r, NULL);
    op_closest(p, &r);
    if (!p->committed) {
        FUZZ_CHECK(rc == -RAY_ESTATE && occ == -RAY_ESTATE,
                   "ray_intersect: -RAY_ESTATE before commit");
        FUZZ_CHECK(fuzz_untouched(&hit, sizeof hit), "ray_intersect");
        return;
    }
    FUZZ_CHECK(rc == 0 || rc == 1, "ray_intersect: 1 or 0");
    FUZZ_CHECK(occ == 0 || occ == 1, "ray_occluded: 1 or 0");
    if (rc == 0) {
        FUZZ_CHECK(fuzz_untouched(&hit, sizeof hit),
                   "ray_intersect: a miss leaves *hit untouched");
    } else {
        fuzz_check_hit(&r, &hit, 1, "ray_intersect");
        FUZZ_CHECK(hit.geom_id < p->n_geoms, "ray_intersect: geom_id");
        FUZZ_CHECK(!p->hidden[hit.geom_id],
                   "ray_intersect: disabled, removed or masked geometry");
        FUZZ_CHECK(hit.inst_id == RAY_INVALID_ID, "ray_intersect: inst_id");
        FUZZ_CHECK(p->geom_tris[hit.geom_id] ? hit.prim_id <
                                                   p->geom_tris[hit.geom_id]
                                             : hit.prim_id == 0,
                   "ray_intersect: prim_id");
    }
    /* Root finders may fail on one interval and not on another. */
    if (!p->curved)
        FUZZ_CHECK(rc == occ, "ray_occluded agrees with ray_intersect");
    FUZZ_CHECK(ray_intersect(p->scene, NULL, &hit, NULL) == -RAY_EINVAL &&
                   ray_intersect(p->scene, &r, NULL, NULL) == -RAY_EINVAL &&
                   ray_occluded(NULL, &r, NULL) == -RAY_EINVAL,
               "ray_intersect: -RAY_EINVAL for NULL");
}

/* The closest point to the ray's origin within tmax (any value, so the
** refused ones too); reads no input of its own. */
static void op_closest(prog *p, const ray_ray *r)
{
    ray_closest c;
    int valid = isfinite(r->org.x) && isfinite(r->org.y) &&
                isfinite(r->org.z) && r->tmax >= 0;
    int rc;
    double n2;

    fuzz_sentinel(&c, sizeof c);
    rc = ray_closest_point(p->scene, r->org, r->tmax, &c);
    if (!valid || !p->committed) {
        FUZZ_CHECK(rc == (valid ? -RAY_ESTATE : -RAY_EINVAL),
                   "ray_closest_point: -RAY_EINVAL, then -RAY_ESTATE");
        FUZZ_CHECK(fuzz_untouched(&c, sizeof c), "ray_closest_point: refused");
        return;
    }
    FUZZ_CHECK(rc == 0 || rc == 1, "ray_closest_point: 1 or 0");
    if (rc == 0) {
        FUZZ_CHECK(fuzz_untouched(&c, sizeof c),
                   "ray_closest_point: nothing near leaves *out untouched");
        return;
    }
    n2 = c.n.x * c.n.x + c.n.y * c.n.y + c.n.z * c.n.z;
    FUZZ_CHECK(isfinite(c.p.x) && isfinite(c.p.y) && isfinite(c.p.z) &&
                   isfinite(c.distance) && c.distance >= 0 &&
                   c.distance <= r->tmax,
               "ray_closest_point: a finite point within the radius");
    FUZZ_CHECK(fabs(n2 - 1) < 1e-12, "ray_closest_point: unit normal");
    FUZZ_CHECK(c.geom_id < p->n_geoms, "ray_closest_point: geom_id");
    FUZZ_CHECK(p->geom_tris[c.geom_id] ? c.prim_id < p->geom_tris[c.geom_id]
                                       : c.prim_id == 0,
               "ray_closest_point: prim_id");
}

static void check_rgb_finite(const ray_rgb *c, const char *what)
{
    FUZZ_CHECK(isfinite(c->r) && isfinite(c->g) && isfinite(c->b), what);
}

static void op_trace(prog *p)
{
    ray_ray r = fuzz_ray(&p->in);
    ray_ctx *ctx;
    ray_rgb out;
    ray_stats st;
    int rc = ray_ctx_new(p->scene, 7, &ctx);

    if (!p->committed) {
        FUZZ_CHECK(rc == RAY_ESTATE, "ray_ctx_new: uncommitted scene");
        return;
    }
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM, "ray_ctx_new: status");
    if (rc != RAY_OK)
        return;
    fuzz_sentinel(&out, sizeof out);
    rc = ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &out);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ELIMIT || rc == RAY_EINVAL,
               "ray_trace: status");
    if (rc != RAY_OK)
        FUZZ_CHECK(fuzz_untouched(&out, sizeof out), "ray_trace: untouched");
    else
        check_rgb_finite(&out, "ray_trace: a finite colour");
    ray_ctx_stats(ctx, &st);
    ray_ctx_free(ctx);
}

/* ------------------------------------------------------------- render */

/* Whether u is exactly parallel to v (cross product exactly zero). */
/* v scaled by a power of two so its largest component is in [0.5, 1):
** exact, and it keeps the products below from underflowing (0.5 times
** the smallest subnormal rounds to 0, so (0, -0.5, 0) and (0, 0, -2^-1074)
** looked parallel: a reproducer in fuzz/crashes/fuzz_scene/). */
static ray_vec3 unit_scale(ray_vec3 v)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    int e;

    if (!(m > 0))
        return v;
    frexp(m, &e);
    v.x = ldexp(v.x, -e), v.y = ldexp(v.y, -e), v.z = ldexp(v.z, -e);
    return v;
}

static int exactly_parallel(ray_vec3 u, ray_vec3 v)
{
    /* Products of doubles are exact in long double only with a 106-bit
    ** mantissa; compare a*b with c*d through fma's exact residual. */
    double p1, p2;

    u = unit_scale(u);
    v = unit_scale(v);
#define SAME_PRODUCT(a, b, c, d) \
    (p1 = (a) * (b), p2 = (c) * (d), \
     p1 == p2 && fma(a, b, -p1) == fma(c, d, -p2))
    return SAME_PRODUCT(u.y, v.z, u.z, v.y) &&
           SAME_PRODUCT(u.z, v.x, u.x, v.z) &&
           SAME_PRODUCT(u.x, v.y, u.y, v.x);
#undef SAME_PRODUCT
}

/* a - b (both finite) has no rounding error: TwoSum's error term is 0
** (Knuth, TAOCP vol. 2, 4.2.2, Theorem B). */
static int exact_diff1(double a, double b, double *d)
{
    double s = a - b, bv = s - a, av = s - bv;
    *d = s;
    return isfinite(s) && (a - av) + (-b - bv) == 0;
}

/* The view a - b, if it is computed exactly. */
static int exact_sub(ray_vec3 a, ray_vec3 b, ray_vec3 *d)
{
    return exact_diff1(a.x, b.x, &d->x) && exact_diff1(a.y, b.y, &d->y) &&
           exact_diff1(a.z, b.z, &d->z);
}

typedef struct cancel_ud {
    unsigned after;
} cancel_ud;

static int progress_fn(void *ud, unsigned done, unsigned total)
{
    const cancel_ud *c = (const cancel_ud *)ud;
    FUZZ_CHECK(done <= total, "ray_render: progress");
    return done >= c->after;
}

static void op_render(prog *p)
{
    ray_camera cam;
    ray_render_options o;
    unsigned mode = fuzz_u8(&p->in) % 3, y;
    float rgb[3 * IMG_SIZE * IMG_SIZE];
    ray_stats st;
    ray_vec3 view;
    cancel_ud cancel;
    int rc;

    cam.position = fuzz_vec3(&p->in);
    cam.look_at = fuzz_vec3(&p->in);
    if (mode == 0) {
        cam.up = fuzz_vec3(&p->in);
    } else {
        /* The up vector along the view: defect 3's case when exact. */
        double k = fuzz_double(&p->in);
        cam.up.x = (cam.look_at.x - cam.position.x) * k;
        cam.up.y = (cam.look_at.y - cam.position.y) * k;
        cam.up.z = (cam.look_at.z - cam.position.z) * k;
    }
    cam.vfov = fuzz_u8(&p->in) & 1 ? fuzz_double(&p->in) : 60;
    cam.aperture = fuzz_u8(&p->in) & 1 ? fuzz_double(&p->in) : 0;
    cam.focus_distance = fuzz_u8(&p->in) & 1 ? fuzz_double(&p->in) : 0;
    o = (ray_render_options){.width = IMG_SIZE, .height = IMG_SIZE};
    o.threads = 1;
    o.samples = 1 + fuzz_below(&p->in, 2);
    o.seed = fuzz_u8(&p->in);
    o.y0 = fuzz_below(&p->in, IMG_SIZE + 1);
    o.y1 = fuzz_below(&p->in, IMG_SIZE + 2);
    if (fuzz_u8(&p->in) & 1) {
        o.adaptive_threshold = fuzz_double(&p->in);
        o.adaptive_depth = fuzz_below(&p->in, 4);
    }
    cancel.after = fuzz_below(&p->in, IMG_SIZE + 2);
    if (cancel.after < IMG_SIZE) {
        o.progress = progress_fn;
        o.progress_ud = &cancel;
    }
    fuzz_sentinel(rgb, sizeof rgb);
    fuzz_sentinel(&st, sizeof st);
    rc = ray_render(p->scene, &cam, &o, rgb, &st);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL || rc == RAY_ESTATE ||
                   rc == RAY_ENOMEM || rc == RAY_ECANCELED,
               "ray_render: status");
    if (!p->committed)
        FUZZ_CHECK(rc == RAY_ESTATE, "ray_render: uncommitted scene");
    {
        /* ray_render_check makes ray_render's checks: the same refusal,
        ** with a reason; no refusal where the render went ahead. */
        char why[160];
        int check = ray_render_check(p->scene, &cam, &o, NULL, why,
                                     sizeof why);
        if (rc == RAY_EINVAL || rc == RAY_ESTATE)
            FUZZ_CHECK(check == rc && why[0] != '\0',
                       "ray_render_check: the render's refusal, with a reason");
        else
            FUZZ_CHECK(check == RAY_OK && why[0] == '\0',
                       "ray_render_check: no refusal where the render ran");
        /* Asked for warnings too: the same status (a warning is not an
        ** error), *warnings written on RAY_OK alone, only known bits,
        ** and words exactly when there are bits. */
        {
            unsigned w = 0xdeadu;
            int again = ray_render_check(p->scene, &cam, &o, &w, why,
                                         sizeof why);
            FUZZ_CHECK(again == check, "ray_render_check: warnings change "
                       "no status");
            if (again != RAY_OK)
                FUZZ_CHECK(w == 0xdeadu, "ray_render_check: warnings "
                           "untouched on a refusal");
            else
                FUZZ_CHECK((w & ~(RAY_RENDER_WARN_UNLIT |
                                  RAY_RENDER_WARN_EMPTY |
                                  RAY_RENDER_WARN_EYE_INSIDE)) == 0 &&
                               (w != 0) == (why[0] != '\0'),
                           "ray_render_check: known warnings, named");
        }
    }
    if (rc == RAY_EINVAL || rc == RAY_ESTATE || rc == RAY_ENOMEM) {
        FUZZ_CHECK(fuzz_untouched(rgb, sizeof rgb) &&
                       fuzz_untouched(&st, sizeof st),
                   "ray_render: outputs untouched on error");
        return;
    }
    if (exact_sub(cam.look_at, cam.position, &view)) {
        /* up (0, 0, 0) is the default, +y (issue 37): the up the render
        ** used. */
        ray_vec3 up = cam.up;
        if (up.x == 0 && up.y == 0 && up.z == 0)
            up = ray_vec3_make(0, 1, 0);
        FUZZ_CHECK(!exactly_parallel(up, view),
                   "ray_render: up parallel to the view is RAY_EINVAL");
    }
    if (rc != RAY_OK)
        return;
    for (y = 0; y < 3 * IMG_SIZE * ((o.y1 ? o.y1 : IMG_SIZE) - o.y0); y++) {
        FUZZ_CHECK(isfinite(rgb[y]), "ray_render: finite pixels");
    }
}

/* ------------------------------------------------------------ driver */

enum {
    OP_MATERIAL, OP_SPHERE, OP_PLANE, OP_TRIANGLE, OP_POLYGON, OP_MESH,
    OP_TORUS, OP_IMPLICIT, OP_PARAMETRIC, OP_BEZIER, OP_LIGHT, OP_SETTING,
    OP_COMMIT, OP_QUERY, OP_TRACE, OP_RENDER, OP_NULL_SCENE, OP_DYNAMIC,
    OP_COUNT
};

/* Building calls on a NULL scene: RAY_EINVAL, nothing written. */
/*
** Changes after adding: enable, disable, remove (twice is an error), a
** mask of all bits or none.  Geometry ids may be out of range (an error
** that changes nothing).
*/
static void op_dynamic(prog *p)
{
    unsigned what = fuzz_u8(&p->in) % 4, g = fuzz_u8(&p->in);
    int rc, valid = g < p->n_geoms && !p->removed[g];

    switch (what) {
    case 0:
        rc = ray_scene_set_enabled(p->scene, g, 0);
        break;
    case 1:
        rc = ray_scene_set_enabled(p->scene, g, 1);
        break;
    case 2:
        rc = ray_scene_remove(p->scene, g);
        break;
    default:
        p->mask_zero = fuzz_u8(&p->in) & 1;
        rc = ray_scene_set_mask(p->scene, g, p->mask_zero ? 0u : ~0u);
        break;
    }
    FUZZ_CHECK(rc == (valid ? RAY_OK : RAY_EINVAL), "dynamic: status");
    FUZZ_CHECK((rc == RAY_OK) == (ray_scene_errmsg(p->scene)[0] == '\0'),
               "dynamic: message");
    if (rc != RAY_OK)
        return;
    /* Setting the enabled flag it has stages nothing; every other
    ** success is a change staged for the next commit. */
    if (what > 1 || p->disabled[g] != (what == 0))
        p->committed = 0;
    if (what == 2)
        p->removed[g] = 1;
    else if (what < 2)
        p->disabled[g] = what == 0;
    else
        p->masked[g] = rc == RAY_OK && p->mask_zero;
    p->hidden[g] = p->removed[g] || p->disabled[g] || p->masked[g];
}

static void op_null_scene(prog *p)
{
    unsigned id;
    ray_vec3 o = {0, 0, 0};
    fuzz_sentinel(&id, sizeof id);
    FUZZ_CHECK(ray_scene_add_sphere(NULL, o, 1, 0, &id) == RAY_EINVAL &&
                   ray_scene_commit(NULL) == RAY_EINVAL &&
                   fuzz_untouched(&id, sizeof id) &&
                   strcmp(ray_scene_errmsg(NULL), "no scene (NULL)") == 0,
               "NULL scene: RAY_EINVAL");
    (void)p;
}

static void run_op(prog *p, unsigned op)
{
    switch (op) {
    case OP_MATERIAL: op_material(p); break;
    case OP_SPHERE: op_sphere_plane_triangle(p, 0); break;
    case OP_PLANE: op_sphere_plane_triangle(p, 1); break;
    case OP_TRIANGLE: op_sphere_plane_triangle(p, 2); break;
    case OP_POLYGON: op_polygon(p); break;
    case OP_MESH: op_mesh(p); break;
    case OP_TORUS: op_torus(p); break;
    case OP_IMPLICIT: op_implicit(p); break;
    case OP_PARAMETRIC: op_parametric(p); break;
    case OP_BEZIER: op_bezier(p); break;
    case OP_LIGHT: op_light(p); break;
    case OP_SETTING: op_setting(p, fuzz_u8(&p->in) % 6); break;
    case OP_COMMIT: op_commit(p); break;
    case OP_QUERY: op_query(p); break;
    case OP_TRACE: op_trace(p); break;
    case OP_RENDER: op_render(p); break;
    case OP_DYNAMIC: op_dynamic(p); break;
    default: op_null_scene(p); break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static prog p;       /* large; the fuzzer's state, not the library's */
    unsigned first, k;
    int rc;

    memset(&p, 0, sizeof p);
    p.in = fuzz_input_of(data, size);
    /* First byte: which allocation fails (>= 200: one of the first 56). */
    first = fuzz_u8(&p.in);
    p.alloc.fail_at = first >= 200 ? first - 199 : 0;
    rc = ray_scene_new(&p.scene, fuzz_alloc_fn, &p.alloc);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_ENOMEM, "ray_scene_new: status");
    if (rc != RAY_OK) {
        FUZZ_CHECK(p.alloc.live_blocks == 0, "ray_scene_new: no leak");
        return 0;
    }
    for (k = 0; k < MAX_OPS && fuzz_more(&p.in); k++, p.slot++)
        run_op(&p, fuzz_below(&p.in, OP_COUNT));
    if (!p.committed)
        op_commit(&p);
    for (k = 0; k < MAX_QUERIES && fuzz_more(&p.in); k++)
        op_query(&p);
    ray_scene_free(p.scene);
    FUZZ_CHECK(p.alloc.live_blocks == 0 && p.alloc.live_bytes == 0,
               "ray_scene_free: every allocation returned");
    return 0;
}
