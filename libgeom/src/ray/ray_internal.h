/* Private declarations of the ray module. Not installed. */
#ifndef GEOM_SRC_RAY_INTERNAL_H
#define GEOM_SRC_RAY_INTERNAL_H

#include "geom/ray.h"
#include "core/internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Query modes of the per-kind functions. */
enum { GEOM__RAY_CLOSEST = 0, GEOM__RAY_ANY = 1, GEOM__RAY_ALL = 2 };

/* gamma(n) = n eps / (1 - n eps) (Higham), eps = 2^-53. */
static inline double geom__gamma(int n)
{
    const double e = DBL_EPSILON * 0.5;
    return (n * e) / (1.0 - n * e);
}

/* geom_ray_check without the call: finite origin and direction, a nonzero
 * direction, tmin and tmax not NaN. */
static inline int geom__ray_valid(const geom_ray *r)
{
    return fabs(r->origin.x) <= DBL_MAX && fabs(r->origin.y) <= DBL_MAX && fabs(r->origin.z) <= DBL_MAX &&
           fabs(r->dir.x) <= DBL_MAX && fabs(r->dir.y) <= DBL_MAX && fabs(r->dir.z) <= DBL_MAX &&
           (r->dir.x != 0 || r->dir.y != 0 || r->dir.z != 0) && !isnan(r->tmin) && !isnan(r->tmax);
}

/* A ray's slab-test state computed once per query (Ize, "Robust BVH Ray
 * Traversal", JCGT 2013): the reciprocal direction, used by every box test of
 * the scene-level traversal instead of a division per slab. A slab distance
 * fl(fl(L - o) * fl(1/d)) is within gamma(3) relative of the exact (L - o)/d;
 * the largest near and smallest far distance are each one of them, so
 * widening both by 2 gamma(3) |t| (as geom_ray_aabb does) keeps the test
 * conservative. A zero component has an infinite reciprocal: the distances
 * are then +-inf (origin outside the slab: the right answer) or NaN (origin
 * on a slab plane), which the comparisons ignore (the ray is in the slab).
 * ok == 0 (a reciprocal beyond 2^1000, or a NaN-free test impossible) sends
 * every box to geom_ray_aabb; ok == -1: not computed yet (geom__rslab_hit
 * computes it at the first box, so a ray that needs none costs no division). */
typedef struct geom__rslab {
    double o[3], inv[3];
    int neg[3];
    int ok;
} geom__rslab;

/* Compute s for r (hit.c): inv[k] = 1/d[k], or +-inf (the sign of d[k]) for
 * a zero component; neg[k] = the sign bit of d[k]. */
void geom__rslab_init(geom__rslab *s, const geom_ray *r);

#if defined(__GNUC__) || defined(__clang__)
#define GEOM__RAY_INLINE static inline __attribute__((always_inline))
#else
#define GEOM__RAY_INLINE static inline
#endif

/* Whether the ray r (whose state s is, or ok == -1) meets the finite box b
 * within [r->tmin, r->tmax]: the answer of geom_ray_aabb(r, b, NULL, NULL)
 * but for the last rounding of a slab distance (both are conservative). */
GEOM__RAY_INLINE int geom__rslab_hit(geom__rslab *s, const geom_ray *r, const geom_aabb *b)
{
    const double *lo = &b->min.x, *hi = &b->max.x;
    const double w = 2 * geom__gamma(3);
    double tn = -INFINITY, tf = INFINITY;
    int k;
    if (s->ok <= 0) {
        if (s->ok < 0) geom__rslab_init(s, r);
        if (!s->ok) return geom_ray_aabb(r, *b, NULL, NULL);
    }
    for (k = 0; k < 3; k++) {
        double a = ((s->neg[k] ? hi[k] : lo[k]) - s->o[k]) * s->inv[k];
        double c = ((s->neg[k] ? lo[k] : hi[k]) - s->o[k]) * s->inv[k];
        tn = a > tn ? a : tn; /* NaN ignored */
        tf = c < tf ? c : tf;
    }
    tn -= fabs(tn) * w; /* +-inf - inf: NaN, a miss below (the exact distance is infinite) */
    tf += fabs(tf) * w;
    return tn <= tf && tf >= r->tmin && tn <= r->tmax;
}

/* A growable list of hits with a small inline buffer: no allocation for
 * the common closest/any queries. Never copied by value. */
typedef struct geom__rhits {
    geom_ray_hit *h;
    size_t n, cap;
    const geom_allocator *alloc;
    int heap;
    int failed; /* an allocation failed: the list is incomplete */
    geom_ray_hit local[8];
} geom__rhits;

void geom__rhits_init(geom__rhits *l, const geom_allocator *alloc);
void geom__rhits_free(geom__rhits *l);
/* Append (returns the new slot, zeroed, or NULL when out of memory). */
geom_ray_hit *geom__rhits_push(geom__rhits *l);
/* Append without zeroing (the caller sets every field): the slot or NULL. */
geom_ray_hit *geom__rhits_push_raw(geom__rhits *l);
/* Sort [from, n) by t, entering first on ties. */
void geom__rhits_sort(geom__rhits *l, size_t from);

/* Mesh data (mesh.c): triangles in a BVH from the spatial module. */
typedef struct geom__tmesh {
    double *pos;       /* 3*nv */
    double *nrm;       /* 3*nv or NULL */
    uint32_t *tri;     /* 3*nt */
    uint32_t *face;    /* nt: face index reported as prim (NULL: identity) */
    size_t nv, nt;
    void *bvh;         /* geom_bvh * */
    double *tv;        /* 9 doubles per triangle in BVH leaf order (v0, v1, v2) */
    uint32_t *tid;     /* triangle index of each tv slot */
    struct geom__rbvh4 *wide; /* 8-wide copy of bvh for traversal (mesh.c), or NULL */
    double *cuv;       /* 6*nt corner UVs per triangle (its corner order) or NULL (walk.c) */
    double *cnrm;      /* 9*nt corner normals per triangle or NULL (walk.c) */
} geom__tmesh;

/* Surface data (surface.c). */
typedef struct geom__tsurf {
    geom_nurbs_surface s;   /* view of the owned arrays below */
    double *knots_u, *knots_v, *points, *weights;
    /* Bezier patches: np patches of (pu+1)*(pv+1) homogeneous points (4 doubles each),
     * patch i covering [u0,u1]x[v0,v1] = dom[4i..4i+3]. */
    size_t np;
    double *hp;
    double *dom;
    geom_aabb *pbox;
    double extent;          /* control points' bounding box diagonal */
    double pmag;            /* largest control point coordinate magnitude */
    double wmax;            /* largest weight (1 if none) */
} geom__tsurf;

typedef struct geom__ray_node {
    geom_ray_kind kind;
    char name[64];
    int has_xf;
    double m[16], minv[16];
    double nm[9];          /* inverse transpose of m's 3x3 */
    double mnorm;          /* max abs row sum of m's 3x3 (for error bounds) */
    int is_child;          /* used by a CSG node */
    int bounded;           /* box valid (else infinite) */
    geom_aabb box;         /* in the parent frame (transform applied) */
    double prm[24];        /* analytic parameters */
    double *verts;         /* polygon vertices */
    size_t nverts;
    geom__tmesh *mesh;     /* mesh, subdiv */
    geom__tsurf *surf;     /* surface */
    const geom_implicit_expr *expr;
    const geom_implicit_volume *vol;
    uint32_t a, b;         /* CSG children / instance target */
    uint32_t *members;     /* group */
    size_t nmembers;
    int op;
    int capped;
    geom_error_report err;
    geom_mesh *control;    /* subdivision: a copy of the control mesh (walk.c) */
    int scheme, levels;    /* subdivision: as asked */
} geom__ray_node;

struct geom_ray_scene {
    geom_allocator alloc_store;
    const geom_allocator *alloc;
    geom__ray_node *nodes;
    size_t n, cap;
    uint32_t *roots;
    size_t nroots, roots_cap;
    int roots_explicit;
    int built;
    /* Top-level BVH over the bounded objects (when there are many). */
    void *top;                 /* geom_bvh * or NULL */
    uint32_t *top_obj;         /* BVH primitive -> object index */
    uint32_t *unbounded;       /* objects tested on every ray (without top: all) */
    size_t ntop, nunbounded;
};

/* The query of one node (in its parent's frame: the node's transform is
 * applied here), appending to out. Closest mode may prune with r->tmax. */
geom_status geom__ray_node_query(const geom_ray_scene *s, uint32_t id, const geom_ray *r, int mode,
                                 geom__rhits *out);

/* Per-kind queries, in the node's local frame. They append hits in
 * [r->tmin, r->tmax] (all of them for ALL mode; at least the closest for
 * CLOSEST; at least one for ANY). */
geom_status geom__ray_plane(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_disk(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_box(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_obox(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_sphere(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_quadric(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_torus(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_tri(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_polygon(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_mesh(const geom__tmesh *m, const geom_ray *r, int mode, geom__rhits *out);
/* geom__ray_mesh with the ray's slab state (sl->ok >= 0: computed for r) or
 * NULL: the reciprocal direction is then not computed again. */
geom_status geom__ray_mesh_sl(const geom__tmesh *m, const geom_ray *r, const geom__rslab *sl, int mode,
                              geom__rhits *out);
geom_status geom__ray_surface(const geom__tsurf *sf, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_implicit(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_volume(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out);
geom_status geom__ray_csg(const geom_ray_scene *s, const geom__ray_node *nd, const geom_ray *r,
                          int mode, geom__rhits *out);

/* Build helpers. */
geom_status geom__ray_mesh_build(geom__tmesh *m, const geom_ray_build_options *opt,
                                 const geom_allocator *alloc, geom_diag *diag);
void geom__ray_mesh_free(geom__tmesh *m, const geom_allocator *alloc);
size_t geom__ray_mesh_bvh_nodes(const geom__tmesh *m, size_t *bytes);
geom_aabb geom__ray_mesh_bounds(const geom__tmesh *m);
/* Closest hits of rays idx[0 .. n) (each valid, tmin <= tmax) against the
 * mesh, their traversals interleaved (mesh.c): hits[idx[i]] and
 * found[idx[i]] set as geom__ray_mesh in closest mode gives them (found
 * left alone on a miss). */
geom_status geom__ray_mesh_closest_many(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                                        geom_ray_hit *hits, int *found, const geom_allocator *alloc);
/* Tests and bench_ray only: the wide mesh traversal of every mesh object of
 * s forced to isa (0: SSE2, 1: AVX2 + FMA when the CPU has them; otherwise,
 * and for -1, unchanged). Returns the first mesh's previous isa, or -1 when
 * s has no wide tree. */
int geom__ray_scene_simd(geom_ray_scene *s, int isa);
/* Tests only: how many runs of eight rays (of the valid ones of rays[0 ..
 * n), with tmin <= tmax, in order) geom_ray_scene_closest_many traces as
 * packets on s as it is (0 when it takes no packets: not a single mesh
 * with a wide tree on the AVX2 path). */
size_t geom__ray_scene_packets(const geom_ray_scene *s, const geom_ray *rays, size_t n);
geom_status geom__ray_surface_build(geom__tsurf *sf, const geom_allocator *alloc, geom_diag *diag);
void geom__ray_surface_free(geom__tsurf *sf, const geom_allocator *alloc);

/* Corner attributes of a mesh's fan triangles (walk.c): m->cuv from a
 * CORNER or VERTEX "uv" channel (2 components), m->cnrm from a CORNER
 * "normal" channel (3), in tmesh_from_mesh's triangle order. */
geom_status geom__ray_tmesh_corner_attrs(geom__tmesh *m, const geom_mesh *gm, const geom_allocator *alloc);
void geom__ray_tmesh_corner_attrs_free(geom__tmesh *m, const geom_allocator *alloc);

/* Polynomial roots with per-coefficient absolute errors cerr (NULL: 0). */
size_t geom__poly_roots(const double *c, const double *cerr, int deg, double lo, double hi,
                        double *roots);

/* The watertight triangle test with a precomputed ray shear. */
typedef struct geom__wbw {
    int kx, ky, kz;
    double sx, sy, sz;
    double o[3], d[3];
} geom__wbw;
void geom__wbw_setup(geom__wbw *w, const geom_ray *r);
/* 1 on a hit with t in [tmin, tmax]; fills t, u, v (barycentrics of v1, v2) */
int geom__wbw_test(const geom__wbw *w, const double *v0, const double *v1, const double *v2,
                   double tmin, double tmax, double *t, double *b);
/* Fill a triangle hit from the barycentrics b[3]. */
void geom__tri_fill(const geom_ray *r, const double *v0, const double *v1, const double *v2,
                    double t, const double *b, geom_ray_hit *h);

/* Small vector helpers. */
static inline geom_vec3 geom__v3(const double *p) { geom_vec3 v = {p[0], p[1], p[2]}; return v; }
static inline double geom__dot(geom_vec3 a, geom_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline geom_vec3 geom__unit(geom_vec3 a)
{
    geom_vec3 u;
    double l2 = a.x * a.x + a.y * a.y + a.z * a.z;
    if (l2 > 1e-280 && l2 < 1e280) { /* fast path: no overflow or underflow possible */
        double s = 1.0 / sqrt(l2);
        u.x = a.x * s; u.y = a.y * s; u.z = a.z * s;
        return u;
    }
    if (geom_vec3_normalize(a, &u) != GEOM_OK) { u.x = 0; u.y = 0; u.z = 1; }
    return u;
}
/* t error from the point's distance to the surface and the angle: the
 * first-order bound (|dist| + point rounding) / |n.d|. */
double geom__terr(const geom_ray *r, double t, double dist, geom_vec3 n);
/* Point rounding bound for o + t d, per component. */
geom_vec3 geom__perr_ray(const geom_ray *r, double t);
/* Two orthonormal tangents of unit n. */
void geom__frame(geom_vec3 n, geom_vec3 *t1, geom_vec3 *t2);
/* Append a hit if t in range; returns the slot or NULL (out of range / no memory). */
geom_ray_hit *geom__push_t(geom__rhits *out, const geom_ray *r, double t);

#endif
