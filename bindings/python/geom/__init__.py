"""Python bindings of libgeom (numpy arrays in and out) over its C ABI.

Loaded with cffi in ABI mode: no compiler is needed, only the shared library
libgeom.so (found through the GEOM_LIBRARY environment variable, next to
this package, or by the system loader; see geom._ffi).

Submodules:
  geom.core      GeomError, status names, exact predicates, 4x4 transforms
  geom.bary      barycentric, mean value, Wachspress, perspective weights
  geom.spatial   KdTree, Octree, MeshDistance, Bvh (batch kNN/radius/box
                 queries, closest points, winding numbers, signed distance)
  geom.mesh      Mesh (half-edge mesh, file I/O, normals, features, clipping,
                 subdivision)
  geom.subdiv    Refiner (topology refined once, data interpolated per level,
                 limit positions and normals, the level's mesh)
  geom.curve     NurbsCurve (evaluation, derivatives, exact circles, ...)
  geom.surface   NurbsSurface, .bpt patches, tessellation to a Mesh
  geom.step      Brep: STEP files read, evaluated, estimated and tessellated
  geom.implicit  Expression, marching_cubes, read_volume, Volume
  geom.iso       isosurfaces chunk by chunk (extract_stream, chunks) and
                 triangle estimates
  geom.ray       RayScene (closest / any / all hits of numpy ray arrays)
  geom.scene     cameras: primary rays, projection to pixels; Shapes (a
                 RayScene's objects tessellated, triangle estimates)

Every error status of the C library raises geom.GeomError, which carries the
status (``.code`` e.g. "ERR_PARSE", ``.name`` e.g. "parse error") and the
diagnostic (``.message``, ``.source``, ``.line``, ``.column``,
``.location`` = "file:line:column: message").
"""

from ._ffi import has_module, library_path
from .core import (STATUS, GeomError, Output, Progress, incircle, orient2d, orient2d_exact,
                   orient3d, orient3d_exact, status_name, version, write_file)

__version__ = version()

from . import bary, core  # noqa: E402

__all__ = ["GeomError", "STATUS", "status_name", "version", "orient2d", "orient3d", "incircle",
           "orient2d_exact", "orient3d_exact", "bary", "core", "has_module", "library_path",
           "Output", "Progress", "write_file"]

if has_module("mesh") and has_module("meshio"):
    from . import mesh  # noqa: E402
    from .mesh import Mesh  # noqa: E402
    __all__ += ["mesh", "Mesh"]
if has_module("subdiv") and has_module("meshio"):
    from . import subdiv  # noqa: E402
    __all__ += ["subdiv"]
if has_module("spatial"):
    from . import spatial  # noqa: E402
    __all__ += ["spatial"]
if has_module("curve"):
    from . import curve  # noqa: E402
    from .curve import NurbsCurve  # noqa: E402
    __all__ += ["curve", "NurbsCurve"]
if has_module("surface") and has_module("meshio"):
    from . import surface  # noqa: E402
    from .surface import NurbsSurface, tessellate  # noqa: E402
    __all__ += ["surface", "NurbsSurface", "tessellate"]
if has_module("step") and has_module("meshio"):
    from . import step  # noqa: E402
    __all__ += ["step"]
if has_module("implicit") and has_module("iso") and has_module("meshio"):
    from . import implicit  # noqa: E402
    from .implicit import Expression, Volume, marching_cubes, read_volume  # noqa: E402
    __all__ += ["implicit", "Expression", "Volume", "marching_cubes", "read_volume"]
    from . import iso  # noqa: E402
    __all__ += ["iso"]
if has_module("ray"):
    from . import ray  # noqa: E402
    from .ray import RayScene  # noqa: E402
    __all__ += ["ray", "RayScene"]
if has_module("scene"):
    from . import scene  # noqa: E402
    __all__ += ["scene"]
