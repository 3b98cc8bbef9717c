"""Issue 35's figures: plans for another robot body, and goal points where a robot would stop.

    .venv/bin/python benchmarks/robot_body.py [--seeds 0-4] [--starts 3]

Homes: the bundled ones (3LDK_01, 3LDK_05, 3LDK_06, albert-b) and generated battery homes (the seeds, each bare
and furnished), supervised parameters learned once with the default body (a 0.22 m circle, inflation 1 m,
scaling 10). Prints two markdown tables on stdout:

1. Bodies: plans to every place from ``--starts`` start points (candidate nodes of the body's own graph), for a
   0.30 m robot read from a Nav2 params file (Nav2's footprint_padding 0.01 m, inflation 0.55 m, scaling 3) and for
   a 0.60 x 0.52 m footprint (centre 0.04 m behind the middle, inflation 0.8 m): the poses of the default body's
   plans and of the body's own plans in that body's inscribed cells (cost >= 253). Re-planned from the stored map;
   nothing learned again.
2. Stops: each place's goal point (its mean's candidate) under the paper's rule (nearest traversable cell of its
   territory) and under the stop rule (spcotmhp/planning/stops.py: the most probable cell of published cost < 50):
   the highest published cost and how many points have cost >= 50, the distance from the place's mean (median and
   largest), and the places without a stop cell (kept on the previous rule).
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from pathlib import Path

import numpy as np

from benchmarks._args import parse_seeds
from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.errors import PlanningError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.costmap import INSCRIBED_INFLATED_OBSTACLE, inflate
from spcotmhp.metric.nav2_params import resolve_body
from spcotmhp.planning.body import with_body
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.stops import STOP_COST, published_cost

NAV2 = """global_costmap:
  global_costmap:
    ros__parameters:
      robot_radius: 0.30
      plugins: ["static_layer", "inflation_layer"]
      inflation_layer:
        plugin: "nav2_costmap_2d::InflationLayer"
        inflation_radius: 0.55
        cost_scaling_factor: 3.0
"""
FOOTPRINT = "[[0.34, 0.26], [0.34, -0.26], [-0.26, -0.26], [-0.26, 0.26]]"


def nav2_body():
    """The 0.30 m robot of :data:`NAV2`, read as ``--nav2-params`` reads a params file."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "nav2_params.yaml"
        path.write_text(NAV2, encoding="utf-8")
        return resolve_body(path)


def homes(seeds: list[int]):
    """(name, dataset) of every home measured."""
    for name in ("3LDK_01", "3LDK_05", "3LDK_06", "albert-b"):
        yield name, load_bundled(name, lang="ja" if name == "albert-b" else "en")
    for seed in seeds:
        for furniture in (False, True):
            data = battery_home(seed, furniture=furniture)
            yield data.name, data


def poses_in(planner: HierarchicalPlanner, starts: np.ndarray, inscribed: np.ndarray) -> tuple[int, int, int]:
    """(plans, poses, poses in ``inscribed``) of a plan to every planned place from each start."""
    occ = planner.model.require_map()
    plans = poses = hits = 0
    for start in starts:
        for k in np.flatnonzero(planner.planned):
            try:
                plan = planner.plan({"goal": planner.names[k].split()}, tuple(start))
            except PlanningError:
                continue
            cells = occ.world_to_cell(plan.path)
            plans, poses = plans + 1, poses + len(cells)
            hits += int(np.count_nonzero(inscribed[cells[:, 0], cells[:, 1]]))
    return plans, poses, hits


def body_row(name: str, model, body, label: str, n_starts: int) -> str:
    """One row of table 1."""
    mine = HierarchicalPlanner(with_body(model, body))
    graph = mine.graph
    nodes = np.linspace(0, len(graph.node_cell) - 1, min(n_starts, len(graph.node_cell))).astype(int)
    starts = model.require_map().cell_to_world(graph.to_map(graph.node_cell[nodes]))
    inscribed = inflate(model.require_map(), **mine.model.costmap).costs >= INSCRIBED_INFLATED_OBSTACLE
    plans_d, poses_d, hits_d = poses_in(HierarchicalPlanner(model), starts, inscribed)
    plans_b, poses_b, hits_b = poses_in(mine, starts, inscribed)
    return f"| {name} | {label} | {plans_d} | {poses_d} | {hits_d} | {plans_b} | {poses_b} | {hits_b} |"


def goal_points(planner: HierarchicalPlanner) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(place, published cost, distance from the place's mean in metres, point) of each place's first candidate."""
    graph, model = planner.graph, planner.model
    first = np.r_[True, graph.node_place[1:] != graph.node_place[:-1]]
    place, cells = graph.node_place[first], graph.node_cell[first]
    cost = published_cost(graph.log_p)[cells[:, 0], cells[:, 1]]
    xy = model.require_map().cell_to_world(graph.to_map(cells))
    return place, cost, np.linalg.norm(xy - model.mu[place], axis=1), xy


def stop_row(name: str, model) -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
    """One row of table 2, and the distances from the mean under both rules and between the two points."""
    old_place, old_cost, old_d, old_xy = goal_points(HierarchicalPlanner(model, stop_cost=None))
    planner = HierarchicalPlanner(model)
    place, new_cost, new_d, new_xy = goal_points(planner)
    before = {int(k): xy for k, xy in zip(old_place, old_xy, strict=True)}
    moved = np.array(
        [np.linalg.norm(xy - before[int(k)]) for k, xy in zip(place, new_xy, strict=True) if int(k) in before]
    )
    fallback = set(planner.graph.info["stop_fallback"])
    kept = ~np.isin(place, list(fallback))
    row = (
        f"| {name} | {len(place)} | {old_cost.max():.0f} | {int((old_cost >= STOP_COST).sum())} | "
        f"{new_cost[kept].max():.0f} | {int((new_cost[kept] >= STOP_COST).sum())} | {len(fallback)} | "
        f"{np.median(old_d):.2f} / {old_d.max():.2f} | {np.median(new_d):.2f} / {new_d.max():.2f} | "
        f"{int((moved > 0).sum())} / {moved.max():.2f} |"
    )
    return row, old_d, new_d, moved


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="0-4", help="battery home seeds, e.g. 0-4 (default)")
    parser.add_argument("--starts", type=int, default=3, help="start points per home and body (default 3)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    bodies = [(nav2_body(), "0.30 m Nav2"), (resolve_body(footprint=FOOTPRINT, inflation_radius=0.8), "footprint")]
    rows1, rows2, old_all, new_all, moved_all = [], [], [], [], []
    for name, data in homes(parse_seeds(args.seeds)):
        model = fit_supervised(data)
        rows1 += [body_row(name, model, body, label, args.starts) for body, label in bodies]
        row, old_d, new_d, moved = stop_row(name, model)
        rows2.append(row)
        moved_all.append(moved)
        old_all.append(old_d)
        new_all.append(new_d)
    print("| home | body | default body: plans | poses | in the body's inscribed cells | the body: plans | poses "
          "| in its inscribed cells |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows1))
    print()
    print("| home | places | previous rule: max cost | points >= 50 | stop rule: max cost | points >= 50 | "
          "no stop cell | from the mean, previous (median / max m) | stop rule (median / max m) | "
          "moved (points / max m) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows2))
    old, new, moved = np.concatenate(old_all), np.concatenate(new_all), np.concatenate(moved_all)
    print(f"\nall {len(old)} places: from the mean {np.median(old):.2f} / {old.max():.2f} m (previous), "
          f"{np.median(new):.2f} / {new.max():.2f} m (stop rule); {int((moved > 0).sum())} points moved, "
          f"by {np.median(moved[moved > 0]) if (moved > 0).any() else 0:.2f} m median, "
          f"{moved.max():.2f} m at most")  # fmt: skip


if __name__ == "__main__":
    main()
