#!/usr/bin/env bash
# `make demo`: runs the tools on the bundled data and prints what they computed.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
bin="$build/tools"
out="$build/demo"
mkdir -p "$out"
section() { printf '\n== %s\n' "$*"; }

section "barycentric coordinates (geom-bary data/bary_points.txt)"
"$bin/geom-bary" "$root/data/bary_points.txt"
