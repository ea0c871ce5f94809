"""Mesh features, Part compounds and imported STEP parts as inputs of the mesh object."""


def test_mesh_feature_compound_and_step_part_volumes_per_material(run_freecad):
    r = run_freecad("input_kinds.py", timeout=300)
    kinds = r["input_kinds"]
    assert r["input_kinds_before_recompute"] == kinds  # shown as soon as the inputs are set
    assert kinds[0].startswith("Bone: triangle surface (") and kinds[0].endswith(" triangles)")
    assert kinds[1] == "Blocks: B-rep compound (2 solids)"
    assert kinds[2] == "%s: B-rep compound (2 solids)" % r["imported_label"]
    # What the GUI command accepts from the selection: not the plain face.
    assert r["can_be_input"] == [True, True, True, False]
    # Each compound is split into one part per solid, in compound order: a Part::Compound's
    # parts are named by its links, a STEP part without names by its label and solid number.
    names = [name for name, _, _ in r["core_inputs"]]
    assert names == ["Bone", "BlockA", "BlockB",
                     r["imported_label"] + " Solid1", r["imported_label"] + " Solid2"]
    assert [kind for _, kind, _ in r["core_inputs"]] == ["triangle surface"] + ["B-rep solid"] * 4
    # Every part has a material id of its own; the plates' solids are both named by one FEM
    # material: one group.
    assert [m for _, _, m in r["core_inputs"]] == [1, 2, 3, 4, 5]
    assert r["mesh"]["groups_cover_all_once"]
    assert len(r["volume_expected"]) == 4
    assert sorted(r["volume"]) == sorted(r["volume_expected"])
    # Per material: the bone (its Placement applied: otherwise it would overlap block A
    # elsewhere and by a different amount), block A minus the bone, block B, the plates. Planar
    # faces are met exactly; the bone is a polyhedron meshed to facet_distance 0.05: 0.5 %.
    for group, expected in r["volume_expected"].items():
        got = r["volume"][group]
        print("%s: tet10 volume %.2f vs %.2f (%+.3f %%)" % (group, got, expected, 100 * (got / expected - 1)))
        assert abs(got - expected) < 0.005 * expected, (group, got, expected)
