/*
 * Dense sampled volumes: creation, raw and NRRD readers, trilinear
 * evaluation with central-difference gradients, and the field adapter.
 */
#include "implicit/implicit_internal.h"

#include <errno.h>
#include <limits.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct geom_implicit_volume {
    size_t dims[3];
    double spacing[3];
    double origin[3];
    geom_implicit_scalar type;
    void *data;
    size_t nbytes;
    geom_allocator alloc;
};

static size_t scalar_size(geom_implicit_scalar t)
{
    return t == GEOM_IMPLICIT_SCALAR_F32 ? 4 : t == GEOM_IMPLICIT_SCALAR_F64 ? 8 : 0;
}

/* Check a description; fill the sample count and byte size. */
static geom_status check_desc(const geom_implicit_volume_desc *d, size_t *count, size_t *bytes)
{
    if (!d || scalar_size(d->type) == 0)
        return GEOM_ERR_INVALID_ARG;
    size_t n = 1;
    for (int a = 0; a < 3; a++) {
        if (d->dims[a] == 0)
            return GEOM_ERR_INVALID_ARG;
        if (!isfinite(d->origin[a]) || !isfinite(d->spacing[a]) || d->spacing[a] < 0.0)
            return GEOM_ERR_INVALID_ARG;
        if (geom__size_mul(n, d->dims[a], &n) != GEOM_OK)
            return GEOM_ERR_LIMIT;
    }
    if (geom__size_mul(n, scalar_size(d->type), bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    *count = n;
    return GEOM_OK;
}

geom_status geom_implicit_volume_create(const geom_implicit_volume_desc *desc,
                                        const geom_allocator *alloc,
                                        geom_implicit_volume **out)
{
    if (out)
        *out = NULL;
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    size_t count, bytes;
    geom_status st = check_desc(desc, &count, &bytes);
    if (st != GEOM_OK)
        return st;
    geom_implicit_volume *v = geom__alloc(alloc, sizeof *v);
    if (!v)
        return GEOM_ERR_NOMEM;
    memset(v, 0, sizeof *v);
    if (alloc)
        v->alloc = *alloc;
    v->data = geom__alloc(alloc, bytes);
    if (!v->data) {
        geom__free(alloc, v, sizeof *v);
        return GEOM_ERR_NOMEM;
    }
    memset(v->data, 0, bytes);
    v->nbytes = bytes;
    v->type = desc->type;
    for (int a = 0; a < 3; a++) {
        v->dims[a] = desc->dims[a];
        v->spacing[a] = desc->spacing[a] > 0.0 ? desc->spacing[a] : 1.0;
        v->origin[a] = desc->origin[a];
    }
    *out = v;
    return GEOM_OK;
}

void geom_implicit_volume_destroy(geom_implicit_volume *v)
{
    if (!v)
        return;
    geom_allocator a = v->alloc;
    geom__free(&a, v->data, v->nbytes);
    geom__free(&a, v, sizeof *v);
}

void geom_implicit_volume_get_desc(const geom_implicit_volume *v, geom_implicit_volume_desc *out)
{
    if (!v || !out)
        return;
    memset(out, 0, sizeof *out);
    for (int a = 0; a < 3; a++) {
        out->dims[a] = v->dims[a];
        out->spacing[a] = v->spacing[a];
        out->origin[a] = v->origin[a];
    }
    out->type = v->type;
}

void *geom_implicit_volume_data(geom_implicit_volume *v)
{
    return v ? v->data : NULL;
}

const void *geom_implicit_volume_cdata(const geom_implicit_volume *v)
{
    return v ? v->data : NULL;
}

static inline double sample(const geom_implicit_volume *v, size_t idx)
{
    if (v->type == GEOM_IMPLICIT_SCALAR_F32)
        return (double)((const float *)v->data)[idx];
    return ((const double *)v->data)[idx];
}

double geom_implicit_volume_at(const geom_implicit_volume *v, size_t i, size_t j, size_t k)
{
    if (!v || i >= v->dims[0] || j >= v->dims[1] || k >= v->dims[2])
        return NAN;
    return sample(v, i + v->dims[0] * (j + v->dims[1] * k));
}

geom_aabb geom_implicit_volume_bounds(const geom_implicit_volume *v)
{
    if (!v)
        return geom_aabb_empty();
    geom_aabb b;
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = v->origin[a];
        hi[a] = v->origin[a] + (double)(v->dims[a] - 1) * v->spacing[a];
    }
    b.min = geom_vec3_make(lo[0], lo[1], lo[2]);
    b.max = geom_vec3_make(hi[0], hi[1], hi[2]);
    return b;
}

static void desc_of(const geom_implicit_volume *v, geom_implicit_volume_desc *d)
{
    memset(d, 0, sizeof *d);
    for (int a = 0; a < 3; a++) {
        d->dims[a] = v->dims[a];
        d->spacing[a] = v->spacing[a];
        d->origin[a] = v->origin[a];
    }
    d->type = v->type;
}

double geom_implicit_volume_eval(const geom_implicit_volume *v, const double p[3])
{
    if (!v)
        return NAN;
    geom_implicit_volume_desc d;
    desc_of(v, &d);
    return geom_implicit_samples_value(&d, v->data, p);
}

double geom_implicit_volume_eval_grad(const geom_implicit_volume *v, const double p[3],
                                      double grad[3])
{
    double val = geom_implicit_volume_eval(v, p);
    if (!grad)
        return val;
    if (!v) {
        grad[0] = grad[1] = grad[2] = NAN;
        return val;
    }
    geom_implicit_volume_desc d;
    desc_of(v, &d);
    geom_implicit_samples_gradient(&d, v->data, p, grad);
    return val;
}

double geom_implicit_volume_value_cb(void *user, const double p[3])
{
    return geom_implicit_volume_eval((const geom_implicit_volume *)user, p);
}

double geom_implicit_volume_grad_cb(void *user, const double p[3], double grad[3])
{
    return geom_implicit_volume_eval_grad((const geom_implicit_volume *)user, p, grad);
}

void geom_implicit_field_from_volume(const geom_implicit_volume *v, geom_implicit_field *out)
{
    if (!out)
        return;
    out->value = geom_implicit_volume_value_cb;
    out->gradient = geom_implicit_volume_grad_cb;
    out->user = (void *)(uintptr_t)v;
    out->exact = 0;
}

/* ------------------------------------------------------------- byte order */

static int host_is_little(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

static void swap_bytes(void *data, size_t count, size_t size)
{
    unsigned char *p = data;
    for (size_t i = 0; i < count; i++, p += size)
        for (size_t a = 0, b = size - 1; a < b; a++, b--) {
            unsigned char t = p[a];
            p[a] = p[b];
            p[b] = t;
        }
}

/* Size of an open file (from the current position: its remaining bytes). */
static int file_remaining(FILE *fp, uint64_t *out)
{
    long here = ftell(fp);
    if (here < 0 || fseek(fp, 0, SEEK_END) != 0)
        return -1;
    long end = ftell(fp);
    if (end < 0 || fseek(fp, here, SEEK_SET) != 0)
        return -1;
    *out = (uint64_t)(end - here);
    return 0;
}

static const char *type_name(geom_implicit_scalar t)
{
    return t == GEOM_IMPLICIT_SCALAR_F32 ? "f32" : "f64";
}

geom_status geom_implicit_volume_read_raw(const char *path, const geom_implicit_volume_desc *desc,
                                          const geom_allocator *alloc,
                                          geom_implicit_volume **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path ? path : "", 0, 0,
                             "NULL path or output");
    size_t count, bytes;
    geom_status st = check_desc(desc, &count, &bytes);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, path, 0, 0,
                             st == GEOM_ERR_LIMIT ? "volume dimensions too large"
                                                  : "invalid volume description");
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "cannot open: %s", strerror(errno));
    uint64_t size;
    if (file_remaining(fp, &size) != 0) {
        fclose(fp);
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "cannot determine the file size");
    }
    if (size != (uint64_t)bytes) {
        fclose(fp);
        return geom__diag_set(diag, GEOM_ERR_PARSE, path, 0, 0,
                             "file has %llu bytes but %zux%zux%zu %s samples need %llu",
                             (unsigned long long)size, desc->dims[0], desc->dims[1],
                             desc->dims[2], type_name(desc->type), (unsigned long long)bytes);
    }
    geom_implicit_volume *v;
    st = geom_implicit_volume_create(desc, alloc, &v);
    if (st != GEOM_OK) {
        fclose(fp);
        return geom__diag_set(diag, st, path, 0, 0, "%s", geom_status_str(st));
    }
    size_t got = fread(v->data, 1, bytes, fp);
    int err = ferror(fp);
    fclose(fp);
    if (got != bytes || err) {
        geom_implicit_volume_destroy(v);
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "read error after %zu bytes", got);
    }
    if ((desc->big_endian != 0) == host_is_little())
        swap_bytes(v->data, count, scalar_size(desc->type));
    *out = v;
    return GEOM_OK;
}

/* ------------------------------------------------------------------- NRRD */

enum { NRRD_LINE_MAX = 65536, NRRD_HEADER_MAX = 1 << 20 };

enum { ENC_RAW = 1, ENC_ASCII = 2 };

typedef struct nrrd_info {
    geom_implicit_scalar type;
    int dimension;
    size_t sizes[3];
    int have_sizes;
    int encoding;
    int endian; /* 0 unknown, 1 little, 2 big */
    double spacing[3];
    int have_spacing;
    double origin[3];
    int have_origin;
    double axis_min[3];
    int have_axis_min;
    char data_file[1024];
    int detached;
    long long byte_skip;
    long long line_skip;
} nrrd_info;

/* A source of header lines and then data: a FILE or a memory block. */
typedef struct nrrd_src {
    FILE *fp;
    const unsigned char *mem;
    size_t size, pos;
    const char *name;
    size_t lineno;
} nrrd_src;

/* Read one line (without its "\n" or "\r\n") into buf (cap bytes). Returns
 * 1 for a line, 0 at end of input, -1 for a line that is too long or holds
 * a NUL byte. */
static int src_line(nrrd_src *s, char *buf, size_t cap, size_t *len)
{
    size_t n = 0;
    int any = 0;
    for (;;) {
        int c;
        if (s->fp) {
            c = fgetc(s->fp);
            if (c == EOF)
                break;
        } else {
            if (s->pos >= s->size)
                break;
            c = s->mem[s->pos++];
        }
        any = 1;
        if (c == '\n')
            break;
        if (c == '\0' || n + 1 >= cap)
            return -1;
        buf[n++] = (char)c;
    }
    if (!any)
        return 0;
    if (n > 0 && buf[n - 1] == '\r')
        n--;
    buf[n] = '\0';
    *len = n;
    s->lineno++;
    return 1;
}

static geom_status nrrd_err(geom_diag *diag, const nrrd_src *s, size_t col, const char *fmt,
                            const char *arg)
{
    return geom__diag_set(diag, GEOM_ERR_PARSE, s->name, s->lineno, col, fmt, arg);
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

static const char *skip_ws(const char *p)
{
    while (*p == ' ' || *p == '\t')
        p++;
    return p;
}

/* Parse a double at *p (C-locale spelling); advance *p. Accepts nan. */
static int parse_num(const char **p, double *out)
{
    const char *s = skip_ws(*p);
    char buf[128];
    size_t n = 0;
    while (s[n] && s[n] != ' ' && s[n] != '\t' && s[n] != ',' && s[n] != ')' && n < 127) {
        buf[n] = s[n];
        n++;
    }
    if (n == 0 || n >= 127)
        return -1;
    buf[n] = '\0';
    char *end;
    double v = strtod(buf, &end);
    if (*end != '\0') {
        const struct lconv *lc = localeconv();
        char *dot = strchr(buf, '.');
        if (!dot || !lc || !lc->decimal_point || strlen(lc->decimal_point) != 1)
            return -1;
        *dot = lc->decimal_point[0];
        v = strtod(buf, &end);
        if (*end != '\0')
            return -1;
    }
    *out = v;
    *p = s + n;
    return 0;
}

static int parse_size(const char **p, size_t *out)
{
    const char *s = skip_ws(*p);
    if (*s < '0' || *s > '9')
        return -1;
    size_t v = 0;
    while (*s >= '0' && *s <= '9') {
        size_t d = (size_t)(*s - '0');
        if (v > (SIZE_MAX - d) / 10)
            return -1;
        v = v * 10 + d;
        s++;
    }
    *out = v;
    *p = s;
    return 0;
}

static int parse_ll(const char **p, long long *out)
{
    const char *s = skip_ws(*p);
    int neg = 0;
    if (*s == '-') {
        neg = 1;
        s++;
    }
    if (*s < '0' || *s > '9')
        return -1;
    long long v = 0;
    while (*s >= '0' && *s <= '9') {
        if (v > (LLONG_MAX - 9) / 10)
            return -1;
        v = v * 10 + (*s - '0');
        s++;
    }
    *out = neg ? -v : v;
    *p = s;
    return 0;
}

/* "(a,b,c)" or "none"; n = number of components read (0 for none). */
static int parse_vector(const char **p, double v[3], int *n)
{
    const char *s = skip_ws(*p);
    if (strncmp(s, "none", 4) == 0) {
        *n = 0;
        *p = s + 4;
        return 0;
    }
    if (*s != '(')
        return -1;
    s++;
    int k = 0;
    for (;;) {
        double x;
        if (k >= 3 || parse_num(&s, &x) != 0)
            return -1;
        v[k++] = x;
        s = skip_ws(s);
        if (*s == ',') {
            s++;
            continue;
        }
        if (*s == ')') {
            s++;
            break;
        }
        return -1;
    }
    *n = k;
    *p = s;
    return 0;
}

static geom_status nrrd_field(nrrd_info *h, const nrrd_src *s, const char *key, const char *val,
                              size_t val_col, geom_diag *diag)
{
    const char *p = val;
    if (ieq(key, "type")) {
        if (ieq(val, "float"))
            h->type = GEOM_IMPLICIT_SCALAR_F32;
        else if (ieq(val, "double"))
            h->type = GEOM_IMPLICIT_SCALAR_F64;
        else
            return nrrd_err(diag, s, val_col,
                            "type '%s' is not supported (float or double samples only)", val);
    } else if (ieq(key, "dimension")) {
        size_t d;
        if (parse_size(&p, &d) != 0 || *skip_ws(p) || d < 1 || d > 3)
            return nrrd_err(diag, s, val_col, "dimension '%s': 1, 2 or 3 supported", val);
        h->dimension = (int)d;
    } else if (ieq(key, "sizes")) {
        if (h->dimension == 0)
            return nrrd_err(diag, s, val_col, "'sizes' before 'dimension'%s", "");
        for (int a = 0; a < h->dimension; a++)
            if (parse_size(&p, &h->sizes[a]) != 0 || h->sizes[a] == 0)
                return nrrd_err(diag, s, val_col, "sizes '%s': expected positive integers", val);
        if (*skip_ws(p))
            return nrrd_err(diag, s, val_col, "sizes '%s': more sizes than the dimension", val);
        h->have_sizes = 1;
    } else if (ieq(key, "encoding")) {
        if (ieq(val, "raw"))
            h->encoding = ENC_RAW;
        else if (ieq(val, "ascii") || ieq(val, "text") || ieq(val, "txt"))
            h->encoding = ENC_ASCII;
        else if (ieq(val, "gzip") || ieq(val, "gz") || ieq(val, "bzip2") || ieq(val, "bz2"))
            return nrrd_err(diag, s, val_col,
                            "encoding '%s' is not supported: libgeom's core has no compression "
                            "library; decompress first (e.g. unu save -f nrrd -e raw)",
                            val);
        else
            return nrrd_err(diag, s, val_col,
                            "encoding '%s' is not supported (raw or ascii)", val);
    } else if (ieq(key, "endian")) {
        if (ieq(val, "little"))
            h->endian = 1;
        else if (ieq(val, "big"))
            h->endian = 2;
        else
            return nrrd_err(diag, s, val_col, "endian '%s': expected little or big", val);
    } else if (ieq(key, "spacings")) {
        if (h->dimension == 0)
            return nrrd_err(diag, s, val_col, "'spacings' before 'dimension'%s", "");
        for (int a = 0; a < h->dimension; a++) {
            double x;
            if (parse_num(&p, &x) != 0)
                return nrrd_err(diag, s, val_col, "spacings '%s': expected numbers", val);
            if (isnan(x))
                x = 1.0;
            if (!(x > 0.0) || !isfinite(x))
                return nrrd_err(diag, s, val_col,
                                "spacings '%s': spacings must be positive and finite", val);
            h->spacing[a] = x;
        }
        h->have_spacing = 1;
    } else if (ieq(key, "space directions")) {
        if (h->dimension == 0)
            return nrrd_err(diag, s, val_col, "'space directions' before 'dimension'%s", "");
        for (int a = 0; a < h->dimension; a++) {
            double v[3] = {0, 0, 0};
            int n;
            if (parse_vector(&p, v, &n) != 0)
                return nrrd_err(diag, s, val_col,
                                "space directions '%s': expected (x,y,z) vectors", val);
            if (n == 0) {
                h->spacing[a] = 1.0;
                continue;
            }
            for (int b = 0; b < n; b++)
                if (b != a && v[b] != 0.0)
                    return nrrd_err(diag, s, val_col,
                                    "space directions '%s': only axis-aligned directions are "
                                    "supported",
                                    val);
            if (a >= n || !(v[a] > 0.0) || !isfinite(v[a]))
                return nrrd_err(diag, s, val_col,
                                "space directions '%s': directions must point along +x, +y, +z",
                                val);
            h->spacing[a] = v[a];
        }
        h->have_spacing = 1;
    } else if (ieq(key, "space origin")) {
        double v[3] = {0, 0, 0};
        int n;
        if (parse_vector(&p, v, &n) != 0 || n == 0)
            return nrrd_err(diag, s, val_col, "space origin '%s': expected (x,y,z)", val);
        for (int a = 0; a < 3; a++) {
            if (!isfinite(v[a]))
                return nrrd_err(diag, s, val_col, "space origin '%s': not finite", val);
            h->origin[a] = v[a];
        }
        h->have_origin = 1;
    } else if (ieq(key, "axis mins") || ieq(key, "axismins")) {
        if (h->dimension == 0)
            return nrrd_err(diag, s, val_col, "'axis mins' before 'dimension'%s", "");
        for (int a = 0; a < h->dimension; a++) {
            double x;
            if (parse_num(&p, &x) != 0)
                return nrrd_err(diag, s, val_col, "axis mins '%s': expected numbers", val);
            h->axis_min[a] = isfinite(x) ? x : 0.0;
        }
        h->have_axis_min = 1;
    } else if (ieq(key, "data file") || ieq(key, "datafile")) {
        size_t n = strlen(val);
        if (n == 0 || n >= sizeof h->data_file || strchr(val, ' ') || strchr(val, '%'))
            return nrrd_err(diag, s, val_col,
                            "data file '%s': only a single file name is supported", val);
        memcpy(h->data_file, val, n + 1);
        h->detached = 1;
    } else if (ieq(key, "byte skip") || ieq(key, "byteskip")) {
        if (parse_ll(&p, &h->byte_skip) != 0 || h->byte_skip < -1)
            return nrrd_err(diag, s, val_col, "byte skip '%s': expected -1 or more", val);
    } else if (ieq(key, "line skip") || ieq(key, "lineskip")) {
        if (parse_ll(&p, &h->line_skip) != 0 || h->line_skip < 0)
            return nrrd_err(diag, s, val_col, "line skip '%s': expected 0 or more", val);
    }
    /* Every other field (kinds, centers, space, units, content, ...) is
     * accepted and ignored. */
    return GEOM_OK;
}

/* Parse the header from s up to the blank line (or the end, for a
 * detached header). */
static geom_status nrrd_header(nrrd_src *s, nrrd_info *h, const geom_allocator *alloc,
                               geom_diag *diag)
{
    memset(h, 0, sizeof *h);
    char *line = geom__alloc(alloc, NRRD_LINE_MAX);
    if (!line)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, s->name, 0, 0, "out of memory");
    size_t len, total = 0;
    geom_status st = GEOM_OK;
    int r = src_line(s, line, NRRD_LINE_MAX, &len);
    if (r != 1 || len < 8 || strncmp(line, "NRRD000", 7) != 0 || line[7] < '1' || line[7] > '5') {
        st = geom__diag_set(diag, GEOM_ERR_PARSE, s->name, 1, 1,
                           "not a NRRD file: expected the magic 'NRRD0001'..'NRRD0005'");
        goto done;
    }
    for (;;) {
        r = src_line(s, line, NRRD_LINE_MAX, &len);
        if (r < 0) {
            st = geom__diag_set(diag, GEOM_ERR_PARSE, s->name, s->lineno + 1, 1,
                               "header line too long or holding a NUL byte");
            goto done;
        }
        if (r == 0 || len == 0)
            break;
        total += len + 1;
        if (total > NRRD_HEADER_MAX) {
            st = geom__diag_set(diag, GEOM_ERR_LIMIT, s->name, s->lineno, 1,
                               "header longer than %d bytes", NRRD_HEADER_MAX);
            goto done;
        }
        if (line[0] == '#')
            continue;
        char *colon = strstr(line, ": ");
        char *kv = strstr(line, ":=");
        if (kv && (!colon || kv < colon))
            continue; /* key/value pair */
        if (!colon) {
            st = nrrd_err(diag, s, 1, "malformed header line '%.60s': expected 'field: value'",
                          line);
            goto done;
        }
        *colon = '\0';
        char *val = colon + 2;
        size_t vlen = strlen(val);
        while (vlen > 0 && (val[vlen - 1] == ' ' || val[vlen - 1] == '\t'))
            val[--vlen] = '\0';
        st = nrrd_field(h, s, line, val, (size_t)(val - line) + 1, diag);
        if (st != GEOM_OK)
            goto done;
    }
    if (!h->type || !h->dimension || !h->have_sizes || !h->encoding) {
        const char *missing = !h->type ? "type" : !h->dimension ? "dimension"
                              : !h->have_sizes ? "sizes" : "encoding";
        st = geom__diag_set(diag, GEOM_ERR_PARSE, s->name, s->lineno, 0,
                           "NRRD header lacks the '%s' field", missing);
        goto done;
    }
    if (h->encoding == ENC_RAW && !h->endian) {
        st = geom__diag_set(diag, GEOM_ERR_PARSE, s->name, s->lineno, 0,
                           "NRRD header lacks the 'endian' field needed for raw %s data",
                           type_name(h->type));
        goto done;
    }
    if (h->byte_skip == -1 && h->encoding != ENC_RAW) {
        st = geom__diag_set(diag, GEOM_ERR_PARSE, s->name, s->lineno, 0,
                           "'byte skip: -1' needs raw encoding");
        goto done;
    }
done:
    geom__free(alloc, line, NRRD_LINE_MAX);
    return st;
}

/* Parse count ASCII numbers from s into the volume. */
static geom_status nrrd_read_ascii(nrrd_src *s, geom_implicit_volume *v, size_t count,
                                   geom_diag *diag)
{
    char tok[128];
    size_t n = 0;
    uint64_t off = 0;
    for (size_t i = 0; i < count; i++) {
        int c;
        /* skip separators */
        for (;;) {
            if (s->fp)
                c = fgetc(s->fp);
            else
                c = s->pos < s->size ? s->mem[s->pos++] : EOF;
            off++;
            if (c == EOF || !(c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ','))
                break;
        }
        n = 0;
        while (c != EOF && !(c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',')) {
            if (n + 1 >= sizeof tok || c == '\0')
                return geom__diag_set_offset(diag, GEOM_ERR_PARSE, s->name, off,
                                            "malformed ASCII value %zu", i + 1);
            tok[n++] = (char)c;
            if (s->fp)
                c = fgetc(s->fp);
            else
                c = s->pos < s->size ? s->mem[s->pos++] : EOF;
            off++;
        }
        if (n == 0)
            return geom__diag_set_offset(diag, GEOM_ERR_PARSE, s->name, off,
                                        "data ends after %zu of %zu values", i, count);
        tok[n] = '\0';
        const char *p = tok;
        double x;
        if (parse_num(&p, &x) != 0 || *p)
            return geom__diag_set_offset(diag, GEOM_ERR_PARSE, s->name, off,
                                        "malformed ASCII value %zu", i + 1);
        if (v->type == GEOM_IMPLICIT_SCALAR_F32)
            ((float *)v->data)[i] = (float)x;
        else
            ((double *)v->data)[i] = x;
    }
    return GEOM_OK;
}

/* Skip `lines` lines then `bytes` bytes of s. */
static geom_status nrrd_skip(nrrd_src *s, const nrrd_info *h, geom_diag *diag)
{
    for (long long l = 0; l < h->line_skip; l++) {
        int c;
        do {
            if (s->fp)
                c = fgetc(s->fp);
            else
                c = s->pos < s->size ? s->mem[s->pos++] : EOF;
        } while (c != EOF && c != '\n');
        if (c == EOF)
            return geom__diag_set(diag, GEOM_ERR_PARSE, s->name, 0, 0,
                                 "data ends within the %lld skipped lines", h->line_skip);
    }
    if (h->byte_skip > 0) {
        uint64_t rem;
        if (s->fp) {
            if (file_remaining(s->fp, &rem) != 0)
                return geom__diag_set(diag, GEOM_ERR_IO, s->name, 0, 0,
                                     "cannot determine the file size");
        } else {
            rem = s->size - s->pos;
        }
        if ((uint64_t)h->byte_skip > rem)
            return geom__diag_set(diag, GEOM_ERR_PARSE, s->name, 0, 0,
                                 "byte skip %lld is beyond the end of the data", h->byte_skip);
        if (s->fp) {
            if (fseek(s->fp, (long)h->byte_skip, SEEK_CUR) != 0)
                return geom__diag_set(diag, GEOM_ERR_IO, s->name, 0, 0, "seek failed");
        } else {
            s->pos += (size_t)h->byte_skip;
        }
    }
    return GEOM_OK;
}

/* Read the data described by h from s (positioned at the data). */
static geom_status nrrd_data(nrrd_src *s, const nrrd_info *h, const geom_allocator *alloc,
                             geom_implicit_volume **out, geom_diag *diag)
{
    geom_implicit_volume_desc d;
    memset(&d, 0, sizeof d);
    d.type = h->type;
    for (int a = 0; a < 3; a++) {
        d.dims[a] = a < h->dimension ? h->sizes[a] : 1;
        d.spacing[a] = h->have_spacing && a < h->dimension ? h->spacing[a] : 1.0;
        d.origin[a] = h->have_origin ? h->origin[a]
                      : h->have_axis_min && a < h->dimension ? h->axis_min[a] : 0.0;
    }
    size_t count, bytes;
    geom_status st = check_desc(&d, &count, &bytes);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, s->name, 0, 0, "volume dimensions too large");
    st = nrrd_skip(s, h, diag);
    if (st != GEOM_OK)
        return st;
    uint64_t rem;
    if (s->fp) {
        if (file_remaining(s->fp, &rem) != 0)
            return geom__diag_set(diag, GEOM_ERR_IO, s->name, 0, 0, "cannot determine the file size");
    } else {
        rem = s->size - s->pos;
    }
    /* Size checks before allocating. */
    if (h->encoding == ENC_RAW) {
        if (rem < (uint64_t)bytes)
            return geom__diag_set_offset(diag, GEOM_ERR_PARSE, s->name, rem,
                                        "data has %llu bytes but %zux%zux%zu %s samples need %llu",
                                        (unsigned long long)rem, d.dims[0], d.dims[1], d.dims[2],
                                        type_name(d.type), (unsigned long long)bytes);
        if (h->byte_skip == -1) {
            uint64_t skip = rem - (uint64_t)bytes;
            if (s->fp) {
                if (fseek(s->fp, (long)skip, SEEK_CUR) != 0)
                    return geom__diag_set(diag, GEOM_ERR_IO, s->name, 0, 0, "seek failed");
            } else {
                s->pos += (size_t)skip;
            }
        }
    } else if (rem / 2 + 1 < (uint64_t)count) {
        return geom__diag_set_offset(diag, GEOM_ERR_PARSE, s->name, rem,
                                    "ASCII data of %llu bytes cannot hold %zu values",
                                    (unsigned long long)rem, count);
    }
    geom_implicit_volume *v;
    st = geom_implicit_volume_create(&d, alloc, &v);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, s->name, 0, 0, "%s", geom_status_str(st));
    if (h->encoding == ENC_RAW) {
        size_t got;
        if (s->fp) {
            got = fread(v->data, 1, bytes, s->fp);
        } else {
            memcpy(v->data, s->mem + s->pos, bytes);
            got = bytes;
        }
        if (got != bytes) {
            geom_implicit_volume_destroy(v);
            return geom__diag_set(diag, GEOM_ERR_IO, s->name, 0, 0, "read error");
        }
        if ((h->endian == 2) == host_is_little())
            swap_bytes(v->data, count, scalar_size(d.type));
    } else {
        st = nrrd_read_ascii(s, v, count, diag);
        if (st != GEOM_OK) {
            geom_implicit_volume_destroy(v);
            return st;
        }
    }
    *out = v;
    return GEOM_OK;
}

geom_status geom_implicit_volume_read_nrrd_memory(const void *data, size_t size,
                                                  const char *source_name,
                                                  const geom_allocator *alloc,
                                                  geom_implicit_volume **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (!data && size > 0))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "NULL data or output");
    nrrd_src s;
    memset(&s, 0, sizeof s);
    s.mem = data;
    s.size = size;
    s.name = source_name ? source_name : "<memory>";
    nrrd_info h;
    geom_status st = nrrd_header(&s, &h, alloc, diag);
    if (st != GEOM_OK)
        return st;
    if (h.detached)
        return geom__diag_set(diag, GEOM_ERR_PARSE, s.name, 0, 0,
                             "detached NRRD header ('data file: %s') cannot be read from memory",
                             h.data_file);
    return nrrd_data(&s, &h, alloc, out, diag);
}

geom_status geom_implicit_volume_read_nrrd(const char *path, const geom_allocator *alloc,
                                           geom_implicit_volume **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "NULL path or output");
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "cannot open: %s", strerror(errno));
    nrrd_src s;
    memset(&s, 0, sizeof s);
    s.fp = fp;
    s.name = path;
    nrrd_info h;
    geom_status st = nrrd_header(&s, &h, alloc, diag);
    if (st != GEOM_OK) {
        fclose(fp);
        return st;
    }
    if (!h.detached) {
        st = nrrd_data(&s, &h, alloc, out, diag);
        fclose(fp);
        return st;
    }
    fclose(fp);
    /* The data file, relative to the header's directory. */
    size_t flen = strlen(h.data_file);
    const char *slash = strrchr(path, '/');
    size_t dlen = (h.data_file[0] == '/' || !slash) ? 0 : (size_t)(slash - path) + 1;
    size_t dsize = dlen + flen + 1;
    char *dpath = geom__alloc(alloc, dsize);
    if (!dpath)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");
    memcpy(dpath, path, dlen);
    memcpy(dpath + dlen, h.data_file, flen + 1);
    FILE *df = fopen(dpath, "rb");
    if (!df) {
        st = geom__diag_set(diag, GEOM_ERR_IO, dpath, 0, 0, "cannot open the data file: %s",
                           strerror(errno));
        geom__free(alloc, dpath, dsize);
        return st;
    }
    nrrd_src ds;
    memset(&ds, 0, sizeof ds);
    ds.fp = df;
    ds.name = dpath;
    st = nrrd_data(&ds, &h, alloc, out, diag);
    fclose(df);
    geom__free(alloc, dpath, dsize);
    return st;
}
