/*
 * Output size of a B-rep tessellation before doing it: each face's
 * parameter box from its edges, the surface module's per-patch estimate
 * (surface/tess_estimate.c) over that box from the face surface's second
 * derivatives, plus the boundary samples its edges will get.
 */
#include "step/step_internal.h"
#include "surface/surface_internal.h"

#include <math.h>
#include <string.h>

/* Samples per edge for the parameter box and for the edge's own estimate. */
#define EDGE_SAMPLES 16

typedef struct face_fn {
    const geom_brep *b;
    const geom_brep_surface *S;
    double h[2]; /* difference steps in u and v */
} face_fn;

static double len3(const double *v)
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* |S_uu|, |S_uv|, |S_vv|: exact for NURBS, central differences of the
 * first derivatives for the others (closed forms, smooth everywhere). */
static int face_second(void *user, double u, double v, double out[3])
{
    const face_fn *F = user;
    if (F->S->type == GEOM_BREP_SURFACE_NURBS) {
        double ders[27];
        if (geom_surface_derivs(&F->S->nurbs, u, v, 2, 0, ders) != GEOM_OK)
            return 0;
        out[0] = len3(ders + 3 * 6);
        out[1] = len3(ders + 3 * 4);
        out[2] = len3(ders + 3 * 2);
        return 1;
    }
    double p[3], ua[3], ub[3], va[3], vb[3], w[3], d[3];
    double hu = F->h[0], hv = F->h[1];
    geom__brep_surface_eval(F->b, F->S, u + hu, v, p, ua, w);
    geom__brep_surface_eval(F->b, F->S, u - hu, v, p, ub, w);
    for (int k = 0; k < 3; k++)
        d[k] = (ua[k] - ub[k]) / (2 * hu);
    out[0] = len3(d);
    geom__brep_surface_eval(F->b, F->S, u, v + hv, p, ua, va);
    geom__brep_surface_eval(F->b, F->S, u, v - hv, p, ub, vb);
    for (int k = 0; k < 3; k++)
        d[k] = (ua[k] - ub[k]) / (2 * hv);
    out[1] = len3(d);
    for (int k = 0; k < 3; k++)
        d[k] = (va[k] - vb[k]) / (2 * hv);
    out[2] = len3(d);
    return isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]);
}

/* Pieces the tessellation cuts edge e into (its samples but one end, so
 * that a loop's pieces sum to its points): its initial pieces (as
 * sample_edge in tessellate.c) or the chords a curvature |C''| allows
 * (a chord of length l deviates by about |C''| l^2 / 8), whichever is more. */
static double edge_samples(const geom_brep *b, uint32_t e, double tol)
{
    const geom_brep_edge *E = &b->edges[e];
    const geom_brep_curve *c = &b->curves[E->curve];
    double t0 = E->t0, t1 = E->t1;
    double n0 = 1;
    if (c->type == GEOM_BREP_CURVE_CIRCLE || c->type == GEOM_BREP_CURVE_ELLIPSE)
        n0 = ceil(fabs(t1 - t0) / (GEOM_PI / 4));
    else if (c->type == GEOM_BREP_CURVE_NURBS)
        n0 = 2.0 * (double)(c->nurbs.n - (size_t)c->nurbs.degree) + 2;
    n0 = n0 < 1 ? 1 : n0 > 4096 ? 4096 : n0;
    if (c->type == GEOM_BREP_CURVE_LINE || !(t1 != t0) || !isfinite(t1 - t0))
        return n0;
    double dt = (t1 - t0) / EDGE_SAMPLES, h = fabs(dt) * 1e-3;
    double chords = 0;
    for (int k = 0; k < EDGE_SAMPLES; k++) {
        double t = t0 + (k + 0.5) * dt, p[3], da[3] = {0, 0, 0}, db[3] = {0, 0, 0}, dd[3];
        geom__brep_curve_eval(c, t + h, p, da);
        geom__brep_curve_eval(c, t - h, p, db);
        for (int q = 0; q < 3; q++)
            dd[q] = (da[q] - db[q]) / (2 * h);
        double n = sqrt(len3(dd) / (8 * tol)) * fabs(dt);
        if (isfinite(n))
            chords += n;
    }
    /* bisection lands between the needed count and twice it: 1.5 */
    double n = 1.5 * chords;
    return n > n0 ? n : n0;
}

/* The face's parameter box from EDGE_SAMPLES + 1 points of each of its
 * edges inverted onto its surface (unwrapped along each loop across the
 * seams of periodic parameters), at most one period wide. 0 when no
 * point could be placed. */
static int face_box(const geom_brep *b, const geom_brep_face *fc, double box[4])
{
    const geom_brep_surface *S = &b->surfaces[fc->surface];
    double per[2] = {S->u_periodic ? 2 * GEOM_PI : 0, S->v_periodic ? 2 * GEOM_PI : 0};
    box[0] = box[2] = INFINITY;
    box[1] = box[3] = -INFINITY;
    int any = 0;
    for (uint32_t l = 0; l < fc->nloops; l++) {
        const geom_brep_loop *L = &b->loops[fc->first_loop + l];
        double last[2];
        int have = 0;
        for (uint32_t k = 0; k < L->n; k++) {
            const geom_brep_edge *E = &b->edges[b->coedges[L->first + k].edge];
            const geom_brep_curve *c = &b->curves[E->curve];
            for (int q = 0; q <= EDGE_SAMPLES; q++) {
                double t = E->t0 + (E->t1 - E->t0) * q / EDGE_SAMPLES, p[3], uv[2];
                geom__brep_curve_eval(c, t, p, NULL);
                geom__brep_surface_invert(b, S, p, have ? last : NULL, have, uv);
                if (!isfinite(uv[0]) || !isfinite(uv[1]))
                    continue;
                for (int a = 0; a < 2; a++)
                    if (have && per[a] > 0)
                        uv[a] += per[a] * round((last[a] - uv[a]) / per[a]);
                box[0] = fmin(box[0], uv[0]);
                box[1] = fmax(box[1], uv[0]);
                box[2] = fmin(box[2], uv[1]);
                box[3] = fmax(box[3], uv[1]);
                last[0] = uv[0];
                last[1] = uv[1];
                have = any = 1;
            }
        }
    }
    for (int a = 0; a < 2; a++)
        if (per[a] > 0 && box[2 * a + 1] - box[2 * a] > per[a])
            box[2 * a + 1] = box[2 * a] + per[a];
    return any && box[1] >= box[0] && box[3] >= box[2];
}

double geom__step_default_tolerance(const geom_brep *b)
{
    geom_aabb box = geom_aabb_empty();
    for (size_t k = 0; k < b->nvertices; k++)
        box = geom_aabb_extend(box, geom_vec3_make(b->vertices[k].p[0], b->vertices[k].p[1],
                                                   b->vertices[k].p[2]));
    double diag_len = geom_aabb_is_empty(box) ? 1 : geom_vec3_length(geom_vec3_sub(box.max, box.min));
    return 1e-3 * (diag_len > 0 ? diag_len : 1);
}

geom_status geom_step_tess_estimate(const geom_brep *b, const geom_brep_tess_options *options,
                                    double *triangles, double *per_face)
{
    if (triangles)
        *triangles = 0;
    if (!b || !triangles)
        return GEOM_ERR_INVALID_ARG;
    double tol = options ? options->tolerance : 0;
    if (tol < 0 || !isfinite(tol))
        return GEOM_ERR_INVALID_ARG;
    if (!(tol > 0))
        tol = geom__step_default_tolerance(b);
    size_t ne = b->nedges ? b->nedges : 1;
    double *es = geom__alloc(options ? options->alloc : NULL, ne * sizeof *es);
    if (!es)
        return GEOM_ERR_NOMEM;
    for (size_t e = 0; e < b->nedges; e++)
        es[e] = edge_samples(b, (uint32_t)e, tol);
    double total = 0;
    for (size_t f = 0; f < b->nfaces; f++) {
        const geom_brep_face *fc = &b->faces[f];
        double t = 0, boundary = 0;
        for (uint32_t l = 0; l < fc->nloops; l++) {
            const geom_brep_loop *L = &b->loops[fc->first_loop + l];
            for (uint32_t k = 0; k < L->n; k++)
                boundary += es[b->coedges[L->first + k].edge];
        }
        double box[4];
        if (face_box(b, fc, box)) {
            face_fn F;
            F.b = b;
            F.S = &b->surfaces[fc->surface];
            size_t gu = 8, gv = 8;
            if (F.S->type == GEOM_BREP_SURFACE_NURBS) {
                /* 4 samples per knot span, as for a NURBS patch */
                gu = 4 * (F.S->nurbs.nu - (size_t)F.S->nurbs.degree_u);
                gv = 4 * (F.S->nurbs.nv - (size_t)F.S->nurbs.degree_v);
                gu = gu < 4 ? 4 : gu > 256 ? 256 : gu;
                gv = gv < 4 ? 4 : gv > 256 ? 256 : gv;
            }
            F.h[0] = 1e-4 * (box[1] - box[0]) + 1e-7;
            F.h[1] = 1e-4 * (box[3] - box[2]) + 1e-7;
            /* no floor: the face's Delaunay refinement adds interior
             * points only where the surface bends */
            t = geom__tess_estimate_grid(face_second, &F, box, gu, gv, tol, 0.0);
        }
        /* a triangulation of a polygon of n boundary points has n - 2
         * triangles before any interior point */
        t += boundary > 2 ? boundary - 2 : 1;
        if (per_face)
            per_face[f] = t;
        total += t;
    }
    geom__free(options ? options->alloc : NULL, es, ne * sizeof *es);
    *triangles = total;
    return GEOM_OK;
}
