"""implicit and iso: expressions against numpy, exact gradients, interval
bounds, parse errors with columns, and marching cubes of expressions,
sampled volumes and Python functions (topology and vertex accuracy)."""

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(
    not (geom.has_module("implicit") and geom.has_module("iso")), reason="no implicit/iso")

from geom.implicit import Expression, marching_cubes  # noqa: E402


def test_expression_values_and_gradients():
    rng = np.random.default_rng(50)
    p = rng.normal(size=(1000, 3))
    with Expression("sphere(1)") as e:
        r = np.linalg.norm(p, axis=1)
        assert np.allclose(e(p), r - 1, rtol=0, atol=1e-15)
        v, g = e.gradient(p)
        assert np.allclose(v, r - 1, atol=1e-15)
        assert np.allclose(g, p / r[:, None], atol=1e-15)
    e = Expression("x^2 + 3*y*z - t")
    grid = p.reshape(10, 100, 3)
    vals = e(grid)
    assert vals.shape == (10, 100)
    assert np.allclose(vals, grid[..., 0] ** 2 + 3 * grid[..., 1] * grid[..., 2], atol=1e-13)
    e.time = 2.5
    assert e([1, 1, 1]) == pytest.approx(1 + 3 - 2.5) and e.time == 2.5
    v, g = e.gradient([1.0, 2.0, 3.0])
    assert np.allclose(g, [2, 9, 6])
    assert e.variables == {"x", "y", "z", "t"} and e.size > 0
    assert Expression("2*z + pi").variables == {"z"}
    e.close()
    with pytest.raises(ValueError):
        e([0, 0, 0])


def test_interval_bounds_enclose_samples():
    e = Expression("sin(3*x)*y - z^2 + torus(1, 0.25)")
    lo, hi = np.array([-0.3, 0.1, -0.5]), np.array([0.4, 0.9, 0.2])
    a, b = e.interval(lo, hi)
    pts = lo + np.random.default_rng(51).random((5000, 3)) * (hi - lo)
    vals = e(pts)
    assert a <= vals.min() and vals.max() <= b
    with pytest.raises(geom.GeomError) as info:
        e.interval(hi, lo)
    assert info.value.code == "ERR_INVALID_ARG"


def test_parse_errors_name_the_column():
    with pytest.raises(geom.GeomError) as info:
        Expression("sphere(1) + spher(2)")
    e = info.value
    assert e.code == "ERR_PARSE" and e.column == 13 and "spher" in e.message
    with pytest.raises(geom.GeomError) as info:
        Expression("(x + 1")
    assert info.value.code == "ERR_PARSE" and "')'" in info.value.message
    with pytest.raises(geom.GeomError) as info:
        Expression("(" * 100 + "x" + ")" * 100)
    assert info.value.code == "ERR_LIMIT"


def test_marching_cubes_of_expressions():
    # 23 cells: no grid node lies exactly on the sphere (such vertices are
    # moved off the node by design), so every vertex is a refined root.
    b = (-1.5, -1.5, -1.5, 1.5, 1.5, 1.5)
    mesh, rep = marching_cubes("sphere(1)", b, (23, 23, 23), refine=True, normals=True)
    with mesh:
        assert rep["iso_nodes"] == 0
        t = mesh.topology()
        assert t["closed"] and t["manifold"] and t["genus"] == 0 and t["components"] == 1
        P = mesh.positions
        assert np.max(np.abs(np.linalg.norm(P, axis=1) - 1)) < 1e-12  # refined onto f = 0
        assert rep["vertex_error"]["max_error"] < 1e-12
        assert rep["sample_error"]["method"] == "sampled" and rep["active_cells"] > 0
        n = mesh.channel("normal")
        assert np.allclose(n, P / np.linalg.norm(P, axis=1, keepdims=True), atol=1e-12)
        # Triangles face increasing f (outward).
        F = mesh.faces
        fn = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
        assert np.all((fn * P[F].mean(axis=1)).sum(axis=1) > 0)
    mesh, rep = marching_cubes(Expression("torus(1, 0.35)"), (-2, -2, -1, 2, 2, 1), (40, 40, 20))
    with mesh:
        t = mesh.topology()
        assert t["closed"] and t["genus"] == 1
    # Caps close a surface cut by the box.
    mesh, rep = marching_cubes("sphere(1)", (-1.5, -1.5, 0, 1.5, 1.5, 1.5), (16, 16, 8), caps=True)
    with mesh:
        assert mesh.topology()["closed"] and rep["n_cap_triangles"] > 0


def test_marching_cubes_of_a_volume_and_a_callable():
    n = 20
    ax = np.linspace(-1.2, 1.2, n)
    X, Y, Z = np.meshgrid(ax, ax, ax, indexing="ij")
    vol = np.sqrt(X ** 2 + (Y / 0.5) ** 2 + Z ** 2) - 1  # ellipsoid, semi-axis 0.5 along y
    h = ax[1] - ax[0]
    mesh, rep = marching_cubes(vol, spacing=(h, h, h), origin=(-1.2, -1.2, -1.2))
    with mesh:
        lo, hi = mesh.bbox()
        assert np.allclose(hi, [1, 0.5, 1], atol=0.05) and np.allclose(lo, -hi, atol=1e-12)
        assert mesh.topology()["genus"] == 0
    mesh32, _ = marching_cubes(vol.astype(np.float32), spacing=(h, h, h))
    with mesh32:
        assert mesh32.topology()["closed"]

    def f(p):
        return np.sqrt(p[:, 0] ** 2 + p[:, 1] ** 2 + p[:, 2] ** 2) - 1

    b, res = (-1.5, -1.5, -1.5, 1.5, 1.5, 1.5), (12, 12, 12)
    m1, _ = marching_cubes(f, b, res)
    m2, _ = marching_cubes("sphere(1)", b, res)
    with m1, m2:
        assert np.array_equal(m1.faces, m2.faces)
        assert np.allclose(m1.positions, m2.positions, atol=1e-14)

    def broken(p):
        raise RuntimeError("field failed")

    with pytest.raises(RuntimeError, match="field failed"):
        marching_cubes(broken, b, res)
    with pytest.raises(geom.GeomError) as info:
        marching_cubes("sphere(1)", b, (0, 4, 4))
    assert info.value.code == "ERR_INVALID_ARG"


def _points_with_specials(n, lo, hi, seed):
    rng = np.random.default_rng(seed)
    p = rng.uniform(lo, hi, (n, 3))
    flat = p.reshape(-1)
    specials = [np.nan, np.inf, -np.inf, 0.0, -0.0, 1e300, -1e300, 0.5]
    flat[5::37] = np.resize(specials, flat[5::37].size)
    flat[7::41] = np.floor(flat[7::41])
    return p


def _same_bits(a, b):
    """Bitwise equal, or NaN in both."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return bool(np.all((a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b))))


@pytest.mark.parametrize("text", ["sqrt(x*x + y*y + z*z) - 1", "x*y - z/3 + t", "sin(x) * exp(y)",
                                  "min(abs(x), y^2) + clamp(z, -1, t)", "sphere(t) + x^3",
                                  "smooth_union(box(1, 0.5, 0.2), gyroid(2), 0.3)"])
def test_expression_batch_is_the_single_point_result(text):
    """Expression(points) and .gradient(points) run in C over the whole
    array and give, bit for bit, the single-point results (NaN/Inf
    coordinates, block tails)."""
    from geom._ffi import ffi, lib
    e = Expression(text)
    e.time = 0.375
    p = _points_with_specials(1000 + 37, -2.5, 2.5, 3)
    vals = e(p)
    gv, gg = e.gradient(p)
    for i in range(p.shape[0]):
        q = np.ascontiguousarray(p[i])
        g = ffi.new("double[3]")
        one = lib.geom_implicit_expr_eval(e._ptr, ffi.from_buffer("double[]", q))
        onev = lib.geom_implicit_expr_eval_grad(e._ptr, ffi.from_buffer("double[]", q), g)
        assert _same_bits(vals[i], one), (text, p[i], vals[i], one)
        assert _same_bits(gv[i], onev), (text, p[i])
        assert _same_bits(gg[i], list(g)), (text, p[i])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_volume_eval_batch_is_the_single_point_result(dtype):
    """Volume.eval over an array (the block interpolator) gives, bit for bit,
    geom_implicit_volume_eval at each point, inside and outside the box,
    on sample positions, next to NaN samples and at NaN/Inf points."""
    from geom._ffi import ffi, lib
    rng = np.random.default_rng(4)
    s = rng.uniform(-1, 1, (17, 9, 6)).astype(dtype)
    s[3, 4, 2] = np.nan
    s[10, 1, 5] = np.inf
    vol = geom.Volume(s, spacing=(0.5, 2.0, 0.25), origin=(-1.0, 3.0, 0.125))
    u = _points_with_specials(3000 + 11, -0.3, 1.3, 5)
    p = np.where(np.isfinite(u), np.array(vol.origin) +
                 u * (np.array(s.shape) - 1) * np.array(vol.spacing), u)
    ours = vol.eval(p)
    v = vol._c()
    for i in range(p.shape[0]):
        one = lib.geom_implicit_volume_eval(v, ffi.from_buffer("double[]",
                                                               np.ascontiguousarray(p[i])))
        assert _same_bits(ours[i], one), (p[i], ours[i], one)
