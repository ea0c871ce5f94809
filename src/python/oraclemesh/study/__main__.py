"""`oraclemesh batch ...` (the C++ CLI execs `python3 -m oraclemesh.study ...`).

Exit codes: 0 every case succeeded, 1 the study finished with failed cases, 2 bad arguments
or no jobs, 3 the cluster could not be used.
"""
import argparse
import signal
import sys

import oraclemesh
from oraclemesh.study import batch, results


def parse(argv):
    parser = argparse.ArgumentParser(
        prog="oraclemesh batch",
        description="Mesh many jobs on a Dask cluster (default: a local one, one worker per core) and "
                    "write one table of results (DIR/results.csv, DIR/results.json, summary, plots). "
                    "A rerun reuses the cases already done with the same job and inputs. The study "
                    "file format, the columns and the hash rule: pydoc oraclemesh.study.")
    parser.add_argument("jobs", nargs="+", metavar="JOBS", help="job files, folders of job files, study files")
    parser.add_argument("--out", required=True, metavar="DIR", help="results folder (reused by reruns)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="local cluster of N workers (default: one per core)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://host:8786")
    parser.add_argument("--group-by", metavar="PARAM", help="study parameter the summary is grouped by")
    parser.add_argument("--x", metavar="PARAM", help="study parameter on the plots' x axis")
    parser.add_argument("--attempts", type=int, default=3, metavar="N",
                        help="submissions of a case whose worker is lost (default 3)")
    parser.add_argument("--grace", type=float, default=60.0, metavar="SECONDS",
                        help="a case still running at its limits.time_limit plus this is stopped (default 60)")
    parser.add_argument("--ship-inputs", action="store_true",
                        help="send input files with the cases (for workers that do not see this file system)")
    parser.add_argument("--no-progress", action="store_true", help="no progress line on stderr")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.attempts < 1:
        parser.error("--attempts must be at least 1")
    return args


def main(argv=None):
    args = parse(sys.argv[1:] if argv is None else argv)
    # A terminated batch closes its local cluster (the finally blocks run) instead of leaving
    # the worker processes behind; every case already finished is on disk either way.
    signal.signal(signal.SIGTERM, lambda number, frame: sys.exit(128 + number))
    try:
        result = batch(args.jobs, out=args.out, scheduler=args.scheduler, workers=args.workers,
                       group_by=args.group_by, x=args.x, attempts=args.attempts, grace=args.grace,
                       ship_inputs=args.ship_inputs, progress=not args.no_progress)
    except (oraclemesh.InputError, ValueError) as e:
        print("oraclemesh batch: error: %s" % e, file=sys.stderr)
        return 2
    except (oraclemesh.Error, OSError) as e:
        print("oraclemesh batch: %s" % e, file=sys.stderr)
        return 3
    print(results.format_summary(result.summary, result.group_by))
    for row in result.failed:
        print("failed: %s: %s: %s" % (row["case"], row["error_type"], row["error"].splitlines()[0] if row["error"] else ""))
    print("table: %s/results.csv, %s/results.json%s" % (result.out, result.out,
          "; plots: " + ", ".join(result.plots) if result.plots else ""))
    return 1 if result.failed else 0


if __name__ == "__main__":
    sys.exit(main())
