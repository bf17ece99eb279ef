"""geom.step.Brep on data/sphere.step (a sphere of radius 10 mm in one
face): surface evaluation against the sphere's closed form, a closed
tessellation whose vertices lie on the sphere and whose enclosed volume
approaches 4/3 pi r^3, the estimate against the triangles made, units, and
errors naming the line."""

import math
import os

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("step"), reason="no step module")


@pytest.fixture(scope="module")
def sphere_path(data_dir):
    return os.path.join(data_dir, "sphere.step")


def volume(m):
    p = m.positions
    t = np.asarray(m.face_indices).reshape(-1, 3)
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    return np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6


def test_read_and_evaluate(sphere_path):
    b = geom.step.Brep.read(sphere_path)
    assert b.counts["faces"] >= 1 and b.unit_metres == pytest.approx(1e-3)
    s = [i for i in range(b.counts["surfaces"]) if b.surface_type(i) == "sphere"]
    assert s
    centre = np.array(list(b._b.surfaces[s[0]].origin))
    for u, v in ((0.3, 0.2), (2.0, -1.0), (5.0, 1.2)):
        p, du, dv = b.surface_eval(s[0], u, v)
        assert np.linalg.norm(p - centre) == pytest.approx(10.0, rel=1e-14)
        assert abs(np.dot(du, p - centre)) < 1e-9 and abs(np.dot(dv, p - centre)) < 1e-9
    with pytest.raises(IndexError):
        b.surface_eval(b.counts["surfaces"], 0, 0)
    assert geom.step.Brep.from_bytes(open(sphere_path, "rb").read()).counts == b.counts


@pytest.mark.parametrize("tol", [0.05, 0.005])
def test_tessellation_on_the_sphere(sphere_path, tol):
    b = geom.step.Brep.read(sphere_path)
    m, rep = b.tessellate(tolerance=tol, attributes=("normal",))
    assert rep["open_edges"] == 0 and rep["faces_failed"] == 0
    assert rep["error"]["max_error"] <= tol
    r = np.linalg.norm(m.positions - np.array(list(b._b.surfaces[0].origin)), axis=1)
    assert np.abs(r - 10).max() <= 1e-6
    # inscribed polyhedron: volume below 4/3 pi r^3, by at most the chordal band
    v = volume(m)
    assert 4 / 3 * math.pi * (10 - tol) ** 3 <= abs(v) <= 4 / 3 * math.pi * 1000
    est, per = b.estimate(tolerance=tol)
    made = int(np.sum(np.asarray(m.face_sizes) - 2))
    assert per.sum() == pytest.approx(est) and 0.5 <= est / made <= 2.0, (est, made)
    assert m.has_channel("normal", "corner")


def test_units_and_errors(sphere_path):
    b = geom.step.Brep.read(sphere_path, unit_metres=1.0)   # output in metres
    m, _ = b.tessellate(tolerance=5e-5)
    assert np.linalg.norm(m.positions, axis=1).max() == pytest.approx(0.01, rel=1e-6)
    with pytest.raises(geom.GeomError) as e:
        geom.step.Brep.from_bytes(b"ISO-10303-21;\nHEADER;\nnot step at all", source_name="x.step")
    assert e.value.code == "ERR_PARSE" and "x.step" in str(e.value)
    with pytest.raises(geom.GeomError) as e:
        geom.step.Brep.read("/nonexistent/part.step")
    assert e.value.code == "ERR_IO"
