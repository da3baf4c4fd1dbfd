/* SPDX-License-Identifier: MIT */
/*
** refit.c -- a BVH's boxes fitted again, bottom up, to geometry that
** moved but kept its items (ray__bvh_refit): the same tree.
*/
#include "accel/builder.h"

/* Slot k of node q fitted to box b. */
static void slot_fit(ray__wnode *q, int k, const box *b)
{
    int a;

    for (a = 0; a < 3; a++) {
        q->lo[a][k] = b->lo[a];
        q->hi[a][k] = b->hi[a];
    }
}

/*
** The leaf slots listed by their first item (node * RAY__WIDTH + slot),
** kept in bvh->leaves: the leaves of a wide node sit wherever the
** collapse numbered them, so visiting them node by node reads the items
** (the triangles, 72 bytes each) in a scattered order that misses the
** cache at every leaf, where this list reads them as they lie.  Made
** once, through a temporary array of n_items (the slot starting at each
** item); 0 if memory is short (the caller then goes node by node).
*/
static int leaves_in_order(const ray__allocator *a, ray__bvh *bvh,
                           size_t n_items)
{
    unsigned *at, *list;
    size_t w, i, n = 0;
    int k;

    if (bvh->leaves != NULL)
        return 1;
    if (n_items == 0 || bvh->n_wide > 0xffffffffu / RAY__WIDTH)
        return 0;
    at = ray__allocate(a, n_items * sizeof *at);
    if (at == NULL)
        return 0;
    for (i = 0; i < n_items; i++)
        at[i] = 0xffffffffu;
    for (w = 0; w < bvh->n_wide; w++)
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__wnode *q = &bvh->wide[w];
            if (q->count[k] != 0 && (q->count[k] & ~RAY__LEAF) != 0 &&
                q->child[k] < n_items) {
                at[q->child[k]] = (unsigned)(w * RAY__WIDTH + (size_t)k);
                n++;
            }
        }
    list = ray__allocate(a, n * sizeof *list);
    if (list != NULL) {
        size_t j = 0;
        for (i = 0; i < n_items; i++)
            if (at[i] != 0xffffffffu)
                list[j++] = at[i];
        bvh->leaves = list;
        bvh->n_leaves = n;
    }
    ray__release(a, at, n_items * sizeof *at);
    return list != NULL;
}

/* The leaf slots refitted in the order of their items. */
static int refit_leaves_in_order(const ray__allocator *a, ray__bvh *bvh,
                                 ray__range_box_fn range_box, const void *ud,
                                 size_t n_items)
{
    size_t i;

    if (!leaves_in_order(a, bvh, n_items))
        return 0;
    for (i = 0; i < bvh->n_leaves; i++) {
        ray__wnode *q = &bvh->wide[bvh->leaves[i] / RAY__WIDTH];
        int slot = (int)(bvh->leaves[i] % RAY__WIDTH);
        box b;
        range_box(ud, q->child[slot], q->count[slot] & ~RAY__LEAF, b.lo,
                  b.hi);
        slot_fit(q, slot, &b);
    }
    return 1;
}

/*
** Wide nodes are numbered so that every child comes after its parent
** (collapse numbers them as it goes), so one pass from the last node to
** the first sees every child refitted before its parent.
*/
void ray__bvh_refit(const ray__allocator *a, ray__bvh *bvh,
                    ray__range_box_fn range_box, const void *ud,
                    size_t n_items)
{
    int leaves_done = refit_leaves_in_order(a, bvh, range_box, ud, n_items);
    size_t w = bvh->n_wide;

    while (w-- > 0) {
        ray__wnode *q = &bvh->wide[w];
        int k, j, ax;
        for (k = 0; k < RAY__WIDTH; k++) {
            box b;
            if (q->count[k] == 0) {               /* an inner node */
                const ray__wnode *c = &bvh->wide[q->child[k]];
                box_empty(&b);
                for (j = 0; j < RAY__WIDTH; j++) {
                    float lo[3], hi[3];
                    for (ax = 0; ax < 3; ax++) {
                        lo[ax] = c->lo[ax][j];
                        hi[ax] = c->hi[ax][j];
                    }
                    box_grow(&b, lo, hi);
                }
                slot_fit(q, k, &b);
            } else if (!leaves_done && (q->count[k] & ~RAY__LEAF) != 0) {
                range_box(ud, q->child[k], q->count[k] & ~RAY__LEAF, b.lo,
                          b.hi);
                slot_fit(q, k, &b);
            }
        }
    }
}
