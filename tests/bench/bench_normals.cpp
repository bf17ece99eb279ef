// Vertex normals on a 1M-triangle mesh: libgeom (every weighting) against
// OpenMesh 9 (update_face_normals + update_vertex_normals: the sum of unit
// face normals, i.e. our "uniform") and CGAL 5.5
// (Polygon_mesh_processing::compute_vertex_normals: Aubry et al.'s most
// visible normal), all in double precision, measured in the same run.
//
// Input: a UV sphere (1000 x 500 with 2 triangles per cell, about 1M
// triangles) whose vertices are jittered along the sphere, so the exact
// normal is the radial direction: the error printed is the largest and the
// mean angle (radians) between each vertex normal and the radius. Max's
// weights are exact for vertices on a sphere (Max 1999), the others are not.
// Times are in seconds, the best of 5 rounds in which libgeom and OpenMesh
// alternate (CGAL: one run, it is slow); meshes are built before timing.
//
// Built by tests/bench/CMakeLists.txt (C++17, -O2, NDEBUG) when OpenMesh
// and CGAL are found; `make bench` installs them and runs it.
// Usage: bench_normals [NLON NLAT]   (default 1000 500)
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

extern "C" {
#include "geom/mesh.h"
}

namespace {

struct DTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<DTraits> OMesh;
typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Surface_mesh<K::Point_3> SMesh;

double best_of(int runs, const std::function<void()> &f)
{
    double best = 1e300;
    for (int i = 0; i < runs; i++) {
        auto t0 = std::chrono::steady_clock::now();
        f();
        auto t1 = std::chrono::steady_clock::now();
        best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
    }
    return best;
}

// Largest and mean angle between normals n (3 per vertex) and the radius.
void radial_error(const std::vector<double> &xyz, const double *n, double *maxe, double *meane)
{
    size_t nv = xyz.size() / 3;
    double mx = 0.0, sum = 0.0;
    for (size_t v = 0; v < nv; v++) {
        const double *p = &xyz[3 * v], *q = n + 3 * v;
        double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        double c[3] = {p[1] / r * q[2] - p[2] / r * q[1], p[2] / r * q[0] - p[0] / r * q[2],
                       p[0] / r * q[1] - p[1] / r * q[0]};
        double d = (p[0] * q[0] + p[1] * q[1] + p[2] * q[2]) / r;
        double a = std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), d);
        mx = std::max(mx, a);
        sum += a;
    }
    *maxe = mx;
    *meane = sum / (double)nv;
}

} // namespace

int main(int argc, char **argv)
{
    int nlon = 1000, nlat = 500;
    if (argc == 3) {
        nlon = std::atoi(argv[1]);
        nlat = std::atoi(argv[2]);
        if (nlon < 3 || nlat < 1) {
            std::fprintf(stderr, "usage: %s [NLON NLAT]\n", argv[0]);
            return 2;
        }
    }
    // jittered UV sphere of radius 1 at the origin
    std::vector<double> xyz;
    std::vector<uint32_t> idx;
    uint64_t rng = 0x9e3779b97f4a7c15ull;
    auto rnd = [&rng]() {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        return (double)(rng >> 11) / 9007199254740992.0;
    };
    const double PI = 3.14159265358979323846;
    for (int i = 0; i < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            double th = PI * (i + 1 + 0.3 * (rnd() - 0.5)) / (nlat + 1);
            double ph = 2 * PI * (j + 0.3 * (rnd() - 0.5)) / nlon;
            xyz.push_back(std::sin(th) * std::cos(ph));
            xyz.push_back(std::sin(th) * std::sin(ph));
            xyz.push_back(std::cos(th));
        }
    }
    uint32_t N = (uint32_t)(nlat * nlon), S = N + 1;
    for (double z : {1.0, -1.0}) {
        xyz.push_back(0.0);
        xyz.push_back(0.0);
        xyz.push_back(z);
    }
    for (int j = 0; j < nlon; j++) {
        uint32_t j1 = (uint32_t)((j + 1) % nlon), base = (uint32_t)((nlat - 1) * nlon);
        idx.insert(idx.end(), {N, (uint32_t)j, j1, S, base + j1, base + (uint32_t)j});
    }
    for (int i = 0; i + 1 < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            uint32_t j1 = (uint32_t)((j + 1) % nlon);
            uint32_t a = (uint32_t)(i * nlon + j), b = (uint32_t)(i * nlon) + j1;
            uint32_t c = a + (uint32_t)nlon, d = b + (uint32_t)nlon;
            idx.insert(idx.end(), {a, c, d, a, d, b});
        }
    }
    size_t nv = xyz.size() / 3, nf = idx.size() / 3;
    std::printf("bench_normals: jittered UV sphere, %zu vertices, %zu triangles\n", nv, nf);

    // --- libgeom and OpenMesh, timed in interleaved rounds (best of 5 each)
    // so that a change in the machine's load affects both alike
    geom_mesh *m = geom_mesh_create(nullptr);
    std::vector<uint32_t> sizes(nf, 3);
    if (!m || geom_mesh_build(m, nv, xyz.data(), nf, sizes.data(), idx.data(), nullptr, nullptr,
                              nullptr) != GEOM_OK) {
        std::fprintf(stderr, "geom_mesh_build failed\n");
        return 1;
    }
    OMesh om;
    om.request_face_normals();
    om.request_vertex_normals();
    {
        std::vector<OMesh::VertexHandle> vh(nv);
        for (size_t v = 0; v < nv; v++)
            vh[v] = om.add_vertex(OMesh::Point(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]));
        for (size_t f = 0; f < nf; f++)
            om.add_face(vh[idx[3 * f]], vh[idx[3 * f + 1]], vh[idx[3 * f + 2]]);
    }
    struct W {
        geom_normal_weight w;
        const char *name;
        double t;
        std::vector<double> n;
    } ws[4] = {{GEOM_NORMAL_WEIGHT_UNIFORM, "uniform", 1e300, {}},
               {GEOM_NORMAL_WEIGHT_AREA, "area", 1e300, {}},
               {GEOM_NORMAL_WEIGHT_ANGLE, "angle", 1e300, {}},
               {GEOM_NORMAL_WEIGHT_MAX, "max", 1e300, {}}};
    for (W &w : ws)
        w.n.resize(3 * nv);
    double t_om = 1e300, t_om_vertex = 1e300;
    for (int round = 0; round < 5; round++) {
        for (W &w : ws)
            w.t = std::min(w.t, best_of(1, [&]() {
                               geom_mesh_vertex_normals(m, w.w, w.n.data(), nullptr);
                           }));
        t_om = std::min(t_om, best_of(1, [&]() {
                            om.update_face_normals();
                            om.update_vertex_normals();
                        }));
        t_om_vertex = std::min(t_om_vertex, best_of(1, [&]() { om.update_vertex_normals(); }));
    }
    geom_mesh_destroy(m);
    std::printf("%-44s %10s %12s %12s\n", "method", "seconds", "max error", "mean error");
    double t_uniform = ws[0].t;
    for (const W &w : ws) {
        double mx, mean;
        radial_error(xyz, w.n.data(), &mx, &mean);
        std::printf("libgeom %-36s %10.4f %12.3e %12.3e\n", w.name, w.t, mx, mean);
    }
    std::vector<double> omn(3 * nv);
    for (size_t v = 0; v < nv; v++) {
        OMesh::Normal n = om.normal(OMesh::VertexHandle((int)v));
        omn[3 * v] = n[0];
        omn[3 * v + 1] = n[1];
        omn[3 * v + 2] = n[2];
    }
    {
        double mx, mean;
        radial_error(xyz, omn.data(), &mx, &mean);
        std::printf("%-44s %10.4f %12.3e %12.3e\n", "OpenMesh update_face+vertex_normals", t_om, mx,
                    mean);
        std::printf("%-44s %10.4f %12s %12s\n", "OpenMesh update_vertex_normals only", t_om_vertex,
                    "", "");
    }

    // --- CGAL
    SMesh sm;
    {
        std::vector<SMesh::Vertex_index> vi(nv);
        for (size_t v = 0; v < nv; v++)
            vi[v] = sm.add_vertex(K::Point_3(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]));
        for (size_t f = 0; f < nf; f++)
            sm.add_face(vi[idx[3 * f]], vi[idx[3 * f + 1]], vi[idx[3 * f + 2]]);
    }
    auto vnormals = sm.add_property_map<SMesh::Vertex_index, K::Vector_3>("v:normals",
                                                                          CGAL::NULL_VECTOR)
                        .first;
    double t_cgal = best_of(1, [&]() { // slow: one run
        CGAL::Polygon_mesh_processing::compute_vertex_normals(sm, vnormals);
    });
    std::vector<double> cgn(3 * nv);
    for (size_t v = 0; v < nv; v++) {
        K::Vector_3 n = vnormals[SMesh::Vertex_index((uint32_t)v)];
        cgn[3 * v] = n.x();
        cgn[3 * v + 1] = n.y();
        cgn[3 * v + 2] = n.z();
    }
    {
        double mx, mean;
        radial_error(xyz, cgn.data(), &mx, &mean);
        std::printf("%-44s %10.4f %12.3e %12.3e\n", "CGAL compute_vertex_normals (default)", t_cgal,
                    mx, mean);
    }
    std::printf("ratio OpenMesh / libgeom uniform (same weights): %.2fx\n", t_om / t_uniform);
    std::printf("ratio CGAL / libgeom uniform: %.2fx\n", t_cgal / t_uniform);
    // agreement of the same weighting
    {
        double d = 0.0;
        for (size_t i = 0; i < 3 * nv; i++)
            d = std::max(d, std::fabs(ws[0].n[i] - omn[i]));
        std::printf("max |libgeom uniform - OpenMesh| = %.3e\n", d);
    }
    return 0;
}
