"""OracleMesh for FreeCAD: multi-material tetrahedral FEM meshes of overlapping solids.

    from oraclemesh_fc import makeMesh
    mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[corner], cell_size=4)
    doc.recompute()

The core (`oraclemesh`, C++ via pybind11) is imported only when a mesh is computed, so the
workbench loads even before the core is built.
"""
import os

from .mesh_object import OracleMeshProxy, makeMesh  # noqa: F401
from .job import MeshInputError  # noqa: F401

__all__ = ["makeMesh", "OracleMeshProxy", "MeshInputError", "icon_path"]


def icon_path(name="OracleMesh.svg"):
    """Path of an icon: Mod/OracleMesh/icons (installed link) or the repository's icons/."""
    package = os.path.dirname(os.path.abspath(__file__))
    candidates = (
        os.path.join(os.path.dirname(package), "icons", name),  # ~/.../Mod/OracleMesh/icons
        # The workbench folder is a set of symlinks into the repository: follow them back.
        os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(package)))),
                     "icons", name),
    )
    for path in candidates:
        if os.path.exists(path):
            return path
    return ""
