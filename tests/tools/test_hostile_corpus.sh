#!/bin/bash
# The hostile-input corpus (tests/data/hostile, see its README) through every
# tool that reads it: each file must give exit status 1 (never 0, never a
# signal), a message on stderr naming the file and containing the words
# EXPECT.tsv lists for it, no output file, and no control byte copied to the
# terminal. Mesh files (OBJ, OFF, PLY, STL, GLB) go through every mesh-reading
# tool, surface and STEP files through geom-tessellate, volumes through
# geom-iso --volume, scene files through geom-render, geom-scene and
# geom-raycast (render_* files only through the first two: geom-raycast
# ignores the rendering keys), point files through geom-query (as the points
# and as the queries) and ray files through geom-raycast --rays; a directory
# as input is named as one.
# Usage: test_hostile_corpus.sh CORPUS_DIR TOOL...
set -u
C=$1
shift
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-hostile.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/testlib.sh" # failures, checks, fail
expect_of() { awk -F'\t' -v f="$1" '$1 == f { print $2 }' "$C/EXPECT.tsv"; }
SCENE="$C/../../../data/scenes/spheres.json"
TETRA="$C/../../../data/tetra.off"
# check NAME REL CMD...: run CMD (in the corpus directory, stdin empty) and
# check its exit status, message and output as described above.
check() {
    local name=$1 rel=$2 want rc
    shift 2
    want=$(expect_of "$rel")
    checks=$((checks + 1))
    [ -n "$want" ] || { fail "$rel: not listed in EXPECT.tsv"; return; }
    (cd "$C" && timeout 60 "$@" </dev/null >"$T/out" 2>"$T/err"); rc=$?
    [ $rc -eq 1 ] || fail "$name $rel: exit status $rc, expected 1 ($(head -c 200 "$T/err"))"
    grep -qF -- "$rel" "$T/err" || fail "$name $rel: the message does not name the file: $(head -c 200 "$T/err")"
    grep -qF -- "$want" "$T/err" || fail "$name $rel: expected '$want' in: $(head -c 300 "$T/err")"
    if LC_ALL=C grep -q '[[:cntrl:]]' <(tr -d '\n' <"$T/err"); then
        fail "$name $rel: a control byte reached stderr"
    fi
    for o in "$T"/out.*; do
        [ ! -e "$o" ] || fail "$name $rel: an output file was written ($(basename "$o"))"
    done
    rm -f "$T"/out.*
}
for tool in "$@"; do
    name=$(basename "$tool")
    case $name in
    geom-info)
        for f in "$C"/mesh/*; do check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}"; done ;;
    geom-convert | geom-normals | geom-tangents | geom-features | geom-subdivide)
        for f in "$C"/mesh/*; do
            check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}" -o "$T/out.obj"
        done ;;
    geom-tessellate)
        for f in "$C"/surface/* "$C"/step/*; do
            check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}" -o "$T/out.obj"
        done ;;
    geom-iso)
        for f in "$C"/volume/*; do
            check "$name" "${f#"$C"/}" "$tool" --volume "${f#"$C"/}" --iso 0.5 -o "$T/out.obj"
        done ;;
    geom-render)
        for f in "$C"/scene/*; do
            check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}" -o "$T/out.png"
        done ;;
    geom-scene)
        for f in "$C"/scene/*; do
            check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}" --export "$T/out.glb"
        done ;;
    geom-raycast)
        for f in "$C"/scene/*; do
            case $f in */render_*) continue ;; esac
            check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}" -o "$T/out.txt"
        done
        for f in "$C"/rays/*; do
            check "$name" "${f#"$C"/}" "$tool" "$SCENE" --rays "${f#"$C"/}" -o "$T/out.txt"
        done ;;
    geom-query)
        for f in "$C"/points/*; do
            check "$name" "${f#"$C"/}" "$tool" "${f#"$C"/}" --knn 1 -o "$T/out.txt"
            check "$name --queries" "${f#"$C"/}" "$tool" "$TETRA" --knn 1 --queries "${f#"$C"/}" \
                -o "$T/out.txt"
        done ;;
    esac
done
# A directory given as the input says so.
mkdir "$T/adir"
for tool in "$@"; do
    checks=$((checks + 1))
    case $(basename "$tool") in
    geom-iso) "$tool" --volume "$T/adir" -o "$T/out.obj" </dev/null >/dev/null 2>"$T/err"; rc=$? ;;
    geom-scene) "$tool" "$T/adir" --export "$T/out.obj" </dev/null >/dev/null 2>"$T/err"; rc=$? ;;
    geom-query) "$tool" "$T/adir" --knn 1 </dev/null >/dev/null 2>"$T/err"; rc=$? ;;
    geom-render) "$tool" "$T/adir" -o "$T/out.png" </dev/null >/dev/null 2>"$T/err"; rc=$? ;;
    *) "$tool" "$T/adir" -o "$T/out.obj" </dev/null >/dev/null 2>"$T/err"; rc=$? ;;
    esac
    [ $rc -eq 1 ] && grep -q "is a directory" "$T/err" ||
        fail "$(basename "$tool") DIR: exit $rc, expected 1 and 'is a directory': $(head -c 200 "$T/err")"
done
# A tool that cannot write what was asked says so: tangents into OBJ.
for tool in "$@"; do
    [ "$(basename "$tool")" = geom-tangents ] || continue
    checks=$((checks + 1))
    "$tool" "$C/../../../data/cube_seams.obj" -o "$T/t.obj" >/dev/null 2>"$T/err"; rc=$?
    [ $rc -eq 0 ] && grep -q 'cannot hold the mesh.s "tangent" attribute' "$T/err" ||
        fail "geom-tangents to OBJ: exit $rc, no warning about the tangents: $(head -c 200 "$T/err")"
done
# Output limits: geom-subdivide estimates before the work (the cube's 3
# Catmull-Clark levels make exactly 768 triangles' worth of quads).
for tool in "$@"; do
    [ "$(basename "$tool")" = geom-subdivide ] || continue
    cube="$C/../../../data/cube_seams.obj"
    checks=$((checks + 3))
    "$tool" "$cube" --levels 12 -o "$T/s.obj" >/dev/null 2>"$T/err"; rc=$?
    [ $rc -eq 1 ] && grep -q "estimate" "$T/err" && [ ! -e "$T/s.obj" ] ||
        fail "geom-subdivide --levels 12: exit $rc, expected 1 with the estimate: $(head -c 200 "$T/err")"
    "$tool" "$cube" --levels 3 --max-triangles 767 -o "$T/s.obj" >/dev/null 2>"$T/err"; rc=$?
    [ $rc -eq 1 ] || fail "geom-subdivide --max-triangles 767: exit $rc, expected 1"
    "$tool" "$cube" --levels 3 --max-triangles 768 -o "$T/s.obj" >/dev/null 2>"$T/err"; rc=$?
    [ $rc -eq 0 ] || fail "geom-subdivide --max-triangles 768: exit $rc, expected 0: $(head -c 200 "$T/err")"
    rm -f "$T/s.obj"
done
echo "$checks checks, $failures failures"
[ "$failures" -eq 0 ]
