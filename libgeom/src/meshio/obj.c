/* Wavefront OBJ: reading into a soup (v, vt, vn, f, l, g, o, s, usemtl,
 * mtllib, t) and writing a mesh back with the same structure. */
#include "core/numbers_internal.h"
#include "mesh/mesh_internal.h"
#include "meshio/meshio_internal.h"

#include <stdio.h>

/* --------------------------------------------------------------- reading */

typedef struct obj_state {
    mio_ctx *c;
    mio_soup *s;
    const char *line; /* current logical line */
    size_t len;
    size_t lineno;
    mio_chan *uv, *normal, *color, *weight;
    size_t nvt, nvn;
    /* group state: string offsets (MIO_NOSTR: unset) */
    size_t cur[4];
    int dirty;
    int have_groups;
    uint32_t cur_group;
    geom__hindex ghash;
} obj_state;

static size_t col_of(const obj_state *o, const char *t) { return (size_t)(t - o->line) + 1; }

static geom_status obj_err(obj_state *o, geom_status st, const char *t, const char *fmt, ...)
    GEOM_PRINTF(4, 5);

static geom_status obj_err(obj_state *o, geom_status st, const char *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    geom__meshio_vdiag(o->c->diag, st, o->c->source, o->lineno, t ? col_of(o, t) : 0, fmt, ap);
    va_end(ap);
    return st;
}

static geom_status num_err(obj_state *o, const char *t, size_t tl, int rc, const char *what)
{
    if (rc == -2)
        return obj_err(o, GEOM_ERR_PARSE, t, "%s '%.*s' is out of range", what,
                       (int)(tl > 40 ? 40 : tl), t);
    return obj_err(o, GEOM_ERR_PARSE, t, "expected %s, found '%.*s'", what,
                   (int)(tl > 40 ? 40 : tl), t);
}

/* Up to max numbers from the rest of the line into v; *n the count. */
static geom_status obj_numbers(obj_state *o, size_t *pos, double *v, size_t max, size_t *n,
                               const char *kw)
{
    const char *t = NULL;
    size_t tl = 0;
    *n = 0;
    while (mio_token(o->line, o->len, pos, 1, &t, &tl)) {
        if (*n == max)
            return obj_err(o, GEOM_ERR_PARSE, t, "too many numbers in '%s': at most %zu", kw,
                           max);
        int rc = geom__meshio_parse_double(t, tl, &v[*n]);
        if (rc != 0)
            return num_err(o, t, tl, rc, "a number");
        (*n)++;
    }
    return GEOM_OK;
}

static geom_status obj_vertex(obj_state *o, size_t pos, const char *kwt)
{
    mio_ctx *c = o->c;
    mio_soup *s = o->s;
    double v[7];
    size_t n;
    geom_status st = obj_numbers(o, &pos, v, 7, &n, "v");
    if (st != GEOM_OK)
        return st;
    if (n != 3 && n != 4 && n != 6 && n != 7)
        return obj_err(o, GEOM_ERR_PARSE, kwt,
                       "expected 'v x y z', 'v x y z w', 'v x y z r g b' or 'v x y z w r g b', "
                       "found %zu numbers",
                       n);
    size_t nv = mio_soup_nv(s);
    if (nv >= c->max_elements)
        return geom__meshio_check_count(c, nv + 1, "vertices", o->lineno, 0);
    if (MIO_RESERVE(c->alloc, s->pos, 3) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    s->pos.p[s->pos.n++] = v[0];
    s->pos.p[s->pos.n++] = v[1];
    s->pos.p[s->pos.n++] = v[2];
    static const double ones[3] = {1.0, 1.0, 1.0};
    int has_w = n == 4 || n == 7;
    int has_c = n >= 6;
    if (has_w && !o->weight) {
        o->weight = geom__meshio_soup_chan(s, c->alloc, "weight", GEOM_MESH_DOMAIN_VERTEX, 1, ones);
        if (!o->weight)
            return GEOM_ERR_NOMEM;
    }
    if (has_c && !o->color) {
        o->color = geom__meshio_soup_chan(s, c->alloc, "color", GEOM_MESH_DOMAIN_VERTEX, 3, ones);
        if (!o->color)
            return GEOM_ERR_NOMEM;
    }
    /* channels created just now were filled up to the new vertex included */
    if (o->weight && o->weight->val.n < nv + 1)
        if (MIO_PUSH(c->alloc, o->weight->val, has_w ? v[3] : 1.0) != GEOM_OK)
            return GEOM_ERR_NOMEM;
    if (o->weight && has_w)
        o->weight->val.p[nv] = v[3];
    if (o->color) {
        const double *rgb = has_c ? v + (has_w ? 4 : 3) : ones;
        if (o->color->val.n < 3 * (nv + 1)) {
            if (MIO_RESERVE(c->alloc, o->color->val, 3) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            o->color->val.n += 3;
        }
        memcpy(o->color->val.p + 3 * nv, rgb, 3 * sizeof(double));
    }
    return GEOM_OK;
}

static geom_status obj_texcoord(obj_state *o, size_t pos, const char *kwt)
{
    double v[3];
    size_t n;
    geom_status st = obj_numbers(o, &pos, v, 3, &n, "vt");
    if (st != GEOM_OK)
        return st;
    if (n == 0)
        return obj_err(o, GEOM_ERR_PARSE, kwt, "expected 'vt u [v [w]]'");
    if (n == 1)
        v[1] = 0.0;
    if (n == 3) {
        if (o->c->stats->skipped_statements++ == 0)
            snprintf(o->c->stats->first_skipped, sizeof o->c->stats->first_skipped, "vt w");
    }
    if (!o->uv) {
        o->uv = geom__meshio_soup_chan(o->s, o->c->alloc, "uv", GEOM_MESH_DOMAIN_CORNER, 2, NULL);
        if (!o->uv)
            return GEOM_ERR_NOMEM;
    }
    if (o->nvt >= o->c->max_elements)
        return geom__meshio_check_count(o->c, o->nvt + 1, "texture coordinates", o->lineno, 0);
    if (MIO_RESERVE(o->c->alloc, o->uv->val, 2) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    o->uv->val.p[o->uv->val.n++] = v[0];
    o->uv->val.p[o->uv->val.n++] = v[1];
    o->nvt++;
    return GEOM_OK;
}

static geom_status obj_normal(obj_state *o, size_t pos, const char *kwt)
{
    double v[3];
    size_t n;
    geom_status st = obj_numbers(o, &pos, v, 3, &n, "vn");
    if (st != GEOM_OK)
        return st;
    if (n != 3)
        return obj_err(o, GEOM_ERR_PARSE, kwt, "expected 'vn x y z', found %zu numbers", n);
    if (!o->normal) {
        o->normal =
            geom__meshio_soup_chan(o->s, o->c->alloc, "normal", GEOM_MESH_DOMAIN_CORNER, 3, NULL);
        if (!o->normal)
            return GEOM_ERR_NOMEM;
    }
    if (o->nvn >= o->c->max_elements)
        return geom__meshio_check_count(o->c, o->nvn + 1, "normals", o->lineno, 0);
    if (MIO_RESERVE(o->c->alloc, o->normal->val, 3) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    memcpy(o->normal->val.p + o->normal->val.n, v, sizeof v);
    o->normal->val.n += 3;
    o->nvn++;
    return GEOM_OK;
}

/* Resolve a 1-based or negative (relative) OBJ index against count. */
static geom_status obj_index(obj_state *o, const char *t, size_t tl, size_t count,
                             const char *what, const char *whats, const char *stmt,
                             uint32_t *out)
{
    int64_t v;
    int rc = geom__meshio_parse_int64(t, tl, &v);
    if (rc != 0 || tl == 0)
        return tl == 0 ? obj_err(o, GEOM_ERR_PARSE, t, "expected a %s index", what)
                       : num_err(o, t, tl, rc, "an index");
    if (v == 0)
        return obj_err(o, GEOM_ERR_PARSE, t, "%s index 0 is invalid (indices start at 1)", what);
    int64_t r = v > 0 ? v - 1 : (int64_t)count + v;
    if (r < 0 || (uint64_t)r >= count)
        return obj_err(o, GEOM_ERR_PARSE, t,
                       "%s refers to %s %lld, but %zu %s %s defined so far", stmt, what,
                       (long long)v, count, count == 1 ? what : whats,
                       count == 1 ? "is" : "are");
    *out = (uint32_t)r;
    return GEOM_OK;
}

static geom_status obj_face(obj_state *o, size_t pos, const char *kwt, int is_line);

static geom_status obj_group_face(obj_state *o)
{
    mio_ctx *c = o->c;
    mio_soup *s = o->s;
    if (!o->have_groups)
        return GEOM_OK;
    if (o->dirty) {
        uint64_t hv = 0;
        for (int i = 0; i < 4; i++) {
            uint64_t x = 0x51ed27u + (uint64_t)i;
            if (o->cur[i] != MIO_NOSTR)
                for (const char *p = s->strings.p + o->cur[i]; *p; p++)
                    x = x * 1099511628211ull ^ (unsigned char)*p;
            hv = geom__hash_mix(hv, x);
        }
        size_t it = 0;
        uint32_t g, found = GEOM_INVALID_INDEX;
        while ((g = geom__hindex_next(&o->ghash, hv, &it)) != UINT32_MAX) {
            int eq = 1;
            for (int i = 0; i < 4 && eq; i++) {
                size_t a = s->groups.p[4 * g + i], b = o->cur[i];
                eq = (a == MIO_NOSTR || b == MIO_NOSTR)
                         ? a == b
                         : strcmp(s->strings.p + a, s->strings.p + b) == 0;
            }
            if (eq) {
                found = g;
                break;
            }
        }
        if (found == GEOM_INVALID_INDEX) {
            size_t ng = s->groups.n / 4;
            if (ng >= c->max_elements)
                return geom__meshio_check_count(c, ng + 1, "groups", o->lineno, 0);
            if (geom__hindex_reserve(&o->ghash, c->alloc, ng + 1) != GEOM_OK ||
                MIO_RESERVE(c->alloc, s->groups, 4) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            it = 0;
            while (geom__hindex_next(&o->ghash, hv, &it) != UINT32_MAX) {
            }
            geom__hindex_insert_at(&o->ghash, hv, it, (uint32_t)ng);
            for (int i = 0; i < 4; i++)
                s->groups.p[s->groups.n++] = o->cur[i];
            found = (uint32_t)ng;
        }
        o->cur_group = found;
        o->dirty = 0;
    }
    return MIO_PUSH(c->alloc, s->fgroup, o->cur_group);
}

static geom_status obj_face(obj_state *o, size_t pos, const char *kwt, int is_line)
{
    mio_ctx *c = o->c;
    mio_soup *s = o->s;
    const char *t = NULL;
    size_t tl = 0;
    size_t nv = mio_soup_nv(s);
    size_t start = is_line ? s->pl_verts.n : s->fidx.n;
    size_t n = 0;
    int form0 = 0; /* the first corner's form: bit 1 vt, bit 2 vn */
    const char *t0 = NULL;
    size_t tl0 = 0;
    while (mio_token(o->line, o->len, &pos, 1, &t, &tl)) {
        /* split v[/vt[/vn]] */
        const char *part[3] = {t, NULL, NULL};
        size_t plen[3] = {tl, 0, 0};
        int np = 1;
        for (size_t i = 0; i < tl; i++) {
            if (t[i] == '/') {
                if (np == 3)
                    return obj_err(o, GEOM_ERR_PARSE, t,
                                   "expected v, v/vt, v//vn or v/vt/vn, found '%.*s'",
                                   (int)(tl > 40 ? 40 : tl), t);
                plen[np - 1] = (size_t)(t + i - part[np - 1]);
                part[np] = t + i + 1;
                plen[np] = (size_t)(t + tl - part[np]);
                np++;
            }
        }
        uint32_t vi, ti = GEOM_INVALID_INDEX, ni = GEOM_INVALID_INDEX;
        if (plen[0] == 0)
            return obj_err(o, GEOM_ERR_PARSE, t, "expected a vertex index");
        geom_status st =
            obj_index(o, part[0], plen[0], nv, "vertex", "vertices", is_line ? "line" : "face", &vi);
        if (st != GEOM_OK)
            return st;
        if (np >= 2 && plen[1] > 0) {
            st = obj_index(o, part[1], plen[1], o->nvt, "texture coordinate",
                           "texture coordinates",
                           is_line ? "line" : "face", &ti);
            if (st != GEOM_OK)
                return st;
        }
        if (np == 3 && plen[2] > 0) {
            if (is_line)
                return obj_err(o, GEOM_ERR_PARSE, part[2], "a line takes v or v/vt references");
            st = obj_index(o, part[2], plen[2], o->nvn, "normal", "normals", "face", &ni);
            if (st != GEOM_OK)
                return st;
        }
        /* Every corner of one element has the same form (v, v/vt, v//vn or
         * v/vt/vn): a mix would lose attributes on some corners. */
        int form = (ti != GEOM_INVALID_INDEX ? 1 : 0) | (ni != GEOM_INVALID_INDEX ? 2 : 0);
        if (n == 0) {
            form0 = form;
            t0 = t;
            tl0 = tl;
        } else if (form != form0 && !is_line) { /* lines keep only v anyway */
            static const char *const forms[] = {"v", "v/vt", "v//vn", "v/vt/vn"};
            return obj_err(o, GEOM_ERR_PARSE, t,
                           "corner '%.*s' is %s but the first corner '%.*s' is %s: every corner "
                           "of a face must have the same form",
                           (int)(tl > 40 ? 40 : tl), t, forms[form], (int)(tl0 > 40 ? 40 : tl0),
                           t0, forms[form0]);
        }
        if (is_line) {
            if (s->pl_verts.n >= c->max_elements)
                return geom__meshio_check_count(c, s->pl_verts.n + 1, "polyline vertices",
                                                o->lineno, 0);
            if (MIO_PUSH(c->alloc, s->pl_verts, vi) != GEOM_OK)
                return GEOM_ERR_NOMEM;
        } else {
            if (s->fidx.n >= c->max_elements)
                return geom__meshio_check_count(c, s->fidx.n + 1, "face corners", o->lineno, 0);
            if (MIO_PUSH(c->alloc, s->fidx, vi) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            if (o->uv && MIO_PUSH(c->alloc, o->uv->idx, ti) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            if (o->normal && MIO_PUSH(c->alloc, o->normal->idx, ni) != GEOM_OK)
                return GEOM_ERR_NOMEM;
        }
        n++;
    }
    if (is_line) {
        if (n < 2)
            return obj_err(o, GEOM_ERR_PARSE, kwt, "expected at least 2 vertices after 'l'");
        if (s->pl_off.n == 0 && MIO_PUSH(c->alloc, s->pl_off, start) != GEOM_OK)
            return GEOM_ERR_NOMEM;
        return MIO_PUSH(c->alloc, s->pl_off, s->pl_verts.n);
    }
    if (n == 0)
        return obj_err(o, GEOM_ERR_PARSE, kwt, "expected vertex references after 'f'");
    if (s->fsize.n >= c->max_elements)
        return geom__meshio_check_count(c, s->fsize.n + 1, "faces", o->lineno, 0);
    if (MIO_PUSH(c->alloc, s->fsize, (uint32_t)n) != GEOM_OK ||
        mio_floc_push(c->alloc, s, (uint64_t)o->lineno) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    return obj_group_face(o);
}

/* The rest of the line as one string: its tokens joined by single spaces
 * (a '#' comment ends it). *off = MIO_NOSTR when there are none. */
static geom_status obj_rest(obj_state *o, size_t pos, size_t *off)
{
    const char *t = NULL;
    size_t tl = 0;
    mio_soup *s = o->s;
    const geom_allocator *a = o->c->alloc;
    *off = MIO_NOSTR;
    while (mio_token(o->line, o->len, &pos, 1, &t, &tl)) {
        if (memchr(t, '\0', tl))
            return obj_err(o, GEOM_ERR_PARSE, t, "NUL byte in a name");
        if (*off == MIO_NOSTR) {
            if (geom__meshio_soup_str(s, a, t, tl, off) != GEOM_OK)
                return GEOM_ERR_NOMEM;
        } else {
            /* extend the last string: replace its NUL by a space */
            if (MIO_RESERVE(a, s->strings, tl + 1) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            s->strings.p[s->strings.n - 1] = ' ';
            memcpy(s->strings.p + s->strings.n, t, tl);
            s->strings.n += tl;
            s->strings.p[s->strings.n++] = '\0';
        }
    }
    return GEOM_OK;
}

static geom_status obj_group_stmt(obj_state *o, size_t pos, int which)
{
    mio_ctx *c = o->c;
    mio_soup *s = o->s;
    size_t mark = s->strings.n;
    size_t off;
    geom_status st = obj_rest(o, pos, &off);
    if (st != GEOM_OK)
        return st;
    if (!o->have_groups) {
        /* faces read so far have no group */
        o->have_groups = 1;
        for (int i = 0; i < 4; i++)
            o->cur[i] = MIO_NOSTR;
        if (MIO_RESERVE(c->alloc, s->fgroup, s->fsize.n) != GEOM_OK)
            return GEOM_ERR_NOMEM;
        for (size_t f = 0; f < s->fsize.n; f++)
            s->fgroup.p[f] = GEOM_INVALID_INDEX;
        s->fgroup.n = s->fsize.n;
        o->dirty = 1;
    }
    size_t old = o->cur[which];
    int same = (old == MIO_NOSTR || off == MIO_NOSTR)
                   ? old == off
                   : strcmp(s->strings.p + old, s->strings.p + off) == 0;
    if (same) {
        s->strings.n = mark; /* drop the duplicate */
        return GEOM_OK;
    }
    o->cur[which] = off;
    o->dirty = 1;
    return GEOM_OK;
}

static geom_status obj_tag(obj_state *o, size_t pos, const char *kwt)
{
    mio_ctx *c = o->c;
    mio_soup *s = o->s;
    const geom_allocator *a = c->alloc;
    const char *t, *name;
    size_t tl, nl;
    if (!mio_token(o->line, o->len, &pos, 1, &name, &nl))
        return obj_err(o, GEOM_ERR_PARSE, kwt, "expected 't name nint/nfloat/nstring ...'");
    if (memchr(name, '\0', nl))
        return obj_err(o, GEOM_ERR_PARSE, name, "NUL byte in a tag name");
    if (!mio_token(o->line, o->len, &pos, 1, &t, &tl))
        return obj_err(o, GEOM_ERR_PARSE, NULL,
                       "expected the counts nint/nfloat/nstring after the tag name");
    /* counts "a/b/c" */
    int64_t cnt[3];
    const char *p = t, *end = t + tl;
    for (int i = 0; i < 3; i++) {
        const char *q = p;
        while (q < end && *q != '/')
            q++;
        if (geom__meshio_parse_int64(p, (size_t)(q - p), &cnt[i]) != 0 || cnt[i] < 0 ||
            (i < 2 && q == end) || (i == 2 && q != end))
            return obj_err(o, GEOM_ERR_PARSE, t,
                           "expected tag counts nint/nfloat/nstring, found '%.*s'",
                           (int)(tl > 40 ? 40 : tl), t);
        p = q + 1;
    }
    /* every value is a token of the rest of the line */
    size_t remaining = o->len - pos;
    if ((uint64_t)cnt[0] > remaining || (uint64_t)cnt[1] > remaining ||
        (uint64_t)cnt[2] > remaining ||
        (uint64_t)cnt[0] + (uint64_t)cnt[1] + (uint64_t)cnt[2] > remaining)
        return obj_err(o, GEOM_ERR_PARSE, t,
                       "tag counts %lld/%lld/%lld exceed the values on the line",
                       (long long)cnt[0], (long long)cnt[1], (long long)cnt[2]);
    mio_tagrec r;
    r.nint = (size_t)cnt[0];
    r.nfloat = (size_t)cnt[1];
    r.nstring = (size_t)cnt[2];
    r.ints = s->tag_ints.n;
    r.floats = s->tag_floats.n;
    r.strs = s->tag_strs.n;
    if (s->tag_ints.n + r.nint > c->max_elements || s->tag_floats.n + r.nfloat > c->max_elements ||
        s->tag_strs.n + r.nstring > c->max_elements)
        return geom__meshio_check_count(c, c->max_elements + 1, "tag values", o->lineno, 0);
    if (geom__meshio_soup_str(s, a, name, nl, &r.name) != GEOM_OK ||
        MIO_RESERVE(a, s->tag_ints, r.nint) != GEOM_OK ||
        MIO_RESERVE(a, s->tag_floats, r.nfloat) != GEOM_OK ||
        MIO_RESERVE(a, s->tag_strs, r.nstring) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    for (size_t i = 0; i < r.nint + r.nfloat + r.nstring; i++) {
        if (!mio_token(o->line, o->len, &pos, 1, &t, &tl))
            return obj_err(o, GEOM_ERR_PARSE, NULL,
                           "tag '%.*s' declares %zu/%zu/%zu values but the line ends after %zu",
                           (int)(nl > 40 ? 40 : nl), name, r.nint, r.nfloat, r.nstring, i);
        if (i < r.nint) {
            int64_t v;
            int rc = geom__meshio_parse_int64(t, tl, &v);
            if (rc != 0)
                return num_err(o, t, tl, rc, "an integer tag value");
            s->tag_ints.p[s->tag_ints.n++] = v;
        } else if (i < r.nint + r.nfloat) {
            double v;
            int rc = geom__meshio_parse_double(t, tl, &v);
            if (rc != 0)
                return num_err(o, t, tl, rc, "a floating-point tag value");
            s->tag_floats.p[s->tag_floats.n++] = v;
        } else {
            if (memchr(t, '\0', tl))
                return obj_err(o, GEOM_ERR_PARSE, t, "NUL byte in a tag string");
            size_t off;
            if (geom__meshio_soup_str(s, a, t, tl, &off) != GEOM_OK)
                return GEOM_ERR_NOMEM;
            s->tag_strs.p[s->tag_strs.n++] = off;
        }
    }
    if (mio_token(o->line, o->len, &pos, 1, &t, &tl))
        return obj_err(o, GEOM_ERR_PARSE, t,
                       "unexpected '%.*s': the tag declares %zu/%zu/%zu values",
                       (int)(tl > 40 ? 40 : tl), t, r.nint, r.nfloat, r.nstring);
    if (s->tags.n >= c->max_elements)
        return geom__meshio_check_count(c, s->tags.n + 1, "tags", o->lineno, 0);
    return MIO_PUSH(a, s->tags, r);
}

geom_status geom__meshio_read_obj(mio_ctx *c, mio_soup *s)
{
    obj_state o;
    memset(&o, 0, sizeof o);
    o.c = c;
    o.s = s;
    o.cur_group = GEOM_INVALID_INDEX;
    for (int i = 0; i < 4; i++)
        o.cur[i] = MIO_NOSTR;
    mio_lines lines;
    geom__meshio_lines_init(&lines, c->data, c->size, 1);
    geom_status st = GEOM_OK;
    int rc;
    while (st == GEOM_OK && (rc = geom__meshio_lines_next(&lines, c->alloc, &o.line, &o.len)) != 0) {
        if (rc < 0) {
            st = (geom_status)rc;
            break;
        }
        o.lineno = lines.lineno;
        size_t pos = 0;
        const char *kw;
        size_t kl;
        if (!mio_token(o.line, o.len, &pos, 1, &kw, &kl))
            continue;
        if (mio_tok_eq(kw, kl, "v"))
            st = obj_vertex(&o, pos, kw);
        else if (mio_tok_eq(kw, kl, "f"))
            st = obj_face(&o, pos, kw, 0);
        else if (mio_tok_eq(kw, kl, "vt"))
            st = obj_texcoord(&o, pos, kw);
        else if (mio_tok_eq(kw, kl, "vn"))
            st = obj_normal(&o, pos, kw);
        else if (mio_tok_eq(kw, kl, "l"))
            st = obj_face(&o, pos, kw, 1);
        else if (mio_tok_eq(kw, kl, "g"))
            st = obj_group_stmt(&o, pos, 0);
        else if (mio_tok_eq(kw, kl, "o"))
            st = obj_group_stmt(&o, pos, 1);
        else if (mio_tok_eq(kw, kl, "usemtl"))
            st = obj_group_stmt(&o, pos, 2);
        else if (mio_tok_eq(kw, kl, "s"))
            st = obj_group_stmt(&o, pos, 3);
        else if (mio_tok_eq(kw, kl, "t"))
            st = obj_tag(&o, pos, kw);
        else if (mio_tok_eq(kw, kl, "mtllib")) {
            size_t off;
            st = obj_rest(&o, pos, &off);
            if (st == GEOM_OK && off != MIO_NOSTR)
                st = MIO_PUSH(c->alloc, s->mtllibs, off);
        } else {
            if (c->stats->skipped_statements++ == 0)
                geom__meshio_printable(c->stats->first_skipped, sizeof c->stats->first_skipped,
                                       kw, kl);
        }
    }
    if (st == GEOM_ERR_NOMEM && c->diag && c->diag->status != GEOM_ERR_NOMEM)
        geom__meshio_err_line(c, st, o.lineno, 0, "out of memory");
    geom__meshio_lines_free(&lines, c->alloc);
    geom__hindex_free(&o.ghash, c->alloc);
    s->loc_is_offset = 0;
    return st;
}

/* --------------------------------------------------------------- writing */

/* v in decimal at p; returns the end (at most 20 bytes). */
static inline char *put_index(char *p, uint64_t v)
{
    int n = geom__decimal_length(v);
    geom__put_digits(p, v, n);
    return p + n;
}

/* End a line; a line whose text ends with a backslash would continue on the
 * next one when read back, so it gets a trailing space (which the reader
 * drops) first. `last` is the last string written on the line. */
static void end_line(mio_sink *k, const char *last)
{
    size_t n = last ? strlen(last) : 0;
    if (n && last[n - 1] == '\\')
        mio_putc(k, ' ');
    mio_putc(k, '\n');
}

static void put_name_line(mio_sink *k, const char *kw, const char *val)
{
    geom__meshio_puts(k, kw);
    if (val) {
        mio_putc(k, ' ');
        geom__meshio_puts(k, val);
    }
    end_line(k, val);
}

static int str_eq(const char *a, const char *b)
{
    return (!a || !b) ? a == b : strcmp(a, b) == 0;
}

geom_status geom__meshio_write_obj(const geom_mesh *m, const geom_meshio_write_options *opt,
                                   mio_sink *k)
{
    const geom_allocator *a = opt->alloc;
    unsigned omit = opt->omit;
    uint32_t *vmap = NULL;
    size_t nlive = 0;
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    geom_status st = geom__meshio_vertex_map(m, a, &vmap, &nlive);
    if (st != GEOM_OK)
        return geom__meshio_sink_fail(k, st, "out of memory");

    geom__meshio_puts(k, "# written by libgeom ");
    geom__meshio_puts(k, geom_version_string());
    mio_putc(k, '\n');
    int meta = !(omit & GEOM_MESHIO_ATTR_META);
    if (meta && !(omit & GEOM_MESHIO_ATTR_MTLLIB))
        for (size_t i = 0; i < geom_mesh_mtllib_count(m); i++)
            put_name_line(k, "mtllib", geom_mesh_mtllib_get(m, i));

    const double *pos = geom_mesh_cpositions(m);
    uint32_t cw = geom_mesh_channel_find(m, "weight", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t cc = (omit & GEOM_MESHIO_ATTR_COLOR)
                      ? GEOM_INVALID_INDEX
                      : geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_VERTEX);
    if (cw != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, cw) != 1)
        cw = GEOM_INVALID_INDEX;
    if (cc != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, cc) < 3)
        cc = GEOM_INVALID_INDEX;
    const double *wd = cw != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, cw) : NULL;
    const double *cd = cc != GEOM_INVALID_INDEX ? geom_mesh_channel_cdata(m, cc) : NULL;
    size_t cnc = cd ? geom_mesh_channel_ncomp(m, cc) : 0;
    for (size_t v = 0; v < nv && k->status == GEOM_OK; v++) {
        if (vmap[v] == GEOM_INVALID_INDEX)
            continue;
        mio_putc(k, 'v');
        for (int i = 0; i < 3; i++) {
            mio_putc(k, ' ');
            geom__meshio_put_double(k, pos[3 * v + i]);
        }
        if (wd) {
            mio_putc(k, ' ');
            geom__meshio_put_double(k, wd[v]);
        }
        if (cd)
            for (int i = 0; i < 3; i++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, cd[cnc * v + (size_t)i]);
            }
        mio_putc(k, '\n');
    }

    /* vt and vn: CORNER pools in order, or one per live vertex */
    uint32_t ch[2] = {geom__meshio_attr_channel(m, MIO_ATTR_UV, omit),
                      geom__meshio_attr_channel(m, MIO_ATTR_NORMAL, omit)};
    const char *kw[2] = {"vt", "vn"};
    const uint32_t *cix[2] = {NULL, NULL};
    size_t pool[2] = {0, 0};
    for (int c = 0; c < 2; c++) {
        if (ch[c] == GEOM_INVALID_INDEX)
            continue;
        size_t nc = geom_mesh_channel_ncomp(m, ch[c]);
        size_t wnc = c == 0 ? (nc > 3 ? 3 : nc) : 3;
        if (nc < (c == 0 ? 1u : 3u)) {
            ch[c] = GEOM_INVALID_INDEX;
            continue;
        }
        const double *d = geom_mesh_channel_cdata(m, ch[c]);
        int corner = geom_mesh_channel_domain(m, ch[c]) == GEOM_MESH_DOMAIN_CORNER;
        size_t n = geom_mesh_channel_size(m, ch[c]);
        pool[c] = n;
        if (corner)
            cix[c] = geom_mesh_corner_cindices(m, ch[c]);
        for (size_t i = 0; i < n && k->status == GEOM_OK; i++) {
            if (!corner && vmap[i] == GEOM_INVALID_INDEX)
                continue;
            geom__meshio_puts(k, kw[c]);
            for (size_t j = 0; j < wnc; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, d[i * nc + j]);
            }
            mio_putc(k, '\n');
        }
    }

    const uint32_t *fg = meta ? geom_mesh_face_cgroups(m) : NULL;
    const char *state[4] = {NULL, NULL, NULL, NULL};
    uint32_t prev_group = GEOM_INVALID_INDEX;
    for (size_t f = 0; f < nf && k->status == GEOM_OK; f++) {
        if (m->f_del[f])
            continue;
        if (fg && fg[f] != prev_group) {
            const char *want[4] = {NULL, NULL, NULL, NULL};
            geom_mesh_group g;
            if (fg[f] != GEOM_INVALID_INDEX && geom_mesh_group_get(m, fg[f], &g) == GEOM_OK) {
                want[0] = g.object;
                want[1] = g.group;
                want[2] = g.material;
                want[3] = g.smoothing;
            }
            static const char *const gkw[4] = {"o", "g", "usemtl", "s"};
            for (int i = 0; i < 4; i++) {
                if (str_eq(state[i], want[i]))
                    continue;
                put_name_line(k, gkw[i], want[i] ? want[i] : (i == 3 ? "off" : NULL));
                state[i] = want[i];
            }
            prev_group = fg[f];
        }
        uint32_t h0 = m->f_he[f], h = h0;
        /* which of vt / vn every corner of this face has */
        int use[2] = {0, 0};
        for (int c = 0; c < 2; c++) {
            if (ch[c] == GEOM_INVALID_INDEX)
                continue;
            use[c] = 1;
            if (!cix[c])
                continue;
            do {
                if (cix[c][h] >= pool[c])
                    use[c] = 0;
                h = geom_mesh_he_next(m, h);
            } while (h != h0 && use[c]);
            h = h0;
        }
        mio_putc(k, 'f');
        /* each corner " v[/[vt][/vn]]" (at most 33 bytes) straight into
         * the sink's buffer */
        do {
            if (!mio_room(k, 40))
                break;
            char *p0 = (char *)k->buf + k->n, *p = p0;
            uint32_t v = m->he_vertex[h];
            uint64_t vi = (uint64_t)vmap[v] + 1;
            *p++ = ' ';
            p = put_index(p, vi);
            if (use[0] || use[1]) {
                *p++ = '/';
                if (use[0])
                    p = put_index(p, cix[0] ? (uint64_t)cix[0][h] + 1 : vi);
                if (use[1]) {
                    *p++ = '/';
                    p = put_index(p, cix[1] ? (uint64_t)cix[1][h] + 1 : vi);
                }
            }
            mio_advance(k, (size_t)(p - p0));
            h = m->he_next[h];
        } while (h != h0 && h != GEOM_INVALID_INDEX);
        mio_putc(k, '\n');
    }

    if (meta) {
        for (size_t i = 0; i < geom_mesh_polyline_count(m) && k->status == GEOM_OK; i++) {
            size_t n;
            const uint32_t *vs;
            if (geom_mesh_polyline_get(m, i, &n, &vs) != GEOM_OK)
                continue;
            size_t live = 0;
            for (size_t j = 0; j < n; j++)
                live += vs[j] < nv && vmap[vs[j]] != GEOM_INVALID_INDEX;
            if (live < 2)
                continue;
            mio_putc(k, 'l');
            for (size_t j = 0; j < n; j++) {
                if (vs[j] >= nv || vmap[vs[j]] == GEOM_INVALID_INDEX)
                    continue;
                mio_putc(k, ' ');
                geom__meshio_put_u64(k, (uint64_t)vmap[vs[j]] + 1);
            }
            mio_putc(k, '\n');
        }
        for (size_t i = 0; i < geom_mesh_tag_count(m) && k->status == GEOM_OK; i++) {
            geom_mesh_tag t;
            if (geom_mesh_tag_get(m, i, &t) != GEOM_OK)
                continue;
            geom__meshio_puts(k, "t ");
            geom__meshio_puts(k, t.name);
            mio_putc(k, ' ');
            geom__meshio_put_u64(k, t.nint);
            mio_putc(k, '/');
            geom__meshio_put_u64(k, t.nfloat);
            mio_putc(k, '/');
            geom__meshio_put_u64(k, t.nstring);
            for (size_t j = 0; j < t.nint; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_i64(k, t.ints[j]);
            }
            for (size_t j = 0; j < t.nfloat; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, t.floats[j]);
            }
            for (size_t j = 0; j < t.nstring; j++) {
                mio_putc(k, ' ');
                geom__meshio_puts(k, t.strings[j]);
            }
            end_line(k, t.nstring ? t.strings[t.nstring - 1] : NULL);
        }
    }
    geom__free(a, vmap, nv * sizeof(uint32_t));
    return k->status;
}
