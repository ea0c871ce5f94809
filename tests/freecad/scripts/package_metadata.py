"""FreeCAD's own metadata parser (the one the Addon Manager uses) reads both package.xml files:
the repository's (Addon Manager) and the workbench folder's (cmake/install-workbench.sh)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def describe(path):
    import FreeCAD
    md = FreeCAD.Metadata(path)
    root = os.path.dirname(path)
    wb = md.Content["workbench"][0]
    subdir = os.path.normpath(os.path.join(root, wb.Subdirectory or wb.Name))
    return {
        "name": md.Name, "version": md.Version, "license": [l["name"] for l in md.License],
        "icon_exists": os.path.exists(os.path.join(root, md.Icon)),
        "workbench": wb.Name, "classname": wb.Classname,
        "initgui_exists": os.path.exists(os.path.join(subdir, "InitGui.py")),
        # The Addon Manager joins the subdirectory and the workbench icon.
        "wb_icon_exists": os.path.exists(os.path.join(subdir, wb.Icon)),
        "classname_defined": ("class %s(" % wb.Classname) in open(os.path.join(subdir, "InitGui.py")).read(),
    }


def check(params):
    return {"repo": describe(os.path.join(h.REPO, "package.xml")),
            "workbench": describe(os.path.join(h.REPO, "Mod", "OracleMesh", "package.xml"))}


h.main(check)
