#!/bin/bash
# Tests of geom-info: topology of the sample meshes in data/ and of meshes
# generated here (tori, an open grid, a bowtie, a degenerate triangle)
# against references computed independently by Python from the file text
# (V - E + F from the face lists, edges counted as unordered pairs, genus of
# closed orientable components), --json keys and values, standard input,
# repairs, --skip-invalid, errors (exit 1, FILE:LINE:COL) and usage errors
# (exit 2).
# Usage: test_geom_info.sh /path/to/geom-info DATA_DIR   (env PYTHON3: python)
set -u
if [ $# -ne 2 ]; then
    echo "usage: $0 TOOL DATA_DIR" >&2
    exit 2
fi
TOOL=$1
DATA=$2
PY=${PYTHON3:-/usr/bin/python3}
[ -x "$TOOL" ] || { echo "FAIL: $TOOL is not an executable" >&2; exit 1; }
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-info-test.XXXXXX") || exit 1
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
expect_line() { # expect_line LINE WHAT: stdout has this exact line
    checks=$((checks + 1))
    grep -qxF -- "$1" "$T/stdout" || fail "$2: no line '$1' in: $out"
}
expect_err() { # expect_err SUBSTRING WHAT
    checks=$((checks + 1))
    case $err in
    *"$1"*) ;;
    *) fail "$2: stderr '$err' lacks '$1'" ;;
    esac
}

# ------------------------------------------------ independent references
# ref.py FILE: print the reference JSON (vertices, faces, edges, euler,
# boundary_loops, components, genus) computed from an OBJ/OFF file's text.
cat >"$T/ref.py" <<'EOF'
import sys, json
def load(path):
    V, F = 0, []
    if path.endswith('.off'):
        toks = [l.split('#')[0].split() for l in open(path)]
        toks = [t for t in toks if t]
        nv, nf = int(toks[1][0]), int(toks[1][1])
        V = nv
        for t in toks[2 + nv:2 + nv + nf]:
            n = int(t[0]); F.append([int(x) for x in t[1:1 + n]])
    else:
        for l in open(path):
            t = l.split()
            if not t: continue
            if t[0] == 'v': V += 1
            if t[0] == 'f':
                F.append([(int(x.split('/')[0]) - 1) if int(x.split('/')[0]) > 0
                          else V + int(x.split('/')[0]) for x in t[1:]])
    return V, F
V, F = load(sys.argv[1])
edges = {}
for f in F:
    for i in range(len(f)):
        e = tuple(sorted((f[i], f[(i + 1) % len(f)])))
        edges[e] = edges.get(e, 0) + 1
# union-find over vertices joined by edges
parent = list(range(V))
def find(a):
    while parent[a] != a:
        parent[a] = parent[parent[a]]; a = parent[a]
    return a
for a, b in edges:
    parent[find(a)] = find(b)
comps = {}
for v in range(V):
    comps.setdefault(find(v), []).append(v)
bnd = [e for e, c in edges.items() if c == 1]
# boundary loops: boundary edges form disjoint cycles in these tests
adj = {}
for a, b in bnd:
    adj.setdefault(a, []).append(b); adj.setdefault(b, []).append(a)
seen, loops = set(), 0
for a, b in bnd:
    if (a, b) in seen: continue
    loops += 1
    prev, cur = a, b
    seen.add((min(a, b), max(a, b)))
    while cur != a:
        nxt = [x for x in adj[cur] if x != prev][0]
        seen.add((min(cur, nxt), max(cur, nxt)))
        prev, cur = cur, nxt
genus = 0
for root, vs in comps.items():
    vset = set(vs)
    ce = sum(1 for e in edges if e[0] in vset)
    cf = sum(1 for f in F if f[0] in vset)
    cb = 0
    # boundary loops of this component
    cl, seen2 = 0, set()
    for a, b in bnd:
        if a not in vset or (a, b) in seen2: continue
        cl += 1
        prev, cur = a, b
        seen2.add((min(a, b), max(a, b)))
        while cur != a:
            nxt = [x for x in adj[cur] if x != prev][0]
            seen2.add((min(cur, nxt), max(cur, nxt)))
            prev, cur = cur, nxt
    genus += (2 - (len(vs) - ce + cf) - cl) // 2
print(json.dumps({"vertices": V, "faces": len(F), "edges": len(edges),
                  "euler": V - len(edges) + len(F), "boundary_loops": loops,
                  "components": len(comps), "genus": genus}))
EOF

# compare PATH: geom-info --json PATH agrees with ref.py on every key
compare() {
    local path=$1
    run --json "$path"
    expect_rc 0 "geom-info --json $path"
    "$PY" "$T/ref.py" "$path" >"$T/ref.json" || { fail "ref.py $path"; return; }
    checks=$((checks + 1))
    "$PY" - "$T/stdout" "$T/ref.json" <<'EOF' || fail "geom-info --json $path disagrees with the reference"
import sys, json
got = json.load(open(sys.argv[1])); ref = json.load(open(sys.argv[2]))
keys = ["vertices", "faces", "edges", "boundary_loops", "components", "euler", "genus",
        "manifold", "closed", "degenerate_faces", "bbox", "attributes"]
missing = [k for k in keys if k not in got]
if missing:
    print("missing keys", missing); sys.exit(1)
bad = [(k, got[k], v) for k, v in ref.items() if got[k] != v]
if bad:
    print("mismatch", bad); sys.exit(1)
if got["closed"] != (ref["boundary_loops"] == 0):
    print("closed", got["closed"]); sys.exit(1)
EOF
}

# ------------------------------------------------------------- sample data
run "$DATA/cube_seams.obj"
expect_rc 0 "cube"
for l in "vertices: 8" "faces: 6" "edges: 12" "boundary_loops: 0" "components: 1" \
    "euler: 2" "genus: 0" "manifold: true" "closed: true" "degenerate_faces: 0" \
    "bbox: 0 0 0 1 1 1" "attributes: position (vertex, 3, 8), uv (corner, 2, 14), normal (corner, 3, 6)"; do
    expect_line "$l" "cube text"
done
checks=$((checks + 1))
[ -z "$err" ] || fail "cube: unexpected stderr '$err'"
compare "$DATA/cube_seams.obj"
compare "$DATA/tetra.off"

run --json "$DATA/pyramid.ply"
expect_rc 0 "pyramid"
checks=$((checks + 1))
"$PY" - "$T/stdout" <<'EOF' || fail "pyramid --json values"
import sys, json
g = json.load(open(sys.argv[1]))
assert g["format"] == "ply"
assert (g["vertices"], g["faces"], g["edges"], g["euler"], g["genus"]) == (5, 5, 8, 2, 0), g
assert g["closed"] is True and g["manifold"] is True
assert g["bbox"] == {"min": [-1, -1, 0], "max": [1, 1, 1]}, g["bbox"]
assert [a["name"] for a in g["attributes"]] == ["position", "color"]
assert g["skipped"]["elements"] == 1 and g["skipped"]["properties"] == 2
EOF
run --json "$DATA/wedge.stl"
expect_rc 0 "wedge"
checks=$((checks + 1))
"$PY" - "$T/stdout" <<'EOF' || fail "wedge --json values"
import sys, json
g = json.load(open(sys.argv[1]))
assert (g["vertices"], g["faces"], g["edges"], g["euler"], g["closed"]) == (6, 8, 12, 2, True), g
assert g["bbox"]["max"] == [1, 1, 2]
EOF

# ---------------------------------------------------- generated meshes
# torus(n, m, dx): an n x m quad torus shifted by dx, as OBJ text
cat >"$T/gen.py" <<'EOF'
import sys, math
def torus(n, m, dx, base):
    out = []
    for i in range(n):
        for j in range(m):
            a, b = 2 * math.pi * i / n, 2 * math.pi * j / m
            out.append("v %r %r %r" % (dx + (2 + math.cos(b)) * math.cos(a),
                                       (2 + math.cos(b)) * math.sin(a), math.sin(b)))
    for i in range(n):
        for j in range(m):
            q = [i * m + j, ((i + 1) % n) * m + j, ((i + 1) % n) * m + (j + 1) % m,
                 i * m + (j + 1) % m]
            out.append("f " + " ".join(str(base + x + 1) for x in q))
    return out
kind = sys.argv[1]
if kind == "torus":
    print("\n".join(torus(8, 6, 0, 0)))
elif kind == "two_tori":
    print("\n".join(torus(8, 6, 0, 0)[:48] + torus(5, 4, 10, 48)[:20] +
                    torus(8, 6, 0, 0)[48:] + torus(5, 4, 10, 48)[20:]))
elif kind == "grid":
    k = 4
    print("\n".join("v %d %d 0" % (i, j) for j in range(k) for i in range(k)))
    print("\n".join("f %d %d %d %d" % (j * k + i + 1, j * k + i + 2, (j + 1) * k + i + 2,
                                       (j + 1) * k + i + 1)
                    for j in range(k - 1) for i in range(k - 1)))
EOF
"$PY" "$T/gen.py" torus >"$T/torus.obj"
"$PY" "$T/gen.py" two_tori >"$T/two_tori.obj"
"$PY" "$T/gen.py" grid >"$T/grid.obj"
compare "$T/torus.obj"
compare "$T/two_tori.obj"
compare "$T/grid.obj"
run "$T/torus.obj"
expect_line "genus: 1" "torus genus"
expect_line "euler: 0" "torus euler"
run "$T/two_tori.obj"
expect_line "genus: 2" "two tori: genus summed over components"
expect_line "components: 2" "two tori components"
run "$T/grid.obj"
expect_line "boundary_loops: 1" "grid boundary"
expect_line "closed: false" "grid open"

# a degenerate (collinear) triangle next to a good one
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 2 3 4\nf 1 4 3\nf 1 3 2\n' >"$T/degen.obj"
run "$T/degen.obj"
expect_rc 0 "degenerate"
expect_line "degenerate_faces: 1" "collinear triangle counted"

# repairs: a bowtie (two triangles sharing only a vertex) is split
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n' >"$T/bowtie.obj"
run "$T/bowtie.obj"
expect_rc 0 "bowtie"
expect_line "vertices: 6" "bowtie vertex split"
expect_err "repaired: 1 split_vertices" "bowtie repair on stderr"
run --json "$T/bowtie.obj"
checks=$((checks + 1))
"$PY" -c 'import sys, json; g = json.load(open(sys.argv[1])); assert g["repairs"]["split_vertices"] == 1 and g["repairs"]["added_vertices"] == 1 and g["components"] == 2' "$T/stdout" ||
    fail "bowtie --json repairs"

# --skip-invalid
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 2\n' >"$T/dup.obj"
run "$T/dup.obj"
expect_rc 1 "repeated vertex without --skip-invalid"
expect_err "geom-info: $T/dup.obj:5:" "FILE:LINE in the message"
expect_err "appears twice" "what is wrong"
run --skip-invalid --json "$T/dup.obj"
expect_rc 0 "--skip-invalid"
checks=$((checks + 1))
"$PY" -c 'import sys, json; g = json.load(open(sys.argv[1])); assert g["repairs"]["invalid_faces"] == 1 and g["faces"] == 1' "$T/stdout" ||
    fail "--skip-invalid counts the skipped face"

# ------------------------------------------------------------ standard input
"$TOOL" <"$DATA/tetra.off" >"$T/stdout" 2>"$T/stderr"
rc=$?
err=$(cat "$T/stderr")
expect_rc 0 "stdin, sniffed"
expect_line "faces: 4" "stdin tetra"
"$TOOL" --json --format stl - <"$DATA/wedge.stl" >"$T/stdout" 2>"$T/stderr"
rc=$?
expect_rc 0 "stdin with --format"
checks=$((checks + 1))
"$PY" -c 'import sys, json; g = json.load(open(sys.argv[1])); assert g["file"] == "<stdin>" and g["faces"] == 8' "$T/stdout" ||
    fail "stdin --json"
# -o FILE
run -o "$T/info.txt" "$DATA/tetra.off"
expect_rc 0 "-o"
checks=$((checks + 1))
grep -qx "vertices: 4" "$T/info.txt" || fail "-o FILE content"

# ------------------------------------------------------------------ errors
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' >"$T/bad.obj"
run "$T/bad.obj"
expect_rc 1 "bad index"
expect_err "geom-info: $T/bad.obj:4:7: " "FILE:LINE:COL"
run "$T/missing.obj"
expect_rc 1 "missing file"
run --format xyz "$DATA/tetra.off"
expect_rc 2 "unknown format"
run --bogus
expect_rc 2 "unknown option"
run "$DATA/tetra.off" "$DATA/tetra.off"
expect_rc 2 "two operands"
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 99999999\nproperty float x\nproperty float y\nproperty float z\nend_header\n' >"$T/absurd.ply"
run "$T/absurd.ply"
expect_rc 1 "absurd count"
expect_err "bytes" "absurd count message"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
