"""The demo assembly (oraclemesh_fc.demo: a steel pin through an aluminium plate, one corner
cut away, the plate fixed at x = 0 and pulled down at x = 100) with the pin-plate interface
params["kind"], meshed by OracleMesh and solved by CalculiX through FreeCAD (ccxtools).
Then saved, reopened and written again: the setting and the cards survive."""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def card_names(path):
    with open(path) as f:
        return [line.split(",")[0].strip().upper() for line in f if line.startswith("*")
                and not line.startswith("**")]


def part_nodes(fm):
    """{volume group: its nodes}."""
    out = {}
    for g in fm.Groups:
        if fm.getGroupElementType(g) == "Volume":
            out[fm.getGroupName(g)] = {n for e in fm.getGroupElements(g) for n in fm.getElementNodes(e)}
    return out


def check(params):
    import FreeCAD
    from femtools import ccxtools
    from oraclemesh_fc import makeMesh
    from oraclemesh_fc.calculix import run_calculix
    from oraclemesh_fc.demo import build

    workdir = params["workdir"]
    doc = FreeCAD.newDocument("PinPlate")
    analysis, solver, pin, plate, corner = build(doc)
    mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[corner], cell_size=4.0,
                    facet_distance=0.1, element_order=2,
                    interfaces={"pairs": [{"between": [pin, plate], "kind": params["kind"]}]})
    facts = h.recompute_mesh(doc, mesh)
    result, inp = run_calculix(analysis, solver, os.path.join(workdir, "ccx"))
    disp = dict(zip(result.NodeNumbers, result.DisplacementVectors))
    report = json.loads(mesh.Report)
    fm = mesh.FemMesh
    faces = {fm.getGroupName(g): g for g in fm.Groups if fm.getGroupElementType(g) == "Face"}
    (entry,) = [e for e in report["interfaces"] if sorted(e["parts"]) == ["Pin", "Plate"]]
    out = {
        "mesh": facts, "status": mesh.Status, "entry": entry,
        "cylinder_area": 2 * math.pi * pin.Radius.Value * plate.Height.Value,
        "group_areas": {s: h.face_group_area(fm, faces[s]) for s in entry["surfaces"]},
        "max_displacement": {part: max(disp[n].Length for n in nodes)
                             for part, nodes in part_nodes(fm).items()},
        "cards": card_names(inp),
        "increments": len([o for o in analysis.Group if o.isDerivedFrom("Fem::FemResultObject")]),
    }

    # Saved and reopened: the setting is there and FreeCAD's writer adds the cards again.
    path = os.path.join(workdir, "pin_plate.FCStd")
    names = mesh.Name, analysis.Name, solver.Name
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(path)
    mesh, analysis, solver = (doc.getObject(n) for n in names)
    out["reopened_interfaces"] = mesh.Interfaces
    fea = ccxtools.FemToolsCcx(analysis, solver)
    fea.update_objects()
    fea.setup_working_dir(os.path.join(workdir, "reopened"))
    fea.write_inp_file()
    out["reopened_cards"] = card_names(fea.inp_file_name)
    return out


h.main(check)
