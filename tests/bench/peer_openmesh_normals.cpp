// Whole-process peer of `geom-normals --weight area IN.obj -o OUT.obj`: read
// the OBJ into an OpenMesh 9 triangle mesh (double precision), compute
// area-weighted vertex normals (the sum of the faces' cross products,
// normalised: the same weights as libgeom's "area"), and write an OBJ with
// the vertex normals at 17 significant digits (exact, as libgeom writes).
// Run by tests/bench/whole_process.sh against geom-normals on the same file.
// Usage: peer_openmesh_normals IN.obj OUT.obj
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cmath>
#include <cstdio>

struct DTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<DTraits> OMesh;

int main(int argc, char **argv)
{
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s IN.obj OUT.obj\n", argv[0]);
        return 2;
    }
    OMesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
        std::fprintf(stderr, "%s: cannot read\n", argv[1]);
        return 1;
    }
    mesh.request_vertex_normals();
    for (auto v : mesh.vertices())
        mesh.set_normal(v, OMesh::Normal(0, 0, 0));
    for (auto f : mesh.faces()) {
        auto h = mesh.halfedge_handle(f);
        auto a = mesh.to_vertex_handle(h);
        h = mesh.next_halfedge_handle(h);
        auto b = mesh.to_vertex_handle(h);
        h = mesh.next_halfedge_handle(h);
        auto c = mesh.to_vertex_handle(h);
        OMesh::Normal n = OpenMesh::cross(mesh.point(b) - mesh.point(a), mesh.point(c) - mesh.point(a));
        mesh.set_normal(a, mesh.normal(a) + n);
        mesh.set_normal(b, mesh.normal(b) + n);
        mesh.set_normal(c, mesh.normal(c) + n);
    }
    for (auto v : mesh.vertices()) {
        double l = mesh.normal(v).norm();
        if (l > 0)
            mesh.set_normal(v, mesh.normal(v) / l);
    }
    if (!OpenMesh::IO::write_mesh(mesh, argv[2], OpenMesh::IO::Options::VertexNormal, 17)) {
        std::fprintf(stderr, "%s: cannot write\n", argv[2]);
        return 1;
    }
    return 0;
}
