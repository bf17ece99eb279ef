/* The shape walk (ray_walk.h): a ray scene's nodes as named fields for the
 * scene module, and the corner attributes (UVs, normals) kept with the
 * stored triangles of a mesh so that a textured mesh keeps its mapping. */
#include "ray/ray_internal.h"
#include "ray/ray_walk.h"

/* The channel `name` with ncomp components: CORNER first, VERTEX if allowed. */
static uint32_t find_channel(const geom_mesh *gm, const char *name, size_t ncomp, int vertex_ok,
                             int *corner)
{
    uint32_t c = geom_mesh_channel_find(gm, name, GEOM_MESH_DOMAIN_CORNER);
    *corner = 1;
    if (c != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(gm, c) == ncomp) return c;
    *corner = 0;
    if (!vertex_ok) return GEOM_INVALID_INDEX;
    c = geom_mesh_channel_find(gm, name, GEOM_MESH_DOMAIN_VERTEX);
    if (c != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(gm, c) == ncomp) return c;
    return GEOM_INVALID_INDEX;
}

/* Value of channel c at halfedge h's corner (the vertex h leaves). */
static const double *corner_value(const geom_mesh *gm, uint32_t c, int corner, uint32_t h, size_t ncomp)
{
    const double *d = geom_mesh_channel_cdata(gm, c);
    uint32_t idx;
    if (corner) {
        /* corner values are indexed by the halfedge pointing to the corner vertex */
        const uint32_t *ci = geom_mesh_corner_cindices(gm, c);
        idx = ci ? ci[geom_mesh_he_prev(gm, h)] : GEOM_INVALID_INDEX;
    } else {
        idx = geom_mesh_he_from(gm, h);
    }
    if (idx == GEOM_INVALID_INDEX) return NULL;
    return d + ncomp * (size_t)idx;
}

geom_status geom__ray_tmesh_corner_attrs(geom__tmesh *m, const geom_mesh *gm, const geom_allocator *alloc)
{
    int uv_corner, n_corner;
    uint32_t cu = find_channel(gm, "uv", 2, 1, &uv_corner);
    uint32_t cn = find_channel(gm, "normal", 3, 0, &n_corner);
    size_t nf = geom_mesh_n_faces(gm), f, k = 0;
    if (cu == GEOM_INVALID_INDEX && cn == GEOM_INVALID_INDEX) return GEOM_OK;
    if (cu != GEOM_INVALID_INDEX && !(m->cuv = geom__alloc(alloc, (m->nt ? m->nt : 1) * 6 * sizeof(double))))
        return GEOM_ERR_NOMEM;
    if (cn != GEOM_INVALID_INDEX && !(m->cnrm = geom__alloc(alloc, (m->nt ? m->nt : 1) * 9 * sizeof(double))))
        return GEOM_ERR_NOMEM;
    /* the same walk as tmesh_from_mesh: fans (v0, prev, cur) from each face's first halfedge */
    for (f = 0; f < nf && k < m->nt; f++) {
        uint32_t h0, hp, h;
        if (geom_mesh_face_is_deleted(gm, (uint32_t)f)) continue;
        if (geom_mesh_face_valence(gm, (uint32_t)f) < 3) continue;
        h0 = geom_mesh_face_he(gm, (uint32_t)f);
        hp = geom_mesh_he_next(gm, h0);
        h = geom_mesh_he_next(gm, hp);
        while (hp != h0 && h != h0 && k < m->nt) {
            uint32_t hs[3];
            int j;
            hs[0] = h0;
            hs[1] = hp;
            hs[2] = h;
            for (j = 0; j < 3; j++) {
                if (m->cuv) {
                    const double *v = corner_value(gm, cu, uv_corner, hs[j], 2);
                    m->cuv[6 * k + 2 * j] = v ? v[0] : 0;
                    m->cuv[6 * k + 2 * j + 1] = v ? v[1] : 0;
                }
                if (m->cnrm) {
                    const double *v = corner_value(gm, cn, n_corner, hs[j], 3);
                    int c;
                    for (c = 0; c < 3; c++) m->cnrm[9 * k + 3 * j + c] = v ? v[c] : 0;
                }
            }
            k++;
            hp = h;
            h = geom_mesh_he_next(gm, h);
        }
    }
    return GEOM_OK;
}

void geom__ray_tmesh_corner_attrs_free(geom__tmesh *m, const geom_allocator *alloc)
{
    if (!m) return;
    if (m->cuv) geom__free(alloc, m->cuv, (m->nt ? m->nt : 1) * 6 * sizeof(double));
    if (m->cnrm) geom__free(alloc, m->cnrm, (m->nt ? m->nt : 1) * 9 * sizeof(double));
    m->cuv = m->cnrm = NULL;
}

geom_status geom__ray_scene_node_info(const geom_ray_scene *s, uint32_t id, geom__ray_node_info *o)
{
    const geom__ray_node *nd;
    if (!s || !o || id >= s->n) return GEOM_ERR_INVALID_ARG;
    nd = &s->nodes[id];
    memset(o, 0, sizeof *o);
    o->kind = nd->kind;
    o->name = nd->name;
    o->xf = nd->has_xf ? nd->m : NULL;
    switch (nd->kind) {
    case GEOM_RAY_SPHERE:
        memcpy(o->center, nd->prm, 3 * sizeof(double));
        o->radius = nd->prm[3];
        break;
    case GEOM_RAY_BOX:
        memcpy(o->min, nd->prm, 3 * sizeof(double));
        memcpy(o->max, nd->prm + 3, 3 * sizeof(double));
        break;
    case GEOM_RAY_OBOX:
        memcpy(o->center, nd->prm, 3 * sizeof(double));
        memcpy(o->axes, nd->prm + 3, 9 * sizeof(double));
        memcpy(o->half, nd->prm + 12, 3 * sizeof(double));
        break;
    case GEOM_RAY_PLANE:
    case GEOM_RAY_DISK:
        memcpy(o->center, nd->prm, 3 * sizeof(double));
        memcpy(o->normal, nd->prm + 3, 3 * sizeof(double));
        if (nd->kind == GEOM_RAY_DISK) o->radius = nd->prm[6];
        break;
    case GEOM_RAY_QUADRIC:
        memcpy(o->q, nd->prm, 10 * sizeof(double));
        if (nd->prm[16] != 0) {
            o->has_clip = 1;
            memcpy(o->clip, nd->prm + 10, 6 * sizeof(double));
        }
        o->capped = nd->capped;
        break;
    case GEOM_RAY_TORUS:
        o->major = nd->prm[0];
        o->minor = nd->prm[1];
        break;
    case GEOM_RAY_TRIANGLE:
        o->verts = nd->prm;
        o->nverts = 3;
        break;
    case GEOM_RAY_POLYGON:
        o->verts = nd->verts;
        o->nverts = nd->nverts;
        break;
    case GEOM_RAY_MESH:
    case GEOM_RAY_SUBDIV:
        if (nd->mesh) {
            o->pos = nd->mesh->pos;
            o->nrm = nd->mesh->nrm;
            o->nv = nd->mesh->nv;
            o->tri = nd->mesh->tri;
            o->face = nd->mesh->face;
            o->nt = nd->mesh->nt;
            o->cuv = nd->mesh->cuv;
            o->cnrm = nd->mesh->cnrm;
        }
        o->control = nd->control;
        o->scheme = nd->scheme;
        o->levels = nd->levels;
        break;
    case GEOM_RAY_SURFACE:
        o->surface = nd->surf ? &nd->surf->s : NULL;
        break;
    case GEOM_RAY_IMPLICIT:
        o->expr = nd->expr;
        memcpy(o->bounds, nd->prm, 6 * sizeof(double));
        break;
    case GEOM_RAY_VOLUME:
        o->volume = nd->vol;
        o->iso = nd->prm[0];
        o->inside = nd->prm[1] != 0;
        break;
    case GEOM_RAY_CSG:
    case GEOM_RAY_INSTANCE:
        o->op = nd->op;
        o->a = nd->a;
        o->b = nd->b;
        break;
    case GEOM_RAY_GROUP:
        o->members = nd->members;
        o->nmembers = nd->nmembers;
        break;
    }
    return GEOM_OK;
}

size_t geom__ray_scene_top(const geom_ray_scene *s, uint32_t *ids, size_t cap)
{
    size_t n = 0, i;
    if (!s) return 0;
    if (s->roots_explicit) {
        for (i = 0; i < s->nroots; i++)
            if (n < cap && ids) ids[n++] = s->roots[i];
            else n++;
        return n;
    }
    for (i = 0; i < s->n; i++) {
        if (s->nodes[i].is_child) continue;
        if (n < cap && ids) ids[n] = (uint32_t)i;
        n++;
    }
    return n;
}
