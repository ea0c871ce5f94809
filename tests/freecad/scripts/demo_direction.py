"""The demo document (oraclemesh_fc.demo) meshed coarse and solved by CalculiX: which way the
loaded end of the plate moves, against the way the demo says it is pulled (down, -z)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def check(params):
    import FreeCAD
    from oraclemesh_fc import demo, makeMesh

    doc = FreeCAD.newDocument("DemoDirection")
    analysis, solver, pin, plate, corner = demo.build(doc)
    mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[corner], **params["mesh"])
    facts = h.recompute_mesh(doc, mesh)
    disp, _ = h.solve_displacements(analysis, solver, params["workdir"])
    force = doc.getObject("EndForce")
    loaded = mesh.FemMesh.getNodesByFace(plate.Shape.getElement(force.References[0][1][0]))
    mean = [sum(disp[n][k] for n in loaded) / len(loaded) for k in range(3)]
    return {"loaded_nodes": len(loaded), "mean_displacement": mean,
            "direction_vector": list(force.DirectionVector), "mesh": facts}


h.main(check)
