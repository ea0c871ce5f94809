"""Extra edges of the mesh object (ExtraEdges): a sketch with a line and an arc on a box's top
face, and one picked edge of another (rotated) box lying on the box's side face.

Measures, for each extra edge, the mesh feature edges lying on it (nodes within 1e-6 of the
diagonal of the exact FreeCAD edge) and whether they form one chain from end to end; the
second-order mid nodes of those edges; then a sketch leaving the box (error message, mesh and
document unchanged), bad links, a deleted sketch, SharpAngle 0, and a save/reload.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def sketch(doc, name, z, geometry):
    import FreeCAD
    sk = doc.addObject("Sketcher::SketchObject", name)
    sk.Placement = FreeCAD.Placement(FreeCAD.Vector(0, 0, z), FreeCAD.Rotation())
    for g in geometry:
        sk.addGeometry(g)
    return sk


def chain_facts(fm, feature_pairs, edge, tolerance):
    """Feature edges with both nodes on `edge`: count, summed length, whether they form one
    chain (connected, two ends of degree 1 at the edge's end points), worst node distance."""
    import Part
    nodes = fm.Nodes
    on = {}

    def distance(n):
        if n not in on:
            on[n] = edge.distToShape(Part.Vertex(nodes[n]))[0]
        return on[n]

    pairs = [(a, b) for a, b in feature_pairs if distance(a) <= tolerance and distance(b) <= tolerance]
    degree, neighbours = {}, {}
    for a, b in pairs:
        for x, y in ((a, b), (b, a)):
            degree[x] = degree.get(x, 0) + 1
            neighbours.setdefault(x, []).append(y)
    ends = sorted(n for n, d in degree.items() if d == 1)
    seen, stack = set(), ends[:1]
    while stack:
        n = stack.pop()
        if n not in seen:
            seen.add(n)
            stack.extend(neighbours[n])
    start, end = edge.Vertexes[0].Point, edge.Vertexes[-1].Point
    end_points = sorted(min((nodes[n] - p).Length for p in (start, end)) for n in ends)
    return {
        "edges": len(pairs),
        "length": sum((nodes[a] - nodes[b]).Length for a, b in pairs),
        "edge_length": edge.Length,
        "ends": len(ends),
        "connected": len(seen) == len(degree) and len(degree) > 0,
        "max_degree": max(degree.values()) if degree else 0,
        "end_offsets": end_points,
        "worst_node": max([distance(n) for n in degree] or [float("inf")]),
        "pairs": pairs,
    }


def mid_nodes(fm, pairs):
    """{frozenset(corner ids): mid node id} of the tet10 edges in `pairs`, from the elements."""
    wanted = {frozenset(p) for p in pairs}
    mids = {}
    for e in fm.Volumes:
        ids = fm.getElementNodes(e)
        for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))):
            key = frozenset((ids[a], ids[b]))
            if key in wanted:
                mids[key] = ids[4 + k]
    return mids


def mid_node_offset(fm, mids, pairs, edge):
    """(mid nodes found, largest distance from `edge`) of the tet10 edges in `pairs`."""
    import Part
    nodes = fm.Nodes
    found = [mids[frozenset(p)] for p in pairs if frozenset(p) in mids]
    return len(found), max(edge.distToShape(Part.Vertex(nodes[m]))[0] for m in found)


def check(params):
    import FreeCAD
    import Part
    from oraclemesh_fc import makeMesh
    from oraclemesh_fc import job as jobmod

    doc = FreeCAD.newDocument("ExtraEdges")
    box = h.box(doc, "Box", 0, 0, 0, 20, 20, 10)
    top = sketch(doc, "TopSketch", 10, [
        Part.LineSegment(FreeCAD.Vector(2, 3, 0), FreeCAD.Vector(15, 7, 0)),
        Part.ArcOfCircle(Part.Circle(FreeCAD.Vector(10, 12, 0), FreeCAD.Vector(0, 0, 1), 4),
                         0.0, math.pi)])
    # Another shape, rotated: its local y edge at the origin lies on the box's face y = 20.
    marker = h.box(doc, "Marker", 16, 20, 3, 6, 3, 3)
    marker.Placement.Rotation = FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), 90)
    outside = sketch(doc, "Outside", 10, [
        Part.LineSegment(FreeCAD.Vector(10, 10, 0), FreeCAD.Vector(30, 10, 0))])
    doc.recompute()
    marker_edge = next("Edge%d" % i for i, e in enumerate(marker.Shape.Edges, start=1)
                       if all(abs(v.Point.y - 20) < 1e-9 and abs(v.Point.z - 3) < 1e-9
                              for v in e.Vertexes))

    mesh = makeMesh(doc, [box], cell_size=3.0, element_order=2, sharp_angle=30,
                    extra_edges=[top, (marker, marker_edge)])
    out = {"extra_edges": [(o.Name, list(s)) for o, s in mesh.ExtraEdges]}
    job, _, _, names = jobmod.build_job(mesh)
    out["polyline_names"] = names
    out["polyline_points"] = [len(p["points"]) for p in job["features"]["polylines"]]
    out["features"] = {k: v for k, v in job["features"].items() if k != "polylines"}

    facts = h.recompute_mesh(doc, mesh)
    out["mesh"] = facts
    fm = mesh.FemMesh
    diagonal = box.Shape.BoundBox.DiagonalLength
    tolerance = 1e-6 * diagonal
    out["tolerance"] = tolerance
    ids = list(mesh.FeatureEdges)
    feature_pairs = list(zip(ids[0::2], ids[1::2]))
    out["feature_edges"] = len(feature_pairs)
    edges = {"line": top.Shape.Edges[0], "arc": top.Shape.Edges[1],
             "marker": marker.Shape.getElement(marker_edge)}
    mids = mid_nodes(fm, feature_pairs)
    # The view draws each quadratic feature edge through the mid node stored for it.
    out["stored_mid_nodes_right"] = list(mesh.FeatureEdgeMidNodes) == [
        mids.get(frozenset(p)) for p in feature_pairs]
    chains = {}
    for name, edge in edges.items():
        chains[name] = chain_facts(fm, feature_pairs, edge, tolerance)
        chains[name]["mid_nodes"], chains[name]["mid_offset"] = mid_node_offset(
            fm, mids, chains[name].pop("pairs"), edge)
    out["chains"] = chains

    # A sketch leaving the box: the core refuses it, the message names the sketch's edge.
    before = (fm.NodeCount, fm.VolumeCount, ids)
    objects = sorted((o.Name, o.Label) for o in doc.Objects)
    mesh.ExtraEdges = list(mesh.ExtraEdges) + [outside]
    doc.recompute()
    out["leaving"] = {
        "valid": mesh.isValid(),
        "status": mesh.Status,
        "mesh_kept": (mesh.FemMesh.NodeCount, mesh.FemMesh.VolumeCount,
                      list(mesh.FeatureEdges)) == before,
        "objects_kept": sorted((o.Name, o.Label) for o in doc.Objects) == objects,
    }

    # Links that no longer fit the shape, and picked faces: a clear message before meshing.
    bad = {}
    for case, value in {"edge_gone": [(box, "Edge99")], "face": [(box, "Face1")]}.items():
        mesh.ExtraEdges = value
        try:
            jobmod.build_job(mesh)
            bad[case] = "no error"
        except jobmod.MeshInputError as e:
            bad[case] = str(e)
    out["bad_links"] = bad

    # A deleted sketch drops out of the links; what is left still builds.
    mesh.ExtraEdges = [outside, (marker, marker_edge)]
    doc.removeObject("Outside")
    out["after_delete"] = [(o.Name, list(s)) for o, s in mesh.ExtraEdges]
    out["after_delete_polylines"] = len(jobmod.build_job(mesh)[3])

    # Sharp edges off: the extra edges are still sent, with no sharp edges or junctions.
    mesh.SharpAngle = 0
    features = jobmod.build_job(mesh)[0]["features"]
    out["sharp_off_features"] = {k: (len(v) if k == "polylines" else v) for k, v in features.items()}
    mesh.SharpAngle = 30

    # Save and reload: the links survive.
    mesh.ExtraEdges = [top, (marker, marker_edge)]
    saved = [(o.Name, list(s)) for o, s in mesh.ExtraEdges]
    path = os.path.join(params["workdir"], "extra_edges.FCStd")
    name = mesh.Name
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(path)
    mesh = doc.getObject(name)
    out["saved"] = saved
    out["reloaded"] = [(o.Name, list(s)) for o, s in mesh.ExtraEdges]
    out["reloaded_polylines"] = jobmod.build_job(mesh)[3]
    return out


h.main(check)
