/* Stanford PLY: ascii, binary_little_endian and binary_big_endian; any
 * scalar and list types; unknown elements and properties skipped. */
#include "meshio/meshio_internal.h"

#include <stdio.h>

/* --------------------------------------------------------------- types */

typedef enum ply_type {
    PT_NONE = 0, PT_I8, PT_U8, PT_I16, PT_U16, PT_I32, PT_U32, PT_F32, PT_F64
} ply_type;

static const struct {
    const char *name;
    ply_type type;
} ply_type_names[] = {{"char", PT_I8},    {"int8", PT_I8},     {"uchar", PT_U8},
                      {"uint8", PT_U8},   {"short", PT_I16},   {"int16", PT_I16},
                      {"ushort", PT_U16}, {"uint16", PT_U16},  {"int", PT_I32},
                      {"int32", PT_I32},  {"uint", PT_U32},    {"uint32", PT_U32},
                      {"float", PT_F32},  {"float32", PT_F32}, {"double", PT_F64},
                      {"float64", PT_F64}};

static const size_t ply_type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

static ply_type ply_type_from(const char *t, size_t tl)
{
    for (size_t i = 0; i < sizeof ply_type_names / sizeof ply_type_names[0]; i++)
        if (mio_tok_eq(t, tl, ply_type_names[i].name))
            return ply_type_names[i].type;
    return PT_NONE;
}

static int ply_type_is_int(ply_type t) { return t != PT_F32 && t != PT_F64; }

/* Range of the integer types (ASCII values outside are errors). */
static const double ply_type_min[] = {0, -128, 0, -32768, 0, -2147483648.0, 0, 0, 0};
static const double ply_type_max[] = {0, 127, 255, 32767, 65535, 2147483647.0, 4294967295.0, 0, 0};

static const char *ply_type_name(ply_type t)
{
    static const char *const names[] = {"?", "char", "uchar", "short", "ushort",
                                        "int", "uint", "float", "double"};
    return (unsigned)t < sizeof names / sizeof names[0] ? names[t] : "?";
}

enum {
    R_NONE = 0,
    R_X, R_Y, R_Z, R_NX, R_NY, R_NZ, R_U, R_V, R_R, R_G, R_B, R_A, /* vertex */
    R_INDICES, R_TEXCOORD, R_FR, R_FG, R_FB, R_FA                  /* face */
};

typedef struct ply_prop {
    char name[64];
    ply_type type;       /* scalar type, or item type of a list */
    ply_type count_type; /* PT_NONE for a scalar */
    int role;
} ply_prop;

enum { E_OTHER = 0, E_VERTEX = 1, E_FACE = 2 };

typedef struct ply_elem {
    char name[64];
    size_t count;
    size_t first, nprop; /* into the property array */
    int kind;
} ply_elem;

/* --------------------------------------------------------------- reading */

typedef struct ply_in {
    mio_ctx *c;
    int ascii, be;
    size_t pos; /* binary: offset into c->data */
    mio_cursor cur;
    const ply_elem *elem;
    size_t inst;
    size_t tok_line, tok_col; /* ascii: where the last value was */
    size_t tok_off;           /* binary: offset of the last value */
} ply_in;

static geom_status ply_data_err(ply_in *in, const ply_prop *p, size_t line, size_t col,
                                const char *what)
{
    const char *en = in->elem ? in->elem->name : "?";
    if (in->ascii)
        return geom__meshio_err_line(in->c, GEOM_ERR_PARSE, line, col,
                                     "%s (element '%s' %zu, property '%s')", what, en,
                                     in->inst, p ? p->name : "?");
    return geom__meshio_err_off(in->c, GEOM_ERR_PARSE, in->pos,
                                "%s (element '%s' %zu, property '%s')", what, en, in->inst,
                                p ? p->name : "?");
}

/* One value of type t. */
static geom_status ply_value(ply_in *in, ply_type t, const ply_prop *p, double *out)
{
    if (in->ascii) {
        const char *tok;
        size_t tl, line, col;
        if (!geom__meshio_cursor_next(&in->cur, &tok, &tl, &line, &col))
            return ply_data_err(in, p, line, col, "unexpected end of file");
        in->tok_line = line;
        in->tok_col = col;
        int rc = geom__meshio_parse_double(tok, tl, out);
        if (rc != 0)
            return ply_data_err(in, p, line, col,
                                rc == -2 ? "number out of range" : "expected a number");
        if (ply_type_is_int(t) && *out != floor(*out))
            return ply_data_err(in, p, line, col, "expected an integer");
        if (ply_type_is_int(t) && (*out < ply_type_min[t] || *out > ply_type_max[t])) {
            char what[96];
            snprintf(what, sizeof what, "%.0f is outside the range of %s [%.0f, %.0f]", *out,
                     ply_type_name(t), ply_type_min[t], ply_type_max[t]);
            return ply_data_err(in, p, line, col, what);
        }
        return GEOM_OK;
    }
    size_t sz = ply_type_size[t];
    const unsigned char *d = in->c->data;
    if (in->c->size - in->pos < sz)
        return ply_data_err(in, p, 0, 0, "unexpected end of file");
    unsigned char b[8];
    for (size_t i = 0; i < sz; i++)
        b[i] = d[in->pos + (in->be ? sz - 1 - i : i)];
    in->tok_off = in->pos;
    in->pos += sz;
    uint64_t u = 0;
    for (size_t i = 0; i < sz; i++)
        u |= (uint64_t)b[i] << (8 * i);
    switch (t) {
    case PT_I8: *out = (double)(int8_t)(uint8_t)u; break;
    case PT_U8: *out = (double)(uint8_t)u; break;
    case PT_I16: *out = (double)(int16_t)(uint16_t)u; break;
    case PT_U16: *out = (double)(uint16_t)u; break;
    case PT_I32: *out = (double)(int32_t)(uint32_t)u; break;
    case PT_U32: *out = (double)(uint32_t)u; break;
    case PT_F32: {
        uint32_t w = (uint32_t)u;
        float f;
        memcpy(&f, &w, 4);
        *out = (double)f;
        break;
    }
    case PT_F64: memcpy(out, &u, 8); break;
    default: *out = 0; break;
    }
    if (!isfinite(*out)) {
        in->pos = in->tok_off; /* the offset of the bad value itself */
        return ply_data_err(in, p, 0, 0, "non-finite value");
    }
    return GEOM_OK;
}

/* A list's count, checked against what remains of the input. */
static geom_status ply_list_count(ply_in *in, const ply_prop *p, size_t *n)
{
    double v;
    geom_status st = ply_value(in, p->count_type, p, &v);
    if (st != GEOM_OK)
        return st;
    size_t line = in->tok_line, col = in->tok_col;
    size_t room = in->ascii ? (in->c->size - in->cur.pos) / 2 + 1
                            : (in->c->size - in->pos) / ply_type_size[p->type];
    if (v < 0 || v > (double)room) {
        if (!in->ascii)
            in->pos = in->tok_off; /* messages point at the bad value */
        return ply_data_err(in, p, line, col,
                            v < 0 ? "negative list length"
                                  : "list length exceeds what remains of the file");
    }
    *n = (size_t)v;
    return GEOM_OK;
}

static double color_scale(ply_type t)
{
    if (t == PT_U16)
        return 1.0 / 65535.0;
    if (t == PT_F32 || t == PT_F64)
        return 1.0;
    return 1.0 / 255.0;
}

typedef struct ply_header {
    int ascii, be;
    MIO_ARR(ply_elem) elems;
    MIO_ARR(ply_prop) props;
    size_t data_start;
    size_t data_line;
} ply_header;

static geom_status ply_parse_header(mio_ctx *c, ply_header *h)
{
    mio_lines lines;
    geom__meshio_lines_init(&lines, c->data, c->size, 0);
    const char *line;
    size_t len;
    geom_status st = GEOM_OK;
    int rc = geom__meshio_lines_next(&lines, c->alloc, &line, &len);
    if (rc <= 0 || len != 3 || memcmp(line, "ply", 3) != 0) {
        st = geom__meshio_err_line(c, GEOM_ERR_PARSE, 1, 1, "expected 'ply' on the first line");
        goto done;
    }
    int have_format = 0, ended = 0;
    ply_elem *cur = NULL;
    while (!ended && (rc = geom__meshio_lines_next(&lines, c->alloc, &line, &len)) > 0) {
        size_t ln = lines.lineno, pos = 0;
        const char *t[6];
        size_t tl[6];
        int n = 0;
        while (n < 6 && mio_token(line, len, &pos, 0, &t[n], &tl[n]))
            n++;
        if (n == 0)
            continue;
        size_t col = (size_t)(t[0] - line) + 1;
        if (mio_tok_eq(t[0], tl[0], "comment") || mio_tok_eq(t[0], tl[0], "obj_info"))
            continue;
        if (mio_tok_eq(t[0], tl[0], "end_header")) {
            ended = 1;
            break;
        }
        if (mio_tok_eq(t[0], tl[0], "format")) {
            if (n < 2 || have_format) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                           have_format ? "second 'format' line"
                                                       : "expected 'format ascii|"
                                                         "binary_little_endian|"
                                                         "binary_big_endian 1.0'");
                goto done;
            }
            if (mio_tok_eq(t[1], tl[1], "ascii")) {
                h->ascii = 1;
            } else if (mio_tok_eq(t[1], tl[1], "binary_little_endian")) {
                h->be = 0;
            } else if (mio_tok_eq(t[1], tl[1], "binary_big_endian")) {
                h->be = 1;
            } else {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, (size_t)(t[1] - line) + 1,
                                           "expected ascii, binary_little_endian or "
                                           "binary_big_endian, found '%.*s'",
                                           (int)(tl[1] > 40 ? 40 : tl[1]), t[1]);
                goto done;
            }
            have_format = 1;
            continue;
        }
        if (mio_tok_eq(t[0], tl[0], "element")) {
            int64_t cnt;
            if (n != 3 || geom__meshio_parse_int64(t[2], tl[2], &cnt) != 0 || cnt < 0) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                           "expected 'element <name> <count>'");
                goto done;
            }
            if ((uint64_t)cnt > c->max_elements) {
                st = geom__meshio_err_line(c, GEOM_ERR_LIMIT, ln, (size_t)(t[2] - line) + 1,
                                           "element '%.*s' count %lld exceeds the limit of %zu",
                                           (int)(tl[1] > 40 ? 40 : tl[1]), t[1],
                                           (long long)cnt, c->max_elements);
                goto done;
            }
            ply_elem e;
            memset(&e, 0, sizeof e);
            snprintf(e.name, sizeof e.name, "%.*s", (int)(tl[1] > 63 ? 63 : tl[1]), t[1]);
            e.count = (size_t)cnt;
            e.first = h->props.n;
            e.kind = strcmp(e.name, "vertex") == 0 ? E_VERTEX
                     : strcmp(e.name, "face") == 0 ? E_FACE
                                                   : E_OTHER;
            for (size_t i = 0; i < h->elems.n; i++)
                if (e.kind != E_OTHER && h->elems.p[i].kind == e.kind) {
                    st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                               "second '%s' element", e.name);
                    goto done;
                }
            if (h->elems.n >= 1024) {
                st = geom__meshio_err_line(c, GEOM_ERR_LIMIT, ln, col, "more than 1024 elements");
                goto done;
            }
            if (MIO_PUSH(c->alloc, h->elems, e) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            cur = &h->elems.p[h->elems.n - 1];
            continue;
        }
        if (mio_tok_eq(t[0], tl[0], "property")) {
            if (!cur) {
                st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                           "'property' before any 'element'");
                goto done;
            }
            ply_prop p;
            memset(&p, 0, sizeof p);
            const char *nm;
            size_t nl;
            if (n >= 2 && mio_tok_eq(t[1], tl[1], "list")) {
                if (n != 5 || (p.count_type = ply_type_from(t[2], tl[2])) == PT_NONE ||
                    (p.type = ply_type_from(t[3], tl[3])) == PT_NONE ||
                    !ply_type_is_int(p.count_type)) {
                    st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                               "expected 'property list <integer type> <type> "
                                               "<name>'");
                    goto done;
                }
                nm = t[4];
                nl = tl[4];
            } else {
                if (n != 3 || (p.type = ply_type_from(t[1], tl[1])) == PT_NONE) {
                    st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                               "expected 'property <type> <name>' with type "
                                               "char, uchar, short, ushort, int, uint, float "
                                               "or double");
                    goto done;
                }
                nm = t[2];
                nl = tl[2];
            }
            snprintf(p.name, sizeof p.name, "%.*s", (int)(nl > 63 ? 63 : nl), nm);
            for (size_t i = 0; i < cur->nprop; i++)
                if (strcmp(h->props.p[cur->first + i].name, p.name) == 0) {
                    st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, (size_t)(nm - line) + 1,
                                               "duplicate property '%s' in element '%s'",
                                               p.name, cur->name);
                    goto done;
                }
            if (cur->nprop >= 1024) {
                st = geom__meshio_err_line(c, GEOM_ERR_LIMIT, ln, col,
                                           "more than 1024 properties in an element");
                goto done;
            }
            if (MIO_PUSH(c->alloc, h->props, p) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            cur->nprop++;
            continue;
        }
        st = geom__meshio_err_line(c, GEOM_ERR_PARSE, ln, col,
                                   "expected format, element, property, comment, obj_info or "
                                   "end_header, found '%.*s'",
                                   (int)(tl[0] > 40 ? 40 : tl[0]), t[0]);
        goto done;
    }
    if (rc < 0) {
        st = (geom_status)rc;
        goto done;
    }
    if (!ended) {
        st = geom__meshio_err_line(c, GEOM_ERR_PARSE, lines.next_lineno, 1,
                                   "unexpected end of file: expected 'end_header'");
        goto done;
    }
    if (!have_format) {
        st = geom__meshio_err_line(c, GEOM_ERR_PARSE, lines.lineno, 1,
                                   "no 'format' line before 'end_header'");
        goto done;
    }
    h->data_start = lines.pos;
    h->data_line = lines.next_lineno;
done:
    geom__meshio_lines_free(&lines, c->alloc);
    return st;
}

/* Give each property of the vertex and face elements its role. */
static void ply_assign_roles(ply_header *h, mio_ctx *c)
{
    static const struct {
        const char *name;
        int role;
    } vroles[] = {{"x", R_X},         {"y", R_Y},          {"z", R_Z},
                  {"nx", R_NX},       {"ny", R_NY},        {"nz", R_NZ},
                  {"u", R_U},         {"v", R_V},          {"s", R_U},
                  {"t", R_V},         {"texture_u", R_U},  {"texture_v", R_V},
                  {"texture_s", R_U}, {"texture_t", R_V},  {"red", R_R},
                  {"green", R_G},     {"blue", R_B},       {"alpha", R_A},
                  {"diffuse_red", R_R}, {"diffuse_green", R_G}, {"diffuse_blue", R_B}},
      froles[] = {{"red", R_FR}, {"green", R_FG}, {"blue", R_FB}, {"alpha", R_FA}};
    for (size_t i = 0; i < h->elems.n; i++) {
        ply_elem *e = &h->elems.p[i];
        int seen[R_FA + 1] = {0};
        for (size_t j = 0; j < e->nprop; j++) {
            ply_prop *p = &h->props.p[e->first + j];
            int role = R_NONE;
            if (e->kind == E_VERTEX && p->count_type == PT_NONE) {
                for (size_t k = 0; k < sizeof vroles / sizeof vroles[0]; k++)
                    if (strcmp(p->name, vroles[k].name) == 0)
                        role = vroles[k].role;
            } else if (e->kind == E_FACE) {
                if (p->count_type != PT_NONE &&
                    (strcmp(p->name, "vertex_indices") == 0 ||
                     strcmp(p->name, "vertex_index") == 0) &&
                    ply_type_is_int(p->type))
                    role = R_INDICES;
                else if (p->count_type != PT_NONE && strcmp(p->name, "texcoord") == 0)
                    role = R_TEXCOORD;
                else if (p->count_type == PT_NONE)
                    for (size_t k = 0; k < sizeof froles / sizeof froles[0]; k++)
                        if (strcmp(p->name, froles[k].name) == 0)
                            role = froles[k].role;
            }
            if (role != R_NONE && seen[role])
                role = R_NONE; /* a repeated name: keep the first */
            if (role != R_NONE)
                seen[role] = 1;
            p->role = role;
        }
        /* partial groups are not used */
        for (size_t j = 0; j < e->nprop; j++) {
            ply_prop *p = &h->props.p[e->first + j];
            int r = p->role;
            if (((r == R_NX || r == R_NY || r == R_NZ) && !(seen[R_NX] && seen[R_NY] && seen[R_NZ])) ||
                ((r == R_U || r == R_V) && !(seen[R_U] && seen[R_V])) ||
                ((r == R_R || r == R_G || r == R_B || r == R_A) &&
                 !(seen[R_R] && seen[R_G] && seen[R_B])) ||
                ((r == R_FR || r == R_FG || r == R_FB || r == R_FA) &&
                 !(seen[R_FR] && seen[R_FG] && seen[R_FB])))
                p->role = R_NONE;
            if (p->role == R_NONE && e->kind != E_OTHER)
                c->stats->skipped_properties++;
        }
    }
}

geom_status geom__meshio_read_ply(mio_ctx *c, mio_soup *s)
{
    ply_header h;
    memset(&h, 0, sizeof h);
    MIO_ARR(double) tex;
    memset(&tex, 0, sizeof tex);
    geom_status st = ply_parse_header(c, &h);
    if (st != GEOM_OK)
        goto done;
    ply_assign_roles(&h, c);
    c->stats->binary = !h.ascii;
    s->loc_is_offset = !h.ascii;

    /* every element's instances need at least this many bytes */
    {
        uint64_t need = 0;
        for (size_t i = 0; i < h.elems.n; i++) {
            const ply_elem *e = &h.elems.p[i];
            uint64_t per = 0;
            for (size_t j = 0; j < e->nprop; j++) {
                const ply_prop *p = &h.props.p[e->first + j];
                per += h.ascii ? 2 : ply_type_size[p->count_type != PT_NONE ? p->count_type
                                                                              : p->type];
            }
            need += per * e->count;
        }
        size_t remaining = c->size - h.data_start;
        if (need > (uint64_t)remaining + (h.ascii ? 1 : 0)) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, h.data_line, 1,
                                       "the header declares elements that need at least %llu "
                                       "bytes, but only %zu bytes follow it",
                                       (unsigned long long)need, remaining);
            goto done;
        }
    }
    const ply_elem *ve = NULL, *fe = NULL;
    for (size_t i = 0; i < h.elems.n; i++) {
        if (h.elems.p[i].kind == E_VERTEX)
            ve = &h.elems.p[i];
        if (h.elems.p[i].kind == E_FACE)
            fe = &h.elems.p[i];
    }
    mio_chan *cn = NULL, *cuv = NULL, *ccol = NULL, *ctex = NULL, *cfcol = NULL;
    int has_alpha = 0, has_falpha = 0, has_indices = 0;
    if (ve) {
        int have[R_FA + 1] = {0};
        for (size_t j = 0; j < ve->nprop; j++)
            have[h.props.p[ve->first + j].role] = 1;
        if (!have[R_X] || !have[R_Y] || !have[R_Z]) {
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, 1, 0,
                                       "the vertex element has no x, y and z properties");
            goto done;
        }
        has_alpha = have[R_A];
        if ((have[R_NX] && !(cn = geom__meshio_soup_chan(s, c->alloc, "normal",
                                                         GEOM_MESH_DOMAIN_VERTEX, 3, NULL))) ||
            (have[R_U] && !(cuv = geom__meshio_soup_chan(s, c->alloc, "uv",
                                                         GEOM_MESH_DOMAIN_VERTEX, 2, NULL))) ||
            (have[R_R] && !(ccol = geom__meshio_soup_chan(s, c->alloc, "color",
                                                          GEOM_MESH_DOMAIN_VERTEX,
                                                          has_alpha ? 4 : 3, NULL)))) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
    }
    if (fe) {
        int have[R_FA + 1] = {0};
        for (size_t j = 0; j < fe->nprop; j++)
            have[h.props.p[fe->first + j].role] = 1;
        has_indices = have[R_INDICES];
        has_falpha = have[R_FA];
        if (has_indices &&
            ((have[R_TEXCOORD] && !(ctex = geom__meshio_soup_chan(s, c->alloc, "uv",
                                                                  GEOM_MESH_DOMAIN_CORNER, 2,
                                                                  NULL))) ||
             (have[R_FR] && !(cfcol = geom__meshio_soup_chan(s, c->alloc, "color",
                                                             GEOM_MESH_DOMAIN_FACE,
                                                             has_falpha ? 4 : 3, NULL))))) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
    }

    ply_in in;
    memset(&in, 0, sizeof in);
    in.c = c;
    in.ascii = h.ascii;
    in.be = h.be;
    in.pos = h.data_start;
    in.cur.data = (const char *)c->data;
    in.cur.size = c->size;
    in.cur.pos = h.data_start;
    in.cur.line = h.data_line;
    in.cur.line_start = h.data_start;
    for (size_t ei = 0; ei < h.elems.n; ei++) {
        const ply_elem *e = &h.elems.p[ei];
        in.elem = e;
        int is_v = e == ve, is_f = e == fe && has_indices;
        if (!is_v && !is_f)
            c->stats->skipped_elements += e->count;
        if (e->nprop == 0)
            continue;
        if (is_v) {
            if ((st = geom__meshio_check_count(c, e->count, "vertices", 0, 0)) != GEOM_OK)
                goto done;
            if (MIO_RESERVE(c->alloc, s->pos, 3 * e->count) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
        }
        for (size_t i = 0; i < e->count; i++) {
            in.inst = i;
            double vv[R_FA + 1];
            vv[R_A] = vv[R_FA] = 1.0;
            if (h.ascii) { /* step to the instance's first token for its line */
                while (in.cur.pos < in.cur.size && mio_is_space(in.cur.data[in.cur.pos])) {
                    if (in.cur.data[in.cur.pos] == '\n') {
                        in.cur.line++;
                        in.cur.line_start = in.cur.pos + 1;
                    }
                    in.cur.pos++;
                }
            }
            uint64_t loc = h.ascii ? in.cur.line : in.pos;
            size_t nidx = 0;
            tex.n = 0;
            int got_indices = 0;
            for (size_t j = 0; j < e->nprop; j++) {
                const ply_prop *p = &h.props.p[e->first + j];
                int role = (is_v || is_f) ? p->role : R_NONE;
                if (p->count_type == PT_NONE) {
                    double x;
                    if ((st = ply_value(&in, p->type, p, &x)) != GEOM_OK)
                        goto done;
                    if (role >= R_R && role <= R_A)
                        x *= color_scale(p->type);
                    if (role >= R_FR && role <= R_FA)
                        x *= color_scale(p->type);
                    vv[role] = x;
                    continue;
                }
                size_t n = 0;
                if ((st = ply_list_count(&in, p, &n)) != GEOM_OK)
                    goto done;
                if (role == R_INDICES && !got_indices) {
                    got_indices = 1;
                    nidx = n;
                    if (s->fidx.n + n > c->max_elements) {
                        st = geom__meshio_check_count(c, s->fidx.n + n, "face corners", loc,
                                                      !h.ascii);
                        goto done;
                    }
                    if (MIO_RESERVE(c->alloc, s->fidx, n) != GEOM_OK) {
                        st = GEOM_ERR_NOMEM;
                        goto done;
                    }
                    for (size_t k = 0; k < n; k++) {
                        double x;
                        if ((st = ply_value(&in, p->type, p, &x)) != GEOM_OK)
                            goto done;
                        if (x < 0 || x >= 4294967295.0) {
                            if (!in.ascii)
                                in.pos = in.tok_off;
                            st = ply_data_err(&in, p, in.tok_line, in.tok_col,
                                              "negative or too large vertex index");
                            goto done;
                        }
                        s->fidx.p[s->fidx.n++] = (uint32_t)x;
                    }
                } else if (role == R_TEXCOORD) {
                    if (MIO_RESERVE(c->alloc, tex, n) != GEOM_OK) {
                        st = GEOM_ERR_NOMEM;
                        goto done;
                    }
                    for (size_t k = 0; k < n; k++)
                        if ((st = ply_value(&in, p->type, p, &tex.p[tex.n++])) != GEOM_OK)
                            goto done;
                } else {
                    for (size_t k = 0; k < n; k++) {
                        double x;
                        if ((st = ply_value(&in, p->type, p, &x)) != GEOM_OK)
                            goto done;
                    }
                }
            }
            if (is_v) {
                s->pos.p[s->pos.n++] = vv[R_X];
                s->pos.p[s->pos.n++] = vv[R_Y];
                s->pos.p[s->pos.n++] = vv[R_Z];
                if (cn && (MIO_PUSH(c->alloc, cn->val, vv[R_NX]) != GEOM_OK ||
                           MIO_PUSH(c->alloc, cn->val, vv[R_NY]) != GEOM_OK ||
                           MIO_PUSH(c->alloc, cn->val, vv[R_NZ]) != GEOM_OK)) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
                if (cuv && (MIO_PUSH(c->alloc, cuv->val, vv[R_U]) != GEOM_OK ||
                            MIO_PUSH(c->alloc, cuv->val, vv[R_V]) != GEOM_OK)) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
                if (ccol && (MIO_PUSH(c->alloc, ccol->val, vv[R_R]) != GEOM_OK ||
                             MIO_PUSH(c->alloc, ccol->val, vv[R_G]) != GEOM_OK ||
                             MIO_PUSH(c->alloc, ccol->val, vv[R_B]) != GEOM_OK ||
                             (has_alpha && MIO_PUSH(c->alloc, ccol->val, vv[R_A]) != GEOM_OK))) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            } else if (is_f) {
                if (s->fsize.n >= c->max_elements) {
                    st = geom__meshio_check_count(c, s->fsize.n + 1, "faces", loc, !h.ascii);
                    goto done;
                }
                if (MIO_PUSH(c->alloc, s->fsize, (uint32_t)nidx) != GEOM_OK ||
                    mio_floc_push(c->alloc, s, loc) != GEOM_OK) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
                if (ctex) {
                    int use = tex.n == 2 * nidx;
                    if (!use && tex.n != 0) {
                        st = ply_data_err(&in, NULL, in.cur.line, 0,
                                          "texcoord list length is not twice the number of "
                                          "vertices");
                        goto done;
                    }
                    size_t pool = ctex->val.n / 2;
                    if (MIO_RESERVE(c->alloc, ctex->idx, nidx) != GEOM_OK ||
                        (use && MIO_RESERVE(c->alloc, ctex->val, tex.n) != GEOM_OK)) {
                        st = GEOM_ERR_NOMEM;
                        goto done;
                    }
                    for (size_t k = 0; k < nidx; k++)
                        ctex->idx.p[ctex->idx.n++] = use ? (uint32_t)(pool + k) : GEOM_INVALID_INDEX;
                    if (use && tex.n) {
                        memcpy(ctex->val.p + ctex->val.n, tex.p, tex.n * sizeof(double));
                        ctex->val.n += tex.n;
                    }
                }
                if (cfcol && (MIO_PUSH(c->alloc, cfcol->val, vv[R_FR]) != GEOM_OK ||
                              MIO_PUSH(c->alloc, cfcol->val, vv[R_FG]) != GEOM_OK ||
                              MIO_PUSH(c->alloc, cfcol->val, vv[R_FB]) != GEOM_OK ||
                              (has_falpha && MIO_PUSH(c->alloc, cfcol->val, vv[R_FA]) != GEOM_OK))) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            }
        }
    }
    /* Nothing but white space may follow the declared elements. */
    if (st != GEOM_OK) {
        /* reported */
    } else if (h.ascii) {
        const char *tok;
        size_t tl, line, col;
        if (geom__meshio_cursor_next(&in.cur, &tok, &tl, &line, &col))
            st = geom__meshio_err_line(c, GEOM_ERR_PARSE, line, col,
                                       "data after the last declared element");
    } else {
        const unsigned char *d = c->data;
        size_t at = in.pos;
        while (at < c->size && mio_is_space((char)d[at]))
            at++;
        if (at < c->size)
            st = geom__meshio_err_off(c, GEOM_ERR_PARSE, in.pos,
                                      "%zu bytes after the last declared element",
                                      c->size - in.pos);
    }
done:
    if (st == GEOM_ERR_NOMEM && c->diag && c->diag->status != GEOM_ERR_NOMEM)
        geom__meshio_err_line(c, st, 0, 0, "out of memory");
    MIO_FREE(c->alloc, tex);
    MIO_FREE(c->alloc, h.elems);
    MIO_FREE(c->alloc, h.props);
    return st;
}

/* --------------------------------------------------------------- writing */

static void put_ply_value(mio_sink *k, double v, int ascii, int be, int as_float)
{
    if (ascii) {
        geom__meshio_put_double(k, v);
    } else if (!isfinite(v)) {
        geom__meshio_sink_fail(k, GEOM_ERR_INVALID_ARG, "cannot write a non-finite value");
    } else if (as_float) {
        geom__meshio_put_f32(k, (float)v, be);
    } else {
        geom__meshio_put_f64(k, v, be);
    }
}

static unsigned char to_u8(double v)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 255;
    return (unsigned char)(v * 255.0 + 0.5);
}

/* n color components (0..1) as uchar: " r g b[ a]" in ASCII, n bytes else. */
static void put_colors(mio_sink *k, const double *col, int n, int ascii)
{
    for (int j = 0; j < n; j++) {
        unsigned char u = to_u8(col[j]);
        if (ascii) {
            mio_putc(k, ' ');
            geom__meshio_put_u64(k, u);
        } else {
            geom__meshio_put(k, &u, 1);
        }
    }
}

geom_status geom__meshio_write_ply(const geom_mesh *m, const geom_meshio_write_options *opt,
                                   mio_sink *k)
{
    int ascii = opt->encoding == GEOM_MESHIO_ENCODING_ASCII;
    int be = opt->encoding == GEOM_MESHIO_ENCODING_BINARY_BE;
    int as_float = opt->ply_float && !ascii;
    /* tangents (x, y, z and the bitangent sign w) as tangent_x..tangent_w:
     * PLY has no standard name for them */
    mio_export e;
    geom_status st = geom__meshio_export_prepare(&e, m, opt, 1, k);
    if (st != GEOM_OK)
        return st;
    int has_n = mio_export_has(&e, MIO_ATTR_NORMAL), has_uv = mio_export_has(&e, MIO_ATTR_UV);
    int has_c = mio_export_has(&e, MIO_ATTR_COLOR), has_t = mio_export_has(&e, MIO_ATTR_TANGENT);
    int alpha = has_c && geom_mesh_channel_ncomp(m, e.chan[MIO_ATTR_COLOR]) >= 4;
    uint32_t fcol = e.fcol;
    int falpha = fcol != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, fcol) >= 4;
    const char *ft = as_float ? "float" : "double";

    geom__meshio_puts(k, "ply\nformat ");
    geom__meshio_puts(k, ascii ? "ascii" : be ? "binary_big_endian" : "binary_little_endian");
    geom__meshio_puts(k, " 1.0\ncomment written by libgeom ");
    geom__meshio_puts(k, geom_version_string());
    geom__meshio_puts(k, "\nelement vertex ");
    geom__meshio_put_u64(k, e.nv);
    mio_putc(k, '\n');
    static const char *const xyz[] = {"x", "y", "z"}, *const nxyz[] = {"nx", "ny", "nz"},
                              *const uv[] = {"s", "t"}, /* Blender, MeshLab */
                              *const rgba[] = {"red", "green", "blue", "alpha"},
                              *const txyzw[] = {"tangent_x", "tangent_y", "tangent_z",
                                                "tangent_w"};
    const char *const *fnames[4] = {xyz, nxyz, uv, txyzw};
    const int fon[4] = {1, has_n, has_uv, has_t};
    static const int fcount[4] = {3, 3, 2, 4};
    for (int a = 0; a < 4; a++)
        for (int i = 0; fon[a] && i < fcount[a]; i++) {
            geom__meshio_puts(k, "property ");
            geom__meshio_puts(k, ft);
            mio_putc(k, ' ');
            geom__meshio_puts(k, fnames[a][i]);
            mio_putc(k, '\n');
        }
    for (int i = 0; has_c && i < 3 + alpha; i++) {
        geom__meshio_puts(k, "property uchar ");
        geom__meshio_puts(k, rgba[i]);
        mio_putc(k, '\n');
    }
    geom__meshio_puts(k, "element face ");
    geom__meshio_put_u64(k, e.nf);
    geom__meshio_puts(k, e.max_valence > 255 ? "\nproperty list int int vertex_indices\n"
                                             : "\nproperty list uchar int vertex_indices\n");
    for (int i = 0; fcol != GEOM_INVALID_INDEX && i < 3 + falpha; i++) {
        geom__meshio_puts(k, "property uchar ");
        geom__meshio_puts(k, rgba[i]);
        mio_putc(k, '\n');
    }
    geom__meshio_puts(k, "end_header\n");
    if (e.nv > INT32_MAX)
        geom__meshio_sink_fail(k, GEOM_ERR_LIMIT, "too many vertices for PLY int indices");

    const double *pos = geom_mesh_cpositions(m);
    for (size_t i = 0; i < e.nv && k->status == GEOM_OK; i++) {
        const double *p = pos + 3 * (size_t)e.vert[i];
        double val[4];
        for (int j = 0; j < 3; j++) {
            if (ascii && j)
                mio_putc(k, ' ');
            put_ply_value(k, p[j], ascii, be, as_float);
        }
        /* the floating-point attributes, in header order */
        static const int fattr[3] = {MIO_ATTR_NORMAL, MIO_ATTR_UV, MIO_ATTR_TANGENT};
        const int fhas[3] = {has_n, has_uv, has_t};
        static const size_t fcomp[3] = {3, 2, 4};
        for (int a = 0; a < 3; a++) {
            if (!fhas[a])
                continue;
            val[3] = 1.0; /* a tangent without w */
            geom__meshio_export_value(&e, m, fattr[a], i, val, fcomp[a]);
            for (size_t j = 0; j < fcomp[a]; j++) {
                if (ascii)
                    mio_putc(k, ' ');
                put_ply_value(k, val[j], ascii, be, as_float);
            }
        }
        if (has_c) {
            val[3] = 1.0;
            geom__meshio_export_value(&e, m, MIO_ATTR_COLOR, i, val, 4);
            put_colors(k, val, 3 + alpha, ascii);
        }
        if (ascii)
            mio_putc(k, '\n');
    }
    size_t off = 0;
    for (size_t f = 0; f < e.nf && k->status == GEOM_OK; f++) {
        uint32_t n = e.fsize[f];
        if (ascii) {
            geom__meshio_put_u64(k, n);
            for (uint32_t j = 0; j < n; j++) {
                mio_putc(k, ' ');
                geom__meshio_put_u64(k, e.fidx[off + j]);
            }
        } else {
            if (e.max_valence > 255) {
                geom__meshio_put_u32(k, n, be);
            } else {
                unsigned char u = (unsigned char)n;
                geom__meshio_put(k, &u, 1);
            }
            for (uint32_t j = 0; j < n; j++)
                geom__meshio_put_u32(k, e.fidx[off + j], be);
        }
        off += n;
        double col[4];
        if (geom__meshio_export_face_color(&e, m, f, col))
            put_colors(k, col, 3 + falpha, ascii);
        if (ascii)
            mio_putc(k, '\n');
    }
    geom__meshio_export_free(&e);
    return k->status;
}
