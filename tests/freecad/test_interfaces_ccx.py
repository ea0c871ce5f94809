"""Assembly interfaces through FreeCAD to CalculiX (issue 19 item 3): makeMesh(interfaces=...)
on two stacked steel plates 200 x 20 x 5, both fixed at x = 0, 100 N down on the top face,
solved by ccxtools with FreeCAD's own writer, to which the workbench adds the surfaces, *TIE and
*CONTACT PAIR (scripts/stacked_plates.py). Bonded and tied bend as one 10 mm beam
(Euler-Bernoulli F L^3 / 8 E I), frictionless contact as two 5 mm beams sharing the load (4x)."""
import pytest

EULER_BERNOULLI = 100.0 * 200.0 ** 3 / (8 * 210000.0 * 20.0 * 10.0 ** 3 / 12)  # 0.2857 mm
KINDS = ("bonded", "tied", "contact")


@pytest.fixture(scope="module")
def plates(tmp_path_factory):
    return {}


def solve(run_freecad, plates, kind):
    if kind not in plates:
        plates[kind] = run_freecad("stacked_plates.py", {"kind": kind}, timeout=300)
    return plates[kind]


@pytest.mark.parametrize("kind", KINDS)
def test_plates_reach_calculix_through_freecad(run_freecad, plates, kind):
    r = solve(run_freecad, plates, kind)
    print("%s: %d nodes, %d elements, tip deflection %.5f mm (top %.5f, bottom %.5f), "
          "Euler-Bernoulli %.5f mm, ratio %.3f; cards %s"
          % (kind, r["nodes"], r["elements"], r["tip_deflection"], r["top_tip"], r["bottom_tip"],
             EULER_BERNOULLI, r["tip_deflection"] / EULER_BERNOULLI, r["cards"]))
    assert r["mesh"]["groups_cover_all_once"]
    # FreeCAD writes the FemMesh's ids, which are the core's: the same element lines.
    assert r["elements_equal"] and r["elements"] == r["mesh"]["volumes"]
    (entry,) = r["report_interfaces"]
    assert sorted(entry["parts"]) == ["Bottom", "Top"] and entry["kind"] == kind
    assert entry["area"] == pytest.approx(4000, rel=1e-9)
    names = [c.split(",")[0] for c in r["cards"]]
    if kind == "bonded":
        assert "*TIE" not in names and "*CONTACT PAIR" not in names
        assert r["surfaces_written"] == []
        assert r["tip_deflection"] == pytest.approx(EULER_BERNOULLI, rel=0.03)
        return
    # Both sides of the interface, face by face as the core's own INP has them.
    assert sorted(r["interface_groups"]) == sorted(entry["surfaces"])
    assert all(r["surfaces_equal"].values()), r["surfaces_equal"]
    assert r["step_after_cards"]
    if kind == "tied":
        assert names.count("*TIE") == 1 and "*CONTACT PAIR" not in names
    else:
        assert names.count("*CONTACT PAIR") == 1 and "*SURFACE INTERACTION" in names
        assert "*TIE" not in names


def test_bonded_and_tied_bend_as_one_beam(run_freecad, plates):
    bonded = solve(run_freecad, plates, "bonded")["tip_deflection"]
    tied = solve(run_freecad, plates, "tied")["tip_deflection"]
    print("bonded %.5f, tied %.5f, Euler-Bernoulli %.5f mm" % (bonded, tied, EULER_BERNOULLI))
    assert tied == pytest.approx(bonded, rel=0.02)
    assert bonded == pytest.approx(EULER_BERNOULLI, rel=0.03)
    assert tied == pytest.approx(EULER_BERNOULLI, rel=0.03)


def test_frictionless_contact_bends_as_two_beams(run_freecad, plates):
    r = solve(run_freecad, plates, "contact")
    print("contact %.5f mm = %.3f x Euler-Bernoulli; top %.5f, bottom %.5f"
          % (r["tip_deflection"], r["tip_deflection"] / EULER_BERNOULLI, r["top_tip"], r["bottom_tip"]))
    assert r["tip_deflection"] == pytest.approx(4.0 * EULER_BERNOULLI, rel=0.03)
    # Pressed together, the plates stay in contact at the tip.
    assert abs(r["top_tip"] - r["bottom_tip"]) < 0.01 * r["tip_deflection"]


def test_contact_lets_the_plates_separate(run_freecad):
    # Cell size 10 and those sizes alone: the opening contact takes CalculiX about a hundred
    # iterations, over two minutes at cell size 5; at the default fineness (three sizes through
    # each plate) CalculiX stops with "increment size smaller than minimum".
    r = run_freecad("stacked_plates.py", {"kind": "contact", "load": "pull", "cell_size": 10.0,
                                          "fineness": "off"}, timeout=300)
    print("pulled apart (%d nodes): top plate tip %.5f mm, bottom %.3g mm"
          % (r["nodes"], -r["top_tip"], -r["bottom_tip"]))
    # The top plate alone (5 mm, 100 N at its tip: F L^3 / 3 E I = 6.1 mm) lifts off...
    lift = -r["top_tip"]
    assert lift > 0.5 * 100.0 * 200.0 ** 3 / (3 * 210000.0 * 20 * 5.0 ** 3 / 12)
    # ...and the unloaded bottom plate stays put.
    assert abs(r["bottom_tip"]) < 1e-3 * lift


def test_contact_friction_reaches_the_input_and_follows_the_mesh(run_freecad):
    r = run_freecad("stacked_plates.py", {"kind": "contact", "friction": 0.2, "write_only": True,
                                          "then_tied": True}, timeout=120)
    (entry,) = r["report_interfaces"]
    print("friction %s, slope %g: %s" % (entry["friction"], entry["contact_stiffness"],
                                         r["friction_lines"]))
    assert entry["friction"] == 0.2
    # mu, then the stick slope (a hundredth of the normal slope, as the core writes it).
    (line,) = r["friction_lines"]
    mu, stick = (float(v) for v in line.split(","))
    assert mu == 0.2 and stick == pytest.approx(0.01 * entry["contact_stiffness"], rel=1e-9)
    # Interfaces changed after the mesh: the input still has the mesh's contact, and the
    # report view says to mesh again.
    assert "*CONTACT PAIR" in r["keywords"] and "*TIE" not in r["keywords"]
    with open(r["log"]) as f:
        assert "recompute the mesh first to use the new settings" in f.read()


def test_tet4_tie_equals_bonded(run_freecad):
    """C3D4 faces are numbered as C3D10's corners: a tie of tet4 plates is their bonded mesh."""
    r = {kind: run_freecad("stacked_plates.py", {"kind": kind, "element_order": 1}, timeout=120)
         for kind in ("bonded", "tied")}
    print("tet4: bonded %.5f, tied %.5f mm" % (r["bonded"]["tip_deflection"], r["tied"]["tip_deflection"]))
    tied = r["tied"]
    assert tied["mesh"]["nodes_per_volume"] == 4 and tied["elements_equal"]
    assert all(tied["surfaces_equal"].values()) and len(tied["surfaces_equal"]) == 2
    assert [c.split(",")[0] for c in tied["cards"]].count("*TIE") == 1
    assert tied["tip_deflection"] == pytest.approx(r["bonded"]["tip_deflection"], rel=0.02)
