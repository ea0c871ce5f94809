"""Where things are and which core the FreeCAD tests use (shared by conftest and tests;
a uniquely named module, so it cannot clash with another folder's conftest)."""
import glob
import os
import shutil

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
CORE = os.environ.get("ORACLEMESH_TEST_CORE", "oraclemesh")
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build"))


def core_available():
    if CORE == "gmsh":
        return shutil.which("gmsh") is not None
    return bool(glob.glob(os.path.join(BUILD, "python", "oraclemesh", "_core*.so")))


needs_real_core = pytest.mark.skipif(
    CORE == "gmsh", reason="checks the real core's behaviour (ORACLEMESH_TEST_CORE=gmsh)")
