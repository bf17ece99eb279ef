/* geom-module: scene meshio */
/*
 * geom-scene: tessellate every object of a scene file into one mesh for
 * renderers (glTF binary or OBJ), each object to the tolerance its
 * picture needs, with only the attributes its material uses.
 */
#include "cli.h"
#include "cli_mesh.h"
#include "geom/meshio.h"
#include "geom/scene.h"
#ifdef GEOM_HAVE_SCENE_IO
#include "scene_render_json.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const cli_tool tool = {
    "geom-scene",
    "[OPTION]... SCENE.json --export OUT.glb|OUT.obj",
    "Tessellate every object of a scene file (surfaces, subdivision limits,\n"
    "implicit and volume isosurfaces, CSG through implicit forms, analytic\n"
    "shapes) into one mesh, transforms applied.",
    "  -e, --export=FILE      OUT.glb (Y-up: a Z-up scene is turned) or OUT.obj\n"
    "      --tol=T            one world tolerance for every object\n"
    "      --pixel-error=P    tolerance from the camera: projected chordal error\n"
    "                         below P pixels where the object is seen (default 0.5)\n"
    "      --json             the report as one JSON object on standard output\n"
    CLI_LIMIT_HELP,
    "Each object becomes an OBJ object / glTF face group, with normals always,\n"
    "UVs where its material has a texture or map, tangents for normal and bump\n"
    "maps. The report gives per object the tolerance, the achieved error and\n"
    "the time. A CSG object whose children have no implicit form (meshes,\n"
    "surfaces) is an error naming it.\n",
    "  geom-scene data/scenes/csg.json --export csg.glb\n"
    "  geom-scene data/scenes/teapot.json --export teapot.obj --pixel-error 0.5 --json\n",
};

enum { OPT_TOL = CLI_OPT_TOOL_BASE, OPT_PIXEL_ERROR };

/* Peak bytes per exported triangle: measured 426 (GLB) and 307 (OBJ) on
 * data/scenes/spheres.json at --tol 1e-4 (499,806 triangles, 213 MB and
 * 154 MB peak). */
#define EXPORT_BYTES_PER_TRIANGLE 450.0

typedef struct opts {
    const char *export_path;
    geom_export_options e;
    cli_limits lim;
} opts;

static int on_opt(const cli_tool *t, void *user, int opt, const char *arg)
{
    opts *o = user;
    int lrc = cli_limits_option(t, &o->lim, opt, arg);
    if (lrc != CLI_NOT_HANDLED)
        return lrc;
    switch (opt) {
    case 'e':
        o->export_path = arg;
        break;
    case OPT_TOL:
        return cli_positive_option(t, "--tol", arg, &o->e.tolerance);
    case OPT_PIXEL_ERROR:
        return cli_positive_option(t, "--pixel-error", arg, &o->e.pixel_error);
    default:
        return CLI_EXIT_USAGE;
    }
    return CLI_CONTINUE;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"export", required_argument, NULL, 'e'},
                                             {"tol", required_argument, NULL, OPT_TOL},
                                             {"pixel-error", required_argument, NULL, OPT_PIXEL_ERROR},
                                             CLI_LIMIT_LONGOPTS,
                                             {NULL, 0, NULL, 0}};
    cli_common common;
    opts o;
    memset(&o, 0, sizeof o);
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "e:", longopts, on_opt, &o, &common, &first);
    if (rc != CLI_CONTINUE)
        return rc;
    if (first >= argc)
        return cli_usage_error(&tool, "missing scene file");
    if (first + 1 < argc)
        return cli_usage_error(&tool, "extra operand '%s'", argv[first + 1]);
    if (!o.export_path)
        return cli_usage_error(&tool, "--export OUT.glb or OUT.obj is required");
    size_t pl = strlen(o.export_path);
    int glb = pl > 4 && !strcmp(o.export_path + pl - 4, ".glb");
    int obj = pl > 4 && !strcmp(o.export_path + pl - 4, ".obj");
    if (!glb && !obj)
        return cli_usage_error(&tool, "--export: the output must end in .glb or .obj");
#ifndef GEOM_HAVE_SCENE_IO
    return cli_error(&tool, "built without cJSON/libspng: scene files unavailable");
#else
    geom_diag diag;
    geom_diag_clear(&diag);
    cli_timer t;
    cli_timer_start(&t);
    srj_file f;
    geom_status st = srj_load(argv[first], tool.name, &f, &diag);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    double t_parse = cli_timer_elapsed(&t);
    /* glTF is Y-up: turn a Z-up scene (camera up along z) by -90 degrees about x */
    geom_vec3 up = f.render.camera.up;
    int zup = fabs(up.z) > fabs(up.x) && fabs(up.z) > fabs(up.y);
    if (glb && zup)
        geom_mat4_rotate(geom_vec3_make(1, 0, 0), -1.5707963267948966, &o.e.world);
    geom_export_object_report *rep = calloc(f.n_objects ? f.n_objects : 1, sizeof *rep);
    geom_mesh *m = geom_mesh_create(NULL);
    if (!rep || !m) {
        free(rep);
        geom_mesh_destroy(m);
        srj_file_free(&f);
        return cli_error(&tool, "out of memory");
    }
    /* the output's size before the work: the sum of the objects' estimates
     * at their tolerances, against --max-triangles; memory (the objects'
     * meshes, the joined soup and mesh with their corner channels: about
     * EXPORT_BYTES_PER_TRIANGLE) against --max-memory */
    double est = 0;
    double *per = calloc(f.n_objects ? f.n_objects : 1, sizeof *per);
    if (!per) {
        free(rep);
        geom_mesh_destroy(m);
        srj_file_free(&f);
        return cli_error(&tool, "out of memory");
    }
    /* the limits as triangles: the exact marching-cubes trials run only
     * when the cheap bounds could be above them */
    size_t lim_t = o.lim.max_triangles ? o.lim.max_triangles : CLI_MAX_TRIANGLES_DEFAULT;
    size_t lim_m = o.lim.max_memory ? o.lim.max_memory : CLI_MAX_MEMORY_DEFAULT;
    o.e.max_triangles = fmin((double)lim_t, (double)lim_m / EXPORT_BYTES_PER_TRIANGLE);
    if (geom_scene_export_estimate(&f.render.camera, f.render.materials, f.render.n_materials,
                                   f.objects, f.n_objects, &o.e, per, &est, NULL) == GEOM_OK) {
        size_t worst = 0;
        for (size_t i = 1; i < f.n_objects; i++)
            worst = per[i] > per[worst] ? i : worst;
        char what[512];
        snprintf(what, sizeof what, "%s: the export (%zu objects; the largest, %s, about %.0f)",
                 argv[first], f.n_objects, f.n_objects ? f.names[worst] : "-",
                 f.n_objects ? per[worst] : 0.0);
        if (cli_limits_check(&tool, &o.lim, what, est, est * EXPORT_BYTES_PER_TRIANGLE) !=
            CLI_CONTINUE) {
            free(per);
            free(rep);
            geom_mesh_destroy(m);
            srj_file_free(&f);
            return CLI_EXIT_ERROR;
        }
    }
    free(per);
    cli_timer_start(&t);
    st = geom_scene_export(&f.render.camera, f.render.materials, f.render.n_materials, f.objects,
                           f.n_objects, (const char *const *)f.names, &o.e, m, rep, &diag);
    double t_tess = cli_timer_elapsed(&t);
    cli_timer_start(&t);
    if (st == GEOM_OK)
        st = cli_mesh_write(m, o.export_path, GEOM_MESHIO_FORMAT_AUTO, &diag);
    double t_write = cli_timer_elapsed(&t);
    if (st != GEOM_OK) {
        if (!diag.source[0])
            snprintf(diag.source, sizeof diag.source, "%s", argv[first]);
        rc = cli_print_diag(&tool, &diag);
    } else {
        FILE *fp = stdout;
        size_t tris = geom_mesh_n_live_faces(m);
        if (common.json) {
            fprintf(fp, "{\"output\": ");
            cli_json_string(fp, o.export_path);
            fprintf(fp, ", \"y_up_turned\": %s, \"triangles\": %zu, \"estimated_triangles\": ",
                    glb && zup ? "true" : "false", tris);
            cli_json_number(fp, est);
            fprintf(fp, ", \"vertices\": %zu, \"seconds\": {\"parse\": ", geom_mesh_n_vertices(m));
            cli_json_number(fp, t_parse);
            fprintf(fp, ", \"tessellate\": ");
            cli_json_number(fp, t_tess);
            fprintf(fp, ", \"write\": ");
            cli_json_number(fp, t_write);
            fprintf(fp, "}, \"objects\": [");
            for (size_t i = 0; i < f.n_objects; i++) {
                static const char *const how[] = {"none", "bound", "sampled", "estimate"};
                fprintf(fp, "%s\n  {\"name\": ", i ? "," : "");
                cli_json_string(fp, f.names[i]);
                fprintf(fp, ", \"kind\": \"%s\", \"method\": \"%s\", \"tolerance\": ",
                        geom_scene_shapes_kind_name(f.shapes, i),
                        rep[i].tess.method ? rep[i].tess.method : "");
                cli_json_number(fp, rep[i].tolerance);
                fprintf(fp, ", \"error\": ");
                cli_json_number(fp, rep[i].tess.error.max_error);
                fprintf(fp, ", \"error_method\": \"%s\", \"triangles\": %zu, \"seconds\": ",
                        how[rep[i].tess.error.method & 3], rep[i].tess.triangles);
                cli_json_number(fp, rep[i].tess.seconds);
                fprintf(fp, ", \"normals\": true, \"uvs\": %s, \"tangents\": %s}",
                        rep[i].attributes & GEOM_NEEDS_UV ? "true" : "false",
                        rep[i].attributes & GEOM_NEEDS_TANGENT ? "true" : "false");
            }
            fprintf(fp, "\n]}\n");
        } else {
            fprintf(fp, "wrote %s: %zu triangles, %zu vertices%s\n", o.export_path, tris,
                    geom_mesh_n_vertices(m), glb && zup ? " (Z-up turned to glTF's Y-up)" : "");
            fprintf(fp, "time: parse %.3f s, tessellate %.3f s, write %.3f s\n", t_parse, t_tess, t_write);
            for (size_t i = 0; i < f.n_objects; i++)
                fprintf(fp, "  %s (%s): %s, tol %.3g, error %.3g, %zu triangles, %.3f s%s%s\n",
                        f.names[i], geom_scene_shapes_kind_name(f.shapes, i),
                        rep[i].tess.method ? rep[i].tess.method : "?", rep[i].tolerance,
                        rep[i].tess.error.max_error, rep[i].tess.triangles, rep[i].tess.seconds,
                        rep[i].attributes & GEOM_NEEDS_UV ? ", uvs" : "",
                        rep[i].attributes & GEOM_NEEDS_TANGENT ? ", tangents" : "");
        }
        rc = CLI_EXIT_OK;
    }
    geom_mesh_destroy(m);
    free(rep);
    srj_file_free(&f);
    return rc;
#endif
}
