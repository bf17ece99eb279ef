"""Implicit functions (geom/implicit.h) and marching cubes (geom/iso.h).

Expression compiles libgeom's expression language once (x, y, z, t,
sphere(), torus(), box(), CSG, smooth unions, ...; f < 0 inside) and
evaluates it over numpy arrays of points in C (geom_implicit_expr_eval_many,
32 points per dispatch: tens of nanoseconds per point).

marching_cubes() extracts an isosurface with the topologically correct
marching cubes of geom/iso.h from an expression, a sampled numpy volume, or
a Python function of an (n, 3) array of points.
"""

import os

import numpy as np

from ._ffi import ffi, lib
from .core import Progress, check, dptr, error_report, new_diag
from .mesh import Mesh

_ISO_ERROR = {"auto": 0, "always": 1, "never": 2}


class Expression:
    """A compiled implicit expression (geom_implicit_expr).

    Expression("sphere(1)")([[0, 0, 0], [2, 0, 0]]) -> array([-1., 1.]).
    GeomError ERR_PARSE (with the column in .column and .location) for a
    syntax error, ERR_LIMIT for a text too long or nested too deep. Freed by
    close(), a with block, or garbage collection.
    """

    def __init__(self, text, max_length=0, max_depth=0):
        self.text = str(text)
        raw = self.text.encode()
        opt = ffi.new("geom_implicit_expr_options *")
        opt.max_length = max_length
        opt.max_depth = max_depth
        out = ffi.new("geom_implicit_expr **")
        diag = new_diag()
        check(lib.geom_implicit_expr_compile(raw, len(raw), opt, out, diag), diag,
              context="Expression")
        self._p = ffi.gc(out[0], lib.geom_implicit_expr_destroy)
        self._time = 0.0

    @property
    def _ptr(self):
        if self._p is None:
            raise ValueError("the expression is closed")
        return self._p

    def close(self):
        if self._p is not None:
            ffi.release(self._p)
            self._p = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        return "<geom.Expression %r>" % (self.text,)

    @property
    def time(self):
        """The value of the variable t (initially 0)."""
        return self._time

    @time.setter
    def time(self, t):
        lib.geom_implicit_expr_set_time(self._ptr, float(t))
        self._time = float(t)

    @property
    def size(self):
        """Instructions of the compiled program (after constant folding)."""
        return int(lib.geom_implicit_expr_size(self._ptr))

    @property
    def variables(self):
        """The set of variables the expression reads, e.g. {"x", "z"}."""
        bits = lib.geom_implicit_expr_variables(self._ptr)
        return {name for bit, name in ((1, "x"), (2, "y"), (4, "z"), (8, "t")) if bits & bit}

    def __call__(self, points):
        """f at points (3,) -> float, or (..., 3) -> (...)."""
        pts = np.ascontiguousarray(points, dtype=np.float64)
        if pts.shape[-1:] != (3,):
            raise ValueError("points must have shape (..., 3), got %s" % (pts.shape,))
        flat = pts.reshape(-1, 3)
        out = np.empty(flat.shape[0])
        if flat.shape[0]:
            lib.geom_implicit_expr_eval_many(self._ptr, flat.shape[0], dptr(flat), dptr(out))
        return float(out[0]) if pts.ndim == 1 else out.reshape(pts.shape[:-1])

    def gradient(self, points):
        """(values, gradients): f and its exact gradient (dual numbers) at
        points (3,) or (..., 3)."""
        pts = np.ascontiguousarray(points, dtype=np.float64)
        if pts.shape[-1:] != (3,):
            raise ValueError("points must have shape (..., 3), got %s" % (pts.shape,))
        flat = pts.reshape(-1, 3)
        vals = np.empty(flat.shape[0])
        grads = np.empty(flat.shape)
        if flat.shape[0]:
            lib.geom_implicit_expr_eval_grad_many(self._ptr, flat.shape[0], dptr(flat),
                                                  dptr(vals), dptr(grads))
        if pts.ndim == 1:
            return float(vals[0]), grads[0]
        return vals.reshape(pts.shape[:-1]), grads.reshape(pts.shape)

    def interval(self, lo, hi):
        """(lower, upper) bounds of f over the box lo..hi by interval
        arithmetic: every finite value of f in the box lies between them."""
        a = np.ascontiguousarray(lo, dtype=np.float64).reshape(3)
        b = np.ascontiguousarray(hi, dtype=np.float64).reshape(3)
        out = ffi.new("double[2]")
        check(lib.geom_implicit_expr_eval_interval(self._ptr, dptr(a), dptr(b), out),
              context="interval")
        return float(out[0]), float(out[1])

    def bounds(self, lo, hi):
        """(lower, upper, defined): interval bounds of f over the box lo..hi
        (3 coordinates each, lo <= hi, infinite bounds allowed) with
        definedness (geom_implicit_expr_eval_bounds). lower <= f(p) <= upper
        for every p in the box where f(p) is finite, as f(points) computes
        it; defined is True when, in addition, f is finite everywhere in the
        box (no NaN, no infinity), so the bounds hold at every point without
        exception. The test is conservative: defined is False whenever an
        intermediate interval is unbounded or reaches outside the domain of
        sqrt, log or a non-integer power. (nan, nan) when f is defined
        nowhere in the box. The bounds are rigorous, not tight (interval
        arithmetic overestimates where a variable occurs more than once).
        Many boxes: lo and hi (..., 3) arrays (broadcast against each
        other) give lower, upper (float arrays) and defined (a bool array)
        of shape (...), in one C call (geom_implicit_expr_eval_bounds_many),
        each box exactly what the single call gives.
        Raises GeomError (ERR_INVALID_ARG) for NaN bounds or lo > hi (in
        any box); ValueError when the last axis is not 3."""
        a = np.asarray(lo, dtype=np.float64)
        b = np.asarray(hi, dtype=np.float64)
        if a.shape[-1:] != (3,) or b.shape[-1:] != (3,):
            raise ValueError("lo and hi: 3 coordinates each, got shapes %s and %s"
                             % (a.shape, b.shape))
        if a.shape == (3,) and b.shape == (3,):
            a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
            out = ffi.new("double[2]")
            defined = ffi.new("int *")
            check(lib.geom_implicit_expr_eval_bounds(self._ptr, dptr(a), dptr(b), out, defined),
                  context="bounds")
            return float(out[0]), float(out[1]), bool(defined[0])
        a, b = np.broadcast_arrays(a, b)
        shape = a.shape[:-1]
        a = np.ascontiguousarray(a.reshape(-1, 3))
        b = np.ascontiguousarray(b.reshape(-1, 3))
        n = a.shape[0]
        out = np.empty((n, 2))
        defined = np.empty(n, dtype=np.intc)
        if n:
            check(lib.geom_implicit_expr_eval_bounds_many(
                self._ptr, n, dptr(a), dptr(b), dptr(out),
                ffi.from_buffer("int[]", defined)), context="bounds")
        return (out[:, 0].reshape(shape), out[:, 1].reshape(shape),
                defined.astype(bool).reshape(shape))


def _iso_options(iso, refine, normals, caps, error, threads):
    """A geom_iso_options * from marching_cubes' arguments."""
    opt = ffi.new("geom_iso_options *")
    opt.iso = float(iso)
    opt.refine = lib.GEOM_IMPLICIT_REFINE_AUTO if refine else lib.GEOM_IMPLICIT_REFINE_NEVER
    opt.normals = 1 if normals else 0
    opt.caps = 1 if caps else 0
    opt.error = _ISO_ERROR[error]
    threads = int(threads)
    if threads < 0:
        raise ValueError("threads must be >= 0 (0: all cores), got %d" % threads)
    opt.threads = min(threads, os.cpu_count() or 1)  # capped to the machine
    return opt


def _grid_field(field, spacing, origin, keep):
    """A geom_iso_grid * over a 3-D numpy array or a Volume (as
    marching_cubes takes them), its buffers appended to keep; None for
    other fields."""
    if isinstance(field, Volume):
        spacing = field.spacing if spacing is None else spacing
        origin = field.origin if origin is None else origin
        field = field.samples
    if not isinstance(field, np.ndarray):
        return None
    if field.ndim != 3:
        raise ValueError("a volume must be a 3-D array")
    dtype = volume_dtype(field.dtype)
    vol = np.asfortranarray(field, dtype=dtype)  # i (x) fastest in memory
    grid = ffi.new("geom_iso_grid *")
    grid.dims = list(vol.shape)
    grid.type = (lib.GEOM_IMPLICIT_SCALAR_F32 if dtype == np.float32
                 else lib.GEOM_IMPLICIT_SCALAR_F64)
    buf = ffi.from_buffer(vol.reshape(-1, order="F"))
    keep += [vol, buf]
    grid.data = buf
    sp = [1.0, 1.0, 1.0] if spacing is None else [float(s) for s in spacing]
    org = [0.0, 0.0, 0.0] if origin is None else [float(s) for s in origin]
    # validated here: C reads a zero spacing as its default 1, which from
    # Python would silently hide a caller's bug
    if len(sp) != 3 or not all(np.isfinite(v) and v > 0 for v in sp):
        raise ValueError("spacing must be three finite numbers > 0, got %r" % (spacing,))
    if len(org) != 3 or not all(np.isfinite(v) for v in org):
        raise ValueError("origin must be three finite numbers, got %r" % (origin,))
    grid.spacing = sp
    grid.origin = org
    return grid


def _function_field(field, bounds, resolution, keep, error_box):
    """(geom_iso_field *, bounds (6,), size_t[3] resolution, single_thread)
    for an expression string, an Expression or a Python callable (as
    marching_cubes takes them); what C must not free goes to keep, the first
    exception a callable raises to error_box."""
    if bounds is None or resolution is None:
        raise ValueError("bounds and resolution are needed for a function field")
    b = np.ascontiguousarray(bounds, dtype=np.float64).reshape(6)
    res = ffi.new("size_t[3]", [int(r) for r in resolution])
    f = ffi.new("geom_iso_field *")
    keep.append(b)
    if isinstance(field, str):
        field = Expression(field)
    if isinstance(field, Expression):
        check(lib.geom_iso_field_from_expr(field._ptr, f), context="marching_cubes")
        keep.append(field)
        return f, b, res, False
    if not callable(field):
        raise TypeError("field must be an expression string, an Expression, a 3-D array "
                        "or a callable")
    fn = field

    def on_error(exc_type, exc_value, tb):
        if not error_box:
            error_box.append(exc_value)

    @ffi.callback("double(void *, const double *)", onerror=on_error, error=float("nan"))
    def value_cb(user, p):
        pts = np.frombuffer(ffi.buffer(p, 24), dtype=np.float64).reshape(1, 3)
        return float(np.asarray(fn(pts.copy()), dtype=np.float64).reshape(-1)[0])

    @ffi.callback("void(void *, size_t, const double *, double *)", onerror=on_error)
    def values_cb(user, n, p, out):
        pts = np.frombuffer(ffi.buffer(p, 24 * n), dtype=np.float64).reshape(n, 3)
        res_v = np.asarray(fn(pts.copy()), dtype=np.float64).reshape(-1)
        if res_v.shape != (n,):
            raise ValueError("the field function returned shape %s for %d points"
                             % (res_v.shape, n))
        ffi.memmove(out, ffi.from_buffer(np.ascontiguousarray(res_v)), 8 * n)

    keep += [value_cb, values_cb]
    f.value = value_cb
    f.values = values_cb
    f.exact = 1
    return f, b, res, True


def marching_cubes(field, bounds=None, resolution=None, iso=0.0, refine=False, normals=False,
                   caps=False, error="auto", threads=0, spacing=None, origin=None,
                   progress=None):
    """Isosurface by topologically correct marching cubes (geom/iso.h).

    field is one of:
      - an expression string or an Expression: sampled on the grid of
        `resolution` (nx, ny, nz) cells over bounds (x0, y0, z0, x1, y1,
        z1); exact field, so refine=True puts vertices on the surface to
        rounding and the error is measured;
      - a 3-D numpy array volume[i, j, k] (x index first; float32,
        float64, or 8/16/32-bit integers, bool and float16, converted
        exactly; other dtypes raise TypeError) of samples at
        origin + (i, j, k) * spacing (or a Volume from read_volume, whose
        spacing and origin are used): the cells are
        the boxes between samples (bounds and resolution unused);
      - a Python callable f(points (n, 3)) -> (n,) values, sampled like an
        expression (called one grid row at a time, from a single thread).
    Inside is f <= iso (as in contour); triangles face increasing f. progress: a callable
    given the fraction (0..1] of the grid's slabs extracted (on the calling
    thread); an exception it raises is raised after the extraction.

    Returns (mesh, report): a Mesh (vertex channel "normal" when
    normals=True; its last report["n_cap_triangles"] faces are caps when
    caps=True) and the extraction report (vertex_error, sample_error,
    seconds, active_cells, tunnels, ...).
    """
    opt = _iso_options(iso, refine, normals, caps, error, threads)
    prog = Progress(progress)
    prog.install(opt)
    surf = ffi.new("geom_iso_surface *")
    diag = new_diag()
    keep = []
    error_box = []
    grid = _grid_field(field, spacing, origin, keep)
    if grid is not None:
        st = lib.geom_iso_extract_grid(grid, opt, surf, diag)
    else:
        f, b, res, single = _function_field(field, bounds, resolution, keep, error_box)
        if single:
            opt.threads = 1
        st = lib.geom_iso_extract(f, dptr(b), res, opt, surf, diag)
    try:
        if error_box:
            raise error_box[0]
        check(st, diag, context="marching_cubes")
        prog.reraise()
        report = {k: v for k, v in _iso_report(surf.report).items()}
        report["n_cap_triangles"] = int(surf.n_cap_triangles)
        mesh = Mesh()
        d2 = new_diag()
        st2 = lib.geom_iso_surface_to_mesh(surf, mesh._ptr, d2)
        if st2 != 0:
            mesh.close()
            check(st2, d2, context="marching_cubes")
        return mesh, report
    finally:
        lib.geom_iso_surface_free(surf)
        del keep


def _contour_args(field, bounds, resolution, iso, z, keep, error_box):
    """(field *, bounds (4,), nx, ny, geom_implicit_contour_options *) of
    contour()'s arguments (what C must not free goes to keep)."""
    b4 = np.ascontiguousarray(bounds, dtype=np.float64).reshape(4)
    nx, ny = (int(r) for r in resolution)
    f, _, _, _ = _function_field(field, (b4[0], b4[1], 0, b4[2], b4[3], 1), (nx, ny, 1),
                                 keep, error_box)
    opt = ffi.new("geom_implicit_contour_options *")
    opt.iso, opt.z = float(iso), float(z)
    return f, b4, nx, ny, opt


def _contour(field, bounds, resolution, iso, z, refine, take):
    """Run geom_implicit_contour and return take(isolines) (then freed)."""
    keep, error_box = [], []
    f, b4, nx, ny, opt = _contour_args(field, bounds, resolution, iso, z, keep, error_box)
    opt.refine = (lib.GEOM_IMPLICIT_REFINE_AUTO if refine is None else
                  lib.GEOM_IMPLICIT_REFINE_ALWAYS if refine else lib.GEOM_IMPLICIT_REFINE_NEVER)
    out = ffi.new("geom_implicit_isolines *")
    diag = new_diag()
    st = lib.geom_implicit_contour(f, dptr(b4), nx, ny, opt, out, diag)
    try:
        if error_box:
            raise error_box[0]
        check(st, diag, context="contour")
        return take(out)
    finally:
        lib.geom_implicit_isolines_free(out)
        del keep


def _contour_report(out):
    r = out.report
    return {"error": error_report(r.error), "unmeasured": int(r.unmeasured),
            "seconds": float(r.seconds), "cells": int(r.cells), "saddles": int(r.saddles),
            "refined": int(r.refined), "nan_nodes": int(r.nan_nodes)}


def _isoline_arrays(out):
    nv, npl = int(out.n_vertices), int(out.n_polylines)
    xy = (np.frombuffer(ffi.buffer(out.xy, 16 * nv), dtype=np.float64).reshape(nv, 2).copy()
          if nv else np.empty((0, 2)))
    start = np.frombuffer(ffi.buffer(out.start, ffi.sizeof("size_t") * (npl + 1)),
                          dtype=np.uintp).astype(np.int64)
    idx = (np.frombuffer(ffi.buffer(out.indices, 4 * int(start[-1])), dtype=np.uint32).copy()
           if start[-1] else np.empty(0, dtype=np.uint32))
    lines = [idx[start[k]:start[k + 1]] for k in range(npl)]
    closed = (np.frombuffer(ffi.buffer(out.closed, npl), dtype=np.uint8).astype(bool)
              if npl else np.empty(0, dtype=bool))
    return xy, lines, closed, _contour_report(out)


def contour(field, bounds, resolution, iso=0.0, z=0.0, refine=None):
    """Isolines f(x, y, z) = iso of a 2-D slice by marching squares with the
    asymptotic decider (geom_implicit_contour): field an expression string,
    an Expression or a Python function of (n, 3) points; bounds (x0, y0,
    x1, y1) split into resolution (nx, ny) cells. refine: None (the
    default: refine exact fields), True or False.

    Returns (xy (n, 2), polylines, closed, report): polylines a list of
    vertex-index arrays (closed loops list each vertex once, inside f <= iso
    on the left), closed a bool array, report the achieved error (distance
    estimate |f - iso| / |grad f| at the vertices) and the counts."""
    return _contour(field, bounds, resolution, iso, z, refine, _isoline_arrays)


def contour_mesh(field, bounds, resolution, iso=0.0, z=0.0, refine=None):
    """contour() as a Mesh of polylines, ready for Mesh.write (OBJ `l`
    lines): vertices (x, y, z) at the slice height z, one polyline per
    isoline, a closed loop repeating its first vertex at the end
    (geom_implicit_isolines_to_mesh). Returns (Mesh, report); arguments,
    report and errors as contour()."""
    def take(out):
        m = Mesh()
        st = lib.geom_implicit_isolines_to_mesh(out, float(z), m._ptr)
        if st != 0:
            m.close()
            check(st, context="contour_mesh")
        return m, _contour_report(out)
    return _contour(field, bounds, resolution, iso, z, refine, take)


def contour_estimate(field, bounds, resolution, iso=0.0, z=0.0):
    """(vertices, cells): the vertices contour() would make, estimated from
    at most 65^2 samples (features thinner than a coarse cell are missed),
    and the grid cells it would sample (exact)."""
    keep, error_box = [], []
    f, b4, nx, ny, opt = _contour_args(field, bounds, resolution, iso, z, keep, error_box)
    v, c = ffi.new("double *"), ffi.new("double *")
    st = lib.geom_implicit_contour_estimate(f, dptr(b4), nx, ny, opt, v)
    if st == 0:
        st = lib.geom_implicit_contour_estimate_cells(f, dptr(b4), nx, ny, opt, c)
    if error_box:
        raise error_box[0]
    check(st, context="contour_estimate")
    return float(v[0]), float(c[0])

def _iso_report(r):
    return {
        "vertex_error": error_report(r.vertex_error),
        "sample_error": error_report(r.sample_error),
        "unmeasured": int(r.unmeasured),
        "seconds": float(r.seconds),
        "error_seconds": float(r.error_seconds),
        "cells": int(r.cells),
        "active_cells": int(r.active_cells),
        "ambiguous_faces": int(r.ambiguous_faces),
        "tunnels": int(r.tunnels),
        "iso_nodes": int(r.iso_nodes),
        "nan_nodes": int(r.nan_nodes),
        "refined": int(r.refined),
        "slabs": int(r.slabs),
        "threads": int(r.threads),
    }


_EXACT32 = {np.dtype(t) for t in ("u1", "i1", "u2", "i2", "f2", "f4", "?")}
_EXACT64 = {np.dtype(t) for t in ("u4", "i4", "f8")}


def volume_dtype(dtype):
    """The sample type libgeom computes with for a numpy dtype: float32 for
    8/16-bit integers, bool, float16 and float32; float64 for 32-bit
    integers and float64 (every value exact, either byte order). Any other
    dtype (64-bit integers, complex, float128, objects, strings) raises
    TypeError instead of being converted with a loss."""
    dt = np.dtype(dtype).newbyteorder("=")
    if dt in _EXACT32:
        return np.float32
    if dt in _EXACT64:
        return np.float64
    raise TypeError("volume samples of dtype %s cannot be read exactly; convert them to "
                    "float32 or float64 first" % np.dtype(dtype))


_FORMATS = {None: 0, "auto": 0, "raw": 1, "nrrd": 2, "metaimage": 3, "mha": 3, "mhd": 3,
            "inrimage": 4, "inr": 4, "nifti": 5, "nii": 5}
_FORMAT_NAMES = {0: "auto", 1: "raw", 2: "nrrd", 3: "metaimage", 4: "inrimage", 5: "nifti"}
_SAMPLES = {"u1": "u8", "i1": "i8", "u2": "u16", "i2": "i16", "u4": "u32", "i4": "i32",
            "f4": "f32", "f8": "f64"}


@ffi.callback("geom_status(void *, const void *, size_t, void *, size_t, size_t *)",
              error=lib.GEOM_ERR_PARSE)
def _inflate(user, src, n, dst, cap, got):
    import zlib
    try:
        data = zlib.decompressobj(47).decompress(bytes(ffi.buffer(src, n)), cap + 1)
    except zlib.error:
        return lib.GEOM_ERR_PARSE
    return _deliver(data, dst, cap, got)


def _deliver(data, dst, cap, got):
    """The end of a decompression callback: data into dst (cap bytes)."""
    got[0] = len(data)
    if len(data) > cap:
        return lib.GEOM_ERR_LIMIT
    ffi.memmove(dst, data, len(data))
    return 0


@ffi.callback("geom_status(void *, const void *, size_t, void *, size_t, size_t *)",
              error=lib.GEOM_ERR_PARSE)
def _bunzip2(user, src, n, dst, cap, got):
    import bz2
    data, rest = b"", bytes(ffi.buffer(src, n))
    try:
        while rest:  # concatenated streams, as the bzip2 program reads them
            d = bz2.BZ2Decompressor()
            data += d.decompress(rest, cap + 1 - len(data))
            if len(data) > cap:
                break
            if not d.eof:
                return lib.GEOM_ERR_PARSE  # truncated
            rest = d.unused_data
    except (OSError, ValueError, EOFError):
        return lib.GEOM_ERR_PARSE
    return _deliver(data, dst, cap, got)


class Volume:
    """A sampled volume read from a file (read_volume): samples[i, j, k]
    (x index first; float32 or float64 as read_volume says), spacing and
    origin (3-tuples from the header), and info (format, the file's sample
    type, compressed, flipped axes, scaled). eval(points) interpolates
    trilinearly in C (geom_implicit_volume_eval_many); marching_cubes(vol)
    uses its placement."""

    def __init__(self, samples, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), info=None):
        arr = np.asarray(samples)
        if arr.ndim != 3:
            raise ValueError("a volume must be a 3-D array")
        self.samples = np.asfortranarray(arr, dtype=volume_dtype(arr.dtype))
        self.spacing = tuple(float(x) for x in spacing)
        self.origin = tuple(float(x) for x in origin)
        self.info = dict(info or {})

    shape = property(lambda self: self.samples.shape)

    def __repr__(self):
        return "<geom.Volume %dx%dx%d %s, spacing %s, origin %s>" % (
            self.shape + (self.samples.dtype, self.spacing, self.origin))

    def _c(self):
        d = ffi.new("geom_implicit_volume_desc *")
        d.dims = list(self.samples.shape)
        f32 = self.samples.dtype == np.float32
        d.type = lib.GEOM_IMPLICIT_SCALAR_F32 if f32 else lib.GEOM_IMPLICIT_SCALAR_F64
        d.spacing = list(self.spacing)
        d.origin = list(self.origin)
        out = ffi.new("geom_implicit_volume **")
        check(lib.geom_implicit_volume_create(d, ffi.NULL, out), context="Volume")
        v = ffi.gc(out[0], lib.geom_implicit_volume_destroy)
        flat = self.samples.reshape(-1, order="F")
        ffi.memmove(lib.geom_implicit_volume_data(v), ffi.from_buffer(flat), flat.nbytes)
        return v

    @property
    def bounds(self):
        """(lo, hi): the box the samples span, origin .. origin + (dims - 1)
        * spacing (geom_implicit_volume_bounds), where eval interpolates."""
        b = lib.geom_implicit_volume_bounds(self._c())
        return (np.array([b.min.x, b.min.y, b.min.z]), np.array([b.max.x, b.max.y, b.max.z]))

    def detect_inside(self, iso):
        """Which side of iso is the inside, from the samples on the grid's six
        faces (taken to lie outside; geom_implicit_volume_detect_inside, the
        detection geom-iso and scene files use): "above" (f >= iso inside, a
        CT volume, dense inside) when more than half of them are < iso, else
        "below". Returns (side, face samples < iso, face samples)."""
        above = ffi.new("int *")
        below = ffi.new("size_t *")
        total = ffi.new("size_t *")
        check(lib.geom_implicit_volume_detect_inside(self._c(), float(iso), above, below, total),
              context="detect_inside")
        return ("above" if above[0] else "below", int(below[0]), int(total[0]))

    def eval(self, points, gradient=False):
        """Trilinear values at points ((3,) or (n, 3)); with gradient=True
        also the interpolated central-difference gradients ((n, 3))."""
        v = self._c()
        pts = np.ascontiguousarray(points, dtype=np.float64)
        single = pts.ndim == 1
        pts = pts.reshape(-1, 3)
        out = np.empty(pts.shape[0])
        grad = np.empty((pts.shape[0], 3)) if gradient else None
        lib.geom_implicit_volume_eval_many(v, pts.shape[0], ffi.from_buffer("double[]", pts),
                                           ffi.from_buffer("double[]", out),
                                           ffi.from_buffer("double[]", grad) if gradient
                                           else ffi.NULL)
        if single:
            return (out[0], grad[0]) if gradient else out[0]
        return (out, grad) if gradient else out

    __call__ = eval


def read_volume(path_or_bytes, dims=None, dtype=None, spacing=None, origin=None,
                big_endian=False, skip=0, format=None, source_name=None):
    """Read a volume file (geom_implicit_volume_read): NRRD (.nrrd, .nhdr;
    raw, ascii, hex, gzip, bzip2), MetaImage (.mha, .mhd), INRIMAGE (.inr)
    and NIfTI-1 (.nii, .hdr/.img), each possibly gzipped or bzip2-compressed
    (decompressed with Python's zlib and bz2), with spacing and origin from
    the header (a spacing the header leaves unknown, NRRD nan, or gives
    invalid, NIfTI pixdim <= 0, is read as 1 with a RuntimeWarning and
    listed in info["warnings"]); or raw samples: dims
    (nx, ny, nz) and dtype (a numpy dtype or "u8".."f64"; 64-bit integers
    and complex raise TypeError) after `skip` header bytes, x fastest.
    path_or_bytes is a path or a bytes-like object. Returns a Volume.
    GeomError ERR_IO / ERR_PARSE (with the file and line or byte offset)."""
    opt = ffi.new("geom_implicit_volume_read_options *")
    fmt = format.lower() if isinstance(format, str) else format
    if fmt not in _FORMATS:
        raise ValueError("unknown volume format %r" % (format,))
    opt.format = _FORMATS[fmt]
    if dims is not None:
        if dtype is None:
            raise ValueError("raw volumes need dims and dtype")
        opt.dims = [int(x) for x in dims]
        # numpy's meaning first ("i8" is int64 and refused; np.uint8, "uint8",
        # "u1" are bytes), then libgeom's names ("u16", "f32", ...)
        try:
            name = _SAMPLES.get(np.dtype(dtype).str[1:], "?")
        except TypeError:
            name = str(dtype)
        sample = ffi.new("geom_implicit_sample *")
        if lib.geom_implicit_sample_parse(name.encode(), sample) != 0:
            raise TypeError("raw volume samples of dtype %r cannot be read (u8, i8, u16, i16, "
                            "u32, i32, f32, f64)" % (dtype,))
        opt.sample = sample[0]
        if opt.format == 0:
            opt.format = 1
        opt.big_endian = 1 if big_endian else 0
        opt.skip = int(skip)
        if spacing is not None:
            opt.spacing = [float(x) for x in spacing]
        if origin is not None:
            opt.origin = [float(x) for x in origin]
    opt.inflate = _inflate
    opt.bunzip2 = _bunzip2
    out = ffi.new("geom_implicit_volume **")
    info = ffi.new("geom_implicit_volume_file_info *")
    diag = new_diag()
    if isinstance(path_or_bytes, (bytes, bytearray, memoryview)):
        buf = ffi.from_buffer(path_or_bytes)
        where = source_name or "<memory>"
        name = where.encode()
        st = lib.geom_implicit_volume_read_memory(buf, len(buf), name, opt, ffi.NULL, out, info,
                                                  diag)
    else:
        path = os.fspath(path_or_bytes)
        where = path if isinstance(path, str) else os.fsdecode(path)
        raw = path.encode() if isinstance(path, str) else path
        if b"\0" in raw:
            raise ValueError("path contains a NUL byte")
        st = lib.geom_implicit_volume_read(raw, opt, ffi.NULL, out, info, diag)
    check(st, diag, context="read_volume")
    v = ffi.gc(out[0], lib.geom_implicit_volume_destroy)
    d = ffi.new("geom_implicit_volume_desc *")
    lib.geom_implicit_volume_get_desc(v, d)
    shape = tuple(int(x) for x in d.dims)
    f32 = d.type == lib.GEOM_IMPLICIT_SCALAR_F32
    count = shape[0] * shape[1] * shape[2]
    data = np.frombuffer(ffi.buffer(lib.geom_implicit_volume_cdata(v), count * (4 if f32 else 8)),
                         dtype=np.float32 if f32 else np.float64).copy()
    meta = {"format": _FORMAT_NAMES.get(int(info.format), "?"),
            "sample": ffi.string(lib.geom_implicit_sample_name(info.sample)).decode(),
            "compressed": bool(info.compressed),
            "flipped": tuple(bool(x) for x in info.flipped),
            "scaled": bool(info.scaled),
            "spacing_defaulted": tuple(bool(x) for x in info.spacing_defaulted),
            "warnings": []}
    if any(meta["spacing_defaulted"]):
        # the header's spacing was unknown (NRRD nan) or invalid (NIfTI
        # pixdim <= 0): read as 1, never silently
        note = ffi.string(info.spacing_note).decode("utf-8", "replace")
        meta["warnings"].append(note)
        import warnings
        warnings.warn("%s: %s" % (where, note), RuntimeWarning, stacklevel=2)
    return Volume(data.reshape(shape, order="F"), tuple(d.spacing), tuple(d.origin), meta)


__all__ = ["Expression", "Volume", "marching_cubes", "read_volume", "volume_dtype"]


# ------------------------------------------------------------ root finding

def bracket_root(fn, a, b, x=None, max_iterations=100, fa=None, fb=None):
    """A root of the Python function fn (a float -> float) in the open
    interval (a, b), a < b, with fn(a) and fn(b) of opposite strict signs
    (geom_implicit_bracket_root: Illinois regula falsi with a bisection step
    whenever the bracket has not halved over two steps; the stopping rule
    of the library's contouring). Starts from x (default: the linear
    interpolation of the end values; moved to the midpoint when not
    strictly inside). Stops when the bracket ends are adjacent doubles, fn
    is exactly 0 (that point is returned), fn is NaN, or max_iterations
    evaluations were made; then returns the end of the final bracket with
    the smaller |fn| (at a jump of fn, a point next to the jump), always
    strictly inside (a, b). So for a continuous fn, the result is within
    one ulp of a root unless max_iterations stopped it first.

    fa, fb: fn(a) and fn(b) if already known (else fn is called at a and
    b here, not counted in the evaluations). Returns (root, evaluations):
    the calls the C root finder made. Raises ValueError for a >= b, a NaN
    end, end values that are not of opposite strict signs, or
    max_iterations < 1; an exception raised by fn is re-raised (the root
    finder stops at the NaN it then sees). One root per call: libgeom has
    no batch form (marching cubes and contour() refine their edges in C)."""
    a, b = float(a), float(b)
    if not a < b:
        raise ValueError("bracket_root needs a < b, got a=%r, b=%r" % (a, b))
    fa = float(fn(a)) if fa is None else float(fa)
    fb = float(fn(b)) if fb is None else float(fb)
    if not ((fa < 0 < fb) or (fb < 0 < fa)):
        raise ValueError("bracket_root: fn(a)=%r and fn(b)=%r are not of opposite strict signs"
                         % (fa, fb))
    if int(max_iterations) < 1:
        raise ValueError("max_iterations must be >= 1, got %r" % (max_iterations,))
    if x is None:
        x = a + (b - a) * fa / (fa - fb)
    errors = []

    def on_error(exc_type, exc_value, tb):
        if not errors:
            errors.append(exc_value)

    @ffi.callback("double(void *, double)", onerror=on_error, error=float("nan"))
    def cb(user, t):
        return float(fn(t))

    evals = ffi.new("size_t *")
    root = lib.geom_implicit_bracket_root(cb, ffi.NULL, a, b, fa, fb, float(x),
                                          int(max_iterations), evals)
    if errors:
        raise errors[0]
    return float(root), int(evals[0])
