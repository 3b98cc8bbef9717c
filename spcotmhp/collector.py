"""When Python's cyclic garbage collector runs: paused while a process starts, and during precomputation.

CPython collects cycles when allocations outnumber deallocations by a threshold, and a full collection
traverses every tracked object. Starting a planner makes about 200,000 objects that live as long as the process
(the modules of numpy, numba and this package, numba's type registries loaded with the first compiled kernel,
the model) and almost no cyclic garbage, so the collections made meanwhile traverse a growing heap again and
again and free nothing (the README's "Cold start" measures the share of a fresh process's first plan they
take).

Two tools, for two owners of the process:

* :func:`paused` is for the library: a block during which automatic collection is off, restored afterwards to
  what it was (blocks may nest and run in several threads at once: collection resumes when the last running
  block ends, and only if it was on when the first began). :meth:`PlanningGraph.build` runs its precomputation
  so. Garbage made meanwhile is collected after the block, so nothing is lost.
* :func:`pause_for_startup` and :func:`end_startup` are for applications, which own the process (the
  ``spcotmhp`` command line, the HTTP service, the ROS 2 node): the collector is paused from the first import to
  the end of start-up (for ``spcotmhp plan``, the plan; for ``serve`` and the ROS node, the models loaded and
  their planners built), and then the objects made so far are frozen (:func:`gc.freeze`: moved to a
  generation no collection traverses) before collection resumes, as CPython's documentation advises for
  long-lived start-up state. The cost: a cycle that became garbage during start-up is never freed; start-up
  is bounded, so that is bounded too.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["end_startup", "pause_for_startup", "paused"]

# Per-process state (one process has one collector): whether pause_for_startup turned collection off, and
# how many paused() blocks run now (guarded by _lock) and whether the last to end turns collection back on.
_startup_paused = False
_lock = threading.Lock()
_depth = 0
_resume = False


@contextmanager
def paused() -> Iterator[None]:
    """Automatic collection off during the block, then as it was before (module docstring).

    >>> import gc
    >>> with paused():
    ...     gc.isenabled()
    False
    >>> gc.isenabled()
    True
    """
    global _depth, _resume
    with _lock:
        if _depth == 0:
            _resume = gc.isenabled()
            gc.disable()
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0 and _resume:
                gc.enable()


def pause_for_startup() -> None:
    """Turn automatic collection off until :func:`end_startup` (for an application's entry point)."""
    global _startup_paused
    if gc.isenabled():
        gc.disable()
        _startup_paused = True


def end_startup() -> None:
    """Freeze what start-up made and turn collection back on, if :func:`pause_for_startup` turned it off;
    otherwise nothing (calling it twice is harmless)."""
    global _startup_paused
    if _startup_paused:
        _startup_paused = False
        gc.freeze()
        gc.enable()
