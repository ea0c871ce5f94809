"""Issue 18: the CLI ends within limits.time_limit even when the meshing thread is stuck where
the core cannot check the limit (a call looping inside OpenCASCADE on a damaged shape): a
watchdog ends the process a grace period after the limit (2 s for limits up to 20 s). Stuck
inside OpenCASCADE on an input, that input is bad: exit code 2 and a message naming it and its
file, as when reading it hangs; stuck anywhere else, exit code 3 and a message naming the job
and the phase. Either way the job's output.report says how it ended. The stall is the CLI's test hook ORACLEMESH_CLI_STALL=<phase> (or
opencascade:<phase>), which blocks the meshing thread as such a call would.
"""
import json
import os
import subprocess
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
PLATE = os.path.abspath(os.path.join(HERE, "..", "data", "plate_200x20x5.brep"))
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build"))
CLI = os.path.join(BUILD, "oraclemesh")
TIME_LIMIT = 2
GRACE = 2
SLACK = 10  # process start and a loaded machine


def ball_job(folder):
    path = os.path.join(folder, "ball.json")
    with open(path, "w") as f:
        json.dump({"inputs": [{"name": "ball", "sphere": {"center": [0, 0, 0], "radius": 1}, "material": 1}],
                   "element_order": 1, "limits": {"time_limit": TIME_LIMIT},
                   "output": {"report": os.path.join(folder, "report.json")},
                   "checks": "warn"}, f)  # a coarse tet4 ball is short of volume; the deadline is tested
    return path


@pytest.mark.parametrize("phase", ["load", "refine"])
def test_stuck_job_ends_after_its_time_limit_with_exit_code_3(phase, tmp_path):
    job = ball_job(str(tmp_path))
    start = time.monotonic()
    run = subprocess.run([CLI, job], capture_output=True, text=True, timeout=60,
                         env=dict(os.environ, ORACLEMESH_CLI_STALL=phase))
    seconds = time.monotonic() - start
    assert run.returncode == 3, (run.returncode, run.stderr[-1000:])
    assert TIME_LIMIT + GRACE <= seconds < TIME_LIMIT + GRACE + SLACK, seconds
    assert "the job '%s' did not end within limits.time_limit = 2 s" % job in run.stderr, run.stderr[-1000:]
    assert "stuck in phase '%s'" % phase in run.stderr
    assert "Part > Check geometry" in run.stderr
    with open(tmp_path / "report.json") as f:
        report = json.load(f)
    assert report["status"] == "stopped" and report["stopped_in"] == phase, report
    assert report["error"] in run.stderr and "did not end within" in report["error"], report
    # The watchdog's clock: the phases the progress went through, the stuck one holding the
    # limit and the grace, and together the total.
    spent = report["seconds"]
    assert TIME_LIMIT + GRACE <= spent["total"] < seconds, spent
    assert spent[phase] > TIME_LIMIT + GRACE - 1, spent
    assert abs(sum(v for k, v in spent.items() if k != "total") - spent["total"]) < 1e-6, spent
    if phase == "refine":
        assert {"load", "initial points"} <= set(spent), spent


def test_job_that_ends_in_time_is_not_stopped(tmp_path):
    run = subprocess.run([CLI, ball_job(str(tmp_path))], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr[-1000:]
    assert "did not end within" not in run.stderr
    with open(tmp_path / "report.json") as f:
        report = json.load(f)
    assert report["status"] == "done" and "error" not in report and report["counts"]["tets"] > 0, report


@pytest.mark.parametrize("phase", ["initial points", "refine"])
def test_job_stuck_in_opencascade_on_an_input_ends_with_exit_code_2_naming_it(phase, tmp_path):
    job = str(tmp_path / "plate.json")
    with open(job, "w") as f:
        json.dump({"inputs": [{"name": "plate", "file": PLATE, "material": 1}], "element_order": 1,
                   "criteria": {"default": {"cell_size": 5, "facet_size": 5, "facet_distance": 0.5}},
                   "limits": {"time_limit": TIME_LIMIT},
                   "output": {"report": str(tmp_path / "report.json")}}, f)
    start = time.monotonic()
    run = subprocess.run([CLI, job], capture_output=True, text=True, timeout=60,
                         env=dict(os.environ, ORACLEMESH_CLI_STALL="opencascade:" + phase))
    seconds = time.monotonic() - start
    assert run.returncode == 2, (run.returncode, run.stderr[-1000:])
    assert TIME_LIMIT + GRACE <= seconds < TIME_LIMIT + GRACE + SLACK, seconds
    assert ("OpenCASCADE did not finish working on input 'plate' (file '%s') within limits.time_limit = 2 s "
            "(and 2 s of grace), in phase '%s'" % (PLATE, phase)) in run.stderr, run.stderr[-1000:]
    assert "Part > Check geometry" in run.stderr and "internal error" not in run.stderr
    with open(tmp_path / "report.json") as f:
        report = json.load(f)
    assert report["status"] == "input_error" and report["stopped_in"] == phase, report
    assert "OpenCASCADE did not finish working on input 'plate'" in report["error"], report
    # The same job stuck outside OpenCASCADE is the job's limit, not the input's fault.
    run = subprocess.run([CLI, job], capture_output=True, text=True, timeout=60,
                         env=dict(os.environ, ORACLEMESH_CLI_STALL=phase))
    assert run.returncode == 3 and "stuck in phase '%s'" % phase in run.stderr, run.stderr[-1000:]
