"""Triangle-surface inputs (STL ASCII and binary, OFF, and triangles in the job itself, as
FreeCAD Mesh objects send them): meshed like any other input, and broken surfaces give errors
that name the input, the file and the defect."""
import math
import struct

import numpy as np
import pytest

import oraclemesh
from test_job_contract import tet10_volume


def icosphere(radius=5.0, center=(0.0, 0.0, 0.0), subdivisions=3):
    """(points, triangles) of a subdivided icosahedron, outward oriented."""
    t = (1 + 5 ** 0.5) / 2
    pts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
           (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    pts = [np.array(p, float) / np.linalg.norm(p) for p in pts]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
            (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
            (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        cache, new = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = pts[a] + pts[b]
                pts.append(m / np.linalg.norm(m))
                cache[key] = len(pts) - 1
            return cache[key]
        for a, b, c in tris:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = new
    return np.array(pts) * radius + np.array(center), np.array(tris)


def polyhedron_volume(points, tris):
    p = points[tris]
    return np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6


def write_ascii_stl(path, points, tris):
    with open(path, "w") as f:
        f.write("solid test\n")
        for a, b, c in tris:
            f.write(" facet normal 0 0 0\n  outer loop\n")
            for v in (a, b, c):
                f.write("   vertex %.17g %.17g %.17g\n" % tuple(points[v]))
            f.write("  endloop\n endfacet\n")
        f.write("endsolid test\n")


def write_binary_stl(path, points, tris):
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(tris)))
        for a, b, c in tris:
            f.write(struct.pack("<12fH", 0, 0, 0, *points[a], *points[b], *points[c], 0))


def job_for(path, **criteria):
    return {"inputs": [{"name": "bone", "file": str(path), "material": 1}],
            "criteria": {"default": dict({"cell_size": 2, "facet_size": 1.5, "facet_distance": 0.05},
                                         **criteria)},
            "element_order": 1,
            "checks": "warn"}  # tet4 at these sizes: the bone's volume is measured where it matters


@pytest.mark.parametrize("writer", [write_ascii_stl, write_binary_stl])
def test_stl_meshes_with_the_polyhedron_volume(tmp_path, writer):
    points, tris = icosphere()
    path = tmp_path / "ball.stl"
    writer(path, points, tris)
    job = job_for(path, facet_distance=0.02)
    job["element_order"] = 2
    result = oraclemesh.run(job)
    exact = polyhedron_volume(points, tris)
    volume = tet10_volume(result.points, result.tets)
    assert abs(volume - exact) < 0.005 * exact
    # Boundary nodes lie on the input surface (here: within the sphere's chord sagitta).
    r = np.linalg.norm(result.points[np.unique(result.boundary_triangles)], axis=1)
    assert r.max() <= 5.0 + 1e-9 and r.min() > 5.0 * math.cos(math.radians(10))


def test_reversed_orientation_is_fixed_silently(tmp_path):
    points, tris = icosphere(subdivisions=2)
    path = tmp_path / "inside_out.stl"
    write_ascii_stl(path, points, tris[:, ::-1])
    result = oraclemesh.run(job_for(path))
    assert result.report["inputs"][0]["source_volume"] > 0


def test_off_with_a_flipped_triangle_names_it(tmp_path):
    points, tris = icosphere(subdivisions=2)
    tris = tris.copy()
    tris[7] = tris[7][::-1]
    path = tmp_path / "ball.off"
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(points), len(tris)))
        f.writelines("%.17g %.17g %.17g\n" % tuple(p) for p in points)
        f.writelines("3 %d %d %d\n" % tuple(t) for t in tris)
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job_for(path))
    message = str(err.value)
    assert "1 triangle oriented against its neighbours" in message
    assert "triangle 8 of the file (counting from 1)" in message and "reverse" in message


def broken(tmp_path, kind):
    points, tris = icosphere(subdivisions=2)
    path = tmp_path / ("%s.stl" % kind)
    if kind == "hole":
        write_ascii_stl(path, points, tris[1:])
    elif kind == "self_intersecting":
        other, otris = icosphere(subdivisions=2, center=(3.0, 0, 0))
        write_ascii_stl(path, np.vstack([points, other]), np.vstack([tris, otris + len(points)]))
    elif kind == "flipped":
        flipped = tris.copy()
        flipped[[3, 40]] = flipped[[3, 40], ::-1]
        write_binary_stl(path, points, flipped)
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "truncated":
        write_binary_stl(path, points, tris)
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    return path


@pytest.mark.parametrize("kind, words", [
    ("hole", ["not closed", "border edges"]),
    ("self_intersecting", ["intersects itself"]),
    ("flipped", ["2 triangles oriented against their neighbours", "first: triangle 4 of the file",
                 "reverse the corner order"]),
    ("empty", ["empty"]),
    ("truncated", ["truncated"]),
])
def test_broken_surfaces_give_clear_errors(tmp_path, kind, words):
    path = broken(tmp_path, kind)
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job_for(path))
    message = str(err.value)
    assert "bone" in message and str(path) in message
    for word in words:
        assert word in message


def surface_job(points, tris, **input_keys):
    job = job_for("unused.stl")
    # numpy arrays as they are: the package turns them into JSON lists.
    job["inputs"] = [dict({"name": "bone", "material": 1,
                           "surface": {"points": np.asarray(points), "triangles": np.asarray(tris)}},
                          **input_keys)]
    return job


def test_surface_in_the_job_meshes_with_the_polyhedron_volume():
    points, tris = icosphere(center=(1.0, 2.0, 3.0))
    # Given inside out: turned round silently, like a file.
    job = surface_job(points, tris[:, ::-1])
    job["criteria"]["default"]["facet_distance"] = 0.02
    job["element_order"] = 2
    result = oraclemesh.run(job)
    exact = polyhedron_volume(points, tris)
    entry = result.report["inputs"][0]
    assert entry["kind"] == "triangle surface" and entry["name"] == "bone"
    assert abs(entry["source_volume"] - exact) < 1e-9 * exact
    assert abs(tet10_volume(result.points, result.tets) - exact) < 0.005 * exact
    # Where the surface is: boundary nodes on the sphere about (1, 2, 3).
    r = np.linalg.norm(result.points[np.unique(result.boundary_triangles)] - (1, 2, 3), axis=1)
    assert r.max() <= 5.0 + 1e-9 and r.min() > 5.0 * math.cos(math.radians(10))


@pytest.mark.parametrize("defect, words", [
    ("hole", ["(triangle surface) is not closed", "border edges"]),
    ("flipped", ["1 triangle oriented against its neighbours", "triangles[7]", "reverse"]),
    ("bad_index", ["triangles[5] refers to point 9999", "indices count from 0"]),
    ("not_a_list", ["'surface' must be"]),
    ("empty", ["is empty"]),
])
def test_broken_surface_in_the_job_names_the_defect(defect, words):
    points, tris = icosphere(subdivisions=2)
    tris = tris.copy()
    if defect == "hole":
        tris = tris[1:]
    elif defect == "flipped":
        tris[7] = tris[7][::-1]
    elif defect == "bad_index":
        tris[5][1] = 9999
    elif defect == "empty":
        tris = tris[:0]
    job = surface_job(points, tris)
    if defect == "not_a_list":
        job["inputs"][0]["surface"] = {"points": 3, "triangles": []}
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job)
    message = str(err.value)
    assert "input 'bone'" in message
    for word in words:
        assert word in message


@pytest.mark.parametrize("keys, words", [
    ({"solids": "together"}, ["'solids' applies to STEP, IGES and BREP inputs only"]),
    ({"materials": [1, 2]}, ["'materials' belongs to STEP, IGES or BREP inputs"]),
])
def test_solid_keys_are_refused_on_surfaces(keys, words):
    points, tris = icosphere(subdivisions=1)
    job = surface_job(points, tris, **keys)
    job["inputs"][0].pop("material")
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(job)
    for word in words:
        assert word in str(err.value)
