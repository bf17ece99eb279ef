#!/bin/bash
# Every tool's error paths, swept: each long option that takes a value gets
# bad values (empty, a word, negative, NaN, huge, zero), on top of a command
# that works; and each tool gets a missing file, a directory, an empty file
# and garbage as input. Whatever fails must say why: never "invalid
# argument: ok" or any message ending in ": ok" (a status string printed for
# a GEOM_OK status, or an empty diagnostic), never an empty message, never a
# hint naming a library field (an options struct member such as
# "skip_invalid_faces" or "opts.max_depth") instead of the tool's option;
# and a run that prints "error"-like text must not exit 0 silently.
# Usage: test_messages.sh DATA_DIR TOOL_DIR
set -u
D=$1
B=$2
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-messages.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
cd "$T" || exit 1
failures=0
runs=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

printf '0 0 0  1 0 0  0 1 0  0.2 0.2 0\n' > q.txt
printf '0 0 5 0 0 -1\n' > rays.txt
printf '0 0 0\n1 0 0\n0 1 0\n' > pts.txt
: > empty.obj
head -c 600 /dev/urandom > garbage.obj 2>/dev/null || printf '\x01\x02garbage\xff' > garbage.obj
mkdir -p adir
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n' > twocorners.obj

# A working command per tool (OUT is replaced by an output path).
base_of() {
    case $1 in
    geom-bary) echo "$D/bary_points.txt" ;;
    geom-clip) echo "--plane 0,0,1,-0.1 $D/tetra.off -o OUT.obj" ;;
    geom-contour) echo "--expr x^2+y^2-1 --bounds -2,-2,2,2 --res 16 -o OUT.svg" ;;
    geom-convert) echo "$D/tetra.off OUT.ply" ;;
    geom-curve) echo "$D/surfaces.json --tol 1e-2 -o OUT.obj" ;;
    geom-features) echo "--crease 40 $D/tetra.off -o OUT.obj" ;;
    geom-info) echo "$D/tetra.off" ;;
    geom-iso) echo "--expr torus(1,0.3) --bounds -2,-2,-1,2,2,1 --res 12 -o OUT.obj" ;;
    geom-normals) echo "$D/tetra.off -o OUT.obj" ;;
    geom-query) echo "pts.txt --knn 2 --queries pts.txt" ;;
    geom-raycast) echo "$D/scenes/spheres.json --rays rays.txt --closest" ;;
    geom-render) echo "$D/scenes/spheres.json --width 8 --height 8 -o OUT.pfm" ;;
    geom-scene) echo "$D/scenes/spheres.json --export OUT.obj" ;;
    geom-subdivide) echo "--levels 1 $D/tetra.off -o OUT.obj" ;;
    geom-tangents) echo "$D/cube_seams.obj -o OUT.glb" ;;
    geom-tessellate) echo "$D/teapot.bpt --tol 1e-1 -o OUT.obj" ;;
    *) echo "" ;;
    esac
}

check_run() { # tool, label, args...
    local tool=$1 label=$2
    shift 2
    runs=$((runs + 1))
    timeout 5 "$tool" "$@" > out.txt 2> err.txt < /dev/null
    local rc=$?
    local name
    name=$(basename "$tool")
    [ -n "${GEOM_MESSAGES_LOG:-}" ] && sed "s|^|$name $label [$rc]: |" err.txt >> "$GEOM_MESSAGES_LOG"
    if grep -Eq '(: ok$|: ok[^a-z_]|invalid argument: ok)' err.txt out.txt; then
        fail "$name $label: a status string for GEOM_OK: $(grep -E ': ok' err.txt out.txt | head -1)"
    fi
    if [ $rc -ne 0 ] && [ $rc -lt 124 ] && ! grep -q '[A-Za-z]' err.txt; then
        fail "$name $label: exit $rc with no message"
    fi
    if grep -Eq "^$name: *$|: $" err.txt; then
        fail "$name $label: an empty message: $(head -1 err.txt)"
    fi
    if grep -Eq '(\bopts?\.[a-z_]+|\boptions\.[a-z_]+|_options\b|skip_invalid_faces|\bset [a-z]+_[a-z_]+ to)' err.txt; then
        fail "$name $label: a hint names a library field: $(head -1 err.txt)"
    fi
    [ $rc -eq 124 ] && echo "note: $name $label: timed out" >&2
    if [ $rc -gt 124 ]; then
        fail "$name $label: killed by a signal (exit $rc)"
    fi
}

for tool in "$B"/geom-*; do
    [ -x "$tool" ] || continue
    name=$(basename "$tool")
    base=$(base_of "$name")
    [ -n "$base" ] || { echo "note: no base command for $name" >&2; continue; }
    # shellcheck disable=SC2086
    set -- $(echo "$base" | sed "s|OUT|$T/out|g")
    check_run "$tool" "base" "$@"
    [ -s err.txt ] && grep -qi "error\|failed" err.txt && [ "$(cat err.txt | wc -l)" -gt 0 ] &&
        echo "note: $name base: $(head -1 err.txt)" >&2
    # the inputs
    for bad in missing.obj adir empty.obj garbage.obj twocorners.obj; do
        check_run "$tool" "input $bad" "$bad" -o "$T/out.obj"
    done
    # every long option that takes a value, with bad values
    opts=$("$tool" --help 2>&1 | grep -oE -- '--[a-z][a-z0-9-]*[= ][A-Z]' | sed -E 's/[= ][A-Z]$//' | sort -u)
    for o in $opts; do
        case $o in --output|--json) continue ;; esac
        for v in "" "x" "-1" "nan" "0" "1e-300"; do
            check_run "$tool" "$o=$v" "$@" "$o=$v"
        done
    done
done
echo "$runs runs, $failures failures"
[ $failures -eq 0 ]
