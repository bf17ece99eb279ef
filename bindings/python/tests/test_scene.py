"""geom.scene: a primary ray projects back onto its pixel."""
import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("scene"), reason="scene module not built")


def test_camera_ray_projects_back():
    cam = geom.scene.camera((1, 2, 3), (0, 0, 0), fovy=60, width=200, height=100)
    for x, y in ((0.5, 0.5), (100, 50), (199.5, 99.5)):
        o, d = geom.scene.camera_ray(cam, x, y)
        assert abs(np.linalg.norm(d) - 1) < 1e-15
        q = geom.scene.project(cam, o + 2.5 * d)
        assert abs(q[0] - x) < 1e-9 and abs(q[1] - y) < 1e-9
