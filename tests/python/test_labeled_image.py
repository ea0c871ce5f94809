"""Labeled voxel images as inputs: a numpy label array or a NRRD file, one material per
mapped label, volumes that match the voxel counts, and errors that name the image and the fix."""
import gzip
import os

import numpy as np
import pytest

import oraclemesh
from oraclemesh.images import write_nrrd
from test_job_contract import tet10_volume

SPACING = (0.5, 0.5, 0.5)
ORIGIN = (-3.0, 1.0, 2.0)


def two_touching_balls(n=40, radius=4.0):
    """labels[z][y][x] of two balls of radius 4 (8 voxels) on a 40^3 grid of 0.5 voxels, with
    label 1 and label 2, touching along x (label 1 wins the voxels both would claim)."""
    z, y, x = np.mgrid[0:n, 0:n, 0:n] * SPACING[0]
    centre1, centre2 = (7.0, 9.8, 10.1), (14.0, 9.8, 10.1)
    labels = np.zeros((n, n, n), np.uint8)
    in1 = (x - centre1[0]) ** 2 + (y - centre1[1]) ** 2 + (z - centre1[2]) ** 2 <= radius ** 2
    in2 = (x - centre2[0]) ** 2 + (y - centre2[1]) ** 2 + (z - centre2[2]) ** 2 <= radius ** 2
    labels[in1] = 1
    labels[in2 & ~in1] = 2
    return labels


def image_job(image, order=2, materials=None):
    return {"inputs": [{"name": "scan", "image": image, "materials": {"1": 3, "2": 5} if materials is None else materials}],
            "criteria": {"default": {"cell_size": 1.5, "facet_size": 1.5, "facet_distance": 0.1}},
            "element_order": order}


def array_image(labels, **extra):
    return dict({"labels": labels, "spacing": list(SPACING), "origin": list(ORIGIN)}, **extra)


def majority_gap(labels, points):
    """Weight of the strongest label minus that of the runner-up at each point, with the
    trilinear weights of the 8 surrounding voxel centres (0 = on a region boundary of the
    image; independent of the core's implementation)."""
    padded = np.pad(labels, 1)  # outside the grid is background
    u = (np.asarray(points) - ORIGIN) / SPACING + 1  # (x, y, z) index into padded
    base = np.floor(u).astype(int)
    f = u - base
    totals = np.zeros((len(u), int(labels.max()) + 1))
    for corner in range(8):
        d = np.array([corner & 1, (corner >> 1) & 1, (corner >> 2) & 1])
        w = np.prod(np.where(d, f, 1 - f), axis=1)
        idx = base + d
        corner_labels = padded[idx[:, 2], idx[:, 1], idx[:, 0]]
        np.add.at(totals, (np.arange(len(u)), corner_labels), w)
    top = np.sort(totals, axis=1)
    return top[:, -1] - top[:, -2]


def boundary_nodes_with_mid_nodes(result):
    """Corner and mid nodes of the boundary triangles of a tet10 mesh."""
    mid_of_edge = {}
    for a, b, m in ((0, 1, 4), (1, 2, 5), (2, 0, 6), (0, 3, 7), (1, 3, 8), (2, 3, 9)):
        for t in result.tets:
            mid_of_edge[(min(t[a], t[b]), max(t[a], t[b]))] = t[m]
    tri = result.boundary_triangles
    mids = [mid_of_edge[(min(x, y), max(x, y))] for t in tri for x, y in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))]
    return np.unique(tri), np.unique(mids)


def tet4_volumes(points, tets):
    p = points[tets[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6


def test_two_touching_balls_mesh_into_two_materials_with_the_voxel_volumes():
    labels = two_touching_balls()
    voxel = np.prod(SPACING)
    result = oraclemesh.run(image_job(array_image(labels)))
    assert result.tets.shape[1] == 10
    assert set(np.unique(result.tet_materials)) == {3, 5}
    volumes = tet10_volumes_by_material(result)
    for label, material in ((1, 3), (2, 5)):
        expected = np.count_nonzero(labels == label) * voxel
        assert abs(volumes[material] - expected) < 0.02 * expected, (label, volumes[material], expected)
    # The balls share an interface: boundary triangles between the two materials, and the
    # whole mesh lies where the image says (origin = centre of voxel [0][0][0]).
    pairs = {tuple(sorted(m)) for m in result.boundary_materials}
    assert (3, 5) in pairs and (0, 3) in pairs and (0, 5) in pairs
    lo = np.array(ORIGIN) - 0.5 * np.array(SPACING)
    hi = np.array(ORIGIN) + (np.array(labels.shape[::-1]) - 0.5) * np.array(SPACING)
    assert np.all(result.points >= lo) and np.all(result.points <= hi)
    centre1 = np.array(ORIGIN) + (7.0, 9.8, 10.1)
    material3 = result.points[np.unique(result.tets[result.tet_materials == 3])]
    assert np.linalg.norm(material3 - centre1, axis=1).max() < 4.0 + 2 * SPACING[0]
    # Boundary nodes are on the image's region boundaries (where the two strongest
    # interpolated labels tie): every corner (snapped), and every mid node except those the
    # second-order safety check left straight because curving would fold a tet (the voxel
    # surface is bumpy at the voxel scale: about 8% of them here).
    corners, mids = boundary_nodes_with_mid_nodes(result)
    assert len(corners) > 200 and len(mids) > 500
    assert np.abs(majority_gap(labels, result.points[corners])).max() < 1e-9
    off_surface = mids[np.abs(majority_gap(labels, result.points[mids])) > 1e-9]
    assert len(off_surface) <= result.report["second_order_straight_fallbacks"] < 0.15 * len(mids)
    straight = {t[4 + k]: 0.5 * (result.points[t[a]] + result.points[t[b]]) for t in result.tets
                for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))) if t[4 + k] in off_surface}
    for node in off_surface:
        np.testing.assert_allclose(result.points[node], straight[node], rtol=0, atol=1e-12)
    report = result.report
    assert report["conformity"]["ok"]
    assert [i["name"] for i in report["inputs"]] == ["scan label 1", "scan label 2"]
    assert report["inputs"][0]["source_volume"] == pytest.approx(np.count_nonzero(labels == 1) * voxel)


def tet10_volumes_by_material(result):
    return {m: tet10_volume(result.points, result.tets[result.tet_materials == m])
            for m in np.unique(result.tet_materials)}


def test_array_nrrd_file_transposed_array_and_run_isolated_give_the_same_mesh(tmp_path):
    labels = two_touching_balls()
    reference = oraclemesh.run(image_job(array_image(labels), order=1))
    write_nrrd(str(tmp_path / "labels.nrrd"), labels, SPACING, ORIGIN)
    from_file = oraclemesh.run(image_job("labels.nrrd", order=1), base_directory=str(tmp_path))
    transposed = oraclemesh.run(image_job(array_image(labels.transpose(2, 1, 0).astype(np.int64), axes="xyz"),
                                          order=1))
    isolated = oraclemesh.run_isolated(image_job(array_image(labels), order=1))
    for other in (from_file, transposed, isolated):
        np.testing.assert_array_equal(other.points, reference.points)
        np.testing.assert_array_equal(other.tets, reference.tets)
        np.testing.assert_array_equal(other.tet_materials, reference.tet_materials)
    # tet4 volumes are chords of the curved surface: still within 2% at this size.
    voxel = np.prod(SPACING)
    v = tet4_volumes(reference.points, reference.tets)
    for label, material in ((1, 3), (2, 5)):
        expected = np.count_nonzero(labels == label) * voxel
        assert abs(v[reference.tet_materials == material].sum() - expected) < 0.02 * expected


def write_header(path, header, data=b""):
    with open(path, "wb") as f:
        f.write(("NRRD0004\n" + header + "\n").encode() + data)


BAD_FILES = [
    ("missing.nrrd", None, "cannot read the image file"),
    ("truncated.nrrd", ("type: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n", b"\1" * 10),
     "truncated: 10 bytes for 64 voxels"),
    ("truncated_gzip.nrrd", ("type: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n",
                             gzip.compress(b"\1" * 64)[:15]), "truncated"),
    ("float.nrrd", ("type: float\ndimension: 3\nsizes: 1 1 1\nencoding: raw\nendian: little\n", b"\0" * 4),
     "labels must be integers"),
    ("bz.nrrd", ("type: uint8\ndimension: 3\nsizes: 1 1 1\nencoding: bzip2\n", b""), "encoding raw or gzip"),
    ("two_d.nrrd", ("type: uint8\ndimension: 2\nsizes: 2 2\nencoding: raw\n", b"\1" * 4), "give a 3D label image"),
    ("flat.nrrd", ("type: uint8\ndimension: 3\nsizes: 1 1 1\nencoding: raw\nspacings: 1 0 1\n", b"\1"),
     "give positive voxel sizes"),
    ("other_label.nrrd", ("type: uint8\ndimension: 3\nsizes: 2 1 1\nencoding: raw\n", b"\1\7"),
     "label 2 of the 'materials' map of input 'scan' does not occur"),
    ("background.nrrd", ("type: uint8\ndimension: 3\nsizes: 2 1 1\nencoding: raw\n", b"\0\0"),
     "no voxel of the image"),
]


@pytest.mark.parametrize("name,content,message", BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_bad_image_files_name_the_file_and_the_fix(tmp_path, name, content, message):
    path = tmp_path / name
    if content:
        write_header(path, *content)
    with pytest.raises(oraclemesh.InputError) as error:
        oraclemesh.run(image_job(str(path), materials={"1": 1, "2": 2}))
    assert message in str(error.value)
    assert str(path) in str(error.value)


BAD_JOBS = [
    (image_job("x.nrrd", materials={}), "needs 'materials'"),
    (image_job("x.nrrd", materials={"0": 1}), "label 0 is background"),
    (image_job("x.nrrd", materials={"1": 0}), "material ids must be positive"),
    ({"inputs": [{"name": "scan", "image": "x.nrrd", "material": 1}]}, "instead of 'material'"),
    ({"inputs": [{"name": "ball", "sphere": {"center": [0, 0, 0], "radius": 1}, "materials": {"1": 1}}]},
     "and to 'image' inputs"),
    (image_job(array_image(np.zeros((2, 2, 2), np.float32))), "must be an integer array"),
    (image_job(array_image(np.zeros((2, 2), np.uint8))), "must be a 3D array"),
    (image_job({"labels": np.ones((2, 2, 2), np.uint8), "spacing": [1, -1, 1]}), "non-positive voxel size"),
    (image_job({"labels": np.ones((2, 2, 2), np.uint8)}), "'spacing' (voxel size in mm) is missing"),
    (image_job(array_image(np.ones((2, 2, 2), np.uint8), axes="yxz")), "'axes' must be"),
]


@pytest.mark.parametrize("job,message", BAD_JOBS, ids=[m for _, m in BAD_JOBS])
def test_bad_image_jobs_say_what_to_fix(job, message):
    with pytest.raises(oraclemesh.InputError) as error:
        oraclemesh.run(job)
    assert message in str(error.value)
    assert "'scan'" in str(error.value) or "'ball'" in str(error.value)
