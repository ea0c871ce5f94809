"""Headless checks of the workbench parts behind the GUI: quality measure, export files,
old documents gaining the new properties, material names for groups, presets."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402

NEW_PROPERTIES = ("Engine", "Junctions", "PlanarFaces", "InputMaterialNames", "FeatureEdges", "ContactTolerance",
                  "Fineness", "Checks")


def check(params):
    import json
    import numpy as np
    import FreeCAD
    from oraclemesh_fc import makeMesh, export, preferences, quality

    out = {}
    regular = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
    out["regular_tet_min_dihedral"] = float(quality.min_dihedral_angles(regular, [[0, 1, 2, 3]])[0])
    flat = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.3, 0.3, 1e-3]], float)
    out["flat_tet_min_dihedral"] = float(quality.min_dihedral_angles(flat, [[0, 1, 2, 3]])[0])

    from oraclemesh_fc import input_checks
    import Part
    # A wedge prism: a triangle with a 10 degree corner, extruded; a box has none.
    tri = Part.makePolygon([FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(20, 0, 0),
                            FreeCAD.Vector(20, 20 * math.tan(math.radians(10)), 0),
                            FreeCAD.Vector(0, 0, 0)])
    wedge = Part.Face(tri).extrude(FreeCAD.Vector(0, 0, 5))
    out["wedge_small_angles"] = [a for _, a in input_checks.small_edge_angles(wedge)]
    out["box_small_angles"] = input_checks.small_edge_angles(Part.makeBox(5, 5, 5))
    out["cylinder_small_angles"] = input_checks.small_edge_angles(Part.makeCylinder(3, 5))

    doc = FreeCAD.newDocument("Parts")
    block = h.box(doc, "Block", 0, 0, 0, 20, 10, 10)
    rod = doc.addObject("Part::Cylinder", "Rod")
    rod.Radius, rod.Height = 3, 20
    rod.Placement.Base = FreeCAD.Vector(10, 5, -5)
    doc.recompute()
    out["preset_moderate"] = preferences.preset_cell_size("moderate", [block, rod])
    out["bbox_diagonal"] = block.Shape.fuse(rod.Shape).BoundBox.DiagonalLength
    out["preset_automatic"] = preferences.preset_cell_size("automatic", [block, rod])

    mesh = makeMesh(doc, [rod, block], cell_size=3.0, element_order=2)
    mesh.InputMaterialNames = {"Rod": "Steel"}
    doc.recompute()
    if not mesh.isValid():
        raise RuntimeError(mesh.Status)
    fm = mesh.FemMesh
    out["groups"] = {fm.getGroupName(g): len(fm.getGroupElements(g)) for g in fm.Groups
                     if fm.getGroupElementType(g) == "Volume"}
    out["feature_edges"] = len(mesh.FeatureEdges) // 2
    out["feature_edge_nodes_exist"] = all(i in fm.Nodes for i in mesh.FeatureEdges)
    report = json.loads(mesh.Report)
    out["report_min_dihedral"] = report["quality"]["min_dihedral_deg"]
    out["report_counts"] = report["counts"]
    out["report_features"] = report["features"]
    out["report_engine"] = report["engine"]
    out["new_mesh_engine"] = mesh.Engine
    out["report_contact_tolerance"] = report["contact_tolerance"]
    given = makeMesh(doc, [block], cell_size=4.0, element_order=1, contact_tolerance=0.02, name="GivenTolerance")
    doc.recompute()
    out["given_contact_tolerance"] = json.loads(given.Report)["contact_tolerance"]
    ids, angles, groups = quality.element_quality(mesh)
    out["quality_min"] = float(angles.min())
    out["quality_count"] = len(angles)
    out["quality_groups"] = sorted(set(groups.tolist()))

    # Face groups (interfaces, exteriors): area of the corner triangles of their face elements.
    nodes = fm.Nodes
    out["face_group_areas"] = {}
    for g in fm.Groups:
        if fm.getGroupElementType(g) != "Face":
            continue
        area = 0.0
        for e in fm.getGroupElements(g):
            c = [nodes[n] for n in fm.getElementNodes(e)[:3]]
            area += 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).Length
        out["face_group_areas"][fm.getGroupName(g)] = area
    out["exports"] = {}
    for ext in (".vtu", ".inp", ".msh"):
        path = os.path.join(params["workdir"], "parts" + ext)
        export.export_mesh(mesh, path)
        out["exports"][ext] = path
    out["report_volumes"] = report["volume_per_material"]
    try:
        export.export_mesh(mesh, os.path.join(params["workdir"], "parts.xyz"))
        out["bad_extension"] = None
    except export.ExportError as e:
        out["bad_extension"] = str(e)

    # An "old" document: the mesh object without the properties this version added.
    old = makeMesh(doc, [block], cell_size=4.0, element_order=1, name="OldMesh")
    for name in NEW_PROPERTIES:
        old.removeProperty(name)
    # A document of a version that listed the engines in another order stored Mesh_3.
    stored = makeMesh(doc, [block], cell_size=4.0, element_order=1, name="StoredCgal")
    stored.Engine = ["cgal", "thesis"]
    stored.Engine = "cgal"
    path = os.path.join(params["workdir"], "old.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(path)
    old = doc.getObject("OldMesh")
    out["restored_properties"] = {n: hasattr(old, n) for n in NEW_PROPERTIES}
    out["restored_engine"] = old.Engine
    out["restored_fineness"] = old.Fineness
    out["restored_checks"] = old.Checks
    new = makeMesh(doc, [doc.getObject("Block")], name="NewMesh")
    out["new_mesh_fineness"] = new.Fineness
    out["new_mesh_checks"] = new.Checks
    doc.removeObject(new.Name)
    stored = doc.getObject("StoredCgal")
    out["stored_engine"] = [stored.Engine, list(stored.getEnumerationsOfProperty("Engine"))]
    out["restored_junctions"] = old.Junctions
    out["restored_planar_faces"] = old.PlanarFaces
    doc.recompute()
    out["restored_meshes"] = old.isValid() and old.FemMesh.VolumeCount > 0
    out["restored_status"] = old.Status
    return out


h.main(check)
