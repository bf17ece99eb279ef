"""RayScene.any / RayScene.all (one C call over all rays: geom_ray_scene_any_many,
geom_ray_scene_all_many) against the Python loop they replace (one
geom_ray_scene_any / geom_ray_scene_all call per ray through cffi, as ray.py did
before session 8), on the same rays in the same run; also checks that both give
the same answers.

    GEOM_LIBRARY=build/libgeom/libgeom.so PYTHONPATH=bindings/python \\
        /usr/bin/python3 tests/bench/bench_python_ray.py [N_RAYS] [MESH]

Scene: MESH if given (any format geom reads), else a sphere, a torus and a box
in front of a 5,120-triangle icosphere mesh. Rays: random, from a sphere of
twice the scene's radius to points of its bounding box. Times: process CPU
time, best of 5 repeats.
"""
import sys
import time

import numpy as np

import geom
from geom._ffi import ffi, lib


def icosphere(levels):
    t = (1 + 5 ** 0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
         [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
         [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    v = [list(np.array(p) / np.linalg.norm(p)) for p in v]
    for _ in range(levels):
        cache, nf = {}, []
        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                m = np.array(v[a]) + np.array(v[b])
                v.append(list(m / np.linalg.norm(m)))
                cache[k] = len(v) - 1
            return cache[k]
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    return np.array(v), np.array(f)


def cpu(fn, reps=5):
    best, out = float("inf"), None
    for _ in range(reps):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return best, out


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100000
    s = geom.RayScene()
    if len(sys.argv) > 2:
        m = geom.read_mesh(sys.argv[2])
        s.add_mesh(m)
        p = m.positions
        lo, hi = p.min(axis=0), p.max(axis=0)
    else:
        v, f = icosphere(4)
        s.add_triangles(v, f)
        s.add_sphere([2.5, 0, 0], 0.7)
        s.add_torus(1.5, 0.3)
        s.add_box([-3, -1, -1], [-2, 1, 1])
        lo, hi = np.array([-3.0, -1.8, -1.8]), np.array([3.2, 1.8, 1.8])
    s.build()
    c, r = 0.5 * (lo + hi), np.linalg.norm(hi - lo)
    g = np.random.default_rng(1)
    z = 2 * g.random(n) - 1
    ph = 2 * np.pi * g.random(n)
    q = np.sqrt(1 - z * z)
    o = c + r * np.stack([q * np.cos(ph), q * np.sin(ph), z], axis=1)
    d = lo + (hi - lo) * g.random((n, 3)) - o

    def loop_any():
        res = np.zeros(n, bool)
        ray = ffi.new("geom_ray *")
        fnd = ffi.new("int *")
        for i in range(n):
            ray.origin.x, ray.origin.y, ray.origin.z = o[i]
            ray.dir.x, ray.dir.y, ray.dir.z = d[i]
            ray.tmin, ray.tmax = 0.0, np.inf
            if lib.geom_ray_scene_any(s._s, ray, fnd) == 0:
                res[i] = bool(fnd[0])
        return res

    def loop_all():
        ts = []
        ray = ffi.new("geom_ray *")
        cnt = ffi.new("size_t *")
        hits = ffi.new("geom_ray_hit[]", 64)
        for i in range(n):
            ray.origin.x, ray.origin.y, ray.origin.z = o[i]
            ray.dir.x, ray.dir.y, ray.dir.z = d[i]
            ray.tmin, ray.tmax = 0.0, np.inf
            lib.geom_ray_scene_all(s._s, ray, hits, 64, cnt)
            ts.append([hits[j].t for j in range(min(int(cnt[0]), 64))])
        return ts

    ta, a = cpu(lambda: s.any(o, d))
    tla, la = cpu(loop_any, 3)
    tb, b = cpu(lambda: s.all(o, d))
    tlb, lb = cpu(loop_all, 3)
    assert np.array_equal(a, la)
    off = b["offsets"]
    assert all(list(b["t"][off[i]:off[i + 1]]) == lb[i] for i in range(n))
    print("bench_python_ray: %d rays, %d with a hit, %d hits (answers identical)"
          % (n, int(a.sum()), int(off[-1])))
    print("%-14s %12s %12s %8s" % ("query", "batch CPU s", "loop CPU s", "loop/batch"))
    print("%-14s %12.4f %12.4f %8.1f" % ("RayScene.any", ta, tla, tla / ta))
    print("%-14s %12.4f %12.4f %8.1f" % ("RayScene.all", tb, tlb, tlb / tb))


if __name__ == "__main__":
    main()
