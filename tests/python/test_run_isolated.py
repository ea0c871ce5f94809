"""oraclemesh.run_isolated: the core in a child process, so its crash cannot end the caller
(FreeCAD). Same results as run(), errors with their types, cancel, and a real crash."""
import os
import signal

import numpy as np
import pytest

import oraclemesh
from test_job_contract import sphere_job
from worker_processes import live_worker_children  # noqa: E402


def worker_pids():
    """This test process's live oraclemesh.worker children (other runs may have their own)."""
    return live_worker_children()


def test_same_mesh_as_in_process():
    job = sphere_job(order=2)
    here = oraclemesh.run(job)
    there = oraclemesh.run_isolated(job)
    assert np.array_equal(here.points, there.points)
    assert np.array_equal(here.tets, there.tets)
    assert np.array_equal(here.tet_materials, there.tet_materials)
    assert there.report["counts"] == here.report["counts"]


def test_errors_keep_their_type_and_message():
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run_isolated(sphere_job(criteria={"default": {"cell_size": 1e-4}}))
    assert "max_vertices" in str(err.value)


def test_cancel_ends_the_child():
    with pytest.raises(oraclemesh.Cancelled):
        oraclemesh.run_isolated(sphere_job(order=1), progress=lambda phase, f: phase != "refine")
    assert worker_pids() == []


def test_crash_of_the_core_is_an_error_not_a_crash():
    def crash(phase, fraction):
        if phase == "refine":
            for pid in worker_pids():
                os.kill(pid, signal.SIGSEGV)  # what a segfault in CGAL would do
        return True

    with pytest.raises(oraclemesh.Error) as err:
        oraclemesh.run_isolated(sphere_job(order=1), progress=crash)
    assert "crashed" in str(err.value) and "signal %d" % signal.SIGSEGV in str(err.value)


def test_worker_crash_hook_is_a_real_segfault(monkeypatch):
    # The FreeCAD tests force a crash through this hook; it must be a real SIGSEGV of the child.
    monkeypatch.setenv("ORACLEMESH_WORKER_CRASH", "refine")
    with pytest.raises(oraclemesh.Error) as err:
        oraclemesh.run_isolated(sphere_job(order=1))
    assert "crashed" in str(err.value) and "signal %d" % signal.SIGSEGV in str(err.value)
    assert worker_pids() == []


def test_cancel_event_ends_the_child_without_a_progress_report():
    # The event is set from another thread and no progress callback follows (as in sliver
    # perturbation, which reports nothing): the child must still end at once.
    import threading
    import time
    cancel = threading.Event()
    marks = {}

    def progress(phase, fraction):
        if "set" not in marks:
            def set_later():
                marks["set"] = time.time()
                cancel.set()
            threading.Timer(0.3, set_later).start()
            marks["set"] = None
        return True

    with pytest.raises(oraclemesh.Cancelled):
        # ~3 s of meshing here (0.3 s at cell size 1 since Mesh_3 uses exact crossings).
        oraclemesh.run_isolated(sphere_job(order=2, criteria={"default": {"cell_size": 0.5}}),
                                progress=progress, cancel=cancel)
    assert time.time() - marks["set"] < 1.0
    assert worker_pids() == []


def test_worker_ends_when_its_caller_is_killed(tmp_path):
    # A caller (FreeCAD) killed mid-mesh must not leave the meshing process running, also in
    # phases that write no progress (a broken stdout pipe would not end the worker then). The
    # worker's stdout goes to a file here, so only the parent-death signal can end it.
    import json
    import subprocess
    import sys
    import time
    job = tmp_path / "job.json"
    # About 1.2 million tets: 30 s or more of meshing, long enough to tell a worker that
    # ended with its caller from one that finished its job.
    job.write_text(json.dumps(sphere_job(order=2, criteria={"default": {"cell_size": 0.25}})))
    caller = subprocess.Popen(
        [sys.executable, "-c",
         "import os, subprocess, sys, time\n"
         "out = open(sys.argv[2], 'w')\n"
         "env = dict(os.environ, ORACLEMESH_WORKER_PARENT=str(os.getpid()))\n"
         "w = subprocess.Popen([sys.executable, '-m', 'oraclemesh.worker', sys.argv[1], "
         "sys.argv[3]], stdout=out, env=env)\n"
         "print(w.pid, flush=True)\n"
         "time.sleep(120)\n",
         str(job), str(tmp_path / "progress.txt"), str(tmp_path / "result.npz")],
        stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    child = int(caller.stdout.readline())
    time.sleep(1.0)  # the worker is starting up or meshing
    caller.kill()
    caller.wait()
    # A worker still importing when its caller died ends as soon as it reaches prctl; on a
    # loaded machine that can take seconds. Without the parent-death signal it would mesh on
    # for 30 s or more, so 15 s of waiting still tells the two apart.
    deadline = time.monotonic() + 15
    while True:
        try:
            with open("/proc/%d/stat" % child) as f:
                state = f.read().rsplit(")", 1)[1].split()[0]
        except OSError:
            state = "gone"
        if state in ("gone", "Z") or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    if state not in ("gone", "Z"):
        os.kill(child, signal.SIGKILL)
    assert state in ("gone", "Z"), "the worker outlived its caller (state %s)" % state
