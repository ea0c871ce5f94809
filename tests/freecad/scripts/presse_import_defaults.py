"""presse_asm.step the way a new user meets it (issue 17): File > Import, select the imported
object, "Mesh selection with OracleMesh", Mesh, nothing changed. The GUI's STEP import (with
FreeCAD's default "merge compound") gives one Part::Feature holding the assembly as a compound
of 16 solids. Headless, Import.insert with merge=True crashes FreeCAD 0.20.2 (its importer
returns part colours of objects the merge deleted), so the script imports the assembly tree
(merge=False) and merges it as the importer does: one Part::Feature with the root's shape.
The command's own step follows: makeMesh on the selection with the preferences' options
(preferences.mesh_options, what CommandMeshSelection records), then the recompute the
panel's Mesh button does."""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def check(params):
    import FreeCAD
    import Import
    import Part
    from oraclemesh_fc import makeMesh, preferences

    doc = FreeCAD.newDocument("Presse")
    Import.insert(params["step"], doc.Name, merge=False)
    roots = [o for o in doc.Objects if not o.InList]
    merged = doc.addObject("Part::Feature", "PresseAsm")
    merged.Shape = Part.getShape(roots[0])
    doc.recompute()

    # What CommandMeshSelection.Activated does (no analysis is active).
    mesh = makeMesh(doc, [merged], **preferences.mesh_options([merged]))
    start = time.time()
    facts = h.recompute_mesh(doc, mesh)
    seconds = time.time() - start
    report = json.loads(mesh.Report)
    edges = list(mesh.FeatureEdges)
    return {
        "roots": [o.Label for o in roots],
        "solids": len(merged.Shape.Solids),
        "options": {"engine": mesh.Engine, "order": mesh.ElementOrder, "sharp": float(mesh.SharpAngle),
                    "cell_size": float(mesh.CellSize)},
        "mesh": facts,
        "valid": mesh.isValid(),
        "status": mesh.Status,
        "feature_edges": len(edges) // 2,
        "feature_edge_mid_nodes": len(mesh.FeatureEdgeMidNodes),
        "group_expected": merged.Label + "_Volumes",
        "final_check": report["thesis"]["final_check"],
        "quality": report["quality"],
        "seconds": seconds,
    }


h.main(check)
