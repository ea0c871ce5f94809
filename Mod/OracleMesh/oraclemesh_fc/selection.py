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


# What the mesh command and the task panel take, for the messages that refuse anything else.
ACCEPTED = ("OracleMesh meshes solids, compounds of solids (an imported assembly), closed "
            "shells and Mesh objects: select those, highest priority first")

# Shape types in the words of a refusal ("'Plane' (Part::Plane) is a face, not a solid").
SHAPE_WORDS = {"Face": "a face", "Wire": "a wire", "Edge": "an edge", "Vertex": "a point",
               "Shell": "an open shell"}


def refusal(obj):
    """Why obj is not a mesh input, naming what it is ('' for an OracleMesh object, which is
    left out of its own inputs without a word)."""
    what = "'%s' (%s)" % (obj.Label, obj.TypeId)
    if is_oracle_mesh(obj):
        return ""
    if obj.isDerivedFrom("Mesh::Feature"):
        return "%s is an empty mesh" % what
    shape = getattr(obj, "Shape", None)
    if shape is None:
        return "%s has no shape" % what
    if shape.isNull():
        return "%s has an empty shape (recompute it)" % what
    if shape.ShapeType in SHAPE_WORDS:
        return "%s is %s, not a solid" % (what, SHAPE_WORDS[shape.ShapeType])
    parts = [(len(shape.Faces), "face"), (len(shape.Edges), "edge"), (len(shape.Vertexes), "point")]
    count, word = next(((n, w) for n, w in parts if n), (0, "shape"))
    return "%s is a %s of %d %s%s and no solid" % (what, shape.ShapeType.lower(), count, word,
                                                  "" if count == 1 else "s")


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
