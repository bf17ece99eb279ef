"""geom.scene: cameras, and the tessellation of a RayScene's objects with its
triangle estimates (Shapes, export_estimate; rendering is reached through the
geom-render and geom-scene tools)."""
import numpy as np

from ._ffi import ffi, lib
from .core import check, new_diag


def camera(eye, center, up=(0, 1, 0), fovy=45.0, width=320, height=240, orthographic=False,
           ortho_height=2.0):
    """A geom_camera (cffi struct) as gluLookAt + gluPerspective or glOrtho."""
    c = ffi.new("geom_camera *")
    c.eye = list(map(float, eye))
    c.center = list(map(float, center))
    c.up = list(map(float, up))
    c.fovy_degrees = fovy
    c.projection = lib.GEOM_PROJECTION_ORTHOGRAPHIC if orthographic else lib.GEOM_PROJECTION_PERSPECTIVE
    c.ortho_height = ortho_height
    c.width = width
    c.height = height
    return c


def camera_ray(cam, x, y):
    """(origin, unit direction) of the primary ray through pixel point (x, y)."""
    r = ffi.new("geom_ray *")
    check(lib.geom_scene_camera_ray(cam, x, y, r))
    return (np.array([r.origin.x, r.origin.y, r.origin.z]),
            np.array([r.dir.x, r.dir.y, r.dir.z]))


def project(cam, p):
    """Pixel coordinates (x, y) and view depth of world point p."""
    out = ffi.new("double[3]")
    v = ffi.new("geom_vec3 *", list(map(float, p)))
    check(lib.geom_scene_camera_project(cam, v[0], out))
    return np.array([out[0], out[1], out[2]])


def camera_matrices(cam, near, far):
    """(view, projection) numpy (4, 4) matrices M[row, col] (OpenGL
    convention) of the camera with these near and far distances."""
    from .core import from_mat4
    v, p = ffi.new("geom_mat4 *"), ffi.new("geom_mat4 *")
    check(lib.geom_scene_camera_matrices(cam, float(near), float(far), v, p),
          context="camera_matrices")
    return from_mat4(v[0]), from_mat4(p[0])


def pixel_size(cam, depth):
    """World size of one pixel at view depth `depth`."""
    return float(lib.geom_scene_camera_pixel_size(cam, float(depth)))


def pixel_tolerance(cam, lo, hi, pixel_error=0.5):
    """(chordal tolerance, visible) that keeps the projected error of an
    object with world box [lo, hi] below pixel_error pixels
    (geom_scene_pixel_tolerance)."""
    box = ffi.new("geom_aabb *")
    box.min.x, box.min.y, box.min.z = (float(v) for v in lo)
    box.max.x, box.max.y, box.max.z = (float(v) for v in hi)
    vis = ffi.new("int *")
    t = lib.geom_scene_pixel_tolerance(cam, box[0], float(pixel_error), vis)
    return float(t), bool(vis[0])


def mesh_transform(mesh, matrix):
    """Apply a (4, 4) affine matrix to a Mesh in place: positions, normals
    (inverse transpose, renormalised) and tangents."""
    from .core import to_mat4
    check(lib.geom_scene_mesh_transform(mesh._ptr, to_mat4(matrix)), context="mesh_transform")


# ------------------------------------------------------------ tessellation

_NEEDS = {"uv": 1, "tangent": 2, "normal": 4}  # GEOM_NEEDS_* (scene.h, an anonymous enum)


def _request(tol, attributes, extent):
    rq = ffi.new("geom_tess_request *")
    tol = float(tol)
    if not (tol > 0 and np.isfinite(tol)):
        raise ValueError("tol must be a finite number > 0, got %r" % (tol,))
    rq.tol = tol
    bits = 0
    for a in attributes:
        if a not in _NEEDS:
            raise ValueError("attributes are 'normal', 'uv', 'tangent', got %r" % (a,))
        bits |= _NEEDS[a]
    rq.attributes = bits
    if extent is not None:
        e = np.asarray(extent, dtype=np.float64).reshape(6)
        rq.extent.min.x, rq.extent.min.y, rq.extent.min.z = (float(v) for v in e[:3])
        rq.extent.max.x, rq.extent.max.y, rq.extent.max.z = (float(v) for v in e[3:])
    return rq


class Shapes:
    """The top-level objects of a geom.ray.RayScene as shapes to tessellate
    (geom_scene_shapes_from_ray): len(), kind(i), and per object the
    triangle estimate and the tessellation geom-scene --export and the
    rasteriser use. The RayScene must stay alive (it is kept referenced)."""

    def __init__(self, ray_scene):
        out = ffi.new("geom_scene_shapes **")
        diag = new_diag()
        check(lib.geom_scene_shapes_from_ray(ray_scene._s, out, diag), diag, "Shapes")
        self._p = ffi.gc(out[0], lib.geom_scene_shapes_destroy)
        self._scene = ray_scene

    def __len__(self):
        return int(lib.geom_scene_shapes_count(self._p))

    def _get(self, i):
        i = int(i)
        if not 0 <= i < len(self):
            raise IndexError("shape %d out of 0..%d" % (i, len(self) - 1))
        return lib.geom_scene_shapes_get(self._p, i)

    def bounds(self, i):
        """(lo, hi) of object i in its own frame (infinite for unbounded
        shapes)."""
        b = lib.geom_scene_shape_bounds(self._get(i))
        return (np.array([b.min.x, b.min.y, b.min.z]), np.array([b.max.x, b.max.y, b.max.z]))

    def kind(self, i):
        """The ray-module kind name of object i ("sphere", "mesh", ...)."""
        self._get(i)
        return ffi.string(lib.geom_scene_shapes_kind_name(self._p, int(i))).decode()

    def estimate(self, i, tol, attributes=(), extent=None):
        """Triangles tessellate(i, tol, ...) would make, estimated before the
        work (geom_scene_tessellate_estimate: exact for boxes, planes,
        polygons, disks and meshes; within about 2x for spheres, tori and
        surfaces; marching cubes' estimate for implicit kinds)."""
        out = ffi.new("double *")
        check(lib.geom_scene_tessellate_estimate(self._get(i), _request(tol, attributes, extent),
                                                 out), context="estimate")
        return float(out[0])

    def tessellate(self, i, tol, attributes=(), extent=None):
        """(Mesh, info) of object i in its own frame (its transform not
        applied), to chordal tolerance tol; attributes: any of "normal",
        "uv", "tangent" (CORNER channels where the method makes them);
        extent (x0, y0, z0, x1, y1, z1) cuts unbounded shapes. info: the
        achieved error report, triangles, seconds, method."""
        from .core import error_report
        from .mesh import Mesh
        m = Mesh()
        info = ffi.new("geom_tess_info *")
        diag = new_diag()
        st = lib.geom_scene_tessellate(self._get(i), _request(tol, attributes, extent), m._ptr,
                                       info, diag)
        if st != 0:
            m.close()
            check(st, diag, "tessellate")
        return m, {"error": error_report(info.error), "triangles": int(info.triangles),
                   "seconds": float(info.seconds),
                   "method": ffi.string(info.method).decode() if info.method != ffi.NULL else ""}


def export_estimate(shapes, tolerance=0.0, camera=None, pixel_error=0.0):
    """(total, per_object array) of the triangles geom-scene --export would
    make for every object of shapes with the default material (normals
    only): a world tolerance, or the camera's pixel-error tolerance per
    object (geom_scene_export_estimate; an estimate, not a bound)."""
    n = len(shapes)
    objs = ffi.new("geom_scene_object[]", max(n, 1))
    for i in range(n):
        objs[i].shape = shapes._get(i)
        objs[i].material = 0
    mat = ffi.new("geom_material *", lib.geom_scene_material_default())
    opt = ffi.new("geom_export_options *")
    opt.tolerance = float(tolerance)
    opt.pixel_error = float(pixel_error)
    per = np.zeros(n, dtype=np.float64)
    tot = ffi.new("double *")
    diag = new_diag()
    check(lib.geom_scene_export_estimate(camera if camera is not None else ffi.NULL, mat, 1, objs, n,
                                         opt, ffi.from_buffer("double[]", per) if n else ffi.NULL,
                                         tot, diag), diag, "export_estimate")
    return float(tot[0]), per
