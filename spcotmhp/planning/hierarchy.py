"""Territory-local cost-to-go fields and a portal graph: the planning graph's fields at building scale.

Every leg of the planning graph uses the same step cost, the map term of Eq. 26, ``c(x) = log|A| - log p(x|m)``
(optimality is observed at the leg's end; :mod:`spcotmhp.planning.graph`), so the partial path between two
candidate points (Eq. 27), the start leg from any start and w-hat (Eq. 24) are all shortest paths under one cost
map. Instead of one field per node over the whole map (M x h x w, 9.6 GB for 200 places on 2000 x 2000 cells),
this is an HPA* abstraction (Botea, Mueller and Schaeffer 2004) whose clusters are the place territories
(:mod:`spcotmhp.learning.territory`):

* **Portals.** Where two territories touch (two 4-neighbouring cells), each connected run of such cells (an
  *entrance*: a door, an open boundary) gets ``ceil(sqrt(length / portal_spacing))`` crossings evenly spread
  along it (:func:`~spcotmhp.planning._portals.crossings_on`: one a spacing up to two spacings, as doors, then
  spaced by the geometric mean of the length and the spacing; the rule's reason is there); both cells of a
  crossing are abstract nodes, joined by the one grid step between them (cost ``c(v)`` of the cell entered).
  The candidate points (Algorithm 1, line 2) are abstract nodes too.
* **Exact local fields.** For every abstract node, the cost-to-go field into it over its own territory only
  (bounded by the territory's bounding box; every other cell is blocked), computed once, in parallel on every
  core (numba ``prange``). Intra-territory edges of the abstract graph read them: ``a -> b`` costs
  ``field_b[cell_a]``.
* **Abstract distances.** One Dijkstra per candidate on the (reversed) abstract graph gives
  ``portal_cost[a, j]``, the cost from every abstract node ``a`` into node ``j``, and its next hop: w-hat (Eq. 24,
  end-observed) is ``-portal_cost[i, j] + log N(x_j | mu_b, Sigma_b)``.
* **The start leg from any start** x_0 in territory t stays a table look-up (Algorithm 1's online part):
  ``min over abstract nodes a of t of field_a[x_0] + portal_cost[a, j]``.
* **Refinement.** A chosen leg is read back cell by cell: the local field from the start into its best abstract
  node, then hop by hop, each hop inside one territory following that territory's exact field. Its cost is
  exactly the portal_cost above, so w-hat, the explanation and the path agree.

What is kept: every cell of every path lies in a traversable cell of a territory (never an inscribed or lethal
one); territories are 4-connected and adjacent territories share at least one crossing per entrance, so whenever
the free space joins two cells the abstract graph joins them (never "no path"); an avoided place's territory is
removed with its abstract nodes and no field enters another territory, so a view's paths never enter it and the
other fields stay valid unchanged. What is approximate: a leg is the cheapest path through the chosen crossings,
at least the exact grid optimum (HPA*'s error, about 1% in Botea et al.; ours on generated offices and
homes in docs/speed.md, issue 35's crossings section).

Incremental update: the fields of a territory depend only on its cells and their costs, so a rebuild reuses, for
every territory whose cells and costs are unchanged, the field of every abstract node that is still there
(:func:`build` with ``reuse``).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.metric.grid_ops import find_boxes
from spcotmhp.metric.grid_search import SQRT2
from spcotmhp.planning import _field_kernel as _fk
from spcotmhp.planning import _portals
from spcotmhp.planning import _tree_codes as _tc

ENTRY_CELLS = 8
"""Start cells whose :meth:`TerritoryFields.entries` a portal graph keeps (a plan asks one; a few concurrent
plans of a server each theirs)."""


@dataclass
class TerritoryFields:
    """The abstraction of the module docstring. Abstract node ``a`` sits at crop cell ``cells[a]`` in territory
    ``terr[a]``; the first ``n_nodes`` are the planning graph's nodes (same order). Fields are stored flat: node
    ``a``'s field covers its territory's window ``win[terr[a]]`` (r0, c0, r1, c1) at ``fcode[off[a]:off[a + 1]]``:
    the shortest-path tree into ``a``, one int8 direction code a cell (:mod:`spcotmhp.planning._tree_codes`; the
    cost to go is summed along it, bit for bit the search's)."""

    cost: np.ndarray
    territory: np.ndarray
    n_nodes: int
    cells: np.ndarray
    terr: np.ndarray
    win: np.ndarray
    off: np.ndarray
    fcode: np.ndarray
    members: list  # territory -> abstract nodes in it (int64 array)
    links: tuple  # (src, dst, weight) of the abstract graph's edges
    removed: np.ndarray  # (A,) abstract nodes of avoided territories
    portal_cost: np.ndarray = field(default_factory=lambda: np.empty((0, 0)))  # (A, n_nodes) see solve()
    hop: np.ndarray = field(default_factory=lambda: np.empty((0, 0), dtype=np.int64))
    info: dict = field(default_factory=dict)
    sums: np.ndarray | None = None  # (A, 4) uint64: each node's block's checksum, for codes read from a file
    checked: np.ndarray | None = None  # (A,) blocks already checked against ``sums`` (shared by views)
    _entries_of: Callable[[int, int], tuple[np.ndarray, np.ndarray]] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._entries_of = functools.lru_cache(maxsize=ENTRY_CELLS)(self._entries)  # thread-safe, per object

    def verify(self, nodes: np.ndarray) -> None:
        """Check the tree codes of ``nodes`` against their checksums the first time they are read (codes loaded
        from a file, :data:`spcotmhp.planning.graph_file.BLOCKS`); ModelError on a damaged block."""
        if self.sums is None or self.checked is None:
            return
        from spcotmhp.planning.graph_file import checksum_words

        for a in np.asarray(nodes, dtype=np.int64):
            if self.checked[a]:
                continue
            block = self.fcode[self.off[a] : self.off[a + 1]].view(np.uint8)
            if not np.array_equal(checksum_words(block, block.size), self.sums[a]):
                raise ModelError(
                    f"graph.npz: the local field of abstract node {int(a)} does not match its checksum (a damaged "
                    "file); save the graph again: spcotmhp precompute MODEL --overwrite"
                )
            self.checked[a] = True

    @property
    def nbytes(self) -> int:
        """Bytes held by the fields and the abstract distance tables."""
        return int(self.fcode.nbytes + self.portal_cost.nbytes + self.hop.nbytes)

    def solve(self) -> None:
        """``portal_cost[a, j]`` (the cost from abstract node a into node j over the abstract graph) and ``hop[a, j]``
        (the next abstract node on that way) by Dijkstra on the reversed abstract graph from every node (removed
        nodes cut)."""
        from scipy.sparse import csr_matrix  # here, not at import: only building-scale maps have a portal graph
        from scipy.sparse.csgraph import dijkstra

        src, dst, w = self.links
        keep = ~self.removed[src] & ~self.removed[dst]
        A = len(self.cells)
        reverse = csr_matrix((w[keep], (dst[keep], src[keep])), shape=(A, A))
        dist, pred = dijkstra(reverse, directed=True, indices=np.arange(self.n_nodes), return_predecessors=True)
        self.portal_cost = np.ascontiguousarray(dist.T)
        self.portal_cost[self.removed] = np.inf
        self.hop = np.ascontiguousarray(pred.T).astype(np.int64)  # next abstract node on the way into j

    def local(self, a: int, cell: np.ndarray) -> float:
        """Node a's field at crop cell ``cell`` (inf outside a's territory window)."""
        return float(self._costs(np.array([a], dtype=np.int64), cell)[0])

    def _costs(self, nodes: np.ndarray, cell: np.ndarray) -> np.ndarray:
        self.verify(nodes)
        return _tc.costs_at(
            self.fcode, self.off, nodes, self.win, self.terr, self.cells, int(cell[0]), int(cell[1]), self.cost, SQRT2
        )

    def entries(self, cell: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(nodes, costs)``: the abstract nodes of ``cell``'s territory and the local cost from ``cell`` into
        each (empty off every territory), read-only. A plan asks them for its start cell for the start leg and
        for each leg read back (a walk along every node's tree each), so the last few cells' are kept."""
        return self._entries_of(int(cell[0]), int(cell[1]))

    def _entries(self, r: int, c: int) -> tuple[np.ndarray, np.ndarray]:
        t = int(self.territory[r, c])
        if t < 0:
            nodes, costs = np.empty(0, dtype=np.int64), np.empty(0)
        else:
            nodes = self.members[t][~self.removed[self.members[t]]]
            costs = self._costs(nodes, np.array([r, c]))
        nodes.setflags(write=False)
        costs.setflags(write=False)
        return nodes, costs

    def cost_to_nodes(self, cell: np.ndarray) -> np.ndarray:
        """(n_nodes,) the cost of the best path from crop cell ``cell`` into each node (inf: none)."""
        nodes, local = self.entries(cell)
        if not len(nodes):
            return np.full(self.n_nodes, np.inf)
        return (local[:, None] + self.portal_cost[nodes]).min(axis=0)

    def path(self, cell: np.ndarray, j: int) -> np.ndarray | None:
        """The cells of the best path from crop cell ``cell`` into node j (module docstring), None if none."""
        nodes, local = self.entries(cell)
        if not len(nodes):
            return None
        total = local + self.portal_cost[nodes, j]
        best = int(np.argmin(total))
        if not np.isfinite(total[best]):
            return None
        a = int(nodes[best])
        pieces = [self._follow(a, cell)]
        for _ in range(len(self.cells)):  # a way visits each abstract node once; a longer chain is a cycle
            if a == j:
                break
            b = int(self.hop[a, j])
            if b < 0:
                raise ModelError(f"the portal graph has no next hop from abstract node {a} into node {j}")
            pieces.append(self._follow(b, self.cells[a])[1:] if self.terr[b] == self.terr[a] else self.cells[b][None])
            a = b
        else:
            if a != j:
                raise ModelError(f"the portal graph's next hops from abstract node {a} into node {j} go round a cycle")
        return np.concatenate(pieces)

    def _follow(self, a: int, cell: np.ndarray) -> np.ndarray:
        self.verify(np.array([a]))
        r0, c0, r1, c1 = self.win[self.terr[a]]
        codes = self.fcode[self.off[a] : self.off[a + 1]]
        cells = _tc.follow_codes(codes, r1 - r0, c1 - c0, int(cell[0]) - r0, int(cell[1]) - c0)
        return cells + np.array([r0, c0])

    def without(self, places: tuple[int, ...]) -> TerritoryFields:
        """A view whose abstract nodes in the territories of ``places`` are removed (fields shared)."""
        removed = self.removed | np.isin(self.terr, places)
        view = TerritoryFields(
            self.cost,
            self.territory,
            self.n_nodes,
            self.cells,
            self.terr,
            self.win,
            self.off,
            self.fcode,
            self.members,
            self.links,
            removed,
            info=dict(self.info),
            sums=self.sums,
            checked=self.checked,
        )
        view.solve()
        return view


def build(
    cost: np.ndarray,
    territory: np.ndarray,
    node_cell: np.ndarray,
    n_places: int,
    spacing: int,
    connectivity: int,
    reuse: TerritoryFields | None = None,
) -> TerritoryFields:
    """The abstraction over crop ``cost`` (log|A| - log p(x|m), inf off the traversable cells) and ``territory``
    (labels 0..n_places-1, -1 elsewhere) with the planning graph's nodes ``node_cell`` first; an entrance's crossings
    from ``spacing`` cells (:func:`~spcotmhp.planning._portals.crossings_on`). ``reuse``: an earlier abstraction
    whose fields are copied for every territory whose cells and costs are unchanged (module docstring)."""
    territory = np.ascontiguousarray(territory, dtype=np.int64)
    win = _windows(territory, n_places)
    crossing = _portals.crossings(territory, max(1, int(spacing)))
    cells, inter = _portals.abstract_nodes(node_cell, crossing, territory.shape[1])
    terr = territory[cells[:, 0], cells[:, 1]]
    sizes = (win[terr, 2] - win[terr, 0]) * (win[terr, 3] - win[terr, 1])
    off = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    fcode = np.empty(int(off[-1]), dtype=np.int8)
    todo = _reuse_fields(reuse, cost, territory, cells, terr, win, off, fcode)
    cost = np.ascontiguousarray(cost)
    _local_fields(cost, territory, cells, terr, win, off, todo, fcode, connectivity)
    order = np.argsort(terr, kind="stable").astype(np.int64)
    bounds = np.searchsorted(terr[order], np.arange(n_places + 1)).astype(np.int64)
    members = [order[bounds[t] : bounds[t + 1]] for t in range(n_places)]
    pairs = _tc.pair_costs(fcode, off, order, bounds, win, cells, cost, SQRT2)
    out = TerritoryFields(
        cost,
        territory,
        len(node_cell),
        cells,
        terr,
        win,
        off,
        fcode,
        members,
        _abstract_links(cost, cells, pairs, members, inter),
        np.zeros(len(cells), dtype=bool),
        info={
            "abstract_nodes": len(cells),
            "crossings": len(inter),
            "fields_computed": len(todo),
            "fields_reused": int(len(cells) - len(todo)),
        },
    )
    out.solve()
    return out


def _windows(territory: np.ndarray, n_places: int) -> np.ndarray:
    """(n_places, 4) the bounding box (r0, c0, r1, c1) of each territory (zeros for an empty one)."""
    win = np.zeros((n_places, 4), dtype=np.int64)
    for t, sl in enumerate(find_boxes(territory + 1, max_label=n_places)):
        if sl is not None:
            win[t] = (sl[0].start, sl[1].start, sl[0].stop, sl[1].stop)
    return win


def _abstract_links(
    cost: np.ndarray, cells: np.ndarray, pairs: np.ndarray, members: list, inter: list[tuple[int, int]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(src, dst, weight)`` of the abstract graph's edges: within a territory, a -> b for every two of its
    nodes that b's local field reaches (weight ``field_b[cell_a]``: ``pairs``, :func:`~spcotmhp.planning.
    _tree_codes.pair_costs`); across, both ways along every crossing (weight ``c(v)`` of the cell entered)."""
    src, dst, w = [], [], []
    at = 0
    for m in members:
        n = len(m)
        vals = pairs[at : at + n * n].reshape(n, n)  # [a, b]: from a into b
        at += n * n
        if n < 2:
            continue
        a_idx, b_idx = np.nonzero(np.isfinite(vals) & ~np.eye(n, dtype=bool))
        src.append(m[a_idx])
        dst.append(m[b_idx])
        w.append(vals[a_idx, b_idx])
    if inter:
        u, v = np.array(inter, dtype=np.int64).T
        src += [u, v]
        dst += [v, u]
        w += [cost[cells[v, 0], cells[v, 1]], cost[cells[u, 0], cells[u, 1]]]
    links = tuple(np.concatenate(x) if x else np.empty(0) for x in (src, dst, w))
    return links[0].astype(np.int64), links[1].astype(np.int64), links[2].astype(float)


def _reuse_fields(reuse, cost, territory, cells, terr, win, off, fcode) -> np.ndarray:
    """Copy the fields of ``reuse`` for nodes at the same cell of a territory whose window, cells and costs are
    unchanged; return the nodes still to compute."""
    todo = np.ones(len(cells), dtype=bool)
    if reuse is None or reuse.cost.shape != cost.shape:
        return np.arange(len(cells))
    old_at = {(int(reuse.terr[a]), int(r), int(c)): a for a, (r, c) in enumerate(reuse.cells)}
    same: dict[int, bool] = {}
    for a in range(len(cells)):
        t = int(terr[a])
        if t not in same:
            ok = t < len(reuse.win) and np.array_equal(win[t], reuse.win[t])
            if ok:
                r0, c0, r1, c1 = win[t]
                mine = territory[r0:r1, c0:c1] == t
                ok = np.array_equal(mine, reuse.territory[r0:r1, c0:c1] == t) and np.array_equal(
                    cost[r0:r1, c0:c1][mine], reuse.cost[r0:r1, c0:c1][mine]
                )
            same[t] = ok
        old = old_at.get((t, int(cells[a, 0]), int(cells[a, 1])))
        if same[t] and old is not None:
            reuse.verify(np.array([old]))
            fcode[off[a] : off[a + 1]] = reuse.fcode[reuse.off[old] : reuse.off[old + 1]]
            todo[a] = False
    return np.flatnonzero(todo)


def _local_fields(cost, territory, cells, terr, win, off, todo, fcode, connectivity) -> None:
    """The exact field into each abstract node of ``todo`` over its own territory (module docstring), as its
    tree's direction codes, a territory at a time (:mod:`spcotmhp.planning._field_kernel`: its window's costs
    copied once, its nodes' searches in parallel)."""
    todo = np.asarray(todo, dtype=np.int64)
    order = todo[np.argsort(terr[todo], kind="stable")]
    starts = np.flatnonzero(np.diff(terr[order], prepend=-1))
    for nodes in np.split(order, starts[1:]):
        if not len(nodes):
            continue
        t = int(terr[nodes[0]])
        r0, c0, r1, c1 = (int(v) for v in win[t])
        grid, n_cells = _fk.padded_window(cost, territory, t, r0, c0, r1, c1)
        sources = np.ascontiguousarray(cells[nodes] - np.array([r0, c0]))
        _fk.territory_fields(grid, r1 - r0, c1 - c0, n_cells, sources, fcode, off[nodes], connectivity, SQRT2)
