"""Workbench parts behind the GUI, headless: the quality measure (against the geometry and
the core's report), export files read back by meshio, old documents gaining this version's
properties, group names from InputMaterialNames, size presets."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from installed import require_module  # noqa: E402
from tet_geometry import tet10_volumes  # noqa: E402


def test_workbench_parts(run_freecad):
    r = run_freecad("workbench_parts.py", timeout=300)
    # Regular tetrahedron: every dihedral angle is arccos(1/3).
    assert abs(r["regular_tet_min_dihedral"] - math.degrees(math.acos(1 / 3))) < 1e-9
    assert r["flat_tet_min_dihedral"] < 1.0
    assert abs(r["preset_moderate"] - round(r["bbox_diagonal"] / 15, 3)) < 1e-9
    assert r["preset_automatic"] == 0.0
    # The wedge's 10 degree edge (the only one below 15 degrees); box and cylinder have none.
    assert len(r["wedge_small_angles"]) == 1 and abs(r["wedge_small_angles"][0] - 10) < 1e-6
    assert r["box_small_angles"] == [] and r["cylinder_small_angles"] == []

    # Group of the rod named by InputMaterialNames, the block by its label.
    assert set(r["groups"]) == {"Steel_Volumes", "Block_Volumes"}
    assert sum(r["groups"].values()) == r["report_counts"]["tets"] == r["quality_count"]
    assert r["report_features"]["junctions"] is True
    # A mesh object made without an engine meshes with the default, Rule Set T (issue 7).
    assert r["new_mesh_engine"] == r["report_engine"] == "thesis"
    assert r["feature_edges"] == r["report_counts"]["feature_edges"] > 0
    assert r["feature_edge_nodes_exist"]
    # The workbench measures the same worst element as the core.
    assert abs(r["quality_min"] - r["report_min_dihedral"]) < 1e-6
    assert r["quality_groups"] == ["Block_Volumes", "Steel_Volumes"]

    meshio = require_module("meshio", "python3-meshio")
    total = sum(r["report_volumes"].values())
    assert sorted(r["exports"]) == [".inp", ".msh", ".vtu"]
    for ext, path in r["exports"].items():
        m = meshio.read(path)
        tets = m.cells[0].data
        assert m.cells[0].type == "tetra10" and len(tets) == r["quality_count"], ext
        vol = tet10_volumes(m.points, tets)
        assert (vol > 0).all(), "%s: exported tets are not positively oriented" % ext
        assert abs(vol.sum() - total) < 1e-6 * total, ext
    inp = open(r["exports"][".inp"]).read()
    assert "*ELSET, ELSET=Steel_Volumes" in inp and "*ELSET, ELSET=Block_Volumes" in inp
    vtu = meshio.read(r["exports"][".vtu"])
    assert sorted(np.unique(vtu.cell_data["material"][0]).tolist()) == [1, 2]
    check_exported_face_groups(r["face_group_areas"], vtu, r["exports"][".inp"], meshio)
    assert "xyz" in r["bad_extension"] and ".vtu" in r["bad_extension"]

    assert len(r["restored_properties"]) == 5 and all(r["restored_properties"].values()), \
        r["restored_properties"]
    # Saved before the Engine property: kept on Mesh_3, which meshed it then.
    assert r["restored_engine"] == "cgal" and r["restored_junctions"] is True
    # An engine the document stored stays, whatever order the engines were listed in.
    assert r["stored_engine"] == ["cgal", ["thesis", "cgal"]]
    assert r["restored_planar_faces"] is False  # off unless asked for
    assert r["restored_meshes"], r["restored_status"]


# CalculiX's tet faces S1..S4 by corner (0-based).
CALCULIX_FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))


def triangle_areas(points, corners):
    c = points[np.asarray(corners)]
    return 0.5 * np.linalg.norm(np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), axis=1)


def inp_surfaces(path):
    """{name: [(element id, face 0..3)]} of the *SURFACE, TYPE=ELEMENT blocks."""
    surfaces, current = {}, None
    for line in open(path):
        if line.startswith("*"):
            current = None
            if line.upper().startswith("*SURFACE,"):
                current = surfaces.setdefault(line.split("NAME=")[1].split(",")[0].strip(), [])
        elif current is not None and line.strip():
            element, face = line.split(",")
            current.append((int(element), int(face.strip()[1:]) - 1))
    return surfaces


def check_exported_face_groups(areas, vtu, inp_path, meshio):
    """The VTU's face cells and the INP's *SURFACEs are the FemMesh's face groups: the same
    names, the same areas (corner triangles, as the FreeCAD side measured them)."""
    # The rod through the block: their (bonded: one-sided) interface and both exteriors; the
    # interface is the rod's side inside the 10 mm block, 2 pi 3 x 10, less its faceting.
    assert sorted(areas) == ["Exterior_Block", "Exterior_Rod", "Interface_Rod_Block"]
    assert 0.98 * 60 * math.pi < areas["Interface_Rod_Block"] < 60 * math.pi
    # VTU: a triangle6 block, its cells' face_group index named by the field data.
    block = [k for k, c in enumerate(vtu.cells) if c.type == "triangle6"]
    assert len(block) == 1, [c.type for c in vtu.cells]
    faces, group = vtu.cells[block[0]].data, vtu.cell_data["face_group"][block[0]]
    names = {int(v[0]): n for n, v in vtu.field_data.items()}
    assert sorted(names.values()) == sorted(areas)
    assert (vtu.cell_data["face_group"][0] == 0).all() and (group > 0).all()
    face_area = triangle_areas(vtu.points, faces[:, :3])
    for k, name in names.items():
        assert abs(face_area[group == k].sum() - areas[name]) < 1e-9 * areas[name], name
    # INP: one *SURFACE per face group over the tets' faces.
    inp = meshio.read(inp_path)
    tets = inp.cells[0].data
    surfaces = inp_surfaces(inp_path)
    assert sorted(surfaces) == sorted(n.replace(" ", "_") for n in areas)
    for name, area in areas.items():
        sides = np.array(surfaces[name.replace(" ", "_")])
        corners = tets[sides[:, 0] - 1][np.arange(len(sides))[:, None],
                                        np.array(CALCULIX_FACES)[sides[:, 1]]]
        assert abs(triangle_areas(inp.points, corners).sum() - area) < 1e-9 * area, name
