"""CLI command ``teach``: teach a saved model a place name at run time (online learning), or apply teaching
recorded by ``spcotmhp ros2 MODEL --record DIR`` to the model it was said against (``--from DIR``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer


def teach(
    model_dir: Annotated[Path, typer.Argument(help="Model folder to update (written back atomically).")],
    utterance: Annotated[
        str | None, typer.Argument(help='What the place is called, e.g. "this is alice\'s room".')
    ] = None,
    at: Annotated[
        tuple[float, float] | None, typer.Option("--at", help="Where it was said: X Y in metres (map frame).")
    ] = None,
    from_: Annotated[
        Path | None,
        typer.Option(
            "--from",
            help="A folder recorded by 'spcotmhp ros2 MODEL_DIR --record DIR': apply its utterances (those not "
            "applied yet) to this model.",
        ),
    ] = None,
    answer: Annotated[
        bool, typer.Option("--answer", help="The utterance answers one of the model's questions ('questions').")
    ] = False,
    answers: Annotated[
        str | None,
        typer.Option(
            "--answers", help="How an answer enters the model (spcotmhp/teaching/answers.py; default: the chosen one)."
        ),
    ] = None,
) -> None:
    """Teach the model in MODEL_DIR that UTTERANCE was said at X Y (or the utterances recorded in --from DIR), save
    it, and print what happened (a new place, or the place it joined). The folder is replaced whole or not at all;
    it must hold a model (nothing else is ever overwritten)."""
    from spcotmhp.errors import TeachingError
    from spcotmhp.persistence.io import check_target, load_model, save_model
    from spcotmhp.teaching.recorded import apply_recording
    from spcotmhp.teaching.teach import teach as teach_model

    if (from_ is None) == (utterance is None) or (utterance is not None and at is None) or (from_ and at):
        raise TeachingError("give an UTTERANCE with --at X Y, or --from DIR (a folder recorded by 'spcotmhp ros2')")
    model = load_model(model_dir)
    check_target(model_dir, True, "teach replaces the model folder whole: move those files out of it first")
    if from_ is not None:
        taught, applied, total = apply_recording(model, from_)
        if taught is None:
            typer.echo(f"nothing new in {from_}: its {total} utterance(s) are already in {model_dir}")
            return
        save_model(taught.model, model_dir, overwrite=True)
        for k in range(applied):
            typer.echo(f"{taught.summary(k)['message']}")
        typer.echo(
            f"applied {applied} recorded utterance(s) of {from_} ({total} in all); "
            f"{int(taught.model.active_places.sum())} places; saved to {model_dir}"
        )
        return
    assert at is not None and utterance is not None
    taught = teach_model(model, [{"x": at[0], "y": at[1], "utterance": utterance, "answer": answer}], answers)
    save_model(taught.model, model_dir, overwrite=True)
    s = taught.summary()
    typer.echo(
        f"taught {utterance!r} at ({at[0]:g}, {at[1]:g}): {s['message']}; {s['places']} places; update "
        f"{1000 * s['time_update_s']:.0f} ms, model {1000 * s['time_export_s']:.0f} ms; saved to {model_dir}"
    )
    _say_merges(taught.model)


def _say_merges(model) -> None:
    """Echo the merges a teach leaves (``learning.merges``): a teach that renamed a shared place says so."""
    from spcotmhp.learning.merges import merge_lines
    from spcotmhp.teaching.questions import said_merges

    for line in merge_lines(said_merges(model)):
        typer.echo(line)


def questions(
    model_dir: Annotated[Path, typer.Argument(help="Model folder.")],
    max_questions: Annotated[int, typer.Option("--max", min=1, max=100, help="Questions to list.")] = 5,
    as_json: Annotated[bool, typer.Option("--json", help='Print {"questions": [...]} as JSON.')] = False,
    answers: Annotated[
        str | None,
        typer.Option("--answers", help="How answers enter the model (spcotmhp/teaching/answers.py; default: chosen)."),
    ] = None,
) -> None:
    """List where an answer would tell the model most about what a place is called, best first
    (spcotmhp/teaching/questions.py: the entropy of the name the model expects there). Answer one with
    'spcotmhp teach MODEL_DIR "this is the NAME" --at X Y --answer'."""
    import json

    from spcotmhp.persistence.io import load_model
    from spcotmhp.teaching.questions import questions as ask

    asked = ask(load_model(model_dir), max_questions, answers=answers)
    if as_json:
        typer.echo(json.dumps({"questions": asked}, ensure_ascii=False))
        return
    if not asked:
        typer.echo("no question: the model is sure of the name wherever it was taught")
    for i, q in enumerate(asked, 1):
        typer.echo(
            f"{i}. at ({q['x']:g}, {q['y']:g}): {q['ask']} ({' or '.join(q['candidates'])}?) "
            f"[{q['information']:.2f} nats: {q['why']}]"
        )


def register(app: typer.Typer) -> None:
    """Add ``teach`` and ``questions`` to ``app``."""
    app.command()(teach)
    app.command()(questions)
