#!/bin/sh
# Whole-process benchmarks of issue 9: each job is run as a user runs it
# (start-up, reading, the work, the error report, writing), ours and the
# peer's alternately, RUNS times each; prints the median wall seconds, the
# ratio ours / peer of the medians (and the median of the pairwise ratios)
# and the peak resident memory of each (GNU time's maximum RSS).
#
#   tests/bench/whole_process.sh BUILD_DIR [RUNS]
#
# Needs: BUILD_DIR/tools/geom-subdivide and geom-iso, BUILD_DIR/tests/bench/
# peer_subdiv_far and peer_iso_vtk (built when OpenSubdiv and VTK are
# found), /usr/bin/time, and bunny00.off from libcgal-demo's data.tar.gz.
set -eu
B=${1:?usage: whole_process.sh BUILD_DIR [RUNS]}
RUNS=${2:-7}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$T" data/meshes/bunny00.off
"$B/tools/geom-convert" "$T/data/meshes/bunny00.off" -o "$T/bunny.obj"
TT='min(torus(-0.7,0,0,0.9,0.3), torus(0.7,0,0,0.9,0.3))'

# run LABEL CMD...: one run, appends "seconds rss_kb" to $T/LABEL
run() {
    label=$1
    shift
    /usr/bin/time -f "%e %M" -o "$T/time" "$@" >/dev/null 2>&1
    cat "$T/time" >>"$T/$label"
}

job() {
    name=$1
    rm -f "$T/ours" "$T/peer"
    i=0
    while [ "$i" -lt "$RUNS" ]; do
        if [ "$name" = subdiv ]; then
            run ours "$B/tools/geom-subdivide" --scheme loop --levels 1 "$T/bunny.obj" -o "$T/o.obj"
            run peer "$B/tests/bench/peer_subdiv_far" loop 1 "$T/bunny.obj" "$T/p.obj"
        else
            run ours "$B/tools/geom-iso" -e "$TT" -b -2.16,-1.296,-0.432,2.16,1.296,0.432 \
                -r 320,192,64 -o "$T/o.obj"
            run peer "$B/tests/bench/peer_iso_vtk" 320 192 64 "$T/p.obj"
        fi
        i=$((i + 1))
    done
    /usr/bin/python3 - "$name" "$T/ours" "$T/peer" <<'PY'
import statistics, sys
name = sys.argv[1]
o = [tuple(map(float, l.split())) for l in open(sys.argv[2])]
p = [tuple(map(float, l.split())) for l in open(sys.argv[3])]
mo, mp = statistics.median(x[0] for x in o), statistics.median(x[0] for x in p)
pair = statistics.median(a[0] / b[0] for a, b in zip(o, p) if b[0] > 0)
print(f"{name:8s} ours {mo:.3f} s  peer {mp:.3f} s  ratio {mo / mp:.2f} "
      f"(pairwise median {pair:.2f})  peak RSS ours {max(x[1] for x in o) / 1024:.0f} MB "
      f"peer {max(x[1] for x in p) / 1024:.0f} MB  ({len(o)} runs each)")
PY
}

job subdiv
job iso
