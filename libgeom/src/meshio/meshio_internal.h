/*
 * Private helpers of the meshio module: growable arrays, a hash index, text
 * lines and tokens, strict number parsing and exact number formatting, the
 * polygon soup every reader fills (and geom_mesh_build turns into a mesh),
 * the output sink every writer writes to, and the "export view" that
 * unwelds corner attributes for per-vertex formats. Not installed.
 *
 * Shared functions are named geom__meshio_<name> (the library-wide internal
 * prefix geom__, as every internal helper) so that
 * they count as the meshio module's symbols and never clash with public ones.
 */
#ifndef GEOM_SRC_MESHIO_INTERNAL_H
#define GEOM_SRC_MESHIO_INTERNAL_H

#include "core/internal.h"
#include "geom/mesh.h"
#include "geom/meshio.h"

#include <stdarg.h>
#include <stdint.h>
#include <string.h>

/* ------------------------------------------------------- growable arrays */

/* Arrays grown through core's geom__grow (core/grow.c). */

#define MIO_ARR(T)                                                                         \
    struct {                                                                               \
        T *p;                                                                              \
        size_t n, cap;                                                                     \
    }

/* Make room for `extra` more elements in arr; evaluates to a geom_status. */
#define MIO_RESERVE(alloc, arr, extra)                                                     \
    ((arr).n + (extra) <= (arr).cap                                                        \
         ? GEOM_OK                                                                         \
         : geom__grow((alloc), (void **)&(arr).p, &(arr).cap, (arr).n + (extra),   \
                             sizeof *(arr).p))

/* Append one value; evaluates to a geom_status. */
#define MIO_PUSH(alloc, arr, val)                                                          \
    (MIO_RESERVE(alloc, arr, 1) == GEOM_OK ? ((arr).p[(arr).n++] = (val), GEOM_OK)        \
                                           : GEOM_ERR_NOMEM)

#define MIO_FREE(alloc, arr)                                                               \
    do {                                                                                   \
        geom__free((alloc), (arr).p, (arr).cap * sizeof *(arr).p);                          \
        (arr).p = NULL;                                                                    \
        (arr).n = (arr).cap = 0;                                                           \
    } while (0)

/* ---------------------------------------------------------------- numbers */

/* Strict decimal number, the whole token, through geom_parse_double
 * (correctly rounded; no hexadecimal, "inf" or "nan"). Returns 0, or -1
 * (syntax), -2 (overflow to infinity). */
int geom__meshio_parse_double(const char *s, size_t len, double *out);
/* Strict integer [+-]digits. 0, -1 (syntax), -2 (out of int64 range). */
int geom__meshio_parse_int64(const char *s, size_t len, int64_t *out);

/* -------------------------------------------------------- reading context */

typedef struct mio_ctx {
    const geom_allocator *alloc;
    const char *source;
    geom_diag *diag;
    size_t max_elements;          /* resolved (<= UINT32_MAX - 1) */
    int skip_invalid;             /* build.skip_invalid_faces */
    geom_meshio_read_stats *stats; /* never NULL */
    int gltf_z_up;                /* GLB: rotate from glTF's Y-up to Z-up */
    const unsigned char *data;
    size_t size;
} mio_ctx;

/* Set d (if not NULL) to st at source line:col (0: unknown) with the message
 * fmt/ap, formatted before d is touched; returns st. The one formatting path
 * of the readers' and the sink's errors. */
geom_status geom__meshio_vdiag(geom_diag *d, geom_status st, const char *source, size_t line,
                               size_t col, const char *fmt, va_list ap) GEOM_PRINTF(6, 0);
geom_status geom__meshio_err_line(mio_ctx *c, geom_status st, size_t line, size_t col,
                                  const char *fmt, ...) GEOM_PRINTF(5, 6);
geom_status geom__meshio_err_off(mio_ctx *c, geom_status st, uint64_t off, const char *fmt,
                                 ...) GEOM_PRINTF(4, 5);

/* ------------------------------------------------------------ text lines */

/* Physical lines ("\n", "\r\n" or a lone final "\r" end), optionally joined
 * by a trailing backslash (OBJ). */
typedef struct mio_lines {
    const char *data;
    size_t size, pos;
    size_t lineno;      /* first physical line of the current logical line */
    size_t next_lineno; /* number of the next physical line */
    int join_backslash;
    MIO_ARR(char) join; /* scratch for joined lines */
} mio_lines;

void geom__meshio_lines_init(mio_lines *l, const void *data, size_t size, int join_backslash);
void geom__meshio_lines_free(mio_lines *l, const geom_allocator *a);
/* 1 with the line in *s, *len (not NUL-terminated), 0 at the end,
 * GEOM_ERR_NOMEM. */
int geom__meshio_lines_next(mio_lines *l, const geom_allocator *a, const char **s, size_t *len);

static inline int mio_is_space(char ch)
{
    return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f' || ch == '\n';
}

/* Next whitespace-separated token of s[0..len) from *pos; '#' at the start
 * of a token begins a comment to the end when `comments` is nonzero, and
 * also right after a token when it is 2 (OFF: "0#red" is the token "0"; OBJ
 * names may contain '#'). 1 with *t, *tl, else 0. */
static inline int mio_token(const char *s, size_t len, size_t *pos, int comments,
                            const char **t, size_t *tl)
{
    size_t i = *pos;
    while (i < len && mio_is_space(s[i]))
        i++;
    if (i >= len || (comments && s[i] == '#')) {
        *pos = len;
        return 0;
    }
    size_t b = i;
    while (i < len && !mio_is_space(s[i]) && !(comments == 2 && s[i] == '#'))
        i++;
    *t = s + b;
    *tl = i - b;
    *pos = i;
    return 1;
}

static inline int mio_tok_eq(const char *t, size_t tl, const char *word)
{
    size_t n = strlen(word);
    return tl == n && memcmp(t, word, n) == 0;
}

/* Case-insensitive ASCII comparison of a token with a lower-case word. */
int geom__meshio_tok_ieq(const char *t, size_t tl, const char *word);

/* A token cursor over whole text (PLY ascii data, ASCII STL): tokens
 * separated by any whitespace, lines counted for diagnostics. */
typedef struct mio_cursor {
    const char *data;
    size_t size, pos;
    size_t line;       /* 1-based line of pos */
    size_t line_start; /* offset of that line's first byte */
} mio_cursor;

/* Next token: 1 with *t, *tl and its line and column, 0 at the end. */
int geom__meshio_cursor_next(mio_cursor *cur, const char **t, size_t *tl, size_t *line,
                             size_t *col);

/* --------------------------------------------------------------- the soup */

enum { MIO_MAX_CHANNELS = 8 };

typedef struct mio_chan {
    char name[32];
    geom_mesh_domain domain; /* VERTEX, FACE or CORNER */
    size_t ncomp;
    MIO_ARR(double) val;   /* VERTEX/FACE: per element; CORNER: the value pool */
    MIO_ARR(uint32_t) idx; /* CORNER: pool index per soup corner (GEOM_INVALID_INDEX: none) */
} mio_chan;

typedef struct mio_tagrec {
    size_t name; /* offset in strings */
    size_t nint, nfloat, nstring;
    size_t ints, floats, strs; /* offsets in tag_ints, tag_floats, tag_strs */
} mio_tagrec;

#define MIO_NOSTR SIZE_MAX

/* Face locations (a line, or a byte offset in binary input), kept for
 * diagnostics only, as runs of faces whose locations step evenly: faces
 * face0, face0 + 1, ... (up to the next run's face0) are at loc0,
 * loc0 + step, ... One run for a file whose faces are one a line (or one
 * fixed-size record each), instead of 8 bytes a face at the build's peak. */
typedef struct mio_locrun {
    uint64_t loc0;
    uint32_t face0, step;
} mio_locrun;

typedef struct mio_soup {
    MIO_ARR(double) pos;      /* 3 per vertex */
    MIO_ARR(uint32_t) fsize;  /* per face */
    MIO_ARR(uint32_t) fidx;   /* per corner */
    MIO_ARR(mio_locrun) floc; /* face locations (mio_floc_push, geom__meshio_floc) */
    size_t floc_n;            /* faces located so far */
    uint64_t floc_last;       /* the last face's location */
    int loc_is_offset;
    mio_chan chan[MIO_MAX_CHANNELS];
    size_t nchan;
    MIO_ARR(uint32_t) fgroup; /* per face, when groups exist */
    MIO_ARR(size_t) groups;   /* 4 string offsets per group (MIO_NOSTR: unset) */
    MIO_ARR(char) strings;    /* NUL-terminated strings */
    MIO_ARR(mio_tagrec) tags;
    MIO_ARR(int64_t) tag_ints;
    MIO_ARR(double) tag_floats;
    MIO_ARR(size_t) tag_strs;
    MIO_ARR(size_t) mtllibs;  /* string offsets */
    MIO_ARR(size_t) pl_off;   /* polyline start offsets into pl_verts (n+1 when used) */
    MIO_ARR(uint32_t) pl_verts;
} mio_soup;

void geom__meshio_soup_free(mio_soup *s, const geom_allocator *a);
static inline size_t mio_soup_nv(const mio_soup *s) { return s->pos.n / 3; }

/* Record the location of the next face (faces are located in order). */
static inline geom_status mio_floc_push(const geom_allocator *a, mio_soup *s, uint64_t loc)
{
    size_t nr = s->floc.n;
    if (nr) {
        mio_locrun *r = &s->floc.p[nr - 1];
        size_t in_run = s->floc_n - r->face0;
        uint64_t d = loc - s->floc_last;
        if (loc >= s->floc_last &&
            (in_run == 1 ? d <= UINT32_MAX : d == r->step)) {
            r->step = (uint32_t)d;
            s->floc_last = loc;
            s->floc_n++;
            return GEOM_OK;
        }
    }
    if (s->floc_n > UINT32_MAX)
        return GEOM_ERR_LIMIT;
    if (MIO_RESERVE(a, s->floc, 1) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    mio_locrun *r = &s->floc.p[s->floc.n++];
    r->loc0 = loc;
    r->face0 = (uint32_t)s->floc_n;
    r->step = 0;
    s->floc_last = loc;
    s->floc_n++;
    return GEOM_OK;
}
/* The location of face f (< s->floc_n). */
uint64_t geom__meshio_floc(const mio_soup *s, size_t f);
/* The channel (name, domain), created with ncomp comps if absent; for VERTEX
 * and FACE channels created late, existing elements get `fill` (ncomp
 * values, NULL = zeros). NULL on NOMEM or when MIO_MAX_CHANNELS is reached. */
mio_chan *geom__meshio_soup_chan(mio_soup *s, const geom_allocator *a, const char *name,
                                 geom_mesh_domain domain, size_t ncomp, const double *fill);
/* Append a string (len bytes) to the pool; *off receives its offset. */
geom_status geom__meshio_soup_str(mio_soup *s, const geom_allocator *a, const char *str,
                                  size_t len, size_t *off);
/* Limit checks: GEOM_ERR_LIMIT (with a diag) when n exceeds c->max_elements. */
geom_status geom__meshio_check_count(mio_ctx *c, size_t n, const char *what, uint64_t loc,
                                     int loc_is_offset);
/* Validate the faces (sizes >= 3, indices in range and not repeated within
 * a face): with skip_invalid off, the first invalid face is a parse error
 * at its location. Then build the mesh (*out) and copy channels, groups,
 * tags, mtllibs and polylines into it. */
geom_status geom__meshio_soup_finish(mio_ctx *c, mio_soup *s, const geom_meshio_read_options *opt,
                                     geom_mesh **out, geom_mesh_build_report *report);

/* Format readers: fill the soup from c->data[0..c->size). */
geom_status geom__meshio_read_obj(mio_ctx *c, mio_soup *s);
geom_status geom__meshio_read_off(mio_ctx *c, mio_soup *s);
geom_status geom__meshio_read_ply(mio_ctx *c, mio_soup *s);
geom_status geom__meshio_read_stl(mio_ctx *c, mio_soup *s);
geom_status geom__meshio_read_glb(mio_ctx *c, mio_soup *s); /* gltf_read.c */

/* ------------------------------------------------------------------- sink */

/* Writers append bytes to a sink: a memory buffer that either grows (memory
 * output) or is flushed through flush_fn when it fills (file output). The
 * first error sticks in `status` and makes later writes no-ops. */
typedef struct mio_sink {
    const geom_allocator *alloc;
    unsigned char *buf;
    size_t n, cap;
    geom_status (*flush_fn)(void *user, const void *data, size_t n, geom_diag *diag);
    void *user;
    geom_diag *diag;
    geom_status status;
    int precision;
    uint64_t total; /* bytes written so far (flushed + buffered) */
} mio_sink;

void geom__meshio_put(mio_sink *k, const void *p, size_t n);
static inline void mio_putc(mio_sink *k, char ch)
{
    if (k->n < k->cap && k->status == GEOM_OK) {
        k->buf[k->n++] = (unsigned char)ch;
        k->total++;
    } else {
        geom__meshio_put(k, &ch, 1);
    }
}
/* Make room for `need` more bytes at k->buf + k->n (flushing a file sink,
 * growing a memory sink); 0 when the sink has failed. */
int geom__meshio_sink_make_room(mio_sink *k, size_t need);
/* Room for need (<= 1024) bytes to be written at k->buf + k->n directly,
 * then counted with mio_advance; 0 when the sink has failed. */
static inline int mio_room(mio_sink *k, size_t need)
{
    return (k->cap - k->n >= need && k->status == GEOM_OK) ||
           geom__meshio_sink_make_room(k, need);
}
static inline void mio_advance(mio_sink *k, size_t n)
{
    k->n += n;
    k->total += n;
}
void geom__meshio_puts(mio_sink *k, const char *s);
/* A finite double as text: geom_format_double_digits with k->precision (0:
 * the shortest that reads back exactly); non-finite: GEOM_ERR_INVALID_ARG. */
void geom__meshio_put_double(mio_sink *k, double x);
void geom__meshio_put_u64(mio_sink *k, uint64_t v);
void geom__meshio_put_i64(mio_sink *k, int64_t v);
/* Binary scalars in little (be = 0) or big (be = 1) endian order. */
void geom__meshio_put_u16(mio_sink *k, uint16_t v, int be);
void geom__meshio_put_u32(mio_sink *k, uint32_t v, int be);
void geom__meshio_put_f32(mio_sink *k, float v, int be);
void geom__meshio_put_f64(mio_sink *k, double v, int be);
/* Flush buffered bytes (file sinks). */
geom_status geom__meshio_sink_flush(mio_sink *k);
/* The one buffered write path (meshio.c): body(ctx, o, k) puts the bytes
 * into a 64 KiB sink; _stream flushes it through fn(user, ...), _path into
 * an atomic geom_output at path (committed on success, aborted otherwise). */
typedef geom_status (*geom__meshio_body_fn)(const void *ctx, const geom_meshio_write_options *o,
                                            mio_sink *k);
geom_status geom__meshio_write_body_stream(geom__meshio_body_fn body, const void *ctx,
                                           const geom_meshio_write_options *o,
                                           geom_meshio_write_fn fn, void *user, geom_diag *diag);
geom_status geom__meshio_write_body_path(geom__meshio_body_fn body, const void *ctx,
                                         const geom_meshio_write_options *o, const char *path,
                                         geom_diag *diag);
/* Fail the sink with a status and message (first error wins). */
geom_status geom__meshio_sink_fail(mio_sink *k, geom_status st, const char *fmt, ...)
    GEOM_PRINTF(3, 4);

/* Copy len bytes of input text into dst (size bytes, NUL-terminated, cut
 * with "..." when too long) for a message: control bytes and DEL become
 * \xNN, so input cannot drive the terminal; bytes >= 0x80 are kept only as
 * whole valid UTF-8 sequences (else \xNN). */
void geom__meshio_printable(char *dst, size_t size, const char *src, size_t len);

/* ------------------------------------------------------------ export view */

enum { MIO_ATTR_NORMAL = 0, MIO_ATTR_UV = 1, MIO_ATTR_COLOR = 2, MIO_ATTR_TANGENT = 3,
       MIO_NATTR = 4 };

/* The attribute channel to write for `which` (CORNER channel of that name
 * first, else VERTEX), or GEOM_INVALID_INDEX if absent or omitted. */
uint32_t geom__meshio_attr_channel(const geom_mesh *m, int which, unsigned omit);
/* The channels the per-vertex writers (OFF, PLY, glTF) write: chan[a] is
 * geom__meshio_attr_channel's normal (3+ components), uv (2+), color (3+)
 * and, when `tangents`, tangent (3+) channel, else GEOM_INVALID_INDEX. */
void geom__meshio_attr_channels(const geom_mesh *m, unsigned omit, int tangents,
                                uint32_t chan[MIO_NATTR]);

/* A mesh seen as output vertices (one per distinct (vertex, corner indices
 * of the selected CORNER channels)) and faces over them. Output vertex k
 * comes from mesh vertex vert[k]; attribute a's value index is
 * aidx[a][k] (a vertex index for VERTEX channels, a pool index for CORNER
 * channels, GEOM_INVALID_INDEX for none). When no selected channel has
 * seams, output vertex i is the i-th live vertex. */
typedef struct mio_export {
    const geom_allocator *alloc;
    size_t nv;            /* output vertices */
    uint32_t *vert;       /* nv */
    uint32_t *aidx[MIO_NATTR];
    uint32_t chan[MIO_NATTR]; /* channel ids (GEOM_INVALID_INDEX: not written) */
    uint32_t fcol;        /* FACE "color" channel (3+ components) written, or
                             GEOM_INVALID_INDEX (set by export_prepare only) */
    size_t nf;            /* live faces */
    uint32_t *fsize;      /* nf */
    uint32_t *fface;      /* nf: the mesh face */
    uint32_t *fidx;       /* sum of fsize: output vertex indices */
    size_t nidx;
    size_t max_valence;
    size_t cap_v;
} mio_export;

/* Build the view for the channels in chan[] (GEOM_INVALID_INDEX entries are
 * skipped). triangulate: faces with more than three vertices become the
 * triangles geom_mesh_triangulate would make of them, in its face order,
 * one face at a time (the mesh is not copied). GEOM_ERR_NOMEM /
 * GEOM_ERR_LIMIT. */
geom_status geom__meshio_export_build(mio_export *e, const geom_mesh *m,
                                      const uint32_t chan[MIO_NATTR],
                                      const geom_allocator *alloc, int triangulate);
void geom__meshio_export_free(mio_export *e);
/* The view the per-vertex text and binary writers (OFF, PLY) write: the
 * channels of geom__meshio_attr_channels (tangents only when `tangents`),
 * e->fcol the FACE "color" channel (3+ components) unless opt->omit drops
 * colours, e built over them without triangulating. A failure fails the
 * sink and is returned. */
geom_status geom__meshio_export_prepare(mio_export *e, const geom_mesh *m,
                                        const geom_meshio_write_options *opt, int tangents,
                                        mio_sink *k);
/* Whether attribute a is written. */
static inline int mio_export_has(const mio_export *e, int a)
{
    return e->chan[a] != GEOM_INVALID_INDEX;
}
/* The colour of output face f (e->fcol) into rgba, alpha 1 when the channel
 * has three components; the channel's ncomp, or 0 (rgba untouched) when
 * faces have no colour. */
size_t geom__meshio_export_face_color(const mio_export *e, const geom_mesh *m, size_t f,
                                      double rgba[4]);
/* The ncomp values of attribute a at output vertex k into out (zeros when
 * the corner has no value); returns the channel's ncomp (0 if no channel). */
size_t geom__meshio_export_value(const mio_export *e, const geom_mesh *m, int a, size_t k,
                                 double *out, size_t max);

/* Format writers. */
geom_status geom__meshio_write_obj(const geom_mesh *m, const geom_meshio_write_options *o,
                                   mio_sink *k);
geom_status geom__meshio_write_off(const geom_mesh *m, const geom_meshio_write_options *o,
                                   mio_sink *k);
geom_status geom__meshio_write_ply(const geom_mesh *m, const geom_meshio_write_options *o,
                                   mio_sink *k);
geom_status geom__meshio_write_stl(const geom_mesh *m, const geom_meshio_write_options *o,
                                   mio_sink *k);
geom_status geom__meshio_write_glb(const geom_mesh *m, const geom_meshio_write_options *o,
                                   mio_sink *k);

/* GEOM_OK if every live vertex position is finite, else fails the sink
 * with GEOM_ERR_INVALID_ARG naming the vertex. */
geom_status geom__meshio_check_finite(const geom_mesh *m, mio_sink *k);

/* Live vertices densely renumbered: map[v] = new index or GEOM_INVALID_INDEX
 * for deleted vertices (n_vertices entries, allocated); *n_live the count. */
geom_status geom__meshio_vertex_map(const geom_mesh *m, const geom_allocator *a,
                                    uint32_t **map, size_t *n_live);

#endif
