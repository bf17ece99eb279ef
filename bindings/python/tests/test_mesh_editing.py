"""Mesh editing from Python (add_vertex/add_face/delete/compact, lookups,
material libraries, tags, groups), checked against the counts and indices
the operations must give by construction, the half-edge invariants
(validate), and an OBJ round trip."""

import numpy as np
import pytest

import geom


def grid_mesh():
    m = geom.Mesh()
    ids = [m.add_vertex([x, y, 0]) for y in range(3) for x in range(3)]
    assert ids == list(range(9))
    faces = []
    for y in range(2):
        for x in range(2):
            a = 3 * y + x
            faces.append(m.add_face([a, a + 1, a + 4, a + 3]))
    assert faces == [0, 1, 2, 3]
    return m


def test_build_find_delete_compact():
    m = grid_mesh()
    assert (m.n_vertices, m.n_faces, m.n_edges) == (9, 4, 12)
    assert m.topology()["manifold"]
    h = m.find_halfedge(0, 1)
    assert h is not None and m.find_halfedge(0, 8) is None
    assert m.find_edge(1, 0) == m.find_edge(0, 1) == h >> 1
    np.testing.assert_array_equal(m.vertex_valences(), [2, 3, 2, 3, 4, 3, 2, 3, 2])
    with pytest.raises(geom.GeomError) as e:
        m.add_face([0, 1, 4, 3])      # the same face again: non-manifold
    assert e.value.code == "ERR_NONMANIFOLD" and m.n_faces == 4
    m.delete_face(3)                   # corner face: vertex 8 left alone goes too
    assert m.is_deleted("face", 3) and m.is_deleted("vertex", 8) and not m.is_deleted("vertex", 4)
    vm, fm = m.compact()
    np.testing.assert_array_equal(fm, [0, 1, 2, -1])
    np.testing.assert_array_equal(vm, [0, 1, 2, 3, 4, 5, 6, 7, -1])
    assert (m.n_vertices, m.n_faces) == (8, 3)
    m.delete_vertex(4)                 # the centre: every face goes
    m.compact()
    assert m.n_faces == 0 and m.n_live_vertices == 0 and m.n_live_edges == 0


def test_degenerate_polyline_and_clear():
    m = grid_mesh()
    v = m.add_vertex([5, 5, 0])
    w = m.add_vertex([5, 5, 0])        # coincident with v
    x = m.add_vertex([6, 5, 0])
    f = m.add_face([v, w, x])
    np.testing.assert_array_equal(m.degenerate_faces(), [f])
    m.add_polyline([0, 1, 2, 5])
    assert [list(p) for p in m.polylines] == [[0, 1, 2, 5]]
    m.clear()
    assert (m.n_vertices, m.n_faces) == (0, 0) and m.polylines == []


def test_metadata_round_trip(tmp_path):
    m = grid_mesh()
    m.add_mtllib("shiny.mtl")
    m.add_tag("crease", [0, 1], [2.5])
    m.add_tag("interpolateboundary", [1])
    gid = m.set_face_groups({"group": "left", "material": "red"}, [0, 2])
    assert m.mtllibs == ["shiny.mtl"]
    assert m.tags == [("crease", [0, 1], [2.5], []), ("interpolateboundary", [1], [], [])]
    assert m.groups[gid] == {"group": "left", "object": None, "material": "red", "smoothing": None}
    np.testing.assert_array_equal(m.face_groups(), [gid, -1, gid, -1])
    path = str(tmp_path / "m.obj")
    m.write(path)
    text = open(path).read()
    assert "mtllib shiny.mtl" in text and "t crease 2/1/0 0 1 2.5" in text and "usemtl red" in text
    r = geom.Mesh.read(path)
    assert r.mtllibs == ["shiny.mtl"] and r.tags[0] == ("crease", [0, 1], [2.5], [])
    assert "red" in [g["material"] for g in r.groups]
