"""Small bindings of sessions 6 and 7 against closed forms: geom.ray.poly_roots
(products of known roots, a double root twice, Wilkinson's degree 8, numpy.roots on
separated roots), Octree.ray (front to
back, brute-force slab test over the items), geom.ray.quadric (the
coefficients' equations at points of the shape, and hits of a RayScene),
geom.iso.measure_error (refined vertices give marching_cubes' own vertex error, a scaled
sphere the scale's distance) and geom.mesh.sniff_format."""

import math

import numpy as np
import pytest

import geom


@pytest.mark.skipif(not geom.has_module("spatial"), reason="no spatial module")
def test_octree_ray_front_to_back():
    rng = np.random.default_rng(2)
    pts = rng.uniform(-1, 1, (500, 3))
    t = geom.spatial.Octree(pts, bucket_size=4)
    o, d = np.array([-2.0, 0.01, 0.02]), np.array([1.0, 0.003, -0.002])
    idx, entry = t.ray(o, d)
    assert (np.diff(entry) >= 0).all()
    # every point on the ray's line within the conservative slab test: the
    # points themselves are zero-size boxes, so only points on the ray come
    # back; a ray through a point must report it
    o2 = pts[17] - 3 * d
    idx2, entry2 = t.ray(o2, d)
    assert 17 in idx2 and entry2[list(idx2).index(17)] == pytest.approx(3.0, rel=1e-12)
    with pytest.raises(geom.GeomError):
        t.ray([np.nan, 0, 0], d)


@pytest.mark.skipif(not geom.has_module("ray"), reason="no ray module")
def test_quadric_coefficients():
    def F(q, p):
        x, y, z = p
        return (q[0] * x * x + q[1] * y * y + q[2] * z * z + 2 * q[3] * x * y + 2 * q[4] * y * z
                + 2 * q[5] * x * z + 2 * q[6] * x + 2 * q[7] * y + 2 * q[8] * z + q[9])
    e = geom.ray.quadric("ellipsoid", 2, 3, 4)
    for p in ((2, 0, 0), (0, 3, 0), (0, 0, -4)):
        assert F(e, p) == pytest.approx(0, abs=1e-14)
    assert F(e, (0, 0, 0)) < 0
    c = geom.ray.quadric("cylinder", 1.5)
    assert F(c, (1.5 * math.cos(1), 1.5 * math.sin(1), 7)) == pytest.approx(0, abs=1e-14)
    k = geom.ray.quadric("cone", 0.5)
    assert F(k, (1, 0, 2)) == pytest.approx(0, abs=1e-14)
    with pytest.raises(geom.GeomError):
        geom.ray.quadric("cylinder", -1)
    with pytest.raises(ValueError):
        geom.ray.quadric("torus", 1)
    s = geom.RayScene()
    s.add_quadric(c, clip=[-5, -5, -1, 5, 5, 1], capped=True)
    s.build()
    h = s.closest([[-5, 0, 0]], [[1, 0, 0]])
    assert h["t"][0] == pytest.approx(3.5, abs=1e-12)


@pytest.mark.skipif(not geom.has_module("iso"), reason="no iso module")
def test_measure_error():
    m, rep = geom.marching_cubes("sphere(1)", (-1.5,) * 3 + (1.5,) * 3, (24, 24, 24), refine=True)
    t = np.asarray(m.face_indices).reshape(-1, 3)
    ve, se, un = geom.iso.measure_error("sphere(1)", m.positions, t)
    # the same measure marching_cubes reports for its own refined output
    assert ve["max_error"] == pytest.approx(rep["vertex_error"]["max_error"], rel=1e-12)
    assert ve["max_error"] <= 1e-8 and se["max_error"] > 1e-4
    assert se["max_error"] == pytest.approx(rep["sample_error"]["max_error"], rel=1e-12)
    ve2, _, _ = geom.iso.measure_error("sphere(1)", 1.01 * m.positions, t)
    assert ve2["max_error"] == pytest.approx(0.01, rel=1e-6)
    with pytest.raises(geom.GeomError):
        geom.iso.measure_error("sphere(1)", m.positions, [[0, 1, 10 ** 9]])


@pytest.mark.skipif(not geom.has_module("meshio"), reason="no meshio module")
def test_sniff_format():
    assert geom.mesh.sniff_format(b"ply\nformat ascii 1.0\n") == "ply"
    assert geom.mesh.sniff_format(b"OFF\n3 1 0\n") == "off"
    assert geom.mesh.sniff_format(b"solid x\n") == "stl"
    assert geom.mesh.sniff_format(b"glTF\x02\x00\x00\x00") == "glb"
    assert geom.mesh.sniff_format(b"v 0 0 0\n") == "obj"
    assert geom.mesh.sniff_format(b"") == "obj"
    assert geom.mesh.sniff_format(b"\0" * 80 + (1).to_bytes(4, "little") + b"\0" * 50) == "stl"


# ------------------------------------------------------ geom.ray.poly_roots

@pytest.mark.skipif(not geom.has_module("ray"), reason="ray module not built")
def test_poly_roots_against_closed_forms():
    P = np.polynomial.polynomial
    pr = geom.ray.poly_roots
    np.testing.assert_allclose(pr(P.polyfromroots([1, 2, 3]), 0, 4), [1, 2, 3], rtol=5e-16)
    np.testing.assert_allclose(pr(P.polyfromroots([1, 2, 3]), 1.5, 2.5), [2], rtol=5e-16)
    np.testing.assert_allclose(pr(P.polyfromroots([1, 1, 3]), 0, 4), [1, 1, 3], rtol=1e-8)  # twice
    np.testing.assert_array_equal(pr([0, 0, 1], -1, 1), [0, 0])
    assert pr([1, 0, 1], -10, 10).size == 0                                     # x^2 + 1
    assert pr([5.0], 0, 1).size == 0
    w = pr(P.polyfromroots(np.arange(1, 9)), 0, 9)                             # Wilkinson, degree 8
    np.testing.assert_allclose(w, np.arange(1, 9), rtol=0, atol=1e-10)
    # a torus-like quartic (x^2 + 0.91)^2 - 4 x^2 (R = 1, r = 0.3 along a ray through the axis)
    q = pr([0.91 ** 2, 0, 2 * 0.91 - 4, 0, 1], -2, 2)
    np.testing.assert_allclose(q, [-1.3, -0.7, 0.7, 1.3], rtol=0, atol=1e-14)
    rng = np.random.default_rng(6)
    for _ in range(50):                  # well separated real roots: numpy.roots agrees
        r = np.sort(rng.choice(np.arange(-20, 20), 4, replace=False) / 4 + rng.uniform(0, 0.01))
        c = P.polyfromroots(r) * rng.uniform(0.5, 2)
        np.testing.assert_allclose(pr(c, -6, 6), r, rtol=0, atol=1e-12)


@pytest.mark.skipif(not geom.has_module("ray"), reason="ray module not built")
def test_poly_roots_bad_input():
    with pytest.raises(ValueError):
        geom.ray.poly_roots(np.ones(10), 0, 1)
    with pytest.raises(ValueError):
        geom.ray.poly_roots([1, np.nan], 0, 1)
    with pytest.raises(ValueError):
        geom.ray.poly_roots([1, 1], 0, np.inf)
    with pytest.raises(ValueError):
        geom.ray.poly_roots([1, 1], 1, 0)
