"""Issue 35 on real ROS maps nobody here made: places, merges, goal points, a 0.30 m Nav2 body, names as taught.

    PYTHONPATH=. .venv/bin/python benchmarks/real_maps.py [--seeds 0-2] [--starts 3]

Maps (``tests/data/real_maps/``, provenance and licences in its README): Nav2's depot, the TurtleBot3 world (English
and Japanese teaching), the AWS RoboMaker small house; rooms taught by hand, 5-6 points each (``teach_points.txt``
beside each ``teaching.csv``). Per map and learner seed, ``learn``'s own path (10 runs of 100 sweeps, the kept run's
taught-merge split) and then, for the 0.30 m robot of ``benchmarks/robot_body.py``'s Nav2 params file
(``robot_radius`` 0.30, inflation 0.55 m, scaling 3), re-planned from the stored map:

1. **places**: how many taught rooms are a place of their own (the majority place of their teaching points is
   theirs alone), how many merges ``learn`` reports (``said_merges``) and how many pairs of differently named rooms
   share a place with neither name reported ("silent", the acceptance is 0);
2. **asked**: "go to the <name>" for every taught name; "there" when the plan's goal point is nearer to a teaching
   point of that room than to any other room's;
3. **body**: plans to every place from ``--starts`` start points, the poses in that body's inscribed cells
   (cost >= 253);
4. **goals**: each place's goal point under the paper's rule (the mean snapped to the nearest traversable cell: the
   highest published cost and the points of cost >= 50) and under the stop rule (``planning/stops.py``: published
   cost < 50): the points of cost >= 50 (places without such a cell left out, their count given), the distance from
   the place's mean (median / max m);
5. **names**: the active places' labels that are a taught name written as taught, of the taught names.
"""

from __future__ import annotations

import argparse
import copy
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository's benchmarks, from any folder
from benchmarks._args import parse_seeds  # noqa: E402
from benchmarks.merges import silent_merges  # noqa: E402
from benchmarks.robot_body import goal_points, nav2_body, poses_in  # noqa: E402
from spcotmhp.datasets.loader import load_dataset  # noqa: E402
from spcotmhp.errors import SpcotmhpError  # noqa: E402
from spcotmhp.metric.costmap import INSCRIBED_INFLATED_OBSTACLE, inflate  # noqa: E402
from spcotmhp.planning.body import with_body  # noqa: E402
from spcotmhp.planning.planner import HierarchicalPlanner  # noqa: E402
from spcotmhp.planning.stops import STOP_COST  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent / "tests" / "data" / "real_maps"
MAPS = (("nav2-depot", "en"), ("turtlebot3-world", "en"), ("turtlebot3-world", "ja"), ("aws-small-house", "en"))
ASK = {"en": "go to the {}", "ja": "{}に行って"}


@dataclass
class Row:
    """One map and seed's figures (module docstring, 1-5)."""

    rooms: int
    own: int
    reported: int
    silent: int
    asked: int
    there: int
    plans: int
    poses: int
    inscribed: int
    goals: int
    paper_max: float
    paper_costly: int
    costly: int
    no_stop: int
    from_mean: np.ndarray
    labels_as_taught: int
    labels: list[str]


def learned(data, seed: int):
    """``learn``'s model of ``data`` for ``seed`` (10 runs, the kept run split where the teaching says so) and the
    merges it reports."""
    from spcotmhp.learning.selection import fit_runs
    from spcotmhp.learning.taught_split import split_selected
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
    from spcotmhp.teaching.questions import name_vocabulary, said_merges

    sel = fit_runs(data, runs=10, seed=seed)
    words, labels = name_vocabulary(sel.model_), place_labels(sel.model_, place_vocabulary(sel.model_))
    split_selected(sel, data, words, labels)
    return sel.model_, said_merges(sel.model_)


def own_rooms(model, data) -> int:
    """Taught rooms whose teaching points' majority place is no other room's majority place."""
    place = np.asarray(model.learner["arrays"]["place"])[: len(data.truth_place)]
    home = [int(np.bincount(place[data.truth_place == r]).argmax()) for r in np.unique(data.truth_place)]
    return sum(home.count(h) == 1 for h in home)


def asked_there(planner: HierarchicalPlanner, data, start) -> tuple[int, int]:
    """(names asked, plans whose goal point is nearest a teaching point of the asked room)."""
    there = 0
    for room, name in enumerate(data.place_names):
        try:
            goal = planner.plan(ASK[data.lang].format(name), start).path[-1]
        except SpcotmhpError:  # refused (the name lost its place): not there
            continue
        there += int(data.truth_place[np.argmin(np.linalg.norm(data.positions - goal, axis=1))] == room)
    return len(data.place_names), there


def measure(folder: str, lang: str, seed: int, n_starts: int, body) -> Row:
    """Every figure of one map, language and learner seed."""
    data = load_dataset(ROOT / folder, lang=lang)
    model, found = learned(data, seed)
    mine = HierarchicalPlanner(with_body(copy.deepcopy(model), body))
    graph, occ = mine.graph, model.require_map()
    nodes = np.linspace(0, len(graph.node_cell) - 1, min(n_starts, len(graph.node_cell))).astype(int)
    starts = occ.cell_to_world(graph.to_map(graph.node_cell[nodes]))
    inscribed = inflate(occ, **mine.model.costmap).costs >= INSCRIBED_INFLATED_OBSTACLE
    plans, poses, hits = poses_in(mine, starts, inscribed)
    place, cost, dist, _ = goal_points(mine)
    _, paper_cost, _, _ = goal_points(HierarchicalPlanner(mine.model, stop_cost=None))
    kept = ~np.isin(place, list(mine.graph.info["stop_fallback"]))
    asked, there = asked_there(mine, data, tuple(starts[0]))
    act = np.flatnonzero(model.active_places)
    labels = [mine.shown[k] for k in act]
    return Row(
        rooms=len(data.place_names),
        own=own_rooms(model, data),
        reported=len(found),
        silent=silent_merges(model, data, found),
        asked=asked,
        there=there,
        plans=plans,
        poses=poses,
        inscribed=hits,
        goals=int(kept.sum()),
        paper_max=float(paper_cost.max()),
        paper_costly=int((paper_cost >= STOP_COST).sum()),
        costly=int((cost[kept] >= STOP_COST).sum()),
        no_stop=int((~kept).sum()),
        from_mean=dist[kept],
        labels_as_taught=len(set(labels) & set(data.place_names)),
        labels=labels,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="0-2", help="learner seeds, e.g. 0-2 (default)")
    parser.add_argument("--starts", type=int, default=3, help="start points per map (default 3)")
    parser.add_argument("--only", default=None, help="measure only the maps whose folder name contains this text")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    body = nav2_body()
    print("| map | seed | rooms | own place | merges reported | silent | asked: there | plans | poses | "
          "in the 0.30 m body's inscribed cells | goals | paper's rule: max cost / points >= 50 | "
          "stop rule: cost >= 50 | no stop cell | from the mean (median / max m) | labels as taught |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    shown = {}
    for folder, lang in (m for m in MAPS if args.only is None or args.only in m[0]):
        for seed in parse_seeds(args.seeds):
            r = measure(folder, lang, seed, args.starts, body)
            shown[(folder, lang)] = r.labels
            d = r.from_mean
            print(f"| {folder} ({lang}) | {seed} | {r.rooms} | {r.own} | {r.reported} | {r.silent} | "
                  f"{r.there} / {r.asked} | {r.plans} | {r.poses} | {r.inscribed} | {r.goals} | "
                  f"{r.paper_max:.0f} / {r.paper_costly} | {r.costly} | "
                  f"{r.no_stop} | {np.median(d):.2f} / {d.max():.2f} | {r.labels_as_taught} / {r.rooms} |",
                  flush=True)  # fmt: skip
    print()
    for (folder, lang), labels in shown.items():
        print(f"{folder} ({lang}), last seed's labels: {', '.join(labels)}")


if __name__ == "__main__":
    main()
