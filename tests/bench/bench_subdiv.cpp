// Benchmark: uniform subdivision to level 3 of a 10k-face and a 100k-face
// mesh (a perturbed torus, quads for Catmull-Clark, triangles for Loop),
// libgeom (geom_subdiv: topology refinement, then positions) against
// OpenSubdiv Far (TopologyRefinerFactory<TopologyDescriptor> +
// RefineUniform, then PrimvarRefinerReal<double>::Interpolate) and, when
// built with GEOM_BENCH_OPENMESH, OpenMesh's CatmullClarkT / LoopT
// subdividers. Both libgeom and Far are timed twice: with only what
// interpolation needs in the last level (Far's default,
// fullTopologyInLastLevel = false; geom_subdiv_options.partial_last_level)
// and with the full topology that limit evaluation needs. All in the same
// run, one thread, best of N runs (argument 1, default 3). Prints the
// times, the ratio to Far with the same last-level topology, and how far
// each result is from the other's (by index for Far, which orders vertices
// the same way; nearest vertex for OpenMesh).
//
// Usage: bench_subdiv [RUNS]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <unordered_map>
#include <vector>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#ifdef GEOM_BENCH_OPENMESH
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#endif

extern "C" {
#include "geom/subdiv.h"
}
#ifdef GEOM_BENCH_CGAL
#include "validate/geom_validate.h"
#endif

using namespace OpenSubdiv;

namespace {

double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

struct Soup {
    std::vector<double> xyz;
    std::vector<uint32_t> sizes, idx;
};

// Torus with nu x nv quads (or 2 nu nv triangles), radii 3 and 1, slightly
// perturbed so no two edge lengths are equal.
Soup torus(int nu, int nv, bool tris)
{
    Soup s;
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            double r = 1.0 + 0.05 * std::sin(7 * u + 3 * v);
            s.xyz.push_back((3 + r * std::cos(v)) * std::cos(u));
            s.xyz.push_back((3 + r * std::cos(v)) * std::sin(u));
            s.xyz.push_back(r * std::sin(v));
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = j * nu + i, b = j * nu + (i + 1) % nu;
            uint32_t c = ((j + 1) % nv) * nu + (i + 1) % nu, d = ((j + 1) % nv) * nu + i;
            if (tris) {
                uint32_t t[6] = {a, b, c, a, c, d};
                s.idx.insert(s.idx.end(), t, t + 6);
                s.sizes.push_back(3);
                s.sizes.push_back(3);
            } else {
                uint32_t q[4] = {a, b, c, d};
                s.idx.insert(s.idx.end(), q, q + 4);
                s.sizes.push_back(4);
            }
        }
    return s;
}

struct Result {
    double topo = 0, primvar = 0;
    std::vector<double> pos;
};

const int LEVELS = 3;

Result run_geom(const Soup &s, geom_subdiv_scheme scheme, bool full)
{
    Result res;
    geom_subdiv_options o;
    std::memset(&o, 0, sizeof o);
    o.scheme = scheme;
    o.partial_last_level = !full;
    double t0 = now();
    geom_subdiv_refiner *r = nullptr;
    if (geom_subdiv_refiner_create_soup(s.xyz.size() / 3, s.sizes.size(), s.sizes.data(),
                                        s.idx.data(), &o, &r, nullptr) != GEOM_OK ||
        geom_subdiv_refiner_refine(r, LEVELS) != GEOM_OK) {
        std::fprintf(stderr, "geom_subdiv failed\n");
        std::exit(1);
    }
    double t1 = now();
    std::vector<double> cur = s.xyz, next;
    for (int l = 1; l <= LEVELS; l++) {
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r, l, &li);
        next.resize(3 * li.vertices);
        geom_subdiv_interpolate(r, l, 3, cur.data(), next.data());
        cur.swap(next);
    }
    double t2 = now();
    geom_subdiv_refiner_destroy(r);
    res.topo = t1 - t0;
    res.primvar = t2 - t1;
    res.pos.swap(cur);
    return res;
}

struct V3 {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const V3 &s, double w)
    {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

Result run_far(const Soup &s, Sdc::SchemeType type, bool full)
{
    Result res;
    std::vector<int> sizes(s.sizes.begin(), s.sizes.end()), idx(s.idx.begin(), s.idx.end());
    double t0 = now();
    Far::TopologyDescriptor d;
    d.numVertices = (int)(s.xyz.size() / 3);
    d.numFaces = (int)sizes.size();
    d.numVertsPerFace = sizes.data();
    d.vertIndicesPerFace = idx.data();
    Sdc::Options opt;
    opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> F;
    std::unique_ptr<Far::TopologyRefiner> r(F::Create(d, F::Options(type, opt)));
    Far::TopologyRefiner::UniformOptions uo(LEVELS);
    uo.orderVerticesFromFacesFirst = true;
    uo.fullTopologyInLastLevel = full;
    r->RefineUniform(uo);
    double t1 = now();
    std::vector<std::vector<V3>> lv(LEVELS + 1);
    lv[0].resize(d.numVertices);
    std::memcpy(lv[0].data(), s.xyz.data(), s.xyz.size() * sizeof(double));
    Far::PrimvarRefinerReal<double> pr(*r);
    for (int l = 1; l <= LEVELS; l++) {
        lv[l].resize(r->GetLevel(l).GetNumVertices());
        pr.Interpolate(l, lv[l - 1], lv[l]);
    }
    double t2 = now();
    res.topo = t1 - t0;
    res.primvar = t2 - t1;
    res.pos.resize(3 * lv[LEVELS].size());
    std::memcpy(res.pos.data(), lv[LEVELS].data(), res.pos.size() * sizeof(double));
    return res;
}

#ifdef GEOM_BENCH_OPENMESH
struct DTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<DTraits> PolyMesh;
typedef OpenMesh::TriMesh_ArrayKernelT<DTraits> TriMesh;

template <class Mesh, class Sub> Result run_openmesh(const Soup &s)
{
    Result res;
    Mesh m;
    std::vector<typename Mesh::VertexHandle> vh;
    for (size_t v = 0; v < s.xyz.size() / 3; v++)
        vh.push_back(m.add_vertex(typename Mesh::Point(s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2])));
    size_t k = 0;
    for (size_t f = 0; f < s.sizes.size(); f++) {
        std::vector<typename Mesh::VertexHandle> fv;
        for (uint32_t j = 0; j < s.sizes[f]; j++)
            fv.push_back(vh[s.idx[k++]]);
        m.add_face(fv);
    }
    double t0 = now();
    Sub sub;
    sub.attach(m);
    sub(LEVELS);
    sub.detach();
    double t1 = now();
    res.topo = t1 - t0; // OpenMesh does both at once
    for (auto v : m.vertices()) {
        auto p = m.point(v);
        res.pos.push_back(p[0]);
        res.pos.push_back(p[1]);
        res.pos.push_back(p[2]);
    }
    return res;
}
#endif

#ifdef GEOM_BENCH_CGAL
// CGAL's Subdivision_method_3 through the validation shim (gv_subdiv_cgal):
// the time includes building CGAL's Surface_mesh from the soup and copying
// the refined mesh out, which the shim cannot separate.
Result run_cgal(const Soup &s, int scheme)
{
    Result res;
    gv_subdiv_result out;
    double t0 = now();
    int rc = gv_subdiv_cgal(scheme, LEVELS, s.xyz.size() / 3, s.xyz.data(), s.sizes.size(),
                            s.sizes.data(), s.idx.data(), &out);
    res.topo = now() - t0;
    if (rc != GV_OK) {
        std::fprintf(stderr, "gv_subdiv_cgal failed\n");
        std::exit(1);
    }
    res.pos.assign(out.xyz, out.xyz + 3 * out.nverts);
    gv_subdiv_result_free(&out);
    return res;
}
#endif

double max_index_diff(const std::vector<double> &a, const std::vector<double> &b)
{
    if (a.size() != b.size())
        return INFINITY;
    double m = 0;
    for (size_t i = 0; i < a.size(); i++)
        m = std::max(m, std::fabs(a[i] - b[i]));
    return m;
}

// Largest distance from a point of b to the nearest point of a (grid hash).
double max_nearest(const std::vector<double> &a, const std::vector<double> &b)
{
    if (a.size() != b.size())
        return INFINITY;
    const double h = 0.02;
    auto key = [&](double x, double y, double z) {
        long long i = (long long)std::floor(x / h), j = (long long)std::floor(y / h),
                  k = (long long)std::floor(z / h);
        return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
    };
    std::unordered_multimap<long long, size_t> grid;
    for (size_t i = 0; i < a.size() / 3; i++)
        grid.emplace(key(a[3 * i], a[3 * i + 1], a[3 * i + 2]), i);
    double worst = 0;
    for (size_t i = 0; i < b.size() / 3; i++) {
        double best = INFINITY;
        for (int dx = -1; dx <= 1; dx++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dz = -1; dz <= 1; dz++) {
                    auto r = grid.equal_range(key(b[3 * i] + dx * h, b[3 * i + 1] + dy * h,
                                                  b[3 * i + 2] + dz * h));
                    for (auto it = r.first; it != r.second; ++it) {
                        size_t j = it->second;
                        double d = std::hypot(std::hypot(a[3 * j] - b[3 * i], a[3 * j + 1] - b[3 * i + 1]),
                                              a[3 * j + 2] - b[3 * i + 2]);
                        best = std::min(best, d);
                    }
                }
        worst = std::max(worst, best);
    }
    return worst;
}

template <class F> Result best_of(int n, F f)
{
    Result best = f();
    for (int i = 1; i < n; i++) {
        Result r = f();
        if (r.topo + r.primvar < best.topo + best.primvar)
            best = std::move(r);
    }
    return best;
}

void line(const char *mesh, const char *who, const Result &r, double far_total, double diff)
{
    double total = r.topo + r.primvar;
    std::printf("%-30s %-24s %10.4f %11.4f %10.4f %8.2f %12.3g\n", mesh, who, r.topo, r.primvar,
                total, total / far_total, diff);
}

} // namespace

int main(int argc, char **argv)
{
    int runs = argc > 1 ? std::atoi(argv[1]) : 3;
    if (runs < 1)
        runs = 1;
    std::printf("uniform refinement to level %d, best of %d runs, one thread\n", LEVELS, runs);
    std::printf("%-30s %-24s %10s %11s %10s %8s %12s\n", "mesh", "implementation", "topology s",
                "positions s", "total s", "/ Far", "max |diff|");
    struct Case {
        const char *name;
        int nu, nv;
        bool tris;
    } cases[] = {{"torus 10k quads", 100, 100, false},
                 {"torus 100k quads", 317, 316, false},
                 {"torus 10k triangles", 100, 50, true},
                 {"torus 100k triangles", 317, 158, true}};
    for (const Case &c : cases) {
        Soup s = torus(c.nu, c.nv, c.tris);
        char name[64];
        std::snprintf(name, sizeof name, "%s (%zu)", c.name, s.sizes.size());
        geom_subdiv_scheme gs = c.tris ? GEOM_SUBDIV_LOOP : GEOM_SUBDIV_CATMULL_CLARK;
        Sdc::SchemeType ft = c.tris ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
        Result far = best_of(runs, [&] { return run_far(s, ft, false); });
        Result farfull = best_of(runs, [&] { return run_far(s, ft, true); });
        Result ours = best_of(runs, [&] { return run_geom(s, gs, false); });
        Result oursfull = best_of(runs, [&] { return run_geom(s, gs, true); });
        double far_total = far.topo + far.primvar, farfull_total = farfull.topo + farfull.primvar;
        line(name, "libgeom", ours, far_total, max_index_diff(ours.pos, far.pos));
        line(name, "OpenSubdiv Far", far, far_total, 0.0);
        line(name, "libgeom, full topology", oursfull, farfull_total, max_index_diff(oursfull.pos, far.pos));
        line(name, "Far, full topology", farfull, farfull_total, max_index_diff(ours.pos, farfull.pos));
#ifdef GEOM_BENCH_OPENMESH
        Result om = c.tris ? best_of(runs, [&] { return run_openmesh<TriMesh, OpenMesh::Subdivider::Uniform::LoopT<TriMesh, double>>(s); })
                           : best_of(runs, [&] { return run_openmesh<PolyMesh, OpenMesh::Subdivider::Uniform::CatmullClarkT<PolyMesh, double>>(s); });
        line(name, c.tris ? "OpenMesh LoopT" : "OpenMesh CatmullClarkT", om, far_total,
             max_nearest(ours.pos, om.pos));
#endif
#ifdef GEOM_BENCH_CGAL
        Result cg = best_of(runs, [&] {
            return run_cgal(s, c.tris ? GV_SUBDIV_LOOP : GV_SUBDIV_CATMULL_CLARK);
        });
        line(name, c.tris ? "CGAL Loop" : "CGAL CatmullClark", cg, far_total,
             max_nearest(ours.pos, cg.pos));
#endif
    }
    std::printf("(topology s: building and refining the topology; positions s: interpolating\n"
                " the positions through the levels; OpenMesh and CGAL do both at once (CGAL's time includes copying the mesh in and out). \"/ Far\": total\n"
                " time over Far's with the same last-level topology (full topology: what limit\n"
                " evaluation needs; otherwise only what interpolation needs, OpenSubdiv's\n"
                " default). max |diff|: against the other implementation's positions, by\n"
                " vertex index for Far, nearest vertex for OpenMesh)\n");
    return 0;
}
