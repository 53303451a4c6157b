"""Where a batch runs: the worker count for the estimated work, the process pool's rows, and
a file that kills its worker process (a real SIGSEGV) costing one row, not the run.

Truth: the single-file API (inertia.mesh_file_properties, process_file) for every row; the
integer minimiser of ``work / n + n * start`` found by brute force for the worker count.
"""

from __future__ import annotations

import os
import signal

import numpy as np
import pytest

pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

import inertia  # noqa: E402
from inertia.batch import read_frame, run_batch  # noqa: E402
from inertia.batch.pool import ProcessPool, start_method  # noqa: E402
from inertia.batch.record import process_file, process_packed  # noqa: E402
from inertia.batch.run import formats_of, plan_workers  # noqa: E402
from inertia.batch.sources import Job  # noqa: E402

CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_F = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
          (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]


def _cube(path, scale=1.0):
    path.write_text("".join(f"v {x * scale} {y * scale} {z * scale}\n" for x, y, z in CUBE_V)
                    + "".join(f"f {a} {b} {c}\n" for a, b, c in CUBE_F))
    return path


def segfaulting_task(payload: bytes) -> bytes:
    """process_packed, except that a chunk holding a file named SEGV*.obj dies of SIGSEGV,
    as a crash in compiled code does (no exception, no cleanup)."""
    import pickle

    jobs, _ = pickle.loads(payload)
    if any(os.path.basename(job.path).startswith("SEGV") for job in jobs):
        os.kill(os.getpid(), signal.SIGSEGV)
    return process_packed(payload)


@pytest.mark.parametrize("seconds, start, cores", [(0.001, 0.02, 8), (0.05, 0.02, 8), (0.3, 0.02, 2), (3.0, 0.02, 64),
                                                   (1.5, 1.0, 8), (30.0, 1.0, 8), (0.0, 0.02, 4), (1e4, 1.0, 3)])
def test_workers_minimise_work_per_worker_plus_start_up(seconds, start, cores):
    n = plan_workers(seconds, start, cores)
    cost = [seconds / k + k * start for k in range(1, cores + 1)]
    assert 1 <= n <= cores and cost[n - 1] <= min(cost) * 1.2 + 1e-12


def test_a_small_job_gets_one_worker_and_a_large_one_every_core():
    assert plan_workers(0.01, 0.02, 8) == 1            # 10 ms of work: a second worker would not pay
    assert plan_workers(100.0, 0.02, 8) == 8
    assert plan_workers(2.0, 1.0, 8) == 1              # spawned workers (1 s each) need more work
    assert plan_workers(100.0, 1.0, 8) == 8


def test_formats_are_told_from_extensions_and_stl_headers(tmp_path):
    from tests._make import write_ascii_stl, write_binary_stl

    tri = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], float)
    jobs = [Job(str(write_binary_stl(tmp_path / "b.stl", tri))), Job(str(write_ascii_stl(tmp_path / "a.stl", tri))),
            Job(str(_cube(tmp_path / "c.obj"))), Job(str(tmp_path / "d.ply")), Job(str(tmp_path / "missing.stl"))]
    assert formats_of(jobs) == {"binary_stl", "ascii_stl", "obj", "trimesh"}
    assert formats_of(jobs[:1]) == {"binary_stl"}


def test_the_pool_gives_the_single_file_rows_and_a_segfault_costs_one_row(tmp_path):
    jobs = [Job(str(_cube(tmp_path / f"cube{k}.obj", 1 + k)), 1000.0) for k in range(6)]
    jobs.insert(4, Job(str(_cube(tmp_path / "SEGV.obj")), 1000.0))
    chunks = [jobs[:3], jobs[3:6], jobs[6:]]
    with ProcessPool(2, task=segfaulting_task) as pool:
        got = dict(pool.map(chunks, {}))
        assert all(w["proc"].is_alive() for w in pool.workers)   # the lost worker was replaced
    rows = [row for i in sorted(got) for row in got[i]]
    assert [r["path"] for r in rows] == [j.path for j in jobs]
    for job, row in zip(jobs, rows):
        if "SEGV" in job.path:
            assert row["status"] == "error" and row["reason"] == "crashed" and job.path in row["message"]
            assert "SIGSEGV" in row["message"] or start_method() != "fork"
        else:
            want = process_file(job)
            assert row["status"] == "ok" and row["mass"] == want["mass"] and row["com"] == want["com"]
            assert row["inertia_com"] == want["inertia_com"]


def test_default_run_says_where_it_ran_and_matches_the_single_file_api(tmp_path):
    folder = tmp_path / "meshes"
    folder.mkdir()
    for k in range(5):
        _cube(folder / f"cube{k}.obj", 0.5 + k)
    out = tmp_path / "out.parquet"
    summary = run_batch([folder], out, progress=False)
    assert summary.ok == 5 and "1 worker process on this machine" in summary.placement
    assert "would not pay for their start" in summary.placement   # a few ms of work: one worker
    assert any(line.startswith("ran on 1 worker process") for line in summary.lines())
    table = read_frame(out)
    for path, mass, com in zip(table["path"], table["mass"], table["com"]):
        ref = inertia.mesh_file_properties(path, density=1000.0)
        assert mass == ref.mass and np.array_equal(com, ref.com)
    forced = run_batch([folder], out, progress=False, overwrite=True, n_workers=2)
    assert "2 worker processes" in forced.placement and "as asked" in forced.placement
    assert read_frame(out).equals(table) or read_frame(out).drop(columns="elapsed_s").equals(
        table.drop(columns="elapsed_s"))
    sync = run_batch([folder], out, progress=False, overwrite=True, scheduler="synchronous")
    assert sync.placement.startswith("in this process")
