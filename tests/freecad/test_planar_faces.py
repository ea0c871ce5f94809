"""PlanarFaces (thesis engine): the planar faces of a 40-degree wedge are planes in the FEM mesh
(every boundary triangle of a face has its nodes on the plane, the triangles' areas add up to
the face's), which they are not without it; with the cgal engine the property gives a message
naming it and keeps the mesh. scripts/planar_faces.py measures, this file judges."""


def test_planar_faces(run_freecad):
    r = run_freecad("planar_faces.py", timeout=300)
    on, off = r["on"]["faces"], r["off"]["faces"]
    # The wedge's five faces, all planar and bounded by sharp edges: each one is checked.
    assert len(on) == len(off) == 5
    assert r["report_planar_faces"]["faces"] == 5, r["report_planar_faces"]
    print("wedge tets: off %d, on %d; report %s" % (r["off"]["volumes"], r["on"]["volumes"],
                                                   r["report_planar_faces"]))
    for k, face in enumerate(on):
        print("face", k, "on", face, "off", off[k])
        assert face["triangles"] > 0
        assert face["off_plane"] == 0, face
        assert abs(face["area"] - face["face_area"]) <= 1e-9 * face["face_area"], face
    assert sum(f["off_plane"] for f in off) > 0
    assert any(abs(f["area"] - f["face_area"]) > 1e-9 * f["face_area"] for f in off)
    assert r["report_planar_faces"]["missing"] == 0
    cgal = r["cgal"]
    assert not cgal["valid"] and cgal["mesh_kept"]
    assert "PlanarFaces" in cgal["status"] and "thesis" in cgal["status"], cgal["status"]
