/*
 * Helpers shared by the iso tests (unit, stability, validation): an
 * independent topology and validity checker for indexed triangle meshes,
 * and the scalar fields the tests contour. Header-only (static functions).
 */
#ifndef TEST_ISO_UTIL_H
#define TEST_ISO_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "geom/iso.h"

/* ------------------------------------------------------------ topology */

typedef struct iso_topo {
    long vertices;          /* vertices used by some triangle */
    long edges, faces;
    long euler;             /* V - E + F over used vertices */
    long components;        /* edge-connected components of triangles */
    long boundary_edges;    /* edges with one triangle */
    long boundary_loops;    /* connected sets of boundary edges */
    long nonmanifold_edges; /* edges with more than two triangles */
    long misoriented_edges; /* edges whose two triangles run the same way */
    long nonmanifold_vertices; /* vertices whose triangles form several fans */
    long duplicate_points;  /* pairs of used vertices at the same position */
    long duplicate_faces;   /* triangles with the same vertex set */
    long degenerate_faces;  /* repeated index or exactly collinear corners */
    long isolated_vertices; /* vertices no triangle uses */
} iso_topo;

typedef struct iso_he_rec {
    uint32_t lo, hi;  /* sorted endpoints */
    uint32_t from;    /* directed start */
    uint32_t face;
} iso_he_rec;

static inline int iso_cmp_he(const void *a, const void *b)
{
    const iso_he_rec *x = a, *y = b;
    if (x->lo != y->lo)
        return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    return 0;
}

static inline int iso_cmp_u3(const void *a, const void *b)
{
    const uint32_t *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x[i] != y[i])
            return x[i] < y[i] ? -1 : 1;
    return 0;
}

static const double *iso_sort_base;
static inline int iso_cmp_pt(const void *a, const void *b)
{
    const double *x = iso_sort_base + 3 * (size_t) * (const uint32_t *)a;
    const double *y = iso_sort_base + 3 * (size_t) * (const uint32_t *)b;
    for (int i = 0; i < 3; i++)
        if (x[i] != y[i])
            return x[i] < y[i] ? -1 : 1;
    return 0;
}

static inline uint32_t iso_uf_find(uint32_t *p, uint32_t a)
{
    while (p[a] != a) {
        p[a] = p[p[a]];
        a = p[a];
    }
    return a;
}

static inline void iso_uf_join(uint32_t *p, uint32_t a, uint32_t b)
{
    a = iso_uf_find(p, a);
    b = iso_uf_find(p, b);
    if (a != b)
        p[a < b ? b : a] = a < b ? a : b;
}

/* Exact collinearity of three points: all three coordinate projections
 * have zero exact orientation. */
static inline int iso_collinear(const double *a, const double *b, const double *c)
{
    for (int k = 0; k < 3; k++) {
        int u = k, v = (k + 1) % 3;
        double pa[2] = {a[u], a[v]}, pb[2] = {b[u], b[v]}, pc[2] = {c[u], c[v]};
        if (geom_orient2d(pa, pb, pc) != 0)
            return 0;
    }
    return 1;
}

static inline iso_topo iso_topology(size_t nv, const double *xyz, size_t nt, const uint32_t *t)
{
    iso_topo r;
    memset(&r, 0, sizeof r);
    r.faces = (long)nt;
    unsigned char *used = calloc(nv + 1, 1);
    for (size_t i = 0; i < 3 * nt; i++)
        used[t[i]] = 1;
    for (size_t i = 0; i < nv; i++) {
        r.vertices += used[i];
        r.isolated_vertices += !used[i];
    }
    iso_he_rec *h = malloc(sizeof *h * (3 * nt + 1));
    for (size_t f = 0; f < nt; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = t[3 * f + k], b = t[3 * f + (k + 1) % 3];
            iso_he_rec *e = &h[3 * f + (size_t)k];
            e->lo = a < b ? a : b;
            e->hi = a < b ? b : a;
            e->from = a;
            e->face = (uint32_t)f;
        }
    qsort(h, 3 * nt, sizeof *h, iso_cmp_he);
    uint32_t *fp = malloc(sizeof(uint32_t) * (nt + 1));
    for (size_t i = 0; i < nt; i++)
        fp[i] = (uint32_t)i;
    uint32_t *bp = malloc(sizeof(uint32_t) * (nv + 1));
    unsigned char *bv = calloc(nv + 1, 1);
    for (size_t i = 0; i < nv; i++)
        bp[i] = (uint32_t)i;
    for (size_t i = 0; i < 3 * nt;) {
        size_t j = i;
        while (j < 3 * nt && iso_cmp_he(&h[i], &h[j]) == 0)
            j++;
        r.edges++;
        size_t m = j - i;
        if (m == 1) {
            r.boundary_edges++;
            iso_uf_join(bp, h[i].lo, h[i].hi);
            bv[h[i].lo] = bv[h[i].hi] = 1;
        } else if (m == 2) {
            if (h[i].from == h[i + 1].from)
                r.misoriented_edges++;
            iso_uf_join(fp, h[i].face, h[i + 1].face);
        } else {
            r.nonmanifold_edges++;
            for (size_t q = i + 1; q < j; q++)
                iso_uf_join(fp, h[i].face, h[q].face);
        }
        i = j;
    }
    for (size_t i = 0; i < nt; i++)
        r.components += iso_uf_find(fp, (uint32_t)i) == i;
    for (size_t i = 0; i < nv; i++)
        r.boundary_loops += bv[i] && iso_uf_find(bp, (uint32_t)i) == i;
    r.euler = r.vertices - r.edges + r.faces;

    /* Fans: around each vertex, join the corners of its triangles that
     * share an edge at the vertex; more than one group = several fans. */
    {
        /* corner c = 3 f + k at vertex t[c]; an edge (v, w) appears in the
         * two triangles containing it, each has a corner at v. */
        uint32_t *cp = malloc(sizeof(uint32_t) * (3 * nt + 1));
        for (size_t c = 0; c < 3 * nt; c++)
            cp[c] = (uint32_t)c;
        for (size_t i = 0; i < 3 * nt;) {
            size_t j = i;
            while (j < 3 * nt && iso_cmp_he(&h[i], &h[j]) == 0)
                j++;
            /* corners at lo and at hi of each triangle of this edge */
            uint32_t first_lo = UINT32_MAX, first_hi = UINT32_MAX;
            for (size_t q = i; q < j; q++) {
                uint32_t f = h[q].face;
                for (int k = 0; k < 3; k++) {
                    uint32_t c = 3 * f + (uint32_t)k;
                    if (t[c] == h[i].lo) {
                        if (first_lo == UINT32_MAX)
                            first_lo = c;
                        else
                            iso_uf_join(cp, first_lo, c);
                    } else if (t[c] == h[i].hi) {
                        if (first_hi == UINT32_MAX)
                            first_hi = c;
                        else
                            iso_uf_join(cp, first_hi, c);
                    }
                }
            }
            i = j;
        }
        long *groups = calloc(nv + 1, sizeof(long));
        for (size_t c = 0; c < 3 * nt; c++)
            if (iso_uf_find(cp, (uint32_t)c) == c)
                groups[t[c]]++;
        for (size_t v = 0; v < nv; v++)
            r.nonmanifold_vertices += groups[v] > 1;
        free(groups);
        free(cp);
    }

    uint32_t *s = malloc(sizeof(uint32_t) * (3 * nt + 3));
    for (size_t f = 0; f < nt; f++) {
        uint32_t a = t[3 * f], b = t[3 * f + 1], c = t[3 * f + 2], x;
        if (a > b) { x = a; a = b; b = x; }
        if (b > c) { x = b; b = c; c = x; }
        if (a > b) { x = a; a = b; b = x; }
        s[3 * f] = a;
        s[3 * f + 1] = b;
        s[3 * f + 2] = c;
        if (a == b || b == c)
            r.degenerate_faces++;
        else if (iso_collinear(xyz + 3 * (size_t)a, xyz + 3 * (size_t)b, xyz + 3 * (size_t)c))
            r.degenerate_faces++;
    }
    qsort(s, nt, 3 * sizeof(uint32_t), iso_cmp_u3);
    for (size_t f = 1; f < nt; f++)
        r.duplicate_faces += iso_cmp_u3(s + 3 * f, s + 3 * (f - 1)) == 0;

    uint32_t *order = malloc(sizeof(uint32_t) * (nv + 1));
    size_t nu = 0;
    for (size_t i = 0; i < nv; i++)
        if (used[i])
            order[nu++] = (uint32_t)i;
    iso_sort_base = xyz;
    qsort(order, nu, sizeof(uint32_t), iso_cmp_pt);
    for (size_t i = 1; i < nu; i++)
        r.duplicate_points += iso_cmp_pt(&order[i], &order[i - 1]) == 0;
    free(order);
    free(s);
    free(bv);
    free(bp);
    free(fp);
    free(h);
    free(used);
    return r;
}

/* Closed, manifold, consistently oriented, without duplicates/degenerates. */
static inline int iso_topo_clean(const iso_topo *r)
{
    return r->nonmanifold_edges == 0 && r->misoriented_edges == 0 &&
           r->nonmanifold_vertices == 0 && r->duplicate_points == 0 && r->duplicate_faces == 0 &&
           r->degenerate_faces == 0 && r->isolated_vertices == 0;
}

/* Signed volume enclosed by a closed triangle mesh (divergence theorem). */
static inline double iso_volume(const double *xyz, size_t nt, const uint32_t *t)
{
    double v = 0;
    for (size_t f = 0; f < nt; f++) {
        const double *a = xyz + 3 * (size_t)t[3 * f], *b = xyz + 3 * (size_t)t[3 * f + 1],
                     *c = xyz + 3 * (size_t)t[3 * f + 2];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
             a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6.0;
}

/* -------------------------------------------------------------- fields */

/* Sphere of radius 1 at the origin (exact signed distance). */
static inline double iso_f_sphere(void *u, const double p[3])
{
    (void)u;
    return sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1.0;
}

/* gradient callbacks return the value too (geom_implicit_grad_fn) */
static inline double iso_g_sphere(void *u, const double p[3], double g[3])
{
    (void)u;
    double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++)
        g[k] = r > 0 ? p[k] / r : 0;
    return r - 1.0;
}

/* Torus around z, radii 1 and 0.4 (exact signed distance). */
static inline double iso_f_torus(void *u, const double p[3])
{
    (void)u;
    double q = sqrt(p[0] * p[0] + p[1] * p[1]) - 1.0;
    return sqrt(q * q + p[2] * p[2]) - 0.4;
}

/* Two linked tori (radii 1, 0.3): one around z at the origin, one around y
 * centred at (1, 0, 0). */
static inline double iso_f_linked(void *u, const double p[3])
{
    (void)u;
    double q = sqrt(p[0] * p[0] + p[1] * p[1]) - 1.0;
    double a = sqrt(q * q + p[2] * p[2]) - 0.3;
    double x = p[0] - 1.0, y = p[2], z = p[1];
    q = sqrt(x * x + y * y) - 1.0;
    double b = sqrt(q * q + z * z) - 0.3;
    return a < b ? a : b;
}

/* Gyroid sin x cos y + sin y cos z + sin z cos x. */
static inline double iso_f_gyroid(void *u, const double p[3])
{
    (void)u;
    return sin(p[0]) * cos(p[1]) + sin(p[1]) * cos(p[2]) + sin(p[2]) * cos(p[0]);
}

static inline double iso_g_gyroid(void *u, const double p[3], double g[3])
{
    double sx = sin(p[0]), cx = cos(p[0]), sy = sin(p[1]), cy = cos(p[1]), sz = sin(p[2]),
           cz = cos(p[2]);
    g[0] = cx * cy - sz * sx;
    g[1] = -sx * sy + cy * cz;
    g[2] = -sy * sz + cz * cx;
    return iso_f_gyroid(u, p);
}

/* Three metaballs (inverse-square potential) merged into one blob. */
static inline double iso_f_meta(void *u, const double p[3])
{
    (void)u;
    static const double c[3][3] = {{0, 0, 0}, {0.9, 0.2, 0}, {-0.3, 0.8, 0.4}};
    double s = 0;
    for (int i = 0; i < 3; i++) {
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += (p[k] - c[i][k]) * (p[k] - c[i][k]);
        s += 1.0 / (d + 1e-9);
    }
    return 2.5 - s;
}

/* Genus 3: the union of three tori (radii 0.8, 0.3) around z centred at
 * x = -1.2, 0, 1.2, each overlapping the next. */
static inline double iso_f_genus3(void *u, const double p[3])
{
    (void)u;
    static const double cx[3] = {-1.2, 0, 1.2};
    double m = HUGE_VAL;
    for (int i = 0; i < 3; i++) {
        double x = p[0] - cx[i], y = p[1];
        double q = sqrt(x * x + y * y) - 0.8;
        double d = sqrt(q * q + p[2] * p[2]) - 0.3;
        if (d < m)
            m = d;
    }
    return m;
}

#endif
