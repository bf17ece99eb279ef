/* Freeing an extracted surface and turning it into a half-edge mesh. */
#include "iso/iso_internal.h"

#include <string.h>

void geom_iso_surface_free(geom_iso_surface *s)
{
    if (!s)
        return;
    const geom_allocator *a = s->alloc.alloc_fn ? &s->alloc : NULL;
    size_t nv = s->n_vertices ? s->n_vertices : 1;
    size_t nt = s->n_triangles ? s->n_triangles : 1;
    geom__free(a, s->xyz, nv * 3 * sizeof(double));
    geom__free(a, s->normals, nv * 3 * sizeof(double));
    geom__free(a, s->tris, nt * 3 * sizeof(uint32_t));
    memset(s, 0, sizeof *s);
}

geom_status geom_iso_surface_to_mesh(const geom_iso_surface *s, geom_mesh *m, geom_diag *diag)
{
    if (!s || !m || (s->n_vertices && !s->xyz) || (s->n_triangles && !s->tris))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_surface_to_mesh: NULL argument");
    const geom_allocator *a = s->alloc.alloc_fn ? &s->alloc : NULL;
    size_t nt = s->n_triangles;
    uint32_t *sizes = geom__alloc(a, (nt ? nt : 1) * sizeof(uint32_t));
    if (!sizes)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_iso_surface_to_mesh: out of memory");
    for (size_t t = 0; t < nt; t++)
        sizes[t] = 3;
    geom_mesh_build_channel nch;
    memset(&nch, 0, sizeof nch);
    nch.name = "normal";
    nch.domain = GEOM_MESH_DOMAIN_VERTEX;
    nch.ncomp = 3;
    nch.values = s->normals;
    geom_mesh_build_options bo;
    memset(&bo, 0, sizeof bo);
    bo.keep_orientation = 1;
    bo.channels = &nch;
    bo.n_channels = s->normals ? 1 : 0;
    geom_mesh_build_report rep;
    geom_status st = geom_mesh_build(m, s->n_vertices, s->xyz, nt, sizes, s->tris, &bo, &rep, diag);
    geom__free(a, sizes, (nt ? nt : 1) * sizeof(uint32_t));
    if (st != GEOM_OK)
        return st;
    if (rep.invalid_faces || rep.flipped_faces || rep.nonmanifold_edges || rep.detached_faces ||
        rep.split_vertices || rep.added_vertices || rep.nonorientable_components)
        return geom__diag_set(diag, GEOM_ERR_NONMANIFOLD, "", 0, 0,
                             "geom_iso_surface_to_mesh: the mesh builder had to repair the surface");
    return GEOM_OK;
}
