"""Scale benchmark: SpCoTMHP on a generated 1000 x 1000-cell office with 60 rooms (0.1 m cells, 100 m x 100 m),
or with ``--building`` on a 2000 x 2000-cell floor with 200 places (200 m x 200 m; about 3 minutes).

    .venv/bin/python benchmarks/scale.py [--rooms 60] [--size 1000] [--queries 40] [--repeat 3] [--seed 0]
        [--building]

Offline: the synthetic office and its teaching walk (``datasets.synthetic.generate_environment``), the supervised
fit (truth places, the generator's adjacency), the costmap_2d cost map, and the planning graph precomputation
(Algorithm 1, lines 1-7; target <= 30 s). Online: plans from random free start cells to random place names, half
of them with a waypoint (target <= 20 ms median), each compared with one flat grid search over the whole map
from the same start to the nearest cell of a goal-named place's region (the metric level alone, with the cost map
step cost), measured in the same run, and with pyastar2d from the same start to the plan's final cell. Basic
plans (no waypoint) are compared with the free-space geodesic (uniform step cost on the traversable cells) from
the same start to the same final cell. Memory: the planning graph's field bytes and the process's peak resident
set. Every plan and baseline search is run ``--repeat`` times in a row and the fastest kept (on a machine shared
with other jobs the slower tries measure the other jobs); the plans' p95 of the first tries is printed too.
Prints a markdown table on stdout (progress on stderr).
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
from pathlib import Path
from statistics import median

import numpy as np
import pyastar2d
from rich.console import Console

from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.errors import SpcotmhpError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.costmap import inflate
from spcotmhp.metric.grid_search import shortest_paths, step_cost_map, warmup
from spcotmhp.planning.instructions import Instruction, PlaceQuery
from spcotmhp.planning.planner import HierarchicalPlanner

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the helper beside this script, however it is loaded
from _timing import best_of  # noqa: E402

# (precompute s, plan median s, peak GiB) per case: issue 11's targets
TARGETS = {"office": (30.0, 0.020, None), "building": (60.0, 0.005, 2.0)}
GEODESIC_TARGET = 1.05


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rooms", type=int, default=60)
    ap.add_argument("--size", type=int, default=1000)
    ap.add_argument("--queries", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=3, help="tries per query; the fastest is kept")
    ap.add_argument("--building", action="store_true", help="the 2000 x 2000-cell floor with 200 places")
    args = ap.parse_args(argv)
    if args.building:
        args.rooms, args.size = 200, 2000
    pre_target, plan_target, mem_target = TARGETS["building" if args.building else "office"]
    err = Console(stderr=True)
    warmup()

    with err.status("generating the office"):
        ds, t_gen = timed(lambda: generate_environment("office", seed=args.seed, n_rooms=args.rooms, size=args.size))
    with err.status("supervised fit"):
        model, t_fit = timed(lambda: fit_supervised(ds, adjacency="given"))
    with err.status("cost map"):
        costmap, t_cost = timed(lambda: inflate(ds.map, **model.costmap))
    with err.status("planning graph (precompute)"):
        planner, t_pre = timed(lambda: HierarchicalPlanner(model, log_p=costmap.log_p))
    graph = planner.graph

    rng = np.random.default_rng(args.seed)
    names = sorted(set(ds.place_names))
    free = np.argwhere(graph.traversable)
    truth = np.asarray(ds.truth_place)
    flat_cost = step_cost_map(costmap.log_p, connectivity=8)
    plan_t, first_t, cpu_t, flat_t, astar_t, astar_cpu, lengths, failures, detour = ([] for _ in range(9))
    free_cost = np.where(graph.traversable, 1.0, np.inf)
    weights = np.ascontiguousarray(graph.map_cost, dtype=np.float32)
    for q in range(args.queries):
        start = graph.to_map(free[rng.integers(len(free))])
        xy = ds.map.cell_to_world(start)
        goal = str(rng.choice(names))
        waypoints = ()
        if q % 2:
            via = str(rng.choice([n for n in names if n != goal]))
            waypoints = (PlaceQuery({via: 1.0}, via),)
        ins = Instruction(goal=PlaceQuery({goal: 1.0}, goal), waypoints=waypoints)
        try:
            plan, t, t_first, cpu = best_of(args.repeat, planner.plan, ins, xy)
        except SpcotmhpError as exc:  # reported, not hidden: a benchmark must show what failed
            failures.append(f"{ins.describe()} from ({xy[0]:.1f}, {xy[1]:.1f}): {exc}")
            continue
        plan_t.append(t)
        first_t.append(t_first)
        cpu_t.append(cpu)
        lengths.append(plan.length_m)
        # the flat baseline: one grid search from the same start to the goal name's teaching positions
        goal_places = [k for k, n in enumerate(ds.place_names) if n == goal]
        targets = ds.map.world_to_cell(ds.positions[np.isin(truth, goal_places)])
        targets = targets[np.isfinite(flat_cost[targets[:, 0], targets[:, 1]])]
        flat_t.append(best_of(args.repeat, shortest_paths, flat_cost, start, targets, connectivity=8)[1])
        # pyastar2d from the same start to the plan's final cell on the planning graph's cost grid
        a, b = graph.to_crop(plan.cells[0]), graph.to_crop(plan.cells[-1])
        ends = (int(a[0]), int(a[1])), (int(b[0]), int(b[1]))
        _, t, _, cpu = best_of(args.repeat, pyastar2d.astar_path, weights, *ends, allow_diagonal=True)
        astar_t.append(t)
        astar_cpu.append(cpu)
        if not waypoints:  # basic task: against the free-space geodesic between the same cells
            geo = shortest_paths(free_cost, a, b[None], connectivity=8, resolution=ds.map.resolution)
            if geo is not None and geo.length_m > 0:
                detour.append(plan.length_m / geo.length_m)

    h, w = graph.log_p.shape
    kind = f"portal graph, {graph.info['abstract_nodes']} abstract nodes" if graph.hier else "dense"
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    rows = [
        ("map", f"{ds.map.height} x {ds.map.width} cells, {args.rooms} places, {ds.n_events} events", "", ""),
        ("generate office + walk", f"{t_gen:.2f} s", "", ""),
        ("supervised fit", f"{t_fit * 1e3:.1f} ms", "", ""),
        ("cost map (costmap_2d inflation)", f"{t_cost:.2f} s", "", ""),
        (
            "precompute (planning graph)",
            f"{t_pre:.2f} s ({graph.n_nodes} nodes, crop {h} x {w}, {kind})",
            f"<= {pre_target:.0f} s",
            "yes" if t_pre <= pre_target else "NO",
        ),
        ("fields + links + tables (bytes)", f"{graph.field_bytes:,}", "", ""),
        (
            "peak resident memory (whole process)",
            f"{peak:.2f} GiB",
            f"<= {mem_target:.0f} GiB" if mem_target else "",
            ("yes" if peak <= mem_target else "NO") if mem_target else "",
        ),
    ]
    if plan_t:
        med, p95 = median(plan_t), float(np.percentile(plan_t, 95))
        ratio = median(flat_t) / med
        rows += [
            (
                "plan, median / p95",
                f"{med * 1e3:.2f} / {p95 * 1e3:.2f} ms ({len(plan_t)} plans, fastest of {args.repeat}; "
                f"first tries p95 {float(np.percentile(first_t, 95)) * 1e3:.2f} ms)",
                f"<= {plan_target * 1e3:.0f} ms",
                "yes" if med <= plan_target else "NO",
            ),
            (
                "flat grid search, median (baseline)",
                f"{median(flat_t) * 1e3:.2f} ms",
                "",
                f"plan is {ratio:.1f}x faster" if ratio >= 1 else f"plan is {1 / ratio:.1f}x slower",
            ),
            (
                "pyastar2d to the plan's final cell, median",
                f"{median(astar_t) * 1e3:.2f} ms",
                ">= 10x",
                f"plan is {median(astar_t) / med:.1f}x faster",
            ),
            (
                "CPU time: plan / pyastar2d, medians",
                f"{median(cpu_t) * 1e3:.2f} / {median(astar_cpu) * 1e3:.2f} ms",
                "<= 5 ms, >= 10x",
                f"plan is {median(astar_cpu) / median(cpu_t):.1f}x faster",
            ),
            ("plan length, median", f"{median(lengths):.1f} m", "", ""),
        ]
    if detour:
        rows.append(
            (
                "basic plans / free-space geodesic, median / max",
                (f"{median(detour):.3f} / {max(detour):.3f} ({len(detour)} plans)"),
                f"<= {GEODESIC_TARGET:.2f}",
                "yes" if max(detour) <= GEODESIC_TARGET else "NO",
            )
        )
    rows.append(("failed plans", f"{len(failures)} of {args.queries}", "", ""))
    print("| step | measured | target | met |")
    print("|---|---|---|---|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    for f in failures:
        print(f"- failed: {f}")
    return 0 if plan_t else 1


if __name__ == "__main__":
    sys.exit(main())
