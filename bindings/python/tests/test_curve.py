"""curve: exact circles and arcs, B-spline evaluation and derivatives
against the Bernstein closed form, knot insertion and degree elevation keep
the curve, arc length, closest points and polylines against geometry."""

import math

import numpy as np
import pytest

import geom
from geom.curve import NurbsCurve, bezier_derivs, bezier_eval, uniform_knots

pytestmark = pytest.mark.skipif(not geom.has_module("curve"), reason="no curve module")


def test_circle_is_exact():
    c = NurbsCurve.circle([1.0, -2.0], 3.0)
    assert c.rational and c.n == 9 and c.degree == 2 and c.domain == (0.0, 1.0)
    assert np.array_equal(c(0.0), [4.0, -2.0])  # clamped end: the control point exactly
    u = np.linspace(0, 1, 1001)
    P = c(u)
    assert P.shape == (1001, 2)
    assert np.max(np.abs(np.hypot(P[:, 0] - 1, P[:, 1] + 2) - 3)) < 1e-14
    kappa, tors = c.curvature(u[:-1])
    assert tors is None and np.allclose(kappa, 1 / 3, rtol=1e-12)  # counter-clockwise: > 0
    length, rep = c.arc_length()
    assert length == pytest.approx(6 * math.pi, rel=1e-13)
    assert rep["method"] == "estimate" and rep["max_error"] < 1e-10
    # 3D circle in the plane spanned by two orthonormal axes.
    x = np.array([1, 1, 0]) / math.sqrt(2)
    y = np.array([0, 0, 1.0])
    c3 = NurbsCurve.circle([0, 0, 0], 2.0, x, y)
    P = c3(u)
    assert np.allclose(np.linalg.norm(P, axis=1), 2, atol=1e-14)
    assert np.allclose(P @ np.cross(x, y), 0, atol=1e-14)
    k, t = c3.curvature(0.3)
    assert k == pytest.approx(0.5) and t == pytest.approx(0, abs=1e-12)


def test_arc_closest_point_and_polyline():
    arc = NurbsCurve.arc([0, 0], 1.0, 0.0, math.pi / 2 * 3)
    assert np.allclose(arc(1.0), [0, -1], atol=1e-15)
    length, _ = arc.arc_length()
    assert length == pytest.approx(1.5 * math.pi, rel=1e-13)
    u, p, d = arc.closest_point([2.0, 2.0])
    assert np.allclose(p, [math.sqrt(0.5)] * 2, atol=1e-12)
    assert d == pytest.approx(2 * math.sqrt(2) - 1, rel=1e-13)
    tol = 1e-4
    params, pts, rep = arc.polyline(tolerance=tol)
    assert rep["method"] == "bound" and rep["max_error"] <= tol
    assert np.allclose(np.linalg.norm(pts, axis=1), 1, atol=1e-14)
    # Sagitta of each chord of the unit circle: 1 - cos(theta / 2) <= tol.
    theta = np.diff(np.unwrap(np.arctan2(pts[:, 1], pts[:, 0])))
    assert np.all(1 - np.cos(theta / 2) <= tol * (1 + 1e-9))
    assert np.allclose(arc(params), pts)


def test_bspline_matches_bernstein_and_derivatives():
    ctrl = np.array([[0, 0], [1, 3], [3, -1], [4, 2]], dtype=float)
    c = NurbsCurve(3, [0, 0, 0, 0, 1, 1, 1, 1], ctrl)
    t = np.linspace(0, 1, 9)
    B = np.column_stack([(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t ** 2 * (1 - t), t ** 3])
    assert np.allclose(c(t), B @ ctrl, atol=1e-15)
    assert np.allclose(bezier_eval(ctrl, t), B @ ctrl, atol=1e-15)
    d = c.derivs(t, 3)
    assert d.shape == (9, 4, 2)
    D1 = 3 * np.column_stack([(1 - t) ** 2, 2 * t * (1 - t), t ** 2]) @ np.diff(ctrl, axis=0)
    D2 = 6 * np.column_stack([1 - t, t]) @ np.diff(ctrl, 2, axis=0)
    D3 = 6 * np.diff(ctrl, 3, axis=0)
    assert np.allclose(d[:, 1], D1, atol=1e-13)
    assert np.allclose(d[:, 2], D2, atol=1e-12)
    assert np.allclose(d[:, 3], np.repeat(D3, 9, axis=0), atol=1e-12)
    assert np.allclose(bezier_derivs(ctrl, 0.3, 2), c.derivs(0.3, 2), atol=1e-14)


def test_knot_insertion_and_elevation_keep_the_curve():
    rng = np.random.default_rng(30)
    pts = rng.normal(size=(7, 3))
    w = rng.random(7) + 0.5
    c = NurbsCurve(3, uniform_knots(3, 7), pts, w)
    u = np.linspace(0, 1, 57)
    c2 = c.insert_knot(0.37, 2)
    assert c2.n == 9 and c2.knots.size == c.knots.size + 2
    assert np.allclose(c2(u), c(u), atol=1e-13)
    c3 = c.elevate(2)
    assert c3.degree == 5 and np.allclose(c3(u), c(u), atol=1e-12)
    with pytest.raises(ValueError):
        c.points[0, 0] = 1  # read-only: the C struct points at these arrays


def test_invalid_curves_and_domain():
    with pytest.raises(geom.GeomError) as info:
        NurbsCurve(2, [0, 0, 0, 0.5, 0.2, 1, 1, 1], np.zeros((5, 2)))
    assert info.value.code == "ERR_INVALID_ARG" and "knot" in info.value.message
    c = NurbsCurve(1, [0, 0, 1, 2, 2], [[0, 0], [1, 1], [2, 0]])
    with pytest.raises(geom.GeomError) as info:
        c(2.5)
    assert info.value.code == "ERR_DOMAIN"
    # Left and right limits at the interior knot of a degree-1 curve: the
    # point is the same, the derivatives differ.
    assert np.allclose(c.derivs(1.0, 1)[1], [1, -1])
    assert np.allclose(c.derivs(1.0, 1, left=True)[1], [1, 1])
    assert np.allclose(c(2.5, wrap=True), c(0.5))


def test_eval_batch_matches_single_and_raises_on_nan():
    """The batch evaluation equals the scalar one bitwise in every row
    (blocks of one span and mixed spans, a tail block), exact control
    points at the clamped ends; a NaN parameter raises naming it, one
    outside the domain raises ERR_DOMAIN."""
    rng = np.random.default_rng(30)
    knots = np.concatenate([[0] * 4, [0.2, 0.5, 0.5, 0.9], [1] * 4])
    P = rng.normal(size=(8, 3))
    w = rng.uniform(0.5, 2, 8)
    for crv in (geom.curve.NurbsCurve(3, knots, P), geom.curve.NurbsCurve(3, knots, P, w)):
        u = np.concatenate([rng.uniform(0, 1, 250), knots, np.full(37, 0.3)])
        X = crv.eval(u)
        for i in range(0, u.size, 7):
            assert np.array_equal(X[i], crv.eval(u[i]))
        assert np.array_equal(crv.eval([0.0, 1.0]), P[[0, -1]])
        with pytest.raises(geom.GeomError, match="nan") as info:
            crv.eval(np.concatenate([u, [np.nan]]))
        assert info.value.code == "ERR_INVALID_ARG"
        with pytest.raises(geom.GeomError) as info:
            crv.eval([0.5, 1.5])
        assert info.value.code == "ERR_DOMAIN"


def test_polyline_estimate_bounds_the_count():
    """polyline_estimate is at least the polyline's count for polynomial
    curves (a bound) and says it is only an estimate for rational ones."""
    rng = np.random.default_rng(31)
    for trial in range(40):
        p = 1 + trial % 4
        n = p + 1 + trial % 5
        knots = np.concatenate([[0] * (p + 1), np.sort(rng.uniform(0, 1, n - p - 1)),
                                [1] * (p + 1)])
        crv = geom.curve.NurbsCurve(p, knots, rng.normal(size=(n, 2)))
        for tol in (0.0, 1e-2, 1e-5):
            est, is_bound = crv.polyline_estimate(tol)
            assert is_bound and est >= len(crv.polyline(tol)[0])
    s = np.sqrt(0.5)
    circle = geom.curve.NurbsCurve(
        2, [0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1],
        [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]],
        [1, s, 1, s, 1, s, 1, s, 1])
    est, is_bound = circle.polyline_estimate(1e-3)
    assert not is_bound and 1.0 <= est / len(circle.polyline(1e-3)[0]) <= 1.2
    with pytest.raises(geom.GeomError):
        circle.polyline_estimate(-1.0)
