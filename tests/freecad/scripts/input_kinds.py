"""Input kinds from FreeCAD objects: a Mesh feature (moved by its Placement), a Part compound
of two boxes whose solids have different FEM materials, and an imported STEP part holding two
solids of one material, meshed together. Returns the mesh object's InputKinds, the core's
per-solid input names and the tet10 volume of each volume group next to the volumes the
composition must give."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def check(params):
    import FreeCAD
    import Mesh
    import Part
    from oraclemesh_fc import makeMesh
    from oraclemesh_fc.job import can_be_input

    doc = FreeCAD.newDocument("InputKinds")
    # A "scanned bone": a finely tessellated cylinder, radius 4, height 30, as a Mesh feature
    # whose Placement puts it through the first block (x 11..19, y 6..14, z -10..20).
    bone = doc.addObject("Mesh::Feature", "Bone")
    bone.Mesh = Mesh.Mesh(Part.makeCylinder(4, 30).tessellate(0.005))
    bone.Placement = FreeCAD.Placement(FreeCAD.Vector(15, 10, -10), FreeCAD.Rotation())
    # Two boxes side by side as a Part compound: one input per solid in the core.
    blocks = doc.addObject("Part::Compound", "Blocks")
    blocks.Links = [h.box(doc, "BlockA", 0, 0, 0, 20, 20, 10), h.box(doc, "BlockB", 20, 0, 0, 20, 20, 10)]
    # An imported STEP assembly: a Part::Feature holding a compound of two solids.
    step = os.path.join(params["workdir"], "two_plates.step")
    Part.makeCompound([Part.makeBox(40, 8, 4, FreeCAD.Vector(0, 25, 0)),
                       Part.makeBox(40, 8, 4, FreeCAD.Vector(0, 35, 0))]).exportStep(step)
    imported = doc.addObject("Part::Feature", "Plates")
    imported.Shape = Part.read(step)
    doc.recompute()

    analysis, _ = h.analysis_with_solver(doc)
    # FEM materials as a user sets them: the whole Mesh object, single solids of the Part
    # compound (each block its own material), both solids of the STEP part by name.
    refs = {"MatBone": [(bone, "")], "MatBlockA": [(blocks, "Solid1")], "MatBlockB": [(blocks, "Solid2")],
            "MatPlates": [(imported, ("Solid1", "Solid2"))]}
    materials = {}
    for name, references in refs.items():
        materials[name] = h.material(doc, analysis, name, 1000, 0.3, [])
        materials[name].References = references
    mesh = makeMesh(doc, [bone, blocks, imported], analysis=analysis, cell_size=3.0,
                    facet_distance=0.05, element_order=2, **params.get("mesh", {}))
    kinds_before_recompute = list(mesh.InputKinds)
    facts = h.recompute_mesh(doc, mesh)
    report = json.loads(mesh.Report)
    sheet = doc.addObject("Part::Plane", "Sheet")  # a face: nothing to mesh
    doc.recompute()
    bone_volume = bone.Mesh.Volume  # the polyhedron, a prism: a third of it is inside BlockA
    return {
        "mesh": facts,
        "input_kinds": list(mesh.InputKinds),
        "input_kinds_before_recompute": kinds_before_recompute,
        "can_be_input": [can_be_input(o) for o in (bone, blocks, imported, sheet)],
        "imported_label": imported.Label,
        "core_inputs": [(e["name"], e["kind"], e["material"]) for e in report["inputs"]],
        "volume": h.group_volumes(mesh.FemMesh),
        "volume_expected": {materials["MatBone"].Name + "_Volumes": bone_volume,
                            materials["MatBlockA"].Name + "_Volumes": 4000 - bone_volume / 3,
                            materials["MatBlockB"].Name + "_Volumes": 4000,
                            materials["MatPlates"].Name + "_Volumes": 2 * 40 * 8 * 4},
    }


h.main(check)
