"""The OracleMesh main job, run headless by FreeCAD:

    OUT_DIR=out freecadcmd examples/demo_assembly.py

A steel pin (cylinder r 5, h 40) through an aluminium plate (box 100 x 60 x 10, no hole: the
pin overlaps it and wins by priority) with a cut box removing one corner of the plate. A FEM
analysis with both materials, the plate fixed at x = 0 and pulled down (1000 N) at x = 100,
meshed by OracleMesh (tet10) and solved by CalculiX through FreeCAD's FEM workbench.
Writes to OUT_DIR (default ./out): demo.FCStd, mesh.vtu, mesh.inp, report.json, ccx/ (the
CalculiX run), and prints a summary. Exit code 0 on success, 1 with a message on failure.
"""
import json
import os
import sys
import time
import traceback

import FreeCAD

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def import_workbench():
    """oraclemesh_fc from FreeCAD's Mod folder (cmake/install-workbench.sh), else the repo."""
    try:
        import oraclemesh_fc  # noqa: F401
        import oraclemesh  # noqa: F401
    except ImportError:
        build = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build"))
        sys.path[:0] = [os.path.join(REPO, "Mod", "OracleMesh"), os.path.join(build, "python")]
        for name in [m for m in sys.modules if m.startswith("oraclemesh")]:
            del sys.modules[name]
    from oraclemesh_fc import makeMesh
    from oraclemesh_fc.calculix import run_calculix
    return makeMesh, run_calculix


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
    import ObjectsFem
    obj = ObjectsFem.makeMaterialSolid(doc, name)
    mat = obj.Material
    mat.update(card)
    obj.Material = mat
    obj.References = [(o, "Solid1") for o in refs]
    analysis.addObject(obj)
    return obj


def build(doc):
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
    fem_material(doc, analysis, "Steel", {
        "Name": "Steel", "YoungsModulus": "210000 MPa", "PoissonRatio": "0.30",
        "Density": "7900 kg/m^3"}, [pin])
    fem_material(doc, analysis, "Aluminium", {
        "Name": "Aluminium", "YoungsModulus": "70000 MPa", "PoissonRatio": "0.33",
        "Density": "2700 kg/m^3"}, [plate])
    fixed = ObjectsFem.makeConstraintFixed(doc, "FixedEnd")
    fixed.References = [(plate, face_at(plate, "x", 0))]
    analysis.addObject(fixed)
    force = ObjectsFem.makeConstraintForce(doc, "EndForce")
    force.References = [(plate, face_at(plate, "x", 100))]
    force.Force = 1000.0
    vertical = next("Edge%d" % i for i, e in enumerate(plate.Shape.Edges, start=1)
                    if abs(e.Vertexes[0].Point.z - e.Vertexes[1].Point.z) > 1e-9)
    force.Direction = (plate, [vertical])
    force.Reversed = plate.Shape.getElement(vertical).Vertexes[1].Point.z > \
        plate.Shape.getElement(vertical).Vertexes[0].Point.z  # point down (-z)
    analysis.addObject(force)
    return analysis, solver, pin, plate, corner


def main():
    out = os.path.abspath(os.environ.get("OUT_DIR") or "out")
    os.makedirs(out, exist_ok=True)
    makeMesh, run_calculix = import_workbench()
    doc = FreeCAD.newDocument("OracleMeshDemo")
    analysis, solver, pin, plate, corner = build(doc)

    report_path = os.path.join(out, "report.json")
    mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[corner], name="OracleMesh",
                    cell_size=4.0, facet_distance=0.1, element_order=2,
                    output={"files": [os.path.join(out, "mesh.vtu"), os.path.join(out, "mesh.inp")],
                            "report": report_path})
    t0 = time.time()
    doc.recompute()
    mesh_seconds = time.time() - t0
    if not mesh.isValid() or mesh.FemMesh.VolumeCount == 0:
        raise RuntimeError(mesh.Status or "meshing failed")

    t0 = time.time()
    result, ccx_inp = run_calculix(analysis, solver, os.path.join(out, "ccx"))
    ccx_seconds = time.time() - t0
    max_disp = max(result.DisplacementLengths)
    doc.saveAs(os.path.join(out, "demo.FCStd"))

    report = json.loads(mesh.Report)
    fm = mesh.FemMesh
    groups = {fm.getGroupName(g): len(fm.getGroupElements(g)) for g in fm.Groups}
    report["fem"] = {"groups": groups, "max_displacement_mm": max_disp,
                     "ccx_input": ccx_inp, "seconds": {"mesh_in_freecad": mesh_seconds,
                                                       "calculix": ccx_seconds}}
    with open(report_path, "w") as f:
        json.dump(report, f, indent=1, sort_keys=True)

    quality = report.get("quality", {})
    print("\nOracleMesh demo: steel pin through an aluminium plate, one corner cut away")
    print("  mesh: %d nodes, %d tet10" % (fm.NodeCount, fm.VolumeCount))
    for name, count in groups.items():
        print("  tets in %-22s %d" % (name, count))
    print("  dihedral angles: min %.1f deg, max %.1f deg"
          % (quality.get("min_dihedral_deg", float("nan")),
             quality.get("max_dihedral_deg", float("nan"))))
    seconds = report.get("seconds", {})
    print("  seconds per phase: " + ", ".join("%s %.2f" % (k, v)
                                              for k, v in sorted(seconds.items())))
    print("  seconds: meshing in FreeCAD %.2f, CalculiX (write, solve, read) %.2f"
          % (mesh_seconds, ccx_seconds))
    print("  max displacement: %.4f mm" % max_disp)
    missing = [p for p in mesh.OutputFiles if not os.path.exists(p)]
    if missing:
        raise RuntimeError("the core did not write %s" % ", ".join(missing))
    print("  written: %s" % ", ".join(sorted(os.listdir(out))))


try:
    main()
except Exception:
    sys.stderr.write("demo_assembly failed:\n" + traceback.format_exc())
    sys.stderr.flush()
    os._exit(1)  # freecadcmd would exit 0 after an uncaught exception
sys.stdout.flush()
os._exit(0)
