"""Volume files through the binding (geom.read_volume) and the batch entry
points: files made here from a closed form (every sample type, NRRD gzip
and bzip2, MetaImage, INRIMAGE, NIfTI-1 gzipped, raw with a header, unknown
or invalid spacing warned about or refused) read back exactly
at the header's placement; dtypes that cannot be read exactly are refused;
batch evaluation (bary, curve, surface, volume) against numpy closed
forms, failing rows as NaN or raised."""

import gzip
import os
import struct

import numpy as np
import pytest

import geom

N = (5, 4, 3)
SP = (0.5, 2.0, 0.25)
ORG = (-1.0, 3.0, 1e6)


def values(dtype):
    i, j, k = np.meshgrid(np.arange(N[0]), np.arange(N[1]), np.arange(N[2]), indexing="ij")
    v = i + 7 * j + 31 * k
    if np.dtype(dtype).kind == "i":
        v = v - 40
    return v.astype(dtype)  # [i, j, k]


def raw_bytes(v, big=False):
    return np.asfortranarray(v).astype(v.dtype.newbyteorder(">" if big else "<")).tobytes(order="F")


@pytest.mark.parametrize("dtype", ["u1", "i1", "u2", "i2", "u4", "i4", "f4", "f8"])
@pytest.mark.parametrize("big", [False, True])
def test_raw_every_type(dtype, big):
    v = values(dtype)
    data = b"HEADER" + raw_bytes(v, big)
    vol = geom.read_volume(data, dims=N, dtype=dtype, skip=6, big_endian=big, spacing=SP,
                           origin=ORG)
    assert vol.shape == N
    assert vol.spacing == SP and vol.origin == ORG
    assert np.array_equal(vol.samples, v.astype(np.float64))
    assert vol.info["sample"] == {"u1": "u8", "i1": "i8", "u2": "u16", "i2": "i16", "u4": "u32",
                                  "i4": "i32", "f4": "f32", "f8": "f64"}[dtype]
    with pytest.raises(geom.GeomError):
        geom.read_volume(data[:-1], dims=N, dtype=dtype, skip=6)


def test_nrrd_gzip_and_flip():
    v = values("i2")
    head = ("NRRD0004\ntype: short\ndimension: 3\nsizes: %d %d %d\nencoding: gzip\n"
            "endian: big\nspace directions: (%g,0,0) (0,%g,0) (0,0,-%g)\n"
            "space origin: (%g,%g,%g)\n\n" % (N + SP + ORG)).encode()
    vol = geom.read_volume(head + gzip.compress(raw_bytes(v, True)))
    assert vol.info["compressed"] and vol.info["flipped"] == (False, False, True)
    # file sample (i, j, k) sits at ORG + (i sx, j sy, -k sz): same world point
    for i, j, k in [(0, 0, 0), (4, 3, 2), (2, 1, 1)]:
        p = (ORG[0] + i * SP[0], ORG[1] + j * SP[1], ORG[2] - k * SP[2])
        assert vol.eval(p) == v[i, j, k]
    assert vol.origin[2] == ORG[2] - 2 * SP[2]


def test_nrrd_bzip2_reads_as_raw(tmp_path):
    import bz2
    v = values("i2")
    head = ("NRRD0005\ntype: short\ndimension: 3\nsizes: %d %d %d\nencoding: %s\n"
            "endian: big\nspacings: %g %g %g\naxis mins: %g %g %g\n\n")
    raw = geom.read_volume((head % (N + ("raw",) + SP + ORG)).encode() + raw_bytes(v, True))
    data = bz2.compress(raw_bytes(v, True))
    bz = geom.read_volume((head % (N + ("bzip2",) + SP + ORG)).encode() + data)
    assert bz.info["compressed"] and not raw.info["compressed"]
    assert np.array_equal(bz.samples, raw.samples) and np.array_equal(bz.samples, v)
    assert bz.spacing == raw.spacing == SP and bz.origin == raw.origin == ORG
    # two concatenated streams, as the bzip2 program writes with cat
    half = len(raw_bytes(v, True)) // 2
    two = bz2.compress(raw_bytes(v, True)[:half]) + bz2.compress(raw_bytes(v, True)[half:])
    assert np.array_equal(geom.read_volume((head % (N + ("bz2",) + SP + ORG)).encode() + two)
                          .samples, v)
    # truncated and corrupt streams: GeomError naming the file and bzip2
    for name, body in [("cut.nrrd", data[:-30]),
                       ("bad.nrrd", data[:20] + bytes([data[20] ^ 0x55]) + data[21:])]:
        p = tmp_path / name
        p.write_bytes((head % (N + ("bzip2",) + SP + ORG)).encode() + body)
        with pytest.raises(geom.GeomError, match=name + ".*bzip2"):
            geom.read_volume(str(p))


def test_unknown_spacing_warns():
    v = values("u1")
    head = ("NRRD0004\ntype: uchar\ndimension: 3\nsizes: %d %d %d\nencoding: raw\n"
            "spacings: 0.5 nan 2\n\n" % N).encode()
    with pytest.warns(RuntimeWarning, match=r"x.nrrd: line 6: 'spacings: 0.5 nan 2': axis 1"):
        vol = geom.read_volume(head + raw_bytes(v), source_name="x.nrrd")
    assert vol.spacing == (0.5, 1.0, 2.0)
    assert vol.info["spacing_defaulted"] == (False, True, False)
    assert "spacing unknown (nan), 1 used" in vol.info["warnings"][0]
    with pytest.raises(geom.GeomError, match="spacings"):
        geom.read_volume(head.replace(b"nan", b"0") + raw_bytes(v))
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, N[0], N[1], N[2], 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 2, 8)
    struct.pack_into("<8f", h, 76, 1, -0.5, 2, 0, 0, 0, 0, 0)
    struct.pack_into("<f", h, 108, 352)
    h[344:348] = b"n+1\0"
    with pytest.warns(RuntimeWarning, match=r"pixdim\[1\] = -0.5 \(byte 80\), pixdim\[3\] = 0"):
        vol = geom.read_volume(bytes(h) + raw_bytes(v))
    assert vol.spacing == (1.0, 2.0, 1.0)
    with pytest.raises(geom.GeomError, match="ElementSpacing"):
        geom.read_volume(("NDims = 3\nDimSize = %d %d %d\nElementType = MET_UCHAR\n"
                          "ElementSpacing = 1 nan 1\nElementDataFile = LOCAL\n" % N).encode()
                         + raw_bytes(v))


def test_nifti_gz_and_metaimage(tmp_path):
    v = values("f4")
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, N[0], N[1], N[2], 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 16, 32)
    struct.pack_into("<8f", h, 76, 1, SP[0], SP[1], SP[2], 0, 0, 0, 0)
    struct.pack_into("<f", h, 108, 352)
    h[344:348] = b"n+1\0"
    path = tmp_path / "v.nii.gz"
    path.write_bytes(gzip.compress(bytes(h) + raw_bytes(v)))
    vol = geom.read_volume(str(path))
    assert vol.info["format"] == "nifti" and vol.info["compressed"]
    assert vol.samples.dtype == np.float32 and np.array_equal(vol.samples, v)
    assert vol.spacing == SP
    mhd = tmp_path / "v.mhd"
    mhd.write_text("NDims = 3\nDimSize = %d %d %d\nElementSpacing = %g %g %g\nOffset = %g %g %g\n"
                   "ElementType = MET_USHORT\nElementDataFile = v.raw\n" % (N + SP + ORG))
    (tmp_path / "v.raw").write_bytes(raw_bytes(values("u2")))
    vol = geom.read_volume(mhd)
    assert vol.info["format"] == "metaimage" and vol.origin == ORG
    assert np.array_equal(vol.samples, values("u2"))


def test_inrimage():
    v = values("u1")
    h = ("#INRIMAGE-4#{\nXDIM=%d\nYDIM=%d\nZDIM=%d\nVDIM=1\nTYPE=unsigned fixed\nPIXSIZE=8 bits\n"
         "CPU=decm\nVX=%g\nVY=%g\nVZ=%g\n" % (N + SP))
    h = h + "\n" * (252 - len(h)) + "##}\n"
    vol = geom.read_volume(h.encode() + raw_bytes(v))
    assert vol.info["format"] == "inrimage" and vol.spacing == SP
    assert np.array_equal(vol.samples, v)


def test_errors_name_the_file(tmp_path):
    p = tmp_path / "bad.nrrd"
    p.write_bytes(b"NRRD0004\ntype: int64\n")
    with pytest.raises(geom.GeomError) as e:
        geom.read_volume(p)
    assert "bad.nrrd" in str(e.value) and "int64" in str(e.value)
    with pytest.raises(geom.GeomError):
        geom.read_volume(b"plain text, no header")
    with pytest.raises(TypeError):
        geom.read_volume(b"x" * 8, dims=(1, 1, 1), dtype="i8")   # int64 is not a sample type
    with pytest.raises(ValueError):
        geom.read_volume("a\0b")


def test_cgal_skull_when_present():
    tar = "/usr/share/doc/libcgal-dev/data.tar.gz"
    if not os.path.exists(tar):
        pytest.skip("libcgal-demo not installed")
    import tarfile
    with tarfile.open(tar) as t:
        data = t.extractfile("data/images/skull_2.9.inr").read()
    vol = geom.read_volume(data)
    ref = np.frombuffer(data[256:], dtype="<f4").reshape((64, 64, 64), order="F")
    assert vol.shape == (64, 64, 64) and np.array_equal(vol.samples, ref)
    assert vol.spacing == (3.94305, 3.94305, 3.65079)


@pytest.mark.parametrize("dtype", ["i8", "u8", "c8", "c16", "O", "U1"])
def test_marching_cubes_rejects_lossy_dtypes(dtype):
    arr = np.zeros((3, 3, 3), dtype=dtype)
    with pytest.raises(TypeError):
        geom.marching_cubes(arr, iso=0.5)


def test_marching_cubes_accepts_integers_exactly():
    i, j, k = np.meshgrid(*(np.arange(9),) * 3, indexing="ij")
    r2 = ((i - 4) ** 2 + (j - 4) ** 2 + (k - 4) ** 2).astype(np.uint16)
    m1, _ = geom.marching_cubes(r2, iso=9)
    m2, _ = geom.marching_cubes(r2.astype(np.float64), iso=9)
    assert m1.n_faces == m2.n_faces > 0
    vol = geom.Volume(r2, spacing=(2, 2, 2), origin=(10, 0, 0))
    m3, _ = geom.marching_cubes(vol, iso=9)
    pts = m3.positions
    assert np.allclose(np.linalg.norm(pts - (18, 8, 8), axis=1), 6, atol=0.2)


def test_batch_bary_against_numpy():
    rng = np.random.default_rng(3)
    a, b, c = np.array([0.1, 0.2]), np.array([3.0, 0.5]), np.array([1.0, 2.5])
    p = rng.uniform(-1, 3, (1000, 2))
    lam = geom.bary.tri2(a, b, c, p)
    assert np.allclose(lam[:, :1] * a + lam[:, 1:2] * b + lam[:, 2:] * c, p, atol=1e-13)
    assert np.allclose(lam.sum(axis=1), 1, atol=1e-14)
    # per-row triangles, one degenerate: NaN row or an error naming the row
    A = np.tile(a, (1000, 1))
    A[7] = b
    B = np.tile(b, (1000, 1))
    C = np.tile(c, (1000, 1))
    C[7] = (a + b) / 2 * 0 + b  # b == c: degenerate
    out = geom.bary.tri2(A, B, C, p, errors="nan")
    assert np.isnan(out[7]).all() and np.isfinite(np.delete(out, 7, axis=0)).all()
    with pytest.raises(geom.GeomError) as e:
        geom.bary.tri2(A, B, C, p)
    assert "row 7" in str(e.value)
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    q = rng.uniform(0, 1, (100, 2))
    w = geom.bary.mean_value(sq, q)
    assert np.allclose(w @ sq, q, atol=1e-13)
    w = geom.bary.wachspress(sq, q)
    assert np.allclose(w @ sq, q, atol=1e-13)


def test_batch_curve_surface_volume():
    P = np.array([[0, 0, 0], [1, 2, 0], [3, 2, 1], [4, 0, 0]], dtype=float)
    crv = geom.curve.NurbsCurve(3, [0, 0, 0, 0, 1, 1, 1, 1], P)
    u = np.linspace(0, 1, 101)
    s = 1 - u
    ref = np.stack([s**3, 3 * s * s * u, 3 * s * u * u, u**3], axis=1) @ P
    assert np.allclose(crv.eval(u), ref, atol=1e-14)
    with pytest.raises(geom.GeomError):
        crv.eval([0.5, 1.5])
    Q = np.random.default_rng(2).uniform(0, 1, (4, 4, 3))
    srf = geom.surface.NurbsSurface(3, 3, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1], Q)
    bu = np.stack([s**3, 3 * s * s * u, 3 * s * u * u, u**3], axis=1)
    ref = np.einsum("ni,nj,ijk->nk", bu, bu[::-1], Q)
    assert np.allclose(srf.eval(u, u[::-1]), ref, atol=1e-14)
    lin = geom.Volume(np.fromfunction(lambda i, j, k: 2 * i - j + 3 * k, (4, 5, 6)),
                      spacing=(1, 2, 0.5), origin=(1, 1, 1))
    pts = np.random.default_rng(5).uniform((1, 1, 1), (4, 9, 3.5), (50, 3))
    want = 2 * (pts[:, 0] - 1) - (pts[:, 1] - 1) / 2 + 3 * (pts[:, 2] - 1) / 0.5
    val, grad = lin.eval(pts, gradient=True)
    assert np.allclose(val, want, atol=1e-12)
    assert np.allclose(grad, [2, -0.5, 6], atol=1e-12)


def test_halfedge_arrays_and_rings():
    # a square of two triangles and an octahedron (every vertex valence 4)
    sq = geom.Mesh.from_soup([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    he = sq.halfedges()
    nh = sq.n_halfedges
    assert nh == 10
    h = np.arange(nh)
    assert np.array_equal(he["next"][he["prev"]], h)
    inner = he["face"] != 0xFFFFFFFF
    # a face's three half-edges: next^3 = identity
    assert np.array_equal(he["next"][he["next"][he["next"][inner]]], h[inner])
    # the vertex a half-edge points to is where its opposite starts: prev(opp).vertex
    assert np.array_equal(he["vertex"][he["prev"][he["opposite"]]], he["vertex"][he["prev"]][he["opposite"]])
    o = geom.Mesh.from_soup([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
                            [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                             [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    off, ring = o.vertex_rings()
    assert np.array_equal(np.diff(off), [4] * 6)
    for v in range(6):
        nb = set(ring[off[v]:off[v + 1]].tolist())
        assert nb == set(range(6)) - {v, v ^ 1}          # every vertex but itself and its antipode
        assert np.array_equal(np.sort(o.one_ring(v)), np.sort(ring[off[v]:off[v + 1]]))
    off, faces = o.vertex_rings("faces")
    assert faces.size == 24
    assert sq.boundary_loops() == 1
    loops = sq.boundary_loop_vertices()
    assert len(loops) == 1 and sorted(loops[0].tolist()) == [0, 1, 2, 3]
    # consecutive loop vertices are joined by a boundary edge
    lp = loops[0].tolist()
    edges = {tuple(sorted(e)) for e in sq.edges.tolist()}
    assert all(tuple(sorted((lp[i], lp[(i + 1) % 4]))) in edges for i in range(4))
    assert o.boundary_loop_vertices() == []


def test_bspline_basis_batch():
    knots = [0, 0, 0, 1, 2, 3, 3, 3]
    u = np.linspace(0, 3, 31)
    spans, ders = geom.curve.bspline_basis(2, knots, u, nderiv=1)
    assert ders.shape == (31, 2, 3)
    assert np.allclose(ders[:, 0].sum(axis=1), 1, atol=1e-15)      # partition of unity
    assert np.allclose(ders[:, 1].sum(axis=1), 0, atol=1e-13)      # derivatives sum to 0
    # uniform quadratic in the middle span [1, 2): N = ((1-t)^2/2, -t^2 + t + 1/2, t^2/2)
    t = 0.25
    sp, d = geom.curve.bspline_basis(2, knots, 1.25)
    assert sp == 3 and np.allclose(d[0], [(1 - t) ** 2 / 2, -t * t + t + 0.5, t * t / 2], atol=1e-15)
    with pytest.raises(geom.GeomError):
        geom.curve.bspline_basis(2, knots, [1.0, 4.0])


def test_knot_refine_and_remove_keep_the_curve():
    P = np.array([[0, 0], [1, 2], [3, 2], [4, 0], [5, 1]], dtype=float)
    c = geom.curve.NurbsCurve(3, [0, 0, 0, 0, 0.5, 1, 1, 1, 1], P)
    r = c.refine([0.25, 0.5, 0.75])
    assert r.n == c.n + 3
    u = np.linspace(0, 1, 57)
    assert np.allclose(r.eval(u), c.eval(u), atol=1e-14)
    back, removed = r.remove_knot(0.25, times=1, tol=1e-12)
    assert removed == 1 and back.n == r.n - 1
    assert np.allclose(back.eval(u), c.eval(u), atol=1e-11)


def _corner_tuples(mesh, name):
    """Every face corner as (position, value) rounded to float32: the
    mesh's geometry and one corner channel, independent of vertex order,
    face order and triangulation."""
    vals, idx = mesh.corner(name)
    pos = mesh.positions.astype(np.float32)
    fi = mesh.face_indices
    out = set()
    for k in range(fi.size):
        v = vals[idx[k]].astype(np.float32) if idx[k] >= 0 else None
        out.add((tuple(pos[fi[k]].tolist()), None if v is None else tuple(v.tolist())))
    return out


def test_glb_round_trip(data_dir):
    src = geom.Mesh.read(os.path.join(data_dir, "cube_seams.obj"))
    src.set_corner("normal", *_flat_normals(src))
    glb = src.to_bytes("glb")
    back = geom.Mesh.from_bytes(glb, format="glb")
    # positions welded back: the same vertices, seams kept as corner values
    assert back.n_vertices == src.n_vertices
    assert back.topology()["genus"] == src.topology()["genus"] == 0
    assert back.topology()["closed"]
    for name in ("uv", "normal"):
        assert _corner_tuples(back, name) == _corner_tuples(src, name), name
    # the file is also recognised without a format hint
    assert geom.Mesh.from_bytes(glb).n_faces == back.n_faces
    # malformed: cut short, bad magic, an index beyond its vertices
    for bad in (glb[:40], b"glTX" + glb[4:]):
        with pytest.raises(geom.GeomError):
            geom.Mesh.from_bytes(bad, format="glb")


def _flat_normals(mesh):
    """Per-face normals as a corner channel (values, indices)."""
    pos = mesh.positions
    sizes = mesh.face_sizes
    fi = mesh.face_indices
    normals, idx, k = [], [], 0
    for f, n in enumerate(sizes):
        a, b, c = pos[fi[k]], pos[fi[k + 1]], pos[fi[k + 2]]
        nv = np.cross(b - a, c - a)
        normals.append(nv / np.linalg.norm(nv))
        idx += [f] * int(n)
        k += int(n)
    return np.array(normals), np.array(idx)


def test_volume_bounds_are_the_sampled_box():
    v = geom.implicit.Volume(np.zeros((4, 3, 2), dtype=np.float32), spacing=(0.5, 2, 3),
                             origin=(1e8, -1, 0.25))
    lo, hi = v.bounds
    np.testing.assert_array_equal(lo, [1e8, -1, 0.25])
    np.testing.assert_array_equal(hi, [1e8 + 1.5, 3, 3.25])
    # eval is defined on that box: its corners interpolate, just outside is NaN or clamped
    assert np.isfinite(v.eval(hi)) and np.isfinite(v.eval(lo))
