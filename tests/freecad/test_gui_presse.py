"""The FEM user's assembly path in the real FreeCAD GUI (under Xvfb), on presse_asm.step
(scripts/gui_presse.py drives it; one FreeCAD session, judged here by several tests):

- FreeCAD's own STEP import gives one compound of 16 solids; the mesh command at the
  defaults (ContactTolerance 0.6 mm and Fineness very coarse, as in the macro) lists one row
  per solid, named as the STEP file names the parts, and meshes it into one volume group per
  solid; the hand-off gives every feature edge its mid node;
- the screenshot shows at least 10 part colours and no selection highlight;
- examples/OracleMesh_Presse.FCMacro makes the same mesh, and CalculiX solves it: the ram is
  pushed down and the base's reaction balances the force;
- the panel's rows per solid: a FEM material referencing one solid, a name for another, one
  solid moved to the top, the compound treated as one input and split again.
"""
import os

import pytest

from gui_session import run_gui_script

PARTS = ["PLATEAU_BAS", "COLONNE", "COLONNE001", "COLONNE002", "COLONNE003", "PLATEAU_HAUT",
         "SUP-VERIN", "VERIN", "CAPTEUR_FORCE", "SUPPORT", "MATRICE", "SERRE_FLAN",
         "CORPS_AMMOVIBLE", "CORPS_FIXE", "PRT0001", "SPHERE_CN"]


@pytest.fixture(scope="module")
def presse(tmp_path_factory):
    return run_gui_script(tmp_path_factory, "gui_presse.py", "gui_presse", timeout=1800)  # two presse meshes at the defaults, slow on a loaded machine


def test_imported_assembly_meshes_at_defaults_one_group_per_solid(presse):
    assert presse["imported"] == ["Part::Feature", "presse_asm", 16]
    name = presse["rows"][0][0].split(".")[0]
    assert presse["rows"] == [["%s.Solid%d" % (name, k), label]
                              for k, label in enumerate(PARTS, start=1)]
    assert presse["table_labels"] == PARTS
    assert presse["mesh_ok"], presse["status"]
    assert presse["messages"] == []
    print("GUI mesh: %s in %.0f s" % (presse["status"], presse["mesh_seconds"]))
    assert sorted(presse["groups"]) == sorted(p + "_Volumes" for p in PARTS)
    assert all(n > 0 for n in presse["groups"].values())
    assert sum(presse["groups"].values()) == presse["mesh"]["volumes"]
    assert presse["groups_cover_all_once"]


def test_imported_assembly_hand_off_at_defaults(presse):
    # The recompute used to fail in the hand-off, on feature edges the core returned that
    # were no edge of its tets (issue 17).
    assert presse["options"] == {"engine": "thesis", "order": 2, "sharp": 30.0, "cell_size": 0.0}
    # A new mesh object's sizes follow the geometry (issue 16); the session picks the macro's
    # coarser fineness in the panel (see the macro why).
    assert presse["fineness_default"] == "moderate"
    assert presse["fineness_chosen"] == "very coarse"
    assert presse["nodes_per_volume"] == 10
    assert presse["max_signed_volume6"] < 0  # FreeCAD's orientation
    assert presse["feature_edges"] > 4000
    assert presse["feature_edge_mid_nodes"] == presse["feature_edges"]
    assert presse["final_check"]["subsegments_outside_material"] == 0
    # FreeCAD's STEP import drops the file's declared uncertainty; the workbench finds the file
    # (as for the part names) and sends it, so the GUI's default bonds what the CLI on the same
    # file bonds: its largest UNCERTAINTY_MEASURE_WITH_UNIT, 7.418088244970E-2 mm. The session
    # sets ContactTolerance 0.6 mm (the macro's; see there why), which the job then carries.
    assert abs(presse["job_cad_uncertainty"] - 7.418088244970e-2) < 1e-9
    assert presse["contact_tolerance"] == {"value": 0.6, "from": "job"}, presse["contact_tolerance"]
    print("presse at defaults in the GUI: %d nodes, %d tet10, %d feature edges, dihedral %.3g-%.6g "
          "deg, final check %s" % (presse["mesh"]["nodes"], presse["mesh"]["volumes"],
                                   presse["feature_edges"], presse["quality"]["min_dihedral_deg"],
                                   presse["quality"]["max_dihedral_deg"], presse["final_check"]))


@pytest.mark.xfail(strict=True, reason=(
    "issue 19: at fineness very coarse with the clearances under 0.6 mm bonded (the same job by "
    "the CLI, 2026-12-06, tangent cusps merged), 8 of 12 are off by -3.5 to +17.4 %: the faces "
    "within 0.6 mm that the fuzzy common leaves out (CORPS_FIXE-PRT0001, a nut's 30-degree chamfer "
    "over a face: +17.4 %; CAPTEUR_FORCE-CORPS_FIXE +4.0 %, CORPS_AMMOVIBLE-SPHERE_CN +3.1 %), the "
    "bonded clearances (SUPPORT-MATRICE, 0.5 mm: -3.5 %; MATRICE-SERRE_FLAN, 0.22 mm, and its "
    "tangent ring: +2.7 %) and chords at this fineness (three plane contacts -1.3 to +1.2 %)"))
def test_interfaces_are_the_common_faces_of_the_parts(presse):
    # Issue 19: each interface of the imported assembly at the defaults is a Face group of the
    # FemMesh whose area is within 1 % of OpenCASCADE's (the higher-priority part's faces inside
    # or on the other part: common faces where parts touch, the overlap's wall where they do not).
    areas = presse["interface_areas"]
    print("interfaces (mesh, OpenCASCADE) mm^2:", areas)
    assert len(areas) >= 12, areas  # 12 part pairs touch or overlap in presse_asm.step
    off = {name: (mesh, occt) for name, (mesh, occt, _) in areas.items()
           if mesh is None or abs(mesh - occt) > 0.01 * occt}
    assert not off, off


def test_screenshot_shows_the_part_colours_without_highlight(presse):
    assert os.path.getsize(presse["screenshot"]) > 10000
    assert presse["palette_size"] >= 16
    assert presse["selection"] == []
    assert presse["faces_coloured"] > 1000
    pixels = presse["palette_pixels"]
    print("pixels per palette colour:", pixels, "highlight:", presse["highlight_pixels"])
    assert sum(count > 50 for count in pixels) >= 10, presse["screenshot"]
    assert presse["highlight_pixels"] < 100, presse["screenshot"]


def test_macro_makes_the_same_mesh(presse):
    macro = presse["macro"]
    print("macro: %s in %.0f s" % (macro.get("status"), macro["seconds"]))
    assert macro.get("valid"), macro.get("error") or macro.get("status")
    assert macro["parts"] == PARTS
    assert macro["mesh"] == presse["mesh"]  # same nodes, same elements
    # Cast iron for the two plates, steel for every other solid: FreeCAD's CalculiX writer
    # takes one group per FEM material.
    assert len(macro["groups"]) == 2 and sum(macro["groups"].values()) == macro["mesh"]["volumes"]


# The presse mesh still has tets flat to 1e-8 degrees; CalculiX refuses one whose printed
# coordinates turn it over ("nonpositive jacobian"). tests/bench/inp_orientation.py lists them.
def test_calculix_solves_the_macro_analysis(presse):
    macro = presse["macro"]
    assert "error" not in macro, macro.get("error")
    print("CalculiX: max displacement %.4f mm, loaded face mean uy %.4f mm, reaction %.1f N of "
          "%.1f N" % (macro["max_displacement"], macro["loaded_face_mean_uy"], macro["reaction"],
                      macro["force"]))
    assert macro["loaded_face_mean_uy"] < 0  # pushed down, as the macro says
    assert 0 < macro["max_displacement"] < 1.0
    assert abs(macro["reaction"] - macro["force"]) < 0.02 * macro["force"]


def test_rows_per_solid_materials_names_priorities(presse):
    name = presse["rows"][0][0].split(".")[0]
    written = presse["rows_written"]
    assert written["bronze_references"] == [[name, ["Solid3", "Solid16"]]]
    assert written["names"] == {"%s.Solid5" % name: "Rubber"}
    assert written["order"] == ["%s.Solid8" % name, "%s.Solid1" % name, "%s.Solid2" % name]
    assert written["job_inputs"] == ["VERIN", "PLATEAU_BAS", "COLONNE"]
    assert written["labels_kept"] == "COLONNE001"
    groups = dict((g, ids) for g, ids in written["groups"])
    bronze = [g for g in groups if g.startswith("Bronze")]
    assert len(bronze) == 1 and len(groups[bronze[0]]) == 2  # COLONNE001 and SPHERE_CN
    assert len(groups["Rubber_Volumes"]) == 1 and "COLONNE003_Volumes" not in groups
    assert len(groups) == 15


def test_compound_as_one_input_and_split_again(presse):
    name = presse["rows"][0][0].split(".")[0]
    assert presse["whole_rows"] == [[name, "presse_asm"]]
    whole = presse["whole"]
    assert whole["whole_inputs"] == [name]
    assert whole["job_inputs"] == [["presse_asm", 1]]
    assert len(whole["groups"]) == 1 and whole["groups"][0][1] == [1]
    assert sorted(presse["split_again"]) == sorted(PARTS)
