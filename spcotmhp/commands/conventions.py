"""The command line's conventions, in one place: plain help (readable piped or at 80 columns) with click-style
metavars (``--start X Y``, ``--out PATH``; flags show none), defaults and ``[required]`` marked, and every usage
error (a missing or unknown option, a bad value) as one ``error: ...`` line with exit status 2, like the
library's own errors (``spcotmhp.cli.main``)."""

from __future__ import annotations

import itertools
import re
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

import typer
from typer.core import TyperGroup

try:  # typer >= 0.2x vendors click
    from typer._click import exceptions as click_exceptions
except ImportError:  # pragma: no cover - older typer uses click itself
    from click import exceptions as click_exceptions  # type: ignore[no-redef]  # the same module, unvendored

# the type part of typer's help label ("<int range>", "<path>") -> a click-style metavar
METAVARS = {
    "str": "TEXT",
    "int": "INTEGER",
    "int range": "INTEGER",
    "float": "FLOAT",
    "float range": "FLOAT",
    "path": "PATH",
    "file": "FILE",
    "directory": "DIR",
    "list[str]": "TEXT",
}
_NUMBER = re.compile(r"-?[\d.,]+(?:e[-+]?\d+)?(?: ?(?:ms|s|%))?|-|")
_PAIR = re.compile(r"\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*,\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*")


def metavar(param: Any, ctx: Any) -> str:
    """The metavar shown for a parameter that has none: nothing for a flag, else the value's kind in capitals
    (an argument: its name in capitals)."""
    if getattr(param, "is_flag", False):
        return ""
    if getattr(param, "param_type_name", "") == "argument":
        return param.name.upper()
    try:
        label = str(param.display_type(ctx)).strip("<>")
    except (AttributeError, TypeError):
        return ""
    if "|" in label:  # choices: shown as they are typed
        return f"[{label}]"
    return " ".join(METAVARS.get(part, part.upper()) for part in label.split(","))


def tidy_params(command: Any, ctx: Any = None) -> None:
    """Give every parameter of ``command`` (and of its subcommands) a click-style metavar (idempotent)."""
    for param in getattr(command, "params", []):
        if param.metavar is None:
            param.metavar = metavar(param, ctx)
        if getattr(param, "param_type_name", "") == "argument" and hasattr(param, "display_type_rich"):
            param.display_type_rich = _no_type  # the argument's name says what it is: MODEL_DIR, not <path>
    for sub in getattr(command, "commands", {}).values():
        tidy_params(sub, ctx)


def _no_type(ctx: Any = None) -> None:
    return None


def one_line(text: str) -> str:
    """``text`` with its whitespace runs (newlines included) as single spaces."""
    return " ".join(str(text).split())


def usage_message(exc: click_exceptions.ClickException, args: Sequence[str], group: Any = None) -> str:
    """The one-line message of a click usage error, with a hint where the cause is a common slip (two numbers
    written with a comma) and a pointer to the command's ``--help``."""
    message = one_line(exc.format_message())
    for option, value in itertools.pairwise(args):
        pair = _PAIR.fullmatch(value)
        if option.startswith("--") and pair and option in message:
            message = (
                f"{option} takes two numbers separated by a space, e.g. {option} {pair[1]} {pair[2]} (got {value!r})"
            )
            break
    ctx = getattr(exc, "ctx", None)
    if ctx is not None:
        path = ctx.command_path
    else:  # e.g. a missing value: the command is the first word that names one
        names = getattr(group, "commands", {})
        path = " ".join(["spcotmhp"] + [a for a in args[:1] if a in names])
    return f"{message.rstrip('.')} (see '{path} --help')"


class ConventionalGroup(TyperGroup):
    """The top-level command group: tidy help and one-line usage errors (see the module docstring)."""

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        windows_expand_args: bool = True,
        **extra: Any,
    ) -> Any:
        argv = list(sys.argv[1:] if args is None else args)
        tidy_params(self)
        try:
            code = super().main(
                argv,
                prog_name or "spcotmhp",
                complete_var,
                standalone_mode=False,
                windows_expand_args=windows_expand_args,
                **extra,
            )
        except click_exceptions.ClickException as exc:
            if not standalone_mode:
                raise
            if type(exc).__name__ == "NoArgsIsHelpError":  # `spcotmhp` alone: the help (status 2, as click)
                exc.show()
                sys.exit(2)
            typer.echo(f"error: {usage_message(exc, argv, self)}", err=True)
            sys.exit(getattr(exc, "exit_code", 2))
        except typer.Abort:
            if not standalone_mode:
                raise
            typer.echo("error: aborted", err=True)
            sys.exit(1)
        if not standalone_mode:
            return code
        sys.exit(code if isinstance(code, int) else 0)


def plain_table(headers: Sequence[str], rows: Sequence[Sequence[Any]], title: str | None = None) -> str:
    """Rows as plain aligned text (columns of numbers right-aligned), never cut to the terminal's width: readable
    piped, in a log or at 80 columns (long lines wrap, numbers stay whole)."""
    cells = [list(map(str, headers))] + [list(map(str, r)) for r in rows]
    widths = [max(len(r[j]) for r in cells) for j in range(len(headers))]
    numeric = [all(_NUMBER.fullmatch(r[j]) for r in cells[1:]) and len(cells) > 1 for j in range(len(headers))]

    def line(r: list[str]) -> str:
        return "  ".join(
            c.rjust(w) if num else c.ljust(w) for c, w, num in zip(r, widths, numeric, strict=False)
        ).rstrip()

    out = [title] if title else []
    out += [line(cells[0]), "  ".join("-" * w for w in widths)] + [line(r) for r in cells[1:]]
    return "\n".join(out)


@contextmanager
def sweep_progress(total: int, label: str) -> Iterator:
    """A progress bar (:func:`spcotmhp.progress.progress_bar`) counting Gibbs sweeps; yields the ``progress(n)``
    callback."""
    from spcotmhp.progress import progress_bar

    with progress_bar() as bar:
        task = bar.add_task(label, total=total)
        yield lambda n: bar.advance(task, n)
