"""The precomputed planning graph (Algorithm 1, lines 1-7): candidate points, partial paths and their w-hat.

Partial paths (Eqs. 26-27, control as inference). The paper observes optimality o_t = 1 at every time step of a
leg, with p(o_t = 1 | x_t) = N(x_t | mu_b, Sigma_b) of the leg's destination b, so a leg's log-likelihood sums
log N(x_t | mu_b, Sigma_b) over *every* cell: it grows with the squared distance from mu_b along the whole
leg, not with the leg's length, and Eq. 28 then prefers a farther instance of a shared name whose Gaussian is
broad along the approach (the README gives the measurement). We observe optimality once per leg, at its end,
the event of Eqs. 3-4 that closes the HSMM segment (o_t = 1 only at t = t'_e):

    w_hat[i, j] = sum_{t in leg} [log p(x_t|m) - log|A|]  +  log N(x_j | mu_b, Sigma_b)     (Eq. 24, end-observed)

i.e. the uniform action prior p(x_t | x_{t-1}, u_t) = 1/|A| and the map term of Eq. 24 along the leg (their
negative sum is the cost of the leg under the step cost ``log|A| - log p(x|m)``, a length weighted by the
inflation cost), and the destination's Gaussian at the candidate point the leg ends in. The best leg into node
j is then the same for every destination place, so one cost-to-go field per node gives

* the partial path from any candidate i into j (Eq. 27) and ``w_hat[i, j] = -field_j[cell_i] + log N(x_j |
  mu_b, Sigma_b)``, between every pair of candidates (Algorithm 1, line 3: "a graph between the waypoint
  candidates for all nodes"; ``w_hat_metric``, ``log_transition_all``) and restricted to Figure 3's connected
  places (``w_hat``, ``log_transition``: the reference code's graph, which HPP-I/II use);
* the start leg from *any* start pose x_0 to j (``-field_j[x_0] + log N(x_j | ...)``), which makes online
  planning from any start a table look-up (the reference code ran an exhaustive grid search per query).

Steps into a diagonal neighbour weigh sqrt 2. Every step cost is at least log|A| > 0, so shortest paths are
well defined.

The paper's Eq. 24 as written (``GraphSettings.optimality = "every_step"``, to compare methods): optimality is
observed at every cell of a leg, so the step cost into a cell x of a leg towards node j of place b is
``log|A| - log p(x|m) - log N(x | mu_b, Sigma_b)`` (:func:`~spcotmhp.metric.grid_search.step_cost_map`; the
reference code's ``log 5 - log(p N)`` on its 4-connected grid), one cost-to-go field per node over its own step
cost, ``w_hat[i, j] = -field_j[cell_i]`` and the end term 0 (the node's cell is the leg's last step, counted in the
field; a negative step cost is refused, :func:`~spcotmhp.planning.precompute.every_step_cost`). It needs the
dense fields (the portal graph shares one step cost between destinations).

The grid is the robot's: p(x|m) = 0 on occupied, unknown, lethal and inscribed cells (:mod:`spcotmhp.metric.
costmap`), so no partial path, start leg or smoothed path puts the robot's centre where its footprint overlaps
an obstacle. Candidate points are snapped into their own place's territory (:mod:`spcotmhp.learning.territory`)
within the largest free region; every other free region that holds places (a place reaches a region where its
2-sigma ellipse holds a cell of it: :mod:`spcotmhp.planning.regions`) has a graph of its own, on its own window
(``regions``), and a plan starts in the graph of the start's region (:meth:`PlanningGraph.for_start`). A place
with a node in no region is reported in ``info["unreachable_places"]``.

Avoided places (:func:`spcotmhp.planning.avoid.avoided_view`) block their territories, in views that share the fields a
blocked region does not change (:mod:`spcotmhp.planning.avoid`).

For path smoothing (Algorithm 1, line 13; :mod:`spcotmhp.planning.assemble`) the graph also keeps each cell's
territory, every place's territory grown by ``tube_margin`` metres (a window and a mask each;
:mod:`spcotmhp.planning.territory`), and the map-only step cost ``log|A| - log p(x|m)``
(:attr:`PlanningGraph.map_cost`).

At building scale the per-node fields over the whole crop (M x h x w) do not fit: beyond
``GraphSettings.max_dense_bytes`` the fields are territory-local and the nodes are joined through a portal graph
(HPA* with the territories as clusters, :mod:`spcotmhp.planning.hierarchy`): the same step cost, the same queries
(``start_w_hat``, ``leg``, ``edge_path``, ``field_piece``, avoidance views, ``cost_to_nodes``), ``dist`` and
``next_step`` empty, and :meth:`PlanningGraph.update_place` / :meth:`PlanningGraph.update` recompute only the
fields of territories whose cells or costs changed.

Everything is computed on the bounding box of the traversable cells (``offset``; the crop, territories and
candidates: :mod:`spcotmhp.planning.precompute`). A graph is cached only in a
:class:`~spcotmhp.planning.graph_cache.GraphCache` its caller owns and passes to :meth:`PlanningGraph.build`,
keyed by a hash of the model parameters, the map and the settings, so a changed model or map never reuses a stale
graph.

Memos and threads: queries fill memos in a graph (``_paths``, the partial paths extracted so far; ``_views``, the
avoidance views, in a :class:`GraphCache` of their own with its own lock; a view's fields recomputed for a start;
the lazily computed ``map_cost``, ``clearance`` and ``centres``). The partial paths and a view's fields are
guarded by the graph's own lock (``_lock``), held only around reading and storing a memo, so concurrent queries
from threads on one graph are safe and give the same answers as sequential ones; the lazy values are computed from
the graph's read-only arrays and assigned whole (a race at worst computes one twice).
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, field

import numpy as np

import spcotmhp.planning.hierarchy as hierarchy
from spcotmhp.collector import paused
from spcotmhp.errors import InvalidSettings, ModelError, PlanningError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.grid_search import SQRT2, GridPath, cost_to_go, path_from_field
from spcotmhp.planning._paths import cells_cost, field_path_within, octile_length, start_legs
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.graph_settings import GraphSettings, fingerprint
from spcotmhp.planning.graph_update import reusable_fields, same_cost_map, with_place
from spcotmhp.planning.precompute import every_step_cost, graph_inputs
from spcotmhp.planning.sight import chessboard_clearance
from spcotmhp.planning.territory import tube_window

AVOID_CACHE_SIZE = 32  # avoidance views a graph keeps (planning/avoid.py)


@dataclass
class PlanningGraph:
    """Candidate nodes, cost-to-go fields and partial-path likelihoods for one model + map + settings.

    Grids (``log_p``, ``traversable``, ``dist[j]``, ``next_step[j]``) cover the crop ``offset`` .. ``offset +
    shape`` of the map; node cells are in crop coordinates (add ``offset`` for map cells). A view made by
    :func:`~spcotmhp.planning.avoid.avoided_view` has ``blocked`` (crop mask) and ``usable`` (nodes outside the
    avoided places).
    """

    model: SpatialConceptModel
    settings: GraphSettings
    key: str
    offset: tuple[int, int]
    log_p: np.ndarray
    traversable: np.ndarray
    node_place: np.ndarray
    node_cell: np.ndarray
    dist: np.ndarray | list  # (M, h, w) cost to go into node j over c_place[j] (a list in views)
    next_step: np.ndarray | list  # (M, h, w) flat index of the next cell (-1 at the node / unreachable)
    end_term: np.ndarray  # (M,) log N(x_j | mu_b, Sigma_b) at each node (optimality at a leg's end)
    w_hat: np.ndarray  # (M, M) partial-path log-likelihoods, -inf if not connected/unreachable
    w_hat_metric: np.ndarray  # (M, M) the same between any two nodes (the metric fallback's legs)
    log_transition: np.ndarray  # (M, M) log psi - log UR + w_hat (the per-step factor of Eq. 28 w/o words)
    connected: np.ndarray  # (K, K) connected places
    time_precompute_s: float
    territory: np.ndarray  # (h, w) place of each cell of the graph's free region (-1 elsewhere)
    main: np.ndarray  # (h, w) the graph's free region (where its nodes are): the largest one, or a region's own
    usable: np.ndarray  # (M,) nodes outside the avoided places (all True outside an avoidance view)
    log_transition_all: np.ndarray = field(default_factory=lambda: np.empty(0))  # log_transition, any two nodes
    _territories: dict = field(default_factory=dict, repr=False)  # place -> (row, col, grown mask)
    _map_cost: np.ndarray | None = field(default=None, repr=False)
    _clearance: np.ndarray | None = field(default=None, repr=False)
    info: dict = field(default_factory=dict)
    _paths: dict = field(default_factory=dict, repr=False)
    _centres: np.ndarray | None = field(default=None, repr=False)
    blocked: np.ndarray | None = None  # (h, w) cells of the avoided territories (None outside an avoidance view)
    _shared: set = field(default_factory=set, repr=False)  # fields still shared with the base graph
    _base_fields: tuple | None = field(default=None, repr=False)  # the base graph's (dist, next_step) arrays
    _views: GraphCache = field(default_factory=lambda: GraphCache(AVOID_CACHE_SIZE), repr=False, compare=False)
    hier: hierarchy.TerritoryFields | None = None  # territory-local fields (when dense ones exceed the budget)
    region: np.ndarray | None = None  # (h, w) free region label of each traversable cell (0 elsewhere; main graph)
    plannable: np.ndarray | None = None  # (h, w) cells of the regions that hold places (main graph)
    regions: dict = field(default_factory=dict, repr=False)  # region label -> the graph of that free region
    _lock: threading.RLock = field(default_factory=threading.RLock, repr=False, compare=False)  # guards memos

    def __getstate__(self) -> dict:
        """Pickled (a process pool's or Ray's copy of a planner) without the lock; the copy gets its own."""
        state = self.__dict__.copy()
        del state["_lock"]
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._lock = threading.RLock()

    # ---- construction ----------------------------------------------------------------------------------
    @classmethod
    def build(
        cls,
        model: SpatialConceptModel,
        settings: GraphSettings | None = None,
        log_p: np.ndarray | None = None,
        cache: GraphCache | None = None,
        reuse: PlanningGraph | None = None,
    ) -> PlanningGraph:
        """Precompute (or fetch from ``cache``, when one is given, or load the one saved with a model loaded from a
        folder: :mod:`spcotmhp.planning.graph_store`; ``info["graph_source"]`` says which) the graph of ``model``
        on its map. ``log_p``
        overrides the cost map log p(x|m) (default: costmap_2d inflation of ``model.map`` with ``model.costmap``
        settings).
        ``reuse``: an earlier graph (same map size) whose territory-local fields are kept wherever a territory's
        cells and costs did not change (:mod:`spcotmhp.planning.hierarchy`); the result is the same as without."""
        settings = settings or GraphSettings()
        if model.map is None:
            raise ModelError("the model has no map; planning needs the occupancy map it was learned on")
        if not np.any(model.active_places):
            raise ModelError("the model has no active place to plan with")
        key = fingerprint(model, settings, log_p)

        def make() -> PlanningGraph:
            note = "built"
            if log_p is None and reuse is None and model.folder is not None:
                from spcotmhp.planning.graph_store import load_saved

                saved, note = load_saved(model, settings, key, cls)
                if saved is not None:
                    saved.info["graph_source"] = note
                    return saved
            graph = cls._compute(model, settings, key, log_p, reuse)
            graph.info["graph_source"] = note
            return graph

        return make() if cache is None else cache.get_or_build(key, make)

    @classmethod
    def _compute(cls, model, settings, key, log_p_full, reuse=None) -> PlanningGraph:
        """The precomputation, with automatic garbage collection paused (:func:`spcotmhp.collector.paused`: it
        makes long-lived arrays and, in a fresh process, numba's registries; collecting meanwhile frees nothing)."""
        t0 = time.perf_counter()
        with paused():
            if log_p_full is None and reuse is not None:
                log_p_full = same_cost_map(reuse, model)
            inputs, subs = graph_inputs(model, settings, log_p_full)  # Alg. 1, lines 1-3
            graph = cls(key=key, **inputs)
            graph._fields(reuse)
            graph._edges()
            for label, sub_inputs in subs.items():  # every other free region with places: a graph of its own
                t1 = time.perf_counter()
                sub = cls(key=f"{key}/region-{label}", **sub_inputs)
                sub._fields(None if reuse is None else reuse.regions.get(label))
                sub._edges()
                sub.time_precompute_s = time.perf_counter() - t1
                graph.regions[label] = sub
            graph.info["regions"] = len(graph.regions)
            graph.info["field_bytes"] = graph.field_bytes
        graph.time_precompute_s = time.perf_counter() - t0
        return graph

    def _fields(self, reuse: PlanningGraph | None) -> None:
        """The cost-to-go fields into every node (Alg. 1, lines 4-6): dense (M, h, w) ones when they fit in
        ``max_dense_bytes``, else territory-local ones joined by a portal graph (module docstring), keeping those
        of ``reuse`` whose territory did not change."""
        cells, occ = self.node_cell, self.model.require_map()
        dense = self.settings.dense(len(cells), self.log_p.size)
        if not dense and self.settings.optimality == "every_step":
            raise InvalidSettings(
                f"optimality 'every_step' needs one dense field per node ({12 * len(cells) * self.log_p.size} "
                f"bytes), more than max_dense_bytes = {self.settings.max_dense_bytes}; raise it or use 'end'"
            )
        if dense:
            kept = reusable_fields(reuse, self)
            fields = [kept.get((int(r), int(c))) or self._field(j) for j, (r, c) in enumerate(cells)]
            self.info["fields_reused"] = sum((int(r), int(c)) in kept for r, c in cells)
            self.dist = np.stack([d for d, _ in fields])  # (M, h, w), shared by avoidance views
            self.next_step = np.stack([n for _, n in fields])
            return
        old = reuse.hier if reuse is not None and reuse.offset == self.offset else None
        self.hier = hierarchy.build(
            self.map_cost,
            self.territory,
            cells,
            self.model.K,
            round(self.settings.portal_spacing / occ.resolution),
            self.settings.connectivity,
            reuse=old,
        )
        self.info.update(self.hier.info)

    def _field(self, j: int) -> tuple[np.ndarray, np.ndarray]:
        """The cost-to-go field into node j (Alg. 1, lines 4-6) under the step cost log|A| - log p(x|m) (minus
        log N(x | mu_b, Sigma_b) of node j's place b with ``optimality = "every_step"``), with the blocked cells
        blocked (module docstring)."""
        cost = self.map_cost
        if self.settings.optimality == "every_step":
            cost = every_step_cost(self.model, self.map_cost, self.centres, int(self.node_place[j]))
        return cost_to_go(cost, self.node_cell[j][None, :], self.settings.connectivity, SQRT2)

    def _edges(self) -> None:
        """w-hat of the partial paths between candidates of connected places (Alg. 1, line 6) and the per-step
        factor of Eq. 28 without the word term."""
        M = self.n_nodes
        rows, cols = self.node_cell[:, 0], self.node_cell[:, 1]
        w_hat = np.full((M, M), -np.inf)
        for j in np.flatnonzero(self.usable):  # -field_j[cell_i] + log N(x_j)
            to_j = self.hier.portal_cost[:M, j] if self.hier is not None else self.dist[j][rows, cols]
            w_hat[:, j] = self.end_term[j] - to_j
        pairs = ~np.eye(M, dtype=bool) & self.usable[:, None] & self.usable[None, :]
        self.w_hat_metric = np.where(pairs, w_hat, -np.inf)
        allowed = pairs & self.connected[self.node_place[:, None], self.node_place[None, :]]
        self.w_hat = np.where(allowed, w_hat, -np.inf)
        with np.errstate(divide="ignore"):
            log_psi = self.model.log_psi()[self.node_place[:, None], self.node_place[None, :]]
        log_ur = self.model.log_unigram_rescaling()[self.node_place]
        self.log_transition = np.where(np.isfinite(self.w_hat), log_psi - log_ur[None, :] + self.w_hat, -np.inf)
        self.log_transition_all = np.where(
            np.isfinite(self.w_hat_metric), log_psi - log_ur[None, :] + self.w_hat_metric, -np.inf
        )
        self._paths = {}

    # ---- queries ---------------------------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return len(self.node_place)

    def to_crop(self, cells: np.ndarray) -> np.ndarray:
        return np.asarray(cells) - np.array(self.offset)

    def to_map(self, cells: np.ndarray) -> np.ndarray:
        return np.asarray(cells) + np.array(self.offset)

    def in_crop(self, cell: np.ndarray) -> bool:
        h, w = self.log_p.shape
        return bool(0 <= cell[0] < h and 0 <= cell[1] < w)

    def start_w_hat(self, cell: np.ndarray) -> np.ndarray:
        """(M,) log-likelihood of the best start leg from crop cell ``cell`` into each node (-inf: none).

        In an avoidance view, a shared field whose path from ``cell`` enters the blocked region is recomputed
        first (and kept), so the value is exact for the blocked map (:class:`~spcotmhp.planning.avoid.
        AvoidanceView`)."""
        if self.hier is None and isinstance(self.dist, np.ndarray):  # dense fields: one kernel, the same values
            return start_legs(self.dist, int(cell[0]), int(cell[1]), self.usable, self.end_term)
        return np.where(self.usable, self.end_term - self.cost_to_nodes(cell), -np.inf)

    def cost_to_nodes(self, cell: np.ndarray) -> np.ndarray:
        """(M,) the cost of the best path from crop cell ``cell`` into each node (the fields' value there; inf:
        none). In an avoidance view call :meth:`start_w_hat` first (it makes shared fields exact there)."""
        if self.hier is not None:
            return self.hier.cost_to_nodes(cell)
        r, c = int(cell[0]), int(cell[1])
        if isinstance(self.dist, np.ndarray):
            return self.dist[:, r, c].astype(float)
        if self._base_fields is not None:  # a view: its graph's fields, except those it recomputed
            out = self._base_fields[0][:, r, c].astype(float)
            for j in self.info["recomputed_fields"]:
                out[j] = self.dist[j][r, c]
            return out
        return np.array([self.dist[j][r, c] for j in range(self.n_nodes)], dtype=float)

    @property
    def field_bytes(self) -> int:
        """Bytes held by the cost-to-go fields and next-step links (and the portal graph's tables), the other free
        regions' graphs included."""
        own = (
            self.hier.nbytes
            if self.hier is not None
            else sum(np.asarray(d).nbytes for d in self.dist) + sum(np.asarray(n).nbytes for n in self.next_step)
        )
        return int(own + sum(sub.field_bytes for sub in self.regions.values()))

    def for_start(self, cell: np.ndarray) -> tuple[PlanningGraph, np.ndarray]:
        """The graph of the free region holding crop cell ``cell`` (this one in its own region; the region's graph
        in another, :mod:`spcotmhp.planning.regions`) and the cell in that graph's crop."""
        r, c = int(cell[0]), int(cell[1])
        if not self.regions or self.region is None or self.main[r, c]:
            return self, cell
        sub = self.regions.get(int(self.region[r, c]))
        if sub is None:
            return self, cell
        return sub, np.asarray(cell) - (np.array(sub.offset) - np.array(self.offset))

    def places_planned(self) -> np.ndarray:
        """(K,) bool: the places with a node in this graph or in one of its other free regions' graphs."""
        out = np.zeros(self.model.K, dtype=bool)
        for g in (self, *self.regions.values()):
            out[g.node_place] = True
        return out

    def leg(self, cell: np.ndarray, node: int) -> GridPath:
        """The best path from crop cell ``cell`` into ``node`` (crop cells)."""
        if self.hier is None:
            return path_from_field(self.dist[node], self.next_step[node], cell, strict=True)
        cells = self.hier.path(cell, node)
        if cells is None:
            raise PlanningError(
                f"start cell ({int(cell[0])}, {int(cell[1])}) cannot reach node {node} (blocked or disconnected)"
            )
        diagonal = int(np.count_nonzero(np.abs(np.diff(cells, axis=0)).sum(axis=1) == 2))
        return GridPath(cells, float(cells_cost(cells, self.map_cost)), len(cells) - 1 + diagonal * (SQRT2 - 1), -1)

    def edge_path(self, i: int, j: int) -> np.ndarray:
        """The partial path (crop cells) from node i into node j (Eq. 27), extracted once and memoised (under the
        graph's lock; module docstring)."""
        with self._lock:
            cells = self._paths.get((i, j))
        if cells is None:
            cells = self.leg(self.node_cell[i], j).cells
            with self._lock:
                cells = self._paths.setdefault((i, j), cells)
        return cells

    def field_piece(
        self, cells: np.ndarray, a: int, b: int, ends: np.ndarray, nodes: np.ndarray, places: np.ndarray
    ) -> np.ndarray | None:
        """An answer of the tube re-planning of the piece ``cells[a:b + 1]`` (which ends at a node, ``cells[b]``)
        read from that node's field, or None when the field's path leaves the tube (:mod:`spcotmhp.planning.
        _paths`). ``ends[e]``: index in ``cells`` where ``nodes[e]`` is reached; ``places``: the tube's places.
        A piece that is one leg is already that field's path."""
        inner = (ends > a) & (ends < b)
        if not inner.any():
            return cells[a : b + 1]
        node = int(nodes[np.flatnonzero(ends == b)[-1]])
        flags = np.zeros(self.model.K, dtype=np.bool_)
        flags[places[places >= 0]] = True
        piece = cells[a : b + 1]
        if self.hier is not None:  # the portal graph's path, if it stays in the tube's territories
            path = self.hier.path(piece[0], node)
            return path if path is not None and flags[self.territory[path[:, 0], path[:, 1]]].all() else None
        (r0, c0), (r1, c1), half = piece[0].tolist(), piece[-1].tolist(), octile_length(piece) / 2
        mid_r, mid_c = (r0 + r1) / 2, (c0 + c1) / 2  # the window of replan_segment, in scalars
        width = self.log_p.shape[1]
        path, ok = field_path_within(
            self.next_step[node].reshape(-1),
            r0 * width + c0,
            width,
            self.territory,
            flags,
            max(math.floor(mid_r - half), 0),
            max(math.floor(mid_c - half), 0),
            math.ceil(mid_r + half) + 1,
            math.ceil(mid_c + half) + 1,
            self.map_cost,
        )
        return path if ok else None

    @property
    def map_cost(self) -> np.ndarray:
        """(h, w) the step cost of Eq. 26 with the map term only, log|A| - log p(x|m), +inf off the traversable
        cells (so also on an avoidance view's blocked cells); computed once per graph or view."""
        if self._map_cost is None:
            n_actions = self.settings.connectivity + 1
            self._map_cost = np.where(self.traversable, math.log(n_actions) - self.log_p, np.inf)
        return self._map_cost

    @property
    def clearance(self) -> np.ndarray:
        """(h, w) chessboard distance of each traversable cell to the nearest cell that is not
        (:func:`~spcotmhp.planning.sight.chessboard_clearance`; what line-of-sight tests skip by), once per graph."""
        if self._clearance is None:
            self._clearance = chessboard_clearance(self.traversable)
        return self._clearance

    def tube(self, places: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(origin, mask)``: the smallest window of the crop (corner at crop cell ``origin``) that holds the
        territories of ``places`` grown by ``tube_margin``, and their union in it."""
        return tube_window(self._territories, places)

    def centres_at(self, cells: np.ndarray) -> np.ndarray:
        """(n, 2) map-frame centres of the crop cells ``cells`` (the values of :attr:`centres` there, without the
        whole crop's: 16 bytes a cell)."""
        if self._centres is not None:
            return self._centres[cells[:, 0], cells[:, 1]]
        return self.model.require_map().cell_to_world(np.asarray(cells) + self.offset)

    @property
    def centres(self) -> np.ndarray:
        """(h, w, 2) map-frame centres of the crop's cells."""
        if self._centres is None:
            r0, c0 = (int(v) for v in self.offset)
            self._centres = self.model.require_map().window_centres(r0, c0, *self.log_p.shape)
        return self._centres

    # ---- incremental update (online learning) -----------------------------------------------------------
    def update_place(self, k: int, mu: np.ndarray, Sigma: np.ndarray, cache: GraphCache | None = None) -> PlanningGraph:
        """The graph of this model with place k's Gaussian replaced by N(mu, Sigma), reusing every territory-
        local field whose territory's cells and costs did not change (:meth:`build` with ``reuse``)."""
        model = with_place(self.model, k, mu, Sigma)
        return self.update(model, cache=cache)

    def update(
        self, model: SpatialConceptModel, log_p: np.ndarray | None = None, cache: GraphCache | None = None
    ) -> PlanningGraph:
        """The graph of a changed model or cost map (same map size), recomputing only what depends on the
        change: :meth:`build` with ``reuse=self`` (and ``cache``)."""
        return PlanningGraph.build(model, self.settings, log_p=log_p, cache=cache, reuse=self)
