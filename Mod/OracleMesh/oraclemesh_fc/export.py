"""Export an OracleMesh mesh with its material groups and face groups: VTU (ParaView), INP
(CalculiX/Abaqus) and MSH (Gmsh 2.2, physical tag = material group), through meshio
(Debian's python3-meshio).

Material (Volume) groups: cell data "material" (VTU; index k of group k, 1-based), one ELSET
each (INP), the physical tag (MSH). Face groups (the interfaces and exteriors): in the VTU a
second cell block of their face elements (triangle / triangle6) with cell data "face_group"
(index k of face group k, 1-based; 0 on the tets, whose "material" is 0 on the faces) and a
FieldData array per face group, name -> [k, 2] (as meshio keeps Gmsh's physical names); in
the INP one *SURFACE, TYPE=ELEMENT each, over the faces of the tets (CalculiX S1..S4), the
form loads and contact pairs refer to. The MSH has the volumes only.

The mesh is read back from the object's FemMesh, so what is exported is what FreeCAD shows
and solves; nodes and elements are renumbered 1..n in FemMesh id order.
"""
import os

import numpy as np

from .handoff import CORE_TO_FREECAD, OUTWARD_FACE_CORNERS

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


def _oriented_key(corners):
    """A face's corners rotated to start at the smallest, keeping their cyclic order."""
    k = corners.index(min(corners))
    return tuple(corners[k:] + corners[:k])


def face_groups(femmesh, tets):
    """[(group name, faces (f, 2) = (tet row of `tets`, CalculiX face 0..3), face nodes
    (f, 3|6) as point indices)] for every Face group, `tets` as mesh_arrays returns them.

    The workbench's face elements have their corners ordered so that their normal points out
    of the tet they belong to (handoff.surface_face_nodes): where two parts' tets share a face
    (a bonded interface), that order tells whose face it is."""
    groups = [g for g in femmesh.Groups if femmesh.getGroupElementType(g) == "Face"]
    if not groups:
        return []
    index_of = {nid: k for k, nid in enumerate(sorted(femmesh.Nodes))}
    owner = {}
    for row, tet in enumerate(tets[:, :4].tolist()):
        for face, corners in enumerate(OUTWARD_FACE_CORNERS):
            owner[_oriented_key([tet[c] for c in corners])] = (row, face)
    result = []
    for g in groups:
        name = femmesh.getGroupName(g)
        elements = sorted(femmesh.getGroupElements(g))
        if not elements:
            continue  # nothing to write (and CalculiX rejects an empty *SURFACE)
        nodes = np.array([[index_of[n] for n in femmesh.getElementNodes(e)] for e in elements],
                         dtype=np.int64)
        faces = []
        for corners in nodes[:, :3].tolist():
            found = owner.get(_oriented_key(corners))
            if found is None:
                raise ExportError("face group '%s': a face (nodes %s) is no face of the mesh's "
                                  "tets, or its corners are not ordered outward; remesh to "
                                  "renew the face groups" % (name, corners))
            faces.append(found)
        result.append((name, np.array(faces, dtype=np.int64).reshape(-1, 2), nodes))
    return result


def _inp_surfaces(surfaces):
    """*SURFACE blocks over element faces: element id = tet row + 1, as meshio numbers them."""
    lines = []
    for name, faces, _ in surfaces:
        lines.append("*SURFACE, NAME=%s, TYPE=ELEMENT" % name.replace(" ", "_"))
        lines += ["%d, S%d" % (row + 1, face + 1) for row, face in faces.tolist()]
    return "\n".join(lines) + "\n" if lines else ""


def export_mesh(obj, path):
    """Write obj's FemMesh to path; the format follows the extension (.vtu, .inp, .msh)."""
    import meshio

    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise ExportError("'%s': unknown extension, use one of %s"
                          % (path, ", ".join(sorted(FORMATS))))
    points, tets, _, material, names = mesh_arrays(obj.FemMesh)
    surfaces = face_groups(obj.FemMesh, tets) if ext in (".vtu", ".inp") else []
    cell_type = "tetra10" if tets.shape[1] == 10 else "tetra"
    cells = [(cell_type, tets)]
    cell_data = {"material": [material]}
    if ext == ".msh":
        cell_data = {"gmsh:physical": [material], "gmsh:geometrical": [material]}
    if ext == ".vtu" and surfaces:
        face_nodes = np.concatenate([nodes for _, _, nodes in surfaces])
        group = np.concatenate([np.full(len(nodes), k + 1, dtype=np.int32)
                                for k, (_, _, nodes) in enumerate(surfaces)])
        cells.append(("triangle6" if face_nodes.shape[1] == 6 else "triangle", face_nodes))
        cell_data = {"material": [material, np.zeros(len(group), dtype=np.int32)],
                     "face_group": [np.zeros(len(tets), dtype=np.int32), group]}
    # Set names as FreeCAD's groups; INP set names may not contain spaces.
    cell_sets = {name.replace(" ", "_"): [np.flatnonzero(material == k + 1)]
                 for k, name in enumerate(names)}
    mesh = meshio.Mesh(points, cells, cell_data=cell_data,
                       cell_sets=cell_sets if ext == ".inp" else {})
    # CalculiX reads each *NODE coordinate from a 20-character field (f20.0): meshio's default
    # %.16e makes 22 or 23 characters; .12e makes at most 19.
    options = {"float_fmt": ".12e"} if ext == ".inp" else {}
    meshio.write(path, mesh, file_format=FORMATS[ext][0], **options)
    if ext == ".inp":
        _finish_inp(path, surfaces)
    if ext == ".vtu" and surfaces:
        _add_vtu_field_data(path, [name for name, _, _ in surfaces])
    return path


def _finish_inp(path, surfaces):
    """Makes meshio's INP one CalculiX reads: meshio names tetra10 C3D10MH (the last of the
    Abaqus types it maps to tetra10), which CalculiX does not know; and adds the surfaces."""
    with open(path) as f:
        text = f.read()
    text = text.replace("*ELEMENT, TYPE=C3D10MH\n", "*ELEMENT, TYPE=C3D10\n")
    with open(path, "w") as f:
        f.write(text + _inp_surfaces(surfaces))


def _add_vtu_field_data(path, names):
    """Names the face groups in the VTU's FieldData, name -> [index, 2] (Gmsh's [tag, dim]
    as meshio keeps physical names): meshio 5.0 reads FieldData but does not write it."""
    from xml.sax.saxutils import quoteattr

    arrays = "".join('<DataArray type="Int32" Name=%s NumberOfTuples="2" format="ascii">%d 2'
                     '</DataArray>\n' % (quoteattr(name), k + 1) for k, name in enumerate(names))
    with open(path) as f:
        text = f.read()
    if text.count("<UnstructuredGrid>") != 1:
        raise ExportError("%s: meshio wrote no single <UnstructuredGrid> to name the face "
                          "groups in" % path)
    text = text.replace("<UnstructuredGrid>", "<UnstructuredGrid>\n<FieldData>\n%s</FieldData>"
                        % arrays, 1)
    with open(path, "w") as f:
        f.write(text)


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
