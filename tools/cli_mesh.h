/*
 * Mesh input and output shared by the tools that read or write meshes
 * (geom-normals, geom-tangents, geom-features, geom-clip, geom-subdivide,
 * geom-tessellate, ...). Built into geom_cli_mesh when the meshio module is.
 */
#ifndef GEOM_TOOLS_CLI_MESH_H
#define GEOM_TOOLS_CLI_MESH_H

#include "cli.h"
#include "geom/meshio.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Read the mesh in path ("-": standard input, read whole into memory) with
 * format fmt (GEOM_MESHIO_FORMAT_AUTO: from the name or the content) into
 * *m. The repairs geom_mesh_build made are printed to stderr as
 * "<tool_name>: <file>: repaired: N <what>", an empty result as
 * "<tool_name>: <file>: warning: ..." (cli_mesh_empty_warning). A .glb is
 * rotated from glTF's Y-up frame to Z-up when the tool was given --up z
 * (cli_up_z), as cli_mesh_read_input does. Returns the reader's status
 * (diag filled), GEOM_ERR_NOMEM or GEOM_ERR_IO.
 */
geom_status cli_mesh_read(const char *tool_name, const char *path, geom_meshio_format fmt,
                          geom_mesh **m, geom_diag *diag);
/* cli_mesh_read that keeps the input's bytes (file or standard input) in
 * *kept on success, for messages that quote the input (release them with
 * geom_file_unmap); kept NULL is cli_mesh_read. */
geom_status cli_mesh_read_kept(const char *tool_name, const char *path, geom_meshio_format fmt,
                               geom_mesh **m, geom_file *kept, geom_diag *diag);

/** A warning for a mesh with nothing in it ("empty mesh: no vertices and
 *  no faces", "no faces: only N vertices"), or NULL when it has faces. */
const char *cli_mesh_empty_warning(const geom_mesh *m);

/**
 * Write m to path atomically ("-": standard output, where fmt must not be
 * AUTO), with default write options and format fmt (AUTO: from the name).
 */
geom_status cli_mesh_write(const geom_mesh *m, const char *path, geom_meshio_format fmt,
                           geom_diag *diag);

/** cli_mesh_write for a mesh whose up axis is z when up_z (--up z): GLB
 *  output is rotated into glTF's Y-up frame; other formats are unchanged. */
geom_status cli_mesh_write_up(const geom_mesh *m, const char *path, geom_meshio_format fmt,
                              bool up_z, geom_diag *diag);

/**
 * Parse a --format (input = 0: obj, off, ply, stl, glb) or --input-format
 * (input = 1: obj, off, ply, stl) option argument into *out. Returns
 * CLI_CONTINUE, or the usage-error exit status after printing the message.
 */
int cli_mesh_format_option(const cli_tool *t, const char *arg, int input,
                           geom_meshio_format *out);

/**
 * OBJ output keeps the mesh's mtllib lines only when the material libraries
 * they name are where a reader of the output will look: relative to the
 * output's directory (the tools never write a .mtl). If one is not there, a
 * warning on stderr names it and GEOM_MESHIO_ATTR_MTLLIB is returned (OR it
 * into geom_meshio_write_options.omit); standard output keeps none. Returns
 * 0 when every library is found (or there is none).
 */
unsigned cli_mesh_mtllib_omit(const geom_mesh *m, const char *path, bool to_stdout);

/** --mtllib=FILE (tools writing OBJ): the OBJ output references the
 *  material library FILE (one `mtllib FILE` line first; the mesh's own
 *  mtllib lines are dropped), whether or not FILE exists yet. */
#define CLI_OPT_MTLLIB 0x1200
#define CLI_MTLLIB_LONGOPT {"mtllib", required_argument, NULL, CLI_OPT_MTLLIB}
#define CLI_MTLLIB_HELP                                                              \
    "      --mtllib=FILE    OBJ output: reference the material library FILE\n"       \
    "                       (instead of the input's, kept only when found next\n"    \
    "                       to the output)\n"
/** Handles CLI_OPT_MTLLIB for every later cli_mesh_write* of the process:
 *  CLI_CONTINUE, CLI_EXIT_USAGE (a name with blanks or control characters,
 *  which OBJ cannot hold) or CLI_NOT_HANDLED for other options. */
int cli_mesh_mtllib_option(const cli_tool *t, int opt, const char *arg);

/** The FILE given with --mtllib (NULL when none): for a tool writing OBJ
 *  through its own path (geom-convert), which then writes the one `mtllib
 *  FILE` line first and omits GEOM_MESHIO_ATTR_MTLLIB. */
const char *cli_mesh_user_mtllib(void);

/* Degenerate (zero-area) live faces of m, the ones geom_mesh_face_normal
 * refuses: their count, and the first one (0-based, in face order) in *first
 * when there is any. Tools that compute normals or tangents warn with it. */
size_t cli_mesh_degenerate_faces(const geom_mesh *m, size_t *first);

/* ------------------------------------ the prologue of a mesh-in, mesh-out tool */

/** Short options of the mesh tools' --format and --input-format, and the
 *  long options cli_mesh_io_option handles (put them in a tool's option
 *  table; a tool without --format lists the other two itself). */
#define CLI_OPT_FORMAT 'f'
#define CLI_OPT_INPUT_FORMAT 'i'
#define CLI_MESH_IO_LONGOPTS                                                   \
    {"format", required_argument, NULL, CLI_OPT_FORMAT},                      \
    {"input-format", required_argument, NULL, CLI_OPT_INPUT_FORMAT},          \
    CLI_MTLLIB_LONGOPT

/**
 * The mesh I/O options, first in a tool's cli_option_fn: --mtllib
 * (cli_mesh_mtllib_option), -f/--format into *out_fmt (when out_fmt is not
 * NULL) and -i/--input-format into *in_fmt (when in_fmt is not NULL), each
 * as cli_mesh_format_option. Returns CLI_CONTINUE, CLI_EXIT_USAGE after the
 * message, or CLI_NOT_HANDLED for any other option.
 */
int cli_mesh_io_option(const cli_tool *t, int opt, const char *arg, geom_meshio_format *in_fmt,
                       geom_meshio_format *out_fmt);

/**
 * Where a tool writes its result after cli_parse_args: *path is -o's FILE
 * or "-" (standard output), and *fmt, when still GEOM_MESHIO_FORMAT_AUTO
 * (no --format), the format of path's extension. Usage errors
 * (CLI_EXIT_USAGE after the message): standard output without a format
 * ("writing to standard output needs --format"), an extension no format has
 * ("cannot tell the output format from 'X': use --format"), and --json with
 * the result on standard output, where the summary goes ("--json needs the
 * <what> written to a file (-o OUT)"; what: "mesh", "output", ...).
 * Returns CLI_CONTINUE.
 */
int cli_mesh_output(const cli_tool *t, const cli_common *common, const char *what,
                    geom_meshio_format *fmt, const char **path);

/**
 * The mesh in the input `path` (NULL or "-": standard input, through
 * cli_read_input) read in format fmt, invalid faces skipped when
 * skip_invalid, with the build report and the reader's statistics: the
 * reading of a tool that reports on the input itself (geom-info,
 * geom-convert). On success *m (destroy it) and *name (the input's name for
 * messages: free it); on failure nothing to release and the diagnostic in
 * diag.
 */
geom_status cli_mesh_read_input(const char *path, geom_meshio_format fmt, bool skip_invalid,
                                geom_mesh **m, geom_mesh_build_report *report,
                                geom_meshio_read_stats *stats, char **name, geom_diag *diag);

/**
 * The rest of the prologue of a tool that reads one mesh and writes one,
 * after cli_parse_args: exactly one operand (cli_operands), the output
 * (cli_mesh_output, what "mesh"), then the mesh in argv[first] read with
 * cli_mesh_read in format in_fmt. Returns CLI_CONTINUE with *m (destroy
 * it), or the exit status after the message: CLI_EXIT_USAGE, or
 * CLI_EXIT_ERROR with the reader's diagnostic printed (cli_print_diag).
 */
int cli_mesh_open(const cli_tool *t, int argc, char **argv, int first, const cli_common *common,
                  geom_meshio_format in_fmt, geom_meshio_format *out_fmt, const char **out_path,
                  geom_mesh **m);

/** A --crease=DEG argument (a dihedral angle in degrees, 0 < DEG < 180)
 *  into *deg: CLI_CONTINUE, or CLI_EXIT_USAGE after the message. */
int cli_mesh_crease_option(const cli_tool *t, const char *arg, double *deg);

#ifdef __cplusplus
}
#endif

#endif
