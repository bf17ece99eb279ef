#!/bin/bash
# Tests of geom-raycast: a scene of every analytic type, CSG, instances,
# transforms, an inline Bezier surface and a mesh file, checked against
# closed forms (closest, --any, --all output format and values, 17 digits);
# invalid rays answer miss and are counted in --json (last line of stderr);
# tmin/tmax; a mesh given directly; errors naming the object and the key
# (exit 1), JSON syntax errors with line and column, bad ray lines with
# their line, usage errors (exit 2); over several batches of rays, --any
# and --all agree with --closest ray by ray.
# Usage: test_geom_raycast.sh /path/to/geom-raycast VERSION   (env PYTHON3)
set -u
if [ $# -ne 2 ]; then
    echo "usage: $0 TOOL VERSION" >&2
    exit 2
fi
TOOL=$1
VERSION=$2
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-raycast-test.XXXXXX") || exit 1
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
expect_out() {
    checks=$((checks + 1))
    [ "$out" == "$1" ] || fail "$2: got '$out', expected '$1'"
}
expect_err_match() {
    checks=$((checks + 1))
    # shellcheck disable=SC2053
    [[ $err == $1 ]] || fail "$2: stderr '$err' does not match '$1'"
}

mkdir -p "$T/sub"
cat >"$T/sub/tet.off" <<'EOF'
OFF
4 4 0
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
EOF
cat >"$T/scene.json" <<'EOF'
{"objects": [
  {"type": "sphere", "center": [0, 0, 0], "radius": 1, "name": "ball"},
  {"type": "box", "min": [3, -1, -1], "max": [5, 1, 1]},
  {"type": "torus", "major": 2, "minor": 0.5, "transform": {"translate": [0, 10, 0]}},
  {"type": "instance", "of": "ball", "transform": {"scale": 2, "translate": [0, -10, 0]}},
  {"type": "csg", "op": "difference", "transform": {"translate": [10, 0, 0]},
   "children": [{"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1]},
                {"type": "sphere", "center": [0, 0, 0], "radius": 0.5}]},
  {"type": "quadric", "coefficients": [1, 1, 0, 0, 0, 0, 0, 0, 0, -1],
   "clip": [-1, -1, -1, 1, 1, 1], "capped": true, "transform": {"translate": [-10, 0, 0]}},
  {"type": "triangle", "vertices": [[20, 0, 0], [21, 0, 0], [20, 1, 0]]},
  {"type": "plane", "point": [0, 0, -50], "normal": [0, 0, 1]},
  {"type": "mesh", "file": "sub/tet.off", "transform": {"translate": [30, 0, 0]}},
  {"type": "bezier", "points": [[[40, 0, 0], [40, 1, 0]], [[41, 0, 0], [41, 1, 0]]]},
  {"type": "disk", "center": [50, 0, 0], "normal": [0, 0, 1], "radius": 1,
   "transform": {"rotate": [90, 1, 0, 0]}}
]}
EOF
# rays (from z = -5 upward unless stated)
cat >"$T/rays.txt" <<'EOF'
# comment lines and blank lines are skipped

0 0 -5 0 0 1
4 0 -5 0 0 2
0 12 5 0 0 -1
0 -10 -5 0 0 1
10 0 -5 0 0 1
-10 0 -5 0 0 1
20.25 0.25 -5 0 0 1
30.2 0.2 -5 0 0 1
40.25 0.5 -5 0 0 1
50 -5 0.5 0 1 0
0 0 0 nan 0 1
0 0 0 0 0 0
0 0 -5 0 0 1 4.5
0 0 -5 0 0 1 0 3.9
EOF
run "$T/scene.json" --rays "$T/rays.txt" --all --json
expect_rc 0 "--all"
cat >"$T/expect_all" <<'EOF'
4 enter 6 leave
2 enter 3 leave
4.5 enter 5.5 leave 55 enter
3 enter 7 leave
4 enter 4.5 leave 5.5 enter 6 leave
4 enter 6 leave
5 leave
5 enter T5.6 leave
5 leave
5 enter
miss
miss
6 leave
miss
EOF
checks=$((checks + 1))
"$PY" - "$T/stdout" "$T/expect_all" <<'PYEOF' || fail "--all output differs: $out"
import sys
got = open(sys.argv[1]).read().split("\n")
exp = open(sys.argv[2]).read().split("\n")
assert len(got) == len(exp), (got, exp)
for g, e in zip(got, exp):
    gw, ew = g.split(), e.split()
    assert len(gw) == len(ew), (g, e)
    for a, b in zip(gw, ew):
        if b.startswith("T"):  # t within 4 ulp-ish
            assert abs(float(a) - float(b[1:])) <= 4e-15 * abs(float(b[1:])), (g, e)
        else:
            assert a == b, (g, e)
PYEOF
last=$(tail -n 1 "$T/stderr")
checks=$((checks + 1))
"$PY" - "$last" <<'PYEOF' || fail "--json report: $last"
import json, sys
j = json.loads(sys.argv[1])
assert j["tool"] == "geom-raycast" and j["mode"] == "all"
assert j["rays"] == 14 and j["invalid_rays"] == 2 and j["rays_hit"] == 11, j
assert j["built"]["bvhs"] == 1 and j["built"]["triangles"] == 4
assert len(j["objects"]) == 11 and j["objects"][8]["acceleration"] == "bvh"
assert j["objects"][9]["acceleration"] == "bezier-patches"
assert j["build_seconds"] >= 0 and j["rays_per_second"] >= 0
PYEOF

run "$T/scene.json" --rays "$T/rays.txt"
expect_rc 0 "--closest"
checks=$((checks + 1))
"$PY" - "$T/stdout" <<'PYEOF' || fail "closest hits: $out"
import sys
lines = open(sys.argv[1]).read().split("\n")[:-1]
assert len(lines) == 14, lines
def f(i): return [float(x) for x in lines[i].split()]
h = f(0)  # unit sphere from below
assert h[0] == 4 and h[1:4] == [0, 0, -1] and h[4:7] == [0, 0, -1] and h[9:] == [0, 0], h
h = f(1)  # box bottom face, t in units of dir (|dir| = 2)
assert h[0] == 2 and h[3] == -1 and h[6] == -1 and h[9] == 1 and h[10] == 4, h
h = f(2)  # torus top at (0, 12, 0.5)
assert abs(h[0] - 4.5) < 1e-12 and abs(h[6] - 1) < 1e-12 and h[9] == 2, h
h = f(3)  # instance: sphere of radius 2 at y = -10
assert abs(h[0] - 3) < 1e-12 and h[9] == 3, h
h = f(6)  # triangle: barycentrics of v1, v2
assert h[0] == 5 and h[7] == 0.25 and h[8] == 0.25 and h[6] == 1 and h[9] == 6, h
h = f(7)  # mesh (tetrahedron) bottom face, outward normal -z
assert h[0] == 5 and h[6] == -1 and h[9] == 8, h
h = f(8)  # Bezier patch, u = x - 40, v = y
assert abs(h[0] - 5) < 1e-12 and abs(h[7] - 0.25) < 1e-12 and abs(h[8] - 0.5) < 1e-12 and h[9] == 9, h
h = f(9)  # disk rotated +90 about x: normal +z -> -y; ray along +y: leave
assert abs(h[0] - 5) < 1e-12 and abs(h[5] + 1) < 1e-12 and h[9] == 10, h
assert lines[10] == "miss" and lines[11] == "miss"
assert f(12)[0] == 6 and lines[13] == "miss"
for l in lines:
    for w in l.split()[:9]:
        if w != "miss" and "." in w:
            m = w.split("e")[0].replace("-", "").replace(".", "").lstrip("0")
            assert len(m) <= 17, w
PYEOF
run "$T/scene.json" --rays "$T/rays.txt" --any
expect_rc 0 "--any"
expect_out "$(printf 'hit\nhit\nhit\nhit\nhit\nhit\nhit\nhit\nhit\nhit\nmiss\nmiss\nhit\nmiss')" "--any answers"

# more rays than one batch (4096): --any and --all agree ray by ray with
# --closest (hit iff not miss; the first --all t is the closest t), and the
# --json counts add up over the batches; invalid rays in every batch
"$PY" - "$T/many.txt" <<'PYEOF'
import random, sys
rng = random.Random(5)
with open(sys.argv[1], "w") as f:
    for i in range(9500):
        tx = rng.choice([0, 4, 10, -10, 20.3, 30.2, 40.5, 0]) + rng.uniform(-1.2, 1.2)
        ty = rng.choice([0, 0, 10, -10]) + rng.uniform(-1.5, 1.5)
        o = [rng.uniform(-60, 60), rng.uniform(-60, 60), rng.uniform(-40, 40)]
        d = [tx - o[0], ty - o[1], rng.uniform(-1, 1) - o[2]]
        if i % 997 == 3:
            o[1] = float("nan")
        elif i % 991 == 5:
            d = [0, 0, 0]
        extra = " 0 %r" % rng.uniform(10, 80) if i % 7 == 0 else ""
        f.write("%r %r %r %r %r %r%s\n" % (o[0], o[1], o[2], d[0], d[1], d[2], extra))
PYEOF
run "$T/scene.json" --rays "$T/many.txt" --closest --json
expect_rc 0 "many rays --closest"
cp "$T/stdout" "$T/many_closest"
tail -n 1 "$T/stderr" >"$T/many_closest.json"
run "$T/scene.json" --rays "$T/many.txt" --any --json
expect_rc 0 "many rays --any"
cp "$T/stdout" "$T/many_any"
tail -n 1 "$T/stderr" >"$T/many_any.json"
run "$T/scene.json" --rays "$T/many.txt" --all --json
expect_rc 0 "many rays --all"
cp "$T/stdout" "$T/many_all"
tail -n 1 "$T/stderr" >"$T/many_all.json"
checks=$((checks + 1))
"$PY" - "$T" <<'PYEOF' || fail "--any / --all / --closest disagree over several batches"
import json, sys
d = sys.argv[1]
c = open(d + "/many_closest").read().split("\n")[:-1]
a = open(d + "/many_any").read().split("\n")[:-1]
l = open(d + "/many_all").read().split("\n")[:-1]
assert len(c) == len(a) == len(l) == 9500, (len(c), len(a), len(l))
nhit = nhits = 0
for i, (ci, ai, li) in enumerate(zip(c, a, l)):
    if ci == "miss":
        assert ai == "miss" and li == "miss", (i, ci, ai, li)
        continue
    nhit += 1
    w = li.split()
    assert ai == "hit" and len(w) % 2 == 0 and w[1] in ("enter", "leave"), (i, ci, ai, li)
    ts = [float(x) for x in w[0::2]]
    assert ts == sorted(ts) and ts[0] == float(ci.split()[0]), (i, ci, li)
    nhits += len(ts)
assert 2000 < nhit < 9000, nhit
jc, ja, jl = (json.load(open(d + "/many_%s.json" % m)) for m in ("closest", "any", "all"))
for j in (jc, ja, jl):
    assert j["rays"] == 9500 and j["invalid_rays"] == 20 and j["rays_hit"] == nhit, j
assert jl["hits"] == nhits, (jl["hits"], nhits)
PYEOF

# rays from standard input, a mesh given directly
printf '0.2 0.2 -1 0 0 1\n5 5 5 1 0 0\n' | "$TOOL" "$T/sub/tet.off" --all >"$T/stdout" 2>"$T/stderr"
rc=$?
out=$(cat "$T/stdout")
expect_rc 0 "mesh from stdin"
checks=$((checks + 1))
case "$out" in
"1 enter 1.6"*" leave"$'\n'"miss" | "1 enter 1.59999999999999"*" leave"$'\n'"miss") ;;
*) fail "mesh --all: $out" ;;
esac

# errors name the object and the key
printf '{"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1},\n {"type": "sphere", "name": "b", "center": [0,0], "radius": 1}]}' >"$T/bad1.json"
run "$T/bad1.json" --rays "$T/rays.txt"
expect_rc 1 "bad center"
expect_err_match '*bad1.json*objects\[1\] ("b")*"center"*3 numbers*' "bad center message"
printf '{"objects": [{"type": "torus", "major": 2, "minor": -1}]}' >"$T/bad2.json"
run "$T/bad2.json" --rays "$T/rays.txt"
expect_rc 1 "bad minor"
expect_err_match '*objects\[0\]*"minor"*> 0*' "bad minor message"
printf '{"objects": [{"type": "mesh", "file": "missing.obj"}]}' >"$T/bad3.json"
run "$T/bad3.json" --rays "$T/rays.txt"
expect_rc 1 "missing mesh"
expect_err_match '*objects\[0\]*"file"*' "missing mesh message"
printf '{"objects": [{"type": "instance", "of": "nobody"}]}' >"$T/bad4.json"
run "$T/bad4.json" --rays "$T/rays.txt"
expect_rc 1 "unknown instance"
expect_err_match '*"of"*nobody*' "unknown instance message"
printf '{"objects": [\n  {"type": "sphere",, }\n]}' >"$T/bad5.json"
run "$T/bad5.json" --rays "$T/rays.txt"
expect_rc 1 "JSON syntax"
expect_err_match '*bad5.json:2:*JSON syntax error*' "JSON syntax position"
printf '{"objects": [{"type": "cube"}]}' >"$T/bad6.json"
run "$T/bad6.json" --rays "$T/rays.txt"
expect_rc 1 "unknown type"
expect_err_match '*"type"*unknown type "cube"*' "unknown type message"
printf '0 0 0 1 0 0\n0 0 0 1 0\n' >"$T/badrays.txt"
run "$T/scene.json" --rays "$T/badrays.txt"
expect_rc 1 "short ray line"
expect_err_match '*badrays.txt:2*6 to 8 numbers*' "short ray line message"
run
expect_rc 2 "no input"
run "$T/scene.json" extra
expect_rc 2 "extra operand"
run --version
expect_rc 0 "--version"
expect_out "geom-raycast (libgeom) $VERSION" "--version text"

echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
