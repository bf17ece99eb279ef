/*
 * The public refiner: options and OpenSubdiv-style tags, the base level
 * from a geom_mesh or a soup, uniform refinement and queries.
 */
#include "subdiv_internal.h"

const geom_allocator *sd_alloc(const geom_subdiv_refiner *r)
{
    return r->has_alloc ? &r->alloc : NULL;
}

geom_status geom_subdiv_scheme_from_name(const char *name, geom_subdiv_scheme *out)
{
    static const struct {
        const char *n;
        geom_subdiv_scheme s;
    } names[] = {{"catmull-clark", GEOM_SUBDIV_CATMULL_CLARK},
                 {"catmark", GEOM_SUBDIV_CATMULL_CLARK},
                 {"loop", GEOM_SUBDIV_LOOP},
                 {"bilinear", GEOM_SUBDIV_BILINEAR},
                 {"butterfly", GEOM_SUBDIV_BUTTERFLY},
                 {"sqrt3", GEOM_SUBDIV_SQRT3}};
    if (!name || !out)
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (strcmp(name, names[i].n) == 0) {
            *out = names[i].s;
            return GEOM_OK;
        }
    }
    return GEOM_ERR_INVALID_ARG;
}

const char *geom_subdiv_scheme_name(geom_subdiv_scheme s)
{
    switch (s) {
    case GEOM_SUBDIV_CATMULL_CLARK:
        return "catmull-clark";
    case GEOM_SUBDIV_LOOP:
        return "loop";
    case GEOM_SUBDIV_BILINEAR:
        return "bilinear";
    case GEOM_SUBDIV_BUTTERFLY:
        return "butterfly";
    case GEOM_SUBDIV_SQRT3:
        return "sqrt3";
    }
    return "unknown";
}

/* ------------------------------------------------------------ options */

static int is_tri_scheme(int s)
{
    return s == GEOM_SUBDIV_LOOP || s == GEOM_SUBDIV_BUTTERFLY || s == GEOM_SUBDIV_SQRT3;
}

/* Option tags of the mesh into *eff (fields still DEFAULT only). */
static geom_status read_option_tags(const geom_mesh *m, geom_subdiv_options *eff, int *propagate,
                                    geom_diag *diag)
{
    size_t nt = geom_mesh_tag_count(m);
    geom_subdiv_boundary b = GEOM_SUBDIV_BOUNDARY_DEFAULT;
    geom_subdiv_fvar fv = GEOM_SUBDIV_FVAR_DEFAULT;
    geom_subdiv_crease cm = GEOM_SUBDIV_CREASE_DEFAULT;
    geom_subdiv_triangles tr = GEOM_SUBDIV_TRIANGLES_DEFAULT;
    for (size_t i = 0; i < nt; i++) {
        geom_mesh_tag t;
        if (geom_mesh_tag_get(m, i, &t) != GEOM_OK || !t.name)
            continue;
        if (strcmp(t.name, "interpolateboundary") == 0) {
            if (t.nint < 1 || t.ints[0] < 0 || t.ints[0] > 2)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "tag %zu: interpolateboundary needs 0, 1 or 2", i);
            b = t.ints[0] == 0   ? GEOM_SUBDIV_BOUNDARY_NONE
                : t.ints[0] == 1 ? GEOM_SUBDIV_BOUNDARY_EDGE_AND_CORNER
                                 : GEOM_SUBDIV_BOUNDARY_EDGE_ONLY;
        } else if (strcmp(t.name, "facevaryinginterpolateboundary") == 0) {
            if (t.nint < 1 || t.ints[0] < 0 || t.ints[0] > 5)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "tag %zu: facevaryinginterpolateboundary needs 0..5", i);
            fv = (geom_subdiv_fvar)(t.ints[0] + 1);
        } else if (strcmp(t.name, "facevaryingpropagatecorners") == 0) {
            if (t.nint >= 1 && t.ints[0] != 0)
                *propagate = 1;
        } else if (strcmp(t.name, "creasemethod") == 0) {
            if (t.nstring < 1 || (strcmp(t.strings[0], "normal") && strcmp(t.strings[0], "chaikin")))
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "tag %zu: creasemethod needs normal or chaikin", i);
            cm = strcmp(t.strings[0], "chaikin") == 0 ? GEOM_SUBDIV_CREASE_CHAIKIN
                                                      : GEOM_SUBDIV_CREASE_UNIFORM;
        } else if (strcmp(t.name, "smoothtriangles") == 0) {
            if (t.nstring < 1 || (strcmp(t.strings[0], "catmark") && strcmp(t.strings[0], "smooth")))
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "tag %zu: smoothtriangles needs catmark or smooth", i);
            tr = strcmp(t.strings[0], "smooth") == 0 ? GEOM_SUBDIV_TRIANGLES_SMOOTH
                                                     : GEOM_SUBDIV_TRIANGLES_CATMARK;
        }
    }
    if (eff->boundary == GEOM_SUBDIV_BOUNDARY_DEFAULT)
        eff->boundary = b;
    if (eff->fvar_boundary == GEOM_SUBDIV_FVAR_DEFAULT)
        eff->fvar_boundary = fv;
    if (eff->crease_method == GEOM_SUBDIV_CREASE_DEFAULT)
        eff->crease_method = cm;
    if (eff->triangles == GEOM_SUBDIV_TRIANGLES_DEFAULT)
        eff->triangles = tr;
    return GEOM_OK;
}

static geom_status resolve_options(geom_subdiv_options *eff, int propagate, sd_opts *o)
{
    if ((unsigned)eff->scheme > GEOM_SUBDIV_SQRT3 ||
        (unsigned)eff->boundary > GEOM_SUBDIV_BOUNDARY_EDGE_AND_CORNER ||
        (unsigned)eff->fvar_boundary > GEOM_SUBDIV_FVAR_ALL ||
        (unsigned)eff->crease_method > GEOM_SUBDIV_CREASE_CHAIKIN ||
        (unsigned)eff->triangles > GEOM_SUBDIV_TRIANGLES_SMOOTH)
        return GEOM_ERR_INVALID_ARG;
    if (eff->boundary == GEOM_SUBDIV_BOUNDARY_DEFAULT)
        eff->boundary = GEOM_SUBDIV_BOUNDARY_EDGE_ONLY;
    if (eff->fvar_boundary == GEOM_SUBDIV_FVAR_DEFAULT)
        eff->fvar_boundary = GEOM_SUBDIV_FVAR_ALL;
    if (propagate && eff->fvar_boundary == GEOM_SUBDIV_FVAR_CORNERS_PLUS1)
        eff->fvar_boundary = GEOM_SUBDIV_FVAR_CORNERS_PLUS2;
    if (eff->crease_method == GEOM_SUBDIV_CREASE_DEFAULT)
        eff->crease_method = GEOM_SUBDIV_CREASE_UNIFORM;
    if (eff->triangles == GEOM_SUBDIV_TRIANGLES_DEFAULT)
        eff->triangles = GEOM_SUBDIV_TRIANGLES_CATMARK;
    o->scheme = (int)eff->scheme;
    o->vtx = eff->boundary == GEOM_SUBDIV_BOUNDARY_NONE        ? SD_VTX_NONE
             : eff->boundary == GEOM_SUBDIV_BOUNDARY_EDGE_ONLY ? SD_VTX_EDGE_ONLY
                                                               : SD_VTX_EDGE_AND_CORNER;
    o->fvar = (int)eff->fvar_boundary - 1;
    if (eff->scheme == GEOM_SUBDIV_BUTTERFLY || eff->scheme == GEOM_SUBDIV_SQRT3)
        o->fvar = SD_FVAR_ALL; /* linear face-varying data for the extra schemes */
    o->chaikin = eff->crease_method == GEOM_SUBDIV_CREASE_CHAIKIN;
    o->smooth_tri = eff->scheme == GEOM_SUBDIV_CATMULL_CLARK &&
                    eff->triangles == GEOM_SUBDIV_TRIANGLES_SMOOTH;
    return GEOM_OK;
}

static float clamp_sharp(double s)
{
    if (!(s > 0.0))
        return 0.0f;
    if (s > 1e30)
        return 1e30f;
    return (float)s;
}

static geom_status set_crease(sd_level *l, uint32_t a, uint32_t b, double s, geom_diag *diag,
                              const char *what, size_t i)
{
    uint32_t e = sd_find_edge(l, a, b);
    if (e == SD_INVALID)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "%s %zu: no edge between vertices %u and %u", what, i, a, b);
    l->esharp[e] = clamp_sharp(s);
    return GEOM_OK;
}

/* Sharpness tags of the mesh. face_of_input maps an input face index to
 * the first level-0 face made from it (SD_INVALID if none), with
 * next_same chaining further ones; both may be NULL (identity). */
static geom_status read_sharp_tags(const geom_mesh *m, sd_level *l, const uint32_t *face_of_input,
                                   size_t n_input_faces, geom_diag *diag)
{
    size_t nt = geom_mesh_tag_count(m);
    for (size_t i = 0; i < nt; i++) {
        geom_mesh_tag t;
        if (geom_mesh_tag_get(m, i, &t) != GEOM_OK || !t.name)
            continue;
        if (strcmp(t.name, "crease") == 0) {
            size_t npairs = t.nint / 2;
            if (t.nfloat == 0 || (t.nfloat != 1 && t.nfloat != npairs))
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "tag %zu: crease needs 1 sharpness or one per edge", i);
            for (size_t j = 0; j < npairs; j++) {
                int64_t a = t.ints[2 * j], b = t.ints[2 * j + 1];
                if (a < 0 || b < 0 || a >= (int64_t)l->nv || b >= (int64_t)l->nv)
                    return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                         "tag %zu: crease vertex out of range", i);
                geom_status st = set_crease(l, (uint32_t)a, (uint32_t)b,
                                            t.floats[t.nfloat > 1 ? j : 0], diag, "crease tag", i);
                if (st != GEOM_OK)
                    return st;
            }
        } else if (strcmp(t.name, "corner") == 0) {
            if (t.nfloat == 0 || (t.nfloat != 1 && t.nfloat != t.nint))
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "tag %zu: corner needs 1 sharpness or one per vertex", i);
            for (size_t j = 0; j < t.nint; j++) {
                int64_t v = t.ints[j];
                if (v < 0 || v >= (int64_t)l->nv)
                    return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                         "tag %zu: corner vertex %lld out of range", i,
                                         (long long)v);
                l->vsharp[v] = clamp_sharp(t.floats[t.nfloat > 1 ? j : 0]);
            }
        } else if (strcmp(t.name, "hole") == 0) {
            for (size_t j = 0; j < t.nint; j++) {
                int64_t f = t.ints[j];
                if (f < 0 || (size_t)f >= n_input_faces)
                    return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                         "tag %zu: hole face %lld out of range", i, (long long)f);
                uint32_t lf = face_of_input ? face_of_input[f] : (uint32_t)f;
                if (lf != SD_INVALID && lf < l->nf)
                    l->fhole[lf] = 1;
            }
        }
    }
    return GEOM_OK;
}

static geom_status apply_option_arrays(const geom_subdiv_options *opt, sd_level *l, geom_diag *diag)
{
    if (!opt)
        return GEOM_OK;
    if ((opt->n_creases && (!opt->crease_verts || !opt->crease_sharpness)) ||
        (opt->n_corners && (!opt->corner_verts || !opt->corner_sharpness)) ||
        (opt->n_holes && !opt->hole_faces))
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < opt->n_creases; i++) {
        geom_status st = set_crease(l, opt->crease_verts[2 * i], opt->crease_verts[2 * i + 1],
                                    opt->crease_sharpness[i], diag, "crease", i);
        if (st != GEOM_OK)
            return st;
    }
    for (size_t i = 0; i < opt->n_corners; i++) {
        if (opt->corner_verts[i] >= l->nv)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "corner %zu: vertex %u out of range", i, opt->corner_verts[i]);
        l->vsharp[opt->corner_verts[i]] = clamp_sharp(opt->corner_sharpness[i]);
    }
    for (size_t i = 0; i < opt->n_holes; i++) {
        if (opt->hole_faces[i] >= l->nf)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "hole %zu: face %u out of range", i, opt->hole_faces[i]);
        l->fhole[opt->hole_faces[i]] = 1;
    }
    return GEOM_OK;
}

static geom_subdiv_refiner *new_refiner(const geom_subdiv_options *opt)
{
    const geom_allocator *a = opt ? opt->alloc : NULL;
    geom_subdiv_refiner *r = geom__alloc(a, sizeof *r);
    if (!r)
        return NULL;
    memset(r, 0, sizeof *r);
    if (a) {
        r->alloc = *a;
        r->has_alloc = 1;
    }
    return r;
}

/* Keep the effective options in r->opt without their arrays (creases,
 * corners, holes: the caller's, applied at creation and not kept). */
static void keep_options(geom_subdiv_refiner *r, geom_subdiv_options eff)
{
    eff.n_creases = eff.n_corners = eff.n_holes = 0;
    eff.crease_verts = eff.corner_verts = eff.hole_faces = NULL;
    eff.crease_sharpness = eff.corner_sharpness = NULL;
    r->opt = eff;
}

static geom_status finish_create(geom_subdiv_refiner *r, sd_level *l0, geom_diag *diag)
{
    if (is_tri_scheme(r->o.scheme)) {
        for (uint32_t f = 0; f < l0->nf; f++) {
            if (l0->fv_off[f + 1] - l0->fv_off[f] != 3)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "%s subdivision needs triangles: face %u has %u vertices",
                                     geom_subdiv_scheme_name((geom_subdiv_scheme)r->o.scheme), f,
                                     l0->fv_off[f + 1] - l0->fv_off[f]);
        }
    }
    sd_level0_tags(l0, &r->o, &r->has_holes);
    sd_level_count(l0);
    return GEOM_OK;
}

void geom_subdiv_refiner_destroy(geom_subdiv_refiner *r)
{
    if (!r)
        return;
    const geom_allocator *a = sd_alloc(r);
    for (int i = 0; i < r->nlevels; i++)
        sd_level_free(a, r->lv[i]);
    geom_allocator copy = r->alloc;
    geom__free(r->has_alloc ? &copy : NULL, r, sizeof *r);
}

geom_status geom_subdiv_refiner_create_soup(size_t nverts, size_t nfaces,
                                            const uint32_t *face_sizes, const uint32_t *indices,
                                            const geom_subdiv_options *opt,
                                            geom_subdiv_refiner **out, geom_diag *diag)
{
    if (!out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_subdiv_refiner_create_soup: invalid argument");
    *out = NULL;
    if (nfaces == 0 || !face_sizes || !indices)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "no faces to subdivide");
    if (nverts > INT32_MAX || nfaces > INT32_MAX)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0, "geom_subdiv_refiner_create_soup: too large for 32-bit indices");
    geom_subdiv_refiner *r = new_refiner(opt);
    if (!r)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_subdiv_refiner_create_soup: out of memory");
    geom_subdiv_options eff;
    memset(&eff, 0, sizeof eff);
    if (opt)
        eff = *opt;
    geom_status st = resolve_options(&eff, 0, &r->o);
    sd_level *l0 = NULL;
    if (st == GEOM_OK)
        st = sd_level0_build(sd_alloc(r), (uint32_t)nverts, (uint32_t)nfaces, face_sizes, indices,
                             &l0, diag);
    if (st == GEOM_OK) {
        r->lv[0] = l0;
        r->nlevels = 1;
        st = apply_option_arrays(opt, l0, diag);
    }
    if (st == GEOM_OK)
        st = finish_create(r, l0, diag);
    keep_options(r, eff);
    if (st != GEOM_OK) {
        geom_subdiv_refiner_destroy(r);
        return st;
    }
    *out = r;
    return GEOM_OK;
}

/* The base-level soup of a mesh: live faces in order, vertices merged
 * through the build origin. corner_he receives, per face-vertex, the
 * halfedge whose corner it is. */
static geom_status mesh_soup(const geom_mesh *m, const geom_allocator *a, uint32_t *nv_out,
                             uint32_t *nf_out, size_t *total_out, uint32_t **sizes, uint32_t **idx,
                             uint32_t **corner_he, uint32_t **face_mesh)
{
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    const uint32_t *origin = geom_mesh_vertex_origin(m);
    uint32_t nv0 = (uint32_t)nv;
    if (origin) {
        uint32_t mx = 0;
        for (size_t v = 0; v < nv; v++) {
            if (origin[v] >= nv) {
                origin = NULL;
                break;
            }
            if (origin[v] > mx)
                mx = origin[v];
        }
        if (origin)
            nv0 = nv ? mx + 1 : 0;
    }
    size_t live = 0, total = 0;
    for (size_t f = 0; f < nf; f++) {
        if (geom_mesh_face_is_deleted(m, (uint32_t)f))
            continue;
        live++;
        total += geom_mesh_face_valence(m, (uint32_t)f);
    }
    if (total > INT32_MAX)
        return GEOM_ERR_LIMIT;
    *total_out = total;
    *nf_out = (uint32_t)live;
    *sizes = sd_calloc(a, live, sizeof(uint32_t));
    *idx = sd_calloc(a, total, sizeof(uint32_t));
    *corner_he = sd_calloc(a, total, sizeof(uint32_t));
    *face_mesh = sd_calloc(a, live, sizeof(uint32_t));
    if (!*sizes || !*idx || !*corner_he || !*face_mesh)
        return GEOM_ERR_NOMEM;
    size_t k = 0, fi = 0;
    for (size_t f = 0; f < nf; f++) {
        if (geom_mesh_face_is_deleted(m, (uint32_t)f))
            continue;
        uint32_t h0 = geom_mesh_face_he(m, (uint32_t)f), h = h0, n = 0;
        do {
            uint32_t v = geom_mesh_he_vertex(m, h);
            (*idx)[k] = origin ? origin[v] : v;
            (*corner_he)[k] = h;
            k++;
            n++;
            h = geom_mesh_he_next(m, h);
        } while (h != h0 && h != GEOM_INVALID_INDEX && n <= total);
        (*sizes)[fi] = n;
        (*face_mesh)[fi] = (uint32_t)f;
        fi++;
    }
    *nv_out = nv0;
    *nf_out = (uint32_t)live;
    return GEOM_OK;
}

geom_status geom_subdiv_refiner_create(const geom_mesh *m, const geom_subdiv_options *opt,
                                       geom_subdiv_refiner **out, geom_diag *diag)
{
    if (!out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_subdiv_refiner_create: invalid argument");
    *out = NULL;
    if (!m)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "geom_subdiv_refiner_create: invalid argument");
    geom_subdiv_refiner *r = new_refiner(opt);
    if (!r)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "geom_subdiv_refiner_create: out of memory");
    const geom_allocator *a = sd_alloc(r);
    geom_subdiv_options eff;
    memset(&eff, 0, sizeof eff);
    if (opt)
        eff = *opt;
    int propagate = 0;
    geom_status st = GEOM_OK;
    if (!eff.ignore_tags)
        st = read_option_tags(m, &eff, &propagate, diag);
    if (st == GEOM_OK)
        st = resolve_options(&eff, propagate, &r->o);
    uint32_t nv0 = 0, nf0 = 0, *sizes = NULL, *idx = NULL, *corner_he = NULL, *face_mesh = NULL;
    size_t total_fv = 0;
    uint32_t *face_of_input = NULL;
    size_t n_input = 0;
    sd_level *l0 = NULL;
    if (st == GEOM_OK)
        st = mesh_soup(m, a, &nv0, &nf0, &total_fv, &sizes, &idx, &corner_he, &face_mesh);
    if (st == GEOM_OK && nf0 == 0)
        st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "the mesh has no faces");
    if (st == GEOM_OK)
        st = sd_level0_build(a, nv0, nf0, sizes, idx, &l0, diag);
    if (st == GEOM_OK) {
        r->lv[0] = l0;
        r->nlevels = 1;
        /* input face -> level-0 face, for hole tags */
        const uint32_t *forig = geom_mesh_face_origin(m);
        n_input = geom_mesh_n_faces(m);
        if (forig)
            for (uint32_t f = 0; f < nf0; f++)
                if (forig[face_mesh[f]] + 1 > n_input)
                    n_input = forig[face_mesh[f]] + 1;
        face_of_input = sd_calloc(a, n_input, sizeof(uint32_t));
        if (!face_of_input) {
            st = GEOM_ERR_NOMEM;
        } else {
            for (size_t i = 0; i < n_input; i++)
                face_of_input[i] = SD_INVALID;
            for (uint32_t f = nf0; f-- > 0;) {
                uint32_t in = forig ? forig[face_mesh[f]] : face_mesh[f];
                if (in < n_input)
                    face_of_input[in] = f;
            }
        }
    }
    if (st == GEOM_OK && !eff.ignore_tags)
        st = read_sharp_tags(m, l0, face_of_input, n_input, diag);
    if (st == GEOM_OK)
        st = apply_option_arrays(opt, l0, diag);
    if (st == GEOM_OK)
        st = finish_create(r, l0, diag);
    /* Face-varying channels from the CORNER channels. */
    if (st == GEOM_OK) {
        size_t nch = geom_mesh_channel_count(m);
        uint32_t total = l0->fv_off[l0->nf];
        uint32_t *vals = sd_calloc(a, total, sizeof(uint32_t));
        if (!vals)
            st = GEOM_ERR_NOMEM;
        for (size_t ch = 0; st == GEOM_OK && ch < nch; ch++) {
            if (geom_mesh_channel_domain(m, (uint32_t)ch) != GEOM_MESH_DOMAIN_CORNER)
                continue;
            const uint32_t *ci = geom_mesh_corner_cindices(m, (uint32_t)ch);
            size_t pool = geom_mesh_channel_size(m, (uint32_t)ch);
            int ok = ci != NULL && pool > 0 && pool < INT32_MAX && r->n_fvar_mesh < 64;
            for (uint32_t i = 0; ok && i < total; i++) {
                vals[i] = ci[corner_he[i]];
                ok = vals[i] < pool;
            }
            if (!ok)
                continue;
            st = geom_subdiv_refiner_add_fvar(r, pool, vals, NULL);
            if (st == GEOM_OK)
                r->fvar_mesh_channel[r->n_fvar_mesh++] = (uint32_t)ch;
        }
        sd_free(a, vals, total, sizeof(uint32_t));
    }
    sd_free(a, sizes, nf0, sizeof(uint32_t));
    sd_free(a, idx, total_fv, sizeof(uint32_t));
    sd_free(a, corner_he, total_fv, sizeof(uint32_t));
    sd_free(a, face_mesh, nf0, sizeof(uint32_t));
    sd_free(a, face_of_input, n_input, sizeof(uint32_t));
    keep_options(r, eff);
    if (st != GEOM_OK) {
        geom_subdiv_refiner_destroy(r);
        return st;
    }
    *out = r;
    return GEOM_OK;
}

geom_status geom_subdiv_refiner_add_fvar(geom_subdiv_refiner *r, size_t n_values,
                                         const uint32_t *face_values, uint32_t *channel)
{
    if (!r || !face_values || r->nlevels != 1 || n_values == 0 || n_values > INT32_MAX)
        return GEOM_ERR_INVALID_ARG;
    sd_level *l = r->lv[0];
    uint32_t total = l->fv_off[l->nf];
    for (uint32_t i = 0; i < total; i++)
        if (face_values[i] >= n_values)
            return GEOM_ERR_INVALID_ARG;
    const geom_allocator *a = sd_alloc(r);
    sd_fvar *nf = sd_calloc(a, (size_t)l->nfvar + 1, sizeof(sd_fvar));
    if (!nf)
        return GEOM_ERR_NOMEM;
    if (l->nfvar)
        memcpy(nf, l->fvar, (size_t)l->nfvar * sizeof(sd_fvar));
    geom_status st = sd_fvar_level0(a, l, &r->o, (uint32_t)n_values, face_values, &nf[l->nfvar]);
    if (st != GEOM_OK) {
        sd_fvar_free(a, l, &nf[l->nfvar]);
        sd_free(a, nf, (size_t)l->nfvar + 1, sizeof(sd_fvar));
        return st;
    }
    sd_free(a, l->fvar, l->nfvar, sizeof(sd_fvar));
    l->fvar = nf;
    if (channel)
        *channel = l->nfvar;
    l->nfvar++;
    return GEOM_OK;
}

size_t geom_subdiv_refiner_fvar_count(const geom_subdiv_refiner *r)
{
    return r && r->nlevels ? r->lv[0]->nfvar : 0;
}

uint32_t geom_subdiv_refiner_fvar_mesh_channel(const geom_subdiv_refiner *r, uint32_t channel)
{
    if (!r || channel >= r->n_fvar_mesh)
        return GEOM_INVALID_INDEX;
    return r->fvar_mesh_channel[channel];
}

geom_status geom_subdiv_refiner_refine(geom_subdiv_refiner *r, int levels)
{
    if (!r || levels < 0)
        return GEOM_ERR_INVALID_ARG;
    if (r->nlevels - 1 + levels > GEOM_SUBDIV_MAX_LEVEL)
        return GEOM_ERR_LIMIT;
    /* Predict the sizes first, so an impossible request allocates nothing. */
    {
        const sd_level *l = r->lv[r->nlevels - 1];
        uint64_t nv = l->nv, ne = l->ne, nf = l->nf, nfv = l->fv_off[l->nf];
        const uint64_t cap = (uint64_t)1 << 28;
        for (int i = 0; i < levels; i++) {
            uint64_t nv2, ne2, nf2, nfv2;
            if (sd_quad_split(&r->o)) {
                nf2 = nfv, nfv2 = 4 * nfv, ne2 = nfv + 2 * ne, nv2 = nf + ne + nv;
            } else if (r->o.scheme == GEOM_SUBDIV_SQRT3) {
                nf2 = 3 * nf, nfv2 = 9 * nf, ne2 = ne + 3 * nf, nv2 = nf + nv;
            } else {
                nf2 = 4 * nf, nfv2 = 12 * nf, ne2 = 3 * nf + 2 * ne, nv2 = ne + nv;
            }
            nv = nv2, ne = ne2, nf = nf2, nfv = nfv2;
            if (nfv > cap || nv > cap || ne > cap)
                return GEOM_ERR_LIMIT;
        }
    }
    const geom_allocator *a = sd_alloc(r);
    if (levels > 0 && r->lv[r->nlevels - 1]->complete != SD_REL_FULL) {
        geom_status st = sd_complete_level(a, &r->o, r->lv[r->nlevels - 2],
                                           r->lv[r->nlevels - 1], SD_REL_FULL);
        if (st != GEOM_OK)
            return st;
    }
    for (int i = 0; i < levels; i++) {
        sd_level *c = NULL;
        int rel = !r->opt.partial_last_level || i + 1 < levels ? SD_REL_FULL
                  : r->opt.partial_last_level == 2              ? SD_REL_LIMIT
                                                                : SD_REL_NONE;
        geom_status st = sd_refine_level(a, &r->o, r->lv[r->nlevels - 1], rel, &c);
        if (st != GEOM_OK)
            return st;
        sd_level_count(c);
        r->lv[r->nlevels++] = c;
    }
    return GEOM_OK;
}

int geom_subdiv_refiner_max_level(const geom_subdiv_refiner *r)
{
    return r ? r->nlevels - 1 : 0;
}

geom_subdiv_scheme geom_subdiv_refiner_scheme(const geom_subdiv_refiner *r)
{
    return r ? (geom_subdiv_scheme)r->o.scheme : GEOM_SUBDIV_CATMULL_CLARK;
}

geom_subdiv_options geom_subdiv_refiner_options(const geom_subdiv_refiner *r)
{
    geom_subdiv_options o;
    memset(&o, 0, sizeof o);
    if (r)
        o = r->opt;
    return o;
}

static const sd_level *get_level(const geom_subdiv_refiner *r, int level)
{
    if (!r || level < 0 || level >= r->nlevels)
        return NULL;
    return r->lv[level];
}

geom_status geom_subdiv_refiner_level_info(const geom_subdiv_refiner *r, int level,
                                           geom_subdiv_level_info *info)
{
    const sd_level *l = get_level(r, level);
    if (!l || !info)
        return GEOM_ERR_INVALID_ARG;
    memset(info, 0, sizeof *info);
    info->vertices = l->nv;
    info->edges = l->ne;
    info->faces = l->nf;
    info->face_vertices = l->fv_off[l->nf];
    info->max_valence = l->max_valence;
    info->sharp_edges = l->n_sharp_edges;
    info->hole_faces = l->n_hole_faces;
    return GEOM_OK;
}

geom_status geom_subdiv_refiner_faces(const geom_subdiv_refiner *r, int level,
                                      uint32_t *face_sizes, uint32_t *indices, uint8_t *is_hole)
{
    const sd_level *l = get_level(r, level);
    if (!l)
        return GEOM_ERR_INVALID_ARG;
    for (uint32_t f = 0; f < l->nf; f++) {
        if (face_sizes)
            face_sizes[f] = l->fv_off[f + 1] - l->fv_off[f];
        if (is_hole)
            is_hole[f] = l->fhole[f];
    }
    if (indices)
        memcpy(indices, l->fv, (size_t)l->fv_off[l->nf] * sizeof(uint32_t));
    return GEOM_OK;
}

const uint32_t *geom_subdiv_refiner_face_indices(const geom_subdiv_refiner *r, int level)
{
    const sd_level *l = get_level(r, level);
    return l ? l->fv : NULL;
}

geom_status geom_subdiv_refiner_edges(const geom_subdiv_refiner *r, int level, uint32_t *verts,
                                      float *sharpness)
{
    const sd_level *l = get_level(r, level);
    if (!l)
        return GEOM_ERR_INVALID_ARG;
    if (verts)
        memcpy(verts, l->ev, 2 * (size_t)l->ne * sizeof(uint32_t));
    if (sharpness)
        memcpy(sharpness, l->esharp, (size_t)l->ne * sizeof(float));
    return GEOM_OK;
}

geom_status geom_subdiv_refiner_vertex_rules(const geom_subdiv_refiner *r, int level,
                                             float *sharpness, uint8_t *rule)
{
    const sd_level *l = get_level(r, level);
    if (!l)
        return GEOM_ERR_INVALID_ARG;
    for (uint32_t v = 0; v < l->nv; v++) {
        if (sharpness)
            sharpness[v] = l->vsharp[v];
        if (rule)
            rule[v] = (uint8_t)(l->vtag[v] & SD_V_RULE);
    }
    return GEOM_OK;
}

uint32_t geom_subdiv_refiner_child_vertex(const geom_subdiv_refiner *r, int level,
                                          geom_subdiv_origin kind, uint32_t index)
{
    const sd_level *p = get_level(r, level);
    if (!p || level + 1 >= r->nlevels)
        return GEOM_INVALID_INDEX;
    int s = r->o.scheme;
    switch (kind) {
    case GEOM_SUBDIV_FROM_FACE:
        if (index >= p->nf)
            return GEOM_INVALID_INDEX;
        if (s == GEOM_SUBDIV_LOOP || s == GEOM_SUBDIV_BUTTERFLY)
            return GEOM_INVALID_INDEX;
        return index;
    case GEOM_SUBDIV_FROM_EDGE:
        if (index >= p->ne || s == GEOM_SUBDIV_SQRT3)
            return GEOM_INVALID_INDEX;
        return (s == GEOM_SUBDIV_LOOP || s == GEOM_SUBDIV_BUTTERFLY ? 0 : p->nf) + index;
    case GEOM_SUBDIV_FROM_VERTEX:
        if (index >= p->nv)
            return GEOM_INVALID_INDEX;
        if (s == GEOM_SUBDIV_SQRT3)
            return p->nf + index;
        return (s == GEOM_SUBDIV_LOOP || s == GEOM_SUBDIV_BUTTERFLY ? 0 : p->nf) + p->ne + index;
    }
    return GEOM_INVALID_INDEX;
}

geom_status geom_subdiv_refiner_vertex_parent(const geom_subdiv_refiner *r, int level, uint32_t v,
                                              geom_subdiv_origin *kind, uint32_t *parent)
{
    const sd_level *c = get_level(r, level);
    if (!c || level < 1 || v >= c->nv || !kind || !parent)
        return GEOM_ERR_INVALID_ARG;
    const sd_level *p = r->lv[level - 1];
    int s = r->o.scheme;
    if (c->vparent) {
        *kind = (geom_subdiv_origin)(c->vparent[v] >> 30);
        *parent = c->vparent[v] & 0x3fffffffu;
        return GEOM_OK;
    }
    uint32_t nfp = sd_quad_split(&r->o) ? p->nf : 0;
    (void)s;
    if (v < nfp) {
        *kind = GEOM_SUBDIV_FROM_FACE;
        *parent = v;
    } else if (v < nfp + p->ne) {
        *kind = GEOM_SUBDIV_FROM_EDGE;
        *parent = v - nfp;
    } else {
        *kind = GEOM_SUBDIV_FROM_VERTEX;
        *parent = v - nfp - p->ne;
    }
    return GEOM_OK;
}

uint32_t geom_subdiv_refiner_face_parent(const geom_subdiv_refiner *r, int level, uint32_t f)
{
    const sd_level *c = get_level(r, level);
    if (!c || level < 1 || f >= c->nf || !c->face_parent)
        return GEOM_INVALID_INDEX;
    return c->face_parent[f];
}

size_t geom_subdiv_fvar_size(const geom_subdiv_refiner *r, uint32_t channel, int level)
{
    const sd_level *l = get_level(r, level);
    if (!l || channel >= l->nfvar)
        return 0;
    return l->fvar[channel].nvalues;
}

geom_status geom_subdiv_fvar_face_values(const geom_subdiv_refiner *r, uint32_t channel, int level,
                                         uint32_t *face_values)
{
    const sd_level *l = get_level(r, level);
    if (!l || channel >= l->nfvar || !face_values)
        return GEOM_ERR_INVALID_ARG;
    memcpy(face_values, l->fvar[channel].fvals, (size_t)l->fv_off[l->nf] * sizeof(uint32_t));
    return GEOM_OK;
}
