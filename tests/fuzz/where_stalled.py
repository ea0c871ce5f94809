"""Where OpenCASCADE stalls on a B-rep file: runs the helper oraclemesh-shape-reader on it (what
the CLI does first with a file input: read, checks, sewing, tessellation, a probe of the
classifier and intersector) and, if it is still running after SECONDS, names the phase from
its stack (gdb). The CLI's own message says only "did not finish reading".

    /usr/bin/python3 tests/fuzz/where_stalled.py [--seconds 5] FILE...

Prints one line a file: finished (exit code), or stalled and the phase with the OpenCASCADE
frames that named it.
"""
import argparse
import os
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
HELPER = os.path.join(os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build")),
                      "oraclemesh-shape-reader")

# Checked from the first to the last: a tessellation called by the transfer's healing is tessellation.
PHASES = [
    ("tessellation (BRepMesh)", ("BRepMesh",)),
    ("classifier", ("BRepClass3d", "probeQueries")),
    ("sewing", ("BRepBuilderAPI_Sewing",)),
    ("transfer (shape healing)", ("ShapeFix", "ShapeUpgrade", "ShapeAnalysis")),
    ("transfer", ("TransferRoots", "TransferOne", "Transfer_", "StepToTopoDS", "IGESToBRep")),
    ("parsing", ("ReadFile", "StepFile", "IGESFile", "BRepTools::Read", "BRepTools_ShapeSet")),
]


def stack_of(pid):
    run = subprocess.run(["gdb", "-p", str(pid), "-batch", "-ex", "thread apply all bt"],
                         capture_output=True, text=True, timeout=120)
    return [line for line in run.stdout.splitlines() if line.startswith("#")]


def phase_of(frames):
    for phase, marks in PHASES:
        hits = [f for f in frames if any(m in f for m in marks)]
        if hits:
            return phase, hits
    core = [f for f in frames if "oraclemesh::" in f]  # the innermost of the core's own frames
    return "other", frames[:8] + core[:1]


def where_stalled(path, seconds):
    """("finished", exit code, the helper's error message) or ("stalled", phase, frames naming it)."""
    with tempfile.TemporaryDirectory() as out:
        helper = subprocess.Popen([HELPER, "--file", os.path.abspath(path), out, "part", "separate", str(os.getpid())],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        end = time.monotonic() + seconds
        while time.monotonic() < end and helper.poll() is None:
            time.sleep(0.05)
        if helper.poll() is not None:
            error = os.path.join(out, "error.txt")
            message = open(error, errors="replace").read() if os.path.exists(error) else ""
            return ("finished", helper.returncode, message)
        frames = stack_of(helper.pid)
        helper.kill()
        helper.wait()
        phase, hits = phase_of(frames)
        return ("stalled", phase, hits)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("files", nargs="+")
    parser.add_argument("--seconds", type=float, default=5)
    args = parser.parse_args()
    for path in args.files:
        result = where_stalled(path, args.seconds)
        if result[0] == "finished":
            print("%s: finished, exit code %d %s" % (path, result[1], result[2][:300]))
        else:
            print("%s: stalled in %s" % (path, result[1]))
            for frame in result[2][:6]:
                print("    " + frame[:200])


if __name__ == "__main__":
    main()
