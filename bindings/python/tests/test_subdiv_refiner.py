"""geom.subdiv.Refiner against closed forms computed here in numpy: the
Catmull-Clark rules of one level (face points, edge points, vertex points,
Catmull and Clark 1978), the limit mask of a quad mesh (Halstead, Kass and
DeRose 1993), linear face-varying data against varying interpolation, the
parent/child maps against each other, and the plain-level shortcut against
the built mesh."""

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("subdiv"), reason="no subdiv module")

CUBE_P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                   [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
CUBE_F = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def cube():
    return geom.Mesh.from_soup(CUBE_P, CUBE_F)


def split(sizes, idx):
    out, k = [], 0
    for s in sizes:
        out.append([int(v) for v in idx[k:k + s]])
        k += s
    return out


def catmull_clark(points, faces):
    """One Catmull-Clark step of a closed mesh: (face points, edge point of
    each edge (a, b) with a < b, vertex points)."""
    fp = np.array([points[f].mean(axis=0) for f in faces])
    edge_faces = {}
    for fi, f in enumerate(faces):
        for a, b in zip(f, f[1:] + f[:1]):
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(fi)
    ep = {e: (points[e[0]] + points[e[1]] + fp[fs[0]] + fp[fs[1]]) / 4 for e, fs in edge_faces.items()}
    vp = np.empty_like(points)
    for v in range(len(points)):
        fs = [fi for fi, f in enumerate(faces) if v in f]
        es = [e for e in edge_faces if v in e]
        n = len(fs)
        q = fp[fs].mean(axis=0)
        r = np.mean([(points[e[0]] + points[e[1]]) / 2 for e in es], axis=0)
        vp[v] = (q + 2 * r + (n - 3) * points[v]) / n
    return fp, ep, vp


def test_level_one_matches_catmull_clark_rules():
    r = geom.subdiv.Refiner(cube())
    r.refine(1)
    assert r.max_level == 1 and r.scheme == "catmull-clark"
    info = r.level_info(1)
    assert (info["vertices"], info["edges"], info["faces"]) == (26, 48, 24)
    p1 = r.interpolate(1, CUBE_P)
    fp, ep, vp = catmull_clark(CUBE_P, CUBE_F)
    for f in range(6):
        np.testing.assert_allclose(p1[r.child_vertex(0, "face", f)], fp[f], atol=1e-15)
    for v in range(8):
        np.testing.assert_allclose(p1[r.child_vertex(0, "vertex", v)], vp[v], atol=1e-15)
    ev, _ = r.edges(0)
    for e, (a, b) in enumerate(ev):
        np.testing.assert_allclose(p1[r.child_vertex(0, "edge", e)], ep[(min(a, b), max(a, b))],
                                   atol=1e-15)


def test_child_and_parent_maps_agree():
    r = geom.subdiv.Refiner(cube())
    r.refine(2)
    for level in (0, 1):
        info = r.level_info(level)
        for kind, count in (("face", info["faces"]), ("edge", info["edges"]),
                            ("vertex", info["vertices"])):
            for i in range(count):
                c = r.child_vertex(level, kind, i)
                assert r.vertex_parent(level + 1, c) == (kind, i)
    parents = [r.face_parent(2, f) for f in range(r.level_info(2)["faces"])]
    assert sorted(set(parents)) == list(range(24)) and all(parents.count(p) == 4 for p in set(parents))
    assert r.face_parent(2, 10 ** 6) is None and r.child_vertex(0, "face", 99) is None


def test_face_indices_is_faces_and_the_plain_level_is_the_built_mesh():
    r = geom.subdiv.Refiner(cube())
    r.refine(2)
    sizes, idx, hole = r.faces(2)
    assert np.array_equal(r.face_indices(2), idx) and not hole.any() and (sizes == 4).all()
    p = r.interpolate(2, r.interpolate(1, CUBE_P))
    assert r.level_is_plain(2, p)
    m = r.build_mesh(2, p)
    assert np.array_equal(m.positions, p)
    assert split(m.face_sizes, m.face_indices) == split(sizes, idx)
    # a crease makes the level not plain (the built mesh carries tags)
    rc = geom.subdiv.Refiner(cube(), creases=([[0, 1]], [2.0]))
    rc.refine(1)
    assert not rc.level_is_plain(1, rc.interpolate(1, CUBE_P))
    # out of range: False, not an error
    assert not r.level_is_plain(0, CUBE_P) and not r.level_is_plain(3, p)


def test_limit_is_the_quad_limit_mask():
    r = geom.subdiv.Refiner(cube())
    r.refine(2)
    p = r.interpolate(2, r.interpolate(1, CUBE_P))
    faces = split(*r.faces(2)[:2])
    pos, t1, t2 = r.limit(p, tangents=True)
    for v in range(len(p)):
        fs = [f for f in faces if v in f]
        n = len(fs)
        edge, diag = set(), set()
        for f in fs:
            k = f.index(v)
            edge |= {f[(k + 1) % 4], f[(k + 3) % 4]}
            diag.add(f[(k + 2) % 4])
        want = (n * n * p[v] + 4 * p[list(edge)].sum(axis=0) + p[list(diag)].sum(axis=0)) / (n * (n + 5))
        np.testing.assert_allclose(pos[v], want, atol=1e-14)
    nrm = r.limit_normals(p)
    np.testing.assert_allclose(np.linalg.norm(nrm, axis=1), 1, atol=1e-12)
    assert (np.einsum("ij,ij->i", nrm, pos - 0.5) > 0).all()  # outward
    c = np.cross(t1, t2)
    np.testing.assert_allclose(c / np.linalg.norm(c, axis=1)[:, None], nrm, atol=1e-12)


def test_soup_refiner_equals_mesh_refiner():
    a = geom.subdiv.Refiner(cube())
    b = geom.subdiv.Refiner.from_soup(8, CUBE_F)
    a.refine(2)
    b.refine(2)
    assert np.array_equal(a.face_indices(2), b.face_indices(2))
    pa = a.interpolate(2, a.interpolate(1, CUBE_P))
    pb = b.interpolate(2, b.interpolate(1, CUBE_P))
    assert np.array_equal(pa, pb)


def test_linear_face_varying_is_varying_interpolation():
    r = geom.subdiv.Refiner(cube(), fvar_boundary="all")
    idx = np.concatenate([np.array(f) for f in CUBE_F])
    ch = r.add_fvar(24, np.arange(24))  # every corner its own value: 6 islands
    assert r.fvar_count == 1 and r.fvar_mesh_channel(ch) is None
    r.refine(2)
    vals0 = CUBE_P[idx]                        # the corner's vertex position
    v1 = r.interpolate_fvar(ch, 1, vals0)
    v2 = r.interpolate_fvar(ch, 2, v1)
    var = r.interpolate_varying(2, r.interpolate_varying(1, CUBE_P))
    fv = r.fvar_face_values(ch, 2)
    np.testing.assert_allclose(v2[fv], var[r.face_indices(2)], atol=1e-15)
    np.testing.assert_allclose(r.limit_fvar(ch, v2), v2, atol=0)  # linear: stays
    assert r.fvar_size(ch, 0) == 24


def test_face_data_and_rules():
    r = geom.subdiv.Refiner(cube(), corners=([0], [10.0]))
    r.refine(1)
    d = r.interpolate_face(1, np.arange(6.0))
    assert np.array_equal(d[:, 0], [r.face_parent(1, f) for f in range(24)])
    s, rules = r.vertex_rules(0)
    assert rules[0] == "corner" and s[0] == 10 and set(rules[1:]) == {"smooth"}


def test_errors():
    r = geom.subdiv.Refiner(cube())
    with pytest.raises(ValueError):
        r.interpolate(1, CUBE_P)           # level 1 not refined yet
    r.refine(1)
    with pytest.raises(ValueError):
        r.interpolate(1, CUBE_P[:5])       # wrong row count
    with pytest.raises(geom.GeomError) as e:
        r.refine(20)
    assert e.value.code == "ERR_LIMIT"
    with pytest.raises(geom.GeomError):
        geom.subdiv.Refiner(cube(), scheme="loop")   # quads
    with pytest.raises(ValueError):
        r.add_fvar(3, [0, 1, 2])


def test_effective_options():
    pts = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    m = geom.Mesh.from_soup(pts, faces)
    r = geom.subdiv.Refiner(m, scheme="bilinear", boundary="edge_and_corner", crease_method="chaikin",
                            fvar_boundary="corners_only")
    o = r.options()
    assert o["scheme"] == "bilinear" and o["boundary"] == "edge_and_corner"
    assert o["crease_method"] == "chaikin" and o["fvar_boundary"] == "corners_only"
    assert not o["ignore_tags"]
    d = geom.subdiv.Refiner(m).options()          # 0s resolved to the scheme's defaults
    assert d["scheme"] == "catmull-clark" and None not in d.values()
