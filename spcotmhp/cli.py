"""The ``spcotmhp`` command line. Each area's commands live in ``spcotmhp/commands/<area>.py`` and register
themselves here (one file per area keeps modules short and lets the areas grow independently)."""

from __future__ import annotations

import importlib
import sys

import typer

from spcotmhp.errors import SpcotmhpError

app = typer.Typer(
    name="spcotmhp",
    help="Learn topometric semantic maps from teaching utterances and plan paths from instructions (SpCoTMHP).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

@app.callback()
def _root() -> None:
    """Learn topometric semantic maps from teaching utterances and plan paths from instructions (SpCoTMHP)."""


@app.command()
def version() -> None:
    """Print the package version."""
    from spcotmhp import __version__

    typer.echo(__version__)


# area modules, each with a ``register(app)`` function; a module that does not exist yet is skipped.
COMMAND_MODULES = ("metric", "datasets", "learning", "teaching", "planning", "evaluation", "service", "robot",
                   "demo")

for _name in COMMAND_MODULES:
    try:
        _mod = importlib.import_module(f"spcotmhp.commands.{_name}")
    except ModuleNotFoundError as exc:  # only skip the area module itself being absent
        if exc.name != f"spcotmhp.commands.{_name}":
            raise
        continue
    _mod.register(app)


def main() -> None:
    """Entry point: library errors become one line on stderr and exit status 2 (usage errors are click's)."""
    try:
        app()
    except SpcotmhpError as exc:
        typer.echo(f"error: {exc}", err=True)
        sys.exit(2)


if __name__ == "__main__":
    main()
