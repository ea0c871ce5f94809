"""The mesh files of src/core/mesh/Writers, read by independent software (meshio, CalculiX).

Each run makes its own files: oraclemesh.run meshes two overlapping balls (materials 3 and 8,
the first wins the overlap) in both element orders and writes .vtu and .inp into pytest's
tmp_path through the job's output.files; the files read back must hold the mesh the same
run returned in memory. The first ball's centre (1/3, -2/7, 1e-5/3) gives coordinates
that %.17g prints in more than CalculiX's 20 characters.
"""
import os
import subprocess
import sys

import numpy as np
import pytest

import oraclemesh

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from installed import require_module, require_programs  # noqa: E402
from tet_geometry import tet10_volumes  # noqa: E402

MATERIALS = (3, 8)
ORDERS = {1: "tetra", 2: "tetra10"}  # element order -> meshio cell type


def two_balls_job(order, folder):
    centre = [1.0 / 3, -2.0 / 7, 1e-5 / 3]
    return {
        "inputs": [{"name": "first", "sphere": {"center": centre, "radius": 1.0}, "material": 3},
                   {"name": "second", "sphere": {"center": [centre[0] + 1.2, centre[1], centre[2]],
                                                 "radius": 1.0}, "material": 8}],
        "criteria": {"default": {"cell_size": 0.4, "facet_size": 0.4, "facet_distance": 0.02}},
        "element_order": order,
        "checks": "warn",  # tet4 balls at these sizes are 2.5 % short; the writers are tested
        "seed": 0,
        "output": {"files": [os.path.join(folder, "two_balls.vtu"),
                             os.path.join(folder, "two_balls.inp")]},
    }


@pytest.fixture(scope="module")
def meshio():
    return require_module("meshio", "python3-meshio")


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """{order: (Result, folder)}: each order meshed once in this run, its files in folder."""
    out = {}
    for order in ORDERS:
        folder = str(tmp_path_factory.mktemp("writers_order%d" % order))
        result = oraclemesh.run(two_balls_job(order, folder))
        for name in ("two_balls.vtu", "two_balls.inp"):
            assert os.path.getsize(os.path.join(folder, name)) > 0, name
        out[order] = (result, folder)
    return out


def corner_volumes(points, cells):
    a, b, c, d = (points[cells[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


def by_material(result):
    """The result's tets grouped by material, in tet order within a group (the .inp order)."""
    return np.concatenate([result.tets[result.tet_materials == m] for m in MATERIALS])


def check_cells(mesh, result, cell_type):
    """The file's cells: one type, positively oriented, tet10 mid nodes in the core's order."""
    assert {block.type for block in mesh.cells} == {cell_type}
    cells = np.concatenate([block.data for block in mesh.cells])
    assert len(cells) == len(result.tets) > 100
    assert (corner_volumes(mesh.points, cells) > 0).all(), \
        "corners must be positively oriented (VTK and CalculiX)"
    return cells


def test_the_job_meshes_both_materials(written):
    for order, (result, _) in written.items():
        assert result.tets.shape[1] == (4 if order == 1 else 10)
        assert sorted(np.unique(result.tet_materials).tolist()) == list(MATERIALS)


@pytest.mark.parametrize("order", sorted(ORDERS))
def test_vtu_read_by_meshio(meshio, written, order):
    result, folder = written[order]
    mesh = meshio.read(os.path.join(folder, "two_balls.vtu"))
    cells = check_cells(mesh, result, ORDERS[order])
    # Written with %.17g: the same doubles, the same node numbers, tets in the core's order.
    np.testing.assert_array_equal(mesh.points, result.points)
    np.testing.assert_array_equal(cells, result.tets)
    material = mesh.cell_data["material"][0]
    assert material.dtype == np.int32
    np.testing.assert_array_equal(material, result.tet_materials)
    np.testing.assert_array_equal(mesh.point_data["vertex_dimension"], result.vertex_dimension)


@pytest.mark.parametrize("order", sorted(ORDERS))
def test_inp_read_by_meshio(meshio, written, order):
    result, folder = written[order]
    mesh = meshio.read(os.path.join(folder, "two_balls.inp"))
    cells = check_cells(mesh, result, ORDERS[order])
    # Coordinates shortened to CalculiX's 20 characters: at least 14 significant digits.
    np.testing.assert_allclose(mesh.points, result.points, rtol=0,
                               atol=1e-13 * np.abs(result.points).max())
    np.testing.assert_array_equal(cells, by_material(result))
    # One element set per material, defined on the *ELEMENT lines. meshio gives set members
    # per cell block, numbered within the block.
    offsets = np.cumsum([0] + [len(block.data) for block in mesh.cells])
    start = 0
    for material in MATERIALS:
        members = sorted(int(offsets[b] + i)
                         for b, local in enumerate(mesh.cell_sets["Material%d" % material])
                         for i in local)
        count = int((result.tet_materials == material).sum())
        assert members == list(range(start, start + count)), material
        start += count


@pytest.mark.parametrize("order", sorted(ORDERS))
def test_inp_accepted_by_calculix(written, order, tmp_path):
    """ccx stops with 'nonpositive jacobian' on a badly ordered element; its element volumes
    must add up to the mesh's."""
    require_programs({"ccx": "calculix-ccx"})
    result, folder = written[order]
    with open(os.path.join(folder, "two_balls.inp")) as f:
        (tmp_path / "mesh.inp").write_text(f.read())
    (tmp_path / "job.inp").write_text(
        "*INCLUDE, INPUT=mesh.inp\n"
        "*MATERIAL, NAME=Steel\n*ELASTIC\n210000, 0.3\n"
        "*MATERIAL, NAME=Aluminium\n*ELASTIC\n70000, 0.33\n"
        "*SOLID SECTION, ELSET=Material3, MATERIAL=Steel\n"
        "*SOLID SECTION, ELSET=Material8, MATERIAL=Aluminium\n"
        "*STEP\n*STATIC\n*BOUNDARY\nNall, 1, 3, 0\n*EL PRINT, ELSET=Eall\nEVOL\n*END STEP\n")
    run = subprocess.run(["ccx", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0 and "*ERROR" not in run.stdout, run.stdout[-2000:]
    lines = (tmp_path / "job.dat").read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if "volume (element, volume)" in line)
    volumes = {}
    for line in lines[start + 1:]:
        fields = line.split()
        if len(fields) == 2:
            volumes[int(fields[0])] = float(fields[1])
        elif volumes:
            break
    assert sorted(volumes) == list(range(1, len(result.tets) + 1))
    if order == 2:
        expected = tet10_volumes(result.points, result.tets).sum()
    else:
        expected = corner_volumes(result.points, result.tets).sum()
    assert sum(volumes.values()) == pytest.approx(expected, rel=1e-5)
