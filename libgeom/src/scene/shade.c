/* Materials and local illumination: Phong (1975) and Blinn-Phong (1977)
 * specular, Lambertian diffuse, bump mapping (Blinn 1978), tangent-space
 * normal maps, and the cool-to-warm tone of Gooch et al. (1998). */
#include "geom/scene.h"

#include <math.h>

#include "core/internal.h"
#include "scene/scene_internal.h"

geom_material geom_scene_material_default(void)
{
    geom_material m = {0};
    m.kd = geom_vec3_make(0.8, 0.8, 0.8);
    m.ka = geom_vec3_make(0.1, 0.1, 0.1);
    m.ns = 32;
    m.ior = 1;
    return m;
}

unsigned geom_scene_material_needs(const geom_material *m)
{
    if (!m)
        return 0;
    unsigned f = GEOM_NEEDS_NORMAL;
    if (m->texture || m->bump || m->normal_map || m->displace)
        f |= GEOM_NEEDS_UV;
    if (m->normal_map || m->bump)
        f |= GEOM_NEEDS_TANGENT;
    if (m->reflect > 0)
        f |= GEOM_NEEDS_REFLECTION;
    if (m->transmit > 0)
        f |= GEOM_NEEDS_REFRACTION;
    return f;
}

static geom_vec3 unit_or(geom_vec3 a, geom_vec3 fallback)
{
    geom_vec3 u;
    return geom__v3unit(a, &u) ? u : fallback;
}

geom_vec3 geom_scene_shade_normal(const geom_material *m, const geom_shade_point *sp)
{
    geom_vec3 n = sp->n;
    if (m && sp->has_uv && sp->has_tangent && (m->normal_map || m->bump)) {
        /* Tangent frame: T orthogonalised against N, B = sign * N x T. */
        geom_vec3 t = geom_vec3_sub(sp->tangent, geom_vec3_scale(n, geom_vec3_dot(n, sp->tangent)));
        t = unit_or(t, sp->tangent);
        double sg = sp->tangent_sign < 0 ? -1.0 : 1.0;
        geom_vec3 b = geom_vec3_scale(geom_vec3_cross(n, t), sg);
        if (m->normal_map) {
            double c[4] = {0.5, 0.5, 1, 1};
            geom_scene_texture_sample(m->normal_map, sp->uv[0], sp->uv[1], sp->footprint, c);
            double x = 2 * c[0] - 1, y = 2 * c[1] - 1, z = 2 * c[2] - 1;
            n = unit_or(geom_vec3_add(geom_vec3_add(geom_vec3_scale(t, x), geom_vec3_scale(b, y)),
                                      geom_vec3_scale(n, z)),
                        n);
        } else {
            /* Blinn 1978: N' = N + h_u (N x P_v) - h_v (N x P_u), with the
             * unit tangent frame standing for (P_u, P_v). */
            double hu, hv, s = m->bump_scale != 0 ? m->bump_scale : 1.0;
            geom_scene_texture_gradient(m->bump, sp->uv[0], sp->uv[1], &hu, &hv);
            geom_vec3 d = geom_vec3_sub(geom_vec3_scale(geom_vec3_cross(n, b), s * hu),
                                        geom_vec3_scale(geom_vec3_cross(n, t), s * hv));
            n = unit_or(geom_vec3_add(n, d), n);
        }
    }
    if (geom_vec3_dot(n, sp->v) < 0)
        n = geom_vec3_neg(n);
    return n;
}

#define mul3 geom__v3mul

void geom_scene_shade(const geom_material *m, const geom_light *lights, size_t n_lights,
                const double *visibility, const geom_shade_point *sp, geom_vec3 n, geom_vec3 *out)
{
    geom_vec3 acc = {0, 0, 0};
    if (!m || !sp || !out) {
        if (out)
            *out = acc;
        return;
    }
    if (geom__v3dot(n, sp->v) < 0)
        n = geom__v3neg(n);
    geom_vec3 kd = m->kd, ka = m->ka;
    if (m->texture && sp->has_uv) {
        double c[4] = {1, 1, 1, 1};
        geom_scene_texture_sample(m->texture, sp->uv[0], sp->uv[1], sp->footprint, c);
        geom_vec3 tc = geom_scene_texture_channels(m->texture) >= 3 ? geom__v3(c[0], c[1], c[2])
                                                               : geom__v3(c[0], c[0], c[0]);
        kd = mul3(kd, tc);
        ka = mul3(ka, tc);
    }
    int gooch = m->style == GEOM_STYLE_COOL_TO_WARM, gooch_done = 0;
    for (size_t i = 0; i < n_lights; i++) {
        const geom_light *L = &lights[i];
        if (L->kind == GEOM_LIGHT_AMBIENT) {
            if (!gooch)
                acc = geom__v3add(acc, mul3(ka, L->color));
            continue;
        }
        double vis = visibility ? visibility[i] : 1.0;
        geom_vec3 l;
        if (L->kind == GEOM_LIGHT_POINT)
            l = unit_or(geom__v3sub(L->position, sp->p), n);
        else
            l = unit_or(geom__v3neg(L->direction), n);
        double nl = geom__v3dot(n, l);
        if (gooch) {
            if (gooch_done)
                continue;
            gooch_done = 1;
            double b = m->gooch_b != 0 ? m->gooch_b : 0.4, y = m->gooch_y != 0 ? m->gooch_y : 0.4;
            double al = m->gooch_alpha != 0 ? m->gooch_alpha : 0.2;
            double be = m->gooch_beta != 0 ? m->gooch_beta : 0.6;
            geom_vec3 kc = geom__v3add(geom__v3(0, 0, b), geom__v3scale(kd, al));
            geom_vec3 kw = geom__v3add(geom__v3(y, y, 0), geom__v3scale(kd, be));
            double s = 0.5 * (1 + nl);
            acc = geom__v3add(acc, geom__v3add(geom__v3scale(kw, s),
                                                   geom__v3scale(kc, 1 - s)));
        } else if (nl > 0 && vis > 0) {
            acc = geom__v3add(acc, geom__v3scale(mul3(kd, L->color), nl * vis));
        }
        if (nl > 0 && vis > 0 && (m->ks.x != 0 || m->ks.y != 0 || m->ks.z != 0)) {
            double sp_term;
            if (m->specular == GEOM_SPECULAR_PHONG) {
                geom_vec3 r = geom__v3sub(geom__v3scale(n, 2 * nl), l);
                double rv = geom__v3dot(r, sp->v);
                sp_term = rv > 0 ? pow(rv, m->ns) : 0;
            } else {
                geom_vec3 h = unit_or(geom__v3add(l, sp->v), n);
                double nh = geom__v3dot(n, h);
                sp_term = nh > 0 ? pow(nh, m->ns) : 0;
            }
            acc = geom__v3add(acc, geom__v3scale(mul3(m->ks, L->color), sp_term * vis));
        }
    }
    *out = acc;
}
