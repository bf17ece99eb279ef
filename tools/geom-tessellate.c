/* geom-module: surface meshio step */
/*
 * geom-tessellate: tessellate Bezier, B-spline and NURBS surfaces to a mesh.
 *
 *   geom-tessellate IN.json|IN.bpt|IN.step|IN.stp -o OUT.obj [--tol T | --grid NU,NV]
 *                   [--normals] [--uvs] [--tangents] [--json]
 *
 * IN is a JSON file {"curves": [...], "surfaces": [...]} (see
 * tools/surface_json.h; needs cJSON at build time) or a .bpt Bezier patch
 * file (Newell's teapot format); the format comes from the extension, else
 * from the content ('{' first: JSON). All its surfaces are tessellated
 * together with geom_surface_tessellate, so patches that share edges are
 * welded without cracks. Adaptive to a chordal tolerance by default
 * (--tol, default 1e-3 of the control points' box diagonal), or uniform
 * (--grid NU,NV quads per knot span, or per surface with --per-surface).
 * Only the attributes asked for are written (--normals: analytic normals,
 * welded across patch seams where they agree within --normal-weld degrees;
 * --uvs: surface parameters; --tangents: MikkTSpace tangent frames, or
 * dP/du with --tangents=dpdu, to the formats that hold tangents: GLB and
 * PLY; OBJ, OFF and STL cannot, which is a usage error). OUT's format comes from its extension (obj, ply, off, stl,
 * glb); "-" writes OBJ to standard output.
 *
 * The report -- the achieved chordal error (the largest distance between a
 * triangle and the exact surface at its parameter-space position, sampled),
 * the triangle count and the time -- goes to standard output (standard
 * error when the mesh does), as "key: value" lines or, with --json, one
 * object with at least max_error, triangles and seconds.
 *
 * Exit status 0 on success, 1 on a read, parse, tessellation or write error,
 * 2 on a usage error.
 */
#include "cli.h"
#include "cli_mesh.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"
#include "geom/surface.h"
#include "geom/step.h"
#ifdef GEOM_HAVE_CJSON
#include "surface_json.h"
#endif

static const cli_tool tool = {
    "geom-tessellate",
    "[OPTION]... IN.json|IN.bpt|IN.step|IN.stp -o OUT",
    "Tessellate the Bezier, B-spline and NURBS surfaces in IN (JSON or .bpt\n"
    "Bezier patches) into one crack-free triangle mesh and write it to OUT.\n"
    "A STEP file (.step/.stp, ISO 10303-21) is read as a B-rep and its trimmed\n"
    "faces tessellated into one watertight mesh (closed solids stay closed);\n"
    "GLB output is turned from STEP's Z-up to glTF's Y-up.",
    "  -t, --tol=T          adaptive: chordal tolerance (absolute; default 1e-3\n"
    "                       times the diagonal of the control points' box)\n"
    "  -a, --angle=DEG      adaptive: also keep the normals at the corners of\n"
    "                       every triangle within DEG degrees of each other\n"
    "  -g, --grid=NU,NV     uniform: NU x NV quads per knot span (Bezier patch)\n"
    "      --per-surface    uniform: the grid spans each whole surface\n"
    "      --per-face       STEP input: each B-rep face an OBJ group face<#id>\n"
    "  -n, --normals        write analytic normals\n"
    "  -u, --uvs            write texture coordinates (the surface parameters)\n"
    "      --uv-normalized  texture coordinates normalised to [0,1] per surface\n"
    "      --tangents[=KIND]  write tangents (GLB, PLY; OBJ, OFF and STL cannot\n"
    "                       hold them): mikk (default) MikkTSpace tangent frames\n"
    "                       for normal maps, with normals and UVs (implied);\n"
    "                       dpdu: the surface derivative dP/du, w = +-1\n"
    "      --no-weld        do not weld surfaces along shared edges\n"
    "      --normal-weld=DEG  one normal for the corners of a vertex whose patch\n"
    "                       normals are within DEG degrees (default 0.01; 0: never)\n"
    "  -f, --format=FMT     output format (obj, off, ply, stl, glb); default: from\n"
    "                       OUT's extension\n"
    CLI_MTLLIB_HELP
    CLI_LIMIT_HELP,
    "Prints max_error (sampled chordal error: the largest distance from the\n"
    "surface, at 12 points per triangle, to the mesh there), mean_error,\n"
    "triangles, vertices, surfaces and seconds (tessellation time); adaptive\n"
    "runs also print the per-span uniform grid when one with fewer triangles\n"
    "met the tolerance and was written instead. With --json one object with\n"
    "those keys and a few counts (welded_edges, collapsed_edges,\n"
    "flipped_surfaces, evaluations, tolerance, mode, uniform_grid).\n",
    "  geom-tessellate data/teapot.bpt --tol 1e-3 --normals -o teapot.glb\n"
    "  geom-tessellate data/surfaces.json --grid 16,16 --uvs -o surfaces.obj\n",
};

enum {
    OPT_PER_SURFACE = CLI_OPT_TOOL_BASE,
    OPT_UV_NORMALIZED,
    OPT_TANGENTS,
    OPT_NO_WELD,
    OPT_PER_FACE,
    OPT_NORMAL_WELD
};

typedef struct tess_opts {
    geom_surface_tess_options to;
    int have_tol, have_grid;
    geom_meshio_format format;
    cli_limits lim;
    int per_face; /* STEP input: face ids as OBJ groups */
    int tangents; /* 0: none, 1: MikkTSpace (geom_mesh_tangents), 2: dP/du */
} tess_opts;

/* Progress of geom_surface_tessellate: a pass restarts the fraction, and
 * the display with "pass N" (the last pass, the output, is the largest). */
typedef struct tess_progress {
    cli_progress bar;
    double last;
    int pass;
    char label[48];
} tess_progress;

static void on_progress(void *user, double fraction)
{
    tess_progress *p = user;
    if (fraction < p->last) {
        p->pass++;
        snprintf(p->label, sizeof p->label, "tessellating, pass %d", p->pass + 1);
        /* restarted: the ETA of this pass from its own start */
        bool shown = p->bar.shown;
        cli_progress_start(&p->bar, &tool, p->label, !p->bar.enabled);
        p->bar.shown = shown;
    }
    p->last = fraction;
    cli_progress_update(&p->bar, fraction);
}

static int parse_positive(const char *arg, double *out)
{
    return cli_parse_double(arg, strlen(arg), 0, out, NULL) == GEOM_OK && *out > 0.0;
}

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    tess_opts *o = user;
    int mrc = cli_mesh_mtllib_option(t, opt, arg);
    if (mrc != CLI_NOT_HANDLED)
        return mrc;
    double d;
    int lrc = cli_limits_option(t, &o->lim, opt, arg);
    if (lrc != CLI_NOT_HANDLED)
        return lrc;
    switch (opt) {
    case 't':
        if (!parse_positive(arg, &d))
            return cli_usage_error(t, "--tol takes a positive number, not '%s'", arg);
        o->to.tolerance = d;
        o->have_tol = 1;
        return CLI_CONTINUE;
    case 'a':
        if (!parse_positive(arg, &d) || !(d < 180.0))
            return cli_usage_error(t, "--angle takes degrees in (0, 180), not '%s'", arg);
        o->to.angle_degrees = d;
        return CLI_CONTINUE;
    case 'g': {
        const char *comma = strchr(arg, ',');
        double a, b;
        if (!comma ||
            cli_parse_double(arg, (size_t)(comma - arg), 0, &a, NULL) != GEOM_OK ||
            cli_parse_double(comma + 1, strlen(comma + 1), 0, &b, NULL) != GEOM_OK ||
            a != (int)a || b != (int)b || a < 1 || b < 1 || a > 65536 || b > 65536)
            return cli_usage_error(t, "--grid takes NU,NV (integers 1..65536), not '%s'", arg);
        o->to.grid_u = (int)a;
        o->to.grid_v = (int)b;
        o->have_grid = 1;
        return CLI_CONTINUE;
    }
    case OPT_PER_SURFACE:
        o->to.per_surface = 1;
        return CLI_CONTINUE;
    case 'n':
        o->to.attributes |= GEOM_SURFACE_ATTR_NORMAL;
        return CLI_CONTINUE;
    case 'u':
        o->to.attributes |= GEOM_SURFACE_ATTR_UV;
        return CLI_CONTINUE;
    case OPT_UV_NORMALIZED:
        o->to.attributes |= GEOM_SURFACE_ATTR_UV;
        o->to.uv_normalized = 1;
        return CLI_CONTINUE;
    case OPT_TANGENTS:
        if (!arg || strcmp(arg, "mikk") == 0) {
            o->tangents = 1;
        } else if (strcmp(arg, "dpdu") == 0) {
            o->tangents = 2;
            o->to.attributes |= GEOM_SURFACE_ATTR_TANGENT;
        } else {
            return cli_usage_error(t, "--tangents takes mikk or dpdu, not '%s'", arg);
        }
        return CLI_CONTINUE;
    case OPT_NO_WELD:
        o->to.no_weld = 1;
        return CLI_CONTINUE;
    case OPT_PER_FACE:
        o->per_face = 1;
        return CLI_CONTINUE;
    case OPT_NORMAL_WELD:
        if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || !(d >= 0.0) ||
            !(d < 180.0))
            return cli_usage_error(t, "--normal-weld takes degrees in [0, 180), not '%s'", arg);
        o->to.normal_weld_degrees = d > 0.0 ? d : -1.0;
        return CLI_CONTINUE;
    case 'f':
        return cli_mesh_format_option(t, arg, 0, &o->format);
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

/* Surfaces from IN: JSON or .bpt. */
static geom_status read_surfaces(const char *path, geom_surface_set **set, geom_diag *diag)
{
    cli_input in;
    geom_status st = cli_input_open(&in, path, diag);
    if (st != GEOM_OK)
        return st;
    const char *name = in.name;
    geom_file file;
    st = cli_read_all(in.fp, name, &file, diag);
    cli_input_close(&in);
    if (st != GEOM_OK)
        return st;
    const char *data = (const char *)file.data;
    size_t size = file.size;
    int json;
    if (cli_ends_with(path, ".json"))
        json = 1;
    else if (cli_ends_with(path, ".bpt"))
        json = 0;
    else {
        size_t i = 0;
        while (i < size && isspace((unsigned char)data[i]))
            ++i;
        json = i < size && data[i] == '{';
    }
    if (json) {
#ifdef GEOM_HAVE_CJSON
        sj_file f;
        st = sj_read_memory(data, size, name, &f, diag);
        if (st == GEOM_OK) {
            *set = f.surfaces;
            f.surfaces = NULL;
            sj_free(&f);
        }
#else
        st = cli_diag_set(diag, GEOM_ERR_INVALID_ARG, name, 0, 0,
                          "JSON input needs cJSON, which this build does not have");
#endif
    } else {
        st = geom_surface_read_bpt_memory(data, size, name, NULL, set, diag);
    }
    geom_file_unmap(&file);
    return st;
}

/* ----------------------------------------------------------- STEP input */

/* Peak bytes per triangle of a STEP tessellation: measured about 200
 * (data/sphere.step at --tol 1e-3: 130,076 triangles, 29 MB peak). */
#define STEP_BYTES_PER_TRIANGLE 250.0

static int is_step_path(const char *path)
{
    return cli_ends_with(path, ".step") || cli_ends_with(path, ".stp") || cli_ends_with(path, ".STEP") ||
           cli_ends_with(path, ".STP");
}

/* STEP is Z-up; glTF is Y-up: (x, y, z) -> (x, z, -y) for positions and
 * normals. */
static void step_to_y_up(geom_mesh *m)
{
    double *p = geom_mesh_positions(m);
    for (size_t i = 0; p && i < geom_mesh_n_vertices(m); ++i) {
        double y = p[3 * i + 1];
        p[3 * i + 1] = p[3 * i + 2];
        p[3 * i + 2] = -y;
    }
    uint32_t ch = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    if (ch != GEOM_INVALID_INDEX) {
        double *n = geom_mesh_channel_data(m, ch);
        for (size_t i = 0; n && i < geom_mesh_channel_size(m, ch); ++i) {
            double y = n[3 * i + 1];
            n[3 * i + 1] = n[3 * i + 2];
            n[3 * i + 2] = -y;
        }
    }
}

/* --per-face: one OBJ group "face<id>" per B-rep face (id: the STEP #id). */
static geom_status step_face_groups(geom_mesh *m, const geom_brep *b)
{
    uint32_t ch = geom_mesh_channel_find(m, "face", GEOM_MESH_DOMAIN_FACE);
    if (ch == GEOM_INVALID_INDEX)
        return GEOM_OK;
    const double *fid = geom_mesh_channel_cdata(m, ch);
    uint32_t *gid = malloc((b->nfaces ? b->nfaces : 1) * sizeof *gid);
    if (!gid)
        return GEOM_ERR_NOMEM;
    for (size_t f = 0; f < b->nfaces; ++f)
        gid[f] = GEOM_INVALID_INDEX;
    geom_status st = GEOM_OK;
    size_t nf = geom_mesh_n_faces(m);
    for (size_t f = 0; f < nf && st == GEOM_OK; ++f) {
        size_t bf = (size_t)fid[f];
        if (bf >= b->nfaces)
            continue;
        if (gid[bf] == GEOM_INVALID_INDEX) {
            char name[64];
            snprintf(name, sizeof name, "face%llu", (unsigned long long)b->faces[bf].entity);
            geom_mesh_group g = {name, NULL, NULL, NULL};
            st = geom_mesh_group_add(m, &g, &gid[bf]);
        }
        uint32_t *fg = geom_mesh_face_groups(m);
        if (!fg)
            st = GEOM_ERR_NOMEM;
        else
            fg[f] = gid[bf];
    }
    free(gid);
    return st;
}

static int tessellate_step(const char *in, const tess_opts *o, int json, const char *out_path,
                           FILE *rep)
{
    if (o->have_grid || o->to.per_surface || o->to.no_weld ||
        (o->to.attributes & GEOM_SURFACE_ATTR_TANGENT) || o->to.uv_normalized)
        return cli_usage_error(&tool, "STEP input takes --tol, --angle, --normals, --uvs and "
                                      "--per-face (not --grid, --tangents, --no-weld)");
    geom_diag diag;
    geom_diag_clear(&diag);
    geom_brep *b = NULL;
    cli_timer timer;
    cli_timer_start(&timer);
    if (geom_step_read(in, NULL, &b, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    double read_secs = cli_timer_elapsed(&timer);
    for (size_t k = 0; k < b->nissues && k < 64; ++k)
        fprintf(stderr, "%s: %s: note: #%llu %s: %s\n", tool.name, in,
                (unsigned long long)b->issues[k].entity, b->issues[k].type, b->issues[k].reason);
    if (b->nfaces == 0) { /* nothing to tessellate is an error, never 0 triangles and exit 0 */
        size_t nissues = b->nissues;
        geom_step_destroy(b);
        return cli_error(&tool, "%s: no B-rep face to tessellate (%zu unsupported entities)", in,
                         nissues);
    }
    geom_brep_tess_options to;
    memset(&to, 0, sizeof to);
    to.tolerance = o->to.tolerance;
    to.angle_degrees = o->to.angle_degrees;
    to.attributes = (o->to.attributes & (GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_UV)) |
                    GEOM_SURFACE_ATTR_SOURCE;
    /* the output's size before the work (geom_step_tess_estimate, not a
     * bound), against --max-triangles and --max-memory (about
     * STEP_BYTES_PER_TRIANGLE at the peak); the library also stops at
     * --max-triangles during the work */
    double est = 0;
    char what[300];
    snprintf(what, sizeof what, "%s: the tessellation", in);
    if (geom_step_tess_estimate(b, &to, &est, NULL) == GEOM_OK &&
        cli_limits_check(&tool, &o->lim, what, est, est * STEP_BYTES_PER_TRIANGLE) !=
            CLI_CONTINUE) {
        geom_step_destroy(b);
        return CLI_EXIT_ERROR;
    }
    to.max_triangles = o->lim.max_triangles ? o->lim.max_triangles : CLI_MAX_TRIANGLES_DEFAULT;
    geom_mesh *m = geom_mesh_create(NULL);
    geom_brep_face_report *fr = calloc(b->nfaces ? b->nfaces : 1, sizeof *fr);
    if (!m || !fr) {
        geom_mesh_destroy(m);
        free(fr);
        geom_step_destroy(b);
        return cli_error(&tool, "out of memory");
    }
    geom_error_report report;
    geom_brep_tess_stats stats;
    cli_timer_start(&timer);
    geom_status st = geom_step_tessellate(b, &to, m, &report, fr, &stats, &diag);
    double secs = cli_timer_elapsed(&timer);
    if (st == GEOM_OK && o->per_face)
        st = step_face_groups(m, b);
    if (st == GEOM_OK && o->format == GEOM_MESHIO_FORMAT_GLB)
        step_to_y_up(m);
    if (st == GEOM_OK)
        st = cli_mesh_write(m, out_path, o->format, &diag);
    size_t nsolids = b->nsolids, nfaces = b->nfaces, nissues = b->nissues;
    double tol = to.tolerance;
    if (!(tol > 0)) {
        geom_aabb box = geom_mesh_bbox(m);
        tol = 1e-3 * geom_vec3_length(geom_vec3_sub(box.max, box.min));
    }
    double face_gap = 0;
    for (size_t f = 0; f < nfaces; ++f)
        face_gap = fr[f].edge_gap > face_gap ? fr[f].edge_gap : face_gap;
    geom_mesh_destroy(m);
    free(fr);
    geom_step_destroy(b);
    if (st == GEOM_ERR_LIMIT)
        return cli_error(&tool, "%s: the tessellation needs more than --max-triangles %zu "
                                "triangles (estimated %.0f before the work); raise "
                                "--max-triangles or coarsen --tol",
                         in, to.max_triangles, est);
    if (st != GEOM_OK) {
        if (!diag.source[0])
            snprintf(diag.source, sizeof diag.source, "%s", in);
        return cli_print_diag(&tool, &diag);
    }
    if (json) {
        fprintf(rep, "{\"solids\":%zu,\"faces\":%zu,\"faces_failed\":%zu,\"unsupported\":%zu,"
                     "\"triangles\":%zu,\"vertices\":%zu,\"open_edges\":%zu,\"max_error\":",
                nsolids, nfaces, stats.faces_failed, nissues, stats.triangles, stats.vertices,
                stats.open_edges);
        cli_json_number(rep, report.max_error);
        fprintf(rep, ",\"mean_error\":");
        cli_json_number(rep, report.mean_error);
        fprintf(rep, ",\"edge_error\":");
        cli_json_number(rep, stats.edge_error);
        fprintf(rep, ",\"edge_gap\":");
        cli_json_number(rep, face_gap);
        fprintf(rep, ",\"method\":\"sampled\",\"mode\":\"step\",\"tolerance\":");
        cli_json_number(rep, tol);
        fprintf(rep, ",\"estimated_triangles\":");
        cli_json_number(rep, est);
        fprintf(rep, ",\"evaluations\":%zu,\"read_seconds\":", report.evaluations);
        cli_json_number(rep, read_secs);
        fprintf(rep, ",\"seconds\":");
        cli_json_number(rep, secs);
        fprintf(rep, "}\n");
    } else {
        fprintf(rep, "solids: %zu\nfaces: %zu\nfaces_failed: %zu\nunsupported: %zu\n", nsolids,
                nfaces, stats.faces_failed, nissues);
        fprintf(rep, "triangles: %zu\nvertices: %zu\nopen_edges: %zu\n", stats.triangles,
                stats.vertices, stats.open_edges);
        fprintf(rep, "tolerance: %.6g\n", tol);
        fprintf(rep, "max_error: %.6g (sampled chordal deviation, faces and edges)\n",
                report.max_error);
        fprintf(rep, "mean_error: %.6g\n", report.mean_error);
        fprintf(rep, "edge_gap: %.6g (largest |C(t) - S(uv(t))|)\n", face_gap);
        fprintf(rep, "read_seconds: %.6f\nseconds: %.6f\n", read_secs, secs);
    }
    return stats.faces_failed ? cli_error(&tool, "%s: %zu face(s) could not be meshed", in,
                                          stats.faces_failed)
                              : CLI_EXIT_OK;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"tol", required_argument, NULL, 't'},
        {"angle", required_argument, NULL, 'a'},
        {"grid", required_argument, NULL, 'g'},
        {"per-surface", no_argument, NULL, OPT_PER_SURFACE},
        {"normals", no_argument, NULL, 'n'},
        {"uvs", no_argument, NULL, 'u'},
        {"uv-normalized", no_argument, NULL, OPT_UV_NORMALIZED},
        {"tangents", optional_argument, NULL, OPT_TANGENTS},
        {"no-weld", no_argument, NULL, OPT_NO_WELD},
        {"per-face", no_argument, NULL, OPT_PER_FACE},
        {"normal-weld", required_argument, NULL, OPT_NORMAL_WELD},
        {"format", required_argument, NULL, 'f'},
        CLI_LIMIT_LONGOPTS,
        CLI_MTLLIB_LONGOPT,
        {NULL, 0, NULL, 0}};
    tess_opts o;
    memset(&o, 0, sizeof o);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "t:a:g:nuf:", longopts, on_option, &o, &common,
                            &first);
    if (rc != CLI_CONTINUE)
        return rc;
    rc = cli_operands(&tool, argc, argv, first, 1, 1);
    if (rc != CLI_CONTINUE)
        return rc;
    if (o.have_tol && o.have_grid)
        return cli_usage_error(&tool, "--tol and --grid exclude each other");
    if (o.to.angle_degrees > 0.0 && o.have_grid)
        return cli_usage_error(&tool, "--angle applies to adaptive tessellation, not --grid");
    if (o.to.per_surface && !o.have_grid)
        return cli_usage_error(&tool, "--per-surface needs --grid");
    if (!common.output)
        return cli_usage_error(&tool, "missing -o OUT (use '-o -' for OBJ on standard output)");
    const char *out_path = common.output;
    int to_stdout = strcmp(out_path, "-") == 0;
    if (o.format == GEOM_MESHIO_FORMAT_AUTO) {
        o.format = to_stdout ? GEOM_MESHIO_FORMAT_OBJ : geom_meshio_format_from_name(out_path);
        if (o.format == GEOM_MESHIO_FORMAT_AUTO)
            return cli_usage_error(&tool, "cannot tell the output format from '%s': use --format",
                                   out_path);
    }
    if (o.have_grid)
        o.to.mode = GEOM_SURFACE_TESS_UNIFORM;
    if (o.tangents && o.format != GEOM_MESHIO_FORMAT_GLB && o.format != GEOM_MESHIO_FORMAT_PLY)
        return cli_usage_error(&tool, "%s output cannot hold tangents (GLB and PLY can): "
                                      "drop --tangents or write .glb or .ply",
                               geom_meshio_format_name(o.format));
    if (o.tangents == 1) /* MikkTSpace frames are built from normals and UVs */
        o.to.attributes |= GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_UV;
    FILE *rep = to_stdout ? stderr : stdout;
    if (is_step_path(argv[first]))
        return tessellate_step(argv[first], &o, common.json, out_path, rep);

    geom_diag diag;
    geom_diag_clear(&diag);
    geom_surface_set *set = NULL;
    if (read_surfaces(argv[first], &set, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    size_t ns = geom_surface_set_count(set);
    if (ns == 0) {
        geom_surface_set_destroy(set);
        return cli_error(&tool, "%s: no surfaces", argv[first]);
    }
    if (!o.have_grid && !o.have_tol) {
        /* the library's default, made explicit for the report */
        geom_aabb box = geom_aabb_empty();
        const geom_nurbs_surface *S = geom_surface_set_data(set);
        for (size_t k = 0; k < ns; ++k)
            for (size_t i = 0; i < S[k].nu * S[k].nv; ++i)
                box = geom_aabb_extend(box, geom_vec3_make(S[k].points[3 * i],
                                                           S[k].points[3 * i + 1],
                                                           S[k].points[3 * i + 2]));
        /* halves first: the difference of +-1e308 overflows */
        o.to.tolerance = geom_vec3_length(geom_vec3_scale(
            geom_vec3_sub(geom_vec3_scale(box.max, 0.5), geom_vec3_scale(box.min, 0.5)), 2e-3));
    }
    geom_mesh *m = geom_mesh_create(NULL);
    if (!m) {
        geom_surface_set_destroy(set);
        return cli_error(&tool, "out of memory");
    }
    /* estimate first: stop before filling memory (about 250 bytes per
     * triangle at the peak, with its vertex share, attributes, half-edges and
     * the adaptive cells: measured 241 B on the teapot, 6.9M triangles at
     * --tol 1e-5 peaking at 1.63 GB, and 693k at 1e-4 at 167 MB) */
    double est = 0.0;
    if (geom_surface_tess_estimate(geom_surface_set_data(set), ns, &o.to, &est) == GEOM_OK &&
        cli_limits_check(&tool, &o.lim, "the tessellation", est, est * 250.0) != CLI_CONTINUE) {
        geom_mesh_destroy(m);
        geom_surface_set_destroy(set);
        return CLI_EXIT_ERROR;
    }
    o.to.max_triangles = o.lim.max_triangles ? o.lim.max_triangles : CLI_MAX_TRIANGLES_DEFAULT;
    geom_error_report report;
    geom_surface_tess_stats stats;
    cli_timer timer;
    cli_timer_start(&timer);
    tess_progress prog;
    memset(&prog, 0, sizeof prog);
    cli_progress_start(&prog.bar, &tool, "tessellating", common.quiet);
    if (prog.bar.enabled) {
        o.to.progress = on_progress;
        o.to.progress_user = &prog;
    }
    geom_status st = geom_surface_tessellate(geom_surface_set_data(set), ns, &o.to, m, &report,
                                             &stats, &diag);
    cli_progress_done(&prog.bar);
    double secs = cli_timer_elapsed(&timer);
    geom_surface_set_destroy(set);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        if (!diag.source[0])
            snprintf(diag.source, sizeof diag.source, "%s", argv[first]);
        return cli_print_diag(&tool, &diag);
    }
    if (o.tangents == 1) {
        uint32_t tid;
        st = geom_mesh_tangents(m, &tid);
        if (st != GEOM_OK) {
            geom_mesh_destroy(m);
            return cli_error(&tool, "%s: tangents: %s", argv[first], geom_status_str(st));
        }
    }
    st = cli_mesh_write_up(m, out_path, o.format, common.up_z, &diag);
    geom_mesh_destroy(m);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    const char *mode = o.have_grid ? "uniform" : "adaptive";
    if (common.json) {
        fprintf(rep, "{\"surfaces\":%zu,\"triangles\":%zu,\"vertices\":%zu,\"max_error\":", ns,
                stats.triangles, stats.vertices);
        cli_json_number(rep, report.max_error);
        fprintf(rep, ",\"mean_error\":");
        cli_json_number(rep, report.mean_error);
        fprintf(rep, ",\"method\":\"sampled\",\"mode\":\"%s\",\"tolerance\":", mode);
        if (o.have_grid)
            fprintf(rep, "null");
        else
            cli_json_number(rep, o.to.tolerance);
        fprintf(rep,
                ",\"evaluations\":%zu,\"cells\":%zu,\"welded_edges\":%zu,\"collapsed_edges\":%zu,"
                "\"flipped_surfaces\":%zu,\"seconds\":",
                report.evaluations, stats.cells, stats.welded_edges, stats.collapsed_edges,
                stats.flipped_surfaces);
        cli_json_number(rep, secs);
        if (stats.uniform_u)
            fprintf(rep, ",\"uniform_grid\":[%u,%u]", stats.uniform_u, stats.uniform_v);
        else
            fprintf(rep, ",\"uniform_grid\":null");
        fprintf(rep, ",\"error\":");
        cli_json_error_report(rep, &report, "chordal distance to the mesh");
        fprintf(rep, "}\n");
    } else {
        fprintf(rep, "surfaces: %zu\n", ns);
        fprintf(rep, "mode: %s\n", mode);
        fprintf(rep, "triangles: %zu\n", stats.triangles);
        fprintf(rep, "vertices: %zu\n", stats.vertices);
        if (!o.have_grid)
            fprintf(rep, "tolerance: %.6g\n", o.to.tolerance);
        if (stats.uniform_u)
            fprintf(rep, "uniform grid: %u x %u per span (fewer triangles than adaptive)\n",
                    stats.uniform_u, stats.uniform_v);
        fprintf(rep, "max_error: %.6g (sampled chordal deviation)\n", report.max_error);
        fprintf(rep, "mean_error: %.6g\n", report.mean_error);
        fprintf(rep, "seconds: %.6f\n", secs);
    }
    return CLI_EXIT_OK;
}
