#!/bin/bash
# Tests of geom-curve on data/surfaces.json's curves, checked by Python
# against closed forms: the rational circle's polyline vertices at radius 1
# and its chords' sagitta 1 - |midpoint| within the tolerance; sampled
# derivatives of the circle (p . p' = 0 and p' . p' + p . p'' = 0); the
# clamped B-spline's end points; the Hermite spline's end tangents; the
# Catmull-Rom curve through its points; --json keys; usage errors (exit 2);
# malformed input naming the entry and the key (exit 1).
# Usage: test_geom_curve.sh TOOL DATA_DIR HAVE_JSON   (env PYTHON3)
set -u
if [ $# -ne 3 ]; then
    echo "usage: $0 TOOL DATA_DIR HAVE_JSON" >&2
    exit 2
fi
TOOL=$1
DATA=$2
HAVE_JSON=$3
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-curve-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

. "$(dirname "$0")/testlib.sh"

run --help
expect_rc 0 "--help"
run --version
expect_rc 0 "--version"

if [ "$HAVE_JSON" != 1 ]; then
    run "$DATA/surfaces.json" -o "$T/c.obj"
    expect_rc 1 "JSON without cJSON"
    expect_err "needs cJSON" "JSON without cJSON"
    echo "$checks checks, $failures failures"
    [ "$failures" -eq 0 ]
    exit
fi

# ------------------------------------------------------------------ OBJ
run "$DATA/surfaces.json" -o "$T/c.obj" --tol 1e-3 --json
expect_rc 0 "obj polylines"
echo "$out" >"$T/c.json"
pycheck "obj: polylines, circle radius and sagitta" "$T/c.json" "$T/c.obj" <<'EOF'
import json, math, sys
r = json.load(open(sys.argv[1]))
for k in ("curves", "points", "max_error", "seconds"):
    assert k in r, k
assert r["curves"] == 6 and r["max_error"] <= 1e-3
V, L, names = [], [], []
for line in open(sys.argv[2]):
    t = line.split()
    if not t: continue
    if t[0] == 'v': V.append(tuple(map(float, t[1:4])))
    elif t[0] == 'l': L.append([int(x) - 1 for x in t[1:]])
    elif t[0] == 'o': names.append(t[1])
assert len(L) == 6 and names[0] == "circle_0", names
assert sum(len(l) for l in L) == r["points"] == len(V)
circle = [V[i] for i in L[0]]
assert circle[0] == (1.0, 0.0, 0.0) and circle[-1] == (1.0, 0.0, 0.0)
for p in circle:
    assert abs(math.hypot(p[0], p[1]) - 1) < 4e-16, p
sag = max(1 - math.hypot((a[0] + b[0]) / 2, (a[1] + b[1]) / 2) for a, b in zip(circle, circle[1:]))
assert 0 < sag <= 1e-3, sag
# Catmull-Rom (curve 4) passes through its points: they are polyline vertices
cr = set((p[0], p[1]) for p in (V[i] for i in L[4]))
for q in [(0, 0), (1, 2), (3, 2), (4, 0), (6, 1)]:
    assert q in cr, q
# the closed Kochanek-Bartels loop ends where it starts
kb = [V[i] for i in L[5]]
assert kb[0] == kb[-1] == (0.0, 0.0, 0.0)
print("ok")
EOF

# ------------------------------------------------------------------ CSV
run "$DATA/surfaces.json" -o "$T/c.csv" --samples 33 --derivs 2
expect_rc 0 "csv samples"
pycheck "csv: circle derivatives, B-spline ends, Hermite tangents" "$T/c.csv" <<'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert list(rows[0].keys())[:6] == ["curve", "index", "u", "x", "y", "z"]
by = {}
for r in rows:
    by.setdefault(int(r["curve"]), []).append({k: float(v) for k, v in r.items()})
assert len(by) == 6 and all(len(v) == 33 for v in by.values())
for r in by[0]:
    p = (r["x"], r["y"]); d1 = (r["d1x"], r["d1y"]); d2 = (r["d2x"], r["d2y"])
    assert abs(math.hypot(*p) - 1) < 4e-16
    s = math.hypot(*d1)
    assert abs(p[0] * d1[0] + p[1] * d1[1]) <= 1e-14 * s
    assert abs(d1[0] ** 2 + d1[1] ** 2 + p[0] * d2[0] + p[1] * d2[1]) <= 1e-13 * s * s
w = by[1]
assert (w[0]["x"], w[0]["y"]) == (0, 0) and (w[-1]["x"], w[-1]["y"]) == (6, 0)
assert w[0]["u"] == 0 and w[-1]["u"] == 1
h = by[3]   # Hermite through (0,0), (1,1), (2,0) with tangents (1,1), (1,0), (1,-1)
assert (h[0]["d1x"], h[0]["d1y"]) == (1, 1), h[0]
assert abs(h[-1]["d1x"] - 1) < 1e-15 and abs(h[-1]["d1y"] + 1) < 1e-15, h[-1]
assert (h[16]["x"], h[16]["y"]) == (1, 1) and h[16]["u"] == 1.0
assert (h[16]["d1x"], h[16]["d1y"]) == (1, 0)
print("ok")
EOF

# ---------------------------------------------------------------- errors
run "$DATA/surfaces.json" -o "$T/x.obj" --derivs 1
expect_rc 2 "--derivs with obj"
run "$DATA/surfaces.json" -o "$T/x.obj" --tol 1e-3 --samples 5
expect_rc 2 "--tol with --samples"
run "$DATA/surfaces.json" -o "$T/x.obj" --samples 1
expect_rc 2 "--samples 1"
run "$DATA/surfaces.json" -o "$T/x.txt"
expect_rc 2 "unknown format"
printf '{"curves": [{"name": "c", "type": "spiral", "points": [[0,0],[1,1]]}]}' >"$T/bad1.json"
run "$T/bad1.json" -o "$T/x.obj"
expect_rc 1 "unknown type"
expect_err 'curves[0] ("c"): "type": unknown curve type "spiral"' "unknown type named"
printf '{"curves": [{"type": "bspline", "degree": 2, "knots": [0,0,0,1,1], "points": [[0,0],[1,1],[2,0]]}]}' >"$T/bad2.json"
run "$T/bad2.json" -o "$T/x.obj"
expect_rc 1 "knot count"
expect_err 'curves[0]: "knots": 5 knots, 6 expected' "knot count named"
printf '{"curves": [{"type": "hermite", "points": [[0,0],[1,1]], "tangents": [[1,0]]}]}' >"$T/bad3.json"
run "$T/bad3.json" -o "$T/x.obj"
expect_rc 1 "tangent count"
expect_err '"tangents": 1 points, 2 expected' "tangent count named"
printf '{"curves": [{"type": "nurbs", "degree": 1, "knots": [0,0,1,1], "points": [[0,0],[1,1]], "weights": [1, 0]}]}' >"$T/bad4.json"
run "$T/bad4.json" -o "$T/x.obj"
expect_rc 1 "zero weight"
expect_err '"weights":' "zero weight named"

# limits: the output is counted before the work; past --max-points an error
# with the count, exit 1, nothing written
rm -f "$T/big.obj"
run "$DATA/surfaces.json" -o "$T/big.obj" --samples 1000000 --max-points 1000
expect_rc 1 "--samples past --max-points"
expect_err "would have 1000000 points (limit 1000" "--samples estimate in the message"
checks=$((checks + 1))
[ ! -e "$T/big.obj" ] || fail "--max-points: output written"
run "$DATA/surfaces.json" -o "$T/big.obj" --tol 1e-4 --max-points 100
expect_rc 1 "--tol past --max-points"
expect_err "raise --max-points or the tolerance" "--tol limit message"
run "$DATA/surfaces.json" -o "$T/ok.obj" --tol 1e-4 --max-points 100000
expect_rc 0 "--max-points above the count"
run "$DATA/surfaces.json" -o "$T/x.obj" --max-points 1
expect_rc 2 "--max-points 1"

# the a priori bound (geom_curve_nurbs_polyline_estimate) of two polynomial
# curves at 1e-6 is 2049 + 4098 = 6147 points for 2049 + 3656 = 5705 made:
# above the bound no count is needed; between count and bound the exact
# count decides (the run succeeds); below the count it fails naming it
printf '{"curves": [{"type": "bezier", "points": [[0,0],[1,2],[3,2],[4,0]]}, {"type": "bspline", "degree": 2, "knots": [0,0,0,0.5,1,1,1], "points": [[0,0],[1,3],[2,-1],[4,0]]}]}' >"$T/poly.json"
for lim in 7000 6000; do
    run "$T/poly.json" -o "$T/poly.obj" --tol 1e-6 --max-points $lim
    expect_rc 0 "--max-points $lim (count 5705, bound 6147)"
    checks=$((checks + 1))
    [ "$(grep -c '^v ' "$T/poly.obj")" = 5705 ] || fail "--max-points $lim: not 5705 vertices"
done
run "$T/poly.json" -o "$T/poly.obj" --tol 1e-6 --max-points 5000
expect_rc 1 "--max-points below the count"
expect_err "would have 5705 points (limit 5000" "exact count past the bound"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
