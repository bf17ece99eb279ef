/* meshio export view: the mesh as output vertices (one per distinct corner
 * attribute combination at a vertex) and faces over them, for the formats
 * that store attributes per vertex (OFF, PLY, glTF). */
#include "meshio/meshio_internal.h"

static const char *const attr_names[MIO_NATTR] = {"normal", "uv", "color", "tangent"};
static const unsigned attr_bits[MIO_NATTR] = {GEOM_MESHIO_ATTR_NORMAL, GEOM_MESHIO_ATTR_UV,
                                              GEOM_MESHIO_ATTR_COLOR, GEOM_MESHIO_ATTR_TANGENT};

uint32_t geom__meshio_attr_channel(const geom_mesh *m, int which, unsigned omit)
{
    if (which < 0 || which >= MIO_NATTR || (omit & attr_bits[which]))
        return GEOM_INVALID_INDEX;
    uint32_t id = geom_mesh_channel_find(m, attr_names[which], GEOM_MESH_DOMAIN_CORNER);
    if (id == GEOM_INVALID_INDEX)
        id = geom_mesh_channel_find(m, attr_names[which], GEOM_MESH_DOMAIN_VERTEX);
    return id;
}

void geom__meshio_attr_channels(const geom_mesh *m, unsigned omit, int tangents,
                                uint32_t chan[MIO_NATTR])
{
    static const size_t min_ncomp[MIO_NATTR] = {3, 2, 3, 3}; /* normal, uv, color, tangent */
    for (int a = 0; a < MIO_NATTR; a++) {
        chan[a] = a == MIO_ATTR_TANGENT && !tangents ? GEOM_INVALID_INDEX
                                                     : geom__meshio_attr_channel(m, a, omit);
        if (chan[a] != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, chan[a]) < min_ncomp[a])
            chan[a] = GEOM_INVALID_INDEX;
    }
}

geom_status geom__meshio_check_finite(const geom_mesh *m, mio_sink *k)
{
    const double *p = geom_mesh_cpositions(m);
    size_t nv = geom_mesh_n_vertices(m);
    for (size_t v = 0; v < nv; v++)
        if (!geom_mesh_vertex_is_deleted(m, (uint32_t)v) && !geom__isfinite3(p + 3 * v))
            return geom__meshio_sink_fail(k, GEOM_ERR_INVALID_ARG,
                                          "vertex %zu has a non-finite coordinate", v);
    return GEOM_OK;
}

geom_status geom__meshio_vertex_map(const geom_mesh *m, const geom_allocator *a,
                                    uint32_t **map, size_t *n_live)
{
    size_t nv = geom_mesh_n_vertices(m);
    size_t bytes;
    if (geom__size_mul(nv, sizeof(uint32_t), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    uint32_t *mp = geom__alloc(a, bytes);
    if (!mp)
        return GEOM_ERR_NOMEM;
    size_t k = 0;
    for (size_t v = 0; v < nv; v++)
        mp[v] = geom_mesh_vertex_is_deleted(m, (uint32_t)v) ? GEOM_INVALID_INDEX
                                                             : (uint32_t)k++;
    *map = mp;
    *n_live = k;
    return GEOM_OK;
}

void geom__meshio_export_free(mio_export *e)
{
    const geom_allocator *a = e->alloc;
    geom__free(a, e->vert, e->cap_v * sizeof(uint32_t));
    for (int i = 0; i < MIO_NATTR; i++)
        geom__free(a, e->aidx[i], e->cap_v * sizeof(uint32_t));
    geom__free(a, e->fsize, e->nf * sizeof(uint32_t));
    geom__free(a, e->fface, e->nf * sizeof(uint32_t));
    geom__free(a, e->fidx, e->nidx * sizeof(uint32_t));
    memset(e, 0, sizeof *e);
}

/* Grow the per-output-vertex arrays to hold n entries, each through
 * geom__grow to the same capacity. */
static geom_status grow_out(mio_export *e, size_t n)
{
    if (n <= e->cap_v)
        return GEOM_OK;
    uint32_t **arr[1 + MIO_NATTR] = {&e->vert};
    size_t cap[1 + MIO_NATTR];
    geom_status st = GEOM_OK;
    for (int i = 0; i <= MIO_NATTR; i++) {
        if (i)
            arr[i] = &e->aidx[i - 1];
        cap[i] = e->cap_v;
        if (st == GEOM_OK) /* the others to the capacity the first got */
            st = geom__grow(e->alloc, (void **)arr[i], &cap[i], i ? cap[0] : n,
                            sizeof(uint32_t));
    }
    if (st == GEOM_OK) {
        e->cap_v = cap[0];
        return GEOM_OK;
    }
    /* their sizes now differ: free them all, so export_free has none */
    for (int i = 0; i <= MIO_NATTR; i++) {
        geom__free(e->alloc, *arr[i], cap[i] * sizeof(uint32_t));
        *arr[i] = NULL;
    }
    e->cap_v = 0;
    return st;
}

/* State of one export_build while the corners are visited. */
typedef struct exp_walk {
    mio_export *e;
    const geom_mesh *m;
    const uint32_t *cidx[MIO_NATTR];
    const uint32_t *vmap;
    uint8_t *primary_set;
    geom__hindex hash;
    int ncorner;
} exp_walk;

/* The output vertex of the corner at halfedge h (its target vertex with
 * h's corner attributes): the vertex's own when its first tuple matches or
 * it has none yet, else one per distinct tuple. */
static geom_status export_corner(exp_walk *w, uint32_t h, uint32_t *outp)
{
    mio_export *e = w->e;
    uint32_t v = geom_mesh_he_vertex(w->m, h);
    uint32_t out = w->vmap[v];
    *outp = out;
    if (!w->ncorner)
        return GEOM_OK;
    uint32_t key[MIO_NATTR];
    for (int a = 0; a < MIO_NATTR; a++)
        key[a] = w->cidx[a] ? w->cidx[a][h] : e->aidx[a][out];
    if (!w->primary_set[v]) {
        w->primary_set[v] = 1;
        for (int a = 0; a < MIO_NATTR; a++)
            e->aidx[a][out] = key[a];
        return GEOM_OK;
    }
    int same = 1;
    for (int a = 0; a < MIO_NATTR; a++)
        same &= e->aidx[a][out] == key[a];
    if (same)
        return GEOM_OK;
    uint64_t hv = geom__hash_mix(0, v);
    for (int a = 0; a < MIO_NATTR; a++)
        hv = geom__hash_mix(hv, key[a]);
    size_t it = 0;
    uint32_t cand;
    while ((cand = geom__hindex_next(&w->hash, hv, &it)) != UINT32_MAX) {
        int eq = e->vert[cand] == v;
        for (int a = 0; a < MIO_NATTR && eq; a++)
            eq = e->aidx[a][cand] == key[a];
        if (eq) {
            *outp = cand;
            return GEOM_OK;
        }
    }
    if (e->nv >= UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    geom_status st = grow_out(e, e->nv + 1);
    if (st == GEOM_OK)
        st = geom__hindex_reserve(&w->hash, e->alloc, w->hash.n + 1);
    if (st != GEOM_OK)
        return st;
    /* the table may have been rebuilt: find the slot again */
    it = 0;
    while (geom__hindex_next(&w->hash, hv, &it) != UINT32_MAX) {
    }
    out = (uint32_t)e->nv++;
    e->vert[out] = v;
    for (int a = 0; a < MIO_NATTR; a++)
        e->aidx[a][out] = key[a];
    geom__hindex_insert_at(&w->hash, hv, it, out);
    *outp = out;
    return GEOM_OK;
}

/* Polygons as geom_mesh_triangulate makes them triangles, one face at a
 * time: pass 0 writes every triangle and the first triangle of each
 * polygon (in the face's place), pass 1 the polygons' other triangles
 * (after the last face), each starting where the triangulated face's
 * cycle would. */
static geom_status export_triangles(exp_walk *w, size_t nmax, size_t *fi, size_t *ii)
{
    mio_export *e = w->e;
    const geom_mesh *m = w->m;
    const geom_allocator *al = e->alloc;
    size_t nf = geom_mesh_n_faces(m);
    const double *pos = geom_mesh_cpositions(m);
    double *pts = geom__alloc(al, 3 * nmax * sizeof(double));
    uint32_t *ub = geom__alloc(al, 4 * nmax * sizeof(uint32_t));
    geom_status st = pts && ub ? GEOM_OK : GEOM_ERR_NOMEM;
    uint32_t *tris = ub, *hk = ub ? ub + 3 * nmax : NULL; /* no offset on NULL (UB) */
    for (int pass = 0; pass < 2 && st == GEOM_OK; pass++)
        for (size_t f = 0; f < nf && st == GEOM_OK; f++) {
            if (geom_mesh_face_is_deleted(m, (uint32_t)f))
                continue;
            size_t n = geom_mesh_face_valence(m, (uint32_t)f);
            if (n == 3 && pass)
                continue;
            uint32_t h = geom_mesh_face_he(m, (uint32_t)f);
            for (size_t c = 0; c < n; c++, h = geom_mesh_he_next(m, h)) {
                hk[c] = h;
                memcpy(pts + 3 * c, pos + 3 * (size_t)geom_mesh_he_vertex(m, h),
                       3 * sizeof(double));
            }
            if (n == 3) {
                /* the face itself: its cycle from f_he */
                tris[0] = 2, tris[1] = 0, tris[2] = 1;
            } else
                (void)geom_polygon_triangulate(n, pts, tris); /* degenerate: a fan */
            for (size_t t = pass ? 1 : 0; t < (pass ? n - 2 : 1) && st == GEOM_OK; t++) {
                for (int i = 0; i < 3 && st == GEOM_OK; i++)
                    st = export_corner(w, hk[tris[3 * t + (size_t)((i + 1) % 3)]], &e->fidx[(*ii)++]);
                e->fsize[*fi] = 3;
                e->fface[*fi] = (uint32_t)f;
                (*fi)++;
            }
        }
    geom__free(al, pts, 3 * nmax * sizeof(double));
    geom__free(al, ub, 4 * nmax * sizeof(uint32_t));
    return st;
}

geom_status geom__meshio_export_build(mio_export *e, const geom_mesh *m,
                                      const uint32_t chan[MIO_NATTR],
                                      const geom_allocator *alloc, int triangulate)
{
    memset(e, 0, sizeof *e);
    e->alloc = alloc;
    e->fcol = GEOM_INVALID_INDEX;
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    exp_walk w;
    memset(&w, 0, sizeof w);
    w.e = e;
    w.m = m;
    for (int a = 0; a < MIO_NATTR; a++) {
        e->chan[a] = chan[a];
        if (chan[a] != GEOM_INVALID_INDEX &&
            geom_mesh_channel_domain(m, chan[a]) == GEOM_MESH_DOMAIN_CORNER) {
            w.cidx[a] = geom_mesh_corner_cindices(m, chan[a]);
            w.ncorner += w.cidx[a] != NULL;
        }
    }
    uint32_t *vmap = NULL;
    size_t nlive = 0;
    geom_status st = geom__meshio_vertex_map(m, alloc, &vmap, &nlive);
    if (st != GEOM_OK)
        return st;
    w.vmap = vmap;
    if (nlive > UINT32_MAX - 1) {
        geom__free(alloc, vmap, nv * sizeof(uint32_t));
        return GEOM_ERR_LIMIT;
    }
    /* live faces (triangles when triangulating) and their sizes */
    size_t nlf = 0, nidx = 0, nmax = 3;
    for (size_t f = 0; f < nf; f++) {
        if (geom_mesh_face_is_deleted(m, (uint32_t)f))
            continue;
        size_t n = geom_mesh_face_valence(m, (uint32_t)f);
        nmax = n > nmax ? n : nmax;
        nlf += triangulate ? n - 2 : 1;
        nidx += triangulate ? 3 * (n - 2) : n;
    }
    e->nf = nlf;
    e->nidx = nidx;
    e->fsize = geom__alloc(alloc, nlf * sizeof(uint32_t));
    e->fface = geom__alloc(alloc, nlf * sizeof(uint32_t));
    e->fidx = geom__alloc(alloc, nidx * sizeof(uint32_t));
    st = (e->fsize && e->fface && e->fidx) ? grow_out(e, nlive) : GEOM_ERR_NOMEM;
    if (st == GEOM_OK) {
        /* the first nlive outputs are the live vertices; their attribute
         * tuple is set by the first corner seen (or stays unset) */
        for (size_t v = 0; v < nv; v++) {
            uint32_t o = vmap[v];
            if (o == GEOM_INVALID_INDEX)
                continue;
            e->vert[o] = (uint32_t)v;
            for (int a = 0; a < MIO_NATTR; a++)
                e->aidx[a][o] = chan[a] == GEOM_INVALID_INDEX ? GEOM_INVALID_INDEX
                                : w.cidx[a]                   ? GEOM_INVALID_INDEX
                                                              : (uint32_t)v;
        }
        e->nv = nlive;
        if (w.ncorner) {
            w.primary_set = geom__alloc(alloc, nv ? nv : 1);
            if (!w.primary_set)
                st = GEOM_ERR_NOMEM;
            else
                memset(w.primary_set, 0, nv ? nv : 1);
        }
    }
    size_t fi = 0, ii = 0;
    if (st == GEOM_OK && triangulate) {
        st = export_triangles(&w, nmax, &fi, &ii);
        e->max_valence = nlf ? 3 : 0;
    }
    for (size_t f = 0; f < nf && st == GEOM_OK && !triangulate; f++) {
        if (geom_mesh_face_is_deleted(m, (uint32_t)f))
            continue;
        uint32_t h0 = geom_mesh_face_he(m, (uint32_t)f), h = h0;
        size_t cnt = 0;
        do {
            st = export_corner(&w, h, &e->fidx[ii]);
            if (st != GEOM_OK)
                break;
            ii++;
            cnt++;
            h = geom_mesh_he_next(m, h);
        } while (h != h0 && cnt < nidx);
        e->fsize[fi] = (uint32_t)cnt;
        e->fface[fi] = (uint32_t)f;
        if (cnt > e->max_valence)
            e->max_valence = cnt;
        fi++;
    }
    geom__free(alloc, w.primary_set, nv ? nv : 1);
    geom__hindex_free(&w.hash, alloc);
    geom__free(alloc, vmap, nv * sizeof(uint32_t));
    if (st != GEOM_OK)
        geom__meshio_export_free(e);
    return st;
}

geom_status geom__meshio_export_prepare(mio_export *e, const geom_mesh *m,
                                        const geom_meshio_write_options *opt, int tangents,
                                        mio_sink *k)
{
    uint32_t chan[MIO_NATTR];
    geom__meshio_attr_channels(m, opt->omit, tangents, chan);
    uint32_t fcol = (opt->omit & GEOM_MESHIO_ATTR_COLOR)
                        ? GEOM_INVALID_INDEX
                        : geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_FACE);
    if (fcol != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, fcol) < 3)
        fcol = GEOM_INVALID_INDEX;
    geom_status st = geom__meshio_export_build(e, m, chan, opt->alloc, 0);
    if (st != GEOM_OK)
        return geom__meshio_sink_fail(k, st, "%s while preparing the output",
                                      geom_status_str(st));
    e->fcol = fcol;
    return GEOM_OK;
}

size_t geom__meshio_export_face_color(const mio_export *e, const geom_mesh *m, size_t f,
                                      double rgba[4])
{
    if (e->fcol == GEOM_INVALID_INDEX)
        return 0;
    size_t nc = geom_mesh_channel_ncomp(m, e->fcol);
    const double *col = geom_mesh_channel_cdata(m, e->fcol) + (size_t)e->fface[f] * nc;
    for (size_t j = 0; j < 4; j++)
        rgba[j] = j < nc ? col[j] : 1.0;
    return nc;
}

size_t geom__meshio_export_value(const mio_export *e, const geom_mesh *m, int a, size_t k,
                                 double *out, size_t max)
{
    uint32_t id = e->chan[a];
    if (id == GEOM_INVALID_INDEX)
        return 0;
    size_t nc = geom_mesh_channel_ncomp(m, id);
    size_t n = nc < max ? nc : max;
    uint32_t ix = e->aidx[a][k];
    const double *d = geom_mesh_channel_cdata(m, id);
    if (ix == GEOM_INVALID_INDEX || ix >= geom_mesh_channel_size(m, id) || !d) {
        for (size_t i = 0; i < n; i++)
            out[i] = 0.0;
    } else {
        for (size_t i = 0; i < n; i++)
            out[i] = d[(size_t)ix * nc + i];
    }
    return nc;
}
