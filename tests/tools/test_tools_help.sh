#!/bin/bash
# Every tool's --help ends with two examples of itself and points to
# docs/formats.md, which exists; and --quiet is a common option.
# Usage: test_tools_help.sh SOURCE_DIR TOOL...
set -u
SRC=$1
shift
failures=0
[ -f "$SRC/docs/formats.md" ] || { echo "FAIL: docs/formats.md missing" >&2; failures=1; }
for tool in "$@"; do
    name=$(basename "$tool")
    help=$("$tool" --help) || { echo "FAIL: $name --help failed" >&2; failures=$((failures + 1)); continue; }
    n=$(printf '%s\n' "$help" | sed -n '/^Examples:$/,/^$/p' | grep -c "^  $name ")
    [ "$n" -eq 2 ] || { echo "FAIL: $name: $n examples, expected 2" >&2; failures=$((failures + 1)); }
    printf '%s\n' "$help" | tail -2 | grep -q "docs/formats.md" ||
        { echo "FAIL: $name: --help does not end pointing to docs/formats.md" >&2; failures=$((failures + 1)); }
    printf '%s\n' "$help" | grep -q -- "--quiet" ||
        { echo "FAIL: $name: no --quiet in --help" >&2; failures=$((failures + 1)); }
done
[ "$failures" -eq 0 ] && echo "all $# tools ok"
exit $((failures > 0))
