"""OracleMesh defaults (Edit > Preferences > OracleMesh): size preset, engine, element order,
sharp-edge angle. New mesh objects made by the command start from them (mesh_options, written
into the command's makeMesh call); makeMesh (the macro API) does not read them, so a macro
gives the same mesh on every machine.
"""
import FreeCAD

PARAM_PATH = "User parameter:BaseApp/Preferences/Mod/OracleMesh"

# Size presets: cell size = model bounding-box diagonal / divisor ("automatic" leaves every
# size at 0, so the core derives them: diagonal / 15).
PRESETS = (("automatic", None), ("coarse", 8.0), ("moderate", 15.0), ("fine", 30.0))
# The first engine is the default (the same as a new mesh object's, mesh_object.ENGINE_NAMES).
ENGINES = (("thesis", "Rule Set T (thesis)", True),
           ("cgal", "CGAL Mesh_3", True))


def params():
    return FreeCAD.ParamGet(PARAM_PATH)


def defaults():
    p = params()
    return {
        "Preset": p.GetString("Preset", "automatic"),
        "Engine": p.GetString("Engine", ENGINES[0][0]),
        "ElementOrder": p.GetInt("ElementOrder", 2),
        "SharpAngle": p.GetFloat("SharpAngle", 30.0),
    }


def save(values):
    p = params()
    p.SetString("Preset", values["Preset"])
    p.SetString("Engine", values["Engine"])
    p.SetInt("ElementOrder", int(values["ElementOrder"]))
    p.SetFloat("SharpAngle", float(values["SharpAngle"]))


def preset_cell_size(preset, inputs):
    """Cell size of a preset for the given input objects (0 = automatic)."""
    divisor = dict(PRESETS).get(preset)
    if not divisor:
        return 0.0
    box = None
    for obj in inputs:
        shape = getattr(obj, "Shape", None)
        if shape is None or shape.isNull():
            continue
        if box is None:
            box = FreeCAD.BoundBox(shape.BoundBox)
        else:
            box.add(shape.BoundBox)
    if box is None or box.DiagonalLength <= 0:
        return 0.0
    return round(box.DiagonalLength / divisor, 3)


def mesh_options(inputs):
    """makeMesh options of a new mesh object of the given inputs, from the preferences.

    The command writes them out as values in its recorded makeMesh call, so the macro makes
    the same object whatever the preferences of the machine that replays it."""
    d = defaults()
    options = {}
    if d["Engine"] in [e for e, _, works in ENGINES if works]:
        options["engine"] = d["Engine"]
    options["element_order"] = min(max(int(d["ElementOrder"]), 1), 2)
    options["sharp_angle"] = float(d["SharpAngle"])
    options["cell_size"] = preset_cell_size(d["Preset"], inputs)
    return options


class PreferencePage:
    """Edit > Preferences > OracleMesh (FreeCADGui.addPreferencePage takes this class)."""

    def __init__(self, parent=None):
        from PySide import QtGui
        self.form = QtGui.QWidget(parent)
        self.form.setWindowTitle("OracleMesh")
        layout = QtGui.QFormLayout(self.form)
        self.preset = QtGui.QComboBox()
        for name, divisor in PRESETS:
            self.preset.addItem(name if divisor is None else
                                "%s (cell size = model diagonal / %g)" % (name, divisor), name)
        self.preset.setToolTip("Cell size of new meshes; automatic = model diagonal / 15, "
                               "chosen by the mesher")
        layout.addRow("Default sizes", self.preset)
        self.engine = QtGui.QComboBox()
        add_engines(self.engine)
        self.engine.setToolTip("Meshing engine of new meshes")
        layout.addRow("Engine", self.engine)
        self.order = QtGui.QComboBox()
        self.order.addItem("1 - linear (C3D4)", 1)
        self.order.addItem("2 - quadratic (C3D10)", 2)
        self.order.setToolTip("Element order of new meshes")
        layout.addRow("Element order", self.order)
        self.sharp = QtGui.QDoubleSpinBox()
        self.sharp.setRange(0.0, 180.0)
        self.sharp.setSuffix(" deg")
        self.sharp.setToolTip("B-rep edges whose faces meet at more than this angle are kept as "
                              "mesh edges in new meshes")
        layout.addRow("Sharp-edge angle (0 = off)", self.sharp)

    def loadSettings(self):
        d = defaults()
        self.preset.setCurrentIndex(max(self.preset.findData(d["Preset"]), 0))
        self.engine.setCurrentIndex(max(self.engine.findData(d["Engine"]), 0))
        self.order.setCurrentIndex(max(self.order.findData(d["ElementOrder"]), 0))
        self.sharp.setValue(d["SharpAngle"])

    def saveSettings(self):
        save({"Preset": self.preset.currentData(), "Engine": self.engine.currentData(),
              "ElementOrder": self.order.currentData(), "SharpAngle": self.sharp.value()})


def add_engines(combo):
    """Fill an engine combo box; engines not in this version are listed but disabled."""
    for name, text, works in ENGINES:
        combo.addItem(text, name)
        if not works:
            item = combo.model().item(combo.count() - 1)
            item.setEnabled(False)
