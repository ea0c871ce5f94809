"""The OracleMesh main job, run headless by FreeCAD:

    OUT_DIR=out freecadcmd examples/demo_assembly.py

A steel pin (cylinder r 5, h 40) through an aluminium plate (box 100 x 60 x 10, no hole: the
pin overlaps it and wins by priority) with a cut box removing one corner of the plate. A FEM
analysis with both materials, the plate fixed at x = 0 and pulled down (1000 N) at x = 100,
meshed by OracleMesh (tet10, the default engine: Rule Set T) and solved by CalculiX through FreeCAD's FEM workbench.
The document is built by oraclemesh_fc.demo (shared with the macro and the GUI tests).
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
    from oraclemesh_fc.demo import build
    return makeMesh, run_calculix, build


def main():
    out = os.path.abspath(os.environ.get("OUT_DIR") or "out")
    os.makedirs(out, exist_ok=True)
    makeMesh, run_calculix, build = import_workbench()
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
    groups = {fm.getGroupName(g): len(fm.getGroupElements(g)) for g in fm.Groups
              if fm.getGroupElementType(g) == "Volume"}
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
