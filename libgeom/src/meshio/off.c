/* Geomview OFF (ASCII): [ST][C][N]OFF headers, vertex normals, colours and
 * texture coordinates, per-face colours. */
#include "meshio/meshio_internal.h"

#include <stdio.h>

/* --------------------------------------------------------------- reading */

typedef struct off_reader {
    mio_ctx *c;
    mio_lines lines;
    const char *line;
    size_t len, pos;
    size_t lineno;
} off_reader;

/* Next line with a token (comments and blank lines skipped). 1, 0 at the
 * end, or a negative status. */
static int off_next_line(off_reader *r)
{
    for (;;) {
        int rc = geom__meshio_lines_next(&r->lines, r->c->alloc, &r->line, &r->len);
        if (rc <= 0)
            return rc;
        r->lineno = r->lines.lineno;
        r->pos = 0;
        size_t p = 0;
        const char *t = NULL;
        size_t tl = 0;
        if (mio_token(r->line, r->len, &p, 2, &t, &tl))
            return 1;
    }
}

/* Tokens of the current line (comment excluded) into toks (up to max). */
static size_t off_tokens(off_reader *r, const char **toks, size_t *lens, size_t max,
                         size_t *total)
{
    size_t n = 0, p = r->pos;
    const char *t = NULL;
    size_t tl = 0;
    *total = 0;
    while (mio_token(r->line, r->len, &p, 2, &t, &tl)) {
        if (n < max) {
            toks[n] = t;
            lens[n] = tl;
            n++;
        }
        (*total)++;
    }
    return n;
}

static size_t off_col(const off_reader *r, const char *t) { return (size_t)(t - r->line) + 1; }

static geom_status off_num(off_reader *r, const char *t, size_t tl, double *v)
{
    int rc = geom__meshio_parse_double(t, tl, v);
    if (rc == 0)
        return GEOM_OK;
    return geom__meshio_err_line(r->c, GEOM_ERR_PARSE, r->lineno, off_col(r, t),
                                 rc == -2 ? "number '%.*s' is out of range"
                                          : "expected a number, found '%.*s'",
                                 (int)(tl > 40 ? 40 : tl), t);
}

static int is_integer_token(const char *t, size_t tl)
{
    int64_t v;
    return geom__meshio_parse_int64(t, tl, &v) == 0;
}

/* Colour tokens: all integers -> 0..255 scale, else floats as they are. */
static geom_status off_color(off_reader *r, const char **t, const size_t *tl, size_t n,
                             double *out)
{
    int ints = 1;
    for (size_t i = 0; i < n; i++)
        ints &= is_integer_token(t[i], tl[i]);
    for (size_t i = 0; i < n; i++) {
        geom_status st = off_num(r, t[i], tl[i], &out[i]);
        if (st != GEOM_OK)
            return st;
        if (ints)
            out[i] /= 255.0;
    }
    return GEOM_OK;
}

static geom_status off_count(off_reader *r, const char *t, size_t tl, const char *what,
                             size_t *out)
{
    int64_t v;
    int rc = geom__meshio_parse_int64(t, tl, &v);
    if (rc != 0 || v < 0)
        return geom__meshio_err_line(r->c, GEOM_ERR_PARSE, r->lineno, off_col(r, t),
                                     "expected the number of %s, found '%.*s'", what,
                                     (int)(tl > 40 ? 40 : tl), t);
    if ((uint64_t)v > r->c->max_elements)
        return geom__meshio_err_line(r->c, GEOM_ERR_LIMIT, r->lineno, off_col(r, t),
                                     "%lld %s exceed the limit of %zu elements", (long long)v,
                                     what, r->c->max_elements);
    *out = (size_t)v;
    return GEOM_OK;
}

geom_status geom__meshio_read_off(mio_ctx *c, mio_soup *s)
{
    off_reader r;
    memset(&r, 0, sizeof r);
    r.c = c;
    geom__meshio_lines_init(&r.lines, c->data, c->size, 0);
    geom_status st = GEOM_OK;
    const char *toks[16];
    size_t lens[16], total;
    int has_st = 0, has_c = 0, has_n = 0;
    size_t nv = 0, nf = 0;
    mio_chan *cn = NULL, *cc = NULL, *cuv = NULL, *fc = NULL;
    size_t vcolor_n = 0, fcolor_n = 0;

    int rc = off_next_line(&r);
    if (rc < 0) {
        st = (geom_status)rc;
        goto done;
    }
    if (rc == 0) {
        st = geom__meshio_err_line(c, GEOM_ERR_PARSE, 1, 1, "expected 'OFF', found an empty file");
        goto done;
    }
    {
        const char *t = NULL;
        size_t tl = 0;
        mio_token(r.line, r.len, &r.pos, 2, &t, &tl);
        size_t i = 0;
        if (tl >= 2 && t[0] == 'S' && t[1] == 'T') {
            has_st = 1;
            i = 2;
        }
        if (i < tl && t[i] == 'C') {
            has_c = 1;
            i++;
        }
        if (i < tl && t[i] == 'N') {
            has_n = 1;
            i++;
        }
        if (i < tl && (t[i] == '4' || t[i] == 'n'))
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, i + 1,
                                       "4OFF and nOFF (other than 3 dimensions) are not supported");
        else if (tl - i != 3 || memcmp(t + i, "OFF", 3) != 0)
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, t),
                                       "expected '[ST][C][N]OFF', found '%.*s'",
                                       (int)(tl > 40 ? 40 : tl), t);
        if (st != GEOM_OK)
            goto done;
        /* the counts may follow on the same line */
        size_t n = off_tokens(&r, toks, lens, 16, &total);
        if (n > 0 && mio_tok_eq(toks[0], lens[0], "BINARY")) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[0]),
                                       "binary OFF is not supported");
            goto done;
        }
        if (n == 0) {
            rc = off_next_line(&r);
            if (rc <= 0) {
                st = rc < 0 ? (geom_status)rc
                            : geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno + 1, 1,
                                                    "expected the vertex, face and edge counts");
                goto done;
            }
            n = off_tokens(&r, toks, lens, 16, &total);
        }
        if (total < 2 || total > 3) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[0]),
                                       "expected 'nvertices nfaces [nedges]', found %zu values",
                                       total);
            goto done;
        }
        size_t ne;
        if ((st = off_count(&r, toks[0], lens[0], "vertices", &nv)) != GEOM_OK ||
            (st = off_count(&r, toks[1], lens[1], "faces", &nf)) != GEOM_OK ||
            (total == 3 && (st = off_count(&r, toks[2], lens[2], "edges", &ne)) != GEOM_OK))
            goto done;
        /* each vertex needs at least 2 bytes per number, each face 2 */
        size_t per_v = 2 * (3 + (has_n ? 3 : 0) + (has_c ? 3 : 0) + (has_st ? 2 : 0));
        uint64_t need = (uint64_t)nv * per_v + (uint64_t)nf * 2;
        size_t remaining = c->size - r.lines.pos;
        if (need > (uint64_t)remaining + 1) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[0]),
                                       "header declares %zu vertices and %zu faces, which need "
                                       "at least %llu bytes, but only %zu bytes follow",
                                       nv, nf, (unsigned long long)need, remaining);
            goto done;
        }
    }
    if (has_n && !(cn = geom__meshio_soup_chan(s, c->alloc, "normal", GEOM_MESH_DOMAIN_VERTEX, 3,
                                               NULL))) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    if (has_st && !(cuv = geom__meshio_soup_chan(s, c->alloc, "uv", GEOM_MESH_DOMAIN_VERTEX, 2,
                                                 NULL))) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    if (MIO_RESERVE(c->alloc, s->pos, 3 * nv) != GEOM_OK) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t v = 0; v < nv; v++) {
        rc = off_next_line(&r);
        if (rc <= 0) {
            st = rc < 0 ? (geom_status)rc
                        : geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lines.next_lineno, 1,
                                                "unexpected end of file: expected vertex %zu "
                                                "(0-based) of %zu",
                                                v, nv);
            goto done;
        }
        size_t n = off_tokens(&r, toks, lens, 16, &total);
        size_t fixed = 3 + (has_n ? 3 : 0) + (has_st ? 2 : 0);
        size_t ncol = total >= fixed ? total - fixed : 0;
        if (total != n || total < fixed || (has_c ? (ncol != 3 && ncol != 4) : ncol != 0)) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[0]),
                                       "expected vertex %zu (0-based) as 'x y z%s%s%s', found %zu values",
                                       v, has_n ? " nx ny nz" : "",
                                       has_c ? " r g b [a]" : "", has_st ? " s t" : "", total);
            goto done;
        }
        double x[16];
        size_t k = 0;
        for (; k < 3 + (has_n ? 3u : 0u); k++)
            if ((st = off_num(&r, toks[k], lens[k], &x[k])) != GEOM_OK)
                goto done;
        if (cn) {
            if (MIO_RESERVE(c->alloc, cn->val, 3) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            memcpy(cn->val.p + cn->val.n, x + 3, 3 * sizeof(double));
            cn->val.n += 3;
        }
        if (has_c) {
            double col[4];
            if ((st = off_color(&r, toks + k, lens + k, ncol, col)) != GEOM_OK)
                goto done;
            if (!cc) {
                vcolor_n = ncol;
                cc = geom__meshio_soup_chan(s, c->alloc, "color", GEOM_MESH_DOMAIN_VERTEX, ncol,
                                            NULL);
                if (!cc) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            } else if (ncol != vcolor_n) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[k]),
                                           "expected %zu colour components as in the first "
                                           "vertex, found %zu",
                                           vcolor_n, ncol);
                goto done;
            }
            if (MIO_RESERVE(c->alloc, cc->val, ncol) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            memcpy(cc->val.p + cc->val.n, col, ncol * sizeof(double));
            cc->val.n += ncol;
            k += ncol;
        }
        if (cuv) {
            double uv[2];
            if ((st = off_num(&r, toks[k], lens[k], &uv[0])) != GEOM_OK ||
                (st = off_num(&r, toks[k + 1], lens[k + 1], &uv[1])) != GEOM_OK)
                goto done;
            if (MIO_RESERVE(c->alloc, cuv->val, 2) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            cuv->val.p[cuv->val.n++] = uv[0];
            cuv->val.p[cuv->val.n++] = uv[1];
        }
        /* last, so that a colour channel created at this vertex has no
         * entry for it yet */
        s->pos.p[s->pos.n++] = x[0];
        s->pos.p[s->pos.n++] = x[1];
        s->pos.p[s->pos.n++] = x[2];
    }
    for (size_t f = 0; f < nf; f++) {
        rc = off_next_line(&r);
        if (rc <= 0) {
            st = rc < 0 ? (geom_status)rc
                        : geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lines.next_lineno, 1,
                                                "unexpected end of file: expected face %zu (0-based) of %zu",
                                                f, nf);
            goto done;
        }
        size_t p = 0;
        const char *t = NULL;
        size_t tl = 0;
        mio_token(r.line, r.len, &p, 2, &t, &tl);
        int64_t cnt;
        if (geom__meshio_parse_int64(t, tl, &cnt) != 0 || cnt < 0 ||
            (uint64_t)cnt > r.len) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, t),
                                       "expected the vertex count of face %zu (0-based), found '%.*s'",
                                       f, (int)(tl > 40 ? 40 : tl), t);
            goto done;
        }
        if (s->fidx.n + (size_t)cnt > c->max_elements) {
            st = geom__meshio_check_count(c, s->fidx.n + (size_t)cnt, "face corners", r.lineno, 0);
            goto done;
        }
        if (MIO_RESERVE(c->alloc, s->fidx, (size_t)cnt) != GEOM_OK) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        for (int64_t i = 0; i < cnt; i++) {
            if (!mio_token(r.line, r.len, &p, 2, &t, &tl)) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, r.len + 1,
                                           "face %zu (0-based) declares %lld vertices but the line has %lld",
                                           f, (long long)cnt, (long long)i);
                goto done;
            }
            int64_t ix;
            int prc = geom__meshio_parse_int64(t, tl, &ix);
            if (prc != 0 || ix < 0 || (uint64_t)ix >= nv) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, t),
                                           prc != 0 ? "expected a vertex index, found '%.*s'"
                                                    : "vertex index %.*s out of range",
                                           (int)(tl > 40 ? 40 : tl), t);
                if (prc == 0 && c->diag) {
                    size_t l = strlen(c->diag->message);
                    snprintf(c->diag->message + l, sizeof c->diag->message - l,
                             " (0-based; %zu vertices)", nv);
                }
                goto done;
            }
            s->fidx.p[s->fidx.n++] = (uint32_t)ix;
        }
        /* optional face colour */
        r.pos = p;
        size_t n = off_tokens(&r, toks, lens, 16, &total);
        if (total != 0) {
            if (total != n || (total != 3 && total != 4)) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[0]),
                                           "expected nothing or a colour 'r g b [a]' after the "
                                           "indices of face %zu (0-based), found %zu values",
                                           f, total);
                goto done;
            }
            double col[4];
            if ((st = off_color(&r, toks, lens, n, col)) != GEOM_OK)
                goto done;
            if (!fc) {
                static const double grey[4] = {0.666, 0.666, 0.666, 1.0};
                fcolor_n = n;
                fc = geom__meshio_soup_chan(s, c->alloc, "color", GEOM_MESH_DOMAIN_FACE, n, grey);
                if (!fc) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            } else if (n != fcolor_n) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, r.lineno, off_col(&r, toks[0]),
                                           "expected %zu colour components as in the first "
                                           "coloured face, found %zu",
                                           fcolor_n, n);
                goto done;
            }
            if (MIO_RESERVE(c->alloc, fc->val, n) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            memcpy(fc->val.p + fc->val.n, col, n * sizeof(double));
            fc->val.n += n;
        } else if (fc) {
            static const double grey[4] = {0.666, 0.666, 0.666, 1.0};
            if (MIO_RESERVE(c->alloc, fc->val, fcolor_n) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            memcpy(fc->val.p + fc->val.n, grey, fcolor_n * sizeof(double));
            fc->val.n += fcolor_n;
        }
        if (MIO_PUSH(c->alloc, s->fsize, (uint32_t)cnt) != GEOM_OK ||
            mio_floc_push(c->alloc, s, (uint64_t)r.lineno) != GEOM_OK) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
    }
done:
    if (st == GEOM_ERR_NOMEM && c->diag && c->diag->status != GEOM_ERR_NOMEM)
        geom__meshio_err_line(c, st, r.lineno, 0, "out of memory");
    geom__meshio_lines_free(&r.lines, c->alloc);
    s->loc_is_offset = 0;
    return st;
}

/* --------------------------------------------------------------- writing */

/* A colour component, always with a '.' or an exponent so that readers
 * take it for a float in [0,1], not an integer in [0,255]. */
static void put_color(mio_sink *k, double v)
{
    if (!isfinite(v)) {
        geom__meshio_put_double(k, v); /* fails the sink */
        return;
    }
    char buf[GEOM_DOUBLE_CHARS];
    size_t n = geom_format_double_digits(v, k->precision, buf);
    geom__meshio_put(k, buf, n);
    if (!memchr(buf, '.', n) && !memchr(buf, 'e', n))
        geom__meshio_puts(k, ".0");
}

geom_status geom__meshio_write_off(const geom_mesh *m, const geom_meshio_write_options *opt,
                                   mio_sink *k)
{
    mio_export e;
    geom_status st = geom__meshio_export_prepare(&e, m, opt, 0, k);
    if (st != GEOM_OK)
        return st;
    int has_n = mio_export_has(&e, MIO_ATTR_NORMAL), has_c = mio_export_has(&e, MIO_ATTR_COLOR);
    int has_st = mio_export_has(&e, MIO_ATTR_UV);
    if (has_st)
        geom__meshio_puts(k, "ST");
    if (has_c)
        mio_putc(k, 'C');
    if (has_n)
        mio_putc(k, 'N');
    geom__meshio_puts(k, "OFF\n# written by libgeom ");
    geom__meshio_puts(k, geom_version_string());
    mio_putc(k, '\n');
    geom__meshio_put_u64(k, e.nv);
    mio_putc(k, ' ');
    geom__meshio_put_u64(k, e.nf);
    geom__meshio_puts(k, " 0\n");
    const double *pos = geom_mesh_cpositions(m);
    for (size_t i = 0; i < e.nv && k->status == GEOM_OK; i++) {
        const double *p = pos + 3 * (size_t)e.vert[i];
        for (int j = 0; j < 3; j++) {
            if (j)
                mio_putc(k, ' ');
            geom__meshio_put_double(k, p[j]);
        }
        double val[4];
        if (has_n) {
            geom__meshio_export_value(&e, m, MIO_ATTR_NORMAL, i, val, 3);
            for (int j = 0; j < 3; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, val[j]);
            }
        }
        if (has_c) {
            val[3] = 1.0;
            geom__meshio_export_value(&e, m, MIO_ATTR_COLOR, i, val, 4);
            for (int j = 0; j < 4; j++) {
                mio_putc(k, ' ');
                put_color(k, val[j]);
            }
        }
        if (has_st) {
            geom__meshio_export_value(&e, m, MIO_ATTR_UV, i, val, 2);
            for (int j = 0; j < 2; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, val[j]);
            }
        }
        mio_putc(k, '\n');
    }
    size_t off = 0;
    for (size_t f = 0; f < e.nf && k->status == GEOM_OK; f++) {
        geom__meshio_put_u64(k, e.fsize[f]);
        for (uint32_t j = 0; j < e.fsize[f]; j++) {
            mio_putc(k, ' ');
            geom__meshio_put_u64(k, e.fidx[off + j]);
        }
        off += e.fsize[f];
        double col[4];
        size_t nc = geom__meshio_export_face_color(&e, m, f, col);
        for (size_t j = 0; nc && j < 4; j++) {
            mio_putc(k, ' ');
            put_color(k, col[j]);
        }
        mio_putc(k, '\n');
    }
    geom__meshio_export_free(&e);
    return k->status;
}
