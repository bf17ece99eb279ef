/*
 * The OBJ writer alone: geom_meshio_write_stream of a torus mesh (NU x NV
 * quads split into triangles, the whole-process benchmark's shape: 1000 x
 * 500 is 500,000 vertices and 1M triangles) into a write function that only
 * counts and hashes the bytes (no I/O), with positions only ("v" and
 * "f a b c") and with a vertex "normal" channel as geom-normals writes it
 * ("vn" and "f a//a b//b c//c"). Prints CPU ns per number written (doubles
 * and indices), MB/s, the output size and an FNV-1a hash of the bytes, so
 * that two builds' outputs can be compared without files; with OUT, the
 * normals case is also written to OUT for cmp. No peer: before/after
 * figures go into BENCHMARKS.md.
 * Usage: bench_obj_write [NU NV [REPS [OUT]]]   (default 1000 500 3)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "geom/mesh.h"
#include "geom/meshio.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct counter {
    unsigned long long bytes, hash;
    int hashing;
    FILE *fp;
} counter;

static geom_status count_bytes(void *user, const void *data, size_t n)
{
    counter *c = user;
    c->bytes += n;
    if (c->hashing) {
        const unsigned char *p = data;
        unsigned long long h = c->hash;
        for (size_t i = 0; i < n; i++)
            h = (h ^ p[i]) * 1099511628211ull;
        c->hash = h;
    }
    if (c->fp && fwrite(data, 1, n, c->fp) != n)
        return GEOM_ERR_IO;
    return GEOM_OK;
}

static geom_mesh *torus(size_t nu, size_t nv)
{
    size_t n = nu * nv;
    double *xyz = malloc(3 * n * sizeof(double));
    uint32_t *idx = malloc(6 * n * sizeof(uint32_t));
    uint32_t *sz = malloc(2 * n * sizeof(uint32_t));
    geom_mesh *m = geom_mesh_create(NULL);
    if (!xyz || !idx || !sz || !m)
        return NULL;
    const double R = 2.0, r = 0.75, pi = 3.14159265358979323846;
    for (size_t i = 0; i < nu; i++)
        for (size_t j = 0; j < nv; j++) {
            double a = 2 * pi * (double)i / (double)nu, b = 2 * pi * (double)j / (double)nv;
            double *p = xyz + 3 * (i * nv + j);
            p[0] = (R + r * cos(b)) * cos(a);
            p[1] = (R + r * cos(b)) * sin(a);
            p[2] = r * sin(b);
        }
#define V(i, j) ((uint32_t)(((i) % nu) * nv + ((j) % nv)))
    size_t t = 0;
    for (size_t i = 0; i < nu; i++)
        for (size_t j = 0; j < nv; j++) {
            uint32_t a = V(i, j), b = V(i + 1, j), c = V(i + 1, j + 1), d = V(i, j + 1);
            uint32_t *q = idx + 3 * t;
            q[0] = a, q[1] = b, q[2] = c, q[3] = a, q[4] = c, q[5] = d;
            sz[t] = sz[t + 1] = 3;
            t += 2;
        }
#undef V
    geom_status st = geom_mesh_build(m, n, xyz, 2 * n, sz, idx, NULL, NULL, NULL);
    free(xyz);
    free(idx);
    free(sz);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return NULL;
    }
    return m;
}

static void run(const char *label, const geom_mesh *m, size_t numbers, int reps, FILE *fp)
{
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    double best = 1e300;
    counter c = {0, 14695981039346656037ull, 0, NULL};
    unsigned long long hash = 0;
    for (int r = 0; r < reps; r++) {
        /* the first run hashes the bytes (and writes OUT), untimed when
         * there are more */
        c.bytes = 0;
        c.hashing = r == 0;
        c.fp = r == 0 ? fp : NULL;
        double t0 = now();
        geom_status st = geom_meshio_write_stream(m, &wo, count_bytes, &c, NULL);
        double t = now() - t0;
        if (st != GEOM_OK) {
            fprintf(stderr, "write failed: %s\n", geom_status_str(st));
            exit(1);
        }
        if (r == 0)
            hash = c.hash;
        if (r > 0 || reps == 1)
            best = t < best ? t : best;
    }
    printf("%-22s %8.3f s  %6.1f ns/number  %7.1f MB/s  %llu bytes  fnv %016llx\n", label, best,
           1e9 * best / (double)numbers, (double)c.bytes / best / 1e6, c.bytes, hash);
}

int main(int argc, char **argv)
{
    size_t nu = argc > 1 ? strtoul(argv[1], NULL, 10) : 1000;
    size_t nv = argc > 2 ? strtoul(argv[2], NULL, 10) : 500;
    int reps = argc > 3 ? atoi(argv[3]) : 3;
    FILE *fp = argc > 4 ? fopen(argv[4], "wb") : NULL;
    if (nu < 3 || nv < 3 || reps < 1 || (argc > 4 && !fp)) {
        fprintf(stderr, "usage: bench_obj_write [NU NV [REPS [OUT]]]\n");
        return 2;
    }
    geom_mesh *m = torus(nu, nv);
    if (!m) {
        fprintf(stderr, "mesh build failed\n");
        return 1;
    }
    size_t V = geom_mesh_n_vertices(m), F = geom_mesh_n_faces(m);
    printf("OBJ writer, torus %zu x %zu: %zu vertices, %zu triangles; CPU time, best of %d\n", nu,
           nv, V, F, reps > 1 ? reps - 1 : 1);
    run("positions (v, f)", m, 3 * V + 3 * F, reps, NULL);
    uint32_t id;
    if (geom_mesh_channel_add(m, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id) != GEOM_OK ||
        geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_AREA, geom_mesh_channel_data(m, id),
                                 NULL) != GEOM_OK) {
        fprintf(stderr, "normals failed\n");
        return 1;
    }
    run("+ normals (vn, v//vn)", m, 6 * V + 6 * F, reps, fp);
    if (fp)
        fclose(fp);
    geom_mesh_destroy(m);
    return 0;
}
