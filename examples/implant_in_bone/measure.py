"""Measurements of a mesh against the implant-in-bone inputs, independent of the core:
dihedral angles, Hausdorff distance between the mesh boundary and the composite input
boundary, and how much of the implant's sharp edges the mesh keeps as edges.
numpy + scipy only (reference geometry comes from make_implant_in_bone.py's reference/).
"""
import json
import math
import os
import struct

import numpy as np
from scipy.spatial import cKDTree


def read_binary_stl(path):
    """(points, triangles) of a binary STL, vertices merged by exact position."""
    with open(path, "rb") as f:
        data = f.read()
    count = struct.unpack_from("<I", data, 80)[0]
    record = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    corners = np.frombuffer(data, dtype=record, count=count, offset=84)["v"].reshape(-1, 3).astype(float)
    points, inverse = np.unique(corners, axis=0, return_inverse=True)
    return points, inverse.reshape(-1, 3).astype(np.int64)


# --- tetrahedra ----------------------------------------------------------------------------

def dihedral_angles(points, tets):
    """(m, 6) interior dihedral angles in degrees of tets given by corner indices."""
    p = points[tets[:, :4]]
    faces = [(1, 2, 3, 0), (0, 3, 2, 1), (0, 1, 3, 2), (0, 2, 1, 3)]  # face corners, opposite corner
    normals = []
    for a, b, c, opposite in faces:
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        # Outward: away from the opposite corner, whatever the tet's orientation.
        flip = np.einsum("ij,ij->i", n, p[:, opposite] - p[:, a]) > 0
        n[flip] *= -1
        normals.append(n / np.linalg.norm(n, axis=1, keepdims=True))
    angles = []
    for i in range(4):
        for j in range(i + 1, 4):
            cosine = np.clip(np.einsum("ij,ij->i", normals[i], normals[j]), -1, 1)
            angles.append(180.0 - np.degrees(np.arccos(cosine)))
    return np.stack(angles, 1)


# --- distances -----------------------------------------------------------------------------

def closest_points_on_triangles(p, a, b, c):
    """Closest point to p[i] on triangle (a[i], b[i], c[i]), vectorized (Ericson's regions)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    denom = va + vb + vc
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.where(denom != 0, vb / denom, 0)
        w = np.where(denom != 0, vc / denom, 0)
        result = a + v[:, None] * ab + w[:, None] * ac  # inside the face
        t_ab = np.where(d1 - d3 != 0, d1 / (d1 - d3), 0)
        t_ac = np.where(d2 - d6 != 0, d2 / (d2 - d6), 0)
        t_bc = np.where((d4 - d3) + (d5 - d6) != 0, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 0)
    regions = [
        (vc <= 0) & (d1 >= 0) & (d3 <= 0), a + t_ab[:, None] * ab,
        (vb <= 0) & (d2 >= 0) & (d6 <= 0), a + t_ac[:, None] * ac,
        (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), b + t_bc[:, None] * (c - b),
        (d1 <= 0) & (d2 <= 0), a,
        (d3 >= 0) & (d4 <= d3), b,
        (d6 >= 0) & (d5 <= d6), c,
    ]
    for mask, point in zip(regions[0::2], regions[1::2]):  # vertex regions last: they win
        result = np.where(mask[:, None], point, result)
    return result


def subdivide(points, tris, longest):
    """Split triangles along their longest edge until no edge is longer than `longest`, so a
    triangle's points all lie within `longest` of its centroid."""
    points = [np.asarray(points, float)]
    count = len(points[0])
    tris = np.asarray(tris, np.int64)
    all_points = points[0]
    while True:
        p = all_points[tris]
        lengths = np.stack([np.linalg.norm(p[:, (k + 1) % 3] - p[:, k], axis=1) for k in range(3)], 1)
        long = lengths.max(1) > longest
        if not long.any():
            return all_points, tris
        split, keep = tris[long], tris[~long]
        k = lengths[long].argmax(1)
        rows = np.arange(len(split))
        a, b, c = split[rows, k], split[rows, (k + 1) % 3], split[rows, (k + 2) % 3]
        mids = 0.5 * (all_points[a] + all_points[b])
        m = np.arange(count, count + len(split))
        count += len(split)
        all_points = np.concatenate([all_points, mids])
        tris = np.concatenate([keep, np.stack([a, m, c], 1), np.stack([m, b, c], 1)])


class TriangleDistance:
    """Distance from points to a triangle soup: the exact distance to the nearest of the
    `candidates` triangles with the nearest centroids, after splitting the triangles so that
    none is longer than `longest`. Where the nearest triangle is not among them the answer
    is slightly too large, never too small (on the implant's 0.01 mm tessellation, 300
    points 0.3 mm off the surface: at most 1.5e-4 mm against the distance to every triangle)."""

    def __init__(self, points, tris, longest, candidates=16):
        self.points, self.tris = subdivide(points, tris, longest)
        self.tree = cKDTree(self.points[self.tris].mean(1))
        self.candidates = min(candidates, len(self.tris))

    def __call__(self, queries):
        queries = np.asarray(queries, float)
        result = np.full(len(queries), np.inf)
        for start in range(0, len(queries), 20000):
            q = queries[start:start + 20000]
            _, nearest = self.tree.query(q, k=self.candidates)
            nearest = nearest.reshape(len(q), -1)
            t = self.points[self.tris[nearest.ravel()]]
            qq = np.repeat(q, nearest.shape[1], axis=0)
            d = np.linalg.norm(closest_points_on_triangles(qq, t[:, 0], t[:, 1], t[:, 2]) - qq, axis=1)
            result[start:start + 20000] = d.reshape(len(q), -1).min(1)
        return result


def box_boundary_distance(points, lo, hi):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    outside = np.linalg.norm(np.maximum(np.maximum(lo - points, points - hi), 0), axis=1)
    inside = np.minimum(points - lo, hi - points).min(1)
    return np.where(outside > 0, outside, np.maximum(inside, 0))


def inside_box(points, lo, hi):
    return np.all((points > np.asarray(lo)) & (points < np.asarray(hi)), axis=1)


class InsideTest:
    """Inside a closed triangle surface by the parity of its crossings with the ray from the
    point towards +z; the triangles meeting each ray are found in a grid over x and y."""

    def __init__(self, points, tris, cell=1.0):
        self.t = points[tris]
        self.cell = cell
        lo = np.floor(self.t[:, :, :2].min(1) / cell).astype(np.int64)
        hi = np.floor(self.t[:, :, :2].max(1) / cell).astype(np.int64)
        self.grid = {}
        for k in range(len(tris)):
            for i in range(lo[k, 0], hi[k, 0] + 1):
                for j in range(lo[k, 1], hi[k, 1] + 1):
                    self.grid.setdefault((i, j), []).append(k)

    def __call__(self, queries):
        # Rays through a vertex or along an edge (the bone's poles are on the z axis) would be
        # counted twice; nudging the ray off such special places changes the answer only
        # within 1e-7 of the surface.
        queries = np.asarray(queries, float) + np.array([math.pi, math.e, 0.0]) * 1e-8
        keys = np.floor(queries[:, :2] / self.cell).astype(np.int64)
        candidates = [self.grid.get((int(i), int(j)), []) for i, j in keys]
        owner = np.repeat(np.arange(len(queries)), [len(c) for c in candidates])
        if len(owner) == 0:
            return np.zeros(len(queries), bool)
        t = self.t[np.concatenate([np.asarray(c, np.int64) for c in candidates])]
        q = queries[owner]
        a, b, c = t[:, 0], t[:, 1], t[:, 2]
        # Barycentric coordinates of the query in the triangle's projection on the xy plane.
        det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):  # flat triangles (det 0) never hit
            u = ((q[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (q[:, 1] - a[:, 1])) / det
            v = ((b[:, 0] - a[:, 0]) * (q[:, 1] - a[:, 1]) - (q[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])) / det
            hit = (det != 0) & (u >= 0) & (v >= 0) & (u + v < 1)
            z = a[:, 2] + u * (b[:, 2] - a[:, 2]) + v * (c[:, 2] - a[:, 2])
        crossings = np.bincount(owner[hit & (z > q[:, 2])], minlength=len(queries))
        return crossings % 2 == 1


def sample_triangles(points, tris, count, rng):
    """Area-weighted random points on triangles, with the triangles' unit normals."""
    p = points[tris]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    area = 0.5 * np.linalg.norm(n, axis=1)
    pick = rng.choice(len(tris), size=count, p=area / area.sum())
    r1, r2 = rng.random(count), rng.random(count)
    s = np.sqrt(r1)
    u, v, w = 1 - s, s * (1 - r2), s * r2
    q = u[:, None] * p[pick, 0] + v[:, None] * p[pick, 1] + w[:, None] * p[pick, 2]
    return q, n[pick] / (2 * area[pick])[:, None]


def segment_distance(queries, a, b):
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", queries - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return np.linalg.norm(queries - (a + t[:, None] * ab), axis=1)


class SegmentDistance:
    def __init__(self, a, b):
        self.a, self.b = np.asarray(a, float), np.asarray(b, float)
        self.reach = 0.5 * np.linalg.norm(self.b - self.a, axis=1).max() if len(self.a) else 0
        self.tree = cKDTree(0.5 * (self.a + self.b)) if len(self.a) else None

    def __call__(self, queries, radius):
        """Distance to the nearest segment, or inf when none is within `radius`."""
        result = np.full(len(queries), np.inf)
        if self.tree is None or len(queries) == 0:
            return result
        candidates = self.tree.query_ball_point(queries, radius + self.reach)
        owner = np.repeat(np.arange(len(queries)), [len(c) for c in candidates])
        if len(owner) == 0:
            return result
        seg = np.concatenate([np.asarray(c, np.int64) for c in candidates])
        np.minimum.at(result, owner, segment_distance(queries[owner], self.a[seg], self.b[seg]))
        return result


# --- the inputs ----------------------------------------------------------------------------

class ImplantInBone:
    """The example's composite boundary: implant (priority 1, material 1) over the resection
    box (cut) over the bone (material 2)."""

    def __init__(self, folder, samples=6000, seed=1):
        with open(os.path.join(folder, "reference", "implant_sharp_edges.json")) as f:
            self.info = json.load(f)
        self.bone = read_binary_stl(os.path.join(folder, "bone.stl"))
        self.implant = read_binary_stl(os.path.join(folder, "reference", "implant_fine.stl"))
        self.box = [np.array(c, float) for c in self.info["resection_box"]]
        self.implant_distance = TriangleDistance(*self.implant, longest=0.5)
        # One tree over both surfaces: a k-d tree answers slowly for queries far from its
        # points, and every query is near one of the two.
        bone_points, bone_tris = subdivide(*self.bone, longest=1.0)
        self.surface_distance = TriangleDistance(
            np.concatenate([bone_points, self.implant_distance.points]),
            np.concatenate([bone_tris, self.implant_distance.tris + len(bone_points)]), longest=1.0)
        self.in_bone = InsideTest(*self.bone)
        self.in_implant = InsideTest(*self.implant)
        self.sharp = [np.array(pl, float) for pl in self.info["polylines"]]
        # Samples of the composite boundary: the implant's surface, then the bone's and cut's.
        self.implant_samples, self.other_samples = self._composite_boundary_samples(
            samples, np.random.default_rng(seed))
        self.boundary_samples = np.concatenate([self.implant_samples, self.other_samples])

    def _composite_boundary_samples(self, count, rng):
        # Implant: top priority and the only material 1, so all of its surface is boundary.
        implant, _ = sample_triangles(*self.implant, count, rng)
        # Bone: boundary where neither the implant nor the cut covers it.
        bone, _ = sample_triangles(*self.bone, count, rng)
        bone = bone[~inside_box(bone, *self.box)]
        bone = bone[~self.in_implant(bone)]
        # Cut: its faces are boundary where they cross the bone outside the implant; only the
        # face(s) meeting the bone's bounding box can.
        lo, hi = self.bone[0].min(0), self.bone[0].max(0)
        cut = []
        for axis in range(3):
            for side in (0, 1):
                plane = self.box[side][axis]
                if not lo[axis] < plane < hi[axis]:
                    continue
                a, b = [k for k in range(3) if k != axis]
                flo = np.maximum(self.box[0], lo)
                fhi = np.minimum(self.box[1], hi)
                q = np.empty((count, 3))
                q[:, a] = rng.uniform(flo[a], fhi[a], count)
                q[:, b] = rng.uniform(flo[b], fhi[b], count)
                q[:, axis] = plane
                q = q[self.in_bone(q)]
                cut.append(q[~self.in_implant(q)])
        return implant, np.concatenate([bone] + cut)

    def distance_to_inputs(self, q):
        return np.minimum(self.surface_distance(q), box_boundary_distance(q, *self.box))


def boundary_sample_points(points, triangles):
    """Nodes, edge midpoints and centroids of the mesh's boundary triangles."""
    t = points[triangles]
    nodes = points[np.unique(triangles)]
    mids = np.concatenate([0.5 * (t[:, k] + t[:, (k + 1) % 3]) for k in range(3)])
    return np.concatenate([nodes, mids, t.mean(1)])


def hausdorff(result, inputs):
    """One-sided Hausdorff distances between the mesh boundary and the composite input
    boundary, {"implant": (mesh -> input, input -> mesh), "bone_and_cut": (...)}: the implant
    part compares the boundary triangles with the implant on one side against the implant's
    surface; the other part the remaining triangles against all inputs."""
    tris = np.asarray(result.boundary_triangles)[:, :3]
    corners = np.asarray(result.points)
    implant_side = (np.asarray(result.boundary_materials) == 1).any(1)
    edges = np.linalg.norm(corners[tris] - corners[np.roll(tris, 1, axis=1)], axis=2)
    longest = max(0.5, 0.5 * float(np.median(edges)))
    figures = {}
    for part, side, samples, to_input in (
            ("implant", implant_side, inputs.implant_samples, inputs.implant_distance),
            ("bone_and_cut", ~implant_side, inputs.other_samples, inputs.distance_to_inputs)):
        if not side.any():
            figures[part] = (float("inf"), float("inf"))
            continue
        mesh_to_input = to_input(boundary_sample_points(corners, tris[side])).max()
        # Input samples may lie nearest to either kind of mesh triangle (where they meet).
        input_to_mesh = TriangleDistance(corners, tris, longest)(samples).max()
        figures[part] = (float(mesh_to_input), float(input_to_mesh))
    return figures


def sharp_edges_kept(result, inputs, chord_tolerance, on_curve_tolerance=1e-3):
    """Percentages of the sampled sharp implant edges covered by (feature edges, any boundary
    mesh edges) whose two end nodes lie on the sharp edges."""
    samples = np.concatenate(inputs.sharp)
    curve = SegmentDistance(np.concatenate([pl[:-1] for pl in inputs.sharp]),
                            np.concatenate([pl[1:] for pl in inputs.sharp]))
    points = np.asarray(result.points)
    tris = np.asarray(result.boundary_triangles)[:, :3]
    boundary_edges = np.unique(np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), 1), axis=0)
    features = np.asarray(result.feature_edges).reshape(-1, 2)
    kept = []
    for edges in (features, boundary_edges):
        if len(edges) == 0:
            kept.append(0.0)
            continue
        ends = np.unique(edges)
        on_curve = np.zeros(len(points), bool)
        on_curve[ends] = curve(points[ends], on_curve_tolerance) <= on_curve_tolerance
        edges = edges[on_curve[edges[:, 0]] & on_curve[edges[:, 1]]]
        cover = SegmentDistance(points[edges[:, 0]], points[edges[:, 1]])
        covered = cover(samples, chord_tolerance) <= chord_tolerance
        kept.append(100.0 * covered.mean())
    return kept
