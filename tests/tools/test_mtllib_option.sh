#!/bin/bash
# --mtllib FILE on the tools that write OBJ through cli_mesh: the output's
# only mtllib line names FILE (whether or not it exists; the input's own
# library is dropped), usemtl groups stay, other formats are unchanged,
# standard output gets it too; a name OBJ cannot hold is a usage error
# (exit 2). Without --mtllib the input's library is still kept only when it
# is next to the output.
# Usage: test_mtllib_option.sh DATA_DIR TOOL...   (geom-normals, geom-tangents,
#        geom-clip, geom-subdivide, geom-convert: mesh in, mesh out;
#        geom-tessellate: surfaces; geom-features: polylines, OBJ only)
set -u
DATA=$1
shift
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-mtllib-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/testlib.sh" # failures, checks, fail
check() { checks=$((checks + 1)); "$@"; }
cp "$DATA/cube_seams.obj" "$T/in.obj"
mkdir -p "$T/out"
# geom-features (OBJ only, no --format): its own cases, run from the loop
features_checks() {
    local tool=$1
    "$tool" "$T/in.obj" --with-mesh --mtllib shiny.mtl -o "$T/out/f.obj" >"$T/log" 2>&1
    check [ $? -eq 0 ] || fail "geom-features --mtllib: exit $? ($(cat "$T/log"))"
    check [ "$(grep -c '^mtllib' "$T/out/f.obj")" = 1 ] || fail "geom-features: not one mtllib line"
    check grep -qx 'mtllib shiny.mtl' "$T/out/f.obj" || fail "geom-features: mtllib shiny.mtl missing"
    check grep -q '^usemtl' "$T/out/f.obj" || fail "geom-features --with-mesh: usemtl lost"
    check grep -q '^l ' "$T/out/f.obj" || fail "geom-features --with-mesh: no polylines"
    "$tool" "$T/in.obj" --with-mesh -o "$T/out/g.obj" >"$T/log" 2>&1
    check grep -q '^mtllib' "$T/out/g.obj" && fail "geom-features: dangling mtllib kept"
    # the polylines alone get the line too, first; so does standard output
    "$tool" "$T/in.obj" --mtllib shiny.mtl -o - >"$T/out/h.obj" 2>"$T/log"
    check [ "$(head -c 17 "$T/out/h.obj")" = "mtllib shiny.mtl" ] ||
        fail "geom-features: stdout has no mtllib line first"
    check grep -q '^l ' "$T/out/h.obj" || fail "geom-features: no polylines on stdout"
    "$tool" "$T/in.obj" --mtllib 'two words.mtl' -o "$T/out/i.obj" >"$T/log" 2>&1
    check [ $? -eq 2 ] || fail "geom-features: a name with a blank is not a usage error"
    check grep -q 'blanks' "$T/log" || fail "geom-features: message does not say why"
    check [ ! -e "$T/out/i.obj" ] || fail "geom-features: output written after a usage error"
}
for tool in "$@"; do
    name=$(basename "$tool")
    if [ "$name" = geom-features ]; then
        features_checks "$tool"
        continue
    fi
    case "$name" in
    geom-tessellate) in=("$DATA/teapot.bpt") ;;
    geom-clip) in=("$T/in.obj" --plane 0,0,1,100) ;;
    *) in=("$T/in.obj") ;;
    esac
    "$tool" "${in[@]}" --mtllib shiny.mtl -o "$T/out/a.obj" >"$T/log" 2>&1
    check [ $? -eq 0 ] || fail "$name --mtllib: exit $? ($(cat "$T/log"))"
    check [ "$(grep -c '^mtllib' "$T/out/a.obj")" = 1 ] || fail "$name: not one mtllib line"
    check grep -qx 'mtllib shiny.mtl' "$T/out/a.obj" || fail "$name: mtllib shiny.mtl missing"
    if [ "$name" != geom-tessellate ]; then
        check grep -q '^usemtl' "$T/out/a.obj" || fail "$name: usemtl lost"
        # without the option: the input's cube.mtl is not next to the output
        "$tool" "${in[@]}" -o "$T/out/b.obj" >"$T/log" 2>&1
        check grep -q '^mtllib' "$T/out/b.obj" && fail "$name: dangling mtllib kept"
    fi
    "$tool" "${in[@]}" --mtllib shiny.mtl -f obj -o - >"$T/out/c.obj" 2>"$T/log"
    check [ "$(head -c 17 "$T/out/c.obj")" = "mtllib shiny.mtl" ] ||
        fail "$name: stdout has no mtllib line first"
    "$tool" "${in[@]}" --mtllib shiny.mtl -o "$T/out/d.ply" >"$T/log" 2>&1
    check [ $? -eq 0 ] || fail "$name --mtllib with PLY output"
    check grep -aq 'shiny' "$T/out/d.ply" && fail "$name: mtllib in a PLY"
    "$tool" "${in[@]}" --mtllib 'two words.mtl' -o "$T/out/e.obj" >"$T/log" 2>&1
    check [ $? -eq 2 ] || fail "$name: a name with a blank is not a usage error"
    check grep -q 'blanks' "$T/log" || fail "$name: message does not say why"
    check [ ! -e "$T/out/e.obj" ] || fail "$name: output written after a usage error"
done
echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
