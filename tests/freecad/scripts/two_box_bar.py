"""A bar of two overlapping boxes in series along x: steel x 0..110 (higher priority) over
aluminium x 90..200, section 10 x 10, so steel holds 0..110 and aluminium 110..200.
Axial force 1000 N on x = 200; rollers on x = 0 (ux), y = 0 (uy), z = 0 (uz) and Poisson's
ratio 0 make uniaxial stress the exact solution: elongation = F L1/(E1 A) + F L2/(E2 A)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def roller(doc, analysis, name, axis, refs):
    import ObjectsFem
    c = ObjectsFem.makeConstraintDisplacement(doc, name)
    c.References = refs
    for a in "xyz":
        setattr(c, a + "Free", a != axis)
        setattr(c, a + "Fix", a == axis)
    analysis.addObject(c)
    return c


def check(params):
    import FreeCAD
    import ObjectsFem
    from oraclemesh_fc import makeMesh

    doc = FreeCAD.newDocument("TwoBoxBar")
    steel = h.box(doc, "SteelBox", 0, 0, 0, 110, 10, 10)
    alu = h.box(doc, "AluminiumBox", 90, 0, 0, 110, 10, 10)
    doc.recompute()
    analysis, solver = h.analysis_with_solver(doc)
    m_steel = h.material(doc, analysis, "Steel", 210000, 0.0, [steel])
    m_alu = h.material(doc, analysis, "Aluminium", 70000, 0.0, [alu])
    roller(doc, analysis, "RollerX", "x", [(steel, h.face_where(steel, "x", 0))])
    roller(doc, analysis, "RollerY", "y", [(steel, h.face_where(steel, "y", 0)),
                                           (alu, h.face_where(alu, "y", 0))])
    roller(doc, analysis, "RollerZ", "z", [(steel, h.face_where(steel, "z", 0)),
                                           (alu, h.face_where(alu, "z", 0))])
    end_face = h.face_where(alu, "x", 200)
    force = ObjectsFem.makeConstraintForce(doc, "ConstraintForce")
    force.References = [(alu, end_face)]
    force.Force = 1000.0
    force.Direction = (alu, [h.edge_along(alu, "x")])
    analysis.addObject(force)

    mesh = makeMesh(doc, [steel, alu], analysis=analysis, **params["mesh"])
    facts = h.recompute_mesh(doc, mesh)
    disp, inp = h.solve_displacements(analysis, solver, params["workdir"])
    end_nodes = mesh.FemMesh.getNodesByFace(alu.Shape.getElement(end_face))
    ux = [disp[n][0] for n in end_nodes]
    # The ccx input must carry one element set per material, from the groups.
    with open(inp) as f:
        text = f.read()
    return {"elongation": sum(ux) / len(ux), "ux_spread": max(ux) - min(ux),
            "end_nodes": len(end_nodes), "mesh": facts, "status": mesh.Status,
            "groups_expected": [m_steel.Name + "_Volumes", m_alu.Name + "_Volumes"],
            "inp_has_material_elsets": all(("ELSET=" in text, m_steel.Name in text,
                                            m_alu.Name in text)),
            "inp_materials": [line.strip() for line in text.splitlines()
                              if line.upper().startswith("*SOLID SECTION")]}


h.main(check)
