# OracleMesh workbench, GUI part: toolbar and menu (mesh selection, edit, export, quality
# histogram) and the preferences page.


class OracleMeshWorkbench(Workbench):  # noqa: F821 (Workbench is provided by FreeCAD)
    MenuText = "OracleMesh"
    ToolTip = "Multi-material tetrahedral FEM meshes of overlapping solids, composed by priority"

    def __init__(self):
        from oraclemesh_fc.icons import icon_path
        self.__class__.Icon = icon_path()

    def Initialize(self):
        import FreeCADGui
        from oraclemesh_fc import commands, preferences
        names = commands.register()
        self.appendToolbar("OracleMesh", names)
        self.appendMenu("OracleMesh", names)
        FreeCADGui.addPreferencePage(preferences.PreferencePage, "OracleMesh")

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(OracleMeshWorkbench())  # noqa: F821
