# OracleMesh workbench, GUI part: a toolbar and a menu with "Mesh selection with OracleMesh".


class OracleMeshWorkbench(Workbench):  # noqa: F821 (Workbench is provided by FreeCAD)
    MenuText = "OracleMesh"
    ToolTip = "Multi-material tetrahedral FEM meshes of overlapping solids, composed by priority"

    def __init__(self):
        from oraclemesh_fc import icon_path
        self.__class__.Icon = icon_path()

    def Initialize(self):
        from oraclemesh_fc import commands
        names = commands.register()
        self.appendToolbar("OracleMesh", names)
        self.appendMenu("OracleMesh", names)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(OracleMeshWorkbench())  # noqa: F821
