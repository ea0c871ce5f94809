"""Writes the knee study: variants of examples/implant_in_bone and the study file that meshes
each with and without constrained segments.

    /usr/bin/python3 examples/knee_study/make_knee_study.py [--cases N] [--seed S] [--time-limit S]

The thesis meshed 100 implant/tibia configurations of a clinical study; here each variant
moves and tilts the implant of implant_in_bone in the resected bone, drawn from a seeded
distribution, so that the tray's rounded corners and the stem cross the bone surface in a
different place each time:
- shift in the resection plane: normal, sd 1.5 mm, clipped to 3 mm;
- seating depth of the tray: uniform 0.5 to 2 mm below the plane (the example: 1 mm);
- spin about the stem's axis: uniform -10 to 10 degrees;
- tilt: |normal| with sd 3 degrees, clipped to 8, about a horizontal axis of uniform
  direction through the tray's centre.
The draws of variant k do not depend on N: --cases 20 makes the first 20 of the 100.
Writes variants/implant_NNN.brep (FreeCAD's Part module) and study.json next to this file,
and the example's bone.stl and resection.brep if they are missing.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(os.path.dirname(HERE), "implant_in_bone")
sys.path.insert(0, EXAMPLE)
import make_implant_in_bone as example  # noqa: E402  (imports FreeCAD's Part)

FreeCAD, Part = example.FreeCAD, example.Part
VARIANTS = 100
SEED = 2013
# Seconds per case (limits.time_limit): the cases take seconds to a minute, and a case the
# core cannot finish should cost a worker minutes, not the base job's half hour.
TIME_LIMIT = 600


def placement(k, seed=SEED):
    """Variant k's shift (dx, dy), depth, spin, tilt and tilt direction, from a generator of
    its own (seeded by seed and k), so that the first variants are the same for any count."""
    rng = np.random.default_rng([seed, k])
    shift = 1.5 * rng.standard_normal(2)
    shift *= min(1.0, 3.0 / max(float(np.linalg.norm(shift)), 1e-12))
    return {"dx_mm": round(float(shift[0]), 3), "dy_mm": round(float(shift[1]), 3),
            "depth_mm": round(float(rng.uniform(0.5, 2.0)), 3),
            "spin_deg": round(float(rng.uniform(-10, 10)), 2),
            "tilt_deg": round(min(8.0, abs(float(rng.normal(0, 3)))), 2),
            "tilt_azimuth_deg": round(float(rng.uniform(0, 360)), 1)}


def placed_implant(implant, p):
    """The example's implant moved as variant p says: spin and tilt about the centre of the
    tray's underside, then down to the seating depth and sideways."""
    Vector = FreeCAD.Vector
    centre = Vector(0, 0, example.CUT_Z - 1.0)
    azimuth = math.radians(p["tilt_azimuth_deg"])
    placement = FreeCAD.Placement(Vector(p["dx_mm"], p["dy_mm"], 1.0 - p["depth_mm"]), FreeCAD.Rotation())
    tilt = FreeCAD.Rotation(Vector(math.cos(azimuth), math.sin(azimuth), 0), p["tilt_deg"])
    spin = FreeCAD.Rotation(Vector(0, 0, 1), p["spin_deg"])
    about = FreeCAD.Placement(centre, tilt.multiply(spin)).multiply(FreeCAD.Placement(-centre, FreeCAD.Rotation()))
    moved = implant.copy()
    moved.transformShape(placement.multiply(about).toMatrix(), True)
    if not moved.isValid() or len(moved.Solids) != 1:
        raise RuntimeError("variant implant is not one valid solid: %s" % p)
    return moved


def study(variants, time_limit=TIME_LIMIT):
    return {
        "study": "knee",
        "base": "../implant_in_bone/implant_in_bone.json",
        "set": {"output": None, "limits.time_limit": time_limit},
        "parameters": {
            "variant": [{"value": k, "set": {"inputs.0.file": "variants/implant_%03d.brep" % k}, "columns": p}
                        for k, p in enumerate(variants)],
            # The thesis compared its Rule Set T with segments against CGAL's featureless
            # method (Pons et al.), both with the same criteria and sliver removal.
            "approach": [{"value": "segments"},
                         {"value": "featureless", "set": {"engine": "cgal", "features": False}}],
        },
        "name": "v{variant:03d}-{approach}",
        "group_by": "approach",
        "x": "variant",
    }


def main(cases=VARIANTS, seed=SEED, folder=HERE, time_limit=TIME_LIMIT):
    if not all(os.path.exists(os.path.join(EXAMPLE, n)) for n in ("bone.stl", "resection.brep", "implant.step")):
        example.main(EXAMPLE)
    implant = example.implant_solid()
    os.makedirs(os.path.join(folder, "variants"), exist_ok=True)
    variants = [placement(k, seed) for k in range(cases)]
    written = 0
    for k, p in enumerate(variants):
        path = os.path.join(folder, "variants", "implant_%03d.brep" % k)
        if not os.path.exists(path) or _placement_changed(path, p):
            placed_implant(implant, p).exportBrep(path)
            with open(path + ".json", "w") as f:
                json.dump(p, f)
            written += 1
    with open(os.path.join(folder, "study.json"), "w") as f:
        json.dump(study(variants, time_limit), f, indent=1)
    print("knee study: %d variants (%d written), %d cases, in %s/study.json" % (cases, written, 2 * cases, folder))
    return os.path.join(folder, "study.json")


def _placement_changed(path, p):
    """The variant's file was made for another draw (another seed): redo it."""
    try:
        with open(path + ".json") as f:
            return json.load(f) != p
    except (OSError, ValueError):
        return True


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=VARIANTS, help="variants (default 100)")
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--time-limit", type=int, default=TIME_LIMIT, help="seconds per case (default 600)")
    args = parser.parse_args()
    main(args.cases, args.seed, time_limit=args.time_limit)
