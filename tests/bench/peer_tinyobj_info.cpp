// Whole-process peer of `geom-info FILE.obj`: load an OBJ with tinyobjloader
// (Debian libtinyobjloader-dev, the double-precision build; no
// triangulation, no topology) and print the counts and the bounding box.
// Run by tests/bench/whole_process.sh against geom-info on the same file.
// Usage: peer_tinyobj_info FILE.obj
#ifndef TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_USE_DOUBLE
#endif
#include <tiny_obj_loader.h>

#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s FILE.obj\n", argv[0]);
        return 2;
    }
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, argv[1], nullptr,
                               false /* triangulate */);
    if (!ok) {
        std::fprintf(stderr, "%s: %s\n", argv[1], err.c_str());
        return 1;
    }
    size_t faces = 0, corners = 0;
    for (const auto &s : shapes) {
        faces += s.mesh.num_face_vertices.size();
        corners += s.mesh.indices.size();
    }
    const auto &v = attrib.vertices;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (size_t i = 0; i + 2 < v.size(); i += 3)
        for (int k = 0; k < 3; k++) {
            lo[k] = v[i + k] < lo[k] ? v[i + k] : lo[k];
            hi[k] = v[i + k] > hi[k] ? v[i + k] : hi[k];
        }
    std::printf("vertices %zu\nfaces %zu\ncorners %zu\nnormals %zu\ntexcoords %zu\n",
                v.size() / 3, faces, corners, attrib.normals.size() / 3,
                attrib.texcoords.size() / 2);
    std::printf("bbox %.17g %.17g %.17g  %.17g %.17g %.17g\n", lo[0], lo[1], lo[2], hi[0], hi[1],
                hi[2]);
    return 0;
}
