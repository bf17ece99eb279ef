#!/usr/bin/python3
"""Write the whole-process benchmark input: a torus of NU x NV quads split
into 2*NU*NV triangles (default 1000 x 600: 600,000 vertices, 1.2M
triangles), positions as Python's repr (the shortest decimal that reads back
exactly: 16-17 significant digits), faces "f a b c" (about 63 MB). With --vt-vn also vt and vn
lines (%.6f) and faces "f v/vt/vn" (about 150 MB).
Usage: /usr/bin/python3 make_torus_obj.py OUT.obj [NU NV] [--vt-vn]"""
import sys
import numpy as np

args = [a for a in sys.argv[1:] if not a.startswith("--")]
full = "--vt-vn" in sys.argv
out = args[0]
nu = int(args[1]) if len(args) > 1 else 1000
nv = int(args[2]) if len(args) > 2 else 600
R, r = 2.0, 0.75
a = 2 * np.pi * np.arange(nu) / nu
b = 2 * np.pi * np.arange(nv) / nv
A, B = np.meshgrid(a, b, indexing="ij")
P = np.stack([(R + r * np.cos(B)) * np.cos(A), (R + r * np.cos(B)) * np.sin(A), r * np.sin(B)], -1)
P = P.reshape(-1, 3)
i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
V = lambda i, j: (i % nu) * nv + (j % nv) + 1
a, b, c, d = V(i, j), V(i + 1, j), V(i + 1, j + 1), V(i, j + 1)
T = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
with open(out, "w") as f:
    f.write("# torus %d x %d, %d triangles\n" % (nu, nv, len(T)))
    f.write("".join("v %r %r %r\n" % tuple(p) for p in P.tolist()))
    if full:
        N = np.stack([np.cos(B) * np.cos(A), np.cos(B) * np.sin(A), np.sin(B)], -1).reshape(-1, 3)
        f.write("".join("vt %.6f %.6f\n" % (u, w) for u, w in zip((i / nu).ravel(), (j / nv).ravel())))
        f.write("".join("vn %.6f %.6f %.6f\n" % tuple(n) for n in N.tolist()))
        f.write("".join("f %d/%d/%d %d/%d/%d %d/%d/%d\n" % (x, x, x, y, y, y, z, z, z) for x, y, z in T.tolist()))
    else:
        f.write("".join("f %d %d %d\n" % tuple(t) for t in T.tolist()))
