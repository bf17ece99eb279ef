"""Meshes built in numpy for the tests."""

import numpy as np

CUBE_POINTS = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
# Vertex x + 2y + 4z; quads counter-clockwise seen from outside.
CUBE_FACES = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2],
                       [1, 3, 7, 5]])


def torus(n=24, m=12, R=2.0, r=0.5):
    """Quad torus about z: vertex i*m + j at angles u_i, v_j; faces outward."""
    u = 2 * np.pi * np.arange(n) / n
    v = 2 * np.pi * np.arange(m) / m
    U, V = np.meshgrid(u, v, indexing="ij")
    pts = np.stack([(R + r * np.cos(V)) * np.cos(U), (R + r * np.cos(V)) * np.sin(U),
                    r * np.sin(V)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    i, j = i.ravel(), j.ravel()
    i1, j1 = (i + 1) % n, (j + 1) % m
    faces = np.column_stack([i * m + j, i1 * m + j, i1 * m + j1, i * m + j1])
    return pts, faces


def grid(n=4):
    """Unit square [0,1]^2 at z = 0 as n x n quads facing +z."""
    xs = np.linspace(0, 1, n + 1)
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    pts = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    k = n + 1
    faces = np.column_stack([i * k + j, (i + 1) * k + j, (i + 1) * k + j + 1, i * k + j + 1])
    return pts, faces


def volume(mesh):
    """Enclosed volume of a closed mesh (fan-triangulated faces)."""
    pts = mesh.positions
    total = 0.0
    for f in _face_list(mesh):
        for k in range(1, len(f) - 1):
            total += np.linalg.det(pts[[f[0], f[k], f[k + 1]]])
    return total / 6


def _face_list(mesh):
    faces = mesh.faces
    return list(faces) if isinstance(faces, list) else [row for row in faces]
