#!/bin/bash
# `pip install bindings/python` without network or build isolation, into a
# scratch HOME (--user), bundling the given libgeom.so; then `import geom`
# from another directory with neither PYTHONPATH nor GEOM_LIBRARY must load
# the bundled library and compute.
# Usage: check_pip_install.sh PYTHON SOURCE_DIR LIBGEOM_SO
set -eu
PY=$1 SRC=$2 LIB=$3
"$PY" -m pip --version >/dev/null 2>&1 || { echo "pip not available for $PY: skipped"; exit 0; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-pip.XXXXXX")
trap 'rm -rf "$T"' EXIT
cp -r "$SRC/bindings/python" "$T/src"
rm -rf "$T/src/build" "$T/src"/*.egg-info
HOME=$T/home GEOM_BUNDLE_LIBRARY=$LIB "$PY" -m pip install --quiet --no-build-isolation \
    --no-index --user --break-system-packages "$T/src" 2>"$T/err" || { cat "$T/err"; exit 1; }
cd /
HOME=$T/home env -u GEOM_LIBRARY -u PYTHONPATH "$PY" -c '
import geom, numpy as np
assert geom._ffi.library_path.startswith("'"$T"'/home/"), geom._ffi.library_path
l = geom.bary.tri2([0, 0], [1, 0], [0, 1], [[0.25, 0.5]])
assert np.array_equal(l, [[0.25, 0.25, 0.5]]), l
print("pip-installed geom", geom.__version__ if hasattr(geom, "__version__") else "", "from", geom._ffi.library_path)
'
