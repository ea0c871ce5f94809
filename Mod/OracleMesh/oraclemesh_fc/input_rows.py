"""The task panel's input rows: what it shows and edits of the mesh object's parts (parts.py),
and how the rows are written back (Inputs, Cuts, WholeInputs, PartOrder, PartLabels,
InputMaterialNames, InputSizes and the FEM materials' References).

A row is one part: a whole object, or one solid of a compound. Its material is a FEM material
of the analysis (the row's object, or its solid 'SolidK', is then in that material's
References, which names the volume group and is what FreeCAD's CalculiX writer reads) or a
free name (group '<name>_Volumes'). A compound can be "treated as one input": its solid rows
are joined into one row (and split again).
"""
from . import job as jobmod
from .parts import input_parts, part_key, solid_count, solid_labels, store_cad_uncertainty, unique_labels


class Row:
    """One part as the panel edits it."""

    def __init__(self, obj, role, material, sizes, solid=None, label=None):
        self.obj, self.role, self.material, self.sizes = obj, role, material, sizes
        self.solid = solid
        self.label = label or obj.Label

    @property
    def key(self):
        return part_key(self.obj, self.solid)


def material_of(mesh_obj, fem_materials, obj, solid=None):
    """Label of the FEM material referencing the part, else its free name, else ''."""
    for m in fem_materials:
        if jobmod.references(m, obj, solid):
            return m.Label
    names = dict(mesh_obj.InputMaterialNames)
    return names.get(part_key(obj, solid), names.get(obj.Name, "") if solid is not None else "")


def parsed_sizes(mesh_obj, part):
    sizes = dict(mesh_obj.InputSizes)
    text = sizes.get(part.key, sizes.get(part.label, ""))
    if not text and part.solid is not None:
        text = sizes.get(part.obj.Name, sizes.get(part.obj.Label, ""))
    try:
        return jobmod.parse_size_entry(text, part.label) if text else {}
    except jobmod.MeshInputError:
        return {}  # shown empty; the object keeps reporting the bad entry on recompute


def rows_from_object(mesh_obj, fem_materials):
    rows = []
    for part, role in input_parts(mesh_obj):
        rows.append(Row(part.obj, role,
                        material_of(mesh_obj, fem_materials, part.obj, part.solid)
                        if role == "material" else "",
                        parsed_sizes(mesh_obj, part), part.solid, part.label))
    return rows


def rows_for_object(mesh_obj, fem_materials, obj, whole, taken=()):
    """New rows for obj: one per solid of a compound unless whole; labels not in taken."""
    count = 0 if whole else solid_count(obj)
    if not count:
        return [Row(obj, "material", material_of(mesh_obj, fem_materials, obj), {})]
    labels = unique_labels(list(taken) + solid_labels(mesh_obj, obj, count))[len(taken):]
    return [Row(obj, "material", material_of(mesh_obj, fem_materials, obj, k), {}, k,
                labels[k - 1]) for k in range(1, count + 1)]


def join_rows(rows, obj):
    """Rows with obj's solid rows replaced by one whole row where the first of them was."""
    at = next(i for i, r in enumerate(rows) if r.obj == obj)
    first = rows[at]
    kept = [r for r in rows if r.obj != obj]
    kept.insert(at, Row(obj, first.role, first.material, dict(first.sizes)))
    return kept


def split_rows(mesh_obj, fem_materials, rows, obj):
    """Rows with obj's whole row replaced by one row per solid."""
    at = next(i for i, r in enumerate(rows) if r.obj == obj)
    kept = [r for r in rows if r.obj != obj]
    new = rows_for_object(mesh_obj, fem_materials, obj, False, [r.label for r in kept])
    return kept[:at] + new + kept[at:]


def new_references(material, rows, chosen_rows):
    """material's References with the rows' objects referenced as chosen_rows say: a whole
    row by all its solids, a solid row by 'SolidK'; references to other objects are kept."""
    objs = []
    for r in rows:
        if r.obj not in objs:
            objs.append(r.obj)
    refs = [ref for ref in material.References if ref[0] not in objs]
    for obj in objs:
        subs = []
        for r in chosen_rows:
            if r.obj != obj:
                continue
            if r.solid is None:
                subs += ["Solid%d" % i for i in range(1, len(obj.Shape.Solids) + 1)] or ["Solid1"]
            else:
                subs.append("Solid%d" % r.solid)
        if subs:
            refs.append((obj, tuple(subs)))
    return refs


def write_rows(mesh_obj, rows, fem_materials):
    """Write the rows into the mesh object and the FEM materials' References."""
    o = mesh_obj
    inputs = []
    for r in rows:
        if r.obj not in inputs:
            inputs.append(r.obj)
    o.Inputs = inputs
    o.Cuts = [r.obj for r in rows if r.role == "cut"]
    split = {r.obj.Name for r in rows if r.solid is not None}
    o.WholeInputs = [obj for obj in inputs if obj.Name not in split
                     and len(getattr(getattr(obj, "Shape", None), "Solids", [])) > 1]
    o.PartOrder = [r.key for r in rows] if split else []
    labels = {k: v for k, v in dict(o.PartLabels).items() if k.split(".")[0] not in split}
    labels.update({r.key: r.label for r in rows if r.solid is not None})
    o.PartLabels = labels
    store_cad_uncertainty(o)

    by_label = {m.Label: m for m in fem_materials}
    for m in fem_materials:
        chosen = [r for r in rows if r.role == "material" and by_label.get(r.material) is m]
        refs = new_references(m, rows, chosen)
        if refs != list(m.References):
            m.References = refs
    keys = {r.key for r in rows} | {r.obj.Name for r in rows}
    names = {k: v for k, v in dict(o.InputMaterialNames).items() if k not in keys}
    for r in rows:
        if r.role == "material" and r.material and r.material not in by_label:
            names[r.key] = r.material
    o.InputMaterialNames = names

    listed = keys | {r.obj.Label for r in rows} | {r.label for r in rows}
    sizes = {k: t for k, t in dict(o.InputSizes).items() if k not in listed}
    for r in rows:
        if r.role == "material" and r.sizes:
            sizes[r.key] = " ".join("%s=%r" % (k, float(v)) for k, v in sorted(r.sizes.items()))
    o.InputSizes = sizes

