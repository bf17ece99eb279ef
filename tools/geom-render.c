/* geom-module: scene */
/*
 * geom-render: render a scene file to PNG or PFM by Whitted ray tracing
 * (every representation traced directly) or z-buffer rasterization of a
 * tessellation sized to the pixel error; print what was built and how long
 * each stage took.
 */
#include "cli.h"
#include "geom/scene.h"
#ifdef GEOM_HAVE_SCENE_IO
#include "image_io.h"
#include "scene_render_json.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const cli_tool tool = {
    "geom-render",
    "[OPTION]... SCENE.json -o OUT.png|OUT.pfm",
    "Render a scene file (objects, camera, lights, materials) to an image.",
    "  -m, --method=ray|raster  Whitted ray tracing (default) or z-buffer\n"
    "                           rasterization of a tessellation\n"
    "      --aov=depth|normal|object  write that instead of colour (PFM: raw\n"
    "                           values; PNG: depth and normals mapped to [0,1],\n"
    "                           objects as distinct colours)\n"
    "      --pixel-error=P      raster: projected chordal error in pixels (0.5)\n"
    "      --tol=T              raster: a fixed world tolerance instead\n"
    "      --no-shadows         no shadow rays / shadow maps\n"
    "      --json               the report as one JSON object on standard output\n",
    "The report gives the time of each stage, the samples traced, the image's\n"
    "estimated error (standard error of the pixel means) and, per object, what\n"
    "was built: acceleration structure (ray), tessellation with its tolerance,\n"
    "achieved error and triangle count (raster; ray: subdivision surfaces and\n"
    "displaced objects), normals, UVs, tangents. On a terminal, progress (percent\n"
    "and ETA) goes to standard error while rays are traced; --quiet silences it.\n"
    "Objects that no ray can reach and the camera cannot see are not built.\n",
    "  geom-render data/scenes/spheres.json -o spheres.png\n"
    "  geom-render data/scenes/teapot.json --method raster -o teapot.png --json\n",
};

static void on_progress(void *user, double fraction)
{
    cli_progress_update(user, fraction);
}

enum { OPT_AOV = CLI_OPT_TOOL_BASE, OPT_PIXEL_ERROR, OPT_TOL, OPT_NO_SHADOWS };

typedef struct opts {
    geom_render_options r;
} opts;

static int on_opt(const cli_tool *t, void *user, int opt, const char *arg)
{
    opts *o = user;
    switch (opt) {
    case 'm':
        if (!strcmp(arg, "ray"))
            o->r.method = GEOM_RENDER_RAY;
        else if (!strcmp(arg, "raster"))
            o->r.method = GEOM_RENDER_RASTER;
        else
            return cli_usage_error(t, "--method: expected ray or raster, not '%s'", arg);
        break;
    case OPT_AOV:
        if (!strcmp(arg, "depth"))
            o->r.aov = GEOM_AOV_DEPTH;
        else if (!strcmp(arg, "normal"))
            o->r.aov = GEOM_AOV_NORMAL;
        else if (!strcmp(arg, "object"))
            o->r.aov = GEOM_AOV_OBJECT;
        else
            return cli_usage_error(t, "--aov: expected depth, normal or object, not '%s'", arg);
        break;
    case OPT_PIXEL_ERROR:
        return cli_positive_option(t, "--pixel-error", arg, &o->r.pixel_error);
    case OPT_TOL:
        return cli_positive_option(t, "--tol", arg, &o->r.tolerance);
    case OPT_NO_SHADOWS:
        o->r.no_shadows = 1;
        break;
    default:
        return CLI_EXIT_USAGE;
    }
    return CLI_CONTINUE;
}

#ifdef GEOM_HAVE_SCENE_IO
/* Map an AOV to something a PNG can show. */
static void aov_to_display(geom_image *img, geom_aov aov)
{
    size_t n = (size_t)img->width * img->height;
    if (aov == GEOM_AOV_NORMAL) {
        for (size_t i = 0; i < 3 * n; i++)
            img->data[i] = 0.5 * (img->data[i] + 1);
    } else if (aov == GEOM_AOV_DEPTH) {
        double lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < n; i++)
            if (isfinite(img->data[i])) {
                lo = fmin(lo, img->data[i]);
                hi = fmax(hi, img->data[i]);
            }
        for (size_t i = 0; i < n; i++)
            img->data[i] = isfinite(img->data[i]) ? 1 - 0.8 * (img->data[i] - lo) / (hi - lo + 1e-300) : 0;
    }
}

static geom_status object_colors(geom_image *img)
{
    geom_image c = {0};
    geom_status st = geom_scene_image_init(&c, img->width, img->height, 3, NULL);
    if (st != GEOM_OK)
        return st;
    for (size_t i = 0; i < (size_t)img->width * img->height; i++) {
        double id = img->data[i];
        if (id < 0)
            continue;
        unsigned h = (unsigned)id * 2654435761u;
        c.data[3 * i] = 0.25 + 0.75 * ((h >> 8) & 255) / 255.0;
        c.data[3 * i + 1] = 0.25 + 0.75 * ((h >> 16) & 255) / 255.0;
        c.data[3 * i + 2] = 0.25 + 0.75 * ((h >> 24) & 255) / 255.0;
    }
    geom_scene_image_free(img, NULL);
    *img = c;
    return GEOM_OK;
}

static void print_error_report(FILE *fp, const geom_error_report *e)
{
    static const char *const how[] = {"none", "bound", "sampled", "estimate"};
    fprintf(fp, "{\"max\": ");
    cli_json_number(fp, e->max_error);
    fprintf(fp, ", \"mean\": ");
    cli_json_number(fp, e->mean_error);
    fprintf(fp, ", \"method\": \"%s\", \"evaluations\": %zu}", how[e->method & 3], e->evaluations);
}

static void report_json(FILE *fp, const srj_file *f, const geom_render_options *ro,
                        const geom_render_report *r, const geom_render_object_report *orep,
                        double t_parse, double t_write, const geom_image *img)
{
    fprintf(fp, "{\"method\": \"%s\", \"width\": %u, \"height\": %u, ",
            ro->method == GEOM_RENDER_RAY ? "ray" : "raster", img->width, img->height);
    fprintf(fp, "\"seconds\": {\"parse\": ");
    cli_json_number(fp, t_parse);
    fprintf(fp, ", \"build\": ");
    cli_json_number(fp, r->seconds_build);
    fprintf(fp, ", \"render\": ");
    cli_json_number(fp, r->seconds_render);
    if (ro->method == GEOM_RENDER_RASTER) {
        fprintf(fp, ", \"shadow_maps\": ");
        cli_json_number(fp, r->raster.seconds_shadow);
        fprintf(fp, ", \"clip\": ");
        cli_json_number(fp, r->raster.seconds_clip);
        fprintf(fp, ", \"raster\": ");
        cli_json_number(fp, r->raster.seconds_raster);
        fprintf(fp, ", \"shade\": ");
        cli_json_number(fp, r->raster.seconds_shade);
    }
    fprintf(fp, ", \"write\": ");
    cli_json_number(fp, t_write);
    fprintf(fp, "}, \"objects_needed\": %zu, \"reflection\": %s, \"refraction\": %s, ",
            r->objects_needed, r->reflection ? "true" : "false", r->refraction ? "true" : "false");
    if (ro->method == GEOM_RENDER_RAY) {
        const geom_trace_report *t = &r->trace;
        fprintf(fp, "\"rays\": {\"primary\": %zu, \"shadow\": %zu, \"reflection\": %zu, "
                    "\"refraction\": %zu, \"total_internal_reflections\": %zu, "
                    "\"cut_by_depth\": %zu, \"cut_by_weight\": %zu}, ",
                t->primary_rays, t->shadow_rays, t->reflection_rays, t->refraction_rays,
                t->total_internal_reflections, t->cut_by_depth, t->cut_by_weight);
        fprintf(fp, "\"samples\": {\"mean_per_pixel\": ");
        cli_json_number(fp, t->mean_samples_per_pixel);
        fprintf(fp, ", \"max_per_pixel\": %u}, \"image_error\": ", t->max_samples_per_pixel);
        print_error_report(fp, &t->image_error);
        fprintf(fp, ", \"ray_build\": {\"meshes\": %zu, \"triangles\": %zu, \"bvh_nodes\": %zu, "
                    "\"bvh_bytes\": %zu, \"bezier_patches\": %zu, \"analytic\": %zu}, ",
                r->ray_build.meshes, r->ray_build.triangles, r->ray_build.bvh_nodes,
                r->ray_build.bvh_bytes, r->ray_build.bezier_patches, r->ray_build.analytic);
    } else {
        const geom_raster_report *t = &r->raster;
        fprintf(fp, "\"raster\": {\"triangles_in\": %zu, \"triangles_clipped\": %zu, "
                    "\"fragments\": %zu, \"shadow_maps\": %zu, \"samples_per_pixel\": %u}, ",
                t->triangles_in, t->triangles_clipped, t->fragments, t->shadow_maps,
                t->samples_per_pixel);
    }
    fprintf(fp, "\"objects\": [");
    for (size_t i = 0; i < f->n_objects; i++) {
        const geom_render_object_report *o = &orep[i];
        fprintf(fp, "%s\n  {\"name\": ", i ? "," : "");
        cli_json_string(fp, f->names[i]);
        fprintf(fp, ", \"kind\": \"%s\", \"visible\": %s, \"built\": %s, \"acceleration\": %s",
                geom_scene_shapes_kind_name(f->shapes, i), o->visible ? "true" : "false",
                o->needed ? "true" : "false", o->acceleration ? "true" : "false");
        fprintf(fp, ", \"tessellated\": %s", o->tessellated ? "true" : "false");
        if (o->tessellated) {
            fprintf(fp, ", \"tolerance\": ");
            cli_json_number(fp, o->tolerance);
            fprintf(fp, ", \"tessellation\": {\"method\": \"%s\", \"triangles\": %zu, \"seconds\": ",
                    o->tess.method ? o->tess.method : "", o->tess.triangles);
            cli_json_number(fp, o->tess.seconds);
            fprintf(fp, ", \"error\": ");
            print_error_report(fp, &o->tess.error);
            fprintf(fp, "}");
        }
        fprintf(fp, ", \"normals\": %s, \"uvs\": %s, \"tangents\": %s}", o->normals ? "true" : "false",
                o->uvs ? "true" : "false", o->tangents ? "true" : "false");
    }
    fprintf(fp, "\n]}\n");
}

static void report_text(FILE *fp, const srj_file *f, const geom_render_options *ro,
                        const geom_render_report *r, const geom_render_object_report *orep,
                        double t_parse, double t_write)
{
    fprintf(fp, "method: %s\n", ro->method == GEOM_RENDER_RAY ? "ray" : "raster");
    fprintf(fp, "time: parse %.3f s, build %.3f s, render %.3f s, write %.3f s\n", t_parse,
            r->seconds_build, r->seconds_render, t_write);
    fprintf(fp, "objects: %zu of %zu built\n", r->objects_needed, f->n_objects);
    if (ro->method == GEOM_RENDER_RAY) {
        const geom_trace_report *t = &r->trace;
        fprintf(fp, "rays: %zu primary, %zu shadow, %zu reflection, %zu refraction (%zu TIR)\n",
                t->primary_rays, t->shadow_rays, t->reflection_rays, t->refraction_rays,
                t->total_internal_reflections);
        fprintf(fp, "samples: %.3g per pixel (max %u), estimated image error max %.3g mean %.3g\n",
                t->mean_samples_per_pixel, t->max_samples_per_pixel, t->image_error.max_error,
                t->image_error.mean_error);
    } else {
        fprintf(fp, "raster: %zu triangles in, %zu after clipping, %zu fragments, %zu shadow maps\n",
                r->raster.triangles_in, r->raster.triangles_clipped, r->raster.fragments,
                r->raster.shadow_maps);
    }
    for (size_t i = 0; i < f->n_objects; i++) {
        const geom_render_object_report *o = &orep[i];
        fprintf(fp, "  %s (%s): %s%s", f->names[i], geom_scene_shapes_kind_name(f->shapes, i),
                o->visible ? "visible" : "not visible", o->needed ? "" : ", not built");
        if (o->acceleration)
            fprintf(fp, ", BVH");
        if (o->tessellated)
            fprintf(fp, ", %s tessellation tol %.3g error %.3g, %zu triangles in %.3f s",
                    o->tess.method, o->tolerance, o->tess.error.max_error, o->tess.triangles,
                    o->tess.seconds);
        if (o->needed)
            fprintf(fp, "%s%s", o->uvs ? ", uvs" : "", o->tangents ? ", tangents" : "");
        fprintf(fp, "\n");
    }
}
#endif

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"method", required_argument, NULL, 'm'},
                                             {"aov", required_argument, NULL, OPT_AOV},
                                             {"pixel-error", required_argument, NULL, OPT_PIXEL_ERROR},
                                             {"tol", required_argument, NULL, OPT_TOL},
                                             {"no-shadows", no_argument, NULL, OPT_NO_SHADOWS},
                                             {NULL, 0, NULL, 0}};
    cli_common common;
    opts o;
    memset(&o, 0, sizeof o);
    int first;
    int rc = cli_parse_args(&tool, argc, argv, "m:", longopts, on_opt, &o, &common, &first);
    if (rc != CLI_CONTINUE)
        return rc;
    if (first >= argc)
        return cli_usage_error(&tool, "missing scene file");
    if (first + 1 < argc)
        return cli_usage_error(&tool, "extra operand '%s'", argv[first + 1]);
    if (!common.output || !strcmp(common.output, "-"))
        return cli_usage_error(&tool, "-o OUT.png or OUT.pfm is required");
#ifndef GEOM_HAVE_SCENE_IO
    return cli_error(&tool, "built without libspng/cJSON: rendering unavailable");
#else
    const char *out = common.output;
    size_t ol = strlen(out);
    int pfm = ol > 4 && !strcmp(out + ol - 4, ".pfm");
    int png = ol > 4 && !strcmp(out + ol - 4, ".png");
    if (!pfm && !png)
        return cli_usage_error(&tool, "-o: the output must end in .png or .pfm");
    geom_diag diag;
    geom_diag_clear(&diag);
    cli_timer t;
    cli_timer_start(&t);
    srj_file f;
    geom_status st = srj_load(argv[first], tool.name, &f, &diag);
    if (st != GEOM_OK)
        return cli_print_diag(&tool, &diag);
    double t_parse = cli_timer_elapsed(&t);
    o.r.background = f.render.background;
    geom_render_report rep;
    geom_render_object_report *orep = calloc(f.n_objects ? f.n_objects : 1, sizeof *orep);
    geom_image img = {0};
    if (!orep) {
        srj_file_free(&f);
        return cli_error(&tool, "out of memory");
    }
    /* percent and ETA on a terminal's stderr while rays are traced */
    cli_progress prog;
    cli_progress_start(&prog, &tool, "rendering", common.quiet);
    if (o.r.method == GEOM_RENDER_RAY) {
        o.r.progress = on_progress;
        o.r.progress_user = &prog;
    }
    st = geom_scene_render(&f.render.camera, f.render.lights, f.render.n_lights, f.render.materials,
                           f.render.n_materials, f.objects, f.n_objects, &o.r, &img, &rep, orep,
                           &diag);
    cli_progress_done(&prog);
    if (st != GEOM_OK) {
        if (!diag.message[0])
            snprintf(diag.message, sizeof diag.message, "rendering failed: %s", geom_status_str(st));
        snprintf(diag.source, sizeof diag.source, "%s", argv[first]);
        rc = cli_print_diag(&tool, &diag);
        free(orep);
        srj_file_free(&f);
        return rc;
    }
    cli_timer_start(&t);
    if (png && o.r.aov == GEOM_AOV_OBJECT)
        st = object_colors(&img);
    else if (png)
        aov_to_display(&img, o.r.aov);
    if (st == GEOM_OK)
        st = image_write_file(out, &img, o.r.aov == GEOM_AOV_COLOR || o.r.aov == GEOM_AOV_OBJECT, &diag);
    double t_write = cli_timer_elapsed(&t);
    if (st != GEOM_OK) {
        if (!diag.source[0])
            snprintf(diag.source, sizeof diag.source, "%s", out);
        rc = cli_print_diag(&tool, &diag);
    } else {
        if (common.json)
            report_json(stdout, &f, &o.r, &rep, orep, t_parse, t_write, &img);
        else
            report_text(stdout, &f, &o.r, &rep, orep, t_parse, t_write);
        rc = CLI_EXIT_OK;
    }
    geom_scene_image_free(&img, NULL);
    free(orep);
    srj_file_free(&f);
    return rc;
#endif
}
