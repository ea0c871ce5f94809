"""presse_asm.step meshed in FreeCAD the way the GUI command does it, at the defaults: where
the time goes. Run with freecadcmd (the workbench and the core from this tree's build):

    ORACLEMESH_BUILD_DIR=build PRESSE_JOB_OUT=/tmp/presse_job.json \
        freecadcmd tests/bench/presse_in_freecad.py

Headless, Import.insert with merge=True crashes FreeCAD 0.20.2, so the assembly tree is read
with merge=False and merged into one Part::Feature holding the root's compound, as the GUI's
STEP import gives it. The mesh object is made with the preferences' options (what
"Mesh selection with OracleMesh" records), then recomputed under cProfile. Prints the wall
time, the core's seconds per phase, the Python functions that took longest, and (with
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
STEP = os.path.join(os.environ.get("ORACLEMESH_CAD_DIR", os.path.join(REPO, "..", "shared", "data", "cad")),
                    "presse_asm.step")

import FreeCAD  # noqa: E402
import Import  # noqa: E402
import Part  # noqa: E402
from oraclemesh_fc import makeMesh, preferences  # noqa: E402
from oraclemesh_fc.job import build_job  # noqa: E402

doc = FreeCAD.newDocument("Presse")
Import.insert(STEP, doc.Name, merge=False)
root = [o for o in doc.Objects if not o.InList][0]
presse = doc.addObject("Part::Feature", "PresseAsm")
presse.Shape = Part.getShape(root)
doc.recompute()
mesh = makeMesh(doc, [presse], **preferences.mesh_options([presse]))
if os.environ.get("PRESSE_JOB_OUT"):
    with open(os.environ["PRESSE_JOB_OUT"], "w") as f:
        json.dump(build_job(mesh)[0], f)

profile = cProfile.Profile()
start = time.time()
profile.enable()
doc.recompute()
profile.disable()
print("recompute: %.1f s wall; %s" % (time.time() - start, mesh.Status[:200]))
seconds = json.loads(mesh.Report).get("seconds", {}) if mesh.Report else {}
print("core seconds per phase:", ", ".join("%s %.1f" % kv for kv in sorted(seconds.items()) if kv[1] >= 0.1))
text = io.StringIO()
pstats.Stats(profile, stream=text).sort_stats("cumulative").print_stats(12)
print(text.getvalue())
