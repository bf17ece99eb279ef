/*
 * libFuzzer target over the camera/lights/materials reader of the scene
 * tools (srj_parse in tools/scene_render_json.c, through cJSON). Image keys
 * ("texture", "bump", "normal_map", "displace") are removed first so that
 * the fuzzer never opens files. Checks the contract and aborts on a
 * violation:
 *  - the status is GEOM_OK or GEOM_ERR_PARSE (or NOMEM); on error the
 *    output is all zero and the diagnostic has a message;
 *  - on success, a camera given gives a primary ray at every corner, every
 *    light and material value is finite, material 0 is the default.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "geom/scene.h"
#include "scene_render_json.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);       \
            abort();                                                                       \
        }                                                                                  \
    } while (0)

static int finite3(geom_vec3 v)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cJSON *root = cJSON_ParseWithLength((const char *)data, size);
    if (!root)
        return 0;
    cJSON *ms = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (cJSON_IsObject(ms)) {
        cJSON *m;
        cJSON_ArrayForEach(m, ms)
        {
            static const char *const keys[] = {"texture", "bump", "normal_map", "displace"};
            for (int k = 0; k < 4; k++)
                cJSON_DeleteItemFromObjectCaseSensitive(m, keys[k]);
        }
    }
    srj_scene s;
    geom_diag d;
    geom_diag_clear(&d);
    geom_status st = srj_parse(root, "fuzz.json", &s, &d);
    CHECK(st == GEOM_OK || st == GEOM_ERR_PARSE || st == GEOM_ERR_NOMEM);
    if (st != GEOM_OK) {
        srj_scene zero;
        memset(&zero, 0, sizeof zero);
        CHECK(memcmp(&s, &zero, sizeof s) == 0);
        CHECK(d.message[0] != 0);
    } else {
        if (s.has_camera) {
            geom_camera c = geom_scene_camera_resolved(&s.camera);
            double xs[2] = {0, c.width}, ys[2] = {0, c.height};
            for (int i = 0; i < 2; i++)
                for (int j = 0; j < 2; j++) {
                    geom_ray r;
                    CHECK(geom_scene_camera_ray(&s.camera, xs[i], ys[j], &r) == GEOM_OK);
                    CHECK(finite3(r.origin) && finite3(r.dir));
                }
        }
        for (size_t i = 0; i < s.n_lights; i++)
            CHECK(finite3(s.lights[i].color) && finite3(s.lights[i].position) &&
                  finite3(s.lights[i].direction));
        CHECK(s.n_materials >= 1 && s.material_names[0][0] == 0);
        for (size_t i = 0; i < s.n_materials; i++) {
            const geom_material *m = &s.materials[i];
            CHECK(finite3(m->ka) && finite3(m->kd) && finite3(m->ks) && isfinite(m->ns));
            CHECK(m->reflect >= 0 && m->reflect <= 1 && m->transmit >= 0 && m->transmit <= 1);
            CHECK(srj_material_index(&s, s.material_names[i]) <= i);
        }
        srj_free(&s);
    }
    cJSON_Delete(root);
    return 0;
}
