"""geom.ray against closed forms: a sphere, a box, a torus and a closed
triangle mesh (one hit from inside through its vertices)."""
import math

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("ray"), reason="ray module not built")


def test_sphere_closest_and_all():
    s = geom.RayScene()
    s.add_sphere([1, 2, 3], 2.0)
    s.build()
    h = s.closest([1, 2, -10], [0, 0, 2])
    assert h["hit"] and h["t"] == pytest.approx(5.5, abs=1e-14) and h["enter"]
    assert np.allclose(h["normal"], [0, 0, -1])
    hits = s.all([1, 2, -10], [0, 0, 2])
    assert [x["enter"] for x in hits] == [True, False]
    assert hits[1]["t"] == pytest.approx(7.5, abs=1e-14)
    o = np.array([[1, 2, -10], [10, 10, 10], [np.nan, 0, 0]])
    d = np.array([[0, 0, 1], [1, 0, 0], [0, 0, 1]])
    r = s.closest(o, d)
    assert list(r["hit"]) == [True, False, False] and list(r["valid"]) == [True, True, False]
    assert list(s.any(o, d)) == [True, False, False]


def test_torus_and_box():
    s = geom.RayScene()
    s.add_torus(2.0, 1.0)
    b = s.add_box([10, -1, -1], [12, 1, 1])
    s.build()
    ts = [x["t"] for x in s.all([-5, 0, 0], [1, 0, 0])]
    assert np.allclose(ts, [2, 4, 6, 8, 15, 17])
    assert s.all([-5, 0, 0], [1, 0, 0])[4]["object"] == b


def test_mesh_watertight():
    # octahedron: rays from the centre through every vertex and edge midpoint hit once
    p = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    t = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                  [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    s = geom.RayScene()
    s.add_triangles(p, t)
    info = s.build()
    assert info["triangles"] == 8
    targets = list(p) + [(p[a] + p[b]) / 2 for tri in t for a, b in ((tri[0], tri[1]), (tri[1], tri[2]))]
    for q in targets:
        hits = s.all([0, 0, 0], q)
        assert len(hits) == 1 and not hits[0]["enter"]
        assert hits[0]["t"] == pytest.approx(1.0, abs=1e-15)


def test_closest_batch_matches_first_of_all():
    # closest() answers every ray in one C call (geom_ray_scene_closest_many);
    # each answer must be the first hit of the single-ray all() query
    p = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    t = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                  [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    s = geom.RayScene()
    s.add_triangles(p * 1e7 + 3e7, t)   # far from the origin, large
    s.build()
    rng = np.random.default_rng(7)
    n = 300
    o = 3e7 + rng.normal(size=(n, 3)) * 3e7
    d = (3e7 + rng.normal(size=(n, 3)) * 4e6) - o
    o[5] = np.nan          # invalid rays: not hit, not valid
    d[9] = 0
    r = s.closest(o, d)
    assert not r["valid"][5] and not r["valid"][9] and r["valid"].sum() == n - 2
    assert 50 < r["hit"].sum() < n
    for i in range(n):
        hits = s.all(o[i], d[i]) if r["valid"][i] else []
        if not hits:
            assert not r["hit"][i] and np.isnan(r["t"][i])
            continue
        h = hits[0]
        assert r["hit"][i] and r["t"][i] == h["t"] and r["prim"][i] == h["prim"]
        assert np.array_equal(r["normal"][i], h["normal"]) and np.array_equal(r["point"][i], h["point"])
        assert r["enter"][i] == h["enter"] and r["object"][i] == h["object"]
        assert np.array_equal(r["uv"][i], h["uv"])


def test_volume_inside_above_is_outward():
    # a CT-like volume, dense (high) inside a ball: detected "above"; the
    # normal faces the ray coming from outside and the first hit enters
    n = 24
    g = np.linspace(-1.2, 1.2, n)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    vol = geom.Volume(1000.0 * (1.0 - np.sqrt(x * x + y * y + z * z)), spacing=(g[1] - g[0],) * 3,
                      origin=(-1.2, -1.2, -1.2))
    side, below, total = vol.detect_inside(0.0)
    assert side == "above" and total == 6 * n * n - 12 * n + 8 and below > total // 2
    for inside, enters in (("detect", True), ("above", True), ("below", False)):
        s = geom.RayScene()
        s.add_volume(vol, 0.0, inside=inside)
        s.build()
        h = s.closest([0, 0, -5], [0, 0, 1])
        assert h["hit"] and h["t"] == pytest.approx(4.0, abs=0.02)
        assert bool(h["enter"]) == enters
        assert (h["normal"][2] < -0.9) == enters
    with pytest.raises(ValueError):
        geom.RayScene().add_volume(vol, 0.0, inside="up")
