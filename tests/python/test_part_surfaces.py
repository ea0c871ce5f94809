"""Result.surfaces (issue 19 item 1): the interfaces and exteriors the core hands to Python
(and FreeCAD), checked on the mesh itself: two boxes given as triangle surfaces, the upper one
standing on the rectangle x 2..8, y 3..9 of the lower one's top (area 36)."""
import numpy as np

import oraclemesh

# CalculiX tet faces S1..S4 (corners 1-2-3, 1-4-2, 2-4-3, 3-4-1), zero-based.
FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))


def box_surface(lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    points = [[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    # Corner index = 4 i + 2 j + k for (x_i, y_j, z_k); two outward triangles per side.
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    triangles = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return {"points": points, "triangles": triangles}


def two_boxes_job():
    return {"inputs": [{"name": "Lower", "surface": box_surface((0, 0, 0), (10, 10, 10)), "material": 1},
                       {"name": "Upper", "surface": box_surface((2, 3, 10), (8, 9, 15)), "material": 2}],
            "criteria": {"default": {"cell_size": 3, "facet_size": 3, "facet_distance": 0.5}},
            "element_order": 2, "seed": 0}


def face_corners(result, faces):
    tets = np.asarray(result.tets)[:, :4]
    return np.array([tets[t, list(FACES[f])] for t, f in faces]).reshape(-1, 3)


def test_the_interface_is_the_contact_rectangle_between_the_two_parts():
    result = oraclemesh.run(two_boxes_job())
    by_name = {s["name"]: s for s in result.surfaces}
    assert sorted(by_name) == ["Exterior_Lower", "Exterior_Upper", "Interface_Lower_Upper"]
    interface = by_name["Interface_Lower_Upper"]
    assert (interface["material"], interface["other_material"]) == (1, 2)
    report = result.report["interfaces"][0]
    assert report["parts"] == ["Lower", "Upper"] and len(interface["faces"]) == report["triangles"]

    corners = face_corners(result, interface["faces"])
    p = np.asarray(result.points)[corners]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
    # The hand-off's faces are the report's; the rectangle's rim is meshed to within 1 % here
    # (35.81 measured: the B-rep boxes of tests/cpp/pipeline_interfaces.cpp give 36 exactly).
    assert abs(area - report["area"]) < 36e-9 and abs(area - 36) < 0.36
    assert np.allclose(p[:, :, 2], 10, atol=1e-9)

    # Each interface face is a face of one Lower tet and one Upper tet; exterior faces of one tet.
    tets = np.asarray(result.tets)[:, :4]
    owners = {}
    for t, tet in enumerate(tets.tolist()):
        for f in FACES:
            owners.setdefault(tuple(sorted(tet[i] for i in f)), []).append(int(result.tet_materials[t]))
    for s in result.surfaces:
        want = sorted([s["material"], s["other_material"]]) if s["other_material"] else [s["material"]]
        for c in face_corners(result, s["faces"]).tolist():
            assert sorted(owners[tuple(sorted(c))]) == want, s["name"]


def test_run_isolated_hands_over_the_same_surfaces():
    job = two_boxes_job()
    job["element_order"] = 1
    here, there = oraclemesh.run(job), oraclemesh.run_isolated(job)
    assert [s["name"] for s in there.surfaces] == [s["name"] for s in here.surfaces]
    for a, b in zip(here.surfaces, there.surfaces):
        assert (a["material"], a["other_material"]) == (b["material"], b["other_material"])
        assert np.array_equal(a["faces"], b["faces"])


def test_vtu_surfaces_file_reads_in_meshio(tmp_path):
    """The VTU's *_surfaces.vtu (tet10: 6-node triangles) as meshio, and so ParaView, reads it."""
    import meshio
    job = two_boxes_job()
    job["output"] = {"files": [str(tmp_path / "mesh.vtu")]}
    result = oraclemesh.run(job)
    surfaces = meshio.read(str(tmp_path / "mesh_surfaces.vtu"))
    assert [c.type for c in surfaces.cells] == ["triangle6"]
    index = surfaces.cell_data["surface"][0]
    for i, s in enumerate(result.surfaces):
        assert (index == i).sum() == len(s["faces"]), s["name"]
    # Corners as the hand-off's faces, mid nodes those of the tets' edges.
    corners = face_corners(result, np.concatenate([s["faces"] for s in result.surfaces]))
    assert np.array_equal(surfaces.cells[0].data[:, :3], corners)
    text = (tmp_path / "mesh_surfaces.vtu").read_text()
    assert all("<!-- surface %d: %s -->" % (i, s["name"]) in text for i, s in enumerate(result.surfaces))
