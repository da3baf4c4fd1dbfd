/* SPDX-License-Identifier: MIT */
/*
** query.h -- the query layer: a query's gate (masks, filters, all hits)
** and the scene queries every layer above asks (intersect.c over the
** traversal template, traverse.h).
*/
#ifndef RAY_QUERY_H
#define RAY_QUERY_H

#include "scene/scene.h"

/* RAY__INLINE: inlined wherever called (the walk, traverse.h, into each
** caller, its "leaf" and "any" constant there, so that each copy keeps
** only its own branches; a query's set-up, slab.h, into the function
** that tests the scene's box before any frame of its own).
** RAY__NOINLINE: a function kept apart, its frame paid only by the calls
** that reach it. */
#if defined(__GNUC__)
#define RAY__INLINE inline __attribute__((always_inline))
#define RAY__NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define RAY__INLINE __forceinline
#define RAY__NOINLINE __declspec(noinline)
#else
#define RAY__INLINE inline
#define RAY__NOINLINE
#endif

/*
** A gated query's rules (ray_query, filters, ray_intersect_all): the
** ray's mask, the filters' query_ud, which filters apply
** (RAY_FILTER_INTERSECT or _OCCLUDED), and for ray_intersect_all the
** collector that every accepted candidate goes to (then rejected, so the
** traversal goes on).
*/
/*
** The work of the queries, counted in the bench's counted build alone
** (make bench-counts: the library compiled with -DRAY_BENCH_COUNTS, for
** bench/raycost's work-per-ray table, issue 34): inner nodes tested,
** triangle leaves reached, triangles through the float filter, exact
** tests.  Global counters, so never in the library proper, which keeps
** no global state: there RAY__WORK is nothing.
*/
#ifdef RAY_BENCH_COUNTS
enum { RAY__WORK_NODES, RAY__WORK_LEAVES, RAY__WORK_FILTERED,
       RAY__WORK_EXACT, RAY__WORK_KINDS };
extern unsigned long long ray__work[RAY__WORK_KINDS];
#define RAY__WORK(kind, n) (ray__work[kind] += (n))
#else
#define RAY__WORK(kind, n) ((void)0)
#endif

typedef struct ray__collect {
    ray_hit *hits;
    size_t cap, count;
} ray__collect;

typedef struct ray__gate {
    unsigned mask;
    void *query_ud;
    unsigned query;
    ray__collect *all;
} ray__gate;

/* ------------------------------------------------------------ the queries */

/* Whether q lies in one of s's solids (contains.c says which count):
** ray_render_check's test of the camera's eye. */
int ray__solid_holds(const ray_scene *s, ray_vec3 q);

/* ray_contains, its reasons (ray_contains_options.why) given in the name
** of op: ray_contains, ray_signed_distance or ray_distance_grid. */
int ray__contains_run(const ray_scene *s, const ray_vec3 *points, size_t n,
                      const ray_contains_options *o, ray_inside *out,
                      const char *op);

/* ray_signed_distance at finite q for a caller that ran
** ray__contains_run(s, .., o, ..) and had RAY_OK: its checks passed and
** what the answers read is made (ray_distance_grid's samples), so none
** of its locks is taken again; ray_signed_distance's answers. */
int ray__signed_distance_at(const ray_scene *s, ray_vec3 q, double radius,
                            const ray_contains_options *o, double *distance,
                            ray_closest *closest);

/*
** The generalized winding number's parts (winding.c), as sums of signed
** solid angles (4 pi per turn) at the world point qw of scene s's
** triangles, their corners taken to world space through instance "in"
** (NULL: s is the top scene).  all: every triangle; else those of single
** triangles and open meshes (not a closed mesh's: ray__closed_ensure
** first).
** ray__solid_angle -- one triangle's (Van Oosterom and Strackee).
** ray__winding_exact -- summed over every live triangle whose geometry
** is enabled and has a mask bit outside "ignore".
** ray__wexp_ensure -- the expansions of s and of its instances'
** children made, where their queries need them (all: any triangle),
** under each scene's lock: RAY_OK or RAY_ENOMEM (a later call tries
** again).
** ray__winding_fast -- through the BVH and the expansions, every
** triangle of the class counted (the caller checks that no mask leaves
** one out): 1 with *angle set, or 0 where s has no expansions (no lock
** made them), nothing set.
*/
double ray__solid_angle(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 q);
double ray__winding_exact(const ray_scene *s, ray_vec3 qw,
                          const ray__instance *in, unsigned ignore, int all);
int ray__wexp_ensure(const ray_scene *s, int all);
int ray__winding_fast(const ray_scene *s, ray_vec3 qw,
                      const ray__instance *in, int all, double *angle);

/*
** Nearest hit / any hit over the scene, counting intersection tests, in
** all and by kind of primitive, into *st (may be NULL), with the
** scene's filters of that kind of query: ray_trace's and the shadow
** rays' queries.  uv: 1 fills every field of the hit; 0 (a render)
** leaves a sphere's texture coordinates 0 (an atan2 and an acos saved per
** hit) unless its material reads them (RAY_EFFECT_TEXTURE).
*/
int ray__intersect(const ray_scene *s, const ray_ray *r, int uv,
                   ray_hit *hit, ray_stats *st);
int ray__occluded(const ray_scene *s, const ray_ray *r, ray_stats *st);

/*
** ray__occluded for rays[0 .. n - 1] into out[0 .. n - 1]: the same
** answers, eight at a time through the packets where the scene, the CPU
** and the rays allow (ray_occluded_batch's choice: intersect.c), as a
** shading point's shadow rays towards one area light do.  The tests
** counted into *st are the packets' where they ran: the same rays' tests
** in another order, so their count may differ from one ray at a time.
*/
void ray__occluded_group(const ray_scene *s, const ray_ray *rays, size_t n,
                         int *out, ray_stats *st);

/* The queries come in two copies, for the baseline instruction set and
** for AVX2 (x86 with GCC, Clang or MSVC, intersect_avx2.c built with
** -mavx2 or /arch:AVX2: RAY__AVX2_COPY), which ray__intersect and
** ray__occluded choose between (below); the tests compare the two. */
#if ((defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))) || \
     (defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86)))) && \
    !defined(RAY_NO_SIMD) && !defined(RAY_NO_AVX2)
#define RAY__AVX2_COPY 1
#else
#define RAY__AVX2_COPY 0
#endif

/* Can ray__packets_avx2 take scene s with gate g (NULL: none)?  No gate,
** and triangles alone (the packets settle ties between triangles only:
** packet.h), or for any hit (no ties) planes and a few spheres beside
** them (s->few_spheres, which a scene of triangles alone has too; no
** other kind, so no instances).  The one rule for the batch calls and
** for ray__occluded_group. */
static inline int ray__packable(const ray_scene *s, const ray__gate *g,
                                int any)
{
    return g == NULL && ((s->n_planes == 0 && s->prim_bvh.n_wide == 0) ||
                         (any && s->few_spheres));
}

/* Can ray__occluded_group take packets in scene s (on this CPU)?  Where
** it cannot, it is ray__occluded ray by ray.  Inline: ray_shade_direct
** asks once a light a hit. */
static inline int ray__occluded_packs(const ray_scene *s)
{
#if RAY__AVX2_COPY
    return s->avx2 && !s->gated && ray__packable(s, NULL, 1);
#else
    (void)s;
    return 0;
#endif
}

/*
** The queries with a gate (masks, filters, all hits: ray__gate; NULL for
** none, what ray__intersect and ray__occluded pass a scene without masks
** or filters), in both copies.  They return 1 (hit), 0, or -RAY_ESTATE when an
** instance met a child changed since the commit.
*/
int ray__intersect_gated(const ray_scene *s, const ray_ray *r,
                         const ray__gate *g, int uv, ray_hit *hit,
                         ray_stats *st);
int ray__occluded_gated(const ray_scene *s, const ray_ray *r,
                        const ray__gate *g, ray_stats *st);
int ray__intersect_gated_base(const ray_scene *s, const ray_ray *r,
                              const ray__gate *g, int uv, ray_hit *hit,
                              ray_stats *st);
int ray__occluded_gated_base(const ray_scene *s, const ray_ray *r,
                             const ray__gate *g, ray_stats *st);
int ray__intersect_gated_avx2(const ray_scene *s, const ray_ray *r,
                              const ray__gate *g, int uv, ray_hit *hit,
                              ray_stats *st);
int ray__occluded_gated_avx2(const ray_scene *s, const ray_ray *r,
                             const ray__gate *g, ray_stats *st);

/*
** The plain queries of a scene of triangles alone (no planes, no bounded
** kinds, no masks or filters: traverse.h's query_nearest_tris), in both
** copies: ray_intersect's and ray_occluded's fast path, the same answers
** as the general queries'.
*/
int ray__intersect_tris_base(const ray_scene *s, const ray_ray *r,
                             ray_hit *hit);
int ray__occluded_tris_base(const ray_scene *s, const ray_ray *r);
int ray__intersect_tris_avx2(const ray_scene *s, const ray_ray *r,
                             ray_hit *hit);
int ray__occluded_tris_avx2(const ray_scene *s, const ray_ray *r);

/* The ungated queries, counted or not, of a scene of planes, a few
** spheres and triangles alone (ray_scene's few_spheres: plain.h's
** query_nearest_few), in both copies: the tracer's path. */
int ray__intersect_few_base(const ray_scene *s, const ray_ray *r, int uv,
                            ray_hit *hit, ray_stats *st);
int ray__occluded_few_base(const ray_scene *s, const ray_ray *r,
                           ray_stats *st);
int ray__intersect_few_avx2(const ray_scene *s, const ray_ray *r, int uv,
                            ray_hit *hit, ray_stats *st);
int ray__occluded_few_avx2(const ray_scene *s, const ray_ray *r,
                           ray_stats *st);

/* The same for a scene of instances alone, each of a child of triangles
** alone, ungated (ray_scene's instances_of_tris: traverse.h's
** query_nearest_instances). */
int ray__intersect_instances_base(const ray_scene *s, const ray_ray *r,
                                  ray_hit *hit);
int ray__occluded_instances_base(const ray_scene *s, const ray_ray *r);
int ray__intersect_instances_avx2(const ray_scene *s, const ray_ray *r,
                                  ray_hit *hit);
int ray__occluded_instances_avx2(const ray_scene *s, const ray_ray *r);

/*
** A ray's traversal data (slab.h's trav_init) as each copy computes it,
** for the tests (the AVX set-up against the baseline's, bit for bit):
** f[0..2] the origin's near ends, f[3..5] its far ends, f[6..8] the
** reciprocals, f[9] tmin, f[10..12] the far distances' grown
** reciprocals (FAR_GROW), all as their float bits; at[0..2] the near
** offsets, at[3..5] the far ones.  r must pass ray__ray_usable.
*/
void ray__trav_data_base(const ray_ray *r, uint32_t f[13], size_t at[6]);
void ray__trav_data_avx2(const ray_ray *r, uint32_t f[13], size_t at[6]);

/*
** ray_intersect_batch and ray_occluded_batch's packets (packet.h): n rays of a
** scene that ray__packable accepts, eight at a time; results[i] (and
** hits[i] unless "any") as the single-ray queries give them.  AVX2 copy
** only.
*/
void ray__packets_avx2(const ray_scene *s, const ray_ray *rays, size_t n,
                       ray_hit *hits, int *results, int any, ray_stats *st);

#endif /* RAY_QUERY_H */
