"""Spatial indices and their batch queries (geom/spatial.h).

Every query takes an (n, dim) array of query points (or one point) and calls
the C batch function once (parallel over the queries with OpenMP; the
answers do not depend on the thread count), never a Python loop.

  KdTree(points)            2D or 3D points: knn, radius, box
  Octree(points)            quadtree (2D) / octree (3D) over points: knn,
                            radius, box, frustum; Octree.triangles(...) and
                            Octree.segments(...) over elements: box, frustum
  MeshDistance(pos, tris)   closest point, winding number, signed distance
  Bvh(pos, tris)            the flat BVH (nodes and primitive order), refit
                            after moving vertices; Bvh.from_boxes(lo, hi)
                            over caller boxes; overlap(lo, hi) box queries

Answers follow the C contracts: neighbours sorted by distance then index, a
point at exactly the radius is inside, boxes include their boundary, a
winding number of exactly 1/2 counts as inside.
"""

import numpy as np

from ._ffi import ffi, lib
from .core import as_points, check, dptr, error_report

_INVALID = 0xFFFFFFFF


def _queries(q, dim):
    arr, single = as_points(q, dim, "queries")
    return arr, single


def _diag():
    return ffi.new("geom_diag *")


def _u32(arr):
    return ffi.cast("uint32_t *", ffi.from_buffer("uint32_t[]", arr))


def _rows(nb, with_dist):
    """geom_neighbors -> (offsets, index, distance) numpy arrays, then freed."""
    try:
        nq = int(nb.query_count)
        offsets = np.frombuffer(ffi.buffer(nb.offsets, 8 * (nq + 1)), dtype=np.uint64).astype(np.int64)
        total = int(offsets[-1])
        index = (np.frombuffer(ffi.buffer(nb.index, 4 * total), dtype=np.uint32).astype(np.int64)
                 if total else np.empty(0, dtype=np.int64))
        dist = None
        if with_dist:
            dist = (np.frombuffer(ffi.buffer(nb.distance, 8 * total), dtype=np.float64).copy()
                    if total else np.empty(0, dtype=np.float64))
    finally:
        lib.geom_neighbors_free(nb)
    return offsets, index, dist


def _split(offsets, arr):
    return [arr[offsets[i]:offsets[i + 1]] for i in range(len(offsets) - 1)]


class _PointIndex:
    _knn = None
    _radius = None
    _box = None

    def knn(self, queries, k, threads=0):
        """The k nearest points of each query: (index, distance) arrays of
        shape (n, k) (or (k,) for one query), index -1 / distance inf where
        there are fewer than k points."""
        q, single = _queries(queries, self.dim)
        n = q.shape[0]
        idx = np.empty((n, k), dtype=np.uint32)
        dist = np.empty((n, k), dtype=np.float64)
        d = _diag()
        check(self._knn(self._ptr, dptr(q), n, k, _u32(idx), dptr(dist), threads, d), d, "knn")
        idx = idx.astype(np.int64)
        idx[idx == _INVALID] = -1
        return (idx[0], dist[0]) if single else (idx, dist)

    def radius(self, queries, r, threads=0):
        """All points within distance r (inclusive) of each query, nearest
        first: a list of (index, distance) pairs of arrays (one pair for one
        query)."""
        q, single = _queries(queries, self.dim)
        nb = ffi.new("geom_neighbors *")
        d = _diag()
        check(self._radius(self._ptr, dptr(q), q.shape[0], float(r), nb, threads, d), d, "radius")
        off, idx, dist = _rows(nb, True)
        out = list(zip(_split(off, idx), _split(off, dist)))
        return out[0] if single else out

    def box(self, lo, hi):
        """Indices of the points in the closed box [lo, hi], increasing."""
        lo = np.ascontiguousarray(lo, dtype=np.float64).reshape(self.dim)
        hi = np.ascontiguousarray(hi, dtype=np.float64).reshape(self.dim)
        nb = ffi.new("geom_neighbors *")
        check(self._box(self._ptr, dptr(lo), dptr(hi), nb), None, "box")
        return _rows(nb, False)[1]


class KdTree(_PointIndex):
    """kd-tree over an (n, 2) or (n, 3) array of points."""

    def __init__(self, points, leaf_size=0, threads=0):
        pts = np.ascontiguousarray(points, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] not in (2, 3):
            raise ValueError("points: expected shape (n, 2) or (n, 3), got %s" % (pts.shape,))
        self.dim = pts.shape[1]
        opt = ffi.new("geom_kdtree_options *")
        opt.leaf_size = leaf_size
        opt.threads = threads
        out = ffi.new("geom_kdtree **")
        d = _diag()
        check(lib.geom_kdtree_build(dptr(pts), pts.shape[0], self.dim, opt, out, d), d, "KdTree")
        self._ptr = ffi.gc(out[0], lib.geom_kdtree_destroy)
        self._knn = lib.geom_kdtree_knn
        self._radius = lib.geom_kdtree_radius
        self._box = lib.geom_kdtree_box

    @property
    def depth(self):
        return int(lib.geom_kdtree_depth(self._ptr))

    @property
    def nbytes(self):
        return int(lib.geom_kdtree_bytes(self._ptr))

    @property
    def node_count(self):
        """Nodes of the tree (geom_kdtree_node_count)."""
        return int(lib.geom_kdtree_node_count(self._ptr))


def _octree_options(bucket_size, max_depth, balance, threads):
    opt = ffi.new("geom_octree_options *")
    opt.bucket_size = bucket_size
    opt.max_depth = max_depth
    opt.balance = 1 if balance else 0
    opt.threads = threads
    return opt


class Octree(_PointIndex):
    """Quadtree (2D points) or octree (3D points); see also the
    Octree.triangles and Octree.segments constructors."""

    def __init__(self, points=None, bucket_size=0, max_depth=0, balance=False, threads=0,
                 _ptr=None, _dim=None):
        if _ptr is not None:
            self._ptr = _ptr
            self.dim = int(lib.geom_octree_dim(_ptr))
        else:
            pts = np.ascontiguousarray(points, dtype=np.float64)
            if pts.ndim != 2 or pts.shape[1] not in (2, 3):
                raise ValueError("points: expected shape (n, 2) or (n, 3), got %s" % (pts.shape,))
            self.dim = pts.shape[1]
            out = ffi.new("geom_octree **")
            d = _diag()
            check(lib.geom_octree_build_points(dptr(pts), pts.shape[0], self.dim,
                                               _octree_options(bucket_size, max_depth, balance,
                                                               threads), out, d), d, "Octree")
            self._ptr = ffi.gc(out[0], lib.geom_octree_destroy)
        self._knn = lib.geom_octree_knn
        self._radius = lib.geom_octree_radius
        self._box = lib.geom_octree_box

    @classmethod
    def triangles(cls, positions, tris, bucket_size=0, max_depth=0, balance=False, threads=0):
        """Octree over triangles (positions (nv, 3), tris (nt, 3))."""
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        t = np.ascontiguousarray(tris, dtype=np.uint32).reshape(-1, 3)
        out = ffi.new("geom_octree **")
        d = _diag()
        check(lib.geom_octree_build_triangles(dptr(pos), pos.shape[0], _u32(t), t.shape[0],
                                              _octree_options(bucket_size, max_depth, balance,
                                                              threads), out, d), d, "Octree")
        return cls(_ptr=ffi.gc(out[0], lib.geom_octree_destroy), _dim=3)

    @classmethod
    def segments(cls, positions, segs, bucket_size=0, max_depth=0, balance=False, threads=0):
        """Quadtree over 2D segments (positions (nv, 2), segs (ns, 2))."""
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 2)
        s = np.ascontiguousarray(segs, dtype=np.uint32).reshape(-1, 2)
        out = ffi.new("geom_octree **")
        d = _diag()
        check(lib.geom_octree_build_segments(dptr(pos), pos.shape[0], _u32(s), s.shape[0],
                                             _octree_options(bucket_size, max_depth, balance,
                                                             threads), out, d), d, "Octree")
        return cls(_ptr=ffi.gc(out[0], lib.geom_octree_destroy), _dim=2)

    def frustum(self, planes):
        """Items whose box is not outside any of six planes (a, b, c, d),
        a*x + b*y + c*z + d >= 0 inside; increasing indices."""
        pl = np.ascontiguousarray(planes, dtype=np.float64).reshape(24)
        nb = ffi.new("geom_neighbors *")
        check(lib.geom_octree_frustum(self._ptr, dptr(pl), nb), None, "frustum")
        return _rows(nb, False)[1]

    @property
    def depth(self):
        return int(lib.geom_octree_depth(self._ptr))

    @property
    def node_count(self):
        n = ffi.new("size_t *")
        lib.geom_octree_nodes(self._ptr, n)
        return int(n[0])

    @property
    def nbytes(self):
        """Bytes held by the tree (geom_octree_bytes)."""
        return int(lib.geom_octree_bytes(self._ptr))

    def nodes(self):
        """The flat node array as a dict of arrays (geom_octree_nodes):
        'cell_min', 'cell_max' (m, 3) (the node's square or cube, z extent
        0 in 2D), 'bounds_min', 'bounds_max' (m, 3) (the tight box of the
        subtree's items, empty (min > max) without items), 'first_child'
        (-1 for a leaf; the children are contiguous from there, in
        increasing octant order for the bits of child_mask: bit 0 = +x
        half, bit 1 = +y, bit 2 = +z), 'child_mask', 'item_start',
        'item_total' (the subtree's items are items()[item_start :
        item_start + item_total]), 'own_count' (the first own_count of them
        are stored at the node itself), 'level' (root 0)."""
        n = ffi.new("size_t *")
        p = lib.geom_octree_nodes(self._ptr, n)
        m = int(n[0])
        raw = np.frombuffer(ffi.buffer(p, ffi.sizeof("geom_octree_node") * m), dtype=np.uint8)
        arr = raw.view(_OCTREE_NODE_DTYPE).copy() if m else np.zeros(0, dtype=_OCTREE_NODE_DTYPE)
        out = {k: arr[k] for k in _OCTREE_NODE_DTYPE.names}
        fc = out["first_child"].astype(np.int64)
        fc[fc == _INVALID] = -1
        out["first_child"] = fc
        return out

    def items(self):
        """Item (point, segment or triangle) indices in tree order
        (geom_octree_items), which nodes() index into."""
        n = ffi.new("size_t *")
        p = lib.geom_octree_items(self._ptr, n)
        m = int(n[0])
        return (np.frombuffer(ffi.buffer(p, 4 * m), dtype=np.uint32).astype(np.int64)
                if m else np.empty(0, dtype=np.int64))

    def ray(self, origin, direction, tmin=0.0, tmax=np.inf):
        """The items whose box the ray origin + t direction meets within
        [tmin, tmax], front to back (geom_octree_ray: a conservative slab
        test, nothing missed at shared faces): (index, entry t) arrays."""
        r = ffi.new("geom_ray *")
        o = np.asarray(origin, dtype=np.float64).reshape(-1)
        d = np.asarray(direction, dtype=np.float64).reshape(-1)
        o3, d3 = np.zeros(3), np.zeros(3)
        o3[:o.size], d3[:d.size] = o, d
        r.origin.x, r.origin.y, r.origin.z = (float(v) for v in o3)
        r.dir.x, r.dir.y, r.dir.z = (float(v) for v in d3)
        r.tmin, r.tmax = float(tmin), float(tmax)
        nb = ffi.new("geom_neighbors *")
        check(lib.geom_octree_ray(self._ptr, r, nb), None, "ray")
        _, index, dist = _rows(nb, True)
        return index, dist


_OCTREE_NODE_DTYPE = np.dtype([("cell_min", "<f8", 3), ("cell_max", "<f8", 3),
                               ("bounds_min", "<f8", 3), ("bounds_max", "<f8", 3),
                               ("first_child", "<u4"), ("child_mask", "<u4"),
                               ("item_start", "<u4"), ("item_total", "<u4"),
                               ("own_count", "<u4"), ("level", "<u4")])


class MeshDistance:
    """Closest points, winding numbers and signed distances to a triangle
    mesh (positions (nv, 3), tris (nt, 3))."""

    def __init__(self, positions, tris, beta=0.0, tolerance=0.0, threads=0):
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        t = np.ascontiguousarray(tris, dtype=np.uint32).reshape(-1, 3)
        opt = ffi.new("geom_meshdist_options *")
        opt.beta = beta
        opt.tolerance = tolerance
        opt.threads = threads
        out = ffi.new("geom_meshdist **")
        d = _diag()
        check(lib.geom_meshdist_create(dptr(pos), pos.shape[0], _u32(t), t.shape[0], opt, out, d),
              d, "MeshDistance")
        self._ptr = ffi.gc(out[0], lib.geom_meshdist_destroy)
        self._pos, self._tris = pos.copy(), t.copy()

    @property
    def nbytes(self):
        """Bytes held (geom_meshdist_bytes: the BVH, the triangle data and
        the winding-number moments)."""
        return int(lib.geom_meshdist_bytes(self._ptr))

    @property
    def bvh(self):
        """The BVH over the triangles the queries use (geom_meshdist_bvh),
        as a read-only Bvh (nodes, prim_indices, overlap; refit raises
        ValueError). It keeps this MeshDistance alive."""
        return Bvh._view(lib.geom_meshdist_bvh(self._ptr), self, self._pos, self._tris)

    def closest(self, queries, threads=0):
        """dict with 'point' (n, 3), 'triangle' (n,), 'bary' (n, 3),
        'distance' (n,) (unbatched shapes for one query)."""
        q, single = _queries(queries, 3)
        n = q.shape[0]
        pt = np.empty((n, 3))
        bary = np.empty((n, 3))
        dist = np.empty(n)
        tri = np.empty(n, dtype=np.uint32)
        d = _diag()
        check(lib.geom_meshdist_closest(self._ptr, dptr(q), n, dptr(pt), _u32(tri), dptr(bary),
                                        dptr(dist), threads, d), d, "closest")
        tri = tri.astype(np.int64)
        tri[tri == _INVALID] = -1
        out = {"point": pt, "triangle": tri, "bary": bary, "distance": dist}
        return {k: v[0] for k, v in out.items()} if single else out

    def _scalar(self, fn, queries, threads, what):
        q, single = _queries(queries, 3)
        n = q.shape[0]
        out = np.empty(n)
        rep = ffi.new("geom_error_report *")
        d = _diag()
        check(fn(self._ptr, dptr(q), n, dptr(out), rep, threads, d), d, what)
        return (out[0] if single else out), error_report(rep)

    def winding_number(self, queries, threads=0):
        """(values, error report): generalized winding numbers (fast
        approximation, error bound in the report)."""
        return self._scalar(lib.geom_meshdist_winding, queries, threads, "winding_number")

    def signed_distance(self, queries, threads=0):
        """(values, error report): signed distances, negative inside."""
        return self._scalar(lib.geom_meshdist_signed_distance, queries, threads, "signed_distance")


def _bvh_options(method, max_leaf_size, bins, threads):
    if method not in ("sah", "lbvh"):
        raise ValueError("method is 'sah' or 'lbvh', got %r" % (method,))
    opt = ffi.new("geom_bvh_options *")
    opt.method = {"sah": lib.GEOM_BVH_SAH, "lbvh": lib.GEOM_BVH_LBVH}[method]
    opt.max_leaf_size = max_leaf_size
    opt.bins = bins
    opt.threads = threads
    return opt


_NODE_DTYPE = np.dtype([("min", "<f8", 3), ("max", "<f8", 3), ("index", "<u4"), ("count", "<u4"),
                        ("axis", "<u4"), ("pad", "<u4")])


def _aabbs(boxes):
    """A `geom_aabb *` over a C-contiguous (n, 6) float64 array."""
    return ffi.cast("geom_aabb *", ffi.from_buffer("double[]", boxes))


def _box_pairs(lo, hi, what):
    """(lo, hi) as C-contiguous (n, 3) float64 arrays, and whether one box
    was given; hi None means lo is (n, 6) (min xyz, max xyz)."""
    if hi is None:
        b = np.asarray(lo, dtype=np.float64)
        if b.ndim not in (1, 2) or b.shape[-1] != 6:
            raise ValueError("%s: expected shape (6,) or (n, 6) (min xyz, max xyz), or lo and hi, "
                             "got %s" % (what, b.shape))
        single = b.ndim == 1
        b = b.reshape(-1, 6)
        lo, hi = b[:, :3], b[:, 3:]
    else:
        lo, single = as_points(lo, 3, what + " lo")
        hi, single_hi = as_points(hi, 3, what + " hi")
        if single != single_hi or lo.shape != hi.shape:
            raise ValueError("%s: lo %s and hi %s differ in shape" % (what, lo.shape, hi.shape))
    return np.ascontiguousarray(lo), np.ascontiguousarray(hi), single


class Bvh:
    """A BVH (bounding volume hierarchy) over triangles (positions (nv, 3),
    tris (nt, 3)) or, with Bvh.from_boxes, over caller boxes: method 'sah'
    (binned surface area heuristic, Wald 2007; the default) or 'lbvh'
    (Morton codes, Lauterbach et al. 2009). The tree is deterministic
    (the same for any thread count) and its boxes are exact: each contains
    its primitives' bounds, computed with min/max only.

    nodes() and prim_indices() give the flat depth-first layout;
    overlap(lo, hi) answers box queries; refit(positions) recomputes the
    boxes of a triangle BVH after its vertices moved (same topology)."""

    def __init__(self, positions, tris, method="sah", max_leaf_size=0, threads=0, bins=0):
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        t = np.ascontiguousarray(tris, dtype=np.uint32).reshape(-1, 3).copy()
        out = ffi.new("geom_bvh **")
        d = _diag()
        check(lib.geom_bvh_build_triangles(dptr(pos), pos.shape[0], _u32(t), t.shape[0],
                                           _bvh_options(method, max_leaf_size, bins, threads), out,
                                           d), d, "Bvh")
        self._ptr = ffi.gc(out[0], lib.geom_bvh_destroy)
        self._tris = t
        self._boxes = self._triangle_boxes(pos)

    def _triangle_boxes(self, pos):
        """The primitive boxes as an (nt, 6) geom_aabb array (min xyz, max
        xyz), the min/max of each triangle's vertices."""
        if self._tris.shape[0] == 0:
            return np.empty((0, 6))
        v = pos[self._tris.astype(np.int64)]
        return np.ascontiguousarray(np.hstack([v.min(axis=1), v.max(axis=1)]))

    @classmethod
    def from_boxes(cls, lo, hi=None, method="sah", max_leaf_size=0, threads=0, bins=0):
        """A BVH over n caller boxes (geom_bvh_build_boxes): lo and hi
        (n, 3) arrays, or lo alone as (n, 6) (min xyz, max xyz); primitive
        i is box i. Raises GeomError (ERR_INVALID_ARG, the message naming
        the first bad box) for an empty box (min > max on an axis) or a
        NaN/Inf bound; ValueError for bad shapes."""
        lo, hi, _ = _box_pairs(lo, hi, "boxes")
        boxes = np.ascontiguousarray(np.hstack([lo, hi]))   # geom_aabb: min xyz, max xyz
        assert ffi.sizeof("geom_aabb") == 48
        out = ffi.new("geom_bvh **")
        d = _diag()
        check(lib.geom_bvh_build_boxes(_aabbs(boxes), boxes.shape[0],
                                       _bvh_options(method, max_leaf_size, bins, threads), out, d),
              d, "Bvh.from_boxes")
        self = cls.__new__(cls)
        self._ptr = ffi.gc(out[0], lib.geom_bvh_destroy)
        self._tris = None
        self._boxes = boxes
        return self

    @classmethod
    def _view(cls, ptr, owner, pos, tris):
        self = cls.__new__(cls)
        self._ptr = ptr
        self._owner = owner
        self._tris = tris
        self._boxes = self._triangle_boxes(pos)
        return self

    def refit(self, positions, tris=None):
        """Recompute every box bottom-up after the vertices moved
        (geom_bvh_refit_triangles), keeping the tree's topology: queries
        then answer as a fresh build over the new positions would (the
        tree may be less tight than a fresh build's). positions (nv, 3);
        tris defaults to the triangles the BVH was built with (same count
        required). Raises GeomError (ERR_INVALID_ARG: triangle count
        mismatch, a vertex index >= nv, NaN/Inf; the BVH is then left
        unchanged); ValueError for a BVH built from boxes without tris."""
        if getattr(self, "_owner", None) is not None:
            raise ValueError("refit: this BVH belongs to a MeshDistance and is read-only")
        if tris is None:
            if self._tris is None:
                raise ValueError("refit: this BVH was built from boxes; pass tris")
            t = self._tris
        else:
            t = np.ascontiguousarray(tris, dtype=np.uint32).reshape(-1, 3).copy()
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        check(lib.geom_bvh_refit_triangles(self._ptr, dptr(pos), pos.shape[0], _u32(t),
                                           t.shape[0]), None, "Bvh.refit")
        self._tris = t
        self._boxes = self._triangle_boxes(pos)

    def nodes(self):
        """dict of arrays: 'min' (m, 3), 'max' (m, 3), 'index', 'count',
        'axis'. Interior node i (count 0): left child i + 1, right child
        index[i]; leaf: primitives prim_indices()[index : index + count]."""
        n = ffi.new("size_t *")
        p = lib.geom_bvh_nodes(self._ptr, n)
        m = int(n[0])
        raw = np.frombuffer(ffi.buffer(p, ffi.sizeof("geom_bvh_node") * m), dtype=np.uint8)
        arr = raw.view(_NODE_DTYPE).copy() if m else np.zeros(0, dtype=_NODE_DTYPE)
        return {k: arr[k] for k in ("min", "max", "index", "count", "axis")}

    def prim_indices(self):
        """The primitive indices the leaves reference (a permutation of
        0..n-1)."""
        n = ffi.new("size_t *")
        p = lib.geom_bvh_prim_indices(self._ptr, n)
        m = int(n[0])
        return (np.frombuffer(ffi.buffer(p, 4 * m), dtype=np.uint32).astype(np.int64)
                if m else np.empty(0, dtype=np.int64))

    def overlap(self, lo, hi=None, threads=0):
        """Primitives whose bounding box meets the closed query box [lo, hi]
        (boxes touching at a face, edge or corner count; lo > hi on an axis
        is an empty box that meets nothing), in increasing order: one array
        for one box (lo, hi of shape (3,), or lo (6,)), a list of arrays
        for n boxes ((n, 3) each, or lo (n, 6)). The primitive boxes are the
        caller's boxes (from_boxes) or the min/max of each triangle's
        vertices at the last build or refit. One C call over every query
        box (geom_bvh_query_boxes: a pruned walk of the tree per query, in
        parallel chunks), exactly what a brute-force test of every
        primitive box gives. ValueError for a NaN bound."""
        qlo, qhi, single = _box_pairs(lo, hi, "overlap")
        if np.isnan(qlo).any() or np.isnan(qhi).any():
            raise ValueError("overlap: NaN in a query box")
        q = np.ascontiguousarray(np.hstack([qlo, qhi]))
        nb = ffi.new("geom_neighbors *")
        d = _diag()
        check(lib.geom_bvh_query_boxes(self._ptr, _aabbs(self._boxes), _aabbs(q), q.shape[0], nb,
                                       threads, d), d, "overlap")
        offsets, index, _ = _rows(nb, False)
        out = _split(offsets, index)
        return out[0] if single else out

    @property
    def depth(self):
        return int(lib.geom_bvh_depth(self._ptr))

    @property
    def nbytes(self):
        """Bytes held by the BVH (geom_bvh_bytes)."""
        return int(lib.geom_bvh_bytes(self._ptr))
