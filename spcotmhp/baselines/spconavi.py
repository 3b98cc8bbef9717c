"""SpCoNavi (Taniguchi et al. 2020b) on SpCoSLAM parameters: baselines (B) Viterbi and (C) A* approximation of
Experiment I (paper Section 4.2).

SpCoNavi plans by control as inference over every free cell for a horizon of T steps: the path maximises
``sum_t log w(x_t)`` under the deterministic motion model ``x_t = x_{t-1} + u_t``, u in {stay, up, down, left,
right}, with the per-cell weight

    w(x) = p(x | m) * sum_C Mult(S | W_C) pi_C sum_k phi_C(k) N(x | mu_k, Sigma_k)

(the cost map's free-space probability times the joint probability of the instruction words and the position;
paper Eqs. 17 and 28 without the topological term). For an advanced task the waypoint and goal words arrive
as one bag, as in the paper.

* :func:`viterbi`: exact max-product dynamic programming. Each step is a max over five shifted copies of the
  value array (numpy, log space), back-pointers kept as uint8: O(T * cells) (times in docs/results.md; the
  reference code's per-cell Python loops took about 45 minutes, the paper reports 2680 s).
* :func:`astar_approximation`: J goal cells drawn from the normalised w, the cheapest path to each with the
  objective's own step cost -log w, and the path whose SpCoNavi objective (the same sum over T steps) is highest
  is kept. The reference code drew the goals from the place Gaussians (sometimes inside walls), searched with a
  sign-flipped heuristic and kept the path of highest mean log w per cell.

Both use the paper's action set {stay, up, down, left, right} by default, as Experiment I specifies for
SpCoNavi (``connectivity=8`` adds the diagonals for other uses). Their paths are therefore 4-connected, while
SpCoTMHP, the A* baseline and the reference length l of SPL (an 8-connected geodesic) move 8-connected: on a
diagonal stretch a 4-connected path is up to sqrt 2 (41 %) longer, and SPL counts that against SpCoNavi. This
is the method as published, kept so the comparison is with SpCoNavi itself; it is said beside the results.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from spcotmhp.errors import PlanningError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.logspace import logsumexp
from spcotmhp.metric.grid_search import shortest_paths
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.planning.plan import Plan
from spcotmhp.planning.protocol import PlanVocabulary, StartPose, merged_bag, path_plan
from spcotmhp.planning.start import start_point

# (d_row, d_col) of each action; index = back-pointer value. 4-connected: the paper's action set.
ACTIONS_4 = np.array([(0, 0), (1, 0), (-1, 0), (0, -1), (0, 1)], dtype=np.int64)
ACTIONS_8 = np.vstack([ACTIONS_4, [(1, 1), (1, -1), (-1, 1), (-1, -1)]])


def log_weight_map(
    model: SpatialConceptModel,
    log_p: np.ndarray,
    cell_xy: np.ndarray,
    words: Sequence[str] | Mapping[str, float],
) -> np.ndarray:
    """log w(x) on every cell (module docstring): (H, W), -inf where log p(x|m) is -inf.

    Args:
        model: the spatial concept parameters.
        log_p: (H, W) log p(x|m) of the cost map (-inf blocked).
        cell_xy: (H, W, 2) world coordinates of the cell centres.
        words: the instruction's bag of words (unknown words are ignored by the model).
    """
    log_p = np.asarray(log_p, dtype=float)
    out = np.full(log_p.shape, -np.inf)
    ok = np.isfinite(log_p)
    lg = model.log_place_density(cell_xy[ok])  # (n, K)
    with np.errstate(divide="ignore"):
        log_phi, log_pi = np.log(model.phi), np.log(model.pi)  # (L, K), (L,)
    per_concept = logsumexp(lg[:, None, :] + log_phi[None, :, :], axis=2)  # (n, L)
    concept_prior = model.log_word_likelihood(words if isinstance(words, Mapping) else list(words)) + log_pi  # (L,)
    out[ok] = log_p[ok] + logsumexp(per_concept + concept_prior, axis=1)
    return out


@dataclass(frozen=True)
class ViterbiResult:
    """The most probable T-step path: cells (T + 1, 2) (row, col) including stays, and its log weight sum."""

    cells: np.ndarray
    log_prob: float


def viterbi(log_w: np.ndarray, start: tuple[int, int], T: int = 200, connectivity: int = 4) -> ViterbiResult:
    """Exact max-product decoding of ``argmax_{x_0 = start, x_1..x_T} sum_{t=1..T} log w(x_t)`` with moves
    restricted to cells of finite weight.

    Vectorised over cells: V_t = log w + max_a shift_a(V_{t-1}); ties prefer staying, then the action order of
    :data:`ACTIONS_4`. Work is confined to the bounding box of the finite-weight cells.

    Raises:
        PlanningError: the start cell is off the grid or has weight 0 (-inf), or T < 1.
    """
    log_w = np.asarray(log_w, dtype=float)
    if T < 1:
        raise PlanningError(f"the SpCoNavi horizon T must be >= 1, got {T}")
    actions = {4: ACTIONS_4, 8: ACTIONS_8}.get(connectivity)
    if actions is None:
        raise PlanningError(f"connectivity must be 4 or 8, got {connectivity}")
    height, width = log_w.shape
    r0, c0 = int(start[0]), int(start[1])
    if not (0 <= r0 < height and 0 <= c0 < width) or not np.isfinite(log_w[r0, c0]):
        raise PlanningError(f"start cell (row, col) = ({r0}, {c0}) is off the grid or not traversable")
    # crop to the finite cells reachable within T steps of the start (a box of radius T)
    rows, cols = np.nonzero(np.isfinite(log_w))
    top, bottom = max(rows.min(), r0 - T), min(rows.max(), r0 + T) + 1
    left, right = max(cols.min(), c0 - T), min(cols.max(), c0 + T) + 1
    lw = log_w[top:bottom, left:right]
    h, w = lw.shape
    value = np.full((h, w), -np.inf)
    value[r0 - top, c0 - left] = 0.0
    back = np.empty((T, h, w), dtype=np.uint8)
    cand = np.empty((len(actions), h, w))
    for t in range(T):
        cand.fill(-np.inf)
        for a, (dr, dc) in enumerate(actions):  # cand[a][r, c] = value[r - dr, c - dc]
            cand[a][max(dr, 0) : h + min(dr, 0), max(dc, 0) : w + min(dc, 0)] = value[
                max(-dr, 0) : h + min(-dr, 0), max(-dc, 0) : w + min(-dc, 0)
            ]
        best = cand.argmax(axis=0)
        back[t] = best
        value = np.take_along_axis(cand, best[None], axis=0)[0] + lw
    end = np.unravel_index(int(np.argmax(value)), value.shape)
    log_prob = float(value[end])
    cells = np.empty((T + 1, 2), dtype=np.int64)
    r, c = end
    for t in range(T, 0, -1):
        cells[t] = (r, c)
        dr, dc = actions[back[t - 1, r, c]]
        r, c = r - dr, c - dc
    cells[0] = (r, c)
    cells += (top, left)
    return ViterbiResult(cells, log_prob)


def horizon_objective(log_w: np.ndarray, cells: np.ndarray, T: int = 200) -> float:
    """The SpCoNavi objective of a given path over T steps: sum of log w over x_1..x_T, the path followed for
    its first T steps and then staying at its last cell (the A* approximation's selection criterion)."""
    cells = np.asarray(cells).reshape(-1, 2)
    vals = log_w[cells[1 : T + 1, 0], cells[1 : T + 1, 1]]
    stays = T - len(vals)
    return float(vals.sum() + (stays * log_w[cells[-1, 0], cells[-1, 1]] if stays > 0 else 0.0))


def sample_cells(log_w: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """n cells (n, 2) drawn with probability proportional to w (with replacement)."""
    flat = log_w.reshape(-1)
    ok = np.flatnonzero(np.isfinite(flat))
    if len(ok) == 0:
        raise PlanningError("the SpCoNavi weight map is zero everywhere (no traversable cell)")
    p = np.exp(flat[ok] - logsumexp(flat[ok]))
    pick = ok[rng.choice(len(ok), size=n, p=p / p.sum())]
    return np.stack(np.unravel_index(pick, log_w.shape), axis=1)


def astar_approximation(
    log_w: np.ndarray,
    start: tuple[int, int],
    rng: np.random.Generator,
    J: int = 10,
    T: int = 200,
    connectivity: int = 4,
) -> np.ndarray | None:
    """SpCoNavi's A* approximation: J goal cells drawn from the normalised w (the posterior p(x | S, m)), the
    cheapest path to each under the same per-step cost as the Viterbi objective, ``-log w(x) + log|A|`` (one
    Dijkstra run settles all J goals), and the path with the highest :func:`horizon_objective` kept.

    Returns the cells of the kept path, or None when no sampled goal is reachable.

    Raises:
        PlanningError: w exceeds |A| somewhere (a negative step cost; only for densities above |A| per m^2).
    """
    goals = sample_cells(log_w, J, rng)
    finite = np.isfinite(log_w)
    cost = np.full(log_w.shape, np.inf)
    cost[finite] = np.log(len(ACTIONS_4) if connectivity == 4 else len(ACTIONS_8)) - log_w[finite]
    if (cost < 0).any():
        raise PlanningError(
            "the SpCoNavi weight exceeds the number of actions somewhere: its step cost "
            "-log w + log|A| is negative there and A* cannot search it"
        )
    paths = shortest_paths(cost, start, goals, connectivity=connectivity, all_targets=True)
    found = {i: p.cells for i, p in enumerate(paths) if p is not None}
    scored = [(horizon_objective(log_w, cells, T), i) for i, cells in found.items()]
    if not scored:
        return None
    return found[max(scored)[1]]


class SpCoNaviPlanner:
    """Baselines (B) and (C) as a :class:`~spcotmhp.planning.protocol.Planner`: the waypoints' and the goal's
    words as one bag, log w on every cell of ``log_p`` (the cost map of ``occ_map``), then the exact Viterbi
    path (``approximation=False``) or the A* approximation with J goals drawn with ``rng`` (default: this
    planner's own generator, seeded by ``seed``); horizon T, the paper's action set unless ``connectivity=8``."""

    def __init__(
        self,
        model: SpatialConceptModel,
        log_p: np.ndarray,
        occ_map: OccupancyMap,
        approximation: bool = False,
        T: int = 200,
        J: int = 10,
        connectivity: int = 4,
        seed: int | None = None,
    ) -> None:
        self.vocabulary = PlanVocabulary(model)
        self.model, self.log_p, self.occ_map = model, log_p, occ_map
        self.cell_xy = occ_map.cell_centres()
        self.approximation, self.T, self.J, self.connectivity = approximation, T, J, connectivity
        self.rng = np.random.default_rng(seed)

    def plan(self, instruction: Any, start: StartPose, *, rng: np.random.Generator | None = None) -> Plan:
        t0 = time.perf_counter()
        ins = self.vocabulary.instruction(instruction)
        r, c = self.occ_map.world_to_cell(start_point(start))
        cell = (int(r), int(c))
        log_w = log_weight_map(self.model, self.log_p, self.cell_xy, merged_bag(ins))
        if self.approximation:
            cells = astar_approximation(
                log_w, cell, self.rng if rng is None else rng, self.J, self.T, self.connectivity
            )
        else:
            cells = viterbi(log_w, cell, self.T, self.connectivity).cells
        if cells is None:
            raise PlanningError("SpCoNavi: no sampled goal is reachable from the start")
        return path_plan(self.vocabulary, self.occ_map, cells, ins, t0)
