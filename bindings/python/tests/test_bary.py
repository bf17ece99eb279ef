"""bary: coordinates reproduce their points, closed forms (bilinear
Wachspress weights on a rectangle, barycentrics from mean value coordinates
on a triangle), exact zeros on edges, and the error modes."""

from fractions import Fraction

import numpy as np
import pytest

import geom
from geom import bary


def test_tri2_reproduces_points_and_matches_solve():
    rng = np.random.default_rng(10)
    a, b, c = rng.normal(size=(3, 2))
    p = rng.normal(size=(500, 2)) * 3
    l = bary.tri2(a, b, c, p)
    assert l.shape == (500, 3)
    assert np.allclose(l @ np.array([a, b, c]), p, atol=1e-12)
    assert np.allclose(l.sum(axis=1), 1, atol=1e-12)
    A = np.array([[a[0], b[0], c[0]], [a[1], b[1], c[1]], [1, 1, 1]])
    want = np.linalg.solve(A, np.column_stack([p, np.ones(len(p))]).T).T
    assert np.allclose(l, want, rtol=1e-10, atol=1e-12)
    # One row equals the scalar call.
    assert np.array_equal(bary.tri2(a, b, c, p[7]), l[7])


def test_tri2_exact_on_edges_and_vertices():
    a, b, c = [0.1, 0.2], [3.7, 0.2], [0.1, 5.3]
    assert list(bary.tri2(a, b, c, a)) == [1.0, 0.0, 0.0]
    mid = [(0.1 + 3.7) / 2, 0.2]  # on the edge ab (same y)
    l = bary.tri2(a, b, c, mid)
    assert l[2] == 0.0
    # Rational reference for a point one ulp off the edge: the sign is exact.
    p = [mid[0], np.nextafter(0.2, 1.0)]
    l = bary.tri2(a, b, c, p)
    fa, fb, fc, fp = ([Fraction(x) for x in q] for q in (a, b, c, p))
    area = (fb[0] - fa[0]) * (fc[1] - fa[1]) - (fb[1] - fa[1]) * (fc[0] - fa[0])
    l2 = ((fb[0] - fa[0]) * (fp[1] - fa[1]) - (fb[1] - fa[1]) * (fp[0] - fa[0])) / area
    assert l[2] > 0 and abs(l[2] - float(l2)) <= 1e-12 * abs(float(l2))


def test_tri3_projects_and_tet_reproduces():
    rng = np.random.default_rng(11)
    a, b, c = rng.normal(size=(3, 3))
    n = np.cross(b - a, c - a)
    q = rng.random((100, 3)) @ np.array([a, b, c]) / 1.5
    l_in = bary.tri3(a, b, c, q)
    # Moving a point along the normal does not change its coordinates.
    l_off = bary.tri3(a, b, c, q + rng.normal(size=(100, 1)) * n)
    assert np.allclose(l_in, l_off, atol=1e-12)
    proj = q - ((q - a) @ n)[:, None] / (n @ n) * n
    assert np.allclose(l_in @ np.array([a, b, c]), proj, atol=1e-12)
    d = rng.normal(size=3)
    p = rng.normal(size=(100, 3))
    l = bary.tet(a, b, c, d, p)
    assert l.shape == (100, 4)
    assert np.allclose(l @ np.array([a, b, c, d]), p, atol=1e-11)
    assert np.allclose(l.sum(axis=1), 1, atol=1e-12)


def test_degenerate_raises_or_gives_nan():
    a, b, c = [0, 0], [1, 1], [2, 2]  # collinear
    with pytest.raises(geom.GeomError) as info:
        bary.tri2(a, b, c, [0.5, 0.0])
    assert info.value.code == "ERR_DEGENERATE"
    # Vectorised: the failing row is named; with errors="nan" it becomes NaN.
    A = np.array([[0, 0], [0, 0], [0, 0]], dtype=float)
    B = np.array([[1, 0], [1, 1], [1, 0]], dtype=float)
    C = np.array([[0, 1], [2, 2], [0, 1]], dtype=float)
    P = np.full((3, 2), 0.25)
    with pytest.raises(geom.GeomError, match=r"row 1"):
        bary.tri2(A, B, C, P)
    l = bary.tri2(A, B, C, P, errors="nan")
    assert np.isnan(l[1]).all()
    assert np.allclose(l[[0, 2]], [[0.5, 0.25, 0.25]] * 2)
    with pytest.raises(geom.GeomError) as info:
        bary.tri2([0, 0], [1, 0], [0, 1], [np.inf, 0])
    assert info.value.code == "ERR_INVALID_ARG"
    with pytest.raises(geom.GeomError) as info:
        bary.tet([0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0.2, 0.2, 0.2])
    assert info.value.code == "ERR_DEGENERATE"
    with pytest.raises(ValueError):
        bary.tri2(a, b, c, [0, 0], errors="ignore")


def test_mean_value_linear_precision_nonconvex():
    L = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], dtype=float)
    rng = np.random.default_rng(12)
    p = rng.random((400, 2)) * 2
    inside = ~((p[:, 0] > 1) & (p[:, 1] > 1))
    p = p[inside]
    w = bary.mean_value(L, p)
    assert w.shape == (len(p), 6)
    assert np.allclose(w.sum(axis=1), 1, atol=1e-13)
    assert np.allclose(w @ L, p, atol=1e-12)
    # On a triangle, mean value coordinates are the barycentric coordinates.
    T = np.array([[0, 0], [3, 0.5], [1, 2]])
    q = rng.random((50, 2))
    assert np.allclose(bary.mean_value(T, q), bary.tri2(T[0], T[1], T[2], q), atol=1e-13)
    # At a vertex: exactly 1 there.
    assert list(bary.mean_value(L, L[3])) == [0, 0, 0, 1, 0, 0]


def test_wachspress_is_bilinear_on_a_rectangle():
    R = np.array([[0, 0], [2, 0], [2, 3], [0, 3]], dtype=float)
    rng = np.random.default_rng(13)
    p = rng.random((200, 2)) * [2, 3]
    w = bary.wachspress(R, p)
    s, t = p[:, 0] / 2, p[:, 1] / 3
    want = np.column_stack([(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t])
    assert np.allclose(w, want, atol=1e-13)
    hexagon = np.column_stack([np.cos(np.arange(6) * np.pi / 3), np.sin(np.arange(6) * np.pi / 3)])
    q = (rng.random((100, 2)) - 0.5) * 1.2
    assert np.allclose(bary.wachspress(hexagon, q) @ hexagon, q, atol=1e-13)
    with pytest.raises(geom.GeomError) as info:
        bary.wachspress(R, [5, 5])
    assert info.value.code == "ERR_DOMAIN"
    L = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], dtype=float)
    with pytest.raises(geom.GeomError) as info:
        bary.wachspress(L, [0.5, 0.5])
    assert info.value.code == "ERR_DOMAIN"
    out = bary.wachspress(R, [[1, 1], [5, 5]], errors="nan")
    assert np.isnan(out[1]).all() and np.allclose(out[0].sum(), 1)


def test_perspective_weights_closed_form():
    rng = np.random.default_rng(14)
    l = rng.random((100, 3))
    l /= l.sum(axis=1, keepdims=True)
    w = rng.random((100, 3)) + 0.5
    want = (l / w) / (l / w).sum(axis=1, keepdims=True)
    assert np.allclose(bary.perspective(l, w), want, rtol=1e-14)
    # Broadcasting one set of w; and a zero w is degenerate.
    assert np.allclose(bary.perspective(l, w[0]),
                       (l / w[0]) / (l / w[0]).sum(axis=1, keepdims=True), rtol=1e-14)
    with pytest.raises(geom.GeomError) as info:
        bary.perspective([1 / 3] * 3, [1, 0, 1])
    assert info.value.code == "ERR_DEGENERATE"


def test_interpolate():
    attr = np.array([[1.0, 10], [2, 20], [3, 30]])
    assert np.allclose(bary.interpolate([0.2, 0.3, 0.5], attr), [0.2 + 0.6 + 1.5, 23])
    W = np.random.default_rng(15).random((10, 3))
    assert np.allclose(bary.interpolate(W, attr), W @ attr)


def test_shared_simplex_batch_edges():
    """One triangle (tetrahedron) for many points takes the lane loop: every
    row equals the single-point call bitwise (tri2) or within the stated
    accuracy (tet), exact zeros and ones on edges and vertices in any row of
    a block, a NaN row raises naming it or is NaN alone, a degenerate
    simplex raises."""
    a, b, c = np.array([0.1, 0.2]), np.array([3.7, 0.2]), np.array([0.1, 5.3])
    rng = np.random.default_rng(20)
    p = rng.uniform(-1, 5, (203, 2))          # 12 full blocks of 16 and a tail
    p[17] = a                                  # a vertex inside a block
    p[64] = [(0.1 + 3.7) / 2, 0.2]             # on edge ab at a block start
    p[202] = c                                 # the tail
    l = bary.tri2(a, b, c, p)
    for i in (0, 15, 16, 17, 63, 64, 65, 200, 202):
        assert np.array_equal(l[i], bary.tri2(a, b, c, p[i]))
    assert list(l[17]) == [1.0, 0.0, 0.0] and list(l[202]) == [0.0, 0.0, 1.0]
    assert l[64][2] == 0.0
    q = p.copy()
    q[33, 1] = np.nan
    with pytest.raises(geom.GeomError, match=r"row 33") as info:
        bary.tri2(a, b, c, q)
    assert info.value.code == "ERR_INVALID_ARG"
    ln = bary.tri2(a, b, c, q, errors="nan")
    assert np.isnan(ln[33]).all()
    keep = np.arange(len(p)) != 33
    assert np.array_equal(ln[keep], l[keep])
    with pytest.raises(geom.GeomError) as info:
        bary.tri2([0, 0], [1, 1], [2, 2], p)   # collinear: every row
    assert info.value.code == "ERR_DEGENERATE" and "row 0" in str(info.value)
    assert np.isnan(bary.tri2([0, 0], [1, 1], [2, 2], p, errors="nan")).all()
    with pytest.raises(geom.GeomError):
        bary.tri2(a, b, [np.nan, 0.0], p)      # NaN vertex
    T = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float) + 1e8
    x = rng.uniform(-0.5, 1, (99, 3)) + 1e8
    x[5] = T[2]
    x[40] = (T[0] + T[1] + T[3]) / 3           # on the face opposite vertex 2
    x[70, 0] = np.inf
    lt = bary.tet(*T, x, errors="nan")
    assert list(lt[5]) == [0.0, 0.0, 1.0, 0.0] and lt[40][2] == 0.0
    assert np.isnan(lt[70]).all() and not np.isnan(np.delete(lt, 70, axis=0)).any()
    for i in (0, 5, 16, 40, 98):
        assert np.allclose(lt[i], bary.tet(*T, x[i]), rtol=5e-13, atol=0)
    with pytest.raises(geom.GeomError, match=r"row 70"):
        bary.tet(*T, x)
    with pytest.raises(geom.GeomError) as info:
        bary.tet(T[0], T[1], T[2], T[0] + T[1] - T[2], x)   # coplanar
    assert info.value.code == "ERR_DEGENERATE"


def _bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def test_perspective_batch_bitwise_single_rows_and_edges():
    """bary.perspective over arrays (geom_bary_perspective_many) gives
    bitwise each row's single-point result, and the failing rows of the
    single function (zero w, vanishing sum, NaN/Inf) fail with its status."""
    rng = np.random.default_rng(5)
    l = rng.random((300, 3))
    w = 0.1 + 10 * rng.random((300, 3))
    w[1, 2] = 0.0                                  # zero w
    l[2], w[2] = [1, -1, 0], [2, 2, 3]             # the sum vanishes
    w[3] = [1e-300, 1e300, -1e-310]                # the rescaled path
    l[4, 1] = np.nan
    w[5, 0] = np.inf
    w[6, 0] = -1.0                                 # mixed signs
    got = bary.perspective(l, w, errors="nan")
    bad = []
    for i in range(300):
        try:
            want = bary.perspective(l[i], w[i])
        except geom.GeomError as e:
            bad.append((i, e.status))
            assert np.isnan(got[i]).all()
            continue
        assert (_bits(got[i]) == _bits(want)).all(), i
    assert [i for i, _ in bad] == [1, 2, 4, 5]
    assert bad[0][1] == geom.STATUS["ERR_DEGENERATE"]
    assert bad[2][1] == geom.STATUS["ERR_INVALID_ARG"]
    with pytest.raises(geom.GeomError, match=r"row 1"):
        bary.perspective(l, w)
    # a shared w (broadcast, stride 0) is each row with that w
    shared = bary.perspective(l[7:], w[0])
    assert (_bits(shared) == _bits(bary.perspective(l[7:], np.tile(w[0], (293, 1))))).all()
    # the closed form on the ordinary rows (numpy overflows on row 3)
    ok = np.setdiff1d(np.arange(300), [1, 2, 3, 4, 5])
    q = l[ok] / w[ok]
    assert np.allclose(got[ok], q / q.sum(axis=1, keepdims=True), rtol=1e-12, atol=0)


def test_interpolate_batch_bitwise_single_rows():
    rng = np.random.default_rng(6)
    W = rng.random((200, 4)) * 2 - 0.5
    A = 1e8 + rng.random((4, 5))
    W[3, 1] = np.nan
    got = bary.interpolate(W, A)
    for i in range(200):
        want = bary.interpolate(W[i], A)
        assert (np.isnan(got[i]) == np.isnan(want)).all()
        fin = ~np.isnan(want)
        assert (_bits(got[i][fin]) == _bits(want[fin])).all()
    assert np.isnan(got[3]).all()
    assert np.allclose(np.delete(got, 3, 0), np.delete(W, 3, 0) @ A, rtol=1e-15)
    assert bary.interpolate(np.empty((0, 4)), A).shape == (0, 5)
    with pytest.raises(ValueError):
        bary.interpolate(np.ones((3, 2)), A)
