// Benchmark: loading a 1M-triangle OBJ with libgeom (geom_meshio_read: parse
// and build the half-edge mesh with its corner channels) and with
// tinyobjloader (Debian libtinyobjloader-dev, the double-precision build:
// parse into flat arrays, no topology), in the same run on the same file.
//
// The file is generated here: a torus of 1000 x 500 quads split into
// triangles (1,000,000 triangles, 500,000 vertices), with vt and vn and
// faces "f v/vt/vn". Two number styles: "%.6f" (what most exporters write)
// and 17 significant digits (what exact writers write). For each loader it
// prints the best of 3 wall-clock times, the ratio, and the accuracy of the
// parsed positions against strtod (correctly rounded): the largest error in
// units in the last place over all coordinates.
//
// Built by tests/bench/CMakeLists.txt when tinyobjloader is found; `make bench`
// installs it and runs this.
// or by hand (one line):
//   g++ -O2 -DTINYOBJLOADER_USE_DOUBLE tests/bench/bench_obj_load.cpp
//       -Ilibgeom/include build/libgeom/libgeom.a -ltinyobjloader_double -lm
//       -o bench_obj_load
// Usage: bench_obj_load [N_U N_V]   (torus grid size; default 1000 500)
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#ifndef TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_USE_DOUBLE
#endif
#include <tiny_obj_loader.h>

#include "geom/meshio.h"

static double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// Write the torus OBJ; returns the exact coordinates as strtod reads them.
static std::vector<double> write_torus(const char *path, int nu, int nv, bool exact)
{
    FILE *fp = std::fopen(path, "w");
    if (!fp) {
        std::perror(path);
        std::exit(1);
    }
    std::vector<double> ref;
    ref.reserve(3 * (size_t)nu * nv);
    const double R = 2.0, r = 0.75, pi = 3.14159265358979323846;
    char buf[3][40];
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double a = 2 * pi * i / nu, b = 2 * pi * j / nv;
            double p[3] = {(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a),
                           r * std::sin(b)};
            for (int k = 0; k < 3; k++) {
                std::snprintf(buf[k], sizeof buf[k], exact ? "%.17g" : "%.6f", p[k]);
                ref.push_back(std::strtod(buf[k], nullptr));
            }
            std::fprintf(fp, "v %s %s %s\n", buf[0], buf[1], buf[2]);
        }
    for (int i = 0; i <= nu; i++)
        for (int j = 0; j <= nv; j++)
            std::fprintf(fp, exact ? "vt %.17g %.17g\n" : "vt %.6f %.6f\n", (double)i / nu,
                         (double)j / nv);
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double a = 2 * pi * i / nu, b = 2 * pi * j / nv;
            std::fprintf(fp, exact ? "vn %.17g %.17g %.17g\n" : "vn %.6f %.6f %.6f\n",
                         std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b));
        }
    auto V = [&](int i, int j) { return (i % nu) * nv + (j % nv) + 1; };
    auto T = [&](int i, int j) { return i * (nv + 1) + j + 1; };
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int a = V(i, j), b = V(i + 1, j), c = V(i + 1, j + 1), d = V(i, j + 1);
            int ta = T(i, j), tb = T(i + 1, j), tc = T(i + 1, j + 1), td = T(i, j + 1);
            std::fprintf(fp, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", a, ta, a, b, tb, b, c, tc, c);
            std::fprintf(fp, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", a, ta, a, c, tc, c, d, td, d);
        }
    std::fclose(fp);
    return ref;
}

static double ulp_error(double got, double want)
{
    if (got == want)
        return 0;
    double ulp = std::nextafter(std::fabs(want), INFINITY) - std::fabs(want);
    return std::fabs(got - want) / ulp;
}

int main(int argc, char **argv)
{
    int nu = argc > 2 ? std::atoi(argv[1]) : 1000, nv = argc > 2 ? std::atoi(argv[2]) : 500;
    std::string path = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                       "/bench_obj_load.obj";
    std::printf("OBJ load: torus %d x %d quads = %zu triangles, %zu vertices, v/vt/vn faces\n",
                nu, nv, (size_t)2 * nu * nv, (size_t)nu * nv);
    for (int exact = 0; exact < 2; exact++) {
        std::vector<double> ref = write_torus(path.c_str(), nu, nv, exact);
        FILE *fp = std::fopen(path.c_str(), "rb");
        std::fseek(fp, 0, SEEK_END);
        long bytes = std::ftell(fp);
        std::fclose(fp);
        std::printf("\nnumbers %s, file %.1f MB\n", exact ? "%.17g" : "%.6f", bytes / 1e6);

        double best_geom = 1e300, best_tiny = 1e300, err_geom = 0, err_tiny = 0;
        size_t faces_geom = 0, faces_tiny = 0;
        for (int rep = 0; rep < 3; rep++) {
            geom_mesh *m = nullptr;
            geom_diag d;
            double t0 = now();
            geom_status st = geom_meshio_read(path.c_str(), nullptr, &m, nullptr, &d);
            double t1 = now();
            if (st != GEOM_OK) {
                std::fprintf(stderr, "libgeom: %s\n", d.message);
                return 1;
            }
            best_geom = std::min(best_geom, t1 - t0);
            faces_geom = geom_mesh_n_faces(m);
            const double *p = geom_mesh_cpositions(m);
            err_geom = 0;
            for (size_t i = 0; i < ref.size(); i++)
                err_geom = std::max(err_geom, ulp_error(p[i], ref[i]));
            geom_mesh_destroy(m);

            tinyobj::attrib_t attrib;
            std::vector<tinyobj::shape_t> shapes;
            std::vector<tinyobj::material_t> materials;
            std::string warn, err;
            t0 = now();
            bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, path.c_str(),
                                       nullptr, false);
            t1 = now();
            if (!ok) {
                std::fprintf(stderr, "tinyobjloader: %s\n", err.c_str());
                return 1;
            }
            best_tiny = std::min(best_tiny, t1 - t0);
            faces_tiny = 0;
            for (auto &s : shapes)
                faces_tiny += s.mesh.num_face_vertices.size();
            err_tiny = 0;
            for (size_t i = 0; i < ref.size() && i < attrib.vertices.size(); i++)
                err_tiny = std::max(err_tiny, ulp_error(attrib.vertices[i], ref[i]));
        }
        std::printf("  %-40s %8.3f s  %zu faces  max error %g ulp\n",
                    "libgeom geom_meshio_read (half-edge)", best_geom, faces_geom, err_geom);
        std::printf("  %-40s %8.3f s  %zu faces  max error %g ulp\n",
                    "tinyobjloader LoadObj (arrays, double)", best_tiny, faces_tiny, err_tiny);
        std::printf("  ratio libgeom / tinyobjloader: %.2f\n", best_geom / best_tiny);
    }
    std::remove(path.c_str());
    return 0;
}
