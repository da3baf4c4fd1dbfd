/* SPDX-License-Identifier: MIT */
/*
** wide.c -- the node layout traversal reads: the binary tree collapsed
** into RAY__WIDTH-wide nodes (ray__wnode, bvh.h), eight children's boxes
** side by side.
*/
#include "accel/builder.h"

static float node_area(const ray__node *n)
{
    box b;
    memcpy(b.lo, n->lo, sizeof b.lo);
    memcpy(b.hi, n->hi, sizeof b.hi);
    return box_area(&b);
}

/* Is binary node n an inner node, opened by the collapse? */
static int opens(const ray__node *n)
{
    return n->count == 0;
}

/*
** The up to RAY__WIDTH binary nodes that become the children of the wide
** node for binary node "n": start from its two children and open inner
** ones until there are RAY__WIDTH or only leaves remain.  Which one: an
** inner child whose whole subtree fits in the slots left (leaves[c], its
** leaf count, at most one more than the free slots) is opened first, the
** smallest first, so that small subtrees are flattened into this node
** rather than left to become wide nodes of two or three children; then
** the inner one of largest surface area (the usual greedy collapse: the
** largest boxes are the likeliest to be hit, so they gain most from being
** tested together).  On the 59k bunny this takes 2,198 wide nodes with
** 5.6 children each where the area alone took 3,785 with 3.7 (bytes per
** triangle 9.6 against 16.5), for the same instructions per ray
** (callgrind, bench/mesh's primary and incoherent rays; issue 27).
** leaves may be NULL (memory was short): the area alone.  Returns how
** many.
*/
static int gather_children(const ray__node *nodes, const unsigned *leaves,
                           unsigned n, unsigned out[RAY__WIDTH])
{
    float area[RAY__WIDTH];      /* out[i]'s, taken once */
    int k = 2;

    out[0] = nodes[n].first;
    out[1] = nodes[n].first + 1;
    area[0] = node_area(&nodes[out[0]]);
    area[1] = node_area(&nodes[out[1]]);
    while (k < RAY__WIDTH) {
        unsigned free_slots = (unsigned)(RAY__WIDTH - k), fewest = ~0u;
        int best = -1, i;
        float best_area = -1;
        for (i = 0; i < k && leaves != NULL; i++)
            if (opens(&nodes[out[i]]) && leaves[out[i]] - 1 <= free_slots &&
                leaves[out[i]] < fewest) {
                fewest = leaves[out[i]];
                best = i;
            }
        for (i = 0; i < k && best < 0; i++)
            if (opens(&nodes[out[i]]) && area[i] > best_area) {
                best_area = area[i];
                best = i;
            }
        if (best < 0)
            break;
        out[k] = nodes[out[best]].first + 1;
        out[best] = nodes[out[best]].first;
        area[k] = node_area(&nodes[out[k]]);
        area[best] = node_area(&nodes[out[best]]);
        k++;
    }
    return k;
}

static void slot_set(ray__wnode *q, int k, const ray__node *c)
{
    int a;
    for (a = 0; a < 3; a++) {
        q->lo[a][k] = c->lo[a];
        q->hi[a][k] = c->hi[a];
    }
}

static void slot_empty(ray__wnode *q, int k)
{
    int a;
    for (a = 0; a < 3; a++) {
        q->lo[a][k] = HUGE_VALF;
        q->hi[a][k] = -HUGE_VALF;
    }
    q->child[k] = 0;
    q->count[k] = RAY__LEAF;            /* a leaf of no items */
}

/*
** Room in the wide nodes for one more node's children (RAY__WIDTH), the
** array grown by half when full.  RAY_OK or RAY_ENOMEM (*w kept).
*/
static int wide_room(const ray__allocator *a, ray__wnode **w, size_t *cap,
                     size_t used)
{
    size_t more = *cap + *cap / 2 + RAY__WIDTH;
    ray__wnode *grown;

    if (*cap - used >= RAY__WIDTH)
        return RAY_OK;
    grown = ray__reallocate(a, *w, *cap * sizeof **w, more * sizeof **w);
    if (grown == NULL)
        return RAY_ENOMEM;
    *w = grown;
    *cap = more;
    return RAY_OK;
}

/*
** Collapse the binary BVH into wide nodes.  The children of a wide node
** are numbered consecutively, depth first.  The array starts at a sixth
** of the binary nodes (the bunnies need a seventh to an eighth), grows by
** half when full and is trimmed to its size at the end: one walk of the
** tree, where counting first took two.
*/
int ray__bvh_collapse(const ray__allocator *a, ray__bvh *bvh,
                      const unsigned *leaves)
{
    size_t cap = bvh->n_nodes / 6 + RAY__WIDTH, used = 1;
    /* (binary node, wide node): RAY__WIDTH - 1 per level, 64 levels */
    unsigned stack[RAY__WIDTH * 64][2];
    ray__wnode *w = ray__allocate(a, cap * sizeof *w), *trimmed;
    int sp = 0;

    if (w == NULL)
        return RAY_ENOMEM;
    if (!opens(&bvh->nodes[0])) {         /* the root is a leaf */
        int k;
        for (k = 1; k < RAY__WIDTH; k++)
            slot_empty(&w[0], k);
        slot_set(&w[0], 0, &bvh->nodes[0]);
        w[0].child[0] = bvh->nodes[0].first;
        w[0].count[0] = RAY__LEAF | bvh->nodes[0].count;
    } else {
        stack[0][0] = 0;
        stack[0][1] = 0;
        sp = 1;
    }
    while (sp > 0) {
        unsigned n = stack[--sp][0], qi = stack[sp][1], kids[RAY__WIDTH];
        int k, m = gather_children(bvh->nodes, leaves, n, kids);
        ray__wnode *q;
        if (wide_room(a, &w, &cap, used) != RAY_OK) {
            ray__release(a, w, cap * sizeof *w);
            return RAY_ENOMEM;
        }
        q = &w[qi];
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__node *c;
            if (k >= m) {
                slot_empty(q, k);
                continue;
            }
            c = &bvh->nodes[kids[k]];
            slot_set(q, k, c);
            if (!opens(c)) {
                q->child[k] = c->first;
                q->count[k] = RAY__LEAF | c->count;
            } else {
                q->child[k] = (unsigned)used;
                q->count[k] = 0;
                stack[sp][0] = kids[k];
                stack[sp++][1] = (unsigned)used++;
            }
        }
    }
    trimmed = ray__reallocate(a, w, cap * sizeof *w, used * sizeof *w);
    if (trimmed != NULL) {               /* else keep the larger block */
        w = trimmed;
        cap = used;
    }
    bvh->wide = w;
    bvh->n_wide = used;
    bvh->cap_wide = cap;
    return RAY_OK;
}
