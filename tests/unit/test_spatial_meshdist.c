/*
 * Closest point on a triangle mesh against an independent brute force
 * (projection onto the plane + inside test, else the nearest edge), and
 * against the index with one leaf (no pruning: identical answers, ties
 * included); winding numbers against the solid-angle sum computed here
 * (L'Huilier's theorem, not the library's formula) within the reported
 * bound, 1 inside and 0 outside a closed mesh, open and self-intersecting
 * meshes; signed distances; NaN queries rejected.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/spatial.h"

#define PI 3.14159265358979323846

static uint64_t rng_state = 0x853c49e6748fea9bull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

typedef struct tmesh {
    double *pos;
    uint32_t *tris;
    size_t nv, nt;
} tmesh;

/* UV sphere (closed, outward), radius r, centre c. */
static tmesh sphere(int nu, int nv_, double r, const double c[3])
{
    tmesh m;
    m.nv = (size_t)nu * (size_t)(nv_ - 1) + 2;
    m.nt = 2 * (size_t)nu * (size_t)(nv_ - 1);
    m.pos = malloc(3 * m.nv * sizeof *m.pos);
    m.tris = malloc(3 * m.nt * sizeof *m.tris);
    size_t k = 0;
    m.pos[k++] = c[0], m.pos[k++] = c[1], m.pos[k++] = c[2] + r;
    for (int j = 1; j < nv_; j++)
        for (int i = 0; i < nu; i++) {
            double th = PI * j / nv_, ph = 2 * PI * i / nu;
            m.pos[k++] = c[0] + r * sin(th) * cos(ph);
            m.pos[k++] = c[1] + r * sin(th) * sin(ph);
            m.pos[k++] = c[2] + r * cos(th);
        }
    m.pos[k++] = c[0], m.pos[k++] = c[1], m.pos[k++] = c[2] - r;
    size_t t = 0;
    uint32_t south = (uint32_t)(m.nv - 1);
    for (int i = 0; i < nu; i++) {
        uint32_t a = 1 + (uint32_t)i, b = 1 + (uint32_t)((i + 1) % nu);
        m.tris[t++] = 0, m.tris[t++] = a, m.tris[t++] = b;
    }
    for (int j = 1; j < nv_ - 1; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = 1 + (uint32_t)((j - 1) * nu + i), b = 1 + (uint32_t)((j - 1) * nu + (i + 1) % nu);
            uint32_t c2 = a + (uint32_t)nu, d = b + (uint32_t)nu;
            m.tris[t++] = a, m.tris[t++] = c2, m.tris[t++] = d;
            m.tris[t++] = a, m.tris[t++] = d, m.tris[t++] = b;
        }
    for (int i = 0; i < nu; i++) {
        uint32_t a = 1 + (uint32_t)((nv_ - 2) * nu + i), b = 1 + (uint32_t)((nv_ - 2) * nu + (i + 1) % nu);
        m.tris[t++] = a, m.tris[t++] = south, m.tris[t++] = b;
    }
    m.nt = t / 3;
    return m;
}

static tmesh soup(size_t nt, int kind)
{
    tmesh m;
    m.nt = nt;
    m.nv = 3 * nt;
    m.pos = malloc(3 * m.nv * sizeof *m.pos);
    m.tris = malloc(3 * nt * sizeof *m.tris);
    for (size_t t = 0; t < nt; t++) {
        double c[3];
        for (int k = 0; k < 3; k++)
            c[k] = kind == 1 ? 1e8 + urand() : kind == 2 ? (double)((t >> (2 * k)) & 3) : urand();
        for (int v = 0; v < 3; v++) {
            for (int k = 0; k < 3; k++)
                m.pos[3 * (3 * t + v) + k] =
                    kind == 2 ? c[k] + (v == k ? 0.5 : 0.0) : c[k] + 0.1 * (urand() - 0.5);
            m.tris[3 * t + v] = (uint32_t)(3 * t + v);
        }
    }
    return m;
}

static void free_mesh(tmesh *m)
{
    free(m->pos);
    free(m->tris);
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double seg_d2(const double *p, const double *a, const double *b)
{
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double l = dot(ab, ab), t = l > 0 ? dot(ap, ab) / l : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return dot(d, d);
}

/* Independent point-triangle distance: plane projection if inside, else edges. */
static double tri_d2(const double *p, const double *a, const double *b, const double *c)
{
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double nn = dot(n, n);
    double best = seg_d2(p, a, b), d;
    if ((d = seg_d2(p, b, c)) < best) best = d;
    if ((d = seg_d2(p, c, a)) < best) best = d;
    if (nn > 0) {
        double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double h = dot(ap, n) / nn;
        double pr[3] = {p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]};
        int s = 1;
        const double *v[3] = {a, b, c};
        for (int i = 0; i < 3; i++) {
            const double *x = v[i], *y = v[(i + 1) % 3];
            double ex[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, px[3] = {pr[0] - x[0], pr[1] - x[1], pr[2] - x[2]};
            double cr[3] = {ex[1] * px[2] - ex[2] * px[1], ex[2] * px[0] - ex[0] * px[2], ex[0] * px[1] - ex[1] * px[0]};
            if (dot(cr, n) < 0) s = 0;
        }
        if (s) {
            double hd = h * h * nn;
            if (hd < best) best = hd;
        }
    }
    return best;
}

static void check_closest(const tmesh *m, double scale)
{
    geom_meshdist *md = NULL, *one = NULL;
    assert_int_equal(geom_meshdist_create(m->pos, m->nv, m->tris, m->nt, NULL, &md, NULL), GEOM_OK);
    geom_meshdist_options o = {0};
    o.max_leaf_size = (uint32_t)m->nt;
    assert_int_equal(geom_meshdist_create(m->pos, m->nv, m->tris, m->nt, &o, &one, NULL), GEOM_OK);
    size_t nq = 1500; /* > 512: the batch runs in Morton order with hints */
    double *q = malloc(3 * nq * sizeof *q);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < m->nv; i++)
        for (int k = 0; k < 3; k++) {
            if (m->pos[3 * i + k] < lo[k]) lo[k] = m->pos[3 * i + k];
            if (m->pos[3 * i + k] > hi[k]) hi[k] = m->pos[3 * i + k];
        }
    for (size_t i = 0; i < nq; i++)
        for (int k = 0; k < 3; k++) {
            double ext = hi[k] - lo[k];
            q[3 * i + k] = i % 10 == 0 ? m->pos[3 * (i % m->nv) + k] /* at a vertex */
                                       : lo[k] - 0.2 * ext + 1.4 * ext * urand();
        }
    double *pt = malloc(3 * nq * sizeof *pt), *pt1 = malloc(3 * nq * sizeof *pt1);
    double *bary = malloc(3 * nq * sizeof *bary), *d = malloc(nq * sizeof *d), *d1 = malloc(nq * sizeof *d1);
    uint32_t *tri = malloc(nq * sizeof *tri), *tri1 = malloc(nq * sizeof *tri1);
    assert_int_equal(geom_meshdist_closest(md, q, nq, pt, tri, bary, d, 2, NULL), GEOM_OK);
    assert_int_equal(geom_meshdist_closest(one, q, nq, pt1, tri1, NULL, d1, 1, NULL), GEOM_OK);
    assert_memory_equal(tri, tri1, nq * sizeof *tri);
    assert_memory_equal(d, d1, nq * sizeof *d);
    assert_memory_equal(pt, pt1, 3 * nq * sizeof *pt);
    /* One query at a time (no reordering, no starting hint): the same answers. */
    for (size_t i = 0; i < nq; i++) {
        double p1[3], b1[3], dd1;
        uint32_t t1;
        assert_int_equal(geom_meshdist_closest(md, q + 3 * i, 1, p1, &t1, b1, &dd1, 1, NULL), GEOM_OK);
        assert_int_equal(t1, tri[i]);
        assert_memory_equal(&dd1, &d[i], sizeof dd1);
        assert_memory_equal(p1, &pt[3 * i], sizeof p1);
        assert_memory_equal(b1, &bary[3 * i], sizeof b1);
    }
    for (size_t i = 0; i < nq; i++) {
        double best = INFINITY;
        for (size_t t = 0; t < m->nt; t++) {
            double d2 = tri_d2(q + 3 * i, m->pos + 3 * m->tris[3 * t], m->pos + 3 * m->tris[3 * t + 1],
                               m->pos + 3 * m->tris[3 * t + 2]);
            if (d2 < best) best = d2;
        }
        double tol = 1e-9 * scale;
        if (!(fabs(sqrt(best) - d[i]) <= tol))
            fail_msg("query %zu: distance %.17g, brute force %.17g", i, d[i], sqrt(best));
        /* The point is on the triangle named, at the distance reported. */
        const uint32_t *v = m->tris + 3 * tri[i];
        double s = bary[3 * i] + bary[3 * i + 1] + bary[3 * i + 2];
        assert_true(fabs(s - 1) < 1e-12);
        for (int k = 0; k < 3; k++) {
            assert_true(bary[3 * i + k] >= -1e-12);
            double x = bary[3 * i] * m->pos[3 * v[0] + k] + bary[3 * i + 1] * m->pos[3 * v[1] + k] +
                       bary[3 * i + 2] * m->pos[3 * v[2] + k];
            assert_true(fabs(x - pt[3 * i + k]) <= tol);
        }
        double dd[3] = {pt[3 * i] - q[3 * i], pt[3 * i + 1] - q[3 * i + 1], pt[3 * i + 2] - q[3 * i + 2]};
        assert_true(fabs(sqrt(dot(dd, dd)) - d[i]) <= tol);
    }
    free(q), free(pt), free(pt1), free(bary), free(d), free(d1), free(tri), free(tri1);
    geom_meshdist_destroy(md);
    geom_meshdist_destroy(one);
}

static void test_closest(void **st)
{
    (void)st;
    tmesh a = soup(2000, 0), b = soup(2000, 1), c = soup(64, 2);
    const double c0[3] = {0.1, -0.2, 0.3};
    tmesh s = sphere(40, 20, 1.0, c0);
    check_closest(&a, 1.0);
    check_closest(&b, 1e8);
    check_closest(&c, 4.0);
    check_closest(&s, 1.0);
    free_mesh(&a), free_mesh(&b), free_mesh(&c), free_mesh(&s);
}

/* Solid angle by L'Huilier's theorem on the unit-sphere triangle, signed by
 * the orientation. */
static double solid_angle_lhuilier(const double *q, const double *A, const double *B, const double *C)
{
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; k++)
        a[k] = A[k] - q[k], b[k] = B[k] - q[k], c[k] = C[k] - q[k];
    double la = sqrt(dot(a, a)), lb = sqrt(dot(b, b)), lc = sqrt(dot(c, c));
    if (la == 0 || lb == 0 || lc == 0)
        return 0;
    double ta = acos(fmax(-1, fmin(1, dot(b, c) / (lb * lc))));
    double tb = acos(fmax(-1, fmin(1, dot(c, a) / (lc * la))));
    double tc = acos(fmax(-1, fmin(1, dot(a, b) / (la * lb))));
    double s = 0.5 * (ta + tb + tc);
    double x = tan(s / 2) * tan((s - ta) / 2) * tan((s - tb) / 2) * tan((s - tc) / 2);
    double e = 4 * atan(sqrt(fmax(0, x)));
    double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0]);
    return det < 0 ? -e : e;
}

static double brute_winding(const tmesh *m, const double *q)
{
    double s = 0;
    for (size_t t = 0; t < m->nt; t++)
        s += solid_angle_lhuilier(q, m->pos + 3 * m->tris[3 * t], m->pos + 3 * m->tris[3 * t + 1],
                                  m->pos + 3 * m->tris[3 * t + 2]);
    return s / (4 * PI);
}

static void check_winding(const tmesh *m, int closed)
{
    geom_meshdist *fast = NULL, *exact = NULL;
    geom_meshdist_options o = {0};
    o.tolerance = 1e-2;
    assert_int_equal(geom_meshdist_create(m->pos, m->nv, m->tris, m->nt, &o, &fast, NULL), GEOM_OK);
    geom_meshdist *barill = NULL;
    o.tolerance = 0;
    assert_int_equal(geom_meshdist_create(m->pos, m->nv, m->tris, m->nt, &o, &barill, NULL), GEOM_OK);
    o.beta = -1;
    assert_int_equal(geom_meshdist_create(m->pos, m->nv, m->tris, m->nt, &o, &exact, NULL), GEOM_OK);
    size_t nq = 400;
    double *q = malloc(3 * nq * sizeof *q), *wf = malloc(nq * sizeof *wf), *we = malloc(nq * sizeof *we);
    for (size_t i = 0; i < 3 * nq; i++)
        q[i] = 6 * (urand() - 0.5);
    geom_error_report rf, re;
    assert_int_equal(geom_meshdist_winding(fast, q, nq, wf, &rf, 2, NULL), GEOM_OK);
    assert_int_equal(geom_meshdist_winding(exact, q, nq, we, &re, 1, NULL), GEOM_OK);
    /* Barill's criterion alone: fewer terms, every value within its bound. */
    double *wb = malloc(nq * sizeof *wb);
    geom_error_report rb;
    assert_int_equal(geom_meshdist_winding(barill, q, nq, wb, &rb, 1, NULL), GEOM_OK);
    assert_true(rb.evaluations < rf.evaluations);
    double worst_b = 0;
    for (size_t i = 0; i < nq; i++) {
        double e = fabs(wb[i] - we[i]);
        if (e > worst_b)
            worst_b = e;
        assert_true(e <= rb.max_error + 1e-9);
    }
    print_message("winding, Barill criterion only: bound %.3g, worst actual error %.3g, %zu terms\n",
                  rb.max_error, worst_b, rb.evaluations);
    free(wb);
    assert_int_equal(rf.method, GEOM_ERROR_BOUND);
    assert_true(re.max_error == 0);
    assert_true(rf.max_error <= 1e-2 + 1e-9);
    assert_true(rf.evaluations < re.evaluations);
    double worst = 0;
    for (size_t i = 0; i < nq; i++) {
        double b = brute_winding(m, q + 3 * i);
        assert_true(fabs(we[i] - b) < 1e-9);
        if (!(fabs(wf[i] - b) <= rf.max_error + 1e-9))
            fail_msg("query %zu: fast %.17g exact %.17g bound %g", i, wf[i], b, rf.max_error);
        if (fabs(wf[i] - b) > worst) worst = fabs(wf[i] - b);
        if (closed) {
            double r2 = q[3 * i] * q[3 * i] + q[3 * i + 1] * q[3 * i + 1] + q[3 * i + 2] * q[3 * i + 2];
            if (r2 < 0.9 * 0.9)
                assert_true(fabs(we[i] - 1) < 1e-9);
            else if (r2 > 1.1 * 1.1)
                assert_true(fabs(we[i]) < 1e-9);
        }
    }
    print_message("winding: bound %.3g, worst actual error %.3g, %zu vs %zu terms\n", rf.max_error,
                  worst, rf.evaluations, re.evaluations);
    /* Signed distance: sign from the winding number, magnitude = closest distance. */
    double *sd = malloc(nq * sizeof *sd), *d = malloc(nq * sizeof *d);
    assert_int_equal(geom_meshdist_signed_distance(barill, q, nq, sd, NULL, 0, NULL), GEOM_OK);
    assert_int_equal(geom_meshdist_closest(fast, q, nq, NULL, NULL, NULL, d, 0, NULL), GEOM_OK);
    for (size_t i = 0; i < nq; i++) {
        assert_true(fabs(sd[i]) == d[i]);
        assert_true((sd[i] < 0 || (sd[i] == 0 && we[i] >= 0.5)) == (we[i] >= 0.5));
    }
    /* Near the surface (where the refinement works hardest): points on
     * random triangles, pushed off by up to 1e-2 either way, and vertices
     * themselves; the sign must be that of the exact sum. */
    for (size_t i = 0; i < nq; i++) {
        const uint32_t *v = m->tris + 3 * (size_t)(urand() * (double)m->nt);
        const double *a = m->pos + 3 * v[0], *b = m->pos + 3 * v[1], *c = m->pos + 3 * v[2];
        double u = urand(), w = urand();
        if (u + w > 1) u = 1 - u, w = 1 - w;
        double off = i % 7 == 0 ? 0.0 : (urand() - 0.5) * (i % 3 ? 2e-2 : 2e-6);
        for (int k = 0; k < 3; k++)
            q[3 * i + k] = (i % 11 == 0 ? a[k] : a[k] + u * (b[k] - a[k]) + w * (c[k] - a[k])) * (1 + off);
    }
    geom_error_report rs;
    assert_int_equal(geom_meshdist_winding(exact, q, nq, we, NULL, 1, NULL), GEOM_OK);
    assert_int_equal(geom_meshdist_signed_distance(barill, q, nq, sd, &rs, 2, NULL), GEOM_OK);
    assert_int_equal(geom_meshdist_closest(fast, q, nq, NULL, NULL, NULL, d, 0, NULL), GEOM_OK);
    for (size_t i = 0; i < nq; i++) {
        assert_true(fabs(sd[i]) == d[i]);
        if ((sd[i] < 0 || (sd[i] == 0 && we[i] >= 0.5)) != (we[i] >= 0.5))
            fail_msg("near-surface query %zu: signed distance %.17g, exact winding %.17g", i, sd[i], we[i]);
    }
    print_message("signed distance near the surface: %zu terms for %zu queries\n", rs.evaluations, nq);
    free(sd), free(d), free(q), free(wf), free(we);
    geom_meshdist_destroy(fast);
    geom_meshdist_destroy(barill);
    geom_meshdist_destroy(exact);
}

static void test_winding(void **st)
{
    (void)st;
    const double c0[3] = {0, 0, 0};
    tmesh s = sphere(64, 32, 1.0, c0);
    check_winding(&s, 1);
    /* Open: drop a cap of triangles (a hole). */
    s.nt -= 64;
    check_winding(&s, 0);
    free_mesh(&s);
    /* Two overlapping spheres: winding 2 in the overlap. */
    const double c1[3] = {0.5, 0, 0};
    tmesh a = sphere(32, 16, 1.0, c0), b = sphere(32, 16, 1.0, c1);
    tmesh u;
    u.nv = a.nv + b.nv;
    u.nt = a.nt + b.nt;
    u.pos = malloc(3 * u.nv * sizeof *u.pos);
    u.tris = malloc(3 * u.nt * sizeof *u.tris);
    memcpy(u.pos, a.pos, 3 * a.nv * sizeof *u.pos);
    memcpy(u.pos + 3 * a.nv, b.pos, 3 * b.nv * sizeof *u.pos);
    memcpy(u.tris, a.tris, 3 * a.nt * sizeof *u.tris);
    for (size_t i = 0; i < 3 * b.nt; i++)
        u.tris[3 * a.nt + i] = b.tris[i] + (uint32_t)a.nv;
    check_winding(&u, 0);
    geom_meshdist *md = NULL;
    assert_int_equal(geom_meshdist_create(u.pos, u.nv, u.tris, u.nt, NULL, &md, NULL), GEOM_OK);
    double q[3] = {0.25, 0, 0}, w;
    assert_int_equal(geom_meshdist_winding(md, q, 1, &w, NULL, 0, NULL), GEOM_OK);
    assert_true(fabs(w - 2) < 0.1); /* Barill approximation, default options */
    geom_meshdist_destroy(md);
    free_mesh(&a), free_mesh(&b), free_mesh(&u);
}

static void test_edges(void **st)
{
    (void)st;
    geom_meshdist *md = NULL;
    geom_diag d;
    /* Empty mesh. */
    assert_int_equal(geom_meshdist_create(NULL, 0, NULL, 0, NULL, &md, NULL), GEOM_OK);
    double q[6] = {0, 0, 0, 1, NAN, 0}, dist, w;
    uint32_t t;
    assert_int_equal(geom_meshdist_closest(md, q, 1, NULL, &t, NULL, &dist, 0, NULL), GEOM_OK);
    assert_int_equal(t, GEOM_INVALID_INDEX);
    assert_true(isinf(dist));
    assert_int_equal(geom_meshdist_winding(md, q, 1, &w, NULL, 0, NULL), GEOM_OK);
    assert_true(w == 0);
    assert_int_equal(geom_meshdist_closest(md, q, 2, NULL, &t, NULL, &dist, 0, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "query 1"));
    geom_meshdist_destroy(md);
    geom_meshdist_destroy(NULL);
    /* Degenerate triangles (a segment, a point) are fine. */
    double p[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    uint32_t tr[6] = {0, 1, 2, 1, 1, 1};
    assert_int_equal(geom_meshdist_create(p, 3, tr, 2, NULL, &md, NULL), GEOM_OK);
    double qq[3] = {1.5, 1, 0}, pt[3], bary[3];
    assert_int_equal(geom_meshdist_closest(md, qq, 1, pt, &t, bary, &dist, 0, NULL), GEOM_OK);
    assert_true(dist == 1.0);
    assert_true(pt[0] == 1.5 && pt[1] == 0 && pt[2] == 0);
    assert_int_equal(t, 0);
    geom_meshdist_destroy(md);
    p[4] = INFINITY;
    assert_int_equal(geom_meshdist_create(p, 3, tr, 2, NULL, &md, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "triangle 0"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closest),
        cmocka_unit_test(test_winding),
        cmocka_unit_test(test_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
