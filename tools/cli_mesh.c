/* Mesh input and output shared by the mesh tools (see cli_mesh.h). */
#include "cli_mesh.h"

#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

geom_status cli_mesh_read(const char *tool_name, const char *path, geom_meshio_format fmt,
                          geom_mesh **m, geom_diag *diag)
{
    return cli_mesh_read_kept(tool_name, path, fmt, m, NULL, diag);
}

geom_status cli_mesh_read_kept(const char *tool_name, const char *path, geom_meshio_format fmt,
                               geom_mesh **m, geom_file *kept, geom_diag *diag)
{
    cli_input in;
    geom_status st = cli_input_open(&in, path, diag);
    if (st != GEOM_OK)
        return st;
    geom_file file;
    st = cli_read_all(in.fp, in.name, &file, diag);
    if (st != GEOM_OK) {
        cli_input_close(&in);
        return st;
    }
    geom_meshio_read_options ro;
    memset(&ro, 0, sizeof ro);
    ro.format = fmt;
    ro.gltf_z_up = cli_up_z();
    geom_mesh_build_report r;
    st = geom_meshio_read_file(&file, in.name, &ro, m, &r, diag);
    if (kept && st == GEOM_OK)
        *kept = file;
    else
        geom_file_unmap(&file);
    if (st == GEOM_OK) {
        /* repairs made while building the mesh are worth knowing */
        const struct {
            const char *what;
            size_t n;
        } items[] = {{"invalid faces skipped", r.invalid_faces},
                     {"faces flipped", r.flipped_faces},
                     {"non-manifold edges", r.nonmanifold_edges},
                     {"faces detached", r.detached_faces},
                     {"vertices split", r.split_vertices},
                     {"non-orientable components cut", r.nonorientable_components}};
        for (size_t i = 0; i < sizeof items / sizeof items[0]; i++)
            if (items[i].n)
                fprintf(stderr, "%s: %s: repaired: %zu %s\n", tool_name, in.name, items[i].n,
                        items[i].what);
        if (cli_mesh_empty_warning(*m))
            fprintf(stderr, "%s: %s: warning: %s\n", tool_name, in.name,
                    cli_mesh_empty_warning(*m));
    }
    cli_input_close(&in);
    return st;
}

const char *cli_mesh_empty_warning(const geom_mesh *m)
{
    if (!m || geom_mesh_n_faces(m) > 0)
        return NULL;
    return geom_mesh_n_vertices(m) == 0 ? "empty mesh: no vertices and no faces"
                                        : "no faces: only vertices";
}

/* Say so when the format cannot hold an attribute the mesh has. */
static void warn_dropped(const geom_mesh *m, const char *path, geom_meshio_format f)
{
    static const char *const names[] = {"normal", "uv", "color", "tangent"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        int held = f == GEOM_MESHIO_FORMAT_GLB || (f != GEOM_MESHIO_FORMAT_STL && i < 3) ||
                   (f == GEOM_MESHIO_FORMAT_PLY && i == 3);
        if (held)
            continue;
        if (geom_mesh_channel_find(m, names[i], GEOM_MESH_DOMAIN_CORNER) == GEOM_INVALID_INDEX &&
            geom_mesh_channel_find(m, names[i], GEOM_MESH_DOMAIN_VERTEX) == GEOM_INVALID_INDEX)
            continue;
        fprintf(stderr, "warning: %s: %s cannot hold the mesh's \"%s\" attribute: not written%s\n",
                path, geom_meshio_format_name(f), names[i],
                i == 3 ? " (write .glb or .ply to keep tangents)"
                : i == 0 ? " (STL keeps face normals only)"
                         : "");
    }
}

/* --mtllib's FILE: the tool's argv, set once while parsing options. */
static const char *user_mtllib;

int cli_mesh_mtllib_option(const cli_tool *t, int opt, const char *arg)
{
    if (opt != CLI_OPT_MTLLIB)
        return CLI_NOT_HANDLED;
    for (const unsigned char *c = (const unsigned char *)arg; *c; c++)
        if (*c <= ' ' || *c == 0x7f)
            return cli_usage_error(t, "--mtllib: OBJ cannot hold a name with blanks or "
                                      "control characters");
    if (!arg[0])
        return cli_usage_error(t, "--mtllib needs a file name");
    user_mtllib = arg;
    return CLI_CONTINUE;
}

const char *cli_mesh_user_mtllib(void)
{
    return user_mtllib;
}

unsigned cli_mesh_mtllib_omit(const geom_mesh *m, const char *path, bool to_stdout)
{
    size_t n = geom_mesh_mtllib_count(m);
    if (n == 0)
        return 0;
    const char *slash = to_stdout ? NULL : strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    for (size_t i = 0; i < n; i++) {
        const char *name = geom_mesh_mtllib_get(m, i);
        int found = 0;
        if (!to_stdout && name && name[0]) {
            size_t len = dirlen + strlen(name) + 1;
            char *full = malloc(len);
            if (full) {
                if (name[0] == '/')
                    snprintf(full, len, "%s", name);
                else
                    snprintf(full, len, "%.*s%s", (int)dirlen, path, name);
                struct stat sb;
                found = stat(full, &sb) == 0 && S_ISREG(sb.st_mode);
                free(full);
            }
        }
        if (!found) {
            fprintf(stderr,
                    "warning: %s: mtllib %s not written: no such material library next to the "
                    "output (copy it there to keep the materials)\n",
                    to_stdout ? "<stdout>" : path, name ? name : "");
            return GEOM_MESHIO_ATTR_MTLLIB;
        }
    }
    return 0;
}

geom_status cli_mesh_write(const geom_mesh *m, const char *path, geom_meshio_format fmt,
                           geom_diag *diag)
{
    return cli_mesh_write_up(m, path, fmt, false, diag);
}

static geom_status write_to_fp(void *user, const void *data, size_t size)
{
    return fwrite(data, 1, size, (FILE *)user) == size ? GEOM_OK : GEOM_ERR_IO;
}

geom_status cli_mesh_write_up(const geom_mesh *m, const char *path, geom_meshio_format fmt,
                              bool up_z, geom_diag *diag)
{
    /* Streamed into cli_output's temporary file, renamed at the end: one
     * output path for every tool (cp's rules for what is replaced,
     * temporary files removed on SIGINT, SIGTERM and SIGHUP) without
     * holding the file in memory. */
    bool to_stdout = strcmp(path, "-") == 0;
    const char *where = to_stdout ? "<stdout>" : path;
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = fmt ? fmt : to_stdout ? GEOM_MESHIO_FORMAT_AUTO : geom_meshio_format_from_name(path);
    if (wo.format == GEOM_MESHIO_FORMAT_AUTO)
        return cli_diag_set(diag, GEOM_ERR_INVALID_ARG, where, 0, 0,
                            "output format not recognised from the name: give --format");
    wo.gltf_z_up = up_z;
    bool mtl = wo.format == GEOM_MESHIO_FORMAT_OBJ && user_mtllib;
    if (wo.format == GEOM_MESHIO_FORMAT_OBJ)
        wo.omit |= mtl ? GEOM_MESHIO_ATTR_MTLLIB : cli_mesh_mtllib_omit(m, path, to_stdout);
    cli_output out;
    geom_status st;
    if (to_stdout) {
        /* standard output cannot be taken back: made in memory first, so
         * that an error writes nothing */
        void *buf = NULL;
        size_t n = 0;
        st = geom_meshio_write_memory(m, &wo, &buf, &n, diag);
        if (st != GEOM_OK) {
            if (diag && diag->source[0] == '\0')
                cli_diag_locate(diag, where, 0);
            return st;
        }
        warn_dropped(m, where, wo.format);
        st = cli_output_open(&out, NULL, diag);
        if (st == GEOM_OK) {
            if (mtl)
                fprintf(out.fp, "mtllib %s\n", user_mtllib);
            if (n > 0 && fwrite(buf, 1, n, out.fp) != n) {
                cli_output_abort(&out);
                st = cli_diag_set(diag, GEOM_ERR_IO, where, 0, 0, "write error: %s",
                                  strerror(errno ? errno : EIO));
            } else {
                st = cli_output_commit(&out, diag);
            }
        }
        geom_meshio_buffer_free(buf, n, NULL);
        return st;
    }
    if ((st = cli_output_open(&out, path, diag)) != GEOM_OK)
        return st;
    errno = 0;
    if (mtl)
        fprintf(out.fp, "mtllib %s\n", user_mtllib); /* errors: seen at the commit */
    st = geom_meshio_write_stream(m, &wo, write_to_fp, out.fp, diag);
    if (st != GEOM_OK) {
        int err = errno;
        cli_output_abort(&out);
        if (st == GEOM_ERR_IO)
            return cli_diag_set(diag, GEOM_ERR_IO, where, 0, 0, "write error: %s",
                                strerror(err ? err : EIO));
        if (diag && diag->source[0] == '\0')
            cli_diag_locate(diag, where, 0);
        return st;
    }
    warn_dropped(m, where, wo.format);
    return cli_output_commit(&out, diag);
}

int cli_mesh_format_option(const cli_tool *t, const char *arg, int input,
                           geom_meshio_format *out)
{
    geom_meshio_format f = geom_meshio_format_from_name(arg);
    if (f == GEOM_MESHIO_FORMAT_AUTO || (input && f == GEOM_MESHIO_FORMAT_GLB))
        return cli_usage_error(t, input ? "unknown input format '%s' (obj, off, ply, stl)"
                                        : "unknown output format '%s' (obj, off, ply, stl, glb)",
                               arg);
    *out = f;
    return CLI_CONTINUE;
}

size_t cli_mesh_degenerate_faces(const geom_mesh *m, size_t *first)
{
    size_t n = 0;
    *first = 0;
    for (size_t f = 0; f < geom_mesh_n_faces(m); f++) {
        double fn[3];
        if (geom_mesh_face_is_deleted(m, (uint32_t)f) ||
            geom_mesh_face_normal(m, (uint32_t)f, fn) != GEOM_ERR_DEGENERATE)
            continue;
        if (!n++)
            *first = f;
    }
    return n;
}

/* ------------------------------------ the prologue of a mesh-in, mesh-out tool */

int cli_mesh_io_option(const cli_tool *t, int opt, const char *arg, geom_meshio_format *in_fmt,
                       geom_meshio_format *out_fmt)
{
    if (opt == CLI_OPT_FORMAT && out_fmt)
        return cli_mesh_format_option(t, arg, 0, out_fmt);
    if (opt == CLI_OPT_INPUT_FORMAT && in_fmt)
        return cli_mesh_format_option(t, arg, 1, in_fmt);
    return cli_mesh_mtllib_option(t, opt, arg);
}

int cli_mesh_output(const cli_tool *t, const cli_common *common, const char *what,
                    geom_meshio_format *fmt, const char **path)
{
    const char *out = common->output ? common->output : "-";
    bool to_stdout = strcmp(out, "-") == 0;
    if (*fmt == GEOM_MESHIO_FORMAT_AUTO) {
        if (to_stdout)
            return cli_usage_error(t, "writing to standard output needs --format");
        *fmt = geom_meshio_format_from_name(out);
        if (*fmt == GEOM_MESHIO_FORMAT_AUTO)
            return cli_usage_error(t, "cannot tell the output format from '%s': use --format",
                                   out);
    }
    if (common->json && to_stdout)
        return cli_usage_error(t, "--json needs the %s written to a file (-o OUT)", what);
    *path = out;
    return CLI_CONTINUE;
}

geom_status cli_mesh_read_input(const char *path, geom_meshio_format fmt, bool skip_invalid,
                                geom_mesh **m, geom_mesh_build_report *report,
                                geom_meshio_read_stats *stats, char **name, geom_diag *diag)
{
    *m = NULL;
    geom_file file;
    geom_status st = cli_read_input(path, &file, name, diag);
    if (st != GEOM_OK)
        return st;
    geom_meshio_read_options ro;
    memset(&ro, 0, sizeof ro);
    ro.format = fmt;
    ro.gltf_z_up = cli_up_z();
    ro.build.skip_invalid_faces = skip_invalid;
    ro.stats = stats;
    st = geom_meshio_read_file(&file, *name, &ro, m, report, diag);
    geom_file_unmap(&file);
    if (st != GEOM_OK) {
        free(*name);
        *name = NULL;
    }
    return st;
}

int cli_mesh_open(const cli_tool *t, int argc, char **argv, int first, const cli_common *common,
                  geom_meshio_format in_fmt, geom_meshio_format *out_fmt, const char **out_path,
                  geom_mesh **m)
{
    int rc = cli_operands(t, argc, argv, first, 1, 1);
    if (rc == CLI_CONTINUE)
        rc = cli_mesh_output(t, common, "mesh", out_fmt, out_path);
    if (rc != CLI_CONTINUE)
        return rc;
    geom_diag diag;
    geom_diag_clear(&diag);
    *m = NULL;
    if (cli_mesh_read(t->name, argv[first], in_fmt, m, &diag) != GEOM_OK)
        return cli_print_diag(t, &diag);
    return CLI_CONTINUE;
}

int cli_mesh_crease_option(const cli_tool *t, const char *arg, double *deg)
{
    double d;
    if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || !(d > 0.0) || !(d < 180.0))
        return cli_usage_error(t, "--crease takes an angle in degrees in (0, 180), not '%s'", arg);
    *deg = d;
    return CLI_CONTINUE;
}
