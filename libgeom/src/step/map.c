/*
 * From the Part 21 instance table to the B-rep: the topology entities of
 * ISO 10303-42 (MANIFOLD_SOLID_BREP ... VERTEX_POINT), their curves and
 * surfaces (geometry in the B-rep's conventions, see step.h), units of
 * ISO 10303-41 (SI prefixes, CONVERSION_BASED_UNIT), and the assembly
 * structure of AP203/AP214/AP242 (representations linked by
 * REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION / ITEM_DEFINED_TRANSFORMATION,
 * and MAPPED_ITEM), flattened: every placed instance of a body gets its own
 * transformed copy.
 */
#include "step/step_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ISSUES 64

typedef struct xform {
    double R[9]; /* column-major, orthonormal (a mirror when its determinant is -1) */
    double t[3];
    double s;    /* uniform scale: p -> s R p + t */
} xform;

typedef struct mapper {
    geom__p21 *p;
    geom_brep *b;
    const geom_allocator *a;
    geom_diag *diag;
    int strict;
    size_t cap[9];
    size_t capissues;
    uint32_t *memo, *stamp;
    uint32_t inst;
    double scale;    /* file length unit -> output unit, for the current body
                      * (times the placement's scale) */
    int mirror;      /* the current placement reverses orientation */
    double angle;    /* file plane angle unit -> radians */
    xform X;         /* current placement */
    double out_m;    /* metres per output unit */
} mapper;

enum { A_SOLID, A_SHELL, A_FACE, A_LOOP, A_COEDGE, A_EDGE, A_VERTEX, A_CURVE, A_SURFACE };

static geom_status push(mapper *M, int which, void **arr, size_t *n, size_t elem, const void *item,
                        uint32_t *idx)
{
    if (*n >= UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    if (idx)
        *idx = (uint32_t)*n;
    return geom__push(M->a, arr, n, &M->cap[which], elem, item);
}

#define PUSH(M, which, field, count, item, idx)                                            \
    push(M, which, (void **)&(M)->b->field, &(M)->b->count, sizeof *(M)->b->field, item, idx)

static geom_status bad(mapper *M, uint32_t e, const char *fmt, const char *a1)
{
    const geom__p21_entity *E = &M->p->ents[e];
    char msg[320]; /* larger than a diag message (256), so no -Wformat-truncation at -O3 */
    snprintf(msg, sizeof msg, fmt, a1 ? a1 : "");
    return geom__diag_set(M->diag, GEOM_ERR_PARSE, M->p->source, E->line, E->column, "#%llu %s: %s",
                         (unsigned long long)E->id, geom__p21_type(M->p, e), msg);
}

static geom_status note(mapper *M, uint32_t e, const char *reason)
{
    geom_brep *b = M->b;
    b->nissues++;
    if (b->nissues > MAX_ISSUES)
        return GEOM_OK;
    if (b->nissues > M->capissues) {
        size_t nc = MAX_ISSUES;
        geom_brep_issue *q = geom__realloc(M->a, b->issues, M->capissues * sizeof *q, nc * sizeof *q);
        if (!q)
            return GEOM_ERR_NOMEM;
        b->issues = q;
        M->capissues = nc;
    }
    geom_brep_issue *is = &b->issues[b->nissues - 1];
    memset(is, 0, sizeof *is);
    is->entity = M->p->ents[e].id;
    snprintf(is->type, sizeof is->type, "%s", geom__p21_type(M->p, e));
    snprintf(is->reason, sizeof is->reason, "%s", reason);
    return GEOM_OK;
}

/* ----------------------------------------------------------- arguments */

static const geom__p21_value *arg(const mapper *M, const geom__p21_part_t *pt, uint32_t k)
{
    const geom__p21_value *l = &M->p->vals[pt->args];
    if (k >= l->n)
        return NULL;
    return &M->p->vals[l->off + k];
}

static int as_real(const mapper *M, const geom__p21_value *v, double *x)
{
    if (!v)
        return 0;
    if (v->kind == GEOM__P21_TYPED)
        v = &M->p->vals[v->off];
    if (v->kind == GEOM__P21_REAL) {
        *x = v->u.r;
        return 1;
    }
    if (v->kind == GEOM__P21_INT) {
        *x = (double)v->u.i;
        return 1;
    }
    return 0;
}

static int as_ref(const geom__p21_value *v, uint32_t *e)
{
    if (!v || v->kind != GEOM__P21_REF)
        return 0;
    *e = (uint32_t)v->u.ref;
    return 1;
}

static const geom__p21_value *as_list(const mapper *M, const geom__p21_value *v, uint32_t *n)
{
    *n = 0;
    if (!v || v->kind != GEOM__P21_LIST)
        return NULL;
    *n = v->n;
    return &M->p->vals[v->off];
}

static const char *as_enum(const mapper *M, const geom__p21_value *v)
{
    if (!v || v->kind != GEOM__P21_ENUM)
        return NULL;
    return geom__p21_str(M->p, v->off);
}

/* .T. / .F. (anything else, e.g. .U., gives dflt). */
static int as_bool(const mapper *M, const geom__p21_value *v, int dflt)
{
    const char *s = as_enum(M, v);
    if (!s)
        return dflt;
    if (!strcmp(s, "T"))
        return 1;
    if (!strcmp(s, "F"))
        return 0;
    return dflt;
}

static const geom__p21_part_t *first(const mapper *M, uint32_t e)
{
    return &M->p->parts[M->p->ents[e].first_part];
}

static int is_type(const mapper *M, uint32_t e, const char *t)
{
    return geom__p21_part(M->p, e, t) != NULL;
}

/* ------------------------------------------------------- points, frames */

static void xf_point(const mapper *M, const double *in, double *out)
{
    double x = in[0] * M->scale, y = in[1] * M->scale, z = in[2] * M->scale;
    const double *R = M->X.R;
    for (int k = 0; k < 3; k++)
        out[k] = R[k] * x + R[3 + k] * y + R[6 + k] * z + M->X.t[k];
}

static void xf_dir(const mapper *M, const double *in, double *out)
{
    const double *R = M->X.R;
    double x = in[0], y = in[1], z = in[2];
    for (int k = 0; k < 3; k++)
        out[k] = R[k] * x + R[3 + k] * y + R[6 + k] * z;
}

/* CARTESIAN_POINT / DIRECTION coordinates (up to 3; missing ones 0). */
static geom_status coords(mapper *M, uint32_t e, const char *type, double *out, int *dim)
{
    const geom__p21_part_t *pt = geom__p21_part(M->p, e, type);
    if (!pt)
        return bad(M, e, "expected a %s", type);
    uint32_t n;
    const geom__p21_value *l = as_list(M, arg(M, pt, 1), &n);
    if (!l || n < 1 || n > 3)
        return bad(M, e, "expected 1 to 3 coordinates%s", NULL);
    out[0] = out[1] = out[2] = 0;
    for (uint32_t k = 0; k < n; k++)
        if (!as_real(M, &l[k], &out[k]))
            return bad(M, e, "coordinate is not a number%s", NULL);
    if (dim)
        *dim = (int)n;
    return GEOM_OK;
}

static geom_status ref_coords(mapper *M, const geom__p21_value *v, uint32_t owner, const char *type,
                              double *out, int *dim)
{
    uint32_t e;
    if (!as_ref(v, &e))
        return bad(M, owner, "expected a reference to a %s", type);
    return coords(M, e, type, out, dim);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm3(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        for (int k = 0; k < 3; k++)
            v[k] /= l;
    return l;
}

/* AXIS2_PLACEMENT_3D / _2D in file coordinates: origin and unit axes. */
static geom_status placement(mapper *M, const geom__p21_value *v, uint32_t owner, double o[3],
                             double x[3], double y[3], double z[3])
{
    uint32_t e;
    if (!as_ref(v, &e))
        return bad(M, owner, "expected a reference to an AXIS2_PLACEMENT_3D%s", NULL);
    const geom__p21_part_t *pt = geom__p21_part(M->p, e, "AXIS2_PLACEMENT_3D");
    int two = 0;
    if (!pt) {
        pt = geom__p21_part(M->p, e, "AXIS2_PLACEMENT_2D");
        two = 1;
    }
    if (!pt)
        return bad(M, e, "expected AXIS2_PLACEMENT_3D%s", NULL);
    geom_status st = ref_coords(M, arg(M, pt, 1), e, "CARTESIAN_POINT", o, NULL);
    if (st)
        return st;
    z[0] = 0, z[1] = 0, z[2] = 1;
    const geom__p21_value *va = arg(M, pt, two ? 99 : 2), *vr = arg(M, pt, two ? 2 : 3);
    if (va && va->kind == GEOM__P21_REF) {
        if ((st = ref_coords(M, va, e, "DIRECTION", z, NULL)) != GEOM_OK)
            return st;
        if (norm3(z) == 0)
            return bad(M, e, "zero axis%s", NULL);
    }
    if (vr && vr->kind == GEOM__P21_REF) {
        if ((st = ref_coords(M, vr, e, "DIRECTION", x, NULL)) != GEOM_OK)
            return st;
    } else {
        x[0] = 1, x[1] = 0, x[2] = 0;
        if (fabs(z[0]) > 0.999)
            x[0] = 0, x[2] = 1;
    }
    double d = x[0] * z[0] + x[1] * z[1] + x[2] * z[2];
    for (int k = 0; k < 3; k++)
        x[k] -= d * z[k];
    if (norm3(x) == 0)
        return bad(M, e, "ref_direction parallel to the axis%s", NULL);
    y[0] = z[1] * x[2] - z[2] * x[1];
    y[1] = z[2] * x[0] - z[0] * x[2];
    y[2] = z[0] * x[1] - z[1] * x[0];
    return GEOM_OK;
}

/* A placement transformed into output coordinates. */
static geom_status placement_out(mapper *M, const geom__p21_value *v, uint32_t owner, double o[3],
                                 double x[3], double y[3], double z[3])
{
    double lo[3], lx[3], ly[3], lz[3];
    geom_status st = placement(M, v, owner, lo, lx, ly, lz);
    if (st)
        return st;
    xf_point(M, lo, o);
    xf_dir(M, lx, x);
    xf_dir(M, ly, y);
    xf_dir(M, lz, z);
    return GEOM_OK;
}

/* --------------------------------------------------------------- curves */

static geom_status knots_from(mapper *M, uint32_t e, const geom__p21_value *vm,
                              const geom__p21_value *vk, size_t need, double **out)
{
    uint32_t nm = 0, nk = 0;
    const geom__p21_value *lm = as_list(M, vm, &nm), *lk = as_list(M, vk, &nk);
    if (!lm || !lk || nm != nk || nk < 2)
        return bad(M, e, "knot multiplicities and knots must be lists of equal length%s", NULL);
    size_t total = 0;
    for (uint32_t k = 0; k < nm; k++) {
        double m;
        if (!as_real(M, &lm[k], &m) || m < 1 || m > 64 || m != floor(m))
            return bad(M, e, "bad knot multiplicity%s", NULL);
        total += (size_t)m;
    }
    if (total != need)
        return bad(M, e, "knot multiplicities do not add up to points + degree + 1%s", NULL);
    double *kn = geom__alloc(M->a, need * sizeof *kn);
    if (!kn)
        return GEOM_ERR_NOMEM;
    size_t j = 0;
    for (uint32_t k = 0; k < nm; k++) {
        double m = 1, x;
        as_real(M, &lm[k], &m);
        if (!as_real(M, &lk[k], &x) || !isfinite(x)) {
            geom__free(M->a, kn, need * sizeof *kn);
            return bad(M, e, "knot is not a number%s", NULL);
        }
        for (int r = 0; r < (int)m; r++)
            kn[j++] = x;
    }
    *out = kn;
    return GEOM_OK;
}

static void free_curve(const geom_allocator *a, geom_brep_curve *c)
{
    if (c->type != GEOM_BREP_CURVE_NURBS)
        return;
    geom__free(a, (void *)c->nurbs.knots, c->nknots * sizeof(double));
    geom__free(a, (void *)c->nurbs.points, c->nurbs.n * c->nurbs.dim * sizeof(double));
    geom__free(a, (void *)c->nurbs.weights, c->nurbs.n * sizeof(double));
    c->nurbs.knots = c->nurbs.points = c->nurbs.weights = NULL;
}

static geom_status bspline_curve(mapper *M, uint32_t e, int dim2, geom_brep_curve *c)
{
    const geom__p21_part_t *pb = geom__p21_part(M->p, e, "B_SPLINE_CURVE_WITH_KNOTS");
    const geom__p21_part_t *pc = geom__p21_part(M->p, e, "B_SPLINE_CURVE");
    const geom__p21_part_t *pr = geom__p21_part(M->p, e, "RATIONAL_B_SPLINE_CURVE");
    uint32_t off = 0; /* simple form: name first */
    const geom__p21_part_t *pd = pc;
    if (!pc) {
        pd = pb;
        off = 1;
    }
    if (!pb || !pd)
        return note(M, e, "B-spline curve without knots (BEZIER / UNIFORM forms unsupported)") ? GEOM_ERR_NOMEM : GEOM_ERR_DOMAIN;
    double deg;
    uint32_t n;
    const geom__p21_value *pts;
    if (!as_real(M, arg(M, pd, off + 0), &deg) || deg < 1 || deg > 32 ||
        !(pts = as_list(M, arg(M, pd, off + 1), &n)) || n < (uint32_t)deg + 1)
        return bad(M, e, "bad degree or control points%s", NULL);
    /* in the simple form the knots follow the 5 B_SPLINE_CURVE attributes */
    uint32_t koff = pc ? 0 : 6;
    memset(c, 0, sizeof *c);
    c->type = GEOM_BREP_CURVE_NURBS;
    c->entity = M->p->ents[e].id;
    c->dim = dim2 ? 2 : 3;
    size_t need = n + (size_t)deg + 1;
    double *kn = NULL, *P = NULL, *W = NULL;
    geom_status st = knots_from(M, e, arg(M, pb, koff), arg(M, pb, koff + 1), need, &kn);
    if (st)
        return st;
    P = geom__alloc(M->a, (size_t)n * c->dim * sizeof *P);
    if (!P) {
        geom__free(M->a, kn, need * sizeof *kn);
        return GEOM_ERR_NOMEM;
    }
    c->nurbs.degree = (int)deg;
    c->nurbs.n = n;
    c->nurbs.dim = (size_t)c->dim;
    c->nurbs.knots = kn;
    c->nurbs.points = P;
    c->nknots = need;
    for (uint32_t k = 0; k < n && !st; k++) {
        double q[3];
        uint32_t pe;
        if (!as_ref(&pts[k], &pe))
            st = bad(M, e, "control point is not a reference%s", NULL);
        else
            st = coords(M, pe, "CARTESIAN_POINT", q, NULL);
        if (!st) {
            if (dim2) {
                P[2 * k] = q[0];
                P[2 * k + 1] = q[1];
            } else {
                xf_point(M, q, P + 3 * k);
            }
        }
    }
    if (!st && pr) {
        uint32_t nw;
        const geom__p21_value *lw = as_list(M, arg(M, pr, 0), &nw);
        W = geom__alloc(M->a, (size_t)n * sizeof *W);
        if (!W)
            st = GEOM_ERR_NOMEM;
        else if (!lw || nw != n)
            st = bad(M, e, "weights do not match the control points%s", NULL);
        for (uint32_t k = 0; k < n && !st; k++)
            if (!as_real(M, &lw[k], &W[k]) || !(W[k] > 0) || !isfinite(W[k]))
                st = bad(M, e, "weight not a finite number > 0%s", NULL);
        c->nurbs.weights = W;
    }
    if (!st) {
        geom_diag d;
        if (geom_curve_nurbs_validate(&c->nurbs, need, &d) != GEOM_OK)
            st = bad(M, e, "%s", d.message);
    }
    if (st)
        free_curve(M->a, c);
    return st;
}

static geom_status map_curve_(mapper *M, uint32_t e, int dim2, uint32_t *out, int *sense, int depth);

/* A curve entity: *out its index; *sense 0 when a TRIMMED_CURVE runs
 * against its basis. GEOM_ERR_DOMAIN for an unsupported curve (noted). */
static geom_status map_curve(mapper *M, uint32_t e, int dim2, uint32_t *out, int *sense)
{
    *sense = 1;
    return map_curve_(M, e, dim2, out, sense, 0);
}

static geom_status map_curve_(mapper *M, uint32_t e, int dim2, uint32_t *out, int *sense, int depth)
{
    if (depth > 8)
        return bad(M, e, "curves nested too deeply%s", NULL);
    const char *ty = geom__p21_type(M->p, e);
    if (!dim2 && M->stamp[e] == M->inst && strcmp(ty, "TRIMMED_CURVE") != 0) {
        *out = M->memo[e];
        return GEOM_OK;
    }
    geom_brep_curve c;
    memset(&c, 0, sizeof c);
    c.entity = M->p->ents[e].id;
    c.dim = dim2 ? 2 : 3;
    geom_status st = GEOM_OK;
    const geom__p21_part_t *pt;
    if ((pt = geom__p21_part(M->p, e, "TRIMMED_CURVE")) != NULL) {
        uint32_t basis;
        if (!as_ref(arg(M, pt, 1), &basis))
            return bad(M, e, "basis curve is not a reference%s", NULL);
        if (!as_bool(M, arg(M, pt, 4), 1))
            *sense = !*sense;
        return map_curve_(M, basis, dim2, out, sense, depth + 1);
    }
    if ((pt = geom__p21_part(M->p, e, "SURFACE_CURVE")) != NULL ||
        (pt = geom__p21_part(M->p, e, "SEAM_CURVE")) != NULL ||
        (pt = geom__p21_part(M->p, e, "INTERSECTION_CURVE")) != NULL) {
        uint32_t c3;
        if (!as_ref(arg(M, pt, 1), &c3))
            return bad(M, e, "curve_3d is not a reference%s", NULL);
        return map_curve_(M, c3, dim2, out, sense, depth + 1);
    }
    if ((pt = geom__p21_part(M->p, e, "LINE")) != NULL) {
        double o[3], d[3], mag;
        uint32_t ve;
        if ((st = ref_coords(M, arg(M, pt, 1), e, "CARTESIAN_POINT", o, NULL)) != GEOM_OK)
            return st;
        if (!as_ref(arg(M, pt, 2), &ve) || !geom__p21_part(M->p, ve, "VECTOR"))
            return bad(M, e, "expected a VECTOR%s", NULL);
        const geom__p21_part_t *pv = geom__p21_part(M->p, ve, "VECTOR");
        if ((st = ref_coords(M, arg(M, pv, 1), ve, "DIRECTION", d, NULL)) != GEOM_OK)
            return st;
        if (!as_real(M, arg(M, pv, 2), &mag))
            return bad(M, ve, "magnitude is not a number%s", NULL);
        if (norm3(d) == 0 || mag == 0)
            return bad(M, e, "zero direction%s", NULL);
        c.type = GEOM_BREP_CURVE_LINE;
        if (dim2) {
            memcpy(c.origin, o, sizeof o);
            for (int k = 0; k < 3; k++)
                c.dir[k] = d[k] * mag;
        } else {
            double dd[3] = {d[0] * mag * M->scale, d[1] * mag * M->scale, d[2] * mag * M->scale};
            xf_point(M, o, c.origin);
            xf_dir(M, dd, c.dir);
        }
    } else if ((pt = geom__p21_part(M->p, e, "CIRCLE")) != NULL ||
               (pt = geom__p21_part(M->p, e, "ELLIPSE")) != NULL) {
        int circ = geom__p21_part(M->p, e, "CIRCLE") != NULL;
        double r1, r2 = 0;
        if (!as_real(M, arg(M, pt, 2), &r1) || !(r1 > 0) ||
            (!circ && (!as_real(M, arg(M, pt, 3), &r2) || !(r2 > 0))))
            return bad(M, e, "radius not a number > 0%s", NULL);
        if (dim2) {
            if ((st = placement(M, arg(M, pt, 1), e, c.origin, c.x, c.y, c.z)) != GEOM_OK)
                return st;
        } else {
            if ((st = placement_out(M, arg(M, pt, 1), e, c.origin, c.x, c.y, c.z)) != GEOM_OK)
                return st;
            r1 *= M->scale;
            r2 *= M->scale;
        }
        c.type = circ ? GEOM_BREP_CURVE_CIRCLE : GEOM_BREP_CURVE_ELLIPSE;
        c.r1 = r1;
        c.r2 = circ ? r1 : r2;
    } else if (geom__p21_part(M->p, e, "B_SPLINE_CURVE_WITH_KNOTS") ||
               geom__p21_part(M->p, e, "B_SPLINE_CURVE")) {
        st = bspline_curve(M, e, dim2, &c);
        if (st)
            return st;
    } else if ((pt = geom__p21_part(M->p, e, "POLYLINE")) != NULL) {
        uint32_t n;
        const geom__p21_value *l = as_list(M, arg(M, pt, 1), &n);
        if (!l || n < 2)
            return bad(M, e, "fewer than two points%s", NULL);
        c.type = GEOM_BREP_CURVE_NURBS;
        c.nurbs.degree = 1;
        c.nurbs.n = n;
        c.nurbs.dim = (size_t)c.dim;
        c.nknots = (size_t)n + 2;
        double *kn = geom__alloc(M->a, c.nknots * sizeof *kn);
        double *P = geom__alloc(M->a, (size_t)n * c.nurbs.dim * sizeof *P);
        c.nurbs.knots = kn;
        c.nurbs.points = P;
        if (!kn || !P) {
            free_curve(M->a, &c);
            return GEOM_ERR_NOMEM;
        }
        kn[0] = 0;
        for (uint32_t k = 0; k < n; k++)
            kn[k + 1] = k;
        kn[n + 1] = n - 1;
        for (uint32_t k = 0; k < n && !st; k++) {
            double q[3];
            st = ref_coords(M, &l[k], e, "CARTESIAN_POINT", q, NULL);
            if (!st) {
                if (dim2)
                    P[2 * k] = q[0], P[2 * k + 1] = q[1];
                else
                    xf_point(M, q, P + 3 * k);
            }
        }
        if (st) {
            free_curve(M->a, &c);
            return st;
        }
    } else {
        if ((st = note(M, e, "unsupported curve type")) != GEOM_OK)
            return st;
        return GEOM_ERR_DOMAIN;
    }
    if ((st = PUSH(M, A_CURVE, curves, ncurves, &c, out)) != GEOM_OK) {
        free_curve(M->a, &c);
        return st;
    }
    if (!dim2) {
        M->stamp[e] = M->inst;
        M->memo[e] = *out;
    }
    return GEOM_OK;
}

/* ------------------------------------------------------------- surfaces */

static void free_surface(const geom_allocator *a, geom_brep_surface *s)
{
    if (s->type != GEOM_BREP_SURFACE_NURBS)
        return;
    const geom_nurbs_surface *n = &s->nurbs;
    geom__free(a, (void *)n->knots_u, (n->nu + (size_t)n->degree_u + 1) * sizeof(double));
    geom__free(a, (void *)n->knots_v, (n->nv + (size_t)n->degree_v + 1) * sizeof(double));
    geom__free(a, (void *)n->points, 3 * n->nu * n->nv * sizeof(double));
    geom__free(a, (void *)n->weights, n->nu * n->nv * sizeof(double));
    s->nurbs.knots_u = s->nurbs.knots_v = s->nurbs.points = s->nurbs.weights = NULL;
}

static geom_status bspline_surface(mapper *M, uint32_t e, geom_brep_surface *s)
{
    const geom__p21_part_t *pb = geom__p21_part(M->p, e, "B_SPLINE_SURFACE_WITH_KNOTS");
    const geom__p21_part_t *pc = geom__p21_part(M->p, e, "B_SPLINE_SURFACE");
    const geom__p21_part_t *pr = geom__p21_part(M->p, e, "RATIONAL_B_SPLINE_SURFACE");
    uint32_t off = pc ? 0 : 1;
    const geom__p21_part_t *pd = pc ? pc : pb;
    if (!pb)
        return GEOM_ERR_DOMAIN;
    double du, dv;
    uint32_t nu, nv;
    const geom__p21_value *rows;
    if (!as_real(M, arg(M, pd, off), &du) || !as_real(M, arg(M, pd, off + 1), &dv) || du < 1 ||
        dv < 1 || du > 32 || dv > 32 || !(rows = as_list(M, arg(M, pd, off + 2), &nu)) ||
        nu < (uint32_t)du + 1)
        return bad(M, e, "bad degrees or control points%s", NULL);
    const geom__p21_value *r0 = as_list(M, &rows[0], &nv);
    if (!r0 || nv < (uint32_t)dv + 1)
        return bad(M, e, "bad control point rows%s", NULL);
    size_t np;
    if (geom__size_mul(nu, nv, &np) || np > ((size_t)1 << 24))
        return bad(M, e, "too many control points%s", NULL);
    uint32_t koff = pc ? 0 : 8;
    memset(s, 0, sizeof *s);
    s->type = GEOM_BREP_SURFACE_NURBS;
    s->entity = M->p->ents[e].id;
    geom_nurbs_surface *n = &s->nurbs;
    n->degree_u = (int)du;
    n->degree_v = (int)dv;
    n->nu = nu;
    n->nv = nv;
    double *ku = NULL, *kv = NULL, *P = NULL, *W = NULL;
    geom_status st = knots_from(M, e, arg(M, pb, koff), arg(M, pb, koff + 2), nu + (size_t)du + 1, &ku);
    if (st)
        return st;
    n->knots_u = ku;
    st = knots_from(M, e, arg(M, pb, koff + 1), arg(M, pb, koff + 3), nv + (size_t)dv + 1, &kv);
    n->knots_v = kv;
    if (!st) {
        P = geom__alloc(M->a, 3 * np * sizeof *P);
        n->points = P;
        if (!P)
            st = GEOM_ERR_NOMEM;
    }
    for (uint32_t i = 0; i < nu && !st; i++) {
        uint32_t m;
        const geom__p21_value *row = as_list(M, &rows[i], &m);
        if (!row || m != nv) {
            st = bad(M, e, "control point rows of different lengths%s", NULL);
            break;
        }
        for (uint32_t j = 0; j < nv && !st; j++) {
            double q[3];
            st = ref_coords(M, &row[j], e, "CARTESIAN_POINT", q, NULL);
            if (!st)
                xf_point(M, q, P + 3 * ((size_t)i * nv + j));
        }
    }
    if (!st && pr) {
        uint32_t m;
        const geom__p21_value *wr = as_list(M, arg(M, pr, 0), &m);
        W = geom__alloc(M->a, np * sizeof *W);
        n->weights = W;
        if (!W)
            st = GEOM_ERR_NOMEM;
        else if (!wr || m != nu)
            st = bad(M, e, "weights do not match the control points%s", NULL);
        for (uint32_t i = 0; i < nu && !st; i++) {
            uint32_t mm;
            const geom__p21_value *row = as_list(M, &wr[i], &mm);
            if (!row || mm != nv) {
                st = bad(M, e, "weights do not match the control points%s", NULL);
                break;
            }
            for (uint32_t j = 0; j < nv && !st; j++) {
                double w;
                if (!as_real(M, &row[j], &w) || !(w > 0) || !isfinite(w))
                    st = bad(M, e, "weight not a finite number > 0%s", NULL);
                else
                    W[(size_t)i * nv + j] = w;
            }
        }
    }
    if (!st) {
        geom_diag d;
        if (geom_surface_validate(n, &d) != GEOM_OK)
            st = bad(M, e, "%s", d.message);
    }
    if (st)
        free_surface(M->a, s);
    return st;
}

/* A surface entity; GEOM_ERR_DOMAIN for an unsupported one (noted). */
static geom_status map_surface(mapper *M, uint32_t e, uint32_t *out, int depth)
{
    if (M->stamp[e] == M->inst) {
        *out = M->memo[e];
        return GEOM_OK;
    }
    if (depth > 8)
        return bad(M, e, "surfaces nested too deeply%s", NULL);
    geom_brep_surface s;
    memset(&s, 0, sizeof s);
    s.entity = M->p->ents[e].id;
    s.curve = GEOM_INVALID_INDEX;
    geom_status st = GEOM_OK;
    const geom__p21_part_t *pt;
    const char *ty = geom__p21_type(M->p, e);
    double r = 0;
    if ((pt = geom__p21_part(M->p, e, "PLANE")) != NULL) {
        s.type = GEOM_BREP_SURFACE_PLANE;
        st = placement_out(M, arg(M, pt, 1), e, s.origin, s.x, s.y, s.z);
    } else if ((pt = geom__p21_part(M->p, e, "CYLINDRICAL_SURFACE")) != NULL ||
               (pt = geom__p21_part(M->p, e, "SPHERICAL_SURFACE")) != NULL) {
        s.type = !strcmp(M->p->pool + pt->name, "SPHERICAL_SURFACE") ? GEOM_BREP_SURFACE_SPHERE
                                                                    : GEOM_BREP_SURFACE_CYLINDER;
        st = placement_out(M, arg(M, pt, 1), e, s.origin, s.x, s.y, s.z);
        if (!st && (!as_real(M, arg(M, pt, 2), &r) || !(r > 0)))
            st = bad(M, e, "radius not a number > 0%s", NULL);
        s.r1 = r * M->scale;
        s.u_periodic = 1;
    } else if ((pt = geom__p21_part(M->p, e, "CONICAL_SURFACE")) != NULL) {
        double a = 0;
        s.type = GEOM_BREP_SURFACE_CONE;
        st = placement_out(M, arg(M, pt, 1), e, s.origin, s.x, s.y, s.z);
        if (!st && (!as_real(M, arg(M, pt, 2), &r) || !(r >= 0) || !as_real(M, arg(M, pt, 3), &a)))
            st = bad(M, e, "bad radius or semi-angle%s", NULL);
        s.r1 = r * M->scale;
        s.r2 = a * M->angle;
        if (!st && !(fabs(s.r2) > 0 && fabs(s.r2) < GEOM_PI / 2))
            st = bad(M, e, "semi-angle outside (0, 90) degrees%s", NULL);
        s.u_periodic = 1;
    } else if ((pt = geom__p21_part(M->p, e, "TOROIDAL_SURFACE")) != NULL ||
               (pt = geom__p21_part(M->p, e, "DEGENERATE_TOROIDAL_SURFACE")) != NULL) {
        double r2 = 0;
        s.type = GEOM_BREP_SURFACE_TORUS;
        st = placement_out(M, arg(M, pt, 1), e, s.origin, s.x, s.y, s.z);
        if (!st && (!as_real(M, arg(M, pt, 2), &r) || !as_real(M, arg(M, pt, 3), &r2) || !(r > 0) ||
                    !(r2 > 0)))
            st = bad(M, e, "radii not numbers > 0%s", NULL);
        s.r1 = r * M->scale;
        s.r2 = r2 * M->scale;
        s.u_periodic = s.v_periodic = 1;
    } else if (geom__p21_part(M->p, e, "B_SPLINE_SURFACE_WITH_KNOTS")) {
        st = bspline_surface(M, e, &s);
    } else if ((pt = geom__p21_part(M->p, e, "SURFACE_OF_REVOLUTION")) != NULL) {
        uint32_t ce, ae;
        int sense;
        s.type = GEOM_BREP_SURFACE_REVOLUTION;
        s.u_periodic = 1;
        if (!as_ref(arg(M, pt, 1), &ce) || !as_ref(arg(M, pt, 2), &ae) ||
            !geom__p21_part(M->p, ae, "AXIS1_PLACEMENT"))
            return bad(M, e, "expected a curve and an AXIS1_PLACEMENT%s", NULL);
        const geom__p21_part_t *pa = geom__p21_part(M->p, ae, "AXIS1_PLACEMENT");
        double o[3], z[3] = {0, 0, 1};
        if ((st = ref_coords(M, arg(M, pa, 1), ae, "CARTESIAN_POINT", o, NULL)) != GEOM_OK)
            return st;
        const geom__p21_value *va = arg(M, pa, 2);
        if (va && va->kind == GEOM__P21_REF && (st = ref_coords(M, va, ae, "DIRECTION", z, NULL)) != GEOM_OK)
            return st;
        if (norm3(z) == 0)
            return bad(M, ae, "zero axis%s", NULL);
        xf_point(M, o, s.origin);
        xf_dir(M, z, s.z);
        if (M->mirror) /* a mirror turns a rotation about z into one about -z */
            for (int k = 0; k < 3; k++)
                s.z[k] = -s.z[k];
        if ((st = map_curve(M, ce, 0, &s.curve, &sense)) != GEOM_OK)
            return st;
    } else if ((pt = geom__p21_part(M->p, e, "SURFACE_OF_LINEAR_EXTRUSION")) != NULL) {
        uint32_t ce, ve;
        int sense;
        s.type = GEOM_BREP_SURFACE_EXTRUSION;
        if (!as_ref(arg(M, pt, 1), &ce) || !as_ref(arg(M, pt, 2), &ve) ||
            !geom__p21_part(M->p, ve, "VECTOR"))
            return bad(M, e, "expected a curve and a VECTOR%s", NULL);
        const geom__p21_part_t *pv = geom__p21_part(M->p, ve, "VECTOR");
        double d[3], mag;
        if ((st = ref_coords(M, arg(M, pv, 1), ve, "DIRECTION", d, NULL)) != GEOM_OK)
            return st;
        if (!as_real(M, arg(M, pv, 2), &mag) || norm3(d) == 0 || mag == 0)
            return bad(M, ve, "zero extrusion vector%s", NULL);
        for (int k = 0; k < 3; k++)
            d[k] *= mag * M->scale;
        xf_dir(M, d, s.dir);
        if ((st = map_curve(M, ce, 0, &s.curve, &sense)) != GEOM_OK)
            return st;
    } else if ((pt = geom__p21_part(M->p, e, "OFFSET_SURFACE")) != NULL) {
        /* exact for offsets of planes, cylinders, spheres and tori: the
         * same kind of surface with a shifted origin or radius */
        uint32_t be, bi;
        double d;
        if (!as_ref(arg(M, pt, 1), &be) || !as_real(M, arg(M, pt, 2), &d))
            return bad(M, e, "expected a basis surface and a distance%s", NULL);
        if ((st = map_surface(M, be, &bi, depth + 1)) != GEOM_OK)
            return st;
        s = M->b->surfaces[bi];
        s.entity = M->p->ents[e].id;
        d *= M->scale;
        if (s.type == GEOM_BREP_SURFACE_PLANE) {
            for (int k = 0; k < 3; k++)
                s.origin[k] += d * s.z[k];
        } else if (s.type == GEOM_BREP_SURFACE_CYLINDER || s.type == GEOM_BREP_SURFACE_SPHERE) {
            s.r1 += d;
        } else if (s.type == GEOM_BREP_SURFACE_TORUS) {
            s.r2 += d;
        } else {
            if ((st = note(M, e, "offset of this surface type is not exact: unsupported")) != GEOM_OK)
                return st;
            return GEOM_ERR_DOMAIN;
        }
        if (!(s.r1 >= 0) || (s.type == GEOM_BREP_SURFACE_TORUS && !(s.r2 > 0)))
            return bad(M, e, "offset collapses the surface%s", NULL);
    } else {
        (void)ty;
        if ((st = note(M, e, "unsupported surface type")) != GEOM_OK)
            return st;
        return GEOM_ERR_DOMAIN;
    }
    if (st)
        return st;
    if ((st = PUSH(M, A_SURFACE, surfaces, nsurfaces, &s, out)) != GEOM_OK) {
        free_surface(M->a, &s);
        return st;
    }
    M->stamp[e] = M->inst;
    M->memo[e] = *out;
    return GEOM_OK;
}

/* ------------------------------------------------------------- topology */

static geom_status map_vertex(mapper *M, uint32_t e, uint32_t *out)
{
    if (M->stamp[e] == M->inst) {
        *out = M->memo[e];
        return GEOM_OK;
    }
    const geom__p21_part_t *pt = geom__p21_part(M->p, e, "VERTEX_POINT");
    if (!pt)
        return bad(M, e, "expected a VERTEX_POINT%s", NULL);
    double q[3];
    geom_status st = ref_coords(M, arg(M, pt, 1), e, "CARTESIAN_POINT", q, NULL);
    if (st)
        return st;
    geom_brep_vertex v;
    xf_point(M, q, v.p);
    v.entity = M->p->ents[e].id;
    if ((st = PUSH(M, A_VERTEX, vertices, nvertices, &v, out)) != GEOM_OK)
        return st;
    M->stamp[e] = M->inst;
    M->memo[e] = *out;
    return GEOM_OK;
}

/* The pcurves of a SURFACE_CURVE / SEAM_CURVE geometry (up to two). */
static geom_status edge_pcurves(mapper *M, uint32_t g, geom_brep_edge *E)
{
    const geom__p21_part_t *pt = geom__p21_part(M->p, g, "SURFACE_CURVE");
    if (!pt)
        pt = geom__p21_part(M->p, g, "SEAM_CURVE");
    if (!pt)
        pt = geom__p21_part(M->p, g, "INTERSECTION_CURVE");
    if (!pt)
        return GEOM_OK;
    uint32_t n;
    const geom__p21_value *l = as_list(M, arg(M, pt, 2), &n);
    for (uint32_t k = 0, j = 0; l && k < n && j < 2; k++) {
        uint32_t pe;
        if (!as_ref(&l[k], &pe))
            continue;
        const geom__p21_part_t *pp = geom__p21_part(M->p, pe, "PCURVE");
        if (!pp)
            continue;
        uint32_t se, de, ce;
        if (!as_ref(arg(M, pp, 1), &se) || !as_ref(arg(M, pp, 2), &de))
            return bad(M, pe, "expected a surface and a DEFINITIONAL_REPRESENTATION%s", NULL);
        const geom__p21_part_t *pd = first(M, de);
        uint32_t ni;
        const geom__p21_value *items = as_list(M, arg(M, pd, 1), &ni);
        if (!items || ni < 1 || !as_ref(&items[0], &ce))
            return bad(M, de, "no curve in the definitional representation%s", NULL);
        uint32_t si, ci;
        int sense;
        geom_status st = map_surface(M, se, &si, 0);
        if (st == GEOM_ERR_DOMAIN)
            continue;
        if (st)
            return st;
        st = map_curve(M, ce, 1, &ci, &sense);
        if (st == GEOM_ERR_DOMAIN)
            continue;
        if (st)
            return st;
        E->pcurve[j] = ci;
        E->pcurve_surface[j] = si;
        j++;
    }
    return GEOM_OK;
}

static geom_status map_edge(mapper *M, uint32_t e, uint32_t *out)
{
    if (M->stamp[e] == M->inst) {
        *out = M->memo[e];
        return GEOM_OK;
    }
    const geom__p21_part_t *pt = geom__p21_part(M->p, e, "EDGE_CURVE");
    if (!pt)
        return bad(M, e, "expected an EDGE_CURVE%s", NULL);
    geom_brep_edge E;
    memset(&E, 0, sizeof E);
    E.entity = M->p->ents[e].id;
    E.pcurve[0] = E.pcurve[1] = E.pcurve_surface[0] = E.pcurve_surface[1] = GEOM_INVALID_INDEX;
    uint32_t v0, v1, g;
    if (!as_ref(arg(M, pt, 1), &v0) || !as_ref(arg(M, pt, 2), &v1) || !as_ref(arg(M, pt, 3), &g))
        return bad(M, e, "expected two vertices and a curve%s", NULL);
    geom_status st;
    if ((st = map_vertex(M, v0, &E.v0)) != GEOM_OK || (st = map_vertex(M, v1, &E.v1)) != GEOM_OK)
        return st;
    int sense;
    if ((st = map_curve(M, g, 0, &E.curve, &sense)) != GEOM_OK)
        return st;
    E.same_sense = as_bool(M, arg(M, pt, 4), 1);
    if (!sense)
        E.same_sense = !E.same_sense;
    if ((st = edge_pcurves(M, g, &E)) != GEOM_OK)
        return st;
    /* curve parameters of the end vertices */
    const geom_brep_curve *c = &M->b->curves[E.curve];
    const double *p0 = M->b->vertices[E.v0].p, *p1 = M->b->vertices[E.v1].p;
    double d0 = geom__brep_curve_invert(c, p0, 0, 0, &E.t0);
    double d1 = geom__brep_curve_invert(c, p1, 0, 0, &E.t1);
    (void)d0;
    (void)d1;
    double lo, hi;
    int closed_vertex = E.v0 == E.v1 || (p0[0] == p1[0] && p0[1] == p1[1] && p0[2] == p1[2]);
    if (geom__brep_curve_periodic(c)) {
        double P = 2 * GEOM_PI;
        if (E.same_sense) {
            while (E.t1 <= E.t0 + 1e-12)
                E.t1 += P;
            if (!closed_vertex && E.t1 - E.t0 > P - 1e-12)
                E.t1 -= P;
        } else {
            while (E.t1 >= E.t0 - 1e-12)
                E.t1 -= P;
            if (!closed_vertex && E.t0 - E.t1 > P - 1e-12)
                E.t1 += P;
        }
    } else if (closed_vertex && geom__brep_curve_domain(c, &lo, &hi)) {
        /* a closed B-spline edge runs over its whole domain */
        E.t0 = E.same_sense ? lo : hi;
        E.t1 = E.same_sense ? hi : lo;
    }
    if ((st = PUSH(M, A_EDGE, edges, nedges, &E, out)) != GEOM_OK)
        return st;
    M->stamp[e] = M->inst;
    M->memo[e] = *out;
    return GEOM_OK;
}

static geom_status map_loop(mapper *M, uint32_t be, int outer, uint32_t *out)
{
    const geom__p21_part_t *pt = geom__p21_part(M->p, be, "FACE_OUTER_BOUND");
    if (!pt)
        pt = geom__p21_part(M->p, be, "FACE_BOUND");
    if (!pt)
        return bad(M, be, "expected a FACE_BOUND%s", NULL);
    if (geom__p21_part(M->p, be, "FACE_OUTER_BOUND"))
        outer = 1;
    uint32_t le;
    if (!as_ref(arg(M, pt, 1), &le))
        return bad(M, be, "bound is not a reference%s", NULL);
    geom_brep_loop L;
    memset(&L, 0, sizeof L);
    L.outer = outer;
    L.orientation = as_bool(M, arg(M, pt, 2), 1);
    L.entity = M->p->ents[le].id;
    L.vertex = GEOM_INVALID_INDEX;
    L.first = (uint32_t)M->b->ncoedges;
    geom_status st;
    const geom__p21_part_t *pl;
    if ((pl = geom__p21_part(M->p, le, "VERTEX_LOOP")) != NULL) {
        uint32_t ve;
        if (!as_ref(arg(M, pl, 1), &ve))
            return bad(M, le, "vertex is not a reference%s", NULL);
        if ((st = map_vertex(M, ve, &L.vertex)) != GEOM_OK)
            return st;
    } else if ((pl = geom__p21_part(M->p, le, "EDGE_LOOP")) != NULL) {
        uint32_t n;
        const geom__p21_value *l = as_list(M, arg(M, pl, 1), &n);
        if (!l || n < 1)
            return bad(M, le, "empty edge loop%s", NULL);
        for (uint32_t k = 0; k < n; k++) {
            uint32_t oe, ee;
            const geom__p21_part_t *po;
            if (!as_ref(&l[k], &oe) || !(po = geom__p21_part(M->p, oe, "ORIENTED_EDGE")))
                return bad(M, le, "expected ORIENTED_EDGE references%s", NULL);
            if (!as_ref(arg(M, po, 3), &ee))
                return bad(M, oe, "edge_element is not a reference%s", NULL);
            geom_brep_coedge ce;
            ce.reversed = !as_bool(M, arg(M, po, 4), 1);
            if ((st = map_edge(M, ee, &ce.edge)) != GEOM_OK)
                return st;
            if ((st = PUSH(M, A_COEDGE, coedges, ncoedges, &ce, NULL)) != GEOM_OK)
                return st;
        }
        L.n = (uint32_t)(M->b->ncoedges - L.first);
    } else {
        if ((st = note(M, le, "unsupported loop type")) != GEOM_OK)
            return st;
        return GEOM_ERR_DOMAIN;
    }
    return PUSH(M, A_LOOP, loops, nloops, &L, out);
}

static geom_status map_face(mapper *M, uint32_t fe, uint32_t shell, int flip)
{
    const geom__p21_part_t *pt = geom__p21_part(M->p, fe, "ADVANCED_FACE");
    if (!pt)
        pt = geom__p21_part(M->p, fe, "FACE_SURFACE");
    if (!pt) {
        geom_status st = note(M, fe, "unsupported face type");
        if (st)
            return st;
        M->b->nskipped_faces++;
        return M->strict ? bad(M, fe, "unsupported face type%s", NULL) : GEOM_OK;
    }
    uint32_t se, nb;
    const geom__p21_value *bl = as_list(M, arg(M, pt, 1), &nb);
    if (!bl || !as_ref(arg(M, pt, 2), &se))
        return bad(M, fe, "expected bounds and a surface%s", NULL);
    geom_brep_face F;
    memset(&F, 0, sizeof F);
    F.entity = M->p->ents[fe].id;
    F.shell = shell;
    F.same_sense = as_bool(M, arg(M, pt, 3), 1);
    if (flip ^ M->mirror) /* a mirrored placement turns S_u x S_v inward */
        F.same_sense = !F.same_sense;
    size_t nl0 = M->b->nloops, nc0 = M->b->ncoedges;
    geom_status st = map_surface(M, se, &F.surface, 0);
    F.first_loop = (uint32_t)M->b->nloops;
    for (uint32_t k = 0; k < nb && st == GEOM_OK; k++) {
        uint32_t be;
        if (!as_ref(&bl[k], &be))
            return bad(M, fe, "bound is not a reference%s", NULL);
        st = map_loop(M, be, 0, NULL);
    }
    if (st == GEOM_ERR_DOMAIN) {
        M->b->nloops = nl0;
        M->b->ncoedges = nc0;
        M->b->nskipped_faces++;
        return M->strict ? bad(M, fe, "face on unsupported geometry%s", NULL) : GEOM_OK;
    }
    if (st)
        return st;
    F.nloops = (uint32_t)(M->b->nloops - F.first_loop);
    return PUSH(M, A_FACE, faces, nfaces, &F, NULL);
}

static geom_status map_shell(mapper *M, uint32_t se, uint32_t solid, int flip)
{
    const geom__p21_part_t *pt;
    if ((pt = geom__p21_part(M->p, se, "ORIENTED_CLOSED_SHELL")) != NULL ||
        (pt = geom__p21_part(M->p, se, "ORIENTED_OPEN_SHELL")) != NULL) {
        uint32_t inner;
        if (!as_ref(arg(M, pt, 2), &inner))
            return bad(M, se, "shell element is not a reference%s", NULL);
        return map_shell(M, inner, solid, flip ^ !as_bool(M, arg(M, pt, 3), 1));
    }
    int closed = 1;
    pt = geom__p21_part(M->p, se, "CLOSED_SHELL");
    if (!pt) {
        pt = geom__p21_part(M->p, se, "OPEN_SHELL");
        closed = 0;
    }
    if (!pt) {
        geom_status st = note(M, se, "unsupported shell type");
        return st ? st : GEOM_OK;
    }
    uint32_t n;
    const geom__p21_value *l = as_list(M, arg(M, pt, 1), &n);
    if (!l)
        return bad(M, se, "expected a list of faces%s", NULL);
    geom_brep_shell S;
    memset(&S, 0, sizeof S);
    S.closed = closed;
    S.solid = solid;
    S.entity = M->p->ents[se].id;
    S.first_face = (uint32_t)M->b->nfaces;
    uint32_t idx = (uint32_t)M->b->nshells;
    for (uint32_t k = 0; k < n; k++) {
        uint32_t fe;
        if (!as_ref(&l[k], &fe))
            return bad(M, se, "face is not a reference%s", NULL);
        geom_status st = map_face(M, fe, idx, flip);
        if (st)
            return st;
    }
    S.nfaces = (uint32_t)(M->b->nfaces - S.first_face);
    return PUSH(M, A_SHELL, shells, nshells, &S, NULL);
}

static int is_body(const mapper *M, uint32_t e)
{
    return is_type(M, e, "MANIFOLD_SOLID_BREP") || is_type(M, e, "BREP_WITH_VOIDS") ||
           is_type(M, e, "SHELL_BASED_SURFACE_MODEL");
}

static geom_status map_body(mapper *M, uint32_t e)
{
    const geom__p21_part_t *pt;
    geom_status st;
    M->inst++;
    M->b->ninstances++;
    if ((pt = geom__p21_part(M->p, e, "SHELL_BASED_SURFACE_MODEL")) != NULL) {
        uint32_t n;
        const geom__p21_value *l = as_list(M, arg(M, pt, 1), &n);
        if (!l)
            return bad(M, e, "expected a list of shells%s", NULL);
        for (uint32_t k = 0; k < n; k++) {
            uint32_t se;
            if (!as_ref(&l[k], &se))
                return bad(M, e, "shell is not a reference%s", NULL);
            if ((st = map_shell(M, se, GEOM_INVALID_INDEX, 0)) != GEOM_OK)
                return st;
        }
        return GEOM_OK;
    }
    pt = geom__p21_part(M->p, e, "MANIFOLD_SOLID_BREP");
    const geom__p21_part_t *pv = geom__p21_part(M->p, e, "BREP_WITH_VOIDS");
    if (!pt && pv)
        pt = pv;
    geom_brep_solid S;
    memset(&S, 0, sizeof S);
    S.entity = M->p->ents[e].id;
    S.first_shell = (uint32_t)M->b->nshells;
    uint32_t idx = (uint32_t)M->b->nsolids;
    uint32_t oe;
    if (!as_ref(arg(M, pt, 1), &oe))
        return bad(M, e, "outer shell is not a reference%s", NULL);
    if ((st = map_shell(M, oe, idx, 0)) != GEOM_OK)
        return st;
    if (pv) {
        /* complex form: BREP_WITH_VOIDS(voids); simple: (name, outer, voids) */
        uint32_t n;
        const geom__p21_value *l = as_list(M, arg(M, pv, pv == pt ? 2 : 0), &n);
        for (uint32_t k = 0; l && k < n; k++) {
            uint32_t ve;
            if (!as_ref(&l[k], &ve))
                return bad(M, e, "void is not a reference%s", NULL);
            if ((st = map_shell(M, ve, idx, 0)) != GEOM_OK)
                return st;
        }
    }
    S.nshells = (uint32_t)(M->b->nshells - S.first_shell);
    return PUSH(M, A_SOLID, solids, nsolids, &S, NULL);
}

/* ----------------------------------------------------------------- units */

/* Metres (length) or radians (angle) per unit entity u; 0 if unknown. */
static double unit_factor(mapper *M, uint32_t u, int depth)
{
    if (depth > 8)
        return 0;
    const geom__p21_part_t *pt;
    if ((pt = geom__p21_part(M->p, u, "SI_UNIT")) != NULL) {
        const char *pre = as_enum(M, arg(M, pt, 0)), *name = as_enum(M, arg(M, pt, 1));
        if (!name) {
            pre = as_enum(M, arg(M, pt, 1));
            name = as_enum(M, arg(M, pt, 2));
        }
        static const struct {
            const char *n;
            double f;
        } prefixes[] = {{"EXA", 1e18}, {"PETA", 1e15}, {"TERA", 1e12}, {"GIGA", 1e9},
                        {"MEGA", 1e6}, {"KILO", 1e3},  {"HECTO", 1e2}, {"DECA", 1e1},
                        {"DECI", 1e-1}, {"CENTI", 1e-2}, {"MILLI", 1e-3}, {"MICRO", 1e-6},
                        {"NANO", 1e-9}, {"PICO", 1e-12}, {"FEMTO", 1e-15}, {"ATTO", 1e-18}};
        double f = 1;
        if (pre)
            for (size_t k = 0; k < sizeof prefixes / sizeof *prefixes; k++)
                if (!strcmp(pre, prefixes[k].n))
                    f = prefixes[k].f;
        if (name && (!strcmp(name, "METRE") || !strcmp(name, "RADIAN")))
            return f;
        return 0;
    }
    if ((pt = geom__p21_part(M->p, u, "CONVERSION_BASED_UNIT")) != NULL) {
        uint32_t me, ue;
        if (!as_ref(arg(M, pt, 1), &me))
            return 0;
        const geom__p21_part_t *pm = first(M, me);
        double x;
        /* LENGTH_MEASURE_WITH_UNIT(value, unit) or the complex form */
        const geom__p21_part_t *pw = geom__p21_part(M->p, me, "MEASURE_WITH_UNIT");
        if (pw)
            pm = pw;
        if (!as_real(M, arg(M, pm, 0), &x) || !as_ref(arg(M, pm, 1), &ue))
            return 0;
        return x * unit_factor(M, ue, depth + 1);
    }
    return 0;
}

/* Length scale (file unit -> output unit) and angle scale of a
 * representation context; defaults mm and radians. */
static void context_units(mapper *M, uint32_t ctx, double *len, double *ang)
{
    *len = 0.001 / M->out_m;
    *ang = 1;
    const geom__p21_part_t *pt = geom__p21_part(M->p, ctx, "GLOBAL_UNIT_ASSIGNED_CONTEXT");
    if (!pt)
        return;
    uint32_t n;
    const geom__p21_value *l = as_list(M, arg(M, pt, 0), &n);
    for (uint32_t k = 0; l && k < n; k++) {
        uint32_t u;
        if (!as_ref(&l[k], &u))
            continue;
        double f = unit_factor(M, u, 0);
        if (!(f > 0))
            continue;
        if (is_type(M, u, "LENGTH_UNIT"))
            *len = f / M->out_m;
        else if (is_type(M, u, "PLANE_ANGLE_UNIT"))
            *ang = f;
    }
}

/* ------------------------------------------------------------- assembly */

typedef struct rel {
    uint32_t child, parent, xf; /* xf: ITEM_DEFINED_TRANSFORMATION or UINT32_MAX */
} rel;

typedef struct emitted {
    uint32_t body;
    xform X;
    double scale;
} emitted;

typedef struct walker {
    rel *rels;
    size_t nrels;
    emitted *em;
    size_t nem, capem;
    uint32_t path[40];
    int depth;
} walker;

static int is_shape_rep(const mapper *M, uint32_t e)
{
    const geom__p21_entity *E = &M->p->ents[e];
    for (uint32_t k = 0; k < E->nparts; k++) {
        const geom__p21_part_t *q = &M->p->parts[E->first_part + k];
        const char *n = M->p->pool + q->name;
        size_t len = strlen(n);
        if (len >= 20 && !strcmp(n + len - 20, "SHAPE_REPRESENTATION")) {
            uint32_t ni;
            if (arg(M, q, 2) && as_list(M, arg(M, q, 1), &ni))
                return 1;
        }
    }
    return 0;
}

static const geom__p21_part_t *rep_part(const mapper *M, uint32_t e)
{
    const geom__p21_entity *E = &M->p->ents[e];
    for (uint32_t k = 0; k < E->nparts; k++) {
        const geom__p21_part_t *q = &M->p->parts[E->first_part + k];
        uint32_t ni;
        if (arg(M, q, 2) && as_list(M, arg(M, q, 1), &ni))
            return q;
    }
    return first(M, e);
}

static void rep_units(mapper *M, uint32_t rep, double *len, double *ang)
{
    uint32_t ctx;
    if (as_ref(arg(M, rep_part(M, rep), 2), &ctx))
        context_units(M, ctx, len, ang);
    else
        context_units(M, UINT32_MAX, len, ang);
}

/* Placement entity -> transform (rotation, translation scaled by len). */
static geom_status placement_xform(mapper *M, uint32_t pe, double len, xform *X)
{
    geom__p21_value v;
    memset(&v, 0, sizeof v);
    v.kind = GEOM__P21_REF;
    v.u.ref = pe;
    double o[3], x[3], y[3], z[3];
    geom_status st = placement(M, &v, pe, o, x, y, z);
    if (st)
        return st;
    for (int k = 0; k < 3; k++) {
        X->R[k] = x[k];
        X->R[3 + k] = y[k];
        X->R[6 + k] = z[k];
        X->t[k] = o[k] * len;
    }
    X->s = 1;
    return GEOM_OK;
}

/* A DIRECTION argument normalised, or absent ($): returns 0 when absent. */
static geom_status opt_dir(mapper *M, const geom__p21_value *v, uint32_t owner, double d[3], int *have)
{
    *have = 0;
    if (!v || v->kind != GEOM__P21_REF)
        return GEOM_OK;
    geom_status st = ref_coords(M, v, owner, "DIRECTION", d, NULL);
    if (st)
        return st;
    if (norm3(d) == 0)
        return bad(M, owner, "zero axis%s", NULL);
    *have = 1;
    return GEOM_OK;
}

static uint32_t nargs(const mapper *M, const geom__p21_part_t *pt)
{
    return pt ? M->p->vals[pt->args].n : 0;
}

/* CARTESIAN_TRANSFORMATION_OPERATOR(_3D) -> transform, by ISO 10303-42's
 * base_axis: z = axis3 (default +Z), x = axis1 made orthogonal to z
 * (default +X, or +Y when z is +X), y = axis2 made orthogonal to z and x
 * (default +Y; z cross x where that default degenerates):
 * p -> local_origin + scale (x px + y py + z pz). y is not forced to
 * z cross x, so the operator may mirror. Its attributes are the
 * last five of the _3D part (axis1, axis2, local_origin, scale, axis3;
 * before them one or two labels), or, in the complex-instance form, the
 * four of CARTESIAN_TRANSFORMATION_OPERATOR and axis3 in the _3D part. */
static geom_status operator_xform(mapper *M, uint32_t e, double len, xform *X)
{
    const geom__p21_part_t *p3 = geom__p21_part(M->p, e, "CARTESIAN_TRANSFORMATION_OPERATOR_3D");
    const geom__p21_part_t *p2 = geom__p21_part(M->p, e, "CARTESIAN_TRANSFORMATION_OPERATOR");
    const geom__p21_value *a1, *a2, *org, *sc, *a3 = NULL;
    uint32_t n3 = nargs(M, p3), n2 = nargs(M, p2);
    if (p3 && n3 >= 5) {
        a1 = arg(M, p3, n3 - 5), a2 = arg(M, p3, n3 - 4), org = arg(M, p3, n3 - 3);
        sc = arg(M, p3, n3 - 2), a3 = arg(M, p3, n3 - 1);
    } else if (p2 && n2 >= 4) {
        a1 = arg(M, p2, n2 - 4), a2 = arg(M, p2, n2 - 3), org = arg(M, p2, n2 - 2);
        sc = arg(M, p2, n2 - 1);
        if (p3 && n3 >= 1)
            a3 = arg(M, p3, n3 - 1);
    } else {
        return bad(M, e, "expected axis1, axis2, local_origin, scale and axis3%s", NULL);
    }
    double o[3], x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1}, s = 1;
    int h1, h2, h3;
    geom_status st = ref_coords(M, org, e, "CARTESIAN_POINT", o, NULL);
    if (!st)
        st = opt_dir(M, a3, e, z, &h3);
    if (!st)
        st = opt_dir(M, a1, e, x, &h1);
    if (!st)
        st = opt_dir(M, a2, e, y, &h2);
    if (st)
        return st;
    if (sc && sc->kind != GEOM__P21_NULL && (!as_real(M, sc, &s) || !(s > 0) || !isfinite(s)))
        return bad(M, e, "the scale must be a positive number%s", NULL);
    if (!h1 && fabs(z[0]) > 1 - 1e-12 && fabs(z[1]) + fabs(z[2]) < 1e-12)
        x[0] = 0, x[1] = 1, x[2] = 0;
    double d = dot3(x, z);
    for (int k = 0; k < 3; k++)
        x[k] -= d * z[k];
    if (norm3(x) == 0)
        return bad(M, e, "axis1 parallel to axis3%s", NULL);
    d = dot3(y, z);
    for (int k = 0; k < 3; k++)
        y[k] -= d * z[k];
    d = dot3(y, x);
    for (int k = 0; k < 3; k++)
        y[k] -= d * x[k];
    if (norm3(y) == 0) {
        if (h2)
            return bad(M, e, "axis2 in the plane of axis1 and axis3%s", NULL);
        /* the default +Y along axis1 (axis3 = +X): ISO's rule degenerates */
        y[0] = z[1] * x[2] - z[2] * x[1];
        y[1] = z[2] * x[0] - z[0] * x[2];
        y[2] = z[0] * x[1] - z[1] * x[0];
    }
    for (int k = 0; k < 3; k++) {
        X->R[k] = x[k];
        X->R[3 + k] = y[k];
        X->R[6 + k] = z[k];
        X->t[k] = o[k] * len;
    }
    X->s = s;
    return GEOM_OK;
}

/* A placement item (AXIS2_PLACEMENT_3D, or a cartesian transformation
 * operator) -> transform; 0 with *X untouched for another type. */
static int item_xform(mapper *M, uint32_t e, double len, xform *X, geom_status *st)
{
    if (is_type(M, e, "AXIS2_PLACEMENT_3D"))
        *st = placement_xform(M, e, len, X);
    else if (is_type(M, e, "CARTESIAN_TRANSFORMATION_OPERATOR_3D") ||
             is_type(M, e, "CARTESIAN_TRANSFORMATION_OPERATOR"))
        *st = operator_xform(M, e, len, X);
    else
        return 0;
    return 1;
}

static double xf_det(const xform *A)
{
    const double *R = A->R;
    return R[0] * (R[4] * R[8] - R[5] * R[7]) - R[3] * (R[1] * R[8] - R[2] * R[7]) +
           R[6] * (R[1] * R[5] - R[2] * R[4]);
}

/* A * B */
static xform xf_mul(const xform *A, const xform *B)
{
    xform C;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            C.R[3 * c + r] = A->R[r] * B->R[3 * c] + A->R[3 + r] * B->R[3 * c + 1] +
                             A->R[6 + r] * B->R[3 * c + 2];
    for (int r = 0; r < 3; r++)
        C.t[r] = A->s * (A->R[r] * B->t[0] + A->R[3 + r] * B->t[1] + A->R[6 + r] * B->t[2]) + A->t[r];
    C.s = A->s * B->s;
    return C;
}

static xform xf_inv(const xform *A)
{
    xform C;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            C.R[3 * c + r] = A->R[3 * r + c];
    for (int r = 0; r < 3; r++)
        C.t[r] = -(C.R[r] * A->t[0] + C.R[3 + r] * A->t[1] + C.R[6 + r] * A->t[2]) / A->s;
    C.s = 1 / A->s;
    return C;
}

static int xf_equal(const xform *A, const xform *B)
{
    for (int k = 0; k < 9; k++)
        if (fabs(A->R[k] - B->R[k]) > 1e-9)
            return 0;
    for (int k = 0; k < 3; k++)
        if (fabs(A->t[k] - B->t[k]) > 1e-9 * (1 + fabs(A->t[k])))
            return 0;
    return fabs(A->s - B->s) <= 1e-12 * A->s;
}

static geom_status emit(mapper *M, walker *W, uint32_t body, const xform *X, double scale)
{
    for (size_t k = 0; k < W->nem; k++)
        if (W->em[k].body == body && xf_equal(&W->em[k].X, X))
            return GEOM_OK;
    geom_status st = geom__grow(M->a, (void **)&W->em, &W->capem, W->nem + 1, sizeof *W->em);
    if (st != GEOM_OK)
        return st;
    W->em[W->nem].body = body;
    W->em[W->nem].X = *X;
    W->em[W->nem].scale = scale;
    W->nem++;
    return GEOM_OK;
}

static geom_status visit(mapper *M, walker *W, uint32_t rep, const xform *X)
{
    if (W->depth >= 40)
        return bad(M, rep, "assembly nested too deeply (or cyclic)%s", NULL);
    for (int k = 0; k < W->depth; k++)
        if (W->path[k] == rep)
            return GEOM_OK;
    W->path[W->depth++] = rep;
    double len, ang;
    rep_units(M, rep, &len, &ang);
    geom_status st = GEOM_OK;
    uint32_t n;
    const geom__p21_value *items = as_list(M, arg(M, rep_part(M, rep), 1), &n);
    for (uint32_t k = 0; items && k < n && !st; k++) {
        uint32_t it;
        if (!as_ref(&items[k], &it))
            continue;
        if (is_body(M, it)) {
            st = emit(M, W, it, X, len);
        } else if (is_type(M, it, "MAPPED_ITEM")) {
            const geom__p21_part_t *pm = geom__p21_part(M->p, it, "MAPPED_ITEM");
            uint32_t src, tgt, org, child;
            const geom__p21_part_t *ps;
            if (!as_ref(arg(M, pm, 1), &src) || !as_ref(arg(M, pm, 2), &tgt) ||
                !(ps = geom__p21_part(M->p, src, "REPRESENTATION_MAP")) ||
                !as_ref(arg(M, ps, 0), &org) || !as_ref(arg(M, ps, 1), &child))
                st = bad(M, it, "expected a REPRESENTATION_MAP and a target%s", NULL);
            else {
                double clen, cang;
                rep_units(M, child, &clen, &cang);
                xform A, B;
                geom_status s1 = GEOM_OK, s2 = GEOM_OK;
                if (!item_xform(M, tgt, len, &A, &s1) || !item_xform(M, org, clen, &B, &s2))
                    st = note(M, it,
                              "mapping origin or target is not an AXIS2_PLACEMENT_3D or a "
                              "transformation operator: not placed");
                else if ((st = s1 ? s1 : s2) == GEOM_OK) {
                    xform Bi = xf_inv(&B), T = xf_mul(&A, &Bi), Y = xf_mul(X, &T);
                    st = visit(M, W, child, &Y);
                }
            }
        }
    }
    for (size_t k = 0; k < W->nrels && !st; k++) {
        const rel *r = &W->rels[k];
        if (r->xf == UINT32_MAX) {
            if (r->parent == rep)
                st = visit(M, W, r->child, X);
            else if (r->child == rep)
                st = visit(M, W, r->parent, X);
            continue;
        }
        if (r->parent != rep)
            continue;
        const geom__p21_part_t *pi = geom__p21_part(M->p, r->xf, "ITEM_DEFINED_TRANSFORMATION");
        uint32_t i1, i2;
        if (!pi) {
            st = note(M, r->xf, "unsupported assembly transformation: not placed");
            continue;
        }
        if (!as_ref(arg(M, pi, 2), &i1) || !as_ref(arg(M, pi, 3), &i2)) {
            st = bad(M, r->xf, "expected two placements%s", NULL);
            break;
        }
        double clen, cang;
        rep_units(M, r->child, &clen, &cang);
        xform A, B;
        geom_status s1 = GEOM_OK, s2 = GEOM_OK;
        if (!item_xform(M, i2, len, &A, &s1) || !item_xform(M, i1, clen, &B, &s2)) {
            st = note(M, r->xf, "transformation items are not placements: not placed");
            continue;
        }
        if ((st = s1 ? s1 : s2) != GEOM_OK)
            break;
        xform Bi = xf_inv(&B), T = xf_mul(&A, &Bi), Y = xf_mul(X, &T);
        st = visit(M, W, r->child, &Y);
    }
    W->depth--;
    return st;
}

static geom_status assemble(mapper *M)
{
    geom__p21 *p = M->p;
    walker W;
    memset(&W, 0, sizeof W);
    geom_status st = GEOM_OK;
    size_t nrel = 0;
    for (size_t e = p->nheader; e < p->nents; e++)
        if (geom__p21_part(p, (uint32_t)e, "REPRESENTATION_RELATIONSHIP") ||
            geom__p21_part(p, (uint32_t)e, "SHAPE_REPRESENTATION_RELATIONSHIP"))
            nrel++;
    W.rels = geom__alloc(M->a, (nrel ? nrel : 1) * sizeof *W.rels);
    uint8_t *child = geom__alloc(M->a, p->nents ? p->nents : 1);
    uint8_t *parent = geom__alloc(M->a, p->nents ? p->nents : 1);
    if (!W.rels || !child || !parent) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    memset(child, 0, p->nents);
    memset(parent, 0, p->nents);
    for (size_t e = p->nheader; e < p->nents; e++) {
        const geom__p21_part_t *pr = geom__p21_part(p, (uint32_t)e, "REPRESENTATION_RELATIONSHIP");
        if (!pr)
            pr = geom__p21_part(p, (uint32_t)e, "SHAPE_REPRESENTATION_RELATIONSHIP");
        if (pr) {
            rel r;
            if (!as_ref(arg(M, pr, 2), &r.child) || !as_ref(arg(M, pr, 3), &r.parent))
                continue;
            r.xf = UINT32_MAX;
            const geom__p21_part_t *pw =
                geom__p21_part(p, (uint32_t)e, "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION");
            uint32_t xf;
            if (pw && as_ref(arg(M, pw, 0), &xf)) {
                r.xf = xf;
                child[r.child] = 1;
                parent[r.parent] = 1;
            }
            W.rels[W.nrels++] = r;
        }
        if (is_shape_rep(M, (uint32_t)e)) {
            uint32_t n;
            const geom__p21_value *items = as_list(M, arg(M, rep_part(M, (uint32_t)e), 1), &n);
            for (uint32_t k = 0; items && k < n; k++) {
                uint32_t it, src, c;
                const geom__p21_part_t *pm, *ps;
                if (as_ref(&items[k], &it) && (pm = geom__p21_part(p, it, "MAPPED_ITEM")) &&
                    as_ref(arg(M, pm, 1), &src) && (ps = geom__p21_part(p, src, "REPRESENTATION_MAP")) &&
                    as_ref(arg(M, ps, 1), &c)) {
                    child[c] = 1;
                    parent[e] = 1;
                }
            }
        }
    }
    xform I;
    memset(&I, 0, sizeof I);
    I.R[0] = I.R[4] = I.R[8] = 1;
    I.s = 1;
    /* phase 1: from the tops of assemblies; phase 2: other representations,
     * for bodies not placed yet */
    for (int phase = 0; phase < 2 && !st; phase++) {
        size_t before = W.nem;
        for (size_t e = p->nheader; e < p->nents && !st; e++) {
            if (!is_shape_rep(M, (uint32_t)e) || child[e])
                continue;
            if (phase == 0 && !parent[e])
                continue;
            if (phase == 1 && parent[e])
                continue;
            if (phase == 0) {
                st = visit(M, &W, (uint32_t)e, &I);
            } else {
                walker W2 = W;
                W2.em = NULL;
                W2.nem = W2.capem = 0;
                W2.depth = 0;
                st = visit(M, &W2, (uint32_t)e, &I);
                for (size_t k = 0; k < W2.nem && !st; k++) {
                    int seen = 0;
                    for (size_t j = 0; j < before; j++)
                        seen |= W.em[j].body == W2.em[k].body;
                    if (!seen)
                        st = emit(M, &W, W2.em[k].body, &W2.em[k].X, W2.em[k].scale);
                }
                geom__free(M->a, W2.em, W2.capem * sizeof *W2.em);
            }
        }
    }
    /* bodies in no representation at all: at the origin, in the first
     * context's units */
    for (size_t e = p->nheader; e < p->nents && !st; e++) {
        if (!is_body(M, (uint32_t)e))
            continue;
        int seen = 0;
        for (size_t j = 0; j < W.nem; j++)
            seen |= W.em[j].body == e;
        if (!seen) {
            double len = 0.001 / M->out_m, ang = 1;
            for (size_t c = p->nheader; c < p->nents; c++)
                if (geom__p21_part(p, (uint32_t)c, "GLOBAL_UNIT_ASSIGNED_CONTEXT")) {
                    context_units(M, (uint32_t)c, &len, &ang);
                    break;
                }
            st = emit(M, &W, (uint32_t)e, &I, len);
        }
    }
    for (size_t k = 0; k < W.nem && !st; k++) {
        M->X = W.em[k].X;
        M->scale = W.em[k].scale * W.em[k].X.s;
        M->mirror = xf_det(&W.em[k].X) < 0;
        st = map_body(M, W.em[k].body);
    }
done:
    geom__free(M->a, W.rels, (nrel ? nrel : 1) * sizeof *W.rels);
    geom__free(M->a, W.em, W.capem * sizeof *W.em);
    geom__free(M->a, child, p->nents ? p->nents : 1);
    geom__free(M->a, parent, p->nents ? p->nents : 1);
    return st;
}

/* --------------------------------------------------------------- public */

typedef struct brep_internal {
    const geom_allocator *alloc;
    size_t cap[9];
    size_t capissues;
} brep_internal;

GEOM_API void geom_step_destroy(geom_brep *b)
{
    if (!b)
        return;
    brep_internal *in = b->internal_;
    const geom_allocator *a = in ? in->alloc : NULL;
    for (size_t k = 0; k < b->ncurves; k++)
        free_curve(a, &b->curves[k]);
    for (size_t k = 0; k < b->nsurfaces; k++)
        free_surface(a, &b->surfaces[k]);
    size_t *cap = in ? in->cap : NULL;
    if (cap) {
        geom__free(a, b->solids, cap[A_SOLID] * sizeof *b->solids);
        geom__free(a, b->shells, cap[A_SHELL] * sizeof *b->shells);
        geom__free(a, b->faces, cap[A_FACE] * sizeof *b->faces);
        geom__free(a, b->loops, cap[A_LOOP] * sizeof *b->loops);
        geom__free(a, b->coedges, cap[A_COEDGE] * sizeof *b->coedges);
        geom__free(a, b->edges, cap[A_EDGE] * sizeof *b->edges);
        geom__free(a, b->vertices, cap[A_VERTEX] * sizeof *b->vertices);
        geom__free(a, b->curves, cap[A_CURVE] * sizeof *b->curves);
        geom__free(a, b->surfaces, cap[A_SURFACE] * sizeof *b->surfaces);
        geom__free(a, b->issues, in->capissues * sizeof *b->issues);
    }
    geom__free(a, in, sizeof *in);
    geom__free(a, b, sizeof *b);
}

GEOM_API geom_status geom_step_read_memory(const void *data, size_t size, const char *source_name,
                                           const geom_step_read_options *options, geom_brep **out,
                                           geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (!data && size))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, source_name ? source_name : "", 0, 0,
                             "NULL argument");
    geom_step_read_options o;
    memset(&o, 0, sizeof o);
    if (options)
        o = *options;
    if (!(o.unit_metres > 0) || !isfinite(o.unit_metres))
        o.unit_metres = 0.001;
    geom__p21 p;
    geom_status st = geom__p21_parse(&p, data ? data : "", size, source_name, o.max_bytes,
                                     o.max_depth, o.alloc, diag);
    if (st)
        return st;
    geom_brep *b = geom__alloc(o.alloc, sizeof *b);
    brep_internal *in = geom__alloc(o.alloc, sizeof *in);
    size_t nb = p.nents ? p.nents : 1;
    uint32_t *memo = geom__alloc(o.alloc, nb * sizeof *memo);
    uint32_t *stamp = geom__alloc(o.alloc, nb * sizeof *stamp);
    if (!b || !in || !memo || !stamp) {
        geom__free(o.alloc, b, sizeof *b);
        geom__free(o.alloc, in, sizeof *in);
        geom__free(o.alloc, memo, nb * sizeof *memo);
        geom__free(o.alloc, stamp, nb * sizeof *stamp);
        geom__p21_free(&p);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, p.source, 0, 0, "out of memory");
    }
    memset(b, 0, sizeof *b);
    memset(in, 0, sizeof *in);
    memset(stamp, 0, nb * sizeof *stamp);
    in->alloc = o.alloc;
    b->internal_ = in;
    b->unit_metres = o.unit_metres;
    mapper M;
    memset(&M, 0, sizeof M);
    M.p = &p;
    M.b = b;
    M.a = o.alloc;
    M.diag = diag;
    M.strict = o.strict;
    M.memo = memo;
    M.stamp = stamp;
    M.out_m = o.unit_metres;
    M.angle = 1;
    /* the plane angle unit of the first context (used for cone angles) */
    for (size_t c = p.nheader; c < p.nents; c++)
        if (geom__p21_part(&p, (uint32_t)c, "GLOBAL_UNIT_ASSIGNED_CONTEXT")) {
            double len;
            context_units(&M, (uint32_t)c, &len, &M.angle);
            break;
        }
    st = assemble(&M);
    memcpy(in->cap, M.cap, sizeof M.cap);
    in->capissues = M.capissues;
    if (st == GEOM_ERR_NOMEM && diag && diag->status != GEOM_ERR_NOMEM)
        geom__diag_set(diag, st, p.source, 0, 0, "out of memory");
    if (st == GEOM_ERR_DOMAIN)
        st = geom__diag_set(diag, GEOM_ERR_PARSE, p.source, 0, 0, "unsupported geometry");
    geom__free(o.alloc, memo, nb * sizeof *memo);
    geom__free(o.alloc, stamp, nb * sizeof *stamp);
    geom__p21_free(&p);
    if (st) {
        geom_step_destroy(b);
        return st;
    }
    *out = b;
    return GEOM_OK;
}

GEOM_API geom_status geom_step_read(const char *path, const geom_step_read_options *options,
                                    geom_brep **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "NULL argument");
    geom_file f;
    geom_status st = geom_file_map(path, options ? options->alloc : NULL, &f, diag);
    if (!st) /* the parser checks max_bytes */
        st = geom_step_read_memory(f.data, f.size, path, options, out, diag);
    geom_file_unmap(&f);
    return st;
}
