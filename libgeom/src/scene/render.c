/* Whole-scene rendering: bounds, visibility and reachability decide what is
 * built; the ray path traces every representation directly through the ray
 * module, the raster path tessellates to the pixel error. */
#include "geom/scene.h"

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

/* ------------------------------------------------------- ray-scene adapter */

typedef struct ray_user {
    const geom_ray_scene *rs;
    const uint32_t *root_object;  /* ray root -> scene object (NULL: identity) */
    const uint32_t *object_material;
    size_t n_objects;
    const geom_scene_object *objects; /* for mesh UVs/tangents; may be NULL */
    const unsigned *needs;            /* per scene object: material needs */
} ray_user;

static geom_vec3 any_tangent(geom_vec3 n)
{
    /* the direction of increasing longitude about z, where defined */
    geom_vec3 t = geom_vec3_cross(geom_vec3_make(0, 0, 1), n), u;
    if (geom_vec3_normalize(t, &u) != GEOM_OK)
        u = geom_vec3_make(1, 0, 0);
    return u;
}

/* UV (and tangent) of a mesh hit from the mesh's CORNER or VERTEX channels:
 * triangle faces only (the ray module's barycentrics are those of the face's
 * first fan triangle). */
static int mesh_attr(const geom_mesh *m, const char *name, size_t ncomp, uint32_t face, double u,
                     double v, double *out)
{
    if (!m || face >= geom_mesh_n_faces(m) || geom_mesh_face_valence(m, face) != 3)
        return 0;
    uint32_t c = geom_mesh_channel_find(m, name, GEOM_MESH_DOMAIN_CORNER);
    uint32_t vc = c == GEOM_INVALID_INDEX ? geom_mesh_channel_find(m, name, GEOM_MESH_DOMAIN_VERTEX)
                                          : GEOM_INVALID_INDEX;
    if (c == GEOM_INVALID_INDEX && vc == GEOM_INVALID_INDEX)
        return 0;
    uint32_t id = c != GEOM_INVALID_INDEX ? c : vc;
    if (geom_mesh_channel_ncomp(m, id) < ncomp)
        return 0;
    const double *d = geom_mesh_channel_cdata(m, id);
    const uint32_t *ci = c != GEOM_INVALID_INDEX ? geom_mesh_corner_cindices(m, c) : NULL;
    size_t k = geom_mesh_channel_ncomp(m, id);
    uint32_t h = geom_mesh_face_he(m, face);
    double w[3] = {1 - u - v, u, v};
    for (size_t j = 0; j < ncomp; j++)
        out[j] = 0;
    for (int i = 0; i < 3; i++) {
        uint32_t idx = ci ? ci[h] : geom_mesh_he_vertex(m, h);
        if (idx == GEOM_INVALID_INDEX)
            return 0;
        for (size_t j = 0; j < ncomp; j++)
            out[j] += w[i] * d[k * idx + j];
        h = geom_mesh_he_next(m, h);
    }
    return 1;
}

static int cb_closest(void *user, const geom_ray *r, geom__scene_hit *h)
{
    ray_user *u = user;
    int found = 0;
    geom_ray_hit rh;
    if (geom_ray_scene_closest(u->rs, r, &rh, &found) != GEOM_OK || !found)
        return 0;
    uint32_t obj = u->root_object ? u->root_object[rh.object] : rh.object;
    memset(h, 0, sizeof *h);
    h->raw = rh;
    h->t = rh.t;
    h->p = rh.point;
    h->ng = rh.ng;
    h->n = rh.ns;
    if (geom_vec3_dot(h->n, h->ng) < 0)
        h->n = geom_vec3_neg(h->n);
    h->object = obj;
    h->material = obj < u->n_objects ? u->object_material[obj] : UINT32_MAX;
    unsigned needs = u->needs ? u->needs[obj] : GEOM_NEEDS_UV;
    if (needs & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT)) {
        const geom_shape *sh = u->objects ? u->objects[obj].shape : NULL;
        int is_mesh = sh && sh->kind == GEOM_SHAPE_MESH && !sh->transform;
        if (is_mesh && mesh_attr(sh->mesh, "uv", 2, rh.prim, rh.u, rh.v, h->uv))
            h->has_uv = 1;
        else if (!is_mesh) {
            h->uv[0] = rh.u;
            h->uv[1] = rh.v;
            h->has_uv = 1;
        }
        if (needs & GEOM_NEEDS_TANGENT) {
            double t[4];
            if (is_mesh && mesh_attr(sh->mesh, "tangent", 4, rh.prim, rh.u, rh.v, t)) {
                h->tangent = geom_vec3_make(t[0], t[1], t[2]);
                h->tangent_sign = t[3] < 0 ? -1 : 1;
            } else {
                h->tangent = any_tangent(h->n);
                h->tangent_sign = 1;
            }
            h->has_tangent = 1;
        }
    }
    return 1;
}

static int cb_occluded(void *user, const geom_ray *r)
{
    ray_user *u = user;
    int found = 0;
    if (geom_ray_scene_any(u->rs, r, &found) != GEOM_OK)
        return 0;
    return found;
}

static geom_vec3 cb_spawn(void *user, const geom__scene_hit *h, geom_vec3 dir)
{
    (void)user;
    return geom_ray_offset_origin(&h->raw, dir);
}

geom_status geom_scene_trace(const geom_ray_scene *rs, const uint32_t *object_material,
                             size_t n_objects, const geom_camera *cam, const geom_light *lights,
                             size_t n_lights, const geom_material *materials, size_t n_materials,
                             const geom_trace_options *opt, geom_image *out,
                             geom_trace_report *report)
{
    if (!rs || (n_objects && !object_material))
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < n_objects; i++)
        if (object_material[i] >= n_materials)
            return GEOM_ERR_INVALID_ARG;
    ray_user u;
    memset(&u, 0, sizeof u);
    u.rs = rs;
    u.object_material = object_material;
    u.n_objects = n_objects;
    geom__tracer tr = {&u, cb_closest, cb_occluded, cb_spawn};
    return geom__scene_trace(&tr, cam, lights, n_lights, materials, n_materials, opt, out, report);
}

/* ------------------------------------------------------------ shape -> ray */

static geom_status add_one(geom_ray_scene *rs, const geom_shape *s, uint32_t *ids, size_t *n,
                           int top, geom_diag *diag)
{
    geom_status st = GEOM_OK;
    uint32_t id = GEOM_INVALID_INDEX;
    *n = 0;
    switch (s->kind) {
    case GEOM_SHAPE_SPHERE:
        st = geom_ray_scene_add_sphere(rs, s->p, s->radius, &id);
        break;
    case GEOM_SHAPE_BOX:
        st = geom_ray_scene_add_box(rs, s->min, s->max, &id);
        break;
    case GEOM_SHAPE_PLANE:
        st = geom_ray_scene_add_plane(rs, s->p, s->n, &id);
        break;
    case GEOM_SHAPE_DISK:
        st = geom_ray_scene_add_disk(rs, s->p, s->n, s->radius, &id);
        break;
    case GEOM_SHAPE_TORUS:
        st = geom_ray_scene_add_torus(rs, s->major, s->minor, &id);
        break;
    case GEOM_SHAPE_QUADRIC:
        st = geom_ray_scene_add_quadric(rs, s->q, s->clip, s->capped, &id);
        break;
    case GEOM_SHAPE_POLYGON:
        if (!s->vertices)
            st = GEOM_ERR_INVALID_ARG;
        else if (s->n_vertices == 3)
            st = geom_ray_scene_add_triangle(rs, s->vertices, &id);
        else
            st = geom_ray_scene_add_polygon(rs, s->vertices, s->n_vertices, &id);
        break;
    case GEOM_SHAPE_MESH:
        st = s->mesh ? geom_ray_scene_add_mesh(rs, s->mesh, &id) : GEOM_ERR_INVALID_ARG;
        break;
    case GEOM_SHAPE_SUBDIV:
        st = s->mesh ? geom_ray_scene_add_subdiv(rs, s->mesh, s->scheme, 0, &id, diag)
                     : GEOM_ERR_INVALID_ARG;
        break;
    case GEOM_SHAPE_IMPLICIT:
        st = s->expr ? geom_ray_scene_add_implicit(rs, s->expr, s->bounds, 0, &id)
                     : GEOM_ERR_INVALID_ARG;
        break;
    case GEOM_SHAPE_VOLUME:
        st = s->volume ? geom_ray_scene_add_volume(rs, s->volume, s->iso, &id) : GEOM_ERR_INVALID_ARG;
        break;
    case GEOM_SHAPE_SURFACE:
        if (!s->surfaces || !s->n_surfaces)
            return GEOM_ERR_INVALID_ARG;
        if (s->n_surfaces > 1 && !top)
            return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "object %s: a CSG child cannot have several surfaces",
                                 s->name ? s->name : "(unnamed)");
        for (size_t k = 0; k < s->n_surfaces && st == GEOM_OK; k++) {
            st = geom_ray_scene_add_surface(rs, &s->surfaces[k], &id, diag);
            if (st == GEOM_OK && s->transform)
                st = geom_ray_scene_set_transform(rs, id, s->transform->m);
            if (st == GEOM_OK)
                ids[(*n)++] = id;
        }
        return st;
    case GEOM_SHAPE_GROUP: {
        uint32_t *mem = geom_alloc(NULL, (s->n_members + 1) * sizeof *mem);
        size_t nm = 0;
        if (!mem)
            return GEOM_ERR_NOMEM;
        for (size_t k = 0; k < s->n_members && st == GEOM_OK; k++) {
            size_t got = 0;
            st = add_one(rs, s->members[k], mem + nm, &got, 0, diag);
            nm += got;
        }
        if (st == GEOM_OK)
            st = geom_ray_scene_add_group(rs, mem, nm, &id);
        geom_free(NULL, mem, (s->n_members + 1) * sizeof *mem);
        break;
    }
    case GEOM_SHAPE_CSG: {
        uint32_t a, b;
        size_t na, nb;
        if (!s->a || !s->b || s->csg_op < 1 || s->csg_op > 3)
            return GEOM_ERR_INVALID_ARG;
        if ((st = add_one(rs, s->a, &a, &na, 0, diag)) != GEOM_OK ||
            (st = add_one(rs, s->b, &b, &nb, 0, diag)) != GEOM_OK)
            return st;
        st = geom_ray_scene_add_csg(rs, (geom_ray_csg_op)s->csg_op, a, b, &id);
        break;
    }
    default:
        st = GEOM_ERR_INVALID_ARG;
    }
    if (st == GEOM_OK && s->transform)
        st = geom_ray_scene_set_transform(rs, id, s->transform->m);
    if (st == GEOM_OK) {
        ids[0] = id;
        *n = 1;
    } else if (diag && diag->message[0] == 0) {
        geom_diag_set(diag, st, NULL, 0, 0, "object %s: %s", s->name ? s->name : "(unnamed)",
                      geom_status_str(st));
    }
    return st;
}

geom_status geom_scene_shape_to_ray(geom_ray_scene *rs, const geom_shape *s, uint32_t *ids,
                                    size_t *n_ids, geom_diag *diag)
{
    if (!rs || !s || !ids || !n_ids)
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_scene_shape_to_ray: invalid argument");
    return add_one(rs, s, ids, n_ids, 1, diag);
}

/* ---------------------------------------------------------------- render */

static int bounded(geom_aabb b)
{
    return !geom_aabb_is_empty(b) && isfinite(b.min.x) && isfinite(b.min.y) && isfinite(b.min.z) &&
           isfinite(b.max.x) && isfinite(b.max.y) && isfinite(b.max.z);
}

static int overlap(geom_aabb a, geom_aabb b)
{
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
           a.min.z <= b.max.z && b.min.z <= a.max.z;
}

/* Largest scale of an affine transform (largest column norm of its 3x3). */
static double max_scale(const geom_mat4 *M)
{
    if (!M)
        return 1;
    double s = 0;
    for (int c = 0; c < 3; c++)
        s = fmax(s, geom_vec3_length(geom_vec3_make(M->m[4 * c], M->m[4 * c + 1], M->m[4 * c + 2])));
    return s > 0 ? s : 1;
}

geom_status geom_scene_render(const geom_camera *cam_in, const geom_light *lights, size_t n_lights,
                              const geom_material *materials, size_t n_materials,
                              const geom_scene_object *objects, size_t n_objects,
                              const geom_render_options *opt_in, geom_image *out,
                              geom_render_report *report, geom_render_object_report *orep_out,
                              geom_diag *diag)
{
    geom_render_report rep;
    memset(&rep, 0, sizeof rep);
    if (report)
        memset(report, 0, sizeof *report);
    if (!cam_in || !out || (n_lights && !lights) || !materials || !n_materials ||
        (n_objects && !objects))
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_scene_render: invalid argument");
    for (size_t i = 0; i < n_objects; i++)
        if (!objects[i].shape || objects[i].material >= n_materials)
            return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "object %zu: no shape or material index out of range", i);
    geom_render_options opt;
    memset(&opt, 0, sizeof opt);
    if (opt_in)
        opt = *opt_in;
    geom_camera cam = geom_camera_resolved(cam_in);
    geom_ray r0;
    geom_status st = geom_camera_ray(&cam, 0.5, 0.5, &r0);
    if (st != GEOM_OK)
        return st;
    double t0 = now();
    size_t n = n_objects ? n_objects : 1;
    geom_render_object_report *orep = geom_alloc(NULL, n * sizeof *orep);
    geom_aabb *box = geom_alloc(NULL, n * sizeof *box);
    unsigned *needs = geom_alloc(NULL, n * sizeof *needs);
    uint32_t *omat = geom_alloc(NULL, n * sizeof *omat);
    if (!orep || !box || !needs || !omat) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    memset(orep, 0, n * sizeof *orep);
    /* 1. bounds and visibility */
    geom_aabb seen = geom_aabb_empty(), all = geom_aabb_empty();
    geom_mat4 vp;
    {
        geom_aabb sb = geom_aabb_empty();
        for (size_t i = 0; i < n_objects; i++) {
            box[i] = geom_scene_shape_bounds(objects[i].shape);
            if (bounded(box[i]))
                sb = geom_aabb_union(sb, box[i]);
        }
        all = geom_aabb_extend(sb, cam.eye);
        for (size_t i = 0; i < n_lights; i++)
            if (lights[i].kind == GEOM_LIGHT_POINT)
                all = geom_aabb_extend(all, lights[i].position);
        double diag_all = geom_vec3_length(geom_vec3_sub(all.max, all.min));
        double far = 4 * diag_all + 1, near = far * 1e-7;
        geom_mat4 view, proj;
        if (cam.projection == GEOM_PROJECTION_ORTHOGRAPHIC) {
            double h = 0.5 * cam.ortho_height, asp = (double)cam.width / cam.height;
            geom_mat4_lookat(cam.eye, cam.center, cam.up, &view);
            geom_mat4_ortho(-h * asp, h * asp, -h, h, -far, far, &proj);
        } else {
            geom_camera_matrices(&cam, near, far, &view, &proj);
        }
        vp = geom_mat4_mul(proj, view);
    }
    int refl = 0, refr = 0;
    for (size_t i = 0; i < n_objects; i++) {
        orep[i].visible = bounded(box[i]) ? geom__scene_box_frustum(box[i], vp) != 0 : 1;
        needs[i] = geom_material_needs(&materials[objects[i].material]);
        omat[i] = objects[i].material;
        if (orep[i].visible) {
            if (bounded(box[i]))
                seen = geom_aabb_union(seen, box[i]);
            refl |= (needs[i] & GEOM_NEEDS_REFLECTION) != 0;
            refr |= (needs[i] & GEOM_NEEDS_REFRACTION) != 0;
        }
    }
    /* 2. reachability */
    for (size_t i = 0; i < n_objects; i++) {
        if (orep[i].visible || refl || refr || !bounded(box[i])) {
            orep[i].needed = orep[i].visible || refl || refr;
            continue;
        }
        if (opt.no_shadows || geom_aabb_is_empty(seen))
            continue;
        for (size_t l = 0; l < n_lights && !orep[i].needed; l++) {
            geom_aabb hull = seen;
            if (lights[l].kind == GEOM_LIGHT_POINT)
                hull = geom_aabb_extend(hull, lights[l].position);
            else if (lights[l].kind == GEOM_LIGHT_DIRECTIONAL) {
                double D = geom_vec3_length(geom_vec3_sub(all.max, all.min)) * 4 + 1;
                geom_vec3 back = geom_vec3_scale(lights[l].direction, -D);
                geom_aabb moved = {geom_vec3_add(seen.min, back), geom_vec3_add(seen.max, back)};
                hull = geom_aabb_union(hull, moved);
            } else
                continue;
            if (overlap(hull, box[i]))
                orep[i].needed = 1;
        }
    }
    /* refraction/reflection matter only through needed objects */
    refl = refr = 0;
    for (size_t i = 0; i < n_objects; i++)
        if (orep[i].needed) {
            rep.objects_needed++;
            refl |= (needs[i] & GEOM_NEEDS_REFLECTION) != 0;
            refr |= (needs[i] & GEOM_NEEDS_REFRACTION) != 0;
        }
    rep.reflection = refl;
    rep.refraction = refr;

    if (opt.method == GEOM_RENDER_RAY) {
        geom_ray_scene *rs = geom_ray_scene_create(NULL);
        uint32_t *roots = NULL, *root_obj = NULL;
        size_t nroots = 0, cap = 0;
        if (!rs) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        for (size_t i = 0; i < n_objects && st == GEOM_OK; i++) {
            if (!orep[i].needed)
                continue;
            const geom_shape *sh = objects[i].shape;
            size_t k = sh->kind == GEOM_SHAPE_SURFACE && sh->n_surfaces > 1 ? sh->n_surfaces : 1;
            if (nroots + k > cap) {
                size_t nc = (nroots + k) * 2;
                uint32_t *a = geom_realloc(NULL, roots, cap * sizeof *a, nc * sizeof *a);
                if (a)
                    roots = a;
                uint32_t *b = a ? geom_realloc(NULL, root_obj, cap * sizeof *b, nc * sizeof *b) : NULL;
                if (b)
                    root_obj = b;
                if (!a || !b) {
                    st = GEOM_ERR_NOMEM;
                    break;
                }
                cap = nc;
            }
            size_t got = 0;
            st = geom_scene_shape_to_ray(rs, sh, roots + nroots, &got, diag);
            for (size_t j = 0; j < got; j++)
                root_obj[nroots + j] = (uint32_t)i;
            nroots += got;
            orep[i].uvs = (needs[i] & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT)) != 0;
            orep[i].tangents = (needs[i] & GEOM_NEEDS_TANGENT) != 0;
            orep[i].normals = 1;
            if (sh->kind == GEOM_SHAPE_MESH || sh->kind == GEOM_SHAPE_SUBDIV) {
                orep[i].acceleration = 1;
            }
        }
        if (st == GEOM_OK)
            st = geom_ray_scene_set_objects(rs, roots, nroots);
        if (st == GEOM_OK)
            st = geom_ray_scene_build(rs, NULL, &rep.ray_build, diag);
        rep.seconds_build = now() - t0;
        if (st == GEOM_OK) {
            ray_user u;
            memset(&u, 0, sizeof u);
            u.rs = rs;
            u.root_object = root_obj;
            u.object_material = omat;
            u.n_objects = n_objects;
            u.objects = objects;
            u.needs = needs;
            geom__tracer tr = {&u, cb_closest, cb_occluded, cb_spawn};
            geom_trace_options to;
            memset(&to, 0, sizeof to);
            to.aov = opt.aov;
            to.background = opt.background;
            to.max_depth = opt.max_depth;
            to.min_weight = opt.min_weight;
            to.no_shadows = opt.no_shadows;
            double t1 = now();
            st = geom__scene_trace(&tr, &cam, lights, n_lights, materials, n_materials, &to, out,
                                   &rep.trace);
            rep.seconds_render = now() - t1;
        }
        geom_free(NULL, roots, cap * sizeof *roots);
        geom_free(NULL, root_obj, cap * sizeof *root_obj);
        geom_ray_scene_destroy(rs);
    } else {
        /* raster: tessellate what is needed to the pixel error */
        geom_mesh **meshes = geom_alloc(NULL, n * sizeof *meshes);
        geom_scene_draw *draws = geom_alloc(NULL, n * sizeof *draws);
        size_t nd = 0;
        if (!meshes || !draws) {
            geom_free(NULL, meshes, n * sizeof *meshes);
            geom_free(NULL, draws, n * sizeof *draws);
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        memset(meshes, 0, n * sizeof *meshes);
        /* unbounded shapes are cut to a box around everything bounded, the
         * eye and the point lights, 4 times its size */
        geom_aabb ext = all;
        {
            geom_vec3 c = geom_vec3_scale(geom_vec3_add(ext.min, ext.max), 0.5);
            geom_vec3 h = geom_vec3_scale(geom_vec3_sub(ext.max, ext.min), 2.0);
            double m = fmax(h.x, fmax(h.y, h.z)) + 1e-9;
            ext.min = geom_vec3_sub(c, geom_vec3_make(m, m, m));
            ext.max = geom_vec3_add(c, geom_vec3_make(m, m, m));
        }
        double pe = opt.pixel_error > 0 ? opt.pixel_error : 0.5;
        for (size_t i = 0; i < n_objects && st == GEOM_OK; i++) {
            if (!orep[i].needed)
                continue;
            const geom_shape *sh = objects[i].shape;
            geom_aabb wb = bounded(box[i]) ? box[i] : ext;
            if (!bounded(box[i]))
                wb = geom_aabb_union(geom_aabb_empty(), ext);
            double tol = opt.tolerance > 0 ? opt.tolerance
                                           : geom_scene_pixel_tolerance(&cam, wb, pe, NULL);
            if (!(tol > 0))
                tol = 1e-3 * geom_vec3_length(geom_vec3_sub(wb.max, wb.min)) + 1e-12;
            geom_tess_request rq;
            memset(&rq, 0, sizeof rq);
            rq.tol = tol / max_scale(sh->transform);
            rq.attributes = needs[i] & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT);
            if (sh->transform) {
                geom_mat4 inv;
                if (geom_mat4_inverse(*sh->transform, &inv) == GEOM_OK) {
                    rq.extent = geom_aabb_empty();
                    for (int c = 0; c < 8; c++) {
                        geom_vec3 p = geom_vec3_make(c & 1 ? ext.max.x : ext.min.x,
                                                     c & 2 ? ext.max.y : ext.min.y,
                                                     c & 4 ? ext.max.z : ext.min.z), q;
                        geom_mat4_transform_point(inv, p, &q);
                        rq.extent = geom_aabb_extend(rq.extent, q);
                    }
                }
            } else
                rq.extent = ext;
            meshes[i] = geom_mesh_create(NULL);
            if (!meshes[i]) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            st = geom_scene_tessellate(sh, &rq, meshes[i], &orep[i].tess, diag);
            if (st != GEOM_OK)
                break;
            {
                const geom_material *mt = &materials[objects[i].material];
                if (mt->displace && orep[i].tess.triangles) {
                    st = geom_scene_displace(meshes[i], mt->displace, mt->displace_scale);
                    if (st != GEOM_OK)
                        break;
                    orep[i].displaced = 1;
                }
            }
            orep[i].tessellated = 1;
            orep[i].tolerance = tol;
            orep[i].tess.error.max_error *= max_scale(sh->transform); /* world units */
            orep[i].tess.error.mean_error *= max_scale(sh->transform);
            orep[i].normals = geom_mesh_channel_find(meshes[i], "normal", GEOM_MESH_DOMAIN_CORNER) != GEOM_INVALID_INDEX ||
                              geom_mesh_channel_find(meshes[i], "normal", GEOM_MESH_DOMAIN_VERTEX) != GEOM_INVALID_INDEX;
            orep[i].uvs = geom_mesh_channel_find(meshes[i], "uv", GEOM_MESH_DOMAIN_CORNER) != GEOM_INVALID_INDEX ||
                          geom_mesh_channel_find(meshes[i], "uv", GEOM_MESH_DOMAIN_VERTEX) != GEOM_INVALID_INDEX;
            orep[i].tangents = geom_mesh_channel_find(meshes[i], "tangent", GEOM_MESH_DOMAIN_CORNER) != GEOM_INVALID_INDEX;
            draws[nd].mesh = meshes[i];
            draws[nd].transform = sh->transform;
            draws[nd].material = objects[i].material;
            draws[nd].object_id = (uint32_t)i;
            nd++;
        }
        rep.seconds_build = now() - t0;
        if (st == GEOM_OK) {
            geom_raster_options ro;
            memset(&ro, 0, sizeof ro);
            ro.aov = opt.aov;
            ro.background = opt.background;
            ro.shadows = !opt.no_shadows;
            ro.shadow_map_size = opt.shadow_map_size;
            double t1 = now();
            st = geom_scene_raster(&cam, lights, n_lights, materials, n_materials, draws, nd, &ro,
                                   out, &rep.raster);
            rep.seconds_render = now() - t1;
        }
        for (size_t i = 0; i < n_objects; i++)
            geom_mesh_destroy(meshes[i]);
        geom_free(NULL, meshes, n * sizeof *meshes);
        geom_free(NULL, draws, n * sizeof *draws);
    }
done:
    if (st == GEOM_OK && orep_out)
        memcpy(orep_out, orep, n_objects * sizeof *orep);
    geom_free(NULL, orep, n * sizeof *orep);
    geom_free(NULL, box, n * sizeof *box);
    geom_free(NULL, needs, n * sizeof *needs);
    geom_free(NULL, omat, n * sizeof *omat);
    if (report)
        *report = rep;
    return st;
}
