"""The job contract through Python (oraclemesh.run) and the CLI: results, progress, errors.

Run by tests/run.sh with PYTHONPATH pointing at the build's staged package and
ORACLEMESH_BUILD_DIR at the build (for the CLI binary).
"""
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import pytest

import oraclemesh

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tet_geometry import tet10_volumes  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data")
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build"))
CLI = os.path.join(BUILD, "oraclemesh")


def sphere_job(radius=10.0, order=2, **extra):
    job = {
        "inputs": [{"name": "ball", "sphere": {"center": [1, 2, 3], "radius": radius}, "material": 1}],
        "criteria": {"default": {"cell_size": radius / 3, "facet_size": radius / 4,
                                 "facet_distance": radius / 200}},
        "element_order": order,
    }
    job.update(extra)
    return job


def tet10_volume(points, tets):
    """Exact total volume of quadratic tets (positively oriented)."""
    return tet10_volumes(points, tets).sum()


@pytest.mark.parametrize("engine", ["cgal", "thesis"])
def test_sphere_tet10_volume_and_nodes_on_surface(engine):
    r = 10.0
    result = oraclemesh.run(sphere_job(r, engine=engine))
    assert result.report["engine"] == engine
    assert result.tets.shape[1] == 10
    assert set(np.unique(result.tet_materials)) == {1}
    exact = 4.0 / 3.0 * math.pi * r ** 3
    assert abs(tet10_volume(result.points, result.tets) - exact) < 0.005 * exact
    # Every boundary node (corners and mid nodes of boundary triangles) is on the sphere.
    center = np.array([1.0, 2.0, 3.0])
    tri = result.boundary_triangles
    assert len(tri) > 50
    radii = np.linalg.norm(result.points[np.unique(tri)] - center, axis=1)
    assert np.max(np.abs(radii - r)) < 1e-9 * 2 * r * math.sqrt(3)
    # Corner orientation is positive for every tet.
    p = result.points[result.tets[:, :4]]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    assert np.all(vol > 0)
    assert result.report["counts"]["tets"] == len(result.tets)


def test_default_engine_is_thesis():
    """Rule Set T is the default since it beat Mesh_3 on the refine benchmark (issue 7): a job
    without "engine" runs on it and may use its own options."""
    job = sphere_job(order=1, material_assignment="barycenter")
    assert "engine" not in job
    result = oraclemesh.run(job)
    assert result.report["engine"] == "thesis"
    assert "thesis" in result.report  # the engine's own report section
    assert result.report["material_assignment"] == "barycenter"
    assert len(result.tets) > 100


def test_progress_is_reported_and_cancel_stops():
    phases = []
    oraclemesh.run(sphere_job(order=1), progress=lambda phase, f: phases.append((phase, f)))
    names = [p for p, _ in phases]
    assert "load" in names and "refine" in names and names[-1] == "done"
    assert all(0.0 <= f <= 1.0 for _, f in phases)

    with pytest.raises(oraclemesh.Cancelled):
        oraclemesh.run(sphere_job(order=1), progress=lambda phase, f: phase != "refine")


BAD_JOBS = [
    ({"inputs": []}, "no inputs"),
    ({"inputs": [{"name": "tool", "sphere": {"center": [0, 0, 0], "radius": 1}, "role": "cut"}]},
     "role 'cut'"),
    ({"inputs": [{"name": "flat", "file": os.path.join(DATA, "face_only.brep")}]}, "no solid"),
    ({"inputs": [{"name": "lid_missing", "file": os.path.join(DATA, "open_shell.brep")}]}, "open shell"),
    ({"inputs": [{"name": "garbage", "file": os.path.join(DATA, "not_a_shape.step")}]}, "garbage"),
    ({"inputs": [{"name": "gone", "file": "/nonexistent/part.step"}]}, "/nonexistent/part.step"),
    (sphere_job(criteria={"default": {"cell_size": float("nan")}}), "criteria.default.cell_size"),
    (sphere_job(criteria={"default": {"cell_size": -1}}), "positive"),
    (sphere_job(criteria={"default": {"cell_size": 1e-4}}), "max_vertices"),
    (sphere_job(engine="delaunay"), "engine must be 'cgal' (Mesh_3) or 'thesis'"),
    # Mesh_3's own error path: it assigns materials by circumcentre only.
    (sphere_job(engine="cgal", material_assignment="barycenter"), "engine 'thesis'"),
    (sphere_job(engine="thesis", initial_points=[[0, 0]]), "initial_points[0]"),
    (sphere_job(engine="cgal", initial_points=[[1, 2, 3]]), "not supported by the 'cgal' engine"),
]


@pytest.mark.parametrize("job, expected", BAD_JOBS)
def test_bad_input_names_input_and_fix(job, expected):
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job)
    assert expected in str(err.value)


def test_open_shell_message_counts_free_edges():
    job = {"inputs": [{"name": "lid_missing", "file": os.path.join(DATA, "open_shell.brep")}]}
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job)
    message = str(err.value)
    assert "lid_missing" in message and "4 free edges" in message


def test_cli_runs_job_file_and_writes_outputs(tmp_path):
    job = sphere_job(order=1, output={"files": ["ball.vtu", "ball.inp"], "report": "report.json"})
    path = tmp_path / "job.json"
    path.write_text(json.dumps(job))
    run = subprocess.run([CLI, str(path)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert "refine" in run.stderr  # progress goes to stderr
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["counts"]["tets"] > 100
    assert "tets" in run.stdout
    assert (tmp_path / "ball.vtu").stat().st_size > 0 and (tmp_path / "ball.inp").stat().st_size > 0


@pytest.mark.parametrize("job, expected", BAD_JOBS)
def test_cli_bad_input_exits_nonzero_with_message(tmp_path, job, expected):
    path = tmp_path / "job.json"
    # JSON has no NaN: the CLI sees the literal and reports where the job stops parsing.
    text = json.dumps(job)
    path.write_text(text)
    run = subprocess.run([CLI, str(path)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stderr
    if "NaN" in text:
        assert "not valid JSON" in run.stderr and "cell_size" in run.stderr
    else:
        assert expected in run.stderr


def test_cli_missing_job_file(tmp_path):
    run = subprocess.run([CLI, str(tmp_path / "missing.json")], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "missing.json" in run.stderr


def test_every_boundary_component_is_meshed():
    """A small part far from a big one: seeds on every input's boundary make Mesh_3 find it
    (its own seeding shoots rays from the bounding-box centre and can miss it)."""
    job = {
        "inputs": [{"name": "big", "sphere": {"center": [0, 0, 0], "radius": 10}, "material": 1},
                   {"name": "small", "sphere": {"center": [40, 0, 0], "radius": 1.0}, "material": 2}],
        "criteria": {"default": {"cell_size": 3, "facet_size": 2, "facet_distance": 0.05},
                     "materials": {"2": {"cell_size": 0.4, "facet_size": 0.3, "facet_distance": 0.005}}},
        "element_order": 2,
    }
    result = oraclemesh.run(job)
    small = result.tets[result.tet_materials == 2]
    assert len(small) > 20
    exact = 4.0 / 3.0 * math.pi
    assert abs(tet10_volume(result.points, small) - exact) < 0.01 * exact
    assert result.report["seeds_on_boundary"] > 0


def test_time_limit_stops_with_a_clear_error():
    job = sphere_job(order=1, criteria={"default": {"cell_size": 0.4, "facet_size": 0.4, "facet_distance": 0.01}},
                     limits={"time_limit": 0.3})
    started = time.time()
    with pytest.raises(oraclemesh.LimitError) as err:
        oraclemesh.run(job)
    assert "limits.time_limit" in str(err.value)
    assert time.time() - started < 5.0  # stopped near the limit, not at the end of meshing
