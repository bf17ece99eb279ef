"""Status codes and errors, exact predicates, and 4x4 transform helpers.

Matrices: libgeom stores a 4x4 matrix column-major (element (r, c) at
m[4*c + r], as OpenGL). Here every matrix is a numpy (4, 4) float64 array
indexed M[r, c] in the usual mathematical sense, so ``M @ p`` applies M to a
column vector p; the conversion (a transpose of the 16 doubles) happens at
the boundary and never shows.
"""

import os

import numpy as np

from ._ffi import ffi, lib

#: Status codes (geom_status), name -> value.
STATUS = {
    "OK": lib.GEOM_OK,
    "ERR_NOMEM": lib.GEOM_ERR_NOMEM,
    "ERR_INVALID_ARG": lib.GEOM_ERR_INVALID_ARG,
    "ERR_PARSE": lib.GEOM_ERR_PARSE,
    "ERR_IO": lib.GEOM_ERR_IO,
    "ERR_DEGENERATE": lib.GEOM_ERR_DEGENERATE,
    "ERR_NONMANIFOLD": lib.GEOM_ERR_NONMANIFOLD,
    "ERR_DOMAIN": lib.GEOM_ERR_DOMAIN,
    "ERR_LIMIT": lib.GEOM_ERR_LIMIT,
}
_CODE_TO_KEY = {v: k for k, v in STATUS.items()}

#: Value of GEOM_INVALID_INDEX (UINT32_MAX).
INVALID_INDEX = 0xFFFFFFFF

# geom_error_report::method values.
_ERROR_METHODS = {0: "none", 1: "bound", 2: "sampled", 3: "estimate"}


def version():
    """The version string of the loaded library, e.g. "0.1.0"."""
    return ffi.string(lib.geom_version_string()).decode()


def status_name(status):
    """geom_status_str: the library's name for a status code ("ok",
    "invalid argument", ...; "unknown status" for other values)."""
    return ffi.string(lib.geom_status_str(int(status))).decode()


class GeomError(Exception):
    """A libgeom function returned an error status.

    Attributes:
      status: the geom_status value (a negative int).
      code: its symbolic name without the GEOM_ prefix, e.g. "ERR_PARSE".
      name: the library's name for it (geom_status_str), e.g. "parse error".
      message: the geom_diag message ("" when the function has no diag).
      source, line, column, byte_offset: where in the input, when the
        function reported it (source "" and 0 otherwise).
      location: geom_diag_format's "source:line:column: message" text.
    """

    def __init__(self, status, message="", source="", line=0, column=0, byte_offset=0,
                 location="", context=""):
        self.status = int(status)
        self.code = _CODE_TO_KEY.get(self.status, "UNKNOWN")
        self.name = status_name(self.status)
        self.message = message
        self.source = source
        self.line = line
        self.column = column
        self.byte_offset = byte_offset
        self.location = location
        self.context = context
        text = self.name
        if context:
            text = "%s: %s" % (context, text)
        if location:
            text = "%s: %s" % (text, location)
        super().__init__(text)


def new_diag():
    """A zeroed geom_diag to pass to a C function."""
    return ffi.new("geom_diag *")


def _diag_fields(diag):
    # A diag the failing function did not fill (status still GEOM_OK, no
    # message) says nothing: formatting it would print "ok" after the error's
    # name ("invalid argument: ok").
    if diag == ffi.NULL or diag is None or (diag.status == 0 and diag.message[0] == b"\0"):
        return {}
    size = lib.geom_diag_format(diag, ffi.NULL, 0)
    buf = ffi.new("char[]", size + 1)
    lib.geom_diag_format(diag, buf, size + 1)
    return {
        "message": ffi.string(diag.message).decode(errors="replace"),
        "source": ffi.string(diag.source).decode(errors="replace"),
        "line": int(diag.line),
        "column": int(diag.column),
        "byte_offset": int(diag.byte_offset),
        "location": ffi.string(buf).decode(errors="replace"),
    }


def check(status, diag=None, context=""):
    """Raise GeomError if status is not GEOM_OK (0); diag, when given, is
    the geom_diag the call filled."""
    if status != 0:
        raise GeomError(status, context=context, **_diag_fields(diag))


def error_report(rep):
    """A geom_error_report as a dict."""
    return {
        "max_error": float(rep.max_error),
        "mean_error": float(rep.mean_error),
        "method": _ERROR_METHODS.get(int(rep.method), str(int(rep.method))),
        "evaluations": int(rep.evaluations),
        "tolerance": float(rep.tolerance),
        "pieces": int(rep.pieces),
        "seconds": float(rep.seconds),
    }


def flag_bits(table, names, what):
    """The OR of table[name] for names (an unknown name: ValueError naming
    the choices)."""
    bits = 0
    for a in names:
        if a not in table:
            raise ValueError("%s are %s, got %r" % (what, ", ".join(repr(k) for k in table), a))
        bits |= table[a]
    return bits


def struct_dict(cdata, ctype):
    """The scalar fields of a C struct as a dict (numbers as Python ints or
    floats, bools as bool, nested structs recursively, arrays as lists)."""
    out = {}
    t = ctype if isinstance(ctype, ffi.CType) else ffi.typeof(ctype)
    for name, field in t.fields:
        value = getattr(cdata, name)
        kind = field.type.kind
        if kind == "struct":
            out[name] = struct_dict(value, field.type)
        elif kind == "array":
            out[name] = list(value)
        elif kind == "primitive" and field.type.cname in ("_Bool", "bool"):
            out[name] = bool(value)
        elif kind in ("primitive", "enum"):
            out[name] = value
    return out


# --------------------------------------------------------------- arrays

def as_points(x, dim, name="points"):
    """x as a C-contiguous float64 array of shape (n, dim), and whether it
    was a single point (shape (dim,))."""
    arr = np.ascontiguousarray(x, dtype=np.float64)
    if arr.ndim == 1:
        if arr.shape[0] != dim:
            raise ValueError("%s: expected %d coordinates, got shape %s" % (name, dim, arr.shape))
        return arr.reshape(1, dim), True
    if arr.ndim != 2 or arr.shape[1] != dim:
        raise ValueError("%s: expected shape (%d,) or (n, %d), got %s"
                         % (name, dim, dim, arr.shape))
    return arr, False


def dptr(arr):
    """A `double *` into a C-contiguous float64 numpy array (no copy; the
    array must outlive the pointer's use)."""
    return ffi.cast("double *", ffi.from_buffer("double[]", arr))


def from_c_doubles(ptr, count):
    """A numpy copy of `count` doubles at a C pointer."""
    if count == 0:
        return np.empty(0, dtype=np.float64)
    return np.frombuffer(ffi.buffer(ptr, 8 * count), dtype=np.float64).copy()


def from_c_uint32(ptr, count):
    """A numpy copy of `count` uint32 at a C pointer."""
    if count == 0:
        return np.empty(0, dtype=np.uint32)
    return np.frombuffer(ffi.buffer(ptr, 4 * count), dtype=np.uint32).copy()


# ----------------------------------------------------------- predicates

def stride_args(dim, names, args, nslots):
    """Pointers and strides for a C batch entry point over n rows (the
    `const double *const pts[k], const size_t strides[k]` convention of
    geom_predicate_many and geom_bary_simplex_many): each argument is a
    point (dim,) (stride 0: broadcast without copying) or an (n, dim) array
    (stride dim). Returns (n, single, pts, strides, keep) where single says
    that every argument was one point and keep holds the buffers alive."""
    n = None
    parsed = []
    for name, value in zip(names, args):
        arr, one = as_points(value, dim, name)
        if not one:
            if n is not None and n != arr.shape[0]:
                raise ValueError("%s: %d rows, others have %d" % (name, arr.shape[0], n))
            n = arr.shape[0]
        parsed.append((arr, one))
    single = n is None
    pts = ffi.new("const double *[%d]" % nslots)
    strides = ffi.new("size_t[%d]" % nslots)
    keep = []
    for j, (arr, one) in enumerate(parsed):
        buf = ffi.from_buffer("double[]", arr)
        keep.append(buf)
        pts[j] = buf
        strides[j] = 0 if one else dim
    return (1 if single else n), single, pts, strides, keep


def _predicate(kind, dim, names, args):
    """One C call over every row (geom_predicate_many)."""
    n, single, pts, strides, keep = stride_args(dim, names, args, 4)
    out = np.empty(n, dtype=np.float64)
    st = lib.geom_predicate_many(kind, n, pts, strides, ffi.from_buffer("double[]", out))
    del keep
    if st != 0:
        raise GeomError(int(st), context="predicate")
    return float(out[0]) if single else out


def orient2d(a, b, c):
    """Orientation of 2D points: > 0 counter-clockwise, < 0 clockwise, 0
    collinear, with an exact sign (geom_orient2d); the magnitude
    approximates twice the signed area. Each argument is a point (2,) or
    an (n, 2) array (single points broadcast); returns a float or an (n,)
    array. NaN where an input is not finite. Arrays run in C in one call
    (geom_predicate_many), bitwise the single-point results."""
    return _predicate(lib.GEOM_PREDICATE_ORIENT2D, 2, ("a", "b", "c"), (a, b, c))


def orient3d(a, b, c, d):
    """Sign of det[a-d; b-d; c-d], exact (geom_orient3d): > 0 when d lies
    below the plane of a, b, c seen counter-clockwise from above. Points
    (3,) or (n, 3) arrays."""
    return _predicate(lib.GEOM_PREDICATE_ORIENT3D, 3, ("a", "b", "c", "d"), (a, b, c, d))


def incircle(a, b, c, d):
    """> 0 if d is inside the circle through a, b, c (counter-clockwise),
    < 0 outside, 0 on it; exact sign (geom_incircle). Points (2,) or
    (n, 2)."""
    return _predicate(lib.GEOM_PREDICATE_INCIRCLE, 2, ("a", "b", "c", "d"), (a, b, c, d))


def orient2d_exact(a, b, c):
    """orient2d's determinant rounded once to the nearest double
    (geom_orient2d_exact)."""
    return _predicate(lib.GEOM_PREDICATE_ORIENT2D_EXACT, 2, ("a", "b", "c"), (a, b, c))


def orient3d_exact(a, b, c, d):
    """orient3d's determinant rounded once to the nearest double."""
    return _predicate(lib.GEOM_PREDICATE_ORIENT3D_EXACT, 3, ("a", "b", "c", "d"), (a, b, c, d))


# ------------------------------------------------------------- matrices

def to_mat4(m):
    """A numpy (4, 4) matrix M[r, c] as a geom_mat4 (column-major)."""
    arr = np.asarray(m, dtype=np.float64)
    if arr.shape != (4, 4):
        raise ValueError("expected a (4, 4) matrix, got shape %s" % (arr.shape,))
    out = ffi.new("geom_mat4 *")
    out.m = list(arr.T.ravel())
    return out[0]


def from_mat4(m):
    """A geom_mat4 (value or pointer) as a numpy (4, 4) array M[r, c]."""
    return np.array(list(m.m), dtype=np.float64).reshape(4, 4).T.copy()


def from_mat3(m):
    return np.array(list(m.m), dtype=np.float64).reshape(3, 3).T.copy()


def _vec3(v, name):
    arr = np.asarray(v, dtype=np.float64)
    if arr.shape != (3,):
        raise ValueError("%s: expected 3 coordinates, got shape %s" % (name, arr.shape))
    return {"x": float(arr[0]), "y": float(arr[1]), "z": float(arr[2])}


def perspective(fovy, aspect, near, far):
    """gluPerspective: fovy in radians (0, pi), aspect > 0, 0 < near < far.
    GeomError ERR_DOMAIN otherwise."""
    out = ffi.new("geom_mat4 *")
    check(lib.geom_mat4_perspective(fovy, aspect, near, far, out), context="perspective")
    return from_mat4(out)


def ortho(left, right, bottom, top, near, far):
    """glOrtho (depth to [-1, 1])."""
    out = ffi.new("geom_mat4 *")
    check(lib.geom_mat4_ortho(left, right, bottom, top, near, far, out), context="ortho")
    return from_mat4(out)


def lookat(eye, center, up):
    """gluLookAt view matrix. ERR_DEGENERATE if eye == center or up is
    parallel to the view direction."""
    out = ffi.new("geom_mat4 *")
    check(lib.geom_mat4_lookat(_vec3(eye, "eye"), _vec3(center, "center"), _vec3(up, "up"), out),
          context="lookat")
    return from_mat4(out)


def rotate(axis, radians):
    """Rotation about axis through the origin (right-handed, as glRotate)."""
    out = ffi.new("geom_mat4 *")
    check(lib.geom_mat4_rotate(_vec3(axis, "axis"), radians, out), context="rotate")
    return from_mat4(out)


def translate(t):
    return from_mat4(lib.geom_mat4_translate(_vec3(t, "t")))


def scale(s):
    return from_mat4(lib.geom_mat4_scale(_vec3(s, "s")))


def inverse(m):
    """Inverse of a (4, 4) matrix by cofactors. ERR_DEGENERATE when it is
    singular or numerically so (|det| <= 1e-14 times the product of the
    column norms)."""
    out = ffi.new("geom_mat4 *")
    check(lib.geom_mat4_inverse(to_mat4(m), out), context="inverse")
    return from_mat4(out)


def determinant(m):
    return float(lib.geom_mat4_determinant(to_mat4(m)))


def normal_matrix(m):
    """Inverse-transpose of the upper-left 3x3 block, as a (3, 3) array."""
    out = ffi.new("geom_mat3 *")
    check(lib.geom_mat4_normal_matrix(to_mat4(m), out), context="normal_matrix")
    return from_mat3(out)


def transform_point(m, p):
    """Apply m to the point p (w = 1) with the homogeneous divide; p is (3,)
    or (n, 3). ERR_DEGENERATE where the resulting w is 0."""
    pts, single = as_points(p, 3, "p")
    mm = to_mat4(m)
    out = ffi.new("geom_vec3 *")
    res = np.empty_like(pts)
    for i, q in enumerate(pts):
        check(lib.geom_mat4_transform_point(mm, {"x": q[0], "y": q[1], "z": q[2]}, out),
              context="transform_point (row %d)" % i)
        res[i] = (out.x, out.y, out.z)
    return res[0] if single else res


class Progress:
    """A Python callable as a C progress callback (the `progress` and
    `progress_user` fields of the tessellation, iso and render options):
    fn(fraction) is called with the fraction done in [0, 1]. An exception
    raised by fn is kept (later calls are skipped) and raised again by
    reraise() once the C call has returned; the C work itself runs to its
    end. With fn None the fields stay NULL."""

    def __init__(self, fn):
        self.error = None
        self._fn = fn
        self._c = ffi.NULL if fn is None else ffi.callback("void(void *, double)", self._call)

    def _call(self, user, fraction):
        if self.error is None:
            try:
                self._fn(float(fraction))
            except BaseException as e:  # noqa: B902 - re-raised after the C call
                self.error = e

    def install(self, options):
        """Set options.progress (keep this object alive for the C call)."""
        options.progress = self._c
        options.progress_user = ffi.NULL

    def reraise(self):
        if self.error is not None:
            raise self.error


class Output:
    """An output file written the way the tools write theirs
    (geom_output_open/_write/_commit/_abort): a regular file (or a new
    path) is written to a temporary file next to it and renamed over it on
    commit, keeping the replaced file's mode, so a failed or interrupted
    write never leaves a truncated file; a device or FIFO is written
    through; a directory, a dangling link or a file the caller may not
    write is refused (GeomError ERR_IO naming the path and the system's
    reason).

    As a context manager: committed on a normal exit, abandoned (the
    destination left as it was) when the block raises::

        with geom.Output("out.txt") as f:
            f.write(b"...")
    """

    def __init__(self, path):
        p = os.fsencode(path)
        if b"\0" in p:
            raise ValueError("path contains a NUL byte")
        self._out = ffi.new("geom_output *")
        self._out.fd = -1
        diag = new_diag()
        check(lib.geom_output_open(p, ffi.NULL, self._out, diag), diag, context="Output")
        self.path = path

    @property
    def closed(self):
        return self._out.fd < 0

    @property
    def temporary(self):
        """The temporary file's path while open (None when written through
        or closed)."""
        t = self._out.temporary
        return None if self.closed or t == ffi.NULL else os.fsdecode(ffi.string(t))

    def write(self, data):
        """Write bytes-like data; returns its length."""
        buf = ffi.from_buffer(memoryview(data).cast("B"))
        diag = new_diag()
        check(lib.geom_output_write(self._out, buf, len(buf), diag), diag, context="Output.write")
        return len(buf)

    def commit(self):
        """Finish: the file replaces the destination (fsync'd, renamed)."""
        diag = new_diag()
        check(lib.geom_output_commit(self._out, diag), diag, context="Output.commit")

    def abort(self):
        """Abandon: the temporary file is removed. A no-op once closed."""
        lib.geom_output_abort(self._out)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            self.commit()
        else:
            self.abort()
        return False

    def __del__(self):
        out = getattr(self, "_out", None)
        if out is not None and out.fd >= 0:
            lib.geom_output_abort(out)


def write_file(path, data):
    """Write bytes to path atomically with the rules of Output."""
    with Output(path) as f:
        f.write(data)
