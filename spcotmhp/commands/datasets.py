"""CLI commands for datasets: list the bundled ones, check any folder; and how every command reads a dataset argument
(a folder or a bundled name, its warnings summarised: :func:`load_dataset_reporting`)."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer

from spcotmhp.errors import DatasetError
from spcotmhp.limits import MAX_SYNTH_EVENTS, MAX_SYNTH_ROOMS

if TYPE_CHECKING:  # the datasets package is imported by the commands that use it (a quick `spcotmhp plan`)
    from spcotmhp.datasets.dataset import Dataset


SHOWN_WARNINGS = 3


def load_dataset_arg(dataset: str, lang: str | None) -> Dataset:
    """A dataset folder, or the name of a bundled dataset ("3LDK_01", "albert-b"); ``lang`` None picks "en"
    when the teaching file has English words, else "ja"."""
    from spcotmhp.datasets.bundled import bundled_path
    from spcotmhp.datasets.loader import available_languages, load_dataset

    path = Path(dataset)
    if not path.exists():
        try:
            path = bundled_path(dataset)
        except DatasetError:
            from spcotmhp.datasets.bundled import list_bundled

            raise DatasetError(
                f"{dataset} is neither a dataset folder nor a bundled dataset name (bundled: "
                f"{', '.join(list_bundled())}; `spcotmhp datasets` describes them)"
            ) from None
    if lang is None:
        langs = available_languages(path) if (path / "teaching.csv").is_file() else []
        lang = langs[0] if langs else "en"
    return load_dataset(path, lang=lang)


def load_dataset_reporting(dataset: str, lang: str | None) -> Dataset:
    """``load_dataset_arg``, printing its DatasetWarnings to stderr as a count and the first few (as
    ``check-dataset`` lists them); other warnings pass through unchanged."""
    from spcotmhp.datasets.loader import DatasetWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DatasetWarning)
        data = load_dataset_arg(dataset, lang)
    messages = []
    for w in caught:
        if issubclass(w.category, DatasetWarning):
            messages.append(str(w.message))
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if messages and not Path(dataset).exists():  # a bundled dataset: its known warnings in one line
        from spcotmhp.datasets.bundled import known_warnings_note

        typer.echo(f"warning: {known_warnings_note(data.name, len(messages))}", err=True)
    elif messages:
        lines = [f"{data.name}: {len(messages)} dataset warning(s)"]
        lines += [f"  warning: {m}" for m in messages[:SHOWN_WARNINGS]]
        if len(messages) > SHOWN_WARNINGS:
            lines.append(
                f"  ... {len(messages) - SHOWN_WARNINGS} more (`spcotmhp check-dataset {dataset}` lists them all)"
            )
        typer.echo("\n".join(lines), err=True)
    return data


def _n_places(d: Dataset) -> int | None:
    if d.place_names is not None:
        return len(d.place_names)
    return None if d.truth_place is None else len(np.unique(d.truth_place))


def _map_size(d: Dataset) -> str:
    return f"{d.map.height}x{d.map.width} @ {d.map.resolution:g} m"


def _load_quietly(path: Path, lang: str) -> tuple[Dataset, list[str]]:
    """Load, returning the DatasetWarning messages instead of printing them."""
    from spcotmhp.datasets.loader import DatasetWarning, load_dataset

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DatasetWarning)
        d = load_dataset(path, lang=lang)
    return d, [str(w.message) for w in caught if issubclass(w.category, DatasetWarning)]


def datasets() -> None:
    """List the datasets bundled with the package (name, folder, events, places, map size, languages)."""
    from spcotmhp.commands.conventions import plain_table
    from spcotmhp.datasets.bundled import bundled_path, data_root, list_bundled
    from spcotmhp.datasets.loader import available_languages

    root = data_root()
    rows = []
    for name in list_bundled():
        path = bundled_path(name)
        langs = available_languages(path)
        d, caught = _load_quietly(path, langs[0])
        places = _n_places(d)
        rows.append(
            [
                name,
                path.relative_to(root).as_posix(),
                d.n_events,
                "-" if places is None else places,
                _map_size(d),
                ",".join(langs),
                len(caught),
            ]
        )
    typer.echo(
        plain_table(
            [
                "name",
                "folder under data/",
                "events",
                "places",
                "map (cells @ m/cell)",
                "languages",
                "warnings",
            ],
            rows,
            title=f"bundled datasets in {root}",
        )
    )


def check_dataset(
    folder: Annotated[
        Path,
        typer.Argument(
            metavar="DATASET",
            help="Dataset folder (map.yaml, teaching.csv, optional extras), or a bundled dataset's name.",
        ),
    ],
    lang: Annotated[str, typer.Option(help="en, ja, or auto (en when teaching.csv has words_en).")] = "auto",
    strict: Annotated[bool, typer.Option(help="Exit with status 1 when there are warnings.")] = False,
) -> None:
    """Load a dataset folder, print a summary and every warning; errors are one line (exit status 2)."""
    from spcotmhp.datasets.bundled import bundled_path, list_bundled
    from spcotmhp.datasets.loader import available_languages

    if not folder.exists() and str(folder) in list_bundled():
        folder = bundled_path(str(folder))
    if lang == "auto":
        langs = available_languages(folder) if (folder / "teaching.csv").is_file() else []
        lang = langs[0] if langs else "en"
    d, caught = _load_quietly(folder, lang)
    from spcotmhp.learning.observations import Observations

    Observations.from_dataset(d)  # what learning refuses before it starts (a word past the model's limit), here too
    m = d.map
    free, occupied, unknown = (float(np.mean(mask)) for mask in (m.free, m.occupied, m.unknown))
    n_words = sum(len(t) for t in d.tokens)
    lines = [
        f"dataset     {d.name} ({folder})",
        (
            f"map         {m.height} x {m.width} cells at {m.resolution:g} m, origin ({m.origin[0]:g}, "
            f"{m.origin[1]:g}); {free:.0%} free, {occupied:.0%} occupied, {unknown:.0%} unknown"
        ),
        (
            f"events      {d.n_events} teaching events, lang {d.lang}, {len(d.vocabulary)} distinct words, "
            f"{n_words / max(d.n_events, 1):.1f} words per event"
        ),
        "vocabulary  " + " ".join(d.vocabulary[:30]) + (" ..." if len(d.vocabulary) > 30 else ""),
    ]
    if d.features is not None:
        lines.append(f"features    {d.features.shape[1]}-d per event")
    if d.trajectory is not None and d.event_steps is not None:
        lines.append(f"trajectory  {len(d.trajectory)} poses; events at steps {d.event_steps[0]}..{d.event_steps[-1]}")
    if d.truth_place is not None:
        concepts = "" if d.truth_concept is None else f", {len(np.unique(d.truth_concept))} concepts"
        lines.append(f"truth       {len(np.unique(d.truth_place))} places{concepts}")
    if d.place_names is not None:
        lines.append("places      " + ", ".join(d.place_names))
    if d.adjacency is not None:
        edges = int((np.triu(d.adjacency, 1) > 0).sum())
        lines.append(f"adjacency   {len(d.adjacency)} x {len(d.adjacency)}, {edges} edges")
    if d.costmap_ros is not None:
        lines.append(
            f"costmap     costmap_ros.csv {d.costmap_ros.shape[0]} x {d.costmap_ros.shape[1]}: {recorded_note(d)}"
        )
    lines.append(f"warnings    {len(caught)}")
    lines += [f"  warning: {msg}" for msg in caught]
    typer.echo("\n".join(lines))
    if strict and caught:
        raise typer.Exit(1)


def recorded_note(d: Dataset) -> str:
    """What ``learn`` does with the dataset's costmap_ros.csv (:mod:`spcotmhp.metric.recorded`), judged against the
    default body: used when it is that body's cost map, else learned only with the body it was made for."""
    from spcotmhp.metric.costmap import default_costmap, inflate
    from spcotmhp.metric.recorded import compare_recorded

    assert d.costmap_ros is not None
    comparison = compare_recorded(d.costmap_ros, inflate(d.map, **default_costmap()))
    if comparison.same:
        return "the default body's cost map (a 0.22 m circle), used by learn"
    return (
        f"not the default body's ({comparison.unsafe} cells inscribed or lethal there are free for a 0.22 m circle, "
        f"{comparison.stricter} the other way, {comparison.other} of another cost; its inscribed cells reach "
        f"{comparison.reach_m:.3g} m): learn refuses it unless given the body it was made for"
    )


def synth(
    kind: Annotated[str, typer.Argument(help="flat, house or office; or building (of houses, with --floors)")],
    out: Annotated[Path, typer.Option("--out", help="dataset folder to write")],
    rooms: Annotated[
        int | None, typer.Option("--rooms", min=1, max=MAX_SYNTH_ROOMS, help="number of places, corridors included")
    ] = None,
    size: Annotated[
        int | None, typer.Option("--size", min=1, help="map side in cells (at most 4000: the map loader's 16e6 pixels)")
    ] = None,
    seed: Annotated[int, typer.Option("--seed", min=0)] = 0,
    word_noise: Annotated[float, typer.Option("--word-noise", help="share of place words replaced")] = 0.0,
    events_per_room: Annotated[
        int,
        typer.Option(
            "--events-per-room", min=1, max=MAX_SYNTH_EVENTS, help=f"(rooms x this: at most {MAX_SYNTH_EVENTS})"
        ),
    ] = 15,
    overwrite: Annotated[
        bool,
        typer.Option(
            "--overwrite",
            help=("Replace the dataset already in --out (a folder holding anything else is never replaced)."),
        ),
    ] = False,
    floors: Annotated[
        int | None, typer.Option("--floors", min=1, max=20, help="with KIND building: number of floors (default 2)")
    ] = None,
) -> None:
    """Generate a seeded synthetic environment (floor plan + teaching walk) as a dataset folder; `synth building
    --floors N` a building folder (building.yaml and a house per floor, stairs and a lift; spcotmhp/building/).

    --out must be a new or empty folder, or with --overwrite a dataset folder, which is replaced whole."""
    from spcotmhp.datasets.synthetic import check_dataset_target, generate_environment, write_dataset

    if kind == "building" or floors is not None:
        from spcotmhp.commands.building import synth_building

        synth_building(kind, out, floors, rooms, size, seed, word_noise, events_per_room, overwrite)
        return

    check_dataset_target(out, overwrite)  # before generating
    d = generate_environment(
        kind, seed=seed, n_rooms=rooms, size=size, word_noise=word_noise, events_per_room=events_per_room
    )
    path = write_dataset(d, out, overwrite=overwrite)
    typer.echo(
        f"wrote {path}: {d.n_events} events, {len(d.place_names or [])} places, "
        f"map {_map_size(d)}, trajectory {0 if d.trajectory is None else len(d.trajectory)} poses"
    )


def register(app: typer.Typer) -> None:
    """Add the dataset commands to ``app``."""
    app.command("datasets")(datasets)
    app.command("check-dataset")(check_dataset)
    app.command("synth")(synth)
