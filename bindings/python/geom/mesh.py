"""Half-edge polygon meshes (geom/mesh.h) and mesh files (geom/meshio.h).

A Mesh owns one C geom_mesh. It is freed by close(), at the end of a
``with`` block, or when the Mesh is garbage-collected, whichever comes
first; using a closed Mesh raises ValueError.

Lifetime of arrays: every array a Mesh returns (positions, faces, channels,
normals, ...) is a numpy COPY of the C data, owned by numpy. It stays valid
after the mesh changes or is closed, and writing to it does not change the
mesh: assign to ``mesh.positions`` (or use set_channel / set_corner) to do
that. Copies cost one memcpy, negligible next to any mesh operation.

Faces are listed as geom_mesh_to_soup lists them: face f's vertices in
counter-clockwise order starting at its first halfedge, so a soup given to
from_soup() comes back unchanged (repairs aside). Corner (face-varying)
channels are returned with one index per face corner in the same order
(see corner()).
"""

import os

import numpy as np

from ._ffi import ffi, has_module, lib
from .core import (INVALID_INDEX, check, dptr, from_c_doubles, from_c_uint32,
                   new_diag, struct_dict, to_mat4)

DOMAINS = {"vertex": 0, "face": 1, "edge": 2, "corner": 3}
_DOMAIN_NAMES = {v: k for k, v in DOMAINS.items()}
NORMAL_WEIGHTS = {"angle": 0, "uniform": 1, "area": 2, "max": 3}
FEATURE_KINDS = {"boundary": 1, "crease": 2, "silhouette": 4}
ENCODINGS = {"default": 0, "ascii": 1, "binary": 2, "binary_le": 2, "binary_be": 3}
OMIT_BITS = {"normal": 1, "uv": 2, "color": 4, "tangent": 8, "meta": 16}
DEFECT_KINDS = {1: "bad_index", 2: "next_prev", 3: "face_cycle", 4: "vertex_halfedge",
                5: "boundary_not_first", 6: "nonmanifold_vertex", 7: "deleted_reference",
                8: "small_face", 9: "channel"}
SUBDIV_SCHEMES = ("catmull-clark", "catmark", "loop", "bilinear", "butterfly", "sqrt3")
_SUBDIV_BOUNDARY = {None: 0, "none": 1, "edge_only": 2, "edge_and_corner": 3}
_SUBDIV_FVAR = {None: 0, "none": 1, "corners_only": 2, "corners_plus1": 3, "corners_plus2": 4,
                "boundaries": 5, "all": 6}
_SUBDIV_CREASE = {None: 0, "uniform": 1, "chaikin": 2}
_SUBDIV_TRIANGLES = {None: 0, "catmark": 1, "smooth": 2}

#: Keys of the repairs dictionary, in geom-info's order.
REPAIR_KEYS = ("invalid_faces", "flipped_faces", "nonmanifold_edges", "detached_faces",
               "split_vertices", "added_vertices", "isolated_vertices",
               "nonorientable_components")


def _format_code(fmt):
    if fmt is None:
        return 0
    code = lib.geom_meshio_format_from_name(str(fmt).encode())
    if code == 0:
        raise ValueError("unknown mesh format %r (obj, off, ply, stl, glb)" % (fmt,))
    return code


def _format_name(code):
    return ffi.string(lib.geom_meshio_format_name(code)).decode()


def _choice(table, value, what):
    try:
        return table[value]
    except KeyError:
        names = sorted(k for k in table if k is not None)
        raise ValueError("%s must be one of %s, not %r" % (what, names, value)) from None


def _soup_arrays(faces):
    """(face_sizes, indices) uint32 arrays from an (m, k) array or a list of
    index sequences."""
    if isinstance(faces, np.ndarray) and faces.ndim == 2:
        arr = faces
        sizes = np.full(arr.shape[0], arr.shape[1], dtype=np.int64)
        flat = arr.reshape(-1)
    else:
        rows = [np.asarray(f).reshape(-1) for f in faces]
        sizes = np.array([r.size for r in rows], dtype=np.int64)
        flat = np.concatenate(rows) if rows else np.empty(0, dtype=np.int64)
    if flat.size and not np.issubdtype(flat.dtype, np.integer):
        if not np.all(np.equal(np.mod(flat, 1), 0)):
            raise ValueError("face indices must be integers")
    flat = flat.astype(np.int64)
    if flat.size and (flat.min() < 0 or flat.max() > 0xFFFFFFFE):
        raise ValueError("face indices must be in [0, 2^32 - 2]")
    return (np.ascontiguousarray(sizes, dtype=np.uint32),
            np.ascontiguousarray(flat, dtype=np.uint32))


def _u32ptr(arr):
    return ffi.cast("uint32_t *", ffi.from_buffer("uint32_t[]", arr))


class Mesh:
    """A half-edge polygon mesh with attribute channels (see geom/mesh.h).

    Make one with Mesh() (empty), Mesh.read(path), Mesh.from_bytes(data),
    Mesh.from_soup(points, faces), or an operation that returns a new mesh
    (clip_plane, subdivide, copy, ...).
    """

    def __init__(self):
        ptr = lib.geom_mesh_create(ffi.NULL)
        if ptr == ffi.NULL:
            raise MemoryError("geom_mesh_create")
        self._init(ptr)

    def _init(self, ptr, file=None, fmt=None, report=None, stats=None):
        self._p = ffi.gc(ptr, lib.geom_mesh_destroy)
        self._file = file
        self._format = fmt
        self._report = report
        self._stats = stats
        #: Set by subdivide(): what the subdivision did.
        self.subdiv_report = None

    @classmethod
    def _wrap(cls, ptr, **kw):
        m = cls.__new__(cls)
        m._init(ptr, **kw)
        return m

    # ------------------------------------------------------------ lifetime

    @property
    def _ptr(self):
        if self._p is None:
            raise ValueError("the mesh is closed")
        return self._p

    def close(self):
        """Free the C mesh now (idempotent)."""
        if self._p is not None:
            ffi.release(self._p)
            self._p = None

    @property
    def closed(self):
        return self._p is None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        if self._p is None:
            return "<geom.Mesh closed>"
        return "<geom.Mesh %d vertices, %d faces, %d edges>" % (
            self.n_vertices, self.n_faces, self.n_edges)

    def copy(self):
        """A deep copy (geom_mesh_clone)."""
        out = ffi.new("geom_mesh **")
        check(lib.geom_mesh_clone(self._ptr, out), context="copy")
        return Mesh._wrap(out[0], file=self._file, fmt=self._format, report=self._report,
                          stats=self._stats)

    # ------------------------------------------------------------- reading

    @staticmethod
    def _read_options(fmt, skip_invalid, keep_orientation, max_elements):
        opt = ffi.new("geom_meshio_read_options *")
        opt.format = _format_code(fmt)
        opt.build.skip_invalid_faces = 1 if skip_invalid else 0
        opt.build.keep_orientation = 1 if keep_orientation else 0
        opt.max_elements = int(max_elements)
        stats = ffi.new("geom_meshio_read_stats *")
        opt.stats = stats
        return opt, stats

    @classmethod
    def read(cls, path, format=None, skip_invalid=False, keep_orientation=False,
             max_elements=0):
        """Read an OBJ, OFF, PLY or STL file (geom_meshio_read). format:
        None (from the extension, else the content) or a format name.
        skip_invalid: skip faces with repeated or out-of-range indices
        (counted in build_report) instead of failing. Raises GeomError
        (ERR_IO, ERR_PARSE with file:line:column in .location, ...)."""
        opt, stats = cls._read_options(format, skip_invalid, keep_orientation, max_elements)
        out = ffi.new("geom_mesh **")
        rep = ffi.new("geom_mesh_build_report *")
        diag = new_diag()
        st = lib.geom_meshio_read(os.fsencode(os.fspath(path)), opt, out, rep, diag)
        check(st, diag, context="read")
        return cls._wrap(out[0], file=os.fspath(path), fmt=stats.format, report=rep,
                         stats=stats)

    @classmethod
    def from_bytes(cls, data, format=None, source_name=None, skip_invalid=False,
                   keep_orientation=False, max_elements=0):
        """Read a mesh from bytes (geom_meshio_read_memory); source_name names
        the input in errors and, without format, gives the extension."""
        opt, stats = cls._read_options(format, skip_invalid, keep_orientation, max_elements)
        buf = bytes(data)
        out = ffi.new("geom_mesh **")
        rep = ffi.new("geom_mesh_build_report *")
        diag = new_diag()
        name = ffi.NULL if source_name is None else str(source_name).encode()
        st = lib.geom_meshio_read_memory(buf, len(buf), name, opt, out, rep, diag)
        check(st, diag, context="from_bytes")
        return cls._wrap(out[0], file=source_name, fmt=stats.format, report=rep, stats=stats)

    @classmethod
    def from_soup(cls, points, faces, skip_invalid=False, keep_orientation=False):
        """Build a mesh from a polygon soup (geom_mesh_build): points (n, 3)
        and faces, an (m, k) integer array or a list of index sequences of
        any lengths >= 3. Non-manifold input is repaired (see build_report);
        output vertex i < n is input vertex i."""
        pts = np.ascontiguousarray(points, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError("points must have shape (n, 3), got %s" % (pts.shape,))
        sizes, idx = _soup_arrays(faces)
        m = cls()
        opt = ffi.new("geom_mesh_build_options *")
        opt.skip_invalid_faces = 1 if skip_invalid else 0
        opt.keep_orientation = 1 if keep_orientation else 0
        rep = ffi.new("geom_mesh_build_report *")
        diag = new_diag()
        st = lib.geom_mesh_build(m._ptr, pts.shape[0], dptr(pts), sizes.size, _u32ptr(sizes),
                                 _u32ptr(idx), opt, rep, diag)
        if st != 0:
            m.close()
            check(st, diag, context="from_soup")
        m._report = rep
        return m

    @property
    def build_report(self):
        """What building from the soup repaired (geom_mesh_build_report as a
        dict, with the first_* index lists), or None for meshes made
        otherwise (clipping, subdivision, tessellation...)."""
        if self._report is None:
            return None
        return struct_dict(self._report[0], "geom_mesh_build_report")

    @property
    def read_stats(self):
        """What the reader skipped (geom_meshio_read_stats as a dict), or
        None for meshes not read from a file or bytes."""
        if self._stats is None:
            return None
        d = struct_dict(self._stats[0], "geom_meshio_read_stats")
        d["format"] = _format_name(self._stats.format)
        d["first_skipped"] = ffi.string(self._stats.first_skipped).decode(errors="replace")
        return d

    # ------------------------------------------------------------- writing

    @staticmethod
    def _write_options(fmt, precision, encoding, omit, ply_float, gltf_keep_v):
        opt = ffi.new("geom_meshio_write_options *")
        opt.format = _format_code(fmt)
        opt.encoding = _choice(ENCODINGS, encoding, "encoding")
        bits = 0
        for name in omit:
            bits |= _choice(OMIT_BITS, name, "omit")
        opt.omit = bits
        opt.precision = int(precision)
        opt.ply_float = 1 if ply_float else 0
        opt.gltf_keep_v = 1 if gltf_keep_v else 0
        return opt

    def write(self, path, format=None, precision=0, encoding="default", omit=(),
              ply_float=False, gltf_keep_v=False):
        """Write the mesh atomically (geom_meshio_write): OBJ, OFF, PLY, STL
        or GLB, from format or the extension. precision 0 writes the
        shortest round-trip decimals; encoding "ascii", "binary_le",
        "binary_be" (PLY) or "default"; omit: names among "normal", "uv",
        "color", "tangent", "meta"."""
        opt = self._write_options(format, precision, encoding, omit, ply_float, gltf_keep_v)
        diag = new_diag()
        st = lib.geom_meshio_write(self._ptr, os.fsencode(os.fspath(path)), opt, diag)
        check(st, diag, context="write")

    def to_bytes(self, format, precision=0, encoding="default", omit=(), ply_float=False,
                 gltf_keep_v=False):
        """The file contents write() would produce, as bytes
        (geom_meshio_write_memory)."""
        opt = self._write_options(format, precision, encoding, omit, ply_float, gltf_keep_v)
        data = ffi.new("void **")
        size = ffi.new("size_t *")
        diag = new_diag()
        st = lib.geom_meshio_write_memory(self._ptr, opt, data, size, diag)
        check(st, diag, context="to_bytes")
        try:
            return bytes(ffi.buffer(data[0], size[0]))
        finally:
            lib.geom_meshio_buffer_free(data[0], size[0], ffi.NULL)

    # -------------------------------------------------------------- counts

    @property
    def n_vertices(self):
        return int(lib.geom_mesh_n_vertices(self._ptr))

    @property
    def n_faces(self):
        return int(lib.geom_mesh_n_faces(self._ptr))

    @property
    def n_edges(self):
        return int(lib.geom_mesh_n_edges(self._ptr))

    @property
    def n_live_vertices(self):
        """Vertices not marked deleted."""
        return int(lib.geom_mesh_n_live_vertices(self._ptr))

    @property
    def n_live_edges(self):
        """Edges not marked deleted."""
        return int(lib.geom_mesh_n_live_edges(self._ptr))

    @property
    def n_halfedges(self):
        return int(lib.geom_mesh_n_halfedges(self._ptr))

    # ---------------------------------------------------------- geometry

    @property
    def positions(self):
        """Vertex positions as an (n, 3) array (a copy). Assigning an (n, 3)
        array writes the positions back (n must be n_vertices)."""
        n = self.n_vertices
        return from_c_doubles(lib.geom_mesh_cpositions(self._ptr), 3 * n).reshape(n, 3)

    @positions.setter
    def positions(self, value):
        arr = np.ascontiguousarray(value, dtype=np.float64)
        n = self.n_vertices
        if arr.shape != (n, 3):
            raise ValueError("positions must have shape (%d, 3), got %s" % (n, arr.shape))
        if n:
            ffi.memmove(lib.geom_mesh_positions(self._ptr), ffi.from_buffer(arr), arr.nbytes)

    def _soup(self):
        p = self._ptr
        nidx = ffi.new("size_t *")
        check(lib.geom_mesh_to_soup(p, ffi.NULL, ffi.NULL, nidx), context="faces")
        nf = int(lib.geom_mesh_n_live_faces(p))
        sizes = np.zeros(nf, dtype=np.uint32)
        idx = np.zeros(int(nidx[0]), dtype=np.uint32)
        if nf:
            check(lib.geom_mesh_to_soup(p, _u32ptr(sizes), _u32ptr(idx), nidx), context="faces")
        return sizes.astype(np.int64), idx.astype(np.int64)

    @property
    def face_sizes(self):
        """Number of vertices of each (live) face, an int64 array."""
        return self._soup()[0]

    @property
    def face_indices(self):
        """All faces' vertex indices, concatenated (int64); face f's are at
        offsets[f] : offsets[f] + face_sizes[f] with
        offsets = concatenate(([0], cumsum(face_sizes)[:-1]))."""
        return self._soup()[1]

    @property
    def faces(self):
        """The faces: an (m, k) int64 array when every face has k vertices
        (e.g. a triangle mesh), otherwise a list of 1-D int64 arrays."""
        sizes, idx = self._soup()
        if sizes.size == 0:
            return np.zeros((0, 3), dtype=np.int64)
        if np.all(sizes == sizes[0]):
            return idx.reshape(-1, int(sizes[0]))
        return np.split(idx, np.cumsum(sizes)[:-1])

    @property
    def edges(self):
        """(n_edges, 2) vertex pairs: edge e runs from halfedge 2e's start
        to its end."""
        p = self._ptr
        ne = self.n_edges
        hv = lib.geom_mesh_he_vertex
        out = np.fromiter((hv(p, h) for h in range(2 * ne)), dtype=np.int64, count=2 * ne)
        return out.reshape(ne, 2)[:, ::-1].copy()

    def _face_halfedges(self):
        """Halfedges of every live face in face_indices order."""
        p = self._ptr
        fhe, nxt = lib.geom_mesh_face_he, lib.geom_mesh_he_next
        deleted = lib.geom_mesh_face_is_deleted
        hes = []
        for f in range(self.n_faces):
            if deleted(p, f):
                continue
            h0 = fhe(p, f)
            h = h0
            while True:
                hes.append(h)
                h = nxt(p, h)
                if h == h0:
                    break
        return np.array(hes, dtype=np.int64)

    @property
    def vertex_origin(self):
        """For each vertex, the input soup vertex it came from (None if the
        mesh was not built from a soup)."""
        ptr = lib.geom_mesh_vertex_origin(self._ptr)
        if ptr == ffi.NULL:
            return None
        return from_c_uint32(ptr, self.n_vertices).astype(np.int64)

    @property
    def face_origin(self):
        """For each face, the input soup face it came from (or None)."""
        ptr = lib.geom_mesh_face_origin(self._ptr)
        if ptr == ffi.NULL:
            return None
        return from_c_uint32(ptr, self.n_faces).astype(np.int64)

    # ------------------------------------------------------------ channels

    def channels(self):
        """Every channel as a dict {name, domain, ncomp, size}, in id order
        (channel 0 is "position")."""
        p = self._ptr
        out = []
        for c in range(lib.geom_mesh_channel_count(p)):
            out.append({
                "name": ffi.string(lib.geom_mesh_channel_name(p, c)).decode(),
                "domain": _DOMAIN_NAMES.get(lib.geom_mesh_channel_domain(p, c), "unknown"),
                "ncomp": int(lib.geom_mesh_channel_ncomp(p, c)),
                "size": int(lib.geom_mesh_channel_size(p, c)),
            })
        return out

    def _find(self, name, domain):
        dom = _choice(DOMAINS, domain, "domain")
        cid = lib.geom_mesh_channel_find(self._ptr, name.encode(), dom)
        return None if cid == INVALID_INDEX else int(cid)

    def has_channel(self, name, domain="vertex"):
        return self._find(name, domain) is not None

    def channel(self, name, domain="vertex"):
        """The values of a channel as a (size, ncomp) array (a copy). For a
        corner channel these are its value pool (see corner()). KeyError if
        there is no such channel."""
        cid = self._find(name, domain)
        if cid is None:
            raise KeyError("no %s channel %r" % (domain, name))
        p = self._ptr
        size = int(lib.geom_mesh_channel_size(p, cid))
        ncomp = int(lib.geom_mesh_channel_ncomp(p, cid))
        data = from_c_doubles(lib.geom_mesh_channel_cdata(p, cid), size * ncomp)
        return data.reshape(size, ncomp)

    def set_channel(self, name, values, domain="vertex"):
        """Create or overwrite a vertex, face or edge channel from a
        (count, ncomp) array (count = the number of such elements)."""
        if domain == "corner":
            raise ValueError("use set_corner for corner channels")
        arr = np.ascontiguousarray(values, dtype=np.float64)
        if arr.ndim == 1:
            arr = arr.reshape(-1, 1)
        count = {"vertex": self.n_vertices, "face": self.n_faces, "edge": self.n_edges}[domain]
        if arr.ndim != 2 or arr.shape[0] != count or arr.shape[1] < 1:
            raise ValueError("%s channel %r needs shape (%d, ncomp), got %s"
                             % (domain, name, count, arr.shape))
        cid = self._ensure_channel(name, domain, arr.shape[1])
        if arr.size:
            ffi.memmove(lib.geom_mesh_channel_data(self._ptr, cid), ffi.from_buffer(arr),
                        arr.nbytes)

    def _ensure_channel(self, name, domain, ncomp):
        p = self._ptr
        cid = self._find(name, domain)
        if cid is not None and int(lib.geom_mesh_channel_ncomp(p, cid)) != ncomp:
            if cid == 0:
                raise ValueError("position has 3 components")
            check(lib.geom_mesh_channel_remove(p, cid), context="set_channel")
            cid = None
        if cid is None:
            out = ffi.new("uint32_t *")
            check(lib.geom_mesh_channel_add(p, name.encode(), DOMAINS[domain], ncomp, out),
                  context="set_channel %r" % name)
            cid = int(out[0])
        return cid

    def remove_channel(self, name, domain="vertex"):
        cid = self._find(name, domain)
        if cid is None:
            raise KeyError("no %s channel %r" % (domain, name))
        check(lib.geom_mesh_channel_remove(self._ptr, cid), context="remove_channel")

    def corner(self, name):
        """A corner (face-varying) channel as (values, indices): values is
        the (pool, ncomp) value pool and indices has one entry per face
        corner, aligned with face_indices (-1 where a corner has no value).
        The value at corner j of face f is values[indices[offsets[f] + j]]:
        a seam is a vertex whose corners use different values."""
        cid = self._find(name, "corner")
        if cid is None:
            raise KeyError("no corner channel %r" % name)
        values = self.channel(name, "corner")
        per_he = from_c_uint32(lib.geom_mesh_corner_cindices(self._ptr, cid), self.n_halfedges)
        idx = per_he[self._face_halfedges()].astype(np.int64)
        idx[idx == INVALID_INDEX] = -1
        return values, idx

    def corner_values(self, name):
        """A corner channel expanded to one row per face corner, aligned with
        face_indices: (corners, ncomp), NaN where a corner has no value."""
        values, idx = self.corner(name)
        out = np.full((idx.size, values.shape[1]), np.nan)
        ok = idx >= 0
        out[ok] = values[idx[ok]]
        return out

    def set_corner(self, name, values, indices=None):
        """Create or overwrite a corner channel: values (pool, ncomp) and
        indices, one per face corner aligned with face_indices (-1 for
        none); without indices, values must have one row per face corner
        and each corner gets its own row."""
        vals = np.ascontiguousarray(values, dtype=np.float64)
        if vals.ndim == 1:
            vals = vals.reshape(-1, 1)
        hes = self._face_halfedges()
        if indices is None:
            if vals.shape[0] != hes.size:
                raise ValueError("need one value per face corner (%d), got %d"
                                 % (hes.size, vals.shape[0]))
            idx = np.arange(hes.size, dtype=np.int64)
        else:
            idx = np.asarray(indices, dtype=np.int64).reshape(-1)
            if idx.size != hes.size:
                raise ValueError("need one index per face corner (%d), got %d"
                                 % (hes.size, idx.size))
            if idx.size and (idx.max() >= vals.shape[0] or idx.min() < -1):
                raise ValueError("corner index out of range")
        cid = self._ensure_channel(name, "corner", vals.shape[1])
        p = self._ptr
        check(lib.geom_mesh_corner_pool_resize(p, cid, vals.shape[0]), context="set_corner")
        if vals.size:
            ffi.memmove(lib.geom_mesh_channel_data(p, cid), ffi.from_buffer(vals), vals.nbytes)
        nh = self.n_halfedges
        per_he = np.full(nh, INVALID_INDEX, dtype=np.uint32)
        per_he[hes] = np.where(idx < 0, INVALID_INDEX, idx).astype(np.uint32)
        ffi.memmove(lib.geom_mesh_corner_indices(p, cid), ffi.from_buffer(per_he), per_he.nbytes)

    # ------------------------------------------------------------- queries

    def bbox(self):
        """(min, max) of the vertices as two (3,) arrays, or None when the
        mesh has no vertices."""
        b = lib.geom_mesh_bbox(self._ptr)
        lo = np.array([b.min.x, b.min.y, b.min.z])
        hi = np.array([b.max.x, b.max.y, b.max.z])
        if np.any(lo > hi):
            return None
        return lo, hi

    def halfedges(self):
        """The half-edge connectivity as uint32 arrays of n_halfedges:
        {"next", "prev", "vertex" (the vertex it points to), "face"
        (0xFFFFFFFF on a boundary), "opposite" (h ^ 1), "edge" (h >> 1)}."""
        nh = self.n_halfedges
        arrs = {k: np.empty(nh, dtype=np.uint32) for k in ("next", "prev", "vertex", "face")}
        check(lib.geom_mesh_halfedge_arrays(self._ptr, *(_u32ptr(arrs[k]) for k in
                                                         ("next", "prev", "vertex", "face"))),
              context="halfedges")
        h = np.arange(nh, dtype=np.uint32)
        arrs["opposite"] = h ^ 1
        arrs["edge"] = h >> 1
        return arrs

    _RINGS = {"vertices": 2, "faces": 1, "outgoing": 0}

    def vertex_rings(self, kind="vertices"):
        """Every vertex's one-ring as (offsets, items): vertex v's ring is
        items[offsets[v]:offsets[v+1]] in circulator order (counter-clockwise
        from the boundary); kind "vertices" (neighbours), "faces" or
        "outgoing" (half-edges)."""
        k = _choice(self._RINGS, kind, "kind")
        nv = self.n_vertices
        offsets = np.empty(nv + 1, dtype=np.uintp)
        items = np.empty(max(self.n_halfedges, 1), dtype=np.uint32)
        count = ffi.new("size_t *")
        check(lib.geom_mesh_vertex_rings(self._ptr, k, ffi.cast("size_t *",
                                                                ffi.from_buffer(offsets)),
                                         _u32ptr(items), items.size, count),
              context="vertex_rings")
        return offsets.astype(np.int64), items[:int(count[0])].copy()

    def one_ring(self, v, kind="vertices"):
        """The one-ring of vertex v as an array (see vertex_rings)."""
        k = _choice(self._RINGS, kind, "kind")
        if not 0 <= int(v) < self.n_vertices:
            raise IndexError("vertex %d out of range" % v)
        c = ffi.new("geom_mesh_circ *")
        c[0] = lib.geom_mesh_circ_begin(self._ptr, k, int(v))
        x = ffi.new("uint32_t *")
        out = []
        while lib.geom_mesh_circ_next(c, x):
            out.append(int(x[0]))
        return np.array(out, dtype=np.uint32)

    def boundary_loops(self):
        """Number of boundary loops."""
        n = ffi.new("size_t *")
        check(lib.geom_mesh_boundary_loops(self._ptr, n, ffi.NULL), context="boundary_loops")
        return int(n[0])

    def boundary_loop_vertices(self):
        """The boundary loops as a list of vertex arrays, each in the order
        of its boundary half-edges (the interior on the left when the mesh
        faces are counter-clockwise), starting at its lowest half-edge."""
        nh = self.n_halfedges
        loop_of = np.empty(nh, dtype=np.uint32)
        n = ffi.new("size_t *")
        check(lib.geom_mesh_boundary_loops(self._ptr, n, _u32ptr(loop_of)),
              context="boundary_loops")
        he = self.halfedges()
        nxt, to = he["next"], he["vertex"]
        loops = []
        seen = np.zeros(int(n[0]), dtype=bool)
        for h in np.nonzero(loop_of != 0xFFFFFFFF)[0]:
            lid = int(loop_of[h])
            if seen[lid]:
                continue
            seen[lid] = True
            verts, x = [], int(h)
            while True:
                verts.append(int(to[he["prev"][x]]))
                x = int(nxt[x])
                if x == h or len(verts) > nh:
                    break
            loops.append(np.array(verts, dtype=np.uint32))
        return loops

    def components(self):
        """(count, vertex_component (n_vertices,), face_component (n_faces,))."""
        n = ffi.new("size_t *")
        vc = np.zeros(self.n_vertices, dtype=np.uint32)
        fc = np.zeros(self.n_faces, dtype=np.uint32)
        check(lib.geom_mesh_components(self._ptr, n, _u32ptr(vc), _u32ptr(fc)),
              context="components")
        return int(n[0]), vc.astype(np.int64), fc.astype(np.int64)

    def validate(self):
        """Invariant violations of the data structure as a list of
        (kind, element) pairs; empty for a valid mesh."""
        n = ffi.new("size_t *")
        check(lib.geom_mesh_validate(self._ptr, ffi.NULL, 0, n), context="validate")
        if n[0] == 0:
            return []
        defects = ffi.new("geom_mesh_defect[]", n[0])
        check(lib.geom_mesh_validate(self._ptr, defects, n[0], n), context="validate")
        return [(DEFECT_KINDS.get(d.kind, str(d.kind)), int(d.element)) for d in defects]

    def topology(self):
        """The summary geom-info --json prints, as a dict with the same keys:
        file, format (None unless read from a file), vertices, faces, edges,
        boundary_loops, components, euler, genus, manifold, closed,
        degenerate_faces, isolated_vertices, bbox ({"min": [...], "max":
        [...]} or None), attributes (channels()), repairs (the build report's
        counts), skipped ({statements, elements, properties}), tags, groups,
        polylines."""
        p = self._ptr
        t = ffi.new("geom_mesh_topology *")
        check(lib.geom_mesh_topology_summary(p, t), context="topology")
        box = self.bbox()
        rep = self._report
        st = self._stats
        return {
            "file": self._file,
            "format": None if self._format is None else _format_name(self._format),
            "vertices": int(t.vertices),
            "faces": int(t.faces),
            "edges": int(t.edges),
            "boundary_loops": int(t.boundary_loops),
            "components": int(t.components),
            "euler": int(t.euler),
            "genus": int(t.genus),
            "manifold": bool(t.manifold),
            "closed": bool(t.closed),
            "degenerate_faces": int(t.degenerate_faces),
            "isolated_vertices": int(t.isolated_vertices),
            "bbox": None if box is None else {"min": box[0].tolist(), "max": box[1].tolist()},
            "attributes": self.channels(),
            "repairs": {k: (int(getattr(rep, k)) if rep is not None else 0) for k in REPAIR_KEYS},
            "skipped": {
                "statements": int(st.skipped_statements) if st is not None else 0,
                "elements": int(st.skipped_elements) if st is not None else 0,
                "properties": int(st.skipped_properties) if st is not None else 0,
            },
            "tags": int(lib.geom_mesh_tag_count(p)),
            "groups": int(lib.geom_mesh_group_count(p)),
            "polylines": int(lib.geom_mesh_polyline_count(p)),
        }

    @property
    def polylines(self):
        """The mesh's polylines (OBJ l, feature edges) as a list of int64
        vertex index arrays."""
        return self._polylines(0)

    def _polylines(self, start):
        p = self._ptr
        n = ffi.new("size_t *")
        verts = ffi.new("uint32_t **")
        out = []
        for i in range(start, lib.geom_mesh_polyline_count(p)):
            check(lib.geom_mesh_polyline_get(p, i, n, verts), context="polylines")
            out.append(from_c_uint32(verts[0], n[0]).astype(np.int64))
        return out

    # ------------------------------------------------------------- editing

    def add_vertex(self, p):
        """Append a vertex at p (3 numbers); returns its index."""
        a = np.ascontiguousarray(p, dtype=np.float64).reshape(3)
        out = ffi.new("uint32_t *")
        check(lib.geom_mesh_add_vertex(self._ptr, dptr(a), out), context="add_vertex")
        return int(out[0])

    def add_face(self, verts):
        """Append a face over existing vertices (counter-clockwise from
        outside); returns its index. GeomError ERR_NONMANIFOLD when it would
        make the mesh non-manifold (nothing is changed)."""
        v = np.ascontiguousarray(np.asarray(verts).reshape(-1), dtype=np.uint32)
        out = ffi.new("uint32_t *")
        check(lib.geom_mesh_add_face(self._ptr, v.size, _u32ptr(v), out), context="add_face")
        return int(out[0])

    def add_polyline(self, verts):
        """Append a polyline (OBJ l) over existing vertices."""
        v = np.ascontiguousarray(np.asarray(verts).reshape(-1), dtype=np.uint32)
        check(lib.geom_mesh_polyline_add(self._ptr, v.size, _u32ptr(v)), context="add_polyline")

    def delete_face(self, f):
        """Mark face f deleted (its edges and vertices left unused are
        deleted too); compact() removes them."""
        check(lib.geom_mesh_delete_face(self._ptr, int(f)), context="delete_face")

    def delete_vertex(self, v):
        """Delete vertex v and every face around it (marks; see compact)."""
        check(lib.geom_mesh_delete_vertex(self._ptr, int(v)), context="delete_vertex")

    def is_deleted(self, kind, i):
        """Whether vertex/face/edge i (kind "vertex", "face", "edge") is
        marked deleted."""
        fn = {"vertex": lib.geom_mesh_vertex_is_deleted, "face": lib.geom_mesh_face_is_deleted,
              "edge": lib.geom_mesh_edge_is_deleted}[kind]
        return bool(fn(self._ptr, int(i)))

    def compact(self):
        """Remove what is marked deleted; returns (vertex_map, face_map):
        the new index of every old vertex and face (-1 when deleted)."""
        nv, nf = self.n_vertices, self.n_faces
        vm = np.empty(max(nv, 1), dtype=np.uint32)
        fm = np.empty(max(nf, 1), dtype=np.uint32)
        check(lib.geom_mesh_compact(self._ptr, _u32ptr(vm), _u32ptr(fm)), context="compact")
        conv = lambda a, n: np.where(a[:n] == 0xFFFFFFFF, -1, a[:n].astype(np.int64))  # noqa: E731
        return conv(vm, nv), conv(fm, nf)

    def clear(self):
        """Remove every element, channel (but "position"), tag and polyline."""
        lib.geom_mesh_clear(self._ptr)

    def find_halfedge(self, a, b):
        """The halfedge from vertex a to vertex b, or None."""
        h = lib.geom_mesh_find_halfedge(self._ptr, int(a), int(b))
        return None if h == 0xFFFFFFFF else int(h)

    def find_edge(self, a, b):
        """The edge between vertices a and b, or None."""
        e = lib.geom_mesh_find_edge(self._ptr, int(a), int(b))
        return None if e == 0xFFFFFFFF else int(e)

    def vertex_valences(self):
        """Edges at every vertex (n_vertices,) int64."""
        p = self._ptr
        return np.array([lib.geom_mesh_vertex_valence(p, v) for v in range(self.n_vertices)],
                        dtype=np.int64)

    def degenerate_faces(self):
        """Indices of the degenerate faces: two coincident vertices, or an
        area at most 1e-14 times the square of the longest edge."""
        p = self._ptr
        return np.array([f for f in range(self.n_faces) if lib.geom_mesh_face_is_degenerate(p, f)],
                        dtype=np.int64)

    @property
    def mtllibs(self):
        """The material libraries (OBJ mtllib) the mesh names."""
        p = self._ptr
        return [ffi.string(lib.geom_mesh_mtllib_get(p, i)).decode()
                for i in range(lib.geom_mesh_mtllib_count(p))]

    def add_mtllib(self, name):
        check(lib.geom_mesh_mtllib_add(self._ptr, str(name).encode()), context="add_mtllib")

    @property
    def tags(self):
        """The subdivision tags (OBJ t lines) as a list of (name, ints,
        floats, strings)."""
        p = self._ptr
        t = ffi.new("geom_mesh_tag *")
        out = []
        for i in range(lib.geom_mesh_tag_count(p)):
            check(lib.geom_mesh_tag_get(p, i, t), context="tags")
            out.append((ffi.string(t.name).decode(), [int(t.ints[k]) for k in range(t.nint)],
                        [float(t.floats[k]) for k in range(t.nfloat)],
                        [ffi.string(t.strings[k]).decode() for k in range(t.nstring)]))
        return out

    def add_tag(self, name, ints=(), floats=(), strings=()):
        """Append a tag, e.g. add_tag("crease", [0, 1], [2.0])."""
        ia = ffi.new("int64_t[]", [int(x) for x in ints] or [0])
        fa = ffi.new("double[]", [float(x) for x in floats] or [0.0])
        keep = [ffi.new("char[]", str(x).encode()) for x in strings]
        sa = ffi.new("char *[]", keep or [ffi.NULL])
        nm = ffi.new("char[]", str(name).encode())
        t = ffi.new("geom_mesh_tag *")
        t.name, t.nint, t.nfloat, t.nstring = nm, len(ints), len(floats), len(strings)
        t.ints, t.floats, t.strings = ia, fa, sa
        check(lib.geom_mesh_tag_add(self._ptr, t), context="add_tag")

    @property
    def groups(self):
        """The face groups (OBJ g/o/usemtl/s) as dicts of group, object,
        material, smoothing (None when unset)."""
        p = self._ptr
        g = ffi.new("geom_mesh_group *")
        out = []
        for i in range(lib.geom_mesh_group_count(p)):
            check(lib.geom_mesh_group_get(p, i, g), context="groups")
            out.append({k: (None if getattr(g, k) == ffi.NULL else ffi.string(getattr(g, k)).decode())
                        for k in ("group", "object", "material", "smoothing")})
        return out

    def face_groups(self):
        """The group id of every face (n_faces,) int64, -1 for none."""
        p = self._ptr
        ids = lib.geom_mesh_face_cgroups(p)
        if ids == ffi.NULL:
            return np.full(self.n_faces, -1, dtype=np.int64)
        a = from_c_uint32(ids, self.n_faces).astype(np.int64)
        a[a == 0xFFFFFFFF] = -1
        return a

    def set_face_groups(self, group, faces):
        """Add a group (dict with any of group, object, material, smoothing)
        and put the faces (indices) in it; returns its id."""
        g = ffi.new("geom_mesh_group *")
        keep = []
        for k in ("group", "object", "material", "smoothing"):
            if group.get(k) is not None:
                keep.append(ffi.new("char[]", str(group[k]).encode()))
                setattr(g, k, keep[-1])
        gid = ffi.new("uint32_t *")
        check(lib.geom_mesh_group_add(self._ptr, g, gid), context="set_face_groups")
        ids = lib.geom_mesh_face_groups(self._ptr)
        if ids == ffi.NULL:
            raise MemoryError("geom_mesh_face_groups")
        for f in np.asarray(faces).reshape(-1):
            if not 0 <= int(f) < self.n_faces:
                raise IndexError("face %d out of range" % int(f))
            ids[int(f)] = gid[0]
        return int(gid[0])

    # ---------------------------------------------------------- operations

    def triangulate(self):
        """Triangulate every polygon with more than three vertices in place
        (geom_polygon_triangulate: exact predicates), keeping corner channels; returns
        the number of faces added."""
        n = ffi.new("size_t *")
        check(lib.geom_mesh_triangulate(self._ptr, n), context="triangulate")
        return int(n[0])

    def vertex_normals(self, weight="angle"):
        """Unit vertex normals (n, 3) (geom_mesh_vertex_normals) with the
        weight "angle" (default), "uniform", "area" or "max"; vertices
        without a usable face get (0, 0, 0)."""
        n = self.n_vertices
        out = np.zeros((n, 3), dtype=np.float64)
        check(lib.geom_mesh_vertex_normals(self._ptr, _choice(NORMAL_WEIGHTS, weight, "weight"),
                                           dptr(out), ffi.NULL), context="vertex_normals")
        return out

    def face_normals(self):
        """Unit face normals (n_faces, 3) by Newell's method; (0, 0, 0) for
        degenerate faces."""
        p = self._ptr
        nf = self.n_faces
        out = np.zeros((nf, 3), dtype=np.float64)
        po = ffi.from_buffer("double[]", out)
        fn = lib.geom_mesh_face_normal
        for f in range(nf):
            st = fn(p, f, po + 3 * f)
            if st not in (0, lib.GEOM_ERR_DEGENERATE):
                check(st, context="face_normals (face %d)" % f)
        return out

    def corner_normals(self, crease_degrees=0.0, weight="angle", split_at=None):
        """Compute the corner channel "normal" (geom_mesh_corner_normals):
        smooth within fans of faces bounded by edges sharper than
        crease_degrees (0: no creases), boundaries and, with split_at (the
        name of a corner channel, e.g. "uv"), that channel's seams. Returns
        corner("normal")."""
        opt = ffi.new("geom_corner_normal_options *")
        opt.weight = _choice(NORMAL_WEIGHTS, weight, "weight")
        opt.crease_degrees = float(crease_degrees)
        if split_at is not None:
            cid = self._find(split_at, "corner")
            if cid is None:
                raise KeyError("no corner channel %r" % split_at)
            opt.split_at_channel_plus_one = cid + 1
        check(lib.geom_mesh_corner_normals(self._ptr, opt, ffi.NULL), context="corner_normals")
        return self.corner("normal")

    def tangents(self):
        """Compute the corner channel "tangent" (4 comps: xyz and the
        bitangent sign) from the "uv" and "normal" corner channels
        (MikkTSpace-compatible, geom_mesh_tangents). Returns
        corner("tangent")."""
        check(lib.geom_mesh_tangents(self._ptr, ffi.NULL), context="tangents")
        return self.corner("tangent")

    def uv_data(self, channel="uv"):
        """UV charts and seams of a corner channel (geom_mesh_uv_data): a
        dict with the report's fields plus chart_bounds (charts, 4: umin
        vmin umax vmax), face_chart (n_faces,) and seam_edge (n_edges,
        bool)."""
        cid = self._find(channel, "corner")
        if cid is None:
            raise KeyError("no corner channel %r" % channel)
        p = self._ptr
        rep = ffi.new("geom_uv_report *")
        check(lib.geom_mesh_uv_data(p, cid, rep, ffi.NULL, ffi.NULL, ffi.NULL), context="uv_data")
        bounds = np.zeros((rep.charts, 4), dtype=np.float64)
        chart = np.zeros(self.n_faces, dtype=np.uint32)
        seam = np.zeros(self.n_edges, dtype=np.uint8)
        check(lib.geom_mesh_uv_data(p, cid, rep, dptr(bounds) if bounds.size else ffi.NULL,
                                    _u32ptr(chart), ffi.cast("uint8_t *", ffi.from_buffer(seam))),
              context="uv_data")
        d = struct_dict(rep[0], "geom_uv_report")
        chart64 = chart.astype(np.int64)
        chart64[chart == INVALID_INDEX] = -1
        d.update(chart_bounds=bounds, face_chart=chart64, seam_edge=seam.astype(bool))
        return d

    def features(self, kinds=("boundary", "crease"), crease_degrees=30.0, eye=None):
        """Feature edges (geom_mesh_features): kinds among "boundary",
        "crease", "silhouette" (which needs eye, a (3,) point). Returns
        (edge_kind, polylines): edge_kind (n_edges,) uint8 bit flags
        (1 boundary, 2 crease, 4 silhouette) and the polylines made, which are
        also appended to the mesh's polylines."""
        opt = ffi.new("geom_feature_options *")
        bits = 0
        for k in ([kinds] if isinstance(kinds, str) else kinds):
            bits |= _choice(FEATURE_KINDS, k, "kind")
        opt.kinds = bits
        opt.crease_degrees = float(crease_degrees)
        if eye is not None:
            e = np.asarray(eye, dtype=np.float64).reshape(3)
            opt.eye = list(e)
        elif bits & FEATURE_KINDS["silhouette"]:
            raise ValueError("silhouette edges need an eye point")
        kind = np.zeros(self.n_edges, dtype=np.uint8)
        start = int(lib.geom_mesh_polyline_count(self._ptr))
        check(lib.geom_mesh_features(self._ptr, opt, ffi.cast("uint8_t *", ffi.from_buffer(kind)),
                                     ffi.NULL), context="features")
        return kind, self._polylines(start)

    def clip_plane(self, plane, cap=False):
        """A new mesh: the part where a*x + b*y + c*z + d >= 0 for plane =
        (a, b, c, d), faces cut and channels interpolated; cap=True closes
        the cut of a closed mesh (geom_mesh_clip_plane)."""
        pl = np.ascontiguousarray(plane, dtype=np.float64).reshape(4)
        opt = ffi.new("geom_clip_options *")
        opt.cap = 1 if cap else 0
        out = ffi.new("geom_mesh **")
        check(lib.geom_mesh_clip_plane(self._ptr, dptr(pl), opt, out), context="clip_plane")
        return Mesh._wrap(out[0])

    def clip_frustum(self, view_proj, cap=False):
        """A new mesh clipped to the view frustum of the (4, 4)
        view-projection matrix (OpenGL clip convention)."""
        opt = ffi.new("geom_clip_options *")
        opt.cap = 1 if cap else 0
        out = ffi.new("geom_mesh **")
        check(lib.geom_mesh_clip_frustum(self._ptr, to_mat4(view_proj), opt, out),
              context="clip_frustum")
        return Mesh._wrap(out[0])

    def subdivide(self, levels=1, scheme="catmull-clark", limit=False, normals=False,
                  boundary=None, fvar_boundary=None, crease_method=None, triangles=None,
                  ignore_tags=False, creases=None, corners=None, holes=None):
        """A new mesh subdivided `levels` times (geom_subdiv_mesh): scheme
        "catmull-clark", "loop", "bilinear", "butterfly" or "sqrt3";
        limit=True moves the vertices to the limit surface, normals=True adds
        the vertex channel "normal" of limit normals. boundary: "none",
        "edge_only", "edge_and_corner"; fvar_boundary: "none",
        "corners_only", "corners_plus1", "corners_plus2", "boundaries",
        "all"; crease_method: "uniform", "chaikin"; triangles: "catmark",
        "smooth" (None: the mesh's tags, else OpenSubdiv's defaults).
        creases: (pairs (k, 2), sharpness (k,)); corners: (vertices (k,),
        sharpness (k,)); holes: face indices. The result's subdiv_report
        holds what was done and the distance of the vertices to the limit
        surface."""
        opt, keep = subdiv_options(scheme, boundary, fvar_boundary, crease_method, triangles,
                                   ignore_tags, creases, corners, holes)
        flags = (1 if limit else 0) | (2 if normals else 0)
        out = ffi.new("geom_mesh **")
        rep = ffi.new("geom_subdiv_report *")
        diag = new_diag()
        check(lib.geom_subdiv_mesh(self._ptr, opt, int(levels), flags, out, rep, diag), diag,
              context="subdivide")
        m = Mesh._wrap(out[0])
        m.subdiv_report = struct_dict(rep[0], "geom_subdiv_report")
        return m


def sniff_format(data):
    """The mesh format geom_meshio_format_sniff guesses from file content
    (bytes): "ply", "glb", "stl", "off", else "obj"."""
    b = bytes(data)
    return _format_name(lib.geom_meshio_format_sniff(ffi.from_buffer(b) if b else ffi.NULL, len(b)))


def subdiv_options(scheme="catmull-clark", boundary=None, fvar_boundary=None, crease_method=None,
                   triangles=None, ignore_tags=False, creases=None, corners=None, holes=None):
    """(geom_subdiv_options *, arrays to keep alive while it is used) from
    the arguments of Mesh.subdivide (also used by geom.subdiv.Refiner)."""
    if not has_module("subdiv"):
        raise NotImplementedError("libgeom was built without the subdiv module")
    opt = ffi.new("geom_subdiv_options *")
    sch = ffi.new("geom_subdiv_scheme *")
    check(lib.geom_subdiv_scheme_from_name(str(scheme).encode(), sch),
          context="subdivide: unknown scheme %r" % (scheme,))
    opt.scheme = sch[0]
    opt.boundary = _choice(_SUBDIV_BOUNDARY, boundary, "boundary")
    opt.fvar_boundary = _choice(_SUBDIV_FVAR, fvar_boundary, "fvar_boundary")
    opt.crease_method = _choice(_SUBDIV_CREASE, crease_method, "crease_method")
    opt.triangles = _choice(_SUBDIV_TRIANGLES, triangles, "triangles")
    opt.ignore_tags = 1 if ignore_tags else 0
    keep = []
    if creases is not None:
        pairs = np.ascontiguousarray(np.asarray(creases[0]).reshape(-1, 2), dtype=np.uint32)
        sharp = np.ascontiguousarray(creases[1], dtype=np.float64).reshape(-1)
        if sharp.size != pairs.shape[0]:
            raise ValueError("creases: one sharpness per vertex pair")
        keep += [pairs, sharp]
        opt.n_creases = pairs.shape[0]
        opt.crease_verts = _u32ptr(pairs)
        opt.crease_sharpness = dptr(sharp)
    if corners is not None:
        verts = np.ascontiguousarray(np.asarray(corners[0]).reshape(-1), dtype=np.uint32)
        sharp = np.ascontiguousarray(corners[1], dtype=np.float64).reshape(-1)
        if sharp.size != verts.size:
            raise ValueError("corners: one sharpness per vertex")
        keep += [verts, sharp]
        opt.n_corners = verts.size
        opt.corner_verts = _u32ptr(verts)
        opt.corner_sharpness = dptr(sharp)
    if holes is not None:
        hf = np.ascontiguousarray(np.asarray(holes).reshape(-1), dtype=np.uint32)
        keep.append(hf)
        opt.n_holes = hf.size
        opt.hole_faces = _u32ptr(hf)
    return opt, keep


def polygon_triangulate(points):
    """Triangulation of one simple polygon ((n, 3) points, or
    (n, 2) taken at z = 0): (n - 2, 3) indices into the polygon
    (geom_polygon_triangulate: a monotone-decomposition sweep above 64
    vertices, O(n log n); ear clipping up to 64 and for non-simple input).
    Raises GeomError ERR_DEGENERATE for a
    zero-area polygon."""
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim == 2 and pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(pts.shape[0])])
    pts = np.ascontiguousarray(pts)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError("points must have shape (n, 2) or (n, 3)")
    n = pts.shape[0]
    tris = np.zeros((max(n - 2, 0), 3), dtype=np.uint32)
    check(lib.geom_polygon_triangulate(n, dptr(pts), _u32ptr(tris) if tris.size else ffi.NULL),
          context="polygon_triangulate")
    return tris.astype(np.int64)


__all__ = ["Mesh", "polygon_triangulate", "DOMAINS", "REPAIR_KEYS"]
