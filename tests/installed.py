"""What cmake/install-deps.sh installs, as the tests need it: a missing Python module or
program fails the test (never skips it) with the Debian package to install."""
import importlib
import shutil

import pytest


def require_module(module, package):
    """The imported module, or a failure naming the package."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        pytest.fail("Python module %s cannot be imported (%s): cmake/install-deps.sh installs "
                    "the Debian package %s" % (module, e, package), pytrace=False)


def require_programs(programs):
    """Fails naming every missing program of {program: Debian package}."""
    missing = ["%s (Debian package %s)" % (p, package) for p, package in programs.items()
               if shutil.which(p) is None]
    if missing:
        pytest.fail("not installed: %s; cmake/install-deps.sh installs them"
                    % ", ".join(missing), pytrace=False)
