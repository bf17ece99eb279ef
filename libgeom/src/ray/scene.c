/* Scenes: nodes of every representation with transforms, instances and CSG;
 * build; closest / any / all queries. */
#include "ray/ray_internal.h"
#include "geom/spatial.h"
#include "geom/subdiv.h"

#include <stdlib.h>

geom_ray_scene *geom_ray_scene_create(const geom_allocator *alloc)
{
    geom_ray_scene *s = geom__alloc(alloc, sizeof *s);
    if (!s) return NULL;
    memset(s, 0, sizeof *s);
    if (alloc) {
        s->alloc_store = *alloc;
        s->alloc = &s->alloc_store;
    }
    return s;
}

static void node_free(geom_ray_scene *s, geom__ray_node *nd)
{
    if (nd->verts) geom__free(s->alloc, nd->verts, 3 * nd->nverts * sizeof(double));
    if (nd->mesh) geom__ray_tmesh_corner_attrs_free(nd->mesh, s->alloc);
    if (nd->mesh) geom__ray_mesh_free(nd->mesh, s->alloc);
    geom_mesh_destroy(nd->control);
    if (nd->surf) geom__ray_surface_free(nd->surf, s->alloc);
    if (nd->members) geom__free(s->alloc, nd->members, nd->nmembers * sizeof *nd->members);
}

static void top_free(geom_ray_scene *s)
{
    geom_bvh_destroy(s->top);
    if (s->top_obj) geom__free(s->alloc, s->top_obj, (s->ntop ? s->ntop : 1) * sizeof *s->top_obj);
    if (s->unbounded) geom__free(s->alloc, s->unbounded, (s->nroots ? s->nroots : 1) * sizeof *s->unbounded);
    s->top = NULL;
    s->top_obj = NULL;
    s->unbounded = NULL;
    s->ntop = s->nunbounded = 0;
}

void geom_ray_scene_destroy(geom_ray_scene *s)
{
    size_t i;
    if (!s) return;
    for (i = 0; i < s->n; i++) node_free(s, &s->nodes[i]);
    if (s->nodes) geom__free(s->alloc, s->nodes, s->cap * sizeof *s->nodes);
    if (s->roots) geom__free(s->alloc, s->roots, s->roots_cap * sizeof *s->roots);
    top_free(s);
    {
        const geom_allocator *a = s->alloc ? &s->alloc_store : NULL;
        geom_allocator copy;
        if (a) {
            copy = *a;
            geom__free(&copy, s, sizeof *s);
        } else {
            geom__free(NULL, s, sizeof *s);
        }
    }
}

static geom__ray_node *node_new(geom_ray_scene *s, geom_ray_kind kind, uint32_t *id)
{
    geom__ray_node *nd;
    if (!s) return NULL;
    if (s->n >= 0x7fffffffu) return NULL;
    if (geom__grow(s->alloc, (void **)&s->nodes, &s->cap, s->n + 1, sizeof *s->nodes) != GEOM_OK) return NULL;
    nd = &s->nodes[s->n];
    memset(nd, 0, sizeof *nd);
    nd->kind = kind;
    if (id) *id = (uint32_t)s->n;
    s->n++;
    s->built = 0;
    return nd;
}

static int finite_n(const double *p, size_t n)
{
    size_t i;
    if (!p) return 0;
    for (i = 0; i < n; i++)
        if (!isfinite(p[i])) return 0;
    return 1;
}

static geom_status unit_normal(const double *n, double out[3])
{
    geom_vec3 u;
    geom_status st;
    if (!finite_n(n, 3)) return GEOM_ERR_INVALID_ARG;
    st = geom_vec3_normalize(geom__v3(n), &u);
    if (st != GEOM_OK) return st;
    out[0] = u.x; out[1] = u.y; out[2] = u.z;
    return GEOM_OK;
}

/* The (u, v) frame of a plane or disk, made once here rather than at every
 * hit: prm[9..11] and prm[12..14] (plane.c). */
static void plane_frame(geom__ray_node *nd)
{
    geom_vec3 t1, t2;
    geom__frame(geom__v3(nd->prm + 3), &t1, &t2);
    nd->prm[9] = t1.x; nd->prm[10] = t1.y; nd->prm[11] = t1.z;
    nd->prm[12] = t2.x; nd->prm[13] = t2.y; nd->prm[14] = t2.z;
}

geom_status geom_ray_scene_add_plane(geom_ray_scene *s, const double point[3], const double n[3],
                                     uint32_t *id)
{
    double un[3];
    geom_status st;
    geom__ray_node *nd;
    if (!s || !finite_n(point, 3)) return GEOM_ERR_INVALID_ARG;
    if ((st = unit_normal(n, un)) != GEOM_OK) return st;
    if (!(nd = node_new(s, GEOM_RAY_PLANE, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, point, 3 * sizeof(double));
    memcpy(nd->prm + 3, un, sizeof un);
    plane_frame(nd);
    return GEOM_OK;
}

geom_status geom_ray_scene_add_disk(geom_ray_scene *s, const double center[3], const double n[3],
                                    double radius, uint32_t *id)
{
    double un[3];
    geom_status st;
    geom__ray_node *nd;
    if (!s || !finite_n(center, 3) || !isfinite(radius)) return GEOM_ERR_INVALID_ARG;
    if (!(radius > 0)) return GEOM_ERR_DEGENERATE;
    if ((st = unit_normal(n, un)) != GEOM_OK) return st;
    if (!(nd = node_new(s, GEOM_RAY_DISK, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, center, 3 * sizeof(double));
    memcpy(nd->prm + 3, un, sizeof un);
    nd->prm[6] = radius;
    plane_frame(nd);
    return GEOM_OK;
}

geom_status geom_ray_scene_add_box(geom_ray_scene *s, const double min[3], const double max[3],
                                   uint32_t *id)
{
    geom__ray_node *nd;
    int k;
    if (!s || !finite_n(min, 3) || !finite_n(max, 3)) return GEOM_ERR_INVALID_ARG;
    for (k = 0; k < 3; k++)
        if (min[k] > max[k]) return GEOM_ERR_INVALID_ARG;
    if (!(nd = node_new(s, GEOM_RAY_BOX, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, min, 3 * sizeof(double));
    memcpy(nd->prm + 3, max, 3 * sizeof(double));
    return GEOM_OK;
}

geom_status geom_ray_scene_add_obox(geom_ray_scene *s, const double center[3], const double axes[9],
                                    const double half[3], uint32_t *id)
{
    geom__ray_node *nd;
    double ax[9];
    int k;
    if (!s || !finite_n(center, 3) || !finite_n(axes, 9) || !finite_n(half, 3)) return GEOM_ERR_INVALID_ARG;
    for (k = 0; k < 3; k++) {
        geom_status st = unit_normal(axes + 3 * k, ax + 3 * k);
        if (st != GEOM_OK) return st;
        if (half[k] < 0) return GEOM_ERR_INVALID_ARG;
    }
    for (k = 0; k < 3; k++) {
        const double *a = ax + 3 * k, *b = ax + 3 * ((k + 1) % 3);
        if (fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) > 1e-9) return GEOM_ERR_INVALID_ARG;
    }
    if (!(nd = node_new(s, GEOM_RAY_OBOX, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, center, 3 * sizeof(double));
    memcpy(nd->prm + 3, ax, sizeof ax);
    memcpy(nd->prm + 12, half, 3 * sizeof(double));
    return GEOM_OK;
}

geom_status geom_ray_scene_add_sphere(geom_ray_scene *s, const double center[3], double radius,
                                      uint32_t *id)
{
    geom__ray_node *nd;
    if (!s || !finite_n(center, 3) || !isfinite(radius)) return GEOM_ERR_INVALID_ARG;
    if (!(radius > 0)) return GEOM_ERR_DEGENERATE;
    if (!(nd = node_new(s, GEOM_RAY_SPHERE, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, center, 3 * sizeof(double));
    nd->prm[3] = radius;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_quadric(geom_ray_scene *s, const double q[10], const double clip[6],
                                       int capped, uint32_t *id)
{
    geom__ray_node *nd;
    int k, nz = 0;
    if (!s || !finite_n(q, 10)) return GEOM_ERR_INVALID_ARG;
    for (k = 0; k < 9; k++) nz |= q[k] != 0;
    if (!nz) return GEOM_ERR_DEGENERATE;
    if (clip) {
        if (!finite_n(clip, 6)) return GEOM_ERR_INVALID_ARG;
        for (k = 0; k < 3; k++)
            if (clip[k] > clip[k + 3]) return GEOM_ERR_INVALID_ARG;
    }
    if (!(nd = node_new(s, GEOM_RAY_QUADRIC, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, q, 10 * sizeof(double));
    if (clip) {
        memcpy(nd->prm + 10, clip, 6 * sizeof(double));
        nd->prm[16] = 1;
        nd->capped = capped != 0;
    }
    return GEOM_OK;
}

geom_status geom_ray_scene_add_torus(geom_ray_scene *s, double major, double minor, uint32_t *id)
{
    geom__ray_node *nd;
    if (!s || !isfinite(major) || !isfinite(minor)) return GEOM_ERR_INVALID_ARG;
    if (!(major > 0) || !(minor > 0)) return GEOM_ERR_DEGENERATE;
    if (!(nd = node_new(s, GEOM_RAY_TORUS, id))) return GEOM_ERR_NOMEM;
    nd->prm[0] = major;
    nd->prm[1] = minor;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_triangle(geom_ray_scene *s, const double v[9], uint32_t *id)
{
    geom__ray_node *nd;
    if (!s || !finite_n(v, 9)) return GEOM_ERR_INVALID_ARG;
    if (!(nd = node_new(s, GEOM_RAY_TRIANGLE, id))) return GEOM_ERR_NOMEM;
    memcpy(nd->prm, v, 9 * sizeof(double));
    return GEOM_OK;
}

geom_status geom_ray_scene_add_polygon(geom_ray_scene *s, const double *v, size_t n, uint32_t *id)
{
    geom__ray_node *nd;
    double nrm[3] = {0, 0, 0}, c[3] = {0, 0, 0}, un[3];
    size_t i, bytes;
    geom_status st;
    if (!s || n < 3 || !v) return GEOM_ERR_INVALID_ARG;
    if (geom__size_mul(3 * sizeof(double), n, &bytes) != GEOM_OK) return GEOM_ERR_LIMIT;
    if (!finite_n(v, 3 * n)) return GEOM_ERR_INVALID_ARG;
    for (i = 0; i < n; i++) {
        const double *p = v + 3 * i, *q = v + 3 * ((i + 1) % n);
        nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
        nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
        nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
        c[0] += p[0] / (double)n;
        c[1] += p[1] / (double)n;
        c[2] += p[2] / (double)n;
    }
    if ((st = unit_normal(nrm, un)) != GEOM_OK) return st;
    if (!(nd = node_new(s, GEOM_RAY_POLYGON, id))) return GEOM_ERR_NOMEM;
    nd->verts = geom__alloc(s->alloc, bytes);
    if (!nd->verts) {
        s->n--;
        return GEOM_ERR_NOMEM;
    }
    memcpy(nd->verts, v, bytes);
    nd->nverts = n;
    memcpy(nd->prm, un, sizeof un);
    memcpy(nd->prm + 3, c, sizeof c);
    return GEOM_OK;
}

static geom_status tmesh_new(geom_ray_scene *s, size_t nv, size_t nt, int normals, int faces,
                             geom__tmesh **out)
{
    geom__tmesh *m = geom__alloc(s->alloc, sizeof *m);
    size_t b1, b2;
    if (!m) return GEOM_ERR_NOMEM;
    memset(m, 0, sizeof *m);
    if (geom__size_mul(3 * sizeof(double), nv, &b1) != GEOM_OK ||
        geom__size_mul(3 * sizeof(uint32_t), nt, &b2) != GEOM_OK) {
        geom__free(s->alloc, m, sizeof *m);
        return GEOM_ERR_LIMIT;
    }
    m->nv = nv;
    m->nt = nt;
    m->pos = geom__alloc(s->alloc, b1 ? b1 : 1);
    m->tri = geom__alloc(s->alloc, b2 ? b2 : 1);
    if (normals) m->nrm = geom__alloc(s->alloc, b1 ? b1 : 1);
    if (faces) m->face = geom__alloc(s->alloc, nt ? nt * sizeof(uint32_t) : 1);
    if (!m->pos || !m->tri || (normals && !m->nrm) || (faces && !m->face)) {
        geom__ray_mesh_free(m, s->alloc);
        return GEOM_ERR_NOMEM;
    }
    *out = m;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_triangles(geom_ray_scene *s, const double *positions, size_t nv,
                                         const uint32_t *tris, size_t nt, const double *normals,
                                         uint32_t *id)
{
    geom__tmesh *m;
    geom__ray_node *nd;
    geom_status st;
    size_t i;
    if (!s || (nv && !positions) || (nt && !tris)) return GEOM_ERR_INVALID_ARG;
    if (!finite_n(positions, 3 * nv) && nv) return GEOM_ERR_INVALID_ARG;
    for (i = 0; i < 3 * nt; i++)
        if (tris[i] >= nv) return GEOM_ERR_INVALID_ARG;
    if ((st = tmesh_new(s, nv, nt, normals != NULL, 0, &m)) != GEOM_OK) return st;
    memcpy(m->pos, positions, 3 * nv * sizeof(double));
    memcpy(m->tri, tris, 3 * nt * sizeof(uint32_t));
    if (normals) memcpy(m->nrm, normals, 3 * nv * sizeof(double));
    if (!(nd = node_new(s, GEOM_RAY_MESH, id))) {
        geom__ray_mesh_free(m, s->alloc);
        return GEOM_ERR_NOMEM;
    }
    nd->mesh = m;
    return GEOM_OK;
}

/* Fan-triangulated copy of a half-edge mesh (faces reported as prim). */
static geom_status tmesh_from_mesh(geom_ray_scene *s, const geom_mesh *gm, geom__tmesh **out)
{
    size_t nv = geom_mesh_n_vertices(gm), nf = geom_mesh_n_faces(gm), nt = 0, f, k = 0;
    uint32_t ch = geom_mesh_channel_find(gm, "normal", GEOM_MESH_DOMAIN_VERTEX);
    int has_n = ch != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(gm, ch) == 3;
    geom__tmesh *m;
    geom_status st;
    const double *pos = geom_mesh_cpositions(gm);
    for (f = 0; f < nf; f++) {
        size_t val;
        if (geom_mesh_face_is_deleted(gm, (uint32_t)f)) continue;
        val = geom_mesh_face_valence(gm, (uint32_t)f);
        if (val >= 3) nt += val - 2;
    }
    if (nv && !finite_n(pos, 3 * nv)) return GEOM_ERR_INVALID_ARG;
    if ((st = tmesh_new(s, nv, nt, has_n, 1, &m)) != GEOM_OK) return st;
    if (nv) memcpy(m->pos, pos, 3 * nv * sizeof(double));
    if (has_n) memcpy(m->nrm, geom_mesh_channel_cdata(gm, ch), 3 * nv * sizeof(double));
    for (f = 0; f < nf; f++) {
        uint32_t h0, h, v0, prev;
        if (geom_mesh_face_is_deleted(gm, (uint32_t)f)) continue;
        if (geom_mesh_face_valence(gm, (uint32_t)f) < 3) continue;
        h0 = geom_mesh_face_he(gm, (uint32_t)f);
        v0 = geom_mesh_he_from(gm, h0);
        h = geom_mesh_he_next(gm, h0);
        prev = geom_mesh_he_from(gm, h);
        h = geom_mesh_he_next(gm, h);
        while (h != h0) {
            uint32_t cur = geom_mesh_he_from(gm, h);
            m->tri[3 * k] = v0;
            m->tri[3 * k + 1] = prev;
            m->tri[3 * k + 2] = cur;
            m->face[k] = (uint32_t)f;
            k++;
            prev = cur;
            h = geom_mesh_he_next(gm, h);
        }
    }
    m->nt = k;
    if ((st = geom__ray_tmesh_corner_attrs(m, gm, s->alloc)) != GEOM_OK) {
        geom__ray_tmesh_corner_attrs_free(m, s->alloc);
        geom__ray_mesh_free(m, s->alloc);
        return st;
    }
    *out = m;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_mesh(geom_ray_scene *s, const geom_mesh *gm, uint32_t *id)
{
    geom__tmesh *m;
    geom__ray_node *nd;
    geom_status st;
    if (!s || !gm) return GEOM_ERR_INVALID_ARG;
    if ((st = tmesh_from_mesh(s, gm, &m)) != GEOM_OK) return st;
    if (!(nd = node_new(s, GEOM_RAY_MESH, id))) {
        geom__ray_tmesh_corner_attrs_free(m, s->alloc);
        geom__ray_mesh_free(m, s->alloc);
        return GEOM_ERR_NOMEM;
    }
    nd->mesh = m;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_subdiv(geom_ray_scene *s, const geom_mesh *gm, int scheme, int levels,
                                      uint32_t *id, geom_diag *diag)
{
    geom_subdiv_options o;
    geom_subdiv_report rep;
    geom_mesh *lim = NULL;
    geom__tmesh *m;
    geom__ray_node *nd;
    geom_status st;
    if (!s || !gm) return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_ray_scene_add_subdiv: invalid argument");
    int asked_levels = levels;
    if (levels < 0 || levels > 8) return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_ray_scene_add_subdiv: invalid argument");
    if (levels == 0) levels = 5;
    memset(&o, 0, sizeof o);
    o.scheme = (geom_subdiv_scheme)scheme;
    o.alloc = s->alloc;
    st = geom_subdiv_mesh(gm, &o, levels, GEOM_SUBDIV_LIMIT | GEOM_SUBDIV_NORMALS, &lim, &rep, diag);
    if (st != GEOM_OK) return st;
    /* The refined level's distance to the limit (rep.level_*, measured
     * before the projection) estimates the traced surface's: both O(h^2). */
    st = tmesh_from_mesh(s, lim, &m);
    geom_mesh_destroy(lim);
    if (st != GEOM_OK) return st;
    {
        geom_mesh *ctrl = NULL;
        if (geom_mesh_clone(gm, &ctrl) != GEOM_OK || !(nd = node_new(s, GEOM_RAY_SUBDIV, id))) {
            geom_mesh_destroy(ctrl);
            geom__ray_tmesh_corner_attrs_free(m, s->alloc);
            geom__ray_mesh_free(m, s->alloc);
            return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_ray_scene_add_subdiv: out of memory");
        }
        nd->control = ctrl;
        nd->scheme = scheme;
        nd->levels = asked_levels;
    }
    nd->mesh = m;
    nd->err.max_error = rep.level_max_limit_distance;
    nd->err.mean_error = rep.level_rms_limit_distance;
    nd->err.method = GEOM_ERROR_ESTIMATE;
    nd->err.evaluations = rep.vertices;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_surface(geom_ray_scene *s, const geom_nurbs_surface *surf, uint32_t *id,
                                       geom_diag *diag)
{
    geom__tsurf *sf;
    geom__ray_node *nd;
    geom_status st;
    size_t nk_u, nk_v, np;
    if (!s || !surf) return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_ray_scene_add_surface: invalid argument");
    if ((st = geom_surface_validate(surf, diag)) != GEOM_OK) return st;
    sf = geom__alloc(s->alloc, sizeof *sf);
    if (!sf) return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_ray_scene_add_surface: out of memory");
    memset(sf, 0, sizeof *sf);
    nk_u = surf->nu + (size_t)surf->degree_u + 1;
    nk_v = surf->nv + (size_t)surf->degree_v + 1;
    np = surf->nu * surf->nv;
    sf->knots_u = geom__alloc(s->alloc, nk_u * sizeof(double));
    sf->knots_v = geom__alloc(s->alloc, nk_v * sizeof(double));
    sf->points = geom__alloc(s->alloc, 3 * np * sizeof(double));
    if (surf->weights) sf->weights = geom__alloc(s->alloc, np * sizeof(double));
    if (!sf->knots_u || !sf->knots_v || !sf->points || (surf->weights && !sf->weights)) {
        sf->s = *surf;
        geom__ray_surface_free(sf, s->alloc);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_ray_scene_add_surface: out of memory");
    }
    memcpy(sf->knots_u, surf->knots_u, nk_u * sizeof(double));
    memcpy(sf->knots_v, surf->knots_v, nk_v * sizeof(double));
    memcpy(sf->points, surf->points, 3 * np * sizeof(double));
    if (surf->weights) memcpy(sf->weights, surf->weights, np * sizeof(double));
    sf->s = *surf;
    sf->s.knots_u = sf->knots_u;
    sf->s.knots_v = sf->knots_v;
    sf->s.points = sf->points;
    sf->s.weights = sf->weights;
    if ((st = geom__ray_surface_build(sf, s->alloc, diag)) != GEOM_OK) {
        geom__ray_surface_free(sf, s->alloc);
        return st;
    }
    if (!(nd = node_new(s, GEOM_RAY_SURFACE, id))) {
        geom__ray_surface_free(sf, s->alloc);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_ray_scene_add_surface: out of memory");
    }
    nd->surf = sf;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_implicit(geom_ray_scene *s, const geom_implicit_expr *e,
                                        const double bounds[6], double lipschitz, uint32_t *id)
{
    geom__ray_node *nd;
    int k;
    if (!s || !e || !finite_n(bounds, 6) || isnan(lipschitz) || lipschitz < 0) return GEOM_ERR_INVALID_ARG;
    for (k = 0; k < 3; k++)
        if (!(bounds[k] < bounds[k + 3])) return GEOM_ERR_INVALID_ARG;
    if (!(nd = node_new(s, GEOM_RAY_IMPLICIT, id))) return GEOM_ERR_NOMEM;
    nd->expr = e;
    memcpy(nd->prm, bounds, 6 * sizeof(double));
    nd->prm[6] = isfinite(lipschitz) ? lipschitz : 0;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_volume(geom_ray_scene *s, const geom_implicit_volume *v, double iso,
                                      uint32_t *id)
{
    return geom_ray_scene_add_volume_opt(s, v, iso, NULL, id);
}

geom_status geom_ray_scene_add_volume_opt(geom_ray_scene *s, const geom_implicit_volume *v,
                                          double iso, const geom_ray_volume_options *opt,
                                          uint32_t *id)
{
    geom__ray_node *nd;
    int above = opt ? opt->inside : 0;
    if (!s || !v || !isfinite(iso) || (above != 0 && above != 1)) return GEOM_ERR_INVALID_ARG;
    if (!(nd = node_new(s, GEOM_RAY_VOLUME, id))) return GEOM_ERR_NOMEM;
    nd->vol = v;
    nd->prm[0] = iso;
    nd->prm[1] = above; /* 1: inside f > iso, normals against the gradient */
    return GEOM_OK;
}

geom_status geom_ray_scene_add_csg(geom_ray_scene *s, geom_ray_csg_op op, uint32_t a, uint32_t b,
                                   uint32_t *id)
{
    geom__ray_node *nd;
    if (!s || a >= s->n || b >= s->n || a == b) return GEOM_ERR_INVALID_ARG;
    if (op != GEOM_RAY_CSG_UNION && op != GEOM_RAY_CSG_INTERSECTION && op != GEOM_RAY_CSG_DIFFERENCE)
        return GEOM_ERR_INVALID_ARG;
    if (!(nd = node_new(s, GEOM_RAY_CSG, id))) return GEOM_ERR_NOMEM;
    nd->a = a;
    nd->b = b;
    nd->op = (int)op;
    s->nodes[a].is_child = 1;
    s->nodes[b].is_child = 1;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_group(geom_ray_scene *s, const uint32_t *ids, size_t n, uint32_t *id)
{
    geom__ray_node *nd;
    size_t i;
    uint32_t *copy;
    if (!s || !ids || n == 0 || n > 0x7fffffffu) return GEOM_ERR_INVALID_ARG;
    for (i = 0; i < n; i++)
        if (ids[i] >= s->n) return GEOM_ERR_INVALID_ARG;
    copy = geom__alloc(s->alloc, n * sizeof *copy);
    if (!copy) return GEOM_ERR_NOMEM;
    memcpy(copy, ids, n * sizeof *copy);
    if (!(nd = node_new(s, GEOM_RAY_GROUP, id))) {
        geom__free(s->alloc, copy, n * sizeof *copy);
        return GEOM_ERR_NOMEM;
    }
    nd->members = copy;
    nd->nmembers = n;
    for (i = 0; i < n; i++) s->nodes[ids[i]].is_child = 1;
    return GEOM_OK;
}

geom_status geom_ray_scene_add_instance(geom_ray_scene *s, uint32_t of, const double m[16], uint32_t *id)
{
    geom__ray_node *nd;
    uint32_t nid;
    geom_status st;
    if (!s || of >= s->n) return GEOM_ERR_INVALID_ARG;
    if (!(nd = node_new(s, GEOM_RAY_INSTANCE, &nid))) return GEOM_ERR_NOMEM;
    nd->a = of;
    if (m && (st = geom_ray_scene_set_transform(s, nid, m)) != GEOM_OK) {
        s->n--;
        return st;
    }
    if (id) *id = nid;
    return GEOM_OK;
}

geom_status geom_ray_scene_set_transform(geom_ray_scene *s, uint32_t id, const double m[16])
{
    geom__ray_node *nd;
    geom_mat4 M, Mi;
    geom_mat3 N;
    geom_status st;
    int r, c;
    if (!s || id >= s->n || !finite_n(m, 16)) return GEOM_ERR_INVALID_ARG;
    if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1) return GEOM_ERR_INVALID_ARG;
    memcpy(M.m, m, sizeof M.m);
    if ((st = geom_mat4_inverse(M, &Mi)) != GEOM_OK) return st;
    if ((st = geom_mat4_normal_matrix(M, &N)) != GEOM_OK) return st;
    nd = &s->nodes[id];
    nd->has_xf = 1;
    memcpy(nd->m, m, sizeof nd->m);
    memcpy(nd->minv, Mi.m, sizeof nd->minv);
    memcpy(nd->nm, N.m, sizeof nd->nm);
    nd->mnorm = 0;
    for (r = 0; r < 3; r++) {
        double sum = 0;
        for (c = 0; c < 3; c++) sum += fabs(m[4 * c + r]);
        if (sum > nd->mnorm) nd->mnorm = sum;
    }
    s->built = 0;
    return GEOM_OK;
}

geom_status geom_ray_scene_set_name(geom_ray_scene *s, uint32_t id, const char *name)
{
    size_t n;
    if (!s || id >= s->n || !name) return GEOM_ERR_INVALID_ARG;
    n = strlen(name);
    if (n > sizeof s->nodes[id].name - 1) n = sizeof s->nodes[id].name - 1;
    memcpy(s->nodes[id].name, name, n);
    s->nodes[id].name[n] = 0;
    return GEOM_OK;
}

uint32_t geom_ray_scene_find(const geom_ray_scene *s, const char *name)
{
    size_t i;
    if (!s || !name || !name[0]) return GEOM_INVALID_INDEX;
    for (i = 0; i < s->n; i++)
        if (strncmp(s->nodes[i].name, name, sizeof s->nodes[i].name - 1) == 0 &&
            strlen(name) <= sizeof s->nodes[i].name - 1)
            return (uint32_t)i;
    return GEOM_INVALID_INDEX;
}

static geom_status roots_reserve(geom_ray_scene *s, size_t n)
{
    return geom__grow(s->alloc, (void **)&s->roots, &s->roots_cap, n, sizeof *s->roots);
}

geom_status geom_ray_scene_set_objects(geom_ray_scene *s, const uint32_t *ids, size_t n)
{
    size_t i;
    geom_status st;
    if (!s || (n && !ids)) return GEOM_ERR_INVALID_ARG;
    for (i = 0; i < n; i++)
        if (ids[i] >= s->n) return GEOM_ERR_INVALID_ARG;
    if ((st = roots_reserve(s, n ? n : 1)) != GEOM_OK) return st;
    if (n) memcpy(s->roots, ids, n * sizeof *ids);
    s->nroots = n;
    s->roots_explicit = 1;
    s->built = 0;
    return GEOM_OK;
}

size_t geom_ray_scene_node_count(const geom_ray_scene *s) { return s ? s->n : 0; }
size_t geom_ray_scene_object_count(const geom_ray_scene *s) { return s ? s->nroots : 0; }

uint32_t geom_ray_scene_object_node(const geom_ray_scene *s, size_t i)
{
    if (!s || i >= s->nroots) return GEOM_INVALID_INDEX;
    return s->roots[i];
}

geom_ray_kind geom_ray_scene_node_kind(const geom_ray_scene *s, uint32_t id)
{
    if (!s || id >= s->n) return (geom_ray_kind)0;
    return s->nodes[id].kind;
}

const char *geom_ray_kind_name(geom_ray_kind k)
{
    switch (k) {
    case GEOM_RAY_PLANE: return "plane";
    case GEOM_RAY_DISK: return "disk";
    case GEOM_RAY_BOX: return "box";
    case GEOM_RAY_OBOX: return "obox";
    case GEOM_RAY_SPHERE: return "sphere";
    case GEOM_RAY_QUADRIC: return "quadric";
    case GEOM_RAY_TORUS: return "torus";
    case GEOM_RAY_TRIANGLE: return "triangle";
    case GEOM_RAY_POLYGON: return "polygon";
    case GEOM_RAY_MESH: return "mesh";
    case GEOM_RAY_SURFACE: return "surface";
    case GEOM_RAY_SUBDIV: return "subdivision";
    case GEOM_RAY_IMPLICIT: return "implicit";
    case GEOM_RAY_VOLUME: return "volume";
    case GEOM_RAY_CSG: return "csg";
    case GEOM_RAY_INSTANCE: return "instance";
    case GEOM_RAY_GROUP: return "group";
    }
    return "unknown";
}

geom_status geom_ray_scene_object_error(const geom_ray_scene *s, uint32_t id, geom_error_report *out)
{
    if (!s || id >= s->n || !out) return GEOM_ERR_INVALID_ARG;
    *out = s->nodes[id].err;
    return GEOM_OK;
}

/* ------------------------------------------------------------------ build */

static geom_aabb box_xf(const double *m, geom_aabb b)
{
    geom_aabb o = geom_aabb_empty();
    int i;
    if (geom_aabb_is_empty(b)) return b;
    for (i = 0; i < 8; i++) {
        double p[3] = {(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                       (i & 4) ? b.max.z : b.min.z};
        geom_vec3 q;
        double mag;
        q.x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
        q.y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
        q.z = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
        mag = geom__gamma(6) * (fabs(q.x) + fabs(q.y) + fabs(q.z) + fabs(p[0]) + fabs(p[1]) + fabs(p[2]));
        o = geom_aabb_extend(o, geom_vec3_make(q.x - mag, q.y - mag, q.z - mag));
        o = geom_aabb_extend(o, geom_vec3_make(q.x + mag, q.y + mag, q.z + mag));
    }
    return o;
}

/* Local bounds of node id (in its own frame); *bounded = 0 if infinite. */
static geom_status node_bounds(geom_ray_scene *s, uint32_t id, int depth, const geom_ray_build_options *opt,
                               geom_ray_build_info *info, geom_diag *diag)
{
    geom__ray_node *nd = &s->nodes[id];
    geom_aabb b = geom_aabb_empty();
    int bounded = 1, k;
    geom_status st;
    if (depth > 64) return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                          "node %u: instance or CSG nesting deeper than 64 (a cycle?)",
                                          (unsigned)id);
    switch (nd->kind) {
    case GEOM_RAY_PLANE:
        bounded = 0;
        break;
    case GEOM_RAY_DISK:
        for (k = 0; k < 3; k++) {
            (&b.min.x)[k] = nd->prm[k] - nd->prm[6];
            (&b.max.x)[k] = nd->prm[k] + nd->prm[6];
        }
        break;
    case GEOM_RAY_BOX:
        b.min = geom__v3(nd->prm);
        b.max = geom__v3(nd->prm + 3);
        break;
    case GEOM_RAY_OBOX:
        for (k = 0; k < 3; k++) {
            double e = 0;
            int j;
            for (j = 0; j < 3; j++) e += fabs(nd->prm[3 + 3 * j + k]) * nd->prm[12 + j];
            e += geom__gamma(4) * (e + fabs(nd->prm[k]));
            (&b.min.x)[k] = nd->prm[k] - e;
            (&b.max.x)[k] = nd->prm[k] + e;
        }
        break;
    case GEOM_RAY_SPHERE:
        for (k = 0; k < 3; k++) {
            (&b.min.x)[k] = nd->prm[k] - nd->prm[3];
            (&b.max.x)[k] = nd->prm[k] + nd->prm[3];
        }
        break;
    case GEOM_RAY_QUADRIC:
        if (nd->prm[16] != 0) {
            b.min = geom__v3(nd->prm + 10);
            b.max = geom__v3(nd->prm + 13);
        } else {
            bounded = 0;
        }
        info->analytic++;
        break;
    case GEOM_RAY_TORUS: {
        double e = nd->prm[0] + nd->prm[1];
        b.min = geom_vec3_make(-e, -e, -nd->prm[1]);
        b.max = geom_vec3_make(e, e, nd->prm[1]);
        break;
    }
    case GEOM_RAY_TRIANGLE:
        for (k = 0; k < 3; k++) b = geom_aabb_extend(b, geom__v3(nd->prm + 3 * k));
        break;
    case GEOM_RAY_POLYGON: {
        size_t i;
        for (i = 0; i < nd->nverts; i++) b = geom_aabb_extend(b, geom__v3(nd->verts + 3 * i));
        break;
    }
    case GEOM_RAY_MESH:
    case GEOM_RAY_SUBDIV:
        if ((st = geom__ray_mesh_build(nd->mesh, opt, s->alloc, diag)) != GEOM_OK) return st;
        b = geom__ray_mesh_bounds(nd->mesh);
        info->meshes++;
        info->triangles += nd->mesh->nt;
        {
            size_t bytes;
            info->bvh_nodes += geom__ray_mesh_bvh_nodes(nd->mesh, &bytes);
            info->bvh_bytes += bytes;
        }
        break;
    case GEOM_RAY_SURFACE: {
        size_t i;
        for (i = 0; i < nd->surf->np; i++) b = geom_aabb_union(b, nd->surf->pbox[i]);
        info->bezier_patches += nd->surf->np;
        break;
    }
    case GEOM_RAY_IMPLICIT:
        b.min = geom__v3(nd->prm);
        b.max = geom__v3(nd->prm + 3);
        break;
    case GEOM_RAY_VOLUME:
        b = geom_implicit_volume_bounds(nd->vol);
        break;
    case GEOM_RAY_CSG: {
        geom__ray_node *A, *B;
        if ((st = node_bounds(s, nd->a, depth + 1, opt, info, diag)) != GEOM_OK) return st;
        if ((st = node_bounds(s, nd->b, depth + 1, opt, info, diag)) != GEOM_OK) return st;
        nd = &s->nodes[id];
        A = &s->nodes[nd->a];
        B = &s->nodes[nd->b];
        if (nd->op == GEOM_RAY_CSG_UNION) {
            bounded = A->bounded && B->bounded;
            b = geom_aabb_union(A->box, B->box);
        } else if (nd->op == GEOM_RAY_CSG_INTERSECTION) {
            if (A->bounded && B->bounded) {
                b.min = geom_vec3_make(fmax(A->box.min.x, B->box.min.x), fmax(A->box.min.y, B->box.min.y),
                                       fmax(A->box.min.z, B->box.min.z));
                b.max = geom_vec3_make(fmin(A->box.max.x, B->box.max.x), fmin(A->box.max.y, B->box.max.y),
                                       fmin(A->box.max.z, B->box.max.z));
            } else if (A->bounded) {
                b = A->box;
            } else if (B->bounded) {
                b = B->box;
            } else {
                bounded = 0;
            }
        } else {
            bounded = A->bounded;
            b = A->box;
        }
        break;
    }
    case GEOM_RAY_GROUP: {
        size_t i;
        for (i = 0; i < nd->nmembers; i++) {
            const geom__ray_node *A;
            if ((st = node_bounds(s, nd->members[i], depth + 1, opt, info, diag)) != GEOM_OK) return st;
            nd = &s->nodes[id];
            A = &s->nodes[nd->members[i]];
            if (!A->bounded) bounded = 0;
            b = geom_aabb_union(b, A->box);
        }
        break;
    }
    case GEOM_RAY_INSTANCE: {
        geom__ray_node *A;
        if ((st = node_bounds(s, nd->a, depth + 1, opt, info, diag)) != GEOM_OK) return st;
        nd = &s->nodes[id];
        A = &s->nodes[nd->a];
        bounded = A->bounded;
        b = A->box;
        break;
    }
    }
    nd = &s->nodes[id];
    nd->bounded = bounded;
    nd->box = (bounded && nd->has_xf) ? box_xf(nd->m, b) : b;
    return GEOM_OK;
}

geom_status geom_ray_scene_build(geom_ray_scene *s, const geom_ray_build_options *opt,
                                 geom_ray_build_info *info, geom_diag *diag)
{
    geom_ray_build_info inf;
    size_t i;
    geom_status st;
    if (!s) return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_ray_scene_build: invalid argument");
    memset(&inf, 0, sizeof inf);
    for (i = 0; i < s->n; i++)
        if ((st = node_bounds(s, (uint32_t)i, 0, opt, &inf, diag)) != GEOM_OK) return st;
    /* Analytic count: kinds that need no acceleration. */
    inf.analytic = 0;
    for (i = 0; i < s->n; i++) {
        geom_ray_kind k = s->nodes[i].kind;
        if (k <= GEOM_RAY_POLYGON) inf.analytic++;
    }
    if (!s->roots_explicit) {
        size_t n = 0;
        if ((st = roots_reserve(s, s->n ? s->n : 1)) != GEOM_OK) return st;
        for (i = 0; i < s->n; i++)
            if (!s->nodes[i].is_child) s->roots[n++] = (uint32_t)i;
        s->nroots = n;
    }
    /* Objects: the bounded ones in a BVH when there are many, the others
     * (planes, unclipped quadrics) tested on every ray. */
    top_free(s);
    s->unbounded = geom__alloc(s->alloc, (s->nroots ? s->nroots : 1) * sizeof *s->unbounded);
    if (!s->unbounded) return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_ray_scene_build: out of memory");
    if (s->nroots >= 8) {
        geom_aabb *boxes = geom__alloc(s->alloc, s->nroots * sizeof *boxes);
        geom_bvh_options bo;
        geom_bvh *b = NULL;
        s->top_obj = geom__alloc(s->alloc, s->nroots * sizeof *s->top_obj);
        if (!boxes || !s->top_obj) {
            if (boxes) geom__free(s->alloc, boxes, s->nroots * sizeof *boxes);
            return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_ray_scene_build: out of memory");
        }
        for (i = 0; i < s->nroots; i++) {
            const geom__ray_node *nd = &s->nodes[s->roots[i]];
            if (!nd->bounded) {
                s->unbounded[s->nunbounded++] = (uint32_t)i;
            } else if (!geom_aabb_is_empty(nd->box)) {
                boxes[s->ntop] = nd->box;
                s->top_obj[s->ntop++] = (uint32_t)i;
            }
        }
        memset(&bo, 0, sizeof bo);
        bo.alloc = s->alloc;
        bo.threads = opt ? opt->bvh_threads : 0;
        st = geom_bvh_build_boxes(boxes, s->ntop, &bo, &b, diag);
        geom__free(s->alloc, boxes, s->nroots * sizeof *boxes);
        if (st != GEOM_OK) return st;
        s->top = b;
    } else {
        for (i = 0; i < s->nroots; i++) s->unbounded[s->nunbounded++] = (uint32_t)i;
    }
    s->built = 1;
    if (info) *info = inf;
    return GEOM_OK;
}

/* ---------------------------------------------------------------- queries */

static void hit_to_parent(const geom__ray_node *nd, geom_ray_hit *h, const geom_ray *r)
{
    const double *m = nd->m, *n = nd->nm;
    geom_vec3 p = h->point, q, pe = h->p_error, ng = h->ng, ns = h->ns;
    double tn = fabs(m[12]) + fabs(m[13]) + fabs(m[14]);
    double g = geom__gamma(4) * (nd->mnorm * (fabs(p.x) + fabs(p.y) + fabs(p.z)) + tn);
    q.x = m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12];
    q.y = m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13];
    q.z = m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14];
    h->point = q;
    h->p_error.x = fabs(m[0]) * pe.x + fabs(m[4]) * pe.y + fabs(m[8]) * pe.z + g;
    h->p_error.y = fabs(m[1]) * pe.x + fabs(m[5]) * pe.y + fabs(m[9]) * pe.z + g;
    h->p_error.z = fabs(m[2]) * pe.x + fabs(m[6]) * pe.y + fabs(m[10]) * pe.z + g;
    h->ng = geom__unit(geom_vec3_make(n[0] * ng.x + n[3] * ng.y + n[6] * ng.z,
                                      n[1] * ng.x + n[4] * ng.y + n[7] * ng.z,
                                      n[2] * ng.x + n[5] * ng.y + n[8] * ng.z));
    h->ns = geom__unit(geom_vec3_make(n[0] * ns.x + n[3] * ns.y + n[6] * ns.z,
                                      n[1] * ns.x + n[4] * ns.y + n[7] * ns.z,
                                      n[2] * ns.x + n[5] * ns.y + n[8] * ns.z));
    /* The mapped ray carries rounding of its own: widen t's bound. */
    {
        double dn = fabs(geom__dot(h->ng, r->dir));
        double pn = fabs(h->ng.x) * g + fabs(h->ng.y) * g + fabs(h->ng.z) * g;
        if (dn > 0) h->t_error += pn / dn;
    }
}

geom_status geom__ray_node_query(const geom_ray_scene *s, uint32_t id, const geom_ray *r, int mode,
                                 geom__rhits *out)
{
    const geom__ray_node *nd = &s->nodes[id];
    geom_ray lr;
    const geom_ray *q = r;
    size_t start = out->n, i;
    geom_status st = GEOM_OK;
    if (nd->has_xf) {
        const double *m = nd->minv;
        geom_vec3 o = r->origin, d = r->dir;
        lr.origin.x = m[0] * o.x + m[4] * o.y + m[8] * o.z + m[12];
        lr.origin.y = m[1] * o.x + m[5] * o.y + m[9] * o.z + m[13];
        lr.origin.z = m[2] * o.x + m[6] * o.y + m[10] * o.z + m[14];
        lr.dir.x = m[0] * d.x + m[4] * d.y + m[8] * d.z;
        lr.dir.y = m[1] * d.x + m[5] * d.y + m[9] * d.z;
        lr.dir.z = m[2] * d.x + m[6] * d.y + m[10] * d.z;
        lr.tmin = r->tmin;
        lr.tmax = r->tmax;
        if (!isfinite(lr.dir.x + lr.dir.y + lr.dir.z) || !isfinite(lr.origin.x + lr.origin.y + lr.origin.z) ||
            (lr.dir.x == 0 && lr.dir.y == 0 && lr.dir.z == 0))
            return GEOM_OK;
        q = &lr;
    }
    switch (nd->kind) {
    case GEOM_RAY_PLANE: st = geom__ray_plane(nd, q, mode, out); break;
    case GEOM_RAY_DISK: st = geom__ray_disk(nd, q, mode, out); break;
    case GEOM_RAY_BOX: st = geom__ray_box(nd, q, mode, out); break;
    case GEOM_RAY_OBOX: st = geom__ray_obox(nd, q, mode, out); break;
    case GEOM_RAY_SPHERE: st = geom__ray_sphere(nd, q, mode, out); break;
    case GEOM_RAY_QUADRIC: st = geom__ray_quadric(nd, q, mode, out); break;
    case GEOM_RAY_TORUS: st = geom__ray_torus(nd, q, mode, out); break;
    case GEOM_RAY_TRIANGLE: st = geom__ray_tri(nd, q, mode, out); break;
    case GEOM_RAY_POLYGON: st = geom__ray_polygon(nd, q, mode, out); break;
    case GEOM_RAY_MESH:
    case GEOM_RAY_SUBDIV: st = geom__ray_mesh(nd->mesh, q, mode, out); break;
    case GEOM_RAY_SURFACE: st = geom__ray_surface(nd->surf, q, mode, out); break;
    case GEOM_RAY_IMPLICIT: st = geom__ray_implicit(nd, q, mode, out); break;
    case GEOM_RAY_VOLUME: st = geom__ray_volume(nd, q, mode, out); break;
    case GEOM_RAY_CSG: st = geom__ray_csg(s, nd, q, mode, out); break;
    case GEOM_RAY_GROUP: {
        size_t i;
        for (i = 0; i < nd->nmembers && st == GEOM_OK; i++) {
            const geom__ray_node *c = &s->nodes[nd->members[i]];
            if (c->bounded && !geom_ray_aabb(q, c->box, NULL, NULL)) continue;
            st = geom__ray_node_query(s, nd->members[i], q, mode, out);
            if (mode == GEOM__RAY_ANY && out->n > start) break;
        }
        break;
    }
    case GEOM_RAY_INSTANCE: {
        const geom__ray_node *c = &s->nodes[nd->a];
        double t0, t1;
        if (!c->bounded || geom_ray_aabb(q, c->box, &t0, &t1)) st = geom__ray_node_query(s, nd->a, q, mode, out);
        break;
    }
    }
    if (nd->has_xf)
        for (i = start; i < out->n; i++) hit_to_parent(nd, &out->h[i], r);
    if (st == GEOM_OK && out->failed) st = GEOM_ERR_NOMEM;
    return st;
}

/* Keep only the closest hit among [from, n). */
static void keep_closest(geom__rhits *l, size_t from)
{
    size_t i, best = from;
    if (l->n <= from) return;
    for (i = from + 1; i < l->n; i++)
        if (l->h[i].t < l->h[best].t) best = i;
    if (best != from) l->h[from] = l->h[best];
    l->n = from + 1;
}

/* Query top-level object i; 1 = stop (any hit found). Keeps the closest
 * hit in slot 0 in closest mode (ties: the smaller object index). */
static int visit(const geom_ray_scene *s, uint32_t i, geom_ray *q, geom__rslab *sl, int mode,
                 geom__rhits *out, geom_status *st)
{
    const geom__ray_node *nd = &s->nodes[s->roots[i]];
    size_t start = out->n, j;
    if (nd->bounded && !geom__rslab_hit(sl, q, &nd->box)) return 0;
    if ((nd->kind == GEOM_RAY_MESH || nd->kind == GEOM_RAY_SUBDIV) && !nd->has_xf) {
        /* geom__ray_node_query's mesh case, with the ray's reciprocal */
        *st = geom__ray_mesh_sl(nd->mesh, q, sl, mode, out);
        if (*st == GEOM_OK && out->failed) *st = GEOM_ERR_NOMEM;
    } else {
        *st = geom__ray_node_query(s, s->roots[i], q, mode, out);
    }
    if (*st != GEOM_OK) return 1;
    for (j = start; j < out->n; j++) out->h[j].object = i;
    if (mode == GEOM__RAY_ANY && out->n > 0) return 1;
    if (mode == GEOM__RAY_CLOSEST && out->n > start) {
        keep_closest(out, start);
        if (start > 0) {
            if (out->h[start].t < out->h[0].t || (out->h[start].t == out->h[0].t && i < out->h[0].object))
                out->h[0] = out->h[start];
            out->n = 1;
        }
        q->tmax = out->h[0].t;
    }
    return 0;
}

static geom_status run(const geom_ray_scene *s, const geom_ray *r, int mode, geom__rhits *out)
{
    geom_ray q = *r;
    geom__rslab sl;
    size_t i;
    geom_status st = GEOM_OK;
    if (!s->built) return GEOM_ERR_INVALID_ARG;
    if (!geom__ray_valid(r)) return GEOM_ERR_INVALID_ARG;
    if (!(r->tmin <= r->tmax)) return GEOM_OK;
    sl.ok = -1; /* computed at the first box test */
    for (i = 0; i < s->nunbounded; i++)
        if (visit(s, s->unbounded[i], &q, &sl, mode, out, &st)) return st;
    if (s->top) {
        size_t nn = 0;
        const geom_bvh_node *nodes = geom_bvh_nodes(s->top, &nn);
        const uint32_t *prims = geom_bvh_prim_indices(s->top, NULL);
        uint32_t stack[256];
        int sp = 0;
        if (nn == 0) return GEOM_OK;
        stack[sp++] = 0;
        while (sp > 0) {
            const geom_bvh_node *nd = &nodes[stack[--sp]];
            if (!geom__rslab_hit(&sl, &q, &nd->box)) continue;
            if (nd->count == 0) {
                if (sp + 2 > 256) return GEOM_ERR_LIMIT;
                stack[sp++] = nd->index;
                stack[sp++] = (uint32_t)(nd - nodes) + 1;
            } else {
                uint32_t k;
                for (k = 0; k < nd->count; k++)
                    if (visit(s, s->top_obj[prims[nd->index + k]], &q, &sl, mode, out, &st)) return st;
            }
        }
    }
    return GEOM_OK;
}

geom_status geom_ray_scene_closest(const geom_ray_scene *s, const geom_ray *r, geom_ray_hit *hit, int *found)
{
    geom__rhits l;
    geom_status st;
    if (found) *found = 0;
    if (!s || !r || !hit || !found) return GEOM_ERR_INVALID_ARG;
    geom__rhits_init(&l, s->alloc);
    st = run(s, r, GEOM__RAY_CLOSEST, &l);
    if (st == GEOM_OK && l.n > 0) {
        *hit = l.h[0];
        *found = 1;
    }
    geom__rhits_free(&l);
    return st;
}

geom_status geom_ray_scene_any(const geom_ray_scene *s, const geom_ray *r, int *found)
{
    geom__rhits l;
    geom_status st;
    if (found) *found = 0;
    if (!s || !r || !found) return GEOM_ERR_INVALID_ARG;
    geom__rhits_init(&l, s->alloc);
    st = run(s, r, GEOM__RAY_ANY, &l);
    if (st == GEOM_OK) *found = l.n > 0;
    geom__rhits_free(&l);
    return st;
}

geom_status geom_ray_scene_all(const geom_ray_scene *s, const geom_ray *r, geom_ray_hit *hits, size_t cap,
                               size_t *n)
{
    geom__rhits l;
    geom_status st;
    if (n) *n = 0;
    if (!s || !r || !n || (cap && !hits)) return GEOM_ERR_INVALID_ARG;
    geom__rhits_init(&l, s->alloc);
    st = run(s, r, GEOM__RAY_ALL, &l);
    if (st == GEOM_OK) {
        geom__rhits_sort(&l, 0);
        *n = l.n;
        if (cap) memcpy(hits, l.h, (l.n < cap ? l.n : cap) * sizeof *hits);
        if (l.n > cap) st = GEOM_ERR_LIMIT;
    }
    geom__rhits_free(&l);
    return st;
}

/* Batches: each ray answered by run() as the single-ray functions do, one
 * hit list reused (emptied before each ray: its inline buffer or the heap
 * array the previous rays grew). */
static geom_status run_one(const geom_ray_scene *s, const geom_ray *r, int mode, geom__rhits *l, int *bad)
{
    geom_status st;
    l->n = 0;
    l->failed = 0;
    st = run(s, r, mode, l);
    if (st == GEOM_ERR_INVALID_ARG) { /* an invalid ray: no hit, the batch goes on */
        *bad = 1;
        l->n = 0;
        st = GEOM_OK;
    }
    return st;
}

geom_status geom_ray_scene_any_many(const geom_ray_scene *s, const geom_ray *rays, size_t n, int *found)
{
    geom__rhits l;
    geom_status st = GEOM_OK;
    size_t i;
    int bad = 0;
    if (found)
        for (i = 0; i < n; i++) found[i] = 0;
    if (!s || (n && (!rays || !found))) return GEOM_ERR_INVALID_ARG;
    if (!s->built) return GEOM_ERR_INVALID_ARG;
    geom__rhits_init(&l, s->alloc);
    for (i = 0; i < n; i++) {
        if ((st = run_one(s, &rays[i], GEOM__RAY_ANY, &l, &bad)) != GEOM_OK) break;
        found[i] = l.n > 0;
    }
    geom__rhits_free(&l);
    if (st != GEOM_OK) return st;
    return bad ? GEOM_ERR_INVALID_ARG : GEOM_OK;
}

geom_status geom_ray_scene_all_many(const geom_ray_scene *s, const geom_ray *rays, size_t n, size_t *offsets,
                                   geom_ray_hit *hits, size_t cap, size_t *count)
{
    geom__rhits l;
    geom_status st = GEOM_OK;
    size_t i, total = 0;
    int bad = 0;
    if (count) *count = 0;
    if (offsets)
        for (i = 0; i <= n; i++) offsets[i] = 0;
    if (!s || !offsets || !count || (n && !rays) || (cap && !hits)) return GEOM_ERR_INVALID_ARG;
    if (!s->built) return GEOM_ERR_INVALID_ARG;
    geom__rhits_init(&l, s->alloc);
    for (i = 0; i < n; i++) {
        if ((st = run_one(s, &rays[i], GEOM__RAY_ALL, &l, &bad)) != GEOM_OK) break;
        geom__rhits_sort(&l, 0);
        if (total < cap) memcpy(hits + total, l.h, (l.n < cap - total ? l.n : cap - total) * sizeof *hits);
        total += l.n;
        offsets[i + 1] = total;
    }
    geom__rhits_free(&l);
    if (st != GEOM_OK) return st;
    *count = total;
    if (total > cap) return GEOM_ERR_LIMIT;
    return bad ? GEOM_ERR_INVALID_ARG : GEOM_OK;
}
