"""One worker thread with a bounded queue, for the node's slow jobs (a teach, a recognition) off the executor.

The node's executor thread must keep serving poses, instructions and Nav2's feedback while a job runs, and a
flood of jobs must not queue without bound (each holds its input: a model copy, an utterance's audio): at most
``limit`` jobs wait or run, and one past that is refused at once with the error ``busy(pending)`` gives.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any


class BoundedWorker:
    """A thread named ``name`` running jobs in order; :meth:`submit` raises ``busy(pending)`` when ``limit`` jobs
    already wait or run."""

    def __init__(self, name: str, limit: int, busy: Callable[[int], Exception]) -> None:
        self.pool = ThreadPoolExecutor(1, thread_name_prefix=name)
        self.limit, self.busy = limit, busy
        self.pending = 0
        self.lock = threading.Lock()

    def submit(self, job: Callable[..., Any], *args: Any) -> None:
        """Queue ``job(*args)``; nothing is queued once shutting down."""
        with self.lock:
            if self.pending >= self.limit:
                raise self.busy(self.pending)
            self.pending += 1
        try:
            self.pool.submit(self._run, job, *args)
        except RuntimeError:  # shutting down
            self._done()

    def _run(self, job: Callable[..., Any], *args: Any) -> None:
        try:
            job(*args)
        finally:
            self._done()

    def _done(self) -> None:
        with self.lock:
            self.pending -= 1

    def shutdown(self) -> None:
        """Wait for the job running; drop those waiting."""
        self.pool.shutdown(wait=True, cancel_futures=True)
