"""Run inside the real FreeCAD GUI (xvfb) with the installed workbench, on presse_asm.step:

  macro     examples/OracleMesh_Presse.FCMacro: the presse as a FEM analysis, meshed and
            solved by CalculiX (FreeCAD's ccxtools, as the solver's task panel runs it)
  import    what a user does: FreeCAD's own STEP import (ImportGui.insert, one compound of 16
            solids), select it, "Mesh selection with OracleMesh" at the defaults but for
            ContactTolerance 0.6 mm in the property editor and "very coarse" in the panel's
            fineness row (the macro's), Mesh; the
            hand-off's facts (tet10 in FreeCAD's orientation, a mid node on every feature
            edge, the core's final check)
  interfaces  each Face group Interface_<a>_<b> of that mesh (curved tri6 area) against
            OpenCASCADE: the area of part a's faces inside or on part b (a the higher priority)
  look      screenshot of the mesh: the part colours, no selection highlight
  rows      the panel's per-solid rows: a FEM material on one solid, a name on another, one
            moved to the top, the compound treated as one input and split again

Writes what it measured as JSON to $OMFC_RESULT; test_gui_presse.py judges it. PRESSE_ELEMENT_ORDER
(optional) overrides the element order of both meshes.
"""
import hashlib
import json
import os
import sys
import time
import traceback

STEP = os.path.join(os.environ.get("ORACLEMESH_CAD_DIR", "/work/shared/data/cad"),
                    "presse_asm.step")
CONTACT_TOLERANCE = float(os.environ.get("PRESSE_CONTACT_TOLERANCE", "0.6"))  # mm, the macro's
FINENESS = os.environ.get("PRESSE_FINENESS", "very coarse")  # the macro's


sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from gui_script import main, pump, step  # noqa: E402
from fc_harness import common_face_areas, face_group_area, mesh_facts  # noqa: E402


def mesh_fingerprint(mesh_obj):
    """Counts and a hash of the node coordinates and element connectivity of a FemMesh."""
    fm = mesh_obj.FemMesh
    nodes = fm.Nodes
    digest = hashlib.sha1()
    for n in sorted(nodes):
        digest.update(("%.9g %.9g %.9g;" % tuple(nodes[n])).encode())
    for e in sorted(fm.Volumes):
        digest.update(repr(fm.getElementNodes(e)).encode())
    return {"nodes": fm.NodeCount, "volumes": fm.VolumeCount, "sha1": digest.hexdigest()}


def groups(mesh_obj):
    fm = mesh_obj.FemMesh
    return {fm.getGroupName(g): len(fm.getGroupElements(g)) for g in fm.Groups
            if fm.getGroupElementType(g) == "Volume"}


def interface_areas(mesh_obj, report, job):
    """{interface name: (mesh area, OpenCASCADE area, the report's beyond_contact_area)}: the
    mesh's Face group Interface_<a>_<b> (curved tri6) against the common faces
    (fc_harness.common_face_areas)."""
    fm = mesh_obj.FemMesh
    face_groups = {fm.getGroupName(g): g for g in fm.Groups if fm.getGroupElementType(g) == "Face"}
    occt = common_face_areas(job, report)
    areas = {}
    for interface in report["interfaces"]:
        group = face_groups.get(interface["name"])
        areas[interface["name"]] = (face_group_area(fm, group) if group is not None else None,
                                    occt[interface["name"]], interface.get("beyond_contact_area"))
    return areas


def hue_pixels(path, colours, tolerance=6):
    """{palette index: pixels of that hue} of a screenshot (every 2nd pixel in x and y),
    saturated pixels only; plus the pixels of FreeCAD's selection highlight colour."""
    from PySide import QtGui
    image = QtGui.QImage(path)
    hues = [QtGui.QColor.fromRgbF(*c).hsvHue() for c in colours]
    counts = [0] * len(colours)
    highlight = 0
    for y in range(0, image.height(), 2):
        for x in range(0, image.width(), 2):
            c = QtGui.QColor(image.pixel(x, y))
            if (c.red(), c.green(), c.blue()) == (28, 173, 28):
                highlight += 1
            if c.hsvSaturation() < 100 or c.value() < 60:
                continue
            d = [min(abs(c.hsvHue() - h), 360 - abs(c.hsvHue() - h)) for h in hues]
            best = min(range(len(d)), key=d.__getitem__)
            if d[best] <= tolerance:
                counts[best] += 1
    return counts, highlight


def run_macro(workdir, out):
    path = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))))), "examples", "OracleMesh_Presse.FCMacro")
    os.environ["OUT_DIR"] = os.path.join(workdir, "macro")
    os.environ["PRESSE_STEP"] = STEP
    namespace = {"__file__": path, "__name__": "__main__"}
    t0 = time.time()
    macro = out["macro"] = {}
    try:
        exec(compile(open(path).read(), path, "exec"), namespace)
    except Exception:  # judged by the tests; what the macro got to is measured all the same
        macro["error"] = traceback.format_exc()[-3000:]
    macro["seconds"] = time.time() - t0
    mesh = namespace.get("mesh")
    if mesh is not None:
        macro.update({"status": mesh.Status, "valid": mesh.isValid(),
                      "mesh": mesh_fingerprint(mesh), "groups": groups(mesh),
                      "parts": list(namespace.get("solid_of", []))})
    result, force = namespace.get("result"), namespace.get("force")
    if result is not None and "reaction" in namespace:
        displacements = dict(zip(result.NodeNumbers, result.DisplacementVectors))
        nodes = mesh.FemMesh.Nodes
        top = [displacements[n].y for n, p in nodes.items() if p.y > 535.9 and n in displacements]
        macro.update({"max_displacement": max(result.DisplacementLengths),
                      "loaded_face_mean_uy": sum(top) / len(top) if top else None,
                      "reaction": namespace["reaction"], "force": force.Force})
    return namespace.get("doc")


def check(out):
    import FreeCAD
    import FreeCADGui
    import ImportGui

    workdir = os.environ["OMFC_WORKDIR"]
    FreeCADGui.activateWorkbench("OracleMeshWorkbench")
    from oraclemesh_fc import display, task_panel
    from oraclemesh_fc.job import build_job
    import oraclemesh_fc.mesh_object as mo
    shown = []
    mo.show_error = shown.append  # a modal box would wait for a click; record instead
    order = os.environ.get("PRESSE_ELEMENT_ORDER")

    step("macro")
    macro_doc = run_macro(workdir, out)

    step("import with FreeCAD's STEP importer")
    doc = FreeCAD.newDocument("Imported")
    FreeCAD.setActiveDocument(doc.Name)
    FreeCADGui.activateView("Gui::View3DInventor", True)
    # File > Import leaves its folder as the file dialogs' working directory
    # (Gui::FileDialog::setWorkingDirectory); ImportGui.insert called directly does not.
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/General").SetString(
        "FileOpenSavePath", os.path.dirname(STEP))
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Import/hSTEP").SetBool(
        "ReadShapeCompoundMode", True)  # FreeCAD's default: one compound
    ImportGui.insert(STEP, doc.Name)
    presse = doc.Objects[0]
    out["imported"] = [o.TypeId for o in doc.Objects] + [presse.Label, len(presse.Shape.Solids)]

    step("mesh command at defaults")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(presse)
    FreeCADGui.runCommand("OracleMesh_MeshSelection")
    pump()
    panel = task_panel.current
    mesh = panel.obj
    out["rows"] = [(r.key, r.label) for r in panel.rows]
    out["table_labels"] = [panel.inputs.item(i, 0).text() for i in range(panel.inputs.rowCount())]
    if order:
        panel.element_order.setCurrentIndex(panel.element_order.findData(int(order)))
    # The property editor's ContactTolerance and the panel's fineness, as the macro sets them
    # (see there why).
    mesh.ContactTolerance = CONTACT_TOLERANCE
    out["fineness_default"] = panel.fineness.currentData()
    panel.fineness.setCurrentIndex(panel.fineness.findData(FINENESS))
    out["fineness_chosen"] = panel.fineness.currentData()
    t0 = time.time()
    out["mesh_ok"] = panel.mesh()
    out["mesh_seconds"] = time.time() - t0
    out["status"] = mesh.Status
    out["messages"] = list(shown)
    out["mesh"] = mesh_fingerprint(mesh)
    facts = mesh_facts(mesh)
    out["groups"] = facts["group_sizes"]
    out["groups_cover_all_once"] = facts["groups_cover_all_once"]
    out["options"] = {"engine": mesh.Engine, "order": mesh.ElementOrder,
                      "sharp": float(mesh.SharpAngle), "cell_size": float(mesh.CellSize)}
    out["nodes_per_volume"] = facts["nodes_per_volume"]
    out["max_signed_volume6"] = facts["max_signed_volume6"]
    out["feature_edges"] = len(mesh.FeatureEdges) // 2
    out["feature_edge_mid_nodes"] = len(mesh.FeatureEdgeMidNodes)
    report = json.loads(mesh.Report)
    out["final_check"] = report["thesis"]["final_check"]
    out["quality"] = report["quality"]

    out["contact_tolerance"] = report["contact_tolerance"]
    out["job_cad_uncertainty"] = build_job(mesh)[0].get("cad_uncertainty")
    step("interfaces against OpenCASCADE")
    out["interface_areas"] = interface_areas(mesh, report, build_job(mesh)[0])

    step("screenshot")
    pump(0.5)
    out["selection"] = [o.Name for o in FreeCADGui.Selection.getSelection()]
    if macro_doc is not None and macro_doc.Name != doc.Name:
        FreeCAD.closeDocument(macro_doc.Name)
    FreeCAD.setActiveDocument(doc.Name)
    presse.ViewObject.Visibility = False
    mesh.ViewObject.Visibility = True
    view = FreeCADGui.getDocument(doc.Name).ActiveView
    # Parts inside the press hide behind others: two views, each colour's best count.
    counts, highlight = [0] * len(display.PALETTE), 0
    for name in ("viewIsometric", "viewRear"):
        getattr(view, name)()
        view.fitAll()
        pump(0.5)
        shot = os.path.join(workdir, "presse_mesh_%s.png" % name[4:].lower())
        view.saveImage(shot, 1000, 800, "White")
        seen, lit = hue_pixels(shot, display.PALETTE)
        counts = [max(a, b) for a, b in zip(counts, seen)]
        highlight += lit
    out["screenshot"] = os.path.join(workdir, "presse_mesh_isometric.png")
    out["faces_coloured"] = mesh.ViewObject.Proxy.shown[0]
    out["palette_pixels"] = counts
    out["highlight_pixels"] = highlight
    out["palette_size"] = len(display.PALETTE)

    step("per-solid rows")
    import ObjectsFem
    bronze = ObjectsFem.makeMaterialSolid(doc, "Bronze")
    bronze.References = [(presse, "Solid16")]  # so it is no "everything else" material
    panel.reject()
    pump()
    panel = mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject) and task_panel.current
    pump()
    labels = [r.label for r in panel.rows]
    third, fifth = labels.index("COLONNE001"), labels.index("COLONNE003")
    panel.inputs.cellWidget(third, 2).setEditText("Bronze")
    panel.inputs.cellWidget(fifth, 2).setEditText("Rubber")
    panel.select_row(labels.index("VERIN"))
    for _ in range(labels.index("VERIN")):
        panel.up_button.click()
    panel.write_object()
    job, groups_of_job, _, _ = build_job(mesh)
    out["rows_written"] = {
        "bronze_references": [(o.Name, list(s)) for o, s in bronze.References],
        "names": dict(mesh.InputMaterialNames),
        "order": list(mesh.PartOrder)[:3],
        "job_inputs": [i["name"] for i in job["inputs"]][:3],
        "groups": groups_of_job,
        "labels_kept": dict(mesh.PartLabels).get("%s.Solid3" % presse.Name),
    }
    panel.select_row(0)
    panel.whole_check.setChecked(True)
    out["whole_rows"] = [(r.key, r.label) for r in panel.rows]
    panel.write_object()
    job, groups_of_job, _, _ = build_job(mesh)
    out["whole"] = {"whole_inputs": [o.Name for o in mesh.WholeInputs],
                    "job_inputs": [(i["name"], i.get("material")) for i in job["inputs"]],
                    "groups": groups_of_job}
    panel.whole_check.setChecked(False)
    out["split_again"] = [r.label for r in panel.rows]
    panel.reject()
    pump()
    step("done")


main(check)
