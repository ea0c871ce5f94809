"""Qt pieces of the task panel that make it fit FreeCAD's narrow combo view (264 px by
default) and show what "automatic" means: tables of a given number of rows, form rows with
the field under its label, push buttons as narrow as their text, and a delegate that paints
an empty criteria cell as the value the mesher will use."""
from PySide import QtCore, QtGui


def show_rows(table, rows):
    """Make the table tall enough for `rows` rows between its header and its sideways scroll
    bar (narrow panels scroll tables sideways)."""
    height = (table.horizontalHeader().sizeHint().height()
              + rows * table.verticalHeader().defaultSectionSize() + 2 * table.frameWidth()
              + table.horizontalScrollBar().sizeHint().height())
    table.setMinimumHeight(height)


def fit_columns(table, header_width=90):
    """Columns as wide as their header and cells (the table scrolls sideways when they do not
    fit), the row labels at most header_width wide (elided; their tooltip has them whole)."""
    table.horizontalHeader().setSectionResizeMode(QtGui.QHeaderView.ResizeToContents)
    table.verticalHeader().setMaximumWidth(header_width)
    table.setTextElideMode(QtCore.Qt.ElideRight)


def narrow_form(parent=None):
    """A form layout with every field under its label: fields get the panel's full width."""
    grid = QtGui.QFormLayout(parent) if parent is not None else QtGui.QFormLayout()
    grid.setRowWrapPolicy(QtGui.QFormLayout.WrapAllRows)
    return grid


def fit_text(button):
    """Let a push button shrink to what its text needs (the style's minimum of 80 px would
    put three buttons of a row beyond the combo view's width)."""
    style = button.style()
    margin = style.pixelMetric(QtGui.QStyle.PM_ButtonMargin, None, button)
    frame = style.pixelMetric(QtGui.QStyle.PM_DefaultFrameWidth, None, button)
    button.setMinimumWidth(button.fontMetrics().width(button.text()) + 2 * (margin + frame))
    button.setSizePolicy(QtGui.QSizePolicy.Preferred, button.sizePolicy().verticalPolicy())


class AutomaticDelegate(QtGui.QStyledItemDelegate):
    """Paints an empty criteria cell as the value the core will use, in grey italics; the cell
    stays empty, so it still means "automatic"."""

    def __init__(self, automatic_text, parent):
        super().__init__(parent)
        self.automatic_text = automatic_text

    def sizeHint(self, option, index):
        size = super().sizeHint(option, index)
        text = "" if index.data() else self.automatic_text(index.row(), index.column())
        if text:
            font = QtGui.QFont(option.font)
            font.setItalic(True)
            size.setWidth(max(size.width(), QtGui.QFontMetrics(font).width(text) + 8))
        return size

    def paint(self, painter, option, index):
        super().paint(painter, option, index)
        if index.data():
            return
        text = self.automatic_text(index.row(), index.column())
        if not text:
            return
        painter.save()
        font = QtGui.QFont(option.font)
        font.setItalic(True)
        painter.setFont(font)
        painter.setPen(option.palette.color(QtGui.QPalette.Disabled, QtGui.QPalette.Text))
        painter.drawText(option.rect.adjusted(4, 0, -4, 0),
                         QtCore.Qt.AlignVCenter | QtCore.Qt.AlignLeft, text)
        painter.restore()
