"""From an OracleMesh document object to a job dict (src/README.md, "The job contract").

Priority: `Inputs` are listed highest priority first; where inputs overlap the earlier one
wins. `Cuts` remove material. A FEM engineer marks a cut region to make a hole, so by default
every cut sits at the TOP of the priority list and removes material from all inputs. To let a
cut act only on the inputs below a given position, list the same object in `Inputs` at that
position as well: an object that is in both lists is a cut at its place in `Inputs`.

Input kinds: Part/PartDesign features and App::Links go to the core as BREP text; a compound
of solids (Part::Compound, an imported STEP assembly) is split into parts, one per solid
(parts.py: labels, PartOrder), each its own core input with its own material id, unless it is
in WholeInputs: then it is one input (the core still meshes its solids separately) with one
material. Mesh features (Mesh::Feature) go as triangle surfaces (closed, manifold,
consistently oriented; their Placement applied).

Material ids are 1, 2, ... in priority order of the material parts. Volume groups follow the
hand-off rule of src/README.md: `<FemMaterial.Name>_Volumes` when a FEM material of the analysis
references the part (the object, or its solid 'SolidK'), else the name the user gave it, else
`<part label>_Volumes`.
"""
import math

import FreeCAD

from .interfaces import (InterfaceSettingsError, check_part_names, found_pairs, last_report,
                         with_stiffer_masters)
from .interfaces import from_text as interface_from_text
from .input_objects import (  # noqa: F401 (also the names other modules import from here)
    MeshInputError, global_mesh, global_shape, is_mesh_feature, priority_entries)


# Property name -> (job criteria key). Zero means "not set": the core then derives the value
# from the model size (cell_size = diagonal/15, facet_size = cell_size, ...).
CRITERIA_PROPERTIES = (
    ("CellSize", "cell_size"),
    ("CellRadiusEdgeRatio", "cell_radius_edge_ratio"),
    ("FacetSize", "facet_size"),
    ("FacetDistance", "facet_distance"),
    ("FacetAngle", "facet_angle"),
    ("EdgeSize", "edge_size"),
)
CRITERIA_KEYS = tuple(key for _, key in CRITERIA_PROPERTIES)


def _value(prop):
    """Float of a plain float or a FreeCAD Quantity (Length/Angle properties)."""
    return float(getattr(prop, "Value", prop))


def input_item(obj):
    """(job input dict without role/material, kind text) for one input object.

    Mesh features become in-memory triangle surfaces; everything with a shape goes as BREP
    text, and the core makes one input per solid (file order = priority) of a compound."""
    if is_mesh_feature(obj):
        points, triangles = global_mesh(obj)
        return ({"name": obj.Label, "surface": {"points": points, "triangles": triangles}},
                "triangle surface (%d triangles)" % len(triangles))
    shape = global_shape(obj)
    return {"name": obj.Label, "brep": shape.exportBrepToString()}, shape_kind(shape)


def shape_kind(shape):
    solids = len(shape.Solids)
    if solids == 1 and shape.ShapeType == "Solid":
        return "B-rep solid"
    if solids >= 1:
        return "B-rep compound (%d solid%s)" % (solids, "" if solids == 1 else "s")
    shells = len(shape.Shells)
    if shells:
        return "B-rep shell%s (made solid if closed)" % ("" if shells == 1 else "s")
    return "no solid (%s)" % shape.ShapeType


def can_be_input(obj):
    """Could obj be a mesh input: a shape with solids or shells, or a non-empty Mesh object."""
    if is_mesh_feature(obj):
        return obj.Mesh.CountFacets > 0
    shape = getattr(obj, "Shape", None)
    return shape is not None and not shape.isNull() and bool(shape.Solids or shape.Shells)


def input_kinds(mesh_obj):
    """'<Label>: <kind>' for every entry of the mesh object, in priority order."""
    lines = []
    for obj, role in priority_entries(mesh_obj.Inputs, mesh_obj.Cuts):
        try:
            if is_mesh_feature(obj):
                kind = "triangle surface (%d triangles)" % obj.Mesh.CountFacets
            else:
                kind = shape_kind(global_shape(obj))
        except MeshInputError as e:
            kind = "not usable: %s" % e
        lines.append("%s: %s%s" % (obj.Label, kind, " (cut)" if role == "cut" else ""))
    return lines


def fem_materials(mesh_obj):
    """Linear FEM material objects of the analysis holding mesh_obj (else of the document)."""
    from femtools import femutils

    analyses = [o for o in mesh_obj.InList if o.isDerivedFrom("Fem::FemAnalysis")]
    pool = analyses[0].Group if analyses else mesh_obj.Document.Objects
    return [o for o in pool
            if femutils.is_of_type(o, "Fem::MaterialCommon")
            or femutils.is_of_type(o, "Fem::MaterialReinforced")]


def _subnames(ref):
    subs = ref[1] if len(ref) > 1 else ()
    return (subs,) if isinstance(subs, str) else tuple(subs)


def references(material, obj, solid=None):
    """Does the FEM material reference obj (solid=None), or solid number `solid` of obj?

    A reference to the whole object (no sub-element) covers every solid of it; a reference
    to 'SolidK' covers that solid only, as FreeCAD's own CalculiX writer reads it."""
    for ref in material.References:
        if ref[0] != obj:
            continue
        subs = [s for s in _subnames(ref) if s]
        if solid is None or not subs or "Solid%d" % solid in subs:
            return True
    return False


def volume_groups(material_entries, materials, names=None):
    """[(group_name, [material ids])] for the material parts [(InputPart, material id)]
    (parts.py: an object, or one solid of a compound).

    FreeCAD 0.20's CalculiX writer (femmesh/meshtools.get_femelement_sets_from_group_data)
    takes, for each FEM material, the first Volume group whose name starts with
    `<material.Name>_`, and uses the groups only if their sizes add up to the volume count.
    So each FEM material gets exactly one group, and parts it references are merged into it.
    A material with empty References is FreeCAD's "everything else" material: it takes the
    parts no other material references. names ({part key: material name}, a whole object's
    key being its Name) names the group of a part no FEM material references (instead of
    its label).
    """
    by_name = {}
    order = []
    fallback = [m for m in materials if not m.References]
    for part, mid in material_entries:
        owners = [m for m in materials if references(m, part.obj, part.solid)]
        if len(owners) > 1:
            FreeCAD.Console.PrintWarning(
                "OracleMesh: input '%s' is referenced by several FEM materials (%s); using '%s'\n"
                % (part.label, ", ".join(m.Label for m in owners), owners[0].Label))
        if owners:
            name = owners[0].Name + "_Volumes"
        elif (names or {}).get(part.key):
            name = names[part.key] + "_Volumes"
        elif fallback:
            name = fallback[0].Name + "_Volumes"
        else:
            name = part.label + "_Volumes"
        if name not in by_name:
            by_name[name] = []
            order.append(name)
        by_name[name].append(mid)
    return [(name, by_name[name]) for name in order]


def parse_size_entry(text, where):
    """'1.5' -> {'cell_size': 1.5}; 'cell_size=1.5 facet_distance=0.05' -> both keys."""
    text = str(text).strip()
    sizes = {}
    try:
        sizes["cell_size"] = float(text)
        items = []
    except ValueError:
        items = text.replace(",", " ").replace(";", " ").split()
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or key not in CRITERIA_KEYS:
            raise MeshInputError(
                "%s: '%s' is not understood: give a cell size ('1.5') or key=value pairs with "
                "keys %s" % (where, item, ", ".join(CRITERIA_KEYS)))
        try:
            sizes[key] = float(value)
        except ValueError:
            raise MeshInputError("%s: %s = '%s' is not a number" % (where, key, value)) from None
    for key, value in sizes.items():
        # NaN would not even survive JSON; say which entry is wrong instead.
        if not math.isfinite(value) or value <= 0:
            raise MeshInputError("%s: %s = %s is not a positive finite number: give a positive "
                                 "size in model units (mm)" % (where, key, value))
    return sizes


# Chord error allowed when a curved extra edge becomes a polyline, as a fraction of the edge's
# length (a full circle gets 28 chords). The core keeps every point as a
# mesh vertex and puts the nodes between them back onto the exact curve (the edge goes along
# as BREP), so the chords only need to stay well inside the elements along the edge.
EXTRA_EDGE_CHORD_ERROR = 1e-3


def extra_edge_links(items):
    """ExtraEdges (PropertyLinkSubList) value of extra edges given as objects or (object,
    sub-names): what extra_edge_items reads back.

    A whole object goes in bare: FreeCAD drops an (object, ()) pair with no sub-names."""
    links = []
    for item in items:
        if isinstance(item, (tuple, list)):
            obj, subs = item[0], item[1] if len(item) > 1 else ()
            subs = [subs] if isinstance(subs, str) else [s for s in subs if s]
            links.extend([(obj, s) for s in subs] if subs else [obj])
        else:
            links.append(item)
    return links


def extra_edge_items(mesh_obj):
    """[(name for the user, Part.Edge in global coordinates)] of the mesh object's ExtraEdges,
    in property order: each picked 'EdgeN', and every edge of a whole linked object (a
    sketch, or any shape). Sketches keep their construction geometry out of their shape."""
    items = []
    for ref in getattr(mesh_obj, "ExtraEdges", []) or []:
        obj, subs = ref[0], [s for s in _subnames(ref) if s]
        try:
            alive = obj is not None and obj.Document is not None
        except Exception:  # a deleted object refuses every attribute
            alive = False
        if not alive:
            raise MeshInputError("ExtraEdges of '%s' links a deleted object: remove it from the "
                                 "extra edges" % mesh_obj.Label)
        try:
            shape = global_shape(obj)
        except MeshInputError as e:
            raise MeshInputError("ExtraEdges of '%s': %s" % (mesh_obj.Label, e)) from None
        if not subs:
            if not shape.Edges:
                raise MeshInputError(
                    "ExtraEdges of '%s' links '%s', which has no edges: link sketches or "
                    "edges of shapes" % (mesh_obj.Label, obj.Label))
            subs = ["Edge%d" % i for i in range(1, len(shape.Edges) + 1)]
        for sub in subs:
            number = sub[4:] if sub.startswith("Edge") else ""
            if not number.isdigit():
                raise MeshInputError(
                    "ExtraEdges of '%s' names '%s' of '%s', which is not an edge: pick edges "
                    "(EdgeN) or whole sketches" % (mesh_obj.Label, sub, obj.Label))
            if not 1 <= int(number) <= len(shape.Edges):
                raise MeshInputError(
                    "ExtraEdges of '%s' names %s of '%s', which has only %d edges now (its "
                    "shape changed): pick the edge again" % (mesh_obj.Label, sub, obj.Label,
                                                             len(shape.Edges)))
            items.append(("%s of '%s'" % (sub, obj.Label), shape.Edges[int(number) - 1]))
    return items


def edge_points(edge):
    """Points of a polyline along edge: its ends for a straight edge, else chords within
    EXTRA_EDGE_CHORD_ERROR of the edge's length of the curve."""
    if edge.Curve.TypeId == "Part::GeomLine":
        points = [edge.valueAt(edge.FirstParameter), edge.valueAt(edge.LastParameter)]
    else:
        points = edge.discretize(Deflection=EXTRA_EDGE_CHORD_ERROR * edge.Length)
    out = []
    for p in points:  # the core refuses a point repeated right after itself
        if not out or (p - out[-1]).Length > 1e-12 * edge.Length:
            out.append(p)
    return [[p.x, p.y, p.z] for p in out]


def extra_edge_polylines(mesh_obj):
    """(job features.polylines, [name of polyline i]): one polyline per extra edge, with the
    edge as BREP text so the core snaps mesh nodes onto the exact curve."""
    polylines, names = [], []
    for name, edge in extra_edge_items(mesh_obj):
        if edge.isNull() or edge.Length <= 0:
            raise MeshInputError("extra edge %s of '%s' has no length: remove it"
                                 % (name, mesh_obj.Label))
        polylines.append({"points": edge_points(edge), "brep": edge.exportBrepToString()})
        names.append(name)
    return polylines, names


def in_mesh_object_words(text, names, described=()):
    """A core message as the mesh object's user reads it: 'features.polylines[i]' with the
    extra edge's name (`names`), the self-check's way out as the Checks property, and a
    material's sizes (criteria.materials."N") as the InputSizes key of its part where one part
    has that material (`described`: build_job's (part, role, material id) triples)."""
    import re

    def named(match):
        i = int(match.group(1))
        if i < len(names):
            return "extra edge %s (%s)" % (names[i], match.group(0))
        return match.group(0)
    text = re.sub(r"features\.polylines\[(\d+)\]", named, text)
    keys = {}  # material id -> the keys of its parts (InputSizes' keys)
    for part, role, mid in described:
        if role == "material":
            keys.setdefault(mid, []).append(part.key)
    for mid, of in keys.items():
        if len(of) == 1:
            text = text.replace('criteria.materials."%d"' % mid, "InputSizes['%s']" % of[0])
    return text.replace('set "checks": "warn"', "set the mesh object's Checks to warn")


def build_job(mesh_obj):
    """(job dict, volume groups, [(obj, role, material id or None)], [name of each
    features.polylines entry]) for the mesh object."""
    from .parts import input_parts

    if not mesh_obj.Inputs:
        raise MeshInputError(
            "'%s' has no inputs: add solids to its Inputs property, highest priority first "
            "(or select solids and run 'Mesh selection with OracleMesh')" % mesh_obj.Label)
    # Labels the panel or makeMesh did not store stay '<Label> SolidK': no STEP file is read
    # (into a scratch document) during a recompute.
    entries = input_parts(mesh_obj, search=False)
    if all(role == "cut" for _, role in entries):
        raise MeshInputError(
            "every input of '%s' is also in Cuts (%s), so nothing is left to mesh: remove "
            "the solids to mesh from Cuts" % (mesh_obj.Label,
                                             ", ".join(p.label for p, _ in entries)))

    materials = fem_materials(mesh_obj)
    job_inputs, material_entries, described = [], [], []
    for part, role in entries:
        if part.solid is None:
            item, _ = input_item(part.obj)
        else:  # one solid of a compound: an input of its own, with its own material id
            item = {"name": part.label, "brep": part.shape().exportBrepToString()}
        if role == "cut":
            item["role"] = "cut"
            described.append((part, "cut", None))
        else:
            mid = len(material_entries) + 1
            item["material"] = mid
            material_entries.append((part, mid))
            described.append((part, "material", mid))
        job_inputs.append(item)

    default = {}
    for prop, key in CRITERIA_PROPERTIES:
        value = _value(getattr(mesh_obj, prop))
        if not math.isfinite(value) or value < 0:
            raise MeshInputError("%s of '%s' is %s: give a positive value, or 0 for automatic"
                                 % (prop, mesh_obj.Label, value))
        if value != 0:  # 0 = automatic (the core derives it from the model size)
            default[key] = value

    per_material = {}
    # Key (Name, Name.SolidK), else Label (of the object, or of the part) -> material ids.
    by_key = {}
    for part, mid in material_entries:
        for key in (part.obj.Label, part.label, part.key, part.obj.Name):
            by_key.setdefault(key, []).append(mid)
    for key, text in dict(mesh_obj.InputSizes).items():
        if key not in by_key:
            raise MeshInputError(
                "InputSizes names '%s', which is not a material input of '%s': use the Name "
                "or Label of an object in Inputs, or Name.SolidK of one of its solids"
                % (key, mesh_obj.Label))
        sizes = parse_size_entry(text, "InputSizes['%s']" % key)
        for mid in by_key[key]:
            per_material.setdefault(str(mid), {}).update(sizes)

    # SharpAngle 0 switches the automatic features (sharp edges, junctions) off; extra edges
    # the user picked are kept either way.
    polylines, polyline_names = extra_edge_polylines(mesh_obj)
    sharp = _value(mesh_obj.SharpAngle)
    if sharp > 0:
        features = {"sharp_angle_deg": sharp, "junctions": bool(getattr(mesh_obj, "Junctions", True))}
    elif polylines:
        features = {"sharp_angle_deg": 0.0, "junctions": False}
    else:
        features = False
    if polylines:
        features["polylines"] = polylines
    if bool(getattr(mesh_obj, "PlanarFaces", False)):
        if str(getattr(mesh_obj, "Engine", "thesis")) != "thesis" or not features or not features.get("junctions"):
            raise MeshInputError(
                "PlanarFaces of '%s' needs Engine 'thesis', a sharp-edge angle above 0 and "
                "Junctions on (the planar faces' borders must be kept as mesh edges): set them or "
                "switch PlanarFaces off" % mesh_obj.Label)
        features["planar_faces"] = True

    criteria = {"default": default, "materials": per_material}
    # Always sent: the core's unset value is "moderate", and "off" must reach it as "off".
    criteria["fineness"] = str(getattr(mesh_obj, "Fineness", "off")).replace(" ", "_")
    job = {
        "inputs": job_inputs,
        "criteria": criteria,
        "features": features,
        "engine": str(getattr(mesh_obj, "Engine", "thesis")),
        "checks": str(getattr(mesh_obj, "Checks", "error")),
        "element_order": int(mesh_obj.ElementOrder),
        "optimize": {"perturb": bool(mesh_obj.Optimize), "exude": bool(mesh_obj.Optimize)},
        "seed": int(mesh_obj.Seed),
        "limits": {"max_vertices": int(mesh_obj.MaxVertices),
                   "time_limit": float(mesh_obj.TimeLimit)},
    }
    contact_tolerance = _value(getattr(mesh_obj, "ContactTolerance", 0.0))
    if contact_tolerance > 0:  # 0: the core's default from the shapes
        job["contact_tolerance"] = contact_tolerance
    cad_uncertainty = _value(getattr(mesh_obj, "CadUncertainty", 0.0))
    if cad_uncertainty > 0:
        job["cad_uncertainty"] = cad_uncertainty
    if mesh_obj.OutputFiles or mesh_obj.OutputReport:
        job["output"] = {}
        if mesh_obj.OutputFiles:
            job["output"]["files"] = list(mesh_obj.OutputFiles)
        if mesh_obj.OutputReport:
            job["output"]["report"] = mesh_obj.OutputReport

    settings = interface_settings(mesh_obj)
    if settings:
        try:
            check_interface_parts(settings, entries, "Interfaces of '%s'" % mesh_obj.Label)
        except InterfaceSettingsError as e:
            raise MeshInputError(str(e)) from None
        # Pairs of the last mesh whose parts are still parts (not renamed or removed since).
        labels = {part.label for part, _ in material_entries}
        touching = [(a, b) for a, b, _, _, _ in found_pairs(last_report(mesh_obj))
                    if a in labels and b in labels]
        job["interfaces"] = with_stiffer_masters(
            settings, youngs_moduli(material_entries, materials), touching)

    groups = volume_groups(material_entries, materials, dict(getattr(mesh_obj, "InputMaterialNames", {})))
    return job, groups, described, polyline_names


def check_interface_parts(settings, entries, where):
    """The parts the interface settings name are material parts of entries [(InputPart,
    role)]. A whole input of several solids is one part the core names itself: then the
    core checks the names (its error lists its part names)."""
    materials = [part for part, role in entries if role != "cut"]
    if not any(part.solid is None and not is_mesh_feature(part.obj)
               and len(global_shape(part.obj).Solids) > 1 for part in materials):
        check_part_names(settings, [part.label for part in materials], where)


def youngs_moduli(material_entries, materials):
    """{part label: Young's modulus in MPa} of the parts a FEM material with a modulus covers
    (its References, else FreeCAD's "everything else" material with empty References)."""
    fallback = [m for m in materials if not m.References]
    moduli = {}
    for part, _ in material_entries:
        owners = [m for m in materials if references(m, part.obj, part.solid)] or fallback
        text = owners[0].Material.get("YoungsModulus") if owners else None
        try:
            moduli[part.label] = FreeCAD.Units.Quantity(text).getValueAs("MPa").Value
        except Exception:  # no modulus, or text FreeCAD cannot read: the core decides
            continue
    return moduli


def interface_settings(mesh_obj):
    """The mesh object's checked interface settings ({} = all bonded); MeshInputError naming
    the property when its text is bad."""
    try:
        return interface_from_text(getattr(mesh_obj, "Interfaces", ""),
                                   "Interfaces of '%s'" % mesh_obj.Label)
    except InterfaceSettingsError as e:
        raise MeshInputError(str(e)) from None
