#!/usr/bin/env bash
# `make demo`: runs the tools on the bundled data and prints what they computed.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
bin="$build/tools"
out="$build/demo"
mkdir -p "$out"
section() { printf '\n== %s\n' "$*"; }

section "surfaces to OBJ with normals and UVs: Newell's teapot (32 Bezier patches), tolerance 1e-3"
"$bin/geom-tessellate" "$root/data/teapot.bpt" -o "$out/teapot.obj" --tol 1e-3 --normals --uvs
"$bin/geom-info" "$out/teapot.obj" | grep -E '^(faces|components|boundary_loops|manifold):'

section "NURBS sphere, torus and a B-spline patch (data/surfaces.json): adaptive vs uniform"
"$bin/geom-tessellate" "$root/data/surfaces.json" -o "$out/surfaces.obj" --tol 1e-3 --normals --uvs
"$bin/geom-tessellate" "$root/data/surfaces.json" -o "$out/surfaces_grid.obj" --grid 16,16 --normals --uvs

section "curves to polylines (data/surfaces.json)"
"$bin/geom-curve" "$root/data/surfaces.json" -o "$out/curves.obj" --tol 1e-3

section "implicit surfaces by marching cubes: a torus, refined on the exact function"
"$bin/geom-iso" --expr 'torus(1, 0.35)' --bounds -1.5,-1.5,-0.5,1.5,1.5,0.5 --res 96,96,32 \
  --refine --normals -o "$out/torus_iso.obj"
"$bin/geom-info" "$out/torus_iso.obj" | grep -E '^(vertices|faces|genus|manifold|closed):'

section "a gyroid clipped to a box, closed with caps"
"$bin/geom-iso" --expr 'gyroid(6)' --bounds -1,-1,-1,1,1,1 --res 64 --caps -o "$out/gyroid.obj"
"$bin/geom-info" "$out/gyroid.obj" | grep -E '^(faces|genus|closed):'

section "isolines by marching squares (geom-contour), refined"
"$bin/geom-contour" --expr 'smooth_union(sphere(0, 0, 0, 0.6), sphere(0.7, 0.3, 0, 0.5), 0.2)' \
  --bounds -1,-1,1.5,1 --res 200 -o "$out/contour.svg"

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


section "pictures (geom-render): the teapot's 32 Bezier patches, a NURBS torus and a gyroid traced directly, a creased subdivision surface, a CSG part"
for s in teapot nurbs_torus gyroid subdivision csg; do
  "$bin/geom-render" "$root/data/scenes/$s.json" -o "$out/$s.png" | grep -E '^(time|rays|samples):' | sed "s/^/$s: /"
done
"$bin/geom-render" "$root/data/scenes/spheres.json" -o "$out/spheres_ray.png" | grep -E '^(time|objects):' | sed 's/^/spheres, ray: /'
"$bin/geom-render" "$root/data/scenes/spheres.json" -o "$out/spheres_raster.png" --method raster | grep -E '^(time|objects|raster):' | sed 's/^/spheres, raster: /'
"$bin/geom-scene" "$root/data/scenes/spheres.json" --export "$out/spheres.glb" | head -1
echo "PNGs:"
ls "$out"/*.png | sed 's/^/  /'
