/* STL: ASCII and binary reading (binary recognised by its size, 84 + 50 *
 * the triangle count, not by the "solid" prefix), welding corners by exact
 * position; ASCII and binary writing of the triangulated mesh. */
#include "meshio/meshio_internal.h"
#include "mesh/mesh_internal.h"

#include <stdio.h>

/* --------------------------------------------------------------- reading */

typedef struct stl_weld {
    geom__hindex hash;
} stl_weld;

/* The vertex at exactly p (after -0 -> +0), added if new. */
static geom_status stl_vertex(mio_ctx *c, mio_soup *s, stl_weld *w, const double in[3],
                              uint32_t *out, uint64_t loc, int loc_is_offset)
{
    double p[3] = {in[0] + 0.0, in[1] + 0.0, in[2] + 0.0}; /* -0 + 0 = +0 */
    uint64_t bits[3];
    memcpy(bits, p, sizeof bits);
    uint64_t hv = geom__hash_mix(geom__hash_mix(geom__hash_mix(0, bits[0]), bits[1]),
                                   bits[2]);
    size_t it = 0;
    uint32_t cand;
    while ((cand = geom__hindex_next(&w->hash, hv, &it)) != UINT32_MAX) {
        const double *q = s->pos.p + 3 * (size_t)cand;
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
            *out = cand;
            c->stats->welded_corners++;
            return GEOM_OK;
        }
    }
    size_t nv = mio_soup_nv(s);
    if (nv >= c->max_elements)
        return geom__meshio_check_count(c, nv + 1, "vertices", loc, loc_is_offset);
    if (geom__hindex_reserve(&w->hash, c->alloc, nv + 1) != GEOM_OK ||
        MIO_RESERVE(c->alloc, s->pos, 3) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    it = 0;
    while (geom__hindex_next(&w->hash, hv, &it) != UINT32_MAX) {
    }
    geom__hindex_insert_at(&w->hash, hv, it, (uint32_t)nv);
    memcpy(s->pos.p + s->pos.n, p, sizeof p);
    s->pos.n += 3;
    *out = (uint32_t)nv;
    return GEOM_OK;
}

static uint32_t rd_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static geom_status stl_binary(mio_ctx *c, mio_soup *s, stl_weld *w)
{
    const unsigned char *d = c->data;
    size_t n = rd_u32(d + 80);
    c->stats->binary = 1;
    s->loc_is_offset = 1;
    if (n > c->max_elements)
        return geom__meshio_err_off(c, GEOM_ERR_LIMIT, 80,
                                    "%zu triangles exceed the limit of %zu elements", n,
                                    c->max_elements);
    if (MIO_RESERVE(c->alloc, s->fsize, n) != GEOM_OK ||
        MIO_RESERVE(c->alloc, s->fidx, 3 * n) != GEOM_OK ||
        geom__hindex_reserve(&w->hash, c->alloc, n / 2 + 4) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    for (size_t t = 0; t < n; t++) {
        size_t off = 84 + 50 * t;
        for (int k = 0; k < 3; k++) {
            double p[3];
            for (int j = 0; j < 3; j++) {
                size_t fo = off + 12 + 12 * (size_t)k + 4 * (size_t)j;
                uint32_t u = rd_u32(d + fo);
                float f;
                memcpy(&f, &u, 4);
                if (!isfinite(f))
                    return geom__meshio_err_off(c, GEOM_ERR_PARSE, fo,
                                                "triangle %zu: non-finite coordinate", t + 1);
                p[j] = (double)f;
            }
            uint32_t v;
            geom_status st = stl_vertex(c, s, w, p, &v, off, 1);
            if (st != GEOM_OK)
                return st;
            s->fidx.p[s->fidx.n++] = v;
        }
        s->fsize.p[s->fsize.n++] = 3;
        if (mio_floc_push(c->alloc, s, off) != GEOM_OK)
            return GEOM_ERR_NOMEM;
    }
    return GEOM_OK;
}

typedef struct stl_text {
    mio_ctx *c;
    mio_cursor cur;
    const char *t;
    size_t tl, line, col;
} stl_text;

static int stl_next(stl_text *x)
{
    return geom__meshio_cursor_next(&x->cur, &x->t, &x->tl, &x->line, &x->col);
}

static geom_status stl_expect(stl_text *x, const char *word)
{
    if (!stl_next(x))
        return geom__meshio_err_line(x->c, GEOM_ERR_PARSE, x->line, x->col,
                                     "unexpected end of file: expected '%s'", word);
    if (!geom__meshio_tok_ieq(x->t, x->tl, word))
        return geom__meshio_err_line(x->c, GEOM_ERR_PARSE, x->line, x->col,
                                     "expected '%s', found '%.*s'", word,
                                     (int)(x->tl > 40 ? 40 : x->tl), x->t);
    return GEOM_OK;
}

static geom_status stl_numbers(stl_text *x, double *v, int n)
{
    for (int i = 0; i < n; i++) {
        if (!stl_next(x))
            return geom__meshio_err_line(x->c, GEOM_ERR_PARSE, x->line, x->col,
                                         "unexpected end of file: expected a number");
        int rc = geom__meshio_parse_double(x->t, x->tl, &v[i]);
        if (rc != 0)
            return geom__meshio_err_line(x->c, GEOM_ERR_PARSE, x->line, x->col,
                                         rc == -2 ? "number '%.*s' is out of range"
                                                  : "expected a number, found '%.*s'",
                                         (int)(x->tl > 40 ? 40 : x->tl), x->t);
    }
    return GEOM_OK;
}

static void stl_skip_line(stl_text *x)
{
    const char *nl = memchr(x->cur.data + x->cur.pos, '\n', x->cur.size - x->cur.pos);
    x->cur.pos = nl ? (size_t)(nl - x->cur.data) : x->cur.size;
}

static geom_status stl_ascii(mio_ctx *c, mio_soup *s, stl_weld *w)
{
    stl_text x;
    memset(&x, 0, sizeof x);
    x.c = c;
    x.cur.data = (const char *)c->data;
    x.cur.size = c->size;
    x.cur.line = 1;
    s->loc_is_offset = 0;
    geom_status st;
    if ((st = stl_expect(&x, "solid")) != GEOM_OK)
        return st;
    stl_skip_line(&x);
    for (;;) {
        if (!stl_next(&x))
            return geom__meshio_err_line(c, GEOM_ERR_PARSE, x.line, x.col,
                                         "unexpected end of file: expected 'facet' or "
                                         "'endsolid'");
        if (geom__meshio_tok_ieq(x.t, x.tl, "endsolid")) {
            stl_skip_line(&x);
            if (!stl_next(&x))
                return GEOM_OK;
            if (!geom__meshio_tok_ieq(x.t, x.tl, "solid"))
                return geom__meshio_err_line(c, GEOM_ERR_PARSE, x.line, x.col,
                                             "expected 'solid' or the end of the file after "
                                             "'endsolid', found '%.*s'",
                                             (int)(x.tl > 40 ? 40 : x.tl), x.t);
            stl_skip_line(&x);
            continue;
        }
        if (!geom__meshio_tok_ieq(x.t, x.tl, "facet"))
            return geom__meshio_err_line(c, GEOM_ERR_PARSE, x.line, x.col,
                                         "expected 'facet' or 'endsolid', found '%.*s'",
                                         (int)(x.tl > 40 ? 40 : x.tl), x.t);
        size_t fline = x.line;
        double nrm[3];
        if ((st = stl_expect(&x, "normal")) != GEOM_OK || (st = stl_numbers(&x, nrm, 3)) != GEOM_OK ||
            (st = stl_expect(&x, "outer")) != GEOM_OK || (st = stl_expect(&x, "loop")) != GEOM_OK)
            return st;
        uint32_t n = 0;
        for (;;) {
            if (!stl_next(&x))
                return geom__meshio_err_line(c, GEOM_ERR_PARSE, x.line, x.col,
                                             "unexpected end of file: expected 'vertex' or "
                                             "'endloop'");
            if (geom__meshio_tok_ieq(x.t, x.tl, "endloop"))
                break;
            if (!geom__meshio_tok_ieq(x.t, x.tl, "vertex"))
                return geom__meshio_err_line(c, GEOM_ERR_PARSE, x.line, x.col,
                                             "expected 'vertex' or 'endloop', found '%.*s'",
                                             (int)(x.tl > 40 ? 40 : x.tl), x.t);
            double p[3];
            if ((st = stl_numbers(&x, p, 3)) != GEOM_OK)
                return st;
            uint32_t v;
            if (s->fidx.n >= c->max_elements)
                return geom__meshio_check_count(c, s->fidx.n + 1, "face corners", x.line, 0);
            if ((st = stl_vertex(c, s, w, p, &v, x.line, 0)) != GEOM_OK)
                return st;
            if (MIO_PUSH(c->alloc, s->fidx, v) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            n++;
        }
        if ((st = stl_expect(&x, "endfacet")) != GEOM_OK)
            return st;
        if (s->fsize.n >= c->max_elements)
            return geom__meshio_check_count(c, s->fsize.n + 1, "faces", fline, 0);
        if (MIO_PUSH(c->alloc, s->fsize, n) != GEOM_OK ||
            mio_floc_push(c->alloc, s, (uint64_t)fline) != GEOM_OK)
            return GEOM_ERR_NOMEM;
    }
}

static int starts_with_solid(const unsigned char *d, size_t size)
{
    size_t i = 0;
    while (i < size && mio_is_space((char)d[i]))
        i++;
    return size - i >= 5 && geom__meshio_tok_ieq((const char *)d + i, 5, "solid") &&
           (size - i == 5 || mio_is_space((char)d[i + 5]));
}

geom_status geom__meshio_read_stl(mio_ctx *c, mio_soup *s)
{
    stl_weld w;
    memset(&w, 0, sizeof w);
    geom_status st;
    const unsigned char *d = c->data;
    size_t size = c->size;
    uint64_t expect = size >= 84 ? 84 + 50 * (uint64_t)rd_u32(d + 80) : 0;
    int solid = starts_with_solid(d, size);
    int has_nul = size > 0 && memchr(d, 0, size < 1024 ? size : 1024) != NULL;
    if (size >= 84 && expect == size)
        st = stl_binary(c, s, &w);
    else if (solid && !has_nul)
        st = stl_ascii(c, s, &w);
    else if (size < 84)
        st = geom__meshio_err_off(c, GEOM_ERR_PARSE, size,
                                  "not an ASCII STL (no 'solid') and shorter than the 84-byte "
                                  "header of a binary STL");
    else
        st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 80,
                                  "binary STL header declares %lu triangles, which need %llu "
                                  "bytes, but the file has %zu bytes",
                                  (unsigned long)rd_u32(d + 80), (unsigned long long)expect,
                                  size);
    if (st == GEOM_ERR_NOMEM && c->diag && c->diag->status != GEOM_ERR_NOMEM)
        geom__meshio_err_line(c, st, 0, 0, "out of memory");
    geom__hindex_free(&w.hash, c->alloc);
    return st;
}

/* --------------------------------------------------------------- writing */

/* One facet: the normal, then the corners v[0..2]. */
static void stl_facet(mio_sink *k, int ascii, const double *const v[3], const double n[3])
{
    if (ascii) {
        geom__meshio_puts(k, "  facet normal");
        for (int j = 0; j < 3; j++) {
            mio_putc(k, ' ');
            geom__meshio_put_double(k, n[j]);
        }
        geom__meshio_puts(k, "\n    outer loop\n");
        for (int i = 0; i < 3; i++) {
            geom__meshio_puts(k, "      vertex");
            for (int j = 0; j < 3; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, v[i][j]);
            }
            mio_putc(k, '\n');
        }
        geom__meshio_puts(k, "    endloop\n  endfacet\n");
        return;
    }
    for (int j = 0; j < 3; j++)
        geom__meshio_put_f32(k, (float)n[j], 0);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double x = v[i][j];
            if (!isfinite(x) || fabs(x) > 3.4028234663852886e38)
                geom__meshio_sink_fail(k, GEOM_ERR_INVALID_ARG,
                                       "coordinate %g cannot be stored as a float", x);
            geom__meshio_put_f32(k, (float)x, 0);
        }
    geom__meshio_put_u16(k, 0, 0);
}

/*
 * Faces with more than three vertices are triangulated one at a time
 * (geom_polygon_triangulate, as geom_mesh_triangulate does) instead of on a
 * copy of the mesh, in the order geom_mesh_triangulate gives: each face's
 * first triangle in the face's place, the other triangles after the last
 * face, face by face; each triangle starts where the triangulated face's
 * cycle would, and its normal is that face's geom_mesh_face_normal.
 */
geom_status geom__meshio_write_stl(const geom_mesh *m, const geom_meshio_write_options *opt,
                                   mio_sink *k)
{
    int ascii = opt->encoding == GEOM_MESHIO_ENCODING_ASCII;
    if (geom__meshio_check_finite(m, k) != GEOM_OK)
        return k->status;
    size_t nf = geom_mesh_n_faces(m), ntri = 0, nmax = 3;
    for (size_t f = 0; f < nf; f++) {
        if (geom_mesh_face_is_deleted(m, (uint32_t)f))
            continue;
        size_t n = geom_mesh_face_valence(m, (uint32_t)f);
        ntri += n - 2;
        nmax = n > nmax ? n : nmax;
    }
    if (!ascii && ntri > UINT32_MAX)
        return geom__meshio_sink_fail(k, GEOM_ERR_LIMIT, "more than 2^32-1 triangles");
    const geom_allocator *al = opt->alloc;
    double *pts = NULL;
    uint32_t *ub = NULL;
    if (nmax > 3) {
        pts = geom__alloc(al, 3 * nmax * sizeof(double));
        ub = geom__alloc(al, 4 * nmax * sizeof(uint32_t));
        if (!pts || !ub) {
            geom__free(al, pts, 3 * nmax * sizeof(double));
            geom__free(al, ub, 4 * nmax * sizeof(uint32_t));
            return geom__meshio_sink_fail(k, GEOM_ERR_NOMEM, "out of memory");
        }
    }
    uint32_t *tris = ub, *vid = ub ? ub + 3 * nmax : NULL;
    const double *pos = geom_mesh_cpositions(m);
    if (ascii) {
        geom__meshio_puts(k, "solid libgeom\n");
    } else {
        char header[80];
        memset(header, ' ', sizeof header);
        static const char text[] = "binary STL written by libgeom";
        memcpy(header, text, sizeof text - 1);
        geom__meshio_put(k, header, sizeof header);
        geom__meshio_put_u32(k, (uint32_t)ntri, 0);
    }
    /* pass 0: triangles and each polygon's first triangle; pass 1: the
     * polygons' other triangles */
    for (int pass = 0; pass < 2; pass++)
        for (size_t f = 0; f < nf && k->status == GEOM_OK; f++) {
            if (geom_mesh_face_is_deleted(m, (uint32_t)f))
                continue;
            size_t n = geom_mesh_face_valence(m, (uint32_t)f);
            uint32_t h = geom_mesh_face_he(m, (uint32_t)f);
            const double *v[3];
            double nrm[3];
            if (n == 3) {
                if (pass)
                    continue;
                for (int i = 0; i < 3; i++, h = geom_mesh_he_next(m, h))
                    v[i] = pos + 3 * (size_t)geom_mesh_he_vertex(m, h);
                if (geom_mesh_face_normal(m, (uint32_t)f, nrm) != GEOM_OK)
                    nrm[0] = nrm[1] = nrm[2] = 0.0;
                stl_facet(k, ascii, v, nrm);
                continue;
            }
            for (size_t c = 0; c < n; c++, h = geom_mesh_he_next(m, h)) {
                vid[c] = geom_mesh_he_vertex(m, h);
                memcpy(pts + 3 * c, pos + 3 * (size_t)vid[c], 3 * sizeof(double));
            }
            (void)geom_polygon_triangulate(n, pts, tris); /* degenerate: a fan is written */
            for (size_t t = pass ? 1 : 0; t < (pass ? n - 2 : 1); t++) {
                /* the triangulated face's cycle starts at its second corner */
                for (int i = 0; i < 3; i++)
                    v[i] = pos + 3 * (size_t)vid[tris[3 * t + (size_t)((i + 1) % 3)]];
                if (geom__mesh_triangle_normal(v, nrm) != GEOM_OK)
                    nrm[0] = nrm[1] = nrm[2] = 0.0;
                stl_facet(k, ascii, v, nrm);
            }
        }
    if (ascii)
        geom__meshio_puts(k, "endsolid libgeom\n");
    geom__free(al, pts, 3 * nmax * sizeof(double));
    geom__free(al, ub, 4 * nmax * sizeof(uint32_t));
    return k->status;
}
