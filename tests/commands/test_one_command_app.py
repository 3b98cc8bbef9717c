"""``cli.app_for``: a command line naming a command runs an app holding that command alone, with the same
help, usage errors and results as the full app; anything else runs the full app."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from spcotmhp.cli import _command_name, app, app_for

runner = CliRunner()

LINES = [
    ["plan", "--help"],
    ["plan"],
    ["plan", "no-such-model", "go to the kitchen", "--start", "0", "0"],
    ["plan", "m", "go", "--start", "0"],
    ["plan", "m", "go", "--start", "0", "0", "--bogus"],
    ["learn", "--help"],
    ["check-dataset", "--help"],
    ["version"],
    ["precompute", "--help"],
]


@pytest.mark.parametrize("args", LINES, ids=" ".join)
def test_the_one_command_app_answers_as_the_full_app(args):
    alone = app_for(args)
    assert alone is not app and len(alone.registered_commands) == 1
    assert _command_name(alone.registered_commands[0]) == args[0]
    full, one = runner.invoke(app, args), runner.invoke(alone, args)
    assert (one.exit_code, one.output) == (full.exit_code, full.output)


@pytest.mark.parametrize("args", [[], ["--help"], ["--version"], ["plann"], ["-h"]])
def test_anything_but_a_command_runs_the_full_app(args):
    assert app_for(args) is app
    assert len(app.registered_commands) > 10  # the copy never changed the app itself
