"""Worker side of a batch: runs one case in a child process and returns its record.

run_case is what the Dask workers execute. It never raises for a failing case (bad input,
limit, crash of the core, deadline): those are records with status "failed", so that only
the loss of the worker itself is an error Dask sees (and the batch retries).
"""
import os
import socket
import tempfile
import threading
import time
import traceback

import oraclemesh

from .cases import FILE_KEYS, output_names

# How long past the job's own limits.time_limit (the core's default: 3600 s) the child may
# run before the batch ends it: the core checks its limit only where it reports progress.
DEFAULT_TIME_LIMIT = 3600.0


def deadline_of(job, grace):
    limits = job.get("limits") if isinstance(job.get("limits"), dict) else {}
    limit = limits.get("time_limit", DEFAULT_TIME_LIMIT)
    return (limit if isinstance(limit, (int, float)) and limit > 0 else DEFAULT_TIME_LIMIT) + grace


# Event topic on which each case tells the scheduler that it began (dispatch counts attempts).
STARTED_TOPIC = "oraclemesh-case-started"


def run_case(task, files=None):
    """task: {"name", "job", "environment", "grace", "shipped": {input path: file key}};
    files: {file key: bytes} when the inputs travel with the task (paths no worker sees);
    a key is "<input number>/<name>", detached data files sit beside their header."""
    started = time.time()
    _announce(task)
    record = {"name": task["name"], "status": "failed", "error_type": "", "error": "",
              "phase": "", "report": None, "outputs": {}, "host": socket.gethostname(),
              "worker": _worker_address()}
    phase = {"name": ""}  # the core's last progress report: where a failed case stopped
    with tempfile.TemporaryDirectory(prefix="oraclemesh-case-") as folder:
        job = _with_shipped_inputs(task["job"], task.get("shipped") or {}, files or {}, folder)
        deadline = deadline_of(job, task["grace"])
        cancel = threading.Event()
        timer = threading.Timer(deadline, cancel.set)
        timer.daemon = True

        def progress(name, fraction):
            phase["name"] = name
            return True

        timer.start()
        try:
            result = oraclemesh.run_isolated(job, progress=progress, base_directory=folder,
                                             cancel=cancel, environment=task.get("environment"),
                                             hard_deadline=False)  # the timer above is the deadline
            record.update(status="ok", report=result.report)
            for name in output_names(job):
                path = os.path.join(folder, name)
                if os.path.isfile(path):
                    with open(path, "rb") as f:
                        record["outputs"][name] = f.read()
        except oraclemesh.Cancelled:
            record.update(error_type="Timeout", error=(
                "no result within the case's deadline (%g s: limits.time_limit plus %g s grace), "
                "in phase '%s': the core was stopped" % (deadline, task["grace"], phase["name"] or "(none reported yet)")))
        except oraclemesh.Error as e:
            kind = type(e).__name__
            record.update(error_type="Crash" if kind == "Error" and "crashed" in str(e) else kind,
                          error=str(e))
        except Exception as e:  # a bug on this side: the case fails, the study goes on
            record.update(error_type="InternalError", error="%s: %s\n%s" % (
                type(e).__name__, e, traceback.format_exc(limit=5)))
        finally:
            timer.cancel()
    record["phase"] = phase["name"]
    record["seconds"] = time.time() - started
    return record


def _with_shipped_inputs(job, shipped, files, folder):
    """Shipped inputs are written into the case's folder and the job points at them there."""
    if not shipped:
        return job
    for key, data in files.items():
        path = os.path.join(folder, "inputs", key)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)
    job = dict(job, inputs=[dict(entry) for entry in job["inputs"]])
    for entry in job["inputs"]:
        for key in FILE_KEYS:
            if isinstance(entry.get(key), str) and entry[key] in shipped:
                entry[key] = os.path.join(folder, "inputs", shipped[entry[key]])
    return job


def _worker():
    try:
        from distributed import get_worker
        return get_worker()
    except (ImportError, ValueError):
        return None  # called outside a Dask worker


def _worker_address():
    worker = _worker()
    return worker.address if worker else ""


def _announce(task):
    """Tells the scheduler that the case began, and returns once the scheduler has it: the
    worker's own log_event only queues the message, and a worker killed a few milliseconds
    later (out of memory at once) would take it along, so the lost case would not count."""
    worker = _worker()
    if worker is None or not task.get("key"):
        return
    msg = {"key": task["key"], "case": task["name"]}
    try:
        from distributed.utils import sync
        sync(worker.loop, worker.scheduler.log_event, topic=STARTED_TOPIC, msg=msg,
             callback_timeout=30)
    except Exception:
        worker.log_event(STARTED_TOPIC, msg)  # the scheduler is busy or unreachable: queue it


def check_worker(paths):
    """Run on every worker before the study: oraclemesh's version there and the input
    files it cannot see."""
    return {"version": oraclemesh.__version__, "missing": [p for p in paths if not os.path.isfile(p)]}
