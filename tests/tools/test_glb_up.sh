#!/bin/bash
# The .glb round trip of a Z-up mesh: an OBJ (an asymmetric box of quads
# with per-corner normals and UVs with a seam, coordinates far from the
# origin) -> geom-convert --up z -> .glb -> geom-convert --up z -> OBJ
# gives back the Z-up mesh: positions equal to 1e-6 relative (glTF stores
# floats), normals to 1e-6, UVs to 1e-6 (glTF's v flip undone), the same
# faces and v/vt/vn structure. The .glb itself is Y-up: (x, y, z) stored
# as (x, z, -y). Without --up z the read gives that Y-up frame; with it
# every tool reading through tools/cli_mesh.c turns it back (geom-info's
# bbox, geom-normals' output). A .glb written with --up y and read with
# --up y is unchanged; --up on OBJ input changes nothing.
# Usage: test_glb_up.sh geom-convert geom-info geom-normals   (env PYTHON3)
set -u
TOOL=$1
INFO=$2
NORMALS=$3
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-glbup-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/testlib.sh"

# a box 2 x 3 x 5 at (100, -200, 7), six quads, outward corner normals,
# a UV chart per face (a seam everywhere)
"$PY" - "$T/box.obj" <<'PYEOF' || { echo "FAIL: cannot write the box" >&2; exit 1; }
import sys
o, s = (100.25, -200.5, 7.125), (2.0, 3.0, 5.0)
v = [(o[0] + s[0] * (i & 1), o[1] + s[1] * ((i >> 1) & 1), o[2] + s[2] * ((i >> 2) & 1)) for i in range(8)]
faces = [((0, 2, 3, 1), (0, 0, -1)), ((4, 5, 7, 6), (0, 0, 1)), ((0, 1, 5, 4), (0, -1, 0)),
         ((2, 6, 7, 3), (0, 1, 0)), ((0, 4, 6, 2), (-1, 0, 0)), ((1, 3, 7, 5), (1, 0, 0))]
with open(sys.argv[1], 'w') as f:
    for p in v:
        f.write('v %r %r %r\n' % p)
    for k in range(6):
        for uv in ((0.1, 0.2), (0.4, 0.2), (0.4, 0.7), (0.1, 0.7)):
            f.write('vt %r %r\n' % (uv[0] + 0.01 * k, uv[1]))
    for _, n in faces:
        f.write('vn %r %r %r\n' % n)
    for k, (q, _) in enumerate(faces):
        f.write('f ' + ' '.join('%d/%d/%d' % (q[c] + 1, 4 * k + c + 1, k + 1) for c in range(4)) + '\n')
PYEOF

run_ok() { # WHAT CMD...
    local what=$1
    shift
    checks=$((checks + 1))
    "$@" >"$T/stdout" 2>"$T/stderr" || fail "$what: exit $?: $(cat "$T/stderr")"
}
run_ok "OBJ -> GLB --up z" "$TOOL" "$T/box.obj" --up z -o "$T/box.glb"
run_ok "GLB -> OBJ --up z" "$TOOL" "$T/box.glb" --up z -o "$T/back.obj"
run_ok "GLB -> OBJ (no --up)" "$TOOL" "$T/box.glb" -o "$T/yup.obj"
run_ok "OBJ -> GLB --up y" "$TOOL" "$T/box.obj" -o "$T/box_y.glb"
run_ok "GLB --up y -> OBJ --up y" "$TOOL" "$T/box_y.glb" --up y -o "$T/back_y.obj"
run_ok "OBJ --up z -> OBJ" "$TOOL" "$T/box.obj" --up z -o "$T/objz.obj"
run_ok "geom-normals on the GLB --up z" "$NORMALS" "$T/box.glb" --up z -o "$T/normals.obj"
checks=$((checks + 1))
"$INFO" --json --up z "$T/box.glb" >"$T/info_z.json" 2>"$T/stderr" || fail "geom-info --up z: $(cat "$T/stderr")"
checks=$((checks + 1))
"$INFO" --json "$T/box.glb" >"$T/info_y.json" 2>"$T/stderr" || fail "geom-info: $(cat "$T/stderr")"

pycheck "round trips and frames" "$T" <<'PYEOF'
import sys, json, struct
T = sys.argv[1]
def obj(path):
    v, vt, vn, f = [], [], [], []
    for l in open(path):
        w = l.split()
        if not w:
            continue
        if w[0] == 'v':
            v.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == 'vt':
            vt.append(tuple(float(x) for x in w[1:3]))
        elif w[0] == 'vn':
            vn.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == 'f':
            f.append([tuple(int(x) - 1 if x else None for x in c.split('/')) for c in w[1:]])
    return v, vt, vn, f
def corners(m):
    """faces as sorted lists of (position, uv, normal) corners, rotated to
    start at the smallest, so vertex order and numbering do not matter"""
    v, vt, vn, f = m
    out = []
    for face in f:
        cs = [(v[c[0]], vt[c[1]] if len(c) > 1 and c[1] is not None else None,
               vn[c[2]] if len(c) > 2 and c[2] is not None else None) for c in face]
        out.append(cs)
    return out
def close(a, b, rel):
    if a is None or b is None:
        return a is b
    return all(abs(x - y) <= rel * max(1.0, abs(x), abs(y)) for x, y in zip(a, b))
def match(fa, fb, rel, xf=lambda p: p, xn=lambda n: n):
    """every face of fa has a face of fb with the same corners in the same
    cyclic order (a quad may come back as two triangles: compare the
    triangle fans' corner sets then)"""
    ca = [c for face in fa for c in face]
    cb = [c for face in fb for c in face]
    def same(c, d):
        return close(xf(c[0]), d[0], rel) and close(c[1], d[1], rel) and close(xn(c[2]) if c[2] else None, d[2], rel)
    for c in ca:
        assert any(same(c, d) for d in cb), ('corner not found', c)
    for d in cb:
        assert any(same(c, d) for c in ca), ('extra corner', d)
    # orientation: each face's normal by Newell agrees
    def newell(face):
        n = [0.0, 0.0, 0.0]
        for i in range(len(face)):
            p, q = face[i][0], face[(i + 1) % len(face)][0]
            n[0] += (p[1] - q[1]) * (p[2] + q[2]); n[1] += (p[2] - q[2]) * (p[0] + q[0]); n[2] += (p[0] - q[0]) * (p[1] + q[1])
        return n
    for face in fb:
        n = newell(face)
        stored = face[0][2]
        assert sum(a * b for a, b in zip(n, stored)) > 0, ('winding against the normal', face)
orig = corners(obj(T + '/box.obj'))
back = corners(obj(T + '/back.obj'))
match(orig, back, 1e-6)
assert len(obj(T + '/back.obj')[0]) == 8, 'vertices not welded back to 8'
# without --up z the OBJ is the Y-up frame: (x, z, -y)
yup = corners(obj(T + '/yup.obj'))
rot = lambda p: (p[0], p[2], -p[1])
match(orig, yup, 1e-6, rot, rot)
# --up y both ways: unchanged; --up z on OBJ to OBJ: unchanged
match(orig, corners(obj(T + '/back_y.obj')), 1e-6)
match(orig, corners(obj(T + '/objz.obj')), 0)
# the GLB's POSITION is Y-up
d = open(T + '/box.glb', 'rb').read()
jl = struct.unpack_from('<I', d, 12)[0]
j = json.loads(d[20:20 + jl].decode())
acc = j['accessors'][j['meshes'][0]['primitives'][0]['attributes']['POSITION']]
lo, hi = acc['min'], acc['max']
assert abs(lo[1] - 7.125) < 1e-4 and abs(hi[1] - 12.125) < 1e-4, (lo, hi)     # y = z
assert abs(lo[2] - 197.5) < 1e-4 and abs(hi[2] - 200.5) < 1e-4, (lo, hi)      # z = -y
# geom-info: bbox in the Z-up frame with --up z, Y-up without
bz = json.load(open(T + '/info_z.json'))['bbox']
by = json.load(open(T + '/info_y.json'))['bbox']
assert close(bz['min'], [100.25, -200.5, 7.125], 1e-6) and close(bz['max'], [102.25, -197.5, 12.125], 1e-6), bz
assert close(by['min'], [100.25, 7.125, 197.5], 1e-6) and close(by['max'], [102.25, 12.125, 200.5], 1e-6), by
# geom-normals --up z: Z-up positions, normals outward in that frame
v, vt, vn, f = obj(T + '/normals.obj')
assert all(close(p, q, 1e-6) for p, q in zip(sorted(v), sorted(obj(T + '/box.obj')[0]))), 'normals: positions'
for face in f:
    p = [v[c[0]] for c in face]
    n = vn[face[0][2]] if len(face[0]) > 2 and face[0][2] is not None else None
    assert n is not None
    cen = [sum(q[k] for q in p) / len(p) for k in range(3)]
    mid = (101.25, -199.0, 9.625)
    assert sum((cen[k] - mid[k]) * n[k] for k in range(3)) > 0, ('inward normal', face)
print('ok')
PYEOF

testlib_summary
