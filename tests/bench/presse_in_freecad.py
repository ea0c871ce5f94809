"""presse_asm.step meshed in FreeCAD the way the GUI command does it, at the defaults: where
the time goes. Run with freecadcmd (the workbench and the core from this tree's build):

    ORACLEMESH_BUILD_DIR=build PRESSE_JOB_OUT=/tmp/presse_job.json \
        freecadcmd tests/bench/presse_in_freecad.py

The assembly is imported as File > Import does (the workbench's `import_assembly`, which
headless builds FreeCAD's merged compound from the unmerged tree), and the mesh command is given
the STEP file as the GUI's is, so the job carries the file's declared uncertainty (0.074 mm) as
its contact tolerance. The mesh object is made with the preferences' options (what
"Mesh selection with OracleMesh" records), then recomputed under cProfile. Prints the wall
time, the core's seconds per phase, each interface's area against OpenCASCADE's common faces
(issue 19: within 1 %; the part beyond the contact tolerance is the bonded wedge beside a
tangent contact), the Python functions that took longest, and (with
PRESSE_JOB_OUT) writes the job the workbench sent, so the CLI can rerun it:
`build/oraclemesh /tmp/presse_job.json`."""
import cProfile
import io
import json
import os
import pstats
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build")), "python"))
sys.path.insert(0, os.path.join(REPO, "Mod", "OracleMesh"))
sys.path.insert(0, os.path.join(REPO, "tests", "freecad"))
STEP = os.path.join(os.environ.get("ORACLEMESH_CAD_DIR", os.path.join(REPO, "..", "shared", "data", "cad")),
                    "presse_asm.step")

import FreeCAD  # noqa: E402
from fc_harness import common_face_areas  # noqa: E402
from oraclemesh_fc import makeMesh, preferences  # noqa: E402
from oraclemesh_fc.job import build_job  # noqa: E402
from oraclemesh_fc.step_labels import import_assembly  # noqa: E402

doc = FreeCAD.newDocument("Presse")
presse = import_assembly(doc, STEP)
mesh = makeMesh(doc, [presse], step_file=STEP, **preferences.mesh_options([presse]))
job = build_job(mesh)[0]
if os.environ.get("PRESSE_JOB_OUT"):
    with open(os.environ["PRESSE_JOB_OUT"], "w") as f:
        json.dump(job, f)

profile = cProfile.Profile()
start = time.time()
profile.enable()
doc.recompute()
profile.disable()
print("recompute: %.1f s wall; %s" % (time.time() - start, mesh.Status[:200]))
report = json.loads(mesh.Report) if mesh.Report else {}
seconds = report.get("seconds", {})
print("contact tolerance: %s; %s tets; min dihedral %s" % (report.get("contact_tolerance"), report.get("counts", {}).get("tets"),
                                                         report.get("quality", {}).get("min_dihedral_deg")))
print("core seconds per phase:", ", ".join("%s %.1f" % kv for kv in sorted(seconds.items()) if kv[1] >= 0.1))
improve = report.get("improve", {})
print("tets under 5/10/15 degrees after the improvement stage: %s/%s/%s (%s near a small input angle); "
      "self-check %s" % (improve.get("tets_under_5_deg"), improve.get("tets_under_10_deg"),
                         improve.get("tets_under_15_deg"), improve.get("tets_under_15_deg_near_small_input_angle"),
                         "passed" if report.get("self_check", {}).get("ok") else report.get("self_check", {}).get("problems")))
print("curved mid nodes kept straight (second_order_straight_fallbacks): %s"
      % report.get("second_order_straight_fallbacks"))
if report.get("interfaces"):
    occt = common_face_areas(job, report)
    print("interfaces: mesh area, OpenCASCADE's common faces (mm^2), deviation; beyond the contact "
          "tolerance, deviation without it")
    for interface in report["interfaces"]:
        area, beyond, common = interface["area"], interface["beyond_contact_area"], occt[interface["name"]]
        print("  %-40s %10.2f %10.2f %+7.2f %%   %8.2f %+7.2f %%" % (
            interface["name"], area, common, 100 * (area - common) / common, beyond,
            100 * (area - beyond - common) / common))
text = io.StringIO()
pstats.Stats(profile, stream=text).sort_stats("cumulative").print_stats(12)
print(text.getvalue())
