#!/bin/bash
# The hostile-input corpus (tests/data/hostile, see its README) through every
# tool that reads it: each file must give exit status 1 (never 0, never a
# signal), a message on stderr naming the file and containing the words
# EXPECT.tsv lists for it, no output file, and no control byte copied to the
# terminal. Mesh files go through every mesh-reading tool, surface files
# through geom-tessellate; a directory as input is named as one.
# Usage: test_hostile_corpus.sh CORPUS_DIR TOOL...
set -u
C=$1
shift
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-hostile.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
failures=0
checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
expect_of() { awk -F'\t' -v f="$1" '$1 == f { print $2 }' "$C/EXPECT.tsv"; }
for tool in "$@"; do
    name=$(basename "$tool")
    case $name in
    geom-tessellate) files=("$C"/surface/*) ;;
    geom-info | geom-convert | geom-normals | geom-tangents | geom-features | geom-subdivide)
        files=("$C"/mesh/*) ;;
    *) continue ;;
    esac
    for f in "${files[@]}"; do
        rel=${f#"$C"/}
        want=$(expect_of "$rel")
        checks=$((checks + 1))
        [ -n "$want" ] || { fail "$rel: not listed in EXPECT.tsv"; continue; }
        if [ "$name" = geom-info ]; then
            (cd "$C" && "$tool" "$rel" >"$T/out" 2>"$T/err"); rc=$?
        else
            (cd "$C" && "$tool" "$rel" -o "$T/out.obj" >/dev/null 2>"$T/err"); rc=$?
        fi
        [ $rc -eq 1 ] || fail "$name $rel: exit status $rc, expected 1 ($(head -c 200 "$T/err"))"
        grep -qF -- "$rel" "$T/err" || fail "$name $rel: the message does not name the file: $(head -c 200 "$T/err")"
        grep -qF -- "$want" "$T/err" || fail "$name $rel: expected '$want' in: $(head -c 300 "$T/err")"
        if LC_ALL=C grep -q '[[:cntrl:]]' <(tr -d '\n' <"$T/err"); then
            fail "$name $rel: a control byte reached stderr"
        fi
        [ ! -e "$T/out.obj" ] || fail "$name $rel: an output file was written"
        rm -f "$T/out.obj"
    done
done
# A directory given as the input says so.
mkdir "$T/adir"
for tool in "$@"; do
    checks=$((checks + 1))
    "$tool" "$T/adir" -o "$T/out.obj" >/dev/null 2>"$T/err"; rc=$?
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
