"""The thesis experiment on the implant-in-bone example, measured in one run:

    PYTHONPATH=build/python /usr/bin/python3 examples/implant_in_bone/run_table.py
        [--rows a,b,c,d] [--coarsen F] [--json FILE] [--inputs DIR] [--repeat N]

(a) thesis engine with constrained segments, (b) thesis engine featureless, (c) Mesh_3
featureless, (d) Mesh_3 with protecting balls; all from implant_in_bone.json (the thesis
criteria), sliver removal (perturb + exude) on. Per row: tets per material, vertices,
min/max dihedral angle (measured here from the tets), Hausdorff distance between the mesh
boundary and the composite input boundary (both ways), the share of the implant's sharp
edges covered by mesh feature edges and by any boundary mesh edges whose ends lie on them,
and seconds per phase from the report. Rows of an engine this build does not have say so.
--coarsen F multiplies every size in the job by F (a quick check of the script itself).
--repeat N meshes every row N times, the rows taking turns, and the seconds column is the
median: on a shared machine one run of a row can be 1.5x slower than the next. With rows
(a) and (c) it also prints (a)'s time per tetrahedron against (c)'s, repeat by repeat.
The inputs are generated first if missing (make_implant_in_bone.py, needs FreeCAD's Part).
"""
import argparse
import copy
import json
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
try:
    import oraclemesh
except ImportError:
    sys.path.insert(0, os.path.join(os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build")), "python"))
    import oraclemesh

import measure  # noqa: E402

ROWS = {
    "a": ("(a) thesis, segments", "thesis", True),
    "b": ("(b) thesis, featureless", "thesis", False),
    "c": ("(c) Mesh_3, featureless", "cgal", False),
    "d": ("(d) Mesh_3, protecting balls", "cgal", True),
}
SIZE_KEYS = ("cell_size", "facet_size", "facet_distance", "edge_size")


def ensure_inputs(folder):
    needed = ["bone.stl", "implant.step", "resection.brep", "reference/implant_fine.stl",
              "reference/implant_sharp_edges.json"]
    if not all(os.path.exists(os.path.join(folder, n)) for n in needed):
        import make_implant_in_bone
        make_implant_in_bone.main(folder)


def job_for(base, engine, features, coarsen):
    job = copy.deepcopy(base)
    job["engine"] = engine
    if not features:
        job["features"] = False
    job.pop("output", None)
    # The table compares the rows, the featureless ones (which cut the implant's edges) and
    # coarsened runs included: a row short of volume is measured, not refused.
    job["checks"] = "warn"
    for criteria in [job["criteria"]["default"]] + list(job["criteria"].get("materials", {}).values()):
        for key in SIZE_KEYS:
            if key in criteria:
                criteria[key] *= coarsen
    return job


def engine_unavailable(message, engine):
    return ("engine '%s'" % engine) in message and "not available" in message


def measure_row(key, base, inputs, coarsen, folder):
    label, engine, features = ROWS[key]
    job = job_for(base, engine, features, coarsen)
    row = {"row": key, "label": label, "engine": engine, "features": features}
    start = time.perf_counter()
    try:
        result = oraclemesh.run(job, base_directory=folder)
    except oraclemesh.Error as e:
        row["status"] = ("engine '%s' not available" % engine) if engine_unavailable(str(e), engine) else "error: %s" % e
        return row
    row["seconds_total"] = time.perf_counter() - start
    tets = np.asarray(result.tets)[:, :4]
    materials = np.asarray(result.tet_materials)
    row["status"] = "ok"
    row["tets_per_material"] = {str(m): int((materials == m).sum()) for m in sorted(set(materials.tolist()))}
    row["tets"] = int(len(tets))
    row["vertices"] = int(len(np.unique(tets)))
    angles = measure.dihedral_angles(np.asarray(result.points), tets)
    row["min_dihedral_deg"] = float(angles.min())
    row["max_dihedral_deg"] = float(angles.max())
    t0 = time.perf_counter()
    distances = measure.hausdorff(result, inputs)
    row["hausdorff_implant"], row["hausdorff_bone_and_cut"] = distances["implant"], distances["bone_and_cut"]
    implant_facet_distance = job["criteria"]["materials"]["1"]["facet_distance"]
    row["sharp_edges_by_feature_edges_pct"], row["sharp_edges_by_mesh_edges_pct"] = measure.sharp_edges_kept(
        result, inputs, chord_tolerance=implant_facet_distance)
    row["seconds_measure"] = time.perf_counter() - t0
    row["seconds"] = result.report.get("seconds", {})
    row["radius_edge_ratio_applied"] = result.report.get("criteria", {}).get("cell_radius_edge_ratio_applied")
    return row


def number(value, digits):
    return ("%%.%df" % digits) % value


def pair(distances):
    return "%.3f / %.3f" % tuple(distances)


def print_table(rows, coarsen, out=sys.stdout):
    w = out.write
    w("\nimplant_in_bone (mm; implant = material 1, bone = material 2)%s\n\n"
      % ("" if coarsen == 1 else ", sizes x %g" % coarsen))
    w("| row | tets implant | tets bone | vertices | min dihedral | max dihedral | Hausdorff implant "
      "| Hausdorff bone + cut | sharp edges by feature edges % | sharp edges by mesh edges % | seconds |\n")
    w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    for r in rows:
        if r["status"] != "ok":
            w("| %s | %s |||||||||| \n" % (r["label"], r["status"]))
            continue
        t = r["tets_per_material"]
        w("| %s | %d | %d | %d | %s | %s | %s | %s | %s | %s | %s |\n" % (
            r["label"], t.get("1", 0), t.get("2", 0), r["vertices"], number(r["min_dihedral_deg"], 2),
            number(r["max_dihedral_deg"], 2), pair(r["hausdorff_implant"]), pair(r["hausdorff_bone_and_cut"]),
            number(r["sharp_edges_by_feature_edges_pct"], 1),
            number(r["sharp_edges_by_mesh_edges_pct"], 1), number(r["seconds_total"], 1)))
    measured = [r for r in rows if r["status"] == "ok"]
    if measured:
        phases = sorted({p for r in measured for p in r["seconds"]})
        w("\nSeconds per phase (from the report):\n\n| row | %s |\n|---|%s\n"
          % (" | ".join(phases), "---:|" * len(phases)))
        for r in measured:
            w("| %s | %s |\n" % (r["label"], " | ".join(
                number(r["seconds"][p], 2) if p in r["seconds"] else "-" for p in phases)))
        applied = sorted({r["radius_edge_ratio_applied"] for r in measured if r.get("radius_edge_ratio_applied")})
        w("\nRadius-edge bound applied: %s. Hausdorff (mm, mesh -> inputs / inputs -> mesh): from the "
          "boundary nodes, edge midpoints and centroids to the input surfaces (implant: triangles with the implant "
          "on one side, to the implant's surface), and from %d samples of the composite input boundary to the mesh "
          "boundary. Sharp edges: samples of the implant's sharp B-rep edges "
          "within the implant facet distance of a mesh edge whose end nodes lie on them (1e-3 mm).\n"
          % (", ".join("%g" % a for a in applied) or "-", len(INPUTS.boundary_samples) if INPUTS else 0))


def repeat_timings(rows, base, coarsen, folder, repeat):
    """Meshes the measured rows repeat - 1 more times, taking turns, so that a slow spell of
    the machine hits every row; each row's seconds become the median of its runs."""
    measured = [r for r in rows if r["status"] == "ok"]
    for r in measured:
        r["seconds_runs"] = [r["seconds_total"]]
    for _ in range(repeat - 1):
        for r in measured:
            _, engine, features = ROWS[r["row"]]
            job = job_for(base, engine, features, coarsen)
            start = time.perf_counter()
            oraclemesh.run(job, base_directory=folder)
            r["seconds_runs"].append(time.perf_counter() - start)
    for r in measured:
        r["seconds_total"] = statistics.median(r["seconds_runs"])


def print_time_per_tet(rows, out=sys.stdout):
    """Microseconds per tetrahedron of each row, and (a) against (c) (issue 7's target: <= 1)."""
    measured = {r["row"]: r for r in rows if r["status"] == "ok"}
    if not measured:
        return
    out.write("\nTime per tetrahedron, whole job (µs/tet%s): %s\n" % (
        ", median of %d runs" % len(next(iter(measured.values())).get("seconds_runs", [0]))
        if any("seconds_runs" in r for r in measured.values()) else "",
        ", ".join("(%s) %.1f" % (k, 1e6 * r["seconds_total"] / r["tets"]) for k, r in sorted(measured.items()))))
    if "a" in measured and "c" in measured:
        a, c = measured["a"], measured["c"]
        runs = list(zip(a.get("seconds_runs", [a["seconds_total"]]), c.get("seconds_runs", [c["seconds_total"]])))
        ratios = [(ta / a["tets"]) / (tc / c["tets"]) for ta, tc in runs]
        out.write("(a) / (c) per tetrahedron: median %.2f over %d run(s) (each: %s)\n" % (
            statistics.median(ratios), len(ratios), ", ".join("%.2f" % x for x in ratios)))


INPUTS = None


def main(argv=None):
    global INPUTS
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", default="a,b,c,d")
    parser.add_argument("--coarsen", type=float, default=1.0)
    parser.add_argument("--json", help="also write the rows as JSON to this file")
    parser.add_argument("--inputs", default=HERE, help="folder of the generated inputs (default: this folder)")
    parser.add_argument("--repeat", type=int, default=1, help="mesh every row this many times (seconds: median)")
    args = parser.parse_args(argv)
    keys = [k.strip() for k in args.rows.split(",") if k.strip()]
    unknown = [k for k in keys if k not in ROWS]
    if unknown:
        parser.error("unknown rows %s: use a, b, c, d" % ",".join(unknown))
    folder = os.path.abspath(args.inputs)
    ensure_inputs(folder)
    with open(os.path.join(HERE, "implant_in_bone.json")) as f:
        base = json.load(f)
    INPUTS = measure.ImplantInBone(folder)
    rows = []
    for key in keys:
        rows.append(measure_row(key, base, INPUTS, args.coarsen, folder))
        print("%s: %s" % (rows[-1]["label"], rows[-1]["status"]), file=sys.stderr, flush=True)
    if args.repeat > 1:
        repeat_timings(rows, base, args.coarsen, folder, args.repeat)
    print_table(rows, args.coarsen)
    print_time_per_tet(rows)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"coarsen": args.coarsen, "rows": rows}, f, indent=1)
    return 0 if all(r["status"] == "ok" or r["status"].endswith("not available") for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
