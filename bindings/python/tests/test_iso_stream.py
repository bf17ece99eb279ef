"""geom.iso: the chunks of geom_iso_extract_stream concatenated against
marching_cubes' whole surface (same vertices, normals and triangles, in
order), stopping early (callback returning False, generator closed, an
exception), and the triangle estimates against a brute-force count of the
crossed cells (grids) and the extracted surface (functions)."""

import threading

import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not (geom.has_module("iso") and geom.has_module("meshio")),
                                reason="no iso module")

BOX = (-1.5, -1.3, -1.2, 1.4, 1.3, 1.25)
TORUS = "torus(1, 0.35)"


def joined(chunks):
    v = np.concatenate([c["vertices"] for c in chunks])
    t = np.concatenate([c["triangles"] for c in chunks])
    return v, t


def mesh_arrays(m):
    return m.positions, np.asarray(m.face_indices, dtype=np.int64).reshape(-1, 3)


@pytest.mark.parametrize("normals,caps", [(False, False), (True, False), (True, True)])
def test_chunks_are_marching_cubes(normals, caps):
    box = (-1.5, -1.5, -0.2, 1.5, 1.5, 0.25) if caps else BOX   # caps: the box cuts the torus
    res = (40, 37, 23)
    chunks = list(geom.iso.chunks(TORUS, box, res, normals=normals, caps=caps))
    assert len(chunks) > 1
    first = 0
    for c in chunks:   # numbering: each chunk's vertices follow the previous ones
        assert c["first_vertex"] == first
        first += len(c["vertices"])
        if len(c["triangles"]):
            assert c["triangles"].max() < first
    assert chunks[-1]["caps"] == caps and not any(c["caps"] for c in chunks[:-1])
    m, rep = geom.marching_cubes(TORUS, box, res, normals=normals, caps=caps)
    v, t = joined(chunks)
    mv, mt = mesh_arrays(m)
    assert np.array_equal(v, mv) and np.array_equal(t, mt)
    if normals:
        n = np.concatenate([c["normals"] for c in chunks if len(c["vertices"])])
        assert np.array_equal(n, m.channel("normal"))
    else:
        assert all(c["normals"] is None for c in chunks)


def test_extract_stream_callback_and_report():
    got = []
    rep = geom.iso.extract_stream("sphere(1)", BOX, (30, 30, 30), got.append)
    v, t = joined(got)
    assert rep["n_vertices"] == len(v) and rep["n_triangles"] == len(t) and not rep["stopped"]
    # vertices on the unit sphere to the marching-cubes chordal error (h^2 / 8 r)
    h = 2.9 / 30
    assert np.abs(np.linalg.norm(v, axis=1) - 1).max() <= h * h / 8 * 1.5


def test_stop_and_errors():
    seen = []
    rep = geom.iso.extract_stream(TORUS, BOX, (60, 60, 60),
                                  lambda c: seen.append(c) or len(seen) < 2)
    assert rep["stopped"] and len(seen) == 2
    full = geom.iso.extract_stream(TORUS, BOX, (60, 60, 60), lambda c: None)
    assert rep["n_triangles"] < full["n_triangles"]

    def boom(c):
        raise KeyError("from the callback")
    with pytest.raises(KeyError):
        geom.iso.extract_stream(TORUS, BOX, (20, 20, 20), boom)
    with pytest.raises(geom.GeomError) as e:
        list(geom.iso.chunks(TORUS, (0, 0, 0, 0, 1, 1), (8, 8, 8)))   # empty box
    assert e.value.code == "ERR_INVALID_ARG"


def test_closing_the_generator_stops_the_worker():
    before = threading.active_count()
    g = geom.iso.chunks(TORUS, BOX, (200, 200, 200))
    first = next(g)
    assert len(first["triangles"]) > 0
    g.close()
    assert threading.active_count() == before
    # the report is the generator's return value
    def collect():
        rep = yield from geom.iso.chunks("sphere(1)", BOX, (10, 10, 10))
        yield rep
    *cs, rep = list(collect())
    assert rep["n_triangles"] == sum(len(c["triangles"]) for c in cs)


def test_python_function_field():
    f = lambda p: np.sum(p * p, axis=1) - 1.0     # noqa: E731
    cs = list(geom.iso.chunks(f, BOX, (16, 16, 16)))
    m, _ = geom.marching_cubes(f, BOX, (16, 16, 16))
    v, t = joined(cs)
    assert np.array_equal(v, m.positions)


def test_grid_estimate_counts_crossed_cells():
    rng = np.random.default_rng(5)
    vol = rng.standard_normal((13, 11, 9)).cumsum(axis=0)
    iso = 0.3
    below = vol < iso   # a cell is crossed when its 8 corners are not all on one side
    c = np.zeros((12, 10, 8), dtype=int)
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                c += below[dx:dx + 12, dy:dy + 10, dz:dz + 8]
    crossed = np.count_nonzero((c > 0) & (c < 8))
    assert geom.iso.estimate_triangles(vol, iso=iso) == 2 * crossed
    assert geom.iso.estimate_triangles(vol.astype(np.float32), iso=iso) == 2 * crossed


def test_function_estimate_near_the_result():
    for res in ((40, 40, 40), (120, 120, 120)):
        est = geom.iso.estimate_triangles(TORUS, BOX, res)
        m, _ = geom.marching_cubes(TORUS, BOX, res)
        assert 0.7 < est / m.n_faces < 1.3, (res, est, m.n_faces)
    assert geom.iso.estimate_triangles("x*x + y*y + z*z + 5", BOX, (50, 50, 50)) == 0


def test_estimate_counts_caps():
    # a gyroid cut by its box: with caps the estimate includes the cap
    # triangles (without them it was about 0.7x of the capped count)
    g = "sin(5*x)*cos(5*y) + sin(5*y)*cos(5*z) + sin(5*z)*cos(5*x)"
    box = (-1, -1, -1, 1, 1, 1)
    for res in ((30, 30, 30), (90, 90, 90)):
        m, _ = geom.marching_cubes(g, box, res, caps=True)
        est = geom.iso.estimate_triangles(g, box, res, caps=True)
        bare = geom.iso.estimate_triangles(g, box, res)
        assert 0.9 < est / m.n_faces < 1.1 and bare / m.n_faces < 0.8, (res, est, bare, m.n_faces)
    # a sampled volume: the caps counted exactly
    x = np.linspace(-1, 1, 25)
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    vol = np.sin(5 * X) * np.cos(5 * Y) + np.sin(5 * Y) * np.cos(5 * Z) + np.sin(5 * Z) * np.cos(5 * X)
    m_caps, _ = geom.marching_cubes(vol, caps=True)
    m_bare, _ = geom.marching_cubes(vol)
    est_caps = geom.iso.estimate_triangles(vol, caps=True)
    assert est_caps - geom.iso.estimate_triangles(vol) == m_caps.n_faces - m_bare.n_faces
