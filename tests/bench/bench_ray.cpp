// Ray casting on one thread: libgeom (double, watertight, BVH from the
// spatial module) vs Embree 3 (float; default and RTC_SCENE_FLAG_ROBUST,
// rtcNewDevice("threads=1")) vs CGAL's AABB_tree (Simple_cartesian<double>,
// first_intersection), closest hits on the same mesh and the same rays:
// primary rays from a camera and random rays. Prints rays per second, the
// ratios, and how the answers agree (hit/miss, max |t - t_embree| / t).
// Each time is the thread CPU time of the best of three interleaved runs.
// Two tables: the mesh, then the mesh Loop-subdivided LEVELS times by the
// library (bunny00 twice: 1,206,528 triangles, the issue's "1.2M-triangle
// bunny", as in the spatial benchmark).
//
//   bench_ray [MESH.off] [N] [LEVELS]
//        (default: bunny00.off from libcgal-demo's data.tar.gz, extracted to
//        /tmp; N = 512: N*N rays of each kind; LEVELS = 2, 0: the mesh only)
#include <embree3/rtcore.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

extern "C" {
#include "geom/meshio.h"
#include "geom/ray.h"
#include "geom/subdiv.h"
// Internal (ray/ray_internal.h; the bench links the static library): the
// mesh traversal forced to SSE2 (0) or AVX2 (1), for the A/B of the two
// paths in the same run.
int geom__ray_scene_simd(geom_ray_scene *s, int isa);
}

typedef CGAL::Simple_cartesian<double> K;
typedef std::vector<K::Triangle_3>::const_iterator TriIt;
typedef CGAL::AABB_triangle_primitive<K, TriIt> Prim;
typedef CGAL::AABB_traits<K, Prim> Traits;
typedef CGAL::AABB_tree<Traits> Tree;

static double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// CPU time of the calling thread: every traced ray runs on it (Embree with
// threads=1 traces in the caller), and unlike wall time it does not count
// the time the shared machine gives to other processes.
static double cpu_now()
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

struct Ray {
    double o[3], d[3];
};

struct Result {
    std::vector<double> t; // NaN = miss
    double seconds;
};

static Result run_geom(const geom_ray_scene *s, const std::vector<Ray> &rays)
{
    Result r;
    r.t.resize(rays.size());
    double t0 = cpu_now();
    for (size_t i = 0; i < rays.size(); i++) {
        geom_ray q;
        q.origin = geom_vec3_make(rays[i].o[0], rays[i].o[1], rays[i].o[2]);
        q.dir = geom_vec3_make(rays[i].d[0], rays[i].d[1], rays[i].d[2]);
        q.tmin = 0;
        q.tmax = INFINITY;
        geom_ray_hit h;
        int found = 0;
        geom_ray_scene_closest(s, &q, &h, &found);
        r.t[i] = found ? h.t : NAN;
    }
    r.seconds = cpu_now() - t0;
    return r;
}

// The batch APIs take the rays in chunks of CHUNK through one reused
// buffer (as geom-raycast does), ours and Embree's stream alike: a whole
// set's hit records (262,144 of them, 35 MB for ours, 21 MB for Embree's)
// would stream through the cache and evict the trees.
static const size_t CHUNK = 4096;

// The batch entry point (the traversals of eight rays interleaved), the
// geom_ray records filled inside the timing as above.
static Result run_geom_many(const geom_ray_scene *s, const std::vector<Ray> &rays)
{
    Result r;
    r.t.resize(rays.size());
    std::vector<geom_ray> q(CHUNK);
    std::vector<geom_ray_hit> h(CHUNK);
    std::vector<int> found(CHUNK);
    double t0 = cpu_now();
    for (size_t b = 0; b < rays.size(); b += CHUNK) {
        size_t n = std::min(CHUNK, rays.size() - b);
        for (size_t i = 0; i < n; i++) {
            const Ray &ray = rays[b + i];
            q[i].origin = geom_vec3_make(ray.o[0], ray.o[1], ray.o[2]);
            q[i].dir = geom_vec3_make(ray.d[0], ray.d[1], ray.d[2]);
            q[i].tmin = 0;
            q[i].tmax = INFINITY;
        }
        geom_ray_scene_closest_many(s, q.data(), n, h.data(), found.data());
        for (size_t i = 0; i < n; i++) r.t[b + i] = found[i] ? h[i].t : NAN;
    }
    r.seconds = cpu_now() - t0;
    return r;
}

static void embree_ray(RTCRayHit &rh, const Ray &ray)
{
    rh.ray.org_x = (float)ray.o[0];
    rh.ray.org_y = (float)ray.o[1];
    rh.ray.org_z = (float)ray.o[2];
    rh.ray.dir_x = (float)ray.d[0];
    rh.ray.dir_y = (float)ray.d[1];
    rh.ray.dir_z = (float)ray.d[2];
    rh.ray.tnear = 0;
    rh.ray.tfar = INFINITY;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// Embree's stream API: rtcIntersect1M on chunks of CHUNK rays.
static Result run_embree_1M(RTCScene sc, const std::vector<Ray> &rays)
{
    Result r;
    r.t.resize(rays.size());
    std::vector<RTCRayHit> rh(CHUNK);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    double t0 = cpu_now();
    for (size_t b = 0; b < rays.size(); b += CHUNK) {
        size_t n = std::min(CHUNK, rays.size() - b);
        for (size_t i = 0; i < n; i++) embree_ray(rh[i], rays[b + i]);
        rtcIntersect1M(sc, &ctx, rh.data(), (unsigned)n, sizeof(RTCRayHit));
        for (size_t i = 0; i < n; i++)
            r.t[b + i] = rh[i].hit.geomID != RTC_INVALID_GEOMETRY_ID ? (double)rh[i].ray.tfar : NAN;
    }
    r.seconds = cpu_now() - t0;
    return r;
}

// Embree's packets of eight (rtcIntersect8), consecutive rays in a packet.
static Result run_embree_8(RTCScene sc, const std::vector<Ray> &rays)
{
    Result r;
    r.t.resize(rays.size());
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(32) RTCRayHit8 p;
    alignas(32) int valid[8];
    double t0 = cpu_now();
    for (size_t b = 0; b < rays.size(); b += 8) {
        for (int j = 0; j < 8; j++) {
            size_t i = b + (size_t)j;
            valid[j] = i < rays.size() ? -1 : 0;
            const Ray &ray = rays[i < rays.size() ? i : b];
            p.ray.org_x[j] = (float)ray.o[0];
            p.ray.org_y[j] = (float)ray.o[1];
            p.ray.org_z[j] = (float)ray.o[2];
            p.ray.dir_x[j] = (float)ray.d[0];
            p.ray.dir_y[j] = (float)ray.d[1];
            p.ray.dir_z[j] = (float)ray.d[2];
            p.ray.tnear[j] = 0;
            p.ray.tfar[j] = INFINITY;
            p.ray.mask[j] = 0xffffffffu;
            p.ray.flags[j] = 0;
            p.ray.time[j] = 0;
            p.ray.id[j] = (unsigned)j;
            p.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
            p.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, sc, &ctx, &p);
        for (int j = 0; j < 8 && b + (size_t)j < rays.size(); j++)
            r.t[b + (size_t)j] = p.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID ? (double)p.ray.tfar[j] : NAN;
    }
    r.seconds = cpu_now() - t0;
    return r;
}

static Result run_embree(RTCScene sc, const std::vector<Ray> &rays)
{
    Result r;
    r.t.resize(rays.size());
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    double t0 = cpu_now();
    for (size_t i = 0; i < rays.size(); i++) {
        RTCRayHit rh;
        embree_ray(rh, rays[i]);
        rtcIntersect1(sc, &ctx, &rh);
        r.t[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? (double)rh.ray.tfar : NAN;
    }
    r.seconds = cpu_now() - t0;
    return r;
}

static Result run_cgal(const Tree &tree, const std::vector<Ray> &rays, size_t stride)
{
    Result r;
    r.t.assign(rays.size(), NAN);
    double t0 = cpu_now();
    for (size_t i = 0; i < rays.size(); i += stride) {
        K::Ray_3 ray(K::Point_3(rays[i].o[0], rays[i].o[1], rays[i].o[2]),
                     K::Vector_3(rays[i].d[0], rays[i].d[1], rays[i].d[2]));
        auto hit = tree.first_intersection(ray);
        if (hit) {
            if (const K::Point_3 *p = boost::get<K::Point_3>(&hit->first)) {
                double dd = rays[i].d[0] * rays[i].d[0] + rays[i].d[1] * rays[i].d[1] + rays[i].d[2] * rays[i].d[2];
                r.t[i] = ((p->x() - rays[i].o[0]) * rays[i].d[0] + (p->y() - rays[i].o[1]) * rays[i].d[1] +
                          (p->z() - rays[i].o[2]) * rays[i].d[2]) / dd;
            } else {
                r.t[i] = 0; // segment (coplanar): counted as a hit
            }
        }
    }
    r.seconds = (cpu_now() - t0) * (double)stride;
    return r;
}

static void compare(const char *name, const Result &a, const Result &b, size_t stride)
{
    size_t n = 0, agree = 0, both = 0;
    double maxrel = 0;
    for (size_t i = 0; i < a.t.size(); i += stride) {
        n++;
        bool ha = !std::isnan(a.t[i]), hb = !std::isnan(b.t[i]);
        if (ha == hb) agree++;
        if (ha && hb) {
            both++;
            double rel = std::fabs(a.t[i] - b.t[i]) / std::fmax(std::fabs(b.t[i]), 1e-300);
            if (rel > maxrel) maxrel = rel;
        }
    }
    std::printf("    %-22s hit/miss agree %zu/%zu (%zu differ), max |t - t_ref|/t %.3g over %zu hits\n", name,
                agree, n, n - agree, maxrel, both);
}

// The triangles of m (faces fanned) and its positions.
static void mesh_soup(const geom_mesh *m, std::vector<double> &pos, std::vector<uint32_t> &tris)
{
    size_t nv = geom_mesh_n_vertices(m), nidx = 0;
    tris.clear();
    geom_mesh_to_soup(m, nullptr, nullptr, &nidx);
    std::vector<uint32_t> sizes(geom_mesh_n_live_faces(m)), idx(nidx);
    geom_mesh_to_soup(m, sizes.data(), idx.data(), &nidx);
    {
        size_t k = 0;
        for (uint32_t s : sizes) {
            for (uint32_t j = 1; j + 1 < s; j++) {
                tris.push_back(idx[k]);
                tris.push_back(idx[k + j]);
                tris.push_back(idx[k + j + 1]);
            }
            k += s;
        }
    }
    const double *P = geom_mesh_cpositions(m);
    pos.assign(P, P + 3 * nv);
}

// Every measurement on one mesh: builds, camera and random rays, agreement.
static void bench_mesh(const std::string &label, const std::vector<double> &pos, const std::vector<uint32_t> &tris,
                       int N)
{
    geom_diag diag;
    geom_diag_clear(&diag);
    size_t nv = pos.size() / 3, nt = tris.size() / 3;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = std::fmin(lo[k], pos[3 * i + k]);
            hi[k] = std::fmax(hi[k], pos[3 * i + k]);
        }
    double c[3], diagl = 0;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5 * (lo[k] + hi[k]);
        diagl += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    diagl = std::sqrt(diagl);
    std::printf("\nbench_ray: %s: %zu vertices, %zu triangles; %d x %d rays per set, one thread\n", label.c_str(),
                nv, nt, N, N);

    // Rays: a pinhole camera looking at the centre, and random rays.
    std::vector<Ray> cam, rnd;
    {
        double eye[3] = {c[0] + 0.3 * diagl, c[1] + 0.2 * diagl, c[2] + 1.2 * diagl};
        double fwd[3], up[3] = {0, 1, 0}, right[3], u2[3], l = 0;
        for (int k = 0; k < 3; k++) fwd[k] = c[k] - eye[k], l += fwd[k] * fwd[k];
        l = std::sqrt(l);
        for (int k = 0; k < 3; k++) fwd[k] /= l;
        right[0] = fwd[1] * up[2] - fwd[2] * up[1];
        right[1] = fwd[2] * up[0] - fwd[0] * up[2];
        right[2] = fwd[0] * up[1] - fwd[1] * up[0];
        u2[0] = right[1] * fwd[2] - right[2] * fwd[1];
        u2[1] = right[2] * fwd[0] - right[0] * fwd[2];
        u2[2] = right[0] * fwd[1] - right[1] * fwd[0];
        double rl = std::sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
        double ul = std::sqrt(u2[0] * u2[0] + u2[1] * u2[1] + u2[2] * u2[2]);
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                double sx = (x + 0.5) / N * 2 - 1, sy = (y + 0.5) / N * 2 - 1;
                Ray r;
                for (int k = 0; k < 3; k++) {
                    r.o[k] = eye[k];
                    r.d[k] = fwd[k] + 0.45 * (sx * right[k] / rl + sy * u2[k] / ul);
                }
                cam.push_back(r);
            }
        std::mt19937_64 g(12345);
        std::uniform_real_distribution<double> U(0, 1);
        for (int i = 0; i < N * N; i++) {
            double z = 2 * U(g) - 1, ph = 2 * M_PI * U(g), s = std::sqrt(1 - z * z);
            Ray r;
            double o[3] = {c[0] + diagl * s * std::cos(ph), c[1] + diagl * s * std::sin(ph), c[2] + diagl * z};
            for (int k = 0; k < 3; k++) {
                double tgt = lo[k] + (hi[k] - lo[k]) * U(g);
                r.o[k] = o[k];
                r.d[k] = tgt - o[k];
            }
            rnd.push_back(r);
        }
    }

    // Builds.
    double t0 = now();
    geom_ray_scene *gs = geom_ray_scene_create(nullptr);
    geom_ray_scene_add_triangles(gs, pos.data(), nv, tris.data(), nt, nullptr, nullptr);
    geom_ray_build_options bo;
    std::memset(&bo, 0, sizeof bo);
    bo.bvh_threads = 1;
    geom_ray_build_info info;
    if (geom_ray_scene_build(gs, &bo, &info, &diag) != GEOM_OK) {
        std::fprintf(stderr, "bench_ray: build failed: %s\n", diag.message);
        std::exit(1);
    }
    double tb_geom = now() - t0;

    RTCDevice dev = rtcNewDevice("threads=1");
    RTCScene esc[2];
    double tb_e[2];
    for (int robust = 0; robust < 2; robust++) {
        t0 = now();
        esc[robust] = rtcNewScene(dev);
        if (robust) rtcSetSceneFlags(esc[robust], RTC_SCENE_FLAG_ROBUST);
        RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *v = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                    3 * sizeof(float), nv);
        unsigned *ix = (unsigned *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), nt);
        for (size_t i = 0; i < 3 * nv; i++) v[i] = (float)pos[i];
        for (size_t i = 0; i < 3 * nt; i++) ix[i] = tris[i];
        rtcCommitGeometry(g);
        rtcAttachGeometry(esc[robust], g);
        rtcReleaseGeometry(g);
        rtcCommitScene(esc[robust]);
        tb_e[robust] = now() - t0;
    }

    t0 = now();
    std::vector<K::Triangle_3> ktris;
    ktris.reserve(nt);
    for (size_t i = 0; i < nt; i++) {
        const double *a = &pos[3 * tris[3 * i]], *b = &pos[3 * tris[3 * i + 1]], *cc = &pos[3 * tris[3 * i + 2]];
        ktris.emplace_back(K::Point_3(a[0], a[1], a[2]), K::Point_3(b[0], b[1], b[2]),
                           K::Point_3(cc[0], cc[1], cc[2]));
    }
    Tree tree(ktris.begin(), ktris.end());
    tree.build();
    double tb_cgal = now() - t0;

    std::printf("build seconds: libgeom %.4f (SAH, %zu nodes, %zu bytes)  embree %.4f  embree-robust %.4f  "
                "cgal %.4f\n",
                tb_geom, info.bvh_nodes, info.bvh_bytes, tb_e[0], tb_e[1], tb_cgal);

    const int isa = geom__ray_scene_simd(gs, -1); // the path chosen at build (-1: left unchanged)
    const size_t cstride = 4;
    const char *names[2] = {"camera", "random"};
    const std::vector<Ray> *sets[2] = {&cam, &rnd};
    for (int si = 0; si < 2; si++) {
        const std::vector<Ray> &rays = *sets[si];
        // Best of three runs each (interleaved): the machine may be shared.
        Result rg, re, rr, rc, rs, gm, em[2], e8[2];
        for (int rep = 0; rep < 3; rep++) {
            geom__ray_scene_simd(gs, 0);
            Result s2 = run_geom(gs, rays);
            geom__ray_scene_simd(gs, isa);
            Result a = run_geom(gs, rays), b = run_embree(esc[0], rays), c2 = run_embree(esc[1], rays),
                   d = run_cgal(tree, rays, cstride);
            Result g2 = run_geom_many(gs, rays);
            for (int md = 0; md < 2; md++) {
                Result x = run_embree_1M(esc[md], rays), y = run_embree_8(esc[md], rays);
                if (rep == 0 || x.seconds < em[md].seconds) em[md] = x;
                if (rep == 0 || y.seconds < e8[md].seconds) e8[md] = y;
            }
            if (rep == 0 || g2.seconds < gm.seconds) gm = g2;
            if (rep == 0 || s2.seconds < rs.seconds) rs = s2;
            if (rep == 0 || a.seconds < rg.seconds) rg = a;
            if (rep == 0 || b.seconds < re.seconds) re = b;
            if (rep == 0 || c2.seconds < rr.seconds) rr = c2;
            if (rep == 0 || d.seconds < rc.seconds) rc = d;
        }
        double n = (double)rays.size();
        size_t hits = 0;
        for (double t : rg.t) hits += !std::isnan(t);
        std::printf("%s rays (%zu, %zu hit):\n", names[si], rays.size(), hits);
        std::printf("  rays/s: libgeom %.4g  embree %.4g  embree-robust %.4g  cgal %.4g (every %zuth ray)\n",
                    n / rg.seconds, n / re.seconds, n / rr.seconds, n / rc.seconds, cstride);
        std::printf("  ratio libgeom/embree %.3f  libgeom/embree-robust %.3f  libgeom/cgal %.2f\n",
                    re.seconds / rg.seconds, rr.seconds / rg.seconds, rc.seconds / rg.seconds);
        std::printf("  libgeom path %s; the SSE2 path in the same run: %.4g rays/s, ratio to embree %.3f, "
                    "embree-robust %.3f\n",
                    isa == 1 ? "AVX2" : "SSE2", n / rs.seconds, re.seconds / rs.seconds, rr.seconds / rs.seconds);
        {
            // The goal is judged against Embree's best API in each mode.
            double eb[2] = {std::min(re.seconds, std::min(em[0].seconds, e8[0].seconds)),
                            std::min(rr.seconds, std::min(em[1].seconds, e8[1].seconds))};
            double gb = std::min(rg.seconds, gm.seconds);
            std::printf("  batch rays/s: libgeom closest_many %.4g  embree 1M %.4g  embree 8 %.4g  "
                        "embree-robust 1M %.4g  embree-robust 8 %.4g\n",
                        n / gm.seconds, n / em[0].seconds, n / e8[0].seconds, n / em[1].seconds, n / e8[1].seconds);
            std::printf("  best of each: libgeom %.4g  embree %.4g  embree-robust %.4g rays/s; "
                        "ratio libgeom/embree %.3f  libgeom/embree-robust %.3f\n",
                        n / gb, n / eb[0], n / eb[1], eb[0] / gb, eb[1] / gb);
        }
        compare("libgeom batch vs embree", gm, re, 1);
        compare("libgeom batch vs libgeom", gm, rg, 1);
        compare("embree 1M vs embree", em[0], re, 1);
        compare("embree 8 vs embree", e8[0], re, 1);
        compare("libgeom vs embree", rg, re, 1);
        compare("libgeom sse2 vs embree", rs, re, 1);
        compare("libgeom vs embree-rob", rg, rr, 1);
        compare("libgeom vs cgal", rg, rc, cstride);
        compare("embree vs cgal", re, rc, cstride);
    }
    rtcReleaseScene(esc[0]);
    rtcReleaseScene(esc[1]);
    rtcReleaseDevice(dev);
    geom_ray_scene_destroy(gs);
}


int main(int argc, char **argv)
{
    std::string path = argc > 1 ? argv[1] : "/tmp/geom-bench-data/data/meshes/bunny00.off";
    int N = argc > 2 ? std::atoi(argv[2]) : 512;
    int levels = argc > 3 ? std::atoi(argv[3]) : 2;
    if (argc <= 1) {
        FILE *f = std::fopen(path.c_str(), "rb");
        if (!f) {
            if (std::system("mkdir -p /tmp/geom-bench-data && tar xzf /usr/share/doc/libcgal-dev/data.tar.gz "
                            "-C /tmp/geom-bench-data data/meshes/bunny00.off") != 0) {
                std::fprintf(stderr, "bench_ray: cannot extract bunny00.off (install libcgal-demo)\n");
                return 1;
            }
        } else {
            std::fclose(f);
        }
    }
    geom_mesh *m = nullptr;
    geom_diag diag;
    geom_diag_clear(&diag);
    if (geom_meshio_read(path.c_str(), nullptr, &m, nullptr, &diag) != GEOM_OK) {
        std::fprintf(stderr, "bench_ray: %s: %s\n", path.c_str(), diag.message);
        return 1;
    }
    std::vector<double> pos;
    std::vector<uint32_t> tris;
    mesh_soup(m, pos, tris);
    bench_mesh(path, pos, tris, N);
    if (levels > 0) {
        // The same mesh Loop-subdivided (bunny00 twice: 1,206,528 triangles,
        // as the spatial benchmark's mesh).
        geom_subdiv_options so;
        std::memset(&so, 0, sizeof so);
        so.scheme = GEOM_SUBDIV_LOOP;
        geom_mesh *sm = nullptr;
        if (geom_subdiv_mesh(m, &so, levels, 0, &sm, nullptr, &diag) != GEOM_OK) {
            std::fprintf(stderr, "bench_ray: Loop subdivision failed: %s\n", diag.message);
            return 1;
        }
        mesh_soup(sm, pos, tris);
        geom_mesh_destroy(sm);
        bench_mesh(path + " Loop-subdivided " + std::to_string(levels) + "x", pos, tris, N);
    }
    geom_mesh_destroy(m);
    return 0;
}
