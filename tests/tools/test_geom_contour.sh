#!/bin/bash
# Tests of geom-contour: circles contoured to OBJ and SVG checked against
# their closed-form radii (parsed with Python), loop counts, --iso, --z,
# --no-refine (larger but O(h^2) error), --json keys, expression errors
# with their column (exit 1), usage errors (exit 2), standard output, and
# the no-partial-output guarantee of -o.
# Usage: test_geom_contour.sh /path/to/geom-contour VERSION   (env PYTHON3)
set -u
if [ $# -ne 2 ]; then
    echo "usage: $0 TOOL VERSION" >&2
    exit 2
fi
TOOL=$1
VERSION=$2
PY=${PYTHON3:-/usr/bin/python3}
if [ ! -x "$TOOL" ]; then
    echo "FAIL: $TOOL is not an executable" >&2
    exit 1
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-contour-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

failures=0
checks=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
check() { # check DESCRIPTION command...
    local what=$1
    shift
    checks=$((checks + 1))
    "$@" || fail "$what"
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
expect_err_match() {
    checks=$((checks + 1))
    # shellcheck disable=SC2053
    [[ $err == $1 ]] || fail "$2: stderr '$err' does not match '$1'"
}

cat >"$T/check.py" <<'PYEOF'
import json, math, sys, xml.etree.ElementTree as ET

def obj(path):
    vs, ls = [], []
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == 'v':
            vs.append(tuple(float(t) for t in w[1:4]))
        elif w[0] == 'l':
            ls.append([int(t) - 1 for t in w[1:]])
    return vs, ls

def svg(path):
    root = ET.parse(path).getroot()
    paths = [e for e in root.iter() if e.tag.endswith('path')]
    loops = []
    for p in paths:
        toks = p.get('d').replace('M', ' ').replace('L', ' ').split()
        closed = toks[-1] == 'Z'
        if closed:
            toks = toks[:-1]
        pts = [(float(toks[i]), -float(toks[i + 1])) for i in range(0, len(toks), 2)]
        loops.append((pts, closed))
    return root, loops

mode = sys.argv[1]
if mode == 'json':
    # json FILE key=value... (value: int exact, or <X / >X)
    d = json.load(open(sys.argv[2]))
    assert set(d) >= {'vertices', 'polylines', 'max_error', 'seconds'}, d
    e = d['error']  # the report every approximating tool prints
    assert e['max'] == d['max_error'] and e['mean'] == d['mean_error'], e
    assert e['pieces'] == d['vertices'] and e['tolerance'] is None, e
    for kv in sys.argv[3:]:
        k, v = kv.split('=')
        if v.startswith('<'):
            assert d[k] < float(v[1:]), (k, d[k], v)
        elif v.startswith('>'):
            assert d[k] > float(v[1:]), (k, d[k], v)
        else:
            assert d[k] == int(v), (k, d[k], v)
elif mode == 'obj-circles':
    # obj-circles FILE Z TOL (cx,cy,r)...: every vertex on one of the circles,
    # one closed `l` line per circle
    vs, ls = obj(sys.argv[2])
    z, tol = float(sys.argv[3]), float(sys.argv[4])
    circles = [tuple(float(t) for t in c.split(',')) for c in sys.argv[5:]]
    assert len(ls) == len(circles), (len(ls), len(circles))
    for v in vs:
        assert v[2] == z, v
        e = min(abs(math.hypot(v[0] - cx, v[1] - cy) - r) for cx, cy, r in circles)
        assert e <= tol, (v, e)
    for l in ls:
        assert l[0] == l[-1] and len(l) >= 4, l
        assert len(set(l[:-1])) == len(l) - 1, 'repeated vertex'
    assert len(set(vs)) == len(vs), 'duplicate vertices'
elif mode == 'svg-circles':
    root, loops = svg(sys.argv[2])
    tol = float(sys.argv[3])
    circles = [tuple(float(t) for t in c.split(',')) for c in sys.argv[4:]]
    assert root.tag.endswith('svg')
    assert len(loops) == len(circles), len(loops)
    for pts, closed in loops:
        assert closed
        # counter-clockwise around the inside (y up)
        a = sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
                for i in range(len(pts)))
        assert a > 0, a
        for x, y in pts:
            e = min(abs(math.hypot(x - cx, y - cy) - r) for cx, cy, r in circles)
            assert e <= tol, (x, y, e)
elif mode == 'max-radius-error':
    # max-radius-error FILE R: print max | |v| - R | over OBJ vertices
    vs, ls = obj(sys.argv[2])
    print('%.3g' % max(abs(math.hypot(v[0], v[1]) - float(sys.argv[3])) for v in vs))
PYEOF

# --- help and version
run --help
expect_rc 0 "--help"
check "--help names --expr" grep -q -- "--expr" "$T/stdout"
run --version
expect_rc 0 "--version"
check "--version" [ "$out" = "geom-contour (libgeom) $VERSION" ]

# --- one circle, refined: radius to ~1e-16, one closed loop
run --expr 'x^2 + y^2 - 1' --bounds -2,-2,2,2 --res 64 -o "$T/c.obj" --json
expect_rc 0 "circle obj"
echo "$out" >"$T/c.json"
check "circle json" "$PY" "$T/check.py" json "$T/c.json" polylines=1 closed=1 'max_error=<1e-13' 'vertices=>100' 'seconds=>0'
check "circle obj radius" "$PY" "$T/check.py" obj-circles "$T/c.obj" 0 1e-14 0,0,1

# --- without refinement: O(h^2) error, reported, halving h divides it by ~4
run --expr 'x^2 + y^2 - 1' --bounds -2,-2,2,2 --res 32 --no-refine -o "$T/l32.obj"
expect_rc 0 "no-refine 32"
check "summary on stdout" grep -q '^vertices ' "$T/stdout"
e32=$("$PY" "$T/check.py" max-radius-error "$T/l32.obj" 1)
run --expr 'x^2 + y^2 - 1' --bounds -2,-2,2,2 --res 64 --no-refine -o "$T/l64.obj"
e64=$("$PY" "$T/check.py" max-radius-error "$T/l64.obj" 1)
check "linear error ratio ~4 ($e32 / $e64)" "$PY" -c "import sys; r = $e32 / $e64; sys.exit(not (3 < r < 5.5 and $e32 > 1e-5))"

# --- two circles to SVG, counter-clockwise
run -e 'union(sphere(-1, 0, 0, 0.5), sphere(1, 0.5, 0, 0.7))' -b -2,-1.5,2,1.5 -r 80,60 -o "$T/two.svg"
expect_rc 0 "two circles svg"
check "two circles svg" "$PY" "$T/check.py" svg-circles "$T/two.svg" 1e-12 -1,0,0.5 1,0.5,0.7

# --- --iso and --z
run -e 'sphere(1)' -b -2,-2,2,2 -r 50 --iso 0.5 -o "$T/iso.obj"
expect_rc 0 "--iso"
check "--iso radius 1.5" "$PY" "$T/check.py" obj-circles "$T/iso.obj" 0 1e-13 0,0,1.5
run -e 'sphere(1)' -b -2,-2,2,2 -r 50 --z 0.6 -o "$T/z.obj"
expect_rc 0 "--z"
check "--z radius 0.8" "$PY" "$T/check.py" obj-circles "$T/z.obj" 0.6 1e-13 0,0,0.8

# --- standard output
run -e 'sphere(1)' -b -2,-2,2,2 -r 10 --format svg
expect_rc 0 "svg to stdout"
check "svg on stdout" grep -q '<svg' "$T/stdout"
check "summary on stderr" grep -q '^polylines 1 (1 closed)' "$T/stderr"
run -e 'sphere(1)' -b -2,-2,2,2 -r 10 -f obj -o -
expect_rc 0 "obj to stdout"
check "obj on stdout" grep -q '^l ' "$T/stdout"

# --- expression errors: exit 1, column, the file untouched
echo "keep me" >"$T/keep.svg"
run -e 'sphere(1) + w' -b -2,-2,2,2 -r 10 -o "$T/keep.svg"
expect_rc 1 "unknown identifier"
expect_err_match "geom-contour: expression:1:13: unknown identifier 'w'*" "unknown identifier message"
check "file untouched" [ "$(cat "$T/keep.svg")" = "keep me" ]
run -e 'sphere(1, 2)' -b -2,-2,2,2 -r 10 -o "$T/x.svg"
expect_rc 1 "arity"
expect_err_match "*expression:1:1: 'sphere' takes 1 or 4 arguments, got 2*" "arity message"
run -e '(x + 1' -b -2,-2,2,2 -r 10 -o "$T/x.svg"
expect_rc 1 "unclosed parenthesis"
expect_err_match "*expression:1:7: expected ')' to close '(' at column 1, found end of input*" "paren message"
check "no output left" [ ! -e "$T/x.svg" ]

# --- usage errors: exit 2
run -b -2,-2,2,2 -r 10 -o "$T/u.svg"
expect_rc 2 "missing --expr"
run -e x -r 10 -o "$T/u.svg"
expect_rc 2 "missing --bounds"
run -e x -b -2,-2,2,2 -o "$T/u.svg"
expect_rc 2 "missing --res"
run -e x -b 2,-2,-2,2 -r 10 -o "$T/u.svg"
expect_rc 2 "empty bounds"
run -e x -b 1,2,3 -r 10 -o "$T/u.svg"
expect_rc 2 "three bounds"
run -e x -b -2,-2,2,2 -r 0 -o "$T/u.svg"
expect_rc 2 "zero res"
run -e x -b -2,-2,2,2 -r 2.5 -o "$T/u.svg"
expect_rc 2 "fractional res"
run -e x -b -2,-2,2,2 -r 10 -o "$T/u.png"
expect_rc 2 "unknown extension"
run -e x -b -2,-2,2,2 -r 10
expect_rc 2 "stdout without --format"
run -e x -b -2,-2,2,2 -r 10 -f svg --json
expect_rc 2 "--json to stdout"
run -e x -b -2,-2,2,2 -r 10 -o "$T/u.svg" extra
expect_rc 2 "extra operand"
run -e x -b -2,-2,2,2 -r 10 --iso nan -o "$T/u.svg"
expect_rc 2 "nan iso"
check "no output after usage errors" [ ! -e "$T/u.svg" ]

# --- write errors
run -e 'sphere(1)' -b -2,-2,2,2 -r 10 -o "$T/no/such/dir/out.svg"
expect_rc 1 "unwritable svg"
run -e 'sphere(1)' -b -2,-2,2,2 -r 10 -o "$T/no/such/dir/out.obj"
expect_rc 1 "unwritable obj"

# --- limits: the estimate before the work, in the message (issue 15)
run -e 'gyroid(30)' -b -1,-1,1,1 -r 2000 --max-triangles 1000 -o "$T/lim.svg"
expect_rc 1 "--max-triangles"
expect_err_match "*would have about * (estimate), more than --max-triangles 1000*" "limit message"
check "no output past the limit" [ ! -e "$T/lim.svg" ]
run -e 'gyroid(30)' -b -1,-1,1,1 -r 2000 --max-memory 1M -o "$T/lim.svg"
expect_rc 1 "--max-memory"
expect_err_match "*MiB (estimate), more than --max-memory*" "memory message"
run -e 'sphere(1)' -b -2,-2,2,2 -r 64 --max-triangles 10000 --json -o "$T/ok.svg"
expect_rc 0 "within the limit"
checks=$((checks + 1))
"$PY" -c 'import json,sys; d=json.loads(sys.argv[1]); e=d["estimated_vertices"]; v=d["vertices"]
assert 0.7*v <= e <= 1.3*v, (e, v)' "$out" || fail "estimate within 30% of the vertices made: $out"

# --- NaN somewhere on the grid: the warning says where (grid index, point)
run -e 'sqrt(x - 0.3) - 0.5' -b -1,-1,1,1 -r 8 --json -o "$T/nan.svg"
expect_rc 0 "NaN field"
expect_err_match "*NaN at 54 grid nodes*first at node (0, 0), point (-1, -1)*" "NaN warning"
checks=$((checks + 1))
"$PY" -c 'import json,sys; d=json.loads(sys.argv[1]); assert d["nan_nodes"] == 54
assert d["first_nan"] == {"node": [0, 0], "point": [-1, -1]}, d["first_nan"]
assert d["warnings"]' "$out" || fail "NaN in --json: $out"
run -e 'sqrt(x) - 0.5' -b 0,-1,1,1 -r 8 -o "$T/nonan.svg"
check "no NaN warning when there is none" [ -z "$err" ]

# the work before it (issue 15): an expression samples only the cells near
# the curve, so res 100000 (10^10 cells; more than 8 minutes before) is
# quick, and --max-cells refuses past the count with the figure
run -e 'x^2 + y^2 - 1' -b -2,-2,2,2 -r 100000 --json -o "$T/fine.obj"
expect_rc 0 "res 100000"
checks=$((checks + 1))
"$PY" -c 'import json,sys; d=json.loads(sys.argv[1]); assert d["polylines"] == 1 and d["vertices"] > 190000, d
assert d["cells_sampled"] < 1e-3 * 1e10, d["cells_sampled"]' "$out" || fail "res 100000: $out"
run -e 'x^2 + y^2 - 1' -b -2,-2,2,2 -r 100000 --max-cells 1M -o "$T/refused.obj"
expect_rc 1 "--max-cells 1M"
expect_err_match "*would sample 3200000 grid cells*more than --max-cells 1000000*" "--max-cells message"
check "a refused run leaves no file" [ ! -e "$T/refused.obj" ]
run -e 'x^2 + y^2 - 1' -b -2,-2,2,2 -r 8 --max-cells 0 -o "$T/refused.obj"
expect_rc 2 "--max-cells 0"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
