"""A stand-in for the OracleMesh core built from OpenCASCADE Booleans and the Gmsh CLI.

Used only by tests (ORACLEMESH_TEST_CORE=gmsh) to prove the FreeCAD hand-off (job building,
node order, volume groups, CalculiX) independently of the real core, and as a reference mesh.
It speaks the same `run(job, progress)` contract and returns arrays in the core's convention
(positive corner orientation, tet10 mid nodes 01, 12, 20, 03, 13, 23). It must run inside
FreeCAD (it composes the priority regions with FreeCAD's Part module).
Only what the tests use is supported: BREP text inputs, roles, default cell size, order 1/2.
"""
import json
import os
import subprocess
import tempfile
import time

import numpy as np

__version__ = "gmsh-stand-in"


class Error(Exception):
    pass


class InputError(Error):
    pass


class LimitError(Error):
    pass


class Cancelled(Error):
    pass


class Result:
    def __init__(self, points, tets, tet_materials, report):
        self.points, self.tets, self.tet_materials, self.report = points, tets, tet_materials, report
        self.boundary_triangles = np.zeros((0, 3), np.int64)
        self.feature_edges = np.zeros((0, 2), np.int64)


# Flip a negatively oriented tet by swapping corners 0 and 1 (mid nodes follow).
_FLIP = {4: [1, 0, 2, 3], 10: [1, 0, 2, 3, 4, 6, 5, 8, 7, 9]}


def _regions(job):
    """[(material id, solid region)] after priority composition (Booleans: the slow way)."""
    import Part

    higher = []
    regions = []
    for i, item in enumerate(job.get("inputs", [])):
        shape = Part.Shape()
        shape.importBrepFromString(item["brep"])
        if not shape.Solids:
            raise InputError("inputs[%d] '%s' has no solid" % (i, item.get("name")))
        solid = Part.makeCompound(shape.Solids)
        if item.get("role", "material") == "material":
            region = solid.cut(higher) if higher else solid
            if region.Solids:
                regions.append((int(item["material"]), region))
        higher.append(solid)
    if not regions:
        raise InputError("nothing to mesh")
    return regions


def run(job, progress=None, base_directory=None):
    import FreeCAD
    import Part

    timings = {}
    t0 = time.time()
    regions = _regions(job)
    # General fuse makes the regions share their common faces (a conforming compound).
    pieces = [s for _, r in regions for s in r.Solids]
    fused = pieces[0].generalFuse(pieces[1:])[0] if len(pieces) > 1 else Part.makeCompound(pieces)
    solids = fused.Solids
    timings["compose"] = time.time() - t0

    size = job.get("criteria", {}).get("default", {}).get("cell_size")
    if size is None:
        size = fused.BoundBox.DiagonalLength / 15
    order = int(job.get("element_order", 2))
    t1 = time.time()
    with tempfile.TemporaryDirectory(prefix="om_gmsh_") as tmp:
        brep = os.path.join(tmp, "model.brep")
        Part.makeCompound(solids).exportBrep(brep)
        geo = os.path.join(tmp, "model.geo")
        with open(geo, "w") as f:
            f.write('SetFactory("OpenCASCADE");\nMerge "model.brep";\n'
                    "Mesh.CharacteristicLengthMax = %r;\nMesh.ElementOrder = %d;\n"
                    "Mesh.SecondOrderLinear = 0;\nMesh.Optimize = 1;\nGeneral.NumThreads = 1;\n"
                    % (float(size), order))
        msh = os.path.join(tmp, "model.msh")
        proc = subprocess.run(["gmsh", geo, "-3", "-format", "msh41", "-o", msh],
                              cwd=tmp, capture_output=True, text=True)
        if proc.returncode != 0 or not os.path.exists(msh):
            raise Error("gmsh failed: %s" % (proc.stdout[-2000:] + proc.stderr[-2000:]))
        import meshio
        mesh = meshio.read(msh)
    timings["mesh"] = time.time() - t1

    kind = "tetra10" if order == 2 else "tetra"
    blocks = [(c.data, mesh.cell_data["gmsh:geometrical"][k])
              for k, c in enumerate(mesh.cells) if c.type == kind]
    tets = np.concatenate([b for b, _ in blocks]).astype(np.int64)
    volume_tags = np.concatenate([t for _, t in blocks])

    # Material of each Gmsh volume: the region containing one of its tets' centroid.
    points = np.asarray(mesh.points, float)
    materials = np.zeros(len(tets), np.int32)
    for tag in np.unique(volume_tags):
        sel = volume_tags == tag
        centroid = points[tets[sel][0, :4]].mean(axis=0)
        for mid, region in regions:
            if region.isInside(FreeCAD.Vector(*centroid), 1e-7, True):
                materials[sel] = mid
                break
        else:
            raise Error("gmsh volume %d is in no region" % tag)

    # Compact the nodes and make every tet positive (the core's contract).
    used, inverse = np.unique(tets, return_inverse=True)
    tets = inverse.reshape(tets.shape).astype(np.int64)
    points = points[used]
    p = points[tets[:, :4]]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    tets[vol < 0] = tets[vol < 0][:, _FLIP[tets.shape[1]]]
    if progress is not None:
        progress("done", 1.0)
    counts = {str(m): int((materials == m).sum()) for m in np.unique(materials)}
    report = {"engine": "gmsh-stand-in", "counts": {"vertices": int(len(points)),
                                                    "tets": int(len(tets)),
                                                    "tets_per_material": counts},
              "seconds": timings}
    output = job.get("output") or {}
    if output.get("report"):
        with open(output["report"], "w") as f:
            json.dump(report, f, indent=1)
    return Result(points, tets, materials, report)
