"""Workbench parts behind the GUI, headless: the quality measure (against the geometry and
the core's report), export files read back by meshio, old documents gaining this version's
properties, group names from InputMaterialNames, size presets."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from installed import require_module, require_programs  # noqa: E402
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
    # ContactTolerance 0 leaves the core's default (1e-6 of the diagonal here, FreeCAD's
    # primitives carry 1e-7); makeMesh(contact_tolerance=...) reaches the job.
    assert r["report_contact_tolerance"]["from"] == "diagonal", r["report_contact_tolerance"]
    assert abs(r["report_contact_tolerance"]["value"] - 1e-6 * r["bbox_diagonal"]) < 1e-12
    assert r["given_contact_tolerance"] == {"value": 0.02, "from": "job"}
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
    check_exported_inp_in_calculix(r["exports"][".inp"], meshio)
    assert "xyz" in r["bad_extension"] and ".vtu" in r["bad_extension"]

    assert len(r["restored_properties"]) == 8 and all(r["restored_properties"].values()), \
        r["restored_properties"]
    # Saved before the Engine property: kept on Mesh_3, which meshed it then; saved before the
    # Fineness property: kept on the sizes alone, while a new mesh object follows the geometry.
    assert r["restored_engine"] == "cgal" and r["restored_junctions"] is True
    assert r["restored_fineness"] == "off" and r["new_mesh_fineness"] == "moderate"
    assert r["restored_checks"] == "warn"  # as old documents were meshed
    assert r["new_mesh_checks"] == "error"  # a new mesh object refuses a mesh that is not the model
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


def check_exported_inp_in_calculix(inp_path, meshio):
    """CalculiX reads the exported INP and its *SURFACEs name the right faces: a pressure of
    1 N/mm^2 on the faces of Exterior_Rod in the plane z = 15 (the rod's flat top cap) with the
    block's bottom (z = 0) clamped; the clamp's reaction is the pressure times the cap's area,
    along z: the 3 mm disk's 9 pi, as the tri6 faces' mid nodes on its rim bend their edges
    round it (their corner triangles miss the segments). Faces named by a wrong S1..S4 would
    be other faces of those tets, not flat in that plane."""
    require_programs({"ccx": "calculix-ccx"})
    inp = meshio.read(inp_path)
    points, tets = inp.points, inp.cells[0].data
    faces = np.array(inp_surfaces(inp_path)["Exterior_Rod"])
    corners = tets[faces[:, 0] - 1][np.arange(len(faces))[:, None], np.array(CALCULIX_FACES)[faces[:, 1]]]
    cap = points[corners][:, :, 2].min(axis=1) > 15 - 1e-9
    cap_area = triangle_areas(points, corners[cap]).sum()
    assert 0.95 * 9 * math.pi < cap_area < 9 * math.pi  # the corner triangles: a polygon
    fixed = [i + 1 for i, p in enumerate(points) if abs(p[2]) < 1e-9]
    folder = os.path.dirname(inp_path)
    lines = ["*INCLUDE, INPUT=%s" % os.path.basename(inp_path), "*NSET, NSET=Nfix"]
    lines += [", ".join(map(str, fixed[k:k + 8])) for k in range(0, len(fixed), 8)]
    lines += ["*SURFACE, NAME=Pressed, TYPE=ELEMENT"] + ["%d, S%d" % (e, f + 1) for e, f in faces[cap]]
    lines += ["*ELSET, ELSET=Eall", "Steel_Volumes, Block_Volumes", "*MATERIAL, NAME=Steel", "*ELASTIC",
              "210000, 0.3", "*SOLID SECTION, ELSET=Eall, MATERIAL=Steel", "*STEP", "*STATIC",
              "*BOUNDARY", "Nfix, 1, 3", "*DLOAD", "Pressed, P, 1.0",
              "*NODE PRINT, NSET=Nfix, TOTALS=ONLY", "RF", "*END STEP"]
    with open(os.path.join(folder, "pressed.inp"), "w") as f:
        f.write("\n".join(lines) + "\n")
    run = subprocess.run(["ccx", "pressed"], cwd=folder, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0 and "*ERROR" not in run.stdout, run.stdout[-2000:]
    with open(os.path.join(folder, "pressed.dat")) as f:
        # " total force (fx,fy,fz) for set NFIX and time  0.1000000E+01", then fx fy fz.
        reaction = [float(v) for v in f.read().split("total force")[-1].split()[-3:]]
    print("reaction %s N; pressure x disk area %.5f N" % (reaction, 9 * math.pi))
    # The pressure pushes the cap down (-z) with p A; ccx prints the clamp's reaction as +p A.
    assert reaction[2] == pytest.approx(9 * math.pi, rel=1e-4)
    assert abs(reaction[0]) < 1e-6 * reaction[2] and abs(reaction[1]) < 1e-6 * reaction[2]
