// Subdivision reference for libgeom's tests: CGAL's Subdivision_method_3
// (Loop_subdivision, CatmullClark_subdivision) on a CGAL::Surface_mesh over
// CGAL::Simple_cartesian<double>. See geom_validate.h for the contract.

#include "geom_validate.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

typedef CGAL::Simple_cartesian<double> K;
typedef K::Point_3 Point_3;
typedef CGAL::Surface_mesh<Point_3> Mesh;
typedef Mesh::Vertex_index Vertex;
typedef Mesh::Face_index Face;

void clear(gv_subdiv_result *out)
{
    std::free(out->xyz);
    std::free(out->face_sizes);
    std::free(out->indices);
    std::memset(out, 0, sizeof *out);
}

// Fill *out from the refined mesh; returns GV_OK or GV_ERR_INTERNAL (out of
// memory, an index that does not fit 32 bits). May throw.
int extract(const Mesh &mesh, gv_subdiv_result *out)
{
    const size_t nv = mesh.number_of_vertices();
    const size_t nf = mesh.number_of_faces();
    if (nv > (size_t)UINT32_MAX)
        return GV_ERR_INTERNAL;
    // Vertex numbers in iteration order (the mesh has no removed elements
    // after subdivision, but do not rely on it).
    std::vector<uint32_t> number(mesh.num_vertices(), UINT32_MAX);
    size_t ni = 0;
    for (Face f : mesh.faces())
        ni += mesh.degree(f);
    out->xyz = static_cast<double *>(std::malloc((nv ? nv : 1) * 3 * sizeof(double)));
    out->face_sizes = static_cast<uint32_t *>(std::malloc((nf ? nf : 1) * sizeof(uint32_t)));
    out->indices = static_cast<uint32_t *>(std::malloc((ni ? ni : 1) * sizeof(uint32_t)));
    if (!out->xyz || !out->face_sizes || !out->indices)
        return GV_ERR_INTERNAL;
    size_t at = 0;
    for (Vertex v : mesh.vertices()) {
        const Point_3 &p = mesh.point(v);
        out->xyz[3 * at + 0] = p.x();
        out->xyz[3 * at + 1] = p.y();
        out->xyz[3 * at + 2] = p.z();
        number[(size_t)v] = (uint32_t)at;
        ++at;
    }
    size_t fi = 0, ii = 0;
    for (Face f : mesh.faces()) {
        uint32_t k = 0;
        for (Vertex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
            out->indices[ii++] = number[(size_t)v];
            ++k;
        }
        out->face_sizes[fi++] = k;
    }
    out->nverts = nv;
    out->nfaces = nf;
    out->nindices = ni;
    return GV_OK;
}

int run(int scheme, int levels, size_t nverts, const double *xyz, size_t nfaces,
        const uint32_t *face_sizes, const uint32_t *indices, gv_subdiv_result *out)
{
    if (scheme != GV_SUBDIV_LOOP && scheme != GV_SUBDIV_CATMULL_CLARK)
        return GV_ERR_INVALID;
    if (levels < 0 || levels > GV_SUBDIV_MAX_LEVELS || nverts == 0 || nfaces == 0 || xyz == nullptr || face_sizes == nullptr ||
        indices == nullptr || nverts > (size_t)UINT32_MAX)
        return GV_ERR_INVALID;
    Mesh mesh;
    std::vector<Vertex> vs;
    vs.reserve(nverts);
    for (size_t i = 0; i < nverts; ++i) {
        const double *p = xyz + 3 * i;
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            return GV_ERR_INVALID;
        vs.push_back(mesh.add_vertex(Point_3(p[0], p[1], p[2])));
    }
    size_t at = 0;
    std::vector<Vertex> poly;
    for (size_t f = 0; f < nfaces; ++f) {
        const size_t k = face_sizes[f];
        if (k < 3 || (scheme == GV_SUBDIV_LOOP && k != 3))
            return GV_ERR_INVALID;
        poly.clear();
        for (size_t j = 0; j < k; ++j) {
            const uint32_t v = indices[at + j];
            if (v >= nverts)
                return GV_ERR_INVALID;
            poly.push_back(vs[v]);
        }
        at += k;
        // Surface_mesh refuses faces that would make the mesh non-manifold
        // or non-orientable (and faces repeating a vertex).
        if (mesh.add_face(poly) == Mesh::null_face())
            return GV_ERR_INVALID;
    }
    const auto np = CGAL::parameters::number_of_iterations(static_cast<unsigned int>(levels));
    if (levels > 0) {
        if (scheme == GV_SUBDIV_LOOP)
            CGAL::Subdivision_method_3::Loop_subdivision(mesh, np);
        else
            CGAL::Subdivision_method_3::CatmullClark_subdivision(mesh, np);
    }
    return extract(mesh, out);
}

} // namespace

extern "C" int gv_subdiv_cgal(int scheme, int levels, size_t nverts, const double *xyz,
                              size_t nfaces, const uint32_t *face_sizes, const uint32_t *indices,
                              gv_subdiv_result *out)
{
    if (out == nullptr)
        return GV_ERR_INVALID;
    std::memset(out, 0, sizeof *out);
    int rc;
    try {
        rc = run(scheme, levels, nverts, xyz, nfaces, face_sizes, indices, out);
    } catch (...) {
        rc = GV_ERR_INTERNAL;
    }
    if (rc != GV_OK)
        clear(out);
    return rc;
}

extern "C" void gv_subdiv_result_free(gv_subdiv_result *r)
{
    if (r != nullptr)
        clear(r);
}
