# Shell helpers shared by the tool tests; source it after setting TOOL (the
# tool under test), PY (python) and T (a scratch directory):
#   . "$(dirname "$0")/testlib.sh"
# It sets failures=0 and checks=0; end the script with testlib_summary.
failures=0
checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
# run ARGS...: the tool's exit status in rc, its outputs in out and err.
run() {
    "$TOOL" "$@" >"$T/stdout" 2>"$T/stderr"
    rc=$?
    out=$(cat "$T/stdout")
    err=$(cat "$T/stderr")
}
expect_rc() { # STATUS WHAT
    checks=$((checks + 1))
    [ "$rc" -eq "$1" ] || fail "$2: exit status $rc, expected $1 (stderr: $err)"
}
expect_err() { # TEXT WHAT: stderr contains TEXT
    checks=$((checks + 1))
    case "$err" in
    *"$1"*) ;;
    *) fail "$2: stderr '$err' does not contain '$1'" ;;
    esac
}
# pycheck WHAT ARGS... <<SCRIPT: run a Python check; it prints "ok".
pycheck() {
    local what=$1
    shift
    checks=$((checks + 1))
    local res
    res=$("$PY" - "$@" 2>&1) || { fail "$what: $res"; return; }
    [ "$res" = "ok" ] || fail "$what: $res"
}
# The degenerate-face report of geom-normals and geom-tangents (one
# cli_mesh_degenerate_faces behind both), after a run:
# expect_degenerate WHAT TEXT: stderr has a warning with TEXT ("2 degenerate
# (zero-area) faces, the first face 1").
expect_degenerate() {
    checks=$((checks + 1))
    case "$err" in
    *"warning"*"$2"*) ;;
    *) fail "$1: stderr '$err' lacks the count and first face" ;;
    esac
}
# expect_degenerate_json WHAT COUNT FIRST: after a --json run, the JSON on
# stdout has degenerate_faces COUNT, first_degenerate_face FIRST (null when
# COUNT is 0) and a warning naming them exactly when COUNT > 0.
expect_degenerate_json() {
    pycheck "$1" "$out" "$2" "$3" <<'PYEOF'
import sys, json
d = json.loads(sys.argv[1])
n, first = int(sys.argv[2]), (None if sys.argv[3] == "null" else int(sys.argv[3]))
assert d["degenerate_faces"] == n and d["first_degenerate_face"] == first, d
if n:
    assert any("degenerate" in w for w in d["warnings"]), d
else:
    assert "warnings" not in d, d
print("ok")
PYEOF
}
testlib_summary() {
    echo "$checks checks, $failures failures"
    [ "$failures" -eq 0 ]
}
