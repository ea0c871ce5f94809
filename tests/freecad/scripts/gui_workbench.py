"""Run inside the real FreeCAD GUI (xvfb) with the installed workbench, on the demo document:

  panel     the command opens the task panel on the selection; the corner is added as a cut
            and moved to the top, the inputs are meshed, then Pin and Plate are swapped and
            meshed again (group volumes against OpenCASCADE for both orders)
  look      screenshot of the coloured mesh (pixels of each material colour counted)
  cancel    Cancel in the progress dialog during a long mesh: time until meshing returns,
            previous mesh kept, no worker left
  errors    a bad per-material size (the core refuses it) and a forced segfault of the core
            (ORACLEMESH_WORKER_CRASH): an error is shown, the document is unchanged
  reopen    double click opens the panel again; the histogram and export commands run
  record    the lines the mesh command wrote to the console (= the macro recorder), replayed
            on a new demo document, make the same mesh object

Writes what it measured as JSON to $OMFC_RESULT; the pytest side (test_gui.py) judges it.
The trail of steps goes to $OMFC_RESULT.steps, so a GUI crash shows where it happened.
"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from gui_script import main, pump, step  # noqa: E402



def group_volumes(mesh_obj):
    """{group: exact volume of its tet10 elements} of the FemMesh."""
    import numpy as np
    from tet_geometry import tet10_volumes
    fm = mesh_obj.FemMesh
    nodes = fm.Nodes
    out = {}
    for g in fm.Groups:
        if fm.getGroupElementType(g) != "Volume":
            continue  # the interfaces' and exteriors' face groups
        elements = fm.getGroupElements(g)
        ids = sorted({n for e in elements for n in fm.getElementNodes(e)})
        index = {n: k for k, n in enumerate(ids)}
        points = np.array([tuple(nodes[n]) for n in ids])
        tets = np.array([[index[n] for n in fm.getElementNodes(e)] for e in elements])
        # FreeCAD's corners are negatively oriented: the volumes come out negative.
        out[fm.getGroupName(g)] = float(-tet10_volumes(points, tets).sum())
    return out


def mesh_state(mesh_obj):
    fm = mesh_obj.FemMesh
    return {"nodes": fm.NodeCount, "volumes": fm.VolumeCount,
            "groups": {fm.getGroupName(g): len(fm.getGroupElements(g)) for g in fm.Groups
                       if fm.getGroupElementType(g) == "Volume"},
            "feature_edges": len(mesh_obj.FeatureEdges) // 2}


def mesh_settings(mesh_obj):
    """What a new mesh object is made of: its links by name and the options the command sets."""
    return {"inputs": [o.Name for o in mesh_obj.Inputs], "cuts": [o.Name for o in mesh_obj.Cuts],
            "analysis": [o.Name for o in mesh_obj.InList if o.isDerivedFrom("Fem::FemAnalysis")],
            "engine": mesh_obj.Engine, "element_order": mesh_obj.ElementOrder,
            "sharp_angle": mesh_obj.SharpAngle.Value, "cell_size": mesh_obj.CellSize.Value}


def console_lines():
    """Statements in FreeCAD's Python console, prompts stripped; None without a console. The
    empty prompt at the end is left out: the next statement is written into its line."""
    import FreeCADGui
    from PySide import QtGui
    console = FreeCADGui.getMainWindow().findChild(QtGui.QPlainTextEdit, "Python console")
    if console is None:
        return None
    return [line[4:] for line in console.toPlainText().splitlines()
            if line.startswith(">>> ") and line[4:].strip()]


def document_state(doc):
    """Names and the properties a failed mesh must not change."""
    return {o.Name: [o.Label, bool(o.isValid()) if o.TypeId != "Fem::FemMeshObjectPython" else None]
            for o in doc.Objects}


def colour_pixels(path, colours):
    """{name: pixels whose hue matches the colour} in a screenshot, every 2nd pixel
    in x and y (a quarter of them)."""
    from PySide import QtGui
    image = QtGui.QImage(path)
    targets = {}
    for name, (r, g, b) in colours.items():
        c = QtGui.QColor.fromRgbF(r, g, b)
        targets[name] = c.hsvHue()
    counts = dict.fromkeys(colours, 0)
    counts["other colours"] = 0  # saturated pixels of no material: a wrong colouring
    for y in range(0, image.height(), 2):
        for x in range(0, image.width(), 2):
            c = QtGui.QColor(image.pixel(x, y))
            if c.hsvSaturation() < 100 or c.value() < 60:
                continue
            for name, hue in targets.items():
                d = abs(c.hsvHue() - hue)
                if min(d, 360 - d) <= 12:
                    counts[name] += 1
                    break
            else:
                counts["other colours"] += 1
    return counts


def dark_pixels(path):
    """Near-black pixels (the feature edges' colour) in a screenshot, every 2nd pixel in x
    and y."""
    from PySide import QtGui
    image = QtGui.QImage(path)
    return sum(QtGui.QColor(image.pixel(x, y)).value() < 60
               for y in range(0, image.height(), 2) for x in range(0, image.width(), 2))


def find_progress_dialog():
    from PySide import QtGui
    for w in QtGui.QApplication.topLevelWidgets():
        if isinstance(w, QtGui.QProgressDialog) and w.isVisible():
            return w
    for w in QtGui.QApplication.allWidgets():
        if isinstance(w, QtGui.QProgressDialog) and w.isVisible():
            return w
    return None


def check(out):
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path.insert(0, os.path.dirname(here))  # tests/: tet_geometry
    import FreeCAD
    import FreeCADGui
    import FemGui
    from PySide import QtCore

    workdir = os.environ["OMFC_WORKDIR"]
    step("activate workbench")
    FreeCADGui.activateWorkbench("OracleMeshWorkbench")
    out["workbench"] = FreeCADGui.activeWorkbench().name()
    out["commands"] = sorted(c for c in FreeCADGui.listCommands() if c.startswith("OracleMesh_"))

    import oraclemesh_fc
    from oraclemesh_fc import demo, display, task_panel
    import oraclemesh_fc.mesh_object as mo
    out["workbench_from"] = os.path.normpath(os.path.dirname(oraclemesh_fc.__file__))
    shown = []
    mo.show_error = shown.append  # a modal box would wait for a click; record instead

    step("demo document")
    doc = FreeCAD.newDocument("Demo")
    analysis, solver, pin, plate, corner = demo.build(doc)
    FemGui.setActiveAnalysis(analysis)
    doc.recompute()

    step("command opens the task panel")
    # The console shows what the macro recorder records (FreeCAD's MacroManager writes every
    # doCommand line to both); on, whatever the user's preference.
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Macro").SetBool("ScriptToPyConsole", True)
    console_before = console_lines()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(pin)
    FreeCADGui.Selection.addSelection(plate)
    FreeCADGui.runCommand("OracleMesh_MeshSelection")
    pump()
    out["console_found"] = console_before is not None
    out["recorded"] = (console_lines() or [])[len(console_before or []):]
    panel = task_panel.current
    out["panel_open"] = panel is not None and FreeCADGui.Control.activeDialog()
    mesh = panel.obj
    out["command_mesh"] = mesh_settings(mesh)
    out["mesh_in_analysis"] = mesh in analysis.Group
    out["panel_rows"] = [r.obj.Name for r in panel.rows]
    out["panel_materials"] = [r.material for r in panel.rows]
    # The engine a new mesh object starts with, as the panel's combo shows it.
    out["new_mesh_engine"] = [panel.engine.currentData(), mesh.Engine]

    step("add the corner as a cut at the top")
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(corner)
    panel.add_button.click()
    panel.inputs.cellWidget(2, 1).setCurrentIndex(task_panel.ROLES.index("cut"))
    panel.select_row(2)
    panel.up_button.click()
    panel.up_button.click()
    out["rows_with_cut"] = [(r.obj.Name, r.role) for r in panel.rows]
    panel.cell_size.setValue(8.0)
    panel.facet_distance.setValue(0.25)
    panel.element_order.setCurrentIndex(panel.element_order.findData(2))
    panel.optimize.setChecked(True)
    # The pin finer (per-material criteria), so its facetted surface stays close to the CAD.
    pin_row = [r.obj.Name for r in panel.rows if r.role == "material"].index("Pin")
    panel.criteria.item(pin_row, 0).setText("2.5")
    panel.criteria.item(pin_row, 2).setText("1.5")

    step("mesh: pin first")
    t0 = time.time()
    out["mesh1_ok"] = panel.mesh()
    out["mesh1_seconds"] = time.time() - t0
    out["mesh1"] = mesh_state(mesh)
    out["mesh1_status"] = mesh.Status
    out["mesh1_volumes"] = group_volumes(mesh)
    out["report_html"] = panel.report.toHtml()
    out["cuts"] = [o.Name for o in mesh.Cuts]
    out["inputs"] = [o.Name for o in mesh.Inputs]
    out["input_sizes"] = dict(mesh.InputSizes)
    # The planar-faces checkbox shows and writes PlanarFaces (off by default; switched off
    # again before the next mesh, which is checked as meshed without it).
    out["planar_faces_shown"] = [panel.planar_faces.isChecked(), mesh.PlanarFaces]
    panel.planar_faces.setChecked(True)
    panel.write_object()
    out["planar_faces_written"] = mesh.PlanarFaces
    panel.planar_faces.setChecked(False)
    panel.write_object()

    step("swap Pin and Plate, mesh again")
    panel.select_row(1)  # Pin
    panel.down_button.click()
    out["rows_swapped"] = [r.obj.Name for r in panel.rows]
    out["mesh2_ok"] = panel.mesh()
    out["mesh2"] = mesh_state(mesh)
    out["mesh2_volumes"] = group_volumes(mesh)
    out["inputs_swapped"] = [o.Name for o in mesh.Inputs]
    cut = corner.Shape
    out["occ"] = {
        "pin_full": pin.Shape.Volume,
        "pin_outside_plate": pin.Shape.cut(plate.Shape).Volume,
        "plate_without_pin": plate.Shape.cut(cut).cut(pin.Shape).Volume,
        "plate_full": plate.Shape.cut(cut).Volume,
    }
    out["group_names"] = {"pin": [m.Name for m in analysis.Group if m.Label == "Steel"][0] + "_Volumes",
                          "plate": [m.Name for m in analysis.Group if m.Label == "Aluminium"][0]
                          + "_Volumes"}

    step("screenshot")
    for o in doc.Objects:
        if o.ViewObject is not None and o != mesh:
            o.ViewObject.Visibility = False
    mesh.ViewObject.Visibility = True
    view = FreeCADGui.getDocument(doc.Name).ActiveView
    view.viewIsometric()
    view.fitAll()
    pump(0.5)
    shot = os.path.join(workdir, "gui_mesh.png")
    view.saveImage(shot, 800, 600, "White")
    out["screenshot"] = shot
    colours = display.material_colours(mesh.FemMesh)
    out["colours"] = colours
    out["colour_pixels"] = colour_pixels(shot, colours)
    out["element_colours"], out["edges_drawn"] = mesh.ViewObject.Proxy.shown
    faces = display.face_set_nodes(mesh.ViewObject.RootNode)[1]
    out["face_polygons"] = list(faces.coordIndex.getValues()).count(-1)
    # The same view without the edge lines: what the lines add is what the user sees of them.
    mesh.ViewObject.Proxy.edge_node.update([])
    pump(0.3)
    bare = os.path.join(workdir, "gui_mesh_without_edges.png")
    view.saveImage(bare, 800, 600, "White")
    out["dark_pixels"] = {"with_edges": dark_pixels(shot), "without_edges": dark_pixels(bare)}
    mesh.ViewObject.Proxy.show(mesh)
    pump(0.3)

    step("cancel during a long mesh")
    previous = mesh_state(mesh)
    before_doc = document_state(doc)
    panel.cell_size.setValue(0.7)
    panel.facet_distance.setValue(0.02)
    panel.element_order.setCurrentIndex(panel.element_order.findData(2))
    panel.optimize.setChecked(True)
    timing = {}

    def press_cancel():
        dialog = find_progress_dialog()
        timing["dialog_found"] = dialog is not None
        timing["label"] = dialog.labelText() if dialog else ""
        timing["value"] = dialog.value() if dialog else -1
        timing["pressed"] = time.time()
        if dialog is not None:
            dialog.cancel()

    QtCore.QTimer.singleShot(2500, press_cancel)
    n_shown = len(shown)
    panel.mesh()
    timing["returned"] = time.time()
    out["cancel"] = {
        "dialog_found": timing.get("dialog_found", False),
        "label_at_cancel": timing.get("label"),
        "progress_at_cancel": timing.get("value"),
        "seconds_to_return": timing["returned"] - timing.get("pressed", float("inf")),
        "mesh_kept": mesh_state(mesh) == previous,
        "document_kept": document_state(doc) == before_doc,
        "status": mesh.Status,
        "messages": shown[n_shown:],
        "workers_left": worker_children(),
    }

    step("bad per-material size (core refuses it)")
    panel.cell_size.setValue(8.0)
    panel.facet_distance.setValue(0.25)
    panel.element_order.setCurrentIndex(panel.element_order.findData(2))
    panel.optimize.setChecked(True)
    plate_row = [r.obj.Name for r in panel.rows if r.role == "material"].index("Plate")
    panel.criteria.item(plate_row, 0).setText("0.001")
    n_shown = len(shown)
    ok = panel.mesh()
    out["bad_size"] = {"ok": ok, "messages": shown[n_shown:], "status": mesh.Status,
                       "mesh_kept": mesh_state(mesh) == previous,
                       "document_kept": document_state(doc) == before_doc,
                       "input_sizes": dict(mesh.InputSizes)}
    panel.criteria.item(plate_row, 0).setText("")

    step("a cell that is not a number: Apply refuses it, nothing changes")
    sizes_before = dict(mesh.InputSizes)
    panel.criteria.item(plate_row, 2).setText("abc")
    out["bad_cell"] = {"applied": panel.apply_clicked(), "report": panel.report.toPlainText(),
                       "sizes_kept": dict(mesh.InputSizes) == sizes_before}
    panel.criteria.item(plate_row, 2).setText("")

    step("forced crash of the core")
    os.environ["ORACLEMESH_WORKER_CRASH"] = "refine"
    n_shown = len(shown)
    ok = panel.mesh()
    del os.environ["ORACLEMESH_WORKER_CRASH"]
    out["crash"] = {"ok": ok, "messages": shown[n_shown:], "status": mesh.Status,
                    "mesh_kept": mesh_state(mesh) == previous,
                    "document_kept": document_state(doc) == before_doc,
                    "workers_left": worker_children()}

    step("FreeCAD still works: mesh again")
    out["after_errors_ok"] = panel.mesh()
    out["after_errors"] = mesh_state(mesh)

    step("extra edges: a sketch from the tree, a plate edge added and removed, a face refused")
    import Part
    sketch = doc.addObject("Sketcher::SketchObject", "EdgeSketch")
    sketch.Placement = FreeCAD.Placement(FreeCAD.Vector(0, 0, 10), FreeCAD.Rotation())
    sketch.addGeometry(Part.LineSegment(FreeCAD.Vector(60, 10, 0), FreeCAD.Vector(90, 50, 0)))
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(sketch)
    FreeCADGui.Selection.addSelection(plate, "Edge1")
    FreeCADGui.Selection.addSelection(plate, "Face1")
    panel.extra_add_button.click()
    extra = {"listed": [panel.extra_list.item(i).text() for i in range(panel.extra_list.count())],
             "refused": panel.report.toPlainText()}
    panel.extra_list.setCurrentRow(1)
    panel.extra_remove_button.click()
    extra["after_remove"] = [panel.extra_list.item(i).text()
                             for i in range(panel.extra_list.count())]
    extra["mesh_ok"] = panel.mesh()
    extra["property"] = [(o.Name, list(s)) for o, s in mesh.ExtraEdges]
    nodes = mesh.FemMesh.Nodes
    line = sketch.Shape.Edges[0]
    ids = list(mesh.FeatureEdges)
    on_line = [(a, b) for a, b in zip(ids[0::2], ids[1::2])
               if max(line.distToShape(Part.Vertex(nodes[n]))[0] for n in (a, b)) < 1e-6 * 120]
    extra["line_edges"] = len(on_line)
    extra["line_covered"] = sum((nodes[a] - nodes[b]).Length for a, b in on_line)
    extra["line_length"] = line.Length
    out["extra_edges"] = extra

    step("drag and drop in the inputs table")
    from PySide import QtGui
    table = panel.inputs
    table.selectRow(2)  # Pin, dropped onto row 1 (Plate): Pin gets priority back
    target = table.visualRect(table.model().index(1, 0)).center()
    mime = table.model().mimeData([table.model().index(2, 0)])
    drop = QtGui.QDropEvent(QtCore.QPointF(target), QtCore.Qt.MoveAction, mime,
                            QtCore.Qt.LeftButton, QtCore.Qt.NoModifier)
    table.dropEvent(drop)
    out["rows_after_drop"] = [r.obj.Name for r in panel.rows]
    out["role_widgets_after_drop"] = [table.cellWidget(i, 1).currentText()
                                      for i in range(table.rowCount())]
    table.selectRow(1)
    table.dropEvent(QtGui.QDropEvent(
        QtCore.QPointF(table.visualRect(table.model().index(2, 0)).center()),
        QtCore.Qt.MoveAction, table.model().mimeData([table.model().index(1, 0)]),
        QtCore.Qt.LeftButton, QtCore.Qt.NoModifier))
    out["rows_after_second_drop"] = [r.obj.Name for r in panel.rows]

    step("undo of Apply")
    panel.sharp_angle.setValue(45.0)
    panel.apply()
    applied = mesh.SharpAngle.Value
    doc.undo()
    out["undo"] = {"applied": applied, "after_undo": mesh.SharpAngle.Value}
    panel.load_options()

    step("preferences page")
    from oraclemesh_fc import preferences
    page = preferences.PreferencePage()
    page.loadSettings()
    out["prefs_loaded"] = {"order": page.order.currentData(), "engine": page.engine.currentData()}
    page.order.setCurrentIndex(page.order.findData(1))
    page.preset.setCurrentIndex(page.preset.findData("coarse"))
    page.saveSettings()
    out["prefs_saved"] = preferences.defaults()
    out["thesis_engine_enabled"] = page.engine.model().item(page.engine.findData("thesis")).isEnabled()

    step("close the panel, double click opens it again")
    panel.accept()
    pump()
    out["closed"] = task_panel.current is None and not FreeCADGui.Control.activeDialog()
    mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject)
    pump()
    out["reopened"] = task_panel.current is not None and \
        [r.obj.Name for r in task_panel.current.rows] == out["rows_swapped"]
    out["reopened_extra_edges"] = [task_panel.current.extra_list.item(i).text()
                                   for i in range(task_panel.current.extra_list.count())]
    task_panel.current.reject()
    pump()

    step("histogram and export")
    from pivy import coin
    from oraclemesh_fc import quality, export
    dialog = quality.show_histogram(mesh)
    pump()
    dialog.worst.selectRow(0)
    pump()
    out["histogram"] = {"png": os.path.getsize(dialog.png), "rows": dialog.worst.rowCount(),
                        "worst": float(dialog.angles.min()),
                        "report_min": json.loads(mesh.Report)["quality"]["min_dihedral_deg"],
                        "highlighted": len(mesh.ViewObject.HighlightedNodes),
                        "under_one_degree": dialog.under_one_degree,
                        "angles_under_one": int((dialog.angles < 1.0).sum()),
                        "model_diagonal": mesh.FemMesh.BoundBox.DiagonalLength,
                        "poor": {str(k): v for k, v in dialog.poor.items()},
                        "poor_from_angles": {str(b): int((dialog.angles < b).sum()) for b in (5, 10, 15)},
                        "poor_line": dialog.poor_line.text(),
                        "report_improve": {k: v for k, v in json.loads(mesh.Report)["improve"].items()
                                           if k.startswith("tets_under") and not k.endswith("listed")}}
    camera = FreeCADGui.ActiveDocument.ActiveView.getCameraNode()
    if dialog.zoomed is not None:
        centre, size = dialog.zoomed
        eye = camera.position.getValue().getValue()
        look = camera.orientation.getValue().multVec(coin.SbVec3f(0, 0, -1)).getValue()
        to_centre = [c - e for c, e in zip(centre, eye)]
        along = sum(a * b for a, b in zip(to_centre, look))
        # How far the element's centre is from the camera's line of sight.
        off_axis = sum((t - along * l) ** 2 for t, l in zip(to_centre, look)) ** 0.5
        out["histogram"]["zoom"] = {"size": size, "off_axis": off_axis, "in_front": along > 0,
                                    "ortho_height": camera.height.getValue()
                                    if isinstance(camera, coin.SoOrthographicCamera) else None}
    dialog.dialog.close()
    pump()
    out["export"] = {}
    for ext in (".vtu", ".inp", ".msh"):
        path = os.path.join(workdir, "exported" + ext)
        export.export_mesh(mesh, path)
        out["export"][ext] = path
    out["final"] = mesh_state(mesh)
    out["final_volumes"] = group_volumes(mesh)
    doc.saveAs(os.path.join(workdir, "gui_demo.FCStd"))

    step("replay the recorded lines in a new demo document")
    replay = FreeCAD.newDocument("Replay")
    demo.build(replay)
    replay.recompute()
    FreeCAD.setActiveDocument(replay.Name)
    namespace = {"FreeCAD": FreeCAD}
    # The document lines: not the GUI's (views, selection, edit mode; FreeCAD's own included).
    replayed = [line for line in out["recorded"] if not line.startswith("#")
                and "Gui." not in line and "ViewObject" not in line]
    for line in replayed:
        exec(line, namespace)
    out["replayed"] = replayed
    out["replayed_mesh"] = mesh_settings(namespace["oracle_mesh"]) \
        if "oracle_mesh" in namespace else None
    step("done")


def worker_children():
    """Live oraclemesh.worker processes that are children of this FreeCAD."""
    from worker_processes import live_worker_children
    return live_worker_children()


main(check)
