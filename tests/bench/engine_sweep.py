"""Runs one engine over every model users mesh and prints one table row per case: success,
seconds, tets, min dihedral, the thesis engine's final check, conformity and the volume error
per material against OpenCASCADE Booleans of the same priority composition (FreeCAD's Part).

    PYTHONPATH=build/python /usr/bin/python3 tests/bench/engine_sweep.py \
        [--engine thesis] [--time-limit 300] [--implant DIR] [--only NAME,...] [--variants sharp-tet4,...]

--implant is the folder make_implant_in_bone.py wrote (default examples/implant_in_bone).
Each case runs in a child process under a wall-clock limit (limits.time_limit + 60 s), so a
crash or a hang costs one row, not the sweep. Variants: sharp edges on (30 degrees) or off
(featureless), tet4 or tet10; sizes are the defaults (bounding-box diagonal / 15) except for
implant_in_bone, which keeps the thesis criteria of its job file.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

for path in ("/usr/lib/freecad/lib", "/usr/lib/freecad-python3/lib"):
    if os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
CAD = os.path.join(ROOT, "..", "shared", "data", "cad")
VARIANTS = ["sharp-tet4", "sharp-tet10", "nosharp-tet4", "nosharp-tet10"]


def load_freecad():
    """FreeCAD must be imported before Part and Mesh (importing them first crashes)."""
    import FreeCAD  # noqa: F401


# ------------------------------------------------------------------ reference volumes
def composition_volumes(shapes, roles):
    """{material index from 1: volume} of solid k minus every input before it (cuts too)."""
    volumes = {}
    material = 0
    for k, shape in enumerate(shapes):
        if roles[k] == "cut":
            continue
        material += 1
        owned = shape
        for j in range(k):
            owned = owned.cut(shapes[j])
        volumes[material] = owned.Volume
    return volumes


def solids_of(path):
    import Part
    shape = Part.read(path) if not path.endswith((".brep", ".brp")) else Part.Shape()
    if path.endswith((".brep", ".brp")):
        shape.read(path)
    return list(shape.Solids)


def surface_solid(points, triangles):
    import Mesh
    import Part
    mesh = Mesh.Mesh([[points[i] for i in t] for t in triangles])
    shape = Part.Shape()
    shape.makeShapeFromMesh(mesh.Topology, 1e-6)
    return Part.makeSolid(Part.makeShell(shape.Faces))


# ------------------------------------------------------------------ cases
def step_case(name, filename):
    path = os.path.join(CAD, filename)
    solids = solids_of(path)
    job_input = {"name": name, "file": path}
    if len(solids) > 1:
        job_input["materials"] = list(range(1, len(solids) + 1))
    else:
        job_input["material"] = 1
    return {"inputs": [job_input]}, lambda: composition_volumes(solids, ["material"] * len(solids))


def demo_case():
    import Part
    import FreeCAD
    pin = Part.makeCylinder(5, 30, FreeCAD.Vector(30, 30, -10))
    cut = Part.makeBox(30, 30, 20, FreeCAD.Vector(80, 40, -5))
    plate = Part.makeBox(100, 60, 10)
    inputs = [{"name": "Pin", "brep": pin.exportBrepToString(), "material": 1},
              {"name": "CutCorner", "brep": cut.exportBrepToString(), "role": "cut"},
              {"name": "Plate", "brep": plate.exportBrepToString(), "material": 2}]
    return {"inputs": inputs}, lambda: composition_volumes([pin, cut, plate], ["material", "cut", "material"])


def boxes_case(name, boxes):
    import Part
    import FreeCAD
    shapes = [Part.makeBox(*size, FreeCAD.Vector(*origin)) for origin, size in boxes]
    inputs = [{"name": "%s%d" % (name, i + 1), "brep": s.exportBrepToString(), "material": i + 1}
              for i, s in enumerate(shapes)]
    return {"inputs": inputs}, lambda: composition_volumes(shapes, ["material"] * len(shapes))


def input_kinds_case():
    """tests/freecad/scripts/input_kinds.py: a tessellated cylinder ("bone", a triangle
    surface) through the first of two blocks, and two plates from a STEP compound."""
    import Part
    import FreeCAD
    cylinder = Part.makeCylinder(4, 30, FreeCAD.Vector(15, 10, -10))
    points, triangles = cylinder.tessellate(0.005)
    points = [[p.x, p.y, p.z] for p in points]
    blocks = [Part.makeBox(20, 20, 10), Part.makeBox(20, 20, 10, FreeCAD.Vector(20, 0, 0))]
    plates = [Part.makeBox(40, 8, 4, FreeCAD.Vector(0, 25, 0)), Part.makeBox(40, 8, 4, FreeCAD.Vector(0, 35, 0))]
    inputs = [{"name": "Bone", "surface": {"points": points, "triangles": [list(t) for t in triangles]}, "material": 1},
              {"name": "Blocks", "brep": Part.makeCompound(blocks).exportBrepToString(), "materials": [2, 3]},
              {"name": "Plates", "brep": Part.makeCompound(plates).exportBrepToString(), "materials": [4, 5]}]
    return {"inputs": inputs}, lambda: composition_volumes(
        [surface_solid(points, triangles)] + blocks + plates, ["material"] * 5)


def spheres_case():
    import Part
    import FreeCAD
    spheres = [((0, 0, 0), 5.0), ((6, 0, 0), 4.0), ((0, 7, 1), 3.0)]
    inputs = [{"name": "ball%d" % (i + 1), "sphere": {"center": list(c), "radius": r}, "material": i + 1}
              for i, (c, r) in enumerate(spheres)]
    shapes = [Part.makeSphere(r, FreeCAD.Vector(*c)) for c, r in spheres]
    return {"inputs": inputs}, lambda: composition_volumes(shapes, ["material"] * 3)


def image_case():
    """tests/python/test_labeled_image.py's two touching balls; reference: voxel counts."""
    import numpy as np
    sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
    from test_labeled_image import two_touching_balls, SPACING, ORIGIN
    labels = two_touching_balls()
    voxel = SPACING[0] * SPACING[1] * SPACING[2]
    image = {"labels": labels.tolist(), "spacing": list(SPACING), "origin": list(ORIGIN)}
    counts = {1: float(np.count_nonzero(labels == 1)) * voxel, 2: float(np.count_nonzero(labels == 2)) * voxel}
    return {"inputs": [{"name": "scan", "image": image, "materials": {"1": 1, "2": 2}}]}, lambda: counts


def implant_case(folder):
    """The example's own job (thesis criteria) on the inputs make_implant_in_bone.py wrote."""
    with open(os.path.join(ROOT, "examples", "implant_in_bone", "implant_in_bone.json")) as f:
        job = json.load(f)
    for entry in job["inputs"]:
        entry["file"] = os.path.join(folder, entry["file"])
    job.pop("output", None)

    def reference():
        import Mesh
        import Part
        implant = solids_of(os.path.join(folder, "implant.step"))[0]
        cut = solids_of(os.path.join(folder, "resection.brep"))[0]
        bone = Mesh.Mesh(os.path.join(folder, "bone.stl"))
        shape = Part.Shape()
        shape.makeShapeFromMesh(bone.Topology, 1e-6)
        bone_solid = Part.makeSolid(Part.makeShell(shape.Faces))
        return composition_volumes([implant, cut, bone_solid], ["material", "cut", "material"])
    return job, reference


def cases(implant_folder):
    c = [("part.step", lambda: step_case("part", "part.step")),
         ("screw.step", lambda: step_case("screw", "screw.step")),
         ("Kurbelwelle.stp", lambda: step_case("Kurbelwelle", "Kurbelwelle.stp")),
         ("U_Joint_2.stp", lambda: step_case("U_Joint_2", "U_Joint_2.stp")),
         ("presse_asm.step", lambda: step_case("Presse", "presse_asm.step")),
         ("cube_filet.stp", lambda: ({"inputs": [{"name": "cube", "file": os.path.join(CAD, "cube_filet.stp"),
                                                  "material": 1}]}, lambda: {})),
         ("demo assembly", demo_case),
         ("two-box bar", lambda: boxes_case("box", [((0, 0, 0), (110, 10, 10)), ((90, 0, 0), (110, 10, 10))])),
         ("cantilever", lambda: boxes_case("beam", [((0, 0, 0), (100, 10, 10))])),
         ("input kinds (STL+compounds)", input_kinds_case),
         ("spheres", spheres_case),
         ("image", image_case)]
    if implant_folder and os.path.exists(os.path.join(implant_folder, "bone.stl")):
        c.append(("implant_in_bone", lambda: implant_case(implant_folder)))
    return c


# ------------------------------------------------------------------ one run (child process)
def child(job_path):
    import oraclemesh
    with open(job_path) as f:
        job = json.load(f)
    t0, cpu0 = time.monotonic(), time.process_time()
    try:
        result = oraclemesh.run(job)
    except oraclemesh.Error as e:
        print(json.dumps({"ok": False, "error": str(e), "seconds": time.monotonic() - t0,
                          "cpu_seconds": time.process_time() - cpu0}))
        return
    r = result.report
    thesis = r.get("thesis", {})
    print(json.dumps({"ok": True, "seconds": time.monotonic() - t0, "cpu_seconds": time.process_time() - cpu0, "tets": r["counts"]["tets"],
                      "vertices": r["counts"]["vertices"], "min_dihedral": r["quality"]["min_dihedral_deg"],
                      "final_check": thesis.get("final_check"), "elements_left": len(thesis.get("elements_left", [])),
                      "conformity_ok": r["conformity"]["ok"], "inverted": r["conformity"]["inverted_tets"],
                      "volumes": r["volume_per_material"], "warnings": r["warnings"],
                      "phases": r["seconds"]}))


def run_case(job, time_limit):
    with tempfile.TemporaryDirectory(prefix="oraclemesh-sweep-") as tmp:
        path = os.path.join(tmp, "job.json")
        with open(path, "w") as f:
            json.dump(job, f)
        try:
            p = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", path], capture_output=True,
                               text=True, timeout=time_limit + 60)
        except subprocess.TimeoutExpired:
            return {"ok": False, "error": "no answer within %d s (hang past limits.time_limit)" % (time_limit + 60)}
        lines = [l for l in p.stdout.splitlines() if l.startswith("{")]
        if p.returncode != 0 or not lines:
            return {"ok": False, "error": "exit code %d: %s" % (p.returncode, p.stderr.strip()[-300:])}
        return json.loads(lines[-1])


def final_check_text(fc):
    if not fc:
        return "-"
    return "%d/%d/%d" % (fc["subsegments_not_edges"], fc["encroached_subsegments"], fc["restricted_facets_off_boundary"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--child")
    ap.add_argument("--engine", default="thesis")
    ap.add_argument("--time-limit", type=float, default=300)
    ap.add_argument("--implant", default=os.path.join(ROOT, "examples", "implant_in_bone"))
    ap.add_argument("--only", default="")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--json", default="", help="also append every row as a JSON line to this file")
    args = ap.parse_args()
    if args.child:
        return child(args.child)
    only = [s for s in args.only.split(",") if s]
    print("| model | variant | result | CPU s (wall s) | tets | min dihedral | final check (not edges/encroached/off boundary) "
          "| conformity | worst material volume error vs B-rep | total volume error |")
    print("|---|---|---|---:|---:|---:|---|---|---:|---:|")
    for name, make in cases(args.implant):
        if only and name not in only:
            continue
        load_freecad()
        base, reference = make()
        expected = None
        for variant in args.variants.split(","):
            job = json.loads(json.dumps(base))
            job["engine"] = args.engine
            if variant.startswith("nosharp"):
                job["features"] = False
            elif "features" not in job:
                job["features"] = {"sharp_angle_deg": 30}
            job["element_order"] = 2 if variant.endswith("tet10") else 1
            job.setdefault("optimize", {})["perturb"] = True
            job["limits"] = dict(job.get("limits", {}), time_limit=args.time_limit)
            job["seed"] = 0
            row = run_case(job, args.time_limit)
            if row["ok"] and expected is None:
                expected = reference()
            worst = total = ""
            if row["ok"] and expected:
                errors = {m: 100 * (row["volumes"].get(str(m), 0.0) - v) / v for m, v in expected.items()}
                m = max(errors, key=lambda k: abs(errors[k]))
                worst = "%+.3f %% (material %d)" % (errors[m], m)
                total = "%+.3f %%" % (100 * (sum(row["volumes"].values()) - sum(expected.values())) / sum(expected.values()))
            if row["ok"]:
                print("| %s | %s | ok | %.1f (%.0f) | %d | %.2f | %s (%d left) | %s | %s | %s |" % (
                    name, variant, row["cpu_seconds"], row["seconds"], row["tets"], row["min_dihedral"], final_check_text(row["final_check"]),
                    row["elements_left"], "ok" if row["conformity_ok"] else "FAILED (%d inverted)" % row["inverted"],
                    worst, total), flush=True)
            else:
                print("| %s | %s | error: %s | %s | | | | | | |" % (
                    name, variant, row["error"].replace("\n", " ")[:300],
                    "%.1f (%.0f)" % (row["cpu_seconds"], row["seconds"]) if "seconds" in row else ""),
                    flush=True)
            if args.json:
                with open(args.json, "a") as f:
                    f.write(json.dumps(dict(row, model=name, variant=variant, engine=args.engine, expected=expected)) + "\n")


if __name__ == "__main__":
    main()
