"""Ray intersection (geom/ray.h): a RayScene of analytic shapes and triangle
meshes, queried with numpy arrays of rays.

    s = RayScene()
    s.add_sphere([0, 0, 0], 1.0)
    s.add_triangles(positions, triangles)      # (n, 3) floats, (m, 3) ints
    s.build()
    hit = s.closest(origins, directions)       # (k, 3) arrays (or one ray)

closest() returns a dict of arrays: "hit" (bool), "t" (NaN on a miss),
"point", "normal" (geometric, stored orientation), "shading_normal", "uv",
"prim", "object", "t_error", "enter". all() returns the list of hits of one
ray as dicts, sorted by t. t is in units of the direction as given; tmin
and tmax (scalars or arrays) default to 0 and +inf. Invalid rays (NaN/Inf,
zero direction) are misses with "valid" False, as geom-raycast reports them.
Queries loop in Python over the C function (about a microsecond of overhead
per ray).
"""

import numpy as np

from ._ffi import ffi, lib
from .core import as_points, check, new_diag


class RayScene:
    """A geom_ray_scene: add objects, build(), then query."""

    def __init__(self):
        self._s = ffi.gc(lib.geom_ray_scene_create(ffi.NULL), lib.geom_ray_scene_destroy)
        if self._s == ffi.NULL:
            raise MemoryError("geom_ray_scene_create")
        self._built = False
        self._keep = []

    def _id(self, status, idp, what):
        check(status, context=what)
        self._built = False
        return int(idp[0])

    def add_sphere(self, center, radius):
        idp = ffi.new("uint32_t *")
        c = np.ascontiguousarray(center, dtype=np.float64)
        return self._id(lib.geom_ray_scene_add_sphere(self._s, ffi.from_buffer("double[]", c),
                                                      float(radius), idp), idp, "add_sphere")

    def add_box(self, lo, hi):
        idp = ffi.new("uint32_t *")
        a = np.ascontiguousarray(lo, dtype=np.float64)
        b = np.ascontiguousarray(hi, dtype=np.float64)
        return self._id(lib.geom_ray_scene_add_box(self._s, ffi.from_buffer("double[]", a),
                                                   ffi.from_buffer("double[]", b), idp), idp, "add_box")

    def add_plane(self, point, normal):
        idp = ffi.new("uint32_t *")
        a = np.ascontiguousarray(point, dtype=np.float64)
        b = np.ascontiguousarray(normal, dtype=np.float64)
        return self._id(lib.geom_ray_scene_add_plane(self._s, ffi.from_buffer("double[]", a),
                                                     ffi.from_buffer("double[]", b), idp), idp, "add_plane")

    def add_torus(self, major, minor):
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_torus(self._s, float(major), float(minor), idp), idp,
                        "add_torus")

    def add_quadric(self, coefficients, clip=None, capped=False):
        idp = ffi.new("uint32_t *")
        q = np.ascontiguousarray(coefficients, dtype=np.float64)
        if q.shape != (10,):
            raise ValueError("coefficients: expected 10 numbers")
        cp = ffi.NULL
        if clip is not None:
            c = np.ascontiguousarray(clip, dtype=np.float64)
            if c.shape != (6,):
                raise ValueError("clip: expected 6 numbers")
            self._keep.append(c)
            cp = ffi.from_buffer("double[]", c)
        return self._id(lib.geom_ray_scene_add_quadric(self._s, ffi.from_buffer("double[]", q), cp,
                                                       int(bool(capped)), idp), idp, "add_quadric")

    def add_triangles(self, positions, triangles, normals=None):
        idp = ffi.new("uint32_t *")
        p, _ = as_points(positions, 3, "positions")
        t = np.ascontiguousarray(triangles, dtype=np.uint32)
        if t.ndim != 2 or t.shape[1] != 3:
            raise ValueError("triangles: expected shape (m, 3)")
        npp = ffi.NULL
        if normals is not None:
            nrm, _ = as_points(normals, 3, "normals")
            npp = ffi.from_buffer("double[]", nrm)
        return self._id(lib.geom_ray_scene_add_triangles(
            self._s, ffi.from_buffer("double[]", p), p.shape[0], ffi.from_buffer("uint32_t[]", t),
            t.shape[0], npp, idp), idp, "add_triangles")

    def set_transform(self, node, matrix):
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape == (4, 4):
            m = m.T.copy()  # row-major numpy matrix to column-major
        m = np.ascontiguousarray(m.reshape(16))
        check(lib.geom_ray_scene_set_transform(self._s, int(node), ffi.from_buffer("double[]", m)),
              context="set_transform")
        self._built = False

    def build(self, threads=0):
        """Build (BVHs for meshes); returns what was built as a dict."""
        opt = ffi.new("geom_ray_build_options *")
        opt.bvh_threads = int(threads)
        info = ffi.new("geom_ray_build_info *")
        diag = new_diag()
        check(lib.geom_ray_scene_build(self._s, opt, info, diag), diag, "build")
        self._built = True
        return {k: int(getattr(info, k)) for k in ("meshes", "triangles", "bvh_nodes", "bvh_bytes",
                                                   "bezier_patches", "analytic")}

    def _rays(self, origins, directions, tmin, tmax):
        if not self._built:
            raise RuntimeError("RayScene: call build() after adding objects")
        o, one_o = as_points(origins, 3, "origins")
        d, one_d = as_points(directions, 3, "directions")
        n = max(o.shape[0], d.shape[0])
        if o.shape[0] not in (1, n) or d.shape[0] not in (1, n):
            raise ValueError("origins and directions: different row counts")
        o = np.broadcast_to(o, (n, 3))
        d = np.broadcast_to(d, (n, 3))
        t0 = np.broadcast_to(np.asarray(tmin, dtype=np.float64), (n,))
        t1 = np.broadcast_to(np.asarray(tmax, dtype=np.float64), (n,))
        return n, one_o and one_d, o, d, t0, t1

    @staticmethod
    def _ray(r, o, d, t0, t1):
        r.origin.x, r.origin.y, r.origin.z = o
        r.dir.x, r.dir.y, r.dir.z = d
        r.tmin = t0
        r.tmax = t1

    def closest(self, origins, directions, tmin=0.0, tmax=np.inf):
        n, single, o, d, t0, t1 = self._rays(origins, directions, tmin, tmax)
        out = {"hit": np.zeros(n, bool), "valid": np.ones(n, bool), "t": np.full(n, np.nan),
               "point": np.full((n, 3), np.nan), "normal": np.full((n, 3), np.nan),
               "shading_normal": np.full((n, 3), np.nan), "uv": np.full((n, 2), np.nan),
               "prim": np.zeros(n, np.int64), "object": np.full(n, -1, np.int64),
               "t_error": np.full(n, np.nan), "enter": np.zeros(n, bool)}
        r = ffi.new("geom_ray *")
        h = ffi.new("geom_ray_hit *")
        found = ffi.new("int *")
        for i in range(n):
            self._ray(r, o[i], d[i], t0[i], t1[i])
            st = lib.geom_ray_scene_closest(self._s, r, h, found)
            if st == lib.GEOM_ERR_INVALID_ARG:
                out["valid"][i] = False
                continue
            check(st, context="closest")
            if not found[0]:
                continue
            out["hit"][i] = True
            out["t"][i] = h.t
            out["point"][i] = (h.point.x, h.point.y, h.point.z)
            out["normal"][i] = (h.ng.x, h.ng.y, h.ng.z)
            out["shading_normal"][i] = (h.ns.x, h.ns.y, h.ns.z)
            out["uv"][i] = (h.u, h.v)
            out["prim"][i] = h.prim
            out["object"][i] = h.object
            out["t_error"][i] = h.t_error
            out["enter"][i] = bool(h.enter)
        if single:
            out = {k: v[0] for k, v in out.items()}
        return out

    def any(self, origins, directions, tmin=0.0, tmax=np.inf):
        """Boolean array: does each ray hit anything in [tmin, tmax]?"""
        n, single, o, d, t0, t1 = self._rays(origins, directions, tmin, tmax)
        res = np.zeros(n, bool)
        r = ffi.new("geom_ray *")
        found = ffi.new("int *")
        for i in range(n):
            self._ray(r, o[i], d[i], t0[i], t1[i])
            st = lib.geom_ray_scene_any(self._s, r, found)
            if st == lib.GEOM_ERR_INVALID_ARG:
                continue
            check(st, context="any")
            res[i] = bool(found[0])
        return bool(res[0]) if single else res

    def all(self, origin, direction, tmin=0.0, tmax=np.inf):
        """Every hit of one ray, sorted by t: a list of dicts (t, point,
        normal, uv, prim, object, enter)."""
        n, _, o, d, t0, t1 = self._rays(origin, direction, tmin, tmax)
        if n != 1:
            raise ValueError("all(): one ray at a time")
        r = ffi.new("geom_ray *")
        self._ray(r, o[0], d[0], t0[0], t1[0])
        cnt = ffi.new("size_t *")
        cap = 16
        while True:
            hits = ffi.new("geom_ray_hit[]", cap)
            st = lib.geom_ray_scene_all(self._s, r, hits, cap, cnt)
            if st == lib.GEOM_ERR_LIMIT:
                cap = int(cnt[0])
                continue
            check(st, context="all")
            break
        return [{"t": hits[i].t, "point": (hits[i].point.x, hits[i].point.y, hits[i].point.z),
                 "normal": (hits[i].ng.x, hits[i].ng.y, hits[i].ng.z), "uv": (hits[i].u, hits[i].v),
                 "prim": int(hits[i].prim), "object": int(hits[i].object), "enter": bool(hits[i].enter)}
                for i in range(int(cnt[0]))]
