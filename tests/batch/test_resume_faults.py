"""Resuming from outputs that are damaged or foreign, and two runs on one output.

Truth: the table of an uninterrupted run of the same files (every column but the timing);
a refusal names the output and what to do, never an internal error.
"""

from __future__ import annotations

import subprocess
import sys
import time

import numpy as np
import pytest

pd = pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

from inertia.batch import read_frame, run_batch  # noqa: E402
from inertia.errors import InputError  # noqa: E402
from tests._make import write_binary_stl  # noqa: E402


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    trimesh = pytest.importorskip("trimesh")
    d = tmp_path_factory.mktemp("meshes")
    for k in range(12):
        m = trimesh.creation.icosphere(subdivisions=1 + k % 3, radius=1 + k)
        write_binary_stl(d / f"s{k:02d}.stl", m.vertices[m.faces])
    return d


def _strip(frame):
    return frame.drop(columns="elapsed_s").sort_values("path").reset_index(drop=True)


@pytest.fixture(scope="module")
def full(folder, tmp_path_factory):
    out = tmp_path_factory.mktemp("full") / "full.parquet"
    run_batch([folder], out, progress=False, scheduler="synchronous")
    return _strip(read_frame(out))


def test_a_json_lines_output_cut_mid_line_resumes_its_whole_rows(folder, full, tmp_path, capsys):
    out = tmp_path / "out.jsonl"
    run_batch([folder], out, progress=False, scheduler="synchronous")
    data = out.read_bytes()
    lines = data.splitlines(keepends=True)
    out.write_bytes(b"".join(lines[:7]) + lines[7][: len(lines[7]) // 2])   # 7 whole rows, then a cut
    summary = run_batch([folder], out, progress=False, scheduler="synchronous", resume=True)
    assert summary.skipped == 7 and summary.processed == 5
    assert "1 line cut short or unreadable" in capsys.readouterr().err
    got = _strip(read_frame(out))
    pd.testing.assert_frame_equal(got.drop(columns=["mtime_ns"]), full.drop(columns=["mtime_ns"]), check_dtype=False)


@pytest.mark.parametrize("ext, content", [("jsonl", b'{"a": 1}\n{"b": 2}\n'), ("csv", b"x,y\n1,2\n3,4\n"),
                                          ("parquet", None)])
def test_resume_on_a_file_that_is_not_a_batch_table_is_refused_by_name(folder, tmp_path, ext, content):
    out = tmp_path / f"other.{ext}"
    if content is None:
        pd.DataFrame({"x": [1.0, 2.0], "y": ["a", "b"]}).to_parquet(out)
    else:
        out.write_bytes(content)
    before = out.read_bytes()
    with pytest.raises(InputError, match="is not a table of inertia batch") as info:
        run_batch([folder], out, progress=False, scheduler="synchronous", resume=True)
    assert str(out) in str(info.value) and "--force" in str(info.value)
    assert out.read_bytes() == before          # the input is never modified unless asked


def test_resume_on_a_truncated_parquet_file_is_refused_and_force_starts_again(folder, full, tmp_path):
    out = tmp_path / "out.parquet"
    run_batch([folder], out, progress=False, scheduler="synchronous")
    out.write_bytes(out.read_bytes()[:-100])
    with pytest.raises(InputError, match="cannot be read as a parquet table to resume") as info:
        run_batch([folder], out, progress=False, scheduler="synchronous", resume=True)
    assert info.value.code == "invalid_input" and str(out) in str(info.value)
    run_batch([folder], out, progress=False, scheduler="synchronous", overwrite=True)
    pd.testing.assert_frame_equal(_strip(read_frame(out)), full, check_dtype=False)


def test_a_second_run_on_the_same_output_is_refused_while_the_first_runs(folder, tmp_path):
    out = tmp_path / "same.jsonl"
    many = tmp_path / "many"
    many.mkdir()
    data = sorted(folder.iterdir())
    for k in range(400):
        (many / f"m{k:03d}.stl").write_bytes(data[k % len(data)].read_bytes())
    cmd = [sys.executable, "-m", "inertia.cli.main", "batch", str(many), "-o", str(out), "--force", "--no-progress",
           "--scheduler", "synchronous"]
    first = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lock = tmp_path / "same.jsonl.lock"
    deadline = time.monotonic() + 60
    while not lock.exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    second = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    out_first, err_first = first.communicate(timeout=300)
    assert first.returncode == 0, err_first
    assert second.returncode == 1, second.stderr
    assert "another inertia batch run is writing this output" in second.stderr and "internal" not in second.stderr
    table = read_frame(out)
    assert len(table) == 400 and set(table["status"]) == {"ok"}
    assert not lock.exists()
    volumes = dict(zip(table["path"], table["volume"]))
    assert np.isclose(volumes[str(many / "m000.stl")], volumes[str(many / "m012.stl")])
