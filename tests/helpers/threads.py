"""Run calls from several threads at once, for the tests that compare concurrent answers with sequential ones."""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any


def in_threads(n: int, jobs: Sequence[Any], call: Callable[[Any], Any]) -> list:
    """``[call(job) for job in jobs]``, computed by ``n`` threads released together (a barrier), thread w taking
    jobs w, w + n, ...; an exception in any thread is raised here."""
    got: list = [None] * len(jobs)
    errors: list[BaseException] = []
    barrier = threading.Barrier(n)

    def worker(w: int) -> None:
        barrier.wait()
        try:
            for i in range(w, len(jobs), n):
                got[i] = call(jobs[i])
        except BaseException as exc:  # handed to the main thread below
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(w,)) for w in range(n)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return got
