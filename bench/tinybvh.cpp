// SPDX-License-Identifier: MIT
//
// tinybvh.cpp -- the fastest float BVH measured beside libray: tinybvh's
// BVH8_CPU (Jacco Bikker, MIT licence, ../shared/ext/tiny_bvh.h; 8-wide,
// AVX2, the child order per ray octant of Fuetterling et al. 2017), behind
// the C calls of tinybvh.h, so that bench/raycost.c can time it on the
// same rays as libray and Embree.  Built only when the header exists (the
// Makefile: TINYBVH_OBJ); never part of the library.
#define TINYBVH_IMPLEMENTATION
#include "tiny_bvh.h"

#include "tinybvh.h"

using namespace tinybvh;

struct tbvh {
    bvhvec4 *tris;       // three corners a triangle, as BVH8_CPU reads them
    BVH8_CPU bvh;
};

extern "C" tbvh *tbvh_build(const double *xyz, const unsigned *idx,
                            size_t ntri)
{
    tbvh *h = new tbvh;
    h->tris = static_cast<bvhvec4 *>(malloc64(3 * ntri * sizeof(bvhvec4)));
    for (size_t i = 0; i < 3 * ntri; i++) {
        const double *p = xyz + 3 * static_cast<size_t>(idx[i]);
        h->tris[i] = bvhvec4(static_cast<float>(p[0]), static_cast<float>(p[1]),
                             static_cast<float>(p[2]), 0.0f);
    }
    h->bvh.Build(h->tris, static_cast<uint32_t>(ntri));
    return h;
}

extern "C" void tbvh_free(tbvh *h)
{
    if (h == nullptr)
        return;
    free64(h->tris);
    delete h;
}

// As a user calls it: a Ray made per query (its constructor normalises
// the direction and takes its reciprocal), then Intersect.  The direction
// passed is unit already, so t is the same distance as libray's.
extern "C" int tbvh_intersect(const tbvh *h, const float o[3],
                              const float d[3], float tmax, float *t,
                              unsigned *prim)
{
    Ray r(bvhvec3(o[0], o[1], o[2]), bvhvec3(d[0], d[1], d[2]), tmax);
    h->bvh.Intersect(r);
    *t = r.hit.t;
    *prim = r.hit.prim;
    return r.hit.t < tmax;
}

extern "C" int tbvh_occluded(const tbvh *h, const float o[3],
                             const float d[3], float tmax)
{
    Ray r(bvhvec3(o[0], o[1], o[2]), bvhvec3(d[0], d[1], d[2]), tmax);
    return h->bvh.IsOccluded(r) ? 1 : 0;
}
