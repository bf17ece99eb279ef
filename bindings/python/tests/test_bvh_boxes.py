"""geom.spatial.Bvh over caller boxes and refitting after moved vertices:
box queries against a numpy brute force over every primitive box
(touching boxes count), the exactness of every node box (leaf = min/max of
its primitives, interior = union of its children), refit answering as a
fresh build does, and bad input."""

import numpy as np
import pytest

import geom

spatial = pytest.importorskip("geom.spatial") if geom.has_module("spatial") else None
pytestmark = pytest.mark.skipif(spatial is None, reason="spatial module not built")


def brute(plo, phi, qlo, qhi):
    return [np.flatnonzero(np.all((plo <= b) & (phi >= a), axis=1)) for a, b in zip(qlo, qhi)]


def check_nodes(bvh, plo, phi):
    """Every leaf box is exactly the min/max of its primitives' boxes and
    every interior box exactly the union of its children's."""
    nd = bvh.nodes()
    prim = bvh.prim_indices()
    assert np.array_equal(np.sort(prim), np.arange(len(plo)))
    for i in range(len(nd["min"])):
        c, ix = int(nd["count"][i]), int(nd["index"][i])
        if c:
            p = prim[ix:ix + c]
            lo, hi = plo[p].min(axis=0), phi[p].max(axis=0)
        else:
            lo = np.minimum(nd["min"][i + 1], nd["min"][ix])
            hi = np.maximum(nd["max"][i + 1], nd["max"][ix])
        assert np.array_equal(nd["min"][i], lo) and np.array_equal(nd["max"][i], hi), i


def random_boxes(rng, n, offset=0.0):
    c = rng.uniform(-1, 1, (n, 3)) + offset
    r = rng.uniform(0, 0.08, (n, 3))
    r[::7] = 0                                # some points (degenerate boxes)
    return c - r, c + r


@pytest.mark.parametrize("method", ["sah", "lbvh"])
@pytest.mark.parametrize("leaf", [0, 1, 7])
def test_boxes_against_brute_force(method, leaf):
    rng = np.random.default_rng(11)
    plo, phi = random_boxes(rng, 700)
    b = spatial.Bvh.from_boxes(plo, phi, method=method, max_leaf_size=leaf)
    check_nodes(b, plo, phi)
    assert b.depth >= 1 and b.nbytes > 0
    q = rng.uniform(-1.2, 1.2, (80, 3))
    qr = rng.uniform(0, 0.3, (80, 3))
    got = b.overlap(q - qr, q + qr)
    want = brute(plo, phi, q - qr, q + qr)
    assert len(got) == 80 and sum(map(len, want)) > 80
    for g, w in zip(got, want):
        assert np.array_equal(g, w)
    # one box, as (3,) + (3,) or (6,); the (n, 6) form of the constructor
    one = b.overlap(q[0] - qr[0], q[0] + qr[0])
    assert np.array_equal(one, want[0])
    assert np.array_equal(b.overlap(np.r_[q[0] - qr[0], q[0] + qr[0]]), want[0])
    b6 = spatial.Bvh.from_boxes(np.hstack([plo, phi]), method=method, max_leaf_size=leaf)
    assert np.array_equal(b6.prim_indices(), b.prim_indices())


def test_touching_and_point_queries_count():
    # unit cubes on a 4 x 4 x 4 lattice, sharing faces, edges and corners
    g = np.stack(np.meshgrid(*[np.arange(4.0)] * 3, indexing="ij"), -1).reshape(-1, 3)
    b = spatial.Bvh.from_boxes(g, g + 1)
    corner = b.overlap([1, 1, 1], [1, 1, 1])               # a lattice point: 8 cubes meet
    assert len(corner) == 8
    np.testing.assert_array_equal(corner, brute(g, g + 1, [[1, 1, 1]], [[1, 1, 1]])[0])
    face = b.overlap([4, 0.5, 0.5], [5, 0.6, 0.6])         # touches one face of one cube
    np.testing.assert_array_equal(face, np.flatnonzero(np.all(g == [3, 0, 0], axis=1)))
    assert len(b.overlap([4.0000001, 0, 0], [5, 1, 1])) == 0
    inf = b.overlap([-np.inf] * 3, [np.inf] * 3)           # infinite query box: all
    np.testing.assert_array_equal(inf, np.arange(64))
    assert len(b.overlap([2, 2, 2], [1, 1, 1])) == 0       # lo > hi: nothing


def test_far_from_the_origin():
    rng = np.random.default_rng(2)
    plo, phi = random_boxes(rng, 300, offset=1e8)
    b = spatial.Bvh.from_boxes(plo, phi)
    check_nodes(b, plo, phi)
    q = rng.uniform(-1, 1, (30, 3)) + 1e8
    for g, w in zip(b.overlap(q - 0.2, q + 0.2), brute(plo, phi, q - 0.2, q + 0.2)):
        assert np.array_equal(g, w)


def test_empty_and_single():
    b = spatial.Bvh.from_boxes(np.zeros((0, 3)), np.zeros((0, 3)))
    assert b.depth == 0 and len(b.nodes()["min"]) == 0
    assert [len(r) for r in b.overlap(np.zeros((3, 3)), np.ones((3, 3)))] == [0, 0, 0]
    s = spatial.Bvh.from_boxes([[0, 0, 0]], [[1, 2, 3]])
    assert s.depth == 1 and list(s.overlap([0.5, 2, 3], [9, 9, 9])) == [0]


def test_bad_boxes():
    lo = np.zeros((5, 3))
    hi = np.ones((5, 3))
    hi[3, 1] = -1                          # min > max on y
    with pytest.raises(geom.GeomError) as e:
        spatial.Bvh.from_boxes(lo, hi)
    assert e.value.code == "ERR_INVALID_ARG" and "3" in e.value.message
    hi[3, 1] = np.nan
    with pytest.raises(geom.GeomError):
        spatial.Bvh.from_boxes(lo, hi)
    hi[3, 1] = np.inf
    with pytest.raises(geom.GeomError):
        spatial.Bvh.from_boxes(lo, hi)
    with pytest.raises(ValueError):
        spatial.Bvh.from_boxes(np.zeros((4, 5)))
    with pytest.raises(ValueError):
        spatial.Bvh.from_boxes(np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(ValueError):
        spatial.Bvh.from_boxes(lo, np.ones((5, 3)), method="median")
    b = spatial.Bvh.from_boxes(lo, np.ones((5, 3)))
    with pytest.raises(ValueError):
        b.overlap([np.nan, 0, 0], [1, 1, 1])
    with pytest.raises(ValueError):
        b.refit(np.zeros((3, 3)))          # built from boxes: no triangles to refit


# -------------------------------------------------------------------- refit

def soup(rng, nv=400, nt=600):
    pos = rng.uniform(-1, 1, (nv, 3))
    tris = rng.integers(0, nv, (nt, 3))
    return pos, tris


def tri_boxes(pos, tris):
    v = pos[tris]
    return v.min(axis=1), v.max(axis=1)


@pytest.mark.parametrize("method", ["sah", "lbvh"])
def test_refit_answers_as_a_fresh_build(method):
    rng = np.random.default_rng(5)
    pos, tris = soup(rng)
    b = spatial.Bvh(pos, tris, method=method)
    check_nodes(b, *tri_boxes(pos, tris))
    before = b.nodes()
    moved = pos + rng.normal(0, 0.4, pos.shape)           # large moves: the old boxes fail
    plo, phi = tri_boxes(moved, tris)
    with pytest.raises(AssertionError):
        check_nodes(b, plo, phi)
    b.refit(moved)
    check_nodes(b, plo, phi)                                # exact boxes again
    after = b.nodes()
    assert np.array_equal(before["index"], after["index"])  # same topology
    assert np.array_equal(before["count"], after["count"])
    fresh = spatial.Bvh(moved, tris, method=method)
    q = rng.uniform(-1.5, 1.5, (60, 3))
    qr = rng.uniform(0, 0.25, (60, 3))
    want = brute(plo, phi, q - qr, q + qr)
    for g, f, w in zip(b.overlap(q - qr, q + qr), fresh.overlap(q - qr, q + qr), want):
        assert np.array_equal(g, w) and np.array_equal(f, w)
    # a refit with the connectivity passed explicitly gives the same boxes
    b.refit(pos, tris)
    check_nodes(b, *tri_boxes(pos, tris))


def test_refit_bad_input_leaves_the_bvh_unchanged():
    rng = np.random.default_rng(8)
    pos, tris = soup(rng, 50, 80)
    b = spatial.Bvh(pos, tris)
    nodes = b.nodes()
    bad = pos.copy()
    bad[tris[10, 1], 2] = np.nan
    with pytest.raises(geom.GeomError) as e:
        b.refit(bad)
    assert e.value.code == "ERR_INVALID_ARG"
    with pytest.raises(geom.GeomError):
        b.refit(pos, tris[:-1])                             # triangle count mismatch
    with pytest.raises(geom.GeomError):
        b.refit(pos[:10])                                   # indices >= nv
    after = b.nodes()
    for k in nodes:
        assert np.array_equal(nodes[k], after[k])
    q = rng.uniform(-1, 1, (20, 3))
    for g, w in zip(b.overlap(q - 0.2, q + 0.2), brute(*tri_boxes(pos, tris), q - 0.2, q + 0.2)):
        assert np.array_equal(g, w)


# ------------------------------------------ trees' arrays and memory counters

def test_meshdistance_bvh_view():
    rng = np.random.default_rng(4)
    pos, tris = soup(rng, 200, 300)
    md = spatial.MeshDistance(pos, tris)
    b = md.bvh
    del md                                           # the view keeps its owner alive
    import gc
    gc.collect()
    plo, phi = tri_boxes(pos, tris)
    check_nodes(b, plo, phi)
    q = rng.uniform(-1, 1, (20, 3))
    for g, w in zip(b.overlap(q - 0.2, q + 0.2), brute(plo, phi, q - 0.2, q + 0.2)):
        assert np.array_equal(g, w)
    with pytest.raises(ValueError):
        b.refit(pos)
    small = spatial.MeshDistance(pos, tris[:10])
    assert 0 < small.nbytes < spatial.MeshDistance(pos, tris).nbytes


@pytest.mark.parametrize("dim", [2, 3])
def test_octree_nodes_and_items(dim):
    rng = np.random.default_rng(9)
    P = rng.random((900, dim))
    P[::5] = P[1::5]                                       # duplicates
    t = spatial.Octree(P, bucket_size=8)
    assert t.dim == dim and t.nbytes > 0
    nd, items = t.nodes(), t.items()
    assert len(nd["level"]) == t.node_count
    assert np.array_equal(np.sort(items), np.arange(len(P)))
    assert nd["item_total"][0] == len(P) and nd["level"][0] == 0
    P3 = np.zeros((len(P), 3))
    P3[:, :dim] = P
    for i in range(t.node_count):
        s, n = int(nd["item_start"][i]), int(nd["item_total"][i])
        sub = P3[items[s:s + n]]
        if n:   # the tight box of the subtree's items
            assert np.array_equal(nd["bounds_min"][i], sub.min(axis=0))
            assert np.array_equal(nd["bounds_max"][i], sub.max(axis=0))
        fc, mask = int(nd["first_child"][i]), int(nd["child_mask"][i])
        if fc < 0:
            assert mask == 0 and nd["own_count"][i] == n
            continue
        k = bin(mask).count("1")
        kids = range(fc, fc + k)
        assert all(nd["level"][c] == nd["level"][i] + 1 for c in kids)
        assert sum(int(nd["item_total"][c]) for c in kids) + int(nd["own_count"][i]) == n
        assert np.all(nd["cell_min"][list(kids)] >= nd["cell_min"][i])
        assert np.all(nd["cell_max"][list(kids)] <= nd["cell_max"][i])
    segs = spatial.Octree.segments(P[:, :2], np.arange(40).reshape(-1, 2))
    assert segs.dim == 2 and len(segs.items()) == 20


def test_kdtree_node_count():
    rng = np.random.default_rng(1)
    for n, leaf in ((1, 10), (100, 10), (1000, 4)):
        t = spatial.KdTree(rng.random((n, 3)), leaf_size=leaf)
        c = t.node_count
        assert c >= 2 * -(-n // leaf) - 1 and c % 2 == 1   # a full binary tree


@pytest.mark.parametrize("method", ["sah", "lbvh"])
def test_overlap_in_c_grid_points_offsets_threads(method):
    """Bvh.overlap (geom_bvh_query_boxes) on boxes snapped to a coarse grid
    at a 1e8 offset (faces, edges and corners coincide), point queries and
    point primitives, against brute force; 1 and 4 threads answer alike."""
    rng = np.random.default_rng(23)
    n, m = 900, 400
    plo = 1e8 + np.floor(rng.uniform(0, 32, (n, 3))) / 8
    phi = plo + np.floor(rng.uniform(0, 8, (n, 3))) / 8
    phi[::5] = plo[::5]                                   # point primitives
    qlo = 1e8 + np.floor(rng.uniform(0, 32, (m, 3))) / 8
    qhi = qlo + np.floor(rng.uniform(0, 8, (m, 3))) / 8
    qhi[::3] = qlo[::3]                                   # point queries
    b = spatial.Bvh.from_boxes(plo, phi, method=method, max_leaf_size=3)
    want = brute(plo, phi, qlo, qhi)
    got1 = b.overlap(qlo, qhi, threads=1)
    got4 = b.overlap(np.hstack([qlo, qhi]), threads=4)
    assert sum(len(w) for w in want) > m
    for g1, g4, w in zip(got1, got4, want):
        assert np.array_equal(g1, w) and np.array_equal(g4, w)
    assert b.overlap(np.empty((0, 3)), np.empty((0, 3))) == []
