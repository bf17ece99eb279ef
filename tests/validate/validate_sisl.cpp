// SISL part of the validation shim (see geom_validate_sisl.h).
#include "geom_validate_sisl.h"

#include <sisl.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

struct gv_sisl_surface {
    SISLSurf *surf = nullptr;
    int left1 = 0, left2 = 0; // s1421's knot interval hints
    std::vector<double> scratch;
};

namespace {

bool finite_all(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i]))
            return false;
    return true;
}

// Homogeneous (or plain) coefficients in SISL's order for a curve.
std::vector<double> curve_coefs(size_t n, size_t dim, const double *points, const double *weights)
{
    size_t D = dim + (weights ? 1 : 0);
    std::vector<double> c(n * D);
    for (size_t i = 0; i < n; ++i) {
        double w = weights ? weights[i] : 1.0;
        for (size_t d = 0; d < dim; ++d)
            c[i * D + d] = weights ? w * points[i * dim + d] : points[i * dim + d];
        if (weights)
            c[i * D + dim] = w;
    }
    return c;
}

} // namespace

extern "C" int gv_sisl_curve_derivs(int degree, size_t n, size_t dim, const double *knots,
                                    const double *points, const double *weights, double u,
                                    int nderiv, int left, double *ders)
{
    if (!ders || nderiv < 0)
        return GV_SISL_ERR_INVALID;
    std::memset(ders, 0, (size_t)(nderiv + 1) * dim * sizeof(double));
    if (!knots || !points || degree < 1 || dim < 1 || dim > 4 || n < (size_t)degree + 1 ||
        n > 1u << 24 || !std::isfinite(u) || !finite_all(knots, n + degree + 1) ||
        !finite_all(points, n * dim) || (weights && !finite_all(weights, n)))
        return GV_SISL_ERR_INVALID;
    try {
        std::vector<double> coef = curve_coefs(n, dim, points, weights);
        std::vector<double> et(knots, knots + n + degree + 1);
        SISLCurve *c = newCurve((int)n, degree + 1, et.data(), coef.data(), weights ? 2 : 1,
                                (int)dim, 1);
        if (!c)
            return GV_SISL_ERR_INTERNAL;
        int ileft = 0, stat = 0;
        std::vector<double> out((size_t)(nderiv + 1) * dim);
        if (left)
            s1227(c, nderiv, u, &ileft, out.data(), &stat);
        else
            s1221(c, nderiv, u, &ileft, out.data(), &stat);
        freeCurve(c);
        if (stat < 0)
            return GV_SISL_ERR_SISL;
        std::memcpy(ders, out.data(), out.size() * sizeof(double));
        return GV_SISL_OK;
    } catch (...) {
        return GV_SISL_ERR_INTERNAL;
    }
}

extern "C" gv_sisl_surface *gv_sisl_surface_create(int degree_u, int degree_v, size_t nu,
                                                   size_t nv, const double *knots_u,
                                                   const double *knots_v, const double *points,
                                                   const double *weights)
{
    if (!knots_u || !knots_v || !points || degree_u < 1 || degree_v < 1 ||
        nu < (size_t)degree_u + 1 || nv < (size_t)degree_v + 1 || nu > 1u << 16 ||
        nv > 1u << 16 || !finite_all(knots_u, nu + degree_u + 1) ||
        !finite_all(knots_v, nv + degree_v + 1) || !finite_all(points, 3 * nu * nv) ||
        (weights && !finite_all(weights, nu * nv)))
        return nullptr;
    try {
        size_t D = weights ? 4 : 3;
        std::vector<double> coef(nu * nv * D);
        for (size_t i = 0; i < nu; ++i)
            for (size_t j = 0; j < nv; ++j) {
                const double *P = points + 3 * (i * nv + j);
                double w = weights ? weights[i * nv + j] : 1.0;
                double *C = coef.data() + (j * nu + i) * D; // first direction fastest
                for (int d = 0; d < 3; ++d)
                    C[d] = weights ? w * P[d] : P[d];
                if (weights)
                    C[3] = w;
            }
        std::vector<double> et1(knots_u, knots_u + nu + degree_u + 1);
        std::vector<double> et2(knots_v, knots_v + nv + degree_v + 1);
        gv_sisl_surface *s = new gv_sisl_surface;
        s->surf = newSurf((int)nu, (int)nv, degree_u + 1, degree_v + 1, et1.data(), et2.data(),
                          coef.data(), weights ? 2 : 1, 3, 1);
        if (!s->surf) {
            delete s;
            return nullptr;
        }
        return s;
    } catch (...) {
        return nullptr;
    }
}

extern "C" void gv_sisl_surface_destroy(gv_sisl_surface *s)
{
    if (!s)
        return;
    if (s->surf)
        freeSurf(s->surf);
    delete s;
}

extern "C" int gv_sisl_surface_eval(gv_sisl_surface *s, double u, double v, int d, double *ders)
{
    if (!s || !ders || d < 0 || d > 64)
        return GV_SISL_ERR_INVALID;
    size_t d1 = (size_t)d + 1;
    std::memset(ders, 0, 3 * d1 * d1 * sizeof(double));
    if (!std::isfinite(u) || !std::isfinite(v))
        return GV_SISL_ERR_INVALID;
    try {
        size_t tri = d1 * (d1 + 1) / 2;
        if (s->scratch.size() < 3 * tri)
            s->scratch.resize(3 * tri);
        double epar[2] = {u, v}, normal[3];
        int stat = 0;
        s1421(s->surf, d, epar, &s->left1, &s->left2, s->scratch.data(), normal, &stat);
        if (stat < 0)
            return GV_SISL_ERR_SISL;
        // SISL: order m in sequence (m,0), (m-1,1), ..., (0,m)
        size_t idx = 0;
        for (int m = 0; m <= d; ++m)
            for (int l = 0; l <= m; ++l, ++idx) {
                int k = m - l;
                std::memcpy(ders + 3 * ((size_t)k * d1 + (size_t)l), s->scratch.data() + 3 * idx,
                            3 * sizeof(double));
            }
        return GV_SISL_OK;
    } catch (...) {
        return GV_SISL_ERR_INTERNAL;
    }
}

extern "C" int gv_sisl_surface_point(gv_sisl_surface *s, double u, double v, double *p)
{
    if (!s || !p)
        return GV_SISL_ERR_INVALID;
    double epar[2] = {u, v}, normal[3];
    int stat = 0;
    s1421(s->surf, 0, epar, &s->left1, &s->left2, p, normal, &stat);
    return stat < 0 ? GV_SISL_ERR_SISL : GV_SISL_OK;
}

extern "C" int gv_sisl_surface_derivs(int degree_u, int degree_v, size_t nu, size_t nv,
                                      const double *knots_u, const double *knots_v,
                                      const double *points, const double *weights, double u,
                                      double v, int d, double *ders)
{
    gv_sisl_surface *s =
        gv_sisl_surface_create(degree_u, degree_v, nu, nv, knots_u, knots_v, points, weights);
    if (!s) {
        if (ders && d >= 0 && d <= 64)
            std::memset(ders, 0, 3 * (size_t)(d + 1) * (size_t)(d + 1) * sizeof(double));
        return GV_SISL_ERR_INVALID;
    }
    int rc = gv_sisl_surface_eval(s, u, v, d, ders);
    gv_sisl_surface_destroy(s);
    return rc;
}

extern "C" int gv_sisl_line_surface(gv_sisl_surface *s, const double point[3], const double dir[3],
                                    double eps, double *params, size_t cap, size_t *n)
{
    if (!s || !point || !dir || !n || (cap && !params) || !(eps > 0))
        return GV_SISL_ERR_INVALID;
    *n = 0;
    double P[3] = {point[0], point[1], point[2]}, D[3] = {dir[0], dir[1], dir[2]};
    int jpt = 0, jcrv = 0, stat = 0;
    double *gpar = nullptr;
    SISLIntcurve **wcurve = nullptr;
    s1856(s->surf, P, D, 3, 1e-15, eps, &jpt, &gpar, &jcrv, &wcurve, &stat);
    if (stat < 0) {
        std::free(gpar);
        if (wcurve)
            freeIntcrvlist(wcurve, jcrv);
        return GV_SISL_ERR_SISL;
    }
    for (int i = 0; i < jpt && (size_t)i < cap; ++i) {
        params[2 * i] = gpar[2 * i];
        params[2 * i + 1] = gpar[2 * i + 1];
    }
    *n = (size_t)jpt;
    std::free(gpar);
    if (wcurve)
        freeIntcrvlist(wcurve, jcrv);
    return jcrv > 0 ? GV_SISL_ERR_SISL : GV_SISL_OK;
}
