"""Bad inputs through FreeCAD: each must fail with a clear message, leave the previous mesh
and the document as they were, and not crash FreeCAD; a fixed input must mesh again."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def check(params):
    import FreeCAD
    import Part
    from oraclemesh_fc import makeMesh

    doc = FreeCAD.newDocument("BadInputs")
    good = h.box(doc, "GoodBox", 0, 0, 0, 20, 10, 10)
    plane = doc.addObject("Part::Plane", "FaceOnly")
    plane.Length = plane.Width = 10
    shell = doc.addObject("Part::Feature", "OpenShell")
    shell.Shape = Part.Shell(Part.makeBox(10, 10, 10).Faces[:5])  # one face missing
    group = doc.addObject("App::DocumentObjectGroup", "JustAGroup")
    pin = doc.addObject("Part::Cylinder", "Pin")
    pin.Radius, pin.Height = 3, 20
    doc.recompute()
    mesh = makeMesh(doc, [good], cell_size=3.0, element_order=1)
    doc.recompute()
    if not mesh.isValid():
        raise RuntimeError("the good mesh failed: " + mesh.Status)
    baseline = (mesh.FemMesh.VolumeCount, mesh.FemMesh.NodeCount)
    names = sorted(o.Name for o in doc.Objects)

    cases = {
        "no_inputs": {"Inputs": []},
        "face_only": {"Inputs": [plane]},
        "open_shell": {"Inputs": [shell]},
        "only_cuts": {"Inputs": [good], "Cuts": [good]},
        "negative_size": {"InputSizes": {"GoodBox": "-1"}},
        "nan_size": {"InputSizes": {"GoodBox": "cell_size=nan"}},
        "too_many_vertices": {"CellSize": 0.05, "MaxVertices": 1000},
        "not_a_shape": {"Inputs": [good, group]},
        "unknown_size_key": {"InputSizes": {"Nope": "1"}},
        "listed_twice": {"Inputs": [good, good]},
        "interface_unknown_part": {"Interfaces": '{"pairs": [{"between": ["GoodBox", "Nope"], '
                                                 '"kind": "tied"}]}'},
        "interface_bad_kind": {"Interfaces": '{"default": "glued"}'},
        "interface_not_json": {"Interfaces": '{"default": bonded'},
        # tet4 cells of 30 on a pin of radius 3: a prism of a few sides, far short of its volume
        "fails_its_check": {"Inputs": [pin], "Checks": "error", "CellSize": 30, "Fineness": "off"},
    }
    out = {}
    for case, props in cases.items():
        saved = {k: getattr(mesh, k) for k in props}
        for k, v in props.items():
            setattr(mesh, k, v)
        doc.recompute()
        out[case] = {
            "valid": mesh.isValid(),
            "state": list(mesh.State),
            "status": mesh.Status,
            "kinds": list(mesh.InputKinds),
            "mesh_kept": (mesh.FemMesh.VolumeCount, mesh.FemMesh.NodeCount) == baseline,
            "objects_kept": sorted(o.Name for o in doc.Objects) == names,
        }
        for k, v in saved.items():
            setattr(mesh, k, v)
    doc.recompute()
    out["recovered"] = mesh.isValid() and mesh.FemMesh.VolumeCount > 0

    # With Checks = warn the pin that fails its check is kept, and the problem reaches the
    # report view as well as the report, in the mesh object's words.
    printed = []
    print_warning = FreeCAD.Console.PrintWarning
    FreeCAD.Console.PrintWarning = printed.append
    try:
        mesh.Inputs, mesh.Checks, mesh.CellSize, mesh.Fineness = [pin], "warn", 30, "off"
        doc.recompute()
    finally:
        FreeCAD.Console.PrintWarning = print_warning
    out["kept_with_warn"] = {"valid": mesh.isValid(), "volumes": mesh.FemMesh.VolumeCount,
                             "warnings": json.loads(mesh.Report).get("warnings", []), "printed": printed}

    # makeMesh refuses bad interface settings before it makes anything.
    refusals = {
        "kind": {"pairs": [{"between": ["GoodBox", "Other"], "kind": "glued"}]},
        "friction": {"pairs": [{"between": ["GoodBox", "Other"], "kind": "tied", "friction": 0.2}]},
        "part": {"pairs": [{"between": ["GoodBox", "Nope"], "kind": "contact"}]},
        "key": {"pairs": [{"between": ["GoodBox", "Other"], "kind": "contact", "mu": 0.2}]},
    }
    other = h.box(doc, "Other", 20, 0, 0, 10, 10, 10)
    doc.recompute()
    names = sorted(o.Name for o in doc.Objects)
    refused = {}
    for case, settings in refusals.items():
        try:
            makeMesh(doc, [good, other], interfaces=settings)
            refused[case] = {"message": None}
        except ValueError as e:
            refused[case] = {"message": str(e)}
        refused[case]["objects_kept"] = sorted(o.Name for o in doc.Objects) == names
    return {"cases": out, "refused": refused}


h.main(check)
