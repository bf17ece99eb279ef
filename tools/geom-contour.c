/* geom-module: implicit meshio */
/*
 * geom-contour: isolines of an expression f(x, y, z0) by marching squares.
 *
 *   geom-contour --expr E --bounds X0,Y0,X1,Y1 --res N[,NY] [--iso V] [--z Z]
 *                [--no-refine] [--format svg|obj] [--json] -o OUT.svg|OUT.obj
 *
 * The expression language is libgeom's (see geom/implicit.h): x, y, z, t,
 * numbers, + - * / ^, functions, primitives (sphere, torus, box, ...) and
 * CSG (union, smooth_union, ...). The grid has N x NY cells (NY = N when
 * omitted) over the bounds; vertices are refined on their edges by root
 * finding unless --no-refine. Prints the vertex and polyline counts, the
 * achieved error (max over vertices of |f - iso| / |grad f|) and the time;
 * with --json a JSON object with the keys vertices, polylines, closed,
 * max_error, mean_error, seconds on standard output (OUT must be a file).
 *
 * Exit status 0 on success, 1 on an expression or write error, 2 on a
 * usage error.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"
#include "geom/meshio.h"

static const cli_tool tool = {
    "geom-contour",
    "--expr E --bounds X0,Y0,X1,Y1 --res N[,NY] [OPTION]... [-o OUT]",
    "Isolines f(x, y, z) = V of the expression E over a grid of N x NY cells\n"
    "(marching squares with the asymptotic decider), written as SVG or as OBJ\n"
    "polylines (`l` lines) to OUT (standard output when OUT is '-' or absent;\n"
    "then --format is needed).",
    "  -e, --expr=E         the function, e.g. 'smooth_union(sphere(1), box(1,0.5,1,1.2,\n"
    "                       0.3,1), 0.2)'; inside is f <= V\n"
    "  -b, --bounds=X0,Y0,X1,Y1  the rectangle to contour (X0 < X1, Y0 < Y1)\n"
    "  -r, --res=N[,NY]     cells along x (and y; default NY = N), at most 100000\n"
    "  -i, --iso=V          the isovalue (default 0)\n"
    "  -z, --z=Z            the value of z in E (default 0)\n"
    "      --no-refine      place vertices by linear interpolation only (default:\n"
    "                       refine them on their edge by root finding)\n"
    "  -f, --format=FMT     svg or obj (default: from OUT's extension)\n"
    "      --max-cells=N    stop before sampling more than N grid cells (the work,\n"
    "                       estimated before it: every cell of a field without\n"
    "                       bounds, only those near the curve for an expression;\n"
    "                       default 1G; suffixes k, M, G)\n"
    CLI_LIMIT_HELP
    "                       (for isolines a segment counts as a triangle)\n",
    "Expressions: numbers, x y z t, + - * / ^, sqrt abs sin cos tan exp log min\n"
    "max clamp atan2 pow, sphere ellipsoid torus box cylinder plane capsule gyroid,\n"
    "union intersection difference smooth_union smooth_intersection\n"
    "smooth_difference; see geom/implicit.h for every signature.\n"
    "The summary (vertices, polylines, closed loops, max_error, seconds) goes to\n"
    "standard output, or to standard error when the result does; with --json it\n"
    "is a JSON object on standard output and OUT must be a file.\n",
    "  geom-contour --expr \"x^2 + y^2 - 1\" --bounds -2,-2,2,2 --res 64 -o circle.svg\n"
    "  geom-contour --expr \"torus(1, 0.3)\" --z 0.1 --bounds -2,-2,2,2 --res 200 --json -o slice.obj\n",
};

enum { OPT_NO_REFINE = CLI_OPT_TOOL_BASE, OPT_MAX_CELLS };
enum { FMT_NONE = 0, FMT_SVG, FMT_OBJ };

typedef struct contour_opts {
    const char *expr;
    double bounds[4];
    int have_bounds;
    size_t res[2];
    int have_res;
    double iso, z;
    int no_refine;
    int format;
    cli_limits lim;
    size_t max_cells; /* 0: MAX_CELLS_DEFAULT */
} contour_opts;

/* Default --max-cells: 10^9 cells sampled, about 3.5 minutes of a field
 * without bounds on one core (the dense path measured 21.7 s for 10^8);
 * expression fields sample only the cells near the curve. */
#define MAX_CELLS_DEFAULT ((size_t)1000000000)

static int format_from_name(const char *s)
{
    const char *dot = strrchr(s, '.');
    const char *ext = dot ? dot + 1 : s;
    if (strcmp(ext, "svg") == 0 || strcmp(ext, "SVG") == 0)
        return FMT_SVG;
    if (strcmp(ext, "obj") == 0 || strcmp(ext, "OBJ") == 0)
        return FMT_OBJ;
    return FMT_NONE;
}

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    contour_opts *o = user;
    double v[4];
    size_t n;
    geom_diag d;
    int lrc = cli_limits_option(t, &o->lim, opt, arg);
    if (lrc != CLI_NOT_HANDLED)
        return lrc;
    switch (opt) {
    case 'e':
        o->expr = arg;
        return CLI_CONTINUE;
    case 'b':
        if (cli_parse_numbers(arg, strlen(arg), 0, v, 4, &n, &d) != GEOM_OK || n != 4)
            return cli_usage_error(t, "--bounds takes four numbers X0,Y0,X1,Y1, not '%s'", arg);
        if (!(v[0] < v[2]) || !(v[1] < v[3]))
            return cli_usage_error(t, "--bounds '%s': need X0 < X1 and Y0 < Y1", arg);
        if (!isfinite(v[2] - v[0]) || !isfinite(v[3] - v[1])) /* else nan/inf in the SVG */
            return cli_usage_error(t, "--bounds '%s': the width or height overflows a double",
                                   arg);
        memcpy(o->bounds, v, sizeof o->bounds);
        o->have_bounds = 1;
        return CLI_CONTINUE;
    case 'r':
        if (cli_parse_numbers(arg, strlen(arg), 0, v, 2, &n, &d) != GEOM_OK || n < 1)
            return cli_usage_error(t, "--res takes N or N,NY, not '%s'", arg);
        for (size_t k = 0; k < n; k++)
            if (!(v[k] >= 1 && v[k] <= 100000) || v[k] != (double)(size_t)v[k])
                return cli_usage_error(t, "--res '%s': cell counts are integers in 1..100000",
                                       arg);
        o->res[0] = (size_t)v[0];
        o->res[1] = n == 2 ? (size_t)v[1] : (size_t)v[0];
        o->have_res = 1;
        return CLI_CONTINUE;
    case 'i':
        if (cli_parse_double(arg, strlen(arg), 0, &o->iso, &d) != GEOM_OK)
            return cli_usage_error(t, "--iso takes a finite number, not '%s'", arg);
        return CLI_CONTINUE;
    case 'z':
        if (cli_parse_double(arg, strlen(arg), 0, &o->z, &d) != GEOM_OK)
            return cli_usage_error(t, "--z takes a finite number, not '%s'", arg);
        return CLI_CONTINUE;
    case OPT_NO_REFINE:
        o->no_refine = 1;
        return CLI_CONTINUE;
    case OPT_MAX_CELLS:
        if (cli_parse_size(arg, false, &o->max_cells) != 0 || o->max_cells == 0)
            return cli_usage_error(t, "--max-cells takes a positive count (suffixes k, M, G), "
                                      "not '%s'", arg);
        return CLI_CONTINUE;
    case 'f':
        o->format = format_from_name(arg);
        if (o->format == FMT_NONE || strchr(arg, '.'))
            return cli_usage_error(t, "unknown format '%s' (svg or obj)", arg);
        return CLI_CONTINUE;
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

static void write_svg(FILE *fp, const geom_implicit_isolines *c, const double b[4])
{
    double w = b[2] - b[0], h = b[3] - b[1];
    double px = 800.0, py = 800.0 * (h / w); /* h / w first: 800 * h overflows near DBL_MAX */
    if (py > 800.0) {
        py = 800.0;
        px = 800.0 * (w / h);
    }
    fprintf(fp, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    fprintf(fp, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
                "viewBox=\"", px, py);
    /* y up: the picture shows (x, -y) */
    cli_print_double(fp, b[0]);
    fputc(' ', fp);
    cli_print_double(fp, -b[3]);
    fputc(' ', fp);
    cli_print_double(fp, w);
    fputc(' ', fp);
    cli_print_double(fp, h);
    fprintf(fp, "\">\n");
    fprintf(fp, "<rect x=\"%.17g\" y=\"%.17g\" width=\"%.17g\" height=\"%.17g\" fill=\"none\" "
                "stroke=\"#bbbbbb\" stroke-width=\"1\" vector-effect=\"non-scaling-stroke\"/>\n",
            b[0], -b[3], w, h);
    for (size_t k = 0; k < c->n_polylines; k++) {
        fprintf(fp, "<path fill=\"none\" stroke=\"black\" stroke-width=\"1\" "
                    "vector-effect=\"non-scaling-stroke\" d=\"");
        for (size_t q = c->start[k]; q < c->start[k + 1]; q++) {
            uint32_t v = c->indices[q];
            fputs(q == c->start[k] ? "M" : " L", fp);
            cli_print_double(fp, c->xy[2 * v]);
            fputc(' ', fp);
            cli_print_double(fp, -c->xy[2 * v + 1]);
        }
        if (c->closed[k])
            fputs(" Z", fp);
        fprintf(fp, "\"/>\n");
    }
    fprintf(fp, "</svg>\n");
}

static geom_status write_obj(const geom_implicit_isolines *c, double z, const char *path,
                             geom_diag *diag)
{
    geom_mesh *m = geom_mesh_create(NULL);
    if (!m)
        return cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
    geom_status st = geom_implicit_isolines_to_mesh(c, z, m);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_diag_set(diag, st, NULL, 0, 0, "building the polylines: %s",
                            geom_status_str(st));
    }
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    if (strcmp(path, "-") != 0) {
        st = geom_meshio_write(m, path, &wo, diag);
    } else {
        void *buf = NULL;
        size_t n = 0;
        st = geom_meshio_write_memory(m, &wo, &buf, &n, diag);
        if (st == GEOM_OK) {
            cli_output out;
            st = cli_output_open(&out, NULL, diag);
            if (st == GEOM_OK) {
                fwrite(buf, 1, n, out.fp);
                st = cli_output_commit(&out, diag);
            }
            geom_meshio_buffer_free(buf, n, NULL);
        }
    }
    geom_mesh_destroy(m);
    return st;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"expr", required_argument, NULL, 'e'},
                                             {"bounds", required_argument, NULL, 'b'},
                                             {"res", required_argument, NULL, 'r'},
                                             {"iso", required_argument, NULL, 'i'},
                                             {"z", required_argument, NULL, 'z'},
                                             {"no-refine", no_argument, NULL, OPT_NO_REFINE},
                                             {"format", required_argument, NULL, 'f'},
                                             {"max-cells", required_argument, NULL, OPT_MAX_CELLS},
                                             CLI_LIMIT_LONGOPTS,
                                             {NULL, 0, NULL, 0}};
    contour_opts o;
    memset(&o, 0, sizeof o);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "e:b:r:i:z:f:", longopts, on_option, &o, &common,
                            &first);
    if (rc != CLI_CONTINUE)
        return rc;
    if (first < argc)
        return cli_usage_error(&tool, "extra operand '%s'", argv[first]);
    if (!o.expr)
        return cli_usage_error(&tool, "missing --expr");
    if (!o.have_bounds)
        return cli_usage_error(&tool, "missing --bounds");
    if (!o.have_res)
        return cli_usage_error(&tool, "missing --res");
    const char *out_path = common.output ? common.output : "-";
    int to_stdout = strcmp(out_path, "-") == 0;
    if (o.format == FMT_NONE) {
        if (to_stdout)
            return cli_usage_error(&tool, "writing to standard output needs --format");
        o.format = format_from_name(out_path);
        if (o.format == FMT_NONE)
            return cli_usage_error(&tool, "cannot tell the output format from '%s': use --format",
                                   out_path);
    }
    if (common.json && to_stdout)
        return cli_usage_error(&tool, "--json needs the result written to a file (-o OUT)");

    cli_timer timer;
    cli_timer_start(&timer);
    geom_diag diag;
    geom_diag_clear(&diag);
    geom_implicit_expr *e = NULL;
    if (geom_implicit_expr_compile(o.expr, strlen(o.expr), NULL, &e, &diag) != GEOM_OK) {
        cli_print_diag(&tool, &diag);
        if (diag.column > 0 && diag.line == 1 && strlen(o.expr) < 200 && !strchr(o.expr, '\n'))
            fprintf(stderr, "  %s\n  %*s^\n", o.expr, (int)diag.column - 1, "");
        return CLI_EXIT_ERROR;
    }
    geom_implicit_field field;
    geom_implicit_field_from_expr(e, &field);
    geom_implicit_contour_options co;
    memset(&co, 0, sizeof co);
    co.iso = o.iso;
    co.z = o.z;
    co.refine = o.no_refine ? GEOM_IMPLICIT_REFINE_NEVER : GEOM_IMPLICIT_REFINE_AUTO;
    /* the output's size before the work: segments (about one per vertex)
     * against --max-triangles, memory (the library's arrays, the mesh and
     * the text written, about 160 bytes a vertex) against --max-memory */
    double est = 0.0;
    if (geom_implicit_contour_estimate(&field, o.bounds, o.res[0], o.res[1], &co, &est) ==
            GEOM_OK &&
        cli_limits_check(&tool, &o.lim, "the isolines (a segment counts as a triangle)", est,
                         est * 160.0) != CLI_CONTINUE) {
        geom_implicit_expr_destroy(e);
        return CLI_EXIT_ERROR;
    }
    /* the work before it: the cells marching squares will sample (the
     * blocks the interval bounds cannot prove free of the curve) */
    double cells = 0.0;
    size_t max_cells = o.max_cells ? o.max_cells : MAX_CELLS_DEFAULT;
    if (geom_implicit_contour_estimate_cells(&field, o.bounds, o.res[0], o.res[1], &co, &cells) ==
            GEOM_OK &&
        cells > (double)max_cells) {
        geom_implicit_expr_destroy(e);
        return cli_error(&tool, "the contour would sample %.0f grid cells (computed before the "
                                "work), more than --max-cells %zu; raise --max-cells or lower "
                                "--res", cells, max_cells);
    }
    geom_implicit_isolines c;
    if (geom_implicit_contour(&field, o.bounds, o.res[0], o.res[1], &co, &c, &diag) != GEOM_OK) {
        geom_implicit_expr_destroy(e);
        return cli_print_diag(&tool, &diag);
    }
    double secs = cli_timer_elapsed(&timer);

    geom_status st;
    if (o.format == FMT_SVG) {
        cli_output out;
        st = cli_output_open(&out, to_stdout ? NULL : out_path, &diag);
        if (st == GEOM_OK) {
            write_svg(out.fp, &c, o.bounds);
            st = cli_output_commit(&out, &diag);
        }
    } else {
        st = write_obj(&c, o.z, out_path, &diag);
    }
    if (st != GEOM_OK) {
        geom_implicit_isolines_free(&c);
        geom_implicit_expr_destroy(e);
        return cli_print_diag(&tool, &diag);
    }
    size_t closed = 0;
    for (size_t k = 0; k < c.n_polylines; k++)
        closed += c.closed[k];
    const geom_error_report *er = &c.report.error;
    const geom_implicit_contour_report *rp = &c.report;
    if (rp->nan_nodes)
        fprintf(stderr, "%s: warning: the field is NaN at %zu grid node%s (counted outside, as in "
                        "geom-iso); the first at node (%zu, %zu), point (%.17g, %.17g)\n",
                tool.name, rp->nan_nodes, rp->nan_nodes == 1 ? "" : "s", rp->nan_first[0],
                rp->nan_first[1], rp->nan_point[0], rp->nan_point[1]);
    /* an empty result is a warning (issue 15), on stderr and in --json */
    const int empty = c.n_polylines == 0;
    if (empty)
        fprintf(stderr, "%s: warning: empty result: no isoline (the curve f = %.17g misses the "
                        "box, or the field is NaN there)\n", tool.name, o.iso);
    if (common.json) {
        printf("{\"vertices\":%zu,\"polylines\":%zu,\"closed\":%zu,\"max_error\":", c.n_vertices,
               c.n_polylines, closed);
        cli_json_number(stdout, er->max_error);
        printf(",\"mean_error\":");
        cli_json_number(stdout, er->mean_error);
        printf(",\"seconds\":");
        cli_json_number(stdout, secs);
        printf(",\"error\":");
        cli_json_error_report(stdout, er, "|f - iso| / |grad f| at vertices");
        printf(",\"estimated_vertices\":");
        cli_json_number(stdout, est);
        printf(",\"cells_sampled\":");
        cli_json_number(stdout, cells);
        printf(",\"nan_nodes\":%zu", rp->nan_nodes);
        if (rp->nan_nodes) {
            printf(",\"first_nan\":{\"node\":[%zu,%zu],\"point\":[", rp->nan_first[0],
                   rp->nan_first[1]);
            cli_json_number(stdout, rp->nan_point[0]);
            printf(",");
            cli_json_number(stdout, rp->nan_point[1]);
            printf("]}");
        }
        if (empty || rp->nan_nodes) {
            printf(",\"warnings\":[");
            if (empty)
                printf("\"empty result: no isoline\"%s", rp->nan_nodes ? "," : "");
            if (rp->nan_nodes)
                printf("\"the field is NaN at %zu grid nodes, the first at node (%zu, %zu)\"",
                       rp->nan_nodes, rp->nan_first[0], rp->nan_first[1]);
            printf("]");
        }
        printf("}\n");
    } else {
        FILE *fp = to_stdout ? stderr : stdout;
        fprintf(fp, "vertices %zu\npolylines %zu (%zu closed)\nmax_error %.3g (mean %.3g, "
                    "|f - iso| / |grad f| over vertices)\nseconds %.6f\n",
                c.n_vertices, c.n_polylines, closed, er->max_error, er->mean_error, secs);
    }
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
    return CLI_EXIT_OK;
}
