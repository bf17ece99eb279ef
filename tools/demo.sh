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

section "mesh topology (geom-info data/cube_seams.obj)"
"$bin/geom-info" "$root/data/cube_seams.obj"

section "angle-weighted normals with 30-degree creases, then tangents to glTF"
"$bin/geom-normals" --weight angle --crease 30 "$root/data/cube_seams.obj" -o "$out/cube_normals.obj"
"$bin/geom-tangents" "$out/cube_normals.obj" -o "$out/cube.glb"
ls -l "$out/cube_normals.obj" "$out/cube.glb" | awk '{print $5, $9}'

section "feature edges and a plane clip with caps"
"$bin/geom-features" --crease 30 "$root/data/cube_seams.obj" -o "$out/cube_features.obj"
grep -c '^l ' "$out/cube_features.obj" | sed 's/^/polylines: /'
"$bin/geom-clip" --plane 1,1,1,-1.5 --cap "$root/data/cube_seams.obj" -o "$out/cube_clipped.obj"
"$bin/geom-info" "$out/cube_clipped.obj"
