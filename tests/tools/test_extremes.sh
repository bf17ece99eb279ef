#!/bin/bash
# Never wrong at the extremes (issue 15): the same curves and surfaces
# scaled by powers of ten from 1e-300 to 1e307 give the same polylines and
# tessellations (point and triangle counts equal to those at scale 1, errors
# scaled by the same factor to 1e-9), or fail with a message; never a chord
# with max_error 0, never 0 triangles with exit 0, never fewer triangles
# than the grid asks for. Closed form: tessellation is invariant under
# scaling, so scale 1 is the reference.
# SVG output of geom-contour never holds nan or inf (huge and tiny bounds).
# Usage: test_extremes.sh GEOM-TESSELLATE GEOM-CURVE DATA_DIR [GEOM-CONTOUR]  (env PYTHON3)
set -u
TESS=$1
CURVE=$2
DATA=$3
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-extremes.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
svg_fail=0
if [ $# -ge 4 ]; then
    for b in -1e307,-1e307,1e307,1e307 0,0,1e-300,1 -1e308,-1e308,1e308,1e308; do
        "$4" --expr 'x-y' --bounds "$b" --res 8 -o "$T/c.svg" >/dev/null 2>"$T/err"; rc=$?
        if [ $rc -eq 0 ] && grep -qiE 'nan|inf' "$T/c.svg"; then
            echo "FAIL: geom-contour --bounds $b: nan/inf in the SVG" >&2; svg_fail=1
        elif [ $rc -ne 0 ] && ! grep -q overflows "$T/err"; then
            echo "FAIL: geom-contour --bounds $b: exit $rc: $(cat "$T/err")" >&2; svg_fail=1
        fi
        rm -f "$T/c.svg"
    done
fi
"$PY" - "$TESS" "$CURVE" "$DATA/surfaces.json" "$T" <<'PYEOF'
import json, subprocess, sys
tess, curve, src, tmp = sys.argv[1:5]
d = json.load(open(src))
def scale(x, s):
    return [scale(y, s) for y in x] if isinstance(x, list) else x * s
fails = checks = 0
def check(ok, what):
    global fails, checks
    checks += 1
    if not ok:
        fails += 1
        print("FAIL:", what, file=sys.stderr)
def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    return r.returncode, (json.loads(r.stdout) if r.returncode == 0 else None), r.stderr
scales = [1.0, 1e-300, 1e155, 1e200, 1e300, 5e307]
for s in d["surfaces"]:
    for args in ([], ["-g", "4,4"]):
        ref = None
        for S in scales:
            s2 = dict(s, points=scale(s["points"], S))
            if max(abs(v) for row in s2["points"] for pt in row for v in pt) > 1.7e308:
                continue
            p = f"{tmp}/s.json"
            json.dump({"surfaces": [s2]}, open(p, "w"))
            rc, j, err = run([tess, p, "-o", f"{tmp}/s.obj", "--json"] + args)
            what = f"{s['name']} {args} x{S:g}"
            check(rc == 0, f"{what}: exit {rc} {err.strip()}")
            if rc != 0:
                continue
            check(j["triangles"] > 0, f"{what}: 0 triangles")
            if ref is None:
                ref = j
                continue
            check(j["triangles"] == ref["triangles"],
                  f"{what}: {j['triangles']} triangles, {ref['triangles']} at scale 1")
            e, r = j["max_error"], ref["max_error"]
            check(e is not None and r is not None and abs(e / S - r) <= 1e-9 * r,
                  f"{what}: max_error {e}, expected {r} x {S:g}")
for c in d["curves"]:
    for args in ([], ["-s", "9"]):
        ref = None
        for S in scales:
            c2 = dict(c, points=scale(c["points"], S))
            if max(abs(v) for pt in c2["points"] for v in pt) > 1.7e308:
                continue
            if "tangents" in c2:
                c2["tangents"] = scale(c["tangents"], S)
            p = f"{tmp}/c.json"
            json.dump({"curves": [c2]}, open(p, "w"))
            rc, j, err = run([curve, p, "-o", f"{tmp}/c.obj", "--json"] + args)
            what = f"curve {c['name']} {args} x{S:g}"
            check(rc == 0, f"{what}: exit {rc} {err.strip()}")
            if rc != 0:
                continue
            if ref is None:
                ref = j
                continue
            check(j["points"] == ref["points"], f"{what}: {j['points']} points, {ref['points']} at scale 1")
            e, r = j["max_error"], ref["max_error"]
            check(e is not None and r is not None and abs(e / S - r) <= 1e-9 * r,
                  f"{what}: max_error {e}, expected {r} x {S:g}")
print(f"{checks} checks, {fails} failures")
sys.exit(1 if fails else 0)
PYEOF
rc=$?
[ $rc -eq 0 ] && [ $svg_fail -eq 0 ]
