/* geom-module: meshio */
/*
 * geom-normals: compute per-corner normals of a mesh and write it.
 *
 *   geom-normals [--weight uniform|area|angle|max] [--crease DEG] [--split-uv]
 *                IN -o OUT
 *
 * Normals are computed with geom_mesh_corner_normals: around each vertex,
 * corners are grouped into fans bounded by hard edges (dihedral angle above
 * --crease, boundary edges, and with --split-uv the seams of the "uv"
 * channel) and each fan gets the weighted average of its faces' normals.
 * Without --crease nothing is split and the result is the smooth vertex
 * normal at every corner. The CORNER channel "normal" replaces any normal
 * the input had (a VERTEX "normal" channel is removed). OUT's format comes
 * from --format or its extension ("-": standard output, needs --format).
 * With --json a summary (faces, vertices, normals, zero normals, degenerate
 * faces and the first one, seconds, warnings) is printed on standard output
 * (OUT must then be a file). Degenerate (zero-area) faces have no normal and
 * contribute nothing: a warning on standard error (and in --json) gives
 * their count and the first face index, instead of silent zero normals.
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
    "geom-normals",
    "[OPTION]... IN [-o OUT]",
    "Compute per-corner normals of the mesh in IN and write the mesh to OUT\n"
    "(standard output when OUT is '-' or absent; then --format is needed).",
    "  -w, --weight=W       face weights: angle (default; Thuermer & Wuethrich),\n"
    "                       uniform, area, max (Max 1999)\n"
    "  -c, --crease=DEG     split the normals at edges whose dihedral angle\n"
    "                       exceeds DEG degrees (0 < DEG < 180); default: no\n"
    "                       splitting (smooth vertex normals)\n"
    "      --split-uv       also split at the seams of the \"uv\" channel\n"
    "  -f, --format=FMT     output format (obj, off, ply, stl, glb); default: from\n"
    "                       OUT's extension\n"
    CLI_MTLLIB_HELP
    "  -i, --input-format=FMT  input format (obj, off, ply, stl); default: from\n"
    "                       IN's extension, else from the content\n",
    "Without --crease and --split-uv the normals are one per vertex (a vertex\n"
    "\"normal\" channel); with them, the mesh's per-corner \"normal\" channel, so\n"
    "OBJ output shares vn values within smooth fans and splits them at hard edges.\n"
    "With --json, prints {\"faces\", \"vertices\", \"normals\", \"zero_normals\",\n"
    "\"degenerate_faces\", \"first_degenerate_face\", \"seconds\"} and \"warnings\"\n"
    "on standard output (OUT must be a file). Degenerate (zero-area) faces have no\n"
    "normal: a warning gives their count and the first one (0-based).\n",
    "  geom-normals --crease 30 mesh.obj -o with_normals.obj\n"
    "  geom-normals --weight area --format ply - < in.obj > out.ply\n",
};

enum { OPT_SPLIT_UV = CLI_OPT_TOOL_BASE };

typedef struct normals_opts {
    geom_corner_normal_options no;
    int split_uv;
    geom_meshio_format in_format, out_format;
} normals_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    normals_opts *o = user;
    int rc = cli_mesh_io_option(t, opt, arg, &o->in_format, &o->out_format);
    if (rc != CLI_NOT_HANDLED)
        return rc;
    switch (opt) {
    case 'w':
        if (strcmp(arg, "angle") == 0)
            o->no.weight = GEOM_NORMAL_WEIGHT_ANGLE;
        else if (strcmp(arg, "uniform") == 0)
            o->no.weight = GEOM_NORMAL_WEIGHT_UNIFORM;
        else if (strcmp(arg, "area") == 0)
            o->no.weight = GEOM_NORMAL_WEIGHT_AREA;
        else if (strcmp(arg, "max") == 0)
            o->no.weight = GEOM_NORMAL_WEIGHT_MAX;
        else
            return cli_usage_error(t, "unknown weight '%s' (uniform, area, angle, max)", arg);
        return CLI_CONTINUE;
    case 'c':
        return cli_mesh_crease_option(t, arg, &o->no.crease_degrees);
    case OPT_SPLIT_UV:
        o->split_uv = 1;
        return CLI_CONTINUE;
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"weight", required_argument, NULL, 'w'},
                                             {"crease", required_argument, NULL, 'c'},
                                             {"split-uv", no_argument, NULL, OPT_SPLIT_UV},
                                             CLI_MESH_IO_LONGOPTS,
                                             {NULL, 0, NULL, 0}};
    normals_opts no;
    memset(&no, 0, sizeof no);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "w:c:f:i:", longopts, on_option, &no, &common,
                            &first);
    const char *out_path = NULL;
    geom_mesh *m = NULL;
    if (rc == CLI_CONTINUE)
        rc = cli_mesh_open(&tool, argc, argv, first, &common, no.in_format, &no.out_format,
                           &out_path, &m);
    if (rc != CLI_CONTINUE)
        return rc;
    geom_diag diag;
    geom_diag_clear(&diag);
    if (no.split_uv) {
        uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
        if (uv == GEOM_INVALID_INDEX) {
            geom_mesh_destroy(m);
            return cli_error(&tool, "%s: --split-uv: the mesh has no per-corner \"uv\" channel",
                             argv[first]);
        }
        no.no.split_at_channel_plus_one = uv + 1;
    }
    cli_timer timer;
    cli_timer_start(&timer);
    uint32_t vn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX);
    geom_status st = GEOM_OK;
    if (vn != GEOM_INVALID_INDEX) {
        if (no.no.split_at_channel_plus_one > vn + 1)
            no.no.split_at_channel_plus_one--; /* ids after vn shift down */
        st = geom_mesh_channel_remove(m, vn);
    }
    uint32_t id = GEOM_INVALID_INDEX;
    size_t zero = 0, nn = 0;
    if (st == GEOM_OK && no.no.crease_degrees == 0.0 && !no.no.split_at_channel_plus_one) {
        /* nothing splits the fans: one normal per vertex is the answer */
        uint32_t cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
        if (cn != GEOM_INVALID_INDEX)
            st = geom_mesh_channel_remove(m, cn);
        if (st == GEOM_OK)
            st = geom_mesh_channel_add(m, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id);
        if (st == GEOM_OK)
            st = geom_mesh_vertex_normals(m, no.no.weight, geom_mesh_channel_data(m, id), &zero);
        nn = geom_mesh_n_live_vertices(m);
    } else if (st == GEOM_OK) {
        st = geom_mesh_corner_normals(m, &no.no, &id);
        if (st == GEOM_OK) {
            nn = geom_mesh_channel_size(m, id);
            const double *d = geom_mesh_channel_cdata(m, id);
            for (size_t i = 0; i < nn; i++)
                zero += d[3 * i] == 0.0 && d[3 * i + 1] == 0.0 && d[3 * i + 2] == 0.0;
        }
    }
    double secs = cli_timer_elapsed(&timer);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_error(&tool, "%s: computing normals failed: %s", argv[first],
                         geom_status_str(st));
    }
    /* degenerate (zero-area) faces have no normal: they contribute nothing,
     * which is said, with their count and the first one (0-based, in the
     * mesh's face order), rather than left to show as zero normals */
    size_t first_deg = 0, ndeg = cli_mesh_degenerate_faces(m, &first_deg);
    char warning[256] = "";
    if (ndeg)
        snprintf(warning, sizeof warning,
                 "%zu degenerate (zero-area) face%s, the first face %zu: no normal, not "
                 "counted in their vertices' normals%s",
                 ndeg, ndeg == 1 ? "" : "s", first_deg,
                 zero ? "; vertices with only such faces get a zero normal" : "");
    else if (zero)
        snprintf(warning, sizeof warning, "%zu normal%s zero (isolated vertices)", zero,
                 zero == 1 ? " is" : "s are");
    if (warning[0])
        fprintf(stderr, "%s: warning: %s: %s\n", tool.name, argv[first], warning);
    st = cli_mesh_write_up(m, out_path, no.out_format, common.up_z, &diag);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_print_diag(&tool, &diag);
    }
    if (common.json) {
        printf("{\"faces\":%zu,\"vertices\":%zu,\"normals\":%zu,\"zero_normals\":%zu,"
               "\"degenerate_faces\":%zu,\"first_degenerate_face\":",
               geom_mesh_n_live_faces(m), geom_mesh_n_live_vertices(m), nn, zero, ndeg);
        if (ndeg)
            printf("%zu", first_deg);
        else
            printf("null");
        printf(",\"seconds\":");
        cli_json_number(stdout, secs);
        cli_json_warning(stdout, warning);
        printf("}\n");
    }
    geom_mesh_destroy(m);
    return CLI_EXIT_OK;
}
