#!/bin/bash
# Tests of geom-features: OBJ polylines ("l") against closed forms checked
# here by Python: a cube's 12 crease edges at 30 degrees (axis-aligned unit
# segments), none at 100 degrees; an open cylinder's two closed boundary
# circles; a UV sphere's silhouette from an eye point near the tangent
# circle (p - c).a = R^2/D; --kinds, --with-mesh, --json and errors.
# Usage: test_geom_features.sh /path/to/geom-features   (env PYTHON3: python)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOL" >&2
    exit 2
fi
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-features-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

. "$(dirname "$0")/testlib.sh"

cat >"$T/lines.py" <<'EOF'
import math
def read_lines(path):
    V, L, F = [], [], 0
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': V.append(tuple(map(float, t[1:4])))
        elif t[0] == 'l': L.append([int(x.split('/')[0]) - 1 for x in t[1:]])
        elif t[0] == 'f': F += 1
    return V, L, F
EOF

# triangulated unit cube
cat >"$T/cube.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
v 0 0 1
v 1 0 1
v 0 1 1
v 1 1 1
f 1 3 4
f 1 4 2
f 5 6 8
f 5 8 7
f 1 2 6
f 1 6 5
f 3 7 8
f 3 8 4
f 1 5 7
f 1 7 3
f 2 4 8
f 2 8 6
EOF

run --crease 30 "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "cube --crease 30"
pycheck "cube: 12 unit axis-aligned crease segments, all distinct" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from lines import *
V, L, F = read_lines(sys.argv[1])
assert F == 0 and len(L) == 12, (F, len(L))
seen = set()
for l in L:
    assert len(l) == 2
    a, b = V[l[0]], V[l[1]]
    d = sorted(abs(x - y) for x, y in zip(a, b))
    assert d == [0.0, 0.0, 1.0], (a, b)
    seen.add(frozenset((a, b)))
assert len(seen) == 12
print("ok")
EOF

run --crease 100 --json "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "cube --crease 100"
pycheck "cube at 100 degrees: nothing" "$out" "$T/out.obj" <<EOF
import sys, json; sys.path.insert(0, "$T"); from lines import *
d = json.loads(sys.argv[1])
assert d["crease"] == 0 and d["boundary"] == 0 and d["polylines"] == 0, d
V, L, F = read_lines(sys.argv[2]); assert not L and not V
print("ok")
EOF

run --with-mesh "$T/cube.obj" -o "$T/out.obj"
expect_rc 0 "--with-mesh"
pycheck "--with-mesh: faces and lines" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from lines import *
V, L, F = read_lines(sys.argv[1]); assert F == 12 and len(L) == 12 and len(V) == 8
print("ok")
EOF

# open cylinder (32 segments, 3 rings) and UV sphere
"$PY" - "$T" <<'EOF'
import sys, math
T = sys.argv[1]
n, r = 32, 3
with open(T + "/cyl.obj", "w") as f:
    for k in range(r + 1):
        for s in range(n):
            a = 2 * math.pi * s / n
            f.write("v %.17g %.17g %d\n" % (math.cos(a), math.sin(a), k))
    for k in range(r):
        for s in range(n):
            a, b = k * n + s + 1, k * n + (s + 1) % n + 1
            f.write("f %d %d %d %d\n" % (a, b, b + n, a + n))
nlat, nlon, R, c = 40, 80, 2.0, (1.0, -1.0, 0.5)
with open(T + "/sphere.obj", "w") as f:
    for i in range(nlat):
        for j in range(nlon):
            th, ph = math.pi * (i + 1) / (nlat + 1), 2 * math.pi * j / nlon
            f.write("v %.17g %.17g %.17g\n" % (c[0] + R * math.sin(th) * math.cos(ph),
                    c[1] + R * math.sin(th) * math.sin(ph), c[2] + R * math.cos(th)))
    N, S = nlat * nlon + 1, nlat * nlon + 2
    f.write("v %.17g %.17g %.17g\nv %.17g %.17g %.17g\n" % (c[0], c[1], c[2] + R, c[0], c[1], c[2] - R))
    for j in range(nlon):
        j1 = (j + 1) % nlon
        f.write("f %d %d %d\n" % (N, j + 1, j1 + 1))
        base = (nlat - 1) * nlon
        f.write("f %d %d %d\n" % (S, base + j1 + 1, base + j + 1))
    for i in range(nlat - 1):
        for j in range(nlon):
            j1 = (j + 1) % nlon
            a, b = i * nlon + j + 1, i * nlon + j1 + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, a + nlon, b + nlon, a, b + nlon, b))
EOF

run --json "$T/cyl.obj" -o "$T/out.obj"
expect_rc 0 "cylinder"
pycheck "cylinder: two closed unit circles at z = 0 and z = 3" "$out" "$T/out.obj" <<EOF
import sys, json; sys.path.insert(0, "$T"); from lines import *
d = json.loads(sys.argv[1])
assert d["boundary"] == 64 and d["crease"] == 0 and d["polylines"] == 2, d
V, L, F = read_lines(sys.argv[2])
zs = set()
for l in L:
    assert len(l) == 33 and l[0] == l[-1], len(l)
    z = V[l[0]][2]; zs.add(z)
    for i in l:
        p = V[i]; assert p[2] == z and abs(math.hypot(p[0], p[1]) - 1) < 1e-15
    # consecutive vertices are neighbours on the ring
    for a, b in zip(l, l[1:]):
        assert abs(math.dist(V[a], V[b]) - 2 * math.sin(math.pi / 32)) < 1e-14
assert zs == {0.0, 3.0}
print("ok")
EOF

run --kinds silhouette --eye 7,2,3.5 --json "$T/sphere.obj" -o "$T/out.obj"
expect_rc 0 "sphere silhouette"
pycheck "sphere silhouette: near the tangent circle, all around" "$T/out.obj" <<EOF
import sys; sys.path.insert(0, "$T"); from lines import *
V, L, F = read_lines(sys.argv[1])
c, R, eye = (1.0, -1.0, 0.5), 2.0, (7.0, 2.0, 3.5)
a = [e - x for e, x in zip(eye, c)]; D = math.sqrt(sum(x * x for x in a)); a = [x / D for x in a]
h, rc = R * R / D, R * math.sqrt(1 - (R / D) ** 2)
tol = 2 * R * 2 * math.pi / 80
u = [-a[1], a[0], 0.0]; ul = math.hypot(u[0], u[1]); u = [x / ul for x in u]
w = [a[1]*u[2]-a[2]*u[1], a[2]*u[0]-a[0]*u[2], a[0]*u[1]-a[1]*u[0]]
sectors = set()
assert L
for l in L:
    for i in l:
        q = [p - x for p, x in zip(V[i], c)]
        along = sum(x * y for x, y in zip(q, a))
        x, y = sum(p * s for p, s in zip(q, u)), sum(p * s for p, s in zip(q, w))
        assert abs(along - h) < tol and abs(math.hypot(x, y) - rc) < tol, (along, h)
        sectors.add(int((math.atan2(y, x) + math.pi) / (2 * math.pi) * 12) % 12)
assert len(sectors) == 12, sectors
print("ok")
EOF

# errors and usage
run --kinds silhouette "$T/sphere.obj" -o "$T/x.obj"
expect_rc 2 "silhouette without --eye"
run --kinds edges "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "unknown kind"
run --eye 1,2 "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "--eye with two numbers"
run "$T/cube.obj" -o "$T/x.ply"
expect_rc 2 "non-OBJ output"
run --crease -3 "$T/cube.obj" -o "$T/x.obj"
expect_rc 2 "negative crease"
run "$T/nothing.obj" -o "$T/x.obj"
expect_rc 1 "missing input"
checks=$((checks + 1))
[ ! -e "$T/x.obj" ] && [ ! -e "$T/x.ply" ] || fail "an error left an output file"
run "$T/cube.obj"
expect_rc 0 "standard output"
checks=$((checks + 1))
[ "$(grep -c '^l ' "$T/stdout")" -eq 12 ] || fail "standard output: expected 12 l lines"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
