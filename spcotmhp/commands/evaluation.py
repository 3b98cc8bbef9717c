"""CLI commands of the evaluation area: ``spcotmhp evaluate`` (Experiment I on any homes) and
``spcotmhp reproduce`` (Tables 4 and 5 on the bundled SIGVerse homes, the paper's rows beside ours)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from typer.core import TyperCommand

from spcotmhp.errors import SpcotmhpError
from spcotmhp.limits import MAX_HOMES, MAX_JOBS, MAX_SEEDS
from spcotmhp.safe_write import atomic_write_text, check_output

if TYPE_CHECKING:
    from spcotmhp.evaluation.tasks import TaskKind

METHOD_NAMES = (
    "spcotmhp,astar,spconavi-viterbi,spconavi-astar,hpp1,hpp2,hpp1-smoothed,hpp2-smoothed,"
    "spcotmhp-unsmoothed,spcotmhp-ma,spcotmhp-paper,spcotmhp-paper-ma"
)


class _OptionalRayAddress(TyperCommand):
    """Lets ``--ray`` take an optional value: a bare ``--ray`` (last, or followed by another option) means a local
    Ray instance; ``--ray ADDRESS`` joins a cluster (click supports optional values, Typer does not expose it)."""

    def parse_args(self, ctx, args):
        out = []
        for i, arg in enumerate(args):
            out.append(arg)
            if arg == "--ray" and (i + 1 == len(args) or args[i + 1].startswith("-")):
                out.append("local")
        return super().parse_args(ctx, out)


def load_home(name_or_path: str, lang: str):
    """A dataset folder, or a bundled dataset by name; its dataset warnings as a count and the first few."""
    from spcotmhp.commands.datasets import load_dataset_reporting

    return load_dataset_reporting(name_or_path, lang)


def _check(value: str, allowed: tuple[str, ...], option: str) -> str:
    if value not in allowed:
        raise SpcotmhpError(f"{option} must be one of {', '.join(allowed)}, got {value!r}")
    return value


def check_writable(path: Path) -> None:
    """Fail before a long run when ``path`` cannot be written: its folder must exist and be writable, and the path
    must not be a folder."""
    import os

    folder = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise SpcotmhpError(f"--out {path} is a folder; give a file name such as {path / 'tables.md'}")
    if not folder.is_dir():
        raise SpcotmhpError(f"--out {path}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise SpcotmhpError(f"--out {path}: not writable")


def _print_result(result: dict) -> None:
    from spcotmhp.commands.conventions import plain_table
    from spcotmhp.evaluation.tables import COLUMNS, METHOD_LABELS, fmt_time, success_rule

    keys = [k for k, _ in COLUMNS[result["task"]]]
    heads = [h for _, h in COLUMNS[result["task"]]]
    blocks = list(result["homes"].items()) + ([("all homes", result["mean"])] if len(result["homes"]) > 1 else [])
    for home, metrics in blocks:
        rows = [
            [
                METHOD_LABELS.get(method, method),
                *[_with_interval(m, k) for k in keys],
                _with_interval(m, "success"),
                " / ".join(f"{m[f'strict_{k}']:.3f}" for k in [*keys, "success"]),
                fmt_time(m["time_median_s"]),
                fmt_time(m["time_p95_s"]),
                m["n_tasks"],
            ]
            for method, m in metrics.items()
        ]
        typer.echo(
            plain_table(
                ["Method"]
                + heads
                + ["Success", "Strict: " + " / ".join([*heads, "Success"])]
                + ["Time median", "Time p95", "Tasks"],
                rows,
                title=f"{home}: {result['task']} tasks, {result['params']} parameters",
            )
            + "\n"
        )
    typer.echo(success_rule(spread=False) + " [low, high]: 95% bootstrap interval over tasks.")
    for home, note in result["notes"].items():
        extra = f"; {len(note['dropped'])} task(s) dropped (unreachable)" if note.get("dropped") else ""
        if note.get("no_safe_path"):
            extra += f"; {len(note['no_safe_path'])} task(s) set apart (no footprint-safe path)"
        for scores in note.get("vs_truth") or []:
            extra += f"; learned vs truth: ARI places {scores['ari_i']:.3f}, concepts {scores['ari_c']:.3f}"
        typer.echo(f"{home}: place adjacency: {note['adjacency']}; precompute {fmt_time(note['precompute_s'])}{extra}")
    if result.get("moves"):
        moves = "; ".join(f"{METHOD_LABELS.get(m, m)} {v}" for m, v in result["moves"].items())
        typer.echo(f"moves: {moves}; SPL's reference length l is an 8-connected geodesic")


def _with_interval(metrics: dict, key: str) -> str:
    ci = metrics.get(f"{key}_ci")
    return f"{metrics[key]:.3f}" + ("" if ci is None else f" [{ci[0]:.3f}, {ci[1]:.3f}]")


def register(app: typer.Typer) -> None:
    """Add ``evaluate``, ``reproduce`` and ``battery`` to ``app``."""

    # long: a CLI command: 40 lines of typer options and help, a 27-line body
    @app.command()
    def battery(
        datasets: Annotated[
            list[str] | None,
            typer.Argument(
                metavar="[DATASET_DIR]...",
                help="Run on these dataset folders or bundled homes instead of "
                "generated ones (e.g. 3LDK_01 3LDK_05 3LDK_06).",
            ),
        ] = None,
        homes: Annotated[int, typer.Option("--homes", min=1, max=MAX_HOMES, help="Number of seeded homes.")] = 50,
        first_seed: Annotated[int, typer.Option("--first-seed", min=0, help="Seed of the first home.")] = 0,
        params: Annotated[
            str, typer.Option("--params", help="Comma-separated: supervised, learned.")
        ] = "supervised,learned",
        max_tasks: Annotated[
            int, typer.Option("--max-tasks", min=1, help="Advanced tasks per home (a seeded subset).")
        ] = 60,
        workers: Annotated[
            int | None, typer.Option("--workers", min=1, max=MAX_JOBS, help="Processes (default: all cores).")
        ] = None,
        as_json: Annotated[bool, typer.Option("--json", help="Print JSON (every home).")] = False,
        furniture: Annotated[
            bool,
            typer.Option(
                "--furniture", help="Furnish the generated homes (seating groups that cut islands out of rooms)."
            ),
        ] = False,
    ) -> None:
        """The planner's acceptance battery on seeded synthetic homes (three bedrooms, west/east corridor,
        narrow doors, a room taught partly in unknown space; with --furniture, islands cut off by furniture):
        refusals although a path exists, plans touching walls, the closest instance of a shared name, SPL
        family, places refused while their 2-sigma ellipse is within reach."""
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        from spcotmhp.evaluation.battery import markdown, run_battery, summary
        from spcotmhp.evaluation.runner import default_workers

        kinds = [p.strip() for p in params.split(",") if p.strip()]
        for p in kinds:
            _check(p, ("supervised", "learned"), "--params")
        if furniture and datasets:
            raise SpcotmhpError("--furniture furnishes the generated homes; give it without dataset folders")
        chosen = [load_home(d, "en") for d in datasets] if datasets else range(first_seed, first_seed + homes)
        with Progress(
            TextColumn("{task.description}"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            transient=True,
            disable=as_json,
        ) as bar:
            job = bar.add_task("battery", total=len(chosen) * len(kinds))
            results = run_battery(
                chosen,
                kinds,
                max_tasks,
                workers or default_workers(),
                lambda label: bar.update(job, advance=1, description=label),
                furniture=furniture,
            )
        if as_json:
            typer.echo(json.dumps({"summary": summary(results), "homes": [r.to_dict() for r in results]}, indent=2))
            return
        typer.echo(markdown(results))
        for r in results:
            for e in r.errors:
                typer.echo(f"refused: {e}")

    # long: a CLI command: 49 lines of typer options and help, a 26-line body
    @app.command(cls=_OptionalRayAddress)
    def evaluate(
        datasets: Annotated[
            list[str],
            typer.Argument(metavar="DATASET_DIR...", help="Dataset folders or bundled dataset names (e.g. 3LDK_01)."),
        ],
        task: Annotated[str, typer.Option("--task", help="basic | advanced (with a waypoint).")] = "basic",
        method: Annotated[str, typer.Option("--method", help="Comma-separated methods.")] = METHOD_NAMES,
        params: Annotated[
            str,
            typer.Option("--params", help="supervised (truth labels, the paper's 'ideal' parameters) | learned."),
        ] = "supervised",
        lang: Annotated[str, typer.Option("--lang", help="Language of the words: en | ja.")] = "en",
        workers: Annotated[
            int | None, typer.Option("--workers", min=1, max=MAX_JOBS, help="Processes (default: all cores).")
        ] = None,
        max_tasks: Annotated[
            int | None,
            typer.Option("--max-tasks", min=1, help="A seeded random subset of each home's tasks."),
        ] = None,
        seed: Annotated[int, typer.Option("--seed", min=0, help="First seed of the random draws (and learning).")] = 0,
        seeds: Annotated[
            int,
            typer.Option(
                "--seeds",
                min=1,
                max=MAX_SEEDS,
                help=(
                    "Seeds (seed, seed + 1, ...): metrics are mean ± sd over them; learned parameters are learned "
                    "again "
                    "for each."
                ),
            ),
        ] = 5,
        connectivity: Annotated[
            str,
            typer.Option(
                "--connectivity",
                help=("Where learned psi comes from: auto (walk, else map), hmm, walk or map."),
            ),
        ] = "auto",
        model: Annotated[
            Path | None,
            typer.Option(
                "--model",
                metavar="MODEL_DIR",
                help=(
                    "Evaluate this model folder (learned, taught or questioned) as it is, on the one DATASET_DIR "
                    "it was made on, instead of fitting parameters (--params is then ignored)."
                ),
            ),
        ] = None,
        as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
        ray: Annotated[
            str | None,
            typer.Option(
                "--ray",
                metavar="[ADDRESS]",
                help="Run on Ray (extra 'dist'): a local instance, or the cluster at ADDRESS.",
            ),
        ] = None,
    ) -> None:
        """Experiment I: plan every task of each home with each method and report SPL, N-SPL (and W-SPL, WN-SPL
        for advanced tasks), success and online planning time, mean ± sd over seeds, with a 95% bootstrap interval
        over tasks, under the footprint success rule and the paper's strict one."""
        from spcotmhp.evaluation.context import CONNECTIVITY
        from spcotmhp.evaluation.runner import evaluate as run

        _check(task, ("basic", "advanced"), "--task")
        _check(connectivity, CONNECTIVITY, "--connectivity")
        _check(params, ("supervised", "learned"), "--params")
        _check(lang, ("en", "ja"), "--lang")
        if model is not None and len(datasets) != 1:
            raise SpcotmhpError(
                f"--model evaluates one model on the one dataset it was made on; got {len(datasets)} datasets"
            )
        given = None
        if model is not None:
            from spcotmhp.persistence.io import load_model

            given = load_model(model)
        homes = [load_home(d, lang) for d in datasets]
        kind: TaskKind = "advanced" if task == "advanced" else "basic"
        result = run(
            homes,
            kind,
            method.split(","),
            params,
            seed,
            workers,
            max_tasks,
            "ray" if ray else "local",
            ray,
            seeds=seeds,
            connectivity=connectivity,
            model=given,
        )
        if given is not None:
            result["model"] = str(model)
        if as_json:
            typer.echo(json.dumps(result, indent=2, ensure_ascii=False))
        else:
            _print_result(result)

    @app.command()
    def reproduce(
        out: Annotated[Path | None, typer.Option("--out", help="Write the markdown here (default: stdout).")] = None,
        seeds: Annotated[
            int,
            typer.Option(
                "--seeds", min=1, max=MAX_SEEDS, help=("Seeds of Table 6 and of Tables 4-5 with supervised parameters.")
            ),
        ] = 5,
        learned_seeds: Annotated[
            int,
            typer.Option(
                "--learned-seeds",
                min=1,
                max=MAX_SEEDS,
                help=("Seeds of the tables with learned parameters (each learns again)."),
            ),
        ] = 3,
        workers: Annotated[
            int | None, typer.Option("--workers", min=1, max=MAX_JOBS, help="Processes (default: all cores).")
        ] = None,
        max_tasks: Annotated[
            int | None,
            typer.Option("--max-tasks", min=1, help="A seeded random subset of each home's tasks."),
        ] = None,
        overwrite: Annotated[bool, typer.Option("--overwrite", help="Replace the --out file if it exists.")] = False,
        quick: Annotated[
            bool,
            typer.Option(
                "--quick",
                help=(
                    "2 seeds, 30 tasks per home, few benchmark queries: a first look in a few minutes (the README's "
                    "figures come from the full run)."
                ),
            ),
        ] = False,
    ) -> None:
        """Every results table of the README (Table 6, Tables 4 and 5 with supervised and learned parameters,
        planning with the HMM's psi, the planning and scale benchmarks) as one markdown document with the
        paper's rows beside ours, mean ± sd over seeds; prints the total run time."""
        from spcotmhp.evaluation.reproduce import Plan
        from spcotmhp.evaluation.reproduce import reproduce as run_all

        if out is not None:
            check_writable(out)
            check_output(out, overwrite)
        plan = (
            Plan.quick(workers)
            if quick
            else Plan(seeds=seeds, learned_seeds=learned_seeds, max_tasks=max_tasks, workers=workers)
        )
        if max_tasks is not None:
            plan = Plan(**{**plan.__dict__, "max_tasks": max_tasks, "albert_tasks": max_tasks})
        text = run_all(plan, lambda what: typer.echo(f"reproduce: {what}", err=True))
        typer.echo(text.strip().splitlines()[-1], err=True)
        if out is None:
            typer.echo(text)
        else:
            atomic_write_text(out, text)
            typer.echo(f"wrote {out}", err=True)
