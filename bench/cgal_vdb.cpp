// SPDX-License-Identifier: MIT
//
// cgal_vdb.cpp -- CGAL's Side_of_triangle_mesh and OpenVDB's mesh-to-
// volume bakers behind the C calls of bench/cgal_vdb.h, for
// bench/contains.c.  C++17, built by the Makefile with $(CXX) only where
// /usr/include/CGAL (libcgal-dev: HAVE_CGAL) or /usr/include/openvdb
// (libopenvdb-dev: HAVE_OPENVDB) exists; either part alone is fine.
#include "cgal_vdb.h"

#include <chrono>
#include <vector>

#ifdef HAVE_CGAL
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <cmath>

typedef CGAL::Exact_predicates_inexact_constructions_kernel Kernel;
typedef Kernel::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef CGAL::Side_of_triangle_mesh<Mesh, Kernel> Side;
typedef CGAL::AABB_face_graph_triangle_primitive<Mesh> Primitive;
typedef CGAL::AABB_traits<Kernel, Primitive> Traits;
typedef CGAL::AABB_tree<Traits> Tree;

struct cgal_side {
    Mesh mesh;
    Side *side;
    Tree *tree;
};

extern "C" cgal_side *cgal_side_new(const double *xyz, size_t nv,
                                    const unsigned *idx, size_t nt)
{
    cgal_side *c = new cgal_side;
    std::vector<Mesh::Vertex_index> v(nv);

    for (size_t i = 0; i < nv; i++)
        v[i] = c->mesh.add_vertex(Point(xyz[3 * i], xyz[3 * i + 1],
                                        xyz[3 * i + 2]));
    for (size_t i = 0; i < nt; i++)
        if (c->mesh.add_face(v[idx[3 * i]], v[idx[3 * i + 1]],
                             v[idx[3 * i + 2]]) == Mesh::null_face()) {
            delete c;
            return nullptr;
        }
    c->side = new Side(c->mesh);
    (void)(*c->side)(Point(xyz[0], xyz[1], xyz[2]));  // builds its tree
    c->tree = new Tree(faces(c->mesh).first, faces(c->mesh).second, c->mesh);
    c->tree->accelerate_distance_queries();
    (void)c->tree->closest_point(Point(xyz[0], xyz[1], xyz[2]));
    return c;
}

extern "C" void cgal_side_free(cgal_side *c)
{
    if (c != nullptr) {
        delete c->side;
        delete c->tree;
    }
    delete c;
}

extern "C" void cgal_closest_query(const cgal_side *c, const double *pts,
                                   size_t n, double *dist)
{
    for (size_t i = 0; i < n; i++) {
        Point q(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
        dist[i] = std::sqrt(CGAL::to_double(
            CGAL::squared_distance(c->tree->closest_point(q), q)));
    }
}

extern "C" void cgal_side_query(const cgal_side *c, const double *pts,
                                size_t n, signed char *out)
{
    for (size_t i = 0; i < n; i++) {
        CGAL::Bounded_side b = (*c->side)(Point(pts[3 * i], pts[3 * i + 1],
                                                pts[3 * i + 2]));
        out[i] = b == CGAL::ON_BOUNDED_SIDE ? 1
                 : b == CGAL::ON_BOUNDARY   ? 0
                                            : -1;
    }
}
#endif

#ifdef HAVE_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/global_control.h>

extern "C" double vdb_bake(const double *xyz, size_t nv, const unsigned *idx,
                           size_t nt, const double lo[3], double step,
                           unsigned n, double band_voxels, unsigned threads,
                           float *out)
{
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              threads);
    std::vector<openvdb::Vec3s> points(nv);
    std::vector<openvdb::Vec3I> tris(nt);
    std::vector<openvdb::Vec4I> quads;
    openvdb::FloatGrid::Ptr grid;

    openvdb::initialize();
    for (size_t i = 0; i < nv; i++)
        points[i] = openvdb::Vec3s((float)xyz[3 * i], (float)xyz[3 * i + 1],
                                   (float)xyz[3 * i + 2]);
    for (size_t i = 0; i < nt; i++)
        tris[i] = openvdb::Vec3I(idx[3 * i], idx[3 * i + 1], idx[3 * i + 2]);
    // Index (i, j, k) at lo + step (i, j, k): the voxel centres are the
    // lattice's samples.
    openvdb::math::Transform::Ptr xform =
        openvdb::math::Transform::createLinearTransform(step);
    xform->postTranslate(openvdb::Vec3d(lo[0], lo[1], lo[2]));
    auto t0 = std::chrono::steady_clock::now();
    try {
        if (band_voxels > 0) {
            grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
                *xform, points, tris, (float)band_voxels);
        } else {
            // Both bands over the whole lattice (its diagonal in voxels).
            float wide = 1.75f * (float)n;
            grid = openvdb::tools::meshToSignedDistanceField<
                openvdb::FloatGrid>(*xform, points, tris, quads, wide, wide);
        }
    } catch (...) {
        return -1;
    }
    double secs = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - t0).count();
    openvdb::FloatGrid::ConstAccessor acc = grid->getConstAccessor();
    for (unsigned k = 0; k < n; k++)
        for (unsigned j = 0; j < n; j++)
            for (unsigned i = 0; i < n; i++)
                out[((size_t)k * n + j) * n + i] =
                    acc.getValue(openvdb::Coord((int)i, (int)j, (int)k));
    return secs;
}
#endif
