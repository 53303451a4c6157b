"""The batch's Arrow tables built from NumPy buffers: the same table as pyarrow's own
converter builds (the second method), and pandas never imported on the way."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

pa = pytest.importorskip("pyarrow")
np = pytest.importorskip("numpy")

from inertia.batch import output  # noqa: E402
from inertia.batch.arrow_columns import column  # noqa: E402
from inertia.batch.record import COLUMNS  # noqa: E402


def _finding(text: str) -> dict:
    """A finding as a batch row holds it (every field text)."""
    return {"code": "open_edges", "severity": "warning", "message": text, "where": "/data/a.stl",
            "values": '{"count": 3}'}


def _rows():
    """Rows with every kind of value a batch row holds: missing ones, NaN, non-ASCII text,
    empty lists, NaN inside a list, NumPy scalars."""
    import numpy as np

    full = {c: None for c in COLUMNS}
    full.update(path="/data/a.stl", status="ok", reason=None, message=None, size_bytes=1234,
                mtime_ns=1_700_000_000_123_456_789, n_vertices=8, n_faces=12, density=1000.0,
                mass=1.0, volume=0.001, elapsed_s=0.002, watertight=True, winding_consistent=False,
                findings=[], com=[0.0, 0.5, -0.25], inertia_com=[1.0] * 9,
                principal_moments=[1.0, 2.0, 3.0], R_body_principal=[0.0] * 9)
    return [
        full,
        dict(full, path="/data/ü/b.stl", status="error", reason="not_closed", message="edge (3, 4) ✗",
             mass=None, volume=float("nan"), watertight=None, n_faces=None, findings=[_finding("a"), _finding("é")],
             principal_moments=[1.0, float("nan"), 2.0], com=None),
        dict(full, n_vertices=np.int64(9), density=np.float64(7.5), watertight=np.bool_(False)),
        {"path": "only a path"},
    ]


def _plain_rows():
    """Rows as a clean run gives them: every value a plain int, float, bool, str or list of
    floats (the builders' one-conversion path), one volume NaN, one negative zero."""
    full = _rows()[0]
    full.update(reason="", message="", units="m", options="units=m", status="ok")
    rows = []
    for k in range(5):
        row = dict(full, path=f"/data/{k}.stl", size_bytes=1234 + k, mass=1.0 + k, volume=0.001 * k,
                   com=[0.1 * k, -0.0, 2.0 ** -1070], findings=[_finding("w")] * k, n_faces=12 + k)
        rows.append(row)
    rows[2]["volume"] = float("nan")
    for name in COLUMNS:
        assert all(row[name] is not None for row in rows), name
    return rows


def _by_pyarrow(rows):
    arrays = []
    for field in output.arrow_schema():
        values = [row.get(field.name) for row in rows]
        arrays.append(pa.array(values, type=field.type, from_pandas=not pa.types.is_list(field.type)))
    return pa.Table.from_arrays(arrays, schema=output.arrow_schema())


def _same(a, b) -> bool:
    """Equal values, NaN equal to NaN (Arrow's equals says NaN != NaN inside lists)."""
    def norm(v):
        if isinstance(v, float) and math.isnan(v):
            return "nan"
        if isinstance(v, list):
            return [norm(x) for x in v]
        return v
    return norm(a) == norm(b)


@pytest.mark.parametrize("plain", [False, True])
def test_the_buffer_built_table_is_the_one_pyarrow_builds(plain):
    rows = _plain_rows() if plain else _rows()
    ours = output.rows_to_table(rows)
    ours.validate(full=True)
    theirs = _by_pyarrow(rows)
    assert ours.schema == theirs.schema
    for name in COLUMNS:
        assert ours.column(name).type == theirs.column(name).type
        assert ours.column(name).null_count == theirs.column(name).null_count, name
        assert _same(ours.column(name).to_pylist(), theirs.column(name).to_pylist()), name
    if plain:
        assert ours.column("volume").to_pylist()[2] is None      # a NaN number is missing
        assert math.copysign(1.0, ours.column("com").to_pylist()[0][1]) == -1.0   # -0.0 kept
        return
    assert ours.column("volume").to_pylist()[1] is None          # a NaN number is missing
    assert math.isnan(ours.column("principal_moments").to_pylist()[1][1])   # inside a list, a value


@pytest.mark.parametrize("values, arrow_type", [
    ([1, "x"], pa.int64()), ([1.5], pa.int64()), ([True], pa.float64()), ([b"x"], pa.string()),
    ([[1.0, "a"]], pa.list_(pa.float64())), ([2**70], pa.int64()), ([2**53 + 1], pa.float64()),
    ([[np.bool_(True)]], pa.list_(pa.float64())), ([[b"1.5"]], pa.list_(pa.float64())),
    ([[2**60]], pa.list_(pa.float64())), ([[None]], pa.list_(pa.float64())),
])
def test_values_of_another_kind_take_the_general_route(values, arrow_type):
    assert column(values, arrow_type) is None


def test_a_whole_batch_run_to_parquet_does_not_import_pandas(tmp_path):
    """The run writes its parts and the final table, then reads them back for the summary,
    all without pandas (0.2 s of the parent's CPU); the table holds every file's row."""
    import numpy as np

    from tests._make import write_binary_stl

    folder = tmp_path / "meshes"
    folder.mkdir()
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    tris = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5),
            (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    for k in range(3):
        write_binary_stl(folder / f"cube{k}.stl", (cube * (k + 1))[np.array(tris)])
    out = tmp_path / "out.parquet"
    code = ("import sys\n"
            "from inertia.batch.run import run_batch\n"
            f"summary = run_batch([{str(folder)!r}], {str(out)!r}, progress=False)\n"
            "print(summary.ok, 'pandas' in sys.modules)\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.strip().splitlines()[-1] == "3 False"
    import pyarrow.parquet as pq

    table = pq.read_table(out)
    masses = dict(zip(table.column("path").to_pylist(), table.column("mass").to_pylist()))
    assert len(masses) == 3
    for path, mass in masses.items():       # the default density, 1000 kg/m^3, times (k+1)^3
        k = int(path[-5])
        assert mass == pytest.approx(1000.0 * (k + 1) ** 3, rel=1e-12)
