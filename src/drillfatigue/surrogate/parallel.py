"""Batched inference on whole chunks, each on a one-thread torch worker.

Many rows: whole chunks go to ``torch.get_num_threads()`` Python workers,
each running torch on one thread (torch releases the GIL inside its kernels).
Unlike torch's intra-op threads there is no barrier per operation, so a worker
preempted on a shared machine does not stall the others (5x faster at load 3
on 2 cores, equal on an idle machine). Few rows: waking a pool costs more than
the work, so the chunks run in the calling thread.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor

import torch

_POOLS: dict[int, ThreadPoolExecutor] = {}


def thread_pool(workers: int) -> ThreadPoolExecutor:
    """A process-wide thread pool of ``workers`` threads for batched inference."""
    if workers not in _POOLS:
        _POOLS[workers] = ThreadPoolExecutor(workers, thread_name_prefix="surrogate")
    return _POOLS[workers]


def map_chunks(run: Callable[[int], None], starts: Sequence[int], *, serial: bool = False) -> None:
    """Call ``run(start)`` for every chunk start, torch on one thread per call.

    ``serial``: run in the calling thread (small batches). Restores torch's
    thread count afterwards.
    """
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        if serial or threads <= 1 or len(starts) < 2:
            for a in starts:
                run(a)
        else:
            list(thread_pool(threads).map(run, starts))
    finally:
        torch.set_num_threads(threads)
