"""The relation battery (issue 23): "the bedroom closest to the kitchen" and its kin on seeded generated homes with
three bedrooms each, every plan checked against the stated rule computed independently
(:mod:`spcotmhp.evaluation.relations_battery`). Prints one row per kind of relation: requests where the rule names
an instance and the plan ends there with the relation in its explanation (right), requests where the rule names
none and the planner refuses (none named), refusals although the rule names one, and silently wrong plans.

    .venv/bin/python benchmarks/relations.py [--homes 50] [--first-seed 0] [--per-kind 6]
"""

from __future__ import annotations

import argparse
import platform
import time
import warnings
from collections import Counter

from rich.progress import Progress

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.evaluation.relations_battery import KINDS, evaluate_relations


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--homes", type=int, default=50, help="seeded homes")
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--per-kind", type=int, default=6, help="requests per kind and repeated name")
    args = parser.parse_args(argv)
    total: Counter = Counter()
    wrong: list[str] = []
    t0 = time.perf_counter()
    with warnings.catch_warnings(), Progress(transient=True) as bar:
        warnings.simplefilter("ignore")
        job = bar.add_task("homes", total=args.homes)
        for seed in range(args.first_seed, args.first_seed + args.homes):
            result = evaluate_relations(battery_home(seed), seed, args.per_kind)
            total.update(result.counts)
            wrong += result.wrong
            bar.advance(job)
    print(f"machine: {platform.machine()}, Python {platform.python_version()}; {args.homes} homes from seed "
          f"{args.first_seed}, {time.perf_counter() - t0:.0f} s")  # fmt: skip
    print("\n| relation | requests | right | none named (refused, as the rule names none) | refused | wrong | right share |")
    print("|---|---|---|---|---|---|---|")
    for kind in (*KINDS, "all"):
        pick = KINDS if kind == "all" else (kind,)
        c = {v: sum(n for (k, verdict), n in total.items() if k in pick and verdict == v) for v in
             ("right", "none named", "refused", "wrong")}  # fmt: skip
        named = c["right"] + c["refused"] + c["wrong"]
        share = f"{c['right'] / named:.3f}" if named else "-"
        print(f"| {kind} | {sum(c.values())} | {c['right']} | {c['none named']} | {c['refused']} | {c['wrong']} | "
              f"{share} |")  # fmt: skip
    for w in wrong:
        print(f"wrong: {w}")


if __name__ == "__main__":
    main()
