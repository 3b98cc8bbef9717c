"""CLI command of the planning area: ``spcotmhp plan MODEL_DIR "go to the bedroom via the corridor" --start X Y``."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Annotated, Any

import typer

from spcotmhp.collector import end_startup
from spcotmhp.commands import body_options as bo
from spcotmhp.errors import InstructionError, SpcotmhpError
from spcotmhp.limits import MAX_CANDIDATES, MAX_STEPS
from spcotmhp.safe_read import excerpt, parse_json
from spcotmhp.safe_write import atomic_write, check_output, outside_model

MAX_NBEST_BYTES = 256 * 1024


def register(app: typer.Typer) -> None:
    """Add the planning commands to ``app``."""
    app.command("plan")(plan_command)
    app.command("precompute")(precompute_command)


# long: a CLI command: 45 lines of typer options and help, a 34-line body
def plan_command(
    model_dir: Annotated[Path, typer.Argument(help="Model folder (as written by `spcotmhp learn`).")],
    start: Annotated[
        tuple[float, float],
        typer.Option("--start", metavar="X Y", help="Start pose in metres (map frame), e.g. --start -3.9 -3.5."),
    ],
    instruction: Annotated[
        str | None,
        typer.Argument(
            help='The instruction, e.g. "go to the bedroom via the corridor" or "廊下を通って寝室へ行って", or a JSON '
            'object {"goal": [...], "waypoints": [[...]], "avoid": [[...]]}. Omit it with --nbest or --audio.'
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print the plan as JSON.")] = False,
    png: Annotated[Path | None, typer.Option("--png", help="Also draw the plan to this PNG file.")] = None,
    nbest: Annotated[
        Path | None,
        typer.Option("--nbest", help='JSON file with recogniser hypotheses [["text", score], ...] (Eq. 25).'),
    ] = None,
    audio: Annotated[
        Path | None,
        typer.Option(
            "--audio",
            help="WAV file of a spoken English instruction: recognised with pocketsphinx (extra 'speech'), "
            "planned from its 5-best hypotheses (Eq. 25).",
        ),
    ] = None,
    lang: Annotated[str | None, typer.Option(help="Instruction language (en, ja); default: detected.")] = None,
    candidates: Annotated[
        int, typer.Option(min=1, max=MAX_CANDIDATES, help="Candidate points per place (N of Section 3.4).")
    ] = 1,
    seed: Annotated[int, typer.Option(min=0, help="Seed of the candidate sampling.")] = 0,
    smooth: Annotated[
        bool,
        typer.Option(
            help=(
                "Smooth the path (Algorithm 1 line 13): exact re-planning between the waypoint and goal points within "
                "the places passed, then line-of-sight shortcuts; never longer."
            )
        ),
    ] = True,
    max_steps: Annotated[
        int | None, typer.Option(min=1, max=MAX_STEPS, help="Topological horizon E (default 10 per waypoint/goal).")
    ] = None,
    overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace an existing --png file.")] = False,
    floor: Annotated[
        str | None,
        typer.Option(
            "--floor",
            metavar="F",
            help="A building's model: the start's floor (its index or name); --start is in that floor's map frame, "
            "--png writes one picture per floor crossed (NAME-floorF.png) and --json adds segments per floor.",
        ),
    ] = None,
    nav2_params: bo.Nav2Params = None,
    robot_radius: bo.RobotRadius = None,
    footprint: bo.Footprint = None,
    inflation_radius: bo.InflationRadius = None,
    cost_scaling_factor: bo.CostScaling = None,
) -> None:
    """Plan a path from an instruction with SpCoTMHP (Algorithm 1): waypoints in order, the closest goal."""
    from spcotmhp.persistence.io import load_model
    from spcotmhp.planning.planner import HierarchicalPlanner

    given = [
        name
        for name, value in (("INSTRUCTION", instruction), ("--nbest", nbest), ("--audio", audio))
        if value is not None
    ]
    if len(given) != 1:
        raise typer.BadParameter(
            "give exactly one of INSTRUCTION, --nbest FILE or --audio FILE"
            + (f" (got {' and '.join(given)})" if given else "")
        )
    if png is not None:
        check_output(png, overwrite, input_files(model_dir, nbest, audio), SpcotmhpError, "--png")
        outside_model(png, model_dir, "--png")
    source: Any = instruction if nbest is None else read_nbest(nbest)
    settings: dict[str, Any] = {"n_candidates": candidates, "seed": seed, "smooth": smooth, "max_steps": max_steps}
    body = bo.body_from_options(nav2_params, robot_radius, footprint, inflation_radius, cost_scaling_factor)
    if plan_in_building(model_dir, floor):
        from spcotmhp.commands.building import plan_building

        recognise = None if audio is None else functools.partial(recognise_audio, audio)
        plan_building(model_dir, source, start, floor, recognise=recognise, as_json=as_json, png=png,
                      overwrite=overwrite, lang=lang, settings=settings, body=body)  # fmt: skip
        return
    from spcotmhp.planning.body import with_body

    model = with_body(load_model(model_dir), body)  # another body: its cost map and graph from the stored map
    if audio is not None:
        source = recognise_audio(audio, model)
    planner = HierarchicalPlanner(model, **settings)
    plan = planner.plan(source, start, lang=lang)
    # the first plan of a process loads the compiled kernels: the text output says so, and what the same plan
    # takes warm (planned again, still with the collector paused)
    warm = None if as_json else planner.plan(source, start, lang=lang).time_online_s
    end_startup()
    if png is not None:
        from spcotmhp.viz.plan import draw_plan

        atomic_write(png, lambda tmp: draw_plan(plan, model, tmp), SpcotmhpError)
    if as_json:
        typer.echo(plan.to_json())
    else:
        typer.echo(plan.explanation)
        assert warm is not None  # planned again above for the text output
        loaded = planner.graph.info.get("load_s")
        setup = f"precomputation {plan.time_precompute_s:.2f} s" + (
            f", loaded from the model folder in {loaded:.2f} s" if loaded is not None else ""
        )
        typer.echo(
            f"log p = {plan.log_prob:.2f}; planned in {warm * 1e3:.2f} ms warm (the first plan of this process took "
            f"{plan.time_online_s * 1e3:.0f} ms: it loads the compiled kernels; {setup})",
            err=True,
        )
    graph_note(planner.graph.info)  # after the plan: a refused plan's stderr is its one error line


def graph_note(info: dict) -> None:
    """Say on stderr when the planning graph was built rather than loaded from the model folder, and how to save
    it (:mod:`spcotmhp.planning.graph_store`)."""
    source = str(info.get("graph_source", ""))
    if source and not source.startswith("loaded"):
        typer.echo(f"planning graph {source}", err=True)


def precompute_command(
    model_dir: Annotated[Path, typer.Argument(help="Model folder (as written by `spcotmhp learn`).")],
    candidates: Annotated[
        int, typer.Option(min=1, max=MAX_CANDIDATES, help="Candidate points per place (N of Section 3.4).")
    ] = 1,
    seed: Annotated[int, typer.Option(min=0, help="Seed of the candidate sampling.")] = 0,
    overwrite: Annotated[
        bool, typer.Option("--overwrite", help="Replace a planning graph already saved in the folder.")
    ] = False,
) -> None:
    """Precompute the planning graph (Algorithm 1, lines 1-7) and save it in the model folder, so that `plan`,
    `serve`, `ros2` and the library load it instead of building it (spcotmhp/planning/graph_store.py).

    The folder is rewritten whole and atomically with its files unchanged and graph.json + graph.npz added; a
    graph already there (made for other settings, or stale) is replaced only with --overwrite. `learn` saves the
    graph of the default settings with the model; `plan` with other --candidates / --seed builds its own."""
    import time

    from spcotmhp.persistence.io import load_model
    from spcotmhp.planning.graph import PlanningGraph
    from spcotmhp.planning.graph_settings import GraphSettings
    from spcotmhp.planning.graph_store import GRAPH_FILES, save_graph

    if plan_in_building(model_dir, None):
        raise SpcotmhpError(f"{model_dir} holds a building's model; precompute takes the model of one map")
    model = load_model(model_dir)
    t0 = time.perf_counter()
    graph = PlanningGraph.build(model, GraphSettings(n_candidates=candidates, seed=seed))
    if str(graph.info.get("graph_source", "")).startswith("loaded"):
        typer.echo(f"{model_dir}: the planning graph saved there is up to date ({', '.join(GRAPH_FILES)})")
        return
    built = time.perf_counter() - t0
    save_graph(model_dir, graph, overwrite=overwrite)
    typer.echo(
        f"planning graph of {model_dir} precomputed in {built:.1f} s ({graph.n_nodes} nodes"
        + (f", {len(graph.regions)} other free regions" if graph.regions else "")
        + f") and saved ({', '.join(GRAPH_FILES)})"
    )


def plan_in_building(model_dir: Path, floor: str | None) -> bool:
    """Whether ``plan`` takes its building branch: the folder holds a building's model; ``--floor`` with any other
    model is refused."""
    from spcotmhp.building.io import is_building_model

    if is_building_model(model_dir):
        return True
    if floor is not None:
        raise typer.BadParameter(
            f"--floor is for a building's model (learned from a building folder); {model_dir} is not one"
        )
    return False


def input_files(model_dir: Path, *files: Path | None) -> list[Path]:
    """The files a command reads: every file of the model folder, and the other files given (an output must
    not be one of them: ``plan --png m/model.json`` would destroy the model)."""
    inputs = [f for f in files if f is not None]
    if Path(model_dir).is_dir():
        inputs += [p for p in Path(model_dir).iterdir() if p.is_file()]
    return inputs


def recognise_audio(path: Path, model: Any) -> list[tuple[str, float]]:
    """The 5-best hypotheses of a WAV file (:func:`spcotmhp.speech.recognise_for_model`), listed on stderr."""
    from spcotmhp.speech import recognise_for_model

    if not Path(path).is_file():
        raise InstructionError(f"the audio file {path} does not exist or is not a file")
    hypotheses = recognise_for_model(path, model, nbest=5)
    for text, weight in hypotheses:
        typer.echo(f"heard: {weight:.3f} {text}", err=True)
    return hypotheses


def read_nbest(path: Path) -> list[tuple[str, float]]:
    """An N-best file: a JSON list of [text, score] pairs or {"text": ..., "score": ...} objects."""
    from spcotmhp.safe_read import read_text

    text = read_text(Path(path), MAX_NBEST_BYTES, "N-best file", InstructionError)
    data = parse_json(text, f"the N-best file {path}", InstructionError)
    if not isinstance(data, list):
        raise InstructionError(f"the N-best file {path} must hold a JSON list of [text, score] pairs")
    out = []
    for i, item in enumerate(data):
        if isinstance(item, dict) and set(item) == {"text", "score"}:
            item = [item["text"], item["score"]]
        if not (isinstance(item, list) and len(item) == 2):
            raise InstructionError(
                f'{path}: entry {i} must be [text, score] or {{"text", "score"}}, got {excerpt(item)}'
            )
        out.append((item[0], item[1]))
    return out
