"""oraclemesh batch (oraclemesh.study): many small jobs on a local Dask cluster of 2 workers.

Failures stay cases (bad input, a real crash of the core, a hang past the deadline, a missing
file), a killed Dask worker's case is retried, reruns reuse what is done, and every case's
mesh is the one `oraclemesh JOB.json` makes alone.
"""
import csv
import json
import os
import resource
import shutil
import signal
import subprocess
import threading
import time

import pytest

import oraclemesh
from oraclemesh.study import cases as study_cases
from oraclemesh.study import local_cluster

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD = os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build"))
CLI = os.path.join(BUILD, "oraclemesh")

CUBE_OFF = """OFF
8 12 0
0 0 0
{s} 0 0
{s} {s} 0
0 {s} 0
0 0 {s}
{s} 0 {s}
{s} {s} {s}
0 {s} {s}
3 0 2 1
3 0 3 2
3 4 5 6
3 4 6 7
3 0 1 5
3 0 5 4
3 1 2 6
3 1 6 5
3 2 3 7
3 2 7 6
3 3 0 4
3 3 4 7
"""


def ball_job(name, radius=10.0, cell_size=3.0, **extra):
    job = {"inputs": [{"name": "ball", "sphere": {"center": [0, 0, 0], "radius": radius}, "material": 1}],
           "criteria": {"default": {"cell_size": cell_size, "facet_size": cell_size, "facet_distance": 0.1}},
           "element_order": 1, "output": {"files": [name + ".vtu"], "report": name + "_report.json"},
           "checks": "warn"}  # tet4 balls are short of volume; the batch is tested
    job.update(extra)
    return job


def cube_job(name, cell_size):
    return {"inputs": [{"name": "cube", "file": "cube.off", "material": 2}],
            "criteria": {"default": {"cell_size": cell_size}}, "element_order": 2,
            "output": {"files": [name + ".vtu"], "report": name + "_report.json"}}


def write_json(path, data):
    with open(path, "w") as f:
        json.dump(data, f)


def good_jobs(folder):
    """Four jobs that mesh in about a second each; two read cube.off."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "cube.off"), "w") as f:
        f.write(CUBE_OFF.format(s=20))
    write_json(os.path.join(folder, "ball_a.json"), ball_job("ball_a", 10))
    write_json(os.path.join(folder, "ball_b.json"), ball_job("ball_b", 8))
    write_json(os.path.join(folder, "cube_a.json"), cube_job("cube_a", 5))
    write_json(os.path.join(folder, "cube_b.json"), cube_job("cube_b", 4))
    return folder


@pytest.fixture(scope="module")
def client():
    from distributed import Client
    cluster = local_cluster(2)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.fixture(scope="module")
def six_cases(tmp_path_factory, client):
    """4 good jobs, one bad input, one crash of the core (the worker's forced-crash switch)."""
    folder = good_jobs(str(tmp_path_factory.mktemp("six")))
    bad = ball_job("bad")
    bad["criteria"]["default"]["cell_size"] = -1
    write_json(os.path.join(folder, "bad.json"), bad)
    write_json(os.path.join(folder, "crash.json"), {
        "base": "ball_a.json", "cases": [{"name": "crash", "environment": {"ORACLEMESH_WORKER_CRASH": "refine"}}]})
    out = os.path.join(folder, "out")
    result = oraclemesh.batch([folder], client=client, out=out, progress=False)
    return folder, out, result


def by_case(rows):
    return {r["case"]: r for r in rows}


def test_failures_stay_cases_and_the_table_says_so(six_cases):
    folder, out, result = six_cases
    rows = by_case(result.rows)
    assert sorted(rows) == sorted(["ball_a", "ball_b", "bad", "crash", "cube_a", "cube_b"])
    assert sorted(r["case"] for r in result.failed) == ["bad", "crash"]
    assert rows["bad"]["error_type"] == "InputError" and "cell_size" in rows["bad"]["error"]
    assert rows["crash"]["error_type"] == "Crash" and "signal %d" % signal.SIGSEGV in rows["crash"]["error"]
    for name in ("ball_a", "ball_b", "cube_a", "cube_b"):
        assert rows[name]["status"] == "ok" and rows[name]["tets"] > 100
        assert rows[name]["min_dihedral_deg"] > 5 and rows[name]["attempts"] == 1
    assert rows["cube_a"]["tets_material_2"] == rows["cube_a"]["tets"]
    with open(os.path.join(out, "results.csv")) as f:
        table = by_case(csv.DictReader(f))
    assert {k: v["status"] for k, v in table.items()} == {k: v["status"] for k, v in rows.items()}
    assert "signal" in table["crash"]["error"] and table["ball_b"]["tets"] == str(rows["ball_b"]["tets"])
    with open(os.path.join(out, "results.json")) as f:
        saved = json.load(f)
    assert saved["summary"]["all"]["ok"] == 4 and saved["summary"]["all"]["failed"] == 2
    tets = saved["summary"]["all"]["metrics"]["tets"]
    assert tets["min"] == min(rows[n]["tets"] for n in ("ball_a", "ball_b", "cube_a", "cube_b"))
    for png in result.plots:
        with open(png, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert sorted(os.path.basename(p) for p in result.plots) == ["min_dihedral.png", "tets.png"]


def test_results_are_those_of_the_cli_alone(six_cases, tmp_path):
    folder, out, _ = six_cases
    for name in ("ball_a", "cube_b"):
        alone = tmp_path / name
        alone.mkdir()
        shutil.copy(os.path.join(folder, name + ".json"), alone)
        shutil.copy(os.path.join(folder, "cube.off"), alone)
        subprocess.run([CLI, str(alone / (name + ".json"))], check=True, capture_output=True)
        with open(alone / (name + ".vtu"), "rb") as f, open(os.path.join(out, "cases", name, name + ".vtu"), "rb") as g:
            assert f.read() == g.read(), name
        with open(alone / (name + "_report.json")) as f:
            report = json.load(f)
        with open(os.path.join(out, "cases", name, "case.json")) as f:
            record = json.load(f)
        assert record["report"]["counts"] == report["counts"]
        assert record["report"]["quality"] == report["quality"]


def test_rerun_redoes_the_failed_cases_only(six_cases, client):
    folder, out, _ = six_cases
    again = oraclemesh.batch([folder], client=client, out=out, progress=False)
    assert again.ran == 2 and again.reused == 4
    rows = by_case(again.rows)
    assert [rows[n]["reused"] for n in ("ball_a", "bad", "crash")] == [True, False, False]
    assert sorted(r["case"] for r in again.failed) == ["bad", "crash"]


def test_rerun_meshes_nothing_and_an_edited_input_redoes_its_cases(tmp_path, client):
    folder = good_jobs(str(tmp_path / "jobs"))
    out = str(tmp_path / "out")
    first = oraclemesh.batch([folder], client=client, out=out, progress=False)
    assert first.ran == 4 and not first.failed
    vtu = {r["case"]: os.path.join(out, "cases", r["case"], r["case"] + ".vtu") for r in first.rows}
    stamps = {k: os.stat(p).st_mtime_ns for k, p in vtu.items()}

    again = oraclemesh.batch([folder], client=client, out=out, progress=False)
    assert again.ran == 0 and again.reused == 4
    assert {k: os.stat(p).st_mtime_ns for k, p in vtu.items()} == stamps

    with open(os.path.join(folder, "cube.off"), "w") as f:
        f.write(CUBE_OFF.format(s=22))
    edited = oraclemesh.batch([folder], client=client, out=out, progress=False)
    assert edited.ran == 2
    assert sorted(r["case"] for r in edited.rows if not r["reused"]) == ["cube_a", "cube_b"]
    changed = {k for k, p in vtu.items() if os.stat(p).st_mtime_ns != stamps[k]}
    assert changed == {"cube_a", "cube_b"}
    assert by_case(edited.rows)["cube_a"]["volume"] > by_case(first.rows)["cube_a"]["volume"] * 1.3


def mesh_children_of(pids):
    """{oraclemesh.worker pid: (its parent, its job file)} for children of the given pids."""
    found = {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                args = f.read().split(b"\0")
            with open("/proc/%s/stat" % pid) as f:
                parent = int(f.read().rsplit(")", 1)[1].split()[1])
        except OSError:
            continue
        if b"oraclemesh.worker" in args and parent in pids:
            found[int(pid)] = (parent, args[args.index(b"oraclemesh.worker") + 1].decode())
    return found


def test_a_killed_worker_s_case_is_retried(tmp_path, client):
    folder = tmp_path / "jobs"
    folder.mkdir()
    radii = [9.0, 9.5, 10.0, 10.5, 11.0]
    for r in radii:
        write_json(folder / ("r%g.json" % r), ball_job("r%g" % r, r, cell_size=0.8))
    worker_pids = set(client.run(os.getpid).values())
    killed = {}

    def kill_one_worker():
        deadline = time.time() + 120
        while time.time() < deadline and not killed:
            for child, (parent, job_path) in mesh_children_of(worker_pids).items():
                try:
                    with open(job_path) as f:
                        radius = json.load(f)["inputs"][0]["sphere"]["radius"]
                except (OSError, ValueError):
                    continue  # the job file is still being written
                os.kill(parent, signal.SIGKILL)
                killed.update(worker=parent, child=child, radius=radius)
                break
            time.sleep(0.02)

    killer = threading.Thread(target=kill_one_worker)
    killer.start()
    result = oraclemesh.batch([str(folder)], client=client, out=str(tmp_path / "out"), progress=False)
    killer.join()
    assert killed, "no case was seen running"
    assert not result.failed and len(result.rows) == len(radii)
    retried = [r for r in result.rows if r["attempts"] > 1]
    assert [r["case"] for r in retried] == ["r%g" % killed["radius"]]
    assert retried[0]["attempts"] == 2
    assert not os.path.exists("/proc/%d/cmdline" % killed["child"]) or \
        b"oraclemesh.worker" not in open("/proc/%d/cmdline" % killed["child"], "rb").read()


def test_hang_past_the_deadline_and_missing_input_fail_alone(tmp_path, client):
    missing = {"inputs": [{"name": "part", "file": str(tmp_path / "nowhere.step"), "material": 1}]}
    study = {"base": ball_job("ok"), "cases": [
        {"name": "ok"}, {"name": "hang", "set": {"limits": {"time_limit": 1}},
                         "environment": {"ORACLEMESH_WORKER_HANG": "refine"}}]}
    started = time.time()
    result = oraclemesh.batch([study, missing], client=client, out=str(tmp_path / "out"), grace=2,
                              progress=False)
    rows = by_case(result.rows)
    assert rows["ok"]["status"] == "ok"
    assert rows["hang"]["error_type"] == "Timeout" and "3 s" in rows["hang"]["error"]
    assert rows["job-2"]["error_type"] == "MissingInput" and "nowhere.step" in rows["job-2"]["error"]
    assert time.time() - started < 60


def test_damaged_cad_files_fail_alone_naming_the_file(tmp_path, client):
    """Issue 18: a STEP file OpenCASCADE's reader segfaults on and a BREP file its reader loops
    on, in one batch with a good job: each is an InputError naming its file within its time
    limit, and the good job meshes (the workers survive)."""
    bad = os.path.abspath(os.path.join(HERE, "..", "data", "bad", "cad"))
    damaged = ["step_reader_crash.step", "brep_reader_loop.brep"]
    jobs = [ball_job("ok")] + [{"inputs": [{"name": "part", "file": os.path.join(bad, name), "material": 1}],
                                "element_order": 1, "limits": {"time_limit": 4}} for name in damaged]
    started = time.time()
    result = oraclemesh.batch(jobs, client=client, out=str(tmp_path / "out"), grace=2, progress=False)
    rows = sorted(result.rows, key=lambda r: r["case"])
    assert [r["status"] for r in rows] == ["ok", "failed", "failed"], rows
    for row, name, what in zip(rows[1:], damaged, ["OpenCASCADE crashed reading", "OpenCASCADE did not finish reading"]):
        assert row["error_type"] == "InputError", row
        assert what in row["error"] and name in row["error"], row["error"]
    assert time.time() - started < 60


def test_shipped_inputs_give_the_same_mesh(six_cases, tmp_path, client):
    folder, out, _ = six_cases
    shipped = oraclemesh.batch([os.path.join(folder, "cube_a.json")], client=client,
                               out=str(tmp_path / "out"), ship_inputs=True, progress=False)
    assert not shipped.failed and shipped.ran == 1
    with open(tmp_path / "out" / "cases" / "cube_a" / "cube_a.vtu", "rb") as f, \
            open(os.path.join(out, "cases", "cube_a", "cube_a.vtu"), "rb") as g:
        assert f.read() == g.read()


def test_study_grid_names_parameters_and_paths(tmp_path):
    with open(tmp_path / "cube.off", "w") as f:
        f.write(CUBE_OFF.format(s=20))
    write_json(tmp_path / "base.json", cube_job("mesh", 5))
    write_json(tmp_path / "study.json", {
        "base": "base.json", "name": "s{size}-{order}", "group_by": "order",
        "set": {"output": None},
        "parameters": {"size": {"path": "criteria.default.cell_size", "values": [4, 6]},
                       "order": [{"value": "linear", "set": {"element_order": 1}, "columns": {"nodes": 4}},
                                 {"value": "quadratic", "set": {"element_order": 2, "inputs.0.file": "cube.off"}}]}})
    found, options = study_cases.collect([str(tmp_path / "study.json")])
    assert [c.name for c in found] == ["s4-linear", "s4-quadratic", "s6-linear", "s6-quadratic"]
    assert options == {"group_by": "order"}
    c = found[2]
    assert c.parameters == {"size": 6, "order": "linear"} and c.columns == {"nodes": 4}
    assert c.job["criteria"]["default"]["cell_size"] == 6 and c.job["element_order"] == 1
    assert "output" not in c.job
    assert all(x.job["inputs"][0]["file"] == str(tmp_path / "cube.off") for x in found)
    assert len({x.hash for x in found}) == 4
    # The hash follows the bytes, not the place: the same study moved elsewhere keeps it.
    moved = tmp_path / "moved"
    shutil.copytree(tmp_path, moved, ignore=shutil.ignore_patterns("moved"))
    assert [x.hash for x in study_cases.collect([str(moved / "study.json")])[0]] == [x.hash for x in found]


def test_job_and_base_files_over_the_size_limit_are_refused_unread(tmp_path):
    """Issue 18's JSON size limit holds for batch jobs, studies' base jobs and folders of jobs
    too: a sparse file one byte over it is refused by its size (reading it would take 1 GiB)."""
    huge = str(tmp_path / "huge.json")
    with open(huge, "wb") as f:
        f.truncate(oraclemesh._core.max_job_bytes + 1)
    write_json(tmp_path / "study.json", {"base": "huge.json", "cases": [{"name": "a"}]})
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for jobs in ([huge], [str(tmp_path / "study.json")], [str(tmp_path)]):
        with pytest.raises(oraclemesh.InputError, match="the job file '%s' is 1073741825 bytes of JSON, more than "
                                                        "the limit of 1073741824 bytes" % huge):
            study_cases.collect(jobs)
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 256 * 1024


def test_cli_batch_command(tmp_path):
    folder = tmp_path / "jobs"
    folder.mkdir()
    write_json(folder / "ball_a.json", ball_job("ball_a", 10))
    bad = ball_job("bad")
    bad["criteria"]["default"]["cell_size"] = -1
    write_json(folder / "bad.json", bad)
    out = tmp_path / "out"
    run = subprocess.run([CLI, "batch", str(folder), "--out", str(out), "--workers", "1"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 1, run.stderr  # finished, with a failed case
    assert "failed: bad: InputError" in run.stdout
    assert "2/2 done, 1 failed" in run.stderr
    with open(out / "results.csv") as f:
        assert {r["case"]: r["status"] for r in csv.DictReader(f)} == {"ball_a": "ok", "bad": "failed"}
    usage = subprocess.run([CLI, "--help"], capture_output=True, text=True)
    assert "oraclemesh batch JOBS" in usage.stderr and "-m oraclemesh.study" in usage.stderr
