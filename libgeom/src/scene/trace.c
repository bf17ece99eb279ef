/* Whitted ray tracing (Whitted 1980): primary rays, a shadow ray to every
 * light, mirror reflection and refraction by Snell's law with total internal
 * reflection, recursion cut by depth and by weight; supersampling on a
 * regular grid, jittered strata, or adaptively until the standard error of a
 * pixel's mean falls below the tolerance. */
#include "geom/scene.h"

#include <math.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "scene/scene_internal.h"

typedef struct tctx {
    const geom__tracer *tr;
    const geom_light *lights;
    size_t n_lights;
    const geom_material *materials;
    size_t n_materials;
    geom_trace_options opt;
    double *vis;
    geom_trace_report *rep;
    geom_vec3 fwd;
} tctx;

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

static double rnd(uint64_t *s)
{
    *s += 0x9e3779b97f4a7c15ull;
    return (double)(mix64(*s) >> 11) * 0x1p-53;
}

static geom_vec3 trace(tctx *c, const geom_ray *r, uint32_t depth, double weight,
                       geom__scene_hit *first);

/* The colour a reflected or refracted ray brings back, times its share k,
 * or nothing when the depth or weight cut-off stops it (counted). */
static geom_vec3 secondary(tctx *c, const geom__scene_hit *h, geom_vec3 dir, double k,
                           uint32_t depth, double weight, size_t *counter)
{
    double w = weight * k;
    if (depth + 1 > c->opt.max_depth) {
        c->rep->cut_by_depth++;
        return geom_vec3_make(0, 0, 0);
    }
    if (w < c->opt.min_weight) {
        c->rep->cut_by_weight++;
        return geom_vec3_make(0, 0, 0);
    }
    geom_ray t;
    t.origin = c->tr->spawn(c->tr->user, h, dir);
    t.dir = dir;
    t.tmin = 0;
    t.tmax = INFINITY;
    (*counter)++;
    return geom_vec3_scale(trace(c, &t, depth + 1, w, NULL), k);
}

/* The shading point of a hit seen along unit direction d. */
static geom_shade_point shade_point(const geom__scene_hit *h, geom_vec3 d)
{
    geom_shade_point sp;
    memset(&sp, 0, sizeof sp);
    sp.p = h->p;
    sp.n = h->n;
    sp.ng = h->ng;
    sp.v = geom_vec3_neg(d);
    sp.has_uv = h->has_uv;
    sp.uv[0] = h->uv[0];
    sp.uv[1] = h->uv[1];
    sp.has_tangent = h->has_tangent;
    sp.tangent = h->tangent;
    sp.tangent_sign = h->tangent_sign;
    return sp;
}

static geom_vec3 shade_hit(tctx *c, const geom_ray *r, const geom__scene_hit *h, uint32_t depth,
                           double weight)
{
    const geom_material *m = &c->materials[h->material];
    geom_vec3 d;
    if (!geom__v3unit(r->dir, &d))
        return geom__v3(0, 0, 0);
    geom_shade_point sp = shade_point(h, d);
    geom_vec3 n = geom_scene_shade_normal(m, &sp);
    /* geometric normal on the viewer's side */
    geom_vec3 ngv = geom__v3dot(h->ng, sp.v) < 0 ? geom__v3neg(h->ng) : h->ng;
    for (size_t i = 0; i < c->n_lights; i++) {
        const geom_light *L = &c->lights[i];
        c->vis[i] = 1;
        if (L->kind == GEOM_LIGHT_AMBIENT || c->opt.no_shadows)
            continue;
        geom_ray s;
        double dist;
        geom_vec3 ldir;
        if (L->kind == GEOM_LIGHT_POINT) {
            geom_vec3 to = geom__v3sub(L->position, h->p);
            dist = sqrt(geom__v3dot(to, to));
            if (!(dist > 0) || !geom__v3unit(to, &ldir))
                continue;
        } else {
            if (!geom__v3unit(geom__v3neg(L->direction), &ldir))
                continue;
            dist = INFINITY;
        }
        /* a light below the surface (seen from the viewer's side) is blocked
         * by the surface itself: no ray needed */
        if (geom__v3dot(ldir, ngv) <= 0 || geom__v3dot(ldir, n) <= 0) {
            c->vis[i] = 0;
            continue;
        }
        s.origin = c->tr->spawn(c->tr->user, h, ldir);
        s.dir = ldir;
        s.tmin = 0;
        if (L->kind == GEOM_LIGHT_POINT) {
            geom_vec3 rest = geom__v3sub(L->position, s.origin);
            s.tmax = sqrt(geom__v3dot(rest, rest)) * (1 - 1e-12);
        } else {
            s.tmax = INFINITY;
        }
        c->rep->shadow_rays++;
        c->vis[i] = c->tr->visibility(c->tr->user, &s);
    }
    geom_vec3 col;
    geom_scene_shade(m, c->lights, c->n_lights, c->vis, &sp, n, &col);
    double refl = m->reflect, trans = m->transmit;
    if (refl <= 0 && trans <= 0)
        return col;
    /* Refraction: entering when the ray meets the stored outward normal. */
    geom_vec3 rdir = geom_vec3_reflect(d, n);
    if (trans > 0) {
        int entering = geom_vec3_dot(d, h->ng) < 0;
        double ior = m->ior > 0 ? m->ior : 1;
        double eta = entering ? 1 / ior : ior;
        geom_vec3 nf = geom_vec3_dot(d, n) < 0 ? n : geom_vec3_neg(n);
        geom_vec3 tdir;
        geom_status st = geom_vec3_refract(d, nf, eta, &tdir);
        if (st == GEOM_ERR_DOMAIN) {
            c->rep->total_internal_reflections++;
            refl += trans; /* all of it reflects */
            trans = 0;
        } else if (st == GEOM_OK) {
            col = geom_vec3_add(col, secondary(c, h, tdir, trans, depth, weight,
                                               &c->rep->refraction_rays));
        }
    }
    if (refl > 0)
        col = geom_vec3_add(col, secondary(c, h, rdir, refl, depth, weight, &c->rep->reflection_rays));
    return col;
}

static geom_vec3 trace(tctx *c, const geom_ray *r, uint32_t depth, double weight,
                       geom__scene_hit *first)
{
    geom__scene_hit h;
    if (!c->tr->closest(c->tr->user, r, &h) || h.material >= c->n_materials) {
        if (first)
            first->t = INFINITY;
        return c->opt.background;
    }
    if (first)
        *first = h;
    return shade_hit(c, r, &h, depth, weight);
}

static double luminance(geom_vec3 c)
{
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

/* A pixel's samples so far: the colour sum, the luminance sum and sum of
 * squares (for the standard error of the mean), and their count. */
typedef struct px_sum {
    geom_vec3 sum;
    double lsum, lsq;
    uint32_t n;
} px_sum;

/* One primary sample through image position (x, y), traced and added to s
 * (both sampling passes). */
static void take_sample(tctx *c, const geom__scene_cam *kc, double x, double y, px_sum *s)
{
    geom_ray r;
    geom__scene_cam_ray(kc, x, y, &r);
    c->rep->primary_rays++;
    geom_vec3 col = trace(c, &r, 0, 1.0, NULL);
    double l = luminance(col);
    s->sum = geom_vec3_add(s->sum, col);
    s->lsum += l;
    s->lsq += l * l;
    s->n++;
}

geom_status geom__scene_trace(const geom__tracer *tr, const geom_camera *cam_in,
                              const geom_light *lights, size_t n_lights,
                              const geom_material *materials, size_t n_materials,
                              const geom_trace_options *opt_in, geom_image *out,
                              geom_trace_report *report)
{
    struct timespec ts0, ts1;
    timespec_get(&ts0, TIME_UTC);
    geom_trace_report rep;
    memset(&rep, 0, sizeof rep);
    if (report)
        memset(report, 0, sizeof *report);
    if (!tr || !cam_in || !out || (n_lights && !lights) || !materials || n_materials == 0)
        return GEOM_ERR_INVALID_ARG;
    tctx c;
    memset(&c, 0, sizeof c);
    c.tr = tr;
    c.lights = lights;
    c.n_lights = n_lights;
    c.materials = materials;
    c.n_materials = n_materials;
    if (opt_in)
        c.opt = *opt_in;
    if (c.opt.max_depth == 0)
        c.opt.max_depth = 8;
    if (c.opt.min_weight == 0)
        c.opt.min_weight = 1.0 / 256;
    c.rep = &rep;
    const geom_allocator *a = c.opt.alloc;
    geom__scene_cam kc;
    geom_status st = geom__scene_cam_init(cam_in, &kc);
    if (st != GEOM_OK)
        return st;
    const geom_camera cam = kc.c;
    geom_ray r0;
    geom__scene_cam_ray(&kc, 0.5 * cam.width, 0.5 * cam.height, &r0);
    c.fwd = r0.dir;
    if (cam.projection == GEOM_PROJECTION_PERSPECTIVE)
        geom_vec3_normalize(geom_vec3_sub(cam.center, cam.eye), &c.fwd);
    c.vis = geom__alloc(a, (n_lights + 1) * sizeof(double));
    if (!c.vis)
        return GEOM_ERR_NOMEM;
    uint32_t nch = c.opt.aov == GEOM_AOV_COLOR || c.opt.aov == GEOM_AOV_NORMAL ? 3 : 1;
    st = geom_scene_image_init(out, cam.width, cam.height, nch, a);
    if (st != GEOM_OK) {
        geom__free(a, c.vis, (n_lights + 1) * sizeof(double));
        return st;
    }
    uint32_t k = (uint32_t)ceil(sqrt((double)cam.samples) - 1e-9);
    if (k < 1)
        k = 1;
    int adaptive = cam.sampling == GEOM_SAMPLING_ADAPTIVE;
    if (adaptive && k < 2)
        k = 2;
    uint32_t maxn = adaptive ? (cam.max_samples > k * k ? cam.max_samples : k * k) : k * k;
    double err_sum = 0, err_max = 0;
    size_t total = 0;
    for (uint32_t j = 0; j < cam.height && st == GEOM_OK; j++) {
        if (j > 0 && c.opt.progress)
            c.opt.progress(c.opt.progress_user, (double)j / cam.height);
        for (uint32_t i = 0; i < cam.width; i++) {
            double *px = out->data + ((size_t)j * cam.width + i) * nch;
            if (c.opt.aov != GEOM_AOV_COLOR) {
                /* one ray through the pixel centre */
                geom_ray r;
                geom__scene_hit h;
                geom__scene_cam_ray(&kc, i + 0.5, j + 0.5, &r);
                rep.primary_rays++;
                total++;
                int hit = tr->closest(tr->user, &r, &h);
                if (c.opt.aov == GEOM_AOV_DEPTH)
                    px[0] = hit ? h.t * geom_vec3_dot(r.dir, c.fwd) : INFINITY;
                else if (c.opt.aov == GEOM_AOV_OBJECT)
                    px[0] = hit ? (double)h.object : -1;
                else if (hit) {
                    geom_vec3 n = h.n;
                    if (h.material < n_materials) {
                        geom_shade_point sp = shade_point(&h, r.dir);
                        n = geom_scene_shade_normal(&materials[h.material], &sp);
                    }
                    px[0] = n.x;
                    px[1] = n.y;
                    px[2] = n.z;
                }
                continue;
            }
            uint64_t seed = cam.seed ^ mix64(((uint64_t)j << 32) | i);
            px_sum ps = {{0, 0, 0}, 0, 0, 0};
            /* first pass: k x k grid (regular: centres; jittered/adaptive: random in each stratum) */
            for (uint32_t b = 0; b < k; b++)
                for (uint32_t a2 = 0; a2 < k; a2++) {
                    double ox = 0.5, oy = 0.5;
                    if (cam.sampling != GEOM_SAMPLING_REGULAR) {
                        ox = rnd(&seed);
                        oy = rnd(&seed);
                    }
                    take_sample(&c, &kc, i + (a2 + ox) / k, j + (b + oy) / k, &ps);
                }
            /* adaptive: batches of 4 stratified samples while the standard
             * error of the mean exceeds the tolerance */
            for (;;) {
                double stderr_ = 0;
                uint32_t n = ps.n;
                double lsum = ps.lsum, lsq = ps.lsq;
                if (n > 1) {
                    double mean = lsum / n, var = (lsq - n * mean * mean) / (n - 1);
                    stderr_ = var > 0 ? sqrt(var / n) : 0;
                }
                if (!adaptive || stderr_ <= cam.tolerance || n + 4 > maxn) {
                    err_sum += stderr_;
                    err_max = fmax(err_max, stderr_);
                    break;
                }
                for (uint32_t q = 0; q < 4; q++) {
                    double ox = ((q & 1) + rnd(&seed)) / 2, oy = ((q >> 1) + rnd(&seed)) / 2;
                    take_sample(&c, &kc, i + ox, j + oy, &ps);
                }
            }
            uint32_t n = ps.n;
            total += n;
            if (n > rep.max_samples_per_pixel)
                rep.max_samples_per_pixel = n;
            px[0] = ps.sum.x / n;
            px[1] = ps.sum.y / n;
            px[2] = ps.sum.z / n;
        }
    }
    if (c.opt.progress)
        c.opt.progress(c.opt.progress_user, 1.0);
    size_t npx = (size_t)cam.width * cam.height;
    rep.mean_samples_per_pixel = (double)total / (double)npx;
    rep.image_error.evaluations = total;
    if (c.opt.aov == GEOM_AOV_COLOR && maxn > 1) {
        rep.image_error.max_error = err_max;
        rep.image_error.mean_error = err_sum / (double)npx;
        rep.image_error.method = GEOM_ERROR_ESTIMATE;
    }
    if (c.opt.aov != GEOM_AOV_COLOR)
        rep.max_samples_per_pixel = 1;
    geom__free(a, c.vis, (n_lights + 1) * sizeof(double));
    timespec_get(&ts1, TIME_UTC);
    rep.seconds = (double)(ts1.tv_sec - ts0.tv_sec) + 1e-9 * (double)(ts1.tv_nsec - ts0.tv_nsec);
    if (report)
        *report = rep;
    return st;
}
