/* SPDX-License-Identifier: MIT */
/*
** sparse.c -- a node of few items that still splits.  The SAH makes a
** node of costs->leaf_items items or fewer a leaf (eight triangles: the
** float filter tests them in one pass); sah.c still splits it where its
** items, large beside the node, fall into two groups whose boxes are
** apart and have less area together than the node's: a room's walls, a
** level's separate slabs.
** In one leaf, every ray that enters the node's box (a ray inside the
** room) pays the leaf's test; split, the wide node above tests the
** groups' boxes in the same pass as its other children's, and most such
** rays enter neither.  The Cornell box's shadow rays: the four triangles
** of its red and green walls were one leaf, which each of them tested
** (issue 35; -11% of its render's instructions).  A mesh's leaves, whose
** triangles touch, stay whole, and cheaply (ray__bvh_has_gap).
*/
#include "accel/builder.h"

/*
** Where on some axis the items' lengths add up to less than b's extent:
** boxes without a gap would cover it.  Not every gap (boxes that overlap
** may leave one and still add up to more: such a node stays a leaf, a
** little speed lost, never an answer).  A few operations an item, where
** the best split of a leaf-sized node costs about 1,600 instructions: a
** mesh's leaves stop here (the 59k bunny's build: 1.1% more
** instructions, callgrind).
*/
int ray__bvh_has_gap(const builder *bd, size_t begin, size_t end,
                     const box *b)
{
    float x = 0, y = 0, z = 0;
    size_t i;

    for (i = begin; i < end; i++) {
        const ref *r = &bd->refs[i];
        x += r->hi[0] - r->lo[0];
        y += r->hi[1] - r->lo[1];
        z += r->hi[2] - r->lo[2];
    }
    return x < b->hi[0] - b->lo[0] || y < b->hi[1] - b->lo[1] ||
           z < b->hi[2] - b->lo[2];
}

/*
** Read only: the items keep their order (a leaf's, if not split).  The
** items must also be large beside their node: their boxes' areas add up
** to the node's at least (a room's walls: 4/3 of it).  Small items
** scattered through their node (a soup of small triangles, particles,
** foliage) keep their leaves of up to eight: split at every gap, 200k
** scattered triangles made leaves of one triangle and 5.6 times the
** hierarchy's bytes, and a rule asking for a gap of half the node's
** width still 1.7 times, its rays no faster (issue 35's review).
*/
int ray__bvh_sides_sparse(const builder *bd, size_t begin, size_t end,
                          const split *sp, const box *node)
{
    float edge = (float)(sp->bin + 1), items = 0, area = box_area(node);
    box side[2], b;
    size_t i;
    int a;

    box_empty(&side[0]);
    box_empty(&side[1]);
    for (i = begin; i < end; i++) {
        const ref *r = &bd->refs[i];
        memcpy(b.lo, r->lo, sizeof b.lo);
        memcpy(b.hi, r->hi, sizeof b.hi);
        items += box_area(&b);
        box_grow(&side[!goes_left(r, sp, edge)], r->lo, r->hi);
    }
    if (!(items >= area) ||
        !(box_area(&side[0]) + box_area(&side[1]) < area))
        return 0;
    for (a = 0; a < 3; a++)
        if (side[0].hi[a] < side[1].lo[a] || side[1].hi[a] < side[0].lo[a])
            return 1;
    return 0;
}
