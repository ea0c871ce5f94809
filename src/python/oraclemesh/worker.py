"""Child-process side of oraclemesh.run_isolated: `python3 -m oraclemesh.worker JOB RESULT`.

Runs the job in its own process so that a crash of the native core (a segfault in CGAL or
OpenCASCADE) ends this process, not FreeCAD. Speaks to the parent through:
  stdout  one line per progress report: "progress <fraction> <phase>"
  RESULT  an .npz with the result arrays and the report (on success, exit 0)
  RESULT.error.json  {"type": "InputError", "message": ...} (on an oraclemesh.Error, exit 2)

ORACLEMESH_WORKER_DEADLINE="<time limit> <grace>" (run_isolated's hard deadline): that long after
the core's first report, a core stuck inside OpenCASCADE on one of the job's inputs ends this
process with an InputError naming the input (as the CLI's deadline does: exit code 2), before the
parent's own deadline kills it as a LimitError.

Test hook: ORACLEMESH_WORKER_CRASH=<phase> makes this process die of a real segmentation
fault when the core first reports that phase (after passing the report on), so callers (FreeCAD tests) can check that a
crash of the native code becomes an error message in the parent.
ORACLEMESH_WORKER_HANG=<phase> makes it stop there for good instead (a core stuck where it
reports no progress), so callers can check that their own deadline ends it (oraclemesh.study);
ORACLEMESH_WORKER_HANG=opencascade:<phase> stops it as inside OpenCASCADE on the job's first input.
"""
import ctypes
import os
import json
import sys
import threading
import time

import numpy as np

import oraclemesh

# Environment variable through which the caller gives its pid (see die_with_parent).
PARENT_VARIABLE = "ORACLEMESH_WORKER_PARENT"
# ... and its hard deadline, "<time limit> <grace>" (see judge_opencascade_stall).
DEADLINE_VARIABLE = "ORACLEMESH_WORKER_DEADLINE"

def die_with_parent():
    """Linux: end this process when the caller (FreeCAD) ends, so a killed or crashed caller
    leaves no meshing process behind."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        # The caller names itself: a caller killed while this process was still starting up
        # (imports take a second or more on a loaded machine) has already handed it to a new
        # parent, so the parent seen here would be the wrong one to compare with.
        expected = os.environ.get(PARENT_VARIABLE, "")
        parent = int(expected) if expected.isdigit() else os.getppid()
        libc.prctl(1, 9)  # PR_SET_PDEATHSIG, SIGKILL
        if os.getppid() != parent:  # the parent ended before prctl took effect
            os._exit(3)
    except (OSError, AttributeError):
        pass  # not Linux: the caller's cancel still kills this process


def judge_opencascade_stall(job_path, result_path, limit, grace, started, phase):
    """At the deadline (limit + grace after the core's first report, the parent's rule): if
    the meshing thread is inside OpenCASCADE on an input, that input's geometry is the cause,
    so this process ends with that InputError; otherwise the parent's deadline ends it."""
    started.wait()
    time.sleep(limit + grace)
    with open(job_path) as f:
        text = f.read()
    message = oraclemesh._core.opencascade_stall(text, os.path.dirname(os.path.abspath(job_path)), limit, grace,
                                                 phase[0])
    if message:
        with open(result_path + ".error.json", "w") as f:
            json.dump({"type": "InputError", "message": message}, f)
        oraclemesh._report_killed_child(json.loads(text), "input_error", message, phase[0])
        os._exit(2)  # the meshing thread cannot be stopped: no clean exit


def main(job_path, result_path):
    die_with_parent()
    crash_phase = os.environ.get("ORACLEMESH_WORKER_CRASH")
    hang_phase = os.environ.get("ORACLEMESH_WORKER_HANG", "")
    if hang_phase.startswith("opencascade:"):
        with open(job_path) as f:
            first_input = json.load(f)["inputs"][0]["name"]
    started, phase_now = threading.Event(), [""]
    deadline = os.environ.get(DEADLINE_VARIABLE, "").split()
    if len(deadline) == 2:
        oraclemesh._core.watch_opencascade_in_this_thread()
        threading.Thread(target=judge_opencascade_stall, daemon=True,
                         args=(job_path, result_path, float(deadline[0]), float(deadline[1]), started,
                               phase_now)).start()

    def progress(phase, fraction):
        phase_now[0] = phase
        started.set()
        # The report goes out first: a core crashing or stuck inside a phase has reported it.
        sys.stdout.write("progress %.6f %s\n" % (fraction, phase))
        sys.stdout.flush()
        if phase == crash_phase:
            ctypes.string_at(0)  # reads address 0: SIGSEGV, as a bug in CGAL would
        if hang_phase.startswith("opencascade:") and phase == hang_phase.split(":", 1)[1]:
            oraclemesh._core.hang_in_opencascade(first_input)
        while phase == hang_phase:
            time.sleep(3600)  # the core's own time limit cannot fire while this blocks

    try:
        result = oraclemesh.run(job_path, progress=progress, isolated=False)  # this is the isolation
    except oraclemesh.Error as e:
        with open(result_path + ".error.json", "w") as f:
            json.dump({"type": type(e).__name__, "message": str(e)}, f)
        return 2
    np.savez(result_path, report=np.array(json.dumps(result.report)),
             **{name: getattr(result, name) for name in oraclemesh.Result.ARRAYS}, **result.surface_arrays())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
