"""OracleMesh for FreeCAD: multi-material tetrahedral FEM meshes of overlapping solids.

    from oraclemesh_fc import makeMesh
    mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[corner], cell_size=4)
    doc.recompute()

The core (`oraclemesh`, C++ via pybind11) is imported only when a mesh is computed, so the
workbench loads even before the core is built. No module of the package imports the package
itself (tests/python/test_workbench_imports.py keeps the import graph free of cycles).
"""
from .factory import makeMesh  # noqa: F401
from .icons import icon_path  # noqa: F401
from .job import MeshInputError  # noqa: F401
from .mesh_object import OracleMeshProxy  # noqa: F401

__all__ = ["makeMesh", "OracleMeshProxy", "MeshInputError", "icon_path"]
