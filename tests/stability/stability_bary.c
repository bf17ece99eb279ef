/*
 * Barycentric coordinates on stiff input: sliver triangles and tetrahedra
 * with area / longest edge^2 (volume / longest edge^3) from 1e-3 down to
 * 1e-15, coordinates offset by 1e8, tiny (~1e-150) and huge (~1e150)
 * triangles, and points exactly on the edges of slivers.
 *
 * Reference answers are exact by construction: every vertex is an integer
 * (below 2^53) times a power of two, and the query point is the vertex
 * combination with weights k_i / 8 (integers k_i summing to 8) computed in
 * integer arithmetic, so it is exactly representable and its exact
 * barycentric coordinates are k_i / 8. Off-plane points for the 3D triangle
 * add an integer multiple of the plane's integer normal.
 *
 * Checked: each coordinate is within 2^-40 of its exact value relative to
 * its own magnitude (the library promises 2^-41 + 2^-53), hence far inside
 * the required 1e-9 of the largest coordinate; a zero weight gives exactly
 * 0 and a vertex exactly the unit vector. The largest errors seen are
 * printed.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "geom/bary.h"

#define TWO53 9007199254740992.0

static const int weights[][4] = {
    {1, 3, 4, 0}, {2, 5, 1, 0}, {6, 1, 1, 0}, {3, 3, 2, 0}, {7, 1, 0, 0}, /* on an edge */
    {0, 4, 4, 0},                                                      /* on an edge */
    {5, 0, 3, 0},                                                      /* on an edge */
    {8, 0, 0, 0},                                                      /* vertex */
    {0, 0, 8, 0},                                                      /* vertex */
    {-2, 5, 5, 0},                                                     /* outside */
};
#define NW (sizeof weights / sizeof weights[0])

static const double rhos[] = {1e-3, 1e-6, 1e-9, 1e-12, 1e-15};
#define NR (sizeof rhos / sizeof rhos[0])

/* unit (power of two) and offset (in units) of each placement */
typedef struct placement {
    const char *name;
    double unit;
    int64_t offset;
} placement;

static const placement places[] = {
    {"origin", 0x1p-21, 0},
    {"offset 1e8", 0x1p-21, (int64_t)100000000 << 21}, /* 1e8 exactly */
    {"offset -1e8", 0x1p-21, -((int64_t)100000000 << 21)},
    {"tiny (1e-150)", 0x1p-541, 0},
    {"tiny, offset", 0x1p-541, (int64_t)100000000 << 21},
    {"huge (1e150)", 0x1p459, 0},
    {"huge, offset", 0x1p459, (int64_t)100000000 << 21},
};
#define NP (sizeof places / sizeof places[0])

static double maxrel = 0.0;  /* max over coordinates of |l - exact| / |exact| */
static double maxabs = 0.0;  /* max of |l - exact| / max |exact| */

static double coord(const placement *pl, int64_t v)
{
    int64_t x = v + pl->offset;
    assert_true(fabs((double)x) < TWO53);
    return (double)x * pl->unit;
}

static void check(const double *l, const int *k, int n, const char *what)
{
    double big = 0.0;
    for (int i = 0; i < n; i++)
        big = fmax(big, fabs(k[i] / 8.0));
    for (int i = 0; i < n; i++) {
        double ex = k[i] / 8.0;
        double err = fabs(l[i] - ex);
        if (k[i] == 0) {
            if (l[i] != 0.0)
                fail_msg("%s: coordinate %d is %.17g, not exactly 0", what, i, l[i]);
            continue;
        }
        double rel = err / fabs(ex);
        if (rel > maxrel)
            maxrel = rel;
        if (err / big > maxabs)
            maxabs = err / big;
        if (!(rel <= 0x1p-40))
            fail_msg("%s: coordinate %d = %.17g, exact %.17g (rel. error %.3g)", what, i, l[i], ex,
                     rel);
        if (!(err <= 1e-9 * big))
            fail_msg("%s: error %.3g above 1e-9 of the largest coordinate", what, err);
    }
}

/* The sliver: a = 0, b = 8 B, c = 8 (B / 2 + delta), |delta| = 2 rho |B|
 * perpendicular to B, so that area / |b|^2 ~ rho. */
static void sliver2(double rho, int64_t B[2], int64_t C[2])
{
    B[0] = ((int64_t)3 << 47) + 1234566; /* even, generic direction */
    B[1] = ((int64_t)1 << 47) + 7654322;
    int64_t dx = llround(-2.0 * rho * (double)B[1]);
    int64_t dy = llround(2.0 * rho * (double)B[0]);
    if (dx == 0 && dy == 0)
        dy = 1;
    C[0] = 8 * (B[0] / 2 + dx);
    C[1] = 8 * (B[1] / 2 + dy);
    B[0] *= 8;
    B[1] *= 8;
}

static void test_tri2_slivers(void **state)
{
    (void)state;
    maxrel = maxabs = 0.0;
    for (size_t r = 0; r < NR; r++) {
        int64_t B[2], C[2], A[2] = {0, 0};
        sliver2(rhos[r], B, C);
        for (size_t pi = 0; pi < NP; pi++) {
            const placement *pl = &places[pi];
            for (int perm = 0; perm < 3; perm++) {
                /* rotate the vertex roles so that every edge is the long one */
                const int64_t *V[3] = {A, B, C};
                const int64_t *W[3] = {V[perm], V[(perm + 1) % 3], V[(perm + 2) % 3]};
                double v[3][2];
                for (int i = 0; i < 3; i++)
                    for (int c = 0; c < 2; c++)
                        v[i][c] = coord(pl, W[i][c]);
                for (size_t w = 0; w < NW; w++) {
                    const int *k = weights[w];
                    if (k[3] != 0)
                        continue; /* 4-weight rows are for the tetrahedron */
                    double p[2];
                    for (int c = 0; c < 2; c++)
                        p[c] = coord(pl, (k[0] * W[0][c] + k[1] * W[1][c] + k[2] * W[2][c]) / 8);
                    /* integer combination divisible by 8: all inputs are
                     * multiples of 8 */
                    double l[3];
                    assert_int_equal(geom_bary_tri2(v[0], v[1], v[2], p, l), GEOM_OK);
                    char what[96];
                    snprintf(what, sizeof what, "tri2 rho %g %s perm %d w %zu", rhos[r], pl->name,
                             perm, w);
                    check(l, k, 3, what);
                }
            }
        }
    }
    print_message("tri2 slivers: max rel. error %.3g (%.1f ulp), max error / largest %.3g\n",
                  maxrel, maxrel / 0x1p-53, maxabs);
}

static void test_tri3_slivers(void **state)
{
    (void)state;
    maxrel = maxabs = 0.0;
    for (size_t r = 0; r < NR; r++) {
        int64_t B[2], C[2], A[2] = {0, 0};
        sliver2(rhos[r], B, C);
        /* (x, y) -> (x, y, x + y) keeps integers below 2^53 and multiples of
         * 8; the plane has the integer normal (-1, -1, 1). */
        int64_t V3[3][3];
        const int64_t *V[3] = {A, B, C};
        for (int i = 0; i < 3; i++) {
            V3[i][0] = V[i][0];
            V3[i][1] = V[i][1];
            V3[i][2] = V[i][0] + V[i][1];
        }
        for (size_t pi = 0; pi < NP; pi++) {
            const placement *pl = &places[pi];
            double v[3][3];
            for (int i = 0; i < 3; i++)
                for (int c = 0; c < 3; c++)
                    v[i][c] = coord(pl, V3[i][c]);
            for (size_t w = 0; w < NW; w++) {
                const int *k = weights[w];
                if (k[3] != 0)
                    continue;
                for (int off = -1; off <= 1; off++) {
                    int64_t q[3];
                    for (int c = 0; c < 3; c++)
                        q[c] = (k[0] * V3[0][c] + k[1] * V3[1][c] + k[2] * V3[2][c]) / 8;
                    /* leave the plane along the normal (by 3 and by 2^20 units) */
                    int64_t t = off * (off > 0 ? 3 : ((int64_t)1 << 20));
                    q[0] -= t;
                    q[1] -= t;
                    q[2] += t;
                    double p[3] = {coord(pl, q[0]), coord(pl, q[1]), coord(pl, q[2])};
                    double l[3];
                    assert_int_equal(geom_bary_tri3(v[0], v[1], v[2], p, l), GEOM_OK);
                    char what[96];
                    snprintf(what, sizeof what, "tri3 rho %g %s off %d w %zu", rhos[r], pl->name,
                             off, w);
                    check(l, k, 3, what);
                }
            }
        }
    }
    print_message("tri3 slivers: max rel. error %.3g (%.1f ulp), max error / largest %.3g\n",
                  maxrel, maxrel / 0x1p-53, maxabs);
}

static void test_tet_slivers(void **state)
{
    (void)state;
    maxrel = maxabs = 0.0;
    static const int wt[][4] = {{1, 2, 3, 2}, {2, 2, 2, 2}, {5, 1, 1, 1}, {0, 3, 3, 2},
                                {1, 0, 0, 7}, {0, 0, 0, 8}, {-1, 3, 3, 3}, {4, 4, 4, -4}};
    for (size_t r = 0; r < NR; r++) {
        /* a = 0, b, c generic, d near the plane of a, b, c: the height is
         * ~rho times the edge length, so volume / edge^3 ~ rho */
        int64_t b[3] = {((int64_t)1 << 46) + 123454, ((int64_t)1 << 44) - 9876, 3 * 4096 + 2};
        int64_t c[3] = {((int64_t)1 << 44) + 3332, ((int64_t)1 << 46) - 22222, 7 * 1024};
        int64_t h = llround(rhos[r] * 0x1p46);
        if (h == 0)
            h = 1;
        int64_t d[3] = {(b[0] + c[0]) / 2, (b[1] + c[1]) / 2, (b[2] + c[2]) / 2 + h};
        int64_t a[3] = {0, 0, 0};
        int64_t *V[4] = {a, b, c, d};
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                V[i][k] *= 8;
        for (size_t pi = 0; pi < NP; pi++) {
            const placement *pl = &places[pi];
            double v[4][3];
            for (int i = 0; i < 4; i++)
                for (int k = 0; k < 3; k++)
                    v[i][k] = coord(pl, V[i][k]);
            for (size_t w = 0; w < sizeof wt / sizeof wt[0]; w++) {
                const int *k = wt[w];
                double p[3];
                for (int c2 = 0; c2 < 3; c2++)
                    p[c2] = coord(pl, (k[0] * V[0][c2] + k[1] * V[1][c2] + k[2] * V[2][c2] +
                                       k[3] * V[3][c2]) / 8);
                double l[4];
                assert_int_equal(geom_bary_tet(v[0], v[1], v[2], v[3], p, l), GEOM_OK);
                char what[96];
                snprintf(what, sizeof what, "tet rho %g %s w %zu", rhos[r], pl->name, w);
                check(l, k, 4, what);
            }
        }
    }
    print_message("tet slivers: max rel. error %.3g (%.1f ulp), max error / largest %.3g\n",
                  maxrel, maxrel / 0x1p-53, maxabs);
}

/* Points just off the long edge of a sliver, on both sides: p = m +- (c -
 * m) 2^-20 with m the midpoint of a-b, so the exact coordinates are
 * ((1 -+ 2^-20) / 2, (1 -+ 2^-20) / 2, +-2^-20). Coordinates are multiples of
 * 2^21 units so that p is exact. */
static void test_near_edge(void **state)
{
    (void)state;
    maxrel = maxabs = 0.0;
    static const double rh[] = {1e-3, 1e-6, 1e-9};
    for (size_t r = 0; r < sizeof rh / sizeof rh[0]; r++) {
        int64_t B0[2] = {((int64_t)3 << 28) + 12346, ((int64_t)1 << 28) + 76542};
        int64_t dx = llround(-2.0 * rh[r] * (double)B0[1]);
        int64_t dy = llround(2.0 * rh[r] * (double)B0[0]);
        int64_t M[2] = {B0[0] / 2, B0[1] / 2};
        int64_t C0[2] = {M[0] + dx, M[1] + dy};
        for (size_t pi = 0; pi < NP; pi++) {
            const placement *pl = &places[pi];
            const int64_t S = (int64_t)1 << 21;
            double a[2] = {coord(pl, 0), coord(pl, 0)};
            double b[2] = {coord(pl, B0[0] * S), coord(pl, B0[1] * S)};
            double c[2] = {coord(pl, C0[0] * S), coord(pl, C0[1] * S)};
            for (int s = -1; s <= 1; s += 2) {
                double p[2];
                for (int k = 0; k < 2; k++)
                    p[k] = coord(pl, M[k] * S + s * (C0[k] - M[k]) * 2);
                double l[3];
                assert_int_equal(geom_bary_tri2(a, b, c, p, l), GEOM_OK);
                const double ex[3] = {(1 - s * 0x1p-20) / 2, (1 - s * 0x1p-20) / 2, s * 0x1p-20};
                for (int i = 0; i < 3; i++) {
                    double rel = fabs(l[i] - ex[i]) / fabs(ex[i]);
                    if (rel > maxrel)
                        maxrel = rel;
                    if (!(rel <= 0x1p-40))
                        fail_msg("near edge rho %g %s side %d: l[%d] = %.17g, exact %.17g",
                                 rh[r], pl->name, s, i, l[i], ex[i]);
                }
            }
        }
    }
    print_message("near-edge points: max rel. error %.3g (%.1f ulp)\n", maxrel,
                  maxrel / 0x1p-53);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tri2_slivers),
        cmocka_unit_test(test_tri3_slivers),
        cmocka_unit_test(test_tet_slivers),
        cmocka_unit_test(test_near_edge),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
