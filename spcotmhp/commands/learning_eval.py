"""CLI command ``evaluate-learning``: Table 6 (NMI and ARI against the truth), batch or online."""

from __future__ import annotations

import json
import warnings
from typing import TYPE_CHECKING, Annotated

import typer

from spcotmhp.commands.conventions import sweep_progress
from spcotmhp.commands.datasets import load_dataset_reporting
from spcotmhp.limits import MAX_CONCEPTS, MAX_ITERATIONS, MAX_JOBS, MAX_PLACES, MAX_RUNS, MAX_SEEDS

if TYPE_CHECKING:
    from spcotmhp.datasets.dataset import Dataset


# long: a CLI command: 27 lines of typer options and help, a 40-line body
def evaluate_learning(
    dataset: Annotated[str, typer.Argument(help="Dataset folder with truth.csv, or a bundled dataset name.")],
    runs: Annotated[int, typer.Option(min=1, max=MAX_RUNS, help="Runs per method and seed.")] = 10,
    seed: Annotated[int, typer.Option(min=0, help="First random seed.")] = 0,
    seeds: Annotated[
        int, typer.Option(min=1, max=MAX_SEEDS, help="Seeds (seed, seed + 1, ...): results are mean ± sd over them.")
    ] = 5,
    iterations: Annotated[int, typer.Option(min=1, max=MAX_ITERATIONS, help="Gibbs sweeps per run.")] = 100,
    lang: Annotated[str | None, typer.Option(help="en or ja (default: en when available).")] = None,
    features: Annotated[bool, typer.Option(help="Use image features when the dataset has them.")] = True,
    jobs: Annotated[int, typer.Option(min=1, max=MAX_JOBS, help="Worker processes for the runs.")] = 1,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of the table.")] = False,
    max_places: Annotated[int, typer.Option(min=1, max=MAX_PLACES, help="Truncation K of the place DP.")] = 20,
    max_concepts: Annotated[int, typer.Option(min=1, max=MAX_CONCEPTS, help="Truncation L of the concept DP.")] = 20,
    online: Annotated[
        bool,
        typer.Option(
            "--online",
            help=(
                "Stream the events one at a time to the online learner (one seed per run) and compare with batch "
                "learning; reports the update time per event."
            ),
        ),
    ] = False,
) -> None:
    """Table 6: NMI and ARI of concepts and places against the truth for SpCoTMHP with and without reverse
    replay and the SpCoSLAM baseline (means over runs, then mean ± sd over seeds), beside the paper's numbers."""
    from spcotmhp.evaluation import table6
    from spcotmhp.learning.posterior import TruncationWarning

    data = load_dataset_reporting(dataset, lang)
    if online:
        _evaluate_online(data, runs, seed, iterations, features, jobs, as_json, max_places, max_concepts)
        return
    with (
        sweep_progress(3 * seeds * runs * iterations, f"Table 6 on {data.name}") as progress,
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", TruncationWarning)  # counted per method, reported below
        results = table6.evaluate_seeds(
            data,
            seeds=seeds,
            seed=seed,
            runs=runs,
            iterations=iterations,
            n_jobs=jobs,
            progress=progress,
            use_features=features,
            K=max_places,
            L=max_concepts,
        )
    for name, scores in results.items():
        for what, option, size in (
            ("places", "--max-places", max_places),
            ("concepts", "--max-concepts", max_concepts),
        ):
            if scores["saturated"][what]:
                typer.echo(
                    f"warning: {table6.LABELS[name]}: all {size} {what[:-1]} components hold events in "
                    f"{scores['saturated'][what]} of {seeds * runs} run(s) (the weak-limit truncation "
                    f"is saturated, so {what} may have been merged): evaluate again with a larger {option}",
                    err=True,
                )
    if as_json:
        typer.echo(json.dumps({**results, "seeds": seeds}, indent=1))
    else:
        typer.echo(table6.format_table(results, f"{data.name} (lang {data.lang})"))


def _evaluate_online(
    data: Dataset,
    runs: int,
    seed: int,
    iterations: int,
    features: bool,
    jobs: int,
    as_json: bool,
    K: int,
    L: int,
) -> None:
    """evaluate-learning --online (``evaluation.online_eval``): JSON with an "online" key, or a short table."""
    from spcotmhp.evaluation.online_eval import evaluate_online, format_report
    from spcotmhp.learning.posterior import TruncationWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)
        result = evaluate_online(
            data, seeds=runs, seed=seed, iterations=iterations, n_jobs=jobs, use_features=features, K=K, L=L
        )
    typer.echo(json.dumps(result, indent=1) if as_json else format_report(result))
