"""A Dask task for tests: :func:`inertia.batch.record.process_packed`, except that a file
whose name contains ``CRASH`` ends the worker process the way a segfault in compiled code
does (no exception, no cleanup)."""

import os
import pickle

from inertia.batch.record import process_packed


def crashing_task(payload: bytes) -> bytes:
    jobs, _ = pickle.loads(payload)
    if any("CRASH" in os.path.basename(job.path) for job in jobs):
        os._exit(139)
    return process_packed(payload)
