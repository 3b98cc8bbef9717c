"""Planning time in a building (issue 28): a seeded building of N floors against one floor of the same total size
(a generated home of N times the rooms, so N times the area at the generator's area per room), measured in the
same run. Per seed, plans "go to the X" for every name of the building, from the truth position of a few places
of every floor (the building: with the goal on any floor, and on each floor; the single floor: the same names
from as many starts). Each plan is timed as the best of ``--repeat`` (benchmarks/_timing.py; its online time),
after one warm-up plan. Prints one row per seed and the median ratio (target: <= 2).

    .venv/bin/python benchmarks/building.py [--seeds 5] [--floors 3] [--rooms 11] [--repeat 3]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from spcotmhp.building.learn import learn_building
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import generate_building
from spcotmhp.datasets.synthetic_plan import generate_floor_plan
from spcotmhp.datasets.synthetic_walk import teaching_walk
from spcotmhp.evaluation.tasks import build_places
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning.planner import HierarchicalPlanner

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import best_of  # noqa: E402


def starts(dataset, n: int) -> list[tuple[float, float]]:
    """The truth positions of the first ``n`` places of ``dataset``."""
    return [tuple(dataset.map.cell_to_world(np.array(p.cell))) for p in build_places(dataset)[:n]]


def time_building(bp: BuildingPlanner, building, per_floor: int, repeat: int) -> tuple[list[float], list[float]]:
    """Online seconds per plan: (goal on any floor, goal on a floor named)."""
    names = sorted({n for d in building.floors.values() for n in d.place_names})
    anywhere, named = [], []
    for f, d in building.floors.items():
        for xy in starts(d, per_floor):
            for name in names:
                for goal_floor in (None, *building.floors):
                    _, t, _, _ = best_of(repeat, bp.plan, f"go to the {name}", xy, f, goal_floor=goal_floor,
                                         seconds=lambda p, _: p.time_online_s)  # fmt: skip
                    (anywhere if goal_floor is None else named).append(t)
    return anywhere, named


def time_single(hp: HierarchicalPlanner, dataset, n_starts: int, repeat: int) -> list[float]:
    names = sorted(set(dataset.place_names))
    out = []
    for xy in starts(dataset, n_starts):
        for name in names:
            _, t, _, _ = best_of(repeat, hp.plan, f"go to the {name}", xy, seconds=lambda p, _: p.time_online_s)
            out.append(t)
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--floors", type=int, default=3)
    parser.add_argument("--rooms", type=int, default=11, help="places per floor (house)")
    parser.add_argument("--starts", type=int, default=3, help="start places per floor")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"machine: {platform.machine()}, Python {platform.python_version()}; {args.floors} floors of "
          f"{args.rooms} places vs one floor of {args.floors * args.rooms}; best of {args.repeat}")  # fmt: skip
    print("\n| seed | building: cells | single: cells | building ms (any floor) | building ms (floor named) | "
          "single ms | ratio (any) | ratio (named) | precompute s (building / single) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    ratios, ratios_named = [], []
    for seed in range(args.seeds):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            building = generate_building(args.floors, seed=seed, n_rooms=args.rooms)
            t0 = time.perf_counter()
            bp = BuildingPlanner(learn_building(building))
            pre_b = time.perf_counter() - t0
            plan = generate_floor_plan("house", n_rooms=args.floors * args.rooms, seed=seed)
            single = teaching_walk(plan, seed=seed)
            t0 = time.perf_counter()
            hp = HierarchicalPlanner(fit_supervised(single))
            pre_s = time.perf_counter() - t0
        first = next(iter(building.floors))
        bp.plan("go to the kitchen", starts(building.floors[first], 1)[0], first)  # warm-up: the kernels
        hp.plan("go to the kitchen", starts(single, 1)[0])
        anywhere, named = time_building(bp, building, args.starts, args.repeat)
        one = time_single(hp, single, args.starts * args.floors, args.repeat)
        b_any, b_named, s = (statistics.median(x) * 1e3 for x in (anywhere, named, one))
        ratios.append(b_any / s)
        ratios_named.append(b_named / s)
        cells_b = sum(d.map.data.size for d in building.floors.values())
        print(f"| {seed} | {cells_b} | {single.map.data.size} | {b_any:.2f} | {b_named:.2f} | {s:.2f} | "
              f"{b_any / s:.2f} | {b_named / s:.2f} | {pre_b:.1f} / {pre_s:.1f} |")  # fmt: skip
    print(f"\nmedian ratio over {args.seeds} seeds: any floor {statistics.median(ratios):.2f} "
          f"(min {min(ratios):.2f}, max {max(ratios):.2f}); floor named {statistics.median(ratios_named):.2f} "
          f"(min {min(ratios_named):.2f}, max {max(ratios_named):.2f}); target <= 2")  # fmt: skip


if __name__ == "__main__":
    main()
