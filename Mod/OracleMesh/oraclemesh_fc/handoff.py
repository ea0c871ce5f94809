"""FEM hand-off: numpy mesh arrays (core convention) -> Fem.FemMesh with material groups.

The core returns tets with POSITIVE corner orientation ((v1-v0)x(v2-v0).(v3-v0) > 0, the
VTK/CGAL convention) and tet10 mid nodes in the order 01, 12, 20, 03, 13, 23.
FreeCAD/SMESH wants NEGATIVE orientation ((n2-n1)x(n3-n1).(n4-n1) < 0) and mid nodes in the
order 12, 23, 31, 14, 24, 34 (1-based). Swapping corners 1 and 2 (0-based) flips the sign;
the mid nodes follow the swapped corners:
    FreeCAD corners  c0 c2 c1 c3
    FreeCAD mids     (c0,c2)=m20 (c2,c1)=m12 (c1,c0)=m01 (c0,c3)=m03 (c2,c3)=m23 (c1,c3)=m13
FreeCAD's writeABAQUS swaps corners 1 and 2 back when it writes C3D4/C3D10 (CalculiX's order
is the core's, positive), so an error here shows up as a failed or nonsensical ccx run; the orientation is checked before anything is handed to FreeCAD.

Only numpy and FreeCAD's Fem module are needed, so the same function serves the OracleMesh
object and tests that feed it meshes from other generators (e.g. Gmsh).
"""
import numpy as np

# Column permutations from the core's node order to FreeCAD's.
CORE_TO_FREECAD = {
    4: (0, 2, 1, 3),
    10: (0, 2, 1, 3, 6, 5, 4, 7, 9, 8),
}


class HandoffError(Exception):
    """The mesh arrays break the core's contract (a bug in the mesher, not a user error)."""


def corner_volumes6(points, tets):
    """Six times the signed volume of the corner tetrahedron of each element."""
    p = points[tets[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])


def to_freecad_order(points, tets):
    """Reorder (m, 4|10) tets from the core convention to FreeCAD's; checks orientation."""
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets, dtype=np.int64)
    if tets.ndim != 2 or tets.shape[1] not in CORE_TO_FREECAD:
        raise HandoffError("tets must be an (m, 4) or (m, 10) array, got shape %s" % (tets.shape,))
    if points.ndim != 2 or points.shape[1] != 3:
        raise HandoffError("points must be an (n, 3) array, got shape %s" % (points.shape,))
    if len(tets) and (tets.min() < 0 or tets.max() >= len(points)):
        raise HandoffError("tets reference nodes outside 0..%d" % (len(points) - 1))
    vol = corner_volumes6(points, tets)
    bad = np.flatnonzero(vol <= 0)
    if len(bad):
        raise HandoffError(
            "%d of %d tets are not positively oriented (first: tet %d, 6V = %g): the mesher "
            "broke the node-order contract" % (len(bad), len(tets), bad[0], vol[bad[0]]))
    return tets[:, CORE_TO_FREECAD[tets.shape[1]]]


def build_femmesh(points, tets, tet_materials, groups, surfaces=()):
    """Build a Fem.FemMesh from arrays in the core's convention.

    points (n, 3), tets (m, 4|10) 0-based, tet_materials (m,) material ids.
    groups: list of (group_name, material_ids); every material id present in tet_materials
    must be in exactly one group, so the groups cover every volume once (FreeCAD's CalculiX
    writer only trusts group data when the element counts add up to the volume count).
    surfaces: list of (surface_name, faces (f, 2) = (tet index, CalculiX face 0..3)), the
    core's Result.surfaces; each becomes face elements (tri3 or tri6, see surface_face_nodes)
    and a Face group of that name.
    Node ids are 1..n, volume ids 1..m in the order of the arrays, face ids m+1.. in the
    order of the surfaces.
    """
    import Fem  # FreeCAD module; imported here so the numpy part is usable without FreeCAD

    points = np.asarray(points, dtype=float)
    tet_materials = np.asarray(tet_materials).reshape(-1)
    fc_tets = to_freecad_order(points, tets)
    if len(tet_materials) != len(fc_tets):
        raise HandoffError("%d material ids for %d tets" % (len(tet_materials), len(fc_tets)))

    group_of = {}
    for name, ids in groups:
        for mid in ids:
            if int(mid) in group_of:
                raise HandoffError("material %d is in groups '%s' and '%s'"
                                   % (mid, group_of[int(mid)], name))
            group_of[int(mid)] = name
    missing = sorted(set(np.unique(tet_materials).tolist()) - set(group_of))
    if missing:
        raise HandoffError("tets with material ids %s have no group" % missing)

    mesh = Fem.FemMesh()
    for i, (x, y, z) in enumerate(points.tolist(), start=1):
        mesh.addNode(x, y, z, i)
    for i, nodes in enumerate((fc_tets + 1).tolist(), start=1):
        mesh.addVolume(nodes, i)

    element_ids = np.arange(1, len(fc_tets) + 1)
    for name, ids in groups:
        members = element_ids[np.isin(tet_materials, [int(m) for m in ids])]
        if len(members) == 0:
            continue  # a material that lost every tet (covered by higher priorities / cut)
        gid = mesh.addGroup(name, "Volume")
        mesh.addGroupElements(gid, members.tolist())

    # FreeCAD draws a mesh's face elements only when it has no volumes, so these change
    # nothing on screen; they are there to be selected, exported and referred to.
    face_id = len(fc_tets)
    for name, faces in surfaces:
        nodes = surface_face_nodes(tets, faces) + 1
        ids = list(range(face_id + 1, face_id + len(nodes) + 1))
        for fid, face in zip(ids, nodes.tolist()):
            mesh.addFace(face, fid)
        face_id += len(nodes)
        gid = mesh.addGroup(name, "Face")
        mesh.addGroupElements(gid, ids)
    return mesh


# Corners of the CalculiX faces S1..S4 (012, 031, 132, 230) in reverse, so that the face's
# right-hand normal points out of its tet: for a part's exterior, out of the part.
OUTWARD_FACE_CORNERS = ((0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3))


def surface_face_nodes(tets, faces):
    """Core node indices of element faces [(tet, CalculiX face 0..3)] as FreeCAD face
    elements: (f, 3) corners, or for tet10 (f, 6) corners then the mid nodes of the edges
    12, 23, 31 (SMESH's tri6 order); corners ordered so the normal points out of the tet."""
    tets = np.asarray(tets, dtype=np.int64)
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 2)
    if len(faces) and (faces[:, 1].min() < 0 or faces[:, 1].max() > 3
                       or faces[:, 0].min() < 0 or faces[:, 0].max() >= len(tets)):
        raise HandoffError("a surface face refers to no face of the mesh's tets")
    mid_column = {frozenset(e): 4 + k for k, e in enumerate(MID_NODE_EDGES)}
    columns = []
    for corners in OUTWARD_FACE_CORNERS:
        row = list(corners)
        if tets.shape[1] == 10:
            row += [mid_column[frozenset((corners[i], corners[(i + 1) % 3]))] for i in range(3)]
        columns.append(row)
    columns = np.array(columns, dtype=np.int64)
    return tets[faces[:, 0][:, None], columns[faces[:, 1]]]


# Tet10 corner pairs of the core's mid-node columns 4..9 (01, 12, 20, 03, 13, 23).
MID_NODE_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


def feature_edge_mid_nodes(tets, feature_edges):
    """Mid node index of each feature edge (core indices, as the core's arrays), or an empty
    list for linear tets. Quadratic faces are drawn through their mid nodes, which lie on the
    CAD surface: a straight line between the corners of a curved edge would sink under them."""
    import numpy as np
    tets, feature_edges = np.asarray(tets), np.asarray(feature_edges).reshape(-1, 2)
    if tets.ndim != 2 or tets.shape[1] != 10 or not len(feature_edges):
        return []
    n = int(tets[:, :4].max()) + 1

    def keys(a, b):
        return np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b)

    all_keys = np.concatenate([keys(tets[:, i], tets[:, j]) for i, j in MID_NODE_EDGES])
    all_mids = np.concatenate([tets[:, 4 + k] for k in range(6)])
    all_keys, first = np.unique(all_keys, return_index=True)
    wanted = keys(feature_edges[:, 0], feature_edges[:, 1])
    at = np.searchsorted(all_keys, wanted)
    if np.any(at >= len(all_keys)) or np.any(all_keys[np.minimum(at, len(all_keys) - 1)] != wanted):
        raise ValueError("a feature edge of the core is no edge of its tets")
    return all_mids[first[at]].tolist()

