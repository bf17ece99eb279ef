"""Spatial indices and their batch queries (geom/spatial.h).

Every query takes an (n, dim) array of query points (or one point) and calls
the C batch function once (parallel over the queries with OpenMP; the
answers do not depend on the thread count), never a Python loop.

  KdTree(points)            2D or 3D points: knn, radius, box
  Octree(points)            quadtree (2D) / octree (3D) over points: knn,
                            radius, box, frustum; Octree.triangles(...) and
                            Octree.segments(...) over elements: box, frustum
  MeshDistance(pos, tris)   closest point, winding number, signed distance
  Bvh(pos, tris)            the flat BVH (nodes and primitive order)

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
            self._ptr, self.dim = _ptr, _dim
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


class Bvh:
    """A BVH over triangles (method 'sah' or 'lbvh'): nodes as numpy arrays."""

    def __init__(self, positions, tris, method="sah", max_leaf_size=0, threads=0):
        pos = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        t = np.ascontiguousarray(tris, dtype=np.uint32).reshape(-1, 3)
        opt = ffi.new("geom_bvh_options *")
        opt.method = {"sah": lib.GEOM_BVH_SAH, "lbvh": lib.GEOM_BVH_LBVH}[method]
        opt.max_leaf_size = max_leaf_size
        opt.threads = threads
        out = ffi.new("geom_bvh **")
        d = _diag()
        check(lib.geom_bvh_build_triangles(dptr(pos), pos.shape[0], _u32(t), t.shape[0], opt, out,
                                           d), d, "Bvh")
        self._ptr = ffi.gc(out[0], lib.geom_bvh_destroy)

    def nodes(self):
        """dict of arrays: 'min' (m, 3), 'max' (m, 3), 'index', 'count', 'axis'."""
        n = ffi.new("size_t *")
        p = lib.geom_bvh_nodes(self._ptr, n)
        m = int(n[0])
        raw = np.frombuffer(ffi.buffer(p, ffi.sizeof("geom_bvh_node") * m), dtype=np.uint8)
        rec = np.dtype([("min", "<f8", 3), ("max", "<f8", 3), ("index", "<u4"), ("count", "<u4"),
                        ("axis", "<u4"), ("pad", "<u4")])
        arr = raw.view(rec).copy() if m else np.zeros(0, dtype=rec)
        return {k: arr[k] for k in ("min", "max", "index", "count", "axis")}

    def prim_indices(self):
        n = ffi.new("size_t *")
        p = lib.geom_bvh_prim_indices(self._ptr, n)
        m = int(n[0])
        return (np.frombuffer(ffi.buffer(p, 4 * m), dtype=np.uint32).astype(np.int64)
                if m else np.empty(0, dtype=np.int64))

    @property
    def depth(self):
        return int(lib.geom_bvh_depth(self._ptr))
