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
- Interfaces: per pair of touching parts the last mesh found, bonded / tied / contact /
  separate, and the default of the others (interface_table.py); used by the next mesh.
- The report of the last mesh: tets and volume per material, dihedral angles, warnings (the
  core's, and small angles between the faces of an input, see input_checks.py), or why
  meshing failed.

It fits FreeCAD's default combo view (264 px wide): short labels with the explanations in
tooltips, form rows wrapped, buttons no wider than their text needs. "automatic" shows the
value the core will use (sizes.py). Traps are said where they are set: a cut with no
material input below it, which would remove nothing. OK and Apply without a change write
nothing, so the mesh is not touched (no remesh on the next recompute).
"""

import FreeCADGui
from PySide import QtCore, QtGui

from . import job as jobmod
from . import input_rows, interfaces, preferences
from .interface_table import InterfaceBox
from . import sizes
from .panel_widgets import AutomaticDelegate, fit_columns, fit_text, narrow_form, show_rows
from .input_checks import cut_warnings, input_warnings
from .selection import ACCEPTED, refusal, selected_solids

# Criteria table columns: (job key, name)
CRITERIA_COLUMNS = (
    ("cell_size", "Cell size"),
    ("facet_distance", "Facet distance"),
    ("facet_size", "Facet size"),
    ("cell_radius_edge_ratio", "Radius-edge ratio"),
)
# Job key -> (header short enough for the combo view, tooltip)
CRITERIA_HEADERS = {
    "cell_size": ("Cell", "Cell size: largest tetrahedron circumradius"),
    "facet_distance": ("Distance", "Facet distance: largest distance of a surface triangle "
                                   "from the CAD surface"),
    "facet_size": ("Facet", "Facet size: largest surface triangle (circumradius)"),
    "cell_radius_edge_ratio": ("Ratio", "Radius-edge ratio: largest circumradius / shortest "
                                        "edge of a tetrahedron"),
}
ROLES = ("material", "cut")
AUTO_MATERIAL = "(automatic)"
# Rows the inputs and criteria tables show without scrolling.
VISIBLE_ROWS = 5
INPUT_COLUMN_TIPS = (
    "The input object (hover a row for its name and priority)",
    "material: meshed; cut: removes material from the inputs below it",
    "A FEM material of the analysis (its References get the input) or any name: the volume "
    "group is '<name>_Volumes'",
)

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
        self.diagonal, self.automatic = 0.0, {}  # model size and sizes of the rows shown
        try:
            self.interface_settings = jobmod.interface_settings(mesh_obj)
        except jobmod.MeshInputError:
            self.interface_settings = {}  # a bad property text: meshing says what is wrong
        self.form = self.build_form()
        self.load_options()
        self.refresh_inputs()
        self.show_report()
        self.loaded_state = self.state()

    # ------------------------------------------------------------------ model <-> object

    def material_of(self, obj, solid=None):
        return input_rows.material_of(self.obj, self.fem_materials, obj, solid)

    def rows_from_object(self):
        return input_rows.rows_from_object(self.obj, self.fem_materials)

    def apply(self):
        """Write the panel's state into the mesh object (and the FEM materials' References).

        Nothing is written when nothing changed since the panel opened or last applied: a
        written property touches the mesh object, and a touched mesh is meshed again on the
        next recompute (minutes on a large assembly)."""
        self.read_tables()
        state = self.state()
        if state == self.loaded_state:
            return
        self.doc.openTransaction("OracleMesh settings")
        try:
            self.write_object()
        finally:
            self.doc.commitTransaction()
        self.loaded_state = state

    def state(self):
        """What the panel would write, as comparable values (objects by Name)."""
        def plain(value):
            if hasattr(value, "Name") and hasattr(value, "Document"):
                return value.Name
            if isinstance(value, dict):
                return tuple(sorted((k, plain(v)) for k, v in value.items()))
            if isinstance(value, (list, tuple)):
                return tuple(plain(v) for v in value)
            return value
        rows = tuple(plain(vars(r)) for r in self.rows)
        # The settings the table makes, not its rows: the rows a new mesh adds change nothing.
        return (rows, plain(self.extra_edges), self.option_values(),
                interfaces.to_text(self.interfaces.settings(self.interface_settings)))

    def option_values(self):
        return (self.cell_size.value(), self.facet_distance.value(), self.fineness.currentData(),
                self.engine.currentData(),
                self.sharp_angle.value(), self.junctions.isChecked(),
                self.planar_faces.isChecked(), self.element_order.currentData(),
                self.optimize.isChecked())

    def write_object(self):
        o = self.obj
        input_rows.write_rows(o, self.rows, self.fem_materials)
        o.CellSize = self.cell_size.value()
        o.FacetDistance = self.facet_distance.value()
        o.Fineness = self.fineness.currentData()
        o.Engine = self.engine.currentData()
        o.SharpAngle = self.sharp_angle.value()
        o.Junctions = self.junctions.isChecked()
        o.PlanarFaces = self.planar_faces.isChecked()
        o.ElementOrder = self.element_order.currentData()
        o.Optimize = self.optimize.isChecked()
        o.ExtraEdges = jobmod.extra_edge_links(self.extra_edges)
        self.interface_settings = self.interfaces.settings(self.interface_settings)
        text = interfaces.to_text(self.interface_settings)
        if o.Interfaces != text:
            o.Interfaces = text

    # ------------------------------------------------------------------ widgets

    def build_form(self):
        form = QtGui.QWidget()
        form.setWindowTitle("OracleMesh")
        form.setObjectName("OracleMeshTaskPanel")
        layout = QtGui.QVBoxLayout(form)
        layout.setContentsMargins(0, 0, 0, 0)  # the task box around the form has its own

        box = QtGui.QGroupBox("Inputs, highest priority first")
        box.setToolTip("Where inputs overlap, the one higher in the list wins; a cut removes "
                       "material from the inputs below it. Drag rows or use Up and Down.")
        v = QtGui.QVBoxLayout(box)
        self.inputs = InputTable(self.move_row)
        self.inputs.setHorizontalHeaderLabels(["Input", "Role", "Material"])
        for i, tip in enumerate(INPUT_COLUMN_TIPS):
            self.inputs.horizontalHeaderItem(i).setToolTip(tip)
        self.inputs.setToolTip("Inputs in priority order; drag a row onto another to move it")
        self.inputs.setSelectionBehavior(QtGui.QAbstractItemView.SelectRows)
        self.inputs.setSelectionMode(QtGui.QAbstractItemView.SingleSelection)
        self.inputs.horizontalHeader().setStretchLastSection(True)
        self.inputs.verticalHeader().setVisible(True)
        fit_columns(self.inputs)
        show_rows(self.inputs, VISIBLE_ROWS)
        v.addWidget(self.inputs)
        self.cut_warning = QtGui.QLabel()
        self.cut_warning.setWordWrap(True)
        self.cut_warning.setStyleSheet("color: #b00000")
        self.cut_warning.setToolTip("A cut removes material only from the inputs below it")
        self.cut_warning.hide()
        v.addWidget(self.cut_warning)
        buttons = QtGui.QGridLayout()
        self.up_button = QtGui.QPushButton("Up")
        self.down_button = QtGui.QPushButton("Down")
        self.add_button = QtGui.QPushButton("Add selected")
        self.remove_button = QtGui.QPushButton("Remove")
        for k, (b, tip) in enumerate((
                (self.up_button, "Move the selected input up: higher priority"),
                (self.down_button, "Move the selected input down: lower priority"),
                (self.add_button, "Add the solids selected in the tree or the 3D view, at the "
                                  "end of the list (lowest priority)"),
                (self.remove_button, "Remove the selected input from the mesh"))):
            b.setToolTip(tip)
            buttons.addWidget(b, k // 2, k % 2)
        v.addLayout(buttons)
        self.up_button.clicked.connect(lambda: self.move_selected(-1))
        self.down_button.clicked.connect(lambda: self.move_selected(+1))
        self.add_button.clicked.connect(self.add_selected)
        self.remove_button.clicked.connect(self.remove_selected)
        self.whole_check = QtGui.QCheckBox("Treat as one input")
        self.whole_check.setToolTip("One row, one material and one volume group for all solids "
                                    "of the selected compound, instead of one row per solid")
        self.whole_check.setEnabled(False)
        self.whole_check.toggled.connect(self.set_whole)
        v.addWidget(self.whole_check)
        self.inputs.itemSelectionChanged.connect(self.sync_whole_check)
        layout.addWidget(box)

        box = QtGui.QGroupBox("Sizes (model units)")
        box.setToolTip("0 or an empty cell = automatic: the value shown is what the mesher "
                       "will use")
        v = QtGui.QVBoxLayout(box)
        grid = narrow_form()
        self.cell_size = self.length_box()
        self.cell_size.setToolTip("Largest tetrahedron circumradius of every material without "
                                  "its own cell size (0 = automatic: model diagonal / %g)"
                                  % sizes.CELL_SIZE_DIVISOR)
        self.facet_distance = self.length_box()
        self.facet_distance.setToolTip("Largest distance of a surface triangle from the CAD "
                                       "surface (0 = automatic: facet size / 10)")
        self.fineness = QtGui.QComboBox()
        for name in sizes.FINENESS_NAMES:
            self.fineness.addItem(name, name)
        self.fineness.setToolTip(self.obj.getDocumentationOfProperty("Fineness"))
        grid.addRow("Cell size", self.cell_size)
        grid.addRow("Facet distance", self.facet_distance)
        grid.addRow("From geometry", self.fineness)
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
        self.criteria.setHorizontalHeaderLabels(
            [CRITERIA_HEADERS[k][0] for k, _ in CRITERIA_COLUMNS])
        for i, (key, _) in enumerate(CRITERIA_COLUMNS):
            self.criteria.horizontalHeaderItem(i).setToolTip(CRITERIA_HEADERS[key][1])
        self.criteria.setToolTip("Per-material criteria; an empty cell takes the global value, "
                                 "shown in grey")
        self.criteria.setItemDelegate(AutomaticDelegate(self.automatic_text, self.criteria))
        fit_columns(self.criteria)
        self.criteria.itemChanged.connect(lambda item: self.refresh_automatic())
        show_rows(self.criteria, VISIBLE_ROWS)
        v.addWidget(self.criteria)
        layout.addWidget(box)
        self.cell_size.valueChanged.connect(lambda value: self.refresh_automatic())
        self.facet_distance.valueChanged.connect(lambda value: self.refresh_automatic())

        box = QtGui.QGroupBox("Meshing")
        grid = narrow_form(box)
        self.engine = QtGui.QComboBox()
        preferences.add_engines(self.engine)
        self.engine.setToolTip("Rule Set T (thesis): constrained segments, per-material "
                               "radius-edge ratio; CGAL Mesh_3: protecting balls")
        grid.addRow("Engine", self.engine)
        self.sharp_angle = QtGui.QDoubleSpinBox()
        self.sharp_angle.setRange(0.0, 180.0)
        self.sharp_angle.setSuffix(" deg")
        self.sharp_angle.setSpecialValueText("off")
        self.sharp_angle.setToolTip("Edges whose faces meet at more than this angle are kept "
                                    "as mesh edges (0 = off: no sharp edges, no junctions)")
        grid.addRow("Sharp-edge angle", self.sharp_angle)
        self.junctions = QtGui.QCheckBox("Junction curves")
        self.junctions.setToolTip("Keep the curves where two inputs' boundaries meet (material "
                                  "junctions) as mesh edges")
        grid.addRow(self.junctions)
        self.planar_faces = QtGui.QCheckBox("Flat planar faces")
        self.planar_faces.setToolTip("Planar faces bounded by sharp edges, such as planar contact "
                                     "faces of an assembly, are meshed as planes (thesis engine; "
                                     "needs a sharp-edge angle and junction curves)")
        grid.addRow(self.planar_faces)
        self.element_order = QtGui.QComboBox()
        self.element_order.addItem("1 - linear (C3D4)", 1)
        self.element_order.addItem("2 - quadratic (C3D10)", 2)
        self.element_order.setToolTip("Quadratic tetrahedra have their mid nodes on the CAD "
                                      "faces and curves")
        grid.addRow("Element order", self.element_order)
        self.optimize = QtGui.QCheckBox("Remove slivers")
        self.optimize.setToolTip("Remove flat tetrahedra (thesis engine: its sliver rule and vertex "
                                 "moves; CGAL: perturb and exude)")
        grid.addRow(self.optimize)
        layout.addWidget(box)

        box = QtGui.QGroupBox("Extra mesh edges")
        box.setToolTip("Curves kept as chains of mesh edges")
        v = QtGui.QVBoxLayout(box)
        self.extra_list = QtGui.QListWidget()
        self.extra_list.setToolTip("Edges picked in the 3D view and whole sketches or shapes "
                                   "(all their edges); they must lie inside or on the parts")
        self.extra_list.setSelectionMode(QtGui.QAbstractItemView.ExtendedSelection)
        v.addWidget(self.extra_list)
        buttons = QtGui.QHBoxLayout()
        self.extra_add_button = QtGui.QPushButton("Add selection")
        self.extra_add_button.setToolTip("Add the edges picked in the 3D view, or the sketches "
                                         "and shapes selected in the tree")
        self.extra_remove_button = QtGui.QPushButton("Remove")
        self.extra_remove_button.setToolTip("Remove the selected extra edges")
        buttons.addWidget(self.extra_add_button)
        buttons.addWidget(self.extra_remove_button)
        v.addLayout(buttons)
        self.extra_add_button.clicked.connect(self.add_extra_edges)
        self.extra_remove_button.clicked.connect(self.remove_extra_edges)
        layout.addWidget(box)

        self.interfaces = InterfaceBox(VISIBLE_ROWS)
        layout.addWidget(self.interfaces.box)

        actions = QtGui.QHBoxLayout()
        self.apply_button = QtGui.QPushButton("Apply")
        self.apply_button.setToolTip("Write the settings into the mesh object (no meshing)")
        self.mesh_button = QtGui.QPushButton("Mesh")
        self.mesh_button.setToolTip("Apply, then mesh now (a progress dialog can cancel it)")
        self.apply_button.clicked.connect(self.apply_clicked)
        self.mesh_button.clicked.connect(self.mesh)
        actions.addWidget(self.apply_button)
        actions.addWidget(self.mesh_button)
        layout.addLayout(actions)

        self.report = QtGui.QTextBrowser()
        self.report.setMinimumHeight(120)
        self.report.setToolTip("The last mesh, or why meshing failed; warnings about the inputs")
        layout.addWidget(self.report)
        for button in form.findChildren(QtGui.QPushButton):
            fit_text(button)
        return form

    @staticmethod
    def length_box():
        box = QtGui.QDoubleSpinBox()
        box.setRange(0.0, 1e6)
        box.setDecimals(4)
        box.setSpecialValueText("automatic")
        return box

    # ------------------------------------------------------------------ automatic sizes

    def automatic_sizes(self):
        """(resolved defaults, {row index in the criteria table: resolved criteria}) as the
        core will resolve the panel's current settings."""
        given = {}
        for prop, key in jobmod.CRITERIA_PROPERTIES:
            value = jobmod._value(getattr(self.obj, prop))
            if value > 0:
                given[key] = value
        for key, box in (("cell_size", self.cell_size), ("facet_distance", self.facet_distance)):
            given.pop(key, None)
            if box.value() > 0:
                given[key] = box.value()
        defaults = sizes.resolved_defaults(self.diagonal, given)
        materials = [r for r in self.rows if r.role == "material"]
        per_row = {}
        for i, r in enumerate(materials):
            own = {}
            for j, (key, _) in enumerate(CRITERIA_COLUMNS):
                item = self.criteria.item(i, j)
                try:
                    value = float(item.text()) if item is not None and item.text().strip() else 0
                except ValueError:
                    value = 0
                if value > 0:
                    own[key] = value
            per_row[i] = sizes.resolved_material(defaults, own)
        return defaults, per_row

    def automatic_text(self, row, column):
        """Text of an empty criteria cell: the value that material will get."""
        per_row = self.automatic.get(row)
        if per_row is None or self.diagonal <= 0:
            return ""
        return "%.4g" % per_row[CRITERIA_COLUMNS[column][0]]

    def refresh_automatic(self):
        """Show in every "automatic" the value the core will use."""
        defaults, self.automatic = self.automatic_sizes()
        for key, box in (("cell_size", self.cell_size), ("facet_distance", self.facet_distance)):
            box.setSpecialValueText("automatic (%.4g)" % defaults[key] if self.diagonal > 0
                                    else "automatic")
        self.criteria.resizeColumnsToContents()  # the automatic texts are no cell data
        self.criteria.viewport().update()

    def load_options(self):
        o = self.obj
        self.cell_size.setValue(jobmod._value(o.CellSize))
        self.facet_distance.setValue(jobmod._value(o.FacetDistance))
        self.fineness.setCurrentIndex(max(self.fineness.findData(str(getattr(o, "Fineness", "off"))), 0))
        self.engine.setCurrentIndex(max(self.engine.findData(o.Engine), 0))
        self.sharp_angle.setValue(jobmod._value(o.SharpAngle))
        self.junctions.setChecked(bool(o.Junctions))
        self.planar_faces.setChecked(bool(getattr(o, "PlanarFaces", False)))
        self.element_order.setCurrentIndex(max(self.element_order.findData(o.ElementOrder), 0))
        self.optimize.setChecked(bool(o.Optimize))
        self.refresh_extra_edges()
        self.interfaces.load(self.interface_settings, interfaces.last_report(o))

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
        self.rows_changed()

    def rows_changed(self):
        """What follows from the rows: the model size behind "automatic", the cut warning,
        the tooltips of the cell widgets."""
        self.diagonal = sizes.model_diagonal([r.obj for r in self.rows if r.role == "material"])
        self.refresh_automatic()
        warnings = cut_warnings([(r.obj, r.role) for r in self.rows])
        self.cut_warning.setText("\n".join(warnings))
        self.cut_warning.setVisible(bool(warnings))
        for i in range(self.criteria.rowCount()):
            item = self.criteria.verticalHeaderItem(i)
            if item is not None:
                item.setToolTip("%s: empty cells take the global value, shown in grey"
                                % item.text())
        for i in range(self.inputs.rowCount()):
            for j, tip in enumerate(INPUT_COLUMN_TIPS):
                widget = self.inputs.cellWidget(i, j)
                if widget is not None and not widget.toolTip():
                    widget.setToolTip(tip)

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
        accepted = selected_solids()
        for obj in accepted:
            if obj.Name not in present and obj != self.obj:
                self.rows += input_rows.rows_for_object(
                    self.obj, self.fem_materials, obj, obj in self.obj.WholeInputs,
                    [r.label for r in self.rows])
        self.refresh_inputs()
        refused = [refusal(o) for o in FreeCADGui.Selection.getSelection() if o not in accepted]
        if any(refused):
            self.report.setPlainText("Not added: %s. %s." % ("; ".join(r for r in refused if r),
                                                             ACCEPTED))

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
        self.show_report()
        return True

    def mesh(self):
        """Apply, then recompute the mesh object (progress dialog; errors shown by the object)."""
        try:
            self.apply()
        except jobmod.MeshInputError as e:
            self.report.setPlainText(str(e))
            return False
        except Exception as e:  # FreeCAD refused a property: say so, not only in the report view
            self.report.setPlainText("The settings could not be written: %s" % e)
            QtGui.QMessageBox.critical(self.form, "OracleMesh", self.report.toPlainText())
            return False
        self.doc.openTransaction("OracleMesh mesh")
        try:
            self.obj.touch()
            self.doc.recompute()
        except Exception as e:  # the mesh object reports its own failures; this is anything else
            self.obj.Status = "OracleMesh '%s' failed: %s" % (self.obj.Label, e)
            QtGui.QMessageBox.critical(self.form, "OracleMesh", self.obj.Status)
        finally:
            self.doc.commitTransaction()
        ok = bool(self.obj.isValid()) and self.obj.FemMesh.VolumeCount > 0
        if ok:  # the pairs this mesh found, with the settings just applied
            self.interfaces.load(self.interface_settings, interfaces.last_report(self.obj))
        # A selected mesh is drawn all in FreeCAD's highlight colour, over the material colours.
        FreeCADGui.Selection.removeSelection(self.obj)
        self.show_inputs(not ok and self.obj.FemMesh.VolumeCount == 0)
        self.show_report()
        return ok

    def show_inputs(self, visible):
        """The inputs while there is no mesh, else the mesh alone (a failed first mesh must
        not leave an empty view)."""
        for r in self.rows:
            view = getattr(r.obj, "ViewObject", None)
            if view is not None and view.Visibility != visible:
                view.Visibility = visible
        if self.obj.ViewObject is not None:
            self.obj.ViewObject.Visibility = True

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
    failed = not obj.isValid() or "failed" in obj.Status
    parts = ['<p style="color:%s"><b>%s</b></p>' % ("#b00000" if failed else "black",
                                                     esc(obj.Status or "Not meshed yet."))]
    report = interfaces.last_report(obj)
    warnings = list(report.get("warnings", []))
    warnings += input_warnings(obj)
    if warnings:
        parts.append("<p><b>Warnings</b></p><ul>%s</ul>"
                     % "".join("<li>%s</li>" % esc(w) for w in warnings))
    if not report:
        return "".join(parts)
    if failed:
        parts.append("<p>The previous mesh, kept:</p>")
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
    seconds = wall_seconds(report)
    if seconds is not None:
        parts.append("<p>Meshed in %.1f s</p>" % seconds)
    return "".join(parts)


def wall_seconds(report):
    """Seconds the user waited for the mesh; for reports of older versions, the sum of the
    core's top-level phases (engine phases named thesis_*, mesh3_* nest inside them)."""
    wall = report.get("freecad", {}).get("wall_seconds")
    if wall is not None:
        return float(wall)
    seconds = report.get("seconds", {})
    if not seconds:
        return None
    return sum(v for k, v in seconds.items() if not k.startswith(("mesh3_", "thesis_")))
