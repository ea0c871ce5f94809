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
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

from . import _core
from ._core import Cancelled, Error, InputError, LimitError
from .images import with_image_files

__all__ = ["run", "run_isolated", "batch", "step_uncertainty", "Result", "Error", "InputError", "LimitError", "Cancelled",
           "__version__"]
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


# File inputs the core reads as triangle surfaces (job/InputLoading); any other file is a
# STEP, IGES or BREP file for OpenCASCADE (or a type the core refuses with a message).
_SURFACE_FILE_EXTENSIONS = (".stl", ".obj", ".off")


def _read_job_file(path):
    _core.require_job_file_size(path)  # a job over the limit is refused before it is read
    try:
        with open(path) as f:
            return f.read()
    except OSError as e:
        raise InputError("cannot read the job file '%s': %s" % (path, e.strerror)) from None


def _job_as_dict(job):
    """The job as a dict, to look at its inputs; None when it is not one (the core then
    explains what is wrong with it)."""
    if isinstance(job, (str, os.PathLike)):
        try:
            job = json.loads(_read_job_file(os.fspath(job)))
        except (ValueError, RecursionError):
            return None
    return job if isinstance(job, dict) else None


def _opencascade_inputs(job):
    """What in a job OpenCASCADE works on, as the core names it in messages ("input 'pin'
    (file 'pin.step')", "features.polylines[0]"); empty for a job without B-rep geometry."""
    if job is None:
        return []
    found = []
    inputs = job.get("inputs")
    for entry in inputs if isinstance(inputs, list) else []:
        if not isinstance(entry, dict):
            continue
        name = entry.get("name") if isinstance(entry.get("name"), str) else "?"
        file = entry.get("file")
        if isinstance(file, str) and not file.lower().endswith(_SURFACE_FILE_EXTENSIONS):
            found.append("input '%s' (file '%s')" % (name, file))
        elif "brep" in entry:
            found.append("input '%s' (BREP text)" % name)
    features = job.get("features")
    polylines = features.get("polylines") if isinstance(features, dict) else None
    for i, line in enumerate(polylines if isinstance(polylines, list) else []):
        if isinstance(line, dict) and "brep" in line:
            found.append("features.polylines[%d] (BREP edge)" % i)
    return found


def _time_limit(job):
    """limits.time_limit as the core reads it (default 3600 s); an invalid one is the
    core's to report, the default bounds the wait meanwhile."""
    limits = job.get("limits") if isinstance(job, dict) else None
    limit = limits.get("time_limit") if isinstance(limits, dict) else None
    valid = isinstance(limit, (int, float)) and not isinstance(limit, bool) and 0 < limit < math.inf
    return float(limit) if valid else 3600.0


# How long run_isolated waits past the deadline for the child's own verdict (an input
# OpenCASCADE is stuck on, oraclemesh.worker) before it kills the child as a LimitError.
_CHILD_VERDICT_SECONDS = 2.0


def _grace(limit):
    """As the CLI's hard deadline (src/cli/HardDeadline.h): a tenth of the limit, 2 to 30 s,
    for the core's own checkpoint to stop the job first."""
    return min(30.0, max(2.0, 0.1 * limit))


def step_uncertainty(path):
    """The largest length uncertainty (UNCERTAINTY_MEASURE_WITH_UNIT) the STEP file at path
    declares, in mm, 0 when it declares none: the distance below which its CAD tool took two
    points as one. The shapes OpenCASCADE reads from the file do not carry it. InputError when
    the file is no readable STEP file."""
    return _core.step_uncertainty(os.fspath(path))


def run(job, progress=None, base_directory=None, isolated=None):
    """Run a job (dict, or path to a JSON job file) and return a Result.

    progress(phase: str, fraction: float) is called with the GIL held; returning False
    cancels (oraclemesh.Cancelled is raised); an exception it raises stops the run and is
    raised again here, as itself. Relative paths in the
    job are taken relative to base_directory (default: the job file's folder, or the
    current directory for a dict). An image input may give its labels as a numpy array:
    {"image": {"labels": labels[z][y][x], "spacing": [sx, sy, sz], "origin": [x, y, z]},
    "materials": {"1": 2}} (see oraclemesh.images for the axis order). Raises
    oraclemesh.Error subclasses with a message that names the input and the fix.

    isolated: None (default) runs a job in which OpenCASCADE works on the user's geometry
    (a STEP, IGES or BREP file, BREP text, a polyline with a "brep" edge) as run_isolated
    does, in a child process, and any other job in this process; True or False forces
    either way. OpenCASCADE can loop or crash on a damaged shape in calls the core cannot
    interrupt; in a child, that ends at limits.time_limit plus a grace as an
    oraclemesh.Error naming the B-rep inputs, and this interpreter goes on. The result is
    the same (the same core in both); the child costs a process start and a copy of the
    arrays.
    """
    if isolated is None:
        isolated = bool(_opencascade_inputs(_job_as_dict(job)))
    if isolated:
        return run_isolated(job, progress=progress, base_directory=base_directory)
    # Images given as arrays live in NRRD files until the core has read them.
    with tempfile.TemporaryDirectory(prefix="oraclemesh-images-") as images:
        if isinstance(job, (str, os.PathLike)):
            path = os.fspath(job)
            text = _read_job_file(path)
            base = base_directory or os.path.dirname(os.path.abspath(path))
        else:
            _check_values(job)
            job = with_image_files(job, images)
            text = _job_json(job)
            base = base_directory or os.getcwd()
        return Result(_core.run(text, base, progress))


def run_isolated(job, progress=None, base_directory=None, cancel=None, environment=None, hard_deadline=True):
    """Like run(), but the core runs in a child Python process (oraclemesh.worker).

    A crash of the native core then raises oraclemesh.Error here instead of ending the
    caller's process (FreeCAD), and cancelling (progress returning False) ends the child at
    once. cancel: an optional threading.Event; setting it (from any thread) ends the child
    within 0.1 s even in phases that report no progress (sliver perturbation, exudation).
    hard_deadline: when a call that reports no progress keeps the core from its own
    checkpoint, the job ends limits.time_limit plus a grace (a tenth of it, 2 to 30 s, as the
    CLI's) after the core's first report: stuck inside OpenCASCADE on an input's geometry, the
    child says so, an oraclemesh.InputError naming the input and its file (as the CLI's exit
    code 2); stuck elsewhere, the child is killed 2 s later, an oraclemesh.LimitError naming
    the phase and the B-rep inputs (the CLI's 3). False leaves the deadline to the caller (oraclemesh.study
    has its own). environment: extra variables for the child only (a batch case's test
    hooks, see oraclemesh.worker). Costs a process start and a copy of the result arrays.
    """
    if not isinstance(job, (str, os.PathLike)):
        _check_values(job)
    with tempfile.TemporaryDirectory(prefix="oraclemesh-") as tmp:
        if isinstance(job, (str, os.PathLike)):
            job_path = os.path.abspath(os.fspath(job))
            base_directory = base_directory or os.path.dirname(job_path)
            job = json.loads(_read_job_file(job_path))
        brep_inputs = _opencascade_inputs(job)
        job = with_image_files(job, tmp)
        job_path = os.path.join(tmp, "job.json")
        absolute_job = _with_absolute_paths(job, base_directory or os.getcwd())
        with open(job_path, "w") as f:
            json.dump(absolute_job, f)
        result_path = os.path.join(tmp, "result.npz")
        package_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            [package_parent] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
        env.update(environment or {})
        env["ORACLEMESH_WORKER_PARENT"] = str(os.getpid())  # worker.PARENT_VARIABLE
        limit = _time_limit(job)
        grace = _grace(limit)
        if hard_deadline:  # worker.DEADLINE_VARIABLE: the child names an input OpenCASCADE is stuck on
            env["ORACLEMESH_WORKER_DEADLINE"] = "%r %r" % (limit, grace)
        # The module is built for the system interpreter; inside FreeCAD sys.executable is
        # FreeCAD itself, so the interpreter is found from the running Python's prefix.
        python = os.path.join(sys.base_prefix, "bin", "python3")
        # stderr goes to a file: a pipe nobody reads while stdout is read could fill and stall.
        stderr_file = open(os.path.join(tmp, "stderr.txt"), "w+")
        child = subprocess.Popen([python, "-m", "oraclemesh.worker", job_path, result_path],
                                 stdout=subprocess.PIPE, stderr=stderr_file, env=env, text=True)
        ended = _ChildEnder(child, cancel, limit + grace + _CHILD_VERDICT_SECONDS if hard_deadline else None)
        phase = ""
        try:
            for line in child.stdout:
                if not line.startswith("progress "):
                    continue
                _, fraction, phase = line.rstrip("\n").split(" ", 2)
                ended.core_started()
                if progress is None or ended.cancelled:
                    continue
                if progress(phase, float(fraction)) is False:
                    ended.cancel()
        except BaseException:
            # The callback raised (or the caller was interrupted): the child must not go on
            # meshing unobserved, and the exception reaches the caller as itself.
            child.kill()
            child.wait()
            ended.stop()
            stderr_file.close()
            raise
        code = child.wait()
        ended.stop()
        stderr_file.seek(0)
        stderr = stderr_file.read()
        stderr_file.close()
        if ended.cancelled:
            if code < 0:
                _report_killed_child(absolute_job, "cancelled", "meshing was cancelled", phase)
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
        suspects = ("; OpenCASCADE works on %s: check %s with Part > Check geometry or re-export it"
                    % (", ".join(brep_inputs), "it" if len(brep_inputs) == 1 else "them")) if brep_inputs else ""
        if ended.past_deadline:
            message = ("the job did not end within limits.time_limit = %g s (and %g s of grace) and was "
                       "stuck in phase '%s'; its process was stopped%s, or coarsen the sizes or raise "
                       "limits.time_limit" % (limit, grace, phase or "(none reported yet)",
                                              suspects or ": an input may be damaged"))
            _report_killed_child(absolute_job, "stopped", message, phase)
            raise LimitError(message)
        how = ("was killed by signal %d" % -code) if code < 0 else ("exited with code %d" % code)
        message = ("the OracleMesh core crashed on this job in phase '%s' (its process %s); the calling "
                   "program is unaffected%s. If the inputs are sound, please report it with the job and "
                   "this output:\n%s" % (phase or "(none reported yet)", how, suspects, stderr[-2000:]))
        _report_killed_child(absolute_job, "error", message, phase)
        raise Error(message)


def _report_killed_child(job, status, message, phase):
    """output.report for a child that was stopped or crashed before the core could write it:
    how the job ended and the phase it last reported, as the core's own report of an
    unfinished job (src/README.md, The report). The error is what the caller must get, so a
    report that cannot be written is left unwritten."""
    output = job.get("output") if isinstance(job, dict) else None
    path = output.get("report") if isinstance(output, dict) else None
    if not isinstance(path, str):
        return
    try:
        with open(path, "w") as f:
            json.dump({"status": status, "error": message, "stopped_in": phase}, f, indent=2)
    except OSError:
        pass


class _ChildEnder:
    """Kills run_isolated's child on the caller's cancel (an Event or a callback's False)
    or at the hard deadline, from a thread of its own: a child stuck where it reports no
    progress writes no line that the reading loop would wake up for. The deadline counts
    from the core's first report, as the core's own limit does: the child's interpreter and
    imports may take seconds on a loaded machine, and the core's limit (which names the
    input and phase better) must stay the first to fire."""

    # How long the child may take to start the core before the deadline counts anyway.
    STARTUP_SECONDS = 60.0

    def __init__(self, child, cancel_event, deadline_seconds):
        self.child = child
        self.cancelled = False
        self.past_deadline = False
        self._event = cancel_event
        self._deadline_seconds = deadline_seconds
        self._end = None if deadline_seconds is None else time.monotonic() + self.STARTUP_SECONDS + deadline_seconds
        self._started = False
        self._done = threading.Event()
        self._thread = None
        if cancel_event is not None or deadline_seconds is not None:
            self._thread = threading.Thread(target=self._watch, name="oraclemesh-child", daemon=True)
            self._thread.start()

    def core_started(self):
        if not self._started and self._deadline_seconds is not None:
            self._started = True
            self._end = time.monotonic() + self._deadline_seconds

    def _watch(self):
        while not self._done.is_set() and self.child.poll() is None:
            if self._event is not None and self._event.is_set():
                self.cancel()
                return
            if self._end is not None and time.monotonic() >= self._end:
                self.past_deadline = True
                self.child.kill()
                return
            self._done.wait(0.1)

    def cancel(self):
        self.cancelled = True
        self.child.kill()

    def stop(self):
        self._done.set()
        if self._thread is not None:
            self._thread.join()
        self.cancelled = self.cancelled or (self._event is not None and self._event.is_set())


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


def _job_json(job):
    try:
        return json.dumps(job, allow_nan=False, default=_array_as_list)
    except (TypeError, ValueError) as e:
        raise InputError("the job is not JSON-serialisable (%s): use plain dicts, lists, "
                         "strings and numbers" % e) from None


def np_load(path):
    return np.load(path, allow_pickle=False)


def _with_absolute_paths(job, base):
    """The child runs elsewhere: input and output paths are made absolute first."""
    job = json.loads(_job_json(job))
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
