"""Issue 18: bad input through the CLI and oraclemesh.run ends in a message naming the input
or key and the fix (exit code 2, oraclemesh.InputError), never a signal, a hang or an
unrelated error; the interpreter goes on meshing afterwards.

tests/data/bad/ holds one job per case (with the files they read); EXPECTED says what each
message must name.
"""
import glob
import math
import os
import resource
import subprocess

import numpy as np
import pytest

import oraclemesh

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "..", "data", "bad")
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build"))
CLI = os.path.join(BUILD, "oraclemesh")

# Per job file of tests/data/bad: what its message must contain (the input or key, the fix).
EXPECTED = {
    "material_overflow": ["inputs[0].material", "4294967297", "positive integer ids"],
    "element_order_overflow": ["element_order", "4294967297"],
    "max_vertices_overflow": ["limits.max_vertices", "1e+19"],
    "number_overflow": ["1e999", "numbers must be finite"],
    "tiny_cell_size": ["criteria.default.cell_size", "model units"],
    "name_not_string": ["inputs[0].name must be a string"],
    "role_not_string": ["inputs[0].role must be a string", "\"cut\""],
    "cell_size_string": ["criteria.default.cell_size must be a number"],
    "deep_nesting": ["levels deep"],
    "nrrd_huge_header": ["input 'scan'", "huge_header.nrrd", "truncated"],
    "nrrd_anisotropic": ["input 'scan'", "anisotropic.nrrd", "resample"],
    "polyline_far": ["features.polylines[0] leaves the meshed domain: point 1", "outside the bounding box"],
    "polyline_wrong_brep": ["features.polylines[0] point 0", "the brep must be the edge"],
    "stl_nan_vertex": ["input 'bone'", "nan_vertex.stl", "not a finite number"],
    "stl_inf_vertex": ["input 'bone'", "inf_vertex.stl", "not a finite number"],
    "off_huge_counts": ["input 'part'", "huge_counts.off", "declares 1000000000 vertices"],
    # Non-finite numbers in the text formats and NRRD headers: refused where they are read.
    "obj_nan_vertex": ["input 'bone'", "nan_vertex.obj", "is not a readable obj file", "export it again"],
    "off_inf_vertex": ["input 'part'", "inf_vertex.off", "no x y z numbers at vertex 2 of 4 (line 4)"],
    "stl_ascii_nan_vertex": ["input 'bone'", "nan_vertex_ascii.stl", "is not a readable stl file"],
    "nrrd_nan_spacing": ["input 'scan'", "nan_spacing.nrrd", "axis 0 has spacing nan", "give positive voxel sizes"],
    "nrrd_inf_origin": ["input 'scan'", "inf_origin.nrrd", "'space origin' is not a finite 3D point"],
    "missing_output_folder": ["output.files[0]", "no_such_folder", "does not exist"],
    "cut_removes_everything": ["the cut 'cutter' removes everything", "'ball'"],
    "tiny_box": ["input 'box'", "tiny_box.brep", "units"],
}
BAD_JOBS = sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(BAD, "*.json")))


def small_ball():
    # tet10: in tet4 the coarse ball is short of its volume, which the default checks refuse.
    return {"inputs": [{"name": "ball", "sphere": {"center": [0, 0, 0], "radius": 1}, "material": 1}],
            "criteria": {"default": {"cell_size": 0.5, "facet_size": 0.5, "facet_distance": 0.05}},
            "element_order": 2}


def test_every_bad_job_has_its_expectation():
    assert set(BAD_JOBS) == set(EXPECTED)


@pytest.mark.parametrize("name", BAD_JOBS)
def test_cli_refuses_bad_input_with_exit_code_2(name):
    run = subprocess.run([CLI, os.path.join(BAD, name + ".json")], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, (run.returncode, run.stderr[-2000:])  # a signal is negative
    message = run.stderr
    assert "internal error" not in message
    for part in EXPECTED[name]:
        assert part in message, (part, message[-2000:])


@pytest.mark.parametrize("name", BAD_JOBS)
def test_run_refuses_bad_input_and_still_works_afterwards(name):
    with pytest.raises(oraclemesh.InputError) as err:
        oraclemesh.run(os.path.join(BAD, name + ".json"))
    for part in EXPECTED[name]:
        assert part in str(err.value), (part, str(err.value))
    assert len(oraclemesh.run(small_ball()).tets) > 0


def sparse_job_file(folder, size):
    """A job file of `size` bytes that takes no disk (a hole)."""
    path = os.path.join(str(folder), "job_%d.json" % size)
    with open(path, "wb") as f:
        f.truncate(size)
    return path


def test_job_file_over_the_size_limit_is_refused_before_it_is_read(tmp_path):
    limit = oraclemesh._core.max_job_bytes
    assert limit == 1 << 30  # the README's "at most 1 GiB of JSON"
    path = sparse_job_file(tmp_path, limit + 1)
    expected = ("the job file '%s' is %d bytes of JSON, more than the limit of %d bytes (1 GiB): give large "
                "surfaces as STL/OBJ/OFF files instead of 'surface' lists" % (path, limit + 1, limit))
    # The CLI: exit code 2 at once, and its peak memory shows it read none of the file.
    child = subprocess.Popen([CLI, path], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    message = child.stderr.read()
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    assert child.returncode == 2, (child.returncode, message)
    assert expected in message, message
    assert usage.ru_maxrss < 256 * 1024, usage.ru_maxrss  # kB; reading the file would take 1 GiB
    # oraclemesh.run and run_isolated, in this process and before a child is started.
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for run in (oraclemesh.run, oraclemesh.run_isolated):
        with pytest.raises(oraclemesh.InputError) as err:
            run(path)
        assert str(err.value) == expected
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 256 * 1024
    assert len(oraclemesh.run(small_ball()).tets) > 0


def test_error_classes_are_oraclemesh_errors():
    for cls in (oraclemesh.InputError, oraclemesh.LimitError, oraclemesh.Cancelled):
        assert issubclass(cls, oraclemesh.Error)
    job = small_ball()
    job["inputs"][0]["name"] = ["not", "a", "name"]  # used to be a bare RuntimeError
    with pytest.raises(oraclemesh.InputError, match=r"inputs\[0\]\.name must be a string"):
        oraclemesh.run(job)


def test_callback_exception_comes_back_as_itself():
    class Stop(Exception):
        pass

    def progress(phase, fraction):
        raise Stop("from the callback in phase " + phase)

    # Used to be reported as "meshing was cancelled".
    with pytest.raises(Stop, match="from the callback in phase load"):
        oraclemesh.run(small_ball(), progress=progress)
    assert len(oraclemesh.run(small_ball()).tets) > 0


def test_non_finite_numbers_in_arrays_name_their_place():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    points[2, 1] = math.nan
    job = {"inputs": [{"name": "tet", "surface": {"points": points,
                                                   "triangles": np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])}}]}
    with pytest.raises(oraclemesh.InputError, match=r"inputs\[0\]\.surface\.points\[2\]\[1\] is not a finite number"):
        oraclemesh.run(job)
    job = small_ball()
    job["inputs"][0]["sphere"]["center"] = np.array([0.0, math.inf, 0.0])
    with pytest.raises(oraclemesh.InputError, match=r"inputs\[0\]\.sphere\.center\[1\] is not a finite number"):
        oraclemesh.run(job)


def test_deeply_nested_dict_is_an_input_error():
    nested = []
    for _ in range(100000):
        nested = [nested]
    job = small_ball()
    job["initial_points"] = nested  # json.dumps would raise RecursionError
    with pytest.raises(oraclemesh.InputError, match="levels deep"):
        oraclemesh.run(job)


def test_callback_exception_in_run_isolated_comes_back_and_ends_the_child():
    seen = []

    def progress(phase, fraction):
        seen.append(phase)
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        oraclemesh.run_isolated(small_ball(), progress=progress)
    assert seen == ["load"]
