"""Steel cantilever 100 x 10 x 10 mm, fixed at x = 0, 1000 N downwards on the face x = 100,
meshed by OracleMesh (tet10) and solved by CalculiX through FreeCAD's FEM workbench."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def check(params):
    import FreeCAD
    import ObjectsFem
    from oraclemesh_fc import makeMesh

    doc = FreeCAD.newDocument("Cantilever")
    beam = h.box(doc, "Beam", 0, 0, 0, 100, 10, 10)
    doc.recompute()
    analysis, solver = h.analysis_with_solver(doc)
    # One material with empty References: FreeCAD's "everything" material.
    h.material(doc, analysis, "Steel", 210000, 0.3, [])
    fixed = ObjectsFem.makeConstraintFixed(doc, "ConstraintFixed")
    fixed.References = [(beam, h.face_where(beam, "x", 0))]
    analysis.addObject(fixed)
    tip_face = h.face_where(beam, "x", 100)
    force = ObjectsFem.makeConstraintForce(doc, "ConstraintForce")
    force.References = [(beam, tip_face)]
    force.Force = 1000.0
    force.Direction = (beam, [h.edge_along(beam, "z")])
    analysis.addObject(force)

    mesh = makeMesh(doc, [beam], analysis=analysis, element_order=2, **params["mesh"])
    facts = h.recompute_mesh(doc, mesh)
    disp, _ = h.solve_displacements(analysis, solver, params["workdir"])
    tip_nodes = mesh.FemMesh.getNodesByFace(beam.Shape.getElement(tip_face))
    uz = [disp[n][2] for n in tip_nodes]
    return {"tip_deflection": abs(sum(uz) / len(uz)), "tip_nodes": len(tip_nodes),
            "mesh": facts, "status": mesh.Status}


h.main(check)
