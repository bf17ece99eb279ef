#!/bin/bash
# Garbage and emptiness are not silent: geom-info on a text file that is not
# a mesh (/etc/passwd-like) exits 1 naming the file; an empty OBJ is a
# warning on stderr and in --json; an isosurface that misses its box warns
# on stderr and in --json; --quiet is accepted everywhere.
# PLY output names texture coordinates s, t (what Blender and MeshLab
# read) and reads them back.
# Usage: test_geom_feedback.sh GEOM_INFO GEOM_ISO GEOM_CONVERT CUBE_SEAMS_OBJ
set -u
INFO=$1 ISO=$2 CONVERT=$3 CUBE=$4
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-feedback-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
failures=0 checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
printf 'root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n' >"$T/passwd"
checks=$((checks + 1))
"$INFO" "$T/passwd" >"$T/out" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -Eq "passwd: not (a mesh|an OBJ file)" "$T/err" && [ ! -s "$T/out" ] ||
    fail "passwd: exit $rc, stderr '$(cat "$T/err")'"
: >"$T/empty.obj"
checks=$((checks + 1))
"$INFO" --json --quiet "$T/empty.obj" >"$T/out" 2>"$T/err"; rc=$?
[ $rc -eq 0 ] && grep -q "warning: empty mesh" "$T/err" &&
    "$PY" -c "import json; assert json.load(open('$T/out'))['warnings'] == ['empty mesh: no vertices or faces']" ||
    fail "empty.obj: exit $rc, stderr '$(cat "$T/err")', out '$(cat "$T/out")'"
checks=$((checks + 1))
"$ISO" --expr "sphere(1)" --bounds 5,5,5,6,6,6 --res 4 --json -o "$T/e.obj" >"$T/out" 2>"$T/err"; rc=$?
[ $rc -eq 0 ] && grep -q "warning: empty isosurface" "$T/err" &&
    "$PY" -c "import json; d = json.load(open('$T/out')); assert d['triangles'] == 0 and d['warnings']" ||
    fail "iso miss: exit $rc, stderr '$(cat "$T/err")'"
checks=$((checks + 1))
"$ISO" --expr "sphere(1)" --bounds -2,-2,-2,2,2,2 --res 8 --json -o "$T/s.obj" >"$T/out" 2>"$T/err"
"$PY" -c "import json; assert 'warnings' not in json.load(open('$T/out'))" && [ ! -s "$T/err" ] ||
    fail "iso hit: unexpected warning"
checks=$((checks + 1))
"$CONVERT" --ascii "$CUBE" "$T/c.ply" 2>"$T/err" &&
    grep -q "^property double s$" "$T/c.ply" && grep -q "^property double t$" "$T/c.ply" &&
    ! grep -q "^property double u$" "$T/c.ply" ||
    fail "PLY uv names: $(grep property "$T/c.ply" | tr '\n' ' ')"
checks=$((checks + 1))
"$CONVERT" "$T/c.ply" "$T/back.obj" 2>"$T/err" && grep -q "^vt " "$T/back.obj" ||
    fail "PLY s, t not read back as UVs"
# --up z: a Z-up source is rotated into glTF's Y-up frame, (x, y, z) -> (x, z, -y);
# --up y (the default) writes it unchanged; a bad axis is a usage error
checks=$((checks + 3))
"$CONVERT" --up z "$CUBE" "$T/z.glb" 2>"$T/err" && "$CONVERT" "$T/z.glb" "$T/z.obj" 2>>"$T/err" &&
    "$CONVERT" --up y "$CUBE" "$T/y.glb" 2>>"$T/err" && "$CONVERT" "$T/y.glb" "$T/y.obj" 2>>"$T/err" ||
    fail "--up: $(cat "$T/err")"
"$PY" - "$CUBE" "$T/z.obj" "$T/y.obj" <<'PYEOF' || fail "--up z: wrong rotation"
import sys
def verts(path):
    return {tuple(round(float(x), 6) for x in l.split()[1:4]) for l in open(path) if l.startswith('v ')}
src = verts(sys.argv[1])
assert verts(sys.argv[2]) == {(x, z, -y + 0.0) for x, y, z in src}, 'z-up'
assert verts(sys.argv[3]) == src, 'y-up changed'
PYEOF
"$CONVERT" --up x "$CUBE" "$T/x.glb" 2>/dev/null; [ $? -eq 2 ] || fail "--up x accepted"
if [ "$failures" -ne 0 ]; then
    echo "$failures of $checks checks failed" >&2
    exit 1
fi
echo "all $checks checks passed"
