#!/bin/bash
# Tests of geom-bary: known answers (exact values from closed forms), exact
# rational references computed by Python's fractions, degenerate triangles,
# --json, malformed input (exit 1, FILE:LINE:COL), usage errors (exit 2),
# --help/--version, standard input, -o with its no-partial-output guarantee,
# CRLF, NUL bytes, long lines and write errors.
# Usage: test_geom_bary.sh /path/to/geom-bary VERSION   (env PYTHON3: python)
set -u
if [ $# -ne 2 ]; then
    echo "usage: $0 TOOL VERSION" >&2
    exit 2
fi
TOOL=$1
VERSION=$2
PY=${PYTHON3:-/usr/bin/python3}
if [ ! -x "$TOOL" ]; then
    echo "FAIL: $TOOL is not an executable" >&2
    exit 1
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-bary-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

failures=0
checks=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
check() { # check CONDITION-DESCRIPTION then test args
    local what=$1
    shift
    checks=$((checks + 1))
    "$@" || fail "$what"
}

# run ARGS...: run the tool; sets rc, out (stdout) and err (stderr).
run() {
    "$TOOL" "$@" >"$T/stdout" 2>"$T/stderr"
    rc=$?
    out=$(cat "$T/stdout")
    err=$(cat "$T/stderr")
}
# run_stdin TEXT ARGS...: as run, with TEXT (printf %b escapes) on stdin.
run_stdin() {
    local text=$1
    shift
    printf '%b' "$text" | "$TOOL" "$@" >"$T/stdout" 2>"$T/stderr"
    rc=$?
    out=$(cat "$T/stdout")
    err=$(cat "$T/stderr")
}
# input TEXT: write TEXT (printf %b escapes) to $T/in.
input() { printf '%b' "$1" >"$T/in"; }

expect_rc() {
    checks=$((checks + 1))
    [ "$rc" -eq "$1" ] || fail "$2: exit status $rc, expected $1 (stderr: $err)"
}
expect_out() {
    checks=$((checks + 1))
    [ "$out" = "$1" ] || fail "$2: stdout '$out', expected '$1'"
}
expect_err() {
    checks=$((checks + 1))
    [ "$err" = "$1" ] || fail "$2: stderr '$err', expected '$1'"
}
expect_err_match() { # glob pattern
    checks=$((checks + 1))
    # shellcheck disable=SC2053
    [[ $err == $1 ]] || fail "$2: stderr '$err' does not match '$1'"
}

# known INPUT-LINE EXPECTED-OUTPUT DESCRIPTION
known() {
    input "$1\n"
    run "$T/in"
    expect_rc 0 "$3"
    expect_out "$2" "$3"
    expect_err "" "$3 (stderr)"
}

# ---------------------------------------------------------------- known answers
# 2D triangle a=(0,0) b=(1,0) c=(0,1): l = (1-x-y, x, y).
known "0 0 1 0 0 1 0 0" "1 0 0" "2D vertex a"
known "0 0 1 0 0 1 1 0" "0 1 0" "2D vertex b"
known "0 0 1 0 0 1 0 1" "0 0 1" "2D vertex c"
known "0 0 1 0 0 1 0.5 0" "0.5 0.5 0" "2D midpoint of ab"
known "0 0 1 0 0 1 0.5 0.5" "0 0.5 0.5" "2D midpoint of bc"
known "0 0 1 0 0 1 0.25 0.25" "0.5 0.25 0.25" "2D interior point"
known "0 0 1 0 0 1 -1 0" "2 -1 0" "2D point outside"
known "0 0 1 0 0 1 2 3" "-4 2 3" "2D point far outside"
# Clockwise triangle a=(0,0) b=(0,1) c=(1,0): l = (1-x-y, y, x). On edge ac the
# b coordinate is 0/negative = -0, printed as 0.
known "0 0 0 1 1 0 0.25 0.5" "0.25 0.5 0.25" "2D clockwise triangle"
known "0 0 0 1 1 0 0.5 0" "0.5 0 0.5" "2D clockwise, point on an edge (no -0)"
# The same triangle translated far from the origin (all values exact doubles):
# the answer must not change.
known "100000000 100000000 100000001 100000000 100000000 100000001 100000000.25 100000000.25" \
    "0.5 0.25 0.25" "2D triangle far from the origin"
# Centroid: each coordinate is 1/3 rounded once, printed with 17 digits.
third=$("$PY" -c 'print(" ".join(["%.17g" % (1 / 3)] * 3))')
known "0 0 3 0 0 3 1 1" "$third" "2D centroid (1/3 correctly rounded)"
# 3D: triangle in the z=0 plane, p lifted off the plane (projected).
known "0 0 0 2 0 0 0 2 0 0.5 0.5 7" "0.5 0.25 0.25" "3D point above the plane"
known "0 0 0 2 0 0 0 2 0 0 0 -3" "1 0 0" "3D vertex a projected"
# A tilted triangle a=(1,2,3) b=(4,-1,2) c=(0,5,-2).
known "1 2 3 4 -1 2 0 5 -2 4 -1 2" "0 1 0" "3D vertex b"
known "1 2 3 4 -1 2 0 5 -2 2 2 0" "0 0.5 0.5" "3D midpoint of bc"
known "1 2 3 4 -1 2 0 5 -2 0.5 3.5 0.5" "0.5 0 0.5" "3D midpoint of ca"
# Separators: commas with or without spaces, tabs, leading/trailing blanks.
known "0,0,1,0,0,1,0.25,0.25" "0.5 0.25 0.25" "comma separated"
known "  0, 0 ,1,\t0 , 0,1, 0.25 ,0.25  " "0.5 0.25 0.25" "mixed separators"
# Number syntax strtod accepts: exponents, signs, hex floats, long tokens.
known "0e0 -0 1e0 +0 0 0.1e1 0x1p-2 2.5e-1" "0.5 0.25 0.25" "number syntax"
long_quarter="0.25$(printf '0%.0s' $(seq 1 300))"
known "0 0 1 0 0 1 $long_quarter 0.25" "0.5 0.25 0.25" "300-digit number"
pad=$(printf '%200000s' '')
known "0${pad}0 1 0 0 1 0.25 0.25" "0.5 0.25 0.25" "200000-character line"

# ---------------------------------------------------------------- degenerate
known "0 0 1 1 2 2 0.5 0.5" "degenerate" "2D collinear triangle"
known "1 1 1 1 1 1 0 0" "degenerate" "2D triangle collapsed to a point"
known "0 0 0 1 1 1 2 2 2 0 0 1" "degenerate" "3D collinear triangle"

# -------------------------------------------- exact references (Python fractions)
# Coordinates must agree with the exact rational answer within 3 ulp each (the
# bary.h contract), through parsing, computing and 17-digit printing.
cat >"$T/ref.py" <<'PYEOF'
import sys, math
from fractions import Fraction as F
lines = [
    "0.1 0.2 0.7 0.3 0.4 0.9 0.3 0.45",
    "-3.25 1e-3 7 2.5 1.5 -9 0.1 0.3",
    "1e-8 0 1 1e-8 0 1.0000001 0.5 0.5",
    "123456.789 -98765.4321 123457.789 -98765.4321 123456.789 -98764.4321 123457 -98765",
    "0.1 0.2 0.3 1.7 -0.4 0.25 -0.6 2.2 1.1 0.3 0.3 0.3",
    "1e6 1e6 1e6 1000001 1e6 1e6 1e6 1000001 1e6 1e6 1e6 1000001",
    "5 5 5 6 5.5 5 5.5 7 5.25 5.6 5.9 100",
]
def ref(v):
    v = [F(x) for x in v]
    if len(v) == 8:
        a, b, c, p = v[0:2], v[2:4], v[4:6], v[6:8]
        def o(a, b, c):
            return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        d = o(a, b, c)
        return [o(p, b, c) / d, o(a, p, c) / d, o(a, b, p) / d]
    a, b, c, p = v[0:3], v[3:6], v[6:9], v[9:12]
    sub = lambda u, w: [u[i] - w[i] for i in range(3)]
    cross = lambda u, w: [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                          u[0] * w[1] - u[1] * w[0]]
    dot = lambda u, w: sum(u[i] * w[i] for i in range(3))
    n = cross(sub(b, a), sub(c, a))
    nn = dot(n, n)
    return [dot(n, cross(sub(b, p), sub(c, p))) / nn,
            dot(n, cross(sub(p, a), sub(c, a))) / nn,
            dot(n, cross(sub(b, a), sub(p, a))) / nn]
if sys.argv[1] == "input":
    print("\n".join(lines))
    sys.exit(0)
got = open(sys.argv[2]).read().split("\n")[:-1]
assert len(got) == len(lines), (len(got), len(lines))
bad = 0
for line, g in zip(lines, got):
    r = ref([float(x) for x in line.split()])
    toks = g.split()
    assert len(toks) == 3, g
    for t, e in zip(toks, r):
        x = float(t)
        if F(x) == e:
            continue
        tol = 3 * math.ulp(float(e))
        if abs(F(x) - e) > F(tol):
            print("line %r: got %s, exact %r (%.17g)" % (line, t, e, float(e)))
            bad = 1
sys.exit(bad)
PYEOF
"$PY" "$T/ref.py" input >"$T/refin"
run "$T/refin"
expect_rc 0 "exact references"
check "exact references within 3 ulp" "$PY" "$T/ref.py" check "$T/stdout"

# ---------------------------------------------- comments, blank lines, line ends
input "# a comment\n\n   \n  # indented comment\n0 0 1 0 0 1 0.25 0.25\n\t\n0 0 2 0 0 2 1 0\n"
run "$T/in"
expect_rc 0 "comments and blank lines"
expect_out "$(printf '0.5 0.25 0.25\n0.5 0.5 0')" "comments and blank lines"
# CRLF line ends, and no newline after the last line.
input "# crlf\r\n0 0 1 0 0 1 0.25 0.25\r\n\r\n0 0 2 0 0 2 1 0\r\n0 0 1 0 0 1 0 1"
run "$T/in"
expect_rc 0 "CRLF input"
expect_out "$(printf '0.5 0.25 0.25\n0.5 0.5 0\n0 0 1')" "CRLF input"
input "0 0 1 0 0 1 0.25 0.25\r\n\r\n0 0 1 0 x 1 0.25 0.25\r\n"
run "$T/in"
expect_rc 1 "CRLF input with a bad number"
expect_err "geom-bary: $T/in:3:9: invalid number 'x'" "CRLF input with a bad number"
input "0 0 1 0 0 1 0.25 0.25"
run "$T/in"
expect_out "0.5 0.25 0.25" "no final newline"
input ""
run "$T/in"
expect_rc 0 "empty input"
expect_out "" "empty input"

# ---------------------------------------------------------------------- --json
input "# header\n0 0 1 0 0 1 0 0\n\n0 0 1 1 2 2 0 0\n0 0 3 0 0 3 1 1\n0 0 0 2 0 0 0 2 0 0.5 0.5 7\n"
run --json "$T/in"
expect_rc 0 "--json"
cat >"$T/check_json.py" <<'PYEOF'
import json, sys
lines = open(sys.argv[1]).read().split("\n")
assert lines[-1] == "", "output must end with a newline"
objs = [json.loads(s) for s in lines[:-1]]
want = [
    {"line": 2, "status": "ok", "l": [1, 0, 0]},
    {"line": 4, "status": "degenerate"},
    {"line": 5, "status": "ok", "l": [1 / 3, 1 / 3, 1 / 3]},
    {"line": 6, "status": "ok", "l": [0.5, 0.25, 0.25]},
]
assert objs == want, objs
PYEOF
check "--json output parses and has the expected objects" "$PY" "$T/check_json.py" "$T/stdout"

# ---------------------------------------------------------------- malformed input
input "0 0 1 0 0 1 0 0\n# c\n1 2 3 4 5 6 7\n0 0 1 0 0 1 0 0\n"
run "$T/in"
expect_rc 1 "7 numbers"
expect_err "geom-bary: $T/in:3:14: expected 8 (2D) or 12 (3D) numbers, found 7" "7 numbers"
# Streaming: the result of line 1 was written before the error, nothing after.
expect_out "1 0 0" "output before the error is kept on stdout"
input "0 0 1 0 0 1 0 0 1 1\n"
run "$T/in"
expect_rc 1 "10 numbers"
expect_err "geom-bary: $T/in:1:20: expected 8 (2D) or 12 (3D) numbers, found 10" "10 numbers"
input "1 2 3 4 5 6 7 8 9 10 11 12 13\n"
run "$T/in"
expect_rc 1 "13 numbers"
expect_err "geom-bary: $T/in:1:28: too many numbers (expected at most 12)" "13 numbers"
input "\n0 0 1 0 0 x 0.25 0.25\n"
run "$T/in"
expect_rc 1 "bad number"
expect_err "geom-bary: $T/in:2:11: invalid number 'x'" "bad number"
input "0 0 1 0 0 1 0.25 0.25.5\n"
run "$T/in"
expect_rc 1 "trailing garbage in a number"
expect_err "geom-bary: $T/in:1:18: invalid number '0.25.5'" "trailing garbage"
input "0 0 1 0 0 1 nan 0.25\n"
run "$T/in"
expect_rc 1 "NaN"
expect_err "geom-bary: $T/in:1:13: NaN not allowed 'nan'" "NaN"
input "0 0 1 0 0 1 0.25 -inf\n"
run "$T/in"
expect_rc 1 "infinity"
expect_err "geom-bary: $T/in:1:18: infinity not allowed '-inf'" "infinity"
input "0 0 1e999 0 0 1 0.25 0.25\n"
run "$T/in"
expect_rc 1 "overflowing number"
expect_err "geom-bary: $T/in:1:5: number out of range '1e999'" "overflowing number"
input "0 0 1 0,,0 1 0.25 0.25\n"
run "$T/in"
expect_rc 1 "empty field"
expect_err "geom-bary: $T/in:1:9: empty field between commas" "empty field"
input "0 0 1 0 0 1 0.25 0.25,\n"
run "$T/in"
expect_rc 1 "trailing comma"
expect_err "geom-bary: $T/in:1:22: trailing comma after the last number" "trailing comma"
input "0 0 1 0 0 1 0.25 0.25\n0 0\00001 0 0 1 0.25 0.25\n"
run "$T/in"
expect_rc 1 "NUL byte"
expect_err "geom-bary: $T/in:2:4: NUL byte in input" "NUL byte"
input "0 0 1 0 0 1 0.25 0.25 # trailing comment\n"
run "$T/in"
expect_rc 1 "trailing comment is not a number"
expect_err_match "geom-bary: $T/in:1:23: *" "trailing comment"
run "$T/does-not-exist"
expect_rc 1 "missing input file"
expect_err "geom-bary: $T/does-not-exist: No such file or directory" "missing input file"
run "$T"
expect_rc 1 "directory as input"
expect_err_match "geom-bary: $T: is a directory, not a file*" "directory as input"

# ------------------------------------------------------------------ usage errors
run --bogus
expect_rc 2 "unknown option"
expect_out "" "unknown option (stdout)"
expect_err_match "geom-bary: *'--bogus'*Try 'geom-bary --help' for more information." "unknown option"
run -x
expect_rc 2 "unknown short option"
input "0 0 1 0 0 1 0 0\n"
run "$T/in" "$T/in"
expect_rc 2 "two operands"
expect_err_match "geom-bary: extra operand '$T/in'*Try 'geom-bary --help'*" "two operands"
run "$T/in" -o
expect_rc 2 "-o without an argument"
run --json=yes "$T/in"
expect_rc 2 "--json with an argument"
run -o "" "$T/in"
expect_rc 2 "empty output name"

# ------------------------------------------------------------- --help, --version
run --help
expect_rc 0 "--help"
expect_err "" "--help (stderr)"
check "--help starts with the usage line" [ "${out%%$'\n'*}" = "Usage: geom-bary [OPTION]... [FILE]" ]
run --version
expect_rc 0 "--version"
expect_out "geom-bary (libgeom) $VERSION" "--version"
run "$T/in" --help
expect_rc 0 "--help after an operand"

# ------------------------------------------------------------------ standard input
run_stdin "0 0 1 0 0 1 0.25 0.25\n" -
expect_rc 0 "stdin with -"
expect_out "0.5 0.25 0.25" "stdin with -"
run_stdin "0 0 1 0 0 1 0.25 0.25\n"
expect_out "0.5 0.25 0.25" "stdin without an operand"
run_stdin "0 0 1 0 0 1 0 0\n0 0 1 0 0 1 0 y\n" --json -
expect_rc 1 "stdin with an error"
expect_err "geom-bary: <stdin>:2:15: invalid number 'y'" "stdin with an error"
expect_out '{"line":1,"status":"ok","l":[1,0,0]}' "stdin --json output before the error"

# ------------------------------------------------------------------------- -o
input "0 0 1 0 0 1 0.25 0.25\n0 0 1 1 2 2 0 0\n"
mkdir "$T/o"
run "$T/in"
expected=$out
run -o "$T/o/res.txt" "$T/in"
expect_rc 0 "-o FILE"
expect_out "" "-o FILE (nothing on stdout)"
check "-o FILE has the results" [ "$(cat "$T/o/res.txt")" = "$expected" ]
check "-o FILE leaves no temporary file" [ "$(ls -A "$T/o")" = "res.txt" ]
(umask 027 && "$TOOL" -o "$T/o/mode.txt" "$T/in")
check "-o FILE gets mode 0666 less the umask" [ "$(stat -c %a "$T/o/mode.txt")" = "640" ]
chmod 604 "$T/o/mode.txt"
"$TOOL" --output="$T/o/mode.txt" "$T/in"
check "-o keeps the mode of the file it replaces" [ "$(stat -c %a "$T/o/mode.txt")" = "604" ]
rm -f "$T/o/mode.txt"
run -o - "$T/in"
expect_out "$expected" "-o - writes to stdout"
run --json -o "$T/o/res.json" "$T/in"
check "--json -o FILE" "$PY" -c 'import json,sys; [json.loads(l) for l in open(sys.argv[1])]' "$T/o/res.json"
rm -f "$T/o/res.json"
# A failing run creates no file, leaves no temporary file, and does not
# touch an existing file.
input "0 0 1 0 0 1 0.25 0.25\n0 0 1 0 0 1 bad 0\n"
mkdir "$T/fail"
run -o "$T/fail/res.txt" "$T/in"
expect_rc 1 "failing run with -o"
expect_err "geom-bary: $T/in:2:13: invalid number 'bad'" "failing run with -o"
check "failing run with -o creates no file" [ ! -e "$T/fail/res.txt" ]
check "failing run with -o leaves no temporary file" [ -z "$(ls -A "$T/fail")" ]
run -o "$T/o/res.txt" "$T/in"
expect_rc 1 "failing run over an existing file"
check "failing run keeps the existing file" [ "$(cat "$T/o/res.txt")" = "$expected" ]
check "failing run over an existing file leaves no temporary file" [ "$(ls -A "$T/o")" = "res.txt" ]
run -o "$T/no/such/dir/res.txt" "$T/in"
expect_rc 1 "-o into a missing directory"
expect_err_match "geom-bary: $T/no/such/dir/res.txt: cannot create output file: *" "-o into a missing directory"
run -o "$T/o" "$T/in"
expect_rc 1 "-o onto a directory"
expect_err "geom-bary: $T/o: is a directory" "-o onto a directory"
# Write errors are detected (exit 1), not silently lost.
if [ -w /dev/full ]; then
    input "0 0 1 0 0 1 0.25 0.25\n"
    "$TOOL" "$T/in" >/dev/full 2>"$T/stderr"
    rc=$?
    err=$(cat "$T/stderr")
    expect_rc 1 "write to /dev/full"
    expect_err_match "geom-bary: <stdout>: write error: *" "write to /dev/full"
fi

if [ $failures -ne 0 ]; then
    echo "$failures of $checks checks failed" >&2
    exit 1
fi
echo "all $checks checks passed"
