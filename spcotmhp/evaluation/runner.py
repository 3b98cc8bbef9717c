"""Experiment runner: every (task, method) of every home, in parallel, scored with the SPL family.

Per home, :func:`spcotmhp.evaluation.context.build_context` does the offline work once (parameters, cost map,
planning graph); the tasks are then cut into chunks and evaluated by a local process pool (all cores by
default) or by Ray (``backend="ray"``). Every random draw of a method uses its own generator seeded from
(seed, home, task, method), so results do not depend on the backend, the number of workers or the order in
which chunks finish. Only online planning is timed, inside the worker.
"""

from __future__ import annotations

import multiprocessing
import os
import time
import zlib
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field

import numpy as np
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from spcotmhp.errors import PlanningError
from spcotmhp.evaluation.context import HomeContext
from spcotmhp.evaluation.methods import METHODS, MOVE_MODELS, run_method
from spcotmhp.evaluation.metrics import Outcome, failed, score_path, summarise
from spcotmhp.evaluation.tasks import Task

CHUNK = 16  # tasks per work item: large enough to amortise IPC, small enough to balance two cores


@dataclass
class TaskRecord:
    """One method on one task: the outcome plus why it failed (planner error message), if it did."""

    task_index: int
    method: str
    outcome: Outcome
    error: str | None = None


@dataclass
class HomeResult:
    """All records of one home, with the context's notes (adjacency source, dropped tasks, precompute)."""

    home: str
    records: list[TaskRecord]
    notes: dict = field(default_factory=dict)

    def metrics(self) -> dict[str, dict]:
        """{method: summarise(outcomes)} in the order methods were given."""
        by_method: dict[str, list[Outcome]] = {}
        for r in self.records:
            by_method.setdefault(r.method, []).append(r.outcome)
        return {m: summarise(o) for m, o in by_method.items()}


def task_seed(seed: int, home: str, task_index: int, method: str) -> np.random.SeedSequence:
    """The seed of one method's draws on one task (independent of scheduling)."""
    return np.random.SeedSequence([seed, zlib.crc32(home.encode()), task_index, zlib.crc32(method.encode())])


def evaluate_chunk(ctx: HomeContext, tasks: Sequence[Task], methods: Sequence[str], seed: int) -> list[TaskRecord]:
    """Run each method on each task and score it (runs in a worker)."""
    out = []
    for task in tasks:
        goal_boxes = [ctx.places[k].box for k in task.goal_places]
        wp_boxes = [ctx.places[k].box for k in task.waypoint_places] if task.kind == "advanced" else None
        for method in methods:
            rng = np.random.default_rng(task_seed(seed, ctx.name, task.index, method))
            t0 = time.perf_counter()
            try:
                path, error = run_method(method, ctx, task, rng), None
            except PlanningError as exc:
                path, error = None, str(exc)
            elapsed = time.perf_counter() - t0
            if path is None or len(path) == 0:
                outcome = failed(task.l, elapsed, wp_boxes is not None)
                error = error or "no path"
            else:
                outcome = score_path(path, goal_boxes, task.closest_goal, task.l, elapsed, wp_boxes,
                                     step=ctx.dataset.map.resolution / 2)
            out.append(TaskRecord(task.index, method, outcome, error))
    return out


# ---- local process pool ---------------------------------------------------------------------------------
_WORKER_CTX: HomeContext | None = None


def _init_worker(ctx: HomeContext, task: Task, methods: Sequence[str]) -> None:
    global _WORKER_CTX
    _WORKER_CTX = ctx
    ctx.warmup(task, methods)


def _pool_chunk(tasks: Sequence[Task], methods: Sequence[str], seed: int) -> list[TaskRecord]:
    assert _WORKER_CTX is not None
    return evaluate_chunk(_WORKER_CTX, tasks, methods, seed)


def chunks(tasks: Sequence[Task], size: int = CHUNK) -> list[list[Task]]:
    return [list(tasks[i:i + size]) for i in range(0, len(tasks), size)]


def run_local(ctx: HomeContext, tasks: Sequence[Task], methods: Sequence[str], seed: int, workers: int,
              advance: Callable[[int], None]) -> list[TaskRecord]:
    """Evaluate on ``workers`` processes (in this process when 1); ``advance(n)`` after every chunk of n tasks."""
    parts = chunks(tasks)
    if not parts:
        return []
    if workers <= 1 or len(parts) <= 1:
        ctx.warmup(parts[0][0], methods)
        out = []
        for part in parts:
            out.extend(evaluate_chunk(ctx, part, methods, seed))
            advance(len(part))
        return out
    out = []
    # fork where the platform has it: workers inherit the loaded modules and compiled kernels (no re-import,
    # nothing read from disk again); spawn elsewhere. The kernels run no threads of their own.
    mp = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    with ProcessPoolExecutor(max_workers=min(workers, len(parts)), mp_context=mp,
                             initializer=_init_worker, initargs=(ctx, parts[0][0], list(methods))) as pool:
        futures = {pool.submit(_pool_chunk, part, list(methods), seed): len(part) for part in parts}
        for fut in as_completed(futures):
            out.extend(fut.result())
            advance(futures[fut])
    return out


# ---- driver -----------------------------------------------------------------------------------------------
def default_workers() -> int:
    """All cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def check_methods(methods: Iterable[str]) -> list[str]:
    """The method names, validated against :data:`~spcotmhp.evaluation.methods.METHODS`."""
    from spcotmhp.errors import SpcotmhpError

    names = [m.strip() for m in methods if m.strip()]
    bad = [m for m in names if m not in METHODS]
    if bad or not names:
        raise SpcotmhpError(f"unknown method(s) {', '.join(bad) or '(none given)'}; "
                            f"accepted: {', '.join(METHODS)}")
    return list(dict.fromkeys(names))


def progress_bar(quiet: bool = False) -> Progress:
    """A rich progress bar on stderr."""
    return Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                    TimeElapsedColumn(), console=Console(stderr=True), disable=quiet, transient=False)


def evaluate_home(ctx: HomeContext, tasks: Sequence[Task], methods: Sequence[str], seed: int = 0,
                  workers: int | None = None, backend: str = "local", ray_address: str | None = None,
                  progress: Progress | None = None) -> HomeResult:
    """All methods on the given tasks of one home."""
    methods = check_methods(methods)
    workers = default_workers() if workers is None else workers
    bar = progress.add_task(f"{ctx.name} {tasks[0].kind if tasks else ''}", total=len(tasks)) if progress else None

    def advance(n: int) -> None:
        if progress is not None:
            progress.advance(bar, n)

    if backend == "ray":
        from spcotmhp.evaluation.ray_backend import run_ray

        records = run_ray(ctx, tasks, methods, seed, ray_address, advance)
    elif backend == "local":
        records = run_local(ctx, tasks, methods, seed, workers, advance)
    else:
        raise ValueError(f"backend must be 'local' or 'ray', got {backend!r}")
    order = {m: i for i, m in enumerate(methods)}
    records.sort(key=lambda r: (order[r.method], r.task_index))
    return HomeResult(ctx.name, records, ctx.notes())


def overall(results: Sequence[HomeResult]) -> dict[str, dict]:
    """Metrics over the tasks of all homes pooled (so each home weighs by its number of tasks)."""
    pooled: dict[str, list[Outcome]] = {}
    for res in results:
        for r in res.records:
            pooled.setdefault(r.method, []).append(r.outcome)
    return {m: summarise(o) for m, o in pooled.items()}


def evaluate(datasets: Sequence, kind: str, methods: Sequence[str], params: str = "supervised", seed: int = 0,
             workers: int | None = None, max_tasks: int | None = None, backend: str = "local",
             ray_address: str | None = None, quiet: bool = False) -> dict:
    """Evaluate methods on the tasks of several homes; the JSON-ready result
    ``{task, params, seed, homes: {name: {method: metrics}}, mean: {method: metrics}, notes: {name: {...}},
    moves: {method: move model}}`` (``mean`` pools the tasks of all homes)."""
    from spcotmhp.evaluation.context import build_context
    from spcotmhp.evaluation.tasks import make_tasks, subset

    methods = check_methods(methods)
    results, notes = [], {}
    with progress_bar(quiet) as progress:
        for ds in datasets:
            ctx = build_context(ds, params, seed)
            home_tasks = make_tasks(ds, kind, ctx.adjacency, ctx.adjacency_source, places=ctx.places)
            tasks = subset(home_tasks.tasks, max_tasks, seed)
            if not tasks:
                notes[ds.name] = {**ctx.notes(), "n_tasks_all": 0, "dropped": home_tasks.dropped}
                continue
            res = evaluate_home(ctx, tasks, methods, seed, workers, backend, ray_address, progress)
            failures: dict[str, int] = {}
            for r in res.records:
                if r.error:
                    failures[r.method] = failures.get(r.method, 0) + 1
            notes[ds.name] = {**res.notes, "n_tasks_all": len(home_tasks.tasks), "dropped": home_tasks.dropped,
                              "no_path": failures}
            results.append(res)
    return {"task": kind, "params": params, "seed": seed,
            "homes": {r.home: r.metrics() for r in results},
            "mean": overall(results) if results else {},
            "notes": notes, "moves": {m: MOVE_MODELS[m] for m in methods}}
