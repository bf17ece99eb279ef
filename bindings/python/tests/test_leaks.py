"""Repeated create/use/free cycles keep the process size flat: every C
object the bindings create (meshes, expressions, surfaces, surface sets,
write buffers, iso surfaces, textures, raster images, BVHs) is freed."""

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
    if geom.has_module("scene"):
        # a 256 x 256 RGB texture (about 2 MiB with its MIP pyramid) per cycle
        t = geom.scene.Texture(np.ones((256, 256, 3)))
        with geom.Mesh.from_soup(pts, faces) as m2:
            m2.set_channel("uv", pts[:, :2] * 0.1)
            geom.scene.raster([m2], geom.scene.camera((0, 0, 6), (0, 0, 0), width=16, height=12),
                              materials=[{"texture": t}])
        del t
    if geom.has_module("spatial"):
        b = geom.spatial.Bvh.from_boxes(pts, pts + 0.1)
        b.overlap(pts[:4], pts[:4] + 1)
        del b
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
