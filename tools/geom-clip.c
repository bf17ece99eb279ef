/* geom-module: meshio */
/*
 * geom-clip: clip a mesh by planes or by a view frustum.
 *
 *   geom-clip (--plane A,B,C,D | --frustum SPEC | --matrix M) [--cap] IN -o OUT
 *
 * --plane keeps the part where A x + B y + C z + D >= 0 (may be repeated:
 * the planes are applied in turn). --frustum keeps what a perspective camera
 * sees; SPEC is a comma-separated list of key=value fields:
 *   eye=X,Y,Z        camera position (required)
 *   center=X,Y,Z     point looked at (required)
 *   up=X,Y,Z         up direction (default 0,1,0)
 *   fovy=DEG         vertical field of view in degrees, in (0, 180) (required)
 *   aspect=A         width / height (default 1)
 *   near=N, far=F    clipping distances, 0 < N < F (required)
 * e.g. --frustum eye=0,0,5,center=0,0,0,up=0,1,0,fovy=60,aspect=1.5,near=1,far=100
 * (gluLookAt and gluPerspective conventions). --matrix gives the 16 numbers
 * of a view-projection matrix instead, column-major (OpenGL clip space).
 * The frustum's six planes come from the matrix (Gribb & Hartmann).
 * Faces cut by a plane are split, vertex and corner attributes interpolated
 * linearly (geom_mesh_clip_plane); --cap closes each cut of a closed mesh
 * with triangulated cap faces. OUT's format comes from --format or its
 * extension ("-": standard output, needs --format). With --json a summary
 * is printed on standard output (OUT must be a file).
 *
 * Exit status 0 on success, 1 on a read, parse or write error, 2 on a usage
 * error (including an invalid plane or frustum).
 */
#include "cli.h"
#include "cli_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

static const cli_tool tool = {
    "geom-clip",
    "[OPTION]... (--plane A,B,C,D | --frustum SPEC | --matrix M) IN [-o OUT]",
    "Clip the mesh in IN by planes or by a camera's view frustum and write the\n"
    "part inside to OUT (standard output when OUT is '-' or absent; then\n"
    "--format is needed).",
    "  -p, --plane=A,B,C,D  keep A x + B y + C z + D >= 0 (repeatable)\n"
    "      --frustum=SPEC   keep the inside of a perspective view frustum:\n"
    "                       eye=X,Y,Z,center=X,Y,Z[,up=X,Y,Z],fovy=DEG\n"
    "                       [,aspect=A],near=N,far=F\n"
    "      --matrix=M       keep the inside of the frustum of a view-projection\n"
    "                       matrix: 16 numbers, column-major (OpenGL)\n"
    "      --cap            close the cuts of a closed mesh with cap faces\n"
    "  -f, --format=FMT     output format (obj, off, ply, stl, glb); default: from\n"
    "                       OUT's extension\n"
    CLI_MTLLIB_HELP
    "  -i, --input-format=FMT  input format (obj, off, ply, stl); default: from\n"
    "                       IN's extension, else from the content\n",
    "Frustum SPEC fields (gluLookAt / gluPerspective conventions): eye and center\n"
    "(required), up (default 0,1,0), fovy in degrees (required), aspect = width /\n"
    "height (default 1), near and far distances (required, 0 < near < far), e.g.\n"
    "  --frustum eye=0,0,5,center=0,0,0,up=0,1,0,fovy=60,aspect=1.5,near=1,far=100\n"
    "Cut faces are split with linearly interpolated attributes; vertices within\n"
    "1e-12 (relative to the bounding box) of a plane are snapped onto it. With\n"
    "--json, prints {\"vertices\", \"faces\", \"input_faces\", \"seconds\"} on\n"
    "standard output (OUT must be a file).\n",
    "  geom-clip --plane 0,0,1,-0.5 mesh.obj -o top.obj\n"
    "  geom-clip --frustum eye=0,0,5,center=0,0,0,fovy=40,near=0.1,far=10 scene.ply -o seen.ply\n",
};

enum { OPT_FRUSTUM = CLI_OPT_TOOL_BASE, OPT_MATRIX, OPT_CAP };

#define MAX_PLANES 64

typedef struct clip_opts {
    double planes[MAX_PLANES][4];
    size_t nplanes;
    int have_frustum;
    geom_mat4 vp;
    int cap;
    geom_meshio_format in_format, out_format;
} clip_opts;

/* Parse the --frustum SPEC into a view-projection matrix. */
static int parse_frustum(const cli_tool *t, const char *arg, geom_mat4 *vp)
{
    double eye[3], center[3], up[3] = {0.0, 1.0, 0.0}, fovy = 0, aspect = 1.0, nz = 0, fz = 0;
    int have[7] = {0}; /* eye center up fovy aspect near far */
    static const char *const keys[7] = {"eye", "center", "up", "fovy", "aspect", "near", "far"};
    static const size_t counts[7] = {3, 3, 3, 1, 1, 1, 1};
    double *dst[7] = {eye, center, up, &fovy, &aspect, &nz, &fz};
    const char *s = arg;
    while (*s) {
        const char *eq = strchr(s, '=');
        if (!eq)
            return cli_usage_error(t, "--frustum: expected key=value at '%s'", s);
        int k = -1;
        for (int i = 0; i < 7; i++) {
            if (strlen(keys[i]) == (size_t)(eq - s) && strncmp(s, keys[i], (size_t)(eq - s)) == 0)
                k = i;
        }
        if (k < 0)
            return cli_usage_error(t, "--frustum: unknown field '%.*s' (eye, center, up, fovy, "
                                      "aspect, near, far)", (int)(eq - s), s);
        /* the value runs to the comma before the next key=, or the end */
        const char *v = eq + 1, *end = v + strlen(v);
        for (const char *q = v; *q; q++) {
            if (*q == ',') {
                const char *r = q + 1;
                while (*r && *r != ',' && *r != '=')
                    r++;
                if (*r == '=') {
                    end = q;
                    break;
                }
            }
        }
        size_t n = 0;
        if (cli_parse_numbers(v, (size_t)(end - v), 0, dst[k], counts[k], &n, NULL) != GEOM_OK ||
            n != counts[k])
            return cli_usage_error(t, "--frustum: %s takes %zu number%s", keys[k], counts[k],
                                   counts[k] > 1 ? "s" : "");
        have[k] = 1;
        s = *end ? end + 1 : end;
    }
    if (!have[0] || !have[1] || !have[3] || !have[5] || !have[6])
        return cli_usage_error(t, "--frustum needs eye, center, fovy, near and far");
    geom_mat4 view, proj;
    if (geom_mat4_lookat(geom_vec3_make(eye[0], eye[1], eye[2]),
                         geom_vec3_make(center[0], center[1], center[2]),
                         geom_vec3_make(up[0], up[1], up[2]), &view) != GEOM_OK)
        return cli_usage_error(t, "--frustum: eye equals center or up is parallel to the view");
    if (!(fovy > 0.0 && fovy < 180.0) ||
        geom_mat4_perspective(fovy * (3.14159265358979323846 / 180.0), aspect, nz, fz, &proj) !=
            GEOM_OK)
        return cli_usage_error(t, "--frustum: need 0 < fovy < 180, aspect > 0, 0 < near < far");
    *vp = geom_mat4_mul(proj, view);
    return CLI_CONTINUE;
}

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    clip_opts *o = user;
    int rc = cli_mesh_io_option(t, opt, arg, &o->in_format, &o->out_format);
    if (rc != CLI_NOT_HANDLED)
        return rc;
    switch (opt) {
    case 'p': {
        if (o->nplanes == MAX_PLANES)
            return cli_usage_error(t, "at most %d planes", MAX_PLANES);
        size_t n = 0;
        double *pl = o->planes[o->nplanes];
        if (cli_parse_numbers(arg, strlen(arg), 0, pl, 4, &n, NULL) != GEOM_OK || n != 4)
            return cli_usage_error(t, "--plane takes four numbers A,B,C,D, not '%s'", arg);
        if (pl[0] == 0.0 && pl[1] == 0.0 && pl[2] == 0.0)
            return cli_usage_error(t, "--plane: the normal (A,B,C) is zero");
        o->nplanes++;
        return CLI_CONTINUE;
    }
    case OPT_FRUSTUM:
        if (o->have_frustum)
            return cli_usage_error(t, "only one --frustum or --matrix");
        o->have_frustum = 1;
        return parse_frustum(t, arg, &o->vp);
    case OPT_MATRIX: {
        if (o->have_frustum)
            return cli_usage_error(t, "only one --frustum or --matrix");
        size_t n = 0;
        if (cli_parse_numbers(arg, strlen(arg), 0, o->vp.m, 16, &n, NULL) != GEOM_OK || n != 16)
            return cli_usage_error(t, "--matrix takes 16 numbers (column-major)");
        o->have_frustum = 1;
        return CLI_CONTINUE;
    }
    case OPT_CAP:
        o->cap = 1;
        return CLI_CONTINUE;
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"plane", required_argument, NULL, 'p'},
                                             {"frustum", required_argument, NULL, OPT_FRUSTUM},
                                             {"matrix", required_argument, NULL, OPT_MATRIX},
                                             {"cap", no_argument, NULL, OPT_CAP},
                                             CLI_MESH_IO_LONGOPTS,
                                             {NULL, 0, NULL, 0}};
    static clip_opts co; /* large: keep it off the stack */
    memset(&co, 0, sizeof co);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "p:f:i:", longopts, on_option, &co, &common,
                            &first);
    const char *out_path = NULL;
    geom_mesh *m = NULL;
    if (rc == CLI_CONTINUE) /* the operand count first, then what to clip by */
        rc = cli_operands(&tool, argc, argv, first, 1, 1);
    if (rc == CLI_CONTINUE && co.nplanes == 0 && !co.have_frustum)
        rc = cli_usage_error(&tool, "give --plane, --frustum or --matrix");
    if (rc == CLI_CONTINUE)
        rc = cli_mesh_open(&tool, argc, argv, first, &common, co.in_format, &co.out_format,
                           &out_path, &m);
    if (rc != CLI_CONTINUE)
        return rc;
    geom_diag diag;
    geom_diag_clear(&diag);
    size_t in_faces = geom_mesh_n_live_faces(m);
    geom_clip_options opt;
    memset(&opt, 0, sizeof opt);
    opt.cap = co.cap;
    cli_timer timer;
    cli_timer_start(&timer);
    geom_status st = GEOM_OK;
    for (size_t i = 0; i < co.nplanes && st == GEOM_OK; i++) {
        geom_mesh *next = NULL;
        st = geom_mesh_clip_plane(m, co.planes[i], &opt, &next);
        geom_mesh_destroy(m);
        m = next;
    }
    if (st == GEOM_OK && co.have_frustum) {
        geom_mesh *next = NULL;
        st = geom_mesh_clip_frustum(m, co.vp, &opt, &next);
        geom_mesh_destroy(m);
        m = next;
    }
    double secs = cli_timer_elapsed(&timer);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_error(&tool, "%s: clipping failed: %s", argv[first], geom_status_str(st));
    }
    st = cli_mesh_write_up(m, out_path, co.out_format, common.up_z, &diag);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return cli_print_diag(&tool, &diag);
    }
    /* an empty result is a warning (issue 15), on stderr and in --json */
    const char *empty = geom_mesh_n_live_faces(m) == 0 && in_faces > 0
                            ? "empty result: every face was clipped away"
                            : NULL;
    if (empty)
        fprintf(stderr, "%s: %s: warning: %s\n", tool.name, argv[first], empty);
    if (common.json) {
        printf("{\"vertices\":%zu,\"faces\":%zu,\"input_faces\":%zu,\"seconds\":",
               geom_mesh_n_live_vertices(m), geom_mesh_n_live_faces(m), in_faces);
        cli_json_number(stdout, secs);
        cli_json_warning(stdout, empty);
        printf("}\n");
    }
    geom_mesh_destroy(m);
    return CLI_EXIT_OK;
}
