// SPDX-License-Identifier: MIT
//
// bullet.cpp -- Bullet's sphere sweeps and rays over a triangle mesh, for
// bench/shapes.c (shapes.h says what it does).  C++, built by the
// Makefile with $(CXX) only where /usr/include/bullet exists (Debian's
// libbullet-dev, single-precision btScalar as Debian builds it).
#include <btBulletCollisionCommon.h>

#include <chrono>
#include <vector>

#include "shapes.h"

extern "C" double bullet_sweeps(const double *v, size_t nv,
                                const unsigned *idx, size_t nt,
                                double radius, bullet_path *paths, size_t n)
{
    std::vector<btScalar> verts(3 * nv);
    std::vector<int> tris(3 * nt);
    for (size_t i = 0; i < 3 * nv; i++)
        verts[i] = (btScalar)v[i];
    for (size_t i = 0; i < 3 * nt; i++)
        tris[i] = (int)idx[i];
    btTriangleIndexVertexArray mesh((int)nt, tris.data(), 3 * sizeof(int),
                                    (int)nv, verts.data(),
                                    3 * sizeof(btScalar));
    btBvhTriangleMeshShape shape(&mesh, true);
    btCollisionObject object;
    object.setCollisionShape(&shape);
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btCollisionWorld world(&dispatcher, &broadphase, &config);
    world.addCollisionObject(&object);
    world.updateAabbs();
    btSphereShape sphere((btScalar)(radius > 0 ? radius : 1));

    auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < n; i++) {
        btVector3 from((btScalar)paths[i].from[0], (btScalar)paths[i].from[1],
                       (btScalar)paths[i].from[2]);
        btVector3 to((btScalar)paths[i].to[0], (btScalar)paths[i].to[1],
                     (btScalar)paths[i].to[2]);
        if (radius > 0) {
            btTransform a, b;
            a.setIdentity();
            b.setIdentity();
            a.setOrigin(from);
            b.setOrigin(to);
            btCollisionWorld::ClosestConvexResultCallback cb(from, to);
            world.convexSweepTest(&sphere, a, b, cb);
            paths[i].hit = cb.hasHit();
            paths[i].fraction = cb.m_closestHitFraction;
        } else {
            btCollisionWorld::ClosestRayResultCallback cb(from, to);
            world.rayTest(from, to, cb);
            paths[i].hit = cb.hasHit();
            paths[i].fraction = cb.m_closestHitFraction;
        }
    }
    std::chrono::duration<double> s = std::chrono::steady_clock::now() - start;
    world.removeCollisionObject(&object);
    return s.count();
}
