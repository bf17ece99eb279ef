// C++ consumer of the installed libgeom: the headers' extern "C" guards, the
// static library (with the iso module's OpenMP runtime) and the shared one.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "geom/geom.h"

int main()
{
#ifdef GEOM_BARY_H
    const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, p[2] = {0.25, 0.5};
    double l[3];
    if (geom_bary_tri2(a, b, c, p, l) != GEOM_OK || l[0] != 0.25 || l[1] != 0.25 || l[2] != 0.5) {
        std::fprintf(stderr, "bary: wrong result\n");
        return 1;
    }
#endif
#if defined(GEOM_ISO_H) && defined(GEOM_IMPLICIT_H)
    // an isosurface (the OpenMP-parallel module) of a sphere
    geom_implicit_expr *e = nullptr;
    const char *text = "sphere(1)";
    if (geom_implicit_expr_compile(text, std::strlen(text), nullptr, &e, nullptr) != GEOM_OK)
        return 1;
    geom_iso_field f;
    geom_iso_field_from_expr(e, &f);
    const double box[6] = {-1.5, -1.5, -1.5, 1.5, 1.5, 1.5};
    const size_t res[3] = {12, 12, 12};
    geom_iso_options o;
    std::memset(&o, 0, sizeof o);
    geom_iso_surface s;
    std::memset(&s, 0, sizeof s);
    geom_status st = geom_iso_extract(&f, box, res, &o, &s, nullptr);
    size_t tris = s.n_triangles;
    geom_iso_surface_free(&s);
    geom_implicit_expr_destroy(e);
    if (st != GEOM_OK || tris == 0) {
        std::fprintf(stderr, "iso: status %d, %zu triangles\n", (int)st, tris);
        return 1;
    }
    std::printf("iso: %zu triangles\n", tris);
#endif
    std::printf("ok: %s\n", geom_version_string());
    return 0;
}
