/* SPDX-License-Identifier: MIT */
/*
** gate.h -- part of the query template (traverse.h): a gated query's
** candidates (masks, filters, all hits) offered in world space.
*/
#ifndef RAY_GATE_H
#define RAY_GATE_H

#include "query/slab.h"

/*
** Gates (ray__gate: masks, filters, all hits), on the gated path only: a
** query without a gate never reaches them.
**
** gate_wants -- does candidate of geometry p need a hit record: a filter
** that applies to this query, or a collector?
** gate_offer -- offer candidate h of geometry p (in the space of the
** query's current scene: object space inside an instance) to its filter
** and the collector, in world space: 1 accepted, 0 rejected.  Collected
** hits are rejected after being recorded, so the traversal goes on and
** finds them all.
*/
static int gate_wants(const ray__prim *p, const ray__gate *g)
{
    return g->all != NULL ||
           (p->filter != NULL && (p->filter_queries & g->query) != 0);
}

/* Keep the cap nearest hits: a new one takes the place of the farthest
** kept when there is no room (hits order by t, then ids: collect_before). */
static int collect_before(const ray_hit *a, const ray_hit *b)
{
    if (a->t != b->t)
        return a->t < b->t;
    if (a->geom_id != b->geom_id)
        return a->geom_id < b->geom_id;
    if (a->prim_id != b->prim_id)
        return a->prim_id < b->prim_id;
    return a->inst_id < b->inst_id;
}

static void collect(ray__collect *c, const ray_hit *h)
{
    size_t i, worst = 0;

    if (c->count < c->cap) {
        ray__hit_store(&c->hits[c->count], h);
    } else if (c->cap > 0) {
        for (i = 1; i < c->cap; i++)
            if (collect_before(&c->hits[worst], &c->hits[i]))
                worst = i;
        if (collect_before(h, &c->hits[worst]))
            ray__hit_store(&c->hits[worst], h);
    }
    c->count++;
}

/*
** The filter is handed the query's ray with tmax shrunk to the nearest
** hit kept so far, which a candidate may tie (two triangles of a shared
** edge hit at the same t: leaf.h's tri_limit lets the tie through to be
** settled by ids).  A ray is the open interval, so such a candidate
** would lie outside the ray it comes with: its tmax is then moved to the
** next double above t, as tri_limit does, and the filter always sees
** tmin < candidate->t < tmax (ray_scene_set_filter(3)).
*/
static int gate_offer(const ray__prim *p, const ray_ray *r, const ray_hit *h,
                      ray__counts *qc)
{
    const ray__gate *g = qc->gate;
    const ray_ray *wr = qc->inst != NULL ? qc->world_ray : r;
    ray_hit w = *h;

    if (qc->inst != NULL) {
        ray__instance_to_world(qc->inst, h, &w);
        w.inst_id = qc->inst_id;
    }
    if (p->filter != NULL && (p->filter_queries & g->query) != 0) {
        ray_ray tie;
        if (!(w.t < wr->tmax)) {
            tie = *wr;
            tie.tmax = ray__next_up(w.t);   /* nextafter, inline */
            wr = &tie;
        }
        qc->filter_calls++;
        if (!p->filter(p->filter_ud, wr, &w, g->query_ud))
            return 0;
    }
    if (g->all != NULL) {
        collect(g->all, &w);
        return 0;
    }
    return 1;
}

/* Triangle i's candidate hit (t, beta, gamma) through the gate. */
static int tri_gate(const ray_scene *s, unsigned i, const ray__tri *tri,
                    double t, double beta, double gamma, const ray_ray *r,
                    ray__counts *qc)
{
    const ray__tri_id *id = &s->tri_ids[i];
    const ray__prim *p = &s->prims[id->geom_id];
    ray_hit h;

    if ((p->mask & qc->gate->mask) == 0)
        return 0;
    if (!gate_wants(p, qc->gate))
        return 1;
    /* A triangle that was hit has a normal (ray__tri_of): it fills. */
    if (!ray__triangle_fill(tri->a, tri->b, tri->c, t, beta, gamma, &h))
        return 0;
    h.geom_id = id->geom_id;
    h.prim_id = id->prim_id;
    h.inst_id = RAY_INVALID_ID;
    return gate_offer(p, r, &h, qc);
}

/* A surface may be asked again past a rejected hit this many times per
** ray (ray.h: both sides of a sphere need 2; a torus 4; 16 leaves room
** for implicit surfaces with several layers, and bounds the work a filter
** that rejects everything can cause). */
#define GATE_RETRIES 16

/*
** Geometry "idx" (not a triangle) against r through the gate: hidden by
** its mask; else its hits, nearest first, offered until one is accepted
** (each next one asked for past the last: tmin = its t).  An instance
** passes its own mask here and gates its child's geometry inside.
*/
static int prim_gated(const ray_scene *s, unsigned idx, const ray_ray *r,
                      ray_hit *h, ray__counts *qc)
{
    const ray__prim *p = &s->prims[idx];
    ray_ray rr = *r;
    int k;

    if ((p->mask & qc->gate->mask) == 0)
        return 0;
    if (!gate_wants(p, qc->gate))
        return ray__prim_intersect(s, idx, r, h, qc);
    for (k = 0; k < GATE_RETRIES; k++) {
        if (!ray__prim_intersect(s, idx, &rr, h, qc))
            return 0;
        if (gate_offer(p, r, h, qc))
            return 1;
        rr.tmin = h->t;
    }
    return 0;
}

#endif /* RAY_GATE_H */
