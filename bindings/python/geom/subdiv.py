"""Subdivision refiner (geom/subdiv.h): topology refined once, then applied
to any number of data arrays (OpenSubdiv's Far::TopologyRefiner and
PrimvarRefiner), for callers that refine positions, colours or UVs
themselves or time the levels.

    r = Refiner(mesh)                        # or Refiner.from_soup(n, faces)
    r.refine(2)
    p1 = r.interpolate(1, mesh.positions)    # (n1, k) from (n0, k)
    p2 = r.interpolate(2, p1)
    pos, t1, t2 = r.limit(p2, tangents=True)
    m = r.build_mesh(2, pos, r.limit_normals(p2))

Mesh.subdivide does all of this in one call; this module is for more
control. Arrays are numpy (float64 data, uint32 indices); each method
copies what it returns, so results stay valid after further refinement.
"""
import numpy as np

from ._ffi import ffi, lib
from .core import GeomError, check, dptr, new_diag
from .mesh import Mesh, _soup_arrays, _u32ptr, subdiv_options

_ORIGIN = {0: "face", 1: "edge", 2: "vertex"}
_ORIGIN_CODE = {v: k for k, v in _ORIGIN.items()}
_RULE = {1: "smooth", 2: "dart", 4: "crease", 8: "corner"}
_INVALID = 0xFFFFFFFF


def _data(values, rows, what):
    """values as a C-contiguous float64 (rows, k) array (1-D: k = 1)."""
    a = np.ascontiguousarray(values, dtype=np.float64)
    if a.ndim == 1:
        a = a.reshape(-1, 1)
    if a.ndim != 2 or a.shape[0] != rows or a.shape[1] < 1:
        raise ValueError("%s: expected %d rows of data, got shape %s" % (what, rows, a.shape))
    return a


class Refiner:
    """A geom_subdiv_refiner over a Mesh (its live faces, tags and CORNER
    channels as face-varying channels) or a polygon soup. The keyword
    arguments are those of Mesh.subdivide (scheme, boundary, fvar_boundary,
    crease_method, triangles, ignore_tags, creases, corners, holes)."""

    def __init__(self, mesh, **options):
        opt, keep = subdiv_options(**options)
        out = ffi.new("geom_subdiv_refiner **")
        diag = new_diag()
        check(lib.geom_subdiv_refiner_create(mesh._ptr, opt, out, diag), diag, "Refiner")
        self._r = ffi.gc(out[0], lib.geom_subdiv_refiner_destroy)
        self._mesh = mesh
        del keep

    @classmethod
    def from_soup(cls, n_vertices, faces, **options):
        """A refiner over n_vertices vertices and faces (an (m, k) array or
        a list of index lists, each of size >= 3); sharp features come from
        creases/corners/holes only."""
        sizes, idx = _soup_arrays(faces)
        opt, keep = subdiv_options(**options)
        out = ffi.new("geom_subdiv_refiner **")
        diag = new_diag()
        check(lib.geom_subdiv_refiner_create_soup(int(n_vertices), sizes.size, _u32ptr(sizes),
                                                  _u32ptr(idx), opt, out, diag), diag,
              "Refiner.from_soup")
        self = cls.__new__(cls)
        self._r = ffi.gc(out[0], lib.geom_subdiv_refiner_destroy)
        self._mesh = None
        del keep
        return self

    # ------------------------------------------------------------ topology
    def refine(self, levels=1):
        """Refine `levels` more times (topology only). GeomError ERR_LIMIT
        beyond level 12 or 2^28 elements (nothing added)."""
        check(lib.geom_subdiv_refiner_refine(self._r, int(levels)), context="refine")

    @property
    def max_level(self):
        return int(lib.geom_subdiv_refiner_max_level(self._r))

    @property
    def scheme(self):
        return ffi.string(lib.geom_subdiv_scheme_name(lib.geom_subdiv_refiner_scheme(self._r))).decode()

    def options(self):
        """The effective options (geom_subdiv_refiner_options: after the
        mesh's tags were read) as a dict with the names Mesh.subdivide
        takes: scheme, boundary, fvar_boundary, crease_method, triangles
        (None where the option is 0, the scheme's default), ignore_tags,
        partial_last_level. The crease, corner and hole arrays are not
        kept by the refiner (its sharpness is per level: level_info)."""
        from .mesh import _SUBDIV_BOUNDARY, _SUBDIV_CREASE, _SUBDIV_FVAR, _SUBDIV_TRIANGLES
        o = lib.geom_subdiv_refiner_options(self._r)

        def name(table, value):
            inv = {v: k for k, v in table.items()}
            return inv.get(int(value), int(value))
        return {"scheme": ffi.string(lib.geom_subdiv_scheme_name(o.scheme)).decode(),
                "boundary": name(_SUBDIV_BOUNDARY, o.boundary),
                "fvar_boundary": name(_SUBDIV_FVAR, o.fvar_boundary),
                "crease_method": name(_SUBDIV_CREASE, o.crease_method),
                "triangles": name(_SUBDIV_TRIANGLES, o.triangles),
                "ignore_tags": bool(o.ignore_tags),
                "partial_last_level": int(o.partial_last_level)}

    def _level(self, level, lo=0):
        level = int(level)
        if not lo <= level <= self.max_level:
            raise ValueError("level %d out of %d..%d" % (level, lo, self.max_level))
        return level

    def level_info(self, level):
        """Sizes of a level: dict of vertices, edges, faces, face_vertices,
        max_valence, sharp_edges, hole_faces."""
        info = ffi.new("geom_subdiv_level_info *")
        check(lib.geom_subdiv_refiner_level_info(self._r, self._level(level), info),
              context="level_info")
        return {k: int(getattr(info, k)) for k in ("vertices", "edges", "faces", "face_vertices",
                                                   "max_valence", "sharp_edges", "hole_faces")}

    def faces(self, level):
        """(face_sizes (faces,), indices (face_vertices,), is_hole (faces,)
        bool) of a level, hole faces included."""
        level = self._level(level)
        info = self.level_info(level)
        sizes = np.empty(info["faces"], dtype=np.uint32)
        idx = np.empty(info["face_vertices"], dtype=np.uint32)
        hole = np.empty(info["faces"], dtype=np.uint8)
        check(lib.geom_subdiv_refiner_faces(self._r, level, _u32ptr(sizes), _u32ptr(idx),
                                            ffi.from_buffer("uint8_t[]", hole)), context="faces")
        return sizes, idx, hole.astype(bool)

    def face_indices(self, level):
        """The face-vertex indices of a level (face_vertices,) uint32, read
        through geom_subdiv_refiner_face_indices (the refiner's own array,
        copied)."""
        level = self._level(level)
        n = self.level_info(level)["face_vertices"]
        p = lib.geom_subdiv_refiner_face_indices(self._r, level)
        if p == ffi.NULL:
            raise GeomError(lib.GEOM_ERR_INVALID_ARG, context="face_indices")
        return np.frombuffer(ffi.buffer(p, 4 * n), dtype=np.uint32).copy()

    def edges(self, level):
        """((edges, 2) uint32 vertex pairs, (edges,) float32 sharpness; 10 =
        infinitely sharp) of a level."""
        level = self._level(level)
        n = self.level_info(level)["edges"]
        v = np.empty((n, 2), dtype=np.uint32)
        s = np.empty(n, dtype=np.float32)
        check(lib.geom_subdiv_refiner_edges(self._r, level, _u32ptr(v),
                                            ffi.from_buffer("float[]", s)), context="edges")
        return v, s

    def vertex_rules(self, level):
        """((vertices,) float32 sharpness, list of rule names "smooth",
        "dart", "crease", "corner") of a level."""
        level = self._level(level)
        n = self.level_info(level)["vertices"]
        s = np.empty(n, dtype=np.float32)
        r = np.empty(n, dtype=np.uint8)
        check(lib.geom_subdiv_refiner_vertex_rules(self._r, level, ffi.from_buffer("float[]", s),
                                                   ffi.from_buffer("uint8_t[]", r)),
              context="vertex_rules")
        return s, [_RULE.get(int(x), "?") for x in r]

    def child_vertex(self, level, kind, index):
        """The vertex of level+1 made from face/edge/vertex `index` of
        `level` (kind "face", "edge" or "vertex"); None when there is none."""
        if kind not in _ORIGIN_CODE:
            raise ValueError("kind must be 'face', 'edge' or 'vertex', got %r" % (kind,))
        v = lib.geom_subdiv_refiner_child_vertex(self._r, int(level), _ORIGIN_CODE[kind], int(index))
        return None if v == _INVALID else int(v)

    def vertex_parent(self, level, v):
        """(kind, index) that vertex v of level (>= 1) comes from."""
        kind = ffi.new("geom_subdiv_origin *")
        parent = ffi.new("uint32_t *")
        check(lib.geom_subdiv_refiner_vertex_parent(self._r, int(level), int(v), kind, parent),
              context="vertex_parent")
        return _ORIGIN[int(kind[0])], int(parent[0])

    def face_parent(self, level, f):
        """The face of level-1 that face f of level (>= 1) comes from, or
        None out of range."""
        p = lib.geom_subdiv_refiner_face_parent(self._r, int(level), int(f))
        return None if p == _INVALID else int(p)

    # ----------------------------------------------------------------- data
    def _step(self, fn, level, values, rows_of, what):
        level = self._level(level, 1)
        src = _data(values, rows_of(level - 1), what)
        dst = np.empty((rows_of(level), src.shape[1]), dtype=np.float64)
        check(fn(self._r, level, src.shape[1], dptr(src), dptr(dst)), context=what)
        return dst

    def interpolate(self, level, values):
        """Vertex data of level-1 ((n, k) or (n,)) to level `level` with the
        scheme's vertex rules."""
        return self._step(lib.geom_subdiv_interpolate, level, values,
                          lambda l: self.level_info(l)["vertices"], "interpolate")

    def interpolate_varying(self, level, values):
        """As interpolate, with linear (varying) averages."""
        return self._step(lib.geom_subdiv_interpolate_varying, level, values,
                          lambda l: self.level_info(l)["vertices"], "interpolate_varying")

    def interpolate_face(self, level, values):
        """Face data of level-1 to level (each child face its parent's)."""
        return self._step(lib.geom_subdiv_interpolate_face, level, values,
                          lambda l: self.level_info(l)["faces"], "interpolate_face")

    def limit(self, values, tangents=False):
        """Limit positions of the deepest level's vertices from its data
        (n, k); with tangents=True (pos, tan1, tan2), tan1 x tan2 the
        outward normal of counter-clockwise faces."""
        n = self.level_info(self.max_level)["vertices"]
        src = _data(values, n, "limit")
        pos = np.empty_like(src)
        t1 = np.empty_like(src) if tangents else None
        t2 = np.empty_like(src) if tangents else None
        check(lib.geom_subdiv_limit(self._r, src.shape[1], dptr(src), dptr(pos),
                                    dptr(t1) if tangents else ffi.NULL,
                                    dptr(t2) if tangents else ffi.NULL), context="limit")
        return (pos, t1, t2) if tangents else pos

    def limit_normals(self, positions):
        """Unit limit normals (n, 3) of the deepest level from its positions;
        degenerate vertices get (0, 0, 0)."""
        n = self.level_info(self.max_level)["vertices"]
        src = _data(positions, n, "limit_normals")
        if src.shape[1] != 3:
            raise ValueError("limit_normals: positions must be (n, 3)")
        out = np.empty_like(src)
        check(lib.geom_subdiv_limit_normals(self._r, dptr(src), dptr(out), ffi.NULL),
              context="limit_normals")
        return out

    # ------------------------------------------------------ face-varying data
    @property
    def fvar_count(self):
        return int(lib.geom_subdiv_refiner_fvar_count(self._r))

    def fvar_mesh_channel(self, channel):
        """The mesh CORNER channel id face-varying channel `channel` was made
        from, or None (added with add_fvar, or out of range)."""
        c = lib.geom_subdiv_refiner_fvar_mesh_channel(self._r, int(channel))
        return None if c == _INVALID else int(c)

    def add_fvar(self, n_values, face_values):
        """Add a face-varying channel (before refine): n_values values and
        the value index of each level-0 face-vertex (in face order).
        Returns the channel index."""
        fv = np.ascontiguousarray(np.asarray(face_values).reshape(-1), dtype=np.uint32)
        if fv.size != self.level_info(0)["face_vertices"]:
            raise ValueError("add_fvar: one value index per level-0 face-vertex (%d), got %d"
                             % (self.level_info(0)["face_vertices"], fv.size))
        ch = ffi.new("uint32_t *")
        check(lib.geom_subdiv_refiner_add_fvar(self._r, int(n_values), _u32ptr(fv), ch),
              context="add_fvar")
        return int(ch[0])

    def fvar_size(self, channel, level):
        return int(lib.geom_subdiv_fvar_size(self._r, int(channel), int(level)))

    def fvar_face_values(self, channel, level):
        """Value index of every face-vertex of a level for the channel."""
        level = self._level(level)
        out = np.empty(self.level_info(level)["face_vertices"], dtype=np.uint32)
        check(lib.geom_subdiv_fvar_face_values(self._r, int(channel), level, _u32ptr(out)),
              context="fvar_face_values")
        return out

    def interpolate_fvar(self, channel, level, values):
        """Face-varying values of level-1 to level (fvar_boundary rules)."""
        level = self._level(level, 1)
        src = _data(values, self.fvar_size(channel, level - 1), "interpolate_fvar")
        dst = np.empty((self.fvar_size(channel, level), src.shape[1]), dtype=np.float64)
        check(lib.geom_subdiv_interpolate_fvar(self._r, int(channel), level, src.shape[1],
                                               dptr(src), dptr(dst)), context="interpolate_fvar")
        return dst

    def limit_fvar(self, channel, values):
        """Limit of face-varying values at the deepest level."""
        src = _data(values, self.fvar_size(channel, self.max_level), "limit_fvar")
        dst = np.empty_like(src)
        check(lib.geom_subdiv_limit_fvar(self._r, int(channel), src.shape[1], dptr(src),
                                         dptr(dst)), context="limit_fvar")
        return dst

    # --------------------------------------------------------------- meshes
    def _positions(self, level, positions, normals):
        n = self.level_info(level)["vertices"]
        p = _data(positions, n, "positions")
        nn = None if normals is None else _data(normals, n, "normals")
        if p.shape[1] != 3 or (nn is not None and nn.shape[1] != 3):
            raise ValueError("positions and normals must be (n, 3)")
        return p, nn

    def build_mesh(self, level, positions, normals=None, like=None):
        """The Mesh of a level from positions (and normals, a VERTEX
        "normal" channel) refined by the caller; like (default: the mesh
        the refiner was made from) carries its channels, groups and tags as
        Mesh.subdivide does (False: nothing). Hole faces are left out."""
        level = self._level(level)
        p, nn = self._positions(level, positions, normals)
        like = self._mesh if like is None else (None if like is False else like)
        out = ffi.new("geom_mesh **")
        holes = ffi.new("size_t *")
        diag = new_diag()
        check(lib.geom_subdiv_build_mesh(self._r, level, dptr(p), ffi.NULL if nn is None else dptr(nn),
                                         ffi.NULL if like is None else like._ptr, out, holes, diag),
              diag, "build_mesh")
        m = Mesh._wrap(out[0])
        m.hole_faces = int(holes[0])
        return m

    def level_is_plain(self, level, positions, normals=False, like=None):
        """Whether build_mesh(level, positions, normals, like) would be
        plainly the level (its vertices in order, its faces in faces()
        order, nothing repaired or added), so that the level can be written
        straight from faces() and positions. like as in build_mesh."""
        level = int(level)
        if not 1 <= level <= self.max_level:
            return False
        p, _ = self._positions(level, positions, None)
        like = self._mesh if like is None else (None if like is False else like)
        return bool(lib.geom_subdiv_level_is_plain(self._r, level, dptr(p), 1 if normals else 0,
                                                   ffi.NULL if like is None else like._ptr))
