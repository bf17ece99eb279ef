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
 * "<tool_name>: <file>: warning: ..." (cli_mesh_empty_warning). Returns the reader's status
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

#ifdef __cplusplus
}
#endif

#endif
