#!/bin/bash
# Tests of geom-tangents: the glTF TANGENT of planar meshes with affine UV
# maps against dP/du and the bitangent sign computed here by Python from the
# GLB's own POSITION, NORMAL and TEXCOORD_0 (so the check holds whatever the
# writer's v convention): tangent = normalize(dP/du), w = sign of
# (normal x tangent) . dP/dv; a UV-mirrored half flips w; --json; errors.
# Usage: test_geom_tangents.sh /path/to/geom-tangents   (env PYTHON3: python)
set -u
if [ $# -ne 1 ]; then
    echo "usage: $0 TOOL" >&2
    exit 2
fi
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-tangents-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

. "$(dirname "$0")/testlib.sh"

# A tilted 3x2 grid of quads with uv = A (s, t) + b over plane coordinates;
# MIRROR=1 mirrors u on the right half (x > 1.5), giving a mirrored seam.
make_grid() { # OUT MIRROR
    "$PY" - "$1" "$2" <<'EOF'
import sys, math
out, mirror = sys.argv[1], int(sys.argv[2])
e1 = (1 / math.sqrt(2), 0.0, 1 / math.sqrt(2)); e2 = (0.0, 1.0, 0.0)
A = (0.8, 0.3, -0.1, 1.2)
lines = []
for j in range(3):
    for i in range(4):
        s, t = i * 0.5, j * 0.5
        lines.append("v %.17g %.17g %.17g" % tuple(1 + s * a + t * b for a, b in zip(e1, e2)))
vt = []
faces = []
for j in range(2):
    for i in range(3):
        c = [j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i]
        f = []
        for v in c:
            s, t = (v % 4) * 0.5, (v // 4) * 0.5
            u = A[0] * s + A[1] * t
            if mirror and i == 2:
                u = 2 * (A[0] * 1.0 + A[1] * t) - u   # mirror about the column s = 1
            vv = A[2] * s + A[3] * t
            vt.append("vt %.17g %.17g" % (u, vv))
            f.append("%d/%d" % (v + 1, len(vt)))
        faces.append("f " + " ".join(f))
open(out, "w").write("\n".join(lines + vt + faces) + "\n")
EOF
}

cat >"$T/glb.py" <<'EOF'
import json, struct, math
def read_glb(path):
    b = open(path, 'rb').read()
    magic, ver, length = struct.unpack_from('<4sII', b, 0)
    assert magic == b'glTF' and ver == 2 and length == len(b)
    jl, jt = struct.unpack_from('<I4s', b, 12)
    assert jt == b'JSON'
    js = json.loads(b[20:20 + jl])
    bl, bt = struct.unpack_from('<I4s', b, 20 + jl)
    assert bt == b'BIN\0'
    bin_ = b[28 + jl:28 + jl + bl]
    def acc(i):
        a = js['accessors'][i]; bv = js['bufferViews'][a['bufferView']]
        off = bv.get('byteOffset', 0) + a.get('byteOffset', 0)
        n = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4}[a['type']]
        fmt = {5126: 'f', 5125: 'I', 5123: 'H', 5121: 'B'}[a['componentType']]
        size = struct.calcsize(fmt)
        stride = bv.get('byteStride', n * size)
        return [struct.unpack_from('<%d%s' % (n, fmt), bin_, off + k * stride) for k in range(a['count'])]
    prim = js['meshes'][0]['primitives'][0]
    at = prim['attributes']
    return {k: acc(v) for k, v in at.items()}, [x[0] for x in acc(prim['indices'])]
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def cross(a, b): return (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def unit(a):
    l = math.sqrt(dot(a, a)); return tuple(x / l for x in a)
def check(path, expect_mirrored):
    at, idx = read_glb(path)
    P, N, UV, TG = at['POSITION'], at['NORMAL'], at['TEXCOORD_0'], at['TANGENT']
    mirrored = 0
    for k in range(0, len(idx), 3):
        a, b, c = idx[k:k + 3]
        d1, d2 = sub(P[b], P[a]), sub(P[c], P[a])
        u1, v1 = UV[b][0] - UV[a][0], UV[b][1] - UV[a][1]
        u2, v2 = UV[c][0] - UV[a][0], UV[c][1] - UV[a][1]
        det = u1 * v2 - u2 * v1
        dpdu = tuple((v2 * x - v1 * y) / det for x, y in zip(d1, d2))
        dpdv = tuple((-u2 * x + u1 * y) / det for x, y in zip(d1, d2))
        t = unit(dpdu)
        for v in (a, b, c):
            tg = TG[v]
            assert all(abs(x - y) < 2e-6 for x, y in zip(tg[:3], t)), (tg, t)
            assert abs(dot(tg[:3], N[v])) < 2e-6
            w = 1.0 if dot(cross(N[v], t), dpdv) > 0 else -1.0
            assert tg[3] == w, (tg, w)
            mirrored += tg[3] != TG[idx[0]][3]
    assert (mirrored > 0) == expect_mirrored, mirrored
EOF

make_grid "$T/grid.obj" 0
run "$T/grid.obj" -o "$T/grid.glb"
expect_rc 0 "grid"
pycheck "grid: TANGENT = normalize(dP/du), w from dP/dv" <<EOF
import sys; sys.path.insert(0, "$T"); from glb import *
check("$T/grid.glb", False); print("ok")
EOF

make_grid "$T/mirror.obj" 1
run --json "$T/mirror.obj" -o "$T/mirror.glb"
expect_rc 0 "mirrored grid"
pycheck "mirrored seam: both signs, each matching its side" <<EOF
import sys; sys.path.insert(0, "$T"); from glb import *
check("$T/mirror.glb", True); print("ok")
EOF
pycheck "--json: 6 faces, 24 corners, 8 mirrored (the right column)" "$out" <<'EOF'
import sys, json
d = json.loads(sys.argv[1])
assert d["faces"] == 6 and d["corners"] == 24 and d["mirrored"] == 8, d
print("ok")
EOF

# --crease recomputes normals; the result is still a valid frame
run --crease 45 "$T/grid.obj" -o "$T/grid2.glb"
expect_rc 0 "--crease 45"
pycheck "--crease: same frames on a flat grid" <<EOF
import sys; sys.path.insert(0, "$T"); from glb import *
check("$T/grid2.glb", False); print("ok")
EOF

# degenerate (zero-area) faces: a warning with the count and the first face
# (0-based), in --json too
cat >"$T/deg.obj" <<'EOF'
v 0 0 0
v 1 0 0
v 1 1 0
v 2 0 0
v 3 0 0
v 4 0 0
vt 0 0
vt 1 0
vt 1 1
f 1/1 2/2 3/3
f 4/1 5/2 6/3
EOF
run --json "$T/deg.obj" -o "$T/deg.glb"
expect_rc 0 "degenerate face"
expect_degenerate "degenerate face" "1 degenerate (zero-area) face, the first face 1"
expect_degenerate_json "degenerate face --json" 1 1
run --json "$T/grid.obj" -o "$T/nodeg.glb"
expect_degenerate_json "no degenerate face --json" 0 null

# errors
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$T/nouv.obj"
run "$T/nouv.obj" -o "$T/x.glb"
expect_rc 1 "no texture coordinates"
checks=$((checks + 1))
[ ! -e "$T/x.glb" ] || fail "no-uv error left an output file"
run --crease 200 "$T/grid.obj" -o "$T/x.glb"
expect_rc 2 "bad crease"
run "$T/grid.obj"
expect_rc 2 "stdout without --format"
run "$T/grid.obj" -o "$T/x.unknown"
expect_rc 2 "unknown output extension"
run "$T/none.obj" -o "$T/x.glb"
expect_rc 1 "missing input"

# An invalid face: the library's hint (geom_diag.hint) becomes a tool hint;
# geom-tangents has no --skip-invalid, so it names geom-convert's.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1/1 2/1 2/1\n' >"$T/dup.obj"
run "$T/dup.obj" -o "$T/dup.glb"
expect_rc 1 "a face with a repeated vertex"
checks=$((checks + 1))
[ "$err" = "geom-tangents: $T/dup.obj:6: face 2: vertex 2 appears twice (again at corner 3): expected distinct vertices (geom-convert --skip-invalid can drop such faces first)" ] ||
    fail "invalid-face hint: $err"

testlib_summary
