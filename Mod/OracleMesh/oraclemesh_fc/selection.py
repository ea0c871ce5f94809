"""What the user has selected in the GUI, as the commands and the task panel read it: the
solids to mesh (selection order = priority), the OracleMesh object, the active analysis."""
import FreeCAD
import FreeCADGui

from .job import can_be_input
from .mesh_object import TYPE


def is_oracle_mesh(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == TYPE


def selected_solids():
    """Selected solids, compounds, shells and Mesh objects, in selection order (= priority,
    highest first)."""
    objs = []
    for sel in FreeCADGui.Selection.getSelectionEx("", 0):
        obj = sel.Object
        if can_be_input(obj) and obj not in objs and not is_oracle_mesh(obj):
            objs.append(obj)
    return objs


def selected_mesh():
    """The selected OracleMesh object (or the only one of the active document)."""
    for obj in FreeCADGui.Selection.getSelection():
        if is_oracle_mesh(obj):
            return obj
    doc = FreeCAD.ActiveDocument
    meshes = [o for o in doc.Objects if is_oracle_mesh(o)] if doc else []
    return meshes[0] if len(meshes) == 1 else None


def selected_meshed():
    """The selected OracleMesh object if it has a mesh."""
    obj = selected_mesh()
    return obj if obj is not None and obj.FemMesh.VolumeCount > 0 else None


def active_analysis():
    """The active FEM analysis, if the FEM workbench knows one."""
    try:
        import FemGui
        return FemGui.getActiveAnalysis()
    except Exception:  # FEM GUI not loaded or no active analysis
        return None
