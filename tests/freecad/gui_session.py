"""Runs a script of scripts/ once in the real FreeCAD GUI under Xvfb, with the workbench
installed by cmake/install-workbench.sh into a scratch HOME (the GUI tests' fixtures).

The script writes its measurements as JSON to $OMFC_RESULT (see gui_script.py) and may leave
a trail of steps in $OMFC_RESULT.steps, so a GUI crash shows where it happened. Outputs go to
ORACLEMESH_TEST_OUTPUT/freecad/<name> when that is set, else to a pytest temporary folder.
"""
import json
import os
import signal
import shutil
import subprocess
import sys

import pytest

from fc_testenv import BUILD, REPO, core_available

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from installed import require_programs  # noqa: E402

# program -> the Debian package that cmake/install-deps.sh installs it from
GUI_PROGRAMS = {"xvfb-run": "xvfb", "xauth": "xauth", "freecad": "freecad"}


def run_gui_script(tmp_path_factory, script, name, timeout=600):
    """The dict the script wrote; fails the test when the run wrote none or not ok."""
    require_programs(GUI_PROGRAMS)
    if not core_available():
        pytest.fail("the core under test is missing: build the project first")
    tmp = tmp_path_factory.mktemp(name)
    base = os.environ.get("ORACLEMESH_TEST_OUTPUT")
    workdir = os.path.join(base, "freecad", name) if base else str(tmp)
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    home = tmp / "home"
    home.mkdir()
    result = os.path.join(workdir, name + ".json")
    env = dict(os.environ, HOME=str(home), OMFC_RESULT=result, OMFC_WORKDIR=workdir,
               # FreeCAD's start page uses QtWebEngine, which refuses to run as root sandboxed.
               QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox")
    env.pop("XDG_DATA_HOME", None)
    env.pop("ORACLEMESH_WORKER_CRASH", None)
    subprocess.run(["bash", os.path.join(REPO, "cmake", "install-workbench.sh"), BUILD],
                   env=env, check=True, capture_output=True)
    # A session of its own, so that a timeout ends FreeCAD and Xvfb too, not only xvfb-run.
    proc = subprocess.Popen(
        ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad",
         os.path.join(REPO, "tests", "freecad", "scripts", script)],
        env=env, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        log = out + err
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        log = "timeout after %d s" % timeout
    with open(os.path.join(workdir, name + ".log"), "w") as f:
        f.write(log)
    steps = result + ".steps"
    trail = open(steps).read() if os.path.exists(steps) else ""
    if not os.path.exists(result):
        pytest.fail("the GUI run wrote no result; steps reached:\n%s\n%s" % (trail, log[-3000:]))
    with open(result) as f:
        r = json.load(f)
    assert r["ok"], "%s\nsteps:\n%s" % (r.get("traceback"), trail)
    return r
