"""OracleMesh: multi-material tetrahedral meshes of CAD assemblies, composed by priority.

    import oraclemesh
    result = oraclemesh.run({"inputs": [{"name": "pin", "file": "pin.step", "material": 1}]})
    result.points, result.tets, result.tet_materials, result.report

The job dict is the job contract of DESIGN.md (the same JSON the `oraclemesh` CLI reads).
"""
import json
import math
import os

from . import _core
from ._core import Cancelled, Error, InputError, LimitError

__all__ = ["run", "Result", "Error", "InputError", "LimitError", "Cancelled", "__version__"]
__version__ = _core.version()


class Result:
    """A mesh and its report.

    points: (n, 3) float64. tets: (m, 4) or (m, 10) int64, corners positively oriented
    ((v1-v0)x(v2-v0).(v3-v0) > 0), tet10 mid nodes in the order 01, 12, 20, 03, 13, 23.
    tet_materials: (m,) int32 material ids. boundary_triangles: (k, 3) int64 with
    boundary_materials (k, 2) = (material inside, material outside; 0 = no material).
    feature_edges: (e, 2) int64 mesh edges on constrained segments, feature_edge_curves (e,).
    vertex_dimension: (n,) 0 corner, 1 on a feature curve, 2 on a surface, 3 interior.
    report: dict (counts, quality, criteria, seconds per phase, warnings).
    """

    def __init__(self, arrays):
        self.points = arrays["points"]
        self.tets = arrays["tets"]
        self.tet_materials = arrays["tet_materials"]
        self.boundary_triangles = arrays["boundary_triangles"]
        self.boundary_materials = arrays["boundary_materials"]
        self.feature_edges = arrays["feature_edges"]
        self.feature_edge_curves = arrays["feature_edge_curves"]
        self.vertex_dimension = arrays["vertex_dimension"]
        self.report = json.loads(arrays["report"])

    def __repr__(self):
        return "<oraclemesh.Result %d points, %d tets>" % (len(self.points), len(self.tets))


def _first_non_finite(value, path):
    """Key path of the first NaN or infinity in a job (JSON has no such numbers)."""
    if isinstance(value, float) and not math.isfinite(value):
        return path or "the job"
    if isinstance(value, dict):
        items = ((str(k), v) for k, v in value.items())
    elif isinstance(value, (list, tuple)):
        items = (("[%d]" % i, v) for i, v in enumerate(value))
    else:
        return None
    for key, item in items:
        where = path + key if key.startswith("[") else (path + "." + key if path else key)
        found = _first_non_finite(item, where)
        if found:
            return found
    return None


def run(job, progress=None, base_directory=None):
    """Run a job (dict, or path to a JSON job file) and return a Result.

    progress(phase: str, fraction: float) is called from the meshing thread with the GIL
    held; returning False cancels (oraclemesh.Cancelled is raised). Relative paths in the
    job are taken relative to base_directory (default: the job file's folder, or the
    current directory for a dict). Raises oraclemesh.Error subclasses with a message that
    names the input and the fix.
    """
    if isinstance(job, (str, os.PathLike)):
        path = os.fspath(job)
        try:
            with open(path) as f:
                text = f.read()
        except OSError as e:
            raise InputError("cannot read the job file '%s': %s" % (path, e.strerror)) from None
        base = base_directory or os.path.dirname(os.path.abspath(path))
    else:
        bad = _first_non_finite(job, "")
        if bad:
            raise InputError("%s is not a finite number: give a positive value in model units (mm)" % bad)
        try:
            text = json.dumps(job, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise InputError("the job is not JSON-serialisable (%s): use plain dicts, lists, "
                             "strings and numbers" % e) from None
        base = base_directory or os.getcwd()
    return Result(_core.run(text, base, progress))
