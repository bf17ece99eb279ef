/*
 * Watertight trimmed tessellation of a B-rep (see geom_step_tessellate in
 * step.h): edges sampled once in 3D, loops inverted into each face's
 * parameter domain (unwrapped across seams, joined through poles), faces
 * meshed there by constrained Delaunay triangulation (cdt.c) refined at
 * the worst sample of every triangle over the chordal or angle tolerance,
 * one geom_mesh built at the end.
 */
#include "step/cdt.h"
#include "step/step_internal.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct buf {
    void *p;
    size_t n, cap, elem;
} buf;

static geom_status bpush(const geom_allocator *a, buf *b, const void *x)
{
    return geom__push(a, &b->p, &b->n, &b->cap, b->elem, x);
}

static void bfree(const geom_allocator *a, buf *b)
{
    geom__free(a, b->p, b->cap * b->elem);
    b->p = NULL;
    b->n = b->cap = 0;
}

typedef struct sample {
    double t;
    uint32_t vid;
} sample;

typedef struct lpt { /* a loop point in the face's domain */
    double uv[2];
    uint32_t vid;
    int free_u; /* at a pole: u undetermined */
    int gap;    /* joins the previous point through a pole */
} lpt;

typedef struct tess {
    const geom_brep *b;
    const geom_allocator *a;
    double tol, cos_angle;
    size_t max_tris;
    buf pos;      /* double[3] */
    buf samples;  /* sample */
    size_t *efirst, *ecount;
    buf tris;     /* uint32_t[3] */
    buf tface;    /* uint32_t */
    buf tuv;      /* double[6] */
    buf split;    /* uint32_t[2]: boundary segments a face could not meet the tolerance on */
    size_t evals;
    double edge_err, face_err;
    double err_sum;
    size_t err_n;
} tess;

static double d3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static double seg_dist(const double *p, const double *a, const double *b)
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double l = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double s = l > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l : 0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    double q[3] = {a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]};
    return d3(p, q);
}

static geom_status add_pos(tess *T, const double p[3], uint32_t *id)
{
    if (T->pos.n >= UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    *id = (uint32_t)T->pos.n;
    return bpush(T->a, &T->pos, p);
}

static const double *posof(const tess *T, uint32_t v)
{
    return (const double *)T->pos.p + 3 * (size_t)v;
}

/* ------------------------------------------------------------- edges */

static geom_status sample_edge(tess *T, uint32_t e)
{
    const geom_brep *b = T->b;
    const geom_brep_edge *E = &b->edges[e];
    const geom_brep_curve *c = &b->curves[E->curve];
    double t0 = E->t0, t1 = E->t1;
    int n0 = 1;
    if (c->type == GEOM_BREP_CURVE_CIRCLE || c->type == GEOM_BREP_CURVE_ELLIPSE)
        n0 = (int)ceil(fabs(t1 - t0) / (GEOM_PI / 4));
    else if (c->type == GEOM_BREP_CURVE_NURBS)
        n0 = 2 * (int)(c->nurbs.n - (size_t)c->nurbs.degree) + 2;
    if (n0 < 1)
        n0 = 1;
    if (n0 > 4096)
        n0 = 4096;
    T->efirst[e] = T->samples.n;
    sample s = {t0, b->edges[e].v0};
    geom_status st = bpush(T->a, &T->samples, &s);
    if (st)
        return st;
    /* depth-first bisection of each initial piece */
    double stack[64][2];
    for (int k = 0; k < n0; k++) {
        double a0 = t0 + (t1 - t0) * k / n0, a1 = t0 + (t1 - t0) * (k + 1) / n0;
        int sp = 0;
        stack[sp][0] = a0;
        stack[sp][1] = a1;
        sp++;
        while (sp > 0) {
            sp--;
            double ta = stack[sp][0], tb = stack[sp][1];
            double pa[3], pb[3], err = 0;
            geom__brep_curve_eval(c, ta, pa, NULL);
            geom__brep_curve_eval(c, tb, pb, NULL);
            for (int q = 1; q < 4; q++) {
                double pm[3];
                geom__brep_curve_eval(c, ta + (tb - ta) * q / 4, pm, NULL);
                double dd = seg_dist(pm, pa, pb);
                if (dd > err)
                    err = dd;
            }
            T->evals += 5;
            if (err > T->tol && sp < 60 && fabs(tb - ta) > 1e-12 * (1 + fabs(ta))) {
                double tm = 0.5 * (ta + tb);
                /* push the right half first so the left one is done first */
                stack[sp][0] = tm;
                stack[sp][1] = tb;
                sp++;
                stack[sp][0] = ta;
                stack[sp][1] = tm;
                sp++;
                continue;
            }
            if (err > T->edge_err)
                T->edge_err = err;
            int last = (k == n0 - 1) && tb == a1 && sp == 0;
            sample q;
            q.t = tb;
            if (last) {
                q.vid = E->v1;
            } else {
                double p[3];
                geom__brep_curve_eval(c, tb, p, NULL);
                if ((st = add_pos(T, p, &q.vid)) != GEOM_OK)
                    return st;
            }
            if ((st = bpush(T->a, &T->samples, &q)) != GEOM_OK)
                return st;
        }
    }
    T->ecount[e] = T->samples.n - T->efirst[e];
    return GEOM_OK;
}

/* ------------------------------------------------------------- faces */

typedef struct facectx {
    tess *T;
    const geom_brep_surface *S;
    uint32_t fi;
    double pu, pv; /* periods (0: none) */
    double gap;    /* largest edge gap */
} facectx;

static double wrap_near(double x, double ref, double period)
{
    if (period <= 0)
        return x;
    return x + period * round((ref - x) / period);
}

/* uv of a 3D point on the face's surface, unwrapped near ref. */
static double invert(facectx *F, const double p[3], const double *guess, const double *ref,
                     double uv[2], int *free_u)
{
    const geom_brep *b = F->T->b;
    double d = geom__brep_surface_invert(b, F->S, p, guess, guess != NULL, uv);
    F->T->evals += 8;
    if (ref) {
        uv[0] = wrap_near(uv[0], ref[0], F->pu);
        uv[1] = wrap_near(uv[1], ref[1], F->pv);
    }
    double q[3], su[3], sv[3];
    geom__brep_surface_eval(b, F->S, uv[0], uv[1], q, su, sv);
    double lu = sqrt(su[0] * su[0] + su[1] * su[1] + su[2] * su[2]);
    double lv = sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]);
    *free_u = F->pu > 0 && lu <= 1e-9 * (lv + 1e-300) ? 1 : 0;
    return d;
}

/* Points of one coedge in the face's domain. */
static geom_status coedge_uv(facectx *F, const geom_brep_coedge *ce, const double *ref, buf *out)
{
    tess *T = F->T;
    const geom_brep *b = T->b;
    const geom_brep_edge *E = &b->edges[ce->edge];
    size_t n = T->ecount[ce->edge], f = T->efirst[ce->edge];
    const sample *S = (const sample *)T->samples.p + f;
    size_t start = out->n;
    double last[2];
    int have_last = ref != NULL;
    if (ref)
        memcpy(last, ref, sizeof last);
    for (size_t k = 0; k < n; k++) {
        const sample *s = &S[ce->reversed ? n - 1 - k : k];
        const double *p = posof(T, s->vid);
        double guess[2], *g = NULL;
        /* the pcurve's image as a guess (NURBS surfaces: the parameters are unitless) */
        if (F->S->type == GEOM_BREP_SURFACE_NURBS) {
            double best = DBL_MAX;
            for (int j = 0; j < 2; j++) {
                if (E->pcurve[j] == GEOM_INVALID_INDEX || E->pcurve_surface[j] == GEOM_INVALID_INDEX)
                    continue;
                if (b->surfaces[E->pcurve_surface[j]].entity != F->S->entity)
                    continue;
                double q[2];
                geom__brep_curve_eval(&b->curves[E->pcurve[j]], s->t, q, NULL);
                double dd = have_last ? hypot(q[0] - last[0], q[1] - last[1]) : 0;
                if (dd < best) {
                    best = dd;
                    guess[0] = q[0];
                    guess[1] = q[1];
                    g = guess;
                }
            }
            if (g) {
                double sp[3];
                geom__brep_surface_eval(b, F->S, g[0], g[1], sp, NULL, NULL);
                double gap = d3(sp, p);
                if (gap > F->gap)
                    F->gap = gap;
            } else if (have_last) {
                g = last;
            }
        }
        lpt L;
        memset(&L, 0, sizeof L);
        double d = invert(F, p, g, have_last ? last : NULL, L.uv, &L.free_u);
        if (d > F->gap)
            F->gap = d;
        L.vid = s->vid;
        geom_status st = bpush(T->a, out, &L);
        if (st)
            return st;
        if (!L.free_u) {
            memcpy(last, L.uv, sizeof last);
            have_last = 1;
        }
    }
    /* poles: u from the neighbour along the same edge */
    lpt *P = (lpt *)out->p;
    for (size_t k = start; k < out->n; k++) {
        if (!P[k].free_u)
            continue;
        if (k + 1 < out->n && !P[k + 1].free_u)
            P[k].uv[0] = P[k + 1].uv[0];
        else if (k > start && !P[k - 1].free_u)
            P[k].uv[0] = P[k - 1].uv[0];
    }
    return GEOM_OK;
}

static double loop_area(const lpt *P, size_t n)
{
    double a = 0;
    for (size_t k = 0; k < n; k++) {
        const double *p = P[k].uv, *q = P[(k + 1) % n].uv;
        a += p[0] * q[1] - q[0] * p[1];
    }
    return 0.5 * a;
}

/* The loop's points in the domain, closed implicitly (last joins first).
 * A loop that closes in 3D but not in the domain, its last point one
 * period away from its first (a circle around a cylinder with no seam
 * edge), is "open": shift receives that period vector, else (0, 0). */
static geom_status loop_uv(facectx *F, const geom_brep_loop *L, buf *out, int *ok, double shift[2])
{
    shift[0] = shift[1] = 0;
    tess *T = F->T;
    const geom_brep *b = T->b;
    buf tmp = {NULL, 0, 0, sizeof(lpt)};
    geom_status st = GEOM_OK;
    *ok = 1;
    out->n = 0;
    for (uint32_t k = 0; k < L->n && !st; k++) {
        const geom_brep_coedge *ce = &b->coedges[L->first + k];
        tmp.n = 0;
        double ref[2];
        int have = 0;
        for (size_t j = out->n; j-- > 0;) {
            const lpt *q = (const lpt *)out->p + j;
            if (!q->free_u) {
                memcpy(ref, q->uv, sizeof ref);
                have = 1;
                break;
            }
        }
        if ((st = coedge_uv(F, ce, have ? ref : NULL, &tmp)) != GEOM_OK)
            break;
        int second = 0; /* the edge's second use in this loop: a seam */
        for (uint32_t j = 0; j < k; j++)
            second |= b->coedges[L->first + j].edge == ce->edge;
        lpt *P = (lpt *)tmp.p;
        for (size_t j = 0; j < tmp.n && !st; j++) {
            P[j].gap = second ? 2 : 0;
            st = bpush(T->a, out, &P[j]);
        }
    }
    bfree(T->a, &tmp);
    if (st)
        return st;
    lpt *P = (lpt *)out->p;
    size_t n = out->n;
    const geom_brep_face *fc = &b->faces[F->fi];
    int want = (fc->same_sense ? 1 : -1) * (L->orientation ? 1 : -1);
    double area = loop_area(P, n);
    /* a seam used twice whose second use must run on the far side */
    if (F->pu > 0 && area * want <= 1e-12 * F->pu * F->pu) {
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            for (size_t k = 0; k < n; k++)
                if (P[k].gap == 2)
                    P[k].uv[0] += sgn * F->pu;
            area = loop_area(P, n);
            if (area * want > 0)
                break;
            for (size_t k = 0; k < n; k++)
                if (P[k].gap == 2)
                    P[k].uv[0] -= sgn * F->pu;
        }
    }
    /* drop repeated points; the same vertex at another (u, v) is a pole */
    size_t m = 0;
    for (size_t k = 0; k < n; k++) {
        lpt q = P[k];
        q.gap = 0;
        if (m > 0 && P[m - 1].vid == q.vid) {
            if (fabs(P[m - 1].uv[0] - q.uv[0]) + fabs(P[m - 1].uv[1] - q.uv[1]) <= 1e-12)
                continue;
            q.gap = 1;
        }
        P[m++] = q;
    }
    n = out->n = m;
    if (n >= 2 && P[n - 1].vid == P[0].vid) {
        if (fabs(P[n - 1].uv[0] - P[0].uv[0]) + fabs(P[n - 1].uv[1] - P[0].uv[1]) <= 1e-12)
            out->n = --n;
        else
            P[0].gap = 1;
    }
    if (n < 3) {
        *ok = 0;
        return GEOM_OK;
    }
    /* a loop through a pole may need the part after the first gap shifted
     * by a period so that it encloses the face on its left */
    size_t g = 0;
    for (size_t k = 1; k < n; k++)
        if (P[k].gap) {
            g = k;
            break;
        }
    area = loop_area(P, n);
    if (g && F->pu > 0 && (area * want <= 0 || L->outer)) {
        for (int sgn = -1; sgn <= 1 && area * want <= 0; sgn += 2) {
            for (size_t k = g; k < n; k++)
                P[k].uv[0] += sgn * F->pu;
            area = loop_area(P, n);
            if (area * want <= 0)
                for (size_t k = g; k < n; k++)
                    P[k].uv[0] -= sgn * F->pu;
        }
    }
    /* every gap must be a pole (one 3D point all along), or, when it is the
     * loop's only gap, at its closure, and one period long: an open loop */
    size_t ngaps = 0;
    for (size_t k = 0; k < n; k++)
        ngaps += P[k].gap != 0;
    for (size_t k = 0; k < n; k++) {
        if (!P[k].gap)
            continue;
        const lpt *a = &P[(k + n - 1) % n], *c = &P[k];
        double q[3];
        geom__brep_surface_eval(b, F->S, 0.5 * (a->uv[0] + c->uv[0]), 0.5 * (a->uv[1] + c->uv[1]), q,
                                NULL, NULL);
        if (d3(q, posof(T, c->vid)) <= 10 * T->tol + 1e-9)
            continue;
        double du = a->uv[0] - c->uv[0], dv = a->uv[1] - c->uv[1];
        double ku = F->pu > 0 ? round(du / F->pu) : 0, kv = F->pv > 0 ? round(dv / F->pv) : 0;
        if (k != 0 || ngaps != 1 || (ku == 0 && kv == 0) || fabs(du - ku * F->pu) > 1e-6 ||
            fabs(dv - kv * F->pv) > 1e-6) {
            *ok = 0;
            return GEOM_OK;
        }
        shift[0] = ku * F->pu;
        shift[1] = kv * F->pv;
        P[n - 1].uv[0] = P[0].uv[0] + shift[0];
        P[n - 1].uv[1] = P[0].uv[1] + shift[1];
        P[0].gap = 0;
    }
    return GEOM_OK;
}

/* Interior points of the straight (u, v) segment from p to q, bisected until
 * every chord is within the tolerance of the surface (sampled at its quarter
 * points), with their 3D positions: an added seam. */
static geom_status seam_points(facectx *F, const double p[2], const double q[2], buf *out)
{
    tess *T = F->T;
    double stack[64][2];
    int sp = 0;
    stack[sp][0] = 0;
    stack[sp][1] = 1;
    sp++;
    geom_status st = GEOM_OK;
    while (sp > 0 && !st) {
        sp--;
        double ta = stack[sp][0], tb = stack[sp][1], pa[3], pb[3], err = 0;
        geom__brep_surface_eval(T->b, F->S, p[0] + ta * (q[0] - p[0]), p[1] + ta * (q[1] - p[1]), pa,
                                NULL, NULL);
        geom__brep_surface_eval(T->b, F->S, p[0] + tb * (q[0] - p[0]), p[1] + tb * (q[1] - p[1]), pb,
                                NULL, NULL);
        for (int k = 1; k < 4; k++) {
            double t = ta + (tb - ta) * k / 4, pm[3];
            geom__brep_surface_eval(T->b, F->S, p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), pm,
                                    NULL, NULL);
            err = fmax(err, seg_dist(pm, pa, pb));
        }
        T->evals += 5;
        if (err > T->tol && sp < 60 && tb - ta > 1e-9) {
            double tm = 0.5 * (ta + tb);
            stack[sp][0] = tm, stack[sp][1] = tb, sp++;
            stack[sp][0] = ta, stack[sp][1] = tm, sp++;
            continue;
        }
        if (tb >= 1)
            break;
        lpt L;
        memset(&L, 0, sizeof L);
        L.uv[0] = p[0] + tb * (q[0] - p[0]);
        L.uv[1] = p[1] + tb * (q[1] - p[1]);
        if ((st = add_pos(T, pb, &L.vid)) == GEOM_OK)
            st = bpush(T->a, out, &L);
    }
    return st;
}

/* A periodic face bounded by two open loops (an annulus in the domain once
 * unwrapped: the side of a cylinder between two circles, no seam edge):
 * joined into one loop through an added seam, from loop A's first point to
 * the nearest point of loop B, sampled once and used on both sides (the
 * second use one period over), as a seam edge would be. Other loops (holes)
 * are moved by whole periods between the seam's two copies. Loops are
 * all[starts[l] ..], shifts[l] each loop's period vector (0, 0: closed). */
static geom_status join_open_loops(facectx *F, buf *all, buf *starts, const buf *shifts)
{
    tess *T = F->T;
    size_t nl = starts->n, open[2], nopen = 0;
    const double *sh = (const double *)shifts->p;
    const size_t *S0 = (const size_t *)starts->p;
    for (size_t l = 0; l < nl; l++)
        if (sh[2 * l] != 0 || sh[2 * l + 1] != 0) {
            if (nopen == 2)
                return GEOM_ERR_DEGENERATE;
            open[nopen++] = l;
        }
    if (nopen == 0)
        return GEOM_OK;
    const double *sA = sh + 2 * open[0], *sB = sh + 2 * open[1];
    if (nopen != 2 || sA[0] != -sB[0] || sA[1] != -sB[1])
        return GEOM_ERR_DEGENERATE;
#define LOOP_END(l) ((l) + 1 < nl ? S0[(l) + 1] : all->n)
    const lpt *A = (const lpt *)all->p + S0[open[0]], *B = (const lpt *)all->p + S0[open[1]];
    size_t na = LOOP_END(open[0]) - S0[open[0]], nb = LOOP_END(open[1]) - S0[open[1]];
    /* B's point nearest A's first, in 3D */
    size_t j = 0;
    double best = DBL_MAX;
    for (size_t k = 0; k + 1 < nb; k++) {
        double d = d3(posof(T, B[k].vid), posof(T, A[0].vid));
        if (d < best)
            best = d, j = k;
    }
    const double *am = A[na - 1].uv;
    double w[2] = {F->pu > 0 ? F->pu * round((am[0] - B[j].uv[0]) / F->pu) : 0,
                   F->pv > 0 ? F->pv * round((am[1] - B[j].uv[1]) / F->pv) : 0};
    double bj[2] = {B[j].uv[0] + w[0], B[j].uv[1] + w[1]};
    buf nall = {NULL, 0, 0, sizeof(lpt)}, seam = {NULL, 0, 0, sizeof(lpt)}, nst = {NULL, 0, 0, sizeof(size_t)};
    size_t zero = 0;
    geom_status st = seam_points(F, am, bj, &seam);
    if (!st)
        st = bpush(T->a, &nst, &zero);
    for (size_t k = 0; k < na && !st; k++)
        st = bpush(T->a, &nall, &A[k]);
    for (size_t k = 0; k < seam.n && !st; k++)
        st = bpush(T->a, &nall, (const lpt *)seam.p + k);
    for (size_t k = j; k + 1 < nb && !st; k++) {
        lpt q = B[k];
        q.uv[0] += w[0], q.uv[1] += w[1];
        st = bpush(T->a, &nall, &q);
    }
    for (size_t k = 0; k <= j && !st; k++) {
        lpt q = B[k];
        q.uv[0] += sB[0] + w[0], q.uv[1] += sB[1] + w[1];
        st = bpush(T->a, &nall, &q);
    }
    for (size_t k = seam.n; k-- > 0 && !st;) {
        lpt q = ((const lpt *)seam.p)[k];
        q.uv[0] -= sA[0], q.uv[1] -= sA[1];
        st = bpush(T->a, &nall, &q);
    }
    /* the other loops, moved between the two copies of the seam */
    int c = sA[0] != 0 ? 0 : 1;
    double per = c == 0 ? F->pu : F->pv;
    double lo = 0.5 * (A[0].uv[c] + bj[c] - sA[c]), dir = sA[c] > 0 ? 1 : -1;
    for (size_t l = 0; l < nl && !st; l++) {
        if (l == open[0] || l == open[1])
            continue;
        size_t s0 = S0[l], s1 = LOOP_END(l), at = nall.n;
        double mean = 0;
        for (size_t k = s0; k < s1; k++)
            mean += ((const lpt *)all->p)[k].uv[c];
        mean /= (double)(s1 - s0);
        double move = per * floor((lo - mean) * dir / per + 1) * dir;
        if ((st = bpush(T->a, &nst, &at)) != GEOM_OK)
            break;
        for (size_t k = s0; k < s1 && !st; k++) {
            lpt q = ((const lpt *)all->p)[k];
            q.uv[c] += move;
            st = bpush(T->a, &nall, &q);
        }
    }
#undef LOOP_END
    bfree(T->a, &seam);
    if (st) {
        bfree(T->a, &nall);
        bfree(T->a, &nst);
        return st;
    }
    bfree(T->a, all);
    bfree(T->a, starts);
    *all = nall;
    *starts = nst;
    return GEOM_OK;
}

typedef struct fpt {
    double uv[2];
    uint32_t vid;
    double off[3]; /* position - S(uv): the edge gap at a boundary point, else 0 */
} fpt;

/* Triangle t of C if it is alive and inside the face: its points V (from
 * pts) and their positions X. 0 otherwise. */
static int live_tri(const tess *T, const geom__cdt *C, const buf *pts, size_t t, fpt V[3],
                    const double *X[3])
{
    if (C->tri[t].dead || !C->tri[t].inside)
        return 0;
    for (int k = 0; k < 3; k++) {
        V[k] = ((const fpt *)pts->p)[C->tri[t].v[k]];
        X[k] = posof(T, V[k].vid);
    }
    return 1;
}

/* The surface at the barycentric point bc of triangle V, displaced by the
 * corners' offsets interpolated alike: what the triangle is measured
 * against, so that an edge curve lying off its surface (the file's own
 * gap, reported as edge_gap) is not taken for chordal error. */
static void surf_bary(facectx *F, const fpt *V, const double bc[3], double uv[2], double p[3])
{
    uv[0] = bc[0] * V[0].uv[0] + bc[1] * V[1].uv[0] + bc[2] * V[2].uv[0];
    uv[1] = bc[0] * V[0].uv[1] + bc[1] * V[1].uv[1] + bc[2] * V[2].uv[1];
    geom__brep_surface_eval(F->T->b, F->S, uv[0], uv[1], p, NULL, NULL);
    for (int j = 0; j < 3; j++)
        p[j] += bc[0] * V[0].off[j] + bc[1] * V[1].off[j] + bc[2] * V[2].off[j];
}

static void tri_error(facectx *F, const fpt *V, const double *const X[3], double *err, double best[2],
                      int *on_edge)
{
    static const double bc[7][3] = {{1. / 3, 1. / 3, 1. / 3}, {.5, .5, 0},  {0, .5, .5},
                                    {.5, 0, .5},             {2. / 3, 1. / 6, 1. / 6},
                                    {1. / 6, 2. / 3, 1. / 6}, {1. / 6, 1. / 6, 2. / 3}};
    *err = -1;
    *on_edge = -1;
    for (int s = 0; s < 7; s++) {
        double uv[2], x[3] = {0, 0, 0}, p[3];
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                x[j] += bc[s][k] * X[k][j];
        surf_bary(F, V, bc[s], uv, p);
        double d = d3(p, x);
        if (d > *err) {
            *err = d;
            best[0] = uv[0];
            best[1] = uv[1];
            *on_edge = s >= 1 && s <= 3 ? s - 1 : -1; /* edge index: 0=(0,1) 1=(1,2) 2=(2,0) */
        }
    }
    F->T->evals += 7;
}

static double normal_cos(facectx *F, const fpt *V)
{
    double n[3][3];
    for (int k = 0; k < 3; k++) {
        double p[3], su[3], sv[3];
        geom__brep_surface_eval(F->T->b, F->S, V[k].uv[0], V[k].uv[1], p, su, sv);
        n[k][0] = su[1] * sv[2] - su[2] * sv[1];
        n[k][1] = su[2] * sv[0] - su[0] * sv[2];
        n[k][2] = su[0] * sv[1] - su[1] * sv[0];
        double l = sqrt(n[k][0] * n[k][0] + n[k][1] * n[k][1] + n[k][2] * n[k][2]);
        if (!(l > 0))
            return 1; /* a pole: no normal to compare */
        for (int j = 0; j < 3; j++)
            n[k][j] /= l;
    }
    double c = 1;
    for (int k = 0; k < 3; k++) {
        const double *a = n[k], *bb = n[(k + 1) % 3];
        double d = a[0] * bb[0] + a[1] * bb[1] + a[2] * bb[2];
        if (d < c)
            c = d;
    }
    return c;
}

static geom_status mesh_face(tess *T, uint32_t fi, geom_brep_face_report *rep)
{
    const geom_brep *b = T->b;
    const geom_brep_face *fc = &b->faces[fi];
    facectx F;
    memset(&F, 0, sizeof F);
    F.T = T;
    F.S = &b->surfaces[fc->surface];
    F.fi = fi;
    F.pu = F.S->u_periodic ? 2 * GEOM_PI : 0;
    F.pv = F.S->v_periodic ? 2 * GEOM_PI : 0;
    buf pts = {NULL, 0, 0, sizeof(fpt)};   /* cdt vertex -> uv, vid (after the 3 super points) */
    buf loop = {NULL, 0, 0, sizeof(lpt)};
    buf segs = {NULL, 0, 0, sizeof(int32_t) * 2};
    geom__cdt C;
    memset(&C, 0, sizeof C);
    geom_status st = GEOM_OK;
    double box[4] = {DBL_MAX, -DBL_MAX, DBL_MAX, -DBL_MAX};
    /* loops to the domain */
    buf all = {NULL, 0, 0, sizeof(lpt)};
    buf starts = {NULL, 0, 0, sizeof(size_t)};
    buf shifts = {NULL, 0, 0, 2 * sizeof(double)};
    for (uint32_t l = 0; l < fc->nloops && !st; l++) {
        const geom_brep_loop *L = &b->loops[fc->first_loop + l];
        if (L->n == 0)
            continue; /* a vertex loop (an apex): nothing to bound */
        int ok;
        double sh[2];
        if ((st = loop_uv(&F, L, &loop, &ok, sh)) != GEOM_OK)
            break;
        if (!ok) {
            st = GEOM_ERR_DEGENERATE;
            break;
        }
        size_t s0 = all.n;
        if ((st = bpush(T->a, &starts, &s0)) != GEOM_OK || (st = bpush(T->a, &shifts, sh)) != GEOM_OK)
            break;
        for (size_t k = 0; k < loop.n && !st; k++)
            st = bpush(T->a, &all, (lpt *)loop.p + k);
    }
    if (!st)
        st = join_open_loops(&F, &all, &starts, &shifts);
    bfree(T->a, &shifts);
    /* a periodic face bounded by loops that are not closed in the domain
     * is outside what this mesher handles: reported through the status */
    if (!st && all.n < 3)
        st = GEOM_ERR_DEGENERATE;
    double su = 0, sv = 0;
    if (!st) {
        const lpt *P = (const lpt *)all.p;
        for (size_t k = 0; k < all.n; k++) {
            double p[3], du[3], dv[3];
            geom__brep_surface_eval(b, F.S, P[k].uv[0], P[k].uv[1], p, du, dv);
            su += sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]);
            sv += sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
        }
        su /= (double)all.n;
        sv /= (double)all.n;
        if (!(su > 0))
            su = sv > 0 ? sv : 1;
        if (!(sv > 0))
            sv = su;
        for (size_t k = 0; k < all.n; k++) {
            double x = P[k].uv[0] * su, y = P[k].uv[1] * sv;
            box[0] = fmin(box[0], x), box[1] = fmax(box[1], x);
            box[2] = fmin(box[2], y), box[3] = fmax(box[3], y);
        }
        st = geom__cdt_init(&C, T->a, box);
    }
    fpt dummy = {{0, 0}, 0, {0, 0, 0}};
    for (int k = 0; k < 3 && !st; k++)
        st = bpush(T->a, &pts, &dummy);
    /* boundary points and segments */
    size_t nl = starts.n;
    for (size_t l = 0; l < nl && !st; l++) {
        size_t s0 = ((size_t *)starts.p)[l], s1 = l + 1 < nl ? ((size_t *)starts.p)[l + 1] : all.n;
        int32_t firstv = -1, prevv = -1;
        for (size_t k = s0; k < s1 && !st; k++) {
            const lpt *q = (const lpt *)all.p + k;
            int32_t v;
            geom_status si = geom__cdt_insert(&C, q->uv[0] * su, q->uv[1] * sv, &v);
            if (si == GEOM_OK) {
                fpt fp = {{q->uv[0], q->uv[1]}, q->vid, {0, 0, 0}};
                double sp[3];
                const double *x = posof(T, q->vid);
                geom__brep_surface_eval(b, F.S, q->uv[0], q->uv[1], sp, NULL, NULL);
                for (int j = 0; j < 3; j++)
                    fp.off[j] = x[j] - sp[j];
                st = bpush(T->a, &pts, &fp);
            } else if (si != GEOM_ERR_DEGENERATE || v < 0) {
                st = si == GEOM_ERR_DEGENERATE ? GEOM_ERR_DEGENERATE : si;
                break;
            }
            if (firstv < 0)
                firstv = v;
            if (prevv >= 0 && prevv != v) {
                int32_t sg[2] = {prevv, v};
                st = bpush(T->a, &segs, sg);
            }
            prevv = v;
        }
        if (!st && prevv != firstv) {
            int32_t sg[2] = {prevv, firstv};
            st = bpush(T->a, &segs, sg);
        }
    }
    for (size_t k = 0; k < segs.n && !st; k++) {
        const int32_t *sg = (const int32_t *)segs.p + 2 * k;
        st = geom__cdt_constrain(&C, sg[0], sg[1], 0);
    }
    if (!st)
        geom__cdt_classify(&C);
    /* refinement */
    for (int round = 0; round < 40 && !st; round++) {
        size_t inserted = 0, nt = C.nt;
        for (size_t t = 0; t < nt && !st; t++) {
            fpt V[3];
            const double *X[3];
            if (!live_tri(T, &C, &pts, t, V, X))
                continue;
            double err, best[2];
            int on_edge;
            tri_error(&F, V, X, &err, best, &on_edge);
            int bad = err > T->tol;
            if (!bad && T->cos_angle < 1)
                bad = normal_cos(&F, V) < T->cos_angle;
            if (!bad)
                continue;
            if (on_edge >= 0 && C.tri[t].con[(on_edge + 2) % 3]) {
                /* the worst point is on the boundary, which this face cannot
                 * move: refine only if the interior is off too */
                static const double third[3] = {1. / 3, 1. / 3, 1. / 3};
                double c3[2], pc[3], xc[3];
                surf_bary(&F, V, third, c3, pc);
                for (int j = 0; j < 3; j++)
                    xc[j] = (X[0][j] + X[1][j] + X[2][j]) / 3;
                if (d3(pc, xc) <= T->tol && !(T->cos_angle < 1 && normal_cos(&F, V) < T->cos_angle))
                    continue;
                best[0] = (V[0].uv[0] + V[1].uv[0] + V[2].uv[0]) / 3;
                best[1] = (V[0].uv[1] + V[1].uv[1] + V[2].uv[1]) / 3;
            } else if (!(err > T->tol)) {
                best[0] = (V[0].uv[0] + V[1].uv[0] + V[2].uv[0]) / 3;
                best[1] = (V[0].uv[1] + V[1].uv[1] + V[2].uv[1]) / 3;
            }
            if (T->tris.n + 2 * inserted > T->max_tris) {
                st = GEOM_ERR_LIMIT;
                break;
            }
            /* Ruppert's choice: the circumcentre (in the scaled domain) when
             * it lies inside the face, which keeps the triangles well shaped;
             * else the worst sample */
            {
                const double *a = C.xy + 2 * C.tri[t].v[0], *bq = C.xy + 2 * C.tri[t].v[1],
                             *cq = C.xy + 2 * C.tri[t].v[2];
                double bx = bq[0] - a[0], by = bq[1] - a[1], cx = cq[0] - a[0], cy = cq[1] - a[1];
                double dd = 2 * (bx * cy - by * cx);
                if (dd != 0) {
                    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
                    double q[2] = {a[0] + (cy * b2 - by * c2) / dd, a[1] + (bx * c2 - cx * b2) / dd};
                    int32_t lt = isfinite(q[0]) && isfinite(q[1]) ? geom__cdt_locate(&C, q) : -1;
                    if (lt >= 0 && C.tri[lt].inside) {
                        int near_con = 0;
                        /* not within the diametral circle of a constrained edge of
                         * its triangle (it would crowd the boundary) */
                        for (int k = 0; k < 3; k++) {
                            if (!C.tri[lt].con[k])
                                continue;
                            const double *e0 = C.xy + 2 * C.tri[lt].v[(k + 1) % 3],
                                         *e1 = C.xy + 2 * C.tri[lt].v[(k + 2) % 3];
                            double mx = 0.5 * (e0[0] + e1[0]), my = 0.5 * (e0[1] + e1[1]);
                            double r2 = 0.25 * ((e1[0] - e0[0]) * (e1[0] - e0[0]) +
                                                (e1[1] - e0[1]) * (e1[1] - e0[1]));
                            if ((q[0] - mx) * (q[0] - mx) + (q[1] - my) * (q[1] - my) <= r2)
                                near_con = 1;
                        }
                        if (!near_con) {
                            best[0] = q[0] / su;
                            best[1] = q[1] / sv;
                        }
                    }
                }
            }
            int32_t v;
            geom_status si = geom__cdt_insert(&C, best[0] * su, best[1] * sv, &v);
            if (si == GEOM_OK) {
                fpt fp;
                memset(&fp, 0, sizeof fp);
                fp.uv[0] = best[0];
                fp.uv[1] = best[1];
                double p[3];
                geom__brep_surface_eval(b, F.S, best[0], best[1], p, NULL, NULL);
                if ((st = add_pos(T, p, &fp.vid)) != GEOM_OK)
                    break;
                st = bpush(T->a, &pts, &fp);
                inserted++;
            } else if (si != GEOM_ERR_DEGENERATE && si != GEOM_ERR_DOMAIN) {
                st = si;
            }
        }
        if (inserted == 0)
            break;
    }
    /* output, with the achieved error */
    double ferr = 0;
    size_t ntri = 0;
    for (size_t t = 0; t < C.nt && !st; t++) {
        fpt V[3];
        const double *X[3];
        if (!live_tri(T, &C, &pts, t, V, X))
            continue;
        if (V[0].vid == V[1].vid || V[1].vid == V[2].vid || V[2].vid == V[0].vid)
            continue; /* collapsed at a pole */
        double err, best[2];
        int on_edge;
        tri_error(&F, V, X, &err, best, &on_edge);
        if (err > T->tol && on_edge >= 0 && C.tri[t].con[(on_edge + 2) % 3]) {
            uint32_t a = V[on_edge].vid, c = V[(on_edge + 1) % 3].vid;
            uint32_t pr[2] = {a < c ? a : c, a < c ? c : a};
            if ((st = bpush(T->a, &T->split, pr)) != GEOM_OK)
                break;
        }
        if (err > ferr)
            ferr = err;
        T->err_sum += err;
        T->err_n++;
        uint32_t tri[3] = {V[0].vid, V[1].vid, V[2].vid};
        double uv[6] = {V[0].uv[0], V[0].uv[1], V[1].uv[0], V[1].uv[1], V[2].uv[0], V[2].uv[1]};
        if (!fc->same_sense) {
            uint32_t x = tri[1];
            tri[1] = tri[2];
            tri[2] = x;
            double u0 = uv[2], u1 = uv[3];
            uv[2] = uv[4], uv[3] = uv[5];
            uv[4] = u0, uv[5] = u1;
        }
        if ((st = bpush(T->a, &T->tris, tri)) || (st = bpush(T->a, &T->tface, &fi)) ||
            (st = bpush(T->a, &T->tuv, uv)))
            break;
        ntri++;
    }
    if (!st && ferr > T->face_err)
        T->face_err = ferr;
    if (rep) {
        rep->chordal_error = ferr;
        rep->edge_gap = F.gap;
        rep->triangles = ntri;
        rep->status = st;
    }
    geom__cdt_free(&C);
    bfree(T->a, &pts);
    bfree(T->a, &loop);
    bfree(T->a, &segs);
    bfree(T->a, &all);
    bfree(T->a, &starts);
    return st;
}

static int cmp_pair(const void *x, const void *y)
{
    const uint32_t *a = x, *b = y;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return a[1] < b[1] ? -1 : a[1] > b[1];
}

/* Split the edge pieces a face asked for (T->split) at their parameter
 * midpoints, so that the next pass meets the tolerance along them. */
static geom_status resample_edges(tess *T, size_t *nsplit, uint8_t *changed)
{
    const geom_brep *b = T->b;
    qsort(T->split.p, T->split.n, 2 * sizeof(uint32_t), cmp_pair);
    buf ns = {NULL, 0, 0, sizeof(sample)};
    geom_status st = GEOM_OK;
    *nsplit = 0;
    for (size_t e = 0; e < b->nedges && !st; e++) {
        const sample *S = (const sample *)T->samples.p + T->efirst[e];
        size_t n = T->ecount[e], first = ns.n;
        const geom_brep_curve *c = &b->curves[b->edges[e].curve];
        for (size_t k = 0; k < n && !st; k++) {
            if ((st = bpush(T->a, &ns, &S[k])) != GEOM_OK)
                break;
            if (k + 1 == n)
                break;
            uint32_t a = S[k].vid, d = S[k + 1].vid;
            uint32_t key[2] = {a < d ? a : d, a < d ? d : a};
            if (!bsearch(key, T->split.p, T->split.n, 2 * sizeof(uint32_t), cmp_pair))
                continue;
            sample m;
            m.t = 0.5 * (S[k].t + S[k + 1].t);
            double p[3];
            geom__brep_curve_eval(c, m.t, p, NULL);
            if ((st = add_pos(T, p, &m.vid)) != GEOM_OK)
                break;
            st = bpush(T->a, &ns, &m);
            (*nsplit)++;
            changed[e] = 1;
        }
        T->efirst[e] = first;
        T->ecount[e] = ns.n - first;
    }
    bfree(T->a, &T->samples);
    T->samples = ns;
    return st;
}

static double now(void)
{
    return (double)clock() / CLOCKS_PER_SEC;
}

GEOM_API geom_status geom_step_tessellate(const geom_brep *b, const geom_brep_tess_options *options,
                                          geom_mesh *out, geom_error_report *report,
                                          geom_brep_face_report *faces, geom_brep_tess_stats *stats,
                                          geom_diag *diag)
{
    if (!b || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "NULL argument");
    geom_brep_tess_options o;
    memset(&o, 0, sizeof o);
    if (options)
        o = *options;
    if (o.tolerance < 0 || !isfinite(o.tolerance) || o.angle_degrees < 0 || !isfinite(o.angle_degrees))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "tolerance and angle must be finite and >= 0");
    double t_start = now();
    tess T;
    memset(&T, 0, sizeof T);
    T.b = b;
    T.a = o.alloc;
    T.pos.elem = 3 * sizeof(double);
    T.samples.elem = sizeof(sample);
    T.tris.elem = 3 * sizeof(uint32_t);
    T.tface.elem = sizeof(uint32_t);
    T.tuv.elem = 6 * sizeof(double);
    T.split.elem = 2 * sizeof(uint32_t);
    T.max_tris = o.max_triangles ? o.max_triangles : ((size_t)1 << 24);
    T.cos_angle = o.angle_degrees > 0 ? cos(o.angle_degrees * GEOM_PI / 180) : 1;
    T.tol = o.tolerance;
    if (!(T.tol > 0))
        T.tol = geom__step_default_tolerance(b);
    geom_status st = GEOM_OK;
    size_t ne = b->nedges ? b->nedges : 1;
    T.efirst = geom__alloc(T.a, ne * sizeof(size_t));
    T.ecount = geom__alloc(T.a, ne * sizeof(size_t));
    if (!T.efirst || !T.ecount)
        st = GEOM_ERR_NOMEM;
    for (size_t k = 0; k < b->nvertices && !st; k++) {
        uint32_t id;
        st = add_pos(&T, b->vertices[k].p, &id);
    }
    for (size_t e = 0; e < b->nedges && !st; e++)
        st = sample_edge(&T, (uint32_t)e);
    size_t failed = 0;
    double gap = 0;
    /* mesh the faces; where a face's boundary pieces are off the tolerance,
     * split those edge pieces (for both faces of the edge) and mesh again
     * the faces that use a split edge; the others keep their triangles */
    size_t nf = b->nfaces ? b->nfaces : 1;
    buf *ftris = geom__alloc(T.a, nf * sizeof *ftris), *ftuv = geom__alloc(T.a, nf * sizeof *ftuv);
    geom_brep_face_report *frs = geom__alloc(T.a, nf * sizeof *frs);
    double *fsum = geom__alloc(T.a, nf * sizeof *fsum);
    size_t *fcnt = geom__alloc(T.a, nf * sizeof *fcnt);
    uint8_t *changed = geom__alloc(T.a, ne);
    if (ftris && ftuv)
        for (size_t f = 0; f < nf; f++) {
            buf z3 = {NULL, 0, 0, 3 * sizeof(uint32_t)}, z6 = {NULL, 0, 0, 6 * sizeof(double)};
            ftris[f] = z3;
            ftuv[f] = z6;
        }
    if (!ftris || !ftuv || !frs || !fsum || !fcnt || !changed)
        st = st ? st : GEOM_ERR_NOMEM;
    else
        memset(changed, 0, ne);
    for (int pass = 0; pass < 6 && !st; pass++) {
        if (pass > 0) {
            size_t nsplit = 0;
            if (T.split.n == 0)
                break;
            memset(changed, 0, ne);
            if ((st = resample_edges(&T, &nsplit, changed)) != GEOM_OK || nsplit == 0)
                break;
        }
        T.split.n = 0;
        for (size_t f = 0; f < b->nfaces && !st; f++) {
            if (pass > 0) {
                const geom_brep_face *fc = &b->faces[f];
                int dirty = 0;
                for (uint32_t l = 0; l < fc->nloops && !dirty; l++) {
                    const geom_brep_loop *L = &b->loops[fc->first_loop + l];
                    for (uint32_t k = 0; k < L->n && !dirty; k++)
                        dirty = changed[b->coedges[L->first + k].edge];
                }
                if (!dirty)
                    continue;
            }
            geom_brep_face_report fr;
            memset(&fr, 0, sizeof fr);
            double t0 = now();
            size_t npos = T.pos.n;
            T.tris.n = T.tface.n = T.tuv.n = 0;
            T.err_sum = 0;
            T.err_n = 0;
            geom_status fs = mesh_face(&T, (uint32_t)f, &fr);
            fr.seconds = now() - t0;
            if (fs == GEOM_ERR_NOMEM || fs == GEOM_ERR_LIMIT) {
                st = fs;
            } else if (fs != GEOM_OK) {
                /* leave the face out, keep going */
                T.tris.n = T.tface.n = T.tuv.n = 0;
                T.pos.n = npos;
                T.err_sum = 0;
                T.err_n = 0;
                fr.triangles = 0;
                fr.status = fs;
            }
            frs[f] = fr;
            fsum[f] = T.err_sum;
            fcnt[f] = T.err_n;
            ftris[f].n = ftuv[f].n = 0;
            for (size_t k = 0; k < T.tris.n && !st; k++)
                if ((st = bpush(T.a, &ftris[f], (const uint32_t *)T.tris.p + 3 * k)) == GEOM_OK)
                    st = bpush(T.a, &ftuv[f], (const double *)T.tuv.p + 6 * k);
        }
    }
    /* all faces' triangles, in face order, and the totals */
    T.tris.n = T.tface.n = T.tuv.n = 0;
    T.face_err = T.err_sum = 0;
    T.err_n = 0;
    for (size_t f = 0; f < b->nfaces && !st; f++) {
        uint32_t fi = (uint32_t)f;
        for (size_t k = 0; k < ftris[f].n && !st; k++)
            if ((st = bpush(T.a, &T.tris, (const uint32_t *)ftris[f].p + 3 * k)) == GEOM_OK &&
                (st = bpush(T.a, &T.tface, &fi)) == GEOM_OK)
                st = bpush(T.a, &T.tuv, (const double *)ftuv[f].p + 6 * k);
        if (frs[f].status != GEOM_OK)
            failed++;
        else if (frs[f].chordal_error > T.face_err)
            T.face_err = frs[f].chordal_error;
        if (frs[f].edge_gap > gap)
            gap = frs[f].edge_gap;
        T.err_sum += fsum[f];
        T.err_n += fcnt[f];
        if (faces)
            faces[f] = frs[f];
    }
    if (ftris && ftuv)
        for (size_t f = 0; f < nf; f++) {
            bfree(T.a, &ftris[f]);
            bfree(T.a, &ftuv[f]);
        }
    geom__free(T.a, ftris, nf * sizeof *ftris);
    geom__free(T.a, ftuv, nf * sizeof *ftuv);
    geom__free(T.a, frs, nf * sizeof *frs);
    geom__free(T.a, fsum, nf * sizeof *fsum);
    geom__free(T.a, fcnt, nf * sizeof *fcnt);
    geom__free(T.a, changed, ne);
    if (st) {
        geom__diag_set(diag, st, "", 0, 0, "tessellation failed: %s", geom_status_str(st));
        goto done;
    }
    {
        /* compact the used vertices and build the mesh once */
        size_t nv = T.pos.n, nt = T.tris.n;
        uint32_t *map = geom__alloc(T.a, (nv ? nv : 1) * sizeof *map);
        double *xyz = geom__alloc(T.a, (nv ? nv : 1) * 3 * sizeof *xyz);
        uint32_t *sizes = geom__alloc(T.a, (nt ? nt : 1) * sizeof *sizes);
        uint32_t *idx = geom__alloc(T.a, (nt ? nt : 1) * 3 * sizeof *idx);
        if (!map || !xyz || !sizes || !idx) {
            st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "out of memory");
        } else {
            for (size_t k = 0; k < nv; k++)
                map[k] = GEOM_INVALID_INDEX;
            size_t used = 0;
            const uint32_t *tr = (const uint32_t *)T.tris.p;
            for (size_t k = 0; k < 3 * nt; k++) {
                uint32_t v = tr[k];
                if (map[v] == GEOM_INVALID_INDEX) {
                    map[v] = (uint32_t)used;
                    memcpy(xyz + 3 * used, posof(&T, v), 3 * sizeof(double));
                    used++;
                }
                idx[k] = map[v];
            }
            for (size_t k = 0; k < nt; k++)
                sizes[k] = 3;
            geom_mesh_build_options bo;
            memset(&bo, 0, sizeof bo);
            bo.keep_orientation = 1;
            geom_mesh_build_report br;
            memset(&br, 0, sizeof br);
            st = geom_mesh_build(out, used, xyz, nt, sizes, idx, &bo, &br, diag);
            if (!st && nt) {
                const uint32_t *fo = geom_mesh_face_origin(out);
                size_t nf = geom_mesh_n_faces(out);
                if (o.attributes & GEOM_SURFACE_ATTR_SOURCE) {
                    uint32_t ch;
                    st = geom_mesh_channel_add(out, "face", GEOM_MESH_DOMAIN_FACE, 1, &ch);
                    if (!st) {
                        double *d = geom_mesh_channel_data(out, ch);
                        for (size_t f = 0; f < nf; f++)
                            d[f] = (double)((const uint32_t *)T.tface.p)[fo ? fo[f] : f];
                    }
                }
                if (!st && (o.attributes & (GEOM_SURFACE_ATTR_UV | GEOM_SURFACE_ATTR_NORMAL))) {
                    /* corner values in each face's order as built */
                    uint32_t chu = GEOM_INVALID_INDEX, chn = GEOM_INVALID_INDEX;
                    size_t nh = geom_mesh_n_halfedges(out);
                    if (o.attributes & GEOM_SURFACE_ATTR_UV)
                        st = geom_mesh_channel_add(out, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &chu);
                    if (!st && (o.attributes & GEOM_SURFACE_ATTR_NORMAL))
                        st = geom_mesh_channel_add(out, "normal", GEOM_MESH_DOMAIN_CORNER, 3, &chn);
                    if (!st && chu != GEOM_INVALID_INDEX)
                        st = geom_mesh_corner_pool_resize(out, chu, 3 * nf);
                    if (!st && chn != GEOM_INVALID_INDEX)
                        st = geom_mesh_corner_pool_resize(out, chn, 3 * nf);
                    for (size_t f = 0; f < nf && !st; f++) {
                        size_t src = fo ? fo[f] : f;
                        uint32_t fi = ((const uint32_t *)T.tface.p)[src];
                        const double *uv = (const double *)T.tuv.p + 6 * src;
                        const uint32_t *tri = (const uint32_t *)T.tris.p + 3 * src;
                        uint32_t h = geom_mesh_face_he(out, (uint32_t)f);
                        for (int c = 0; c < 3; c++, h = geom_mesh_he_next(out, h)) {
                            if (h >= nh)
                                break;
                            /* which input corner this halfedge points to */
                            uint32_t v = geom_mesh_he_vertex(out, h);
                            int k = 0;
                            for (int j = 0; j < 3; j++)
                                if (map[tri[j]] == v)
                                    k = j;
                            if (chu != GEOM_INVALID_INDEX) {
                                double *pool = geom_mesh_channel_data(out, chu);
                                pool[2 * (3 * f + c)] = uv[2 * k];
                                pool[2 * (3 * f + c) + 1] = uv[2 * k + 1];
                                geom_mesh_corner_indices(out, chu)[h] = (uint32_t)(3 * f + c);
                            }
                            if (chn != GEOM_INVALID_INDEX) {
                                double p[3], du[3], dv[3], n[3];
                                const geom_brep_face *fc = &b->faces[fi];
                                geom__brep_surface_eval(b, &b->surfaces[fc->surface], uv[2 * k],
                                                        uv[2 * k + 1], p, du, dv);
                                n[0] = du[1] * dv[2] - du[2] * dv[1];
                                n[1] = du[2] * dv[0] - du[0] * dv[2];
                                n[2] = du[0] * dv[1] - du[1] * dv[0];
                                double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                                if (!(l > 0)) {
                                    geom_mesh_face_normal(out, (uint32_t)f, n);
                                    l = 1;
                                } else if (!fc->same_sense) {
                                    l = -l;
                                }
                                double *pool = geom_mesh_channel_data(out, chn);
                                for (int j = 0; j < 3; j++)
                                    pool[3 * (3 * f + c) + j] = n[j] / l;
                                geom_mesh_corner_indices(out, chn)[h] = (uint32_t)(3 * f + c);
                            }
                        }
                    }
                }
            }
            if (stats) {
                memset(stats, 0, sizeof *stats);
                stats->nonmanifold_edges = br.nonmanifold_edges;
            }
        }
        geom__free(T.a, map, (nv ? nv : 1) * sizeof *map);
        geom__free(T.a, xyz, (nv ? nv : 1) * 3 * sizeof *xyz);
        geom__free(T.a, sizes, (nt ? nt : 1) * sizeof *sizes);
        geom__free(T.a, idx, (nt ? nt : 1) * 3 * sizeof *idx);
    }
    if (st)
        goto done;
    if (report) {
        report->max_error = fmax(T.face_err, T.edge_err);
        report->mean_error = T.err_n ? T.err_sum / (double)T.err_n : 0;
        report->method = GEOM_ERROR_SAMPLED;
        report->evaluations = T.evals;
    }
    if (stats) {
        stats->faces = b->nfaces;
        stats->faces_failed = failed;
        stats->triangles = geom_mesh_n_faces(out);
        stats->vertices = geom_mesh_n_vertices(out);
        size_t es = 0;
        for (size_t e = 0; e < b->nedges; e++)
            es += T.ecount[e] > 2 ? T.ecount[e] - 2 : 0;
        stats->edge_samples = es;
        stats->edge_gap = gap;
        stats->edge_error = T.edge_err;
        size_t open = 0;
        for (size_t e = 0; e < geom_mesh_n_edges(out); e++)
            open += geom_mesh_edge_is_boundary(out, (uint32_t)e);
        stats->open_edges = open;
        stats->seconds = now() - t_start;
    }
done:
    geom__free(T.a, T.efirst, ne * sizeof(size_t));
    geom__free(T.a, T.ecount, ne * sizeof(size_t));
    bfree(T.a, &T.pos);
    bfree(T.a, &T.samples);
    bfree(T.a, &T.tris);
    bfree(T.a, &T.tface);
    bfree(T.a, &T.tuv);
    bfree(T.a, &T.split);
    return st;
}
