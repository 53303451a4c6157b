"""Chunking of batch jobs: every job exactly once, work balanced, small chunks at the end.

Truth: the sizes given to the jobs, counted independently of make_chunks.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from inertia.batch.run import (
    CHUNK_BYTES,
    FILE_COST_BYTES,
    GUIDED_SHARE,
    MAX_CHUNK_FILES,
    TAIL_CHUNKS_PER_WORKER,
    make_chunks,
)
from inertia.batch.sources import Job


def _jobs(sizes):
    return [Job(f"/data/mesh_{i:06d}.stl", size=int(s)) for i, s in enumerate(sizes)]


def _work(chunk):
    return sum(j.size + FILE_COST_BYTES for j in chunk)


@pytest.mark.parametrize("workers", [1, 2, 7])
def test_every_job_once_in_order_and_largest_first(workers):
    rng = np.random.default_rng(3)
    sizes = np.concatenate([rng.integers(50_000, 500_000, 3000), rng.integers(2_000_000, 6_000_000, 20)])
    rng.shuffle(sizes)
    jobs = _jobs(sizes)
    chunks = make_chunks(jobs, workers)
    flat = list(itertools.chain.from_iterable(chunks))
    assert sorted(flat, key=lambda j: j.path) == jobs  # each job exactly once
    index = {j.path: i for i, j in enumerate(jobs)}
    for chunk in chunks:  # jobs' order kept inside a chunk, and chunks are runs of it
        pos = [index[j.path] for j in chunk]
        assert pos == list(range(pos[0], pos[0] + len(pos)))
    work = [_work(c) for c in chunks]
    assert work == sorted(work, reverse=True)
    assert all(len(c) <= MAX_CHUNK_FILES for c in chunks)
    assert all(w <= CHUNK_BYTES or len(c) == 1 for w, c in zip(work, chunks))


@pytest.mark.parametrize("workers", [1, 2, 4])
def test_guided_sizes_shrink_to_a_small_tail(workers):
    sizes = np.full(4000, 100_000)  # 4000 equal files: the bound of each chunk is its share of what is left
    chunks = make_chunks(_jobs(sizes), workers)
    total = sum(_work(c) for c in chunks)
    work_in_job_order = [_work(c) for c in sorted(chunks, key=lambda c: c[0].path)]
    left = total
    for w in work_in_job_order[:-1]:  # the last chunk holds whatever remains
        bound = max(total / (TAIL_CHUNKS_PER_WORKER * workers), left / (GUIDED_SHARE * workers))
        assert w <= bound + 1e-9
        # a chunk closes only when one more file would cross its bound (or the file cap)
        assert w + 100_000 + FILE_COST_BYTES > bound or w // (100_000 + FILE_COST_BYTES) == MAX_CHUNK_FILES
        left -= w
    # the smallest chunks are a small share of one worker's work: the workers end together
    assert min(work_in_job_order[:-1]) <= 1.0001 * total / (TAIL_CHUNKS_PER_WORKER * workers) + 100_000 + FILE_COST_BYTES
    # far fewer tasks than files, and fewer than equal chunks of the tail size would need
    assert len(chunks) < TAIL_CHUNKS_PER_WORKER * workers


def test_a_file_larger_than_the_byte_cap_is_a_chunk_alone():
    sizes = [1000, 1000, CHUNK_BYTES * 2, 1000]
    chunks = make_chunks(_jobs(sizes), 2)
    assert [len(c) for c in chunks][0] == 1 and chunks[0][0].size == CHUNK_BYTES * 2
    assert sum(len(c) for c in chunks) == 4


def test_fixed_files_per_chunk():
    chunks = make_chunks(_jobs([10] * 10), 4, chunk_files=3)
    assert sorted(len(c) for c in chunks) == [1, 3, 3, 3]


def test_unknown_sizes_are_read_from_disk_and_missing_files_cost_little(tmp_path):
    a = tmp_path / "a.stl"
    a.write_bytes(b"x" * 5000)
    chunks = make_chunks([Job(str(a)), Job(str(tmp_path / "gone.stl"))], 1)
    assert sorted(j.path for c in chunks for j in c) == sorted([str(a), str(tmp_path / "gone.stl")])


def test_no_jobs_no_chunks():
    assert make_chunks([], 2) == []
