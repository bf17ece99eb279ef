/*
 * Subdivision against OpenSubdiv 3 (Far): every regression shape of
 * tests/data/osd-shapes is read with the libgeom OBJ reader, refined to
 * levels 1..3 by geom_subdiv and by Far (through geom_validate_osd), and
 * compared vertex by vertex (both order child vertices face points, edge
 * points, vertex points, so matching is by index): topology identical
 * (face-vertices and edge numbering), edge and vertex sharpness (single
 * precision, exactly), vertex rules and hole faces identical, positions
 * within 1e-12 (relative to the shape's size), limit positions
 * (PrimvarRefiner::Limit) within 1e-12, limit tangents within 1e-12 of
 * their magnitude, and for shapes with texture coordinates the
 * face-varying values and their limits within 1e-12.
 *
 * The OBJ reader is run with keep_orientation (OpenSubdiv does not reorient
 * faces) and skip_invalid_faces: faces that use a vertex twice cannot be a
 * geom_mesh face, so the reader drops them and both sides refine the shape
 * without them; those shapes are also refined whole, through
 * geom_subdiv_refiner_create_soup, from their v/vt/f lines. Hierarchical
 * edits (vertexedit, edgeedit, faceedit: dropped by OpenSubdiv 3) are
 * ignored by both sides.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"
#include "geom/subdiv.h"
#include "geom_validate_osd.h"

#define LEVELS 3
#define TOL 1e-12

typedef struct soup {
    size_t nv, nf, nfv;
    double *pos;
    uint32_t *sizes, *idx;
    size_t nuv;
    double *uv;
    uint32_t *uvidx;
    size_t ntags;
    gv_osd_tag *tags;
} soup;

static void soup_free(soup *s)
{
    free(s->pos);
    free(s->sizes);
    free(s->idx);
    free(s->uv);
    free(s->uvidx);
    free(s->tags);
    memset(s, 0, sizeof *s);
}

/* The shape's soup as geom_mesh_build received it: vertices merged back
 * through the vertex origin, faces in order, tags as read. */
static void mesh_to_soup(const geom_mesh *m, soup *s)
{
    memset(s, 0, sizeof *s);
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    const uint32_t *org = geom_mesh_vertex_origin(m);
    assert_non_null(org);
    uint32_t mx = 0;
    for (size_t v = 0; v < nv; v++)
        if (org[v] > mx)
            mx = org[v];
    s->nv = mx + 1;
    s->pos = calloc(3 * s->nv, sizeof(double));
    const double *p = geom_mesh_cpositions(m);
    for (size_t v = 0; v < nv; v++)
        memcpy(s->pos + 3 * org[v], p + 3 * v, 3 * sizeof(double));
    s->nf = nf;
    s->sizes = calloc(nf, sizeof(uint32_t));
    size_t total = 0;
    for (size_t f = 0; f < nf; f++)
        total += geom_mesh_face_valence(m, (uint32_t)f);
    s->nfv = total;
    s->idx = calloc(total, sizeof(uint32_t));
    uint32_t uvch = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    const uint32_t *ci = uvch != GEOM_INVALID_INDEX ? geom_mesh_corner_cindices(m, uvch) : NULL;
    if (ci) {
        s->nuv = geom_mesh_channel_size(m, uvch);
        s->uv = malloc(2 * s->nuv * sizeof(double));
        memcpy(s->uv, geom_mesh_channel_cdata(m, uvch), 2 * s->nuv * sizeof(double));
        s->uvidx = calloc(total, sizeof(uint32_t));
    }
    size_t k = 0;
    for (size_t f = 0; f < nf; f++) {
        uint32_t h0 = geom_mesh_face_he(m, (uint32_t)f), h = h0, n = 0;
        do {
            s->idx[k] = org[geom_mesh_he_vertex(m, h)];
            if (ci)
                s->uvidx[k] = ci[h];
            k++;
            n++;
            h = geom_mesh_he_next(m, h);
        } while (h != h0);
        s->sizes[f] = n;
    }
    s->ntags = geom_mesh_tag_count(m);
    s->tags = calloc(s->ntags + 1, sizeof(gv_osd_tag));
    for (size_t i = 0; i < s->ntags; i++) {
        geom_mesh_tag t;
        assert_int_equal(geom_mesh_tag_get(m, i, &t), GEOM_OK);
        s->tags[i].name = t.name;
        s->tags[i].nint = t.nint;
        s->tags[i].nfloat = t.nfloat;
        s->tags[i].nstring = t.nstring;
        s->tags[i].ints = t.ints;
        s->tags[i].floats = t.floats;
        s->tags[i].strings = t.strings;
    }
}

static double max_abs_diff(const double *a, const double *b, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; i++) {
        double d = fabs(a[i] - b[i]);
        if (!(d <= m))
            m = isnan(d) ? INFINITY : d;
    }
    return m;
}

static double max_abs(const double *a, size_t n)
{
    double m = 0.0;
    for (size_t i = 0; i < n; i++)
        if (fabs(a[i]) > m)
            m = fabs(a[i]);
    return m;
}

typedef struct stats {
    int shapes, compared, with_uv, dropped_faces;
    double worst_pos, worst_limit, worst_tan, worst_fvar;
    int failures;
} stats;

static void check_shape(const char *dir, const char *file, stats *st)
{
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    geom_meshio_read_options ro;
    memset(&ro, 0, sizeof ro);
    ro.build.keep_orientation = 1;
    ro.build.skip_invalid_faces = 1;
    geom_mesh *m = NULL;
    geom_mesh_build_report rep;
    geom_diag diag;
    geom_status rs = geom_meshio_read(path, &ro, &m, &rep, &diag);
    if (rs != GEOM_OK) {
        print_message("%s: read failed: %s\n", file, diag.message);
        st->failures++;
        return;
    }
    st->shapes++;
    if (rep.invalid_faces)
        st->dropped_faces++;
    geom_subdiv_options opt;
    memset(&opt, 0, sizeof opt);
    int osd_scheme = GV_OSD_CATMARK;
    if (strncmp(file, "loop_", 5) == 0) {
        opt.scheme = GEOM_SUBDIV_LOOP;
        osd_scheme = GV_OSD_LOOP;
    } else if (strncmp(file, "bilinear_", 9) == 0) {
        opt.scheme = GEOM_SUBDIV_BILINEAR;
        osd_scheme = GV_OSD_BILINEAR;
    }
    soup s;
    mesh_to_soup(m, &s);
    gv_osd_shape shape;
    memset(&shape, 0, sizeof shape);
    shape.scheme = osd_scheme;
    shape.nverts = s.nv;
    shape.positions = s.pos;
    shape.nfaces = s.nf;
    shape.face_sizes = s.sizes;
    shape.indices = s.idx;
    shape.ntags = s.ntags;
    shape.tags = s.tags;
    if (s.uv) {
        shape.n_fvar_values = s.nuv;
        shape.fvar_values = s.uv;
        shape.fvar_indices = s.uvidx;
        st->with_uv++;
    }
    char err[256] = "";
    gv_osd *ref = gv_osd_create(&shape, LEVELS, err, sizeof err);
    geom_subdiv_refiner *r = NULL;
    geom_status cs = geom_subdiv_refiner_create(m, &opt, &r, &diag);
    if (!ref || cs != GEOM_OK) {
        print_message("%s: %s%s%s\n", file, ref ? "" : "Far failed: ", ref ? "" : err,
                      cs == GEOM_OK ? "" : diag.message);
        st->failures++;
        gv_osd_destroy(ref);
        geom_subdiv_refiner_destroy(r);
        soup_free(&s);
        geom_mesh_destroy(m);
        return;
    }
    assert_int_equal(geom_subdiv_refiner_refine(r, LEVELS), GEOM_OK);
    double scale = 1.0;
    for (size_t i = 0; i < 3 * s.nv; i++)
        if (fabs(s.pos[i]) > scale)
            scale = fabs(s.pos[i]);
    int ok = 1;
    double *pos[LEVELS + 1] = {NULL};
    pos[0] = malloc(3 * s.nv * sizeof(double));
    memcpy(pos[0], s.pos, 3 * s.nv * sizeof(double));
    double wpos = 0.0;
    for (int l = 1; l <= LEVELS && ok; l++) {
        geom_subdiv_level_info li;
        assert_int_equal(geom_subdiv_refiner_level_info(r, l, &li), GEOM_OK);
        if (li.vertices != gv_osd_vertices(ref, l) || li.faces != gv_osd_faces(ref, l) ||
            li.face_vertices != gv_osd_face_vertices(ref, l)) {
            print_message("%s: level %d counts differ: v %zu/%zu f %zu/%zu\n", file, l,
                          li.vertices, gv_osd_vertices(ref, l), li.faces, gv_osd_faces(ref, l));
            ok = 0;
            break;
        }
        uint32_t *a = malloc(li.face_vertices * sizeof(uint32_t));
        uint32_t *b = malloc(li.face_vertices * sizeof(uint32_t));
        geom_subdiv_refiner_faces(r, l, NULL, a, NULL);
        gv_osd_topology(ref, l, NULL, b);
        if (memcmp(a, b, li.face_vertices * sizeof(uint32_t)) != 0) {
            print_message("%s: level %d face-vertices differ\n", file, l);
            ok = 0;
        }
        free(a);
        free(b);
        /* edges (numbering), sharpness, rules and holes */
        if (li.edges != gv_osd_edges(ref, l)) {
            print_message("%s: level %d edge counts differ\n", file, l);
            ok = 0;
        } else {
            uint32_t *ea = malloc(2 * li.edges * sizeof(uint32_t)), *eb = malloc(2 * li.edges * sizeof(uint32_t));
            float *sa = malloc(li.edges * sizeof(float)), *sb = malloc(li.edges * sizeof(float));
            float *va = malloc(li.vertices * sizeof(float)), *vb = malloc(li.vertices * sizeof(float));
            uint8_t *ra = malloc(li.vertices), *rb = malloc(li.vertices);
            uint8_t *ha = malloc(li.faces), *hb = malloc(li.faces);
            geom_subdiv_refiner_edges(r, l, ea, sa);
            geom_subdiv_refiner_vertex_rules(r, l, va, ra);
            geom_subdiv_refiner_faces(r, l, NULL, NULL, ha);
            gv_osd_tags(ref, l, eb, sb, vb, rb, hb);
            if (memcmp(ea, eb, 2 * li.edges * sizeof(uint32_t)) ||
                memcmp(sa, sb, li.edges * sizeof(float)) ||
                memcmp(va, vb, li.vertices * sizeof(float)) || memcmp(ra, rb, li.vertices) ||
                memcmp(ha, hb, li.faces)) {
                print_message("%s: level %d edges, sharpness, rules or holes differ\n", file, l);
                ok = 0;
            }
            free(ea), free(eb), free(sa), free(sb), free(va), free(vb), free(ra), free(rb),
                free(ha), free(hb);
        }
        pos[l] = malloc(3 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_interpolate(r, l, 3, pos[l - 1], pos[l]), GEOM_OK);
        double d = max_abs_diff(pos[l], gv_osd_positions(ref, l), 3 * li.vertices) / scale;
        if (d > wpos)
            wpos = d;
        if (!(d <= TOL)) {
            size_t worst = 0;
            const double *q = gv_osd_positions(ref, l);
            for (size_t i = 0; i < 3 * li.vertices; i++)
                if (fabs(pos[l][i] - q[i]) > fabs(pos[l][worst] - q[worst]))
                    worst = i;
            print_message("%s: level %d positions differ by %.3g (vertex %zu)\n", file, l, d,
                          worst / 3);
            ok = 0;
        }
    }
    if (ok) {
        size_t nl = gv_osd_vertices(ref, LEVELS);
        double *lim = malloc(9 * nl * sizeof(double));
        assert_int_equal(geom_subdiv_limit(r, 3, pos[LEVELS], lim, lim + 3 * nl, lim + 6 * nl),
                         GEOM_OK);
        double d = max_abs_diff(lim, gv_osd_limit(ref), 3 * nl) / scale;
        if (d > st->worst_limit)
            st->worst_limit = d;
        if (!(d <= TOL)) {
            print_message("%s: limit positions differ by %.3g\n", file, d);
            ok = 0;
        }
        double dt = 0.0;
        if (gv_osd_limit_tan1(ref)) {
            double tscale =
                max_abs(gv_osd_limit_tan1(ref), 3 * nl) + max_abs(gv_osd_limit_tan2(ref), 3 * nl);
            dt = max_abs_diff(lim + 3 * nl, gv_osd_limit_tan1(ref), 3 * nl);
            double dt2 = max_abs_diff(lim + 6 * nl, gv_osd_limit_tan2(ref), 3 * nl);
            dt = (dt > dt2 ? dt : dt2) / (tscale > 0 ? tscale : 1.0);
        }
        if (dt > st->worst_tan)
            st->worst_tan = dt;
        if (!(dt <= TOL)) {
            print_message("%s: limit tangents differ by %.3g\n", file, dt);
            ok = 0;
        }
        free(lim);
    }
    if (ok && s.uv) {
        uint32_t uvch = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER), ch = 0;
        while (ch < geom_subdiv_refiner_fvar_count(r) &&
               geom_subdiv_refiner_fvar_mesh_channel(r, ch) != uvch)
            ch++;
        assert_true(ch < geom_subdiv_refiner_fvar_count(r));
        double *fv[LEVELS + 1] = {NULL};
        fv[0] = malloc(2 * s.nuv * sizeof(double));
        memcpy(fv[0], s.uv, 2 * s.nuv * sizeof(double));
        int fl = 0;
        for (int l = 1; l <= LEVELS; l++) {
            size_t n = geom_subdiv_fvar_size(r, ch, l);
            fv[l] = malloc((2 * n + 1) * sizeof(double));
            fl = l;
            if (n != gv_osd_fvar_values(ref, l)) {
                print_message("%s: level %d fvar values %zu, Far %zu\n", file, l, n,
                              gv_osd_fvar_values(ref, l));
                ok = 0;
                break;
            }
            assert_int_equal(geom_subdiv_interpolate_fvar(r, ch, l, 2, fv[l - 1], fv[l]), GEOM_OK);
            geom_subdiv_level_info li;
            geom_subdiv_refiner_level_info(r, l, &li);
            uint32_t *a = malloc(li.face_vertices * sizeof(uint32_t));
            uint32_t *b = malloc(li.face_vertices * sizeof(uint32_t));
            geom_subdiv_fvar_face_values(r, ch, l, a);
            gv_osd_fvar_indices(ref, l, b);
            int same = memcmp(a, b, li.face_vertices * sizeof(uint32_t)) == 0;
            free(a);
            free(b);
            if (!same) {
                print_message("%s: level %d fvar face values differ\n", file, l);
                ok = 0;
                break;
            }
            double d = max_abs_diff(fv[l], gv_osd_fvar(ref, l), 2 * n);
            if (d > st->worst_fvar)
                st->worst_fvar = d;
            if (!(d <= TOL)) {
                print_message("%s: level %d fvar values differ by %.3g\n", file, l, d);
                ok = 0;
                break;
            }
        }
        if (ok) {
            size_t n = geom_subdiv_fvar_size(r, ch, LEVELS);
            double *lim = malloc((2 * n + 1) * sizeof(double));
            assert_int_equal(geom_subdiv_limit_fvar(r, ch, 2, fv[LEVELS], lim), GEOM_OK);
            double d = max_abs_diff(lim, gv_osd_fvar_limit(ref), 2 * n);
            if (d > st->worst_fvar)
                st->worst_fvar = d;
            if (!(d <= TOL)) {
                print_message("%s: fvar limit differs by %.3g\n", file, d);
                ok = 0;
            }
            free(lim);
        }
        for (int l = 0; l <= fl; l++)
            free(fv[l]);
    }
    if (wpos > st->worst_pos)
        st->worst_pos = wpos;
    for (int l = 0; l <= LEVELS; l++)
        free(pos[l]);
    if (!ok)
        st->failures++;
    else
        st->compared++;
    gv_osd_destroy(ref);
    geom_subdiv_refiner_destroy(r);
    soup_free(&s);
    geom_mesh_destroy(m);
}

/* ----------------------------------------------------------------------
 * Faces that use a vertex twice: geom_mesh cannot hold them, so the shapes
 * that have them are also checked through geom_subdiv_refiner_create_soup
 * with the complete soup. The soup is taken from the file's v, vt and f
 * lines by the few lines below (test-only; everything else about these
 * shapes, tags included, comes from the libgeom reader).
 */
typedef struct rawobj {
    size_t nv, nvt, nf, nfv;
    double *v, *vt;
    uint32_t *sizes, *idx, *tidx;
} rawobj;

static int read_raw(const char *path, rawobj *o)
{
    memset(o, 0, sizeof *o);
    FILE *fp = fopen(path, "r");
    if (!fp)
        return 0;
    size_t cv = 1024, cvt = 1024, cf = 1024, cfv = 4096;
    o->v = malloc(3 * cv * sizeof(double));
    o->vt = malloc(2 * cvt * sizeof(double));
    o->sizes = malloc(cf * sizeof(uint32_t));
    o->idx = malloc(cfv * sizeof(uint32_t));
    o->tidx = malloc(cfv * sizeof(uint32_t));
    char line[4096];
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (o->nv == cv)
                o->v = realloc(o->v, 3 * (cv *= 2) * sizeof(double));
            sscanf(line + 2, "%lf %lf %lf", &o->v[3 * o->nv], &o->v[3 * o->nv + 1],
                   &o->v[3 * o->nv + 2]);
            o->nv++;
        } else if (line[0] == 'v' && line[1] == 't') {
            if (o->nvt == cvt)
                o->vt = realloc(o->vt, 2 * (cvt *= 2) * sizeof(double));
            sscanf(line + 3, "%lf %lf", &o->vt[2 * o->nvt], &o->vt[2 * o->nvt + 1]);
            o->nvt++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            if (o->nf == cf)
                o->sizes = realloc(o->sizes, (cf *= 2) * sizeof(uint32_t));
            uint32_t n = 0;
            for (char *t = strtok(line + 2, " \t\r\n"); t; t = strtok(NULL, " \t\r\n")) {
                if (o->nfv == cfv) {
                    cfv *= 2;
                    o->idx = realloc(o->idx, cfv * sizeof(uint32_t));
                    o->tidx = realloc(o->tidx, cfv * sizeof(uint32_t));
                }
                long a = strtol(t, &t, 10), b = 0;
                if (*t == '/')
                    b = strtol(t + 1, NULL, 10);
                o->idx[o->nfv] = (uint32_t)(a - 1);
                o->tidx[o->nfv] = b > 0 ? (uint32_t)(b - 1) : 0;
                o->nfv++;
                n++;
            }
            o->sizes[o->nf++] = n;
        }
    }
    fclose(fp);
    return 1;
}

static void free_raw(rawobj *o)
{
    free(o->v);
    free(o->vt);
    free(o->sizes);
    free(o->idx);
    free(o->tidx);
}

static void check_soup_shape(const char *dir, const char *file, int *checked)
{
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    geom_meshio_read_options ro;
    memset(&ro, 0, sizeof ro);
    ro.build.keep_orientation = 1;
    ro.build.skip_invalid_faces = 1;
    geom_mesh *m = NULL;
    geom_mesh_build_report rep;
    assert_int_equal(geom_meshio_read(path, &ro, &m, &rep, NULL), GEOM_OK);
    if (rep.invalid_faces == 0) {
        geom_mesh_destroy(m);
        return;
    }
    rawobj o;
    assert_true(read_raw(path, &o));
    assert_int_equal(o.nf, rep.invalid_faces + geom_mesh_n_faces(m));
    /* options and tags from the libgeom reader */
    geom_subdiv_options opt;
    memset(&opt, 0, sizeof opt);
    int osd_scheme = GV_OSD_CATMARK;
    if (strncmp(file, "loop_", 5) == 0) {
        opt.scheme = GEOM_SUBDIV_LOOP;
        osd_scheme = GV_OSD_LOOP;
    }
    size_t ntags = geom_mesh_tag_count(m);
    gv_osd_tag *tags = calloc(ntags + 1, sizeof *tags);
    for (size_t i = 0; i < ntags; i++) {
        geom_mesh_tag t;
        geom_mesh_tag_get(m, i, &t);
        tags[i].name = t.name;
        tags[i].nint = t.nint;
        tags[i].nfloat = t.nfloat;
        tags[i].nstring = t.nstring;
        tags[i].ints = t.ints;
        tags[i].floats = t.floats;
        tags[i].strings = t.strings;
        assert_true(strcmp(t.name, "crease") && strcmp(t.name, "corner") && strcmp(t.name, "hole"));
        if (strcmp(t.name, "interpolateboundary") == 0)
            opt.boundary = t.ints[0] == 0   ? GEOM_SUBDIV_BOUNDARY_NONE
                           : t.ints[0] == 1 ? GEOM_SUBDIV_BOUNDARY_EDGE_AND_CORNER
                                            : GEOM_SUBDIV_BOUNDARY_EDGE_ONLY;
    }
    gv_osd_shape shape;
    memset(&shape, 0, sizeof shape);
    shape.scheme = osd_scheme;
    shape.nverts = o.nv;
    shape.positions = o.v;
    shape.nfaces = o.nf;
    shape.face_sizes = o.sizes;
    shape.indices = o.idx;
    shape.ntags = ntags;
    shape.tags = tags;
    if (o.nvt) {
        shape.n_fvar_values = o.nvt;
        shape.fvar_values = o.vt;
        shape.fvar_indices = o.tidx;
    }
    gv_osd *ref = gv_osd_create(&shape, LEVELS, NULL, 0);
    assert_non_null(ref);
    geom_subdiv_refiner *r = NULL;
    assert_int_equal(geom_subdiv_refiner_create_soup(o.nv, o.nf, o.sizes, o.idx, &opt, &r, NULL),
                     GEOM_OK);
    if (o.nvt)
        assert_int_equal(geom_subdiv_refiner_add_fvar(r, o.nvt, o.tidx, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, LEVELS), GEOM_OK);
    double *p = malloc(3 * o.nv * sizeof(double)), *u = malloc(2 * (o.nvt + 1) * sizeof(double));
    memcpy(p, o.v, 3 * o.nv * sizeof(double));
    memcpy(u, o.vt, 2 * o.nvt * sizeof(double));
    for (int l = 1; l <= LEVELS; l++) {
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r, l, &li);
        assert_int_equal(li.vertices, gv_osd_vertices(ref, l));
        assert_int_equal(li.faces, gv_osd_faces(ref, l));
        double *q = malloc(3 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_interpolate(r, l, 3, p, q), GEOM_OK);
        free(p);
        p = q;
        double d = max_abs_diff(p, gv_osd_positions(ref, l), 3 * li.vertices);
        if (!(d <= TOL))
            print_message("%s (soup): level %d positions differ by %.3g\n", file, l, d);
        assert_true(d <= TOL);
        if (o.nvt) {
            size_t n = geom_subdiv_fvar_size(r, 0, l);
            assert_int_equal(n, gv_osd_fvar_values(ref, l));
            double *w = malloc((2 * n + 1) * sizeof(double));
            assert_int_equal(geom_subdiv_interpolate_fvar(r, 0, l, 2, u, w), GEOM_OK);
            free(u);
            u = w;
            assert_true(max_abs_diff(u, gv_osd_fvar(ref, l), 2 * n) <= TOL);
        }
    }
    size_t nl = gv_osd_vertices(ref, LEVELS);
    double *lim = malloc(3 * nl * sizeof(double));
    assert_int_equal(geom_subdiv_limit(r, 3, p, lim, NULL, NULL), GEOM_OK);
    assert_true(max_abs_diff(lim, gv_osd_limit(ref), 3 * nl) <= TOL);
    (*checked)++;
    free(lim);
    free(p);
    free(u);
    free(tags);
    free_raw(&o);
    gv_osd_destroy(ref);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static void test_all_shapes(void **state)
{
    (void)state;
    const char *shared = getenv("GEOM_SHARED_DATA");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/osd-shapes", shared ? shared : "tests/data");
    DIR *d = opendir(dir);
    assert_non_null(d);
    char *names[512];
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d)) && n < 512) {
        size_t len = strlen(e->d_name);
        if (len > 4 && strcmp(e->d_name + len - 4, ".obj") == 0)
            names[n++] = strdup(e->d_name);
    }
    closedir(d);
    qsort(names, n, sizeof names[0], cmp_str);
    stats st;
    memset(&st, 0, sizeof st);
    int soups = 0;
    for (size_t i = 0; i < n; i++) {
        check_shape(dir, names[i], &st);
        check_soup_shape(dir, names[i], &soups);
        free(names[i]);
    }
    print_message("osd-shapes with faces using a vertex twice, refined as whole soups: %d "
                  "agree with Far\n",
                  soups);
    assert_int_equal(soups, st.dropped_faces);
    print_message("osd-shapes: %d read, %d agree with Far (levels 1-%d, limit, tangents%s), "
                  "%d with uv, %d lost faces using a vertex twice; worst: positions %.3g, "
                  "limit %.3g, tangents %.3g, fvar %.3g\n",
                  st.shapes, st.compared, LEVELS, st.with_uv ? ", fvar" : "", st.with_uv,
                  st.dropped_faces, st.worst_pos, st.worst_limit, st.worst_tan, st.worst_fvar);
    assert_true(n >= 100);
    assert_int_equal(st.failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_shapes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
