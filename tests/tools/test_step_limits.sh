#!/usr/bin/env bash
# geom-tessellate on STEP input estimates its output before the work
# (geom_step_tess_estimate) and refuses past --max-triangles / --max-memory
# at once, with the estimate in the message and no output file (issue 15:
# the old tool worked until the library's limit and gave no figure). Every
# STEP file of Debian's gmsh-doc and data/sphere.step; the estimate in
# --json is within a factor 3 of the count made at the default tolerance.
# Exit 77 (skipped) without gmsh-doc's files only for those; sphere.step
# always runs.
. "$(dirname "$0")/strict.sh" "$@"
files=("$data/sphere.step")
for f in $(find /usr/share/doc/gmsh-doc /usr/share/doc/gmsh -name '*.st*p.gz' 2>/dev/null | sort); do
    b=$(basename "$f" .gz)
    zcat "$f" > "$tmp/$b"
    files+=("$tmp/$b")
done
[ ${#files[@]} -gt 1 ] || echo "note: gmsh-doc's STEP files are missing; sphere.step only"
for f in "${files[@]}"; do
    name=$(basename "$f")
    rm -f "$tmp/o.obj"
    # a tiny tolerance and a small limit: refused quickly with the figure
    if "$tool" "$f" --tol 1e-7 --max-triangles 10 -o "$tmp/o.obj" 2> "$tmp/err"; then
        fail "$name: --tol 1e-7 --max-triangles 10 accepted"
    fi
    grep -q "would have about [0-9]* triangles (estimate), more than --max-triangles 10;" \
        "$tmp/err" || fail "$name: no estimate in the message: $(cat "$tmp/err")"
    [ ! -e "$tmp/o.obj" ] || fail "$name: a refused run left a file"
    # memory, with the default triangle limit
    # memory, with the default triangle limit (a flat part may fit: then
    # its estimate must say so)
    if "$tool" "$f" --tol 1e-5 --max-memory 1M --json -o "$tmp/o.obj" > "$tmp/r.json" 2> "$tmp/err"; then
        "$py" -c 'import json,sys; r=json.load(open(sys.argv[1])); assert r["estimated_triangles"] * 250 <= 1 << 20, r' "$tmp/r.json" ||
            fail "$name: --max-memory 1M accepted past its estimate"
    else
        grep -q "MiB (estimate), more than --max-memory 1 MiB" "$tmp/err" ||
            fail "$name: $(cat "$tmp/err")"
    fi
    # the estimate against the count made
    "$tool" "$f" --json -o "$tmp/o.obj" > "$tmp/r.json"
    "$py" - "$tmp/r.json" "$name" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ratio = r["estimated_triangles"] / r["triangles"]
print("%s: estimate %.0f, made %d, ratio %.2f" % (sys.argv[2], r["estimated_triangles"],
                                                  r["triangles"], ratio))
assert 1 / 3 <= ratio <= 3, ratio
PY
done
echo ok
