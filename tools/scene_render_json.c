/* Camera, lights and materials of a scene JSON file. */
#include "scene_render_json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "image_io.h"
#include "scene_json.h"
#include "surface_json.h"

static geom_status fail(const char *src, geom_diag *d, const char *where, const char *msg)
{
    return cli_diag_set(d, GEOM_ERR_PARSE, src, 0, 0, "%s: %s", where, msg);
}

static geom_status get_vec3(const cJSON *o, const char *key, int allow_scalar, geom_vec3 *out,
                            const char *src, const char *where, geom_diag *d)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    char w[256];
    snprintf(w, sizeof w, "%s.%s", where, key);
    if (!v)
        return GEOM_OK;
    if (allow_scalar && cJSON_IsNumber(v)) {
        if (!isfinite(v->valuedouble))
            return fail(src, d, w, "expected a finite number");
        *out = geom_vec3_make(v->valuedouble, v->valuedouble, v->valuedouble);
        return GEOM_OK;
    }
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return fail(src, d, w, allow_scalar ? "expected a number or 3 numbers" : "expected 3 numbers");
    double a[3];
    for (int i = 0; i < 3; i++) {
        const cJSON *e = cJSON_GetArrayItem(v, i);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return fail(src, d, w, "expected 3 finite numbers");
        a[i] = e->valuedouble;
    }
    *out = geom_vec3_make(a[0], a[1], a[2]);
    return GEOM_OK;
}

static geom_status get_num(const cJSON *o, const char *key, double lo, double hi, double *out,
                           const char *src, const char *where, geom_diag *d)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v)
        return GEOM_OK;
    char w[256];
    snprintf(w, sizeof w, "%s.%s", where, key);
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return fail(src, d, w, "expected a number");
    if (v->valuedouble < lo || v->valuedouble > hi) {
        char m[128];
        snprintf(m, sizeof m, "%g is outside [%g, %g]", v->valuedouble, lo, hi);
        return fail(src, d, w, m);
    }
    *out = v->valuedouble;
    return GEOM_OK;
}

static geom_status get_u32(const cJSON *o, const char *key, uint32_t lo, uint32_t hi,
                           uint32_t *out, const char *src, const char *where, geom_diag *d)
{
    double x = NAN;
    geom_status st = get_num(o, key, lo, hi, &x, src, where, d);
    if (st != GEOM_OK || isnan(x))
        return st;
    if (x != floor(x)) {
        char w[256];
        snprintf(w, sizeof w, "%s.%s", where, key);
        return fail(src, d, w, "expected an integer");
    }
    *out = (uint32_t)x;
    return GEOM_OK;
}

/* A string key's value among `names` (index), -1 when absent. */
static geom_status get_enum(const cJSON *o, const char *key, const char *const *names, int n,
                            int *out, const char *src, const char *where, geom_diag *d)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v)
        return GEOM_OK;
    char w[256];
    snprintf(w, sizeof w, "%s.%s", where, key);
    if (cJSON_IsString(v))
        for (int i = 0; i < n; i++)
            if (!strcmp(v->valuestring, names[i])) {
                *out = i;
                return GEOM_OK;
            }
    char m[256] = "expected one of";
    for (int i = 0; i < n; i++) {
        strncat(m, i ? ", \"" : " \"", sizeof m - strlen(m) - 1);
        strncat(m, names[i], sizeof m - strlen(m) - 1);
        strncat(m, "\"", sizeof m - strlen(m) - 1);
    }
    return fail(src, d, w, m);
}

static geom_status parse_camera(const cJSON *c, const char *src, geom_camera *cam, geom_diag *d)
{
    const char *w = "camera";
    if (!cJSON_IsObject(c))
        return fail(src, d, w, "expected an object");
    memset(cam, 0, sizeof *cam);
    cam->eye = geom_vec3_make(0, 0, 5);
    geom_status st;
    if ((st = get_vec3(c, "eye", 0, &cam->eye, src, w, d)) ||
        (st = get_vec3(c, "center", 0, &cam->center, src, w, d)) ||
        (st = get_vec3(c, "up", 0, &cam->up, src, w, d)) ||
        (st = get_num(c, "fovy", 1e-6, 179.999, &cam->fovy_degrees, src, w, d)) ||
        (st = get_num(c, "ortho_height", 1e-300, 1e300, &cam->ortho_height, src, w, d)) ||
        (st = get_u32(c, "width", 1, 16384, &cam->width, src, w, d)) ||
        (st = get_u32(c, "height", 1, 16384, &cam->height, src, w, d)) ||
        (st = get_u32(c, "samples", 1, 4096, &cam->samples, src, w, d)))
        return st;
    static const char *const proj[] = {"perspective", "orthographic"};
    static const char *const smp[] = {"regular", "jittered"};
    int p = 0, s = 0;
    if ((st = get_enum(c, "projection", proj, 2, &p, src, w, d)) ||
        (st = get_enum(c, "sampling", smp, 2, &s, src, w, d)))
        return st;
    cam->projection = (geom_projection)p;
    cam->sampling = (geom_sampling)s;
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(c, "adaptive");
    if (a) {
        if (!cJSON_IsObject(a))
            return fail(src, d, "camera.adaptive", "expected an object");
        cam->sampling = GEOM_SAMPLING_ADAPTIVE;
        if ((st = get_u32(a, "max_samples", 1, 4096, &cam->max_samples, src, "camera.adaptive", d)) ||
            (st = get_num(a, "tolerance", 1e-12, 1, &cam->tolerance, src, "camera.adaptive", d)))
            return st;
    }
    geom_ray r;
    st = geom_scene_camera_ray(cam, 0.5, 0.5, &r);
    if (st != GEOM_OK)
        return fail(src, d, w, st == GEOM_ERR_DEGENERATE
                                   ? "eye equals center, or up is parallel to the view direction"
                                   : "invalid field of view or orthographic height");
    return GEOM_OK;
}

static geom_status parse_lights(const cJSON *ls, const char *src, srj_scene *s, geom_diag *d)
{
    if (!cJSON_IsArray(ls))
        return fail(src, d, "lights", "expected an array");
    size_t n = (size_t)cJSON_GetArraySize(ls);
    s->lights = calloc(n ? n : 1, sizeof(geom_light));
    if (!s->lights)
        return cli_diag_set(d, GEOM_ERR_NOMEM, src, 0, 0, "out of memory");
    size_t i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, ls)
    {
        char w[64];
        snprintf(w, sizeof w, "lights[%zu]", i);
        if (!cJSON_IsObject(e))
            return fail(src, d, w, "expected an object");
        static const char *const kinds[] = {"point", "directional", "ambient"};
        int k = -1;
        geom_status st = get_enum(e, "type", kinds, 3, &k, src, w, d);
        if (st)
            return st;
        if (k < 0)
            return fail(src, d, w, "missing \"type\"");
        geom_light *L = &s->lights[i];
        L->kind = (geom_light_kind)k;
        L->color = geom_vec3_make(1, 1, 1);
        L->direction = geom_vec3_make(0, 0, -1);
        if ((st = get_vec3(e, "color", 1, &L->color, src, w, d)) ||
            (st = get_vec3(e, "position", 0, &L->position, src, w, d)) ||
            (st = get_vec3(e, "direction", 0, &L->direction, src, w, d)))
            return st;
        if (k == 0 && !cJSON_GetObjectItemCaseSensitive(e, "position"))
            return fail(src, d, w, "a point light needs \"position\"");
        if (k == 1) {
            geom_vec3 u;
            if (geom_vec3_normalize(L->direction, &u) != GEOM_OK)
                return fail(src, d, w, "\"direction\" must be a non-zero vector");
            L->direction = u;
        }
        i++;
    }
    s->n_lights = n;
    return GEOM_OK;
}

/* Directory part of path (with the trailing slash) joined to rel. */
static char *join_path(const char *scene_path, const char *rel)
{
    if (rel[0] == '/' || !scene_path)
        return strdup(rel);
    const char *slash = strrchr(scene_path, '/');
    size_t dl = slash ? (size_t)(slash - scene_path + 1) : 0;
    char *p = malloc(dl + strlen(rel) + 1);
    if (!p)
        return NULL;
    memcpy(p, scene_path, dl);
    strcpy(p + dl, rel);
    return p;
}

static geom_status get_texture(const cJSON *o, const char *key, geom_wrap wrap, int srgb,
                               srj_scene *s, const char *src, const char *where,
                               const geom_texture **out, geom_diag *d)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v)
        return GEOM_OK;
    char w[256];
    snprintf(w, sizeof w, "%s.%s", where, key);
    if (!cJSON_IsString(v) || !v->valuestring[0])
        return fail(src, d, w, "expected an image file name");
    char *path = join_path(src, v->valuestring);
    if (!path)
        return cli_diag_set(d, GEOM_ERR_NOMEM, src, 0, 0, "out of memory");
    char tag[8];
    snprintf(tag, sizeof tag, "|%d%d", (int)wrap, srgb);
    size_t pl = strlen(path);
    for (size_t i = 0; i < s->n_textures; i++)
        if (!strncmp(s->texture_paths[i], path, pl) && !strcmp(s->texture_paths[i] + pl, tag)) {
            *out = s->textures[i];
            free(path);
            return GEOM_OK;
        }
    geom_image img;
    geom_diag d2;
    geom_diag_clear(&d2);
    geom_status st = image_read_file(path, srgb, &img, &d2);
    if (st != GEOM_OK) {
        cli_diag_set(d, st, src, 0, 0, "%s: %s: %s", w, path, d2.message);
        free(path);
        return st;
    }
    geom_texture *t = NULL;
    st = geom_scene_texture_create(&img, wrap, NULL, &t);
    geom_scene_image_free(&img, NULL);
    if (st != GEOM_OK) {
        cli_diag_set(d, st, src, 0, 0, "%s: %s: %s", w, path, geom_status_str(st));
        free(path);
        return st;
    }
    geom_texture **nt = realloc(s->textures, (s->n_textures + 1) * sizeof *nt);
    char **np = nt ? realloc(s->texture_paths, (s->n_textures + 1) * sizeof *np) : NULL;
    char *full = malloc(pl + strlen(tag) + 1);
    if (nt)
        s->textures = nt;
    if (np)
        s->texture_paths = np;
    if (!nt || !np || !full) {
        free(full);
        free(path);
        geom_scene_texture_destroy(t);
        return cli_diag_set(d, GEOM_ERR_NOMEM, src, 0, 0, "out of memory");
    }
    strcpy(full, path);
    strcat(full, tag);
    free(path);
    s->textures[s->n_textures] = t;
    s->texture_paths[s->n_textures] = full;
    s->n_textures++;
    *out = t;
    return GEOM_OK;
}

static geom_status parse_material(const cJSON *e, const char *name, const char *src, srj_scene *s,
                                  geom_material *m, geom_diag *d)
{
    char w[192];
    snprintf(w, sizeof w, "materials.%s", name);
    if (!cJSON_IsObject(e))
        return fail(src, d, w, "expected an object");
    *m = geom_scene_material_default();
    geom_status st;
    if ((st = get_vec3(e, "ka", 1, &m->ka, src, w, d)) || (st = get_vec3(e, "kd", 1, &m->kd, src, w, d)) ||
        (st = get_vec3(e, "ks", 1, &m->ks, src, w, d)) ||
        (st = get_num(e, "ns", 0, 1e6, &m->ns, src, w, d)) ||
        (st = get_num(e, "reflect", 0, 1, &m->reflect, src, w, d)) ||
        (st = get_num(e, "transmit", 0, 1, &m->transmit, src, w, d)) ||
        (st = get_num(e, "ior", 1e-3, 100, &m->ior, src, w, d)) ||
        (st = get_num(e, "bump_scale", -1e6, 1e6, &m->bump_scale, src, w, d)) ||
        (st = get_num(e, "displace_scale", -1e6, 1e6, &m->displace_scale, src, w, d)) ||
        (st = get_num(e, "line_width", 0, 100, &m->line_width, src, w, d)) ||
        (st = get_num(e, "crease_degrees", 0, 180, &m->crease_degrees, src, w, d)))
        return st;
    static const char *const spec[] = {"blinn", "phong"};
    static const char *const shading[] = {"phong", "gouraud", "flat"};
    static const char *const style[] = {"standard", "cool-to-warm"};
    static const char *const wraps[] = {"repeat", "clamp"};
    int sp = 0, sh = 0, sy = 0, wr = 0;
    if ((st = get_enum(e, "specular", spec, 2, &sp, src, w, d)) ||
        (st = get_enum(e, "shading", shading, 3, &sh, src, w, d)) ||
        (st = get_enum(e, "style", style, 2, &sy, src, w, d)) ||
        (st = get_enum(e, "wrap", wraps, 2, &wr, src, w, d)))
        return st;
    m->specular = (geom_specular)sp;
    m->shading = (geom_shading)sh;
    m->style = (geom_style)sy;
    geom_wrap wrap = (geom_wrap)wr;
    if ((st = get_texture(e, "texture", wrap, 1, s, src, w, &m->texture, d)) ||
        (st = get_texture(e, "bump", wrap, 0, s, src, w, &m->bump, d)) ||
        (st = get_texture(e, "normal_map", wrap, 0, s, src, w, &m->normal_map, d)) ||
        (st = get_texture(e, "displace", wrap, 0, s, src, w, &m->displace, d)))
        return st;
    return GEOM_OK;
}

static geom_status parse_materials(const cJSON *ms, const char *src, srj_scene *s, geom_diag *d)
{
    size_t n = ms ? (size_t)cJSON_GetArraySize(ms) : 0;
    if (ms && !cJSON_IsObject(ms))
        return fail(src, d, "materials", "expected an object of named materials");
    s->materials = calloc(n + 1, sizeof(geom_material));
    s->material_names = calloc(n + 1, sizeof(char *));
    if (!s->materials || !s->material_names)
        return cli_diag_set(d, GEOM_ERR_NOMEM, src, 0, 0, "out of memory");
    s->materials[0] = geom_scene_material_default();
    s->material_names[0] = strdup("");
    s->n_materials = 1;
    if (!s->material_names[0])
        return cli_diag_set(d, GEOM_ERR_NOMEM, src, 0, 0, "out of memory");
    const cJSON *e;
    if (ms)
        cJSON_ArrayForEach(e, ms)
        {
            if (!e->string || !e->string[0])
                return fail(src, d, "materials", "a material needs a non-empty name");
            geom_status st = parse_material(e, e->string, src, s, &s->materials[s->n_materials], d);
            if (st)
                return st;
            s->material_names[s->n_materials] = strdup(e->string);
            if (!s->material_names[s->n_materials])
                return cli_diag_set(d, GEOM_ERR_NOMEM, src, 0, 0, "out of memory");
            s->n_materials++;
        }
    return GEOM_OK;
}

geom_status srj_parse(const cJSON *root, const char *scene_path, srj_scene *out, geom_diag *d)
{
    memset(out, 0, sizeof *out);
    const char *src = scene_path ? scene_path : "<scene>";
    if (!cJSON_IsObject(root))
        return fail(src, d, "scene", "expected a JSON object");
    geom_status st = GEOM_OK;
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(root, "camera");
    if (c) {
        st = parse_camera(c, src, &out->camera, d);
        out->has_camera = 1;
    }
    const cJSON *ls = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (st == GEOM_OK && ls)
        st = parse_lights(ls, src, out, d);
    if (st == GEOM_OK)
        st = parse_materials(cJSON_GetObjectItemCaseSensitive(root, "materials"), src, out, d);
    if (st == GEOM_OK)
        st = get_vec3(root, "background", 1, &out->background, src, "scene", d);
    if (st != GEOM_OK)
        srj_free(out);
    return st;
}

uint32_t srj_material_index(const srj_scene *s, const char *name)
{
    if (!name || !name[0])
        return 0;
    for (size_t i = 1; i < s->n_materials; i++)
        if (!strcmp(s->material_names[i], name))
            return (uint32_t)i;
    return UINT32_MAX;
}

void srj_free(srj_scene *s)
{
    if (!s)
        return;
    free(s->lights);
    free(s->materials);
    for (size_t i = 0; i < s->n_materials && s->material_names; i++)
        free(s->material_names[i]);
    free(s->material_names);
    for (size_t i = 0; i < s->n_textures; i++) {
        geom_scene_texture_destroy(s->textures[i]);
        free(s->texture_paths[i]);
    }
    free(s->textures);
    free(s->texture_paths);
    memset(s, 0, sizeof *s);
}

void srj_file_free(srj_file *f)
{
    if (!f)
        return;
    srj_free(&f->render);
    geom_scene_shapes_destroy(f->shapes);
    if (f->objects_json) {
        scene_json_free(f->objects_json);
        free(f->objects_json);
    }
    for (size_t i = 0; i < f->n_objects && f->names; i++)
        free(f->names[i]);
    free(f->names);
    free(f->objects);
    memset(f, 0, sizeof *f);
}

geom_status srj_load(const char *path, const char *tool_name, srj_file *out, geom_diag *d)
{
    memset(out, 0, sizeof *out);
    geom_file file_;
    geom_status st = geom_file_map(path, NULL, &file_, d);
    if (st != GEOM_OK)
        return st;
    const unsigned char *text = file_.data;
    size_t len = file_.size;
    cJSON *root = NULL;
    st = sj_json_parse((const char *)text, len, path, &root, d);
    if (st != GEOM_OK) {
        geom_file_unmap(&file_);
        return st;
    }
    geom_file_unmap(&file_);
    st = srj_parse(root, path, &out->render, d);
    if (st == GEOM_OK && !out->render.has_camera)
        st = cli_diag_set(d, GEOM_ERR_PARSE, path, 0, 0, "scene: no \"camera\"");
    const cJSON *objs = cJSON_GetObjectItemCaseSensitive(root, "objects");
    if (st == GEOM_OK && !cJSON_IsArray(objs))
        st = cli_diag_set(d, GEOM_ERR_PARSE, path, 0, 0, "scene: \"objects\" must be an array");
    char *dir = NULL;
    if (st == GEOM_OK) {
        const char *slash = strrchr(path, '/');
        size_t dl = slash ? (size_t)(slash - path) : 0;
        dir = malloc(dl + 1);
        if (!dir)
            st = GEOM_ERR_NOMEM;
        else {
            memcpy(dir, path, dl);
            dir[dl] = 0;
        }
    }
    scene_json_objects *sj = NULL;
    if (st == GEOM_OK) {
        sj = calloc(1, sizeof *sj);
        if (!sj)
            st = GEOM_ERR_NOMEM;
        else {
            st = scene_json_parse_objects(objs, dir, path, tool_name, sj, d);
            if (st == GEOM_OK)
                out->objects_json = sj;
            else
                free(sj);
        }
    }
    free(dir);
    if (st == GEOM_OK)
        st = geom_scene_shapes_from_ray(sj->scene, &out->shapes, d);
    size_t n = st == GEOM_OK ? geom_scene_shapes_count(out->shapes) : 0;
    if (st == GEOM_OK) {
        out->objects = calloc(n ? n : 1, sizeof *out->objects);
        out->names = calloc(n ? n : 1, sizeof *out->names);
        if (!out->objects || !out->names)
            st = GEOM_ERR_NOMEM;
        out->n_objects = n;
    }
    for (size_t i = 0; i < n && st == GEOM_OK; i++) {
        const cJSON *o = (size_t)cJSON_GetArraySize(objs) == n ? cJSON_GetArrayItem(objs, (int)i) : NULL;
        const cJSON *nm = o ? cJSON_GetObjectItemCaseSensitive(o, "name") : NULL;
        const cJSON *mt = o ? cJSON_GetObjectItemCaseSensitive(o, "material") : NULL;
        char buf[64];
        snprintf(buf, sizeof buf, "objects[%zu]", i);
        out->names[i] = strdup(cJSON_IsString(nm) ? nm->valuestring : buf);
        if (!out->names[i]) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        out->objects[i].shape = geom_scene_shapes_get(out->shapes, i);
        uint32_t mi = 0;
        if (mt) {
            mi = cJSON_IsString(mt) ? srj_material_index(&out->render, mt->valuestring) : UINT32_MAX;
            if (mi == UINT32_MAX)
                st = cli_diag_set(d, GEOM_ERR_PARSE, path, 0, 0,
                                  "%s: \"material\": no material %s%s%s in \"materials\"", buf,
                                  cJSON_IsString(mt) ? "\"" : "",
                                  cJSON_IsString(mt) ? mt->valuestring : "(not a string)",
                                  cJSON_IsString(mt) ? "\"" : "");
        }
        out->objects[i].material = mi;
    }
    cJSON_Delete(root);
    if (st != GEOM_OK)
        srj_file_free(out);
    if (st != GEOM_OK && d && !d->source[0])
        snprintf(d->source, sizeof d->source, "%s", path);
    return st;
}
