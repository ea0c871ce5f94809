"""PlanarFaces of the mesh object: a 40-degree wedge meshed by the thesis engine with and
without it. For each planar face of the wedge, the boundary triangles of the FemMesh whose
centroid is nearest to that face, how many have a node off the face's plane, and their summed
area against the face's; then PlanarFaces with the cgal engine (message, mesh kept)."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402


def wedge_shape(angle_deg, length, height):
    import FreeCAD
    import Part
    v = FreeCAD.Vector
    wire = Part.makePolygon([v(0, 0, 0), v(length, 0, 0),
                             v(length, length * math.tan(math.radians(angle_deg)), 0), v(0, 0, 0)])
    return Part.Face(wire).extrude(v(0, 0, height))


def boundary_triangles(fm):
    """Faces of the tets used once (a one-material mesh's outer surface), as node id triples."""
    count = {}
    for e in fm.Volumes:
        ids = fm.getElementNodes(e)[:4]
        for skip in range(4):
            face = tuple(sorted(ids[k] for k in range(4) if k != skip))
            count[face] = count.get(face, 0) + 1
    return [f for f, n in count.items() if n == 1]


def planar_face_facts(mesh_obj, shape):
    import Part
    nodes = mesh_obj.FemMesh.Nodes
    faces = shape.Faces
    diagonal = shape.BoundBox.DiagonalLength
    facts = [{"triangles": 0, "off_plane": 0, "area": 0.0, "face_area": f.Area} for f in faces]
    for tri in boundary_triangles(mesh_obj.FemMesh):
        a, b, c = (nodes[n] for n in tri)
        centroid = (a + b + c) * (1.0 / 3)
        nearest = min(range(len(faces)), key=lambda k: faces[k].distToShape(Part.Vertex(centroid))[0])
        face = faces[nearest]
        normal = face.normalAt(0, 0)
        origin = face.Vertexes[0].Point
        off = max(abs((p - origin).dot(normal)) for p in (a, b, c))
        fact = facts[nearest]
        fact["triangles"] += 1
        fact["off_plane"] += off > 1e-9 * diagonal
        fact["area"] += 0.5 * (b - a).cross(c - a).Length
    return facts


def check(params):
    import FreeCAD
    from oraclemesh_fc import makeMesh

    doc = FreeCAD.newDocument("PlanarFaces")
    wedge = doc.addObject("Part::Feature", "Wedge")
    wedge.Shape = wedge_shape(40, 30, 10)
    doc.recompute()
    out = {}
    # The wedge's thin edge comes out in pieces at these sizes: kept, its faces are measured.
    mesh = makeMesh(doc, [wedge], cell_size=8.0, element_order=1, engine="thesis", planar_faces=True,
                    checks="warn")
    mesh.FacetDistance = 0.8
    mesh.EdgeSize = 4.0
    for planar in (False, True):
        mesh.PlanarFaces = planar
        h.recompute_mesh(doc, mesh)
        out["on" if planar else "off"] = {"faces": planar_face_facts(mesh, wedge.Shape),
                                          "volumes": mesh.FemMesh.VolumeCount}
    import json
    out["report_planar_faces"] = json.loads(mesh.Report)["thesis"]["planar_faces"]
    baseline = mesh.FemMesh.VolumeCount
    mesh.Engine = "cgal"
    doc.recompute()
    out["cgal"] = {"valid": mesh.isValid(), "status": mesh.Status,
                   "mesh_kept": mesh.FemMesh.VolumeCount == baseline}
    return out


h.main(check)
