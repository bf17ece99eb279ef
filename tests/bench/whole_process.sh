#!/bin/sh
# Whole-process benchmark: libgeom's tools against peer programs on the same
# input, runs alternating (ours, peer, ours, peer, ...), N runs each. Prints
# each run's wall and cpu seconds and peak RSS (/usr/bin/time -v), then the
# medians and the ratios ours/peer.
#
#   geom-info IN.obj                       vs peer_tinyobj_info IN.obj
#   geom-normals --weight area IN -o OUT   vs peer_openmesh_normals IN OUT
#   geom-subdivide --scheme loop --levels 1 vs peer_subdiv_far (OpenSubdiv Far
#                                             with OBJ in and out), bunny00.off
#   geom-iso 320x192x64 on two tori          vs peer_iso_vtk (vtkFlyingEdges3D)
#   geom-iso 512^3 on two tori (sparse)      vs geom-iso --dense, and vs
#                                               peer_iso_vtk 512 512 512
#
# Usage: tests/bench/whole_process.sh [BUILD_DIR] [N] [JOBS]
#   (default build, 5, all; JOBS is a comma-separated subset of
#   info,normals,subdivide,iso,iso512)
# The input is a 1000 x 600 torus (1.2M triangles, 63 MB) made by
# make_torus_obj.py in $TMPDIR (kept between calls). The peers are built by
# tests/bench/CMakeLists.txt when libtinyobjloader-dev and libopenmesh-dev
# are installed: cmake --build BUILD --target geom-info geom-normals
# peer_tinyobj_info peer_openmesh_normals geom-subdivide geom-iso geom-convert
# peer_subdiv_far peer_iso_vtk (the last two when OpenSubdiv and VTK are
# found). bunny00.off comes from libcgal-demo's data.tar.gz.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
n=${2:-5}
jobs=,${3:-info,normals,subdivide,iso},
want() { case $jobs in *,"$1",*) return 0 ;; esac; [ "$jobs" = ",all," ]; }
tmp=${TMPDIR:-/tmp}
obj=$tmp/geom_whole_process_torus.obj
{ want info || want normals; } && [ ! -s "$obj" ] && /usr/bin/python3 "$here/make_torus_obj.py" "$obj" 1000 600

# one run: prints "wall cpu peak_kb"
run() {
    /usr/bin/time -f '%e %U %S %M' -o "$tmp/geom_wp_time" "$@" >/dev/null 2>"$tmp/geom_wp_err" ||
        { cat "$tmp/geom_wp_err" >&2; exit 1; }
    awk '{printf "%s %.3f %s\n", $1, $2 + $3, $4}' "$tmp/geom_wp_time"
}

median() { sort -n | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

compare() {
    name=$1
    shift
    ours=$1
    peer=$2
    : >"$tmp/geom_wp_a"
    : >"$tmp/geom_wp_b"
    i=0
    while [ $i -lt "$n" ]; do
        # shellcheck disable=SC2086
        run $ours >>"$tmp/geom_wp_a"
        # shellcheck disable=SC2086
        run $peer >>"$tmp/geom_wp_b"
        i=$((i + 1))
    done
    aw=$(cut -d' ' -f1 "$tmp/geom_wp_a" | median)
    ac=$(cut -d' ' -f2 "$tmp/geom_wp_a" | median)
    am=$(cut -d' ' -f3 "$tmp/geom_wp_a" | median)
    bw=$(cut -d' ' -f1 "$tmp/geom_wp_b" | median)
    bc=$(cut -d' ' -f2 "$tmp/geom_wp_b" | median)
    bm=$(cut -d' ' -f3 "$tmp/geom_wp_b" | median)
    echo "$name ($n runs each, alternating; medians)"
    echo "  ours: wall $aw s  cpu $ac s  peak $((am / 1024)) MiB   ($ours)"
    echo "  peer: wall $bw s  cpu $bc s  peak $((bm / 1024)) MiB   ($peer)"
    awk -v aw="$aw" -v bw="$bw" -v ac="$ac" -v bc="$bc" -v am="$am" -v bm="$bm" \
        'BEGIN {printf "  ours/peer: wall %.2f  cpu %.2f  peak %.2f\n", aw / bw, ac / bc, am / bm}'
}

want info && compare "geom-info vs tinyobjloader load" \
    "$build/tools/geom-info $obj" \
    "$build/tests/bench/peer_tinyobj_info $obj"
want normals && compare "geom-normals --weight area vs OpenMesh read + area normals + write" \
    "$build/tools/geom-normals --weight area $obj -o $tmp/geom_wp_ours.obj" \
    "$build/tests/bench/peer_openmesh_normals $obj $tmp/geom_wp_peer.obj"
bunny=$tmp/geom_whole_process_bunny.obj
if want subdivide && [ ! -s "$bunny" ]; then
    tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$tmp" data/meshes/bunny00.off
    "$build/tools/geom-convert" "$tmp/data/meshes/bunny00.off" -o "$bunny"
fi
want subdivide && compare "geom-subdivide --scheme loop --levels 1 vs OpenSubdiv Far + OBJ I/O (bunny, 75k triangles)" \
    "$build/tools/geom-subdivide --scheme loop --levels 1 $bunny -o $tmp/geom_wp_ours.obj" \
    "$build/tests/bench/peer_subdiv_far loop 1 $bunny $tmp/geom_wp_peer.obj"
tt='min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))'
want iso && compare "geom-iso 320x192x64 two tori vs vtkFlyingEdges3D + OBJ" \
    "$build/tools/geom-iso -e $tt -b -2.16,-1.296,-0.432,2.16,1.296,0.432 -r 320,192,64 -o $tmp/geom_wp_ours.obj" \
    "$build/tests/bench/peer_iso_vtk 320 192 64 $tmp/geom_wp_peer.obj"
# 512^3: the sparse path (default) against the dense path and against VTK
want iso512 && compare "geom-iso 512^3 two tori, sparse vs --dense" \
    "$build/tools/geom-iso -e $tt -b -2.16,-1.296,-0.432,2.16,1.296,0.432 -r 512 -o $tmp/geom_wp_ours.obj" \
    "$build/tools/geom-iso -e $tt -b -2.16,-1.296,-0.432,2.16,1.296,0.432 -r 512 --dense -o $tmp/geom_wp_peer.obj"
want iso512 && { cmp -s "$tmp/geom_wp_ours.obj" "$tmp/geom_wp_peer.obj" &&
    echo "  sparse and dense outputs: byte-identical" ||
    echo "  sparse and dense outputs DIFFER"; }
want iso512 && compare "geom-iso 512^3 two tori (sparse) vs vtkFlyingEdges3D + OBJ" \
    "$build/tools/geom-iso -e $tt -b -2.16,-1.296,-0.432,2.16,1.296,0.432 -r 512 -o $tmp/geom_wp_ours.obj" \
    "$build/tests/bench/peer_iso_vtk 512 512 512 $tmp/geom_wp_peer.obj"
rm -f "$tmp/geom_wp_a" "$tmp/geom_wp_b" "$tmp/geom_wp_time" "$tmp/geom_wp_err" \
    "$tmp/geom_wp_ours.obj" "$tmp/geom_wp_peer.obj"
