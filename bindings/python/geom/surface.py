"""B-spline and NURBS tensor-product surfaces, exact quadrics, Bezier patch
files and crack-free tessellation (geom/surface.h).

A NurbsSurface holds read-only numpy arrays: knots_u, knots_v, points
(nu, nv, 3) (point (i, j): i along u, j along v) and weights (nu, nv) or
None. tessellate() returns a Mesh and the error report of the check against
the exact surfaces.
"""

import os

import numpy as np

from ._ffi import ffi, lib
from .core import GeomError, Progress, check, dptr, error_report, new_diag, struct_dict
from .mesh import Mesh

U_LEFT = 1
V_LEFT = 2
_NORMAL_HOW = {0: "regular", 1: "limit", 2: "none"}
_ATTRS = {"normal": 1, "uv": 2, "tangent": 4, "source": 8}


def _frozen(arr):
    arr = np.ascontiguousarray(arr, dtype=np.float64).copy()
    arr.flags.writeable = False
    return arr


class NurbsSurface:
    """A B-spline (weights None) or NURBS surface: degrees (pu, pv), knots_u
    (nu + pu + 1), knots_v (nv + pv + 1), points (nu, nv, 3), weights
    (nu, nv) or None. Validated with geom_surface_validate unless
    validate=False."""

    def __init__(self, degree_u, degree_v, knots_u, knots_v, points, weights=None,
                 validate=True, name=None, _trusted=False):
        self._pu, self._pv = int(degree_u), int(degree_v)
        self._ku = _frozen(knots_u).reshape(-1)
        self._kv = _frozen(knots_v).reshape(-1)
        pts = np.asarray(points, dtype=np.float64)
        if pts.ndim != 3 or pts.shape[2] != 3:
            raise ValueError("points must have shape (nu, nv, 3), got %s" % (pts.shape,))
        self._points = _frozen(pts)
        nu, nv = pts.shape[:2]
        self._weights = None
        if weights is not None:
            self._weights = _frozen(weights).reshape(nu, nv)
        self.name = name
        s = ffi.new("geom_nurbs_surface *")
        s.degree_u, s.degree_v, s.nu, s.nv = self._pu, self._pv, nu, nv
        self._keep = [ffi.from_buffer("double[]", a) for a in (self._ku, self._kv, self._points)]
        s.knots_u, s.knots_v, s.points = self._keep
        if self._weights is not None:
            self._keep.append(ffi.from_buffer("double[]", self._weights))
            s.weights = self._keep[3]
        self._s = s
        # validate=False is no way around validation (see NurbsCurve): only
        # surfaces made by the library itself (_from_c) skip the O(n) check.
        nku, nkv = nu + self._pu + 1, nv + self._pv + 1
        if not _trusted and (self._ku.size != nku or self._kv.size != nkv):
            raise ValueError("knot counts must be nu + pu + 1 = %d and nv + pv + 1 = %d"
                             % (nku, nkv))
        if not _trusted and self._weights is not None and self._weights.size != nu * nv:
            raise ValueError("need one weight per control point")
        if validate or not _trusted:
            diag = new_diag()
            check(lib.geom_surface_validate(s, diag), diag, context="NurbsSurface")
        if validate and (self._ku.size != nku or self._kv.size != nkv):
            raise ValueError("knot counts must be nu + pu + 1 = %d and nv + pv + 1 = %d"
                             % (nku, nkv))

    @classmethod
    def _from_c(cls, s, name=None):
        nu, nv, pu, pv = int(s.nu), int(s.nv), int(s.degree_u), int(s.degree_v)

        def grab(ptr, count):
            return np.frombuffer(ffi.buffer(ptr, 8 * count), dtype=np.float64)
        pts = grab(s.points, 3 * nu * nv).reshape(nu, nv, 3)
        w = None if s.weights == ffi.NULL else grab(s.weights, nu * nv)
        return cls(pu, pv, grab(s.knots_u, nu + pu + 1), grab(s.knots_v, nv + pv + 1), pts, w,
                   validate=False, name=name, _trusted=True)

    degree_u = property(lambda self: self._pu)
    degree_v = property(lambda self: self._pv)
    knots_u = property(lambda self: self._ku)
    knots_v = property(lambda self: self._kv)
    points = property(lambda self: self._points)
    weights = property(lambda self: self._weights)
    rational = property(lambda self: self._weights is not None)

    def __repr__(self):
        nu, nv = self._points.shape[:2]
        return "<geom.NurbsSurface degrees (%d, %d), %dx%d points%s>" % (
            self._pu, self._pv, nu, nv, ", rational" if self.rational else "")

    @property
    def domain(self):
        """(u0, u1, v0, v1)."""
        d = ffi.new("double[4]")
        check(lib.geom_surface_domain(self._s, d), context="domain")
        return tuple(float(x) for x in d)

    def _uv(self, u, v):
        uu, vv = np.broadcast_arrays(np.asarray(u, dtype=np.float64),
                                     np.asarray(v, dtype=np.float64))
        return uu.reshape(-1), vv.reshape(-1), uu.ndim == 0, uu.shape

    def eval(self, u, v, flags=0):
        """S(u, v): (3,) for scalars, S + (3,) for arrays (broadcast)."""
        us, vs, scalar, shape = self._uv(u, v)
        uv = np.empty((us.size, 2))
        uv[:, 0] = us
        uv[:, 1] = vs
        out = np.empty((us.size, 3))
        puv, po = ffi.from_buffer("double[]", uv), ffi.from_buffer("double[]", out)
        nfail = ffi.new("size_t *")
        # Row statuses only when a row failed (no n int32 writes and no scan).
        check(lib.geom_surface_eval_many(self._s, us.size, puv, flags, 0, po, ffi.NULL, nfail),
              context="eval")
        if nfail[0]:
            status = np.empty(us.size, dtype=np.int32)
            lib.geom_surface_eval_many(self._s, us.size, puv, flags, 0, po,
                                       ffi.from_buffer("int32_t[]", status), ffi.NULL)
            i = int(np.nonzero(status)[0][0])
            check(int(status[i]), context="eval(%r, %r)" % (us[i], vs[i]))
        return out[0] if scalar else out.reshape(shape + (3,))

    __call__ = eval

    def derivs(self, u, v, d=1, flags=0):
        """All partial derivatives S^(k,l), k + l <= d, at scalar (u, v):
        a (d + 1, d + 1, 3) array, entry [k, l] = d^(k+l) S / du^k dv^l
        (zero where k + l > d)."""
        out = np.zeros((d + 1, d + 1, 3))
        check(lib.geom_surface_derivs(self._s, float(u), float(v), int(d), flags, dptr(out)),
              context="derivs")
        return out

    def normal(self, u, v, flags=0, return_how=False):
        """Unit normal along Su x Sv, defined at degenerate points too (poles,
        apexes) as the limit; (0, 0, 0) where the surface is a single point.
        Shapes as eval(). return_how=True also returns, per point, "regular",
        "limit" or "none"."""
        us, vs, scalar, shape = self._uv(u, v)
        out = np.zeros((us.size, 3))
        po = ffi.from_buffer("double[]", out)
        how = ffi.new("int *")
        hows = []
        for i in range(us.size):
            st = lib.geom_surface_normal(self._s, us[i], vs[i], flags, po + 3 * i, how)
            if st != 0 and st != lib.GEOM_ERR_DEGENERATE:
                check(st, context="normal(%r, %r)" % (us[i], vs[i]))
            hows.append(_NORMAL_HOW.get(how[0], "none"))
        res = out[0] if scalar else out.reshape(shape + (3,))
        if return_how:
            return res, (hows[0] if scalar else np.array(hows).reshape(shape))
        return res

    # ------------------------------------------------------ constructors

    @classmethod
    def bezier(cls, points, weights=None):
        """A Bezier patch from (pu + 1, pv + 1, 3) control points."""
        pts = np.ascontiguousarray(points, dtype=np.float64)
        pu, pv = pts.shape[0] - 1, pts.shape[1] - 1
        ku, kv = np.zeros(2 * pu + 2), np.zeros(2 * pv + 2)
        w = None if weights is None else np.ascontiguousarray(weights, dtype=np.float64)
        out = ffi.new("geom_nurbs_surface *")
        check(lib.geom_surface_bezier(pu, pv, dptr(pts), dptr(w) if w is not None else ffi.NULL,
                                      dptr(ku), dptr(kv), out), context="bezier")
        return cls._from_c(out)

    @classmethod
    def bilinear(cls, p00, p10, p01, p11):
        """The bilinear patch through four corners."""
        ku, kv, pts = np.zeros(4), np.zeros(4), np.zeros(12)
        c = [np.ascontiguousarray(p, dtype=np.float64).reshape(3) for p in (p00, p10, p01, p11)]
        out = ffi.new("geom_nurbs_surface *")
        check(lib.geom_surface_bilinear(*[dptr(x) for x in c], dptr(ku), dptr(kv), dptr(pts), out),
              context="bilinear")
        return cls._from_c(out)

    @classmethod
    def sphere(cls, radius, center=(0, 0, 0), zaxis=(0, 0, 1), xaxis=(1, 0, 0)):
        """The exact NURBS sphere (degrees 2 x 2, 9 x 5 points)."""
        return cls._quadric(lib.geom_surface_sphere, (radius,), 9, 5, 12, 8,
                            center, zaxis, xaxis, "sphere")

    @classmethod
    def cylinder(cls, radius, height, center=(0, 0, 0), zaxis=(0, 0, 1), xaxis=(1, 0, 0)):
        """The exact circular cylinder along +z of the frame."""
        return cls._quadric(lib.geom_surface_cylinder, (radius, height), 9, 2, 12, 4,
                            center, zaxis, xaxis, "cylinder")

    @classmethod
    def cone(cls, r0, r1, height, center=(0, 0, 0), zaxis=(0, 0, 1), xaxis=(1, 0, 0)):
        """The exact cone (frustum) with radius r0 at v = 0 and r1 at v = 1."""
        return cls._quadric(lib.geom_surface_cone, (r0, r1, height), 9, 2, 12, 4,
                            center, zaxis, xaxis, "cone")

    @classmethod
    def torus(cls, major_radius, minor_radius, center=(0, 0, 0), zaxis=(0, 0, 1),
              xaxis=(1, 0, 0)):
        """The exact torus about the frame's z axis (degrees 2 x 2, 9 x 9)."""
        return cls._quadric(lib.geom_surface_torus, (major_radius, minor_radius), 9, 9, 12, 12,
                            center, zaxis, xaxis, "torus")

    @classmethod
    def extrude(cls, curve, direction):
        """The extrusion of a NurbsCurve (dim 3) along direction: S(u, v) =
        C(u) + v d, v in [0, 1] (exact; rational when the curve is)."""
        d = np.ascontiguousarray(direction, dtype=np.float64).reshape(3)
        n = curve.n
        ku, kv = np.zeros(curve.knots.size), np.zeros(4)
        pts, w = np.zeros(n * 2 * 3), (np.zeros(n * 2) if curve.rational else None)
        out = ffi.new("geom_nurbs_surface *")
        diag = new_diag()
        check(lib.geom_surface_extrude(curve._c, dptr(d), dptr(ku), dptr(kv), dptr(pts),
                                       dptr(w) if w is not None else ffi.NULL, out, diag), diag,
              context="extrude")
        return cls._from_c(out)

    @classmethod
    def ruled(cls, c0, c1):
        """The ruled surface (1-v) C0(u) + v C1(u) between two NurbsCurves
        (made compatible: same degree and knots; u normalised to [0, 1])."""
        nu, nk = ffi.new("size_t *"), ffi.new("size_t *")
        check(lib.geom_surface_ruled_bound(c0._c, c1._c, nu, nk), context="ruled")
        ku, kv = np.zeros(nk[0]), np.zeros(4)
        pts = np.zeros(nu[0] * 2 * 3)
        w = np.zeros(nu[0] * 2) if (c0.rational or c1.rational) else None
        out = ffi.new("geom_nurbs_surface *")
        diag = new_diag()
        check(lib.geom_surface_ruled(c0._c, c1._c, dptr(ku), dptr(kv), dptr(pts),
                                     dptr(w) if w is not None else ffi.NULL, out, diag), diag,
              context="ruled")
        return cls._from_c(out)

    @classmethod
    def revolve(cls, profile, origin=(0, 0, 0), axis=(0, 0, 1), angle=2 * np.pi, xaxis=None):
        """The exact surface of revolution (A8.1) of a profile NurbsCurve
        (2-D: (radius, height) in the half-plane of xaxis and axis; or 3-D)
        about the axis through origin, sweeping angle radians."""
        o = np.ascontiguousarray(origin, dtype=np.float64).reshape(3)
        a = np.ascontiguousarray(axis, dtype=np.float64).reshape(3)
        xa = None if xaxis is None else np.ascontiguousarray(xaxis, dtype=np.float64).reshape(3)
        nu, nk = ffi.new("size_t *"), ffi.new("size_t *")
        check(lib.geom_surface_revolve_bound(float(angle), nu, nk), context="revolve")
        n = profile.n
        ku, kv = np.zeros(nk[0]), np.zeros(n + profile.degree + 1)
        pts, w = np.zeros(nu[0] * n * 3), np.zeros(nu[0] * n)
        out = ffi.new("geom_nurbs_surface *")
        diag = new_diag()
        check(lib.geom_surface_revolve(profile._c, dptr(o), dptr(a),
                                       dptr(xa) if xa is not None else ffi.NULL, float(angle),
                                       dptr(ku), dptr(kv), dptr(pts), dptr(w), out, diag), diag,
              context="revolve")
        return cls._from_c(out)

    @classmethod
    def _quadric(cls, fn, args, nu, nv, nku, nkv, center, zaxis, xaxis, what):
        frame = ffi.new("geom_surface_frame *")
        frame.center = [float(x) for x in np.asarray(center, dtype=np.float64).reshape(3)]
        frame.zaxis = [float(x) for x in np.asarray(zaxis, dtype=np.float64).reshape(3)]
        frame.xaxis = [float(x) for x in np.asarray(xaxis, dtype=np.float64).reshape(3)]
        ku, kv = np.zeros(nku), np.zeros(nkv)
        pts, w = np.zeros(3 * nu * nv), np.zeros(nu * nv)
        out = ffi.new("geom_nurbs_surface *")
        check(fn(frame, *args, dptr(ku), dptr(kv), dptr(pts), dptr(w), out), context=what)
        return cls._from_c(out)


def read_bpt(path_or_bytes, source_name=None):
    """Bezier patches from a .bpt file (Newell's teapot format): a list of
    bicubic NurbsSurface. Accepts a path or the file's bytes."""
    out = ffi.new("geom_surface_set **")
    diag = new_diag()
    if isinstance(path_or_bytes, (bytes, bytearray, memoryview)):
        data = bytes(path_or_bytes)
        name = ffi.NULL if source_name is None else str(source_name).encode()
        st = lib.geom_surface_read_bpt_memory(data, len(data), name, ffi.NULL, out, diag)
    else:
        st = lib.geom_surface_read_bpt(os.fsencode(os.fspath(path_or_bytes)), ffi.NULL, out, diag)
    check(st, diag, context="read_bpt")
    sset = ffi.gc(out[0], lib.geom_surface_set_destroy)
    try:
        n = lib.geom_surface_set_count(sset)
        views = lib.geom_surface_set_data(sset)
        res = []
        for i in range(n):
            nm = lib.geom_surface_set_name(sset, i)
            res.append(NurbsSurface._from_c(views[i], name=ffi.string(nm).decode() or None))
        return res
    finally:
        ffi.release(sset)


class SurfaceJSONError(ValueError):
    """A surface JSON file that does not describe valid curves and surfaces:
    the message names the source, the entry and the key (as the tools'
    reader, tools/surface_json.h, does), e.g.
    'x.json: surfaces[1] ("torus"): "knots_v": 10 knots, 12 expected'."""


def _json_num_array(value, where, key, ndim):
    def numbers(v):
        if isinstance(v, list):
            return all(numbers(x) for x in v)
        return isinstance(v, (int, float)) and not isinstance(v, bool)
    if not isinstance(value, list) or not numbers(value):
        raise SurfaceJSONError('%s: "%s": not an array of numbers' % (where, key))
    try:
        out = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise SurfaceJSONError('%s: "%s": ragged array' % (where, key)) from None
    if out.ndim != ndim:
        raise SurfaceJSONError('%s: "%s": expected a %d-dimensional array, got shape %s'
                               % (where, key, ndim, out.shape))
    if not np.all(np.isfinite(out)):
        raise SurfaceJSONError('%s: "%s": non-finite number' % (where, key))
    return out


def _json_int(entry, key, where, default=None):
    v = entry.get(key, default)
    if v is None:
        raise SurfaceJSONError('%s: missing "%s"' % (where, key))
    if isinstance(v, bool) or not isinstance(v, (int, float)) or v != int(v) or v < 1:
        raise SurfaceJSONError('%s: "%s": a positive integer, not %r' % (where, key, v))
    return int(v)


def _json_surface(entry, where):
    kind = entry.get("type")
    if kind not in ("bezier", "bspline", "nurbs"):
        raise SurfaceJSONError('%s: "type": unknown surface type %r (bezier, bspline, nurbs)'
                               % (where, kind))
    if "points" not in entry:
        raise SurfaceJSONError('%s: missing "points"' % where)
    P = _json_num_array(entry["points"], where, "points", 3)
    if P.shape[2] != 3 or P.shape[0] < 1 or P.shape[1] < 1:
        raise SurfaceJSONError('%s: "points": expected points[i][j] of 3 numbers, got shape %s'
                               % (where, P.shape))
    nu, nv = P.shape[:2]
    W = None
    if entry.get("weights") is not None:
        W = _json_num_array(entry["weights"], where, "weights", 2)
        if W.shape != (nu, nv):
            raise SurfaceJSONError('%s: "weights": shape %s, %s expected (one per point)'
                                   % (where, W.shape, (nu, nv)))
    if kind == "bezier":
        pu, pv = nu - 1, nv - 1
        for key, p in (("degree_u", pu), ("degree_v", pv)):
            if key in entry and _json_int(entry, key, where) != p:
                raise SurfaceJSONError('%s: "%s": %r, but the points make degree %d'
                                       % (where, key, entry[key], p))
        if pu < 1 or pv < 1:
            raise SurfaceJSONError('%s: "points": a Bezier patch needs 2 points or more '
                                   'along u and v' % where)
        ku = [0.0] * (pu + 1) + [1.0] * (pu + 1)
        kv = [0.0] * (pv + 1) + [1.0] * (pv + 1)
    else:
        pu, pv = _json_int(entry, "degree_u", where), _json_int(entry, "degree_v", where)
        ku, kv = [], []
        for key, n, p, out in (("knots_u", nu, pu, ku), ("knots_v", nv, pv, kv)):
            if key not in entry:
                raise SurfaceJSONError('%s: missing "%s"' % (where, key))
            k = _json_num_array(entry[key], where, key, 1)
            if k.size != n + p + 1:
                raise SurfaceJSONError('%s: "%s": %d knots, %d expected (n%s + degree%s + 1)'
                                       % (where, key, k.size, n + p + 1, key[-2:], key[-2:]))
            out.extend(k.tolist())
    try:
        return NurbsSurface(pu, pv, ku, kv, P, W, name=entry.get("name"))
    except GeomError as e:
        raise SurfaceJSONError("%s: %s" % (where, e)) from None


def _json_curve(entry, where):
    from .curve import NurbsCurve
    kind = entry.get("type")
    if kind in ("hermite", "catmull_rom", "kochanek_bartels"):
        return _json_cubic_spline(entry, where, kind)
    if kind not in ("bezier", "bspline", "nurbs"):
        raise SurfaceJSONError('%s: "type": unknown curve type %r (bezier, bspline, nurbs, '
                               'hermite, catmull_rom, kochanek_bartels)' % (where, kind))
    if "points" not in entry:
        raise SurfaceJSONError('%s: missing "points"' % where)
    P = _json_num_array(entry["points"], where, "points", 2)
    if P.shape[1] not in (2, 3) or P.shape[0] < 2:
        raise SurfaceJSONError('%s: "points": 2 or more points of 2 or 3 numbers expected, got '
                               'shape %s' % (where, P.shape))
    n = P.shape[0]
    W = None
    if entry.get("weights") is not None:
        W = _json_num_array(entry["weights"], where, "weights", 1)
        if W.size != n:
            raise SurfaceJSONError('%s: "weights": %d weights for %d points' % (where, W.size, n))
    if kind == "bezier":
        p = n - 1
        if "degree" in entry and _json_int(entry, "degree", where) != p:
            raise SurfaceJSONError('%s: "degree": %r, but %d points make degree %d'
                                   % (where, entry["degree"], n, p))
        knots = [0.0] * (p + 1) + [1.0] * (p + 1)
    else:
        p = _json_int(entry, "degree", where)
        if "knots" not in entry:
            raise SurfaceJSONError('%s: missing "knots"' % where)
        k = _json_num_array(entry["knots"], where, "knots", 1)
        if k.size != n + p + 1:
            raise SurfaceJSONError('%s: "knots": %d knots, %d expected (n + degree + 1)'
                                   % (where, k.size, n + p + 1))
        knots = k.tolist()
    try:
        return NurbsCurve(p, knots, P, W)
    except GeomError as e:
        raise SurfaceJSONError("%s: %s" % (where, e)) from None


def _json_cubic_spline(entry, where, kind):
    """Hermite, Catmull-Rom and Kochanek-Bartels splines as the C library's
    exact piecewise cubic Bezier form, a clamped cubic B-spline with double
    interior knots (as tools/surface_json.c builds them)."""
    from .curve import NurbsCurve
    if "points" not in entry:
        raise SurfaceJSONError('%s: missing "points"' % where)
    P = np.ascontiguousarray(_json_num_array(entry["points"], where, "points", 2))
    if P.shape[1] not in (2, 3) or P.shape[0] < 2:
        raise SurfaceJSONError('%s: "points": 2 or more points of 2 or 3 numbers expected, got '
                               'shape %s' % (where, P.shape))
    n, dim = P.shape
    params = None
    diag = new_diag()
    if kind == "hermite":
        if "tangents" not in entry:
            raise SurfaceJSONError('%s: missing "tangents"' % where)
        Tn = np.ascontiguousarray(_json_num_array(entry["tangents"], where, "tangents", 2))
        if Tn.shape != P.shape:
            raise SurfaceJSONError('%s: "tangents": shape %s, %s expected (one per point)'
                                   % (where, Tn.shape, P.shape))
        if entry.get("params") is not None:
            params = np.ascontiguousarray(_json_num_array(entry["params"], where, "params", 1))
            if params.size != n:
                raise SurfaceJSONError('%s: "params": %d values for %d points'
                                       % (where, params.size, n))
        nseg = n - 1
        bez = np.empty((3 * nseg + 1, dim))
        st = lib.geom_curve_hermite_spline_to_bezier(
            dim, n, dptr(P), dptr(Tn), dptr(params) if params is not None else ffi.NULL,
            dptr(bez))
        if st != 0:
            raise SurfaceJSONError('%s: "params": must be strictly increasing' % where)
    else:
        closed = entry.get("closed", False)
        if not isinstance(closed, bool):
            raise SurfaceJSONError('%s: "closed": true or false, not %r' % (where, closed))
        ends = lib.GEOM_CURVE_END_CLOSED if closed else lib.GEOM_CURVE_END_EXTRAPOLATE
        pn = ffi.new("size_t *")
        if lib.geom_curve_catmull_rom_segments(n, ends, pn) != 0:
            raise SurfaceJSONError('%s: "points": %d points are too few%s'
                                   % (where, n, " for a closed curve (3 needed)" if closed else ""))
        nseg = int(pn[0])
        bez = np.empty((3 * nseg + 1, dim))
        if kind == "catmull_rom":
            alpha = entry.get("alpha", 0.5)
            if isinstance(alpha, bool) or not isinstance(alpha, (int, float)) or \
                    not 0.0 <= alpha <= 1.0:
                raise SurfaceJSONError('%s: "alpha": %r is not in [0, 1]' % (where, alpha))
            params = np.empty(nseg + 1)
            st = lib.geom_curve_catmull_rom_to_bezier(dim, n, dptr(P), float(alpha), ends,
                                                      dptr(bez), dptr(params), diag)
        else:
            tcb = ffi.new("geom_kb_params[]", n)
            for key in ("tension", "continuity", "bias"):
                v = entry.get(key, 0.0)
                vals = v if isinstance(v, list) else [v] * n
                if len(vals) != n or any(isinstance(x, bool) or not isinstance(x, (int, float))
                                         for x in vals):
                    raise SurfaceJSONError('%s: "%s": a number or a list of %d numbers'
                                           % (where, key, n))
                for i, x in enumerate(vals):
                    setattr(tcb[i], key, float(x))
            st = lib.geom_curve_kochanek_bartels_to_bezier(dim, n, dptr(P), tcb, n, ends,
                                                           dptr(bez), diag)
        if st != 0:
            raise SurfaceJSONError('%s: "points": %s'
                                   % (where, ffi.string(diag.message).decode(errors="replace")))
    knots = np.empty(3 * nseg + 3 + 2)
    st = lib.geom_curve_piecewise_bezier_knots(3, nseg, dptr(params) if params is not None
                                               else ffi.NULL, dptr(knots))
    if st != 0:
        raise SurfaceJSONError('%s: cannot build the knots (%d)' % (where, st))
    return NurbsCurve(3, knots, bez)


def read_json(path_or_text, source_name=None):
    """Curves and surfaces from a surface JSON file (the format geom-tessellate
    and geom-curve read: {"curves": [...], "surfaces": [...]}, see
    docs/formats.md), parsed with Python's json module and built through the
    C API (geom_surface_validate / geom_curve_validate check every entry).

    path_or_text: a path, or the JSON text itself (str starting with "{" or "[", or
    bytes). Returns {"curves": [NurbsCurve], "surfaces": [NurbsSurface]}
    (names kept as NurbsSurface.name). Hermite, Catmull-Rom and
    Kochanek-Bartels curves become their exact piecewise cubic Bezier form
    as clamped cubic B-splines, as in the tools. Errors raise
    SurfaceJSONError naming the source, the
    entry and the key (JSON syntax errors: line and column)."""
    import json
    if isinstance(path_or_text, bytes):
        text, src = path_or_text.decode("utf-8"), source_name or "<bytes>"
    elif isinstance(path_or_text, str) and path_or_text.lstrip()[:1] in ("{", "["):
        text, src = path_or_text, source_name or "<string>"
    else:
        path = os.fspath(path_or_text)
        if "\0" in path:
            raise ValueError("path contains a NUL character")
        with open(path, "r", encoding="utf-8-sig") as fh:
            text = fh.read()
        src = source_name or path
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise SurfaceJSONError("%s:%d:%d: JSON syntax error: %s" % (src, e.lineno, e.colno, e.msg)) \
            from None
    if not isinstance(doc, dict):
        raise SurfaceJSONError("%s: expected an object {\"curves\": [...], \"surfaces\": [...]}"
                               % src)
    out = {"curves": [], "surfaces": []}
    for key, build in (("curves", _json_curve), ("surfaces", _json_surface)):
        entries = doc.get(key, [])
        if not isinstance(entries, list):
            raise SurfaceJSONError('%s: "%s": expected a list' % (src, key))
        for i, entry in enumerate(entries):
            where = "%s: %s[%d]" % (src, key, i)
            if not isinstance(entry, dict):
                raise SurfaceJSONError("%s: expected an object" % where)
            if isinstance(entry.get("name"), str):
                where += ' ("%s")' % entry["name"]
            out[key].append(build(entry, where))
    return out


def _surface_array(surfaces):
    if isinstance(surfaces, NurbsSurface):
        surfaces = [surfaces]
    surfaces = list(surfaces)
    arr = ffi.new("geom_nurbs_surface[]", len(surfaces))
    for i, s in enumerate(surfaces):
        arr[i] = s._s[0]
    return surfaces, arr


def _tess_options(tolerance, mode, grid, per_surface, angle_degrees, attributes, uv_normalized,
                  no_weld, keep_orientation, check_subdivisions, max_triangles,
                  normal_weld_degrees):
    opt = ffi.new("geom_surface_tess_options *")
    opt.mode = {"adaptive": 0, "uniform": 1}[mode]
    opt.tolerance = tolerance
    opt.angle_degrees = angle_degrees
    opt.grid_u, opt.grid_v = int(grid[0]), int(grid[1])
    opt.per_surface = 1 if per_surface else 0
    bits = 0
    for a in attributes:
        bits |= _ATTRS[a]
    opt.attributes = bits
    opt.uv_normalized = 1 if uv_normalized else 0
    opt.no_weld = 1 if no_weld else 0
    opt.keep_orientation = 1 if keep_orientation else 0
    opt.check_subdivisions = int(check_subdivisions)
    opt.max_triangles = int(max_triangles)
    opt.normal_weld_degrees = float(normal_weld_degrees)
    return opt


def tess_estimate(surfaces, tolerance=0.0, mode="adaptive", grid=(8, 8), per_surface=False,
                  angle_degrees=0.0):
    """The triangles tessellate(surfaces, ...) would make with these
    options, before the work (geom_surface_tess_estimate): in uniform mode
    an upper bound, exact unless cells collapse (a sphere's pole triangles
    are counted but not made); within about a factor 2 in adaptive mode
    (not a bound)."""
    surfaces, arr = _surface_array(surfaces)
    opt = _tess_options(tolerance, mode, grid, per_surface, angle_degrees, (), False, False,
                        False, 0, 0, 0.0)
    out = ffi.new("double *")
    check(lib.geom_surface_tess_estimate(arr, len(surfaces), opt, out), context="tess_estimate")
    return float(out[0])


def tessellate(surfaces, tolerance=0.0, mode="adaptive", grid=(8, 8), per_surface=False,
               angle_degrees=0.0, attributes=("normal", "uv"), uv_normalized=False,
               no_weld=False, keep_orientation=False, check_subdivisions=0, max_triangles=0,
               normal_weld_degrees=0.0, progress=None):
    """Crack-free triangulation of one NurbsSurface or a list of them
    (geom_surface_tessellate), welded along shared boundaries.

    mode "adaptive": each cell's grid sized to the chordal `tolerance`
    (0: 1e-3 of the control box diagonal), then checked against the exact
    surface and refined; "uniform": grid = (quads along u, along v) per knot
    span (per surface with per_surface=True). attributes: corner channels
    among "normal", "uv", "tangent", and "source" (a face channel with the
    surface index). normal_weld_degrees: the corner normals of a vertex
    within this angle become one (0: the library's default, 0.01 degree;
    negative: never). progress: a callable given the fraction (0..1] of
    each pass's cells done (adaptive tessellation runs several passes; see
    geom_surface_tess_options.progress); an exception it raises is raised
    after the tessellation.

    Returns (mesh, report): report has the sampled error against the exact
    surfaces (max_error, mean_error, method, evaluations) and the
    tessellation statistics under "stats". The error is the distance from
    surface points sampled over each triangle's parameter image to the mesh
    there (a one-sided Hausdorff distance at the samples, never more than
    the distance at equal parameters), so an uneven parametrisation (e.g.
    extreme rational weights) is not counted as error. Adaptive mode never
    returns more triangles than the per-span uniform grid (gu x gv on every
    knot span) with the fewest triangles that meets the tolerance: when one
    has fewer, it is returned, and stats "uniform_u", "uniform_v" name it
    (0 otherwise). See geom_surface_tessellate in geom/surface.h.
    """
    surfaces, arr = _surface_array(surfaces)
    opt = _tess_options(tolerance, mode, grid, per_surface, angle_degrees, attributes,
                        uv_normalized, no_weld, keep_orientation, check_subdivisions,
                        max_triangles, normal_weld_degrees)
    prog = Progress(progress)
    prog.install(opt)
    mesh = Mesh()
    rep = ffi.new("geom_error_report *")
    stats = ffi.new("geom_surface_tess_stats *")
    diag = new_diag()
    st = lib.geom_surface_tessellate(arr, len(surfaces), opt, mesh._ptr, rep, stats, diag)
    if st != 0:
        mesh.close()
        check(st, diag, context="tessellate")
    if prog.error is not None:
        mesh.close()
        prog.reraise()
    report = error_report(rep)
    report["stats"] = struct_dict(stats[0], "geom_surface_tess_stats")
    del surfaces
    return mesh, report


__all__ = ["NurbsSurface", "SurfaceJSONError", "read_bpt", "read_json", "tessellate",
           "tess_estimate"]
