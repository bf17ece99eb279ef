// Exact predicates and barycentric coordinates for libgeom's tests, in exact
// arithmetic: every sum, product and determinant of the double inputs is
// computed exactly in CGAL::Gmpzf (exact big floats, mantissa * 2^exponent,
// through the kernel CGAL::Simple_cartesian<CGAL::Gmpzf>; about 2-3 times
// faster than CGAL::Gmpq here, since it never reduces fractions), and the
// final quotient of two such exact values is formed exactly as a GMP
// rational and rounded once, to nearest. See geom_validate.h for the
// contracts.

#include "geom_validate.h"

#include <CGAL/Gmpzf.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <gmp.h>
#include <mpfr.h>

#include <cfloat>
#include <cmath>
#include <exception>

namespace {

typedef CGAL::Gmpzf RT; // exact for +, -, *
typedef CGAL::Simple_cartesian<RT> K;
typedef K::Point_2 Point_2;
typedef K::Vector_2 Vector_2;
typedef K::Point_3 Point_3;
typedef K::Vector_3 Vector_3;

bool finite(const double *p, int n)
{
    if (p == nullptr)
        return false;
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(p[i]))
            return false;
    return true;
}

Point_2 pt2(const double p[2]) { return Point_2(RT(p[0]), RT(p[1])); }
Point_3 pt3(const double p[3]) { return Point_3(RT(p[0]), RT(p[1]), RT(p[2])); }

// det[q-p; r-p]: twice the signed area of (p, q, r).
RT det2(const Point_2 &p, const Point_2 &q, const Point_2 &r)
{
    const Vector_2 u = q - p, v = r - p;
    return u.x() * v.y() - u.y() * v.x();
}

// det[q-p; r-p; s-p]: six times the signed volume of (p, q, r, s).
RT det3(const Point_3 &p, const Point_3 &q, const Point_3 &r, const Point_3 &s)
{
    return CGAL::cross_product(q - p, r - p) * (s - p);
}

int sign_of(CGAL::Sign s) { return s == CGAL::POSITIVE ? 1 : (s == CGAL::NEGATIVE ? -1 : 0); }

// RAII holders for the GMP/MPFR temporaries.
struct Mpz {
    mpz_t v;
    Mpz() { mpz_init(v); }
    ~Mpz() { mpz_clear(v); }
    Mpz(const Mpz &) = delete;
    Mpz &operator=(const Mpz &) = delete;
};
struct Mpq {
    mpq_t v;
    Mpq() { mpq_init(v); }
    ~Mpq() { mpq_clear(v); }
    Mpq(const Mpq &) = delete;
    Mpq &operator=(const Mpq &) = delete;
};
struct Mpfr {
    mpfr_t v;
    Mpfr() { mpfr_init2(v, 53); }
    ~Mpfr() { mpfr_clear(v); }
    Mpfr(const Mpfr &) = delete;
    Mpfr &operator=(const Mpfr &) = delete;
};

// The rational q rounded to the nearest double, ties to even, with the
// subnormal range rounded once to its own grid (multiples of 2^-1074).
// mpfr_set_q at 53 bits rounds correctly wherever the result is normal (the
// default MPFR exponent range is far wider than double's, so nothing
// overflows or underflows inside MPFR); below DBL_MIN that 53-bit result
// would be rounded a second time by mpfr_get_d, so we round q * 2^1074 to an
// integer exactly instead.
double round_to_double(mpq_srcptr q)
{
    if (mpq_sgn(q) == 0)
        return 0.0;
    Mpfr x;
    mpfr_set_q(x.v, q, MPFR_RNDN);
    const double d = mpfr_get_d(x.v, MPFR_RNDN); // exact: x has 53 bits
    if (std::fabs(d) >= DBL_MIN)
        return d; // includes +-inf past DBL_MAX, which is the correct rounding
    // |q| < 2^-1022 (or rounds to it, where both roundings agree): integer
    // n = round(|q| * 2^1074) < 2^53, and the result is n * 2^-1074.
    Mpq t;
    mpq_abs(t.v, q);
    mpq_mul_2exp(t.v, t.v, 1074);
    Mpz quot, rem, twice;
    mpz_fdiv_qr(quot.v, rem.v, mpq_numref(t.v), mpq_denref(t.v));
    mpz_mul_2exp(twice.v, rem.v, 1);
    const int cmp = mpz_cmp(twice.v, mpq_denref(t.v));
    if (cmp > 0 || (cmp == 0 && mpz_odd_p(quot.v)))
        mpz_add_ui(quot.v, quot.v, 1);
    const double n = mpz_get_d(quot.v); // exact: quot <= 2^52
    const double r = std::ldexp(n, -1074);
    return mpq_sgn(q) < 0 ? -r : r;
}

// num / den (den != 0) as an exact rational, rounded once.
double ratio(const RT &num, const RT &den)
{
    Mpq q;
    mpz_set(mpq_numref(q.v), num.man());
    mpz_set(mpq_denref(q.v), den.man());
    const long e = num.exp() - den.exp(); // value = num.man / den.man * 2^e
    if (e > 0)
        mpz_mul_2exp(mpq_numref(q.v), mpq_numref(q.v), (mp_bitcnt_t)e);
    else if (e < 0)
        mpz_mul_2exp(mpq_denref(q.v), mpq_denref(q.v), (mp_bitcnt_t)-e);
    mpq_canonicalize(q.v); // reduces, and makes the denominator positive
    return round_to_double(q.v);
}

void zero(double *l, int n)
{
    if (l != nullptr)
        for (int i = 0; i < n; ++i)
            l[i] = 0.0;
}

} // namespace

extern "C" int gv_orient2d(const double a[2], const double b[2], const double c[2])
{
    if (!finite(a, 2) || !finite(b, 2) || !finite(c, 2))
        return GV_SIGN_ERROR;
    try {
        return sign_of(CGAL::orientation(pt2(a), pt2(b), pt2(c)));
    } catch (...) {
        return GV_SIGN_ERROR;
    }
}

extern "C" int gv_orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
    if (!finite(a, 3) || !finite(b, 3) || !finite(c, 3) || !finite(d, 3))
        return GV_SIGN_ERROR;
    try {
        // CGAL::orientation(a,b,c,d) is the sign of det[b-a; c-a; d-a],
        // positive when d is above counter-clockwise a, b, c: the opposite of
        // det[a-d; b-d; c-d].
        return -sign_of(CGAL::orientation(pt3(a), pt3(b), pt3(c), pt3(d)));
    } catch (...) {
        return GV_SIGN_ERROR;
    }
}

extern "C" int gv_incircle(const double a[2], const double b[2], const double c[2], const double d[2])
{
    if (!finite(a, 2) || !finite(b, 2) || !finite(c, 2) || !finite(d, 2))
        return GV_SIGN_ERROR;
    try {
        return sign_of(CGAL::side_of_oriented_circle(pt2(a), pt2(b), pt2(c), pt2(d)));
    } catch (...) {
        return GV_SIGN_ERROR;
    }
}

extern "C" int gv_bary_tri2(const double a[2], const double b[2], const double c[2], const double p[2],
                            double l[3])
{
    if (l == nullptr)
        return GV_ERR_INVALID;
    zero(l, 3);
    if (!finite(a, 2) || !finite(b, 2) || !finite(c, 2) || !finite(p, 2))
        return GV_ERR_INVALID;
    try {
        const Point_2 A = pt2(a), B = pt2(b), C = pt2(c), P = pt2(p);
        const RT den = det2(A, B, C);
        if (CGAL::is_zero(den))
            return GV_ERR_DEGENERATE;
        const double r0 = ratio(det2(P, B, C), den);
        const double r1 = ratio(det2(A, P, C), den);
        const double r2 = ratio(det2(A, B, P), den);
        l[0] = r0;
        l[1] = r1;
        l[2] = r2;
        return GV_OK;
    } catch (...) {
        zero(l, 3);
        return GV_ERR_INTERNAL;
    }
}

extern "C" int gv_bary_tri3(const double a[3], const double b[3], const double c[3], const double p[3],
                            double l[3])
{
    if (l == nullptr)
        return GV_ERR_INVALID;
    zero(l, 3);
    if (!finite(a, 3) || !finite(b, 3) || !finite(c, 3) || !finite(p, 3))
        return GV_ERR_INVALID;
    try {
        const Point_3 A = pt3(a), B = pt3(b), C = pt3(c), P = pt3(p);
        const Vector_3 n = CGAL::cross_product(B - A, C - A);
        const RT den = n * n;
        if (CGAL::is_zero(den))
            return GV_ERR_DEGENERATE;
        const Vector_3 n0 = CGAL::cross_product(C - B, P - B);
        const Vector_3 n1 = CGAL::cross_product(A - C, P - C);
        const Vector_3 n2 = CGAL::cross_product(B - A, P - A);
        const double r0 = ratio(n * n0, den);
        const double r1 = ratio(n * n1, den);
        const double r2 = ratio(n * n2, den);
        l[0] = r0;
        l[1] = r1;
        l[2] = r2;
        return GV_OK;
    } catch (...) {
        zero(l, 3);
        return GV_ERR_INTERNAL;
    }
}

extern "C" int gv_bary_tet(const double a[3], const double b[3], const double c[3], const double d[3],
                           const double p[3], double l[4])
{
    if (l == nullptr)
        return GV_ERR_INVALID;
    zero(l, 4);
    if (!finite(a, 3) || !finite(b, 3) || !finite(c, 3) || !finite(d, 3) || !finite(p, 3))
        return GV_ERR_INVALID;
    try {
        const Point_3 A = pt3(a), B = pt3(b), C = pt3(c), D = pt3(d), P = pt3(p);
        const RT den = det3(A, B, C, D);
        if (CGAL::is_zero(den))
            return GV_ERR_DEGENERATE;
        const double r0 = ratio(det3(P, B, C, D), den);
        const double r1 = ratio(det3(A, P, C, D), den);
        const double r2 = ratio(det3(A, B, P, D), den);
        const double r3 = ratio(det3(A, B, C, P), den);
        l[0] = r0;
        l[1] = r1;
        l[2] = r2;
        l[3] = r3;
        return GV_OK;
    } catch (...) {
        zero(l, 4);
        return GV_ERR_INTERNAL;
    }
}

extern "C" int gv_div_rounded(double num, double den, double *out)
{
    if (out == nullptr)
        return GV_ERR_INVALID;
    *out = 0.0;
    if (!std::isfinite(num) || !std::isfinite(den) || den == 0.0)
        return GV_ERR_INVALID;
    try {
        *out = ratio(RT(num), RT(den));
        return GV_OK;
    } catch (...) {
        *out = 0.0;
        return GV_ERR_INTERNAL;
    }
}

extern "C" int gv_ray_triangle(const double o[3], const double d[3], const double a[3], const double b[3],
                               const double c[3])
{
    if (!finite(o, 3) || !finite(d, 3) || !finite(a, 3) || !finite(b, 3) || !finite(c, 3))
        return GV_SIGN_ERROR;
    if (d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0)
        return GV_SIGN_ERROR;
    try {
        const Point_3 pa = pt3(a), pb = pt3(b), pc = pt3(c), po = pt3(o);
        if (CGAL::collinear(pa, pb, pc))
            return GV_SIGN_ERROR;
        const K::Ray_3 ray(po, Vector_3(RT(d[0]), RT(d[1]), RT(d[2])));
        return CGAL::do_intersect(ray, K::Triangle_3(pa, pb, pc)) ? 1 : 0;
    } catch (...) {
        return GV_SIGN_ERROR;
    }
}
