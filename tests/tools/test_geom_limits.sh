#!/bin/bash
# Output limits of geom-tessellate and geom-iso: an output estimated past
# --max-triangles stops before the work (exit 1, the estimate in the
# message, no output file); the estimate is checked against the count the
# run then makes (within a factor 1.5 either way); bad limit values are
# usage errors; --quiet is accepted.
# Usage: test_geom_limits.sh GEOM_TESSELLATE GEOM_ISO TEAPOT_BPT
set -u
TESS=$1 ISO=$2 TEAPOT=$3
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-limits-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
failures=0 checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
check() { checks=$((checks + 1)); }

# estimate vs made: the estimate is printed when the limit is 1
estimate_vs_made() { # WHAT TOOL ARGS...
    local what=$1 tool=$2
    shift 2
    check
    "$tool" "$@" --max-triangles 1 -o "$T/o.obj" 2>"$T/err"
    local rc=$?
    [ $rc -eq 1 ] || { fail "$what: exit $rc with --max-triangles 1"; return; }
    [ ! -e "$T/o.obj" ] || fail "$what: output written although stopped"
    local est
    est=$(sed -n 's/.*about \([0-9]*\) triangles (estimate).*/\1/p' "$T/err")
    [ -n "$est" ] || { fail "$what: no estimate in '$(cat "$T/err")'"; return; }
    "$tool" "$@" --json --quiet -o "$T/o.obj" >"$T/j" 2>"$T/err" || { fail "$what: $(cat "$T/err")"; return; }
    "$PY" -c "
import json, sys
made = json.load(open('$T/j'))['triangles']
est = $est
if not (made / 1.5 <= est <= made * 1.5):
    sys.exit('estimate %d, made %d' % (est, made))
" || fail "$what: estimate off"
    rm -f "$T/o.obj"
}
estimate_vs_made "teapot --tol 1e-2" "$TESS" --tol 1e-2 "$TEAPOT"
estimate_vs_made "teapot --tol 1e-3" "$TESS" --tol 1e-3 "$TEAPOT"
estimate_vs_made "teapot --grid 7,5" "$TESS" --grid 7,5 "$TEAPOT"
estimate_vs_made "sphere res 60" "$ISO" --expr "sphere(1)" --bounds -2,-2,-2,2,2,2 --res 60
estimate_vs_made "torus res 90" "$ISO" --expr "torus(1, 0.3)" --bounds -2,-2,-2,2,2,2 --res 90,80,70

# the issue's case: --tol 1e-5 on the teapot (10M triangles, 2.3 GB) stops
# before the work at a 1M limit (the estimate's message, no file), and a
# 5000^3 isosurface at the default
check
"$TESS" --tol 1e-5 "$TEAPOT" --max-triangles 1M -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "triangles (estimate), more than --max-triangles 1000000" "$T/err" &&
    [ ! -e "$T/o.obj" ] || fail "teapot 1e-5: exit $rc: $(cat "$T/err")"
check
"$ISO" --expr "sphere(1)" --bounds -2,-2,-2,2,2,2 --res 5000 -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "max-triangles 50000000" "$T/err" || fail "iso res 5000: exit $rc: $(cat "$T/err")"
check
"$ISO" --expr "sphere(1)" --bounds -2,-2,-2,2,2,2 --res 100 --max-memory 1K -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "max-memory" "$T/err" || fail "iso --max-memory 1K: exit $rc: $(cat "$T/err")"

# bad values are usage errors
for bad in 0 -5 abc 1X ""; do
    check
    "$TESS" --tol 1e-2 "$TEAPOT" --max-triangles "$bad" -o "$T/o.obj" 2>/dev/null; rc=$?
    [ $rc -eq 2 ] || fail "--max-triangles '$bad': exit $rc"
done
check
"$ISO" --expr "sphere(1)" --bounds -2,-2,-2,2,2,2 --res 10 --max-memory 2Q -o "$T/o.obj" 2>/dev/null
[ $? -eq 2 ] || fail "--max-memory 2Q accepted"

if [ "$failures" -ne 0 ]; then
    echo "$failures of $checks checks failed" >&2
    exit 1
fi
echo "all $checks checks passed"
