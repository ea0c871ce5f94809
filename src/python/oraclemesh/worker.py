"""Child-process side of oraclemesh.run_isolated: `python3 -m oraclemesh.worker JOB RESULT`.

Runs the job in its own process so that a crash of the native core (a segfault in CGAL or
OpenCASCADE) ends this process, not FreeCAD. Speaks to the parent through:
  stdout  one line per progress report: "progress <fraction> <phase>"
  RESULT  an .npz with the result arrays and the report (on success, exit 0)
  RESULT.error.json  {"type": "InputError", "message": ...} (on an oraclemesh.Error, exit 2)

Test hook: ORACLEMESH_WORKER_CRASH=<phase> makes this process die of a real segmentation
fault when the core first reports that phase (after passing the report on), so callers (FreeCAD tests) can check that a
crash of the native code becomes an error message in the parent.
ORACLEMESH_WORKER_HANG=<phase> makes it stop there for good instead (a core stuck where it
reports no progress), so callers can check that their own deadline ends it (oraclemesh.study).
"""
import ctypes
import os
import json
import sys
import time

import numpy as np

import oraclemesh

# Environment variable through which the caller gives its pid (see die_with_parent).
PARENT_VARIABLE = "ORACLEMESH_WORKER_PARENT"

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


def main(job_path, result_path):
    die_with_parent()
    crash_phase = os.environ.get("ORACLEMESH_WORKER_CRASH")
    hang_phase = os.environ.get("ORACLEMESH_WORKER_HANG")

    def progress(phase, fraction):
        # The report goes out first: a core crashing or stuck inside a phase has reported it.
        sys.stdout.write("progress %.6f %s\n" % (fraction, phase))
        sys.stdout.flush()
        if phase == crash_phase:
            ctypes.string_at(0)  # reads address 0: SIGSEGV, as a bug in CGAL would
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
