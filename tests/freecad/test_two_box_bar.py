"""Two overlapping boxes composed by priority, in series along x, under axial load, meshed by
each engine and solved by CalculiX."""
import pytest

F, A = 1000.0, 100.0
E_STEEL, E_ALU = 210000.0, 70000.0
L_STEEL, L_ALU = 110.0, 90.0  # steel (first input) wins the overlap x 90..110
EXPECTED = F * L_STEEL / (E_STEEL * A) + F * L_ALU / (E_ALU * A)


@pytest.mark.parametrize("engine", ["cgal", "thesis"])
def test_two_box_bar_elongation_tet10(run_freecad, engine):
    # A few seconds when it works; the limit keeps a hanging core from blocking the suite.
    r = run_freecad("two_box_bar.py", {"mesh": {"cell_size": 4.0, "element_order": 2, "engine": engine,
                                                "time_limit": 120}}, timeout=300)
    mesh = r["mesh"]
    assert mesh["nodes_per_volume"] == 10
    assert mesh["max_signed_volume6"] < 0
    # One group per FEM material, covering every volume once: the ccx writer uses them.
    assert sorted(mesh["group_sizes"]) == sorted(r["groups_expected"])
    assert mesh["groups_cover_all_once"]
    assert len(r["inp_materials"]) == 2, r["inp_materials"]
    print("two-box bar (%s): %s, elongation %.6f mm (expected %.6f mm, %+.3f%%), spread %.2e"
          % (engine, mesh["group_sizes"], r["elongation"], EXPECTED,
             100 * (r["elongation"] / EXPECTED - 1), r["ux_spread"]))
    assert abs(r["elongation"] - EXPECTED) < 0.01 * EXPECTED
