// Embree part of the validation shim (see geom_validate_embree.h).
#include "geom_validate_embree.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstdint>

extern "C" int gv_embree_closest(const double *positions, size_t nv, const uint32_t *tris, size_t nt,
                                 int robust, const double *rays, size_t nr, double *t_out,
                                 uint32_t *prim_out)
{
    RTCDevice dev = rtcNewDevice("threads=1");
    if (!dev) return -1;
    RTCScene sc = rtcNewScene(dev);
    if (robust) rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = static_cast<float *>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    unsigned *ix = static_cast<unsigned *>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    if (!v || !ix) {
        rtcReleaseGeometry(g);
        rtcReleaseScene(sc);
        rtcReleaseDevice(dev);
        return -1;
    }
    for (size_t i = 0; i < 3 * nv; i++) v[i] = static_cast<float>(positions[i]);
    for (size_t i = 0; i < 3 * nt; i++) ix[i] = tris[i];
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = 0; i < nr; i++) {
        const double *r = rays + 6 * i;
        RTCRayHit rh;
        rh.ray.org_x = static_cast<float>(r[0]);
        rh.ray.org_y = static_cast<float>(r[1]);
        rh.ray.org_z = static_cast<float>(r[2]);
        rh.ray.dir_x = static_cast<float>(r[3]);
        rh.ray.dir_y = static_cast<float>(r[4]);
        rh.ray.dir_z = static_cast<float>(r[5]);
        rh.ray.tnear = 0;
        rh.ray.tfar = INFINITY;
        rh.ray.mask = 0xffffffffu;
        rh.ray.flags = 0;
        rh.ray.time = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(sc, &ctx, &rh);
        bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        t_out[i] = hit ? static_cast<double>(rh.ray.tfar) : NAN;
        if (prim_out) prim_out[i] = hit ? rh.hit.primID : UINT32_MAX;
    }
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
    return 0;
}
