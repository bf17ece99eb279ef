/*
 * Volume file formats: raw samples of eight types after a header offset,
 * NRRD, MetaImage, INRIMAGE-4 and NIfTI-1, each decoded into a dense
 * geom_implicit_volume (float32 for 8/16-bit and float32 samples, float64
 * for 32-bit integers and float64: every value exact). Compressed data goes
 * through the caller's inflate callback (libgeom has no zlib).
 *
 * References: Teem's NRRD format definition (teem.sourceforge.net/nrrd/
 * format.html), the MetaIO documentation (itk.org, MetaImage), the
 * INRIMAGE-4 header as written by CGAL's ImageIO, and the NIfTI-1 header
 * nifti1.h (NIfTI DFWG, 2004).
 */
#include "implicit/implicit_internal.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ----------------------------------------------------------- sample types */

size_t geom_implicit_sample_size(geom_implicit_sample s)
{
    switch (s) {
    case GEOM_IMPLICIT_SAMPLE_U8:
    case GEOM_IMPLICIT_SAMPLE_I8:
        return 1;
    case GEOM_IMPLICIT_SAMPLE_U16:
    case GEOM_IMPLICIT_SAMPLE_I16:
        return 2;
    case GEOM_IMPLICIT_SAMPLE_U32:
    case GEOM_IMPLICIT_SAMPLE_I32:
    case GEOM_IMPLICIT_SAMPLE_F32:
        return 4;
    case GEOM_IMPLICIT_SAMPLE_F64:
        return 8;
    }
    return 0;
}

static const char *const sample_names[] = {"?", "u8", "i8", "u16", "i16", "u32", "i32", "f32", "f64"};

const char *geom_implicit_sample_name(geom_implicit_sample s)
{
    return geom_implicit_sample_size(s) ? sample_names[s] : "?";
}

static int ieq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++) {
        int ca = (*a >= 'A' && *a <= 'Z') ? *a + 32 : *a;
        int cb = (*b >= 'A' && *b <= 'Z') ? *b + 32 : *b;
        if (ca != cb)
            return 0;
    }
    return *a == *b;
}

/* A sample type's name (ASCII case-blind) and the type: the tables of the
 * API's names, NRRD's and MetaImage's. */
typedef struct sample_name {
    const char *n;
    geom_implicit_sample s;
} sample_name;

/* The type named t in the n entries of tab into *s: 0, or -1 (unknown). */
static int sample_lookup(const sample_name *tab, size_t n, const char *t, geom_implicit_sample *s)
{
    for (size_t i = 0; i < n; i++)
        if (ieq(t, tab[i].n)) {
            *s = tab[i].s;
            return 0;
        }
    return -1;
}

geom_status geom_implicit_sample_parse(const char *name, geom_implicit_sample *out)
{
    static const sample_name tab[] = {{"u8", GEOM_IMPLICIT_SAMPLE_U8},       {"uint8", GEOM_IMPLICIT_SAMPLE_U8},
               {"i8", GEOM_IMPLICIT_SAMPLE_I8},       {"int8", GEOM_IMPLICIT_SAMPLE_I8},
               {"u16", GEOM_IMPLICIT_SAMPLE_U16},     {"uint16", GEOM_IMPLICIT_SAMPLE_U16},
               {"i16", GEOM_IMPLICIT_SAMPLE_I16},     {"int16", GEOM_IMPLICIT_SAMPLE_I16},
               {"u32", GEOM_IMPLICIT_SAMPLE_U32},     {"uint32", GEOM_IMPLICIT_SAMPLE_U32},
               {"i32", GEOM_IMPLICIT_SAMPLE_I32},     {"int32", GEOM_IMPLICIT_SAMPLE_I32},
               {"f32", GEOM_IMPLICIT_SAMPLE_F32},     {"float32", GEOM_IMPLICIT_SAMPLE_F32},
               {"float", GEOM_IMPLICIT_SAMPLE_F32},   {"f64", GEOM_IMPLICIT_SAMPLE_F64},
               {"float64", GEOM_IMPLICIT_SAMPLE_F64}, {"double", GEOM_IMPLICIT_SAMPLE_F64}};
    if (!name || !out)
        return GEOM_ERR_INVALID_ARG;
    return sample_lookup(tab, sizeof tab / sizeof tab[0], name, out) == 0 ? GEOM_OK
                                                                          : GEOM_ERR_PARSE;
}

const char *geom_implicit_volume_format_name(geom_implicit_volume_format f)
{
    switch (f) {
    case GEOM_IMPLICIT_VOLUME_AUTO:
        return "auto";
    case GEOM_IMPLICIT_VOLUME_RAW:
        return "raw";
    case GEOM_IMPLICIT_VOLUME_NRRD:
        return "nrrd";
    case GEOM_IMPLICIT_VOLUME_METAIMAGE:
        return "metaimage";
    case GEOM_IMPLICIT_VOLUME_INRIMAGE:
        return "inrimage";
    case GEOM_IMPLICIT_VOLUME_NIFTI:
        return "nifti";
    }
    return "?";
}

/* ------------------------------------------------------------- the layout */

/* What a header describes: the samples and their placement. world =
 * origin + sum_a axis[a] * index_a. */
typedef struct vf_layout {
    size_t dims[3];
    geom_implicit_sample sample;
    int big_endian;
    double axis[3][3]; /* axis[a] = step vector of grid axis a */
    double origin[3];
    double slope, inter; /* NIfTI scaling when scaled */
    int scaled;
} vf_layout;

static void layout_init(vf_layout *L)
{
    memset(L, 0, sizeof *L);
    for (int a = 0; a < 3; a++) {
        L->dims[a] = 1;
        L->axis[a][a] = 1.0;
    }
}

/* The reading context: the whole input in memory, its name, the directory
 * for detached data (NULL when reading from memory), options and output. */
typedef struct vf_ctx {
    const unsigned char *buf;
    size_t size;
    const char *name;
    const char *path; /* the file's path, for detached data; NULL in memory */
    const geom_implicit_volume_read_options *opt;
    const geom_allocator *alloc;
    geom_implicit_volume_file_info *info;
    geom_diag *diag;
} vf_ctx;

static uint64_t load_uint(const unsigned char *p, size_t n, int big)
{
    uint64_t v = 0;
    for (size_t i = 0; i < n; i++)
        v |= (uint64_t)p[big ? i : n - 1 - i] << (8 * (n - 1 - i));
    return v;
}

/* The value of sample i of src (raw bytes in the layout's type and order). */
static double decode_one(const unsigned char *p, geom_implicit_sample s, int big)
{
    switch (s) {
    case GEOM_IMPLICIT_SAMPLE_U8:
        return (double)p[0];
    case GEOM_IMPLICIT_SAMPLE_I8:
        return (double)(int8_t)p[0];
    case GEOM_IMPLICIT_SAMPLE_U16:
        return (double)(uint16_t)load_uint(p, 2, big);
    case GEOM_IMPLICIT_SAMPLE_I16:
        return (double)(int16_t)(uint16_t)load_uint(p, 2, big);
    case GEOM_IMPLICIT_SAMPLE_U32:
        return (double)(uint32_t)load_uint(p, 4, big);
    case GEOM_IMPLICIT_SAMPLE_I32:
        return (double)(int32_t)(uint32_t)load_uint(p, 4, big);
    case GEOM_IMPLICIT_SAMPLE_F32: {
        uint32_t u = (uint32_t)load_uint(p, 4, big);
        float f;
        memcpy(&f, &u, 4);
        return (double)f;
    }
    case GEOM_IMPLICIT_SAMPLE_F64: {
        uint64_t u = load_uint(p, 8, big);
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    }
    return NAN;
}

static geom_implicit_scalar stored_type(const vf_layout *L)
{
    if (L->scaled)
        return GEOM_IMPLICIT_SCALAR_F64;
    switch (L->sample) {
    case GEOM_IMPLICIT_SAMPLE_U32:
    case GEOM_IMPLICIT_SAMPLE_I32:
    case GEOM_IMPLICIT_SAMPLE_F64:
        return GEOM_IMPLICIT_SCALAR_F64;
    default:
        return GEOM_IMPLICIT_SCALAR_F32;
    }
}

/* Count and byte size of the layout's samples. */
static geom_status layout_bytes(const vf_layout *L, size_t *count, size_t *bytes)
{
    size_t n = 1;
    for (int a = 0; a < 3; a++) {
        if (L->dims[a] == 0)
            return GEOM_ERR_PARSE;
        if (geom__size_mul(n, L->dims[a], &n) != GEOM_OK)
            return GEOM_ERR_LIMIT;
    }
    if (geom__size_mul(n, geom_implicit_sample_size(L->sample), bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    *count = n;
    return GEOM_OK;
}

/*
 * Check the placement is axis-aligned and make the volume: spacing from the
 * axis lengths, axes with a negative direction reversed (origin moved to the
 * other end). Then decode `src` (exactly the layout's byte size) into it.
 * `values` (optional, count doubles) replaces src for text encodings.
 */
static geom_status make_volume(vf_ctx *c, const vf_layout *L, const unsigned char *src,
                               const double *values, geom_implicit_volume **out)
{
    geom_implicit_grid d;
    memset(&d, 0, sizeof d);
    d.type = stored_type(L);
    int flip[3];
    for (int a = 0; a < 3; a++) {
        d.dims[a] = L->dims[a];
        double len = 0.0;
        int main_ax = a;
        for (int w = 0; w < 3; w++)
            len += L->axis[a][w] * L->axis[a][w];
        len = sqrt(len);
        if (!isfinite(len))
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                 "axis %d has a non-finite direction or spacing", a);
        if (len == 0.0) {
            if (L->dims[a] > 1)
                return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                     "axis %d has zero spacing", a);
            len = 1.0;
            d.spacing[a] = 1.0;
            flip[a] = 0;
        } else {
            for (int w = 0; w < 3; w++)
                if (w != main_ax && fabs(L->axis[a][w]) > 1e-6 * len)
                    return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                         "axis %d direction (%g, %g, %g) is not along world "
                                         "axis %d: rotated or permuted volumes are not supported",
                                         a, L->axis[a][0], L->axis[a][1], L->axis[a][2], a);
            flip[a] = L->axis[a][a] < 0.0 && L->dims[a] > 1;
            d.spacing[a] = len;
        }
        d.origin[a] = L->origin[a];
        if (flip[a])
            d.origin[a] -= (double)(L->dims[a] - 1) * len;
        if (!isfinite(d.origin[a]))
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                 "non-finite origin");
    }
    geom_implicit_volume *v;
    geom_status st = geom_implicit_volume_create(&d, c->alloc, &v);
    if (st != GEOM_OK)
        return geom__diag_set(c->diag, st, c->name, 0, 0, "cannot create a %zux%zux%zu volume: %s",
                             d.dims[0], d.dims[1], d.dims[2], geom_status_str(st));
    void *dst = geom_implicit_volume_data(v);
    size_t nx = d.dims[0], ny = d.dims[1], nz = d.dims[2];
    size_t es = geom_implicit_sample_size(L->sample);
    int f32 = d.type == GEOM_IMPLICIT_SCALAR_F32;
    size_t in = 0;
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++, in++) {
                double x = values ? values[in] : decode_one(src + in * es, L->sample, L->big_endian);
                if (L->scaled)
                    x = x * L->slope + L->inter;
                size_t oi = flip[0] ? nx - 1 - i : i, oj = flip[1] ? ny - 1 - j : j,
                       ok = flip[2] ? nz - 1 - k : k;
                size_t o = oi + nx * (oj + ny * ok);
                if (f32)
                    ((float *)dst)[o] = (float)x;
                else
                    ((double *)dst)[o] = x;
            }
    if (c->info) {
        c->info->sample = L->sample;
        c->info->scaled = L->scaled;
        for (int a = 0; a < 3; a++)
            c->info->flipped[a] = flip[a];
    }
    *out = v;
    return GEOM_OK;
}

/* ----------------------------------------------------------------- files */

/* Read a whole file into memory (allocated with alloc). */
static geom_status slurp(const char *path, const geom_allocator *alloc, unsigned char **data,
                         size_t *size, geom_diag *diag)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "cannot open: %s", strerror(errno));
    /* a directory opens but cannot be read: say so (not "out of memory") */
    errno = 0;
    if (getc(fp) == EOF && ferror(fp)) {
        int e = errno;
        fclose(fp);
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "cannot read: %s",
                              e == EISDIR ? "is a directory" : strerror(e));
    }
    long end = -1;
    if (fseek(fp, 0, SEEK_END) == 0)
        end = ftell(fp);
    if (end < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        fclose(fp);
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0,
                             "cannot determine the size (not a regular file?)");
    }
    size_t n = (size_t)end;
    unsigned char *buf = geom__alloc(alloc, n ? n : 1);
    if (!buf) {
        fclose(fp);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory for %zu bytes", n);
    }
    size_t got = n ? fread(buf, 1, n, fp) : 0;
    int err = ferror(fp);
    fclose(fp);
    if (got != n || err) {
        geom__free(alloc, buf, n ? n : 1);
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "read error after %zu of %zu bytes",
                             got, n);
    }
    *data = buf;
    *size = n;
    return GEOM_OK;
}

/* The path of `file` relative to the directory of `header` (allocated). */
static char *sibling_path(const char *header, const char *file, const geom_allocator *alloc,
                          size_t *cap)
{
    size_t flen = strlen(file);
    const char *slash = strrchr(header, '/');
    size_t dlen = (file[0] == '/' || !slash) ? 0 : (size_t)(slash - header) + 1;
    *cap = dlen + flen + 1;
    char *p = geom__alloc(alloc, *cap);
    if (!p)
        return NULL;
    memcpy(p, header, dlen);
    memcpy(p + dlen, file, flen + 1);
    return p;
}

/* Is in[0..n) a bzip2 stream? "BZh", the block size '1'..'9', then the
 * magic of a block (pi) or of the end of stream (sqrt(pi)). */
static int is_bzip2(const unsigned char *b, size_t n)
{
    static const unsigned char block[6] = {0x31, 0x41, 0x59, 0x26, 0x53, 0x59},
                               eos[6] = {0x17, 0x72, 0x45, 0x38, 0x50, 0x90};
    return n >= 10 && b[0] == 'B' && b[1] == 'Z' && b[2] == 'h' && b[3] >= '1' && b[3] <= '9' &&
           (memcmp(b + 4, block, 6) == 0 || memcmp(b + 4, eos, 6) == 0);
}

/* Decompress in[0..n) (codec 'g': zlib or gzip through options->inflate;
 * 'b': bzip2 through options->bunzip2) into a new buffer of *cap_out bytes
 * (free with that size) holding *out_size bytes; exact when `expect` is
 * nonzero, else sized from the gzip trailer (or 4n for bzip2) and grown as
 * needed. */
static geom_status inflate_all(vf_ctx *c, int codec, const unsigned char *in, size_t n,
                               size_t expect, unsigned char **out, size_t *out_size,
                               size_t *cap_out)
{
    int bz = codec == 'b';
    geom_implicit_inflate_fn fn = !c->opt ? NULL : bz ? c->opt->bunzip2 : c->opt->inflate;
    void *user = !c->opt ? NULL : bz ? c->opt->bunzip2_user : c->opt->inflate_user;
    const char *what = bz ? "bzip2" : "compressed";
    if (!fn)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0, "%s",
                              bz ? "bzip2 data and no bzip2 decompressor (libgeom has no libbz2: "
                                   "the caller must pass a bunzip2 callback, as the tools do when "
                                   "built with libbz2, Debian libbz2-dev)"
                                 : "compressed data and no decompressor (libgeom has no zlib: the "
                                   "caller must pass an inflate callback, as the tools do)");
    /* deflate expands at most 1032:1, bzip2 at most about 4.6e7:1 (runs
     * of 255 bytes in 5, then runs of a million symbols in 20 bits), so a
     * size claim beyond that is false (and is refused before allocating) */
    size_t ratio = bz ? 46000000 : 1032;
    size_t most = n > (SIZE_MAX - 4096) / ratio ? SIZE_MAX - 1 : n * ratio + 4096;
    if (expect > most)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "%zu %s bytes cannot hold the %zu bytes the header declares", n,
                             what, expect);
    size_t cap = expect;
    if (cap == 0) {
        /* gzip ISIZE (mod 2^32); bzip2 stores no size */
        cap = n >= 4 && !bz ? (size_t)load_uint(in + n - 4, 4, 0) : 0;
        if (cap < n)
            cap = n > (SIZE_MAX - 64) / 4 ? SIZE_MAX - 1 : n * 4 + 64;
        if (cap > most)
            cap = most;
    }
    for (int tries = 0; tries < 40; tries++) {
        size_t alloc_size = cap + 1; /* one spare byte: a full buffer means "maybe more" */
        unsigned char *buf = geom__alloc(c->alloc, alloc_size);
        if (!buf)
            return geom__diag_set(c->diag, GEOM_ERR_NOMEM, c->name, 0, 0,
                                 "out of memory decompressing to %zu bytes", cap);
        size_t got = 0;
        geom_status st = fn(user, in, n, buf, alloc_size, &got);
        if (st == GEOM_OK && got <= cap) {
            if (expect && got != expect) {
                geom__free(c->alloc, buf, alloc_size);
                return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                     "%s data decompresses to %zu bytes, expected %zu", what,
                                     got, expect);
            }
            *out = buf;
            *out_size = got;
            *cap_out = alloc_size;
            return GEOM_OK;
        }
        geom__free(c->alloc, buf, alloc_size);
        if (st == GEOM_OK)
            st = GEOM_ERR_LIMIT; /* filled the spare byte */
        if (st != GEOM_ERR_LIMIT || expect)
            return geom__diag_set(c->diag, st == GEOM_ERR_LIMIT ? GEOM_ERR_PARSE : st, c->name, 0,
                                 0, "%s %s",
                                 st == GEOM_ERR_LIMIT ? what
                                 : bz                 ? "corrupt or truncated"
                                                      : "corrupt",
                                 st == GEOM_ERR_LIMIT ? "data decompresses to more than expected"
                                 : bz                 ? "bzip2 data"
                                                      : "compressed data");
        if (cap >= most)
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                 "%s data decompresses to more than %zu times its size", what,
                                 ratio);
        cap = cap > most / 2 ? most : cap * 2;
    }
    return geom__diag_set(c->diag, GEOM_ERR_LIMIT, c->name, 0, 0, "decompressed data too large");
}

/*
 * Decode the samples of `L` from payload[0..n): `encoding` 0 raw, 'g' zlib
 * or gzip compressed, 'b' bzip2 compressed, 'a' ASCII numbers, 'h' hex.
 * `exact` nonzero: raw data must be exactly the size (else at least).
 * Offsets in messages are relative to `base` in the input.
 */
static geom_status decode_payload(vf_ctx *c, const vf_layout *L, const unsigned char *p, size_t n,
                                  int encoding, int exact, uint64_t base,
                                  geom_implicit_volume **out)
{
    size_t count, bytes;
    geom_status st = layout_bytes(L, &count, &bytes);
    if (st != GEOM_OK)
        return geom__diag_set(c->diag, st, c->name, 0, 0,
                             st == GEOM_ERR_LIMIT ? "volume dimensions too large"
                                                  : "a dimension is zero");
    if (encoding == 0) {
        if (n < bytes || (exact && n != bytes))
            return geom__diag_set_offset(
                c->diag, GEOM_ERR_PARSE, c->name, base + n,
                "data has %zu bytes but %zux%zux%zu %s samples need %zu", n, L->dims[0],
                L->dims[1], L->dims[2], geom_implicit_sample_name(L->sample), bytes);
        return make_volume(c, L, p, NULL, out);
    }
    if (encoding == 'g' || encoding == 'b') {
        unsigned char *raw;
        size_t got, cap;
        st = inflate_all(c, encoding, p, n, bytes, &raw, &got, &cap);
        if (st != GEOM_OK)
            return st;
        if (c->info)
            c->info->compressed = 1;
        st = make_volume(c, L, raw, NULL, out);
        geom__free(c->alloc, raw, cap);
        return st;
    }
    if (encoding == 'h') {
        if (n / 2 < bytes)
            return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + n,
                                        "hex data of %zu bytes cannot hold %zu bytes", n, bytes);
        unsigned char *raw = geom__alloc(c->alloc, bytes ? bytes : 1);
        if (!raw)
            return geom__diag_set(c->diag, GEOM_ERR_NOMEM, c->name, 0, 0, "out of memory");
        size_t o = 0, i = 0;
        int half = -1;
        for (; i < n && o < bytes; i++) {
            int ch = p[i], v;
            if (ch >= '0' && ch <= '9')
                v = ch - '0';
            else if (ch >= 'a' && ch <= 'f')
                v = ch - 'a' + 10;
            else if (ch >= 'A' && ch <= 'F')
                v = ch - 'A' + 10;
            else if (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r')
                continue;
            else {
                geom__free(c->alloc, raw, bytes ? bytes : 1);
                return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + i,
                                            "invalid hex digit (byte 0x%02x)", (unsigned)ch);
            }
            if (half < 0) {
                half = v;
            } else {
                raw[o++] = (unsigned char)(half << 4 | v);
                half = -1;
            }
        }
        if (o < bytes) {
            geom__free(c->alloc, raw, bytes ? bytes : 1);
            return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + i,
                                        "hex data ends after %zu of %zu bytes", o, bytes);
        }
        st = make_volume(c, L, raw, NULL, out);
        geom__free(c->alloc, raw, bytes ? bytes : 1);
        return st;
    }
    /* ASCII */
    if (n / 2 + 1 < count)
        return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + n,
                                    "ASCII data of %zu bytes cannot hold %zu values", n, count);
    size_t vb;
    if (geom__size_mul(count, sizeof(double), &vb) != GEOM_OK)
        return geom__diag_set(c->diag, GEOM_ERR_LIMIT, c->name, 0, 0, "volume too large");
    double *vals = geom__alloc(c->alloc, vb ? vb : 1);
    if (!vals)
        return geom__diag_set(c->diag, GEOM_ERR_NOMEM, c->name, 0, 0, "out of memory");
    size_t i = 0;
    for (size_t k = 0; k < count; k++) {
        while (i < n && (p[i] == ' ' || p[i] == '\t' || p[i] == '\n' || p[i] == '\r' || p[i] == ','))
            i++;
        char tok[80];
        size_t t = 0, start = i;
        while (i < n && !(p[i] == ' ' || p[i] == '\t' || p[i] == '\n' || p[i] == '\r' || p[i] == ',')) {
            if (t + 1 >= sizeof tok || p[i] == '\0')
                break;
            tok[t++] = (char)p[i++];
        }
        tok[t] = '\0';
        char *end = NULL;
        double x = t ? strtod(tok, &end) : 0.0;
        if (t == 0 || *end != '\0' ||
            (i < n && !(p[i] == ' ' || p[i] == '\t' || p[i] == '\n' || p[i] == '\r' || p[i] == ','))) {
            geom__free(c->alloc, vals, vb ? vb : 1);
            if (t == 0)
                return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + start,
                                            "data ends after %zu of %zu values", k, count);
            return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + start,
                                        "malformed ASCII value %zu", k + 1);
        }
        vals[k] = x;
    }
    st = make_volume(c, L, NULL, vals, out);
    geom__free(c->alloc, vals, vb ? vb : 1);
    return st;
}

/* Load a detached data file named in a header (the caller frees *data and *dpath). */
static geom_status load_detached(vf_ctx *c, const char *file, unsigned char **data, size_t *size,
                                 char **dpath, size_t *dcap)
{
    if (!c->path)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "the header names a separate data file '%s', which cannot be read "
                             "from memory",
                             file);
    *dpath = sibling_path(c->path, file, c->alloc, dcap);
    if (!*dpath)
        return geom__diag_set(c->diag, GEOM_ERR_NOMEM, c->name, 0, 0, "out of memory");
    geom_status st = slurp(*dpath, c->alloc, data, size, c->diag);
    if (st != GEOM_OK) {
        if (c->diag) { /* the data file is the source; name the header the user gave too */
            char why[GEOM_DIAG_MESSAGE_MAX];
            snprintf(why, sizeof why, "%s", c->diag->message);
            geom__diag_set(c->diag, st, *dpath, 0, 0, "%s (data file named by %s)", why, c->name);
        }
        geom__free(c->alloc, *dpath, *dcap);
        *dpath = NULL;
    }
    return st;
}

/* ------------------------------------------------------------ header text */

/* Text header lines over [buf, buf+size): *pos advances past each line. */
typedef struct vf_lines {
    const unsigned char *buf;
    size_t size, pos, lineno;
    char line[4096];
} vf_lines;

/* A text header's reader over size bytes at buf, and the layout it fills
 * (layout_init): the start of the NRRD, MetaImage and INRIMAGE readers. */
static void header_start(vf_lines *L, const unsigned char *buf, size_t size, vf_layout *Lay)
{
    memset(L, 0, sizeof *L);
    L->buf = buf;
    L->size = size;
    layout_init(Lay);
}

/* 1: a line (in L->line, without its end); 0: end; -1 too long or NUL. */
static int next_line(vf_lines *L)
{
    if (L->pos >= L->size)
        return 0;
    size_t n = 0;
    while (L->pos < L->size) {
        unsigned char ch = L->buf[L->pos++];
        if (ch == '\n')
            break;
        if (ch == '\0' || n + 1 >= sizeof L->line)
            return -1;
        L->line[n++] = (char)ch;
    }
    if (n > 0 && L->line[n - 1] == '\r')
        n--;
    L->line[n] = '\0';
    L->lineno++;
    return 1;
}

static char *trim(char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t'))
        s[--n] = '\0';
    return s;
}

/* Parse up to max doubles separated by spaces, commas or parentheses; the
 * count parsed, or -1 on a malformed number. */
static int parse_doubles(const char *s, double *out, int max)
{
    int n = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t' || *s == ',' || *s == '(' || *s == ')')
            s++;
        if (!*s)
            return n;
        if (n == max)
            return -1;
        char *end;
        double v = strtod(s, &end);
        if (end == s)
            return -1;
        if (*end && !(*end == ' ' || *end == '\t' || *end == ',' || *end == '(' || *end == ')'))
            return -1;
        out[n++] = v;
        s = end;
    }
}

static int parse_sizes(const char *s, size_t *out, int max)
{
    int n = 0;
    for (;;) {
        while (*s == ' ' || *s == '\t')
            s++;
        if (!*s)
            return n;
        if (n == max || *s < '0' || *s > '9')
            return -1;
        size_t v = 0;
        while (*s >= '0' && *s <= '9') {
            size_t dgt = (size_t)(*s - '0');
            if (v > (SIZE_MAX - dgt) / 10)
                return -1;
            v = v * 10 + dgt;
            s++;
        }
        if (*s && *s != ' ' && *s != '\t')
            return -1;
        out[n++] = v;
    }
}

static geom_status line_err(vf_ctx *c, const vf_lines *L, const char *what, const char *val)
{
    return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, L->lineno, 1, "%s '%.80s'", what, val);
}

/* Record that the header's spacing of axis `a` was unknown or invalid and
 * read as 1 (info->spacing_defaulted, with `note` naming the field, where it
 * is and its value: the caller warns). */
static void spacing_defaulted(vf_ctx *c, int a, const char *note)
{
    if (!c->info)
        return;
    c->info->spacing_defaulted[a] = 1;
    snprintf(c->info->spacing_note, sizeof c->info->spacing_note, "%s", note);
}

/* A spacing value that is not a positive finite number (MetaImage,
 * INRIMAGE): an error naming the line, the field and the value. */
static geom_status bad_spacing(vf_ctx *c, size_t line, const char *key, double v)
{
    return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, line, 1,
                          "%s: spacing %g is not a positive finite number", key, v);
}

/* The next "KEY = value" line of a text header (MetaImage, INRIMAGE),
 * blank lines and '#' comments skipped: 1 with *key and *val trimmed in
 * place, 0 at the end of the header, -1 after setting *st to the error (an
 * over-long line, a NUL byte, or a line without '=', named with `what`). */
static int next_key_value(vf_ctx *c, vf_lines *L, const char *what, char **key, char **val,
                          geom_status *st)
{
    for (;;) {
        int r = next_line(L);
        if (r < 0) {
            *st = geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, L->lineno + 1, 1,
                                "header line too long or holding a NUL byte");
            return -1;
        }
        if (r == 0)
            return 0;
        char *ln = trim(L->line);
        if (!*ln || *ln == '#')
            continue;
        char *eq = strchr(ln, '=');
        if (!eq) {
            *st = line_err(c, L, what, ln);
            return -1;
        }
        *eq = '\0';
        *key = trim(ln);
        *val = trim(eq + 1);
        return 1;
    }
}

/* A header's dimension count (NRRD "dimension", MetaImage "NDims": sizes
 * NULL, one number from 1 to 16) or its sizes (NRRD "sizes", MetaImage
 * "DimSize": up to 16 numbers into sizes[16]) into *n; on a bad value, a
 * parse error "<what> '<value>'" naming the line. */
static geom_status parse_dims_field(vf_ctx *c, const vf_lines *L, const char *what,
                                    const char *val, size_t *sizes, int *n)
{
    size_t d = 0;
    int k = sizes ? parse_sizes(val, sizes, 16) : parse_sizes(val, &d, 1);
    if (sizes ? k < 1 : (k != 1 || d < 1 || d > 16))
        return line_err(c, L, what, val);
    *n = sizes ? k : (int)d;
    return GEOM_OK;
}

/* n sizes against the header's dimension count (`count`, 0 where the header
 * gave none), the fields named `sizes_key` and `count_key` in the message. */
static geom_status check_dim_count(vf_ctx *c, int n, int count, const char *sizes_key,
                                   const char *count_key, size_t line)
{
    if (count && n != count)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, line, 0,
                             "%s has %d values but %s is %d", sizes_key, n, count_key, count);
    return GEOM_OK;
}

/* Dimensions beyond the supported three must be 1. */
static geom_status take_dims(vf_ctx *c, vf_layout *Lay, const size_t *sz, int n, size_t line)
{
    if (n < 1)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, line, 1, "no dimensions");
    for (int a = 0; a < n; a++) {
        if (sz[a] == 0)
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, line, 1,
                                 "dimension %d is zero", a + 1);
        if (a < 3)
            Lay->dims[a] = sz[a];
        else if (sz[a] != 1)
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, line, 1,
                                 "dimension %d has size %zu: only 3-D scalar volumes are supported",
                                 a + 1, sz[a]);
    }
    return GEOM_OK;
}

/* ------------------------------------------------------------------ NRRD */

static int nrrd_type(const char *t, geom_implicit_sample *s)
{
    static const sample_name tab[] = {
        {"signed char", GEOM_IMPLICIT_SAMPLE_I8},      {"int8", GEOM_IMPLICIT_SAMPLE_I8},
        {"int8_t", GEOM_IMPLICIT_SAMPLE_I8},           {"uchar", GEOM_IMPLICIT_SAMPLE_U8},
        {"unsigned char", GEOM_IMPLICIT_SAMPLE_U8},    {"uint8", GEOM_IMPLICIT_SAMPLE_U8},
        {"uint8_t", GEOM_IMPLICIT_SAMPLE_U8},          {"short", GEOM_IMPLICIT_SAMPLE_I16},
        {"short int", GEOM_IMPLICIT_SAMPLE_I16},       {"signed short", GEOM_IMPLICIT_SAMPLE_I16},
        {"signed short int", GEOM_IMPLICIT_SAMPLE_I16}, {"int16", GEOM_IMPLICIT_SAMPLE_I16},
        {"int16_t", GEOM_IMPLICIT_SAMPLE_I16},         {"ushort", GEOM_IMPLICIT_SAMPLE_U16},
        {"unsigned short", GEOM_IMPLICIT_SAMPLE_U16},  {"unsigned short int", GEOM_IMPLICIT_SAMPLE_U16},
        {"uint16", GEOM_IMPLICIT_SAMPLE_U16},          {"uint16_t", GEOM_IMPLICIT_SAMPLE_U16},
        {"int", GEOM_IMPLICIT_SAMPLE_I32},             {"signed int", GEOM_IMPLICIT_SAMPLE_I32},
        {"int32", GEOM_IMPLICIT_SAMPLE_I32},           {"int32_t", GEOM_IMPLICIT_SAMPLE_I32},
        {"uint", GEOM_IMPLICIT_SAMPLE_U32},            {"unsigned int", GEOM_IMPLICIT_SAMPLE_U32},
        {"uint32", GEOM_IMPLICIT_SAMPLE_U32},          {"uint32_t", GEOM_IMPLICIT_SAMPLE_U32},
        {"float", GEOM_IMPLICIT_SAMPLE_F32},           {"double", GEOM_IMPLICIT_SAMPLE_F64},
    };
    return sample_lookup(tab, sizeof tab / sizeof tab[0], t, s);
}

/* Parse "space directions": per axis "(x,y,z)" or "none". */
static int nrrd_directions(const char *s, double dir[][3], int *ndir, int max)
{
    int n = 0;
    while (*s) {
        while (*s == ' ' || *s == '\t')
            s++;
        if (!*s)
            break;
        if (n == max)
            return -1;
        if (strncmp(s, "none", 4) == 0) {
            dir[n][0] = dir[n][1] = dir[n][2] = NAN;
            n++;
            s += 4;
            continue;
        }
        if (*s != '(')
            return -1;
        const char *close = strchr(s, ')');
        if (!close)
            return -1;
        char tmp[256];
        size_t len = (size_t)(close - s) + 1;
        if (len >= sizeof tmp)
            return -1;
        memcpy(tmp, s, len);
        tmp[len] = '\0';
        double v[3] = {0, 0, 0};
        int k = parse_doubles(tmp, v, 3);
        if (k < 1 || k > 3)
            return -1;
        dir[n][0] = v[0];
        dir[n][1] = v[1];
        dir[n][2] = v[2];
        n++;
        s = close + 1;
    }
    *ndir = n;
    return 0;
}

static geom_status read_nrrd(vf_ctx *c, geom_implicit_volume **out)
{
    vf_lines Ls;
    vf_layout Lay;
    header_start(&Ls, c->buf, c->size, &Lay);
    int r = next_line(&Ls);
    if (r != 1 || strncmp(Ls.line, "NRRD000", 7) != 0 || Ls.line[7] < '1' || Ls.line[7] > '5')
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 1, 1,
                             "not a NRRD file: expected the magic 'NRRD0001'..'NRRD0005'");
    int dimension = 0, have_type = 0, have_sizes = 0, encoding = -1, endian = 0;
    size_t sizes[16];
    int nsizes = 0;
    double spacings[16], mins[16], dirs[16][3], sorigin[3] = {0, 0, 0};
    int nspacings = 0, nmins = 0, ndirs = 0, have_sorigin = 0;
    size_t spacings_line = 0;
    char spacings_val[96] = "";
    char data_file[1024] = "";
    long long byte_skip = 0, line_skip = 0;
    for (;;) {
        r = next_line(&Ls);
        if (r < 0)
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, Ls.lineno + 1, 1,
                                 "header line too long or holding a NUL byte");
        if (r == 0 || Ls.line[0] == '\0')
            break;
        if (Ls.line[0] == '#')
            continue;
        char *colon = strstr(Ls.line, ": ");
        char *kv = strstr(Ls.line, ":=");
        if (kv && (!colon || kv < colon))
            continue;
        if (!colon)
            return line_err(c, &Ls, "malformed header line (expected 'field: value'):", Ls.line);
        *colon = '\0';
        char *key = trim(Ls.line), *val = trim(colon + 2);
        if (ieq(key, "type")) {
            if (nrrd_type(val, &Lay.sample) != 0)
                return line_err(c, &Ls, "unsupported NRRD type", val);
            have_type = 1;
        } else if (ieq(key, "dimension")) {
            if (parse_dims_field(c, &Ls, "bad dimension", val, NULL, &dimension) != GEOM_OK)
                return GEOM_ERR_PARSE;
        } else if (ieq(key, "sizes")) {
            if (parse_dims_field(c, &Ls, "bad sizes", val, sizes, &nsizes) != GEOM_OK)
                return GEOM_ERR_PARSE;
            have_sizes = 1;
        } else if (ieq(key, "encoding")) {
            if (ieq(val, "raw"))
                encoding = 0;
            else if (ieq(val, "ascii") || ieq(val, "text") || ieq(val, "txt"))
                encoding = 'a';
            else if (ieq(val, "hex"))
                encoding = 'h';
            else if (ieq(val, "gzip") || ieq(val, "gz"))
                encoding = 'g';
            else if (ieq(val, "bzip2") || ieq(val, "bz2"))
                encoding = 'b';
            else
                return line_err(c, &Ls, "unknown encoding", val);
        } else if (ieq(key, "endian")) {
            if (ieq(val, "little"))
                endian = 1;
            else if (ieq(val, "big"))
                endian = 2;
            else
                return line_err(c, &Ls, "bad endian", val);
        } else if (ieq(key, "spacings")) {
            char tmp[4096];
            snprintf(tmp, sizeof tmp, "%s", val);
            /* "nan" entries stand for non-spatial axes */
            nspacings = parse_doubles(tmp, spacings, 16);
            if (nspacings < 1)
                return line_err(c, &Ls, "bad spacings", val);
            spacings_line = Ls.lineno;
            snprintf(spacings_val, sizeof spacings_val, "%.80s", val);
        } else if (ieq(key, "axis mins") || ieq(key, "axismins")) {
            nmins = parse_doubles(val, mins, 16);
            if (nmins < 1)
                return line_err(c, &Ls, "bad axis mins", val);
        } else if (ieq(key, "space directions")) {
            if (nrrd_directions(val, dirs, &ndirs, 16) != 0)
                return line_err(c, &Ls, "bad space directions", val);
        } else if (ieq(key, "space origin")) {
            double o[3] = {0, 0, 0};
            int k = parse_doubles(val, o, 3);
            if (k < 1)
                return line_err(c, &Ls, "bad space origin", val);
            memcpy(sorigin, o, sizeof o);
            have_sorigin = 1;
        } else if (ieq(key, "data file") || ieq(key, "datafile")) {
            if (strncmp(val, "LIST", 4) == 0 || strchr(val, '%'))
                return line_err(c, &Ls, "multi-file data is not supported:", val);
            if (strlen(val) >= sizeof data_file || !*val)
                return line_err(c, &Ls, "bad data file", val);
            snprintf(data_file, sizeof data_file, "%s", val);
        } else if (ieq(key, "byte skip") || ieq(key, "byteskip")) {
            char *end;
            byte_skip = strtoll(val, &end, 10);
            if (*end || byte_skip < -1)
                return line_err(c, &Ls, "byte skip: expected -1 or more, got", val);
        } else if (ieq(key, "line skip") || ieq(key, "lineskip")) {
            char *end;
            line_skip = strtoll(val, &end, 10);
            if (*end || line_skip < 0)
                return line_err(c, &Ls, "line skip: expected 0 or more, got", val);
        }
    }
    if (!have_type || !dimension || !have_sizes || encoding < 0)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, Ls.lineno, 0,
                             "NRRD header lacks the '%s' field",
                             !have_type ? "type" : !dimension ? "dimension"
                             : !have_sizes ? "sizes" : "encoding");
    if (check_dim_count(c, nsizes, dimension, "sizes", "dimension", Ls.lineno) != GEOM_OK)
        return GEOM_ERR_PARSE;
    if (geom_implicit_sample_size(Lay.sample) > 1 &&
        (encoding == 0 || encoding == 'g' || encoding == 'b' || encoding == 'h') && !endian)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, Ls.lineno, 0,
                             "NRRD header lacks the 'endian' field needed for %s data",
                             geom_implicit_sample_name(Lay.sample));
    if (byte_skip == -1 && encoding != 0)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, Ls.lineno, 0,
                             "'byte skip: -1' needs raw encoding");
    Lay.big_endian = endian == 2;
    geom_status st = take_dims(c, &Lay, sizes, nsizes, Ls.lineno);
    if (st != GEOM_OK)
        return st;
    if (ndirs > 0) {
        int a = 0;
        for (int i = 0; i < ndirs && a < 3; i++) {
            if (isnan(dirs[i][0]))
                continue; /* non-spatial axis (must have size 1 by take_dims for i >= 3) */
            memcpy(Lay.axis[a], dirs[i], sizeof dirs[i]);
            a++;
        }
        if (have_sorigin)
            memcpy(Lay.origin, sorigin, sizeof sorigin);
    } else {
        /* Teem: a spacing is nonzero and finite, or nan for "unknown" (read
         * as 1 with a note for the caller); negative reverses the axis */
        char unknown[32] = "";
        for (int a = 0; a < 3 && a < nspacings; a++) {
            if (isnan(spacings[a])) {
                size_t u = strlen(unknown);
                snprintf(unknown + u, sizeof unknown - u, "%s%d", u ? ", " : "", a);
                continue;
            }
            if (!isfinite(spacings[a]) || spacings[a] == 0.0)
                return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, spacings_line, 1,
                                      "spacings: axis %d has %s spacing in '%s' (nonzero and "
                                      "finite, or nan for unknown)",
                                      a, spacings[a] == 0.0 ? "zero" : "infinite", spacings_val);
            Lay.axis[a][a] = spacings[a];
        }
        for (int a = 0; a < 3 && a < nspacings; a++)
            if (isnan(spacings[a])) {
                char note[GEOM_DIAG_MESSAGE_MAX];
                snprintf(note, sizeof note,
                         "line %zu: 'spacings: %s': axis %s spacing unknown (nan), 1 used",
                         spacings_line, spacings_val, unknown);
                spacing_defaulted(c, a, note);
            }
        if (have_sorigin)
            memcpy(Lay.origin, sorigin, sizeof sorigin);
        else
            for (int a = 0; a < 3 && a < nmins; a++)
                if (isfinite(mins[a]))
                    Lay.origin[a] = mins[a];
    }
    /* the data */
    const unsigned char *p = c->buf + Ls.pos;
    size_t n = c->size - Ls.pos;
    unsigned char *dbuf = NULL;
    size_t dsize = 0, dcap = 0;
    char *dpath = NULL;
    const char *saved = c->name;
    if (data_file[0]) {
        st = load_detached(c, data_file, &dbuf, &dsize, &dpath, &dcap);
        if (st != GEOM_OK)
            return st;
        p = dbuf;
        n = dsize;
        c->name = dpath;
    }
    uint64_t base = (uint64_t)(p - (dbuf ? dbuf : c->buf));
    for (long long l = 0; l < line_skip && st == GEOM_OK; l++) {
        const unsigned char *nl = memchr(p, '\n', n);
        if (!nl)
            st = geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                               "data ends within the %lld skipped lines", line_skip);
        else {
            size_t k = (size_t)(nl - p) + 1;
            p += k;
            n -= k;
            base += k;
        }
    }
    if (st == GEOM_OK) {
        size_t count, bytes;
        if (byte_skip == -1) {
            st = layout_bytes(&Lay, &count, &bytes);
            if (st == GEOM_OK && n < bytes)
                st = geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + n,
                                          "data has %zu bytes but the samples need %zu", n, bytes);
            else if (st == GEOM_OK) {
                p += n - bytes;
                base += n - bytes;
                n = bytes;
            } else
                st = geom__diag_set(c->diag, st, c->name, 0, 0, "volume dimensions too large");
        } else if ((uint64_t)byte_skip > n) {
            st = geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                               "byte skip %lld is beyond the end of the data", byte_skip);
        } else {
            p += byte_skip;
            n -= (size_t)byte_skip;
            base += (uint64_t)byte_skip;
        }
    }
    if (st == GEOM_OK)
        st = decode_payload(c, &Lay, p, n, encoding, 0, base, out);
    c->name = saved;
    if (dbuf)
        geom__free(c->alloc, dbuf, dsize ? dsize : 1);
    if (dpath)
        geom__free(c->alloc, dpath, dcap);
    return st;
}

/* ------------------------------------------------------------- MetaImage */

static int met_type(const char *t, geom_implicit_sample *s)
{
    static const sample_name tab[] = {{"MET_UCHAR", GEOM_IMPLICIT_SAMPLE_U8},   {"MET_CHAR", GEOM_IMPLICIT_SAMPLE_I8},
               {"MET_USHORT", GEOM_IMPLICIT_SAMPLE_U16}, {"MET_SHORT", GEOM_IMPLICIT_SAMPLE_I16},
               {"MET_UINT", GEOM_IMPLICIT_SAMPLE_U32},   {"MET_INT", GEOM_IMPLICIT_SAMPLE_I32},
               {"MET_ULONG", GEOM_IMPLICIT_SAMPLE_U32},  {"MET_LONG", GEOM_IMPLICIT_SAMPLE_I32},
               {"MET_FLOAT", GEOM_IMPLICIT_SAMPLE_F32},  {"MET_DOUBLE", GEOM_IMPLICIT_SAMPLE_F64}};
    return sample_lookup(tab, sizeof tab / sizeof tab[0], t, s);
}

static int met_bool(const char *v, int *out)
{
    if (ieq(v, "true") || ieq(v, "1")) {
        *out = 1;
        return 0;
    }
    if (ieq(v, "false") || ieq(v, "0")) {
        *out = 0;
        return 0;
    }
    return -1;
}

static geom_status read_metaimage(vf_ctx *c, geom_implicit_volume **out)
{
    vf_lines Ls;
    vf_layout Lay;
    header_start(&Ls, c->buf, c->size, &Lay);
    int ndims = 0, have_type = 0, compressed = 0, have_dims = 0, have_matrix = 0;
    size_t dimsz[16];
    int ndimsz = 0;
    double spacing[3] = {1, 1, 1}, matrix[9];
    long long header_size = 0;
    char data_file[1024] = "";
    for (;;) {
        char *key, *val;
        geom_status kst = GEOM_OK;
        int r = next_key_value(c, &Ls, "malformed MetaImage line (expected 'Key = Value'):", &key, &val, &kst);
        if (r < 0)
            return kst;
        if (r == 0)
            break;
        if (ieq(key, "NDims")) {
            if (parse_dims_field(c, &Ls, "bad NDims", val, NULL, &ndims) != GEOM_OK)
                return GEOM_ERR_PARSE;
        } else if (ieq(key, "DimSize")) {
            if (parse_dims_field(c, &Ls, "bad DimSize", val, dimsz, &ndimsz) != GEOM_OK)
                return GEOM_ERR_PARSE;
            have_dims = 1;
        } else if (ieq(key, "ElementType")) {
            if (met_type(val, &Lay.sample) != 0)
                return line_err(c, &Ls, "unsupported ElementType", val);
            have_type = 1;
        } else if (ieq(key, "ElementSpacing") || (ieq(key, "ElementSize") && spacing[0] == 1 &&
                                                  spacing[1] == 1 && spacing[2] == 1)) {
            double v[16];
            int k = parse_doubles(val, v, 16);
            if (k < 1)
                return line_err(c, &Ls, "bad spacing", val);
            for (int a = 0; a < 3 && a < k; a++) {
                if (!(isfinite(v[a]) && v[a] > 0.0))
                    return bad_spacing(c, Ls.lineno, key, v[a]);
                spacing[a] = v[a];
            }
        } else if (ieq(key, "Offset") || ieq(key, "Origin") || ieq(key, "Position")) {
            double v[16];
            int k = parse_doubles(val, v, 16);
            if (k < 1)
                return line_err(c, &Ls, "bad origin", val);
            for (int a = 0; a < 3 && a < k; a++)
                Lay.origin[a] = v[a];
        } else if (ieq(key, "TransformMatrix") || ieq(key, "Rotation") || ieq(key, "Orientation")) {
            double v[16];
            int k = parse_doubles(val, v, 16);
            if (k != 9 && k != 4 && k != 1)
                return line_err(c, &Ls, "bad TransformMatrix (expected 9 values)", val);
            if (k == 9) {
                memcpy(matrix, v, sizeof matrix);
                have_matrix = 1;
            }
        } else if (ieq(key, "ElementByteOrderMSB") || ieq(key, "BinaryDataByteOrderMSB")) {
            if (met_bool(val, &Lay.big_endian) != 0)
                return line_err(c, &Ls, "bad byte order", val);
        } else if (ieq(key, "CompressedData")) {
            if (met_bool(val, &compressed) != 0)
                return line_err(c, &Ls, "bad CompressedData", val);
        } else if (ieq(key, "HeaderSize")) {
            char *end;
            header_size = strtoll(val, &end, 10);
            if (*end || header_size < -1)
                return line_err(c, &Ls, "bad HeaderSize", val);
        } else if (ieq(key, "ElementNumberOfChannels")) {
            if (strcmp(val, "1") != 0)
                return line_err(c, &Ls, "only one channel is supported, ElementNumberOfChannels =",
                                val);
        } else if (ieq(key, "ElementDataFile")) {
            if (!*val || strlen(val) >= sizeof data_file)
                return line_err(c, &Ls, "bad ElementDataFile", val);
            if (ieq(val, "LIST") || strchr(val, '%') || strchr(val, ' '))
                return line_err(c, &Ls, "multi-file data is not supported:", val);
            snprintf(data_file, sizeof data_file, "%s", val);
            break; /* the last header line */
        }
    }
    if (!data_file[0] || !have_type || !have_dims)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, Ls.lineno, 0,
                             "MetaImage header lacks '%s'",
                             !have_type ? "ElementType" : !have_dims ? "DimSize" : "ElementDataFile");
    geom_status st = check_dim_count(c, ndimsz, ndims, "DimSize", "NDims", Ls.lineno);
    if (st == GEOM_OK)
        st = take_dims(c, &Lay, dimsz, ndimsz, Ls.lineno);
    if (st != GEOM_OK)
        return st;
    for (int a = 0; a < 3; a++)
        for (int w = 0; w < 3; w++)
            /* TransformMatrix is row-major with the direction of axis a in column a
             * (ITK's convention, written as a flattened direction matrix) */
            Lay.axis[a][w] = (have_matrix ? matrix[w * 3 + a] : (w == a)) * spacing[a];
    const unsigned char *p;
    size_t n;
    unsigned char *dbuf = NULL;
    size_t dsize = 0, dcap = 0;
    char *dpath = NULL;
    const char *saved = c->name;
    uint64_t base;
    if (ieq(data_file, "LOCAL")) {
        p = c->buf + Ls.pos;
        n = c->size - Ls.pos;
        base = Ls.pos;
    } else {
        st = load_detached(c, data_file, &dbuf, &dsize, &dpath, &dcap);
        if (st != GEOM_OK)
            return st;
        p = dbuf;
        n = dsize;
        base = 0;
        c->name = dpath;
    }
    size_t count, bytes;
    st = layout_bytes(&Lay, &count, &bytes);
    if (st != GEOM_OK)
        st = geom__diag_set(c->diag, st, c->name, 0, 0, "volume dimensions too large");
    if (st == GEOM_OK && header_size == -1 && !compressed) {
        if (n < bytes)
            st = geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, base + n,
                                      "data has %zu bytes but the samples need %zu", n, bytes);
        else {
            p += n - bytes;
            base += n - bytes;
            n = bytes;
        }
    } else if (st == GEOM_OK && header_size > 0) {
        if ((uint64_t)header_size > n)
            st = geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                               "HeaderSize %lld is beyond the end of the data", header_size);
        else {
            p += header_size;
            n -= (size_t)header_size;
            base += (uint64_t)header_size;
        }
    }
    if (st == GEOM_OK)
        st = decode_payload(c, &Lay, p, n, compressed ? 'g' : 0, 0, base, out);
    c->name = saved;
    if (dbuf)
        geom__free(c->alloc, dbuf, dsize ? dsize : 1);
    if (dpath)
        geom__free(c->alloc, dpath, dcap);
    return st;
}

/* -------------------------------------------------------------- INRIMAGE */

static geom_status read_inrimage(vf_ctx *c, geom_implicit_volume **out)
{
    /* The header is text in 256-byte blocks ending with the line "##}". */
    const unsigned char *end = NULL;
    for (size_t i = 0; i + 3 <= c->size && i < (1u << 20); i++)
        if (c->buf[i] == '#' && c->buf[i + 1] == '#' && c->buf[i + 2] == '}' &&
            (i == 0 || c->buf[i - 1] == '\n')) {
            end = c->buf + i;
            break;
        }
    if (!end)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "INRIMAGE header does not end with '##}'");
    size_t hlen = (size_t)(end - c->buf) + 3;
    if (hlen < c->size && c->buf[hlen] == '\n')
        hlen++;
    size_t hsize = (hlen + 255) / 256 * 256;
    vf_lines Ls;
    vf_layout Lay;
    header_start(&Ls, c->buf, (size_t)(end - c->buf), &Lay);
    size_t dims[3] = {0, 0, 0};
    int kind = 0; /* 'u' unsigned fixed, 's' signed fixed, 'f' float */
    size_t bits = 0;
    int cpu_big = -1;
    double vox[3] = {1, 1, 1};
    next_line(&Ls); /* #INRIMAGE-4#{ */
    for (;;) {
        char *key, *val;
        geom_status kst = GEOM_OK;
        int r = next_key_value(c, &Ls, "malformed INRIMAGE line (expected KEY=value):", &key, &val, &kst);
        if (r < 0)
            return kst;
        if (r == 0)
            break;
        int axis = -1;
        if (!strcmp(key, "XDIM") || !strcmp(key, "YDIM") || !strcmp(key, "ZDIM")) {
            axis = key[0] - 'X';
            if (parse_sizes(val, &dims[axis], 1) != 1 || dims[axis] == 0)
                return line_err(c, &Ls, "bad dimension", val);
        } else if (!strcmp(key, "VDIM")) {
            if (strcmp(val, "1") != 0)
                return line_err(c, &Ls, "only scalar images are supported, VDIM =", val);
        } else if (!strcmp(key, "TYPE")) {
            if (!strcmp(val, "unsigned fixed"))
                kind = 'u';
            else if (!strcmp(val, "signed fixed"))
                kind = 's';
            else if (!strcmp(val, "float"))
                kind = 'f';
            else
                return line_err(c, &Ls, "unsupported TYPE", val);
        } else if (!strcmp(key, "PIXSIZE")) {
            if (sscanf(val, "%zu", &bits) != 1)
                return line_err(c, &Ls, "bad PIXSIZE", val);
        } else if (!strcmp(key, "CPU")) {
            if (!strcmp(val, "decm") || !strcmp(val, "alpha") || !strcmp(val, "pc"))
                cpu_big = 0;
            else if (!strcmp(val, "sun") || !strcmp(val, "sgi"))
                cpu_big = 1;
            else
                return line_err(c, &Ls, "unknown CPU", val);
        } else if (!strcmp(key, "VX") || !strcmp(key, "VY") || !strcmp(key, "VZ")) {
            if (parse_doubles(val, &vox[key[1] - 'X'], 1) != 1)
                return line_err(c, &Ls, "bad voxel size", val);
            if (!(isfinite(vox[key[1] - 'X']) && vox[key[1] - 'X'] > 0.0))
                return bad_spacing(c, Ls.lineno, key, vox[key[1] - 'X']);
        } else if (!strcmp(key, "XO") || !strcmp(key, "YO") || !strcmp(key, "ZO") ||
                   !strcmp(key, "TX") || !strcmp(key, "TY") || !strcmp(key, "TZ")) {
            int a = key[0] == 'T' ? key[1] - 'X' : key[0] - 'X';
            if (parse_doubles(val, &Lay.origin[a], 1) != 1)
                return line_err(c, &Ls, "bad origin", val);
        } else if (!strcmp(key, "SCALE")) {
            if (strcmp(val, "2**0") != 0)
                return line_err(c, &Ls, "fixed-point scaling is not supported, SCALE =", val);
        }
    }
    if (!dims[0] || !dims[1] || !dims[2] || !kind || !bits)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, Ls.lineno, 0,
                             "INRIMAGE header lacks %s",
                             !dims[0] || !dims[1] || !dims[2] ? "XDIM/YDIM/ZDIM"
                             : !kind ? "TYPE" : "PIXSIZE");
    if (kind == 'f')
        Lay.sample = bits == 32 ? GEOM_IMPLICIT_SAMPLE_F32 : bits == 64 ? GEOM_IMPLICIT_SAMPLE_F64 : 0;
    else if (bits == 8)
        Lay.sample = kind == 'u' ? GEOM_IMPLICIT_SAMPLE_U8 : GEOM_IMPLICIT_SAMPLE_I8;
    else if (bits == 16)
        Lay.sample = kind == 'u' ? GEOM_IMPLICIT_SAMPLE_U16 : GEOM_IMPLICIT_SAMPLE_I16;
    else if (bits == 32)
        Lay.sample = kind == 'u' ? GEOM_IMPLICIT_SAMPLE_U32 : GEOM_IMPLICIT_SAMPLE_I32;
    if (!Lay.sample)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "unsupported INRIMAGE sample: %zu-bit %s", bits,
                             kind == 'f' ? "float" : "fixed");
    if (cpu_big < 0 && bits > 8)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "INRIMAGE header lacks CPU (the byte order)");
    Lay.big_endian = cpu_big == 1;
    for (int a = 0; a < 3; a++) {
        Lay.dims[a] = dims[a];
        Lay.axis[a][a] = vox[a];
    }
    if (hsize > c->size)
        hsize = hlen;
    return decode_payload(c, &Lay, c->buf + hsize, c->size - hsize, 0, 0, hsize, out);
}

/* ----------------------------------------------------------------- NIfTI */

static double nii_f32(const unsigned char *h, size_t off, int big)
{
    return decode_one(h + off, GEOM_IMPLICIT_SAMPLE_F32, big);
}

static int nii_i16(const unsigned char *h, size_t off, int big)
{
    return (int)(int16_t)(uint16_t)load_uint(h + off, 2, big);
}

static int is_nifti(const unsigned char *b, size_t n)
{
    if (n < 348)
        return 0;
    uint32_t le = (uint32_t)load_uint(b, 4, 0), be = (uint32_t)load_uint(b, 4, 1);
    return (le == 348 || be == 348) && (memcmp(b + 344, "n+1", 4) == 0 || memcmp(b + 344, "ni1", 4) == 0);
}

static geom_status read_nifti(vf_ctx *c, geom_implicit_volume **out)
{
    const unsigned char *h = c->buf;
    if (!is_nifti(h, c->size))
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "not a NIfTI-1 file (sizeof_hdr 348 and magic 'n+1' or 'ni1')");
    int big = load_uint(h, 4, 0) != 348;
    vf_layout Lay;
    layout_init(&Lay);
    Lay.big_endian = big;
    int ndim = nii_i16(h, 40, big);
    if (ndim < 1 || ndim > 7)
        return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, 40,
                                    "dim[0] = %d: expected 1 to 7", ndim);
    size_t sz[7];
    for (int a = 0; a < ndim; a++) {
        int d = nii_i16(h, 42 + 2 * (size_t)a, big);
        if (d < 1)
            return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, 42 + 2 * (uint64_t)a,
                                        "dim[%d] = %d: expected >= 1", a + 1, d);
        sz[a] = (size_t)d;
    }
    geom_status st = take_dims(c, &Lay, sz, ndim, 0);
    if (st != GEOM_OK)
        return st;
    int dt = nii_i16(h, 70, big);
    switch (dt) {
    case 2: Lay.sample = GEOM_IMPLICIT_SAMPLE_U8; break;
    case 4: Lay.sample = GEOM_IMPLICIT_SAMPLE_I16; break;
    case 8: Lay.sample = GEOM_IMPLICIT_SAMPLE_I32; break;
    case 16: Lay.sample = GEOM_IMPLICIT_SAMPLE_F32; break;
    case 64: Lay.sample = GEOM_IMPLICIT_SAMPLE_F64; break;
    case 256: Lay.sample = GEOM_IMPLICIT_SAMPLE_I8; break;
    case 512: Lay.sample = GEOM_IMPLICIT_SAMPLE_U16; break;
    case 768: Lay.sample = GEOM_IMPLICIT_SAMPLE_U32; break;
    default:
        return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, 70,
                                    "unsupported NIfTI datatype %d (supported: 2, 4, 8, 16, 64, "
                                    "256, 512, 768)",
                                    dt);
    }
    double pix[4];
    for (int a = 0; a < 4; a++)
        pix[a] = nii_f32(h, 76 + 4 * (size_t)a, big);
    double vox_offset = nii_f32(h, 108, big);
    double slope = nii_f32(h, 112, big), inter = nii_f32(h, 116, big);
    if (isfinite(slope) && slope != 0.0 && isfinite(inter) && (slope != 1.0 || inter != 0.0)) {
        Lay.scaled = 1;
        Lay.slope = slope;
        Lay.inter = inter;
    }
    int qcode = nii_i16(h, 252, big), scode = nii_i16(h, 254, big);
    if (scode <= 0) {
        /* the placement uses pixdim[1..3]: voxel widths, positive in
         * nifti1.h; otherwise 1, as nifti1_io does, and a note */
        char note[GEOM_DIAG_MESSAGE_MAX] = "";
        for (int a = 0; a < 3 && a < ndim; a++)
            if (!(isfinite(pix[a + 1]) && pix[a + 1] > 0.0)) {
                size_t u = strlen(note);
                snprintf(note + u, sizeof note - u, "%spixdim[%d] = %g (byte %d)", u ? ", " : "",
                         a + 1, pix[a + 1], 76 + 4 * (a + 1));
                pix[a + 1] = 1.0;
                spacing_defaulted(c, a, "");
            }
        if (note[0] && c->info)
            snprintf(c->info->spacing_note, sizeof c->info->spacing_note,
                     "%s: not a positive voxel width, 1 used", note);
    }
    if (scode > 0) {
        for (int w = 0; w < 3; w++) {
            for (int a = 0; a < 3; a++)
                Lay.axis[a][w] = nii_f32(h, 280 + 16 * (size_t)w + 4 * (size_t)a, big);
            Lay.origin[w] = nii_f32(h, 280 + 16 * (size_t)w + 12, big);
        }
    } else if (qcode > 0) {
        double b = nii_f32(h, 256, big), cq = nii_f32(h, 260, big), d = nii_f32(h, 264, big);
        double a2 = 1.0 - (b * b + cq * cq + d * d);
        double a = a2 > 0.0 ? sqrt(a2) : 0.0;
        double R[3][3] = {{a * a + b * b - cq * cq - d * d, 2 * (b * cq - a * d), 2 * (b * d + a * cq)},
                          {2 * (b * cq + a * d), a * a + cq * cq - b * b - d * d, 2 * (cq * d - a * b)},
                          {2 * (b * d - a * cq), 2 * (cq * d + a * b), a * a + d * d - cq * cq - b * b}};
        double qfac = pix[0] < 0.0 ? -1.0 : 1.0;
        double s[3] = {pix[1], pix[2], pix[3] * qfac};
        for (int ax = 0; ax < 3; ax++)
            for (int w = 0; w < 3; w++)
                Lay.axis[ax][w] = R[w][ax] * s[ax];
        for (int w = 0; w < 3; w++)
            Lay.origin[w] = nii_f32(h, 268 + 4 * (size_t)w, big);
    } else {
        for (int a = 0; a < 3; a++)
            Lay.axis[a][a] = pix[a + 1] > 0.0 ? pix[a + 1] : 1.0; /* a < ndim: checked above */
    }
    for (int a = ndim; a < 3; a++) { /* missing axes: unit spacing */
        memset(Lay.axis[a], 0, sizeof Lay.axis[a]);
        Lay.axis[a][a] = 1.0;
    }
    if (memcmp(h + 344, "ni1", 4) == 0) {
        /* header/image pair: the .img next to the .hdr */
        if (!c->path)
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                 "a NIfTI .hdr names a separate .img, which cannot be read from "
                                 "memory");
        const char *slash = strrchr(c->path, '/');
        const char *base = slash ? slash + 1 : c->path;
        const char *dot = strrchr(base, '.');
        char img[1024];
        size_t stem = dot ? (size_t)(dot - base) : strlen(base);
        if (stem + 5 >= sizeof img)
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0, "file name too long");
        memcpy(img, base, stem);
        memcpy(img + stem, ".img", 5);
        unsigned char *dbuf;
        size_t dsize, dcap;
        char *dpath;
        st = load_detached(c, img, &dbuf, &dsize, &dpath, &dcap);
        if (st != GEOM_OK)
            return st;
        const char *saved = c->name;
        c->name = dpath;
        size_t off = vox_offset > 0.0 && vox_offset < (double)dsize ? (size_t)vox_offset : 0;
        st = decode_payload(c, &Lay, dbuf + off, dsize - off, 0, 0, off, out);
        c->name = saved;
        geom__free(c->alloc, dbuf, dsize ? dsize : 1);
        geom__free(c->alloc, dpath, dcap);
        return st;
    }
    if (!(vox_offset >= 348.0) || vox_offset > (double)c->size)
        return geom__diag_set_offset(c->diag, GEOM_ERR_PARSE, c->name, 108,
                                    "vox_offset %g is outside the file (352 or more expected)",
                                    vox_offset);
    size_t off = (size_t)vox_offset;
    return decode_payload(c, &Lay, c->buf + off, c->size - off, 0, 0, off, out);
}

/* ------------------------------------------------------------------- raw */

static geom_status read_rawfile(vf_ctx *c, geom_implicit_volume **out)
{
    const geom_implicit_volume_read_options *o = c->opt;
    if (!o || !o->dims[0] || !o->dims[1] || !o->dims[2])
        return geom__diag_set(c->diag, GEOM_ERR_INVALID_ARG, c->name, 0, 0,
                             "a raw volume needs its dimensions (and sample type)");
    vf_layout Lay;
    layout_init(&Lay);
    Lay.sample = o->sample ? o->sample : GEOM_IMPLICIT_SAMPLE_F32;
    if (!geom_implicit_sample_size(Lay.sample))
        return geom__diag_set(c->diag, GEOM_ERR_INVALID_ARG, c->name, 0, 0, "invalid sample type");
    Lay.big_endian = o->big_endian != 0;
    for (int a = 0; a < 3; a++) {
        if (!isfinite(o->spacing[a]) || o->spacing[a] < 0.0 || !isfinite(o->origin[a]))
            return geom__diag_set(c->diag, GEOM_ERR_INVALID_ARG, c->name, 0, 0,
                                 "invalid spacing or origin");
        Lay.dims[a] = o->dims[a];
        Lay.axis[a][a] = o->spacing[a] > 0.0 ? o->spacing[a] : 1.0;
        Lay.origin[a] = o->origin[a];
    }
    if (o->skip > (uint64_t)c->size)
        return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                             "the file has %zu bytes, fewer than the %llu to skip", c->size,
                             (unsigned long long)o->skip);
    size_t skip = (size_t)o->skip;
    return decode_payload(c, &Lay, c->buf + skip, c->size - skip, 0, 1, skip, out);
}

/* --------------------------------------------------------------- dispatch */

static int starts(const unsigned char *b, size_t n, const char *magic)
{
    size_t m = strlen(magic);
    return n >= m && memcmp(b, magic, m) == 0;
}

/* A MetaImage header: the first non-blank line is "Key = value" with a
 * MetaIO key. */
static int is_metaimage(const unsigned char *b, size_t n)
{
    static const char *keys[] = {"ObjectType", "NDims", "Comment", "ObjectSubType", "DimSize",
                                 "ElementType", "BinaryData", "TransformType"};
    size_t i = 0;
    while (i < n && (b[i] == ' ' || b[i] == '\t' || b[i] == '\n' || b[i] == '\r'))
        i++;
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
        size_t m = strlen(keys[k]);
        if (n - i > m && memcmp(b + i, keys[k], m) == 0) {
            size_t j = i + m;
            while (j < n && (b[j] == ' ' || b[j] == '\t'))
                j++;
            if (j < n && b[j] == '=')
                return 1;
        }
    }
    return 0;
}

static geom_status dispatch(vf_ctx *c, geom_implicit_volume **out)
{
    geom_implicit_volume_format f = c->opt ? c->opt->format : GEOM_IMPLICIT_VOLUME_AUTO;
    if (f == GEOM_IMPLICIT_VOLUME_AUTO) {
        if (starts(c->buf, c->size, "NRRD000"))
            f = GEOM_IMPLICIT_VOLUME_NRRD;
        else if (starts(c->buf, c->size, "#INRIMAGE"))
            f = GEOM_IMPLICIT_VOLUME_INRIMAGE;
        else if (is_nifti(c->buf, c->size))
            f = GEOM_IMPLICIT_VOLUME_NIFTI;
        else if (is_metaimage(c->buf, c->size))
            f = GEOM_IMPLICIT_VOLUME_METAIMAGE;
        else if (c->opt && c->opt->dims[0])
            f = GEOM_IMPLICIT_VOLUME_RAW;
        else
            return geom__diag_set(c->diag, GEOM_ERR_PARSE, c->name, 0, 0,
                                 "not a known volume format (NRRD, MetaImage, INRIMAGE, NIfTI-1); "
                                 "for raw samples give the dimensions and sample type");
    }
    if (c->info)
        c->info->format = f;
    switch (f) {
    case GEOM_IMPLICIT_VOLUME_RAW:
        return read_rawfile(c, out);
    case GEOM_IMPLICIT_VOLUME_NRRD:
        return read_nrrd(c, out);
    case GEOM_IMPLICIT_VOLUME_METAIMAGE:
        return read_metaimage(c, out);
    case GEOM_IMPLICIT_VOLUME_INRIMAGE:
        return read_inrimage(c, out);
    case GEOM_IMPLICIT_VOLUME_NIFTI:
        return read_nifti(c, out);
    default:
        return geom__diag_set(c->diag, GEOM_ERR_INVALID_ARG, c->name, 0, 0, "unknown format %d",
                             (int)f);
    }
}

/* Read from memory; a whole-file gzip or bzip2 stream is decompressed
 * first (but for raw samples asked for without that decompressor: their
 * first bytes may be anything, 1f 8b or "BZh" included). */
static geom_status read_buffer(vf_ctx *c, geom_implicit_volume **out)
{
    int raw_fmt = c->opt && c->opt->format == GEOM_IMPLICIT_VOLUME_RAW;
    int gz = c->size >= 2 && c->buf[0] == 0x1f && c->buf[1] == 0x8b &&
             !(raw_fmt && !c->opt->inflate);
    int bz = is_bzip2(c->buf, c->size) && !(raw_fmt && !c->opt->bunzip2);
    if (gz || bz) {
        unsigned char *raw;
        size_t n, cap;
        geom_status st = inflate_all(c, bz ? 'b' : 'g', c->buf, c->size, 0, &raw, &n, &cap);
        if (st != GEOM_OK)
            return st;
        if (c->info)
            c->info->compressed = 1;
        const unsigned char *saved = c->buf;
        size_t ssize = c->size;
        c->buf = raw;
        c->size = n;
        st = dispatch(c, out);
        c->buf = saved;
        c->size = ssize;
        geom__free(c->alloc, raw, cap);
        if (c->info && st == GEOM_OK)
            c->info->compressed = 1;
        return st;
    }
    return dispatch(c, out);
}

geom_status geom_implicit_volume_read_memory(const void *data, size_t size, const char *source_name,
                                             const geom_implicit_volume_read_options *options,
                                             const geom_allocator *alloc,
                                             geom_implicit_volume **out,
                                             geom_implicit_volume_file_info *info, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (info)
        memset(info, 0, sizeof *info);
    if (!out || (!data && size > 0))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, source_name ? source_name : "", 0, 0,
                             "NULL data or output");
    vf_ctx c;
    memset(&c, 0, sizeof c);
    c.buf = data ? data : (const unsigned char *)"";
    c.size = size;
    c.name = source_name ? source_name : "<memory>";
    c.opt = options;
    c.alloc = alloc;
    c.info = info;
    c.diag = diag;
    return read_buffer(&c, out);
}

geom_status geom_implicit_volume_read(const char *path,
                                      const geom_implicit_volume_read_options *options,
                                      const geom_allocator *alloc, geom_implicit_volume **out,
                                      geom_implicit_volume_file_info *info, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (info)
        memset(info, 0, sizeof *info);
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path ? path : "", 0, 0,
                             "NULL path or output");
    unsigned char *buf;
    size_t size;
    geom_status st = slurp(path, alloc, &buf, &size, diag);
    if (st != GEOM_OK)
        return st;
    vf_ctx c;
    memset(&c, 0, sizeof c);
    c.buf = buf;
    c.size = size;
    c.name = path;
    c.path = path;
    c.opt = options;
    c.alloc = alloc;
    c.info = info;
    c.diag = diag;
    st = read_buffer(&c, out);
    geom__free(alloc, buf, size ? size : 1);
    return st;
}
