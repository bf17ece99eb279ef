#!/usr/bin/python3
"""Batch entry points of the Python bindings against numpy, same run.

For each per-point operation: the binding (one C call over the whole
array), the same computation vectorised in numpy, and a per-point Python
loop with numpy (the "loop in plain numpy"); times, ratios and the largest
difference between the binding's and numpy's results.

Every operation has two numpy formulations: the first one written for this
benchmark ("plain", kept so that figures stay comparable with earlier runs)
and a tuned one a careful numpy user would write (products instead of
``x**3``, which numpy evaluates with pow(); a precomputed inverse and one
matrix product instead of a solve; one flat gather index instead of three
fancy indices; einsum with a contraction path; row sums of squares as a
product with a vector of ones). The ratio is taken against the fastest
formulation in the same run.

Times are the minimum over repeats of both the wall clock and the process
CPU time (time.process_time): on a shared, loaded machine the CPU time is
the steadier figure; with OpenMP kernels the wall time is the one that
counts (CPU time adds the threads). GEOM_THREADS is honoured by the C side
(see README) when set.

    GEOM_LIBRARY=build/libgeom/libgeom.so PYTHONPATH=bindings/python \\
        /usr/bin/python3 tests/bench/bench_python_batch.py [N] [--no-loop]
"""
import os
import sys
import time

import numpy as np

import geom

args = [a for a in sys.argv[1:] if not a.startswith("--")]
N = int(args[0]) if args else 1000000
LOOP = "--no-loop" not in sys.argv
NLOOP = min(N, 20000)   # the per-point loop is timed on fewer points and scaled
REPS = 9
rng = np.random.default_rng(1)


def best(fn, reps=REPS):
    """(min wall seconds, min CPU seconds, result)."""
    wall, cpu = [], []
    r = None
    for _ in range(reps):
        r = None
        t0, c0 = time.perf_counter(), time.process_time()
        r = fn()
        c1, t1 = time.process_time(), time.perf_counter()
        wall.append(t1 - t0)
        cpu.append(c1 - c0)
    return min(wall), min(cpu), r


def maxdiff(a, b):
    """Largest difference between results (arrays, or tuples of arrays)."""
    if isinstance(a, tuple):
        return max(maxdiff(x, y) for x, y in zip(a, b))
    return float(np.abs(np.asarray(a) - np.asarray(b)).max())


def run(name, ours, refs, loop, copy=None):
    """refs: (label, fn) numpy formulations; loop: per-point fn over NLOOP
    points; copy: a plain numpy copy of the bytes ours reads and writes
    (fresh output arrays, as the binding allocates them), its memory
    bound."""
    w_o, c_o, r_o = best(ours)
    cols = []
    diff = 0.0
    bw, bc = float("inf"), float("inf")
    for label, fn in refs:
        w, c, r = best(fn)
        diff = max(diff, maxdiff(r_o, r))
        cols.append("%s %.4f/%.4f" % (label, w, c))
        bw, bc = min(bw, w), min(bc, c)
    lp = ""
    if copy is not None:
        w, c, _ = best(copy)
        lp += "  copy %.4f/%.4f (ours/copy x%.2f cpu)" % (w, c, c_o / c)
    if LOOP:
        w, c, _ = best(loop, 1)
        lp += "  loop %.1f s (x%.0f)" % (w / NLOOP * N, w / NLOOP * N / w_o)
    print("%-19s ours %.4f/%.4f  numpy %s  ->  x%.2f wall, x%.2f cpu%s  max diff %.2g"
          % (name, w_o, c_o, "  ".join(cols), bw / w_o, bc / c_o, lp, diff))
    sys.stdout.flush()


print("N = %d points; times are min wall/min CPU seconds over %d runs; load average %s"
      % (N, REPS, " ".join("%.1f" % x for x in os.getloadavg())))

# bary.tri2 ----------------------------------------------------------------
a, b, c = np.array([0.1, 0.2]), np.array([3.0, 0.5]), np.array([1.0, 2.5])
p = rng.uniform(-1, 3, (N, 2))


def np_tri2(p):
    d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    l1 = ((p[:, 0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[:, 1] - a[1])) / d
    l2 = ((b[0] - a[0]) * (p[:, 1] - a[1]) - (p[:, 0] - a[0]) * (b[1] - a[1])) / d
    return np.stack([1 - l1 - l2, l1, l2], axis=1)


def np_tri2_tuned(p):
    # (l1, l2) = (p - a) T^-1 with the rows of T the edges b - a, c - a
    Ti = np.linalg.inv(np.stack([b - a, c - a]))
    out = np.empty((p.shape[0], 3))
    np.matmul(p - a, Ti, out=out[:, 1:])
    np.subtract(1.0, out[:, 1], out=out[:, 0])
    out[:, 0] -= out[:, 2]
    return out


run("bary.tri2", lambda: geom.bary.tri2(a, b, c, p),
    [("plain", lambda: np_tri2(p)), ("tuned", lambda: np_tri2_tuned(p))],
    lambda: np.array([np_tri2(x.reshape(1, 2))[0] for x in p[:NLOOP]]))

# bary.tri3 (the projection onto the plane of a 3D triangle) ---------------
a3, b3, c3 = np.array([0.1, 0.2, 0.3]), np.array([3.0, 0.5, -0.2]), np.array([1.0, 2.5, 0.7])
p3t = rng.uniform(-1, 3, (N, 3))


def np_tri3(p):
    # the textbook formula (dot products of the edges, Cramer's rule)
    e0, e1, v = b3 - a3, c3 - a3, p - a3
    d00, d01, d11 = e0 @ e0, e0 @ e1, e1 @ e1
    d20, d21 = v @ e0, v @ e1
    den = d00 * d11 - d01 * d01
    l1 = (d11 * d20 - d01 * d21) / den
    l2 = (d00 * d21 - d01 * d20) / den
    return np.stack([1 - l1 - l2, l1, l2], axis=1)


run("bary.tri3", lambda: geom.bary.tri3(a3, b3, c3, p3t),
    [("plain", lambda: np_tri3(p3t))],
    lambda: np.array([np_tri3(x.reshape(1, 3))[0] for x in p3t[:NLOOP]]))

# bary.tet -----------------------------------------------------------------
A = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
q = rng.uniform(-0.5, 1, (N, 3))


def np_tet(q):
    T = np.stack([A[1] - A[0], A[2] - A[0], A[3] - A[0]], axis=1)
    l = np.linalg.solve(T, (q - A[0]).T).T
    return np.concatenate([1 - l.sum(axis=1, keepdims=True), l], axis=1)


def np_tet_tuned(q):
    Ti = np.linalg.inv(A[1:] - A[0])
    out = np.empty((q.shape[0], 4))
    np.matmul(q - A[0], Ti, out=out[:, 1:])
    np.subtract(1.0, out[:, 1:].sum(axis=1), out=out[:, 0])
    return out


run("bary.tet", lambda: geom.bary.tet(A[0], A[1], A[2], A[3], q),
    [("plain", lambda: np_tet(q)), ("tuned", lambda: np_tet_tuned(q))],
    lambda: [np_tet(x.reshape(1, 3)) for x in q[:NLOOP]])

# bary.perspective, bary.interpolate ----------------------------------------
lw = rng.uniform(0, 1, (N, 3))
lw /= lw.sum(axis=1, keepdims=True)
ww = rng.uniform(0.5, 20, (N, 3))
attr = rng.uniform(-1, 1, (3, 4))


def np_persp(l, w):
    qq = l / w
    return qq / qq.sum(axis=1, keepdims=True)


def copy_persp():
    # read l and w (n, 3) each, write n x 3 values: 48 + 24 bytes a row (one
    # numpy pass with a fresh output)
    return np.add(lw, ww, out=np.empty_like(lw))


run("bary.perspective", lambda: geom.bary.perspective(lw, ww),
    [("plain", lambda: np_persp(lw, ww))],
    lambda: [np_persp(lw[i:i + 1], ww[i:i + 1]) for i in range(NLOOP)], copy_persp)


def copy_interp():
    # read the weights (n, 3), write n x 4 values: 24 + 32 bytes a row
    o = np.empty(lw.shape[0] * attr.shape[1])
    o[:lw.size] = lw.reshape(-1)
    o[lw.size:].fill(0.0)
    return o


run("bary.interpolate", lambda: geom.bary.interpolate(lw, attr),
    [("plain", lambda: lw @ attr)],
    lambda: [lw[i] @ attr for i in range(NLOOP)], copy_interp)

# predicates: libgeom's are exact in sign; numpy has no exact predicate, so
# the peer is the float determinant (not robust: wrong signs near zero) ----
p2 = [rng.uniform(-1, 1, (N, 2)) for _ in range(4)]
p3 = [rng.uniform(-1, 1, (N, 3)) for _ in range(4)]


def np_orient2d(a, b, c):
    return (a[:, 0] - c[:, 0]) * (b[:, 1] - c[:, 1]) - (a[:, 1] - c[:, 1]) * (b[:, 0] - c[:, 0])


def np_orient3d(a, b, c, d):
    return np.einsum("ij,ij->i", a - d, np.cross(b - d, c - d))


def np_incircle(a, b, c, d):
    m = np.stack([a - d, b - d, c - d], axis=1)
    m = np.concatenate([m, (m * m).sum(axis=2, keepdims=True)], axis=2)
    return np.linalg.det(m)




def copy_orient2d():
    # the 48 bytes a row orient2d reads (a max reduction: one pass, nothing
    # written) and the 8 it writes (a fresh array filled)
    s = 0.0
    for x in p2[:3]:
        s += np.maximum.reduce(x.reshape(-1))
    o = np.empty(N)
    o.fill(s)
    return o


run("core.orient2d", lambda: geom.orient2d(*p2[:3]),
    [("float", lambda: np_orient2d(*p2[:3]))],
    lambda: [np_orient2d(*[x[i:i + 1] for x in p2[:3]]) for i in range(NLOOP)], copy_orient2d)
run("core.orient3d", lambda: geom.orient3d(*p3),
    [("float", lambda: np_orient3d(*p3))],
    lambda: [np_orient3d(*[x[i:i + 1] for x in p3]) for i in range(NLOOP)])
run("core.incircle", lambda: geom.incircle(*p2),
    [("float", lambda: np_incircle(*p2))],
    lambda: [np_incircle(*[x[i:i + 1] for x in p2]) for i in range(NLOOP)])

# scene.Texture.sample: bilinear on level 0, repeat wrap --------------------
timg = rng.uniform(0, 1, (256, 256, 3))
tex = geom.scene.Texture(timg) if geom.has_module("scene") else None
tu, tv = rng.uniform(-1, 2, N), rng.uniform(-1, 2, N)


def np_bilinear(u, v):
    h, w = timg.shape[:2]
    x = (u - np.floor(u)) * w - 0.5
    y = (1.0 - (v - np.floor(v))) * h - 0.5
    fx, fy = np.floor(x), np.floor(y)
    ax, ay = (x - fx)[:, None], (y - fy)[:, None]
    x0, y0 = fx.astype(np.int64) % w, fy.astype(np.int64) % h
    x1, y1 = (x0 + 1) % w, (y0 + 1) % h
    top = (1 - ax) * timg[y0, x0] + ax * timg[y0, x1]
    bot = (1 - ax) * timg[y1, x0] + ax * timg[y1, x1]
    return (1 - ay) * top + ay * bot


if tex is not None:
    run("Texture.sample", lambda: tex.sample(tu, tv),
        [("plain", lambda: np_bilinear(tu, tv))],
        lambda: [np_bilinear(tu[i:i + 1], tv[i:i + 1]) for i in range(NLOOP)])

# curve eval: a cubic Bezier as a NURBS curve ------------------------------
P = np.array([[0, 0, 0], [1, 2, 0], [3, 2, 1], [4, 0, 0]], dtype=float)
crv = geom.curve.NurbsCurve(3, [0, 0, 0, 0, 1, 1, 1, 1], P)
u = rng.uniform(0, 1, N)


def np_bez(u):
    s = 1 - u
    B = np.stack([s**3, 3 * s * s * u, 3 * s * u * u, u**3], axis=1)
    return B @ P


def np_bez_tuned(u):
    s = 1 - u
    B = np.empty((u.size, 4))
    s2, u2 = s * s, u * u
    np.multiply(s2, s, out=B[:, 0])
    np.multiply(s2, u, out=B[:, 1])
    B[:, 1] *= 3
    np.multiply(s, u2, out=B[:, 2])
    B[:, 2] *= 3
    np.multiply(u2, u, out=B[:, 3])
    return B @ P


run("NurbsCurve.eval", lambda: crv.eval(u),
    [("plain", lambda: np_bez(u)), ("tuned", lambda: np_bez_tuned(u))],
    lambda: [np_bez(np.array([x])) for x in u[:NLOOP]])

# surface eval: a bicubic Bezier patch -------------------------------------
rng2 = np.random.default_rng(2)
Q = rng2.uniform(0, 1, (4, 4, 3))
srf = geom.surface.NurbsSurface(3, 3, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1], Q)
us, vs = rng.uniform(0, 1, N), rng.uniform(0, 1, N)


def bern(t):
    s = 1 - t
    return np.stack([s**3, 3 * s * s * t, 3 * s * t * t, t**3], axis=1)


def bern_tuned(t):
    s = 1 - t
    s2, t2 = s * s, t * t
    return np.stack([s2 * s, 3 * s2 * t, 3 * s * t2, t2 * t], axis=1)


def np_patch(us, vs):
    return np.einsum("ni,nj,ijk->nk", bern(us), bern(vs), Q)


def np_patch_tuned(us, vs):
    # rows of Bu against the 4 rows of control points, then along v
    R = (bern_tuned(us) @ Q.reshape(4, 12)).reshape(-1, 4, 3)
    return np.einsum("nj,njk->nk", bern_tuned(vs), R, optimize=True)


run("NurbsSurface.eval", lambda: srf.eval(us, vs),
    [("plain", lambda: np_patch(us, vs)), ("tuned", lambda: np_patch_tuned(us, vs))],
    lambda: [np_patch(us[i:i + 1], vs[i:i + 1]) for i in range(NLOOP)])

# implicit: expression over points -----------------------------------------
e = geom.Expression("sqrt(x*x + y*y + z*z) - 1")
pts = rng.uniform(-2, 2, (N, 3))


def np_sphere_tuned(pts):
    r = np.einsum("ij,ij->i", pts, pts)
    np.sqrt(r, out=r)
    r -= 1
    return r


ones3 = np.ones(3)


def np_sphere_matmul(pts):
    # row sums as a matrix-vector product: with the BLAS numpy links (even
    # the reference one) faster than einsum or .sum(axis=1)
    r = (pts * pts) @ ones3
    np.sqrt(r, out=r)
    r -= 1
    return r


run("Expression(points)", lambda: e(pts),
    [("plain", lambda: np.sqrt((pts * pts).sum(axis=1)) - 1),
     ("tuned", lambda: np_sphere_tuned(pts)), ("matmul", lambda: np_sphere_matmul(pts))],
    lambda: [np.sqrt((x * x).sum()) - 1 for x in pts[:NLOOP]])

# implicit: value and exact gradient over points ------------------------------
# numpy's hand-written gradient of the same sphere: (|p| - 1, p / |p|), the
# row sums as in np_sphere_matmul, one division per component.


def np_sphere_grad_plain(pts):
    r = np.sqrt((pts * pts).sum(axis=1))
    return r - 1, pts / r[:, None]


def np_sphere_grad(pts):
    r = (pts * pts) @ ones3
    np.sqrt(r, out=r)
    g = pts / r[:, None]
    r -= 1
    return r, g




def copy_grad(pts):
    # read the points, write values and gradients: 24 + 32 bytes a point
    g = np.empty_like(pts)
    np.copyto(g, pts)
    v = np.empty(pts.shape[0])
    v.fill(0.0)
    return v, g


run("Expression.gradient", lambda: e.gradient(pts),
    [("plain", lambda: np_sphere_grad_plain(pts)), ("tuned", lambda: np_sphere_grad(pts))],
    lambda: [np_sphere_grad_plain(x.reshape(1, 3)) for x in pts[:NLOOP]],
    lambda: copy_grad(pts))

# a torus: a program the distance-shaped kernel does not take (the general
# batch); numpy: q = |(x, y)|, d = |(q - R, z)|, f = d - r, grad = ((q - R)/d
# (x, y)/q, z/d)
et = geom.Expression("torus(1, 0.3)")


def np_torus_grad(pts):
    x, y, z = pts[:, 0], pts[:, 1], pts[:, 2]
    q = np.sqrt(x * x + y * y)
    a = q - 1.0
    d = np.sqrt(a * a + z * z)
    s = a / d / q
    g = np.empty_like(pts)
    np.multiply(x, s, out=g[:, 0])
    np.multiply(y, s, out=g[:, 1])
    np.divide(z, d, out=g[:, 2])
    d -= 0.3
    return d, g


run("Expression.gradient(torus)", lambda: et.gradient(pts),
    [("tuned", lambda: np_torus_grad(pts))],
    lambda: [np_torus_grad(x.reshape(1, 3)) for x in pts[:NLOOP]], lambda: copy_grad(pts))

# volume: trilinear interpolation ------------------------------------------
vol = geom.Volume(rng.uniform(0, 1, (32, 32, 32)).astype(np.float32))
vp = rng.uniform(0, 31, (N, 3))
S = vol.samples.astype(np.float64)
Sflat = S.reshape(-1)


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


def np_tri_tuned(vp):
    i0 = np.minimum(vp.astype(np.intp), 30)     # vp >= 0: truncation is floor
    f = vp - i0
    g = 1 - f
    sy, sx = S.shape[2], S.shape[1] * S.shape[2]
    base = i0 @ np.array([sx, sy, 1], dtype=np.intp)
    r = np.zeros(vp.shape[0])
    for dx in (0, 1):
        wx = f[:, 0] if dx else g[:, 0]
        for dy in (0, 1):
            wxy = wx * (f[:, 1] if dy else g[:, 1])
            off = dx * sx + dy * sy
            r += wxy * (g[:, 2] * Sflat.take(base + off) + f[:, 2] * Sflat.take(base + off + 1))
    return r


run("Volume.eval", lambda: vol.eval(vp),
    [("plain", lambda: np_tri(vp)), ("tuned", lambda: np_tri_tuned(vp))],
    lambda: [np_tri(x.reshape(1, 3)) for x in vp[:NLOOP]])

# volume: trilinear gradient (interpolated central differences) -------------
# numpy: the node gradients once (np.gradient: central inside, one-sided on
# the border, as the library), outside the timed part, then each component
# interpolated as np_tri_tuned does the values.
G = [g.reshape(-1) for g in np.gradient(S)]


def np_tri_grad(vp):
    i0 = np.minimum(vp.astype(np.intp), 30)
    f = vp - i0
    g = 1 - f
    sy, sx = S.shape[2], S.shape[1] * S.shape[2]
    base = i0 @ np.array([sx, sy, 1], dtype=np.intp)
    acc = [np.zeros(vp.shape[0]) for _ in range(3)]   # contiguous, stacked at the end
    for dx in (0, 1):
        wx = f[:, 0] if dx else g[:, 0]
        for dy in (0, 1):
            wxy = wx * (f[:, 1] if dy else g[:, 1])
            i0, i1 = base + (dx * sx + dy * sy), base + (dx * sx + dy * sy + 1)
            w0, w1 = wxy * g[:, 2], wxy * f[:, 2]
            for a in range(3):
                acc[a] += w0 * G[a].take(i0) + w1 * G[a].take(i1)
    return np.stack(acc, axis=1)


run("Volume.eval(grad)", lambda: vol.eval(vp, gradient=True)[1],
    [("tuned", lambda: np_tri_grad(vp))],
    lambda: [np_tri_grad(x.reshape(1, 3)) for x in vp[:NLOOP]])

# implicit: interval bounds over boxes -----------------------------------------
# numpy has no interval arithmetic: the peer is the one-box-per-call loop
# the binding offered before the batch (same C evaluator per box).
NB = min(N, 100000)
bc = rng.uniform(-1.5, 1.5, (NB, 3))
br = rng.uniform(0, 0.2, (NB, 3))
blo, bhi = bc - br, bc + br
eb = geom.Expression("min(torus(1, 0.3), box(0.5, 0.5, 0.5))")
w_s, c_s, _ = best(lambda: [eb.bounds(blo[i], bhi[i]) for i in range(min(NB, 20000))], 1)
scale = NB / min(NB, 20000)
try:
    w_o, c_o, r_o = best(lambda: eb.bounds(blo, bhi), 3)
except ValueError:      # a binding without the batch (one box per call)
    w_o, c_o = w_s * scale, c_s * scale
print("%-19s %d boxes: ours %.4f/%.4f  per-box calls %.4f/%.4f (scaled)  ->  x%.2f wall, "
      "x%.2f cpu" % ("Expression.bounds", NB, w_o, c_o, w_s * scale, c_s * scale,
                     w_s * scale / w_o, c_s * scale / c_o))
