/* Z-buffer rasterization (Catmull 1974) with a visibility buffer: meshes
 * clipped to the frustum by geom_mesh_clip_frustum, triangles scan-converted
 * with edge functions on a 1/256-pixel fixed-point grid (top-left rule:
 * watertight), attributes interpolated perspective-correctly with
 * geom_bary_perspective, shading once per visible sample, shadow maps
 * (Williams 1978) for point (cube) and directional (orthographic) lights. */
#include "geom/scene.h"
#include "geom/bary.h"

#include <float.h>
#include <math.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "scene/scene_internal.h"

static double now(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A world-space triangle with its corner attributes. */
typedef struct rtri {
    double p[3][3], n[3][3], uv[3][2], t[3][4];
    double ng[3];
    uint32_t material, object;
    unsigned char has_n, has_uv, has_t;
    geom_vec3 col[3]; /* Gouraud colours */
} rtri;

typedef struct tri_list {
    rtri *v;
    size_t n, cap;
    const geom_allocator *alloc;
} tri_list;

static geom_status tri_push(tri_list *l, rtri **out)
{
    geom_status st = geom__grow(l->alloc, (void **)&l->v, &l->cap, l->n + 1, sizeof(rtri));
    if (st != GEOM_OK)
        return st;
    *out = &l->v[l->n++];
    memset(*out, 0, sizeof **out);
    return GEOM_OK;
}

static void tri_list_free(tri_list *l)
{
    geom__free(l->alloc, l->v, l->cap * sizeof(rtri));
    l->v = NULL;
    l->n = l->cap = 0;
}

static geom_vec3 v3(const double *a)
{
    return geom_vec3_make(a[0], a[1], a[2]);
}

geom_aabb geom__scene_draw_bbox(const geom_scene_draw *d)
{
    geom_aabb b = geom_mesh_bbox(d->mesh), w = geom_aabb_empty();
    if (geom_aabb_is_empty(b))
        return b;
    geom_mat4 M = d->transform ? *d->transform : geom_mat4_identity();
    for (int c = 0; c < 8; c++) {
        geom_vec3 p = geom_vec3_make(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y,
                                     c & 4 ? b.max.z : b.min.z), q;
        if (geom_mat4_transform_point(M, p, &q) == GEOM_OK)
            w = geom_aabb_extend(w, q);
    }
    return w;
}

/* Append the world-space triangles of draw d clipped to the frustum of vp
 * (world to clip). attrs: also normals, UVs, tangents. */
static geom_status collect(const geom_scene_draw *d, geom_mat4 vp, int attrs, tri_list *out,
                           size_t *n_in)
{
    geom_mat4 M = d->transform ? *d->transform : geom_mat4_identity();
    geom_mat4 mvp = geom_mat4_mul(vp, M);
    geom_aabb ob = geom_mesh_bbox(d->mesh);
    if (geom_aabb_is_empty(ob))
        return GEOM_OK;
    int where = geom__scene_box_frustum(ob, mvp);
    const geom_mesh *m = d->mesh;
    geom_mesh *clipped = NULL;
    if (n_in) {
        size_t nf = geom_mesh_n_faces(m);
        for (uint32_t f = 0; f < nf; f++)
            if (!geom_mesh_face_is_deleted(m, f))
                *n_in += geom_mesh_face_valence(m, f) - 2;
    }
    if (where == 0)
        return GEOM_OK;
    if (where == 2) {
        geom_status st = geom_mesh_clip_frustum(m, mvp, NULL, &clipped);
        if (st != GEOM_OK)
            return st;
        m = clipped;
    }
    geom_mat3 nm;
    if (geom_mat4_normal_matrix(M, &nm) != GEOM_OK)
        nm = geom_mat3_identity();
    uint32_t cn = GEOM_INVALID_INDEX, vn = GEOM_INVALID_INDEX, cuv = GEOM_INVALID_INDEX,
             vuv = GEOM_INVALID_INDEX, ct = GEOM_INVALID_INDEX;
    if (attrs) {
        cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
        if (cn == GEOM_INVALID_INDEX)
            vn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX);
        cuv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
        if (cuv == GEOM_INVALID_INDEX)
            vuv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_VERTEX);
        ct = geom_mesh_channel_find(m, "tangent", GEOM_MESH_DOMAIN_CORNER);
    }
    const double *P = geom_mesh_cpositions(m);
    const double *Dn = cn != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, cn)
                       : vn != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, vn) : NULL;
    const uint32_t *In = cn != GEOM_INVALID_INDEX ? geom_mesh_corner_cindices(m, cn) : NULL;
    const double *Duv = cuv != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, cuv)
                        : vuv != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, vuv) : NULL;
    const uint32_t *Iuv = cuv != GEOM_INVALID_INDEX ? geom_mesh_corner_cindices(m, cuv) : NULL;
    const double *Dt = ct != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, ct) : NULL;
    const uint32_t *It = ct != GEOM_INVALID_INDEX ? geom_mesh_corner_cindices(m, ct) : NULL;
    size_t nf = geom_mesh_n_faces(m);
    geom_status st = GEOM_OK;
    for (uint32_t f = 0; f < nf && st == GEOM_OK; f++) {
        if (geom_mesh_face_is_deleted(m, f))
            continue;
        uint32_t h0 = geom_mesh_face_he(m, f);
        uint32_t h1 = geom_mesh_he_next(m, h0);
        uint32_t h2 = geom_mesh_he_next(m, h1);
        while (h2 != h0) {
            uint32_t hs[3] = {h0, h1, h2};
            rtri *t;
            if ((st = tri_push(out, &t)) != GEOM_OK)
                break;
            t->material = d->material;
            t->object = d->object_id;
            int ok_n = Dn != NULL, ok_uv = Duv != NULL, ok_t = Dt != NULL;
            for (int c = 0; c < 3; c++) {
                uint32_t h = hs[c], v = geom_mesh_he_vertex(m, h);
                geom_vec3 q;
                if (geom_mat4_transform_point(M, v3(P + 3 * (size_t)v), &q) != GEOM_OK ||
                    !isfinite(q.x) || !isfinite(q.y) || !isfinite(q.z)) {
                    st = GEOM_ERR_INVALID_ARG;
                    break;
                }
                t->p[c][0] = q.x;
                t->p[c][1] = q.y;
                t->p[c][2] = q.z;
                if (ok_n) {
                    uint32_t i = In ? In[h] : v;
                    if (i == GEOM_INVALID_INDEX)
                        ok_n = 0;
                    else {
                        geom_vec3 nn = geom_mat3_mul_vec3(nm, v3(Dn + 3 * (size_t)i));
                        if (geom_vec3_normalize(nn, &nn) != GEOM_OK)
                            ok_n = 0;
                        t->n[c][0] = nn.x;
                        t->n[c][1] = nn.y;
                        t->n[c][2] = nn.z;
                    }
                }
                if (ok_uv) {
                    uint32_t i = Iuv ? Iuv[h] : v;
                    if (i == GEOM_INVALID_INDEX)
                        ok_uv = 0;
                    else {
                        t->uv[c][0] = Duv[2 * (size_t)i];
                        t->uv[c][1] = Duv[2 * (size_t)i + 1];
                    }
                }
                if (ok_t) {
                    uint32_t i = It[h];
                    if (i == GEOM_INVALID_INDEX)
                        ok_t = 0;
                    else {
                        geom_vec3 tt = geom_mat4_transform_dir(M, v3(Dt + 4 * (size_t)i));
                        t->t[c][0] = tt.x;
                        t->t[c][1] = tt.y;
                        t->t[c][2] = tt.z;
                        t->t[c][3] = Dt[4 * (size_t)i + 3];
                    }
                }
            }
            if (st != GEOM_OK)
                break;
            geom_vec3 e1 = geom_vec3_sub(v3(t->p[1]), v3(t->p[0]));
            geom_vec3 e2 = geom_vec3_sub(v3(t->p[2]), v3(t->p[0]));
            geom_vec3 ng;
            if (geom_vec3_normalize(geom_vec3_cross(e1, e2), &ng) != GEOM_OK) {
                out->n--; /* zero-area triangle: covers no sample */
            } else {
                t->ng[0] = ng.x;
                t->ng[1] = ng.y;
                t->ng[2] = ng.z;
                t->has_n = (unsigned char)ok_n;
                t->has_uv = (unsigned char)ok_uv;
                t->has_t = (unsigned char)ok_t;
            }
            h1 = h2;
            h2 = geom_mesh_he_next(m, h2);
        }
    }
    geom_mesh_destroy(clipped);
    return st;
}

/* ---------------------------------------------------------- scan conversion */

typedef struct target {
    uint32_t w, h;
    float *depth;  /* perspective-correct view depth, FLT_MAX = empty */
    uint32_t *id;  /* triangle index or GEOM_INVALID_INDEX; NULL for shadow maps */
    size_t fragments;
} target;

/* Screen-space setup of one triangle. */
typedef struct setup {
    double x[3], y[3], iw[3], dv[3], area;
} setup;

static int setup_tri(const rtri *t, geom_mat4 vp, geom_mat4 view, int ortho, uint32_t W,
                     uint32_t H, setup *s)
{
    for (int c = 0; c < 3; c++) {
        geom_vec4 q = geom_mat4_mul_vec4(vp, geom_vec4_make(t->p[c][0], t->p[c][1], t->p[c][2], 1));
        geom_vec4 e = geom_mat4_mul_vec4(view, geom_vec4_make(t->p[c][0], t->p[c][1], t->p[c][2], 1));
        double w = q.w;
        if (!ortho && w < 1e-300)
            w = 1e-300; /* on the near plane after rounding */
        double x = (q.x / w + 1) * 0.5 * W, y = (1 - q.y / w) * 0.5 * H;
        s->x[c] = nearbyint(x * 256.0) / 256.0;
        s->y[c] = nearbyint(y * 256.0) / 256.0;
        s->iw[c] = ortho ? 1.0 : 1.0 / w;
        s->dv[c] = -e.z;
    }
    s->area = (s->x[1] - s->x[0]) * (s->y[2] - s->y[0]) - (s->y[1] - s->y[0]) * (s->x[2] - s->x[0]);
    return s->area != 0 && isfinite(s->area);
}

/* Edge function of edge j->k at (px, py), scaled to be positive inside. */
static double edge(const setup *s, int j, int k, double px, double py)
{
    return (s->x[k] - s->x[j]) * (py - s->y[j]) - (s->y[k] - s->y[j]) * (px - s->x[j]);
}

static int top_left(const setup *s, int j, int k, double sign)
{
    double dx = (s->x[k] - s->x[j]) * sign, dy = (s->y[k] - s->y[j]) * sign;
    /* interior has E*sign > 0; with y down, left edges have dy < 0 and top
     * edges dy == 0, dx > 0 (after orienting). */
    return dy < 0 || (dy == 0 && dx > 0);
}

/* Screen barycentrics of (px, py); returns 1 if the sample is covered. */
static int cover(const setup *s, double px, double py, double l[3])
{
    double sign = s->area > 0 ? 1.0 : -1.0;
    static const int J[3] = {1, 2, 0}, K[3] = {2, 0, 1};
    for (int i = 0; i < 3; i++) {
        double e = edge(s, J[i], K[i], px, py) * sign;
        if (e < 0 || (e == 0 && !top_left(s, J[i], K[i], sign)))
            return 0;
        l[i] = e;
    }
    double a = fabs(s->area);
    l[0] /= a;
    l[1] /= a;
    l[2] /= a;
    return 1;
}

static void raster_tri(target *tg, const setup *s, uint32_t id)
{
    double xmin = fmin(s->x[0], fmin(s->x[1], s->x[2])), xmax = fmax(s->x[0], fmax(s->x[1], s->x[2]));
    double ymin = fmin(s->y[0], fmin(s->y[1], s->y[2])), ymax = fmax(s->y[0], fmax(s->y[1], s->y[2]));
    long i0 = (long)floor(xmin - 0.5), i1 = (long)ceil(xmax - 0.5);
    long j0 = (long)floor(ymin - 0.5), j1 = (long)ceil(ymax - 0.5);
    if (i0 < 0) i0 = 0;
    if (j0 < 0) j0 = 0;
    if (i1 > (long)tg->w - 1) i1 = (long)tg->w - 1;
    if (j1 > (long)tg->h - 1) j1 = (long)tg->h - 1;
    for (long j = j0; j <= j1; j++) {
        for (long i = i0; i <= i1; i++) {
            double l[3];
            if (!cover(s, i + 0.5, j + 0.5, l))
                continue;
            double den = l[0] * s->iw[0] + l[1] * s->iw[1] + l[2] * s->iw[2];
            double z = (l[0] * s->dv[0] * s->iw[0] + l[1] * s->dv[1] * s->iw[1] +
                        l[2] * s->dv[2] * s->iw[2]) / den;
            size_t k = (size_t)j * tg->w + (size_t)i;
            if ((float)z < tg->depth[k]) {
                tg->depth[k] = (float)z;
                if (tg->id)
                    tg->id[k] = id;
                tg->fragments++;
            }
        }
    }
}

static geom_status target_init(target *tg, uint32_t w, uint32_t h, int ids,
                               const geom_allocator *a)
{
    memset(tg, 0, sizeof *tg);
    tg->w = w;
    tg->h = h;
    size_t n = (size_t)w * h;
    tg->depth = geom__alloc(a, n * sizeof(float));
    if (ids)
        tg->id = geom__alloc(a, n * sizeof(uint32_t));
    if (!tg->depth || (ids && !tg->id))
        return GEOM_ERR_NOMEM;
    for (size_t k = 0; k < n; k++) {
        tg->depth[k] = FLT_MAX;
        if (ids)
            tg->id[k] = GEOM_INVALID_INDEX;
    }
    return GEOM_OK;
}

static void target_free(target *tg, const geom_allocator *a)
{
    size_t n = (size_t)tg->w * tg->h;
    geom__free(a, tg->depth, n * sizeof(float));
    geom__free(a, tg->id, n * sizeof(uint32_t));
    tg->depth = NULL;
    tg->id = NULL;
}

/* ------------------------------------------------------------ shadow maps */

typedef struct shadow {
    int kind; /* 0 none, 1 point (6 faces), 2 directional */
    geom_mat4 vp[6], view[6];
    target face[6];
    double texel[6]; /* world size of a texel at depth 1 (point) or absolute */
} shadow;

static geom_status render_shadow(const geom_light *L, geom_aabb sb, const geom_scene_draw *draws,
                                 size_t n_draws, uint32_t size, const geom_allocator *a,
                                 shadow *sh, size_t *n_maps)
{
    memset(sh, 0, sizeof *sh);
    geom_vec3 c = geom_vec3_scale(geom_vec3_add(sb.min, sb.max), 0.5);
    double R = 0.5 * geom_vec3_length(geom_vec3_sub(sb.max, sb.min)) + 1e-12;
    int nfaces;
    if (L->kind == GEOM_LIGHT_POINT) {
        sh->kind = 1;
        nfaces = 6;
        double far = geom_vec3_length(geom_vec3_sub(L->position, c)) + R;
        double near = far * 1e-5;
        static const double dirs[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        static const double ups[6][3] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
        for (int f = 0; f < 6; f++) {
            geom_mat4 proj;
            geom_mat4_lookat(L->position, geom_vec3_add(L->position, v3(dirs[f])), v3(ups[f]),
                             &sh->view[f]);
            geom_mat4_perspective(GEOM_PI / 2, 1, near, far, &proj);
            sh->vp[f] = geom_mat4_mul(proj, sh->view[f]);
            sh->texel[f] = 2.0 / size;
        }
    } else {
        sh->kind = 2;
        nfaces = 1;
        geom_vec3 d;
        if (geom_vec3_normalize(L->direction, &d) != GEOM_OK)
            return GEOM_OK;
        geom_vec3 up = fabs(d.y) < 0.9 ? geom_vec3_make(0, 1, 0) : geom_vec3_make(1, 0, 0);
        geom_vec3 eye = geom_vec3_sub(c, geom_vec3_scale(d, 2 * R));
        geom_mat4 proj;
        geom_mat4_lookat(eye, c, up, &sh->view[0]);
        geom_mat4_ortho(-R, R, -R, R, R * 1e-3, 4 * R, &proj);
        sh->vp[0] = geom_mat4_mul(proj, sh->view[0]);
        sh->texel[0] = 2 * R / size;
    }
    for (int f = 0; f < nfaces; f++) {
        geom_status st = target_init(&sh->face[f], size, size, 0, a);
        if (st != GEOM_OK)
            return st;
        tri_list tl = {0};
        tl.alloc = a;
        for (size_t i = 0; i < n_draws && st == GEOM_OK; i++)
            st = collect(&draws[i], sh->vp[f], 0, &tl, NULL);
        for (size_t i = 0; i < tl.n && st == GEOM_OK; i++) {
            setup s;
            if (setup_tri(&tl.v[i], sh->vp[f], sh->view[f], sh->kind == 2, size, size, &s))
                raster_tri(&sh->face[f], &s, 0);
        }
        tri_list_free(&tl);
        if (st != GEOM_OK)
            return st;
        (*n_maps)++;
    }
    return GEOM_OK;
}

static void shadow_free(shadow *sh, const geom_allocator *a)
{
    for (int f = 0; f < 6; f++)
        if (sh->face[f].depth)
            target_free(&sh->face[f], a);
}

/* Visibility of world point p (geometric normal ng) from the light. */
static double shadow_lookup(const shadow *sh, const geom_light *L, geom_vec3 p, geom_vec3 ng)
{
    if (sh->kind == 0)
        return 1;
    int f = 0;
    double depth_scale = 1;
    if (sh->kind == 1) {
        geom_vec3 d = geom_vec3_sub(p, L->position);
        double ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
        if (ax >= ay && ax >= az)
            f = d.x > 0 ? 0 : 1;
        else if (ay >= az)
            f = d.y > 0 ? 2 : 3;
        else
            f = d.z > 0 ? 4 : 5;
        depth_scale = fmax(ax, fmax(ay, az));
    }
    const target *tg = &sh->face[f];
    if (!tg->depth)
        return 1;
    /* Normal offset (toward the light side) by 1.5 texels plus a depth bias
     * of 2 texels. */
    double texel = sh->texel[f] * depth_scale;
    geom_vec3 l = sh->kind == 1 ? geom_vec3_sub(L->position, p) : geom_vec3_neg(L->direction);
    if (geom_vec3_dot(ng, l) < 0)
        ng = geom_vec3_neg(ng);
    geom_vec3 q = geom_vec3_add(p, geom_vec3_scale(ng, 1.5 * texel));
    geom_vec4 c = geom_mat4_mul_vec4(sh->vp[f], geom_vec4_make(q.x, q.y, q.z, 1));
    geom_vec4 e = geom_mat4_mul_vec4(sh->view[f], geom_vec4_make(q.x, q.y, q.z, 1));
    if (!(c.w > 0))
        return 1;
    double x = (c.x / c.w + 1) * 0.5 * tg->w, y = (1 - c.y / c.w) * 0.5 * tg->h;
    long i = (long)floor(x), j = (long)floor(y);
    if (i < 0 || j < 0 || i >= (long)tg->w || j >= (long)tg->h)
        return 1;
    double z = -e.z;
    return z - 2 * texel > tg->depth[(size_t)j * tg->w + (size_t)i] ? 0 : 1;
}

/* ------------------------------------------------------------------ driver */

typedef struct shade_ctx {
    const geom_camera *cam;
    geom_vec3 eye, fwd;
    int ortho;
    const geom_light *lights;
    size_t n_lights;
    const geom_material *materials;
    shadow *shadows; /* n_lights entries or NULL */
    double *vis;     /* n_lights scratch */
} shade_ctx;

static void lights_vis(const shade_ctx *cx, geom_vec3 p, geom_vec3 ng)
{
    for (size_t i = 0; i < cx->n_lights; i++)
        cx->vis[i] = cx->shadows ? shadow_lookup(&cx->shadows[i], &cx->lights[i], p, ng) : 1.0;
}

static geom_vec3 view_dir(const shade_ctx *cx, geom_vec3 p)
{
    geom_vec3 v;
    if (cx->ortho)
        return geom_vec3_neg(cx->fwd);
    if (geom_vec3_normalize(geom_vec3_sub(cx->eye, p), &v) != GEOM_OK)
        return geom_vec3_neg(cx->fwd);
    return v;
}

static geom_vec3 shade_corner(const shade_ctx *cx, const rtri *t, int c)
{
    geom_shade_point sp = {0};
    sp.p = v3(t->p[c]);
    sp.ng = v3(t->ng);
    sp.n = t->has_n ? v3(t->n[c]) : sp.ng;
    sp.v = view_dir(cx, sp.p);
    if (t->has_uv) {
        sp.has_uv = 1;
        sp.uv[0] = t->uv[c][0];
        sp.uv[1] = t->uv[c][1];
    }
    const geom_material *m = &cx->materials[t->material];
    lights_vis(cx, sp.p, sp.ng);
    geom_vec3 col;
    geom_scene_shade(m, cx->lights, cx->n_lights, cx->vis, &sp, geom_scene_shade_normal(m, &sp), &col);
    return col;
}

geom_status geom_scene_raster(const geom_camera *cam_in, const geom_light *lights, size_t n_lights,
                              const geom_material *materials, size_t n_materials,
                              const geom_scene_draw *draws, size_t n_draws,
                              const geom_raster_options *opt_in, geom_image *out,
                              geom_raster_report *report)
{
    geom_raster_report rep;
    memset(&rep, 0, sizeof rep);
    if (report)
        memset(report, 0, sizeof *report);
    if (!cam_in || !out || (n_lights && !lights) || (n_draws && !draws) ||
        (n_materials && !materials))
        return GEOM_ERR_INVALID_ARG;
    geom_raster_options opt;
    memset(&opt, 0, sizeof opt);
    if (opt_in)
        opt = *opt_in;
    const geom_allocator *a = opt.alloc;
    for (size_t i = 0; i < n_draws; i++)
        if (!draws[i].mesh || draws[i].material >= n_materials)
            return GEOM_ERR_INVALID_ARG;
    geom_camera cam = geom_scene_camera_resolved(cam_in);
    uint32_t k = (uint32_t)ceil(sqrt((double)cam.samples) - 1e-9);
    if (k < 1)
        k = 1;
    if (k > 16)
        k = 16;
    rep.samples_per_pixel = k * k;
    geom_ray r0;
    geom_status st = geom_scene_camera_ray(&cam, 0.5 * cam.width, 0.5 * cam.height, &r0);
    if (st != GEOM_OK)
        return st;
    /* Scene bounds give near and far. */
    geom_aabb sb = geom_aabb_empty();
    for (size_t i = 0; i < n_draws; i++)
        sb = geom_aabb_union(sb, geom__scene_draw_bbox(&draws[i]));
    geom_vec3 fwd;
    geom_vec3_normalize(geom_vec3_sub(cam.center, cam.eye), &fwd);
    double zmin = INFINITY, zmax = 0;
    if (!geom_aabb_is_empty(sb))
        geom__scene_box_depth_range(sb, cam.eye, fwd, &zmin, &zmax);
    int ortho = cam.projection == GEOM_PROJECTION_ORTHOGRAPHIC;
    if (!(zmax > 0)) { /* nothing in front of the camera */
        zmin = 0.5;
        zmax = 1;
    }
    double far = opt.far_z > 0 ? opt.far_z : (zmax > 0 ? zmax * 1.01 + 1e-9 : 1);
    double near = opt.near_z > 0 ? opt.near_z : fmax(zmin * 0.99, far * 1e-5);
    if (ortho && !(opt.near_z > 0)) {
        /* the view volume starts at the eye plane, as the ray tracer's
         * primary rays do */
        double span = fmax(zmax - zmin, 1e-300);
        near = fmax(zmin - 1e-3 * span, 1e-9 * span);
        far = opt.far_z > 0 ? opt.far_z : zmax + 1e-3 * span;
    }
    geom_mat4 view, proj;
    if (ortho) {
        st = geom_mat4_lookat(cam.eye, cam.center, cam.up, &view);
        double h = 0.5 * cam.ortho_height, asp = (double)cam.width / cam.height;
        if (st == GEOM_OK)
            st = geom_mat4_ortho(-h * asp, h * asp, -h, h, near, far > near ? far : near + 1, &proj);
    } else {
        st = geom_scene_camera_matrices(&cam, near, far > near ? far : near * 2, &view, &proj);
    }
    if (st != GEOM_OK)
        return st;
    geom_mat4 vp = geom_mat4_mul(proj, view);
    uint32_t W = cam.width * k, H = cam.height * k;

    /* Shadow maps. */
    double t0 = now();
    shadow *shadows = NULL;
    double *vis = geom__alloc(a, (n_lights + 1) * sizeof(double));
    if (!vis)
        return GEOM_ERR_NOMEM;
    if (opt.shadows && n_lights && !geom_aabb_is_empty(sb)) {
        shadows = geom__alloc(a, n_lights * sizeof(shadow));
        if (!shadows) {
            geom__free(a, vis, (n_lights + 1) * sizeof(double));
            return GEOM_ERR_NOMEM;
        }
        memset(shadows, 0, n_lights * sizeof(shadow));
        uint32_t size = opt.shadow_map_size ? opt.shadow_map_size : 1024;
        for (size_t i = 0; i < n_lights && st == GEOM_OK; i++)
            if (lights[i].kind != GEOM_LIGHT_AMBIENT)
                st = render_shadow(&lights[i], sb, draws, n_draws, size, a, &shadows[i],
                                   &rep.shadow_maps);
    }
    double t1 = now();
    rep.seconds_shadow = t1 - t0;

    tri_list tl = {0};
    tl.alloc = a;
    target tg = {0};
    setup *su = NULL;
    size_t su_n = 0;
    for (size_t i = 0; i < n_draws && st == GEOM_OK; i++)
        st = collect(&draws[i], vp, 1, &tl, &rep.triangles_in);
    rep.triangles_clipped = tl.n;
    double t2 = now();
    rep.seconds_clip = t2 - t1;
    if (st == GEOM_OK)
        st = target_init(&tg, W, H, 1, a);
    if (st == GEOM_OK && tl.n) {
        su = geom__alloc(a, tl.n * sizeof(setup));
        if (!su)
            st = GEOM_ERR_NOMEM;
        su_n = tl.n;
    }
    for (size_t i = 0; i < tl.n && st == GEOM_OK; i++)
        if (setup_tri(&tl.v[i], vp, view, ortho, W, H, &su[i]))
            raster_tri(&tg, &su[i], (uint32_t)i);
    rep.fragments = tg.fragments;
    double t3 = now();
    rep.seconds_raster = t3 - t2;

    shade_ctx cx = {0};
    cx.cam = &cam;
    cx.eye = cam.eye;
    cx.fwd = fwd;
    cx.ortho = ortho;
    cx.lights = lights;
    cx.n_lights = n_lights;
    cx.materials = materials;
    cx.shadows = shadows;
    cx.vis = vis;
    /* Gouraud colours for the triangles that are seen. */
    if (st == GEOM_OK && opt.aov == GEOM_AOV_COLOR) {
        size_t n = (size_t)W * H;
        unsigned char *seen = geom__alloc(a, tl.n + 1);
        if (!seen)
            st = GEOM_ERR_NOMEM;
        else {
            memset(seen, 0, tl.n + 1);
            for (size_t q = 0; q < n; q++)
                if (tg.id[q] != GEOM_INVALID_INDEX)
                    seen[tg.id[q]] = 1;
            for (size_t i = 0; i < tl.n; i++)
                if (seen[i] && materials[tl.v[i].material].shading == GEOM_SHADING_GOURAUD)
                    for (int c = 0; c < 3; c++)
                        tl.v[i].col[c] = shade_corner(&cx, &tl.v[i], c);
            geom__free(a, seen, tl.n + 1);
        }
    }
    uint32_t nch = opt.aov == GEOM_AOV_COLOR || opt.aov == GEOM_AOV_NORMAL ? 3 : 1;
    geom_image big = {0};
    if (st == GEOM_OK)
        st = geom_scene_image_init(&big, W, H, nch, a);
    for (uint32_t j = 0; j < H && st == GEOM_OK; j++) {
        for (uint32_t i = 0; i < W; i++) {
            size_t q = (size_t)j * W + i;
            double *px = big.data + q * nch;
            uint32_t id = tg.id[q];
            if (id == GEOM_INVALID_INDEX) {
                if (opt.aov == GEOM_AOV_COLOR) {
                    px[0] = opt.background.x;
                    px[1] = opt.background.y;
                    px[2] = opt.background.z;
                } else if (opt.aov == GEOM_AOV_DEPTH)
                    px[0] = INFINITY;
                else if (opt.aov == GEOM_AOV_OBJECT)
                    px[0] = -1;
                continue;
            }
            const rtri *t = &tl.v[id];
            const setup *s = &su[id];
            double l[3], lp[3];
            double sx = i + 0.5, sy = j + 0.5;
            if (!cover(s, sx, sy, l)) {
                /* cannot happen for a covered sample; stay safe */
                l[0] = l[1] = l[2] = 1.0 / 3;
            }
            double wv[3] = {1 / s->iw[0], 1 / s->iw[1], 1 / s->iw[2]};
            if (geom_bary_perspective(l, wv, lp) != GEOM_OK)
                memcpy(lp, l, sizeof lp);
            const geom_material *m = &materials[t->material];
            geom_shade_point sp = {0};
            double pp[3], nn[3] = {0, 0, 0};
            geom_bary_interpolate(3, lp, 3, &t->p[0][0], pp);
            sp.p = v3(pp);
            sp.ng = v3(t->ng);
            if (t->has_n && m->shading != GEOM_SHADING_FLAT) {
                geom_bary_interpolate(3, lp, 3, &t->n[0][0], nn);
                if (geom_vec3_normalize(v3(nn), &sp.n) != GEOM_OK)
                    sp.n = sp.ng;
            } else
                sp.n = sp.ng;
            sp.v = view_dir(&cx, sp.p);
            if (opt.aov == GEOM_AOV_DEPTH) {
                px[0] = geom_vec3_dot(geom_vec3_sub(sp.p, cam.eye), fwd);
                continue;
            }
            if (opt.aov == GEOM_AOV_OBJECT) {
                px[0] = t->object;
                continue;
            }
            if (t->has_uv) {
                sp.has_uv = 1;
                geom_bary_interpolate(3, lp, 2, &t->uv[0][0], sp.uv);
                /* UV footprint from the neighbouring samples (the barycentric
                 * functions are affine, so extrapolating is exact). */
                double fp = 0;
                for (int dd = 0; dd < 2; dd++) {
                    double l2[3], lp2[3], uv2[2];
                    double qx = sx + (dd == 0), qy = sy + (dd == 1);
                    double sign = s->area > 0 ? 1.0 : -1.0, aa = fabs(s->area);
                    l2[0] = edge(s, 1, 2, qx, qy) * sign / aa;
                    l2[1] = edge(s, 2, 0, qx, qy) * sign / aa;
                    l2[2] = edge(s, 0, 1, qx, qy) * sign / aa;
                    if (geom_bary_perspective(l2, wv, lp2) != GEOM_OK)
                        continue;
                    geom_bary_interpolate(3, lp2, 2, &t->uv[0][0], uv2);
                    fp = fmax(fp, hypot(uv2[0] - sp.uv[0], uv2[1] - sp.uv[1]));
                }
                sp.footprint = fp;
            }
            if (t->has_t) {
                double tt[4];
                geom_bary_interpolate(3, lp, 4, &t->t[0][0], tt);
                sp.tangent = v3(tt);
                sp.tangent_sign = t->t[0][3];
                sp.has_tangent = 1;
            }
            geom_vec3 n = geom_scene_shade_normal(m, &sp);
            if (opt.aov == GEOM_AOV_NORMAL) {
                px[0] = n.x;
                px[1] = n.y;
                px[2] = n.z;
                continue;
            }
            geom_vec3 col;
            if (m->shading == GEOM_SHADING_GOURAUD) {
                col = geom_vec3_add(geom_vec3_add(geom_vec3_scale(t->col[0], lp[0]),
                                                  geom_vec3_scale(t->col[1], lp[1])),
                                    geom_vec3_scale(t->col[2], lp[2]));
            } else {
                lights_vis(&cx, sp.p, sp.ng);
                geom_scene_shade(m, lights, n_lights, vis, &sp, n, &col);
            }
            px[0] = col.x;
            px[1] = col.y;
            px[2] = col.z;
        }
    }
    /* Cool-to-warm lines: silhouettes (object or background changes) and
     * creases (geometric normals turning by more than the crease angle). */
    if (st == GEOM_OK && opt.aov == GEOM_AOV_COLOR) {
        for (uint32_t j = 0; j < H; j++) {
            for (uint32_t i = 0; i < W; i++) {
                uint32_t id = tg.id[(size_t)j * W + i];
                if (id == GEOM_INVALID_INDEX)
                    continue;
                const geom_material *m = &materials[tl.v[id].material];
                if (m->style != GEOM_STYLE_COOL_TO_WARM)
                    continue;
                double lw = (m->line_width > 0 ? m->line_width : 1.5) * k * 0.5;
                double cosc = cos((m->crease_degrees > 0 ? m->crease_degrees : 30) * GEOM_PI / 180);
                long r = (long)ceil(lw);
                int line = 0;
                for (long dj = -r; dj <= r && !line; dj++) {
                    for (long di = -r; di <= r && !line; di++) {
                        if ((double)(di * di + dj * dj) > lw * lw)
                            continue;
                        long ii = (long)i + di, jj = (long)j + dj;
                        if (ii < 0 || jj < 0 || ii >= (long)W || jj >= (long)H)
                            continue;
                        uint32_t o = tg.id[(size_t)jj * W + (size_t)ii];
                        if (o == GEOM_INVALID_INDEX || tl.v[o].object != tl.v[id].object) {
                            line = 1;
                            break;
                        }
                        if (o != id && geom_vec3_dot(v3(tl.v[o].ng), v3(tl.v[id].ng)) < cosc)
                            line = 1;
                        /* silhouette inside one object: depth jump */
                        double z0 = tg.depth[(size_t)j * W + i], z1 = tg.depth[(size_t)jj * W + (size_t)ii];
                        if (fabs(z1 - z0) > 0.05 * fmax(z0, 1e-12) * (fabs((double)di) + fabs((double)dj)))
                            line = 1;
                    }
                }
                if (line) {
                    double *px = big.data + ((size_t)j * W + i) * 3;
                    px[0] = px[1] = px[2] = 0;
                }
            }
        }
    }
    double t4 = now();
    rep.seconds_shade = t4 - t3;
    /* Box filter down to the camera resolution (colour/normal), or the
     * centre sample (depth, object). */
    if (st == GEOM_OK) {
        if (k == 1) {
            *out = big;
            big.data = NULL;
        } else {
            st = geom_scene_image_init(out, cam.width, cam.height, nch, a);
            for (uint32_t j = 0; j < cam.height && st == GEOM_OK; j++)
                for (uint32_t i = 0; i < cam.width; i++) {
                    double *o = out->data + ((size_t)j * cam.width + i) * nch;
                    if (opt.aov == GEOM_AOV_COLOR || opt.aov == GEOM_AOV_NORMAL) {
                        for (uint32_t dj = 0; dj < k; dj++)
                            for (uint32_t di = 0; di < k; di++)
                                for (uint32_t c = 0; c < nch; c++)
                                    o[c] += big.data[(((size_t)j * k + dj) * W + i * k + di) * nch + c];
                        for (uint32_t c = 0; c < nch; c++)
                            o[c] /= (double)(k * k);
                    } else {
                        o[0] = big.data[(((size_t)j * k + k / 2) * W + i * k + k / 2)];
                    }
                }
        }
    }
    geom_scene_image_free(&big, a);
    target_free(&tg, a);
    geom__free(a, su, su_n * sizeof(setup));
    tri_list_free(&tl);
    if (shadows) {
        for (size_t i = 0; i < n_lights; i++)
            shadow_free(&shadows[i], a);
        geom__free(a, shadows, n_lights * sizeof(shadow));
    }
    geom__free(a, vis, (n_lights + 1) * sizeof(double));
    if (report)
        *report = rep;
    return st;
}
