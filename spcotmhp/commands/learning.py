"""CLI commands of the learning area: ``learn`` (fit and save a model); ``evaluate-learning`` (Table 6) is in
:mod:`spcotmhp.commands.learning_eval`."""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from spcotmhp.commands import body_options as bo
from spcotmhp.commands.conventions import sweep_progress
from spcotmhp.commands.datasets import load_dataset_reporting
from spcotmhp.errors import ModelError
from spcotmhp.limits import MAX_CONCEPTS, MAX_ITERATIONS, MAX_JOBS, MAX_PLACES, MAX_RUNS

if TYPE_CHECKING:  # the datasets package is imported by the commands that use it (a quick `spcotmhp plan`)
    from spcotmhp.datasets.dataset import Dataset
    from spcotmhp.learning.model import Hyperparameters
    from spcotmhp.metric.body import RobotBody

# learn --connectivity -> the adjacency source of the supervised fit ("hmm": the truth's transition counts)
SUPERVISED_CONNECTIVITY = {
    "auto": "auto",
    "hmm": "transitions",
    "walk": "walk",
    "map": "map",
    "given": "given",
}


def parse_feature_weight(text: str) -> float | None:
    """--feature-weight: a finite number > 0 (the total count of one image), or "authors" (None: the authors'
    p * 10 + 1 counts)."""
    if text.strip().lower() == "authors":
        return None
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise ModelError(
            f"--feature-weight must be a number > 0 or 'authors' (the authors' p * 10 + 1 counts), got {text!r}"
        )
    return value


def _not_for_supervised(given: dict[str, bool]) -> None:
    """--supervised fits the truth labels directly: options of the Gibbs learner are a mistake there."""
    wrong = [name for name, is_given in given.items() if is_given]
    if wrong:
        raise ModelError(
            f"{', '.join(wrong)}: option(s) of the Gibbs learner, which --supervised (a fit from the "
            f"truth labels) does not use; drop {'it' if len(wrong) == 1 else 'them'}"
        )


# long: a CLI command: 53 lines of typer options and help, a 56-line body
def learn(
    dataset: Annotated[str, typer.Argument(help="Dataset folder, or a bundled dataset name (3LDK_01, albert-b).")],
    out: Annotated[Path, typer.Option("--out", help="Model folder to write (model.json, arrays.npz, map).")],
    lang: Annotated[str | None, typer.Option(help="en or ja (default: en when available).")] = None,
    supervised: Annotated[bool, typer.Option(help="Fit from the truth labels (paper Experiment I).")] = False,
    runs: Annotated[
        int | None, typer.Option(min=1, max=MAX_RUNS, help="Independent Gibbs runs; one is kept (default 10).")
    ] = None,
    iterations: Annotated[
        int | None, typer.Option(min=1, max=MAX_ITERATIONS, help="Gibbs sweeps per run (default 100).")
    ] = None,
    seed: Annotated[
        int | None, typer.Option(min=0, help="Random seed (run r uses its r-th child stream; default 0).")
    ] = None,
    no_replay: Annotated[bool, typer.Option("--no-replay", help="No reverse replay.")] = False,
    gmm: Annotated[bool, typer.Option("--gmm", help="SpCoSLAM baseline: Gaussian mixture, no transitions.")] = False,
    criterion: Annotated[
        str | None,
        typer.Option(
            help="Run selection: auto (default: mutual_information with image features, else log_joint), "
            "mutual_information, log_joint, or one of the criteria that handle the background-word switches: "
            "log_joint_switch_mode, log_joint_switch_marginal, log_joint_switch_plugin, log_joint_tail_mean, "
            "held_out_words (research variants, spcotmhp/experimental/selection.py; docs/experimental.md)."
        ),
    ] = None,
    connectivity: Annotated[
        str,
        typer.Option(
            help=(
                "psi of the model: auto, hmm, walk or map (with --supervised also given: adjacency.csv; hmm there is "
                "the truth's transition counts)."
            )
        ),
    ] = "auto",
    features: Annotated[bool, typer.Option(help="Use image features when the dataset has them.")] = True,
    feature_weight: Annotated[
        str,
        typer.Option(help=("Total count of one image's features, or 'authors' for the authors' p * 10 + 1 counts.")),
    ] = "1",
    max_places: Annotated[
        int | None,
        typer.Option(min=1, max=MAX_PLACES, help="Truncation K of the place DP (more than the places; default 20)."),
    ] = None,
    max_concepts: Annotated[
        int | None, typer.Option(min=1, max=MAX_CONCEPTS, help="Truncation L of the concept DP (default 20).")
    ] = None,
    jobs: Annotated[
        int | None, typer.Option(min=1, max=MAX_JOBS, help="Worker processes for the runs (default 1).")
    ] = None,
    split: Annotated[
        bool,
        typer.Option(
            "--split/--no-split",
            help="Split a place where two names taught >= 3 times each have a wall or door between them (a "
            "departure from the paper, spcotmhp/learning/taught_split.py); --no-split keeps the paper's places.",
        ),
    ] = True,
    overwrite: Annotated[
        bool,
        typer.Option(
            "--overwrite",
            help=("Replace the model already in --out (a folder holding anything else is never replaced)."),
        ),
    ] = False,
    nav2_params: bo.Nav2Params = None,
    robot_radius: bo.RobotRadius = None,
    footprint: bo.Footprint = None,
    inflation_radius: bo.InflationRadius = None,
    cost_scaling_factor: bo.CostScaling = None,
    precompute: Annotated[
        bool,
        typer.Option(
            help="Save the planning graph (default settings) with the model, so that plan / serve / ros2 load it "
            "instead of building it (`spcotmhp precompute MODEL` adds it later)."
        ),
    ] = True,
) -> None:
    """Learn spatial concepts and places from a dataset and save the model.

    --out must be a new or empty folder, or with --overwrite a model folder; it is written whole or not at all
    (the previous model stays loadable until the new one is complete), never onto the dataset itself. A folder
    recorded by ``spcotmhp ros2 --record`` is refused: its teaching goes into its model (``teach --from``)."""
    from spcotmhp.persistence.io import prepare_model_folder, save_model
    from spcotmhp.teaching.recorded import refuse_learning_alone

    if Path(dataset).is_dir():
        refuse_learning_alone(Path(dataset))
    weight = parse_feature_weight(feature_weight)
    if supervised:
        _not_for_supervised(
            {
                "--runs": runs is not None,
                "--iterations": iterations is not None,
                "--seed": seed is not None,
                "--no-replay": no_replay,
                "--gmm": gmm,
                "--criterion": criterion is not None,
                "--max-places": max_places is not None,
                "--max-concepts": max_concepts is not None,
                "--jobs": jobs is not None,
                "--no-split": not split,
            }
        )
        if connectivity not in SUPERVISED_CONNECTIVITY:
            raise ModelError(
                f"--connectivity must be one of {', '.join(SUPERVISED_CONNECTIVITY)} with "
                f"--supervised, got {connectivity!r}"
            )
    from spcotmhp.commands.building import joint_or_none

    building = joint_or_none(dataset, lang)  # a building folder: its floors as one (joint) dataset
    data = building.data if building is not None else load_dataset_reporting(dataset, lang)
    if data.path is not None and _overlaps(out, Path(data.path)):
        raise ModelError(f"--out {out} is the dataset folder {data.path} or contains it; write the model elsewhere")
    prepare_model_folder(out, overwrite)  # a bad --out fails now, not after the fit
    body = bo.body_from_options(nav2_params, robot_radius, footprint, inflation_radius, cost_scaling_factor)
    check_recorded_costmap(data, body)  # a costmap_ros.csv made for another robot fails now
    if supervised:
        from spcotmhp.learning.supervised import fit_supervised

        model = fit_supervised(
            data,
            adjacency=SUPERVISED_CONNECTIVITY[connectivity],
            use_features=features,
            feature_weight=weight,
            hyper=None if building is None else building.hyper(supervised=True),
        )
        summary = f"supervised fit: {int(model.active_places.sum())} places, psi from {model.info['psi_from']}"
        from spcotmhp.learning.merges import merge_lines
        from spcotmhp.teaching.questions import said_merges

        merged = merge_lines(said_merges(model))
    else:
        model, summary, merged = _fit_gibbs(
            data,
            runs or 10,
            iterations or 100,
            seed or 0,
            not no_replay,
            gmm,
            criterion or "auto",
            connectivity,
            features,
            weight,
            max_places or (20 if building is None else building.default_places),
            max_concepts or 20,
            jobs or 1,
            None if building is None else building.hyper(supervised=False),
            split,
        )
    from spcotmhp.teaching.answers import attach_walk

    attach_walk(model, data.trajectory)  # the walk judges the split at an answer (teaching/answers.py)
    if body is not None:
        from spcotmhp.planning.body import with_body

        model = with_body(model, body)
        summary += f"\nbody: {body.describe()}"
    if building is not None:
        building.save(model, out, overwrite)
    else:
        files, note = _graph_for(model) if precompute else (None, "")
        save_model(model, out, overwrite=overwrite, files=files)
        summary += note
    from spcotmhp.language.said_names import shown_names
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary

    names = shown_names(place_labels(model, place_vocabulary(model)), model)  # as plans name them, as taught
    places = ", ".join(names[k] for k in range(model.K) if model.active_places[k])
    typer.echo("\n".join([summary, f"places: {places}", *merged, f"model written to {out}"]))


def check_recorded_costmap(data: Dataset, body: RobotBody | None) -> None:
    """A dataset's costmap_ros.csv must be the cost map of the model's body (:mod:`spcotmhp.metric.recorded`):
    used when it is, refused with one line when it is not."""
    if data.costmap_ros is None:
        return
    from spcotmhp.errors import RobotBodyError
    from spcotmhp.metric.costmap import default_costmap, inflate
    from spcotmhp.metric.recorded import compare_recorded

    comparison = compare_recorded(
        data.costmap_ros, inflate(data.map, **(body.costmap() if body else default_costmap()))
    )
    if not comparison.same:
        what = body.describe() if body is not None else "the default body (a 0.22 m circle, inflation 1 m, scaling 10)"
        raise RobotBodyError(
            f"{data.path}: {comparison.describe(what)}; give the body it was made for (--nav2-params FILE, "
            "--robot-radius R or --footprint) or remove costmap_ros.csv"
        )


def _graph_for(model: Any) -> tuple[Any, str]:
    """``(writers, note)``: the files of the planning graph of ``model`` under the default settings, saved with
    it, or None and why not (a model that cannot be planned with is still saved)."""
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.planning.graph import PlanningGraph
    from spcotmhp.planning.graph_store import graph_writers

    try:
        graph = PlanningGraph.build(model)
    except SpcotmhpError as exc:
        return None, f"\nplanning graph not saved: {exc}"
    note = f"\nplanning graph precomputed in {graph.time_precompute_s:.1f} s and saved with the model"
    return graph_writers(graph), note


def _overlaps(out: Path, folder: Path) -> bool:
    """Whether the folder ``out`` is ``folder`` or one of its parents (replacing it would replace ``folder``)."""
    from spcotmhp.safe_write import same_file

    target = Path(out).resolve()
    here = folder.resolve()
    return same_file(Path(out), folder) or here.is_relative_to(target)


CRITERION_WORDS = {
    "log_joint": "the highest collapsed log joint",
    "mutual_information": "the highest word-concept mutual information",
}
"""How ``learn`` names the run-selection criterion it used (the others by their names)."""


def _fit_gibbs(
    data: Dataset,
    runs: int,
    iterations: int,
    seed: int,
    replay: bool,
    gmm: bool,
    criterion: str,
    connectivity: str,
    features: bool,
    feature_weight: float | None,
    K: int,
    L: int,
    jobs: int,
    hyper: Hyperparameters | None = None,
    split: bool = True,
):
    """The multi-run Gibbs fit of ``learn``, then (``split``) the taught-merge split of the kept run
    (``taught_split``); a saturated truncation of the kept run is reported on stderr. Returns the model, the
    summary line and the lines on splits and merges."""
    from spcotmhp.learning.gibbs import SpCoTMHP
    from spcotmhp.learning.posterior import TruncationWarning, truncation_messages
    from spcotmhp.learning.selection import CRITERIA, MultiRunSelector

    chosen: Any = criterion
    if criterion not in CRITERIA:  # a research criterion (or an unknown name: a one-line ModelError)
        from spcotmhp.experimental.selection import criterion as research_criterion

        chosen = research_criterion(criterion)
    est = SpCoTMHP(
        K=K,
        L=L,
        iterations=iterations,
        seed=seed,
        replay=replay,
        transitions="none" if gmm else "hmm",
        connectivity=connectivity,
        use_features=features,
        feature_weight=feature_weight,
        hyper=hyper,
    )
    with sweep_progress(runs * iterations, f"learning {data.name}") as progress, warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)  # reported once below, for the kept run
        sel = MultiRunSelector(est, runs=runs, criterion=chosen, n_jobs=jobs).fit(data, progress=progress)
    merged = _split_kept(sel, data, split)
    model = sel.model_
    for message in truncation_messages(model):
        typer.echo(f"warning: {message}", err=True)
    why = CRITERION_WORDS.get(sel.criterion_, sel.criterion_)
    if criterion == "auto":
        why += f" (--criterion auto: {'with' if sel.criterion_ == 'mutual_information' else 'no'} image features)"
    summary = (
        f"{model.info['method']}: run {sel.best_index_} of {runs} kept by {why}, "
        f"{int(model.active_places.sum())} places, {int(model.active_concepts.sum())} concepts, "
        f"psi from {model.info['psi_from']}, {sel.fit_time_:.2f} s"
    )
    return model, summary, merged


def _split_kept(sel: Any, data: Dataset, split: bool) -> list[str]:
    """``learn``'s taught-merge split of the run ``sel`` kept (``split``: else the paper's places), and the lines
    that say what it split and which merges remain (``taught_split.SplitOutcome.lines``)."""
    from spcotmhp.learning.taught_split import SplitOutcome, split_selected
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
    from spcotmhp.teaching.questions import name_vocabulary, said_merges

    words, labels = name_vocabulary(sel.model_), place_labels(sel.model_, place_vocabulary(sel.model_))
    outcome = split_selected(sel, data, words, labels) if split else SplitOutcome()
    return outcome.lines(said_merges(sel.model_))


def register(app: typer.Typer) -> None:
    """Add the learning commands to ``app``."""
    app.command()(learn)
    from spcotmhp.commands.learning_eval import evaluate_learning

    app.command("evaluate-learning")(evaluate_learning)
