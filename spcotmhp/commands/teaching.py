"""CLI command ``teach``: teach a saved model a place name at run time (online learning)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer


def teach(
    model_dir: Annotated[Path, typer.Argument(help="Model folder to update (written back atomically).")],
    utterance: Annotated[str, typer.Argument(help='What the place is called, e.g. "this is alice\'s room".')],
    at: Annotated[tuple[float, float], typer.Option("--at", help="Where it was said: X Y in metres (map frame).")],
) -> None:
    """Teach the model in MODEL_DIR that UTTERANCE was said at X Y, save it, and print the place it was assigned
    to. The folder is replaced whole or not at all; it must hold a model (nothing else is ever overwritten)."""
    from spcotmhp.learning.io import check_target, load_model, save_model
    from spcotmhp.learning.teach import teach as teach_model

    model = load_model(model_dir)
    check_target(model_dir, True, "teach replaces the model folder whole: move those files out of it first")
    taught = teach_model(model, [{"x": at[0], "y": at[1], "utterance": utterance}])
    save_model(taught.model, model_dir, overwrite=True)
    s = taught.summary()
    typer.echo(
        f"taught {utterance!r} at ({at[0]:g}, {at[1]:g}): place {s['place']} "
        f"'{s['label']}'{' (a new place)' if s['new_place'] else ''}; {s['places']} places; update "
        f"{1000 * s['time_update_s']:.0f} ms, model {1000 * s['time_export_s']:.0f} ms; saved to {model_dir}"
    )


def register(app: typer.Typer) -> None:
    """Add ``teach`` to ``app``."""
    app.command()(teach)
