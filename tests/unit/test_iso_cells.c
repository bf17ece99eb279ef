/*
 * Per-cell topology of the marching cubes against independent references:
 *  - the single-cell cases of CGAL's Isosurfacing_3 TMC test suite
 *    (tests/data/tmc-cases.tsv: components, Euler characteristic and
 *    boundary loops of the trilinear interpolant's level set in one cell),
 *    alone and embedded in a closing 4x4x4 grid (manifold, watertight, no
 *    duplicate points or faces, no degenerate faces), and under the 48
 *    symmetries of the cube and the sign flip f -> -f;
 *  - random cells against a brute-force reference: the sign regions of the
 *    trilinear interpolant, flood-filled on fine sample grids. Inside the
 *    cell the level set's components and the sign regions form a tree, so
 *    regions = components + 1.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/iso.h"
#include "unit/test_iso_util.h"

typedef struct tmc_case {
    char name[64];
    double v[8]; /* TSV order: corner index 4x + 2y + z */
    double iso;
    int checked; /* components/euler/boundaries listed */
    long comps, euler, loops;
} tmc_case;

static tmc_case cases[64];
static int ncases;

static int load_cases(void **state)
{
    (void)state;
    const char *dir = getenv("GEOM_SHARED_DATA");
    char path[4096];
    snprintf(path, sizeof path, "%s/tmc-cases.tsv", dir ? dir : "tests/data");
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "cannot open %s\n", path);
        return -1;
    }
    char line[4096];
    ncases = 0;
    while (fgets(line, sizeof line, f) && ncases < 64) {
        if (line[0] == '#' || strncmp(line, "name\t", 5) == 0)
            continue;
        tmc_case *c = &cases[ncases];
        char a[16], b[16], d[16];
        if (sscanf(line, "%63s %lf %lf %lf %lf %lf %lf %lf %lf %lf %15s %15s %15s", c->name,
                   &c->v[0], &c->v[1], &c->v[2], &c->v[3], &c->v[4], &c->v[5], &c->v[6],
                   &c->v[7], &c->iso, a, b, d) != 13)
            continue;
        c->checked = strcmp(a, "-") != 0;
        if (c->checked) {
            c->comps = atol(a);
            c->euler = atol(b);
            c->loops = atol(d);
        }
        ncases++;
    }
    fclose(f);
    return ncases == 33 ? 0 : -1;
}

/* One cell with corner values in our order (x + 2y + 4z). */
static void extract_cell(const double g[8], double iso, geom_iso_surface *s)
{
    geom_iso_grid grid;
    memset(&grid, 0, sizeof grid);
    grid.dims[0] = grid.dims[1] = grid.dims[2] = 2;
    grid.type = GEOM_ISO_SCALAR_F64;
    grid.data = g;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    assert_int_equal(geom_iso_extract_grid(&grid, &o, s, NULL), GEOM_OK);
}

static void tsv_to_ours(const double v[8], double g[8])
{
    for (int x = 0; x < 2; x++)
        for (int y = 0; y < 2; y++)
            for (int z = 0; z < 2; z++)
                g[x + 2 * y + 4 * z] = v[4 * x + 2 * y + z];
}

static iso_topo cell_topo(const double g[8], double iso)
{
    geom_iso_surface s;
    extract_cell(g, iso, &s);
    iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    geom_iso_surface_free(&s);
    return r;
}

static void test_tmc_single(void **state)
{
    (void)state;
    for (int i = 0; i < ncases; i++) {
        double g[8];
        tsv_to_ours(cases[i].v, g);
        iso_topo r = cell_topo(g, cases[i].iso);
        if (!iso_topo_clean(&r) || r.nonmanifold_edges) {
            fprintf(stderr, "%s: not clean\n", cases[i].name);
            fail();
        }
        if (cases[i].checked &&
            (r.components != cases[i].comps || r.euler != cases[i].euler ||
             r.boundary_loops != cases[i].loops)) {
            fprintf(stderr, "%s: got %ld %ld %ld, expected %ld %ld %ld\n", cases[i].name,
                    r.components, r.euler, r.boundary_loops, cases[i].comps, cases[i].euler,
                    cases[i].loops);
            fail();
        }
    }
}

static void test_tmc_embedded(void **state)
{
    (void)state;
    for (int i = 0; i < ncases; i++) {
        double big = 0;
        for (int k = 0; k < 8; k++)
            big = fmax(big, fabs(cases[i].v[k] - cases[i].iso));
        double d[64];
        for (int k = 0; k < 64; k++)
            d[k] = cases[i].iso + 2 * big + 1;
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2; y++)
                for (int z = 0; z < 2; z++)
                    d[(x + 1) + 4 * ((y + 1) + 4 * (z + 1))] = cases[i].v[4 * x + 2 * y + z];
        geom_iso_grid grid;
        memset(&grid, 0, sizeof grid);
        grid.dims[0] = grid.dims[1] = grid.dims[2] = 4;
        grid.type = GEOM_ISO_SCALAR_F64;
        grid.data = d;
        geom_iso_options o;
        memset(&o, 0, sizeof o);
        o.iso = cases[i].iso;
        for (int layers = 1; layers <= 3; layers += 2) {
            o.slab_layers = (size_t)layers;
            geom_iso_surface s;
            assert_int_equal(geom_iso_extract_grid(&grid, &o, &s, NULL), GEOM_OK);
            iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
            if (!iso_topo_clean(&r) || r.boundary_edges || r.nonmanifold_edges ||
                s.n_triangles == 0) {
                fprintf(stderr, "%s embedded: nm %ld/%ld dupP %ld dupF %ld deg %ld open %ld\n",
                        cases[i].name, r.nonmanifold_edges, r.nonmanifold_vertices,
                        r.duplicate_points, r.duplicate_faces, r.degenerate_faces,
                        r.boundary_edges);
                fail();
            }
            /* the closed surface bounds the inside: positive volume */
            assert_true(iso_volume(s.xyz, s.n_triangles, s.tris) > 0);
            geom_iso_surface_free(&s);
        }
    }
}

/* The 48 symmetries of the cube (axis permutations and reflections) leave
 * the topology unchanged; so does f -> -f with iso -> -iso when no corner
 * equals the isovalue (the level set is the same set). */
static void test_tmc_symmetries(void **state)
{
    (void)state;
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int i = 0; i < ncases; i++) {
        double g[8];
        tsv_to_ours(cases[i].v, g);
        iso_topo ref = cell_topo(g, cases[i].iso);
        int zero = 0;
        for (int k = 0; k < 8; k++)
            zero |= g[k] == cases[i].iso;
        for (int p = 0; p < 6; p++)
            for (int refl = 0; refl < 8; refl++) {
                double h[8];
                for (int c = 0; c < 8; c++) {
                    int x[3] = {c & 1, (c >> 1) & 1, c >> 2}, y[3];
                    for (int a = 0; a < 3; a++)
                        y[a] = x[perms[p][a]] ^ ((refl >> a) & 1);
                    h[y[0] + 2 * y[1] + 4 * y[2]] = g[c];
                }
                iso_topo r = cell_topo(h, cases[i].iso);
                assert_true(iso_topo_clean(&r));
                if (!cases[i].checked)
                    continue;
                if (r.components != ref.components || r.euler != ref.euler ||
                    r.boundary_loops != ref.boundary_loops) {
                    fprintf(stderr, "%s: symmetry %d/%d changes the topology\n", cases[i].name,
                            p, refl);
                    fail();
                }
            }
        if (!zero && cases[i].checked) {
            double n[8];
            for (int k = 0; k < 8; k++)
                n[k] = -g[k];
            iso_topo r = cell_topo(n, -cases[i].iso);
            assert_int_equal(r.components, ref.components);
            assert_int_equal(r.euler, ref.euler);
            assert_int_equal(r.boundary_loops, ref.boundary_loops);
        }
    }
}

/* ------------------------------------------------- brute-force reference */

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static double trilinear(const double g[8], double x, double y, double z)
{
    double a = g[0] * (1 - x) + g[1] * x, b = g[2] * (1 - x) + g[3] * x;
    double c = g[4] * (1 - x) + g[5] * x, d = g[6] * (1 - x) + g[7] * x;
    double e = a * (1 - y) + b * y, f = c * (1 - y) + d * y;
    return e * (1 - z) + f * z;
}

/* Connected components of the sign classes {F > 0} and {F <= 0} sampled on
 * an m^3 grid of the closed cell, faces included (6-connectivity). */
static int regions(const double g[8], int m)
{
    size_t n = (size_t)m * m * m;
    unsigned char *s = malloc(n);
    int *lab = malloc(n * sizeof(int));
    int *stack = malloc(n * sizeof(int));
    for (int k = 0; k < m; k++)
        for (int j = 0; j < m; j++)
            for (int i = 0; i < m; i++) {
                size_t q = (size_t)i + (size_t)m * ((size_t)j + (size_t)m * (size_t)k);
                s[q] = trilinear(g, (double)i / (m - 1), (double)j / (m - 1),
                                 (double)k / (m - 1)) > 0;
                lab[q] = -1;
            }
    int nreg = 0;
    for (size_t q0 = 0; q0 < n; q0++) {
        if (lab[q0] >= 0)
            continue;
        int sp = 0;
        stack[sp++] = (int)q0;
        lab[q0] = nreg;
        while (sp) {
            int q = stack[--sp];
            int i = q % m, j = (q / m) % m, k = q / (m * m);
            const int nb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
            for (int t = 0; t < 6; t++) {
                int a = i + nb[t][0], b = j + nb[t][1], c = k + nb[t][2];
                if (a < 0 || b < 0 || c < 0 || a >= m || b >= m || c >= m)
                    continue;
                int r = a + m * (b + m * c);
                if (lab[r] < 0 && s[r] == s[q]) {
                    lab[r] = nreg;
                    stack[sp++] = r;
                }
            }
        }
        nreg++;
    }
    free(stack);
    free(lab);
    free(s);
    return nreg;
}

static void test_random_cells(void **state)
{
    (void)state;
    int tested = 0, tubes = 0, multi = 0, attempts = 0;
    while (tested < 300 && attempts < 200000) {
        attempts++;
        double g[8];
        /* sign patterns with interior ambiguities are likelier when the
         * corners are drawn around a random trilinear saddle structure; a
         * plain uniform draw covers the rest */
        for (int c = 0; c < 8; c++)
            g[c] = 2 * rnd() - 1;
        if (attempts % 2) {
            /* MC case 4 / 13 sign patterns: opposite corners share a sign */
            int pat = (int)(rnd() * 3);
            /* positive corners strong, negative ones weak: tunnels joining
             * the positive corners are likely */
            for (int c = 0; c < 8; c++) {
                int par = ((c & 1) + ((c >> 1) & 1) + (c >> 2)) & 1;
                int pos = pat == 0 ? (c == 0 || c == 7)
                                   : pat == 1 ? par : (c == 0 || c == 7 || c == 3);
                g[c] = pos ? 0.4 + 0.6 * fabs(g[c]) : -0.02 - 0.4 * fabs(g[c]);
            }
        }
        geom_iso_surface s;
        extract_cell(g, 0.0, &s);
        iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
        size_t tun = s.report.tunnels;
        geom_iso_surface_free(&s);
        assert_true(iso_topo_clean(&r));
        if (r.boundary_loops < 2)
            continue;
        /* skip cells whose face saddles are nearly on the isovalue: their
         * channels are thinner than any sampling resolves */
        int near = 0;
        double scale = 0;
        for (int c = 0; c < 8; c++)
            scale = fmax(scale, fabs(g[c]));
        for (int axis = 0; axis < 3; axis++)
            for (int side = 0; side < 2; side++) {
                int au = axis == 0 ? 1 : 0, av = axis == 2 ? 1 : 2;
                int c00 = side << axis, c10 = c00 | 1 << au, c01 = c00 | 1 << av,
                    c11 = c10 | 1 << av;
                double q = g[c00] * g[c11] - g[c10] * g[c01];
                near |= fabs(q) < 0.02 * scale * scale;
            }
        if (near)
            continue;
        int r1 = regions(g, 33), r2 = regions(g, 57);
        if (r1 != r2)
            continue; /* a feature thinner than the sampling: skip */
        tested++;
        multi++;
        tubes += tun > 0;
        if (r.components + 1 != r1) {
            fprintf(stderr, "cell %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g: %ld components, "
                            "%d regions\n",
                    g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], r.components, r1);
            fail();
        }
        /* genus 0 pieces: chi = 2 components - contours */
        assert_int_equal(r.euler, 2 * r.components - r.boundary_loops);
    }
    printf("random cells: %d tested (%d attempts), %d with a tunnel\n", tested, attempts, tubes);
    assert_int_equal(tested, 300);
    assert_true(tubes >= 20);         /* tunnels were exercised */
    assert_true(multi - tubes >= 20); /* and separated sheets */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tmc_single),
        cmocka_unit_test(test_tmc_embedded),
        cmocka_unit_test(test_tmc_symmetries),
        cmocka_unit_test(test_random_cells),
    };
    return cmocka_run_group_tests(tests, load_cases, NULL);
}
