/* geom-module: ray meshio */
/*
 * geom-raycast: intersect rays with a scene (JSON), a mesh or a surface
 * file. One ray a line in, one answer a line out.
 */
#include "cli.h"
#include "cli_mesh.h"
#include "geom/ray.h"
#ifdef GEOM_HAVE_CJSON
#include "scene_json.h"
#include "surface_json.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const cli_tool tool = {
    "geom-raycast",
    "[OPTION]... SCENE.json|MESH|SURFACE.json",
    "Intersect rays with every object of a scene file, a mesh (OBJ, OFF, PLY, STL)\n"
    "or a curve/surface JSON file (each surface one object).",
    "  -r, --rays=FILE    rays, one a line: ox oy oz dx dy dz [tmin [tmax]]\n"
    "                     (default: standard input; tmin 0, tmax +inf, inclusive)\n"
    "      --closest      the closest hit (default):\n"
    "                     t px py pz nx ny nz u v object primitive, or miss\n"
    "      --any          hit or miss\n"
    "      --all          every hit as 't enter|leave' pairs on one line, or miss\n"
    "      --json         add a JSON report (build time, rays per second, what\n"
    "                     was built) as the last line of standard error\n",
    "t is in units of the direction as given. The normal is the unit geometric\n"
    "normal with the stored orientation (outward for closed solids); 'enter' means\n"
    "d.n < 0. A ray with a zero-length or non-finite direction or origin answers\n"
    "'miss' and is counted as invalid. Numbers have 17 significant digits.\n",
    "  geom-raycast data/scenes/spheres.json --rays rays.txt --closest\n"
    "  geom-raycast mesh.obj --rays rays.txt --all --json -o hits.txt\n",
};

enum { OPT_CLOSEST = CLI_OPT_TOOL_BASE, OPT_ANY, OPT_ALL };

typedef struct opts {
    const char *rays;
    int mode; /* 0 closest, 1 any, 2 all */
} opts;

static int on_opt(const cli_tool *t, void *user, int opt, const char *arg)
{
    opts *o = user;
    (void)t;
    switch (opt) {
    case 'r': o->rays = arg; break;
    case OPT_CLOSEST: o->mode = 0; break;
    case OPT_ANY: o->mode = 1; break;
    case OPT_ALL: o->mode = 2; break;
    default: return CLI_EXIT_USAGE;
    }
    return CLI_CONTINUE;
}

static int ends_with(const char *s, const char *suf)
{
    size_t a = strlen(s), b = strlen(suf);
    return a >= b && strcmp(s + a - b, suf) == 0;
}

/* Load the input into a scene (not built). */
static geom_status load(const char *path, geom_ray_scene **scene, void **keep, geom_diag *diag)
{
    geom_status st;
    *keep = NULL;
    if (ends_with(path, ".json") || ends_with(path, ".JSON")) {
#ifdef GEOM_HAVE_CJSON
        /* A scene has "objects"; otherwise a curve/surface file. */
        scene_json_objects *so = calloc(1, sizeof *so);
        if (!so) return GEOM_ERR_NOMEM;
        st = scene_json_read_file(path, tool.name, so, diag);
        if (st == GEOM_OK) {
            *scene = so->scene;
            *keep = so;
            return GEOM_OK;
        }
        free(so);
        if (st == GEOM_ERR_PARSE && diag && strstr(diag->message, "expected an object {\"objects\"")) {
            sj_file f;
            size_t n, i;
            geom_ray_scene *s;
            geom_diag_clear(diag);
            if ((st = sj_read_file(path, &f, diag)) != GEOM_OK) return st;
            n = geom_surface_set_count(f.surfaces);
            s = geom_ray_scene_create(NULL);
            if (!s) {
                sj_free(&f);
                return GEOM_ERR_NOMEM;
            }
            for (i = 0; i < n && st == GEOM_OK; i++)
                st = geom_ray_scene_add_surface(s, &geom_surface_set_data(f.surfaces)[i], NULL, diag);
            sj_free(&f);
            if (st == GEOM_OK && n == 0) {
                st = GEOM_ERR_PARSE;
                if (diag) {
                    snprintf(diag->source, sizeof diag->source, "%s", path);
                    snprintf(diag->message, sizeof diag->message, "no \"objects\" and no \"surfaces\"");
                }
            }
            if (st != GEOM_OK) {
                geom_ray_scene_destroy(s);
                return st;
            }
            *scene = s;
        }
        return st;
#else
        if (diag) {
            snprintf(diag->source, sizeof diag->source, "%s", path);
            snprintf(diag->message, sizeof diag->message, "built without cJSON: JSON input unavailable");
        }
        return GEOM_ERR_INVALID_ARG;
#endif
    }
    {
        geom_mesh *m = NULL;
        geom_ray_scene *s;
        if ((st = cli_mesh_read(tool.name, path, GEOM_MESHIO_FORMAT_AUTO, &m, diag)) != GEOM_OK) return st;
        s = geom_ray_scene_create(NULL);
        if (!s) {
            geom_mesh_destroy(m);
            return GEOM_ERR_NOMEM;
        }
        st = geom_ray_scene_add_mesh(s, m, NULL);
        geom_mesh_destroy(m);
        if (st != GEOM_OK) {
            geom_ray_scene_destroy(s);
            return st;
        }
        *scene = s;
    }
    return GEOM_OK;
}

static void unload(geom_ray_scene *scene, void *keep)
{
#ifdef GEOM_HAVE_CJSON
    if (keep) {
        scene_json_free(keep);
        free(keep);
        return;
    }
#else
    (void)keep;
#endif
    geom_ray_scene_destroy(scene);
}

static void pd(FILE *fp, double v)
{
    cli_print_double(fp, v);
}

/* Closest mode reads rays in batches of BATCH and answers them with one
 * geom_ray_scene_closest_many call (the traversals of a mesh's rays
 * interleaved), printing the answers in input order. */
#define BATCH 4096

typedef struct batch {
    geom_ray *r;
    geom_ray_hit *h;
    int *found;
    size_t n;
} batch;

static geom_status batch_alloc(batch *b)
{
    b->r = malloc(BATCH * sizeof *b->r);
    b->h = malloc(BATCH * sizeof *b->h);
    b->found = malloc(BATCH * sizeof *b->found);
    b->n = 0;
    return b->r && b->h && b->found ? GEOM_OK : GEOM_ERR_NOMEM;
}

static void batch_free(batch *b)
{
    free(b->r);
    free(b->h);
    free(b->found);
}

/* Answer and print the batch's rays (invalid ones: miss), then empty it. */
static geom_status flush_closest(const geom_ray_scene *scene, FILE *fp, batch *b, size_t *nhit, double *trace_s)
{
    cli_timer tt;
    geom_status st;
    size_t i;
    cli_timer_start(&tt);
    st = geom_ray_scene_closest_many(scene, b->r, b->n, b->h, b->found);
    *trace_s += cli_timer_elapsed(&tt);
    if (st == GEOM_ERR_INVALID_ARG) st = GEOM_OK; /* some ray invalid: found 0, counted by the caller */
    if (st != GEOM_OK) return st;
    for (i = 0; i < b->n; i++) {
        const geom_ray_hit *h = &b->h[i];
        if (!b->found[i]) {
            fputs("miss\n", fp);
            continue;
        }
        (*nhit)++;
        pd(fp, h->t); fputc(' ', fp);
        pd(fp, h->point.x); fputc(' ', fp);
        pd(fp, h->point.y); fputc(' ', fp);
        pd(fp, h->point.z); fputc(' ', fp);
        pd(fp, h->ng.x); fputc(' ', fp);
        pd(fp, h->ng.y); fputc(' ', fp);
        pd(fp, h->ng.z); fputc(' ', fp);
        pd(fp, h->u); fputc(' ', fp);
        pd(fp, h->v);
        fprintf(fp, " %u %u\n", (unsigned)h->object, (unsigned)h->prim);
    }
    b->n = 0;
    return GEOM_OK;
}

/* A failed query: the status, located at the input line last read. */
static int ray_failed(const cli_tool *tool, geom_diag *diag, geom_status st, const char *name, size_t line)
{
    geom_diag_clear(diag);
    diag->status = st;
    snprintf(diag->message, sizeof diag->message, "ray failed: %s", geom_status_str(st));
    cli_diag_locate(diag, name, line);
    return cli_print_diag(tool, diag);
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"rays", required_argument, NULL, 'r'},
                                             {"closest", no_argument, NULL, OPT_CLOSEST},
                                             {"any", no_argument, NULL, OPT_ANY},
                                             {"all", no_argument, NULL, OPT_ALL},
                                             {NULL, 0, NULL, 0}};
    cli_common common;
    opts o = {NULL, 0};
    int first, rc = CLI_EXIT_ERROR;
    geom_ray_scene *scene = NULL;
    void *keep = NULL;
    geom_diag diag;
    geom_status st;
    geom_ray_build_info info;
    cli_timer tb, tt;
    double build_s, trace_s = 0;
    cli_input in = {0};
    cli_output out = {0};
    cli_lines lines;
    size_t nrays = 0, ninvalid = 0, nhit = 0, nhits_total = 0;
    geom_ray_hit *hits = NULL;
    size_t hcap = 0;
    batch bat = {0};
    rc = cli_parse_args(&tool, argc, argv, "r:", longopts, on_opt, &o, &common, &first);
    if (rc != CLI_CONTINUE) return rc;
    if (first >= argc) return cli_usage_error(&tool, "missing input file (scene, mesh or surface)");
    if (first + 1 < argc) return cli_usage_error(&tool, "extra operand '%s'", argv[first + 1]);
    geom_diag_clear(&diag);
    cli_timer_start(&tb);
    if ((st = load(argv[first], &scene, &keep, &diag)) != GEOM_OK) {
        if (!diag.message[0]) snprintf(diag.message, sizeof diag.message, "%s", geom_status_str(st));
        if (!diag.source[0]) snprintf(diag.source, sizeof diag.source, "%s", argv[first]);
        return cli_print_diag(&tool, &diag);
    }
    if ((st = geom_ray_scene_build(scene, NULL, &info, &diag)) != GEOM_OK) {
        if (!diag.message[0]) snprintf(diag.message, sizeof diag.message, "build: %s", geom_status_str(st));
        rc = cli_print_diag(&tool, &diag);
        unload(scene, keep);
        return rc;
    }
    build_s = cli_timer_elapsed(&tb);
    if ((st = cli_input_open(&in, o.rays, &diag)) != GEOM_OK) {
        rc = cli_print_diag(&tool, &diag);
        unload(scene, keep);
        return rc;
    }
    if ((st = cli_output_open(&out, common.output, &diag)) != GEOM_OK) {
        rc = cli_print_diag(&tool, &diag);
        cli_input_close(&in);
        unload(scene, keep);
        return rc;
    }
    cli_lines_init(&lines, in.fp, in.name);
    rc = CLI_EXIT_OK;
    if (o.mode == 0 && batch_alloc(&bat) != GEOM_OK) {
        geom_diag_clear(&diag);
        diag.status = GEOM_ERR_NOMEM;
        snprintf(diag.message, sizeof diag.message, "out of memory");
        rc = cli_print_diag(&tool, &diag);
        cli_lines_free(&lines);
        cli_input_close(&in);
        cli_output_abort(&out);
        unload(scene, keep);
        return rc;
    }
    for (;;) {
        char *line;
        size_t len, cnt = 0;
        double v[8];
        geom_ray r;
        int k = cli_lines_next(&lines, &line, &len, &diag);
        if (k == 0) break;
        if (k < 0) {
            rc = cli_print_diag(&tool, &diag);
            break;
        }
        if (cli_line_is_blank_or_comment(line, len)) continue;
        st = cli_parse_numbers(line, len, CLI_NUM_ALLOW_NONFINITE, v, 8, &cnt, &diag);
        if (st == GEOM_OK && (cnt < 6 || cnt > 8)) {
            geom_diag_clear(&diag);
            diag.status = st = GEOM_ERR_PARSE;
            snprintf(diag.message, sizeof diag.message,
                     "expected 6 to 8 numbers (ox oy oz dx dy dz [tmin [tmax]]), got %zu", cnt);
        }
        if (st != GEOM_OK) {
            cli_diag_locate(&diag, in.name, lines.lineno);
            rc = cli_print_diag(&tool, &diag);
            break;
        }
        r.origin = geom_vec3_make(v[0], v[1], v[2]);
        r.dir = geom_vec3_make(v[3], v[4], v[5]);
        r.tmin = cnt > 6 ? v[6] : 0;
        r.tmax = cnt > 7 ? v[7] : INFINITY;
        nrays++;
        if (o.mode == 0) { /* closest: batched (an invalid ray answers miss there too) */
            ninvalid += geom_ray_check(&r) != GEOM_OK;
            bat.r[bat.n++] = r;
            if (bat.n == BATCH && (st = flush_closest(scene, out.fp, &bat, &nhit, &trace_s)) != GEOM_OK)
                goto trace_fail;
            continue;
        }
        cli_timer_start(&tt);
        if (geom_ray_check(&r) != GEOM_OK) {
            ninvalid++;
            fputs("miss\n", out.fp);
            continue;
        }
        if (o.mode == 1) {
            int found = 0;
            st = geom_ray_scene_any(scene, &r, &found);
            trace_s += cli_timer_elapsed(&tt);
            if (st != GEOM_OK) goto trace_fail;
            nhit += found != 0;
            fputs(found ? "hit\n" : "miss\n", out.fp);
        } else {
            size_t n = 0, i;
            st = geom_ray_scene_all(scene, &r, hits, hcap, &n);
            if (st == GEOM_ERR_LIMIT) {
                geom_ray_hit *nh = realloc(hits, n * sizeof *nh);
                if (!nh) {
                    st = GEOM_ERR_NOMEM;
                } else {
                    hits = nh;
                    hcap = n;
                    st = geom_ray_scene_all(scene, &r, hits, hcap, &n);
                }
            }
            trace_s += cli_timer_elapsed(&tt);
            if (st != GEOM_OK) goto trace_fail;
            if (n == 0) {
                fputs("miss\n", out.fp);
                continue;
            }
            nhit++;
            nhits_total += n;
            for (i = 0; i < n; i++) {
                if (i) fputc(' ', out.fp);
                pd(out.fp, hits[i].t);
                fputs(hits[i].enter ? " enter" : " leave", out.fp);
            }
            fputc('\n', out.fp);
        }
        continue;
    trace_fail:
        rc = ray_failed(&tool, &diag, st, in.name, lines.lineno);
        break;
    }
    if (rc == CLI_EXIT_OK && bat.n > 0 && (st = flush_closest(scene, out.fp, &bat, &nhit, &trace_s)) != GEOM_OK)
        rc = ray_failed(&tool, &diag, st, in.name, lines.lineno);
    cli_lines_free(&lines);
    cli_input_close(&in);
    if (rc == CLI_EXIT_OK) {
        if (cli_output_commit(&out, &diag) != GEOM_OK) rc = cli_print_diag(&tool, &diag);
    } else {
        cli_output_abort(&out);
    }
    if (rc == CLI_EXIT_OK && common.json) {
        size_t i, nobj = geom_ray_scene_object_count(scene);
        FILE *e = stderr;
        fprintf(e, "{\"tool\":\"geom-raycast\",\"mode\":\"%s\",\"build_seconds\":",
                o.mode == 0 ? "closest" : o.mode == 1 ? "any" : "all");
        cli_json_number(e, build_s);
        fprintf(e, ",\"trace_seconds\":");
        cli_json_number(e, trace_s);
        fprintf(e, ",\"rays\":%zu,\"invalid_rays\":%zu,\"rays_hit\":%zu", nrays, ninvalid, nhit);
        if (o.mode == 2) fprintf(e, ",\"hits\":%zu", nhits_total);
        fprintf(e, ",\"rays_per_second\":");
        cli_json_number(e, trace_s > 0 ? (double)(nrays - ninvalid) / trace_s : 0);
        fprintf(e, ",\"built\":{\"bvhs\":%zu,\"triangles\":%zu,\"bvh_nodes\":%zu,\"bvh_bytes\":%zu,"
                   "\"bezier_patches\":%zu},\"objects\":[",
                info.meshes, info.triangles, info.bvh_nodes, info.bvh_bytes, info.bezier_patches);
        for (i = 0; i < nobj; i++) {
            uint32_t nid = geom_ray_scene_object_node(scene, i);
            geom_ray_kind k = geom_ray_scene_node_kind(scene, nid);
            const char *acc = (k == GEOM_RAY_MESH || k == GEOM_RAY_SUBDIV) ? "bvh"
                              : k == GEOM_RAY_SURFACE                     ? "bezier-patches"
                              : k == GEOM_RAY_VOLUME                      ? "3d-dda"
                              : k == GEOM_RAY_IMPLICIT                    ? "interval"
                              : k == GEOM_RAY_GROUP                       ? "per-member"
                                                                          : "none";
            fprintf(e, "%s{\"object\":%zu,\"type\":\"%s\",\"acceleration\":\"%s\"}", i ? "," : "", i,
                    geom_ray_kind_name(k), acc);
        }
        fprintf(e, "]}\n");
    }
    free(hits);
    batch_free(&bat);
    unload(scene, keep);
    return rc;
}
