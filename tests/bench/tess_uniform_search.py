"""Adaptive tessellation against the best uniform grid, by search.

    GEOM_LIBRARY=build/libgeom/libgeom.so PYTHONPATH=bindings/python \
        /usr/bin/python3 tests/bench/tess_uniform_search.py TOL GU_MIN GU_MAX [NAME]

Tessellates the surface NAME (default "sphere") of data/surfaces.json adaptively
at TOL, then for every gu in GU_MIN..GU_MAX quads along u per knot span finds the
smallest gv whose uniform grid reaches the adaptive result's achieved error
(bisection: assumes the error does not rise as gv grows; gv is searched only up
to where the uniform grid would have more triangles than the adaptive one).
Prints each gu's answer and the best uniform grid found.
"""
import json
import sys
import time

from geom import surface


def main():
    tol = float(sys.argv[1])
    gu_min, gu_max = int(sys.argv[2]), int(sys.argv[3])
    name = sys.argv[4] if len(sys.argv) > 4 else "sphere"
    with open("data/surfaces.json") as f:
        names = [o.get("name") for o in json.load(f)["surfaces"]]
    surf = surface.read_json("data/surfaces.json")["surfaces"][names.index(name)]
    t0 = time.perf_counter()
    mesh, rep = surface.tessellate(surf, tolerance=tol)
    n_adapt, e_adapt = mesh.n_faces, rep["max_error"]
    print(f"adaptive {n_adapt} triangles, error {e_adapt:.6g}, {time.perf_counter() - t0:.2f} s",
          flush=True)

    def uniform(gu, gv):
        m, r = surface.tessellate(surf, mode="uniform", grid=(gu, gv))
        return m.n_faces, r["max_error"]

    spans = max(1, round(uniform(1, 1)[0] / 2))  # cells at 1 x 1 per span
    best = None
    for gu in range(gu_min, gu_max + 1):
        hi = n_adapt // (2 * spans * gu) + 3
        n, e = uniform(gu, hi)
        if e > e_adapt:
            print(f"{gu}: no grid with at most {n} triangles reaches it", flush=True)
            continue
        lo = 1
        while lo < hi:
            mid = (lo + hi) // 2
            if uniform(gu, mid)[1] <= e_adapt:
                hi = mid
            else:
                lo = mid + 1
        n, e = uniform(gu, lo)
        if best is None or n < best[0]:
            best = (n, gu, lo, e)
        print(f"{gu} x {lo}: {n} triangles, error {e:.6g}"
              + ("  FEWER than adaptive" if n < n_adapt else ""), flush=True)
    if best:
        print(f"best uniform {best[1]} x {best[2]}: {best[0]} triangles, error {best[3]:.6g}; "
              f"adaptive {n_adapt} ({n_adapt / best[0]:.4f} of it)")


if __name__ == "__main__":
    main()
