"""Headless checks of the parts of compounds (parts.py, input_rows.py, step_labels.py): the
presse's solids named from its STEP file after FreeCAD's import merged them into one compound;
a Part::Compound of two boxes split into rows named by its links, a FEM material on one
solid, a name on the other, a priority moved, meshed into one group per solid; the same
compound treated as one input."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def check(params):
    import FreeCAD
    from oraclemesh_fc import makeMesh, input_rows
    from oraclemesh_fc.job import build_job
    from oraclemesh_fc.parts import input_parts
    from oraclemesh_fc.step_labels import import_assembly

    out = {}
    step = os.path.join(os.environ.get("ORACLEMESH_CAD_DIR", "/work/shared/data/cad"),
                        "presse_asm.step")
    doc = FreeCAD.newDocument("Presse")
    presse = import_assembly(doc, step)
    out["presse"] = [presse.Label, len(presse.Shape.Solids)]
    named = makeMesh(doc, [presse], step_file=step)
    out["presse_labels"] = [p.label for p, _ in input_parts(named)]
    out["presse_cad_uncertainty"] = named.CadUncertainty.Value
    out["presse_job_cad_uncertainty"] = build_job(named)[0].get("cad_uncertainty")
    # Nowhere FreeCAD's import leaves traces (recent files, file dialog folder) is the file.
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences/General").SetString(
        "FileOpenSavePath", params["workdir"])
    FreeCAD.ParamGet("User parameter:BaseApp/Preferences").RemGroup("RecentFiles")
    unnamed = makeMesh(doc, [presse], name="Unnamed")
    out["unnamed_labels"] = [p.label for p, _ in input_parts(unnamed)][:2]
    out["unnamed_cad_uncertainty"] = unnamed.CadUncertainty.Value
    out["unnamed_job_keys"] = sorted(build_job(unnamed)[0])

    doc = FreeCAD.newDocument("Boxes")
    pair = doc.addObject("Part::Compound", "Pair")
    pair.Links = [h.box(doc, "Left", 0, 0, 0, 10, 10, 10), h.box(doc, "Right", 10, 0, 0, 10, 10, 10)]
    over = h.box(doc, "Over", 5, 2, 2, 10, 6, 6)  # overlaps both boxes
    doc.recompute()
    analysis, _ = h.analysis_with_solver(doc)
    steel = h.material(doc, analysis, "Steel", 210000, 0.3, [over])
    mesh = makeMesh(doc, [pair, over], analysis=analysis, cell_size=3.0, element_order=2)
    rows = input_rows.rows_from_object(mesh, [steel])
    out["rows"] = [(r.key, r.label, r.material) for r in rows]
    rows[1].material = "Steel"           # the Right box: steel too
    rows[0].material = "Aluminium"       # the Left box: a name
    rows.insert(0, rows.pop(2))          # the Over box moves up: it wins the overlap
    rows = [rows[0], rows[2], rows[1]]   # Right above Left
    input_rows.write_rows(mesh, rows, [steel])
    out["written"] = {"steel": [(o.Name, list(s)) for o, s in steel.References],
                      "names": dict(mesh.InputMaterialNames), "order": list(mesh.PartOrder),
                      "whole": [o.Name for o in mesh.WholeInputs]}
    job, groups, _, _ = build_job(mesh)
    out["job_inputs"] = [(i["name"], i["material"]) for i in job["inputs"]]
    out["groups"] = groups
    out["mesh"] = h.recompute_mesh(doc, mesh)
    out["volumes"] = h.group_volumes(mesh.FemMesh)
    out["steel_group"] = steel.Name + "_Volumes"

    joined = input_rows.join_rows(rows, pair)
    input_rows.write_rows(mesh, joined, [steel])
    job, groups, _, _ = build_job(mesh)
    out["joined"] = {"rows": [(r.key, r.label) for r in joined],
                     "whole": [o.Name for o in mesh.WholeInputs],
                     "job_inputs": [(i["name"], i["material"]) for i in job["inputs"]],
                     "groups": groups}
    split = input_rows.split_rows(mesh, [steel], joined, pair)
    out["split_again"] = [(r.key, r.label) for r in split]
    return out


h.main(check)
