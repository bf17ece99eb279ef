/*
 * Evaluation and point inversion of the B-rep's curves and surfaces in
 * their STEP parameterisations (ISO 10303-42): closed forms for the
 * analytic ones, The NURBS Book's algorithms (through geom/curve.h and
 * geom/surface.h) for B-splines, and Gauss-Newton iteration on
 * |S(u, v) - q|^2 from a guess or a sampled start where there is no
 * closed form.
 */
#include "step/step_internal.h"

#include <float.h>
#include <string.h>

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double *a, const double *b, double *o)
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static double dist3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(dot3(d, d));
}

int geom__brep_curve_domain(const geom_brep_curve *c, double *t0, double *t1)
{
    if (c->type == GEOM_BREP_CURVE_NURBS) {
        geom_curve_nurbs_domain(&c->nurbs, t0, t1);
        return 1;
    }
    if (c->type == GEOM_BREP_CURVE_CIRCLE || c->type == GEOM_BREP_CURVE_ELLIPSE) {
        *t0 = 0;
        *t1 = 2 * GEOM_PI;
        return 1;
    }
    return 0;
}

int geom__brep_curve_periodic(const geom_brep_curve *c)
{
    return c->type == GEOM_BREP_CURVE_CIRCLE || c->type == GEOM_BREP_CURVE_ELLIPSE;
}

void geom__brep_curve_eval(const geom_brep_curve *c, double t, double *p, double *d)
{
    int dim = c->dim;
    double P[3], D[3];
    switch (c->type) {
    case GEOM_BREP_CURVE_LINE:
        for (int k = 0; k < 3; k++) {
            P[k] = c->origin[k] + t * c->dir[k];
            D[k] = c->dir[k];
        }
        break;
    case GEOM_BREP_CURVE_CIRCLE:
    case GEOM_BREP_CURVE_ELLIPSE: {
        double a = c->r1, bb = c->type == GEOM_BREP_CURVE_CIRCLE ? c->r1 : c->r2;
        double ct = cos(t), st = sin(t);
        for (int k = 0; k < 3; k++) {
            P[k] = c->origin[k] + a * ct * c->x[k] + bb * st * c->y[k];
            D[k] = -a * st * c->x[k] + bb * ct * c->y[k];
        }
        break;
    }
    default: {
        double t0, t1, ders[8];
        geom_curve_nurbs_domain(&c->nurbs, &t0, &t1);
        if (!(t >= t0))
            t = t0;
        if (!(t <= t1))
            t = t1;
        memset(ders, 0, sizeof ders);
        geom_curve_nurbs_derivs(&c->nurbs, t, 1, 0, ders);
        P[2] = D[2] = 0;
        for (int k = 0; k < dim; k++) {
            P[k] = ders[k];
            D[k] = ders[dim + k];
        }
        break;
    }
    }
    for (int k = 0; k < dim; k++) {
        if (p)
            p[k] = P[k];
        if (d)
            d[k] = D[k];
    }
}

/* Newton on (C(t) - q) . C'(t) with a numerically differentiated second
 * derivative, kept inside [lo, hi] when bounded. */
static double curve_newton(const geom_brep_curve *c, const double *q, double t, int bounded,
                           double lo, double hi, double *tout)
{
    double p[3] = {0, 0, 0}, d[3] = {0, 0, 0};
    int dim = c->dim;
    for (int it = 0; it < 30; it++) {
        geom__brep_curve_eval(c, t, p, d);
        double r[3] = {0, 0, 0};
        for (int k = 0; k < dim; k++)
            r[k] = p[k] - q[k];
        double g = dot3(r, d), dd = dot3(d, d);
        if (!(dd > 0))
            break;
        double step = -g / dd;
        double tn = t + step;
        if (bounded) {
            if (tn < lo)
                tn = lo;
            if (tn > hi)
                tn = hi;
        }
        if (fabs(tn - t) <= 1e-15 * (1 + fabs(t))) {
            t = tn;
            break;
        }
        t = tn;
    }
    geom__brep_curve_eval(c, t, p, NULL);
    *tout = t;
    double r[3] = {0, 0, 0};
    for (int k = 0; k < dim; k++)
        r[k] = p[k] - q[k];
    return sqrt(dot3(r, r));
}

double geom__brep_curve_invert(const geom_brep_curve *c, const double q[3], double guess,
                               int has_guess, double *t)
{
    double w[3];
    for (int k = 0; k < 3; k++)
        w[k] = (k < c->dim ? q[k] : 0) - c->origin[k];
    if (c->type == GEOM_BREP_CURVE_LINE) {
        double dd = dot3(c->dir, c->dir);
        *t = dd > 0 ? dot3(w, c->dir) / dd : 0;
        return curve_newton(c, q, *t, 0, 0, 0, t);
    }
    if (c->type == GEOM_BREP_CURVE_CIRCLE || c->type == GEOM_BREP_CURVE_ELLIPSE) {
        double a = c->r1, bb = c->type == GEOM_BREP_CURVE_CIRCLE ? c->r1 : c->r2;
        double s = atan2(dot3(w, c->y) / bb, dot3(w, c->x) / a);
        if (s < 0)
            s += 2 * GEOM_PI;
        if (c->type == GEOM_BREP_CURVE_CIRCLE) {
            *t = s;
            double p[3];
            geom__brep_curve_eval(c, s, p, NULL);
            double r = 0;
            for (int k = 0; k < c->dim; k++)
                r += (p[k] - q[k]) * (p[k] - q[k]);
            return sqrt(r);
        }
        double d = curve_newton(c, q, s, 0, 0, 0, t);
        *t = fmod(*t, 2 * GEOM_PI);
        if (*t < 0)
            *t += 2 * GEOM_PI;
        return d;
    }
    double t0, t1;
    geom_curve_nurbs_domain(&c->nurbs, &t0, &t1);
    if (has_guess && guess >= t0 && guess <= t1) {
        double tt, d = curve_newton(c, q, guess, 1, t0, t1, &tt);
        *t = tt;
        (void)d;
    }
    double u = 0, pt[4], dist = 0;
    if (geom_curve_nurbs_closest_point(&c->nurbs, q, &u, pt, &dist, NULL) == GEOM_OK) {
        *t = u;
        return dist;
    }
    /* sampled fallback */
    double best = DBL_MAX, bt = t0;
    for (int k = 0; k <= 64; k++) {
        double s = t0 + (t1 - t0) * k / 64.0, p[3];
        geom__brep_curve_eval(c, s, p, NULL);
        double r = 0;
        for (int j = 0; j < c->dim; j++)
            r += (p[j] - q[j]) * (p[j] - q[j]);
        if (r < best)
            best = r, bt = s;
    }
    return curve_newton(c, q, bt, 1, t0, t1, t);
}

/* Rodrigues rotation of w about unit k by angle a, and its derivative. */
static void rotate(const double *k, const double *w, double a, double *out, double *dout)
{
    double kw[3], c = cos(a), s = sin(a), kd = dot3(k, w);
    cross3(k, w, kw);
    for (int i = 0; i < 3; i++) {
        out[i] = w[i] * c + kw[i] * s + k[i] * kd * (1 - c);
        if (dout)
            dout[i] = -w[i] * s + kw[i] * c + k[i] * kd * s;
    }
}

void geom__brep_surface_eval(const geom_brep *b, const geom_brep_surface *s, double u, double v,
                             double p[3], double du[3], double dv[3])
{
    double P[3], U[3] = {0, 0, 0}, V[3] = {0, 0, 0};
    const double *o = s->origin, *x = s->x, *y = s->y, *z = s->z;
    double cu = cos(u), su = sin(u);
    switch (s->type) {
    case GEOM_BREP_SURFACE_PLANE:
        for (int k = 0; k < 3; k++) {
            P[k] = o[k] + u * x[k] + v * y[k];
            U[k] = x[k];
            V[k] = y[k];
        }
        break;
    case GEOM_BREP_SURFACE_CYLINDER:
        for (int k = 0; k < 3; k++) {
            double rad = cu * x[k] + su * y[k];
            P[k] = o[k] + s->r1 * rad + v * z[k];
            U[k] = s->r1 * (-su * x[k] + cu * y[k]);
            V[k] = z[k];
        }
        break;
    case GEOM_BREP_SURFACE_CONE: {
        double ta = tan(s->r2), r = s->r1 + v * ta;
        for (int k = 0; k < 3; k++) {
            double rad = cu * x[k] + su * y[k];
            P[k] = o[k] + r * rad + v * z[k];
            U[k] = r * (-su * x[k] + cu * y[k]);
            V[k] = ta * rad + z[k];
        }
        break;
    }
    case GEOM_BREP_SURFACE_SPHERE: {
        double cv = cos(v), sv = sin(v), r = s->r1;
        for (int k = 0; k < 3; k++) {
            double rad = cu * x[k] + su * y[k];
            P[k] = o[k] + r * cv * rad + r * sv * z[k];
            U[k] = r * cv * (-su * x[k] + cu * y[k]);
            V[k] = -r * sv * rad + r * cv * z[k];
        }
        break;
    }
    case GEOM_BREP_SURFACE_TORUS: {
        double cv = cos(v), sv = sin(v), R = s->r1, r = s->r2;
        for (int k = 0; k < 3; k++) {
            double rad = cu * x[k] + su * y[k];
            P[k] = o[k] + (R + r * cv) * rad + r * sv * z[k];
            U[k] = (R + r * cv) * (-su * x[k] + cu * y[k]);
            V[k] = -r * sv * rad + r * cv * z[k];
        }
        break;
    }
    case GEOM_BREP_SURFACE_NURBS: {
        double dom[4], ders[12];
        geom_surface_domain(&s->nurbs, dom);
        if (!(u >= dom[0]))
            u = dom[0];
        if (!(u <= dom[1]))
            u = dom[1];
        if (!(v >= dom[2]))
            v = dom[2];
        if (!(v <= dom[3]))
            v = dom[3];
        memset(ders, 0, sizeof ders);
        geom_surface_derivs(&s->nurbs, u, v, 1, 0, ders);
        for (int k = 0; k < 3; k++) {
            P[k] = ders[k];
            V[k] = ders[3 + k];
            U[k] = ders[6 + k];
        }
        break;
    }
    case GEOM_BREP_SURFACE_REVOLUTION: {
        double c[3], dc[3], w[3], dw[3];
        geom__brep_curve_eval(&b->curves[s->curve], v, c, dc);
        for (int k = 0; k < 3; k++)
            w[k] = c[k] - o[k];
        rotate(z, w, u, P, U);
        rotate(z, dc, u, V, dw);
        for (int k = 0; k < 3; k++)
            P[k] += o[k];
        break;
    }
    default: { /* EXTRUSION */
        double c[3], dc[3];
        geom__brep_curve_eval(&b->curves[s->curve], u, c, dc);
        for (int k = 0; k < 3; k++) {
            P[k] = c[k] + v * s->dir[k];
            U[k] = dc[k];
            V[k] = s->dir[k];
        }
        break;
    }
    }
    memcpy(p, P, sizeof P);
    if (du)
        memcpy(du, U, sizeof U);
    if (dv)
        memcpy(dv, V, sizeof V);
}

/* Parameter box for sampling and clamping; bounded = 0 where a direction
 * is unbounded (planes, the length of cylinders and extrusions of lines). */
static void surface_box(const geom_brep *b, const geom_brep_surface *s, double box[4], int bounded[2])
{
    bounded[0] = bounded[1] = 0;
    box[0] = box[2] = -1e300;
    box[1] = box[3] = 1e300;
    if (s->type == GEOM_BREP_SURFACE_NURBS) {
        geom_surface_domain(&s->nurbs, box);
        bounded[0] = bounded[1] = 1;
    } else if (s->type == GEOM_BREP_SURFACE_REVOLUTION) {
        box[0] = 0;
        box[1] = 2 * GEOM_PI;
        bounded[1] = geom__brep_curve_domain(&b->curves[s->curve], &box[2], &box[3]);
    } else if (s->type == GEOM_BREP_SURFACE_EXTRUSION) {
        bounded[0] = geom__brep_curve_domain(&b->curves[s->curve], &box[0], &box[1]);
    }
}

static double gauss_newton(const geom_brep *b, const geom_brep_surface *s, const double q[3],
                           double u, double v, const double box[4], const int bounded[2],
                           double uv[2])
{
    double p[3], su[3], sv[3];
    for (int it = 0; it < 40; it++) {
        geom__brep_surface_eval(b, s, u, v, p, su, sv);
        double r[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        double a = dot3(su, su), bb = dot3(su, sv), c = dot3(sv, sv);
        double g0 = dot3(r, su), g1 = dot3(r, sv);
        double det = a * c - bb * bb;
        double du, dv;
        if (det > 1e-14 * a * c && det > 0) {
            du = -(c * g0 - bb * g1) / det;
            dv = -(a * g1 - bb * g0) / det;
        } else if (a >= c && a > 0) { /* degenerate direction: move along the other */
            du = -g0 / a;
            dv = 0;
        } else if (c > 0) {
            du = 0;
            dv = -g1 / c;
        } else {
            break;
        }
        double un = u + du, vn = v + dv;
        if (bounded[0]) {
            un = un < box[0] ? box[0] : un > box[1] ? box[1] : un;
        }
        if (bounded[1]) {
            vn = vn < box[2] ? box[2] : vn > box[3] ? box[3] : vn;
        }
        int done = fabs(un - u) <= 1e-15 * (1 + fabs(u)) && fabs(vn - v) <= 1e-15 * (1 + fabs(v));
        u = un;
        v = vn;
        if (done)
            break;
    }
    geom__brep_surface_eval(b, s, u, v, p, NULL, NULL);
    uv[0] = u;
    uv[1] = v;
    return dist3(p, q);
}

double geom__brep_surface_invert(const geom_brep *b, const geom_brep_surface *s, const double q[3],
                                 const double guess[2], int has_guess, double uv[2])
{
    double w[3] = {q[0] - s->origin[0], q[1] - s->origin[1], q[2] - s->origin[2]};
    double wx = dot3(w, s->x), wy = dot3(w, s->y), wz = dot3(w, s->z);
    double ang = atan2(wy, wx), rho = hypot(wx, wy);
    if (ang < 0)
        ang += 2 * GEOM_PI;
    double p[3];
    switch (s->type) {
    case GEOM_BREP_SURFACE_PLANE:
        uv[0] = wx;
        uv[1] = wy;
        break;
    case GEOM_BREP_SURFACE_CYLINDER:
        uv[0] = ang;
        uv[1] = wz;
        break;
    case GEOM_BREP_SURFACE_CONE: {
        double t = tan(s->r2);
        uv[0] = ang;
        uv[1] = (wz + t * (rho - s->r1)) / (1 + t * t);
        if (s->r1 + uv[1] * t < 0) /* beyond the apex: the other nappe */
            uv[0] = fmod(ang + GEOM_PI, 2 * GEOM_PI);
        break;
    }
    case GEOM_BREP_SURFACE_SPHERE:
        uv[0] = ang;
        uv[1] = atan2(wz, rho);
        break;
    case GEOM_BREP_SURFACE_TORUS:
        uv[0] = ang;
        uv[1] = atan2(wz, rho - s->r1);
        if (uv[1] < 0)
            uv[1] += 2 * GEOM_PI;
        break;
    default: {
        double box[4];
        int bounded[2];
        surface_box(b, s, box, bounded);
        if (has_guess) {
            double g[2] = {guess[0], guess[1]};
            if (bounded[0])
                g[0] = g[0] < box[0] ? box[0] : g[0] > box[1] ? box[1] : g[0];
            if (bounded[1])
                g[1] = g[1] < box[2] ? box[2] : g[1] > box[3] ? box[3] : g[1];
            double d = gauss_newton(b, s, q, g[0], g[1], box, bounded, uv);
            double scale = 1e-9 * (1 + fabs(q[0]) + fabs(q[1]) + fabs(q[2]));
            if (d <= scale)
                return d;
        }
        double bu = 0, bv = 0, best = DBL_MAX;
        if (s->type == GEOM_BREP_SURFACE_REVOLUTION) {
            /* turn q back by each sampled angle and invert on the profile */
            const geom_brep_curve *c = &b->curves[s->curve];
            for (int k = 0; k < 16; k++) {
                double a = 2 * GEOM_PI * k / 16, qr[3], t;
                rotate(s->z, w, -a, qr, NULL);
                for (int j = 0; j < 3; j++)
                    qr[j] += s->origin[j];
                double d = geom__brep_curve_invert(c, qr, 0, 0, &t);
                if (d < best)
                    best = d, bu = a, bv = t;
            }
        } else if (s->type == GEOM_BREP_SURFACE_EXTRUSION && !bounded[0]) {
            double t;
            geom__brep_curve_invert(&b->curves[s->curve], q, 0, 0, &t);
            bu = t;
            bv = 0;
        } else {
            int n = 24;
            double v0 = bounded[1] ? box[2] : -1, v1 = bounded[1] ? box[3] : 1;
            for (int i = 0; i <= n; i++)
                for (int j = 0; j <= n; j++) {
                    double uu = box[0] + (box[1] - box[0]) * i / n, vv = v0 + (v1 - v0) * j / n;
                    geom__brep_surface_eval(b, s, uu, vv, p, NULL, NULL);
                    double d = dist3(p, q);
                    if (d < best)
                        best = d, bu = uu, bv = vv;
                }
        }
        double d = gauss_newton(b, s, q, bu, bv, box, bounded, uv);
        if (s->type == GEOM_BREP_SURFACE_REVOLUTION) {
            uv[0] = fmod(uv[0], 2 * GEOM_PI);
            if (uv[0] < 0)
                uv[0] += 2 * GEOM_PI;
            geom__brep_surface_eval(b, s, uv[0], uv[1], p, NULL, NULL);
            d = dist3(p, q);
        }
        return d;
    }
    }
    geom__brep_surface_eval(b, s, uv[0], uv[1], p, NULL, NULL);
    return dist3(p, q);
}

GEOM_API geom_status geom_step_surface_eval(const geom_brep *b, uint32_t s, double u, double v,
                                            double p[3], double du[3], double dv[3])
{
    if (!b || !p || s >= b->nsurfaces || !isfinite(u) || !isfinite(v))
        return GEOM_ERR_INVALID_ARG;
    const geom_brep_surface *S = &b->surfaces[s];
    if (S->type == GEOM_BREP_SURFACE_NURBS) {
        double dom[4];
        geom_surface_domain(&S->nurbs, dom);
        if (u < dom[0] || u > dom[1] || v < dom[2] || v > dom[3])
            return GEOM_ERR_DOMAIN;
    }
    geom__brep_surface_eval(b, S, u, v, p, du, dv);
    return GEOM_OK;
}

GEOM_API geom_status geom_step_curve_eval(const geom_brep *b, uint32_t c, double t, double *p)
{
    if (!b || !p || c >= b->ncurves || !isfinite(t))
        return GEOM_ERR_INVALID_ARG;
    const geom_brep_curve *C = &b->curves[c];
    double t0, t1;
    if (geom__brep_curve_domain(C, &t0, &t1) && C->type == GEOM_BREP_CURVE_NURBS &&
        (t < t0 || t > t1))
        return GEOM_ERR_DOMAIN;
    geom__brep_curve_eval(C, t, p, NULL);
    return GEOM_OK;
}
