/* geom-module: meshio */
/*
 * geom-convert: convert a mesh between OBJ, OFF, PLY, STL and glTF binary.
 *
 *   geom-convert [OPTION]... IN OUT
 *
 * IN is read with geom_meshio_read ("-": standard input; its format comes
 * from --input-format or from the content) and written to OUT with
 * geom_meshio_write, whose format comes from --format or OUT's extension.
 * OUT "-" (or -o -) writes to standard output and needs --format. A file OUT
 * is written atomically: on any error nothing is left behind and an existing
 * OUT is untouched. Doubles are written so they read back exactly unless
 * --precision asks for fewer digits. --mtllib FILE makes OBJ output name
 * the material library FILE (one mtllib line, the input's dropped).
 * Repairs made while building the mesh (see geom_mesh_build) are reported
 * on standard error.
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
    "geom-convert",
    "[OPTION]... IN [OUT]",
    "Convert the mesh in IN to OUT (or -o FILE). Formats, read and written:\n"
    "obj, off, ply, stl and glb (glTF 2.0 binary). '-' is standard input or\n"
    "output.",
    "  -f, --format=FMT        output format; default: from OUT's extension\n"
    "  -i, --input-format=FMT  input format; default: from IN's extension, else\n"
    "                          from the content\n"
    "      --ascii             PLY/STL: write text (default: binary)\n"
    "      --big-endian        PLY: write binary_big_endian\n"
    "      --float             PLY: store coordinates as float instead of double\n"
    "      --precision=N       significant digits of text numbers (1..17; default:\n"
    "                          the shortest that reads back exactly)\n"
    "      --no-normals, --no-uvs, --no-colors, --no-tangents\n"
    "                          do not write that attribute\n"
    "      --no-meta           OBJ: do not write groups, tags, mtllibs and lines\n"
    "      --mtllib=FILE       OBJ: reference the material library FILE (one\n"
    "                          mtllib line, the input's dropped; without it the\n"
    "                          input's is kept only when found next to OUT)\n"
    "      --keep-v            glTF: do not flip v to glTF's top-left origin\n"
    "      --skip-invalid      skip faces with repeated vertices or fewer than 3\n"
    "                          instead of failing\n",
    "Repairs made while building the mesh (split non-manifold vertices, flipped\n"
    "faces, skipped faces, ...) are reported on standard error.\n",
    "  geom-convert bunny.off bunny.ply\n"
    "  geom-convert --ascii --input-format stl - out.stl < in.stl\n",
};

enum {
    OPT_ASCII = CLI_OPT_TOOL_BASE,
    OPT_BIG_ENDIAN,
    OPT_FLOAT,
    OPT_PRECISION,
    OPT_NO_NORMALS,
    OPT_NO_UVS,
    OPT_NO_COLORS,
    OPT_NO_TANGENTS,
    OPT_NO_META,
    OPT_KEEP_V,
    OPT_SKIP_INVALID
};

typedef struct convert_opts {
    geom_meshio_format in_format;
    geom_meshio_write_options w;
    int skip_invalid;
    int ascii, big_endian;
} convert_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    convert_opts *o = user;
    int mrc = cli_mesh_mtllib_option(t, opt, arg);
    if (mrc != CLI_NOT_HANDLED)
        return mrc;
    switch (opt) {
    case 'f':
        return cli_mesh_format_option(t, arg, 0, &o->w.format);
    case 'i':
        return cli_mesh_format_option(t, arg, 1, &o->in_format);
    case OPT_ASCII: o->ascii = 1; return CLI_CONTINUE;
    case OPT_BIG_ENDIAN: o->big_endian = 1; return CLI_CONTINUE;
    case OPT_FLOAT: o->w.ply_float = 1; return CLI_CONTINUE;
    case OPT_PRECISION: {
        char *end = NULL;
        long p = strtol(arg, &end, 10);
        if (!*arg || *end || p < 1 || p > 17)
            return cli_usage_error(t, "--precision takes a number from 1 to 17, not '%s'", arg);
        o->w.precision = (int)p;
        return CLI_CONTINUE;
    }
    case OPT_NO_NORMALS: o->w.omit |= GEOM_MESHIO_ATTR_NORMAL; return CLI_CONTINUE;
    case OPT_NO_UVS: o->w.omit |= GEOM_MESHIO_ATTR_UV; return CLI_CONTINUE;
    case OPT_NO_COLORS: o->w.omit |= GEOM_MESHIO_ATTR_COLOR; return CLI_CONTINUE;
    case OPT_NO_TANGENTS: o->w.omit |= GEOM_MESHIO_ATTR_TANGENT; return CLI_CONTINUE;
    case OPT_NO_META: o->w.omit |= GEOM_MESHIO_ATTR_META; return CLI_CONTINUE;
    case OPT_KEEP_V: o->w.gltf_keep_v = 1; return CLI_CONTINUE;
    case OPT_SKIP_INVALID: o->skip_invalid = 1; return CLI_CONTINUE;
    default: break;
    }
    return CLI_EXIT_USAGE;
}

static void report_repairs(const char *name, const geom_mesh_build_report *r,
                           const geom_meshio_read_stats *s)
{
    const struct {
        const char *what;
        size_t n;
    } items[] = {{"invalid faces skipped", r->invalid_faces},
                 {"faces flipped", r->flipped_faces},
                 {"non-manifold edges", r->nonmanifold_edges},
                 {"faces detached", r->detached_faces},
                 {"vertices split", r->split_vertices},
                 {"vertices added", r->added_vertices},
                 {"isolated vertices kept", r->isolated_vertices},
                 {"non-orientable components cut", r->nonorientable_components}};
    for (size_t i = 0; i < sizeof items / sizeof items[0]; i++)
        if (items[i].n)
            fprintf(stderr, "%s: %s: repaired: %zu %s\n", tool.name, name, items[i].n,
                    items[i].what);
    if (s->skipped_statements)
        fprintf(stderr, "%s: %s: skipped %zu unsupported statements (first: '%s')\n", tool.name,
                name, s->skipped_statements, s->first_skipped);
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"format", required_argument, NULL, 'f'},
        {"input-format", required_argument, NULL, 'i'},
        {"ascii", no_argument, NULL, OPT_ASCII},
        {"big-endian", no_argument, NULL, OPT_BIG_ENDIAN},
        {"float", no_argument, NULL, OPT_FLOAT},
        {"precision", required_argument, NULL, OPT_PRECISION},
        {"no-normals", no_argument, NULL, OPT_NO_NORMALS},
        {"no-uvs", no_argument, NULL, OPT_NO_UVS},
        {"no-colors", no_argument, NULL, OPT_NO_COLORS},
        {"no-tangents", no_argument, NULL, OPT_NO_TANGENTS},
        {"no-meta", no_argument, NULL, OPT_NO_META},
        {"keep-v", no_argument, NULL, OPT_KEEP_V},
        {"skip-invalid", no_argument, NULL, OPT_SKIP_INVALID},
        CLI_MTLLIB_LONGOPT,
        {NULL, 0, NULL, 0}};
    convert_opts co;
    memset(&co, 0, sizeof co);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "f:i:", longopts, on_option, &co, &common,
                            &first);
    if (rc != CLI_CONTINUE)
        return rc;
    int nops = argc - first;
    rc = cli_operands(&tool, argc, argv, first, 1, 2);
    if (rc != CLI_CONTINUE)
        return rc;
    if (nops == 2 && common.output)
        return cli_usage_error(&tool, "give the output either as OUT or with -o, not both");
    const char *in_path = argv[first];
    const char *out_path = nops == 2 ? argv[first + 1] : common.output ? common.output : "-";
    int to_stdout = strcmp(out_path, "-") == 0;
    if (co.ascii && co.big_endian)
        return cli_usage_error(&tool, "--ascii and --big-endian exclude each other");
    co.w.gltf_z_up = common.up_z;
    co.w.encoding = co.ascii        ? GEOM_MESHIO_ENCODING_ASCII
                    : co.big_endian ? GEOM_MESHIO_ENCODING_BINARY_BE
                                    : GEOM_MESHIO_ENCODING_DEFAULT;
    if (co.w.format == GEOM_MESHIO_FORMAT_AUTO) {
        if (!to_stdout)
            co.w.format = geom_meshio_format_from_name(out_path);
        if (co.w.format == GEOM_MESHIO_FORMAT_AUTO && to_stdout)
            return cli_usage_error(&tool, "writing to standard output needs --format");
        if (co.w.format == GEOM_MESHIO_FORMAT_AUTO)
            return cli_usage_error(&tool, "cannot tell the output format from '%s': use --format",
                                   out_path);
    }
    if (co.big_endian && co.w.format != GEOM_MESHIO_FORMAT_PLY)
        return cli_usage_error(&tool, "--big-endian applies to PLY only");

    geom_diag diag;
    geom_diag_clear(&diag);
    char *name;
    geom_meshio_read_stats stats;
    geom_mesh *m;
    geom_mesh_build_report report;
    geom_status st = cli_mesh_read_input(in_path, co.in_format, co.skip_invalid, &m, &report,
                                         &stats, &name, &diag);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    report_repairs(name, &report, &stats);
    if (cli_mesh_empty_warning(m))
        fprintf(stderr, "%s: %s: warning: %s\n", tool.name, name, cli_mesh_empty_warning(m));
    free(name);
    /* --mtllib FILE: one `mtllib FILE` line first, the mesh's own dropped */
    const char *mtl = co.w.format == GEOM_MESHIO_FORMAT_OBJ ? cli_mesh_user_mtllib() : NULL;
    if (mtl)
        co.w.omit |= GEOM_MESHIO_ATTR_MTLLIB;
    else if (co.w.format == GEOM_MESHIO_FORMAT_OBJ && !(co.w.omit & GEOM_MESHIO_ATTR_META))
        co.w.omit |= cli_mesh_mtllib_omit(m, out_path, to_stdout);

    if (!to_stdout && !mtl) {
        st = geom_meshio_write(m, out_path, &co.w, &diag);
        geom_mesh_destroy(m);
        return st == GEOM_OK ? CLI_EXIT_OK : cli_print_diag(&tool, &diag);
    }
    void *buf = NULL;
    size_t n = 0;
    st = geom_meshio_write_memory(m, &co.w, &buf, &n, &diag);
    geom_mesh_destroy(m);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    cli_output out; /* standard output, or OUT atomically (--mtllib) */
    if (cli_output_open(&out, to_stdout ? NULL : out_path, &diag) != GEOM_OK) {
        geom_meshio_buffer_free(buf, n, NULL);
        return cli_print_diag(&tool, &diag);
    }
    if (mtl)
        fprintf(out.fp, "mtllib %s\n", mtl); /* write errors: seen at the commit */
    fwrite(buf, 1, n, out.fp);
    geom_meshio_buffer_free(buf, n, NULL);
    if (cli_output_commit(&out, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    return CLI_EXIT_OK;
}
