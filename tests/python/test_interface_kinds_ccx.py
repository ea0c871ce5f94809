"""Per-pair interface behaviour (issue 19 item 2) in CalculiX: two steel plates 200 x 20 x 5 mm
stacked (B-rep boxes, tet10, cell size 5), both clamped at x = 0, 100 N pressing down on the top
face. Bonded and tied deflect as one 10 mm beam (Euler-Bernoulli F L^3 / 8 E I = 0.2857 mm);
frictionless contact as two 5 mm beams sharing the load, 4x that. Pulled up at the tip with
contact, the top plate lifts off and the bottom one, with no load of its own, stays put.
The plate BREP is FreeCAD's Part.makeBox(200, 20, 5).exportBrepToString()."""
import os
import subprocess

import numpy as np
import pytest

import oraclemesh
from test_part_surfaces import FACES
from test_writers_meshio import require_programs

HERE = os.path.dirname(os.path.abspath(__file__))
EULER_BERNOULLI = 100.0 * 200.0 ** 3 / (8 * 210000.0 * 20.0 * 10.0 ** 3 / 12)  # 0.2857 mm


def plate_brep(dz):
    """The plate, moved up by dz through a BREP location on the whole shape."""
    with open(os.path.join(HERE, "..", "data", "plate_200x20x5.brep")) as f:
        text = f.read()
    if dz == 0:
        return text
    text = text.replace("Locations 0\n", "Locations 1\n1\n 1 0 0 0\n 0 1 0 0\n 0 0 1 %r\n" % dz, 1)
    assert text.rstrip().endswith("+1 0")
    return text.rstrip()[:-len("+1 0")] + "+1 1\n"


def node_lines(nodes):
    return [", ".join(map(str, nodes[k:k + 8])) for k in range(0, len(nodes), 8)]


def outer_face(result, part, z):
    """The faces of Exterior_<part> in the plane z, as (tet, face) pairs, and their area."""
    points, tets = np.asarray(result.points), np.asarray(result.tets)
    exterior = next(s["faces"] for s in result.surfaces if s["name"] == "Exterior_" + part)
    faces = [(t, f) for t, f in exterior if np.allclose(points[tets[t, list(FACES[f])], 2], z, atol=1e-9)]
    area = sum(0.5 * np.linalg.norm(np.cross(c[1] - c[0], c[2] - c[0]))
               for c in (points[tets[t, list(FACES[f])]] for t, f in faces))
    return faces, area


def pressure_lines(name, faces, pressure):
    return (["*SURFACE, NAME=%s, TYPE=ELEMENT" % name] + ["%d, S%d" % (t + 1, f + 1) for t, f in faces]
            + ["*DLOAD", "%s, P, %.12g" % (name, pressure)])


def run_ccx(folder, fixed, watched, loads):
    """Runs ccx on folder/mesh.inp (steel, nodes `fixed` clamped, the load cards `loads` in one
    static step of up to 100 increments, as contact needs); returns the displacements of the
    nodes `watched` (1-based ids) in the last converged increment, {node: (ux, uy, uz)}."""
    lines = ["*INCLUDE, INPUT=mesh.inp", "*NSET, NSET=Nfix"] + node_lines(fixed)
    lines += ["*NSET, NSET=Nwatch"] + node_lines(watched)
    lines += ["*MATERIAL, NAME=Steel", "*ELASTIC", "210000, 0.3", "*SOLID SECTION, ELSET=Eall, MATERIAL=Steel",
              "*STEP, INC=100", "*STATIC", "1., 1.", "*BOUNDARY", "Nfix, 1, 3"]
    lines += loads + ["*NODE PRINT, NSET=Nwatch", "U", "*END STEP"]
    with open(os.path.join(folder, "job.inp"), "w") as f:
        f.write("\n".join(lines) + "\n")
    run = subprocess.run(["ccx", "job"], cwd=folder, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0 and "*ERROR" not in run.stdout, run.stdout[-2000:]
    with open(os.path.join(folder, "job.dat")) as f:
        last = f.read().split("displacements")[-1]  # the last converged increment
    rows = (line.split() for line in last.splitlines())
    return {int(v[0]): tuple(map(float, v[1:])) for v in rows if len(v) == 4 and v[0].isdigit()}


def solve(folder, pair, load, squeeze=0.0, interfaces=None):
    """Meshes the plates with `pair` (the interfaces.pairs entry without "between", e.g.
    {"kind": "contact", "friction": 0.3}) between them, runs ccx; returns (result, uz of the
    tip nodes, which of them belong to the top plate). `squeeze`: a pressure (N/mm^2) on the
    top plate's top face and the bottom plate's bottom face, pressing them together (it bends
    neither); `interfaces`: more keys of the job's "interfaces"."""
    os.makedirs(folder, exist_ok=True)
    job = {"inputs": [{"name": "top", "brep": plate_brep(5.0), "material": 1},
                      {"name": "bottom", "brep": plate_brep(0.0), "material": 2}],
           "criteria": {"default": {"cell_size": 5, "facet_size": 5}},
           "element_order": 2, "seed": 0,
           "interfaces": dict(interfaces or {}, pairs=[dict(pair, between=["top", "bottom"])]),
           "output": {"files": [os.path.join(folder, "mesh.inp")]}}
    result = oraclemesh.run(job)
    points, tets = np.asarray(result.points), np.asarray(result.tets)
    top_nodes = set(np.unique(tets[np.asarray(result.tet_materials) == 1]).tolist())
    fixed = [i + 1 for i, p in enumerate(points) if abs(p[0]) < 1e-9]
    tip = [i + 1 for i, p in enumerate(points) if abs(p[0] - 200) < 1e-9]
    lines = []
    if load == "down":
        top, area = outer_face(result, "top", 10)
        assert area == pytest.approx(4000, rel=1e-9)
        lines += pressure_lines("Load", top, 100.0 / area + squeeze)
        if squeeze:
            bottom, area = outer_face(result, "bottom", 0)
            assert area == pytest.approx(4000, rel=1e-9)
            lines += pressure_lines("Squeeze", bottom, squeeze)
    else:  # 100 N up, shared by the top plate's nodes on its tip face
        pull = [n for n in tip if n - 1 in top_nodes]
        lines += ["*CLOAD"] + ["%d, 3, %.12g" % (n, 100.0 / len(pull)) for n in pull]
    u = run_ccx(folder, fixed, tip, lines)
    on_top = np.array([n - 1 in top_nodes for n in tip])
    return result, np.array([u[n][2] for n in tip]), on_top


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    require_programs({"ccx": "calculix-ccx"})
    return str(tmp_path_factory.mktemp("interface_kinds"))


@pytest.fixture(scope="module")
def deflections(folder):
    return {kind: solve(os.path.join(folder, kind), {"kind": kind}, "down") for kind in ("bonded", "tied", "contact")}


def test_bonded_and_tied_bend_as_one_beam(deflections):
    bonded = -deflections["bonded"][1].mean()
    tied = -deflections["tied"][1].mean()
    print("tip deflection bonded %.5f tied %.5f Euler-Bernoulli %.5f mm" % (bonded, tied, EULER_BERNOULLI))
    # The tie really joins separate nodes: the tied mesh has one copy per interface node.
    assert len(deflections["tied"][0].points) > len(deflections["bonded"][0].points) + 1000
    assert deflections["tied"][0].report["interfaces"][0]["kind"] == "tied"
    assert tied == pytest.approx(bonded, rel=0.02)
    assert bonded == pytest.approx(EULER_BERNOULLI, rel=0.03)
    assert tied == pytest.approx(EULER_BERNOULLI, rel=0.03)


def test_frictionless_contact_bends_as_two_beams(deflections):
    uz, on_top = deflections["contact"][1], deflections["contact"][2]
    contact = -uz.mean()
    print("tip deflection contact %.5f = %.3f x Euler-Bernoulli of the 10 mm beam" % (contact, contact / EULER_BERNOULLI))
    assert contact == pytest.approx(4.0 * EULER_BERNOULLI, rel=0.03)
    # Pressed together: the plates stay in contact at the tip (no gap, no overlap beyond 1 %).
    assert abs(uz[on_top].mean() - uz[~on_top].mean()) < 0.01 * contact


def test_contact_lets_the_plates_separate(folder):
    _, uz, on_top = solve(os.path.join(folder, "pulled"), {"kind": "contact"}, "up")
    print("pulled apart: top plate tip %.5f, bottom plate tip %.3g mm" % (uz[on_top].mean(), np.abs(uz[~on_top]).max()))
    # The top plate alone (5 mm, 100 N at its tip: F L^3 / 3 E I = 6.1 mm) lifts off...
    assert uz[on_top].mean() > 0.5 * 100.0 * 200.0 ** 3 / (3 * 210000.0 * 20 * 5.0 ** 3 / 12)
    # ...and the unloaded bottom plate stays put.
    assert np.abs(uz[~on_top]).max() < 1e-3 * uz[on_top].mean()


def test_a_softer_contact_slope_lets_the_top_plate_sink_into_the_bottom(folder, deflections):
    """interfaces.contact_stiffness (issue 19): a penalty slope of 0.01 N/mm^3, about the
    bending stiffness per area of a 5 mm plate (8 E I / L^4 / width = 0.011 N/mm^3), instead of
    the steel default (1e5 N/mm^3 for these 5 mm faces): the contact passes less of the load
    to the bottom plate, so the top plate sinks deeper into it, the bottom one less far."""
    result, uz, on_top = solve(os.path.join(folder, "soft"), {"kind": "contact", "contact_stiffness": 0.01}, "down")
    assert result.report["interfaces"][0]["contact_stiffness"] == 0.01
    _, uz_default, on_top_default = deflections["contact"]
    top, bottom = -uz[on_top].mean(), -uz[~on_top].mean()
    top_default, bottom_default = -uz_default[on_top_default].mean(), -uz_default[~on_top_default].mean()
    print("tip deflection with slope 0.01: top %.4f bottom %.4f mm; default slope: top %.4f bottom %.4f mm"
          % (top, bottom, top_default, bottom_default))
    assert top > 1.2 * top_default
    assert 0 < bottom < 0.8 * bottom_default
    # Still bounded by the top plate carrying all 100 N alone (8x the 10 mm beam's deflection).
    assert top < 8 * EULER_BERNOULLI
    # The overlap at the tip, nil with the default slope, is now a good part of a millimetre.
    assert top - bottom > 0.1


def three_boxes_top_shift(folder, kind):
    """Boxes A (0..10)^3, B beside it (x 10..20), C on A (z 10..20), B and C meeting along one
    edge; A-C `kind`, the rest bonded; clamped at z = 0, 100 N along x spread over C's top
    nodes. Returns the mean x displacement of those nodes."""
    from test_part_surfaces import box_surface
    os.makedirs(folder, exist_ok=True)
    job = {"inputs": [{"name": "A", "surface": box_surface((0, 0, 0), (10, 10, 10)), "material": 1},
                      {"name": "B", "surface": box_surface((10, 0, 0), (20, 10, 10)), "material": 2},
                      {"name": "C", "surface": box_surface((0, 0, 10), (10, 10, 20)), "material": 3}],
           "criteria": {"default": {"cell_size": 3, "facet_size": 3}}, "element_order": 2, "seed": 0,
           "interfaces": {"pairs": [{"between": ["A", "C"], "kind": kind}]},
           "output": {"files": [os.path.join(folder, "mesh.inp")]}}
    result = oraclemesh.run(job)
    points = np.asarray(result.points)
    fixed = [i + 1 for i, p in enumerate(points) if abs(p[2]) < 1e-9]
    top = [i + 1 for i, p in enumerate(points) if abs(p[2] - 20) < 1e-9]
    u = run_ccx(folder, fixed, top, ["*CLOAD"] + ["%d, 1, %.12g" % (n, 100.0 / len(top)) for n in top])
    return result, np.mean([u[n][0] for n in top])


def test_a_tie_beside_a_part_bonded_to_both_parts_solves(folder):
    """A and C tied, both bonded to B along one edge: the nodes there stay shared (the report
    warns), and the tie leaves them out, which ccx 2.20 needs (a node tied to itself stops it:
    "zero coefficient on the dependent term"). The tie joins A and C as bonding does; without
    it C would hang on B's edge alone."""
    tied_result, tied = three_boxes_top_shift(os.path.join(folder, "three_tied"), "tied")
    assert tied_result.report["interface_split"]["kept_joined"][0]["parts"] == ["A", "C"]
    _, bonded = three_boxes_top_shift(os.path.join(folder, "three_bonded"), "bonded")
    _, separate = three_boxes_top_shift(os.path.join(folder, "three_separate"), "separate")
    print("top of C along x: tied %.6g, bonded %.6g, separate %.6g mm" % (tied, bonded, separate))
    assert tied == pytest.approx(bonded, rel=1e-3)
    # Hanging on one edge, C turns about it: a mechanism, whose solution ccx gives as a huge
    # displacement of either sign (rounding decides).
    assert abs(separate) > 10 * bonded
