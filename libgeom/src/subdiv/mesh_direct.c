/*
 * The half-edge mesh of a refined level, made directly from the level's own
 * face-vertex and face-edge relations (geom__mesh_build_cycles): no polygon
 * soup and no rebuild by geom_mesh_build, whose fast path would only find
 * again, by sorting corners by vertex, the edges the refinement already
 * numbered. The result is element for element the mesh geom_mesh_build
 * makes from the level's faces, so outputs do not change. It applies to
 * levels that are oriented manifolds whose vertex pairs name one edge each:
 * sd_mesh_direct_applies says which from the base level's tags; the build
 * itself re-checks every edge and declines otherwise, and the caller then
 * builds from the soup. test_subdiv compares it with geom_mesh_build
 * element for element.
 */
#include "subdiv_internal.h"

#include "mesh/build_internal.h"

int sd_mesh_direct_applies(const geom_subdiv_refiner *r, int level)
{
    int s = r->o.scheme;
    if (level < 1 || (s != GEOM_SUBDIV_CATMULL_CLARK && s != GEOM_SUBDIV_BILINEAR &&
                      s != GEOM_SUBDIV_LOOP))
        return 0;
    const sd_level *l0 = r->lv[0];
    for (uint32_t e = 0; e < l0->ne; e++)
        if (l0->etag[e] & SD_E_NONMANIFOLD)
            return 0;
    for (uint32_t v = 0; v < l0->nv; v++) {
        if (l0->vtag[v] & SD_V_NONMANIFOLD)
            return 0;
        /* Loop: two triangles sharing two edges (an interior vertex of
         * valence 2) give their children two edges between the same two
         * vertices, which geom_mesh_build repairs */
        if (s == GEOM_SUBDIV_LOOP && l0->ve_off[v + 1] - l0->ve_off[v] == 2 &&
            l0->vf_off[v + 1] - l0->vf_off[v] == 2)
            return 0;
    }
    return 1;
}

geom_status sd_mesh_direct(const sd_level *l, const double *positions,
                           const geom_mesh_build_channel *chans, size_t nchans, geom_mesh *m)
{
    geom__mesh_cycles c;
    c.nv = l->nv;
    c.xyz = positions;
    c.nf = l->nf;
    c.fv_off = l->fv_off;
    c.fv = l->fv;
    c.fe = l->fe;
    c.ne = l->ne;
    c.max_face_size = l->max_face_size;
    geom_status st = geom__mesh_build_cycles(m, &c, chans, nchans);
    return st == GEOM_MESH__CYCLES_DECLINED ? SD_DIRECT_DECLINED : st;
}
