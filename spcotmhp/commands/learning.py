"""CLI commands of the learning area: ``learn`` (fit and save a model) and ``evaluate-learning`` (Table 6)."""

from __future__ import annotations

import json
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError


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
            raise DatasetError(f"{dataset} is neither a dataset folder nor a bundled dataset name") from None
    if lang is None:
        langs = available_languages(path) if (path / "teaching.csv").is_file() else []
        lang = langs[0] if langs else "en"
    return load_dataset(path, lang=lang)


@contextmanager
def sweep_progress(total: int, label: str) -> Iterator:
    """A rich progress bar on stderr counting Gibbs sweeps; yields the ``progress(n)`` callback."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=Console(stderr=True), transient=False) as bar:
        task = bar.add_task(label, total=total)
        yield lambda n: bar.advance(task, n)


def learn(
    dataset: Annotated[str, typer.Argument(help="Dataset folder, or a bundled dataset name (3LDK_01, albert-b).")],
    out: Annotated[Path, typer.Option("--out", help="Model folder to write (model.json, arrays.npz, map).")],
    lang: Annotated[str | None, typer.Option(help="en or ja (default: en when available).")] = None,
    supervised: Annotated[bool, typer.Option(help="Fit from the truth labels (paper Experiment I).")] = False,
    runs: Annotated[int, typer.Option(help="Independent Gibbs runs; one is kept.")] = 10,
    iterations: Annotated[int, typer.Option(help="Gibbs sweeps per run.")] = 100,
    seed: Annotated[int, typer.Option(min=0, help="Random seed (run r uses its r-th child stream).")] = 0,
    no_replay: Annotated[bool, typer.Option("--no-replay", help="No reverse replay.")] = False,
    gmm: Annotated[bool, typer.Option("--gmm", help="SpCoSLAM baseline: Gaussian mixture, no transitions.")] = False,
    criterion: Annotated[str, typer.Option(help="Run selection: mutual_information or log_joint.")]
    = "mutual_information",
    connectivity: Annotated[str, typer.Option(help="psi of the model: auto, hmm, walk or map.")] = "auto",
    features: Annotated[bool, typer.Option(help="Use image features when the dataset has them.")] = True,
    max_places: Annotated[int, typer.Option(help="Truncation K of the place DP (more than the places).")] = 20,
    max_concepts: Annotated[int, typer.Option(help="Truncation L of the concept DP.")] = 20,
    jobs: Annotated[int, typer.Option(help="Worker processes for the runs.")] = 1,
) -> None:
    """Learn spatial concepts and places from a dataset and save the model."""
    from spcotmhp.learning.io import save_model

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_dataset_arg(dataset, lang)
    if supervised:
        from spcotmhp.learning.supervised import fit_supervised

        model = fit_supervised(data, use_features=features)
        summary = f"supervised fit: {int(model.active_places.sum())} places, psi from {model.info['psi_from']}"
    else:
        from spcotmhp.learning.gibbs import SpCoTMHP
        from spcotmhp.learning.selection import MultiRunSelector

        est = SpCoTMHP(K=max_places, L=max_concepts, iterations=iterations, seed=seed, replay=not no_replay,
                       transitions="none" if gmm else "hmm", connectivity=connectivity, use_features=features)
        with sweep_progress(runs * iterations, f"learning {data.name}") as progress:
            sel = MultiRunSelector(est, runs=runs, criterion=criterion, n_jobs=jobs).fit(data, progress=progress)
        model = sel.model_
        summary = (f"{model.info['method']}: run {sel.best_index_} of {runs} kept ({criterion}), "
                   f"{int(model.active_places.sum())} places, {int(model.active_concepts.sum())} concepts, "
                   f"psi from {model.info['psi_from']}, {sel.fit_time_:.2f} s")
    save_model(model, out)
    names = model.place_names()
    places = ", ".join(names[k] for k in range(model.K) if model.active_places[k])
    typer.echo(f"{summary}\nplaces: {places}\nmodel written to {out}")


def evaluate_learning(
    dataset: Annotated[str, typer.Argument(help="Dataset folder with truth.csv, or a bundled dataset name.")],
    runs: Annotated[int, typer.Option(help="Runs per method.")] = 10,
    seed: Annotated[int, typer.Option(min=0, help="Random seed.")] = 0,
    iterations: Annotated[int, typer.Option(help="Gibbs sweeps per run.")] = 100,
    lang: Annotated[str | None, typer.Option(help="en or ja (default: en when available).")] = None,
    features: Annotated[bool, typer.Option(help="Use image features when the dataset has them.")] = True,
    jobs: Annotated[int, typer.Option(help="Worker processes for the runs.")] = 1,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of the table.")] = False,
) -> None:
    """Table 6: NMI and ARI of concepts and places against the truth for SpCoTMHP with and without reverse
    replay and the SpCoSLAM baseline (means over runs), beside the paper's numbers."""
    from spcotmhp.learning import table6

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_dataset_arg(dataset, lang)
    with sweep_progress(3 * runs * iterations, f"Table 6 on {data.name}") as progress:
        results = table6.evaluate_learning(data, runs=runs, seed=seed, iterations=iterations, n_jobs=jobs,
                                           progress=progress, use_features=features)
    if as_json:
        typer.echo(json.dumps(table6.as_json(results), indent=1))
    else:
        typer.echo(table6.format_table(results, f"{data.name} (lang {data.lang})"))


def register(app: typer.Typer) -> None:
    """Add the learning commands to ``app``."""
    app.command()(learn)
    app.command("evaluate-learning")(evaluate_learning)
