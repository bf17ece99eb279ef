/* Export: every object tessellated to its tolerance with the attributes its
 * material uses, transformed, joined into one mesh with a group per object. */
#include "geom/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/internal.h"
#include "scene/scene_internal.h"

static const char *const CH[3] = {"normal", "uv", "tangent"};
static const size_t NC[3] = {3, 2, 4};

/* Corner value of channel c at halfedge h of m into v (zero if none). */
static void corner_value(const geom_mesh *m, int c, uint32_t h, double *v)
{
    memset(v, 0, NC[c] * sizeof(double));
    uint32_t id = geom_mesh_channel_find(m, CH[c], GEOM_MESH_DOMAIN_CORNER);
    if (id != GEOM_INVALID_INDEX) {
        uint32_t k = geom_mesh_corner_cindices(m, id)[h];
        if (k != GEOM_INVALID_INDEX)
            memcpy(v, geom_mesh_channel_cdata(m, id) + NC[c] * k, NC[c] * sizeof(double));
        return;
    }
    id = geom_mesh_channel_find(m, CH[c], GEOM_MESH_DOMAIN_VERTEX);
    if (id != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, id) >= NC[c])
        memcpy(v, geom_mesh_channel_cdata(m, id) + geom_mesh_channel_ncomp(m, id) * geom_mesh_he_vertex(m, h),
               NC[c] * sizeof(double));
}

/* Checks the objects and returns the extent unbounded shapes are cut to:
 * twice the box of the bounded ones and the eye. */
static geom_status export_extent(const geom_camera *cam, size_t n_materials,
                                 const geom_scene_object *objects, size_t n, geom_aabb *out,
                                 geom_diag *diag)
{
    geom_aabb all = geom_aabb_empty();
    for (size_t i = 0; i < n; i++) {
        if (objects[i].material >= n_materials || !objects[i].shape)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "object %zu: no shape or material out of range", i);
        geom_aabb b = geom_scene_shape_bounds(objects[i].shape);
        if (!geom_aabb_is_empty(b) && isfinite(b.min.x) && isfinite(b.max.x) && isfinite(b.min.y) &&
            isfinite(b.max.y) && isfinite(b.min.z) && isfinite(b.max.z))
            all = geom_aabb_union(all, b);
    }
    if (cam)
        all = geom_aabb_extend(all, cam->eye);
    if (geom_aabb_is_empty(all))
        all.min = all.max = geom_vec3_make(0, 0, 0);
    geom_vec3 c = geom_vec3_scale(geom_vec3_add(all.min, all.max), 0.5);
    geom_vec3 h = geom_vec3_sub(all.max, all.min);
    double m = fmax(h.x, fmax(h.y, h.z)) + 1;
    all.min = geom_vec3_sub(c, geom_vec3_make(m, m, m));
    all.max = geom_vec3_add(c, geom_vec3_make(m, m, m));
    *out = all;
    return GEOM_OK;
}

/* Object i's tessellation request (its own frame), its world tolerance
 * (*tol) and the transform's largest scale (*sc: errors scale by it). */
static void export_request(const geom_camera *cam, const geom_material *materials,
                           const geom_scene_object *obj, const geom_export_options *opt,
                           geom_aabb all, geom_tess_request *rq, double *tol_out, double *sc_out)
{
    const geom_shape *sh = obj->shape;
    unsigned need = geom_scene_material_needs(&materials[obj->material]) &
                    (GEOM_NEEDS_NORMAL | GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT);
    if (need & GEOM_NEEDS_TANGENT)
        need |= GEOM_NEEDS_UV;
    double pe = opt->pixel_error > 0 ? opt->pixel_error : 0.5;
    geom_aabb b = geom_scene_shape_bounds(sh);
    if (!(isfinite(b.min.x) && isfinite(b.max.x) && isfinite(b.min.y) && isfinite(b.max.y) &&
          isfinite(b.min.z) && isfinite(b.max.z)))
        b = all;
    double tol = opt->tolerance > 0 ? opt->tolerance : geom_scene_pixel_tolerance(cam, b, pe, NULL);
    if (!(tol > 0))
        tol = 1e-3 * geom_vec3_length(geom_vec3_sub(b.max, b.min)) + 1e-12;
    memset(rq, 0, sizeof *rq);
    double sc = 1;
    if (sh->transform) {
        sc = 0;
        for (int c = 0; c < 3; c++)
            sc = fmax(sc, geom_vec3_length(geom_vec3_make(sh->transform->m[4 * c],
                                                          sh->transform->m[4 * c + 1],
                                                          sh->transform->m[4 * c + 2])));
        if (!(sc > 0))
            sc = 1;
        geom_mat4 inv;
        if (geom_mat4_inverse(*sh->transform, &inv) == GEOM_OK) {
            rq->extent = geom_aabb_empty();
            for (int c = 0; c < 8; c++) {
                geom_vec3 p = geom_vec3_make(c & 1 ? all.max.x : all.min.x, c & 2 ? all.max.y : all.min.y,
                                             c & 4 ? all.max.z : all.min.z), q;
                geom_mat4_transform_point(inv, p, &q);
                rq->extent = geom_aabb_extend(rq->extent, q);
            }
        }
    } else
        rq->extent = all;
    rq->tol = tol / sc;
    rq->attributes = need;
    *tol_out = tol;
    *sc_out = sc;
}

geom_status geom_scene_export_estimate(const geom_camera *cam, const geom_material *materials,
                                       size_t n_materials, const geom_scene_object *objects,
                                       size_t n, const geom_export_options *opt_in,
                                       double *per_object, double *triangles, geom_diag *diag)
{
    geom_export_options opt;
    memset(&opt, 0, sizeof opt);
    if (opt_in)
        opt = *opt_in;
    if (triangles)
        *triangles = 0;
    if (!triangles || (n && !objects) || !materials || !n_materials ||
        (!cam && !(opt.tolerance > 0)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "export estimate needs objects, materials, a camera or a tolerance, "
                             "and an output");
    geom_aabb all;
    geom_status st = export_extent(cam, n_materials, objects, n, &all, diag);
    double total = 0;
    /* with max_triangles: the cheap bounds first, the exact trials only when
     * their sum is above it */
    for (int cheap = opt.max_triangles > 0; cheap >= 0 && st == GEOM_OK; cheap--) {
        total = 0;
        for (size_t i = 0; i < n && st == GEOM_OK; i++) {
            geom_tess_request rq;
            double tol, sc, t = 0;
            export_request(cam, materials, &objects[i], &opt, all, &rq, &tol, &sc);
            st = geom__scene_tessellate_estimate(objects[i].shape, &rq, cheap, &t);
            if (st != GEOM_OK)
                geom__diag_set(diag, st, NULL, 0, 0, "object %zu: no estimate: %s", i,
                              geom_status_str(st));
            if (per_object)
                per_object[i] = t;
            total += t;
        }
        if (total <= opt.max_triangles)
            break;
    }
    *triangles = st == GEOM_OK ? total : 0;
    return st;
}

geom_status geom_scene_export(const geom_camera *cam, const geom_material *materials,
                              size_t n_materials, const geom_scene_object *objects, size_t n,
                              const char *const *names, const geom_export_options *opt_in,
                              geom_mesh *out, geom_export_object_report *reports, geom_diag *diag)
{
    geom_export_options opt;
    memset(&opt, 0, sizeof opt);
    if (opt_in)
        opt = *opt_in;
    if (!out || (n && !objects) || !materials || !n_materials || (!cam && !(opt.tolerance > 0)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "export needs objects, materials, and a camera or a tolerance");
    int has_world = 0;
    for (int k = 0; k < 16; k++)
        has_world |= opt.world.m[k] != 0;
    geom_aabb all;
    geom_status st0 = export_extent(cam, n_materials, objects, n, &all, diag);
    if (st0 != GEOM_OK)
        return st0;
    geom_mesh **parts = geom__alloc(NULL, (n ? n : 1) * sizeof *parts);
    if (!parts)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_scene_export: out of memory");
    memset(parts, 0, (n ? n : 1) * sizeof *parts);
    unsigned any = 0;
    geom_status st = GEOM_OK;
    for (size_t i = 0; i < n && st == GEOM_OK; i++) {
        const geom_shape *sh = objects[i].shape;
        geom_tess_request rq;
        double tol, sc;
        export_request(cam, materials, &objects[i], &opt, all, &rq, &tol, &sc);
        unsigned need = rq.attributes;
        any |= need;
        parts[i] = geom_mesh_create(NULL);
        if (!parts[i]) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        geom_export_object_report r;
        memset(&r, 0, sizeof r);
        st = geom_scene_tessellate(sh, &rq, parts[i], &r.tess, diag);
        if (st == GEOM_OK && materials[objects[i].material].displace)
            st = geom_scene_displace(parts[i], materials[objects[i].material].displace,
                                     materials[objects[i].material].displace_scale);
        if (st == GEOM_OK && sh->transform)
            st = geom_scene_mesh_transform(parts[i], *sh->transform);
        if (st == GEOM_OK && has_world)
            st = geom_scene_mesh_transform(parts[i], opt.world);
        if (st == GEOM_OK && geom_mesh_n_faces(parts[i]))
            st = geom_mesh_triangulate(parts[i], NULL);
        /* the error in world units (the transform scales it by at most sc) */
        r.tess.error.max_error *= sc;
        r.tess.error.mean_error *= sc;
        r.tolerance = tol;
        r.attributes = need;
        if (reports)
            reports[i] = r;
        if (st == GEOM_ERR_LIMIT && diag) {
            /* say how far over: the estimate at the tolerance asked */
            double est = 0;
            geom_scene_tessellate_estimate(sh, &rq, &est);
            geom__diag_set(diag, st, NULL, 0, 0,
                          "object %s: limit exceeded: about %.0f triangles (estimate) at "
                          "tolerance %.3g; coarsen the tolerance",
                          names && names[i] ? names[i] : "?", est, tol);
        } else if (st != GEOM_OK && diag && !strstr(diag->message, "object"))
            geom__diag_set(diag, st, NULL, 0, 0, "object %s: %s",
                          names && names[i] ? names[i] : "?", geom_status_str(st));
    }
    /* join */
    size_t nv = 0, nf = 0, ni = 0;
    for (size_t i = 0; i < n && st == GEOM_OK; i++) {
        size_t k = 0;
        st = geom_mesh_to_soup(parts[i], NULL, NULL, &k);
        nv += geom_mesh_n_vertices(parts[i]);
        nf += geom_mesh_n_live_faces(parts[i]);
        ni += k;
    }
    double *xyz = NULL;
    uint32_t *sizes = NULL, *idx = NULL, *fobj = NULL;
    if (st == GEOM_OK) {
        xyz = geom__alloc(NULL, (3 * nv + 1) * sizeof *xyz);
        sizes = geom__alloc(NULL, (nf + 1) * sizeof *sizes);
        idx = geom__alloc(NULL, (ni + 1) * sizeof *idx);
        fobj = geom__alloc(NULL, (nf + 1) * sizeof *fobj);
        if (!xyz || !sizes || !idx || !fobj)
            st = GEOM_ERR_NOMEM;
    }
    size_t ov = 0, of = 0, oi = 0;
    for (size_t i = 0; i < n && st == GEOM_OK; i++) {
        size_t k = 0, mv = geom_mesh_n_vertices(parts[i]), mf = geom_mesh_n_live_faces(parts[i]);
        st = geom_mesh_to_soup(parts[i], sizes + of, idx + oi, &k);
        memcpy(xyz + 3 * ov, geom_mesh_cpositions(parts[i]), 3 * mv * sizeof(double));
        for (size_t j = 0; j < k; j++)
            idx[oi + j] += (uint32_t)ov;
        for (size_t f = 0; f < mf; f++)
            fobj[of + f] = (uint32_t)i;
        ov += mv;
        of += mf;
        oi += k;
    }
    if (st == GEOM_OK) {
        geom_mesh_build_options bo;
        memset(&bo, 0, sizeof bo);
        bo.keep_orientation = 1;
        st = geom_mesh_build(out, nv, xyz, nf, sizes, idx, &bo, NULL, diag);
    }
    /* groups */
    if (st == GEOM_OK && geom_mesh_n_faces(out) == nf) {
        uint32_t *gid = geom__alloc(NULL, (n + 1) * sizeof *gid);
        uint32_t *fg = geom_mesh_face_groups(out);
        if (!gid || !fg)
            st = GEOM_ERR_NOMEM;
        for (size_t i = 0; i < n && st == GEOM_OK; i++) {
            geom_mesh_group g;
            memset(&g, 0, sizeof g);
            char buf[32];
            snprintf(buf, sizeof buf, "object%zu", i);
            g.object = names && names[i] ? names[i] : buf;
            st = geom_mesh_group_add(out, &g, &gid[i]);
        }
        for (size_t f = 0; f < nf && st == GEOM_OK; f++)
            fg[f] = gid[fobj[f]];
        geom__free(NULL, gid, (n + 1) * sizeof *gid);
    }
    /* corner channels: one pool entry per corner */
    for (int c = 0; c < 3 && st == GEOM_OK && geom_mesh_n_faces(out) == nf; c++) {
        unsigned bit = c == 0 ? GEOM_NEEDS_NORMAL : c == 1 ? GEOM_NEEDS_UV : GEOM_NEEDS_TANGENT;
        if (!(any & bit))
            continue;
        uint32_t id;
        if ((st = geom_mesh_channel_add(out, CH[c], GEOM_MESH_DOMAIN_CORNER, NC[c], &id)) != GEOM_OK ||
            (st = geom_mesh_corner_pool_resize(out, id, ni)) != GEOM_OK)
            break;
        uint32_t *ci = geom_mesh_corner_indices(out, id);
        size_t corner = 0;
        uint32_t f_out = 0;
        for (size_t i = 0; i < n; i++) {
            const geom_mesh *m = parts[i];
            for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++) {
                if (geom_mesh_face_is_deleted(m, f))
                    continue;
                uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
                /* geom_mesh_build starts each face at its first input vertex,
                 * as geom_mesh_to_soup listed it from face_he */
                uint32_t g = geom_mesh_face_he(out, f_out);
                size_t val = geom_mesh_face_valence(m, f);
                for (size_t s = 0; s < val; s++) {
                    double *dst = geom_mesh_channel_data(out, id) + NC[c] * corner;
                    corner_value(m, c, h, dst);
                    ci[g] = (uint32_t)corner++;
                    h = geom_mesh_he_next(m, h);
                    g = geom_mesh_he_next(out, g);
                }
                f_out++;
            }
        }
    }
    for (size_t i = 0; i < n; i++)
        geom_mesh_destroy(parts[i]);
    geom__free(NULL, parts, (n ? n : 1) * sizeof *parts);
    geom__free(NULL, xyz, (3 * nv + 1) * sizeof *xyz);
    geom__free(NULL, sizes, (nf + 1) * sizeof *sizes);
    geom__free(NULL, idx, (ni + 1) * sizeof *idx);
    geom__free(NULL, fobj, (nf + 1) * sizeof *fobj);
    return st;
}
