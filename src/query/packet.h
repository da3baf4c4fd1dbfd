/* SPDX-License-Identifier: MIT */
/*
** packet.h -- ray_intersect_batch and ray_occluded_batch's traversal:
** eight rays at once through the triangle BVH.  Included by intersect_avx2.c only.
**
** Why packets: a single ray's traversal is a chain of dependent node
** visits, each mostly waiting on the previous one's result (traverse.h).
** Eight rays that go the same way -- neighbouring camera pixels, shadow
** rays towards one light -- visit nearly the same nodes: a node is then
** fetched once for the eight, and the eight box tests of it are
** independent, so the CPU overlaps them.  Leaves test each ray on its
** own, with the single-ray triangle test (tri_leaf).
**
** Same answers as single rays, bit for bit:
**   * each lane's box test of a node is the single ray's own boxes_hit,
**     with its own traversal data and its own tmax, so a lane enters
**     every box its single ray would have entered at the same tmax (the
**     packet may take a lane into more, which only costs time: a lane's
**     interval only shrinks as hits are found);
**   * the leaves run tri_leaf on the lane's own single-ray state;
**   * the nearest hit does not depend on the order the triangles are met
**     in: nearer wins, and a tie in t goes to the lower (geom_id,
**     prim_id) (tri_beats), so visiting in the packet's order rather
**     than the ray's own finds the same triangle, and the hit record is
**     then filled by the same ray__triangle_fill.
** Only scenes of triangles alone (no planes, no other kinds, no
** instances) without masks or filters take this path (the rule is
** ray__packable, query.h): the other kinds' ties are settled by order.
** Any-hit queries, whose answer has no ties, take it in scenes of
** planes, a few spheres and triangles too: each lane's planes and
** spheres first, on its own (packet_init).
*/
#ifndef RAY_PACKET_H
#define RAY_PACKET_H

#include "query/traverse.h"

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
#define RAY__PACKETS 1
#define PACKET 8

/* Eight rays' state: each lane's single-ray state (its traversal data,
** its box test's registers, its ray and nearest triangle so far). */
typedef struct packet {
    trav tr[PACKET];
    lanes box[PACKET];                  /* each lane's box-test registers */
    ray_ray r[PACKET];
    tri_best best[PACKET];
    float tmax[PACKET], tpop[PACKET];   /* trav_tmax and with_slack */
    unsigned started, live;             /* usable lanes; still searching */
} packet;

/* A lane's interval end, after a hit shrank it. */
static inline void packet_shrink(packet *p, int lane)
{
    p->tmax[lane] = trav_tmax(&p->tr[lane], p->r[lane].tmax);
    p->tpop[lane] = with_slack(p->tmax[lane]);
}

/* Rays[0 .. n - 1] (n <= PACKET) of scene s into *p; lanes past n, rays
** that fail ray__ray_usable and rays that surely miss the scene's box
** (trav_setup's test: a single ray stops there too, having met nothing)
** are not live.  Each lane's ray copied as its set-up reads it
** (ray_copy).  Any hit in a scene with planes or a few spheres beside
** its triangles (s->few_spheres): each lane's planes and spheres first,
** as query_any_few tests them and counted into *st as it counts them; a
** lane they occlude is done (started, not live). */
static void packet_init(packet *p, const ray_scene *s, const ray_ray *rays,
                        int n, int any, ray_stats *st)
{
    unsigned occluded = 0;
    int l;

    p->live = 0;
    for (l = 0; l < PACKET; l++) {
        p->tmax[l] = p->tpop[l] = 0;
        /* the single ray's test (trav_usable: in two registers), where
        ** the plain form left packets of camera rays at 2.5 diagonals
        ** 0.88-0.92 of one ray at a time, now 0.93-0.95 (bench/packets,
        ** issue 34) */
        if (l >= n || !trav_usable(&rays[l]))
            continue;
        ray_copy(&p->r[l], &rays[l]);
        if (any && !tris_only(s) && few_any_prims(s, &p->r[l], st)) {
            occluded |= 1u << l;
            continue;
        }
        if (!trav_setup(&p->tr[l], &p->r[l], &s->lo, &s->hi))
            continue;
        lanes_init(&p->box[l], &p->tr[l]);
        tri_best_start(&p->best[l]);
        packet_shrink(p, l);
        p->live |= 1u << l;
    }
    p->started = p->live | occluded;
}

/* A node's slot waiting on the packet's stack: the lanes that entered it
** and where each entered. */
typedef struct packet_pending {
    unsigned child, count, sel;
    float near;                  /* the nearest entry of those lanes */
    float entry[PACKET];
} packet_pending;

/* The lanes of "sel" whose entry is not past their interval's end (a
** NaN entry stays, as traverse.h's pop keeps it). */
static inline unsigned packet_still(const packet *p, const float *entry,
                                    unsigned sel)
{
    __m256 e = _mm256_loadu_ps(entry), t = _mm256_loadu_ps(p->tpop);

    return sel & (unsigned)_mm256_movemask_ps(
                       _mm256_cmp_ps(e, t, _CMP_NGT_UQ));
}

/* The leaf of triangles first .. end - 1 for each lane of "sel", with
** its single-ray test. */
static void packet_leaf(const ray_scene *s, packet *p, unsigned first,
                        unsigned end, unsigned sel, int any,
                        ray__counts *qc)
{
    for (; sel != 0; sel &= sel - 1) {
        int l = lowest_bit(sel);
        qc->tests[RAY_PRIM_TRIANGLE] += end - first;
        if (!tri_leaf(s, &p->tr[l], first, end, &p->r[l],
                      any ? NULL : &p->best[l], any, qc))
            continue;
        if (any)
            p->live &= ~(1u << l);      /* an occluder: this lane is done */
        else
            packet_shrink(p, l);
    }
}

/*
** The 8 x 8 bit matrix "rows" (byte l: the children lane l enters, bit k
** child k) transposed: byte k, the lanes that enter child k.  Three
** swaps of blocks about the diagonal (Warren, "Hacker's Delight", 2nd
** ed., 7-3, transpose8 on one 64-bit word).
*/
static inline uint64_t by_child(uint64_t x)
{
    uint64_t t;

    t = (x ^ x >> 7) & 0x00AA00AA00AA00AAull;
    x = x ^ t ^ t << 7;
    t = (x ^ x >> 14) & 0x0000CCCC0000CCCCull;
    x = x ^ t ^ t << 14;
    t = (x ^ x >> 28) & 0x00000000F0F0F0F0ull;
    return x ^ t ^ t << 28;
}

/*
** Traversal, as traverse() but for the live lanes of *p: of the children
** some lane enters, the one some lane enters nearest is visited next and
** the others pushed (farthest deepest; unordered for any hit); a popped
** entry goes on with the lanes whose entry is still within their
** interval.
*/
static void packet_traverse(const ray_scene *s, packet *p, int any,
                            ray__counts *qc)
{
    packet_pending stack[RAY__WIDTH * 64];   /* as traverse()'s */
    const ray__bvh *bvh = &s->tri_bvh;
    unsigned child = 0, count = 0, sel = p->live;
    int sp = 0;

    if (bvh->n_wide == 0)
        return;
    for (;;) {
        if (count == 0) {                            /* an inner node */
            const ray__wnode *q = &bvh->wide[child];
            float entry[PACKET][RAY__WIDTH], near[RAY__WIDTH];
            unsigned todo, m;
            uint64_t rows = 0, cols;
            __m256 nearest = _mm256_set1_ps(HUGE_VALF);
            int k, base = sp, j, l;

            /* Each lane's own box test of the eight children (the
            ** single ray's boxes_hit): independent, so they overlap.
            ** Which lanes enter each child and the nearest entry of
            ** those, in registers: the lanes' masks as the rows of a bit
            ** matrix, turned into one row a child (by_child); the nearest
            ** entries as a vector, a lane's entries kept only where it
            ** enters (vminps keeps its second operand on a tie, as the
            ** scalar "e < near ? e : near" does; an entry is never NaN:
            ** boxes_hit's start, tmin, is not).  Scattered lane by lane
            ** and child by child, this took a third of the packets' node
            ** time in stores reloaded (perf annotate, bench/packets). */
            todo = 0;
            for (m = sel; m != 0; m &= m - 1) {
                __m256 e, in;
                unsigned b;
                l = lowest_bit(m);
                b = boxes_hit_v(q, &p->box[l], p->tmax[l], p->tpop[l],
                                p->box[l].grown, &e, &in);
                _mm256_storeu_ps(entry[l], e);
                todo |= b;
                rows |= (uint64_t)b << 8 * l;
                nearest = _mm256_min_ps(
                    _mm256_blendv_ps(_mm256_set1_ps(HUGE_VALF), e, in),
                    nearest);
            }
            cols = by_child(rows);
            _mm256_storeu_ps(near, nearest);
            if (todo != 0 && (todo & (todo - 1)) == 0) {
                /* One child entered, by every lane that goes on: visit
                ** it, with no stack entry to write and read back, as a
                ** single ray does.  Packets / one ray: primary rays at
                ** 1.0 diagonal 1.02-1.05 -> 1.08-1.10, shadow rays
                ** 0.93-0.99 -> 0.98-1.06 (bench/packets, two runs each,
                ** interleaved, issue 34). */
                k = lowest_bit(todo);
                child = q->child[k];
                count = q->count[k];
                sel = (unsigned)(cols >> 8 * k & 0xff);
                continue;
            }
            for (; todo != 0; todo &= todo - 1) {
                packet_pending e;
                k = lowest_bit(todo);
                e.child = q->child[k];
                e.count = q->count[k];
                e.sel = (unsigned)(cols >> 8 * k & 0xff);
                e.near = near[k];
                for (l = 0; l < PACKET; l++)
                    e.entry[l] = (e.sel >> l & 1) ? entry[l][k] : HUGE_VALF;
                for (j = sp; !any && j > base && stack[j - 1].near < e.near;
                     j--)
                    stack[j] = stack[j - 1];
                stack[j] = e;
                sp++;
            }
            if (sp == base)
                goto pop;
            sp--;                             /* the nearest: visit it */
            child = stack[sp].child;
            count = stack[sp].count;
            sel = stack[sp].sel;
            continue;
        }
        packet_leaf(s, p, child, child + (count & ~RAY__LEAF), sel, any,
                    qc);
    pop:
        do {
            if (sp == 0)
                return;
            sp--;
            sel = packet_still(p, stack[sp].entry,
                                 stack[sp].sel & p->live);
        } while (sel == 0);
        child = stack[sp].child;
        count = stack[sp].count;
    }
}

/*
** n rays (any n) eight at a time: results[i] and hits[i] as the single-ray
** query of a scene that ray__packable accepts gives them ("any":
** ray_occluded's, hits not used).
*/
static void packet_queries(const ray_scene *s, const ray_ray *rays,
                           size_t n, ray_hit *hits, int *results, int any,
                           ray_stats *st)
{
    packet p;
    size_t i;
    int l;

    for (i = 0; i < n; i += PACKET) {
        int m = n - i < PACKET ? (int)(n - i) : PACKET;
        ray__counts qc;
        counts_start(&qc, NULL, any);
        packet_init(&p, s, rays + i, m, any, st);
        packet_traverse(s, &p, any, &qc);
        add_counts(st, &qc);
        for (l = 0; l < m; l++) {
            const tri_best *b = &p.best[l];
            /* Any hit: a lane that started and stopped found one. */
            results[i + (size_t)l] = any && (p.started & ~p.live) >> l & 1;
            if (any || !(p.started >> l & 1) || b->index == TRI_NONE)
                continue;
            /* Straight into the output: tri_record writes nothing unless
            ** it fills the record. */
            if (tri_record(s, b, p.r[l].tmax, &hits[i + (size_t)l]))
                results[i + (size_t)l] = 1;
        }
    }
}
#else
#define RAY__PACKETS 0
#endif

#endif /* RAY_PACKET_H */
