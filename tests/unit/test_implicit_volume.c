/*
 * Tests of sampled volumes: trilinear values and central-difference
 * gradients against closed forms, the raw and NRRD readers (data/ samples
 * made from closed forms, see data/README.md; malformed headers, gzip,
 * short data, endianness, ASCII data, detached headers), the iso adapters,
 * and a contour of a volume slice.
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

#include "geom/implicit.h"

static char path_buf[4096];

static const char *data_path(const char *name)
{
    const char *dir = getenv("GEOM_TEST_DATA");
    if (!dir)
        dir = "data";
    snprintf(path_buf, sizeof path_buf, "%s/%s", dir, name);
    return path_buf;
}

static geom_implicit_volume *make_volume(size_t nx, size_t ny, size_t nz,
                                         geom_implicit_scalar type, double sp, double org,
                                         double (*fn)(double, double, double))
{
    geom_implicit_volume_desc d;
    memset(&d, 0, sizeof d);
    d.dims[0] = nx, d.dims[1] = ny, d.dims[2] = nz;
    d.type = type;
    for (int a = 0; a < 3; a++) {
        d.spacing[a] = sp * (a + 1);
        d.origin[a] = org;
    }
    geom_implicit_volume *v;
    assert_int_equal(geom_implicit_volume_create(&d, NULL, &v), GEOM_OK);
    void *data = geom_implicit_volume_data(v);
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                double x = org + i * sp, y = org + j * 2 * sp, z = org + k * 3 * sp;
                size_t idx = i + nx * (j + ny * k);
                if (type == GEOM_IMPLICIT_SCALAR_F32)
                    ((float *)data)[idx] = (float)fn(x, y, z);
                else
                    ((double *)data)[idx] = fn(x, y, z);
            }
    return v;
}

static double linear_fn(double x, double y, double z) { return 1 + 2 * x - 3 * y + 0.5 * z; }
static double quad_fn(double x, double y, double z) { return x * x + 2 * y * y - z * z + x * y; }

static void test_trilinear(void **state)
{
    (void)state;
    geom_implicit_volume *v = make_volume(6, 5, 4, GEOM_IMPLICIT_SCALAR_F64, 0.5, -1.0, linear_fn);
    geom_implicit_volume_desc d;
    geom_implicit_volume_get_desc(v, &d);
    assert_int_equal(d.dims[0], 6);
    assert_true(d.spacing[1] == 1.0 && d.origin[2] == -1.0);
    geom_aabb b = geom_implicit_volume_bounds(v);
    assert_true(b.min.x == -1.0 && b.max.x == 1.5 && b.max.y == 3.0 && b.max.z == 3.5);
    /* samples, exactly */
    for (size_t k = 0; k < 4; k++)
        for (size_t j = 0; j < 5; j++)
            for (size_t i = 0; i < 6; i++) {
                double p[3] = {-1 + 0.5 * i, -1 + 1.0 * j, -1 + 1.5 * k};
                assert_true(geom_implicit_volume_eval(v, p) == linear_fn(p[0], p[1], p[2]));
                assert_true(geom_implicit_volume_at(v, i, j, k) == linear_fn(p[0], p[1], p[2]));
            }
    assert_true(isnan(geom_implicit_volume_at(v, 6, 0, 0)));
    /* trilinear interpolation reproduces a linear function; its gradient too */
    for (int s = 0; s < 200; s++) {
        double p[3] = {-1 + 2.5 * (s % 17) / 16.0, -1 + 4.0 * (s % 13) / 12.0,
                       -1 + 4.5 * (s % 7) / 6.0};
        double g[3];
        double val = geom_implicit_volume_eval_grad(v, p, g);
        assert_true(fabs(val - linear_fn(p[0], p[1], p[2])) < 1e-14);
        assert_true(fabs(g[0] - 2) < 1e-14 && fabs(g[1] + 3) < 1e-14 && fabs(g[2] - 0.5) < 1e-14);
    }
    /* outside: clamped onto the box */
    double out[3] = {-5, 0, 0}, in[3] = {-1, 0, 0};
    assert_true(geom_implicit_volume_eval(v, out) == geom_implicit_volume_eval(v, in));
    double nanp[3] = {NAN, 0, 0};
    assert_true(isnan(geom_implicit_volume_eval(v, nanp)));
    geom_implicit_volume_destroy(v);

    /* central differences are exact for quadratics at interior samples;
     * one-sided on the border (error h * f'' / 2) */
    v = make_volume(7, 6, 5, GEOM_IMPLICIT_SCALAR_F64, 0.25, 0.0, quad_fn);
    for (size_t k = 0; k < 5; k++)
        for (size_t j = 0; j < 6; j++)
            for (size_t i = 0; i < 7; i++) {
                double p[3] = {0.25 * i, 0.5 * j, 0.75 * k}, g[3];
                geom_implicit_volume_eval_grad(v, p, g);
                double gx = 2 * p[0] + p[1], gy = 4 * p[1] + p[0], gz = -2 * p[2];
                if (i == 0)
                    gx += 0.25; /* forward difference: + h f_xx / 2 = 0.25 * 2 / 2 */
                if (i == 6)
                    gx -= 0.25;
                if (j == 0)
                    gy += 1.0; /* h = 0.5, f_yy = 4 */
                if (j == 5)
                    gy -= 1.0;
                if (k == 0)
                    gz -= 0.75; /* h = 0.75, f_zz = -2 */
                if (k == 4)
                    gz += 0.75;
                if (fabs(g[0] - gx) > 1e-13 || fabs(g[1] - gy) > 1e-13 || fabs(g[2] - gz) > 1e-13)
                    fail_msg("gradient at %zu %zu %zu: %g %g %g want %g %g %g", i, j, k, g[0],
                             g[1], g[2], gx, gy, gz);
            }
    geom_implicit_volume_destroy(v);
    /* a flat volume (one sample along z) */
    v = make_volume(3, 3, 1, GEOM_IMPLICIT_SCALAR_F32, 1.0, 0.0, linear_fn);
    double p[3] = {0.5, 0.5, 7}, g[3];
    assert_true(fabs(geom_implicit_volume_eval_grad(v, p, g) - linear_fn(0.5, 0.5, 0)) < 1e-6);
    assert_true(g[2] == 0.0);
    geom_implicit_volume_destroy(v);
    /* invalid descriptions */
    geom_implicit_volume_desc bad;
    memset(&bad, 0, sizeof bad);
    bad.dims[0] = bad.dims[1] = bad.dims[2] = 2;
    assert_int_equal(geom_implicit_volume_create(&bad, NULL, &v), GEOM_ERR_INVALID_ARG);
    bad.type = GEOM_IMPLICIT_SCALAR_F32;
    bad.spacing[1] = -1;
    assert_int_equal(geom_implicit_volume_create(&bad, NULL, &v), GEOM_ERR_INVALID_ARG);
    bad.spacing[1] = 0;
    bad.dims[0] = SIZE_MAX / 2;
    assert_int_equal(geom_implicit_volume_create(&bad, NULL, &v), GEOM_ERR_LIMIT);
    assert_null(v);
    geom_implicit_volume_destroy(NULL);
}

static void test_read_raw(void **state)
{
    (void)state;
    geom_implicit_volume_desc d;
    memset(&d, 0, sizeof d);
    d.dims[0] = 16, d.dims[1] = 12, d.dims[2] = 10;
    d.type = GEOM_IMPLICIT_SCALAR_F32;
    geom_implicit_volume *v;
    geom_diag diag;
    assert_int_equal(geom_implicit_volume_read_raw(data_path("implicit_sphere_16x12x10_f32.raw"),
                                                   &d, NULL, &v, &diag),
                     GEOM_OK);
    for (size_t k = 0; k < 10; k++)
        for (size_t j = 0; j < 12; j++)
            for (size_t i = 0; i < 16; i++) {
                double x = i, y = j, z = k;
                float want = (float)(sqrt((x - 7.5) * (x - 7.5) + (y - 5.5) * (y - 5.5) +
                                          (z - 4.5) * (z - 4.5)) - 4.0);
                assert_true(geom_implicit_volume_at(v, i, j, k) == (double)want);
            }
    /* contour the slice z = 4.5 (between layers): a circle of radius ~
     * sqrt(16 - 0) around (7.5, 5.5), within the sampling error */
    geom_implicit_field f;
    geom_implicit_field_from_volume(v, &f);
    assert_false(f.exact);
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.z = 4.5;
    double bounds[4] = {0, 0, 15, 11};
    geom_implicit_isolines c;
    assert_int_equal(geom_implicit_contour(&f, bounds, 60, 44, &o, &c, NULL), GEOM_OK);
    assert_int_equal(c.n_polylines, 1);
    assert_true(c.closed[0]);
    assert_int_equal(c.report.refined, 0); /* a sampled field is not refined */
    for (size_t q = 0; q < c.n_vertices; q++) {
        double r = hypot(c.xy[2 * q] - 7.5, c.xy[2 * q + 1] - 5.5);
        assert_true(fabs(r - 4.0) < 0.1);
    }
    geom_implicit_isolines_free(&c);
    geom_implicit_volume_destroy(v);

    /* wrong dims: the size check names both sizes, nothing is allocated */
    d.dims[2] = 11;
    assert_int_equal(geom_implicit_volume_read_raw(data_path("implicit_sphere_16x12x10_f32.raw"),
                                                   &d, NULL, &v, &diag),
                     GEOM_ERR_PARSE);
    assert_null(v);
    assert_non_null(strstr(diag.message, "7680 bytes"));
    assert_non_null(strstr(diag.message, "8448"));
    d.dims[2] = 10;
    d.type = GEOM_IMPLICIT_SCALAR_F64;
    assert_int_equal(geom_implicit_volume_read_raw(data_path("implicit_sphere_16x12x10_f32.raw"),
                                                   &d, NULL, &v, &diag),
                     GEOM_ERR_PARSE);
    assert_int_equal(geom_implicit_volume_read_raw(data_path("no-such-file.raw"), &d, NULL, &v,
                                                   &diag),
                     GEOM_ERR_IO);
    d.type = 0;
    assert_int_equal(geom_implicit_volume_read_raw(data_path("implicit_sphere_16x12x10_f32.raw"),
                                                   &d, NULL, &v, &diag),
                     GEOM_ERR_INVALID_ARG);

    /* big-endian doubles written here */
    const char *tmp = "test_implicit_volume_be.raw";
    FILE *fp = fopen(tmp, "wb");
    assert_non_null(fp);
    for (int q = 0; q < 8; q++) {
        double val = q * 0.5 - 1.0;
        unsigned char b[8];
        memcpy(b, &val, 8);
        unsigned char r[8];
        for (int s = 0; s < 8; s++)
            r[s] = b[7 - s]; /* the test machine is little-endian (x86) */
        fwrite(r, 1, 8, fp);
    }
    fclose(fp);
    memset(&d, 0, sizeof d);
    d.dims[0] = d.dims[1] = d.dims[2] = 2;
    d.type = GEOM_IMPLICIT_SCALAR_F64;
    d.big_endian = 1;
    d.spacing[0] = 2;
    d.origin[1] = 5;
    assert_int_equal(geom_implicit_volume_read_raw(tmp, &d, NULL, &v, &diag), GEOM_OK);
    for (int q = 0; q < 8; q++)
        assert_true(geom_implicit_volume_at(v, q & 1, (q >> 1) & 1, q >> 2) == q * 0.5 - 1.0);
    double p[3] = {1.0, 5.5, 0.5};
    assert_true(geom_implicit_volume_eval(v, p) == 0.75); /* mean of the 8 samples */
    geom_implicit_volume_destroy(v);

    /* raw samples that happen to start with the gzip magic (1f 8b) are
     * samples, not a compressed file, when no decompressor is given; the
     * deprecated reader and geom_implicit_volume_read agree */
    fp = fopen(tmp, "wb");
    assert_non_null(fp);
    unsigned char bytes[16] = {0x1f, 0x8b, 0x08, 0x00, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    fwrite(bytes, 1, sizeof bytes, fp);
    fclose(fp);
    memset(&d, 0, sizeof d);
    d.dims[0] = 4, d.dims[1] = d.dims[2] = 1;
    d.type = GEOM_IMPLICIT_SCALAR_F32;
    assert_int_equal(geom_implicit_volume_read_raw(tmp, &d, NULL, &v, &diag), GEOM_OK);
    geom_implicit_volume_read_options ro;
    memset(&ro, 0, sizeof ro);
    ro.format = GEOM_IMPLICIT_VOLUME_RAW;
    ro.dims[0] = 4, ro.dims[1] = ro.dims[2] = 1;
    ro.sample = GEOM_IMPLICIT_SAMPLE_F32;
    geom_implicit_volume *v2;
    assert_int_equal(geom_implicit_volume_read(tmp, &ro, NULL, &v2, NULL, &diag), GEOM_OK);
    float want[4];
    memcpy(want, bytes, sizeof want);
    for (int q = 0; q < 4; q++) {
        double a = geom_implicit_volume_at(v, (size_t)q, 0, 0);
        double b = geom_implicit_volume_at(v2, (size_t)q, 0, 0);
        assert_memory_equal(&a, &b, sizeof a); /* NaN-safe: the same bits */
        double w = (double)want[q];
        assert_memory_equal(&a, &w, sizeof a);
    }
    geom_implicit_volume_destroy(v);
    geom_implicit_volume_destroy(v2);
    remove(tmp);
}

static void test_read_nrrd_files(void **state)
{
    (void)state;
    geom_implicit_volume *v;
    geom_diag diag;
    assert_int_equal(geom_implicit_volume_read_nrrd(data_path("implicit_torus.nrrd"), NULL, &v,
                                                    &diag),
                     GEOM_OK);
    geom_implicit_volume_desc d;
    geom_implicit_volume_get_desc(v, &d);
    assert_int_equal(d.type, GEOM_IMPLICIT_SCALAR_F64);
    assert_true(d.dims[0] == 20 && d.dims[1] == 18 && d.dims[2] == 8);
    assert_true(d.spacing[0] == 0.25 && d.spacing[1] == 0.25 && d.spacing[2] == 0.5);
    assert_true(d.origin[0] == -2.5 && d.origin[1] == -2.25 && d.origin[2] == -1.75);
    for (size_t k = 0; k < 8; k++)
        for (size_t j = 0; j < 18; j++)
            for (size_t i = 0; i < 20; i++) {
                double x = -2.5 + i * 0.25, y = -2.25 + j * 0.25, z = -1.75 + k * 0.5;
                double q = sqrt(x * x + y * y) - 1.5;
                assert_true(geom_implicit_volume_at(v, i, j, k) == sqrt(q * q + z * z) - 0.5);
            }
    /* the cross-section at z = -0.25 (a node layer): an annulus of radii
     * 1.5 +- sqrt(0.25 - 0.0625) */
    geom_implicit_field f;
    geom_implicit_field_from_volume(v, &f);
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.z = -0.25;
    double bounds[4] = {-2.5, -2.25, 2.25, 2.0};
    geom_implicit_isolines c;
    assert_int_equal(geom_implicit_contour(&f, bounds, 76, 68, &o, &c, NULL), GEOM_OK);
    assert_int_equal(c.n_polylines, 2);
    double w = sqrt(0.25 - 0.0625);
    for (size_t q = 0; q < c.n_vertices; q++) {
        double r = hypot(c.xy[2 * q], c.xy[2 * q + 1]);
        assert_true(fmin(fabs(r - 1.5 - w), fabs(r - 1.5 + w)) < 0.06);
    }
    geom_implicit_isolines_free(&c);
    geom_implicit_volume_destroy(v);

    /* detached header, big-endian floats after a 4-byte skip */
    assert_int_equal(geom_implicit_volume_read_nrrd(data_path("implicit_ramp.nhdr"), NULL, &v,
                                                    &diag),
                     GEOM_OK);
    geom_implicit_volume_get_desc(v, &d);
    assert_int_equal(d.type, GEOM_IMPLICIT_SCALAR_F32);
    assert_true(d.dims[0] == 5 && d.dims[1] == 4 && d.dims[2] == 3);
    assert_true(d.spacing[0] == 1 && d.spacing[1] == 2 && d.spacing[2] == 3);
    assert_true(d.origin[0] == 1 && d.origin[1] == 2 && d.origin[2] == 3);
    for (size_t k = 0; k < 3; k++)
        for (size_t j = 0; j < 4; j++)
            for (size_t i = 0; i < 5; i++)
                assert_true(geom_implicit_volume_at(v, i, j, k) == (double)(i + 10 * j + 100 * k));
    geom_implicit_volume_destroy(v);
    assert_int_equal(geom_implicit_volume_read_nrrd(data_path("no-such.nrrd"), NULL, &v, &diag),
                     GEOM_ERR_IO);
}

/* Read a NRRD from a text header plus n raw bytes. */
static geom_status nrrd_mem(const char *header, const void *data, size_t n,
                            geom_implicit_volume **v, geom_diag *diag)
{
    size_t hl = strlen(header);
    unsigned char *buf = malloc(hl + n + 1);
    memcpy(buf, header, hl);
    if (n)
        memcpy(buf + hl, data, n);
    geom_status st = geom_implicit_volume_read_nrrd_memory(buf, hl + n, "mem.nrrd", NULL, v, diag);
    free(buf);
    return st;
}

static void test_nrrd_memory(void **state)
{
    (void)state;
    geom_implicit_volume *v;
    geom_diag d;
    float f8[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    /* minimal attached raw, CRLF line ends, comments and key/value pairs */
    const char *h = "NRRD0001\r\n# a comment\r\ntype: float\r\ndimension: 3\r\nsizes: 2 2 2\r\n"
                    "endian: little\r\nencoding: raw\r\nsome key:=some: value\r\n\r\n";
    assert_int_equal(nrrd_mem(h, f8, sizeof f8, &v, &d), GEOM_OK);
    assert_true(geom_implicit_volume_at(v, 1, 1, 1) == 7.0);
    geom_implicit_volume_destroy(v);
    /* byte skip -1: the data ends the file */
    h = "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n"
        "byte skip: -1\n\n";
    unsigned char pad[40];
    memset(pad, 0xff, 8);
    memcpy(pad + 8, f8, sizeof f8);
    assert_int_equal(nrrd_mem(h, pad, 40, &v, &d), GEOM_OK);
    assert_true(geom_implicit_volume_at(v, 0, 0, 0) == 0.0);
    geom_implicit_volume_destroy(v);
    /* ASCII data, 2-D, line skip */
    h = "NRRD0005\ntype: double\ndimension: 2\nsizes: 3 2\nencoding: ascii\nline skip: 1\n"
        "spacings: 0.5 nan\n\nskipped line\n1 2.5 -3\n4e1\t5 6\n";
    assert_int_equal(nrrd_mem(h, NULL, 0, &v, &d), GEOM_OK);
    geom_implicit_volume_desc desc;
    geom_implicit_volume_get_desc(v, &desc);
    assert_true(desc.dims[0] == 3 && desc.dims[1] == 2 && desc.dims[2] == 1);
    assert_true(desc.spacing[0] == 0.5 && desc.spacing[1] == 1.0);
    assert_true(geom_implicit_volume_at(v, 1, 0, 0) == 2.5);
    assert_true(geom_implicit_volume_at(v, 0, 1, 0) == 40.0);
    geom_implicit_volume_destroy(v);

    /* errors */
    struct {
        const char *header;
        size_t nbytes;
        geom_status st;
        size_t line;
        const char *msg;
    } bad[] = {
        /* geom_implicit_volume_read_nrrd_memory is a wrapper of
         * geom_implicit_volume_read_memory (one NRRD reader): the messages
         * and lines below are that reader's */
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: gzip\n\n",
         32, GEOM_ERR_PARSE, 0, "compressed data and no decompressor"},
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n", 32,
         GEOM_ERR_PARSE, 0, "lacks the 'endian' field"},
        {"NRRD0004\ntype: quaternion\ndimension: 1\nsizes: 2\nendian: little\nencoding: raw\n\n",
         0, GEOM_ERR_PARSE, 2, "unsupported NRRD type 'quaternion'"},
        {"NRRD0004\ntype: float\ndimension: 4\nsizes: 2 2 2 2\nendian: little\nencoding: raw\n\n",
         64, GEOM_ERR_PARSE, 0, "only 3-D scalar volumes"},
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2\nendian: little\nencoding: raw\n\n", 0,
         GEOM_ERR_PARSE, 0, "sizes has 2 values but dimension is 3"},
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n\n",
         31, GEOM_ERR_PARSE, 0, "data has 31 bytes but 2x2x2 f32 samples need 32"},
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n"
         "data file: x.raw\n\n", 0, GEOM_ERR_PARSE, 0, "cannot be read from memory"},
        {"NRRD0004\ntype: float\ndimension: 2\nsizes: 2 2\nspace directions: (1,1) (0,1)\n"
         "endian: little\nencoding: raw\n\n", 16, GEOM_ERR_PARSE, 0, "not along world axis"},
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n", 0, GEOM_ERR_PARSE,
         0, "'endian'"},
        {"NRRD0004\ntype: float\nsizes 2 2 2\n\n", 0, GEOM_ERR_PARSE, 3, "expected 'field: value'"},
        {"P5 2 2 255\n", 0, GEOM_ERR_PARSE, 1, "not a NRRD file"},
        {"NRRD0004\ntype: double\ndimension: 1\nsizes: 3\nencoding: text\n\n1 2", 0,
         GEOM_ERR_PARSE, 0, "cannot hold 3 values"},
        {"NRRD0004\ntype: double\ndimension: 1\nsizes: 2\nencoding: text\n\n1 x", 0,
         GEOM_ERR_PARSE, 0, "malformed ASCII value 2"},
        {"NRRD0004\ntype: float\ndimension: 3\nsizes: 99999999999 99999999999 99999999999\n"
         "endian: little\nencoding: raw\n\n", 0, GEOM_ERR_LIMIT, 0, "too large"},
        {"NRRD0004\ntype: float\ndimension: 1\nsizes: 0\nendian: little\nencoding: raw\n\n", 0,
         GEOM_ERR_PARSE, 0, "is zero"},
    };
    unsigned char zeros[64] = {0};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        geom_diag_clear(&d);
        v = (geom_implicit_volume *)1;
        geom_status st = nrrd_mem(bad[k].header, zeros, bad[k].nbytes, &v, &d);
        if (st != bad[k].st || v != NULL || !strstr(d.message, bad[k].msg) ||
            (bad[k].line && d.line != bad[k].line) || strcmp(d.source, "mem.nrrd") != 0)
            fail_msg("case %zu: status %d line %zu '%s' (source '%s')", k, st, d.line, d.message,
                     d.source);
    }
    /* a NUL byte in the header, an over-long line */
    const char nul[] = "NRRD0004\ntype: fl\0at\n\n";
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(nul, sizeof nul - 1, NULL, NULL, &v, &d),
                     GEOM_ERR_PARSE);
    char *longline = malloc(70000);
    memcpy(longline, "NRRD0004\n#", 10);
    memset(longline + 10, 'a', 70000 - 10);
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(longline, 70000, NULL, NULL, &v, &d),
                     GEOM_ERR_PARSE);
    free(longline);
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(NULL, 0, NULL, NULL, &v, &d),
                     GEOM_ERR_PARSE);
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(NULL, 5, NULL, NULL, &v, &d),
                     GEOM_ERR_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trilinear),
        cmocka_unit_test(test_read_raw),
        cmocka_unit_test(test_read_nrrd_files),
        cmocka_unit_test(test_nrrd_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
