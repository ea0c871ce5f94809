"""Builds the implant-in-bone example, a small stand-in for the thesis' tibia and implant.

    /usr/bin/python3 examples/implant_in_bone/make_implant_in_bone.py [OUT_DIR]
    (or: freecadcmd examples/implant_in_bone/make_implant_in_bone.py, writing next to it)

Units are mm and the model is about a third of a real tibia's proximal end, so that the
thesis criteria (circumradius 1 mm implant / 3 mm bone, facet distance 0.1 mm / 2 mm) mesh
in minutes on a small machine:
- bone.stl: a closed, outward-oriented triangle surface of a bumpy shaft (radius 9 mm) that
  flares to a plateau (radius 16 mm) at the top; z from 0 to 66 mm, about 12,000 triangles.
- implant.step: one B-rep solid, a tray 24 x 18 x 4 mm (rounded corners, chamfered top
  edges) on a stem (radius 4 mm, 30 mm long, chamfered tip, filleted into the tray). The tray
  sits 1 mm deep in the resected bone, the stem goes down the shaft.
- resection.brep: the box above z = 56 mm that the surgeon saws off (a `cut` input).
- reference/: what the table script measures against: implant_fine.stl (the implant
  tessellated to 0.002 mm) and implant_sharp_edges.json (the implant's edges whose faces
  meet at more than 30 degrees, sampled every 0.05 mm on the exact curve).
Deterministic: the same files every run. Needs FreeCAD's Part module (and numpy).
"""
import json
import math
import os
import struct
import sys

import numpy as np

for path in ("/usr/lib/freecad/lib", "/usr/lib/freecad-python3/lib"):
    if os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)
import FreeCAD  # noqa: E402
import Part  # noqa: E402

Vector = FreeCAD.Vector
HERE = os.path.dirname(os.path.abspath(__file__))

CUT_Z = 56.0            # the resection plane
SHAFT_RADIUS = 9.0
PLATEAU_RADIUS = 16.0
FLARE = (38.0, 58.0)    # z range where the shaft widens into the plateau
TOP_Z = 66.0
BOTTOM_CAP = 5.0        # height of the rounded lower end
SHARP_ANGLE_DEG = 30.0  # the job's features.sharp_angle_deg
EDGE_SAMPLE_SPACING = 0.05


def smoothstep(t):
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3 - 2 * t)


def bone_profile(rows):
    """(rho, z) of the bone's meridian from the lower pole to the upper pole, `rows` points
    evenly spaced in arc length (poles excluded), z strictly increasing."""
    # Lower end: a quarter ellipse; then the shaft and flare; then a flattened upper cap.
    parts = []
    a = np.linspace(-math.pi / 2, 0, 400)[1:]
    parts.append(np.stack([SHAFT_RADIUS * np.cos(a), BOTTOM_CAP + BOTTOM_CAP * np.sin(a)], 1))
    z = np.linspace(BOTTOM_CAP, FLARE[1], 2000)[1:]
    rho = SHAFT_RADIUS + (PLATEAU_RADIUS - SHAFT_RADIUS) * smoothstep((z - FLARE[0]) / (FLARE[1] - FLARE[0]))
    parts.append(np.stack([rho, z], 1))
    b = np.linspace(0, math.pi / 2, 400)[1:-1]
    cap = TOP_Z - FLARE[1]
    # A superellipse (exponent 4) keeps the plateau flat-topped yet smooth.
    parts.append(np.stack([PLATEAU_RADIUS * np.cos(b) ** 0.5, FLARE[1] + cap * np.sin(b) ** 0.5], 1))
    curve = np.concatenate(parts)
    curve = np.concatenate([[[0.0, 0.0]], curve, [[0.0, TOP_Z]]])
    arc = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
    targets = np.linspace(0, arc[-1], rows + 2)[1:-1]
    return np.stack([np.interp(targets, arc, curve[:, 0]), np.interp(targets, arc, curve[:, 1])], 1)


def bone_surface(rows=110, columns=96):
    """Points and outward-oriented triangles of the bumpy bone."""
    profile = bone_profile(rows)
    theta = np.linspace(0, 2 * math.pi, columns, endpoint=False)
    rho, z = profile[:, 0][:, None], profile[:, 1][:, None]
    # Smooth bumps (a few percent of the radius), faded out towards the poles so the surface
    # stays smooth there; the radial modulation keeps every meridian a graph over z, so the
    # surface cannot intersect itself.
    fade = np.sin(math.pi * (z - z.min()) / (z.max() - z.min())) ** 2
    bumps = 1 + fade * (0.05 * np.sin(3 * theta + 0.15 * z) + 0.03 * np.cos(5 * theta - 0.08 * z)
                        + 0.02 * np.sin(0.3 * z))
    r = rho * bumps
    ring = np.stack([r * np.cos(theta), r * np.sin(theta), np.broadcast_to(z, r.shape)], -1).reshape(-1, 3)
    points = np.concatenate([[[0, 0, 0.0]], ring, [[0, 0, TOP_Z]]])
    top = len(points) - 1

    def at(i, j):
        return 1 + i * columns + (j % columns)
    tris = []
    for j in range(columns):  # fan round the lower pole, normals pointing down
        tris.append((0, at(0, j + 1), at(0, j)))
    for i in range(rows - 1):
        for j in range(columns):
            a, b, c, d = at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)
            tris += [(a, b, d), (a, d, c)]
    for j in range(columns):
        tris.append((top, at(rows - 1, j), at(rows - 1, j + 1)))
    tris = np.array(tris, dtype=np.int64)
    volume = np.einsum("ij,ij->i", points[tris[:, 0]], np.cross(points[tris[:, 1]], points[tris[:, 2]])).sum() / 6
    assert volume > 0, "bone triangles are oriented inwards"
    return points, tris


def write_binary_stl(path, points, tris, header=b"OracleMesh implant_in_bone example"):
    p = points[tris].astype("<f4")
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    record = np.zeros(len(tris), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    record["n"], record["v"] = normals, p
    with open(path, "wb") as f:
        f.write(header.ljust(80, b"\0") + struct.pack("<I", len(tris)))
        f.write(record.tobytes())


def edges_where(shape, predicate):
    return [e for e in shape.Edges if predicate(e)]


def is_circle(edge, radius, z):
    c = edge.Curve
    return isinstance(c, Part.Circle) and abs(c.Radius - radius) < 1e-6 and abs(c.Center.z - z) < 1e-6


def implant_solid():
    """Stem plus tray with fillets and chamfers, as one valid solid."""
    tray_bottom = CUT_Z - 1.0
    tray = Part.makeBox(24, 18, 4, Vector(-12, -9, tray_bottom))
    vertical = edges_where(tray, lambda e: abs(e.Vertexes[0].Point.z - e.Vertexes[1].Point.z) > 1)
    tray = tray.makeFillet(3.0, vertical)
    stem = Part.makeCylinder(4.0, 31.0, Vector(0, 0, tray_bottom - 30.0))
    implant = tray.fuse(stem).removeSplitter()
    implant = implant.makeFillet(1.5, edges_where(implant, lambda e: is_circle(e, 4.0, tray_bottom)))
    top = tray_bottom + 4
    top_edges = edges_where(implant, lambda e: all(abs(v.Point.z - top) < 1e-6 for v in e.Vertexes)
                            and abs(e.BoundBox.ZMax - top) < 1e-6 and abs(e.BoundBox.ZMin - top) < 1e-6)
    implant = implant.makeChamfer(1.0, top_edges)
    implant = implant.makeChamfer(1.0, edges_where(implant, lambda e: is_circle(e, 4.0, tray_bottom - 30.0)))
    solids = implant.Solids
    if len(solids) != 1 or not solids[0].isValid():
        raise RuntimeError("the implant did not come out as one valid solid")
    return solids[0]


def sharp_edges(solid, angle_deg=SHARP_ANGLE_DEG, spacing=EDGE_SAMPLE_SPACING):
    """Polylines on the exact curves of the edges whose two faces meet at more than angle_deg
    (outward normals compared at several points along the edge)."""
    polylines = []
    for edge in solid.Edges:
        faces = solid.ancestorsOfType(edge, Part.Face)
        if len(faces) != 2 or edge.Length < 1e-9:
            continue
        sharpest = 0.0
        for u in np.linspace(edge.FirstParameter, edge.LastParameter, 7)[1:-1]:
            p = edge.valueAt(u)
            normals = [f.normalAt(*f.Surface.parameter(p)) for f in faces]
            sharpest = max(sharpest, math.degrees(normals[0].getAngle(normals[1])))
        if sharpest > angle_deg:
            count = max(2, int(math.ceil(edge.Length / spacing)) + 1)
            polylines.append([[q.x, q.y, q.z] for q in edge.discretize(Number=count)])
    return polylines


def tessellation(solid, deflection):
    points, tris = solid.tessellate(deflection)
    return np.array([[p.x, p.y, p.z] for p in points]), np.array(tris, dtype=np.int64)


def main(out=HERE):
    os.makedirs(os.path.join(out, "reference"), exist_ok=True)
    points, tris = bone_surface()
    write_binary_stl(os.path.join(out, "bone.stl"), points, tris)

    implant = implant_solid()
    implant.exportStep(os.path.join(out, "implant.step"))
    resection = Part.makeBox(80, 80, 40, Vector(-40, -40, CUT_Z))
    resection.exportBrep(os.path.join(out, "resection.brep"))

    fine_points, fine_tris = tessellation(implant, 0.01)
    write_binary_stl(os.path.join(out, "reference", "implant_fine.stl"), fine_points, fine_tris)
    edges = sharp_edges(implant)
    with open(os.path.join(out, "reference", "implant_sharp_edges.json"), "w") as f:
        json.dump({"sharp_angle_deg": SHARP_ANGLE_DEG, "spacing": EDGE_SAMPLE_SPACING,
                   "implant_volume": implant.Volume, "cut_z": CUT_Z,
                   "resection_box": [[-40, -40, CUT_Z], [40, 40, CUT_Z + 40]],
                   "polylines": edges}, f)
    print("implant_in_bone: bone %d triangles, implant %d faces / %d sharp edges (volume %.1f mm3), "
          "written to %s" % (len(tris), len(implant.Faces), len(edges), implant.Volume, out))


if __name__ == "__main__":
    main(os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 and not sys.argv[1].endswith(".py") else HERE)
