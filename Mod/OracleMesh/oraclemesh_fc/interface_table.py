"""The task panel's "Interfaces" box: how each pair of touching parts is joined (issue 19).

One row per interface the last mesh found (its report's `interfaces`: the two parts, their
contact area), each with a combo box bonded / tied / contact / separate, and a combo box for
the default of every other pair. The choice goes into the mesh object's `Interfaces`
property when the panel applies (interfaces.with_kinds keeps a pair's friction and master),
so it acts on the next mesh; before the first mesh the table is empty and says so.
"""
from PySide import QtCore, QtGui

from . import interfaces
from .panel_widgets import fit_columns, narrow_form, show_rows

COLUMN_TIPS = ("The two parts that touch, and their contact area in the last mesh",
               "How this pair is joined on the next mesh")


def kind_tip(kind):
    return "%s: %s" % (kind, interfaces.KIND_TIPS[kind])


def kind_combo(kind, tip):
    combo = QtGui.QComboBox()
    for k, name in enumerate(interfaces.KINDS):
        combo.addItem(name)
        combo.setItemData(k, kind_tip(name), QtCore.Qt.ToolTipRole)
    combo.setCurrentIndex(interfaces.KINDS.index(kind))
    combo.setToolTip(tip)
    return combo


class InterfaceBox:
    """The box's widgets and the pairs they show."""

    def __init__(self, visible_rows):
        self.box = QtGui.QGroupBox("Interfaces")
        self.box.setToolTip("How touching parts are joined. Ties and contacts reach FreeCAD's "
                            "CalculiX input by themselves; applied on the next mesh")
        v = QtGui.QVBoxLayout(self.box)
        form = narrow_form()
        self.default = kind_combo("bonded", "Every pair not set in the table: "
                                  + "; ".join(kind_tip(k) for k in interfaces.KINDS))
        form.addRow("Default", self.default)
        v.addLayout(form)
        self.table = QtGui.QTableWidget(0, 2)
        self.table.setHorizontalHeaderLabels(["Pair", "Kind"])
        for i, tip in enumerate(COLUMN_TIPS):
            self.table.horizontalHeaderItem(i).setToolTip(tip)
        self.table.setToolTip("The pairs of parts the last mesh found touching")
        self.table.verticalHeader().setVisible(False)
        self.table.horizontalHeader().setStretchLastSection(True)
        fit_columns(self.table)
        show_rows(self.table, visible_rows)
        v.addWidget(self.table)
        self.note = QtGui.QLabel("Mesh once to list the pairs of parts that touch.")
        self.note.setWordWrap(True)
        self.note.setToolTip("The pairs come from the last mesh's report")
        v.addWidget(self.note)
        self.pairs = []  # [(part a, part b)] of the rows

    def load(self, settings, report):
        """Show the settings for the pairs of a report (dict; {} before the first mesh)."""
        self.default.setCurrentIndex(interfaces.KINDS.index(interfaces.default_kind(settings)))
        found = interfaces.found_pairs(report)
        self.pairs = [(a, b) for a, b, _, _, _ in found]
        self.table.setRowCount(len(found))
        for i, (a, b, area, triangles, beyond) in enumerate(found):
            item = QtGui.QTableWidgetItem("%s - %s" % (a, b))
            item.setFlags(QtCore.Qt.ItemIsSelectable | QtCore.Qt.ItemIsEnabled)
            item.setToolTip(interfaces.pair_tip(a, b, area, triangles, beyond))
            self.table.setItem(i, 0, item)
            self.table.setCellWidget(i, 1, kind_combo(interfaces.kind_between(settings, a, b),
                                                      COLUMN_TIPS[1]))
        self.note.setVisible(not found)

    def chosen(self):
        """(default kind, {(part a, part b): kind}) as the combo boxes show them."""
        kinds = {pair: self.table.cellWidget(i, 1).currentText()
                 for i, pair in enumerate(self.pairs)}
        return self.default.currentText(), kinds

    def settings(self, old):
        """The settings to store: `old` with the panel's default and kinds."""
        default, kinds = self.chosen()
        return interfaces.with_kinds(old, default, kinds)
