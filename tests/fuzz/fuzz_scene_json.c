/*
 * libFuzzer target over the scene JSON reader of the tools
 * (scene_json_read_memory in tools/scene_json.c, through cJSON), given the
 * input as a buffer of exactly `size` bytes. Relative file paths resolve
 * under a directory that does not exist, so only absolute paths reach the
 * file system. Besides memory errors, undefined behaviour, hangs and leaks,
 * it checks the contract and aborts on a violation:
 *  - on error the output is all zero and the diagnostic carries the status;
 *  - on success the scene builds (or fails with a status, never crashes),
 *    and 16 fixed rays give hits with t inside [tmin, tmax], finite points
 *    and unit normals, all-hits sorted by t.
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every
 * build with driver.c, which runs the seed corpus tests/fuzz/corpus/scene_json.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/ray.h"
#include "scene_json.h"

static void require(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_scene_json: contract violated: %s\n", what);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    scene_json_objects o;
    geom_diag d;
    geom_status st;
    geom_diag_clear(&d);
    if (size > 1 << 16) return 0;
    st = scene_json_read_memory((const char *)data, size, "/nonexistent-geom-fuzz", "fuzz.json", NULL, &o, &d);
    if (st != GEOM_OK) {
        require(o.scene == NULL && o.nowned == 0 && o.owned == NULL, "output not zeroed on error");
        require(d.status == st, "diagnostic status");
        return 0;
    }
    require(o.scene != NULL, "scene on success");
    if (geom_ray_scene_build(o.scene, NULL, NULL, NULL) == GEOM_OK) {
        int i;
        for (i = 0; i < 16; i++) {
            geom_ray r;
            geom_ray_hit h[32];
            size_t n = 0, k;
            int found = 0;
            r.origin = geom_vec3_make(-5 + i * 0.7, 3 - i * 0.3, -7 + i);
            r.dir = geom_vec3_make(0.3 - i * 0.05, -0.2 + i * 0.03, 1);
            r.tmin = i % 4 == 0 ? -INFINITY : 0;
            r.tmax = INFINITY;
            if (geom_ray_scene_closest(o.scene, &r, h, &found) == GEOM_OK && found) {
                require(h[0].t >= r.tmin && h[0].t <= r.tmax, "closest t in range");
                require(isfinite(h[0].point.x) && isfinite(h[0].point.y) && isfinite(h[0].point.z), "finite point");
                require(fabs(geom_vec3_length(h[0].ng) - 1) < 1e-6, "unit normal");
            }
            st = geom_ray_scene_all(o.scene, &r, h, 32, &n);
            if (st == GEOM_OK)
                for (k = 1; k < n; k++) require(h[k - 1].t <= h[k].t, "all hits sorted");
        }
    }
    scene_json_free(&o);
    return 0;
}
