"""Both success rules on places taught against a wall: generated battery homes, each place in turn moved onto the
free cells beside the wall nearest its mean (``spcotmhp.datasets.against_wall``), supervised parameters.

    .venv/bin/python benchmarks/footprint_scoring.py [--homes 10] [--first-seed 0] [--methods spcotmhp,spcotmhp-paper]
        [--max-advanced 20]

Per home and place: every basic task whose goal is that place, and a seeded subset of the advanced tasks whose goal
or waypoint is that place. A robot whose footprint stays clear of obstacles cannot put its centre in such a place's
teaching box (its cells are inscribed), so under the paper's strict rule such tasks fail because the plan is safe;
under the footprint rule (the centre within the robot's inscribed radius of the box) they succeed when the plan
reaches the place. Tasks with no footprint-safe path are set apart (counted, not planned). Prints a markdown table
on stdout: tasks, set apart, refusals and failures under each rule per method, and the homes' boxes that hold no
robot cell.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from spcotmhp.datasets.against_wall import against_wall
from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.errors import SpcotmhpError
from spcotmhp.evaluation.context import build_context
from spcotmhp.evaluation.reference import robot_cells
from spcotmhp.evaluation.tasks import make_tasks, subset
from spcotmhp.evaluation.work import run_method, score_task


def count_place(home, k: int, methods: list[str], max_advanced: int, totals: dict) -> None:
    """Move place k of ``home`` against a wall, plan its tasks with every method and add the counts."""
    data = against_wall(home, k)
    ctx = build_context(data, "supervised", 0)
    robot = robot_cells(data)
    rows, cols = np.nonzero(robot)
    centres = data.map.cell_to_world(np.stack([rows, cols], axis=1))
    totals["boxes without a robot cell"] += int(not ctx.places[k].box.contains(centres).any())
    totals["places"] += 1
    name = ctx.places[k].name
    basic = make_tasks(data, "basic", ctx.adjacency, places=ctx.places)
    advanced = make_tasks(data, "advanced", ctx.adjacency, places=ctx.places)
    mine = [t for t in basic.tasks if t.goal_name == name]
    mine += subset([t for t in advanced.tasks if name in (t.goal_name, t.waypoint_name)], max_advanced, k)
    totals["set apart"] += sum(f" {name} (" in r for r in basic.no_safe_path + advanced.no_safe_path)
    for method in methods:
        row = totals["methods"].setdefault(method, {"tasks": 0, "refused": 0, "footprint": 0, "strict": 0})
        for task in mine:
            row["tasks"] += 1
            try:
                path = run_method(method, ctx, task, np.random.default_rng(0))
            except SpcotmhpError:
                row["refused"] += 1
                continue
            outcome = score_task(ctx, task, path, 0.0)
            ok = outcome.success and bool(outcome.w_success is not False)
            strict = outcome.strict
            strict_ok = strict is not None and strict.success and bool(strict.w_success is not False)
            row["footprint"] += int(not ok)
            row["strict"] += int(not strict_ok)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--homes", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--methods", default="spcotmhp,spcotmhp-paper")
    ap.add_argument("--max-advanced", type=int, default=20)
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    totals: dict = {"places": 0, "boxes without a robot cell": 0, "set apart": 0, "methods": {}}
    methods = [m for m in args.methods.split(",") if m]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # teaching points beside a wall: the datasets' own warnings
        for seed in range(args.first_seed, args.first_seed + args.homes):
            home = battery_home(seed)
            for k in range(len(home.place_names or [])):
                count_place(home, k, methods, args.max_advanced, totals)
    print(
        f"{args.homes} battery homes (seeds {args.first_seed}..{args.first_seed + args.homes - 1}), every place in "
        f"turn taught against a wall: {totals['places']} places, {totals['boxes without a robot cell']} of whose "
        f"boxes hold no robot cell; {totals['set apart']} tasks set apart (no footprint-safe path).\n"
    )
    print("| method | tasks | refused | fail: footprint rule | fail: strict rule (the paper's) |")
    print("|---|---:|---:|---:|---:|")
    for method, row in totals["methods"].items():
        print(f"| {method} | {row['tasks']} | {row['refused']} | {row['footprint']} | {row['strict']} |")
    print(f"\n({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
