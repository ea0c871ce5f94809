"""The demo assembly as a FreeCAD document, shared by examples/demo_assembly.py (headless
demo), examples/OracleMesh_Demo.FCMacro (the macro version) and the GUI tests.

A steel pin (cylinder r 5, h 40) through an aluminium plate (box 100 x 60 x 10, no hole: the
pin overlaps it and wins by priority) with a cut box removing one corner of the plate. A FEM
analysis with both materials, the plate fixed at x = 0 and pulled down (1000 N) at x = 100.
"""
import FreeCAD


def face_at(obj, axis, value):
    """Name of the planar face of obj at <axis> = value (robust against face numbering)."""
    k = "xyz".index(axis)
    for i, face in enumerate(obj.Shape.Faces, start=1):
        bb = face.BoundBox
        if abs((bb.XMin, bb.YMin, bb.ZMin)[k] - value) < 1e-7 and \
                abs((bb.XMax, bb.YMax, bb.ZMax)[k] - value) < 1e-7:
            return "Face%d" % i
    raise ValueError("%s has no face at %s = %g" % (obj.Label, axis, value))


def fem_material(doc, analysis, name, card, refs):
    """A solid FEM material of the analysis with the given card, referencing refs' solids."""
    import ObjectsFem
    obj = ObjectsFem.makeMaterialSolid(doc, name)
    mat = obj.Material
    mat.update(card)
    obj.Material = mat
    obj.References = [(o, "Solid1") for o in refs]
    analysis.addObject(obj)
    return obj


STEEL = {"Name": "Steel", "YoungsModulus": "210000 MPa", "PoissonRatio": "0.30",
         "Density": "7900 kg/m^3"}
ALUMINIUM = {"Name": "Aluminium", "YoungsModulus": "70000 MPa", "PoissonRatio": "0.33",
             "Density": "2700 kg/m^3"}


def build(doc):
    """Geometry, analysis, CalculiX solver, materials and loads (no mesh yet).

    Returns (analysis, solver, pin, plate, corner)."""
    import ObjectsFem

    plate = doc.addObject("Part::Box", "Plate")
    plate.Length, plate.Width, plate.Height = 100, 60, 10
    pin = doc.addObject("Part::Cylinder", "Pin")
    pin.Radius, pin.Height = 5, 40
    pin.Placement.Base = FreeCAD.Vector(50, 30, -15)
    corner = doc.addObject("Part::Box", "CornerCut")
    corner.Length, corner.Width, corner.Height = 30, 30, 12
    # Removes x 0..20, y 40..60: a corner at the fixed end, so the loaded face stays whole
    # (FreeCAD spreads a face force by CAD face area: a partly cut face would get less load).
    corner.Placement.Base = FreeCAD.Vector(-10, 40, -1)
    doc.recompute()

    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    solver = ObjectsFem.makeSolverCalculixCcxTools(doc, "CalculiX")
    solver.AnalysisType = "static"
    solver.GeometricalNonlinearity = "linear"
    solver.WorkingDir = ""
    analysis.addObject(solver)
    fem_material(doc, analysis, "Steel", STEEL, [pin])
    fem_material(doc, analysis, "Aluminium", ALUMINIUM, [plate])
    fixed = ObjectsFem.makeConstraintFixed(doc, "FixedEnd")
    fixed.References = [(plate, face_at(plate, "x", 0))]
    analysis.addObject(fixed)
    force = ObjectsFem.makeConstraintForce(doc, "EndForce")
    force.References = [(plate, face_at(plate, "x", 100))]
    force.Force = 1000.0
    vertical = next("Edge%d" % i for i, e in enumerate(plate.Shape.Edges, start=1)
                    if abs(e.Vertexes[0].Point.z - e.Vertexes[1].Point.z) > 1e-9)
    force.Direction = (plate, [vertical])
    # FreeCAD takes the direction from the edge's line, not from the order of its vertexes:
    # ask FreeCAD which way it points, and reverse it if that is up.
    force.Reversed = False
    force.Reversed = force.DirectionVector.z > 0  # pull down (-z)
    analysis.addObject(force)
    return analysis, solver, pin, plate, corner
