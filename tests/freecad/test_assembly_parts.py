"""Compounds as one part per solid, headless: names from the STEP file, rows with their own
FEM material, name and priority, one group per part, the compound as one input
(scripts/assembly_parts.py)."""

PRESSE_PARTS = ["PLATEAU_BAS", "COLONNE", "COLONNE001", "COLONNE002", "COLONNE003",
                "PLATEAU_HAUT", "SUP-VERIN", "VERIN", "CAPTEUR_FORCE", "SUPPORT", "MATRICE",
                "SERRE_FLAN", "CORPS_AMMOVIBLE", "CORPS_FIXE", "PRT0001", "SPHERE_CN"]


def test_compound_parts(run_freecad):
    r = run_freecad("assembly_parts.py", timeout=300)
    # FreeCAD's import merges the presse into one compound; the names come from the file.
    assert r["presse"] == ["presse_asm", 16]
    assert r["presse_labels"] == PRESSE_PARTS
    assert r["unnamed_labels"] == ["presse_asm Solid1", "presse_asm Solid2"]
    # The STEP file's declared uncertainty (its largest UNCERTAINTY_MEASURE_WITH_UNIT,
    # 7.418088244970E-2 mm) reaches the job, which FreeCAD's import alone would lose; where the
    # file is not found, none is sent and the core falls back to the shapes' own tolerances.
    assert abs(r["presse_cad_uncertainty"] - 7.418088244970e-2) < 1e-9
    assert abs(r["presse_job_cad_uncertainty"] - 7.418088244970e-2) < 1e-9
    assert r["unnamed_cad_uncertainty"] == 0
    assert "cad_uncertainty" not in r["unnamed_job_keys"]

    # A Part::Compound's solids are named by its links; the FEM material of Over shows.
    assert r["rows"] == [["Pair.Solid1", "Left", ""], ["Pair.Solid2", "Right", ""],
                         ["Over", "Over", "Steel"]]
    w = r["written"]
    assert sorted(w["steel"]) == [["Over", ["Solid1"]], ["Pair", ["Solid2"]]]
    assert w["names"] == {"Pair.Solid1": "Aluminium"}
    assert w["order"] == ["Over", "Pair.Solid2", "Pair.Solid1"] and w["whole"] == []
    assert r["job_inputs"] == [["Over", 1], ["Right", 2], ["Left", 3]]
    steel = r["steel_group"]
    assert r["groups"] == [[steel, [1, 2]], ["Aluminium_Volumes", [3]]]
    # Over wins where it overlaps both boxes (5 x 6 x 6 in each).
    assert r["mesh"]["groups_cover_all_once"]
    v = r["volumes"]
    assert abs(v[steel] - (360 + 820)) < 1e-6 * 1180, v
    assert abs(v["Aluminium_Volumes"] - 820) < 1e-6 * 820, v

    j = r["joined"]
    assert j["rows"] == [["Over", "Over"], ["Pair", "Pair"]] and j["whole"] == ["Pair"]
    assert j["job_inputs"] == [["Over", 1], ["Pair", 2]]
    assert r["split_again"] == [["Over", "Over"], ["Pair.Solid1", "Left"], ["Pair.Solid2", "Right"]]
