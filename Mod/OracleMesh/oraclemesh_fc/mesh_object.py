"""The OracleMesh FEM mesh object: a Fem::FemMeshObjectPython whose recompute runs the core.

Its properties are the job (inputs in priority order, cuts, sizes, element order, sharp-edge
angle, extra edges); execute() builds the job from the linked shapes, runs the core and replaces FemMesh
with the result, one volume group per material (see job.volume_groups). On any error, in the
job, the core or the hand-off, the previous FemMesh stays as it was, the error goes into
Status and the report view (and a message box in the GUI) and execute() raises, so FreeCAD
marks the object as failed.
Objects are made by factory.makeMesh.
"""
import json
import time

import FreeCAD

from . import ccx_interfaces
from .handoff import build_femmesh, feature_edge_mid_nodes
from .input_checks import cut_warnings
from .job import MeshInputError, build_job, input_kinds, in_mesh_object_words, priority_entries
from .proxy import StatelessProxy
from .runner import import_core, run_job
from .sizes import DEFAULT_FINENESS, FINENESS_NAMES

# The job's "engine" values; the first is the default of new mesh objects. Rule Set T is the
# default since it beat Mesh_3 on the refine benchmark (issue 7).
ENGINE_NAMES = ("thesis", "cgal")
# Enumerations whose default is not their first choice.
ENUMERATION_DEFAULTS = {"Fineness": DEFAULT_FINENESS}
# The core's "checks", its default first: a mesh that misses volume of a part, splits it or
# joins two parts is refused (the previous mesh is kept), or kept with warnings.
CHECK_MODES = ("error", "warn")
# What documents saved before these properties existed were meshed with: restored, they keep
# meshing as they did (new mesh objects get the defaults above).
VALUES_OF_OLD_DOCUMENTS = {"Engine": "cgal", "Fineness": "off", "Checks": "warn"}

TYPE = ccx_interfaces.MESH_TYPE


# FreeCAD's CalculiX writer gets the ties and contacts of OracleMesh meshes from here on: this
# module is imported wherever a mesh object exists (made, or restored from a document).
ccx_interfaces.install()


class MeshingFailed(Exception):
    """Raised from execute() so FreeCAD marks the object invalid; the text is for the user."""


# (type, name, group, tooltip, default)
PROPERTIES = (
    ("App::PropertyLinkList", "Inputs", "Inputs",
     "Solids to mesh, highest priority first: where inputs overlap, the earlier one wins", None),
    ("App::PropertyStringList", "InputKinds", "Inputs",
     "What each input is to the mesher, in priority order: B-rep solid, B-rep compound (one "
     "input per solid), triangle surface (Mesh object); updated on recompute", None),
    ("App::PropertyLinkList", "Cuts", "Inputs",
     "Regions removed from every input (a cut also listed in Inputs acts only on the inputs "
     "after it)", None),
    ("App::PropertyMap", "InputSizes", "Sizes",
     "Per-input sizes: key = Name or Label of an input, value = a cell size ('1.5') or "
     "'cell_size=1.5 facet_distance=0.05'", None),
    ("App::PropertyLength", "CellSize", "Sizes",
     "Largest tetrahedron circumradius (0 = automatic: model diagonal / 15)", 0.0),
    ("App::PropertyFloat", "CellRadiusEdgeRatio", "Sizes",
     "Largest circumradius / shortest edge of a tetrahedron (0 = automatic: 2)", 0.0),
    ("App::PropertyLength", "FacetSize", "Sizes",
     "Largest surface triangle size (0 = automatic: the cell size)", 0.0),
    ("App::PropertyLength", "FacetDistance", "Sizes",
     "Largest distance of a surface triangle from the CAD surface (0 = automatic: facet size/10)",
     0.0),
    ("App::PropertyAngle", "FacetAngle", "Sizes",
     "Smallest surface triangle angle, at most 30 degrees (0 = automatic: 25)", 0.0),
    ("App::PropertyLength", "EdgeSize", "Sizes",
     "Largest segment length along sharp edges (0 = automatic: facet size/2)", 0.0),
    ("App::PropertyEnumeration", "Fineness", "Sizes",
     "Sizes from the geometry below the sizes above: segments per circle on curved faces "
     "(6 / 8 / 12 / 18 / 24 from very coarse to very fine), two segments per short sharp edge, "
     "walls several sizes thick, graded (moderate by default); off = the sizes above alone",
     list(FINENESS_NAMES)),
    ("App::PropertyEnumeration", "Checks", "Mesh",
     "A mesh that fails its self-check (a part more than 1 % off its CAD volume, split into "
     "pieces, or two parts joined across a gap): warn = kept, the problems in Status and the "
     "report view; error = refused, the previous mesh is kept",
     list(CHECK_MODES)),
    ("App::PropertyLength", "ContactTolerance", "Mesh",
     "Parts closer than this touch and are bonded; parts farther apart stay apart (with a "
     "Fineness, the sizes resolve the gap). 0 = automatic: the CAD's own tolerance (the "
     "shapes' tolerances and the uncertainty the STEP file they came from declares, "
     "CadUncertainty), at least 1e-6 of the model diagonal", 0.0),
    ("App::PropertyLength", "CadUncertainty", "Mesh",
     "The uncertainty the STEP file the inputs were imported from declares (found when the "
     "inputs are set); the automatic ContactTolerance is at least this", 0.0),
    ("App::PropertyIntegerConstraint", "ElementOrder", "Mesh",
     "1 = linear tetrahedra (C3D4), 2 = quadratic tetrahedra (C3D10, mid nodes on the CAD faces)",
     (2, 1, 2, 1)),
    ("App::PropertyAngle", "SharpAngle", "Mesh",
     "B-rep edges whose faces meet at more than this angle are kept as mesh edges (0 = no "
     "sharp edges and no junctions; extra edges are kept)",
     30.0),
    ("App::PropertyBool", "Optimize", "Mesh", "Remove slivers (thesis: sliver rule, vertex moves; CGAL: perturb, exude)", True),
    ("App::PropertyInteger", "Seed", "Mesh", "Random seed (the same job gives the same mesh)", 0),
    ("App::PropertyInteger", "MaxVertices", "Limits",
     "Refuse jobs that would need more vertices than this", 5000000),
    ("App::PropertyFloat", "TimeLimit", "Limits", "Stop meshing after this many seconds", 3600.0),
    ("App::PropertyStringList", "OutputFiles", "Output",
     "Mesh files the core also writes (.vtu, .inp), optional", None),
    ("App::PropertyString", "OutputReport", "Output",
     "Path of the JSON report the core also writes, optional", ""),
    ("App::PropertyEnumeration", "Engine", "Mesh",
     "Meshing engine: thesis (default; Rule Set T: constrained segments, per-material "
     "radius-edge ratio) or cgal (CGAL Mesh_3 with protecting balls)",
     list(ENGINE_NAMES)),
    ("App::PropertyBool", "Junctions", "Mesh",
     "Keep the curves where inputs meet (material junctions) as mesh edges", True),
    ("App::PropertyBool", "PlanarFaces", "Mesh",
     "Keep planar faces bounded by sharp edges flat, e.g. planar contact faces of an assembly "
     "(engine thesis only; needs a sharp-edge angle above 0 and Junctions)", False),
    ("App::PropertyMap", "InputMaterialNames", "Inputs",
     "Volume group name per input without a FEM material: key = input Name (or Name.SolidK "
     "for one solid of a compound), value = a material name (group '<name>_Volumes')", None),
    ("App::PropertyLinkList", "WholeInputs", "Inputs",
     "Compounds meshed as one input (one material, one group) instead of one part per solid",
     None),
    ("App::PropertyStringList", "PartOrder", "Inputs",
     "Priority order of the parts, one by one: Name of a whole input or Name.SolidK of one "
     "solid of a compound (parts not listed follow in the order of Inputs)", None),
    ("App::PropertyMap", "PartLabels", "Inputs",
     "Label of each solid of a compound: key = Name.SolidK, value = the label (from the STEP "
     "file or the compound's links when found; names the part's volume group)", None),
    ("App::PropertyLinkSubList", "ExtraEdges", "Mesh",
     "Extra curves kept as chains of mesh edges: picked edges (EdgeN) of any shape, and whole "
     "sketches or shapes (all their edges); each must lie inside or on the meshed parts", None),
    ("App::PropertyString", "Interfaces", "Interfaces",
     "How touching parts are joined, as JSON: {\"default\": \"bonded\", \"pairs\": "
     "[{\"between\": [\"Pin\", \"Plate\"], \"kind\": \"contact\"}]}; kinds bonded (shared "
     "nodes), tied (*TIE), contact (*CONTACT PAIR, optional \"friction\"), separate; parts "
     "named as the report's interfaces name them; empty = all bonded. Ties and contacts "
     "reach FreeCAD's CalculiX input by themselves (ccx_interfaces.py)", ""),
    ("App::PropertyIntegerList", "FeatureEdges", "Output",
     "Sharp and junction edges of the last mesh, as pairs of FemMesh node ids (drawn by the "
     "view)", None),
    ("App::PropertyIntegerList", "FeatureEdgeMidNodes", "Output",
     "FemMesh id of the mid node of each feature edge (quadratic meshes; empty for linear)",
     None),
    ("App::PropertyString", "Status", "Output", "Result of the last recompute", ""),
    ("App::PropertyString", "Report", "Output", "JSON report of the last successful mesh", ""),
)
READ_ONLY = ("Status", "Report", "InputKinds", "CadUncertainty")
HIDDEN = ("FeatureEdges", "FeatureEdgeMidNodes")


class OracleMeshProxy(StatelessProxy):
    """Proxy of the mesh object. Stateless: everything lives in the object's properties."""

    Type = TYPE

    def __init__(self, obj):
        obj.Proxy = self
        self.add_properties(obj)

    @staticmethod
    def add_properties(obj):
        # Also called on restore, so documents saved by older versions gain new properties.
        for ptype, name, group, tip, default in PROPERTIES:
            if hasattr(obj, name):
                continue
            obj.addProperty(ptype, name, group, tip)
            if default is not None:
                setattr(obj, name, default)
            if name in ENUMERATION_DEFAULTS:
                setattr(obj, name, ENUMERATION_DEFAULTS[name])
            if name in READ_ONLY:
                obj.setEditorMode(name, 1)
            if name in HIDDEN:
                obj.setEditorMode(name, 2)

    def onDocumentRestored(self, obj):
        missing = [name for name in VALUES_OF_OLD_DOCUMENTS if not hasattr(obj, name)]
        self.add_properties(obj)
        for name in missing:
            setattr(obj, name, VALUES_OF_OLD_DOCUMENTS[name])
        # Documents saved by other versions list other choices (or another order): keep the
        # stored engine.
        if list(obj.getEnumerationsOfProperty("Engine")) != list(ENGINE_NAMES):
            chosen = obj.Engine
            obj.Engine = list(ENGINE_NAMES)
            obj.Engine = chosen

    def onChanged(self, obj, prop):
        # The user sees at once what a newly linked object is to the mesher. Not while a
        # document loads: the saved list is already right and linked shapes may not be yet.
        if prop in ("Inputs", "Cuts") and hasattr(obj, "InputKinds") and "Restore" not in obj.State:
            try:
                kinds = input_kinds(obj)
            except MeshInputError as e:  # an object listed twice: said here, refused on recompute
                kinds = ["not usable: %s" % e]
            if list(obj.InputKinds) != kinds:
                obj.InputKinds = kinds

    def execute(self, obj):
        # Everything that can fail runs before the first output property is written, and any
        # failure (the job, the core, the hand-off, the report) becomes the same message in
        # Status, the report view and (GUI) a message box: never a bare traceback.
        polyline_names, kinds, described = [], None, ()
        had_mesh = obj.FemMesh.VolumeCount > 0
        started = time.time()
        try:
            kinds = input_kinds(obj)
            job, groups, described, polyline_names = build_job(obj)
            result = run_job(job, obj.Label)
            femmesh = build_femmesh(result.points, result.tets, result.tet_materials, groups,
                                    [(s["name"], s["faces"]) for s in result.surfaces])
            outputs = mesh_outputs(result, groups, described, polyline_names, femmesh, time.time() - started)
        except Exception as e:
            # The core names extra edges and materials by their place in the job: say which
            # edge and which part it is.
            message = "OracleMesh '%s' failed%s: %s" % (
                obj.Label, ", the previous mesh is kept" if had_mesh else "",
                in_mesh_object_words(error_text(e), polyline_names, described))
            if kinds is not None:
                obj.InputKinds = kinds
            obj.Status = message
            FreeCAD.Console.PrintError(message + "\n")
            if FreeCAD.GuiUp and not is_cancel(e):  # the user asked for it: no error box
                show_error(message)
            raise MeshingFailed(message) from None
        obj.InputKinds = kinds
        obj.FeatureEdges, obj.FeatureEdgeMidNodes, obj.Report, status, warnings = outputs
        obj.FemMesh = femmesh
        obj.Status = status
        # The core's warnings (with Checks = warn, a part short of volume, split or joined is
        # one) go to the report view as well as the task panel: a macro user sees them too.
        for warning in warnings + cut_warnings(priority_entries(obj.Inputs, obj.Cuts)):
            FreeCAD.Console.PrintWarning("OracleMesh '%s': %s\n" % (obj.Label, warning))


def mesh_outputs(result, groups, described, polyline_names, femmesh, wall_seconds):
    """(FeatureEdges, FeatureEdgeMidNodes, Report, Status, the report's warnings) of a mesh:
    everything execute() writes or prints besides FemMesh, computed before anything is
    written. The warnings name what the mesh object calls things (extra edges, InputSizes
    keys, the Checks property)."""
    report = dict(result.report)
    report["warnings"] = [in_mesh_object_words(w, polyline_names, described) for w in report.get("warnings", [])]
    report["freecad"] = {
        "inputs": [{"name": p.key, "label": p.label, "role": role, "material": mid,
                    "group": next((g for g, ids in groups if mid in ids), None)}
                   for p, role, mid in described],
        "groups": {g: ids for g, ids in groups},
        # What the user waited for: the phases in report["seconds"] nest and overlap.
        "wall_seconds": wall_seconds,
    }
    edges = (result.feature_edges.reshape(-1) + 1).tolist()  # FemMesh ids
    mids = [m + 1 for m in feature_edge_mid_nodes(result.tets, result.feature_edges)]
    volume_groups = [g for g in femmesh.Groups if femmesh.getGroupElementType(g) == "Volume"]
    status = "%d nodes, %d %s; groups: %s; %d face groups (interfaces and exteriors)" % (
        femmesh.NodeCount, femmesh.VolumeCount,
        "tet10" if result.tets.shape[1] == 10 else "tet4",
        ", ".join("%s %d" % (femmesh.getGroupName(g), len(femmesh.getGroupElements(g)))
                  for g in volume_groups),
        len(femmesh.Groups) - len(volume_groups))
    return edges, mids, json.dumps(report, indent=1, sort_keys=True), status, report["warnings"]


def is_cancel(error):
    try:
        return isinstance(error, import_core().Cancelled)
    except ImportError:
        return False


def error_text(error):
    """User text of an exception: core errors carry their own message naming input and fix;
    anything else is a bug of the workbench or the core, said as such (its traceback goes to
    the report view's log)."""
    if is_cancel(error):
        return "meshing was cancelled"
    if isinstance(error, (MeshInputError, ImportError)) or is_core_error(error):
        return str(error) or error.__class__.__name__
    import traceback
    FreeCAD.Console.PrintLog("".join(traceback.format_exception(
        type(error), error, error.__traceback__)))
    return "internal error (%s: %s); please report it with the document" % (
        error.__class__.__name__, error)


def is_core_error(error):
    try:
        return isinstance(error, import_core().Error)
    except ImportError:
        return False


def show_error(message):
    from PySide import QtGui
    import FreeCADGui

    QtGui.QMessageBox.critical(FreeCADGui.getMainWindow(), "OracleMesh", message)
