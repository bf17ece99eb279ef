/*
 * Polygon soup -> manifold, consistently oriented half-edge mesh, with
 * repairs. Linear time apart from union-find (inverse Ackermann):
 *
 *  1. validate faces (out-of-range / repeated indices, < 3 vertices) with a
 *     per-vertex stamp;
 *  2. group the corners' undirected edges (min, max) by two stable counting
 *     sorts (by max, then by min): O(corners + vertices), no per-vertex
 *     search, so high valence costs nothing extra;
 *  3. orient: breadth-first over faces across edges used by exactly two faces
 *     (each connected set follows its first face); a conflict marks the
 *     component non-orientable;
 *  4. pair the uses of each undirected edge: two uses glue when their
 *     oriented directions are opposite. An edge used twice the same way (a
 *     non-orientable cut, or keep_orientation) glues nothing, and the face
 *     with more such edges (the later one on a tie) is reported detached;
 *     an edge used
 *     more than twice glues its first compatible pair ("kept"), then further
 *     compatible pairs among the rest, whose faces are reported detached
 *     (they end up on their own copies of the edge's vertices);
 *  5. one edge per pair or unpaired use; face cycles in oriented order;
 *  6. vertex fans: corners at a vertex linked through glued edges form
 *     paths or cycles (each edge use is glued at most once). Union-find over
 *     outgoing halfedges gives the fans; the fan holding the lowest halfedge
 *     keeps the input vertex index, each other fan gets a new vertex (copy of
 *     the input vertex's position, vertex_origin recording it). This splits
 *     non-manifold vertices and completes every detachment;
 *  7. boundary halfedges: each output vertex has at most one fan, hence at
 *     most one boundary gap, so next(b) = the boundary outgoing halfedge of
 *     b's target.
 * The result always satisfies every invariant geom_mesh_validate checks.
 *
 * Input errors (invalid faces without skip_invalid_faces, non-finite
 * coordinates, NULL arrays) are found before m is touched, so m keeps its
 * contents; running out of memory later leaves m empty.
 *
 * Report conventions: split_vertices counts the input vertices that
 * received more than one output vertex for any reason (so it includes the
 * endpoints of detached edges); added_vertices the copies made.
 */
#include "mesh/mesh_internal.h"

#include <stdio.h>

#define INV GEOM_INVALID_INDEX

typedef struct bscratch {
    const geom_allocator *a;
    void *p[24];
    size_t sz[24];
    int n;
} bscratch;

static void *bs_alloc(bscratch *s, size_t n, size_t es)
{
    size_t b;
    if (geom_size_mul(n ? n : 1, es, &b) != GEOM_OK)
        return NULL;
    void *p = geom_alloc(s->a, b);
    if (p) {
        s->p[s->n] = p;
        s->sz[s->n] = b;
        s->n++;
    }
    return p;
}

static void bs_free_all(bscratch *s)
{
    while (s->n > 0) {
        s->n--;
        geom_free(s->a, s->p[s->n], s->sz[s->n]);
    }
}

static void report_add(size_t *count, uint32_t *first, uint32_t idx)
{
    if (*count < GEOM_MESH_REPORT_FIRST)
        first[*count] = idx;
    (*count)++;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

enum { FL_DETACHED = 1, FL_NONMANIFOLD = 2 };

geom_status geom_mesh_build(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                            const uint32_t *face_sizes, const uint32_t *indices,
                            const geom_mesh_build_options *opt, geom_mesh_build_report *report,
                            geom_diag *diag)
{
    geom_mesh_build_report rep_local;
    geom_mesh_build_report *rep = report ? report : &rep_local;
    memset(rep, 0, sizeof *rep);
    if (!m || (nverts && !xyz) || (nfaces && !face_sizes))
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_mesh_build: NULL argument");
    if (nverts >= (size_t)UINT32_MAX || nfaces >= (size_t)UINT32_MAX)
        return geom_diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                             "geom_mesh_build: more than 2^32-2 vertices or faces");
    int skip = opt && opt->skip_invalid_faces;
    int keep = opt && opt->keep_orientation;

    for (size_t i = 0; i < nverts; ++i)
        if (!geom_isfinite3(xyz + 3 * i))
            return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_mesh_build: vertex %zu has a non-finite coordinate", i);

    bscratch S;
    memset(&S, 0, sizeof S);
    S.a = &m->alloc;
    geom_status st = GEOM_OK;

    /* ---- 1. validate faces */
    uint32_t *stamp = bs_alloc(&S, nverts, sizeof(uint32_t));
    uint8_t *face_ok = bs_alloc(&S, nfaces, 1);
    if (!stamp || !face_ok) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    for (size_t i = 0; i < nverts; ++i)
        stamp[i] = INV;
    size_t F = 0, C = 0, off = 0;
    for (size_t f = 0; f < nfaces; ++f) {
        size_t n = face_sizes[f];
        const char *why = NULL;
        if (n > 0 && !indices)
            why = "NULL indices";
        else if (n < 3)
            why = "fewer than 3 vertices";
        else
            for (size_t k = 0; k < n; ++k) {
                uint32_t v = indices[off + k];
                if ((size_t)v >= nverts) {
                    why = "vertex index out of range";
                    break;
                }
                if (stamp[v] == (uint32_t)f) {
                    why = "repeated vertex";
                    break;
                }
                stamp[v] = (uint32_t)f;
            }
        face_ok[f] = why == NULL;
        if (why) {
            if (!skip) {
                st = geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                   "geom_mesh_build: face %zu: %s", f, why);
                goto out;
            }
            report_add(&rep->invalid_faces, rep->first_invalid_faces, (uint32_t)f);
        } else {
            F++;
            C += n;
        }
        off += n;
    }
    if (C > (size_t)INT32_MAX - 2) {
        st = geom_diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                           "geom_mesh_build: more than 2^31 face corners");
        goto out;
    }

    /* ---- compact valid faces: corner vertex cv, next vertex cb, face cf */
    uint32_t *fs = bs_alloc(&S, F + 1, sizeof(uint32_t));
    uint32_t *forig = bs_alloc(&S, F, sizeof(uint32_t));
    uint32_t *cv = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *cb = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *cf = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *order = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *tmp = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *partner = bs_alloc(&S, C, sizeof(uint32_t));
    uint8_t *flip = bs_alloc(&S, F, 1);
    uint8_t *fflag = bs_alloc(&S, F, 1);
    uint32_t *cnt = bs_alloc(&S, nverts + 1, sizeof(uint32_t));
    if (!fs || !forig || !cv || !cb || !cf || !order || !tmp || !partner || !flip || !fflag ||
        !cnt) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    {
        size_t fo = 0, c = 0;
        off = 0;
        for (size_t f = 0; f < nfaces; ++f) {
            size_t n = face_sizes[f];
            if (face_ok[f]) {
                fs[fo] = (uint32_t)c;
                forig[fo] = (uint32_t)f;
                for (size_t k = 0; k < n; ++k) {
                    cv[c + k] = indices[off + k];
                    cb[c + k] = indices[off + (k + 1 < n ? k + 1 : 0)];
                    cf[c + k] = (uint32_t)fo;
                }
                c += n;
                fo++;
            }
            off += n;
        }
        fs[F] = (uint32_t)C;
    }
    memset(fflag, 0, F ? F : 1);

    /* ---- 2. sort corners by undirected edge (lo, hi): counting sorts */
#define LO(c) (cv[c] < cb[c] ? cv[c] : cb[c])
#define HI(c) (cv[c] < cb[c] ? cb[c] : cv[c])
    {
        memset(cnt, 0, (nverts + 1) * sizeof(uint32_t));
        for (size_t c = 0; c < C; ++c)
            cnt[HI(c) + 1]++;
        for (size_t v = 0; v < nverts; ++v)
            cnt[v + 1] += cnt[v];
        for (size_t c = 0; c < C; ++c)
            tmp[cnt[HI(c)]++] = (uint32_t)c;
        memset(cnt, 0, (nverts + 1) * sizeof(uint32_t));
        for (size_t c = 0; c < C; ++c)
            cnt[LO(c) + 1]++;
        for (size_t v = 0; v < nverts; ++v)
            cnt[v + 1] += cnt[v];
        for (size_t i = 0; i < C; ++i) {
            uint32_t c = tmp[i];
            order[cnt[LO(c)]++] = c;
        }
    }
    for (size_t c = 0; c < C; ++c)
        partner[c] = INV;
    for (size_t i = 0; i < C;) {
        size_t j = i + 1;
        uint32_t lo = LO(order[i]), hi = HI(order[i]);
        while (j < C && LO(order[j]) == lo && HI(order[j]) == hi)
            ++j;
        if (j - i == 2) {
            partner[order[i]] = order[i + 1];
            partner[order[i + 1]] = order[i];
        }
        i = j;
    }

    /* ---- 3. orientation by BFS across two-face edges */
    memset(flip, 0, F ? F : 1);
    if (!keep && F) {
        uint8_t *seen = bs_alloc(&S, F, 1);
        uint32_t *queue = tmp; /* tmp is free again; F <= C */
        if (!seen) {
            st = GEOM_ERR_NOMEM;
            goto out;
        }
        memset(seen, 0, F);
        for (size_t f0 = 0; f0 < F; ++f0) {
            if (seen[f0])
                continue;
            size_t qh = 0, qt = 0;
            int conflict = 0;
            seen[f0] = 1;
            queue[qt++] = (uint32_t)f0;
            while (qh < qt) {
                uint32_t f = queue[qh++];
                for (uint32_t c = fs[f]; c < fs[f + 1]; ++c) {
                    uint32_t p = partner[c];
                    if (p == INV)
                        continue;
                    uint32_t g = cf[p];
                    /* same input direction -> g must be flipped relative to f */
                    uint8_t same = (cv[c] == cv[p]);
                    uint8_t want = (uint8_t)(flip[f] ^ same);
                    if (!seen[g]) {
                        seen[g] = 1;
                        flip[g] = want;
                        queue[qt++] = g;
                    } else if (flip[g] != want)
                        conflict = 1;
                }
            }
            if (conflict)
                rep->nonorientable_components++;
        }
    }

    /* ---- 4. pair edge uses by oriented direction */
#define ODIR(c) ((uint8_t)((cv[c] > cb[c]) ^ flip[cf[c]]))
    /* conflicts per face (two-face edges used twice the same way), to
     * detach the face with more of them rather than its neighbour */
    uint32_t *nconf = bs_alloc(&S, F, sizeof(uint32_t));
    if (!nconf) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    memset(nconf, 0, (F ? F : 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c) {
        uint32_t p = partner[c];
        if (p != INV && ODIR(c) == ODIR(p))
            nconf[cf[c]]++;
    }
    for (size_t c = 0; c < C; ++c)
        partner[c] = INV;
    for (size_t i = 0; i < C;) {
        size_t j = i + 1;
        uint32_t lo = LO(order[i]), hi = HI(order[i]);
        while (j < C && LO(order[j]) == lo && HI(order[j]) == hi)
            ++j;
        size_t k = j - i;
        if (k == 2) {
            uint32_t c0 = order[i], c1 = order[i + 1];
            if (ODIR(c0) != ODIR(c1)) {
                partner[c0] = c1;
                partner[c1] = c0;
            } else {
                /* twice the same way: cut (non-orientable, or kept orientation) */
                rep->nonmanifold_edges++;
                uint32_t f0 = cf[c0], f1 = cf[c1];
                fflag[f0] |= FL_NONMANIFOLD;
                fflag[f1] |= FL_NONMANIFOLD;
                fflag[nconf[f0] > nconf[f1] ? f0 : f1] |= FL_DETACHED;
            }
        } else if (k > 2) {
            rep->nonmanifold_edges++;
            /* pair the a-th use of direction 0 with the a-th use of direction 1 */
            size_t ia = i, ib = i;
            int first = 1;
            for (;;) {
                while (ia < j && ODIR(order[ia]) != 0)
                    ++ia;
                while (ib < j && ODIR(order[ib]) != 1)
                    ++ib;
                if (ia >= j || ib >= j)
                    break;
                uint32_t ca = order[ia], cbb = order[ib];
                partner[ca] = cbb;
                partner[cbb] = ca;
                if (first) {
                    first = 0;
                    /* mark the kept pair so the loop below skips them */
                    fflag[cf[ca]] |= 0x80;
                    fflag[cf[cbb]] |= 0x80;
                }
                ++ia;
                ++ib;
            }
            /* every face of the run other than the kept pair is detached; with
             * no pair at all, the first use keeps the edge */
            uint32_t keep_c = first ? order[i] : INV;
            for (size_t r = i; r < j; ++r) {
                uint32_t c = order[r], f = cf[c];
                fflag[f] |= FL_NONMANIFOLD;
                if (fflag[f] & 0x80)
                    continue;
                if (c != keep_c)
                    fflag[f] |= FL_DETACHED;
            }
            for (size_t r = i; r < j; ++r)
                fflag[cf[order[r]]] &= (uint8_t)~0x80u;
        }
        i = j;
    }
#undef ODIR
#undef LO
#undef HI

    /* ---- 5. edges and face cycles */
    uint32_t *he_of = order; /* order is no longer needed */
    size_t E = 0;
    for (size_t c = 0; c < C; ++c)
        he_of[c] = INV;
    for (size_t c = 0; c < C; ++c) {
        if (he_of[c] != INV)
            continue;
        he_of[c] = (uint32_t)(2 * E);
        if (partner[c] != INV)
            he_of[partner[c]] = (uint32_t)(2 * E + 1);
        E++;
    }
    size_t H = 2 * E;

    geom_mesh__clear_all(m);
    if ((st = geom_mesh__resize(m, nverts, H, F)) != GEOM_OK ||
        (st = geom_mesh__ensure_origins(m)) != GEOM_OK)
        goto fail_mesh;
    for (size_t f = 0; f < F; ++f) {
        uint32_t s = fs[f], e = fs[f + 1];
        m->face_origin[f] = forig[f];
        m->face_flipped[f] = flip[f];
        if (!flip[f]) {
            for (uint32_t c = s; c < e; ++c) {
                uint32_t h = he_of[c], cn = c + 1 < e ? c + 1 : s;
                m->he_vertex[h] = cb[c];
                m->he_face[h] = (uint32_t)f;
                geom_mesh__link(m, h, he_of[cn]);
            }
            m->f_he[f] = he_of[e - 1];
        } else {
            for (uint32_t c = s; c < e; ++c) {
                uint32_t h = he_of[c], cp = c > s ? c - 1 : e - 1;
                m->he_vertex[h] = cv[c];
                m->he_face[h] = (uint32_t)f;
                geom_mesh__link(m, h, he_of[cp]);
            }
            m->f_he[f] = he_of[s];
        }
    }

    /* ---- 6. vertex fans (union-find over interior outgoing halfedges) */
    uint32_t *par = bs_alloc(&S, H, sizeof(uint32_t));
    uint8_t *vsplit = bs_alloc(&S, nverts, 1);
    if (!par || !vsplit) {
        st = GEOM_ERR_NOMEM;
        goto fail_mesh;
    }
    memset(vsplit, 0, nverts ? nverts : 1);
    for (size_t h = 0; h < H; ++h)
        par[h] = (uint32_t)h;
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t g = m->he_prev[h] ^ 1u; /* ccw neighbour around from(h) */
        if (m->he_face[g] != INV)
            uf_union(par, (uint32_t)h, g);
    }
    for (size_t h = 0; h < H; ++h)
        if (m->he_face[h] != INV)
            par[h] = uf_find(par, (uint32_t)h);
    /* roots are the smallest members: assign output vertices in place */
    uint32_t *new_orig = tmp; /* added vertices <= fans <= C */
    size_t added = 0;
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t r = par[h];
        if (r == h) {
            uint32_t v = m->he_vertex[m->he_prev[h]]; /* input vertex h leaves */
            if (m->v_he[v] == INV && !vsplit[v]) {
                vsplit[v] = 1; /* 1: taken by its first fan */
                par[h] = v;
            } else {
                if (nverts + added >= (size_t)UINT32_MAX - 1) {
                    st = GEOM_ERR_LIMIT;
                    goto fail_mesh;
                }
                vsplit[v] = 2; /* several fans */
                new_orig[added] = v;
                par[h] = (uint32_t)(nverts + added);
                added++;
            }
        } else
            par[h] = par[r];
    }
    if ((st = geom_mesh__resize(m, nverts + added, H, F)) != GEOM_OK)
        goto fail_mesh;
    {
        double *pos = geom_mesh__pos(m);
        if (nverts)
            memcpy(pos, xyz, 3 * nverts * sizeof(double));
        for (size_t v = 0; v < nverts; ++v)
            m->vertex_origin[v] = (uint32_t)v;
        for (size_t i = 0; i < added; ++i) {
            uint32_t o = new_orig[i];
            m->vertex_origin[nverts + i] = o;
            memcpy(pos + 3 * (nverts + i), xyz + 3 * (size_t)o, 3 * sizeof(double));
        }
    }
    /* targets: every interior halfedge is prev of one interior halfedge,
     * every boundary halfedge is opposite of one */
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t x = par[h];
        m->he_vertex[m->he_prev[h]] = x;
        if (m->he_face[h ^ 1u] == INV)
            m->he_vertex[h ^ 1u] = x;
        if (m->v_he[x] == INV)
            m->v_he[x] = (uint32_t)h;
    }

    /* ---- 7. boundary cycles */
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        m->v_he[m->he_vertex[b ^ 1u]] = (uint32_t)b;
    }
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        geom_mesh__link(m, (uint32_t)b, m->v_he[m->he_vertex[b]]);
    }

    /* ---- report */
    rep->added_vertices = added;
    size_t n_nmf = 0;
    for (size_t v = 0; v < nverts; ++v) {
        if (vsplit[v] == 2)
            report_add(&rep->split_vertices, rep->first_split_vertices, (uint32_t)v);
        if (vsplit[v] == 0)
            rep->isolated_vertices++;
    }
    for (size_t f = 0; f < F; ++f) {
        if (flip[f])
            report_add(&rep->flipped_faces, rep->first_flipped_faces, forig[f]);
        if (fflag[f] & FL_DETACHED)
            report_add(&rep->detached_faces, rep->first_detached_faces, forig[f]);
        if ((fflag[f] & FL_NONMANIFOLD) && n_nmf < GEOM_MESH_REPORT_FIRST)
            rep->first_nonmanifold_faces[n_nmf++] = forig[f];
    }
    goto out;

fail_mesh:
    geom_mesh__clear_all(m);
out:
    bs_free_all(&S);
    return st;
}
