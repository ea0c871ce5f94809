"""cmake/install-workbench.sh makes FreeCAD find the workbench and the core (in a scratch HOME)."""
import json
import os
import subprocess

from fc_testenv import BUILD, REPO

SCRIPT = os.path.join(REPO, "cmake", "install-workbench.sh")


def test_install_workbench_links_and_freecad_finds_it(tmp_path):
    home = tmp_path / "home"
    home.mkdir()
    env = dict(os.environ, HOME=str(home))
    env.pop("XDG_DATA_HOME", None)
    for _ in range(2):  # idempotent: the second run refreshes the same links
        subprocess.run(["bash", SCRIPT, BUILD], env=env, check=True, capture_output=True)
    target = home / ".local/share/FreeCAD/Mod/OracleMesh"
    assert target.is_dir() and not target.is_symlink()
    for name in ("Init.py", "InitGui.py", "package.xml", "oraclemesh_fc", "icons", "oraclemesh"):
        assert (target / name).is_symlink(), name
    assert os.path.realpath(target / "oraclemesh_fc") == os.path.join(REPO, "Mod", "OracleMesh",
                                                                       "oraclemesh_fc")
    assert os.path.realpath(target / "oraclemesh") == os.path.realpath(
        os.path.join(BUILD, "python", "oraclemesh"))

    result_path = tmp_path / "result.json"
    env["OMFC_RESULT"] = str(result_path)
    subprocess.run(["freecadcmd", os.path.join(REPO, "tests", "freecad", "scripts",
                                               "installed_workbench.py")],
                   env=env, cwd=str(tmp_path), capture_output=True, timeout=300)
    r = json.loads(result_path.read_text())
    assert r["ok"], r
    assert r["oraclemesh_fc"].startswith(os.path.join(REPO, "Mod", "OracleMesh"))
    assert r["icon"].endswith("OracleMesh.svg") and os.path.exists(r["icon"])
    assert r.get("oraclemesh", "").startswith(os.path.realpath(BUILD)), r
