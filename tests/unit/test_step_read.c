/* step module: the Part 21 parser (escapes, complex instances, errors with
 * line and column, dangling references, limits), units (mm and inch), the
 * watertight tessellation of a sphere (data/sphere.step: one face, a seam
 * used twice, two poles) against the closed forms 4 pi r^2 and 4/3 pi r^3,
 * of a cylinder whose side is bounded by two circles and no seam edge
 * (data/cylinder_noseam.step) against 2 pi r (r + h) and pi r^2 h, and that
 * cylinder placed by CARTESIAN_TRANSFORMATION_OPERATOR_3D (rotated, scaled,
 * moved, mirrored) against the transformed closed forms and centroid. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/step.h"

#include <math.h>
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *slurp(const char *name, size_t *n)
{
    const char *dir = getenv("GEOM_TEST_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir ? dir : "data", name);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = malloc(1 << 20);
    *n = fread(buf, 1, (1 << 20) - 1, f);
    buf[*n] = 0;
    fclose(f);
    return buf;
}

/* Area, enclosed volume and volume centroid of a triangle mesh. */
static void area_volume(const geom_mesh *m, double *A, double *V, double c[3])
{
    const double *P = geom_mesh_cpositions(m);
    *A = *V = c[0] = c[1] = c[2] = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++) {
        uint32_t h = geom_mesh_face_he(m, f);
        const double *x = P + 3 * geom_mesh_he_vertex(m, h);
        h = geom_mesh_he_next(m, h);
        const double *y = P + 3 * geom_mesh_he_vertex(m, h);
        h = geom_mesh_he_next(m, h);
        const double *z = P + 3 * geom_mesh_he_vertex(m, h);
        double u[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, v[3] = {z[0] - x[0], z[1] - x[1], z[2] - x[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        *A += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double w = (x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0]) +
                    x[2] * (y[0] * z[1] - y[1] * z[0])) / 6;
        *V += w;
        for (int k = 0; k < 3; k++)
            c[k] += w * (x[k] + y[k] + z[k]) / 4;
    }
    for (int k = 0; k < 3; k++)
        c[k] /= *V;
}

/* Area, volume and volume centroid of the tessellation of text at tol;
 * checks it is one closed, manifold solid within the tolerance. */
static void tess_measure(const char *text, size_t n, double tol, double *A, double *V, double c[3])
{
    geom_brep *b = NULL;
    geom_diag d;
    assert_int_equal(geom_step_read_memory(text, n, "t.step", NULL, &b, &d), GEOM_OK);
    assert_int_equal((int)b->nissues, 0);
    assert_int_equal((int)b->nsolids, 1);
    geom_mesh *m = geom_mesh_create(NULL);
    geom_brep_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    geom_error_report rep;
    geom_brep_tess_stats st;
    assert_int_equal(geom_step_tessellate(b, &o, m, &rep, NULL, &st, &d), GEOM_OK);
    assert_int_equal((int)st.faces_failed, 0);
    assert_int_equal((int)st.open_edges, 0); /* closed */
    assert_int_equal((int)st.nonmanifold_edges, 0);
    assert_true(rep.max_error <= tol * 1.0001);
    area_volume(m, A, V, c);
    geom_mesh_destroy(m);
    geom_step_destroy(b);
}

static void check_sphere(const char *text, size_t n, double r, double tol)
{
    geom_brep *b = NULL;
    geom_diag d;
    assert_int_equal(geom_step_read_memory(text, n, "sphere.step", NULL, &b, &d), GEOM_OK);
    assert_int_equal((int)b->nfaces, 1);
    assert_int_equal(b->surfaces[0].type, GEOM_BREP_SURFACE_SPHERE);
    assert_true(fabs(b->surfaces[0].r1 - r) <= 1e-12 * r);
    geom_step_destroy(b);
    double A, V, c[3];
    tess_measure(text, n, tol, &A, &V, c);
    double A0 = 4 * M_PI * r * r, V0 = 4.0 / 3 * M_PI * r * r * r;
    /* inscribed within tol: the area and volume fall short by O(tol / r) */
    assert_true(A < A0 && A0 - A <= 2 * tol / r * A0);
    assert_true(V > 0 && V < V0 && V0 - V <= 3 * tol / r * V0); /* outward normals */
}

/* The cylinder of radius r and height h tessellated from text: area, volume
 * and centroid (cx, cy, cz) against the closed forms. */
static void check_cylinder(const char *text, size_t n, double r, double h, const double c0[3])
{
    double tol = 1e-3, A, V, c[3];
    tess_measure(text, n, tol, &A, &V, c);
    double A0 = 2 * M_PI * r * (r + h), V0 = M_PI * r * r * h;
    /* inscribed polygons within tol: short by O(tol / r), not more */
    assert_true(A < A0 && A0 - A <= 2 * tol / r * A0);
    assert_true(V > 0 && V < V0 && V0 - V <= 2 * tol / r * V0); /* outward, mirrored or not */
    for (int k = 0; k < 3; k++)
        assert_true(fabs(c[k] - c0[k]) < 1e-6);
}

/* The side of the cylinder is one periodic face between two circles with no
 * seam edge: meshed through an added seam, closed with the two caps. */
static void test_cylinder_noseam(void **state)
{
    (void)state;
    size_t n;
    char *t = slurp("cylinder_noseam.step", &n);
    assert_non_null(t);
    const double c0[3] = {0, 0, 5};
    check_cylinder(t, n, 5, 10, c0);
    free(t);
}

/* The cylinder placed through a MAPPED_ITEM whose target is a cartesian
 * transformation operator: axis1, axis2, axis3, local origin and scale. */
static void check_operator(const char *op, double s, double cx, double cy, double cz)
{
    size_t n;
    char *t = slurp("cylinder_noseam.step", &n);
    assert_non_null(t);
    const char *tail = "ENDSEC;\nEND-ISO-10303-21;";
    char *at = strstr(t, tail);
    assert_non_null(at);
    char extra[2048];
    snprintf(extra, sizeof extra,
             "#100=DIRECTION('',(0.,1.,0.));\n#101=DIRECTION('',(-1.,0.,0.));\n"
             "#102=DIRECTION('',(0.,0.,1.));\n#103=CARTESIAN_POINT('',(100.,0.,0.));\n"
             "#104=DIRECTION('',(1.,0.,0.));\n%s\n"
             "#106=REPRESENTATION_MAP(#4,#38);\n#107=MAPPED_ITEM('',#106,#105);\n"
             "#108=SHAPE_REPRESENTATION('',(#107,#4),#37);\n%s",
             op, tail);
    size_t pre = (size_t)(at - t);
    char *u = malloc(pre + strlen(extra) + 1);
    memcpy(u, t, pre);
    strcpy(u + pre, extra);
    const double c0[3] = {cx, cy, cz};
    check_cylinder(u, strlen(u), 5 * s, 10 * s, c0);
    free(u);
    free(t);
}

static void test_transformation_operator(void **state)
{
    (void)state;
    /* 90 degrees about z, scale 2, moved to (100, 0, 0): axis along z */
    check_operator("#105=CARTESIAN_TRANSFORMATION_OPERATOR_3D('',#100,#101,#103,2.,#102);", 2, 100, 0, 10);
    /* the same with both labels of the supertypes, as some writers give */
    check_operator("#105=CARTESIAN_TRANSFORMATION_OPERATOR_3D('','',$,#100,#101,#103,2.,#102);", 2, 100, 0,
                   10);
    /* axis3 along x (the cylinder's axis becomes x), axis1 defaulted, no scale */
    check_operator("#105=CARTESIAN_TRANSFORMATION_OPERATOR_3D('',$,$,#103,$,#104);", 1, 105, 0, 0);
    /* a mirror: axis2 = +x after axis1 = +y (left-handed), scale 0.5 */
    check_operator("#105=CARTESIAN_TRANSFORMATION_OPERATOR_3D('',#100,#104,#103,0.5,#102);", 0.5, 100, 0,
                   2.5);
    /* the complex-instance form */
    check_operator("#105=(CARTESIAN_TRANSFORMATION_OPERATOR(#100,#101,#103,2.)"
                   "CARTESIAN_TRANSFORMATION_OPERATOR_3D(#102)FUNCTIONALLY_DEFINED_TRANSFORMATION('','')"
                   "GEOMETRIC_REPRESENTATION_ITEM()REPRESENTATION_ITEM(''));",
                   2, 100, 0, 10);
}

static void test_sphere_mm(void **state)
{
    (void)state;
    size_t n;
    char *t = slurp("sphere.step", &n);
    assert_non_null(t);
    check_sphere(t, n, 10.0, 2e-3);
    free(t);
}

static void test_sphere_inch(void **state)
{
    (void)state;
    size_t n;
    char *t = slurp("sphere.step", &n);
    assert_non_null(t);
    /* the same file in inches: radius 10 in = 254 mm */
    const char *mm = "#21=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));";
    char *at = strstr(t, mm);
    assert_non_null(at);
    const char *inch = "#21=(CONVERSION_BASED_UNIT('INCH',#25)LENGTH_UNIT()NAMED_UNIT(#26));\n"
                       "#25=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#27);\n"
                       "#26=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n"
                       "#27=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));";
    size_t pre = (size_t)(at - t), post = n - pre - strlen(mm);
    char *u = malloc(n + strlen(inch) + 1);
    memcpy(u, t, pre);
    memcpy(u + pre, inch, strlen(inch));
    memcpy(u + pre + strlen(inch), at + strlen(mm), post);
    check_sphere(u, pre + strlen(inch) + post, 254.0, 0.0508);
    free(u);
    free(t);
}

static geom_status read_text(const char *text, geom_diag *d, geom_brep **b)
{
    *b = NULL;
    return geom_step_read_memory(text, strlen(text), "t.step", NULL, b, d);
}

#define HEAD "ISO-10303-21;\nHEADER;\nFILE_NAME('a''b',$);\nENDSEC;\nDATA;\n"
#define TAIL "ENDSEC;\nEND-ISO-10303-21;\n"

/* geom_step_tess_estimate before the work against the triangles made:
 * the sphere (one face, a seam and two poles) and the seamless cylinder
 * within a factor 2 at every tolerance, per face summing to the total;
 * bad arguments refused. */
static void test_tess_estimate(void **state)
{
    (void)state;
    static const char *files[2] = {"sphere.step", "cylinder_noseam.step"};
    for (int k = 0; k < 2; k++) {
        size_t n;
        char *t = slurp(files[k], &n);
        assert_non_null(t);
        geom_brep *b = NULL;
        assert_int_equal(geom_step_read_memory(t, n, files[k], NULL, &b, NULL), GEOM_OK);
        free(t);
        for (double tol = 0; tol >= 0; tol = tol == 0 ? 0.5 : tol > 2e-3 ? tol / 4 : -1) {
            geom_brep_tess_options o;
            memset(&o, 0, sizeof o);
            o.tolerance = tol;
            double est = -1, *pf = calloc(b->nfaces, sizeof *pf), sum = 0;
            assert_int_equal(geom_step_tess_estimate(b, &o, &est, pf), GEOM_OK);
            for (size_t f = 0; f < b->nfaces; f++)
                sum += pf[f];
            assert_true(fabs(sum - est) <= 1e-9 * est);
            free(pf);
            geom_mesh *m = geom_mesh_create(NULL);
            geom_brep_tess_stats st;
            assert_int_equal(geom_step_tessellate(b, &o, m, NULL, NULL, &st, NULL), GEOM_OK);
            double ratio = est / (double)st.triangles;
            if (!(ratio >= 0.5 && ratio <= 2.0))
                fail_msg("%s tol %g: estimate %g, made %zu", files[k], tol, est, st.triangles);
            geom_mesh_destroy(m);
        }
        double e;
        assert_int_equal(geom_step_tess_estimate(b, NULL, NULL, NULL), GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_step_tess_estimate(NULL, NULL, &e, NULL), GEOM_ERR_INVALID_ARG);
        geom_brep_tess_options bad;
        memset(&bad, 0, sizeof bad);
        bad.tolerance = -1;
        assert_int_equal(geom_step_tess_estimate(b, &bad, &e, NULL), GEOM_ERR_INVALID_ARG);
        bad.tolerance = NAN;
        assert_int_equal(geom_step_tess_estimate(b, &bad, &e, NULL), GEOM_ERR_INVALID_ARG);
        geom_step_destroy(b);
    }
}

static void test_parser(void **state)
{
    (void)state;
    geom_diag d;
    geom_brep *b;
    /* escapes, comments, complex instances, typed parameters, forward refs */
    const char *ok = HEAD "/* c */ #1=FOO('x\\X\\E9\\X2\\00E9\\X0\\\\\\''',#3,.T.,$,*,(1,2.5E-3),LENGTH_MEASURE(2.));\n"
                          "#3=(A()B(#1));\n" TAIL;
    assert_int_equal(read_text(ok, &d, &b), GEOM_OK);
    assert_int_equal((int)b->nfaces, 0);
    geom_step_destroy(b);
    /* a dangling reference is an error naming where it is */
    const char *dang = HEAD "#1=FOO(#3);\n#3=BAR(\n  #99);\n" TAIL;
    assert_int_equal(read_text(dang, &d, &b), GEOM_ERR_PARSE);
    assert_null(b);
    assert_int_equal((int)d.line, 8);
    assert_int_equal((int)d.column, 3);
    assert_non_null(strstr(d.message, "#99"));
    /* malformed input */
    const char *bad[] = {"", "ISO-10303-21;", HEAD "#1=FOO('abc);\n" TAIL, HEAD "#1=FOO(1,,2);\n" TAIL,
                         HEAD "#1=FOO(1);\n#1=BAR(2);\n" TAIL, HEAD "#1=FOO(1.5E);\n" TAIL,
                         HEAD "#1=FOO(.T);\n" TAIL, HEAD "/* open\n" TAIL, HEAD "#1=FOO('\\X2\\00G9\\X0\\');\n" TAIL};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        geom_status st = read_text(bad[k], &d, &b);
        assert_int_equal(st, GEOM_ERR_PARSE);
        assert_null(b);
        assert_true(d.line >= 1 || k == 0);
    }
    /* depth limit */
    char deep[2000];
    strcpy(deep, HEAD "#1=FOO(");
    for (int k = 0; k < 200; k++)
        strcat(deep, "(");
    strcat(deep, ");\n" TAIL);
    assert_int_equal(read_text(deep, &d, &b), GEOM_ERR_LIMIT);
    /* an unsupported surface is reported by id and type, not dropped silently */
    size_t n;
    char *t = slurp("sphere.step", &n);
    assert_non_null(t);
    char *s = strstr(t, "SPHERICAL_SURFACE('',#4,10.)");
    assert_non_null(s);
    memcpy(s, "SPHERICAL_SURFACX", 17);
    assert_int_equal(geom_step_read_memory(t, n, "x.step", NULL, &b, &d), GEOM_OK);
    assert_int_equal((int)b->nfaces, 0);
    assert_int_equal((int)b->nskipped_faces, 1);
    assert_int_equal((int)b->nissues, 1);
    assert_int_equal((int)b->issues[0].entity, 5);
    assert_string_equal(b->issues[0].type, "SPHERICAL_SURFACX");
    geom_step_destroy(b);
    free(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parser),
        cmocka_unit_test(test_sphere_mm),
        cmocka_unit_test(test_sphere_inch),
        cmocka_unit_test(test_cylinder_noseam),
        cmocka_unit_test(test_transformation_operator),
        cmocka_unit_test(test_tess_estimate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
