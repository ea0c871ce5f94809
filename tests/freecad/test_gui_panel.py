"""The task panel in FreeCAD's default combo view width and the traps of issue 17, in the real
FreeCAD GUI under Xvfb (scripts/gui_panel.py drives one FreeCAD session; each test judges its
section of it)."""
import json
import re

import pytest

from gui_session import run_gui_script


@pytest.fixture(scope="module")
def gui(tmp_path_factory):
    return run_gui_script(tmp_path_factory, "gui_panel.py", "gui_panel")


def part(gui, name):
    r = gui[name]
    assert "error" not in r, r["error"]
    return r


def test_panel_fits_the_default_combo_view(gui):
    r = part(gui, "layout")
    print("combo view %d px, viewport %d px, form %d px; checked %d texts"
          % (r["combo_width"], r["viewport_width"], r["form_width"], len(r["checked"])))
    assert r["combo_width"] == 264
    assert not r["horizontal_scroll"]
    # Every group box, label and button, the dialog's OK and Cancel among them.
    assert {"OK", "Cancel", "Mesh", "Apply", "Add selected", "Cell size",
            "Inputs, highest priority first"} <= set(r["checked"])
    assert r["problems"] == []
    for name, table in r["tables"].items():
        assert table["visible_rows"] >= 5, (name, table)
        assert all(h <= table["default_row"] for h in table["row_heights"]), (name, table)


def test_every_option_has_a_tooltip(gui):
    r = part(gui, "layout")
    assert r["options"] > 15
    assert r["without_tooltip"] == []


def test_cut_in_the_last_row_is_a_warning(gui):
    r = part(gui, "cut_last")
    assert r["rows"][-1] == ["CornerCut", "cut"]
    text = "cut 'CornerCut' is below every input: it removes nothing; move it up"
    assert r["panel_warning"] == text
    assert r["applied"] and text in r["report"]
    assert r["rows_moved"][0] == ["CornerCut", "cut"] and r["warning_after_move"] == ""
    assert r["layout_with_warning_problems"] == []


def test_automatic_shows_the_sizes_the_core_uses(gui):
    r = part(gui, "automatic")
    assert r["ok"], r["status"]
    assert r["messages"] == []
    default = r["criteria"]["default"]
    print("shown:", r["shown"])
    print("core: diagonal %.4f, default %s" % (r["bbox_diagonal"], default))
    assert r["shown"]["cell_size"] == "automatic (%.4g)" % default["cell_size"]
    assert r["shown"]["facet_distance"] == "automatic (%.4g)" % default["facet_distance"]
    assert r["delegate"] == "AutomaticDelegate"
    for label, shown in r["shown"]["materials"].items():
        core = r["criteria"]["materials"][str(r["materials"][label])]
        for key, text in shown.items():
            assert text == "%.4g" % core[key], (label, key, text, core[key])
    # The pin's own cell size is its own; its other criteria are the defaults, not derived
    # from its cell size (the core's rule).
    assert r["criteria"]["materials"][str(r["materials"]["Pin"])]["cell_size"] == 5.0
    assert r["shown"]["materials"]["Pin"]["facet_size"] == "%.4g" % default["facet_size"]
    # Meshed, the mesh alone is shown.
    assert r["inputs_visible"] == [False, False, False]


def test_time_shown_is_the_wall_time(gui):
    r = part(gui, "automatic")
    shown = float(re.search(r"Meshed in ([0-9.]+) s", r["report"]).group(1))
    print("shown %.1f s, panel.mesh() took %.2f s, phases %s" % (shown, r["wall_seconds"],
                                                               r["phase_seconds"]))
    assert shown <= r["wall_seconds"] + 0.05
    assert shown >= 0.5 * r["wall_seconds"] - 0.1


def test_ok_without_change_keeps_the_mesh_untouched(gui):
    r = part(gui, "untouched")
    assert r["closed"]
    assert not r["touched_before"]
    assert not r["touched_after_ok"] and not r["touched_after_second_ok"]
    assert r["materials_touched"] == []
    assert r["meshed_on_recompute"] == 0 and r["mesh_kept"]
    assert r["changed_written"] == [40.0, True]


def test_failure_in_the_handoff_is_a_message_status_and_report(gui):
    r = part(gui, "failure")
    meshed = r["meshed"]
    print("failure on a meshed object:", meshed["messages"])
    assert not meshed["ok"] and not meshed["valid"]
    assert len(meshed["messages"]) == 1
    message = meshed["messages"][0]
    assert "a feature edge of the core is no edge of its tets" in message
    assert "the previous mesh is kept" in message
    assert meshed["status"] == message
    assert message in meshed["report"]
    assert meshed["mesh_kept"]
    first = r["first"]
    print("failure of a first mesh:", first["messages"])
    assert not first["ok"] and first["volumes"] == 0
    assert len(first["messages"]) == 1 and first["status"] == first["messages"][0]
    assert "no edge of its tets" in first["status"] and "previous mesh" not in first["status"]
    assert first["status"] in first["report"]
    assert first["inputs_visible_after_command"] == [True, True]
    assert first["inputs_visible"] == [True, True]


def test_active_analysis_of_another_document_is_ignored(gui):
    r = part(gui, "other_doc")
    assert r["command_error"] is None and r["messages"] == []
    assert r["meshes_in_other"] == 1 and r["panel_on_it"]
    assert not r["in_analysis"] and r["analysis_group_doc"] == ["Demo"]
    assert "is in document 'Demo'" in r["make_mesh_error"]
    assert r["objects_added_by_refused_make_mesh"] == 0


def test_refused_object_says_what_it_is(gui):
    r = part(gui, "refused")
    assert len(r["messages"]) == 1, r["messages"]
    message = r["messages"][0]
    assert "'Plane' (Part::Plane) is a face, not a solid" in message
    assert "solids, compounds of solids" in message and "Mesh objects" in message
    assert r["objects"] == ["Part::Plane"]


def test_interfaces_table_sets_the_pairs(gui):
    r = part(gui, "interfaces")
    print("pairs %s kinds %s default %s; after contact: %s, stored %s, face groups %s"
          % (r["pairs_shown"], r["kinds_shown"], r["default_shown"], r["report_kinds"],
             r["stored"], r["face_groups"]))
    # The pairs of the last mesh, all bonded until set.
    assert r["pairs_shown"] == ["Pin - Plate"] and r["kinds_shown"] == ["bonded"]
    assert r["default_shown"] == "bonded" and not r["note_before"]
    assert r["choices"] == ["bonded", "tied", "contact", "separate"]
    assert r["ok"] and r["messages"] == []
    assert json.loads(r["stored"]) == {"pairs": [{"between": ["Pin", "Plate"], "kind": "contact"}]}
    assert r["report_kinds"] == {"Pin - Plate": "contact"}
    # Split: both sides of the interface are surfaces of the mesh.
    assert {"Interface_Pin_Plate", "Interface_Plate_Pin"} <= set(r["face_groups"])
    assert r["kinds_after_mesh"] == ["contact"] and r["kinds_reopened"] == ["contact"]
    assert not r["touched_after_ok"]
    assert json.loads(r["stored_with_default"]) == {
        "default": "tied", "pairs": [{"between": ["Pin", "Plate"], "kind": "contact"}]}
