"""Ray intersection (geom/ray.h): a RayScene of analytic shapes, triangle
meshes, NURBS surfaces, subdivision surfaces, implicit surfaces, volumes,
CSG, groups and instances, queried with numpy arrays of rays.

    s = RayScene()
    s.add_sphere([0, 0, 0], 1.0)
    s.add_triangles(positions, triangles)      # (n, 3) floats, (m, 3) ints
    s.build()
    hit = s.closest(origins, directions)       # (k, 3) arrays (or one ray)

closest() returns a dict of arrays: "hit" (bool), "t" (NaN on a miss),
"point", "normal" (geometric, stored orientation), "shading_normal", "uv",
"prim", "object", "t_error", "enter". any() returns a boolean array. all()
returns every hit sorted by t: for one ray a list of dicts, for many rays
flat arrays in compressed rows ("offsets"). t is in units of the direction
as given; tmin and tmax (scalars or arrays) default to 0 and +inf. Invalid
rays (NaN/Inf, zero direction) are misses with "valid" False, as
geom-raycast reports them. Each query is one C call over all the rays
(geom_ray_scene_closest_many, _any_many, _all_many), bit for bit the
single-ray functions' answers.
"""

import numpy as np

from ._ffi import ffi, lib
from .core import as_points, check, new_diag


def _hit_dtype():
    """numpy view of geom_ray_hit, laid out by cffi's offsets."""
    off = lambda f: ffi.offsetof("geom_ray_hit", f)
    v3 = ("<f8", (3,))
    return np.dtype({"names": ["t", "point", "ng", "ns", "u", "v", "prim", "object", "t_error", "enter"],
                     "formats": ["<f8", v3, v3, v3, "<f8", "<f8", "<u4", "<u4", "<f8", "<i4"],
                     "offsets": [off(k) for k in ("t", "point", "ng", "ns", "u", "v", "prim", "object",
                                                  "t_error", "enter")],
                     "itemsize": ffi.sizeof("geom_ray_hit")})


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

    def _vec(self, v, n, what):
        a = np.ascontiguousarray(v, dtype=np.float64).reshape(-1)
        if a.size != n:
            raise ValueError("%s: expected %d numbers" % (what, n))
        self._keep.append(a)
        return ffi.from_buffer("double[]", a)

    def add_disk(self, center, normal, radius):
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_disk(self._s, self._vec(center, 3, "center"),
                                                    self._vec(normal, 3, "normal"), float(radius),
                                                    idp), idp, "add_disk")

    def add_obox(self, center, axes, half):
        """Oriented box: center, three orthogonal axes (3, 3) (lengths
        ignored), half-extents along them."""
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_obox(self._s, self._vec(center, 3, "center"),
                                                    self._vec(axes, 9, "axes"),
                                                    self._vec(half, 3, "half"), idp), idp, "add_obox")

    def add_triangle(self, vertices):
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_triangle(self._s, self._vec(vertices, 9, "vertices"),
                                                        idp), idp, "add_triangle")

    def add_polygon(self, vertices):
        """Planar polygon of n >= 3 vertices (n, 3)."""
        idp = ffi.new("uint32_t *")
        v, _ = as_points(vertices, 3, "vertices")
        self._keep.append(v)
        return self._id(lib.geom_ray_scene_add_polygon(self._s, ffi.from_buffer("double[]", v),
                                                       v.shape[0], idp), idp, "add_polygon")

    def add_mesh(self, mesh):
        """A geom.Mesh (faces fan-triangulated, its normals for shading;
        copied)."""
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_mesh(self._s, mesh._ptr, idp), idp, "add_mesh")

    def add_surface(self, surface):
        """A geom.NurbsSurface (kept referenced: the scene borrows it)."""
        idp = ffi.new("uint32_t *")
        diag = new_diag()
        self._keep.append(surface)
        st = lib.geom_ray_scene_add_surface(self._s, surface._s, idp, diag)
        check(st, diag, "add_surface")
        return self._id(st, idp, "add_surface")

    def add_subdiv(self, mesh, scheme="catmull-clark", levels=0):
        """Subdivision surface of a geom.Mesh (levels 0: from the scene's
        tolerance)."""
        idp = ffi.new("uint32_t *")
        sch = ffi.new("geom_subdiv_scheme *")
        check(lib.geom_subdiv_scheme_from_name(str(scheme).encode(), sch),
              context="add_subdiv: unknown scheme %r" % (scheme,))
        diag = new_diag()
        st = lib.geom_ray_scene_add_subdiv(self._s, mesh._ptr, int(sch[0]), int(levels), idp, diag)
        check(st, diag, "add_subdiv")
        return self._id(st, idp, "add_subdiv")

    def add_implicit(self, expr, bounds, lipschitz=0.0):
        """Implicit surface f = 0 (f < 0 inside) of an expression string or
        geom.Expression within bounds (x0, y0, z0, x1, y1, z1); lipschitz >
        0 (a true bound on |grad f|) enables sphere tracing."""
        from .implicit import Expression
        if isinstance(expr, str):
            expr = Expression(expr)
        self._keep.append(expr)
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_implicit(self._s, expr._ptr,
                                                        self._vec(bounds, 6, "bounds"),
                                                        float(lipschitz), idp), idp, "add_implicit")

    def add_volume(self, volume, iso, inside="below"):
        """Iso-surface f = iso of the trilinear interpolant of a geom.Volume
        (from read_volume or Volume(samples, spacing, origin)). inside:
        "below" (f < iso inside, a distance field), "above" (f > iso inside,
        a CT volume, dense inside) or "detect" (Volume.detect_inside); the
        normal points away from the inside (geom_ray_scene_add_volume_opt)."""
        if inside == "detect":
            inside = volume.detect_inside(iso)[0]
        if inside not in ("below", "above"):
            raise ValueError("inside: expected 'below', 'above' or 'detect', got %r" % (inside,))
        v = volume._c()
        self._keep += [volume, v]
        opt = ffi.new("geom_ray_volume_options *")
        opt.inside = 1 if inside == "above" else 0
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_volume_opt(self._s, v, float(iso), opt, idp), idp,
                        "add_volume")

    def add_csg(self, op, a, b):
        """CSG node "union", "intersection" or "difference" (a - b) over two
        closed nodes (ids), which stop being top-level objects."""
        ops = {"union": lib.GEOM_RAY_CSG_UNION, "intersection": lib.GEOM_RAY_CSG_INTERSECTION,
               "difference": lib.GEOM_RAY_CSG_DIFFERENCE}
        if op not in ops:
            raise ValueError("op must be one of %s, got %r" % (sorted(ops), op))
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_csg(self._s, ops[op], int(a), int(b), idp), idp,
                        "add_csg")

    def add_group(self, ids):
        """One object answering for the nodes ids."""
        a = np.ascontiguousarray(np.asarray(ids).reshape(-1), dtype=np.uint32)
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_group(self._s, ffi.from_buffer("uint32_t[]", a),
                                                     a.size, idp), idp, "add_group")

    def add_instance(self, of, matrix):
        """Instance of node `of` under a 4x4 object-to-world matrix (numpy
        row-major (4, 4), or 16 numbers column-major)."""
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape == (4, 4):
            m = m.T
        idp = ffi.new("uint32_t *")
        return self._id(lib.geom_ray_scene_add_instance(self._s, int(of), self._vec(m, 16, "matrix"),
                                                        idp), idp, "add_instance")

    def set_name(self, node, name):
        check(lib.geom_ray_scene_set_name(self._s, int(node), str(name).encode()),
              context="set_name")

    def find(self, name):
        """Node id of the named node, or None."""
        i = lib.geom_ray_scene_find(self._s, str(name).encode())
        return None if i == 0xFFFFFFFF else int(i)

    def set_objects(self, ids):
        """The top-level objects, in order (hit "object" indexes this list)."""
        a = np.ascontiguousarray(np.asarray(ids).reshape(-1), dtype=np.uint32)
        check(lib.geom_ray_scene_set_objects(self._s, ffi.from_buffer("uint32_t[]", a), a.size),
              context="set_objects")
        self._built = False

    @property
    def node_count(self):
        return int(lib.geom_ray_scene_node_count(self._s))

    @property
    def object_count(self):
        """Top-level objects (after build)."""
        return int(lib.geom_ray_scene_object_count(self._s))

    def object_node(self, i):
        n = lib.geom_ray_scene_object_node(self._s, int(i))
        return None if n == 0xFFFFFFFF else int(n)

    def node_kind(self, node):
        """Kind name of node ("sphere", "mesh", ...; "unknown" out of range)."""
        return ffi.string(lib.geom_ray_kind_name(lib.geom_ray_scene_node_kind(self._s, int(node)))).decode()

    def object_error(self, node):
        """The geometric error report of an approximated node (meshes of
        subdivision surfaces, ...), after build."""
        from .core import error_report
        rep = ffi.new("geom_error_report *")
        check(lib.geom_ray_scene_object_error(self._s, int(node), rep), context="object_error")
        return error_report(rep[0])

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

    def closest(self, origins, directions, tmin=0.0, tmax=np.inf):
        n, single, o, d, t0, t1 = self._rays(origins, directions, tmin, tmax)
        out = {"hit": np.zeros(n, bool), "valid": np.ones(n, bool), "t": np.full(n, np.nan),
               "point": np.full((n, 3), np.nan), "normal": np.full((n, 3), np.nan),
               "shading_normal": np.full((n, 3), np.nan), "uv": np.full((n, 2), np.nan),
               "prim": np.zeros(n, np.int64), "object": np.full(n, -1, np.int64),
               "t_error": np.full(n, np.nan), "enter": np.zeros(n, bool)}
        # one C call over all rays (geom_ray_scene_closest_many: bit for bit
        # geom_ray_scene_closest, a mesh's traversals interleaved)
        rays = self._ray_array(n, o, d, t0, t1)
        hits = ffi.new("geom_ray_hit[]", max(n, 1))
        found = np.zeros(n, dtype=np.intc)
        st = lib.geom_ray_scene_closest_many(self._s, ffi.cast("geom_ray *", ffi.from_buffer(rays)), n,
                                             hits, ffi.cast("int *", ffi.from_buffer(found)))
        if st == lib.GEOM_ERR_INVALID_ARG:  # some rays invalid: which (among the misses)
            out["valid"] = self._valid(rays, np.flatnonzero(found == 0))
        else:
            check(st, context="closest")
        h = np.frombuffer(ffi.buffer(hits), dtype=_hit_dtype())[:n]
        f = found != 0
        out["hit"] = f
        out["t"][f] = h["t"][f]
        out["point"][f] = h["point"][f]
        out["normal"][f] = h["ng"][f]
        out["shading_normal"][f] = h["ns"][f]
        out["uv"][f, 0] = h["u"][f]
        out["uv"][f, 1] = h["v"][f]
        out["prim"][f] = h["prim"][f]
        out["object"][f] = h["object"][f]
        out["t_error"][f] = h["t_error"][f]
        out["enter"][f] = h["enter"][f] != 0
        if single:
            out = {k: v[0] for k, v in out.items()}
        return out

    @staticmethod
    def _ray_array(n, o, d, t0, t1):
        """(n, 8) doubles laid out as n geom_ray (origin, dir, tmin, tmax)."""
        rays = np.empty((n, 8))
        rays[:, 0:3] = o
        rays[:, 3:6] = d
        rays[:, 6] = t0
        rays[:, 7] = t1
        return rays

    def _valid(self, rays, idx):
        """geom_ray_check of the rays idx (the ones a batch left empty)."""
        valid = np.ones(rays.shape[0], bool)
        r = ffi.cast("geom_ray *", ffi.from_buffer(rays))
        for i in idx:
            valid[i] = lib.geom_ray_check(r + int(i)) == 0
        return valid

    def any(self, origins, directions, tmin=0.0, tmax=np.inf):
        """Boolean array: does each ray hit anything in [tmin, tmax]? One C
        call over all rays (geom_ray_scene_any_many: bit for bit
        geom_ray_scene_any); an invalid ray is False."""
        n, single, o, d, t0, t1 = self._rays(origins, directions, tmin, tmax)
        rays = self._ray_array(n, o, d, t0, t1)
        found = np.zeros(n, dtype=np.intc)
        st = lib.geom_ray_scene_any_many(self._s, ffi.cast("geom_ray *", ffi.from_buffer(rays)), n,
                                         ffi.cast("int *", ffi.from_buffer(found)))
        if st != lib.GEOM_ERR_INVALID_ARG:  # INVALID_ARG: some rays invalid (found 0)
            check(st, context="any")
        res = found != 0
        return bool(res[0]) if single else res

    def all(self, origins, directions, tmin=0.0, tmax=np.inf):
        """Every hit of each ray, sorted by t (entering first on ties), in
        one C call (geom_ray_scene_all_many: bit for bit geom_ray_scene_all).

        One ray (1-D origin and direction): a list of dicts (t, point,
        normal, uv, prim, object, enter). Many rays ((k, 3) arrays): a dict
        of flat arrays in compressed rows, the hits of ray i being
        [offsets[i], offsets[i+1]): "offsets" (k+1,), "ray" (the ray of each
        hit), "t", "point", "normal", "shading_normal", "uv", "prim",
        "object", "t_error", "enter", and "valid" (k,) (an invalid ray has
        no hit and valid False)."""
        n, single, o, d, t0, t1 = self._rays(origins, directions, tmin, tmax)
        rays = self._ray_array(n, o, d, t0, t1)
        rp = ffi.cast("geom_ray *", ffi.from_buffer(rays))
        offsets = np.zeros(n + 1, dtype=np.uintp)
        op = ffi.cast("size_t *", ffi.from_buffer(offsets))
        cnt = ffi.new("size_t *")
        cap = max(2 * n, 16)
        while True:
            hits = ffi.new("geom_ray_hit[]", cap)
            st = lib.geom_ray_scene_all_many(self._s, rp, n, op, hits, cap, cnt)
            if st == lib.GEOM_ERR_LIMIT:
                cap = int(cnt[0])
                continue
            break
        if st != lib.GEOM_ERR_INVALID_ARG:
            check(st, context="all")
        total = int(cnt[0])
        h = np.frombuffer(ffi.buffer(hits), dtype=_hit_dtype())[:total]
        offsets = offsets.astype(np.int64)
        if single:
            return [{"t": float(h["t"][i]), "point": tuple(float(x) for x in h["point"][i]),
                     "normal": tuple(float(x) for x in h["ng"][i]),
                     "uv": (float(h["u"][i]), float(h["v"][i])),
                     "prim": int(h["prim"][i]), "object": int(h["object"][i]),
                     "enter": bool(h["enter"][i])}
                    for i in range(total)]
        counts = np.diff(offsets)
        valid = (self._valid(rays, np.flatnonzero(counts == 0)) if st == lib.GEOM_ERR_INVALID_ARG
                 else np.ones(n, bool))
        return {"offsets": offsets, "ray": np.repeat(np.arange(n), counts), "valid": valid,
                "t": h["t"].copy(), "point": h["point"].copy(), "normal": h["ng"].copy(),
                "shading_normal": h["ns"].copy(), "uv": np.stack([h["u"], h["v"]], axis=1),
                "prim": h["prim"].astype(np.int64), "object": h["object"].astype(np.int64),
                "t_error": h["t_error"].copy(), "enter": h["enter"] != 0}


_QUADRICS = {"ellipsoid": 1, "cylinder": 2, "cone": 3, "paraboloid": 4, "hyperboloid1": 5,
             "hyperboloid2": 6}


def quadric(shape, *params):
    """Coefficients (10,) of a standard quadric about the z axis for
    RayScene.add_quadric (geom_ray_quadric_make): "ellipsoid" (rx, ry, rz),
    "cylinder" (r), "cone" (k: x^2 + y^2 = (k z)^2), "paraboloid" (k),
    "hyperboloid1" / "hyperboloid2" (a, c); inside F < 0 is the solid."""
    if shape not in _QUADRICS:
        raise ValueError("shape must be one of %s, got %r" % (sorted(_QUADRICS), shape))
    p = ffi.new("double[3]", [float(x) for x in params[:3]])
    q = ffi.new("double[10]")
    check(lib.geom_ray_quadric_make(_QUADRICS[shape], p, q), context="quadric")
    return np.array(list(q))


def poly_roots(coeffs, lo, hi):
    """The real roots in [lo, hi] (finite) of the polynomial
    coeffs[0] + coeffs[1] x + ... + coeffs[d] x^d, degree d <= 8, sorted,
    a double root (a tangency) listed twice (geom_ray_poly_roots, the
    solver behind the ray module's tori and quadrics): the roots of the
    derivative split [lo, hi] into monotone pieces, a piece whose ends have
    opposite signs holds one root, found by safeguarded Newton/bisection to
    full double precision; a critical point where |p| is within Horner's
    running error bound (Higham 5.1) is a double root. No root with a sign
    change is missed and none is reported where |p| exceeds its error
    bound. Unlike numpy.roots (eigenvalues of the companion matrix), no
    complex roots and no loss of accuracy near multiple roots beyond what
    the coefficients determine. Raises ValueError for a degree above 8,
    non-finite coefficients or bounds, or lo > hi."""
    c = np.ascontiguousarray(coeffs, dtype=np.float64).reshape(-1)
    lo, hi = float(lo), float(hi)
    if c.size < 1 or c.size > 9:
        raise ValueError("poly_roots: 1 to 9 coefficients (degree <= 8), got %d" % c.size)
    if not (np.isfinite(c).all() and np.isfinite(lo) and np.isfinite(hi)):
        raise ValueError("poly_roots: coefficients and bounds must be finite")
    if lo > hi:
        raise ValueError("poly_roots: lo > hi (%r > %r)" % (lo, hi))
    deg = c.size - 1
    roots = np.zeros(max(deg, 1))
    n = lib.geom_ray_poly_roots(ffi.cast("double *", ffi.from_buffer("double[]", c)), deg, lo, hi,
                                ffi.cast("double *", ffi.from_buffer("double[]", roots)))
    return roots[:int(n)].copy()
