"""``inertia batch SOURCES... -o results.parquet``: mass properties of many mesh files, in parallel.

SOURCES are mesh files, folders (searched recursively by extension), glob patterns (quote
them) or manifests (.csv/.parquet with a ``path`` column and optional ``density``, ``mass``,
``units``).  One row per file; a file that fails becomes a row with its named reason and
the run goes on.  Only the standard library is imported at module level.
"""

from __future__ import annotations

from . import _format as fmt

EPILOG = """\
examples:
  inertia batch meshes/ -o results.parquet                 (a thread per core in this process)
  inertia batch 'parts/**/*.stl' --units mm --density 2700 -o parts.csv
  inertia batch manifest.csv -o out.parquet --scheduler tcp://10.0.0.5:8786
  inertia batch meshes/ -o results.parquet --resume        (after Ctrl-C: finish the rest)
  inertia batch meshes/ -o results.parquet --scheduler cluster --workers 2   (a local Dask cluster)

columns: path, size_bytes, mtime_ns, status (ok|warning|error), reason, message, findings,
units, density, mass, volume, com, inertia_com (9, row-major, negated products), principal_moments
(ascending), R_body_principal (9, row-major, columns are the axes), n_vertices, n_faces,
watertight, winding_consistent, elapsed_s, options (the resume key's options).  SI units.
Without --density/--mass (and no manifest value) the density of water, 1000 kg/m^3, is used
and recorded in the density column.

Finished rows are saved atomically in OUTPUT.parts/ as the run goes (at most every 2 s;
Ctrl-C saves the rest); the output file is assembled at the end.  --resume skips files
already done (same path, size, mtime and options); a resume with other options is refused
unless --force recomputes those rows.

where it runs (the summary says): by default on a thread per core in this process (--workers N
threads); --scheduler cluster on a local Dask cluster (--workers N processes, each running
threads; a file that ends its worker process costs one 'crashed' row), tcp://HOST:PORT on a
remote one, synchronous one file after another in this process.  Every file's row is the same
wherever it runs.

exit status: 0 the run completed (file errors are rows, counted in the summary), 1 bad input or
the run could not start, 130 interrupted (resumable)."""

HELP = "mass properties of many mesh files (threads here, or a Dask cluster)"
DESCRIPTION = ("Mass properties of every mesh in folders, globs, files or manifests, in parallel (threads or Dask), "
               "one row per file, saved as it goes and resumable.")


def register(sub) -> None:
    from ._options import add_mesh_options, add_units

    p = fmt.add_command(sub, "batch", HELP, DESCRIPTION, EPILOG, usage="SOURCE... -o OUTPUT [options]")
    p.add_argument("sources", nargs="+", metavar="SOURCE", help="mesh file, folder, glob or manifest (.csv/.parquet)")
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="results table (.parquet, .csv or .jsonl)")
    p.add_argument("--format", choices=("parquet", "csv", "jsonl"), help="output format (default: from -o's extension)")
    m = p.add_mutually_exclusive_group()
    m.add_argument("--density", type=float, metavar="RHO", help="kg/m^3 (kg/m^2 with --shell) for every file")
    m.add_argument("--mass", type=float, metavar="KG", help="total mass of each body, kg")
    add_units(p)
    p.add_argument("--scheduler", metavar="ADDR",
                   help="threads (default: a thread per core in this process), cluster (a local Dask cluster), "
                        "synchronous (this process, one file at a time), or tcp://HOST:PORT of a Dask scheduler")
    p.add_argument("--dask-config", metavar="FILE", help="YAML Dask config (its scheduler-address is used)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="threads (default: one per core), or the local cluster's worker processes (default 1)")
    p.add_argument("--chunk-files", type=int, metavar="N", help="files per task (default: automatic)")
    p.add_argument("--resume", action="store_true", help="continue an earlier run into the same output")
    p.add_argument("--force", action="store_true",
                   help="overwrite an existing output and start again; with --resume, recompute the rows made "
                        "with other options")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_mesh_options(p)
    p.set_defaults(func=run)


#: Arrow's allocator for this process (unless the environment names one): its default,
#: mimalloc, stalled 20-60 ms in one write of the table in two (2,000 rows: the final write
#: took 5-31 ms, against 7-9 ms with the C library's allocator)
ARROW_MEMORY_POOL = "system"

#: OpenBLAS threads for this process (unless the environment says): the files' work uses no
#: BLAS, and OpenBLAS's own threads busy-wait for about 0.1 s after NumPy loads it, on the cores
#: the first files run on (500 small STL: 2-3.5 % of the whole run, bench/batch.py)
OPENBLAS_THREADS = "1"


def run(args) -> int:
    import os
    import sys

    from .._core.errors import InputError

    os.environ.setdefault("ARROW_DEFAULT_MEMORY_POOL", ARROW_MEMORY_POOL)   # read when pyarrow first allocates
    os.environ.setdefault("OPENBLAS_NUM_THREADS", OPENBLAS_THREADS)         # read when NumPy first loads
    from ..batch.run import run_batch

    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    if args.chunk_files is not None and args.chunk_files < 1:
        raise InputError(f"--chunk-files must be at least 1, got {args.chunk_files}")
    for name in ("density", "mass"):
        v = getattr(args, name)
        if v is not None and not (v > 0 and v != float("inf")):
            raise InputError(f"--{name} must be finite and positive, got {v}")
    scheduler = args.scheduler
    if args.dask_config:
        scheduler = scheduler or _scheduler_from_config(args.dask_config)
    summary = run_batch(args.sources, args.output, fmt=args.format, density=args.density, mass=args.mass,
                        units=args.units, kind="shell" if args.shell else "solid",
                        repair="orient" if args.fix_orientation else None,
                        on_defect="robust" if args.robust else "warn" if args.accept_defects else "raise",
                        robust_tol=args.robust_tol, self_crossing=args.self_crossing, scheduler=scheduler,
                        n_workers=args.workers, chunk_files=args.chunk_files, resume=args.resume,
                        overwrite=args.force, progress=not args.no_progress)
    sys.stderr.write("\n".join(summary.lines()) + "\n")
    return 0


def _scheduler_from_config(path):
    import dask
    import yaml

    from .._core.errors import InputError
    from .._core.files import MAX_ROBOT_FILE_BYTES, read_regular

    try:
        cfg = yaml.safe_load(read_regular(path, what="Dask configuration (--dask-config)", limit=MAX_ROBOT_FILE_BYTES,
                                          error=InputError)) or {}
    except yaml.YAMLError as exc:
        raise InputError(f"--dask-config {path}: cannot read ({exc})") from None
    dask.config.update(dask.config.config, cfg, priority="new")
    return dask.config.get("scheduler-address", None) or dask.config.get("scheduler_address", None)
