/* geom-module: iso implicit meshio */
/*
 * geom-iso: isosurface of an expression or of a sampled volume by a
 * topologically correct marching cubes.
 *
 *   geom-iso (--expr E | --volume FILE [--dims X,Y,Z --type T [--skip BYTES]]
 *            [--spacing SX,SY,SZ] [--origin OX,OY,OZ] [--big-endian])
 *            [--bounds X0,Y0,Z0,X1,Y1,Z1 --res N[,NY,NZ]] [--iso V] [--refine]
 *            [--normals] [--caps] [--threads N] [--json] -o OUT.obj
 *
 * --expr: libgeom's expression language (geom/implicit.h), contoured over
 * the box --bounds split into --res cells per axis (required). --volume: a
 * raw file (little-endian, x fastest; --dims and --type required) or, when
 * --dims is absent, NRRD, MetaImage, INRIMAGE or NIfTI-1 (gzip, bzip2; see
 * geom_implicit_volume_read and docs/formats.md); its own samples are the grid
 * nodes (no --bounds or --res needed; given, they resample the volume's
 * trilinear interpolant). Inside is f <= V (--inside below, the default for
 * expressions) or f >= V (--inside above; for volumes the default is
 * detected from the boundary samples). Prints the vertex and triangle
 * counts, the achieved error (for expressions: max of |f - V| / |grad f|
 * over vertices and triangle samples) and the time; --json prints
 * {"vertices", "triangles", "max_error", "seconds", ...}.
 *
 * Exit status 0 on success, 1 on an input, expression or write error, 2 on
 * a usage error.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"
#include "geom/iso.h"
#include "geom/meshio.h"

/* Peak bytes per output triangle for --max-memory: measured 108 at res 600
 * (the extraction's arrays and the mesh built for non-OBJ formats). */
#define ISO_PEAK_BYTES_PER_TRIANGLE 120.0

static const cli_tool tool = {
    "geom-iso",
    "(--expr E | --volume FILE [--dims X,Y,Z --type T]) [OPTION]... -o OUT",
    "Isosurface f = V of the expression E over a box, or of the sampled volume\n"
    "in FILE, by marching cubes reproducing the topology of the trilinear\n"
    "interpolant in every cell, written to OUT (OBJ, OFF, PLY, STL or GLB, from\n"
    "the extension; standard output when OUT is '-': then OBJ).",
    "  -e, --expr=E         the function, e.g. 'torus(1, 0.3)'; inside is f <= V\n"
    "      --volume=FILE    a volume: NRRD (.nrrd, .nhdr), MetaImage (.mha, .mhd),\n"
    "                       INRIMAGE (.inr), NIfTI-1 (.nii), each also gzipped\n"
    "                       or bzip2ed, with spacing and origin from the\n"
    "                       header (unknown spacing: 1, warned); or raw\n"
    "                       samples with --dims and --type\n"
    "      --dims=X,Y,Z     samples per axis of a raw volume\n"
    "      --type=T         the raw samples' type: u8, i8, u16, i16, u32, i32,\n"
    "                       f32, f64\n"
    "      --skip=BYTES     header bytes before the raw samples (default 0)\n"
    "      --spacing=SX,SY,SZ  sample spacing of a raw volume (default 1,1,1)\n"
    "      --origin=OX,OY,OZ   position of the first sample (default 0,0,0)\n"
    "      --big-endian     the raw samples are big-endian\n"
    "  -b, --bounds=X0,Y0,Z0,X1,Y1,Z1  the box (required with --expr)\n"
    "  -r, --res=N[,NY,NZ]  cells per axis (required with --expr; NY = NZ = N\n"
    "                       when omitted), at most 100000\n"
    "  -i, --iso=V          the isovalue (default 0)\n"
    "      --refine         refine vertices on their edges by root finding\n"
    "                       (expressions only)\n"
    "  -n, --normals        write vertex normals (exact gradient for expressions,\n"
    "                       central differences for volumes)\n"
    "      --caps           close the surface against the box where it leaves it\n"
    "      --inside=SIDE    below (f <= V is inside; the default for --expr) or\n"
    "                       above (f >= V, e.g. CT: dense inside); for --volume\n"
    "                       the default is detected: above when most samples on\n"
    "                       the volume's boundary lie below V\n"
    "      --dense          sample every grid node (default: skip the 8^3-cell\n"
    "                       blocks the surface provably misses, by interval\n"
    "                       bounds of the expression or a volume's block\n"
    "                       min/max; the output is identical)\n"
    "  -t, --threads=N      threads (default: all; the result is the same)\n"
    CLI_LIMIT_HELP,
    "The summary (vertices, triangles, max_error, seconds) goes to standard\n"
    "output, or to standard error when the mesh does. With --json it is a JSON\n"
    "object on standard output with the keys vertices, triangles, max_error,\n"
    "seconds, mean_error, vertex_max_error, cap_triangles, tunnels,\n"
    "ambiguous_faces, cells_evaluated, blocks, blocks_skipped, error_stride,\n"
    "signed_volume, inside (OUT must then be a file). max_error is null for volumes\n"
    "(their interpolant is what is contoured).\n",
    "  geom-iso --expr \"torus(1, 0.3)\" --bounds -2,-2,-1,2,2,1 --res 128 --normals -o torus.glb\n"
    "  geom-iso --volume liver.inr.gz --iso 100 -o liver.obj\n",
};

enum {
    OPT_VOLUME = CLI_OPT_TOOL_BASE,
    OPT_DIMS,
    OPT_TYPE,
    OPT_SPACING,
    OPT_ORIGIN,
    OPT_BIG_ENDIAN,
    OPT_SKIP,
    OPT_REFINE,
    OPT_CAPS,
    OPT_INSIDE,
    OPT_DENSE
};

typedef struct iso_args {
    const char *expr, *volume;
    int have_dims, have_type, have_bounds, have_res;
    size_t dims[3];
    geom_implicit_sample type;
    double skip;
    double spacing[3], origin[3], bounds[6];
    size_t res[3];
    double iso;
    int refine, normals, caps, threads, big_endian, dense;
    int inside; /* -1: not given, else GEOM_ISO_INSIDE_* */
    cli_limits lim;
} iso_args;

/* Parse exactly n numbers (or 1 or n when one_or_n) separated by commas. */
static int parse_list(const char *arg, double *out, size_t n, int one_or_n)
{
    size_t count = 0;
    if (cli_parse_numbers(arg, strlen(arg), 0, out, n, &count, NULL) != GEOM_OK)
        return 0;
    if (count == n)
        return 1;
    if (one_or_n && count == 1) {
        for (size_t i = 1; i < n; i++)
            out[i] = out[0];
        return 1;
    }
    return 0;
}

static int parse_sizes(const char *arg, size_t *out, int one_or_three, size_t max)
{
    double v[3];
    if (!parse_list(arg, v, 3, one_or_three))
        return 0;
    for (int a = 0; a < 3; a++) {
        if (!(v[a] >= 1) || v[a] > (double)max || v[a] != floor(v[a]))
            return 0;
        out[a] = (size_t)v[a];
    }
    return 1;
}

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    iso_args *a = user;
    int lrc = cli_limits_option(t, &a->lim, opt, arg);
    if (lrc != CLI_NOT_HANDLED)
        return lrc;
    switch (opt) {
    case 'e':
        a->expr = arg;
        return CLI_CONTINUE;
    case OPT_VOLUME:
        a->volume = arg;
        return CLI_CONTINUE;
    case OPT_DIMS:
        if (!parse_sizes(arg, a->dims, 0, (size_t)1 << 31))
            return cli_usage_error(t, "--dims takes three positive integers X,Y,Z, not '%s'", arg);
        a->have_dims = 1;
        return CLI_CONTINUE;
    case OPT_TYPE:
        if (geom_implicit_sample_parse(arg, &a->type) != GEOM_OK)
            return cli_usage_error(t, "--type takes u8, i8, u16, i16, u32, i32, f32 or f64, not "
                                      "'%s'", arg);
        a->have_type = 1;
        return CLI_CONTINUE;
    case OPT_SKIP:
        if (cli_parse_double(arg, strlen(arg), 0, &a->skip, NULL) != GEOM_OK || !(a->skip >= 0) ||
            a->skip != floor(a->skip) || a->skip > 9e15)
            return cli_usage_error(t, "--skip takes a byte count >= 0, not '%s'", arg);
        return CLI_CONTINUE;
    case OPT_SPACING:
        if (!parse_list(arg, a->spacing, 3, 0) || !(a->spacing[0] > 0) || !(a->spacing[1] > 0) ||
            !(a->spacing[2] > 0))
            return cli_usage_error(t, "--spacing takes three positive numbers, not '%s'", arg);
        return CLI_CONTINUE;
    case OPT_ORIGIN:
        if (!parse_list(arg, a->origin, 3, 0))
            return cli_usage_error(t, "--origin takes three numbers X,Y,Z, not '%s'", arg);
        return CLI_CONTINUE;
    case OPT_BIG_ENDIAN:
        a->big_endian = 1;
        return CLI_CONTINUE;
    case 'b':
        if (!parse_list(arg, a->bounds, 6, 0) || !(a->bounds[0] < a->bounds[3]) ||
            !(a->bounds[1] < a->bounds[4]) || !(a->bounds[2] < a->bounds[5]))
            return cli_usage_error(
                t, "--bounds takes X0,Y0,Z0,X1,Y1,Z1 with X0 < X1, Y0 < Y1, Z0 < Z1, not '%s'",
                arg);
        a->have_bounds = 1;
        return CLI_CONTINUE;
    case 'r':
        if (!parse_sizes(arg, a->res, 1, 100000))
            return cli_usage_error(t, "--res takes N or N,NY,NZ (1 to 100000), not '%s'", arg);
        a->have_res = 1;
        return CLI_CONTINUE;
    case 'i':
        if (cli_parse_double(arg, strlen(arg), 0, &a->iso, NULL) != GEOM_OK)
            return cli_usage_error(t, "--iso takes a finite number, not '%s'", arg);
        return CLI_CONTINUE;
    case OPT_REFINE:
        a->refine = 1;
        return CLI_CONTINUE;
    case 'n':
        a->normals = 1;
        return CLI_CONTINUE;
    case OPT_CAPS:
        a->caps = 1;
        return CLI_CONTINUE;
    case OPT_DENSE:
        a->dense = 1;
        return CLI_CONTINUE;
    case OPT_INSIDE:
        if (strcmp(arg, "below") == 0)
            a->inside = GEOM_ISO_INSIDE_BELOW;
        else if (strcmp(arg, "above") == 0)
            a->inside = GEOM_ISO_INSIDE_ABOVE;
        else
            return cli_usage_error(t, "--inside takes below or above, not '%s'", arg);
        return CLI_CONTINUE;
    case 't': {
        double v;
        if (cli_parse_double(arg, strlen(arg), 0, &v, NULL) != GEOM_OK || !(v >= 1) ||
            v > 4096 || v != floor(v))
            return cli_usage_error(t, "--threads takes an integer from 1 to 4096, not '%s'", arg);
        a->threads = (int)v;
        return CLI_CONTINUE;
    }
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

static geom_status stdout_write(void *user, const void *data, size_t size)
{
    return fwrite(data, 1, size, (FILE *)user) == size ? GEOM_OK : GEOM_ERR_IO;
}

/* OBJ written chunk by chunk as the extraction hands them over
 * (geom_iso_extract_stream): no array of the whole surface, and each
 * chunk's v lines before its f lines (the mesh read back is the one
 * geom_iso_extract makes). */
typedef struct obj_stream {
    cli_output out;
    int started; /* the header line is written */
    geom_diag wdiag; /* the writer's message, when it fails */
} obj_stream;

static geom_status write_part(obj_stream *w, const geom_meshio_soup *soup, size_t first)
{
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    geom_status st = geom_meshio_write_soup_part(soup, first, !w->started, &wo, stdout_write,
                                                 w->out.fp, &w->wdiag);
    w->started = 1;
    return st;
}

static geom_status write_chunk(void *user, const geom_iso_chunk *ch)
{
    geom_meshio_soup soup = {ch->n_vertices, ch->xyz, ch->normals, ch->n_triangles, NULL,
                             ch->tris};
    return write_part(user, &soup, ch->first_vertex);
}

static geom_status extract_to_obj(const geom_iso_field *f, const double bounds[6],
                                  const size_t res[3], const geom_iso_options *o,
                                  const char *path, geom_iso_surface *s, geom_diag *diag)
{
    obj_stream w;
    memset(&w, 0, sizeof w);
    geom_diag_clear(&w.wdiag);
    int to_stdout = strcmp(path, "-") == 0;
    geom_status st = cli_output_open(&w.out, to_stdout ? NULL : path, diag);
    if (st != GEOM_OK)
        return st;
    st = geom_iso_extract_stream(f, bounds, res, o, write_chunk, &w, s, diag);
    if (st == GEOM_OK && !w.started) { /* an empty surface: the header line only */
        geom_meshio_soup none = {0, NULL, NULL, 0, NULL, NULL};
        st = write_part(&w, &none, 0);
    }
    if (st != GEOM_OK && w.wdiag.status != GEOM_OK)
        *diag = w.wdiag; /* the writer's reason, not the extraction's summary */
    if (st == GEOM_OK)
        return cli_output_commit(&w.out, diag);
    if (to_stdout && ferror(w.out.fp)) {
        /* a write error is reported as for every tool's output */
        geom_diag_clear(diag);
        geom_status cst = cli_output_commit(&w.out, diag);
        return cst != GEOM_OK ? cst : st;
    }
    cli_output_abort(&w.out);
    return st;
}

static geom_status write_surface(const geom_iso_surface *s, const char *path, bool up_z,
                                 geom_diag *diag)
{
    int to_stdout = strcmp(path, "-") == 0;
    if (to_stdout || geom_meshio_format_from_name(path) == GEOM_MESHIO_FORMAT_OBJ) {
        /* OBJ: written straight from the extraction's arrays, without a
         * half-edge mesh (the same bytes) */
        geom_meshio_soup soup;
        memset(&soup, 0, sizeof soup);
        soup.n_vertices = s->n_vertices;
        soup.xyz = s->xyz;
        soup.normals = s->normals;
        soup.n_faces = s->n_triangles;
        soup.indices = s->tris;
        geom_meshio_write_options wo;
        memset(&wo, 0, sizeof wo);
        wo.format = GEOM_MESHIO_FORMAT_OBJ;
        if (!to_stdout)
            return geom_meshio_write_soup(&soup, path, &wo, diag);
        cli_output out;
        geom_status st = cli_output_open(&out, NULL, diag);
        if (st == GEOM_OK) {
            st = geom_meshio_write_soup_stream(&soup, &wo, stdout_write, out.fp, diag);
            if (st == GEOM_OK || ferror(out.fp)) {
                /* a write error is reported as for every tool's output */
                geom_diag_clear(diag);
                geom_status cst = cli_output_commit(&out, diag);
                st = st == GEOM_OK ? cst : (cst != GEOM_OK ? cst : st);
            } else
                cli_output_abort(&out);
        }
        return st;
    }
    geom_mesh *m = geom_mesh_create(NULL);
    if (!m)
        return cli_diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
    geom_status st = geom_iso_surface_to_mesh(s, m, diag);
    if (st == GEOM_OK) {
        geom_meshio_write_options wo;
        memset(&wo, 0, sizeof wo);
        wo.gltf_z_up = up_z;
        st = geom_meshio_write(m, path, &wo, diag);
    }
    geom_mesh_destroy(m);
    return st;
}

/* Samples on the volume's boundary (its six faces) below iso, and in all. */
static void iso_progress(void *user, double fraction)
{
    cli_progress_update(user, fraction);
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"expr", required_argument, NULL, 'e'},
                                             {"volume", required_argument, NULL, OPT_VOLUME},
                                             {"dims", required_argument, NULL, OPT_DIMS},
                                             {"type", required_argument, NULL, OPT_TYPE},
                                             {"spacing", required_argument, NULL, OPT_SPACING},
                                             {"origin", required_argument, NULL, OPT_ORIGIN},
                                             {"big-endian", no_argument, NULL, OPT_BIG_ENDIAN},
                                             {"skip", required_argument, NULL, OPT_SKIP},
                                             {"bounds", required_argument, NULL, 'b'},
                                             {"res", required_argument, NULL, 'r'},
                                             {"iso", required_argument, NULL, 'i'},
                                             {"refine", no_argument, NULL, OPT_REFINE},
                                             {"normals", no_argument, NULL, 'n'},
                                             {"caps", no_argument, NULL, OPT_CAPS},
                                             {"inside", required_argument, NULL, OPT_INSIDE},
                                             {"dense", no_argument, NULL, OPT_DENSE},
                                             {"threads", required_argument, NULL, 't'},
                                             CLI_LIMIT_LONGOPTS,
                                             {NULL, 0, NULL, 0}};
    iso_args a;
    memset(&a, 0, sizeof a);
    a.inside = -1;
    a.spacing[0] = a.spacing[1] = a.spacing[2] = 1;
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "e:b:r:i:nt:", longopts, on_option, &a, &common,
                            &first);
    if (rc != CLI_CONTINUE)
        return rc;
    if (first < argc)
        return cli_usage_error(&tool, "unexpected operand '%s'", argv[first]);
    if (!a.expr == !a.volume)
        return cli_usage_error(&tool, "give exactly one of --expr and --volume");
    if (a.expr && (!a.have_bounds || !a.have_res))
        return cli_usage_error(&tool, "--expr needs --bounds and --res");
    if (a.have_bounds != a.have_res)
        return cli_usage_error(&tool, "--bounds and --res go together");
    if (a.volume && a.have_dims != a.have_type)
        return cli_usage_error(&tool, "a raw volume needs both --dims and --type");
    if (a.expr && (a.have_dims || a.have_type))
        return cli_usage_error(&tool, "--dims and --type apply to --volume only");
    if (a.skip > 0 && !a.have_dims)
        return cli_usage_error(&tool, "--skip applies to raw volumes (with --dims and --type)");
    const char *out_path = common.output ? common.output : "-";
    int to_stdout = strcmp(out_path, "-") == 0;
    if (!to_stdout && geom_meshio_format_from_name(out_path) == GEOM_MESHIO_FORMAT_AUTO)
        return cli_usage_error(&tool, "cannot tell the output format from '%s'", out_path);
    if (common.json && to_stdout)
        return cli_usage_error(&tool, "--json needs the mesh written to a file (-o OUT)");

    geom_diag diag;
    geom_diag_clear(&diag);
    cli_timer timer;
    cli_timer_start(&timer);
    geom_implicit_expr *expr = NULL;
    geom_implicit_volume *vol = NULL;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.iso = a.iso;
    o.refine = a.refine ? GEOM_IMPLICIT_REFINE_AUTO : GEOM_IMPLICIT_REFINE_NEVER;
    o.normals = a.normals;
    o.caps = a.caps;
    o.threads = a.threads;
    o.dense = a.dense;
    o.inside = a.inside < 0 ? GEOM_ISO_INSIDE_BELOW : a.inside;
    cli_progress prog; /* percent and ETA on a terminal, per slab extracted */
    cli_progress_start(&prog, &tool, "extracting", common.quiet);
    if (prog.enabled) {
        o.progress = iso_progress;
        o.progress_user = &prog;
    }
    int detected = 0;
    char spacing_warning[GEOM_DIAG_MESSAGE_MAX] = ""; /* the volume's spacing read as 1 */
    size_t nb_below = 0, nb_total = 0;
    /* an expression's OBJ is written while the surface is extracted */
    int obj_out = to_stdout || geom_meshio_format_from_name(out_path) == GEOM_MESHIO_FORMAT_OBJ;
    int streamed = 0;
    geom_iso_surface s;
    memset(&s, 0, sizeof s);
    geom_status st;
    if (a.expr) {
        st = geom_implicit_expr_compile(a.expr, strlen(a.expr), NULL, &expr, &diag);
        if (st != GEOM_OK)
            return cli_print_diag(&tool, &diag);
        geom_iso_field f;
        st = geom_iso_field_from_expr(expr, &f);
        double est = 0.0;
        if (st == GEOM_OK && geom_iso_estimate_triangles(&f, a.bounds, a.res, &o, &est) ==
                                 GEOM_OK &&
            cli_limits_check(&tool, &a.lim, "the isosurface", est, est * ISO_PEAK_BYTES_PER_TRIANGLE) != CLI_CONTINUE) {
            geom_implicit_expr_destroy(expr);
            return CLI_EXIT_ERROR;
        }
        if (st == GEOM_OK && obj_out) {
            st = extract_to_obj(&f, a.bounds, a.res, &o, out_path, &s, &diag);
            streamed = 1;
        } else if (st == GEOM_OK)
            st = geom_iso_extract(&f, a.bounds, a.res, &o, &s, &diag);
    } else {
        geom_implicit_volume_read_options ro;
        memset(&ro, 0, sizeof ro);
        if (a.have_dims) {
            ro.format = GEOM_IMPLICIT_VOLUME_RAW;
            for (int k = 0; k < 3; k++) {
                ro.dims[k] = a.dims[k];
                ro.spacing[k] = a.spacing[k];
                ro.origin[k] = a.origin[k];
            }
            ro.sample = a.type;
            ro.big_endian = a.big_endian;
            ro.skip = (uint64_t)a.skip;
        }
        ro.inflate = cli_inflate;
        ro.bunzip2 = cli_have_bunzip2() ? cli_bunzip2 : NULL;
        geom_implicit_volume_file_info vinfo;
        st = geom_implicit_volume_read(a.volume, &ro, NULL, &vol, &vinfo, &diag);
        if (st != GEOM_OK)
            return cli_print_diag(&tool, &diag);
        if (vinfo.spacing_note[0]) { /* an axis in vinfo.spacing_defaulted */
            snprintf(spacing_warning, sizeof spacing_warning, "%s", vinfo.spacing_note);
            fprintf(stderr, "%s: warning: %s: %s\n", tool.name, a.volume, spacing_warning);
        }
        if (a.inside < 0) {
            int above = 0;
            geom_implicit_volume_detect_inside(vol, a.iso, &above, &nb_below, &nb_total);
            detected = 1;
            o.inside = above ? GEOM_ISO_INSIDE_ABOVE : GEOM_ISO_INSIDE_BELOW;
        }
        if (a.have_bounds) {
            geom_iso_field f;
            st = geom_iso_field_from_volume(vol, &f);
            double est = 0.0;
            if (st == GEOM_OK && geom_iso_estimate_triangles(&f, a.bounds, a.res, &o, &est) ==
                                     GEOM_OK &&
                cli_limits_check(&tool, &a.lim, "the isosurface", est, est * ISO_PEAK_BYTES_PER_TRIANGLE) !=
                    CLI_CONTINUE) {
                geom_implicit_volume_destroy(vol);
                return CLI_EXIT_ERROR;
            }
            if (st == GEOM_OK)
                st = geom_iso_extract(&f, a.bounds, a.res, &o, &s, &diag);
        } else {
            geom_iso_grid g;
            st = geom_iso_grid_from_volume(vol, &g);
            double est = 0.0;
            if (st == GEOM_OK && geom_iso_grid_estimate_triangles(&g, &o, &est) == GEOM_OK &&
                cli_limits_check(&tool, &a.lim, "the isosurface", est, est * ISO_PEAK_BYTES_PER_TRIANGLE) !=
                    CLI_CONTINUE) {
                geom_implicit_volume_destroy(vol);
                return CLI_EXIT_ERROR;
            }
            if (st == GEOM_OK)
                st = geom_iso_extract_grid(&g, &o, &s, &diag);
        }
    }
    cli_progress_done(&prog);
    if (st != GEOM_OK) {
        geom_implicit_expr_destroy(expr);
        geom_implicit_volume_destroy(vol);
        if (diag.status == GEOM_OK)
            cli_diag_set(&diag, st, NULL, 0, 0, "%s", geom_status_str(st));
        return cli_print_diag(&tool, &diag);
    }
    double secs = s.report.seconds;
    if (!streamed)
        st = write_surface(&s, out_path, common.up_z, &diag);
    double total = cli_timer_elapsed(&timer);
    if (st != GEOM_OK) {
        geom_iso_surface_free(&s);
        geom_implicit_expr_destroy(expr);
        geom_implicit_volume_destroy(vol);
        return cli_print_diag(&tool, &diag);
    }
    const geom_iso_report *r = &s.report;
    int measured = r->vertex_error.method != GEOM_ERROR_NONE;
    double maxe = measured ? fmax(r->vertex_error.max_error, r->sample_error.max_error) : NAN;
    double meane = measured ? r->sample_error.mean_error : NAN;
    if (s.n_triangles == 0)
        fprintf(stderr, "%s: warning: empty isosurface: no triangles (the surface f = %.17g "
                        "misses the box, or the field is NaN there)\n",
                tool.name, a.iso);
    if (r->nan_nodes)
        fprintf(stderr, "%s: warning: the field is NaN at %zu grid node%s (counted outside); the "
                        "first at node (%zu, %zu, %zu), point (%.17g, %.17g, %.17g)\n",
                tool.name, r->nan_nodes, r->nan_nodes == 1 ? "" : "s", r->nan_first[0],
                r->nan_first[1], r->nan_first[2], r->nan_point[0], r->nan_point[1],
                r->nan_point[2]);
    if (common.json) {
        printf("{\"vertices\":%zu,\"triangles\":%zu,\"max_error\":", s.n_vertices, s.n_triangles);
        cli_json_number(stdout, maxe);
        printf(",\"seconds\":");
        cli_json_number(stdout, secs);
        printf(",\"mean_error\":");
        cli_json_number(stdout, meane);
        printf(",\"vertex_max_error\":");
        cli_json_number(stdout, measured ? r->vertex_error.max_error : NAN);
        printf(",\"cap_triangles\":%zu,\"tunnels\":%zu,\"ambiguous_faces\":%zu,"
               "\"iso_nodes\":%zu,\"cells\":%zu,\"cells_evaluated\":%zu,\"blocks\":%zu,"
               "\"blocks_skipped\":%zu,\"error_stride\":%zu,\"total_seconds\":",
               s.n_cap_triangles, r->tunnels, r->ambiguous_faces, r->iso_nodes, r->cells,
               r->cells_evaluated, r->blocks, r->blocks_skipped, r->error_stride);
        cli_json_number(stdout, total);
        printf(",\"signed_volume\":");
        cli_json_number(stdout, r->signed_volume);
        printf(",\"error\":");
        cli_json_error_report(stdout, &r->error, "|f - iso| / |grad f| at vertices and triangle samples");
        printf(",\"inside\":\"%s\",\"inside_detected\":%s",
               o.inside == GEOM_ISO_INSIDE_ABOVE ? "above" : "below", detected ? "true" : "false");
        printf(",\"nan_nodes\":%zu", r->nan_nodes);
        if (r->nan_nodes) {
            printf(",\"first_nan\":{\"node\":[%zu,%zu,%zu],\"point\":[", r->nan_first[0],
                   r->nan_first[1], r->nan_first[2]);
            for (int q = 0; q < 3; q++) {
                if (q)
                    printf(",");
                cli_json_number(stdout, r->nan_point[q]);
            }
            printf("]}");
        }
        if (s.n_triangles == 0 || r->nan_nodes || spacing_warning[0]) {
            printf(",\"warnings\":[");
            if (s.n_triangles == 0)
                printf("\"empty isosurface: no triangles\"%s",
                       r->nan_nodes || spacing_warning[0] ? "," : "");
            if (r->nan_nodes)
                printf("\"the field is NaN at %zu grid nodes, the first at node "
                       "(%zu, %zu, %zu)\"%s",
                       r->nan_nodes, r->nan_first[0], r->nan_first[1], r->nan_first[2],
                       spacing_warning[0] ? "," : "");
            if (spacing_warning[0])
                cli_json_string(stdout, spacing_warning);
            printf("]");
        }
        printf("}\n");
    } else {
        FILE *fp = to_stdout ? stderr : stdout;
        fprintf(fp, "vertices %zu\ntriangles %zu\n", s.n_vertices, s.n_triangles);
        if (measured && r->error_stride > 1)
            fprintf(fp,
                    "max_error %.6g (|f - iso| / |grad f|, max over every %zu-th vertex and "
                    "triangle (centroid, edge midpoints): %zu points; vertices %.6g, mean "
                    "%.6g; %.3g s)\n",
                    maxe, r->error_stride, r->error.pieces, r->vertex_error.max_error, meane,
                    r->error_seconds);
        else if (measured)
            fprintf(fp,
                    "max_error %.6g (|f - iso| / |grad f|, max over vertices and triangle "
                    "samples; vertices %.6g, mean %.6g; %.3g s)\n",
                    maxe, r->vertex_error.max_error, meane, r->error_seconds);
        else
            fprintf(fp, "max_error not measured (sampled volume)\n");
        fprintf(fp, "signed_volume %.6g (inside %s%s)\n", r->signed_volume,
                o.inside == GEOM_ISO_INSIDE_ABOVE ? "above: f >= iso" : "below: f <= iso",
                detected ? (o.inside == GEOM_ISO_INSIDE_ABOVE
                                ? ", detected: most boundary samples lie below the iso value"
                                : ", detected: most boundary samples lie above the iso value")
                         : "");
        if (detected)
            fprintf(fp, "boundary samples below iso %zu of %zu\n", nb_below, nb_total);
        if (r->blocks)
            fprintf(fp, "cells_evaluated %zu of %zu (%zu of %zu blocks skipped)\n",
                    r->cells_evaluated, r->cells, r->blocks_skipped, r->blocks);
        else
            fprintf(fp, "cells_evaluated %zu of %zu (dense)\n", r->cells_evaluated, r->cells);
        fprintf(fp, "seconds %.6g (extraction%s; %.6g in all)\n", secs,
                streamed ? " and OBJ output" : "", total);
    }
    geom_iso_surface_free(&s);
    geom_implicit_expr_destroy(expr);
    geom_implicit_volume_destroy(vol);
    return CLI_EXIT_OK;
}
