"""Barycentric and generalized barycentric coordinates (geom/bary.h).

Every function takes single points or numpy arrays of points and returns
numpy arrays. The simplex functions (tri2, tri3, tet) keep the C library's
guarantees: exact signs (a point on an edge gets exactly 0, a vertex exactly
(1, 0, 0)) and a relative error of at most about 4.6e-13 per coordinate.

Vectorised calls run in C over the whole array in one call (the batch entry
points geom_bary_simplex_many, geom_bary_polygon_many,
geom_bary_perspective_many and geom_bary_interpolate_many). Arguments
broadcast: a single triangle with an (n, 2) array of points, or (n, 2)
arrays for every vertex and point.

Errors: with errors="raise" (default) the first failing row raises
GeomError (ERR_DEGENERATE for a zero-area triangle, zero-volume tetrahedron
or degenerate polygon, ERR_INVALID_ARG for non-finite input, ERR_DOMAIN for
a Wachspress point outside its polygon) naming the row; with errors="nan"
failing rows are NaN instead and no exception is raised.
"""

import numpy as np

from ._ffi import ffi, lib
from .core import GeomError, as_points, stride_args

_ERRORS = ("raise", "nan")


def _check_errors(errors):
    if errors not in _ERRORS:
        raise ValueError("errors must be 'raise' or 'nan', not %r" % (errors,))


def _finish(out, statuses, single, errors, what):
    bad = np.nonzero(statuses)[0]
    if bad.size:
        if errors == "raise":
            i = int(bad[0])
            raise GeomError(int(statuses[i]),
                            context="%s%s" % (what, "" if single else " (row %d)" % i))
        out[bad] = np.nan
    return out[0] if single else out


def _rows(call, out, n, single, errors, what):
    """Run call(status, n_failed), a *_many C call writing out, without a
    status array on the common path (n int32 writes and a scan saved): the
    per-row statuses are asked for (a second call) only when some row
    failed."""
    nfail = ffi.new("size_t *")
    st = call(ffi.NULL, nfail)
    status = None
    if st == 0 and nfail[0]:
        status = np.empty(n, dtype=np.int32)
        st = call(ffi.from_buffer("int32_t[]", status), ffi.NULL)
    if st != 0:
        raise GeomError(int(st), context=what)
    if status is None:
        return out[0] if single else out
    return _finish(out, status, single, errors, what)


def _simplex(kind, dim, k, names, args, errors, what):
    """One C call over every row (geom_bary_simplex_many): single points
    are passed with stride 0 (broadcast without copying)."""
    _check_errors(errors)
    n, single, pts, strides, keep = stride_args(dim, names, args, 5)
    out = np.empty((n, k), dtype=np.float64)
    pout = ffi.from_buffer("double[]", out)
    r = _rows(lambda status, nfail: lib.geom_bary_simplex_many(kind, n, pts, strides, pout,
                                                               status, nfail),
              out, n, single, errors, what)
    del keep
    return r


def tri2(a, b, c, p, errors="raise"):
    """Barycentric coordinates of p in the 2D triangle (a, b, c)
    (geom_bary_tri2): l with p = l0 a + l1 b + l2 c. Points (2,) or (n, 2);
    returns (3,) or (n, 3)."""
    return _simplex(lib.GEOM_BARY_TRI2, 2, 3, ("a", "b", "c", "p"), (a, b, c, p), errors, "tri2")


def tri3(a, b, c, p, errors="raise"):
    """Barycentric coordinates of the projection of p onto the plane of the
    3D triangle (a, b, c) (geom_bary_tri3). Points (3,) or (n, 3)."""
    return _simplex(lib.GEOM_BARY_TRI3, 3, 3, ("a", "b", "c", "p"), (a, b, c, p), errors, "tri3")


def tet(a, b, c, d, p, errors="raise"):
    """Barycentric coordinates of p in the tetrahedron (a, b, c, d)
    (geom_bary_tet); returns (4,) or (n, 4)."""
    return _simplex(lib.GEOM_BARY_TET, 3, 4, ("a", "b", "c", "d", "p"), (a, b, c, d, p), errors,
                    "tet")


def _polygon(fn, poly, p, errors, what):
    _check_errors(errors)
    P = np.ascontiguousarray(poly, dtype=np.float64)
    if P.ndim != 2 or P.shape[1] != 2:
        raise ValueError("%s: polygon must have shape (k, 2), got %s" % (what, P.shape))
    k = P.shape[0]
    pts, single = as_points(p, 2, "p")
    n = pts.shape[0]
    out = np.empty((n, k), dtype=np.float64)
    status = np.empty(n, dtype=np.int32)
    if k < 3:
        raise GeomError(lib.GEOM_ERR_INVALID_ARG, context="%s: a polygon needs 3 vertices" % what)
    st = lib.geom_bary_polygon_many(fn, k, ffi.from_buffer("double[]", P), n,
                                    ffi.from_buffer("double[]", pts),
                                    ffi.from_buffer("double[]", out),
                                    ffi.from_buffer("int32_t[]", status), ffi.NULL)
    if st != 0:
        raise GeomError(int(st), context=what)
    return _finish(out, status, single, errors, what)


def mean_value(poly, p, errors="raise"):
    """Mean value coordinates (Floater; Hormann and Floater 2006) of p with
    respect to the simple polygon `poly` ((k, 2), either orientation,
    convex or not). p is (2,) or (n, 2); returns (k,) or (n, k) weights
    summing to 1 that reproduce p."""
    return _polygon(0, poly, p, errors, "mean_value")


def wachspress(poly, p, errors="raise"):
    """Wachspress coordinates of p inside the strictly convex polygon
    `poly` ((k, 2)). ERR_DOMAIN for a non-convex polygon or a point
    outside."""
    return _polygon(1, poly, p, errors, "wachspress")


def perspective(l, w, errors="raise"):
    """Perspective-correct interpolation weights (geom_bary_perspective):
    lp_i = (l_i / w_i) / sum_j (l_j / w_j) from screen-space barycentrics l
    ((3,) or (n, 3)) and the clip-space w of the vertices ((3,) or
    (n, 3)). Arrays run in C in one call (geom_bary_perspective_many),
    bitwise the single-point results."""
    _check_errors(errors)
    n, single, pts, strides, keep = stride_args(3, ("l", "w"), (l, w), 2)
    out = np.empty((n, 3), dtype=np.float64)
    pout = ffi.from_buffer("double[]", out)
    r = _rows(lambda status, nfail: lib.geom_bary_perspective_many(
        n, pts[0], strides[0], pts[1], strides[1], pout, status, nfail),
        out, n, single, errors, "perspective")
    del keep
    return r


def interpolate(weights, attributes):
    """sum_i weights[i] * attributes[i] (geom_bary_interpolate): weights
    (k,) and attributes (k, ncomp) give (ncomp,); weights (n, k) give
    (n, ncomp). Arrays run in C in one call (geom_bary_interpolate_many),
    bitwise the single-point results."""
    A = np.ascontiguousarray(attributes, dtype=np.float64)
    if A.ndim == 1:
        A = A.reshape(-1, 1)
    k, ncomp = A.shape
    W, single = as_points(weights, k, "weights")
    n = W.shape[0]
    out = np.empty((n, ncomp), dtype=np.float64)  # every element written
    st = lib.geom_bary_interpolate_many(n, k, ffi.from_buffer("double[]", W), ncomp,
                                        ffi.from_buffer("double[]", A),
                                        ffi.from_buffer("double[]", out))
    if st != 0:
        raise GeomError(int(st), context="interpolate")
    return out[0] if single else out
