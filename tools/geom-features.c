/* geom-module: meshio */
/*
 * geom-features: extract feature edges (boundaries, creases, silhouettes) of
 * a mesh as polylines and write them as OBJ lines.
 *
 *   geom-features [--crease DEG] [--eye X,Y,Z] [--kinds LIST] [--with-mesh]
 *                 [--mtllib FILE] IN -o OUT.obj
 *
 * Edges are classified by geom_mesh_features: boundary edges, creases
 * (dihedral angle above --crease, default 30 degrees) and, with --eye,
 * silhouettes seen from that point (edges between a face turned towards the
 * eye and one turned away). They are chained into polylines through
 * vertices where exactly two feature edges meet (closed loops repeat their
 * first vertex). The output is an OBJ file of the polylines' vertices
 * ("v") and one "l" statement per polyline; --with-mesh writes the whole
 * mesh with the polylines added; --mtllib FILE makes the output reference the
 * material library FILE, as on geom-normals. With --json a summary (edges of each kind,
 * polylines, seconds) is printed on standard output (OUT must be a file).
 *
 * Exit status 0 on success, 1 on a read, parse or write error, 2 on a usage
 * error.
 */
#include "cli.h"
#include "cli_mesh.h"

#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

static const cli_tool tool = {
    "geom-features",
    "[OPTION]... IN [-o OUT]",
    "Extract the feature edges of the mesh in IN (boundaries, creases, and\n"
    "silhouettes seen from an eye point) as polylines, written to OUT as OBJ\n"
    "lines (standard output when OUT is '-' or absent).",
    "  -c, --crease=DEG     crease threshold on the dihedral angle in degrees\n"
    "                       (0 < DEG < 180; default 30)\n"
    "  -e, --eye=X,Y,Z      eye point: also extract the silhouette seen from it\n"
    "  -k, --kinds=LIST     comma-separated kinds among boundary, crease,\n"
    "                       silhouette (default: boundary,crease, plus silhouette\n"
    "                       with --eye)\n"
    "      --with-mesh      write the whole mesh with the polylines, not only the\n"
    "                       polylines\n"
    CLI_MTLLIB_HELP
    "  -i, --input-format=FMT  input format (obj, off, ply, stl); default: from\n"
    "                       IN's extension, else from the content\n",
    "Polylines follow feature edges through vertices where exactly two of them\n"
    "meet; closed loops repeat their first vertex. With --json, prints\n"
    "{\"boundary\", \"crease\", \"silhouette\" (edge counts), \"polylines\",\n"
    "\"seconds\"} on standard output (OUT must be a file).\n",
    "  geom-features --crease 40 fandisk.off -o edges.obj\n"
    "  geom-features --eye 0,0,10 --kinds silhouette bunny.obj -o outline.obj\n",
};

enum { OPT_WITH_MESH = CLI_OPT_TOOL_BASE };

typedef struct feat_opts {
    geom_feature_options fo;
    int have_eye, with_mesh;
    unsigned kinds;
    geom_meshio_format in_format;
} feat_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    feat_opts *o = user;
    int rc = cli_mesh_io_option(t, opt, arg, &o->in_format, NULL);
    if (rc != CLI_NOT_HANDLED)
        return rc;
    switch (opt) {
    case 'c':
        return cli_mesh_crease_option(t, arg, &o->fo.crease_degrees);
    case 'e': {
        size_t n = 0;
        if (cli_parse_numbers(arg, strlen(arg), 0, o->fo.eye, 3, &n, NULL) != GEOM_OK || n != 3)
            return cli_usage_error(t, "--eye takes three numbers X,Y,Z, not '%s'", arg);
        o->have_eye = 1;
        return CLI_CONTINUE;
    }
    case 'k': {
        unsigned k = 0;
        const char *s = arg;
        while (*s) {
            const char *e = strchr(s, ',');
            size_t len = e ? (size_t)(e - s) : strlen(s);
            if (len == 8 && strncmp(s, "boundary", 8) == 0)
                k |= GEOM_FEATURE_BOUNDARY;
            else if (len == 6 && strncmp(s, "crease", 6) == 0)
                k |= GEOM_FEATURE_CREASE;
            else if (len == 10 && strncmp(s, "silhouette", 10) == 0)
                k |= GEOM_FEATURE_SILHOUETTE;
            else
                return cli_usage_error(t, "unknown kind in '%s' (boundary, crease, silhouette)",
                                       arg);
            s += len;
            if (*s == ',')
                s++;
        }
        if (!k)
            return cli_usage_error(t, "--kinds needs at least one kind");
        o->kinds = k;
        return CLI_CONTINUE;
    }
    case OPT_WITH_MESH:
        o->with_mesh = 1;
        return CLI_CONTINUE;
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"crease", required_argument, NULL, 'c'},
                                             {"eye", required_argument, NULL, 'e'},
                                             {"kinds", required_argument, NULL, 'k'},
                                             {"with-mesh", no_argument, NULL, OPT_WITH_MESH},
                                             {"input-format", required_argument, NULL, 'i'},
                                             CLI_MTLLIB_LONGOPT,
                                             {NULL, 0, NULL, 0}};
    feat_opts fo;
    memset(&fo, 0, sizeof fo);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "c:e:k:i:", longopts, on_option, &fo, &common,
                            &first);
    geom_meshio_format out_format = GEOM_MESHIO_FORMAT_OBJ; /* the only one: no --format */
    const char *out_path = NULL;
    if (rc == CLI_CONTINUE)
        rc = cli_operands(&tool, argc, argv, first, 1, 1);
    if (rc == CLI_CONTINUE)
        rc = cli_mesh_output(&tool, &common, "output", &out_format, &out_path);
    if (rc != CLI_CONTINUE)
        return rc;
    if (strcmp(out_path, "-") != 0 &&
        geom_meshio_format_from_name(out_path) != GEOM_MESHIO_FORMAT_OBJ)
        return cli_usage_error(&tool, "polylines are written as OBJ: OUT must end in .obj");
    unsigned kinds = fo.kinds;
    if (!kinds)
        kinds = GEOM_FEATURE_BOUNDARY | GEOM_FEATURE_CREASE |
                (fo.have_eye ? GEOM_FEATURE_SILHOUETTE : 0u);
    if ((kinds & GEOM_FEATURE_SILHOUETTE) && !fo.have_eye)
        return cli_usage_error(&tool, "silhouettes need an eye point (--eye X,Y,Z)");
    fo.fo.kinds = kinds;

    geom_diag diag;
    geom_diag_clear(&diag);
    geom_mesh *m = NULL;
    if (cli_mesh_read(tool.name, argv[first], fo.in_format, &m, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    size_t ne = geom_mesh_n_edges(m), pl0 = geom_mesh_polyline_count(m), npl = 0;
    uint8_t *kind = malloc(ne ? ne : 1);
    if (!kind) {
        geom_mesh_destroy(m);
        return cli_error(&tool, "out of memory");
    }
    cli_timer timer;
    cli_timer_start(&timer);
    geom_status st = geom_mesh_features(m, &fo.fo, kind, &npl);
    double secs = cli_timer_elapsed(&timer);
    if (st != GEOM_OK) {
        free(kind);
        geom_mesh_destroy(m);
        return cli_error(&tool, "%s: feature extraction failed: %s", argv[first],
                         geom_status_str(st));
    }
    size_t count[3] = {0, 0, 0};
    for (size_t e = 0; e < ne; e++) {
        for (int b = 0; b < 3; b++)
            count[b] += (kind[e] >> b) & 1u;
    }
    free(kind);

    geom_mesh *out = m;
    geom_mesh *lines = NULL;
    if (!fo.with_mesh) {
        /* a mesh of the polylines' vertices only */
        lines = geom_mesh_create(NULL);
        size_t nv = geom_mesh_n_vertices(m);
        uint32_t *map = malloc((nv ? nv : 1) * sizeof(uint32_t));
        if (!lines || !map) {
            free(map);
            geom_mesh_destroy(lines);
            geom_mesh_destroy(m);
            return cli_error(&tool, "out of memory");
        }
        for (size_t v = 0; v < nv; v++)
            map[v] = GEOM_INVALID_INDEX;
        const double *p = geom_mesh_cpositions(m);
        uint32_t *buf = NULL;
        size_t bufcap = 0;
        for (size_t i = pl0; i < pl0 + npl && st == GEOM_OK; i++) {
            size_t n;
            const uint32_t *vs;
            st = geom_mesh_polyline_get(m, i, &n, &vs);
            if (st != GEOM_OK)
                break;
            if (n > bufcap) {
                uint32_t *q = realloc(buf, n * sizeof(uint32_t));
                if (!q) {
                    st = GEOM_ERR_NOMEM;
                    break;
                }
                buf = q;
                bufcap = n;
            }
            for (size_t j = 0; j < n && st == GEOM_OK; j++) {
                if (map[vs[j]] == GEOM_INVALID_INDEX)
                    st = geom_mesh_add_vertex(lines, p + 3 * (size_t)vs[j], &map[vs[j]]);
                buf[j] = map[vs[j]];
            }
            if (st == GEOM_OK)
                st = geom_mesh_polyline_add(lines, n, buf);
        }
        free(buf);
        free(map);
        if (st != GEOM_OK) {
            geom_mesh_destroy(lines);
            geom_mesh_destroy(m);
            return cli_error(&tool, "building the output failed: %s", geom_status_str(st));
        }
        out = lines;
    }
    st = cli_mesh_write(out, out_path, out_format, &diag);
    geom_mesh_destroy(lines);
    geom_mesh_destroy(m);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    if (common.json) {
        printf("{\"boundary\":%zu,\"crease\":%zu,\"silhouette\":%zu,\"polylines\":%zu,\"seconds\":",
               count[0], count[1], count[2], npl);
        cli_json_number(stdout, secs);
        printf("}\n");
    }
    return CLI_EXIT_OK;
}
