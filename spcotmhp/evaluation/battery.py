"""The planner's acceptance battery: seeded synthetic homes with the hard cases of real ones.

For every home of :func:`~spcotmhp.datasets.synthetic_battery.battery_home` (three bedrooms, "west/east
corridor", narrow doors, a room taught partly in unknown space, dead ends) and every kind of parameters
(supervised: truth labels and the doors' adjacency; learned: unsupervised Gibbs sampling, psi from the walk
and the map), SpCoTMHP plans

* every **basic** task (each ordered pair of non-adjacent true places; instruction = the goal's name),
* **shared-word** tasks: "go to the corridor" from every other place: the word is part of two names ("west
  corridor", "east corridor"), which it names both, as a name several places share (issue 34): the plan must end
  in the closest of them (counted with the repeated names),
* a seeded subset of the **advanced** tasks (a waypoint, then the goal; :mod:`~spcotmhp.evaluation.tasks`),

and counts what a robot owner would notice:

* ``refused``: plans refused although a path for the robot exists (every task kept has one: its reference
  length over the robot cells is finite);
* ``unsafe``: plans with a pose in a lethal or inscribed cell of the model's cost map (costmap_2d >= 253),
  poses of the escape from a start that is itself in such a cell excepted;
* ``closest``: among successful plans whose goal name has several instances, those ending in the instance with
  the shortest path from the start, up to ``CLOSEST_TOLERANCE_M`` (cell rounding and the inflation cost, which
  prefers a centred route, make equal-length instances differ by a few cells);
* the SPL family (:mod:`~spcotmhp.evaluation.metrics`) of the basic and advanced tasks: advanced WN-SPL with
  the paper's N (the goal instance closest from the start) and with N via the waypoint (the instance where the
  shortest path through the waypoint ends, which is what the planner is asked to reach);
* ``cut_off`` of ``reach_checks``: "go to <name>" for every name of the model's places, from every place's
  position and from one cell of every free region (:func:`reach_refusals`), where some place of that name has a
  cell inside its 2-sigma ellipse that the robot can reach from the start (the oracle: the start's 4-connected
  component of the robot's cells; :mod:`spcotmhp.planning.regions`), refused. Places, not tasks: every learned
  place must be plannable from wherever its mass can be reached, pockets cut off by furniture included.

With ``furniture`` the homes are furnished (:func:`~spcotmhp.datasets.synthetic_battery.battery_home`).
"""

from __future__ import annotations

import multiprocessing
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.errors import SpcotmhpError
from spcotmhp.evaluation.context import HomeContext, build_context
from spcotmhp.evaluation.methods import task_instruction
from spcotmhp.evaluation.metrics import Outcome, summarise
from spcotmhp.evaluation.reference import HomeGeometry
from spcotmhp.evaluation.tasks import Task, home_geometry, make_tasks, subset
from spcotmhp.evaluation.work import failed_task, score_task
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.costmap import INSCRIBED_INFLATED_OBSTACLE, inflate
from spcotmhp.metric.grid_ops import label4
from spcotmhp.planning.places import mahalanobis2
from spcotmhp.planning.regions import REACH_SIGMAS

CLOSEST_TOLERANCE_M = 0.3
SHARED_WORD = "corridor"


@dataclass
class HomeBattery:
    """The battery's counts on one home with one kind of parameters."""

    home: str
    params: str
    tasks: int = 0
    refused: int = 0
    unsafe: int = 0
    closest: int = 0
    repeated: int = 0
    spl: float = 0.0
    n_spl: float = 0.0
    wn_spl: float = 0.0
    wn_spl_via: float = 0.0
    strict_spl: float = 0.0
    strict_wn_spl_via: float = 0.0
    set_apart: int = 0  # tasks with no footprint-safe path (evaluation/tasks.py), not planned
    reach_checks: int = 0
    cut_off: int = 0
    time_median_ms: float = 0.0
    errors: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def evaluate_home(
    dataset: Dataset,
    params: str,
    seed: int = 0,
    max_advanced: int | None = 60,
    learner: Mapping[str, Any] | None = None,
    model: SpatialConceptModel | None = None,
) -> HomeBattery:
    """Build the home's context (fit or learn, precompute; ``learner``: settings of the learner for learned
    parameters, e.g. ``{"hyper": Hyperparameters(place_size=1.0)}``; ``model``: parameters already fitted) and run
    the battery's tasks on it."""
    ctx = build_context(dataset, params, seed, learner=learner, model=model)
    out = HomeBattery(dataset.name, params)
    basic_all = make_tasks(dataset, "basic", ctx.adjacency, places=ctx.places)
    advanced_all = make_tasks(dataset, "advanced", ctx.adjacency, places=ctx.places)
    basic, advanced = basic_all.tasks, subset(advanced_all.tasks, max_advanced, seed)
    geometry = home_geometry(dataset, ctx.places)
    shared = shared_word_tasks(ctx, len(basic) + len(advanced), geometry)
    costmap = inflate(dataset.map, **ctx.model.costmap)
    costs = costmap.costs
    outcomes: dict[str, list[Outcome]] = {"basic": [], "advanced": []}
    times = []
    for task in [*basic, *shared, *advanced]:
        outcome, elapsed = _run(ctx, task, costs, out, geometry)
        times.append(elapsed)
        if task.goal_name != SHARED_WORD:
            outcomes[task.kind].append(outcome)
    b, a = summarise(outcomes["basic"]), summarise(outcomes["advanced"])
    out.spl, out.n_spl, out.wn_spl, out.wn_spl_via = b["spl"], b["n_spl"], a["wn_spl"], a["wn_spl_via"]
    out.strict_spl, out.strict_wn_spl_via = b["strict_spl"], a["strict_wn_spl_via"]
    out.set_apart = len(basic_all.no_safe_path) + len(advanced_all.no_safe_path)
    out.time_median_ms = 1000.0 * float(np.median(times))
    reach_refusals(ctx, costmap.free, out)
    return out


def reach_refusals(ctx: HomeContext, robot: np.ndarray, out: HomeBattery) -> None:
    """``cut_off`` / ``reach_checks`` of the module docstring: from each start, every spoken name whose places'
    2-sigma ellipses hold a robot cell (``robot``: the model's cost map's free cells) of the start's free region must
    be planned to. The starts: the true places' positions, and the first cell (row-major) of every other free
    region, so that pockets cut off by furniture are started from too."""
    planner, data = ctx.planner, ctx.dataset
    regions, _ = label4(robot)
    flat = regions.ravel()
    firsts = np.unique(flat, return_index=True)[1][1:]  # the first cell of each region 1..n
    starts = [p.cell for p in ctx.places] + [divmod(int(i), robot.shape[1]) for i in firsts]
    act = np.flatnonzero(ctx.model.active_places)
    within = {int(k): _regions_within(ctx, int(k), robot, regions) for k in act}
    for start in starts:
        region = int(regions[start])
        for name in dict.fromkeys(planner.spoken_names(act)):
            named = np.flatnonzero(planner.places_named(name.split()))
            if not any(region in within[int(k)] for k in named):
                continue
            out.reach_checks += 1
            try:
                planner.plan({"goal": name.split()}, tuple(data.map.cell_to_world(np.array(start))))
            except SpcotmhpError as exc:
                out.cut_off += 1
                if len(out.errors) < 6:
                    out.errors.append(f"{data.name}: {name} from {start}, its 2-sigma ellipse reachable: {exc}")


def _regions_within(ctx: HomeContext, k: int, robot: np.ndarray, regions: np.ndarray) -> set[int]:
    """The free regions (labels of ``regions``) holding a robot cell inside place k's 2-sigma ellipse."""
    m2 = mahalanobis2(ctx.cell_xy, ctx.model.mu[k : k + 1], ctx.model.Sigma[k : k + 1])[..., 0]
    return set(np.unique(regions[robot & (m2 <= REACH_SIGMAS**2)]).tolist())


def shared_word_tasks(ctx: HomeContext, first_index: int, geometry: HomeGeometry | None = None) -> list[Task]:
    """ "go to the corridor" from every place that is not a corridor: every place whose name holds the word is an
    instance, the closest by the robot's geodesic is the one N-SPL asks for (under each success rule,
    :mod:`~spcotmhp.evaluation.reference`); places from which no corridor region can be reached safely are
    left out."""
    data, places = ctx.dataset, ctx.places
    goals = tuple(p.index for p in places if SHARED_WORD in p.name.split())
    if len(goals) < 2:
        return []
    geometry = home_geometry(data, places) if geometry is None else geometry
    out: list[Task] = []
    for p in places:
        if p.index in goals:
            continue
        safe, strict = geometry.footprint(p.cell, goals, ()), geometry.strict(p.cell, goals, ())
        if not (np.isfinite(safe.l) and np.isfinite(strict.l) and safe.l > 0 and strict.l > 0):
            continue
        x, y = data.map.cell_to_world(np.array(p.cell))
        out.append(
            Task(
                data.name,
                "basic",
                first_index + len(out),
                p.index,
                goals[safe.closest],
                None,
                p.cell,
                (float(x), float(y)),
                SHARED_WORD,
                None,
                goals,
                (),
                safe.closest,
                safe.l,
                safe.closest,
                strict_l=strict.l,
                strict_closest_goal=strict.closest,
                strict_closest_goal_via=strict.closest,
            )
        )
    return out


def _run(
    ctx: HomeContext, task: Task, costs: np.ndarray, out: HomeBattery, geometry: HomeGeometry | None = None
) -> tuple[Outcome, float]:
    """Plan one task, score it and update the counts (``geometry``: the home's, made when not given)."""

    ins = task_instruction(task, ctx.dataset.lang)
    out.tasks += 1
    t0 = time.perf_counter()
    try:
        plan = ctx.planner.plan(ins, task.start_xy)
    except SpcotmhpError as exc:
        elapsed = time.perf_counter() - t0
        out.refused += 1
        if len(out.errors) < 3:
            out.errors.append(f"{task.label()}: {exc}")
        return failed_task(task, elapsed), elapsed
    elapsed = time.perf_counter() - t0
    cells = plan.cells
    start_cost = costs[cells[0, 0], cells[0, 1]]
    body = cells
    if start_cost >= INSCRIBED_INFLATED_OBSTACLE:  # the escape from the start is allowed
        safe = np.flatnonzero(costs[cells[:, 0], cells[:, 1]] < INSCRIBED_INFLATED_OBSTACLE)
        body = cells[safe[0] :] if len(safe) else cells[:0]
    if (costs[body[:, 0], body[:, 1]] >= INSCRIBED_INFLATED_OBSTACLE).any():
        out.unsafe += 1
    outcome = score_task(ctx, task, plan.path, elapsed)
    if len(task.goal_places) > 1 and task.kind == "basic" and outcome.success:
        out.repeated += 1
        geometry = home_geometry(ctx.dataset, ctx.places) if geometry is None else geometry
        out.closest += int(_is_closest(ctx, task, plan.path[-1], geometry))
    return outcome, elapsed


def _is_closest(ctx: HomeContext, task: Task, end: np.ndarray, geometry: HomeGeometry) -> bool:
    """Whether the goal instance whose region the path ends in has the shortest robot path from the start to its
    footprint target (within the tolerance; :mod:`~spcotmhp.evaluation.reference`)."""
    lengths = geometry.to_places(task.start_cell, task.goal_places)
    reached = [i for i, g in enumerate(task.goal_places) if ctx.places[g].region.contains(end)]
    return any(lengths[i] <= lengths.min() + CLOSEST_TOLERANCE_M for i in reached)


def _one(job: tuple[int | Dataset, str, int | None, bool]) -> HomeBattery:
    home, params, max_advanced, furniture = job
    if isinstance(home, Dataset):
        return evaluate_home(home, params, 0, max_advanced)
    return evaluate_home(battery_home(home, furniture=furniture), params, home, max_advanced)


def run_battery(
    homes: Sequence[int | Dataset],
    params: Sequence[str] = ("supervised", "learned"),
    max_advanced: int | None = 60,
    workers: int = 1,
    advance: Callable[[str], None] | None = None,
    furniture: bool = False,
) -> list[HomeBattery]:
    """The battery over ``homes`` (seeds of :func:`battery_home`, furnished with ``furniture``, or datasets such as
    the bundled homes) and each kind of parameters, on ``workers`` processes; results in (home, params) order
    whatever the scheduling."""
    jobs = [(h if isinstance(h, Dataset) else int(h), p, max_advanced, furniture) for h in homes for p in params]
    if workers <= 1:
        out = []
        for job in jobs:
            out.append(_one(job))
            if advance is not None:
                advance(f"{out[-1].home} {job[1]}")
        return out
    mp = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    results: dict[int, HomeBattery] = {}
    with ProcessPoolExecutor(max_workers=workers, mp_context=mp) as pool:
        futures = {pool.submit(_one, job): k for k, job in enumerate(jobs)}
        for fut in as_completed(futures):
            results[futures[fut]] = fut.result()
            if advance is not None:
                advance(f"{results[futures[fut]].home} {jobs[futures[fut]][1]}")
    return [results[k] for k in range(len(jobs))]


def summary(results: Sequence[HomeBattery]) -> dict[str, dict]:
    """Per kind of parameters: totals of the counts, the closest-instance rate, WN-SPL mean and minimum."""
    out = {}
    for p in dict.fromkeys(r.params for r in results):
        rows = [r for r in results if r.params == p]
        repeated = sum(r.repeated for r in rows)
        out[p] = {
            "homes": len(rows),
            "tasks": sum(r.tasks for r in rows),
            "refused": sum(r.refused for r in rows),
            "unsafe": sum(r.unsafe for r in rows),
            "closest_rate": sum(r.closest for r in rows) / repeated if repeated else float("nan"),
            "repeated": repeated,
            "spl_mean": float(np.mean([r.spl for r in rows])),
            "n_spl_mean": float(np.mean([r.n_spl for r in rows])),
            "wn_spl_mean": float(np.mean([r.wn_spl for r in rows])),
            "wn_spl_min": float(np.min([r.wn_spl for r in rows])),
            "wn_spl_via_mean": float(np.mean([r.wn_spl_via for r in rows])),
            "wn_spl_via_min": float(np.min([r.wn_spl_via for r in rows])),
            "strict_spl_mean": float(np.mean([r.strict_spl for r in rows])),
            "strict_wn_spl_via_mean": float(np.mean([r.strict_wn_spl_via for r in rows])),
            "set_apart": sum(r.set_apart for r in rows),
            "reach_checks": sum(r.reach_checks for r in rows),
            "cut_off": sum(r.cut_off for r in rows),
            "time_median_ms": float(np.median([r.time_median_ms for r in rows])),
        }
    return out


def markdown(results: Sequence[HomeBattery]) -> str:
    """The summary as a markdown table (one row per kind of parameters), under its success rule."""
    from spcotmhp.evaluation.tables import success_rule

    rows = [
        success_rule(spread=False)
        + " Set apart: tasks with no footprint-safe path (all of them, not only the planned subset).",
        "",
        (
            "| parameters | homes | tasks | set apart | refused with a free path | plans touching walls | closest "
            "instance | basic SPL | basic N-SPL | advanced WN-SPL mean (min) | advanced WN-SPL via mean (min) "
            "| strict: basic SPL / advanced WN-SPL via | places refused within reach (2 sigma) | online median |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for p, s in summary(results).items():
        rows.append(
            f"| {p} | {s['homes']} | {s['tasks']} | {s['set_apart']} | {s['refused']} | {s['unsafe']} | "
            f"{s['closest_rate']:.1%} of {s['repeated']} | {s['spl_mean']:.3f} | {s['n_spl_mean']:.3f} | "
            f"{s['wn_spl_mean']:.3f} ({s['wn_spl_min']:.3f}) | {s['wn_spl_via_mean']:.3f} ({s['wn_spl_via_min']:.3f}) "
            f"| {s['strict_spl_mean']:.3f} / {s['strict_wn_spl_via_mean']:.3f} | {s['cut_off']} of {s['reach_checks']} "
            f"| {s['time_median_ms']:.2f} ms |"
        )
    return "\n".join(rows)
