#define _POSIX_C_SOURCE 200809L
/*
 * Tests of the volume file readers (geom_implicit_volume_read*): every
 * sample type in both byte orders with a header offset, NRRD (raw, ASCII,
 * hex, gzip through a stand-in inflate callback, bzip2 through a stand-in
 * bunzip2 callback, detached data, negative space directions, the spacing
 * rules: nan/invalid spacing reported or refused, never silently 1),
 * MetaImage (.mha and .mhd + .raw), INRIMAGE and NIfTI-1 (sform, qform,
 * pixdim, scaling, .hdr/.img pairs). Every file is made here
 * from the closed form value(i, j, k) below, encoded by hand (byte by byte,
 * independent of the reader), and the samples read back are compared with
 * it exactly, at the world positions the header gives.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "geom/implicit.h"

enum { NX = 4, NY = 3, NZ = 2, N = NX * NY * NZ };

/* Representable exactly in every sample type (signed ones take negatives). */
static double value(geom_implicit_sample s, int i, int j, int k)
{
    int v = i + 5 * j + 17 * k;
    if (s == GEOM_IMPLICIT_SAMPLE_I8 || s == GEOM_IMPLICIT_SAMPLE_I16 ||
        s == GEOM_IMPLICIT_SAMPLE_I32)
        return v - 20;
    if (s == GEOM_IMPLICIT_SAMPLE_F32 || s == GEOM_IMPLICIT_SAMPLE_F64)
        return (v - 20) * 0.25;
    if (s == GEOM_IMPLICIT_SAMPLE_U16)
        return v * 1000;
    if (s == GEOM_IMPLICIT_SAMPLE_U32)
        return v * 100000000.0;
    return v;
}

/* Encode x as sample type s in the given byte order at p; the byte count. */
static size_t put(unsigned char *p, geom_implicit_sample s, double x, int big)
{
    uint64_t bits;
    size_t n;
    switch (s) {
    case GEOM_IMPLICIT_SAMPLE_U8: bits = (uint8_t)x; n = 1; break;
    case GEOM_IMPLICIT_SAMPLE_I8: bits = (uint8_t)(int8_t)x; n = 1; break;
    case GEOM_IMPLICIT_SAMPLE_U16: bits = (uint16_t)x; n = 2; break;
    case GEOM_IMPLICIT_SAMPLE_I16: bits = (uint16_t)(int16_t)x; n = 2; break;
    case GEOM_IMPLICIT_SAMPLE_U32: bits = (uint32_t)x; n = 4; break;
    case GEOM_IMPLICIT_SAMPLE_I32: bits = (uint32_t)(int32_t)x; n = 4; break;
    case GEOM_IMPLICIT_SAMPLE_F32: {
        float f = (float)x;
        uint32_t u;
        memcpy(&u, &f, 4);
        bits = u;
        n = 4;
        break;
    }
    default: {
        memcpy(&bits, &x, 8);
        n = 8;
        break;
    }
    }
    for (size_t b = 0; b < n; b++)
        p[big ? b : n - 1 - b] = (unsigned char)(bits >> (8 * (n - 1 - b)));
    return n;
}

/* The N samples of s at buf; returns the byte count. */
static size_t put_all(unsigned char *buf, geom_implicit_sample s, int big)
{
    size_t o = 0;
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++)
                o += put(buf + o, s, value(s, i, j, k), big);
    return o;
}

/* Every sample of v equals value() at the file sample whose world position
 * it has: file sample (i, j, k) sits at origin + i*ax + j*ay + k*az, with
 * ax = (sx, 0, 0) etc. and possibly negative steps. */
static void check_volume(const geom_implicit_volume *v, geom_implicit_sample s, const double o[3],
                         const double step[3])
{
    geom_implicit_volume_desc d;
    geom_implicit_volume_get_desc(v, &d);
    assert_int_equal(d.dims[0], NX);
    assert_int_equal(d.dims[1], NY);
    assert_int_equal(d.dims[2], NZ);
    int n[3] = {NX, NY, NZ};
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(d.spacing[a] - fabs(step[a])) <= 1e-12 * fabs(step[a]));
        double lo = step[a] > 0 ? o[a] : o[a] + (n[a] - 1) * step[a];
        assert_true(fabs(d.origin[a] - lo) <= 1e-9);
    }
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                double p[3] = {o[0] + i * step[0], o[1] + j * step[1], o[2] + k * step[2]};
                double got = geom_implicit_volume_eval(v, p);
                if (got != value(s, i, j, k))
                    fail_msg("%s sample (%d,%d,%d): %.17g, expected %.17g",
                             geom_implicit_sample_name(s), i, j, k, got, value(s, i, j, k));
            }
}

static const geom_implicit_sample all_types[] = {
    GEOM_IMPLICIT_SAMPLE_U8,  GEOM_IMPLICIT_SAMPLE_I8,  GEOM_IMPLICIT_SAMPLE_U16,
    GEOM_IMPLICIT_SAMPLE_I16, GEOM_IMPLICIT_SAMPLE_U32, GEOM_IMPLICIT_SAMPLE_I32,
    GEOM_IMPLICIT_SAMPLE_F32, GEOM_IMPLICIT_SAMPLE_F64};

static void test_sample_names(void **state)
{
    (void)state;
    for (size_t t = 0; t < 8; t++) {
        geom_implicit_sample s;
        assert_int_equal(geom_implicit_sample_parse(geom_implicit_sample_name(all_types[t]), &s),
                         GEOM_OK);
        assert_int_equal(s, all_types[t]);
    }
    geom_implicit_sample s;
    assert_int_equal(geom_implicit_sample_parse("int64", &s), GEOM_ERR_PARSE);
    assert_int_equal(geom_implicit_sample_parse("double", &s), GEOM_OK);
    assert_int_equal(s, GEOM_IMPLICIT_SAMPLE_F64);
    assert_int_equal(geom_implicit_sample_size((geom_implicit_sample)99), 0);
    assert_string_equal(geom_implicit_sample_name((geom_implicit_sample)0), "?");
}

static void test_raw_all_types(void **state)
{
    (void)state;
    unsigned char buf[17 + 8 * N];
    for (size_t t = 0; t < 8; t++)
        for (int big = 0; big < 2; big++) {
            memset(buf, 0xAB, 17); /* a 17-byte header to skip */
            size_t n = 17 + put_all(buf + 17, all_types[t], big);
            geom_implicit_volume_read_options o;
            memset(&o, 0, sizeof o);
            o.dims[0] = NX, o.dims[1] = NY, o.dims[2] = NZ;
            o.sample = all_types[t];
            o.big_endian = big;
            o.skip = 17;
            o.spacing[0] = 0.5, o.spacing[1] = 2, o.spacing[2] = 3;
            o.origin[0] = -1, o.origin[1] = 1e8, o.origin[2] = 0;
            geom_implicit_volume *v;
            geom_implicit_volume_file_info info;
            geom_diag diag;
            assert_int_equal(geom_implicit_volume_read_memory(buf, n, "raw", &o, NULL, &v, &info,
                                                              &diag),
                             GEOM_OK);
            assert_int_equal(info.format, GEOM_IMPLICIT_VOLUME_RAW);
            assert_int_equal(info.sample, all_types[t]);
            geom_implicit_volume_desc d;
            geom_implicit_volume_get_desc(v, &d);
            assert_int_equal(d.type, geom_implicit_sample_size(all_types[t]) == 8 ||
                                             all_types[t] == GEOM_IMPLICIT_SAMPLE_U32 ||
                                             all_types[t] == GEOM_IMPLICIT_SAMPLE_I32
                                         ? GEOM_IMPLICIT_SCALAR_F64
                                         : GEOM_IMPLICIT_SCALAR_F32);
            check_volume(v, all_types[t], o.origin, o.spacing);
            geom_implicit_volume_destroy(v);
            /* one byte short, one byte long: both errors naming the sizes */
            assert_int_equal(geom_implicit_volume_read_memory(buf, n - 1, "raw", &o, NULL, &v,
                                                              NULL, &diag),
                             GEOM_ERR_PARSE);
            assert_null(v);
            assert_non_null(strstr(diag.message, "need"));
            o.skip = 16;
            assert_int_equal(geom_implicit_volume_read_memory(buf, n, "raw", &o, NULL, &v, NULL,
                                                              &diag),
                             GEOM_ERR_PARSE);
        }
}

/* Stand-in for zlib: "compressed" data is 'Z' followed by the bytes. */
static geom_status fake_inflate(void *user, const void *in, size_t n, void *out, size_t cap,
                                size_t *got)
{
    (*(int *)user)++;
    const unsigned char *p = in;
    if (n < 1 || p[0] != 'Z')
        return GEOM_ERR_PARSE;
    if (n - 1 > cap)
        return GEOM_ERR_LIMIT;
    memcpy(out, p + 1, n - 1);
    *got = n - 1;
    return GEOM_OK;
}

static const char *nrrd_type_name(geom_implicit_sample s)
{
    static const char *names[] = {"", "uchar", "signed char", "unsigned short", "short",
                                  "uint", "int32_t", "float", "double"};
    return names[s];
}

static void test_nrrd(void **state)
{
    (void)state;
    unsigned char buf[4096];
    int calls = 0;
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.inflate = fake_inflate;
    o.inflate_user = &calls;
    for (size_t t = 0; t < 8; t++)
        for (int enc = 0; enc < 4; enc++) { /* raw big, ascii, hex, gzip */
            geom_implicit_sample s = all_types[t];
            static const char *encs[] = {"raw", "ascii", "hex", "gzip"};
            int n = snprintf((char *)buf, sizeof buf,
                             "NRRD0004\n# a comment\ntype: %s\ndimension: 3\nsizes: %d %d %d\n"
                             "encoding: %s\nendian: big\nspace: right-anterior-superior\n"
                             "space directions: (-0.5,0,0) (0,2,0) (0,0,3)\n"
                             "space origin: (10,20,30)\nkey:=value\n\n",
                             nrrd_type_name(s), NX, NY, NZ, encs[enc]);
            size_t len = (size_t)n;
            unsigned char raw[8 * N];
            size_t rn = put_all(raw, s, 1);
            if (enc == 0) {
                memcpy(buf + len, raw, rn);
                len += rn;
            } else if (enc == 3) {
                buf[len++] = 'Z';
                memcpy(buf + len, raw, rn);
                len += rn;
            } else if (enc == 2) {
                for (size_t b = 0; b < rn; b++)
                    len += (size_t)snprintf((char *)buf + len, sizeof buf - len, "%02X%s", raw[b],
                                            b % 7 == 6 ? "\n" : "");
            } else {
                for (int k = 0; k < NZ; k++)
                    for (int j = 0; j < NY; j++)
                        for (int i = 0; i < NX; i++)
                            len += (size_t)snprintf((char *)buf + len, sizeof buf - len,
                                                    "%.17g%s", value(s, i, j, k),
                                                    i == NX - 1 ? "\n" : " ");
            }
            geom_implicit_volume *v;
            geom_implicit_volume_file_info info;
            geom_diag diag;
            geom_status st = geom_implicit_volume_read_memory(buf, len, "t.nrrd", &o, NULL, &v,
                                                              &info, &diag);
            if (st != GEOM_OK)
                fail_msg("%s %s: %s", nrrd_type_name(s), encs[enc], diag.message);
            assert_int_equal(info.format, GEOM_IMPLICIT_VOLUME_NRRD);
            assert_int_equal(info.flipped[0], 1);
            assert_int_equal(info.compressed, enc == 3);
            double org[3] = {10, 20, 30}, step[3] = {-0.5, 2, 3};
            check_volume(v, s, org, step);
            geom_implicit_volume_destroy(v);
        }
    assert_int_equal(calls, 8);
}

static geom_status read_text(const char *text, size_t extra, geom_diag *diag)
{
    static unsigned char buf[8192];
    size_t n = strlen(text);
    memcpy(buf, text, n);
    memset(buf + n, 0, extra);
    geom_implicit_volume *v = NULL;
    geom_status st = geom_implicit_volume_read_memory(buf, n + extra, "bad", NULL, NULL, &v, NULL,
                                                      diag);
    if (st == GEOM_OK)
        geom_implicit_volume_destroy(v);
    else
        assert_null(v);
    return st;
}

static void test_errors(void **state)
{
    (void)state;
    geom_diag d;
    /* unknown format, no raw dims */
    assert_int_equal(read_text("hello world\n", 0, &d), GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "not a known volume format"));
    /* NRRD: 64-bit type, oblique axes, short data, bzip2, missing endian */
    assert_int_equal(read_text("NRRD0004\ntype: int64\n", 0, &d), GEOM_ERR_PARSE);
    assert_int_equal(d.line, 2);
    assert_int_equal(read_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: "
                               "raw\nspace directions: (1,1,0) (0,1,0) (0,0,1)\n\n",
                               8, &d),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "rotated"));
    assert_int_equal(read_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: "
                               "raw\n\n",
                               7, &d),
                     GEOM_ERR_PARSE);
    assert_int_equal(read_text("NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: "
                               "raw\n\n",
                               16, &d),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "endian"));
    assert_int_equal(read_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: "
                               "bzip2\n\n",
                               8, &d),
                     GEOM_ERR_PARSE);
    /* gzip without an inflate callback */
    assert_int_equal(read_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: "
                               "gzip\n\n",
                               8, &d),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "decompressor"));
    /* a 4-D volume with 2 components is not scalar */
    assert_int_equal(read_text("NRRD0004\ntype: uchar\ndimension: 4\nsizes: 2 2 2 2\nencoding: "
                               "raw\n\n",
                               16, &d),
                     GEOM_ERR_PARSE);
    /* detached data cannot be read from memory */
    assert_int_equal(read_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: "
                               "raw\ndata file: x.raw\n",
                               0, &d),
                     GEOM_ERR_PARSE);
    /* MetaImage: channels, unknown type, missing data file */
    assert_int_equal(read_text("ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = "
                               "MET_UCHAR\nElementNumberOfChannels = 3\nElementDataFile = LOCAL\n",
                               24, &d),
                     GEOM_ERR_PARSE);
    assert_int_equal(read_text("ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = "
                               "MET_LONG_LONG\nElementDataFile = LOCAL\n",
                               64, &d),
                     GEOM_ERR_PARSE);
    assert_int_equal(read_text("ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = "
                               "MET_UCHAR\n",
                               0, &d),
                     GEOM_ERR_PARSE);
    /* INRIMAGE without the end of its header, and with VDIM 3 */
    assert_int_equal(read_text("#INRIMAGE-4#{\nXDIM=2\n", 0, &d), GEOM_ERR_PARSE);
    assert_int_equal(read_text("#INRIMAGE-4#{\nXDIM=2\nYDIM=2\nZDIM=2\nVDIM=3\nTYPE=float\n"
                               "PIXSIZE=32 bits\nCPU=decm\n##}\n",
                               400, &d),
                     GEOM_ERR_PARSE);
}

/* The dimension count and sizes fields of NRRD ("dimension", "sizes") and
 * MetaImage ("NDims", "DimSize"): the same checks and messages, each naming
 * its own field and the line. */
static void test_dims_fields(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        size_t line;
        const char *msg;
    } cases[] = {
        {"NRRD0004\ntype: uchar\ndimension: 0\n", 3, "bad dimension '0'"},
        {"NRRD0004\ntype: uchar\ndimension: 17\n", 3, "bad dimension '17'"},
        {"NRRD0004\ntype: uchar\ndimension: 3 3\n", 3, "bad dimension '3 3'"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 x 2\n", 4, "bad sizes '2 x 2'"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: \n", 4, "bad sizes ''"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2\nencoding: raw\n\n", 6,
         "sizes has 2 values but dimension is 3"},
        {"NDims = 0\n", 1, "bad NDims '0'"},
        {"NDims = 3\nDimSize = 2 -2 2\n", 2, "bad DimSize '2 -2 2'"},
        {"NDims = 3\nDimSize = 2 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", 4,
         "DimSize has 2 values but NDims is 3"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        geom_diag d;
        assert_int_equal(read_text(cases[i].text, 8, &d), GEOM_ERR_PARSE);
        if (!strstr(d.message, cases[i].msg) || d.line != cases[i].line)
            fail_msg("case %zu: line %zu '%s', expected line %zu '%s'", i, (size_t)d.line,
                     d.message, cases[i].line, cases[i].msg);
    }
    /* without NDims, DimSize alone sets the count (4-D with a unit axis) */
    geom_diag d;
    assert_int_equal(read_text("DimSize = 2 2 2 1\nElementType = MET_UCHAR\n"
                               "ElementDataFile = LOCAL\n",
                               8, &d),
                     GEOM_OK);
}

static void test_metaimage(void **state)
{
    (void)state;
    unsigned char buf[4096];
    geom_implicit_sample s = GEOM_IMPLICIT_SAMPLE_I16;
    int n = snprintf((char *)buf, sizeof buf,
                     "ObjectType = Image\nNDims = 3\nBinaryData = True\n"
                     "BinaryDataByteOrderMSB = True\nCompressedData = False\n"
                     "TransformMatrix = 1 0 0 0 1 0 0 0 -1\nOffset = 1 2 3\n"
                     "ElementSpacing = 0.5 0.25 4\nDimSize = %d %d %d\nElementType = MET_SHORT\n"
                     "ElementDataFile = LOCAL\n",
                     NX, NY, NZ);
    size_t len = (size_t)n + put_all(buf + n, s, 1);
    geom_implicit_volume *v;
    geom_diag diag;
    geom_implicit_volume_file_info info;
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.mha", NULL, NULL, &v, &info,
                                                      &diag),
                     GEOM_OK);
    assert_int_equal(info.format, GEOM_IMPLICIT_VOLUME_METAIMAGE);
    double org[3] = {1, 2, 3}, step[3] = {0.5, 0.25, -4};
    check_volume(v, s, org, step);
    geom_implicit_volume_destroy(v);

    /* .mhd naming a .raw next to it, with HeaderSize -1 (data at the end) */
    char dir[] = "/tmp/geom_volfmt_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char hdr[256], dat[256];
    snprintf(hdr, sizeof hdr, "%s/v.mhd", dir);
    snprintf(dat, sizeof dat, "%s/v.raw", dir);
    FILE *fp = fopen(hdr, "wb");
    assert_non_null(fp);
    fprintf(fp, "NDims = 3\nDimSize = %d %d %d\nElementType = MET_FLOAT\nHeaderSize = -1\n"
                "ElementDataFile = v.raw\n",
            NX, NY, NZ);
    fclose(fp);
    s = GEOM_IMPLICIT_SAMPLE_F32;
    unsigned char raw[9 + 4 * N];
    memset(raw, 7, 9);
    size_t rn = 9 + put_all(raw + 9, s, 0);
    fp = fopen(dat, "wb");
    assert_non_null(fp);
    fwrite(raw, 1, rn, fp);
    fclose(fp);
    assert_int_equal(geom_implicit_volume_read(hdr, NULL, NULL, &v, NULL, &diag), GEOM_OK);
    double org0[3] = {0, 0, 0}, unit[3] = {1, 1, 1};
    check_volume(v, s, org0, unit);
    geom_implicit_volume_destroy(v);
    /* the data file missing: an I/O error naming it */
    remove(dat);
    assert_int_equal(geom_implicit_volume_read(hdr, NULL, NULL, &v, NULL, &diag), GEOM_ERR_IO);
    assert_non_null(strstr(diag.source, "v.raw"));
    remove(hdr);
    rmdir(dir);
}

static void test_inrimage(void **state)
{
    (void)state;
    for (int big = 0; big < 2; big++) {
        unsigned char buf[256 + 4 * N];
        memset(buf, '\n', 256);
        geom_implicit_sample s = GEOM_IMPLICIT_SAMPLE_U16;
        int n = snprintf((char *)buf, 256,
                         "#INRIMAGE-4#{\nXDIM=%d\nYDIM=%d\nZDIM=%d\nVDIM=1\nTYPE=unsigned fixed\n"
                         "PIXSIZE=16 bits\nSCALE=2**0\nCPU=%s\nVX=0.5\nVY=1.5\nVZ=2\nXO=-3\n"
                         "#GEOMETRY=CARTESIAN\n",
                         NX, NY, NZ, big ? "sun" : "decm");
        buf[n] = '\n';
        memcpy(buf + 252, "##}\n", 4);
        size_t len = 256 + put_all(buf + 256, s, big);
        geom_implicit_volume *v;
        geom_diag diag;
        geom_status st = geom_implicit_volume_read_memory(buf, len, "t.inr", NULL, NULL, &v, NULL,
                                                          &diag);
        if (st != GEOM_OK)
            fail_msg("%s", diag.message);
        double org[3] = {-3, 0, 0}, step[3] = {0.5, 1.5, 2};
        check_volume(v, s, org, step);
        geom_implicit_volume_destroy(v);
    }
}

static void put16(unsigned char *h, size_t off, int v, int big)
{
    put(h + off, GEOM_IMPLICIT_SAMPLE_I16, v, big);
}

static void putf(unsigned char *h, size_t off, double v, int big)
{
    put(h + off, GEOM_IMPLICIT_SAMPLE_F32, v, big);
}

/* A NIfTI-1 header for NX x NY x NZ samples of NIfTI datatype dt. */
static void nifti_header(unsigned char *h, int dt, int bitpix, int big, const char *magic)
{
    memset(h, 0, 352);
    put(h, GEOM_IMPLICIT_SAMPLE_I32, 348, big);
    put16(h, 40, 3, big);
    put16(h, 42, NX, big);
    put16(h, 44, NY, big);
    put16(h, 46, NZ, big);
    put16(h, 48, 1, big);
    put16(h, 70, dt, big);
    put16(h, 72, bitpix, big);
    putf(h, 108, 352, big);
    memcpy(h + 344, magic, 4);
}

static void test_nifti(void **state)
{
    (void)state;
    static const struct {
        int dt;
        geom_implicit_sample s;
    } types[] = {{2, GEOM_IMPLICIT_SAMPLE_U8},    {4, GEOM_IMPLICIT_SAMPLE_I16},
                 {8, GEOM_IMPLICIT_SAMPLE_I32},   {16, GEOM_IMPLICIT_SAMPLE_F32},
                 {64, GEOM_IMPLICIT_SAMPLE_F64},  {256, GEOM_IMPLICIT_SAMPLE_I8},
                 {512, GEOM_IMPLICIT_SAMPLE_U16}, {768, GEOM_IMPLICIT_SAMPLE_U32}};
    unsigned char buf[352 + 8 * N];
    geom_implicit_volume *v;
    geom_diag diag;
    for (size_t t = 0; t < 8; t++)
        for (int big = 0; big < 2; big++)
            for (int placement = 0; placement < 3; placement++) {
                geom_implicit_sample s = types[t].s;
                nifti_header(buf, types[t].dt, (int)geom_implicit_sample_size(s) * 8, big, "n+1");
                putf(buf, 76, -1, big); /* qfac */
                putf(buf, 80, 0.5, big);
                putf(buf, 84, 2, big);
                putf(buf, 88, 3, big);
                double org[3] = {0, 0, 0}, step[3] = {0.5, 2, 3};
                if (placement == 1) { /* qform: identity rotation, qfac -1 flips z */
                    put16(buf, 252, 1, big);
                    putf(buf, 268, 5, big);
                    putf(buf, 272, 6, big);
                    putf(buf, 276, 7, big);
                    org[0] = 5, org[1] = 6, org[2] = 7;
                    step[2] = -3;
                } else if (placement == 2) { /* sform: x flipped */
                    put16(buf, 252, 1, big);
                    put16(buf, 254, 2, big);
                    putf(buf, 280, -0.25, big);
                    putf(buf, 292, 10, big);
                    putf(buf, 300, 4, big);
                    putf(buf, 308, -5, big);
                    putf(buf, 320, 1, big);
                    putf(buf, 324, 1, big);
                    org[0] = 10, org[1] = -5, org[2] = 1;
                    step[0] = -0.25, step[1] = 4, step[2] = 1;
                }
                size_t len = 352 + put_all(buf + 352, s, big);
                geom_implicit_volume_file_info info;
                geom_status st = geom_implicit_volume_read_memory(buf, len, "t.nii", NULL, NULL,
                                                                  &v, &info, &diag);
                if (st != GEOM_OK)
                    fail_msg("dt %d: %s", types[t].dt, diag.message);
                assert_int_equal(info.format, GEOM_IMPLICIT_VOLUME_NIFTI);
                check_volume(v, s, org, step);
                geom_implicit_volume_destroy(v);
            }
    /* scl_slope / scl_inter: values * 2 + 1, in a float64 volume */
    nifti_header(buf, 4, 16, 0, "n+1");
    putf(buf, 112, 2, 0);
    putf(buf, 116, 1, 0);
    size_t len = 352 + put_all(buf + 352, GEOM_IMPLICIT_SAMPLE_I16, 0);
    geom_implicit_volume_file_info info;
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.nii", NULL, NULL, &v, &info,
                                                      &diag),
                     GEOM_OK);
    assert_int_equal(info.scaled, 1);
    assert_true(geom_implicit_volume_at(v, 3, 2, 1) ==
                2 * value(GEOM_IMPLICIT_SAMPLE_I16, 3, 2, 1) + 1);
    geom_implicit_volume_destroy(v);
    /* unsupported datatype (complex64) and a time series */
    nifti_header(buf, 32, 64, 0, "n+1");
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.nii", NULL, NULL, &v, NULL,
                                                      &diag),
                     GEOM_ERR_PARSE);
    assert_int_equal(diag.byte_offset, 70);
    nifti_header(buf, 2, 8, 0, "n+1");
    put16(buf, 40, 4, 0);
    put16(buf, 48, 2, 0);
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.nii", NULL, NULL, &v, NULL,
                                                      &diag),
                     GEOM_ERR_PARSE);

    /* .hdr + .img pair */
    char dir[] = "/tmp/geom_volfmt_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char hdr[256], img[256];
    snprintf(hdr, sizeof hdr, "%s/a.hdr", dir);
    snprintf(img, sizeof img, "%s/a.img", dir);
    nifti_header(buf, 512, 16, 1, "ni1");
    putf(buf, 108, 0, 1);
    FILE *fp = fopen(hdr, "wb");
    assert_non_null(fp);
    fwrite(buf, 1, 348, fp);
    fclose(fp);
    len = put_all(buf, GEOM_IMPLICIT_SAMPLE_U16, 1);
    fp = fopen(img, "wb");
    assert_non_null(fp);
    fwrite(buf, 1, len, fp);
    fclose(fp);
    assert_int_equal(geom_implicit_volume_read(hdr, NULL, NULL, &v, NULL, &diag), GEOM_OK);
    double org[3] = {0, 0, 0}, unit[3] = {1, 1, 1};
    check_volume(v, GEOM_IMPLICIT_SAMPLE_U16, org, unit);
    geom_implicit_volume_destroy(v);
    remove(hdr);
    remove(img);
    rmdir(dir);
}

/* A whole-file "gzip" (magic 1f 8b) goes through the inflate callback. */
static geom_status fake_gunzip(void *user, const void *in, size_t n, void *out, size_t cap,
                               size_t *got)
{
    (void)user;
    const unsigned char *p = in;
    /* our stand-in: 1f 8b, then the plain bytes, then a 4-byte size */
    if (n < 6 || p[0] != 0x1f || p[1] != 0x8b)
        return GEOM_ERR_PARSE;
    size_t m = n - 6;
    if (m > cap)
        return GEOM_ERR_LIMIT;
    memcpy(out, p + 2, m);
    *got = m;
    return GEOM_OK;
}

static void test_whole_file_gzip(void **state)
{
    (void)state;
    unsigned char buf[2 + 352 + 8 * N + 4];
    buf[0] = 0x1f;
    buf[1] = 0x8b;
    nifti_header(buf + 2, 16, 32, 0, "n+1");
    size_t len = 2 + 352 + put_all(buf + 2 + 352, GEOM_IMPLICIT_SAMPLE_F32, 0);
    /* ISIZE deliberately too small: the reader must grow and retry */
    memset(buf + len, 0, 4);
    buf[len] = 3;
    len += 4;
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.inflate = fake_gunzip;
    geom_implicit_volume *v;
    geom_diag diag;
    geom_implicit_volume_file_info info;
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.nii.gz", &o, NULL, &v, &info,
                                                      &diag),
                     GEOM_OK);
    assert_int_equal(info.compressed, 1);
    double org[3] = {0, 0, 0}, unit[3] = {1, 1, 1};
    check_volume(v, GEOM_IMPLICIT_SAMPLE_F32, org, unit);
    geom_implicit_volume_destroy(v);
    /* without a callback: a clear error */
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.nii.gz", NULL, NULL, &v, NULL,
                                                      &diag),
                     GEOM_ERR_PARSE);
}

/* Stand-in for libbz2: "BZh9", the block magic 31 41 59 26 53 59, then the
 * plain bytes; anything else is corrupt. */
static geom_status fake_bunzip2(void *user, const void *in, size_t n, void *out, size_t cap,
                                size_t *got)
{
    static const unsigned char head[10] = {'B', 'Z', 'h', '9', 0x31, 0x41, 0x59, 0x26, 0x53, 0x59};
    (*(int *)user)++;
    *got = 0;
    if (n < 10 || memcmp(in, head, 10) != 0)
        return GEOM_ERR_PARSE;
    if (n - 10 > cap)
        return GEOM_ERR_LIMIT;
    memcpy(out, (const unsigned char *)in + 10, n - 10);
    *got = n - 10;
    return GEOM_OK;
}

static size_t nrrd_bz_file(unsigned char *buf, size_t cap, geom_implicit_sample s, int corrupt)
{
    static const unsigned char head[10] = {'B', 'Z', 'h', '9', 0x31, 0x41, 0x59, 0x26, 0x53, 0x59};
    size_t len = (size_t)snprintf((char *)buf, cap,
                                  "NRRD0005\ntype: %s\ndimension: 3\nsizes: %d %d %d\n"
                                  "encoding: bzip2\nendian: little\nspacings: 2 3 4\n\n",
                                  nrrd_type_name(s), NX, NY, NZ);
    memcpy(buf + len, head, 10);
    if (corrupt)
        buf[len + 1] = 'X';
    return len + 10 + put_all(buf + len + 10, s, 0);
}

/* NRRD bzip2 encoding and whole .bz2 files go through options->bunzip2 (never
 * the gzip callback); without it, or on corrupt data, a clear error. */
static void test_bzip2(void **state)
{
    (void)state;
    unsigned char buf[4096];
    int bz_calls = 0, gz_calls = 0;
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.inflate = fake_inflate;
    o.inflate_user = &gz_calls;
    o.bunzip2 = fake_bunzip2;
    o.bunzip2_user = &bz_calls;
    double org[3] = {0, 0, 0}, step[3] = {2, 3, 4};
    for (size_t t = 0; t < 8; t++) {
        size_t len = nrrd_bz_file(buf, sizeof buf, all_types[t], 0);
        geom_implicit_volume *v;
        geom_implicit_volume_file_info info;
        geom_diag diag;
        if (geom_implicit_volume_read_memory(buf, len, "t.nrrd", &o, NULL, &v, &info, &diag) !=
            GEOM_OK)
            fail_msg("%s: %s", nrrd_type_name(all_types[t]), diag.message);
        assert_int_equal(info.compressed, 1);
        check_volume(v, all_types[t], org, step);
        geom_implicit_volume_destroy(v);
    }
    assert_int_equal(bz_calls, 8);
    assert_int_equal(gz_calls, 0);
    /* a corrupt stream: GEOM_ERR_PARSE naming the source and bzip2 */
    size_t len = nrrd_bz_file(buf, sizeof buf, GEOM_IMPLICIT_SAMPLE_F32, 1);
    geom_implicit_volume *v = NULL;
    geom_diag diag;
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "bad.nrrd", &o, NULL, &v, NULL,
                                                      &diag),
                     GEOM_ERR_PARSE);
    assert_null(v);
    assert_string_equal(diag.source, "bad.nrrd");
    assert_non_null(strstr(diag.message, "bzip2"));
    /* short data: decompresses to fewer bytes than the header declares */
    len = nrrd_bz_file(buf, sizeof buf, GEOM_IMPLICIT_SAMPLE_F32, 0);
    assert_int_equal(geom_implicit_volume_read_memory(buf, len - 3, "short.nrrd", &o, NULL, &v,
                                                      NULL, &diag),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(diag.message, "expected"));
    /* no bunzip2 callback: the message names the missing library */
    o.bunzip2 = NULL;
    assert_int_equal(geom_implicit_volume_read_memory(buf, len, "t.nrrd", &o, NULL, &v, NULL,
                                                      &diag),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(diag.message, "libbz2"));
    assert_int_equal(gz_calls, 0);
    /* a whole NIfTI file compressed with bzip2, detected by its magic */
    o.bunzip2 = fake_bunzip2;
    static const unsigned char head[10] = {'B', 'Z', 'h', '9', 0x31, 0x41, 0x59, 0x26, 0x53, 0x59};
    unsigned char nii[10 + 352 + 4 * N];
    memcpy(nii, head, 10);
    nifti_header(nii + 10, 16, 32, 0, "n+1");
    for (int a = 1; a <= 3; a++)
        putf(nii + 10, 76 + 4 * (size_t)a, 1.0, 0);
    size_t nlen = 10 + 352 + put_all(nii + 10 + 352, GEOM_IMPLICIT_SAMPLE_F32, 0);
    geom_implicit_volume_file_info info;
    assert_int_equal(geom_implicit_volume_read_memory(nii, nlen, "t.nii.bz2", &o, NULL, &v, &info,
                                                      &diag),
                     GEOM_OK);
    assert_int_equal(info.compressed, 1);
    assert_int_equal(info.format, GEOM_IMPLICIT_VOLUME_NIFTI);
    double unit[3] = {1, 1, 1};
    check_volume(v, GEOM_IMPLICIT_SAMPLE_F32, org, unit);
    geom_implicit_volume_destroy(v);
    /* raw samples that happen to start with the magic are raw without the callback */
    o.bunzip2 = NULL;
    o.inflate = NULL;
    o.format = GEOM_IMPLICIT_VOLUME_RAW;
    o.dims[0] = 10;
    o.dims[1] = o.dims[2] = 1;
    o.sample = GEOM_IMPLICIT_SAMPLE_U8;
    assert_int_equal(geom_implicit_volume_read_memory(head, 10, "r.raw", &o, NULL, &v, NULL, &diag),
                     GEOM_OK);
    assert_true(geom_implicit_volume_at(v, 0, 0, 0) == 'B');
    geom_implicit_volume_destroy(v);
}

static geom_status read_info(const unsigned char *buf, size_t n, const char *name,
                             geom_implicit_volume **v, geom_implicit_volume_file_info *info,
                             geom_diag *diag)
{
    geom_status st = geom_implicit_volume_read_memory(buf, n, name, NULL, NULL, v, info, diag);
    if (st != GEOM_OK)
        assert_null(*v);
    return st;
}

/* Unknown or invalid header spacing is never silently 1: NRRD nan (Teem's
 * "unknown") and NIfTI pixdim <= 0 / NaN are read as 1 and reported in the
 * file info with the field, its place and its value; NRRD 0 or inf,
 * MetaImage and INRIMAGE non-positive or non-finite spacing are errors
 * naming the line, the key and the value. */
static void test_spacing_rules(void **state)
{
    (void)state;
    unsigned char buf[4096];
    geom_implicit_volume *v = NULL;
    geom_implicit_volume_file_info info;
    geom_diag diag;
    /* NRRD */
    static const char *nrrd = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: %d %d %d\n"
                              "encoding: raw\nspacings: %s\n\n";
    int n = snprintf((char *)buf, sizeof buf, nrrd, NX, NY, NZ, "nan 0.5 NaN");
    size_t len = (size_t)n + put_all(buf + n, GEOM_IMPLICIT_SAMPLE_U8, 0);
    assert_int_equal(read_info(buf, len, "s.nrrd", &v, &info, &diag), GEOM_OK);
    assert_int_equal(info.spacing_defaulted[0], 1);
    assert_int_equal(info.spacing_defaulted[1], 0);
    assert_int_equal(info.spacing_defaulted[2], 1);
    assert_non_null(strstr(info.spacing_note, "line 6"));
    assert_non_null(strstr(info.spacing_note, "spacings: nan 0.5 NaN"));
    assert_non_null(strstr(info.spacing_note, "axis 0, 2"));
    double org[3] = {0, 0, 0}, step[3] = {1, 0.5, 1};
    check_volume(v, GEOM_IMPLICIT_SAMPLE_U8, org, step);
    geom_implicit_volume_destroy(v);
    /* a negative NRRD spacing reverses the axis (Teem allows it): no note */
    n = snprintf((char *)buf, sizeof buf, nrrd, NX, NY, NZ, "-2 1 1");
    len = (size_t)n + put_all(buf + n, GEOM_IMPLICIT_SAMPLE_U8, 0);
    assert_int_equal(read_info(buf, len, "s.nrrd", &v, &info, &diag), GEOM_OK);
    assert_int_equal(info.spacing_defaulted[0], 0);
    assert_int_equal(info.flipped[0], 1);
    assert_string_equal(info.spacing_note, "");
    double step2[3] = {-2, 1, 1};
    check_volume(v, GEOM_IMPLICIT_SAMPLE_U8, org, step2);
    geom_implicit_volume_destroy(v);
    static const char *bad_nrrd[] = {"1 0 1", "1 1 inf", "-inf 1 1"};
    for (int b = 0; b < 3; b++) {
        n = snprintf((char *)buf, sizeof buf, nrrd, NX, NY, NZ, bad_nrrd[b]);
        len = (size_t)n + put_all(buf + n, GEOM_IMPLICIT_SAMPLE_U8, 0);
        assert_int_equal(read_info(buf, len, "s.nrrd", &v, &info, &diag), GEOM_ERR_PARSE);
        assert_int_equal(diag.line, 6);
        assert_non_null(strstr(diag.message, "spacings"));
        assert_non_null(strstr(diag.message, bad_nrrd[b]));
    }
    /* MetaImage ElementSpacing / ElementSize */
    static const char *bad_met[] = {"ElementSpacing = nan 1 1", "ElementSpacing = 1 0 1",
                                    "ElementSpacing = 1 1 -2", "ElementSize = 1 inf 1"};
    for (int b = 0; b < 4; b++) {
        n = snprintf((char *)buf, sizeof buf,
                     "NDims = 3\nDimSize = %d %d %d\nElementType = MET_UCHAR\n%s\n"
                     "ElementDataFile = LOCAL\n",
                     NX, NY, NZ, bad_met[b]);
        len = (size_t)n + put_all(buf + n, GEOM_IMPLICIT_SAMPLE_U8, 0);
        assert_int_equal(read_info(buf, len, "s.mha", &v, &info, &diag), GEOM_ERR_PARSE);
        assert_int_equal(diag.line, 4);
        assert_string_equal(diag.source, "s.mha");
        assert_non_null(strstr(diag.message, b == 3 ? "ElementSize" : "ElementSpacing"));
        assert_non_null(strstr(diag.message, "positive"));
    }
    /* INRIMAGE VX/VY/VZ */
    static const char *bad_inr[] = {"VX=0", "VY=-1.5", "VZ=nan"};
    for (int b = 0; b < 3; b++) {
        memset(buf, '\n', 256);
        n = snprintf((char *)buf, 256,
                     "#INRIMAGE-4#{\nXDIM=%d\nYDIM=%d\nZDIM=%d\nVDIM=1\nTYPE=unsigned fixed\n"
                     "PIXSIZE=8 bits\nCPU=decm\n%s\n",
                     NX, NY, NZ, bad_inr[b]);
        buf[n] = '\n';
        memcpy(buf + 252, "##}\n", 4);
        len = 256 + put_all(buf + 256, GEOM_IMPLICIT_SAMPLE_U8, 0);
        assert_int_equal(read_info(buf, len, "s.inr", &v, &info, &diag), GEOM_ERR_PARSE);
        assert_int_equal(diag.line, 9);
        char key[3] = {bad_inr[b][0], bad_inr[b][1], '\0'};
        assert_non_null(strstr(diag.message, key));
    }
    /* NIfTI pixdim: without an sform (pixdim or qform placement) */
    unsigned char nii[352 + N];
    for (int q = 0; q < 2; q++) {
        nifti_header(nii, 2, 8, 0, "n+1");
        putf(nii, 76, 1, 0); /* qfac */
        putf(nii, 80, 0.0, 0);
        putf(nii, 84, 3.0, 0);
        putf(nii, 88, q ? NAN : -2.0, 0);
        if (q) {
            put16(nii, 252, 1, 0); /* qform: identity quaternion, offset (0, 0, 0) */
        }
        len = 352 + put_all(nii + 352, GEOM_IMPLICIT_SAMPLE_U8, 0);
        assert_int_equal(read_info(nii, len, "s.nii", &v, &info, &diag), GEOM_OK);
        assert_int_equal(info.spacing_defaulted[0], 1);
        assert_int_equal(info.spacing_defaulted[1], 0);
        assert_int_equal(info.spacing_defaulted[2], 1);
        assert_non_null(strstr(info.spacing_note, "pixdim[1] = 0 (byte 80)"));
        assert_non_null(strstr(info.spacing_note, q ? "pixdim[3] = nan (byte 88)"
                                                     : "pixdim[3] = -2 (byte 88)"));
        double s3[3] = {1, 3, 1};
        check_volume(v, GEOM_IMPLICIT_SAMPLE_U8, org, s3);
        geom_implicit_volume_destroy(v);
    }
    /* with an sform, pixdim is not used: no note */
    nifti_header(nii, 2, 8, 0, "n+1");
    put16(nii, 254, 1, 0);
    putf(nii, 280, 2, 0);
    putf(nii, 300, 2, 0);
    putf(nii, 320, 2, 0);
    len = 352 + put_all(nii + 352, GEOM_IMPLICIT_SAMPLE_U8, 0);
    assert_int_equal(read_info(nii, len, "s.nii", &v, &info, &diag), GEOM_OK);
    for (int a = 0; a < 3; a++)
        assert_int_equal(info.spacing_defaulted[a], 0);
    double s2[3] = {2, 2, 2};
    check_volume(v, GEOM_IMPLICIT_SAMPLE_U8, org, s2);
    geom_implicit_volume_destroy(v);
}

/* CGAL's skull_2.9.inr (64^3 float32) when GEOM_CGAL_IMAGES names the
 * directory holding it (tests/tools extracts it from libcgal-demo). The
 * reference samples are decoded here byte by byte from the file. */
static void test_cgal_skull(void **state)
{
    (void)state;
    const char *dir = getenv("GEOM_CGAL_IMAGES");
    char path[4096];
    snprintf(path, sizeof path, "%s/skull_2.9.inr", dir ? dir : "");
    FILE *fp = dir ? fopen(path, "rb") : NULL;
    if (!fp)
        skip();
    unsigned char *raw = malloc(256 + 4 * 64 * 64 * 64);
    assert_non_null(raw);
    size_t n = fread(raw, 1, 256 + 4 * 64 * 64 * 64, fp);
    fclose(fp);
    assert_int_equal(n, 256 + 4 * 64 * 64 * 64);
    geom_implicit_volume *v;
    geom_diag diag;
    assert_int_equal(geom_implicit_volume_read(path, NULL, NULL, &v, NULL, &diag), GEOM_OK);
    geom_implicit_volume_desc d;
    geom_implicit_volume_get_desc(v, &d);
    assert_int_equal(d.dims[0], 64);
    assert_true(d.spacing[0] == 3.943050 && d.spacing[2] == 3.650790);
    for (size_t idx = 0; idx < 64 * 64 * 64; idx += 997) {
        const unsigned char *p = raw + 256 + 4 * idx;
        uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                     (uint32_t)p[3] << 24;
        float f;
        memcpy(&f, &u, 4);
        assert_true(geom_implicit_volume_at(v, idx % 64, idx / 64 % 64, idx / 4096) == (double)f);
    }
    geom_implicit_volume_destroy(v);
    free(raw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sample_names), cmocka_unit_test(test_raw_all_types),
        cmocka_unit_test(test_nrrd),         cmocka_unit_test(test_errors),
        cmocka_unit_test(test_dims_fields),  cmocka_unit_test(test_metaimage),
        cmocka_unit_test(test_inrimage),     cmocka_unit_test(test_nifti),
        cmocka_unit_test(test_whole_file_gzip), cmocka_unit_test(test_cgal_skull),
        cmocka_unit_test(test_bzip2),        cmocka_unit_test(test_spacing_rules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
