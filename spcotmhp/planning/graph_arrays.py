"""A planning graph as plain arrays and JSON, and back: what :mod:`spcotmhp.planning.graph_store` writes and reads.

:func:`to_arrays` gives, for the main graph and every other free region's graph, its arrays (prefixed ``g0.``,
``g1.`` ...) and a JSON description (its shape, offset, sizes, info). Per-cell arrays are the cost map and its step cost
(``log_p``, ``map_cost``), the traversable cells, the graph's region, the territories, the line-of-sight
clearance (:attr:`~spcotmhp.planning.graph.PlanningGraph.clearance`) and, in the main graph, the free regions'
labels; labels in the narrowest integer type that holds them. The portal graph's local fields are its trees'
direction codes (:mod:`spcotmhp.planning._tree_codes`, one byte a cell); dense fields (small maps only, at most
``GraphSettings.max_dense_bytes``) are not stored but recomputed on loading (:mod:`spcotmhp.planning.graph_store`).

:func:`expected_arrays` gives, from the JSON alone, the shape and dtype kinds of every array the file must hold,
after checking its sizes against the model's map (:func:`check_meta`), so nothing larger than the map allows is
allocated; :func:`check_values` then checks every index an array holds against the sizes (a next hop of the portal
graph in range or ``NO_HOP``), and that no number is NaN, so that a damaged file is a ModelError, never an index
out of range in a kernel or a NaN in the search.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.limits import MAX_CANDIDATES, MAX_GRAPH_BYTES
from spcotmhp.planning import hierarchy

if TYPE_CHECKING:
    from spcotmhp.learning.model import SpatialConceptModel

PlanningGraph = Any  # spcotmhp.planning.graph's (which imports the store, so the store cannot import it)

NODE_ARRAYS = {"node_place": "i", "node_cell": "i", "end_term": "f", "usable": "b"}
PAIR_ARRAYS = ("w_hat", "w_hat_metric", "log_transition", "log_transition_all")
HIER_ARRAYS = ("cells", "terr", "win", "off", "fcode", "src", "dst", "weight", "portal_cost", "hop")
NO_HOP = -9999  # scipy's dijkstra: no predecessor (the node cannot be reached)


def _narrow(values: np.ndarray) -> np.ndarray:
    """``values`` (integers) in the narrowest signed type that holds them."""
    lo, hi = (int(values.min()), int(values.max())) if values.size else (0, 0)
    for dtype in (np.int8, np.int16, np.int32):
        if np.iinfo(dtype).min <= lo and hi <= np.iinfo(dtype).max:
            return values.astype(dtype)
    return values.astype(np.int64)


def to_arrays(graph: PlanningGraph) -> tuple[dict[str, np.ndarray], list[dict[str, Any]]]:
    """The arrays and JSON descriptions of ``graph`` and its other free regions' graphs (module docstring)."""
    arrays: dict[str, np.ndarray] = {"connected": np.asarray(graph.connected, dtype=bool)}
    metas = []
    for i, (label, g) in enumerate([(None, graph), *graph.regions.items()]):
        p = f"g{i}."
        meta: dict[str, Any] = {
            "region": label,
            "offset": [int(v) for v in g.offset],
            "shape": [int(v) for v in g.log_p.shape],
            "n_nodes": int(g.n_nodes),
            "time_precompute_s": float(g.time_precompute_s),
            "info": g.info,
            "territories": len(g._territories),
            "hier": None,
        }
        arrays[p + "log_p"] = np.asarray(g.log_p, dtype=float)
        arrays[p + "map_cost"] = np.asarray(g.map_cost, dtype=float)
        arrays[p + "clearance"] = np.asarray(g.clearance)
        arrays[p + "traversable"] = np.asarray(g.traversable, dtype=bool)
        arrays[p + "main"] = np.asarray(g.main, dtype=bool)
        arrays[p + "territory"] = _narrow(np.asarray(g.territory))
        for name in NODE_ARRAYS:
            arrays[p + name] = np.asarray(getattr(g, name))
        for name in PAIR_ARRAYS:
            arrays[p + name] = np.asarray(getattr(g, name))
        keys = sorted(g._territories)
        arrays[p + "grown_keys"] = np.array(keys, dtype=np.int64)
        arrays[p + "grown_boxes"] = np.array(
            [(r, c, *m.shape) for r, c, m in (g._territories[k] for k in keys)], dtype=np.int64
        ).reshape(-1, 4)
        masks = [g._territories[k][2].reshape(-1) for k in keys]
        arrays[p + "grown_masks"] = np.concatenate(masks) if masks else np.zeros(0, dtype=bool)
        meta["grown_cells"] = len(arrays[p + "grown_masks"])
        if label is None and g.region is not None and g.plannable is not None:
            arrays[p + "region"] = _narrow(np.asarray(g.region))
            arrays[p + "plannable"] = np.asarray(g.plannable, dtype=bool)
        if g.hier is not None:
            h = g.hier
            src, dst, weight = h.links
            hier = dict(cells=h.cells, terr=h.terr, win=h.win, off=h.off, fcode=h.fcode, src=src, dst=dst)
            hier.update(weight=weight, portal_cost=h.portal_cost, hop=_narrow(h.hop), sums=block_sums(h))
            for name, value in hier.items():
                arrays[p + "hier." + name] = np.asarray(value)
            meta["hier"] = {"A": len(h.cells), "E": len(src), "codes": int(h.off[-1]), "info": h.info}
        metas.append(meta)
    return {name: np.ascontiguousarray(a) for name, a in arrays.items()}, metas


def _count(value: object, name: str, low: int, high: int) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
        raise ModelError(f"graph.json: {name} must be an integer in [{low}, {high}], got {value!r}")
    return value


def check_meta(metas: object, model: SpatialConceptModel) -> list[dict[str, Any]]:
    """The graphs' JSON descriptions, each size checked against the model's map and places (module docstring)."""
    occ = model.require_map()
    if not isinstance(metas, list) or not 1 <= len(metas) <= occ.height * occ.width:
        raise ModelError('graph.json: "graphs" must be a non-empty list of graph descriptions')
    for i, meta in enumerate(metas):
        if not isinstance(meta, dict) or not isinstance(meta.get("info"), dict):
            raise ModelError(f'graph.json: graph {i} must be an object with "info"')
        seconds, region = meta.get("time_precompute_s", 0.0), meta.get("region")
        if not (isinstance(seconds, (int, float)) and not isinstance(seconds, bool) and 0 <= seconds < math.inf):
            raise ModelError(f"graph.json: graph {i}'s time_precompute_s must be seconds >= 0, got {seconds!r}")
        if region is not None:
            _count(region, f"graph {i}'s region", 0, occ.height * occ.width)
        shape, offset = meta.get("shape"), meta.get("offset")
        if not (isinstance(shape, list) and isinstance(offset, list) and len(shape) == len(offset) == 2):
            raise ModelError(f'graph.json: graph {i} needs a 2-element "shape" and "offset"')
        for axis, size in enumerate((occ.height, occ.width)):
            _count(offset[axis], f"graph {i}'s offset[{axis}]", 0, size - 1)
            _count(shape[axis], f"graph {i}'s shape[{axis}]", 1, size - offset[axis])
        _count(meta.get("n_nodes"), f"graph {i}'s n_nodes", 0, model.K * MAX_CANDIDATES)
        _count(meta.get("territories"), f"graph {i}'s territories", 0, model.K)
        _count(meta.get("grown_cells"), f"graph {i}'s grown_cells", 0, meta["territories"] * shape[0] * shape[1])
        hier = meta.get("hier")
        if hier is not None:
            if not isinstance(hier, dict) or not isinstance(hier.get("info"), dict):
                raise ModelError(f'graph.json: graph {i}\'s "hier" must be an object with "info"')
            cells = shape[0] * shape[1]
            a = _count(hier.get("A"), f"graph {i}'s hier.A", meta["n_nodes"], cells)
            _count(hier.get("E"), f"graph {i}'s hier.E", 0, a * a)
            _count(hier.get("codes"), f"graph {i}'s hier.codes", 0, a * cells)
    return metas


def expected_arrays(metas: list[dict[str, Any]], model: SpatialConceptModel) -> dict[str, tuple[tuple, str]]:
    """name -> (shape, dtype kinds) of every array of the graphs described by ``metas`` (checked by
    :func:`check_meta`); the total is refused beyond ``MAX_GRAPH_BYTES`` (8 bytes a number, 1 a tree code)
    before anything is read."""
    K = model.K
    specs: dict[str, tuple[tuple, str]] = {"connected": ((K, K), "b")}
    for i, meta in enumerate(metas):
        p, shape, M = f"g{i}.", tuple(meta["shape"]), meta["n_nodes"]
        specs[p + "log_p"], specs[p + "map_cost"], specs[p + "clearance"] = (shape, "f"), (shape, "f"), (shape, "u")
        for name in ("traversable", "main"):
            specs[p + name] = (shape, "b")
        specs[p + "territory"] = (shape, "i")
        specs.update({p + n: ((M, 2) if n == "node_cell" else (M,), k) for n, k in NODE_ARRAYS.items()})
        specs.update({p + n: ((M, M), "f") for n in PAIR_ARRAYS})
        n = meta["territories"]
        specs[p + "grown_keys"], specs[p + "grown_boxes"] = ((n,), "i"), ((n, 4), "i")
        specs[p + "grown_masks"] = ((meta["grown_cells"],), "b")  # the boxes' areas: check_values
        if i == 0:
            specs[p + "region"], specs[p + "plannable"] = (shape, "i"), (shape, "b")
        if meta.get("hier") is not None:
            A, E, codes = meta["hier"]["A"], meta["hier"]["E"], meta["hier"]["codes"]
            hier = {"cells": (A, 2), "terr": (A,), "win": (K, 4), "off": (A + 1,), "fcode": (codes,)}
            hier.update({"src": (E,), "dst": (E,), "weight": (E,), "portal_cost": (A, M), "hop": (A, M)})
            for name, dims in hier.items():
                specs[p + "hier." + name] = (dims, "f" if name in ("weight", "portal_cost") else "i")
            specs[p + "hier.sums"] = ((A, 4), "u")
    total = sum(  # the tree codes one byte a cell (int8, checked when read), every other number 8
        (1 if name.endswith("hier.fcode") else 8) * int(np.prod([max(d, 0) for d in s]))
        for name, (s, _) in specs.items()
    )
    if total > MAX_GRAPH_BYTES:
        raise ModelError(
            f"graph.json describes {total} bytes of arrays; a planning graph holds at most {MAX_GRAPH_BYTES}"
        )
    return specs


def check_values(arrays: dict[str, np.ndarray], metas: list[dict[str, Any]], model: SpatialConceptModel) -> None:
    """Every index the arrays hold within its range (module docstring); ModelError naming the array."""

    def within(name: str, low: int, high: int) -> None:
        a = arrays[name]
        if a.size and (int(a.min()) < low or int(a.max()) >= high):
            raise ModelError(f"graph.npz: {name} holds values outside [{low}, {high}): the file was altered")

    for name, a in arrays.items():  # costs and log weights may be infinite (unreachable), never NaN
        if a.dtype.kind == "f" and np.isnan(a).any():
            raise ModelError(f"graph.npz: {name} holds NaN: the file was altered")
    K = model.K
    for i, meta in enumerate(metas):
        p, (h, w), M = f"g{i}.", meta["shape"], meta["n_nodes"]
        within(p + "node_place", 0, K)
        within(p + "territory", -1, K)
        within(p + "grown_keys", 0, K)
        if M:
            for axis, size in enumerate((h, w)):
                within_cells = arrays[p + "node_cell"][:, axis]
                if int(within_cells.min()) < 0 or int(within_cells.max()) >= size:
                    raise ModelError(f"graph.npz: {p}node_cell lies outside its graph's {h} x {w} cells")
        if i == 0:
            within(p + "region", 0, h * w + 1)
        boxes = arrays[p + "grown_boxes"]
        if len(boxes) and (
            (boxes < 0).any() or (boxes[:, 0] + boxes[:, 2] > h).any() or (boxes[:, 1] + boxes[:, 3] > w).any()
        ):
            raise ModelError(f"graph.npz: {p}grown_boxes lie outside their graph's {h} x {w} cells")
        if len(arrays[p + "grown_masks"]) != int((boxes[:, 2] * boxes[:, 3]).sum()):
            raise ModelError(f"graph.npz: {p}grown_masks does not hold its boxes' cells")
        if meta.get("hier") is not None:
            q, A = p + "hier.", meta["hier"]["A"]
            within(q + "terr", 0, K)
            for name in ("src", "dst"):
                within(q + name, 0, A)
            within(q + "hop", NO_HOP, A)
            if ((arrays[q + "hop"] < 0) & (arrays[q + "hop"] != NO_HOP)).any():
                raise ModelError(f"graph.npz: {q}hop holds negative hops other than {NO_HOP} (none): altered")
            win, cells = arrays[q + "win"], arrays[q + "cells"]
            if (win < 0).any() or (win[:, 2] > h).any() or (win[:, 3] > w).any() or (win[:, :2] > win[:, 2:]).any():
                raise ModelError(f"graph.npz: {q}win holds windows outside the graph's {h} x {w} cells")
            if len(cells) and ((cells < 0).any() or (cells[:, 0] >= h).any() or (cells[:, 1] >= w).any()):
                raise ModelError(f"graph.npz: {q}cells lie outside the graph's {h} x {w} cells")
            win_t = win[arrays[q + "terr"]]
            sizes = (win_t[:, 2] - win_t[:, 0]) * (win_t[:, 3] - win_t[:, 1])
            off = np.concatenate([[0], np.cumsum(sizes)])
            if not np.array_equal(off, arrays[q + "off"]) or off[-1] != meta["hier"]["codes"]:
                raise ModelError(f"graph.npz: {q}off does not match the territories' windows: the file was altered")


def hier_from_arrays(arrays: dict, q: str, meta: dict, cost: np.ndarray, territory: np.ndarray, K: int):
    """The portal graph (:class:`~spcotmhp.planning.hierarchy.TerritoryFields`) of the arrays prefixed ``q``."""
    terr = arrays[q + "terr"].astype(np.int64)
    order = np.argsort(terr, kind="stable").astype(np.int64)  # as hierarchy.build orders them
    bounds = np.searchsorted(terr[order], np.arange(K + 1))
    out = hierarchy.TerritoryFields(
        cost,
        territory,
        meta["n_nodes"],
        arrays[q + "cells"].astype(np.int64),
        terr,
        arrays[q + "win"].astype(np.int64),
        arrays[q + "off"].astype(np.int64),
        arrays[q + "fcode"] if arrays[q + "fcode"].dtype == np.int8 else arrays[q + "fcode"].astype(np.int8),
        [order[bounds[t] : bounds[t + 1]] for t in range(K)],
        tuple(arrays[q + n].astype(np.int64 if n != "weight" else float) for n in ("src", "dst", "weight")),
        np.zeros(len(terr), dtype=bool),
        portal_cost=arrays[q + "portal_cost"].astype(float),
        hop=arrays[q + "hop"].astype(np.int64),
        info=dict(meta["hier"]["info"]),
        sums=arrays[q + "sums"],
        checked=np.zeros(len(terr), dtype=bool),
    )
    return out


def block_sums(h: hierarchy.TerritoryFields) -> np.ndarray:
    """(A, 4) uint64: the checksum of each abstract node's block of tree codes (:data:`~spcotmhp.planning.
    graph_file.BLOCKS`)."""
    from spcotmhp.planning.graph_file import checksum_words

    out = np.empty((len(h.cells), 4), dtype=np.uint64)
    for a in range(len(h.cells)):
        block = np.ascontiguousarray(h.fcode[h.off[a] : h.off[a + 1]]).view(np.uint8)
        out[a] = checksum_words(block, block.size)
    return out
