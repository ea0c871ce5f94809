"""FEM hand-off checks on the demo-like assembly: a steel pin through an aluminium plate (no
hole: the pin wins by priority) with a cut box removing one corner of the plate.
Returns facts about groups, orientation, constraint node search, boundary mid nodes on the
curved CAD face, volumes per material, and what survives save + reopen."""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402

R, PIN_H = 5.0, 40.0
PLATE = (100.0, 60.0, 10.0)
CUT = (80.0, 40.0, -1.0, 30.0, 30.0, 12.0)  # removes x 80..100, y 40..60 of the plate


def build(doc):
    import FreeCAD
    plate = h.box(doc, "Plate", 0, 0, 0, *PLATE)
    pin = doc.addObject("Part::Cylinder", "Pin")
    pin.Radius, pin.Height = R, PIN_H
    pin.Placement.Base = FreeCAD.Vector(50, 30, -15)
    cut = h.box(doc, "CutBox", *CUT)
    doc.recompute()
    return pin, plate, cut


# FreeCAD's tet10 faces (its node order): corners, then the mid nodes of their edges in turn.
FREECAD_TET10_FACES = ((0, 1, 2, 4, 5, 6), (0, 1, 3, 4, 8, 7), (1, 2, 3, 5, 9, 8), (0, 2, 3, 6, 9, 7))


def face_group_facts(fm, report, pin_group, plate_group):
    """Each Face group of the mesh against the core's report: its name, triangle count and area,
    whether every face element is a face of a volume of the right material group (corners and
    mid nodes, so a tri6 is the tet10's own face), and whether its normal points out of that
    volume."""
    import numpy as np
    nodes = fm.Nodes
    group_of_volume = {}
    for g in fm.Groups:
        if fm.getGroupElementType(g) == "Volume":
            for e in fm.getGroupElements(g):
                group_of_volume[e] = fm.getGroupName(g)
    volume_faces = {}  # sorted corner ids -> [(volume id, face nodes, opposite corner)]
    for e in fm.Volumes:
        ids = fm.getElementNodes(e)
        for f in FREECAD_TET10_FACES:
            corners = tuple(ids[i] for i in f[:3])
            opposite = next(ids[i] for i in range(4) if i not in f[:3])
            volume_faces.setdefault(tuple(sorted(corners)), []).append((e, [ids[i] for i in f], opposite))
    part_group = {"Pin": pin_group, "Plate": plate_group}
    reported = {s["name"]: s for s in report["interfaces"] + report["exteriors"]}
    facts = {}
    for g in fm.Groups:
        if fm.getGroupElementType(g) != "Face":
            continue
        name = fm.getGroupName(g)
        entry = reported.get(name, {})
        side = part_group.get((entry.get("parts") or [entry.get("part")])[0])
        area, on_own_volume, outward, nodes_per_face = 0.0, 0, 0, set()
        for f in fm.getGroupElements(g):
            ids = fm.getElementNodes(f)
            nodes_per_face.add(len(ids))
            p = np.array([tuple(nodes[i]) for i in ids[:3]])
            normal = np.cross(p[1] - p[0], p[2] - p[0])
            area += 0.5 * np.linalg.norm(normal)
            for volume, face_nodes, opposite in volume_faces.get(tuple(sorted(ids[:3])), []):
                if group_of_volume.get(volume) != side:
                    continue
                # Same corners; the mid nodes of a tri6 (12, 23, 31) must be the volume's own.
                mids = {frozenset((face_nodes[a], face_nodes[(a + 1) % 3])): face_nodes[3 + a] for a in range(3)}
                if len(ids) == 6 and any(mids[frozenset((ids[a], ids[(a + 1) % 3]))] != ids[3 + a]
                                         for a in range(3)):
                    continue
                on_own_volume += 1
                outward += int(np.dot(normal, np.array(tuple(nodes[opposite])) - p[0]) < 0)
                break
        facts[name] = {"faces": len(fm.getGroupElements(g)), "area": float(area),
                       "curved_area": float(h.face_group_area(fm, g)),
                       "on_own_volume": on_own_volume, "outward": outward,
                       "nodes_per_face": sorted(nodes_per_face),
                       "reported_triangles": entry.get("triangles"), "reported_area": entry.get("area")}
    facts["_reported_names"] = sorted(reported)
    return facts


def check(params):
    import FreeCAD
    import ObjectsFem
    import numpy as np
    from oraclemesh_fc import makeMesh

    out = {}
    doc = FreeCAD.newDocument("Handoff")
    pin, plate, cut = build(doc)
    analysis, solver = h.analysis_with_solver(doc)
    m_pin = h.material(doc, analysis, "MaterialPin", 210000, 0.3, [pin])
    m_plate = h.material(doc, analysis, "MaterialPlate", 70000, 0.33, [plate])
    fixed = ObjectsFem.makeConstraintFixed(doc, "ConstraintFixed")
    fixed_face = h.face_where(plate, "x", 0)
    fixed.References = [(plate, fixed_face)]
    analysis.addObject(fixed)
    mesh = makeMesh(doc, [pin, plate], analysis=analysis, cuts=[cut], **params["mesh"])
    out["mesh"] = h.recompute_mesh(doc, mesh)
    fm = mesh.FemMesh
    out["groups_expected"] = {m_pin.Name + "_Volumes": "pin", m_plate.Name + "_Volumes": "plate"}
    out["in_analysis"] = mesh in analysis.Group
    report = json.loads(mesh.Report)
    out["second_order_straight_fallbacks"] = report.get("second_order_straight_fallbacks")

    points, tets, vols, index = h.mesh_arrays(fm)
    if tets.shape[1] == 10:
        out["volume"] = h.group_volumes(fm)
    out["volume_expected"] = {
        "pin": math.pi * R * R * PIN_H,
        "plate": PLATE[0] * PLATE[1] * PLATE[2] - 20 * 20 * PLATE[2] - math.pi * R * R * PLATE[2],
    }
    centroids = points[tets[:, :4]].mean(axis=1)
    in_cut = ((centroids[:, 0] > 80) & (centroids[:, 1] > 40)).sum()
    out["tets_in_cut_region"] = int(in_cut)

    # FreeCAD finds the constraint nodes geometrically: it must find every node on the face.
    found = set(fm.getNodesByFace(plate.Shape.getElement(fixed_face)))
    nodes = fm.Nodes
    on_face = {n for n, v in nodes.items() if abs(v.x) < 1e-9}
    out["fixed_face_nodes_found"] = len(found)
    out["fixed_face_nodes_on_plane"] = len(on_face)
    out["fixed_face_found_all"] = found == on_face

    # Boundary mid nodes on the pin's free cylinder (outside the plate) lie on the CAD face.
    faces = {}
    local = ((0, 1, 2, 4, 5, 6), (0, 1, 3, 4, 8, 7), (1, 2, 3, 5, 9, 8), (0, 2, 3, 6, 9, 7))
    if tets.shape[1] == 10:
        for t in tets:
            for f in local:
                key = tuple(sorted(t[list(f[:3])]))
                faces[key] = None if key in faces else [t[i] for i in f]
        boundary = np.array([v for v in faces.values() if v is not None])
        p = points[boundary]
        radius = np.hypot(p[..., 0] - 50, p[..., 1] - 30)
        z = p[..., 2]
        outside = (z.max(axis=1) < -1e-6) | (z.min(axis=1) > 10 + 1e-6)
        # Triangles of the end caps (z = -15 or 25) touch the rim too: leave them out.
        on_cap = (np.abs(z + 15).max(axis=1) < 1e-9) | (np.abs(z - 25).max(axis=1) < 1e-9)
        lateral = outside & ~on_cap & (np.abs(radius - R).max(axis=1) < 0.5)
        out["pin_lateral_boundary_faces"] = int(lateral.sum())
        out["pin_lateral_max_radius_error"] = float(np.abs(radius[lateral] - R).max())

    out["face_groups"] = face_group_facts(fm, report, m_pin.Name + "_Volumes", m_plate.Name + "_Volumes")

    # Save, reopen: the proxy, properties and groups must survive.
    path = os.path.join(params["workdir"], "handoff.FCStd")
    doc.saveAs(path)
    name = mesh.Name
    FreeCAD.closeDocument(doc.Name)
    doc2 = FreeCAD.openDocument(path)
    m2 = doc2.getObject(name)
    fm2 = m2.FemMesh
    out["reopened"] = {
        "proxy": type(m2.Proxy).__name__,
        "inputs": [o.Name for o in m2.Inputs],
        "cuts": [o.Name for o in m2.Cuts],
        "volumes": fm2.VolumeCount,
        "groups": sorted(fm2.getGroupName(g) for g in fm2.Groups if fm2.getGroupElementType(g) == "Volume"),
        "face_groups": sorted(fm2.getGroupName(g) for g in fm2.Groups if fm2.getGroupElementType(g) == "Face"),
        "touched": "Touched" in m2.State,
    }

    # An input changes: FreeCAD marks the input touched and the document as needing a
    # recompute (the mesh is its dependent); nothing is remeshed behind the user's back, and
    # the next recompute meshes the new geometry.
    volumes_before = fm2.VolumeCount
    pin2 = doc2.getObject("Pin")
    pin2.Radius = R + 1
    out["after_input_change"] = {
        "input_touched": "Touched" in pin2.State,
        "document_needs_recompute": bool(doc2.mustExecute()),
        "volumes_unchanged": m2.FemMesh.VolumeCount == volumes_before,
    }
    doc2.recompute()
    pin_points, pin_tets, _, _ = h.mesh_arrays(m2.FemMesh)
    centroids2 = pin_points[pin_tets[:, :4]].mean(axis=1)
    out["after_input_change"]["max_pin_radius_meshed"] = float(
        np.hypot(pin_points[pin_tets[:, :4]][..., 0] - 50, pin_points[pin_tets[:, :4]][..., 1] - 30)[
            (centroids2[:, 2] < -1) | (centroids2[:, 2] > 11)].max())

    # Without FEM materials the groups are named after the input labels.
    doc3 = FreeCAD.newDocument("Labels")
    pin3, plate3, cut3 = build(doc3)
    mesh3 = makeMesh(doc3, [pin3, plate3], cuts=[cut3], **params["mesh"])
    doc3.recompute()
    fm3 = mesh3.FemMesh
    out["label_groups"] = sorted(fm3.getGroupName(g) for g in fm3.Groups if fm3.getGroupElementType(g) == "Volume")
    return out


h.main(check)
