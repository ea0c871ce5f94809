"""OracleMesh: multi-material tetrahedral meshes of CAD assemblies, composed by priority.

    import oraclemesh
    result = oraclemesh.run({"inputs": [{"name": "pin", "file": "pin.step", "material": 1}]})
    result.points, result.tets, result.tet_materials, result.report

The job dict is the job contract of src/README.md (the same JSON the `oraclemesh` CLI reads).
Its "engine" is "thesis" (Rule Set T, the default) or "cgal" (CGAL Mesh_3).
"""
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import threading

import numpy as np

from . import _core
from ._core import Cancelled, Error, InputError, LimitError
from .images import with_image_files

__all__ = ["run", "run_isolated", "batch", "Result", "Error", "InputError", "LimitError", "Cancelled", "__version__"]
__version__ = _core.version()


class Result:
    """A mesh and its report.

    points: (n, 3) float64. tets: (m, 4) or (m, 10) int64, corners positively oriented
    ((v1-v0)x(v2-v0).(v3-v0) > 0), tet10 mid nodes in the order 01, 12, 20, 03, 13, 23.
    tet_materials: (m,) int32 material ids. boundary_triangles: (k, 3) int64 with
    boundary_materials (k, 2) = (material inside, material outside; 0 = no material).
    feature_edges: (e, 2) int64 mesh edges on constrained segments, feature_edge_curves (e,).
    vertex_dimension: (n,) 0 corner, 1 on a feature curve, 2 on a surface, 3 interior.
    surfaces: list of dicts, one per interface (material < other_material) and per part
    exterior (other_material 0): name (as the INP *SURFACE and report.interfaces/exteriors),
    material, other_material, faces (f, 2) int64 = (tet index, face 0..3 = CalculiX S1..S4:
    corners 012, 031, 132, 230); an interface's faces are taken from the smaller material's tets.
    report: dict (counts, quality, criteria, seconds per phase, warnings).
    """

    ARRAYS = ("points", "tets", "tet_materials", "boundary_triangles", "boundary_materials",
              "feature_edges", "feature_edge_curves", "vertex_dimension")

    def __init__(self, arrays):
        for name in self.ARRAYS:
            setattr(self, name, arrays[name])
        self.surfaces = list(arrays.get("surfaces", []))
        self.report = json.loads(str(arrays["report"]))

    def surface_arrays(self):
        """The surfaces as plain arrays (what np.savez can carry from run_isolated's child):
        surface_names/surface_materials (s, 2) per surface, surface_faces (f, 3) = (surface,
        tet, face)."""
        faces = [np.column_stack([np.full(len(s["faces"]), i), np.asarray(s["faces"]).reshape(-1, 2)])
                 for i, s in enumerate(self.surfaces)]
        return {"surface_names": np.array([s["name"] for s in self.surfaces], dtype=str),
                "surface_materials": np.array([[s["material"], s["other_material"]] for s in self.surfaces],
                                              dtype=np.int32).reshape(-1, 2),
                "surface_faces": np.concatenate(faces).astype(np.int64) if faces else np.zeros((0, 3), np.int64)}

    @staticmethod
    def surfaces_from_arrays(arrays):
        """Result.surfaces from surface_arrays' arrays."""
        faces = arrays["surface_faces"]
        return [{"name": str(name), "material": int(m[0]), "other_material": int(m[1]),
                 "faces": faces[faces[:, 0] == i, 1:]}
                for i, (name, m) in enumerate(zip(arrays["surface_names"], arrays["surface_materials"]))]

    def __repr__(self):
        return "<oraclemesh.Result %d points, %d tets>" % (len(self.points), len(self.tets))


# As the core's limit (src/core/job/JobJson.h): deeper jobs are mistakes, and recursion on
# them (json.dumps) would end in RecursionError instead of a message.
_MAX_DEPTH = 64


def _check_values(job):
    """InputError naming the key path of the first NaN or infinity in a job (JSON has no such
    numbers; numpy arrays included) or of nesting deeper than the core accepts."""
    pending = [(job, "", 0)]
    while pending:
        value, path, depth = pending.pop()
        where = path or "the job"
        if depth > _MAX_DEPTH:
            raise InputError("%s nests lists and objects more than %d levels deep: the job contract needs "
                             "at most 6" % (where if len(where) < 80 else where[:60] + "...", _MAX_DEPTH))
        if isinstance(value, float):
            if not math.isfinite(value):
                raise InputError("%s is not a finite number (%r): give a finite value in model units (mm)"
                                 % (where, value))
        elif isinstance(value, dict):
            pending.extend((item, path + "." + str(key) if path else str(key), depth + 1)
                           for key, item in reversed(list(value.items())))
        elif isinstance(value, (list, tuple)):
            pending.extend((item, "%s[%d]" % (path, i), depth + 1) for i, item in reversed(list(enumerate(value))))
        elif hasattr(value, "dtype") and hasattr(value, "shape"):
            _check_array(value, where)


def _check_array(array, where):
    """A numpy array in a job (surface points, image spacing): finite numbers only."""
    import numpy
    if array.dtype.kind not in "fc":
        return
    finite = numpy.isfinite(array)
    if not finite.all():
        index = tuple(int(i) for i in numpy.argwhere(~finite)[0])
        raise InputError("%s%s is not a finite number (%r): give finite values in model units (mm)"
                         % (where, "".join("[%d]" % i for i in index), array[index].item()))


def run(job, progress=None, base_directory=None):
    """Run a job (dict, or path to a JSON job file) and return a Result.

    progress(phase: str, fraction: float) is called from the meshing thread with the GIL
    held; returning False cancels (oraclemesh.Cancelled is raised); an exception it raises
    stops the run and is raised again here, as itself. Relative paths in the
    job are taken relative to base_directory (default: the job file's folder, or the
    current directory for a dict). An image input may give its labels as a numpy array:
    {"image": {"labels": labels[z][y][x], "spacing": [sx, sy, sz], "origin": [x, y, z]},
    "materials": {"1": 2}} (see oraclemesh.images for the axis order). Raises
    oraclemesh.Error subclasses with a message that names the input and the fix.
    """
    # Images given as arrays live in NRRD files until the core has read them.
    with tempfile.TemporaryDirectory(prefix="oraclemesh-images-") as images:
        if isinstance(job, (str, os.PathLike)):
            path = os.fspath(job)
            try:
                with open(path) as f:
                    text = f.read()
            except OSError as e:
                raise InputError("cannot read the job file '%s': %s" % (path, e.strerror)) from None
            base = base_directory or os.path.dirname(os.path.abspath(path))
        else:
            _check_values(job)
            job = with_image_files(job, images)
            try:
                text = json.dumps(job, allow_nan=False, default=_array_as_list)
            except (TypeError, ValueError) as e:
                raise InputError("the job is not JSON-serialisable (%s): use plain dicts, lists, "
                                 "strings and numbers" % e) from None
            base = base_directory or os.getcwd()
        return Result(_core.run(text, base, progress))


def run_isolated(job, progress=None, base_directory=None, cancel=None, environment=None):
    """Like run(), but the core runs in a child Python process (oraclemesh.worker).

    A crash of the native core then raises oraclemesh.Error here instead of ending the
    caller's process (FreeCAD), and cancelling (progress returning False) ends the child at
    once. cancel: an optional threading.Event; setting it (from any thread) ends the child
    within 0.1 s even in phases that report no progress (sliver perturbation, exudation).
    environment: extra variables for the child only (a batch case's test hooks, see
    oraclemesh.worker). Costs a process start and a copy of the result arrays.
    """
    if not isinstance(job, (str, os.PathLike)):
        _check_values(job)
    with tempfile.TemporaryDirectory(prefix="oraclemesh-") as tmp:
        if isinstance(job, (str, os.PathLike)):
            job_path = os.path.abspath(os.fspath(job))
            base_directory = base_directory or os.path.dirname(job_path)
            with open(job_path) as f:
                job = json.load(f)
        job = with_image_files(job, tmp)
        job_path = os.path.join(tmp, "job.json")
        with open(job_path, "w") as f:
            json.dump(_with_absolute_paths(job, base_directory or os.getcwd()), f)
        result_path = os.path.join(tmp, "result.npz")
        package_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            [package_parent] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
        env.update(environment or {})
        env["ORACLEMESH_WORKER_PARENT"] = str(os.getpid())  # worker.PARENT_VARIABLE
        # The module is built for the system interpreter; inside FreeCAD sys.executable is
        # FreeCAD itself, so the interpreter is found from the running Python's prefix.
        python = os.path.join(sys.base_prefix, "bin", "python3")
        # stderr goes to a file: a pipe nobody reads while stdout is read could fill and stall.
        stderr_file = open(os.path.join(tmp, "stderr.txt"), "w+")
        child = subprocess.Popen([python, "-m", "oraclemesh.worker", job_path, result_path],
                                 stdout=subprocess.PIPE, stderr=stderr_file, env=env, text=True)
        cancelled = False
        watcher = None
        if cancel is not None:
            def watch():
                while child.poll() is None:
                    if cancel.wait(0.1):
                        child.send_signal(signal.SIGKILL)
                        return
            watcher = threading.Thread(target=watch, name="oraclemesh-cancel", daemon=True)
            watcher.start()
        try:
            for line in child.stdout:
                if not line.startswith("progress ") or progress is None or cancelled:
                    continue
                _, fraction, phase = line.rstrip("\n").split(" ", 2)
                if progress(phase, float(fraction)) is False:
                    cancelled = True
                    child.send_signal(signal.SIGKILL)
        except BaseException:
            # The callback raised (or the caller was interrupted): the child must not go on
            # meshing unobserved, and the exception reaches the caller as itself.
            child.kill()
            child.wait()
            stderr_file.close()
            raise
        code = child.wait()
        if watcher is not None:
            watcher.join()
            cancelled = cancelled or cancel.is_set()
        stderr_file.seek(0)
        stderr = stderr_file.read()
        stderr_file.close()
        if cancelled:
            raise Cancelled("meshing was cancelled")
        if code == 0:
            with np_load(result_path) as arrays:
                result = Result({name: arrays[name] for name in Result.ARRAYS + ("report",)})
                result.surfaces = Result.surfaces_from_arrays(arrays)
                return result
        if os.path.exists(result_path + ".error.json"):
            with open(result_path + ".error.json") as f:
                error = json.load(f)
            raise {"InputError": InputError, "LimitError": LimitError,
                   "Cancelled": Cancelled}.get(error["type"], Error)(error["message"])
        how = ("was killed by signal %d" % -code) if code < 0 else ("exited with code %d" % code)
        raise Error("the OracleMesh core crashed on this job (its process %s); the calling "
                    "program is unaffected. Please report it with the job and this output:\n%s"
                    % (how, stderr[-2000:]))


def batch(jobs, client=None, **options):
    """Runs many jobs on a Dask cluster and returns an oraclemesh.study.BatchResult (one row
    per case, summary, plots): see oraclemesh.study for the jobs, options and outputs.
    client: a dask.distributed.Client; default a local cluster, one worker per core."""
    from .study import batch as run_batch  # Dask is imported only by batches
    return run_batch(jobs, client=client, **options)


def _array_as_list(value):
    """numpy arrays and scalars in a job (a "surface" input's points and triangles) as JSON."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError("%s is not JSON-serialisable" % type(value).__name__)


def np_load(path):
    return np.load(path, allow_pickle=False)


def _with_absolute_paths(job, base):
    """The child runs elsewhere: input and output paths are made absolute first."""
    job = json.loads(json.dumps(job, default=_array_as_list))
    for entry in job.get("inputs", []) if isinstance(job, dict) else []:
        for key in ("file", "image"):
            if isinstance(entry, dict) and isinstance(entry.get(key), str):
                entry[key] = os.path.join(base, entry[key])
    output = job.get("output") if isinstance(job, dict) else None
    if isinstance(output, dict):
        if isinstance(output.get("files"), list):
            output["files"] = [os.path.join(base, f) if isinstance(f, str) else f for f in output["files"]]
        if isinstance(output.get("report"), str):
            output["report"] = os.path.join(base, output["report"])
    return job
