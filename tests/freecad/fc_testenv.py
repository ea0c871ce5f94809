"""Where things are for the FreeCAD tests (shared by conftest and tests; a uniquely named
module, so it cannot clash with another folder's conftest)."""
import glob
import os

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build"))


def core_available():
    return bool(glob.glob(os.path.join(BUILD, "python", "oraclemesh", "_core*.so")))

