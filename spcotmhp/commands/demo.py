"""CLI commands of the demo area: ``spcotmhp demo`` (learn a bundled home, plan an instruction, draw it),
``spcotmhp show MODEL_DIR`` (list a learned model's places; ``--png`` draws the learned map) and ``spcotmhp
warmup`` (compile every kernel into numba's cache, :mod:`spcotmhp.warmup`)."""

from __future__ import annotations

import json
import time
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from spcotmhp.commands.service import DEFAULT_PORT
from spcotmhp.errors import InstructionError, PlanningError, SpcotmhpError
from spcotmhp.limits import MAX_ITERATIONS, MAX_RUNS
from spcotmhp.safe_write import atomic_write, atomic_write_text, check_output, outside_model

DEMO_INSTRUCTION = "go to the bedroom via the corridor"


@dataclass
class DemoModel:
    """The model the demo plans with, how it was obtained and why."""

    model: Any
    method: str
    reason: str


@contextmanager
def _progress() -> Iterator[Any]:
    """A rich progress display on stderr (spinner, bar, count, elapsed time)."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
    )

    with Progress(
        SpinnerColumn(),
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
    ) as bar:
        yield bar


@contextmanager
def _step(bar: Any, label: str) -> Iterator[None]:
    task = bar.add_task(label, total=1)
    yield
    bar.update(task, completed=1)


def learn_demo_model(
    dataset: Any,
    instruction: str,
    seed: int,
    runs: int,
    iterations: int,
    bar: Any,
    supervised: bool = False,
    cache: Any = None,
) -> DemoModel:
    """The unsupervised SpCoTMHP learner (``runs`` Gibbs runs, the one with the highest word-concept mutual
    information kept), accepted when its map names every place name of the home and the instruction can be
    planned on it; otherwise (or with ``supervised``) the supervised fit from the truth labels. The check plan's
    graph goes into ``cache`` (a :class:`~spcotmhp.planning.graph_cache.GraphCache`), for the demo's planner."""
    from spcotmhp.learning.gibbs import SpCoTMHP
    from spcotmhp.learning.selection import MultiRunSelector
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.viz.labels import place_display_labels

    if supervised:
        return DemoModel(fit_supervised(dataset), "supervised fit (truth labels)", "asked for with --supervised")
    task = bar.add_task(f"learning {dataset.name}", total=runs * iterations)
    sel = MultiRunSelector(SpCoTMHP(iterations=iterations, seed=seed), runs=runs).fit(
        dataset, progress=lambda n: bar.advance(task, n)
    )
    model = sel.model_
    method = (
        f"unsupervised SpCoTMHP (Gibbs sampling, {runs} runs x {iterations} sweeps, seed {seed}; "
        f"run {sel.best_index_} kept by {sel.criterion_.replace('_', ' ')})"
    )
    labels = [lab.split(" #")[0] for lab in place_display_labels(model) if lab]
    missing = sorted(set(dataset.place_names or ()) - set(labels))
    why = f"the unsupervised map lacks the place name(s) {', '.join(missing)}" if missing else None
    if why is None:
        try:
            from spcotmhp.planning.planner import HierarchicalPlanner

            HierarchicalPlanner(model, cache=cache).plan(instruction, model.mu[np.flatnonzero(model.active_places)[0]])
        except InstructionError as exc:
            why = f"the instruction cannot be understood on the unsupervised map ({exc})"
        except PlanningError:
            pass  # the start used for this check may be a wall; the real start is chosen later
    if why is None:
        n_names = len(set(labels))
        return DemoModel(model, method, f"its {len(labels)} places carry all {n_names} place names of the home")
    return DemoModel(fit_supervised(dataset), "supervised fit (truth labels)", why)


def demo_start(planner: Any, place: str | None = None) -> tuple[np.ndarray, str]:
    """The free cell nearest to the mean of the first place labelled ``place``, in the main free component of
    the planning grid; returns (x, y) and the place's label. ``place`` None: the entrance if the map has one,
    else the first active place.

    Raises:
        InstructionError: no place is labelled ``place`` (the message lists the place names).
    """
    from spcotmhp.metric.snap import largest_component, snap
    from spcotmhp.viz.labels import place_display_labels

    model, graph = planner.model, planner.graph
    labels = place_display_labels(model)
    act = np.flatnonzero(model.active_places)
    names = [labels[k].split(" #")[0] for k in act]
    if place is not None and place not in names:
        raise InstructionError(
            f"--start-place {place!r} names no place of the learned map; its places: {', '.join(sorted(set(names)))}"
        )
    wanted = place if place is not None else "entrance"
    k = int(act[names.index(wanted)] if wanted in names else act[0])
    cell = snap(largest_component(graph.traversable), graph.to_crop(model.require_map().world_to_cell(model.mu[k])))
    return model.require_map().cell_to_world(graph.to_map(cell)), labels[k]


# long: a CLI command: 29 lines of typer options and help, a 54-line body of steps
def demo(
    out: Annotated[Path, typer.Option("--out", help="Folder for the picture, plan and model.")] = Path("demo-output"),
    home: Annotated[
        str, typer.Option(help="Bundled home (3LDK_01, 3LDK_05, 3LDK_06) or a dataset folder.")
    ] = "3LDK_06",
    instruction: Annotated[str, typer.Option(help="The instruction to plan.")] = DEMO_INSTRUCTION,
    lang: Annotated[str, typer.Option(help="Language of the teaching words and the instruction (en, ja).")] = "en",
    start: Annotated[
        tuple[float, float] | None,
        typer.Option(
            metavar="X Y",
            help="Start pose X Y in metres (default: the free cell nearest the start place's mean).",
        ),
    ] = None,
    start_place: Annotated[
        str | None,
        typer.Option(
            help="Place to start from when --start is not given (default: the entrance, else the first place)."
        ),
    ] = None,
    seed: Annotated[int, typer.Option(min=0, help="Random seed of the learner.")] = 0,
    runs: Annotated[int, typer.Option(min=1, max=MAX_RUNS, help="Independent Gibbs runs (one is kept).")] = 10,
    iterations: Annotated[int, typer.Option(min=1, max=MAX_ITERATIONS, help="Gibbs sweeps per run.")] = 100,
    supervised: Annotated[bool, typer.Option(help="Skip the unsupervised learner: fit from the truth labels.")] = False,
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="Replace the outputs of an earlier demo in --out.")
    ] = False,
) -> None:
    """Learn a bundled home's map, plan "go to the bedroom via the corridor", print the explanation, draw it."""
    from spcotmhp.commands.datasets import load_dataset_arg
    from spcotmhp.persistence.io import check_target, save_model
    from spcotmhp.planning.graph_cache import GraphCache
    from spcotmhp.planning.planner import HierarchicalPlanner
    from spcotmhp.viz.draw import render
    from spcotmhp.viz.plan import draw_plan

    held = next((p for p in (out.resolve(), *out.resolve().parents) if (p / "model.json").is_file()), None)
    if held is not None:  # teach refuses a model folder holding other files (it replaces the folder whole)
        raise SpcotmhpError(
            f"--out {out} is in the model folder {held}, which must hold only the model; write elsewhere"
        )
    if out.is_dir():  # the outputs of an earlier demo are replaced only with --overwrite
        for name in ("plan.png", "map.png", "plan.json"):
            check_output(out / name, overwrite, (), SpcotmhpError, "--out")
        check_target(out / "model", overwrite)
    t0 = time.perf_counter()
    with _progress() as bar:
        with _step(bar, f"loading {home}"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = load_dataset_arg(home, lang)
        cache = GraphCache()  # the check plan's graph, reused by the planner below
        chosen = learn_demo_model(data, instruction, seed, runs, iterations, bar, supervised, cache)
        model = chosen.model
        with _step(bar, "precomputing the planner"):
            planner = HierarchicalPlanner(model, cache=cache)
        if start is None:
            x0, start_label = demo_start(planner, start_place)
        else:
            x0, start_label = np.asarray(start, dtype=float), "given"
        with _step(bar, "planning"):
            plan = planner.plan(instruction, x0, lang=lang)
        with _step(bar, "drawing"):
            try:
                out.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise SpcotmhpError(f"cannot write the demo output to {out}: {exc.strerror or exc}") from None
            model_dir = save_model(model, out / "model", overwrite=overwrite)
            plan_png = atomic_write(out / "plan.png", lambda tmp: draw_plan(plan, model, tmp))
            map_png = atomic_write(
                out / "map.png",
                lambda tmp: render(
                    model.map, tmp, model=model, title=f"learned map of {data.name}: places, names and edges"
                ),
            )
            atomic_write_text(out / "plan.json", plan.to_json(indent=1))
    n_places = int(model.active_places.sum())
    typer.echo(f"home:        {data.name} ({len(data.positions)} teaching utterances, lang {data.lang})")
    typer.echo(f"model:       {chosen.method}, {n_places} places: {chosen.reason}")
    typer.echo(f"instruction: {instruction!r}")
    typer.echo(f"start:       ({x0[0]:.2f}, {x0[1]:.2f}) ({start_label})")
    typer.echo(f"plan:        {plan.explanation}")
    typer.echo(
        f"timing:      precomputation {plan.time_precompute_s:.2f} s, planning "
        f"{plan.time_online_s * 1e3:.1f} ms, demo {time.perf_counter() - t0:.1f} s in all"
    )
    typer.echo(
        f"wrote:       {plan_png} (the plan), {map_png} (the learned map), {out / 'plan.json'}, "
        f"{model_dir}/ (the model)"
    )
    typer.echo(f"next:        {next_command(model_dir)}")


def serve_port(preferred: int = DEFAULT_PORT) -> int:
    """The port the demo's hint names: ``preferred`` (the service's default) when it can be bound now, else a
    port the system says is free, so the hint runs as typed where something already listens on 8000."""
    import socket

    with socket.socket() as sock:
        try:
            sock.bind(("127.0.0.1", preferred))
        except OSError:
            sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def next_command(model_dir: Path, preferred: int = DEFAULT_PORT) -> str:
    """The demo's hint, runnable as typed from here: serve the model on a port that is free now (with the
    install of the extra 'server' first when it is missing) and open the page."""
    import importlib.util

    from spcotmhp.extras import command_prefix, install_hint

    port = serve_port(preferred)
    option = "" if port == DEFAULT_PORT else f" --port {port}"
    serve = f"{command_prefix()} serve {model_dir}{option}   # then open http://127.0.0.1:{port}/"
    if importlib.util.find_spec("uvicorn") is None or importlib.util.find_spec("fastapi") is None:
        return f"{install_hint('server')} && {serve}"
    return serve


# long: a CLI command: its options, then one listing of places and edges (text, JSON or a picture)
def show(
    model_dir: Annotated[Path, typer.Argument(help="Model folder (as written by `spcotmhp learn`).")],
    png: Annotated[Path | None, typer.Option("--png", help="Draw the learned map to this PNG file.")] = None,
    ids: Annotated[bool, typer.Option("--ids", help="Add the place ids to the labels in the picture.")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print the places and edges as JSON.")] = False,
    overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace an existing --png file.")] = False,
) -> None:
    """List a learned model's places (label, mean, spread) and topological edges; --png draws the map."""
    from spcotmhp.persistence.io import load_model
    from spcotmhp.viz.labels import place_display_labels

    if png is not None:
        from spcotmhp.commands.planning import input_files

        check_output(png, overwrite, input_files(model_dir), SpcotmhpError, "--png")
        outside_model(png, model_dir, "--png")
    model = load_model(model_dir)
    labels = place_display_labels(model)
    edges = _edges(model)
    act = [int(k) for k in np.flatnonzero(model.active_places)]
    if png is not None:
        if model.map is None:
            raise SpcotmhpError(f"{model_dir}: the model has no map to draw")
        from spcotmhp.viz.draw import render

        atomic_write(
            png,
            lambda tmp: render(
                model.require_map(),
                tmp,
                model=model,
                names=place_display_labels(model, ids=ids),
                title=f"learned map ({model_dir}): {len(act)} places",
            ),
        )
    from spcotmhp.learning.merges import merge_lines
    from spcotmhp.teaching.questions import said_merges

    merged = said_merges(model)
    if as_json:
        places = [
            {
                "id": k,
                "label": labels[k],
                "mean": model.mu[k].round(4).tolist(),
                "covariance": model.Sigma[k].round(6).tolist(),
            }
            for k in act
        ]
        found = [m.as_dict() for m in merged]
        typer.echo(json.dumps({"places": places, "edges": edges, "merges": found}, ensure_ascii=False))
        return
    typer.echo(f"{len(act)} places, {len(edges)} edges ((psi_ab + psi_ba) / 2 >= 1/K = {1 / model.K:.3f})")
    if model.psi_learned is not None and not np.allclose(model.psi_learned, model.psi):
        typer.echo(
            f"note: the edges come from psi of {model.info.get('psi_from', 'an adjacency')}; the "
            "transitions the HMM learned are kept as psi_learned in arrays.npz"
        )
    for k in act:
        sd = np.sqrt(np.linalg.eigvalsh(model.Sigma[k]))
        nbrs = ", ".join(labels[b if a == k else a] for a, b in edges if k in (a, b))
        typer.echo(
            f"{k:3d}  {labels[k]:<16} mean ({model.mu[k][0]:6.2f}, {model.mu[k][1]:6.2f})  "
            f"sd {sd[1]:.2f} x {sd[0]:.2f} m  -> {nbrs or '(no edge)'}"
        )
    for line in merge_lines(merged):
        typer.echo(line)
    if png is not None:
        typer.echo(f"wrote {png}")


def _edges(model: Any) -> list[list[int]]:
    from spcotmhp.viz.draw import topological_edges

    return [[a, b] for a, b in topological_edges(model)]


def warmup() -> None:
    """Compile every numba kernel into numba's on-disk cache (once per install; ``make demo`` runs it), so that
    later commands and processes start without compiling."""
    from spcotmhp.warmup import warm_up

    seconds = warm_up()
    typer.echo(f"compiled kernels cached in {seconds:.1f} s")


def register(app: typer.Typer) -> None:
    """Add the demo commands to ``app``."""
    app.command()(demo)
    app.command()(show)
    app.command()(warmup)
