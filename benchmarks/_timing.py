"""Timing under load: each measurement repeated, the fastest kept (the work itself, without the time other
processes on a shared machine took from it); the first try is kept too, and the least CPU time of the tries
(``time.process_time``: what the process itself spent, preemption excluded)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def best_of(
    repeat: int, fn: Callable[..., T], *args, seconds: Callable[[T, float], float] | None = None, **kwargs
) -> tuple[T, float, float, float]:
    """Run ``fn(*args, **kwargs)`` ``repeat`` times; returns its last result, the fastest time, the first one and
    the least CPU time. ``seconds(result, wall)`` picks the time of one call (default: the wall time around it)."""
    best, first, cpu, out = float("inf"), None, float("inf"), None
    for _ in range(max(1, repeat)):
        c0 = time.process_time()
        t0 = time.perf_counter()
        out = fn(*args, **kwargs)
        t = time.perf_counter() - t0
        cpu = min(cpu, time.process_time() - c0)
        if seconds is not None:
            t = seconds(out, t)
        best = min(best, t)
        first = t if first is None else first
    return out, best, first, cpu
