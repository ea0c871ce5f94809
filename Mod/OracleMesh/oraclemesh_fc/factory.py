"""Makes OracleMesh mesh objects: makeMesh, the API of macros and scripts (and of the GUI
command, which writes its call into the macro recorder), also `from oraclemesh_fc import
makeMesh`.

The object itself (properties, recompute) is mesh_object.py; its view provider, attached
here when the GUI is up, is view_provider.py.
"""
import FreeCAD

from .job import check_interface_parts, extra_edge_links
from . import interfaces, step_labels
from .mesh_object import OracleMeshProxy
from .parts import input_parts, store_cad_uncertainty, store_labels


# makeMesh keyword -> property. Sizes accept numbers in model units (mm).
OPTION_PROPERTIES = {
    "cell_size": "CellSize",
    "cell_radius_edge_ratio": "CellRadiusEdgeRatio",
    "facet_size": "FacetSize",
    "facet_distance": "FacetDistance",
    "facet_angle": "FacetAngle",
    "edge_size": "EdgeSize",
    "element_order": "ElementOrder",
    "sharp_angle": "SharpAngle",
    "optimize": "Optimize",
    "seed": "Seed",
    "max_vertices": "MaxVertices",
    "time_limit": "TimeLimit",
    "junctions": "Junctions",
    "planar_faces": "PlanarFaces",
    "engine": "Engine",
    "fineness": "Fineness",
    "checks": "Checks",
    "contact_tolerance": "ContactTolerance",
}


def makeMesh(doc, inputs, analysis=None, cuts=(), name="OracleMesh", **job_options):
    """Make an OracleMesh mesh object (not recomputed; call doc.recompute()).

    inputs: solids, compounds of solids or Mesh objects, highest priority first. cuts: regions removed from every input.
    analysis: a FEM analysis to add the mesh to (its FEM materials name the volume groups).
    job_options: cell_size, cell_radius_edge_ratio, facet_size, facet_distance, facet_angle,
    edge_size, element_order (1 or 2), sharp_angle (degrees; 0/None/False = no sharp edges
    and junctions), junctions (bool), planar_faces (bool, thesis engine: planar faces stay flat),
    engine ("thesis", the default, or "cgal"), fineness ("moderate", the default, "off", "very coarse",
    "coarse", "fine" or "very fine": sizes from the geometry), checks ("error", the default: a
    mesh that misses a part's volume, splits or joins parts is refused; or "warn": kept, with
    the problems as warnings),
    contact_tolerance (parts closer than this are bonded, farther apart they stay apart; 0, the
    default: the CAD's own tolerance, at least 1e-6 of the diagonal), optimize, seed, max_vertices, time_limit,
    whole_inputs (compounds meshed as one input instead of one part per solid), step_file
    (the STEP file compound inputs were imported from: their solids' names),
    material_sizes ({input object, Name or Label: cell size or dict of criteria}), output
    ({"files": [...], "report": path}), extra_edges (curves kept as mesh edges: objects
    (every edge: a sketch, a wire) or (object, "EdgeN") / (object, ["Edge1", ...]) pairs),
    interfaces (how touching parts are joined: {"default": "bonded", "pairs": [{"between":
    ["Pin", "Plate"], "kind": "contact", "friction": 0.2, "master": "Plate"}]}, kinds bonded,
    tied, contact, separate, parts by label or as objects; see interfaces.py).
    """
    known = set(OPTION_PROPERTIES) | {"material_sizes", "output", "extra_edges", "whole_inputs",
                                      "step_file", "interfaces"}
    unknown = sorted(set(job_options) - known)
    if unknown:
        raise TypeError("makeMesh() got unknown option(s) %s: known options are %s"
                        % (", ".join(unknown), ", ".join(sorted(known))))
    if analysis is not None and analysis.Document.Name != doc.Name:
        # Checked before the object exists, so a refused call leaves no orphan mesh behind.
        raise ValueError("makeMesh: analysis '%s' is in document '%s', the mesh would be in '%s': "
                         "an analysis holds objects of its own document only; pass an analysis "
                         "of '%s' or none" % (analysis.Label, analysis.Document.Label, doc.Label,
                                              doc.Label))

    # Checked before the object exists too: a refused call leaves nothing behind.
    settings = interfaces.normalized(job_options.get("interfaces"), "makeMesh(interfaces=...)")

    obj = doc.addObject("Fem::FemMeshObjectPython", name)
    OracleMeshProxy(obj)
    if FreeCAD.GuiUp:
        from .view_provider import ViewProviderOracleMesh
        ViewProviderOracleMesh(obj.ViewObject)

    obj.Inputs = list(inputs)
    obj.Cuts = list(cuts)
    obj.WholeInputs = list(job_options.get("whole_inputs") or ())
    step_labels.extra_files[:] = [job_options["step_file"]] if job_options.get("step_file") else []
    try:
        store_labels(obj, [p for p, _ in input_parts(obj)])
        store_cad_uncertainty(obj)
    finally:
        step_labels.extra_files[:] = []
    for key, prop in OPTION_PROPERTIES.items():
        if key in job_options:
            value = job_options[key]
            if key == "sharp_angle" and value in (None, False):
                value = 0.0
            setattr(obj, prop, value)
    sizes = {}
    for key, value in (job_options.get("material_sizes") or {}).items():
        key = key if isinstance(key, str) else key.Name
        if isinstance(value, dict):
            value = " ".join("%s=%r" % (k, float(v)) for k, v in value.items())
        sizes[key] = str(value)
    obj.InputSizes = sizes
    output = job_options.get("output") or {}
    obj.OutputFiles = [str(f) for f in output.get("files", [])]
    obj.OutputReport = str(output.get("report", ""))
    obj.ExtraEdges = extra_edge_links(job_options.get("extra_edges") or ())
    obj.Interfaces = interfaces.to_text(settings)
    try:
        check_interface_parts(settings, input_parts(obj), "makeMesh(interfaces=...)")
    except interfaces.InterfaceSettingsError:
        doc.removeObject(obj.Name)
        raise
    if analysis is not None:
        analysis.addObject(obj)
    return obj
