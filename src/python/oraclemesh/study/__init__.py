"""Batch studies: many jobs on a Dask cluster, one table of results.

    oraclemesh batch JOBS... --out DIR [--workers N | --scheduler ADDRESS] [--group-by PARAM]
    oraclemesh.batch(jobs, client=None, out="oraclemesh-batch", ...)

JOBS are job files (the CLI's JSON), folders of them (every *.json that is a job or a study;
reports and other JSON files are skipped) and study files. From Python also job and study
dicts (relative paths then against the current directory).

Study file (a base job plus parameters):
    {"study": "knee",                              optional; default: the file's name
     "base": "../implant_in_bone/implant_in_bone.json",   a job file (its paths relative to
                                                   itself) or an inline job object
     "set": {"output": null},                      applied to every case first
     "parameters": {                               every combination is a case, the first
       "variant": [{"value": 0, "set": {"inputs.0.file": "variants/implant_000.brep"},
                    "columns": {"tilt_deg": 2.1}}, ...],  extra table columns (optional)
       "approach": [{"value": "segments"},
                    {"value": "featureless", "set": {"features": false, "engine": "cgal"}}],
       "seed": {"path": "seed", "values": [0, 1, 2]}},    shorthand: one path, plain values
     "cases": [{"name": "...", "parameters": {...}, "set": {...}, "environment": {...}}],
                                                   explicit cases, after the grid
     "environment": {},                            variables of the cases' child processes
                                                   (test hooks such as ORACLEMESH_WORKER_CRASH)
     "name": "v{variant:03d}-{approach}",          case names (str.format of the parameters)
     "group_by": "approach", "x": "variant"}       summary groups, plots' x axis
A "set" path is dotted: "inputs.0.file" (list index), "criteria.materials.1.cell_size" (object
keys); null removes the key. Input paths set by the study are relative to the study file.

Every case runs through oraclemesh.run_isolated inside a Dask worker: a crash of the core
ends that case's child process only; the batch ends a case still running at its job's
limits.time_limit (default 3600 s) plus `grace` seconds. A case lost with its worker is
submitted again, at most `attempts` times in all. One case's failure never stops the study.
Input files must be readable here (for the hash) and on a path every worker sees (checked
before any case runs; a case whose file a worker cannot see fails at once, naming it), or
travel with the cases (ship_inputs / --ship-inputs).

Output, written as each case finishes:
  DIR/cases/<case>/case.json (record: hash, status, row, full report), job.json (the job as
  the core read it: `oraclemesh DIR/cases/<case>/job.json` reruns it alone), the job's
  output.files and output.report (file names only: every case writes into its own folder);
  DIR/results.csv, results.json (rows, summary, study), summary.csv; at the end tets.png and
  min_dihedral.png (one series per group_by value).
Columns: case, status (ok / failed), error_type (InputError: bad job or input; LimitError;
Error: the core stopped with a message; Crash: its process died; Timeout; WorkerLost;
MissingInput; InternalError: a bug of the batch), error (the message), phase (where a
failed case stopped), one column per study parameter (and level "columns"), tets, tets_material_<id>,
vertices, boundary_triangles, feature_edges, min_dihedral_deg, max_dihedral_deg, volume,
volume_material_<id>, seconds_<phase> (the report's), warnings (count), seconds (the case's
wall time on its worker), attempts, reused, worker, hash, source (job or study file).
Summary (per group_by value, over the succeeded cases): n, mean, min, max and sample
standard deviation of tets, vertices, dihedral angles, volumes and seconds.

Reruns: a case whose folder holds a succeeded record with the same hash (and its output
files) is reused without meshing; failed cases and changed ones run again. The hash is the
SHA-256 of the job as sent (sorted-key JSON) with every input file path replaced by the
SHA-256 of the file's bytes plus its extension (detached NRRD data files included), and of
the case's environment: moving the inputs keeps it, editing one redoes the cases using it.
The oraclemesh version is not part of it (a rebuilt core reuses old results: use a new DIR).
"""
import os
import sys
import time

from .. import __version__
from . import dispatch, plots, results
from .cases import collect, input_files
from .progress import ProgressBar

__all__ = ["batch", "BatchResult", "local_cluster"]
local_cluster = dispatch.local_cluster


class BatchResult:
    """rows: one dict per case, in the order of the jobs; summary: per value of group_by (the
    argument or the study's); out: the folder; ran: cases meshed by this call; reused: cases
    taken from an earlier run; plots: the PNG files."""

    def __init__(self, rows, summary, group_by, out, ran, reused, plots):
        self.rows, self.summary, self.group_by, self.out = rows, summary, group_by, out
        self.ran, self.reused, self.plots = ran, reused, plots

    @property
    def failed(self):
        return [r for r in self.rows if r["status"] != "ok"]

    def __repr__(self):
        return "<oraclemesh.BatchResult %d cases, %d failed, %d ran, %d reused>" % (
            len(self.rows), len(self.failed), self.ran, self.reused)


def batch(jobs, client=None, out="oraclemesh-batch", scheduler=None, workers=None, group_by=None,
          x=None, attempts=3, grace=60.0, ship_inputs=False, progress=True, say=None):
    """Runs every case of `jobs` (see the module docstring) and returns a BatchResult.

    client: a dask.distributed.Client to use; else scheduler (an address such as
    "tcp://host:8786"); else a local cluster of `workers` single-threaded worker processes
    (default: one per core). attempts: submissions per case when workers are lost. grace:
    seconds past limits.time_limit before a case is stopped. progress: the progress line on
    stderr. say: where messages go (default: print to stderr).
    """
    say = say or (lambda text: print(text, file=sys.stderr, flush=True))
    started = time.time()
    cases, options = collect(jobs)
    group_by = group_by or options.get("group_by")
    x = x or options.get("x")
    parameters = []
    for case in cases:
        for name in list(case.parameters) + list(case.columns):
            if results.is_reserved(name):
                raise ValueError("study parameter or column '%s' has the name of a results column: "
                                 "rename it" % name)
            if name not in parameters:
                parameters.append(name)
    if group_by and group_by not in parameters:
        raise ValueError("group_by '%s' is not a study parameter (the parameters: %s)"
                         % (group_by, ", ".join(parameters) or "none"))
    out = os.path.abspath(out)
    os.makedirs(out, exist_ok=True)
    study = {"jobs": [j if isinstance(j, dict) else os.fspath(j) for j in
                      (jobs if isinstance(jobs, (list, tuple)) else [jobs])],
             "cases": len(cases), "oraclemesh": __version__, "out": out}
    rows = {}
    for case in cases:
        row = results.previous_row(out, case)
        if row is not None:
            rows[case.name] = row
    to_run = [c for c in cases if c.name not in rows]
    say("oraclemesh batch: %d cases, %d done before with the same job and inputs, %d to run; results in %s"
        % (len(cases), len(rows), len(to_run), out))

    def ordered():
        return [rows[c.name] for c in cases if c.name in rows]

    def write():
        return results.write_tables(out, ordered(), parameters, group_by,
                                    dict(study, seconds=time.time() - started))

    bar = ProgressBar(len(cases), reused=len(rows)) if progress else None

    def counts():
        failed = sum(1 for r in rows.values() if r["status"] != "ok")
        return len(rows) - failed, failed

    def on_row(row):
        rows[row["case"]] = row
        write()

    if to_run:
        client, closing = dispatch.connect(client, scheduler, workers)
        try:
            say(dispatch.dashboard_note(client, local=getattr(client, "cluster", None) is not None))
            needed = set() if ship_inputs else {p for c in to_run for p in input_files(c.job)}
            missing = dispatch.check_workers(client, needed, say)
            say("%d Dask worker(s) at %s" % (len(client.scheduler_info()["workers"]), client.scheduler.address))
            runnable = []
            for case in to_run:
                if case.missing or any(p in missing for p in input_files(case.job)):
                    record = dispatch.missing_record(case, missing)
                    row = results.row_of(case, record, 0)
                    results.store(out, case, record, row)
                    on_row(row)
                else:
                    runnable.append(case)
            dispatch.run_cases(client, runnable, out, attempts, grace, ship_inputs, on_row,
                               lambda running: bar and bar.update(*counts(), running))
        finally:
            for thing in closing:  # the client before its cluster, which it would try to reconnect to
                thing.close()
    summary = write()
    if bar:
        bar.close(*counts())
    figures = plots.write_plots(out, ordered(), group_by, x)
    return BatchResult(ordered(), summary, group_by, out, len(to_run), len(cases) - len(to_run), figures)
