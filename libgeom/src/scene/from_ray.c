/* The shapes of a ray-module scene: one representation, read back from the
 * nodes the scene JSON parser made, through the ray module's shape walk
 * (ray/ray_walk.h). */
#include "geom/scene.h"

#include <string.h>

#include "core/internal.h"
#include "ray/ray_walk.h"

struct geom_scene_shapes {
    const geom_ray_scene *rs;
    /* everything allocated, freed at destroy */
    void **blocks;
    size_t *sizes;
    size_t nblocks, cap, scap; /* capacities of blocks and sizes */
    geom_mesh **meshes;
    size_t nmeshes, mcap;
    const geom_shape **top;
    geom_ray_kind *top_kind;
    size_t ntop;
};

static void *hold(geom_scene_shapes *h, size_t size)
{
    {
        void *nb = h->blocks, *ns = h->sizes;
        geom_status st = geom__grow(NULL, &nb, &h->cap, h->nblocks + 1, sizeof *h->blocks);
        h->blocks = nb;
        if (st == GEOM_OK)
            st = geom__grow(NULL, &ns, &h->scap, h->nblocks + 1, sizeof *h->sizes);
        h->sizes = ns;
        if (st != GEOM_OK)
            return NULL;
    }
    void *p = geom__alloc(NULL, size ? size : 1);
    if (!p)
        return NULL;
    memset(p, 0, size ? size : 1);
    h->blocks[h->nblocks] = p;
    h->sizes[h->nblocks++] = size ? size : 1;
    return p;
}

static geom_status keep_mesh(geom_scene_shapes *h, geom_mesh *m)
{
    void *nm = h->meshes;
    geom_status st = geom__grow(NULL, &nm, &h->mcap, h->nmeshes + 1, sizeof *h->meshes);
    h->meshes = nm;
    if (st != GEOM_OK)
        return st;
    h->meshes[h->nmeshes++] = m;
    return GEOM_OK;
}

void geom_scene_shapes_destroy(geom_scene_shapes *h)
{
    if (!h)
        return;
    for (size_t i = 0; i < h->nblocks; i++)
        geom__free(NULL, h->blocks[i], h->sizes[i]);
    for (size_t i = 0; i < h->nmeshes; i++)
        geom_mesh_destroy(h->meshes[i]);
    geom__free(NULL, h->blocks, h->cap * sizeof *h->blocks);
    geom__free(NULL, h->sizes, h->scap * sizeof *h->sizes);
    geom__free(NULL, h->meshes, h->mcap * sizeof *h->meshes);
    geom__free(NULL, h->top, (h->ntop ? h->ntop : 1) * sizeof *h->top);
    geom__free(NULL, h->top_kind, (h->ntop ? h->ntop : 1) * sizeof *h->top_kind);
    geom__free(NULL, h, sizeof *h);
}

static geom_mat4 mat_of(const double *m)
{
    geom_mat4 r;
    memcpy(r.m, m, sizeof r.m);
    return r;
}

/* A fresh transform = outer * node's own (either may be absent). */
static const geom_mat4 *compose(geom_scene_shapes *h, const geom_mat4 *outer,
                                const geom__ray_node_info *nd)
{
    if (!outer && !nd->xf)
        return NULL;
    geom_mat4 *m = hold(h, sizeof *m);
    if (!m)
        return NULL;
    geom_mat4 own = nd->xf ? mat_of(nd->xf) : geom_mat4_identity();
    *m = outer ? geom_mat4_mul(*outer, own) : own;
    return m;
}

static void corner_channel(geom_mesh_build_channel *c, const char *name, size_t ncomp,
                           const double *values, size_t n, const uint32_t *indices)
{
    c->name = name;
    c->domain = GEOM_MESH_DOMAIN_CORNER;
    c->ncomp = ncomp;
    c->values = values;
    c->n_values = n;
    c->indices = indices;
}

static geom_status mesh_of(geom_scene_shapes *h, const geom__ray_node_info *t, geom_mesh **out)
{
    geom_mesh *m = geom_mesh_create(NULL);
    if (!m)
        return GEOM_ERR_NOMEM;
    geom_status st = keep_mesh(h, m);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return st;
    }
    uint32_t *sizes = geom__alloc(NULL, (t->nt ? t->nt : 1) * sizeof *sizes);
    if (!sizes)
        return GEOM_ERR_NOMEM;
    for (size_t i = 0; i < t->nt; i++)
        sizes[i] = 3;
    /* corner UVs and normals as CORNER channels, one pool value per corner */
    geom_mesh_build_channel ch[2];
    size_t nch = 0;
    uint32_t *cidx = NULL;
    if (t->cuv || t->cnrm) {
        cidx = geom__alloc(NULL, (t->nt ? 3 * t->nt : 1) * sizeof *cidx);
        if (!cidx) {
            geom__free(NULL, sizes, (t->nt ? t->nt : 1) * sizeof *sizes);
            return GEOM_ERR_NOMEM;
        }
        for (size_t i = 0; i < 3 * t->nt; i++)
            cidx[i] = (uint32_t)i;
    }
    memset(ch, 0, sizeof ch);
    if (t->cuv)
        corner_channel(&ch[nch++], "uv", 2, t->cuv, 3 * t->nt, cidx);
    if (t->cnrm)
        corner_channel(&ch[nch++], "normal", 3, t->cnrm, 3 * t->nt, cidx);
    geom_mesh_build_options bo;
    memset(&bo, 0, sizeof bo);
    bo.keep_orientation = 1;
    bo.skip_invalid_faces = 1;
    bo.channels = nch ? ch : NULL;
    bo.n_channels = nch;
    st = geom_mesh_build(m, t->nv, t->pos, t->nt, sizes, t->tri, &bo, NULL, NULL);
    geom__free(NULL, sizes, (t->nt ? t->nt : 1) * sizeof *sizes);
    if (cidx)
        geom__free(NULL, cidx, (t->nt ? 3 * t->nt : 1) * sizeof *cidx);
    if (st == GEOM_OK && t->nrm && !t->cnrm && geom_mesh_n_vertices(m) >= t->nv) {
        uint32_t id;
        st = geom_mesh_channel_add(m, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id);
        if (st == GEOM_OK) {
            double *d = geom_mesh_channel_data(m, id);
            const uint32_t *org = geom_mesh_vertex_origin(m);
            for (size_t v = 0; v < geom_mesh_n_vertices(m); v++) {
                size_t o = org ? org[v] : v;
                memcpy(d + 3 * v, t->nrm + 3 * o, 3 * sizeof(double));
            }
        }
    }
    *out = m;
    return st;
}

static geom_status shape_of(geom_scene_shapes *h, uint32_t id, const geom_mat4 *outer, int depth,
                            const geom_shape **out, geom_diag *diag)
{
    const geom_ray_scene *rs = h->rs;
    geom__ray_node_info ndv;
    if (depth > 64 || geom__ray_scene_node_info(rs, id, &ndv) != GEOM_OK)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "scene: node %u out of range or nested too deeply", (unsigned)id);
    const geom__ray_node_info *nd = &ndv;
    if (nd->kind == GEOM_RAY_INSTANCE) {
        const geom_mat4 *m = compose(h, outer, nd);
        if ((outer || nd->xf) && !m)
            return GEOM_ERR_NOMEM;
        return shape_of(h, nd->a, m, depth + 1, out, diag);
    }
    geom_shape *s = hold(h, sizeof *s);
    if (!s)
        return GEOM_ERR_NOMEM;
    s->name = nd->name[0] ? nd->name : NULL;
    s->transform = compose(h, outer, nd);
    if ((outer || nd->xf) && !s->transform)
        return GEOM_ERR_NOMEM;
    geom_status st = GEOM_OK;
    switch (nd->kind) {
    case GEOM_RAY_SPHERE:
        s->kind = GEOM_SHAPE_SPHERE;
        memcpy(s->p, nd->center, 3 * sizeof(double));
        s->radius = nd->radius;
        break;
    case GEOM_RAY_BOX:
        s->kind = GEOM_SHAPE_BOX;
        memcpy(s->min, nd->min, 3 * sizeof(double));
        memcpy(s->max, nd->max, 3 * sizeof(double));
        break;
    case GEOM_RAY_OBOX: {
        /* a box [-half, half] in the frame (axes, centre) */
        s->kind = GEOM_SHAPE_BOX;
        for (int k = 0; k < 3; k++) {
            s->min[k] = -nd->half[k];
            s->max[k] = nd->half[k];
        }
        geom_mat4 f = geom_mat4_identity();
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++)
                f.m[4 * c + r] = nd->axes[3 * c + r];
        for (int r = 0; r < 3; r++)
            f.m[12 + r] = nd->center[r];
        geom_mat4 *m = hold(h, sizeof *m);
        if (!m)
            return GEOM_ERR_NOMEM;
        *m = s->transform ? geom_mat4_mul(*s->transform, f) : f;
        s->transform = m;
        break;
    }
    case GEOM_RAY_PLANE:
        s->kind = GEOM_SHAPE_PLANE;
        memcpy(s->p, nd->center, 3 * sizeof(double));
        memcpy(s->n, nd->normal, 3 * sizeof(double));
        break;
    case GEOM_RAY_DISK:
        s->kind = GEOM_SHAPE_DISK;
        memcpy(s->p, nd->center, 3 * sizeof(double));
        memcpy(s->n, nd->normal, 3 * sizeof(double));
        s->radius = nd->radius;
        break;
    case GEOM_RAY_QUADRIC:
        s->kind = GEOM_SHAPE_QUADRIC;
        memcpy(s->q, nd->q, 10 * sizeof(double));
        if (nd->has_clip) {
            double *c = hold(h, 6 * sizeof(double));
            if (!c)
                return GEOM_ERR_NOMEM;
            memcpy(c, nd->clip, 6 * sizeof(double));
            s->clip = c;
            s->capped = nd->capped;
        }
        break;
    case GEOM_RAY_TORUS:
        s->kind = GEOM_SHAPE_TORUS;
        s->major = nd->major;
        s->minor = nd->minor;
        break;
    case GEOM_RAY_TRIANGLE:
    case GEOM_RAY_POLYGON:
        s->kind = GEOM_SHAPE_POLYGON;
        s->vertices = nd->verts;
        s->n_vertices = nd->nverts;
        break;
    case GEOM_RAY_SUBDIV:
        if (nd->control && nd->levels == 0) {
            /* levels left to the renderer: the control mesh, refined where
             * the picture needs it */
            s->kind = GEOM_SHAPE_SUBDIV;
            s->mesh = nd->control;
            s->scheme = nd->scheme;
            break;
        }
        /* the refined limit mesh at the levels asked */
        /* fall through */
    case GEOM_RAY_MESH: {
        geom_mesh *m = NULL;
        if (!nd->pos && nd->nv)
            return GEOM_ERR_INVALID_ARG;
        st = mesh_of(h, nd, &m);
        s->kind = GEOM_SHAPE_MESH;
        s->mesh = m;
        break;
    }
    case GEOM_RAY_SURFACE:
        s->kind = GEOM_SHAPE_SURFACE;
        s->surfaces = nd->surface;
        s->n_surfaces = 1;
        break;
    case GEOM_RAY_IMPLICIT:
        s->kind = GEOM_SHAPE_IMPLICIT;
        s->expr = nd->expr;
        memcpy(s->bounds, nd->bounds, 6 * sizeof(double));
        break;
    case GEOM_RAY_VOLUME:
        s->kind = GEOM_SHAPE_VOLUME;
        s->volume = nd->volume;
        s->iso = nd->iso;
        s->inside = nd->inside;
        break;
    case GEOM_RAY_CSG:
        s->kind = GEOM_SHAPE_CSG;
        s->csg_op = nd->op;
        if ((st = shape_of(h, nd->a, NULL, depth + 1, &s->a, diag)) == GEOM_OK)
            st = shape_of(h, nd->b, NULL, depth + 1, &s->b, diag);
        break;
    case GEOM_RAY_GROUP: {
        /* untransformed surfaces: one multi-surface shape (welded seams) */
        int all_surf = 1;
        geom__ray_node_info c;
        for (size_t i = 0; i < nd->nmembers; i++)
            if (geom__ray_scene_node_info(rs, nd->members[i], &c) != GEOM_OK ||
                c.kind != GEOM_RAY_SURFACE || c.xf)
                all_surf = 0;
        if (all_surf) {
            geom_nurbs_surface *ss = hold(h, nd->nmembers * sizeof *ss);
            if (!ss)
                return GEOM_ERR_NOMEM;
            for (size_t i = 0; i < nd->nmembers; i++) {
                geom__ray_scene_node_info(rs, nd->members[i], &c);
                ss[i] = *c.surface;
            }
            s->kind = GEOM_SHAPE_SURFACE;
            s->surfaces = ss;
            s->n_surfaces = nd->nmembers;
            break;
        }
        const geom_shape **mem = hold(h, nd->nmembers * sizeof *mem);
        if (!mem)
            return GEOM_ERR_NOMEM;
        for (size_t i = 0; i < nd->nmembers && st == GEOM_OK; i++)
            st = shape_of(h, nd->members[i], NULL, depth + 1, &mem[i], diag);
        s->kind = GEOM_SHAPE_GROUP;
        s->members = (const geom_shape *const *)mem;
        s->n_members = nd->nmembers;
        break;
    }
    default:
        st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "scene: node %u of kind %s",
                           (unsigned)id, geom_ray_kind_name(nd->kind));
    }
    *out = s;
    return st;
}

geom_status geom_scene_shapes_from_ray(const geom_ray_scene *rs, geom_scene_shapes **out,
                                       geom_diag *diag)
{
    if (!out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_scene_shapes_from_ray: invalid argument");
    *out = NULL;
    if (!rs)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_scene_shapes_from_ray: invalid argument");
    geom_scene_shapes *h = geom__alloc(NULL, sizeof *h);
    if (!h)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_scene_shapes_from_ray: out of memory");
    memset(h, 0, sizeof *h);
    h->rs = rs;
    size_t n = geom__ray_scene_top(rs, NULL, 0);
    h->top = geom__alloc(NULL, (n ? n : 1) * sizeof *h->top);
    h->top_kind = geom__alloc(NULL, (n ? n : 1) * sizeof *h->top_kind);
    uint32_t *ids = geom__alloc(NULL, (n ? n : 1) * sizeof *ids);
    h->ntop = n;
    if (!h->top || !h->top_kind || !ids) {
        geom__free(NULL, ids, (n ? n : 1) * sizeof *ids);
        geom_scene_shapes_destroy(h);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_scene_shapes_from_ray: out of memory");
    }
    geom__ray_scene_top(rs, ids, n);
    geom_status st = GEOM_OK;
    for (size_t k = 0; st == GEOM_OK && k < n; k++) {
        h->top_kind[k] = geom_ray_scene_node_kind(rs, ids[k]);
        st = shape_of(h, ids[k], NULL, 0, &h->top[k], diag);
    }
    geom__free(NULL, ids, (n ? n : 1) * sizeof *ids);
    if (st != GEOM_OK) {
        geom_scene_shapes_destroy(h);
        return st;
    }
    *out = h;
    return GEOM_OK;
}

size_t geom_scene_shapes_count(const geom_scene_shapes *s)
{
    return s ? s->ntop : 0;
}

const geom_shape *geom_scene_shapes_get(const geom_scene_shapes *s, size_t i)
{
    return s && i < s->ntop ? s->top[i] : NULL;
}

const char *geom_scene_shapes_kind_name(const geom_scene_shapes *s, size_t i)
{
    return s && i < s->ntop ? geom_ray_kind_name(s->top_kind[i]) : "unknown";
}
