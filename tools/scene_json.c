/* Scene files for ray casting (see scene_json.h). */
#include "scene_json.h"

#include "cli.h"
#include "cli_mesh.h"
#include "geom/subdiv.h"
#include "surface_json.h"

#include <cjson/cJSON.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG2RAD 0.017453292519943295769

typedef struct sc_ctx {
    const char *source;
    const char *base;
    const char *tool;
    geom_diag *diag;
    scene_json_objects *out;
    char where[200];
} sc_ctx;

#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
static geom_status fail(const sc_ctx *x, geom_status st, const char *fmt, ...)
{
    char msg[GEOM_DIAG_MESSAGE_MAX];
    va_list ap;
    geom_diag *d = x->diag;
    if (!d) return st;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    geom_diag_clear(d);
    d->status = st;
    snprintf(d->source, sizeof d->source, "%s", x->source ? x->source : "");
    if (x->where[0]) {
        char full[GEOM_DIAG_MESSAGE_MAX + 220];
        snprintf(full, sizeof full, "%s: %s", x->where, msg);
        size_t l = strlen(full);
        if (l >= sizeof d->message) l = sizeof d->message - 1;
        memcpy(d->message, full, l);
        d->message[l] = 0;
    } else {
        memcpy(d->message, msg, sizeof d->message);
        d->message[sizeof d->message - 1] = 0;
    }
    return st;
}

/* Prefix a library diagnostic with the object's location. */
static geom_status wrap(const sc_ctx *x, geom_status st, const geom_diag *inner, const char *key)
{
    if (!x->diag) return st;
    return fail(x, st, "\"%s\": %s%s%s", key, inner && inner->source[0] ? inner->source : "",
                inner && inner->source[0] ? ": " : "",
                inner && inner->message[0] ? inner->message : geom_status_str(st));
}

static const cJSON *key(const cJSON *o, const char *k) { return cJSON_GetObjectItemCaseSensitive(o, k); }

static geom_status num(const sc_ctx *x, const cJSON *o, const char *k, int required, double def, double *out)
{
    const cJSON *v = key(o, k);
    if (!v) {
        if (required) return fail(x, GEOM_ERR_PARSE, "missing key \"%s\"", k);
        *out = def;
        return GEOM_OK;
    }
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return fail(x, GEOM_ERR_PARSE, "\"%s\": expected a finite number", k);
    *out = v->valuedouble;
    return GEOM_OK;
}

static geom_status positive(const sc_ctx *x, const cJSON *o, const char *k, double *out)
{
    geom_status st = num(x, o, k, 1, 0, out);
    if (st == GEOM_OK && !(*out > 0)) return fail(x, GEOM_ERR_PARSE, "\"%s\": expected a number > 0", k);
    return st;
}

/* A list of exactly n finite numbers. */
static geom_status nums(const sc_ctx *x, const cJSON *v, const char *k, double *out, int n)
{
    int i;
    if (!v) return fail(x, GEOM_ERR_PARSE, "missing key \"%s\"", k);
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
        return fail(x, GEOM_ERR_PARSE, "\"%s\": expected a list of %d numbers", k, n);
    for (i = 0; i < n; i++) {
        const cJSON *e = cJSON_GetArrayItem(v, i);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return fail(x, GEOM_ERR_PARSE, "\"%s\": element %d is not a finite number", k, i);
        out[i] = e->valuedouble;
    }
    return GEOM_OK;
}

static geom_status vec3(const sc_ctx *x, const cJSON *o, const char *k, double *out)
{
    return nums(x, key(o, k), k, out, 3);
}

/* A list of n >= min points ([x,y,z] each) into a malloc'd array. */
static geom_status points(const sc_ctx *x, const cJSON *o, const char *k, int min, double **out, size_t *n)
{
    const cJSON *v = key(o, k);
    int i, c;
    *out = NULL;
    if (!v) return fail(x, GEOM_ERR_PARSE, "missing key \"%s\"", k);
    if (!cJSON_IsArray(v) || (c = cJSON_GetArraySize(v)) < min)
        return fail(x, GEOM_ERR_PARSE, "\"%s\": expected a list of at least %d points", k, min);
    *out = malloc((size_t)c * 3 * sizeof(double));
    if (!*out) return fail(x, GEOM_ERR_NOMEM, "out of memory");
    for (i = 0; i < c; i++) {
        char kk[64];
        geom_status st;
        snprintf(kk, sizeof kk, "%s[%d]", k, i);
        st = nums(x, cJSON_GetArrayItem(v, i), kk, *out + 3 * i, 3);
        if (st != GEOM_OK) {
            free(*out);
            *out = NULL;
            return st;
        }
    }
    *n = (size_t)c;
    return GEOM_OK;
}

static geom_status str(const sc_ctx *x, const cJSON *o, const char *k, int required, const char **out)
{
    const cJSON *v = key(o, k);
    *out = NULL;
    if (!v) return required ? fail(x, GEOM_ERR_PARSE, "missing key \"%s\"", k) : GEOM_OK;
    if (!cJSON_IsString(v) || !v->valuestring) return fail(x, GEOM_ERR_PARSE, "\"%s\": expected a string", k);
    *out = v->valuestring;
    return GEOM_OK;
}

/* base/rel unless rel is absolute (malloc'd). */
static char *resolve(const sc_ctx *x, const char *rel)
{
    size_t lb = x->base ? strlen(x->base) : 0, lr = strlen(rel);
    char *p = malloc(lb + lr + 2);
    if (!p) return NULL;
    if (rel[0] == '/' || lb == 0) {
        memcpy(p, rel, lr + 1);
    } else {
        memcpy(p, x->base, lb);
        p[lb] = '/';
        memcpy(p + lb + 1, rel, lr + 1);
    }
    return p;
}

static geom_status own(const sc_ctx *x, void *p, int kind)
{
    scene_json_objects *o = x->out;
    if (o->nowned == o->owned_cap) {
        size_t nc = o->owned_cap ? 2 * o->owned_cap : 8;
        void **np = realloc(o->owned, nc * sizeof *np);
        int *nk;
        if (!np) return fail(x, GEOM_ERR_NOMEM, "out of memory");
        o->owned = np;
        nk = realloc(o->owned_kind, nc * sizeof *nk);
        if (!nk) return fail(x, GEOM_ERR_NOMEM, "out of memory");
        o->owned_kind = nk;
        o->owned_cap = nc;
    }
    o->owned[o->nowned] = p;
    o->owned_kind[o->nowned] = kind;
    o->nowned++;
    return GEOM_OK;
}

/* The object's transform ("transform" or "matrix"); *has = 0 if none. */
static geom_status transform(const sc_ctx *x, const cJSON *o, int *has, double m[16])
{
    const cJSON *t = key(o, "transform"), *mt = key(o, "matrix");
    geom_mat4 M = geom_mat4_identity();
    geom_status st;
    *has = 0;
    if (t && mt) return fail(x, GEOM_ERR_PARSE, "\"transform\" and \"matrix\" are exclusive");
    if (mt) {
        if ((st = nums(x, mt, "matrix", m, 16)) != GEOM_OK) return st;
        *has = 1;
        return GEOM_OK;
    }
    if (!t) return GEOM_OK;
    if (!cJSON_IsObject(t)) return fail(x, GEOM_ERR_PARSE, "\"transform\": expected an object");
    {
        const cJSON *s = key(t, "scale"), *r = key(t, "rotate"), *tr = key(t, "translate");
        double v[4];
        if (s) {
            if (cJSON_IsNumber(s)) {
                if (!isfinite(s->valuedouble)) return fail(x, GEOM_ERR_PARSE, "\"transform\": \"scale\": not finite");
                v[0] = v[1] = v[2] = s->valuedouble;
            } else if ((st = nums(x, s, "transform\": \"scale", v, 3)) != GEOM_OK) {
                return st;
            }
            if (v[0] == 0 || v[1] == 0 || v[2] == 0)
                return fail(x, GEOM_ERR_PARSE, "\"transform\": \"scale\": a zero factor");
            M = geom_mat4_scale(geom_vec3_make(v[0], v[1], v[2]));
        }
        if (r) {
            geom_mat4 R;
            if ((st = nums(x, r, "transform\": \"rotate", v, 4)) != GEOM_OK) return st;
            if (geom_mat4_rotate(geom_vec3_make(v[1], v[2], v[3]), v[0] * DEG2RAD, &R) != GEOM_OK)
                return fail(x, GEOM_ERR_PARSE, "\"transform\": \"rotate\": zero axis");
            M = geom_mat4_mul(R, M);
        }
        if (tr) {
            if ((st = nums(x, tr, "transform\": \"translate", v, 3)) != GEOM_OK) return st;
            M = geom_mat4_mul(geom_mat4_translate(geom_vec3_make(v[0], v[1], v[2])), M);
        }
    }
    memcpy(m, M.m, sizeof M.m);
    *has = 1;
    return GEOM_OK;
}

static geom_status lib(const sc_ctx *x, geom_status st, const char *what)
{
    if (st == GEOM_OK) return st;
    return fail(x, st, "%s: %s", what, geom_status_str(st));
}

static geom_status add_surfaces(const sc_ctx *x, const sj_file *f, const char *k, uint32_t *id)
{
    geom_ray_scene *sc = x->out->scene;
    size_t n = geom_surface_set_count(f->surfaces), i;
    const geom_nurbs_surface *s = geom_surface_set_data(f->surfaces);
    uint32_t *ids;
    geom_status st = GEOM_OK;
    if (n == 0) return fail(x, GEOM_ERR_PARSE, "\"%s\": no surfaces", k);
    if (n == 1) {
        geom_diag d;
        geom_diag_clear(&d);
        st = geom_ray_scene_add_surface(sc, &s[0], id, &d);
        return st == GEOM_OK ? st : wrap(x, st, &d, k);
    }
    ids = malloc(n * sizeof *ids);
    if (!ids) return fail(x, GEOM_ERR_NOMEM, "out of memory");
    for (i = 0; i < n && st == GEOM_OK; i++) {
        geom_diag d;
        geom_diag_clear(&d);
        st = geom_ray_scene_add_surface(sc, &s[i], &ids[i], &d);
        if (st != GEOM_OK) st = wrap(x, st, &d, k);
    }
    if (st == GEOM_OK) st = lib(x, geom_ray_scene_add_group(sc, ids, n, id), "group");
    free(ids);
    return st;
}

/* The "file" of a volume object through geom_implicit_volume_read, as
 * geom-iso --volume reads it: every header format, gzip through zlib and
 * bzip2 through libbz2 (cli_inflate, cli_bunzip2); a headerless file with
 * "dims" and "sample" (optional "skip", "spacing", "origin", "big_endian").
 * A spacing the header leaves unknown is read as 1 with a warning on stderr
 * (when the tool's name is known), as geom-iso prints it. */
static geom_status read_volume(const sc_ctx *x, const cJSON *o, geom_implicit_volume **out)
{
    const char *f, *sample = NULL;
    const cJSON *dims = key(o, "dims"), *be = key(o, "big_endian");
    geom_implicit_volume_read_options ro;
    geom_implicit_volume_file_info info;
    geom_status st;
    geom_diag d;
    char *path;
    double a[3], skip = 0;
    int k;
    memset(&ro, 0, sizeof ro);
    if ((st = str(x, o, "file", 1, &f)) != GEOM_OK) return st;
    if ((st = str(x, o, "sample", 0, &sample)) != GEOM_OK) return st;
    if (!dims != !sample) return fail(x, GEOM_ERR_PARSE, "a raw volume needs both \"dims\" and \"sample\"");
    if (!dims) {
        static const char *const raw_only[] = {"skip", "spacing", "origin", "big_endian"};
        for (k = 0; k < 4; k++)
            if (key(o, raw_only[k]))
                return fail(x, GEOM_ERR_PARSE, "\"%s\" applies to raw volumes (with \"dims\" and \"sample\")",
                            raw_only[k]);
    } else {
        ro.format = GEOM_IMPLICIT_VOLUME_RAW;
        if ((st = nums(x, dims, "dims", a, 3)) != GEOM_OK) return st;
        for (k = 0; k < 3; k++) {
            if (!(a[k] >= 1 && a[k] <= 1e15 && a[k] == floor(a[k])))
                return fail(x, GEOM_ERR_PARSE, "\"dims\": element %d is not an integer >= 1", k);
            ro.dims[k] = (size_t)a[k];
        }
        if (geom_implicit_sample_parse(sample, &ro.sample) != GEOM_OK)
            return fail(x, GEOM_ERR_PARSE, "\"sample\": unknown sample type \"%s\" (u8, i8, u16, i16, u32, i32, f32, f64)",
                        sample);
        if ((st = num(x, o, "skip", 0, 0, &skip)) != GEOM_OK) return st;
        if (!(skip >= 0 && skip <= 9e15 && skip == floor(skip)))
            return fail(x, GEOM_ERR_PARSE, "\"skip\": expected a byte count >= 0");
        ro.skip = (uint64_t)skip;
        if (key(o, "spacing")) {
            if ((st = vec3(x, o, "spacing", ro.spacing)) != GEOM_OK) return st;
            for (k = 0; k < 3; k++)
                if (!(ro.spacing[k] > 0)) return fail(x, GEOM_ERR_PARSE, "\"spacing\": expected numbers > 0");
        }
        if (key(o, "origin") && (st = vec3(x, o, "origin", ro.origin)) != GEOM_OK) return st;
        if (be && !cJSON_IsBool(be)) return fail(x, GEOM_ERR_PARSE, "\"big_endian\": expected true or false");
        ro.big_endian = be && cJSON_IsTrue(be);
    }
    ro.inflate = cli_inflate;
    ro.bunzip2 = cli_have_bunzip2() ? cli_bunzip2 : NULL;
    if (!(path = resolve(x, f))) return fail(x, GEOM_ERR_NOMEM, "out of memory");
    geom_diag_clear(&d);
    memset(&info, 0, sizeof info);
    st = geom_implicit_volume_read(path, &ro, NULL, out, &info, &d);
    if (st == GEOM_OK && info.spacing_note[0] && x->tool)
        fprintf(stderr, "%s: warning: %s: %s\n", x->tool, path, info.spacing_note);
    if (st != GEOM_OK) {
        char m[GEOM_DIAG_MESSAGE_MAX + 300];
        if (!d.message[0]) snprintf(d.message, sizeof d.message, "%s", geom_status_str(st));
        if (!d.source[0]) snprintf(d.source, sizeof d.source, "%s", path);
        geom_diag_format(&d, m, sizeof m);
        st = fail(x, st, "\"file\": %s", m);
    }
    free(path);
    return st;
}

static geom_status parse_obj(sc_ctx *x, const cJSON *o, uint32_t *id, int depth);

static geom_status parse_body(sc_ctx *x, const cJSON *o, const char *type, uint32_t *id, int depth)
{
    geom_ray_scene *sc = x->out->scene;
    geom_status st;
    double a[16], b[16], r;
    if (!strcmp(type, "sphere")) {
        if ((st = vec3(x, o, "center", a)) || (st = positive(x, o, "radius", &r))) return st;
        return lib(x, geom_ray_scene_add_sphere(sc, a, r, id), "sphere");
    }
    if (!strcmp(type, "plane")) {
        if ((st = vec3(x, o, "point", a)) || (st = vec3(x, o, "normal", b))) return st;
        if (b[0] == 0 && b[1] == 0 && b[2] == 0) return fail(x, GEOM_ERR_PARSE, "\"normal\": zero vector");
        return lib(x, geom_ray_scene_add_plane(sc, a, b, id), "plane");
    }
    if (!strcmp(type, "disk")) {
        if ((st = vec3(x, o, "center", a)) || (st = vec3(x, o, "normal", b)) || (st = positive(x, o, "radius", &r)))
            return st;
        if (b[0] == 0 && b[1] == 0 && b[2] == 0) return fail(x, GEOM_ERR_PARSE, "\"normal\": zero vector");
        return lib(x, geom_ray_scene_add_disk(sc, a, b, r, id), "disk");
    }
    if (!strcmp(type, "box")) {
        int k;
        if ((st = vec3(x, o, "min", a)) || (st = vec3(x, o, "max", b))) return st;
        for (k = 0; k < 3; k++)
            if (a[k] > b[k]) return fail(x, GEOM_ERR_PARSE, "\"min\": component %d exceeds \"max\"", k);
        return lib(x, geom_ray_scene_add_box(sc, a, b, id), "box");
    }
    if (!strcmp(type, "obox")) {
        double *ax = NULL, h[3];
        size_t n = 0;
        if ((st = vec3(x, o, "center", a)) || (st = vec3(x, o, "half", h))) return st;
        if ((st = points(x, o, "axes", 3, &ax, &n)) != GEOM_OK) return st;
        if (n != 3) {
            free(ax);
            return fail(x, GEOM_ERR_PARSE, "\"axes\": expected 3 vectors");
        }
        st = geom_ray_scene_add_obox(sc, a, ax, h, id);
        free(ax);
        if (st != GEOM_OK) return fail(x, st, "\"axes\"/\"half\": %s (orthogonal nonzero axes, half >= 0)",
                                       geom_status_str(st));
        return st;
    }
    if (!strcmp(type, "torus")) {
        if ((st = positive(x, o, "major", &a[0])) || (st = positive(x, o, "minor", &a[1]))) return st;
        return lib(x, geom_ray_scene_add_torus(sc, a[0], a[1], id), "torus");
    }
    if (!strcmp(type, "quadric")) {
        const cJSON *cl = key(o, "clip"), *cp = key(o, "capped");
        if ((st = nums(x, key(o, "coefficients"), "coefficients", a, 10)) != GEOM_OK) return st;
        if (cl && (st = nums(x, cl, "clip", b, 6)) != GEOM_OK) return st;
        if (cp && !cJSON_IsBool(cp)) return fail(x, GEOM_ERR_PARSE, "\"capped\": expected true or false");
        if (cp && !cl) return fail(x, GEOM_ERR_PARSE, "\"capped\" needs \"clip\"");
        st = geom_ray_scene_add_quadric(sc, a, cl ? b : NULL, cp && cJSON_IsTrue(cp), id);
        if (st != GEOM_OK) return fail(x, st, "\"coefficients\": %s", geom_status_str(st));
        return st;
    }
    if (!strcmp(type, "triangle") || !strcmp(type, "polygon")) {
        double *v = NULL;
        size_t n = 0;
        int tri = type[0] == 't';
        if ((st = points(x, o, "vertices", 3, &v, &n)) != GEOM_OK) return st;
        if (tri && n != 3) {
            free(v);
            return fail(x, GEOM_ERR_PARSE, "\"vertices\": a triangle has 3 vertices, got %zu", n);
        }
        st = tri ? geom_ray_scene_add_triangle(sc, v, id) : geom_ray_scene_add_polygon(sc, v, n, id);
        free(v);
        if (st != GEOM_OK) return fail(x, st, "\"vertices\": %s", geom_status_str(st));
        return st;
    }
    if (!strcmp(type, "mesh") || !strcmp(type, "subdivision")) {
        const char *f, *scheme = NULL;
        char *path;
        geom_mesh *m = NULL;
        geom_diag d;
        double lv = 0;
        if ((st = str(x, o, "file", 1, &f)) != GEOM_OK) return st;
        if (type[0] == 's') {
            if ((st = str(x, o, "scheme", 0, &scheme)) != GEOM_OK) return st;
            if ((st = num(x, o, "levels", 0, 0, &lv)) != GEOM_OK) return st;
            if (lv < 0 || lv > 8 || lv != floor(lv))
                return fail(x, GEOM_ERR_PARSE, "\"levels\": expected an integer 0..8");
        }
        if (!(path = resolve(x, f))) return fail(x, GEOM_ERR_NOMEM, "out of memory");
        geom_diag_clear(&d);
        st = cli_mesh_read(x->tool ? x->tool : "scene", path, GEOM_MESHIO_FORMAT_AUTO, &m, &d);
        free(path);
        if (st != GEOM_OK) return wrap(x, st, &d, "file");
        if (type[0] == 'm') {
            st = lib(x, geom_ray_scene_add_mesh(sc, m, id), "mesh");
        } else {
            geom_subdiv_scheme sch = GEOM_SUBDIV_CATMULL_CLARK;
            if (scheme && geom_subdiv_scheme_from_name(scheme, &sch) != GEOM_OK) {
                geom_mesh_destroy(m);
                return fail(x, GEOM_ERR_PARSE, "\"scheme\": unknown scheme \"%s\" (catmull-clark, loop)", scheme);
            }
            geom_diag_clear(&d);
            st = geom_ray_scene_add_subdiv(sc, m, (int)sch, (int)lv, id, &d);
            if (st != GEOM_OK) st = wrap(x, st, &d, "file");
        }
        geom_mesh_destroy(m);
        return st;
    }
    if (!strcmp(type, "surface")) {
        const char *f;
        char *path;
        sj_file sf;
        geom_diag d;
        if ((st = str(x, o, "file", 1, &f)) != GEOM_OK) return st;
        if (!(path = resolve(x, f))) return fail(x, GEOM_ERR_NOMEM, "out of memory");
        geom_diag_clear(&d);
        st = sj_read_file(path, &sf, &d);
        free(path);
        if (st != GEOM_OK) return wrap(x, st, &d, "file");
        st = add_surfaces(x, &sf, "file", id);
        sj_free(&sf);
        return st;
    }
    if (!strcmp(type, "bezier") || !strcmp(type, "bspline") || !strcmp(type, "nurbs")) {
        /* Inline surface: the surface JSON reader on {"surfaces": [o]}. */
        cJSON *wrapper = cJSON_CreateObject(), *arr = cJSON_CreateArray(), *dup = cJSON_Duplicate(o, 1);
        char *text = NULL;
        sj_file sf;
        geom_diag d;
        if (!wrapper || !arr || !dup) {
            cJSON_Delete(wrapper); cJSON_Delete(arr); cJSON_Delete(dup);
            return fail(x, GEOM_ERR_NOMEM, "out of memory");
        }
        cJSON_DeleteItemFromObjectCaseSensitive(dup, "transform");
        cJSON_DeleteItemFromObjectCaseSensitive(dup, "matrix");
        cJSON_AddItemToArray(arr, dup);
        cJSON_AddItemToObject(wrapper, "surfaces", arr);
        text = cJSON_PrintUnformatted(wrapper);
        cJSON_Delete(wrapper);
        if (!text) return fail(x, GEOM_ERR_NOMEM, "out of memory");
        geom_diag_clear(&d);
        st = sj_read_memory(text, strlen(text), x->source, &sf, &d);
        free(text);
        if (st != GEOM_OK) {
            /* The reader's message names surfaces[0]: keep its key part. */
            const char *m = strstr(d.message, ": ");
            return fail(x, st, "%s", m ? m + 2 : d.message);
        }
        st = add_surfaces(x, &sf, type, id);
        sj_free(&sf);
        return st;
    }
    if (!strcmp(type, "implicit")) {
        const char *e;
        geom_implicit_expr *ex = NULL;
        geom_diag d;
        double L = 0;
        if ((st = str(x, o, "expr", 1, &e)) != GEOM_OK) return st;
        if ((st = nums(x, key(o, "bounds"), "bounds", a, 6)) != GEOM_OK) return st;
        if ((st = num(x, o, "lipschitz", 0, 0, &L)) != GEOM_OK) return st;
        if (L < 0) return fail(x, GEOM_ERR_PARSE, "\"lipschitz\": expected a number >= 0");
        if (!(a[0] < a[3] && a[1] < a[4] && a[2] < a[5]))
            return fail(x, GEOM_ERR_PARSE, "\"bounds\": expected x0 < x1, y0 < y1, z0 < z1");
        geom_diag_clear(&d);
        st = geom_implicit_expr_compile(e, strlen(e), NULL, &ex, &d);
        if (st != GEOM_OK) return fail(x, st, "\"expr\": column %zu: %s", d.column, d.message);
        if ((st = own(x, ex, 0)) != GEOM_OK) {
            geom_implicit_expr_destroy(ex);
            return st;
        }
        return lib(x, geom_ray_scene_add_implicit(sc, ex, a, L, id), "implicit");
    }
    if (!strcmp(type, "volume")) {
        geom_implicit_volume *v = NULL;
        geom_ray_volume_options vo;
        const char *side;
        memset(&vo, 0, sizeof vo);
        if ((st = num(x, o, "iso", 1, 0, &r)) != GEOM_OK) return st;
        if ((st = str(x, o, "inside", 0, &side)) != GEOM_OK) return st;
        if (side && strcmp(side, "below") && strcmp(side, "above"))
            return fail(x, GEOM_ERR_PARSE, "\"inside\": expected \"below\" or \"above\", got \"%s\"", side);
        if ((st = read_volume(x, o, &v)) != GEOM_OK) return st;
        if ((st = own(x, v, 1)) != GEOM_OK) {
            geom_implicit_volume_destroy(v);
            return st;
        }
        if (side) /* absent: detected from the boundary samples, as geom-iso */
            vo.inside = side[0] == 'a';
        else if ((st = geom_implicit_volume_detect_inside(v, r, &vo.inside, NULL, NULL)) != GEOM_OK)
            return lib(x, st, "volume");
        return lib(x, geom_ray_scene_add_volume_opt(sc, v, r, &vo, id), "volume");
    }
    if (!strcmp(type, "csg")) {
        const char *op;
        const cJSON *ch = key(o, "children");
        geom_ray_csg_op cop;
        int n, i;
        uint32_t acc = 0;
        char saved[sizeof x->where];
        if ((st = str(x, o, "op", 1, &op)) != GEOM_OK) return st;
        if (!strcmp(op, "union")) cop = GEOM_RAY_CSG_UNION;
        else if (!strcmp(op, "intersection")) cop = GEOM_RAY_CSG_INTERSECTION;
        else if (!strcmp(op, "difference")) cop = GEOM_RAY_CSG_DIFFERENCE;
        else return fail(x, GEOM_ERR_PARSE, "\"op\": unknown operation \"%s\" (union, intersection, difference)", op);
        if (!ch) return fail(x, GEOM_ERR_PARSE, "missing key \"children\"");
        if (!cJSON_IsArray(ch) || (n = cJSON_GetArraySize(ch)) < 2)
            return fail(x, GEOM_ERR_PARSE, "\"children\": expected a list of at least 2 objects");
        memcpy(saved, x->where, sizeof saved);
        for (i = 0; i < n; i++) {
            uint32_t cid;
            size_t l = strlen(saved);
            snprintf(x->where, sizeof x->where, "%.*s.children[%d]", (int)(l > 150 ? 150 : l), saved, i);
            st = parse_obj(x, cJSON_GetArrayItem(ch, i), &cid, depth + 1);
            memcpy(x->where, saved, sizeof saved);
            if (st != GEOM_OK) return st;
            if (i == 0) {
                acc = cid;
            } else {
                uint32_t nid;
                if ((st = lib(x, geom_ray_scene_add_csg(sc, cop, acc, cid, &nid), "csg")) != GEOM_OK) return st;
                acc = nid;
            }
        }
        *id = acc;
        return GEOM_OK;
    }
    if (!strcmp(type, "instance")) {
        const char *of;
        uint32_t target;
        if ((st = str(x, o, "of", 1, &of)) != GEOM_OK) return st;
        target = geom_ray_scene_find(sc, of);
        if (target == GEOM_INVALID_INDEX)
            return fail(x, GEOM_ERR_PARSE, "\"of\": no object named \"%s\"", of);
        return lib(x, geom_ray_scene_add_instance(sc, target, NULL, id), "instance");
    }
    return fail(x, GEOM_ERR_PARSE,
                "\"type\": unknown type \"%s\" (sphere, plane, disk, box, obox, torus, quadric, triangle, "
                "polygon, mesh, surface, bezier, bspline, nurbs, subdivision, implicit, volume, csg, instance)",
                type);
}

static geom_status parse_obj(sc_ctx *x, const cJSON *o, uint32_t *id, int depth)
{
    const char *type, *name;
    geom_status st;
    double m[16];
    int has;
    if (depth > 64) return fail(x, GEOM_ERR_LIMIT, "objects nested deeper than 64");
    if (!cJSON_IsObject(o)) return fail(x, GEOM_ERR_PARSE, "expected an object");
    if ((st = str(x, o, "name", 0, &name)) != GEOM_OK) return st;
    if (name) {
        size_t l = strlen(x->where);
        snprintf(x->where + l, sizeof x->where - l, " (\"%.40s\")", name);
    }
    if ((st = str(x, o, "type", 1, &type)) != GEOM_OK) return st;
    if ((st = transform(x, o, &has, m)) != GEOM_OK) return st;
    if ((st = parse_body(x, o, type, id, depth)) != GEOM_OK) return st;
    if (has) {
        st = geom_ray_scene_set_transform(x->out->scene, *id, m);
        if (st != GEOM_OK)
            return fail(x, st, "\"%s\": %s (singular or not affine)", key(o, "matrix") ? "matrix" : "transform",
                        geom_status_str(st));
    }
    if (name) {
        if (geom_ray_scene_find(x->out->scene, name) != GEOM_INVALID_INDEX)
            return fail(x, GEOM_ERR_PARSE, "\"name\": \"%s\" is used twice", name);
        geom_ray_scene_set_name(x->out->scene, *id, name);
    }
    return GEOM_OK;
}

void scene_json_free(scene_json_objects *o)
{
    size_t i;
    if (!o) return;
    geom_ray_scene_destroy(o->scene);
    for (i = 0; i < o->nowned; i++) {
        if (o->owned_kind[i] == 0) geom_implicit_expr_destroy(o->owned[i]);
        else geom_implicit_volume_destroy(o->owned[i]);
    }
    free(o->owned);
    free(o->owned_kind);
    memset(o, 0, sizeof *o);
}

geom_status scene_json_parse_objects(const cJSON *objects, const char *base_dir, const char *source,
                                     const char *tool_name, scene_json_objects *out, geom_diag *diag)
{
    sc_ctx x;
    int n, i, pass, pending;
    uint32_t *ids = NULL;
    char *done = NULL;
    geom_status st = GEOM_OK;
    memset(&x, 0, sizeof x);
    x.source = source ? source : "<memory>";
    x.base = base_dir;
    x.tool = tool_name;
    x.diag = diag;
    x.out = out;
    if (!out) return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!objects || !cJSON_IsArray(objects)) return fail(&x, GEOM_ERR_PARSE, "\"objects\": expected a list");
    n = cJSON_GetArraySize(objects);
    out->scene = geom_ray_scene_create(NULL);
    ids = malloc(((size_t)n + 1) * sizeof *ids);
    done = calloc((size_t)n + 1, 1);
    if (!out->scene || !ids || !done) {
        st = fail(&x, GEOM_ERR_NOMEM, "out of memory");
        goto end;
    }
    /* Everything but instances first, so that instances may refer to names
     * defined anywhere; then instances until none is left (instances of
     * instances resolve in order of their targets). */
    for (pass = 0; pass < 2 && st == GEOM_OK; pass++) {
        do {
            pending = 0;
            for (i = 0; i < n && st == GEOM_OK; i++) {
                const cJSON *o = cJSON_GetArrayItem(objects, i);
                const cJSON *t = cJSON_IsObject(o) ? key(o, "type") : NULL;
                int inst = t && cJSON_IsString(t) && t->valuestring && !strcmp(t->valuestring, "instance");
                if (done[i] || (pass == 0 && inst)) continue;
                if (pass == 1) {
                    const cJSON *of = key(o, "of");
                    if (of && cJSON_IsString(of) && of->valuestring &&
                        geom_ray_scene_find(out->scene, of->valuestring) == GEOM_INVALID_INDEX) {
                        pending++;
                        continue;
                    }
                }
                snprintf(x.where, sizeof x.where, "objects[%d]", i);
                st = parse_obj(&x, o, &ids[i], 0);
                done[i] = 1;
            }
            if (pass == 1 && pending && st == GEOM_OK) {
                /* Is any pending instance now resolvable? */
                int progress = 0;
                for (i = 0; i < n; i++) {
                    const cJSON *o = cJSON_GetArrayItem(objects, i), *of;
                    if (done[i]) continue;
                    of = key(o, "of");
                    if (of && cJSON_IsString(of) && geom_ray_scene_find(out->scene, of->valuestring) != GEOM_INVALID_INDEX)
                        progress = 1;
                }
                if (!progress) {
                    for (i = 0; i < n && !done[i]; i++) {}
                    for (i = 0; i < n; i++)
                        if (!done[i]) break;
                    snprintf(x.where, sizeof x.where, "objects[%d]", i);
                    st = parse_obj(&x, cJSON_GetArrayItem(objects, i), &ids[i], 0);
                    if (st == GEOM_OK) st = fail(&x, GEOM_ERR_PARSE, "\"of\": unresolved");
                }
            }
        } while (pass == 1 && pending && st == GEOM_OK);
    }
    if (st == GEOM_OK) {
        x.where[0] = 0;
        st = geom_ray_scene_set_objects(out->scene, ids, (size_t)n);
        if (st != GEOM_OK) st = fail(&x, st, "objects: %s", geom_status_str(st));
        out->nobjects = (size_t)n;
    }
end:
    free(ids);
    free(done);
    if (st != GEOM_OK) scene_json_free(out);
    return st;
}

geom_status scene_json_read_memory(const char *text, size_t len, const char *base_dir, const char *source,
                                   const char *tool_name, scene_json_objects *out, geom_diag *diag)
{
    sc_ctx x;
    cJSON *root;
    geom_status st;
    memset(&x, 0, sizeof x);
    x.source = source ? source : "<memory>";
    x.diag = diag;
    if (!out || (!text && len)) return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    st = sj_json_parse(text, len, x.source, &root, diag);
    if (st != GEOM_OK) return st;
    if (!cJSON_IsObject(root) || !key(root, "objects")) {
        cJSON_Delete(root);
        return fail(&x, GEOM_ERR_PARSE, "expected an object {\"objects\": [...]}");
    }
    st = scene_json_parse_objects(key(root, "objects"), base_dir, source, tool_name, out, diag);
    cJSON_Delete(root);
    return st;
}

geom_status scene_json_read_file(const char *path, const char *tool_name, scene_json_objects *out,
                                 geom_diag *diag)
{
    FILE *fp;
    geom_file file_;
    memset(&file_, 0, sizeof file_);
    geom_status st;
    char *dir;
    const char *slash;
    if (!path || !out) return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    fp = fopen(path, "rb");
    if (!fp) {
        if (diag) {
            geom_diag_clear(diag);
            diag->status = GEOM_ERR_IO;
            snprintf(diag->source, sizeof diag->source, "%s", path);
            snprintf(diag->message, sizeof diag->message, "cannot open the file");
        }
        return GEOM_ERR_IO;
    }
    st = cli_read_all(fp, path, &file_, diag);
    fclose(fp);
    if (st != GEOM_OK) return st;
    const unsigned char *data = file_.data;
    size_t size = file_.size;
    slash = strrchr(path, '/');
    dir = malloc(slash ? (size_t)(slash - path) + 1 : 1);
    if (!dir) {
        geom_file_unmap(&file_);
        return GEOM_ERR_NOMEM;
    }
    if (slash) {
        memcpy(dir, path, (size_t)(slash - path));
        dir[slash - path] = 0;
        if (slash == path) strcpy(dir, "/");
    } else {
        dir[0] = 0;
    }
    st = scene_json_read_memory((const char *)data, size, dir, path, tool_name, out, diag);
    free(dir);
    geom_file_unmap(&file_);
    return st;
}
