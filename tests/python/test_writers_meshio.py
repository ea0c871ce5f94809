"""The mesh files of src/core/mesh/Writers, read by independent software (meshio, CalculiX).

Order dependency: the files are written by the C++ test
`MeshWriters.WritesRoundTripFilesForMeshio` (tests/cpp/test_mesh_writers.cpp, part of
`oraclemesh_tests`) into ${ORACLEMESH_TEST_OUTPUT:-/tmp}. tests/run.sh runs ctest before
pytest with the same ORACLEMESH_TEST_OUTPUT, so the files are there; run on its own, this
module skips (with the reason) when they are missing. The mesh is the unit cube of edge 0.1
split into six Kuhn tets around the diagonal from corner 0 to corner 7, moved by
(1/3, -2/7, 1e-5/3); tets 0-2 (the half x >= y) have material 3, tets 3-5 material 8.
`writer_roundtrip.*` is second order (straight mid nodes), `writer_roundtrip_tet4.*` first order.
"""
import os
import shutil
import subprocess

import numpy as np
import pytest

meshio = pytest.importorskip("meshio")

OUTPUT = os.environ.get("ORACLEMESH_TEST_OUTPUT") or "/tmp"
SIZE = 0.1
OFFSET = np.array([1.0 / 3, -2.0 / 7, 1e-5 / 3])
MATERIALS = [3, 3, 3, 8, 8, 8]
# (stem, meshio cell type, number of points: 8 corners + 19 edges for second order)
CASES = [("writer_roundtrip", "tetra10", 27), ("writer_roundtrip_tet4", "tetra", 8)]


def written(name):
    path = os.path.join(OUTPUT, name)
    if not os.path.exists(path):
        pytest.skip(f"{path} is missing: run the C++ test MeshWriters.WritesRoundTripFilesForMeshio "
                    f"(oraclemesh_tests) first with the same ORACLEMESH_TEST_OUTPUT")
    return path


def corner_volumes(points, cells):
    a, b, c, d = (points[cells[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


def check_geometry(mesh, cell_type, n_points):
    """Checks points and cells; returns the cells of all blocks (the .inp has one per material)."""
    assert len(mesh.points) == n_points
    assert {block.type for block in mesh.cells} == {cell_type}
    cells = np.concatenate([block.data for block in mesh.cells])
    assert len(cells) == 6
    np.testing.assert_allclose(mesh.points.min(axis=0), OFFSET, rtol=1e-13, atol=0)
    np.testing.assert_allclose(mesh.points.max(axis=0), OFFSET + SIZE, rtol=1e-13, atol=0)
    volumes = corner_volumes(mesh.points, cells)
    assert (volumes > 0).all(), "corners must be positively oriented (VTK and CalculiX)"
    assert volumes.sum() == pytest.approx(SIZE ** 3, rel=1e-12)
    if cell_type == "tetra10":
        # Mid nodes in the order 01, 12, 20, 03, 13, 23 sit on the midpoints of those edges.
        for k, (i, j) in enumerate([(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]):
            mid = mesh.points[cells[:, 4 + k]]
            expected = 0.5 * (mesh.points[cells[:, i]] + mesh.points[cells[:, j]])
            np.testing.assert_allclose(mid, expected, rtol=1e-13, atol=0)
    return cells


@pytest.mark.parametrize("stem,cell_type,n_points", CASES)
def test_vtu_read_by_meshio(stem, cell_type, n_points):
    mesh = meshio.read(written(stem + ".vtu"))
    check_geometry(mesh, cell_type, n_points)
    assert mesh.cell_data["material"][0].tolist() == MATERIALS
    assert mesh.cell_data["material"][0].dtype == np.int32
    dims = mesh.point_data["vertex_dimension"]
    assert dims[:8].tolist() == [2] * 8
    if cell_type == "tetra10":
        # Every edge lies on a cube face or, like the main diagonal 0-7, on the interface x = y.
        assert dims[8:].tolist() == [2] * 19


@pytest.mark.parametrize("stem,cell_type,n_points", CASES)
def test_inp_read_by_meshio(stem, cell_type, n_points):
    mesh = meshio.read(written(stem + ".inp"))
    check_geometry(mesh, cell_type, n_points)
    # One element set per material, defined on the *ELEMENT lines. meshio gives set members
    # per cell block, numbered within the block.
    offsets = np.cumsum([0] + [len(block.data) for block in mesh.cells])
    for material in (3, 8):
        members = sorted(int(offsets[b] + i) for b, local in enumerate(mesh.cell_sets[f"Material{material}"])
                         for i in local)
        assert members == [i for i, m in enumerate(MATERIALS) if m == material]


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) is not installed")
@pytest.mark.parametrize("stem", ["writer_roundtrip", "writer_roundtrip_tet4"])
def test_inp_accepted_by_calculix(stem, tmp_path):
    """ccx stops with 'nonpositive jacobian' on a badly ordered element; its element volumes
    must add up to the cube's."""
    mesh_file = written(stem + ".inp")
    shutil.copy(mesh_file, tmp_path / "mesh.inp")
    (tmp_path / "job.inp").write_text(
        "*INCLUDE, INPUT=mesh.inp\n"
        "*MATERIAL, NAME=Steel\n*ELASTIC\n210000, 0.3\n"
        "*MATERIAL, NAME=Aluminium\n*ELASTIC\n70000, 0.33\n"
        "*SOLID SECTION, ELSET=Material3, MATERIAL=Steel\n"
        "*SOLID SECTION, ELSET=Material8, MATERIAL=Aluminium\n"
        "*STEP\n*STATIC\n*BOUNDARY\nNall, 1, 3, 0\n*EL PRINT, ELSET=Eall\nEVOL\n*END STEP\n")
    run = subprocess.run(["ccx", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
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
    assert sorted(volumes) == [1, 2, 3, 4, 5, 6]
    assert sum(volumes.values()) == pytest.approx(SIZE ** 3, rel=1e-5)
