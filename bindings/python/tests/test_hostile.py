"""Hostile input through the Python bindings (issue 15): the bindings are no
way around the C API's validation. Each test feeds what a careless or
malicious caller could pass and expects a Python exception, never a crash,
an out-of-bounds read (the suite runs under ASan in CI) or a silent result.
The hostile-input corpus tests/data/hostile is read through geom.Mesh too."""

import glob
import os

import numpy as np
import pytest

import geom
from geom.core import GeomError

HOSTILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                       "tests", "data", "hostile")

ERRORS = (GeomError, ValueError, TypeError, OverflowError)


def test_curve_validate_false_short_arrays():
    # fewer knots than n + degree + 1: validate=False must not read past them
    with pytest.raises(ERRORS):
        c = geom.curve.NurbsCurve(3, [0, 0, 1, 1], [[0, 0], [1, 1], [2, 0], [3, 1]],
                                  validate=False)
        c.eval(0.5)
    with pytest.raises(ERRORS):
        geom.curve.NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 1], [2, 0]],
                              weights=[1, 1], validate=False)
    with pytest.raises(ERRORS):
        geom.curve.NurbsCurve(9, [0, 1], [[0, 0]], validate=False)


def test_surface_validate_false_short_arrays():
    pts = np.zeros((4, 4, 3))
    with pytest.raises(ERRORS):
        s = geom.surface.NurbsSurface(3, 3, [0, 0, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1], pts,
                                      validate=False)
        geom.surface.tessellate([s])


def test_empty_mesh_operations():
    m = geom.mesh.Mesh()
    assert m.positions.shape == (0, 3)
    m.positions = np.zeros((0, 3))
    m.close()


def test_empty_soup():
    m = geom.mesh.Mesh.from_soup(np.zeros((0, 3)), [])
    assert m.n_vertices == 0
    m.close()


def test_nan_positions_rejected():
    with pytest.raises(ERRORS):
        geom.mesh.Mesh.from_soup([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]])


def test_path_with_nul():
    with pytest.raises(ERRORS):
        geom.mesh.Mesh.read("bad\0name.obj")
    m = geom.mesh.Mesh.from_soup([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(ERRORS):
        m.write("/tmp/bad\0name.obj")
    m.close()


def test_zero_spacing_rejected():
    vol = np.zeros((4, 4, 4))
    vol[1:3, 1:3, 1:3] = -1
    for spacing in ([0, 1, 1], [np.nan, 1, 1], [-1, 1, 1]):
        with pytest.raises(ERRORS):
            geom.implicit.marching_cubes(vol, spacing=spacing)


def test_threads_capped():
    vol = np.zeros((6, 6, 6))
    vol[2:4, 2:4, 2:4] = -1
    out = geom.implicit.marching_cubes(vol, threads=100000)
    assert out is not None


def test_degenerate_barycentric_raises():
    with pytest.raises(ERRORS):
        geom.bary.tri2([0, 0], [1, 1], [2, 2], [0.5, 0.5])


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(HOSTILE, "mesh", "*"))))
def test_hostile_mesh_corpus(path):
    with pytest.raises(ERRORS):
        geom.mesh.Mesh.read(path)
    with open(path, "rb") as f:
        data = f.read()
    with pytest.raises(ERRORS):
        geom.mesh.Mesh.from_bytes(data, format=os.path.splitext(path)[1][1:] or "obj",
                                  source_name=os.path.basename(path))


def test_degree_elevation_huge():
    c = geom.curve.NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 1], [2, 0]])
    e = c.elevate(998)  # degree 1000: the largest allowed, still exact
    u = np.linspace(0, 1, 7)
    assert not np.isnan(e.points).any()
    assert np.abs(e.eval(u) - c.eval(u)).max() < 1e-12
    for times in (999, 3000, 2**31 - 1):  # refused, never NaN control points
        with pytest.raises(ERRORS):
            c.elevate(times)


def test_closest_point_far_and_nan():
    c = geom.curve.NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 1], [2, 0]])
    with pytest.raises(ERRORS):
        c.closest_point([np.nan, 0])
    u, p, d = c.closest_point([1e300, 0])
    assert np.isfinite(u) and np.all(np.isfinite(p))


def test_undiagnosed_failure_never_says_ok():
    # A failing call whose diag stayed empty must not format it: the message
    # is the status name alone, never "invalid argument: ok".
    from geom import core
    with pytest.raises(core.GeomError) as e:
        core.check(-2, core.new_diag(), context="a call")
    text = str(e.value)
    assert not text.endswith(": ok") and ": ok" not in text, text
    assert "invalid argument" in text or e.value.name in text


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(HOSTILE, "volume", "*"))))
def test_hostile_volume_corpus(path):
    # every volume of the corpus is refused, from its path and from its bytes
    # (a detached .mhd header cannot be read from memory: refused as well)
    with pytest.raises(ERRORS):
        geom.implicit.read_volume(path)
    with open(path, "rb") as f:
        data = f.read()
    with pytest.raises(ERRORS):
        geom.implicit.read_volume(data)


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(HOSTILE, "surface", "*"))))
def test_hostile_surface_corpus(path):
    # curve/surface JSON and .bpt files of the corpus are refused
    reader = geom.surface.read_bpt if path.endswith(".bpt") else geom.surface.read_json
    with pytest.raises(ERRORS):
        reader(path)
