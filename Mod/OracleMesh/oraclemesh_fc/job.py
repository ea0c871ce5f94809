"""From an OracleMesh document object to a job dict (DESIGN.md "The job contract").

Priority: `Inputs` are listed highest priority first; where inputs overlap the earlier one
wins. `Cuts` remove material. A FEM engineer marks a cut region to make a hole, so by default
every cut sits at the TOP of the priority list and removes material from all inputs. To let a
cut act only on the inputs below a given position, list the same object in `Inputs` at that
position as well: an object that is in both lists is a cut at its place in `Inputs`.

Material ids are 1, 2, ... in priority order of the material inputs. Volume groups follow the
hand-off rule of DESIGN.md: `<FemMaterial.Name>_Volumes` when a FEM material of the analysis
references the input object, otherwise `<Input.Label>_Volumes`.
"""
import math

import FreeCAD


class MeshInputError(Exception):
    """A user error found on the FreeCAD side (before the core sees the job)."""


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


def global_shape(obj):
    """The object's shape in global coordinates (placement of containers applied)."""
    import Part

    if not hasattr(obj, "Shape") and not obj.isDerivedFrom("App::Link"):
        raise MeshInputError(
            "input '%s' (%s) has no shape: link solids (Part/PartDesign objects) only"
            % (obj.Label, obj.TypeId))
    shape = Part.getShape(obj)  # follows App::Link and applies the object's own placement
    if shape.isNull():
        raise MeshInputError("input '%s' has an empty shape: recompute it or remove it from "
                             "the mesh inputs" % obj.Label)
    # Part.getShape applies the object's own placement; add the placement of any container
    # (App::Part, groups with placement) it lives in.
    own = obj.Placement if hasattr(obj, "Placement") else FreeCAD.Placement()
    parent = obj.getGlobalPlacement().multiply(own.inverse())
    if not parent.isIdentity():
        shape = shape.copy()
        shape.Placement = parent.multiply(shape.Placement)
    return shape


def priority_entries(inputs, cuts):
    """[(obj, role)] highest priority first; see the module docstring for the cut rule."""
    inputs, cuts = list(inputs), list(cuts)
    names = [o.Name for o in inputs]
    for o in inputs:
        if names.count(o.Name) > 1:
            raise MeshInputError("input '%s' is listed twice in Inputs: list each object once"
                                 % o.Label)
    cut_names = {o.Name for o in cuts}
    entries = [(o, "cut") for o in cuts if o.Name not in names]
    entries += [(o, "cut" if o.Name in cut_names else "material") for o in inputs]
    return entries


def fem_materials(mesh_obj):
    """Linear FEM material objects of the analysis holding mesh_obj (else of the document)."""
    from femtools import femutils

    analyses = [o for o in mesh_obj.InList if o.isDerivedFrom("Fem::FemAnalysis")]
    pool = analyses[0].Group if analyses else mesh_obj.Document.Objects
    return [o for o in pool
            if femutils.is_of_type(o, "Fem::MaterialCommon")
            or femutils.is_of_type(o, "Fem::MaterialReinforced")]


def volume_groups(material_entries, materials, names=None):
    """[(group_name, [material ids])] for the material inputs [(obj, material_id)].

    FreeCAD 0.20's CalculiX writer (femmesh/meshtools.get_femelement_sets_from_group_data)
    takes, for each FEM material, the first Volume group whose name starts with
    `<material.Name>_`, and uses the groups only if their sizes add up to the volume count.
    So each FEM material gets exactly one group, and inputs it references are merged into it.
    A material with empty References is FreeCAD's "everything else" material: it takes the
    inputs no other material references. names ({input Name: material name}) names the
    group of an input no FEM material references (instead of its Label).
    """
    by_name = {}
    order = []
    fallback = [m for m in materials if not m.References]
    for obj, mid in material_entries:
        owners = [m for m in materials if any(ref[0] == obj for ref in m.References)]
        if len(owners) > 1:
            FreeCAD.Console.PrintWarning(
                "OracleMesh: input '%s' is referenced by several FEM materials (%s); using '%s'\n"
                % (obj.Label, ", ".join(m.Label for m in owners), owners[0].Label))
        if owners:
            name = owners[0].Name + "_Volumes"
        elif (names or {}).get(obj.Name):
            name = names[obj.Name] + "_Volumes"
        elif fallback:
            name = fallback[0].Name + "_Volumes"
        else:
            name = obj.Label + "_Volumes"
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


def build_job(mesh_obj):
    """(job dict, volume groups, [(obj, role, material id or None)]) for the mesh object."""
    entries = priority_entries(mesh_obj.Inputs, mesh_obj.Cuts)
    if not mesh_obj.Inputs:
        raise MeshInputError(
            "'%s' has no inputs: add solids to its Inputs property, highest priority first "
            "(or select solids and run 'Mesh selection with OracleMesh')" % mesh_obj.Label)

    if all(role == "cut" for _, role in entries):
        raise MeshInputError(
            "every input of '%s' is also in Cuts (%s), so nothing is left to mesh: remove "
            "the solids to mesh from Cuts" % (mesh_obj.Label,
                                             ", ".join(o.Label for o, _ in entries)))

    job_inputs, material_entries, described = [], [], []
    for obj, role in entries:
        item = {"name": obj.Label, "brep": global_shape(obj).exportBrepToString()}
        if role == "cut":
            item["role"] = "cut"
            described.append((obj, "cut", None))
        else:
            mid = len(material_entries) + 1
            item["material"] = mid
            material_entries.append((obj, mid))
            described.append((obj, "material", mid))
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
    by_key = {}
    for obj, mid in material_entries:
        by_key[obj.Name] = mid
        by_key.setdefault(obj.Label, mid)
    for key, text in dict(mesh_obj.InputSizes).items():
        if key not in by_key:
            raise MeshInputError(
                "InputSizes names '%s', which is not a material input of '%s': use the Name "
                "or Label of an object in Inputs" % (key, mesh_obj.Label))
        per_material.setdefault(str(by_key[key]), {}).update(
            parse_size_entry(text, "InputSizes['%s']" % key))

    job = {
        "inputs": job_inputs,
        "criteria": {"default": default, "materials": per_material},
        "features": ({"sharp_angle_deg": _value(mesh_obj.SharpAngle),
                      "junctions": bool(getattr(mesh_obj, "Junctions", True))}
                     if _value(mesh_obj.SharpAngle) > 0 else False),
        "engine": str(getattr(mesh_obj, "Engine", "cgal")),
        "element_order": int(mesh_obj.ElementOrder),
        "optimize": {"perturb": bool(mesh_obj.Optimize), "exude": bool(mesh_obj.Optimize)},
        "seed": int(mesh_obj.Seed),
        "limits": {"max_vertices": int(mesh_obj.MaxVertices),
                   "time_limit": float(mesh_obj.TimeLimit)},
    }
    if mesh_obj.OutputFiles or mesh_obj.OutputReport:
        job["output"] = {}
        if mesh_obj.OutputFiles:
            job["output"]["files"] = list(mesh_obj.OutputFiles)
        if mesh_obj.OutputReport:
            job["output"]["report"] = mesh_obj.OutputReport

    groups = volume_groups(material_entries, fem_materials(mesh_obj),
                           dict(getattr(mesh_obj, "InputMaterialNames", {})))
    return job, groups, described
