/* Distance index over a triangle mesh: a copy of the mesh, its SAH BVH, and
 * per BVH node the dipole data of the fast winding number (Barill et al.
 * 2018): area-weighted centre, summed area vector, area, and a radius
 * bounding every vertex of the subtree. */
#include "spatial/spatial_internal.h"

#include <string.h>

void geom_meshdist_destroy(geom_meshdist *m)
{
    if (!m)
        return;
    const geom_allocator *a = m->has_alloc ? &m->alloc : NULL;
    size_t nn = 0;
    geom_bvh_nodes(m->bvh, &nn);
    geom__free(a, m->dip, (nn ? nn : 1) * sizeof *m->dip);
    geom__free(a, m->tv, (m->nt ? 9 * m->nt : 1) * sizeof *m->tv);
    geom_bvh_destroy(m->bvh);
    geom__free(a, m->pos, 3 * m->nv * sizeof *m->pos);
    geom__free(a, m->tris, 3 * m->nt * sizeof *m->tris);
    geom__free(a, m, sizeof *m);
}

const geom_bvh *geom_meshdist_bvh(const geom_meshdist *m)
{
    return m ? m->bvh : NULL;
}

size_t geom_meshdist_bytes(const geom_meshdist *m)
{
    if (!m)
        return 0;
    size_t nn = 0;
    geom_bvh_nodes(m->bvh, &nn);
    return sizeof *m + geom_bvh_bytes(m->bvh) + nn * sizeof *m->dip + m->nt * 9 * sizeof(double) +
           m->nv * 3 * sizeof(double) + m->nt * 3 * sizeof(uint32_t);
}

static double len3(const double *v)
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* v / |v|, or 0 for the zero vector. */
static void unit3(const double *v, double *u)
{
    double l = len3(v);
    for (int q = 0; q < 3; q++)
        u[q] = l > 0 ? v[q] / l : 0.0;
}

/* Dipole data bottom-up (children follow their parent in the layout). */
static void dipoles(geom_meshdist *m)
{
    size_t nn;
    const geom_bvh_node *nodes = geom_bvh_nodes(m->bvh, &nn);
    const uint32_t *prims = geom_bvh_prim_indices(m->bvh, NULL);
    for (size_t j = nn; j-- > 0;) {
        const geom_bvh_node *nd = &nodes[j];
        geom__dipole *d = &m->dip[j];
        memset(d, 0, sizeof *d);
        if (nd->count) {
            double cs[3] = {0, 0, 0}, cu[3] = {0, 0, 0};
            for (uint32_t k = 0; k < nd->count; k++) {
                const uint32_t *v = m->tris + 3 * (size_t)prims[nd->index + k];
                const double *a = m->pos + 3 * (size_t)v[0], *b = m->pos + 3 * (size_t)v[1],
                             *c = m->pos + 3 * (size_t)v[2];
                double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
                double n[3] = {0.5 * (e1[1] * e2[2] - e1[2] * e2[1]),
                               0.5 * (e1[2] * e2[0] - e1[0] * e2[2]),
                               0.5 * (e1[0] * e2[1] - e1[1] * e2[0])};
                double ar = len3(n);
                for (int q = 0; q < 3; q++) {
                    double cen = (a[q] + b[q] + c[q]) / 3.0;
                    d->n[q] += n[q];
                    cs[q] += ar * cen;
                    cu[q] += cen;
                }
                d->area += ar;
            }
            for (int q = 0; q < 3; q++)
                d->c[q] = d->area > 0 ? cs[q] / d->area : cu[q] / nd->count;
            double r = 0;
            for (uint32_t k = 0; k < nd->count; k++) {
                const uint32_t *v = m->tris + 3 * (size_t)prims[nd->index + k];
                for (int q = 0; q < 3; q++) {
                    const double *p = m->pos + 3 * (size_t)v[q];
                    double e[3] = {p[0] - d->c[0], p[1] - d->c[1], p[2] - d->c[2]};
                    double l = len3(e);
                    if (l > r)
                        r = l;
                }
            }
            d->r = r * (1.0 + 0x1p-50);
            double nu[3];
            unit3(d->n, nu);
            double dev = 0, i2 = 0, m1[3] = {0, 0, 0};
            for (uint32_t k = 0; k < nd->count; k++) {
                const uint32_t *v = m->tris + 3 * (size_t)prims[nd->index + k];
                const double *p[3] = {m->pos + 3 * (size_t)v[0], m->pos + 3 * (size_t)v[1],
                                      m->pos + 3 * (size_t)v[2]};
                double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
                double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
                double a[3] = {0.5 * (e1[1] * e2[2] - e1[2] * e2[1]),
                               0.5 * (e1[2] * e2[0] - e1[0] * e2[2]),
                               0.5 * (e1[0] * e2[1] - e1[1] * e2[0])};
                double ar = len3(a), g[3], spread = 0;
                for (int q = 0; q < 3; q++)
                    g[q] = (p[0][q] + p[1][q] + p[2][q]) / 3.0;
                for (int j = 0; j < 3; j++)
                    for (int q = 0; q < 3; q++)
                        spread += (p[j][q] - g[q]) * (p[j][q] - g[q]);
                double dv[3] = {a[0] - ar * nu[0], a[1] - ar * nu[1], a[2] - ar * nu[2]};
                double gc[3] = {g[0] - d->c[0], g[1] - d->c[1], g[2] - d->c[2]};
                dev += len3(dv);
                /* integral over the triangle of |x - c|^2 = A (|g - c|^2 +
                 * sum_k |v_k - g|^2 / 12) */
                i2 += ar * (gc[0] * gc[0] + gc[1] * gc[1] + gc[2] * gc[2] + spread / 12.0);
                for (int q = 0; q < 3; q++)
                    m1[q] += ar * gc[q];
            }
            double grow = 1.0 + (double)(nd->count + 8) * 0x1p-50;
            d->dev = dev * grow;
            d->i2 = i2 * grow;
            d->m1 = len3(m1) * grow + d->area * d->r * (double)(nd->count + 8) * 0x1p-50;
        } else {
            const geom__dipole *l = &m->dip[j + 1], *r = &m->dip[nd->index];
            d->area = l->area + r->area;
            for (int q = 0; q < 3; q++) {
                d->n[q] = l->n[q] + r->n[q];
                d->c[q] = d->area > 0 ? (l->area * l->c[q] + r->area * r->c[q]) / d->area
                                      : 0.5 * (l->c[q] + r->c[q]);
            }
            double el[3] = {l->c[0] - d->c[0], l->c[1] - d->c[1], l->c[2] - d->c[2]};
            double er[3] = {r->c[0] - d->c[0], r->c[1] - d->c[1], r->c[2] - d->c[2]};
            double rl = len3(el) + l->r, rr = len3(er) + r->r;
            d->r = (rl > rr ? rl : rr) * (1.0 + 0x1p-50);
            double nu[3], nl[3], nr[3];
            unit3(d->n, nu);
            unit3(l->n, nl);
            unit3(r->n, nr);
            double dl[3] = {nl[0] - nu[0], nl[1] - nu[1], nl[2] - nu[2]};
            double dr[3] = {nr[0] - nu[0], nr[1] - nu[1], nr[2] - nu[2]};
            d->dev = (l->dev + l->area * len3(dl) + r->dev + r->area * len3(dr)) * (1.0 + 0x1p-40);
            double ll = len3(el), lr = len3(er);
            d->i2 = (l->i2 + 2.0 * ll * l->m1 + l->area * ll * ll + r->i2 + 2.0 * lr * r->m1 +
                     r->area * lr * lr) * (1.0 + 0x1p-40);
            double m1[3];
            for (int q = 0; q < 3; q++)
                m1[q] = l->area * el[q] + r->area * er[q];
            d->m1 = (len3(m1) + l->m1 + r->m1) * (1.0 + 0x1p-40) + d->area * d->r * 0x1p-44;
        }
    }
}

geom_status geom_meshdist_create(const double *positions, size_t nv, const uint32_t *tris,
                                 size_t nt, const geom_meshdist_options *opt, geom_meshdist **out,
                                 geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (nt && (!positions || !tris)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "mesh distance: NULL argument");
    geom_meshdist_options o;
    memset(&o, 0, sizeof o);
    if (opt)
        o = *opt;
    const geom_allocator *a = o.alloc;
    geom_bvh_options bo = {0};
    bo.max_leaf_size = o.max_leaf_size;
    bo.threads = o.threads;
    bo.alloc = a;
    geom_bvh *bvh = NULL;
    geom_status st = geom_bvh_build_triangles(positions, nv, tris, nt, &bo, &bvh, diag);
    if (st != GEOM_OK)
        return st;
    geom_meshdist *m = geom__alloc(a, sizeof *m);
    if (!m) {
        geom_bvh_destroy(bvh);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "mesh distance: out of memory");
    }
    memset(m, 0, sizeof *m);
    if (a) {
        m->alloc = *a;
        m->has_alloc = 1;
    }
    m->bvh = bvh;
    m->beta = o.beta == 0 ? 2.0 : o.beta;
    m->nv = nv;
    m->nt = nt;
    size_t nn;
    geom_bvh_nodes(bvh, &nn);
    m->pos = geom__alloc(a, 3 * nv * sizeof *m->pos);
    m->tris = geom__alloc(a, 3 * nt * sizeof *m->tris);
    m->dip = geom__alloc(a, (nn ? nn : 1) * sizeof *m->dip);
    m->tv = geom__alloc(a, (nt ? 9 * nt : 1) * sizeof *m->tv);
    geom__advise_huge(a, m->dip, (nn ? nn : 1) * sizeof *m->dip, GEOM__BVH_HUGE_MIN);
    geom__advise_huge(a, m->tv, (nt ? 9 * nt : 1) * sizeof *m->tv, GEOM__BVH_HUGE_MIN);
    if (!m->pos || !m->tris || !m->dip || !m->tv) {
        geom_meshdist_destroy(m);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "mesh distance: out of memory");
    }
    if (nv)
        memcpy(m->pos, positions, 3 * nv * sizeof *m->pos);
    if (nt)
        memcpy(m->tris, tris, 3 * nt * sizeof *m->tris);
    dipoles(m);
    const uint32_t *prims = geom_bvh_prim_indices(bvh, NULL);
    for (size_t i = 0; i < nt; i++)
        for (int v = 0; v < 3; v++)
            memcpy(m->tv + 9 * i + 3 * v, positions + 3 * (size_t)tris[3 * (size_t)prims[i] + (size_t)v],
                   3 * sizeof(double));
    m->tolerance = o.tolerance > 0 ? o.tolerance : 0.0;
    m->area_total = nn ? m->dip[0].area : 0.0;
    *out = m;
    return GEOM_OK;
}
