"""geom.spatial: batch queries against numpy brute force (ties by index,
inclusive radius), closest points and signed distances on a cube, the BVH
arrays."""

import numpy as np
import pytest

import geom

spatial = pytest.importorskip("geom.spatial") if geom.has_module("spatial") else None
pytestmark = pytest.mark.skipif(spatial is None, reason="spatial module not built")


def brute_knn(P, q, k):
    d2 = ((P - q) ** 2).sum(axis=1)
    order = np.lexsort((np.arange(len(P)), d2))
    return order[:k], np.sqrt(d2[order[:k]])


@pytest.mark.parametrize("cls", ["KdTree", "Octree"])
@pytest.mark.parametrize("dim", [2, 3])
def test_knn_radius_box(cls, dim):
    rng = np.random.default_rng(3)
    P = np.floor(rng.random((2000, dim)) * 8) / 8  # many duplicates and ties
    Q = np.floor(rng.random((50, dim)) * 16) / 16
    t = getattr(spatial, cls)(P)
    idx, dist = t.knn(Q, 6)
    assert idx.shape == (50, 6)
    for j in range(50):
        bi, bd = brute_knn(P, Q[j], 6)
        assert (idx[j] == bi).all()
        assert np.array_equal(dist[j], bd)
    rows = t.radius(Q, 0.125)
    for j, (ri, rd) in enumerate(rows):
        d2 = ((P - Q[j]) ** 2).sum(axis=1)
        want = np.lexsort((np.arange(len(P)), d2))
        want = want[np.sqrt(d2[want]) <= 0.125]
        assert (ri == want).all()
    lo, hi = np.full(dim, 0.25), np.full(dim, 0.5)
    inside = np.nonzero(((P >= lo) & (P <= hi)).all(axis=1))[0]
    assert (t.box(lo, hi) == inside).all()
    one_idx, one_d = t.knn(Q[0], 3)
    assert one_idx.shape == (3,)


def test_errors():
    with pytest.raises(geom.GeomError):
        spatial.KdTree(np.array([[0.0, 0.0, np.nan]]))
    t = spatial.KdTree(np.zeros((3, 3)))
    with pytest.raises(geom.GeomError):
        t.knn(np.array([[0.0, np.inf, 0.0]]), 1)
    idx, d = t.knn(np.zeros(3), 5)
    assert list(idx) == [0, 1, 2, -1, -1]


def cube():
    P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
    quads = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    T = []
    for a, b, c, d in quads:
        T += [[a, b, c], [a, c, d]]
    return P, np.array(T)


def test_mesh_distance():
    P, T = cube()
    md = spatial.MeshDistance(P, T)
    Q = np.array([[0.5, 0.5, 0.5], [2, 0.5, 0.5], [0.5, 0.5, -3], [0.25, 0.25, 0.25]])
    sd, rep = md.signed_distance(Q)
    assert np.allclose(sd, [-0.5, 1, 3, -0.25], atol=1e-15)
    assert rep["method"] in ("bound", "BOUND", "1") or rep["max_error"] >= 0
    w, rep = md.winding_number(Q)  # Barill et al.'s approximation: within its bound
    assert (np.abs(w - [1, 0, 0, 1]) <= rep["max_error"] + 1e-12).all()
    exact = spatial.MeshDistance(P, T, beta=-1)
    w, rep = exact.winding_number(Q)
    assert np.allclose(w, [1, 0, 0, 1], atol=1e-12) and rep["max_error"] == 0
    c = md.closest(Q)
    assert np.allclose(c["point"][1], [1, 0.5, 0.5])
    assert np.allclose(c["distance"], np.abs(sd))
    assert c["triangle"].shape == (4,)


def test_bvh_arrays():
    P, T = cube()
    for method in ("sah", "lbvh"):
        b = spatial.Bvh(P, T, method=method, max_leaf_size=2)
        n = b.nodes()
        prims = b.prim_indices()
        assert sorted(prims) == list(range(12))
        assert (n["min"][0] == 0).all() and (n["max"][0] == 1).all()
        assert (n["count"] <= 2).all()
        assert b.depth >= 2


def test_octree_elements():
    P, T = cube()
    t = spatial.Octree.triangles(P, T)
    assert list(t.box([0.9, 0.9, 0.9], [1, 1, 1])) == [2, 3, 6, 7, 8, 9]
    planes = np.array([[1, 0, 0, 0.5], [-1, 0, 0, 2], [0, 1, 0, 1], [0, -1, 0, 2], [0, 0, 1, 1],
                       [0, 0, -1, 2]], dtype=float)
    assert len(t.frustum(planes)) == 12
