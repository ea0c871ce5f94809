"""Where the workbench's icons are (a module of its own, so that the commands and the view
provider need not import the package, whose __init__ imports the mesh object)."""
import os


def icon_path(name="OracleMesh.svg"):
    """Path of an icon: Mod/OracleMesh/icons (installed link) or the repository's icons/."""
    package = os.path.dirname(os.path.abspath(__file__))
    candidates = (
        os.path.join(os.path.dirname(package), "icons", name),  # ~/.../Mod/OracleMesh/icons
        # The workbench folder is a set of symlinks into the repository: follow them back.
        os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(package)))),
                     "icons", name),
    )
    for path in candidates:
        if os.path.exists(path):
            return path
    return ""
