/* step module: stiff cases, each a STEP file written here and checked
 * against closed forms: a plane face with 64 circular holes (area
 * L^2 - n pi r^2, n + 1 boundary loops), two holes a hair apart (near-
 * tangent trims), a rational B-spline quarter cylinder whose weights are
 * scaled by 1e-3 and 1e3 (the same surface: area pi/2 r h), and the
 * model translated by 1e6 (the same answers). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/step.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct w {
    char *s;
    size_t n, cap;
    int id;
} w;

static int put(w *o, const char *fmt, ...)
{
    va_list ap;
    char line[1024];
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    size_t l = strlen(line);
    if (o->n + l + 64 > o->cap) {
        o->cap = 2 * (o->n + l + 64);
        o->s = realloc(o->s, o->cap);
    }
    int id = ++o->id;
    o->n += (size_t)sprintf(o->s + o->n, "#%d=%s;\n", id, line);
    return id;
}

static void begin(w *o)
{
    memset(o, 0, sizeof *o);
    o->cap = 1 << 16;
    o->s = malloc(o->cap);
    o->n = (size_t)sprintf(o->s, "ISO-10303-21;\nHEADER;\nFILE_NAME('stiff',$);\nENDSEC;\nDATA;\n");
}

/* The face in a shell-based surface model with millimetre units. */
static void end(w *o, int face)
{
    int sh = put(o, "OPEN_SHELL('',(#%d))", face);
    int sb = put(o, "SHELL_BASED_SURFACE_MODEL('',(#%d))", sh);
    int u1 = put(o, "(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
    int u2 = put(o, "(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
    int cx = put(o, "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#%d,#%d))"
                    "REPRESENTATION_CONTEXT('',''))", u1, u2);
    put(o, "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#%d),#%d)", sb, cx);
    o->n += (size_t)sprintf(o->s + o->n, "ENDSEC;\nEND-ISO-10303-21;\n");
}

static int pt(w *o, double x, double y, double z)
{
    return put(o, "CARTESIAN_POINT('',(%.17g,%.17g,%.17g))", x, y, z);
}

static int frame(w *o, double x, double y, double z)
{
    int p = pt(o, x, y, z);
    int a = put(o, "DIRECTION('',(0.,0.,1.))");
    int r = put(o, "DIRECTION('',(1.,0.,0.))");
    return put(o, "AXIS2_PLACEMENT_3D('',#%d,#%d,#%d)", p, a, r);
}

/* A line edge from vertex a (at pa) to b (at pb). */
static int line_edge(w *o, int a, int b, const double *pa, const double *pb)
{
    double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    int p = pt(o, pa[0], pa[1], pa[2]);
    int dir = put(o, "DIRECTION('',(%.17g,%.17g,%.17g))", d[0] / l, d[1] / l, d[2] / l);
    int v = put(o, "VECTOR('',#%d,%.17g)", dir, l);
    int ln = put(o, "LINE('',#%d,#%d)", p, v);
    return put(o, "EDGE_CURVE('',#%d,#%d,#%d,.T.)", a, b, ln);
}

static int vtx(w *o, const double *p)
{
    return put(o, "VERTEX_POINT('',#%d)", pt(o, p[0], p[1], p[2]));
}

/* A square [0,L]^2 at offset off with holes (cx, cy, r). */
static char *plate(double L, const double *holes, int nh, double off, size_t *len)
{
    w o;
    begin(&o);
    int fr = frame(&o, off, off, 0);
    int plane = put(&o, "PLANE('',#%d)", fr);
    double c[4][3] = {{off, off, 0}, {off + L, off, 0}, {off + L, off + L, 0}, {off, off + L, 0}};
    int v[4], e[4], oe[4];
    for (int k = 0; k < 4; k++)
        v[k] = vtx(&o, c[k]);
    for (int k = 0; k < 4; k++) {
        e[k] = line_edge(&o, v[k], v[(k + 1) % 4], c[k], c[(k + 1) % 4]);
        oe[k] = put(&o, "ORIENTED_EDGE('',*,*,#%d,.T.)", e[k]);
    }
    int lp = put(&o, "EDGE_LOOP('',(#%d,#%d,#%d,#%d))", oe[0], oe[1], oe[2], oe[3]);
    int outer = put(&o, "FACE_OUTER_BOUND('',#%d,.T.)", lp);
    char *bounds = malloc(16 * (size_t)(nh + 2));
    int bn = sprintf(bounds, "#%d", outer);
    for (int h = 0; h < nh; h++) {
        double x = off + holes[3 * h], y = off + holes[3 * h + 1], r = holes[3 * h + 2];
        int hf = frame(&o, x, y, 0);
        int circ = put(&o, "CIRCLE('',#%d,%.17g)", hf, r);
        double p[3] = {x + r, y, 0};
        int hv = vtx(&o, p);
        int he = put(&o, "EDGE_CURVE('',#%d,#%d,#%d,.T.)", hv, hv, circ);
        int ho = put(&o, "ORIENTED_EDGE('',*,*,#%d,.F.)", he);
        int hl = put(&o, "EDGE_LOOP('',(#%d))", ho);
        int hb = put(&o, "FACE_BOUND('',#%d,.T.)", hl);
        bn += sprintf(bounds + bn, ",#%d", hb);
    }
    int face = put(&o, "ADVANCED_FACE('',(%s),#%d,.T.)", bounds, plane);
    free(bounds);
    end(&o, face);
    *len = o.n;
    return o.s;
}

static void tessellate(const char *text, size_t len, double tol, double *area, size_t *loops,
                       double *err)
{
    geom_brep *b = NULL;
    geom_diag d;
    geom_status st = geom_step_read_memory(text, len, "stiff.step", NULL, &b, &d);
    if (st)
        fprintf(stderr, "%s:%zu:%zu: %s\n", d.source, d.line, d.column, d.message);
    assert_int_equal(st, GEOM_OK);
    assert_int_equal((int)b->nissues, 0);
    geom_mesh *m = geom_mesh_create(NULL);
    geom_brep_tess_options opt;
    memset(&opt, 0, sizeof opt);
    opt.tolerance = tol;
    geom_error_report rep;
    geom_brep_tess_stats stats;
    assert_int_equal(geom_step_tessellate(b, &opt, m, &rep, NULL, &stats, &d), GEOM_OK);
    assert_int_equal((int)stats.faces_failed, 0);
    assert_int_equal((int)stats.nonmanifold_edges, 0);
    *err = rep.max_error;
    const double *P = geom_mesh_cpositions(m);
    double A = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++) {
        uint32_t h = geom_mesh_face_he(m, f);
        const double *x = P + 3 * geom_mesh_he_vertex(m, h);
        h = geom_mesh_he_next(m, h);
        const double *y = P + 3 * geom_mesh_he_vertex(m, h);
        h = geom_mesh_he_next(m, h);
        const double *z = P + 3 * geom_mesh_he_vertex(m, h);
        double u[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, v[3] = {z[0] - x[0], z[1] - x[1], z[2] - x[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        A += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    *area = A;
    assert_int_equal(geom_mesh_boundary_loops(m, loops, NULL), GEOM_OK);
    geom_mesh_destroy(m);
    geom_step_destroy(b);
}

static void test_many_holes(void **state)
{
    (void)state;
    enum { N = 8 };
    double holes[3 * N * N];
    double L = 100, r = 2.5, tol = 2e-3;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            holes[3 * (i * N + j)] = (i + 0.5) * L / N;
            holes[3 * (i * N + j) + 1] = (j + 0.5) * L / N;
            holes[3 * (i * N + j) + 2] = r;
        }
    for (int t = 0; t < 2; t++) {
        double off = t ? 1e6 : 0; /* far from the origin: the same answer */
        size_t len, loops;
        char *s = plate(L, holes, N * N, off, &len);
        double A, err;
        tessellate(s, len, tol, &A, &loops, &err);
        free(s);
        double A0 = L * L - N * N * M_PI * r * r;
        /* inscribed hole polygons: the mesh area exceeds A0 by at most
         * the perimeter times the sag */
        assert_true(A >= A0 - 1e-6 * A0);
        assert_true(A - A0 <= N * N * 2 * M_PI * r * tol);
        assert_int_equal((int)loops, N * N + 1);
        assert_true(err <= tol * (1 + 1e-9));
    }
}

static void test_near_tangent_holes(void **state)
{
    (void)state;
    /* two holes 1e-6 apart, and one 1e-6 inside the outer boundary */
    double r = 10, gap = 1e-6;
    double holes[9] = {30, 50, r, 30 + 2 * r + gap, 50, r, 80, 90 - r - gap + 10 - 10, 0};
    holes[6] = 80;
    holes[7] = 100 - 5 - gap;
    holes[8] = 5;
    size_t len, loops;
    char *s = plate(100, holes, 3, 0, &len);
    double A, err;
    tessellate(s, len, 1e-3, &A, &loops, &err);
    free(s);
    double A0 = 100 * 100 - M_PI * (2 * r * r + 25);
    assert_true(A >= A0 - 1e-6 * A0);
    assert_true(A - A0 <= 2 * M_PI * (2 * r + 5) * 1e-3);
    assert_int_equal((int)loops, 4);
}

/* A quarter cylinder (radius R, height H) as a rational B-spline surface,
 * degree (2, 1), weights (1, sqrt2/2, 1) times s, bounded by its four
 * edges (two circular arcs as rational B-spline curves, two lines). */
static char *quarter_cylinder(double R, double H, double s, size_t *len)
{
    w o;
    begin(&o);
    double c = sqrt(0.5);
    double P[3][2][3] = {{{R, 0, 0}, {R, 0, H}}, {{R, R, 0}, {R, R, H}}, {{0, R, 0}, {0, R, H}}};
    int id[3][2];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++)
            id[i][j] = pt(&o, P[i][j][0], P[i][j][1], P[i][j][2]);
    int surf = put(&o,
                   "(BOUNDED_SURFACE()B_SPLINE_SURFACE(2,1,((#%d,#%d),(#%d,#%d),(#%d,#%d)),"
                   ".UNSPECIFIED.,.F.,.F.,.F.)B_SPLINE_SURFACE_WITH_KNOTS((3,3),(2,2),(0.,1.),(0.,1.),"
                   ".UNSPECIFIED.)GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE(((%.17g,%.17g),"
                   "(%.17g,%.17g),(%.17g,%.17g)))REPRESENTATION_ITEM('')SURFACE())",
                   id[0][0], id[0][1], id[1][0], id[1][1], id[2][0], id[2][1], s, s, c * s, c * s, s, s);
    int v[4];
    double corner[4][3] = {{R, 0, 0}, {0, R, 0}, {0, R, H}, {R, 0, H}};
    for (int k = 0; k < 4; k++)
        v[k] = vtx(&o, corner[k]);
    int arc[2];
    for (int j = 0; j < 2; j++)
        arc[j] = put(&o,
                     "(BOUNDED_CURVE()B_SPLINE_CURVE(2,(#%d,#%d,#%d),.CIRCULAR_ARC.,.F.,.F.)"
                     "B_SPLINE_CURVE_WITH_KNOTS((3,3),(0.,1.),.UNSPECIFIED.)CURVE()"
                     "GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE((%.17g,%.17g,%.17g))"
                     "REPRESENTATION_ITEM(''))",
                     id[0][j], id[1][j], id[2][j], s, c * s, s);
    int e0 = put(&o, "EDGE_CURVE('',#%d,#%d,#%d,.T.)", v[0], v[1], arc[0]);
    int e1 = line_edge(&o, v[1], v[2], corner[1], corner[2]);
    int e2 = put(&o, "EDGE_CURVE('',#%d,#%d,#%d,.T.)", v[3], v[2], arc[1]);
    int e3 = line_edge(&o, v[3], v[0], corner[3], corner[0]);
    int o0 = put(&o, "ORIENTED_EDGE('',*,*,#%d,.T.)", e0);
    int o1 = put(&o, "ORIENTED_EDGE('',*,*,#%d,.T.)", e1);
    int o2 = put(&o, "ORIENTED_EDGE('',*,*,#%d,.F.)", e2);
    int o3 = put(&o, "ORIENTED_EDGE('',*,*,#%d,.T.)", e3);
    int lp = put(&o, "EDGE_LOOP('',(#%d,#%d,#%d,#%d))", o0, o1, o2, o3);
    int fb = put(&o, "FACE_OUTER_BOUND('',#%d,.T.)", lp);
    int face = put(&o, "ADVANCED_FACE('',(#%d),#%d,.T.)", fb, surf);
    end(&o, face);
    *len = o.n;
    return o.s;
}

static void test_rational_weights(void **state)
{
    (void)state;
    double R = 20, H = 10, tol = 1e-3;
    double A0 = M_PI / 2 * R * H;
    double scales[3] = {1e-3, 1, 1e3};
    for (int k = 0; k < 3; k++) {
        size_t len, loops;
        char *s = quarter_cylinder(R, H, scales[k], &len);
        double A, err;
        tessellate(s, len, tol, &A, &loops, &err);
        free(s);
        /* inscribed in the cylinder: short of A0 by O(tol / R) */
        assert_true(A <= A0 * (1 + 1e-12));
        assert_true(A0 - A <= 2 * tol / R * A0);
        assert_int_equal((int)loops, 1);
        assert_true(err <= tol * (1 + 1e-9));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_many_holes),
        cmocka_unit_test(test_near_tangent_holes),
        cmocka_unit_test(test_rational_weights),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
