/* geom-module: meshio */
/*
 * geom-tangents: compute MikkTSpace-compatible tangent frames and write the
 * mesh (normally as glTF binary, which carries them as TANGENT).
 *
 *   geom-tangents [--crease DEG] IN -o OUT.glb
 *
 * IN must have per-corner texture coordinates (OBJ vt, or PLY texcoord
 * lists); a per-vertex "uv" channel (OFF/PLY) is turned into a per-corner one
 * first. Normals: the input's per-corner normals when it has them (OBJ vn),
 * otherwise computed by geom_mesh_corner_normals (smooth, angle weights, or
 * split at --crease DEG; --crease also recomputes existing normals). The
 * tangents (geom_mesh_tangents) are stored as the CORNER channel "tangent"
 * (x y z and the bitangent sign w, bitangent = w cross(normal, tangent)).
 * OUT's format comes from --format or its extension; glTF stores TANGENT,
 * other formats drop it. With --json a summary is printed on standard output
 * (OUT must be a file).
 *
 * Exit status 0 on success, 1 on a read, parse or write error or a mesh
 * without texture coordinates, 2 on a usage error.
 */
#include "cli.h"
#include "cli_mesh.h"

#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

static const cli_tool tool = {
    "geom-tangents",
    "[OPTION]... IN [-o OUT]",
    "Compute MikkTSpace-compatible per-corner tangent frames of the mesh in IN\n"
    "(which needs texture coordinates) and write the mesh to OUT, normally a\n"
    "glTF binary (.glb) file.",
    "  -c, --crease=DEG     (re)compute the normals first, split at edges whose\n"
    "                       dihedral angle exceeds DEG degrees (0 < DEG < 180);\n"
    "                       default: keep the input's normals, or compute smooth\n"
    "                       ones when it has none\n"
    "  -f, --format=FMT     output format (glb, obj, off, ply, stl); default: from\n"
    "                       OUT's extension\n"
    CLI_MTLLIB_HELP
    "  -i, --input-format=FMT  input format (obj, off, ply, stl); default: from\n"
    "                       IN's extension, else from the content\n",
    "Tangents follow MikkTSpace (the convention of Blender and glTF): per-face\n"
    "tangents from UV derivatives, angle-weighted over corners sharing position,\n"
    "normal and uv, orthogonalised against the normal; w = +-1 is the bitangent\n"
    "sign. Degenerate (zero-area) faces are a warning with their count and the\n"
    "first one. With --json, prints {\"faces\", \"corners\", \"tangents\",\n"
    "\"mirrored\", \"degenerate_faces\", \"first_degenerate_face\", \"seconds\"}\n"
    "and \"warnings\" on standard output (OUT must be a file).\n",
    "  geom-tangents --crease 45 textured.obj -o textured.glb\n"
    "  geom-tangents data/cube_seams.obj -o cube.glb\n",
};

typedef struct tan_opts {
    double crease;
    geom_meshio_format in_format, out_format;
} tan_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    tan_opts *o = user;
    int rc = cli_mesh_io_option(t, opt, arg, &o->in_format, &o->out_format);
    if (rc != CLI_NOT_HANDLED)
        return rc;
    switch (opt) {
    case 'c':
        return cli_mesh_crease_option(t, arg, &o->crease);
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

/* Turn a VERTEX channel into a CORNER channel of the same name (one pool
 * value per vertex, every corner of v pointing at it). */
static geom_status vertex_to_corner(geom_mesh *m, const char *name)
{
    uint32_t vid = geom_mesh_channel_find(m, name, GEOM_MESH_DOMAIN_VERTEX);
    if (vid == GEOM_INVALID_INDEX)
        return GEOM_OK;
    size_t nc = geom_mesh_channel_ncomp(m, vid), nv = geom_mesh_n_vertices(m);
    double *copy = malloc((nv ? nv : 1) * nc * sizeof(double));
    if (!copy)
        return GEOM_ERR_NOMEM;
    memcpy(copy, geom_mesh_channel_cdata(m, vid), nv * nc * sizeof(double));
    geom_status st = geom_mesh_channel_remove(m, vid);
    uint32_t cid = GEOM_INVALID_INDEX;
    if (st == GEOM_OK)
        st = geom_mesh_channel_add(m, name, GEOM_MESH_DOMAIN_CORNER, nc, &cid);
    if (st == GEOM_OK)
        st = geom_mesh_corner_pool_resize(m, cid, nv);
    if (st == GEOM_OK) {
        memcpy(geom_mesh_channel_data(m, cid), copy, nv * nc * sizeof(double));
        uint32_t *ix = geom_mesh_corner_indices(m, cid);
        size_t nh = geom_mesh_n_halfedges(m);
        for (uint32_t h = 0; h < nh; h++)
            ix[h] = geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX ? GEOM_INVALID_INDEX
                                                                 : geom_mesh_he_vertex(m, h);
    }
    free(copy);
    return st;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"crease", required_argument, NULL, 'c'},
                                             CLI_MESH_IO_LONGOPTS,
                                             {NULL, 0, NULL, 0}};
    tan_opts to;
    memset(&to, 0, sizeof to);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "c:f:i:", longopts, on_option, &to, &common,
                            &first);
    const char *out_path = NULL;
    geom_mesh *m = NULL;
    if (rc == CLI_CONTINUE)
        rc = cli_mesh_open(&tool, argc, argv, first, &common, to.in_format, &to.out_format,
                           &out_path, &m);
    if (rc != CLI_CONTINUE)
        return rc;
    geom_diag diag;
    geom_diag_clear(&diag);
    geom_status st = GEOM_OK;
    if (geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER) == GEOM_INVALID_INDEX)
        st = vertex_to_corner(m, "uv");
    if (st == GEOM_OK &&
        geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER) == GEOM_INVALID_INDEX) {
        geom_mesh_destroy(m);
        return cli_error(&tool, "%s: the mesh has no texture coordinates", argv[first]);
    }
    cli_timer timer;
    cli_timer_start(&timer);
    if (st == GEOM_OK && (to.crease > 0.0 ||
                          geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER) ==
                              GEOM_INVALID_INDEX)) {
        /* a per-vertex normal from OFF/PLY would be ambiguous next to the
         * computed per-corner one */
        uint32_t vn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX);
        if (vn != GEOM_INVALID_INDEX)
            st = geom_mesh_channel_remove(m, vn);
        geom_corner_normal_options no;
        memset(&no, 0, sizeof no);
        no.crease_degrees = to.crease;
        if (st == GEOM_OK)
            st = geom_mesh_corner_normals(m, &no, NULL);
    }
    uint32_t tid = GEOM_INVALID_INDEX;
    if (st == GEOM_OK)
        st = geom_mesh_tangents(m, &tid);
    double secs = cli_timer_elapsed(&timer);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_error(&tool, "%s: computing tangents failed: %s", argv[first],
                         geom_status_str(st));
    }
    size_t nt = geom_mesh_channel_size(m, tid), mirrored = 0, corners = 0;
    const double *d = geom_mesh_channel_cdata(m, tid);
    const uint32_t *ix = geom_mesh_corner_cindices(m, tid);
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); h++) {
        if (ix[h] == GEOM_INVALID_INDEX)
            continue;
        corners++;
        mirrored += d[4 * (size_t)ix[h] + 3] < 0.0;
    }
    /* degenerate (zero-area) faces have no normal and no tangent frame of
     * their own: said, with their count and the first one, as geom-normals does */
    size_t first_deg = 0, ndeg = cli_mesh_degenerate_faces(m, &first_deg);
    char warning[200] = "";
    if (ndeg)
        snprintf(warning, sizeof warning,
                 "%zu degenerate (zero-area) face%s, the first face %zu: no normal or "
                 "tangent frame of their own",
                 ndeg, ndeg == 1 ? "" : "s", first_deg);
    if (warning[0])
        fprintf(stderr, "%s: warning: %s: %s\n", tool.name, argv[first], warning);
    st = cli_mesh_write_up(m, out_path, to.out_format, common.up_z, &diag);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_print_diag(&tool, &diag);
    }
    if (common.json) {
        printf("{\"faces\":%zu,\"corners\":%zu,\"tangents\":%zu,\"mirrored\":%zu,"
               "\"degenerate_faces\":%zu,\"first_degenerate_face\":",
               geom_mesh_n_live_faces(m), corners, nt, mirrored, ndeg);
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
