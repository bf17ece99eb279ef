/* Sphere by the stable formulation of Haines, Guenther and Akenine-Moeller,
 * "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems,
 * ch. 7, 2019). prm: centre (0..2), radius (3). */
#include "ray/ray_internal.h"

geom_status geom__ray_sphere(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    geom_vec3 c = geom__v3(nd->prm), f = geom_vec3_sub(r->origin, c), l;
    double rad = nd->prm[3], a = geom__dot(r->dir, r->dir), b = geom__dot(f, r->dir), disc, cc, q;
    double ts[2];
    int i;
    /* Line-to-centre vector: f - (f.d / d.d) d; disc = a (r^2 - |l|^2). */
    l = geom_vec3_sub(f, geom_vec3_scale(r->dir, b / a));
    disc = a * (rad - geom_vec3_length(l)) * (rad + geom_vec3_length(l));
    if (disc < 0) return GEOM_OK;
    cc = geom__dot(f, f) - rad * rad;
    q = -(b + copysign(sqrt(disc), b));
    if (q != 0) {
        ts[0] = cc / q;
        ts[1] = q / a;
    } else {
        ts[0] = -sqrt(disc) / a;
        ts[1] = sqrt(disc) / a;
    }
    if (ts[0] > ts[1]) {
        double t = ts[0]; ts[0] = ts[1]; ts[1] = t;
    }
    for (i = 0; i < 2; i++) {
        geom_ray_hit *h = geom__push_t(out, r, ts[i]);
        geom_vec3 p, rel, n;
        double len, g;
        if (!h) { if (out->failed) return GEOM_ERR_NOMEM; continue; }
        p = geom_vec3_add(r->origin, geom_vec3_scale(r->dir, ts[i]));
        rel = geom_vec3_sub(p, c);
        len = geom_vec3_length(rel);
        n = len > 0 ? geom_vec3_scale(rel, 1.0 / len) : geom__unit(geom_vec3_neg(r->dir));
        h->t_error = geom__terr(r, ts[i], len - rad, n);
        /* Re-project onto the sphere (pbrt): error ~ gamma(5) (|c| + r). */
        p = geom_vec3_add(c, geom_vec3_scale(n, rad));
        h->point = p;
        g = geom__gamma(5);
        h->p_error.x = g * (fabs(c.x) + rad);
        h->p_error.y = g * (fabs(c.y) + rad);
        h->p_error.z = g * (fabs(c.z) + rad);
        h->ng = h->ns = n;
        h->enter = i == 0;
        {
            double phi = atan2(n.y, n.x);
            if (phi < 0) phi += 2 * GEOM_PI;
            h->u = phi / (2 * GEOM_PI);
            if (h->u >= 1) h->u = 0;
            h->v = acos(fmax(-1.0, fmin(1.0, n.z))) / GEOM_PI;
        }
        if (mode == GEOM__RAY_ANY) break;
    }
    return GEOM_OK;
}
