"""The parts a mesh object lists: one per solid of a compound (an imported assembly, a
Part::Compound), or an object as one input, in priority order.

A compound of several solids is split into one part per solid unless it is in the mesh
object's WholeInputs ("treat as one input"). Each part has a key, `<Name>` for a whole object
and `<Name>.Solid<k>` for solid k of a compound (FreeCAD's sub-element name, as FEM materials
reference it), and a label for the user, the row and the volume group:

- the label stored in PartLabels (what the panel or makeMesh found, or the user typed);
- else the linked object's label when a Part::Compound's links give one solid each;
- else the name the STEP file gives the solid (step_labels.py);
- else '<Label> Solid<k>'.
Labels are made unique across the mesh object as FreeCAD makes labels unique (COLONNE,
COLONNE001, ...), so each part gets a volume group of its own.

PartOrder, the keys in priority order, orders parts one by one; parts it does not list
follow in the order of Inputs (a compound's solids in compound order). Cuts stay whole.
"""
from .input_objects import MeshInputError, global_shape, is_mesh_feature, priority_entries


class InputPart:
    """One row of the mesh object's inputs: an object, or solid `solid` (1-based) of it."""

    def __init__(self, obj, solid, label):
        self.obj, self.solid, self.label = obj, solid, label

    @property
    def key(self):
        return part_key(self.obj, self.solid)

    def shape(self):
        shape = global_shape(self.obj)
        return shape if self.solid is None else shape.Solids[self.solid - 1]


def part_key(obj, solid=None):
    return obj.Name if solid is None else "%s.Solid%d" % (obj.Name, solid)


def solid_count(obj):
    """Number of solids of obj if it has several (a compound), else 0."""
    if is_mesh_feature(obj):
        return 0
    try:
        count = len(global_shape(obj).Solids)
    except MeshInputError:
        return 0  # reported when the job is built
    return count if count > 1 else 0


def split_solids(mesh_obj, obj):
    """Number of parts obj splits into in mesh_obj (0: it stays whole)."""
    if obj in list(getattr(mesh_obj, "WholeInputs", []) or []):
        return 0
    return solid_count(obj)


def found_labels(obj, count, search=True):
    """Labels of obj's solids from its links or (search) its STEP file (None where unknown)."""
    links = list(getattr(obj, "Links", []) or [])
    if obj.isDerivedFrom("Part::Compound") and len(links) == count and \
            all(len(getattr(getattr(o, "Shape", None), "Solids", [])) == 1 for o in links):
        return [o.Label for o in links]
    if not search:
        return [None] * count
    from .step_labels import step_solid_names
    return step_solid_names(obj, global_shape(obj).Solids)


def solid_labels(mesh_obj, obj, count, search=True):
    """Label of each solid of obj (not yet unique)."""
    stored = dict(getattr(mesh_obj, "PartLabels", {}) or {})
    keys = [part_key(obj, k) for k in range(1, count + 1)]
    found = [None] * count
    if not all(stored.get(k) for k in keys):
        found = found_labels(obj, count, search)
    return [stored.get(key) or found[i] or "%s Solid%d" % (obj.Label, i + 1)
            for i, key in enumerate(keys)]


def unique_labels(labels):
    """FreeCAD-style unique labels: a repeated 'X' becomes 'X001', 'X002', ..."""
    used, out = set(), []
    for label in labels:
        name, n = label, 0
        while name in used:
            n += 1
            name = "%s%03d" % (label, n)
        used.add(name)
        out.append(name)
    return out


def input_parts(mesh_obj, search=True):
    """[(InputPart, role)] highest priority first (see the module docstring). search: look
    for the STEP file of compounds whose labels are not stored (not while recomputing)."""
    rows = []
    for obj, role in priority_entries(mesh_obj.Inputs, mesh_obj.Cuts):
        count = split_solids(mesh_obj, obj) if role == "material" else 0
        if count:
            labels = solid_labels(mesh_obj, obj, count, search)
            rows += [(InputPart(obj, k, labels[k - 1]), role) for k in range(1, count + 1)]
        else:
            rows.append((InputPart(obj, None, obj.Label), role))
    for (part, _), label in zip(rows, unique_labels([p.label for p, _ in rows])):
        part.label = label
    order = list(getattr(mesh_obj, "PartOrder", []) or [])
    if order:
        position = {key: i for i, key in enumerate(order)}
        rank = {id(p): (position.get(p.key, len(order)), i) for i, (p, _) in enumerate(rows)}
        rows.sort(key=lambda row: rank[id(row[0])])
    return rows


def store_labels(mesh_obj, parts):
    """Keep the labels of split solids in PartLabels, so a saved document keeps them even
    where the STEP file is gone."""
    labels = dict(mesh_obj.PartLabels)
    for part in parts:
        if part.solid is not None:
            labels.setdefault(part.key, part.label)
    if labels != dict(mesh_obj.PartLabels):
        mesh_obj.PartLabels = labels


def store_cad_uncertainty(mesh_obj):
    """Keep in CadUncertainty what the STEP files of the material inputs declare, found while
    the files are at hand (setting the inputs), so a recompute needs no search."""
    from .step_labels import declared_uncertainty
    objs = [obj for obj, role in priority_entries(mesh_obj.Inputs, mesh_obj.Cuts) if role == "material"]
    stored = getattr(mesh_obj, "CadUncertainty", None)
    if stored is None:  # a document older than the property, not yet restored by the proxy
        return
    value = declared_uncertainty(objs)
    if float(getattr(stored, "Value", stored)) != value:
        mesh_obj.CadUncertainty = value
