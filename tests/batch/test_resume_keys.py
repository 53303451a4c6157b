"""Resuming never keeps a stale row: the resume key holds every option that shapes a row.

Truth: the single-file API (inertia.mesh_file_properties) with the options of the second
run; closed forms for the unit cube (m = rho a^3).
"""

from __future__ import annotations

import os

import pytest

pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

import inertia  # noqa: E402
from inertia.batch import read_frame, run_batch  # noqa: E402
from inertia.errors import InputError  # noqa: E402


def _cube(path, a=1.0):
    v = [(0, 0, 0), (a, 0, 0), (a, a, 0), (0, a, 0), (0, 0, a), (a, 0, a), (a, a, a), (0, a, a)]
    f = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
         (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in v) + "".join(f"f {a} {b} {c}\n" for a, b, c in f))
    return path


@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "meshes"
    d.mkdir()
    for k in range(4):
        _cube(d / f"cube{k}.obj", a=10.0 * (k + 1))
    return d


def _run(folder, out, **kw):
    return run_batch([folder], out, scheduler="synchronous", progress=False, **kw)


@pytest.mark.parametrize("change", [dict(units="cm", density=7850.0), dict(density=7850.0), dict(units="cm"),
                                    dict(kind="shell"), dict(mass=2.0)])
def test_resume_with_other_options_is_refused_naming_them_and_force_recomputes(folder, tmp_path, change):
    out = tmp_path / "r.parquet"
    _run(folder, out, units="mm", density=2700.0)
    before = out.read_bytes()
    opts = {"units": "mm", "density": 2700.0, **change}
    if "mass" in change:
        opts.pop("density")
    with pytest.raises(InputError) as ei:
        _run(folder, out, resume=True, **opts)
    msg = str(ei.value)
    assert "4 of the rows" in msg and "--force" in msg and str(out) in msg
    for key, value in change.items():
        assert key in msg
    assert out.read_bytes() == before                      # nothing written on refusal
    summary = _run(folder, out, resume=True, overwrite=True, **opts)
    assert (summary.processed, summary.skipped) == (4, 0)
    table = read_frame(out)
    assert len(table) == 4
    for path, mass in zip(table["path"], table["mass"]):
        ref = inertia.mesh_file_properties(path, units=opts["units"], density=opts.get("density"),
                                           mass=opts.get("mass"), kind=opts.get("kind", "solid"),
                                           on_defect="raise")
        assert mass == ref.mass


def test_resume_with_the_same_options_skips_and_the_summary_counts_the_whole_table(folder, tmp_path):
    out = tmp_path / "r.csv"
    (folder / "broken.obj").write_text("v 0 0 0\n")
    first = _run(folder, out, units="mm", density=2700.0)
    assert (first.ok, first.errors) == (4, 1)
    _cube(folder / "cube9.obj", a=5.0)
    again = _run(folder, out, units="mm", density=2700.0, resume=True)
    assert (again.processed, again.skipped) == (1, 5)
    # truth: the table itself
    table = read_frame(out)
    assert (again.ok, again.errors) == ((table["status"] == "ok").sum(), (table["status"] == "error").sum()) == (5, 1)
    row = table[table["path"] == str(folder / "cube9.obj")].iloc[0]
    assert row["mass"] == pytest.approx(2700.0 * 0.005**3, rel=1e-12)


def test_a_table_of_an_older_version_without_options_is_not_trusted(folder, tmp_path):
    import pyarrow.parquet as pq

    out = tmp_path / "r.parquet"
    _run(folder, out, density=1000.0)
    pq.write_table(pq.read_table(out).drop(["options"]), out)   # as written before the column existed
    with pytest.raises(InputError, match="older version"):
        _run(folder, out, density=1000.0, resume=True)
    assert _run(folder, out, density=1000.0, resume=True, overwrite=True).processed == 4


@pytest.mark.skipif(not hasattr(os, "symlink"), reason="needs symlinks")
def test_every_path_found_is_a_row_even_a_looping_or_dangling_link(folder, tmp_path):
    (folder / "a.obj").symlink_to(folder / "b.obj")
    (folder / "b.obj").symlink_to(folder / "a.obj")
    (folder / "gone.stl").symlink_to(tmp_path / "nowhere.stl")
    out = tmp_path / "r.csv"
    summary = _run(folder, out, density=1000.0)
    table = read_frame(out)
    assert summary.total == len(table) == 7
    rows = {os.path.basename(p): r for p, r in zip(table["path"], table.to_dict("records"))}
    assert rows["a.obj"]["reason"] == rows["b.obj"]["reason"] == "unreadable"
    assert "symlink loop" in rows["a.obj"]["message"]
    assert rows["gone.stl"]["reason"] == "not_found"


def test_temporary_files_of_a_killed_run_are_removed_by_the_next(folder, tmp_path):
    out = tmp_path / "r.parquet"
    stale = [tmp_path / ".r.parquet.abcd1234.tmp", tmp_path / "r.parquet.parts" / ".part-000003.parquet.x1y2z3w4.tmp"]
    stale[1].parent.mkdir()
    for p in stale:
        p.write_bytes(b"half a table")
    keep = tmp_path / ".other.parquet.abcd1234.tmp"       # another file's temporary: not ours
    keep.write_bytes(b"x")
    _run(folder, out, density=1000.0, resume=True)
    assert not any(p.exists() for p in stale) and keep.exists()
    assert len(read_frame(out)) == 4


@pytest.mark.parametrize("order", ["identity", "reversed", "runs", "random", "empty", "subset"])
def test_rows_in_job_order_are_those_arrow_take_picks(order):
    # the final table is assembled from slices (no pyarrow.compute in a batch run); truth:
    # pyarrow's own Table.take on the same indices
    import numpy as np
    import pyarrow as pa

    from inertia.batch.run import _rows_at

    n = 57
    table = pa.concat_tables([pa.table({"path": [f"p{i}" for i in range(k, min(k + 10, n))],
                                        "x": [float(i) for i in range(k, min(k + 10, n))]})
                              for k in range(0, n, 10)])
    rng = np.random.default_rng(5)
    index = {"identity": list(range(n)), "reversed": list(range(n))[::-1],
             "runs": list(range(30, 57)) + list(range(0, 10)) + list(range(10, 30)),
             "random": [int(i) for i in rng.permutation(n)], "empty": [],
             "subset": [int(i) for i in rng.choice(n, 20, replace=False)]}[order]
    got = _rows_at(table, index)
    want = table.take(pa.array(index, type=pa.int64()))
    assert got.to_pydict() == want.to_pydict()
    assert got.column("path").to_pylist() == [f"p{i}" for i in index]
