#!/usr/bin/python3
"""Box queries over a BVH from Python against numpy brute force, same run.

geom.spatial.Bvh.from_boxes builds the tree in C; Bvh.overlap answers all
the queries in one C call (geom_bvh_query_boxes, run here on one thread). The
peer is the numpy brute force a user would write: per query box, one
vectorised test of every primitive box. Prints the build time, both query
times (process CPU time, best of 3), their ratio and the number of queries
whose answers differ (must be 0).

    GEOM_LIBRARY=build/libgeom/libgeom.so PYTHONPATH=bindings/python \\
        /usr/bin/python3 tests/bench/bench_python_bvh_overlap.py [N_BOXES] [N_QUERIES]
"""
import sys
import time

import numpy as np

import geom


def best_of(fn, repeats=3):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.process_time()
        out = fn()
        times.append(time.process_time() - t0)
    return min(times), out


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100000
    nq = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    rng = np.random.default_rng(0)
    h = n ** (-1 / 3)                       # mean spacing of the box centres
    c = rng.uniform(0, 1, (n, 3))
    r = rng.uniform(0, 0.5 * h, (n, 3))
    lo, hi = c - r, c + r
    q = rng.uniform(0, 1, (nq, 3))
    t0 = time.process_time()
    bvh = geom.spatial.Bvh.from_boxes(lo, hi, threads=1)
    t_build = time.process_time() - t0
    t_ours, ours = best_of(lambda: bvh.overlap(q - h, q + h, threads=1))
    t_np, peer = best_of(lambda: [np.flatnonzero(np.all((lo <= p + h) & (hi >= p - h), axis=1))
                                  for p in q])
    differ = sum(not np.array_equal(a, b) for a, b in zip(ours, peer))
    print("boxes %d, queries %d (half-size %.4g), hits %d" % (n, nq, h, sum(map(len, ours))))
    print("build (C, 1 thread)      %.3f s" % t_build)
    print("Bvh.overlap (C, 1 thread) %.4f s  %.1f us/query" % (t_ours, 1e6 * t_ours / nq))
    print("numpy brute force        %.4f s  %.1f us/query" % (t_np, 1e6 * t_np / nq))
    print("ratio brute force / ours %.1f; queries whose answers differ: %d" % (t_np / t_ours, differ))
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
