"""``python -m spcotmhp ...`` and the ``spcotmhp`` console script: the command line (:mod:`spcotmhp.cli`),
started with Python's garbage collector paused until the command's start-up is over
(:func:`spcotmhp.collector.pause_for_startup`; for ``plan`` that is its plan, for ``serve`` and ``ros2`` the
models loaded and their planners built, for every other command the command line parsed)."""

from __future__ import annotations

from spcotmhp.collector import pause_for_startup


def main() -> None:
    """Pause collection, then import and run the command line."""
    pause_for_startup()
    from spcotmhp.cli import main as cli_main

    cli_main()


if __name__ == "__main__":
    main()
