/*
 * libFuzzer target over the volume objects of scene files (read_volume in
 * tools/scene_json.c): the input is written as a volume file and read
 * through a scene {"objects": [{"type": "volume", "file": PATH, "iso": 0.5}]}
 * with the tools' real decompressors (cli_inflate over zlib, cli_bunzip2
 * over libbz2, when built with them). Besides memory errors, undefined
 * behaviour, hangs and leaks, it checks the contract and aborts on a
 * violation:
 *  - on error the status is one scene_json documents (PARSE, IO, LIMIT,
 *    NOMEM, INVALID_ARG), the output is all zero, and the message names the
 *    object ("objects[0]"), the key ("\"file\"") and the volume file's path;
 *  - on success the scene builds and rays along the three axes through the
 *    volume's box give hits with t inside [tmin, tmax] and finite points.
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every
 * build with driver.c, which runs the seed corpora of fuzz_volume
 * (tests/fuzz/corpus/volume) and the hostile volumes (tests/data/hostile/volume).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "geom/ray.h"
#include "scene_json.h"

static void require(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_scene_volume: contract violated: %s\n", what);
        abort();
    }
}

/* The directory the volume file is written to, made once per process. */
static char dir[64];
static char path[96];

static void cleanup(void)
{
    if (path[0]) unlink(path);
    if (dir[0]) rmdir(dir);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    scene_json_objects o;
    geom_diag d;
    geom_status st;
    char json[256];
    FILE *fp;
    int n;
    if (size > 1 << 16) return 0;
    if (!dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/geom-fuzz-scenevol.XXXXXX", tmp && strlen(tmp) < 30 ? tmp : "/tmp");
        require(mkdtemp(dir) != NULL, "cannot make a temporary directory");
        snprintf(path, sizeof path, "%s/volume.bin", dir);
        atexit(cleanup);
    }
    fp = fopen(path, "wb");
    require(fp != NULL, "cannot write the volume file");
    require(fwrite(data, 1, size, fp) == size, "cannot write the volume file");
    require(fclose(fp) == 0, "cannot write the volume file");
    n = snprintf(json, sizeof json, "{\"objects\": [{\"type\": \"volume\", \"file\": \"%s\", \"iso\": 0.5}]}", path);
    require(n > 0 && (size_t)n < sizeof json, "scene text");
    geom_diag_clear(&d);
    st = scene_json_read_memory(json, (size_t)n, "/nonexistent-geom-fuzz", "scene.json", NULL, &o, &d);
    if (st != GEOM_OK) {
        require(st == GEOM_ERR_PARSE || st == GEOM_ERR_IO || st == GEOM_ERR_LIMIT ||
                    st == GEOM_ERR_NOMEM || st == GEOM_ERR_INVALID_ARG,
                "documented status");
        require(o.scene == NULL && o.nowned == 0 && o.owned == NULL, "output not zeroed on error");
        require(d.status == st, "diagnostic status");
        require(strstr(d.message, "objects[0]") != NULL, "message names the object");
        require(strstr(d.message, "\"file\"") != NULL, "message names the key");
        require(strstr(d.message, path) != NULL || st == GEOM_ERR_NOMEM, "message names the volume file");
        return 0;
    }
    require(o.scene != NULL && o.nowned == 1 && o.owned_kind[0] == 1, "one volume on success");
    if (geom_ray_scene_build(o.scene, NULL, NULL, NULL) == GEOM_OK) {
        geom_aabb b = geom_implicit_volume_bounds(o.owned[0]);
        double c[3] = {0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), 0.5 * (b.min.z + b.max.z)};
        int a;
        for (a = 0; a < 3; a++) {
            geom_ray r;
            geom_ray_hit h;
            int found = 0;
            double org[3] = {c[0], c[1], c[2]}, dir3[3] = {0, 0, 0};
            double lo = a == 0 ? b.min.x : a == 1 ? b.min.y : b.min.z;
            org[a] = lo - 1;
            dir3[a] = 1;
            r.origin = geom_vec3_make(org[0], org[1], org[2]);
            r.dir = geom_vec3_make(dir3[0], dir3[1], dir3[2]);
            r.tmin = 0;
            r.tmax = INFINITY;
            if (!isfinite(org[a])) continue;
            if (geom_ray_scene_closest(o.scene, &r, &h, &found) == GEOM_OK && found) {
                require(h.t >= r.tmin && h.t <= r.tmax, "closest t in range");
                require(isfinite(h.point.x) && isfinite(h.point.y) && isfinite(h.point.z), "finite point");
            }
        }
    }
    scene_json_free(&o);
    return 0;
}
