#!/usr/bin/python3
"""Batch entry points of the Python bindings against plain numpy, same run.

For each per-point operation: the binding (one C call over the whole
array), the same computation vectorised in numpy, and a per-point Python
loop with numpy (the "loop in plain numpy"); times, ratios and the largest
difference between the binding's and numpy's results.

    GEOM_LIBRARY=build/libgeom/libgeom.so PYTHONPATH=bindings/python \\
        /usr/bin/python3 tests/bench/bench_python_batch.py [N]
"""
import sys
import time

import numpy as np

import geom

N = int(sys.argv[1]) if len(sys.argv) > 1 else 1000000
NLOOP = min(N, 20000)   # the per-point loop is timed on fewer points and scaled
rng = np.random.default_rng(1)


def best(fn, reps=7):
    t = []
    for _ in range(reps):
        t0 = time.perf_counter()
        r = fn()
        t.append(time.perf_counter() - t0)
    return min(t), r


def row(name, ours, vec, loop_per_pt, err):
    print("%-26s ours %8.4f s  numpy-vectorised %8.4f s (x%.2f)  numpy-loop %8.3f s (x%.1f)  "
          "max diff %.2g" % (name, ours, vec, vec / ours, loop_per_pt * N, loop_per_pt * N / ours,
                             err))


print("N = %d points (numpy loop timed on %d, scaled)" % (N, NLOOP))

# bary.tri2
a, b, c = np.array([0.1, 0.2]), np.array([3.0, 0.5]), np.array([1.0, 2.5])
p = rng.uniform(-1, 3, (N, 2))


def np_tri2(p):
    d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    l1 = ((p[:, 0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[:, 1] - a[1])) / d
    l2 = ((b[0] - a[0]) * (p[:, 1] - a[1]) - (p[:, 0] - a[0]) * (b[1] - a[1])) / d
    return np.stack([1 - l1 - l2, l1, l2], axis=1)


def loop_tri2(p):
    return np.array([np_tri2(q.reshape(1, 2))[0] for q in p])


t_ours, r_ours = best(lambda: geom.bary.tri2(a, b, c, p))
t_vec, r_vec = best(lambda: np_tri2(p))
t_loop, _ = best(lambda: loop_tri2(p[:NLOOP]), 1)
row("bary.tri2", t_ours, t_vec, t_loop / NLOOP, np.abs(r_ours - r_vec).max())

# bary.tet
A = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
q = rng.uniform(-0.5, 1, (N, 3))


def np_tet(q):
    T = np.stack([A[1] - A[0], A[2] - A[0], A[3] - A[0]], axis=1)
    l = np.linalg.solve(T, (q - A[0]).T).T
    return np.concatenate([1 - l.sum(axis=1, keepdims=True), l], axis=1)


t_ours, r_ours = best(lambda: geom.bary.tet(A[0], A[1], A[2], A[3], q))
t_vec, r_vec = best(lambda: np_tet(q))
t_loop, _ = best(lambda: [np_tet(x.reshape(1, 3)) for x in q[:NLOOP]], 1)
row("bary.tet", t_ours, t_vec, t_loop / NLOOP, np.abs(r_ours - r_vec).max())

# curve eval: a cubic Bezier as a NURBS curve, numpy Bernstein form
P = np.array([[0, 0, 0], [1, 2, 0], [3, 2, 1], [4, 0, 0]], dtype=float)
crv = geom.curve.NurbsCurve(3, [0, 0, 0, 0, 1, 1, 1, 1], P)
u = rng.uniform(0, 1, N)


def np_bez(u):
    s = 1 - u
    B = np.stack([s**3, 3 * s * s * u, 3 * s * u * u, u**3], axis=1)
    return B @ P


t_ours, r_ours = best(lambda: crv.eval(u))
t_vec, r_vec = best(lambda: np_bez(u))
t_loop, _ = best(lambda: [np_bez(np.array([x])) for x in u[:NLOOP]], 1)
row("NurbsCurve.eval", t_ours, t_vec, t_loop / NLOOP, np.abs(r_ours - r_vec).max())

# surface eval: a bicubic Bezier patch
rng2 = np.random.default_rng(2)
Q = rng2.uniform(0, 1, (4, 4, 3))
srf = geom.surface.NurbsSurface(3, 3, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1], Q)
us, vs = rng.uniform(0, 1, N), rng.uniform(0, 1, N)


def bern(t):
    s = 1 - t
    return np.stack([s**3, 3 * s * s * t, 3 * s * t * t, t**3], axis=1)


def np_patch(us, vs):
    return np.einsum("ni,nj,ijk->nk", bern(us), bern(vs), Q)


t_ours, r_ours = best(lambda: srf.eval(us, vs))
t_vec, r_vec = best(lambda: np_patch(us, vs))
t_loop, _ = best(lambda: [np_patch(us[i:i + 1], vs[i:i + 1]) for i in range(NLOOP)], 1)
row("NurbsSurface.eval", t_ours, t_vec, t_loop / NLOOP, np.abs(r_ours - r_vec).max())

# implicit: expression over points
e = geom.Expression("sqrt(x*x + y*y + z*z) - 1")
pts = rng.uniform(-2, 2, (N, 3))
t_ours, r_ours = best(lambda: e(pts))
t_vec, r_vec = best(lambda: np.sqrt((pts * pts).sum(axis=1)) - 1)
t_loop, _ = best(lambda: [np.sqrt((x * x).sum()) - 1 for x in pts[:NLOOP]], 1)
row("Expression(points)", t_ours, t_vec, t_loop / NLOOP, np.abs(r_ours - r_vec).max())

# volume: trilinear interpolation
vol = geom.Volume(rng.uniform(0, 1, (32, 32, 32)).astype(np.float32))
vp = rng.uniform(0, 31, (N, 3))
S = vol.samples.astype(np.float64)


def np_tri(vp):
    i0 = np.minimum(np.floor(vp).astype(int), 30)
    f = vp - i0
    r = 0
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = (f[:, 0] if dx else 1 - f[:, 0]) * (f[:, 1] if dy else 1 - f[:, 1]) * \
                    (f[:, 2] if dz else 1 - f[:, 2])
                r = r + w * S[i0[:, 0] + dx, i0[:, 1] + dy, i0[:, 2] + dz]
    return r


t_ours, r_ours = best(lambda: vol.eval(vp))
t_vec, r_vec = best(lambda: np_tri(vp))
t_loop, _ = best(lambda: [np_tri(x.reshape(1, 3)) for x in vp[:NLOOP]], 1)
row("Volume.eval", t_ours, t_vec, t_loop / NLOOP, np.abs(r_ours - r_vec).max())
