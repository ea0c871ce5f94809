"""The demo's force pulls the way the demo says: the plate's loaded end moves down (-z) in
CalculiX, not up (FreeCAD takes a force direction from the edge's line, not from the order of
the edge's vertexes)."""


def test_demo_plate_is_pulled_down(run_freecad):
    # Coarse tet4 (the pin comes out short: kept, the direction is what is tested).
    r = run_freecad("demo_direction.py", {"mesh": {"cell_size": 8.0, "element_order": 1, "checks": "warn"}})
    ux, uy, uz = r["mean_displacement"]
    print("demo: %d loaded nodes, mean displacement (%.4f, %.4f, %.4f) mm, force direction %s"
          % (r["loaded_nodes"], ux, uy, uz, r["direction_vector"]))
    assert r["loaded_nodes"] > 10
    assert r["direction_vector"][2] < 0
    assert uz < 0 and abs(uz) > 10 * max(abs(ux), abs(uy)), r["mean_displacement"]
