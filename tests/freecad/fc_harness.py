"""Helpers for the scripts that tests/freecad runs inside `freecadcmd`.

A script does:
    import os, sys; sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import fc_harness
    def check(params): ...; return {"key": value, ...}
    fc_harness.main(check)

main() puts the repo's workbench and the core under test first on sys.path, reads the
parameters the pytest side wrote (JSON), runs the check, and writes its result (or the
traceback) as JSON. freecadcmd exits 0 even when a script raises, so the JSON file is the
only reliable channel; the exit code is set too (0 ok, 1 failed).
"""
import json
import os
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def setup_paths():
    """Repo workbench first, then the build's core module."""
    build = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(REPO, "build"))
    sys.path.insert(0, os.path.join(build, "python"))
    sys.path.insert(0, os.path.join(REPO, "Mod", "OracleMesh"))


def main(check):
    setup_paths()
    result_path = os.environ["OMFC_RESULT"]
    try:
        with open(os.environ["OMFC_PARAMS"]) as f:
            params = json.load(f)
        out = check(params) or {}
        out.setdefault("ok", True)
    except BaseException:
        out = {"ok": False, "traceback": traceback.format_exc()}
    with open(result_path, "w") as f:
        json.dump(out, f, indent=1, default=float)
    sys.stdout.flush()
    os._exit(0 if out["ok"] else 1)  # skip FreeCAD's teardown: nothing left to save


# ---------------------------------------------------------------- FEM set-up helpers

def box(doc, name, x0, y0, z0, lx, ly, lz):
    import FreeCAD
    obj = doc.addObject("Part::Box", name)
    obj.Length, obj.Width, obj.Height = lx, ly, lz
    obj.Placement.Base = FreeCAD.Vector(x0, y0, z0)
    return obj


def face_where(obj, axis, value, tol=1e-6):
    """Name ('FaceN') of the planar face of obj lying in the plane <axis> = value."""
    k = "xyz".index(axis)
    for i, face in enumerate(obj.Shape.Faces, start=1):
        bb = face.BoundBox
        lo, hi = (bb.XMin, bb.YMin, bb.ZMin)[k], (bb.XMax, bb.YMax, bb.ZMax)[k]
        if abs(lo - value) < tol and abs(hi - value) < tol:
            return "Face%d" % i
    raise ValueError("%s has no face at %s = %g" % (obj.Label, axis, value))


def edge_along(obj, axis):
    """Name of a straight edge of obj parallel to the axis."""
    k = "xyz".index(axis)
    for i, edge in enumerate(obj.Shape.Edges, start=1):
        d = edge.Vertexes[-1].Point - edge.Vertexes[0].Point
        if abs(abs(d[k]) - d.Length) < 1e-9 * max(d.Length, 1):
            return "Edge%d" % i
    raise ValueError("%s has no edge along %s" % (obj.Label, axis))


def analysis_with_solver(doc):
    import ObjectsFem
    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    solver = ObjectsFem.makeSolverCalculixCcxTools(doc, "CalculiXccxTools")
    solver.AnalysisType = "static"
    solver.GeometricalNonlinearity = "linear"
    solver.SplitInputWriter = False
    solver.WorkingDir = ""
    analysis.addObject(solver)
    return analysis, solver


def material(doc, analysis, name, youngs_mpa, poisson, refs):
    import ObjectsFem
    mat_obj = ObjectsFem.makeMaterialSolid(doc, name)
    mat = mat_obj.Material
    mat["Name"] = name
    mat["YoungsModulus"] = "%r MPa" % float(youngs_mpa)
    mat["PoissonRatio"] = "%r" % float(poisson)
    mat_obj.Material = mat
    mat_obj.References = [(o, "Solid1") for o in refs]
    analysis.addObject(mat_obj)
    return mat_obj


def recompute_mesh(doc, mesh):
    """Recompute the document; returns the mesh's facts, or raises with the mesh's status."""
    doc.recompute()
    if not mesh.isValid() or mesh.FemMesh.VolumeCount == 0:
        raise RuntimeError("meshing failed: " + mesh.Status)
    return mesh_facts(mesh)


def solve_displacements(analysis, solver, workdir):
    """Run CalculiX on the analysis: ({node id: (ux, uy, uz)}, path of the .inp)."""
    from oraclemesh_fc.calculix import run_calculix
    result, inp = run_calculix(analysis, solver, workdir)
    return displacements(result), inp


def displacements(result):
    """{node id: (ux, uy, uz)} of a FEM result object."""
    return {n: (v.x, v.y, v.z) for n, v in zip(result.NodeNumbers, result.DisplacementVectors)}


def mesh_arrays(fm):
    """(points, tets, element ids, node id -> row) of a FemMesh, rows in node id order."""
    import numpy as np
    nodes = fm.Nodes  # a new dict on every access: fetch once
    ids = sorted(nodes)
    index = {n: i for i, n in enumerate(ids)}
    points = np.array([tuple(nodes[n]) for n in ids])
    vols = sorted(fm.Volumes)
    tets = np.array([[index[n] for n in fm.getElementNodes(e)] for e in vols])
    return points, tets, vols, index


def group_volumes(fm):
    """{volume group name: exact tet10 volume of its elements}."""
    import numpy as np
    sys.path.insert(0, os.path.dirname(HERE))
    from tet_geometry import tet10_volumes
    points, tets, vols, _ = mesh_arrays(fm)
    # FreeCAD's order is negatively oriented: sizes are the absolute values.
    vol = dict(zip(vols, np.abs(tet10_volumes(points, tets))))
    return {fm.getGroupName(g): float(sum(vol[e] for e in fm.getGroupElements(g)))
            for g in fm.Groups if fm.getGroupElementType(g) == "Volume"}


def face_group_area(fm, group):
    """Area of a Face group's elements: a tri6 as its four sub-triangles (corner, mid, mid and
    the middle one), which follow a curved face closer than the corner chord."""
    import numpy as np
    nodes = fm.Nodes
    total = 0.0
    for f in fm.getGroupElements(group):
        p = np.array([tuple(nodes[n]) for n in fm.getElementNodes(f)])
        pieces = ((0, 3, 5), (3, 1, 4), (5, 4, 2), (3, 4, 5)) if len(p) == 6 else ((0, 1, 2),)
        total += sum(0.5 * np.linalg.norm(np.cross(p[b] - p[a], p[c] - p[a])) for a, b, c in pieces)
    return total


def common_face_areas(job, report):
    """{interface name: OpenCASCADE's area of its common faces}: the area of the higher-priority
    part's faces that lie inside or on the other part (the core gives an overlap to the part
    listed first, so its boundary there is the interface), from the very B-rep the job hands
    the core (one input per part). "On" is to the report's contact tolerance (a fuzzy common):
    faces closer than it are touching, and bonded in the mesh. Per face the exact common is a
    floor: OpenCASCADE 7.6's fuzzy common of the presse's CAPTEUR_FORCE toroidal fillets with
    CORPS_FIXE is empty where the exact one has 5.85 mm^2 each."""
    import Part
    shapes = {}
    for entry in job["inputs"]:
        shape = Part.Shape()
        shape.importBrepFromString(entry["brep"])
        shapes[entry["name"]] = shape
    tolerance = report["contact_tolerance"]["value"]
    areas = {}
    for interface in report["interfaces"]:
        high, low = interface["parts"]  # material ids follow the priority: the first is higher
        box = shapes[low].BoundBox
        box.enlarge(1e-3)
        areas[interface["name"]] = sum(max(f.common(shapes[low], tolerance).Area, f.common(shapes[low]).Area)
                                       for f in shapes[high].Faces if box.intersect(f.BoundBox))
    return areas


def mesh_facts(mesh_obj):
    """Counts, groups and FreeCAD-orientation facts of a FEM mesh object."""
    import numpy as np
    fm = mesh_obj.FemMesh
    nodes = fm.Nodes
    vols = list(fm.Volumes)
    signs = []
    mid_err = 0.0
    for e in vols:
        ids = fm.getElementNodes(e)
        p = np.array([tuple(nodes[i]) for i in ids])
        signs.append(np.dot(np.cross(p[1] - p[0], p[2] - p[0]), p[3] - p[0]))
        if len(ids) == 10:
            # FreeCAD mid node order 12, 23, 31, 14, 24, 34: the distance to the edge
            # midpoint is 0 inside and small (curved faces) on the boundary.
            for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))):
                length = np.linalg.norm(p[a] - p[b])
                mid_err = max(mid_err, np.linalg.norm(p[4 + k] - 0.5 * (p[a] + p[b])) / length)
    groups = {fm.getGroupName(g): sorted(fm.getGroupElements(g)) for g in fm.Groups
              if fm.getGroupElementType(g) == "Volume"}
    return {
        "nodes": fm.NodeCount,
        "volumes": fm.VolumeCount,
        "nodes_per_volume": len(fm.getElementNodes(vols[0])) if vols else 0,
        "max_signed_volume6": float(max(signs)) if signs else 0.0,
        "min_abs_signed_volume6": float(min(abs(s) for s in signs)) if signs else 0.0,
        "max_mid_node_offset": float(mid_err),
        "group_sizes": {k: len(v) for k, v in groups.items()},
        "groups_cover_all_once": sorted(sum(groups.values(), [])) == sorted(vols),
    }
