#!/bin/bash
# Validation of geom-tessellate on STEP input against gmsh (OpenCASCADE):
# for each STEP file of Debian's gmsh-doc and data/sphere.step (also
# rewritten in inches), the same number of solids and faces as
# OpenCASCADE finds, every solid closed and manifold (geom-info on the
# output; CGAL's checks are in tests/validate/test_validate_step.c), the
# reported chordal error within the tolerance, every solid in place, and the
# area and enclosed volume of the mesh within 1e-4 of the reference
# (step_gmsh_reference.py: OpenCASCADE's exact GProp integrals for analytic
# parts; for parts with B-spline faces, where those integrals are off by up
# to 5e-4, gmsh's curved second-order mesh integrated exactly); the sphere
# against 4 pi r^2 and 4/3 pi r^3. A dangling reference must fail with exit
# 1 naming the file, line and column. Our tessellation runs while gmsh
# computes the reference (two processes).
# Usage: test_geom_tessellate_step.sh TOOL GEOM_INFO DATA_DIR   (env PYTHON3)
# Exit 77 (skipped) when gmsh's Python module or gmsh-doc is missing.
set -u
TOOL=$1
INFO=$2
DATA=$3
PY=${PYTHON3:-/usr/bin/python3}
if ! "$PY" -c 'import gmsh, numpy' 2>/dev/null; then
    echo "SKIP: gmsh's Python module (Debian python3-gmsh) or numpy is not installed; .ci/deps installs them"
    exit 77
fi
DOC=/usr/share/doc/gmsh-doc/doc/gmsh
if [ ! -d "$DOC" ]; then
    echo "SKIP: gmsh-doc is not installed (no STEP files to validate against); .ci/deps installs it"
    exit 77
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-step-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
files=()
while IFS= read -r f; do
    b=$(basename "$f" .gz)
    [ -e "$T/$b" ] && continue
    case "$f" in *.gz) zcat "$f" >"$T/$b" ;; *) cp "$f" "$T/$b" ;; esac
    # the same part under two names (t20_data.step is component8.step) once
    dup=0
    for g in "${files[@]}"; do cmp -s "$g" "$T/$b" && dup=1; done
    [ $dup = 1 ] || files+=("$T/$b")
done < <(find "$DOC" -iname '*.stp*' -o -iname '*.step*' | sort)
cp "$DATA/sphere.step" "$T/sphere.step"
sed 's/^#21=(LENGTH_UNIT()NAMED_UNIT(\*)SI_UNIT(.MILLI.,.METRE.));/#21=(CONVERSION_BASED_UNIT('"'"'INCH'"'"',#25)LENGTH_UNIT()NAMED_UNIT(#26));\n#25=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#27);\n#26=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n#27=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));/' \
    "$DATA/sphere.step" >"$T/sphere_inch.step"
sed 's/#13=EDGE_CURVE('"''"',#8,#9,#12,.T.);/#13=EDGE_CURVE('"''"',#8,#9,#77,.T.);/' "$DATA/sphere.step" >"$T/dangling.step"
export PYTHONPATH="$(dirname "$0")${PYTHONPATH:+:$PYTHONPATH}"
exec "$PY" -u - "$TOOL" "$INFO" "$T" "${files[@]}" <<'PYEOF'
import json, math, os, subprocess, sys
import numpy as np
import gmsh
from step_gmsh_reference import reference

tool, info, tmp = sys.argv[1:4]
files = sys.argv[4:]
failures = []
def fail(msg):
    print("FAIL:", msg); failures.append(msg)

def read_obj(path):
    V = []; F = []
    for line in open(path):
        if line.startswith('v '):
            V.append([float(x) for x in line.split()[1:4]])
        elif line.startswith('f '):
            F.append([int(t.split('/')[0]) - 1 for t in line.split()[1:4]])
    return np.array(V, dtype=float).reshape(-1, 3), np.array(F, dtype=np.int64).reshape(-1, 3)

def mesh_area_volume(path):
    X, F = read_obj(path)
    a, b, c = X[F[:, 0]], X[F[:, 1]], X[F[:, 2]]
    return (0.5 * float(np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()),
            float(np.einsum('ij,ij->i', a, np.cross(b, c)).sum()) / 6)

def solid_centroids(path):
    """Volume centroids of the mesh's connected components (one per solid)."""
    V = []; F = []
    for line in open(path):
        if line.startswith('v '):
            V.append(tuple(map(float, line.split()[1:4])))
        elif line.startswith('f '):
            F.append([int(t.split('/')[0]) - 1 for t in line.split()[1:4]])
    par = list(range(len(V)))
    def find(x):
        while par[x] != x:
            par[x] = par[par[x]]; x = par[x]
        return x
    for a, b, c in F:
        ra = find(a); par[find(b)] = ra; par[find(c)] = ra
    acc = {}
    for a, b, c in F:
        A, B, C = V[a], V[b], V[c]
        v = (A[0]*(B[1]*C[2]-B[2]*C[1]) - A[1]*(B[0]*C[2]-B[2]*C[0]) + A[2]*(B[0]*C[1]-B[1]*C[0])) / 6
        s = acc.setdefault(find(a), [0.0, 0.0, 0.0, 0.0])
        s[3] += v
        for i in range(3): s[i] += v * (A[i] + B[i] + C[i]) / 4
    return sorted(tuple(s[i] / s[3] for i in range(3)) for s in acc.values())

def start_ours(path, tol):
    out = os.path.join(tmp, os.path.basename(path) + '.obj')
    p = subprocess.Popen([tool, path, '--tol', repr(tol), '--json', '-o', out],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return p, out, path

def finish_ours(job):
    p, out, path = job
    stdout, stderr = p.communicate()
    if p.returncode != 0:
        fail(f"{path}: exit {p.returncode}: {stderr.strip()}"); return None, None
    rep = json.loads(stdout)
    q = subprocess.run([info, '--json', out], capture_output=True, text=True)
    inf = json.loads(q.stdout)
    return rep, (out, inf)

def run_ours(path, tol):
    return finish_ours(start_ours(path, tol))

gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
for path in files:
    # the bounding box first (cheap), so that ours runs during the reference
    gmsh.clear(); gmsh.model.occ.importShapes(path); gmsh.model.occ.synchronize()
    box = gmsh.model.getBoundingBox(-1, -1); diag = math.dist(box[:3], box[3:])
    tol = 5e-5 * diag
    job = start_ours(path, tol)
    R = reference(path)
    rep, (out, inf) = finish_ours(job)
    if rep is None: continue
    name = os.path.basename(path)
    if rep['solids'] != R['solids']: fail(f"{name}: {rep['solids']} solids, OpenCASCADE {R['solids']}")
    if rep['faces'] != R['faces']: fail(f"{name}: {rep['faces']} faces, OpenCASCADE {R['faces']}")
    if rep['faces_failed'] or rep['unsupported']: fail(f"{name}: faces failed or unsupported: {rep}")
    if not (inf['closed'] and inf['manifold']): fail(f"{name}: not closed and manifold: {inf}")
    if inf['components'] != rep['solids']: fail(f"{name}: {inf['components']} components for {rep['solids']} solids")
    if rep['max_error'] > tol * (1 + 1e-9): fail(f"{name}: error {rep['max_error']} above tolerance {tol}")
    A, V = mesh_area_volume(out)
    A0, V0 = R['area'], R['volume']
    ea, ev = abs(A - A0) / A0, abs(V - V0) / V0
    msg = (f"{name}: tol {tol:.3g} triangles {rep['triangles']} area {A:.9g} ({R['source']} {A0:.9g}, rel {ea:.2e};"
           f" OpenCASCADE integral rel {abs(A - R['occ_area']) / R['occ_area']:.2e})"
           f" volume {V:.9g} ({V0:.9g}, rel {ev:.2e}; OpenCASCADE integral rel {abs(V - R['occ_volume']) / R['occ_volume']:.2e})")
    if ea > 1e-4 or ev > 1e-4: fail(msg)
    if V <= 0: fail(f"{name}: volume {V} not positive (normals inward)")
    # every solid in place (assemblies): centroids against OpenCASCADE's
    ref_c = R['centroids']
    ours_c = solid_centroids(out)
    worst = 0.0
    for c in ours_c:
        worst = max(worst, min(math.dist(c, r) for r in ref_c) if ref_c else 0.0)
    msg += f" solids placed within {worst:.2e}"
    if len(ours_c) != len(ref_c) or worst > 1e-3 * diag: fail(msg)
    print(msg)
gmsh.finalize()

for name, r in (('sphere.step', 10.0), ('sphere_inch.step', 254.0)):
    path = os.path.join(tmp, name); tol = 5e-5 * r
    rep, (out, inf) = run_ours(path, tol)
    if rep is None: continue
    A, V = mesh_area_volume(out)
    A0, V0 = 4 * math.pi * r * r, 4 / 3 * math.pi * r ** 3
    print(f"{name}: area rel {abs(A-A0)/A0:.2e} volume rel {abs(V-V0)/V0:.2e} triangles {rep['triangles']}")
    if abs(A - A0) / A0 > 1e-4 or abs(V - V0) / V0 > 1e-4: fail(f"{name}: area {A} / volume {V} vs {A0} / {V0}")
    if not (inf['closed'] and inf['manifold'] and inf['genus'] == 0): fail(f"{name}: not a closed sphere: {inf}")

p = subprocess.run([tool, os.path.join(tmp, 'dangling.step'), '-o', os.path.join(tmp, 'd.obj')], capture_output=True, text=True)
if p.returncode != 1 or 'dangling.step:' not in p.stderr or '#77' not in p.stderr:
    fail(f"dangling reference: exit {p.returncode}, stderr {p.stderr!r}")
if os.path.exists(os.path.join(tmp, 'd.obj')): fail("dangling reference left an output file")
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
PYEOF
