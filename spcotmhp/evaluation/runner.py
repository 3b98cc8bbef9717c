"""Experiment runner: every (task, method) of every home, in parallel, scored with the SPL family.

Per home, :func:`spcotmhp.evaluation.context.build_context` does the offline work once (parameters, cost map,
planning graph); the tasks are then cut into chunks and evaluated by a local process pool (all cores by
default) or by Ray (``backend="ray"``). Every random draw of a method uses its own generator seeded from
(seed, home, task, method), so results do not depend on the backend, the number of workers or the order in
which chunks finish. Only online planning is timed, inside the worker, after every method has run once on a
task (numba compilation and first-call caches are never timed).

With several seeds (:func:`evaluate`, ``seeds``) every seed is a complete repetition: learned parameters are
learned again from that seed, and every random draw follows it. With supervised parameters nothing but the
draws depends on the seed, so the methods that draw nothing (:data:`~spcotmhp.evaluation.methods.RANDOM`) run
once and their outcomes count for every seed (the result lists them in ``deterministic``). Results are means over
the seeds with their standard deviations and, for every metric, a 95% bootstrap interval over tasks (``<key>_ci``:
tasks resampled within each home, the per-task terms averaged over the seeds first; the generator seeded with
``seed``; :mod:`spcotmhp.evaluation.spread`). Tasks whose start lies inside a waypoint-named place are summarised
apart (``start_in_waypoint``), not in ``homes`` and ``mean``.
"""

from __future__ import annotations

import multiprocessing
import os
import time
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field

import numpy as np
from rich.progress import Progress

from spcotmhp.errors import SpcotmhpError
from spcotmhp.evaluation.context import HomeContext, build_context
from spcotmhp.evaluation.methods import METHODS, MOVE_MODELS, RANDOM
from spcotmhp.evaluation.metrics import Outcome, summarise, task_terms
from spcotmhp.evaluation.spread import aggregate_methods, bootstrap_ci
from spcotmhp.evaluation.tasks import HomeTasks, Task, TaskKind, make_tasks, subset
from spcotmhp.evaluation.work import TaskRecord, chunks, evaluate_chunk, warm_up
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.limits import MAX_JOBS, MAX_SEEDS, check_count
from spcotmhp.progress import progress_bar


@dataclass
class HomeResult:
    """All records of one home, with the context's notes (adjacency source, dropped tasks, precompute)."""

    home: str
    records: list[TaskRecord]
    notes: dict = field(default_factory=dict)

    def metrics(self, apart: bool = False) -> dict[str, dict]:
        """{method: summarise(outcomes)} in the order methods were given, over the tasks not set apart (with
        ``apart``: over those whose start lies inside a waypoint-named place)."""
        return summarise_records(self.records, apart)


def summarise_records(records: Iterable[TaskRecord], apart: bool = False) -> dict[str, dict]:
    """{method: summarise(outcomes)} over the records with ``record.apart == apart``."""
    by_method: dict[str, list[Outcome]] = {}
    for r in records:
        if r.apart == apart:
            by_method.setdefault(r.method, []).append(r.outcome)
    return {m: summarise(o) for m, o in by_method.items()}


# ---- local process pool ---------------------------------------------------------------------------------
# Per-process worker context, by design: ProcessPoolExecutor's initializer (_init_worker) sets it once in each
# worker process, so that the home's planners (heavy to pickle) reach the worker once, not with every chunk. It
# is written only by the initializer, before the worker runs any chunk, and read by _pool_chunk; the parent
# process never sets it.
_WORKER_CTX: HomeContext | None = None


def _init_worker(ctx: HomeContext, task: Task, methods: Sequence[str]) -> None:
    global _WORKER_CTX
    _WORKER_CTX = ctx
    warm_up(ctx, task, methods)


def _pool_chunk(tasks: Sequence[Task], methods: Sequence[str], seed: int) -> list[TaskRecord]:
    assert _WORKER_CTX is not None
    return evaluate_chunk(_WORKER_CTX, tasks, methods, seed)


def run_local(
    ctx: HomeContext,
    tasks: Sequence[Task],
    methods: Sequence[str],
    seed: int,
    workers: int,
    advance: Callable[[int], None],
) -> list[TaskRecord]:
    """Evaluate on ``workers`` processes (in this process when 1); ``advance(n)`` after every chunk of n tasks."""
    parts = chunks(tasks)
    if not parts:
        return []
    if workers <= 1 or len(parts) <= 1:
        warm_up(ctx, parts[0][0], methods)
        out = []
        for part in parts:
            out.extend(evaluate_chunk(ctx, part, methods, seed))
            advance(len(part))
        return out
    out = []
    # fork where the platform has it: workers inherit the loaded modules and compiled kernels (no re-import,
    # nothing read from disk again); spawn elsewhere. The kernels run no threads of their own.
    mp = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    with ProcessPoolExecutor(
        max_workers=min(workers, len(parts)),
        mp_context=mp,
        initializer=_init_worker,
        initargs=(ctx, parts[0][0], list(methods)),
    ) as pool:
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
    names = [m.strip() for m in methods if m.strip()]
    bad = [m for m in names if m not in METHODS]
    if bad or not names:
        raise SpcotmhpError(f"unknown method(s) {', '.join(bad) or '(none given)'}; accepted: {', '.join(METHODS)}")
    return list(dict.fromkeys(names))


def evaluate_home(
    ctx: HomeContext,
    tasks: Sequence[Task],
    methods: Sequence[str],
    seed: int = 0,
    workers: int | None = None,
    backend: str = "local",
    ray_address: str | None = None,
    progress: Progress | None = None,
) -> HomeResult:
    """All methods on the given tasks of one home."""
    methods = check_methods(methods)
    workers = default_workers() if workers is None else check_count(workers, "workers", 1, MAX_JOBS, ValueError)
    bar = progress.add_task(f"{ctx.name} {tasks[0].kind if tasks else ''}", total=len(tasks)) if progress else None

    def advance(n: int) -> None:
        if progress is not None and bar is not None:
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


def overall(results: Sequence[HomeResult], apart: bool = False) -> dict[str, dict]:
    """Metrics over the tasks of all homes pooled (so each home weighs by its number of tasks)."""
    return summarise_records((r for res in results for r in res.records), apart)


# long: the runner's public entry: 13 options, a docstring that gives the result's layout, the loop over seeds
def evaluate(
    datasets: Sequence,
    kind: TaskKind,
    methods: Sequence[str],
    params: str = "supervised",
    seed: int = 0,
    workers: int | None = None,
    max_tasks: int | None = None,
    backend: str = "local",
    ray_address: str | None = None,
    quiet: bool = False,
    seeds: int = 1,
    connectivity: str = "auto",
    model: SpatialConceptModel | None = None,
) -> dict:
    """Evaluate methods on the tasks of several homes over ``seeds`` seeds (seed, seed + 1, ...); the JSON-ready
    result ``{task, params, seed, seeds, connectivity, homes: {name: {method: metrics}}, mean: {method: metrics},
    start_in_waypoint: {method: metrics}, deterministic: [method], notes: {name: {...}}, moves: {method: move
    model}, time_s}``: every metric is the mean over the seeds with ``<metric>_sd`` and ``<metric>_ci`` beside it
    (``mean`` pools the tasks of all homes; ``start_in_waypoint`` pools the tasks set apart). ``connectivity`` is
    where learned psi comes from. ``model``: parameters already made (a model folder, taught or questioned) to
    evaluate as they are on the one dataset given, instead of fitting (``params`` is then "model")."""
    methods = check_methods(methods)
    check_count(seeds, "seeds", 1, MAX_SEEDS, ValueError)
    if model is not None:  # a given model: on the one dataset it was made on
        if len(datasets) != 1:
            raise SpcotmhpError(f"a given model is evaluated on one dataset; got {len(datasets)}")
        params = "model"
    fixed = params in ("supervised", "model")  # only the methods that draw change with the seed
    t_start = time.perf_counter()
    notes: dict = {}
    per_seed: list[list[HomeResult]] = []
    first: dict[str, HomeResult] = {}
    with progress_bar(quiet) as progress:
        for k in range(seeds):
            results = []
            for ds in datasets:
                ctx = build_context(ds, params, seed + k, connectivity, model=model)
                tasks, note = _tasks_and_note(ctx, kind, max_tasks, seed, notes)
                if not tasks:
                    continue
                again = [m for m in methods if k == 0 or not fixed or m in RANDOM]
                res = (
                    evaluate_home(ctx, tasks, again, seed + k, workers, backend, ray_address, progress)
                    if again
                    else None
                )
                res = _with_first(res, ds.name, first, again, methods)
                _count_no_path(note, res.records)
                results.append(res)
            per_seed.append(results)
    for note in notes.values():
        note["psi"] = sorted(set(note["psi"]))
        note["vs_truth"] = [v for v in note["vs_truth"] if v]
    return {
        "task": kind,
        "params": params,
        "seed": seed,
        "seeds": seeds,
        "connectivity": connectivity,
        **_aggregate_seeds(per_seed, list(first), methods, seed),
        "deterministic": [m for m in methods if fixed and m not in RANDOM],
        "notes": notes,
        "moves": {m: MOVE_MODELS[m] for m in methods},
        "time_s": time.perf_counter() - t_start,
    }


def _tasks_and_note(ctx: HomeContext, kind: TaskKind, max_tasks: int | None, seed: int, notes: dict):
    """One home's tasks of one seed (the same seeded subset in every seed) and its note in ``notes`` (made on the
    first seed, :func:`_home_note`), with this seed's psi source and learned-vs-truth scores added."""
    home_tasks = make_tasks(ctx.dataset, kind, ctx.adjacency, ctx.adjacency_source, places=ctx.places)
    tasks = subset(home_tasks.tasks, max_tasks, seed)
    note = notes.setdefault(ctx.name, _home_note(ctx, home_tasks, tasks))
    for key in ("psi", "vs_truth"):
        note[key].append(ctx.notes()[key])
    return tasks, note


def _with_first(
    res: HomeResult | None, home: str, first: dict[str, HomeResult], again: Sequence[str], methods: Sequence[str]
) -> HomeResult:
    """A seed's result of ``home`` completed with the first seed's outcomes of the methods it did not run again
    (nothing re-fitted and they draw nothing: those outcomes hold for every seed); the first one is kept."""
    if res is None:
        res = HomeResult(home, [], dict(first[home].notes))
    if len(again) < len(methods):
        res.records += [r for r in first[home].records if r.method not in again]
    first.setdefault(home, res)
    return res


def _home_note(ctx: HomeContext, home_tasks: HomeTasks, tasks: Sequence[Task]) -> dict:
    """A home's notes in :func:`evaluate`'s result: the context's, the task counts and dropped tasks, and the
    per-seed lists to be filled (``psi``: the psi source of each seed; ``vs_truth``: learned parameters' NMI / ARI
    against the truth, per seed; ``no_path``: {method: failed plans})."""
    return {
        **ctx.notes(),
        "psi": [],
        "vs_truth": [],
        "n_tasks_all": len(home_tasks.tasks),
        "dropped": home_tasks.dropped,
        "no_safe_path": home_tasks.no_safe_path,
        "zero_length": len(home_tasks.zero_length),
        "start_in_waypoint": sum(t.start_in_waypoint for t in tasks),
        "no_path": {},
    }


def _count_no_path(note: dict, records: Iterable[TaskRecord]) -> None:
    """Add the records that found no path to ``note["no_path"]`` ({method: count})."""
    for r in records:
        if r.error:
            note["no_path"][r.method] = note["no_path"].get(r.method, 0) + 1


def _aggregate_seeds(
    per_seed: Sequence[Sequence[HomeResult]], homes: Sequence[str], methods: Sequence[str], seed: int = 0
) -> dict:
    """``{homes, mean, start_in_waypoint}`` of :func:`evaluate`: every metric's mean and sd over the seeds and its
    bootstrap interval over tasks (:func:`_add_intervals`), per home, over all homes pooled, and over the tasks set
    apart; methods in the order given."""
    order = {m: i for i, m in enumerate(methods)}

    def ordered(d: dict) -> dict:
        return dict(sorted(d.items(), key=lambda kv: order[kv[0]]))

    apart = [overall(rs, apart=True) for rs in per_seed if rs]
    out = {
        "homes": {
            name: ordered(aggregate_methods([next(r for r in rs if r.home == name).metrics() for rs in per_seed]))
            for name in homes
        },
        "mean": ordered(aggregate_methods([overall(rs) for rs in per_seed if rs])),
        "start_in_waypoint": ordered(aggregate_methods(apart)) if apart and apart[0] else {},
    }
    _add_intervals(out, per_seed, seed)
    return out


def _add_intervals(out: dict, per_seed: Sequence[Sequence[HomeResult]], seed: int) -> None:
    """Add ``<key>_ci`` (:func:`~spcotmhp.evaluation.spread.bootstrap_ci`, seeded with ``seed``) beside every
    per-task metric of ``out["homes"]``, ``out["mean"]`` (stratified by home) and ``out["start_in_waypoint"]``."""
    homes = list(dict.fromkeys(r.home for rs in per_seed for r in rs))
    for apart, pooled in ((False, out["mean"]), (True, out["start_in_waypoint"])):
        for method, metrics in pooled.items():
            found = {h: m for h in homes if (m := _task_matrix(per_seed, h, method, apart)) is not None}
            if not found:
                continue
            keys = next(iter(found.values()))[0]
            _put(metrics, keys, bootstrap_ci([terms for _, terms in found.values()], seed))
            for home, (keys, terms) in found.items() if not apart else ():
                _put(out["homes"][home][method], keys, bootstrap_ci([terms], seed))


def _task_matrix(
    per_seed: Sequence[Sequence[HomeResult]], home: str, method: str, apart: bool
) -> tuple[list[str], np.ndarray] | None:
    """The metric keys and the (tasks, keys) matrix of one method's per-task terms on one home
    (:func:`~spcotmhp.evaluation.metrics.task_terms`), averaged over the seeds (None: no task)."""
    outcomes = [
        [r.outcome for r in res.records if r.method == method and r.apart == apart]
        for results in per_seed
        for res in results
        if res.home == home
    ]
    terms = [task_terms(o) for o in outcomes if o]
    if not terms:
        return None
    keys = list(terms[0])
    return keys, np.mean([np.stack([t[k] for k in keys], axis=1) for t in terms], axis=0)


def _put(metrics: dict, keys: Sequence[str], ci: np.ndarray) -> None:
    for key, (low, high) in zip(keys, ci.tolist(), strict=True):
        metrics[f"{key}_ci"] = [low, high]
