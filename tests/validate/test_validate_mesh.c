/*
 * Mesh topology against CGAL on real meshes that nobody here made: every
 * OpenSubdiv regression shape (tests/data/osd-shapes), meshes of CGAL's
 * demo data (Debian libcgal-demo: /usr/share/doc/libcgal-dev/data.tar.gz,
 * extracted at test time into a temporary directory under the working
 * directory, i.e. the build tree, and removed afterwards) and assimp's test
 * models (Debian assimp-testmodels: /usr/share/assimp/models, OFF, PLY, OBJ
 * and STL, including non-manifold and degenerate STLs).
 *
 * For each file:
 *  1. the polygon soup is read with geom_meshio_read and keep_orientation
 *     (faces are then never reversed, so the file's soup is recovered
 *     exactly: vertex i < input_vertices is input vertex i, and each face
 *     of the mesh, mapped through geom_mesh_vertex_origin, is the input face
 *     with its vertices in the file's order); faces that use a vertex twice,
 *     or that STL welding made degenerate, cannot be faces of any polygon
 *     mesh (CGAL rejects them too), so when the plain read refuses them the
 *     file is read again with skip_invalid_faces and the table says how many
 *     were dropped ("skip");
 *  2. CGAL (gv_soup_check) checks that soup, and geom_mesh_build builds it
 *     with default options (reorientation and repairs on);
 *  3. the two are compared:
 *     a. when CGAL's is_polygon_soup_a_polygon_mesh accepts the soup, our
 *        build must report no repair (and conversely: a repair is reported
 *        exactly when CGAL rejects the soup), and V, E, F, closedness,
 *        components, boundary loops, Euler characteristic and genus must be
 *        equal; CGAL must find the mesh valid unless it has isolated
 *        vertices (CGAL 5.5 calls those invalid), and geom_mesh_to_soup must
 *        give the input soup back unchanged;
 *     b. when CGAL rejects it, both repair (CGAL: orient_polygon_soup, which
 *        reverses polygons and duplicates singular vertices). Where the
 *        repair strategies coincide -- only reversals and vertex splits,
 *        i.e. our report has no non-manifold edge and no non-orientable
 *        component -- both orient each component like its lowest-numbered
 *        polygon and split vertices into the same fans, so the same
 *        polygons are reversed, the same number of vertex copies is made and
 *        every count above must again be equal ("repaired alike");
 *     c. with edges of more than two faces, the strategies differ in a
 *        documented way (libgeom/src/mesh/build.c, step 4): CGAL cuts every
 *        use of such an edge and rejoins only faces that meet again around
 *        both of its vertices; we glue those same pairs and, per edge, one
 *        more compatible pair when that joins no two vertices twice. So,
 *        when the soup is orientable, the same polygons are reversed, ours
 *        has no more vertices, edges or components than CGAL's, and when
 *        the edge counts agree every count is equal. A non-orientable soup
 *        is cut where each traversal meets the conflict (BFS for us, DFS for
 *        CGAL): only F equal and components (ours <= CGAL's) are checked.
 *        Both results are printed;
 *  4. always: our mesh has no defect for geom_mesh_validate, and OUR mesh
 *     given back to CGAL as a soup (geom_mesh_to_soup) is accepted by
 *     is_polygon_soup_a_polygon_mesh as is and CGAL counts on it the same
 *     V, E, F, closedness, components, boundary loops, Euler characteristic
 *     and genus as geom_mesh_topology_summary (a direct check of the repaired
 *     topology, whatever the repair strategy).
 * Conventions: our components count isolated vertices (as components of
 * genus 0), CGAL's do not, so ours less isolated vertices are compared.
 *
 * A table goes to the log (cmocka's print_message): per file, V and F of the
 * input, dropped faces, our repairs, and ours / CGAL's closed, components,
 * boundaries, Euler characteristic, genus, and CGAL's self-intersection
 * verdict (on the input as CGAL repaired it).
 *
 * When libcgal-demo or assimp-testmodels is not installed, its part is
 * skipped with a message (.ci/deps installs both, so CI runs everything).
 * Under sanitizers, soups of more than SANITIZED_MAX_CGAL_FACES faces are
 * not given to CGAL (see below). Files whose plain read fails and are not
 * used: CGAL's mesh_with_colors.off ('#' comment glued to a number, "0#red"),
 * assimp's Wuson.ply (header line without "comment"), issue623.ply and
 * pond.0.ply (malformed / truncated on purpose), number_formats.obj
 * ("3.1+e2"), invalid.off (index out of range).
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "geom/mesh.h"
#include "geom/meshio.h"
#include "validate/geom_validate.h"

/* Under sanitizers the CGAL part of the shim is built at -O0 (see
 * CMakeLists.txt) and took 38 s (of 52) on the three largest meshes here, so
 * there soups with more than SANITIZED_MAX_CGAL_FACES faces are checked on
 * our side only (read, build, validate, summary; the row says so). */
#if defined(__SANITIZE_ADDRESS__)
#define GV_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
#define GV_SANITIZED 1
#endif
#endif
#ifndef GV_SANITIZED
#define GV_SANITIZED 0
#endif
#define SANITIZED_MAX_CGAL_FACES 20000

#define CGAL_DATA_ARCHIVE "/usr/share/doc/libcgal-dev/data.tar.gz"
#define ASSIMP_MODELS "/usr/share/assimp/models"

/* ------------------------------------------------------------ soups */

typedef struct soup {
    size_t nv, nf, ni;
    double *xyz;
    uint32_t *sizes;
    uint32_t *idx;
} soup;

static void soup_free(soup *s)
{
    free(s->xyz);
    free(s->sizes);
    free(s->idx);
    memset(s, 0, sizeof *s);
}

/* The faces of m as a soup over m's own vertices (positions copied). */
static void mesh_soup(const geom_mesh *m, soup *s)
{
    memset(s, 0, sizeof *s);
    s->nv = geom_mesh_n_vertices(m);
    s->nf = geom_mesh_n_live_faces(m);
    assert_int_equal(geom_mesh_to_soup(m, NULL, NULL, &s->ni), GEOM_OK);
    s->xyz = malloc((s->nv ? s->nv : 1) * 3 * sizeof(double));
    s->sizes = malloc((s->nf ? s->nf : 1) * sizeof(uint32_t));
    s->idx = malloc((s->ni ? s->ni : 1) * sizeof(uint32_t));
    assert_true(s->xyz && s->sizes && s->idx);
    if (s->nv)
        memcpy(s->xyz, geom_mesh_cpositions(m), s->nv * 3 * sizeof(double));
    size_t ni = 0;
    assert_int_equal(geom_mesh_to_soup(m, s->sizes, s->idx, &ni), GEOM_OK);
    assert_int_equal(ni, s->ni);
}

/* What reading a file gave. */
typedef struct readinfo {
    size_t skipped;            /* invalid faces dropped */
    char why[320];             /* the plain read's error when it failed */
} readinfo;

/*
 * The file's soup, exactly (see the header comment): read with
 * keep_orientation, so no face is reversed, and mapped back to input
 * vertices. Returns the status of the read.
 */
static geom_status read_soup(const char *path, soup *s, readinfo *ri)
{
    memset(s, 0, sizeof *s);
    memset(ri, 0, sizeof *ri);
    geom_meshio_read_stats st;
    geom_meshio_read_options o;
    memset(&o, 0, sizeof o);
    o.build.keep_orientation = 1;
    o.stats = &st;
    geom_mesh *m = NULL;
    geom_mesh_build_report rep;
    geom_diag d;
    memset(&d, 0, sizeof d);
    geom_status rc = geom_meshio_read(path, &o, &m, &rep, &d);
    if (rc != GEOM_OK) {
        snprintf(ri->why, sizeof ri->why, "%s: %s", geom_status_str(rc), d.message);
        if (rc == GEOM_ERR_IO || rc == GEOM_ERR_NOMEM)
            return rc;
        o.build.skip_invalid_faces = 1;
        memset(&d, 0, sizeof d);
        rc = geom_meshio_read(path, &o, &m, &rep, &d);
        if (rc != GEOM_OK) {
            print_message("%s: %s %s\n", path, geom_status_str(rc), d.message);
            return rc;
        }
        assert_true(rep.invalid_faces > 0);
    }
    ri->skipped = rep.invalid_faces;
    /* keep_orientation: nothing may have been reversed */
    assert_int_equal(rep.flipped_faces, 0);

    soup ms;
    mesh_soup(m, &ms);
    const uint32_t *vo = geom_mesh_vertex_origin(m);
    assert_non_null(vo);
    const size_t nin = st.input_vertices;
    assert_true(ms.nv >= nin);
    assert_int_equal(ms.nf + rep.invalid_faces, st.input_faces);
    for (size_t v = 0; v < ms.nv; ++v) {
        assert_true(v >= nin || vo[v] == v);
        assert_true(vo[v] < nin);
        /* a copy sits where its original is */
        assert_memory_equal(ms.xyz + 3 * v, ms.xyz + 3 * (size_t)vo[v], 3 * sizeof(double));
    }
    for (size_t i = 0; i < ms.ni; ++i)
        ms.idx[i] = vo[ms.idx[i]];
    ms.nv = nin;
    *s = ms;
    geom_mesh_destroy(m);
    return GEOM_OK;
}

/* ------------------------------------------------------------ comparison */

typedef struct totals {
    int files, as_mesh, same_strategy, differ, skipped_files, failures, cgal_skipped;
    double cgal_seconds, ours_seconds;
} totals;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void print_header(const char *title)
{
    print_message("\n%s\n", title);
    print_message("%-34s %7s %7s %4s %-22s %5s %11s %9s %11s %11s %5s %6s %s\n", "shape", "V",
                  "F", "skip", "our repairs", "clos", "components", "borders", "euler", "genus",
                  "selfX", "cgal", "verdict");
    print_message("%-34s %7s %7s %4s %-22s %5s %11s %9s %11s %11s %5s %6s\n", "", "", "", "", "",
                  "o/c", "ours/cgal", "o/c", "ours/cgal", "ours/cgal", "cgal", "s");
    print_message("(skip: faces dropped on reading; our repairs: flipN faces reversed, nmeN "
                  "non-manifold edges, detN faces detached, splitN+M vertices split into M "
                  "copies, nonorN non-orientable components; components without isolated "
                  "vertices; selfX: CGAL's does_self_intersect)\n");
}

/* A check that counts a failure and prints what differs instead of
 * stopping at the first one, so the table is complete. */
#define EXPECT(cond, ...)                                                                      \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            print_message("  FAIL %s: %s: ", label, #cond);                                    \
            print_message(__VA_ARGS__);                                                        \
            print_message("\n");                                                               \
            bad++;                                                                             \
        }                                                                                      \
    } while (0)

/* Our topology equals CGAL's counts (components less our isolated ones). */
static int same_topology(const char *label, const char *what, const geom_mesh_topology *t,
                         const gv_soup_info *c)
{
    int bad = 0;
    EXPECT(t->vertices == c->vertices, "%s: V %zu vs %zu", what, t->vertices, c->vertices);
    EXPECT(t->edges == c->edges, "%s: E %zu vs %zu", what, t->edges, c->edges);
    EXPECT(t->faces == c->faces, "%s: F %zu vs %zu", what, t->faces, c->faces);
    EXPECT(t->isolated_vertices == c->isolated_vertices, "%s: isolated %zu vs %zu", what,
           t->isolated_vertices, c->isolated_vertices);
    EXPECT((int)t->closed == c->closed, "%s: closed %d vs %d", what, (int)t->closed, c->closed);
    EXPECT(t->components - t->isolated_vertices == c->components, "%s: components %zu vs %zu",
           what, t->components - t->isolated_vertices, c->components);
    EXPECT(t->boundary_loops == c->border_cycles, "%s: boundaries %zu vs %zu", what,
           t->boundary_loops, c->border_cycles);
    EXPECT((long long)t->euler == c->euler_characteristic, "%s: euler %ld vs %lld", what,
           t->euler, c->euler_characteristic);
    EXPECT((long long)t->genus == c->genus, "%s: genus %ld vs %lld", what, t->genus, c->genus);
    return bad;
}

static void repairs_text(const geom_mesh_build_report *r, char *buf, size_t n)
{
    buf[0] = 0;
    size_t k = 0;
    if (r->flipped_faces)
        k += (size_t)snprintf(buf + k, n - k, "flip%zu ", r->flipped_faces);
    if (r->nonmanifold_edges && k < n)
        k += (size_t)snprintf(buf + k, n - k, "nme%zu ", r->nonmanifold_edges);
    if (r->detached_faces && k < n)
        k += (size_t)snprintf(buf + k, n - k, "det%zu ", r->detached_faces);
    if (r->split_vertices && k < n)
        k += (size_t)snprintf(buf + k, n - k, "split%zu+%zu ", r->split_vertices,
                              r->added_vertices);
    if (r->nonorientable_components && k < n)
        k += (size_t)snprintf(buf + k, n - k, "nonor%zu ", r->nonorientable_components);
    if (k == 0)
        snprintf(buf, n, "-");
    else if (k < n)
        buf[k - 1] = 0;
}

/*
 * Compare ours and CGAL's on one file; prints one table row (and the
 * failures). label names it in the table.
 */
static void check_file(const char *label, const char *path, totals *tot)
{
    soup s;
    readinfo ri;
    geom_status rc = read_soup(path, &s, &ri);
    tot->files++;
    if (rc != GEOM_OK) {
        print_message("%-34s read failed: %s\n", label, geom_status_str(rc));
        tot->failures++;
        return;
    }
    if (ri.skipped)
        tot->skipped_files++;
    int bad = 0;

    /* CGAL on the input soup */
    const int use_cgal = !GV_SANITIZED || s.nf <= SANITIZED_MAX_CGAL_FACES;
    gv_soup_info cg;
    memset(&cg, 0, sizeof cg);
    double t0 = now(), cgal_s = 0;
    int gst = use_cgal ? gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, &cg) : GV_OK;
    cgal_s += now() - t0;
    EXPECT(gst == GV_OK, "gv_soup_check %d", gst);

    /* ours, with repairs */
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_mesh_build_report rep;
    t0 = now();
    rc = geom_mesh_build(m, s.nv, s.xyz, s.nf, s.sizes, s.idx, NULL, &rep, NULL);
    assert_int_equal(rc, GEOM_OK);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    size_t ndef = 1;
    assert_int_equal(geom_mesh_validate(m, NULL, 0, &ndef), GEOM_OK);
    tot->ours_seconds += now() - t0;
    EXPECT(ndef == 0, "%zu defects", ndef);
    EXPECT(t.manifold, "summary says not manifold");
    EXPECT(rep.invalid_faces == 0, "invalid faces after skipping %zu", rep.invalid_faces);

    const int repaired = rep.flipped_faces || rep.nonmanifold_edges || rep.detached_faces ||
                         rep.split_vertices || rep.added_vertices ||
                         rep.nonorientable_components;
    const int same_strategy = rep.nonmanifold_edges == 0 && rep.nonorientable_components == 0;
    const char *verdict;
    if (!use_cgal) {
        verdict = "CGAL skipped (sanitizer build)";
        tot->cgal_skipped++;
    } else if (gst == GV_OK) {
        EXPECT(repaired == !cg.is_polygon_soup_a_polygon_mesh,
               "our repairs %d, CGAL accepts the soup %d", repaired,
               cg.is_polygon_soup_a_polygon_mesh);
        EXPECT(t.faces == cg.faces, "F %zu vs %zu", t.faces, cg.faces);
        if (cg.is_polygon_soup_a_polygon_mesh) {
            verdict = "mesh: all equal";
            tot->as_mesh++;
            bad += same_topology(label, "as given", &t, &cg);
            EXPECT(cg.valid == (cg.isolated_vertices == 0), "CGAL valid %d with %zu isolated",
                   cg.valid, cg.isolated_vertices);
            /* nothing repaired: the mesh gives the soup back unchanged */
            soup back;
            mesh_soup(m, &back);
            EXPECT(back.nv == s.nv && back.nf == s.nf && back.ni == s.ni &&
                       memcmp(back.sizes, s.sizes, s.nf * sizeof(uint32_t)) == 0 &&
                       memcmp(back.idx, s.idx, s.ni * sizeof(uint32_t)) == 0,
                   "soup does not round-trip");
            soup_free(&back);
        } else if (same_strategy) {
            verdict = "repaired alike: all equal";
            tot->same_strategy++;
            bad += same_topology(label, "repaired", &t, &cg);
            EXPECT(cg.reversed_faces == rep.flipped_faces, "reversed %zu vs %zu",
                   rep.flipped_faces, cg.reversed_faces);
            EXPECT(cg.duplicated_vertices == rep.added_vertices, "vertex copies %zu vs %zu",
                   rep.added_vertices, cg.duplicated_vertices);
        } else {
            /* Our repair glues a superset of what CGAL's glues: the same
             * orientation (when orientable), every two-face edge, the pairs
             * of an edge with more than two faces whose faces meet around
             * both of its vertices (CGAL rejoins exactly those), and one
             * more compatible pair per such edge where that joins no two
             * vertices twice. So ours has no more vertices, edges or
             * components, and when the edge counts agree, nothing more was
             * glued and everything is equal. */
            tot->differ++;
            if (rep.nonorientable_components == 0) {
                verdict = cg.edges == t.edges ? "edges >2 faces, glued alike: all equal"
                                              : "edges >2 faces, we glue more";
                EXPECT(cg.reversed_faces == rep.flipped_faces, "reversed %zu vs %zu",
                       rep.flipped_faces, cg.reversed_faces);
                EXPECT(t.vertices <= cg.vertices, "V %zu > %zu", t.vertices, cg.vertices);
                EXPECT(t.edges <= cg.edges, "E %zu > %zu", t.edges, cg.edges);
                if (cg.edges == t.edges)
                    bad += same_topology(label, "glued alike", &t, &cg);
            } else {
                verdict = "non-orientable, cut differently";
            }
            EXPECT(t.components - t.isolated_vertices <= cg.components, "components %zu > %zu",
                   t.components - t.isolated_vertices, cg.components);
        }
    } else {
        verdict = "CGAL failed";
    }

    /* our repaired mesh, checked by CGAL as it is */
    if (repaired && use_cgal) {
        soup back;
        mesh_soup(m, &back);
        gv_soup_info co;
        t0 = now();
        gst = gv_soup_check(back.nv, back.xyz, back.nf, back.sizes, back.idx, &co);
        cgal_s += now() - t0;
        EXPECT(gst == GV_OK, "gv_soup_check on ours %d", gst);
        if (gst == GV_OK) {
            EXPECT(co.is_polygon_soup_a_polygon_mesh, "CGAL rejects our repaired mesh");
            bad += same_topology(label, "ours checked by CGAL", &t, &co);
        }
        soup_free(&back);
    }

    char rbuf[64];
    repairs_text(&rep, rbuf, sizeof rbuf);
    char sk[16];
    snprintf(sk, sizeof sk, "%zu", ri.skipped);
    tot->cgal_seconds += cgal_s;
    if (use_cgal)
        print_message("%-34s %7zu %7zu %4s %-22s %2d/%-2d %5zu/%-5zu %4zu/%-4zu %5ld/%-5lld "
                      "%5ld/%-5lld %5d %6.2f %s%s\n",
                      label, s.nv, s.nf + ri.skipped, ri.skipped ? sk : "-", rbuf,
                      (int)t.closed, cg.closed, t.components - t.isolated_vertices,
                      cg.components, t.boundary_loops, cg.border_cycles, t.euler,
                      cg.euler_characteristic, t.genus, cg.genus, cg.self_intersecting, cgal_s,
                      verdict, bad ? "  <-- FAILED" : "");
    else
        print_message("%-34s %7zu %7zu %4s %-22s %2d/-  %5zu/-     %4zu/-    %5ld/-     "
                      "%5ld/-     %5s %6s %s%s\n",
                      label, s.nv, s.nf + ri.skipped, ri.skipped ? sk : "-", rbuf,
                      (int)t.closed, t.components - t.isolated_vertices, t.boundary_loops,
                      t.euler, t.genus, "-", "-", verdict, bad ? "  <-- FAILED" : "");
    if (ri.skipped)
        print_message("%-34s   (plain read: %s)\n", "", ri.why);
    tot->failures += bad;
    geom_mesh_destroy(m);
    soup_free(&s);
}

static void print_totals(const char *what, const totals *t)
{
    print_message("%s: %d files (%d with dropped faces): %d polygon meshes as given, %d repaired "
                  "alike, %d repaired differently, %d not given to CGAL; %d failures; "
                  "CGAL %.2f s, ours %.3f s\n",
                  what, t->files, t->skipped_files, t->as_mesh, t->same_strategy, t->differ,
                  t->cgal_skipped, t->failures, t->cgal_seconds, t->ours_seconds);
}

/* ------------------------------------------------------------ the data */

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static void test_osd_shapes(void **state)
{
    (void)state;
    const char *shared = getenv("GEOM_SHARED_DATA");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/osd-shapes", shared ? shared : "tests/data");
    DIR *d = opendir(dir);
    assert_non_null(d);
    char *names[512];
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d)) && n < 512) {
        size_t len = strlen(e->d_name);
        if (len > 4 && strcmp(e->d_name + len - 4, ".obj") == 0)
            names[n++] = strdup(e->d_name);
    }
    closedir(d);
    qsort(names, n, sizeof names[0], cmp_str);
    totals tot;
    memset(&tot, 0, sizeof tot);
    print_header("OpenSubdiv regression shapes (GEOM_SHARED_DATA/osd-shapes)");
    for (size_t i = 0; i < n; i++) {
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        check_file(names[i], path, &tot);
        free(names[i]);
    }
    print_totals("osd-shapes", &tot);
    assert_true(n >= 100);
    assert_int_equal(tot.failures, 0);
}

/* Meshes of CGAL's demo data, extracted at test time (see group_setup):
 * closed, bounded, polygonal, high genus, many components, reoriented and
 * non-manifold ones, as OFF, STL and PLY. */
static const char *const cgal_meshes[] = {
    "bunny00.off",           /* 75k triangles, closed */
    "refined_elephant.off",  /* 89k triangles, genus 3 */
    "elephant.off",          "fandisk.off", /* sharp creases */
    "mech-holes-shark.off",  /* boundaries */
    "elephant-with-holes.off", "double-torus-example.off", /* polygons, genus 2 */
    "torus_quad.off",        "3torus.off", "mpi.off",
    "polygon_mesh.off",      /* polygons, non-manifold vertices */
    "b9_mesh.off",           /* 47 components */
    "blobby-shuffled.off",   "cube-shuffled.off", /* inconsistent orientation */
    "pig.stl",               /* non-manifold vertices */
    "sphere.ply",
};

/* Genus stated by the file's name (and the data set's description). */
static const struct {
    const char *name;
    long genus;
} cgal_genus[] = {{"double-torus-example.off", 2}, {"torus_quad.off", 1}, {"3torus.off", 3}};

/* assimp's test models: OBJ, OFF, PLY (ASCII and binary) and STL (ASCII and
 * binary), with non-manifold edges (3DSMaxExport: edges with three faces),
 * non-manifold vertices (Wuson, sphereWithHole), faces that welding makes
 * degenerate (Spider), inconsistent orientation (regr_3429812, spider) and a
 * face using a vertex twice (box_longline). */
static const char *const assimp_models[] = {
    "STL/3DSMaxExport.STL", "STL/Spider_ascii.stl",   "STL/Spider_binary.stl",
    "STL/Wuson.stl",        "STL/sphereWithHole.stl", "STL/triangle_with_two_solids.stl",
    "OFF/Wuson.off",        "OFF/Cube.off",           "PLY/cube.ply",
    "PLY/cube_binary.ply",  "PLY/cube_uv.ply",        "OBJ/WusonOBJ.obj",
    "OBJ/spider.obj",       "OBJ/regr01.obj",         "OBJ/regr_3429812.obj",
    "OBJ/box_longline.obj", "OBJ/empty_mat.obj",
};

#define N_CGAL (sizeof cgal_meshes / sizeof cgal_meshes[0])
#define N_ASSIMP (sizeof assimp_models / sizeof assimp_models[0])

/* The temporary directory the CGAL meshes were extracted to ("" when the
 * archive is not installed). */
typedef struct fixture {
    char dir[256];
} fixture;

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Extract the chosen CGAL meshes (one tar run) into a new directory under
 * the working directory, i.e. the build tree when run by ctest. */
static int group_setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    if (!fx)
        return -1;
    *state = fx;
    if (!file_exists(CGAL_DATA_ARCHIVE))
        return 0;
    snprintf(fx->dir, sizeof fx->dir, "validate_mesh_XXXXXX");
    if (!mkdtemp(fx->dir)) {
        fx->dir[0] = 0;
        return -1;
    }
    char cmd[4096];
    size_t k = (size_t)snprintf(cmd, sizeof cmd, "tar -xzf '%s' -C '%s'", CGAL_DATA_ARCHIVE,
                                fx->dir);
    for (size_t i = 0; i < N_CGAL && k < sizeof cmd; ++i)
        k += (size_t)snprintf(cmd + k, sizeof cmd - k, " 'data/meshes/%s'", cgal_meshes[i]);
    if (k >= sizeof cmd || system(cmd) != 0) {
        print_message("could not extract the CGAL meshes: %s\n", cmd);
        return -1;
    }
    return 0;
}

static int group_teardown(void **state)
{
    fixture *fx = *state;
    if (fx && fx->dir[0]) {
        char path[1024];
        for (size_t i = 0; i < N_CGAL; ++i) {
            snprintf(path, sizeof path, "%s/data/meshes/%s", fx->dir, cgal_meshes[i]);
            remove(path);
        }
        snprintf(path, sizeof path, "%s/data/meshes", fx->dir);
        rmdir(path);
        snprintf(path, sizeof path, "%s/data", fx->dir);
        rmdir(path);
        rmdir(fx->dir);
    }
    free(fx);
    return 0;
}

static void test_cgal_demo_meshes(void **state)
{
    const fixture *fx = *state;
    if (!fx->dir[0]) {
        print_message("SKIPPED: " CGAL_DATA_ARCHIVE " not found (install libcgal-demo, "
                      "see .ci/deps)\n");
        skip();
    }
    totals tot;
    memset(&tot, 0, sizeof tot);
    print_header("CGAL demo meshes (libcgal-demo: " CGAL_DATA_ARCHIVE ")");
    for (size_t i = 0; i < N_CGAL; ++i) {
        char path[1024];
        snprintf(path, sizeof path, "%s/data/meshes/%s", fx->dir, cgal_meshes[i]);
        check_file(cgal_meshes[i], path, &tot);
    }
    print_totals("CGAL demo meshes", &tot);
    assert_int_equal(tot.files, (int)N_CGAL);
    assert_int_equal(tot.failures, 0);
    /* both paths of the comparison were taken */
    assert_true(tot.as_mesh + tot.cgal_skipped >= 6);
    assert_true(tot.same_strategy >= 3);

    for (size_t i = 0; i < sizeof cgal_genus / sizeof cgal_genus[0]; ++i) {
        char path[1024];
        snprintf(path, sizeof path, "%s/data/meshes/%s", fx->dir, cgal_genus[i].name);
        geom_mesh *m = NULL;
        assert_int_equal(geom_meshio_read(path, NULL, &m, NULL, NULL), GEOM_OK);
        geom_mesh_topology t;
        assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
        assert_true(t.closed);
        assert_int_equal(t.components, 1);
        assert_int_equal(t.genus, cgal_genus[i].genus);
        geom_mesh_destroy(m);
    }
}

static void test_assimp_models(void **state)
{
    (void)state;
    if (!file_exists(ASSIMP_MODELS "/STL/3DSMaxExport.STL")) {
        print_message("SKIPPED: " ASSIMP_MODELS " not found (install assimp-testmodels, "
                      "see .ci/deps)\n");
        skip();
    }
    totals tot;
    memset(&tot, 0, sizeof tot);
    print_header("assimp test models (assimp-testmodels: " ASSIMP_MODELS ")");
    for (size_t i = 0; i < N_ASSIMP; ++i) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", ASSIMP_MODELS, assimp_models[i]);
        check_file(assimp_models[i], path, &tot);
    }
    print_totals("assimp models", &tot);
    assert_int_equal(tot.files, (int)N_ASSIMP);
    assert_int_equal(tot.failures, 0);
    assert_true(tot.as_mesh >= 6);
    assert_true(tot.same_strategy >= 3);
    assert_true(tot.differ >= 1);      /* 3DSMaxExport.STL */
    assert_true(tot.skipped_files >= 3); /* Spider (x2), box_longline */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_osd_shapes),
        cmocka_unit_test(test_cgal_demo_meshes),
        cmocka_unit_test(test_assimp_models),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
