"""setuptools glue for pyproject.toml: bundle libgeom's shared library.

The build step runs CMake on the source tree two directories up (only the
geom_shared target: no tools, no tests) and copies libgeom.so.0 next to
geom/_ffi.py, which loads it from there. GEOM_BUNDLE_LIBRARY=/path/libgeom.so
bundles an already built library instead (no CMake run)."""

import glob
import os
import shutil
import subprocess
import tempfile

from setuptools import setup
from setuptools.command.build_py import build_py as _build_py

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.normpath(os.path.join(HERE, "..", ".."))


class build_py(_build_py):
    def run(self):
        super().run()
        lib = os.environ.get("GEOM_BUNDLE_LIBRARY")
        if not lib:
            if not os.path.exists(os.path.join(SOURCE, "libgeom", "CMakeLists.txt")):
                raise RuntimeError("geom: no libgeom source tree at %s; set GEOM_BUNDLE_LIBRARY "
                                   "to a built libgeom.so" % SOURCE)
            bdir = tempfile.mkdtemp(prefix="geom-cmake-")
            subprocess.check_call(["cmake", "-S", SOURCE, "-B", bdir, "-DCMAKE_BUILD_TYPE=Release",
                                   "-DGEOM_BUILD_TOOLS=OFF", "-DGEOM_BUILD_TESTS=OFF",
                                   "-DGEOM_INSTALL_PYTHON=OFF"])
            subprocess.check_call(["cmake", "--build", bdir, "--target", "geom_shared",
                                   "--parallel", str(os.cpu_count() or 2)])
            found = sorted(glob.glob(os.path.join(bdir, "libgeom", "libgeom.so.*")))
            if not found:
                raise RuntimeError("geom: the CMake build made no libgeom.so in %s" % bdir)
            lib = found[0]
        dest = os.path.join(self.build_lib, "geom", "libgeom.so")
        shutil.copyfile(os.path.realpath(lib), dest)
        if not os.environ.get("GEOM_BUNDLE_LIBRARY"):
            shutil.rmtree(bdir, ignore_errors=True)


setup(cmdclass={"build_py": build_py})
