"""Warnings about the inputs that the core's report cannot give: edges where two faces of an
input meet at a very small angle (thin wedges, or slits for reflex edges). Delaunay
refinement needs small elements there and sliver removal rarely repairs them, so the user is
told where poor elements will come from. And cuts that act on nothing: a cut removes material
from the inputs below it in the priority list only, so a cut below every material input (where
the selection order puts an object selected last) silently removes nothing."""
import math

SMALL_ANGLE_DEG = 15.0


def small_edge_angles(shape, limit_deg=SMALL_ANGLE_DEG):
    """[(edge number (1-based), angle in degrees)] of the edges of shape whose two faces meet
    at less than limit_deg (measured between the faces, at the edge's middle)."""
    import Part

    found = []
    for i, edge in enumerate(shape.Edges, start=1):
        faces = shape.ancestorsOfType(edge, Part.Face)
        if len(faces) != 2 or edge.Length <= 0:
            continue  # seam or free edge
        a, b = edge.ParameterRange
        p = edge.valueAt(0.5 * (a + b))
        normals = []
        for face in faces:
            u, v = face.Surface.parameter(p)
            normals.append(face.normalAt(u, v))  # outward: follows the face orientation
        cos = max(-1.0, min(1.0, normals[0].dot(normals[1])))
        # Outward normals nearly opposite: the faces fold onto each other.
        angle = 180.0 - math.degrees(math.acos(cos))
        if angle < limit_deg:
            found.append((i, angle))
    return found


def cut_warnings(entries):
    """Warning sentences for the cuts of [(obj, role)] (highest priority first) that have no
    material input below them."""
    warnings = []
    for i, (obj, role) in enumerate(entries):
        if role == "cut" and all(r != "material" for _, r in entries[i + 1:]):
            warnings.append("cut '%s' is below every input: it removes nothing; move it up"
                            % obj.Label)
    return warnings


def input_warnings(mesh_obj, limit_deg=SMALL_ANGLE_DEG):
    """Warning sentences for the inputs of mesh_obj (for the task panel report)."""
    from .job import MeshInputError, global_shape, priority_entries

    try:
        entries = priority_entries(mesh_obj.Inputs, mesh_obj.Cuts)
    except MeshInputError:
        return []  # reported by the mesh object itself
    warnings = cut_warnings(entries)
    for obj, role in entries:
        try:
            edges = small_edge_angles(global_shape(obj), limit_deg)
        except Exception:  # bad inputs are reported by the mesh object itself
            continue
        if edges:
            worst = min(edges, key=lambda e: e[1])
            warnings.append(
                "input '%s': %d edge(s) where faces meet at less than %g deg (Edge%d: %.1f "
                "deg); expect small, flat elements there" % (obj.Label, len(edges), limit_deg,
                                                             worst[0], worst[1]))
    return warnings
