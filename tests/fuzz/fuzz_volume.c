/*
 * libFuzzer target over the volume file readers
 * (geom_implicit_volume_read_memory: NRRD, MetaImage, INRIMAGE, NIfTI-1 and
 * raw), given the input as a buffer of exactly `size` bytes. The inflate
 * callback is a stand-in (data after a 'Z' byte, or after the gzip magic,
 * copied), so compressed paths and the retry loop are reached without zlib.
 * Raw reading is reached by dims taken from the input's first bytes when no
 * header is recognised. Checks besides memory errors, UB, hangs and leaks:
 *  - the status is one the header documents (OK, PARSE, LIMIT, NOMEM,
 *    INVALID_ARG); *out is NULL on error, the diagnostic carries the status
 *    and the source name;
 *  - on success the volume has at most as many samples as the input could
 *    encode (bytes, or 1032 per compressed byte), a positive finite spacing
 *    and a finite origin, and evaluates at its centre without crashing.
 * Built with -DGEOM_FUZZ=ON (clang) and in every build with driver.c, which
 * runs the seed corpus tests/fuzz/corpus/volume.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);       \
            abort();                                                                       \
        }                                                                                  \
    } while (0)

static geom_status fake_inflate(void *user, const void *in, size_t n, void *out, size_t cap,
                                size_t *got)
{
    (void)user;
    const unsigned char *p = in;
    size_t skip = n >= 1 && p[0] == 'Z' ? 1 : n >= 2 && p[0] == 0x1f && p[1] == 0x8b ? 2 : 0;
    if (!skip)
        return GEOM_ERR_PARSE;
    if (n - skip > cap)
        return GEOM_ERR_LIMIT;
    memcpy(out, p + skip, n - skip);
    *got = n - skip;
    return GEOM_OK;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    if (size)
        memcpy(copy, data, size);
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.inflate = fake_inflate;
    if (size >= 4) { /* raw fallback: dims and type from the first bytes */
        o.dims[0] = 1 + copy[0] % 8;
        o.dims[1] = 1 + copy[1] % 8;
        o.dims[2] = 1 + copy[2] % 8;
        o.sample = (geom_implicit_sample)(1 + copy[3] % 8);
        o.big_endian = copy[3] & 0x80;
        o.skip = 4;
    }
    static char sentinel;
    geom_implicit_volume *v = (geom_implicit_volume *)(void *)&sentinel;
    geom_implicit_volume_file_info info;
    geom_diag d;
    memset(&d, 0, sizeof d);
    geom_status st = geom_implicit_volume_read_memory(copy, size, "fuzz.vol", &o, NULL, &v, &info,
                                                      &d);
    if (st != GEOM_OK) {
        CHECK(st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT || st == GEOM_ERR_NOMEM ||
              st == GEOM_ERR_INVALID_ARG);
        CHECK(v == NULL);
        CHECK(d.status == st);
        CHECK(d.message[0] != '\0');
        CHECK(strncmp(d.source, "fuzz.vol", 8) == 0 || d.source[0] != '\0');
    } else {
        CHECK(v != NULL);
        geom_implicit_volume_desc desc;
        geom_implicit_volume_get_desc(v, &desc);
        double count = (double)desc.dims[0] * (double)desc.dims[1] * (double)desc.dims[2];
        CHECK(count <= (double)size * 1032.0 + 4096.0);
        double c[3];
        for (int a = 0; a < 3; a++) {
            CHECK(desc.spacing[a] > 0 && isfinite(desc.spacing[a]));
            CHECK(isfinite(desc.origin[a]));
            c[a] = desc.origin[a] + 0.5 * (double)(desc.dims[a] - 1) * desc.spacing[a];
        }
        (void)geom_implicit_volume_eval(v, c);
        geom_implicit_volume_destroy(v);
    }
    free(copy);
    return 0;
}
