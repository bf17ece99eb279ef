/* meshio entry points: format names and detection, reading from a file or
 * memory, writing to a file (atomically) or memory. */
#include "meshio/meshio_internal.h"

#include <errno.h>
#include <stdio.h>

/* ---------------------------------------------------------------- formats */

static const struct {
    const char *name;
    geom_meshio_format format;
} mio_formats[] = {{"obj", GEOM_MESHIO_FORMAT_OBJ},
                   {"off", GEOM_MESHIO_FORMAT_OFF},
                   {"ply", GEOM_MESHIO_FORMAT_PLY},
                   {"stl", GEOM_MESHIO_FORMAT_STL},
                   {"glb", GEOM_MESHIO_FORMAT_GLB}};

geom_meshio_format geom_meshio_format_from_name(const char *name)
{
    if (!name)
        return GEOM_MESHIO_FORMAT_AUTO;
    const char *base = strrchr(name, '/');
    base = base ? base + 1 : name;
    const char *dot = strrchr(base, '.');
    const char *ext = dot ? dot + 1 : base;
    for (size_t i = 0; i < sizeof mio_formats / sizeof mio_formats[0]; i++)
        if (geom__meshio_tok_ieq(ext, strlen(ext), mio_formats[i].name))
            return mio_formats[i].format;
    return GEOM_MESHIO_FORMAT_AUTO;
}

const char *geom_meshio_format_name(geom_meshio_format format)
{
    if (format == GEOM_MESHIO_FORMAT_AUTO)
        return "auto";
    for (size_t i = 0; i < sizeof mio_formats / sizeof mio_formats[0]; i++)
        if (mio_formats[i].format == format)
            return mio_formats[i].name;
    return "unknown";
}

geom_meshio_format geom_meshio_format_sniff(const void *data, size_t size)
{
    const unsigned char *p = data;
    if (!p || size == 0)
        return GEOM_MESHIO_FORMAT_OBJ;
    if (size >= 4 && memcmp(p, "ply", 3) == 0 && (p[3] == '\n' || p[3] == '\r'))
        return GEOM_MESHIO_FORMAT_PLY;
    if (size >= 4 && memcmp(p, "glTF", 4) == 0)
        return GEOM_MESHIO_FORMAT_GLB;
    if (size >= 84) {
        uint32_t n = (uint32_t)p[80] | (uint32_t)p[81] << 8 | (uint32_t)p[82] << 16 |
                     (uint32_t)p[83] << 24;
        if ((uint64_t)84 + (uint64_t)50 * n == (uint64_t)size)
            return GEOM_MESHIO_FORMAT_STL;
    }
    /* first token, skipping blank lines and '#' comments */
    size_t i = 0;
    for (;;) {
        while (i < size && mio_is_space((char)p[i]))
            i++;
        if (i < size && p[i] == '#') {
            while (i < size && p[i] != '\n')
                i++;
            continue;
        }
        break;
    }
    size_t b = i;
    while (i < size && !mio_is_space((char)p[i]) && p[i] != '#')
        i++;
    const char *t = (const char *)p + b;
    size_t tl = i - b;
    if (tl >= 3 && tl <= 8 && memcmp(t + tl - 3, "OFF", 3) == 0)
        return GEOM_MESHIO_FORMAT_OFF;
    if (tl == 5 && geom__meshio_tok_ieq(t, tl, "solid"))
        return GEOM_MESHIO_FORMAT_STL;
    return GEOM_MESHIO_FORMAT_OBJ;
}

/* ------------------------------------------------------------------ reading */

/* Length of the valid UTF-8 sequence at p (1..4), 0 if not valid. */
static size_t utf8_len(const unsigned char *p, size_t n)
{
    unsigned char c = p[0];
    size_t len;
    uint32_t cp;
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF) {
        len = 2;
        cp = c & 0x1F;
    } else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        cp = c & 0x0F;
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        cp = c & 0x07;
    } else {
        return 0;
    }
    if (n < len)
        return 0;
    for (size_t i = 1; i < len; i++) {
        if ((p[i] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (p[i] & 0x3F);
    }
    if ((len == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
        (len == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
        return 0;
    return len;
}

void geom__meshio_printable(char *dst, size_t size, const char *src, size_t len)
{
    static const char hex[] = "0123456789abcdef";
    const unsigned char *p = (const unsigned char *)src;
    size_t o = 0, i = 0;
    if (size == 0)
        return;
    while (i < len) {
        size_t u = utf8_len(p + i, len - i);
        int esc = u == 0 || (u == 1 && (p[i] < 0x20 || p[i] == 0x7F || p[i] == '\\'));
        size_t need = esc ? 4 : u;
        if (o + need + 4 > size) { /* room for "..." and the NUL */
            if (o + 3 < size)
                memcpy(dst + o, "...", 3), o += 3;
            break;
        }
        if (esc) {
            dst[o++] = '\\';
            dst[o++] = 'x';
            dst[o++] = hex[p[i] >> 4];
            dst[o++] = hex[p[i] & 15];
            i++;
        } else {
            memcpy(dst + o, p + i, u);
            o += u;
            i += u;
        }
    }
    dst[o] = '\0';
}

static int is_binary_stl(const unsigned char *p, size_t size)
{
    if (size < 84)
        return 0;
    uint32_t n = (uint32_t)p[80] | (uint32_t)p[81] << 8 | (uint32_t)p[82] << 16 |
                 (uint32_t)p[83] << 24;
    return (uint64_t)84 + (uint64_t)50 * n == (uint64_t)size;
}

/* The validation edge every reader goes through: a UTF-8 byte-order mark is
 * skipped (*skip = 3); UTF-16/32 text, binary bytes where text is expected
 * and content that is plainly another format than the one claimed (a PLY
 * named .obj) are errors naming the file and what was expected. */
static const char *upper_name(geom_meshio_format f)
{
    static const char *const names[] = {"?", "OBJ", "OFF", "PLY", "STL", "GLB"};
    return (unsigned)f < sizeof names / sizeof names[0] ? names[f] : "?";
}

static geom_status check_content(const unsigned char *p, size_t size, geom_meshio_format fmt,
                                 const char *src, size_t *skip, geom_diag *diag)
{
    const char *want = upper_name(fmt);
    *skip = 0;
    if (fmt == GEOM_MESHIO_FORMAT_STL) { /* binary or ASCII: the STL reader decides */
        if (!is_binary_stl(p, size) && size >= 3 && p[0] == 0xEF && p[1] == 0xBB && p[2] == 0xBF)
            *skip = 3;
        return GEOM_OK;
    }
    if (size >= 3 && p[0] == 0xEF && p[1] == 0xBB && p[2] == 0xBF)
        *skip = 3;
    if (size >= 2 && ((p[0] == 0xFF && p[1] == 0xFE) || (p[0] == 0xFE && p[1] == 0xFF)))
        return geom__diag_set(diag, GEOM_ERR_PARSE, src, 0, 0,
                             "UTF-%s text (byte-order mark %02X %02X): expected %s in ASCII or "
                             "UTF-8",
                             size >= 4 && p[2] == 0 && p[3] == 0 ? "32" : "16", p[0], p[1], want);
    if (size >= 4 && p[0] == 0 && p[1] == 0 && p[2] == 0xFE && p[3] == 0xFF)
        return geom__diag_set(diag, GEOM_ERR_PARSE, src, 0, 0,
                             "UTF-32 text (byte-order mark 00 00 FE FF): expected %s in ASCII "
                             "or UTF-8", want);
    p += *skip;
    size -= *skip;
    geom_meshio_format seen = geom_meshio_format_sniff(p, size);
    int sure = seen != GEOM_MESHIO_FORMAT_OBJ; /* sniffing falls back on OBJ */
    if (sure && seen != fmt)
        return geom__diag_set(diag, GEOM_ERR_PARSE, src, 0, 0,
                             "the content is %s (%s), not %s as %s", upper_name(seen),
                             seen == GEOM_MESHIO_FORMAT_PLY   ? "'ply' header"
                             : seen == GEOM_MESHIO_FORMAT_GLB ? "'glTF' magic"
                             : seen == GEOM_MESHIO_FORMAT_OFF ? "OFF keyword"
                             : is_binary_stl(p, size)         ? "binary STL size"
                                                              : "'solid' keyword",
                             want, "the name or the format option says");
    /* Text formats (and the PLY header, whose binary data follows it): the
     * first 4 KiB hold no control bytes but white space. */
    size_t n = size < 4096 ? size : 4096;
    if (fmt == GEOM_MESHIO_FORMAT_PLY) {
        const unsigned char *end = NULL;
        for (size_t i = 0; i + 10 <= n && !end; i++)
            if (memcmp(p + i, "end_header", 10) == 0)
                end = p + i;
        if (end)
            n = (size_t)(end - p);
    }
    for (size_t i = 0; i < n; i++) {
        unsigned char ch = p[i];
        if ((ch < 0x20 && ch != '\t' && ch != '\n' && ch != '\r' && ch != '\v' && ch != '\f') ||
            ch == 0x7F)
            return geom__diag_set(diag, GEOM_ERR_PARSE, src, 0, 0,
                                 "%s at byte offset %zu: not %s text (binary or corrupt file)",
                                 ch == 0 ? "NUL byte" : "control byte", i + *skip, want);
    }
    return GEOM_OK;
}

/* Parse, then (when `file` is given) let the file's pages go before the
 * mesh is built: the soup holds everything that is needed. */
static geom_status read_data(const void *data, size_t size, geom_file *file,
                             const char *source_name, const geom_meshio_read_options *opt,
                             geom_mesh **out, geom_mesh_build_report *report, geom_diag *diag)
{
    geom_meshio_read_stats local_stats;
    const char *src = source_name ? source_name : "<memory>";
    if (out)
        *out = NULL;
    if (report)
        memset(report, 0, sizeof *report);
    geom_diag_clear(diag);
    if (!out || (!data && size))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, src, 0, 0,
                             "NULL output or data pointer");
    mio_ctx c;
    memset(&c, 0, sizeof c);
    c.alloc = opt ? opt->alloc : NULL;
    c.source = src;
    c.diag = diag;
    c.max_elements = opt && opt->max_elements ? opt->max_elements
                                              : GEOM_MESHIO_DEFAULT_MAX_ELEMENTS;
    if (c.max_elements > UINT32_MAX - 1)
        c.max_elements = UINT32_MAX - 1;
    c.skip_invalid = opt ? opt->build.skip_invalid_faces : 0;
    c.stats = opt && opt->stats ? opt->stats : &local_stats;
    c.gltf_z_up = opt ? opt->gltf_z_up : 0;
    memset(c.stats, 0, sizeof *c.stats);
    c.data = data;
    c.size = size;

    geom_meshio_format fmt = opt ? opt->format : GEOM_MESHIO_FORMAT_AUTO;
    if (fmt == GEOM_MESHIO_FORMAT_AUTO)
        fmt = geom_meshio_format_from_name(source_name);
    if (fmt == GEOM_MESHIO_FORMAT_AUTO)
        fmt = geom_meshio_format_sniff(data, size);
    c.stats->format = fmt;
    if (fmt >= GEOM_MESHIO_FORMAT_OBJ && fmt <= GEOM_MESHIO_FORMAT_STL) {
        size_t skip = 0;
        geom_status cs = check_content(data, size, fmt, src, &skip, diag);
        if (cs != GEOM_OK)
            return cs;
        c.data = (const unsigned char *)data + skip;
        c.size = size - skip;
    }

    mio_soup s;
    memset(&s, 0, sizeof s);
    geom_status st;
    switch (fmt) {
    case GEOM_MESHIO_FORMAT_OBJ: st = geom__meshio_read_obj(&c, &s); break;
    case GEOM_MESHIO_FORMAT_OFF: st = geom__meshio_read_off(&c, &s); break;
    case GEOM_MESHIO_FORMAT_PLY: st = geom__meshio_read_ply(&c, &s); break;
    case GEOM_MESHIO_FORMAT_STL: st = geom__meshio_read_stl(&c, &s); break;
    case GEOM_MESHIO_FORMAT_GLB: st = geom__meshio_read_glb(&c, &s); break;
    default:
        st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, src, 0, 0, "unknown format %d",
                           (int)fmt);
        break;
    }
    if (st == GEOM_ERR_NOMEM && diag && diag->status != GEOM_ERR_NOMEM)
        geom__diag_set(diag, st, src, 0, 0, "out of memory");
    /* Text that is not OBJ at all (/etc/passwd, XML) reads as nothing but
     * unknown statements: an error, not an empty mesh. */
    if (st == GEOM_OK && fmt == GEOM_MESHIO_FORMAT_OBJ && s.pos.n == 0 && s.fsize.n == 0 &&
        c.stats->skipped_statements > 0)
        st = geom__diag_set(diag, GEOM_ERR_PARSE, src, 0, 0,
                           "not an OBJ file: no vertex or face, %zu unknown statement%s (first "
                           "'%s')",
                           c.stats->skipped_statements,
                           c.stats->skipped_statements == 1 ? "" : "s", c.stats->first_skipped);
    if (file)
        geom__file_drop_pages(file);
    if (st == GEOM_OK)
        st = geom__meshio_soup_finish(&c, &s, opt, out, report);
    geom__meshio_soup_free(&s, c.alloc);
    if (st != GEOM_OK && report)
        memset(report, 0, sizeof *report);
    return st;
}

geom_status geom_meshio_read_memory(const void *data, size_t size, const char *source_name,
                                    const geom_meshio_read_options *opt, geom_mesh **out,
                                    geom_mesh_build_report *report, geom_diag *diag)
{
    return read_data(data, size, NULL, source_name, opt, out, report, diag);
}

geom_status geom_meshio_read_file(geom_file *file, const char *source_name,
                                  const geom_meshio_read_options *opt, geom_mesh **out,
                                  geom_mesh_build_report *report, geom_diag *diag)
{
    if (!file) {
        if (out)
            *out = NULL;
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, source_name, 0, 0, "NULL file");
    }
    return read_data(file->data, file->size, file, source_name, opt, out, report, diag);
}

geom_status geom_meshio_read(const char *path, const geom_meshio_read_options *opt,
                             geom_mesh **out, geom_mesh_build_report *report, geom_diag *diag)
{
    if (out)
        *out = NULL;
    geom_diag_clear(diag);
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0, "NULL path or output");
    const geom_allocator *a = opt ? opt->alloc : NULL;
    geom_file f;
    geom_status st = geom_file_map(path, a, &f, diag);
    if (st == GEOM_OK) {
        geom_meshio_read_options o;
        if (opt)
            o = *opt;
        else
            memset(&o, 0, sizeof o);
        if (o.format == GEOM_MESHIO_FORMAT_AUTO)
            o.format = geom_meshio_format_from_name(path);
        st = geom_meshio_read_file(&f, path, &o, out, report, diag);
    }
    geom_file_unmap(&f);
    return st;
}

/* ------------------------------------------------------------------ writing */

static geom_status write_dispatch(const geom_mesh *m, const geom_meshio_write_options *o,
                                  geom_meshio_format fmt, mio_sink *k)
{
    switch (fmt) {
    case GEOM_MESHIO_FORMAT_OBJ: return geom__meshio_write_obj(m, o, k);
    case GEOM_MESHIO_FORMAT_OFF: return geom__meshio_write_off(m, o, k);
    case GEOM_MESHIO_FORMAT_PLY: return geom__meshio_write_ply(m, o, k);
    case GEOM_MESHIO_FORMAT_STL: return geom__meshio_write_stl(m, o, k);
    case GEOM_MESHIO_FORMAT_GLB: return geom__meshio_write_glb(m, o, k);
    default: break;
    }
    return geom__meshio_sink_fail(k, GEOM_ERR_INVALID_ARG, "unknown output format %d", (int)fmt);
}

/* The writers' common prologue: the options defaulted (opt NULL: all
 * zero), the format resolved (from path's name when not given) and the
 * arguments checked. */
static geom_status write_prepare(const geom_mesh *m, const geom_meshio_write_options *opt,
                                 const char *path, geom_meshio_write_options *o,
                                 geom_meshio_format *fmt, geom_diag *diag)
{
    if (opt)
        *o = *opt;
    else
        memset(o, 0, sizeof *o);
    *fmt = o->format ? o->format : geom_meshio_format_from_name(path);
    if (!m)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0, "NULL mesh");
    if (*fmt < GEOM_MESHIO_FORMAT_OBJ || *fmt > GEOM_MESHIO_FORMAT_GLB)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0,
                             "output format not given and not recognised from the name");
    if ((unsigned)o->encoding > GEOM_MESHIO_ENCODING_BINARY_BE)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0, "unknown encoding %d",
                             (int)o->encoding);
    if (*fmt == GEOM_MESHIO_FORMAT_STL && o->encoding == GEOM_MESHIO_ENCODING_BINARY_BE)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0,
                             "binary STL is little endian only");
    return GEOM_OK;
}

geom_status geom_meshio_write_memory(const geom_mesh *m, const geom_meshio_write_options *opt,
                                     void **data, size_t *size, geom_diag *diag)
{
    geom_diag_clear(diag);
    if (data)
        *data = NULL;
    if (size)
        *size = 0;
    if (!data || !size)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL output pointer");
    geom_meshio_write_options o;
    geom_meshio_format fmt;
    geom_status st = write_prepare(m, opt, NULL, &o, &fmt, diag);
    if (st != GEOM_OK)
        return st;
    mio_sink k;
    memset(&k, 0, sizeof k);
    k.alloc = o.alloc;
    k.diag = diag;
    k.precision = o.precision;
    st = write_dispatch(m, &o, fmt, &k);
    if (st == GEOM_OK)
        st = k.status;
    if (st == GEOM_OK) {
        /* the NUL after the data */
        st = geom__grow(k.alloc, (void **)&k.buf, &k.cap, k.n + 1, 1);
        if (st != GEOM_OK)
            geom__diag_set(diag, st, NULL, 0, 0, "out of memory");
    }
    if (st != GEOM_OK) {
        geom__free(k.alloc, k.buf, k.cap);
        if (diag && diag->status == GEOM_OK)
            geom__diag_set(diag, st, NULL, 0, 0, "%s", geom_status_str(st));
        return st;
    }
    k.buf[k.n] = 0;
    /* hand out an allocation of exactly n + 1 bytes so that
     * geom_meshio_buffer_free(data, size) passes the right size */
    if (k.cap != k.n + 1) {
        void *q = geom__realloc(k.alloc, k.buf, k.cap, k.n + 1);
        if (!q) {
            geom__free(k.alloc, k.buf, k.cap);
            return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "out of memory");
        }
        k.buf = q;
    }
    *data = k.buf;
    *size = k.n;
    return GEOM_OK;
}

/* Writes through a 64 KiB sink buffer flushed by flush(user, ...): the one
 * streaming path of every mesh and soup writer; body(ctx, o, k) puts the
 * bytes, a failure inside it is k->status. */
static geom_status write_flushed(geom__meshio_body_fn body, const void *ctx,
                                 const geom_meshio_write_options *o,
                                 geom_status (*flush)(void *, const void *, size_t, geom_diag *),
                                 void *user, const char *path, geom_diag *diag)
{
    mio_sink k;
    memset(&k, 0, sizeof k);
    k.alloc = o->alloc;
    k.diag = diag;
    k.precision = o->precision;
    k.cap = 1 << 16;
    k.buf = geom__alloc(o->alloc, k.cap);
    k.flush_fn = flush;
    k.user = user;
    if (!k.buf)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");
    geom_status st = body(ctx, o, &k);
    if (st == GEOM_OK)
        st = k.status;
    if (st == GEOM_OK)
        st = geom__meshio_sink_flush(&k);
    geom__free(o->alloc, k.buf, k.cap);
    if (st != GEOM_OK && diag && diag->status == GEOM_OK)
        geom__diag_set(diag, st, path, 0, 0, "%s", geom_status_str(st));
    return st;
}

typedef struct stream_user {
    geom_meshio_write_fn fn;
    void *user;
} stream_user;

static geom_status stream_flush(void *user, const void *data, size_t n, geom_diag *diag)
{
    const stream_user *u = user;
    geom_status st = u->fn(u->user, data, n);
    if (st != GEOM_OK && diag && diag->status == GEOM_OK)
        geom__diag_set(diag, st, NULL, 0, 0, "output could not be written: %s",
                      geom_status_str(st));
    return st;
}

/* The sink's flush function over core's cp-like output (core/output.c). */
static geom_status output_flush(void *user, const void *data, size_t n, geom_diag *diag)
{
    return geom_output_write(user, data, n, diag);
}

geom_status geom__meshio_write_body_stream(geom__meshio_body_fn body, const void *ctx,
                                           const geom_meshio_write_options *o,
                                           geom_meshio_write_fn fn, void *user, geom_diag *diag)
{
    stream_user su = {fn, user};
    return write_flushed(body, ctx, o, stream_flush, &su, NULL, diag);
}

geom_status geom__meshio_write_body_path(geom__meshio_body_fn body, const void *ctx,
                                         const geom_meshio_write_options *o, const char *path,
                                         geom_diag *diag)
{
    geom_output at;
    geom_status st = geom_output_open(path, o->alloc, &at, diag);
    if (st != GEOM_OK)
        return st;
    st = write_flushed(body, ctx, o, output_flush, &at, path, diag);
    if (st != GEOM_OK) {
        geom_output_abort(&at);
        if (diag && diag->source[0] == '\0')
            snprintf(diag->source, sizeof diag->source, "%s", path);
        return st;
    }
    return geom_output_commit(&at, diag);
}

typedef struct mesh_body {
    const geom_mesh *m;
    geom_meshio_format fmt;
} mesh_body;

static geom_status write_mesh_body(const void *ctx, const geom_meshio_write_options *o, mio_sink *k)
{
    const mesh_body *b = ctx;
    return write_dispatch(b->m, o, b->fmt, k);
}

geom_status geom_meshio_write_stream(const geom_mesh *m, const geom_meshio_write_options *opt,
                                     geom_meshio_write_fn fn, void *user, geom_diag *diag)
{
    geom_diag_clear(diag);
    if (!fn)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL write function");
    geom_meshio_write_options o;
    geom_meshio_format fmt;
    geom_status st = write_prepare(m, opt, NULL, &o, &fmt, diag);
    if (st != GEOM_OK)
        return st;
    mesh_body b = {m, fmt};
    return geom__meshio_write_body_stream(write_mesh_body, &b, &o, fn, user, diag);
}

void geom_meshio_buffer_free(void *data, size_t size, const geom_allocator *alloc)
{
    if (data)
        geom__free(alloc, data, size + 1);
}

geom_status geom_meshio_write(const geom_mesh *m, const char *path,
                              const geom_meshio_write_options *opt, geom_diag *diag)
{
    geom_diag_clear(diag);
    if (!path)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL path");
    geom_meshio_write_options o;
    geom_meshio_format fmt;
    geom_status st = write_prepare(m, opt, path, &o, &fmt, diag);
    if (st != GEOM_OK)
        return st;
    mesh_body b = {m, fmt};
    return geom__meshio_write_body_path(write_mesh_body, &b, &o, path, diag);
}
