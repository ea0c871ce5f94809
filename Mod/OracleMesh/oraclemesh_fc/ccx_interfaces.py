"""Ties and contacts of an OracleMesh mesh in the CalculiX input FreeCAD writes (issue 19 item 3).

FreeCAD 0.20's Tie and Contact constraints take faces of the CAD geometry; the mesh object's
interfaces are mesh surfaces (its Face groups), with no CAD face to pick when parts overlap
and priority carves one out of the other. So the workbench adds the cards itself: install()
wraps femsolver.calculix.write_step_equation.write_step_equation, which FreeCAD's writer
(femsolver/calculix/writer.py, used by ccxtools and by the solver task panel alike) calls
once, after the model definition (mesh, element sets, materials, sections, FreeCAD's own
ties and contacts) and right before `*STEP`. There the wrapper writes, for the mesh of the
analysis, per tied or contact pair of the last mesh's report:

  *SURFACE, NAME=<group>, TYPE=ELEMENT   both sides, as (element id, S1..S4) from the
                                          Face groups of the FemMesh
  *TIE                                    tied: slave, master
  *SURFACE INTERACTION, *SURFACE BEHAVIOR, [*FRICTION,] *CONTACT PAIR     contact

with the values the core chose (report.interfaces: master, slave, position tolerance, contact
stiffness, friction), the same cards the core writes into its own INP.

Element ids: FreeCAD writes the FemMesh's own node and element ids (writeABAQUS), which the
hand-off made the core's (tet i = element i + 1), but not its node order: the corners come
swapped (written_order: SMESH's negatively oriented corners become CalculiX's positive ones,
the core's own order). Face numbers, in the written order, follow CalculiX's C3D4/C3D10 faces
S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1, whose right-hand normals point into the tet; a
face element's corners are ordered outward from the tet it was taken from
(handoff.surface_face_nodes), the reverse, so an oriented corner triple finds its tet even
where both sides of an interface share the nodes.

Contact makes CalculiX's static step nonlinear (increments, contact iterations). FreeCAD's
default step (*STATIC with no data line, automatic incrementation) leaves the times to
CalculiX: the whole load in the first increment, and a smallest increment of 1e-5 of the step.
With contact CalculiX can close such a step with a remainder of 1e-6; where the contact status
still changes between iterations (plates pulled apart) that remainder does not converge and
cannot be cut back, and the job fails ("increment size smaller than minimum"). With contact
pairs the wrapper gives such a step CalculiX's own times but a smallest increment of 1e-9
(CONTACT_STATIC_TIMES, step_with_contact_increments); a step whose times the user set is left
as it is. (A smaller first increment would let the plates close too, but gives contacts that
converge under the whole load several increments each.) User-defined increments (DIRECT) or a
non-static analysis get a warning in the report view.
"""
import io
import re

from .interfaces import last_report

MESH_TYPE = "Fem::OracleMesh"  # mesh_object.TYPE (imported there from here: no cycle)
# CalculiX faces of a tet, corners 0-based in CalculiX (= FreeCAD) node order.
CCX_FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))
# CalculiX's stick slope for face-to-face friction, as a share of the normal slope (the
# core's choice, mesh/InterfaceConstraints).
STICK_SLOPE_SHARE = 0.01
# A contact step's times when the user set none: initial increment, step, smallest and
# largest increment (CalculiX's defaults but the smallest).
CONTACT_STATIC_TIMES = "1.0,1.0,1e-9,1.0"


class InterfaceCardsError(RuntimeError):
    """The mesh's report and its FemMesh disagree (a mesh from another version): mesh again."""


def oriented_key(a, b, c):
    """The same key for (a, b, c), (b, c, a), (c, a, b); another for the reversed order."""
    k = (a, b, c).index(min(a, b, c))
    return ((a, b, c) * 2)[k:k + 3]


_written_orders = {}


def written_order(nodes_per_volume):
    """Positions in getElementNodes' order of the nodes writeABAQUS writes, in written order.

    FreeCAD 0.20 writes a tet's first two corners swapped (getElementNodes 1 2 3 4 -> 2 1 3 4,
    mid nodes along), so the face numbers must be taken in the written order; asked of
    FreeCAD itself with one element, in case another version writes otherwise."""
    if nodes_per_volume not in _written_orders:
        import os
        import tempfile
        import Fem

        one = Fem.FemMesh()
        # Any geometry: writeABAQUS reorders by element type only.
        corners = ((0, 0, 0), (0, 1, 0), (1, 0, 0), (0, 0, 1))
        points = list(corners)
        if nodes_per_volume == 10:
            for a, b in ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)):
                points.append(tuple(0.5 * (corners[a][k] + corners[b][k]) for k in range(3)))
        for i, p in enumerate(points, start=1):
            one.addNode(p[0], p[1], p[2], i)
        one.addVolume(list(range(1, nodes_per_volume + 1)), 1)
        handle, path = tempfile.mkstemp(suffix=".inp")
        os.close(handle)
        try:
            one.writeABAQUS(path, 1, False)
            with open(path) as f:
                text = f.read().upper()
        finally:
            os.remove(path)
        values = text.split("*ELEMENT", 1)[1].split("\n", 1)[1].split("*", 1)[0]
        written = [int(v) for v in values.replace("\n", ",").split(",") if v.strip()][1:]
        if sorted(written) != list(range(1, nodes_per_volume + 1)):
            raise InterfaceCardsError("FreeCAD's writeABAQUS wrote element nodes %s for 1..%d: "
                                      "the interface cards cannot be placed"
                                      % (written, nodes_per_volume))
        _written_orders[nodes_per_volume] = [n - 1 for n in written]
    return _written_orders[nodes_per_volume]


def face_index(femmesh):
    """{oriented corner triple: (volume id, CalculiX face 1..4)} over the mesh's volumes, the
    faces numbered in the node order FreeCAD writes."""
    index = {}
    orders = {}
    for vid in femmesh.Volumes:
        nodes = femmesh.getElementNodes(vid)
        order = orders.get(len(nodes)) or orders.setdefault(len(nodes), written_order(len(nodes)))
        nodes = [nodes[k] for k in order]
        for number, (i, j, k) in enumerate(CCX_FACES, start=1):
            index[oriented_key(nodes[k], nodes[j], nodes[i])] = (vid, number)
    return index


def group_ids(femmesh):
    return {femmesh.getGroupName(g): g for g in femmesh.Groups
            if femmesh.getGroupElementType(g) == "Face"}


def element_faces(femmesh, group, index, where):
    """[(volume id, face number)] of a Face group's face elements."""
    faces = []
    for fid in femmesh.getGroupElements(group):
        a, b, c = femmesh.getElementNodes(fid)[:3]
        found = index.get(oriented_key(a, b, c))
        if found is None:
            raise InterfaceCardsError("%s: face element %d of group '%s' is no face of a volume: "
                                      "mesh again" % (where, fid, femmesh.getGroupName(group)))
        faces.append(found)
    return faces


def constrained_interfaces(mesh_obj):
    """The report's interfaces that need CalculiX cards (tied and contact pairs)."""
    return [e for e in last_report(mesh_obj).get("interfaces", [])
            if e.get("kind") in ("tied", "contact") and e.get("constraint")]


def cards(mesh_obj):
    """The CalculiX cards of the mesh object's ties and contacts ('' when it has none)."""
    entries = constrained_interfaces(mesh_obj)
    if not entries:
        return ""
    where = "OracleMesh '%s'" % mesh_obj.Label
    femmesh = mesh_obj.FemMesh
    groups = group_ids(femmesh)
    index = face_index(femmesh)
    lines = ["", "*" * 59,
             "** OracleMesh '%s': ties and contacts between its parts (the mesh object's "
             "Interfaces)" % mesh_obj.Label]
    written = set()
    for e in entries:
        for surface in (e["slave"], e["master"]):
            if surface in written:
                continue
            if surface not in groups:
                raise InterfaceCardsError("%s: the report's %s '%s' names surface '%s', which "
                                          "is no Face group of the mesh: mesh again"
                                          % (where, e["kind"], e["constraint"], surface))
            lines.append("*SURFACE, NAME=%s, TYPE=ELEMENT" % surface)
            lines += ["%d, S%d" % f for f in element_faces(femmesh, groups[surface], index, where)]
            written.add(surface)
    for e in entries:
        a, b = e["parts"]
        if e["kind"] == "tied":
            # ADJUST=NO: the slave nodes are copies of nodes on the master faces already.
            lines += ["** %s and %s tied" % (a, b),
                      "*TIE, NAME=%s, POSITION TOLERANCE=%.13G, ADJUST=NO"
                      % (e["constraint"], e["position_tolerance"]),
                      "%s, %s" % (e["slave"], e["master"])]
            continue
        slope = float(e["contact_stiffness"])
        friction = float(e.get("friction", 0.0))
        lines += ["** %s and %s in contact (penalty, slope from the core; %s)"
                  % (a, b, "friction %g" % friction if friction > 0 else "frictionless"),
                  "*SURFACE INTERACTION, NAME=%s" % e["constraint"],
                  "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
                  "%.13G" % slope]
        if friction > 0:
            lines += ["*FRICTION", "%.13G, %.13G" % (friction, STICK_SLOPE_SHARE * slope)]
        lines += ["*CONTACT PAIR, INTERACTION=%s, TYPE=SURFACE TO SURFACE" % e["constraint"],
                  "%s, %s" % (e["slave"], e["master"])]
    return "\n".join(lines) + "\n"


def has_contact(mesh_obj):
    """Whether the last mesh's report has a contact pair."""
    return any(e["kind"] == "contact" for e in constrained_interfaces(mesh_obj))


def step_warnings(mesh_obj, solver):
    """What the user must know about the step CalculiX gets for these contacts."""
    if not has_contact(mesh_obj):
        return []
    warnings = []
    analysis_type = getattr(solver, "AnalysisType", "static")
    if analysis_type not in ("static", "thermomech"):
        warnings.append("contact pairs act in static and thermomechanical steps; this analysis "
                        "is '%s': CalculiX may reject or ignore them (make the interfaces tied "
                        "or bonded for it)" % analysis_type)
    if getattr(solver, "IterationsUserDefinedIncrementations", False):
        warnings.append("contact needs CalculiX's automatic incrementation, and the solver's "
                        "IterationsUserDefinedIncrementations (DIRECT) switches it off: clear it "
                        "if CalculiX does not converge")
    return warnings


def step_with_contact_increments(step_text, contact):
    """FreeCAD's step text with times for contact: a *STATIC line followed by an empty data line
    (CalculiX's defaults) gets CONTACT_STATIC_TIMES when `contact`; anything else comes back
    unchanged."""
    if not contact:
        return step_text
    return re.sub(r"^(\*STATIC[^\n]*)\n\n", r"\g<1>\n%s\n" % CONTACT_STATIC_TIMES, step_text, count=1,
                  flags=re.MULTILINE)


def _oraclemesh_of(ccxwriter):
    """The analysis' mesh when it is an OracleMesh, else None."""
    mesh_obj = getattr(ccxwriter, "mesh_object", None)
    return mesh_obj if getattr(getattr(mesh_obj, "Proxy", None), "Type", None) == MESH_TYPE else None


def _add_interface_cards(f, ccxwriter):
    import FreeCAD

    mesh_obj = _oraclemesh_of(ccxwriter)
    if mesh_obj is None:
        return
    if "Touched" in mesh_obj.State:
        # The cards follow the mesh (its report), not settings changed since.
        FreeCAD.Console.PrintWarning(
            "OracleMesh '%s' has changed settings it was not meshed with (Interfaces among "
            "them?): CalculiX gets the last mesh and its ties and contacts; recompute the mesh "
            "first to use the new settings\n" % mesh_obj.Label)
    text = cards(mesh_obj)
    if not text:
        return
    f.write(text)
    for warning in step_warnings(mesh_obj, ccxwriter.solver_obj):
        FreeCAD.Console.PrintWarning("OracleMesh '%s': %s\n" % (mesh_obj.Label, warning))


def install():
    """Make FreeCAD's CalculiX writer add the cards and give a contact step its times (once per
    session; without FreeCAD's FEM workbench there is nothing to do)."""
    try:
        from femsolver.calculix import write_step_equation
    except ImportError:
        return
    original = write_step_equation.write_step_equation
    if getattr(original, "oraclemesh_interfaces", False):
        return

    def write_step_equation_with_interfaces(f, ccxwriter):
        _add_interface_cards(f, ccxwriter)
        step = io.StringIO()
        original(step, ccxwriter)
        mesh_obj = _oraclemesh_of(ccxwriter)
        f.write(step_with_contact_increments(step.getvalue(), mesh_obj is not None and has_contact(mesh_obj)))

    write_step_equation_with_interfaces.oraclemesh_interfaces = True
    write_step_equation.write_step_equation = write_step_equation_with_interfaces
