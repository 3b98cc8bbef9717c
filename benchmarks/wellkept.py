"""Our own implementations against the well-kept library ones, on their real workloads (issue 27).

    .venv/bin/python benchmarks/wellkept.py [--homes 3LDK_01 3LDK_05 3LDK_06] [--iterations 100] [--repeat 5]

Prints two markdown tables on stdout, each with the ratio library / ours measured in the same run (each time the
fastest of ``--repeat`` tries; numba compilation happens before any timing):

* the inverse-Wishart draw Sigma_k ~ IW(V_n, nu_n) of the NIW resample step (Eqs. 5-6,
  ``learning/distributions.sample_inverse_wishart_2d``), in the sampler's call pattern (one call per sweep with
  the K = 20 posterior scales of the model), against ``scipy.stats.invwishart.rvs`` (one call per place: it takes
  one scale): the call alone, and a whole Gibbs fit (``SpCoTMHP(iterations).fit``) on each home with either;
* territory growth from seeds (``learning/territory.partition``: each place's seed piece, then a breadth-first
  wave through the free cells) against ``scipy.ndimage`` (``label`` for each place's seed piece,
  ``watershed_ift`` from the seeds over a flat image for the growth), on the robot's free cells of each home
  with a supervised model's most probable places (what the planner's free regions and the "territory"
  connectivity compute); also how many cells the two assign differently (ties of the wave: cells equally far
  from two seeds).

Line rasterising and the English letter-to-sound rules are not timed here: no dependency has them (their
docstrings say why ours is kept).
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections.abc import Callable

import numpy as np
from scipy import ndimage
from scipy.stats import invwishart

from benchmarks._timing import best_of
from spcotmhp.datasets import load_bundled
from spcotmhp.learning import distributions
from spcotmhp.learning.distributions import GaussianStats
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.posterior import Priors
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.learning.territory import most_probable_labels, partition, place_anchors
from spcotmhp.metric.costmap import inflate


def scipy_inverse_wishart(rng: np.random.Generator, V: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """``sample_inverse_wishart_2d`` with scipy: one ``invwishart.rvs`` per place (it takes a single scale)."""
    return np.stack([invwishart.rvs(df=float(n), scale=v, random_state=rng) for v, n in zip(V, nu, strict=True)])


def scipy_partition(labels: np.ndarray, anchors: np.ndarray) -> np.ndarray:
    """:func:`partition`'s common case with scipy.ndimage: each place's seed is the 4-connected piece of its most
    probable cells that holds its anchor (``ndimage.label`` per place), then ``watershed_ift`` grows the seeds over
    a flat image (0 on the free cells, 255 elsewhere), and cells of free components without a seed get -1. (The
    pinned anchors of places most probable nowhere near their mean are left out: ours pins them.)"""
    four = ndimage.generate_binary_structure(2, 1)
    markers = np.zeros(labels.shape, dtype=np.int32)
    for k, (r, c) in enumerate(anchors):
        if labels[r, c] != k:
            continue
        pieces, _ = ndimage.label(labels == k, structure=four)
        markers[pieces == pieces[r, c]] = k + 1
    free = labels >= 0
    image = np.where(free, 0, 255).astype(np.uint8)
    grown = ndimage.watershed_ift(image, markers, structure=four).astype(np.int64) - 1
    comps, n = ndimage.label(free, structure=four)
    seeded = np.zeros(n + 1, dtype=bool)
    seeded[np.unique(comps[markers > 0])] = True
    seeded[0] = False
    return np.where(seeded[comps], grown, -1)


def _fit_seconds(data, iterations: int, repeat: int) -> tuple[float, float]:
    """The fastest of ``repeat`` Gibbs fits with our inverse-Wishart draw and with scipy's, alternating (both
    see the same machine load). The draws differ, so the two chains differ too, each seeded."""
    ours = distributions.sample_inverse_wishart_2d
    best = {ours: float("inf"), scipy_inverse_wishart: float("inf")}
    try:
        for _ in range(repeat):
            for draw in best:
                distributions.sample_inverse_wishart_2d = draw
                t0 = time.perf_counter()
                SpCoTMHP(iterations=iterations, seed=0).fit(data)
                best[draw] = min(best[draw], time.perf_counter() - t0)
    finally:
        distributions.sample_inverse_wishart_2d = ours
    return best[ours], best[scipy_inverse_wishart]


def inverse_wishart_rows(homes: list[str], iterations: int, repeat: int) -> list[str]:
    rows = []
    for name in homes:
        data = load_bundled(name)
        sampler = SpCoTMHP(iterations=2, seed=0).fit(data)  # compiles the kernels; its posterior scales below
        model = sampler.model_
        K = model.K
        gauss = Priors.build(model.hyper, model.L, K, len(model.vocabulary), None).gauss
        _m, _kappa, V, nu = gauss.posterior(GaussianStats.from_assignments(data.positions, sampler.places_, K))
        calls = 200

        def timed(draw: Callable, V=V, nu=nu, calls=calls) -> float:
            g = np.random.default_rng(1)
            t0 = time.perf_counter()
            for _ in range(calls):
                draw(g, V, nu)
            return (time.perf_counter() - t0) / calls

        ours_call = min(timed(distributions.sample_inverse_wishart_2d) for _ in range(repeat))
        scipy_call = min(timed(scipy_inverse_wishart) for _ in range(repeat))
        ours_fit, scipy_fit = _fit_seconds(data, iterations, repeat)
        rows.append(
            f"| {name} | {K} | {1e6 * ours_call:.1f} | {1e6 * scipy_call:.1f} | {scipy_call / ours_call:.1f}x "
            f"| {ours_fit:.3f} | {scipy_fit:.3f} | {scipy_fit / ours_fit:.2f}x |"
        )
    return rows


def territory_rows(homes: list[str], repeat: int) -> list[str]:
    rows = []
    for name in homes:
        data = load_bundled(name)
        model = fit_supervised(data)
        robot = inflate(data.map, **model.costmap).free
        labels = most_probable_labels(model, robot, data.map.cell_centres())
        anchors = place_anchors(model, robot)
        ours, t_ours, _, _ = best_of(repeat, partition, labels, anchors)
        theirs, t_scipy, _, _ = best_of(repeat, scipy_partition, labels, anchors)
        differ = int((ours != theirs).sum())
        rows.append(
            f"| {name} | {labels.shape[0]} x {labels.shape[1]} | {int((labels >= 0).sum())} | {len(anchors)} "
            f"| {1e3 * t_ours:.2f} | {1e3 * t_scipy:.2f} | {t_scipy / t_ours:.1f}x | {differ} |"
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--homes", nargs="+", default=["3LDK_01", "3LDK_05", "3LDK_06"])
    parser.add_argument("--iterations", type=int, default=100, help="Gibbs sweeps per timed fit")
    parser.add_argument("--repeat", type=int, default=5, help="tries per measurement, the fastest kept")
    args = parser.parse_args()
    warnings.simplefilter("ignore")  # the bundled data's known warnings and the truncation's are not measured
    print("Inverse-Wishart draw (Eqs. 5-6): one call with the K posterior scales, and a whole Gibbs fit\n")
    print(
        f"| home | K | ours us/call | scipy invwishart us/call | scipy / ours | fit s ({args.iterations} sweeps), "
        "ours | fit s, scipy | scipy / ours |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(inverse_wishart_rows(args.homes, args.iterations, args.repeat)))
    print("\nTerritory growth from seeds (learning/territory.partition) against scipy.ndimage\n")
    print(
        "| home | grid | free cells | places | ours ms | scipy.ndimage ms | scipy / ours | cells assigned differently |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(territory_rows(args.homes, args.repeat)))


if __name__ == "__main__":
    main()
