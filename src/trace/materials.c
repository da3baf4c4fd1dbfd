/* SPDX-License-Identifier: MIT */
/*
** materials.c -- the built-in materials.  Written against the public API
** (ray.h), so they double as examples of material callbacks, but for
** v3_normalize and the inlining hints where a direction's length could
** overflow (unit, below); the one internal function, at the end, answers
** which of them can read a ray's cone (ray__material_reads_cone,
** trace.h).
*/
#include <float.h>
#include <math.h>

#include "trace/trace.h"

/* ray.h's helpers, under the short names this file uses. */
#define rgb ray_rgb_make
#define dot ray_vec3_dot

/*
** |a|^2 overflows for |a| past about 1.3e154 and underflows to 0 or a
** denormal below about 1.5e-154, though ray_trace takes any finite,
** non-zero direction.  There (and only there: an ordinary direction
** keeps its bits) a is first divided by its largest |component|, which
** brings |a| into [1, sqrt 3]: v3_normalize (src/core/vec.h) for a unit
** vector; travelled scales t |a| the same way, as (t m) |a / m|, which
** stays finite where |a| alone would not (ray__distance's m |a / m|
** overflows for components near DBL_MAX).  The unusual case out of
** line, so that the ordinary case's two compares stay inline.
*/
static int ordinary(double len2)
{
    return len2 < HUGE_VAL && len2 >= DBL_MIN;
}

static double largest(ray_vec3 a)
{
    double m = fabs(a.x) > fabs(a.y) ? fabs(a.x) : fabs(a.y);
    return m > fabs(a.z) ? m : fabs(a.z);
}

static RAY__NOINLINE ray_vec3 unit_scaled(ray_vec3 a)
{
    ray_vec3 u = a;

    (void)v3_normalize(a, &u);     /* a is finite and non-zero */
    return u;
}

static RAY__INLINE ray_vec3 unit(ray_vec3 a)
{
    double len2 = dot(a, a), len;

    if (!ordinary(len2))
        return unit_scaled(a);
    len = sqrt(len2);
    return ray_vec3_make(a.x / len, a.y / len, a.z / len);
}

/* t |dir|, the distance a ray went to its hit at t, without forming
** |dir|^2 where it overflows or underflows (as unit). */
static double travelled(double t, ray_vec3 dir)
{
    double len2 = dot(dir, dir), m;

    if (ordinary(len2))
        return t * sqrt(len2);
    m = largest(dir);
    dir = ray_vec3_make(dir.x / m, dir.y / m, dir.z / m);
    return t * m * sqrt(dot(dir, dir));
}

/* The parameter blocks are only read, but ray_material.ud is a plain
** void * (user materials may keep mutable state there): drop the const
** through a union rather than a cast that hides it from the compiler. */
static void *unconst(const void *p)
{
    union {
        const void *c;
        void *m;
    } u;
    u.c = p;
    return u.m;
}

/* fmax(c.r, fmax(c.g, c.b)), inline: libm's fmax is a call (issue 35).
** a > b || b != b ? a : b is fmax's answer bit for bit: a NaN gives the
** other operand, two NaNs the first, a tie (+0 and -0 included) the
** second, as glibc's x86-64 fmax (maxsd) answers (src/core/vec.h's
** ray__fmax; this file keeps to the public header). */
static double max2(double a, double b)
{
    return a > b || b != b ? a : b;
}

static double max3(ray_rgb c)
{
    return max2(c.r, max2(c.g, c.b));
}

/* out += k * c (component-wise). */
static void add_product(ray_rgb *out, ray_rgb k, ray_rgb c)
{
    out->r += k.r * c.r;
    out->g += k.g * c.g;
    out->b += k.b * c.b;
}

/*
** Trace the mirror reflection of the incoming ray, weighted by the
** reflectance k, and add it to *out.  A zero reflectance casts no ray; a
** ray the tree's limits refuse adds nothing (the path is cut: black).
*/
static void add_reflection(ray_ctx *ctx, const ray_shade_args *a, ray_rgb k,
                           ray_rgb *out)
{
    ray_ray r;
    ray_rgb c;

    if (a->prune && !(max3(k) > 0))    /* nothing to reflect: spawn nothing */
        return;
    if (ray_spawn(a->hit, ray_reflect(a->ray->dir, a->normal), &r) != RAY_OK)
        return;
    if (ray_trace(ctx, &r, RAY_KIND_REFLECTION, max3(k), &c) == RAY_OK)
        add_product(out, k, c);
}

/* ------------------------------------------------------- Phong, Lambert */

/* The specular lobe for light direction l and view direction v. */
static double specular_term(const ray_phong_params *p, ray_vec3 n,
                            ray_vec3 l, ray_vec3 v)
{
    double c;

    if (p->blinn) {
        ray_vec3 h = {l.x + v.x, l.y + v.y, l.z + v.z};
        double len2 = dot(h, h);
        if (!(len2 > 0))
            return 0;
        c = dot(n, h) / sqrt(len2);
    } else {
        ray_vec3 r = ray_reflect(l, n);       /* l mirrored, sign flipped */
        c = -dot(r, v);
    }
    /* Zero is the default (ray.h): a cos^0 lobe is no highlight. */
    return c > 0 ? pow(c, p->shininess != 0 ? p->shininess
                                            : RAY_DEFAULT_SHININESS)
                 : 0;
}

/* The diffuse colour at the hit: the parameter, times the texture's
** colour there if the material has a texture (preset to white, so a
** texture that writes nothing leaves the colour as it is). */
static ray_rgb diffuse_at(const ray_phong_params *p, const ray_shade_args *a)
{
    ray_rgb t = rgb(1, 1, 1);

    if (p->texture.fn == NULL)
        return p->diffuse;
    p->texture.fn(p->texture.ud, a, &t);
    return rgb(p->diffuse.r * t.r, p->diffuse.g * t.g, p->diffuse.b * t.b);
}

/* What phong_brdf needs beside the light sample: the parameters and the
** diffuse colour at this hit (the texture is read once per hit). */
typedef struct phong_hit {
    const ray_phong_params *p;
    ray_rgb diffuse;
} phong_hit;

/* diffuse * n.l + specular * lobe: the factor of one light sample's
** radiance (ray_shade_direct calls it only when n.l > 0). */
static ray_rgb phong_brdf(void *ud, const ray_brdf_args *b)
{
    const phong_hit *h = ud;
    double ndotl = b->cos_light;
    double spec = specular_term(h->p, b->shade->shading_normal, b->to_light,
                                b->to_eye);

    return rgb(h->diffuse.r * ndotl + h->p->specular.r * spec,
               h->diffuse.g * ndotl + h->p->specular.g * spec,
               h->diffuse.b * ndotl + h->p->specular.b * spec);
}

/* phong_brdf where the specular colour is all +-0 (a Lambertian surface:
** the Cornell box's walls), without the lobe, whose pow was 5% of that
** render's instructions: 0 for the lobe gives the same sum (+-0 times a
** finite lobe is the same +-0), but where the lobe was Inf (a shininess
** near DBL_MAX at a cosine an ulp above 1), whose product was NaN. */
static ray_rgb lambert_brdf(void *ud, const ray_brdf_args *b)
{
    const phong_hit *h = ud;
    double ndotl = b->cos_light;

    return rgb(h->diffuse.r * ndotl + h->p->specular.r * 0.0,
               h->diffuse.g * ndotl + h->p->specular.g * 0.0,
               h->diffuse.b * ndotl + h->p->specular.b * 0.0);
}

/* Phong's BRDF, or Lambert's where the specular colour is all +-0. */
static ray_brdf_fn brdf_of(const ray_phong_params *p)
{
    return fabs(p->specular.r) + fabs(p->specular.g) + fabs(p->specular.b) ==
                   0
               ? lambert_brdf
               : phong_brdf;
}

/*
** A photon's mirror bounce, shared by the mirror and Phong's reflect
** term: the direction ray_reflect gives and the reflectance as the
** weight (no roulette: the weight carries the loss, as the camera's
** reflection ray does).  A reflectance with no positive channel stops it.
*/
static int reflect_photon(const ray_shade_args *a, ray_rgb k, ray_vec3 *dir,
                          ray_rgb *weight)
{
    if (!(max3(k) > 0))
        return 0;
    *dir = ray_reflect(a->ray->dir, a->normal);
    *weight = k;
    return 1;
}

static void phong_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                        ray_rgb *out)
{
    phong_hit h;
    ray_rgb e;

    if (ud == NULL)
        return;
    h.p = ud;
    h.diffuse = diffuse_at(h.p, a);
    add_product(out, a->ambient, h.diffuse);
    (void)ray_shade_direct(ctx, a, brdf_of(h.p), &h, out); /* cannot fail */
    /* Caustics: E is the photons' irradiance, in the units of the direct
    ** term's intensity * n.l / r^2 (ray_caustics_at), so diffuse * E is
    ** as bright as the direct light the caustic focuses.  Zero without a
    ** photon map; then nothing is added (the bytes stay those of a render
    ** without caustics). */
    if (ray_caustics_at(ctx, a, &e) == RAY_OK && max3(e) > 0)
        add_product(out, e, h.diffuse);
    if (max3(h.p->reflect) > 0)
        add_reflection(ctx, a, h.p->reflect, out);
}

/* Phong with a mirror term: a photon goes on with weight "reflect"
** (and is also stored here: it declares RAY_EFFECT_CAUSTICS). */
static int phong_scatter(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_vec3 *dir, ray_rgb *weight)
{
    (void)ctx;
    return ud != NULL &&
           reflect_photon(a, ((const ray_phong_params *)ud)->reflect, dir,
                          weight);
}

ray_material ray_material_phong(const ray_phong_params *p)
{
    ray_material m;

    m.shade = phong_shade;
    m.ud = unconst(p);   /* borrowed */
    m.effects = RAY_EFFECT_SHADOW | RAY_EFFECT_CAUSTICS;
    m.scatter = NULL;
    if (p != NULL && max3(p->reflect) > 0) {
        m.effects |= RAY_EFFECT_REFLECTION | RAY_EFFECT_SCATTER;
        m.scatter = phong_scatter;
    }
    if (p != NULL && p->texture.fn != NULL)
        m.effects |= RAY_EFFECT_TEXTURE;
    return m;
}

/* ----------------------------------------------------------------- mirror */

static void mirror_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_rgb *out)
{
    if (ud != NULL)
        add_reflection(ctx, a, *(const ray_rgb *)ud, out);
}

static int mirror_scatter(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                          ray_vec3 *dir, ray_rgb *weight)
{
    (void)ctx;
    return ud != NULL && reflect_photon(a, *(const ray_rgb *)ud, dir, weight);
}

ray_material ray_material_mirror(const ray_rgb *reflectance)
{
    ray_material m;

    m.shade = mirror_shade;
    m.ud = unconst(reflectance);
    m.effects = RAY_EFFECT_REFLECTION | RAY_EFFECT_SCATTER;
    m.scatter = mirror_scatter;
    return m;
}

/* ------------------------------------------------------------------ glass */

/*
** A dielectric boundary.  eta = n_incident / n_transmitted: 1/ior when the
** ray enters the object, ior when it leaves.  The Fresnel reflectance F
** splits the ray into a reflected part (weight F) and a refracted one
** (1 - F); past the critical angle F = 1 (total internal reflection) and
** only the reflection is traced.  A ray that leaves the object has crossed
** it over the distance t |dir|, which Beer-Lambert attenuates by
** exp(-absorption * distance) per channel.  An ior of 0 is the default,
** 1.5 (window glass), so that a zeroed ray_glass_params is glass.
*/
static double glass_ior(const ray_glass_params *p)
{
    return p->ior == 0 ? 1.5 : p->ior;
}

static void glass_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                        ray_rgb *out)
{
    const ray_glass_params *p = ud;
    ray_vec3 d = unit(a->ray->dir), t;
    double eta, F;
    ray_ray r;
    ray_rgb c;

    if (p == NULL)
        return;
    eta = a->entering ? 1.0 / glass_ior(p) : glass_ior(p);
    F = ray_fresnel(-dot(d, a->normal), eta);
    add_reflection(ctx, a, rgb(F, F, F), out);
    if ((F < 1 || !a->prune) && ray_refract(d, a->normal, eta, &t) &&
        ray_spawn(a->hit, t, &r) == RAY_OK &&
        ray_trace(ctx, &r, RAY_KIND_REFRACTION, 1 - F, &c) == RAY_OK)
        add_product(out, rgb(1 - F, 1 - F, 1 - F), c);
    if (!a->entering) {
        double dist = travelled(a->hit->t, a->ray->dir);
        out->r *= exp(-p->absorption.r * dist);
        out->g *= exp(-p->absorption.g * dist);
        out->b *= exp(-p->absorption.b * dist);
    }
}

/*
** A photon at a dielectric boundary: reflected with probability F,
** refracted with 1 - F, weight 1 either way (Russian roulette: the
** expected power is F * 1 + (1 - F) * 1 of what a split photon would
** carry, without doubling the photons at every surface).  Leaving the
** object, Beer-Lambert's exp(-absorption * distance) is the weight, as
** glass_shade attenuates the camera's rays.
*/
static int glass_scatter(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_vec3 *dir, ray_rgb *weight)
{
    const ray_glass_params *p = ud;
    ray_vec3 d, t;
    double eta, F;

    if (p == NULL)
        return 0;
    d = unit(a->ray->dir);
    eta = a->entering ? 1.0 / glass_ior(p) : glass_ior(p);
    F = ray_fresnel(-dot(d, a->normal), eta);
    if (ray_ctx_random(ctx) < F || !ray_refract(d, a->normal, eta, &t))
        *dir = ray_reflect(a->ray->dir, a->normal);
    else
        *dir = t;
    *weight = rgb(1, 1, 1);
    if (!a->entering) {
        double dist = travelled(a->hit->t, a->ray->dir);
        *weight = rgb(exp(-p->absorption.r * dist),
                      exp(-p->absorption.g * dist),
                      exp(-p->absorption.b * dist));
    }
    return 1;
}

ray_material ray_material_glass(const ray_glass_params *p)
{
    ray_material m;

    m.shade = glass_shade;
    m.ud = unconst(p);
    m.effects = RAY_EFFECT_REFLECTION | RAY_EFFECT_REFRACTION |
                RAY_EFFECT_SCATTER;
    m.scatter = glass_scatter;
    return m;
}

/* ------------------------------------------------------------ checkerboard */

/*
** Is the sum of two floors odd: fabs(fmod(cell, 2.0)) == 1.0, the same
** answer, without libm's fmod call (80 instructions a floor hit in the
** Whitted render, issue 35) where an integer can take it.  Below 2^52 in
** magnitude, cell (a sum of integers, rounded to a double) is an integer
** that a long long holds exactly, and the remainder's parity is fmod's
** (exact for integers); -0 is even both ways.  From 2^52 up, a NaN or an
** infinity: fmod itself (u * scale may be huge or not finite).
*/
static int cell_is_odd(double cell)
{
    if (fabs(cell) < 0x1p52)
        return (long long)cell % 2 != 0;
    return fabs(fmod(cell, 2.0)) == 1.0;
}

/* The material of the square the hit lies in (scale 0: 1, so that {0}
** is a checkerboard). */
static const ray_material *checker_pick(const ray_checker_params *p,
                                        const ray_shade_args *a)
{
    double scale = p->scale != 0 ? p->scale : 1.0;
    double cell = floor(a->u * scale) + floor(a->v * scale);
    return cell_is_odd(cell) ? &p->odd : &p->even;
}

static void checker_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                          ray_rgb *out)
{
    const ray_material *m;

    if (ud == NULL)
        return;
    m = checker_pick(ud, a);
    if (m->shade != NULL)
        m->shade(m->ud, ctx, a, out);
}

/* A photon scatters as the square's material does (or stops there). */
static int checker_scatter(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                           ray_vec3 *dir, ray_rgb *weight)
{
    const ray_material *m;

    if (ud == NULL)
        return 0;
    m = checker_pick(ud, a);
    return (m->effects & RAY_EFFECT_SCATTER) && m->scatter != NULL &&
           m->scatter(m->ud, ctx, a, dir, weight);
}

ray_material ray_material_checker(const ray_checker_params *p)
{
    ray_material m;

    m.shade = checker_shade;
    m.ud = unconst(p);
    m.effects = RAY_EFFECT_TEXTURE |
                (p != NULL ? p->even.effects | p->odd.effects : 0);
    m.scatter = (m.effects & RAY_EFFECT_SCATTER) ? checker_scatter : NULL;
    return m;
}

/* --------------------------------------------------- who reads the cone */

/*
** Checkers nest (a square's material may be a checker itself, even the
** same one): past this depth the answer is "may read", which is always
** safe.
*/
#define CONE_NESTING_MAX 8

static int reads_cone(const ray_material *m, int depth)
{
    if (m->shade == mirror_shade || m->shade == glass_shade)
        return 0;
    if (m->shade == phong_shade) {
        const ray_phong_params *p = m->ud;
        return p != NULL && p->texture.fn != NULL;
    }
    if (m->shade == checker_shade) {
        const ray_checker_params *p = m->ud;
        if (p == NULL)
            return 0;
        if (depth >= CONE_NESTING_MAX)
            return 1;
        return (p->even.shade != NULL && reads_cone(&p->even, depth + 1)) ||
               (p->odd.shade != NULL && reads_cone(&p->odd, depth + 1));
    }
    return 1;       /* a user's callback may read cone_width and footprint */
}

/*
** Can material m read the cone a ray carries (ray_shade_args.cone_width
** and footprint)?  The built-in mirror and glass never do; a Phong
** material only through its texture function, a user's, which gets the
** args; a checker as its squares' materials do; any other material (a
** user's callback) may.  Asked of the params as they are now: they are
** borrowed and read at every shade, as the answer is asked at every
** render (render.c).
*/
int ray__material_reads_cone(const ray_material *m)
{
    return m != NULL && m->shade != NULL && reads_cone(m, 0);
}
