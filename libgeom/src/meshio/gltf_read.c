/*
 * glTF 2.0 binary (.glb) reader: the triangle primitives (mode 4) of the
 * first mesh, POSITION (float VEC3, required), NORMAL (VEC3), TEXCOORD_0
 * (VEC2), TANGENT (VEC4) and COLOR_0 (float VEC3/VEC4) accessors and u8/u16/
 * u32 indices (or none: consecutive triangles), from the GLB's own BIN
 * chunk (buffer 0; external buffers and data URIs are refused). Vertices are
 * welded by exact position, so the per-corner glTF vertices that the writer
 * splits at seams become one mesh again; the attributes become CORNER
 * channels ("normal", "uv", "tangent", "color") whose pools are the glTF
 * vertex arrays, so seams round-trip exactly. TEXCOORD_0's v and TANGENT's
 * w are flipped back (1 - v, -w), undoing the writer's convention change.
 * With the read option gltf_z_up, positions, normals and tangents are
 * rotated from glTF's Y-up frame to Z-up, (x, y, z) -> (x, -z, y): the
 * inverse of the writer's gltf_z_up, exact (a sign and a swap).
 * Layout per the glTF 2.0 specification; every offset, stride and count is
 * checked against the chunk sizes before it is used.
 */
#include "meshio/meshio_internal.h"

#include <string.h>

#define GLB_MAGIC 0x46546C67u
#define GLB_JSON 0x4E4F534Au
#define GLB_BIN 0x004E4942u
#define JSON_MAX_DEPTH 64

/* ----------------------------------------------------------- tiny JSON */

enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };

typedef struct jnode {
    int type;
    double num;
    const char *str; /* J_STR: the raw text between the quotes */
    size_t len;
    const char *key; /* member of an object: its key (raw) */
    size_t keylen;
    uint32_t first, next; /* children list; UINT32_MAX: none */
} jnode;

typedef struct jparse {
    const char *s;
    size_t n, pos;
    jnode *nodes;
    size_t count, cap;
    const geom_allocator *alloc;
    int depth;
} jparse;

static void ws(jparse *p)
{
    while (p->pos < p->n && (p->s[p->pos] == ' ' || p->s[p->pos] == '\t' ||
                             p->s[p->pos] == '\n' || p->s[p->pos] == '\r'))
        p->pos++;
}

static int new_node(jparse *p, int type, uint32_t *id)
{
    if (p->count == p->cap) {
        size_t cap = p->cap;
        if (geom__grow(p->alloc, (void **)&p->nodes, &cap, p->count + 1, sizeof *p->nodes) !=
            GEOM_OK)
            return -1;
        p->cap = cap;
    }
    jnode *nd = &p->nodes[p->count];
    memset(nd, 0, sizeof *nd);
    nd->type = type;
    nd->first = nd->next = UINT32_MAX;
    *id = (uint32_t)p->count++;
    return 0;
}

static int parse_string(jparse *p, const char **str, size_t *len)
{
    if (p->pos >= p->n || p->s[p->pos] != '"')
        return -1;
    size_t start = ++p->pos;
    while (p->pos < p->n && p->s[p->pos] != '"') {
        if ((unsigned char)p->s[p->pos] < 0x20)
            return -1;
        if (p->s[p->pos] == '\\')
            p->pos++;
        p->pos++;
    }
    if (p->pos >= p->n)
        return -1;
    *str = p->s + start;
    *len = p->pos - start;
    p->pos++;
    return 0;
}

/* -1 syntax, -2 no memory */
static int parse_value(jparse *p, uint32_t *out)
{
    ws(p);
    if (p->pos >= p->n || ++p->depth > JSON_MAX_DEPTH)
        return -1;
    char ch = p->s[p->pos];
    uint32_t id;
    int rc = 0;
    if (ch == '{' || ch == '[') {
        int obj = ch == '{';
        if (new_node(p, obj ? J_OBJ : J_ARR, &id) != 0)
            return -2;
        p->pos++;
        ws(p);
        uint32_t last = UINT32_MAX;
        if (p->pos < p->n && p->s[p->pos] == (obj ? '}' : ']')) {
            p->pos++;
        } else {
            for (;;) {
                const char *key = NULL;
                size_t klen = 0;
                ws(p);
                if (obj) {
                    if (parse_string(p, &key, &klen) != 0)
                        return -1;
                    ws(p);
                    if (p->pos >= p->n || p->s[p->pos] != ':')
                        return -1;
                    p->pos++;
                }
                uint32_t child;
                if ((rc = parse_value(p, &child)) != 0)
                    return rc;
                p->nodes[child].key = key;
                p->nodes[child].keylen = klen;
                if (last == UINT32_MAX)
                    p->nodes[id].first = child;
                else
                    p->nodes[last].next = child;
                last = child;
                ws(p);
                if (p->pos < p->n && p->s[p->pos] == ',') {
                    p->pos++;
                    continue;
                }
                if (p->pos < p->n && p->s[p->pos] == (obj ? '}' : ']')) {
                    p->pos++;
                    break;
                }
                return -1;
            }
        }
    } else if (ch == '"') {
        if (new_node(p, J_STR, &id) != 0)
            return -2;
        const char *s;
        size_t len;
        if (parse_string(p, &s, &len) != 0)
            return -1;
        p->nodes[id].str = s;
        p->nodes[id].len = len;
    } else if (ch == 't' || ch == 'f' || ch == 'n') {
        const char *w = ch == 't' ? "true" : ch == 'f' ? "false" : "null";
        size_t wl = strlen(w);
        if (p->n - p->pos < wl || memcmp(p->s + p->pos, w, wl) != 0)
            return -1;
        if (new_node(p, ch == 'n' ? J_NULL : J_BOOL, &id) != 0)
            return -2;
        p->nodes[id].num = ch == 't';
        p->pos += wl;
    } else {
        size_t start = p->pos;
        while (p->pos < p->n && strchr("+-0123456789.eE", p->s[p->pos]) && p->s[p->pos])
            p->pos++;
        double v;
        if (p->pos == start || geom__meshio_parse_double(p->s + start, p->pos - start, &v) != 0)
            return -1;
        if (new_node(p, J_NUM, &id) != 0)
            return -2;
        p->nodes[id].num = v;
    }
    p->depth--;
    *out = id;
    return 0;
}

static const jnode *jget(const jparse *p, const jnode *obj, const char *key)
{
    if (!obj || obj->type != J_OBJ)
        return NULL;
    size_t kl = strlen(key);
    for (uint32_t c = obj->first; c != UINT32_MAX; c = p->nodes[c].next)
        if (p->nodes[c].keylen == kl && memcmp(p->nodes[c].key, key, kl) == 0)
            return &p->nodes[c];
    return NULL;
}

static const jnode *jat(const jparse *p, const jnode *arr, size_t i)
{
    if (!arr || arr->type != J_ARR)
        return NULL;
    for (uint32_t c = arr->first; c != UINT32_MAX; c = p->nodes[c].next, i--)
        if (i == 0)
            return &p->nodes[c];
    return NULL;
}

/* A non-negative integer member (def when absent); -1 when malformed. */
static int64_t jint(const jparse *p, const jnode *obj, const char *key, int64_t def)
{
    const jnode *v = jget(p, obj, key);
    if (!v)
        return def;
    if (v->type != J_NUM || !(v->num >= 0) || v->num > 9007199254740992.0 ||
        v->num != (double)(int64_t)v->num)
        return -1;
    return (int64_t)v->num;
}

static int jstr_is(const jnode *v, const char *s)
{
    return v && v->type == J_STR && v->len == strlen(s) && memcmp(v->str, s, v->len) == 0;
}

/* ----------------------------------------------------------- accessors */

typedef struct glb_acc {
    const unsigned char *base; /* first element */
    size_t count, stride, ncomp;
    unsigned ctype;
} glb_acc;

static uint32_t rd32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static geom_status accessor(mio_ctx *c, const jparse *p, const jnode *root, int64_t index,
                            const unsigned char *bin, size_t binlen, const char *what,
                            glb_acc *out)
{
    const jnode *acc = jat(p, jget(p, root, "accessors"), (size_t)(index < 0 ? 0 : index));
    if (index < 0 || !acc)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 0, "%s: accessor %lld does not exist", what,
                                    (long long)index);
    int64_t viewi = jint(p, acc, "bufferView", -2), aoff = jint(p, acc, "byteOffset", 0),
            count = jint(p, acc, "count", -1), ctype = jint(p, acc, "componentType", -1);
    const jnode *type = jget(p, acc, "type");
    size_t ncomp = jstr_is(type, "SCALAR") ? 1 : jstr_is(type, "VEC2") ? 2
                   : jstr_is(type, "VEC3") ? 3 : jstr_is(type, "VEC4") ? 4 : 0;
    size_t csize = ctype == 5126 || ctype == 5125 ? 4 : ctype == 5123 || ctype == 5122 ? 2
                   : ctype == 5121 || ctype == 5120 ? 1 : 0;
    if (viewi < 0 || aoff < 0 || count < 0 || !ncomp || !csize)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                    "%s: accessor %lld is malformed or sparse (bufferView, "
                                    "byteOffset, count, componentType, type)",
                                    what, (long long)index);
    const jnode *view = jat(p, jget(p, root, "bufferViews"), (size_t)viewi);
    int64_t buf = jint(p, view, "buffer", -1), voff = jint(p, view, "byteOffset", 0),
            vlen = jint(p, view, "byteLength", -1), stride = jint(p, view, "byteStride", 0);
    if (!view || buf != 0 || voff < 0 || vlen < 0 || stride < 0)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                    "%s: bufferView %lld is malformed or not in the GLB's BIN "
                                    "chunk",
                                    what, (long long)viewi);
    size_t esize = csize * ncomp;
    size_t st = stride ? (size_t)stride : esize;
    if (st < esize || (uint64_t)voff + (uint64_t)vlen > binlen ||
        (count > 0 && (uint64_t)aoff + (uint64_t)(count - 1) * st + esize > (uint64_t)vlen))
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                    "%s: accessor %lld reaches beyond its bufferView or the BIN "
                                    "chunk",
                                    what, (long long)index);
    out->base = bin + voff + aoff;
    out->count = (size_t)count;
    out->stride = st;
    out->ncomp = ncomp;
    out->ctype = (unsigned)ctype;
    return GEOM_OK;
}

static float rdf(const unsigned char *b)
{
    uint32_t u = rd32(b);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* glTF's Y-up frame to Z-up: (x, y, z) -> (x, -z, y), the inverse of the
 * writer's (x, y, z) -> (x, z, -y). */
static void z_up(double *v)
{
    double y = v[1];
    v[1] = -v[2];
    v[2] = y;
}

static uint32_t rd_index(const glb_acc *a, size_t i)
{
    const unsigned char *b = a->base + i * a->stride;
    if (a->ctype == 5125)
        return rd32(b);
    if (a->ctype == 5123)
        return (uint32_t)b[0] | (uint32_t)b[1] << 8;
    return b[0];
}

/* ------------------------------------------------------------- reader */

static uint64_t pos_hash(const double *v) { return geom__hash_doubles(v, 3); }

geom_status geom__meshio_read_glb(mio_ctx *c, mio_soup *s)
{
    const unsigned char *d = c->data;
    size_t n = c->size;
    s->loc_is_offset = 1;
    if (n < 20 || rd32(d) != GLB_MAGIC)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 0, "not a glTF binary file (magic 'glTF')");
    if (rd32(d + 4) != 2)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 4, "glTF version %lu, expected 2",
                                    (unsigned long)rd32(d + 4));
    size_t total = rd32(d + 8);
    if (total > n || total < 20)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 8,
                                    "header length %zu but the file has %zu bytes", total, n);
    size_t jlen = rd32(d + 12);
    if (rd32(d + 16) != GLB_JSON || jlen > total - 20)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, 12, "first chunk is not a JSON chunk "
                                                           "within the file");
    const unsigned char *bin = NULL;
    size_t binlen = 0, off = 20 + jlen;
    off = (off + 3) & ~(size_t)3;
    if (off + 8 <= total) {
        size_t blen = rd32(d + off);
        if (rd32(d + off + 4) == GLB_BIN) {
            if (blen > total - off - 8)
                return geom__meshio_err_off(c, GEOM_ERR_PARSE, off,
                                            "BIN chunk of %zu bytes beyond the end", blen);
            bin = d + off + 8;
            binlen = blen;
        }
    }
    jparse p;
    memset(&p, 0, sizeof p);
    p.s = (const char *)d + 20;
    p.n = jlen;
    p.alloc = c->alloc;
    uint32_t rootid;
    int rc = parse_value(&p, &rootid);
    geom_status st = GEOM_OK;
    if (rc == -2) {
        st = geom__meshio_err_off(c, GEOM_ERR_NOMEM, 20, "out of memory");
        goto done;
    }
    if (rc != 0 || p.nodes[rootid].type != J_OBJ) {
        st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 20 + p.pos, "malformed JSON chunk");
        goto done;
    }
    const jnode *root = &p.nodes[rootid];
    const jnode *prims = jget(&p, jat(&p, jget(&p, root, "meshes"), 0), "primitives");
    if (!prims || prims->type != J_ARR) {
        st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 20, "no meshes[0].primitives");
        goto done;
    }
    static const char *const attr_name[4] = {"NORMAL", "TEXCOORD_0", "TANGENT", "COLOR_0"};
    static const char *const chan_name[4] = {"normal", "uv", "tangent", "color"};
    static const size_t want_comp[4] = {3, 2, 4, 0};
    mio_chan *ch[4] = {NULL, NULL, NULL, NULL};
    geom__hindex hash;
    memset(&hash, 0, sizeof hash);
    MIO_ARR(uint32_t) remap;
    memset(&remap, 0, sizeof remap);
    size_t pool_base = 0; /* glTF vertices of earlier primitives */
    for (size_t pi = 0; st == GEOM_OK; pi++) {
        const jnode *prim = jat(&p, prims, pi);
        if (!prim)
            break;
        if (jint(&p, prim, "mode", 4) != 4)
            continue; /* points and lines are not faces */
        const jnode *attrs = jget(&p, prim, "attributes");
        glb_acc pos, acc[4], idx;
        int has[4] = {0, 0, 0, 0};
        if (!bin) {
            st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                      "no BIN chunk: external buffers are not supported");
            break;
        }
        st = accessor(c, &p, root, jint(&p, attrs, "POSITION", -1), bin, binlen, "POSITION", &pos);
        if (st != GEOM_OK)
            break;
        if (pos.ctype != 5126 || pos.ncomp != 3) {
            st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 0, "POSITION must be float VEC3");
            break;
        }
        st = geom__meshio_check_count(c, pool_base + pos.count, "vertices", 0, 1);
        for (int a = 0; a < 4 && st == GEOM_OK; a++) {
            int64_t ai = jint(&p, attrs, attr_name[a], -2);
            if (ai == -2)
                continue;
            st = accessor(c, &p, root, ai, bin, binlen, attr_name[a], &acc[a]);
            if (st != GEOM_OK)
                break;
            if (acc[a].ctype != 5126 || acc[a].count != pos.count ||
                (want_comp[a] ? acc[a].ncomp != want_comp[a] : acc[a].ncomp < 3))
                continue; /* normalised integer colours and odd shapes: skipped */
            has[a] = 1;
        }
        if (st != GEOM_OK)
            break;
        int64_t ii = jint(&p, prim, "indices", -2);
        size_t nidx = pos.count;
        if (ii != -2) {
            st = accessor(c, &p, root, ii, bin, binlen, "indices", &idx);
            if (st != GEOM_OK)
                break;
            if (idx.ncomp != 1 || (idx.ctype != 5121 && idx.ctype != 5123 && idx.ctype != 5125)) {
                st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                          "indices must be unsigned byte/short/int scalars");
                break;
            }
            nidx = idx.count;
        }
        if (nidx % 3) {
            st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                      "primitive %zu: %zu indices is not a multiple of 3", pi,
                                      nidx);
            break;
        }
        /* weld positions, keep each glTF vertex's mesh vertex in remap */
        if (geom__hindex_reserve(&hash, c->alloc, mio_soup_nv(s) + pos.count) != GEOM_OK ||
            MIO_RESERVE(c->alloc, remap, pos.count) != GEOM_OK) {
            st = geom__meshio_err_off(c, GEOM_ERR_NOMEM, 0, "out of memory");
            break;
        }
        for (size_t i = 0; i < pos.count && st == GEOM_OK; i++) {
            double v[3];
            for (int j = 0; j < 3; j++)
                v[j] = (double)rdf(pos.base + i * pos.stride + 4 * (size_t)j);
            if (c->gltf_z_up)
                z_up(v);
            uint64_t h = pos_hash(v);
            size_t it = 0;
            uint32_t cand;
            while ((cand = geom__hindex_next(&hash, h, &it)) != UINT32_MAX)
                if (memcmp(s->pos.p + 3 * (size_t)cand, v, sizeof v) == 0)
                    break;
            if (cand == UINT32_MAX) {
                cand = (uint32_t)mio_soup_nv(s);
                if (MIO_RESERVE(c->alloc, s->pos, 3) != GEOM_OK) {
                    st = GEOM_ERR_NOMEM;
                    break;
                }
                memcpy(s->pos.p + s->pos.n, v, sizeof v);
                s->pos.n += 3;
                geom__hindex_insert_at(&hash, h, it, cand);
            }
            remap.p[remap.n++] = cand;
        }
        /* attribute pools: the glTF vertices */
        for (int a = 0; a < 4 && st == GEOM_OK; a++) {
            if (!has[a])
                continue;
            size_t nc = a == 3 ? acc[a].ncomp : want_comp[a];
            if (!ch[a]) {
                ch[a] = geom__meshio_soup_chan(s, c->alloc, chan_name[a], GEOM_MESH_DOMAIN_CORNER,
                                               nc, NULL);
                if (!ch[a]) {
                    st = GEOM_ERR_NOMEM;
                    break;
                }
            }
            size_t cnc = ch[a]->ncomp;
            if (MIO_RESERVE(c->alloc, ch[a]->val, (pool_base + pos.count) * cnc) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            while (ch[a]->val.n < pool_base * cnc) /* earlier primitives without it */
                ch[a]->val.p[ch[a]->val.n++] = 0.0;
            for (size_t i = 0; i < pos.count; i++)
                for (size_t j = 0; j < cnc; j++) {
                    double x = j < acc[a].ncomp
                                   ? (double)rdf(acc[a].base + i * acc[a].stride + 4 * j)
                                   : 1.0;
                    if (a == 1 && j == 1)
                        x = 1.0 - x;
                    if (a == 2 && j == 3)
                        x = -x;
                    ch[a]->val.p[ch[a]->val.n++] = x;
                }
            if (c->gltf_z_up && (a == 0 || a == 2)) /* normal, tangent xyz */
                for (size_t i = 0; i < pos.count; i++)
                    z_up(ch[a]->val.p + ch[a]->val.n - (pos.count - i) * cnc);
        }
        /* faces */
        for (size_t t = 0; t < nidx / 3 && st == GEOM_OK; t++) {
            if (MIO_RESERVE(c->alloc, s->fidx, 3) != GEOM_OK ||
                MIO_PUSH(c->alloc, s->fsize, 3) != GEOM_OK ||
                mio_floc_push(c->alloc, s, 0) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            for (int k = 0; k < 3; k++) {
                size_t gi = ii != -2 ? rd_index(&idx, 3 * t + (size_t)k) : 3 * t + (size_t)k;
                if (gi >= pos.count) {
                    st = geom__meshio_err_off(c, GEOM_ERR_PARSE, 0,
                                              "primitive %zu: index %zu beyond its %zu vertices",
                                              pi, gi, pos.count);
                    break;
                }
                s->fidx.p[s->fidx.n++] = remap.p[remap.n - pos.count + gi];
                for (int a = 0; a < 4; a++) {
                    if (!ch[a])
                        continue;
                    uint32_t v = has[a] ? (uint32_t)(pool_base + gi) : GEOM_INVALID_INDEX;
                    if (MIO_PUSH(c->alloc, ch[a]->idx, v) != GEOM_OK) {
                        st = GEOM_ERR_NOMEM;
                        break;
                    }
                }
            }
        }
        pool_base += pos.count;
    }
    /* corners made before a channel appeared get no value */
    for (int a = 0; a < 4 && st == GEOM_OK; a++) {
        if (!ch[a])
            continue;
        size_t have = ch[a]->idx.n, need = s->fidx.n;
        if (have < need) {
            if (MIO_RESERVE(c->alloc, ch[a]->idx, need - have) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            memmove(ch[a]->idx.p + (need - have), ch[a]->idx.p, have * sizeof *ch[a]->idx.p);
            for (size_t i = 0; i < need - have; i++)
                ch[a]->idx.p[i] = GEOM_INVALID_INDEX;
            ch[a]->idx.n = need;
        }
    }
    if (st == GEOM_ERR_NOMEM && c->diag && c->diag->status != GEOM_ERR_NOMEM)
        geom__meshio_err_off(c, GEOM_ERR_NOMEM, 0, "out of memory");
    geom__hindex_free(&hash, c->alloc);
    MIO_FREE(c->alloc, remap);
done:
    geom__free(c->alloc, p.nodes, p.cap * sizeof *p.nodes);
    return st;
}
