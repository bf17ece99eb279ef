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

/* Every mode reads rays in batches of BATCH and answers them with one
 * batch call (geom_ray_scene_closest_many: the traversals of a mesh's rays
 * interleaved; geom_ray_scene_any_many; geom_ray_scene_all_many), printing
 * the answers in input order. */
#define BATCH 4096

typedef struct batch {
    geom_ray *r;
    geom_ray_hit *h; /* closest: BATCH hits; all: hcap hits, grown as needed */
    int *found;
    size_t *off;     /* all: BATCH + 1 row offsets */
    size_t n, hcap;
} batch;

static geom_status batch_alloc(batch *b)
{
    b->r = malloc(BATCH * sizeof *b->r);
    b->hcap = BATCH;
    b->h = malloc(b->hcap * sizeof *b->h);
    b->found = malloc(BATCH * sizeof *b->found);
    b->off = malloc((BATCH + 1) * sizeof *b->off);
    b->n = 0;
    return b->r && b->h && b->found && b->off ? GEOM_OK : GEOM_ERR_NOMEM;
}

static void batch_free(batch *b)
{
    free(b->r);
    free(b->h);
    free(b->found);
    free(b->off);
}

static void print_closest(FILE *fp, const geom_ray_hit *h)
{
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

/* geom_ray_scene_all_many into b->h, grown to the batch's hit count when
 * it does not fit (then asked again). */
static geom_status all_many(const geom_ray_scene *scene, batch *b, size_t *count)
{
    geom_status st = geom_ray_scene_all_many(scene, b->r, b->n, b->off, b->h, b->hcap, count);
    if (st == GEOM_ERR_LIMIT) {
        size_t cap = *count + *count / 2;
        geom_ray_hit *nh = malloc(cap * sizeof *nh);
        if (!nh) return GEOM_ERR_NOMEM;
        free(b->h);
        b->h = nh;
        b->hcap = cap;
        st = geom_ray_scene_all_many(scene, b->r, b->n, b->off, b->h, b->hcap, count);
    }
    return st;
}

/* Answer and print the batch's rays in mode (0 closest, 1 any, 2 all;
 * invalid rays: miss), then empty it. */
static geom_status flush_batch(const geom_ray_scene *scene, int mode, FILE *fp, batch *b, size_t *nhit,
                               size_t *nhits_total, double *trace_s)
{
    cli_timer tt;
    geom_status st;
    size_t i, count = 0;
    cli_timer_start(&tt);
    if (mode == 0) st = geom_ray_scene_closest_many(scene, b->r, b->n, b->h, b->found);
    else if (mode == 1) st = geom_ray_scene_any_many(scene, b->r, b->n, b->found);
    else st = all_many(scene, b, &count);
    *trace_s += cli_timer_elapsed(&tt);
    if (st == GEOM_ERR_INVALID_ARG) st = GEOM_OK; /* some ray invalid: no hit, counted by the caller */
    if (st != GEOM_OK) return st;
    for (i = 0; i < b->n; i++) {
        if (mode == 2) {
            size_t j, k0 = b->off[i], k1 = b->off[i + 1];
            if (k0 == k1) {
                fputs("miss\n", fp);
                continue;
            }
            (*nhit)++;
            *nhits_total += k1 - k0;
            for (j = k0; j < k1; j++) {
                if (j > k0) fputc(' ', fp);
                pd(fp, b->h[j].t);
                fputs(b->h[j].enter ? " enter" : " leave", fp);
            }
            fputc('\n', fp);
            continue;
        }
        if (!b->found[i]) {
            fputs("miss\n", fp);
            continue;
        }
        (*nhit)++;
        if (mode == 1) fputs("hit\n", fp);
        else print_closest(fp, &b->h[i]);
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
    cli_timer tb;
    double build_s, trace_s = 0;
    cli_input in = {0};
    cli_output out = {0};
    cli_lines lines;
    size_t nrays = 0, ninvalid = 0, nhit = 0, nhits_total = 0;
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
    if (batch_alloc(&bat) != GEOM_OK) {
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
        /* batched (an invalid ray answers miss there) */
        ninvalid += geom_ray_check(&r) != GEOM_OK;
        bat.r[bat.n++] = r;
        if (bat.n == BATCH &&
            (st = flush_batch(scene, o.mode, out.fp, &bat, &nhit, &nhits_total, &trace_s)) != GEOM_OK)
            goto trace_fail;
        continue;
    trace_fail:
        rc = ray_failed(&tool, &diag, st, in.name, lines.lineno);
        break;
    }
    if (rc == CLI_EXIT_OK && bat.n > 0 &&
        (st = flush_batch(scene, o.mode, out.fp, &bat, &nhit, &nhits_total, &trace_s)) != GEOM_OK)
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
    batch_free(&bat);
    unload(scene, keep);
    return rc;
}
