"""STEP (ISO 10303-21) B-reps (geom/step.h): read a file, evaluate its
surfaces and curves, estimate and make a watertight tessellation.

    b = geom.step.Brep.read("part.step")            # lengths in millimetres
    total, per_face = b.estimate(tolerance=0.01)
    mesh, report = b.tessellate(tolerance=0.01, normals=True)

report: "error" (the achieved chordal error report), "faces" (per face:
chordal_error, edge_gap, triangles, status) and the totals of
geom_brep_tess_stats (faces_failed, open_edges, edge_gap, ...).
"""
import numpy as np

from ._ffi import ffi, lib
from .core import check, error_report, flag_bits, new_diag, struct_dict

_ATTR = {"normal": 1, "uv": 2, "source": 8}  # GEOM_SURFACE_ATTR_* (surface.h macros)


class Brep:
    """A geom_brep read from STEP text. Sizes in .counts, the file's unit
    in metres in .unit_metres, what the reader skipped in .issues."""

    def __init__(self, ptr):
        self._b = ffi.gc(ptr, lib.geom_step_destroy)

    @staticmethod
    def _options(unit_metres, strict, max_bytes):
        o = ffi.new("geom_step_read_options *")
        o.unit_metres = float(unit_metres)
        o.strict = 1 if strict else 0
        o.max_bytes = int(max_bytes)
        return o

    @classmethod
    def read(cls, path, unit_metres=0.0, strict=False, max_bytes=0):
        """Read a .step/.stp file; unit_metres: the output unit (0: mm);
        strict: unsupported entities are errors instead of issues."""
        out = ffi.new("geom_brep **")
        diag = new_diag()
        check(lib.geom_step_read(str(path).encode(), cls._options(unit_metres, strict, max_bytes),
                                 out, diag), diag, "step.read")
        return cls(out[0])

    @classmethod
    def from_bytes(cls, data, source_name=None, unit_metres=0.0, strict=False, max_bytes=0):
        """As read, from the file's contents (bytes or str)."""
        if isinstance(data, str):
            data = data.encode()
        buf = ffi.from_buffer(bytes(data))
        out = ffi.new("geom_brep **")
        diag = new_diag()
        name = ffi.NULL if source_name is None else str(source_name).encode()
        check(lib.geom_step_read_memory(buf, len(data), name,
                                        cls._options(unit_metres, strict, max_bytes), out, diag),
              diag, "step.from_bytes")
        return cls(out[0])

    @property
    def counts(self):
        b = self._b
        return {k: int(getattr(b, "n" + k)) for k in (
            "solids", "shells", "faces", "loops", "coedges", "edges", "vertices", "curves",
            "surfaces", "issues", "skipped_faces", "instances") if hasattr(b, "n" + k)}

    @property
    def unit_metres(self):
        return float(self._b.unit_metres)

    @property
    def issues(self):
        """[(entity number, type, reason)] of what was skipped."""
        return [(int(i.entity), ffi.string(i.type).decode(), ffi.string(i.reason).decode())
                for i in (self._b.issues[k] for k in range(self._b.nissues))]

    def surface_type(self, s):
        names = ("plane", "cylinder", "cone", "sphere", "torus", "nurbs", "revolution", "extrusion")
        return names[int(self._b.surfaces[self._index(s, self._b.nsurfaces)].type)]

    @staticmethod
    def _index(i, n):
        i = int(i)
        if not 0 <= i < n:
            raise IndexError("index %d out of 0..%d" % (i, n - 1))
        return i

    def surface_eval(self, s, u, v):
        """(S(u, v), dS/du, dS/dv) of surface s."""
        p, du, dv = (ffi.new("double[3]") for _ in range(3))
        check(lib.geom_step_surface_eval(self._b, self._index(s, self._b.nsurfaces), float(u),
                                         float(v), p, du, dv), context="surface_eval")
        return tuple(np.array(list(x)) for x in (p, du, dv))

    def curve_eval(self, c, t):
        """C(t) of curve c (2 or 3 numbers: pcurves are 2-D)."""
        c = self._index(c, self._b.ncurves)
        p = ffi.new("double[3]")
        check(lib.geom_step_curve_eval(self._b, c, float(t), p), context="curve_eval")
        return np.array(list(p)[:int(self._b.curves[c].dim) or 3])

    @staticmethod
    def _tess_options(tolerance, angle, attributes, max_triangles):
        o = ffi.new("geom_brep_tess_options *")
        o.tolerance = float(tolerance)
        o.angle_degrees = float(angle)
        o.attributes = flag_bits(_ATTR, attributes, "attributes")
        o.max_triangles = int(max_triangles)
        return o

    def estimate(self, tolerance=0.0, angle=0.0):
        """(total, per_face array) of the triangles tessellate would make
        with these options, before the work (geom_step_tess_estimate)."""
        tot = ffi.new("double *")
        per = np.zeros(max(int(self._b.nfaces), 1))
        check(lib.geom_step_tess_estimate(self._b, self._tess_options(tolerance, angle, (), 0), tot,
                                          ffi.from_buffer("double[]", per)), context="estimate")
        return float(tot[0]), per[:int(self._b.nfaces)]

    def tessellate(self, tolerance=0.0, angle=0.0, attributes=(), max_triangles=0):
        """(Mesh, report) of every face (geom_step_tessellate): tolerance in
        output units (0: 1e-3 of the model's diagonal), angle in degrees
        (0: none), attributes any of "normal", "uv", "source"."""
        from .mesh import Mesh
        m = Mesh()
        rep = ffi.new("geom_error_report *")
        nf = int(self._b.nfaces)
        faces = ffi.new("geom_brep_face_report[]", max(nf, 1))
        stats = ffi.new("geom_brep_tess_stats *")
        diag = new_diag()
        st = lib.geom_step_tessellate(self._b, self._tess_options(tolerance, angle, attributes,
                                                                  max_triangles),
                                      m._ptr, rep, faces, stats, diag)
        if st != 0:
            m.close()
            check(st, diag, "tessellate")
        report = struct_dict(stats[0], "geom_brep_tess_stats")
        report["error"] = error_report(rep[0])
        report["faces"] = [struct_dict(faces[i], "geom_brep_face_report") for i in range(nf)]
        return m, report
