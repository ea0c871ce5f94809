"""The workbench's interface settings (oraclemesh_fc/interfaces.py) and what its CalculiX hook
warns about (ccx_interfaces.step_warnings), without FreeCAD: the task panel's rewrite of a
setting keeps what the panel does not show, and contact with a step it needs is said."""
import json
import os
import sys
import types

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# The package's __init__ imports FreeCAD; these two modules do not: reach them through a bare
# package module (no __init__ run), taken out of sys.modules again afterwards.
_saved = {k: sys.modules.pop(k) for k in list(sys.modules) if k.split(".")[0] == "oraclemesh_fc"}
_package = types.ModuleType("oraclemesh_fc")
_package.__path__ = [os.path.join(REPO, "Mod", "OracleMesh", "oraclemesh_fc")]
sys.modules["oraclemesh_fc"] = _package
try:
    from oraclemesh_fc import ccx_interfaces, interfaces  # noqa: E402
finally:
    for _name in [k for k in sys.modules if k.split(".")[0] == "oraclemesh_fc"]:
        del sys.modules[_name]
    sys.modules.update(_saved)


def test_panel_kinds_keep_friction_and_master_while_they_apply():
    old = interfaces.normalized({"pairs": [
        {"between": ["Pin", "Plate"], "kind": "contact", "friction": 0.2, "master": "Plate"},
        {"between": ["Bolt", "Nut"], "kind": "tied"}]})
    # Still a contact: friction and master stay; a pair the last mesh did not list stays too.
    same = interfaces.with_kinds(old, "bonded", {("Pin", "Plate"): "contact"})
    assert same == old
    # Tied: the friction goes (contact only), the master stays.
    tied = interfaces.with_kinds(old, "bonded", {("Pin", "Plate"): "tied"})
    assert tied["pairs"][0] == {"between": ["Pin", "Plate"], "kind": "tied", "master": "Plate"}
    # Bonded like the default, with nothing else set: the pair is left out.
    plain = interfaces.with_kinds(interfaces.normalized({"pairs": [
        {"between": ["Pin", "Plate"], "kind": "contact"}]}), "bonded", {("Pin", "Plate"): "bonded"})
    assert plain == {}
    assert interfaces.to_text(plain) == ""
    # A default other than bonded is stored; pairs that follow it are not.
    tied_default = interfaces.with_kinds({}, "tied", {("Pin", "Plate"): "tied"})
    assert tied_default == {"default": "tied"}
    assert interfaces.kind_between(tied_default, "Plate", "Pin") == "tied"


def test_parts_may_be_objects_and_text_round_trips():
    pin, plate = types.SimpleNamespace(Label="Pin"), types.SimpleNamespace(Label="Plate")
    settings = interfaces.normalized({"pairs": [{"between": [pin, plate], "kind": "contact",
                                                 "master": plate}]})
    assert settings["pairs"][0]["between"] == ["Pin", "Plate"]
    assert settings["pairs"][0]["master"] == "Plate"
    assert interfaces.from_text(interfaces.to_text(settings), "Interfaces") == settings


@pytest.mark.parametrize("settings, words", [
    ({"pairs": [{"between": ["A", "A"], "kind": "tied"}]}, "names 'A' twice"),
    ({"pairs": [{"between": ["A", "B"], "kind": "tied"}, {"between": ["B", "A"], "kind": "contact"}]},
     "pairs[1] is the pair of interfaces.pairs[0] again"),
    ({"pairs": [{"between": ["A", "B"], "kind": "contact", "friction": -1}]}, "friction = -1"),
    ({"pairs": [{"between": ["A", "B"], "kind": "separate", "master": "A"}]}, "'tied' and 'contact' only"),
    ({"pairs": [{"between": ["A", "B"], "kind": "contact", "master": "C"}]}, "master = 'C' is not one"),
    ({"pairs": [{"between": ["A", "B"]}]}, "has no 'kind'"),
    ({"default": "glued"}, "default = 'glued' is not an interface kind"),
    ({"pair": []}, "unknown key(s) 'pair'"),
])
def test_bad_settings_name_the_key(settings, words):
    with pytest.raises(interfaces.InterfaceSettingsError) as e:
        interfaces.normalized(settings)
    assert words in str(e.value)


def test_contact_step_warnings():
    report = {"interfaces": [{"parts": ["Pin", "Plate"], "kind": "contact",
                              "constraint": "Contact_Pin_Plate"}]}
    mesh = types.SimpleNamespace(Report=json.dumps(report))
    default = types.SimpleNamespace(AnalysisType="static", IterationsUserDefinedIncrementations=False)
    assert ccx_interfaces.step_warnings(mesh, default) == []
    direct = types.SimpleNamespace(AnalysisType="static", IterationsUserDefinedIncrementations=True)
    assert "DIRECT" in ccx_interfaces.step_warnings(mesh, direct)[0]
    frequency = types.SimpleNamespace(AnalysisType="frequency", IterationsUserDefinedIncrementations=False)
    assert "'frequency'" in ccx_interfaces.step_warnings(mesh, frequency)[0]
    tied = types.SimpleNamespace(Report=json.dumps({"interfaces": [dict(
        report["interfaces"][0], kind="tied")]}))
    assert ccx_interfaces.step_warnings(tied, frequency) == []


def test_contact_step_may_cut_back_below_calculixs_default_minimum():
    # FreeCAD's static step at its defaults: *STATIC (with or without a solver) and an empty
    # data line, CalculiX's times (smallest increment 1e-5 of the step).
    for static in ("*STATIC", "*STATIC, SOLVER=SPOOLES"):
        step = "*STEP\n%s\n\n\n*BOUNDARY\nFixed,1\n" % static
        assert ccx_interfaces.step_with_contact_increments(step, True) == (
            "*STEP\n%s\n1.0,1.0,1e-9,1.0\n\n*BOUNDARY\nFixed,1\n" % static)
        assert ccx_interfaces.step_with_contact_increments(step, False) == step
    # Times the user set, and other analyses, are left as they are.
    for step in ("*STEP\n*STATIC\n0.1,2.0\n\n", "*STEP\n*STATIC, DIRECT\n0.5,1.0\n\n",
                 "*STEP\n*COUPLED TEMPERATURE-DISPLACEMENT\n1.0,1.0\n\n", "*STEP\n*FREQUENCY\n10\n\n"):
        assert ccx_interfaces.step_with_contact_increments(step, True) == step


def test_oriented_key_tells_the_two_sides_apart():
    assert ccx_interfaces.oriented_key(3, 1, 2) == ccx_interfaces.oriented_key(1, 2, 3)
    assert ccx_interfaces.oriented_key(2, 3, 1) == (1, 2, 3)
    assert ccx_interfaces.oriented_key(1, 3, 2) != ccx_interfaces.oriented_key(1, 2, 3)


def test_the_stiffer_part_is_master():
    moduli = {"Pin": 210000.0, "Plate": 70000.0, "Bolt": 210000.0, "Nut": 210000.0}
    settings = interfaces.normalized({"default": "contact", "pairs": [
        {"between": ["Plate", "Pin"], "kind": "tied"},
        {"between": ["Plate", "Cover"], "kind": "contact", "master": "Cover"}]})
    job = interfaces.with_stiffer_masters(settings, moduli, [("Pin", "Plate"), ("Bolt", "Plate"),
                                                            ("Bolt", "Nut")])
    by_pair = {frozenset(p["between"]): p for p in job["pairs"]}
    assert by_pair[frozenset(("Pin", "Plate"))]["master"] == "Pin"  # listed, tied
    assert by_pair[frozenset(("Plate", "Cover"))]["master"] == "Cover"  # the user's choice
    assert by_pair[frozenset(("Bolt", "Plate"))] == {"between": ["Bolt", "Plate"], "kind": "contact",
                                                     "master": "Bolt"}  # by the default
    assert "master" not in by_pair[frozenset(("Bolt", "Nut"))]  # equal: the core decides
    assert job["default"] == "contact"
    # The stored settings are not changed, and bonded defaults add no pairs.
    assert "master" not in settings["pairs"][0]
    assert interfaces.with_stiffer_masters({}, moduli, [("Pin", "Plate")]) == {}


def touching_balls_report():
    """The core's report of two unit balls touching at a point, the left one first."""
    import oraclemesh
    job = {"inputs": [{"name": "left", "sphere": {"center": [0, 0, 0], "radius": 1}, "material": 1},
                      {"name": "right", "sphere": {"center": [2, 0, 0], "radius": 1}, "material": 2}],
           "element_order": 1, "checks": "warn",  # coarse tet4 balls are short of volume
           "criteria": {"default": {"cell_size": 0.3, "facet_size": 0.3, "facet_distance": 0.03}}}
    return oraclemesh.run(job).report


def test_a_pairs_row_tells_the_area_where_the_parts_do_not_touch():
    # Balls touching at a point: the mesh bonds a patch around it, and all of it but a disc
    # of radius sqrt(R t) lies where the balls are farther apart than the contact tolerance t.
    ((a, b, area, triangles, beyond),) = interfaces.found_pairs(touching_balls_report())
    assert (a, b) == ("left", "right") and triangles > 0
    assert 0.99 * area < beyond <= area
    assert ("%.3g mm^2 of it where the parts are farther apart than the contact tolerance"
            % beyond) in interfaces.pair_tip(a, b, area, triangles, beyond)
    assert "farther apart" not in interfaces.pair_tip(a, b, area, triangles, 0.0)
