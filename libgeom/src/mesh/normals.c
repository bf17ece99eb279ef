/*
 * Face normals (Newell's method), vertex normals with uniform, area, angle
 * (Thuermer & Wuethrich 1998) and Max (1999) weights, and corner normals
 * with crease-angle splitting and optional splitting at the seams of another
 * corner channel.
 *
 * Robustness: every position difference is multiplied by a power of two G
 * chosen from the mesh's extent (exact), so cross products and the squared
 * lengths of Max's weights neither overflow nor underflow for coordinates
 * anywhere in the double range (1e+-150 and beyond). A face whose area is at
 * most 1e-14 times the square of its longest edge (geom_mesh_face_is_degenerate's
 * rule), or that has a non-finite vertex, contributes nothing.
 *
 * References:
 *  - M. E. Newell's polygon normal (Sutherland, Sproull, Schumacker 1974);
 *  - G. Thuermer, C. A. Wuethrich, "Computing vertex normals from polygonal
 *    facets", Journal of Graphics Tools 3(1), 1998 (angle weights);
 *  - N. Max, "Weights for computing vertex normals from facet normals",
 *    Journal of Graphics Tools 4(2), 1999 (exact for vertices whose
 *    neighbours lie on a sphere through them).
 */
#include "mesh/mesh_internal.h"

#include <float.h>

#define INV GEOM_INVALID_INDEX
#if defined(__GNUC__) || defined(__clang__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif
/* |n|^2 <= DEGEN2 * L^4  <=>  area = |n|/2 <= 1e-14 * L^2. */
#define DEGEN2 4e-28

/* ------------------------------------------------------------ helpers */

/* (b - a) * g without overflow. g == 1 (the usual case, see mesh_scale) is
 * the plain difference; scaling down (g < 1, large coordinates) scales
 * before subtracting, scaling up (g > 1, small extent) subtracts first
 * (exact for nearby values, subnormals included). g is a power of two, so
 * each is exact up to the subtraction's rounding. */
static ALWAYS_INLINE void sub_scaled(const double *b, const double *a, double g, double out[3])
{
    if (g == 1.0) {
        out[0] = b[0] - a[0];
        out[1] = b[1] - a[1];
        out[2] = b[2] - a[2];
    } else if (g < 1.0) {
        out[0] = b[0] * g - a[0] * g;
        out[1] = b[1] * g - a[1] * g;
        out[2] = b[2] * g - a[2] * g;
    } else {
        out[0] = (b[0] - a[0]) * g;
        out[1] = (b[1] - a[1]) * g;
        out[2] = (b[2] - a[2]) * g;
    }
}

/* 2^-ex clamped to the normal range (2^1000 is enough to lift subnormal
 * extents to ~2^-74, where squares of squares still do not underflow). */
static double pow2_scale(int ex)
{
    if (ex > 1000)
        ex = 1000;
    if (ex < -1000)
        ex = -1000;
    return ldexp(1.0, -ex);
}

static inline void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Normalise v in place without overflow or underflow; (0,0,0) (and return 0)
 * for a zero or non-finite vector, 1 otherwise. The common case (a squared
 * length comfortably inside the normal range) takes one square root and one
 * division; others are rescaled by the largest component first. */
static inline int normalize3(double v[3])
{
    double s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (s > 1e-280 && s < 1e280) {
        double inv = 1.0 / sqrt(s);
        v[0] *= inv;
        v[1] *= inv;
        v[2] *= inv;
        return 1;
    }
    return geom__mesh_normalize3(v);
}

/* The power of two that brings the extent of the live vertices (finite
 * coordinates only) near 1. */
static double mesh_scale(const geom_mesh *m)
{
    const double *p = geom__mesh_pos(m);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < m->nv; v++) {
        if (m->v_del[v])
            continue;
        const double *q = p + 3 * v;
        for (int k = 0; k < 3; k++) {
            if (isfinite(q[k])) {
                lo[k] = fmin(lo[k], q[k]);
                hi[k] = fmax(hi[k], q[k]);
            }
        }
    }
    double e = 0.0;
    for (int k = 0; k < 3; k++) {
        if (lo[k] <= hi[k]) {
            /* hi*0.5 - lo*0.5 cannot overflow. */
            e = fmax(e, hi[k] * 0.5 - lo[k] * 0.5);
        }
    }
    if (!(e > 0.0) || !isfinite(e))
        return 1.0;
    int ex;
    frexp(e, &ex);
    return pow2_scale(ex);
}

/* Scale factor for one face: brings its largest vertex offset near 1. */
static double face_scale(const geom_mesh *m, uint32_t f)
{
    const double *p = geom__mesh_pos(m);
    uint32_t h0 = m->f_he[f], h = h0;
    const double *a = p + 3 * (size_t)m->he_vertex[h0];
    double mx = 0.0;
    size_t guard = 0;
    do {
        const double *q = p + 3 * (size_t)m->he_vertex[h];
        for (int k = 0; k < 3; k++)
            mx = fmax(mx, fabs(q[k] * 0.5 - a[k] * 0.5));
        h = m->he_next[h];
    } while (h != h0 && ++guard < m->nh);
    if (!(mx > 0.0) || !isfinite(mx))
        return 1.0;
    int ex;
    frexp(mx, &ex);
    return pow2_scale(ex + 1);
}

/* One corner of Newell's sum over positions scaled by g (a: the face's first
 * vertex, b: this corner's vertex, c: the previous one): adds qprev x q to n,
 * tracks the largest squared edge and flags zero-length edges and non-finite
 * positions. The one loop body of poly_area_vector and
 * geom__mesh_triangle_normal, so that both give the same bits. */
static inline void newell_step(const double *a, const double *b, const double *c, double g,
                               double n[3], double qprev[3], double *L2, int *zero_edge,
                               int *finite)
{
    double q[3], e[3], x[3];
    sub_scaled(b, a, g, q);
    sub_scaled(b, c, g, e);
    double l2 = dot3(e, e);
    if (!geom__isfinite3(b))
        *finite = 0;
    if (l2 == 0.0)
        *zero_edge = 1;
    if (l2 == 0.0 && (e[0] != 0.0 || e[1] != 0.0 || e[2] != 0.0))
        l2 = 0x1p-1074; /* underflowed, not coincident */
    if (l2 > *L2)
        *L2 = l2;
    cross3(qprev, q, x);
    n[0] += x[0];
    n[1] += x[1];
    n[2] += x[2];
    qprev[0] = q[0];
    qprev[1] = q[1];
    qprev[2] = q[2];
}

/*
 * Geometry of a polygon face with positions scaled by g: the area vector
 * times 2 (Newell's sum of q_i x q_i+1 with q relative to the first vertex)
 * in n, and whether the face is degenerate. Returns 1 when usable.
 */
static int poly_area_vector(const geom_mesh *m, uint32_t f, double g, double n[3],
                            double *L2out)
{
    const double *p = geom__mesh_pos(m);
    uint32_t h0 = m->f_he[f];
    const double *a = p + 3 * (size_t)m->he_vertex[h0];
    n[0] = n[1] = n[2] = 0.0;
    double L2 = 0.0;
    int zero_edge = 0, finite = 1;
    uint32_t h = h0;
    double qprev[3] = {0.0, 0.0, 0.0};
    size_t guard = 0;
    do {
        uint32_t hn = m->he_next[h];
        const double *b = p + 3 * (size_t)m->he_vertex[hn];
        const double *c = p + 3 * (size_t)m->he_vertex[h];
        newell_step(a, b, c, g, n, qprev, &L2, &zero_edge, &finite);
        h = hn;
    } while (h != h0 && ++guard < m->nh);
    double n2 = dot3(n, n);
    if (L2out)
        *L2out = L2;
    if (!finite || zero_edge || !isfinite(n2) || !isfinite(L2) || n2 <= DEGEN2 * L2 * L2)
        return 0;
    return 1;
}

/* n normalised into out: GEOM_ERR_DEGENERATE (out left as it is) when n
 * cannot be normalised. The tail of the face-normal functions. */
static geom_status unit_normal_out(double n[3], double out[3])
{
    if (!normalize3(n))
        return GEOM_ERR_DEGENERATE;
    out[0] = n[0];
    out[1] = n[1];
    out[2] = n[2];
    return GEOM_OK;
}

/* geom_mesh_face_normal of a triangle face whose cycle from f_he visits
 * v[0], v[1], v[2] (the same operations in the same order as face_scale,
 * poly_area_vector and normalize3 on that face, so the same bits), for
 * writers that triangulate one face at a time. */
geom_status geom__mesh_triangle_normal(const double *const v[3], double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    const double *a = v[0];
    double mx = 0.0, g = 1.0;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            mx = fmax(mx, fabs(v[i][k] * 0.5 - a[k] * 0.5));
    if (mx > 0.0 && isfinite(mx)) {
        int ex;
        frexp(mx, &ex);
        g = pow2_scale(ex + 1);
    }
    double n[3] = {0.0, 0.0, 0.0}, L2 = 0.0, qprev[3] = {0.0, 0.0, 0.0};
    int zero_edge = 0, finite = 1;
    for (int i = 0; i < 3; i++) {
        const double *b = v[(i + 1) % 3], *c = v[i];
        newell_step(a, b, c, g, n, qprev, &L2, &zero_edge, &finite);
    }
    double n2 = dot3(n, n);
    if (!finite || zero_edge || !isfinite(n2) || !isfinite(L2) || n2 <= DEGEN2 * L2 * L2)
        return GEOM_ERR_DEGENERATE;
    return unit_normal_out(n, out);
}

geom_status geom_mesh_face_normal(const geom_mesh *m, uint32_t f, double out[3])
{
    if (out)
        out[0] = out[1] = out[2] = 0.0;
    if (!m || !out || f >= m->nf || m->f_del[f])
        return GEOM_ERR_INVALID_ARG;
    double n[3];
    if (!poly_area_vector(m, f, face_scale(m, f), n, NULL))
        return GEOM_ERR_DEGENERATE;
    return unit_normal_out(n, out);
}

/* ------------------------------------------------- corner contributions */

/*
 * Corner contributions of triangle (a, b, c) (scaled edge vectors computed
 * here) to its three vertices under `weight`: out[0..2] for a, [3..5] for b,
 * [6..8] for c. Returns 0 (and zeros) for a degenerate triangle. *L2out
 * receives the longest squared (scaled) edge length.
 * nunit (may be NULL) receives the unit normal.
 */
static ALWAYS_INLINE int tri_contrib(const double *pa, const double *pb, const double *pc,
                                     double g, geom_normal_weight weight, double out[9],
                                     double *nunit, double *L2out)
{
    double eab[3], ebc[3], eca[3], n[3];
    sub_scaled(pb, pa, g, eab);
    sub_scaled(pc, pb, g, ebc);
    sub_scaled(pa, pc, g, eca);
    /* n = (b - a) x (c - a) = eab x (-eca) = eca x eab */
    cross3(eca, eab, n);
    double lab = dot3(eab, eab), lbc = dot3(ebc, ebc), lca = dot3(eca, eca);
    double L2 = lab > lbc ? lab : lbc;
    L2 = lca > L2 ? lca : L2;
    *L2out = L2;
    double n2 = dot3(n, n);
    if (!(n2 > DEGEN2 * L2 * L2) || !isfinite(n2)) {
        for (int i = 0; i < 9; i++)
            out[i] = 0.0;
        /* squares that underflowed to zero are not coincident vertices */
        if (L2 == 0.0 && (eab[0] != 0.0 || eab[1] != 0.0 || eab[2] != 0.0 || ebc[0] != 0.0 ||
                          ebc[1] != 0.0 || ebc[2] != 0.0))
            *L2out = 0x1p-1074;
        return 0;
    }
    double len = sqrt(n2);
    double inv = 1.0 / len;
    double u[3] = {n[0] * inv, n[1] * inv, n[2] * inv};
    if (nunit) {
        nunit[0] = u[0];
        nunit[1] = u[1];
        nunit[2] = u[2];
    }
    double wa, wb, wc;
    const double *dir = u;
    switch (weight) {
    case GEOM_NORMAL_WEIGHT_UNIFORM:
        wa = wb = wc = 1.0;
        break;
    case GEOM_NORMAL_WEIGHT_AREA:
        wa = wb = wc = 1.0;
        dir = n;
        break;
    case GEOM_NORMAL_WEIGHT_MAX: {
        /* (e1 x e2) / (|e1|^2 |e2|^2) per corner; e1 x e2 = n at each corner.
         * One division when the product of the three squared lengths is
         * safely representable. */
        double p3 = lab * lbc * lca;
        if (p3 > 1e-290 && p3 < 1e290) {
            double inv = 1.0 / p3;
            wa = lbc * inv;
            wb = lca * inv;
            wc = lab * inv;
        } else {
            wa = 1.0 / (lab * lca);
            wb = 1.0 / (lab * lbc);
            wc = 1.0 / (lbc * lca);
        }
        dir = n;
        break;
    }
    case GEOM_NORMAL_WEIGHT_ANGLE:
    default:
        /* |e1 x e2| = |n| at every corner of a triangle; the angles add up
         * to pi, so the third one (the smallest, for accuracy: its absolute
         * error of a few ulp of pi is what matters in the weighted sum)
         * comes from the other two. */
        if (lbc <= lab && lbc <= lca) { /* a is opposite the shortest edge */
            wb = atan2(len, -dot3(ebc, eab));
            wc = atan2(len, -dot3(eca, ebc));
            wa = GEOM_PI - wb - wc;
        } else if (lca <= lab) { /* b */
            wa = atan2(len, -dot3(eab, eca));
            wc = atan2(len, -dot3(eca, ebc));
            wb = GEOM_PI - wa - wc;
        } else { /* c */
            wa = atan2(len, -dot3(eab, eca));
            wb = atan2(len, -dot3(ebc, eab));
            wc = GEOM_PI - wa - wb;
        }
        if (wa < 0.0)
            wa = 0.0;
        if (wb < 0.0)
            wb = 0.0;
        if (wc < 0.0)
            wc = 0.0;
        break;
    }
    out[0] = dir[0] * wa;
    out[1] = dir[1] * wa;
    out[2] = dir[2] * wa;
    out[3] = dir[0] * wb;
    out[4] = dir[1] * wb;
    out[5] = dir[2] * wb;
    out[6] = dir[0] * wc;
    out[7] = dir[1] * wc;
    out[8] = dir[2] * wc;
    return 1;
}

/*
 * Contributions of a polygon face's corners: for the k-th halfedge h_k of the
 * face starting at f_he[f] (pointing to the corner's vertex), 3 doubles at
 * out[3k]. Returns the valence, or 0 if the face is degenerate (out then
 * untouched). out holds 3 * valence doubles (the caller sized it).
 */
static size_t poly_contrib(const geom_mesh *m, uint32_t f, double g, geom_normal_weight weight,
                           double *out, double *nunit, double *L2)
{
    double n[3];
    if (!poly_area_vector(m, f, g, n, L2))
        return 0;
    double u[3] = {n[0], n[1], n[2]};
    if (!normalize3(u))
        return 0;
    if (nunit) {
        nunit[0] = u[0];
        nunit[1] = u[1];
        nunit[2] = u[2];
    }
    const double *p = geom__mesh_pos(m);
    uint32_t h0 = m->f_he[f], h = h0;
    size_t k = 0;
    do {
        uint32_t hp = m->he_prev[h], hn = m->he_next[h];
        const double *v = p + 3 * (size_t)m->he_vertex[h];
        const double *prv = p + 3 * (size_t)m->he_vertex[hp];
        const double *nxt = p + 3 * (size_t)m->he_vertex[hn];
        double *o = out + 3 * k;
        double w = 1.0;
        const double *dir = u;
        if (weight == GEOM_NORMAL_WEIGHT_AREA) {
            dir = n;
        } else if (weight == GEOM_NORMAL_WEIGHT_ANGLE || weight == GEOM_NORMAL_WEIGHT_MAX) {
            double e1[3], e2[3], x[3];
            sub_scaled(nxt, v, g, e1);
            sub_scaled(prv, v, g, e2);
            cross3(e1, e2, x);
            double s = dot3(x, u);
            if (weight == GEOM_NORMAL_WEIGHT_ANGLE) {
                w = atan2(s, dot3(e1, e2));
                if (w < 0.0)
                    w += 2.0 * GEOM_PI; /* reflex corner of a non-convex polygon */
            } else {
                double d = dot3(e1, e1) * dot3(e2, e2);
                w = d > 0.0 ? s / d : 0.0;
            }
        }
        o[0] = dir[0] * w;
        o[1] = dir[1] * w;
        o[2] = dir[2] * w;
        k++;
        h = hn;
    } while (h != h0 && k < m->nh);
    return k;
}

/* Largest face valence among live faces (3 for an all-triangle mesh). */
static size_t max_valence(const geom_mesh *m, int *all_tris)
{
    size_t mx = 0;
    *all_tris = 1;
    for (size_t f = 0; f < m->nf; f++) {
        if (m->f_del[f])
            continue;
        uint32_t h0 = m->f_he[f], h = h0;
        size_t k = 0;
        do {
            k++;
            h = m->he_next[h];
        } while (h != h0 && k <= m->nh);
        if (k != 3)
            *all_tris = 0;
        if (k > mx)
            mx = k;
    }
    return mx;
}

static int weight_ok(geom_normal_weight w)
{
    return w == GEOM_NORMAL_WEIGHT_ANGLE || w == GEOM_NORMAL_WEIGHT_UNIFORM ||
           w == GEOM_NORMAL_WEIGHT_AREA || w == GEOM_NORMAL_WEIGHT_MAX;
}

/* ------------------------------------------------------- vertex normals */

/* Squared edge lengths for which unscaled arithmetic (g = 1) is safe: then
 * |n|^2 <= L2^2, |e1|^2 |e2|^2 |e3|^2 <= L2^3 cannot overflow, and every
 * edge of a non-degenerate triangle is at least 2e-14 L of the longest
 * (|n| <= shortest * longest), so nothing that matters underflows. */
#define SAFE_L2_MIN 0x1p-300
#define SAFE_L2_MAX 0x1p300

/*
 * One pass over the faces accumulating each corner's weighted normal into
 * its vertex (triangles inline, other polygons through poly_contrib). The
 * weight is a compile-time constant in each of the four instances below, so
 * the per-triangle code has no branch on it. With check != 0 (the unscaled
 * first attempt, g = 1) the pass stops and returns 1 in *redo as soon as a
 * face's longest squared edge is outside [SAFE_L2_MIN, SAFE_L2_MAX] (or
 * infinite): the caller then starts over with a scale from the mesh's extent.
 */
static ALWAYS_INLINE geom_status vn_accumulate(const geom_mesh *m, double g,
                                               geom_normal_weight weight, int check,
                                               double *normals, int *redo)
{
    const double *p = geom__mesh_pos(m);
    const uint32_t *fhe = m->f_he, *nxt = m->he_next, *hv = m->he_vertex;
    const uint8_t *fdel = m->f_del;
    const size_t nf = m->nf;
    double *poly = NULL;
    size_t poly_cap = 0;
    geom_status st = GEOM_OK;
    *redo = 0;
    /* The contributions of a triangle are added one triangle later: the
     * additions then never wait for the square root and division of the
     * triangle just computed, which consecutive triangles sharing a vertex
     * would otherwise serialise. */
    double pw[9] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double *pa = NULL, *pb = NULL, *pc = NULL;
#define FLUSH_PENDING()                                                                        \
    do {                                                                                       \
        if (pa) {                                                                              \
            pa[0] += pw[0];                                                                    \
            pa[1] += pw[1];                                                                    \
            pa[2] += pw[2];                                                                    \
            pb[0] += pw[3];                                                                    \
            pb[1] += pw[4];                                                                    \
            pb[2] += pw[5];                                                                    \
            pc[0] += pw[6];                                                                    \
            pc[1] += pw[7];                                                                    \
            pc[2] += pw[8];                                                                    \
            pa = NULL;                                                                         \
        }                                                                                      \
    } while (0)
    for (size_t f = 0; f < nf; f++) {
        if (fdel[f])
            continue;
        uint32_t h0 = fhe[f], h1 = nxt[h0], h2 = nxt[h1];
        double L2;
        if (nxt[h2] == h0) {
            uint32_t a = hv[h0], b = hv[h1], c = hv[h2];
            double w[9];
            int ok = tri_contrib(p + 3 * (size_t)a, p + 3 * (size_t)b, p + 3 * (size_t)c, g,
                                 weight, w, NULL, &L2);
            /* L2 == 0 (coincident vertices) and NaN are degenerate at any
             * scale; tiny, huge or infinite ones need scaling */
            if (check && L2 != 0.0 && (L2 < SAFE_L2_MIN || L2 > SAFE_L2_MAX)) {
                *redo = 1;
                break;
            }
            if (!ok)
                continue;
            FLUSH_PENDING();
            memcpy(pw, w, sizeof pw);
            pa = normals + 3 * (size_t)a;
            pb = normals + 3 * (size_t)b;
            pc = normals + 3 * (size_t)c;
            continue;
        }
        FLUSH_PENDING();
        /* general polygon */
        size_t k = 0;
        uint32_t h = h0;
        do {
            k++;
            h = nxt[h];
        } while (h != h0 && k <= m->nh);
        if (geom__grow(&m->alloc, (void **)&poly, &poly_cap, k, 3 * sizeof(double)) !=
            GEOM_OK) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        L2 = 0.0;
        size_t kk = poly_contrib(m, (uint32_t)f, g, weight, poly, NULL, &L2);
        if (check && L2 != 0.0 && (L2 < SAFE_L2_MIN || L2 > SAFE_L2_MAX)) {
            *redo = 1;
            break;
        }
        h = h0;
        for (size_t i = 0; i < kk; i++) {
            double *nv3 = normals + 3 * (size_t)hv[h];
            nv3[0] += poly[3 * i];
            nv3[1] += poly[3 * i + 1];
            nv3[2] += poly[3 * i + 2];
            h = nxt[h];
        }
    }
    FLUSH_PENDING();
#undef FLUSH_PENDING
    geom__free(&m->alloc, poly, poly_cap * 3 * sizeof(double));
    return st;
}

static geom_status vn_uniform(const geom_mesh *m, double g, int check, double *n, int *redo)
{
    return vn_accumulate(m, g, GEOM_NORMAL_WEIGHT_UNIFORM, check, n, redo);
}
static geom_status vn_area(const geom_mesh *m, double g, int check, double *n, int *redo)
{
    return vn_accumulate(m, g, GEOM_NORMAL_WEIGHT_AREA, check, n, redo);
}
static geom_status vn_angle(const geom_mesh *m, double g, int check, double *n, int *redo)
{
    return vn_accumulate(m, g, GEOM_NORMAL_WEIGHT_ANGLE, check, n, redo);
}
static geom_status vn_max(const geom_mesh *m, double g, int check, double *n, int *redo)
{
    return vn_accumulate(m, g, GEOM_NORMAL_WEIGHT_MAX, check, n, redo);
}

geom_status geom_mesh_vertex_normals(const geom_mesh *m, geom_normal_weight weight,
                                     double *normals, size_t *n_zero)
{
    if (n_zero)
        *n_zero = 0;
    if (!m || (!normals && m->nv > 0) || !weight_ok(weight))
        return GEOM_ERR_INVALID_ARG;
    const size_t nv = m->nv;
    if (nv == 0)
        return GEOM_OK;
    geom_status (*pass)(const geom_mesh *, double, int, double *, int *);
    switch (weight) {
    case GEOM_NORMAL_WEIGHT_UNIFORM:
        pass = vn_uniform;
        break;
    case GEOM_NORMAL_WEIGHT_AREA:
        pass = vn_area;
        break;
    case GEOM_NORMAL_WEIGHT_MAX:
        pass = vn_max;
        break;
    case GEOM_NORMAL_WEIGHT_ANGLE:
    default:
        pass = vn_angle;
        break;
    }
    /* First without scaling, which suits every mesh whose edges lie between
     * 2^-150 and 2^150; a face outside that range makes the pass stop, and
     * it is redone with differences scaled by a power of two from the
     * mesh's extent (exact, so the results only differ where unscaled
     * arithmetic would have overflowed or underflowed). */
    memset(normals, 0, 3 * nv * sizeof(double));
    int redo = 0;
    geom_status st = pass(m, 1.0, 1, normals, &redo);
    if (st == GEOM_OK && redo) {
        memset(normals, 0, 3 * nv * sizeof(double));
        st = pass(m, mesh_scale(m), 0, normals, &redo);
    }
    if (st != GEOM_OK) {
        memset(normals, 0, 3 * nv * sizeof(double));
        return st;
    }
    size_t zeros = 0;
    for (size_t v = 0; v < nv; v++) {
        if (!normalize3(normals + 3 * v) && !m->v_del[v])
            zeros++;
    }
    if (n_zero)
        *n_zero = zeros;
    return GEOM_OK;
}

/* ------------------------------------------------------- corner normals */

geom_status geom_mesh_corner_normals(geom_mesh *m, const geom_corner_normal_options *opt,
                                     uint32_t *id)
{
    geom_corner_normal_options o = {GEOM_NORMAL_WEIGHT_ANGLE, 0.0, 0};
    if (opt)
        o = *opt;
    if (!m || !weight_ok(o.weight) || !(o.crease_degrees >= 0.0))
        return GEOM_ERR_INVALID_ARG;
    const uint32_t *split = NULL;
    if (o.split_at_channel_plus_one) {
        uint32_t sc = o.split_at_channel_plus_one - 1;
        if (sc >= m->n_channels || m->channels[sc].domain != GEOM_MESH_DOMAIN_CORNER)
            return GEOM_ERR_INVALID_ARG;
        split = m->channels[sc].corner;
    }
    double crease = o.crease_degrees == 0.0 ? 180.0 : o.crease_degrees;
    /* Hard when the angle between the face normals exceeds `crease`; the
     * angle is atan2(|n0 x n1|, n0.n1), accurate down to tiny folds. */
    const int use_crease = crease < 180.0;
    const double crease_rad = crease * (GEOM_PI / 180.0);

    const size_t nv = m->nv, nh = m->nh, nf = m->nf;
    const geom_allocator *al = &m->alloc;
    double *contrib = NULL, *fn = NULL, *poly = NULL, *fans = NULL;
    uint32_t *cidx = NULL, *ring = NULL;
    uint8_t *hard = NULL;
    size_t poly_cap = 0, ring_cap = 0, hard_cap = 0, nfans = 0, fans_cap = 0;
    geom_status st = GEOM_OK;
    int all_tris;
    size_t maxval = max_valence(m, &all_tris);
    (void)all_tris;

    contrib = geom__alloc(al, (nh ? nh : 1) * 3 * sizeof(double));
    fn = geom__alloc(al, (nf ? nf : 1) * 3 * sizeof(double));
    cidx = geom__alloc(al, (nh ? nh : 1) * sizeof(uint32_t));
    poly_cap = maxval ? maxval : 1;
    poly = geom__alloc(al, poly_cap * 3 * sizeof(double));
    if (!contrib || !fn || !cidx || !poly) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    memset(contrib, 0, nh * 3 * sizeof(double));
    memset(fn, 0, nf * 3 * sizeof(double));
    for (size_t h = 0; h < nh; h++)
        cidx[h] = INV;

    /* Per-face unit normals and per-corner weighted contributions. */
    {
        const double g = mesh_scale(m);
        const double *p = geom__mesh_pos(m);
        for (size_t f = 0; f < nf; f++) {
            if (m->f_del[f])
                continue;
            uint32_t h0 = m->f_he[f], h1 = m->he_next[h0], h2 = m->he_next[h1];
            if (m->he_next[h2] == h0) {
                double w[9];
                double L2;
                if (!tri_contrib(p + 3 * (size_t)m->he_vertex[h0], p + 3 * (size_t)m->he_vertex[h1],
                                 p + 3 * (size_t)m->he_vertex[h2], g, o.weight, w, fn + 3 * f,
                                 &L2))
                    continue;
                memcpy(contrib + 3 * (size_t)h0, w, 3 * sizeof(double));
                memcpy(contrib + 3 * (size_t)h1, w + 3, 3 * sizeof(double));
                memcpy(contrib + 3 * (size_t)h2, w + 6, 3 * sizeof(double));
            } else {
                size_t k = poly_contrib(m, (uint32_t)f, g, o.weight, poly, fn + 3 * f, NULL);
                uint32_t h = h0;
                for (size_t i = 0; i < k; i++) {
                    memcpy(contrib + 3 * (size_t)h, poly + 3 * i, 3 * sizeof(double));
                    h = m->he_next[h];
                }
            }
        }
    }

    /* Fans around each vertex. */
    for (size_t v = 0; v < nv; v++) {
        if (m->v_del[v] || m->v_he[v] == INV)
            continue;
        size_t k = 0;
        uint32_t o0 = m->v_he[v], oh = o0;
        do {
            if (k + 1 > ring_cap || k + 1 > hard_cap) {
                if (geom__grow(al, (void **)&ring, &ring_cap, k + 1, sizeof(uint32_t)) !=
                        GEOM_OK ||
                    geom__grow(al, (void **)&hard, &hard_cap, k + 1, 1) != GEOM_OK) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            }
            ring[k++] = oh;
            oh = geom__mesh_ccw(m, oh);
        } while (oh != o0 && k <= nh);
        /* hard[i]: edge(ring[i]) separates face(ring[i-1]) and face(ring[i]). */
        size_t first_hard = k;
        for (size_t i = 0; i < k; i++) {
            uint32_t oi = ring[i];
            uint32_t fa = m->he_face[oi ^ 1u], fb = m->he_face[oi];
            int hd = 0;
            if (fa == INV || fb == INV) {
                hd = 1;
            } else {
                const double *na = fn + 3 * (size_t)fa, *nb = fn + 3 * (size_t)fb;
                /* degenerate faces (zero normal) never make an edge hard */
                if (use_crease && dot3(na, na) > 0.0 && dot3(nb, nb) > 0.0) {
                    double x[3];
                    cross3(na, nb, x);
                    if (atan2(sqrt(dot3(x, x)), dot3(na, nb)) > crease_rad)
                        hd = 1;
                }
                if (split && split[oi ^ 1u] != split[m->he_prev[oi]])
                    hd = 1;
            }
            hard[i] = (uint8_t)hd;
            if (hd && first_hard == k)
                first_hard = i;
        }
        size_t start = first_hard == k ? 0 : first_hard;
        size_t cur = 0;
        int have_fan = 0;
        for (size_t j = 0; j < k; j++) {
            size_t i = (start + j) % k;
            if (hard[i] || !have_fan) {
                have_fan = 1;
                st = geom__grow(al, (void **)&fans, &fans_cap, nfans + 1, 3 * sizeof(double));
                if (st != GEOM_OK)
                    goto done;
                cur = nfans++;
                fans[3 * cur] = fans[3 * cur + 1] = fans[3 * cur + 2] = 0.0;
            }
            uint32_t oi = ring[i];
            if (m->he_face[oi] == INV)
                continue;
            uint32_t c = m->he_prev[oi]; /* corner of face(oi) at v */
            cidx[c] = (uint32_t)cur;
            fans[3 * cur] += contrib[3 * (size_t)c];
            fans[3 * cur + 1] += contrib[3 * (size_t)c + 1];
            fans[3 * cur + 2] += contrib[3 * (size_t)c + 2];
        }
    }

    /* Drop the fans without corners (opened at boundary gaps), number the
     * others in first-use order and normalise them. */
    {
        uint32_t *remap = geom__alloc(al, (nfans ? nfans : 1) * sizeof(uint32_t));
        if (!remap) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        for (size_t i = 0; i < nfans; i++)
            remap[i] = INV;
        size_t used = 0;
        for (size_t h = 0; h < nh; h++) {
            if (cidx[h] == INV)
                continue;
            if (remap[cidx[h]] == INV) {
                size_t src = cidx[h];
                remap[src] = (uint32_t)used;
                double t[3] = {fans[3 * src], fans[3 * src + 1], fans[3 * src + 2]};
                normalize3(t);
                /* contrib is no longer needed: it receives the fan normals
                 * in first-use order (used <= number of corners <= nh). */
                memcpy(contrib + 3 * used, t, sizeof t);
                used++;
            }
            cidx[h] = remap[cidx[h]];
        }
        geom__free(al, remap, (nfans ? nfans : 1) * sizeof(uint32_t));
        nfans = used;
    }
    /* contrib[0 .. 3*nfans) now holds the fan normals (nfans <= nh). */

    st = geom__mesh_corner_channel_store(m, "normal", 3, contrib, nfans, cidx, id);

done:
    geom__free(al, contrib, (nh ? nh : 1) * 3 * sizeof(double));
    geom__free(al, fn, (nf ? nf : 1) * 3 * sizeof(double));
    geom__free(al, cidx, (nh ? nh : 1) * sizeof(uint32_t));
    geom__free(al, poly, poly_cap * 3 * sizeof(double));
    geom__free(al, fans, fans_cap * 3 * sizeof(double));
    geom__free(al, ring, ring_cap * sizeof(uint32_t));
    geom__free(al, hard, hard_cap);
    return st;
}
