"""Ray files for the whole-process comparison of geom-raycast with
bench_ray_embree_file, made as bench_ray.cpp makes its rays for a mesh's
bounding box [LO, HI]: "camera" (a pinhole at centre + diag * (0.3, 0.2,
1.2) looking at the centre, N x N rays through a square of half-size 0.45
about the unit view direction) or "random" (from uniform points of the
sphere of radius diag about the centre to uniform points of the box, seed
12345). One ray a line, `ox oy oz dx dy dz`, 17 significant digits.

    /usr/bin/python3 tests/bench/make_ray_file.py LOX,LOY,LOZ HIX,HIY,HIZ N camera|random > rays.txt
"""
import sys

import numpy as np


def main():
    lo = np.array([float(x) for x in sys.argv[1].split(",")])
    hi = np.array([float(x) for x in sys.argv[2].split(",")])
    n, kind = int(sys.argv[3]), sys.argv[4]
    c = 0.5 * (lo + hi)
    diag = np.linalg.norm(hi - lo)
    if kind == "camera":
        eye = c + diag * np.array([0.3, 0.2, 1.2])
        fwd = (c - eye) / np.linalg.norm(c - eye)
        right = np.cross(fwd, [0.0, 1.0, 0.0])
        up = np.cross(right, fwd)
        right /= np.linalg.norm(right)
        up /= np.linalg.norm(up)
        s = (np.arange(n) + 0.5) / n * 2 - 1
        sy, sx = np.meshgrid(s, s, indexing="ij")
        d = fwd + 0.45 * (sx.reshape(-1, 1) * right + sy.reshape(-1, 1) * up)
        o = np.broadcast_to(eye, d.shape)
    elif kind == "random":
        g = np.random.default_rng(12345)
        m = n * n
        z = 2 * g.random(m) - 1
        ph = 2 * np.pi * g.random(m)
        q = np.sqrt(1 - z * z)
        o = c + diag * np.stack([q * np.cos(ph), q * np.sin(ph), z], axis=1)
        d = lo + (hi - lo) * g.random((m, 3)) - o
    else:
        sys.exit("kind must be camera or random")
    np.savetxt(sys.stdout, np.hstack([o, d]), fmt="%.17g")


if __name__ == "__main__":
    main()
