// Whole-process peer of
//   geom-iso -e 'min(torus(-0.7,0,0,0.9,0.3), torus(0.7,0,0,0.9,0.3))'
//            -b -2.16,-1.296,-0.432,2.16,1.296,0.432 -r NX,NY,NZ -o OUT.obj
// with VTK: the same function sampled at the same (NX+1)(NY+1)(NZ+1) grid
// nodes into a vtkImageData (doubles), vtkFlyingEdges3D at 0, and the
// triangles written as OBJ (points with the shortest round-trip text of
// their float coordinates, std::to_chars). Run by
// tests/bench/whole_process.sh against geom-iso; not a test.
//
// Usage: peer_iso_vtk NX NY NZ OUT.obj
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

static double torus(double x, double y, double z, double cx, double R, double r)
{
    double qx = x - cx;
    double d = std::sqrt(qx * qx + y * y) - R;
    return std::sqrt(d * d + z * z) - r;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        std::fprintf(stderr, "usage: %s NX NY NZ OUT.obj\n", argv[0]);
        return 2;
    }
    int n[3] = {std::atoi(argv[1]), std::atoi(argv[2]), std::atoi(argv[3])};
    const double lo[3] = {-2.16, -1.296, -0.432}, hi[3] = {2.16, 1.296, 0.432};
    double h[3];
    for (int a = 0; a < 3; a++)
        h[a] = (hi[a] - lo[a]) / n[a];
    vtkNew<vtkImageData> img;
    img->SetDimensions(n[0] + 1, n[1] + 1, n[2] + 1);
    img->SetOrigin(lo[0], lo[1], lo[2]);
    img->SetSpacing(h[0], h[1], h[2]);
    vtkNew<vtkDoubleArray> s;
    s->SetNumberOfTuples((vtkIdType)(n[0] + 1) * (n[1] + 1) * (n[2] + 1));
    double *d = s->GetPointer(0);
    size_t i = 0;
    for (int k = 0; k <= n[2]; k++) {
        double z = k == n[2] ? hi[2] : lo[2] + k * h[2];
        for (int j = 0; j <= n[1]; j++) {
            double y = j == n[1] ? hi[1] : lo[1] + j * h[1];
            for (int q = 0; q <= n[0]; q++) {
                double x = q == n[0] ? hi[0] : lo[0] + q * h[0];
                d[i++] = std::fmin(torus(x, y, z, -0.7, 0.9, 0.3), torus(x, y, z, 0.7, 0.9, 0.3));
            }
        }
    }
    img->GetPointData()->SetScalars(s);
    vtkNew<vtkFlyingEdges3D> fe;
    fe->SetInputData(img);
    fe->SetValue(0, 0.0);
    fe->ComputeNormalsOff();
    fe->ComputeGradientsOff();
    fe->ComputeScalarsOff();
    fe->Update();
    vtkPolyData *out = fe->GetOutput();
    FILE *o = std::fopen(argv[4], "wb");
    if (!o)
        return 1;
    std::vector<char> buf;
    buf.reserve(1 << 21);
    char tmp[64];
    auto flush = [&]() {
        std::fwrite(buf.data(), 1, buf.size(), o);
        buf.clear();
    };
    vtkPoints *pts = out->GetPoints();
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); p++) {
        double x[3];
        pts->GetPoint(p, x);
        buf.push_back('v');
        for (int a = 0; a < 3; a++) {
            buf.push_back(' ');
            auto t = std::to_chars(tmp, tmp + sizeof tmp, (float)x[a]);
            buf.insert(buf.end(), tmp, t.ptr);
        }
        buf.push_back('\n');
        if (buf.size() > (1 << 20))
            flush();
    }
    vtkCellArray *polys = out->GetPolys();
    vtkIdType npts;
    const vtkIdType *ids;
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);) {
        buf.push_back('f');
        for (vtkIdType c = 0; c < npts; c++) {
            buf.push_back(' ');
            auto t = std::to_chars(tmp, tmp + sizeof tmp, (long long)ids[c] + 1);
            buf.insert(buf.end(), tmp, t.ptr);
        }
        buf.push_back('\n');
        if (buf.size() > (1 << 20))
            flush();
    }
    flush();
    std::fclose(o);
    std::fprintf(stderr, "vtk: %lld points, %lld triangles\n", (long long)out->GetNumberOfPoints(),
                 (long long)out->GetNumberOfPolys());
    return 0;
}
