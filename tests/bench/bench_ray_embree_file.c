/*
 * The Embree side of the whole-process comparison with geom-raycast: reads
 * a mesh (with libgeom's reader, as geom-raycast does) and a ray file
 * (`ox oy oz dx dy dz [tmin [tmax]]` a line), traces every ray with Embree 3
 * (float, rtcNewDevice("threads=1"), robust mode with --robust) and prints
 * the same closest-hit lines as geom-raycast (t px py pz nx ny nz u v
 * object primitive, 17 significant digits, or miss), or with --any the
 * lines of geom-raycast --any (hit or miss, rtcOccluded1).
 *
 *   bench_ray_embree_file MESH RAYS [--robust] [--any] > out.txt
 *
 * Compare: farm-bench or `time` on both commands with the same files, e.g.
 *   time build/tools/geom-raycast bunny00.off --rays rays.txt > a.txt
 *   time build/tests/bench/bench_ray_embree_file bunny00.off rays.txt > b.txt
 */
#define _POSIX_C_SOURCE 200809L
#include <embree3/rtcore.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

int main(int argc, char **argv)
{
    geom_mesh *m = NULL;
    geom_diag diag;
    size_t nv, nidx = 0, nf, k = 0, i, nt = 0;
    uint32_t *sizes, *idx;
    RTCDevice dev;
    RTCScene sc;
    RTCGeometry g;
    float *v;
    unsigned *ix;
    FILE *fp;
    char *line = NULL;
    size_t cap = 0;
    struct RTCIntersectContext ctx;
    int robust = 0, any = 0, a;
    if (argc < 3) {
        fprintf(stderr, "usage: %s MESH RAYS [--robust] [--any]\n", argv[0]);
        return 2;
    }
    for (a = 3; a < argc; a++) {
        if (strcmp(argv[a], "--robust") == 0) robust = 1;
        else if (strcmp(argv[a], "--any") == 0) any = 1;
        else {
            fprintf(stderr, "usage: %s MESH RAYS [--robust] [--any]\n", argv[0]);
            return 2;
        }
    }
    geom_diag_clear(&diag);
    if (geom_meshio_read(argv[1], NULL, &m, NULL, &diag) != GEOM_OK) {
        fprintf(stderr, "%s: %s\n", argv[1], diag.message);
        return 1;
    }
    nv = geom_mesh_n_vertices(m);
    nf = geom_mesh_n_live_faces(m);
    geom_mesh_to_soup(m, NULL, NULL, &nidx);
    sizes = malloc(nf * sizeof *sizes);
    idx = malloc(nidx * sizeof *idx);
    geom_mesh_to_soup(m, sizes, idx, &nidx);
    for (i = 0; i < nf; i++) nt += sizes[i] >= 3 ? sizes[i] - 2 : 0;
    dev = rtcNewDevice("threads=1");
    sc = rtcNewScene(dev);
    if (robust) rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
    g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv);
    ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt);
    {
        const double *P = geom_mesh_cpositions(m);
        size_t t = 0, f;
        for (i = 0; i < 3 * nv; i++) v[i] = (float)P[i];
        for (f = 0; f < nf; f++) {
            uint32_t j;
            for (j = 1; j + 1 < sizes[f]; j++) {
                ix[3 * t] = idx[k];
                ix[3 * t + 1] = idx[k + j];
                ix[3 * t + 2] = idx[k + j + 1];
                t++;
            }
            k += sizes[f];
        }
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    rtcInitIntersectContext(&ctx);
    fp = fopen(argv[2], "r");
    if (!fp) {
        fprintf(stderr, "%s: cannot open\n", argv[2]);
        return 1;
    }
    while (getline(&line, &cap, fp) > 0) {
        double r[8] = {0, 0, 0, 0, 0, 0, 0, INFINITY};
        char *p = line, *e;
        int n = 0;
        struct RTCRayHit rh;
        while (n < 8) {
            double x = strtod(p, &e);
            if (e == p) break;
            r[n++] = x;
            p = e;
        }
        if (n < 6) continue;
        if (!isfinite(r[0] + r[1] + r[2] + r[3] + r[4] + r[5]) || (r[3] == 0 && r[4] == 0 && r[5] == 0)) {
            fputs("miss\n", stdout);
            continue;
        }
        rh.ray.org_x = (float)r[0];
        rh.ray.org_y = (float)r[1];
        rh.ray.org_z = (float)r[2];
        rh.ray.dir_x = (float)r[3];
        rh.ray.dir_y = (float)r[4];
        rh.ray.dir_z = (float)r[5];
        rh.ray.tnear = n > 6 ? (float)r[6] : 0.0f;
        rh.ray.tfar = n > 7 ? (float)r[7] : INFINITY;
        rh.ray.mask = 0xffffffffu;
        rh.ray.flags = 0;
        rh.ray.time = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        if (any) {
            /* occlusion: tfar becomes -inf on a hit */
            rtcOccluded1(sc, &ctx, &rh.ray);
            fputs(rh.ray.tfar == -INFINITY ? "hit\n" : "miss\n", stdout);
            continue;
        }
        rtcIntersect1(sc, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            fputs("miss\n", stdout);
        } else {
            double t = rh.ray.tfar, nl = sqrt((double)rh.hit.Ng_x * rh.hit.Ng_x + (double)rh.hit.Ng_y * rh.hit.Ng_y +
                                              (double)rh.hit.Ng_z * rh.hit.Ng_z);
            printf("%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g 0 %u\n", t, r[0] + t * r[3],
                   r[1] + t * r[4], r[2] + t * r[5], rh.hit.Ng_x / nl, rh.hit.Ng_y / nl, rh.hit.Ng_z / nl,
                   (double)rh.hit.u, (double)rh.hit.v, rh.hit.primID);
        }
    }
    free(line);
    fclose(fp);
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
    free(sizes);
    free(idx);
    geom_mesh_destroy(m);
    return 0;
}
