"""Worker processes on this machine, for the batch: started in milliseconds, a crash costs one row.

A :class:`ProcessPool` runs chunks of files in child processes, each busy with one chunk at
a time.  On Linux, from a parent without threads, the children are forked: they start in a
few milliseconds with everything the parent has loaded (NumPy, the compiled kernels warmed
up once in the parent).  Elsewhere, or beside threads (where forking is unsafe), they are
spawned and each imports what it needs (about a second).

A child that dies while processing (a segfault in compiled code, the out-of-memory killer)
is replaced; the chunk it was running is retried one file per task, and the file whose task
still kills its worker becomes a ``crashed`` row.  The run goes on.  Each child ignores
Ctrl-C: the parent stops them when it is interrupted.
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
import signal
import sys
import threading
from collections import deque
from multiprocessing.connection import wait

from .record import crashed_row, process_packed

#: seconds to start one worker: forked (inherits the loaded modules) or spawned (imports them)
START_S = {"fork": 0.02, "spawn": 1.0, "forkserver": 1.0}


def start_method() -> str:
    """``fork`` where it is available and safe (no other thread in this process), else ``spawn``."""
    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and sys.platform.startswith("linux") and threading.active_count() == 1:
        return "fork"
    return "spawn"


def _tune_malloc() -> None:
    """glibc: keep freed memory for the next file (what WORKER_MALLOC_ENV asks of Dask workers)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL("libc.so.6")
        m_trim_threshold, m_top_pad, m_mmap_threshold = -1, -2, -3
        libc.mallopt(m_trim_threshold, 2**31 - 1)
        libc.mallopt(m_mmap_threshold, 32 * 2**20)
        libc.mallopt(m_top_pad, 16 * 2**20)
    except (OSError, AttributeError):
        pass


def _serve(conn, others, task) -> None:
    """A worker: answer each payload received on ``conn`` with ``task(payload)`` until told to stop."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # the parent handles Ctrl-C
    for other in others:                           # the parent's ends of the other workers' pipes
        other.close()
    _tune_malloc()
    while True:
        try:
            payload = conn.recv_bytes()
        except (EOFError, OSError):
            return
        if not payload:
            return
        conn.send_bytes(task(payload))


class ProcessPool:
    """``n_workers`` child processes running ``task`` (default :func:`process_packed`) on chunks."""

    def __init__(self, n_workers: int, task=None, method: str | None = None):
        self.method = method or start_method()
        self.context = multiprocessing.get_context(self.method)
        self.task = task or process_packed
        self.n_workers = max(1, int(n_workers))
        self.workers: list[dict] = []

    def _start(self) -> dict:
        parent, child = self.context.Pipe()
        others = [w["conn"] for w in self.workers]
        proc = self.context.Process(target=_serve, args=(child, others if self.method == "fork" else [], self.task),
                                    daemon=True, name="inertia-batch-worker")
        proc.start()
        child.close()
        return {"proc": proc, "conn": parent, "busy": None}

    def __enter__(self):
        for _ in range(self.n_workers):
            self.workers.append(self._start())
        return self

    def __exit__(self, *exc):
        for w in self.workers:
            try:
                w["conn"].send_bytes(b"")
            except OSError:
                pass
        for w in self.workers:
            w["proc"].join(timeout=0 if exc[0] is not None else 5)
            if w["proc"].is_alive():
                w["proc"].kill()
                w["proc"].join()
            w["conn"].close()
        self.workers = []
        return False

    def map(self, chunks, options):
        """Yield ``(i, rows of chunks[i])`` as chunks finish (a crash isolates, see the module)."""
        queue = deque((i, None, chunk) for i, chunk in enumerate(chunks))
        split: dict[int, dict] = {}
        self._dispatch(queue, options)
        while any(w["busy"] for w in self.workers):
            busy = [w for w in self.workers if w["busy"] is not None]
            ready = set(wait([w["conn"] for w in busy] + [w["proc"].sentinel for w in busy]))
            finished = []
            for w in busy:
                i, sub, jobs = w["busy"]
                rows = self._collect(w, ready)
                if rows is None:
                    continue
                if isinstance(rows, Exception):     # the worker was lost with this task
                    if sub is None and len(jobs) > 1:   # isolate: one file per task
                        split[i] = {}
                        queue.extend((i, k, [job]) for k, job in enumerate(jobs))
                        continue
                    rows = [crashed_row(jobs[0], rows, options)]
                whole = reassemble(split, chunks, i, sub, rows)
                if whole is not None:
                    finished.append((i, whole))
            # the idle workers get their next chunk before the caller handles the finished ones
            # (writing a part takes milliseconds, the first one tens: Arrow's import)
            self._dispatch(queue, options)
            yield from finished

    def _dispatch(self, queue: deque, options) -> None:
        """Send the next tasks of ``queue`` to the idle workers."""
        for w in list(self.workers):
            if w["busy"] is None and queue:
                if not w["proc"].is_alive():   # ended between tasks: a fresh one takes the task
                    w = self._replace(w)
                w["busy"] = queue.popleft()
                w["conn"].send_bytes(pickle.dumps((w["busy"][2], options), protocol=pickle.HIGHEST_PROTOCOL))

    def _collect(self, w: dict, ready: set):
        """The rows of ``w``'s task if it answered; if it died, the error (and a new worker in
        its place); None while it works."""
        if w["conn"] in ready:
            try:
                rows = pickle.loads(w["conn"].recv_bytes())
            except (EOFError, OSError):
                rows = None
        elif w["proc"].sentinel in ready:
            rows = None
        else:
            return None
        w["busy"] = None
        if rows is None:
            error = _lost_error(w)
            self._replace(w)
            return error
        return rows

    def _replace(self, w: dict) -> dict:
        """A new worker in the place of ``w``, which has ended."""
        w["proc"].join()
        w["conn"].close()
        new = self._start()
        self.workers[self.workers.index(w)] = new
        return new


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


def _lost_error(w: dict) -> Exception:
    w["proc"].join()
    code = w["proc"].exitcode
    if code is not None and code < 0:
        try:
            what = f"signal {-code} ({signal.Signals(-code).name})"
        except ValueError:
            what = f"signal {-code}"
    else:
        what = f"exit status {code}"
    return ChildProcessError(f"worker process {w['proc'].pid} ended with {what}")


def cpu_count() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1
