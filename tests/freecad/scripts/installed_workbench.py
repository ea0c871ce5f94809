"""Run with HOME pointing at a home where cmake/install-workbench.sh ran: FreeCAD itself must
find the workbench and the core through its user Mod folder (no sys.path set-up here)."""
import json
import os
import sys


def main():
    import FreeCAD
    out = {"ok": True, "user_mod_dir": os.path.join(FreeCAD.getUserAppDataDir(), "Mod")}
    import oraclemesh_fc
    out["oraclemesh_fc"] = os.path.realpath(oraclemesh_fc.__file__)
    out["icon"] = oraclemesh_fc.icon_path()
    try:
        import oraclemesh
        out["oraclemesh"] = os.path.realpath(oraclemesh.__file__)
    except ImportError as e:
        out["oraclemesh_error"] = str(e)
    return out


try:
    result = main()
except BaseException as e:
    result = {"ok": False, "error": repr(e)}
with open(os.environ["OMFC_RESULT"], "w") as f:
    json.dump(result, f)
sys.stdout.flush()
os._exit(0)
