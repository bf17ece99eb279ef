#!/bin/bash
# Tests of geom-subdivide: closed-form Catmull-Clark values on the cube
# [-1,1]^3 (the vertex point of a corner (5/9, 5/9, 5/9), its limit
# (1/2, 1/2, 1/2), face points at the face centres), face and vertex counts
# per scheme, UVs kept, butterfly keeping the original vertices, sqrt3's
# 3^k growth, holes with --boundary none, the --json report (per-level
# counts, distance to the limit shrinking), error and usage exits, and no
# output file left behind on failure.
# Usage: test_geom_subdivide.sh /path/to/geom-subdivide   (env PYTHON3: python)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOL" >&2
    exit 2
fi
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
if [ ! -x "$TOOL" ]; then
    echo "FAIL: $TOOL is not an executable" >&2
    exit 1
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-subdivide-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

failures=0
checks=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
run() {
    "$TOOL" "$@" >"$T/stdout" 2>"$T/stderr"
    rc=$?
    out=$(cat "$T/stdout")
    err=$(cat "$T/stderr")
}
expect_rc() {
    checks=$((checks + 1))
    [ "$rc" -eq "$1" ] || fail "$2: exit status $rc, expected $1 (stderr: $err)"
}
# pycheck DESCRIPTION SCRIPT ARGS...: run a python check; it prints an error
# and exits nonzero on failure.
pycheck() {
    local what=$1
    shift
    checks=$((checks + 1))
    "$PY" - "$@" >"$T/py" 2>&1 || fail "$what: $(cat "$T/py")"
}

# The cube [-1,1]^3 with one UV square per face (a seam on every edge).
cat >"$T/cube.obj" <<'EOF'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1 4/2 3/3 2/4
f 5/1 6/2 7/3 8/4
f 1/1 2/2 6/3 5/4
f 2/1 3/2 7/3 6/4
f 3/1 4/2 8/3 7/4
f 4/1 1/2 5/3 8/4
EOF

# Python helpers: read an OBJ's v, vt and f lines.
cat >"$T/obj.py" <<'EOF'
def read(path):
    v, vt, f = [], [], []
    for line in open(path):
        p = line.split()
        if not p:
            continue
        if p[0] == 'v':
            v.append(tuple(float(x) for x in p[1:4]))
        elif p[0] == 'vt':
            vt.append(tuple(float(x) for x in p[1:3]))
        elif p[0] == 'f':
            f.append([tuple(int(y) if y else 0 for y in c.split('/')) for c in p[1:]])
    return v, vt, f
EOF

# --- Catmull-Clark level 1: counts and closed-form points
run --levels 1 "$T/cube.obj" -o "$T/cc1.obj"
expect_rc 0 "catmull-clark level 1"
pycheck "cc level 1 points" "$T" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import obj
v, vt, f = obj.read(sys.argv[1] + '/cc1.obj')
assert len(f) == 24 and len(v) == 26, (len(f), len(v))
assert all(len(x) == 4 for x in f)
def has(p, tol=1e-15):
    return any(all(abs(a - b) <= tol for a, b in zip(q, p)) for q in v)
# vertex point of (1,1,1): 1/3 v + (sum of edge neighbours + face centres)/9
assert has((5/9, 5/9, 5/9)), 'corner vertex point'
for c in [(0,0,1),(0,0,-1),(1,0,0),(-1,0,0),(0,1,0),(0,-1,0)]:
    assert has(c), ('face point', c)
# smooth edge point of edge (1,1,1)-(1,1,-1): (v0+v1+f0+f1)/4 = (3/4, 3/4, 0)
assert has((0.75, 0.75, 0.0)), 'edge point'
# UVs kept: every face uses vt, one chart per parent face, all in [0,1]
assert len(vt) > 0 and all(c[1] > 0 for x in f for c in x)
assert all(0 <= a <= 1 and 0 <= b <= 1 for a, b in vt)
EOF

# --- --limit: the corner's limit is (1/2, 1/2, 1/2) from any level
run --levels 2 --limit "$T/cube.obj" -o "$T/cc2l.obj"
expect_rc 0 "catmull-clark --limit"
pycheck "cc limit corner" "$T" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import obj
v, vt, f = obj.read(sys.argv[1] + '/cc2l.obj')
assert len(f) == 96
assert any(all(abs(a - 0.5) <= 1e-14 for a in q) for q in v), 'limit of the corner'
assert all(abs(x) <= 1 for q in v for x in q)
EOF

# --- --json: per-level counts, time and distance to the limit
run --levels 3 --json "$T/cube.obj" -o "$T/cc3.obj"
expect_rc 0 "catmull-clark --json"
echo "$out" >"$T/cc3.json"
pycheck "cc json" "$T/cc3.json" <<'EOF'
import json, math, sys
d = json.load(open(sys.argv[1]))
assert d['scheme'] == 'catmull-clark' and d['levels'] == 3
assert d['input'] == {'faces': 6, 'vertices': 8}
assert d['output'] == {'faces': 384, 'vertices': 386}
assert abs(d['bbox_diagonal'] - math.sqrt(12)) < 1e-15
pl = d['per_level']
assert [x['faces'] for x in pl] == [24, 96, 384]
assert [x['vertices'] for x in pl] == [26, 98, 386]
# the corner vertex point at level 1 is sqrt(3)*(5/9 - 1/2) from its limit
assert pl[0]['max_limit_distance'] >= math.sqrt(3) * (5/9 - 0.5) - 1e-15
for a, b in zip(pl, pl[1:]):
    assert b['max_limit_distance'] < a['max_limit_distance'] / 2
    assert b['rms_limit_distance'] <= b['max_limit_distance']
assert d['seconds'] >= 0 and all(x['seconds'] >= 0 for x in pl)
# the error report every approximating tool prints: the last level's
# distance to the limit, measured at its vertices
e = d['error']
assert e['max'] == pl[-1]['max_limit_distance'] and e['method'] == 'sampled'
assert 0 < e['mean'] <= pl[-1]['rms_limit_distance'] <= e['max']
assert e['pieces'] == 386 and e['tolerance'] is None and e['seconds'] >= 0
EOF

# --- Loop on quads: triangulated first, 4x faces per level
run --scheme loop --levels 2 "$T/cube.obj" -o "$T/loop.obj"
expect_rc 0 "loop"
checks=$((checks + 1))
case $err in
*"loop needs triangles: 6 faces added"*) ;;
*) fail "loop: triangulation not reported: $err" ;;
esac
pycheck "loop counts" "$T" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import obj
v, vt, f = obj.read(sys.argv[1] + '/loop.obj')
assert len(f) == 12 * 16 and all(len(x) == 3 for x in f)
# triangulated cube: V 8, E 18, F 12 -> V 26, E 72 -> V 98
assert len(v) == 98, len(v)
EOF

# --- butterfly keeps the original vertices
run --scheme butterfly --levels 2 "$T/cube.obj" -o "$T/bf.obj"
expect_rc 0 "butterfly"
pycheck "butterfly interpolates" "$T" <<'EOF'
import sys, itertools
sys.path.insert(0, sys.argv[1])
import obj
v, vt, f = obj.read(sys.argv[1] + '/bf.obj')
for c in itertools.product((-1.0, 1.0), repeat=3):
    assert c in v, c
assert len(f) == 12 * 16
EOF

# --- sqrt3: 3^k growth on a tetrahedron
cat >"$T/tet.obj" <<'EOF'
v 1 1 1
v -1 -1 1
v -1 1 -1
v 1 -1 -1
f 1 2 3
f 1 4 2
f 1 3 4
f 2 4 3
EOF
run --scheme sqrt3 --levels 3 --json "$T/tet.obj" -o "$T/tet3.obj"
expect_rc 0 "sqrt3"
echo "$out" >"$T/tet.json"
pycheck "sqrt3 growth" "$T/tet.json" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
assert [x['faces'] for x in d['per_level']] == [12, 36, 108]
assert [x['vertices'] for x in d['per_level']] == [8, 20, 56]
EOF

# --- bilinear: the level-1 points are exact midpoints and centres
run --scheme bilinear "$T/tet.obj" -o "$T/bil.obj"
expect_rc 0 "bilinear"
pycheck "bilinear midpoints" "$T" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import obj
v, vt, f = obj.read(sys.argv[1] + '/bil.obj')
assert len(f) == 12 and len(v) == 4 + 6 + 4
assert (0.0, 0.0, 1.0) in v          # midpoint of (1,1,1)-(-1,-1,1)
assert (-1/3, 1/3, 1/3) in v or any(abs(q[0] + 1/3) < 1e-15 and abs(q[1] - 1/3) < 1e-15 and abs(q[2] - 1/3) < 1e-15 for q in v)
EOF

# --- --boundary none: faces at the boundary become holes
cat >"$T/grid.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 2 0 0
v 3 0 0
v 0 1 0
v 1 1 0
v 2 1 0
v 3 1 0
v 0 2 0
v 1 2 0
v 2 2 0
v 3 2 0
v 0 3 0
v 1 3 0
v 2 3 0
v 3 3 0
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 5 6 10 9
f 6 7 11 10
f 7 8 12 11
f 9 10 14 13
f 10 11 15 14
f 11 12 16 15
EOF
run --boundary none --json "$T/grid.obj" -o "$T/gridn.obj"
expect_rc 0 "boundary none"
echo "$out" >"$T/gridn.json"
pycheck "boundary none holes" "$T/gridn.json" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
assert d['hole_faces'] == 32 and d['output']['faces'] == 4, d
EOF
run --boundary corner "$T/grid.obj" -o "$T/gridc.obj"
expect_rc 0 "boundary corner"
pycheck "boundary corner keeps corners" "$T" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import obj
v, vt, f = obj.read(sys.argv[1] + '/gridc.obj')
for c in [(0.0, 0.0, 0.0), (3.0, 0.0, 0.0), (0.0, 3.0, 0.0), (3.0, 3.0, 0.0)]:
    assert c in v, c
assert len(f) == 36
EOF

# --- errors and usage
run --scheme doo-sabin "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "unknown scheme"
run --levels 13 "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "too many levels"
run --levels 1.5 "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "fractional levels"
run --boundary sideways "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "unknown boundary"
run --json "$T/cube.obj"
expect_rc 2 "--json to stdout"
run "$T/cube.obj" "$T/tet.obj" -o "$T/x.obj"
expect_rc 2 "extra operand"
run "$T/missing.obj" -o "$T/x.obj"
expect_rc 1 "missing file"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt interpolateboundary 1/0/0 7\n' >"$T/badtag.obj"
run "$T/badtag.obj" -o "$T/x.obj"
expect_rc 1 "bad tag"
checks=$((checks + 1))
case $err in
*interpolateboundary*) ;;
*) fail "bad tag: message does not name the tag: $err" ;;
esac
printf 'v 0 0 0\nv 1 0 0\nf 1 2 9\n' >"$T/badidx.obj"
run "$T/badidx.obj" -o "$T/x.obj"
expect_rc 1 "bad face index"
checks=$((checks + 1))
[ ! -e "$T/x.obj" ] || fail "a failed run left $T/x.obj behind"
# standard input (no operand) with --input-format
"$TOOL" -i obj -n 1 -o "$T/stdin.obj" <"$T/tet.obj" >"$T/stdout" 2>"$T/stderr"
rc=$?
err=$(cat "$T/stderr")
expect_rc 0 "standard input"
checks=$((checks + 1))
[ "$(grep -c '^f ' "$T/stdin.obj")" -eq 12 ] || fail "standard input: expected 12 faces"
# standard output needs --format; with it, an OBJ comes out
run --levels 1 "$T/tet.obj"
expect_rc 2 "stdout without --format"
run --levels 1 --format obj "$T/tet.obj"
expect_rc 0 "stdout with --format"
checks=$((checks + 1))
[ "$(printf '%s\n' "$out" | grep -c '^f ')" -eq 12 ] || fail "stdout OBJ: expected 12 faces"

# a tag the refiner refuses names its file line (the statement's first line
# when it is continued with a backslash)
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nt corner 1/1/0 0 2.0\nf 1 2 3 4\n# c\nt crease 2/1/0 0 \\\n 9 1.0\n' >"$T/badtag.obj"
run --levels 1 "$T/badtag.obj" -o "$T/badtag_out.obj"
expect_rc 1 "crease tag with a vertex out of range"
checks=$((checks + 1))
case "$err" in
*"badtag.obj:8: tag 1: crease vertex out of range"*) ;;
*) fail "bad crease tag: expected FILE:8 in the message, got: $err" ;;
esac
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 0 2 1.0\n' >"$T/badedge.obj"
run --levels 1 "$T/badedge.obj" -o "$T/badtag_out.obj"
expect_rc 1 "crease tag on no edge"
checks=$((checks + 1))
case "$err" in
*"badedge.obj:6: "*) ;;
*) fail "crease tag on no edge: expected FILE:6 in the message, got: $err" ;;
esac
# the same from standard input: the bytes read once are the ones searched
# (the statement's first line), so the line is named there too
"$TOOL" -i obj --levels 1 -o "$T/badtag_out.obj" <"$T/badtag.obj" >"$T/stdout" 2>"$T/stderr"
rc=$?
err=$(cat "$T/stderr")
expect_rc 1 "crease tag out of range, from standard input"
checks=$((checks + 1))
case "$err" in
*":8: tag 1: crease vertex out of range"*) ;;
*) fail "bad crease tag from standard input: expected line 8 in the message, got: $err" ;;
esac
printf 'v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nf 1 2 3 4\r\nt crease 2/1/0 0 2 1.0\r\n' |
    "$TOOL" -i obj --levels 1 -o "$T/badtag_out.obj" >"$T/stdout" 2>"$T/stderr"
rc=$?
err=$(cat "$T/stderr")
expect_rc 1 "crease tag on no edge, CRLF, from standard input"
checks=$((checks + 1))
case "$err" in
*":6: crease tag 0: no edge"*) ;;
*) fail "crease tag on no edge from standard input: expected line 6 in the message, got: $err" ;;
esac
[ ! -e "$T/badtag_out.obj" ] || fail "a failed run left $T/badtag_out.obj behind"

# An OBJ file of a plain level (no holes, creases, UVs, groups: the cube and
# the tetrahedron) is written straight from the refined level's faces; the
# same run to standard output builds the mesh and writes it (the other
# path): the bytes must be the same, with and without --normals and --limit.
grep -v '^vt' "$T/cube.obj" | sed 's#/[0-9]*##g' >"$T/bare.obj"
for args in "--levels 1" "--levels 2 --limit --normals" "--scheme loop --levels 2" \
    "--scheme bilinear --levels 1"; do
    for shape in bare tet cube; do
        # shellcheck disable=SC2086
        "$TOOL" $args "$T/$shape.obj" -o "$T/plain_file.obj" 2>/dev/null
        # shellcheck disable=SC2086
        "$TOOL" $args "$T/$shape.obj" -f obj -o - >"$T/plain_stdout.obj" 2>/dev/null
        checks=$((checks + 1))
        [ -s "$T/plain_file.obj" ] && cmp -s "$T/plain_file.obj" "$T/plain_stdout.obj" ||
            fail "$shape $args: the OBJ file differs from the mesh written to standard output"
    done
done

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
