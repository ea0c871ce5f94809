"""Issue 18, containment: damaged STEP, IGES and BREP files (OpenCASCADE segfaults or loops on them),
non-finite geometry and models far from the origin end, through the CLI and oraclemesh.run, in
an InputError naming the input within the job's time limit (exit code 2, never a signal), and
the interpreter goes on meshing afterwards.

tests/data/bad/cad/ holds the regression inputs: B-rep files (each read by a job made here, with
a short time limit) and jobs (*.json, run as they are). EXPECTED says what each message must name.
"""
import glob
import json
import os
import subprocess
import threading
import time

import pytest

import oraclemesh

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "..", "data", "bad", "cad")
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build"))
CLI = os.path.join(BUILD, "oraclemesh")
TIME_LIMIT = 4  # seconds: the hangs below end at it
# Files whose loop ends on some machines: a limit well under the time they take where it does
# (brep_tessellation_hang.brep: read and tessellated in 3.7 s on a 2-core machine in 2026-12).
TIME_LIMITS = {"brep_tessellation_hang.brep": 1}
SLACK = 15      # process starts, the mesher's own checkpoint, a loaded machine

CRASHED = "OpenCASCADE crashed reading"
HUNG = "OpenCASCADE did not finish reading"
TOLERANCE_5MM = ["box_edge_curve_misspelt.step", "edge 1 of 11, from (0, 0, 0) to (0, 0, 5), has a tolerance of 5.00005",
                 "the file is damaged", "Part > Check geometry"]
EXPECTED = {
    # random byte changes of screw.step: segfaults in the STEP reader after "Unresolved Reference"
    "step_reader_crash.step": [CRASHED, "step_reader_crash.step", "Part > Check geometry"],
    # a truncated BREP: BRep_CurveOnSurface::Update loops while reading
    "brep_reader_loop.brep": [HUNG, "brep_reader_loop.brep"],
    # part.step's BREP export with one space made a digit: edge 15's curve range and location
    # changed, its curve ends 11.5 mm from its vertex; OpenCASCADE's exact classifier
    # (BRepClass3d_SClassifier, Extrema_ExtCC) then took seconds a point: refine at 0 % after
    # 120 s (exit 3, "coarsen the sizes or raise limits.time_limit"). Refused while reading now.
    "brep_classifier_hang.brep": ["brep_classifier_hang.brep", "edge 15 of 70 whose curve ends at",
                                  "11.5481 model units from its vertex", "the file is damaged there",
                                  "Part > Check geometry"],
    # a mutated BREP: BRepMesh_Delaun loops while tessellating (or takes seconds: TIME_LIMITS)
    "brep_tessellation_hang.brep": [HUNG, "brep_tessellation_hang.brep"],
    # NaN in a vertex and in a surface: used to reach GMP through CGAL (SIGFPE)
    "nan_vertex.brep": ["non-finite number", "nan_vertex.brep", "vertex 1"],
    "nan_surface.brep": ["non-finite number", "nan_surface.brep", "face 1"],
    # NaN and 1.E999 in a CARTESIAN_POINT: the transfer's shape healing used to loop on them
    "nan_point.step": ["not a finite number", "nan_point.step", "entity #24"],
    "inf_point.step": ["not a finite number", "inf_point.step", "entity #24"],
    # 1.D999 for a line's start x in an IGES box (FreeCAD's export): the transfer looped on it
    "inf_line.iges": ["not finite (1.D999)", "inf_line.iges", "IGES entity DE 11"],
    # parameter lines and no directory entry: OpenCASCADE's IGES parser used the previous file's
    # freed entry for them (a segfault when the process had read an IGES file before)
    "iges_without_directory.iges": ["iges_without_directory.iges", "its parameter data (line 3) comes before any "
                                    "directory entry", "export it again"],
    # the first half of that box's IGES file
    "truncated_box.iges": ["holds no shape OpenCASCADE can transfer", "truncated_box.iges"],
    # box.step with one plane's CARTESIAN_POINT and one EDGE_CURVE misspelt: OpenCASCADE widened
    # three edges' tolerance to 5 mm; the thesis engine ended in an "internal error" (feature
    # edges no tet edges), Mesh_3 in an endless edge protection. Both engines, the finding's sizes.
    "box_edge_curve_misspelt.step": TOLERANCE_5MM,
    "box_edge_curve_misspelt_thesis.json": TOLERANCE_5MM,
    "box_edge_curve_misspelt_cgal.json": TOLERANCE_5MM,
    # tube.step with one line's VECTOR magnitude 1. made 0. (and a PCURVE_S1 made S3), from
    # tests/fuzz/mutate_cli.py --digits-only: OpenCASCADE bounds the solid at 1e100, and the
    # thesis engine said "produced no tetrahedra: the inputs may be smaller than the sizes"
    "tube_zero_vector.step": ["tube_zero_vector.step", "has coordinates of 1e+100 model units",
                              "an unbounded curve or surface", "Part > Check geometry"],
    # tube.step with SURFACE_CURVE and .PCURVE_S1. misspelt and REPRESENTATION cut
    # (mutate_cli.py, seed 1806): OpenCASCADE transfers an invalid tube of 4 edges instead of 6
    # that encloses 2.75 of its 175.9 mm^3, the engine makes no tetrahedron; the message used to
    # name neither the input nor the invalid CAD
    "tube_surface_curve_misspelt.step": ["produced no tetrahedra", "'part' (file ", "tube_surface_curve_misspelt.step",
                                         "encloses 2.749 model units^3 in a box of 252", "Part > Check geometry"],
    # a box at x = 1e20
    "far_box.brep": ["from the origin", "far_box.brep", "move the model near the origin"],
    # a sphere of radius 5 at x = 1e20, both engines: used to segfault in insertInitialPoints
    "far_sphere_thesis.json": ["input 'ball' lies 1e+20 model units from the origin"],
    "far_sphere_cgal.json": ["input 'ball' lies 1e+20 model units from the origin"],
}
BAD_INPUTS = sorted(os.path.basename(p) for p in glob.glob(os.path.join(BAD, "*")))


def small_ball():
    # tet10: in tet4 the coarse ball is short of its volume, which the default checks refuse.
    return {"inputs": [{"name": "ball", "sphere": {"center": [0, 0, 0], "radius": 1}, "material": 1}],
            "criteria": {"default": {"cell_size": 0.5, "facet_size": 0.5, "facet_distance": 0.05}},
            "element_order": 2}


def job_file(name, folder):
    """The job that reads tests/data/bad/cad/<name>: the file itself when it is a job."""
    if name.endswith(".json"):
        return os.path.join(BAD, name)
    job = {"inputs": [{"name": "part", "file": os.path.join(os.path.abspath(BAD), name), "material": 1}],
           "element_order": 1, "limits": {"time_limit": TIME_LIMITS.get(name, TIME_LIMIT)}}
    path = os.path.join(folder, name + ".json")
    with open(path, "w") as f:
        json.dump(job, f)
    return path


def test_every_bad_input_has_its_expectation():
    assert set(BAD_INPUTS) == set(EXPECTED)


@pytest.mark.parametrize("name", BAD_INPUTS)
def test_cli_refuses_bad_cad_input_with_exit_code_2_in_time(name, tmp_path):
    start = time.monotonic()
    run = subprocess.run([CLI, job_file(name, str(tmp_path))], capture_output=True, text=True,
                         timeout=TIME_LIMIT + 60)
    seconds = time.monotonic() - start
    assert run.returncode == 2, (run.returncode, run.stderr[-2000:])  # a signal is negative
    assert seconds < TIME_LIMIT + SLACK, seconds
    assert "internal error" not in run.stderr
    for part in EXPECTED[name]:
        assert part in run.stderr, (part, run.stderr[-2000:])


@pytest.mark.parametrize("name", BAD_INPUTS)
def test_run_refuses_bad_cad_input_and_still_works_afterwards(name, tmp_path):
    start = time.monotonic()
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job_file(name, str(tmp_path)))
    assert time.monotonic() - start < TIME_LIMIT + SLACK
    for part in EXPECTED[name]:
        assert part in str(err.value), (part, str(err.value))
    assert len(oraclemesh.run(small_ball()).tets) > 0


def test_progress_callback_cancels_while_a_file_is_read(tmp_path):
    job = json.load(open(job_file("brep_reader_loop.brep", str(tmp_path))))
    job["limits"]["time_limit"] = 600
    calls = []

    def progress(phase, fraction):
        calls.append(phase)
        return len(calls) < 3  # the reader loops: only the wait for it reports

    start = time.monotonic()
    with pytest.raises(oraclemesh.Cancelled):
        oraclemesh.run(job, progress=progress)
    assert time.monotonic() - start < 10
    assert calls == ["load"] * 3
    assert len(oraclemesh.run(small_ball()).tets) > 0


def test_reading_in_threads_at_once():
    """The helper is spawned, not forked: several Python threads may read at the same time."""
    part = os.path.join(os.environ.get("ORACLEMESH_CAD_DIR", os.path.join(HERE, "..", "..", "..", "shared",
                                                                           "data", "cad")), "screw.step")
    # Coarse: the reading is what is tested (a second at this size, a minute at cell size 3).
    job = {"inputs": [{"name": "screw", "file": part, "material": 1}], "element_order": 1,
           "criteria": {"default": {"cell_size": 10, "facet_size": 10, "facet_distance": 1}},
           "checks": "warn"}  # the thread is coarser than these sizes
    results, errors = [], []

    def mesh():
        try:
            results.append(len(oraclemesh.run(job).tets))
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=mesh) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert len(results) == 2 and results[0] == results[1] > 0


def test_installed_cli_finds_its_helper(tmp_path):
    """cmake --install puts the helper in libexec/oraclemesh, where the installed CLI looks."""
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", BUILD, "--prefix", str(prefix)],
                   check=True, capture_output=True)
    assert (prefix / "libexec" / "oraclemesh" / "oraclemesh-shape-reader").is_file()
    job = tmp_path / "job.json"
    job.write_text(json.dumps({"inputs": [{"name": "bad", "file": os.path.join(os.path.abspath(BAD), "nan_vertex.brep"),
                                           "material": 1}]}))
    env = dict(os.environ)
    env.pop("ORACLEMESH_SHAPE_READER", None)
    run = subprocess.run([str(prefix / "bin" / "oraclemesh"), str(job)], capture_output=True, text=True, env=env,
                         timeout=60)
    # The helper read the file: its finite check, not "cannot find its helper", is the answer.
    assert run.returncode == 2 and "non-finite number" in run.stderr, run.stderr[-2000:]
