/*
 * Per-corner tangent frames compatible with MikkTSpace (M. S. Mikkelsen,
 * "Simulation of wrinkled surfaces revisited", MSc thesis, University of
 * Copenhagen 2008, and the conventions of its reference implementation as
 * used by Blender and glTF viewers). Written from the published description:
 *
 *  1. Faces are split into triangles: a quad along its shorter diagonal in
 *     UV space (ties: the shorter one in space, then 0-2), larger polygons
 *     into a fan from their first corner.
 *  2. A corner's identity is (vertex, normal value, uv value); triangles
 *     whose corners share an identity or a position are degenerate and take
 *     part in nothing.
 *  3. Per triangle: the UV-derivative tangent dP/du, normalised (from
 *     vOs = t31v*d1 - t21v*d2 times the sign of the UV area), and an
 *     orientation flag (UV area > 0). Triangles with (nearly) zero UV area
 *     have no tangent and join any group ("group with any"), taking its
 *     orientation. The two triangles of a quad are forced to one orientation
 *     (the one of the triangle with the larger UV area).
 *  4. Around each corner identity, triangles are grouped across edges whose
 *     two end identities match, when their orientations agree: mirrored UV
 *     seams get separate groups.
 *  5. A group's tangent is the sum over its triangles of the triangle tangent
 *     projected on the tangent plane of the corner normal and normalised,
 *     weighted by the corner angle measured between the projected edges;
 *     normalised and orthogonalised against the normal (Gram-Schmidt).
 *     w = +1 for an orientation-preserving group, -1 otherwise, so that
 *     bitangent = w * cross(normal, tangent).
 *  6. Corners of degenerate triangles copy the frame of another corner with
 *     the same identity; a corner left without any tangent (only degenerate
 *     UVs around it) gets a unit vector orthogonal to its normal (Duff et
 *     al. 2017's branchless basis) and w = +1.
 * Differences from the reference implementation: double precision, exact
 * comparisons of identities within one mesh vertex (two mesh vertices at the
 * same position are not welded), triangles with zero UV area contribute no
 * tangent (instead of an unnormalised one), and polygons above 4 sides are
 * fan-triangulated instead of being rejected.
 */
#include "mesh/mesh_internal.h"

#include <float.h>

#define INV GEOM_INVALID_INDEX

typedef struct tri_info {
    uint32_t c[3];  /* corner halfedges (each points to its vertex) */
    uint32_t nb[3]; /* neighbour triangle across edge c[i] -> c[i+1], or INV */
    double os[3];   /* unit tangent dP/du, or zero */
    uint32_t face;
    uint8_t orient; /* UV area > 0 */
    uint8_t any;    /* no usable UV tangent: groups with anything */
    uint8_t degen;  /* excluded */
    uint8_t quad_second; /* second triangle of a quad (its pair is t-1) */
    double uv_area; /* |UV area| * 2 */
} tri_info;

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/* v - (n.v) n, normalised (zero if that vanishes). n is unit or zero. */
static inline void project_unit(const double v[3], const double n[3], double out[3])
{
    double d = dot3(n, v);
    out[0] = v[0] - d * n[0];
    out[1] = v[1] - d * n[1];
    out[2] = v[2] - d * n[2];
    geom__mesh_normalize3(out);
}

/* A unit vector orthogonal to unit n (Duff et al., "Building an orthonormal
 * basis, revisited", JCGT 2017); (1,0,0) for a zero n. */
static void basis_from_normal(const double n[3], double t[3])
{
    if (!(dot3(n, n) > 0.0)) {
        t[0] = 1.0;
        t[1] = t[2] = 0.0;
        return;
    }
    double s = n[2] >= 0.0 ? 1.0 : -1.0;
    double a = -1.0 / (s + n[2]);
    double b = n[0] * n[1] * a;
    t[0] = 1.0 + s * n[0] * n[0] * a;
    t[1] = s * b;
    t[2] = -s * n[0];
    geom__mesh_normalize3(t);
}

typedef struct tan_ctx {
    const geom_mesh *m;
    const double *pos;
    const double *uvd;     /* uv pool (ncomp uvc) */
    const uint32_t *uvi;   /* uv corner indices */
    size_t uvc, uvn;       /* components, pool size */
    const double *nd;      /* normal pool (3) or NULL */
    const uint32_t *ni;
    size_t nn;             /* normal pool size */
    const double *fn;      /* per-face unit normals (fallback) */
} tan_ctx;

static void corner_uv(const tan_ctx *x, uint32_t h, double uv[2])
{
    uint32_t i = x->uvi[h];
    if (i == INV || i >= x->uvn) {
        uv[0] = uv[1] = 0.0;
        return;
    }
    uv[0] = x->uvd[(size_t)i * x->uvc];
    uv[1] = x->uvd[(size_t)i * x->uvc + 1];
}

static void corner_normal(const tan_ctx *x, uint32_t h, double n[3])
{
    uint32_t i = x->ni ? x->ni[h] : INV;
    if (i != INV && i < x->nn) {
        n[0] = x->nd[3 * (size_t)i];
        n[1] = x->nd[3 * (size_t)i + 1];
        n[2] = x->nd[3 * (size_t)i + 2];
    } else {
        uint32_t f = x->m->he_face[h];
        n[0] = x->fn[3 * (size_t)f];
        n[1] = x->fn[3 * (size_t)f + 1];
        n[2] = x->fn[3 * (size_t)f + 2];
    }
    geom__mesh_normalize3(n);
}

/* Squared distance of two UVs / two positions. */
static double d2uv(const double a[2], const double b[2])
{
    double du = a[0] - b[0], dv = a[1] - b[1];
    return du * du + dv * dv;
}
static double d2p(const double *a, const double *b)
{
    /* scaled to avoid overflow: only compared with each other */
    double s = 0.0;
    for (int k = 0; k < 3; k++) {
        double d = a[k] * 0.5 - b[k] * 0.5;
        s += d * d;
    }
    return s;
}

static void tri_setup(const tan_ctx *x, tri_info *t)
{
    const geom_mesh *m = x->m;
    const double *p[3];
    double uv[3][2];
    for (int i = 0; i < 3; i++) {
        p[i] = x->pos + 3 * (size_t)m->he_vertex[t->c[i]];
        corner_uv(x, t->c[i], uv[i]);
    }
    t->os[0] = t->os[1] = t->os[2] = 0.0;
    t->orient = 0;
    t->any = 1;
    t->uv_area = 0.0;
    t->degen = 0;
    for (int i = 0; i < 3; i++) {
        if (!geom__isfinite3(p[i]))
            t->degen = 1;
    }
    if (p[0][0] == p[1][0] && p[0][1] == p[1][1] && p[0][2] == p[1][2])
        t->degen = 1;
    if (p[1][0] == p[2][0] && p[1][1] == p[2][1] && p[1][2] == p[2][2])
        t->degen = 1;
    if (p[0][0] == p[2][0] && p[0][1] == p[2][1] && p[0][2] == p[2][2])
        t->degen = 1;
    if (t->degen)
        return;
    double t21u = uv[1][0] - uv[0][0], t21v = uv[1][1] - uv[0][1];
    double t31u = uv[2][0] - uv[0][0], t31v = uv[2][1] - uv[0][1];
    double area2 = t21u * t31v - t21v * t31u;
    t->orient = area2 > 0.0;
    double l2 = fmax(d2uv(uv[1], uv[0]), fmax(d2uv(uv[2], uv[0]), d2uv(uv[2], uv[1])));
    if (!isfinite(area2) || !(fabs(area2) > 2e-14 * l2))
        return; /* degenerate UVs: group with any, no tangent */
    t->uv_area = fabs(area2);
    double d1[3], d2[3];
    for (int k = 0; k < 3; k++) {
        d1[k] = p[1][k] - p[0][k];
        d2[k] = p[2][k] - p[0][k];
    }
    double s = area2 > 0.0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; k++)
        t->os[k] = s * (t31v * d1[k] - t21v * d2[k]);
    if (geom__mesh_normalize3(t->os))
        t->any = 0;
}

/* The working state of one geom_mesh_tangents call, phase by phase. */
typedef struct tan_work {
    geom_mesh *m;
    const geom_allocator *al;
    size_t nh, nf;
    tan_ctx x;
    double *fn;                  /* face normals, 3 per face */
    uint32_t *ident;             /* corner identity per halfedge */
    uint32_t *boff, *bucket;     /* corners by vertex (CSR) */
    size_t ntotal_corners;
    tri_info *tris;              /* the triangles */
    size_t ntri, tri_cap;
    uint32_t *tri_of_he;         /* triangle of each original polygon edge */
    uint32_t *ga, *stack;        /* group of each triangle corner; flood-fill stack */
    double *gsum;                /* group tangent sums */
    uint8_t *gorient;            /* group orientations */
    size_t ngroups, gcap, ocap;
    double *pool;                /* output frames (x, y, z, w) */
    size_t npool, pool_cap;
    uint32_t *corner_out;        /* pool index per halfedge */
} tan_work;

/* Phase 1: corner identities (vertex, normal value, uv value), and the
 * corners grouped by vertex. */
static geom_status tan_identities(tan_work *W)
{
    geom_mesh *m = W->m;
    const geom_allocator *al = W->al;
    const size_t nh = W->nh, nv = m->nv;
    uint32_t *ident = W->ident;
    W->boff = geom__alloc(al, (nv + 1) * sizeof(uint32_t));
    if (!W->boff)
        return GEOM_ERR_NOMEM;
    uint32_t *boff = W->boff;
    memset(boff, 0, (nv + 1) * sizeof(uint32_t));
    for (size_t h = 0; h < nh; h++) {
        if (m->he_face[h] != INV && !m->f_del[m->he_face[h]]) {
            boff[m->he_vertex[h] + 1]++;
            W->ntotal_corners++;
        }
    }
    for (size_t v = 0; v < nv; v++)
        boff[v + 1] += boff[v];
    W->bucket = geom__alloc(al, (W->ntotal_corners ? W->ntotal_corners : 1) * sizeof(uint32_t));
    uint32_t *fill = geom__alloc(al, (nv ? nv : 1) * sizeof(uint32_t));
    if (!W->bucket || !fill) {
        geom__free(al, fill, (nv ? nv : 1) * sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    uint32_t *bucket = W->bucket;
    memcpy(fill, boff, nv * sizeof(uint32_t));
    for (size_t h = 0; h < nh; h++) {
        if (m->he_face[h] != INV && !m->f_del[m->he_face[h]])
            bucket[fill[m->he_vertex[h]]++] = (uint32_t)h;
    }
    geom__free(al, fill, (nv ? nv : 1) * sizeof(uint32_t));
    uint32_t next_id = 0;
    for (size_t v = 0; v < nv; v++) {
        for (uint32_t i = boff[v]; i < boff[v + 1]; i++) {
            uint32_t h = bucket[i];
            double ui[2], ni[3];
            corner_uv(&W->x, h, ui);
            corner_normal(&W->x, h, ni);
            for (uint32_t j = boff[v]; j < i; j++) {
                uint32_t hj = bucket[j];
                double uj[2], nj[3];
                corner_uv(&W->x, hj, uj);
                corner_normal(&W->x, hj, nj);
                if (ui[0] == uj[0] && ui[1] == uj[1] && ni[0] == nj[0] && ni[1] == nj[1] &&
                    ni[2] == nj[2]) {
                    ident[h] = ident[hj];
                    break;
                }
            }
            if (ident[h] == INV)
                ident[h] = next_id++;
        }
    }
    return GEOM_OK;
}

/* Phase 2: split the faces into triangles (quads along the shorter UV
 * diagonal, larger polygons into fans), linking the triangles of a face. */
static geom_status tan_triangulate(tan_work *W)
{
    geom_mesh *m = W->m;
    const size_t nh = W->nh, nf = W->nf;
    const tan_ctx *xp = &W->x;
    for (size_t f = 0; f < nf; f++) {
        if (m->f_del[f])
            continue;
        uint32_t h0 = m->f_he[f];
        uint32_t cs[4];
        size_t k = 0;
        uint32_t h = h0;
        do {
            if (k < 4)
                cs[k] = h;
            k++;
            h = m->he_next[h];
        } while (h != h0 && k <= nh);
        size_t ntri = W->ntri;
        if (geom__grow(W->al, (void **)&W->tris, &W->tri_cap, ntri + (k - 2), sizeof(tri_info)) !=
            GEOM_OK)
            return GEOM_ERR_NOMEM;
        tri_info *t = W->tris + ntri;
        memset(t, 0, (k - 2) * sizeof(tri_info));
        for (size_t j = 0; j < k - 2; j++) {
            t[j].face = (uint32_t)f;
            t[j].nb[0] = t[j].nb[1] = t[j].nb[2] = INV;
        }
        if (k == 3) {
            t[0].c[0] = cs[0];
            t[0].c[1] = cs[1];
            t[0].c[2] = cs[2];
        } else if (k == 4) {
            double uv[4][2];
            for (int i = 0; i < 4; i++)
                corner_uv(xp, cs[i], uv[i]);
            double u02 = d2uv(uv[0], uv[2]), u13 = d2uv(uv[1], uv[3]);
            int diag02;
            if (u02 < u13)
                diag02 = 1;
            else if (u13 < u02)
                diag02 = 0;
            else {
                const double *p0 = xp->pos + 3 * (size_t)m->he_vertex[cs[0]];
                const double *p1 = xp->pos + 3 * (size_t)m->he_vertex[cs[1]];
                const double *p2 = xp->pos + 3 * (size_t)m->he_vertex[cs[2]];
                const double *p3 = xp->pos + 3 * (size_t)m->he_vertex[cs[3]];
                diag02 = !(d2p(p1, p3) < d2p(p0, p2));
            }
            if (diag02) {
                t[0].c[0] = cs[0], t[0].c[1] = cs[1], t[0].c[2] = cs[2];
                t[1].c[0] = cs[0], t[1].c[1] = cs[2], t[1].c[2] = cs[3];
                t[0].nb[2] = (uint32_t)(ntri + 1); /* c2 -> c0 */
                t[1].nb[0] = (uint32_t)ntri;       /* c0 -> c2 */
            } else {
                t[0].c[0] = cs[0], t[0].c[1] = cs[1], t[0].c[2] = cs[3];
                t[1].c[0] = cs[1], t[1].c[1] = cs[2], t[1].c[2] = cs[3];
                t[0].nb[1] = (uint32_t)(ntri + 1); /* c1 -> c3 */
                t[1].nb[2] = (uint32_t)ntri;       /* c3 -> c1 */
            }
            t[1].quad_second = 1;
        } else {
            /* fan from the first corner */
            uint32_t prev = m->he_next[h0], cur;
            for (size_t j = 0; j < k - 2; j++) {
                cur = m->he_next[prev];
                t[j].c[0] = h0;
                t[j].c[1] = prev;
                t[j].c[2] = cur;
                if (j > 0)
                    t[j].nb[0] = (uint32_t)(ntri + j - 1);
                if (j + 1 < k - 2)
                    t[j].nb[2] = (uint32_t)(ntri + j + 1);
                prev = cur;
            }
        }
        /* original polygon edges: the halfedge ending at c[i+1] when c[i]
         * precedes it in the face */
        for (size_t j = 0; j < k - 2; j++) {
            for (int i = 0; i < 3; i++) {
                uint32_t a = t[j].c[i], b = t[j].c[(i + 1) % 3];
                if (m->he_prev[b] == a)
                    W->tri_of_he[b] = (uint32_t)(ntri + j);
            }
        }
        W->ntri = ntri + (k - 2);
    }
    return GEOM_OK;
}

/* Phase 3: per-triangle tangents, degeneracy and orientation (one per
 * quad), and the neighbours across original edges whose end identities
 * match. */
static void tan_triangle_frames(tan_work *W)
{
    const geom_mesh *m = W->m;
    const uint32_t *ident = W->ident;
    tri_info *tris = W->tris;
    const size_t ntri = W->ntri;
    for (size_t t = 0; t < ntri; t++) {
        tri_info *ti = tris + t;
        tri_setup(&W->x, ti);
        if (ident[ti->c[0]] == ident[ti->c[1]] || ident[ti->c[1]] == ident[ti->c[2]] ||
            ident[ti->c[0]] == ident[ti->c[2]])
            ti->degen = 1;
    }
    /* one orientation per quad */
    for (size_t t = 1; t < ntri; t++) {
        tri_info *b = tris + t, *a = tris + t - 1;
        if (!b->quad_second || a->degen || b->degen || a->orient == b->orient)
            continue;
        int first;
        if (b->any)
            first = 1;
        else if (a->any)
            first = 0;
        else
            first = a->uv_area >= b->uv_area;
        if (first)
            b->orient = a->orient;
        else
            a->orient = b->orient;
    }
    /* neighbours across original edges: matching identities at both ends */
    for (size_t t = 0; t < ntri; t++) {
        tri_info *ti = tris + t;
        for (int i = 0; i < 3; i++) {
            uint32_t a = ti->c[i], b = ti->c[(i + 1) % 3];
            if (m->he_prev[b] != a)
                continue; /* a diagonal, linked above */
            uint32_t o = b ^ 1u;
            if (m->he_face[o] == INV || W->tri_of_he[o] == INV)
                continue;
            /* in the other face, o points to vertex(a) and prev(o) to vertex(b) */
            if (ident[o] == ident[a] && ident[m->he_prev[o]] == ident[b])
                ti->nb[i] = W->tri_of_he[o];
        }
    }
}

/* Phase 4: groups, by flood fill around each corner identity across linked
 * triangles of the same orientation. */
static geom_status tan_groups(tan_work *W)
{
    const geom_allocator *al = W->al;
    const uint32_t *ident = W->ident;
    tri_info *tris = W->tris;
    const size_t ntri = W->ntri;
    W->ga = geom__alloc(al, (ntri ? ntri : 1) * 3 * sizeof(uint32_t));
    W->stack = geom__alloc(al, (ntri ? ntri : 1) * 2 * sizeof(uint32_t) + 8);
    if (!W->ga || !W->stack)
        return GEOM_ERR_NOMEM;
    uint32_t *ga = W->ga, *stack = W->stack;
    for (size_t i = 0; i < 3 * ntri; i++)
        ga[i] = INV;
    for (size_t t = 0; t < ntri; t++) {
        if (tris[t].degen)
            continue;
        for (int i = 0; i < 3; i++) {
            if (ga[3 * t + i] != INV)
                continue;
            if (geom__grow(al, (void **)&W->gsum, &W->gcap, W->ngroups + 1, 3 * sizeof(double)) !=
                    GEOM_OK ||
                geom__grow(al, (void **)&W->gorient, &W->ocap, W->ngroups + 1, 1) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            uint32_t g = (uint32_t)W->ngroups++;
            uint32_t rep = ident[tris[t].c[i]];
            uint8_t *gorient = W->gorient;
            double *gsum = W->gsum;
            gorient[g] = tris[t].orient;
            gsum[3 * g] = gsum[3 * g + 1] = gsum[3 * g + 2] = 0.0;
            size_t sp = 0;
            stack[sp++] = (uint32_t)t;
            while (sp > 0) {
                uint32_t u = stack[--sp];
                tri_info *tu = tris + u;
                if (tu->degen)
                    continue;
                int j = -1;
                for (int q = 0; q < 3; q++) {
                    if (ident[tu->c[q]] == rep)
                        j = q;
                }
                if (j < 0 || ga[3 * (size_t)u + j] != INV)
                    continue;
                if (tu->any && ga[3 * (size_t)u] == INV && ga[3 * (size_t)u + 1] == INV &&
                    ga[3 * (size_t)u + 2] == INV)
                    tu->orient = gorient[g];
                if (tu->orient != gorient[g])
                    continue;
                ga[3 * (size_t)u + j] = g;
                uint32_t n1 = tu->nb[j], n2 = tu->nb[(j + 2) % 3];
                /* a triangle corner is assigned once and pushes at most two
                 * entries: the stack never exceeds 1 + 2 * ntri entries */
                if (n1 != INV)
                    stack[sp++] = n1;
                if (n2 != INV)
                    stack[sp++] = n2;
            }
        }
    }
    return GEOM_OK;
}

/* Phase 5: each group's tangent sum, weighted by the corner angles between
 * the projected edges. */
static void tan_accumulate(tan_work *W)
{
    const geom_mesh *m = W->m;
    const double *pos = W->x.pos;
    for (size_t t = 0; t < W->ntri; t++) {
        const tri_info *ti = W->tris + t;
        if (ti->degen || ti->any)
            continue;
        for (int i = 0; i < 3; i++) {
            uint32_t g = W->ga[3 * t + i];
            if (g == INV)
                continue;
            double n[3], os[3], e1[3], e2[3], v1[3], v2[3];
            corner_normal(&W->x, ti->c[i], n);
            project_unit(ti->os, n, os);
            const double *p = pos + 3 * (size_t)m->he_vertex[ti->c[i]];
            const double *pn = pos + 3 * (size_t)m->he_vertex[ti->c[(i + 1) % 3]];
            const double *pp = pos + 3 * (size_t)m->he_vertex[ti->c[(i + 2) % 3]];
            for (int k = 0; k < 3; k++) {
                e1[k] = pp[k] - p[k];
                e2[k] = pn[k] - p[k];
            }
            project_unit(e1, n, v1);
            project_unit(e2, n, v2);
            double c = dot3(v1, v2);
            c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
            double ang = acos(c);
            W->gsum[3 * g] += ang * os[0];
            W->gsum[3 * g + 1] += ang * os[1];
            W->gsum[3 * g + 2] += ang * os[2];
        }
    }
}

/* Append the frame (t, w) to the output pool; its index in *idx. */
static geom_status tan_pool_add(tan_work *W, const double t[3], double w, uint32_t *idx)
{
    if (geom__grow(W->al, (void **)&W->pool, &W->pool_cap, W->npool + 1, 4 * sizeof(double)) !=
        GEOM_OK)
        return GEOM_ERR_NOMEM;
    double *q = W->pool + 4 * W->npool;
    q[0] = t[0], q[1] = t[1], q[2] = t[2], q[3] = w;
    *idx = (uint32_t)W->npool++;
    return GEOM_OK;
}

/* Phase 6: the output frames. Group g's frame is pool entry g, its sum
 * orthogonalised against the normal of the group's identity; corners left
 * over (degenerate triangles only) copy a corner with the same identity,
 * else get a frame from the normal alone. */
static geom_status tan_frames(tan_work *W)
{
    const geom_mesh *m = W->m;
    const size_t ntri = W->ntri, ngroups = W->ngroups;
    const tri_info *tris = W->tris;
    const uint32_t *ga = W->ga;
    uint32_t *rep_he = geom__alloc(W->al, (ngroups ? ngroups : 1) * sizeof(uint32_t));
    if (!rep_he)
        return GEOM_ERR_NOMEM;
    for (size_t g = 0; g < ngroups; g++)
        rep_he[g] = INV;
    for (size_t t = 0; t < ntri; t++) {
        for (int i = 0; i < 3; i++) {
            uint32_t g = ga[3 * t + i];
            if (g != INV && rep_he[g] == INV)
                rep_he[g] = tris[t].c[i];
        }
    }
    geom_status st = GEOM_OK;
    for (size_t g = 0; g < ngroups && st == GEOM_OK; g++) {
        double n[3] = {0.0, 0.0, 0.0}, tv[3], w;
        uint32_t idx;
        if (rep_he[g] != INV)
            corner_normal(&W->x, rep_he[g], n);
        project_unit(W->gsum + 3 * g, n, tv);
        if (!(dot3(tv, tv) > 0.0)) {
            basis_from_normal(n, tv);
            w = 1.0;
        } else {
            w = W->gorient[g] ? 1.0 : -1.0;
        }
        st = tan_pool_add(W, tv, w, &idx);
    }
    geom__free(W->al, rep_he, (ngroups ? ngroups : 1) * sizeof(uint32_t));
    if (st != GEOM_OK)
        return st;
    uint32_t *corner_out = W->corner_out;
    for (size_t t = 0; t < ntri; t++) {
        for (int i = 0; i < 3; i++) {
            uint32_t g = ga[3 * t + i];
            if (g != INV && corner_out[tris[t].c[i]] == INV)
                corner_out[tris[t].c[i]] = g;
        }
    }
    const uint32_t *boff = W->boff, *bucket = W->bucket, *ident = W->ident;
    for (size_t v = 0; v < m->nv; v++) {
        for (uint32_t i = boff[v]; i < boff[v + 1]; i++) {
            uint32_t h = bucket[i];
            if (corner_out[h] != INV)
                continue;
            for (uint32_t j = boff[v]; j < boff[v + 1]; j++) {
                uint32_t hj = bucket[j];
                if (corner_out[hj] != INV && ident[hj] == ident[h]) {
                    corner_out[h] = corner_out[hj];
                    break;
                }
            }
            if (corner_out[h] != INV)
                continue;
            double n[3], tv[3];
            corner_normal(&W->x, h, n);
            basis_from_normal(n, tv);
            st = tan_pool_add(W, tv, 1.0, &corner_out[h]);
            if (st != GEOM_OK)
                return st;
        }
    }
    return GEOM_OK;
}

/* Phase 7: the "tangent" corner channel (4 components) from the pool. */
static geom_status tan_store(tan_work *W, uint32_t *id)
{
    return geom__mesh_corner_channel_store(W->m, "tangent", 4, W->pool, W->npool, W->corner_out,
                                           id);
}

static void tan_free(tan_work *W)
{
    const geom_allocator *al = W->al;
    const size_t nh1 = W->nh ? W->nh : 1, ntri1 = W->ntri ? W->ntri : 1;
    geom__free(al, W->tris, W->tri_cap * sizeof(tri_info));
    geom__free(al, W->tri_of_he, nh1 * sizeof(uint32_t));
    geom__free(al, W->ident, nh1 * sizeof(uint32_t));
    geom__free(al, W->corner_out, nh1 * sizeof(uint32_t));
    geom__free(al, W->bucket, (W->ntotal_corners ? W->ntotal_corners : 1) * sizeof(uint32_t));
    geom__free(al, W->boff, (W->m->nv + 1) * sizeof(uint32_t));
    geom__free(al, W->ga, ntri1 * 3 * sizeof(uint32_t));
    geom__free(al, W->stack, ntri1 * 2 * sizeof(uint32_t) + 8);
    geom__free(al, W->fn, (W->nf ? W->nf : 1) * 3 * sizeof(double));
    geom__free(al, W->gsum, W->gcap * 3 * sizeof(double));
    geom__free(al, W->gorient, W->ocap);
    geom__free(al, W->pool, W->pool_cap * 4 * sizeof(double));
}

geom_status geom_mesh_tangents(geom_mesh *m, uint32_t *id)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    uint32_t uvch = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    if (uvch == INV || geom_mesh_channel_ncomp(m, uvch) < 2)
        return GEOM_ERR_INVALID_ARG;
    geom_status st = GEOM_OK;
    uint32_t nch = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    if (nch != INV && geom_mesh_channel_ncomp(m, nch) != 3)
        nch = INV;
    if (nch == INV) {
        st = geom_mesh_corner_normals(m, NULL, &nch);
        if (st != GEOM_OK)
            return st;
        uvch = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    }

    tan_work W;
    memset(&W, 0, sizeof W);
    W.m = m;
    W.al = &m->alloc;
    W.nh = m->nh;
    W.nf = m->nf;
    const size_t nh = W.nh, nf = W.nf;
    tan_ctx *x = &W.x;
    x->m = m;
    x->pos = geom__mesh_pos(m);
    x->uvd = geom_mesh_channel_cdata(m, uvch);
    x->uvi = geom_mesh_corner_cindices(m, uvch);
    x->uvc = geom_mesh_channel_ncomp(m, uvch);
    x->uvn = geom_mesh_channel_size(m, uvch);
    x->nd = geom_mesh_channel_cdata(m, nch);
    x->ni = geom_mesh_corner_cindices(m, nch);
    x->nn = geom_mesh_channel_size(m, nch);

    W.fn = geom__alloc(W.al, (nf ? nf : 1) * 3 * sizeof(double));
    W.tri_of_he = geom__alloc(W.al, (nh ? nh : 1) * sizeof(uint32_t));
    W.ident = geom__alloc(W.al, (nh ? nh : 1) * sizeof(uint32_t));
    W.corner_out = geom__alloc(W.al, (nh ? nh : 1) * sizeof(uint32_t));
    if (!W.fn || !W.tri_of_he || !W.ident || !W.corner_out) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t f = 0; f < nf; f++) {
        if (m->f_del[f] || geom_mesh_face_normal(m, (uint32_t)f, W.fn + 3 * f) != GEOM_OK)
            W.fn[3 * f] = W.fn[3 * f + 1] = W.fn[3 * f + 2] = 0.0;
    }
    x->fn = W.fn;
    for (size_t h = 0; h < nh; h++)
        W.tri_of_he[h] = W.ident[h] = W.corner_out[h] = INV;

    if ((st = tan_identities(&W)) != GEOM_OK || (st = tan_triangulate(&W)) != GEOM_OK)
        goto done;
    tan_triangle_frames(&W);
    if ((st = tan_groups(&W)) != GEOM_OK)
        goto done;
    tan_accumulate(&W);
    if ((st = tan_frames(&W)) != GEOM_OK)
        goto done;
    st = tan_store(&W, id);
done:
    tan_free(&W);
    return st;
}
