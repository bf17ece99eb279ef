/*
 * bench_render: geom_scene_render (Whitted ray tracing, one thread) against
 * POV-Ray 3.7 (Debian povray, +WT1) on the same scenes in the same run:
 * spheres and a plane, a box, a torus, a CSG part, and a 75k-triangle mesh
 * (CGAL's bunny00.off from Debian libcgal-demo), 320x240, the same camera,
 * lights and Phong materials written as a .pov file, shadows and mirror
 * reflection on. For each scene and each antialiasing setting (none; 4 rays
 * a pixel: our regular 2x2 grid, POV-Ray's +A0.0 +AM1 +R2) it prints our
 * time, POV-Ray's whole-process time, their ratio, the same for CPU seconds
 * (user + system: ours of this process during the call, POV-Ray's of the
 * child; on a loaded machine the CPU ratio is the fair one), each image's RMS error
 * against its own renderer's 64-ray reference (ours: 8x8 jittered,
 * POV-Ray: +A0.0 +AM1 +R8) and the mean absolute difference between the two
 * renderers' pictures (linear [0,1] values; the lighting models are the same
 * up to POV-Ray's own conventions, so this is a sanity check, not an error).
 * Then our error against time for 1, 4, 16 and 64 samples (regular,
 * jittered, adaptive).
 *
 * Usage: bench_render [OUTDIR [SCENE]]   (default /tmp/bench_render; SCENE: only the
 * scene of that name, e.g. csg, and no error-vs-time sweep)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/resource.h>

#include "geom/meshio.h"
#include "geom/scene.h"

#define W 320
#define H 240
#define PI 3.14159265358979323846

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds (user + system) of this process, or of its waited-for children. */
static double cpu_self(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu_children(void)
{
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
           (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

typedef struct bscene {
    const char *name;
    geom_shape shapes[8];
    geom_scene_object objects[8];
    size_t n;
    geom_material mats[4];
    const char *pov_objects; /* POV-Ray object text (materials M0..M3 declared) */
} bscene;

static geom_camera cam;
static geom_light lights[3];

static void setup_common(void)
{
    memset(&cam, 0, sizeof cam);
    cam.eye = geom_vec3_make(0, -6, 3);
    cam.center = geom_vec3_make(0, 0, 0.8);
    cam.up = geom_vec3_make(0, 0, 1);
    cam.fovy_degrees = 40;
    cam.width = W;
    cam.height = H;
    memset(lights, 0, sizeof lights);
    lights[0].kind = GEOM_LIGHT_POINT;
    lights[0].position = geom_vec3_make(4, -4, 8);
    lights[0].color = geom_vec3_make(0.8, 0.8, 0.8);
    lights[1].kind = GEOM_LIGHT_AMBIENT;
    lights[1].color = geom_vec3_make(1, 1, 1);
}

static geom_material mat(double r, double g, double b, double ks, double ns, double refl)
{
    geom_material m;
    memset(&m, 0, sizeof m);
    m.kd = geom_vec3_make(r, g, b);
    m.ka = geom_vec3_make(0.1 * r, 0.1 * g, 0.1 * b);
    m.ks = geom_vec3_make(ks, ks, ks);
    m.ns = ns;
    m.specular = GEOM_SPECULAR_PHONG; /* POV-Ray's phong */
    m.reflect = refl;
    return m;
}

static void pov_material(FILE *f, int i, const geom_material *m)
{
    fprintf(f, "#declare M%d = texture { pigment { color rgb <%.17g, %.17g, %.17g> } "
               "finish { ambient %.17g diffuse 1 phong %.17g phong_size %.17g reflection %.17g } }\n",
            i, m->kd.x, m->kd.y, m->kd.z, m->kd.x > 0 ? m->ka.x / m->kd.x : 0, m->ks.x, m->ns,
            m->reflect);
}

static void write_pov(const char *path, const bscene *s)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return;
    double aspect = (double)W / H;
    double hfov = 2 * atan(tan(cam.fovy_degrees * PI / 360) * aspect) * 180 / PI;
    fprintf(f, "#version 3.7;\nglobal_settings { assumed_gamma 1.0 ambient_light rgb <1,1,1> "
               "max_trace_level 9 adc_bailout 1/256 }\n");
    fprintf(f, "camera { perspective location <%g, %g, %g> sky <0,0,1> up <0,0,1> "
               "right <%.17g,0,0> look_at <%g, %g, %g> angle %.17g }\n",
            cam.eye.x, cam.eye.y, cam.eye.z, -aspect, cam.center.x, cam.center.y, cam.center.z,
            hfov);
    fprintf(f, "light_source { <%g, %g, %g> color rgb <%g, %g, %g> }\n", lights[0].position.x,
            lights[0].position.y, lights[0].position.z, lights[0].color.x, lights[0].color.y,
            lights[0].color.z);
    fprintf(f, "background { color rgb <0,0,0> }\n");
    for (int i = 0; i < 4; i++)
        pov_material(f, i, &s->mats[i]);
    fputs(s->pov_objects, f);
    fclose(f);
}

/* Read a binary PPM (P6, 8 or 16 bit) into linear doubles (File_Gamma=1). */
static double *read_ppm(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    int v[3], n = 0, c;
    char magic[3] = {0};
    if (fread(magic, 1, 2, f) != 2 || strcmp(magic, "P6")) {
        fclose(f);
        return NULL;
    }
    /* width, height, maxval, with '#' comments (POV-Ray writes one) */
    while (n < 3 && (c = fgetc(f)) != EOF) {
        if (c == '#') {
            while ((c = fgetc(f)) != EOF && c != '\n')
                ;
        } else if (c >= '0' && c <= '9') {
            ungetc(c, f);
            if (fscanf(f, "%d", &v[n]) != 1)
                break;
            n++;
        }
    }
    int w = v[0], h = v[1], maxv = v[2];
    if (n != 3 || w != W || h != H || maxv <= 0) {
        fclose(f);
        return NULL;
    }
    fgetc(f);
    double *d = malloc(sizeof(double) * 3 * W * H);
    for (int i = 0; d && i < 3 * W * H; i++) {
        int q = fgetc(f);
        if (maxv > 255)
            q = (q << 8) | fgetc(f);
        d[i] = (double)q / maxv;
    }
    fclose(f);
    return d;
}

static double pov_render(const char *dir, const bscene *s, const char *aa, double **img,
                         double *cpu)
{
    char pov[512], out[512], cmd[2048];
    snprintf(pov, sizeof pov, "%s/%s.pov", dir, s->name);
    snprintf(out, sizeof out, "%s/%s_pov.ppm", dir, s->name);
    write_pov(pov, s);
    snprintf(cmd, sizeof cmd,
             "povray +WT1 -D -V -GA +I'%s' +O'%s' +FP8 File_Gamma=1.0 +W%d +H%d %s "
             "> /dev/null 2>&1",
             pov, out, W, H, aa);
    double t0 = now(), c0 = cpu_children();
    int rc = system(cmd);
    double t = now() - t0;
    if (cpu)
        *cpu = cpu_children() - c0;
    *img = rc == 0 ? read_ppm(out) : NULL;
    return rc == 0 ? t : -1;
}

static double ours(const bscene *s, uint32_t samples, geom_sampling smp, geom_image *out,
                   double *cpu)
{
    geom_camera c = cam;
    c.samples = samples;
    c.sampling = smp;
    if (smp == GEOM_SAMPLING_ADAPTIVE) {
        c.samples = 4;
        c.max_samples = samples;
        c.tolerance = 0.01;
    }
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    double t0 = now(), c0 = cpu_self();
    geom_status st = geom_scene_render(&c, lights, 2, s->mats, 4, s->objects, s->n, &ro, out, NULL,
                                       NULL, NULL);
    double t = now() - t0;
    if (cpu)
        *cpu = cpu_self() - c0;
    return st == GEOM_OK ? t : -1;
}

static double rms(const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < 3 * W * H; i++) {
        double x = fmin(fmax(a[i], 0), 1), y = fmin(fmax(b[i], 0), 1);
        s += (x - y) * (x - y);
    }
    return sqrt(s / (3.0 * W * H));
}

static double mad(const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < 3 * W * H; i++)
        s += fabs(fmin(fmax(a[i], 0), 1) - fmin(fmax(b[i], 0), 1));
    return s / (3.0 * W * H);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "/tmp/bench_render";
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", dir);
    if (system(cmd) != 0)
        return 1;
    setup_common();
    static bscene sc[6];
    memset(sc, 0, sizeof sc);
    geom_material base[4] = {mat(0.7, 0.7, 0.65, 0, 1, 0), mat(0.8, 0.15, 0.1, 0.4, 60, 0),
                             mat(0.1, 0.1, 0.1, 0.6, 200, 0.7), mat(0.15, 0.25, 0.8, 0.3, 40, 0)};
    static geom_mat4 torus_m;
    torus_m = geom_mat4_translate(geom_vec3_make(0.3, 0.2, 0.5));
    static geom_mat4 bunny_m;
    /* floor shared by all */
    for (int k = 0; k < 6; k++) {
        memcpy(sc[k].mats, base, sizeof base);
        geom_shape *p = &sc[k].shapes[0];
        p->kind = GEOM_SHAPE_PLANE;
        p->n[2] = 1;
        sc[k].n = 1;
    }
    /* 0: spheres (one mirror) */
    sc[0].name = "spheres";
    {
        double c[3][4] = {{-1.6, 0.3, 0.8, 0.8}, {0.2, 1.0, 1.0, 1.0}, {1.5, -0.8, 0.6, 0.6}};
        for (int i = 0; i < 3; i++) {
            geom_shape *s = &sc[0].shapes[1 + i];
            s->kind = GEOM_SHAPE_SPHERE;
            memcpy(s->p, c[i], 3 * sizeof(double));
            s->radius = c[i][3];
        }
        sc[0].n = 4;
        sc[0].pov_objects =
            "plane { <0,0,1>, 0 texture { M0 } }\n"
            "sphere { <-1.6, 0.3, 0.8>, 0.8 texture { M1 } }\n"
            "sphere { <0.2, 1.0, 1.0>, 1.0 texture { M2 } }\n"
            "sphere { <1.5, -0.8, 0.6>, 0.6 texture { M3 } }\n";
    }
    /* 1: box */
    sc[1].name = "box";
    {
        geom_shape *s = &sc[1].shapes[1];
        s->kind = GEOM_SHAPE_BOX;
        s->min[0] = -1; s->min[1] = -0.5; s->min[2] = 0;
        s->max[0] = 1; s->max[1] = 0.7; s->max[2] = 1.4;
        sc[1].n = 2;
        sc[1].pov_objects = "plane { <0,0,1>, 0 texture { M0 } }\n"
                            "box { <-1, -0.5, 0>, <1, 0.7, 1.4> texture { M3 } }\n";
    }
    /* 2: torus */
    sc[2].name = "torus";
    {
        geom_shape *s = &sc[2].shapes[1];
        s->kind = GEOM_SHAPE_TORUS;
        s->major = 1.2;
        s->minor = 0.4;
        s->transform = &torus_m;
        sc[2].n = 2;
        sc[2].pov_objects = "plane { <0,0,1>, 0 texture { M0 } }\n"
                            "torus { 1.2, 0.4 rotate <90,0,0> translate <0.3, 0.2, 0.5> texture { M1 } }\n";
    }
    /* 3: CSG: box minus sphere */
    sc[3].name = "csg";
    {
        geom_shape *b = &sc[3].shapes[2], *s = &sc[3].shapes[3], *c = &sc[3].shapes[1];
        b->kind = GEOM_SHAPE_BOX;
        b->min[0] = -1; b->min[1] = -1; b->min[2] = 0;
        b->max[0] = 1; b->max[1] = 1; b->max[2] = 1.2;
        s->kind = GEOM_SHAPE_SPHERE;
        s->p[2] = 1.3;
        s->radius = 0.9;
        c->kind = GEOM_SHAPE_CSG;
        c->csg_op = 3;
        c->a = b;
        c->b = s;
        sc[3].n = 2;
        sc[3].pov_objects = "plane { <0,0,1>, 0 texture { M0 } }\n"
                            "difference { box { <-1,-1,0>, <1,1,1.2> } sphere { <0,0,1.3>, 0.9 } "
                            "texture { M3 } }\n";
    }
    /* 4: 75k-triangle mesh */
    geom_mesh *bunny = NULL;
    char *mesh2 = NULL;
    sc[4].name = "bunny";
    {
        snprintf(cmd, sizeof cmd,
                 "tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C '%s' data/meshes/bunny00.off",
                 dir);
        char path[512];
        snprintf(path, sizeof path, "%s/data/meshes/bunny00.off", dir);
        if (system(cmd) == 0 && geom_meshio_read(path, NULL, &bunny, NULL, NULL) == GEOM_OK) {
            geom_mesh_triangulate(bunny, NULL);
            geom_aabb bb = geom_mesh_bbox(bunny);
            double size = fmax(bb.max.x - bb.min.x, fmax(bb.max.y - bb.min.y, bb.max.z - bb.min.z));
            double k = 2.4 / size;
            /* the bunny is y-up: turn it z-up, scale to 2.4, stand it on the floor */
            geom_mat4 rot;
            geom_mat4_rotate(geom_vec3_make(1, 0, 0), PI / 2, &rot);
            geom_mat4 sc_m = geom_mat4_scale(geom_vec3_make(k, k, k));
            geom_mat4 tr = geom_mat4_translate(geom_vec3_make(-0.5 * (bb.min.x + bb.max.x), -bb.min.y,
                                                              -0.5 * (bb.min.z + bb.max.z)));
            bunny_m = geom_mat4_mul(rot, geom_mat4_mul(sc_m, tr));
            geom_scene_mesh_transform(bunny, bunny_m);
            geom_shape *s = &sc[4].shapes[1];
            s->kind = GEOM_SHAPE_MESH;
            s->mesh = bunny;
            sc[4].n = 2;
            /* POV-Ray mesh2 of the same triangles */
            size_t nv = geom_mesh_n_vertices(bunny), nf = geom_mesh_n_live_faces(bunny), ni = 0;
            geom_mesh_to_soup(bunny, NULL, NULL, &ni);
            uint32_t *sz = malloc(nf * sizeof *sz), *ix = malloc(ni * sizeof *ix);
            geom_mesh_to_soup(bunny, sz, ix, &ni);
            size_t cap = 128 + nv * 80 + nf * 40;
            mesh2 = malloc(cap);
            size_t o = (size_t)snprintf(mesh2, cap, "plane { <0,0,1>, 0 texture { M0 } }\n"
                                                    "mesh2 { vertex_vectors { %zu", nv);
            const double *P = geom_mesh_cpositions(bunny);
            for (size_t v = 0; v < nv; v++)
                o += (size_t)snprintf(mesh2 + o, cap - o, ", <%.9g,%.9g,%.9g>", P[3 * v],
                                      P[3 * v + 1], P[3 * v + 2]);
            o += (size_t)snprintf(mesh2 + o, cap - o, " } face_indices { %zu", nf);
            for (size_t f = 0; f < nf; f++)
                o += (size_t)snprintf(mesh2 + o, cap - o, ", <%u,%u,%u>", ix[3 * f], ix[3 * f + 1],
                                      ix[3 * f + 2]);
            snprintf(mesh2 + o, cap - o, " } texture { M1 } }\n");
            sc[4].pov_objects = mesh2;
            free(sz);
            free(ix);
        } else {
            sc[4].name = NULL;
            printf("bunny: CGAL's data.tar.gz not found (libcgal-demo), scene skipped\n");
        }
    }
    for (int k = 0; k < 6; k++)
        for (size_t i = 0; i < sc[k].n; i++) {
            sc[k].objects[i].shape = &sc[k].shapes[i];
            sc[k].objects[i].material = i == 0 ? 0 : (uint32_t)(k == 0 ? i : (k == 4 ? 1 : 3));
        }
    sc[2].objects[1].material = 1;
    sc[0].n = 4;

    printf("%-8s %-10s %8s %8s %7s %8s %8s %7s %8s %8s %8s\n", "scene", "AA", "ours s", "pov s",
           "ratio", "ours cpu", "pov cpu", "cpu rat", "our err", "pov err", "ours-pov");
    const char *aa_pov[2] = {"-A", "+A0.0 +AM1 +R2"};
    uint32_t aa_ours[2] = {1, 4};
    const char *only = argc > 2 ? argv[2] : NULL;
    for (int k = 0; k < 5; k++) {
        if (!sc[k].name || (only && strcmp(only, sc[k].name)))
            continue;
        geom_image ref = {0};
        double *pref = NULL;
        ours(&sc[k], 64, GEOM_SAMPLING_JITTERED, &ref, NULL);
        pov_render(dir, &sc[k], "+A0.0 +AM1 +R8", &pref, NULL);
        for (int a = 0; a < 2; a++) {
            geom_image img = {0};
            double *pimg = NULL;
            double co = 0, cp = 0;
            double to = ours(&sc[k], aa_ours[a], GEOM_SAMPLING_REGULAR, &img, &co);
            double tp = pov_render(dir, &sc[k], aa_pov[a], &pimg, &cp);
            printf("%-8s %-10s %8.3f %8.3f %7.2f %8.3f %8.3f %7.2f %8.4f %8.4f %8.4f\n", sc[k].name,
                   a ? "4 rays/px" : "none", to, tp, tp > 0 ? to / tp : NAN, co, cp,
                   cp > 0 ? co / cp : NAN,
                   ref.data && img.data ? rms(img.data, ref.data) : NAN,
                   pref && pimg ? rms(pimg, pref) : NAN,
                   pimg && img.data ? mad(img.data, pimg) : NAN);
            fflush(stdout);
            geom_scene_image_free(&img, NULL);
            free(pimg);
        }
        geom_scene_image_free(&ref, NULL);
        free(pref);
    }
    /* error against time (ours) on the spheres */
    if (only) {
        free(mesh2);
        geom_mesh_destroy(bunny);
        return 0;
    }
    printf("\nerror vs time, spheres, ours (RMS against 8x8 jittered)\n");
    printf("%-10s %8s %10s %10s %10s %12s\n", "sampling", "samples", "seconds", "cpu s", "rms err",
           "est. err max");
    geom_image ref = {0};
    ours(&sc[0], 64, GEOM_SAMPLING_JITTERED, &ref, NULL);
    const char *names[3] = {"regular", "jittered", "adaptive"};
    for (int m = 0; m < 3; m++)
        for (uint32_t n = 1; n <= 64; n *= 4) {
            if (m == 2 && n < 16)
                continue;
            geom_camera c = cam;
            c.samples = m == 2 ? 4 : n;
            c.sampling = (geom_sampling)m;
            c.max_samples = n;
            c.tolerance = 0.01;
            c.seed = 12345;
            geom_render_options ro;
            memset(&ro, 0, sizeof ro);
            geom_render_report rep;
            geom_image img = {0};
            double t0 = now(), c0 = cpu_self();
            geom_scene_render(&c, lights, 2, sc[0].mats, 4, sc[0].objects, sc[0].n, &ro, &img, &rep,
                              NULL, NULL);
            double t = now() - t0, ct = cpu_self() - c0;
            printf("%-10s %8.2f %10.3f %10.3f %10.5f %12.5f\n", names[m],
                   rep.trace.mean_samples_per_pixel, t, ct, rms(img.data, ref.data),
                   rep.trace.image_error.max_error);
            geom_scene_image_free(&img, NULL);
        }
    geom_scene_image_free(&ref, NULL);
    geom_mesh_destroy(bunny);
    free(mesh2);
    return 0;
}
