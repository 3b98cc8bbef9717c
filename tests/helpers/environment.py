"""The process environment a test leaves behind: the tests share one process, and every subprocess a test
starts (``spcotmhp serve``, the ROS 2 node, the command line) inherits ``os.environ``, so a variable a test
sets and does not restore changes what later tests run. tests/conftest.py fails the test (or the module's
fixtures) that leaves it changed."""

from __future__ import annotations

from collections.abc import Mapping

PYTEST_OWNED = {"PYTEST_CURRENT_TEST"}  # pytest sets it to the running test and its phase


def environment_changes(before: Mapping[str, str], after: Mapping[str, str]) -> list[str]:
    """What changed from ``before`` to ``after``, one line per variable, sorted by name."""
    out = []
    for name in sorted((before.keys() | after.keys()) - PYTEST_OWNED):
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
    """The failure message when ``owner`` (a test, a module's fixtures) left the environment changed, else None."""
    changes = environment_changes(before, after)
    if not changes:
        return None
    return (
        f"{owner} left os.environ changed (later tests and the subprocesses they start inherit it; restore it, "
        f"e.g. with monkeypatch.setenv/delenv): {'; '.join(changes)}"
    )
