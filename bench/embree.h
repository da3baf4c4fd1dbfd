/* SPDX-License-Identifier: MIT */
/*
** embree.h -- what the benchmarks that compare with Embree share: a
** triangle geometry of a mesh in Embree's format (float vertices).  Only
** with HAVE_EMBREE (the Makefile defines it where Embree's header is).
** Header-only; not part of the library.
*/
#ifndef BENCH_EMBREE_H
#define BENCH_EMBREE_H

#ifdef HAVE_EMBREE
#include <math.h>
#include <string.h>
#include <embree3/rtcore.h>

#include "ray.h"

/* n positions into Embree's vertex buffer: floats, rounded to nearest. */
static inline void embree_positions(float *dst, const ray_vec3 *v, size_t n)
{
    size_t i;

    for (i = 0; i < n; i++) {
        dst[3 * i] = (float)v[i].x;
        dst[3 * i + 1] = (float)v[i].y;
        dst[3 * i + 2] = (float)v[i].z;
    }
}

/*
** A triangle geometry of nv vertices v and nt index triples idx, not yet
** committed; *vertices (if not NULL) receives its vertex buffer, for
** updates in place (rtcUpdateGeometryBuffer).
*/
static inline RTCGeometry embree_triangles(RTCDevice dev, const ray_vec3 *v,
                                           size_t nv, const unsigned *idx,
                                           size_t nt, float **vertices)
{
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *ev = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                        nv);
    unsigned *ei = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                           RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), nt);

    embree_positions(ev, v, nv);
    memcpy(ei, idx, 3 * nt * sizeof *ei);
    if (vertices != NULL)
        *vertices = ev;
    return g;
}

/* Embree's nearest hit of r (in float, as Embree works): 1 and *t, *prim
** (either may be NULL), or 0. */
static inline int embree_hit(RTCScene scene, const ray_ray *r, float *t,
                             unsigned *prim)
{
    struct RTCIntersectContext ctx;
    struct RTCRayHit rh;

    rtcInitIntersectContext(&ctx);
    rh.ray.org_x = (float)r->org.x;
    rh.ray.org_y = (float)r->org.y;
    rh.ray.org_z = (float)r->org.z;
    rh.ray.dir_x = (float)r->dir.x;
    rh.ray.dir_y = (float)r->dir.y;
    rh.ray.dir_z = (float)r->dir.z;
    rh.ray.tnear = (float)r->tmin;
    rh.ray.tfar = r->tmax < HUGE_VAL ? (float)r->tmax : INFINITY;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    if (t != NULL)
        *t = rh.ray.tfar;
    if (prim != NULL)
        *prim = rh.hit.primID;
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

/* Embree's any hit of r (rtcOccluded1, in float): 1 if occluded. */
static inline int embree_occluded(RTCScene scene, const ray_ray *r)
{
    struct RTCIntersectContext ctx;
    struct RTCRay ray;

    rtcInitIntersectContext(&ctx);
    ray.org_x = (float)r->org.x;
    ray.org_y = (float)r->org.y;
    ray.org_z = (float)r->org.z;
    ray.dir_x = (float)r->dir.x;
    ray.dir_y = (float)r->dir.y;
    ray.dir_z = (float)r->dir.z;
    ray.tnear = (float)r->tmin;
    ray.tfar = r->tmax < HUGE_VAL ? (float)r->tmax : INFINITY;
    ray.mask = 0xffffffffu;
    ray.flags = 0;
    ray.time = 0;
    rtcOccluded1(scene, &ctx, &ray);
    return ray.tfar < 0;
}
#endif

#endif
