#!/bin/bash
# Every built geom-* tool shares the cli layer: --help prints a usage on
# stdout and exits 0, --version prints "geom-<verb> (libgeom) VERSION" and
# exits 0, an unknown option exits 2 with a hint on stderr.
# Usage: test_tools_dispatch.sh VERSION TOOL...
set -u
if [ $# -lt 2 ]; then
    echo "usage: $0 VERSION TOOL..." >&2
    exit 2
fi
version=$1
shift
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

for tool in "$@"; do
    name=$(basename "$tool")
    case $name in
    geom-*) ;;
    *) fail "$tool: tool names must start with geom-" ;;
    esac
    [ -x "$tool" ] || { fail "$tool: not an executable"; continue; }

    out=$("$tool" --help 2>/dev/null); rc=$?
    [ $rc -eq 0 ] || fail "$name --help: exit $rc"
    case $out in
    "Usage: $name "*) ;;
    *) fail "$name --help: output does not start with 'Usage: $name'" ;;
    esac
    case $out in
    *--version*) ;;
    *) fail "$name --help: does not document --version" ;;
    esac
    out=$("$tool" -h 2>/dev/null); rc=$?
    [ $rc -eq 0 ] || fail "$name -h: exit $rc"

    out=$("$tool" --version 2>/dev/null); rc=$?
    [ $rc -eq 0 ] || fail "$name --version: exit $rc"
    [ "$out" = "$name (libgeom) $version" ] ||
        fail "$name --version: got '$out', expected '$name (libgeom) $version'"

    err=$("$tool" --no-such-option 2>&1 >/dev/null); rc=$?
    [ $rc -eq 2 ] || fail "$name --no-such-option: exit $rc, expected 2"
    case $err in
    "$name: "*"Try '$name --help'"*) ;;
    *) fail "$name --no-such-option: unexpected message '$err'" ;;
    esac
    echo "ok: $name"
done

if [ $failures -ne 0 ]; then
    echo "$failures failure(s)" >&2
    exit 1
fi
echo "all $# tool(s) ok"
