/*
 * BVH: structure invariants of both builders (every primitive in exactly one
 * leaf, depth-first layout, leaf sizes), conservative and tight boxes checked
 * against the primitive bounds computed here, the same tree for 1, 2 and 4
 * threads, refit against a fresh computation, NaN/Inf and bad indices
 * rejected with the first bad index, empty input, and depth on coincident,
 * exponentially spaced and 1e8-offset inputs.
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

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

typedef struct soup {
    double *pos;
    uint32_t *tris;
    size_t nv, nt;
} soup;

enum { RANDOM, CLUSTERED, COINCIDENT, OFFSET, GRID, EXPONENTIAL };

static soup make_soup(int kind, size_t nt)
{
    soup s;
    s.nt = nt;
    s.nv = 3 * nt;
    s.pos = malloc(3 * s.nv * sizeof *s.pos);
    s.tris = malloc(3 * nt * sizeof *s.tris);
    for (size_t t = 0; t < nt; t++) {
        double c[3];
        for (int k = 0; k < 3; k++) {
            switch (kind) {
            case CLUSTERED: c[k] = (double)(t % 5) * 10.0 + urand() * 1e-3; break;
            case COINCIDENT: c[k] = 0.5; break;
            case OFFSET: c[k] = 1e8 + urand(); break;
            case GRID: c[k] = (double)((t >> (3 * k)) & 7); break;
            case EXPONENTIAL: c[k] = k == 0 ? ldexp(1.0, (int)(t % 900)) : 0.0; break;
            default: c[k] = urand(); break;
            }
        }
        for (int v = 0; v < 3; v++) {
            for (int k = 0; k < 3; k++) {
                double e = kind == COINCIDENT ? 0.0 : kind == GRID ? 0.25 * (v == k) : 0.01 * urand();
                s.pos[3 * (3 * t + v) + k] = c[k] + e;
            }
            s.tris[3 * t + v] = (uint32_t)(3 * t + v);
        }
    }
    return s;
}

static void free_soup(soup *s)
{
    free(s->pos);
    free(s->tris);
}

static geom_aabb tri_box(const soup *s, size_t t)
{
    geom_aabb b = geom_aabb_empty();
    for (int v = 0; v < 3; v++) {
        const double *p = s->pos + 3 * s->tris[3 * t + v];
        b = geom_aabb_extend(b, geom_vec3_make(p[0], p[1], p[2]));
    }
    return b;
}

static int box_in(geom_aabb in, geom_aabb out)
{
    return out.min.x <= in.min.x && out.min.y <= in.min.y && out.min.z <= in.min.z &&
           in.max.x <= out.max.x && in.max.y <= out.max.y && in.max.z <= out.max.z;
}

static int box_eq(geom_aabb a, geom_aabb b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* Walks the tree; returns the depth; checks every invariant. */
static size_t check_node(const geom_bvh_node *nodes, size_t nn, uint32_t i, const uint32_t *prims,
                         const soup *s, unsigned char *seen_node, unsigned *seen_prim,
                         uint32_t max_leaf)
{
    assert_true(i < nn);
    assert_false(seen_node[i]);
    seen_node[i] = 1;
    const geom_bvh_node *nd = &nodes[i];
    if (nd->count) {
        assert_true(nd->count <= max_leaf);
        assert_true((size_t)nd->index + nd->count <= s->nt);
        geom_aabb u = geom_aabb_empty();
        for (uint32_t k = 0; k < nd->count; k++) {
            uint32_t p = prims[nd->index + k];
            assert_true(p < s->nt);
            seen_prim[p]++;
            geom_aabb tb = tri_box(s, p);
            assert_true(box_in(tb, nd->box));
            u = geom_aabb_union(u, tb);
        }
        assert_true(box_eq(u, nd->box)); /* tight */
        return 1;
    }
    assert_true(nd->axis < 3);
    assert_true(nd->index > i + 1 && nd->index < nn);
    const geom_bvh_node *l = &nodes[i + 1], *r = &nodes[nd->index];
    assert_true(box_in(l->box, nd->box));
    assert_true(box_in(r->box, nd->box));
    assert_true(box_eq(geom_aabb_union(l->box, r->box), nd->box));
    size_t dl = check_node(nodes, nn, i + 1, prims, s, seen_node, seen_prim, max_leaf);
    size_t dr = check_node(nodes, nn, nd->index, prims, s, seen_node, seen_prim, max_leaf);
    return 1 + (dl > dr ? dl : dr);
}

static void check_bvh(const geom_bvh *b, const soup *s, uint32_t max_leaf)
{
    size_t nn, np;
    const geom_bvh_node *nodes = geom_bvh_nodes(b, &nn);
    const uint32_t *prims = geom_bvh_prim_indices(b, &np);
    assert_int_equal(np, s->nt);
    if (s->nt == 0) {
        assert_int_equal(nn, 0);
        assert_int_equal(geom_bvh_depth(b), 0);
        return;
    }
    unsigned char *seen_node = calloc(nn, 1);
    unsigned *seen_prim = calloc(s->nt, sizeof *seen_prim);
    size_t depth = check_node(nodes, nn, 0, prims, s, seen_node, seen_prim, max_leaf);
    for (size_t i = 0; i < nn; i++)
        assert_true(seen_node[i]);
    for (size_t i = 0; i < s->nt; i++)
        assert_int_equal(seen_prim[i], 1);
    assert_int_equal(depth, geom_bvh_depth(b));
    assert_true(depth <= 64 + 33);
    assert_true(geom_bvh_bytes(b) >= nn * sizeof *nodes);
    free(seen_node);
    free(seen_prim);
}

static void same_tree(const geom_bvh *a, const geom_bvh *b)
{
    size_t na, nb, pa, pb;
    const geom_bvh_node *x = geom_bvh_nodes(a, &na), *y = geom_bvh_nodes(b, &nb);
    const uint32_t *u = geom_bvh_prim_indices(a, &pa), *v = geom_bvh_prim_indices(b, &pb);
    assert_int_equal(na, nb);
    assert_int_equal(pa, pb);
    assert_true(na == 0 || memcmp(x, y, na * sizeof *x) == 0);
    assert_true(pa == 0 || memcmp(u, v, pa * sizeof *u) == 0);
}

static void run_kind(int kind, size_t nt)
{
    soup s = make_soup(kind, nt);
    for (int m = 0; m < 2; m++) {
        for (uint32_t leaf = 1; leaf <= 8; leaf += 3) {
            geom_bvh *ref = NULL;
            for (int th = 1; th <= 4; th *= 2) {
                geom_bvh_options o = {0};
                o.method = m ? GEOM_BVH_LBVH : GEOM_BVH_SAH;
                o.max_leaf_size = leaf;
                o.threads = th;
                geom_bvh *b = NULL;
                geom_diag d;
                assert_int_equal(geom_bvh_build_triangles(s.pos, s.nv, s.tris, s.nt, &o, &b, &d),
                                 GEOM_OK);
                check_bvh(b, &s, leaf);
                if (ref) {
                    same_tree(ref, b);
                    geom_bvh_destroy(b);
                } else {
                    ref = b;
                }
            }
            geom_bvh_destroy(ref);
        }
    }
    free_soup(&s);
}

static void test_random(void **st) { (void)st; run_kind(RANDOM, 20000); run_kind(RANDOM, 7); run_kind(RANDOM, 1); }
static void test_clustered(void **st) { (void)st; run_kind(CLUSTERED, 10000); }
static void test_coincident(void **st) { (void)st; run_kind(COINCIDENT, 10000); }
static void test_offset(void **st) { (void)st; run_kind(OFFSET, 10000); }
static void test_grid(void **st) { (void)st; run_kind(GRID, 4096); }
static void test_exponential(void **st) { (void)st; run_kind(EXPONENTIAL, 3000); }

static void test_empty(void **st)
{
    (void)st;
    geom_bvh *b = NULL;
    assert_int_equal(geom_bvh_build_triangles(NULL, 0, NULL, 0, NULL, &b, NULL), GEOM_OK);
    soup s = {0};
    check_bvh(b, &s, 4);
    geom_bvh_destroy(b);
    geom_bvh_destroy(NULL);
    assert_int_equal(geom_bvh_depth(NULL), 0);
}

static void test_nan(void **st)
{
    (void)st;
    soup s = make_soup(RANDOM, 100);
    s.pos[3 * s.tris[3 * 37 + 1] + 2] = NAN;
    s.pos[3 * s.tris[3 * 60] + 0] = INFINITY;
    geom_bvh *b = (geom_bvh *)1;
    geom_diag d;
    assert_int_equal(geom_bvh_build_triangles(s.pos, s.nv, s.tris, s.nt, NULL, &b, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_null(b);
    assert_non_null(strstr(d.message, "triangle 37"));
    /* Out-of-range index. */
    s.pos[3 * s.tris[3 * 37 + 1] + 2] = 0;
    s.pos[3 * s.tris[3 * 60] + 0] = 0;
    s.tris[3 * 12 + 2] = (uint32_t)s.nv;
    assert_int_equal(geom_bvh_build_triangles(s.pos, s.nv, s.tris, s.nt, NULL, &b, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "triangle 12"));
    free_soup(&s);

    geom_aabb boxes[5];
    for (int i = 0; i < 5; i++)
        boxes[i] = (geom_aabb){{i, 0, 0}, {i + 1, 1, 1}};
    boxes[3].max.y = NAN;
    assert_int_equal(geom_bvh_build_boxes(boxes, 5, NULL, &b, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "primitive 3"));
    boxes[3].max.y = 1;
    boxes[2].min.x = 5; /* empty box */
    assert_int_equal(geom_bvh_build_boxes(boxes, 5, NULL, &b, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "primitive 2"));
    assert_int_equal(geom_bvh_build_boxes(NULL, 5, NULL, &b, NULL), GEOM_ERR_INVALID_ARG);
    geom_bvh_options o = {0};
    o.bins = 1000;
    boxes[2].min.x = 2;
    assert_int_equal(geom_bvh_build_boxes(boxes, 5, &o, &b, NULL), GEOM_ERR_INVALID_ARG);
}

static void box_cb(void *user, size_t i, geom_aabb *box)
{
    const soup *s = user;
    *box = tri_box(s, i);
}

static void test_boxes_callback(void **st)
{
    (void)st;
    soup s = make_soup(CLUSTERED, 5000);
    geom_aabb *boxes = malloc(s.nt * sizeof *boxes);
    for (size_t i = 0; i < s.nt; i++)
        boxes[i] = tri_box(&s, i);
    for (int m = 0; m < 2; m++) {
        geom_bvh_options o = {0};
        o.method = m ? GEOM_BVH_LBVH : GEOM_BVH_SAH;
        geom_bvh *a = NULL, *b = NULL, *c = NULL;
        assert_int_equal(geom_bvh_build_triangles(s.pos, s.nv, s.tris, s.nt, &o, &a, NULL), GEOM_OK);
        assert_int_equal(geom_bvh_build_boxes(boxes, s.nt, &o, &b, NULL), GEOM_OK);
        assert_int_equal(geom_bvh_build_callback(s.nt, box_cb, &s, &o, &c, NULL), GEOM_OK);
        check_bvh(b, &s, 4);
        same_tree(a, b);
        same_tree(a, c);
        geom_bvh_destroy(a);
        geom_bvh_destroy(b);
        geom_bvh_destroy(c);
    }
    free(boxes);
    free_soup(&s);
}

static void test_refit(void **st)
{
    (void)st;
    soup s = make_soup(RANDOM, 3000);
    for (int m = 0; m < 2; m++) {
        geom_bvh_options o = {0};
        o.method = m ? GEOM_BVH_LBVH : GEOM_BVH_SAH;
        geom_bvh *b = NULL;
        assert_int_equal(geom_bvh_build_triangles(s.pos, s.nv, s.tris, s.nt, &o, &b, NULL), GEOM_OK);
        for (size_t i = 0; i < 3 * s.nv; i++)
            s.pos[i] += 0.3 * sin((double)i);
        assert_int_equal(geom_bvh_refit_triangles(b, s.pos, s.nv, s.tris, s.nt), GEOM_OK);
        check_bvh(b, &s, 4); /* tight and conservative for the moved vertices */
        assert_int_equal(geom_bvh_refit_triangles(b, s.pos, s.nv, s.tris, s.nt - 1),
                         GEOM_ERR_INVALID_ARG);
        double keep = s.pos[5];
        s.pos[5] = NAN;
        assert_int_equal(geom_bvh_refit_triangles(b, s.pos, s.nv, s.tris, s.nt),
                         GEOM_ERR_INVALID_ARG);
        s.pos[5] = keep;
        check_bvh(b, &s, 4); /* unchanged after the failed refit */
        geom_bvh_destroy(b);
    }
    free_soup(&s);
}

static int n_alloc;
static void *my_alloc(void *u, size_t n) { (void)u; n_alloc++; return malloc(n); }
static void my_free(void *u, void *p, size_t n) { (void)u; (void)n; if (p) n_alloc--; free(p); }

static void test_allocator(void **st)
{
    (void)st;
    soup s = make_soup(RANDOM, 2000);
    geom_allocator al = {my_alloc, NULL, my_free, NULL};
    for (int m = 0; m < 2; m++) {
        geom_bvh_options o = {0};
        o.method = m ? GEOM_BVH_LBVH : GEOM_BVH_SAH;
        o.alloc = &al;
        geom_bvh *b = NULL;
        assert_int_equal(geom_bvh_build_triangles(s.pos, s.nv, s.tris, s.nt, &o, &b, NULL), GEOM_OK);
        assert_true(n_alloc > 0);
        geom_bvh_destroy(b);
        assert_int_equal(n_alloc, 0);
    }
    free_soup(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random),      cmocka_unit_test(test_clustered),
        cmocka_unit_test(test_coincident),  cmocka_unit_test(test_offset),
        cmocka_unit_test(test_grid),        cmocka_unit_test(test_exponential),
        cmocka_unit_test(test_empty),       cmocka_unit_test(test_nan),
        cmocka_unit_test(test_boxes_callback), cmocka_unit_test(test_refit),
        cmocka_unit_test(test_allocator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
