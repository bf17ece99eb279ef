/* Axis-aligned and oriented boxes by the slab method (Kay and Kajiya 1986),
 * exact per-face entry/exit, made conservative as the BVH's box tests (Ize,
 * "Robust BVH Ray Traversal", JCGT 2013): a slab distance
 * fl(fl(L - o) * fl(1/d)) is within gamma(3) relative of the exact (L - o)/d,
 * so the entry (the largest near distance) and the exit (the smallest far
 * one) are each moved out by 2 gamma(3) of their magnitude before they are
 * compared. A ray through a corner or along an edge of the box, where the
 * rounded distances of two axes meet, is then never lost to rounding; when
 * only the widening makes the interval non-empty the two distances are
 * within rounding of each other and are reported in order.
 * prm (box): min (0..2), max (3..5).
 * prm (obox): centre (0..2), unit axes (3..11), half extents (12..14). */
#include "ray/ray_internal.h"

/* Interval of the ray (o, d) inside [lo, hi] (per axis, in box frame):
 * returns 0 if empty; face indices 0..5 of entry and exit. */
static int slab(const double *o, const double *d, const double *lo, const double *hi, double *t0,
                double *t1, int *f0, int *f1)
{
    double a = -INFINITY, b = INFINITY;
    int fa = -1, fb = -1, k;
    for (k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return 0;
            continue;
        }
        {
            double inv = 1.0 / d[k];
            double tn = (lo[k] - o[k]) * inv, tf = (hi[k] - o[k]) * inv;
            int fn = 2 * k, ff = 2 * k + 1;
            if (tn > tf) {
                double tt = tn; tn = tf; tf = tt;
                fn = 2 * k + 1; ff = 2 * k;
            }
            if (tn > a) { a = tn; fa = fn; }
            if (tf < b) { b = tf; fb = ff; }
        }
    }
    {
        const double w = 2 * geom__gamma(3);
        /* an infinite a or b (a reciprocal overflowed) gives inf - inf: NaN,
         * a miss (the exact distance is then beyond any finite t) */
        if (!(a - fabs(a) * w <= b + fabs(b) * w)) return 0;
    }
    if (a > b) { /* touched at a corner or an edge: a and b are the same point but for rounding */
        double tt = a; a = b; b = tt;
    }
    *t0 = a; *t1 = b; *f0 = fa; *f1 = fb;
    return 1;
}

/* Fill one box hit in the box frame (point in box frame: pl). */
static void face_fill(geom_ray_hit *h, int face, const double *pl, const double *lo, const double *hi)
{
    int ax = face / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
    double n[3] = {0, 0, 0};
    n[ax] = (face & 1) ? 1 : -1;
    h->ng.x = h->ns.x = n[0];
    h->ng.y = h->ns.y = n[1];
    h->ng.z = h->ns.z = n[2];
    h->prim = (uint32_t)face;
    h->u = hi[a1] > lo[a1] ? (pl[a1] - lo[a1]) / (hi[a1] - lo[a1]) : 0;
    h->v = hi[a2] > lo[a2] ? (pl[a2] - lo[a2]) / (hi[a2] - lo[a2]) : 0;
}

static geom_status box_frame(const double *o, const double *d, const double *lo, const double *hi,
                             const geom_ray *r, int mode, geom__rhits *out, const double *axes,
                             const double *ctr)
{
    double t0, t1, ts[2];
    int f0, f1, fs[2], i;
    if (!slab(o, d, lo, hi, &t0, &t1, &f0, &f1)) return GEOM_OK;
    if (f0 < 0 || f1 < 0) return GEOM_OK; /* cannot happen for a nonzero dir */
    ts[0] = t0; ts[1] = t1; fs[0] = f0; fs[1] = f1;
    for (i = 0; i < 2; i++) {
        double pl[3];
        int k, ax = fs[i] / 2;
        geom_ray_hit *h = geom__push_t(out, r, ts[i]);
        if (!h) { if (out->failed) return GEOM_ERR_NOMEM; continue; }
        for (k = 0; k < 3; k++) pl[k] = o[k] + ts[i] * d[k];
        pl[ax] = (fs[i] & 1) ? hi[ax] : lo[ax];
        for (k = 0; k < 3; k++) pl[k] = fmin(fmax(pl[k], lo[k]), hi[k]);
        face_fill(h, fs[i], pl, lo, hi);
        h->enter = i == 0;
        if (axes) {
            /* Back to the parent frame. */
            geom_vec3 nl = h->ng, p = geom__v3(ctr), n;
            for (k = 0; k < 3; k++) {
                p.x += axes[3 * k] * pl[k];
                p.y += axes[3 * k + 1] * pl[k];
                p.z += axes[3 * k + 2] * pl[k];
            }
            n.x = axes[0] * nl.x + axes[3] * nl.y + axes[6] * nl.z;
            n.y = axes[1] * nl.x + axes[4] * nl.y + axes[7] * nl.z;
            n.z = axes[2] * nl.x + axes[5] * nl.y + axes[8] * nl.z;
            h->ng = h->ns = n;
            h->point = p;
            {
                double s = fabs(ctr[0]) + fabs(ctr[1]) + fabs(ctr[2]) + fabs(pl[0]) + fabs(pl[1]) +
                           fabs(pl[2]);
                double g = geom__gamma(8) * s;
                h->p_error.x = h->p_error.y = h->p_error.z = g;
            }
        } else {
            h->point.x = pl[0]; h->point.y = pl[1]; h->point.z = pl[2];
            h->p_error.x = h->p_error.y = h->p_error.z = 0; /* face coordinate exact */
            {
                geom_vec3 pe = geom__perr_ray(r, ts[i]);
                h->p_error = pe;
                if (ax == 0) h->p_error.x = 0;
                if (ax == 1) h->p_error.y = 0;
                if (ax == 2) h->p_error.z = 0;
            }
        }
        h->t_error = geom__terr(r, ts[i], 0, h->ng);
        if (mode == GEOM__RAY_ANY) break;
    }
    return GEOM_OK;
}

geom_status geom__ray_box(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    double o[3] = {r->origin.x, r->origin.y, r->origin.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z};
    return box_frame(o, d, nd->prm, nd->prm + 3, r, mode, out, NULL, NULL);
}

geom_status geom__ray_obox(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    const double *c = nd->prm, *ax = nd->prm + 3, *h = nd->prm + 12;
    double rel[3] = {r->origin.x - c[0], r->origin.y - c[1], r->origin.z - c[2]};
    double d0[3] = {r->dir.x, r->dir.y, r->dir.z}, o[3], d[3], lo[3];
    int k;
    for (k = 0; k < 3; k++) {
        o[k] = ax[3 * k] * rel[0] + ax[3 * k + 1] * rel[1] + ax[3 * k + 2] * rel[2];
        d[k] = ax[3 * k] * d0[0] + ax[3 * k + 1] * d0[1] + ax[3 * k + 2] * d0[2];
        lo[k] = -h[k];
    }
    return box_frame(o, d, lo, h, r, mode, out, ax, c);
}
