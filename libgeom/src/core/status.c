/* Status names, diagnostics and the version string. */
#include "core/internal.h"

#include <stdio.h>
#include <string.h>

const char *geom_version_string(void)
{
    return GEOM_VERSION_STRING;
}

const char *geom_status_str(geom_status s)
{
    switch (s) {
    case GEOM_OK: return "ok";
    case GEOM_ERR_NOMEM: return "out of memory";
    case GEOM_ERR_INVALID_ARG: return "invalid argument";
    case GEOM_ERR_PARSE: return "parse error";
    case GEOM_ERR_IO: return "I/O error";
    case GEOM_ERR_DEGENERATE: return "degenerate input";
    case GEOM_ERR_NONMANIFOLD: return "non-manifold input";
    case GEOM_ERR_DOMAIN: return "argument outside the domain";
    case GEOM_ERR_LIMIT: return "limit exceeded";
    }
    return "unknown status";
}

void geom_diag_clear(geom_diag *d)
{
    if (d)
        memset(d, 0, sizeof *d);
}

static void set_common(geom_diag *d, geom_status status, const char *source, const char *fmt,
                       va_list ap)
{
    memset(d, 0, sizeof *d);
    d->status = status;
    if (source)
        snprintf(d->source, sizeof d->source, "%s", source);
    vsnprintf(d->message, sizeof d->message, fmt, ap);
}

geom_status geom__diag_set(geom_diag *d, geom_status status, const char *source, size_t line,
                          size_t column, const char *fmt, ...)
{
    if (d) {
        va_list ap;
        va_start(ap, fmt);
        set_common(d, status, source, fmt, ap);
        va_end(ap);
        d->line = line;
        d->column = column;
    }
    return status;
}

geom_status geom__diag_set_offset(geom_diag *d, geom_status status, const char *source,
                                 uint64_t offset, const char *fmt, ...)
{
    if (d) {
        va_list ap;
        va_start(ap, fmt);
        set_common(d, status, source, fmt, ap);
        va_end(ap);
        d->byte_offset = offset;
    }
    return status;
}

size_t geom_diag_format(const geom_diag *d, char *buf, size_t size)
{
    char where[GEOM_DIAG_MESSAGE_MAX + 64] = "";
    int n;
    if (!d) {
        n = snprintf(buf, size, "(no diagnostic)");
        return n < 0 ? 0 : (size_t)n;
    }
    if (d->source[0]) {
        if (d->line && d->column)
            snprintf(where, sizeof where, "%s:%zu:%zu: ", d->source, d->line, d->column);
        else if (d->line)
            snprintf(where, sizeof where, "%s:%zu: ", d->source, d->line);
        else if (d->byte_offset)
            snprintf(where, sizeof where, "%s: byte %llu: ", d->source,
                     (unsigned long long)d->byte_offset);
        else
            snprintf(where, sizeof where, "%s: ", d->source);
    } else if (d->line) {
        snprintf(where, sizeof where, "line %zu: ", d->line);
    }
    n = snprintf(buf, size, "%s%s", where,
                 d->message[0] ? d->message : geom_status_str(d->status));
    return n < 0 ? 0 : (size_t)n;
}
