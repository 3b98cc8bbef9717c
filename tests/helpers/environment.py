"""The process state a test leaves behind: the tests share one process, and every subprocess a test starts
(``spcotmhp serve``, the ROS 2 node, the command line) inherits ``os.environ``, so a variable a test sets and
does not restore changes what later tests run; so does Python's garbage collector left off (the command line
pauses it during start-up, :mod:`spcotmhp.collector`). tests/conftest.py fails the test (or the module's
fixtures) that leaves either changed."""

from __future__ import annotations

import gc
import os
from collections.abc import Mapping

NOT_STATE = {
    "PYTEST_CURRENT_TEST",  # pytest sets it to the running test and its phase
    # scikit-learn, joblib and threadpoolctl set these defaults when first imported, in whichever test that is
    "KMP_DUPLICATE_LIB_OK",
    "KMP_INIT_AT_FORK",
}
GC = "(garbage collector)"  # the collector's state in a snapshot, under a name no variable has


def process_state() -> dict[str, str]:
    """A snapshot: ``os.environ`` and whether automatic garbage collection is on."""
    return {**os.environ, GC: "enabled" if gc.isenabled() else "disabled"}


def state_changes(before: Mapping[str, str], after: Mapping[str, str]) -> list[str]:
    """What changed from ``before`` to ``after``, one line per variable, sorted by name."""
    out = []
    for name in sorted((before.keys() | after.keys()) - NOT_STATE):
        old, new = before.get(name), after.get(name)
        if old == new:
            continue
        if old is None:
            out.append(f"{name}: set to {new!r}")
        elif new is None:
            out.append(f"{name}: unset (was {old!r})")
        else:
            out.append(f"{name}: {old!r} -> {new!r}")
    return out


def check_unchanged(before: Mapping[str, str], after: Mapping[str, str], owner: str) -> str | None:
    """The failure message when ``owner`` (a test, a module's fixtures) left the state changed, else None."""
    changes = state_changes(before, after)
    if not changes:
        return None
    return (
        f"{owner} left the process changed (later tests, and the subprocesses they start, inherit os.environ; "
        f"restore it, e.g. with monkeypatch.setenv/delenv): {'; '.join(changes)}"
    )
