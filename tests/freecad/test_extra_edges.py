"""Extra edges (ExtraEdges: picked edges and sketches) become chains of mesh edges along the
exact curves; a sketch leaving the meshed domain gives a message naming it and changes
nothing; bad links give clear messages; the links survive save and reload.
scripts/extra_edges.py measures, this file judges."""


def test_extra_edges(run_freecad):
    r = run_freecad("extra_edges.py", timeout=300)
    print("mesh:", r["mesh"]["nodes"], "nodes,", r["mesh"]["volumes"], "tet10;",
          r["feature_edges"], "feature edges; polyline points", r["polyline_points"])
    assert r["extra_edges"] == [["TopSketch", [""]], ["Marker", [r["polyline_names"][2].split()[0]]]]
    assert r["polyline_names"][:2] == ["Edge1 of 'TopSketch'", "Edge2 of 'TopSketch'"]
    assert r["polyline_names"][2].endswith("of 'Marker'")
    assert r["polyline_points"][0] == 2 and r["polyline_points"][2] == 2  # straight: ends only
    assert r["polyline_points"][1] > 10  # the arc in chords
    assert r["features"] == {"sharp_angle_deg": 30.0, "junctions": True}

    assert r["stored_mid_nodes_right"]
    tol = r["tolerance"]
    assert sorted(r["chains"]) == ["arc", "line", "marker"]
    for name, c in r["chains"].items():
        print(name, {k: v for k, v in c.items()})
        assert c["edges"] >= 2 and c["connected"], name
        assert c["ends"] == 2 and c["max_degree"] == 2, name  # one open chain
        assert max(c["end_offsets"]) <= tol, name  # from end to end of the CAD edge
        assert c["worst_node"] <= tol, name
        assert c["mid_nodes"] == c["edges"] and c["mid_offset"] <= tol, name
        if name == "arc":  # chords of the arc: a little shorter than it
            assert 0.99 * c["edge_length"] <= c["length"] <= c["edge_length"]
        else:
            assert abs(c["length"] - c["edge_length"]) <= tol

    leaving = r["leaving"]
    print("leaving:", leaving["status"])
    assert not leaving["valid"]
    assert "extra edge Edge1 of 'Outside'" in leaving["status"]
    assert "leaves the meshed domain" in leaving["status"]
    assert leaving["mesh_kept"] and leaving["objects_kept"]

    bad = r["bad_links"]
    print("bad links:", bad)
    assert "Edge99 of 'Box'" in bad["edge_gone"] and "12 edges" in bad["edge_gone"]
    assert "Face1" in bad["face"] and "not an edge" in bad["face"]
    assert [name for name, _ in r["after_delete"]] == ["Marker"]
    assert r["after_delete_polylines"] == 1
    assert r["sharp_off_features"] == {"sharp_angle_deg": 0.0, "junctions": False, "polylines": 1}

    assert r["reloaded"] == r["saved"]
    assert r["reloaded_polylines"] == r["polyline_names"]
