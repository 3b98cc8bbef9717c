"""The ``spcotmhp`` command line. Each area's commands live in ``spcotmhp/commands/<area>.py`` and register
themselves here (one file per area keeps modules short and lets the areas grow independently)."""

from __future__ import annotations

import copy
import importlib
import sys
from typing import Annotated

import typer

from spcotmhp.collector import end_startup
from spcotmhp.commands.conventions import ConventionalGroup
from spcotmhp.errors import SpcotmhpError

# Commands that end the start-up themselves (spcotmhp.collector): the first plan is what their user waits for.
STARTUP_COMMANDS = frozenset({"plan", "serve", "ros2"})

app = typer.Typer(
    name="spcotmhp",
    cls=ConventionalGroup,
    help="Learn topometric semantic maps from teaching utterances and plan paths from instructions (SpCoTMHP).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain help: the same piped, narrow or in a terminal
    context_settings={"help_option_names": ["--help", "-h"]},
)


def _print_version(value: bool) -> None:
    if value:
        from spcotmhp import __version__

        typer.echo(f"spcotmhp {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    ctx: typer.Context,
    version: Annotated[
        bool,
        typer.Option("--version", is_eager=True, callback=_print_version, help="Print the version and exit."),
    ] = False,
) -> None:
    """Learn topometric semantic maps from teaching utterances and plan paths from instructions (SpCoTMHP).

    Run `spcotmhp COMMAND --help` for a command's options."""
    if ctx.invoked_subcommand not in STARTUP_COMMANDS:
        end_startup()


@app.command()
def version() -> None:
    """Print the package version."""
    from spcotmhp import __version__

    typer.echo(__version__)


# area modules, each with a ``register(app)`` function; a module that does not exist yet is skipped.
COMMAND_MODULES = (
    "metric",
    "datasets",
    "learning",
    "teaching",
    "planning",
    "evaluation",
    "service",
    "robot",
    "demo",
    "examples",
)

for _name in COMMAND_MODULES:
    try:
        _mod = importlib.import_module(f"spcotmhp.commands.{_name}")
    except ModuleNotFoundError as exc:  # only skip the area module itself being absent
        if exc.name != f"spcotmhp.commands.{_name}":
            raise
        continue
    _mod.register(app)


def app_for(args: list[str]) -> typer.Typer:
    """The app to run for the command line ``args``: when the first names a command, a copy of :data:`app` that
    holds that command alone (its options, help and errors the same); else :data:`app` itself (the group's help,
    ``--version``, a misspelt command). Typer builds the click command of every registered command, their
    parameters' annotations evaluated, before it runs one: 0.06 s of every `plan` process for 22 commands."""
    if not args:
        return app
    chosen = [c for c in app.registered_commands if _command_name(c) == args[0]]
    if len(chosen) != 1:
        return app
    alone = copy.copy(app)
    alone.registered_commands = chosen
    return alone


def _command_name(info: typer.models.CommandInfo) -> str:
    """A registered command's name as typer gives it (the function's name, dashed, when none is given)."""
    from typer.main import get_command_name

    return info.name or get_command_name(info.callback.__name__)  # type: ignore[union-attr]


def main() -> None:
    """Entry point: library errors become one line on stderr and exit status 2 (usage errors too:
    :class:`~spcotmhp.commands.conventions.ConventionalGroup`)."""
    try:
        app_for(sys.argv[1:])()
    except SpcotmhpError as exc:
        typer.echo(f"error: {exc}", err=True)
        sys.exit(2)


if __name__ == "__main__":
    main()
