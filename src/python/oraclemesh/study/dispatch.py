"""Sends a batch's cases to a Dask cluster and collects their records as they finish.

Each case is one Dask task (execute.run_case) that meshes in a child process, so a crash of
the core ends the child only. A task lost with its worker process (killed, out of memory)
comes back as an error from Dask and is submitted again: a case may start `attempts` times
in all (a case lost while still queued on the dead worker did not start, and does not count).
On the local cluster the scheduler allows no failure itself (allowed-failures 0), so every
loss is seen and counted here; an existing scheduler may first retry on its own
(its distributed.scheduler.allowed-failures, 3 by default).
"""
import importlib.util
import logging
import os
import time
import uuid

from .. import Error
from . import execute, results
from .cases import input_files

# The batch's own scheduler settings: every lost worker is reported to the batch (which
# bounds the retries), and in a study of more than twice as many cases as worker threads
# (a task group Dask queues on the scheduler) a worker holds only the case it runs; with
# the default 1.1 a single-threaded worker would also hold a queued case, lost with it.
SCHEDULER_CONFIG = {"distributed.scheduler.allowed-failures": 0,
                    "distributed.scheduler.worker-saturation": 1.0}
POLL_SECONDS = 0.2
# Times a case lost before it started (queued on a worker that died) may be sent again.
UNSTARTED_RESUBMITS = 10


def local_cluster(workers=None):
    """A local Dask cluster as the batch makes it: one single-threaded worker process per
    core (or `workers`), scheduler and dashboard on the loopback address, random ports."""
    import dask
    from distributed import LocalCluster
    with dask.config.set(SCHEDULER_CONFIG):
        return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                            processes=True, host="127.0.0.1", dashboard_address="127.0.0.1:0",
                            silence_logs=logging.ERROR)


def connect(client=None, scheduler=None, workers=None):
    """(client, things to close afterwards): the given client, a client of the scheduler at
    `scheduler`, or a new local cluster."""
    from distributed import Client
    if client is not None:
        return client, []
    if scheduler:
        client = Client(scheduler, timeout="30s")
        return client, [client]
    cluster = local_cluster(workers)
    client = Client(cluster)
    return client, [client, cluster]


def dashboard_note(client, local):
    """Where the Dask dashboard is, or why there is none (it needs bokeh)."""
    link = getattr(client, "dashboard_link", None)
    if local and importlib.util.find_spec("bokeh") is None:
        return "Dask dashboard: not available (it needs bokeh, which Debian 12 does not ship)"
    return "Dask dashboard: %s%s" % (link, "" if local else " (if the scheduler has bokeh)")


def check_workers(client, paths, say):
    """Before any case: oraclemesh imports on every worker, and which input files each worker
    cannot see. Returns {path: [workers missing it]}."""
    client.wait_for_workers(1, timeout=120)
    try:
        answers = client.run(execute.check_worker, sorted(paths))
    except Exception as e:
        raise Error("the Dask workers cannot run oraclemesh (%s: %s): install it, or put the build's "
                    "python/ folder on the workers' PYTHONPATH" % (type(e).__name__, e)) from None
    versions = {a["version"] for a in answers.values()}
    if len(versions) > 1:
        say("warning: the workers have different oraclemesh versions: %s" % ", ".join(sorted(versions)))
    missing = {}
    for worker, answer in answers.items():
        for path in answer["missing"]:
            missing.setdefault(path, []).append(worker)
    return missing


def run_cases(client, cases, out, attempts, grace, ship, on_row, bar):
    """Runs the cases on the client's cluster; calls on_row(row) as each one finishes
    (including cases that fail before running: inputs missing)."""
    token = uuid.uuid4().hex[:8]
    scattered = {}  # path -> future of its bytes, each file sent to the cluster once

    def files_of(case):
        """Shipped inputs: {key: bytes future} and {input path: key}; an input's key is
        "<its number>/<file name>", its detached data files keep their place beside it."""
        if not ship:
            return None, {}
        files, mapping = {}, {}
        for k, entry in enumerate(case.job.get("inputs", [])):
            paths = input_files({"inputs": [entry]})
            for path in paths:
                if path not in scattered:
                    with open(path, "rb") as f:
                        scattered[path] = client.scatter(f.read(), hash=False)
                files["%d/%s" % (k, os.path.relpath(path, os.path.dirname(paths[0])))] = scattered[path]
            if paths:
                mapping[paths[0]] = "%d/%s" % (k, os.path.basename(paths[0]))
        return files, mapping

    tries = {}  # case name -> [submissions, submissions that started]

    def submit(case, number):
        files, mapping = files_of(case)
        # One key prefix for all cases: Dask groups tasks by it, and a large group is queued
        # on the scheduler (worker-saturation) instead of on the workers.
        key = "oraclemesh_case-%s-%d-%d" % (token, number, tries[case.name][0])
        task = {"name": case.name, "key": key, "job": case.job, "environment": case.environment,
                "grace": grace, "shipped": mapping}
        tries[case.name][0] += 1
        return client.submit(execute.run_case, task, files, key=key, pure=False, retries=1)

    started = set()  # keys seen started, kept across polls: one failed poll forgets none
    pending = {}
    for number, case in enumerate(cases):
        tries[case.name] = [0, 0]
        pending[submit(case, number)] = (case, number)
    running, last_poll = 0, 0.0
    while pending:
        for future in [f for f in pending if f.done()]:
            case, number = pending.pop(future)
            count = tries[case.name]
            record = None
            if future.status == "finished":
                record = future.result()
                count[1] += 1
            else:
                # A case queued on a lost worker did not start: sent again without counting.
                started |= started_keys(client)
                count[1] += future.key in started
                if count[1] < attempts and count[0] < attempts + UNSTARTED_RESUBMITS:
                    pending[submit(case, number)] = (case, number)
                else:
                    record = lost_record(case, count[1], _error_text(future))
            future.release()
            if record is not None:
                row = results.row_of(case, record, count[1])
                results.store(out, case, record, row)
                on_row(row)
        now = time.time()
        if now - last_poll >= 1.0:
            started |= started_keys(client)
            running = sum(1 for f in pending if f.key in started)
            last_poll = now
        bar(running)
        time.sleep(POLL_SECONDS)


def started_keys(client):
    """Keys of the case tasks that began on a worker (execute.run_case announces each)."""
    try:
        return {msg.get("key") for _, msg in client.get_events(execute.STARTED_TOPIC)}
    except Exception:
        return set()


def _error_text(future):
    if future.status == "cancelled":
        return "cancelled by the scheduler"
    try:
        e = future.exception(timeout=5)
    except Exception as other:
        e = other
    return "%s: %s" % (type(e).__name__, e)


def lost_record(case, attempts, why):
    return {"name": case.name, "status": "failed", "error_type": "WorkerLost", "phase": "",
            "error": "the Dask worker running this case was lost %d time(s) (last: %s); it may "
                     "need more memory than a worker has" % (attempts, why)}


def missing_record(case, missing_on_workers):
    """A case whose input files are not there: it fails at once, with the file's name."""
    path = case.missing[0] if case.missing else next(p for p in input_files(case.job) if p in missing_on_workers)
    if case.missing:
        error = "input file '%s' does not exist" % path
    else:
        error = ("input file '%s' is not visible on the worker(s) %s: put the inputs on a path all "
                 "workers see, or send them with the case (--ship-inputs)"
                 % (path, ", ".join(missing_on_workers[path])))
    return {"name": case.name, "status": "failed", "error_type": "MissingInput", "error": error, "phase": "",
            "seconds": 0.0}
