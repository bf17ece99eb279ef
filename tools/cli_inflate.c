/* gzip/zlib decompression for the tools (tools/cli.h, cli_inflate), through
 * zlib when the build found it (GEOM_HAVE_ZLIB); libgeom itself has none. */
#include "cli.h"

#include <limits.h>
#include <string.h>

#ifdef GEOM_HAVE_ZLIB
#include <zlib.h>

geom_status cli_inflate(void *user, const void *in, size_t in_size, void *out, size_t out_cap,
                        size_t *out_size)
{
    (void)user;
    z_stream zs;
    memset(&zs, 0, sizeof zs);
    /* 15 + 32: a zlib or a gzip header, detected */
    if (inflateInit2(&zs, 15 + 32) != Z_OK)
        return GEOM_ERR_NOMEM;
    const unsigned char *src = in;
    unsigned char *dst = out;
    size_t in_left = in_size, out_left = out_cap;
    int ret = Z_OK;
    for (;;) {
        if (zs.avail_in == 0 && in_left > 0) {
            zs.next_in = (unsigned char *)(uintptr_t)src;
            zs.avail_in = in_left > UINT_MAX ? UINT_MAX : (unsigned)in_left;
            src += zs.avail_in;
            in_left -= zs.avail_in;
        }
        if (zs.avail_out == 0) {
            if (out_left == 0) {
                ret = Z_BUF_ERROR;
                break;
            }
            zs.next_out = dst;
            zs.avail_out = out_left > UINT_MAX ? UINT_MAX : (unsigned)out_left;
            dst += zs.avail_out;
            out_left -= zs.avail_out;
        }
        ret = inflate(&zs, Z_NO_FLUSH);
        if (ret == Z_STREAM_END) {
            /* concatenated gzip members (as `cat a.gz b.gz`) continue */
            if (zs.avail_in == 0 && in_left == 0)
                break;
            if (inflateReset(&zs) != Z_OK) {
                ret = Z_DATA_ERROR;
                break;
            }
            continue;
        }
        if (ret == Z_BUF_ERROR && zs.avail_out == 0 && out_left == 0)
            break;
        if (ret != Z_OK) {
            if (ret == Z_BUF_ERROR && zs.avail_in == 0 && in_left == 0)
                ret = Z_DATA_ERROR; /* truncated */
            break;
        }
    }
    *out_size = (size_t)zs.total_out;
    inflateEnd(&zs);
    if (ret == Z_STREAM_END)
        return GEOM_OK;
    if (ret == Z_BUF_ERROR || (zs.avail_out == 0 && out_left == 0))
        return GEOM_ERR_LIMIT;
    return ret == Z_MEM_ERROR ? GEOM_ERR_NOMEM : GEOM_ERR_PARSE;
}

bool cli_have_inflate(void)
{
    return true;
}

#else

geom_status cli_inflate(void *user, const void *in, size_t in_size, void *out, size_t out_cap,
                        size_t *out_size)
{
    return cli_decompress_missing(user, in, in_size, out, out_cap, out_size);
}

bool cli_have_inflate(void)
{
    return false;
}

#endif

geom_status cli_decompress_missing(void *user, const void *in, size_t in_size, void *out,
                                   size_t out_cap, size_t *out_size)
{
    (void)user;
    (void)in;
    (void)in_size;
    (void)out;
    (void)out_cap;
    *out_size = 0;
    return GEOM_ERR_PARSE;
}
