"""Run a batch on Dask: chunked tasks, part files as chunks complete, resume, Ctrl-C safety.

Execution
---------
* ``scheduler=None``, ``"auto"`` or ``"threads"`` (default): a pool of threads in this process,
  one per core (or ``n_workers``).  The compiled kernels release the GIL, so files run side by
  side; every file's row is the same whatever the thread count.
* ``scheduler="cluster"`` (or ``"local"``): an embedded ``distributed.LocalCluster`` on the
  loopback, one worker process (or ``n_workers``) running threads: the same code path as a
  remote cluster, with Dask's dashboard and memory limits, and a file that ends its worker
  process costs that file one ``crashed`` row.
* ``scheduler="tcp://HOST:PORT"``: an existing ``distributed`` scheduler.  Every worker
  needs ``inertia`` installed and must see the files under the same paths.
* ``scheduler="synchronous"``: in this process, one file after another (debugging, tests).

The summary says where the run went (:attr:`BatchSummary.placement`).

Files are grouped into chunks (:func:`make_chunks`) so that scheduler overhead stays small
next to the work on tiny meshes, while a large file forms a chunk of its own.  Each file is
read exactly once, on the worker that processes it.

Nothing is lost
---------------
The rows of finished chunks are written to part files, ``OUTPUT.parts/part-NNNNNN.parquet``,
atomically: the rows gathered since the start or the last part, at most every
:data:`PART_S` seconds (a part per chunk would cost a fast run more than its output; a run
shorter than that writes no part, only its output).  A
Ctrl-C writes the rows not yet in a part before the run stops, so an interrupted run loses
nothing; a killed process (``kill -9``, a lost machine) loses at most the last
:data:`PART_S` seconds of work.  The final table is assembled from the parts and the rows
since at the end, written atomically, and then the parts are removed.  After an
interruption the parts on disk are whole, and ``resume=True`` skips every file already
done, keyed by path, size and modification time.  A file that changed since is done again.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import sys
import threading
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from .._core.atomic import output_folder, remove_stale_temps
from .._core.errors import InputError
from .._core.optional import require
from .._core.progress import Progress
from .output import (
    format_of,
    read_table,
    rows_to_table,
    table_to_frame,
    write_frame,
    write_rows_parquet,
    write_table_parquet,
)
from .record import crashed_row, keep_freed_memory, options_key, process_chunk, process_file, process_packed
from .sources import Job, collect_jobs

PART_PREFIX = "part-"

#: finished rows go to a part file at most this often (the first at this long after the start):
#: the work a killed run can lose, against the cost of writing a part per chunk (the first part
#: of a 500-file run, written at once, took 7 % of its time: pyarrow's import, under the GIL)
PART_S = 2.0

#: a chunk closes when it reaches this much work, in bytes of input (a large mesh is a chunk alone)
CHUNK_BYTES = 128 * 2**20

#: the fixed cost of one file (open, parse, checks, row), counted as this many bytes of input
#: when chunks are sized (bench/batch.py measures it)
FILE_COST_BYTES = 128 * 2**10

#: guided chunk sizes: each chunk takes 1/(GUIDED_SHARE * workers) of the work left, so the
#: first chunks are large (few tasks, little overhead) and they shrink towards the end
GUIDED_SHARE = 2

#: ...down to 1/(TAIL_CHUNKS_PER_WORKER * workers) of the whole: the last chunks are small,
#: so the workers finish close together
TAIL_CHUNKS_PER_WORKER = 32

#: most files in one default chunk (progress and part files keep moving on huge runs)
MAX_CHUNK_FILES = 256

#: a cluster run in which no task ends for this long asks the scheduler about the tasks it
#: waits for: one the scheduler no longer holds is lost, not waited for (see _Executor.map)
STALL_S = 30.0


@dataclass
class BatchSummary:
    """What a run did. ``errors_by_reason`` maps each error code to its count."""

    total: int = 0
    skipped: int = 0
    processed: int = 0
    ok: int = 0
    warnings: int = 0
    errors: int = 0
    errors_by_reason: dict = field(default_factory=dict)
    elapsed_s: float = 0.0
    output: str = ""
    placement: str = ""

    @property
    def files_per_second(self) -> float:
        return self.processed / self.elapsed_s if self.elapsed_s > 0 else float("nan")

    def lines(self) -> list[str]:
        out = [f"{self.processed} files processed in {self.elapsed_s:.1f} s ({self.files_per_second:.1f} files/s)"
               + (f", {self.skipped} already done (resumed)" if self.skipped else ""),
               f"ok {self.ok}, warnings {self.warnings}, errors {self.errors}"]
        for reason, n in sorted(self.errors_by_reason.items(), key=lambda kv: (-kv[1], kv[0])):
            out.append(f"  {reason}: {n}")
        if self.placement:
            out.append(f"ran {self.placement}")
        if self.output:
            out.append(f"results: {self.output}")
        return out



@contextlib.contextmanager
def _interrupts_held():
    """SIGINT ignored inside (main thread only: elsewhere signals cannot be set), restored after."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)

def job_costs(jobs) -> list[int]:
    """The estimated work of each job, in bytes: its size plus :data:`FILE_COST_BYTES`."""
    costs = []
    for job in jobs:
        size = job.size
        if size is None:
            try:
                size = os.path.getsize(job.path)
            except OSError:
                size = 0
        costs.append(size + FILE_COST_BYTES)
    return costs


def make_chunks(jobs, n_workers: int, chunk_files: int | None = None) -> list[list[Job]]:
    """Group jobs into chunks, largest first; every job is in exactly one chunk.

    The work of a file is estimated as its size plus :data:`FILE_COST_BYTES`.  By default
    chunk sizes are guided: each chunk takes ``1 / (GUIDED_SHARE * n_workers)`` of the work
    still left, but at least ``1 / (TAIL_CHUNKS_PER_WORKER * n_workers)`` of the whole, and
    at most :data:`MAX_CHUNK_FILES` files and :data:`CHUNK_BYTES` (a larger file is a chunk
    alone).  Few large chunks keep Dask's per-task cost small; the small ones at the end
    keep the workers busy until all finish together.  ``chunk_files`` fixes the number of
    files per chunk instead (the byte cap still applies).  Chunks keep the jobs' order
    inside; they are returned largest first, so big files start early and small chunks
    fill the gaps at the end.
    """
    jobs = list(jobs)
    costs = job_costs(jobs)
    workers = max(1, n_workers)
    left = sum(costs)
    floor = left / (TAIL_CHUNKS_PER_WORKER * workers)
    max_files = MAX_CHUNK_FILES if chunk_files is None else chunk_files

    def target() -> float:
        if chunk_files is not None:
            return CHUNK_BYTES
        return min(CHUNK_BYTES, max(floor, left / (GUIDED_SHARE * workers)))

    chunks, current, work = [], [], 0
    goal = target()
    for job, cost in zip(jobs, costs):
        if current and (len(current) >= max_files or work + cost > goal):
            chunks.append((work, current))
            left -= work
            current, work, goal = [], 0, target()
        current.append(job)
        work += cost
    if current:
        chunks.append((work, current))
    chunks.sort(key=lambda wc: -wc[0])  # stable: equal sizes keep the jobs' order
    return [c for _, c in chunks]


def _job_key(job: Job) -> tuple:
    try:
        st = os.stat(job.path)
        return (job.path, int(st.st_size), int(st.st_mtime_ns))
    except OSError:
        return (job.path, None, None)


def _part_files(parts_dir: Path) -> list[Path]:
    return sorted(parts_dir.glob(f"{PART_PREFIX}*.parquet")) if parts_dir.is_dir() else []


def _previous_tables(output: Path, fmt: str, parts_dir: Path) -> list:
    """Arrow tables of an earlier run: the final table (if any), then the parts (newer)."""
    tables = [_previous_output(output, fmt)] if output.exists() else []
    tables += [read_table(part, "parquet") for part in _part_files(parts_dir)]
    return tables


def _previous_output(output: Path, fmt: str):
    """The table in ``output`` to resume from.  A JSON Lines file cut short keeps its whole
    lines (the cut row is done again); a file that is not a batch table, or a Parquet or CSV
    file that cannot be read, is refused by name (``--force`` starts again)."""
    again = "move it away, or add --force (force=True) to start again"
    if fmt == "jsonl":
        rows, cut = [], 0
        with open(output, "rb") as fh:
            for line in fh:
                try:
                    row = json.loads(line)
                except ValueError:
                    cut += 1
                    continue
                if isinstance(row, dict):
                    rows.append(row)
        if cut:
            sys.stderr.write(f"inertia batch: {output}: {cut} line{'s' if cut > 1 else ''} cut short or unreadable; "
                             "those files are done again\n")
        if rows and not all(_BATCH_KEYS <= row.keys() for row in rows):
            raise InputError(f"{output}: is not a table of inertia batch (rows without {sorted(_BATCH_KEYS)}); {again}")
        return rows_to_table(rows)
    if fmt == "csv":
        with open(output, encoding="utf-8", errors="replace") as fh:
            header = set(fh.readline().strip().split(","))
        if not _BATCH_KEYS <= header:
            raise InputError(f"{output}: is not a table of inertia batch (no {sorted(_BATCH_KEYS)} columns); {again}")
    try:
        table = read_table(output, fmt)
    except InputError:
        raise
    except Exception as exc:  # noqa: BLE001 - whatever the reader's complaint, the file cannot be resumed
        raise InputError(f"{output}: cannot be read as a {fmt} table to resume ({type(exc).__name__}: {exc}); "
                         f"{again}") from None
    if len(table) and any(table.column(c).null_count == len(table) for c in _BATCH_KEYS):
        raise InputError(f"{output}: is not a table of inertia batch (no {sorted(_BATCH_KEYS)} columns); {again}")
    return table


#: the columns without which a row cannot be resumed
_BATCH_KEYS = frozenset({"path", "size_bytes", "mtime_ns", "status"})


class _OutputLock:
    """One run at a time per output: an exclusive lock on ``OUTPUT.lock`` (released by the
    system when the process ends, however it ends)."""

    def __init__(self, output: Path):
        self.path = output.with_name(output.name + ".lock")

    def __enter__(self):
        import fcntl

        try:
            self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise InputError(f"{self.path}: cannot write the output's lock there ({exc.strerror or exc})",
                             code="unwritable") from None
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = os.pread(self.fd, 32, 0).decode(errors="replace").strip()
            os.close(self.fd)
            raise InputError(f"{self.path.with_suffix('')}: another inertia batch run is writing this output"
                             + (f" (process {holder})" if holder else "") + "; wait for it to end, or choose "
                             "another output", code="output_busy") from None
        os.ftruncate(self.fd, 0)
        os.pwrite(self.fd, str(os.getpid()).encode(), 0)
        return self

    def __exit__(self, *exc):
        try:
            os.unlink(self.path)
        except OSError:
            pass
        os.close(self.fd)
        return False


def local_cluster(n_workers: int, threads: int):
    """The embedded cluster: ``n_workers`` worker processes of ``threads`` threads each, on the
    loopback.  The workers' sampling profiler is off (it interrupts the compute threads every
    10 ms); no dashboard, but the scheduler's HTTP server (health routes) still starts, so it
    gets a free loopback port (with None it takes 8787, clashing with any other cluster).
    Logs below ERROR are hidden ("worker still alive, killing" at shutdown)."""
    import logging

    import dask
    from distributed import LocalCluster

    # allowed-failures 1: a task that kills its worker twice is given up (then isolated, see
    # _Executor.map) instead of killing four workers in turn
    with dask.config.set({"distributed.worker.profile.enabled": False,
                          "distributed.scheduler.allowed-failures": 1}):
        return LocalCluster(n_workers=n_workers, threads_per_worker=threads, processes=True, host="127.0.0.1",
                            dashboard_address="127.0.0.1:0", scheduler_kwargs={"dashboard": False},
                            silence_logs=logging.ERROR)


def cpu_count() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1


def _chunk_rows(jobs, options: dict, stop: threading.Event):
    """:func:`process_chunk` on a thread of the pool; None once ``stop`` is set (an interrupted
    run: the files not done are done again on resume)."""
    rows = []
    for job in jobs:
        if stop.is_set():
            return None
        rows.append(process_file(job, **options))
    return rows


class _Executor:
    """Maps :func:`process_chunk` over chunks where the run goes; yields results as they finish."""

    def __init__(self, scheduler, n_workers: int | None, jobs=()):
        self.scheduler = "auto" if scheduler is None else scheduler
        self.requested = n_workers
        self.n_workers = n_workers or cpu_count()
        self.jobs = jobs
        self.client = self.cluster = self.threads = None
        self.placement = ""

    def __enter__(self):
        if self.scheduler == "synchronous":
            self.n_workers = 1
            self.placement = "in this process, one file after another (synchronous)"
            return self
        if self.scheduler in ("auto", "threads"):
            keep_freed_memory()
            self.threads = ThreadPoolExecutor(self.n_workers, thread_name_prefix="inertia-batch")
            self._stop = threading.Event()
            self.placement = f"on {self.n_workers} thread{'s' if self.n_workers > 1 else ''} in this process"
            return self
        Client = require("distributed", "a batch run on a Dask cluster (or use scheduler='threads')").Client
        if self.scheduler in ("cluster", "local"):
            import dask

            processes = self.requested or 1
            threads = max(1, cpu_count() // processes)
            self.cluster = local_cluster(processes, threads)
            self.client = Client(self.cluster)
            self.n_workers = processes * threads
            # Our nannies restart a worker that a file kills, but SpecCluster closes for good the
            # nanny of a worker still missing lost-worker-timeout (15 s) after each removal: files
            # that kill their workers in turn meet that check between a death and the restart,
            # until no worker is left and the tasks wait forever.  It is read at each removal, so
            # it is set for the run (a day: a worker lost for that long is gone).
            self._config = dask.config.set({"distributed.deploy.lost-worker-timeout": "1 day"})
            self.placement = (f"on a local Dask cluster of {processes} worker process{'es' if processes > 1 else ''}"
                              f" of {threads} thread{'s' if threads > 1 else ''}")
        elif isinstance(self.scheduler, str) and "://" in self.scheduler:
            try:
                self.client = Client(self.scheduler, timeout="20s")
            except OSError as exc:
                raise InputError(f"cannot reach the Dask scheduler at {self.scheduler}: {exc}") from None
            self.placement = f"on the Dask scheduler at {self.scheduler}"
        elif hasattr(self.scheduler, "submit"):  # an existing distributed.Client
            self.client = self.scheduler
            self.placement = "on the Dask client given"
        else:
            raise InputError(f"unknown scheduler {self.scheduler!r}: use 'threads' (the default: a thread per "
                             "core in this process), 'cluster' (a local Dask cluster), 'synchronous' or a "
                             "'tcp://HOST:PORT' address")
        return self

    def worker_count(self) -> int:
        """Workers in use (``n_workers`` for our pool or cluster, or the synchronous run)."""
        if self.client is None or self.cluster is not None:
            return self.n_workers
        try:
            workers = self.client.scheduler_info().get("workers", {})
            return max(1, sum(int(w.get("nthreads", 1)) for w in workers.values()))
        except Exception:  # noqa: BLE001 - an estimate is enough
            return self.n_workers

    def map(self, chunks, options, task=None):
        """Yield ``(i, rows of chunks[i])`` as chunks finish.

        On a cluster, a chunk whose task fails (a worker process lost, e.g. killed by a
        crash in a compiled library) is split and its files are retried one per task; a file
        whose task is lost again gets one more try, alone on the cluster (Dask also counts
        the tasks queued on a dying worker), and if that fails too it costs one error row
        (``reason="crashed"``, naming the file), never the run.  No wait is unbounded: after
        :data:`STALL_S` in which no task ends, a task the scheduler no longer holds counts as
        lost (:meth:`_stalled`).  ``task`` replaces :func:`process_packed` (tests).
        """
        if self.threads is not None:
            index = {self.threads.submit(_chunk_rows, chunk, options, self._stop): i for i, chunk in enumerate(chunks)}
            for fut in as_completed(index):
                yield index[fut], fut.result()
            return
        if self.client is None:
            for i, chunk in enumerate(chunks):
                yield i, process_chunk(chunk, options)
            return
        import pickle
        import queue
        import uuid

        task = task or process_packed
        # Dask's callback thread puts each future here as it ends (finished, erred or
        # cancelled); it is read with a timeout.  Not distributed.as_completed: with_results
        # fetches each result in a coroutine of its own, and when the fetch fails (the result
        # lost with its worker, then the recomputation lost with another: KilledWorker) that
        # coroutine dies, the future is never yielded and the loop waits forever.
        ended = queue.Queue()
        live = self._live = {}  # key -> (future, chunk index, sub-index or None, jobs, try)
        alone = []              # (jobs, i, sub) of files whose one-file task was lost once

        def submit(jobs, i, sub, attempt=0):
            # a fresh key for every try: a retry never meets an earlier try's task
            key = f"inertia-chunk-{i}-{'all' if sub is None else sub}-{attempt}-{uuid.uuid4().hex[:16]}"
            fut = self.client.submit(task, pickle.dumps((jobs, options), protocol=pickle.HIGHEST_PROTOCOL),
                                     pure=False, key=key)
            live[key] = (fut, i, sub, jobs, attempt)
            fut.add_done_callback(ended.put)

        for i, chunk in enumerate(chunks):
            submit(chunk, i, None)
        split_rows: dict[int, dict] = {}
        while live or alone:
            if not live:
                # a file lost once is tried again alone on the cluster: a worker lost now is
                # lost to this file, not to another task queued beside it
                submit(*alone.pop(0), attempt=1)
            try:
                settled = [(ended.get(timeout=STALL_S), None)]
            except queue.Empty:
                settled = [(live[key][0], error) for key, error in self._stalled(live).items()]
            for fut, error in settled:
                if fut.key not in live:
                    continue  # settled already (given up as stalled, then released)
                _, i, sub, jobs, attempt = live.pop(fut.key)
                rows, error = self._outcome(fut) if error is None else (None, error)
                # released now: a result left on a worker would be computed again each time a
                # worker dies, and a task given up is forgotten rather than run on by Dask
                fut.release()
                if rows is None:
                    if sub is None and len(jobs) > 1:  # isolate: one file per task
                        split_rows[i] = {}
                        for k, job in enumerate(jobs):
                            submit([job], i, k)
                        continue
                    if attempt == 0:
                        alone.append((jobs, i, sub))
                        continue
                    rows = [crashed_row(jobs[0], error, options)]
                whole = reassemble(split_rows, chunks, i, sub, rows)
                if whole is not None:
                    yield i, whole

    @staticmethod
    def _outcome(fut):
        """``(rows, None)`` of a task that ended, or ``(None, error)`` if it was lost: erred (a
        worker died running it), cancelled (a scheduler lost), or its result lost with its
        worker and not computed again within :data:`STALL_S`."""
        import pickle
        from asyncio import CancelledError

        try:
            return pickle.loads(fut.result(timeout=STALL_S)), None
        except (Exception, CancelledError) as exc:  # noqa: BLE001 - whatever the cause, the task is lost
            return None, exc

    def _stalled(self, live: dict) -> dict:
        """After :data:`STALL_S` in which no task ended: ``{key: error}`` of the tasks of ``live``
        given up (``error`` None for one that ended but whose notice never came).  A task the
        scheduler no longer holds (its report lost on the way, or the task lost by the
        scheduler, e.g. on a worker it removed) is given up; one it queues or runs on a worker
        it knows is waited for (a large file can take long), and so is every task when the
        scheduler cannot be asked (the client cancels them all if it loses the scheduler)."""

        def states(keys, dask_scheduler=None):  # runs on the scheduler (nested: sent by value)
            tasks, workers, out = dask_scheduler.tasks, dask_scheduler.workers, {}
            for key in keys:
                ts = tasks.get(key)
                state = "forgotten" if ts is None else ts.state
                if state == "processing" and getattr(ts.processing_on, "address", None) not in workers:
                    state = "processing on a removed worker"
                out[key] = state
            return out

        lost = {key: None for key, (fut, *_) in live.items() if fut.done()}
        try:
            held = self.client.run_on_scheduler(states, keys=[key for key in live if key not in lost])
        except Exception:  # noqa: BLE001 - no answer: keep waiting
            held = {}
        for key, state in held.items():
            if state not in ("processing", "queued", "waiting", "no-worker"):
                lost[key] = TimeoutError(f"no task end reported for {STALL_S:g} s; the scheduler has it {state}")
        return lost

    def __exit__(self, *exc):
        if self.threads is not None:   # the files under way finish; the rest are not started
            self._stop.set()
            self.threads.shutdown(wait=True, cancel_futures=True)
        live = getattr(self, "_live", None)
        if live and self.client is not None:
            try:
                self.client.cancel([fut for fut, *_ in live.values()])
            except Exception:  # noqa: BLE001 - shutting down anyway
                pass
        if self.cluster is not None:  # we own client and cluster
            try:
                self.client.close()
                self.cluster.close()
            except AssertionError:  # a nanny restarting its worker as it is closed (a Dask race): the run is done
                pass
            finally:
                self._config.__exit__(None, None, None)
        return False


def reassemble(split: dict, chunks, i: int, sub, rows):
    """The rows of chunk ``i`` once whole: ``rows`` themselves for a chunk run whole (``sub``
    None), else None until every file of the split chunk has its row in ``split[i]``."""
    if sub is None:
        return rows
    split[i][sub] = rows[0]
    if len(split[i]) < len(chunks[i]):
        return None
    done = split.pop(i)
    return [done[k] for k in range(len(chunks[i]))]


def execute(jobs, *, options: dict, scheduler=None, n_workers: int | None = None, chunk_files=None,
            on_rows=None, progress: Progress | None = None, keep_rows: bool = True, on_start=None) -> list[dict]:
    """Process ``jobs`` and return their rows in job order (``on_rows(i, rows)`` per finished chunk).

    ``keep_rows=False``: hand each chunk's rows to ``on_rows`` only and return ``[]`` (a run
    of millions of files then holds no Python row after its part is written).
    ``on_start(placement)``: told where the run goes (see :attr:`BatchSummary.placement`).
    """
    jobs = list(jobs)
    if not jobs:  # nothing to do: do not start a cluster
        return []
    results: dict[int, list] = {}
    with _Executor(scheduler, n_workers, jobs) as ex:
        if on_start is not None:
            on_start(ex.placement)
        chunks = make_chunks(jobs, ex.worker_count(), chunk_files)
        for i, rows in ex.map(chunks, options):
            if keep_rows:
                results[i] = rows
            if on_rows is not None:
                on_rows(i, rows)
            if progress is not None:
                progress.update(len(rows))
    if not keep_rows:
        return []
    # back in job order (chunks were sent largest first)
    where = {job: n for n, job in enumerate(jobs)}
    rows = [(where[job], row) for i, chunk in enumerate(chunks) for job, row in zip(chunk, results[i])]
    return [row for _, row in sorted(rows, key=lambda nr: nr[0])]


def run_batch(sources, output, *, fmt: str | None = None, density=None, mass=None, units: str = "m",
              kind: str = "solid", on_defect: str = "raise", repair: str | None = None, robust_tol: float = 1e-3,
              robust_budget: float | None = None, self_crossing: str = "search", scheduler=None,
              n_workers: int | None = None, chunk_files: int | None = None, resume: bool = False,
              overwrite: bool = False, progress: bool = True, on_part=None) -> BatchSummary:
    """Mass properties of every mesh in ``sources``, written to ``output`` (see the module docstring).

    ``kind``, ``on_defect``, ``repair``, ``robust_tol``, ``robust_budget`` and ``self_crossing``
    are those of :func:`inertia.mesh_properties`.  ``on_part(part_path, rows)`` is called after
    each part file is written (progress hooks; see :data:`PART_S`).
    Returns a :class:`BatchSummary`; the table itself is in ``output``.
    """
    t0 = time.perf_counter()
    output = Path(output)
    fmt = format_of(output, fmt)
    for module in ("pyarrow",) + (() if fmt == "parquet" else ("pandas",)):
        _available(module, "a batch run")
    output_folder(output)  # a clear error now, not after the work, when it cannot be written
    from ..massprops.mesh import check_options

    check_options(kind, on_defect, repair, self_crossing)
    jobs = sources if sources and all(isinstance(j, Job) for j in sources) else \
        collect_jobs(sources, density=density, mass=mass, units=units)
    with _OutputLock(output):   # a second run on this output is refused, by name
        parts_dir = output.with_name(output.name + ".parts")
        if not resume:
            if output.exists() and not overwrite:
                raise InputError(f"{output} exists: pass resume=True (--resume) to continue it or "
                                 "overwrite=True (--force) to start again")
            if parts_dir.exists():
                _remove_parts_dir(parts_dir)
        remove_stale_temps(output)  # left by a killed run (kill -9 gives no chance to clean up)
        if parts_dir.is_dir():
            for tmp in parts_dir.glob(f".{PART_PREFIX}*.tmp"):
                tmp.unlink(missing_ok=True)
        options = {"kind": kind, "on_defect": on_defect, "repair": repair, "robust_tol": robust_tol,
                   "robust_budget": robust_budget, "self_crossing": self_crossing}
        previous = _previous_tables(output, fmt, parts_dir) if resume else []
        todo = _jobs_to_do(jobs, previous, options, output, recompute_stale=overwrite)
        try:
            parts_dir.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"{output}: cannot write the output there: cannot make {parts_dir} "
                             f"({exc.strerror or exc})", code="unwritable") from None
        first_part = len(_part_files(parts_dir))
        bar = Progress(len(todo), enabled=progress)
        written = [first_part]
        # the parts as Arrow tables (compact, columnar): rows are not kept as Python objects
        # longer than PART_S
        tables = []
        pending: list[dict] = []      # rows of finished chunks not yet in a part
        last_part = [time.perf_counter()]   # when the last part was written (first: the start)

        def write_part():
            rows = pending[:]
            pending.clear()
            path = parts_dir / f"{PART_PREFIX}{written[0]:06d}.parquet"
            written[0] += 1
            tables.append(write_rows_parquet(rows, path))
            last_part[0] = time.perf_counter()
            if on_part is not None:
                on_part(path, rows)

        def take_rows(_, rows):
            pending.extend(rows)
            if time.perf_counter() - last_part[0] >= PART_S:
                write_part()

        placement = [""]
        try:
            execute(todo, options=options, scheduler=scheduler, n_workers=n_workers, chunk_files=chunk_files,
                    on_rows=take_rows, progress=bar, keep_rows=False, on_start=lambda where: placement.append(where))
        except KeyboardInterrupt:
            with _interrupts_held():      # a second Ctrl-C must not cut the saving short
                if pending:               # the rows finished since the last part: saved, not lost
                    write_part()
                n_done = sum(len(read_table(p, "parquet")) for p in _part_files(parts_dir))
                sys.stderr.write(f"\ninterrupted: {n_done} files are saved in {parts_dir}; "
                                 f"run again with --resume to finish\n")
            raise

        if pending:                   # the rows since the last part go straight into the output
            tables.append(rows_to_table(pending))
            pending.clear()
        final = _latest_rows(previous + tables, jobs)
        if fmt == "parquet":
            write_table_parquet(final, output)
        else:
            write_frame(table_to_frame(final), output, fmt)
        _remove_parts_dir(parts_dir)

        # the counts describe the whole table written (after a resume: earlier rows too)
        statuses = final.column("status").to_pylist()
        counts = Counter(statuses)
        reasons = Counter(r for s, r in zip(statuses, final.column("reason").to_pylist()) if s == "error")
        return BatchSummary(total=len(jobs), skipped=len(jobs) - len(todo), processed=len(todo),
                            ok=counts.get("ok", 0), warnings=counts.get("warning", 0), errors=counts.get("error", 0),
                            errors_by_reason=dict(reasons), elapsed_s=time.perf_counter() - t0, output=str(output),
                            placement=placement[-1])


def _available(module: str, needed_for: str) -> None:
    """Raise MissingDependencyError now if ``module`` is missing, without importing it (pandas
    alone takes 0.2 s to import, which a Parquet output never needs)."""
    import importlib.util

    if module in sys.modules or importlib.util.find_spec(module) is None:
        require(module, needed_for)


def _latest_rows(tables, jobs):
    """One Arrow table: the latest row per path (later tables win), in the order of ``jobs``,
    then the rows of earlier runs for paths no longer among the jobs."""
    import pyarrow as pa

    combined = pa.concat_tables(tables) if tables else rows_to_table([])
    latest: dict[str, int] = {}
    for i, p in enumerate(combined.column("path").to_pylist()):
        latest[p] = i  # later rows (newer parts, this run) win; a dict keeps first-seen order
    job_paths = dict.fromkeys(j.path for j in jobs)
    take = [latest[p] for p in job_paths if p in latest] + [i for p, i in latest.items() if p not in job_paths]
    return _rows_at(combined, take)


def _rows_at(table, index):
    """``table.take(index)``, built from slices of the runs of consecutive rows in ``index``
    (the parts hold runs of the jobs' order, so there are about as many runs as parts);
    ``Table.take`` would import ``pyarrow.compute``, slow to load, in the parent."""
    import pyarrow as pa

    pieces, start = [], 0
    for k in range(1, len(index) + 1):
        if k == len(index) or index[k] != index[k - 1] + 1:
            pieces.append(table.slice(index[start], k - start))
            start = k
    return pa.concat_tables(pieces) if pieces else table.slice(0, 0)


def _jobs_to_do(jobs, previous, options: dict, output: Path, *, recompute_stale: bool) -> list:
    """The jobs without a row in ``previous`` of the same file (path, size, mtime) and options.

    A row of the same file made with other options (units, density, ... or another version)
    is stale: refused with the differences named, or done again with ``recompute_stale``.
    """
    if not previous:
        return list(jobs)
    done: dict = {}
    for table in previous:
        keys = table.column("options").to_pylist() if "options" in table.column_names else [None] * len(table)
        files = zip(*(table.column(c).to_pylist() for c in ("path", "size_bytes", "mtime_ns")))
        done.update(zip(files, keys))
    todo, stale = [], []
    for job in jobs:
        key = _job_key(job)
        if key in done:
            if done[key] == options_key(job, **options):
                continue
            stale.append((job, done[key]))
        todo.append(job)
    if stale and not recompute_stale:
        job, old = stale[0]
        raise InputError(f"{output}: {len(stale)} of the rows to resume were computed with other options "
                         f"({_options_change(old, options_key(job, **options))}; e.g. {job.path}); "
                         "resume with the same options, add --force (force=True) to recompute those rows, "
                         "or write to another output")
    return todo


def _options_change(old, new: str) -> str:
    """``units m -> mm, density 1000.0 -> 2700.0``: the fields that differ between two keys."""
    if not old:
        return "the earlier rows record no options (an older version)"
    a = dict(kv.split("=", 1) for kv in old.split())
    b = dict(kv.split("=", 1) for kv in new.split())
    return ", ".join(f"{k} {a.get(k) or '(none)'} -> {b.get(k) or '(none)'}" for k in b if a.get(k) != b.get(k))


def _remove_parts_dir(parts_dir: Path) -> None:
    """Remove a parts folder, refusing if it holds anything but our part files."""
    strangers = [p for p in parts_dir.iterdir()
                 if not (p.name.startswith(PART_PREFIX) or p.name.startswith(f".{PART_PREFIX}"))]
    if strangers:
        raise InputError(f"{parts_dir} holds files this tool did not write ({strangers[0].name}); "
                         "move them away or choose another output")
    shutil.rmtree(parts_dir)
