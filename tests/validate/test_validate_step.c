/*
 * STEP tessellations checked by CGAL (gv_soup_check): every part of
 * data/sphere.step, data/cylinder_noseam.step and, when Debian's gmsh-doc
 * is installed, its STEP files (as1-tu-203: an 18-solid assembly;
 * component8: B-spline faces; step_boundary_colors), tessellated by
 * geom_step_tessellate at 1e-4 of the model's diagonal, must be a polygon
 * mesh as given (every edge used twice, in opposite directions), valid
 * (CGAL::is_valid_polygon_mesh), closed (CGAL::is_closed), with one
 * connected component per solid; and each solid alone (an assembly's solids
 * touch each other) the same and free of self-intersections
 * (PMP::does_self_intersect). The genus CGAL counts is checked where the
 * part's topology is known (the sphere, the cylinder, the box: 0).
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

#ifdef GEOM_HAVE_ZLIB
#include <zlib.h>
#endif

#include "geom/step.h"
#include "validate/geom_validate.h"

/* The whole file (gzip-compressed when the name ends in .gz), NUL-terminated. */
static char *slurp(const char *path, size_t *n)
{
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap + 1);
    if (!buf)
        return NULL;
#ifdef GEOM_HAVE_ZLIB
    gzFile f = gzopen(path, "rb");
    if (!f) {
        free(buf);
        return NULL;
    }
    int r;
    while ((r = gzread(f, buf + len, (unsigned)(cap - len))) > 0) {
        len += (size_t)r;
        if (len == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
        }
    }
    gzclose(f);
#else
    if (strlen(path) > 3 && !strcmp(path + strlen(path) - 3, ".gz")) {
        free(buf);
        return NULL;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        free(buf);
        return NULL;
    }
    size_t r;
    while ((r = fread(buf + len, 1, cap - len, f)) > 0) {
        len += r;
        if (len == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
        }
    }
    fclose(f);
#endif
    buf[len] = 0;
    *n = len;
    return buf;
}

/* Tessellate the part at path and check the mesh with CGAL; 0 if the file
 * is absent (gmsh-doc not installed). genus: expected sum over solids. */
static int check_part(const char *path, long long genus)
{
    size_t n;
    char *text = slurp(path, &n);
    if (!text) {
        printf("skipped (absent or no zlib): %s\n", path);
        return 0;
    }
    geom_brep *b = NULL;
    geom_diag d;
    assert_int_equal(geom_step_read_memory(text, n, path, NULL, &b, &d), GEOM_OK);
    free(text);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 0; k < b->nvertices; k++)
        for (int j = 0; j < 3; j++) {
            lo[j] = fmin(lo[j], b->vertices[k].p[j]);
            hi[j] = fmax(hi[j], b->vertices[k].p[j]);
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    geom_mesh *m = geom_mesh_create(NULL);
    geom_brep_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 1e-4 * diag;
    o.attributes = GEOM_SURFACE_ATTR_SOURCE;
    long long genus_sum = 0;
    geom_error_report rep;
    geom_brep_tess_stats st;
    assert_int_equal(geom_step_tessellate(b, &o, m, &rep, NULL, &st, &d), GEOM_OK);
    assert_int_equal((int)st.faces_failed, 0);
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    uint32_t ch = geom_mesh_channel_find(m, "face", GEOM_MESH_DOMAIN_FACE);
    assert_true(ch != GEOM_INVALID_INDEX);
    const double *src = geom_mesh_channel_data(m, ch);
    uint32_t *sizes = malloc(nf * sizeof *sizes), *idx = malloc(3 * nf * sizeof *idx);
    uint32_t *map = malloc(nv * sizeof *map);
    double *xyz = malloc(3 * nv * sizeof *xyz);
    assert_non_null(sizes);
    assert_non_null(idx);
    assert_non_null(map);
    assert_non_null(xyz);
    const double *P = geom_mesh_cpositions(m);
    /* the whole mesh: a polygon mesh, valid, closed, one component per
     * solid; then each solid alone (the solids of an assembly touch one
     * another: a bolt in its hole) for self-intersections and genus */
    for (long s = -1; s < (long)b->nsolids; s++) {
        size_t n = 0, k = 0;
        for (size_t v = 0; v < nv; v++)
            map[v] = GEOM_INVALID_INDEX;
        for (uint32_t f = 0; f < nf; f++) {
            const geom_brep_face *bf = &b->faces[(uint32_t)src[f]];
            if (s >= 0 && b->shells[bf->shell].solid != (uint32_t)s)
                continue;
            uint32_t h = geom_mesh_face_he(m, f);
            sizes[k++] = 3;
            for (int c = 0; c < 3; c++, h = geom_mesh_he_next(m, h)) {
                uint32_t v = geom_mesh_he_vertex(m, h);
                if (map[v] == GEOM_INVALID_INDEX) {
                    map[v] = (uint32_t)n;
                    memcpy(xyz + 3 * n, P + 3 * (size_t)v, 3 * sizeof(double));
                    n++;
                }
                idx[3 * (k - 1) + (size_t)c] = map[v];
            }
        }
        gv_soup_info info;
        assert_int_equal(gv_soup_check(n, xyz, k, sizes, idx, &info), GV_OK);
        if (s < 0) {
            printf("%s: %zu solids, %zu triangles: polygon mesh %d, valid %d, closed %d, components %zu\n",
                   path, b->nsolids, nf, info.is_polygon_soup_a_polygon_mesh, info.valid, info.closed,
                   info.components);
            assert_int_equal((int)info.components, (int)b->nsolids);
            genus_sum = 0;
        } else {
            if (info.self_intersecting || b->nsolids > 1)
                printf("  solid %ld: %zu triangles, genus %lld, self-intersecting %d\n", s, k, info.genus,
                       info.self_intersecting);
            assert_int_equal(info.self_intersecting, 0);
            assert_int_equal((int)info.components, 1);
            genus_sum += info.genus;
        }
        assert_int_equal(info.is_polygon_soup_a_polygon_mesh, 1);
        assert_int_equal(info.valid, 1);
        assert_int_equal(info.closed, 1);
        assert_int_equal(info.border_cycles, 0);
    }
    printf("  genus (sum over solids) %lld\n", genus_sum);
    if (genus >= 0)
        assert_int_equal((int)genus_sum, (int)genus);
    free(map);
    free(xyz);
    free(sizes);
    free(idx);
    geom_mesh_destroy(m);
    geom_step_destroy(b);
    return 1;
}

static void test_parts(void **state)
{
    (void)state;
    const char *dir = getenv("GEOM_TEST_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/sphere.step", dir ? dir : "data");
    assert_int_equal(check_part(path, 0), 1);
    snprintf(path, sizeof path, "%s/cylinder_noseam.step", dir ? dir : "data");
    assert_int_equal(check_part(path, 0), 1);
    /* gmsh-doc's parts (genus: -1 = not asserted, the assembly's solids
     * have through holes; the other two are checked against their known
     * topology: component8 has four through holes and step_boundary_colors
     * is a box) */
    const char *doc = "/usr/share/doc/gmsh-doc/doc/gmsh/demos";
    snprintf(path, sizeof path, "%s/boolean/component8.step.gz", doc);
    check_part(path, -1);
    snprintf(path, sizeof path, "%s/api/step_boundary_colors.stp.gz", doc);
    check_part(path, 0);
    snprintf(path, sizeof path, "%s/boolean/as1-tu-203.stp.gz", doc);
    check_part(path, -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
