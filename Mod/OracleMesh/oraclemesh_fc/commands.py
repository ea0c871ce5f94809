"""GUI commands: mesh the selection (opens the task panel), edit a mesh, export a mesh,
quality histogram.

As FreeCAD's own FEM commands, they act through FreeCADGui.doCommand (document changes) and
FreeCADGui.doCommandGui (views, dialogs), so the Python console shows, and the macro
recorder records, what a command did: a recorded macro makes the same mesh object. They
import neither the mesh object nor its task panel; the view provider opens the panel in
edit mode.
"""
import FreeCAD
import FreeCADGui

from .icons import icon_path
from .selection import (ACCEPTED, active_analysis, refusal, selected_mesh, selected_meshed,
                        selected_solids)


def object_expression(obj):
    """Python text naming obj in a recorded line."""
    if obj.Document == FreeCAD.ActiveDocument:
        return "FreeCAD.ActiveDocument.getObject(%r)" % obj.Name
    return "FreeCAD.getDocument(%r).getObject(%r)" % (obj.Document.Name, obj.Name)


def make_mesh_line(variable, inputs, analysis, options):
    """The recorded makeMesh call: inputs in priority order, options as values."""
    arguments = ["FreeCAD.ActiveDocument",
                 "[%s]" % ", ".join(object_expression(o) for o in inputs)]
    if analysis is not None:
        arguments.append("analysis=%s" % object_expression(analysis))
    arguments += ["%s=%r" % (key, value) for key, value in sorted(options.items())]
    return "%s = oraclemesh_fc.makeMesh(%s)" % (variable, ", ".join(arguments))


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
        from . import preferences

        doc = FreeCAD.ActiveDocument
        inputs = selected_solids()
        refused = [refusal(o) for o in FreeCADGui.Selection.getSelection() if o not in inputs]
        if not inputs:
            QtGui.QMessageBox.warning(
                FreeCADGui.getMainWindow(), "OracleMesh",
                "Nothing to mesh: %s. %s" % ("; ".join(r for r in refused if r), ACCEPTED))
            return
        for text in refused:
            if text:
                FreeCAD.Console.PrintWarning("OracleMesh: left out %s. %s\n" % (text, ACCEPTED))
        analysis = active_analysis()
        if analysis is not None and analysis.Document.Name != doc.Name:
            # An analysis groups objects of its own document only: this mesh joins none.
            FreeCAD.Console.PrintWarning(
                "OracleMesh: the active analysis '%s' is in document '%s', so the mesh of "
                "'%s' is not added to it; activate an analysis of '%s' and add the mesh there "
                "to use it\n" % (analysis.Label, analysis.Document.Label, doc.Label, doc.Label))
            analysis = None
        doc.openTransaction("OracleMesh mesh")
        try:
            FreeCADGui.addModule("oraclemesh_fc")
            FreeCADGui.doCommand(make_mesh_line("oracle_mesh", inputs, analysis,
                                                preferences.mesh_options(inputs)))
        except Exception:
            doc.abortTransaction()
            raise
        doc.commitTransaction()
        # The inputs stay visible until there is a mesh to show instead (the task panel hides
        # them after meshing), so a failed first mesh does not leave an empty view.
        # Nothing stays selected: FreeCAD would draw the selected mesh all in its highlight
        # colour, over the material colours.
        FreeCADGui.Selection.clearSelection()
        # The user meshes from the panel (Mesh button) after checking priorities and sizes.
        FreeCADGui.doCommandGui("FreeCADGui.ActiveDocument.setEdit(oracle_mesh.Name, 0)")


class CommandEdit:

    def GetResources(self):
        return {"Pixmap": icon_path("OracleMesh_Mesh.svg"),
                "MenuText": "Edit OracleMesh mesh",
                "ToolTip": "Open the task panel of the selected OracleMesh mesh"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_mesh() is not None \
            and not FreeCADGui.Control.activeDialog()

    def Activated(self):
        FreeCADGui.doCommandGui("FreeCADGui.ActiveDocument.setEdit(%r, 0)" % selected_mesh().Name)


class CommandExport:

    def GetResources(self):
        return {"Pixmap": icon_path("OracleMesh_Export.svg"),
                "MenuText": "Export OracleMesh mesh...",
                "ToolTip": "Write the selected mesh with its material groups as VTU, "
                           "CalculiX INP or Gmsh MSH"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_meshed() is not None

    def Activated(self):
        FreeCADGui.addModule("oraclemesh_fc.export")
        FreeCADGui.doCommandGui("oraclemesh_fc.export.export_dialog(%s)"
                                % object_expression(selected_meshed()))


class CommandHistogram:

    def GetResources(self):
        return {"Pixmap": icon_path("OracleMesh_Histogram.svg"),
                "MenuText": "Mesh quality histogram",
                "ToolTip": "Histogram of the smallest dihedral angle per tetrahedron; the "
                           "worst elements can be selected and highlighted"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and selected_meshed() is not None

    def Activated(self):
        FreeCADGui.addModule("oraclemesh_fc.quality")
        FreeCADGui.doCommandGui("oraclemesh_fc.quality.show_histogram(%s)"
                                % object_expression(selected_meshed()))


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
