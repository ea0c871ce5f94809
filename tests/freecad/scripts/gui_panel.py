"""Run inside the real FreeCAD GUI (xvfb) with the installed workbench: the task panel in
FreeCAD's default combo view width and the traps of issue 17, one section each (a failing
section records its traceback and the others still run):

  layout      the combo view at 264 px: geometry of every label, button and group box of the
              panel and of the task dialog's buttons; table heights; tooltips
  cut_last    a cut in the last row: the warning in the panel and in its report
  automatic   the sizes "automatic" shows against the criteria the core reports after meshing;
              the time shown against the wall time of the mesh
  untouched   OK without a change: the mesh object is not touched, a recompute does not mesh
  interfaces  the pairs the last mesh found, one combo box each: contact chosen, meshed,
              stored, shown again on reopening; the default combo
  failure     a forced failure inside the hand-off, on a meshed object and on a new one:
              message box, Status, the panel's report, the inputs shown again
  other_doc   an active analysis in another document: the command makes one mesh, in no
              analysis; makeMesh refuses it and leaves no object
  refused     a Part::Plane selected: the message says what it is and what is accepted

Writes what it measured as JSON to $OMFC_RESULT; test_gui_panel.py judges it.
"""
import json
import os
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from gui_script import main, pump  # noqa: E402

COMBO_VIEW_WIDTH = 264


class MessageBoxes:
    """Records and closes every QMessageBox that opens while it is active (a modal box would
    wait for a click forever)."""

    def __init__(self):
        from PySide import QtCore
        self.texts = []
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(self.poll)
        self.timer.start(50)

    def poll(self):
        from PySide import QtGui
        box = QtGui.QApplication.activeModalWidget()
        if isinstance(box, QtGui.QMessageBox):
            self.texts.append(box.text())
            box.done(0)

    def since(self, n):
        return self.texts[n:]


def open_panel_by_command(objs):
    import FreeCADGui
    from oraclemesh_fc import task_panel
    FreeCADGui.Selection.clearSelection()
    for o in objs:
        FreeCADGui.Selection.addSelection(o)
    FreeCADGui.runCommand("OracleMesh_MeshSelection")
    pump()
    return task_panel.current


def close_panel(panel, ok=True):
    if panel is not None:
        panel.accept() if ok else panel.reject()
    pump()


def task_view_scroll_area():
    """The scroll area of the combo view's task tab (its viewport is what the panel must fit)."""
    from oraclemesh_fc import task_panel
    from PySide import QtGui
    w = task_panel.current.form
    while w is not None and not isinstance(w, QtGui.QScrollArea):
        w = w.parentWidget()
    return w


def needed_width(widget):
    """Width the widget needs to show its text whole (no elision, no clipping)."""
    from PySide import QtGui
    if isinstance(widget, QtGui.QPushButton):
        style = widget.style()
        need = widget.fontMetrics().width(widget.text().replace("&", "")) \
            + style.pixelMetric(QtGui.QStyle.PM_ButtonMargin, None, widget) \
            + 2 * style.pixelMetric(QtGui.QStyle.PM_DefaultFrameWidth, None, widget)
        if not widget.icon().isNull():
            need += widget.iconSize().width() + 4
        return need
    if isinstance(widget, QtGui.QLabel) and widget.wordWrap():
        return 0  # checked by height instead
    return widget.minimumSizeHint().width()


def in_cell_of_a_table(widget, form):
    from PySide import QtGui
    w = widget.parentWidget()
    while w is not None and w is not form:
        if isinstance(w, QtGui.QAbstractItemView):
            return True
        w = w.parentWidget()
    return False


def layout_facts(panel):
    """Every visible label, button and group box of the panel and the dialog's buttons:
    inside the viewport and at least as wide as its text needs."""
    import FreeCADGui
    from PySide import QtCore, QtGui
    scroll = task_view_scroll_area()
    viewport = scroll.viewport()
    form = panel.form
    widgets = [w for w in form.findChildren(QtGui.QWidget)
               if isinstance(w, (QtGui.QLabel, QtGui.QAbstractButton, QtGui.QGroupBox))
               and w.isVisible() and not in_cell_of_a_table(w, form)]
    dialog_buttons = [b for box in FreeCADGui.getMainWindow().findChildren(QtGui.QDialogButtonBox)
                      if box.isVisible() and viewport.isAncestorOf(box) for b in box.buttons()]
    problems, checked = [], []
    for w in widgets + dialog_buttons:
        text = w.title() if isinstance(w, QtGui.QGroupBox) else getattr(w, "text", lambda: "")()
        if not text:
            continue  # the scroll arrows and corner buttons of tables
        top_left = w.mapTo(viewport, QtCore.QPoint(0, 0))
        rect = QtCore.QRect(top_left, w.size())
        checked.append(text)
        # Sideways only: the task view scrolls up and down, so rows below its fold are fine.
        if rect.left() < 0 or rect.right() >= viewport.width():
            problems.append("%r outside the panel: %s in %s" % (
                text, rect.getRect(), viewport.rect().getRect()))
        if w.width() < needed_width(w):
            problems.append("%r clipped: %d px of %d" % (text, w.width(), needed_width(w)))
        if isinstance(w, QtGui.QLabel) and w.wordWrap() and w.height() < w.heightForWidth(w.width()):
            problems.append("%r cut off: %d px high of %d" % (text, w.height(),
                                                               w.heightForWidth(w.width())))
    headers = []
    for table in (panel.inputs, panel.criteria):
        header = table.horizontalHeader()
        for i in range(header.count()):
            item = table.horizontalHeaderItem(i)
            need = header.fontMetrics().width(item.text()) + 2 * header.style().pixelMetric(
                QtGui.QStyle.PM_HeaderMargin, None, header)
            headers.append(item.text())
            if header.sectionSize(i) < need:
                problems.append("header %r clipped: %d px of %d" % (item.text(),
                                                                  header.sectionSize(i), need))
    tables = {}
    for name, table in (("inputs", panel.inputs), ("criteria", panel.criteria)):
        rows = table.verticalHeader().defaultSectionSize()
        tables[name] = {"visible_rows": table.viewport().height() / float(rows),
                        "row_heights": [table.rowHeight(i) for i in range(table.rowCount())],
                        "default_row": rows}
    options = [w for w in form.findChildren(QtGui.QWidget)
               if isinstance(w, (QtGui.QAbstractButton, QtGui.QAbstractSpinBox, QtGui.QComboBox,
                                 QtGui.QAbstractItemView))
               and not isinstance(w, (QtGui.QTextBrowser, QtGui.QHeaderView)) and w.isVisible()
               and (w.text() if isinstance(w, QtGui.QAbstractButton) else True)]
    without_tip = [describe(w) for w in options if not w.toolTip()]
    headers_without_tip = [table.horizontalHeaderItem(i).text()
                           for table in (panel.inputs, panel.criteria)
                           for i in range(table.columnCount())
                           if not table.horizontalHeaderItem(i).toolTip()]
    return {"combo_width": combo_view().width(), "viewport_width": viewport.width(),
            "form_width": form.width(), "horizontal_scroll": scroll.horizontalScrollBar().isVisible(),
            "checked": checked, "headers": headers, "problems": problems, "tables": tables,
            "options": len(options), "without_tooltip": without_tip + headers_without_tip}


def describe(widget):
    from PySide import QtGui
    if isinstance(widget, QtGui.QAbstractButton):
        return "%s %r" % (type(widget).__name__, widget.text())
    if isinstance(widget, QtGui.QComboBox):
        return "QComboBox %r" % widget.currentText()
    return "%s %s" % (type(widget).__name__, widget.objectName())


def combo_view():
    import FreeCADGui
    from PySide import QtGui
    return [d for d in FreeCADGui.getMainWindow().findChildren(QtGui.QDockWidget)
            if d.objectName() == "Combo View"][0]


def active_document_with(name, type_id, object_name):
    """A new active document holding one recomputed object: (document, object)."""
    import FreeCAD
    doc = FreeCAD.newDocument(name)
    FreeCAD.setActiveDocument(doc.Name)
    obj = doc.addObject(type_id, object_name)
    doc.recompute()
    pump()
    return doc, obj


def section(out, name, run):
    out[name] = {}
    try:
        run(out[name])
    except BaseException:
        out[name]["error"] = traceback.format_exc()


def check(out):
    import FreeCAD
    import FreeCADGui
    import FemGui
    from PySide import QtCore

    FreeCADGui.activateWorkbench("OracleMeshWorkbench")
    FreeCADGui.getMainWindow().resizeDocks([combo_view()], [COMBO_VIEW_WIDTH], QtCore.Qt.Horizontal)
    pump()
    import oraclemesh_fc.mesh_object as mo
    from oraclemesh_fc import demo, task_panel
    boxes = MessageBoxes()

    doc = FreeCAD.newDocument("Demo")
    analysis, solver, pin, plate, corner = demo.build(doc)
    FemGui.setActiveAnalysis(analysis)
    doc.recompute()
    state = {}

    def layout(r):
        panel = open_panel_by_command([pin, plate])
        state["mesh"] = panel.obj
        pump(0.5)
        r.update(layout_facts(panel))

    def cut_last(r):
        panel = task_panel.current
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(corner)
        panel.add_button.click()
        panel.inputs.cellWidget(2, 1).setCurrentIndex(task_panel.ROLES.index("cut"))
        pump()
        r["rows"] = [(row.obj.Name, row.role) for row in panel.rows]
        r["panel_warning"] = panel.cut_warning.text() if panel.cut_warning.isVisible() else ""
        r["applied"] = panel.apply_clicked()
        r["report"] = panel.report.toPlainText()
        # Moved to the top, the cut acts on everything: no warning left.
        panel.select_row(2)
        panel.up_button.click()
        panel.up_button.click()
        pump()
        r["rows_moved"] = [(row.obj.Name, row.role) for row in panel.rows]
        r["warning_after_move"] = panel.cut_warning.text() if panel.cut_warning.isVisible() else ""
        r["layout_with_warning_problems"] = layout_facts(panel)["problems"]

    def automatic(r):
        panel = task_panel.current
        mesh = panel.obj
        panel.cell_size.setValue(0.0)
        panel.facet_distance.setValue(0.0)
        panel.element_order.setCurrentIndex(panel.element_order.findData(1))
        # tet4 at these sizes leaves the pin 2 % short: kept (the next sections use this mesh),
        # the sizes shown and the time are what is tested here.
        mesh.Checks = "warn"
        pin_row = [row.obj.Name for row in panel.rows if row.role == "material"].index("Pin")
        panel.criteria.item(pin_row, 0).setText("5")
        pump()
        r["shown"] = {"cell_size": panel.cell_size.text(),
                      "facet_distance": panel.facet_distance.text(),
                      "materials": {row.obj.Label: {key: panel.automatic_text(i, j)
                                                    for j, (key, _) in enumerate(task_panel.CRITERIA_COLUMNS)}
                                    for i, row in enumerate(
                                        [x for x in panel.rows if x.role == "material"])}}
        r["delegate"] = type(panel.criteria.itemDelegate()).__name__
        n = len(boxes.texts)
        t0 = time.time()
        r["ok"] = panel.mesh()
        r["wall_seconds"] = time.time() - t0
        r["messages"] = boxes.since(n)
        r["status"] = mesh.Status
        report = json.loads(mesh.Report)
        r["criteria"] = report["criteria"]
        r["bbox_diagonal"] = report["bbox_diagonal"]
        r["materials"] = {e["label"]: e["material"] for e in report["freecad"]["inputs"]
                          if e["role"] == "material"}
        r["phase_seconds"] = report["seconds"]
        r["report"] = panel.report.toPlainText()
        r["inputs_visible"] = [o.ViewObject.Visibility for o in (pin, plate, corner)]

    def untouched(r):
        panel = task_panel.current
        mesh = panel.obj
        before = (mesh.Report, mesh.FemMesh.VolumeCount)
        r["touched_before"] = "Touched" in mesh.State
        panel.accept()
        pump()
        r["closed"] = task_panel.current is None
        r["touched_after_ok"] = "Touched" in mesh.State
        r["materials_touched"] = [m.Label for m in analysis.Group if "Touched" in m.State]
        # Reopened (double click) and OK again, still nothing changed.
        mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject)
        pump()
        task_panel.current.accept()
        pump()
        r["touched_after_second_ok"] = "Touched" in mesh.State
        calls = []
        original = mo.run_job
        mo.run_job = lambda job, label: calls.append(label) or original(job, label)
        try:
            doc.recompute()
        finally:
            mo.run_job = original
        r["meshed_on_recompute"] = len(calls)
        r["mesh_kept"] = (mesh.Report, mesh.FemMesh.VolumeCount) == before
        # A change is still written (and the mesh touched): the check compares, it does not block.
        mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject)
        pump()
        task_panel.current.sharp_angle.setValue(40.0)
        task_panel.current.accept()
        pump()
        r["changed_written"] = [mesh.SharpAngle.Value, "Touched" in mesh.State]
        mesh.SharpAngle = 30.0  # meshed (and failing) in the next section

    def interfaces(r):
        mesh = state["mesh"]
        mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject)
        pump()
        panel = task_panel.current
        box = panel.interfaces
        r["pairs_shown"] = [box.table.item(i, 0).text() for i in range(box.table.rowCount())]
        r["kinds_shown"] = [box.table.cellWidget(i, 1).currentText()
                            for i in range(box.table.rowCount())]
        r["default_shown"] = box.default.currentText()
        r["note_before"] = box.note.isVisible()
        row = r["pairs_shown"].index("Pin - Plate")
        combo = box.table.cellWidget(row, 1)
        r["choices"] = [combo.itemText(k) for k in range(combo.count())]
        combo.setCurrentIndex(r["choices"].index("contact"))
        n = len(boxes.texts)
        r["ok"] = panel.mesh()
        r["messages"] = boxes.since(n)
        r["stored"] = mesh.Interfaces
        report = json.loads(mesh.Report)
        r["report_kinds"] = {" - ".join(e["parts"]): e["kind"] for e in report["interfaces"]}
        r["face_groups"] = sorted(mesh.FemMesh.getGroupName(g) for g in mesh.FemMesh.Groups
                                  if mesh.FemMesh.getGroupElementType(g) == "Face")
        r["kinds_after_mesh"] = [box.table.cellWidget(i, 1).currentText()
                                 for i in range(box.table.rowCount())]
        panel.accept()
        pump()
        r["touched_after_ok"] = "Touched" in mesh.State
        # Reopened: the panel shows what the object stores.
        mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject)
        pump()
        box = task_panel.current.interfaces
        r["kinds_reopened"] = [box.table.cellWidget(i, 1).currentText()
                               for i in range(box.table.rowCount())]
        # The default combo: every pair not in the table's own choice follows it.
        box.default.setCurrentIndex(box.default.findText("tied"))
        task_panel.current.accept()
        pump()
        r["stored_with_default"] = mesh.Interfaces
        mesh.Interfaces = ""  # the next sections mesh bonded

    def failure(r):
        mesh = state["mesh"]
        mesh.ViewObject.Proxy.doubleClicked(mesh.ViewObject)
        pump()
        panel = task_panel.current
        before = (mesh.Report, mesh.FemMesh.VolumeCount)

        def broken(tets, edges):
            raise ValueError("a feature edge of the core is no edge of its tets")
        original = mo.feature_edge_mid_nodes
        mo.feature_edge_mid_nodes = broken
        try:
            n = len(boxes.texts)
            r["meshed"] = {"ok": panel.mesh(), "messages": boxes.since(n), "status": mesh.Status,
                           "report": panel.report.toPlainText(),
                           "mesh_kept": (mesh.Report, mesh.FemMesh.VolumeCount) == before,
                           "valid": bool(mesh.isValid())}
            panel.reject()
            pump()
            # A new mesh object whose first mesh fails: no "previous mesh", inputs shown.
            for o in (pin, plate):
                o.ViewObject.Visibility = True
            new_panel = open_panel_by_command([pin, plate])
            new_mesh = new_panel.obj
            new_panel.element_order.setCurrentIndex(new_panel.element_order.findData(1))
            new_mesh.Checks = "warn"  # as above: the hand-off's failure is what is tested
            inputs_after_command = [o.ViewObject.Visibility for o in (pin, plate)]
            for o in (pin, plate):
                o.ViewObject.Visibility = False  # as an older version of the command left them
            n = len(boxes.texts)
            r["first"] = {"ok": new_panel.mesh(),
                          # the document's recompute retries the failed first object as well
                          "messages": [t for t in boxes.since(n) if new_mesh.Label + "'" in t],
                          "status": new_mesh.Status, "report": new_panel.report.toPlainText(),
                          "volumes": new_mesh.FemMesh.VolumeCount,
                          "inputs_visible_after_command": inputs_after_command,
                          "inputs_visible": [o.ViewObject.Visibility for o in (pin, plate)]}
            new_panel.reject()
            pump()
            doc.removeObject(new_mesh.Name)
        finally:
            mo.feature_edge_mid_nodes = original

    def other_doc(r):
        FemGui.setActiveAnalysis(analysis)  # stays active while another document is worked on
        other, box = active_document_with("Other", "Part::Box", "Block")
        n = len(boxes.texts)
        error = None
        try:
            panel = open_panel_by_command([box])
        except Exception as e:
            panel, error = None, str(e)
        r["command_error"] = error
        r["messages"] = boxes.since(n)
        meshes = [o for o in other.Objects if o.TypeId == "Fem::FemMeshObjectPython"]
        r["meshes_in_other"] = len(meshes)
        r["panel_on_it"] = panel is not None and meshes and panel.obj == meshes[0]
        r["in_analysis"] = any(m in analysis.Group for m in meshes)
        r["analysis_group_doc"] = sorted({o.Document.Name for o in analysis.Group})
        close_panel(panel, ok=False)
        from oraclemesh_fc import makeMesh
        count = len(other.Objects)
        try:
            makeMesh(other, [box], analysis=analysis)
            r["make_mesh_error"] = None
        except ValueError as e:
            r["make_mesh_error"] = str(e)
        r["objects_added_by_refused_make_mesh"] = len(other.Objects) - count
        FreeCAD.setActiveDocument(doc.Name)

    def refused(r):
        plane_doc, plane = active_document_with("Planes", "Part::Plane", "Plane")
        n = len(boxes.texts)
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(plane)
        FreeCADGui.runCommand("OracleMesh_MeshSelection")
        pump(0.5)
        r["messages"] = boxes.since(n)
        r["objects"] = [o.TypeId for o in plane_doc.Objects]

    section(out, "layout", layout)
    section(out, "cut_last", cut_last)
    section(out, "automatic", automatic)
    section(out, "untouched", untouched)
    section(out, "interfaces", interfaces)
    section(out, "failure", failure)
    section(out, "other_doc", other_doc)
    section(out, "refused", refused)


main(check)
