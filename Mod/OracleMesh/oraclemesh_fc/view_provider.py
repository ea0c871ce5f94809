"""View provider of the OracleMesh object (GUI only): icon, the mesh coloured by material with
its feature edges (display.py), and the task panel (task_panel.py) in edit mode (setEdit):
entered by the commands' recorded FreeCADGui.ActiveDocument.setEdit lines, and by double
click and the context menu through open_panel."""
import FreeCAD
import FreeCADGui

from . import display
from .icons import icon_path
from .proxy import StatelessProxy


class ViewProviderOracleMesh(StatelessProxy):

    def __init__(self, vobj):
        vobj.Proxy = self
        # Faces only: the drawn feature edges stand out instead of every triangle edge.
        vobj.DisplayMode = "Faces"

    def attach(self, vobj):
        self.Object = vobj.Object
        self.ViewObject = vobj
        self.edge_node = display.FeatureEdgeNode()
        self.edge_node.attach_to(vobj.RootNode)

    def updateData(self, obj, prop):
        if prop == "FemMesh" and hasattr(self, "edge_node"):
            # FreeCAD's own FEM view rebuilds (and resets the colours) after this call:
            # colour once control is back in the event loop.
            from PySide import QtCore
            QtCore.QTimer.singleShot(0, lambda: self.show(obj))

    def onChanged(self, vobj, prop):
        # ShowInner makes FreeCAD's view draw another set of faces: colour them again.
        if prop == "ShowInner" and hasattr(self, "edge_node"):
            from PySide import QtCore
            QtCore.QTimer.singleShot(0, lambda: self.show(vobj.Object))

    def show(self, obj):
        try:
            self.shown = display.show(obj, self.edge_node)
        except Exception as e:  # a deleted object or view: nothing to colour
            FreeCAD.Console.PrintLog("OracleMesh: colouring skipped: %s\n" % e)

    def getIcon(self):
        return icon_path("OracleMesh_Mesh.svg")

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None  # transform etc.: FreeCAD's default
        from .task_panel import TaskPanel
        FreeCADGui.Control.showDialog(TaskPanel(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        if FreeCADGui.Control.activeDialog():
            FreeCAD.Console.PrintWarning(
                "OracleMesh: close the open task dialog first, then edit '%s'\n"
                % vobj.Object.Label)
            return True
        open_panel(vobj.Object)
        return True

    def setupContextMenu(self, vobj, menu):
        from PySide import QtGui
        action = QtGui.QAction("Edit OracleMesh mesh...", menu)
        action.triggered.connect(lambda: self.doubleClicked(vobj))
        menu.addAction(action)


def open_panel(mesh_obj):
    """Open the task panel of mesh_obj through FreeCAD's edit mode (as a double click does);
    returns the panel."""
    from . import task_panel
    FreeCADGui.getDocument(mesh_obj.Document.Name).setEdit(mesh_obj.Name, 0)
    return task_panel.current
