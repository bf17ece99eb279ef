"""The curve and surface operations bound in session 6 against closed
forms computed here: Bernstein sums for Bezier split/elevate/bbox, the
Hermite and uniform Catmull-Rom polynomials, the implicit equations of
ellipses and parabolas, clamping and Bezier extraction against the
original curve, periodic continuity, overflow-free segment distance, and
extruded/ruled/revolved surfaces against their definitions; the
tessellation estimate against the triangles made."""

import math

import numpy as np
import pytest

import geom
from geom import curve

pytestmark = pytest.mark.skipif(not geom.has_module("surface"), reason="no surface module")

U = np.linspace(0, 1, 41)


def bernstein(ctrl, t):
    c = np.asarray(ctrl, dtype=float)
    p = len(c) - 1
    t = np.atleast_1d(t)[:, None]
    return sum(math.comb(p, i) * t ** i * (1 - t) ** (p - i) * c[i] for i in range(p + 1))


CTRL = np.array([[0, 0], [1, 3], [3, -2], [4, 1.5], [5, 0.2]])


def test_bezier_split_elevate_bbox():
    left, right = curve.bezier_split(CTRL, 0.3)
    np.testing.assert_allclose(bernstein(left, U), bernstein(CTRL, 0.3 * U), atol=1e-14)
    np.testing.assert_allclose(bernstein(right, U), bernstein(CTRL, 0.3 + 0.7 * U), atol=1e-14)
    assert np.array_equal(left[-1], right[0])
    e = curve.bezier_elevate(CTRL, 3)
    assert e.shape == (8, 2)
    np.testing.assert_allclose(bernstein(e, U), bernstein(CTRL, U), atol=1e-14)
    lo, hi = curve.bezier_bbox(CTRL)
    dense = bernstein(CTRL, np.linspace(0, 1, 200001))
    assert (dense >= lo - 1e-15).all() and (dense <= hi + 1e-15).all()
    np.testing.assert_allclose(lo, dense.min(axis=0), atol=1e-9)
    np.testing.assert_allclose(hi, dense.max(axis=0), atol=1e-9)
    plo, phi = curve.bezier_bbox(CTRL, tight=False)
    assert np.array_equal(plo, CTRL.min(axis=0)) and np.array_equal(phi, CTRL.max(axis=0))
    with pytest.raises(geom.GeomError):
        curve.bezier_split(CTRL, 1.5)


def test_hermite_and_catmull_rom():
    p0, m0, p1, m1 = np.array([0., 1]), np.array([2., 0]), np.array([3., 2]), np.array([0., -4])
    for t in (0, 0.25, 0.6, 1):
        h = [2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2]
        dh = [6 * t**2 - 6 * t, 3 * t**2 - 4 * t + 1, -6 * t**2 + 6 * t, 3 * t**2 - 2 * t]
        d = curve.hermite_eval(p0, m0, p1, m1, t, nderiv=1)
        np.testing.assert_allclose(d[0], h[0] * p0 + h[1] * m0 + h[2] * p1 + h[3] * m1, atol=1e-14)
        np.testing.assert_allclose(d[1], dh[0] * p0 + dh[1] * m0 + dh[2] * p1 + dh[3] * m1, atol=1e-14)
    b = curve.hermite_to_bezier(p0, m0, p1, m1)
    np.testing.assert_allclose(b, [p0, p0 + m0 / 3, p1 - m1 / 3, p1], atol=0)
    P = np.array([[0., 0], [1, 2], [3, 3], [4, 0]])
    for s in (0, 0.3, 0.75, 1):
        want = 0.5 * (2 * P[1] + (-P[0] + P[2]) * s + (2 * P[0] - 5 * P[1] + 4 * P[2] - P[3]) * s**2
                      + (-P[0] + 3 * P[1] - 3 * P[2] + P[3]) * s**3)
        np.testing.assert_allclose(curve.catmull_rom_eval(*P, s, alpha=0), want, atol=1e-14)
    with pytest.raises(geom.GeomError):
        curve.catmull_rom_eval(P[0], P[1], P[1], P[3], 0.5, alpha=0.5)   # coincident points


def test_conics():
    e = geom.NurbsCurve.ellipse_arc([1, -2], [3, 0], [0, 2], 0.2, 5.0)
    p = e.eval(U)
    np.testing.assert_allclose(((p[:, 0] - 1) / 3) ** 2 + ((p[:, 1] + 2) / 2) ** 2, 1, atol=1e-14)
    np.testing.assert_allclose(p[0], [1 + 3 * math.cos(0.2), -2 + 2 * math.sin(0.2)], atol=1e-14)
    par = geom.NurbsCurve.conic([-1, 1], [1, -2], [1, 1], [1, 2], weight=1.0)   # y = x^2
    q = par.eval(U)
    np.testing.assert_allclose(q[:, 1], q[:, 0] ** 2, atol=1e-14)
    through = geom.NurbsCurve.conic([1, 0], [0, 1], [0, 1], [-1, 0], point=[0.8, 0.6])
    assert through.closest_point([0.8, 0.6])[2] < 1e-12
    with pytest.raises(geom.GeomError):
        geom.NurbsCurve.conic([0, 0], [1, 0], [1, 0], [1, 0])   # parallel tangents


def test_clamp_segments_periodic():
    rng = np.random.default_rng(3)
    P = rng.standard_normal((7, 3))
    c = geom.NurbsCurve.periodic(3, P)
    assert c.n == 10 and c.degree == 3
    d0, d1 = c.derivs(0.0, 2), c.derivs(1.0, 2, wrap=True)
    np.testing.assert_allclose(d0, d1, atol=1e-12)              # C^2 across u = 0 == 1
    cl = c.clamp()
    assert cl.knots[0] == cl.knots[3] and cl.knots[-1] == cl.knots[-4]
    u = np.linspace(*c.domain, 57)
    np.testing.assert_allclose(cl.eval(u), c.eval(u), atol=1e-13)
    pts, w, br = cl.bezier_segments()
    assert w is None and pts.shape == (7, 4, 3) and br[0] == 0 and br[-1] == 1
    for s in range(7):
        np.testing.assert_allclose(bernstein(pts[s], U), cl.eval(br[s] + (br[s + 1] - br[s]) * U),
                                   atol=1e-13)
    circ = geom.NurbsCurve.circle([0, 0], 2.0)
    pts, w, br = circ.bezier_segments()
    assert w.shape == (4, 3)   # rational: the weights per segment


def test_segment_distance_without_overflow():
    assert curve.segment_distance([0, 0], [1e300, 0], [5e299, 1e299]) == pytest.approx(1e299, rel=1e-15)
    assert curve.segment_distance([0, 0, 0], [0, 0, 0], [3, 4, 0]) == 5
    assert curve.segment_distance([0, 0], [2, 0], [-3, 4]) == 5


def test_extrude_ruled_revolve():
    circ = geom.NurbsCurve.circle([0, 0, 1], 2.0)
    ext = geom.NurbsSurface.extrude(circ, [0, 0, 3])
    uu, vv = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 7))
    p = ext.eval(uu.ravel(), vv.ravel())
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 2, atol=1e-14)
    np.testing.assert_allclose(p[:, 2], 1 + 3 * vv.ravel(), atol=1e-14)
    a = geom.NurbsCurve(1, [0, 0, 1, 1], [[0, 0, 0], [1, 0, 0]])
    b = geom.NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 1, 1], [0.5, 1.5, 1], [1, 1, 1]])
    r = geom.NurbsSurface.ruled(a, b)
    for u, v in ((0.2, 0.3), (0.7, 1.0), (1, 0.5)):
        np.testing.assert_allclose(r.eval(u, v), (1 - v) * a.eval(u) + v * b.eval(u), atol=1e-14)
    prof = geom.NurbsCurve(1, [0, 0, 1, 1], [[1.5, 0], [1.5, 2]])   # (radius, height)
    cyl = geom.NurbsSurface.revolve(prof, origin=[1, 1, 1], axis=[0, 0, 1])
    p = cyl.eval(uu.ravel(), vv.ravel())
    np.testing.assert_allclose(np.hypot(p[:, 0] - 1, p[:, 1] - 1), 1.5, atol=1e-14)
    np.testing.assert_allclose(p[:, 2], 1 + 2 * vv.ravel(), atol=1e-14)
    with pytest.raises(geom.GeomError):
        geom.NurbsSurface.revolve(prof, axis=[0, 0, 0])


def test_tess_estimate():
    t = geom.NurbsSurface.torus(2.0, 0.5)   # no poles: uniform is exact
    m, rep = geom.tessellate(t, mode="uniform", grid=(5, 3))
    assert geom.surface.tess_estimate(t, mode="uniform", grid=(5, 3)) == m.n_faces
    s = geom.NurbsSurface.sphere(1.0)
    m, rep = geom.tessellate(s, mode="uniform", grid=(5, 3))
    # the poles' collapsed triangles are dropped: the estimate counts them
    # (240 for 200 made; surface.h calls uniform mode exact)
    assert geom.surface.tess_estimate(s, mode="uniform", grid=(5, 3)) == 240 and m.n_faces == 200
    for tol in (1e-3, 1e-4):
        m, rep = geom.tessellate(s, tolerance=tol)
        est = geom.surface.tess_estimate(s, tolerance=tol)
        assert 0.5 <= est / m.n_faces <= 2.0, (tol, est, m.n_faces)
