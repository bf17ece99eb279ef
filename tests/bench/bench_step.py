#!/usr/bin/python3
"""STEP tessellation: area error and triangles against time, libgeom
(geom-tessellate IN.step) next to gmsh's own surface mesher (through its
Python API, OpenCASCADE geometry) on the same files in the same run.

Usage: /usr/bin/python3 tests/bench/bench_step.py build/tools/geom-tessellate [FILE.step ...]
(default files: the STEP files of Debian's gmsh-doc). Needs python3-gmsh.

Area error: |A - A_ref| / A_ref with A_ref from
tests/tools/step_gmsh_reference.py (shared with the validation test):
OpenCASCADE's exact surface integral (gmsh.model.occ.getMass) for analytic
parts, gmsh's curved second-order mesh for parts with B-spline faces (where
OpenCASCADE's integral is off by 5e-4 on component8). libgeom's time is the tessellation time it
reports (reading excluded); gmsh's is mesh.generate(2) (1D and 2D meshing).
gmsh has no chordal tolerance: it is run with Mesh.MeshSizeFromCurvature =
N elements per 2 pi for a few N.
"""
import glob, gzip, json, math, os, subprocess, sys, tempfile, time
import gmsh
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tools'))
from step_gmsh_reference import reference

tool = sys.argv[1]
files = sys.argv[2:]
tmp = tempfile.mkdtemp()
if not files:
    seen = set()
    for f in sorted(glob.glob('/usr/share/doc/gmsh-doc/doc/gmsh/**/*.st*p.gz', recursive=True)):
        data = gzip.open(f).read()
        if data in seen:
            continue
        seen.add(data)
        p = os.path.join(tmp, os.path.basename(f)[:-3])
        open(p, 'wb').write(data)
        files.append(p)

def tri_area(a, b, c):
    u = [b[i] - a[i] for i in range(3)]; w = [c[i] - a[i] for i in range(3)]
    n = (u[1]*w[2]-u[2]*w[1], u[2]*w[0]-u[0]*w[2], u[0]*w[1]-u[1]*w[0])
    return 0.5 * math.sqrt(n[0]**2 + n[1]**2 + n[2]**2)

def obj_area(path):
    V = []; A = 0.0
    for line in open(path):
        if line.startswith('v '):
            V.append(tuple(map(float, line.split()[1:4])))
        elif line.startswith('f '):
            A += tri_area(*(V[int(t.split('/')[0]) - 1] for t in line.split()[1:4]))
    return A

gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
print("| file | mesher | setting | triangles | seconds | area rel. error |")
print("|---|---|---|---|---|---|")
for path in files:
    name = os.path.basename(path)
    R = reference(path)
    A0, diag = R['area'], R['diag']
    print(f"| {name} | reference | {R['source']} | | | area {A0:.9g} |")
    for rel in (1e-3, 3e-4, 1e-4, 3e-5):
        tol = rel * diag
        out = os.path.join(tmp, 'o.obj')
        p = subprocess.run([tool, path, '--tol', repr(tol), '--json', '-o', out], capture_output=True, text=True)
        if p.returncode:
            print(f"| {name} | libgeom | tol {tol:.3g} | failed: {p.stderr.strip()} | | |"); continue
        r = json.loads(p.stdout)
        if r['max_error'] > tol * (1 + 1e-9):
            print(f"| {name} | libgeom | tol {tol:.3g} | error {r['max_error']:.3g} above the tolerance | | |")
        A = obj_area(out)
        print(f"| {name} | libgeom | tol {tol:.3g} (diag x {rel:g}) | {r['triangles']} | {r['seconds']:.3f} | {abs(A - A0) / A0:.2e} |")
    for n in (12, 24, 48):
        gmsh.model.mesh.clear()
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", n)
        gmsh.option.setNumber("Mesh.MeshSizeMax", diag / n)
        t0 = time.perf_counter()
        gmsh.model.mesh.generate(2)
        secs = time.perf_counter() - t0
        nt, coord, _ = gmsh.model.mesh.getNodes()
        pos = {int(t): (coord[3*i], coord[3*i+1], coord[3*i+2]) for i, t in enumerate(nt)}
        A = 0.0; ntri = 0
        types, tags, nodes = gmsh.model.mesh.getElements(2)
        for ty, nn in zip(types, nodes):
            if ty != 2:
                continue
            for k in range(0, len(nn), 3):
                A += tri_area(pos[int(nn[k])], pos[int(nn[k+1])], pos[int(nn[k+2])]); ntri += 1
        print(f"| {name} | gmsh 4.8 | {n} per 2pi, max size diag/{n} | {ntri} | {secs:.3f} | {abs(A - A0) / A0:.2e} |")
gmsh.finalize()
