/* bzip2 decompression for the tools (tools/cli.h, cli_bunzip2), through
 * libbz2 when the build found it (GEOM_HAVE_BZIP2); libgeom itself has none. */
#include "cli.h"

#include <limits.h>
#include <string.h>

#ifdef GEOM_HAVE_BZIP2
#include <bzlib.h>

geom_status cli_bunzip2(void *user, const void *in, size_t in_size, void *out, size_t out_cap,
                        size_t *out_size)
{
    (void)user;
    const char *src = in;
    char *dst = out;
    size_t in_left = in_size, out_left = out_cap, total = 0;
    int ret = in_size ? BZ_OK : BZ_UNEXPECTED_EOF; /* nothing is not a stream */
    /* one stream after the other (as `cat a.bz2 b.bz2`, or pbzip2's output) */
    while (in_left > 0 && ret == BZ_OK) {
        bz_stream bs;
        memset(&bs, 0, sizeof bs);
        if (BZ2_bzDecompressInit(&bs, 0, 0) != BZ_OK) {
            *out_size = total;
            return GEOM_ERR_NOMEM;
        }
        for (;;) {
            if (bs.avail_in == 0 && in_left > 0) {
                bs.next_in = (char *)(uintptr_t)src;
                bs.avail_in = in_left > UINT_MAX ? UINT_MAX : (unsigned)in_left;
                src += bs.avail_in;
                in_left -= bs.avail_in;
            }
            if (bs.avail_out == 0) {
                if (out_left == 0) {
                    ret = BZ_OUTBUFF_FULL;
                    break;
                }
                bs.next_out = dst;
                bs.avail_out = out_left > UINT_MAX ? UINT_MAX : (unsigned)out_left;
                dst += bs.avail_out;
                out_left -= bs.avail_out;
            }
            unsigned in_before = bs.avail_in, out_before = bs.avail_out;
            ret = BZ2_bzDecompress(&bs);
            if (ret == BZ_STREAM_END)
                break;
            if (ret != BZ_OK)
                break;
            if (bs.avail_in == in_before && bs.avail_out == out_before && bs.avail_out > 0 &&
                in_left == 0) {
                ret = BZ_UNEXPECTED_EOF; /* truncated: no input left, no progress */
                break;
            }
        }
        /* give back what this stream did not consume, and the unused output */
        src -= bs.avail_in;
        in_left += bs.avail_in;
        dst -= bs.avail_out;
        out_left += bs.avail_out;
        total = (size_t)(dst - (char *)out);
        BZ2_bzDecompressEnd(&bs);
        if (ret == BZ_STREAM_END)
            ret = BZ_OK;
    }
    *out_size = total;
    if (ret == BZ_OK)
        return GEOM_OK;
    if (ret == BZ_OUTBUFF_FULL)
        return GEOM_ERR_LIMIT;
    return ret == BZ_MEM_ERROR ? GEOM_ERR_NOMEM : GEOM_ERR_PARSE;
}

bool cli_have_bunzip2(void)
{
    return true;
}

#else

geom_status cli_bunzip2(void *user, const void *in, size_t in_size, void *out, size_t out_cap,
                        size_t *out_size)
{
    return cli_decompress_missing(user, in, in_size, out, out_cap, out_size);
}

bool cli_have_bunzip2(void)
{
    return false;
}

#endif
