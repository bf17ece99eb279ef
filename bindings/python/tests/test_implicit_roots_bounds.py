"""geom.implicit.bracket_root (the library's root finder) against closed
forms, jumps, exact zeros and an iteration cap; Expression.bounds (interval
bounds with definedness) against dense random samples of the box."""

import math

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("implicit"), reason="implicit not built")


def ulps(a, b):
    """Distance between two doubles in units in the last place."""
    return abs(a - b) / math.ulp(max(abs(a), abs(b)))


class Counter:
    def __init__(self, f):
        self.f, self.calls = f, 0

    def __call__(self, x):
        self.calls += 1
        return self.f(x)


@pytest.mark.parametrize("f,a,b,root", [
    (lambda x: x * x - 2, 1.0, 2.0, math.sqrt(2)),
    (lambda x: 2 - x * x, 1.0, 2.0, math.sqrt(2)),           # decreasing
    (math.cos, 1.0, 2.0, math.pi / 2),
    (lambda x: math.exp(x) - 10, 0.0, 5.0, math.log(10)),
    (lambda x: x ** 9 - 0.5, 0.0, 1.5, 0.5 ** (1 / 9)),       # flat then steep
    (lambda x: x - (1e8 + 0.1), 1e8, 1e8 + 1, 1e8 + 0.1),     # 1e8 offset
])
def test_roots_to_one_ulp(f, a, b, root):
    fc = Counter(f)
    r, evals = geom.implicit.bracket_root(fc, a, b, fa=f(a), fb=f(b))
    assert a < r < b
    assert ulps(r, root) <= 2, (r, root)
    assert evals == fc.calls and 1 <= evals <= 100
    # fn(a), fn(b) computed by the wrapper when not given: two more calls
    fc2 = Counter(f)
    r2, evals2 = geom.implicit.bracket_root(fc2, a, b)
    assert r2 == r and evals2 == evals and fc2.calls == evals + 2


def test_exact_zero_is_returned():
    r, evals = geom.implicit.bracket_root(lambda x: x - 1.5, 1.0, 2.0, x=1.5)
    assert r == 1.5 and evals == 1


def test_jump_gives_a_point_next_to_it():
    c = 0.3
    r, _ = geom.implicit.bracket_root(lambda x: -1.0 if x < c else 1.0, 0.0, 1.0)
    assert r in (c, math.nextafter(c, 0)), r


def test_start_outside_moves_to_the_midpoint_and_cap():
    fc = Counter(lambda x: x * x * x - 0.001)
    r, evals = geom.implicit.bracket_root(fc, 0.0, 1.0, x=5.0, max_iterations=3)
    assert evals == 3 and fc.calls == 5 and 0 < r < 1     # + fn(a), fn(b)
    r, _ = geom.implicit.bracket_root(lambda x: x * x * x - 0.001, 0.0, 1.0, x=-1.0)
    assert ulps(r, 0.1) <= 2


def test_nan_stops_and_exceptions_propagate():
    r, evals = geom.implicit.bracket_root(lambda x: math.nan, 0.0, 1.0, fa=-1.0, fb=1.0)
    assert 0 < r < 1 and evals == 1

    def boom(x):
        if boom.n == 2:
            raise ZeroDivisionError("from the callback")
        boom.n += 1
        return x * x * x - 0.3
    boom.n = 0
    with pytest.raises(ZeroDivisionError, match="from the callback"):
        geom.implicit.bracket_root(boom, 0.0, 1.0, fa=-0.3, fb=0.7)
    assert boom.n == 2


def test_bad_brackets():
    f = lambda x: x - 0.5  # noqa: E731
    with pytest.raises(ValueError):
        geom.implicit.bracket_root(f, 1.0, 0.0)
    with pytest.raises(ValueError):
        geom.implicit.bracket_root(f, 1.0, 1.0)
    with pytest.raises(ValueError):
        geom.implicit.bracket_root(f, 0.6, 1.0)                # same signs
    with pytest.raises(ValueError):
        geom.implicit.bracket_root(f, 0.5, 1.0)                # f(a) == 0: not strict
    with pytest.raises(ValueError):
        geom.implicit.bracket_root(f, 0.0, 1.0, fa=math.nan)
    with pytest.raises(ValueError):
        geom.implicit.bracket_root(f, 0.0, 1.0, max_iterations=0)


# ------------------------------------------------------------------ bounds

EXPRS = [
    "x*x + y*y + z*z - 1",
    "sphere(1)",
    "torus(1, 0.3)",
    "smooth_union(sphere(1), torus(1.2, 0.3), 0.2)",
    "sin(3*x)*y - z*z*z",
    "x*y*z",
    "abs(x) + max(y, z) - min(x, 2)",
    "exp(x) - cos(y*z)",
]


@pytest.mark.parametrize("text", EXPRS)
def test_bounds_enclose_random_samples(text):
    e = geom.Expression(text)
    rng = np.random.default_rng(17)
    for _ in range(12):
        c = rng.uniform(-1.5, 1.5, 3)
        r = rng.uniform(0, 0.8, 3)
        r[rng.integers(0, 3)] *= rng.integers(0, 2)         # sometimes flat
        lo, hi = c - r, c + r
        low, up, defined = e.bounds(lo, hi)
        assert defined and low <= up
        p = lo + (hi - lo) * rng.random((4000, 3))
        p = np.vstack([p, lo, hi, np.array(np.meshgrid(*zip(lo, hi))).reshape(3, -1).T])
        v = e(p)
        assert v.min() >= low and v.max() <= up, (text, low, v.min(), v.max(), up)
        assert (low, up) == e.interval(lo, hi)


def test_bounds_of_a_linear_function_are_tight():
    e = geom.Expression("x + 2*y - 3*z")
    lo, hi = np.array([-1.0, 0.5, 2.0]), np.array([0.25, 1.0, 4.0])
    low, up, defined = e.bounds(lo, hi)
    assert defined
    assert abs(low - (-1 + 1 - 12)) < 1e-12 and abs(up - (0.25 + 2 - 6)) < 1e-12


def test_definedness():
    s = geom.Expression("sqrt(x) + y")
    assert s.bounds([0, 0, 0], [1, 1, 1])[2]
    low, up, defined = s.bounds([-1, 0, 0], [1, 1, 1])
    assert not defined
    v = s(np.array([[0.25, 0.5, 0.0], [1.0, 1.0, 0.0]]))
    assert low <= v.min() and v.max() <= up              # still bounds the finite values
    assert not geom.Expression("log(x)").bounds([0, 0, 0], [1, 1, 1])[2]
    assert geom.Expression("log(x)").bounds([0.5, 0, 0], [1, 1, 1])[2]
    low, up, defined = geom.Expression("sqrt(x)").bounds([-2, 0, 0], [-1, 1, 1])
    assert np.isnan(low) and np.isnan(up) and not defined  # defined nowhere
    low, up, defined = geom.Expression("x*x + 1").bounds([-np.inf, 0, 0], [np.inf, 0, 0])
    assert low <= 1 and up == np.inf and not defined


def test_bounds_bad_input():
    e = geom.Expression("x + y")
    with pytest.raises(geom.GeomError) as err:
        e.bounds([1, 0, 0], [0, 1, 1])                      # lo > hi
    assert err.value.code == "ERR_INVALID_ARG"
    with pytest.raises(geom.GeomError):
        e.bounds([np.nan, 0, 0], [1, 1, 1])
    with pytest.raises(ValueError):
        e.bounds([0, 0], [1, 1])


@pytest.mark.parametrize("text", EXPRS + ["sqrt(x) + log(y)"])
def test_bounds_of_many_boxes_are_the_single_calls(text):
    e = geom.Expression(text)
    rng = np.random.default_rng(5)
    c = rng.uniform(-1.5, 1.5, (4, 50, 3))
    r = rng.uniform(0, 0.8, (4, 50, 3))
    r[0, :7, 1] = 0.0                                         # flat boxes
    r[1, 3, 2] = np.inf                                       # unbounded
    lo, hi = c - r, c + r
    low, up, defined = e.bounds(lo, hi)
    assert low.shape == up.shape == defined.shape == (4, 50) and defined.dtype == bool
    for idx in np.ndindex(4, 50):
        one = e.bounds(lo[idx], hi[idx])
        assert np.array_equal([low[idx], up[idx]], one[:2], equal_nan=True)
        assert defined[idx] == one[2]
    # one corner broadcast against many
    corner = np.full(3, -3.0)
    low2, up2, _ = e.bounds(corner, hi)
    one = e.bounds(corner, hi[2, 9])
    assert np.array_equal([low2[2, 9], up2[2, 9]], one[:2], equal_nan=True)
    assert e.bounds(np.zeros((0, 3)), np.zeros((0, 3)))[0].shape == (0,)


def test_bounds_of_many_boxes_bad_input():
    e = geom.Expression("x + y")
    lo, hi = np.zeros((5, 3)), np.ones((5, 3))
    lo[3, 1] = 2.0                                            # lo > hi in one box
    with pytest.raises(geom.GeomError) as err:
        e.bounds(lo, hi)
    assert err.value.code == "ERR_INVALID_ARG"
    with pytest.raises(ValueError):
        e.bounds(np.zeros((5, 2)), np.ones((5, 2)))
