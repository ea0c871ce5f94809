"""FEM hand-off: groups, orientation, constraint node search, curved faces, save/reopen."""
import math


def test_fem_handoff_demo_assembly(run_freecad):
    r = run_freecad("handoff_checks.py", {"mesh": {"cell_size": 3.0, "element_order": 2}})
    mesh = r["mesh"]
    assert r["in_analysis"]
    assert mesh["nodes_per_volume"] == 10
    assert mesh["max_signed_volume6"] < 0, "FreeCAD wants (n2-n1)x(n3-n1).(n4-n1) < 0"
    assert mesh["min_abs_signed_volume6"] > 0
    # One group per FEM material (named <FemMaterial.Name>_Volumes), covering all volumes.
    assert len(r["groups_expected"]) == 2
    assert sorted(mesh["group_sizes"]) == sorted(r["groups_expected"])
    assert all(n > 0 for n in mesh["group_sizes"].values())
    assert mesh["groups_cover_all_once"]
    # The cut removed the plate corner.
    assert r["tets_in_cut_region"] == 0
    # FreeCAD's geometric node search finds exactly the nodes on the fixed face.
    assert r["fixed_face_nodes_found"] > 20
    assert r["fixed_face_found_all"], (r["fixed_face_nodes_found"], r["fixed_face_nodes_on_plane"])
    # Boundary nodes, mid nodes included, lie on the pin's cylinder.
    assert r["pin_lateral_boundary_faces"] > 20
    assert r["pin_lateral_max_radius_error"] < 1e-6, (
        "boundary mid nodes off the cylinder by up to %.3g mm (core report: %s straight-sided "
        "fallbacks)" % (r["pin_lateral_max_radius_error"], r["second_order_straight_fallbacks"]))
    # Volume per material (tet10, curved): pin and plate minus pin minus the cut corner.
    for group, part in r["groups_expected"].items():
        expected = r["volume_expected"][part]
        assert abs(r["volume"][group] - expected) < 0.005 * expected, (group, r["volume"][group], expected)
    # Every interface and exterior of the core's report is a Face group of the FemMesh: one tri6
    # per reported triangle, each the face of a tet10 of its part with the same mid nodes, its
    # normal out of that tet; the same area (flat corner triangles, as the report measures).
    faces = dict(r["face_groups"])
    names = faces.pop("_reported_names")
    assert sorted(faces) == names == ["Exterior_Pin", "Exterior_Plate", "Interface_Pin_Plate"], names
    for name, f in faces.items():
        assert f["nodes_per_face"] == [6], (name, f)
        assert f["faces"] == f["reported_triangles"] > 20, (name, f)
        assert f["on_own_volume"] == f["outward"] == f["faces"], (name, f)
        assert abs(f["area"] - f["reported_area"]) < 1e-9 * f["reported_area"], (name, f)
    # The pin's cylinder inside the plate (2 pi r t), from the tri6 faces' mid nodes on it.
    interface = faces["Interface_Pin_Plate"]["curved_area"]
    assert abs(interface - 2 * math.pi * 5 * 10) < 0.005 * 2 * math.pi * 5 * 10, interface
    # Save + reopen keeps the object, its links and the groups; no re-mesh is pending.
    reopened = r["reopened"]
    assert reopened["proxy"] == "OracleMeshProxy"
    assert reopened["inputs"] == ["Pin", "Plate"] and reopened["cuts"] == ["CutBox"]
    assert reopened["volumes"] == mesh["volumes"]
    assert reopened["groups"] == sorted(r["groups_expected"])
    assert reopened["face_groups"] == r["face_groups"]["_reported_names"]
    assert not reopened["touched"]
    # A changed input asks for a recompute without remeshing; the recompute meshes the new pin.
    changed = r["after_input_change"]
    assert changed["input_touched"] and changed["document_needs_recompute"] and changed["volumes_unchanged"]
    assert abs(changed["max_pin_radius_meshed"] - 6.0) < 1e-6, changed
    # Without FEM materials the groups carry the input labels.
    assert r["label_groups"] == ["Pin_Volumes", "Plate_Volumes"]
