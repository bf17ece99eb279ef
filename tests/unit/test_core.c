/* Core: status strings, diagnostics, allocator, vectors, matrices,
 * transforms, projections, rays and boxes. References are closed forms and
 * geometric properties, never saved outputs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/core.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (tol %g)", got, want, tol);
}

static void assert_vec3_near(geom_vec3 a, geom_vec3 b, double tol)
{
    assert_near(a.x, b.x, tol);
    assert_near(a.y, b.y, tol);
    assert_near(a.z, b.z, tol);
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double urand(void) /* splitmix64 -> [-1, 1) */
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-52 - 1.0;
}

static void test_status_strings(void **state)
{
    (void)state;
    geom_status all[] = {GEOM_OK, GEOM_ERR_NOMEM, GEOM_ERR_INVALID_ARG, GEOM_ERR_PARSE,
                         GEOM_ERR_IO, GEOM_ERR_DEGENERATE, GEOM_ERR_NONMANIFOLD,
                         GEOM_ERR_DOMAIN, GEOM_ERR_LIMIT};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i) {
        const char *s = geom_status_str(all[i]);
        assert_non_null(s);
        assert_string_not_equal(s, "unknown status");
        for (size_t j = 0; j < i; ++j) /* names are distinct */
            assert_string_not_equal(s, geom_status_str(all[j]));
    }
    assert_string_equal(geom_status_str((geom_status)-1000), "unknown status");
    assert_string_equal(geom_status_str(GEOM_OK), "ok");
    assert_string_equal(geom_version_string(), GEOM_VERSION_STRING);
    assert_int_equal(GEOM_VERSION, GEOM_VERSION_MAJOR * 10000 + GEOM_VERSION_MINOR * 100 +
                                       GEOM_VERSION_PATCH);
}

static void test_diag_format(void **state)
{
    (void)state;
    geom_diag d;
    geom_diag_clear(&d);
    geom_diag_clear(NULL);
    assert_int_equal(d.status, GEOM_OK);
    d.status = GEOM_ERR_PARSE;
    strcpy(d.source, "mesh.obj");
    d.line = 12;
    d.column = 5;
    strcpy(d.message, "expected a number");
    char buf[512];
    size_t n = geom_diag_format(&d, buf, sizeof buf);
    assert_string_equal(buf, "mesh.obj:12:5: expected a number");
    assert_int_equal(n, strlen(buf));
    /* truncation: returns the full length, writes a terminated prefix */
    char small[8];
    assert_int_equal(geom_diag_format(&d, small, sizeof small), n);
    assert_int_equal(strlen(small), 7);
    d.column = 0;
    geom_diag_format(&d, buf, sizeof buf);
    assert_string_equal(buf, "mesh.obj:12: expected a number");
    d.line = 0;
    d.byte_offset = 84;
    geom_diag_format(&d, buf, sizeof buf);
    assert_string_equal(buf, "mesh.obj: byte 84: expected a number");
    d.message[0] = 0;
    d.source[0] = 0;
    geom_diag_format(&d, buf, sizeof buf);
    assert_string_equal(buf, "parse error");
}

static void test_vec_basics(void **state)
{
    (void)state;
    geom_vec3 a = geom_vec3_make(1, 2, 3), b = geom_vec3_make(-4, 5, 0.5);
    assert_near(geom_vec3_dot(a, b), -4 + 10 + 1.5, 0);
    geom_vec3 c = geom_vec3_cross(a, b);
    /* the cross product is orthogonal to both and |a x b|^2 = |a|^2|b|^2 - (a.b)^2 */
    assert_near(geom_vec3_dot(c, a), 0, 1e-13);
    assert_near(geom_vec3_dot(c, b), 0, 1e-13);
    double la = geom_vec3_length(a), lb = geom_vec3_length(b), d = geom_vec3_dot(a, b);
    assert_near(geom_vec3_dot(c, c), la * la * lb * lb - d * d, 1e-12);
    assert_vec3_near(geom_vec3_cross(geom_vec3_make(1, 0, 0), geom_vec3_make(0, 1, 0)),
                     geom_vec3_make(0, 0, 1), 0);
    assert_near(geom_vec3_length(geom_vec3_make(2, 3, 6)), 7, 0);
    assert_vec3_near(geom_vec3_lerp(a, b, 0.5), geom_vec3_make(-1.5, 3.5, 1.75), 0);
    assert_near(geom_vec2_length(geom_vec2_make(3, 4)), 5, 0);
    assert_near(geom_vec2_cross(geom_vec2_make(1, 0), geom_vec2_make(0, 1)), 1, 0);
    geom_vec2 u;
    assert_int_equal(geom_vec2_normalize(geom_vec2_make(0, -7), &u), GEOM_OK);
    assert_near(u.x, 0, 0);
    assert_near(u.y, -1, 0);
    assert_int_equal(geom_vec2_normalize(geom_vec2_make(0, 0), &u), GEOM_ERR_DEGENERATE);
}

static void test_normalize_extremes(void **state)
{
    (void)state;
    geom_vec3 n;
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(3, 0, 4), &n), GEOM_OK);
    assert_vec3_near(n, geom_vec3_make(0.6, 0, 0.8), 1e-16);
    /* huge: naive x*x overflows to inf */
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(3e300, 0, 4e300), &n), GEOM_OK);
    assert_vec3_near(n, geom_vec3_make(0.6, 0, 0.8), 1e-15);
    assert_near(geom_vec3_length(geom_vec3_make(3e300, 0, 4e300)), 5e300, 5e300 * 1e-15);
    /* tiny and subnormal: naive x*x underflows to 0 */
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(3e-320, 4e-320, 0), &n), GEOM_OK);
    assert_near(geom_vec3_length(n), 1, 1e-3); /* subnormal inputs carry few digits */
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(0, 5e-324, 0), &n), GEOM_OK);
    assert_vec3_near(n, geom_vec3_make(0, 1, 0), 0);
    assert_near(geom_vec3_length(geom_vec3_make(3e-200, 4e-200, 0)), 5e-200, 5e-215);
    /* zero and non-finite are reported, output never NaN */
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(0, 0, 0), &n), GEOM_ERR_DEGENERATE);
    assert_vec3_near(n, geom_vec3_make(0, 0, 0), 0);
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(0, -0.0, 0), &n), GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(NAN, 1, 0), &n), GEOM_ERR_INVALID_ARG);
    assert_vec3_near(n, geom_vec3_make(0, 0, 0), 0);
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(INFINITY, 1, 0), &n),
                     GEOM_ERR_INVALID_ARG);
    assert_true(isinf(geom_vec3_length(geom_vec3_make(-INFINITY, 0, 0))));
    assert_true(isnan(geom_vec3_length(geom_vec3_make(NAN, 0, 0))));
    /* random unit lengths */
    for (int i = 0; i < 1000; ++i) {
        geom_vec3 v = geom_vec3_make(urand(), urand(), urand());
        if (geom_vec3_normalize(v, &n) == GEOM_OK)
            assert_near(geom_vec3_length(n), 1, 4 * DBL_EPSILON);
    }
}

static void test_reflect_refract(void **state)
{
    (void)state;
    geom_vec3 nrm = geom_vec3_make(0, 1, 0), i, t;
    assert_int_equal(geom_vec3_normalize(geom_vec3_make(1, -1, 0), &i), GEOM_OK);
    assert_vec3_near(geom_vec3_reflect(i, nrm), geom_vec3_make(i.x, -i.y, 0), 1e-16);
    /* Snell: n1 sin(theta1) = n2 sin(theta2), for many angles and ratios */
    for (int k = 1; k < 90; k += 7) {
        for (double eta = 0.4; eta < 2.6; eta += 0.3) {
            double th = k * PI / 180.0;
            i = geom_vec3_make(sin(th), -cos(th), 0);
            geom_status s = geom_vec3_refract(i, nrm, eta, &t);
            double sin_t = eta * sin(th);
            if (sin_t > 1.0 + 1e-12) {
                assert_int_equal(s, GEOM_ERR_DOMAIN); /* total internal reflection */
                assert_vec3_near(t, geom_vec3_reflect(i, nrm), 1e-15);
            } else if (sin_t < 1.0 - 1e-12) {
                assert_int_equal(s, GEOM_OK);
                assert_near(geom_vec3_length(t), 1, 1e-14);
                assert_near(t.x, sin_t, 1e-14);            /* sin of the refracted angle */
                assert_true(t.y < 0);                      /* transmitted, not reflected */
                assert_near(t.z, 0, 0);                    /* stays in the plane of incidence */
            }
        }
    }
    /* normal incidence passes straight through; just beyond the critical angle reflects */
    assert_int_equal(geom_vec3_refract(geom_vec3_make(0, -1, 0), nrm, 1.5, &t), GEOM_OK);
    assert_vec3_near(t, geom_vec3_make(0, -1, 0), 1e-16);
    double crit = asin(1 / 1.5);
    i = geom_vec3_make(sin(crit + 1e-9), -cos(crit + 1e-9), 0);
    assert_int_equal(geom_vec3_refract(i, nrm, 1.5, &t), GEOM_ERR_DOMAIN);
    i = geom_vec3_make(sin(crit - 1e-9), -cos(crit - 1e-9), 0);
    assert_int_equal(geom_vec3_refract(i, nrm, 1.5, &t), GEOM_OK);
    assert_int_equal(geom_vec3_refract(i, nrm, 0.0, &t), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_vec3_refract(i, nrm, NAN, &t), GEOM_ERR_INVALID_ARG);
}

static geom_mat4 random_mat4(void)
{
    geom_mat4 m;
    for (int i = 0; i < 16; ++i)
        m.m[i] = urand();
    return m;
}

static void assert_identity4(geom_mat4 m, double tol)
{
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            assert_near(m.m[4 * c + r], r == c ? 1.0 : 0.0, tol);
}

static void test_mat_inverse(void **state)
{
    (void)state;
    for (int k = 0; k < 500; ++k) {
        geom_mat4 a = random_mat4(), inv;
        geom_status s = geom_mat4_inverse(a, &inv);
        assert_int_equal(s, GEOM_OK);
        double det = geom_mat4_determinant(a);
        /* det(A^-1) = 1/det(A) */
        assert_near(geom_mat4_determinant(inv) * det, 1.0, 1e-8);
        assert_identity4(geom_mat4_mul(a, inv), 1e-9);
        assert_identity4(geom_mat4_mul(inv, a), 1e-9);
        geom_mat3 a3 = geom_mat4_upper3(a), i3;
        if (geom_mat3_inverse(a3, &i3) == GEOM_OK) {
            geom_mat3 p = geom_mat3_mul(a3, i3);
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    assert_near(p.m[3 * c + r], r == c, 1e-9);
        }
    }
    /* scale invariance: a well-conditioned matrix at 1e-200 or 1e200 is invertible */
    geom_mat4 s = geom_mat4_scale(geom_vec3_make(1e-200, 2e-200, 3e-200)), inv;
    s.m[15] = 1e-200;
    assert_int_equal(geom_mat4_inverse(s, &inv), GEOM_OK);
    assert_near(inv.m[0], 1e200, 1e185);
    geom_mat3 big = {{1e200, 0, 0, 0, 2e200, 0, 0, 0, 1e200}}, ib;
    assert_int_equal(geom_mat3_inverse(big, &ib), GEOM_OK);
    assert_near(ib.m[4], 0.5e-200, 1e-215);
    /* singular: a repeated column, a zero row, and rank deficiency after rounding */
    geom_mat4 sing = random_mat4();
    for (int r = 0; r < 4; ++r)
        sing.m[4 * 2 + r] = sing.m[4 * 1 + r] * 3.0;
    assert_int_equal(geom_mat4_inverse(sing, &inv), GEOM_ERR_DEGENERATE);
    assert_identity4(inv, 0);
    geom_mat3 z = {{1, 0, 0, 2, 0, 0, 3, 0, 1}}, iz;
    assert_int_equal(geom_mat3_inverse(z, &iz), GEOM_ERR_DEGENERATE);
    geom_mat3 nearly = {{1, 2, 3, 4, 5, 6, 7, 8, 9.000000000000002}};
    assert_int_equal(geom_mat3_inverse(nearly, &iz), GEOM_ERR_DEGENERATE);
    geom_mat4 nan = geom_mat4_identity();
    nan.m[5] = NAN;
    assert_int_equal(geom_mat4_inverse(nan, &inv), GEOM_ERR_INVALID_ARG);
    /* determinant closed form */
    geom_mat3 m3 = {{2, 0, 0, 1, 3, 0, 4, 5, 6}};
    assert_near(geom_mat3_determinant(m3), 36, 0);
    geom_mat4 m4 = geom_mat4_scale(geom_vec3_make(2, 3, 4));
    assert_near(geom_mat4_determinant(m4), 24, 0);
    /* transpose is an involution */
    geom_mat4 a = random_mat4(), tt = geom_mat4_transpose(geom_mat4_transpose(a));
    assert_memory_equal(a.m, tt.m, sizeof a.m);
    assert_near(geom_mat4_transpose(a).m[1], a.m[4], 0);
}

/* Rodrigues' formula applied to a vector directly. */
static geom_vec3 rodrigues(geom_vec3 k, double th, geom_vec3 v)
{
    geom_vec3 r = geom_vec3_scale(v, cos(th));
    r = geom_vec3_add(r, geom_vec3_scale(geom_vec3_cross(k, v), sin(th)));
    return geom_vec3_add(r, geom_vec3_scale(k, geom_vec3_dot(k, v) * (1 - cos(th))));
}

static void test_transforms(void **state)
{
    (void)state;
    geom_mat4 r, t, m;
    geom_vec3 p;
    assert_int_equal(geom_mat4_rotate(geom_vec3_make(0, 0, 5), PI / 2, &r), GEOM_OK);
    assert_vec3_near(geom_mat4_transform_dir(r, geom_vec3_make(1, 0, 0)),
                     geom_vec3_make(0, 1, 0), 1e-16);
    for (int k = 0; k < 200; ++k) {
        geom_vec3 axis = geom_vec3_make(urand(), urand(), urand()), u;
        double th = 4 * urand();
        if (geom_vec3_normalize(axis, &u) != GEOM_OK)
            continue;
        assert_int_equal(geom_mat4_rotate(axis, th, &r), GEOM_OK);
        geom_vec3 v = geom_vec3_make(urand(), urand(), urand());
        assert_vec3_near(geom_mat4_transform_dir(r, v), rodrigues(u, th, v), 1e-14);
        assert_near(geom_mat4_determinant(r), 1, 1e-14);
        /* orthogonal: R^T R = I */
        assert_identity4(geom_mat4_mul(geom_mat4_transpose(r), r), 1e-14);
    }
    assert_int_equal(geom_mat4_rotate(geom_vec3_make(0, 0, 0), 1, &r), GEOM_ERR_DEGENERATE);
    assert_identity4(r, 0);
    /* compose: translate after scale */
    t = geom_mat4_translate(geom_vec3_make(1, 2, 3));
    m = geom_mat4_mul(t, geom_mat4_scale(geom_vec3_make(2, 2, 2)));
    assert_int_equal(geom_mat4_transform_point(m, geom_vec3_make(1, 1, 1), &p), GEOM_OK);
    assert_vec3_near(p, geom_vec3_make(3, 4, 5), 0);
    assert_vec3_near(geom_mat4_transform_dir(t, geom_vec3_make(1, 1, 1)),
                     geom_vec3_make(1, 1, 1), 0);
    /* normal matrix: under a non-uniform scale, a transformed normal stays
     * perpendicular to the transformed tangent plane */
    geom_mat4 sh = geom_mat4_mul(geom_mat4_scale(geom_vec3_make(1, 5, 0.2)), random_mat4());
    geom_mat3 nm;
    assert_int_equal(geom_mat4_normal_matrix(sh, &nm), GEOM_OK);
    geom_vec3 nrm = geom_vec3_make(0.3, -0.5, 0.8);
    geom_vec3 tan1 = geom_vec3_cross(nrm, geom_vec3_make(1, 0, 0));
    geom_vec3 tan2 = geom_vec3_cross(nrm, tan1);
    geom_vec3 n2 = geom_mat3_mul_vec3(nm, nrm);
    assert_near(geom_vec3_dot(n2, geom_mat4_transform_dir(sh, tan1)), 0, 1e-12);
    assert_near(geom_vec3_dot(n2, geom_mat4_transform_dir(sh, tan2)), 0, 1e-12);
    geom_mat4 flat = geom_mat4_scale(geom_vec3_make(1, 0, 1));
    assert_int_equal(geom_mat4_normal_matrix(flat, &nm), GEOM_ERR_DEGENERATE);
}

static void test_lookat_projection(void **state)
{
    (void)state;
    geom_vec3 eye = geom_vec3_make(3, 4, 5), center = geom_vec3_make(-1, 2, 0.5);
    geom_vec3 up = geom_vec3_make(0, 1, 0), p;
    geom_mat4 v, proj;
    assert_int_equal(geom_mat4_lookat(eye, center, up, &v), GEOM_OK);
    /* the eye goes to the origin, the centre onto the -z axis at its distance */
    assert_int_equal(geom_mat4_transform_point(v, eye, &p), GEOM_OK);
    assert_vec3_near(p, geom_vec3_make(0, 0, 0), 1e-14);
    assert_int_equal(geom_mat4_transform_point(v, center, &p), GEOM_OK);
    double dist = geom_vec3_length(geom_vec3_sub(center, eye));
    assert_vec3_near(p, geom_vec3_make(0, 0, -dist), 1e-14);
    /* world up maps into the y/z plane with positive y (up stays up on screen) */
    geom_vec3 u = geom_mat4_transform_dir(v, up);
    assert_near(u.x, 0, 1e-15);
    assert_true(u.y > 0);
    assert_int_equal(geom_mat4_lookat(eye, eye, up, &v), GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_mat4_lookat(eye, geom_vec3_add(eye, up), up, &v), GEOM_ERR_DEGENERATE);

    /* perspective: near plane -> depth -1, far plane -> +1, the top of the
     * frustum -> y = 1, the right edge -> x = 1 */
    double fovy = 1.1, aspect = 1.6, n = 0.25, f = 40;
    assert_int_equal(geom_mat4_perspective(fovy, aspect, n, f, &proj), GEOM_OK);
    assert_int_equal(geom_mat4_transform_point(proj, geom_vec3_make(0, 0, -n), &p), GEOM_OK);
    assert_near(p.z, -1, 1e-15);
    assert_int_equal(geom_mat4_transform_point(proj, geom_vec3_make(0, 0, -f), &p), GEOM_OK);
    assert_near(p.z, 1, 1e-14);
    double zz = -7.0, top = 7.0 * tan(fovy / 2);
    assert_int_equal(geom_mat4_transform_point(proj, geom_vec3_make(top * aspect, top, zz), &p),
                     GEOM_OK);
    assert_near(p.x, 1, 1e-14);
    assert_near(p.y, 1, 1e-14);
    geom_vec4 clip = geom_mat4_mul_vec4(proj, geom_vec4_make(1, 2, zz, 1));
    assert_near(clip.w, -zz, 0); /* clip w is the eye-space distance */
    assert_int_equal(geom_mat4_transform_point(proj, geom_vec3_make(1, 1, 0), &p),
                     GEOM_ERR_DEGENERATE); /* w = 0 at the eye plane */
    assert_int_equal(geom_mat4_perspective(0, 1, 1, 2, &proj), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_mat4_perspective(1, 1, 0, 2, &proj), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_mat4_perspective(1, 1, 2, 2, &proj), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_mat4_perspective(1, NAN, 1, 2, &proj), GEOM_ERR_DOMAIN);

    /* orthographic: the box corners map to the cube corners */
    assert_int_equal(geom_mat4_ortho(-2, 6, -1, 3, 0.5, 10, &proj), GEOM_OK);
    assert_int_equal(geom_mat4_transform_point(proj, geom_vec3_make(-2, -1, -0.5), &p), GEOM_OK);
    assert_vec3_near(p, geom_vec3_make(-1, -1, -1), 1e-15);
    assert_int_equal(geom_mat4_transform_point(proj, geom_vec3_make(6, 3, -10), &p), GEOM_OK);
    assert_vec3_near(p, geom_vec3_make(1, 1, 1), 1e-15);
    assert_int_equal(geom_mat4_ortho(1, 1, 0, 1, 0, 1, &proj), GEOM_ERR_DOMAIN);

    geom_vec3 h;
    assert_int_equal(geom_vec4_homogeneous_divide(geom_vec4_make(2, 4, 6, 2), &h), GEOM_OK);
    assert_vec3_near(h, geom_vec3_make(1, 2, 3), 0);
    assert_int_equal(geom_vec4_homogeneous_divide(geom_vec4_make(2, 4, 6, 0), &h),
                     GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_vec4_homogeneous_divide(geom_vec4_make(2, 4, 6, NAN), &h),
                     GEOM_ERR_INVALID_ARG);
}

static geom_ray ray(double ox, double oy, double oz, double dx, double dy, double dz)
{
    geom_ray r = {geom_vec3_make(ox, oy, oz), geom_vec3_make(dx, dy, dz), 0.0, INFINITY};
    return r;
}

static void test_aabb_slab(void **state)
{
    (void)state;
    geom_aabb b = geom_aabb_empty();
    assert_true(geom_aabb_is_empty(b));
    b = geom_aabb_extend(b, geom_vec3_make(0, 0, 0));
    b = geom_aabb_extend(b, geom_vec3_make(1, 2, 3));
    assert_false(geom_aabb_is_empty(b));
    assert_true(geom_aabb_contains(b, geom_vec3_make(1, 2, 3)));
    assert_false(geom_aabb_contains(b, geom_vec3_make(1, 2, 3.0000001)));
    geom_aabb u = geom_aabb_union(b, geom_aabb_empty());
    assert_memory_equal(&u, &b, sizeof b);
    double t0, t1;
    geom_ray r = ray(-1, 0.5, 0.5, 1, 0, 0);
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    assert_near(t0, 1, 1e-15);
    assert_near(t1, 2, 4e-15); /* widened by 2*gamma(3) */
    /* origin inside: interval starts at tmin */
    r = ray(0.5, 1, 1, 0, 0, -1);
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    assert_near(t0, 0, 0);
    assert_near(t1, 1, 2e-15);
    /* box behind the ray, and a ray whose tmax ends before the box */
    r = ray(-1, 0.5, 0.5, -1, 0, 0);
    assert_false(geom_ray_aabb(&r, b, &t0, &t1));
    r = ray(-1, 0.5, 0.5, 1, 0, 0);
    r.tmax = 0.5;
    assert_false(geom_ray_aabb(&r, b, NULL, NULL));
    /* parallel to a slab: inside iff the origin is within it, including on the face */
    r = ray(-1, 0, 0.5, 1, 0, 0); /* grazing along the y = 0 face */
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    r = ray(-1, -1e-300, 0.5, 1, 0, 0);
    assert_false(geom_ray_aabb(&r, b, &t0, &t1));
    r = ray(-1, 0, 0.5, 1, -0.0, 0);
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    /* through an edge and exactly through a corner */
    r = ray(-1, -1, 0.5, 1, 1, 0);
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    r = ray(-1, -2, -3, 1, 2, 3);
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    assert_near(t0, 1, 1e-15);
    /* origin on a slab plane with a subnormal direction: no 0*inf NaN */
    r = ray(0, 0.5, 0.5, 5e-324, 0, 0);
    assert_true(geom_ray_aabb(&r, b, &t0, &t1));
    /* NaN anywhere is a miss, never a spurious hit */
    r = ray(NAN, 0.5, 0.5, 1, 0, 0);
    assert_false(geom_ray_aabb(&r, b, &t0, &t1));
    r = ray(-1, 0.5, 0.5, NAN, 0, 0);
    assert_false(geom_ray_aabb(&r, b, &t0, &t1));
    geom_aabb bn = b;
    bn.max.y = NAN;
    r = ray(-1, 0.5, 0.5, 1, 0, 0);
    assert_false(geom_ray_aabb(&r, bn, &t0, &t1));
    assert_false(geom_ray_aabb(&r, geom_aabb_empty(), &t0, &t1));
    assert_false(geom_ray_aabb(NULL, b, &t0, &t1));
    /* random rays aimed at a random interior point always hit */
    for (int k = 0; k < 10000; ++k) {
        geom_vec3 target = geom_vec3_make(0.5 + 0.5 * urand(), 1 + urand(), 1.5 + 1.5 * urand());
        geom_vec3 o = geom_vec3_make(10 * urand(), 10 * urand(), 10 * urand());
        geom_ray rr = {o, geom_vec3_sub(target, o), 0, INFINITY};
        assert_true(geom_ray_aabb(&rr, b, &t0, &t1));
        assert_true(t0 <= 1.0 && 1.0 <= t1);
    }
}

static size_t alloc_count, free_count;
static void *my_alloc(void *user, size_t size)
{
    (void)user;
    ++alloc_count;
    return test_malloc(size);
}
static void my_free(void *user, void *p, size_t size)
{
    (void)user;
    (void)size;
    ++free_count;
    test_free(p);
}

static void test_allocator_struct(void **state)
{
    (void)state;
    /* a zero-initialised allocator is valid (means libc); the struct fields exist as documented */
    geom_allocator zero = {0};
    assert_null(zero.alloc_fn);
    geom_allocator a = {my_alloc, NULL, my_free, NULL};
    void *p = a.alloc_fn(a.user, 16);
    a.free_fn(a.user, p, 16);
    assert_int_equal(alloc_count, free_count);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_strings),  cmocka_unit_test(test_diag_format),
        cmocka_unit_test(test_vec_basics),      cmocka_unit_test(test_normalize_extremes),
        cmocka_unit_test(test_reflect_refract), cmocka_unit_test(test_mat_inverse),
        cmocka_unit_test(test_transforms),      cmocka_unit_test(test_lookat_projection),
        cmocka_unit_test(test_aabb_slab),       cmocka_unit_test(test_allocator_struct),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
