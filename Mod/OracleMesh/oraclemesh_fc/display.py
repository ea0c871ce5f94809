"""How a meshed OracleMesh object looks: faces coloured by material (volume group), the
sharp and junction edges of the mesh drawn as dark lines on top (GUI only).

Colours go through the FEM mesh view provider's NodeColor (a colour per node), so FreeCAD's
own display modes, picking and highlighting keep working. (ElementColor would be the natural
choice, but FreeCAD 0.20 scrambles it on quadratic elements, whose faces it draws as four
triangles each; node colours are right for both orders. Nodes on a material interface take
the colour of the input with the higher priority, listed first.) The edges are a Coin line set under the view provider's root, so
they show in every display mode.
"""

# Saturated colours with well separated hues, so materials stand apart under lighting and a
# screenshot test can find each one by hue. Group i takes PALETTE[i % len(PALETTE)].
PALETTE = (
    (0.91, 0.39, 0.09),  # orange
    (0.13, 0.43, 0.89),  # blue
    (0.18, 0.70, 0.24),  # green
    (0.80, 0.16, 0.62),  # magenta
    (0.93, 0.80, 0.10),  # yellow
    (0.10, 0.75, 0.80),  # cyan
)
EDGE_COLOUR = (0.05, 0.05, 0.05)


def volume_groups(femmesh):
    """[(group name, [element ids])] of the volume groups, in the mesh's group order."""
    return [(femmesh.getGroupName(g), list(femmesh.getGroupElements(g)))
            for g in femmesh.Groups if femmesh.getGroupElementType(g) == "Volume"]


def material_colours(femmesh):
    """{group name: (r, g, b)} as shown."""
    return {name: PALETTE[i % len(PALETTE)] for i, (name, _) in enumerate(volume_groups(femmesh))}


def node_colours(femmesh):
    """{node id: (r, g, b)} for every node of an element in a volume group."""
    colours = {}
    groups = volume_groups(femmesh)
    for i in reversed(range(len(groups))):  # the first group is painted last and wins
        colour = PALETTE[i % len(PALETTE)]
        for e in groups[i][1]:
            for n in femmesh.getElementNodes(e):
                colours[n] = colour
    return colours


def feature_edge_points(obj):
    """(flat list of line segment end points [(x, y, z), ...], feature edges drawn) of the
    object's FeatureEdges. A quadratic edge is drawn as two segments through its mid node:
    FreeCAD draws quadratic faces through their mid nodes (on the CAD surface), under which
    the straight chord of a convex curved edge would be hidden."""
    ids = list(getattr(obj, "FeatureEdges", []) or [])
    mids = list(getattr(obj, "FeatureEdgeMidNodes", []) or [])
    if len(mids) != len(ids) // 2:
        mids = [None] * (len(ids) // 2)  # a linear mesh, or one from an older version
    nodes = obj.FemMesh.Nodes
    points, drawn = [], 0
    for a, b, m in zip(ids[0::2], ids[1::2], mids):
        if a not in nodes or b not in nodes:  # stale edges of an older mesh are skipped
            continue
        path = [a, m, b] if m in nodes else [a, b]
        for p, q in zip(path, path[1:]):
            points.append(tuple(nodes[p]))
            points.append(tuple(nodes[q]))
        drawn += 1
    return points, drawn


class FeatureEdgeNode:
    """The Coin subgraph drawing the feature edges (unpickable, so clicks reach the mesh)."""

    def __init__(self):
        from pivy import coin
        self.root = coin.SoSeparator()
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        # Unlit, one colour: the per-face colour binding of the mesh must not leak in.
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.OVERALL
        colour = coin.SoBaseColor()
        colour.rgb.setValue(*EDGE_COLOUR)
        style = coin.SoDrawStyle()
        style.lineWidth = 2.5
        self.coords = coin.SoCoordinate3()
        self.lines = coin.SoLineSet()
        for node in (pick, light, binding, colour, style, self.coords, self.lines):
            self.root.addChild(node)
        # Pushes the mesh faces (drawn after it under the same root) slightly back, so the
        # edges lying on them are not half hidden (z-fighting).
        self.face_offset = coin.SoPolygonOffset()
        self.face_offset.factor = 1.0
        self.face_offset.units = 1.0

    def attach_to(self, root):
        root.insertChild(self.face_offset, 0)
        root.addChild(self.root)

    def update(self, points):
        self.coords.point.setValues(0, len(points), points)
        self.coords.point.setNum(len(points))
        self.lines.numVertices.setValues(0, len(points) // 2, [2] * (len(points) // 2))
        self.lines.numVertices.setNum(len(points) // 2)


def show(obj, edge_node=None):
    """Colour the mesh of obj by material and refresh its feature edges.

    Returns (coloured nodes, feature edges drawn) (FreeCAD cannot read NodeColor back)."""
    vobj = obj.ViewObject
    if vobj is None:
        return 0, 0
    colours = node_colours(obj.FemMesh)
    vobj.NodeColor = colours
    points, drawn = feature_edge_points(obj)
    if edge_node is not None:
        edge_node.update(points)
    return len(colours), drawn
