"""Base of the workbench's Python proxies (the mesh object's and its view provider's).

Everything a proxy needs lives in the object's properties, so a saved document holds no
proxy state: both ways FreeCAD stores a proxy (__getstate__/__setstate__ up to 0.20,
dumps/loads from 0.21 on) store nothing and restore nothing.
"""


class StatelessProxy:

    def dumps(self):
        return None

    def loads(self, state):
        return None

    __getstate__ = dumps
    __setstate__ = loads
