/*
 * Closest points on triangle meshes against CGAL's AABB_tree: the bunny
 * (bunny00.off from libcgal-demo's data.tar.gz when it can be extracted,
 * else skipped) and random soups, including 1e8 offsets; distances agree to
 * a few ulp of the scale, and where CGAL's point is on another triangle the
 * two distances still agree (ties).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"
#include "geom/spatial.h"
#include "geom_validate_spatial.h"

static uint64_t rng_state = 0x6a09e667f3bcc909ull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

static void compare(const double *pos, size_t nv, const uint32_t *tris, size_t nt, double offset,
                    double scale)
{
    size_t nq = 2000;
    double *q = malloc(3 * nq * sizeof *q);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], pos[3 * i + k]);
            hi[k] = fmax(hi[k], pos[3 * i + k]);
        }
    for (size_t i = 0; i < nq; i++)
        for (int k = 0; k < 3; k++)
            q[3 * i + k] = i % 7 == 0 ? pos[3 * ((i * 31) % nv) + k]
                                      : lo[k] + (hi[k] - lo[k]) * (1.4 * urand() - 0.2);
    geom_meshdist *md = NULL;
    assert_int_equal(geom_meshdist_create(pos, nv, tris, nt, NULL, &md, NULL), GEOM_OK);
    double *d = malloc(nq * sizeof *d), *pt = malloc(3 * nq * sizeof *pt), *cd2 = malloc(nq * sizeof *cd2);
    uint32_t *t = malloc(nq * sizeof *t), *ct = malloc(nq * sizeof *ct);
    assert_int_equal(geom_meshdist_closest(md, q, nq, pt, t, NULL, d, 0, NULL), GEOM_OK);
    assert_int_equal(gv_spatial_closest(pos, nv, tris, nt, q, nq, NULL, ct, cd2), GV_SPATIAL_OK);
    double worst = 0;
    size_t other = 0;
    for (size_t i = 0; i < nq; i++) {
        double e = fabs(d[i] - sqrt(cd2[i]));
        if (e > worst)
            worst = e;
        other += t[i] != ct[i];
        if (!(e <= 1e-12 * scale + 1e-15 * offset))
            fail_msg("query %zu: ours %.17g (triangle %u), CGAL %.17g (triangle %u)", i, d[i], t[i],
                     sqrt(cd2[i]), ct[i]);
    }
    print_message("closest point vs CGAL AABB_tree: %zu queries, %zu triangles, max |diff| %.3g,"
                  " %zu on another (equidistant) triangle\n", nq, nt, worst, other);
    geom_meshdist_destroy(md);
    free(q), free(d), free(pt), free(cd2), free(t), free(ct);
}

static void test_soup(void **st)
{
    (void)st;
    for (int off = 0; off < 2; off++) {
        size_t nt = 3000, nv = 3 * nt;
        double *pos = malloc(3 * nv * sizeof *pos);
        uint32_t *tris = malloc(3 * nt * sizeof *tris);
        double o = off ? 1e8 : 0;
        for (size_t i = 0; i < nt; i++) {
            double c[3] = {urand(), urand(), urand()};
            for (int v = 0; v < 3; v++) {
                for (int k = 0; k < 3; k++)
                    pos[3 * (3 * i + v) + k] = o + c[k] + 0.05 * (urand() - 0.5);
                tris[3 * i + v] = (uint32_t)(3 * i + v);
            }
        }
        compare(pos, nv, tris, nt, o, 1.0);
        free(pos);
        free(tris);
    }
}

static void test_bunny(void **st)
{
    (void)st;
    char dir[] = "/tmp/geom-bunny-XXXXXX";
    if (!mkdtemp(dir))
        skip();
    char cmd[512];
    snprintf(cmd, sizeof cmd,
             "tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C %s --wildcards '*bunny00.off' "
             "2>/dev/null", dir);
    if (system(cmd) != 0) {
        print_message("libcgal-demo's data.tar.gz not found: bunny skipped\n");
        skip();
    }
    char path[600];
    snprintf(path, sizeof path, "%s/data/meshes/bunny00.off", dir);
    geom_mesh *m = NULL;
    assert_int_equal(geom_meshio_read(path, NULL, &m, NULL, NULL), GEOM_OK);
    size_t ni = 0;
    assert_int_equal(geom_mesh_triangulate(m, NULL), GEOM_OK);
    geom_mesh_to_soup(m, NULL, NULL, &ni);
    uint32_t *tris = malloc(ni * sizeof *tris), *sizes = malloc(geom_mesh_n_live_faces(m) * sizeof *sizes);
    geom_mesh_to_soup(m, sizes, tris, &ni);
    compare(geom_mesh_cpositions(m), geom_mesh_n_vertices(m), tris, ni / 3, 0, 1.0);
    free(tris);
    free(sizes);
    geom_mesh_destroy(m);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        print_message("could not remove %s\n", dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_soup),
        cmocka_unit_test(test_bunny),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
