#!/bin/bash
# Tests of geom-tessellate: the teapot (.bpt) and data/surfaces.json (an exact
# NURBS sphere and torus and a B-spline patch) tessellated to OBJ, checked by
# Python against closed forms: the reported error within the tolerance, the
# triangle count of uniform grids (32 patches x 2 n^2 minus the 8 collapsed
# edges' n each), the topology (components and boundary edges by union-find
# over the faces), every vertex of the sphere at radius 1 and of the torus
# on its implicit equation, unit normals, only the attributes asked for,
# --json keys, usage errors (exit 2), read errors naming FILE:LINE or the
# JSON entry and key (exit 1), and the no-partial-output guarantee of -o.
# Usage: test_geom_tessellate.sh TOOL DATA_DIR HAVE_JSON   (env PYTHON3)
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
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-tessellate-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

. "$(dirname "$0")/testlib.sh"

cat >"$T/objcheck.py" <<'EOF'
import json, math, sys
def read_obj(path):
    V, VT, VN, F = [], [], [], []
    for line in open(path):
        t = line.split()
        if not t: continue
        if t[0] == 'v': V.append(tuple(map(float, t[1:4])))
        elif t[0] == 'vt': VT.append(tuple(map(float, t[1:3])))
        elif t[0] == 'vn': VN.append(tuple(map(float, t[1:4])))
        elif t[0] == 'f': F.append([c.split('/') for c in t[1:]])
    return V, VT, VN, F
def components_and_boundary(V, F):
    parent = list(range(len(V)))
    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]; a = parent[a]
        return a
    edges = {}
    for f in F:
        idx = [int(c[0]) - 1 for c in f]
        for k in range(len(idx)):
            a, b = idx[k], idx[(k + 1) % len(idx)]
            parent[find(a)] = find(b)
            key = (min(a, b), max(a, b))
            edges[key] = edges.get(key, 0) + 1
    used = set(int(c[0]) - 1 for f in F for c in f)
    comps = len(set(find(v) for v in used))
    boundary = sum(1 for n in edges.values() if n == 1)
    nonmanifold = sum(1 for n in edges.values() if n > 2)
    return comps, boundary, nonmanifold
EOF

# ---------------------------------------------------------------- basics
run --help
expect_rc 0 "--help"
run --version
expect_rc 0 "--version"
checks=$((checks + 1))
[[ "$out" == "geom-tessellate (libgeom) "* ]] || fail "--version prints '$out'"

# ---------------------------------------------------------------- teapot
run "$DATA/teapot.bpt" -o "$T/teapot.obj" --tol 3e-3 --normals --uvs --json
expect_rc 0 "teapot adaptive"
echo "$out" >"$T/teapot.json"
pycheck "teapot adaptive: report, normals, topology" "$T/teapot.json" "$T/teapot.obj" "$T/objcheck.py" <<'EOF'
import json, math, sys
exec(open(sys.argv[3]).read())
r = json.load(open(sys.argv[1]))
for k in ("max_error", "triangles", "seconds", "vertices", "mean_error"):
    assert k in r, "missing key %s" % k
assert 0 < r["max_error"] <= 3e-3, r["max_error"]
assert r["seconds"] >= 0
e = r["error"]  # the report every approximating tool prints
assert e["max"] == r["max_error"] and e["mean"] == r["mean_error"], e
assert e["method"] == "sampled" and e["tolerance"] == 3e-3 and e["pieces"] > 0, e
assert e["evaluations"] == r["evaluations"] and e["seconds"] >= 0, e
V, VT, VN, F = read_obj(sys.argv[2])
assert r["triangles"] == len(F), (r["triangles"], len(F))
assert r["vertices"] == len(V)
assert VN and VT
for f in F:
    assert len(f) == 3 and all(len(c) == 3 and c[1] and c[2] for c in f), f
for n in VN:
    assert abs(math.sqrt(sum(x * x for x in n)) - 1) < 1e-12, n
comps, boundary, nm = components_and_boundary(V, F)
# body, lid, handle, spout; the rims of the opening, lid, handle and spout ends
assert comps == 4, comps
assert nm == 0, nm
assert boundary > 0
print("ok")
EOF

# uniform grid: 32 patches x 2*4*4 triangles, minus 4 per collapsed edge (8 of them)
run "$DATA/teapot.bpt" -o "$T/grid.obj" --grid 4,4 --json
expect_rc 0 "teapot grid"
echo "$out" >"$T/grid.json"
pycheck "teapot grid: triangle count, no attributes" "$T/grid.json" "$T/grid.obj" "$T/objcheck.py" <<'EOF'
import json, sys
exec(open(sys.argv[3]).read())
r = json.load(open(sys.argv[1]))
assert r["triangles"] == 32 * 2 * 16 - 8 * 4, r["triangles"]
assert r["mode"] == "uniform"
assert r["error"]["tolerance"] is None and r["error"]["max"] == r["max_error"]
V, VT, VN, F = read_obj(sys.argv[2])
assert not VT and not VN, "attributes written that were not asked for"
assert len(F) == r["triangles"]
print("ok")
EOF

# text report
run "$DATA/teapot.bpt" -o "$T/t.obj" --tol 0.01
expect_rc 0 "teapot text report"
for key in "max_error:" "triangles:" "seconds:"; do
    checks=$((checks + 1))
    [[ "$out" == *"$key"* ]] || fail "text report lacks $key: $out"
done

# standard output: the mesh on stdout, the report on stderr
run "$DATA/teapot.bpt" -o - --grid 2,2
expect_rc 0 "stdout"
checks=$((checks + 1))
[ "$(grep -c '^f ' "$T/stdout")" -eq $((32 * 8 - 16)) ] || fail "stdout: wrong face count"
expect_err "triangles: 240" "stdout report on stderr"

# GLB with tangents
run "$DATA/teapot.bpt" -o "$T/t.glb" --grid 3,3 --normals --uvs --tangents
expect_rc 0 "glb"
checks=$((checks + 1))
[ "$(head -c 4 "$T/t.glb")" = "glTF" ] || fail "glb magic"
for ext in obj off stl; do
    run "$DATA/teapot.bpt" -o "$T/t2.$ext" --grid 3,3 --tangents
    expect_rc 2 "$ext tangents refused"
    expect_err "cannot hold tangents" "$ext tangents refused"
    checks=$((checks + 1))
    [ ! -e "$T/t2.$ext" ] || fail "$ext tangents: output written"
done
run "$DATA/teapot.bpt" -o "$T/t2.glb" --tangents=bogus
expect_rc 2 "--tangents=bogus"

cat >"$T/glb.py" <<'EOF'
import json, math, struct, sys
def read_glb(path):
    d = open(path, "rb").read()
    assert d[:4] == b"glTF", "magic"
    n = struct.unpack("<I", d[12:16])[0]
    j = json.loads(d[20:20 + n])
    binc = d[20 + n + 8:]
    prim = j["meshes"][0]["primitives"][0]
    out = {}
    for name, ai in prim["attributes"].items():
        a = j["accessors"][ai]
        v = j["bufferViews"][a["bufferView"]]
        k = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = v.get("byteStride", 4 * k)
        out[name] = [struct.unpack_from("<%df" % k, binc, off + i * stride)
                     for i in range(a["count"])]
    return out
EOF
# normals welded across patch seams: one GLB vertex per distinct position
# (7,176 before: the patches' normals differ in their last bits); with
# --normal-weld 0 the seams split again
run "$DATA/teapot.bpt" -o "$T/w.glb" --normals
expect_rc 0 "welded normals"
nverts=$(printf '%s\n' "$out" | sed -n 's/^vertices: //p')
run "$DATA/teapot.bpt" -o "$T/w0.glb" --normals --normal-weld 0
expect_rc 0 "--normal-weld 0"
pycheck "welded normals" "$T/glb.py" "$T/w.glb" "$T/w0.glb" "$nverts" <<'EOF'
import sys
exec(open(sys.argv[1]).read())
w, w0 = read_glb(sys.argv[2]), read_glb(sys.argv[3])
P, N = w["POSITION"], w["NORMAL"]
distinct = int(sys.argv[4])   # the mesh's vertices (distinct positions)
if len(P) != distinct:
    print("welded: %d GLB vertices for %d mesh vertices" % (len(P), distinct)); sys.exit()
if len(w0["POSITION"]) <= distinct:
    print("--normal-weld 0 did not split the seams (%d)" % len(w0["POSITION"])); sys.exit()
# every welded normal is within 0.01 degree (plus float rounding) of one of
# the unwelded normals at its position
byp = {}
for p, n in zip(w0["POSITION"], w0["NORMAL"]):
    byp.setdefault(p, []).append(n)
def angle(n, m):   # degrees, atan2 (acos loses small angles of float normals)
    c = (n[1] * m[2] - n[2] * m[1], n[2] * m[0] - n[0] * m[2], n[0] * m[1] - n[1] * m[0])
    return math.degrees(math.atan2(math.sqrt(sum(x * x for x in c)),
                                   sum(a * b for a, b in zip(n, m))))
worst = 0.0
for p, n in zip(P, N):
    best = min(angle(n, m) for m in byp[p])
    worst = max(worst, best)
print("ok" if worst < 0.01 + 1e-3 else "welded normal %.3g degrees off" % worst)
EOF

# MikkTSpace tangents: unit, orthogonal to the normal, w = +-1; PLY holds
# them as tangent_x..tangent_w; dP/du only when asked by name
run "$DATA/teapot.bpt" -o "$T/m.glb" --tangents
expect_rc 0 "mikk tangents glb"
run "$DATA/teapot.bpt" -o "$T/d.glb" --tangents=dpdu
expect_rc 0 "dpdu tangents glb"
pycheck "tangents" "$T/glb.py" "$T/m.glb" "$T/d.glb" <<'EOF'
import math, sys
exec(open(sys.argv[1]).read())
m, d = read_glb(sys.argv[2]), read_glb(sys.argv[3])
for key in ("NORMAL", "TEXCOORD_0", "TANGENT"):
    if key not in m:
        print("mikk: no %s" % key); sys.exit()
for n, t in zip(m["NORMAL"], m["TANGENT"]):
    l = math.sqrt(sum(x * x for x in t[:3]))
    dot = sum(a * b for a, b in zip(n, t[:3]))
    if abs(l - 1) > 1e-5 or abs(dot) > 1e-4 or abs(t[3]) != 1:
        print("mikk tangent %r normal %r" % (t, n)); sys.exit()
if "TANGENT" not in d or "NORMAL" in d:
    print("dpdu: attributes %s" % sorted(d)); sys.exit()
print("ok")
EOF
run "$DATA/teapot.bpt" -o "$T/m.ply" --grid 2,2 --tangents
expect_rc 0 "mikk tangents ply"
checks=$((checks + 1))
grep -a -q "property double tangent_w" "$T/m.ply" || fail "ply: no tangent properties"

# progress: on a terminal (script(1) gives one) percent and ETA on stderr
# (GEOM_PROGRESS_AFTER=0: from the start, whatever the machine's speed);
# never with --quiet or when stderr is not a terminal
run "$DATA/teapot.bpt" --tol 2e-4 -o "$T/p.obj"
expect_rc 0 "no tty: no progress"
checks=$((checks + 1))
case "$err" in *"%"*) fail "progress written to a non-terminal stderr" ;; esac
if command -v script >/dev/null 2>&1; then
    GEOM_PROGRESS_AFTER=0 script -qec "'$TOOL' '$DATA/teapot.bpt' --tol 2e-4 -o '$T/p.obj' >/dev/null" \
        /dev/null >"$T/tty.txt" 2>&1
    checks=$((checks + 1))
    grep -a -q "tessellating.*%.*ETA" "$T/tty.txt" || fail "tty: no progress line"
    GEOM_PROGRESS_AFTER=0 script -qec "'$TOOL' '$DATA/teapot.bpt' --tol 2e-4 --quiet -o '$T/p.obj' >/dev/null" \
        /dev/null >"$T/tty.txt" 2>&1
    checks=$((checks + 1))
    grep -a -q "%" "$T/tty.txt" && fail "tty --quiet: progress shown"
fi

# ------------------------------------------------------------ usage errors
run "$DATA/teapot.bpt" -o "$T/x.obj" --tol 1e-3 --grid 2,2
expect_rc 2 "--tol with --grid"
run "$DATA/teapot.bpt"
expect_rc 2 "missing -o"
run "$DATA/teapot.bpt" -o "$T/x.obj" --grid 2
expect_rc 2 "bad --grid"
run "$DATA/teapot.bpt" -o "$T/x.obj" --tol -1
expect_rc 2 "negative --tol"
run "$DATA/teapot.bpt" -o "$T/x.unknown"
expect_rc 2 "unknown output format"
run -o "$T/x.obj"
expect_rc 2 "missing input"

# ------------------------------------------------------------- read errors
printf '1\n1,2,3\n' >"$T/bad.bpt"
echo "keep" >"$T/keep.obj"
run "$T/bad.bpt" -o "$T/keep.obj"
expect_rc 1 "malformed bpt"
expect_err "bad.bpt:2:1:" "malformed bpt names line and column"
checks=$((checks + 1))
[ "$(cat "$T/keep.obj")" = "keep" ] || fail "a failed run changed the existing output"
run "$T/missing.bpt" -o "$T/x.obj"
expect_rc 1 "missing input file"

# -------------------------------------------------------------------- JSON
if [ "$HAVE_JSON" != 1 ]; then
    run "$DATA/surfaces.json" -o "$T/s.obj"
    expect_rc 1 "JSON without cJSON"
    expect_err "needs cJSON" "JSON without cJSON"
else
    run "$DATA/surfaces.json" -o "$T/s.obj" --tol 1e-3 --normals --json
    expect_rc 0 "surfaces.json"
    echo "$out" >"$T/s.json"
    pycheck "surfaces.json: exact sphere and torus, three parts" "$T/s.json" "$T/s.obj" "$T/objcheck.py" <<'EOF'
import json, math, sys
exec(open(sys.argv[3]).read())
r = json.load(open(sys.argv[1]))
assert r["surfaces"] == 3 and r["max_error"] <= 1e-3
V, VT, VN, F = read_obj(sys.argv[2])
comps, boundary, nm = components_and_boundary(V, F)
assert comps == 3 and nm == 0, (comps, nm)
ns = nt = 0
for p in V:
    rho = math.hypot(p[0], p[1])
    if p[0] < 3.5 and math.sqrt(rho * rho + p[2] * p[2]) < 1.2:   # the unit sphere
        assert abs(math.sqrt(rho * rho + p[2] * p[2]) - 1) < 1e-14, p
        ns += 1
    elif p[0] < 3.5:                                              # torus R = 2, r = 0.5
        assert abs(math.hypot(rho - 2, p[2]) - 0.5) < 1e-14, p
        nt += 1
assert ns > 100 and nt > 100
# the closed sphere and torus have no boundary: every boundary edge is the hill's
assert boundary > 0
print("ok")
EOF
    cat >"$T/bad1.json" <<'EOF'
{"surfaces": [{"name": "bad", "type": "nurbs", "degree_u": 2, "degree_v": 1,
  "knots_u": [0, 0, 0, 1, 1, 1], "knots_v": [0, 0, 1],
  "points": [[[0,0,0],[0,1,0]], [[1,0,0],[1,1,0]], [[2,0,0],[2,1,1]]]}]}
EOF
    run "$T/bad1.json" -o "$T/x.obj"
    expect_rc 1 "bad knots_v"
    expect_err 'surfaces[0] ("bad")' "message names the entry"
    expect_err '"knots_v"' "message names the key"
    printf '{"surfaces": [{"type": "nurbs", "degree_u": 1}]}' >"$T/bad2.json"
    run "$T/bad2.json" -o "$T/x.obj"
    expect_rc 1 "missing key"
    expect_err 'surfaces[0]: missing key "points"' "missing key"
    printf '{"surfaces": [{"type": "bezier", "points": [[[0,0,0],[1,0,0]],[[0,1,0],[1,1]]]}]}' >"$T/bad3.json"
    run "$T/bad3.json" -o "$T/x.obj"
    expect_rc 1 "2D point in a surface"
    expect_err '"points"[1][1]' "bad point named"
    printf '{"surfaces": [\n  {"type": "bezier",, }\n]}' >"$T/bad4.json"
    run "$T/bad4.json" -o "$T/x.obj"
    expect_rc 1 "JSON syntax"
    expect_err "bad4.json:2:" "syntax error line"
    cat >"$T/bad5.json" <<'EOF'
{"surfaces": [{"type": "nurbs", "degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1],
  "knots_v": [0,0,1,1], "points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,0]]],
  "weights": [[1, 1], [1, -2]]}]}
EOF
    run "$T/bad5.json" -o "$T/x.obj"
    expect_rc 1 "negative weight"
    expect_err '"weights": weight (1, 1) is -2' "negative weight"
fi

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
