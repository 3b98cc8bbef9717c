"""Benchmark of SpCoTMHP online planning (Algorithm 1, lines 9-13) on the bundled homes, supervised parameters.

For each home and each kind of instruction -- basic ("go to the X"), waypoint ("go to the X via the Y") and
avoidance ("go to the X avoiding the Y") -- plans from random free starts of the main free component, timed
from the instruction text to the final (smoothed) path (``Plan.time_online_s``). In the same run, from the same
start to the plan's final cell, on the same cost grid (the map-only step cost log|A| - log p(x|m) of the
planning graph, +inf on blocked cells):

* (a) pyastar2d (C++ A*, 8-connected; its cost model: entering a cell costs its weight, diagonals unscaled);
* (b) the project's flat grid search (:func:`spcotmhp.metric.grid_search.shortest_paths`, exact, numba);
* (c) the previous planner, when ``--previous DIR`` names a checkout of an earlier version: the same queries
  planned there, in a subprocess with that checkout first on the path, and planned by this version in a subprocess
  of its own with the same protocol; the two alternate for ``--rounds`` rounds (default 3) and each query keeps its
  fastest time over all rounds, so that a slow spell of a shared machine does not fall on one side only; "(c) /
  plan" is the ratio of the two medians; "same plans as (c)" counts the queries whose plans (cells, length,
  places, goal options, notes, explanation; or the refusal's type) are identical.

With ``--repeat R`` (default 3) every query, pyastar2d search and flat search is run R times in a row and the
fastest kept (on a machine shared with other jobs, the slower tries measure the other jobs); the p95 of the
first tries is printed as well (it includes the first plan avoiding a given place, which recomputes fields).
Ratios are of medians measured in this run. Memory: the bytes of the precomputed cost-to-go fields and
next-step links. Plans that are impossible (the avoided place is the only way, the start lies inside it) are
counted as failed.

    .venv/bin/python benchmarks/planning.py [--queries 150] [--repeat 3] [--homes 3LDK_01 3LDK_05 3LDK_06]
        [--previous DIR] [--rounds 3]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.errors import PlanningError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning.places import main_component
from spcotmhp.planning.planner import HierarchicalPlanner

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the helper beside this script, however it is loaded
from _timing import best_of  # noqa: E402

KINDS = ("basic", "waypoint", "avoid")
TEMPLATES = {
    "en": ("go to the {g}", "go to the {g} via the {w}", "go to the {g} avoiding the {w}"),
    "ja": ("{g}へ行って", "{w}を通って{g}へ行って", "{w}を避けて{g}へ行って"),
}


def queries(planner: HierarchicalPlanner, n: int, seed: int, lang: str) -> list[tuple[str, str, np.ndarray]]:
    """(kind, text, start xy): n random free starts, each with a basic, a waypoint and an avoidance text."""
    model, graph = planner.model, planner.graph
    rng = np.random.default_rng(seed)
    free = np.argwhere(main_component(graph.traversable))
    names = sorted({planner.names[k] for k in np.flatnonzero(model.active_places)})
    out = []
    for kind, template in zip(KINDS, TEMPLATES[lang], strict=False):
        for cell in free[rng.integers(len(free), size=n)]:
            goal, via = rng.choice(names, size=2, replace=False)
            out.append((kind, template.format(g=goal, w=via), model.map.cell_to_world(graph.to_map(cell))))
    return out


def setup(name: str) -> tuple[HierarchicalPlanner, str, float]:
    lang = "ja" if name == "albert-b" else "en"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled(name, lang=lang)
    model = fit_supervised(dataset)
    t0 = time.perf_counter()
    planner = HierarchicalPlanner(model)
    return planner, lang, time.perf_counter() - t0


def plan_record(plan) -> str:
    """A digest of everything a plan says (cells, length, places and roles, goal options, notes, explanation):
    two checkouts that give the same digest for a query gave the same plan."""
    said = [
        plan.cells.tolist(),
        round(plan.length_m, 9),
        [(p.id, p.role, p.label) for p in plan.places],
        [(o.id, o.label, round(o.length_m, 9), o.exact, round(o.log_prob, 9)) for o in plan.goal_options],
        plan.notes,
        plan.explanation,
    ]
    return hashlib.sha1(json.dumps(said).encode()).hexdigest()


def plan_times(name: str, n: int, seed: int, repeat: int = 1) -> dict:
    """Online times per kind (seconds; failed plans left out; the fastest of ``repeat`` tries each, as in
    :func:`bench_home`) and each query's :func:`plan_record` (or its error's type): what ``--previous`` runs in
    the old checkout."""
    planner, lang, _ = setup(name)
    times: dict[str, list[float]] = {k: [] for k in KINDS}
    records = []
    for kind, text, xy in queries(planner, n, seed, lang):
        try:
            plan, t, _, _ = best_of(repeat, planner.plan, text, xy, seconds=lambda p, _: p.time_online_s)
        except PlanningError as exc:  # a refused request is not timed
            records.append(type(exc).__name__)
            continue
        times[kind].append(t)
        records.append(plan_record(plan))
    return {"times": times, "records": records}


def bench_home(name: str, n: int, seed: int, previous: str | None, repeat: int = 3, rounds: int = 3) -> list[dict]:
    import pyastar2d

    from spcotmhp.metric.grid_search import shortest_paths

    planner, lang, t_pre = setup(name)
    graph = planner.graph
    weights = np.ascontiguousarray(graph.map_cost, dtype=np.float32)
    old, now = _alternated(previous, name, n, seed, repeat, rounds) if previous else (None, None)
    rows = []
    qs = queries(planner, n, seed, lang)
    for kind in KINDS:
        times, first, cpu, astar, astar_cpu, flat, failures, same = [], [], [], [], [], [], 0, 0
        for q, (_, text, xy) in ((q, qs[q]) for q in range(len(qs)) if qs[q][0] == kind):
            try:
                plan, t, t_first, c = best_of(repeat, planner.plan, text, xy, seconds=lambda p, _: p.time_online_s)
            except PlanningError as exc:
                failures += 1
                same += bool(old) and old["records"][q] == type(exc).__name__
                continue
            same += bool(old) and old["records"][q] == plan_record(plan)
            times.append(t)
            first.append(t_first)
            cpu.append(c)
            a, b = graph.to_crop(plan.cells[0]), graph.to_crop(plan.cells[-1])
            ends = (int(a[0]), int(a[1])), (int(b[0]), int(b[1]))
            _, t, _, c = best_of(repeat, pyastar2d.astar_path, weights, *ends, allow_diagonal=True)
            astar.append(t)
            astar_cpu.append(c)
            flat.append(best_of(repeat, shortest_paths, graph.map_cost, a, b[None])[1])
        med = statistics.median(times)
        rows.append(
            {
                "home": name,
                "kind": kind,
                "queries": len(times),
                "failures": failures,
                "median_ms": 1e3 * med,
                "p95_ms": 1e3 * float(np.percentile(times, 95)),
                "p95_first_ms": 1e3 * float(np.percentile(first, 95)),
                "cpu_ms": 1e3 * statistics.median(cpu),
                "cpu_p95_ms": 1e3 * float(np.percentile(cpu, 95)),
                "astar_ms": 1e3 * statistics.median(astar),
                "astar_cpu_ms": 1e3 * statistics.median(astar_cpu),
                "flat_ms": 1e3 * statistics.median(flat),
                "previous_ms": 1e3 * statistics.median(old["times"][kind]) if old and old["times"][kind] else None,
                "this_ms": 1e3 * statistics.median(now["times"][kind]) if now and now["times"][kind] else None,
                "same_plans": f"{same}/{len(times) + failures}" if old else "-",
                "precompute_s": t_pre,
                "nodes": graph.n_nodes,
                "cells": int(graph.traversable.sum()),
                "field_bytes": int(np.asarray(graph.dist).nbytes + np.asarray(graph.next_step).nbytes),
            }
        )
    return rows


def _alternated(folder: str, name: str, n: int, seed: int, repeat: int, rounds: int) -> tuple[dict, dict]:
    """:func:`plan_times` of the checkout ``folder`` and of this version, each in a subprocess, alternating for
    ``rounds`` rounds; each query's time is its fastest over the rounds (module docstring, (c))."""
    here = str(Path(__file__).resolve().parents[1])
    runs: dict[str, list[dict]] = {"old": [], "now": []}
    for _ in range(max(1, rounds)):
        runs["old"].append(_previous_times(folder, name, n, seed, repeat))
        runs["now"].append(_previous_times(here, name, n, seed, repeat))
    out = []
    for side in ("old", "now"):
        first = runs[side][0]
        times = {k: [min(ts) for ts in zip(*(r["times"][k] for r in runs[side]), strict=True)] for k in KINDS}
        out.append({"times": times, "records": first["records"]})
    return out[0], out[1]


def _previous_times(folder: str, name: str, n: int, seed: int, repeat: int) -> dict:
    """This script's :func:`plan_times` run with the checkout ``folder`` first on the path."""
    env = {**os.environ, "PYTHONPATH": os.path.abspath(folder)}
    code = (
        f"import sys, json; sys.path.insert(0, {os.path.dirname(os.path.abspath(__file__))!r}); "
        f"import planning as b; print(json.dumps(b.plan_times({name!r}, {n}, {seed}, {repeat})))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        env=env,
        cwd=os.path.abspath(folder),
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=150, help="starts per kind of instruction")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=3, help="tries per query; the fastest is kept")
    parser.add_argument("--homes", nargs="+", default=["3LDK_01", "3LDK_05", "3LDK_06"])
    parser.add_argument("--previous", help="a checkout of an earlier version to time the same queries with")
    parser.add_argument("--rounds", type=int, default=3, help="rounds alternating the previous and this version")
    args = parser.parse_args(argv)
    from spcotmhp.warmup import warm_up

    warm_up()
    rows = []
    for name in args.homes:
        print(f"benchmarking {name} ...", file=sys.stderr)
        rows += bench_home(name, args.queries, args.seed, args.previous, args.repeat, args.rounds)
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} logical CPUs, Python {platform.python_version()}; "
        f"load average {os.getloadavg()[0]:.1f} at the end; fastest of {args.repeat} tries per query"
    )
    print(
        "\n| home | instructions | plans (failed) | online median ms | p95 ms | p95 first try ms "
        "| CPU median / p95 ms | (a) pyastar2d ms (CPU) | plan / (a) (CPU) "
        "| (b) flat search ms | plan / (b) | (c) previous ms | this version, same protocol ms | (c) / plan "
        "| same plans as (c) | precompute s "
        "| fields MiB |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        prev = (
            f"{r['previous_ms']:.3f} | {r['this_ms']:.3f} | {r['previous_ms'] / r['this_ms']:.2f}x"
            if r["previous_ms"] and r["this_ms"]
            else "- | - | -"
        )
        print(
            f"| {r['home']} | {r['kind']} | {r['queries']} ({r['failures']}) | {r['median_ms']:.3f} | "
            f"{r['p95_ms']:.3f} | {r['p95_first_ms']:.3f} | {r['cpu_ms']:.3f} / {r['cpu_p95_ms']:.3f} | "
            f"{r['astar_ms']:.3f} ({r['astar_cpu_ms']:.3f}) | "
            f"{r['median_ms'] / r['astar_ms']:.1f} ({r['cpu_ms'] / r['astar_cpu_ms']:.1f}) | "
            f"{r['flat_ms']:.3f} | {r['median_ms'] / r['flat_ms']:.1f} | {prev} | {r['same_plans']} | "
            f"{r['precompute_s']:.3f} | "
            f"{r['field_bytes'] / 2**20:.1f} |"
        )
    for what, med, p95, astar in (
        ("wall", "median_ms", "p95_ms", "astar_ms"),
        ("CPU", "cpu_ms", "cpu_p95_ms", "astar_cpu_ms"),
    ):
        ok = all(r[med] <= 0.5 and r[p95] <= 1.0 for r in rows)
        ratio = all(r[med] <= 3 * r[astar] for r in rows)
        print(
            f"targets ({what} time): median <= 0.5 ms and p95 <= 1 ms: {'met' if ok else 'NOT met'}; "
            f"median <= 3x one pyastar2d query: {'met' if ratio else 'NOT met'}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
