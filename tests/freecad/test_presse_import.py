"""presse_asm.step imported through FreeCAD's STEP importer and meshed at the workbench's
defaults (issue 17): the recompute used to fail in the hand-off, on feature edges the core
returned that were no edge of its tets."""
import os

CAD_DIR = os.environ.get("ORACLEMESH_CAD_DIR",
                         os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                      "shared", "data", "cad"))


def test_imported_presse_meshes_at_defaults(run_freecad):
    # About a minute on an idle machine; the limit leaves room for a busy one.
    r = run_freecad("presse_import_defaults.py", {"step": os.path.join(CAD_DIR, "presse_asm.step")},
                    timeout=900)
    assert r["roots"] == ["PRESSE_ASM"] and r["solids"] == 16
    assert r["options"] == {"engine": "thesis", "order": 2, "sharp": 30.0, "cell_size": 0.0}
    assert r["valid"], r["status"]
    mesh = r["mesh"]
    assert mesh["nodes_per_volume"] == 10
    assert mesh["max_signed_volume6"] < 0  # FreeCAD's orientation
    # The compound is one part per solid: 16 volume groups, together holding every element once.
    assert len(mesh["group_sizes"]) == 16
    assert all(name.endswith("_Volumes") and n > 0 for name, n in mesh["group_sizes"].items())
    assert mesh["groups_cover_all_once"]
    # Every feature edge got its mid node (the hand-off finds each among the tets' edges).
    assert r["feature_edges"] > 4000
    assert r["feature_edge_mid_nodes"] == r["feature_edges"]
    assert r["final_check"]["subsegments_outside_material"] == 0
    print("presse at defaults in FreeCAD: %d nodes, %d tet10, %d feature edges, dihedral %.3g-%.6g deg, "
          "final check %s, %.1f s" % (mesh["nodes"], mesh["volumes"], r["feature_edges"],
                                       r["quality"]["min_dihedral_deg"], r["quality"]["max_dihedral_deg"],
                                       r["final_check"], r["seconds"]))
