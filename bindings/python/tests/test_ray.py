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


def _mixed_scene():
    # a mesh, analytic shapes, a CSG difference and an instance; a row of
    # spheres along x so that a ray has more hits than all()'s first guess
    p = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    t = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                  [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    s = geom.RayScene()
    s.add_triangles(p * 0.8 + [0, 0, 3], t)
    s.add_torus(1.5, 0.3)
    a = s.add_box([-1, -1, -1], [1, 1, 1])
    b = s.add_sphere([0, 0, 0], 0.6)
    d = s.add_csg("difference", a, b)
    m = np.diag([0.5, 0.5, 0.5, 1.0])
    m[:3, 3] = [-3, 1, 0]             # half size, moved (row-major 4x4)
    s.add_instance(d, m)
    for i in range(40):
        s.add_sphere([3 + 0.5 * i, 0, 0], 0.2)
    s.build()
    return s


def _rays(n, seed):
    rng = np.random.default_rng(seed)
    o = rng.uniform(-6, 6, size=(n, 3))
    d = rng.uniform(-1.5, 1.5, size=(n, 3)) - o
    o[:8] = [-5, 0, 0]
    d[:8] = [1, 0, 0]                 # along the row of spheres: 80+ hits
    o[11] = np.nan                    # invalid rays
    d[13] = 0
    d[17] = [np.inf, 0, 0]
    return o, d


def test_any_all_batches_match_single_ray_functions():
    # any() and all() answer all rays in one C call each (_any_many,
    # _all_many): every answer bit for bit the single-ray C function's
    from geom._ffi import ffi, lib
    s = _mixed_scene()
    n = 400
    o, d = _rays(n, 11)
    t1 = np.full(n, np.inf)
    t1[20:40] = 5.0                   # limited ranges, one empty (tmin > tmax)
    t0 = np.zeros(n)
    t0[40] = 7.0
    t1[40] = 6.0
    anyb = s.any(o, d, tmin=t0, tmax=t1)
    allb = s.all(o, d, tmin=t0, tmax=t1)
    off = allb["offsets"]
    assert off.shape == (n + 1,) and off[0] == 0 and off[-1] == allb["t"].shape[0]
    assert np.array_equal(allb["ray"], np.repeat(np.arange(n), np.diff(off)))
    r = ffi.new("geom_ray *")
    f = ffi.new("int *")
    cnt = ffi.new("size_t *")
    hits = ffi.new("geom_ray_hit[]", 256)
    invalid = 0
    for i in range(n):
        r.origin.x, r.origin.y, r.origin.z = o[i]
        r.dir.x, r.dir.y, r.dir.z = d[i]
        r.tmin, r.tmax = t0[i], t1[i]
        st = lib.geom_ray_scene_any(s._s, r, f)
        st2 = lib.geom_ray_scene_all(s._s, r, hits, 256, cnt)
        assert st == st2 and st in (0, lib.GEOM_ERR_INVALID_ARG)
        invalid += st != 0
        assert allb["valid"][i] == (st == 0)
        assert anyb[i] == bool(f[0])
        k = int(cnt[0])
        assert off[i + 1] - off[i] == k and bool(anyb[i]) == (k > 0)
        for j in range(k):
            q = off[i] + j
            h = hits[j]
            assert allb["t"][q] == h.t and allb["t_error"][q] == h.t_error
            assert tuple(allb["point"][q]) == (h.point.x, h.point.y, h.point.z)
            assert tuple(allb["normal"][q]) == (h.ng.x, h.ng.y, h.ng.z)
            assert tuple(allb["shading_normal"][q]) == (h.ns.x, h.ns.y, h.ns.z)
            assert tuple(allb["uv"][q]) == (h.u, h.v)
            assert allb["prim"][q] == h.prim and allb["object"][q] == h.object
            assert allb["enter"][q] == bool(h.enter)
    assert invalid == 3
    assert np.diff(off)[:8].min() >= 80          # the row of spheres: grown past the first guess
    assert 50 < anyb.sum() < n and np.diff(off)[40] == 0
    # the one-ray form: a list of dicts, the same hits
    one = s.all(o[0], d[0])
    assert [h["t"] for h in one] == list(allb["t"][off[0]:off[1]])
    assert [h["enter"] for h in one] == list(allb["enter"][off[0]:off[1]])
    assert s.all([np.nan, 0, 0], [1, 0, 0]) == [] and s.any([np.nan, 0, 0], [1, 0, 0]) is False
    # sorted by t within each row
    for i in range(n):
        assert np.all(np.diff(allb["t"][off[i]:off[i + 1]]) >= 0)


def test_any_all_batch_edges():
    s = geom.RayScene()
    s.build()                                    # empty scene
    o, d = _rays(50, 3)
    assert not s.any(o, d).any()
    a = s.all(o, d)
    assert a["t"].shape == (0,) and np.array_equal(a["offsets"], np.zeros(51))
    assert list(np.flatnonzero(~a["valid"])) == [11, 13, 17]
    s.add_sphere([0, 0, 0], 1.0)                 # unbuilt
    with pytest.raises(RuntimeError):
        s.any(o, d)
    s.build()
    a = s.all(np.zeros((0, 3)), np.zeros((0, 3)))
    assert a["offsets"].shape == (1,) and a["t"].shape == (0,)
    assert s.any(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)
    # closed form: from outside through the centre, t = 4 and 6
    a = s.all([[-5, 0, 0], [0, 0, -5]], [[1, 0, 0], [0, 0, 1]])
    assert np.array_equal(a["offsets"], [0, 2, 4]) and np.allclose(a["t"], [4, 6, 4, 6], atol=1e-15)
    assert list(a["enter"]) == [True, False, True, False]
