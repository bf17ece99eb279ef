"""mesh and meshio: topology of closed forms (cube, torus), normals, corner
channels against the OBJ file read in Python, round trips, repairs,
features, clipping, subdivision and the Mesh lifetime."""

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

import geom

if not (geom.has_module("mesh") and geom.has_module("meshio")):
    pytest.skip("libgeom built without mesh/meshio", allow_module_level=True)

from geom import Mesh  # noqa: E402
from geom.mesh import polygon_triangulate  # noqa: E402
from meshes import CUBE_FACES, CUBE_POINTS, grid, torus, volume  # noqa: E402


@pytest.fixture
def cube():
    with Mesh.from_soup(CUBE_POINTS, CUBE_FACES) as m:
        yield m


def test_cube_topology_and_round_trip(cube):
    t = cube.topology()
    assert (t["vertices"], t["edges"], t["faces"]) == (8, 12, 6)
    assert t["euler"] == 2 and t["genus"] == 0 and t["closed"] and t["manifold"]
    assert t["components"] == 1 and t["boundary_loops"] == 0
    assert t["bbox"] == {"min": [0, 0, 0], "max": [1, 1, 1]}
    assert np.array_equal(cube.positions, CUBE_POINTS)
    assert np.array_equal(cube.faces, CUBE_FACES)  # soup order is kept
    assert cube.validate() == []
    assert all(v == 0 for v in t["repairs"].values())
    assert abs(volume(cube) - 1.0) < 1e-15


def test_torus_topology():
    pts, faces = torus(24, 12)
    with Mesh.from_soup(pts, faces) as m:
        t = m.topology()
        assert (t["vertices"], t["edges"], t["faces"]) == (288, 576, 288)
        assert t["euler"] == 0 and t["genus"] == 1 and t["closed"] and t["components"] == 1
        assert m.triangulate() == 288
        t = m.topology()
        assert (t["faces"], t["edges"], t["genus"]) == (576, 864, 1)
        assert m.faces.shape == (576, 3)
    # Two disjoint tori: two components, total genus 2.
    p2 = np.vstack([pts, pts + [10, 0, 0]])
    f2 = np.vstack([faces, faces + len(pts)])
    with Mesh.from_soup(p2, f2) as m:
        n, vc, fc = m.components()
        assert n == 2 and set(vc[:288]) == {vc[0]} and vc[0] != vc[288]
        assert m.topology()["genus"] == 2


def test_vertex_and_face_normals(cube):
    n = cube.vertex_normals()
    want = (2 * CUBE_POINTS - 1) / np.sqrt(3)  # corners point away from the centre
    assert np.allclose(n, want, atol=1e-15)
    for w in ("uniform", "area", "max"):
        assert np.allclose(cube.vertex_normals(weight=w), want, atol=1e-15)
    fn = cube.face_normals()
    assert np.allclose(fn, [[0, 0, -1], [0, 0, 1], [0, -1, 0], [0, 1, 0], [-1, 0, 0], [1, 0, 0]])
    with pytest.raises(ValueError):
        cube.vertex_normals(weight="cosine")
    # Torus: normals close to the analytic ones (tube direction).
    pts, faces = torus(64, 32)
    with Mesh.from_soup(pts, faces) as m:
        n = m.vertex_normals()
    ring = pts.copy()
    ring[:, 2] = 0
    ring = ring / np.linalg.norm(ring, axis=1, keepdims=True) * 2.0
    exact = (pts - ring) / 0.5
    assert np.max(np.degrees(np.arccos(np.clip((n * exact).sum(axis=1), -1, 1)))) < 0.5


def test_corner_channel_matches_obj_file(data_dir):
    path = os.path.join(data_dir, "cube_seams.obj")
    vt, vn, corners = [], [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "vt":
                vt.append([float(x) for x in w[1:3]])
            elif w[0] == "vn":
                vn.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                corners += [[int(x) - 1 for x in c.split("/")] for c in w[1:]]
    corners = np.array(corners)
    with Mesh.read(path) as m:
        assert np.array_equal(m.face_indices, corners[:, 0])
        values, idx = m.corner("uv")
        assert np.array_equal(values, vt) and np.array_equal(idx, corners[:, 1])
        assert np.array_equal(m.corner_values("normal"), np.array(vn)[corners[:, 2]])
        uv = m.uv_data("uv")
        assert uv["uv_area"] == pytest.approx(6 * 0.25 * 0.25, abs=1e-15)
        assert uv["uv_min"] == [0.125, 0.0] and uv["uv_max"] == [0.875, 1.0]
        assert uv["flipped_faces"] == 0 and uv["seam_edge"].shape == (12,)
        m.triangulate()
        assert m.uv_data("uv")["uv_area"] == pytest.approx(0.375, abs=1e-15)
        assert m.faces.shape == (12, 3)


def test_set_corner_and_obj_round_trip(tmp_path, cube):
    uv = np.random.default_rng(20).random((24, 2))
    cube.set_corner("uv", uv)
    values, idx = cube.corner("uv")
    assert np.array_equal(values, uv) and np.array_equal(idx, np.arange(24))
    path = tmp_path / "c.obj"
    cube.write(path)
    with Mesh.read(path) as back:
        assert np.array_equal(back.corner_values("uv"), uv)
        assert np.array_equal(back.positions, CUBE_POINTS)
    with pytest.raises(ValueError):
        cube.set_corner("uv", uv[:5])


def test_channels(cube):
    cube.set_channel("weight", np.arange(8.0), domain="vertex")
    assert np.array_equal(cube.channel("weight"), np.arange(8.0).reshape(8, 1))
    cube.set_channel("color", np.eye(6)[:, :3], domain="face")
    names = [(c["name"], c["domain"], c["ncomp"], c["size"]) for c in cube.channels()]
    assert names == [("position", "vertex", 3, 8), ("weight", "vertex", 1, 8),
                     ("color", "face", 3, 6)]
    with pytest.raises(KeyError):
        cube.channel("nope")
    with pytest.raises(ValueError):
        cube.set_channel("weight", np.zeros(3))
    cube.remove_channel("weight")
    assert not cube.has_channel("weight")
    new = cube.positions * 2
    cube.positions = new
    assert np.array_equal(cube.positions, new)


def test_exact_round_trip_through_files(tmp_path):
    rng = np.random.default_rng(21)
    pts, faces = torus(8, 6)
    pts = pts * rng.random(pts.shape) * 1e3
    with Mesh.from_soup(pts, faces) as m:
        for ext in ("obj", "off", "ply"):
            m.write(tmp_path / ("t." + ext))
            with Mesh.read(tmp_path / ("t." + ext)) as back:
                assert np.array_equal(back.positions, pts), ext
                assert np.array_equal(back.faces, faces), ext
        for fmt, enc in (("ply", "binary_be"), ("ply", "ascii"), ("obj", "default")):
            data = m.to_bytes(fmt, encoding=enc)
            with Mesh.from_bytes(data, format=fmt) as back:
                assert np.array_equal(back.positions, pts)
        assert m.to_bytes("glb")[:4] == b"glTF"
        stl = m.to_bytes("stl")
        with Mesh.from_bytes(stl, format="stl") as back:
            assert back.topology()["faces"] == 2 * len(faces)  # triangulated, float


def test_topology_matches_geom_info(data_dir):
    tool = os.environ.get("GEOM_INFO") or shutil.which("geom-info")
    if not tool or not os.path.exists(tool):
        pytest.skip("geom-info not available (set GEOM_INFO)")
    for name in ("cube_seams.obj", "pyramid.ply", "tetra.off", "wedge.stl"):
        path = os.path.join(data_dir, name)
        # The tool links its own sanitizer runtime in sanitized builds: do not
        # hand it the interpreter's preloaded one.
        env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
        out = subprocess.run([tool, "--json", path], check=True, capture_output=True, text=True,
                             env=env)
        with Mesh.read(path) as m:
            assert m.topology() == json.loads(out.stdout), name


def test_read_stats_and_build_repairs(data_dir):
    with Mesh.read(os.path.join(data_dir, "pyramid.ply")) as m:
        st = m.read_stats
        assert st["format"] == "ply" and st["binary"] == 1
        assert st["skipped_elements"] == 1 and st["skipped_properties"] >= 2
        assert m.channel("color").shape == (5, 3)
    # Three triangles on one edge: one is detached.
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], dtype=float)
    with Mesh.from_soup(pts, [[0, 1, 2], [1, 0, 3], [0, 1, 4]]) as m:
        rep = m.build_report
        assert rep["nonmanifold_edges"] == 1 and rep["detached_faces"] == 1
        assert rep["added_vertices"] == 2 and m.n_vertices == 7
        assert list(m.vertex_origin[5:]) == [0, 1]
        assert m.topology()["repairs"]["detached_faces"] == 1
        assert m.validate() == []


def test_soup_errors():
    with pytest.raises(geom.GeomError) as info:
        Mesh.from_soup(CUBE_POINTS, [[0, 1, 9]])
    assert info.value.code == "ERR_INVALID_ARG" and info.value.message
    with Mesh.from_soup(CUBE_POINTS, [[0, 1, 9], [0, 1, 2]], skip_invalid=True) as m:
        assert m.build_report["invalid_faces"] == 1 and m.n_faces == 1
        assert list(m.face_origin) == [1]
    with pytest.raises(ValueError):
        Mesh.from_soup(CUBE_POINTS, [[0, -1, 2]])
    with pytest.raises(ValueError):
        Mesh.from_soup(CUBE_POINTS[:, :2], [[0, 1, 2]])
    bad = CUBE_POINTS.copy()
    bad[0, 0] = np.nan
    with pytest.raises(geom.GeomError) as info:
        Mesh.from_soup(bad, CUBE_FACES)
    assert info.value.code == "ERR_INVALID_ARG"


def test_mixed_polygons_and_ear_clipping():
    pts = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [1, 0.5, 0], [0, 2, 0], [3, 0, 0]], float)
    with Mesh.from_soup(pts, [[0, 1, 2, 3, 4], [1, 5, 2]]) as m:
        faces = m.faces
        assert isinstance(faces, list) and [len(f) for f in faces] == [5, 3]
        assert list(m.face_sizes) == [5, 3]
        assert m.triangulate() == 2 and m.faces.shape == (4, 3)
        # Areas are preserved: the dart (area 2.5) plus the triangle (1).
        P = m.positions
        area = sum(0.5 * abs(np.cross(P[b] - P[a], P[c] - P[a])[2]) for a, b, c in m.faces)
        assert area == pytest.approx(2 * 2 - 1.5 + 1, abs=1e-14)
    tris = polygon_triangulate(pts[:5, :2])
    assert tris.shape == (3, 3) and set(tris.ravel()) == set(range(5))
    with pytest.raises(geom.GeomError) as info:
        polygon_triangulate([[0, 0], [1, 1], [2, 2]])
    assert info.value.code == "ERR_DEGENERATE"


def test_corner_normals_and_tangents(cube):
    values, idx = cube.corner_normals(crease_degrees=30)
    per_corner = values[idx]
    want = np.repeat(cube.face_normals(), 4, axis=0)
    assert np.allclose(per_corner, want, atol=1e-15)
    smooth, sidx = cube.corner_normals()  # no creases: one normal per vertex
    assert np.allclose(smooth[sidx], cube.vertex_normals()[cube.face_indices], atol=1e-15)
    pts, faces = grid(3)
    with Mesh.from_soup(pts, faces) as g:
        g.set_corner("uv", pts[g.face_indices][:, :2])
        t, tidx = g.tangents()
        assert np.allclose(t[tidx], [1, 0, 0, 1], atol=1e-15)


def test_features(cube):
    kind, lines = cube.features()
    assert list(kind) == [2] * 12  # every cube edge is a 90-degree crease
    assert sum(len(p) - 1 for p in lines) == 12 and len(cube.polylines) == len(lines)
    kind, lines = cube.features(kinds=["crease"], crease_degrees=95)
    assert not kind.any() and lines == []
    pts, faces = grid(4)
    with Mesh.from_soup(pts, faces) as g:
        kind, lines = g.features(kinds="boundary")
        assert (kind == 1).sum() == 16
        assert len(lines) == 1 and lines[0][0] == lines[0][-1] and len(lines[0]) == 17
        with pytest.raises(ValueError):
            g.features(kinds=["silhouette"])


def test_clipping(cube):
    half = cube.clip_plane([1, 0, 0, -0.25])
    with half:
        lo, hi = half.bbox()
        assert lo[0] == 0.25 and hi[0] == 1
        assert not half.topology()["closed"]
    with cube.clip_plane([1, 0, 0, -0.25], cap=True) as capped:
        t = capped.topology()
        assert t["closed"] and t["euler"] == 2
        assert volume(capped) == pytest.approx(0.75, abs=1e-15)
    P = geom.core.ortho(-0.5, 0.5, -0.5, 0.5, -10, 10)
    with cube.clip_frustum(P) as f:
        lo, hi = f.bbox()
        assert np.allclose(lo, [0, 0, 0]) and np.allclose(hi, [0.5, 0.5, 1])
    with pytest.raises(geom.GeomError) as info:
        cube.clip_plane([0, 0, 0, 1])
    assert info.value.code == "ERR_DEGENERATE"


def test_subdivision_closed_forms(cube):
    if not geom.has_module("subdiv"):
        pytest.skip("no subdiv module")
    with cube.subdivide(1) as s:
        t = s.topology()
        assert (t["vertices"], t["edges"], t["faces"]) == (26, 48, 24)
        P = s.positions
        # Catmull-Clark vertex point of a valence-3 corner: (Q + 2R)/3 = 2/9;
        # vertex points follow the 6 face points and 12 edge points.
        assert np.allclose(P[18], [2 / 9] * 3, atol=1e-15)
        assert np.allclose(P[:6].mean(axis=0), [0.5] * 3)  # face centres
        assert any(np.allclose(p, [0.5, 0.125, 0.125], atol=1e-15) for p in P[6:18])
        assert s.subdiv_report["levels"] == 1 and s.subdiv_report["faces"] == 24
    with cube.subdivide(2, limit=True, normals=True) as s:
        assert s.subdiv_report["max_limit_distance"] == 0
        n = s.channel("normal")
        c = s.positions - 0.5
        assert np.all((n * c).sum(axis=1) > 0)  # outward
    tet_faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    with Mesh.from_soup(CUBE_POINTS[[0, 1, 2, 4]], tet_faces) as tet:
        with tet.subdivide(1, scheme="loop") as s:
            assert (s.n_vertices, s.n_faces) == (10, 16)
    pts, faces = grid(1)
    with Mesh.from_soup(pts, faces) as q:
        with q.subdivide(1, scheme="bilinear") as s:
            assert sorted(map(tuple, s.positions)) == sorted(
                (x, y, 0.0) for x in (0, 0.5, 1) for y in (0, 0.5, 1))
    with pytest.raises(geom.GeomError):
        cube.subdivide(1, scheme="loop")  # quads
    with pytest.raises(geom.GeomError):
        cube.subdivide(1, scheme="doo-sabin")


def test_lifetime(cube):
    with Mesh.from_soup(CUBE_POINTS, CUBE_FACES) as m:
        pos = m.positions
        copy = m.copy()
    assert m.closed and "closed" in repr(m)
    with pytest.raises(ValueError):
        m.positions
    m.close()  # idempotent
    pos[:] = 7  # a copy: still valid memory, does not affect anything else
    assert np.array_equal(copy.positions, CUBE_POINTS)
    copy.close()
    empty = Mesh()
    assert empty.topology()["vertices"] == 0 and empty.bbox() is None
    assert empty.faces.shape == (0, 3)
