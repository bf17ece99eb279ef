"""surface: exact quadrics (points on the sphere/torus, normals at the
poles), Bezier and bilinear closed forms, tessellation topology and error
against the geometry, and .bpt reading."""

import os

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("surface"), reason="no surface module")

from geom.surface import NurbsSurface, read_bpt, tessellate  # noqa: E402


def test_sphere_points_and_normals():
    s = NurbsSurface.sphere(2.0, center=(1, 2, 3))
    assert s.rational and s.points.shape == (9, 5, 3) and s.domain == (0, 1, 0, 1)
    u, v = np.meshgrid(np.linspace(0, 1, 33), np.linspace(0, 1, 17), indexing="ij")
    P = s(u, v)
    assert P.shape == (33, 17, 3)
    r = np.linalg.norm(P - [1, 2, 3], axis=-1)
    assert np.max(np.abs(r - 2)) < 1e-14
    n, how = s.normal(u, v, return_how=True)
    assert np.allclose(n, (P - [1, 2, 3]) / 2, atol=1e-12)  # outward, poles included
    assert set(how[:, 0]) == {"limit"} and how[5, 8] == "regular"
    d = s.derivs(0.3, 0.4, 2)
    assert d.shape == (3, 3, 3) and np.array_equal(d[0, 0], s(0.3, 0.4))
    assert np.allclose(np.cross(d[1, 0], d[0, 1]) / np.linalg.norm(np.cross(d[1, 0], d[0, 1])),
                       s.normal(0.3, 0.4))


def test_torus_cylinder_cone_bilinear_bezier():
    t = NurbsSurface.torus(3.0, 1.0)
    u, v = np.meshgrid(np.linspace(0, 1, 21), np.linspace(0, 1, 21), indexing="ij")
    P = t(u, v)
    ring = np.hypot(P[..., 0], P[..., 1]) - 3
    assert np.max(np.abs(np.hypot(ring, P[..., 2]) - 1)) < 1e-14
    cyl = NurbsSurface.cylinder(0.5, 2.0)
    P = cyl(u, v)
    assert np.allclose(np.hypot(P[..., 0], P[..., 1]), 0.5, atol=1e-15)
    assert np.allclose(P[..., 2], 2 * v, atol=1e-15)
    cone = NurbsSurface.cone(1.0, 0.0, 1.0)
    P = cone(u, v)
    assert np.allclose(np.hypot(P[..., 0], P[..., 1]), 1 - P[..., 2], atol=1e-14)
    corners = [np.array(c, float) for c in ([0, 0, 0], [1, 0, 1], [0, 1, 2], [1, 1, -1])]
    b = NurbsSurface.bilinear(*corners)
    uu, vv = 0.3, 0.8
    want = ((1 - uu) * (1 - vv) * corners[0] + uu * (1 - vv) * corners[1]
            + (1 - uu) * vv * corners[2] + uu * vv * corners[3])
    assert np.allclose(b(uu, vv), want, atol=1e-15)
    ctrl = np.random.default_rng(40).normal(size=(4, 3, 3))
    bz = NurbsSurface.bezier(ctrl)
    assert (bz.degree_u, bz.degree_v) == (3, 2)
    Bu = np.array([(1 - uu) ** 3, 3 * uu * (1 - uu) ** 2, 3 * uu ** 2 * (1 - uu), uu ** 3])
    Bv = np.array([(1 - vv) ** 2, 2 * vv * (1 - vv), vv ** 2])
    assert np.allclose(bz(uu, vv), np.einsum("i,j,ijk->k", Bu, Bv, ctrl), atol=1e-14)


def test_tessellate_sphere_and_torus():
    tol = 1e-3
    mesh, rep = tessellate(NurbsSurface.sphere(1.0), tolerance=tol)
    with mesh:
        t = mesh.topology()
        assert t["closed"] and t["manifold"] and t["genus"] == 0 and t["components"] == 1
        assert rep["max_error"] <= tol and rep["method"] == "sampled"
        assert rep["stats"]["triangles"] == t["faces"]
        P = mesh.positions
        assert np.max(np.abs(np.linalg.norm(P, axis=1) - 1)) < 1e-14  # vertices on the sphere
        # Chordal error closed form: a triangle's centroid lies within tol of the sphere
        # (up to the slack of the sampled check).
        F = mesh.faces
        cen = P[F].mean(axis=1)
        assert np.max(1 - np.linalg.norm(cen, axis=1)) < 2 * tol
        nrm, idx = mesh.corner("normal")
        assert np.allclose(nrm[idx], P[mesh.face_indices], atol=1e-12)
        uv, uidx = mesh.corner("uv")
        assert uv.min() >= 0 and uv.max() <= 1
    mesh, rep = tessellate([NurbsSurface.torus(2.0, 0.5)], mode="uniform", grid=(4, 4),
                           attributes=())
    with mesh:
        t = mesh.topology()
        assert t["closed"] and t["genus"] == 1
        assert mesh.channels() == [{"name": "position", "domain": "vertex", "ncomp": 3,
                                    "size": t["vertices"]}]


def test_teapot(data_dir):
    path = os.path.join(data_dir, "teapot.bpt")
    patches = read_bpt(path)
    assert len(patches) == 32
    assert all((p.degree_u, p.degree_v) == (3, 3) and p.points.shape == (4, 4, 3)
               for p in patches)
    with open(path, "rb") as f:
        again = read_bpt(f.read())
    assert all(np.array_equal(a.points, b.points) for a, b in zip(patches, again))
    mesh, rep = tessellate(patches, tolerance=0.01, attributes=("normal", "source"))
    with mesh:
        assert rep["max_error"] <= 0.01
        src = mesh.channel("surface", "face")
        assert set(src.ravel().astype(int)) == set(range(32))
        assert mesh.validate() == []
    with pytest.raises(geom.GeomError) as info:
        read_bpt(b"1\n1 2 3\n", source_name="bad.bpt")
    assert info.value.code == "ERR_PARSE" and info.value.line == 2
    assert info.value.location.startswith("bad.bpt:2:")


def test_invalid_surface():
    with pytest.raises(geom.GeomError) as info:
        NurbsSurface(1, 1, [0, 0, 1, 1], [0, 0, 1, 1], np.zeros((2, 2, 3)),
                     weights=[[1, 1], [1, -1]])
    assert info.value.code == "ERR_INVALID_ARG" and "weight" in info.value.message
