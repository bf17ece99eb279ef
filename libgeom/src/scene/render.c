/* Whole-scene rendering: bounds, visibility and reachability decide what is
 * built; the ray path traces every representation directly through the ray
 * module, the raster path tessellates to the pixel error. */
#include "geom/scene.h"

#include <math.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "scene/scene_internal.h"
#include "ray/ray_walk.h"

static double now(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------------- ray-scene adapter */

/* Corner attributes of one object's traced triangles (meshes): read from
 * the ray scene's stored mesh through the shape walk. */
typedef struct obj_attr {
    const double *pos, *cuv, *cnrm; /* local frame */
    const uint32_t *tri;
    size_t nt;
    uint32_t *face_tri;             /* face (hit prim) -> triangle, or NULL: identity */
    size_t nfaces;
    int has_xf;
    double m3[9], nm3[9];           /* column-major 3x3 of the transform and its inverse transpose */
} obj_attr;

typedef struct ray_user {
    const geom_ray_scene *rs;
    const uint32_t *root_object;  /* ray root -> scene object (NULL: identity) */
    const uint32_t *object_material;
    size_t n_objects;
    const unsigned *needs;            /* per scene object: material needs */
    const obj_attr *attr;             /* per scene object, or NULL */
    const geom_material *materials;   /* for shadow rays through transmissive surfaces */
    int transmissive;                 /* some object's material transmits */
} ray_user;

static geom_vec3 any_tangent(geom_vec3 n)
{
    /* the direction of increasing longitude about z, where defined */
    geom_vec3 t = geom__v3cross(geom__v3(0, 0, 1), n), u;
    if (!geom__v3unit(t, &u))
        u = geom__v3(1, 0, 0);
    return u;
}

static geom_vec3 mul3x3(const double *m, geom_vec3 v)
{
    return geom__v3(m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z,
                    m[2] * v.x + m[5] * v.y + m[8] * v.z);
}

/* UVs, shading normal and tangent of a mesh hit from the stored corner
 * attributes, interpolated with the hit's barycentrics. */
static void mesh_hit_attrs(const obj_attr *A, const geom_ray_hit *rh, unsigned needs, geom__scene_hit *h)
{
    size_t k = rh->prim;
    if (A->face_tri)
        k = rh->prim < A->nfaces ? A->face_tri[rh->prim] : (size_t)-1;
    if (k >= A->nt)
        return;
    double w[3] = {1 - rh->u - rh->v, rh->u, rh->v};
    if (A->cnrm) {
        const double *c = A->cnrm + 9 * k;
        geom_vec3 n = geom__v3(w[0] * c[0] + w[1] * c[3] + w[2] * c[6],
                               w[0] * c[1] + w[1] * c[4] + w[2] * c[7],
                               w[0] * c[2] + w[1] * c[5] + w[2] * c[8]);
        if (A->has_xf)
            n = mul3x3(A->nm3, n);
        if (geom__v3unit(n, &n))
            h->n = geom__v3dot(n, h->ng) < 0 ? geom__v3neg(n) : n;
    }
    if (!A->cuv || !(needs & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT)))
        return;
    const double *t = A->cuv + 6 * k;
    h->uv[0] = w[0] * t[0] + w[1] * t[2] + w[2] * t[4];
    h->uv[1] = w[0] * t[1] + w[1] * t[3] + w[2] * t[5];
    h->has_uv = 1;
    if (!(needs & GEOM_NEEDS_TANGENT))
        return;
    /* dP/du of the triangle's linear UV map */
    const uint32_t *tv = A->tri + 3 * k;
    geom_vec3 p0 = geom__v3(A->pos[3 * tv[0]], A->pos[3 * tv[0] + 1], A->pos[3 * tv[0] + 2]);
    geom_vec3 e1 = geom__v3sub(geom__v3(A->pos[3 * tv[1]], A->pos[3 * tv[1] + 1], A->pos[3 * tv[1] + 2]), p0);
    geom_vec3 e2 = geom__v3sub(geom__v3(A->pos[3 * tv[2]], A->pos[3 * tv[2] + 1], A->pos[3 * tv[2] + 2]), p0);
    double du1 = t[2] - t[0], dv1 = t[3] - t[1], du2 = t[4] - t[0], dv2 = t[5] - t[1];
    double det = du1 * dv2 - du2 * dv1;
    if (det == 0 || !isfinite(det))
        return;
    geom_vec3 T = geom__v3scale(geom__v3sub(geom__v3scale(e1, dv2), geom__v3scale(e2, dv1)), 1 / det);
    geom_vec3 B = geom__v3scale(geom__v3sub(geom__v3scale(e2, du1), geom__v3scale(e1, du2)), 1 / det);
    if (A->has_xf) {
        T = mul3x3(A->m3, T);
        B = mul3x3(A->m3, B);
    }
    if (!geom__v3unit(T, &T))
        return;
    h->tangent = T;
    h->tangent_sign = geom__v3dot(geom__v3cross(h->n, T), B) < 0 ? -1 : 1;
    h->has_tangent = 1;
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
    if (geom__v3dot(h->n, h->ng) < 0)
        h->n = geom__v3neg(h->n);
    h->object = obj;
    h->material = obj < u->n_objects ? u->object_material[obj] : UINT32_MAX;
    unsigned needs = u->needs ? u->needs[obj] : GEOM_NEEDS_UV;
    const obj_attr *A = u->attr && obj < u->n_objects && u->attr[obj].tri ? &u->attr[obj] : NULL;
    if (A)
        mesh_hit_attrs(A, &rh, needs, h);
    else if (needs & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT)) {
        h->uv[0] = rh.u;
        h->uv[1] = rh.v;
        h->has_uv = 1;
    }
    if ((needs & GEOM_NEEDS_TANGENT) && !h->has_tangent) {
        h->tangent = any_tangent(h->n);
        h->tangent_sign = 1;
        h->has_tangent = 1;
    }
    return 1;
}

/* Light passing along a shadow ray: 1 without a hit; through surfaces of
 * transmissive materials the product of their `transmit` weights, one
 * factor per surface crossed (a closed glass object: transmit^2), along the
 * straight ray (no refraction of shadow rays); 0 at the first opaque hit.
 * Scenes without transmissive materials ask only for any hit. */
static double cb_visibility(void *user, const geom_ray *r)
{
    ray_user *u = user;
    int found = 0;
    if (!u->transmissive) {
        if (geom_ray_scene_any(u->rs, r, &found) != GEOM_OK)
            return 1;
        return found ? 0 : 1;
    }
    geom_ray q = *r;
    double vis = 1;
    for (int crossings = 0; crossings < 64; crossings++) {
        geom_ray_hit h;
        if (geom_ray_scene_closest(u->rs, &q, &h, &found) != GEOM_OK || !found)
            return vis;
        uint32_t obj = u->root_object ? u->root_object[h.object] : h.object;
        double tr = obj < u->n_objects && u->materials ? u->materials[u->object_material[obj]].transmit : 0;
        if (!(tr > 0))
            return 0;
        vis *= tr > 1 ? 1 : tr;
        if (vis < 1e-6)
            return 0;
        /* continue past the surface: the rest of the segment from a new origin */
        geom_vec3 end = isfinite(q.tmax) ? geom__v3add(q.origin, geom__v3scale(q.dir, q.tmax))
                                         : geom__v3(0, 0, 0);
        q.origin = geom_ray_offset_origin(&h, q.dir);
        q.tmin = 0;
        if (isfinite(r->tmax)) {
            geom_vec3 rest = geom__v3sub(end, q.origin);
            q.tmax = geom__v3dot(rest, q.dir) / geom__v3dot(q.dir, q.dir);
            if (!(q.tmax > 0))
                return vis;
        }
    }
    return vis;
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
    u.materials = materials;
    for (size_t i = 0; i < n_objects; i++)
        u.transmissive |= materials[object_material[i]].transmit > 0;
    geom__tracer tr = {&u, cb_closest, cb_visibility, cb_spawn};
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
        if (s->volume) {
            geom_ray_volume_options vo = {s->inside};
            st = geom_ray_scene_add_volume_opt(rs, s->volume, s->iso, &vo, &id);
        } else {
            st = GEOM_ERR_INVALID_ARG;
        }
        break;
    case GEOM_SHAPE_SURFACE:
        if (!s->surfaces || !s->n_surfaces)
            return GEOM_ERR_INVALID_ARG;
        if (s->n_surfaces > 1 && !top)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
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
        uint32_t *mem = geom__alloc(NULL, (s->n_members + 1) * sizeof *mem);
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
        geom__free(NULL, mem, (s->n_members + 1) * sizeof *mem);
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
        geom__diag_set(diag, st, NULL, 0, 0, "object %s: %s", s->name ? s->name : "(unnamed)",
                      geom_status_str(st));
    }
    return st;
}

geom_status geom_scene_shape_to_ray(geom_ray_scene *rs, const geom_shape *s, uint32_t *ids,
                                    size_t *n_ids, geom_diag *diag)
{
    if (!rs || !s || !ids || !n_ids)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_scene_shape_to_ray: invalid argument");
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

/* The tessellation request of object sh for the picture: the chordal
 * tolerance that keeps its projected error below pe pixels (or opt's fixed
 * one), in its own frame, with the attributes its material uses; unbounded
 * shapes cut to ext (world). *tol_world receives the world tolerance. */
static geom_tess_request tess_request(const geom_camera *cam, const geom_render_options *opt,
                                      const geom_shape *sh, geom_aabb box, geom_aabb ext,
                                      unsigned needs, double *tol_world)
{
    double pe = opt->pixel_error > 0 ? opt->pixel_error : 0.5;
    geom_aabb wb = bounded(box) ? box : ext;
    double tol = opt->tolerance > 0 ? opt->tolerance : geom_scene_pixel_tolerance(cam, wb, pe, NULL);
    if (!(tol > 0))
        tol = 1e-3 * geom_vec3_length(geom_vec3_sub(wb.max, wb.min)) + 1e-12;
    geom_tess_request rq;
    memset(&rq, 0, sizeof rq);
    rq.tol = tol / max_scale(sh->transform);
    rq.attributes = needs & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT);
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
    *tol_world = tol;
    return rq;
}

/* Tessellate (and displace) one object for either path, filling its report. */
static geom_status tessellate_object(const geom_camera *cam, const geom_render_options *opt,
                                     const geom_shape *sh, const geom_material *mt,
                                     geom_aabb box, geom_aabb ext, unsigned needs,
                                     geom_mesh *out, geom_render_object_report *orep,
                                     geom_diag *diag)
{
    double tol;
    geom_tess_request rq = tess_request(cam, opt, sh, box, ext, needs, &tol);
    geom_status st = geom_scene_tessellate(sh, &rq, out, &orep->tess, diag);
    if (st != GEOM_OK)
        return st;
    if (mt->displace && orep->tess.triangles) {
        st = geom_scene_displace(out, mt->displace, mt->displace_scale);
        if (st != GEOM_OK)
            return st;
        orep->displaced = 1;
    }
    orep->tessellated = 1;
    orep->tolerance = tol;
    orep->tess.error.max_error *= max_scale(sh->transform); /* world units */
    orep->tess.error.mean_error *= max_scale(sh->transform);
    return GEOM_OK;
}

/* The box around everything bounded, the eye and the point lights, 4 times
 * its size: where unbounded shapes are cut when tessellated. */
static geom_aabb cut_extent(geom_aabb all)
{
    geom_aabb ext = all;
    geom_vec3 c = geom_vec3_scale(geom_vec3_add(ext.min, ext.max), 0.5);
    geom_vec3 h = geom_vec3_scale(geom_vec3_sub(ext.max, ext.min), 2.0);
    double m = fmax(h.x, fmax(h.y, h.z)) + 1e-9;
    ext.min = geom_vec3_sub(c, geom_vec3_make(m, m, m));
    ext.max = geom_vec3_add(c, geom_vec3_make(m, m, m));
    return ext;
}

static int has_polygons(const geom_mesh *m)
{
    for (size_t f = 0; f < geom_mesh_n_faces(m); f++)
        if (!geom_mesh_face_is_deleted(m, (uint32_t)f) && geom_mesh_face_valence(m, (uint32_t)f) > 3)
            return 1;
    return 0;
}

/* Corner-attribute table of object i from ray node `node`. */
static geom_status attr_setup(const geom_ray_scene *rs, uint32_t node, const geom_shape *sh,
                              obj_attr *A)
{
    geom__ray_node_info ni;
    memset(A, 0, sizeof *A);
    if (geom__ray_scene_node_info(rs, node, &ni) != GEOM_OK || !ni.tri || (!ni.cuv && !ni.cnrm))
        return GEOM_OK;
    A->pos = ni.pos;
    A->tri = ni.tri;
    A->nt = ni.nt;
    A->cuv = ni.cuv;
    A->cnrm = ni.cnrm;
    if (ni.face) {
        size_t nf = 0;
        for (size_t k = 0; k < ni.nt; k++)
            if (ni.face[k] + (size_t)1 > nf)
                nf = ni.face[k] + (size_t)1;
        A->face_tri = geom__alloc(NULL, (nf ? nf : 1) * sizeof *A->face_tri);
        if (!A->face_tri)
            return GEOM_ERR_NOMEM;
        A->nfaces = nf;
        for (size_t f = 0; f < nf; f++)
            A->face_tri[f] = UINT32_MAX;
        for (size_t k = 0; k < ni.nt; k++)
            if (A->face_tri[ni.face[k]] == UINT32_MAX)
                A->face_tri[ni.face[k]] = (uint32_t)k;
    }
    if (sh->transform) {
        geom_mat4 inv;
        A->has_xf = 1;
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++)
                A->m3[3 * c + r] = sh->transform->m[4 * c + r];
        if (geom_mat4_inverse(*sh->transform, &inv) != GEOM_OK)
            return GEOM_ERR_DEGENERATE;
        /* inverse transpose: element (r, c) = inv(c, r) */
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++)
                A->nm3[3 * c + r] = inv.m[4 * r + c];
    }
    return GEOM_OK;
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
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_scene_render: invalid argument");
    for (size_t i = 0; i < n_objects; i++)
        if (!objects[i].shape || objects[i].material >= n_materials)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "object %zu: no shape or material index out of range", i);
    geom_render_options opt;
    memset(&opt, 0, sizeof opt);
    if (opt_in)
        opt = *opt_in;
    geom_camera cam = geom_scene_camera_resolved(cam_in);
    geom_ray r0;
    geom_status st = geom_scene_camera_ray(&cam, 0.5, 0.5, &r0);
    if (st != GEOM_OK)
        return st;
    double t0 = now();
    size_t n = n_objects ? n_objects : 1;
    geom_render_object_report *orep = geom__alloc(NULL, n * sizeof *orep);
    geom_aabb *box = geom__alloc(NULL, n * sizeof *box);
    unsigned *needs = geom__alloc(NULL, n * sizeof *needs);
    uint32_t *omat = geom__alloc(NULL, n * sizeof *omat);
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
            geom_scene_camera_matrices(&cam, near, far, &view, &proj);
        }
        vp = geom_mat4_mul(proj, view);
    }
    int refl = 0, refr = 0, seen_unbounded = 0;
    for (size_t i = 0; i < n_objects; i++) {
        orep[i].visible = bounded(box[i]) ? geom__scene_box_frustum(box[i], vp) != 0 : 1;
        needs[i] = geom_scene_material_needs(&materials[objects[i].material]);
        omat[i] = objects[i].material;
        if (orep[i].visible) {
            if (bounded(box[i]))
                seen = geom_aabb_union(seen, box[i]);
            else
                seen_unbounded = 1;
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
        if (opt.no_shadows || (geom_aabb_is_empty(seen) && !seen_unbounded))
            continue;
        if (seen_unbounded) {
            /* a seen unbounded object (a ground plane) can be shadowed by
             * anything lit by a point or directional light */
            for (size_t l = 0; l < n_lights; l++)
                if (lights[l].kind != GEOM_LIGHT_AMBIENT)
                    orep[i].needed = 1;
            continue;
        }
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
        size_t nroots = 0, cap = 0, cap_obj = 0;
        /* meshes made for the ray path: subdivision surfaces refined to the
         * pixel error, displaced surfaces, polygon meshes triangulated for
         * their corner attributes */
        geom_mesh **made = geom__alloc(NULL, n * sizeof *made);
        geom_shape *mshape = geom__alloc(NULL, n * sizeof *mshape);
        obj_attr *attr = geom__alloc(NULL, n * sizeof *attr);
        uint32_t *first_root = geom__alloc(NULL, n * sizeof *first_root);
        if (!rs || !made || !mshape || !attr || !first_root) {
            geom_ray_scene_destroy(rs);
            geom__free(NULL, made, n * sizeof *made);
            geom__free(NULL, mshape, n * sizeof *mshape);
            geom__free(NULL, attr, n * sizeof *attr);
            geom__free(NULL, first_root, n * sizeof *first_root);
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        memset(made, 0, n * sizeof *made);
        memset(attr, 0, n * sizeof *attr);
        geom_aabb ext = cut_extent(all);
        for (size_t i = 0; i < n_objects && st == GEOM_OK; i++) {
            first_root[i] = UINT32_MAX;
            if (!orep[i].needed)
                continue;
            const geom_shape *sh = objects[i].shape;
            const geom_material *mt = &materials[objects[i].material];
            int tess = sh->kind == GEOM_SHAPE_SUBDIV || mt->displace != NULL;
            int tri = sh->kind == GEOM_SHAPE_MESH && sh->mesh &&
                      (needs[i] & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT)) && has_polygons(sh->mesh);
            if (tess || tri) {
                if (tess) {
                    made[i] = geom_mesh_create(NULL);
                    st = made[i] ? tessellate_object(&cam, &opt, sh, mt, box[i], ext,
                                                     needs[i] | GEOM_NEEDS_NORMAL, made[i], &orep[i],
                                                     diag)
                                 : GEOM_ERR_NOMEM;
                } else {
                    st = geom_mesh_clone(sh->mesh, &made[i]);
                }
                if (st == GEOM_OK && has_polygons(made[i]))
                    st = geom_mesh_triangulate(made[i], NULL);
                if (st != GEOM_OK)
                    break;
                mshape[i] = *sh;
                memset(&mshape[i], 0, sizeof mshape[i]);
                mshape[i].kind = GEOM_SHAPE_MESH;
                mshape[i].name = sh->name;
                mshape[i].mesh = made[i];
                mshape[i].transform = sh->transform;
                sh = &mshape[i];
            }
            size_t k = sh->kind == GEOM_SHAPE_SURFACE && sh->n_surfaces > 1 ? sh->n_surfaces : 1;
            {
                void *a = roots, *b = root_obj;
                st = geom__grow(NULL, &a, &cap, nroots + k, sizeof *roots);
                roots = a;
                if (st == GEOM_OK)
                    st = geom__grow(NULL, &b, &cap_obj, nroots + k, sizeof *root_obj);
                root_obj = b;
                if (st != GEOM_OK)
                    break;
            }
            size_t got = 0;
            st = geom_scene_shape_to_ray(rs, sh, roots + nroots, &got, diag);
            for (size_t j = 0; j < got; j++)
                root_obj[nroots + j] = (uint32_t)i;
            if (got)
                first_root[i] = roots[nroots];
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
        for (size_t i = 0; i < n_objects && st == GEOM_OK; i++) {
            const geom_shape *sh = made[i] ? &mshape[i] : objects[i].shape;
            if (first_root[i] != UINT32_MAX && sh->kind == GEOM_SHAPE_MESH) {
                st = attr_setup(rs, first_root[i], sh, &attr[i]);
            }
        }
        rep.seconds_build = now() - t0;
        if (st == GEOM_OK) {
            ray_user u;
            memset(&u, 0, sizeof u);
            u.rs = rs;
            u.root_object = root_obj;
            u.object_material = omat;
            u.n_objects = n_objects;
            u.needs = needs;
            u.attr = attr;
            u.materials = materials;
            for (size_t i = 0; i < n_objects; i++)
                u.transmissive |= orep[i].needed && materials[objects[i].material].transmit > 0;
            geom__tracer tr = {&u, cb_closest, cb_visibility, cb_spawn};
            geom_trace_options to;
            memset(&to, 0, sizeof to);
            to.aov = opt.aov;
            to.background = opt.background;
            to.max_depth = opt.max_depth;
            to.min_weight = opt.min_weight;
            to.no_shadows = opt.no_shadows;
            to.progress = opt.progress;
            to.progress_user = opt.progress_user;
            double t1 = now();
            st = geom__scene_trace(&tr, &cam, lights, n_lights, materials, n_materials, &to, out,
                                   &rep.trace);
            rep.seconds_render = now() - t1;
        }
        for (size_t i = 0; i < n_objects; i++) {
            geom_mesh_destroy(made[i]);
            if (attr[i].face_tri)
                geom__free(NULL, attr[i].face_tri, (attr[i].nfaces ? attr[i].nfaces : 1) * sizeof(uint32_t));
        }
        geom__free(NULL, made, n * sizeof *made);
        geom__free(NULL, mshape, n * sizeof *mshape);
        geom__free(NULL, attr, n * sizeof *attr);
        geom__free(NULL, first_root, n * sizeof *first_root);
        geom__free(NULL, roots, cap * sizeof *roots);
        geom__free(NULL, root_obj, cap_obj * sizeof *root_obj);
        geom_ray_scene_destroy(rs);
    } else {
        /* raster: tessellate what is needed to the pixel error */
        geom_mesh **meshes = geom__alloc(NULL, n * sizeof *meshes);
        geom_scene_draw *draws = geom__alloc(NULL, n * sizeof *draws);
        size_t nd = 0;
        if (!meshes || !draws) {
            geom__free(NULL, meshes, n * sizeof *meshes);
            geom__free(NULL, draws, n * sizeof *draws);
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        memset(meshes, 0, n * sizeof *meshes);
        geom_aabb ext = cut_extent(all);
        for (size_t i = 0; i < n_objects && st == GEOM_OK; i++) {
            if (!orep[i].needed)
                continue;
            const geom_shape *sh = objects[i].shape;
            meshes[i] = geom_mesh_create(NULL);
            if (!meshes[i]) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            st = tessellate_object(&cam, &opt, sh, &materials[objects[i].material], box[i], ext,
                                   needs[i], meshes[i], &orep[i], diag);
            if (st != GEOM_OK)
                break;
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
        geom__free(NULL, meshes, n * sizeof *meshes);
        geom__free(NULL, draws, n * sizeof *draws);
    }
done:
    if (st == GEOM_OK && orep_out)
        memcpy(orep_out, orep, n_objects * sizeof *orep);
    geom__free(NULL, orep, n * sizeof *orep);
    geom__free(NULL, box, n * sizeof *box);
    geom__free(NULL, needs, n * sizeof *needs);
    geom__free(NULL, omat, n * sizeof *omat);
    if (report)
        *report = rep;
    return st;
}
