"""examples/implant_in_bone: the generator's files are valid inputs for the core (the bone
surface passes the surface checks, the implant is one valid solid whose sharp edges the core
finds, the resection cut crosses the bone), and the table script's rows (a) thesis, (c) and (d)
Mesh_3 run and parse (at coarse sizes, so this takes seconds)."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import oraclemesh

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "examples", "implant_in_bone")
sys.path.insert(0, EXAMPLE)
sys.path.insert(0, os.path.dirname(HERE))
from installed import require_module  # noqa: E402
for path in ("/usr/lib/freecad/lib", "/usr/lib/freecad-python3/lib"):
    if os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)
require_module("FreeCAD", "freecad")  # the generator needs FreeCAD's Part module
require_module("scipy", "python3-scipy")  # measure.py's distances
import Part  # noqa: E402  (after FreeCAD, which sets it up)
import make_implant_in_bone  # noqa: E402
import measure  # noqa: E402


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("implant_in_bone"))
    make_implant_in_bone.main(folder)
    with open(os.path.join(folder, "reference", "implant_sharp_edges.json")) as f:
        info = json.load(f)
    return folder, info


def coarse_job(inputs, features=False, size=6.0):
    # Coarse tet4: short of volume, which is compared here against the surface's own, 3 %.
    return {"inputs": inputs, "engine": "cgal", "features": features, "element_order": 1, "checks": "warn",
            "criteria": {"default": {"cell_size": size, "facet_size": size, "facet_distance": size / 20,
                                     "edge_size": size / 2}}}


def enclosed_volume(points, tris):
    p = points[tris]
    return np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6


def test_bone_surface_passes_the_core_checks(example, tmp_path):
    folder, _ = example
    points, tris = measure.read_binary_stl(os.path.join(folder, "bone.stl"))
    result = oraclemesh.run(coarse_job([{"name": "bone", "file": "bone.stl", "material": 2}]), base_directory=folder)
    corners = result.points[result.tets[:, :4]]
    volume = np.einsum("ij,ij->i", corners[:, 1] - corners[:, 0],
                       np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 0])).sum() / 6
    assert volume == pytest.approx(enclosed_volume(points, tris), rel=0.03)
    # With one triangle turned over it is refused: the checks are live and the file passes them.
    flipped = os.path.join(str(tmp_path), "one_flipped.stl")
    tris = tris.copy()
    tris[0] = tris[0, ::-1]
    make_implant_in_bone.write_binary_stl(flipped, points, tris)
    with pytest.raises(oraclemesh.InputError, match="oriented against"):
        oraclemesh.run(coarse_job([{"name": "bone", "file": flipped, "material": 2}]))


def test_implant_is_one_valid_solid_whose_sharp_edges_the_core_finds(example):
    folder, info = example
    shape = Part.read(os.path.join(folder, "implant.step"))
    assert len(shape.Solids) == 1 and shape.Solids[0].isValid()
    assert shape.Solids[0].Volume == pytest.approx(info["implant_volume"], rel=1e-6)
    polylines = info["polylines"]
    assert len(polylines) >= 20  # tray top and chamfer, tray bottom, stem tip
    for line in polylines:  # sampled on the exact curves
        for p in (line[0], line[len(line) // 2], line[-1]):
            assert shape.distToShape(Part.Vertex(*p))[0] < 1e-6
    result = oraclemesh.run(coarse_job([{"name": "implant", "file": "implant.step", "material": 1}],
                                       features=True, size=3.0), base_directory=folder)
    assert result.report["features"]["polylines"] == len(polylines)
    assert len(result.feature_edges) > 0


def test_resection_cuts_the_top_of_the_bone(example):
    folder, info = example
    inputs = measure.ImplantInBone(folder, samples=2000)
    lo, hi = inputs.box
    bone_points = inputs.bone[0]
    above = measure.inside_box(bone_points, lo, hi)
    assert above.any() and not above.all()
    # The cut plane crosses the bone (samples of it inside the bone and outside the implant).
    on_plane = inputs.other_samples[np.isclose(inputs.other_samples[:, 2], info["cut_z"])]
    assert len(on_plane) > 100
    # The implant's tray is partly above the resection plane, its stem inside the bone.
    implant_z = inputs.implant[0][:, 2]
    assert implant_z.min() < info["cut_z"] < implant_z.max()
    assert inputs.in_bone(np.array([[0.0, 0.0, implant_z.min() + 1.0]])).all()


def test_table_rows_run_and_parse(example, tmp_path):
    folder, _ = example
    rows_file = os.path.join(str(tmp_path), "rows.json")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    run = subprocess.run([sys.executable, os.path.join(EXAMPLE, "run_table.py"), "--rows", "a,c,d", "--coarsen", "4",
                          "--inputs", folder, "--json", rows_file], capture_output=True, text=True, env=env,
                         timeout=600)
    assert run.returncode == 0, run.stderr
    with open(rows_file) as f:
        rows = {r["row"]: r for r in json.load(f)["rows"]}
    for key in "acd":
        r = rows[key]
        assert r["status"] == "ok", r["status"]
        assert r["tets_per_material"]["1"] > 0 and r["tets_per_material"]["2"] > 0
        assert r["tets"] == sum(r["tets_per_material"].values())
        assert 0 <= r["min_dihedral_deg"] < 70.53 < r["max_dihedral_deg"] <= 180
        # The bone's facet distance is 2 mm x 4 here.
        assert 0 < max(r["hausdorff_bone_and_cut"]) <= 8.0
        assert 0 < max(r["hausdorff_implant"]) < 8.0
        assert r["label"] in run.stdout
    assert rows["c"]["sharp_edges_by_feature_edges_pct"] == 0  # featureless: no feature edges
    assert rows["d"]["sharp_edges_by_feature_edges_pct"] > 95  # protecting balls keep the edges

