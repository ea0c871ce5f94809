#!/usr/bin/python3
"""Lists the tetrahedra of a CalculiX input whose corners are oriented against the rest, the
elements CalculiX stops on with "nonpositive jacobian". A flat tet the core keeps can have a
signed volume so close to zero that the coordinates as FreeCAD prints them flip its sign.

    /usr/bin/python3 tests/bench/inp_orientation.py OUT/ccx/OracleMesh.inp

Reads the file with meshio; prints one line per odd element (its INP number, 6 x signed corner
volume, longest edge) and the counts."""
import sys

import meshio
import numpy as np


def main(path):
    mesh = meshio.read(path, file_format="abaqus")
    tets = [(block.data, block.type) for block in mesh.cells if block.type in ("tetra", "tetra10")]
    if not tets:
        sys.exit("%s: no C3D4 or C3D10 elements" % path)
    corners = np.concatenate([data[:, :4] for data, _ in tets])
    x = mesh.points[corners]
    volume6 = np.einsum("mi,mi->m", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0])
    majority = 1.0 if (volume6 > 0).sum() >= (volume6 < 0).sum() else -1.0
    odd = np.where(volume6 * majority <= 0)[0]
    for i in odd:
        edges = [np.linalg.norm(x[i, a] - x[i, b]) for a in range(4) for b in range(a)]
        # The position in the file: FreeCAD's writer numbers the elements 1, 2, ... in order,
        # so it is the number CalculiX names.
        print("element #%d: 6V = %.3g, longest edge %.3g, corners %s" % (i + 1, volume6[i], max(edges),
                                                                        np.array2string(x[i], precision=6)))
    print("%d elements, %d oriented %s, %d against them" % (len(volume6), len(volume6) - len(odd),
                                                            "positively" if majority > 0 else "negatively", len(odd)))
    return 1 if len(odd) else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
