"""Reference area and volume of a STEP part from gmsh (OpenCASCADE geometry),
shared by the STEP validation test (tests/tools/test_geom_tessellate_step.sh)
and the benchmark (tests/bench/bench_step.py). Needs numpy and python3-gmsh.

reference(path) imports the file once (gmsh must be initialised) and returns
a dict: solids and faces (OpenCASCADE's counts), diag (bounding-box
diagonal), centroids (sorted volume centroids of the solids), area and
volume, and how they were obtained ('source'):
 - a part with no B-spline surface: OpenCASCADE's GProp integrals
   (gmsh.model.occ.getMass), exact for analytic faces;
 - a part with B-spline surfaces: OpenCASCADE's integrals are off there
   (component8: area 5.3e-4, volume 2.1e-4 from every converged mesh), so
   the reference is gmsh's own curved (second-order) surface mesh, its
   mid-edge nodes on the CAD surfaces, integrated exactly for its volume and
   by a 7-point degree-5 rule (Dunavant) for its area. On component8, at
   diag/25 and 32 elements per 2 pi, it is within 6e-7 (area) and 3.2e-6
   (volume) of the same mesh at diag/100 and 64 per 2 pi, which agrees with
   a linear mesh at diag/400 extrapolated (Richardson, h^2) to 1e-6.
   (Projecting a linear mesh's edge midpoints with getClosestPoint instead
   is wrong on narrow fillets: the projections are clamped to the patch
   boundary.)
"""
import math
import numpy as np
import gmsh

# Dunavant's 7-point rule (degree 5) on the reference triangle (u, v >= 0, u + v <= 1)
_A1, _B1, _W1 = 0.059715871789770, 0.470142064105115, 0.132394152788506
_A2, _B2, _W2 = 0.797426985353087, 0.101286507323456, 0.125939180544827
_Q = np.array([(1 / 3, 1 / 3, 0.225), (_B1, _B1, _W1), (_A1, _B1, _W1), (_B1, _A1, _W1),
               (_B2, _B2, _W2), (_A2, _B2, _W2), (_B2, _A2, _W2)])


def _shape():
    """Quadratic Lagrange shape functions (gmsh's 6-node triangle: corners,
    then the midpoints of edges 01, 12, 20) and their u, v derivatives at
    the quadrature points."""
    u, v = _Q[:, 0], _Q[:, 1]
    L = [1 - u - v, u, v]
    dLu, dLv = (-1, 1, 0), (-1, 0, 1)
    pairs = ((0, 1), (1, 2), (2, 0))
    N = [L[i] * (2 * L[i] - 1) for i in range(3)] + [4 * L[a] * L[b] for a, b in pairs]
    Nu = [(4 * L[i] - 1) * dLu[i] for i in range(3)] + [4 * (dLu[a] * L[b] + L[a] * dLu[b]) for a, b in pairs]
    Nv = [(4 * L[i] - 1) * dLv[i] for i in range(3)] + [4 * (dLv[a] * L[b] + L[a] * dLv[b]) for a, b in pairs]
    one = np.ones(len(u))
    return np.array(N), np.array([x * one for x in Nu]), np.array([x * one for x in Nv]), _Q[:, 2] * 0.5


def curved_mesh_area_volume(diag, divisions=25, curvature=32):
    """Area and enclosed volume of gmsh's second-order surface mesh of the
    current model (max size diag / divisions, `curvature` elements per 2 pi),
    with every surface oriented by its solid's boundary (outward)."""
    sign = {}
    for _, v in gmsh.model.getEntities(3):
        for _, s in gmsh.model.getBoundary([(3, v)], oriented=True, combined=False):
            sign[abs(s)] = 1 if s > 0 else -1
    gmsh.model.mesh.clear()
    gmsh.option.setNumber("Mesh.MeshSizeMax", diag / divisions)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", curvature)
    gmsh.model.mesh.generate(2)
    gmsh.model.mesh.setOrder(2)
    tags, coord, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(int)] = coord.reshape(-1, 3)
    N, Nu, Nv, w = _shape()
    A = V = 0.0
    for _, s in gmsh.model.getEntities(2):
        types, _, nodes = gmsh.model.mesh.getElements(2, s)
        for ty, nn in zip(types, nodes):
            if ty != 9:  # 6-node triangle
                continue
            P = X[nn.astype(int).reshape(-1, 6)]
            x = np.einsum('kq,ekj->eqj', N, P)
            n = np.cross(np.einsum('kq,ekj->eqj', Nu, P), np.einsum('kq,ekj->eqj', Nv, P))
            A += float((np.linalg.norm(n, axis=2) * w).sum())
            V += sign.get(s, 0) * float((np.einsum('eqj,eqj->eq', x, n) * w).sum()) / 3
    gmsh.model.mesh.clear()
    return A, V


def reference(path):
    gmsh.clear()
    gmsh.model.occ.importShapes(path)
    gmsh.model.occ.synchronize()
    vols = gmsh.model.getEntities(3)
    surfs = gmsh.model.getEntities(2)
    box = gmsh.model.getBoundingBox(-1, -1)
    r = {'solids': len(vols), 'faces': len(surfs), 'diag': math.dist(box[:3], box[3:]),
         'centroids': sorted(tuple(gmsh.model.occ.getCenterOfMass(3, t)) for _, t in vols),
         'occ_area': sum(gmsh.model.occ.getMass(2, t) for _, t in surfs),
         'occ_volume': sum(gmsh.model.occ.getMass(3, t) for _, t in vols)}
    if 'B_SPLINE_SURFACE' in open(path, errors='replace').read():
        r['area'], r['volume'] = curved_mesh_area_volume(r['diag'])
        r['source'] = "gmsh second-order mesh"
    else:
        r['area'], r['volume'] = r['occ_area'], r['occ_volume']
        r['source'] = "OpenCASCADE integral"
    return r
