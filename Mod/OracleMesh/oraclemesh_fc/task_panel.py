"""The OracleMesh task panel, shown by the view provider in edit mode (after the mesh command,
on double click, from the Edit command).

Everything it shows lives in the mesh object's properties; the panel edits a copy and writes
it back on Apply, Mesh or OK (one undo step each), so Cancel leaves the object as it was.

- Inputs in priority order (the first wins where inputs overlap), one row per part: a compound
  (an imported assembly) has a row per solid, named as the STEP file names it, unless it is
  treated as one input (input_rows.py). Rows move with Up/Down or by dragging a row onto
  another; per input its role (material or cut) and its material: a FemMaterial of the analysis (the input
  is then put into that material's References, which is what names the volume group and what
  FreeCAD's CalculiX writer reads) or a free name (group '<name>_Volumes').
- Per-material criteria (cell size, facet distance, facet size, radius-edge ratio; empty =
  the global value), a global cell size and coarse / moderate / fine presets.
- Engine, sharp-edge angle, junctions, planar faces, element order, optimisation.
- Extra edges kept as mesh edges: edges picked in the 3D view, whole sketches or shapes.
- The report of the last mesh: tets and volume per material, dihedral angles, warnings (the
  core's, and small angles between the faces of an input, see input_checks.py).
"""
import json

import FreeCADGui
from PySide import QtCore, QtGui

from . import job as jobmod
from . import input_rows, preferences
from .input_checks import input_warnings
from .selection import selected_solids

# Criteria table columns: (job key, header)
CRITERIA_COLUMNS = (
    ("cell_size", "Cell size"),
    ("facet_distance", "Facet distance"),
    ("facet_size", "Facet size"),
    ("cell_radius_edge_ratio", "Radius-edge ratio"),
)
ROLES = ("material", "cut")
AUTO_MATERIAL = "(automatic)"

# The open panel, so it is not garbage-collected while FreeCAD shows it (and tests reach it).
current = None


class InputTable(QtGui.QTableWidget):
    """The inputs table; a row dragged onto another row moves there (priority order).

    Qt's own row move would drop the role and material combo boxes of the moved row, so the
    drop only tells the panel which row goes where and the panel rebuilds the table."""

    def __init__(self, on_move):
        super().__init__(0, 3)
        self.on_move = on_move
        self.setDragEnabled(True)
        self.setAcceptDrops(True)
        self.setDragDropMode(QtGui.QAbstractItemView.InternalMove)
        self.setDropIndicatorShown(True)

    def dropEvent(self, event):
        rows = self.selectionModel().selectedRows()
        target = self.rowAt(event.pos().y())
        event.setDropAction(QtCore.Qt.IgnoreAction)
        event.accept()
        if rows:
            self.on_move(rows[0].row(), self.rowCount() - 1 if target < 0 else target)


class TaskPanel:

    def __init__(self, mesh_obj):
        global current
        current = self
        self.obj = mesh_obj
        self.doc = mesh_obj.Document
        self.fem_materials = jobmod.fem_materials(mesh_obj)
        self.rows = self.rows_from_object()
        # [(object, 'EdgeN' or '' for all its edges)], as the ExtraEdges property holds them
        self.extra_edges = [(ref[0], sub) for ref in mesh_obj.ExtraEdges
                            for sub in (jobmod._subnames(ref) or ("",))]
        self.form = self.build_form()
        self.load_options()
        self.refresh_inputs()
        self.show_report()

    # ------------------------------------------------------------------ model <-> object

    def material_of(self, obj, solid=None):
        return input_rows.material_of(self.obj, self.fem_materials, obj, solid)

    def rows_from_object(self):
        return input_rows.rows_from_object(self.obj, self.fem_materials)

    def apply(self):
        """Write the panel's state into the mesh object (and the FEM materials' References)."""
        self.read_tables()
        self.doc.openTransaction("OracleMesh settings")
        try:
            self.write_object()
        finally:
            self.doc.commitTransaction()

    def write_object(self):
        o = self.obj
        input_rows.write_rows(o, self.rows, self.fem_materials)
        o.CellSize = self.cell_size.value()
        o.FacetDistance = self.facet_distance.value()
        o.Engine = self.engine.currentData()
        o.SharpAngle = self.sharp_angle.value()
        o.Junctions = self.junctions.isChecked()
        o.PlanarFaces = self.planar_faces.isChecked()
        o.ElementOrder = self.element_order.currentData()
        o.Optimize = self.optimize.isChecked()
        o.ExtraEdges = jobmod.extra_edge_links(self.extra_edges)

    # ------------------------------------------------------------------ widgets

    def build_form(self):
        form = QtGui.QWidget()
        form.setWindowTitle("OracleMesh")
        form.setObjectName("OracleMeshTaskPanel")
        layout = QtGui.QVBoxLayout(form)

        box = QtGui.QGroupBox("Inputs (highest priority first: the first wins where they overlap)")
        v = QtGui.QVBoxLayout(box)
        self.inputs = InputTable(self.move_row)
        self.inputs.setHorizontalHeaderLabels(["Input", "Role", "Material"])
        self.inputs.setSelectionBehavior(QtGui.QAbstractItemView.SelectRows)
        self.inputs.setSelectionMode(QtGui.QAbstractItemView.SingleSelection)
        self.inputs.horizontalHeader().setStretchLastSection(True)
        self.inputs.verticalHeader().setVisible(True)
        v.addWidget(self.inputs)
        buttons = QtGui.QHBoxLayout()
        self.up_button = QtGui.QPushButton("Up")
        self.down_button = QtGui.QPushButton("Down")
        self.add_button = QtGui.QPushButton("Add selected")
        self.remove_button = QtGui.QPushButton("Remove")
        for b in (self.up_button, self.down_button, self.add_button, self.remove_button):
            buttons.addWidget(b)
        v.addLayout(buttons)
        self.up_button.clicked.connect(lambda: self.move_selected(-1))
        self.down_button.clicked.connect(lambda: self.move_selected(+1))
        self.add_button.clicked.connect(self.add_selected)
        self.remove_button.clicked.connect(self.remove_selected)
        self.whole_check = QtGui.QCheckBox("Treat the selected compound as one input")
        self.whole_check.setToolTip("One row, one material and one volume group for all solids "
                                    "of the selected compound, instead of one row per solid")
        self.whole_check.setEnabled(False)
        self.whole_check.toggled.connect(self.set_whole)
        v.addWidget(self.whole_check)
        self.inputs.itemSelectionChanged.connect(self.sync_whole_check)
        layout.addWidget(box)

        box = QtGui.QGroupBox("Sizes (model units; 0 or empty = automatic)")
        v = QtGui.QVBoxLayout(box)
        grid = QtGui.QFormLayout()
        self.cell_size = self.length_box()
        self.facet_distance = self.length_box()
        grid.addRow("Global cell size", self.cell_size)
        grid.addRow("Global facet distance", self.facet_distance)
        v.addLayout(grid)
        presets = QtGui.QHBoxLayout()
        self.preset_buttons = {}
        for name, divisor in preferences.PRESETS:
            if divisor is None:
                continue
            b = QtGui.QPushButton(name.capitalize())
            b.setToolTip("Cell size = model diagonal / %g" % divisor)
            b.clicked.connect(lambda checked=False, n=name: self.apply_preset(n))
            presets.addWidget(b)
            self.preset_buttons[name] = b
        v.addLayout(presets)
        self.criteria = QtGui.QTableWidget(0, len(CRITERIA_COLUMNS))
        self.criteria.setHorizontalHeaderLabels([h for _, h in CRITERIA_COLUMNS])
        self.criteria.setToolTip("Per-material criteria; an empty cell takes the global value")
        v.addWidget(self.criteria)
        layout.addWidget(box)

        box = QtGui.QGroupBox("Meshing")
        grid = QtGui.QFormLayout(box)
        self.engine = QtGui.QComboBox()
        preferences.add_engines(self.engine)
        grid.addRow("Engine", self.engine)
        self.sharp_angle = QtGui.QDoubleSpinBox()
        self.sharp_angle.setRange(0.0, 180.0)
        self.sharp_angle.setSuffix(" deg")
        self.sharp_angle.setToolTip("Edges whose faces meet at more than this angle are kept "
                                    "as mesh edges (0 = off)")
        grid.addRow("Sharp-edge angle", self.sharp_angle)
        self.junctions = QtGui.QCheckBox("Keep junction curves between inputs")
        grid.addRow(self.junctions)
        self.planar_faces = QtGui.QCheckBox("Keep planar faces flat (thesis engine)")
        self.planar_faces.setToolTip("Planar faces bounded by sharp edges, such as planar contact "
                                     "faces of an assembly, are meshed as planes")
        grid.addRow(self.planar_faces)
        self.element_order = QtGui.QComboBox()
        self.element_order.addItem("1 - linear (C3D4)", 1)
        self.element_order.addItem("2 - quadratic (C3D10)", 2)
        grid.addRow("Element order", self.element_order)
        self.optimize = QtGui.QCheckBox("Remove slivers (perturb and exude)")
        grid.addRow(self.optimize)
        layout.addWidget(box)

        box = QtGui.QGroupBox("Extra edges (kept as mesh edges)")
        v = QtGui.QVBoxLayout(box)
        self.extra_list = QtGui.QListWidget()
        self.extra_list.setToolTip("Edges picked in the 3D view and whole sketches or shapes "
                                   "(all their edges); they must lie inside or on the parts")
        self.extra_list.setSelectionMode(QtGui.QAbstractItemView.ExtendedSelection)
        v.addWidget(self.extra_list)
        buttons = QtGui.QHBoxLayout()
        self.extra_add_button = QtGui.QPushButton("Add selection")
        self.extra_remove_button = QtGui.QPushButton("Remove")
        buttons.addWidget(self.extra_add_button)
        buttons.addWidget(self.extra_remove_button)
        v.addLayout(buttons)
        self.extra_add_button.clicked.connect(self.add_extra_edges)
        self.extra_remove_button.clicked.connect(self.remove_extra_edges)
        layout.addWidget(box)

        actions = QtGui.QHBoxLayout()
        self.apply_button = QtGui.QPushButton("Apply")
        self.mesh_button = QtGui.QPushButton("Mesh")
        self.apply_button.clicked.connect(self.apply_clicked)
        self.mesh_button.clicked.connect(self.mesh)
        actions.addWidget(self.apply_button)
        actions.addWidget(self.mesh_button)
        layout.addLayout(actions)

        self.report = QtGui.QTextBrowser()
        self.report.setMinimumHeight(120)
        layout.addWidget(self.report)
        return form

    @staticmethod
    def length_box():
        box = QtGui.QDoubleSpinBox()
        box.setRange(0.0, 1e9)
        box.setDecimals(4)
        box.setSpecialValueText("automatic")
        return box

    def load_options(self):
        o = self.obj
        self.cell_size.setValue(jobmod._value(o.CellSize))
        self.facet_distance.setValue(jobmod._value(o.FacetDistance))
        self.engine.setCurrentIndex(max(self.engine.findData(o.Engine), 0))
        self.sharp_angle.setValue(jobmod._value(o.SharpAngle))
        self.junctions.setChecked(bool(o.Junctions))
        self.planar_faces.setChecked(bool(getattr(o, "PlanarFaces", False)))
        self.element_order.setCurrentIndex(max(self.element_order.findData(o.ElementOrder), 0))
        self.optimize.setChecked(bool(o.Optimize))
        self.refresh_extra_edges()

    def material_choices(self):
        return [AUTO_MATERIAL] + [m.Label for m in self.fem_materials]

    def refresh_inputs(self):
        """Rebuild both tables from self.rows (after a move, add or remove)."""
        self.inputs.setRowCount(len(self.rows))
        for i, r in enumerate(self.rows):
            item = QtGui.QTableWidgetItem(r.label)
            item.setFlags(QtCore.Qt.ItemIsSelectable | QtCore.Qt.ItemIsEnabled)
            item.setToolTip("%s (%s of '%s'), priority %d" % (r.label, r.key, r.obj.Label, i + 1))
            self.inputs.setItem(i, 0, item)
            role = QtGui.QComboBox()
            role.addItems(ROLES)
            role.setCurrentIndex(ROLES.index(r.role))
            role.currentIndexChanged.connect(lambda k, row=r: self.set_role(row, ROLES[k]))
            self.inputs.setCellWidget(i, 1, role)
            material = QtGui.QComboBox()
            material.setEditable(True)  # a FemMaterial of the analysis, or any name
            material.addItems(self.material_choices())
            material.setEditText(r.material or AUTO_MATERIAL)
            material.setEnabled(r.role == "material")
            material.editTextChanged.connect(lambda text, row=r: self.set_material(row, text))
            self.inputs.setCellWidget(i, 2, material)
        materials = [r for r in self.rows if r.role == "material"]
        self.criteria.setRowCount(len(materials))
        self.criteria.setVerticalHeaderLabels([r.label for r in materials])
        for i, r in enumerate(materials):
            for j, (key, _) in enumerate(CRITERIA_COLUMNS):
                value = r.sizes.get(key)
                self.criteria.setItem(i, j, QtGui.QTableWidgetItem(
                    "" if value is None else "%g" % value))

    def read_tables(self):
        """Criteria table cells -> rows (the other widgets write into rows as they change)."""
        materials = [r for r in self.rows if r.role == "material"]
        for i, r in enumerate(materials):
            for j, (key, header) in enumerate(CRITERIA_COLUMNS):
                item = self.criteria.item(i, j)
                text = item.text().strip() if item is not None else ""
                if not text:
                    r.sizes.pop(key, None)
                    continue
                try:
                    value = float(text)
                except ValueError:
                    value = float("nan")
                if not value > 0:
                    raise jobmod.MeshInputError(
                        "%s of '%s' is '%s': give a positive number, or leave the cell empty"
                        % (header, r.label, text))
                r.sizes[key] = value

    def set_role(self, row, role):
        self.read_tables()
        row.role = role
        if role == "cut" and row.solid is not None:  # a cut removes its whole shape
            self.rows = input_rows.join_rows(self.rows, row.obj)
            self.rows[[r.obj for r in self.rows].index(row.obj)].role = "cut"
        self.refresh_inputs()

    def sync_whole_check(self):
        """The checkbox shows whether the selected row's compound is one input."""
        i = self.selected_row()
        row = self.rows[i] if 0 <= i < len(self.rows) else None
        solids = len(getattr(getattr(row.obj, "Shape", None), "Solids", [])) if row else 0
        self.whole_check.blockSignals(True)
        self.whole_check.setEnabled(row is not None and row.role == "material" and solids > 1)
        self.whole_check.setChecked(row is not None and solids > 1 and row.solid is None)
        self.whole_check.blockSignals(False)

    def set_whole(self, whole):
        """Join the selected compound's solid rows into one row, or split it again."""
        i = self.selected_row()
        if not 0 <= i < len(self.rows):
            return
        self.read_tables()
        obj = self.rows[i].obj
        if whole:
            self.rows = input_rows.join_rows(self.rows, obj)
        else:
            self.rows = input_rows.split_rows(self.obj, self.fem_materials, self.rows, obj)
        self.refresh_inputs()
        self.select_row([r.obj for r in self.rows].index(obj))

    def set_material(self, row, text):
        row.material = "" if text.strip() in ("", AUTO_MATERIAL) else text.strip()

    def selected_row(self):
        rows = self.inputs.selectionModel().selectedRows()
        return rows[0].row() if rows else -1

    def select_row(self, i):
        self.inputs.selectRow(i)

    def move_selected(self, step):
        """Move the selected input up (step -1, higher priority) or down (+1)."""
        i = self.selected_row()
        if i >= 0:
            self.move_row(i, i + step)

    def move_row(self, i, j):
        """Move input i to position j (up/down buttons, drag and drop)."""
        if not (0 <= i < len(self.rows) and 0 <= j < len(self.rows)) or i == j:
            return
        self.read_tables()
        self.rows.insert(j, self.rows.pop(i))
        self.refresh_inputs()
        self.select_row(j)

    def add_selected(self):
        self.read_tables()
        present = {r.obj.Name for r in self.rows}
        for obj in selected_solids():
            if obj.Name not in present and obj != self.obj:
                self.rows += input_rows.rows_for_object(
                    self.obj, self.fem_materials, obj, obj in self.obj.WholeInputs,
                    [r.label for r in self.rows])
        self.refresh_inputs()

    def remove_selected(self):
        i = self.selected_row()
        if i < 0:
            return
        self.read_tables()
        obj = self.rows[i].obj  # a compound goes with all its solids
        self.rows = [r for r in self.rows if r.obj != obj]
        self.refresh_inputs()

    def refresh_extra_edges(self):
        self.extra_list.clear()
        for obj, sub in self.extra_edges:
            self.extra_list.addItem("%s of '%s'" % (sub, obj.Label) if sub
                                    else "'%s' (all edges)" % obj.Label)

    def add_extra_edges(self):
        """Edges picked in the 3D view, and whole objects with edges picked in the tree."""
        skipped = []
        for sel in FreeCADGui.Selection.getSelectionEx():
            obj = sel.Object
            if obj == self.obj:
                continue
            subs = [s for s in sel.SubElementNames if s]
            picked = [(obj, s) for s in subs if s.startswith("Edge")]
            skipped += ["%s of '%s'" % (s, obj.Label) for s in subs if not s.startswith("Edge")]
            if not subs:
                shape = getattr(obj, "Shape", None)
                if shape is not None and not shape.isNull() and shape.Edges:
                    picked = [(obj, "")]
                else:
                    skipped.append("'%s'" % obj.Label)
            for item in picked:
                if item not in self.extra_edges:
                    self.extra_edges.append(item)
        self.refresh_extra_edges()
        if skipped:
            self.report.setPlainText("Not added as extra edges (pick edges, or sketches and "
                                     "shapes in the tree): %s" % ", ".join(skipped))

    def remove_extra_edges(self):
        rows = sorted({i.row() for i in self.extra_list.selectedIndexes()}, reverse=True)
        for i in rows:
            del self.extra_edges[i]
        self.refresh_extra_edges()

    def apply_preset(self, name):
        self.cell_size.setValue(preferences.preset_cell_size(name, [r.obj for r in self.rows]))

    # ------------------------------------------------------------------ actions

    def apply_clicked(self):
        try:
            self.apply()
        except jobmod.MeshInputError as e:  # a bad table cell: say which, change nothing
            self.report.setPlainText(str(e))
            return False
        return True

    def mesh(self):
        """Apply, then recompute the mesh object (progress dialog; errors shown by the object)."""
        try:
            self.apply()
        except jobmod.MeshInputError as e:
            self.report.setPlainText(str(e))
            return False
        self.doc.openTransaction("OracleMesh mesh")
        self.obj.touch()
        self.doc.recompute()
        self.doc.commitTransaction()
        # A selected mesh is drawn all in FreeCAD's highlight colour, over the material colours.
        FreeCADGui.Selection.removeSelection(self.obj)
        self.show_report()
        return self.obj.isValid()

    def show_report(self):
        self.report.setHtml(report_html(self.obj))

    def accept(self):
        try:
            self.apply()
        except jobmod.MeshInputError as e:
            QtGui.QMessageBox.warning(self.form, "OracleMesh", str(e))
            return False
        self.close()
        return True

    def reject(self):
        self.close()
        return True

    def close(self):
        """Leave edit mode (the view provider's unsetEdit closes the dialog); no remesh."""
        global current
        current = None
        gui_doc = FreeCADGui.getDocument(self.doc.Name)
        if gui_doc is not None and gui_doc.getInEdit() is not None:
            gui_doc.resetEdit()
        else:
            FreeCADGui.Control.closeDialog()

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)


def report_html(obj):
    """The last mesh's report as short HTML: status, per material counts, quality, warnings."""
    esc = lambda s: (str(s).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;"))  # noqa: E731
    parts = ["<p><b>%s</b></p>" % esc(obj.Status or "Not meshed yet.")]
    if not obj.Report:
        return "".join(parts)
    try:
        report = json.loads(obj.Report)
    except ValueError:
        return "".join(parts)
    counts = report.get("counts", {})
    per_material = counts.get("tets_per_material", {})
    volumes = report.get("volume_per_material", {})
    rows = []
    for entry in report.get("freecad", {}).get("inputs", []):
        if entry.get("role") != "material":
            continue
        mid = str(entry.get("material"))
        rows.append("<tr><td>%s</td><td>%s</td><td align=right>%s</td><td align=right>%.6g</td></tr>"
                    % (esc(entry.get("label")), esc(entry.get("group")),
                       per_material.get(mid, 0), volumes.get(mid, 0.0)))
    parts.append("<table border=0 cellspacing=4><tr><th>Input</th><th>Group</th><th>Tets</th>"
                 "<th>Volume</th></tr>%s</table>" % "".join(rows))
    q = report.get("quality", {})
    parts.append("<p>%s vertices, %s tets; dihedral angles %.1f&ndash;%.1f&deg;; "
                 "max radius-edge ratio %.2f</p>"
                 % (counts.get("vertices", "?"), counts.get("tets", "?"),
                    q.get("min_dihedral_deg", float("nan")), q.get("max_dihedral_deg", float("nan")),
                    q.get("max_radius_edge_ratio", float("nan"))))
    warnings = list(report.get("warnings", []))
    warnings += input_warnings(obj)
    if warnings:
        parts.append("<p><b>Warnings</b></p><ul>%s</ul>"
                     % "".join("<li>%s</li>" % esc(w) for w in warnings))
    seconds = report.get("seconds", {})
    if seconds:
        total = sum(v for k, v in seconds.items() if not k.startswith("mesh3_"))
        parts.append("<p>%.1f s</p>" % total)
    return "".join(parts)
