"""geom.scene: cameras (the rest of the scene module is reached through the
geom-render and geom-scene tools)."""
import numpy as np

from ._ffi import ffi, lib
from .core import check


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
