/* Surface constructors: Bezier patches, bilinear patches, extrusions,
 * surfaces of revolution (The NURBS Book A8.1) and the exact quadrics and
 * torus built from them (section 8.5). */
#include "surface/surface_internal.h"

#include <stdlib.h>
#include <string.h>

#define SQRT1_2 0.70710678118654752440

geom_status geom_surface_bezier_knots(int degree, double *knots)
{
    if (degree < 1 || !knots)
        return GEOM_ERR_INVALID_ARG;
    for (int i = 0; i <= degree; ++i) {
        knots[i] = 0.0;
        knots[degree + 1 + i] = 1.0;
    }
    return GEOM_OK;
}

geom_status geom_surface_bezier(int degree_u, int degree_v, const double *points,
                                const double *weights, double *knots_u, double *knots_v,
                                geom_nurbs_surface *out)
{
    if (!points || !out || degree_u < 1 || degree_v < 1 || !knots_u || !knots_v)
        return GEOM_ERR_INVALID_ARG;
    geom_surface_bezier_knots(degree_u, knots_u);
    geom_surface_bezier_knots(degree_v, knots_v);
    out->degree_u = degree_u;
    out->degree_v = degree_v;
    out->nu = (size_t)degree_u + 1;
    out->nv = (size_t)degree_v + 1;
    out->knots_u = knots_u;
    out->knots_v = knots_v;
    out->points = points;
    out->weights = weights;
    return GEOM_OK;
}

geom_status geom_surface_bilinear(const double p00[3], const double p10[3], const double p01[3],
                                  const double p11[3], double *knots_u, double *knots_v,
                                  double *points, geom_nurbs_surface *out)
{
    if (!p00 || !p10 || !p01 || !p11 || !knots_u || !knots_v || !points || !out)
        return GEOM_ERR_INVALID_ARG;
    if (!geom__isfinite3(p00) || !geom__isfinite3(p10) || !geom__isfinite3(p01) ||
        !geom__isfinite3(p11))
        return GEOM_ERR_INVALID_ARG;
    /* (i, j) at 3*(i*2 + j): (0,0) p00, (0,1) p01, (1,0) p10, (1,1) p11 */
    memcpy(points + 0, p00, 3 * sizeof(double));
    memcpy(points + 3, p01, 3 * sizeof(double));
    memcpy(points + 6, p10, 3 * sizeof(double));
    memcpy(points + 9, p11, 3 * sizeof(double));
    return geom_surface_bezier(1, 1, points, NULL, knots_u, knots_v, out);
}

/* A valid 2D or 3D curve (reason in diag). */
static geom_status check_curve(const geom_nurbs_curve *c, const char *what, geom_diag *diag)
{
    if (!c)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "surface: %s is NULL", what);
    if (c->dim != 2 && c->dim != 3)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: %s has dimension %zu (2 or 3 needed)", what, c->dim);
    geom_diag d;
    geom_diag_clear(&d);
    geom_status st = geom_curve_nurbs_validate(c, c->n + (size_t)c->degree + 1, &d);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: %s: %s", what, d.message);
    return GEOM_OK;
}

static void curve_point3(const geom_nurbs_curve *c, size_t i, double *P)
{
    const double *Q = c->points + i * c->dim;
    P[0] = Q[0];
    P[1] = Q[1];
    P[2] = c->dim == 3 ? Q[2] : 0.0;
}

geom_status geom_surface_extrude(const geom_nurbs_curve *c, const double d[3], double *knots_u,
                                 double *knots_v, double *points, double *weights,
                                 geom_nurbs_surface *out, geom_diag *diag)
{
    geom_status st = check_curve(c, "extrusion profile", diag);
    if (st != GEOM_OK)
        return st;
    if (!d || !knots_u || !knots_v || !points || !out || (c->weights && !weights))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: NULL argument to geom_surface_extrude");
    if (!geom__isfinite3(d))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: extrusion direction is not finite");
    if (d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0)
        return geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                             "surface: extrusion direction is zero");
    memcpy(knots_u, c->knots, (c->n + (size_t)c->degree + 1) * sizeof(double));
    knots_v[0] = knots_v[1] = 0.0;
    knots_v[2] = knots_v[3] = 1.0;
    for (size_t i = 0; i < c->n; ++i) {
        double P[3];
        curve_point3(c, i, P);
        double *A = points + 3 * (2 * i), *B = A + 3;
        for (int k = 0; k < 3; ++k) {
            A[k] = P[k];
            B[k] = P[k] + d[k];
        }
        if (c->weights)
            weights[2 * i] = weights[2 * i + 1] = c->weights[i];
    }
    out->degree_u = c->degree;
    out->degree_v = 1;
    out->nu = c->n;
    out->nv = 2;
    out->knots_u = knots_u;
    out->knots_v = knots_v;
    out->points = points;
    out->weights = c->weights ? weights : NULL;
    return GEOM_OK;
}

/* ------------------------------------------------------------ revolution */

static int is_full_turn(double angle)
{
    return fabs(fabs(angle) - 2.0 * GEOM_PI) <= 1e-12 * 2.0 * GEOM_PI;
}

geom_status geom_surface_revolve_bound(double angle, size_t *nu, size_t *nknots_u)
{
    if (!isfinite(angle))
        return GEOM_ERR_INVALID_ARG;
    if (is_full_turn(angle)) {
        if (nu)
            *nu = 9;
        if (nknots_u)
            *nknots_u = 12;
        return GEOM_OK;
    }
    return geom_curve_nurbs_arc_bound(0.0, angle, nu, nknots_u);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/*
 * The unit arc through `angle` in a 2D frame: ctrl (nu x 2: the cos and sin
 * coefficients of the control points), weights, knots. A full turn is the
 * 9-point circle (identical first and last points).
 */
static geom_status unit_arc(double angle, double *knots, double *ctrl, double *w)
{
    const double c0[2] = {0.0, 0.0}, ex[2] = {1.0, 0.0}, ey[2] = {0.0, 1.0};
    geom_nurbs_curve arc;
    if (is_full_turn(angle)) {
        double ey2[2] = {0.0, angle > 0 ? 1.0 : -1.0};
        return geom_curve_nurbs_circle(2, c0, ex, ey2, 1.0, knots, ctrl, w, &arc, NULL);
    }
    return geom_curve_nurbs_arc(2, c0, ex, ey, 1.0, 0.0, angle, knots, ctrl, w, &arc, NULL);
}

geom_status geom_surface_revolve(const geom_nurbs_curve *c, const double origin[3],
                                 const double axis[3], const double *xaxis, double angle,
                                 double *knots_u, double *knots_v, double *points, double *weights,
                                 geom_nurbs_surface *out, geom_diag *diag)
{
    geom_status st = check_curve(c, "revolution profile", diag);
    if (st != GEOM_OK)
        return st;
    if (!origin || !axis || !knots_u || !knots_v || !points || !weights || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: NULL argument to geom_surface_revolve");
    if (!geom__isfinite3(origin) || !geom__isfinite3(axis) || !isfinite(angle) ||
        (xaxis && !geom__isfinite3(xaxis)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: revolution: non-finite origin, axis or angle");
    size_t nu, nk;
    st = geom_surface_revolve_bound(angle, &nu, &nk);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0,
                             "surface: revolution angle %.17g is zero or above 2 pi", angle);
    geom_vec3 a;
    if (geom_vec3_normalize(geom_vec3_make(axis[0], axis[1], axis[2]), &a) != GEOM_OK)
        return geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                             "surface: revolution axis is zero");
    double A[3] = {a.x, a.y, a.z};
    double X2[3] = {0.0, 0.0, 0.0}; /* radius direction of 2D profiles */
    if (c->dim == 2) {
        if (xaxis) {
            geom_vec3 x;
            if (geom_vec3_normalize(geom_vec3_make(xaxis[0], xaxis[1], xaxis[2]), &x) != GEOM_OK)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "surface: revolution x axis is zero");
            X2[0] = x.x, X2[1] = x.y, X2[2] = x.z;
            if (fabs(dot3(X2, A)) > 1e-12)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "surface: revolution x axis is not orthogonal to the axis");
        } else {
            /* a fixed perpendicular: the unit axis crossed with the world
             * axis of its smallest component */
            int m = 0;
            for (int k = 1; k < 3; ++k)
                if (fabs(A[k]) < fabs(A[m]))
                    m = k;
            double e[3] = {0.0, 0.0, 0.0}, t[3];
            e[m] = 1.0;
            cross3(e, A, t);
            geom_vec3 x;
            geom_vec3_normalize(geom_vec3_make(t[0], t[1], t[2]), &x);
            X2[0] = x.x, X2[1] = x.y, X2[2] = x.z;
        }
    }
    double arc_knots[16], arc_ctrl[18], arc_w[9];
    st = unit_arc(angle, arc_knots, arc_ctrl, arc_w);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: revolution arc failed");
    size_t n = c->n;
    for (size_t j = 0; j < n; ++j) {
        double O[3], X[3], Y[3], P[3];
        int on_axis;
        const double *Q = c->points + j * c->dim;
        if (c->dim == 2) {
            for (int k = 0; k < 3; ++k) {
                O[k] = origin[k] + Q[1] * A[k];
                X[k] = Q[0] * X2[k];
            }
            on_axis = Q[0] == 0.0;
            memcpy(P, O, sizeof P);
        } else {
            memcpy(P, Q, sizeof P);
            double d[3] = {P[0] - origin[0], P[1] - origin[1], P[2] - origin[2]};
            double h = dot3(d, A);
            for (int k = 0; k < 3; ++k) {
                O[k] = origin[k] + h * A[k];
                X[k] = P[k] - O[k];
            }
            double lx = sqrt(dot3(X, X)), ld = sqrt(dot3(d, d));
            on_axis = lx <= 4.0 * 2.220446049250313e-16 * ld;
        }
        cross3(A, X, Y);
        double wj = c->weights ? c->weights[j] : 1.0;
        for (size_t i = 0; i < nu; ++i) {
            double *R = points + 3 * (i * n + j);
            if (on_axis) {
                memcpy(R, P, 3 * sizeof(double));
            } else if (c->dim == 3 && (i == 0 || (i == nu - 1 && is_full_turn(angle)))) {
                memcpy(R, P, 3 * sizeof(double)); /* the profile itself, exactly */
            } else {
                double ca = arc_ctrl[2 * i], sa = arc_ctrl[2 * i + 1];
                for (int k = 0; k < 3; ++k)
                    R[k] = O[k] + ca * X[k] + sa * Y[k];
            }
            weights[i * n + j] = arc_w[i] * wj;
        }
    }
    memcpy(knots_u, arc_knots, nk * sizeof(double));
    memcpy(knots_v, c->knots, (n + (size_t)c->degree + 1) * sizeof(double));
    out->degree_u = 2;
    out->degree_v = c->degree;
    out->nu = nu;
    out->nv = n;
    out->knots_u = knots_u;
    out->knots_v = knots_v;
    out->points = points;
    out->weights = weights;
    return GEOM_OK;
}

/* ------------------------------------------------------ analytic shapes */

static geom_status frame_axes(const geom_surface_frame *f, double *C, double *Z, double *X)
{
    if (!f) {
        C[0] = C[1] = C[2] = 0.0;
        Z[0] = Z[1] = 0.0, Z[2] = 1.0;
        X[0] = 1.0, X[1] = X[2] = 0.0;
        return GEOM_OK;
    }
    if (!geom__isfinite3(f->center) || !geom__isfinite3(f->zaxis) || !geom__isfinite3(f->xaxis))
        return GEOM_ERR_INVALID_ARG;
    if (fabs(dot3(f->zaxis, f->zaxis) - 1.0) > 1e-12 || fabs(dot3(f->xaxis, f->xaxis) - 1.0) > 1e-12 ||
        fabs(dot3(f->zaxis, f->xaxis)) > 1e-12)
        return GEOM_ERR_INVALID_ARG;
    memcpy(C, f->center, 3 * sizeof(double));
    memcpy(Z, f->zaxis, 3 * sizeof(double));
    memcpy(X, f->xaxis, 3 * sizeof(double));
    return GEOM_OK;
}

/* Revolve a 2D (radius, height) profile through a full turn in the frame. */
static geom_status revolve_profile(const geom_surface_frame *frame, int degree, size_t n,
                                   const double *knots, const double *pts, const double *w,
                                   double *knots_u, double *knots_v, double *points,
                                   double *weights, geom_nurbs_surface *out)
{
    double C[3], Z[3], X[3];
    if (frame_axes(frame, C, Z, X) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    geom_nurbs_curve prof = {degree, n, 2, knots, pts, w};
    return geom_surface_revolve(&prof, C, Z, X, 2.0 * GEOM_PI, knots_u, knots_v, points, weights,
                                out, NULL);
}

geom_status geom_surface_sphere(const geom_surface_frame *frame, double radius, double *knots_u,
                                double *knots_v, double *points, double *weights,
                                geom_nurbs_surface *out)
{
    if (!isfinite(radius) || !knots_u || !knots_v || !points || !weights || !out)
        return GEOM_ERR_INVALID_ARG;
    if (!(radius > 0.0))
        return GEOM_ERR_DOMAIN;
    const double r = radius;
    const double U[8] = {0, 0, 0, 0.5, 0.5, 1, 1, 1};
    const double P[10] = {0, -r, r, -r, r, 0, r, r, 0, r};
    const double W[5] = {1, SQRT1_2, 1, SQRT1_2, 1};
    return revolve_profile(frame, 2, 5, U, P, W, knots_u, knots_v, points, weights, out);
}

geom_status geom_surface_cylinder(const geom_surface_frame *frame, double radius, double height,
                                  double *knots_u, double *knots_v, double *points,
                                  double *weights, geom_nurbs_surface *out)
{
    if (!isfinite(radius) || !isfinite(height))
        return GEOM_ERR_INVALID_ARG;
    if (!(radius > 0.0) || height == 0.0)
        return GEOM_ERR_DOMAIN;
    return geom_surface_cone(frame, radius, radius, height, knots_u, knots_v, points, weights,
                             out);
}

geom_status geom_surface_cone(const geom_surface_frame *frame, double r0, double r1,
                              double height, double *knots_u, double *knots_v, double *points,
                              double *weights, geom_nurbs_surface *out)
{
    if (!isfinite(r0) || !isfinite(r1) || !isfinite(height) || !knots_u || !knots_v ||
        !points || !weights || !out)
        return GEOM_ERR_INVALID_ARG;
    if (r0 < 0.0 || r1 < 0.0 || (r0 == 0.0 && r1 == 0.0) || height == 0.0)
        return GEOM_ERR_DOMAIN;
    const double U[4] = {0, 0, 1, 1};
    const double P[4] = {r0, 0.0, r1, height};
    return revolve_profile(frame, 1, 2, U, P, NULL, knots_u, knots_v, points, weights, out);
}

geom_status geom_surface_torus(const geom_surface_frame *frame, double major_radius,
                               double minor_radius, double *knots_u, double *knots_v,
                               double *points, double *weights, geom_nurbs_surface *out)
{
    if (!isfinite(major_radius) || !isfinite(minor_radius) || !knots_u || !knots_v ||
        !points || !weights || !out)
        return GEOM_ERR_INVALID_ARG;
    if (!(major_radius > 0.0) || !(minor_radius > 0.0))
        return GEOM_ERR_DOMAIN;
    const double c0[2] = {major_radius, 0.0}, ex[2] = {1.0, 0.0}, ey[2] = {0.0, 1.0};
    double U[12], P[18], W[9];
    geom_nurbs_curve circ;
    geom_status st = geom_curve_nurbs_circle(2, c0, ex, ey, minor_radius, U, P, W, &circ, NULL);
    if (st != GEOM_OK)
        return st;
    return revolve_profile(frame, 2, 9, U, P, W, knots_u, knots_v, points, weights, out);
}

/* ------------------------------------------------------------------ ruled */

/* A curve in owned buffers (dim 3 points, weights always present). */
typedef struct rcurve {
    geom_nurbs_curve c;
    double *knots, *points, *weights;
    size_t cap_n, cap_k;
} rcurve;

static void rcurve_free(rcurve *r)
{
    free(r->knots);
    free(r->points);
    free(r->weights);
    memset(r, 0, sizeof *r);
}

static geom_status rcurve_alloc(rcurve *r, size_t n, size_t nk)
{
    rcurve_free(r);
    r->knots = malloc(nk * sizeof(double));
    r->points = malloc(3 * n * sizeof(double));
    r->weights = malloc(n * sizeof(double));
    r->cap_n = n;
    r->cap_k = nk;
    if (!r->knots || !r->points || !r->weights) {
        rcurve_free(r);
        return GEOM_ERR_NOMEM;
    }
    return GEOM_OK;
}

/* Copy c as a 3D rational curve, clamp it and map its domain to [0, 1]. */
static geom_status ruled_prepare(const geom_nurbs_curve *c, rcurve *out, geom_diag *diag)
{
    rcurve tmp;
    memset(&tmp, 0, sizeof tmp);
    size_t n = c->n, p = (size_t)c->degree;
    geom_status st = rcurve_alloc(&tmp, n, n + p + 1);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: out of memory");
    memcpy(tmp.knots, c->knots, (n + p + 1) * sizeof(double));
    for (size_t i = 0; i < n; ++i) {
        curve_point3(c, i, tmp.points + 3 * i);
        tmp.weights[i] = c->weights ? c->weights[i] : 1.0;
    }
    tmp.c = (geom_nurbs_curve){c->degree, n, 3, tmp.knots, tmp.points, tmp.weights};
    st = rcurve_alloc(out, n + 2 * p, n + 3 * p + 1);
    if (st != GEOM_OK) {
        rcurve_free(&tmp);
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: out of memory");
    }
    st = geom_curve_nurbs_clamp(&tmp.c, out->knots, out->points, out->weights, &out->c, diag);
    rcurve_free(&tmp);
    if (st != GEOM_OK)
        return st;
    size_t m = out->c.n + p + 1;
    double a = out->knots[p], b = out->knots[out->c.n];
    for (size_t i = 0; i < m; ++i) {
        double t = (out->knots[i] - a) / (b - a);
        out->knots[i] = i <= p ? 0.0 : (i >= out->c.n ? 1.0 : fmin(fmax(t, 0.0), 1.0));
    }
    return GEOM_OK;
}

static geom_status ruled_elevate(rcurve *r, int to, geom_diag *diag)
{
    int t = to - r->c.degree;
    if (t <= 0)
        return GEOM_OK;
    size_t n, nk;
    geom_status st = geom_curve_nurbs_elevate_bound(&r->c, t, &n, &nk);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: degree elevation failed");
    rcurve e;
    memset(&e, 0, sizeof e);
    st = rcurve_alloc(&e, n, nk);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: out of memory");
    st = geom_curve_nurbs_elevate(&r->c, t, e.knots, e.points, e.weights, &e.c, diag);
    if (st != GEOM_OK) {
        rcurve_free(&e);
        return st;
    }
    rcurve_free(r);
    *r = e;
    return GEOM_OK;
}

/* Knots of `other` missing from r's knots (counting multiplicity), inside
 * the open domain (0, 1): x receives them (room for other's count). */
static size_t missing_knots(const rcurve *r, const rcurve *other, double *x)
{
    size_t nx = 0;
    size_t pr = (size_t)r->c.degree, po = (size_t)other->c.degree;
    const double *U = r->knots, *V = other->knots;
    size_t mu = r->c.n + pr + 1, mv = other->c.n + po + 1;
    size_t i = 0;
    while (i < mv) {
        double val = V[i];
        size_t cv = 0;
        while (i + cv < mv && V[i + cv] == val)
            ++cv;
        if (val > 0.0 && val < 1.0) {
            size_t cu = 0;
            for (size_t k = 0; k < mu; ++k)
                cu += U[k] == val;
            for (size_t k = cu; k < cv; ++k)
                x[nx++] = val;
        }
        i += cv;
    }
    return nx;
}

static geom_status ruled_refine(rcurve *r, const double *x, size_t nx, geom_diag *diag)
{
    if (nx == 0)
        return GEOM_OK;
    rcurve e;
    memset(&e, 0, sizeof e);
    size_t n = r->c.n + nx, nk = n + (size_t)r->c.degree + 1;
    geom_status st = rcurve_alloc(&e, n, nk);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: out of memory");
    st = geom_curve_nurbs_refine(&r->c, x, nx, e.knots, e.points, e.weights, &e.c, diag);
    if (st != GEOM_OK) {
        rcurve_free(&e);
        return st;
    }
    rcurve_free(r);
    *r = e;
    return GEOM_OK;
}

/* Make c0 and c1 compatible (see geom_surface_ruled) in r0, r1. */
static geom_status ruled_compatible(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1,
                                    rcurve *r0, rcurve *r1, geom_diag *diag)
{
    geom_status st = check_curve(c0, "ruled surface curve 0", diag);
    if (st == GEOM_OK)
        st = check_curve(c1, "ruled surface curve 1", diag);
    if (st != GEOM_OK)
        return st;
    st = ruled_prepare(c0, r0, diag);
    if (st == GEOM_OK)
        st = ruled_prepare(c1, r1, diag);
    int p = c0->degree > c1->degree ? c0->degree : c1->degree;
    if (st == GEOM_OK)
        st = ruled_elevate(r0, p, diag);
    if (st == GEOM_OK)
        st = ruled_elevate(r1, p, diag);
    if (st != GEOM_OK)
        return st;
    size_t cap = r0->c.n + r1->c.n + 2 * (size_t)p + 2;
    double *x = malloc(cap * sizeof(double));
    if (!x)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "surface: out of memory");
    size_t n0 = missing_knots(r0, r1, x);
    st = ruled_refine(r0, x, n0, diag);
    if (st == GEOM_OK) {
        size_t n1 = missing_knots(r1, r0, x);
        st = ruled_refine(r1, x, n1, diag);
    }
    free(x);
    if (st == GEOM_OK && (r0->c.n != r1->c.n))
        st = geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                           "surface: ruled surface curves could not be made compatible");
    return st;
}

geom_status geom_surface_ruled_bound(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1,
                                     size_t *nu, size_t *nknots_u)
{
    rcurve r0, r1;
    memset(&r0, 0, sizeof r0);
    memset(&r1, 0, sizeof r1);
    geom_status st = ruled_compatible(c0, c1, &r0, &r1, NULL);
    if (st == GEOM_OK) {
        if (nu)
            *nu = r0.c.n;
        if (nknots_u)
            *nknots_u = r0.c.n + (size_t)r0.c.degree + 1;
    }
    rcurve_free(&r0);
    rcurve_free(&r1);
    return st;
}

geom_status geom_surface_ruled(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1,
                               double *knots_u, double *knots_v, double *points, double *weights,
                               geom_nurbs_surface *out, geom_diag *diag)
{
    if (!knots_u || !knots_v || !points || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: NULL argument to geom_surface_ruled");
    int rational = (c0 && c0->weights) || (c1 && c1->weights);
    if (rational && !weights)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: a rational ruled surface needs a weights buffer");
    rcurve r0, r1;
    memset(&r0, 0, sizeof r0);
    memset(&r1, 0, sizeof r1);
    geom_status st = ruled_compatible(c0, c1, &r0, &r1, diag);
    if (st == GEOM_OK) {
        size_t n = r0.c.n, p = (size_t)r0.c.degree;
        memcpy(knots_u, r0.knots, (n + p + 1) * sizeof(double));
        /* the two knot vectors hold the same values; the exact merge may
         * differ in the last bit only where both had the knot: take r0's */
        knots_v[0] = knots_v[1] = 0.0;
        knots_v[2] = knots_v[3] = 1.0;
        for (size_t i = 0; i < n; ++i) {
            memcpy(points + 3 * (2 * i), r0.points + 3 * i, 3 * sizeof(double));
            memcpy(points + 3 * (2 * i + 1), r1.points + 3 * i, 3 * sizeof(double));
            if (rational) {
                weights[2 * i] = r0.weights[i];
                weights[2 * i + 1] = r1.weights[i];
            }
        }
        out->degree_u = (int)p;
        out->degree_v = 1;
        out->nu = n;
        out->nv = 2;
        out->knots_u = knots_u;
        out->knots_v = knots_v;
        out->points = points;
        out->weights = rational ? weights : NULL;
    }
    rcurve_free(&r0);
    rcurve_free(&r1);
    return st;
}
