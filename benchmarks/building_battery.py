"""Issue 28's acceptance battery on many generated buildings (spcotmhp.evaluation.building_battery): for 2 to 5
floors and several seeds, with supervised and learned (Gibbs) models, "go to the X" for every name on two floors
or more, with the goal on each floor and on any floor, from two truth places of every floor. Prints per number of
floors and kind of model: plans, ended on the floor asked, closest (against the geodesic oracle, within the
single-floor battery's tolerance), "no path" refusals where a connector route exists, and the misses.

    .venv/bin/python benchmarks/building_battery.py [--seeds 3] [--first-seed 10] [--floors 2 3 4 5]
"""

from __future__ import annotations

import argparse
import platform
import time
import warnings
from collections import Counter

from spcotmhp.building.learn import learn_building
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import generate_building
from spcotmhp.evaluation.building_battery import battery

KEYS = ("plans", "on_floor", "closest", "no_path")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=10)
    parser.add_argument("--floors", type=int, nargs="+", default=[2, 3, 4, 5])
    parser.add_argument("--show", type=int, default=3, help="misses shown per building")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    totals: dict[tuple[int, str], Counter] = {}
    misses: list[str] = []
    for n in args.floors:
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                building = generate_building(n, seed=seed)
                models = {"supervised": learn_building(building),
                          "learned": learn_building(building, supervised=False, runs=1, seed=seed)}  # fmt: skip
            for kind, bm in models.items():
                result = battery(building, BuildingPlanner(bm))
                totals.setdefault((n, kind), Counter()).update({k: result[k] for k in KEYS})
                misses += [f"{n} floors, seed {seed}, {kind}: {f}" for f in result["failures"][: args.show]]
    print(f"machine: {platform.machine()}, Python {platform.python_version()}; seeds {args.first_seed}.."
          f"{args.first_seed + args.seeds - 1}, {time.perf_counter() - t0:.0f} s")  # fmt: skip
    print("\n| floors | model | plans | on the floor asked | closest | no path | closest share |")
    print("|---|---|---|---|---|---|---|")
    for (n, kind), c in totals.items():
        print(f"| {n} | {kind} | {c['plans']} | {c['on_floor']} | {c['closest']} | {c['no_path']} | "
              f"{c['closest'] / max(c['plans'], 1):.3f} |")  # fmt: skip
    for m in misses:
        print(f"miss: {m}")


if __name__ == "__main__":
    main()
