/*
 * bench_tessellate: achieved chordal error against run time for the
 * tessellation of Newell's teapot (32 bicubic Bezier patches, data/
 * teapot.bpt) and of the exact NURBS torus and sphere, in the two modes:
 * adaptive at several tolerances and uniform at several grids. For each:
 * the tolerance (or grid), the achieved maximum chordal error the
 * tessellator reports (sampled: the distance between each triangle and the
 * surface at its parameter-space position, 12 points per triangle), an
 * independent check of that error for the sphere and torus (the largest
 * distance from the exact shape at 10 barycentric points per triangle, not
 * the library's points), the triangle count and the time (best of 3 runs,
 * including the error check, which is part of every tessellation).
 *
 * Then evaluation throughput against SISL in the same run (s1421 through the
 * validation shim, one prepared SISL surface): points, and points with
 * first derivatives, at the same 10^6 random parameters, for a bicubic
 * teapot patch and the rational biquadratic torus, with the largest
 * difference between the two and each one's distance from a long double
 * evaluation (the accuracy at equal work).
 *
 * Output: Markdown tables. Usage: bench_tessellate [DATA_DIR] (default: the
 * environment's GEOM_TEST_DATA, else GEOM_BENCH_DATA as compiled in, else
 * ./data).
 *
 * bench_tessellate DATA_DIR --uniform [NTOL]: instead, adaptive against the
 * best uniform grid per span (issue 14): for the sphere, torus and teapot,
 * at tolerances 1e-2, 1e-3, 1e-4
 * (the first NTOL of them), the adaptive triangles and error against the
 * uniform gu x gv grid with the fewest triangles that meets the tolerance
 * (searched: see vs_uniform), their ratio and each one's time.
 */
#define _POSIX_C_SOURCE 199309L

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "geom/surface.h"
#include "tess_shapes.h"
#include "validate/geom_validate_sisl.h"

#ifndef GEOM_BENCH_DATA
#define GEOM_BENCH_DATA "data"
#endif

typedef struct rng {
    uint64_t s;
} rng;

static uint64_t next_u64(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double unif(rng *r)
{
    return (double)(next_u64(r) >> 11) * 0x1p-53;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ------------------------------------------------------------ shapes */

typedef struct shape {
    const char *name;
    const geom_nurbs_surface *s;
    size_t n;
    int kind; /* 0 none, 1 sphere (radius a), 2 torus (R = a, r = b) */
    double a, b;
} shape;

static double exact_error(const geom_mesh *m, const shape *sh)
{
    if (!sh->kind)
        return NAN;
    static const double bary[10][3] = {{1. / 3, 1. / 3, 1. / 3}, {.5, .5, 0}, {.5, 0, .5},
                                       {0, .5, .5},             {.7, .2, .1}, {.1, .7, .2},
                                       {.2, .1, .7},            {.45, .45, .1},
                                       {.1, .45, .45},          {.45, .1, .45}};
    const double *X = geom_mesh_cpositions(m);
    double worst = 0.0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        uint32_t h = geom_mesh_face_he(m, f), v[3];
        for (int k = 0; k < 3; ++k) {
            v[k] = geom_mesh_he_vertex(m, h);
            h = geom_mesh_he_next(m, h);
        }
        for (int b = 0; b < 10; ++b) {
            double p[3];
            for (int x = 0; x < 3; ++x)
                p[x] = bary[b][0] * X[3 * v[0] + x] + bary[b][1] * X[3 * v[1] + x] +
                       bary[b][2] * X[3 * v[2] + x];
            double e = sh->kind == 1 ? fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - sh->a)
                                     : fabs(hypot(hypot(p[0], p[1]) - sh->a, p[2]) - sh->b);
            worst = fmax(worst, e);
        }
    }
    return worst;
}

static void row(const shape *sh, const geom_surface_tess_options *o, const char *param)
{
    double best = INFINITY;
    geom_error_report rep;
    geom_surface_tess_stats st;
    geom_mesh *m = geom_mesh_create(NULL);
    for (int rep_i = 0; rep_i < 3; ++rep_i) {
        double t0 = now_s();
        geom_diag d;
        if (geom_surface_tessellate(sh->s, sh->n, o, m, &rep, &st, &d) != GEOM_OK) {
            printf("| %s | %s | failed: %s | | | | |\n", sh->name, param, d.message);
            geom_mesh_destroy(m);
            return;
        }
        best = fmin(best, now_s() - t0);
    }
    double ex = exact_error(m, sh);
    char exs[32];
    if (isnan(ex))
        snprintf(exs, sizeof exs, "-");
    else
        snprintf(exs, sizeof exs, "%.3g", ex);
    printf("| %s | %s | %s | %.3g | %s | %zu | %.4f | %.0f |\n", sh->name,
           o->mode == GEOM_SURFACE_TESS_UNIFORM ? "uniform" : "adaptive", param, rep.max_error,
           exs, st.triangles, best, (double)st.triangles / best);
    geom_mesh_destroy(m);
}

/* ----------------------------------------------------- long double point */

typedef long double ld;

static size_t ld_basis(int p, size_t n, const double *U, ld u, ld *N)
{
    size_t k = (size_t)p;
    for (size_t i = (size_t)p; i < n; ++i)
        if (U[i] < U[i + 1] && (ld)U[i] <= u)
            k = i;
    ld left[16], right[16];
    N[0] = 1.0L;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - (ld)U[k + 1 - (size_t)j];
        right[j] = (ld)U[k + (size_t)j] - u;
        ld saved = 0.0L;
        for (int r = 0; r < j; ++r) {
            ld t = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * t;
            saved = left[j - r] * t;
        }
        N[j] = saved;
    }
    return k;
}

static void ld_point(const geom_nurbs_surface *s, double u, double v, double *out)
{
    ld Nu[16], Nv[16], A[4] = {0, 0, 0, 0};
    size_t ku = ld_basis(s->degree_u, s->nu, s->knots_u, u, Nu);
    size_t kv = ld_basis(s->degree_v, s->nv, s->knots_v, v, Nv);
    for (int i = 0; i <= s->degree_u; ++i)
        for (int j = 0; j <= s->degree_v; ++j) {
            size_t a = ku - (size_t)s->degree_u + (size_t)i, b = kv - (size_t)s->degree_v + (size_t)j;
            ld w = s->weights ? (ld)s->weights[a * s->nv + b] : 1.0L;
            ld c = Nu[i] * Nv[j] * w;
            for (int x = 0; x < 3; ++x)
                A[x] += c * (ld)s->points[3 * (a * s->nv + b) + (size_t)x];
            A[3] += c;
        }
    for (int x = 0; x < 3; ++x)
        out[x] = (double)(A[x] / A[3]);
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static void throughput(const char *name, const geom_nurbs_surface *s, size_t n)
{
    gv_sisl_surface *ss = gv_sisl_surface_create(s->degree_u, s->degree_v, s->nu, s->nv,
                                                 s->knots_u, s->knots_v, s->points, s->weights);
    if (!ss) {
        printf("| %s | SISL surface could not be made | | | | |\n", name);
        return;
    }
    double dom[4];
    geom_surface_domain(s, dom);
    double *uv = malloc(2 * n * sizeof(double));
    if (!uv) {
        gv_sisl_surface_destroy(ss);
        return;
    }
    rng r = {2024};
    for (size_t i = 0; i < n; ++i) {
        uv[2 * i] = dom[0] + (dom[1] - dom[0]) * unif(&r);
        uv[2 * i + 1] = dom[2] + (dom[3] - dom[2]) * unif(&r);
    }
    for (int d = 0; d <= 1; ++d) {
        double tg = INFINITY, ts = INFINITY;
        size_t stride = d ? 12 : 3;
        double *A = malloc(stride * n * sizeof(double)), *B = malloc(stride * n * sizeof(double));
        if (!A || !B) {
            free(A);
            free(B);
            break;
        }
        for (int rep = 0; rep < 3; ++rep) {
            double t0 = now_s();
            for (size_t i = 0; i < n; ++i) {
                if (d)
                    geom_surface_derivs(s, uv[2 * i], uv[2 * i + 1], 1, 0, A + stride * i);
                else
                    geom_surface_eval(s, uv[2 * i], uv[2 * i + 1], 0, A + stride * i);
            }
            tg = fmin(tg, now_s() - t0);
            t0 = now_s();
            for (size_t i = 0; i < n; ++i) {
                if (d)
                    gv_sisl_surface_eval(ss, uv[2 * i], uv[2 * i + 1], 1, B + stride * i);
                else
                    gv_sisl_surface_point(ss, uv[2 * i], uv[2 * i + 1], B + stride * i);
            }
            ts = fmin(ts, now_s() - t0);
        }
        double diff = 0.0, eg = 0.0, es = 0.0;
        for (size_t i = 0; i < n; ++i) {
            for (size_t k = 0; k < stride; k += 3)
                diff = fmax(diff, dist3(A + stride * i + k, B + stride * i + k));
            if (i % 16 == 0) { /* the point's accuracy against long double */
                double ref[3];
                ld_point(s, uv[2 * i], uv[2 * i + 1], ref);
                eg = fmax(eg, dist3(A + stride * i, ref));
                es = fmax(es, dist3(B + stride * i, ref));
            }
        }
        printf("| %s | %s | %.1f | %.1f | %.2f | %.2g | %.2g / %.2g |\n", name,
               d ? "point + 1st derivatives" : "point", 1e9 * tg / (double)n,
               1e9 * ts / (double)n, ts / tg, diff, eg, es);
        free(A);
        free(B);
    }
    free(uv);
    gv_sisl_surface_destroy(ss);
}

/* ---------------------------------------------- adaptive against uniform */

static size_t uni_run(const shape *sh, int gu, int gv, double *err)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = gu;
    o.grid_v = gv;
    geom_error_report rep;
    geom_surface_tess_stats st;
    geom_mesh *m = geom_mesh_create(NULL);
    if (geom_surface_tessellate(sh->s, sh->n, &o, m, &rep, &st, NULL) != GEOM_OK) {
        geom_mesh_destroy(m);
        *err = INFINITY;
        return SIZE_MAX;
    }
    geom_mesh_destroy(m);
    *err = rep.max_error;
    return st.triangles;
}

/* The uniform gu x gv grid per span with the fewest triangles whose error
 * meets tol: the smallest passing square g x g, then for every gu in
 * [g/2, 2g] the smallest passing gv up to 4g (walked from its neighbour's,
 * assuming the error falls as gv grows). */
static void vs_uniform(const shape *sh, double tol)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    geom_error_report rep;
    geom_surface_tess_stats st;
    geom_mesh *m = geom_mesh_create(NULL);
    double t0 = now_s();
    if (geom_surface_tessellate(sh->s, sh->n, &o, m, &rep, &st, NULL) != GEOM_OK) {
        printf("| %s | %g | failed | | | | |\n", sh->name, tol);
        geom_mesh_destroy(m);
        return;
    }
    double ta = now_s() - t0;
    geom_mesh_destroy(m);
    double e;
    int g = 1;
    while (uni_run(sh, g, g, &e) != SIZE_MAX && !(e <= tol))
        g *= 2;
    int lo = g / 2, hi = g; /* lo fails (or is 0), hi passes */
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        uni_run(sh, mid, mid, &e);
        if (e <= tol)
            hi = mid;
        else
            lo = mid;
    }
    g = hi;
    size_t best = SIZE_MAX;
    int bu = 0, bv = 0;
    double be = 0.0, tu = 0.0;
    int gv = g;
    for (int gu = g; gu >= (g + 1) / 2; --gu) { /* down: gv grows (up to 4g) */
        size_t c;
        while ((c = uni_run(sh, gu, gv, &e)) != SIZE_MAX && !(e <= tol) && gv < 4 * g)
            ++gv;
        if (!(e <= tol))
            break; /* no gv up to 4g passes: smaller gu will not either */
        while (gv > 1) {
            double e2;
            size_t c2 = uni_run(sh, gu, gv - 1, &e2);
            if (!(e2 <= tol))
                break;
            --gv, c = c2, e = e2;
        }
        if (c < best)
            best = c, bu = gu, bv = gv, be = e;
    }
    gv = g;
    for (int gu = g + 1; gu <= 2 * g; ++gu) { /* up: gv falls */
        double e2;
        size_t c = uni_run(sh, gu, gv, &e);
        while (gv > 1) {
            size_t c2 = uni_run(sh, gu, gv - 1, &e2);
            if (!(e2 <= tol))
                break;
            --gv, c = c2, e = e2;
        }
        if (e <= tol && c < best)
            best = c, bu = gu, bv = gv, be = e;
    }
    t0 = now_s();
    uni_run(sh, bu, bv, &e);
    tu = now_s() - t0;
    printf("| %s | %g | %zu (%.4g) | %d x %d: %zu (%.4g) | %.3f | %.3f | %.3f |\n", sh->name, tol,
           st.triangles, rep.max_error, bu, bv, best, be, (double)st.triangles / (double)best, ta,
           tu);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : getenv("GEOM_TEST_DATA");
    if (!dir)
        dir = GEOM_BENCH_DATA;
    geom_diag d;
    geom_surface_set *set = tess_load_teapot(dir, &d);
    if (!set) {
        fprintf(stderr, "bench_tessellate: %s/teapot.bpt: %s\n", dir, d.message);
        return 1;
    }
    double tku[12], tkv[12], TP[243], TW[81], sku[12], skv[8], SP[135], SW[45];
    geom_nurbs_surface torus, sphere;
    geom_surface_torus(NULL, 2.0, 0.5, tku, tkv, TP, TW, &torus);
    geom_surface_sphere(NULL, 1.0, sku, skv, SP, SW, &sphere);
    shape shapes[3] = {{"teapot", geom_surface_set_data(set), 32, 0, 0, 0},
                       {"torus", &torus, 1, 2, 2.0, 0.5},
                       {"sphere", &sphere, 1, 1, 1.0, 0}};
    if (argc > 2 && strcmp(argv[2], "--uniform") == 0) {
        /* adaptive against the best uniform grid per span (issue 14) */
        shape more[3] = {shapes[2], shapes[1], shapes[0]};
        printf("## Adaptive against the best uniform grid per span\n\n| surface | tol | adaptive "
               "(error) | best uniform meeting tol (error) | ratio | adaptive s | uniform s "
               "|\n|---|---|---|---|---|---|---|\n");
        const double ut[3] = {1e-2, 1e-3, 1e-4};
        int nt = argc > 3 ? atoi(argv[3]) : 3;
        for (int k = 0; k < 3; ++k)
            for (int t = 0; t < nt && t < 3; ++t)
                vs_uniform(&more[k], ut[t]);
        geom_surface_set_destroy(set);
        return 0;
    }
    printf("## Tessellation: achieved chordal error against time\n\n");
    printf("Error: the tessellator's own sampled maximum; exact: the largest distance "
           "from the exact sphere/torus at 10 other points per triangle. Time: best of 3, "
           "including the error check.\n\n");
    printf("| shape | mode | tolerance / grid | max error | exact | triangles | seconds | "
           "triangles/s |\n|---|---|---|---|---|---|---|---|\n");
    const double tols[5] = {1e-2, 3e-3, 1e-3, 3e-4, 1e-4};
    const int grids[5] = {2, 4, 8, 16, 32};
    for (int k = 0; k < 3; ++k) {
        geom_surface_tess_options o;
        memset(&o, 0, sizeof o);
        char param[32];
        for (int t = 0; t < 5; ++t) {
            o.tolerance = tols[t];
            snprintf(param, sizeof param, "%g", tols[t]);
            row(&shapes[k], &o, param);
        }
        memset(&o, 0, sizeof o);
        o.mode = GEOM_SURFACE_TESS_UNIFORM;
        for (int g = 0; g < 5; ++g) {
            o.grid_u = o.grid_v = grids[g];
            snprintf(param, sizeof param, "%dx%d per %s", grids[g], grids[g],
                     k == 0 ? "patch" : "span");
            row(&shapes[k], &o, param);
        }
    }
    printf("\n## Evaluation throughput against SISL (s1421), same run, 10^6 random "
           "parameters\n\n");
    printf("| surface | what | ns/eval libgeom | ns/eval SISL | SISL/libgeom | max difference | "
           "point error vs long double: libgeom / SISL |\n|---|---|---|---|---|---|---|\n");
    throughput("teapot patch 6 (bicubic)", &geom_surface_set_data(set)[5], 1000000);
    throughput("torus (rational biquadratic)", &torus, 1000000);
    geom_surface_set_destroy(set);
    return 0;
}
