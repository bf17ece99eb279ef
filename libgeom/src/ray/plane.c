/* Planes and disks. prm: point (0..2), unit normal (3..5), radius (6, disk),
 * the (u, v) frame's tangents t1 (9..11) and t2 (12..14), made once when the
 * object is added. */
#include "ray/ray_internal.h"

static geom_ray_hit *plane_hit(const geom__ray_node *nd, const geom_ray *r, geom__rhits *out,
                               double *rho2, geom_vec3 *rel)
{
    geom_vec3 c = geom__v3(nd->prm), n = geom__v3(nd->prm + 3), p;
    double dn = geom__dot(r->dir, n), t;
    geom_ray_hit *h;
    if (dn == 0) return NULL; /* parallel (also within the plane): miss */
    t = geom__dot(geom_vec3_sub(c, r->origin), n) / dn;
    if (!(t >= r->tmin && t <= r->tmax)) return NULL;
    p = geom_vec3_add(r->origin, geom_vec3_scale(r->dir, t));
    /* Project onto the plane: remove the residual distance along n. */
    {
        double dist = geom__dot(geom_vec3_sub(p, c), n);
        p = geom_vec3_sub(p, geom_vec3_scale(n, dist));
    }
    *rel = geom_vec3_sub(p, c);
    *rho2 = geom__dot(*rel, *rel);
    if (nd->kind == GEOM_RAY_DISK && *rho2 > nd->prm[6] * nd->prm[6]) return NULL;
    h = geom__rhits_push(out);
    if (!h) return NULL;
    h->t = t;
    h->point = p;
    h->ng = h->ns = n;
    h->enter = dn < 0;
    {
        double g = geom__gamma(4);
        h->p_error.x = g * (fabs(c.x) + fabs(rel->x)) + g * fabs(p.x);
        h->p_error.y = g * (fabs(c.y) + fabs(rel->y)) + g * fabs(p.y);
        h->p_error.z = g * (fabs(c.z) + fabs(rel->z)) + g * fabs(p.z);
    }
    h->t_error = geom__terr(r, t, 0, n);
    return h;
}

geom_status geom__ray_plane(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    double rho2;
    geom_vec3 rel;
    geom_ray_hit *h;
    (void)mode;
    h = plane_hit(nd, r, out, &rho2, &rel);
    if (!h) return out->failed ? GEOM_ERR_NOMEM : GEOM_OK;
    h->u = geom__dot(rel, geom__v3(nd->prm + 9));
    h->v = geom__dot(rel, geom__v3(nd->prm + 12));
    return GEOM_OK;
}

geom_status geom__ray_disk(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    double rho2, a;
    geom_vec3 rel;
    geom_ray_hit *h;
    (void)mode;
    h = plane_hit(nd, r, out, &rho2, &rel);
    if (!h) return out->failed ? GEOM_ERR_NOMEM : GEOM_OK;
    h->u = sqrt(rho2) / nd->prm[6];
    a = atan2(geom__dot(rel, geom__v3(nd->prm + 12)), geom__dot(rel, geom__v3(nd->prm + 9)));
    if (a < 0) a += 2 * GEOM_PI;
    h->v = a / (2 * GEOM_PI);
    if (h->v >= 1) h->v = 0;
    return GEOM_OK;
}
