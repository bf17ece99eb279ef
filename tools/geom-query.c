/* geom-module: spatial meshio */
/*
 * geom-query: spatial queries over a point set or a triangle mesh.
 *
 *   geom-query POINTS|MESH [--index octree|quadtree|kdtree|bvh]
 *              (--knn K | --radius R | --box X0,Y0,Z0,X1,Y1,Z1 | --closest |
 *               --signed-distance) [--queries FILE] [--distances]
 *              [--threads N] [--json] [-o OUT]
 *
 * POINTS is a text file of 2 or 3 numbers a line (2 numbers: 2D points, a
 * quadtree or 2D kd-tree) or a mesh file (.obj .off .ply .stl: its
 * vertices). MESH (for --closest and --signed-distance) is a mesh file; its
 * polygons are triangulated. Queries come from --queries FILE or standard
 * input, one point a line (blank lines and '#' comments are skipped); the
 * answer is one line per query:
 *   --knn K, --radius R   0-based indices, nearest first, ties by index
 *                         (with --distances: index:distance pairs)
 *   --box                 reads no queries; one line, the points inside the
 *                         closed box in index order (2D: X0,Y0,X1,Y1)
 *   --closest             x y z triangle distance
 *   --signed-distance     the signed distance (negative inside: winding
 *                         number >= 1/2, exactly 1/2 counting as inside)
 * Numbers are printed with 17 significant digits; an empty answer is an
 * empty line. --json adds one JSON object as the last line of standard
 * error: build and query time, nodes, depth, bytes (and the winding-number
 * error bound for --signed-distance). A line with the wrong count of
 * numbers, or a NaN/Inf, in POINTS or in the queries is an error naming its
 * 1-based line (exit 1).
 */
#include "cli.h"
#include "cli_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"
#include "geom/spatial.h"

static const cli_tool tool = {
    "geom-query",
    "POINTS|MESH (--knn K | --radius R | --box BOX | --closest | --signed-distance) [OPTION]...",
    "Nearest neighbours, radius and box queries over a point set, and closest\n"
    "points and signed distances to a triangle mesh, through a spatial index.",
    "      --index NAME      octree, quadtree, kdtree (points; default kdtree)\n"
    "                        or bvh (--closest/--signed-distance; the default)\n"
    "      --knn K           the K nearest points of each query\n"
    "      --radius R        the points within distance R (inclusive)\n"
    "      --box LIST        X0,Y0,Z0,X1,Y1,Z1 (2D: X0,Y0,X1,Y1): points inside\n"
    "      --closest         closest point on MESH: x y z triangle distance\n"
    "      --signed-distance signed distance to MESH (negative inside)\n"
    "      --queries FILE    read the queries from FILE (default: standard input)\n"
    "      --distances       print index:distance pairs (--knn, --radius)\n"
    "      --threads N       worker threads (0: all; the answers do not depend on it)\n",
    "POINTS: 2 or 3 numbers a line, or a mesh file (.obj .off .ply .stl) whose\n"
    "vertices are the points. Queries: one point a line. One answer line per\n"
    "query (an empty answer is an empty line), 17 significant digits. --json\n"
    "adds a JSON object (times, nodes, depth, bytes) as the last line of\n"
    "standard error. A line with the wrong count of numbers or a NaN/Inf is an\n"
    "error naming its line.\n",
    "  geom-query points.txt --knn 8 --queries q.txt --distances\n"
    "  geom-query bunny.obj --signed-distance --queries q.txt -o sd.txt\n",
};

enum { OPT_INDEX = CLI_OPT_TOOL_BASE, OPT_KNN, OPT_RADIUS, OPT_BOX, OPT_CLOSEST, OPT_SD,
       OPT_QUERIES, OPT_DIST, OPT_THREADS };
enum { Q_NONE, Q_KNN, Q_RADIUS, Q_BOX, Q_CLOSEST, Q_SD };
enum { I_DEFAULT, I_KDTREE, I_OCTREE, I_QUADTREE, I_BVH };

typedef struct opts {
    int query, index, distances, threads;
    size_t k;
    double r;
    double box[6];
    size_t box_n;
    const char *queries;
} opts;

static int on_option(const cli_tool *t, void *user, int opt, const char *arg)
{
    opts *o = user;
    int q = Q_NONE;
    geom_status st;
    double v;
    switch (opt) {
    case OPT_INDEX:
        if (!strcmp(arg, "kdtree")) o->index = I_KDTREE;
        else if (!strcmp(arg, "octree")) o->index = I_OCTREE;
        else if (!strcmp(arg, "quadtree")) o->index = I_QUADTREE;
        else if (!strcmp(arg, "bvh")) o->index = I_BVH;
        else return cli_usage_error(t, "--index: unknown index '%s' (octree, quadtree, kdtree, bvh)", arg);
        return CLI_CONTINUE;
    case OPT_KNN:
        st = cli_parse_double(arg, strlen(arg), 0, &v, NULL);
        if (st != GEOM_OK || !(v >= 1) || v != floor(v) || v > 1e9)
            return cli_usage_error(t, "--knn: expected a positive integer, got '%s'", arg);
        o->k = (size_t)v;
        q = Q_KNN;
        break;
    case OPT_RADIUS:
        st = cli_parse_double(arg, strlen(arg), 0, &v, NULL);
        if (st != GEOM_OK || !(v >= 0))
            return cli_usage_error(t, "--radius: expected a finite number >= 0, got '%s'", arg);
        o->r = v;
        q = Q_RADIUS;
        break;
    case OPT_BOX:
        st = cli_parse_numbers(arg, strlen(arg), 0, o->box, 6, &o->box_n, NULL);
        if (st != GEOM_OK || (o->box_n != 4 && o->box_n != 6))
            return cli_usage_error(t, "--box: expected X0,Y0,Z0,X1,Y1,Z1 or X0,Y0,X1,Y1, got '%s'", arg);
        q = Q_BOX;
        break;
    case OPT_CLOSEST: q = Q_CLOSEST; break;
    case OPT_SD: q = Q_SD; break;
    case OPT_QUERIES: o->queries = arg; return CLI_CONTINUE;
    case OPT_DIST: o->distances = 1; return CLI_CONTINUE;
    case OPT_THREADS:
        st = cli_parse_double(arg, strlen(arg), 0, &v, NULL);
        if (st != GEOM_OK || !(v >= 0) || v != floor(v) || v > 1024)
            return cli_usage_error(t, "--threads: expected an integer in [0, 1024], got '%s'", arg);
        o->threads = (int)v;
        return CLI_CONTINUE;
    default:
        return CLI_EXIT_USAGE;
    }
    if (o->query != Q_NONE && o->query != q)
        return cli_usage_error(t, "give one of --knn, --radius, --box, --closest, --signed-distance");
    o->query = q;
    return CLI_CONTINUE;
}

/* A growable array of doubles. */
typedef struct dvec {
    double *v;
    size_t n, cap;
} dvec;

static int dvec_push(dvec *d, const double *x, size_t m)
{
    if (d->n + m > d->cap) {
        size_t nc = d->cap ? d->cap * 2 : 1024;
        while (nc < d->n + m)
            nc *= 2;
        double *p = realloc(d->v, nc * sizeof *p);
        if (!p)
            return -1;
        d->v = p;
        d->cap = nc;
    }
    memcpy(d->v + d->n, x, m * sizeof *x);
    d->n += m;
    return 0;
}

/* Read points of dimension *dim (0: set from the first line; 2 or 3). */
static geom_status read_points(const char *path, int *dim, dvec *out, geom_diag *diag)
{
    cli_input in;
    geom_status st = cli_input_open(&in, path, diag);
    if (st != GEOM_OK)
        return st;
    cli_lines lines;
    cli_lines_init(&lines, in.fp, in.name);
    char *line;
    size_t len;
    int r;
    st = GEOM_OK;
    while ((r = cli_lines_next(&lines, &line, &len, diag)) > 0) {
        if (cli_line_is_blank_or_comment(line, len))
            continue;
        double v[3];
        size_t n = 0;
        st = cli_parse_numbers(line, len, 0, v, 3, &n, diag);
        if (st != GEOM_OK) {
            cli_diag_locate(diag, lines.source, lines.lineno);
            break;
        }
        if (*dim == 0 && (n == 2 || n == 3))
            *dim = (int)n;
        if ((int)n != *dim) {
            st = cli_diag_set(diag, GEOM_ERR_PARSE, lines.source, lines.lineno, 1,
                              "expected %d numbers, found %zu", *dim ? *dim : 3, n);
            break;
        }
        if (dvec_push(out, v, n)) {
            st = cli_diag_set(diag, GEOM_ERR_NOMEM, lines.source, lines.lineno, 1, "out of memory");
            break;
        }
    }
    if (st == GEOM_OK && r < 0)
        st = (geom_status)r;
    cli_lines_free(&lines);
    cli_input_close(&in);
    return st;
}

static int is_mesh_path(const char *p)
{
    const char *dot = strrchr(p, '.');
    if (!dot)
        return 0;
    const char *ext[] = {".obj", ".off", ".ply", ".stl", ".OBJ", ".OFF", ".PLY", ".STL"};
    for (size_t i = 0; i < sizeof ext / sizeof *ext; i++)
        if (!strcmp(dot, ext[i]))
            return 1;
    return 0;
}

/* Mesh as positions and triangles (polygons triangulated). */
static geom_status read_mesh(const char *path, dvec *pos, uint32_t **tris, size_t *nt, geom_diag *diag)
{
    geom_mesh *m = NULL;
    geom_status st = cli_mesh_read(tool.name, path, GEOM_MESHIO_FORMAT_AUTO, &m, diag);
    if (st != GEOM_OK)
        return st;
    st = geom_mesh_triangulate(m, NULL);
    size_t ni = 0;
    if (st == GEOM_OK)
        st = geom_mesh_to_soup(m, NULL, NULL, &ni);
    *tris = malloc((ni ? ni : 1) * sizeof **tris);
    size_t nf = geom_mesh_n_live_faces(m);
    uint32_t *sizes = malloc((nf ? nf : 1) * sizeof *sizes);
    if (st == GEOM_OK && (!*tris || !sizes))
        st = GEOM_ERR_NOMEM;
    if (st == GEOM_OK)
        st = geom_mesh_to_soup(m, sizes, *tris, &ni);
    if (st == GEOM_OK && dvec_push(pos, geom_mesh_cpositions(m), 3 * geom_mesh_n_vertices(m)))
        st = GEOM_ERR_NOMEM;
    free(sizes);
    *nt = ni / 3;
    geom_mesh_destroy(m);
    if (st != GEOM_OK)
        return cli_diag_set(diag, st, path, 0, 0, "%s", geom_status_str(st));
    return GEOM_OK;
}

static void print_row(FILE *fp, const geom_neighbors *nb, size_t q, int dist)
{
    for (size_t i = nb->offsets[q]; i < nb->offsets[q + 1]; i++) {
        if (i > nb->offsets[q])
            fputc(' ', fp);
        fprintf(fp, "%u", nb->index[i]);
        if (dist && nb->distance) {
            fputc(':', fp);
            cli_print_double(fp, nb->distance[i]);
        }
    }
    fputc('\n', fp);
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"index", required_argument, NULL, OPT_INDEX},
        {"knn", required_argument, NULL, OPT_KNN},
        {"radius", required_argument, NULL, OPT_RADIUS},
        {"box", required_argument, NULL, OPT_BOX},
        {"closest", no_argument, NULL, OPT_CLOSEST},
        {"signed-distance", no_argument, NULL, OPT_SD},
        {"queries", required_argument, NULL, OPT_QUERIES},
        {"distances", no_argument, NULL, OPT_DIST},
        {"threads", required_argument, NULL, OPT_THREADS},
        {0, 0, 0, 0}};
    opts o;
    memset(&o, 0, sizeof o);
    cli_common common;
    int first;
    int rc = cli_parse_args(&tool, argc, argv, NULL, longopts, on_option, &o, &common, &first);
    if (rc != CLI_CONTINUE)
        return rc;
    if (first >= argc)
        return cli_usage_error(&tool, "missing POINTS or MESH operand");
    rc = cli_operands(&tool, argc, argv, first, 0, 1);
    if (rc != CLI_CONTINUE)
        return rc;
    if (o.query == Q_NONE)
        return cli_usage_error(&tool, "give one of --knn, --radius, --box, --closest, --signed-distance");
    int meshq = o.query == Q_CLOSEST || o.query == Q_SD;
    if (meshq && o.index != I_DEFAULT && o.index != I_BVH)
        return cli_usage_error(&tool, "--closest and --signed-distance use --index bvh");
    if (!meshq && o.index == I_BVH)
        return cli_usage_error(&tool, "--index bvh answers --closest and --signed-distance only");
    const char *path = argv[first];
    geom_diag diag;
    geom_diag_clear(&diag);
    dvec pts = {0}, qs = {0};
    uint32_t *tris = NULL;
    size_t nt = 0;
    int dim = 0;
    geom_status st;
    if (meshq) {
        st = read_mesh(path, &pts, &tris, &nt, &diag);
        dim = 3;
    } else if (is_mesh_path(path)) {
        uint32_t *t = NULL;
        st = read_mesh(path, &pts, &t, &nt, &diag);
        free(t);
        dim = 3;
    } else {
        st = read_points(path, &dim, &pts, &diag);
        if (st == GEOM_OK && dim == 0)
            dim = o.query == Q_BOX ? (int)o.box_n / 2 : 3; /* no points */
    }
    if (st != GEOM_OK) {
        free(pts.v);
        free(tris);
        return cli_print_diag(&tool, &diag);
    }
    if (o.query == Q_BOX && (int)o.box_n != 2 * dim) {
        free(pts.v);
        free(tris);
        return cli_usage_error(&tool, "--box needs %d numbers for %dD points", 2 * dim, dim);
    }
    if (o.query != Q_BOX) {
        int qdim = dim;
        st = read_points(o.queries, &qdim, &qs, &diag);
        if (st != GEOM_OK) {
            free(pts.v);
            free(tris);
            free(qs.v);
            return cli_print_diag(&tool, &diag);
        }
    }
    size_t n = pts.n / (size_t)dim, nq = qs.n / (size_t)dim;
    int index = o.index;
    if (index == I_DEFAULT)
        index = meshq ? I_BVH : I_KDTREE;
    if (index == I_OCTREE && dim == 2)
        index = I_QUADTREE;
    if (index == I_QUADTREE && dim == 3)
        index = I_OCTREE;
    static const char *names[] = {"", "kdtree", "octree", "quadtree", "bvh"};

    cli_output out;
    if (cli_output_open(&out, common.output, &diag) != GEOM_OK) {
        free(pts.v);
        free(tris);
        free(qs.v);
        return cli_print_diag(&tool, &diag);
    }
    cli_timer timer;
    cli_timer_start(&timer);
    geom_kdtree *kd = NULL;
    geom_octree *oc = NULL;
    geom_meshdist *md = NULL;
    geom_neighbors nb = {0};
    uint32_t *idx = NULL;
    double *dist = NULL, *cp = NULL;
    size_t nodes = 0, depth = 0, bytes = 0;
    geom_error_report rep;
    memset(&rep, 0, sizeof rep);
    if (index == I_KDTREE) {
        geom_kdtree_options ko = {0};
        ko.threads = o.threads;
        st = geom_kdtree_build(pts.v, n, dim, &ko, &kd, &diag);
        nodes = geom_kdtree_node_count(kd), depth = geom_kdtree_depth(kd), bytes = geom_kdtree_bytes(kd);
    } else if (index == I_BVH) {
        geom_meshdist_options mo = {0};
        mo.threads = o.threads;
        st = geom_meshdist_create(pts.v, n, tris, nt, &mo, &md, &diag);
        geom_bvh_nodes(geom_meshdist_bvh(md), &nodes);
        depth = geom_bvh_depth(geom_meshdist_bvh(md)), bytes = geom_meshdist_bytes(md);
    } else {
        geom_octree_options oo = {0};
        oo.threads = o.threads;
        st = geom_octree_build_points(pts.v, n, dim, &oo, &oc, &diag);
        geom_octree_nodes(oc, &nodes);
        depth = geom_octree_depth(oc), bytes = geom_octree_bytes(oc);
    }
    double build_s = cli_timer_elapsed(&timer);
    if (st == GEOM_OK) {
        /* Point indices name lines of POINTS in errors: shift to 1-based is
         * not possible in general (blank lines), so the message keeps the index. */
        cli_timer_start(&timer);
        if (o.query == Q_KNN) {
            idx = malloc((nq * o.k + 1) * sizeof *idx);
            dist = malloc((nq * o.k + 1) * sizeof *dist);
            if (!idx || !dist)
                st = GEOM_ERR_NOMEM;
            else if (kd)
                st = geom_kdtree_knn(kd, qs.v, nq, o.k, idx, dist, o.threads, &diag);
            else
                st = geom_octree_knn(oc, qs.v, nq, o.k, idx, dist, o.threads, &diag);
        } else if (o.query == Q_RADIUS) {
            st = kd ? geom_kdtree_radius(kd, qs.v, nq, o.r, &nb, o.threads, &diag)
                    : geom_octree_radius(oc, qs.v, nq, o.r, &nb, o.threads, &diag);
        } else if (o.query == Q_BOX) {
            st = kd ? geom_kdtree_box(kd, o.box, o.box + dim, &nb)
                    : geom_octree_box(oc, o.box, o.box + dim, &nb);
        } else {
            idx = malloc((nq ? nq : 1) * sizeof *idx);
            dist = malloc((nq ? nq : 1) * sizeof *dist);
            cp = malloc((nq ? 3 * nq : 1) * sizeof *cp);
            if (!idx || !dist || !cp)
                st = GEOM_ERR_NOMEM;
            else if (o.query == Q_CLOSEST)
                st = geom_meshdist_closest(md, qs.v, nq, cp, idx, NULL, dist, o.threads, &diag);
            else
                st = geom_meshdist_signed_distance(md, qs.v, nq, dist, &rep, o.threads, &diag);
        }
        if (st != GEOM_OK && diag.message[0] == '\0')
            cli_diag_set(&diag, st, NULL, 0, 0, "%s", geom_status_str(st));
    }
    double query_s = cli_timer_elapsed(&timer);
    if (st == GEOM_OK) {
        FILE *fp = out.fp;
        if (o.query == Q_KNN) {
            for (size_t q = 0; q < nq; q++) {
                int firstv = 1;
                for (size_t j = 0; j < o.k; j++) {
                    uint32_t i = idx[q * o.k + j];
                    if (i == GEOM_INVALID_INDEX)
                        break;
                    if (!firstv)
                        fputc(' ', fp);
                    firstv = 0;
                    fprintf(fp, "%u", i);
                    if (o.distances) {
                        fputc(':', fp);
                        cli_print_double(fp, dist[q * o.k + j]);
                    }
                }
                fputc('\n', fp);
            }
        } else if (o.query == Q_RADIUS || o.query == Q_BOX) {
            for (size_t q = 0; q < nb.query_count; q++)
                print_row(fp, &nb, q, o.distances);
        } else if (o.query == Q_CLOSEST) {
            for (size_t q = 0; q < nq; q++) {
                for (int k = 0; k < 3; k++) {
                    cli_print_double(fp, cp[3 * q + (size_t)k] + 0.0);
                    fputc(' ', fp);
                }
                if (idx[q] == GEOM_INVALID_INDEX)
                    fputs("-1 ", fp);
                else
                    fprintf(fp, "%u ", idx[q]);
                cli_print_double(fp, dist[q]);
                fputc('\n', fp);
            }
        } else {
            for (size_t q = 0; q < nq; q++) {
                cli_print_double(fp, dist[q] + 0.0);
                fputc('\n', fp);
            }
        }
    }
    geom_kdtree_destroy(kd);
    geom_octree_destroy(oc);
    geom_meshdist_destroy(md);
    geom_neighbors_free(&nb);
    free(idx), free(dist), free(cp), free(pts.v), free(qs.v), free(tris);
    if (st != GEOM_OK) {
        cli_output_abort(&out);
        if (diag.source[0] == '\0' && strstr(diag.message, "query "))
            snprintf(diag.source, sizeof diag.source, "%s", o.queries ? o.queries : "<stdin>");
        return cli_print_diag(&tool, &diag);
    }
    if (cli_output_commit(&out, &diag) != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    if (common.json) {
        fprintf(stderr, "{\"index\":");
        cli_json_string(stderr, names[index]);
        fprintf(stderr, ",\"dim\":%d,\"points\":%zu,\"triangles\":%zu,\"queries\":%zu,\"build_seconds\":",
                dim, n, nt, o.query == Q_BOX ? (size_t)1 : nq);
        cli_json_number(stderr, build_s);
        fprintf(stderr, ",\"query_seconds\":");
        cli_json_number(stderr, query_s);
        fprintf(stderr, ",\"nodes\":%zu,\"depth\":%zu,\"bytes\":%zu", nodes, depth, bytes);
        if (o.query == Q_SD) {
            fprintf(stderr, ",\"winding_error_bound\":");
            cli_json_number(stderr, rep.max_error);
            fprintf(stderr, ",\"winding_error_method\":\"bound\"");
        }
        fprintf(stderr, "}\n");
    }
    return CLI_EXIT_OK;
}
