// Spatial indices against their usual peers, same inputs, same run, one
// thread each:
//  - kNN (k = 8) and radius queries on 1M uniform random points: our kd-tree
//    (and octree) vs nanoflann's KDTreeSingleIndexAdaptor (leaf size 10);
//    the error column counts queries whose answer differs (index sets for
//    kNN, sizes for radius);
//  - closest point on a triangle mesh (the bunny refined to 1.2M triangles,
//    or any mesh given): our geom_meshdist vs CGAL's AABB_tree with
//    accelerate_distance_queries(); error = largest distance difference;
//  - BVH build time on the same mesh: our binned SAH and LBVH vs Embree 3
//    (rtcNewDevice("threads=1"), default build quality, float input).
// Times are process CPU seconds (one thread each).
// Usage: bench_spatial [MESH.off|obj|ply|stl] [N_POINTS] [N_QUERIES]
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include <nanoflann.hpp>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <embree3/rtcore.h>

extern "C" {
#include "geom/meshio.h"
#include "geom/spatial.h"
}

// Process CPU time: every contestant runs on one thread, so this is its work
// and is not inflated when the machine is shared (wall-clock is printed too).
static double now()
{
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

struct Cloud {
    const std::vector<double> *p;
    size_t kdtree_get_point_count() const { return p->size() / 3; }
    double kdtree_get_pt(size_t i, size_t d) const { return (*p)[3 * i + d]; }
    template <class B> bool kdtree_get_bbox(B &) const { return false; }
};
typedef nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3>
    NanoTree;

static void row(const char *what, double ours, double peer, const char *peer_name, double err)
{
    std::printf("%-34s ours %9.4f s  %-10s %9.4f s  ratio(peer/ours) %6.2f  error %g\n", what, ours,
                peer_name, peer, peer / ours, err);
}

int main(int argc, char **argv)
{
    const char *mesh_path = argc > 1 ? argv[1] : NULL;
    size_t n = argc > 2 ? (size_t)std::atol(argv[2]) : 1000000;
    size_t nq = argc > 3 ? (size_t)std::atol(argv[3]) : 200000;
    auto wall0 = std::chrono::steady_clock::now();
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> U(0.0, 1.0);

    // ------------------------------------------------------------- points
    std::vector<double> pts(3 * n), qs(3 * nq);
    for (auto &x : pts) x = U(rng);
    for (auto &x : qs) x = U(rng);
    const size_t k = 8;
    std::printf("points: %zu uniform in the unit cube, %zu queries, k = %zu, one thread\n", n, nq, k);

    double t0 = now();
    geom_kdtree *kd = NULL;
    geom_kdtree_options ko = {};
    ko.threads = 1;
    if (geom_kdtree_build(pts.data(), n, 3, &ko, &kd, NULL) != GEOM_OK) return 1;
    double kd_build = now() - t0;
    t0 = now();
    Cloud cloud{&pts};
    NanoTree nano(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    nano.buildIndex();
    double nano_build = now() - t0;
    row("kd-tree build", kd_build, nano_build, "nanoflann", 0);

    std::vector<uint32_t> idx(nq * k);
    std::vector<double> dist(nq * k);
    t0 = now();
    geom_kdtree_knn(kd, qs.data(), nq, k, idx.data(), dist.data(), 1, NULL);
    double kd_knn = now() - t0;
    std::vector<size_t> nidx(nq * k);
    std::vector<double> nd2(nq * k);
    t0 = now();
    for (size_t q = 0; q < nq; q++) {
        nanoflann::KNNResultSet<double, size_t> rs(k);
        rs.init(&nidx[q * k], &nd2[q * k]);
        nano.findNeighbors(rs, &qs[3 * q], nanoflann::SearchParams(10));
    }
    double nano_knn = now() - t0;
    size_t bad = 0;
    for (size_t q = 0; q < nq; q++)
        for (size_t j = 0; j < k; j++)
            if (std::fabs(dist[q * k + j] - std::sqrt(nd2[q * k + j])) > 1e-12) { bad++; break; }
    row("kNN k=8 (kd-tree)", kd_knn, nano_knn, "nanoflann", (double)bad);

    geom_octree *oc = NULL;
    geom_octree_options oo = {};
    oo.threads = 1;
    t0 = now();
    geom_octree_build_points(pts.data(), n, 3, &oo, &oc, NULL);
    double oc_build = now() - t0;
    row("octree build", oc_build, nano_build, "nanoflann", 0);
    std::vector<uint32_t> idx2(nq * k);
    t0 = now();
    geom_octree_knn(oc, qs.data(), nq, k, idx2.data(), NULL, 1, NULL);
    double oc_knn = now() - t0;
    bad = 0;
    for (size_t i = 0; i < nq * k; i++) bad += idx2[i] != idx[i];
    row("kNN k=8 (octree)", oc_knn, nano_knn, "nanoflann", (double)bad);

    const double r = 0.02; // about 33 neighbours on average
    geom_neighbors nb = {};
    t0 = now();
    geom_kdtree_radius(kd, qs.data(), nq, r, &nb, 1, NULL);
    double kd_rad = now() - t0;
    size_t nano_total = 0;
    bad = 0;
    t0 = now();
    std::vector<std::pair<uint32_t, double>> matches;
    nanoflann::SearchParams sp(10);
    sp.sorted = true;
    for (size_t q = 0; q < nq; q++) {
        size_t m = nano.radiusSearch(&qs[3 * q], r * r, matches, sp);
        nano_total += m;
        if (m != nb.offsets[q + 1] - nb.offsets[q]) bad++;
    }
    double nano_rad = now() - t0;
    char lab[64];
    std::snprintf(lab, sizeof lab, "radius %.2f (kd-tree, sorted)", r);
    row(lab, kd_rad, nano_rad, "nanoflann", (double)bad);
    std::printf("  (radius: %zu neighbours in all; nanoflann %zu)\n", (size_t)nb.offsets[nq], nano_total);
    geom_neighbors_free(&nb);
    geom_kdtree_destroy(kd);
    geom_octree_destroy(oc);

    // --------------------------------------------------------------- mesh
    if (!mesh_path) {
        std::printf("no mesh given: closest-point and BVH benchmarks skipped\n");
        return 0;
    }
    geom_mesh *m = NULL;
    geom_diag diag;
    if (geom_meshio_read(mesh_path, NULL, &m, NULL, &diag) != GEOM_OK) {
        std::fprintf(stderr, "cannot read %s: %s\n", mesh_path, diag.message);
        return 1;
    }
    geom_mesh_triangulate(m, NULL);
    size_t ni = 0;
    geom_mesh_to_soup(m, NULL, NULL, &ni);
    std::vector<uint32_t> tris(ni), sizes(geom_mesh_n_live_faces(m));
    geom_mesh_to_soup(m, sizes.data(), tris.data(), &ni);
    size_t nv = geom_mesh_n_vertices(m), nt = ni / 3;
    std::vector<double> pos(geom_mesh_cpositions(m), geom_mesh_cpositions(m) + 3 * nv);
    geom_mesh_destroy(m);
    std::printf("mesh: %s, %zu vertices, %zu triangles\n", mesh_path, nv, nt);

    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (size_t i = 0; i < nv; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = std::min(lo[c], pos[3 * i + c]);
            hi[c] = std::max(hi[c], pos[3 * i + c]);
        }
    size_t mq = nq / 2;
    std::vector<double> mqs(3 * mq);
    for (size_t i = 0; i < mq; i++)
        for (int c = 0; c < 3; c++) {
            double e = hi[c] - lo[c];
            mqs[3 * i + c] = lo[c] - 0.1 * e + 1.2 * e * U(rng);
        }

    // BVH build: ours (SAH, LBVH) vs Embree.
    geom_bvh_options bo = {};
    bo.threads = 1;
    geom_bvh *bvh = NULL;
    t0 = now();
    geom_bvh_build_triangles(pos.data(), nv, tris.data(), nt, &bo, &bvh, NULL);
    double sah = now() - t0;
    size_t nn;
    geom_bvh_nodes(bvh, &nn);
    size_t sah_depth = geom_bvh_depth(bvh);
    geom_bvh_destroy(bvh);
    bo.method = GEOM_BVH_LBVH;
    t0 = now();
    geom_bvh_build_triangles(pos.data(), nv, tris.data(), nt, &bo, &bvh, NULL);
    double lbvh = now() - t0;
    geom_bvh_destroy(bvh);

    RTCDevice dev = rtcNewDevice("threads=1");
    std::vector<float> fpos(4 * nv);
    for (size_t i = 0; i < nv; i++)
        for (int c = 0; c < 3; c++) fpos[4 * i + c] = (float)pos[3 * i + c];
    double emb = 1e300;
    for (int rep = 0; rep < 2; rep++) { // best of two (first touches the pages)
        RTCScene scene = rtcNewScene(dev);
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, fpos.data(), 0,
                                   4 * sizeof(float), nv);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, tris.data(), 0,
                                   3 * sizeof(uint32_t), nt);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        t0 = now();
        rtcCommitScene(scene);
        emb = std::min(emb, now() - t0);
        rtcReleaseScene(scene);
    }
    rtcReleaseDevice(dev);
    row("BVH build (binned SAH)", sah, emb, "Embree", 0);
    row("BVH build (LBVH)", lbvh, emb, "Embree", 0);
    std::printf("  (SAH: %zu nodes, depth %zu; Embree: float, 4-wide, its default quality)\n", nn,
                sah_depth);

    // Closest point: ours vs CGAL AABB_tree.
    geom_meshdist_options mo = {};
    mo.threads = 1;
    geom_meshdist *md = NULL;
    t0 = now();
    geom_meshdist_create(pos.data(), nv, tris.data(), nt, &mo, &md, NULL);
    double md_build = now() - t0;
    std::vector<double> cd(mq);
    t0 = now();
    geom_meshdist_closest(md, mqs.data(), mq, NULL, NULL, NULL, cd.data(), 1, NULL);
    double md_q = now() - t0;

    typedef CGAL::Simple_cartesian<double> K;
    typedef K::Triangle_3 Tri;
    typedef std::vector<Tri>::iterator It;
    typedef CGAL::AABB_triangle_primitive<K, It> Prim;
    typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>> Tree;
    std::vector<Tri> ctris;
    ctris.reserve(nt);
    for (size_t t = 0; t < nt; t++) {
        const double *a = &pos[3 * tris[3 * t]], *b = &pos[3 * tris[3 * t + 1]], *c = &pos[3 * tris[3 * t + 2]];
        ctris.emplace_back(K::Point_3(a[0], a[1], a[2]), K::Point_3(b[0], b[1], b[2]),
                           K::Point_3(c[0], c[1], c[2]));
    }
    t0 = now();
    Tree tree(ctris.begin(), ctris.end());
    tree.build();
    tree.accelerate_distance_queries();
    double cg_build = now() - t0;
    double maxerr = 0;
    t0 = now();
    std::vector<double> cgd(mq);
    for (size_t i = 0; i < mq; i++) {
        K::Point_3 p(mqs[3 * i], mqs[3 * i + 1], mqs[3 * i + 2]);
        cgd[i] = std::sqrt(tree.squared_distance(p));
    }
    double cg_q = now() - t0;
    for (size_t i = 0; i < mq; i++) maxerr = std::max(maxerr, std::fabs(cgd[i] - cd[i]));
    row("closest-point index build", md_build, cg_build, "CGAL AABB", 0);
    char lab2[64];
    std::snprintf(lab2, sizeof lab2, "closest point, %zu queries", mq);
    row(lab2, md_q, cg_q, "CGAL AABB", maxerr);

    // Signed distance and winding numbers (no peer: the exact sum is ours).
    size_t sq = std::min<size_t>(mq, 20000);
    std::vector<double> sd(sq);
    geom_error_report rep;
    t0 = now();
    geom_meshdist_signed_distance(md, mqs.data(), sq, sd.data(), &rep, 1, NULL);
    double sd_t = now() - t0;
    std::printf("signed distance, %zu queries: %.4f s (winding error bound %.3g, %zu terms)\n", sq,
                sd_t, rep.max_error, rep.evaluations);
    geom_meshdist_destroy(md);
    std::printf("(times are process CPU seconds; whole run %.1f s wall-clock)\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
    return 0;
}
