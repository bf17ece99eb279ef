/* meshio output sink: buffered bytes, text numbers and binary scalars. */
#include "meshio/meshio_internal.h"
#include "core/numbers_internal.h"

#include <stdio.h>

geom_status geom__meshio_sink_fail(mio_sink *k, geom_status st, const char *fmt, ...)
{
    if (k->status != GEOM_OK)
        return k->status;
    k->status = st;
    va_list ap;
    va_start(ap, fmt);
    geom__meshio_vdiag(k->diag, st, NULL, 0, 0, fmt, ap);
    va_end(ap);
    return st;
}

geom_status geom__meshio_sink_flush(mio_sink *k)
{
    if (k->status != GEOM_OK || !k->flush_fn || k->n == 0)
        return k->status;
    geom_status st = k->flush_fn(k->user, k->buf, k->n, k->diag);
    if (st != GEOM_OK) {
        k->status = st;
        return st;
    }
    k->n = 0;
    return GEOM_OK;
}

void geom__meshio_put(mio_sink *k, const void *p, size_t n)
{
    if (k->status != GEOM_OK || n == 0)
        return;
    const unsigned char *src = p;
    while (n > 0) {
        if (k->n == k->cap) {
            if (k->flush_fn) {
                if (geom__meshio_sink_flush(k) != GEOM_OK)
                    return;
            } else {
                /* memory sink: keep one spare byte for the final NUL */
                geom_status st = geom__grow(k->alloc, (void **)&k->buf, &k->cap,
                                                   k->n + n + 1, 1);
                if (st != GEOM_OK) {
                    geom__meshio_sink_fail(k, st, "out of memory for %llu bytes of output",
                                           (unsigned long long)(k->total + n));
                    return;
                }
            }
        }
        size_t room = k->cap - k->n;
        size_t c = n < room ? n : room;
        memcpy(k->buf + k->n, src, c);
        k->n += c;
        k->total += c;
        src += c;
        n -= c;
    }
}

int geom__meshio_sink_make_room(mio_sink *k, size_t need)
{
    if (k->status != GEOM_OK)
        return 0;
    if (k->cap - k->n >= need)
        return 1;
    if (k->flush_fn) {
        if (geom__meshio_sink_flush(k) != GEOM_OK)
            return 0;
        if (k->cap >= need)
            return 1;
    }
    /* a memory sink (or a file sink's buffer too small: never, at 64 KiB):
     * grow, keeping one spare byte for the final NUL */
    geom_status st = geom__grow(k->alloc, (void **)&k->buf, &k->cap, k->n + need + 1, 1);
    if (st != GEOM_OK) {
        geom__meshio_sink_fail(k, st, "out of memory for %llu bytes of output",
                               (unsigned long long)(k->total + need));
        return 0;
    }
    return 1;
}

void geom__meshio_puts(mio_sink *k, const char *s) { geom__meshio_put(k, s, strlen(s)); }

/* Formatted in place in the sink's buffer: no copy. */
void geom__meshio_put_double(mio_sink *k, double x)
{
    if (!isfinite(x)) {
        geom__meshio_sink_fail(k, GEOM_ERR_INVALID_ARG, "cannot write a non-finite value");
        return;
    }
    if (!mio_room(k, GEOM_DOUBLE_CHARS))
        return;
    mio_advance(k, geom_format_double_digits(x, k->precision, (char *)k->buf + k->n));
}

void geom__meshio_put_u64(mio_sink *k, uint64_t v)
{
    if (!mio_room(k, 20))
        return;
    int n = geom__decimal_length(v);
    geom__put_digits((char *)k->buf + k->n, v, n);
    mio_advance(k, (size_t)n);
}

void geom__meshio_put_i64(mio_sink *k, int64_t v)
{
    if (v < 0) {
        mio_putc(k, '-');
        geom__meshio_put_u64(k, (uint64_t)0 - (uint64_t)v);
    } else {
        geom__meshio_put_u64(k, (uint64_t)v);
    }
}

static void put_uint(mio_sink *k, uint64_t v, int bytes, int be)
{
    unsigned char b[8];
    for (int i = 0; i < bytes; i++) {
        unsigned char byte = (unsigned char)(v >> (8 * i));
        b[be ? bytes - 1 - i : i] = byte;
    }
    geom__meshio_put(k, b, (size_t)bytes);
}

void geom__meshio_put_u16(mio_sink *k, uint16_t v, int be) { put_uint(k, v, 2, be); }
void geom__meshio_put_u32(mio_sink *k, uint32_t v, int be) { put_uint(k, v, 4, be); }

void geom__meshio_put_f32(mio_sink *k, float v, int be)
{
    uint32_t u;
    memcpy(&u, &v, 4);
    put_uint(k, u, 4, be);
}

void geom__meshio_put_f64(mio_sink *k, double v, int be)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    put_uint(k, u, 8, be);
}
