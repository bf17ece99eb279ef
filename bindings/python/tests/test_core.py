"""core: version, statuses and GeomError, exact predicates against rational
arithmetic, and the 4x4 helpers against their closed forms."""

import math
import os
import re
from fractions import Fraction

import numpy as np
import pytest

import geom
from geom import core


def test_version_matches_header(include_dir):
    with open(os.path.join(include_dir, "core.h"), encoding="utf-8") as f:
        m = re.search(r'#define GEOM_VERSION_STRING "([^"]+)"', f.read())
    assert geom.version() == m.group(1) == geom.__version__


def test_status_table_matches_enum(include_dir):
    with open(os.path.join(include_dir, "core.h"), encoding="utf-8") as f:
        body = re.search(r"typedef enum geom_status \{(.*?)\}", f.read(), re.S).group(1)
    header = {k: int(v) for k, v in re.findall(r"GEOM_(\w+) = (-?\d+)", body)}
    assert header == core.STATUS
    names = {geom.status_name(v) for v in header.values()}
    assert len(names) == len(header)  # every status has its own name
    assert geom.status_name(0) == "ok"
    assert geom.status_name(-1000) == "unknown status"


needs_meshio = pytest.mark.skipif(not geom.has_module("meshio"), reason="no meshio module")


@needs_meshio
def test_error_carries_status_and_location(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    with pytest.raises(geom.GeomError) as info:
        geom.Mesh.read(path)
    e = info.value
    assert e.code == "ERR_PARSE" and e.status == core.STATUS["ERR_PARSE"]
    assert e.name == geom.status_name(e.status)
    assert e.source == str(path) and e.line == 4 and e.column > 0
    assert e.location.startswith("%s:4:%d: " % (path, e.column))
    assert e.message and e.message in e.location
    assert str(path) + ":4:" in str(e)


@needs_meshio
def test_io_error(tmp_path):
    with pytest.raises(geom.GeomError) as info:
        geom.Mesh.read(tmp_path / "missing.obj")
    assert info.value.code == "ERR_IO"


# ------------------------------------------------------------- predicates

def _frac_orient2d(a, b, c):
    a, b, c = ([Fraction(x) for x in p] for p in (a, b, c))
    return (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])


def _frac_orient3d(a, b, c, d):
    m = [[Fraction(p[k]) - Fraction(d[k]) for k in range(3)] for p in (a, b, c)]
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _frac_incircle(a, b, c, d):
    rows = []
    for p in (a, b, c):
        dx, dy = Fraction(p[0]) - Fraction(d[0]), Fraction(p[1]) - Fraction(d[1])
        rows.append((dx, dy, dx * dx + dy * dy))
    (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = rows
    return a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0)


def _sign(x):
    return int(x > 0) - int(x < 0)


def test_orient2d_exact_sign_near_degenerate():
    # Shewchuk's classic grid: points a few ulps around the line y = x,
    # where the naive determinant gets the sign wrong.
    ulp = 2.0 ** -53
    a = np.array([[0.5 + i * ulp, 0.5 + j * ulp] for i in range(24) for j in range(24)])
    b, c = np.array([12.0, 12.0]), np.array([24.0, 24.0])
    got = geom.orient2d(a, b, c)
    want = [_sign(_frac_orient2d(p, b, c)) for p in a]
    assert list(np.sign(got).astype(int)) == want
    naive = (a[:, 0] - c[0]) * (b[1] - c[1]) - (a[:, 1] - c[1]) * (b[0] - c[0])
    assert np.any(np.sign(naive) != want)  # the test would catch a naive formula
    # The exactly rounded determinant.
    ex = geom.orient2d_exact(a, b, c)
    assert all(e == float(_frac_orient2d(p, b, c)) for e, p in zip(ex, a))


def test_orient2d_scalar_vector_and_broadcast():
    rng = np.random.default_rng(1)
    a, b, c = rng.random((3, 50, 2))
    vec = geom.orient2d(a, b, c)
    assert vec.shape == (50,)
    for i in range(50):
        assert geom.orient2d(a[i], b[i], c[i]) == vec[i]
        assert _sign(vec[i]) == _sign(_frac_orient2d(a[i], b[i], c[i]))
    assert np.array_equal(geom.orient2d(a[0], b, c), [geom.orient2d(a[0], b[i], c[i])
                                                       for i in range(50)])
    assert isinstance(geom.orient2d([0, 0], [1, 0], [0, 1]), float)
    assert geom.orient2d([0, 0], [1, 0], [0, 1]) == 1.0
    assert math.isnan(geom.orient2d([0, 0], [1, 0], [0, np.nan]))
    with pytest.raises(ValueError):
        geom.orient2d(a, b[:10], c)


def test_orient3d_and_incircle_exact_signs():
    rng = np.random.default_rng(2)
    ulp = 2.0 ** -50
    # Nearly coplanar points: d on the plane z = x + y, perturbed by ulps.
    a, b, c = np.array([0.0, 0, 0]), np.array([1.0, 0, 1]), np.array([0.0, 1, 1])
    xy = rng.random((200, 2))
    d = np.column_stack([xy, xy[:, 0] + xy[:, 1] + rng.integers(-2, 3, 200) * ulp])
    got = geom.orient3d(a, b, c, d)
    assert [int(s) for s in np.sign(got)] == [_sign(_frac_orient3d(a, b, c, p)) for p in d]
    ex = geom.orient3d_exact(a, b, c, d)
    assert all(e == float(_frac_orient3d(a, b, c, p)) for e, p in zip(ex, d))
    # Nearly cocircular: points on the unit circle (rounded), and their ulp neighbours.
    t = rng.random(100) * 2 * np.pi
    q = np.column_stack([np.cos(t), np.sin(t)]) * (1 + rng.integers(-2, 3, (100, 1)) * ulp)
    A, B, C = [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]
    got = geom.incircle(A, B, C, q)
    assert [int(s) for s in np.sign(got)] == [_sign(_frac_incircle(A, B, C, p)) for p in q]


# --------------------------------------------------------------- matrices

def test_perspective_closed_form():
    fovy, aspect, n, f = 0.9, 1.6, 0.5, 40.0
    M = core.perspective(fovy, aspect, n, f)
    t = 1 / math.tan(fovy / 2)
    want = np.array([[t / aspect, 0, 0, 0], [0, t, 0, 0],
                     [0, 0, (f + n) / (n - f), 2 * f * n / (n - f)], [0, 0, -1, 0]])
    assert np.allclose(M, want, rtol=1e-15, atol=0)
    # Depth maps -near to -1 and -far to +1 after the divide.
    assert np.allclose(core.transform_point(M, [[0, 0, -n], [0, 0, -f]])[:, 2], [-1, 1])
    with pytest.raises(geom.GeomError) as info:
        core.perspective(0.0, 1.0, 0.1, 10)
    assert info.value.code == "ERR_DOMAIN"


def test_lookat_and_orientation():
    eye, center, up = np.array([1.0, 2, 3]), np.array([1.0, 2, -4]), np.array([0.0, 1, 0])
    V = core.lookat(eye, center, up)
    assert np.allclose(V @ np.append(eye, 1), [0, 0, 0, 1], atol=1e-15)
    assert np.allclose(V @ np.append(center, 1), [0, 0, -7, 1], atol=1e-14)
    R = V[:3, :3]
    assert np.allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.allclose(V[3], [0, 0, 0, 1])
    with pytest.raises(geom.GeomError) as info:
        core.lookat(eye, eye, up)
    assert info.value.code == "ERR_DEGENERATE"


def test_inverse_and_storage_order():
    rng = np.random.default_rng(3)
    for _ in range(20):
        M = rng.normal(size=(4, 4)) + 4 * np.eye(4)
        inv = core.inverse(M)
        assert np.allclose(inv, np.linalg.inv(M), rtol=1e-12, atol=1e-14)
        assert np.isclose(core.determinant(M), np.linalg.det(M), rtol=1e-12)
    T = core.translate([1, 2, 3])
    assert np.array_equal(T[:3, 3], [1, 2, 3])  # row-major view of a column-major matrix
    assert np.allclose(core.transform_point(T, [1, 1, 1]), [2, 3, 4])
    Rz = core.rotate([0, 0, 1], math.pi / 2)
    assert np.allclose(Rz @ [1, 0, 0, 1], [0, 1, 0, 1], atol=1e-16)
    S = core.scale([2, 3, 4])
    assert np.allclose(core.normal_matrix(S), np.diag([1 / 2, 1 / 3, 1 / 4]))
    with pytest.raises(geom.GeomError) as info:
        core.inverse(np.ones((4, 4)))
    assert info.value.code == "ERR_DEGENERATE"
    # Round trip through the C layout.
    M = rng.normal(size=(4, 4))
    assert np.array_equal(core.from_mat4(core.to_mat4(M)), M)


def test_predicates_batch_bitwise_single_rows():
    """The predicates over arrays (geom_predicate_many) give bitwise each
    row's single-point result: random, nearly collinear, 1e8 offsets,
    NaN/Inf rows, one point broadcast."""
    rng = np.random.default_rng(7)
    n = 400
    P = [rng.integers(-2**20, 2**20, (n, 3)) * 2.0**-20 for _ in range(4)]
    t = rng.integers(0, 1024, n)[:, None] * 2.0**-10
    P[2][::3] = (P[0] + (P[1] - P[0]) * t)[::3]
    P[0][1::5] += 1e8
    P[1][1::5] += 1e8
    P[2][1::5] += 1e8
    P[3][1::5] += 1e8
    P[1][5, 0] = np.nan
    P[3][11, 1] = np.inf
    fns = [(core.orient2d, 2, 3), (core.orient3d, 3, 4), (core.incircle, 2, 4),
           (core.orient2d_exact, 2, 3), (core.orient3d_exact, 3, 4)]
    for fn, dim, k in fns:
        args = [p[:, :dim] for p in P[:k]]
        got = fn(*args)
        assert got.shape == (n,)
        want = np.array([fn(*[a[i] for a in args]) for i in range(n)])
        assert ((got.view(np.uint64) == want.view(np.uint64)) |
                (np.isnan(got) & np.isnan(want))).all(), fn.__name__
        assert np.isnan(got[5])
        shared = fn(args[0][0], *args[1:])
        want = np.array([fn(args[0][0], *[a[i] for a in args[1:]]) for i in range(n)])
        assert ((shared.view(np.uint64) == want.view(np.uint64)) |
                (np.isnan(shared) & np.isnan(want))).all(), fn.__name__
    # exact zeros on the collinear rows (orient2d of c = a + (b - a) t in exact dyadics)
    z = core.orient2d(P[0][::3, :2], P[1][::3, :2], P[2][::3, :2])
    assert z.size and np.isfinite(z).all()
    assert core.orient2d(np.empty((0, 2)), [0, 0], [1, 1]).shape == (0,)
    with pytest.raises(ValueError):
        core.orient2d(np.zeros((3, 2)), np.zeros((4, 2)), [0, 0])
