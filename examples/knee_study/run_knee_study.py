"""The thesis' knee study in one command: variants of implant_in_bone, each meshed with and
without constrained segments on a Dask cluster, and the thesis' table.

    PYTHONPATH=build/python /usr/bin/python3 examples/knee_study/run_knee_study.py
        [--cases N] [--workers N | --scheduler ADDRESS] [--out DIR] [--seed S] [--time-limit S]

--cases N: the first N of the 100 variants (2N cases). The variants and study.json are
written first (make_knee_study.py, FreeCAD's Part module); the batch (oraclemesh.batch)
writes OUT/results.csv, results.json, summary.csv, tets.png and min_dihedral.png and reuses
the cases a previous run did with the same job and inputs. Prints per approach: cases,
failures, tetrahedra mean and range, minimum dihedral angle mean ± standard deviation, and
the throughput of this run (cases meshed per minute of wall time, cluster start included).
"""
import argparse
import os
import signal
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

THESIS = ("Thesis (100 tibiae at full size, CGAL 3.7): segments 437,000 tets (295,000 - 707,992), "
          "featureless 900,898 (614,234 - 1,533,011): 2.06x; min dihedral with segments 8.72 ± 1.31 deg.")
LABELS = {"segments": "segments (Rule Set T, sharp edges constrained)",
          "featureless": "featureless (CGAL Mesh_3, no features)"}


def import_oraclemesh():
    try:
        import oraclemesh
    except ImportError:
        sys.path.insert(0, os.path.join(os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build")), "python"))
        import oraclemesh
    return oraclemesh


def table(result):
    """The thesis' table as Markdown, one row per approach."""
    lines = ["| approach | cases | failed | tetrahedra: mean | range | min dihedral: mean ± sd | "
             "vertices: mean | seconds per case: mean |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for approach, group in result.summary.items():
        m = group["metrics"]
        if "tets" in m:
            cells = ["{:,.0f}".format(m["tets"]["mean"]), "{:,} - {:,}".format(m["tets"]["min"], m["tets"]["max"]),
                     "%.2f ± %.2f" % (m["min_dihedral_deg"]["mean"], m["min_dihedral_deg"]["std"]),
                     "{:,.0f}".format(m["vertices"]["mean"]), "%.1f" % m["seconds"]["mean"]]
        else:
            cells = ["-"] * 5
        lines.append("| %s | %d | %d | %s |" % (LABELS.get(approach, approach), group["cases"], group["failed"],
                                                 " | ".join(cells)))
    s, f = (result.summary.get(k, {}).get("metrics", {}).get("tets") for k in ("segments", "featureless"))
    if s and f:
        lines.append("\nfeatureless / segments, mean tetrahedra: %.2fx" % (f["mean"] / s["mean"]))
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=100, help="variants to mesh (default 100)")
    parser.add_argument("--seed", type=int, default=2013)
    parser.add_argument("--time-limit", type=int, default=600,
                        help="limits.time_limit of every case, seconds (default 600; part of the cases' hash)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="local cluster of N workers (default: one per core)")
    where.add_argument("--scheduler", help="an existing Dask scheduler address")
    parser.add_argument("--out", default=os.path.join(HERE, "out"), help="results folder (default: out/ here)")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args()
    # Terminated, the batch still closes its local cluster (see oraclemesh.study.__main__).
    signal.signal(signal.SIGTERM, lambda number, frame: sys.exit(128 + number))

    sys.path.insert(0, HERE)
    import make_knee_study  # FreeCAD's Part: imported here, not where Dask's workers import this file
    study = make_knee_study.main(args.cases, args.seed, time_limit=args.time_limit)
    oraclemesh = import_oraclemesh()
    started = time.time()
    result = oraclemesh.batch([study], out=args.out, workers=args.workers, scheduler=args.scheduler,
                              progress=not args.no_progress)
    seconds = time.time() - started
    workers = args.scheduler or "%d local worker(s)" % (args.workers or os.cpu_count())
    print("\nKnee study: %d variants x 2 approaches = %d cases (%d meshed now, %d reused) on %s: %.0f s%s\n"
          % (args.cases, len(result.rows), result.ran, result.reused, workers, seconds,
             ", %.2f cases/min" % (60 * result.ran / seconds) if result.ran else ""))
    print(table(result))
    print(THESIS)
    for row in result.failed:
        print("failed: %s: %s: %s" % (row["case"], row["error_type"], (row["error"] or "").splitlines()[0]))
    print("table: %s" % os.path.join(result.out, "results.csv"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
