#!/bin/bash
# Tests of geom-normals: per-corner normals written as OBJ vn against closed
# forms computed here by Python (face normals of a cube at a 30 degree
# crease; smooth angle-weighted (+-1,+-1,+-1)/sqrt(3); uniform weights on an
# asymmetrically triangulated box: the sum of the incident triangles' unit
# normals), --json, standard output, usage errors (exit 2), read errors with
# FILE:LINE (exit 1) and the no-partial-output guarantee of -o.
# Usage: test_geom_normals.sh /path/to/geom-normals   (env PYTHON3: python)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOL" >&2
    exit 2
fi
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-normals-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

. "$(dirname "$0")/testlib.sh"

# Box [0,1]x[0,2]x[0,3]: quads, and quads split along their first diagonal.
cat >"$T/boxq.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 0 2 0
v 1 2 0
v 0 0 3
v 1 0 3
v 0 2 3
v 1 2 3
f 1 3 4 2
f 5 6 8 7
f 1 2 6 5
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
EOF
awk '/^v /{print} /^f /{print "f", $2, $3, $4; print "f", $2, $4, $5}' "$T/boxq.obj" >"$T/boxt.obj"

# The OBJ reader used by the checks: positions, normals, faces (v, vn).
cat >"$T/objread.py" <<'EOF'
import math
def read_obj(path):
    V, N, F = [], [], []
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': V.append(tuple(map(float, t[1:4])))
        elif t[0] == 'vn': N.append(tuple(map(float, t[1:4])))
        elif t[0] == 'f':
            F.append([(int(c.split('/')[0]) - 1, int(c.split('/')[2]) - 1 if c.count('/') == 2 and c.split('/')[2] else None) for c in t[1:]])
    return V, N, F
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def cross(a, b): return (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
def unit(a):
    l = math.sqrt(sum(x * x for x in a)); return tuple(x / l for x in a)
def newell(V, f):
    n = [0.0, 0.0, 0.0]
    for i in range(len(f)):
        a, b = V[f[i][0]], V[f[(i + 1) % len(f)][0]]
        n[0] += (a[1] - b[1]) * (a[2] + b[2]); n[1] += (a[2] - b[2]) * (a[0] + b[0]); n[2] += (a[0] - b[0]) * (a[1] + b[1])
    return unit(n)
def close(a, b, tol=1e-15): return all(abs(x - y) <= tol for x, y in zip(a, b))
EOF

# --- crease 30 on the box: every corner carries its face's normal
run --crease 30 "$T/boxq.obj" -o "$T/out.obj"
expect_rc 0 "--crease 30"
pycheck "crease 30: corner normals are face normals, 24 of them" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from objread import *
V, N, F = read_obj(sys.argv[1])
assert len(N) == 24, len(N)
for f in F:
    fn = newell(V, f)
    for (v, n) in f:
        assert n is not None and close(N[n], fn), (f, N[n], fn)
print("ok")
EOF

# --- smooth (default): angle weights, (+-1,+-1,+-1)/sqrt(3) at each corner
for w in "" "--weight angle" "-w angle"; do
    # shellcheck disable=SC2086
    run $w "$T/boxt.obj" -o "$T/out.obj"
    expect_rc 0 "smooth $w"
    pycheck "smooth $w: (+-1,+-1,+-1)/sqrt(3)" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from objread import *
V, N, F = read_obj(sys.argv[1])
assert len(N) == 8, len(N)
for f in F:
    for (v, n) in f:
        e = tuple((1 if c > 0 else -1) / math.sqrt(3) for c in V[v])
        assert close(N[n], e), (V[v], N[n])
print("ok")
EOF
done

# --- uniform and area weights on the triangulated box, Max radial
for w in uniform area max; do
    run --weight "$w" "$T/boxt.obj" -o "$T/out.obj"
    expect_rc 0 "--weight $w"
    pycheck "--weight $w: closed form" "$T/out.obj" "$w" <<EOF
import sys; sys.path.insert(0, "$T"); from objread import *
V, N, F = read_obj(sys.argv[1]); w = sys.argv[2]
acc = {}
for f in F:
    a, b, c = (V[x[0]] for x in f)
    n = cross(sub(b, a), sub(c, a)); l = math.sqrt(sum(x * x for x in n))
    for x in f:
        s = acc.setdefault(x[0], [0.0, 0.0, 0.0])
        for k in range(3): s[k] += n[k] / l if w == 'uniform' else n[k]
for f in F:
    for (v, n) in f:
        if w == 'max':
            e = unit(tuple(c - m for c, m in zip(V[v], (0.5, 1.0, 1.5))))
        else:
            e = unit(acc[v])
        assert close(N[n], e), (w, V[v], N[n], e)
print("ok")
EOF
done

# --- --json summary
run --crease 30 --json "$T/boxq.obj" -o "$T/out.obj"
expect_rc 0 "--json"
pycheck "--json keys and counts" "$out" <<'EOF'
import sys, json
d = json.loads(sys.argv[1])
assert d["faces"] == 6 and d["vertices"] == 8 and d["normals"] == 24 and d["zero_normals"] == 0, d
assert d["seconds"] >= 0
print("ok")
EOF

# --- degenerate (zero-area) faces: a warning with the count and the first
# face (0-based), in --json too; never NaN normals
cat >"$T/deg.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 3 0 0
v 4 0 0
v 0 0 5
v 0 0 5
v 1 1 5
f 1 2 3
f 5 6 7
f 1 3 4
f 8 9 10
EOF
run "$T/deg.obj" -o "$T/deg_out.obj"
expect_rc 0 "degenerate faces"
expect_degenerate "degenerate faces" "2 degenerate (zero-area) faces, the first face 1"
checks=$((checks + 1))
grep -qi nan "$T/deg_out.obj" && fail "degenerate faces: NaN written"
run --json "$T/deg.obj" -o "$T/deg_out.obj"
expect_rc 0 "degenerate faces --json"
expect_degenerate_json "degenerate faces --json" 2 1
pycheck "degenerate faces --json: zero normals" "$out" <<'EOF'
import sys, json
d = json.loads(sys.argv[1])
assert d["zero_normals"] == 6, d   # vertices 5..10 touch only degenerate faces
print("ok")
EOF
run --json "$T/boxq.obj" -o "$T/deg_out.obj"
expect_degenerate_json "no degenerate faces --json" 0 null

# --- standard output with --format, and PLY output
run --format obj "$T/boxq.obj"
expect_rc 0 "stdout --format obj"
checks=$((checks + 1))
[ "$(grep -c '^vn ' "$T/stdout")" -eq 8 ] || fail "stdout: expected 8 vn lines"
run --crease 30 "$T/boxq.obj" -o "$T/out.ply"
expect_rc 0 "PLY output"
checks=$((checks + 1))
head -c 3 "$T/out.ply" | grep -q ply || fail "PLY output: no ply magic"

# --- usage errors: exit 2, nothing written
rm -f "$T/never.obj"
for args in "--weight heavy" "--crease 0" "--crease 180" "--crease abc" "--crease 30 --json"; do
    # shellcheck disable=SC2086
    run $args "$T/boxq.obj" -o "$T/never.obj"
    if [ "$args" = "--crease 30 --json" ]; then
        expect_rc 0 "$args"
        rm -f "$T/never.obj"
        continue
    fi
    expect_rc 2 "usage error '$args'"
    checks=$((checks + 1))
    [ ! -e "$T/never.obj" ] || fail "usage error '$args' left an output file"
done
run "$T/boxq.obj"
expect_rc 2 "stdout without --format"
run
expect_rc 2 "missing operand"
run "$T/boxq.obj" "$T/boxq.obj" -o "$T/x.obj"
expect_rc 2 "extra operand"
run --json "$T/boxq.obj" --format obj
expect_rc 2 "--json to stdout"

# --- read errors: exit 1 with FILE:LINE, and no partial output
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n' >"$T/bad.obj"
echo "keep me" >"$T/existing.obj"
run "$T/bad.obj" -o "$T/existing.obj"
expect_rc 1 "parse error"
checks=$((checks + 1))
case $err in *bad.obj:4:*) ;; *) fail "parse error: message lacks FILE:LINE: $err" ;; esac
checks=$((checks + 1))
[ "$(cat "$T/existing.obj")" = "keep me" ] || fail "parse error clobbered the output"
run "$T/missing.obj" -o "$T/x.obj"
expect_rc 1 "missing input"
run "$T/boxq.obj" -o "$T/no/such/dir/out.obj"
expect_rc 1 "unwritable output"
checks=$((checks + 1))
[ -z "$(ls -A "$T" | grep '^\.' )" ] || fail "a temporary file was left behind"

# --- standard input
"$TOOL" --input-format obj --format obj - <"$T/boxq.obj" >"$T/stdout" 2>"$T/stderr"
rc=$?
err=$(cat "$T/stderr")
expect_rc 0 "standard input"

testlib_summary
