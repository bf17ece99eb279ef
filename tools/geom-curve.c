/* geom-module: surface meshio */
/*
 * geom-curve: polylines or sampled points (with derivatives) of the curves
 * in a JSON file.
 *
 *   geom-curve IN.json -o OUT.obj|OUT.csv [--tol T | --samples N] [--derivs K]
 *
 * Every curve of IN's "curves" list (tools/surface_json.h: bezier, bspline,
 * nurbs, hermite, catmull_rom, kochanek_bartels) is either approximated by
 * an adaptive polyline to the chordal tolerance T (the default mode; T
 * defaults to 1e-3 times the diagonal of the curve's control point box;
 * geom_curve_nurbs_polyline with its convex-hull bound), or sampled at N
 * parameters evenly spaced over its domain (--samples).
 *
 *  - OBJ output: one `o` and one `l` polyline per curve (v lines in 3D; 2D
 *    curves get z = 0).
 *  - CSV output: a header, then one row per point: curve, index, u, x, y, z
 *    and, with --derivs K, the derivatives d1x, d1y, d1z, ..., dKx, dKy, dKz
 *    with respect to u (one-sided as the curve module's rule at knots says).
 *
 * The report goes to standard output (standard error when the data does):
 * curves, points, max_error (the polyline's chordal error: the bound with
 * --tol, measured at 7 points inside every segment with --samples) and
 * seconds; --json prints it as one object.
 *
 * Exit status 0 on success, 1 on a read, parse or write error, 2 on a usage
 * error.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/curve.h"
#ifdef GEOM_HAVE_CJSON
#include "surface_json.h"
#endif

static const cli_tool tool = {
    "geom-curve",
    "[OPTION]... IN.json -o OUT.obj|OUT.csv",
    "Approximate the curves in IN (JSON) by polylines to a chordal tolerance, or\n"
    "sample them, and write OBJ polylines or CSV points with derivatives.",
    "  -t, --tol=T          adaptive polylines with chordal tolerance T (absolute;\n"
    "                       default 1e-3 times each curve's control box diagonal)\n"
    "  -s, --samples=N      N >= 2 evenly spaced parameters per curve instead\n"
    "  -d, --derivs=K       CSV: also the derivatives of orders 1..K (K <= 16)\n"
    "      --max-points=N   stop before writing more than N points in all (the\n"
    "                       count is computed first; default 10000000)\n"
    "  -f, --format=FMT     obj or csv; default: from OUT's extension\n",
    "Prints curves, points, max_error and seconds (--json: one object).\n",
    "  geom-curve data/surfaces.json --tol 1e-4 -o curves.obj\n"
    "  geom-curve data/surfaces.json --samples 100 --derivs 2 -o samples.csv\n",
};

#define MAX_POINTS_DEFAULT 10000000.0

enum { OPT_MAX_POINTS = CLI_OPT_TOOL_BASE };

typedef struct curve_opts {
    double tol;
    double max_points; /* 0: MAX_POINTS_DEFAULT */
    long samples;
    int derivs;
    int csv, have_format;
} curve_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    curve_opts *o = user;
    double d;
    switch (opt) {
    case 't':
        if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || !(d > 0.0))
            return cli_usage_error(t, "--tol takes a positive number, not '%s'", arg);
        o->tol = d;
        return CLI_CONTINUE;
    case 's':
        if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || d != floor(d) ||
            d < 2 || d > 1e7)
            return cli_usage_error(t, "--samples takes an integer in [2, 1e7], not '%s'", arg);
        o->samples = (long)d;
        return CLI_CONTINUE;
    case 'd':
        if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || d != floor(d) ||
            d < 0 || d > 16)
            return cli_usage_error(t, "--derivs takes an integer in [0, 16], not '%s'", arg);
        o->derivs = (int)d;
        return CLI_CONTINUE;
    case OPT_MAX_POINTS:
        if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || d != floor(d) ||
            d < 2 || d > 1e15)
            return cli_usage_error(t, "--max-points takes an integer >= 2, not '%s'", arg);
        o->max_points = d;
        return CLI_CONTINUE;
    case 'f':
        if (!strcmp(arg, "csv"))
            o->csv = 1;
        else if (!strcmp(arg, "obj"))
            o->csv = 0;
        else
            return cli_usage_error(t, "unknown format '%s' (obj, csv)", arg);
        o->have_format = 1;
        return CLI_CONTINUE;
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

#ifdef GEOM_HAVE_CJSON
/* Distance from q to the segment a-b (dim doubles each). */
/* Parameters and points of one curve (malloc'd), and its chordal error. */
static geom_status approximate(const curve_opts *o, const geom_nurbs_curve *c, double **params,
                               double **points, size_t *count, double *err, geom_diag *diag)
{
    size_t dim = c->dim;
    double u0, u1;
    geom_curve_nurbs_domain(c, &u0, &u1);
    *params = *points = NULL;
    if (o->samples) {
        size_t n = (size_t)o->samples;
        *params = malloc(n * sizeof(double));
        *points = malloc(n * dim * sizeof(double));
        if (!*params || !*points)
            return cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
        for (size_t i = 0; i < n; ++i) {
            double u = i + 1 == n ? u1 : u0 + (u1 - u0) * (double)i / (double)(n - 1);
            (*params)[i] = u;
            geom_status st = geom_curve_nurbs_eval(c, u, 0, *points + i * dim);
            if (st != GEOM_OK)
                return cli_diag_set(diag, st, NULL, 0, 0, "evaluation failed: %s",
                                    geom_status_str(st));
        }
        *count = n;
        /* chordal error, measured inside every segment */
        double e = 0.0;
        for (size_t i = 0; i + 1 < n; ++i)
            for (int k = 1; k <= 7; ++k) {
                double q[GEOM_CURVE_MAX_DIM];
                double u = (*params)[i] + ((*params)[i + 1] - (*params)[i]) * k / 8.0;
                geom_curve_nurbs_eval(c, u, 0, q);
                double di = geom_curve_segment_distance(dim, *points + i * dim,
                                                        *points + (i + 1) * dim, q);
                if (isnan(di)) /* never a silent 0: fmax would drop the NaN */
                    return cli_diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                                        "the chordal error is not a number (points beyond the "
                                        "range of double)");
                e = fmax(e, di);
            }
        *err = e;
        return GEOM_OK;
    }
    geom_curve_polyline_options po;
    memset(&po, 0, sizeof po);
    po.tolerance = o->tol;
    /* the count was checked against --max-points before the work */
    po.max_points = o->max_points <= 0.0  ? (size_t)MAX_POINTS_DEFAULT + 1
                    : o->max_points < 1e15 ? (size_t)o->max_points + 1
                                           : SIZE_MAX;
    size_t n = 0;
    geom_error_report rep;
    geom_status st = geom_curve_nurbs_polyline(c, &po, NULL, NULL, 0, &n, &rep, diag);
    if (st != GEOM_OK)
        return st;
    *params = malloc((n ? n : 1) * sizeof(double));
    *points = malloc((n ? n : 1) * dim * sizeof(double));
    if (!*params || !*points)
        return cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
    st = geom_curve_nurbs_polyline(c, &po, *params, *points, n, count, &rep, diag);
    *err = rep.max_error;
    return st;
}
#endif

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"tol", required_argument, NULL, 't'},
                                             {"samples", required_argument, NULL, 's'},
                                             {"derivs", required_argument, NULL, 'd'},
                                             {"format", required_argument, NULL, 'f'},
                                             {"max-points", required_argument, NULL,
                                              OPT_MAX_POINTS},
                                             {NULL, 0, NULL, 0}};
    curve_opts o;
    memset(&o, 0, sizeof o);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "t:s:d:f:", longopts, on_option, &o, &common,
                            &first);
    if (rc != CLI_CONTINUE)
        return rc;
    rc = cli_operands(&tool, argc, argv, first, 1, 1);
    if (rc != CLI_CONTINUE)
        return rc;
    if (o.tol > 0.0 && o.samples)
        return cli_usage_error(&tool, "--tol and --samples exclude each other");
    if (!common.output)
        return cli_usage_error(&tool, "missing -o OUT.obj|OUT.csv");
    const char *out_path = common.output;
    int to_stdout = strcmp(out_path, "-") == 0;
    if (!o.have_format) {
        if (cli_ends_with(out_path, ".csv"))
            o.csv = 1;
        else if (cli_ends_with(out_path, ".obj"))
            o.csv = 0;
        else if (!to_stdout)
            return cli_usage_error(&tool, "cannot tell the format from '%s': use --format",
                                   out_path);
    }
    if (o.derivs && !o.csv)
        return cli_usage_error(&tool, "--derivs needs CSV output");
#ifndef GEOM_HAVE_CJSON
    return cli_error(&tool, "%s: JSON input needs cJSON, which this build does not have",
                     argv[first]);
#else
    FILE *rep = to_stdout ? stderr : stdout;
    geom_diag diag;
    geom_diag_clear(&diag);
    sj_file f;
    if (sj_read_file(argv[first], &f, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    if (f.ncurves == 0) {
        sj_free(&f);
        return cli_error(&tool, "%s: no curves", argv[first]);
    }
    /* count the output before the work: stop past --max-points with the
     * count in the message instead of filling memory and disk */
    double limit = o.max_points > 0.0 ? o.max_points : MAX_POINTS_DEFAULT;
    double want = 0.0;
    int cut = 0;
    /* the library's a priori bound first (no subdivision): when every
     * curve has one and their sum fits, nothing is counted exactly */
    int bounded = !o.samples;
    double bound_sum = 0.0;
    for (size_t ci = 0; ci < f.ncurves && bounded; ++ci) {
        geom_curve_polyline_options po;
        memset(&po, 0, sizeof po);
        po.tolerance = o.tol;
        double est = 0.0;
        int is_bound = 0;
        bounded = geom_curve_nurbs_polyline_estimate(&f.curves[ci].c, &po, &est, &is_bound,
                                                     NULL) == GEOM_OK &&
                  is_bound;
        bound_sum += est;
    }
    size_t ncount = bounded && bound_sum <= limit ? 0 : f.ncurves;
    for (size_t ci = 0; ci < ncount; ++ci) {
        size_t n = 0;
        if (o.samples) {
            n = (size_t)o.samples;
        } else {
            geom_curve_polyline_options po;
            memset(&po, 0, sizeof po);
            po.tolerance = o.tol;
            /* the library's own cap stops a runaway count early */
            po.max_points = limit > 1e15 ? 0 : (size_t)limit + 1;
            geom_status cs = geom_curve_nurbs_polyline(&f.curves[ci].c, &po, NULL, NULL, 0, &n,
                                                       NULL, NULL);
            if (cs == GEOM_ERR_LIMIT && n == 0) {
                n = (size_t)limit + 1; /* over the cap: the count was cut short */
                cut = 1;
            }
            else if (cs != GEOM_OK)
                continue; /* reported with its curve below */
        }
        want += (double)n;
        if (want > limit) {
            sj_free(&f);
            return cli_error(&tool,
                             "%s: the polylines would have %s%.0f points (limit %.0f, curve %zu "
                             "and before): raise --max-points%s",
                             argv[first], cut ? "more than " : "", want, limit, ci,
                             o.samples ? " or lower --samples" : " or the tolerance");
        }
    }
    cli_output out;
    if (cli_output_open(&out, out_path, &diag) != GEOM_OK) {
        sj_free(&f);
        return cli_print_diag(&tool, &diag);
    }
    double compute = 0.0, max_err = 0.0;
    size_t ncurves = f.ncurves;
    size_t total = 0, vbase = 1;
    int K = o.derivs;
    geom_status st = GEOM_OK;
    if (o.csv) {
        fprintf(out.fp, "curve,index,u,x,y,z");
        for (int k = 1; k <= K; ++k)
            fprintf(out.fp, ",d%dx,d%dy,d%dz", k, k, k);
        fprintf(out.fp, "\n");
    }
    for (size_t ci = 0; ci < f.ncurves && st == GEOM_OK; ++ci) {
        const geom_nurbs_curve *c = &f.curves[ci].c;
        size_t dim = c->dim, n = 0;
        double *params = NULL, *points = NULL, err = 0.0;
        cli_timer t1;
        cli_timer_start(&t1);
        st = approximate(&o, c, &params, &points, &n, &err, &diag);
        compute += cli_timer_elapsed(&t1);
        if (st == GEOM_OK) {
            max_err = fmax(max_err, err);
            total += n;
            const char *name = f.curves[ci].name[0] ? f.curves[ci].name : f.curves[ci].type;
            if (!o.csv) {
                fprintf(out.fp, "o %s_%zu\n", name, ci);
                for (size_t i = 0; i < n; ++i) {
                    const double *P = points + i * dim;
                    fprintf(out.fp, "v %.17g %.17g %.17g\n", P[0], P[1], dim > 2 ? P[2] : 0.0);
                }
                fprintf(out.fp, "l");
                for (size_t i = 0; i < n; ++i)
                    fprintf(out.fp, " %zu", vbase + i);
                fprintf(out.fp, "\n");
                vbase += n;
            } else {
                double D[17 * GEOM_CURVE_MAX_DIM];
                for (size_t i = 0; i < n && st == GEOM_OK; ++i) {
                    st = geom_curve_nurbs_derivs(c, params[i], K, 0, D);
                    if (st != GEOM_OK) {
                        cli_diag_set(&diag, st, argv[first], 0, 0, "curve %zu: derivatives: %s",
                                     ci, geom_status_str(st));
                        break;
                    }
                    memcpy(D, points + i * dim, dim * sizeof(double)); /* the point as written */
                    fprintf(out.fp, "%zu,%zu,%.17g", ci, i, params[i]);
                    for (int k = 0; k <= K; ++k)
                        fprintf(out.fp, ",%.17g,%.17g,%.17g", D[(size_t)k * dim],
                                D[(size_t)k * dim + 1], dim > 2 ? D[(size_t)k * dim + 2] : 0.0);
                    fprintf(out.fp, "\n");
                }
            }
        } else if (!diag.source[0]) {
            char msg[GEOM_DIAG_MESSAGE_MAX];
            snprintf(msg, sizeof msg, "%s", diag.message);
            cli_diag_set(&diag, st, argv[first], 0, 0, "curves[%zu]: %s", ci, msg);
        }
        free(params);
        free(points);
    }
    sj_free(&f);
    if (st != GEOM_OK) {
        cli_output_abort(&out);
        return cli_print_diag(&tool, &diag);
    }
    if (cli_output_commit(&out, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    const char *method = o.samples ? "sampled" : "bound";
    if (common.json) {
        fprintf(rep, "{\"curves\":%zu,\"points\":%zu,\"max_error\":", ncurves, total);
        cli_json_number(rep, max_err);
        fprintf(rep, ",\"method\":\"%s\",\"seconds\":", method);
        cli_json_number(rep, compute);
        fprintf(rep, "}\n");
    } else {
        fprintf(rep, "curves: %zu\npoints: %zu\nmax_error: %.6g (%s)\nseconds: %.6f\n",
                ncurves, total, max_err, method, compute);
    }
    return CLI_EXIT_OK;
#endif
}
