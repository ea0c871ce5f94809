"""View provider of the OracleMesh object (GUI only): icon; display is FreeCAD's FEM mesh."""


class ViewProviderOracleMesh:

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        from . import icon_path
        return icon_path()

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps = __getstate__
    loads = __setstate__
