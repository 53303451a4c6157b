"""Where a batch runs: threads in this process by default, the same table on 1 or N threads,
synchronously, or on a Dask cluster of worker processes running threads.

Truth: the single-file API (inertia.mesh_file_properties) for every row; the table of one
placement for the others (every column but the timing one, bit for bit).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

import inertia  # noqa: E402
from inertia.batch import read_frame, run_batch  # noqa: E402

CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_F = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
          (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]


def _cube(path, scale=1.0):
    path.write_text("".join(f"v {x * scale} {y * scale} {z * scale}\n" for x, y, z in CUBE_V)
                    + "".join(f"f {a} {b} {c}\n" for a, b, c in CUBE_F))
    return path


def _meshes(folder, n=24):
    """Cubes, icospheres and tori of different sizes and a broken file: a mixed folder."""
    import trimesh

    folder.mkdir()
    rng = np.random.default_rng(5)
    for k in range(n):
        kind = k % 3
        if kind == 0:
            _cube(folder / f"cube{k}.obj", 0.5 + k)
        elif kind == 1:
            m = trimesh.creation.icosphere(subdivisions=1 + k % 4, radius=0.1 + k)
            m.vertices += rng.normal(scale=1e-3, size=m.vertices.shape)
            m.export(folder / f"sphere{k}.stl")
        else:
            trimesh.creation.torus(1 + k, 0.3, major_sections=16 + k, minor_sections=12).export(folder / f"torus{k}.stl")
    (folder / "broken.obj").write_text("v 0 0 0\nf 1 2 3\n")
    return folder


def test_default_run_is_threads_here_and_matches_the_single_file_api(tmp_path):
    folder = tmp_path / "meshes"
    folder.mkdir()
    for k in range(5):
        _cube(folder / f"cube{k}.obj", 0.5 + k)
    out = tmp_path / "out.parquet"
    summary = run_batch([folder], out, progress=False, n_workers=2)
    assert summary.ok == 5 and summary.placement == "on 2 threads in this process"
    assert "ran on 2 threads in this process" in summary.lines()
    table = read_frame(out)
    for path, mass, com, inertia_com in zip(table["path"], table["mass"], table["com"], table["inertia_com"]):
        ref = inertia.mesh_file_properties(path, density=1000.0)
        assert mass == ref.mass and np.array_equal(com, ref.com)
        assert np.array_equal(np.reshape(inertia_com, (3, 3)), ref.inertia_com)
    sync = run_batch([folder], out, progress=False, overwrite=True, scheduler="synchronous")
    assert sync.placement.startswith("in this process")


def test_one_or_many_threads_and_synchronous_write_the_same_table(tmp_path):
    folder = _meshes(tmp_path / "meshes")
    tables = []
    for k, kw in enumerate([dict(scheduler="synchronous"), dict(n_workers=1), dict(n_workers=2),
                            dict(n_workers=7, chunk_files=1)]):
        out = tmp_path / f"out{k}.parquet"
        run_batch([folder], out, progress=False, **kw)
        tables.append(read_frame(out).drop(columns="elapsed_s"))
    assert (tables[0]["status"] == "error").sum() == 1
    for t in tables[1:]:
        assert t.equals(tables[0])


@pytest.mark.slow
def test_a_local_cluster_of_one_or_two_processes_writes_the_same_table(tmp_path):
    pytest.importorskip("distributed")
    folder = _meshes(tmp_path / "meshes", n=9)
    ref = tmp_path / "ref.parquet"
    run_batch([folder], ref, progress=False, scheduler="synchronous")
    want = read_frame(ref).drop(columns="elapsed_s")
    for n in (1, 2):
        out = tmp_path / f"cluster{n}.parquet"
        summary = run_batch([folder], out, progress=False, scheduler="cluster", n_workers=n)
        assert summary.placement.startswith(f"on a local Dask cluster of {n} worker process")
        assert read_frame(out).drop(columns="elapsed_s").equals(want)
