"""A batch's results on disk: one folder per case, the table (CSV and JSON), the summary.

OUT/cases/<case>/case.json   the case's record (hash, status, row, full report), written last
OUT/cases/<case>/job.json    the job as the core read it (`oraclemesh job.json` reruns it alone)
OUT/cases/<case>/<outputs>   the job's output.files and output.report
OUT/results.csv, results.json, summary.csv   rewritten after every case
"""
import csv
import json
import math
import os
import shutil
import statistics

from .cases import output_names

LEADING = ("case", "status", "error_type", "error", "phase")
TRAILING = ("warnings", "seconds", "attempts", "reused", "worker", "hash", "source")
# Columns the summary describes (with their per-material variants "<name>_material_<id>").
SUMMARISED = ("tets", "vertices", "min_dihedral_deg", "max_dihedral_deg", "volume", "seconds")


MEASURED = ("tets", "vertices", "boundary_triangles", "feature_edges", "min_dihedral_deg", "max_dihedral_deg",
            "volume")


def is_reserved(name):
    """Whether a study parameter or column name would collide with a column of the table."""
    return (name in LEADING or name in TRAILING or name in MEASURED
            or name.startswith(("tets_material_", "volume_material_", "seconds_")))


def row_of(case, record, attempts):
    """The table row of a case's record (record: what execute.run_case returned)."""
    report = record.get("report") or {}
    counts = report.get("counts", {})
    quality = report.get("quality", {})
    row = {"case": case.name, "status": record["status"], "error_type": record.get("error_type", ""),
           "error": record.get("error", ""), "phase": record.get("phase", "") if record["status"] != "ok" else ""}
    row.update(case.parameters)
    row.update(case.columns)
    if report:
        row["tets"] = counts.get("tets")
        for material, n in sorted(counts.get("tets_per_material", {}).items(), key=_material_order):
            row["tets_material_%s" % material] = n
        for key in ("vertices", "boundary_triangles", "feature_edges"):
            row[key] = counts.get(key)
        row["min_dihedral_deg"] = quality.get("min_dihedral_deg")
        row["max_dihedral_deg"] = quality.get("max_dihedral_deg")
        volumes = report.get("volume_per_material", {})
        row["volume"] = sum(volumes.values()) if volumes else None
        for material, v in sorted(volumes.items(), key=_material_order):
            row["volume_material_%s" % material] = v
        for phase, seconds in report.get("seconds", {}).items():
            row["seconds_%s" % phase] = seconds
        row["warnings"] = len(report.get("warnings", []))
    row.update(seconds=record.get("seconds"), attempts=attempts, reused=False,
               worker=record.get("worker", ""), hash=case.hash, source=case.source)
    return row


def _material_order(item):
    key = item[0]
    return (0, int(key)) if str(key).isdigit() else (1, str(key))


def case_folder(out, case):
    return os.path.join(out, "cases", case.name)


def store(out, case, record, row):
    """Writes a finished case's folder; case.json goes last, so that a study stopped halfway
    never leaves a case that looks done without its files."""
    folder = case_folder(out, case)
    if os.path.isdir(folder):
        shutil.rmtree(folder)
    os.makedirs(folder)
    for name, data in record.get("outputs", {}).items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)
    _write_json(os.path.join(folder, "job.json"), case.job)
    _write_json(os.path.join(folder, "case.json"), {
        "case": case.name, "hash": case.hash, "status": row["status"], "row": row,
        "environment": case.environment, "report": record.get("report")})


def previous_row(out, case):
    """The row of an earlier run of this very case (same hash, succeeded, outputs present),
    marked reused; None if it must run."""
    folder = case_folder(out, case)
    try:
        with open(os.path.join(folder, "case.json")) as f:
            done = json.load(f)
    except (OSError, ValueError):
        return None
    if done.get("hash") != case.hash or done.get("status") != "ok":
        return None
    if not all(os.path.isfile(os.path.join(folder, name)) for name in output_names(case.job)):
        return None
    return dict(done["row"], reused=True, source=case.source)


def columns_of(rows, parameters):
    """Column order: what happened, the study parameters, the measurements, bookkeeping."""
    seen = []
    for row in rows:
        for key in row:
            if key not in seen:
                seen.append(key)
    middle = [k for k in seen if k not in LEADING and k not in TRAILING and k not in parameters]
    return list(LEADING) + [p for p in parameters if p in seen] + middle + [k for k in TRAILING if k in seen]


def summarise(rows, group_by):
    """Per value of the group_by parameter (or one group "all"): case counts and, over the
    cases that succeeded, mean, min, max and sample standard deviation of each measurement."""
    groups = {}
    for row in rows:
        groups.setdefault(str(row.get(group_by, "")) if group_by else "all", []).append(row)
    summary = {}
    for name, members in groups.items():
        ok = [r for r in members if r["status"] == "ok"]
        metrics = {}
        for key in _summarised_columns(ok):
            values = [r[key] for r in ok if isinstance(r.get(key), (int, float)) and not isinstance(r.get(key), bool)]
            if values:
                metrics[key] = {"n": len(values), "mean": statistics.fmean(values), "min": min(values),
                                "max": max(values), "std": statistics.stdev(values) if len(values) > 1 else 0.0}
        summary[name] = {"cases": len(members), "ok": len(ok), "failed": len(members) - len(ok),
                         "metrics": metrics}
    return summary


def _summarised_columns(rows):
    keys = []
    for row in rows:
        for key in row:
            base = key.split("_material_")[0]
            if base in SUMMARISED and key not in keys:
                keys.append(key)
    return keys


def write_tables(out, rows, parameters, group_by, study):
    """results.csv, results.json and summary.csv in OUT (each replaced whole)."""
    columns = columns_of(rows, parameters)
    summary = summarise(rows, group_by)
    _atomic(os.path.join(out, "results.csv"), lambda f: _write_csv(f, columns, rows))
    _write_json(os.path.join(out, "results.json"), {
        "study": study, "group_by": group_by, "columns": columns, "cases": rows, "summary": summary})

    def summary_csv(f):
        writer = csv.writer(f)
        writer.writerow([group_by or "group", "cases", "ok", "failed", "measurement", "n", "mean", "min", "max", "std"])
        for name, group in summary.items():
            for key, m in group["metrics"].items():
                writer.writerow([name, group["cases"], group["ok"], group["failed"], key, m["n"],
                                 _number(m["mean"]), _number(m["min"]), _number(m["max"]), _number(m["std"])])
            if not group["metrics"]:
                writer.writerow([name, group["cases"], group["ok"], group["failed"], "", 0, "", "", "", ""])
    _atomic(os.path.join(out, "summary.csv"), summary_csv)
    return summary


def _write_csv(f, columns, rows):
    writer = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _number(v) if isinstance(v, float) else v for k, v in row.items()})


def _number(value):
    return "" if value is None or (isinstance(value, float) and not math.isfinite(value)) else repr(value)


def _write_json(path, data):
    _atomic(path, lambda f: json.dump(data, f, indent=1, default=str))


def _atomic(path, write):
    partial = path + ".partial"
    with open(partial, "w", newline="") as f:
        write(f)
    os.replace(partial, path)


def format_summary(summary, group_by):
    """The end-of-study table on stdout: one line per group."""
    lines = ["%-14s %6s %4s %6s  %-28s %-18s %s" % (group_by or "group", "cases", "ok", "failed",
                                                    "tets mean [min, max]", "min dihedral", "seconds mean")]
    for name, g in summary.items():
        m = g["metrics"]
        tets = ("%.0f [%d, %d]" % (m["tets"]["mean"], m["tets"]["min"], m["tets"]["max"])) if "tets" in m else "-"
        dihedral = ("%.2f ± %.2f" % (m["min_dihedral_deg"]["mean"], m["min_dihedral_deg"]["std"])
                    if "min_dihedral_deg" in m else "-")
        seconds = ("%.1f" % m["seconds"]["mean"]) if "seconds" in m else "-"
        lines.append("%-14s %6d %4d %6d  %-28s %-18s %s" % (name, g["cases"], g["ok"], g["failed"], tets, dihedral, seconds))
    return "\n".join(lines)
