/* SPDX-License-Identifier: MIT */
/*
** instance.h -- part of the query template (traverse.h): an instance met
** by a query, as Embree's instance intersector sits in its traversal
** kernels.  The scene keeps the instance's record, transforms and world
** box (scene/instance.c); the query moves the ray into the child's space
** and descends into the child's planes and trees itself, in the same
** copy of the template (baseline or AVX2), with the parent's counts,
** gate and kind of query (nearest or any).
*/
#ifndef RAY_QUERY_INSTANCE_H
#define RAY_QUERY_INSTANCE_H

#include "query/slab.h"

/* An instance's child inside a parent's query: nearest or any as the
** parent's query is, with its counts and gate (defined in traverse.h,
** with the queries it recurses into). */
static int query_child(const ray_scene *child, ray_ray *r, ray_hit *hit,
                       ray__counts *qc);

/*
** Geometry idx of s, an instance, against world ray r: RAY__HIT_FULL
** with *hit filled -- the child's hit brought back to world space, its
** error bound grown by the rounding of both transforms
** (ray__instance_to_world), geom_id and prim_id the child's, inst_id idx;
** for an any-hit query only t, which is all it reads -- or 0 on a miss.
** A child changed since s was committed is a miss with qc->stale set (the
** query then answers -RAY_ESTATE).  Counted as one test of its kind
** (RAY_PRIM_INSTANCE, its column in RAY__PRIM_KINDS), as every bounded
** primitive's test is.  Inside, qc names the instance, so that the gate
** offers the child's candidates in world space.
*/
static int instance_hit(const ray_scene *s, unsigned idx, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc)
{
    const ray__instance *in = &s->instances[s->prims[idx].surface];
    const ray__instance *outer_inst = qc->inst;
    const ray_ray *outer_ray = qc->world_ray;
    unsigned outer_id = qc->inst_id;
    ray_ray ro;
    ray_hit h;
    int found;

    qc->tests[RAY_PRIM_INSTANCE]++;
    if (ray__instance_stale(in)) {
        qc->stale = 1;
        return 0;
    }
    ray__instance_ray_to_object(in, r, &ro);
    qc->inst = in;
    qc->inst_id = idx;
    qc->world_ray = r;
    found = query_child(in->child, &ro, &h, qc);
    qc->inst = outer_inst;
    qc->inst_id = outer_id;
    qc->world_ray = outer_ray;
    if (found <= 0)
        return 0;
    if (qc->any) {
        /* Any hit: only that there is one counts; t for the record. */
        memset(hit, 0, sizeof *hit);
        hit->t = ro.tmax;
        return RAY__HIT_FULL;
    }
    ray__instance_to_world(in, &h, hit);
    hit->inst_id = idx;
    return RAY__HIT_FULL;
}

#endif /* RAY_QUERY_INSTANCE_H */
