"""The INP's *SURFACE blocks (issue 19 item 1) carry a CalculiX pressure onto the faces they
name: the two boxes of test_part_surfaces, the lower one fixed at z = 0, pressure 1 on one
surface at a time. No loaded node is fixed, so the reaction at the supports is the load itself,
p times the sum of the faces' outward area vectors; a wrong face label (S1..S4) would load other
faces of the same tets and give another force."""
import os
import subprocess

import numpy as np
import pytest

import oraclemesh
from test_part_surfaces import FACES, two_boxes_job
from test_writers_meshio import require_programs


def outward_area_vectors(points, tets, faces):
    """Sum over (tet, face) of the face's area vector, pointing away from the tet's 4th corner."""
    total = np.zeros(3)
    for t, f in faces:
        corners = points[tets[t, list(FACES[f])]]
        opposite = points[tets[t, 6 - sum(FACES[f])]]
        area = 0.5 * np.cross(corners[1] - corners[0], corners[2] - corners[0])
        if np.dot(area, corners.mean(axis=0) - opposite) < 0:
            area = -area
        total += area
    return total


def reaction_total(dat_text):
    lines = dat_text.splitlines()
    at = max(i for i, line in enumerate(lines) if "total force" in line)
    return np.array([float(v) for v in next(l for l in lines[at + 1:] if l.strip()).split()])


@pytest.fixture(scope="module")
def meshed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("surface_loads")
    job = dict(two_boxes_job(), output={"files": [str(folder / "mesh.inp")]})
    return oraclemesh.run(job), folder


@pytest.mark.parametrize("surface", ["Interface_Lower_Upper", "Exterior_Upper"])
def test_pressure_on_a_surface_is_carried_by_its_faces(meshed, surface, tmp_path):
    require_programs({"ccx": "calculix-ccx"})
    result, folder = meshed
    points = np.asarray(result.points)
    tets = np.asarray(result.tets)[:, :4]
    faces = next(s["faces"] for s in result.surfaces if s["name"] == surface)
    expected = outward_area_vectors(points, tets, faces)

    (tmp_path / "mesh.inp").write_text((folder / "mesh.inp").read_text())
    fixed = [i + 1 for i, p in enumerate(np.asarray(result.points)) if abs(p[2]) < 1e-9]
    nset = "\n".join(", ".join(map(str, fixed[k:k + 8])) for k in range(0, len(fixed), 8))
    (tmp_path / "job.inp").write_text(
        "*INCLUDE, INPUT=mesh.inp\n*NSET, NSET=Nfix\n%s\n"
        "*MATERIAL, NAME=Steel\n*ELASTIC\n210000, 0.3\n"
        "*SOLID SECTION, ELSET=Eall, MATERIAL=Steel\n"
        "*STEP\n*STATIC\n*BOUNDARY\nNfix, 1, 3\n*DLOAD\n%s, P, 1.0\n"
        "*NODE PRINT, NSET=Nfix, TOTALS=ONLY\nRF\n*END STEP\n" % (nset, surface))
    run = subprocess.run(["ccx", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0 and "*ERROR" not in run.stdout, run.stdout[-2000:]
    reaction = reaction_total((tmp_path / "job.dat").read_text())

    area = next(i["area"] for i in result.report["interfaces"])
    # Both surfaces push on a 6 x 6 rectangle's worth of +z (the upper box's top, or the lower
    # box's top under the upper one) and nothing sideways.
    assert np.allclose(expected, [0, 0, area], rtol=0, atol=1e-9 * area)
    assert np.allclose(reaction, expected, rtol=0, atol=1e-6 * area), (reaction, expected)
    assert area == pytest.approx(36.0, rel=0.01)
