// Closest points on a triangle mesh from CGAL's AABB_tree (see
// geom_validate_spatial.h).
#include "geom_validate_spatial.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <vector>

namespace {
typedef CGAL::Simple_cartesian<double> K;
typedef K::Triangle_3 Tri;
typedef std::vector<Tri>::const_iterator It;
typedef CGAL::AABB_triangle_primitive<K, It> Prim;
typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>> Tree;
} // namespace

extern "C" int gv_spatial_closest(const double *positions, size_t nv, const uint32_t *tris,
                                  size_t nt, const double *queries, size_t nq, double *point,
                                  uint32_t *tri, double *d2)
{
    if (nt == 0 || !positions || !tris || (nq && !queries))
        return GV_SPATIAL_ERR;
    try {
        std::vector<Tri> t;
        t.reserve(nt);
        for (size_t i = 0; i < nt; i++) {
            K::Point_3 p[3];
            for (int k = 0; k < 3; k++) {
                uint32_t v = tris[3 * i + k];
                if (v >= nv)
                    return GV_SPATIAL_ERR;
                p[k] = K::Point_3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
            }
            t.emplace_back(p[0], p[1], p[2]);
        }
        Tree tree(t.cbegin(), t.cend());
        tree.build();
        tree.accelerate_distance_queries();
        for (size_t i = 0; i < nq; i++) {
            K::Point_3 q(queries[3 * i], queries[3 * i + 1], queries[3 * i + 2]);
            Tree::Point_and_primitive_id pp = tree.closest_point_and_primitive(q);
            if (point) {
                point[3 * i] = pp.first.x();
                point[3 * i + 1] = pp.first.y();
                point[3 * i + 2] = pp.first.z();
            }
            if (tri)
                tri[i] = (uint32_t)(pp.second - t.cbegin());
            if (d2)
                d2[i] = CGAL::squared_distance(q, pp.first);
        }
    } catch (...) {
        return GV_SPATIAL_ERR;
    }
    return GV_SPATIAL_OK;
}
