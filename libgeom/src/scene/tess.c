/* Tessellation of scene shapes to the tolerance a picture needs: exact
 * NURBS through the surface module, planar shapes exactly, subdivision
 * toward the limit, everything with an implicit form by marching cubes
 * (iso module), CSG through the min/max of its children's implicit forms. */
#include "geom/scene.h"
#include "geom/iso.h"
#include "geom/subdiv.h"

#include <math.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "mesh/mesh_internal.h"
#include "scene/scene_internal.h"

static double now(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *nm(const geom_shape *s)
{
    return s->name ? s->name : "(unnamed)";
}

static unsigned surf_attrs(unsigned a)
{
    unsigned f = 0;
    if (a & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_TANGENT))
        f |= GEOM_SURFACE_ATTR_NORMAL;
    if (a & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT))
        f |= GEOM_SURFACE_ATTR_UV;
    if (a & GEOM_NEEDS_TANGENT)
        f |= GEOM_SURFACE_ATTR_TANGENT;
    return f;
}

/* The exact NURBS of a sphere or a torus (arrays in *b). */
typedef struct quadric_nurbs {
    double ku[12], kv[12], pts[243], w[81];
} quadric_nurbs;

static geom_status sphere_torus_nurbs(const geom_shape *s, quadric_nurbs *b, geom_nurbs_surface *ns)
{
    if (s->kind == GEOM_SHAPE_TORUS)
        return geom_surface_torus(NULL, s->major, s->minor, b->ku, b->kv, b->pts, b->w, ns);
    geom_surface_frame fr;
    memset(&fr, 0, sizeof fr);
    memcpy(fr.center, s->p, sizeof fr.center);
    fr.zaxis[2] = 1;
    fr.xaxis[0] = 1;
    return geom_surface_sphere(&fr, s->radius, b->ku, b->kv, b->pts, b->w, ns);
}

static geom_status tess_nurbs(const geom_nurbs_surface *s, size_t n, const geom_tess_request *rq,
                              geom_mesh *out, geom_tess_info *info, geom_diag *diag)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = rq->tol;
    o.attributes = surf_attrs(rq->attributes);
    o.uv_normalized = 1;
    info->method = "nurbs";
    return geom_surface_tessellate(s, n, &o, out, &info->error, NULL, diag);
}

/* Build a mesh of quads/polygons with per-corner normal and uv. */
static geom_status build_polys(geom_mesh *out, size_t nv, const double *xyz, size_t nf,
                               const uint32_t *sizes, const uint32_t *idx, const double *cn,
                               const double *cuv, unsigned attrs, geom_diag *diag)
{
    geom_mesh_build_options bo;
    memset(&bo, 0, sizeof bo);
    bo.keep_orientation = 1;
    geom_status st = geom_mesh_build(out, nv, xyz, nf, sizes, idx, &bo, NULL, diag);
    if (st != GEOM_OK)
        return st;
    size_t nc = 0;
    for (size_t f = 0; f < nf; f++)
        nc += sizes[f];
    uint32_t ids[2];
    const char *names[2] = {"normal", "uv"};
    const double *src[2] = {cn, cuv};
    size_t comp[2] = {3, 2};
    int want[2] = {(attrs & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_TANGENT)) != 0,
                   (attrs & (GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT)) != 0};
    for (int c = 0; c < 2; c++) {
        if (!want[c] || !src[c])
            continue;
        if ((st = geom_mesh_channel_add(out, names[c], GEOM_MESH_DOMAIN_CORNER, comp[c], &ids[c])) ||
            (st = geom_mesh_corner_pool_resize(out, ids[c], nc)))
            return st;
        memcpy(geom_mesh_channel_data(out, ids[c]), src[c], nc * comp[c] * sizeof(double));
        uint32_t *ci = geom_mesh_corner_indices(out, ids[c]);
        /* corner k of face f (in input order) is the halfedge pointing to
         * idx[k]: walk each face from its first halfedge */
        size_t k = 0;
        for (uint32_t f = 0; f < nf; f++) {
            uint32_t h0 = geom_mesh_face_he(out, f), h = h0;
            /* find the halfedge whose vertex is the face's first input vertex */
            for (size_t i = 0; i < sizes[f]; i++) {
                if (geom_mesh_he_vertex(out, h) == idx[k])
                    break;
                h = geom_mesh_he_next(out, h);
            }
            for (size_t i = 0; i < sizes[f]; i++) {
                ci[h] = (uint32_t)(k + i);
                h = geom_mesh_he_next(out, h);
            }
            k += sizes[f];
        }
    }
    if (attrs & GEOM_NEEDS_TANGENT && cuv)
        st = geom_mesh_tangents(out, NULL);
    return st;
}

static geom_status tess_box(const double mn[3], const double mx[3], unsigned attrs,
                            geom_mesh *out, geom_diag *diag)
{
    double xyz[24 * 3], cn[24 * 3], cuv[24 * 2];
    uint32_t sizes[6], idx[24];
    /* faces -x, +x, -y, +y, -z, +z, counter-clockwise from outside */
    for (int f = 0; f < 6; f++) {
        int ax = f / 2, hi = f % 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
        static const int su[4] = {0, 1, 1, 0}, sv[4] = {0, 0, 1, 1};
        sizes[f] = 4;
        for (int c = 0; c < 4; c++) {
            int cc = hi ? c : (4 - c) % 4; /* reverse winding on the low face */
            int k = 4 * f + c;
            double p[3];
            p[ax] = hi ? mx[ax] : mn[ax];
            p[a1] = su[cc] ? mx[a1] : mn[a1];
            p[a2] = sv[cc] ? mx[a2] : mn[a2];
            memcpy(xyz + 3 * k, p, sizeof p);
            cn[3 * k] = cn[3 * k + 1] = cn[3 * k + 2] = 0;
            cn[3 * k + ax] = hi ? 1 : -1;
            cuv[2 * k] = su[cc];
            cuv[2 * k + 1] = sv[cc];
            idx[k] = (uint32_t)k;
        }
    }
    return build_polys(out, 24, xyz, 6, sizes, idx, cn, cuv, attrs, diag);
}

static void frame_of(const double n[3], double t[3], double b[3], double nn[3])
{
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    nn[0] = n[0] / l;
    nn[1] = n[1] / l;
    nn[2] = n[2] / l;
    double a[3] = {1, 0, 0};
    if (fabs(nn[0]) > 0.9) {
        a[0] = 0;
        a[1] = 1;
    }
    /* t = normalize(a - (a.n) n), b = n x t */
    double d = a[0] * nn[0] + a[1] * nn[1] + a[2] * nn[2];
    for (int i = 0; i < 3; i++)
        t[i] = a[i] - d * nn[i];
    l = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int i = 0; i < 3; i++)
        t[i] /= l;
    b[0] = nn[1] * t[2] - nn[2] * t[1];
    b[1] = nn[2] * t[0] - nn[0] * t[2];
    b[2] = nn[0] * t[1] - nn[1] * t[0];
}

/* Planar polygon (disk: n-gon from the tolerance; plane: square over the
 * extent). */
static geom_status tess_planar(const double *pts, size_t n, const double nrm[3], unsigned attrs,
                               geom_mesh *out, geom_diag *diag)
{
    size_t bytes = n * 3 * sizeof(double);
    double *cn = geom__alloc(NULL, bytes), *cuv = geom__alloc(NULL, n * 2 * sizeof(double));
    uint32_t *idx = geom__alloc(NULL, n * sizeof(uint32_t));
    geom_status st = GEOM_ERR_NOMEM;
    if (cn && cuv && idx) {
        double t[3], b[3], nn[3];
        frame_of(nrm, t, b, nn);
        for (size_t i = 0; i < n; i++) {
            memcpy(cn + 3 * i, nn, sizeof nn);
            const double *p = pts + 3 * i;
            cuv[2 * i] = p[0] * t[0] + p[1] * t[1] + p[2] * t[2];
            cuv[2 * i + 1] = p[0] * b[0] + p[1] * b[1] + p[2] * b[2];
            idx[i] = (uint32_t)i;
        }
        uint32_t sz = (uint32_t)n;
        st = build_polys(out, n, pts, 1, &sz, idx, cn, cuv, attrs, diag);
        if (st == GEOM_OK)
            st = geom_mesh_triangulate(out, NULL);
    }
    geom__free(NULL, cn, bytes);
    geom__free(NULL, cuv, n * 2 * sizeof(double));
    geom__free(NULL, idx, n * sizeof(uint32_t));
    return st;
}

/* ------------------------------------------------------- implicit forms */

static geom_vec3 to_local(const geom_shape *s, geom_vec3 p, int *ok)
{
    if (!s->transform)
        return p;
    geom_mat4 inv;
    if (geom_mat4_inverse(*s->transform, &inv) != GEOM_OK) {
        *ok = 0;
        return p;
    }
    geom_vec3 q;
    geom_mat4_transform_point(inv, p, &q);
    return q;
}

static double quadric_f(const double *q, geom_vec3 p)
{
    double x = p.x, y = p.y, z = p.z;
    return q[0] * x * x + q[1] * y * y + q[2] * z * z + 2 * q[3] * x * y + 2 * q[4] * y * z +
           2 * q[5] * x * z + 2 * q[6] * x + 2 * q[7] * y + 2 * q[8] * z + q[9];
}

static double box_f(const double mn[3], const double mx[3], geom_vec3 p)
{
    double a[3] = {p.x, p.y, p.z}, r = -INFINITY;
    for (int i = 0; i < 3; i++)
        r = fmax(r, fabs(a[i] - 0.5 * (mn[i] + mx[i])) - 0.5 * (mx[i] - mn[i]));
    return r;
}

/* Value of s's implicit form at p (parent frame), inside < 0. */
static double shape_f(const geom_shape *s, geom_vec3 p)
{
    int ok = 1;
    geom_vec3 q = to_local(s, p, &ok);
    if (!ok)
        return NAN;
    switch (s->kind) {
    case GEOM_SHAPE_SPHERE:
        return geom_vec3_length(geom_vec3_sub(q, geom_vec3_make(s->p[0], s->p[1], s->p[2]))) - s->radius;
    case GEOM_SHAPE_BOX:
        return box_f(s->min, s->max, q);
    case GEOM_SHAPE_TORUS: {
        double a = hypot(q.x, q.y) - s->major;
        return hypot(a, q.z) - s->minor;
    }
    case GEOM_SHAPE_PLANE:
        return (q.x - s->p[0]) * s->n[0] + (q.y - s->p[1]) * s->n[1] + (q.z - s->p[2]) * s->n[2];
    case GEOM_SHAPE_QUADRIC: {
        double f = quadric_f(s->q, q);
        if (s->clip && s->capped)
            f = fmax(f, box_f(s->clip, s->clip + 3, q));
        return f;
    }
    case GEOM_SHAPE_IMPLICIT: {
        double a[3] = {q.x, q.y, q.z};
        return geom_implicit_expr_eval(s->expr, a);
    }
    case GEOM_SHAPE_VOLUME: {
        double a[3] = {q.x, q.y, q.z};
        double f = geom_implicit_volume_eval(s->volume, a) - s->iso;
        return s->inside ? -f : f; /* negative inside either way */
    }
    case GEOM_SHAPE_GROUP: {
        double f = INFINITY;
        for (size_t i = 0; i < s->n_members; i++)
            f = fmin(f, shape_f(s->members[i], q));
        return f;
    }
    case GEOM_SHAPE_CSG: {
        double fa = shape_f(s->a, q), fb = shape_f(s->b, q);
        if (s->csg_op == 1)
            return fmin(fa, fb);
        if (s->csg_op == 2)
            return fmax(fa, fb);
        return fmax(fa, -fb);
    }
    default:
        return NAN;
    }
}

/* Check that s has an implicit form; the first offending shape otherwise. */
static const geom_shape *no_implicit(const geom_shape *s)
{
    switch (s->kind) {
    case GEOM_SHAPE_SPHERE: case GEOM_SHAPE_BOX: case GEOM_SHAPE_TORUS: case GEOM_SHAPE_PLANE:
    case GEOM_SHAPE_QUADRIC:
        return NULL;
    case GEOM_SHAPE_IMPLICIT:
        return s->expr ? NULL : s;
    case GEOM_SHAPE_VOLUME:
        return s->volume ? NULL : s;
    case GEOM_SHAPE_GROUP:
        for (size_t i = 0; i < s->n_members; i++) {
            const geom_shape *r = no_implicit(s->members[i]);
            if (r)
                return r;
        }
        return NULL;
    case GEOM_SHAPE_CSG: {
        if (!s->a || !s->b || s->csg_op < 1 || s->csg_op > 3)
            return s;
        const geom_shape *r = no_implicit(s->a);
        return r ? r : no_implicit(s->b);
    }
    default:
        return s;
    }
}

static geom_aabb box_xform(geom_aabb b, const geom_mat4 *M)
{
    if (!M || geom_aabb_is_empty(b))
        return b;
    geom_aabb w = geom_aabb_empty();
    for (int c = 0; c < 8; c++) {
        geom_vec3 p = geom_vec3_make(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y,
                                     c & 4 ? b.max.z : b.min.z), q;
        if (geom_mat4_transform_point(*M, p, &q) == GEOM_OK)
            w = geom_aabb_extend(w, q);
    }
    return w;
}

static geom_aabb box_inter(geom_aabb a, geom_aabb b)
{
    geom_aabb r;
    r.min = geom_vec3_make(fmax(a.min.x, b.min.x), fmax(a.min.y, b.min.y), fmax(a.min.z, b.min.z));
    r.max = geom_vec3_make(fmin(a.max.x, b.max.x), fmin(a.max.y, b.max.y), fmin(a.max.z, b.max.z));
    return r;
}

/* Bounds of s in its parent frame; `extent` (parent frame) for unbounded. */
static geom_aabb shape_bounds(const geom_shape *s, geom_aabb extent)
{
    geom_aabb b = geom_aabb_empty(), inf;
    inf.min = geom_vec3_make(-INFINITY, -INFINITY, -INFINITY);
    inf.max = geom_vec3_make(INFINITY, INFINITY, INFINITY);
    switch (s->kind) {
    case GEOM_SHAPE_SPHERE:
        b.min = geom_vec3_make(s->p[0] - s->radius, s->p[1] - s->radius, s->p[2] - s->radius);
        b.max = geom_vec3_make(s->p[0] + s->radius, s->p[1] + s->radius, s->p[2] + s->radius);
        break;
    case GEOM_SHAPE_BOX:
        b.min = geom_vec3_make(s->min[0], s->min[1], s->min[2]);
        b.max = geom_vec3_make(s->max[0], s->max[1], s->max[2]);
        break;
    case GEOM_SHAPE_TORUS: {
        double R = s->major + s->minor;
        b.min = geom_vec3_make(-R, -R, -s->minor);
        b.max = geom_vec3_make(R, R, s->minor);
        break;
    }
    case GEOM_SHAPE_IMPLICIT:
        b.min = geom_vec3_make(s->bounds[0], s->bounds[1], s->bounds[2]);
        b.max = geom_vec3_make(s->bounds[3], s->bounds[4], s->bounds[5]);
        break;
    case GEOM_SHAPE_VOLUME:
        b = geom_implicit_volume_bounds(s->volume);
        break;
    case GEOM_SHAPE_QUADRIC:
        if (s->clip) {
            b.min = geom_vec3_make(s->clip[0], s->clip[1], s->clip[2]);
            b.max = geom_vec3_make(s->clip[3], s->clip[4], s->clip[5]);
        } else
            b = inf;
        break;
    case GEOM_SHAPE_CSG: {
        geom_aabb ba = shape_bounds(s->a, inf), bb = shape_bounds(s->b, inf);
        b = s->csg_op == 1 ? geom_aabb_union(ba, bb) : s->csg_op == 2 ? box_inter(ba, bb) : ba;
        break;
    }
    case GEOM_SHAPE_GROUP:
        for (size_t i = 0; i < s->n_members; i++)
            b = geom_aabb_union(b, shape_bounds(s->members[i], inf));
        break;
    case GEOM_SHAPE_MESH:
    case GEOM_SHAPE_SUBDIV:
        if (s->mesh)
            b = geom_mesh_bbox(s->mesh); /* the limit lies in the control hull */
        break;
    case GEOM_SHAPE_POLYGON:
        for (size_t i = 0; s->vertices && i < s->n_vertices; i++)
            b = geom_aabb_extend(b, geom_vec3_make(s->vertices[3 * i], s->vertices[3 * i + 1],
                                                   s->vertices[3 * i + 2]));
        break;
    case GEOM_SHAPE_DISK:
        b.min = geom_vec3_make(s->p[0] - s->radius, s->p[1] - s->radius, s->p[2] - s->radius);
        b.max = geom_vec3_make(s->p[0] + s->radius, s->p[1] + s->radius, s->p[2] + s->radius);
        break;
    case GEOM_SHAPE_SURFACE: /* convex hull property (positive weights) */
        for (size_t k = 0; s->surfaces && k < s->n_surfaces; k++) {
            const geom_nurbs_surface *ns = &s->surfaces[k];
            for (size_t i = 0; i < ns->nu * ns->nv; i++)
                b = geom_aabb_extend(b, geom_vec3_make(ns->points[3 * i], ns->points[3 * i + 1],
                                                       ns->points[3 * i + 2]));
        }
        break;
    default:
        b = inf;
    }
    if (geom_aabb_is_empty(b))
        return b;
    int unbounded = !isfinite(b.min.x) || !isfinite(b.min.y) || !isfinite(b.min.z) ||
                    !isfinite(b.max.x) || !isfinite(b.max.y) || !isfinite(b.max.z);
    if (!unbounded)
        b = box_xform(b, s->transform);
    else if (!geom_aabb_is_empty(extent) &&
             geom_vec3_length(geom_vec3_sub(extent.max, extent.min)) > 0)
        b = box_inter(b, extent); /* extent is in the parent frame */
    return b;
}

/* The implicit form with each transform inverted once (marching cubes
 * evaluates it millions of times). */
typedef struct inode {
    const geom_shape *s;
    int has_inv;
    geom_mat4 inv;
    struct inode *a, *b;
    struct inode **m;
    size_t nm;
} inode;

static void inode_free(inode *n)
{
    if (!n)
        return;
    inode_free(n->a);
    inode_free(n->b);
    for (size_t i = 0; i < n->nm; i++)
        inode_free(n->m[i]);
    geom__free(NULL, n->m, n->nm * sizeof *n->m);
    geom__free(NULL, n, sizeof *n);
}

static inode *inode_make(const geom_shape *s, int top)
{
    inode *n = geom__alloc(NULL, sizeof *n);
    if (!n)
        return NULL;
    memset(n, 0, sizeof *n);
    n->s = s;
    if (s->transform && !top) {
        if (geom_mat4_inverse(*s->transform, &n->inv) != GEOM_OK) {
            geom__free(NULL, n, sizeof *n);
            return NULL;
        }
        n->has_inv = 1;
    }
    int ok = 1;
    if (s->kind == GEOM_SHAPE_CSG) {
        n->a = inode_make(s->a, 0);
        n->b = inode_make(s->b, 0);
        ok = n->a && n->b;
    } else if (s->kind == GEOM_SHAPE_GROUP && s->n_members) {
        n->m = geom__alloc(NULL, s->n_members * sizeof *n->m);
        ok = n->m != NULL;
        if (ok) {
            memset(n->m, 0, s->n_members * sizeof *n->m);
            n->nm = s->n_members;
            for (size_t i = 0; i < s->n_members && ok; i++)
                ok = (n->m[i] = inode_make(s->members[i], 0)) != NULL;
        }
    }
    if (!ok) {
        inode_free(n);
        return NULL;
    }
    return n;
}

static double inode_f(const inode *n, geom_vec3 p)
{
    if (n->has_inv)
        geom_mat4_transform_point(n->inv, p, &p);
    const geom_shape *s = n->s;
    if (s->kind == GEOM_SHAPE_CSG) {
        double fa = inode_f(n->a, p), fb = inode_f(n->b, p);
        return s->csg_op == 1 ? fmin(fa, fb) : s->csg_op == 2 ? fmax(fa, fb) : fmax(fa, -fb);
    }
    if (s->kind == GEOM_SHAPE_GROUP) {
        double f = INFINITY;
        for (size_t i = 0; i < n->nm; i++)
            f = fmin(f, inode_f(n->m[i], p));
        return f;
    }
    geom_shape leaf = *s;
    leaf.transform = NULL;
    return shape_f(&leaf, p);
}

static double iso_value_cb(void *user, const double p[3])
{
    return inode_f((const inode *)user, geom_vec3_make(p[0], p[1], p[2]));
}

/* The marching-cubes box of an implicit shape's bounds b (padded by a few
 * percent so a surface touching the box is closed by caps) into bounds,
 * and the first pass's cell size for tolerance tol. */
static double iso_grid(geom_aabb b, double tol, double bounds[6])
{
    geom_vec3 d = geom_vec3_sub(b.max, b.min);
    double diag_len = geom_vec3_length(d);
    double pad = 0.02 * diag_len + 1e-12;
    double bx[6] = {b.min.x - pad, b.min.y - pad, b.min.z - pad,
                    b.max.x + pad, b.max.y + pad, b.max.z + pad};
    memcpy(bounds, bx, sizeof bx);
    return fmax(diag_len / 256, fmin(diag_len / 24, 8 * tol));
}

/* Cells per axis for cell size h: 2..256. */
static void iso_res(const double bounds[6], double h, size_t res[3])
{
    for (int i = 0; i < 3; i++) {
        double ext = bounds[3 + i] - bounds[i];
        double r = ceil(ext / h);
        res[i] = r < 2 ? 2 : (r > 256 ? 256 : (size_t)r);
    }
}

/* The marching-cubes options of every pass (normals when asked). */
static void iso_options(geom_iso_options *o, int normals)
{
    memset(o, 0, sizeof *o);
    o->refine = GEOM_IMPLICIT_REFINE_AUTO; /* the field is exact: refined */
    o->normals = normals;
    o->caps = 1;
    o->error = GEOM_ISO_ERROR_ALWAYS;
    o->threads = 1;
}

/* A pass's achieved error: the larger of the sampled and vertex errors. */
static geom_error_report iso_error(const geom_iso_surface *surf)
{
    geom_error_report e = surf->report.sample_error;
    if (surf->report.vertex_error.max_error > e.max_error)
        e.max_error = surf->report.vertex_error.max_error;
    return e;
}

/* Whether pass `pass` (0-based) on a grid of res cells is the last one
 * whatever its error: sharp CSG edges converge slowly in this measure, so
 * at most three passes and 256 cells per axis. */
static int iso_last_pass(const size_t res[3], int pass)
{
    return res[0] >= 256 || res[1] >= 256 || res[2] >= 256 || pass == 2;
}

static geom_status tess_iso(const geom_shape *s, const geom_tess_request *rq, geom_mesh *out,
                            geom_tess_info *info, geom_diag *diag)
{
    /* the result is in s's own frame: evaluate without s's own transform */
    geom_shape local = *s;
    local.transform = NULL;
    geom_aabb b = shape_bounds(&local, rq->extent);
    if (geom_aabb_is_empty(b) || !isfinite(b.min.x) || !isfinite(b.max.x) ||
        !isfinite(b.min.y) || !isfinite(b.max.y) || !isfinite(b.min.z) || !isfinite(b.max.z))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "object %s: unbounded and no extent to cut it to", nm(s));
    double bounds[6];
    double h = iso_grid(b, rq->tol, bounds);
    geom_iso_field f;
    memset(&f, 0, sizeof f);
    inode *root = inode_make(&local, 1);
    if (!root)
        return GEOM_ERR_NOMEM;
    f.value = iso_value_cb;
    f.user = root;
    f.exact = 1;
    geom_iso_options o;
    iso_options(&o, (rq->attributes & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_TANGENT)) != 0);
    geom_iso_surface surf;
    geom_status st = GEOM_OK;
    info->method = "iso";
    for (int pass = 0; pass < 4; pass++) {
        size_t res[3];
        iso_res(bounds, h, res);
        memset(&surf, 0, sizeof surf);
        st = geom_iso_extract(&f, bounds, res, &o, &surf, diag);
        if (st != GEOM_OK) {
            inode_free(root);
            return st;
        }
        info->error = iso_error(&surf);
        if (info->error.max_error <= rq->tol || iso_last_pass(res, pass))
            break;
        geom_iso_surface_free(&surf);
        h *= 0.5;
    }
    inode_free(root);
    st = geom_iso_surface_to_mesh(&surf, out, diag);
    geom_iso_surface_free(&surf);
    return st;
}

/* Grids of at most this many cells (161^3) are extracted by the estimate. */
#define ISO_TRIAL_CELLS ((size_t)1 << 22)

static double iso_cells(const size_t res[3])
{
    return (double)res[0] * (double)res[1] * (double)res[2];
}

/* One trial extraction for the estimate: its error and triangle count. */
static geom_status iso_trial(const geom_implicit_field *f, const double bounds[6], const size_t res[3],
                             double *err, double *tris)
{
    geom_iso_options o;
    iso_options(&o, 0);
    geom_iso_surface surf;
    memset(&surf, 0, sizeof surf);
    geom_status st = geom_iso_extract(f, bounds, res, &o, &surf, NULL);
    if (st == GEOM_OK) {
        *err = iso_error(&surf).max_error;
        *tris = (double)surf.n_triangles;
    }
    geom_iso_surface_free(&surf);
    return st;
}

/*
 * tess_iso's triangle count, estimated: tess_iso extracts at cell size h0,
 * h0/2, h0/4 until the error is within tol (iso_last_pass ends it sooner).
 * The passes whose grid has at most ISO_TRIAL_CELLS cells are extracted
 * here as tess_iso does them (without normals): when one is within tol or
 * the last, its count is the answer, exact. When the next pass is larger,
 * its error cannot be known without doing it: the last pass is taken (an
 * upper bound), its count the largest trial's (a pass tried, else a grid
 * of at most ISO_TRIAL_CELLS cells) scaled by the cells' ratio to the 2/3
 * (triangles grow with the surface's area, 1/h^2; caps included) plus 10 %.
 */
/* The cheap bound's trial grid: at most this many cells (32^3) and at most
 * a sixteenth of tess_iso's first pass (so it costs about 1/16 of the
 * tessellation), but at least ISO_CHEAP_MIN cells (8^3: below that
 * the count does not scale with the area). */
#define ISO_CHEAP_CELLS ((double)((size_t)1 << 15))
#define ISO_CHEAP_MIN ((double)((size_t)1 << 9))
/* The cheap bound's margin over the scaled count (measured: see scene.h). */
#define ISO_CHEAP_MARGIN 1.5

static geom_status iso_estimate(const geom_implicit_field *f, const double bounds[6], double h0,
                                double tol, int cheap, double *t)
{
    size_t res[3][3];
    int last = 0;
    for (int k = 0; k < 3; k++) {
        iso_res(bounds, ldexp(h0, -k), res[k]);
        last = k;
        if (iso_last_pass(res[k], k))
            break;
    }
    geom_status st = GEOM_OK;
    double e = 0, n = 0, cells = 0;
    if (cheap) {
        /* no pass of tess_iso's: the last one assumed, its count scaled from
         * a coarse grid's */
        double cap = fmin(ISO_CHEAP_CELLS, fmax(iso_cells(res[0]) / 16, ISO_CHEAP_MIN));
        size_t r[3];
        double h = h0;
        do {
            h *= 1.25;
            iso_res(bounds, h, r);
        } while (iso_cells(r) > cap);
        if ((st = iso_trial(f, bounds, r, &e, &n)) != GEOM_OK)
            return st;
        *t = ISO_CHEAP_MARGIN * fmax(n, 1) * pow(iso_cells(res[last]) / iso_cells(r), 2.0 / 3.0);
        return GEOM_OK;
    }
    for (int k = 0; k <= last && iso_cells(res[k]) <= (double)ISO_TRIAL_CELLS; k++) {
        if ((st = iso_trial(f, bounds, res[k], &e, &n)) != GEOM_OK)
            return st;
        if (e <= tol || k == last) {
            *t = n;
            return GEOM_OK;
        }
        cells = iso_cells(res[k]);
    }
    if (cells == 0) { /* no pass tried: a coarser grid that fits */
        size_t r[3];
        double h = h0;
        do {
            h *= 1.25;
            iso_res(bounds, h, r);
        } while (iso_cells(r) > (double)ISO_TRIAL_CELLS);
        if ((st = iso_trial(f, bounds, r, &e, &n)) != GEOM_OK)
            return st;
        cells = iso_cells(r);
    }
    *t = 1.1 * n * pow(iso_cells(res[last]) / cells, 2.0 / 3.0);
    return GEOM_OK;
}

/* Keep only the channels named in keep[n] (VERTEX, and CORNER when corner)
 * besides positions, and no groups, tags, mtllibs or polylines: the
 * attributes a tessellation hands on. */
static void keep_channels(geom_mesh *m, const char *const *keep, size_t n, int corner)
{
    for (uint32_t id = (uint32_t)geom_mesh_channel_count(m); id-- > 1;) {
        geom_mesh_domain d = geom_mesh_channel_domain(m, id);
        int kept = 0;
        for (size_t k = 0; k < n && !kept; k++)
            kept = strcmp(geom_mesh_channel_name(m, id), keep[k]) == 0 &&
                   (d == GEOM_MESH_DOMAIN_VERTEX || (corner && d == GEOM_MESH_DOMAIN_CORNER));
        if (!kept)
            geom_mesh_channel_remove(m, id);
    }
    geom__mesh_drop_meta(m);
}

static geom_status tess_subdiv(const geom_shape *s, const geom_tess_request *rq, geom_mesh *out,
                               geom_tess_info *info, geom_diag *diag)
{
    geom_subdiv_options o;
    memset(&o, 0, sizeof o);
    o.scheme = (geom_subdiv_scheme)s->scheme;
    info->method = "subdiv";
    int level = 1;
    geom_subdiv_report rep;
    for (; level < 7; level++) {
        geom_mesh *tmp = NULL;
        geom_status st = geom_subdiv_mesh(s->mesh, &o, level, 0, &tmp, &rep, diag);
        geom_mesh_destroy(tmp);
        if (st != GEOM_OK)
            return st;
        if (rep.max_limit_distance <= rq->tol)
            break;
    }
    info->error.max_error = rep.max_limit_distance;
    info->error.mean_error = rep.rms_limit_distance;
    info->error.method = GEOM_ERROR_ESTIMATE;
    geom_mesh *res = NULL;
    unsigned flags = GEOM_SUBDIV_LIMIT;
    if (rq->attributes & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_TANGENT))
        flags |= GEOM_SUBDIV_NORMALS;
    geom_status st = geom_subdiv_mesh(s->mesh, &o, level, flags, &res, NULL, diag);
    if (st != GEOM_OK)
        return st;
    /* the result becomes out, with its limit normals (VERTEX "normal") only */
    static const char *const keep[1] = {"normal"};
    st = geom__mesh_take(out, res);
    if (st == GEOM_OK)
        keep_channels(out, keep, 1, 0);
    return st;
}

/* Sides of the polygon standing for a disk at tolerance tol. */
static size_t disk_sides(const geom_shape *s, double tol)
{
    double c = 1 - tol / s->radius;
    size_t n = c <= -1 ? 8 : (size_t)ceil(GEOM_PI / acos(c > -1 ? c : -1));
    if (n < 8)
        n = 8;
    if (n > 65536)
        n = 65536;
    return n;
}

/* A group: its members tessellated (their transforms applied) and joined
 * into one mesh (positions and vertex normals; corner channels dropped). */
static geom_status tess_group(const geom_shape *s, const geom_tess_request *rq, geom_mesh *out,
                              geom_tess_info *info, geom_diag *diag)
{
    size_t nv = 0, nf = 0, ni = 0, capv = 0, capf = 0, capi = 0;
    double *xyz = NULL;
    uint32_t *sizes = NULL, *idx = NULL;
    geom_status st = GEOM_OK;
    info->method = "group";
    for (size_t k = 0; k < s->n_members && st == GEOM_OK; k++) {
        geom_mesh *m = geom_mesh_create(NULL);
        geom_tess_info mi;
        geom_tess_request r2 = *rq;
        r2.attributes = 0;
        if (!m)
            return GEOM_ERR_NOMEM;
        st = geom_scene_tessellate(s->members[k], &r2, m, &mi, diag);
        if (st == GEOM_OK && s->members[k]->transform)
            st = geom_scene_mesh_transform(m, *s->members[k]->transform);
        if (mi.error.max_error > info->error.max_error)
            info->error = mi.error;
        size_t mv = geom_mesh_n_vertices(m), mf = geom_mesh_n_live_faces(m), mi_n = 0;
        if (st == GEOM_OK)
            st = geom_mesh_to_soup(m, NULL, NULL, &mi_n);
        if (st == GEOM_OK) {
            void *a = xyz, *b = sizes, *c = idx;
            st = geom__grow(NULL, &a, &capv, nv + mv, 3 * sizeof *xyz);
            xyz = a;
            if (st == GEOM_OK)
                st = geom__grow(NULL, &b, &capf, nf + mf, sizeof *sizes);
            sizes = b;
            if (st == GEOM_OK)
                st = geom__grow(NULL, &c, &capi, ni + mi_n, sizeof *idx);
            idx = c;
        }
        if (st == GEOM_OK)
            st = geom_mesh_to_soup(m, sizes + nf, idx + ni, &mi_n);
        if (st == GEOM_OK) {
            memcpy(xyz + 3 * nv, geom_mesh_cpositions(m), 3 * mv * sizeof(double));
            for (size_t i = 0; i < mi_n; i++)
                idx[ni + i] += (uint32_t)nv;
            nv += mv;
            nf += mf;
            ni += mi_n;
        }
        geom_mesh_destroy(m);
    }
    if (st == GEOM_OK) {
        geom_mesh_build_options bo;
        memset(&bo, 0, sizeof bo);
        bo.keep_orientation = 1;
        st = geom_mesh_build(out, nv, xyz, nf, sizes, idx, &bo, NULL, diag);
    }
    if (st == GEOM_OK && (rq->attributes & (GEOM_NEEDS_NORMAL | GEOM_NEEDS_TANGENT))) {
        uint32_t id;
        st = geom_mesh_channel_add(out, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id);
        if (st == GEOM_OK)
            st = geom_mesh_vertex_normals(out, GEOM_NORMAL_WEIGHT_ANGLE,
                                          geom_mesh_channel_data(out, id), NULL);
    }
    geom__free(NULL, xyz, 3 * capv * sizeof(double));
    geom__free(NULL, sizes, capf * sizeof(uint32_t));
    geom__free(NULL, idx, capi * sizeof(uint32_t));
    return st;
}

geom_status geom_scene_tessellate(const geom_shape *s, const geom_tess_request *rq, geom_mesh *out,
                                  geom_tess_info *info_out, geom_diag *diag)
{
    geom_tess_info info;
    memset(&info, 0, sizeof info);
    if (info_out)
        memset(info_out, 0, sizeof *info_out);
    if (!s || !rq || !out || !(rq->tol > 0) || !isfinite(rq->tol))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "tessellation needs a shape, an output mesh and a tolerance > 0");
    double t0 = now();
    geom_status st = GEOM_OK;
    unsigned attrs = rq->attributes;
    info.method = "exact";
    info.error.method = GEOM_ERROR_BOUND;
    switch (s->kind) {
    case GEOM_SHAPE_SPHERE:
    case GEOM_SHAPE_TORUS: {
        quadric_nurbs qn;
        geom_nurbs_surface ns;
        st = sphere_torus_nurbs(s, &qn, &ns);
        if (st == GEOM_OK)
            st = tess_nurbs(&ns, 1, rq, out, &info, diag);
        break;
    }
    case GEOM_SHAPE_SURFACE:
        if (!s->surfaces || !s->n_surfaces)
            st = GEOM_ERR_INVALID_ARG;
        else
            st = tess_nurbs(s->surfaces, s->n_surfaces, rq, out, &info, diag);
        break;
    case GEOM_SHAPE_BOX:
        st = tess_box(s->min, s->max, attrs, out, diag);
        break;
    case GEOM_SHAPE_POLYGON:
        if (!s->vertices || s->n_vertices < 3)
            st = GEOM_ERR_INVALID_ARG;
        else {
            double a[3] = {0, 0, 0};
            for (size_t i = 0; i < s->n_vertices; i++) { /* Newell */
                const double *p = s->vertices + 3 * i, *q = s->vertices + 3 * ((i + 1) % s->n_vertices);
                a[0] += (p[1] - q[1]) * (p[2] + q[2]);
                a[1] += (p[2] - q[2]) * (p[0] + q[0]);
                a[2] += (p[0] - q[0]) * (p[1] + q[1]);
            }
            if (a[0] == 0 && a[1] == 0 && a[2] == 0)
                st = GEOM_ERR_DEGENERATE;
            else
                st = tess_planar(s->vertices, s->n_vertices, a, attrs, out, diag);
            info.method = "polygon";
        }
        break;
    case GEOM_SHAPE_DISK: {
        size_t n = disk_sides(s, rq->tol);
        double *pts = geom__alloc(NULL, 3 * n * sizeof(double));
        if (!pts) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        double t[3], b[3], nn[3];
        frame_of(s->n, t, b, nn);
        for (size_t i = 0; i < n; i++) {
            double a = 2 * GEOM_PI * (double)i / (double)n;
            for (int k = 0; k < 3; k++)
                pts[3 * i + k] = s->p[k] + s->radius * (cos(a) * t[k] + sin(a) * b[k]);
        }
        st = tess_planar(pts, n, nn, attrs, out, diag);
        geom__free(NULL, pts, 3 * n * sizeof(double));
        info.error.max_error = s->radius * (1 - cos(GEOM_PI / (double)n));
        info.method = "polygon";
        break;
    }
    case GEOM_SHAPE_PLANE: {
        geom_aabb e = rq->extent;
        if (geom_aabb_is_empty(e) || geom_vec3_length(geom_vec3_sub(e.max, e.min)) == 0) {
            st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                               "object %s: an unbounded plane needs an extent", nm(s));
            break;
        }
        geom_vec3 c = geom_vec3_scale(geom_vec3_add(e.min, e.max), 0.5);
        double R = geom_vec3_length(geom_vec3_sub(e.max, e.min));
        double t[3], b[3], nn[3], pts[12];
        frame_of(s->n, t, b, nn);
        /* centre: the extent's centre projected on the plane */
        double dd = (c.x - s->p[0]) * nn[0] + (c.y - s->p[1]) * nn[1] + (c.z - s->p[2]) * nn[2];
        double pc[3] = {c.x - dd * nn[0], c.y - dd * nn[1], c.z - dd * nn[2]};
        static const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                pts[3 * i + k] = pc[k] + R * (su[i] * t[k] + sv[i] * b[k]);
        st = tess_planar(pts, 4, nn, attrs, out, diag);
        break;
    }
    case GEOM_SHAPE_MESH:
        if (!s->mesh) {
            st = GEOM_ERR_INVALID_ARG;
            break;
        }
        {
            /* a copy of the mesh into out with the attribute channels the
             * renderers read (VERTEX and CORNER "uv", "normal", "tangent") */
            static const char *const keep[3] = {"uv", "normal", "tangent"};
            st = geom__mesh_copy(out, s->mesh);
            if (st == GEOM_OK)
                keep_channels(out, keep, 3, 1);
            info.method = "mesh";
            info.error.method = GEOM_ERROR_NONE;
        }
        break;
    case GEOM_SHAPE_SUBDIV:
        if (!s->mesh)
            st = GEOM_ERR_INVALID_ARG;
        else
            st = tess_subdiv(s, rq, out, &info, diag);
        break;
    case GEOM_SHAPE_GROUP:
        st = tess_group(s, rq, out, &info, diag);
        break;
    case GEOM_SHAPE_QUADRIC:
    case GEOM_SHAPE_IMPLICIT:
    case GEOM_SHAPE_VOLUME:
    case GEOM_SHAPE_CSG: {
        const geom_shape *bad = no_implicit(s);
        if (bad) {
            st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                               "object %s: CSG needs an implicit form, and %s (a %s) has none",
                               nm(s), nm(bad),
                               bad->kind == GEOM_SHAPE_MESH ? "mesh"
                               : bad->kind == GEOM_SHAPE_SURFACE ? "surface"
                               : bad->kind == GEOM_SHAPE_SUBDIV ? "subdivision surface"
                               : "polygon or disk");
            break;
        }
        st = tess_iso(s, rq, out, &info, diag);
        break;
    }
    default:
        st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "object %s: unknown kind %d",
                           nm(s), (int)s->kind);
    }
    if (st == GEOM_OK && (attrs & GEOM_NEEDS_TANGENT) &&
        geom_mesh_channel_find(out, "tangent", GEOM_MESH_DOMAIN_CORNER) == GEOM_INVALID_INDEX &&
        geom_mesh_channel_find(out, "uv", GEOM_MESH_DOMAIN_CORNER) != GEOM_INVALID_INDEX)
        st = geom_mesh_tangents(out, NULL);
    info.triangles = 0;
    if (st == GEOM_OK) {
        size_t nf = geom_mesh_n_faces(out);
        for (uint32_t f = 0; f < nf; f++)
            if (!geom_mesh_face_is_deleted(out, f))
                info.triangles += geom_mesh_face_valence(out, f) - 2;
    }
    info.seconds = now() - t0;
    if (info_out)
        *info_out = info;
    return st;
}

/* ------------------------------------------------------------ estimate */

geom_status geom_scene_tessellate_estimate(const geom_shape *s, const geom_tess_request *rq,
                                           double *triangles)
{
    return geom__scene_tessellate_estimate(s, rq, 0, triangles);
}

geom_status geom__scene_tessellate_estimate(const geom_shape *s, const geom_tess_request *rq,
                                            int cheap, double *triangles)
{
    if (!triangles)
        return GEOM_ERR_INVALID_ARG;
    *triangles = 0;
    if (!s || !rq || !(rq->tol > 0) || !isfinite(rq->tol))
        return GEOM_ERR_INVALID_ARG;
    geom_status st = GEOM_OK;
    double t = 0;
    switch (s->kind) {
    case GEOM_SHAPE_SPHERE:
    case GEOM_SHAPE_TORUS:
    case GEOM_SHAPE_SURFACE: {
        /* the surface module's estimate with the options tess_nurbs uses */
        geom_surface_tess_options o;
        memset(&o, 0, sizeof o);
        o.tolerance = rq->tol;
        if (s->kind == GEOM_SHAPE_SURFACE) {
            if (!s->surfaces || !s->n_surfaces)
                return GEOM_ERR_INVALID_ARG;
            st = geom_surface_tess_estimate(s->surfaces, s->n_surfaces, &o, &t);
        } else {
            quadric_nurbs qn;
            geom_nurbs_surface ns;
            st = sphere_torus_nurbs(s, &qn, &ns);
            if (st == GEOM_OK)
                st = geom_surface_tess_estimate(&ns, 1, &o, &t);
        }
        break;
    }
    case GEOM_SHAPE_BOX:
        t = 12;
        break;
    case GEOM_SHAPE_POLYGON:
        t = s->n_vertices >= 3 ? (double)s->n_vertices - 2 : 0;
        break;
    case GEOM_SHAPE_DISK:
        t = (double)disk_sides(s, rq->tol) - 2;
        break;
    case GEOM_SHAPE_PLANE:
        t = 2;
        break;
    case GEOM_SHAPE_MESH:
    case GEOM_SHAPE_SUBDIV: {
        if (!s->mesh)
            return GEOM_ERR_INVALID_ARG;
        double corners = 0, polys = 0;
        size_t nf = geom_mesh_n_faces(s->mesh);
        for (uint32_t f = 0; f < nf; f++)
            if (!geom_mesh_face_is_deleted(s->mesh, f)) {
                double val = (double)geom_mesh_face_valence(s->mesh, f);
                corners += val;
                polys += val - 2;
            }
        if (s->kind == GEOM_SHAPE_MESH) {
            t = polys;
            break;
        }
        /* tess_subdiv refines until the control points are within tol of
         * the limit, at most to level 7; that distance shrinks about 4 times
         * a level (second-order convergence), from level 1's, which is
         * measured here (tess_subdiv's first step) */
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.scheme = (geom_subdiv_scheme)s->scheme;
        geom_subdiv_report rep;
        memset(&rep, 0, sizeof rep);
        geom_mesh *tmp = NULL;
        st = geom_subdiv_mesh(s->mesh, &o, 1, 0, &tmp, &rep, NULL);
        geom_mesh_destroy(tmp);
        if (st != GEOM_OK)
            break;
        int level = 1;
        double d = rep.max_limit_distance;
        while (level < 7 && !(d <= rq->tol)) {
            d /= 4;
            level++;
        }
        /* Catmull-Clark: one quad per corner at level 1, 4 per quad a level
         * after, 2 triangles each; Loop: 4 triangles per triangle a level */
        double four = ldexp(1.0, 2 * (level - 1));
        t = s->scheme == GEOM_SUBDIV_LOOP ? polys * 4 * four : corners * four * 2;
        break;
    }
    case GEOM_SHAPE_GROUP:
        for (size_t k = 0; k < s->n_members && st == GEOM_OK; k++) {
            double m = 0;
            geom_tess_request r2 = *rq;
            r2.attributes = 0;
            st = geom__scene_tessellate_estimate(s->members[k], &r2, cheap, &m);
            t += m;
        }
        break;
    case GEOM_SHAPE_QUADRIC:
    case GEOM_SHAPE_IMPLICIT:
    case GEOM_SHAPE_VOLUME:
    case GEOM_SHAPE_CSG: {
        if (no_implicit(s))
            return GEOM_ERR_INVALID_ARG;
        geom_shape local = *s;
        local.transform = NULL;
        geom_aabb b = shape_bounds(&local, rq->extent);
        if (geom_aabb_is_empty(b) || !isfinite(b.min.x) || !isfinite(b.max.x) ||
            !isfinite(b.min.y) || !isfinite(b.max.y) || !isfinite(b.min.z) || !isfinite(b.max.z))
            return GEOM_ERR_INVALID_ARG;
        double bounds[6];
        double h = iso_grid(b, rq->tol, bounds);
        inode *root = inode_make(&local, 1);
        if (!root)
            return GEOM_ERR_NOMEM;
        geom_implicit_field f;
        memset(&f, 0, sizeof f);
        f.value = iso_value_cb;
        f.user = root;
        f.exact = 1;
        st = iso_estimate(&f, bounds, h, rq->tol, cheap, &t);
        inode_free(root);
        break;
    }
    default:
        return GEOM_ERR_INVALID_ARG;
    }
    *triangles = st == GEOM_OK ? t : 0;
    return st;
}

geom_status geom_scene_mesh_transform(geom_mesh *m, geom_mat4 M)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    geom_mat3 nmat;
    geom_status st = geom_mat4_normal_matrix(M, &nmat);
    if (st != GEOM_OK)
        return st;
    double *p = geom_mesh_positions(m);
    for (size_t v = 0; v < geom_mesh_n_vertices(m); v++) {
        geom_vec3 q;
        geom_mat4_transform_point(M, geom_vec3_make(p[3 * v], p[3 * v + 1], p[3 * v + 2]), &q);
        p[3 * v] = q.x;
        p[3 * v + 1] = q.y;
        p[3 * v + 2] = q.z;
    }
    size_t nc = geom_mesh_channel_count(m);
    for (uint32_t c = 1; c < nc; c++) {
        const char *name = geom_mesh_channel_name(m, c);
        int is_n = !strcmp(name, "normal"), is_t = !strcmp(name, "tangent");
        if (!is_n && !is_t)
            continue;
        size_t k = geom_mesh_channel_ncomp(m, c), n = geom_mesh_channel_size(m, c);
        if (k < 3)
            continue;
        double *d = geom_mesh_channel_data(m, c);
        for (size_t i = 0; i < n; i++) {
            geom_vec3 a = geom_vec3_make(d[k * i], d[k * i + 1], d[k * i + 2]), b;
            a = is_n ? geom_mat3_mul_vec3(nmat, a) : geom_mat4_transform_dir(M, a);
            if (geom_vec3_normalize(a, &b) != GEOM_OK)
                b = a;
            d[k * i] = b.x;
            d[k * i + 1] = b.y;
            d[k * i + 2] = b.z;
        }
    }
    return GEOM_OK;
}

geom_aabb geom_scene_shape_bounds(const geom_shape *s)
{
    geom_aabb none = geom_aabb_empty();
    if (!s)
        return none;
    return shape_bounds(s, none);
}

geom_status geom_scene_displace(geom_mesh *m, const geom_texture *height, double scale)
{
    if (!m || !height)
        return GEOM_ERR_INVALID_ARG;
    if (scale == 0)
        scale = 1;
    size_t nv = geom_mesh_n_vertices(m);
    uint32_t cuv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t vuv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_VERTEX);
    if (cuv == GEOM_INVALID_INDEX && vuv == GEOM_INVALID_INDEX)
        return GEOM_ERR_INVALID_ARG;
    double *n = geom__alloc(NULL, (3 * nv + 1) * sizeof *n);
    double *uv = geom__alloc(NULL, (2 * nv + 1) * sizeof *uv);
    unsigned char *has = geom__alloc(NULL, nv + 1);
    geom_status st = GEOM_OK;
    if (!n || !uv || !has)
        st = GEOM_ERR_NOMEM;
    if (st == GEOM_OK)
        st = geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_ANGLE, n, NULL);
    if (st == GEOM_OK) {
        memset(has, 0, nv + 1);
        if (vuv != GEOM_INVALID_INDEX) {
            memcpy(uv, geom_mesh_channel_cdata(m, vuv), 2 * nv * sizeof(double));
            memset(has, 1, nv);
        } else {
            /* a vertex on a UV seam takes the value of its first corner */
            const double *d = geom_mesh_channel_cdata(m, cuv);
            const uint32_t *ci = geom_mesh_corner_cindices(m, cuv);
            for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); h++) {
                uint32_t v = geom_mesh_he_vertex(m, h);
                if (v < nv && !has[v] && ci[h] != GEOM_INVALID_INDEX) {
                    uv[2 * v] = d[2 * ci[h]];
                    uv[2 * v + 1] = d[2 * ci[h] + 1];
                    has[v] = 1;
                }
            }
        }
        double *p = geom_mesh_positions(m);
        for (size_t v = 0; v < nv; v++) {
            if (!has[v])
                continue;
            double hgt;
            geom_scene_texture_sample(height, uv[2 * v], uv[2 * v + 1], 0, &hgt);
            for (int k = 0; k < 3; k++)
                p[3 * v + k] += scale * hgt * n[3 * v + k];
        }
        /* the displaced surface's own normals replace the old ones */
        uint32_t c;
        while ((c = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER)) != GEOM_INVALID_INDEX)
            geom_mesh_channel_remove(m, c);
        while ((c = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX)) != GEOM_INVALID_INDEX)
            geom_mesh_channel_remove(m, c);
        st = geom_mesh_channel_add(m, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &c);
        if (st == GEOM_OK)
            st = geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_ANGLE, geom_mesh_channel_data(m, c), NULL);
    }
    geom__free(NULL, n, (3 * nv + 1) * sizeof *n);
    geom__free(NULL, uv, (2 * nv + 1) * sizeof *uv);
    geom__free(NULL, has, nv + 1);
    return st;
}
