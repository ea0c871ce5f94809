"""Run FreeCAD headless checks: each test launches `freecadcmd` on a script in scripts/ and
reads the JSON the script writes (see fc_harness.py).

The core under test is the build's module (ORACLEMESH_BUILD_DIR/python/oraclemesh, default
build/). Script outputs (FCStd, ccx files) go to
ORACLEMESH_TEST_OUTPUT/freecad/<test> when that is set, else to pytest's tmp_path.
"""
import json
import os
import shutil
import subprocess
import sys

import pytest

from fc_testenv import BUILD, HERE, core_available

sys.path.insert(0, os.path.dirname(HERE))
from installed import require_programs  # noqa: E402


@pytest.fixture
def workdir(request, tmp_path):
    base = os.environ.get("ORACLEMESH_TEST_OUTPUT")
    if not base:
        return str(tmp_path)
    path = os.path.join(base, "freecad", request.node.name.replace("[", "_").replace("]", ""))
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


@pytest.fixture
def run_freecad(workdir):
    """run_freecad(script, params, timeout=600, env=None) -> dict written by the script."""
    require_programs({"freecadcmd": "freecad"})
    if not core_available():
        pytest.fail("the core under test is missing: build the project (cmake --build build) "
                    "so %s/python/oraclemesh/_core*.so exists"
                    % BUILD)

    def run(script, params=None, timeout=600, env=None):
        params = dict(params or {})
        params.setdefault("workdir", workdir)
        name = os.path.splitext(os.path.basename(script))[0]
        params_path = os.path.join(workdir, name + ".params.json")
        result_path = os.path.join(workdir, name + ".result.json")
        with open(params_path, "w") as f:
            json.dump(params, f)
        if os.path.exists(result_path):
            os.remove(result_path)
        full_env = dict(os.environ, OMFC_PARAMS=params_path, OMFC_RESULT=result_path,
                        ORACLEMESH_BUILD_DIR=BUILD)
        full_env.update(env or {})
        log = os.path.join(workdir, name + ".log")
        try:
            proc = subprocess.run(["freecadcmd", os.path.join(HERE, "scripts", script)],
                                  cwd=workdir, env=full_env, capture_output=True, text=True,
                                  timeout=timeout)
        except subprocess.TimeoutExpired as e:
            text = "".join(x.decode(errors="replace") if isinstance(x, bytes) else (x or "")
                           for x in (e.stdout, e.stderr))
            with open(log, "w") as f:
                f.write(text)
            pytest.fail("freecadcmd %s did not finish within %d s; log %s:\n%s"
                        % (script, timeout, log, text[-3000:]))
        with open(log, "w") as f:
            f.write(proc.stdout + "\n--- stderr ---\n" + proc.stderr)
        if not os.path.exists(result_path):
            pytest.fail("freecadcmd %s wrote no result (exit %d, crash?); log %s:\n%s"
                        % (script, proc.returncode, log, (proc.stdout + proc.stderr)[-4000:]))
        with open(result_path) as f:
            result = json.load(f)
        if not result.get("ok"):
            pytest.fail("%s failed in FreeCAD:\n%s\nlog: %s"
                        % (script, result.get("traceback"), log))
        result["log"] = log
        return result

    return run
