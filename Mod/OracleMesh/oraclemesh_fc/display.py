"""How a meshed OracleMesh object looks: faces coloured by material (volume group), flat, one
colour per face with no blending across a material interface, and the sharp and junction
edges of the mesh drawn as dark lines on top (GUI only).

FreeCAD's FEM view draws the mesh's outer faces as one Coin face set and keeps picking,
display modes and highlighting on it. Its own colourings do not fit: NodeColor blends the
colours of the nodes across each triangle (an interface shows a gradient), and ElementColor
gives one colour per element face while quadratic faces are drawn as four triangles each, so
its colours land on the wrong triangles. So the colours are written straight into that face
set's material, one per drawn triangle: each triangle's nodes (found by their coordinates)
belong to exactly one element, an outer face lies on one element only. The edges are a Coin
line set under the view provider's root, so they show in every display mode.
"""
import colorsys

# 18 hues 20 degrees apart, in an order that puts far hues next to each other (steps of 140
# degrees), bright and darker in turn: neighbours in the priority list stand apart, and a
# screenshot test can find each material by its hue. Group i takes PALETTE[i % len(PALETTE)].
PALETTE_HUE_STEPS = 18
PALETTE = tuple(colorsys.hsv_to_rgb(((7 * i) % PALETTE_HUE_STEPS) / PALETTE_HUE_STEPS, 0.85,
                                    0.95 if i % 2 == 0 else 0.72)
                for i in range(PALETTE_HUE_STEPS))
EDGE_COLOUR = (0.05, 0.05, 0.05)


def volume_groups(femmesh):
    """[(group name, [element ids])] of the volume groups, in the mesh's group order."""
    return [(femmesh.getGroupName(g), list(femmesh.getGroupElements(g)))
            for g in femmesh.Groups if femmesh.getGroupElementType(g) == "Volume"]


def material_colours(femmesh):
    """{group name: (r, g, b)} as shown."""
    return {name: PALETTE[i % len(PALETTE)] for i, (name, _) in enumerate(volume_groups(femmesh))}


def element_groups(femmesh):
    """{element id: index of its volume group} (the first group wins, as in priority)."""
    of = {}
    for i, (_, elements) in enumerate(volume_groups(femmesh)):
        for e in elements:
            of.setdefault(e, i)
    return of


def triangle_colours(femmesh, points, coord_index):
    """Colour of each polygon of a face set (coord_index: indices with -1 ending each
    polygon; points: the face set's coordinates) from the element its nodes belong to."""
    import numpy as np

    nodes = femmesh.Nodes
    ids = sorted(nodes)
    # Coin stores float coordinates: match them as floats.
    key_of = {np.float32(nodes[n]).tobytes(): n for n in ids} if ids else {}
    node_at = [key_of.get(np.float32(p).tobytes()) for p in points]
    group_of = element_groups(femmesh)
    elements_of = {}
    for e in group_of:
        for n in femmesh.getElementNodes(e):
            elements_of.setdefault(n, set()).add(e)
    colours, polygon = [], []
    for index in coord_index:
        if index >= 0:
            polygon.append(index)
            continue
        common = None
        for i in polygon:
            found = elements_of.get(node_at[i], set())
            common = found if common is None else common & found
        element = min(common) if common else None
        colours.append(PALETTE[group_of[element] % len(PALETTE)] if element is not None
                       else EDGE_COLOUR)
        polygon = []
    return colours


def face_set_nodes(root):
    """(coordinates, face set, material, material binding) of the FEM view's faces."""
    from pivy import coin
    search = coin.SoSearchAction()
    search.setType(coin.SoIndexedFaceSet.getClassTypeId())
    search.setInterest(coin.SoSearchAction.FIRST)
    search.apply(root)
    path = search.getPath()
    if path is None:
        return None
    group = path.getNodeFromTail(1)
    found = {}
    for i in range(group.getNumChildren()):
        child = group.getChild(i)
        for name, kind in (("coords", coin.SoCoordinate3), ("material", coin.SoMaterial),
                           ("binding", coin.SoMaterialBinding)):
            if isinstance(child, kind) and name not in found:
                found[name] = child
    if len(found) < 3:
        return None
    return found["coords"], path.getTail(), found["material"], found["binding"]


def colour_faces(vobj, femmesh):
    """Colour the FEM view's faces flat by material; returns the number of faces coloured."""
    from pivy import coin
    nodes = face_set_nodes(vobj.RootNode)
    if nodes is None:
        return 0
    coords, faces, material, binding = nodes
    points = [tuple(p.getValue()) for p in coords.point.getValues()] if coords.point.getNum() else []
    index = list(faces.coordIndex.getValues()) if faces.coordIndex.getNum() else []
    colours = triangle_colours(femmesh, points, index)
    binding.value = coin.SoMaterialBinding.PER_FACE
    material.diffuseColor.setNum(len(colours))
    material.diffuseColor.setValues(0, len(colours), colours)
    return len(colours)


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

    Returns (faces coloured, feature edges drawn) (FreeCAD cannot read the colours back)."""
    vobj = obj.ViewObject
    if vobj is None:
        return 0, 0
    coloured = colour_faces(vobj, obj.FemMesh)
    points, drawn = feature_edge_points(obj)
    if edge_node is not None:
        edge_node.update(points)
    return coloured, drawn
