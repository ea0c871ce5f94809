"""Quality histogram of an OracleMesh mesh: the smallest dihedral angle of each tetrahedron
(of its corner tetrahedron for tet10), plotted with matplotlib (Debian's python3-matplotlib),
and a list of the worst elements; selecting them highlights their nodes in the 3D view.
"""
import numpy as np

from .export import mesh_arrays

# The six edges of a tetrahedron and, for each, the two faces meeting there, given by the
# vertex opposite each face (face k = the face without vertex k).
_EDGE_FACES = ((0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1))


def min_dihedral_angles(points, tets):
    """Smallest interior dihedral angle (degrees) of each tet's corner tetrahedron."""
    p = np.asarray(points, float)[np.asarray(tets)[:, :4]]  # (m, 4, 3)
    # Inward normal of the face opposite vertex k: the component of (p_k - face point) normal
    # to the face.
    normals = []
    for k in range(4):
        a, b, c = (p[:, i] for i in range(4) if i != k)
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n, axis=1)[:, None]
        side = np.einsum("ij,ij->i", n, p[:, k] - a)
        normals.append(n * np.sign(side)[:, None])
    angles = []
    for _, _, f, g in _EDGE_FACES:
        # Interior angle at the edge shared by faces f and g = pi - angle between inward normals.
        cos = np.clip(-np.einsum("ij,ij->i", normals[f], normals[g]), -1.0, 1.0)
        angles.append(np.degrees(np.arccos(cos)))
    return np.min(np.array(angles), axis=0)


def element_quality(obj):
    """(element ids, min dihedral per element, group name per element) of obj's FemMesh."""
    points, tets, element_ids, material, names = mesh_arrays(obj.FemMesh)
    groups = np.array([names[m - 1] if m > 0 else "" for m in material], dtype=object)
    return element_ids, min_dihedral_angles(points, tets), groups


# The bounds issue 15 judges meshes by (FEM solvers degrade below them, most below 5).
POOR_BOUNDS = (5, 10, 15)


def poor_counts(angles):
    """{bound: tetrahedra whose smallest dihedral angle is under it} for POOR_BOUNDS."""
    return {bound: int(np.count_nonzero(np.asarray(angles) < bound)) for bound in POOR_BOUNDS}


def poor_summary(counts, report):
    """One line for the dialog: the counts, and from the core's report how many of the tets
    under 15 degrees lie next to a small angle of the input itself (which no mesh can avoid)."""
    text = ", ".join("%d under %d deg" % (counts[b], b) for b in POOR_BOUNDS)
    improve = (report or {}).get("improve", {})
    near = improve.get("tets_under_15_deg_near_small_input_angle")
    if near is not None and counts[15]:
        text += "; %d of those under 15 deg lie next to a small input angle (report: improve)" % near
    return "Tetrahedra: " + text


# A bin of its own under 1 degree, then 5-degree bins: the few elements a solver may reject
# must not vanish next to the thousands of good ones, hence also the logarithmic count axis.
HISTOGRAM_BINS = [0.0, 1.0] + list(range(5, 91, 5))


def histogram_png(angles, path, title):
    """Write the histogram (HISTOGRAM_BINS, tetrahedra on a log scale) to a PNG."""
    import matplotlib
    matplotlib.use("Agg")  # drawn off-screen: no second Qt binding inside FreeCAD
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 3.2), dpi=100)
    ax.hist(angles, bins=HISTOGRAM_BINS, color="#216ee3", edgecolor="#10376f")
    ax.set_yscale("log")
    ax.set_xlabel("smallest dihedral angle per tetrahedron (degrees)")
    ax.set_ylabel("tetrahedra (log scale)")
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


class HistogramDialog:
    """Histogram image and the worst elements; selecting rows highlights their nodes."""

    WORST = 50

    def __init__(self, obj):
        import os
        import tempfile
        import FreeCADGui
        from PySide import QtCore, QtGui

        self.obj = obj
        self.zoomed = None  # (centre, size) of the last zoom to selected elements
        self.ids, self.angles, self.groups = element_quality(obj)
        self.png = os.path.join(tempfile.mkdtemp(prefix="oraclemesh-hist-"), "histogram.png")
        self.under_one_degree = int(np.count_nonzero(self.angles < 1.0))
        histogram_png(self.angles, self.png, "%s: %d tets, min %.2g deg, median %.1f deg, %d under 1 deg"
                      % (obj.Label, len(self.angles), self.angles.min(),
                         np.median(self.angles), self.under_one_degree))
        self.dialog = QtGui.QDialog(FreeCADGui.getMainWindow())
        self.dialog.setWindowTitle("OracleMesh quality: " + obj.Label)
        layout = QtGui.QVBoxLayout(self.dialog)
        picture = QtGui.QLabel()
        picture.setPixmap(QtGui.QPixmap(self.png))
        layout.addWidget(picture)
        self.poor = poor_counts(self.angles)
        self.poor_line = QtGui.QLabel(poor_summary(self.poor, self._report()))
        self.poor_line.setWordWrap(True)
        layout.addWidget(self.poor_line)
        layout.addWidget(QtGui.QLabel("Worst elements (select to highlight their nodes and zoom to them):"))
        self.worst = QtGui.QTableWidget(0, 3)
        self.worst.setHorizontalHeaderLabels(["Element", "Min dihedral (deg)", "Group"])
        self.worst.setSelectionBehavior(QtGui.QAbstractItemView.SelectRows)
        order = np.argsort(self.angles, kind="stable")[:self.WORST]
        self.worst.setRowCount(len(order))
        for row, k in enumerate(order):
            for col, text in enumerate((str(self.ids[k]), "%.2f" % self.angles[k],
                                        str(self.groups[k]))):
                item = QtGui.QTableWidgetItem(text)
                item.setFlags(QtCore.Qt.ItemIsSelectable | QtCore.Qt.ItemIsEnabled)
                self.worst.setItem(row, col, item)
        self.worst.itemSelectionChanged.connect(self.highlight)
        layout.addWidget(self.worst)
        close = QtGui.QPushButton("Close")
        close.clicked.connect(self.dialog.close)
        self.dialog.finished.connect(self.clear)
        layout.addWidget(close)

    def _report(self):
        import json
        try:
            return json.loads(self.obj.Report or "{}")
        except ValueError:
            return {}

    def selected_elements(self):
        return sorted({int(self.worst.item(i.row(), 0).text())
                       for i in self.worst.selectionModel().selectedRows()})

    def highlight(self):
        nodes = set()
        for e in self.selected_elements():
            nodes.update(self.obj.FemMesh.getElementNodes(e))
        self.obj.ViewObject.HighlightedNodes = sorted(nodes)
        if nodes:
            self.zoomed = zoom_to(self.obj, sorted(nodes))

    def clear(self, *_):
        if self.obj.ViewObject is not None:
            self.obj.ViewObject.HighlightedNodes = []


def zoom_to(obj, nodes, margin=4.0):
    """Point the active 3D view at the nodes, showing `margin` times their extent around them
    (a flat element is a dot at the model's scale), from the current viewing direction.
    Returns (the centre in global coordinates, the size shown)."""
    import FreeCAD
    import FreeCADGui
    from pivy import coin

    mesh = obj.FemMesh
    # FEM nodes are in the object's frame.
    xyz = np.array([tuple(obj.Placement.multVec(mesh.getNodeById(n))) for n in nodes], float)
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    centre = [float(c) for c in (lo + hi) / 2]
    model = mesh.BoundBox.DiagonalLength
    size = max(margin * float(np.linalg.norm(hi - lo)), 1e-3 * model)
    camera = FreeCADGui.ActiveDocument.ActiveView.getCameraNode()
    direction = camera.orientation.getValue().multVec(coin.SbVec3f(0, 0, -1)).getValue()
    if isinstance(camera, coin.SoOrthographicCamera):
        distance = model  # in front of the whole model, so nothing near is clipped
        camera.height.setValue(size)
    else:
        distance = size / (2.0 * float(np.tan(camera.heightAngle.getValue() / 2.0)))
    camera.position.setValue(coin.SbVec3f(*[c - d * distance for c, d in zip(centre, direction)]))
    camera.focalDistance.setValue(distance)
    FreeCAD.Console.PrintLog("OracleMesh: zoomed to %d node(s) around %s\n" % (len(nodes), centre))
    return centre, size


_open = []  # keep dialogs alive while shown


def show_histogram(obj):
    dialog = HistogramDialog(obj)
    _open[:] = [dialog]
    dialog.dialog.show()
    return dialog
