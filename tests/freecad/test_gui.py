"""The workbench in the real FreeCAD GUI (under Xvfb), installed by cmake/install-workbench.sh
into a scratch HOME, on the demo document (scripts/gui_workbench.py drives it; one FreeCAD
session, judged here by several tests):

- the command opens the task panel; inputs are reordered there and meshed; groups, counts and
  per-material volumes against OpenCASCADE, for both priority orders;
- the screenshot shows the mesh in the material colours;
- Cancel during a long mesh returns within 2 s and keeps the previous mesh;
- a bad input refused by the core and a forced segfault of the core show an error, FreeCAD
  keeps running and the document is unchanged;
- double click reopens the panel; the histogram and the exports work;
- the mesh command's doCommand lines reach the console (what the macro recorder records)
  and, replayed on a new document, make the same mesh object.
"""
import os
import sys

import pytest

from gui_session import run_gui_script

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from installed import require_module  # noqa: E402


@pytest.fixture(scope="module")
def gui(tmp_path_factory):
    """Run scripts/gui_workbench.py once in the FreeCAD GUI; its measurements as a dict."""
    return run_gui_script(tmp_path_factory, "gui_workbench.py", "gui")


def test_task_panel_reorders_and_meshes(gui):
    assert gui["workbench"] == "OracleMeshWorkbench"
    assert gui["workbench_from"].endswith(os.path.join(".local", "share", "FreeCAD", "Mod",
                                                       "OracleMesh", "oraclemesh_fc"))
    assert {"OracleMesh_MeshSelection", "OracleMesh_Edit", "OracleMesh_Export",
            "OracleMesh_Histogram"} <= set(gui["commands"])
    assert gui["panel_open"] and gui["mesh_in_analysis"]
    assert gui["planar_faces_shown"] == [False, False] and gui["planar_faces_written"] is True
    assert gui["panel_rows"] == ["Pin", "Plate"]  # selection order = priority
    assert gui["new_mesh_engine"] == ["thesis", "thesis"]  # the default engine (issue 7)
    assert gui["panel_materials"] == ["Steel", "Aluminium"]  # from the FEM materials
    assert gui["rows_with_cut"] == [["CornerCut", "cut"], ["Pin", "material"],
                                    ["Plate", "material"]]
    assert gui["inputs"] == ["CornerCut", "Pin", "Plate"] and gui["cuts"] == ["CornerCut"]
    assert gui["mesh1_ok"], gui["mesh1_status"]
    assert gui["input_sizes"] == {"Pin": "cell_size=2.5 facet_size=1.5"}
    assert gui["rows_swapped"] == ["CornerCut", "Plate", "Pin"]
    assert gui["inputs_swapped"] == ["CornerCut", "Plate", "Pin"]
    assert gui["mesh2_ok"]
    names = gui["group_names"]
    for state in (gui["mesh1"], gui["mesh2"]):
        assert set(state["groups"]) == {names["pin"], names["plate"]}
        assert sum(state["groups"].values()) == state["volumes"] > 500
        assert state["feature_edges"] > 50
    # The report in the panel names the groups and the quality.
    assert names["pin"] in gui["report_html"] and "dihedral" in gui["report_html"]


def test_reordering_priorities_moves_the_overlap(gui):
    occ = gui["occ"]
    names = gui["group_names"]
    overlap = occ["pin_full"] - occ["pin_outside_plate"]  # the pin's part inside the plate
    first, second = gui["mesh1_volumes"], gui["mesh2_volumes"]
    print("pin first:  pin %.1f (OCC %.1f), plate %.1f (OCC %.1f)"
          % (first[names["pin"]], occ["pin_full"], first[names["plate"]], occ["plate_without_pin"]))
    print("plate first: pin %.1f (OCC %.1f), plate %.1f (OCC %.1f)"
          % (second[names["pin"]], occ["pin_outside_plate"], second[names["plate"]],
             occ["plate_full"]))
    # Coarse tet10 with mid nodes on the CAD: close to OpenCASCADE; the overlap (785 mm3) is
    # what moves between the materials.
    tol = 0.02 * overlap
    assert abs(first[names["pin"]] - occ["pin_full"]) < tol
    assert abs(first[names["plate"]] - occ["plate_without_pin"]) < tol
    assert abs(second[names["pin"]] - occ["pin_outside_plate"]) < tol
    assert abs(second[names["plate"]] - occ["plate_full"]) < tol


def test_screenshot_shows_the_materials(gui):
    assert os.path.getsize(gui["screenshot"]) > 10000
    assert gui["element_colours"] == gui["face_polygons"] > 0  # every drawn face coloured
    assert gui["edges_drawn"] == gui["mesh2"]["feature_edges"]
    pixels = dict(gui["colour_pixels"])
    print("colour pixels:", pixels)
    other = pixels.pop("other colours")
    assert set(pixels) == set(gui["mesh2"]["groups"])
    for group, count in pixels.items():
        assert count > 300, "material %s is not visible in %s" % (group, gui["screenshot"])
    # Saturated pixels are material colours (edges are black, the background white).
    assert other < 0.05 * sum(pixels.values()), gui["screenshot"]
    # The feature edges show: the view without their lines has far fewer dark pixels.
    dark = gui["dark_pixels"]
    print("dark pixels:", dark)
    assert dark["with_edges"] > 10 * dark["without_edges"] + 500, gui["screenshot"]


def test_extra_edges_from_the_panel(gui):
    extra = gui["extra_edges"]
    print("extra edges:", extra)
    assert extra["listed"] == ["'EdgeSketch' (all edges)", "Edge1 of 'Plate'"]
    assert "Face1 of 'Plate'" in extra["refused"]
    assert extra["after_remove"] == ["'EdgeSketch' (all edges)"]
    assert extra["mesh_ok"] and extra["property"] == [["EdgeSketch", [""]]]
    assert extra["line_edges"] >= 2
    assert abs(extra["line_covered"] - extra["line_length"]) < 1e-6 * extra["line_length"]
    assert gui["reopened_extra_edges"] == extra["after_remove"]


def test_cancel_returns_within_two_seconds_and_keeps_the_mesh(gui):
    c = gui["cancel"]
    print("cancel:", c)
    assert c["dialog_found"], "no progress dialog was shown during the long mesh"
    assert 0 <= c["seconds_to_return"] < 2.0
    assert c["mesh_kept"] and c["document_kept"]
    assert "cancelled" in c["status"]
    assert c["messages"] == []  # a cancel the user asked for is not an error box
    assert c["workers_left"] == []


def test_core_failures_show_an_error_and_change_nothing(gui):
    bad, crash = gui["bad_size"], gui["crash"]
    print("bad size:", bad["messages"])
    print("crash:", crash["messages"])
    assert not bad["ok"] and len(bad["messages"]) == 1
    assert "max_vertices" in bad["messages"][0] or "vertices" in bad["messages"][0]
    assert bad["mesh_kept"] and bad["document_kept"]
    assert not crash["ok"] and len(crash["messages"]) == 1
    assert "crashed" in crash["messages"][0] and "signal 11" in crash["messages"][0]
    assert crash["mesh_kept"] and crash["document_kept"] and crash["workers_left"] == []
    cell = gui["bad_cell"]
    assert not cell["applied"] and cell["sizes_kept"]
    assert "Facet size of 'Plate'" in cell["report"] and "abc" in cell["report"]
    assert gui["after_errors_ok"] and gui["after_errors"] == gui["mesh2"]


def test_drag_and_drop_reorders(gui):
    assert gui["rows_after_drop"] == ["CornerCut", "Pin", "Plate"]
    assert gui["role_widgets_after_drop"] == ["cut", "material", "material"]
    assert gui["rows_after_second_drop"] == ["CornerCut", "Plate", "Pin"]


def test_undo_and_preferences(gui):
    assert gui["undo"] == {"applied": 45.0, "after_undo": 30.0}
    assert gui["prefs_loaded"] == {"order": 2, "engine": "thesis"}
    assert gui["prefs_saved"]["ElementOrder"] == 1 and gui["prefs_saved"]["Preset"] == "coarse"
    assert gui["thesis_engine_enabled"] is True


def test_double_click_histogram_export(gui):
    assert gui["closed"] and gui["reopened"]
    h = gui["histogram"]
    assert h["png"] > 5000 and h["rows"] == 50 and h["highlighted"] == 10
    assert abs(h["worst"] - h["report_min"]) < 1e-6
    # The title counts what a linear axis hid; selecting the worst element zooms the view to it.
    assert h["under_one_degree"] == h["angles_under_one"]
    # The counts under 5, 10 and 15 degrees (issue 15) are the mesh's own and the core's report's.
    assert h["poor"] == h["poor_from_angles"]
    improve = h["report_improve"]
    assert [h["poor"][b] for b in ("5", "10", "15")] == [
        improve["tets_under_%s_deg" % b] for b in ("5", "10", "15")], (h["poor"], improve)
    assert "%d under 15 deg" % h["poor"]["15"] in h["poor_line"]
    zoom = h["zoom"]
    assert zoom["in_front"] and zoom["off_axis"] < 1e-4 * h["model_diagonal"]
    assert zoom["size"] < 0.5 * h["model_diagonal"]
    if zoom["ortho_height"] is not None:
        assert abs(zoom["ortho_height"] - zoom["size"]) < 1e-6 * zoom["size"]
    meshio = require_module("meshio", "python3-meshio")
    n = gui["final"]["volumes"]
    assert sorted(gui["export"]) == [".inp", ".msh", ".vtu"]
    for ext, path in gui["export"].items():
        m = meshio.read(path)
        # The VTU also has the face groups' triangles; the volumes are the tets.
        assert sum(len(c.data) for c in m.cells if c.type.startswith("tetra")) == n, ext
    inp = open(gui["export"][".inp"]).read()
    assert len(gui["final"]["groups"]) == 2
    for group in gui["final"]["groups"]:
        assert "ELSET=%s" % group in inp


def test_mesh_command_is_recorded_and_replays(gui):
    """The mesh command acts through FreeCADGui.doCommand, so FreeCAD's macro manager prints
    its lines to the console (and records them in a macro); made directly in Python, the
    object would leave no line there."""
    assert gui["console_found"], "no Python console in the main window"
    recorded = gui["recorded"]
    print("recorded:", recorded)
    made = [line for line in recorded if "oraclemesh_fc.makeMesh(" in line]
    assert made == [
        "oracle_mesh = oraclemesh_fc.makeMesh(FreeCAD.ActiveDocument, "
        "[FreeCAD.ActiveDocument.getObject('Pin'), FreeCAD.ActiveDocument.getObject('Plate')], "
        "analysis=FreeCAD.ActiveDocument.getObject('Analysis'), cell_size=0.0, element_order=2, "
        "engine='thesis', sharp_angle=30.0)"], recorded
    assert "import oraclemesh_fc" in recorded
    assert "FreeCADGui.ActiveDocument.setEdit(oracle_mesh.Name, 0)" in recorded
    # What the command made, and what its lines make on a new demo document.
    made_by_command = gui["command_mesh"]
    assert made_by_command["inputs"] == ["Pin", "Plate"]
    assert made_by_command["analysis"] == ["Analysis"]
    assert gui["replayed"] == ["import oraclemesh_fc", made[0]]
    assert gui["replayed_mesh"] == made_by_command
