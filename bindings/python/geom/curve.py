"""B-spline and NURBS curves, Bezier curves and exact circles (geom/curve.h).

A NurbsCurve holds numpy arrays (knots, points (n, dim), optional weights
(n,)) and hands them to the C functions without copying; the arrays are
read-only so the curve stays consistent. Points are Euclidean (not
multiplied by the weights). Evaluation follows the C rules at knots: right
limits inside the domain unless left=True; wrap=True reduces the parameter
modulo the domain (periodic curves).

Approximating functions (arc_length, polyline) return their result together
with the error report of the C library (max_error, mean_error, method,
evaluations).
"""

import numpy as np

from ._ffi import ffi, lib
from .core import check, dptr, error_report, new_diag

LEFT_LIMIT = 1
WRAP = 2
_KNOT_KINDS = {"clamped": 0, "unclamped": 1, "periodic": 2}
_POLY_METHODS = {"bound": 1, "sampled": 2}


def _flags(left, wrap):
    return (LEFT_LIMIT if left else 0) | (WRAP if wrap else 0)


def _frozen(arr):
    arr = np.ascontiguousarray(arr, dtype=np.float64).copy()
    arr.flags.writeable = False
    return arr


def _params(u):
    arr = np.asarray(u, dtype=np.float64)
    return arr.reshape(-1), arr.ndim == 0, arr.shape


class NurbsCurve:
    """A B-spline (weights None) or NURBS curve of any degree >= 1 in 1 to 4
    dimensions: degree, knots (n + degree + 1), points (n, dim), weights
    (n,) or None. The curve is validated (geom_curve_nurbs_validate) unless
    validate=False; GeomError ERR_INVALID_ARG names the first problem."""

    def __init__(self, degree, knots, points, weights=None, validate=True, _trusted=False):
        self._degree = int(degree)
        self._knots = _frozen(knots).reshape(-1)
        pts = np.asarray(points, dtype=np.float64)
        if pts.ndim == 1:
            pts = pts.reshape(-1, 1)
        if pts.ndim != 2:
            raise ValueError("points must have shape (n, dim)")
        self._points = _frozen(pts)
        self._weights = None if weights is None else _frozen(weights).reshape(-1)
        if self._weights is not None and self._weights.size != self._points.shape[0]:
            raise ValueError("need one weight per control point")
        self._c = ffi.new("geom_nurbs_curve *")
        self._c.degree = self._degree
        self._c.n = self._points.shape[0]
        self._c.dim = self._points.shape[1]
        self._keep = [ffi.from_buffer("double[]", a) for a in (self._knots, self._points)]
        self._c.knots = self._keep[0]
        self._c.points = self._keep[1]
        if self._weights is not None:
            self._keep.append(ffi.from_buffer("double[]", self._weights))
            self._c.weights = self._keep[2]
        # validate=False is no way around validation: the C check is O(n) and
        # guards every later call against reading past the arrays; only
        # curves made by the library itself (_from_c) skip it.
        if validate or not _trusted:
            diag = new_diag()
            check(lib.geom_curve_nurbs_validate(self._c, self._knots.size, diag), diag,
                  context="NurbsCurve")

    @classmethod
    def _from_c(cls, c, nknots):
        n, dim = int(c.n), int(c.dim)
        knots = np.frombuffer(ffi.buffer(c.knots, 8 * nknots), dtype=np.float64)
        pts = np.frombuffer(ffi.buffer(c.points, 8 * n * dim), dtype=np.float64).reshape(n, dim)
        w = None
        if c.weights != ffi.NULL:
            w = np.frombuffer(ffi.buffer(c.weights, 8 * n), dtype=np.float64)
        return cls(c.degree, knots, pts, w, validate=False, _trusted=True)

    degree = property(lambda self: self._degree)
    knots = property(lambda self: self._knots)
    points = property(lambda self: self._points)
    weights = property(lambda self: self._weights)
    dim = property(lambda self: self._points.shape[1])
    n = property(lambda self: self._points.shape[0])
    rational = property(lambda self: self._weights is not None)

    def __repr__(self):
        return "<geom.NurbsCurve degree %d, %d points in %dD%s>" % (
            self.degree, self.n, self.dim, ", rational" if self.rational else "")

    @property
    def domain(self):
        """(u0, u1): the parameter domain [u_p, u_n]."""
        a, b = ffi.new("double *"), ffi.new("double *")
        check(lib.geom_curve_nurbs_domain(self._c, a, b), context="domain")
        return float(a[0]), float(b[0])

    def eval(self, u, left=False, wrap=False):
        """The point at u (a scalar gives (dim,), an array of shape S gives
        S + (dim,)). GeomError ERR_DOMAIN outside the domain unless wrap."""
        us, scalar, shape = _params(u)
        dim = self.dim
        out = np.empty((us.size, dim))
        uc = np.ascontiguousarray(us, dtype=np.float64)
        pu, po = ffi.from_buffer("double[]", uc), ffi.from_buffer("double[]", out)
        nfail = ffi.new("size_t *")
        fl = _flags(left, wrap)
        # Row statuses are asked for only when some row failed (no n int32
        # writes and no scan on the common path).
        check(lib.geom_curve_nurbs_eval_many(self._c, uc.size, pu, fl, po, ffi.NULL, nfail),
              context="eval")
        if nfail[0]:
            status = np.empty(us.size, dtype=np.int32)
            lib.geom_curve_nurbs_eval_many(self._c, uc.size, pu, fl, po,
                                           ffi.from_buffer("int32_t[]", status), ffi.NULL)
            bad = np.nonzero(status)[0]
            check(int(status[bad[0]]), context="eval(%r)" % float(uc[bad[0]]))
        return out[0] if scalar else out.reshape(shape + (dim,))

    __call__ = eval

    def derivs(self, u, n=1, left=False, wrap=False):
        """Point and derivatives 0..n at u: (n + 1, dim) for a scalar u,
        S + (n + 1, dim) for an array."""
        us, scalar, shape = _params(u)
        dim = self.dim
        k = (n + 1) * dim
        out = np.zeros((us.size, n + 1, dim))
        po = ffi.from_buffer("double[]", out)
        fl = _flags(left, wrap)
        for i, x in enumerate(us):
            check(lib.geom_curve_nurbs_derivs(self._c, x, int(n), fl, po + k * i),
                  context="derivs(%r)" % x)
        return out[0] if scalar else out.reshape(shape + (n + 1, dim))

    def curvature(self, u, left=False):
        """Curvature at u (signed in 2D: positive turning counter-clockwise)
        and, for 3D curves, torsion: returns (curvature, torsion) with
        torsion None for other dimensions; arrays for an array u."""
        us, scalar, shape = _params(u)
        want_t = self.dim == 3
        kap = np.zeros(us.size)
        tor = np.zeros(us.size)
        k, t = ffi.new("double *"), ffi.new("double *")
        for i, x in enumerate(us):
            check(lib.geom_curve_nurbs_curvature(self._c, x, _flags(left, False), k,
                                                 t if want_t else ffi.NULL),
                  context="curvature(%r)" % x)
            kap[i] = k[0]
            tor[i] = t[0]
        if scalar:
            return float(kap[0]), (float(tor[0]) if want_t else None)
        return kap.reshape(shape), (tor.reshape(shape) if want_t else None)

    def arc_length(self, u0=None, u1=None, rel_tol=0.0):
        """Arc length over [u0, u1] (default: the domain) by adaptive
        Gauss-Legendre quadrature: returns (length, report) with the error
        estimate in report["max_error"]."""
        a, b = self.domain
        u0 = a if u0 is None else u0
        u1 = b if u1 is None else u1
        length = ffi.new("double *")
        rep = ffi.new("geom_error_report *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_arc_length(self._c, u0, u1, rel_tol, length, rep, diag), diag,
              context="arc_length")
        return float(length[0]), error_report(rep)

    def closest_point(self, q):
        """Global closest point to q (dim,): returns (u, point, distance)."""
        qq = np.ascontiguousarray(q, dtype=np.float64).reshape(-1)
        if qq.size != self.dim:
            raise ValueError("q must have %d coordinates" % self.dim)
        u, d = ffi.new("double *"), ffi.new("double *")
        pt = np.zeros(self.dim)
        diag = new_diag()
        check(lib.geom_curve_nurbs_closest_point(self._c, dptr(qq), u, dptr(pt), d, diag), diag,
              context="closest_point")
        return float(u[0]), pt, float(d[0])

    def polyline(self, tolerance=0.0, method="bound", max_points=0):
        """Adaptive polyline within `tolerance` of the curve (0: 1e-3 of the
        control box's diagonal); method "bound" guarantees it, "sampled"
        measures at samples. Returns (params (k,), points (k, dim), report)."""
        opt = ffi.new("geom_curve_polyline_options *")
        opt.tolerance = tolerance
        opt.method = _POLY_METHODS[method]
        opt.max_points = max_points
        count = ffi.new("size_t *")
        rep = ffi.new("geom_error_report *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_polyline(self._c, opt, ffi.NULL, ffi.NULL, 0, count, rep, diag),
              diag, context="polyline")
        k = int(count[0])
        params = np.zeros(k)
        pts = np.zeros((k, self.dim))
        check(lib.geom_curve_nurbs_polyline(self._c, opt, dptr(params), dptr(pts), k, count, rep,
                                            diag), diag, context="polyline")
        return params, pts, error_report(rep)

    def polyline_estimate(self, tolerance=0.0, method="bound"):
        """The number of points polyline(tolerance, method) would return,
        estimated before the work (geom_curve_nurbs_polyline_estimate):
        returns (count, is_bound). For a polynomial curve count (a float: it
        may be huge) is an upper bound (is_bound True); for a rational one an
        estimate (is_bound False)."""
        opt = ffi.new("geom_curve_polyline_options *")
        opt.tolerance = tolerance
        opt.method = _POLY_METHODS[method]
        count = ffi.new("double *")
        bound = ffi.new("int *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_polyline_estimate(self._c, opt, count, bound, diag), diag,
              context="polyline_estimate")
        return float(count[0]), bool(bound[0])

    def insert_knot(self, u, times=1):
        """The same curve with the knot u inserted `times` times (A5.1)."""
        n, p, dim = self.n, self.degree, self.dim
        knots = np.zeros(self._knots.size + times)
        pts = np.zeros((n + times) * dim)
        w = np.zeros(n + times) if self.rational else None
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_insert_knot(self._c, u, times, dptr(knots), dptr(pts),
                                               dptr(w) if w is not None else ffi.NULL, out, diag),
              diag, context="insert_knot")
        return NurbsCurve._from_c(out, n + p + 1 + times)

    def refine(self, new_knots):
        """The same curve with every knot of new_knots (nondecreasing, in
        the domain) inserted at once (A5.4)."""
        x = np.ascontiguousarray(np.sort(np.asarray(new_knots, dtype=np.float64).reshape(-1)))
        n, p, dim, nx = self.n, self.degree, self.dim, x.size
        knots = np.zeros(self._knots.size + nx)
        pts = np.zeros((n + nx) * dim)
        w = np.zeros(n + nx) if self.rational else None
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_refine(self._c, dptr(x) if nx else ffi.NULL, nx, dptr(knots),
                                          dptr(pts), dptr(w) if w is not None else ffi.NULL, out,
                                          diag), diag, context="refine")
        return NurbsCurve._from_c(out, n + p + 1 + nx)

    def remove_knot(self, u, times=1, tol=1e-9):
        """Remove the interior knot u up to `times` times while each removal
        moves the curve by at most tol (A5.8). Returns (curve, removed)."""
        n, p, dim = self.n, self.degree, self.dim
        knots = np.zeros(self._knots.size)
        pts = np.zeros(n * dim)
        w = np.zeros(n) if self.rational else None
        out = ffi.new("geom_nurbs_curve *")
        removed = ffi.new("size_t *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_remove_knot(self._c, float(u), int(times), float(tol),
                                               dptr(knots), dptr(pts),
                                               dptr(w) if w is not None else ffi.NULL, out,
                                               removed, diag), diag, context="remove_knot")
        r = int(removed[0])
        return NurbsCurve._from_c(out, n + p + 1 - r), r

    def elevate(self, times=1):
        """The same curve with its degree raised by `times` (A5.9; the curve
        must be clamped)."""
        nn, nk = ffi.new("size_t *"), ffi.new("size_t *")
        check(lib.geom_curve_nurbs_elevate_bound(self._c, times, nn, nk), context="elevate")
        knots = np.zeros(nk[0])
        pts = np.zeros(nn[0] * self.dim)
        w = np.zeros(nn[0]) if self.rational else None
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_elevate(self._c, times, dptr(knots), dptr(pts),
                                           dptr(w) if w is not None else ffi.NULL, out, diag),
              diag, context="elevate")
        return NurbsCurve._from_c(out, int(out.n) + int(out.degree) + 1)

    def clamp(self):
        """The same curve on the same domain with a clamped knot vector
        (end knots of multiplicity p + 1); a clamped curve is copied."""
        p, n, dim = self.degree, self.n, self.dim
        knots, pts = np.zeros(n + 3 * p + 1), np.zeros((n + 2 * p) * dim)
        w = np.zeros(n + 2 * p) if self.rational else None
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_clamp(self._c, dptr(knots), dptr(pts),
                                         dptr(w) if w is not None else ffi.NULL, out, diag),
              diag, context="clamp")
        return NurbsCurve._from_c(out, int(out.n) + p + 1)

    def bezier_segments(self):
        """(points (nseg, p+1, dim), weights (nseg, p+1) or None, breaks
        (nseg+1,)): the Bezier segment of every non-empty knot span (A5.6;
        segment s covers [breaks[s], breaks[s+1]] mapped onto [0, 1])."""
        ns = ffi.new("size_t *")
        check(lib.geom_curve_nurbs_segments(self._c, ns), context="bezier_segments")
        nseg, p, dim = int(ns[0]), self.degree, self.dim
        pts = np.zeros((nseg, p + 1, dim))
        w = np.zeros((nseg, p + 1)) if self.rational else None
        br = np.zeros(nseg + 1)
        diag = new_diag()
        check(lib.geom_curve_nurbs_decompose(self._c, dptr(pts), dptr(w) if w is not None else ffi.NULL,
                                             dptr(br), diag), diag, context="bezier_segments")
        return pts, w, br

    # ------------------------------------------------------ constructors

    @classmethod
    def circle(cls, center, radius, xaxis=None, yaxis=None):
        """The exact full circle as the 9-point rational quadratic (The NURBS
        Book ch. 7), in the plane of the orthonormal axes (default: x and y
        of the center's space; dim = len(center), 2 to 4)."""
        c, xa, ya = _frame(center, xaxis, yaxis)
        dim = c.size
        knots, pts, w = np.zeros(12), np.zeros(9 * dim), np.zeros(9)
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_circle(dim, dptr(c), dptr(xa), dptr(ya), radius, dptr(knots),
                                          dptr(pts), dptr(w), out, diag), diag, context="circle")
        return cls._from_c(out, 12)

    @classmethod
    def arc(cls, center, radius, start, end, xaxis=None, yaxis=None):
        """Exact circular arc from angle `start` to `end` (radians; end <
        start runs clockwise)."""
        c, xa, ya = _frame(center, xaxis, yaxis)
        dim = c.size
        n, nk = ffi.new("size_t *"), ffi.new("size_t *")
        check(lib.geom_curve_nurbs_arc_bound(start, end, n, nk), context="arc")
        knots, pts, w = np.zeros(nk[0]), np.zeros(n[0] * dim), np.zeros(n[0])
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_arc(dim, dptr(c), dptr(xa), dptr(ya), radius, start, end,
                                       dptr(knots), dptr(pts), dptr(w), out, diag), diag,
              context="arc")
        return cls._from_c(out, int(nk[0]))


    @classmethod
    def ellipse_arc(cls, center, xaxis, yaxis, start=0.0, end=2 * np.pi):
        """Exact arc of the ellipse center + cos(t) xaxis + sin(t) yaxis
        from t = start to end (radians; A7.1, pieces of at most 90 degrees)."""
        c, xa, ya = _frame(center, xaxis, yaxis)
        n, nk = ffi.new("size_t *"), ffi.new("size_t *")
        check(lib.geom_curve_nurbs_arc_bound(start, end, n, nk), context="ellipse_arc")
        knots, pts, w = np.zeros(nk[0]), np.zeros(n[0] * c.size), np.zeros(n[0])
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_ellipse_arc(c.size, dptr(c), dptr(xa), dptr(ya), float(start),
                                               float(end), dptr(knots), dptr(pts), dptr(w), out,
                                               diag), diag, context="ellipse_arc")
        return cls._from_c(out, int(nk[0]))

    @classmethod
    def conic(cls, p0, t0, p2, t2, point=None, weight=1.0):
        """One conic arc (rational quadratic Bezier) from p0 (tangent t0) to
        p2 (tangent t2), through `point` if given (A7.2), else with middle
        weight `weight` (< 1 ellipse, 1 parabola, > 1 hyperbola)."""
        a = [np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (p0, t0, p2, t2)]
        dim = a[0].size
        if any(v.size != dim for v in a):
            raise ValueError("p0, t0, p2, t2 must have the same dimension")
        q = None if point is None else np.ascontiguousarray(point, dtype=np.float64).reshape(dim)
        knots, pts, w = np.zeros(6), np.zeros(3 * dim), np.zeros(3)
        out = ffi.new("geom_nurbs_curve *")
        diag = new_diag()
        check(lib.geom_curve_nurbs_conic(dim, *[dptr(v) for v in a],
                                         dptr(q) if q is not None else ffi.NULL, float(weight),
                                         dptr(knots), dptr(pts), dptr(w), out, diag), diag,
              context="conic")
        return cls._from_c(out, 6)

    @classmethod
    def periodic(cls, degree, points, weights=None):
        """Closed periodic curve of `degree` through the m > degree distinct
        control points (m, dim) (the first `degree` repeated at the end,
        uniform knots, domain [0, 1], C^(p-1) at u = 0 == 1; evaluate with
        wrap=True for any parameter)."""
        P = np.ascontiguousarray(points, dtype=np.float64)
        if P.ndim != 2:
            raise ValueError("points must be (m, dim)")
        m, dim = P.shape
        p = int(degree)
        wi = None if weights is None else np.ascontiguousarray(weights, dtype=np.float64).reshape(m)
        knots, pts = np.zeros(m + 2 * p + 1), np.zeros((m + p) * dim)
        wo = np.zeros(m + p) if wi is not None else None
        out = ffi.new("geom_nurbs_curve *")
        check(lib.geom_curve_nurbs_periodic(p, m, dim, dptr(P), dptr(wi) if wi is not None else ffi.NULL,
                                            dptr(knots), dptr(pts),
                                            dptr(wo) if wo is not None else ffi.NULL, out),
              context="periodic")
        return cls._from_c(out, m + 2 * p + 1)

def _frame(center, xaxis, yaxis):
    c = np.ascontiguousarray(center, dtype=np.float64).reshape(-1)
    dim = c.size
    if xaxis is None:
        xaxis = np.eye(dim)[0]
    if yaxis is None:
        yaxis = np.eye(dim)[1]
    xa = np.ascontiguousarray(xaxis, dtype=np.float64).reshape(-1)
    ya = np.ascontiguousarray(yaxis, dtype=np.float64).reshape(-1)
    if xa.size != dim or ya.size != dim:
        raise ValueError("axes must have as many coordinates as the center")
    return c, xa, ya


def bspline_basis(degree, knots, u, nderiv=0, left=False):
    """The degree+1 non-zero B-spline basis functions and their derivatives
    0..nderiv at each u (A2.3, in C over the whole array): returns (spans,
    ders) with ders of shape S + (nderiv+1, degree+1) for u of shape S
    (ders[..., k, j] = k-th derivative of N_{span-p+j}) and spans of shape S.
    GeomError ERR_DOMAIN for a u outside the domain."""
    kn = np.ascontiguousarray(knots, dtype=np.float64).reshape(-1)
    n = kn.size - degree - 1
    us, scalar, shape = _params(u)
    uc = np.ascontiguousarray(us, dtype=np.float64)
    ders = np.empty((uc.size, nderiv + 1, degree + 1))
    spans = np.empty(uc.size, dtype=np.uintp)
    status = np.empty(uc.size, dtype=np.int32)
    check(lib.geom_curve_bspline_basis_many(int(degree), n, dptr(kn), uc.size,
                                            ffi.from_buffer("double[]", uc), int(nderiv),
                                            _flags(left, False),
                                            ffi.cast("size_t *", ffi.from_buffer(spans)),
                                            ffi.from_buffer("double[]", ders),
                                            ffi.from_buffer("int32_t[]", status), ffi.NULL),
          context="bspline_basis")
    bad = np.nonzero(status)[0]
    if bad.size:
        check(int(status[bad[0]]), context="bspline_basis(%r)" % float(uc[bad[0]]))
    spans = spans.astype(np.int64)
    if scalar:
        return int(spans[0]), ders[0]
    return spans.reshape(shape), ders.reshape(shape + (nderiv + 1, degree + 1))


def uniform_knots(degree, n, kind="clamped"):
    """Uniform knot vector for n control points: kind "clamped",
    "unclamped" or "periodic" (n + degree + 1 knots)."""
    out = np.zeros(n + degree + 1)
    check(lib.geom_curve_bspline_uniform_knots(_KNOT_KINDS[kind], degree, n, dptr(out)),
          context="uniform_knots")
    return out


def bezier_eval(ctrl, t):
    """Point of the Bezier curve with control points ctrl ((p+1, dim)) at
    t (scalar or array) by de Casteljau."""
    C = np.ascontiguousarray(ctrl, dtype=np.float64)
    if C.ndim == 1:
        C = C.reshape(-1, 1)
    p, dim = C.shape[0] - 1, C.shape[1]
    ts, scalar, shape = _params(t)
    out = np.zeros((ts.size, dim))
    pc, po = ffi.from_buffer("double[]", C), ffi.from_buffer("double[]", out)
    for i, x in enumerate(ts):
        check(lib.geom_curve_bezier_eval(p, dim, pc, x, po + dim * i), context="bezier_eval")
    return out[0] if scalar else out.reshape(shape + (dim,))


def bezier_derivs(ctrl, t, n=1):
    """Point and derivatives 0..n of a Bezier curve at a scalar t:
    (n + 1, dim)."""
    C = np.ascontiguousarray(ctrl, dtype=np.float64)
    if C.ndim == 1:
        C = C.reshape(-1, 1)
    p, dim = C.shape[0] - 1, C.shape[1]
    out = np.zeros((n + 1, dim))
    check(lib.geom_curve_bezier_derivs(p, dim, dptr(C), float(t), int(n), dptr(out)),
          context="bezier_derivs")
    return out


__all__ = ["NurbsCurve", "uniform_knots", "bezier_eval", "bezier_derivs"]


# ------------------------------------------------- Bezier, Hermite, Catmull-Rom

def _ctrl(ctrl):
    c = np.ascontiguousarray(ctrl, dtype=np.float64)
    if c.ndim == 1:
        c = c.reshape(-1, 1)
    if c.ndim != 2 or c.shape[0] < 1:
        raise ValueError("control points must be (degree + 1, dim)")
    return c, c.shape[0] - 1, c.shape[1]


def bezier_split(ctrl, t):
    """(left, right) control points of the Bezier curve ctrl (p+1, dim) cut
    at t in [0, 1] (de Casteljau; the shared point is bit-identical)."""
    c, p, dim = _ctrl(ctrl)
    left, right = np.zeros_like(c), np.zeros_like(c)
    check(lib.geom_curve_bezier_split(p, dim, dptr(c), float(t), dptr(left), dptr(right)),
          context="bezier_split")
    return left, right


def bezier_elevate(ctrl, times=1):
    """Control points (p+times+1, dim) of the same Bezier curve, degree
    raised by `times`."""
    c, p, dim = _ctrl(ctrl)
    out = np.zeros((p + int(times) + 1, dim))
    check(lib.geom_curve_bezier_elevate(p, dim, dptr(c), int(times), dptr(out)),
          context="bezier_elevate")
    return out


def bezier_bbox(ctrl, tight=True):
    """(min, max) of the Bezier curve over [0, 1]: tight (within 1e-15 of
    the coordinate's extent, containing the curve) or the control polygon's
    box (tight=False)."""
    c, p, dim = _ctrl(ctrl)
    lo, hi = np.zeros(dim), np.zeros(dim)
    fn = lib.geom_curve_bezier_bbox_tight if tight else lib.geom_curve_bezier_bbox
    check(fn(p, dim, dptr(c), dptr(lo), dptr(hi)), context="bezier_bbox")
    return lo, hi


def _same_dim(*vs):
    a = [np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in vs]
    if any(v.size != a[0].size for v in a):
        raise ValueError("the points must have the same dimension")
    return a


def hermite_to_bezier(p0, m0, p1, m1):
    """Bezier control points (4, dim) of the cubic Hermite segment."""
    a = _same_dim(p0, m0, p1, m1)
    out = np.zeros((4, a[0].size))
    check(lib.geom_curve_hermite_to_bezier(a[0].size, *[dptr(v) for v in a], dptr(out)),
          context="hermite_to_bezier")
    return out


def hermite_eval(p0, m0, p1, m1, t, nderiv=0):
    """Point and derivatives 0..nderiv (nderiv+1, dim) of the cubic Hermite
    segment at t."""
    a = _same_dim(p0, m0, p1, m1)
    out = np.zeros((int(nderiv) + 1, a[0].size))
    check(lib.geom_curve_hermite_eval(a[0].size, *[dptr(v) for v in a], float(t), int(nderiv),
                                      dptr(out)), context="hermite_eval")
    return out


def catmull_rom_eval(p0, p1, p2, p3, s, alpha=0.5):
    """The Catmull-Rom segment from p1 to p2 at s in [0, 1] (Barry-Goldman;
    alpha 0 uniform, 0.5 centripetal, 1 chordal)."""
    a = _same_dim(p0, p1, p2, p3)
    out = np.zeros(a[0].size)
    check(lib.geom_curve_catmull_rom_eval(a[0].size, *[dptr(v) for v in a], float(alpha), float(s),
                                          dptr(out)), context="catmull_rom_eval")
    return out


def segment_distance(a, b, q):
    """Distance from q to the segment [a, b], accurate for coordinates
    anywhere in the range of double."""
    a, b, q = _same_dim(a, b, q)
    return float(lib.geom_curve_segment_distance(a.size, dptr(a), dptr(b), dptr(q)))
