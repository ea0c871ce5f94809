"""The workbench in the real FreeCAD GUI (under Xvfb), installed by cmake/install-workbench.sh
into a scratch HOME: workbench, command, progress dialog, view provider, error message."""
import json
import os
import shutil
import subprocess

import pytest

from fc_testenv import BUILD, REPO, core_available


@pytest.mark.skipif(shutil.which("xvfb-run") is None or shutil.which("freecad") is None,
                    reason="needs the FreeCAD GUI and xvfb-run (Debian package xvfb)")
def test_gui_command_meshes_selection(tmp_path):
    if not core_available():
        pytest.fail("the core under test is missing: build the project first")
    home = tmp_path / "home"
    home.mkdir()
    env = dict(os.environ, HOME=str(home),
               OMFC_RESULT=str(tmp_path / "gui.json"),
               # FreeCAD's start page uses QtWebEngine, which refuses to run as root sandboxed.
               QTWEBENGINE_CHROMIUM_FLAGS="--no-sandbox")
    env.pop("XDG_DATA_HOME", None)
    subprocess.run(["bash", os.path.join(REPO, "cmake", "install-workbench.sh"), BUILD],
                   env=env, check=True, capture_output=True)
    try:
        proc = subprocess.run(["xvfb-run", "-a", "freecad",
                               os.path.join(REPO, "tests", "freecad", "scripts", "gui_command.py")],
                              env=env, cwd=str(tmp_path), capture_output=True, text=True,
                              timeout=600)
        log = proc.stdout + proc.stderr
    except subprocess.TimeoutExpired:
        log = "timeout"
    steps = tmp_path / "gui.json.steps"
    trail = steps.read_text() if steps.exists() else ""
    if not (tmp_path / "gui.json").exists():
        pytest.fail("the GUI run wrote no result; steps reached:\n%s\n%s" % (trail, log[-3000:]))
    r = json.loads((tmp_path / "gui.json").read_text())
    assert r["ok"], r.get("traceback")
    assert r["workbench"] == "OracleMeshWorkbench"
    assert r["command_registered"]
    assert r["mesh_inputs"] == ["Rod", "Block"]  # selection order = priority
    assert r["mesh_in_analysis"] and r["mesh_valid"] and r["mesh_volumes"] > 100
    assert r["view_provider"] == "ViewProviderOracleMesh"
    assert r["icon"].endswith("OracleMesh.svg")
    assert len(r["error_shown"]) == 1 and "no inputs" in r["error_shown"][0]
    assert r["mesh_kept"]
