#!/bin/bash
# Tests of geom-iso: isosurfaces of expressions and raw volumes checked by
# independent references computed by Python from the OBJ text (every edge
# used exactly twice, in opposite directions: closed, manifold, oriented;
# V - E + F against the known genus; enclosed volume against 4 pi r^3 / 3;
# vertex normals against p / |p| for a sphere; vertices inside the volume's
# box), the --json keys and their agreement with the file, the summary
# lines, --refine, --caps, --iso, --res N,NY,NZ, writing to standard
# output, and errors (exit 1 with the expression's column, unreadable or
# mis-sized volumes) and usage errors (exit 2).
# Usage: test_geom_iso.sh /path/to/geom-iso   (env PYTHON3: Debian's python3)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOL" >&2
    exit 2
fi
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-iso-test.XXXXXX") || exit 1
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
expect_err() { # expect_err SUBSTRING WHAT
    checks=$((checks + 1))
    case $err in
    *"$1"*) ;;
    *) fail "$2: stderr '$err' lacks '$1'" ;;
    esac
}

# check.py OBJ [options]: independent checks of an OBJ triangle mesh; prints
# nothing and exits 0 when every requested property holds, else the reasons.
#   --euler N        V - E + F (used vertices)
#   --closed         every edge in exactly two faces, in opposite directions
#   --volume V TOL   |enclosed volume - V| <= TOL * V
#   --sphere-normals vn lines are unit and equal to v / |v| within 1e-9
#   --inside X0 Y0 Z0 X1 Y1 Z1   every vertex in the box
#   --json FILE      the JSON summary's vertices/triangles match the file
cat >"$T/check.py" <<'EOF'
import sys, json, math
args = sys.argv[1:]
path = args.pop(0)
V, N, F = [], [], []
for line in open(path):
    p = line.split()
    if not p:
        continue
    if p[0] == 'v':
        V.append(tuple(float(x) for x in p[1:4]))
    elif p[0] == 'vn':
        N.append(tuple(float(x) for x in p[1:4]))
    elif p[0] == 'f':
        F.append(tuple(int(x.split('/')[0]) - 1 for x in p[1:]))
bad = []
if any(len(f) != 3 for f in F):
    bad.append('non-triangle face')
while args:
    a = args.pop(0)
    if a == '--euler':
        want = int(args.pop(0))
        used = {i for f in F for i in f}
        edges = {tuple(sorted((f[k], f[(k + 1) % 3]))) for f in F for k in range(3)}
        chi = len(used) - len(edges) + len(F)
        if chi != want:
            bad.append('euler %d, expected %d' % (chi, want))
    elif a == '--closed':
        directed = {}
        for f in F:
            for k in range(3):
                e = (f[k], f[(k + 1) % 3])
                directed[e] = directed.get(e, 0) + 1
        for (u, v), c in directed.items():
            if c != 1 or directed.get((v, u), 0) != 1:
                bad.append('edge %d-%d not used once each way' % (u, v))
                break
    elif a == '--volume':
        want, tol = float(args.pop(0)), float(args.pop(0))
        vol = 0.0
        for f in F:
            (ax, ay, az), (bx, by, bz), (cx, cy, cz) = (V[i] for i in f)
            vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
        vol /= 6.0
        if abs(vol - want) > tol * want:
            bad.append('volume %.9g, expected %.9g' % (vol, want))
    elif a == '--sphere-normals':
        if len(N) != len(V):
            bad.append('%d normals for %d vertices' % (len(N), len(V)))
        for v, n in zip(V, N):
            r = math.sqrt(sum(x * x for x in v))
            if abs(math.sqrt(sum(x * x for x in n)) - 1) > 1e-9 or \
               max(abs(n[k] - v[k] / r) for k in range(3)) > 1e-9:
                bad.append('normal %r at %r' % (n, v))
                break
    elif a == '--inside':
        box = [float(args.pop(0)) for _ in range(6)]
        for v in V:
            if not all(box[k] <= v[k] <= box[k + 3] for k in range(3)):
                bad.append('vertex %r outside the box' % (v,))
                break
    elif a == '--json':
        j = json.load(open(args.pop(0)))
        if j['vertices'] != len(V) or j['triangles'] != len(F):
            bad.append('json %d/%d, file %d/%d' % (j['vertices'], j['triangles'], len(V), len(F)))
if bad:
    print('; '.join(bad))
    sys.exit(1)
EOF
check() { # check WHAT OBJ [options]
    checks=$((checks + 1))
    local what=$1
    shift
    local msg
    msg=$("$PY" "$T/check.py" "$@" 2>&1) || fail "$what: $msg"
}
jget() { # jget FILE KEY: the value of KEY in the JSON object in FILE
    "$PY" -c 'import json,sys; v=json.load(open(sys.argv[1]))[sys.argv[2]]; print("null" if v is None else repr(v))' "$1" "$2"
}
jtrue() { # jtrue WHAT FILE PYTHON-EXPR-over-j
    checks=$((checks + 1))
    "$PY" -c 'import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if eval(sys.argv[2]) else 1)' \
        "$2" "$3" || fail "$1: $3 is false for $(cat "$2")"
}

PI=3.141592653589793

# ------------------------------------------------------------- sphere
run --expr 'sphere(1)' --bounds -1.3,-1.27,-1.31,1.29,1.33,1.3 --res 24 --json -o "$T/s.obj"
expect_rc 0 "sphere"
echo "$out" >"$T/s.json"
check "sphere: closed genus 0" "$T/s.obj" --closed --euler 2 --json "$T/s.json"
check "sphere: volume" "$T/s.obj" --volume "$($PY -c "print(4*$PI/3)")" 0.03
jtrue "sphere: keys" "$T/s.json" "all(k in j for k in ('vertices','triangles','max_error','seconds'))"
# the error of a polyhedron inscribed in the unit sphere with cells of
# h = 2.6/24: positive, below h^2
jtrue "sphere: max_error" "$T/s.json" "0 < j['max_error'] < (2.6/24)**2 and j['seconds'] >= 0"

# ------------------------------------------------- text summary, refine
run --expr 'sphere(1)' --bounds -1.3,-1.3,-1.3,1.3,1.3,1.3 --res 16 --refine -o "$T/r.obj"
expect_rc 0 "refine"
nv=$(grep -c '^v ' "$T/r.obj")
nf=$(grep -c '^f ' "$T/r.obj")
checks=$((checks + 2))
grep -qxF "vertices $nv" "$T/stdout" || fail "summary: no 'vertices $nv' line in: $out"
grep -qxF "triangles $nf" "$T/stdout" || fail "summary: no 'triangles $nf' line in: $out"
checks=$((checks + 1))
grep -q '^max_error ' "$T/stdout" && grep -q '^seconds ' "$T/stdout" || fail "summary lines: $out"
run --expr 'sphere(1)' --bounds -1.3,-1.3,-1.3,1.3,1.3,1.3 --res 16 --refine --json -o "$T/r.obj"
echo "$out" >"$T/r.json"
# refined vertices are roots of |p| - 1 to rounding
jtrue "refine: vertex error" "$T/r.json" "j['vertex_max_error'] < 1e-13"
checks=$((checks + 1))
"$PY" - "$T/r.obj" <<'EOF' || fail "refine: vertices not on the unit sphere"
import sys, math
for line in open(sys.argv[1]):
    p = line.split()
    if p and p[0] == 'v':
        r = math.sqrt(sum(float(x) ** 2 for x in p[1:4]))
        if abs(r - 1) > 1e-13:
            sys.exit(1)
EOF

# ------------------------------------------------------------ normals
run --expr 'sphere(1)' --bounds -1.3,-1.3,-1.3,1.3,1.3,1.3 --res 12 --normals --refine -o "$T/n.obj"
expect_rc 0 "normals"
check "normals: p / |p|" "$T/n.obj" --sphere-normals --closed

# -------------------------------------------------------- torus, --iso
run --expr 'torus(1, 0.35)' --bounds -1.5,-1.5,-0.5,1.5,1.5,0.5 --res 40,40,14 --json -o "$T/t.obj"
expect_rc 0 "torus"
echo "$out" >"$T/t.json"
check "torus: closed genus 1" "$T/t.obj" --closed --euler 0 --json "$T/t.json"
check "torus: volume 2 pi^2 R r^2" "$T/t.obj" --volume "$($PY -c "print(2*$PI**2*0.35**2)")" 0.03
run --expr 'sphere(1)' --iso 0.5 --bounds -2,-2,-2,2,2,2 --res 30 -o "$T/i.obj"
expect_rc 0 "--iso"
check "--iso 0.5: the sphere of radius 1.5" "$T/i.obj" --closed --euler 2 \
    --volume "$($PY -c "print(4*$PI/3*1.5**3)")" 0.03

# -------------------------------------------------------------- caps
run --expr 'gyroid()' --bounds -3,-3.1,-2.9,3.05,3,3.1 --res 24 --caps --json -o "$T/g.obj"
expect_rc 0 "gyroid caps"
echo "$out" >"$T/g.json"
check "gyroid with caps: closed" "$T/g.obj" --closed --json "$T/g.json"
jtrue "gyroid: cap triangles" "$T/g.json" "j['cap_triangles'] > 0"
run --expr 'sphere(1)' --bounds 0,-1.2,-1.2,1.2,1.2,1.2 --res 30 --caps -o "$T/h.obj"
check "hemisphere with a cap: volume 2 pi / 3" "$T/h.obj" --closed --euler 2 \
    --volume "$($PY -c "print(2*$PI/3)")" 0.03

# ------------------------------------------------ output to stdout
run --expr 'sphere(1)' --bounds -1.3,-1.3,-1.3,1.3,1.3,1.3 --res 8 -o -
expect_rc 0 "stdout"
printf '%s\n' "$out" >"$T/o.obj"
check "stdout: an OBJ" "$T/o.obj" --closed --euler 2
expect_err "vertices " "stdout: summary on stderr"

# ------------------------------------------------------------ volumes
"$PY" - "$T" <<'EOF'
import sys, struct, math
d = sys.argv[1]
# 20 x 18 x 16 samples of |p - c| - 5 (spacing 1, origin 0), f32 and f64
nx, ny, nz = 20, 18, 16
c = (9.5, 8.7, 7.4)
vals = [math.sqrt((i - c[0])**2 + (j - c[1])**2 + (k - c[2])**2) - 5
        for k in range(nz) for j in range(ny) for i in range(nx)]
open(d + '/v32.raw', 'wb').write(struct.pack('<%df' % len(vals), *vals))
open(d + '/v64.raw', 'wb').write(struct.pack('<%dd' % len(vals), *vals))
EOF
run --volume "$T/v32.raw" --dims 20,18,16 --type f32 --json -o "$T/v.obj"
expect_rc 0 "volume f32"
echo "$out" >"$T/v.json"
check "volume f32: closed sphere" "$T/v.obj" --closed --euler 2 --json "$T/v.json" \
    --inside 0 0 0 19 17 15 --volume "$($PY -c "print(4*$PI/3*125)")" 0.05
jtrue "volume: max_error is null (sampled)" "$T/v.json" "j['max_error'] is None"
run --volume "$T/v64.raw" --dims 20,18,16 --type f64 --spacing 0.5,0.25,2 --origin 1,-2,3 -o "$T/w.obj"
expect_rc 0 "volume f64 placed"
check "volume f64: placed by spacing and origin" "$T/w.obj" --closed --euler 2 \
    --inside 1 -2 3 10.5 2.25 33
run --volume "$T/v64.raw" --dims 20,18,16 --type f64 --bounds 2,2,2,17,15,13 --res 30 --caps -o "$T/x.obj"
expect_rc 0 "volume resampled"
check "volume resampled with caps: closed" "$T/x.obj" --closed --inside 2 2 2 17 15 13

# ------------------------------------------------------ orientation (inside)
# A CT-like volume, dense inside: 1000 - 100 |p - c| (above 500 within
# radius 5). The boundary samples lie below 500, so inside is detected as
# above: the surface faces outward (positive enclosed volume, as the file
# says and as --json says). --inside below forces the other side: the same
# surface inside out (negative volume).
"$PY" - "$T" <<'EOF2'
import sys, struct, math
d = sys.argv[1]
nx, ny, nz = 20, 18, 16
c = (9.5, 8.7, 7.4)
vals = [1000 - 100 * math.sqrt((i - c[0])**2 + (j - c[1])**2 + (k - c[2])**2)
        for k in range(nz) for j in range(ny) for i in range(nx)]
open(d + '/ct.raw', 'wb').write(struct.pack('<%df' % len(vals), *vals))
EOF2
V5=$($PY -c "print(4*$PI/3*125)")
run --volume "$T/ct.raw" --dims 20,18,16 --type f32 --iso 500 --json -o "$T/ct.obj"
expect_rc 0 "CT volume"
echo "$out" >"$T/ct.json"
check "CT volume: detected inside above, outward" "$T/ct.obj" --closed --euler 2 --json "$T/ct.json" \
    --volume "$V5" 0.05
jtrue "CT volume: inside above, detected" "$T/ct.json" "j['inside'] == 'above' and j['inside_detected']"
jtrue "CT volume: signed volume positive" "$T/ct.json" "abs(j['signed_volume'] - $V5) < 0.05 * $V5"
run --volume "$T/ct.raw" --dims 20,18,16 --type f32 --iso 500 --inside below --json -o "$T/ct2.obj"
expect_rc 0 "CT volume, inside below"
echo "$out" >"$T/ct2.json"
jtrue "CT volume, inside below: inside out" "$T/ct2.json" \
    "j['inside'] == 'below' and not j['inside_detected'] and j['signed_volume'] < -0.9 * $V5"
run --volume "$T/v32.raw" --dims 20,18,16 --type f32 --json -o "$T/sd.obj"
echo "$out" >"$T/sd.json"
jtrue "distance volume: detected inside below" "$T/sd.json" \
    "j['inside'] == 'below' and j['inside_detected'] and j['signed_volume'] > 0"
# An expression with inside above: -sphere(1) is the sphere again.
run --expr '-sphere(1)' --inside above --bounds -1.3,-1.27,-1.31,1.29,1.33,1.3 --res 24 --json -o "$T/ns.obj"
expect_rc 0 "expression, inside above"
echo "$out" >"$T/ns.json"
check "-sphere(1), inside above: closed, outward" "$T/ns.obj" --closed --euler 2 \
    --volume "$($PY -c "print(4*$PI/3)")" 0.02
jtrue "error report object" "$T/ns.json" \
    "j['error']['max'] == j['max_error'] and j['error']['mean'] == j['mean_error'] and j['error']['method'] == 'sampled' and j['error']['tolerance'] is None and j['error']['pieces'] > j['vertices']"
jtrue "volume: error not measured" "$T/ct.json" "j['error']['method'] == 'none' and j['error']['max'] is None"
run --expr 'sphere(1)' --bounds -1.3,-1.27,-1.31,1.29,1.33,1.3 --res 24 -o "$T/ps.obj"
checks=$((checks + 1))
cmp -s "$T/ns.obj" "$T/ps.obj" || fail "-sphere(1) above and sphere(1) below differ"
run --expr 'sphere(1)' --inside sideways --bounds 0,0,0,1,1,1 --res 4 -o "$T/e.obj"
expect_rc 2 "--inside sideways"

# ------------------------------------------------------------- errors
run --expr 'sphere(1' --bounds 0,0,0,1,1,1 --res 4 -o "$T/e.obj"
expect_rc 1 "bad expression"
expect_err "expression:1:" "bad expression: column"
checks=$((checks + 1))
[ ! -e "$T/e.obj" ] || fail "bad expression: output written"
run --expr 'sphere(1)' -o "$T/e.obj"
expect_rc 2 "expr without bounds"
run --expr 'sphere(1)' --volume "$T/v32.raw" --bounds 0,0,0,1,1,1 --res 4 -o "$T/e.obj"
expect_rc 2 "expr and volume"
run --expr 'sphere(1)' --bounds 1,0,0,0,1,1 --res 4 -o "$T/e.obj"
expect_rc 2 "empty bounds"
run --expr 'sphere(1)' --bounds 0,0,0,1,1,1 --res 0 -o "$T/e.obj"
expect_rc 2 "zero res"
run --expr 'sphere(1)' --bounds 0,0,0,1,1,1 --res 2,3 -o "$T/e.obj"
expect_rc 2 "two resolutions"
run --volume "$T/v32.raw" --dims 20,18,16 --type f16 -o "$T/e.obj"
expect_rc 2 "bad type"
run --volume "$T/v32.raw" --dims 20,18 --type f32 -o "$T/e.obj"
expect_rc 2 "two dims"
run --volume "$T/v32.raw" --dims 20,18,17 --type f32 -o "$T/e.obj"
expect_rc 1 "wrong raw size"
run --volume "$T/missing.raw" --dims 2,2,2 --type f32 -o "$T/e.obj"
expect_rc 1 "missing volume"
run --expr 'sphere(1)' --bounds 0,0,0,1,1,1 --res 4 --json -o -
expect_rc 2 "--json with stdout"
run --expr 'sphere(1)' --bounds 0,0,0,1,1,1 --res 4 -o "$T/e.xyz"
expect_rc 2 "unknown output format"

# --- the sparse path (default) against --dense: byte-identical files, on
# the benchmark's two tori, planes through grid nodes (values exactly on the
# iso value), a plate thinner than a cell, a NaN region, caps and normals
for e in 'min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))' 'x - 0.25' \
    'abs(z - 0.01) - 0.001' 'sqrt(x) - 0.5' 'gyroid(6)'; do
    for extra in "" "--caps --normals" "--inside above"; do
        # shellcheck disable=SC2086
        run --expr "$e" --bounds -1,-1,-1,1,1,1 --res 40,36,32 $extra -o "$T/sp.ply"
        expect_rc 0 "sparse $e $extra"
        # shellcheck disable=SC2086
        run --expr "$e" --bounds -1,-1,-1,1,1,1 --res 40,36,32 $extra --dense -o "$T/de.ply"
        expect_rc 0 "dense $e $extra"
        checks=$((checks + 1))
        cmp -s "$T/sp.ply" "$T/de.ply" || fail "sparse and dense differ: $e $extra"
    done
done
run --expr 'sphere(0.5)' --bounds -1,-1,-1,1,1,1 --res 64 --json -o "$T/sp.obj"
expect_rc 0 "sparse --json"
checks=$((checks + 1))
"$PY" -c 'import json,sys; d=json.loads(sys.argv[1])
assert d["cells"] == 64**3 and 0 < d["cells_evaluated"] < d["cells"] / 4, d
assert d["blocks"] == 512 and d["blocks_skipped"] > 0 and d["error_stride"] >= 1' "$out" ||
    fail "cells_evaluated in --json: $out"
run --expr 'sphere(0.5)' --bounds -1,-1,-1,1,1,1 --res 64 --dense --json -o "$T/de.obj"
checks=$((checks + 1))
"$PY" -c 'import json,sys; d=json.loads(sys.argv[1])
assert d["cells_evaluated"] == d["cells"] and d["blocks"] == 0, d' "$out" ||
    fail "--dense evaluates every cell: $out"

# --- a NaN field says where (issue 15)
run --expr 'sqrt(x - 0.3) - 0.5' --bounds -1,-1,-1,1,1,1 --res 8 --json -o "$T/nan.obj"
expect_rc 0 "NaN field"
expect_err "NaN at 486 grid nodes (counted outside); the first at node (0, 0, 0), point (-1, -1, -1)" "NaN warning"
checks=$((checks + 1))
"$PY" -c 'import json,sys; d=json.loads(sys.argv[1]); assert d["nan_nodes"] == 486
assert d["first_nan"] == {"node": [0, 0, 0], "point": [-1, -1, -1]}, d
assert any("NaN" in w for w in d["warnings"])' "$out" || fail "NaN in --json: $out"

if [ "$failures" -ne 0 ]; then
    echo "$failures of $checks checks failed" >&2
    exit 1
fi
echo "all $checks checks passed"
