/*
 * Direct ray casting of a NURBS surface and of an implicit surface against
 * the tessellate-then-trace path (one thread), on the same rays:
 *  - NURBS: a bicubic B-spline patch (10 x 10 control points, a wavy height
 *    field over [0,4]^2) traced directly (geom_ray_scene_add_surface:
 *    Bezier subdivision plus Newton) and through geom_surface_tessellate at
 *    chordal tolerances 1e-2 .. 1e-6, each mesh traced through the BVH;
 *  - implicit: a bumpy sphere "x^2+y^2+z^2 - 1 - 0.1 sin(5x) sin(5y) sin(5z)"
 *    traced directly (interval arithmetic) and through marching cubes
 *    (geom_iso_extract with vertices refined onto f = 0) at 32^3 .. 256^3.
 * For every path: the preparation seconds (tessellation + BVH build), rays
 * per second (thread CPU time, best of three), and the t error against the
 * direct answer (max |t - t_direct| / t over rays both hit, and hit/miss
 * differences); for the direct path, its own largest reported t error bound.
 * "Same accuracy" is the tessellation whose t error reaches the direct
 * path's bound: the table shows how far the sweep gets toward it.
 *
 *   bench_ray_repr [N]     (N x N rays, default 256)
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, CLOCK_THREAD_CPUTIME_ID */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "geom/iso.h"
#include "geom/ray.h"
#include "geom/surface.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct result {
    double *t; /* NaN = miss */
    double seconds, max_err_bound;
} result;

static result trace(const geom_ray_scene *s, const double *rays, size_t n)
{
    result r;
    int rep;
    r.t = malloc(n * sizeof(double));
    r.seconds = INFINITY;
    r.max_err_bound = 0;
    for (rep = 0; rep < 3; rep++) {
        double t0 = cpu_now(), dt;
        size_t i;
        for (i = 0; i < n; i++) {
            geom_ray q;
            geom_ray_hit h;
            int found = 0;
            q.origin = geom_vec3_make(rays[6 * i], rays[6 * i + 1], rays[6 * i + 2]);
            q.dir = geom_vec3_make(rays[6 * i + 3], rays[6 * i + 4], rays[6 * i + 5]);
            q.tmin = 0;
            q.tmax = INFINITY;
            if (geom_ray_scene_closest(s, &q, &h, &found) != GEOM_OK) found = 0;
            r.t[i] = found ? h.t : NAN;
            if (found && h.t_error > r.max_err_bound) r.max_err_bound = h.t_error;
        }
        dt = cpu_now() - t0;
        if (dt < r.seconds) r.seconds = dt;
    }
    return r;
}

static void compare(const result *a, const result *ref, size_t n, double *maxrel, size_t *differ)
{
    size_t i;
    *maxrel = 0;
    *differ = 0;
    for (i = 0; i < n; i++) {
        int ha = !isnan(a->t[i]), hb = !isnan(ref->t[i]);
        if (ha != hb) (*differ)++;
        else if (ha) {
            double e = fabs(a->t[i] - ref->t[i]) / fabs(ref->t[i]);
            if (e > *maxrel) *maxrel = e;
        }
    }
}

static void row(const char *what, double prep, size_t tris, const result *r, size_t n, const result *ref)
{
    double maxrel = 0;
    size_t differ = 0;
    if (ref) compare(r, ref, n, &maxrel, &differ);
    printf("  %-28s prep %8.4f s  %8zu tris  %10.4g rays/s", what, prep, tris, (double)n / r->seconds);
    if (ref)
        printf("  t err %.3g  hit/miss differ %zu\n", maxrel, differ);
    else
        printf("  t error bound (largest, relative) see below\n");
}

static geom_ray_scene *mesh_scene(geom_mesh *m, double *prep, double t0)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_build_options bo;
    memset(&bo, 0, sizeof bo);
    bo.bvh_threads = 1;
    if (geom_ray_scene_add_mesh(s, m, NULL) != GEOM_OK || geom_ray_scene_build(s, &bo, NULL, NULL) != GEOM_OK) {
        fprintf(stderr, "bench_ray_repr: mesh scene failed\n");
        exit(1);
    }
    *prep = cpu_now() - t0;
    return s;
}

static void bench_nurbs(int N)
{
    enum { P = 10 };
    double ku[P + 4], pts[3 * P * P], *rays;
    size_t n = (size_t)N * N, i, j;
    geom_nurbs_surface sf;
    geom_ray_scene *s;
    result ref;
    double t0, prep, relb = 0;
    static const double tols[] = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6};
    for (i = 0; i < P + 4; i++) ku[i] = i < 4 ? 0 : (i >= P ? P - 3 : (double)i - 3);
    for (j = 0; j < P; j++)
        for (i = 0; i < P; i++) {
            double *p = pts + 3 * (j * P + i);
            p[0] = 4.0 * (double)i / (P - 1);
            p[1] = 4.0 * (double)j / (P - 1);
            p[2] = 0.4 * sin(1.7 * p[0]) * cos(1.3 * p[1]) + 0.1 * (double)((i * 7 + j * 3) % 5) / 5;
        }
    sf.degree_u = sf.degree_v = 3;
    sf.nu = sf.nv = P;
    sf.knots_u = sf.knots_v = ku;
    sf.points = pts;
    sf.weights = NULL;
    rays = malloc(n * 6 * sizeof(double));
    for (i = 0; i < n; i++) {
        double sx = ((double)(i % (size_t)N) + 0.5) / N, sy = ((double)(i / (size_t)N) + 0.5) / N;
        double *r = rays + 6 * i;
        r[0] = 0.2 + 3.6 * sx;
        r[1] = 0.2 + 3.6 * sy;
        r[2] = 3;
        r[3] = 0.3;
        r[4] = -0.2;
        r[5] = -1;
    }
    printf("NURBS: bicubic B-spline patch, %d x %d control points; %zu rays\n", P, P, n);
    t0 = cpu_now();
    s = geom_ray_scene_create(NULL);
    if (geom_ray_scene_add_surface(s, &sf, NULL, NULL) != GEOM_OK || geom_ray_scene_build(s, NULL, NULL, NULL) != GEOM_OK) {
        fprintf(stderr, "bench_ray_repr: surface scene failed\n");
        exit(1);
    }
    prep = cpu_now() - t0;
    ref = trace(s, rays, n);
    for (i = 0; i < n; i++)
        if (!isnan(ref.t[i])) {
            double b;
            geom_ray q;
            geom_ray_hit h;
            int found = 0;
            q.origin = geom_vec3_make(rays[6 * i], rays[6 * i + 1], rays[6 * i + 2]);
            q.dir = geom_vec3_make(rays[6 * i + 3], rays[6 * i + 4], rays[6 * i + 5]);
            q.tmin = 0;
            q.tmax = INFINITY;
            geom_ray_scene_closest(s, &q, &h, &found);
            b = found ? h.t_error / h.t : 0;
            if (b > relb) relb = b;
        }
    row("direct (subdivision+Newton)", prep, 0, &ref, n, NULL);
    printf("    direct: largest reported t error bound %.3g (relative %.3g)\n", ref.max_err_bound, relb);
    geom_ray_scene_destroy(s);
    for (j = 0; j < sizeof tols / sizeof tols[0]; j++) {
        geom_surface_tess_options to;
        geom_mesh *m = geom_mesh_create(NULL);
        geom_diag dg;
        geom_status st;
        geom_error_report rep;
        char what[64];
        result r;
        memset(&to, 0, sizeof to);
        to.tolerance = tols[j];
        geom_diag_clear(&dg);
        t0 = cpu_now();
        if ((st = geom_surface_tessellate(&sf, 1, &to, m, &rep, NULL, &dg)) != GEOM_OK) {
            printf("  tessellated tol %.0e        failed: %s (%s)\n", tols[j], geom_status_str(st), dg.message);
            geom_mesh_destroy(m);
            continue;
        }
        s = mesh_scene(m, &prep, t0);
        r = trace(s, rays, n);
        snprintf(what, sizeof what, "tessellated tol %.0e", tols[j]);
        row(what, prep, geom_mesh_n_faces(m), &r, n, &ref);
        free(r.t);
        geom_ray_scene_destroy(s);
        geom_mesh_destroy(m);
    }
    free(ref.t);
    free(rays);
}

static void bench_implicit(int N)
{
    static const char *expr = "x^2 + y^2 + z^2 - 1 - 0.1*sin(5*x)*sin(5*y)*sin(5*z)";
    static const double bounds[6] = {-1.3, -1.3, -1.3, 1.3, 1.3, 1.3};
    static const size_t res[] = {32, 64, 128, 256};
    geom_implicit_expr *e = NULL;
    geom_ray_scene *s;
    size_t n = (size_t)N * N, i, j;
    double *rays = malloc(n * 6 * sizeof(double)), t0, prep;
    result ref;
    if (geom_implicit_expr_compile(expr, strlen(expr), NULL, &e, NULL) != GEOM_OK) {
        fprintf(stderr, "bench_ray_repr: expression failed\n");
        exit(1);
    }
    for (i = 0; i < n; i++) {
        double sx = ((double)(i % (size_t)N) + 0.5) / N * 2 - 1, sy = ((double)(i / (size_t)N) + 0.5) / N * 2 - 1;
        double *r = rays + 6 * i;
        r[0] = 0.1;
        r[1] = 0.2;
        r[2] = 4;
        r[3] = 0.32 * sx;
        r[4] = 0.32 * sy;
        r[5] = -1;
    }
    printf("implicit: \"%s\" in [-1.3, 1.3]^3; %zu rays\n", expr, n);
    t0 = cpu_now();
    s = geom_ray_scene_create(NULL);
    if (geom_ray_scene_add_implicit(s, e, bounds, 0, NULL) != GEOM_OK || geom_ray_scene_build(s, NULL, NULL, NULL) != GEOM_OK) {
        fprintf(stderr, "bench_ray_repr: implicit scene failed\n");
        exit(1);
    }
    prep = cpu_now() - t0;
    ref = trace(s, rays, n);
    row("direct (interval)", prep, 0, &ref, n, NULL);
    printf("    direct: largest reported t error bound %.3g\n", ref.max_err_bound);
    geom_ray_scene_destroy(s);
    for (j = 0; j < sizeof res / sizeof res[0]; j++) {
        geom_iso_field f;
        geom_iso_options io;
        geom_iso_surface surf;
        geom_mesh *m = geom_mesh_create(NULL);
        size_t rr[3] = {res[j], res[j], res[j]};
        char what[64];
        result r;
        memset(&io, 0, sizeof io);
        io.refine = 1;
        io.threads = 1;
        t0 = cpu_now();
        if (geom_iso_field_from_expr(e, &f) != GEOM_OK || geom_iso_extract(&f, bounds, rr, &io, &surf, NULL) != GEOM_OK) {
            printf("  marching cubes %zu^3 failed\n", res[j]);
            geom_mesh_destroy(m);
            continue;
        }
        if (geom_iso_surface_to_mesh(&surf, m, NULL) != GEOM_OK) {
            printf("  marching cubes %zu^3: mesh failed\n", res[j]);
            geom_iso_surface_free(&surf);
            geom_mesh_destroy(m);
            continue;
        }
        geom_iso_surface_free(&surf);
        s = mesh_scene(m, &prep, t0);
        r = trace(s, rays, n);
        snprintf(what, sizeof what, "marching cubes %zu^3", res[j]);
        row(what, prep, geom_mesh_n_faces(m), &r, n, &ref);
        free(r.t);
        geom_ray_scene_destroy(s);
        geom_mesh_destroy(m);
    }
    free(ref.t);
    free(rays);
    geom_implicit_expr_destroy(e);
}

int main(int argc, char **argv)
{
    int N = argc > 1 ? atoi(argv[1]) : 256;
    if (N < 1) N = 1;
    bench_nurbs(N);
    bench_implicit(N);
    return 0;
}
