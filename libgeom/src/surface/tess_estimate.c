/*
 * Output size of a tessellation before doing it: exact for the uniform
 * mode, from the surface's second derivatives for the adaptive mode.
 */
#include "surface/surface_internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* Distinct non-empty knot spans of the domain. */
static size_t spans(const double *knots, size_t n, int p)
{
    size_t c = 0;
    for (size_t i = (size_t)p; i < n; i++)
        if (knots[i + 1] > knots[i])
            c++;
    return c ? c : 1;
}

/* |S''| h^2 / 8 is the deviation of a chord; the adaptive tessellator's
 * triangles (split until the error sampled inside each triangle, not along
 * one chord, meets the tolerance, then each cell given its smallest
 * passing grid) come out about 2.5 times as many as that model says on the
 * teapot (6,232 at 1e-2, 64,529 at 1e-3; estimates 1.12-1.16x those), so
 * the divisor is 3 (about 8 / 2.7). */
#define TRI_ERROR_DIVISOR 3.0

static double len3(const double *v)
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/*
 * Adaptive: a flat triangle over a parameter box hu x hv deviates from the
 * surface by about (|S_uu| hu^2 + 2 |S_uv| hu hv + |S_vv| hv^2) / 8; the
 * tolerance then allows hu = sqrt(8 tol / |S_uu|) (same along v; see
 * TRI_ERROR_DIVISOR). Over a gu x gv sample grid of the parameter box dom
 * (cell centres) the counts nu = du / hu, nv = dv / hv are summed (2
 * triangles per quad, at least floor_count per cell and direction: 1 for
 * the patch tessellator, which starts from a grid). The one per-patch estimate of
 * the library: NURBS surfaces here, STEP faces (step/estimate.c) through
 * their own second derivatives.
 */
double geom__tess_estimate_grid(geom__second_derivs_fn fn, void *user, const double dom[4],
                                size_t gu, size_t gv, double tol, double floor_count)
{
    double du = (dom[1] - dom[0]) / (double)gu, dv = (dom[3] - dom[2]) / (double)gv;
    double total = 0.0;
    for (size_t i = 0; i < gu; i++)
        for (size_t j = 0; j < gv; j++) {
            double u = dom[0] + ((double)i + 0.5) * du, v = dom[2] + ((double)j + 0.5) * dv;
            double sd[3];
            if (!fn(user, u, v, sd))
                continue;
            double suu = sd[0], suv = sd[1], svv = sd[2];
            double cu = sqrt((suu + suv) / (TRI_ERROR_DIVISOR * tol)) * du;
            double cv = sqrt((svv + suv) / (TRI_ERROR_DIVISOR * tol)) * dv;
            if (!isfinite(cu) || !isfinite(cv))
                continue;
            double nu = cu > floor_count ? cu : floor_count;
            double nv = cv > floor_count ? cv : floor_count;
            total += 2.0 * nu * nv;
        }
    return total;
}

/* |S_uu|, |S_uv|, |S_vv| of a NURBS surface. */
static int nurbs_second(void *user, double u, double v, double out[3])
{
    double ders[27];
    if (geom_surface_derivs((const geom_nurbs_surface *)user, u, v, 2, 0, ders) != GEOM_OK)
        return 0;
    /* S^(k,l) at 3*(k*3 + l) */
    out[0] = len3(ders + 3 * 6);
    out[1] = len3(ders + 3 * 4);
    out[2] = len3(ders + 3 * 2);
    return 1;
}

/* A NURBS surface: a 4x4 grid per knot span (at most 256 a side). */
static double adaptive_estimate(const geom_nurbs_surface *s, double tol)
{
    double dom[4];
    if (geom_surface_domain(s, dom) != GEOM_OK)
        return 0.0;
    size_t su = spans(s->knots_u, s->nu, s->degree_u), sv = spans(s->knots_v, s->nv, s->degree_v);
    size_t gu = su * 4 > 256 ? 256 : su * 4, gv = sv * 4 > 256 ? 256 : sv * 4;
    /* floor: one segment per knot span and direction, a quarter on each
     * of its four samples (a floor of 1 per sample asked for 4x4 quads per
     * span where the tessellator makes 1x1 or 2x2 at coarse tolerances: the
     * torus at 0.1 was estimated at 4x the 128 triangles made) */
    double total = geom__tess_estimate_grid(nurbs_second, (void *)(uintptr_t)s, dom, gu, gv, tol,
                                            0.25);
    /* at least two triangles per knot-span cell */
    double floor_ = 2.0 * (double)su * (double)sv;
    return total > floor_ ? total : floor_;
}

geom_status geom_surface_tess_estimate(const geom_nurbs_surface *s, size_t n,
                                       const geom_surface_tess_options *opt, double *triangles)
{
    if (!triangles)
        return GEOM_ERR_INVALID_ARG;
    *triangles = 0.0;
    if (n > 0 && !s)
        return GEOM_ERR_INVALID_ARG;
    geom_surface_tess_options o;
    if (opt)
        o = *opt;
    else
        memset(&o, 0, sizeof o);
    double tol = o.tolerance;
    if (o.mode != GEOM_SURFACE_TESS_UNIFORM && !(tol > 0.0)) {
        /* the default: 1e-3 of the control points' box diagonal */
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t k = 0; k < n; k++)
            for (size_t i = 0; i < s[k].nu * s[k].nv; i++)
                for (int a = 0; a < 3; a++) {
                    double x = s[k].points[3 * i + (size_t)a];
                    lo[a] = x < lo[a] ? x : lo[a];
                    hi[a] = x > hi[a] ? x : hi[a];
                }
        double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
        tol = 1e-3 * len3(d);
        if (!(tol > 0.0))
            tol = 1e-3;
    }
    double total = 0.0;
    for (size_t k = 0; k < n; k++) {
        if (geom_surface_validate(&s[k], NULL) != GEOM_OK)
            return GEOM_ERR_INVALID_ARG;
        if (o.mode == GEOM_SURFACE_TESS_UNIFORM) {
            double gu = o.grid_u > 0 ? o.grid_u : 8, gv = o.grid_v > 0 ? o.grid_v : 8;
            double cells = o.per_surface ? 1.0
                                         : (double)spans(s[k].knots_u, s[k].nu, s[k].degree_u) *
                                               (double)spans(s[k].knots_v, s[k].nv, s[k].degree_v);
            total += 2.0 * gu * gv * cells;
        } else {
            total += adaptive_estimate(&s[k], tol);
        }
    }
    *triangles = total;
    return GEOM_OK;
}
