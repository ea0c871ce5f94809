"""GUI command "Mesh selection with OracleMesh"."""
import FreeCAD
import FreeCADGui

from . import icon_path


def active_analysis():
    """The active FEM analysis, if the FEM workbench knows one."""
    try:
        import FemGui
        return FemGui.getActiveAnalysis()
    except Exception:  # FEM GUI not loaded or no active analysis
        return None


def selected_solids():
    """Selected solids, compounds, shells and Mesh objects, in selection order (= priority,
    highest first)."""
    from .job import can_be_input
    objs = []
    for sel in FreeCADGui.Selection.getSelectionEx("", 0):
        obj = sel.Object
        if can_be_input(obj) and obj not in objs:
            objs.append(obj)
    return objs


class CommandMeshSelection:

    def GetResources(self):
        return {
            "Pixmap": icon_path(),
            "MenuText": "Mesh selection with OracleMesh",
            "ToolTip": "Tetrahedral FEM mesh of the selected solids: the first selected wins "
                       "where solids overlap. The mesh goes into the active FEM analysis.",
        }

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(FreeCADGui.Selection.getSelection())

    def Activated(self):
        from PySide import QtGui
        from .mesh_object import makeMesh

        doc = FreeCAD.ActiveDocument
        inputs = selected_solids()
        if not inputs:
            QtGui.QMessageBox.warning(
                FreeCADGui.getMainWindow(), "OracleMesh",
                "Select one or more solids (or compounds, Mesh objects), highest priority first.")
            return
        analysis = active_analysis()
        doc.openTransaction("OracleMesh mesh")
        mesh = makeMesh(doc, inputs, analysis=analysis)
        for obj in inputs:
            obj.ViewObject.Visibility = False
        doc.commitTransaction()
        # Errors are reported by the object itself (report view + message box); the mesh
        # object stays so the user can fix its properties and recompute.
        doc.recompute()
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(mesh)


COMMANDS = {"OracleMesh_MeshSelection": CommandMeshSelection()}


def register():
    for name, command in COMMANDS.items():
        FreeCADGui.addCommand(name, command)
    return list(COMMANDS)
