/*
 * bench_iso: marching cubes, achieved error against run time, libgeom
 * (geom_iso_extract_grid) next to VTK's vtkFlyingEdges3D and
 * vtkMarchingCubes and scikit-image's measure.marching_cubes (Lewiner), on
 * the same sampled field in the same run, for grids of 32^3 to 512^3 cells.
 *
 * Fields (exact functions with exact gradients, sampled once per
 * resolution into a dense double grid that every method reads):
 *   gyroid: sin x cos y + sin y cos z + sin z cos x over [-pi, pi]^3
 *           (offset by 0.01 so no symmetry plane falls on the grid);
 *   torus:  the signed distance to a torus (radii 1, 0.35) over
 *           [-1.5, 1.5] x [-1.5, 1.5] x [-0.5, 0.5] (cells 3:3:1).
 * Error: for every method's output, geom_iso_measure_error against the
 * exact field: max and mean of |f| / |grad f| over the triangle samples
 * (centroid and edge midpoints; vertex errors are printed too). The same
 * code measures every method.
 * Time: the extraction call alone (sampling excluded), best of 3 up to
 * 256^3, one run at 512^3. "1 core": libgeom with threads = 1, VTK with
 * its Sequential SMP backend; libgeom is also timed with every core.
 * scikit-image runs in /usr/bin/python3 on the same samples (written to a
 * temporary file); its time is measured inside Python around the call.
 *
 * Usage: bench_iso [max_res] [field]   (defaults 512 and both fields)
 */
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkDoubleArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkMarchingCubes.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <unistd.h>

extern "C" {
#include "geom/iso.h"
}

#ifndef GEOM_PYTHON3
#define GEOM_PYTHON3 "/usr/bin/python3"
#endif

namespace {

const double PI = 3.14159265358979323846;

double gyroid(void *, const double p[3])
{
    return std::sin(p[0]) * std::cos(p[1]) + std::sin(p[1]) * std::cos(p[2]) +
           std::sin(p[2]) * std::cos(p[0]);
}

double gyroid_grad(void *u, const double p[3], double g[3]) // returns the value too
{
    double sx = std::sin(p[0]), cx = std::cos(p[0]), sy = std::sin(p[1]), cy = std::cos(p[1]),
           sz = std::sin(p[2]), cz = std::cos(p[2]);
    g[0] = cx * cy - sz * sx;
    g[1] = -sx * sy + cy * cz;
    g[2] = -sy * sz + cz * cx;
    return gyroid(u, p);
}

double torus(void *, const double p[3])
{
    double q = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 1.0;
    return std::sqrt(q * q + p[2] * p[2]) - 0.35;
}

double torus_grad(void *u, const double p[3], double g[3]) // returns the value too
{
    double r = std::sqrt(p[0] * p[0] + p[1] * p[1]);
    double q = r - 1.0;
    double d = std::sqrt(q * q + p[2] * p[2]);
    if (r == 0 || d == 0) {
        g[0] = g[1] = g[2] = 0;
        return torus(u, p);
    }
    g[0] = q / d * p[0] / r;
    g[1] = q / d * p[1] / r;
    g[2] = p[2] / d;
    return torus(u, p);
}

struct field_def {
    const char *name;
    geom_iso_value_fn f;
    geom_iso_gradient_fn g;
    double lo[3], hi[3];
    int ratio[3]; /* cells per axis = res * ratio / max(ratio) */
};

struct mesh {
    std::vector<double> xyz;
    std::vector<uint32_t> tris;
};

struct result {
    size_t nv = 0, nt = 0;
    double seconds = 0;
    geom_error_report ve{}, se{};
    bool ok = false;
};

double now()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

void measure(const field_def &fd, const mesh &m, result &r)
{
    geom_iso_field f;
    std::memset(&f, 0, sizeof f);
    f.value = fd.f;
    f.gradient = fd.g;
    f.exact = 1;
    r.nv = m.xyz.size() / 3;
    r.nt = m.tris.size() / 3;
    size_t un = 0;
    geom_iso_measure_error(&f, 0.0, r.nv, m.xyz.data(), r.nt, m.tris.data(), &r.ve, &r.se, &un);
}

void from_polydata(vtkPolyData *pd, mesh &m)
{
    vtkPoints *pts = pd->GetPoints();
    size_t n = pts ? (size_t)pts->GetNumberOfPoints() : 0;
    m.xyz.resize(3 * n);
    for (size_t i = 0; i < n; i++)
        pts->GetPoint((vtkIdType)i, &m.xyz[3 * i]);
    m.tris.clear();
    vtkCellArray *polys = pd->GetPolys();
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
        vtkIdType npts;
        const vtkIdType *ids;
        it->GetCurrentCell(npts, ids);
        for (vtkIdType k = 1; k + 1 < npts; k++) {
            m.tris.push_back((uint32_t)ids[0]);
            m.tris.push_back((uint32_t)ids[k]);
            m.tris.push_back((uint32_t)ids[k + 1]);
        }
    }
}

template <class Filter> void run_vtk(vtkImageData *img, int reps, result &r, mesh &m)
{
    double best = 1e300;
    for (int q = 0; q < reps; q++) {
        vtkNew<Filter> f;
        f->SetInputData(img);
        f->SetValue(0, 0.0);
        f->ComputeNormalsOff();
        f->ComputeGradientsOff();
        f->ComputeScalarsOff();
        double t0 = now();
        f->Update();
        double dt = now() - t0;
        if (dt < best)
            best = dt;
        if (q == reps - 1)
            from_polydata(f->GetOutput(), m);
    }
    r.seconds = best;
    r.ok = true;
}

void run_ours(const geom_iso_grid &g, int threads, int reps, result &r, mesh &m)
{
    geom_iso_options o;
    std::memset(&o, 0, sizeof o);
    o.threads = threads;
    o.error = GEOM_ISO_ERROR_NEVER;
    double best = 1e300;
    for (int q = 0; q < reps; q++) {
        geom_iso_surface s;
        double t0 = now();
        geom_status st = geom_iso_extract_grid(&g, &o, &s, NULL);
        double dt = now() - t0;
        if (st != GEOM_OK) {
            std::fprintf(stderr, "geom_iso_extract_grid: %s\n", geom_status_str(st));
            return;
        }
        if (dt < best)
            best = dt;
        if (q == reps - 1) {
            m.xyz.assign(s.xyz, s.xyz + 3 * s.n_vertices);
            m.tris.assign(s.tris, s.tris + 3 * s.n_triangles);
        }
        geom_iso_surface_free(&s);
    }
    r.seconds = best;
    r.ok = true;
}

/* scikit-image in Debian's python3 on the samples written to a file. */
bool run_skimage(const std::vector<double> &data, const size_t dims[3], const double org[3],
                 const double sp[3], result &r, mesh &m)
{
    char dir[] = "/tmp/bench_iso_XXXXXX";
    if (!mkdtemp(dir))
        return false;
    std::string base(dir);
    std::string vol = base + "/vol.f64", script = base + "/mc.py", verts = base + "/v.f64",
                faces = base + "/f.i64", info = base + "/info.txt";
    FILE *fp = std::fopen(vol.c_str(), "wb");
    if (!fp)
        return false;
    std::fwrite(data.data(), sizeof(double), data.size(), fp);
    std::fclose(fp);
    fp = std::fopen(script.c_str(), "w");
    std::fprintf(fp,
                 "import sys, time\n"
                 "import numpy as np\n"
                 "from skimage import measure\n"
                 "nx, ny, nz = %zu, %zu, %zu\n"
                 "v = np.fromfile(sys.argv[1], dtype=np.float64).reshape((nz, ny, nx))\n"
                 "t = time.perf_counter()\n"
                 "verts, faces, _, _ = measure.marching_cubes(v, level=0.0, spacing=(%.17g, "
                 "%.17g, %.17g))\n"
                 "dt = time.perf_counter() - t\n"
                 "xyz = np.ascontiguousarray(verts[:, ::-1]) + np.array([%.17g, %.17g, %.17g])\n"
                 "xyz.astype(np.float64).tofile(sys.argv[2])\n"
                 "faces.astype(np.int64).tofile(sys.argv[3])\n"
                 "open(sys.argv[4], 'w').write('%%r %%d %%d\\n' %% (dt, len(xyz), len(faces)))\n",
                 dims[0], dims[1], dims[2], sp[2], sp[1], sp[0], org[0], org[1], org[2]);
    std::fclose(fp);
    std::string cmd = std::string(GEOM_PYTHON3) + " " + script + " " + vol + " " + verts + " " +
                      faces + " " + info;
    int rc = std::system(cmd.c_str());
    bool ok = false;
    fp = rc == 0 ? std::fopen(info.c_str(), "r") : nullptr;
    double dt;
    size_t nv, nf;
    if (fp && std::fscanf(fp, "%lf %zu %zu", &dt, &nv, &nf) == 3) {
        m.xyz.resize(3 * nv);
        std::vector<int64_t> f(3 * nf);
        FILE *a = std::fopen(verts.c_str(), "rb"), *b = std::fopen(faces.c_str(), "rb");
        if (a && b && std::fread(m.xyz.data(), sizeof(double), 3 * nv, a) == 3 * nv &&
            std::fread(f.data(), sizeof(int64_t), 3 * nf, b) == 3 * nf) {
            m.tris.assign(f.begin(), f.end());
            r.seconds = dt;
            r.ok = ok = true;
        }
        if (a)
            std::fclose(a);
        if (b)
            std::fclose(b);
    }
    if (fp)
        std::fclose(fp);
    std::remove(vol.c_str());
    std::remove(script.c_str());
    std::remove(verts.c_str());
    std::remove(faces.c_str());
    std::remove(info.c_str());
    rmdir(dir);
    return ok;
}

void print_row(const char *field, size_t res, const char *method, const result &r, double ref)
{
    if (!r.ok) {
        std::printf("%-7s %4zu  %-22s  (not run)\n", field, res, method);
        return;
    }
    std::printf("%-7s %4zu  %-22s %9zu %9zu %10.4f %7.2f  %10.3e %10.3e %10.3e\n", field, res,
                method, r.nv, r.nt, r.seconds, ref > 0 ? r.seconds / ref : 0.0,
                r.se.max_error, r.se.mean_error, r.ve.max_error);
}

} // namespace

int main(int argc, char **argv)
{
    size_t maxres = argc > 1 ? (size_t)std::atoi(argv[1]) : 512;
    const char *only = argc > 2 ? argv[2] : nullptr;
    const field_def fields[] = {
        {"gyroid", gyroid, gyroid_grad, {-PI + 0.01, -PI + 0.01, -PI + 0.01},
         {PI + 0.01, PI + 0.01, PI + 0.01}, {1, 1, 1}},
        {"torus", torus, torus_grad, {-1.5, -1.5, -0.5}, {1.5, 1.5, 0.5}, {3, 3, 1}},
    };
    std::printf("bench_iso: marching cubes error vs time (libgeom %s)\n", GEOM_VERSION_STRING);
    std::printf("time: extraction only; ratio: time / vtkFlyingEdges3D (1 core)\n");
    std::printf("error: |f| / |grad f| at triangle samples (max, mean) and at vertices (max)\n\n");
    std::printf("%-7s %4s  %-22s %9s %9s %10s %7s  %10s %10s %10s\n", "field", "res", "method",
                "vertices", "triangles", "seconds", "ratio", "max_err", "mean_err", "vert_err");
    for (const field_def &fd : fields) {
        if (only && std::strcmp(only, fd.name) != 0)
            continue;
        for (size_t res = 32; res <= maxres; res *= 2) {
            int rmax = 1;
            for (int a = 0; a < 3; a++)
                rmax = fd.ratio[a] > rmax ? fd.ratio[a] : rmax;
            size_t dims[3];
            double sp[3];
            for (int a = 0; a < 3; a++) {
                size_t cells = res * (size_t)fd.ratio[a] / (size_t)rmax;
                dims[a] = cells + 1;
                sp[a] = (fd.hi[a] - fd.lo[a]) / (double)cells;
            }
            std::vector<double> data(dims[0] * dims[1] * dims[2]);
            for (size_t k = 0; k < dims[2]; k++)
                for (size_t j = 0; j < dims[1]; j++)
                    for (size_t i = 0; i < dims[0]; i++) {
                        double p[3] = {fd.lo[0] + (double)i * sp[0], fd.lo[1] + (double)j * sp[1],
                                       fd.lo[2] + (double)k * sp[2]};
                        data[i + dims[0] * (j + dims[1] * k)] = fd.f(nullptr, p);
                    }
            int reps = res >= 512 ? 1 : 3;
            geom_iso_grid g;
            std::memset(&g, 0, sizeof g);
            for (int a = 0; a < 3; a++) {
                g.dims[a] = dims[a];
                g.spacing[a] = sp[a];
                g.origin[a] = fd.lo[a];
            }
            g.type = GEOM_ISO_SCALAR_F64;
            g.data = data.data();

            vtkNew<vtkImageData> img;
            img->SetDimensions((int)dims[0], (int)dims[1], (int)dims[2]);
            img->SetSpacing(sp[0], sp[1], sp[2]);
            img->SetOrigin(fd.lo[0], fd.lo[1], fd.lo[2]);
            vtkNew<vtkDoubleArray> arr;
            arr->SetNumberOfComponents(1);
            arr->SetArray(data.data(), (vtkIdType)data.size(), 1);
            arr->SetName("f");
            img->GetPointData()->SetScalars(arr);

            mesh m;
            result fe1, mc1, ours1, oursn, sk;
            vtkSMPTools::SetBackend("Sequential");
            run_vtk<vtkFlyingEdges3D>(img, reps, fe1, m);
            measure(fd, m, fe1);
            run_vtk<vtkMarchingCubes>(img, reps, mc1, m);
            measure(fd, m, mc1);
            run_ours(g, 1, reps, ours1, m);
            measure(fd, m, ours1);
            run_ours(g, 0, reps, oursn, m);
            measure(fd, m, oursn);
            result fen;
            vtkSMPTools::SetBackend("TBB");
            run_vtk<vtkFlyingEdges3D>(img, reps, fen, m);
            measure(fd, m, fen);
            if (run_skimage(data, dims, fd.lo, sp, sk, m))
                measure(fd, m, sk);

            double ref = fe1.seconds;
            print_row(fd.name, res, "libgeom (1 core)", ours1, ref);
            print_row(fd.name, res, "vtkFlyingEdges3D (1)", fe1, ref);
            print_row(fd.name, res, "vtkMarchingCubes (1)", mc1, ref);
            print_row(fd.name, res, "skimage marching_cubes", sk, ref);
            print_row(fd.name, res, "libgeom (all cores)", oursn, ref);
            print_row(fd.name, res, "vtkFlyingEdges3D (TBB)", fen, ref);
            std::fflush(stdout);
        }
    }
    return 0;
}
