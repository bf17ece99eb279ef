#!/bin/bash
# Tests of geom-clip against closed forms computed here by Python from the
# output OBJ: volume and area of a unit cube clipped by planes (with and
# without --cap; a regular-hexagon cap through the centre), repeated
# --plane, the --frustum SPEC on a large grid (the kept area is the
# frustum's rectangle at the grid's distance), --matrix, a linear vertex
# attribute (uv) staying linear, and usage/read errors.
# Usage: test_geom_clip.sh /path/to/geom-clip   (env PYTHON3: python)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOL" >&2
    exit 2
fi
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-clip-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

. "$(dirname "$0")/testlib.sh"

cat >"$T/meas.py" <<'EOF'
import math
def read(path):
    V, VT, F = [], [], []
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': V.append(tuple(map(float, t[1:4])))
        elif t[0] == 'vt': VT.append(tuple(map(float, t[1:3])))
        elif t[0] == 'f':
            F.append([(int(c.split('/')[0]) - 1, int(c.split('/')[1]) - 1 if '/' in c and c.split('/')[1] else None) for c in t[1:]])
    return V, VT, F
def area_volume(V, F):
    A = Vol = 0.0
    for f in F:
        p = [V[i] for i, _ in f]
        n = [0.0, 0.0, 0.0]
        for k in range(1, len(p) - 1):
            a, b, c = p[0], p[k], p[k + 1]
            u = [b[i] - a[i] for i in range(3)]; w = [c[i] - a[i] for i in range(3)]
            x = (u[1]*w[2]-u[2]*w[1], u[2]*w[0]-u[0]*w[2], u[0]*w[1]-u[1]*w[0])
            for i in range(3): n[i] += x[i]
            Vol += (a[0]*(b[1]*c[2]-b[2]*c[1]) - a[1]*(b[0]*c[2]-b[2]*c[0]) + a[2]*(b[0]*c[1]-b[1]*c[0])) / 6
        A += 0.5 * math.sqrt(sum(x * x for x in n))
    return A, Vol
def boundary_edges(F):
    d = {}
    for f in F:
        for k in range(len(f)):
            a, b = f[k][0], f[(k + 1) % len(f)][0]
            d[(a, b)] = d.get((a, b), 0) + 1
    return sum(1 for (a, b) in d if (b, a) not in d)
EOF

# unit cube with uv = (x + 2y, z - y) per vertex (a linear map)
"$PY" - "$T/cube.obj" <<'EOF'
import sys
P = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
Q = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)]
with open(sys.argv[1], "w") as f:
    for p in P: f.write("v %d %d %d\n" % p)
    for p in P: f.write("vt %d %d\n" % (p[0] + 2 * p[1], p[2] - p[1]))
    for q in Q: f.write("f " + " ".join("%d/%d" % (i, i) for i in q) + "\n")
EOF

run --plane 0,0,1,-0.3 "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "z >= 0.3"
pycheck "z >= 0.3: area 3.8, open (4 boundary edges)" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1]); A, Vol = area_volume(V, F)
assert abs(A - 3.8) < 1e-14 and boundary_edges(F) == 4, (A, boundary_edges(F))
assert all(p[2] >= 0.3 - 1e-15 for p in V)
print("ok")
EOF

run --cap --json --plane 1,1,1,-1.5 "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "centre plane with cap"
pycheck "x+y+z >= 1.5 capped: volume 1/2, area 3 + 3 sqrt(3)/4, closed" "$T/out.obj" "$out" <<EOF
import sys, json; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1]); A, Vol = area_volume(V, F)
assert abs(Vol - 0.5) < 1e-14 and abs(A - (3 + 3 * math.sqrt(3) / 4)) < 1e-14, (A, Vol)
assert boundary_edges(F) == 0
d = json.loads(sys.argv[2]); assert d["input_faces"] == 6 and d["faces"] == len(F), d
print("ok")
EOF

# uv stays the same linear function of position on the kept (non-cap) faces
run --plane 0.3,-0.7,1,-0.2 "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "oblique plane"
pycheck "uv linear at new vertices" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1])
n = 0
for f in F:
    for v, t in f:
        x, y, z = V[v]; u = VT[t]
        assert abs(u[0] - (x + 2 * y)) < 1e-14 and abs(u[1] - (z - y)) < 1e-14, (V[v], u)
        n += 1
assert n > 0
print("ok")
EOF

# repeated planes: the box [0.25, 0.75]^3 inside the cube, capped
run --cap -p 1,0,0,-0.25 -p -1,0,0,0.75 -p 0,1,0,-0.25 -p 0,-1,0,0.75 -p 0,0,1,-0.25 \
    -p 0,0,-1,0.75 "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "six planes"
pycheck "six planes: a closed cube of side 1/2" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1]); A, Vol = area_volume(V, F)
assert abs(Vol - 0.125) < 1e-15 and abs(A - 1.5) < 1e-14 and boundary_edges(F) == 0, (A, Vol)
print("ok")
EOF

# frustum on a 40x40 grid of [-10, 10]^2 at z = 0, seen from (0, 0, 5)
"$PY" - "$T/grid.obj" <<'EOF'
import sys
n = 40
with open(sys.argv[1], "w") as f:
    for j in range(n + 1):
        for i in range(n + 1):
            f.write("v %.17g %.17g 0\n" % (-10 + 20 * i / n, -10 + 20 * j / n))
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            f.write("f %d %d %d %d\n" % (a, a + 1, a + n + 2, a + n + 1))
EOF
run --frustum eye=0,0,5,center=0,0,0,up=0,1,0,fovy=60,aspect=1.5,near=1,far=100 \
    "$T/grid.obj" -o "$T/out.obj"
expect_rc 0 "--frustum"
pycheck "frustum: the 2h*aspect x 2h rectangle, h = 5 tan 30" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1]); A, Vol = area_volume(V, F)
h = 5 * math.tan(math.radians(30))
assert abs(A - 4 * h * h * 1.5) < 1e-11, A
assert all(abs(p[0]) <= 1.5 * h + 1e-12 and abs(p[1]) <= h + 1e-12 for p in V)
print("ok")
EOF
# fields in another order, defaults for up and aspect
run --frustum fovy=60,far=100,near=1,center=0,0,0,eye=0,0,5 "$T/grid.obj" -o "$T/out.obj"
expect_rc 0 "--frustum reordered"
pycheck "frustum defaults: aspect 1" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1]); A, Vol = area_volume(V, F)
h = 5 * math.tan(math.radians(30)); assert abs(A - 4 * h * h) < 1e-11, A
print("ok")
EOF
# --matrix: an orthographic box x, y in [-2, 2] (glOrtho(-2,2,-2,2,-10,10))
run --matrix 0.5,0,0,0,0,0.5,0,0,0,0,-0.1,0,0,0,0,1 "$T/grid.obj" -o "$T/out.obj"
expect_rc 0 "--matrix"
pycheck "matrix: a 4 x 4 square" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from meas import *
V, VT, F = read(sys.argv[1]); A, Vol = area_volume(V, F)
assert abs(A - 16) < 1e-12, A
print("ok")
EOF

# usage errors (exit 2) and read errors (exit 1); nothing written
for args in "" "--plane 0,0,0,1" "--plane 1,2,3" "--frustum eye=0,0,5" \
    "--frustum eye=0,0,5,center=0,0,5,fovy=60,near=1,far=2" \
    "--frustum eye=0,0,5,center=0,0,0,fovy=200,near=1,far=2" \
    "--frustum eye=0,0,5,center=0,0,0,fovy=60,near=3,far=2" \
    "--frustum eye=0,0,5,center=0,0,0,fov=60,near=1,far=2" "--matrix 1,2,3"; do
    # shellcheck disable=SC2086
    run $args "$T/cube.obj" -o "$T/never.obj"
    expect_rc 2 "usage error '$args'"
done
checks=$((checks + 1))
[ ! -e "$T/never.obj" ] || fail "a usage error left an output file"
run --plane 0,0,1,0 "$T/cube.obj"
expect_rc 2 "stdout without --format"
run --plane 0,0,1,0 --format obj "$T/cube.obj"
expect_rc 0 "stdout with --format"
printf 'v 0 0 0\nf 1 2 3\n' >"$T/bad.obj"
run --plane 0,0,1,0 "$T/bad.obj" -o "$T/never.obj"
expect_rc 1 "bad input"
checks=$((checks + 1))
[ ! -e "$T/never.obj" ] || fail "a read error left an output file"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
