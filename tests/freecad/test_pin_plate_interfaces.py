"""The demo pin in the plate (issue 19): with the pin-plate interface `contact` and `bonded`,
the mesh solves in CalculiX through FreeCAD, the report lists the interface with the area of
the pin's cylinder inside the plate, and the setting and the cards survive save and reopen
(scripts/pin_plate_interfaces.py)."""
import pytest


@pytest.mark.parametrize("kind", ["bonded", "contact"])
def test_pin_in_plate_solves_with_its_interface(run_freecad, kind):
    r = run_freecad("pin_plate_interfaces.py", {"kind": kind, "then_default_contact": kind == "bonded"},
                    timeout=300)
    entry = r["entry"]
    print("%s: %s; interface %s area %.4f (report, flat), groups %s, cylinder %.4f; max "
          "displacement %s; %d result(s); cards %s"
          % (kind, r["status"], entry["name"], entry["area"], r["group_areas"], r["cylinder_area"],
             r["max_displacement"], r["increments"],
             [c for c in r["cards"] if c in ("*TIE", "*CONTACT PAIR", "*SURFACE INTERACTION")]))
    assert entry["kind"] == kind
    if kind == "contact":  # the steel pin is stiffer than the aluminium plate: its side is master
        assert (entry["master"], entry["slave"]) == ("Interface_Pin_Plate", "Interface_Plate_Pin")
    for name, area in r["group_areas"].items():  # tri6 faces, curved onto the cylinder
        assert area == pytest.approx(r["cylinder_area"], rel=0.005), name
    assert len(r["group_areas"]) == (1 if kind == "bonded" else 2)
    # The report's area is of the flat corner triangles: a chord short of the cylinder.
    assert entry["area"] == pytest.approx(r["cylinder_area"], rel=0.005)
    assert kind in r["reopened_interfaces"]
    expected = 1 if kind == "contact" else 0
    assert r["cards"].count("*CONTACT PAIR") == expected
    assert r["reopened_cards"].count("*CONTACT PAIR") == expected
    assert r["framework_cards"].count("*CONTACT PAIR") == expected
    print("solver framework: max displacement %s" % r["framework_max_displacement"])
    assert max(r["max_displacement"].values()) == pytest.approx(r["framework_max_displacement"],
                                                                rel=1e-3)
    # The plate, fixed at one end and pulled down at the other, bends (1.27 mm bonded, 1.30 mm
    # in contact: the pin stiffens it less); the pin goes along.
    plate, pin = r["max_displacement"]["Aluminium_Volumes"], r["max_displacement"]["Steel_Volumes"]
    assert 1.0 < plate < 1.6 and 0.3 * plate < pin < plate
    if kind == "bonded":
        # Then the default made contact and the pin renamed SteelPin: it meshes (the last mesh's
        # pair under the old name is not passed on), in contact; meshed once more, the pair
        # the last mesh found gets the steel pin as master.
        assert r["renamed_valid"], r["renamed_status"]
        (renamed,) = r["renamed_interfaces"]
        assert sorted(renamed["parts"]) == ["Plate", "SteelPin"] and renamed["kind"] == "contact"
        (remeshed,) = r["remeshed_interfaces"]
        assert remeshed["master"] == "Interface_SteelPin_Plate", remeshed
        # The job names the master from the FEM materials (steel 210000 over aluminium 70000 MPa).
        assert r["job_interfaces"] == {"default": "contact", "pairs": [
            {"between": ["SteelPin", "Plate"], "kind": "contact", "master": "SteelPin"}]}
