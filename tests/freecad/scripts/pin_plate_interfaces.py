"""The demo assembly (oraclemesh_fc.demo: a steel pin through an aluminium plate, one corner
cut away, the plate fixed at x = 0 and pulled down at x = 100) with the pin-plate interface
params["kind"], meshed by OracleMesh and solved by CalculiX through FreeCAD (ccxtools).
Then saved, reopened and written again: the setting and the cards survive; and solved by the
solver framework's CalculiX object (femsolver.run, what its task panel runs)."""
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

    # The solver framework's CalculiX (FreeCAD's other CalculiX solver object), run as its
    # task panel runs it: the same writer, so the same cards, and it solves.
    import ObjectsFem
    from femsolver import run
    framework = ObjectsFem.makeSolverCalculix(doc, "CalculiXFramework")
    framework.AnalysisType = "static"
    framework.GeometricalNonlinearity = "linear"
    analysis.addObject(framework)
    analysis.removeObject(solver)
    folder = os.path.join(workdir, "framework")
    os.makedirs(folder, exist_ok=True)
    run.run_fem_solver(framework, folder)
    inps = [os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".inp")]
    out["framework_cards"] = card_names(inps[0]) if inps else []
    results = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemResultObject")]
    out["framework_max_displacement"] = max(results[-1].DisplacementLengths) if results else None

    if params.get("then_default_contact"):
        # The default made contact and the pin renamed since the last mesh: the pairs that mesh
        # found keep their stiffer master only under the parts' present names.
        pin = doc.getObject(names[0]).Inputs[0]
        mesh.Interfaces = '{"default": "contact"}'
        pin.Label = "SteelPin"
        doc.recompute()
        out["renamed_status"] = mesh.Status
        out["renamed_valid"] = bool(mesh.isValid())
        out["renamed_interfaces"] = json.loads(mesh.Report)["interfaces"]
        doc.recompute()  # meshed again, now the last mesh names the pin SteelPin
        mesh.touch()
        doc.recompute()
        out["remeshed_interfaces"] = json.loads(mesh.Report)["interfaces"]
        from oraclemesh_fc.job import build_job
        out["job_interfaces"] = build_job(mesh)[0]["interfaces"]
    return out


h.main(check)
