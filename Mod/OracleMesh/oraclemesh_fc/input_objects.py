"""FreeCAD objects as mesh inputs, before any job is built: their shapes and meshes in
global coordinates, the priority order of Inputs and Cuts, the error for a bad input."""
import FreeCAD


class MeshInputError(Exception):
    """A user error found on the FreeCAD side (before the core sees the job)."""


def global_shape(obj):
    """The object's shape in global coordinates (placement of containers applied)."""
    import Part

    if not hasattr(obj, "Shape") and not obj.isDerivedFrom("App::Link"):
        raise MeshInputError(
            "input '%s' (%s) has no shape: link solids (Part/PartDesign objects) or Mesh "
            "objects only" % (obj.Label, obj.TypeId))
    shape = Part.getShape(obj)  # follows App::Link and applies the object's own placement
    if shape.isNull():
        raise MeshInputError("input '%s' has an empty shape: recompute it or remove it from "
                             "the mesh inputs" % obj.Label)
    # Part.getShape applies the object's own placement; add the placement of any container
    # (App::Part, groups with placement) it lives in.
    own = obj.Placement if hasattr(obj, "Placement") else FreeCAD.Placement()
    parent = obj.getGlobalPlacement().multiply(own.inverse())
    if not parent.isIdentity():
        shape = shape.copy()
        shape.Placement = parent.multiply(shape.Placement)
    return shape


def is_mesh_feature(obj):
    """A FreeCAD Mesh object (Mesh::Feature and its Python subclasses): a triangle surface."""
    return obj.isDerivedFrom("Mesh::Feature")


def global_mesh(obj):
    """(points, triangles) of a Mesh feature in global coordinates.

    FreeCAD applies the feature's own Placement to the points it returns; the placement of
    any container (App::Part, groups with placement) is added here, as for shapes."""
    points, triangles = obj.Mesh.Topology
    if not triangles:
        raise MeshInputError("input '%s' is an empty mesh: recompute it or remove it from the "
                             "mesh inputs" % obj.Label)
    parent = obj.getGlobalPlacement().multiply(obj.Placement.inverse())
    if not parent.isIdentity():
        points = [parent.multVec(p) for p in points]
    return [[p.x, p.y, p.z] for p in points], [list(t) for t in triangles]


def priority_entries(inputs, cuts):
    """[(obj, role)] highest priority first; see the module docstring for the cut rule."""
    inputs, cuts = list(inputs), list(cuts)
    names = [o.Name for o in inputs]
    for o in inputs:
        if names.count(o.Name) > 1:
            raise MeshInputError("input '%s' is listed twice in Inputs: list each object once"
                                 % o.Label)
    cut_names = {o.Name for o in cuts}
    entries = [(o, "cut") for o in cuts if o.Name not in names]
    entries += [(o, "cut" if o.Name in cut_names else "material") for o in inputs]
    return entries
