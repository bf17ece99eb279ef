#!/bin/bash
# Tests of geom-query: kNN/radius/box answers against a brute force in
# Python (ties by index, inclusive radius, every index), the same answers
# from kdtree, octree and quadtree, closest points and signed distances on a
# cube (closed forms; exactly 1/2 winding counts inside), --json as the last
# line of stderr, errors naming the 1-based line (wrong count, NaN/Inf) with
# exit 1, usage errors with exit 2, -o, empty answers as empty lines.
# Usage: test_geom_query.sh /path/to/geom-query   (env PYTHON3: python)
set -u
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-query-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
run() {
    "$TOOL" "$@" >"$T/stdout" 2>"$T/stderr"
    rc=$?
}

# Grid points (many ties) and random queries, 3D and 2D.
"$PY" - "$T" <<'PYEOF'
import random, sys
random.seed(7)
d = sys.argv[1]
with open(d + "/p3.txt", "w") as f:
    for i in range(6):
        for j in range(6):
            for k in range(6):
                f.write("%d %d %d\n" % (i, j, k))
    f.write("2 2 2\n")  # a duplicate
with open(d + "/q3.txt", "w") as f:
    f.write("2.5 2.5 2.5\n0 0 0\n-10 -10 -10\n")
    for _ in range(20):
        f.write("%r %r %r\n" % tuple(round(random.uniform(-1, 6) * 2) / 2 for _ in range(3)))
with open(d + "/p2.txt", "w") as f:
    f.write("# comment\n\n")
    for _ in range(300):
        f.write("%r,%r\n" % (random.random(), random.random()))
with open(d + "/q2.txt", "w") as f:
    for _ in range(20):
        f.write("%r %r\n" % (random.random(), random.random()))
PYEOF

brute() { # brute MODE POINTS QUERIES ARG -> expected output
    "$PY" - "$@" <<'PYEOF'
import sys, math
mode, pf, qf, arg = sys.argv[1:5]
def load(fn):
    out = []
    for line in open(fn):
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        out.append([float(x) for x in s.replace(",", " ").split()])
    return out
P, Q = load(pf), load(qf)
for q in Q:
    d = sorted((sum((a - b) ** 2 for a, b in zip(p, q)), i) for i, p in enumerate(P))
    if mode == "knn":
        sel = d[:int(arg)]
    else:
        sel = [x for x in d if math.sqrt(x[0]) <= float(arg)]
    print(" ".join(str(i) for _, i in sel))
PYEOF
}

for idx in kdtree octree; do
    for spec in "knn 1" "knn 7" "knn 300" "radius 1" "radius 1.5" "radius 0"; do
        set -- $spec
        run "$T/p3.txt" --index $idx --$1 $2 --queries "$T/q3.txt"
        [ $rc -eq 0 ] || fail "$idx --$1 $2: exit $rc: $(cat "$T/stderr")"
        brute $1 "$T/p3.txt" "$T/q3.txt" $2 >"$T/want"
        cmp -s "$T/stdout" "$T/want" || fail "$idx --$1 $2 differs from brute force"
    done
done
for idx in kdtree quadtree; do
    run "$T/p2.txt" --index $idx --knn 5 --queries "$T/q2.txt"
    brute knn "$T/p2.txt" "$T/q2.txt" 5 >"$T/want"
    cmp -s "$T/stdout" "$T/want" || fail "2D $idx --knn 5 differs from brute force"
    run "$T/p2.txt" --index $idx --radius 0.1 --queries "$T/q2.txt"
    brute radius "$T/p2.txt" "$T/q2.txt" 0.1 >"$T/want"
    cmp -s "$T/stdout" "$T/want" || fail "2D $idx --radius differs from brute force"
done

# Radius inclusive; --distances with 17 digits; empty answer = empty line.
printf '0 0 0\n3 4 0\n' >"$T/two.txt"
run "$T/two.txt" --radius 5 --distances <<<"0 0 0"
[ "$(cat "$T/stdout")" = "0:0 1:5" ] || fail "inclusive radius: $(cat "$T/stdout")"
run "$T/two.txt" --radius 4.999 <<<"0 0 0"
[ "$(cat "$T/stdout")" = "0" ] || fail "radius 4.999"
printf '10 10 10\n0 0 0\n' >"$T/qq.txt"
run "$T/two.txt" --radius 1 --queries "$T/qq.txt"
[ "$(cat "$T/stdout")" = "$(printf '\n0')" ] || fail "empty answer must be an empty line"
run "$T/two.txt" --knn 1 --distances <<<"0.1 0 0"
[ "$(cat "$T/stdout")" = "0:0.10000000000000001" ] || fail "17 digits: $(cat "$T/stdout")"

# Box: boundary included, index order, no queries read.
run "$T/p3.txt" --box 0,0,0,1,1,0 </dev/null
[ "$(cat "$T/stdout")" = "0 6 36 42" ] || fail "box: $(cat "$T/stdout")"
run "$T/p2.txt" --index quadtree --box 0,0,0.5,0.5 </dev/null
want=$("$PY" -c "
import sys
P=[[float(x) for x in l.replace(',',' ').split()] for l in open('$T/p2.txt') if l.strip() and not l.startswith('#')]
print(' '.join(str(i) for i,p in enumerate(P) if 0<=p[0]<=0.5 and 0<=p[1]<=0.5))")
[ "$(cat "$T/stdout")" = "$want" ] || fail "2D box"

# --json: last line of stderr is one JSON object.
run "$T/p3.txt" --knn 2 --json --queries "$T/q3.txt"
tail -n 1 "$T/stderr" | "$PY" -c "
import json, sys
o = json.loads(sys.stdin.read())
assert o['index'] == 'kdtree' and o['points'] == 217 and o['queries'] == 23, o
assert o['nodes'] >= 1 and o['depth'] >= 1 and o['bytes'] > 0 and o['build_seconds'] >= 0
" || fail "--json"

# Mesh: unit cube (outward), closest point and signed distance.
cat >"$T/cube.off" <<'CUBE'
OFF
8 6 0
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 1 2 6 5
4 2 3 7 6
4 3 0 4 7
CUBE
printf '0.5 0.5 0.5\n2 0.5 0.5\n0.5 0.5 -3\n0.25 0.25 0.25\n' >"$T/cq.txt"
run "$T/cube.off" --signed-distance --queries "$T/cq.txt" --json
[ $rc -eq 0 ] || fail "signed distance: $(cat "$T/stderr")"
[ "$(cat "$T/stdout")" = "$(printf -- '-0.5\n1\n3\n-0.25')" ] || fail "signed distance: $(cat "$T/stdout")"
tail -n 1 "$T/stderr" | "$PY" -c "
import json, sys
o = json.loads(sys.stdin.read()); assert o['index'] == 'bvh' and o['triangles'] == 12, o
assert 'winding_error_bound' in o" || fail "--json signed distance"
run "$T/cube.off" --closest <<<"2 0.5 0.5"
set -- $(cat "$T/stdout")
[ "$1 $2 $3 $5" = "1 0.5 0.5 1" ] || fail "closest: $(cat "$T/stdout")"
# On the surface: winding number exactly 1/2 counts as inside (distance 0, sign -).
run "$T/cube.off" --signed-distance <<<"0.5 0.5 0"
[ $rc -eq 0 ] || fail "on-surface query"
# A mesh's vertices as points.
run "$T/cube.off" --knn 1 <<<"0.9 0.9 0.9"
[ "$(cat "$T/stdout")" = "6" ] || fail "mesh vertices as points: $(cat "$T/stdout")"

# Errors: 1-based line numbers, exit 1.
printf '0 0 0\n1 1\n' >"$T/bad.txt"
run "$T/bad.txt" --knn 1 <<<"0 0 0"
[ $rc -eq 1 ] && grep -q "bad.txt:2:" "$T/stderr" || fail "wrong count in POINTS: $(cat "$T/stderr")"
printf '0 0 0\n1 inf 1\n' >"$T/bad2.txt"
run "$T/bad2.txt" --knn 1 <<<"0 0 0"
[ $rc -eq 1 ] && grep -q "bad2.txt:2:" "$T/stderr" || fail "Inf in POINTS"
printf '0 0 0\n\n1 2 nan\n' >"$T/badq.txt"
run "$T/p3.txt" --knn 1 --queries "$T/badq.txt"
[ $rc -eq 1 ] && grep -q "badq.txt:3:" "$T/stderr" || fail "NaN query: $(cat "$T/stderr")"
run "$T/p3.txt" --knn 1 <<<"1 2"
[ $rc -eq 1 ] && grep -q "<stdin>:1:" "$T/stderr" || fail "short query line"
run "$T/p3.txt" --knn 1 -o "$T/never.txt" <<<"1 2"
[ ! -e "$T/never.txt" ] || fail "-o must not be created on error"
run "$T/p3.txt" --knn 2 -o "$T/ok.txt" <<<"0 0 0"
[ "$(cat "$T/ok.txt")" = "0 1" ] || fail "-o output"

# Usage errors: exit 2.
for args in "--knn 0" "--knn 2 --radius 1" "" "--radius -1" "--box 1,2,3" "--index bvh --knn 1" \
            "--index nope --knn 1" "--closest --index kdtree"; do
    run "$T/p3.txt" $args </dev/null
    [ $rc -eq 2 ] || fail "usage error expected for '$args' (exit $rc)"
done
run "$T/p3.txt" --box 0,0,1,1 </dev/null
[ $rc -eq 2 ] || fail "2D box on 3D points"
run --help
[ $rc -eq 0 ] || fail "--help"

if [ $failures -ne 0 ]; then
    echo "$failures failure(s)" >&2
    exit 1
fi
echo "geom-query: all checks passed"
