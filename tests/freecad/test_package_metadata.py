"""package.xml files are valid for FreeCAD's metadata parser (Addon Manager) and point at
files that exist."""


def test_package_xml_files(run_freecad):
    r = run_freecad("package_metadata.py", timeout=120)
    for which in ("repo", "workbench"):
        md = r[which]
        print(which, md)
        assert md["name"] == "OracleMesh" and md["workbench"] == "OracleMesh"
        assert md["license"] == ["LGPL-2.1-or-later"]
        assert md["classname"] == "OracleMeshWorkbench" and md["classname_defined"]
        assert md["initgui_exists"]
    # Mod/OracleMesh/icons is a link cmake/install-workbench.sh makes at install time, so only
    # the repository's package.xml (Addon Manager) can point at existing icons here.
    assert r["repo"]["icon_exists"] and r["repo"]["wb_icon_exists"]
