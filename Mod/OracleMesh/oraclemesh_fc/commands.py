"""GUI commands: mesh the selection (opens the task panel), edit a mesh, export a mesh,
quality histogram."""
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
        if can_be_input(obj) and obj not in objs and not is_oracle_mesh(obj):
            objs.append(obj)
    return objs


def is_oracle_mesh(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", None) == "Fem::OracleMesh"


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


class CommandMeshSelection:

    def GetResources(self):
        return {
            "Pixmap": icon_path("OracleMesh_MeshSelection.svg"),
            "MenuText": "Mesh selection with OracleMesh",
            "ToolTip": "Tetrahedral FEM mesh of the selected solids: the first selected wins "
                       "where solids overlap. The mesh goes into the active FEM analysis; its "
                       "task panel opens for sizes, materials and priorities.",
        }

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(FreeCADGui.Selection.getSelection())

    def Activated(self):
        from PySide import QtGui
        from .mesh_object import makeMesh
        from . import preferences

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
        preferences.apply_defaults(mesh)
        for obj in inputs:
            obj.ViewObject.Visibility = False
        doc.commitTransaction()
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(mesh)
        # The user meshes from the panel (Mesh button) after checking priorities and sizes.
        from .task_panel import open_panel
        open_panel(mesh)


class CommandEdit:

    def GetResources(self):
        return {"Pixmap": icon_path("OracleMesh_Mesh.svg"),
                "MenuText": "Edit OracleMesh mesh",
                "ToolTip": "Open the task panel of the selected OracleMesh mesh"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_mesh() is not None \
            and not FreeCADGui.Control.activeDialog()

    def Activated(self):
        from .task_panel import open_panel
        open_panel(selected_mesh())


class CommandExport:

    def GetResources(self):
        return {"Pixmap": icon_path("OracleMesh_Export.svg"),
                "MenuText": "Export OracleMesh mesh...",
                "ToolTip": "Write the selected mesh with its material groups as VTU, "
                           "CalculiX INP or Gmsh MSH"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_meshed() is not None

    def Activated(self):
        from .export import export_dialog
        export_dialog(selected_meshed())


class CommandHistogram:

    def GetResources(self):
        return {"Pixmap": icon_path("OracleMesh_Histogram.svg"),
                "MenuText": "Mesh quality histogram",
                "ToolTip": "Histogram of the smallest dihedral angle per tetrahedron; the "
                           "worst elements can be selected and highlighted"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_meshed() is not None

    def Activated(self):
        from .quality import show_histogram
        show_histogram(selected_meshed())


COMMANDS = {
    "OracleMesh_MeshSelection": CommandMeshSelection(),
    "OracleMesh_Edit": CommandEdit(),
    "OracleMesh_Export": CommandExport(),
    "OracleMesh_Histogram": CommandHistogram(),
}


def register():
    for name, command in COMMANDS.items():
        FreeCADGui.addCommand(name, command)
    return list(COMMANDS)
