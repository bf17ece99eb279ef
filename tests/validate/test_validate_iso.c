/*
 * Marching cubes outputs checked by CGAL (gv_soup_check: the soup must be a
 * polygon mesh as given, valid, closed and free of self-intersections), for
 * a suite of fields whose topology is known: the unit sphere (genus 0), a
 * torus (genus 1), two linked tori (two components of genus 1: CGAL's
 * genus sums them to 2), three merged
 * metaballs (genus 0), a chain of three tori (genus 3) and a gyroid
 * labyrinth in a box closed by caps. The gyroid's genus and the metaballs'
 * are also computed independently from a fine voxelisation of the inside
 * region R (the Euler characteristic of the union of closed voxels, and
 * chi(boundary R) = 2 chi(R)). The TMC single-cell cases are checked too:
 * embedded in a closing grid (closed, manifold, no self-intersection) and
 * alone (tunnels included, no self-intersection).
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
#include "validate/geom_validate.h"

static gv_soup_info check_surface(const geom_iso_surface *s)
{
    uint32_t *sizes = malloc(sizeof(uint32_t) * (s->n_triangles + 1));
    for (size_t t = 0; t < s->n_triangles; t++)
        sizes[t] = 3;
    gv_soup_info info;
    assert_int_equal(gv_soup_check(s->n_vertices, s->xyz, s->n_triangles, sizes, s->tris, &info),
                     GV_OK);
    free(sizes);
    return info;
}

/* Euler characteristic of the union of the closed voxels of side d centred
 * at the samples lo + (i + 1/2) d inside the box where f <= 0. */
static long voxel_euler(geom_iso_value_fn f, const double lo[3], const double hi[3], int m)
{
    double d[3];
    for (int a = 0; a < 3; a++)
        d[a] = (hi[a] - lo[a]) / m;
    int n = m + 2; /* padded */
    unsigned char *in = calloc((size_t)n * n * n, 1);
#define IDX(i, j, k) ((size_t)(i) + (size_t)n * ((size_t)(j) + (size_t)n * (size_t)(k)))
    for (int k = 0; k < m; k++)
        for (int j = 0; j < m; j++)
            for (int i = 0; i < m; i++) {
                double p[3] = {lo[0] + (i + 0.5) * d[0], lo[1] + (j + 0.5) * d[1],
                               lo[2] + (k + 0.5) * d[2]};
                in[IDX(i + 1, j + 1, k + 1)] = f(NULL, p) <= 0;
            }
    long V = 0, E = 0, F = 0, C = 0;
    /* cells of the padded lattice: a cell with dimension mask (dx, dy, dz)
     * at lattice point (i, j, k) is in the union when a voxel containing it
     * is inside; voxel (a, b, c) spans points a..a+1. */
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                if (in[IDX(i, j, k)])
                    C++;
                for (int mask = 0; mask < 7; mask++) {
                    /* a cell at corner point (i, j, k) extending +1 along the
                     * axes in mask; the voxels touching it are (i - 1 + e) for
                     * e in {0, 1} along the axes not in mask, (i) along mask */
                    int dx = mask & 1, dy = (mask >> 1) & 1, dz = (mask >> 2) & 1;
                    int any = 0;
                    for (int ex = 0; ex <= !dx && !any; ex++)
                        for (int ey = 0; ey <= !dy && !any; ey++)
                            for (int ez = 0; ez <= !dz && !any; ez++) {
                                int a = dx ? i : i - 1 + ex, b = dy ? j : j - 1 + ey,
                                    c = dz ? k : k - 1 + ez;
                                if (a >= 0 && b >= 0 && c >= 0 && a < n && b < n && c < n)
                                    any = in[IDX(a, b, c)];
                            }
                    if (!any)
                        continue;
                    int dim = dx + dy + dz;
                    if (dim == 0)
                        V++;
                    else if (dim == 1)
                        E++;
                    else
                        F++;
                }
            }
#undef IDX
    free(in);
    return V - E + F - C;
}

typedef struct suite_case {
    const char *name;
    geom_iso_value_fn f;
    double b[6];
    size_t res;
    int caps;
    long components, genus; /* genus summed over components; < 0: from the voxels */
} suite_case;

static void run_case(const suite_case *c, long genus)
{
    geom_iso_field fl;
    memset(&fl, 0, sizeof fl);
    fl.value = c->f;
    fl.exact = 1;
    size_t res[3] = {c->res, c->res + 1, c->res + 2};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.caps = c->caps;
    for (int refine = 0; refine < 2; refine++) {
        o.refine = refine ? GEOM_IMPLICIT_REFINE_AUTO : GEOM_IMPLICIT_REFINE_NEVER;
        geom_iso_surface s;
        assert_int_equal(geom_iso_extract(&fl, c->b, res, &o, &s, NULL), GEOM_OK);
        gv_soup_info info = check_surface(&s);
        if (!info.is_polygon_soup_a_polygon_mesh || !info.valid || !info.closed ||
            info.self_intersecting != 0 || (long long)info.components != c->components ||
            info.genus != genus) {
            fprintf(stderr,
                    "%s (refine %d): mesh %d valid %d closed %d self-intersecting %d "
                    "components %zu genus %lld (expected %ld, %ld)\n",
                    c->name, refine, info.is_polygon_soup_a_polygon_mesh, info.valid, info.closed,
                    info.self_intersecting, info.components, info.genus, c->components, genus);
            fail();
        }
        assert_int_equal(info.euler_characteristic, 2 * c->components - 2 * genus);
        assert_int_equal(info.vertices, s.n_vertices);
        assert_int_equal(info.faces, s.n_triangles);
        geom_iso_surface_free(&s);
    }
}

static void test_suite(void **state)
{
    (void)state;
    const suite_case cases[] = {
        {"sphere", iso_f_sphere, {-1.3, -1.27, -1.31, 1.29, 1.33, 1.3}, 24, 0, 1, 0},
        {"torus", iso_f_torus, {-1.5, -1.52, -0.55, 1.53, 1.5, 0.56}, 40, 0, 1, 1},
        {"linked tori", iso_f_linked, {-1.41, -1.43, -1.42, 2.42, 1.41, 1.43}, 56, 0, 2, 2},
        {"metaballs", iso_f_meta, {-1.6, -1.5, -1.4, 2.2, 2.1, 1.9}, 48, 0, 1, -1},
        {"genus 3", iso_f_genus3, {-2.3, -1.25, -0.45, 2.31, 1.26, 0.47}, 64, 0, 1, 3},
        {"gyroid with caps", iso_f_gyroid, {-2.9, -3.05, -3.2, 3.1, 3.0, 2.95}, 40, 1, 1, -1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        long genus = cases[i].genus;
        if (genus < 0) {
            const double *b = cases[i].b;
            long chi = voxel_euler(cases[i].f, b, b + 3, 160);
            long chi2 = voxel_euler(cases[i].f, b, b + 3, 211);
            assert_int_equal(chi, chi2); /* resolution-independent */
            /* chi(boundary) = 2 chi(R) = 2 components - 2 genus */
            genus = cases[i].components - chi;
            if (strcmp(cases[i].name, "metaballs") == 0)
                assert_int_equal(genus, 0);
            else
                assert_true(genus > 0);
        }
        run_case(&cases[i], genus);
    }
}

/* The TMC cases embedded in a closing grid (values above every corner
 * around the case cell): CGAL finds the result closed and manifold. */
static void test_tmc_embedded(void **state)
{
    (void)state;
    const char *dir = getenv("GEOM_SHARED_DATA");
    char path[4096];
    snprintf(path, sizeof path, "%s/tmc-cases.tsv", dir ? dir : "tests/data");
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[4096];
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || strncmp(line, "name\t", 5) == 0)
            continue;
        char name[64];
        double v[8], iso;
        if (sscanf(line, "%63s %lf %lf %lf %lf %lf %lf %lf %lf %lf", name, &v[0], &v[1], &v[2],
                   &v[3], &v[4], &v[5], &v[6], &v[7], &iso) != 10)
            continue;
        double big = 0;
        for (int k = 0; k < 8; k++)
            big = fmax(big, fabs(v[k] - iso));
        double d[64];
        for (int k = 0; k < 64; k++)
            d[k] = iso + 2 * big + 1;
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2; y++)
                for (int z = 0; z < 2; z++)
                    d[(x + 1) + 4 * ((y + 1) + 4 * (z + 1))] = v[4 * x + 2 * y + z];
        geom_iso_grid g;
        memset(&g, 0, sizeof g);
        g.dims[0] = g.dims[1] = g.dims[2] = 4;
        g.type = GEOM_ISO_SCALAR_F64;
        g.data = d;
        geom_iso_options o;
        memset(&o, 0, sizeof o);
        o.iso = iso;
        geom_iso_surface s;
        assert_int_equal(geom_iso_extract_grid(&g, &o, &s, NULL), GEOM_OK);
        gv_soup_info info = check_surface(&s);
        if (!info.is_polygon_soup_a_polygon_mesh || !info.valid || !info.closed ||
            info.self_intersecting != 0) {
            fprintf(stderr, "%s: mesh %d valid %d closed %d self-intersecting %d\n", name,
                    info.is_polygon_soup_a_polygon_mesh, info.valid, info.closed,
                    info.self_intersecting);
            fail();
        }
        geom_iso_surface_free(&s);
        /* the cell alone: tunnels and all, no self-intersection either */
        double one[8];
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2; y++)
                for (int z = 0; z < 2; z++)
                    one[x + 2 * y + 4 * z] = v[4 * x + 2 * y + z];
        g.dims[0] = g.dims[1] = g.dims[2] = 2;
        g.data = one;
        assert_int_equal(geom_iso_extract_grid(&g, &o, &s, NULL), GEOM_OK);
        if (s.n_triangles) {
            info = check_surface(&s);
            if (!info.is_polygon_soup_a_polygon_mesh || info.self_intersecting != 0) {
                fprintf(stderr, "%s alone: mesh %d self-intersecting %d\n", name,
                        info.is_polygon_soup_a_polygon_mesh, info.self_intersecting);
                fail();
            }
        }
        geom_iso_surface_free(&s);
        n++;
    }
    fclose(f);
    assert_int_equal(n, 33);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_suite),
        cmocka_unit_test(test_tmc_embedded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
