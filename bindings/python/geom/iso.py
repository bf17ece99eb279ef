"""Isosurfaces piece by piece and their size before the work (geom/iso.h).

extract_stream() runs geom_iso_extract_stream: the surface of an expression
(or a Python function) over a grid arrives in chunks, one per slab of cell
layers, instead of as one mesh, so a large surface can be written (or
reduced) as it comes without holding it whole:

    for c in iso.chunks("sphere(1)", (-2,) * 3 + (2,) * 3, (256,) * 3):
        write(c["vertices"], c["triangles"])        # numpy copies

or with a callback on the calling thread:

    report = iso.extract_stream(field, bounds, res, on_chunk)

Each chunk is a dict: "first_vertex" (the number of its first vertex in
the whole surface), "vertices" (n, 3) float64, "normals" (n, 3) or None,
"triangles" (m, 3) uint32 (numbers in the whole surface: a triangle may use
earlier chunks' vertices), "caps" (True for the last chunk of cap
triangles). The chunks concatenated are marching_cubes' surface, in the
same order.

estimate_triangles() gives the triangle count marching_cubes would make,
from a coarse pass (geom_iso_estimate_triangles) or, for a sampled volume,
one pass over its cells (geom_iso_grid_estimate_triangles).
"""
import queue
import threading

import numpy as np

from ._ffi import ffi, lib
from .core import check, dptr, new_diag
from .implicit import _function_field, _grid_field, _iso_options, _iso_report

_STOP = lib.GEOM_ERR_LIMIT  # the status a callback returns to stop the extraction


def _chunk_dict(c):
    nv, nt = int(c.n_vertices), int(c.n_triangles)
    return {
        "first_vertex": int(c.first_vertex),
        "vertices": (np.frombuffer(ffi.buffer(c.xyz, 24 * nv), dtype=np.float64).reshape(nv, 3).copy()
                     if nv else np.empty((0, 3))),
        "normals": (None if c.normals == ffi.NULL else
                    np.frombuffer(ffi.buffer(c.normals, 24 * nv), dtype=np.float64).reshape(nv, 3).copy()),
        "triangles": (np.frombuffer(ffi.buffer(c.tris, 12 * nt), dtype=np.uint32).reshape(nt, 3).copy()
                      if nt else np.empty((0, 3), dtype=np.uint32)),
        "caps": bool(c.caps),
    }


def extract_stream(field, bounds, resolution, on_chunk, iso=0.0, refine=False, normals=False,
                   caps=False, error="auto", threads=0):
    """Marching cubes of field (an expression string, an Expression or a
    Python function of (n, 3) points, as for marching_cubes) over bounds
    (x0, y0, z0, x1, y1, z1) split into resolution (nx, ny, nz) cells,
    handing each chunk (a dict, see the module) to on_chunk(chunk) on the
    calling thread, in order. on_chunk returning False stops the extraction
    (GeomError ERR_LIMIT is not raised then; the report says how far it
    got); an exception it raises stops it and is raised. Returns the report
    of marching_cubes plus "n_vertices", "n_triangles", "n_cap_triangles"
    and "stopped"."""
    opt = _iso_options(iso, refine, normals, caps, error, threads)
    keep, error_box, stopped = [], [], []
    f, b, res, single = _function_field(field, bounds, resolution, keep, error_box)
    if single:
        opt.threads = 1

    def on_error(exc_type, exc_value, tb):
        if not error_box:
            error_box.append(exc_value)

    @ffi.callback("geom_status(void *, const geom_iso_chunk *)", onerror=on_error,
                  error=lib.GEOM_ERR_INVALID_ARG)
    def chunk_cb(user, c):
        if error_box:
            return lib.GEOM_ERR_INVALID_ARG
        if on_chunk(_chunk_dict(c)) is False:
            stopped.append(True)
            return _STOP
        return lib.GEOM_OK

    surf = ffi.new("geom_iso_surface *")
    diag = new_diag()
    st = lib.geom_iso_extract_stream(f, dptr(b), res, opt, chunk_cb, ffi.NULL, surf, diag)
    del keep
    if error_box:
        raise error_box[0]
    if not (stopped and st == _STOP):
        check(st, diag, context="extract_stream")
    report = _iso_report(surf.report)
    report.update(n_vertices=int(surf.n_vertices), n_triangles=int(surf.n_triangles),
                  n_cap_triangles=int(surf.n_cap_triangles), stopped=bool(stopped))
    return report


def chunks(field, bounds, resolution, **options):
    """A generator of the chunks extract_stream hands over (same arguments
    but on_chunk): the extraction runs on a worker thread, at most two
    chunks ahead of the consumer. Its return value (StopIteration.value,
    or `report = yield from chunks(...)`) is the report. Closing the
    generator early stops the extraction; an error is raised from the
    generator after the chunks made before it."""
    q = queue.Queue(maxsize=2)
    stop = threading.Event()
    result = []

    def put(item):
        while not stop.is_set():
            try:
                q.put(item, timeout=0.05)
                return True
            except queue.Full:
                continue
        return False

    def on_chunk(c):
        return put(("chunk", c))

    def work():
        try:
            result.append(extract_stream(field, bounds, resolution, on_chunk, **options))
            put(("done", None))
        except BaseException as exc:  # handed to the consumer
            put(("error", exc))

    t = threading.Thread(target=work, name="geom-iso-stream", daemon=True)
    t.start()
    try:
        while True:
            kind, item = q.get()
            if kind == "chunk":
                yield item
            elif kind == "error":
                raise item
            else:
                return result[0]
    finally:
        stop.set()
        t.join()


def estimate_triangles(field, bounds=None, resolution=None, iso=0.0, spacing=None, origin=None,
                       caps=False):
    """Triangles marching_cubes(field, ..., caps=caps) would make, estimated
    before the work: for an expression, Expression or function over bounds
    and resolution, from at most 41^3 samples (geom_iso_estimate_triangles:
    features thinner than a coarse cell are missed); for a 3-D array or a
    Volume, from its crossed cells (geom_iso_grid_estimate_triangles, 2 a
    cell). With caps=True the cap triangles on the box faces are included
    (counted exactly for an array or Volume)."""
    keep, error_box = [], []
    out = ffi.new("double *")
    opt = _iso_options(iso, False, False, caps, "auto", 0)
    grid = _grid_field(field, spacing, origin, keep)
    if grid is not None:
        check(lib.geom_iso_grid_estimate_triangles(grid, opt, out),
              context="estimate_triangles")
    else:
        f, b, res, _ = _function_field(field, bounds, resolution, keep, error_box)
        st = lib.geom_iso_estimate_triangles(f, dptr(b), res, opt, out)
        if error_box:
            raise error_box[0]
        check(st, context="estimate_triangles")
    return float(out[0])


def measure_error(field, vertices, triangles, iso=0.0):
    """The error of any triangle mesh (vertices (n, 3), triangles (m, 3))
    against the isosurface field = iso of an expression, Expression or
    Python function (geom_iso_measure_error): (vertex_error, sample_error,
    unmeasured), the reports marching_cubes gives for its own output
    (distance estimates |f - iso| / |grad f| at the vertices and at samples
    inside the triangles)."""
    from .core import error_report
    keep, error_box = [], []
    f, _, _, _ = _function_field(field, (0, 0, 0, 1, 1, 1), (1, 1, 1), keep, error_box)
    v = np.ascontiguousarray(vertices, dtype=np.float64).reshape(-1, 3)
    t = np.ascontiguousarray(triangles, dtype=np.uint32).reshape(-1, 3)
    ve, se = ffi.new("geom_error_report *"), ffi.new("geom_error_report *")
    un = ffi.new("size_t *")
    st = lib.geom_iso_measure_error(f, float(iso), v.shape[0], dptr(v), t.shape[0],
                                    ffi.cast("uint32_t *", ffi.from_buffer("uint32_t[]", t)),
                                    ve, se, un)
    if error_box:
        raise error_box[0]
    check(st, context="measure_error")
    return error_report(ve[0]), error_report(se[0]), int(un[0])
