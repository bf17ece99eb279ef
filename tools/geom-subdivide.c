/* geom-module: subdiv meshio */
/*
 * geom-subdivide: subdivide a mesh.
 *
 *   geom-subdivide [--scheme catmull-clark|loop|bilinear|butterfly|sqrt3]
 *                  [--levels N] [--limit] [--boundary none|edge|corner]
 *                  [--fvar none|corners|corners1|corners2|boundaries|all]
 *                  [--creasing uniform|chaikin] [--normals] [IN] [-o OUT]
 *
 * Refines IN (standard input when absent or "-") uniformly N times
 * (default 1) with geom_subdiv (the rules of
 * OpenSubdiv 3 for Catmull-Clark, Loop and bilinear; OBJ `t` tags for
 * creases, corners, holes and options are honoured) and writes OUT with
 * its UVs and other channels refined. --limit moves the final vertices to
 * their limit positions; --normals adds limit normals. Loop, butterfly and
 * sqrt3 need triangles: other polygons are triangulated first (reported).
 *
 * After the run a summary goes to standard error: the face and vertex
 * counts, the time, and for each level its counts, the time it took
 * (topology and positions) and the distance from its vertices to their
 * limit positions (max and rms; the error of stopping at that level). With
 * --json the same is printed on standard output as one JSON object (OUT
 * must then be a file).
 *
 * Exit status 0 on success, 1 on a read, subdivision or write error, 2 on a
 * usage error.
 */
#include "cli.h"
#include "cli_mesh.h"

#include <errno.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"
#include "geom/subdiv.h"

static const cli_tool tool = {
    "geom-subdivide",
    "[OPTION]... [IN] [-o OUT]",
    "Subdivide the mesh in IN (standard input when IN is '-' or absent; then its\n"
    "format comes from --input-format or the content) and write it to OUT\n"
    "(standard output when OUT is '-' or absent; then --format is needed).",
    "  -s, --scheme=S       catmull-clark (default), loop, bilinear, butterfly,\n"
    "                       sqrt3\n"
    "  -n, --levels=N       levels of uniform refinement, 0..12 (default 1)\n"
    "  -l, --limit          move the result's vertices to the limit surface\n"
    "  -b, --boundary=B     vertex boundary interpolation: none (boundary faces\n"
    "                       become holes), edge (default), corner (edge and corner)\n"
    "      --fvar=F         UV (face-varying) boundaries: none (smooth), corners,\n"
    "                       corners1, corners2, boundaries, all (linear; default)\n"
    "      --creasing=C     semi-sharp crease decay: uniform (default), chaikin\n"
    "      --normals        add per-vertex normals: limit normals (catmull-clark,\n"
    "                       loop, bilinear), angle-weighted (butterfly, sqrt3)\n"
    "  -f, --format=FMT     output format (obj, off, ply, stl, glb); default: from\n"
    "                       OUT's extension\n"
    CLI_MTLLIB_HELP
    "  -i, --input-format=FMT  input format (obj, off, ply, stl); default: from\n"
    "                       IN's extension, else from the content\n"
    CLI_LIMIT_HELP,
    "Options given here override the file's `t` tags (interpolateboundary,\n"
    "facevaryinginterpolateboundary, creasemethod); creases, corners and holes\n"
    "come from `t crease`, `t corner` and `t hole`. Without a tag or option the\n"
    "defaults are OpenSubdiv's: boundary edges sharp, corners smooth, uniform\n"
    "creasing, linear UVs.\n"
    "With --json, prints {\"scheme\", \"levels\", \"input\", \"output\", \"seconds\",\n"
    "\"bbox_diagonal\", \"triangulated_faces\", \"hole_faces\", \"per_level\": [{\"level\",\n"
    "\"faces\", \"vertices\", \"seconds\", \"max_limit_distance\",\n"
    "\"rms_limit_distance\"}]} on standard output (OUT must be a file).\n",
    "  geom-subdivide --levels 2 cube.obj -o smooth.obj\n"
    "  geom-subdivide --scheme loop --levels 3 --limit --normals bunny.off -o bunny_smooth.ply\n",
};

enum { OPT_FVAR = CLI_OPT_TOOL_BASE, OPT_CREASING, OPT_NORMALS };

typedef struct sub_opts {
    geom_subdiv_options so;
    int levels;
    int limit, normals;
    int mtllib; /* --mtllib given: the mesh writer adds the line */
    geom_meshio_format in_format, out_format;
    cli_limits lim;
} sub_opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    sub_opts *o = user;
    if (opt == CLI_OPT_MTLLIB)
        o->mtllib = 1;
    int mrc = cli_mesh_mtllib_option(t, opt, arg);
    if (mrc != CLI_NOT_HANDLED)
        return mrc;
    int lrc = cli_limits_option(t, &o->lim, opt, arg);
    if (lrc != CLI_NOT_HANDLED)
        return lrc;
    switch (opt) {
    case 's':
        if (geom_subdiv_scheme_from_name(arg, &o->so.scheme) != GEOM_OK)
            return cli_usage_error(t, "unknown scheme '%s' (catmull-clark, loop, bilinear, "
                                      "butterfly, sqrt3)",
                                   arg);
        return CLI_CONTINUE;
    case 'n': {
        double d;
        if (cli_parse_double(arg, strlen(arg), 0, &d, NULL) != GEOM_OK || d != floor(d) ||
            d < 0 || d > GEOM_SUBDIV_MAX_LEVEL)
            return cli_usage_error(t, "--levels takes an integer from 0 to %d, not '%s'",
                                   GEOM_SUBDIV_MAX_LEVEL, arg);
        o->levels = (int)d;
        return CLI_CONTINUE;
    }
    case 'l':
        o->limit = 1;
        return CLI_CONTINUE;
    case 'b':
        if (strcmp(arg, "none") == 0)
            o->so.boundary = GEOM_SUBDIV_BOUNDARY_NONE;
        else if (strcmp(arg, "edge") == 0)
            o->so.boundary = GEOM_SUBDIV_BOUNDARY_EDGE_ONLY;
        else if (strcmp(arg, "corner") == 0)
            o->so.boundary = GEOM_SUBDIV_BOUNDARY_EDGE_AND_CORNER;
        else
            return cli_usage_error(t, "unknown boundary rule '%s' (none, edge, corner)", arg);
        return CLI_CONTINUE;
    case OPT_FVAR: {
        static const char *const names[] = {"none", "corners", "corners1", "corners2",
                                            "boundaries", "all"};
        for (int i = 0; i < 6; i++) {
            if (strcmp(arg, names[i]) == 0) {
                o->so.fvar_boundary = (geom_subdiv_fvar)(i + 1);
                return CLI_CONTINUE;
            }
        }
        return cli_usage_error(t, "unknown --fvar rule '%s' (none, corners, corners1, "
                                  "corners2, boundaries, all)",
                               arg);
    }
    case OPT_CREASING:
        if (strcmp(arg, "uniform") == 0)
            o->so.crease_method = GEOM_SUBDIV_CREASE_UNIFORM;
        else if (strcmp(arg, "chaikin") == 0)
            o->so.crease_method = GEOM_SUBDIV_CREASE_CHAIKIN;
        else
            return cli_usage_error(t, "unknown --creasing '%s' (uniform, chaikin)", arg);
        return CLI_CONTINUE;
    case OPT_NORMALS:
        o->normals = 1;
        return CLI_CONTINUE;
    case CLI_OPT_FORMAT:
    case CLI_OPT_INPUT_FORMAT:
        return cli_mesh_io_option(t, opt, arg, &o->in_format, &o->out_format);
    default:
        break;
    }
    return CLI_EXIT_USAGE;
}

typedef struct level_stat {
    size_t faces, vertices;
    double seconds, max_dist, rms_dist, mean_dist;
} level_stat;

/* Distance from each vertex (with a face) of the deepest level to its limit. */
static geom_status limit_distance(const geom_subdiv_refiner *r, const double *pos, size_t nv,
                                  double *maxd, double *rms, double *mean, double **lim_out)
{
    double *lim = malloc((3 * nv + 1) * sizeof(double));
    if (!lim)
        return GEOM_ERR_NOMEM;
    geom_status st = geom_subdiv_limit(r, 3, pos, lim, NULL, NULL);
    double mx = 0.0, sum = 0.0, sum1 = 0.0;
    for (size_t v = 0; st == GEOM_OK && v < nv; v++) {
        double d = hypot(hypot(pos[3 * v] - lim[3 * v], pos[3 * v + 1] - lim[3 * v + 1]),
                         pos[3 * v + 2] - lim[3 * v + 2]);
        if (d > mx)
            mx = d;
        sum += d * d;
        sum1 += d;
    }
    *maxd = mx;
    *mean = nv ? sum1 / (double)nv : 0.0;
    *rms = nv ? sqrt(sum / (double)nv) : 0.0;
    if (lim_out && st == GEOM_OK)
        *lim_out = lim;
    else
        free(lim);
    return st;
}

/* The line of the OBJ input's statement for tag number `tag` (0-based, in
 * file order, as geom_mesh_tag_get numbers them): the (tag+1)-th `t`
 * statement, counting a backslash-continued statement from its first line.
 * in holds the bytes the mesh was read from (a file or standard input), so
 * the count is over what was parsed. 0 when there is no such tag. */
static size_t obj_tag_line(const geom_file *in, size_t tag)
{
    const char *p = (const char *)in->data, *end = p + in->size;
    size_t lineno = 0, seen = 0;
    int cont = 0;
    while (p < end) {
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        const char *next = eol ? eol + 1 : end, *e = eol ? eol : end;
        lineno++;
        int was_cont = cont;
        while (e > p && (e[-1] == '\r' || e[-1] == '\n'))
            e--;
        cont = e > p && e[-1] == '\\';
        if (!was_cont) {
            const char *q = p;
            while (q < e && (*q == ' ' || *q == '\t'))
                q++;
            if (e - q >= 2 && q[0] == 't' && (q[1] == ' ' || q[1] == '\t') && seen++ == tag)
                return lineno;
        }
        p = next;
    }
    return 0;
}

static geom_status write_to_fp(void *user, const void *data, size_t size)
{
    return fwrite(data, 1, size, (FILE *)user) == size ? GEOM_OK : GEOM_ERR_IO;
}

/* The soup as OBJ to the file path through the tools' output path (as
 * cli_mesh_write_up writes a mesh there). */
static geom_status write_soup(const geom_meshio_soup *s, const char *path, geom_diag *diag)
{
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    cli_output out;
    geom_status st = cli_output_open(&out, path, diag);
    if (st != GEOM_OK)
        return st;
    errno = 0;
    st = geom_meshio_write_soup_stream(s, &wo, write_to_fp, out.fp, diag);
    if (st != GEOM_OK) {
        int err = errno;
        cli_output_abort(&out);
        if (st == GEOM_ERR_IO)
            return cli_diag_set(diag, GEOM_ERR_IO, path, 0, 0, "write error: %s",
                                strerror(err ? err : EIO));
        if (diag && diag->source[0] == '\0')
            cli_diag_locate(diag, path, 0);
        return st;
    }
    return cli_output_commit(&out, diag);
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"scheme", required_argument, NULL, 's'},
                                             {"levels", required_argument, NULL, 'n'},
                                             {"limit", no_argument, NULL, 'l'},
                                             {"boundary", required_argument, NULL, 'b'},
                                             {"fvar", required_argument, NULL, OPT_FVAR},
                                             {"creasing", required_argument, NULL, OPT_CREASING},
                                             {"normals", no_argument, NULL, OPT_NORMALS},
                                             {"format", required_argument, NULL, 'f'},
                                             {"input-format", required_argument, NULL, 'i'},
                                             CLI_LIMIT_LONGOPTS,
                                             CLI_MTLLIB_LONGOPT,
                                             {NULL, 0, NULL, 0}};
#ifdef __GLIBC__
    /* The levels' arrays, the positions and the limit report's are made and
     * freed in turn: malloc keeps freed memory for the next ones instead of
     * returning it to the system to fault it in again (first-touch page
     * faults were a fifth of the run; this saves a fifth of them on the
     * bunny at +1 MB of peak). */
    mallopt(M_MMAP_THRESHOLD, 1 << 30);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
    sub_opts so;
    memset(&so, 0, sizeof so);
    so.levels = 1;
    /* the deepest level gets the relations the limit (the error report,
     * --limit, --normals) reads, not those only further refinement would */
    so.so.partial_last_level = 2;
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "s:n:lb:f:i:", longopts, on_option, &so, &common,
                            &first);
    if (rc != CLI_CONTINUE)
        return rc;
    const char *out_path = NULL;
    rc = cli_operands(&tool, argc, argv, first, 0, 1); /* IN is optional: "-" */
    if (rc == CLI_CONTINUE)
        rc = cli_mesh_output(&tool, &common, "mesh", &so.out_format, &out_path);
    if (rc != CLI_CONTINUE)
        return rc;
    int to_stdout = strcmp(out_path, "-") == 0;

    geom_diag diag;
    geom_diag_clear(&diag);
    geom_mesh *m = NULL;
    const char *in_path = argc > first ? argv[first] : "-";
    geom_file in_bytes; /* kept until the tags were read, to name their lines */
    memset(&in_bytes, 0, sizeof in_bytes);
    if (cli_mesh_read_kept(tool.name, in_path, so.in_format, &m, &in_bytes, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    size_t in_faces = geom_mesh_n_live_faces(m), in_verts = geom_mesh_n_live_vertices(m);
    size_t triangulated = 0;
    if (so.so.scheme == GEOM_SUBDIV_LOOP || so.so.scheme == GEOM_SUBDIV_BUTTERFLY ||
        so.so.scheme == GEOM_SUBDIV_SQRT3) {
        int need = 0;
        for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++)
            if (!geom_mesh_face_is_deleted(m, f) && geom_mesh_face_valence(m, f) != 3)
                need = 1;
        if (need) {
            geom_status ts = geom_mesh_triangulate(m, &triangulated);
            if (ts != GEOM_OK && ts != GEOM_ERR_DEGENERATE) {
                geom_file_unmap(&in_bytes);
                geom_mesh_destroy(m);
                return cli_error(&tool, "%s: triangulation failed: %s", in_path,
                                 geom_status_str(ts));
            }
            fprintf(stderr, "%s: %s: %s needs triangles: %zu faces added by triangulation\n",
                    tool.name, in_path, geom_subdiv_scheme_name(so.so.scheme), triangulated);
        }
    }

    /* Estimate before the work: every level multiplies the faces by 4 (3 for
     * sqrt3), the first one turning each polygon corner into a quad for
     * Catmull-Clark and bilinear; a quad counts as two triangles, and about
     * 300 bytes go with each triangle at the peak (measured: 281 bytes per
     * output triangle at --levels 8, the refiner's levels and the output mesh
     * together). */
    {
        double corners = (double)geom_mesh_n_halfedges(m), tris = corners;
        int quads = so.so.scheme == GEOM_SUBDIV_CATMULL_CLARK || so.so.scheme == GEOM_SUBDIV_BILINEAR;
        double per = so.so.scheme == GEOM_SUBDIV_SQRT3 ? 3.0 : 4.0;
        if (so.levels == 0)
            tris = 2.0 * (double)geom_mesh_n_faces(m);
        else
            tris = (quads ? 2.0 * corners : corners) * pow(per, so.levels - 1);
        if (cli_limits_check(&tool, &so.lim, "the subdivision", tris, 300.0 * tris) !=
            CLI_CONTINUE) {
            geom_file_unmap(&in_bytes);
            geom_mesh_destroy(m);
            return CLI_EXIT_ERROR;
        }
    }
    cli_timer total;
    cli_timer_start(&total);
    geom_subdiv_refiner *r = NULL;
    geom_status st = geom_subdiv_refiner_create(m, &so.so, &r, &diag);
    size_t tag_line = 0;
    if (st != GEOM_OK && diag.message[0] && !diag.source[0]) {
        /* a tag the refiner refuses ("tag N: ...") is named by its line */
        char *end;
        const char *num = strncmp(diag.message, "tag ", 4) == 0          ? diag.message + 4
                          : strncmp(diag.message, "crease tag ", 11) == 0 ? diag.message + 11
                                                                           : NULL;
        if (num) {
            unsigned long long ti = strtoull(num, &end, 10);
            if (end != num && *end == ':')
                tag_line = obj_tag_line(&in_bytes, (size_t)ti);
        }
    }
    geom_file_unmap(&in_bytes);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        if (diag.message[0]) {
            if (!diag.source[0])
                cli_diag_locate(&diag, in_path, tag_line);
            return cli_print_diag(&tool, &diag);
        }
        return cli_error(&tool, "%s: %s", in_path, geom_status_str(st));
    }
    double setup = cli_timer_elapsed(&total);
    level_stat ls[GEOM_SUBDIV_MAX_LEVEL + 1];
    memset(ls, 0, sizeof ls);
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, 0, &li);
    double *pos = malloc((3 * li.vertices + 1) * sizeof(double));
    double bbox = 0.0;
    if (!pos) {
        st = GEOM_ERR_NOMEM;
    } else {
        memcpy(pos, geom_mesh_cpositions(m), 3 * li.vertices * sizeof(double));
        geom_aabb b = geom_mesh_bbox(m);
        if (!geom_aabb_is_empty(b))
            bbox = geom_vec3_length(geom_vec3_sub(b.max, b.min));
        /* a mesh with nothing but positions (no other channel, group,
         * material library or tag) gives the output nothing more: it is
         * not kept through the refinement (the output is built with like =
         * NULL, the same mesh) */
        if (geom_mesh_channel_count(m) == 1 && geom_mesh_group_count(m) == 0 &&
            geom_mesh_mtllib_count(m) == 0 && geom_mesh_tag_count(m) == 0) {
            geom_mesh_destroy(m);
            m = NULL;
        }
    }
    double work = setup;
    double *lim_last = NULL; /* the last level's limit positions, with --limit */
    /* progress by face count: level l costs about 4^l of level 0 */
    cli_progress prog;
    cli_progress_start(&prog, &tool, "subdividing", common.quiet);
    double total_w = 0.0, done_w = 0.0;
    for (int l = 1; l <= so.levels; l++)
        total_w += pow(4.0, l);
    for (int l = 1; st == GEOM_OK && l <= so.levels; l++) {
        cli_progress_update(&prog, done_w / total_w);
        done_w += pow(4.0, l);
        cli_timer t;
        cli_timer_start(&t);
        st = geom_subdiv_refiner_refine(r, 1);
        double *next = NULL;
        if (st == GEOM_OK) {
            geom_subdiv_refiner_level_info(r, l, &li);
            next = malloc((3 * li.vertices + 1) * sizeof(double));
            st = next ? geom_subdiv_interpolate(r, l, 3, pos, next) : GEOM_ERR_NOMEM;
        }
        ls[l].seconds = cli_timer_elapsed(&t);
        work += ls[l].seconds;
        free(pos);
        pos = next;
        if (st == GEOM_OK) {
            ls[l].faces = li.faces;
            ls[l].vertices = li.vertices;
            st = limit_distance(r, pos, li.vertices, &ls[l].max_dist, &ls[l].rms_dist,
                                &ls[l].mean_dist, l == so.levels && so.limit ? &lim_last : NULL);
        }
    }
    cli_progress_done(&prog);
    geom_mesh *out = NULL;
    size_t holes = 0;
    /* OBJ of a plain level (geom_subdiv_level_is_plain): written from the
     * level's faces, positions and normals without building the mesh (the
     * same bytes) */
    geom_meshio_soup soup;
    memset(&soup, 0, sizeof soup);
    uint32_t *soup_sizes = NULL;
    double *soup_nrm = NULL;
    int plain = 0;
    if (st == GEOM_OK) {
        cli_timer t;
        cli_timer_start(&t);
        double *nrm = NULL;
        int generic = so.so.scheme == GEOM_SUBDIV_BUTTERFLY || so.so.scheme == GEOM_SUBDIV_SQRT3;
        if (st == GEOM_OK && so.normals && !generic) {
            geom_subdiv_refiner_level_info(r, so.levels, &li);
            nrm = malloc((3 * li.vertices + 1) * sizeof(double));
            st = nrm ? geom_subdiv_limit_normals(r, pos, nrm, NULL) : GEOM_ERR_NOMEM;
        }
        if (so.limit) {
            double mx, rms, mean, *lim = lim_last;
            lim_last = NULL;
            geom_subdiv_refiner_level_info(r, so.levels, &li);
            if (!lim) /* no level: level 0 itself */
                st = limit_distance(r, pos, li.vertices, &mx, &rms, &mean, &lim);
            if (st == GEOM_OK) {
                free(pos);
                pos = lim;
            }
        }
        plain = st == GEOM_OK && so.out_format == GEOM_MESHIO_FORMAT_OBJ && !to_stdout &&
                !so.mtllib && geom_subdiv_level_is_plain(r, so.levels, pos, nrm != NULL, m);
        if (plain) {
            /* written from the refiner's own face arrays; the input is not
             * needed any more */
            geom_mesh_destroy(m);
            m = NULL;
            geom_subdiv_refiner_level_info(r, so.levels, &li);
            int tris = li.face_vertices == 3 * li.faces;
            soup_sizes = tris ? NULL : malloc((li.faces + 1) * sizeof(uint32_t));
            if (!tris && !soup_sizes)
                st = GEOM_ERR_NOMEM;
            else if (!tris)
                st = geom_subdiv_refiner_faces(r, so.levels, soup_sizes, NULL, NULL);
            soup.n_vertices = li.vertices;
            soup.xyz = pos;
            soup.normals = soup_nrm = nrm;
            nrm = NULL;
            soup.n_faces = li.faces;
            soup.face_sizes = soup_sizes;
            soup.indices = geom_subdiv_refiner_face_indices(r, so.levels);
        } else if (st == GEOM_OK) {
            st = geom_subdiv_build_mesh(r, so.levels, pos, nrm, m, &out, &holes, &diag);
        }
        free(nrm);
        if (st == GEOM_OK && so.normals && generic) {
            uint32_t id = geom_mesh_channel_find(out, "normal", GEOM_MESH_DOMAIN_CORNER);
            if (id != GEOM_INVALID_INDEX)
                st = geom_mesh_channel_remove(out, id);
            id = geom_mesh_channel_find(out, "normal", GEOM_MESH_DOMAIN_VERTEX);
            if (st == GEOM_OK && id == GEOM_INVALID_INDEX)
                st = geom_mesh_channel_add(out, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id);
            if (st == GEOM_OK)
                st = geom_mesh_vertex_normals(out, GEOM_NORMAL_WEIGHT_ANGLE,
                                              geom_mesh_channel_data(out, id), NULL);
        }
        work += cli_timer_elapsed(&t);
    }
    free(lim_last);
    if (st == GEOM_OK && plain) /* before the refiner, whose faces it writes */
        st = write_soup(&soup, out_path, &diag);
    free(soup_nrm);
    geom_subdiv_refiner_destroy(r);
    if (st == GEOM_OK && !plain) {
        free(pos);
        pos = NULL;
        st = cli_mesh_write_up(out, out_path, so.out_format, common.up_z, &diag);
        if (st != GEOM_OK) {
            geom_mesh_destroy(m);
            geom_mesh_destroy(out);
            return cli_print_diag(&tool, &diag);
        }
    }
    free(pos);
    free(soup_sizes);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        geom_mesh_destroy(out);
        if (diag.message[0])
            return cli_print_diag(&tool, &diag);
        return cli_error(&tool, "%s: subdivision failed: %s", in_path, geom_status_str(st));
    }
    size_t out_faces = plain ? soup.n_faces : geom_mesh_n_live_faces(out),
           out_verts = plain ? soup.n_vertices : geom_mesh_n_live_vertices(out);
    const char *scheme = geom_subdiv_scheme_name(so.so.scheme);
    if (common.json) {
        printf("{\"scheme\":");
        cli_json_string(stdout, scheme);
        printf(",\"levels\":%d,\"input\":{\"faces\":%zu,\"vertices\":%zu},"
               "\"output\":{\"faces\":%zu,\"vertices\":%zu},\"seconds\":",
               so.levels, in_faces, in_verts, out_faces, out_verts);
        cli_json_number(stdout, work);
        printf(",\"bbox_diagonal\":");
        cli_json_number(stdout, bbox);
        printf(",\"triangulated_faces\":%zu,\"hole_faces\":%zu,\"per_level\":[", triangulated,
               holes);
        for (int l = 1; l <= so.levels; l++) {
            printf("%s{\"level\":%d,\"faces\":%zu,\"vertices\":%zu,\"seconds\":", l > 1 ? "," : "",
                   l, ls[l].faces, ls[l].vertices);
            cli_json_number(stdout, ls[l].seconds);
            printf(",\"max_limit_distance\":");
            cli_json_number(stdout, ls[l].max_dist);
            printf(",\"rms_limit_distance\":");
            cli_json_number(stdout, ls[l].rms_dist);
            printf("}");
        }
        /* the error report, as every approximating tool prints it: the
         * distance of the last level's vertices to their limit positions */
        geom_error_report er;
        memset(&er, 0, sizeof er);
        int L = so.levels;
        er.max_error = so.limit ? 0.0 : ls[L].max_dist;
        er.mean_error = so.limit ? 0.0 : ls[L].mean_dist;
        er.method = L == 0 ? GEOM_ERROR_NONE : so.limit ? GEOM_ERROR_BOUND : GEOM_ERROR_SAMPLED;
        er.evaluations = er.pieces = L ? ls[L].vertices : 0;
        er.seconds = work;
        printf("],\"error\":");
        cli_json_error_report(stdout, &er, "distance to the limit surface");
        printf("}\n");
    } else {
        fprintf(stderr, "%s: %s, %d level%s: %zu -> %zu faces, %zu -> %zu vertices, %.6g s\n",
                tool.name, scheme, so.levels, so.levels == 1 ? "" : "s", in_faces, out_faces,
                in_verts, out_verts, work);
        for (int l = 1; l <= so.levels; l++)
            fprintf(stderr,
                    "%s:   level %d: %zu faces, %zu vertices, %.6g s, distance to limit max "
                    "%.3g rms %.3g\n",
                    tool.name, l, ls[l].faces, ls[l].vertices, ls[l].seconds, ls[l].max_dist,
                    ls[l].rms_dist);
    }
    geom_mesh_destroy(m);
    geom_mesh_destroy(out);
    return CLI_EXIT_OK;
}
