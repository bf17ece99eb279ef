/*
 * Private layout of geom_mesh, shared by the sources of the mesh module (and
 * readable by meshio). Not installed.
 *
 * Arrays (all owned, allocated through m->alloc with geom__alloc/geom__free):
 *
 *   element      count        capacity  arrays
 *   vertex       nv           cap_v     v_he, v_del, vertex channels, vertex_origin
 *   halfedge     nh (= 2*ne)  cap_h     he_next, he_prev, he_vertex, he_face,
 *                                       corner index arrays of CORNER channels
 *   edge         nh / 2       cap_h/2   e_del, EDGE channels
 *   face         nf           cap_f     f_he, f_del, FACE channels, face_origin,
 *                                       face_flipped, face_group
 *
 * Conventions (as the public header): opposite(h) = h ^ 1, edge(h) = h >> 1;
 * he_vertex[h] is the vertex h points TO; he_face[h] is GEOM_INVALID_INDEX on
 * a boundary halfedge; v_he[v] is an outgoing halfedge, a boundary one when v
 * is on a boundary, GEOM_INVALID_INDEX for an isolated vertex; f_he[f] is one
 * halfedge of f. *_del[i] is 1 for an element marked deleted (0 otherwise);
 * n_del_* count them.
 *
 * Hot loops in other mesh sources may read these arrays directly (read-only
 * unless the function owns the mesh change); always keep every array of a
 * domain in sync through geom__mesh_resize().
 *
 * Channels: channels[0] is "position" (VERTEX, 3 comps). For VERTEX, FACE and
 * EDGE channels `data` holds capacity*ncomp doubles (values beyond the count
 * are scratch); for CORNER channels `data` holds pool_cap*ncomp doubles of
 * which `pool` values are in use, and `corner` holds cap_h pool indices (one
 * per halfedge; GEOM_INVALID_INDEX on boundary halfedges and unset corners).
 *
 * Soup origin (set by geom_mesh_build, NULL otherwise):
 *   vertex_origin[v]: the input vertex of output vertex v;
 *   face_origin[f]:   the input face of output face f;
 *   face_flipped[f]:  1 if build reversed face f. Input corner k (0-based, in
 *                     the input face's order) of an n-gon then sits at the
 *                     halfedge reached from f_he[f] by k next-steps when not
 *                     flipped, by (n - k) % n next-steps when flipped; see
 *                     geom__mesh_input_corner_he().
 * Edits keep the maps in sync: added vertices/faces get GEOM_INVALID_INDEX
 * (flag 0), compaction compacts them, triangulation copies the face's origin
 * to its triangles and drops face_flipped (input corners no longer exist).
 * Example (OBJ reader): after geom_mesh_build, for output face f with input
 * face fi = face_origin[f] and its k-th `v/vt/vn` corner, store the pool
 * index at corner[geom__mesh_input_corner_he(m, f, k)]; vertex splitting
 * never touches corner slots, so detached/split vertices keep their data.
 *
 * Compaction remaps polylines (dropping deleted vertices) but leaves tag
 * integers alone (they are file-level indices).
 *
 * Sources: mesh.c (storage, lifetime, navigation, add/delete, compaction),
 * channels.c, circulate.c, meta.c (tags, groups, mtllibs, polylines),
 * build.c, soup.c (to_soup, origin maps, input-corner helpers), topology.c,
 * validate.c, triangulate.c.
 */
#ifndef GEOM_SRC_MESH_INTERNAL_H
#define GEOM_SRC_MESH_INTERNAL_H

#include "core/internal.h"
#include "geom/mesh.h"

#include <string.h>

#define GEOM_MESH__NAME_MAX 64 /* channel name buffer, including the NUL */

typedef struct geom__mesh_channel {
    char name[GEOM_MESH__NAME_MAX];
    geom_mesh_domain domain;
    size_t ncomp;
    double *data;     /* see above */
    size_t data_cap;  /* values allocated in data (not doubles) */
    size_t pool;      /* CORNER: values in use */
    uint32_t *corner; /* CORNER: cap_h entries; NULL for other domains */
} geom__mesh_channel;

typedef struct geom__mesh_tag {
    char *name;
    size_t nint, nfloat, nstring;
    int64_t *ints;
    double *floats;
    char **strings;
} geom__mesh_tag;

typedef struct geom__mesh_group {
    char *s[4]; /* group, object, material, smoothing (NULL when unset) */
} geom__mesh_group;

struct geom_mesh {
    geom_allocator alloc; /* copy of the user's allocator (zeroed = libc) */

    size_t nv, nh, nf;          /* element counts (edges = nh / 2) */
    size_t cap_v, cap_h, cap_f; /* capacities (cap_h even) */
    size_t n_del_v, n_del_e, n_del_f;

    uint32_t *he_next, *he_prev, *he_vertex, *he_face;
    uint32_t *v_he, *f_he;
    uint8_t *v_del, *e_del, *f_del;

    geom__mesh_channel *channels;
    size_t n_channels, cap_channels;

    uint32_t *vertex_origin; /* cap_v entries or NULL */
    uint32_t *face_origin;   /* cap_f entries or NULL */
    uint8_t *face_flipped;   /* cap_f entries or NULL */
    uint32_t *face_group;    /* cap_f entries or NULL */

    geom__mesh_group *groups;
    size_t n_groups, cap_groups;
    geom__mesh_tag *tags;
    size_t n_tags, cap_tags;
    char **mtllibs;
    size_t n_mtllibs, cap_mtllibs;
    size_t n_polylines, cap_polylines;
    size_t *pl_off;          /* cap_polylines + 1 offsets into pl_verts */
    uint32_t *pl_verts;
    size_t pl_nverts, cap_pl_verts;
};

/* ----------------------------------------------------------- accessors */

static inline uint32_t geom__mesh_opp(uint32_t h) { return h ^ 1u; }
static inline uint32_t geom__mesh_next(const geom_mesh *m, uint32_t h) { return m->he_next[h]; }
static inline uint32_t geom__mesh_prev(const geom_mesh *m, uint32_t h) { return m->he_prev[h]; }
static inline uint32_t geom__mesh_to(const geom_mesh *m, uint32_t h) { return m->he_vertex[h]; }
static inline uint32_t geom__mesh_from(const geom_mesh *m, uint32_t h)
{
    return m->he_vertex[h ^ 1u];
}
static inline bool geom__mesh_is_bnd(const geom_mesh *m, uint32_t h)
{
    return m->he_face[h] == GEOM_INVALID_INDEX;
}
/* Counter-clockwise rotation of an outgoing halfedge around its origin. */
static inline uint32_t geom__mesh_ccw(const geom_mesh *m, uint32_t h)
{
    return m->he_prev[h] ^ 1u;
}
/* Clockwise rotation of an outgoing halfedge around its origin. */
static inline uint32_t geom__mesh_cw(const geom_mesh *m, uint32_t h)
{
    return m->he_next[h ^ 1u];
}
/* Positions (channel 0): 3 doubles per vertex. */
static inline double *geom__mesh_pos(const geom_mesh *m) { return m->channels[0].data; }
static inline void geom__mesh_link(geom_mesh *m, uint32_t a, uint32_t b)
{
    m->he_next[a] = b;
    m->he_prev[b] = a;
}

/* ------------------------------------------------ growable-array helper */

/* Grow *p to hold at least `need` elements: core's geom__grow (core/grow.c);
 * the name stays for the mesh sources until the lead's prefix sed. */

/* Duplicate a string (NULL gives NULL in *out); GEOM_ERR_NOMEM. */
geom_status geom__mesh_strdup(const geom_allocator *a, const char *s, char **out);
/* Free a string made by geom__mesh_strdup (NULL allowed). */
void geom__mesh_strfree(const geom_allocator *a, char *s);

/* -------------------------------------------- element storage (mesh.c) */

/* Make room for nv vertices, nh halfedges and nf faces in every array of
 * every domain (channels, corner index arrays, origin maps, groups). Counts
 * are unchanged. GEOM_ERR_NOMEM / GEOM_ERR_LIMIT (nothing changed then). */
geom_status geom__mesh_reserve(geom_mesh *m, size_t nv, size_t nh, size_t nf);

/* Make every domain's capacity nonzero (so optional arrays and channels
 * can be allocated at the domain capacity). */
geom_status geom__mesh_reserve_some(geom_mesh *m);

/* Set the element counts (nh even), reserving as needed. New elements are
 * initialised: links GEOM_INVALID_INDEX, not deleted, channel values zero,
 * corner indices, origins and face groups GEOM_INVALID_INDEX, flipped 0.
 * Shrinking just drops the tail (no link fix-up). This is what keeps the
 * channels in sync with the element counts
 * (geom__mesh_channel_resize_all is the same function). */
geom_status geom__mesh_resize(geom_mesh *m, size_t nv, size_t nh, size_t nf);
#define geom__mesh_channel_resize_all geom__mesh_resize

/* Free every element, channel except position (emptied), origin maps and
 * metadata; capacities are kept for position only. */
void geom__mesh_clear_all(geom_mesh *m);
/* dst (cleared first, its allocator kept) becomes a deep copy of src: what
 * geom_mesh_clone copies. On failure dst is left cleared. */
geom_status geom__mesh_copy(geom_mesh *dst, const geom_mesh *src);
/* dst takes src's contents and src is destroyed: in O(1) by swapping when
 * both use the same allocator, else by geom__mesh_copy (a failure leaves
 * dst cleared; src is destroyed either way). For a result made as a new
 * mesh that belongs in a caller's mesh, without a soup-and-rebuild. */
geom_status geom__mesh_take(geom_mesh *dst, geom_mesh *src);
/* Drop groups (and the face group map), tags, mtllibs and polylines. */
void geom__mesh_drop_meta(geom_mesh *m);

/* Set v_he[v] to a boundary outgoing halfedge if v has one (pmp's
 * adjust_outgoing_halfedge). v must not be isolated. */
void geom__mesh_adjust_outgoing(geom_mesh *m, uint32_t v);

/* Allocate the vertex_origin / face_origin / face_flipped arrays at the
 * current capacity (filled with GEOM_INVALID_INDEX / 0) if absent. */
geom_status geom__mesh_ensure_origins(geom_mesh *m);
/* Storage for a mesh being built from a soup (geom_mesh_build's paths):
 * clears m, reserves exactly nv, nh, nf elements with the origin maps and
 * sets the counts. Only the deleted flags and face_flipped are initialised
 * (zero): the builder writes he_next, he_prev, he_vertex, he_face, v_he,
 * f_he, vertex_origin, face_origin and the positions itself, every entry. */
geom_status geom__mesh_build_storage(geom_mesh *m, size_t nv, size_t nh, size_t nf);
/* Outgoing halfedges (the first interior one in index order; the boundary
 * one where there is one) and the boundary cycles' links, for a mesh whose
 * face cycles (he_next, he_face, he_vertex) are set. With cnt (nv entries of
 * scratch) also the one-fan check: rotating from v_he visits every outgoing
 * halfedge, and *isolated (if non-NULL) counts vertices with none. Returns 1
 * when a vertex has two boundary gaps or (with cnt) more than one fan, for
 * the caller to repair or decline; else 0 (build_fast.c). */
int geom__mesh_link_vertices(geom_mesh *m, uint32_t *cnt, size_t *isolated);
/* Give a new, empty mesh (no vertex storage yet, no channel but positions)
 * the block xyz (3*nv doubles, allocated with m's allocator, exactly that
 * size) as its positions' storage, with room for nv vertices; m owns it
 * from then on. geom_mesh_build(m, nv, xyz, ...) then builds on it without
 * a copy. GEOM_ERR_INVALID_ARG when m is not such a mesh, GEOM_ERR_NOMEM. */
geom_status geom__mesh_adopt_positions(geom_mesh *m, double *xyz, size_t nv);

/* ------------------------------------------------------ channels.c */

/* Free channel i's storage (does not remove it from the list). */
void geom__mesh_channel_free(geom_mesh *m, geom__mesh_channel *c);
/* Grow a CORNER channel's pool capacity to at least n values (no zeroing). */
geom_status geom__mesh_pool_reserve(geom_mesh *m, geom__mesh_channel *c, size_t n);

/* Store a computed corner channel `name` of ncomp components: a channel of
 * that name with another width is replaced, the pool becomes the npool
 * values at `values` (npool*ncomp doubles) and the per-halfedge indices
 * the m->nh at `indices`; *id (NULL allowed) gets the channel. The last
 * step of geom_mesh_corner_normals and geom_mesh_tangents. */
geom_status geom__mesh_corner_channel_store(geom_mesh *m, const char *name, size_t ncomp,
                                            const double *values, size_t npool,
                                            const uint32_t *indices, uint32_t *id);

/* ---------------------------------------------------------- meta.c */

void geom__mesh_meta_free(geom_mesh *m);
/* Deep-copy tags, groups, mtllibs and polylines of src into dst (which has
 * none). GEOM_ERR_NOMEM (dst may then hold part of them; free with
 * geom__mesh_meta_free). */
geom_status geom__mesh_meta_copy(geom_mesh *dst, const geom_mesh *src);
/* Rewrite polyline vertex indices through vmap (old -> new or
 * GEOM_INVALID_INDEX: such entries are dropped). */
void geom__mesh_polylines_remap(geom_mesh *m, const uint32_t *vmap);

/* ------------------------------------------------------- soup helpers */

/* After geom_mesh_build: the halfedge of output face f holding input corner
 * k (k < face valence), i.e. the halfedge pointing to the face's k-th input
 * vertex; its corner-channel slot is that input corner's. Uses face_flipped
 * (treated as not flipped when absent). GEOM_INVALID_INDEX for a bad f/k.
 * O(k). */
uint32_t geom__mesh_input_corner_he(const geom_mesh *m, uint32_t f, uint32_t k);
/* All corners of output face f in input order: out[k] =
 * geom__mesh_input_corner_he(m, f, k) for k < valence (out must hold the
 * face valence). Returns the valence (0 for a bad f). O(valence). */
size_t geom__mesh_input_corners(const geom_mesh *m, uint32_t f, uint32_t *out);

/* geom_mesh_face_normal of a triangle whose cycle from its f_he visits the
 * positions v[0], v[1], v[2], bit for bit (normals.c). */
geom_status geom__mesh_triangle_normal(const double *const v[3], double out[3]);

/* Normalise v in place, scaling by its largest component first so nothing
 * overflows or underflows: (0,0,0) and 0 for a zero or non-finite vector, 1
 * otherwise (normals.c, tangents.c, clip.c). */
static inline int geom__mesh_normalize3(double v[3])
{
    double mx = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(mx > 0.0) || !isfinite(mx)) {
        v[0] = v[1] = v[2] = 0.0;
        return 0;
    }
    double x = v[0] / mx, y = v[1] / mx, z = v[2] / mx;
    double l = sqrt(x * x + y * y + z * z);
    v[0] = x / l;
    v[1] = y / l;
    v[2] = z / l;
    return 1;
}

#endif
