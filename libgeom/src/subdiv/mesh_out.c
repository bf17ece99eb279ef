/*
 * Whole-mesh subdivision: refine a geom_mesh and all its channels and
 * build the refined geom_mesh (holes left out), with the error report.
 */
#include "subdiv_internal.h"

#include <stdlib.h>

/* The output's faces and vertices among the level's: the maps are NULL
 * (the identity) when no face is a hole. */
typedef struct outmap {
    uint32_t nf_out;      /* faces kept (not holes) */
    uint32_t *face_level; /* per soup face: the level face */
    uint32_t *vert_new;   /* per level vertex: soup vertex or SD_INVALID */
    uint32_t *vert_old;   /* per soup vertex: level vertex */
    uint32_t nv_out;
} outmap;

static inline uint32_t om_vert(const outmap *om, uint32_t v)
{
    return om->vert_new ? om->vert_new[v] : v;
}

/* Kinds of data refine_data refines: vertex, face or face-varying. */
enum { KIND_VERTEX, KIND_FACE, KIND_FVAR };

/* Values of the level-0 vertices (KIND_VERTEX) or live faces (KIND_FACE) of
 * a mesh channel, in a zeroed array of one row per level-0 element. */
static double *level0_data(const geom_allocator *a, const geom_mesh *m, const sd_level *l0,
                           int kind, uint32_t ch, size_t nc)
{
    uint32_t n0 = kind == KIND_VERTEX ? l0->nv : l0->nf;
    double *d = sd_calloc(a, (size_t)n0 * nc, sizeof(double));
    if (!d)
        return NULL;
    const double *src = geom_mesh_channel_cdata(m, ch);
    if (kind == KIND_VERTEX) {
        size_t n = geom_mesh_channel_size(m, ch);
        for (uint32_t v = 0; v < n0 && v < n; v++)
            memcpy(d + (size_t)v * nc, src + (size_t)v * nc, nc * sizeof(double));
        return d;
    }
    uint32_t f0 = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m) && f0 < n0; f++) {
        if (geom_mesh_face_is_deleted(m, f))
            continue;
        memcpy(d + (size_t)f0 * nc, src + (size_t)f * nc, nc * sizeof(double));
        f0++;
    }
    return d;
}

/* Refine data from level 0 to `level` (vertex, face or face-varying). */
static geom_status refine_data(const geom_subdiv_refiner *r, int level, int kind, uint32_t fch,
                               size_t nc, double *d0, double **out)
{
    const geom_allocator *a = sd_alloc(r);
    double *cur = d0;
    size_t cur_n = kind == KIND_VERTEX ? r->lv[0]->nv
                   : kind == KIND_FACE ? r->lv[0]->nf
                                       : r->lv[0]->fvar[fch].nvalues;
    for (int l = 1; l <= level; l++) {
        const sd_level *c = r->lv[l];
        size_t n = kind == KIND_VERTEX ? c->nv : kind == KIND_FACE ? c->nf : c->fvar[fch].nvalues;
        double *next = sd_calloc(a, n * nc, sizeof(double));
        if (!next) {
            sd_free(a, cur, cur_n * nc, sizeof(double));
            return GEOM_ERR_NOMEM;
        }
        geom_status st = kind == KIND_VERTEX ? geom_subdiv_interpolate(r, l, nc, cur, next)
                         : kind == KIND_FACE ? geom_subdiv_interpolate_face(r, l, nc, cur, next)
                                             : geom_subdiv_interpolate_fvar(r, fch, l, nc, cur, next);
        sd_free(a, cur, cur_n * nc, sizeof(double));
        if (st != GEOM_OK) {
            sd_free(a, next, n * nc, sizeof(double));
            return st;
        }
        cur = next;
        cur_n = n;
    }
    *out = cur;
    return GEOM_OK;
}

static size_t data_count(const geom_subdiv_refiner *r, int level, int kind, uint32_t fch)
{
    const sd_level *c = r->lv[level];
    return kind == KIND_VERTEX ? c->nv : kind == KIND_FACE ? c->nf : c->fvar[fch].nvalues;
}

static int is_option_tag(const char *n)
{
    return strcmp(n, "interpolateboundary") == 0 || strcmp(n, "facevaryinginterpolateboundary") == 0 ||
           strcmp(n, "facevaryingpropagatecorners") == 0 || strcmp(n, "creasemethod") == 0 ||
           strcmp(n, "smoothtriangles") == 0;
}

static geom_status add_tags(const geom_subdiv_refiner *r, const sd_level *l, const outmap *om,
                            const geom_mesh *like, geom_mesh *out)
{
    const geom_allocator *a = sd_alloc(r);
    geom_status st = GEOM_OK;
    if (like) {
        for (size_t i = 0; st == GEOM_OK && i < geom_mesh_tag_count(like); i++) {
            geom_mesh_tag t;
            if (geom_mesh_tag_get(like, i, &t) == GEOM_OK && t.name && is_option_tag(t.name))
                st = geom_mesh_tag_add(out, &t);
        }
    }
    if (st != GEOM_OK || r->o.scheme == GEOM_SUBDIV_BUTTERFLY || r->o.scheme == GEOM_SUBDIV_SQRT3)
        return st;
    /* creases still sharp (not boundaries or non-manifold edges) */
    size_t n = 0;
    for (uint32_t e = 0; e < l->ne; e++)
        if (l->esharp[e] > 0.0f && !(l->etag[e] & (SD_E_BOUNDARY | SD_E_NONMANIFOLD)) &&
            om_vert(om, l->ev[2 * (size_t)e]) != SD_INVALID &&
            om_vert(om, l->ev[2 * (size_t)e + 1]) != SD_INVALID)
            n++;
    if (n) {
        int64_t *iv = sd_calloc(a, 2 * n, sizeof(int64_t));
        double *fv = sd_calloc(a, n, sizeof(double));
        if (!iv || !fv) {
            sd_free(a, iv, 2 * n, sizeof(int64_t));
            sd_free(a, fv, n, sizeof(double));
            return GEOM_ERR_NOMEM;
        }
        size_t k = 0;
        for (uint32_t e = 0; e < l->ne; e++) {
            if (l->esharp[e] > 0.0f && !(l->etag[e] & (SD_E_BOUNDARY | SD_E_NONMANIFOLD)) &&
                om_vert(om, l->ev[2 * (size_t)e]) != SD_INVALID &&
                om_vert(om, l->ev[2 * (size_t)e + 1]) != SD_INVALID) {
                iv[2 * k] = om_vert(om, l->ev[2 * (size_t)e]);
                iv[2 * k + 1] = om_vert(om, l->ev[2 * (size_t)e + 1]);
                fv[k] = l->esharp[e];
                k++;
            }
        }
        geom_mesh_tag t = {"crease", 2 * n, n, 0, iv, fv, NULL};
        st = geom_mesh_tag_add(out, &t);
        sd_free(a, iv, 2 * n, sizeof(int64_t));
        sd_free(a, fv, n, sizeof(double));
        if (st != GEOM_OK)
            return st;
    }
    n = 0;
    for (uint32_t v = 0; v < l->nv; v++)
        if (l->vsharp[v] > 0.0f && !(l->vtag[v] & SD_V_NONMANIFOLD) && om_vert(om, v) != SD_INVALID)
            n++;
    if (n) {
        int64_t *iv = sd_calloc(a, n, sizeof(int64_t));
        double *fv = sd_calloc(a, n, sizeof(double));
        if (!iv || !fv) {
            sd_free(a, iv, n, sizeof(int64_t));
            sd_free(a, fv, n, sizeof(double));
            return GEOM_ERR_NOMEM;
        }
        size_t k = 0;
        for (uint32_t v = 0; v < l->nv; v++) {
            if (l->vsharp[v] > 0.0f && !(l->vtag[v] & SD_V_NONMANIFOLD) &&
                om_vert(om, v) != SD_INVALID) {
                iv[k] = om_vert(om, v);
                fv[k] = l->vsharp[v];
                k++;
            }
        }
        geom_mesh_tag t = {"corner", n, n, 0, iv, fv, NULL};
        st = geom_mesh_tag_add(out, &t);
        sd_free(a, iv, n, sizeof(int64_t));
        sd_free(a, fv, n, sizeof(double));
    }
    return st;
}

static geom_status copy_groups(const geom_subdiv_refiner *r, int level, const outmap *om,
                               const geom_mesh *like, geom_mesh *out)
{
    const uint32_t *g = geom_mesh_face_cgroups(like);
    if (!g || geom_mesh_group_count(like) == 0)
        return GEOM_OK;
    for (size_t i = 0; i < geom_mesh_group_count(like); i++) {
        geom_mesh_group gr;
        geom_status st = geom_mesh_group_get(like, i, &gr);
        if (st == GEOM_OK)
            st = geom_mesh_group_add(out, &gr, NULL);
        if (st != GEOM_OK)
            return st;
    }
    uint32_t *og = geom_mesh_face_groups(out);
    if (!og)
        return GEOM_ERR_NOMEM;
    const sd_level *l0 = r->lv[0];
    const geom_allocator *a = sd_alloc(r);
    uint32_t *g0 = sd_calloc(a, l0->nf, sizeof(uint32_t));
    if (!g0)
        return GEOM_ERR_NOMEM;
    uint32_t f0 = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(like) && f0 < l0->nf; f++)
        if (!geom_mesh_face_is_deleted(like, f))
            g0[f0++] = g[f];
    const uint32_t *forig = geom_mesh_face_origin(out);
    for (uint32_t f = 0; f < geom_mesh_n_faces(out); f++) {
        uint32_t sf = forig ? forig[f] : f;
        uint32_t lf = om->face_level ? om->face_level[sf] : sf;
        for (int l = level; l > 0; l--)
            lf = r->lv[l]->face_parent[lf];
        og[f] = g0[lf];
    }
    sd_free(a, g0, l0->nf, sizeof(uint32_t));
    return GEOM_OK;
}

/* Values per output (soup) vertex or face from values per level element:
 * `lv` itself when nothing was left out, else a gathered copy (*own). */
static const double *soup_values(const geom_allocator *a, const double *lv, size_t nc,
                                 const uint32_t *map, size_t n, int gather, double **own,
                                 size_t *own_n)
{
    if (!gather)
        return lv;
    double *d = sd_calloc(a, n * nc, sizeof(double));
    if (!d)
        return NULL;
    for (size_t i = 0; i < n; i++)
        memcpy(d + i * nc, lv + (size_t)map[i] * nc, nc * sizeof(double));
    *own = d;
    *own_n = n * nc;
    return d;
}

typedef struct sd_stream_mem {
    double *d;    /* refined values (level order) */
    size_t nd;
    double *g;    /* gathered values (soup order) */
    size_t ng;
    uint32_t *ix; /* gathered corner indices */
    size_t nix;
} sd_stream_mem;

geom_status geom_subdiv_build_mesh(const geom_subdiv_refiner *r, int level, const double *positions,
                                   const double *normals, const geom_mesh *like, geom_mesh **out,
                                   size_t *hole_faces, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (hole_faces)
        *hole_faces = 0;
    if (!r || !positions || !out || level < 0 || level >= r->nlevels)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_subdiv_build_mesh: invalid argument");
    const geom_allocator *a = sd_alloc(r);
    const sd_level *l = r->lv[level];
    outmap om;
    memset(&om, 0, sizeof om);
    geom_status st = GEOM_ERR_NOMEM;
    uint32_t *sizes = NULL, *idx = NULL;
    double *pos = NULL;
    geom_mesh *m = NULL;
    size_t nidx = 0;
    size_t nlike = like ? geom_mesh_channel_count(like) : 0;
    geom_mesh_build_channel *chans = sd_calloc(a, nlike + 1, sizeof *chans);
    sd_stream_mem *mem = sd_calloc(a, nlike + 1, sizeof *mem);
    size_t nch = 0;
    if (!chans || !mem)
        goto done;
    int any_hole = 0;
    for (uint32_t f = 0; f < l->nf; f++) {
        if (l->fhole[f]) {
            any_hole = 1;
            if (hole_faces)
                (*hole_faces)++;
            continue;
        }
        om.nf_out++;
        nidx += l->fv_off[f + 1] - l->fv_off[f];
    }
    om.nv_out = l->nv;
    if (any_hole) {
        om.face_level = sd_malloc(a, om.nf_out, sizeof(uint32_t));
        om.vert_new = sd_malloc(a, l->nv, sizeof(uint32_t));
        om.vert_old = sd_malloc(a, l->nv, sizeof(uint32_t));
        if (!om.face_level || !om.vert_new || !om.vert_old)
            goto done;
        for (uint32_t f = 0, i = 0; f < l->nf; f++)
            if (!l->fhole[f])
                om.face_level[i++] = f;
        for (uint32_t v = 0; v < l->nv; v++)
            om.vert_new[v] = SD_INVALID;
        for (uint32_t i = 0; i < om.nf_out; i++) {
            uint32_t f = om.face_level[i];
            for (uint32_t k = l->fv_off[f]; k < l->fv_off[f + 1]; k++)
                om.vert_new[l->fv[k]] = 0;
        }
        om.nv_out = 0;
        for (uint32_t v = 0; v < l->nv; v++)
            if (om.vert_new[v] == 0)
                om.vert_new[v] = om.nv_out, om.vert_old[om.nv_out++] = v;
    }
    const uint32_t *soup_idx = l->fv + l->fv_off[0];
    const double *soup_pos = positions;
    if (any_hole) {
        idx = sd_calloc(a, nidx, sizeof(uint32_t));
        pos = sd_calloc(a, 3 * (size_t)om.nv_out, sizeof(double));
        if (!idx || !pos)
            goto done;
        for (uint32_t v = 0; v < om.nv_out; v++)
            memcpy(pos + 3 * (size_t)v, positions + 3 * (size_t)om.vert_old[v], 3 * sizeof(double));
        size_t k = 0;
        for (uint32_t i = 0; i < om.nf_out; i++) {
            uint32_t f = om.face_level[i];
            for (uint32_t j = l->fv_off[f]; j < l->fv_off[f + 1]; j++)
                idx[k++] = om.vert_new[l->fv[j]];
        }
        soup_idx = idx;
        soup_pos = pos;
    }
    st = GEOM_OK;
    /* attribute streams: vertex and face channels refined, then the
     * face-varying ones, then the normals (replacing any "normal" channel) */
    int have_vnormal = 0;
    for (uint32_t ch = 1; st == GEOM_OK && ch < nlike; ch++) {
        geom_mesh_domain dom = geom_mesh_channel_domain(like, ch);
        if (dom != GEOM_MESH_DOMAIN_VERTEX && dom != GEOM_MESH_DOMAIN_FACE)
            continue;
        size_t nc = geom_mesh_channel_ncomp(like, ch);
        const char *name = geom_mesh_channel_name(like, ch);
        sd_stream_mem *sm = &mem[nch];
        const double *lv;
        if (normals && dom == GEOM_MESH_DOMAIN_VERTEX && nc == 3 && strcmp(name, "normal") == 0) {
            have_vnormal = 1;
            lv = normals;
        } else {
            int kind = dom == GEOM_MESH_DOMAIN_VERTEX ? KIND_VERTEX : KIND_FACE;
            double *d0 = level0_data(a, like, r->lv[0], kind, ch, nc);
            if (!d0) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            st = refine_data(r, level, kind, 0, nc, d0, &sm->d);
            if (st != GEOM_OK)
                break;
            sm->nd = data_count(r, level, kind, 0) * nc;
            lv = sm->d;
        }
        int vert = dom == GEOM_MESH_DOMAIN_VERTEX;
        const double *vals =
            soup_values(a, lv, nc, vert ? om.vert_old : om.face_level, vert ? om.nv_out : om.nf_out,
                        any_hole, &sm->g, &sm->ng);
        if (!vals) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        geom_mesh_build_channel c = {name, dom, nc, 0, vals, NULL};
        chans[nch++] = c;
    }
    for (uint32_t fc = 0; st == GEOM_OK && fc < r->n_fvar_mesh; fc++) {
        uint32_t ch = r->fvar_mesh_channel[fc];
        if (ch >= nlike || geom_mesh_channel_domain(like, ch) != GEOM_MESH_DOMAIN_CORNER)
            continue;
        const char *name = geom_mesh_channel_name(like, ch);
        if (normals && strcmp(name, "normal") == 0)
            continue; /* replaced by the vertex normals */
        size_t nc = geom_mesh_channel_ncomp(like, ch);
        size_t pool = geom_mesh_channel_size(like, ch);
        sd_stream_mem *sm = &mem[nch];
        double *d0 = sd_calloc(a, pool * nc, sizeof(double));
        if (!d0) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        if (pool)
            memcpy(d0, geom_mesh_channel_cdata(like, ch), pool * nc * sizeof(double));
        st = refine_data(r, level, KIND_FVAR, fc, nc, d0, &sm->d);
        if (st != GEOM_OK)
            break;
        size_t nvals = data_count(r, level, KIND_FVAR, fc);
        sm->nd = nvals * nc;
        const uint32_t *fvals = l->fvar[fc].fvals;
        const uint32_t *cix = fvals + l->fv_off[0];
        if (any_hole) {
            sm->ix = sd_calloc(a, nidx, sizeof(uint32_t));
            if (!sm->ix) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            sm->nix = nidx;
            size_t k = 0;
            for (uint32_t i = 0; i < om.nf_out; i++) {
                uint32_t f = om.face_level[i];
                for (uint32_t j = l->fv_off[f]; j < l->fv_off[f + 1]; j++)
                    sm->ix[k++] = fvals[j];
            }
            cix = sm->ix;
        }
        geom_mesh_build_channel c = {name, GEOM_MESH_DOMAIN_CORNER, nc, nvals, sm->d, cix};
        chans[nch++] = c;
    }
    if (st == GEOM_OK && normals && !have_vnormal) {
        sd_stream_mem *sm = &mem[nch];
        const double *vals =
            soup_values(a, normals, 3, om.vert_old, om.nv_out, any_hole, &sm->g, &sm->ng);
        if (!vals)
            st = GEOM_ERR_NOMEM;
        geom_mesh_build_channel c = {"normal", GEOM_MESH_DOMAIN_VERTEX, 3, 0, vals, NULL};
        chans[nch++] = c;
    }
    if (st != GEOM_OK)
        goto done;
    m = geom_mesh_create(a);
    if (!m) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    /* the level's own relations when it is an oriented manifold without
     * holes (the common case), else the soup through geom_mesh_build */
    int direct = !any_hole && sd_mesh_direct_applies(r, level);
    for (uint32_t v = 0; direct && v < l->nv; v++)
        if (!geom__isfinite3(positions + 3 * (size_t)v))
            direct = 0; /* geom_mesh_build names it */
    if (direct) {
        st = sd_mesh_direct(l, positions, chans, nch, m);
        if (st == SD_DIRECT_DECLINED)
            direct = 0;
    }
    if (!direct) {
        /* the soup: the level's own arrays when no face was left out */
        sizes = sd_malloc(a, om.nf_out, sizeof(uint32_t));
        if (!sizes) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        for (uint32_t i = 0; i < om.nf_out; i++) {
            uint32_t f = om.face_level ? om.face_level[i] : i;
            sizes[i] = l->fv_off[f + 1] - l->fv_off[f];
        }
        geom_mesh_build_options bo;
        memset(&bo, 0, sizeof bo);
        bo.skip_invalid_faces = 1;
        bo.keep_orientation = 1;
        bo.channels = chans;
        bo.n_channels = nch;
        st = geom_mesh_build(m, om.nv_out, soup_pos, om.nf_out, sizes, soup_idx, &bo, NULL, diag);
    }
    if (st == GEOM_OK && like) {
        st = copy_groups(r, level, &om, like, m);
        for (size_t i = 0; st == GEOM_OK && i < geom_mesh_mtllib_count(like); i++)
            st = geom_mesh_mtllib_add(m, geom_mesh_mtllib_get(like, i));
    }
    if (st == GEOM_OK)
        st = add_tags(r, l, &om, like, m);
done:
    if (mem)
        for (size_t i = 0; i < nlike + 1; i++) {
            sd_free(a, mem[i].d, mem[i].nd, sizeof(double));
            sd_free(a, mem[i].g, mem[i].ng, sizeof(double));
            sd_free(a, mem[i].ix, mem[i].nix, sizeof(uint32_t));
        }
    sd_free(a, mem, nlike + 1, sizeof *mem);
    sd_free(a, chans, nlike + 1, sizeof *chans);
    sd_free(a, om.face_level, om.nf_out, sizeof(uint32_t));
    sd_free(a, om.vert_new, l->nv, sizeof(uint32_t));
    sd_free(a, om.vert_old, l->nv, sizeof(uint32_t));
    sd_free(a, sizes, om.nf_out, sizeof(uint32_t));
    sd_free(a, idx, nidx, sizeof(uint32_t));
    sd_free(a, pos, 3 * (size_t)om.nv_out, sizeof(double));
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return st;
    }
    *out = m;
    return GEOM_OK;
}

/* Whether add_tags would give the output no crease or corner tag (no
 * option tag in like, no edge or vertex of l still sharp apart from
 * boundaries and non-manifold ones). */
static int no_tags(const sd_level *l, const geom_mesh *like)
{
    for (size_t i = 0; like && i < geom_mesh_tag_count(like); i++) {
        geom_mesh_tag t;
        if (geom_mesh_tag_get(like, i, &t) == GEOM_OK && t.name && is_option_tag(t.name))
            return 0;
    }
    for (uint32_t e = 0; e < l->ne; e++)
        if (l->esharp[e] > 0.0f && !(l->etag[e] & (SD_E_BOUNDARY | SD_E_NONMANIFOLD)))
            return 0;
    for (uint32_t v = 0; v < l->nv; v++)
        if (l->vsharp[v] > 0.0f && !(l->vtag[v] & SD_V_NONMANIFOLD))
            return 0;
    return 1;
}

int geom_subdiv_level_is_plain(const geom_subdiv_refiner *r, int level, const double *positions,
                               int with_normals, const geom_mesh *like)
{
    if (!r || !positions || level < 1 || level >= r->nlevels)
        return 0;
    const sd_level *l = r->lv[level], *l0 = r->lv[0];
    if (l->n_hole_faces || !sd_mesh_direct_applies(r, level))
        return 0;
    /* an isolated vertex of level 0 stays one (the build keeps it, a soup
     * writer would too, but the direct build is not made for it) */
    for (uint32_t v = 0; v < l0->nv; v++)
        if (l0->vf_off[v + 1] == l0->vf_off[v])
            return 0;
    if (like) {
        /* positions only, or normals that with_normals replaces */
        for (uint32_t ch = 1; ch < geom_mesh_channel_count(like); ch++) {
            geom_mesh_domain d = geom_mesh_channel_domain(like, ch);
            const char *name = geom_mesh_channel_name(like, ch);
            int vn = d == GEOM_MESH_DOMAIN_VERTEX && geom_mesh_channel_ncomp(like, ch) == 3;
            if (!with_normals || !name || strcmp(name, "normal") != 0 ||
                !(vn || d == GEOM_MESH_DOMAIN_CORNER))
                return 0;
        }
        if ((geom_mesh_face_cgroups(like) && geom_mesh_group_count(like)) ||
            geom_mesh_mtllib_count(like))
            return 0;
    }
    if (!no_tags(l, like))
        return 0;
    for (uint32_t v = 0; v < l->nv; v++)
        if (!geom__isfinite3(positions + 3 * (size_t)v))
            return 0;
    return 1;
}

geom_status geom_subdiv_mesh(const geom_mesh *m, const geom_subdiv_options *opt, int levels,
                             unsigned flags, geom_mesh **out, geom_subdiv_report *report,
                             geom_diag *diag)
{
    double t0 = geom__seconds();
    if (out)
        *out = NULL;
    if (report)
        memset(report, 0, sizeof *report);
    if (!m || !out || levels < 0 || levels > GEOM_SUBDIV_MAX_LEVEL)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_subdiv_mesh: invalid argument");
    geom_subdiv_refiner *r = NULL;
    geom_status st = geom_subdiv_refiner_create(m, opt, &r, diag);
    if (st != GEOM_OK)
        return st;
    st = geom_subdiv_refiner_refine(r, levels);
    if (st != GEOM_OK) {
        geom_subdiv_refiner_destroy(r);
        return st;
    }
    geom_allocator acopy = r->alloc;
    const geom_allocator *a = r->has_alloc ? &acopy : NULL;
    const sd_level *l0 = r->lv[0], *ll = r->lv[levels];
    double *pos = level0_data(a, m, l0, KIND_VERTEX, 0, 3), *lp = NULL;
    if (!pos) {
        geom_subdiv_refiner_destroy(r);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_subdiv_mesh: out of memory");
    }
    geom_aabb box = geom_aabb_empty();
    for (uint32_t v = 0; v < l0->nv; v++)
        if (l0->vf_off[v + 1] > l0->vf_off[v])
            box = geom_aabb_extend(box, geom_vec3_make(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]));
    st = refine_data(r, levels, KIND_VERTEX, 0, 3, pos, &pos);
    if (st != GEOM_OK) {
        geom_subdiv_refiner_destroy(r);
        return st;
    }
    size_t nv = ll->nv;
    lp = sd_calloc(a, 3 * nv, sizeof(double));
    if (!lp)
        st = GEOM_ERR_NOMEM;
    else
        st = geom_subdiv_limit(r, 3, pos, lp, NULL, NULL);
    double maxd = 0.0, sum = 0.0, sum1 = 0.0;
    size_t counted = 0;
    if (st == GEOM_OK) {
        for (size_t v = 0; v < nv; v++) {
            if (ll->vf_off[v + 1] == ll->vf_off[v])
                continue;
            double dx = pos[3 * v] - lp[3 * v], dy = pos[3 * v + 1] - lp[3 * v + 1],
                   dz = pos[3 * v + 2] - lp[3 * v + 2];
            double d = sqrt(dx * dx + dy * dy + dz * dz);
            if (d > maxd)
                maxd = d;
            sum += d * d;
            sum1 += d;
            counted++;
        }
    }
    geom_mesh *res = NULL;
    size_t holes = 0;
    double *nrm = NULL;
    int generic = r->o.scheme == GEOM_SUBDIV_BUTTERFLY || r->o.scheme == GEOM_SUBDIV_SQRT3;
    if (st == GEOM_OK && (flags & GEOM_SUBDIV_NORMALS) && !generic) {
        nrm = sd_calloc(a, 3 * nv, sizeof(double));
        st = nrm ? geom_subdiv_limit_normals(r, pos, nrm, NULL) : GEOM_ERR_NOMEM;
    }
    if (st == GEOM_OK && (flags & GEOM_SUBDIV_LIMIT))
        memcpy(pos, lp, 3 * nv * sizeof(double));
    if (st == GEOM_OK)
        st = geom_subdiv_build_mesh(r, levels, pos, nrm, m, &res, &holes, diag);
    if (st == GEOM_OK && (flags & GEOM_SUBDIV_NORMALS) && generic) {
        uint32_t id = geom_mesh_channel_find(res, "normal", GEOM_MESH_DOMAIN_CORNER);
        if (id != GEOM_INVALID_INDEX)
            st = geom_mesh_channel_remove(res, id);
        id = geom_mesh_channel_find(res, "normal", GEOM_MESH_DOMAIN_VERTEX);
        if (st == GEOM_OK && id == GEOM_INVALID_INDEX)
            st = geom_mesh_channel_add(res, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id);
        if (st == GEOM_OK)
            st = geom_mesh_vertex_normals(res, GEOM_NORMAL_WEIGHT_ANGLE,
                                          geom_mesh_channel_data(res, id), NULL);
    }
    sd_free(a, nrm, 3 * nv, sizeof(double));
    if (st == GEOM_OK && report) {
        report->levels = levels;
        report->vertices = geom_mesh_n_vertices(res);
        report->faces = geom_mesh_n_faces(res);
        report->input_faces = l0->nf;
        report->hole_faces = holes;
        report->fvar_channels = r->n_fvar_mesh;
        size_t dropped = 0, corner = 0;
        for (uint32_t ch = 0; ch < geom_mesh_channel_count(m); ch++) {
            geom_mesh_domain d = geom_mesh_channel_domain(m, ch);
            if (d == GEOM_MESH_DOMAIN_EDGE)
                dropped++;
            if (d == GEOM_MESH_DOMAIN_CORNER)
                corner++;
        }
        report->dropped_channels = dropped + (corner - r->n_fvar_mesh);
        report->max_limit_distance = (flags & GEOM_SUBDIV_LIMIT) ? 0.0 : maxd;
        report->rms_limit_distance =
            (flags & GEOM_SUBDIV_LIMIT) || counted == 0 ? 0.0 : sqrt(sum / (double)counted);
        report->bbox_diagonal =
            geom_aabb_is_empty(box) ? 0.0 : geom_vec3_length(geom_vec3_sub(box.max, box.min));
        report->level_max_limit_distance = maxd;
        report->level_rms_limit_distance = counted == 0 ? 0.0 : sqrt(sum / (double)counted);
        geom_error_report *e = &report->error;
        int on_limit = (flags & GEOM_SUBDIV_LIMIT) != 0;
        e->max_error = report->max_limit_distance;
        e->mean_error = on_limit || counted == 0 ? 0.0 : sum1 / (double)counted;
        e->method = on_limit ? GEOM_ERROR_BOUND : GEOM_ERROR_SAMPLED;
        e->evaluations = e->pieces = counted;
        e->seconds = geom__seconds() - t0;
    }
    sd_free(a, pos, 3 * nv, sizeof(double));
    sd_free(a, lp, 3 * nv, sizeof(double));
    geom_subdiv_refiner_destroy(r);
    if (st != GEOM_OK) {
        geom_mesh_destroy(res);
        return st;
    }
    *out = res;
    return GEOM_OK;
}
