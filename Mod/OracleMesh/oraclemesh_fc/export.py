"""Export an OracleMesh mesh with its material groups: VTU (ParaView), INP (CalculiX/Abaqus,
one ELSET per material group) and MSH (Gmsh 2.2, physical tag = material group), through
meshio (Debian's python3-meshio).

The mesh is read back from the object's FemMesh, so what is exported is what FreeCAD shows
and solves; nodes and elements are renumbered 1..n in FemMesh id order.
"""
import os

import numpy as np

from .handoff import CORE_TO_FREECAD

FORMATS = {  # extension -> (meshio format, file dialog filter)
    ".vtu": ("vtu", "VTK unstructured grid (*.vtu)"),
    ".inp": ("abaqus", "CalculiX / Abaqus input (*.inp)"),
    ".msh": ("gmsh22", "Gmsh 2.2 mesh (*.msh)"),
}


class ExportError(Exception):
    pass


def mesh_arrays(femmesh):
    """(points (n,3), tets (m,4|10) 0-based in the core/VTK order, element ids (m,),
    material index per tet (m,), group names). Index i of the material is group i (1-based;
    0 = in no group)."""
    node_ids = sorted(femmesh.Nodes)
    nodes = femmesh.Nodes
    points = np.array([tuple(nodes[i]) for i in node_ids], dtype=float).reshape(-1, 3)
    index_of = {nid: k for k, nid in enumerate(node_ids)}
    element_ids = sorted(femmesh.Volumes)
    tets = np.array([[index_of[n] for n in femmesh.getElementNodes(e)] for e in element_ids],
                    dtype=np.int64)
    if len(tets) == 0:
        raise ExportError("the mesh has no volume elements: mesh it first")
    if tets.shape[1] not in CORE_TO_FREECAD:
        raise ExportError("only tet4 and tet10 meshes can be exported (got %d nodes per "
                          "element)" % tets.shape[1])
    # FreeCAD's order back to the core's: the permutation swaps pairs, so it is its own inverse.
    tets = tets[:, CORE_TO_FREECAD[tets.shape[1]]]
    position = {e: k for k, e in enumerate(element_ids)}
    material = np.zeros(len(element_ids), dtype=np.int32)
    names = []
    for g in femmesh.Groups:
        if femmesh.getGroupElementType(g) != "Volume":
            continue
        names.append(femmesh.getGroupName(g))
        for e in femmesh.getGroupElements(g):
            material[position[e]] = len(names)
    return points, tets, np.array(element_ids), material, names


def export_mesh(obj, path):
    """Write obj's FemMesh to path; the format follows the extension (.vtu, .inp, .msh)."""
    import meshio

    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise ExportError("'%s': unknown extension, use one of %s"
                          % (path, ", ".join(sorted(FORMATS))))
    points, tets, _, material, names = mesh_arrays(obj.FemMesh)
    cell_type = "tetra10" if tets.shape[1] == 10 else "tetra"
    cell_data = {"material": [material]}
    if ext == ".msh":
        cell_data = {"gmsh:physical": [material], "gmsh:geometrical": [material]}
    # Set names as FreeCAD's groups; INP set names may not contain spaces.
    cell_sets = {name.replace(" ", "_"): [np.flatnonzero(material == k + 1)]
                 for k, name in enumerate(names)}
    mesh = meshio.Mesh(points, [(cell_type, tets)], cell_data=cell_data,
                       cell_sets=cell_sets if ext == ".inp" else {})
    meshio.write(path, mesh, file_format=FORMATS[ext][0])
    return path


def export_dialog(obj):
    """Ask for a file name and export (GUI)."""
    import FreeCAD
    import FreeCADGui
    from PySide import QtGui

    filters = ";;".join(f for _, f in FORMATS.values())
    start = os.path.join(os.path.dirname(obj.Document.FileName or os.path.expanduser("~/")),
                         obj.Label + ".vtu")
    path, chosen = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(),
                                                     "Export OracleMesh mesh", start, filters)
    if not path:
        return None
    if not os.path.splitext(path)[1]:
        path += next(ext for ext, (_, f) in FORMATS.items() if f == chosen)
    try:
        export_mesh(obj, path)
    except Exception as e:
        QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "OracleMesh",
                                   "Export of '%s' to %s failed: %s" % (obj.Label, path, e))
        return None
    FreeCAD.Console.PrintMessage("OracleMesh: '%s' written to %s\n" % (obj.Label, path))
    return path
