#!/bin/bash
# Tests of geom-convert: round trips between every pair of formats checked
# with geom-info and with Python parsing the files (positions compared
# exactly: Python's repr gives the shortest decimal that reads back, and
# struct unpacks binary PLY/STL), GLB structure (header, chunks, JSON with
# Python's json module), STL and PLY encodings, standard input and output,
# --precision and --no-* options, and errors: exit 1 with no output file
# created and an existing one untouched; usage errors exit 2.
# Usage: test_geom_convert.sh /path/to/geom-convert /path/to/geom-info DATA_DIR
#        (env PYTHON3: python)
set -u
if [ $# -ne 3 ]; then
    echo "usage: $0 CONVERT INFO DATA_DIR" >&2
    exit 2
fi
TOOL=$1
INFO=$2
DATA=$3
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-convert-test.XXXXXX") || exit 1
trap 'chmod -R u+w "$T"; rm -rf "$T"' EXIT

failures=0
checks=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
run() {
    "$TOOL" "$@" >"$T/stdout" 2>"$T/stderr"
    rc=$?
    err=$(cat "$T/stderr")
}
expect_rc() {
    checks=$((checks + 1))
    [ "$rc" -eq "$1" ] || fail "$2: exit status $rc, expected $1 (stderr: $err)"
}
check_py() { # check_py WHAT SCRIPT ARGS...
    local what=$1 script=$2
    shift 2
    checks=$((checks + 1))
    "$PY" -c "$script" "$@" || fail "$what"
}
# info_key FILE KEY: one value of geom-info --json
info_key() {
    "$INFO" --json "$1" | "$PY" -c 'import sys, json; print(json.dumps(json.load(sys.stdin)[sys.argv[1]]))' "$2"
}

# A reader for every format, used to compare positions exactly.
cat >"$T/read.py" <<'EOF'
import struct, sys
def read(path):
    data = open(path, 'rb').read()
    if path.endswith('.obj'):
        return [tuple(float(x) for x in l.split()[1:4]) for l in data.decode().splitlines()
                if l.startswith('v ')]
    if path.endswith('.off'):
        lines = [l.split('#')[0].split() for l in data.decode().splitlines()]
        lines = [l for l in lines if l]
        nv = int(lines[1][0])
        return [tuple(float(x) for x in l[:3]) for l in lines[2:2 + nv]]
    if path.endswith('.ply'):
        head, body = data.split(b'end_header\n', 1)
        h = head.decode().splitlines()
        nv = int([l for l in h if l.startswith('element vertex')][0].split()[2])
        props = []
        for l in h[h.index([l for l in h if l.startswith('element vertex')][0]) + 1:]:
            if not l.startswith('property'): break
            props.append(l.split()[1])
        fmt = [l for l in h if l.startswith('format')][0].split()[1]
        if fmt == 'ascii':
            rows = body.decode().splitlines()[:nv]
            return [tuple(float(x) for x in r.split()[:3]) for r in rows]
        e = '<' if fmt == 'binary_little_endian' else '>'
        code = {'double': 'd', 'float': 'f', 'uchar': 'B'}
        f = e + ''.join(code[p] for p in props)
        n = struct.calcsize(f)
        return [struct.unpack(f, body[i * n:(i + 1) * n])[:3] for i in range(nv)]
    if path.endswith('.stl'):
        n = struct.unpack('<I', data[80:84])[0]
        out = []
        for t in range(n):
            v = struct.unpack('<12f', data[84 + 50 * t:84 + 50 * t + 48])
            for k in range(3):
                out.append(tuple(v[3 + 3 * k:6 + 3 * k]))
        return out
def key(p):
    return sorted(set(p))
if __name__ == '__main__':
    a, b = read(sys.argv[1]), read(sys.argv[2])
    if key(a) != key(b):
        print('positions differ:', key(a)[:5], key(b)[:5]); sys.exit(1)
EOF

# ------------------------------------------------ every pair of formats
for src in "$DATA/cube_seams.obj" "$DATA/tetra.off" "$DATA/pyramid.ply" "$DATA/wedge.stl"; do
    base=$(basename "$src")
    ref_euler=$(info_key "$src" euler)
    ref_faces=$(info_key "$src" faces)
    for fmt in obj off ply stl; do
        out="$T/${base%.*}.$fmt"
        flags=()
        # per-vertex formats split vertices at the cube's uv and normal
        # seams (checked below); without them the topology is kept
        if [ "$base" = cube_seams.obj ] && { [ $fmt = off ] || [ $fmt = ply ]; }; then
            flags=(--no-normals --no-uvs)
        fi
        run "${flags[@]}" "$src" "$out"
        expect_rc 0 "$base -> $fmt"
        checks=$((checks + 1))
        [ "$(info_key "$out" euler)" = "$ref_euler" ] || fail "$base -> $fmt: euler changed"
        if [ "$fmt" != stl ]; then
            checks=$((checks + 1))
            [ "$(info_key "$out" faces)" = "$ref_faces" ] || fail "$base -> $fmt: faces changed"
        fi
        checks=$((checks + 1))
        "$PY" "$T/read.py" "$src" "$out" || fail "$base -> $fmt: positions"
    done
done

# with its attributes, the cube is one vertex per distinct corner: 24
# vertices, six separate quads
for fmt in off ply; do
    run "$DATA/cube_seams.obj" "$T/split.$fmt"
    checks=$((checks + 1))
    [ "$(info_key "$T/split.$fmt" vertices) $(info_key "$T/split.$fmt" components)" = "24 6" ] ||
        fail "cube -> $fmt with normals and uvs: not split at the seams"
done

# the cube's corners survive obj -> obj byte for byte in the face lines
run "$DATA/cube_seams.obj" "$T/cube2.obj"
checks=$((checks + 1))
diff <(grep '^f ' "$DATA/cube_seams.obj") <(grep '^f ' "$T/cube2.obj") >/dev/null ||
    fail "cube face lines changed"
checks=$((checks + 1))
diff <(grep '^v[tn]* ' "$DATA/cube_seams.obj") <(grep '^v[tn]* ' "$T/cube2.obj") >/dev/null ||
    fail "cube v/vt/vn lines changed"

# ------------------------------------------------ exact doubles through PLY
"$PY" - "$T/rand.obj" <<'EOF'
import random, struct, sys, math
random.seed(7)
vals = []
while len(vals) < 300:
    x = struct.unpack('<d', struct.pack('<Q', random.getrandbits(64)))[0]
    if math.isfinite(x): vals.append(x)
vals[:6] = [0.1, 1 / 3, -0.0, 5e-324, 1.7976931348623157e308, 2.5e-308]
with open(sys.argv[1], 'w') as f:
    for i in range(0, 300, 3):
        f.write('v %r %r %r\n' % tuple(vals[i:i + 3]))
    for i in range(98):
        f.write('f %d %d %d\n' % ((i + 1, i + 2, i + 3) if i % 2 == 0 else (i + 1, i + 3, i + 2)))
EOF
run "$T/rand.obj" "$T/rand.ply"
expect_rc 0 "random -> ply"
run "$T/rand.ply" "$T/rand2.obj"
expect_rc 0 "ply -> obj"
run --ascii "$T/rand2.obj" "$T/rand3.ply"
expect_rc 0 "obj -> ascii ply"
run "$T/rand3.ply" "$T/rand4.off"
expect_rc 0 "ascii ply -> off"
check_py "doubles exact through obj -> ply -> obj -> ply(ascii) -> off" '
import sys
sys.path.insert(0, sys.argv[1])
from read import read
import struct
a, b = read(sys.argv[2]), read(sys.argv[3])
bits = lambda p: [struct.pack("<3d", *v) for v in p]
assert bits(a) == bits(b), (a[:3], b[:3])
' "$T" "$T/rand.obj" "$T/rand4.off"

# ------------------------------------------------------------------- GLB
run "$DATA/cube_seams.obj" "$T/cube.glb"
expect_rc 0 "obj -> glb"
check_py "GLB structure" '
import sys, struct, json
d = open(sys.argv[1], "rb").read()
magic, ver, total = struct.unpack("<III", d[:12])
assert magic == 0x46546C67 and ver == 2 and total == len(d), (magic, ver, total)
jl, jt = struct.unpack("<II", d[12:20])
assert jt == 0x4E4F534A and jl % 4 == 0
j = json.loads(d[20:20 + jl].decode())
assert j["asset"]["version"] == "2.0"
bl, bt = struct.unpack("<II", d[20 + jl:28 + jl])
assert bt == 0x004E4942 and bl % 4 == 0 and 28 + jl + bl == len(d)
prim = j["meshes"][0]["primitives"][0]
pos = j["accessors"][prim["attributes"]["POSITION"]]
assert pos["count"] == 24 and pos["min"] == [0, 0, 0] and pos["max"] == [1, 1, 1]
assert j["accessors"][prim["indices"]]["count"] == 36
for v in j["bufferViews"]:
    assert v["byteOffset"] % 4 == 0 and v["byteOffset"] + v["byteLength"] <= bl
' "$T/cube.glb"
run --no-normals --no-uvs "$DATA/cube_seams.obj" "$T/bare.glb"
check_py "GLB without normals and uvs" '
import sys, struct, json
d = open(sys.argv[1], "rb").read()
jl = struct.unpack("<I", d[12:16])[0]
j = json.loads(d[20:20 + jl].decode())
a = j["meshes"][0]["primitives"][0]["attributes"]
assert sorted(a) == ["POSITION"] and j["accessors"][a["POSITION"]]["count"] == 8
' "$T/bare.glb"

# ------------------------------------------------------- encodings, options
run --ascii "$DATA/wedge.stl" "$T/w.stl"
checks=$((checks + 1))
[ "$(head -c 6 "$T/w.stl")" = "solid " ] || fail "--ascii STL"
run "$DATA/cube_seams.obj" "$T/c.stl"
checks=$((checks + 1))
[ "$(stat -c %s "$T/c.stl")" -eq $((84 + 50 * 12)) ] || fail "binary STL size"
run --big-endian "$DATA/pyramid.ply" "$T/be.ply"
checks=$((checks + 1))
grep -aq "^format binary_big_endian 1.0$" "$T/be.ply" || fail "--big-endian"
run --float "$DATA/pyramid.ply" "$T/f.ply"
checks=$((checks + 1))
grep -aq "^property float x$" "$T/f.ply" || fail "--float"
checks=$((checks + 1))
"$PY" "$T/read.py" "$DATA/pyramid.ply" "$T/be.ply" || fail "big-endian positions"
printf 'v 0.123456789 1 2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$T/p.obj"
run --precision 3 "$T/p.obj" "$T/p3.obj"
checks=$((checks + 1))
grep -qx "v 0.123 1 2" "$T/p3.obj" || fail "--precision 3"
run --no-normals --no-meta "$DATA/cube_seams.obj" "$T/nn.obj"
checks=$((checks + 1))
! grep -q '^vn \|^usemtl\|^mtllib' "$T/nn.obj" || fail "--no-normals --no-meta"
checks=$((checks + 1))
grep -q '^f 1/1 2/2 6/4 5/3$' "$T/nn.obj" || fail "--no-normals keeps v/vt"

# mtllib: kept only when the material library is next to the output (the
# tools never write a .mtl); a dangling reference is dropped with a warning
mkdir -p "$T/mtl_a" "$T/mtl_b"
cp "$DATA/cube_seams.obj" "$T/mtl_a/in.obj"
printf 'newmtl red\nKd 1 0 0\n' >"$T/mtl_a/cube.mtl"
run "$T/mtl_a/in.obj" "$T/mtl_a/out.obj"
expect_rc 0 "mtllib next to the output"
checks=$((checks + 1))
grep -qx 'mtllib cube.mtl' "$T/mtl_a/out.obj" || fail "mtllib dropped although cube.mtl is there"
run "$T/mtl_a/in.obj" "$T/mtl_b/out.obj"
expect_rc 0 "mtllib elsewhere"
checks=$((checks + 1))
grep -q '^mtllib' "$T/mtl_b/out.obj" && fail "dangling mtllib written"
checks=$((checks + 1))
case "$err" in *"mtllib cube.mtl not written"*) ;; *) fail "no warning for a dropped mtllib: $err" ;; esac
checks=$((checks + 1))
grep -q '^usemtl' "$T/mtl_b/out.obj" || fail "usemtl groups lost with the mtllib"

# ----------------------------------------------------- standard streams
"$TOOL" -i obj -f off - - <"$DATA/cube_seams.obj" >"$T/stdout" 2>"$T/stderr"
rc=$?
err=$(cat "$T/stderr")
expect_rc 0 "stdin -> stdout"
checks=$((checks + 1))
[ "$(head -n 1 "$T/stdout")" = "STNOFF" ] || fail "OFF on stdout"
"$TOOL" -f glb "$DATA/tetra.off" >"$T/stdout.glb" 2>"$T/stderr"
rc=$?
expect_rc 0 "default output is stdout"
checks=$((checks + 1))
[ "$(head -c 4 "$T/stdout.glb")" = "glTF" ] || fail "GLB on stdout"
"$TOOL" - "$T/sniffed.obj" <"$DATA/wedge.stl" >/dev/null 2>"$T/stderr"
rc=$?
expect_rc 0 "sniffed binary STL on stdin"
checks=$((checks + 1))
[ "$(grep -c '^f ' "$T/sniffed.obj")" -eq 8 ] || fail "sniffed STL content"

# ------------------------------------------------------------------ errors
echo "precious" >"$T/keep.obj"
printf 'v 0 0 0\nv 1 0 0\nf 1 2 3\n' >"$T/bad.obj"
run "$T/bad.obj" "$T/keep.obj"
expect_rc 1 "bad input"
checks=$((checks + 1))
case $err in *"bad.obj:3:7:"*) ;; *) fail "bad input message: $err" ;; esac
checks=$((checks + 1))
[ "$(cat "$T/keep.obj")" = "precious" ] || fail "existing output clobbered"
run "$T/bad.obj" "$T/new.obj"
checks=$((checks + 1))
[ ! -e "$T/new.obj" ] || fail "output created on error"
run "$DATA/tetra.off" "$T/no/such/dir/x.obj"
expect_rc 1 "missing output directory"
if [ "$(id -u)" -ne 0 ]; then
    mkdir "$T/ro" && chmod 555 "$T/ro"
    run "$DATA/tetra.off" "$T/ro/x.obj"
    expect_rc 1 "read-only directory"
    checks=$((checks + 1))
    [ -z "$(ls -A "$T/ro")" ] || fail "files left in the read-only directory"
fi
checks=$((checks + 1))
[ -z "$(ls -A "$T" | grep '\.tmp$')" ] || fail "temporary files left behind"
run "$DATA/tetra.off" -
expect_rc 2 "stdout without --format"
run "$DATA/tetra.off" "$T/x.xyz"
expect_rc 2 "unknown output extension"
run "$DATA/tetra.off"
expect_rc 2 "no OUT, no --format"
run -f obj "$DATA/tetra.off" "$T/a.obj" "$T/b.obj"
expect_rc 2 "extra operand"
run -o "$T/a.obj" "$DATA/tetra.off" "$T/b.obj"
expect_rc 2 "OUT and -o"
run --precision 40 "$DATA/tetra.off" "$T/a.obj"
expect_rc 2 "bad precision"
run --big-endian "$DATA/tetra.off" "$T/a.obj"
expect_rc 2 "--big-endian for OBJ"
run "$T/cube.glb" "$T/a.obj"
expect_rc 0 "GLB input (read back: the cube's 12 triangles)"
checks=$((checks + 1))
[ "$(grep -c '^f ' "$T/a.obj")" -eq 12 ] || fail "GLB input: $(grep -c '^f ' "$T/a.obj") faces, expected 12"
run -o "$T/o.off" "$DATA/tetra.off"
expect_rc 0 "-o FILE"
checks=$((checks + 1))
[ "$(head -n 1 "$T/o.off")" = "OFF" ] || fail "-o FILE content"

# An invalid face: the library's hint (geom_diag.hint) names the tool's option.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n' >"$T/two.obj"
run "$T/two.obj" "$T/two.off"
expect_rc 1 "a face of two vertices"
checks=$((checks + 1))
[ "$err" = "geom-convert: $T/two.obj:5: face 2: expected at least 3 vertices, found 2 (--skip-invalid skips such faces)" ] ||
    fail "invalid-face hint: $err"
run --skip-invalid "$T/two.obj" "$T/two.off"
expect_rc 0 "--skip-invalid"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
