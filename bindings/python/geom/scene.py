"""geom.scene: cameras, textures (Texture: MIP-mapped images, UV lookup),
materials with textures, bump, normal and displacement maps, the
tessellation of a RayScene's objects with its triangle estimates (Shapes,
export_estimate, export), whole-scene rendering (render, trace) and the
z-buffer rasterizer over caller-made draws (raster)."""
import numpy as np

from ._ffi import ffi, lib
from .core import check, flag_bits, new_diag


def camera(eye, center, up=(0, 1, 0), fovy=45.0, width=320, height=240, orthographic=False,
           ortho_height=2.0, samples=1):
    """A geom_camera (cffi struct) as gluLookAt + gluPerspective or glOrtho;
    samples per pixel on a regular k x k grid, k = ceil(sqrt(samples))."""
    c = ffi.new("geom_camera *")
    c.samples = int(samples)
    c.eye = list(map(float, eye))
    c.center = list(map(float, center))
    c.up = list(map(float, up))
    c.fovy_degrees = fovy
    c.projection = lib.GEOM_PROJECTION_ORTHOGRAPHIC if orthographic else lib.GEOM_PROJECTION_PERSPECTIVE
    c.ortho_height = ortho_height
    c.width = width
    c.height = height
    return c


def camera_resolved(cam):
    """A new camera with every 0 field replaced by its default
    (geom_scene_camera_resolved: 320 x 240 pixels, fovy 45 degrees, ortho
    height 2, up (0, 1, 0), 1 sample, ...): what render, trace and raster use."""
    c = ffi.new("geom_camera *")
    c[0] = lib.geom_scene_camera_resolved(cam)
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
    rq.attributes = flag_bits(_NEEDS, attributes, "attributes")
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
        """(lo, hi): the world box of object i (its transform applied;
        infinite for unbounded shapes)."""
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



def export(shapes, tolerance=0.0, camera=None, pixel_error=0.0, world=None, names=None,
           materials=({},), object_material=None):
    """(Mesh, reports): every object tessellated (geom_scene_export, as
    geom-scene --export: normals always, UVs/tangents where its material
    needs them) to a world tolerance or the camera's pixel-error
    tolerance, transformed, times world (a (4, 4) matrix, e.g. Z-up to
    glTF's Y-up) and joined, one face group per object (its "object" name from names)."""
    from .core import struct_dict, to_mat4
    from .mesh import Mesh
    n = len(shapes)
    objs = ffi.new("geom_scene_object[]", max(n, 1))
    om = [0] * n if object_material is None else [int(x) for x in object_material]
    for i in range(n):
        objs[i].shape = shapes._get(i)
        objs[i].material = om[i]
    M, nm, _textures = _materials(materials)
    opt = ffi.new("geom_export_options *")
    opt.tolerance, opt.pixel_error = float(tolerance), float(pixel_error)
    if world is not None:
        opt.world = to_mat4(world)
    keep = [ffi.new("char[]", str(x).encode()) for x in names] if names is not None else []
    nms = ffi.new("char *[]", keep) if keep else ffi.NULL
    reps = ffi.new("geom_export_object_report[]", max(n, 1))
    m = Mesh()
    diag = new_diag()
    st = lib.geom_scene_export(camera if camera is not None else ffi.NULL, M, nm, objs, n, nms,
                               opt, m._ptr, reps, diag)
    if st != 0:
        m.close()
        check(st, diag, "export")
    return m, [struct_dict(reps[i], "geom_export_object_report") for i in range(n)]

# ---------------------------------------------------------------- rendering

_AOV = {"color": 0, "depth": 1, "normal": 2, "object": 3}
_LIGHT = {"point": 0, "directional": 1, "ambient": 2}
_SHADING = {"phong": 0, "gouraud": 1, "flat": 2}
_SPECULAR = {"blinn": 0, "phong": 1}
_STYLE = {"standard": 0, "cool-to-warm": 1}


def _vec(v, what):
    a = np.broadcast_to(np.asarray(v, dtype=np.float64), (3,)) if np.ndim(v) == 0 else \
        np.asarray(v, dtype=np.float64).reshape(3)
    if not np.isfinite(a).all():
        raise ValueError("%s must be finite" % what)
    return [float(x) for x in a]


def _lights(lights):
    n = len(lights)
    arr = ffi.new("geom_light[]", max(n, 1))
    for i, d in enumerate(lights):
        kind = d.get("kind", "point")
        if kind not in _LIGHT:
            raise ValueError("light kind must be point, directional or ambient, got %r" % (kind,))
        arr[i].kind = _LIGHT[kind]
        for k in ("position", "direction"):
            if k in d:
                x, y, z = _vec(d[k], k)
                setattr(arr[i], k, {"x": x, "y": y, "z": z})
        x, y, z = _vec(d.get("color", 1.0), "color")
        arr[i].color = {"x": x, "y": y, "z": z}
    return arr, n


_TEXTURE_KEYS = ("texture", "bump", "normal_map", "displace")


def _materials(materials):
    """(geom_material[], count, textures kept alive) from dicts (keys as the
    scene JSON's "materials": ka, kd, ks (number or RGB), ns, specular,
    reflect, transmit, ior, shading, style, line_width, crease_degrees,
    gooch_b/y/alpha/beta; and Texture objects under texture, bump,
    normal_map, displace, with bump_scale and displace_scale); missing keys
    keep geom_scene_material_default's values. The caller holds the third
    value for as long as the array is used."""
    mats = list(materials) or [{}]
    arr = ffi.new("geom_material[]", len(mats))
    keep = []
    for i, d in enumerate(mats):
        m = lib.geom_scene_material_default()
        for k, v in d.items():
            if k in _TEXTURE_KEYS:
                if not isinstance(v, Texture):
                    raise ValueError("material key %r takes a geom.scene.Texture, got %r"
                                     % (k, type(v).__name__))
                keep.append(v)
                setattr(m, k, v._ptr)
            elif k in ("ka", "kd", "ks"):
                x, y, z = _vec(v, k)
                setattr(m, k, {"x": x, "y": y, "z": z})
            elif k == "specular":
                m.specular = _SPECULAR[v]
            elif k == "shading":
                m.shading = _SHADING[v]
            elif k == "style":
                m.style = _STYLE[v]
            elif k in ("ns", "reflect", "transmit", "ior", "line_width", "crease_degrees",
                       "gooch_b", "gooch_y", "gooch_alpha", "gooch_beta", "bump_scale",
                       "displace_scale"):
                setattr(m, k, float(v))
            else:
                raise ValueError("unknown material key %r" % (k,))
        arr[i] = m
    return arr, len(mats), keep


def material_needs(material):
    """What a material (a dict as in render's materials) needs from the
    geometry (geom_scene_material_needs): a set of "uv" (a texture, bump,
    normal or displacement map), "tangent" (normal or bump map), "normal",
    "reflection" (reflect > 0) and "refraction" (transmit > 0)."""
    M, _, keep = _materials([material])
    bits = int(lib.geom_scene_material_needs(M))
    del keep
    return {name for name, bit in (("uv", 1), ("tangent", 2), ("normal", 4), ("reflection", 8),
                                   ("refraction", 16)) if bits & bit}


def _image(img):
    try:
        w, h, c = int(img.width), int(img.height), int(img.channels)
        return np.frombuffer(ffi.buffer(img.data, 8 * w * h * c), dtype=np.float64).reshape(h, w, c).copy()
    finally:
        lib.geom_scene_image_free(img, ffi.NULL)


def _picture_setup(ctype, aov, background, lights, materials):
    """(options of ctype with aov and background set, lights, n_lights,
    materials, n_materials, textures to keep alive) for render, trace and
    raster."""
    if aov not in _AOV:
        raise ValueError("aov is one of %s, got %r" % (", ".join(_AOV), aov))
    opt = ffi.new(ctype)
    opt.aov = _AOV[aov]
    x, y, z = _vec(background, "background")
    opt.background = {"x": x, "y": y, "z": z}
    L, nl = _lights(lights)
    M, nm, keep = _materials(materials)
    return opt, L, nl, M, nm, keep


def render(shapes, camera, lights=({"kind": "directional", "direction": (0, 0, -1)},),
           materials=({},), object_material=None, method="ray", aov="color", background=0.0,
           pixel_error=0.0, tolerance=0.0, max_depth=0, no_shadows=False):
    """Render the objects of a Shapes with the camera (camera()) and lights
    (dicts: kind "point" (position), "directional" (direction) or
    "ambient", color) by ray tracing (method "ray") or rasterization
    ("raster", tessellating each object to pixel_error pixels or a world
    tolerance), doing only the work the picture needs
    (geom_scene_render). materials: dicts with the scene JSON's material
    keys (ka, kd, ks, ns, specular, reflect, transmit, ior, shading, style,
    ...) and Texture objects under "texture" (multiplies kd and ka by the
    UVs), "bump" (height map, with "bump_scale"), "normal_map" (tangent
    space, RGB in [0, 1]) and "displace" (moves the tessellated vertices,
    with "displace_scale"); UVs and tangents are made only for the objects
    whose material needs them. object_material: a material index per
    object (default 0). aov: "color" (RGB), "depth", "normal" (xyz) or
    "object" (index, -1 for the background). Returns (image (height,
    width, channels), report dict with the per-object reports under
    "objects")."""
    from .core import struct_dict
    n = len(shapes)
    objs = ffi.new("geom_scene_object[]", max(n, 1))
    om = [0] * n if object_material is None else [int(x) for x in object_material]
    if len(om) != n:
        raise ValueError("object_material: one index per object (%d)" % n)
    for i in range(n):
        objs[i].shape = shapes._get(i)
        objs[i].material = om[i]
    opt, L, nl, M, nm, _textures = _picture_setup("geom_render_options *", aov, background,
                                                  lights, materials)
    opt.method = {"ray": 0, "raster": 1}[method]
    opt.pixel_error, opt.tolerance = float(pixel_error), float(tolerance)
    opt.max_depth = int(max_depth)
    opt.no_shadows = 1 if no_shadows else 0
    img = ffi.new("geom_image *")
    rep = ffi.new("geom_render_report *")
    orep = ffi.new("geom_render_object_report[]", max(n, 1))
    diag = new_diag()
    check(lib.geom_scene_render(camera, L, nl, M, nm, objs, n, opt, img, rep, orep, diag), diag,
          "render")
    image = _image(img)
    report = struct_dict(rep[0], "geom_render_report")
    report["objects"] = [struct_dict(orep[i], "geom_render_object_report") for i in range(n)]
    return image, report


def trace(ray_scene, camera, lights=({"kind": "directional", "direction": (0, 0, -1)},),
          materials=({},), object_material=None, aov="color", background=0.0, max_depth=0,
          no_shadows=False):
    """Whitted ray tracing of a built RayScene (geom_scene_trace): hit
    object i gets materials[object_material[i]] (default 0; materials as
    in render). Texture coordinates are the hit's (u, v): the surface
    parameters or per-shape coordinates of the ray module, barycentric for
    meshes, so textured meshes should go through render, which
    interpolates their "uv" channel. Returns (image (height, width,
    channels), report dict)."""
    from .core import struct_dict
    n = ray_scene.object_count
    om = np.zeros(max(n, 1), dtype=np.uint32)
    if object_material is not None:
        om[:n] = np.asarray(object_material, dtype=np.uint32).reshape(n)
    opt, L, nl, M, nm, _textures = _picture_setup("geom_trace_options *", aov, background,
                                                  lights, materials)
    opt.max_depth = int(max_depth)
    opt.no_shadows = 1 if no_shadows else 0
    img = ffi.new("geom_image *")
    rep = ffi.new("geom_trace_report *")
    check(lib.geom_scene_trace(ray_scene._s, ffi.cast("uint32_t *", ffi.from_buffer("uint32_t[]", om)),
                               n, camera, L, nl, M, nm, opt, img, rep), context="trace")
    return _image(img), struct_dict(rep[0], "geom_trace_report")


# ----------------------------------------------------------------- textures

_WRAP = {"repeat": 0, "clamp": 1}


class Texture:
    """An image texture with its MIP pyramid (geom_scene_texture_create,
    Williams 1983), for the texture, bump, normal_map and displace keys of
    a material and for UV lookups.

    image: (height, width) or (height, width, channels) array, 1 to 4
    channels, row 0 the TOP row (as images are stored); values are copied
    as doubles and used as given (linear colour: convert 8-bit sRGB data to
    linear [0, 1] first; normal maps hold RGB in [0, 1]).
    Texture coordinates: (0, 0) is the bottom-left corner and (1, 1) the
    top-right (OBJ/OpenGL); texel image[y, x] has its centre at
    ((x + 0.5) / width, 1 - (y + 0.5) / height). wrap: "repeat" (the
    default: coordinates modulo 1) or "clamp" (to the edge texels). Each
    MIP level halves each size (rounding down, at least 1) by a box filter
    (2x2, 2x1, or a 3-tap footprint for odd sizes), down to 1 x 1.

    Raises ValueError for a bad shape or wrap name, GeomError
    (ERR_INVALID_ARG) for non-finite texels, GeomError (ERR_NOMEM).

    sample() and gradient() take one (u, v) or 1-D arrays of them (one C
    call over all points, geom_scene_texture_sample_many)."""

    def __init__(self, image, wrap="repeat"):
        img = np.ascontiguousarray(image, dtype=np.float64)
        if img.ndim == 2:
            img = img.reshape(img.shape[0], img.shape[1], 1)
        if img.ndim != 3 or not 1 <= img.shape[2] <= 4 or img.shape[0] < 1 or img.shape[1] < 1:
            raise ValueError("image: expected shape (h, w) or (h, w, 1..4) with h, w >= 1, got %s"
                             % (np.shape(image),))
        if wrap not in _WRAP:
            raise ValueError("wrap is 'repeat' or 'clamp', got %r" % (wrap,))
        gi = ffi.new("geom_image *")
        gi.height, gi.width, gi.channels = img.shape
        gi.data = ffi.cast("double *", ffi.from_buffer("double[]", img))
        out = ffi.new("geom_texture **")
        check(lib.geom_scene_texture_create(gi, _WRAP[wrap], ffi.NULL, out), context="Texture")
        self._ptr = ffi.gc(out[0], lib.geom_scene_texture_destroy)
        self.wrap = wrap

    def __repr__(self):
        w, h = self.size
        return "<geom.scene.Texture %dx%d, %d channels, %d levels, %s>" % (
            w, h, self.channels, self.levels, self.wrap)

    @property
    def channels(self):
        """Channels per texel (1..4)."""
        return int(lib.geom_scene_texture_channels(self._ptr))

    @property
    def size(self):
        """(width, height) of level 0."""
        w, h = ffi.new("uint32_t *"), ffi.new("uint32_t *")
        lib.geom_scene_texture_size(self._ptr, w, h)
        return int(w[0]), int(h[0])

    @property
    def levels(self):
        """Number of MIP levels (floor(log2(max(w, h))) + 1; 1 for 1 x 1)."""
        return int(lib.geom_scene_texture_levels(self._ptr))

    def _many(self, u, v, footprint, what):
        """One C call (geom_scene_texture_sample_many) over the broadcast
        u, v (and footprint); returns (n, scalar, uv, fp) buffers ready."""
        uu, vv = np.broadcast_arrays(np.asarray(u, dtype=np.float64),
                                     np.asarray(v, dtype=np.float64))
        if uu.ndim > 1:
            raise ValueError("%s: u and v must be numbers or 1-D arrays, got shape %s"
                             % (what, uu.shape))
        scalar = uu.ndim == 0
        uv = np.ascontiguousarray(np.stack([uu.ravel(), vv.ravel()], axis=1))
        fp = np.ascontiguousarray(np.asarray(footprint, dtype=np.float64).ravel())
        n = uv.shape[0]
        if fp.size not in (1, n):
            raise ValueError("%s: footprint has %d values for %d points" % (what, fp.size, n))
        return n, scalar, uv, fp

    def sample(self, u, v, footprint=0.0):
        """The texel value at (u, v), a (channels,) array, or (n, channels)
        for 1-D arrays u, v (broadcast; one C call,
        geom_scene_texture_sample_many, bitwise geom_scene_texture_sample
        per point). footprint (a number or one per point): the UV size of
        the screen pixel's footprint; 0 or less means level 0 only
        (bilinear, exact for data bilinear in the texel centres), otherwise
        trilinear between the two levels around lod = log2(footprint *
        max(w, h)). Non-finite (u, v) give texel (0, 0) (the top-left) of
        level 0."""
        n, scalar, uv, fp = self._many(u, v, footprint, "sample")
        out = np.empty((n, self.channels), dtype=np.float64)
        check(lib.geom_scene_texture_sample_many(
            self._ptr, n, ffi.from_buffer("double[]", uv), ffi.from_buffer("double[]", fp),
            0 if fp.size == 1 else 1, ffi.from_buffer("double[]", out), ffi.NULL),
            context="Texture.sample")
        return out[0] if scalar else out

    def gradient(self, u, v):
        """(dh/du, dh/dv): the partial derivatives of channel 0 of level
        0's bilinear interpolant at (u, v), in channel units per UV unit
        (the slopes bump mapping uses; geom_scene_texture_gradient): two
        floats, or two (n,) arrays for 1-D arrays u, v (one C call,
        geom_scene_texture_sample_many)."""
        n, scalar, uv, _ = self._many(u, v, 0.0, "gradient")
        g = np.empty((n, 2), dtype=np.float64)
        check(lib.geom_scene_texture_sample_many(
            self._ptr, n, ffi.from_buffer("double[]", uv), ffi.NULL, 0, ffi.NULL,
            ffi.from_buffer("double[]", g)), context="Texture.gradient")
        if scalar:
            return float(g[0, 0]), float(g[0, 1])
        return g[:, 0].copy(), g[:, 1].copy()


def displace(mesh, height, scale=1.0):
    """Displacement mapping in place (geom_scene_displace): every vertex of
    mesh moves along its angle-weighted vertex normal by scale times
    channel 0 of the Texture `height` at the vertex's UV (its "uv" vertex
    channel, else its first corner's), then the "normal" channels are
    replaced by the displaced surface's vertex normals. Sampled at the
    vertices only. scale 0 means 1 (the C default). GeomError
    (ERR_INVALID_ARG) for a mesh without UVs."""
    if not isinstance(height, Texture):
        raise ValueError("height must be a geom.scene.Texture, got %r" % (type(height).__name__,))
    check(lib.geom_scene_displace(mesh._ptr, height._ptr, float(scale)), context="displace")


# --------------------------------------------------------------- rasterizer

def _draws(draws):
    from .core import to_mat4
    from .mesh import Mesh
    items = list(draws)
    arr = ffi.new("geom_scene_draw[]", max(len(items), 1))
    keep = []
    for i, d in enumerate(items):
        if isinstance(d, Mesh):
            d = {"mesh": d}
        if not isinstance(d, dict) or not isinstance(d.get("mesh"), Mesh):
            raise ValueError("draw %d: a Mesh or a dict with a Mesh under 'mesh'" % i)
        for k in d:
            if k not in ("mesh", "transform", "material", "object_id"):
                raise ValueError("draw %d: unknown key %r" % (i, k))
        arr[i].mesh = d["mesh"]._ptr
        keep.append(d["mesh"])
        if d.get("transform") is not None:
            t = ffi.new("geom_mat4 *", to_mat4(d["transform"]))
            keep.append(t)
            arr[i].transform = t
        material = int(d.get("material", 0))
        object_id = int(d.get("object_id", i))
        if material < 0 or object_id < 0:
            raise ValueError("draw %d: material and object_id are >= 0" % i)
        arr[i].material = material
        arr[i].object_id = object_id
    return arr, len(items), keep


def raster(draws, camera, lights=({"kind": "directional", "direction": (0, 0, -1)},),
           materials=({},), aov="color", background=0.0, shadows=False, shadow_map_size=0,
           near=0.0, far=0.0):
    """Z-buffer rasterization of caller-made draws (geom_scene_raster,
    Catmull 1974): each draw is a Mesh or a dict {"mesh": Mesh,
    "transform": (4, 4) object-to-world matrix (default identity),
    "material": index into materials (default 0), "object_id": written to
    the "object" AOV (default the draw's position)}. Triangles and polygons
    (fan-triangulated) are clipped to the view frustum, scan-converted at
    the sample positions (top-left fill rule: a shared edge covers each
    sample once), attributes ("normal" vertex or corner, "uv", "tangent")
    interpolated perspective-correctly and shaded once per visible sample
    (flat, Gouraud or Phong as the material says; textures MIP-mapped with
    the pixel's UV footprint). camera.samples gives a k x k supersampling
    grid: "color" and "normal" are box filtered over it, "depth" and
    "object" take its sample (k/2, k/2) (for even k not the pixel centre).
    Vertices are snapped to 1/256 pixel before scan conversion, so
    interpolated attributes are those of the snapped triangle (a UV error
    up to |dUV/dpixel| / 512 per axis). shadows: shadow maps (shadow_map_size per face,
    0 = 1024) for point and directional lights. near, far: clip distances
    (0 = from the draws' bounding box). lights and materials as in
    render. aov: "color" (RGB), "depth" (view distance, inf on the
    background), "normal" (world xyz, 0 on the background), "object" (the
    object_id, -1 on the background).

    Returns (image (height, width, channels), report dict: triangles_in,
    triangles_clipped, fragments, shadow_maps, samples_per_pixel and the
    seconds of each step). Raises GeomError (ERR_INVALID_ARG) for a
    material index out of range or non-finite positions, camera statuses
    (ERR_DEGENERATE, ERR_DOMAIN) as camera_ray; ValueError for bad Python
    arguments."""
    from .core import struct_dict
    D, nd, keep = _draws(draws)
    opt, L, nl, M, nm, textures = _picture_setup("geom_raster_options *", aov, background,
                                                 lights, materials)
    opt.shadows = 1 if shadows else 0
    opt.shadow_map_size = int(shadow_map_size)
    opt.near_z, opt.far_z = float(near), float(far)
    img = ffi.new("geom_image *")
    rep = ffi.new("geom_raster_report *")
    check(lib.geom_scene_raster(camera, L, nl, M, nm, D, nd, opt, img, rep), context="raster")
    del keep, textures
    return _image(img), struct_dict(rep[0], "geom_raster_report")
