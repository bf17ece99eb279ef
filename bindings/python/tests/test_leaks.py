"""Repeated create/use/free cycles keep the process size flat: every C
object the bindings create (meshes, expressions, surfaces, surface sets,
write buffers, iso surfaces) is freed."""

import gc
import os

import numpy as np
import pytest

import geom
from meshes import torus

pytestmark = [
    pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs /proc"),
    # AddressSanitizer keeps freed memory in quarantine: the size is not flat.
    pytest.mark.skipif(bool(os.environ.get("GEOM_SANITIZED")), reason="sanitized build"),
    pytest.mark.skipif(not geom.has_module("meshio"), reason="no meshio module"),
]


def _rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def _cycle(pts, faces):
    m = geom.Mesh.from_soup(pts, faces)
    m.topology()
    m.vertex_normals()
    m.set_corner("uv", np.zeros((m.face_indices.size, 2)))
    m.corner("uv")
    with m.clip_plane([1, 0, 0, 0], cap=True) as c:
        c.faces
    m.to_bytes("ply")
    if geom.has_module("subdiv"):
        m.subdivide(1).close()
    copy = m.copy()
    del copy  # freed by garbage collection, not close()
    m.close()
    if geom.has_module("implicit") and geom.has_module("iso"):
        e = geom.Expression("torus(1, 0.3)")
        e(pts)
        mc, _ = geom.marching_cubes(e, (-2, -2, -1, 2, 2, 1), (10, 10, 6))
        mc.close()
        e.close()
    if geom.has_module("surface"):
        s, _ = geom.tessellate(geom.NurbsSurface.sphere(1.0), mode="uniform", grid=(3, 3))
        s.close()
    try:
        geom.Mesh.from_bytes(b"v 0 0 0\nf 1 2 x\n", format="obj")
    except geom.GeomError:
        pass


def test_memory_stays_flat():
    pts, faces = torus(24, 12)
    for _ in range(30):
        _cycle(pts, faces)
    gc.collect()
    before = _rss()
    for _ in range(150):
        _cycle(pts, faces)
    gc.collect()
    grown = _rss() - before
    assert grown < 4 * 2 ** 20, "process grew by %.1f MiB over 150 cycles" % (grown / 2 ** 20)
