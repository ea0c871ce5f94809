"""Geometry of quadratic tetrahedra for the Python and FreeCAD tests, independent of the core.

Mid nodes in the order 01, 12, 20, 03, 13, 23 (the core's and FreeCAD's order; FreeCAD's
corners are negatively oriented, so its volumes come out negative)."""
import numpy as np

_GAUSS = np.array([0.1127016653792583, 0.5, 0.8872983346207417])
_WEIGHTS = np.array([5, 8, 5]) / 18.0
_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
_DL = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)


def tet10_volumes(points, tets):
    """Signed exact volume of each (m, 10) tet: det J is cubic, so a 3x3x3 Gauss rule on the
    cube mapped onto the reference tet (Duffy, whose own Jacobian adds degree 3) is exact."""
    x = np.asarray(points, float)[np.asarray(tets)]  # (m, 10, 3)
    vol = np.zeros(len(x))
    for a in range(3):
        for b in range(3):
            for c in range(3):
                u, s, r = _GAUSS[a], _GAUSS[b], _GAUSS[c]
                xi, eta, zeta = u, s * (1 - u), r * (1 - u) * (1 - s)
                L = np.array([1 - xi - eta - zeta, xi, eta, zeta])
                grads = [(4 * L[i] - 1) * _DL[i] for i in range(4)]
                grads += [4 * (L[i] * _DL[j] + L[j] * _DL[i]) for i, j in _EDGES]
                J = np.einsum("mkr,kc->mrc", x, np.array(grads))
                vol += _WEIGHTS[a] * _WEIGHTS[b] * _WEIGHTS[c] * (1 - u) ** 2 * (1 - s) * np.linalg.det(J)
    return vol
