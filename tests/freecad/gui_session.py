"""Run one script of scripts/ in the real FreeCAD GUI under Xvfb, with the workbench installed
by cmake/install-workbench.sh into a scratch HOME; the script writes its measurements as JSON
to $OMFC_RESULT and its trail of steps to $OMFC_RESULT.steps (a GUI crash shows where)."""
import json
import os
import shutil
import subprocess
import sys

import pytest

from fc_testenv import BUILD, REPO, core_available

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from installed import require_programs  # noqa: E402

# program -> the Debian package that cmake/install-deps.sh installs it from
GUI_PROGRAMS = {"xvfb-run": "xvfb", "xauth": "xauth", "freecad": "freecad"}


def run_gui_script(script, name, tmp_path_factory, timeout=600, env=None):
    """Run scripts/<script> in the FreeCAD GUI; its result dict (fails the test if the script
    failed). Outputs go to $ORACLEMESH_TEST_OUTPUT/freecad/<name>, else a pytest tmp dir."""
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
    full_env = dict(os.environ, HOME=str(home), OMFC_RESULT=result, OMFC_WORKDIR=workdir,
                    # FreeCAD's start page uses QtWebEngine, which refuses to run as root sandboxed.
                    QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox")
    full_env.pop("XDG_DATA_HOME", None)
    full_env.pop("ORACLEMESH_WORKER_CRASH", None)
    full_env.update(env or {})
    subprocess.run(["bash", os.path.join(REPO, "cmake", "install-workbench.sh"), BUILD],
                   env=full_env, check=True, capture_output=True)
    try:
        proc = subprocess.run(
            ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad",
             os.path.join(REPO, "tests", "freecad", "scripts", script)],
            env=full_env, cwd=workdir, capture_output=True, text=True, timeout=timeout)
        log = proc.stdout + proc.stderr
    except subprocess.TimeoutExpired:
        log = "timeout"
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
