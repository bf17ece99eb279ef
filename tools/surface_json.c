/* Curves and surfaces from JSON (see surface_json.h). */
#include "surface_json.h"

#include <cjson/cJSON.h>

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SJ_MAX_COUNT ((size_t)1 << 22)

/* -------------------------------------------------------------- messages */

typedef struct sj_ctx {
    const char *source;
    geom_diag *diag;
    char where[160]; /* "surfaces[2] (\"torus\")" */
} sj_ctx;

#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 5, 6)))
#endif
static geom_status sj_fail(const sj_ctx *x, geom_status st, size_t line, size_t col,
                           const char *fmt, ...)
{
    if (!x->diag)
        return st;
    geom_diag *d = x->diag;
    geom_diag_clear(d);
    d->status = st;
    snprintf(d->source, sizeof d->source, "%s", x->source ? x->source : "");
    d->line = line;
    d->column = col;
    char msg[GEOM_DIAG_MESSAGE_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    char full[sizeof x->where + sizeof msg + 4];
    if (x->where[0])
        snprintf(full, sizeof full, "%s: %s", x->where, msg);
    else
        snprintf(full, sizeof full, "%s", msg);
    size_t l = strlen(full);
    if (l >= sizeof d->message)
        l = sizeof d->message - 1;
    memcpy(d->message, full, l);
    d->message[l] = '\0';
    return st;
}

/* ---------------------------------------------------------- JSON access */

static const cJSON *key(const cJSON *obj, const char *name)
{
    return cJSON_GetObjectItemCaseSensitive(obj, name);
}

static geom_status get_number(const sj_ctx *x, const cJSON *obj, const char *name, int required,
                              double def, double *out)
{
    const cJSON *v = key(obj, name);
    if (!v) {
        if (required)
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "missing key \"%s\"", name);
        *out = def;
        return GEOM_OK;
    }
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": expected a finite number", name);
    *out = v->valuedouble;
    return GEOM_OK;
}

static geom_status get_int(const sj_ctx *x, const cJSON *obj, const char *name, int required,
                           int def, int lo, int hi, int *out)
{
    double d;
    geom_status st = get_number(x, obj, name, required, (double)def, &d);
    if (st != GEOM_OK)
        return st;
    if (d != floor(d) || d < lo || d > hi)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": expected an integer in [%d, %d], not %.17g",
                       name, lo, hi, d);
    *out = (int)d;
    return GEOM_OK;
}

static geom_status get_bool(const sj_ctx *x, const cJSON *obj, const char *name, int *out)
{
    const cJSON *v = key(obj, name);
    *out = 0;
    if (!v)
        return GEOM_OK;
    if (!cJSON_IsBool(v))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": expected true or false", name);
    *out = cJSON_IsTrue(v);
    return GEOM_OK;
}

/* The list under key `name` (exactly `want` items unless want == 0) as *v
 * with its length *n, and *buf malloc'd for its items of `item` doubles
 * each. The messages call it "a list of <kind>" and count its <unit>. */
static geom_status get_list(const sj_ctx *x, const cJSON *obj, const char *name, size_t want,
                            const char *kind, const char *unit, size_t item, const cJSON **v,
                            size_t *n, double **buf)
{
    *buf = NULL;
    *v = key(obj, name);
    if (!*v)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "missing key \"%s\"", name);
    if (!cJSON_IsArray(*v))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": expected a list of %s", name, kind);
    *n = (size_t)cJSON_GetArraySize(*v);
    if (*n > SJ_MAX_COUNT)
        return sj_fail(x, GEOM_ERR_LIMIT, 0, 0, "\"%s\": more than %zu %s", name, SJ_MAX_COUNT,
                       unit);
    if (want && *n != want)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": %zu %s, %zu expected", name, *n, unit,
                       want);
    *buf = malloc((*n ? *n : 1) * item * sizeof(double));
    if (!*buf)
        return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
    return GEOM_OK;
}

/* A list of numbers (exactly `want` unless want == 0): *out malloc'd. */
static geom_status get_numbers(const sj_ctx *x, const cJSON *obj, const char *name, size_t want,
                               double **out, size_t *count)
{
    *out = NULL;
    const cJSON *v;
    size_t n;
    double *a;
    geom_status st = get_list(x, obj, name, want, "numbers", "values", 1, &v, &n, &a);
    if (st != GEOM_OK)
        return st;
    size_t i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, v)
    {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble)) {
            free(a);
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\"[%zu]: expected a finite number", name,
                           i);
        }
        a[i++] = e->valuedouble;
    }
    *out = a;
    *count = n;
    return GEOM_OK;
}

/* One point: a list of dim numbers (dim 0: 2 or 3, then set). */
static geom_status get_point(const sj_ctx *x, const cJSON *p, const char *what, size_t *dim,
                             double *out)
{
    if (!cJSON_IsArray(p))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "%s: expected a point (a list of numbers)", what);
    size_t n = (size_t)cJSON_GetArraySize(p);
    if (*dim == 0) {
        if (n != 2 && n != 3)
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "%s: a point has 2 or 3 coordinates, not %zu",
                           what, n);
        *dim = n;
    } else if (n != *dim) {
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "%s: %zu coordinates, %zu expected", what, n,
                       *dim);
    }
    size_t i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, p)
    {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "%s[%zu]: expected a finite number", what, i);
        out[i++] = e->valuedouble;
    }
    return GEOM_OK;
}

/* A list of points; *dim 0 = 2 or 3 from the first one. */
static geom_status get_points(const sj_ctx *x, const cJSON *obj, const char *name, size_t want,
                              size_t *dim, double **out, size_t *count)
{
    *out = NULL;
    const cJSON *v;
    size_t n;
    double *a;
    geom_status st = get_list(x, obj, name, want, "points", "points", 3, &v, &n, &a);
    if (st != GEOM_OK)
        return st;
    size_t i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, v)
    {
        char what[64];
        snprintf(what, sizeof what, "\"%s\"[%zu]", name, i);
        double p[3];
        st = get_point(x, e, what, dim, p);
        if (st != GEOM_OK) {
            free(a);
            return st;
        }
        memcpy(a + i * *dim, p, *dim * sizeof(double));
        ++i;
    }
    *out = a;
    *count = n;
    return GEOM_OK;
}

/* ------------------------------------------------------------------ curves */

static void curve_free(sj_curve *c)
{
    free(c->knots);
    free(c->points);
    free(c->weights);
    c->knots = c->points = c->weights = NULL;
}

static void set_tcb(geom_kb_params *t, int which, double v)
{
    if (which == 0)
        t->tension = v;
    else if (which == 1)
        t->continuity = v;
    else
        t->bias = v;
}

/* tension/continuity/bias: a number, or one per point */
static geom_status get_tcb(const sj_ctx *x, const cJSON *obj, const char *name, size_t n,
                           geom_kb_params *tcb, int which)
{
    const cJSON *v = key(obj, name);
    if (!v)
        return GEOM_OK;
    double *vals = NULL;
    size_t cnt = 0;
    if (cJSON_IsNumber(v)) {
        double d;
        geom_status st = get_number(x, obj, name, 1, 0.0, &d);
        if (st != GEOM_OK)
            return st;
        for (size_t i = 0; i < n; ++i)
            set_tcb(&tcb[i], which, d);
        return GEOM_OK;
    }
    geom_status st = get_numbers(x, obj, name, n, &vals, &cnt);
    if (st != GEOM_OK)
        return st;
    for (size_t i = 0; i < n; ++i)
        set_tcb(&tcb[i], which, vals[i]);
    free(vals);
    return GEOM_OK;
}

/* Piecewise cubic Bezier (3*nseg+1 points) as a clamped B-spline. */
static geom_status from_bezier_segments(const sj_ctx *x, sj_curve *c, size_t dim, size_t nseg,
                                        double *bez, const double *params)
{
    c->knots = malloc((3 * nseg + 5) * sizeof(double));
    if (!c->knots) {
        free(bez);
        return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
    }
    geom_status st = geom_curve_piecewise_bezier_knots(3, nseg, params, c->knots);
    if (st != GEOM_OK) {
        free(bez);
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "could not build the knot vector");
    }
    c->points = bez;
    c->c = (geom_nurbs_curve){3, 3 * nseg + 1, dim, c->knots, c->points, NULL};
    return GEOM_OK;
}

static geom_status read_curve(sj_ctx *x, const cJSON *e, sj_curve *c)
{
    memset(c, 0, sizeof *c);
    const cJSON *t = key(e, "type");
    if (!t || !cJSON_IsString(t))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "missing key \"type\" (a string)");
    snprintf(c->type, sizeof c->type, "%s", t->valuestring);
    const char *type = t->valuestring;
    size_t dim = 0, n = 0;
    geom_status st = get_points(x, e, "points", 0, &dim, &c->points, &n);
    if (st != GEOM_OK)
        return st;
    if (n < 2)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"points\": at least 2 points needed, not %zu", n);
    if (!strcmp(type, "bezier") || !strcmp(type, "bspline") || !strcmp(type, "nurbs")) {
        int p;
        size_t nk = 0;
        if (!strcmp(type, "bezier")) {
            st = get_int(x, e, "degree", 0, (int)n - 1, 1, 1 << 20, &p);
            if (st != GEOM_OK)
                return st;
            if ((size_t)p != n - 1)
                return sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                               "\"degree\": %d, but %zu points make a Bezier curve of degree %zu",
                               p, n, n - 1);
            nk = 2 * n;
            c->knots = malloc(nk * sizeof(double));
            if (!c->knots)
                return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
            for (size_t i = 0; i < n; ++i) {
                c->knots[i] = 0.0;
                c->knots[n + i] = 1.0;
            }
        } else {
            st = get_int(x, e, "degree", 1, 0, 1, 1 << 20, &p);
            if (st != GEOM_OK)
                return st;
            st = get_numbers(x, e, "knots", 0, &c->knots, &nk);
            if (st != GEOM_OK)
                return st;
            if (nk != n + (size_t)p + 1)
                return sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                               "\"knots\": %zu knots, %zu expected (points + degree + 1)", nk,
                               n + (size_t)p + 1);
        }
        if (key(e, "weights")) {
            size_t nw;
            st = get_numbers(x, e, "weights", n, &c->weights, &nw);
            if (st != GEOM_OK)
                return st;
        } else if (!strcmp(type, "nurbs")) {
            c->weights = malloc(n * sizeof(double));
            if (!c->weights)
                return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
            for (size_t i = 0; i < n; ++i)
                c->weights[i] = 1.0;
        }
        c->c = (geom_nurbs_curve){p, n, dim, c->knots, c->points, c->weights};
        geom_diag d;
        geom_diag_clear(&d);
        if (geom_curve_nurbs_validate(&c->c, nk, &d) != GEOM_OK) {
            const char *k = strstr(d.message, "weight") ? "weights"
                            : strstr(d.message, "knot") ? "knots"
                                                         : "points";
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": %s", k, d.message);
        }
        return GEOM_OK;
    }
    if (!strcmp(type, "hermite")) {
        size_t nt = 0, tdim = dim;
        double *tang = NULL, *params = NULL;
        st = get_points(x, e, "tangents", n, &tdim, &tang, &nt);
        if (st != GEOM_OK)
            return st;
        if (key(e, "params")) {
            size_t np;
            st = get_numbers(x, e, "params", n, &params, &np);
            if (st != GEOM_OK) {
                free(tang);
                return st;
            }
        }
        double *bez = malloc((3 * (n - 1) + 1) * dim * sizeof(double));
        if (!bez) {
            free(tang);
            free(params);
            return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
        }
        st = geom_curve_hermite_spline_to_bezier(dim, n, c->points, tang, params, bez);
        free(tang);
        if (st != GEOM_OK) {
            free(params);
            free(bez);
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                           "\"params\": must be strictly increasing (%s)", geom_status_str(st));
        }
        free(c->points);
        c->points = NULL;
        st = from_bezier_segments(x, c, dim, n - 1, bez, params);
        free(params);
        return st;
    }
    if (!strcmp(type, "catmull_rom") || !strcmp(type, "kochanek_bartels")) {
        int closed;
        st = get_bool(x, e, "closed", &closed);
        if (st != GEOM_OK)
            return st;
        geom_curve_end ends = closed ? GEOM_CURVE_END_CLOSED : GEOM_CURVE_END_EXTRAPOLATE;
        size_t nseg;
        if (geom_curve_catmull_rom_segments(n, ends, &nseg) != GEOM_OK)
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"points\": %zu points are too few%s", n,
                           closed ? " for a closed curve (3 needed)" : "");
        double *bez = malloc((3 * nseg + 1) * dim * sizeof(double));
        double *params = malloc((nseg + 1) * sizeof(double));
        if (!bez || !params) {
            free(bez);
            free(params);
            return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
        }
        geom_diag d;
        geom_diag_clear(&d);
        if (!strcmp(type, "catmull_rom")) {
            double alpha;
            st = get_number(x, e, "alpha", 0, 0.5, &alpha);
            if (st == GEOM_OK && !(alpha >= 0.0 && alpha <= 1.0))
                st = sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"alpha\": %.17g is not in [0, 1]", alpha);
            if (st == GEOM_OK &&
                geom_curve_catmull_rom_to_bezier(dim, n, c->points, alpha, ends, bez, params,
                                                 &d) != GEOM_OK)
                st = sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"points\": %s", d.message);
        } else {
            geom_kb_params *tcb = calloc(n, sizeof *tcb);
            if (!tcb)
                st = sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
            if (st == GEOM_OK)
                st = get_tcb(x, e, "tension", n, tcb, 0);
            if (st == GEOM_OK)
                st = get_tcb(x, e, "continuity", n, tcb, 1);
            if (st == GEOM_OK)
                st = get_tcb(x, e, "bias", n, tcb, 2);
            if (st == GEOM_OK &&
                geom_curve_kochanek_bartels_to_bezier(dim, n, c->points, tcb, n, ends, bez,
                                                      &d) != GEOM_OK)
                st = sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"points\": %s", d.message);
            free(tcb);
            free(params);
            params = NULL; /* uniform: segment i covers [i, i+1] */
        }
        if (st != GEOM_OK) {
            free(bez);
            free(params);
            return st;
        }
        free(c->points);
        c->points = NULL;
        st = from_bezier_segments(x, c, dim, nseg, bez, params);
        free(params);
        return st;
    }
    return sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                   "\"type\": unknown curve type \"%s\" (bezier, bspline, nurbs, hermite, "
                   "catmull_rom, kochanek_bartels)",
                   type);
}

/* ---------------------------------------------------------------- surfaces */

/* points[i][j] (or weights[i][j] when ncomp == 1) */
static geom_status get_grid(const sj_ctx *x, const cJSON *obj, const char *name, int weights,
                            size_t want_nu, size_t want_nv, double **out, size_t *nu, size_t *nv)
{
    *out = NULL;
    const cJSON *v = key(obj, name);
    if (!v)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "missing key \"%s\"", name);
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) < 1)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": expected %s[i][j], a non-empty list of rows",
                       name, name);
    size_t rows = (size_t)cJSON_GetArraySize(v);
    const cJSON *r0 = cJSON_GetArrayItem(v, 0);
    if (!cJSON_IsArray(r0) || cJSON_GetArraySize(r0) < 1)
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\"[0]: expected a non-empty list", name);
    size_t cols = (size_t)cJSON_GetArraySize(r0);
    if (rows > 65536 || cols > 65536 || rows * cols > SJ_MAX_COUNT)
        return sj_fail(x, GEOM_ERR_LIMIT, 0, 0, "\"%s\": %zu x %zu is too large", name, rows, cols);
    if ((want_nu && rows != want_nu) || (want_nv && cols != want_nv))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": %zu x %zu, %zu x %zu expected (as points)",
                       name, rows, cols, want_nu, want_nv);
    size_t nc = weights ? 1 : 3;
    double *a = malloc(rows * cols * nc * sizeof(double));
    if (!a)
        return sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
    size_t i = 0;
    const cJSON *row;
    cJSON_ArrayForEach(row, v)
    {
        if (!cJSON_IsArray(row) || (size_t)cJSON_GetArraySize(row) != cols) {
            free(a);
            return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\"[%zu]: expected a list of %zu %s",
                           name, i, cols, weights ? "numbers" : "points");
        }
        size_t j = 0;
        const cJSON *e;
        cJSON_ArrayForEach(e, row)
        {
            char what[64];
            snprintf(what, sizeof what, "\"%s\"[%zu][%zu]", name, i, j);
            geom_status st;
            if (weights) {
                if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
                    st = sj_fail(x, GEOM_ERR_PARSE, 0, 0, "%s: expected a finite number", what);
                else {
                    a[i * cols + j] = e->valuedouble;
                    st = GEOM_OK;
                }
            } else {
                size_t dim = 3;
                st = get_point(x, e, what, &dim, a + 3 * (i * cols + j));
            }
            if (st != GEOM_OK) {
                free(a);
                return st;
            }
            ++j;
        }
        ++i;
    }
    *out = a;
    *nu = rows;
    *nv = cols;
    return GEOM_OK;
}

static geom_status read_surface(sj_ctx *x, const cJSON *e, geom_surface_set *set,
                                const char *name)
{
    const cJSON *t = key(e, "type");
    if (!t || !cJSON_IsString(t))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0, "missing key \"type\" (a string)");
    const char *type = t->valuestring;
    int bez = !strcmp(type, "bezier");
    if (!bez && strcmp(type, "bspline") && strcmp(type, "nurbs"))
        return sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                       "\"type\": unknown surface type \"%s\" (bezier, bspline, nurbs)", type);
    double *P = NULL, *W = NULL, *ku = NULL, *kv = NULL;
    size_t nu, nv, nku = 0, nkv = 0;
    geom_status st = get_grid(x, e, "points", 0, 0, 0, &P, &nu, &nv);
    int pu = 0, pv = 0;
    if (st == GEOM_OK && (nu < 2 || nv < 2))
        st = sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"points\": %zu x %zu, at least 2 x 2 needed", nu,
                     nv);
    if (st == GEOM_OK && bez) {
        st = get_int(x, e, "degree_u", 0, (int)nu - 1, 1, 1 << 16, &pu);
        if (st == GEOM_OK && (size_t)pu != nu - 1)
            st = sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                         "\"degree_u\": %d, but %zu rows of points make degree %zu", pu, nu,
                         nu - 1);
        if (st == GEOM_OK)
            st = get_int(x, e, "degree_v", 0, (int)nv - 1, 1, 1 << 16, &pv);
        if (st == GEOM_OK && (size_t)pv != nv - 1)
            st = sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                         "\"degree_v\": %d, but %zu points per row make degree %zu", pv, nv,
                         nv - 1);
        if (st == GEOM_OK) {
            nku = 2 * nu;
            nkv = 2 * nv;
            ku = malloc(nku * sizeof(double));
            kv = malloc(nkv * sizeof(double));
            if (!ku || !kv)
                st = sj_fail(x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
            else {
                geom_surface_bezier_knots(pu, ku);
                geom_surface_bezier_knots(pv, kv);
            }
        }
    } else if (st == GEOM_OK) {
        st = get_int(x, e, "degree_u", 1, 0, 1, 1 << 16, &pu);
        if (st == GEOM_OK)
            st = get_int(x, e, "degree_v", 1, 0, 1, 1 << 16, &pv);
        if (st == GEOM_OK)
            st = get_numbers(x, e, "knots_u", 0, &ku, &nku);
        if (st == GEOM_OK && nku != nu + (size_t)pu + 1)
            st = sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                         "\"knots_u\": %zu knots, %zu expected (rows of points + degree_u + 1)",
                         nku, nu + (size_t)pu + 1);
        if (st == GEOM_OK)
            st = get_numbers(x, e, "knots_v", 0, &kv, &nkv);
        if (st == GEOM_OK && nkv != nv + (size_t)pv + 1)
            st = sj_fail(x, GEOM_ERR_PARSE, 0, 0,
                         "\"knots_v\": %zu knots, %zu expected (points per row + degree_v + 1)",
                         nkv, nv + (size_t)pv + 1);
    }
    if (st == GEOM_OK && key(e, "weights")) {
        size_t wu, wv;
        st = get_grid(x, e, "weights", 1, nu, nv, &W, &wu, &wv);
    }
    if (st == GEOM_OK) {
        geom_nurbs_surface s = {pu, pv, nu, nv, ku, kv, P, W};
        geom_diag d;
        geom_diag_clear(&d);
        if (geom_surface_validate(&s, &d) != GEOM_OK) {
            /* the validator's message starts "surface: <key>: ..." */
            const char *m = d.message;
            if (!strncmp(m, "surface: ", 9))
                m += 9;
            const char *k = !strncmp(m, "knots_u", 7)   ? "knots_u"
                            : !strncmp(m, "knots_v", 7) ? "knots_v"
                            : !strncmp(m, "weights", 7) ? "weights"
                                                        : "points";
            size_t kl = strlen(k);
            if (!strncmp(m, k, kl) && m[kl] == ':')
                m += kl + 2;
            st = sj_fail(x, GEOM_ERR_PARSE, 0, 0, "\"%s\": %s", k, m);
        } else {
            st = geom_surface_set_add(set, &s, name);
            if (st != GEOM_OK)
                st = sj_fail(x, st, 0, 0, "out of memory");
        }
    }
    free(P);
    free(W);
    free(ku);
    free(kv);
    return st;
}

/* ------------------------------------------------------------------ files */

void sj_free(sj_file *f)
{
    if (!f)
        return;
    for (size_t i = 0; i < f->ncurves; ++i)
        curve_free(&f->curves[i]);
    free(f->curves);
    geom_surface_set_destroy(f->surfaces);
    memset(f, 0, sizeof *f);
}

static void set_where(sj_ctx *x, const char *list, size_t i, const cJSON *e)
{
    const cJSON *nm = cJSON_IsObject(e) ? key(e, "name") : NULL;
    if (nm && cJSON_IsString(nm))
        snprintf(x->where, sizeof x->where, "%s[%zu] (\"%.60s\")", list, i, nm->valuestring);
    else
        snprintf(x->where, sizeof x->where, "%s[%zu]", list, i);
}

geom_status sj_json_parse(const char *text, size_t len, const char *source, cJSON **root,
                          geom_diag *diag)
{
    sj_ctx x = {source ? source : "<memory>", diag, ""};
    *root = NULL;
    if (!text && len)
        return sj_fail(&x, GEOM_ERR_INVALID_ARG, 0, 0, "NULL argument");
    if (len && memchr(text, '\0', len))
        return sj_fail(&x, GEOM_ERR_PARSE, 0, 0, "NUL byte in the JSON text");
    const char *end = NULL, *start = text;
    int trailing = 0;
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0)
        start += 3; /* a UTF-8 byte-order mark */
    cJSON *r = len ? cJSON_ParseWithLengthOpts(start, len - (size_t)(start - text), &end, 0) : NULL;
    if (r && end) { /* only white space may follow the value */
        const char *q = end;
        while (q < text + len && (*q == ' ' || *q == '\t' || *q == '\n' || *q == '\r'))
            q++;
        if (q < text + len) {
            cJSON_Delete(r);
            r = NULL;
            end = q;
            trailing = 1;
        }
    }
    if (!r) {
        if (start == text + len)
            return sj_fail(&x, GEOM_ERR_PARSE, 0, 0, "empty file: expected a JSON object");
        size_t off = end && end >= text && end <= text + len ? (size_t)(end - text) : 0;
        size_t line = 1, col = 1;
        for (size_t i = 0; i < off; ++i) {
            if (text[i] == '\n')
                line++, col = 1;
            else
                col++;
        }
        return sj_fail(&x, GEOM_ERR_PARSE, line, col,
                       trailing ? "text after the JSON value" : "JSON syntax error");
    }
    *root = r;
    return GEOM_OK;
}

geom_status sj_read_memory(const char *text, size_t len, const char *source, sj_file *out,
                           geom_diag *diag)
{
    sj_ctx x = {source ? source : "<memory>", diag, ""};
    if (!out || (!text && len))
        return sj_fail(&x, GEOM_ERR_INVALID_ARG, 0, 0, "NULL argument");
    memset(out, 0, sizeof *out);
    cJSON *root;
    geom_status pst = sj_json_parse(text, len, source, &root, diag);
    if (pst != GEOM_OK)
        return pst;
    geom_status st = GEOM_OK;
    if (!cJSON_IsObject(root)) {
        st = sj_fail(&x, GEOM_ERR_PARSE, 0, 0,
                     "expected an object {\"curves\": [...], \"surfaces\": [...]}");
        goto done;
    }
    const cJSON *curves = key(root, "curves"), *surfaces = key(root, "surfaces");
    if ((curves && !cJSON_IsArray(curves)) || (surfaces && !cJSON_IsArray(surfaces))) {
        st = sj_fail(&x, GEOM_ERR_PARSE, 0, 0, "\"%s\": expected a list",
                     curves && !cJSON_IsArray(curves) ? "curves" : "surfaces");
        goto done;
    }
    out->surfaces = geom_surface_set_create(NULL);
    if (!out->surfaces) {
        st = sj_fail(&x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
        goto done;
    }
    if (curves) {
        size_t n = (size_t)cJSON_GetArraySize(curves);
        out->curves = calloc(n ? n : 1, sizeof(sj_curve));
        if (!out->curves) {
            st = sj_fail(&x, GEOM_ERR_NOMEM, 0, 0, "out of memory");
            goto done;
        }
        size_t i = 0;
        const cJSON *e;
        cJSON_ArrayForEach(e, curves)
        {
            set_where(&x, "curves", i, e);
            if (!cJSON_IsObject(e)) {
                st = sj_fail(&x, GEOM_ERR_PARSE, 0, 0, "expected an object");
                goto done;
            }
            st = read_curve(&x, e, &out->curves[i]);
            out->ncurves = i + 1;
            if (st != GEOM_OK)
                goto done;
            const cJSON *nm = key(e, "name");
            if (nm && cJSON_IsString(nm))
                snprintf(out->curves[i].name, sizeof out->curves[i].name, "%s", nm->valuestring);
            ++i;
        }
    }
    if (surfaces) {
        size_t i = 0;
        const cJSON *e;
        cJSON_ArrayForEach(e, surfaces)
        {
            set_where(&x, "surfaces", i, e);
            if (!cJSON_IsObject(e)) {
                st = sj_fail(&x, GEOM_ERR_PARSE, 0, 0, "expected an object");
                goto done;
            }
            const cJSON *nm = key(e, "name");
            st = read_surface(&x, e, out->surfaces,
                              nm && cJSON_IsString(nm) ? nm->valuestring : NULL);
            if (st != GEOM_OK)
                goto done;
            ++i;
        }
    }
done:
    cJSON_Delete(root);
    if (st != GEOM_OK)
        sj_free(out);
    return st;
}

geom_status sj_read_file(const char *path, sj_file *out, geom_diag *diag)
{
    if (out)
        memset(out, 0, sizeof *out);
    geom_file f;
    geom_status st = geom_file_map(path, NULL, &f, diag);
    if (st == GEOM_OK)
        st = sj_read_memory((const char *)f.data, f.size, path, out, diag);
    geom_file_unmap(&f);
    return st;
}
