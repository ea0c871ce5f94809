"""Names of the solids of an imported STEP assembly, as the STEP file gives them.

FreeCAD 0.20's STEP import (ImportOCAF2) in its default "merge" mode (Preferences > Import
> STEP > "Enable STEP Compound merge") reads the file's XDE tree, then replaces it by one
Part::Feature holding a compound of every solid, labelled with the file's base name: the
product names are dropped. Read without merging, the same importer keeps them as the labels
of the tree it builds (App::LinkGroup per assembly and product, Part::Feature per shape, an
App::Link array for repeated parts). So the names are got back by reading the file once more
without merging, into a hidden scratch document, and matching its solids to the compound's
by volume and centre of mass (the importer places both alike).

The file is found where FreeCAD's import left traces of it: `<Label>.step` / `.stp` in the
folders of the recent files, of the last file dialog (File > Import leaves both), and of the
document; makeMesh(step_file=...) names it outright.
"""
import os
import re

import FreeCAD

STEP_EXTENSIONS = (".step", ".stp", ".STEP", ".STP")
# Labels OpenCASCADE and FreeCAD give unnamed shapes: the product above them names the part.
GENERIC_LABEL = re.compile(r"^(solid|shell|compound|compsolid|feature)\d*$", re.IGNORECASE)

_cache = {}  # (path, mtime) -> [(label, volume, centre)]
# Files to look in first (makeMesh's step_file, while it runs).
extra_files = []


def candidate_files(obj):
    """Paths where the STEP file obj was imported from may be, most likely first."""
    folders = []
    recent = FreeCAD.ParamGet("User parameter:BaseApp/Preferences/RecentFiles")
    for i in range(int(recent.GetInt("RecentFiles", 4)) or 4):
        path = recent.GetString("MRU%d" % i, "")
        if path:
            folders.append(os.path.dirname(path))
    folders.append(FreeCAD.ParamGet("User parameter:BaseApp/Preferences/General")
                   .GetString("FileOpenSavePath", ""))
    if obj.Document.FileName:
        folders.append(os.path.dirname(obj.Document.FileName))
    seen, paths = set(), [p for p in extra_files if os.path.isfile(p)]
    for folder in folders:
        for ext in STEP_EXTENSIONS:
            path = os.path.join(folder, obj.Label + ext) if folder else ""
            if path and path not in seen and os.path.isfile(path):
                seen.add(path)
                paths.append(path)
    return paths


def part_name(path_objects):
    """Name of a leaf of the import tree: its label, or that of the nearest product above
    it when the shape itself has a generic name ('SOLID001')."""
    for obj in reversed(path_objects):
        label = obj.Label
        linked = obj.getLinkedObject(True)
        if GENERIC_LABEL.match(label) and linked is not None and linked is not obj:
            label = linked.Label
        if not GENERIC_LABEL.match(label):
            return label
    return path_objects[-1].Label


def read_named_solids(path):
    """[(name, volume, centre of mass)] of every solid in the STEP file, in the file's tree
    order. Read with FreeCAD's own importer, without merging, into a hidden document."""
    key = (path, os.path.getmtime(path))
    if key in _cache:
        return _cache[key]
    import Import

    active = FreeCAD.ActiveDocument
    scratch = FreeCAD.newDocument("OracleMeshStepNames", hidden=True, temp=True)
    named = []
    try:
        Import.insert(path, scratch.Name, merge=False)
        for root in [o for o in scratch.Objects if not o.InList]:
            _collect(root, root, "", [root], named)
    finally:
        FreeCAD.closeDocument(scratch.Name)
        if active is not None:
            FreeCAD.setActiveDocument(active.Name)
    _cache[key] = named
    return named


def _collect(root, obj, sub, path_objects, named):
    subs = obj.getSubObjects()
    if not subs:
        shape = root.getSubObject(sub, retType=0) if sub else root.Shape
        for solid in shape.Solids:
            named.append((part_name(path_objects), solid.Volume, solid.CenterOfMass))
        return
    for s in subs:
        child = obj.getSubObject(s, retType=1)
        if child is not None:
            _collect(root, child, sub + s, path_objects + [child], named)


def match_names(solids, named):
    """Name of each solid (None where no solid of the file matches it): the same volume
    (relative 1e-6) and centre of mass (1e-6 of the solid's size)."""
    free = list(named)
    names = []
    for solid in solids:
        size = max(solid.BoundBox.DiagonalLength, 1e-12)
        found = None
        for i, (name, volume, centre) in enumerate(free):
            if abs(volume - solid.Volume) <= 1e-6 * abs(solid.Volume) and \
                    (centre - solid.CenterOfMass).Length <= 1e-6 * size:
                found = i
                break
        names.append(free.pop(found)[0] if found is not None else None)
    return names


def source_file(obj, solids):
    """(path, names): the STEP file obj was imported from and the name it gives each solid
    (None where unknown); (None, all None) when no such file is found or none holds these
    solids."""
    for path in candidate_files(obj):
        try:
            names = match_names(solids, read_named_solids(path))
        except Exception as e:  # an unreadable file: try the next, else no names
            FreeCAD.Console.PrintLog("OracleMesh: names from %s skipped: %s\n" % (path, e))
            continue
        if any(names):
            return path, names
    return None, [None] * len(solids)


def step_solid_names(obj, solids):
    """Names from the STEP file obj was imported from, one per solid (None where unknown)."""
    return source_file(obj, solids)[1]


def declared_uncertainty(objs):
    """The largest uncertainty the STEP files objs were imported from declare (in mm), 0 when
    none is found: FreeCAD's import drops it, and the mesher's contact tolerance is at least
    it (two parts closer than it touch in the CAD tool's eyes)."""
    from .runner import import_core
    largest = 0.0
    for obj in objs:
        shape = getattr(obj, "Shape", None)
        if shape is None or not shape.Solids:
            continue
        path, _ = source_file(obj, shape.Solids)
        if path is None:
            continue
        try:
            largest = max(largest, import_core().step_uncertainty(path))
        except Exception as e:  # the names came from it, so it reads: log, do not fail the mesh
            FreeCAD.Console.PrintLog("OracleMesh: uncertainty of %s skipped: %s\n" % (path, e))
    return largest


def import_assembly(doc, path):
    """Import a STEP assembly as FreeCAD's File > Import does at its defaults (one
    Part::Feature, a compound of every shape, labelled with the file's base name); returns it.

    In the GUI this is FreeCAD's own ImportGui.insert. Headless, FreeCAD 0.20.2 crashes in the
    merge step of Import.insert, so the same result is built from the unmerged tree: the
    merged shape is the tree's shape, as ImportOCAF2 takes it."""
    before = set(o.Name for o in doc.Objects)
    if FreeCAD.GuiUp:
        import ImportGui
        FreeCAD.ParamGet("User parameter:BaseApp/Preferences/Mod/Import/hSTEP").SetBool(
            "ReadShapeCompoundMode", True)
        ImportGui.insert(path, doc.Name)
        return next(o for o in doc.Objects if o.Name not in before)
    import Import
    import Part
    Import.insert(path, doc.Name, merge=False)
    tree = [o for o in doc.Objects if o.Name not in before]
    roots = [o for o in tree if not o.InList]
    shape = Part.getShape(roots[0]) if len(roots) == 1 else \
        Part.makeCompound([Part.getShape(o) for o in roots])
    feature = doc.addObject("Part::Feature", "Feature")
    feature.Label = os.path.splitext(os.path.basename(path))[0]
    feature.Shape = shape
    for name in reversed([o.Name for o in tree]):  # dependents first
        doc.removeObject(name)
    doc.recompute()
    return feature
