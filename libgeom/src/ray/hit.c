/* Hit lists, ray validity, error bounds and the offset-origin helper. */
#include "ray/ray_internal.h"

#include <stdlib.h>

void geom__rhits_init(geom__rhits *l, const geom_allocator *alloc)
{
    l->h = l->local;
    l->n = 0;
    l->cap = sizeof l->local / sizeof l->local[0];
    l->alloc = alloc;
    l->heap = 0;
    l->failed = 0;
}

void geom__rhits_free(geom__rhits *l)
{
    if (l->heap) geom__free(l->alloc, l->h, l->cap * sizeof *l->h);
    geom__rhits_init(l, l->alloc);
}

geom_ray_hit *geom__rhits_push_raw(geom__rhits *l)
{
    if (l->n == l->cap) {
        /* The inline buffer is not the allocator's: the first growth starts
         * a heap array and copies it over. */
        geom_ray_hit *nh = l->heap ? l->h : NULL;
        size_t cap = l->heap ? l->cap : 0;
        if (geom__grow(l->alloc, (void **)&nh, &cap, l->n + 1, sizeof *nh) != GEOM_OK) { l->failed = 1; return NULL; }
        if (!l->heap) memcpy(nh, l->h, l->n * sizeof *nh);
        l->h = nh;
        l->cap = cap;
        l->heap = 1;
    }
    return &l->h[l->n++];
}

geom_ray_hit *geom__rhits_push(geom__rhits *l)
{
    geom_ray_hit *h = geom__rhits_push_raw(l);
    if (h) memset(h, 0, sizeof *h);
    return h;
}

static int hit_cmp(const void *pa, const void *pb)
{
    const geom_ray_hit *a = pa, *b = pb;
    if (a->t < b->t) return -1;
    if (a->t > b->t) return 1;
    if (a->enter != b->enter) return a->enter ? -1 : 1;
    if (a->object != b->object) return a->object < b->object ? -1 : 1;
    if (a->prim != b->prim) return a->prim < b->prim ? -1 : 1;
    return 0;
}

void geom__rhits_sort(geom__rhits *l, size_t from)
{
    if (l->n > from + 1) qsort(l->h + from, l->n - from, sizeof *l->h, hit_cmp);
}

void geom__rslab_init(geom__rslab *s, const geom_ray *r)
{
    const double d[3] = {r->dir.x, r->dir.y, r->dir.z};
    int k;
    s->o[0] = r->origin.x; s->o[1] = r->origin.y; s->o[2] = r->origin.z;
    s->ok = 1;
    for (k = 0; k < 3; k++) {
        s->neg[k] = signbit(d[k]) != 0;
        s->inv[k] = d[k] != 0 ? 1.0 / d[k] : (s->neg[k] ? -INFINITY : INFINITY);
        if (d[k] != 0 && !(fabs(s->inv[k]) <= 0x1p1000)) s->ok = 0;
    }
}

geom_status geom_ray_check(const geom_ray *r)
{
    return r && geom__ray_valid(r) ? GEOM_OK : GEOM_ERR_INVALID_ARG;
}

geom_vec3 geom__perr_ray(const geom_ray *r, double t)
{
    double g = geom__gamma(3);
    geom_vec3 e;
    e.x = g * (fabs(r->origin.x) + fabs(t * r->dir.x));
    e.y = g * (fabs(r->origin.y) + fabs(t * r->dir.y));
    e.z = g * (fabs(r->origin.z) + fabs(t * r->dir.z));
    return e;
}

double geom__terr(const geom_ray *r, double t, double dist, geom_vec3 n)
{
    geom_vec3 pe = geom__perr_ray(r, t);
    double num = fabs(dist) + fabs(n.x) * pe.x + fabs(n.y) * pe.y + fabs(n.z) * pe.z;
    double den = fabs(geom__dot(n, r->dir));
    double e = DBL_EPSILON * fabs(t);
    if (den > 0) e += num / den;
    else e = INFINITY;
    return e;
}

void geom__frame(geom_vec3 n, geom_vec3 *t1, geom_vec3 *t2)
{
    /* Duff et al. 2017, "Building an Orthonormal Basis, Revisited". */
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double b = n.x * n.y * a;
    t1->x = 1.0 + sign * n.x * n.x * a;
    t1->y = sign * b;
    t1->z = -sign * n.x;
    t2->x = b;
    t2->y = sign + n.y * n.y * a;
    t2->z = -n.y;
}

geom_ray_hit *geom__push_t(geom__rhits *out, const geom_ray *r, double t)
{
    geom_ray_hit *h;
    if (!(t >= r->tmin && t <= r->tmax)) return NULL;
    h = geom__rhits_push(out);
    if (h) h->t = t;
    return h;
}

/* x moved by k ulps toward +inf (k > 0) or -inf (k < 0), by integer
 * arithmetic on the representation as Waechter and Binder do. */
static double ulp_step(double x, int64_t k)
{
    int64_t i;
    if (x == 0) return k > 0 ? DBL_TRUE_MIN * (double)k : -DBL_TRUE_MIN * (double)-k;
    memcpy(&i, &x, sizeof i);
    /* Moving away from zero increases the magnitude bits. */
    if ((x > 0) == (k > 0)) i += k > 0 ? k : -k;
    else i -= k > 0 ? k : -k;
    memcpy(&x, &i, sizeof x);
    return x;
}

geom_vec3 geom_ray_offset_origin(const geom_ray_hit *hit, geom_vec3 dir)
{
    const int64_t int_scale = 64;
    double p[3] = {hit->point.x, hit->point.y, hit->point.z};
    double n[3] = {hit->ng.x, hit->ng.y, hit->ng.z};
    double pe[3] = {hit->p_error.x, hit->p_error.y, hit->p_error.z};
    double sdot = dir.x * n[0] + dir.y * n[1] + dir.z * n[2];
    double s = (isfinite(sdot) && sdot < 0) ? -1.0 : 1.0;
    double d = 0, scale = 0;
    geom_vec3 o;
    int k;
    for (k = 0; k < 3; k++) {
        double e = isfinite(pe[k]) ? fabs(pe[k]) : 0;
        d += fabs(n[k]) * e;
        if (fabs(p[k]) > scale) scale = fabs(p[k]);
    }
    for (k = 0; k < 3; k++) {
        double off = s * n[k] * d;
        double q = p[k] + off;
        /* Waechter-Binder: integer ulps away from the surface; an absolute
         * floor near zero where ulps vanish. */
        if (n[k] != 0) {
            int64_t steps = (int64_t)(int_scale * fabs(n[k])) + 1;
            double floor_abs = ldexp(scale, -40) * fabs(n[k]);
            q = ulp_step(q, s * n[k] > 0 ? steps : -steps);
            if (fabs(q - p[k]) < floor_abs) q = p[k] + s * n[k] * ldexp(scale, -40) + off;
        }
        p[k] = q;
    }
    o.x = p[0];
    o.y = p[1];
    o.z = p[2];
    return o;
}
