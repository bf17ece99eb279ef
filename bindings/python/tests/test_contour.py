"""geom.implicit.contour (marching squares, geom_implicit_contour) against
closed forms: refined vertices on the unit circle, counter-clockwise loops
around the inside, the enclosed area, separate loops of separate circles,
open polylines ending on the border, a Python function field, and the
estimates against the result."""

import math

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("implicit"), reason="no implicit module")


def area(xy, loop):
    p = xy[loop]
    q = np.roll(p, -1, axis=0)
    return 0.5 * np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1])


def test_circle_refined_on_the_circle():
    xy, lines, closed, rep = geom.implicit.contour("x*x + y*y - 1", (-1.7, -1.3, 1.6, 1.45), (64, 57))
    assert len(lines) == 1 and closed.all()
    np.testing.assert_allclose(np.hypot(xy[:, 0], xy[:, 1]), 1, atol=1e-15)
    a = area(xy, lines[0])
    assert 0 < a < math.pi and a == pytest.approx(math.pi, rel=2e-3)   # inscribed, ccw
    assert rep["error"]["max_error"] <= 1e-15 and rep["cells"] == 64 * 57


def test_linear_interpolation_and_two_loops():
    f = "min(sqrt((x-1)^2 + y^2), sqrt((x+1)^2 + y^2)) - 0.5"
    xy, lines, closed, rep = geom.implicit.contour(f, (-2, -1, 2, 1), (80, 40), refine=False)
    assert len(lines) == 2 and closed.all() and rep["refined"] == 0
    for ln in lines:
        c = 1 if xy[ln][:, 0].mean() > 0 else -1
        d = np.hypot(xy[ln][:, 0] - c, xy[ln][:, 1])
        assert np.abs(d - 0.5).max() <= (4 / 80) ** 2   # O(h^2) chordal error of the cones
        assert area(xy, ln) > 0


def test_open_line_and_python_function():
    xy, lines, closed, _ = geom.implicit.contour(lambda p: p[:, 1] - 0.3 * p[:, 0], (-1, -1, 1, 1),
                                                 (10, 10), iso=0.1)
    assert len(lines) == 1 and not closed[0]
    np.testing.assert_allclose(xy[:, 1] - 0.3 * xy[:, 0], 0.1, atol=1e-14)
    assert set(np.round(xy[lines[0][[0, -1]], 0], 12)) == {-1.0, 1.0}   # ends on the border


def test_estimates_and_errors():
    v, cells = geom.implicit.contour_estimate("x*x + y*y - 1", (-2, -2, 2, 2), (400, 400))
    xy, _, _, rep = geom.implicit.contour("x*x + y*y - 1", (-2, -2, 2, 2), (400, 400))
    assert 0.8 <= v / len(xy) <= 1.25 and cells < 400 * 400   # far blocks skipped
    with pytest.raises(geom.GeomError):
        geom.implicit.contour("x", (0, 0, 0, 1), (4, 4))


def test_contour_mesh_matches_the_arrays():
    f = "min(sqrt((x-1)^2 + y^2), sqrt((x+1)^2 + y^2)) - 0.5"
    xy, lines, closed, rep = geom.implicit.contour(f, (-2, -1, 2, 1), (80, 40))
    m, rep2 = geom.implicit.contour_mesh(f, (-2, -1, 2, 1), (80, 40), z=0.25)
    assert rep2["cells"] == rep["cells"] and m.n_faces == 0
    p = m.positions
    np.testing.assert_array_equal(p[:, :2], xy)
    assert np.all(p[:, 2] == 0.25)
    pl = m.polylines
    assert len(pl) == len(lines)
    for got, want, c in zip(pl, lines, closed):      # closed loops repeat their first vertex
        assert c and np.array_equal(got, np.r_[want, want[0]])
    assert b"\nl " in m.to_bytes("obj")
    with pytest.raises(geom.GeomError):
        geom.implicit.contour_mesh(f, (-2, -1, 2, 1), (8, 4), z=float("nan"))
