"""Run inside the FreeCAD GUI (xvfb): the installed workbench loads, its command meshes the
selection (progress dialog, worker thread) into the active analysis, the view provider is
attached, and an error shows as a message (captured here instead of a modal box) while the
previous mesh stays."""
import json
import os
import sys
import traceback


def step(text):
    """Leave a trail: if the GUI crashes, the test shows the last step reached."""
    with open(os.environ["OMFC_RESULT"] + ".steps", "a") as f:
        f.write(text + "\n")


def check():
    # The workbench comes from FreeCAD's user Mod folder (cmake/install-workbench.sh ran in
    # this HOME), exactly as a user gets it.
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path.insert(0, here)
    import fc_harness

    import FreeCAD
    import FreeCADGui
    import ObjectsFem
    out = {"ok": True}
    step("activate workbench")
    FreeCADGui.activateWorkbench("OracleMeshWorkbench")
    out["workbench"] = FreeCADGui.activeWorkbench().name()
    out["command_registered"] = "OracleMesh_MeshSelection" in FreeCADGui.listCommands()

    step("document")
    doc = FreeCAD.newDocument("Gui")
    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    import FemGui
    FemGui.setActiveAnalysis(analysis)
    block = fc_harness.box(doc, "Block", 0, 0, 0, 20, 10, 10)
    rod = doc.addObject("Part::Cylinder", "Rod")
    rod.Radius, rod.Height = 3, 20
    rod.Placement.Base = FreeCAD.Vector(10, 5, -5)
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(rod)
    FreeCADGui.Selection.addSelection(block)  # selection order = priority: the rod wins
    step("run command")
    FreeCADGui.runCommand("OracleMesh_MeshSelection")
    step("command done")
    meshes = [o for o in doc.Objects if o.isDerivedFrom("Fem::FemMeshObjectPython")]
    m = meshes[0]
    out["mesh_inputs"] = [o.Name for o in m.Inputs]
    out["mesh_in_analysis"] = m in analysis.Group
    out["mesh_volumes"] = m.FemMesh.VolumeCount
    out["mesh_valid"] = m.isValid()
    out["view_provider"] = type(m.ViewObject.Proxy).__name__
    out["icon"] = m.ViewObject.Proxy.getIcon()

    step("error path")
    shown = []
    import oraclemesh_fc.mesh_object as mo
    mo.show_error = shown.append  # a modal box would wait for a click
    m.Inputs = []
    doc.recompute()
    out["error_shown"] = shown
    out["mesh_kept"] = m.FemMesh.VolumeCount == out["mesh_volumes"]
    step("done")
    return out


try:
    result = check()
except BaseException:
    result = {"ok": False, "traceback": traceback.format_exc()}
with open(os.environ["OMFC_RESULT"], "w") as f:
    json.dump(result, f, indent=1)
os._exit(0)
