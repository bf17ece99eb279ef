/* Images and MIP-mapped textures (Williams 1983): box-filtered pyramid,
 * bilinear lookup in a level, linear blend between two levels. */
#include "geom/scene.h"

#include <math.h>
#include <string.h>

#include "core/internal.h"

geom_status geom_scene_image_init(geom_image *img, uint32_t width, uint32_t height, uint32_t channels,
                            const geom_allocator *alloc)
{
    if (!img || width == 0 || height == 0 || channels == 0)
        return GEOM_ERR_INVALID_ARG;
    size_t n, bytes;
    if (geom__size_mul((size_t)width, (size_t)height, &n) != GEOM_OK ||
        geom__size_mul(n, channels, &n) != GEOM_OK ||
        geom__size_mul(n, sizeof(double), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    double *d = geom__alloc(alloc, bytes);
    if (!d)
        return GEOM_ERR_NOMEM;
    memset(d, 0, bytes);
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->data = d;
    return GEOM_OK;
}

void geom_scene_image_free(geom_image *img, const geom_allocator *alloc)
{
    if (!img || !img->data)
        return;
    geom__free(alloc, img->data,
              (size_t)img->width * img->height * img->channels * sizeof(double));
    memset(img, 0, sizeof *img);
}

#define MAX_LEVELS 40

struct geom_texture {
    geom_allocator alloc;
    int has_alloc;
    geom_wrap wrap;
    uint32_t channels, levels;
    uint32_t w[MAX_LEVELS], h[MAX_LEVELS];
    double *level[MAX_LEVELS];
};

static const geom_allocator *talloc(const geom_texture *t)
{
    return t->has_alloc ? &t->alloc : NULL;
}

void geom_scene_texture_destroy(geom_texture *t)
{
    if (!t)
        return;
    for (uint32_t l = 0; l < t->levels; l++)
        geom__free(talloc(t), t->level[l],
                  (size_t)t->w[l] * t->h[l] * t->channels * sizeof(double));
    geom__free(talloc(t), t, sizeof *t);
}

/* Box-filter weights of output texel o over input size n (n > 1): 2 taps
 * when n is even, 3 taps (1/4 1/2 1/4 style, area weights) when odd. */
static int taps(uint32_t n, uint32_t o, uint32_t *idx, double *wt)
{
    if (n == 1) {
        idx[0] = 0;
        wt[0] = 1;
        return 1;
    }
    if (n % 2 == 0) {
        idx[0] = 2 * o;
        idx[1] = 2 * o + 1;
        wt[0] = wt[1] = 0.5;
        return 2;
    }
    /* Odd: output size m = n/2 (floor); output texel o covers input
     * [o*n/m, (o+1)*n/m), three taps with area weights. */
    uint32_t m = n / 2;
    double a = (double)o * n / m, b = (double)(o + 1) * n / m;
    int k = 0;
    for (uint32_t i = (uint32_t)floor(a); i < n && (double)i < b; i++) {
        double lo = fmax(a, (double)i), hi = fmin(b, (double)i + 1);
        if (hi > lo) {
            idx[k] = i;
            wt[k] = (hi - lo) / (b - a);
            k++;
        }
    }
    return k;
}

geom_status geom_scene_texture_create(const geom_image *img, geom_wrap wrap, const geom_allocator *alloc,
                                geom_texture **out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    *out = NULL;
    if (!img || !img->data || img->width == 0 || img->height == 0 || img->channels == 0 ||
        img->channels > 4)
        return GEOM_ERR_INVALID_ARG;
    size_t n = (size_t)img->width * img->height * img->channels;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(img->data[i]))
            return GEOM_ERR_INVALID_ARG;
    geom_texture *t = geom__alloc(alloc, sizeof *t);
    if (!t)
        return GEOM_ERR_NOMEM;
    memset(t, 0, sizeof *t);
    if (alloc) {
        t->alloc = *alloc;
        t->has_alloc = 1;
    }
    t->wrap = wrap;
    t->channels = img->channels;
    t->w[0] = img->width;
    t->h[0] = img->height;
    t->level[0] = geom__alloc(alloc, n * sizeof(double));
    if (!t->level[0]) {
        geom__free(alloc, t, sizeof *t);
        return GEOM_ERR_NOMEM;
    }
    t->levels = 1;
    memcpy(t->level[0], img->data, n * sizeof(double));
    uint32_t c = t->channels;
    while (t->levels < MAX_LEVELS) {
        uint32_t l = t->levels, pw = t->w[l - 1], ph = t->h[l - 1];
        if (pw == 1 && ph == 1)
            break;
        uint32_t w = pw > 1 ? pw / 2 : 1, h = ph > 1 ? ph / 2 : 1;
        double *d = geom__alloc(alloc, (size_t)w * h * c * sizeof(double));
        if (!d) {
            geom_scene_texture_destroy(t);
            return GEOM_ERR_NOMEM;
        }
        const double *s = t->level[l - 1];
        for (uint32_t y = 0; y < h; y++) {
            uint32_t iy[4], ix[4];
            double wy[4], wx[4];
            int ny = ph > 1 ? taps(ph, y, iy, wy) : taps(1, 0, iy, wy);
            for (uint32_t x = 0; x < w; x++) {
                int nx = pw > 1 ? taps(pw, x, ix, wx) : taps(1, 0, ix, wx);
                for (uint32_t k = 0; k < c; k++) {
                    double acc = 0;
                    for (int a = 0; a < ny; a++)
                        for (int b = 0; b < nx; b++)
                            acc += wy[a] * wx[b] * s[((size_t)iy[a] * pw + ix[b]) * c + k];
                    d[((size_t)y * w + x) * c + k] = acc;
                }
            }
        }
        t->level[l] = d;
        t->w[l] = w;
        t->h[l] = h;
        t->levels++;
    }
    *out = t;
    return GEOM_OK;
}

uint32_t geom_scene_texture_channels(const geom_texture *t)
{
    return t ? t->channels : 0;
}

void geom_scene_texture_size(const geom_texture *t, uint32_t *width, uint32_t *height)
{
    if (width)
        *width = t ? t->w[0] : 0;
    if (height)
        *height = t ? t->h[0] : 0;
}

uint32_t geom_scene_texture_levels(const geom_texture *t)
{
    return t ? t->levels : 0;
}

static long wrap_index(long i, uint32_t n, geom_wrap wrap)
{
    if (wrap == GEOM_WRAP_CLAMP)
        return i < 0 ? 0 : (i >= (long)n ? (long)n - 1 : i);
    long m = i % (long)n;
    return m < 0 ? m + n : m;
}

/* Texel-space continuous coordinates of (u, v) in a w x h level. */
static void texel_coords(double u, double v, uint32_t w, uint32_t h, geom_wrap wrap, double *x,
                         double *y)
{
    if (wrap == GEOM_WRAP_REPEAT) {
        u -= floor(u);
        v -= floor(v);
    }
    *x = u * w - 0.5;
    *y = (1.0 - v) * h - 0.5;
}

static void bilinear(const geom_texture *t, uint32_t l, double u, double v, double *out)
{
    uint32_t w = t->w[l], h = t->h[l], c = t->channels;
    double x, y;
    texel_coords(u, v, w, h, t->wrap, &x, &y);
    double fx = floor(x), fy = floor(y);
    double ax = x - fx, ay = y - fy;
    long x0 = wrap_index((long)fx, w, t->wrap), x1 = wrap_index((long)fx + 1, w, t->wrap);
    long y0 = wrap_index((long)fy, h, t->wrap), y1 = wrap_index((long)fy + 1, h, t->wrap);
    const double *d = t->level[l];
    for (uint32_t k = 0; k < c; k++) {
        double a = d[((size_t)y0 * w + x0) * c + k], b = d[((size_t)y0 * w + x1) * c + k];
        double e = d[((size_t)y1 * w + x0) * c + k], f = d[((size_t)y1 * w + x1) * c + k];
        out[k] = (1 - ay) * ((1 - ax) * a + ax * b) + ay * ((1 - ax) * e + ax * f);
    }
}

void geom_scene_texture_sample(const geom_texture *t, double u, double v, double footprint, double *out)
{
    if (!t || !out)
        return;
    if (!isfinite(u) || !isfinite(v)) {
        for (uint32_t k = 0; k < t->channels; k++)
            out[k] = t->level[0][k];
        return;
    }
    /* Clamp huge coordinates so floor() stays exact and indices fit a long. */
    if (fabs(u) > 1e9)
        u = fmod(u, 1.0);
    if (fabs(v) > 1e9)
        v = fmod(v, 1.0);
    uint32_t maxdim = t->w[0] > t->h[0] ? t->w[0] : t->h[0];
    double lod = footprint > 0 && isfinite(footprint) ? log2(footprint * maxdim) : 0;
    if (!(lod > 0) || t->levels == 1) {
        bilinear(t, 0, u, v, out);
        return;
    }
    if (lod >= t->levels - 1) {
        bilinear(t, t->levels - 1, u, v, out);
        return;
    }
    uint32_t l0 = (uint32_t)floor(lod);
    double a = lod - l0, tmp[4];
    bilinear(t, l0, u, v, out);
    bilinear(t, l0 + 1, u, v, tmp);
    for (uint32_t k = 0; k < t->channels; k++)
        out[k] = (1 - a) * out[k] + a * tmp[k];
}

void geom_scene_texture_gradient(const geom_texture *t, double u, double v, double *dh_du,
                           double *dh_dv)
{
    double gu = 0, gv = 0;
    if (t && isfinite(u) && isfinite(v)) {
        uint32_t w = t->w[0], h = t->h[0], c = t->channels;
        double x, y;
        texel_coords(u, v, w, h, t->wrap, &x, &y);
        double fx = floor(x), fy = floor(y), ax = x - fx, ay = y - fy;
        long x0 = wrap_index((long)fx, w, t->wrap), x1 = wrap_index((long)fx + 1, w, t->wrap);
        long y0 = wrap_index((long)fy, h, t->wrap), y1 = wrap_index((long)fy + 1, h, t->wrap);
        const double *d = t->level[0];
        double a = d[((size_t)y0 * w + x0) * c], b = d[((size_t)y0 * w + x1) * c];
        double e = d[((size_t)y1 * w + x0) * c], f = d[((size_t)y1 * w + x1) * c];
        double dx = (1 - ay) * (b - a) + ay * (f - e); /* per texel in x */
        double dy = (1 - ax) * (e - a) + ax * (f - b); /* per texel in y (downwards) */
        gu = dx * w;
        gv = -dy * h;
        if (t->wrap == GEOM_WRAP_CLAMP) {
            if (x < 0 || x > w - 1)
                gu = 0;
            if (y < 0 || y > h - 1)
                gv = 0;
        }
    }
    if (dh_du)
        *dh_du = gu;
    if (dh_dv)
        *dh_dv = gv;
}

geom_status geom_scene_texture_sample_many(const geom_texture *t, size_t n, const double *uv,
                                           const double *footprint, size_t footprint_stride,
                                           double *out, double *grad)
{
    if (n == 0)
        return GEOM_OK;
    if (!t || !uv)
        return GEOM_ERR_INVALID_ARG;
    size_t c = t->channels;
    for (size_t i = 0; i < n; i++) {
        double u = uv[2 * i], v = uv[2 * i + 1];
        if (out)
            geom_scene_texture_sample(t, u, v, footprint ? footprint[i * footprint_stride] : 0.0,
                                      out + c * i);
        if (grad)
            geom_scene_texture_gradient(t, u, v, grad + 2 * i, grad + 2 * i + 1);
    }
    return GEOM_OK;
}
