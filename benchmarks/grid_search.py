"""Benchmark of spcotmhp.metric.grid_search: query times on the bundled SIGVerse homes and a ratio against
pyastar2d (C++ A*) on the same weighted problems.

    .venv/bin/python benchmarks/grid_search.py [--repeats 5] [--pairs 20]

Prints two markdown tables on stdout (progress on stderr):

1. Control-as-inference planning on the three 192x192 homes (our move model: sqrt 2 diagonals, no squeezing
   between blocked cells): one A* query between two place centres with the destination's Gaussian cost map
   (Eq. 26; target <= 10 ms), and all 110 ordered paths between the 11 place centres (target <= 0.5 s), built
   with 11 cost maps + 11 cost-to-go fields, and with one cost map + 11 Dijkstra runs to all targets.
2. The same weighted problems given to pyastar2d and to our search with pyastar2d's model (entering a cell
   costs its weight, diagonals not scaled: ``diagonal_factor=1.0``; diagonal moves never blocked:
   ``corner_rule="free"``), checked to give the same path cost (pyastar2d accumulates in float32, so within a
   relative 1e-4); weights ``1 + costmap_2d cost (0..99)`` on the homes, and ``1 + 20 exp(-d / 5)`` (d the
   distance to the nearest wall in cells) on a seeded 1000x1000 map of random rectangular walls.

Times are the best of ``--repeats`` runs of each query (the two planners interleaved, so machine load hits
both alike), then the median over queries. numba compilation happens before any timing (``warmup``).
"""

from __future__ import annotations

import argparse
import itertools
import sys
from functools import partial
from pathlib import Path
from statistics import median

import numpy as np
import pyastar2d
from rich.console import Console
from rich.progress import Progress
from scipy import ndimage

from spcotmhp.metric.costmap import COST_TRANSLATION_TABLE, inflate
from spcotmhp.metric.grid_search import (
    cost_to_go,
    path_from_field,
    shortest_paths,
    step_cost_map,
    warmup,
)
from spcotmhp.metric.map_io import load_map

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the helper beside this script, however it is loaded
from _timing import best_of as fastest  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "spcotmhp" / "data" / "sigverse-3ldk"
HOMES = ("3LDK_01", "3LDK_05", "3LDK_06")


def best_of(fn, repeats: int) -> tuple[float, object]:
    """(best wall time in ms, result of the last call): :func:`_timing.best_of`."""
    out, best, _, _ = fastest(repeats, fn)
    return best * 1e3, out


def load_home(name: str):
    """Occupancy map, costmap_2d cost map, place means/covariances (truth places) and centre cells."""
    folder = DATA / name
    occ = load_map(folder / "map.yaml")
    cmap = inflate(occ)  # costmap_2d defaults of the bundled data: 0.22 / 1.0 / 10
    xy = np.loadtxt(folder / "teaching.csv", delimiter=",", skiprows=1, usecols=(1, 2))
    place = np.loadtxt(folder / "truth.csv", delimiter=",", skiprows=1, usecols=1, dtype=np.int64)
    labels = np.unique(place)
    mu = np.array([xy[place == k].mean(axis=0) for k in labels])
    sigma = np.array([np.cov(xy[place == k].T) + 1e-3 * np.eye(2) for k in labels])
    cells = occ.world_to_cell(mu)
    # snap a centre that falls on a blocked cell to the nearest free cell
    free = np.isfinite(cmap.log_p)
    _, (ri, ci) = ndimage.distance_transform_edt(~free, return_indices=True)
    snapped = np.stack([ri[cells[:, 0], cells[:, 1]], ci[cells[:, 0], cells[:, 1]]], axis=1)
    return occ, cmap, mu, sigma, snapped, int((snapped != cells).any(axis=1).sum())


def log_gaussian_grid(occ, mu: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """log N(x | mu, Sigma) at every cell centre (log space throughout)."""
    diff = occ.cell_centres() - mu
    maha = np.einsum("...i,ij,...j->...", diff, np.linalg.inv(sigma), diff)
    return -0.5 * maha - np.log(2 * np.pi) - 0.5 * np.log(np.linalg.det(sigma))


def plan_home(name: str, repeats: int) -> list[str]:
    """One table row: single queries and all 110 ordered paths between the place centres of one home."""
    occ, cmap, mu, sigma, centres, n_snapped = load_home(name)
    n = len(centres)
    log_n = [log_gaussian_grid(occ, mu[b], sigma[b]) for b in range(n)]
    costs = [step_cost_map(cmap.log_p, log_n[b], connectivity=8) for b in range(n)]
    single = []
    for a, b in itertools.permutations(range(n), 2):
        ms, path = best_of(partial(shortest_paths, costs[b], centres[a], [centres[b]]), repeats)
        assert path is not None, f"{name}: no path from place {a} to place {b}"
        single.append(ms)

    def all_pairs_fields():  # one Gaussian cost map (Eq. 26) and one cost-to-go field per destination
        out = []
        for b in range(n):
            field, nxt = cost_to_go(step_cost_map(cmap.log_p, log_n[b], connectivity=8), [centres[b]])
            out += [path_from_field(field, nxt, centres[a], resolution=occ.resolution) for a in range(n)]
        return out

    plain = step_cost_map(cmap.log_p, connectivity=8)

    def all_pairs_dijkstra():  # one cost map, one Dijkstra run to all centres per start
        return [shortest_paths(plain, centres[a], centres, all_targets=True) for a in range(n)]

    t_fields, paths = best_of(all_pairs_fields, repeats)
    assert all(p is not None for p in paths)
    t_dijkstra, _ = best_of(all_pairs_dijkstra, repeats)
    return [
        name,
        f"{occ.height}x{occ.width}",
        f"{median(single):.2f}",
        f"{max(single):.2f}",
        f"{t_fields:.1f}",
        f"{t_dijkstra:.1f}",
        str(n_snapped),
    ]


def synthetic_weights(size: int = 1000, n_walls: int = 400, seed: int = 0) -> np.ndarray:
    """Seeded map of random rectangular walls; weight 1 + 20 exp(-d / 5) with d the distance to a wall."""
    rng = np.random.default_rng(seed)
    wall = np.zeros((size, size), dtype=bool)
    for _ in range(n_walls):
        r, c = rng.integers(0, size, 2)
        if rng.random() < 0.5:
            h, w = rng.integers(2, 6), rng.integers(20, 150)
        else:
            h, w = rng.integers(20, 150), rng.integers(2, 6)
        wall[r : r + h, c : c + w] = True
    d = ndimage.distance_transform_edt(~wall)
    weights = (1.0 + 20.0 * np.exp(-d / 5.0)).astype(np.float32)
    weights[wall] = np.inf
    return weights


def random_pairs(weights: np.ndarray, n: int, seed: int) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """n (start, goal) pairs of cells in the largest 4-connected free component."""
    labels, _ = ndimage.label(np.isfinite(weights))
    largest = np.argmax(np.bincount(labels.ravel())[1:]) + 1
    cells = np.argwhere(labels == largest)
    rng = np.random.default_rng(seed)
    picks = cells[rng.integers(0, len(cells), size=(n, 2))]
    return [((int(s[0]), int(s[1])), (int(g[0]), int(g[1]))) for s, g in picks]


def compare_with_pyastar2d(name: str, weights: np.ndarray, pairs, repeats: int) -> list[list[str]]:
    rows = []
    for connectivity in (4, 8):
        ours_ms, theirs_ms = [], []
        for start, goal in pairs:
            ours_query = partial(
                shortest_paths, weights, start, [goal], connectivity, diagonal_factor=1.0, corner_rule="free"
            )
            ms_ours, ours = best_of(ours_query, repeats)
            theirs_query = partial(pyastar2d.astar_path, weights, start, goal, allow_diagonal=connectivity == 8)
            ms_theirs, theirs = best_of(theirs_query, repeats)
            assert (ours is None) == (theirs is None), f"{name}: reachability differs for {start} -> {goal}"
            if ours is not None:
                their_cost = float(weights[theirs[1:, 0], theirs[1:, 1]].astype(np.float64).sum())
                agree = abs(ours.cost - their_cost) <= 1e-4 * their_cost
                assert agree, f"{name}: {start} -> {goal} costs {ours.cost} (ours), {their_cost} (pyastar2d)"
            ours_ms.append(ms_ours)
            theirs_ms.append(ms_theirs)
        ours_med, theirs_med = median(ours_ms), median(theirs_ms)
        rows.append(
            [
                name,
                str(connectivity),
                str(len(pairs)),
                f"{ours_med:.3f}",
                f"{theirs_med:.3f}",
                f"{ours_med / theirs_med:.2f}",
            ]
        )
    return rows


def comparison_rows(repeats: int, n_pairs: int, progress: Progress) -> list[list[str]]:
    rows = []
    task = progress.add_task("pyastar2d comparison", total=len(HOMES) + 1)
    for name in HOMES:
        _, cmap, _, _, centres, _ = load_home(name)
        ros = COST_TRANSLATION_TABLE[cmap.costs].astype(np.float32)
        weights = np.where(np.isfinite(cmap.log_p), 1.0 + ros, np.inf).astype(np.float32)
        pairs = [
            ((int(a[0]), int(a[1])), (int(b[0]), int(b[1])))
            for i, a in enumerate(centres)
            for j, b in enumerate(centres)
            if i != j
        ]
        rows += compare_with_pyastar2d(f"{name} (192x192)", weights, pairs, repeats)
        progress.advance(task)
    weights = synthetic_weights()
    rows += compare_with_pyastar2d("synthetic 1000x1000", weights, random_pairs(weights, n_pairs, seed=1), repeats)
    progress.advance(task)
    return rows


def markdown(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs per query; the best is kept")
    parser.add_argument("--pairs", type=int, default=20, help="start/goal pairs on the 1000x1000 map")
    args = parser.parse_args()
    warmup()
    with Progress(console=Console(stderr=True), transient=True) as progress:
        task = progress.add_task("homes: control-as-inference planning", total=len(HOMES))
        planning = []
        for name in HOMES:
            planning.append(plan_home(name, args.repeats))
            progress.advance(task)
        comparison = comparison_rows(args.repeats, args.pairs, progress)
    print("Control-as-inference planning on the bundled homes (8-connected, sqrt 2 diagonals)\n")
    print(
        markdown(
            [
                "home",
                "cells",
                "one query, median ms",
                "one query, max ms",
                "110 paths via 11 fields, ms",
                "110 paths via 11 Dijkstra, ms",
                "centres snapped",
            ],
            planning,
        )
    )
    print("\nSame weighted problems as pyastar2d (C++ A*), pyastar2d's move model\n")
    print(
        markdown(
            [
                "problem",
                "connectivity",
                "queries",
                "ours median ms",
                "pyastar2d median ms",
                "ratio ours/pyastar2d",
            ],
            comparison,
        )
    )


if __name__ == "__main__":
    main()
