"""Issue 18, containment in oraclemesh.run: a job in which OpenCASCADE works on the user's
geometry (a STEP, IGES or BREP file, BREP text, a polyline's "brep" edge) runs in a child
process by default, so that OpenCASCADE looping or crashing after the file was read (in the
classifier or intersector, where the core cannot check its time limit) ends at
limits.time_limit plus the grace with an oraclemesh.Error and the interpreter goes on meshing:
an InputError naming the input and its file when the child was inside OpenCASCADE on it (the
CLI's exit code 2), a LimitError naming the phase and the B-rep inputs when it was stuck
elsewhere (the CLI's 3). The same job gives the same INP bytes either way. In each case the
job's output.report says how it ended, as the core's report of an unfinished job does.

Real inputs on which OpenCASCADE ran long after reading are now refused while reading
(domain/brep/ToleranceCheck): tests/data/part_long_initial_points.step (part.step with three
bytes changed: 6.7 s per classification in phase 'initial points') has an edge OpenCASCADE
widened to 9.5 mm; tests/data/bad/cad/brep_classifier_hang.brep (test_bad_cad_inputs.py) an
edge whose curve ends 11.5 mm from its vertex.
Crashes and endless hangs are the worker's test hooks (ORACLEMESH_WORKER_HANG / _CRASH =
phase, HANG = opencascade:phase inside OpenCASCADE on the first input): they block or kill the
child where the core reports that phase, as a call looping or crashing inside OpenCASCADE would.
"""
import json
import os
import signal
import time

import numpy as np
import pytest

import oraclemesh
from test_job_contract import sphere_job
from worker_processes import live_worker_children  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
PLATE = os.path.join(HERE, "..", "data", "plate_200x20x5.brep")
LONG_INITIAL_POINTS = os.path.abspath(os.path.join(HERE, "..", "data", "part_long_initial_points.step"))
TIME_LIMIT = 2
GRACE = 2       # oraclemesh's rule for limits up to 20 s, as the CLI's
SLACK = 10      # process start and a loaded machine


def plate_job(**extra):
    job = {"inputs": [{"name": "plate", "file": os.path.abspath(PLATE), "material": 1}],
           "criteria": {"default": {"cell_size": 5, "facet_size": 5, "facet_distance": 0.5}},
           "element_order": 2}
    job.update(extra)
    return job


def ran_in_a_child(job, **options):
    """Whether run() meshed the job in an oraclemesh.worker child, and the result."""
    seen = set()

    def progress(phase, fraction):
        seen.add(bool(live_worker_children()))  # the last reports may come after the child ended
        return True

    result = oraclemesh.run(job, progress=progress, **options)
    assert seen and len(result.tets) > 0
    return True in seen


def test_brep_jobs_run_in_a_child_and_others_in_this_process():
    assert ran_in_a_child(plate_job(element_order=1))
    assert not ran_in_a_child(sphere_job(order=1))
    assert not ran_in_a_child(plate_job(element_order=1), isolated=False)
    assert ran_in_a_child(sphere_job(order=1), isolated=True)


def test_what_counts_as_opencascade_geometry():
    job = {"inputs": [{"name": "a", "file": "a.STP"}, {"name": "b", "file": "b.stl"}, {"name": "c", "brep": "x"},
                      {"name": "d", "file": "d.igs"}, {"name": "e", "sphere": {}}],
           "features": {"polylines": [[[0, 0, 0], [1, 0, 0]], {"points": [], "brep": "y"}]}}
    assert oraclemesh._opencascade_inputs(job) == [
        "input 'a' (file 'a.STP')", "input 'c' (BREP text)", "input 'd' (file 'd.igs')",
        "features.polylines[1] (BREP edge)"]
    assert oraclemesh._opencascade_inputs(sphere_job(order=1)) == []
    assert oraclemesh._opencascade_inputs(None) == []


def test_same_inp_bytes_in_a_child_and_in_this_process(tmp_path):
    here, there = tmp_path / "here.inp", tmp_path / "there.inp"
    a = oraclemesh.run(plate_job(output={"files": [str(here)]}), isolated=False)
    b = oraclemesh.run(plate_job(output={"files": [str(there)]}))
    assert here.read_bytes() == there.read_bytes() and len(here.read_bytes()) > 10000
    for name in oraclemesh.Result.ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert getattr(a, name).dtype == getattr(b, name).dtype, name
    assert [s["name"] for s in a.surfaces] == [s["name"] for s in b.surfaces]
    assert all(np.array_equal(s["faces"], t["faces"]) for s, t in zip(a.surfaces, b.surfaces))
    assert a.report["counts"] == b.report["counts"]


@pytest.mark.parametrize("phase", ["features", "refine"])
def test_hang_after_reading_ends_at_the_time_limit_naming_the_file(phase, monkeypatch, tmp_path):
    monkeypatch.setenv("ORACLEMESH_WORKER_HANG", phase)
    job = plate_job(limits={"time_limit": TIME_LIMIT}, output={"report": str(tmp_path / "report.json")})
    start = time.monotonic()
    with pytest.raises(oraclemesh.LimitError) as err:
        oraclemesh.run(job)
    seconds = time.monotonic() - start
    assert TIME_LIMIT + GRACE <= seconds < TIME_LIMIT + GRACE + SLACK, seconds
    message = str(err.value)
    assert "did not end within limits.time_limit = 2 s (and 2 s of grace)" in message, message
    assert "stuck in phase '%s'" % phase in message, message
    assert "input 'plate' (file '%s')" % os.path.abspath(PLATE) in message, message
    assert "Part > Check geometry" in message
    assert reported(tmp_path) == {"status": "stopped", "error": message, "stopped_in": phase}
    monkeypatch.delenv("ORACLEMESH_WORKER_HANG")
    assert len(oraclemesh.run(plate_job(element_order=1)).tets) > 0


def reported(folder):
    with open(folder / "report.json") as f:
        return json.load(f)


@pytest.mark.parametrize("phase", ["initial points", "refine"])
def test_hang_inside_opencascade_after_reading_is_an_input_error_naming_the_file(phase, monkeypatch, tmp_path):
    monkeypatch.setenv("ORACLEMESH_WORKER_HANG", "opencascade:" + phase)
    start = time.monotonic()
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(plate_job(limits={"time_limit": TIME_LIMIT}, output={"report": str(tmp_path / "report.json")}))
    seconds = time.monotonic() - start
    assert TIME_LIMIT + GRACE <= seconds < TIME_LIMIT + GRACE + SLACK, seconds
    message = str(err.value)
    assert ("OpenCASCADE did not finish working on input 'plate' (file '%s') within limits.time_limit = 2 s "
            "(and 2 s of grace), in phase '%s'" % (os.path.abspath(PLATE), phase)) in message, message
    assert "Part > Check geometry" in message
    assert reported(tmp_path) == {"status": "input_error", "error": message, "stopped_in": phase}
    monkeypatch.delenv("ORACLEMESH_WORKER_HANG")
    assert len(oraclemesh.run(plate_job(element_order=1)).tets) > 0


def test_real_file_opencascade_ran_long_on_is_refused_while_reading():
    job = {"inputs": [{"name": "part", "file": LONG_INITIAL_POINTS, "material": 1}], "element_order": 1,
           "criteria": {"default": {"cell_size": 4, "facet_size": 4, "facet_distance": 0.5}},
           "limits": {"time_limit": 1}}
    start = time.monotonic()
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job)
    assert time.monotonic() - start < 1 + GRACE + SLACK
    message = str(err.value)
    assert "input 'part' (file '%s'): edge 33 of 70" % LONG_INITIAL_POINTS in message, message
    assert "has a tolerance of 9.5251" in message and "Part > Check geometry" in message, message
    assert len(oraclemesh.run(plate_job(element_order=1)).tets) > 0


def test_crash_after_reading_is_an_error_naming_the_file(monkeypatch, tmp_path):
    monkeypatch.setenv("ORACLEMESH_WORKER_CRASH", "refine")
    with pytest.raises(oraclemesh.Error) as err:
        oraclemesh.run(plate_job(output={"report": str(tmp_path / "report.json")}))
    message = str(err.value)
    assert reported(tmp_path) == {"status": "error", "error": message, "stopped_in": "refine"}
    assert "crashed" in message and "signal %d" % signal.SIGSEGV in message, message
    assert "in phase 'refine'" in message and "plate_200x20x5.brep" in message, message
    monkeypatch.delenv("ORACLEMESH_WORKER_CRASH")
    assert len(oraclemesh.run(plate_job(element_order=1)).tets) > 0


def test_a_job_file_and_its_relative_paths_run_in_the_child(tmp_path):
    import json
    import shutil
    shutil.copy(PLATE, tmp_path / "plate.brep")
    job = plate_job(element_order=1, output={"files": ["plate.inp"]})
    job["inputs"][0]["file"] = "plate.brep"
    (tmp_path / "job.json").write_text(json.dumps(job))
    assert ran_in_a_child(str(tmp_path / "job.json"))
    assert (tmp_path / "plate.inp").stat().st_size > 0


def test_callback_exception_and_cancel_in_a_brep_job():
    class Stop(Exception):
        pass

    def raising(phase, fraction):
        raise Stop("in " + phase)

    with pytest.raises(Stop, match="in load"):
        oraclemesh.run(plate_job(), progress=raising)
    with pytest.raises(oraclemesh.Cancelled):
        oraclemesh.run(plate_job(), progress=lambda phase, fraction: phase != "refine")
    assert len(oraclemesh.run(plate_job(element_order=1)).tets) > 0
