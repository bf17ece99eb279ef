// Polygon-soup and mesh reference checks for libgeom's tests: CGAL's
// Polygon_mesh_processing on a CGAL::Surface_mesh over
// Exact_predicates_inexact_constructions_kernel. See geom_validate.h for the
// contracts, and for how soup vertices map to mesh vertices.

#include "geom_validate.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <cmath>
#include <cstring>
#include <iterator>
#include <vector>

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point_3;
typedef K::Vector_3 Vector_3;
typedef CGAL::Surface_mesh<Point_3> Mesh;
typedef Mesh::Vertex_index Vertex;
typedef Mesh::Face_index Face;
typedef Mesh::Halfedge_index Halfedge;
typedef Mesh::Edge_index Edge;

// Records what orient_polygon_soup changed. The named parameter is copied,
// so the visitor only points at the counters.
struct Orient_visitor : public PMP::Default_orientation_visitor {
    size_t *reversed;
    size_t *duplicated;
    Orient_visitor(size_t *r, size_t *d) : reversed(r), duplicated(d) {}
    void polygon_orientation_reversed(std::size_t) { ++*reversed; }
    void duplicated_vertex(std::size_t, std::size_t) { ++*duplicated; }
};

struct Built {
    Mesh mesh;
    int is_soup_mesh = 0;
    int reoriented = 0;
    size_t reversed = 0;
    size_t duplicated = 0;
};

// Validate the C soup and turn it into a Surface_mesh in which vertex i is
// soup vertex i (i < nverts). Returns GV_OK or GV_ERR_INVALID; may throw.
int build(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
          const uint32_t *indices, Built &out)
{
    if ((nverts > 0 && xyz == nullptr) || (nfaces > 0 && (face_sizes == nullptr || indices == nullptr)))
        return GV_ERR_INVALID;
    if (nverts > (size_t)UINT32_MAX)
        return GV_ERR_INVALID;
    std::vector<Point_3> points;
    points.reserve(nverts);
    for (size_t i = 0; i < nverts; ++i) {
        const double *p = xyz + 3 * i;
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            return GV_ERR_INVALID;
        points.push_back(Point_3(p[0], p[1], p[2]));
    }
    std::vector<std::vector<std::size_t> > polygons(nfaces);
    size_t at = 0;
    for (size_t f = 0; f < nfaces; ++f) {
        const size_t k = face_sizes[f];
        if (k < 3)
            return GV_ERR_INVALID;
        std::vector<std::size_t> &poly = polygons[f];
        poly.reserve(k);
        for (size_t j = 0; j < k; ++j) {
            const uint32_t v = indices[at + j];
            if (v >= nverts)
                return GV_ERR_INVALID;
            for (std::size_t u : poly)
                if (u == v)
                    return GV_ERR_INVALID;
            poly.push_back(v);
        }
        at += k;
    }

    out.is_soup_mesh = PMP::is_polygon_soup_a_polygon_mesh(polygons) ? 1 : 0;
    if (!out.is_soup_mesh) {
        out.reoriented = 1;
        PMP::orient_polygon_soup(points, polygons,
                                 CGAL::parameters::visitor(Orient_visitor(&out.reversed, &out.duplicated)));
    }
    PMP::polygon_soup_to_polygon_mesh(points, polygons, out.mesh);
    return GV_OK;
}

// The face next to halfedge h, or its opposite's when h is a border halfedge.
Face face_of_edge(const Mesh &m, Halfedge h)
{
    Face f = m.face(h);
    return f != Mesh::null_face() ? f : m.face(m.opposite(h));
}

int soup_check(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
               const uint32_t *indices, gv_soup_info *out)
{
    Built b;
    const int st = build(nverts, xyz, nfaces, face_sizes, indices, b);
    if (st != GV_OK)
        return st;
    Mesh &m = b.mesh;
    gv_soup_info info;
    std::memset(&info, 0, sizeof info);
    info.is_polygon_soup_a_polygon_mesh = b.is_soup_mesh;
    info.reoriented = b.reoriented;
    info.reversed_faces = b.reversed;
    info.duplicated_vertices = b.duplicated;
    info.valid = CGAL::is_valid_polygon_mesh(m) ? 1 : 0;
    info.closed = CGAL::is_closed(m) ? 1 : 0;
    info.vertices = m.number_of_vertices();
    info.edges = m.number_of_edges();
    info.faces = m.number_of_faces();
    info.euler_characteristic = (long long)info.vertices - (long long)info.edges + (long long)info.faces;

    // Face-connected components, and V, E, F, boundary loops of each.
    Mesh::Property_map<Face, std::size_t> comp =
        m.add_property_map<Face, std::size_t>("f:gv_component", 0).first;
    const std::size_t ncomp = PMP::connected_components(m, comp);
    info.components = ncomp;
    std::vector<long long> chi(ncomp, 0), loops(ncomp, 0);
    for (Vertex v : m.vertices()) {
        if (m.is_isolated(v)) {
            ++info.isolated_vertices;
            continue;
        }
        chi[comp[face_of_edge(m, m.halfedge(v))]] += 1;
    }
    for (Edge e : m.edges())
        chi[comp[face_of_edge(m, m.halfedge(e))]] -= 1;
    for (Face f : m.faces())
        chi[comp[f]] += 1;
    std::vector<Halfedge> cycles;
    PMP::extract_boundary_cycles(m, std::back_inserter(cycles));
    info.border_cycles = cycles.size();
    for (Halfedge h : cycles)
        loops[comp[m.face(m.opposite(h))]] += 1;
    long long genus = 0;
    for (std::size_t c = 0; c < ncomp; ++c)
        genus += (2 - chi[c] - loops[c]) / 2;
    info.genus = genus;

    // Self-intersection, on triangles.
    bool all_triangles = true;
    for (Face f : m.faces())
        if (m.degree(f) != 3)
            all_triangles = false;
    if (all_triangles) {
        info.self_intersecting = PMP::does_self_intersect(m) ? 1 : 0;
    } else {
        Mesh tri = m;
        if (PMP::triangulate_faces(tri))
            info.self_intersecting = PMP::does_self_intersect(tri) ? 1 : 0;
        else
            info.self_intersecting = -1;
    }
    *out = info;
    return GV_OK;
}

int vertex_normals(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
                   const uint32_t *indices, int weighting, double *normals, size_t *ncopies)
{
    Built b;
    const int st = build(nverts, xyz, nfaces, face_sizes, indices, b);
    if (st != GV_OK)
        return st;
    const Mesh &m = b.mesh;
    Mesh::Property_map<Vertex, Vector_3> vn =
        b.mesh.add_property_map<Vertex, Vector_3>("v:gv_normal", CGAL::NULL_VECTOR).first;
    if (weighting == GV_NORMALS_CGAL) {
        PMP::compute_vertex_normals(m, vn);
    } else {
        // The two fallbacks of compute_vertex_normal(), alone.
        Mesh::Property_map<Face, Vector_3> fn =
            b.mesh.add_property_map<Face, Vector_3>("f:gv_normal", CGAL::NULL_VECTOR).first;
        PMP::compute_face_normals(m, fn);
        const K traits;
        const PMP::internal::Vertex_normal_type type =
            weighting == GV_NORMALS_SINE ? PMP::internal::SIN_WEIGHT : PMP::internal::NO_WEIGHT;
        for (Vertex v : m.vertices()) {
            Vector_3 n = PMP::internal::compute_vertex_normal_as_sum_of_weighted_normals(
                v, type, fn, m.points(), m, traits);
            if (n != CGAL::NULL_VECTOR)
                PMP::internal::normalize(n, traits);
            vn[v] = n;
        }
    }
    for (size_t i = 0; i < nverts; ++i) {
        const Vector_3 &n = vn[Vertex((Mesh::size_type)i)];
        normals[3 * i + 0] = n.x();
        normals[3 * i + 1] = n.y();
        normals[3 * i + 2] = n.z();
    }
    if (ncopies != nullptr)
        *ncopies = b.duplicated;
    return GV_OK;
}

} // namespace

extern "C" int gv_soup_check(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
                             const uint32_t *indices, gv_soup_info *out)
{
    if (out == nullptr)
        return GV_ERR_INVALID;
    std::memset(out, 0, sizeof *out);
    try {
        return soup_check(nverts, xyz, nfaces, face_sizes, indices, out);
    } catch (...) {
        std::memset(out, 0, sizeof *out);
        return GV_ERR_INTERNAL;
    }
}

extern "C" int gv_vertex_normals(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
                                 const uint32_t *indices, int weighting, double *normals, size_t *ncopies)
{
    if (ncopies != nullptr)
        *ncopies = 0;
    if (normals == nullptr && nverts > 0)
        return GV_ERR_INVALID;
    for (size_t i = 0; i < 3 * nverts; ++i)
        normals[i] = 0.0;
    if (weighting != GV_NORMALS_CGAL && weighting != GV_NORMALS_SINE && weighting != GV_NORMALS_UNWEIGHTED)
        return GV_ERR_INVALID;
    try {
        const int st = vertex_normals(nverts, xyz, nfaces, face_sizes, indices, weighting, normals, ncopies);
        if (st != GV_OK)
            for (size_t i = 0; i < 3 * nverts; ++i)
                normals[i] = 0.0;
        return st;
    } catch (...) {
        for (size_t i = 0; i < 3 * nverts; ++i)
            normals[i] = 0.0;
        if (ncopies != nullptr)
            *ncopies = 0;
        return GV_ERR_INTERNAL;
    }
}
