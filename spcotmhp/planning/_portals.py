"""The portal graph's crossings (:mod:`spcotmhp.planning.hierarchy`): where two territories touch, the cells that
become abstract nodes, and how many an entrance gets (:func:`crossings_on`, the rule and its reason)."""

from __future__ import annotations

import math

import numpy as np


def crossings_on(length: int, spacing: int) -> int:
    """Crossings of an entrance of ``length`` cells: ``ceil(sqrt(length / spacing))``, at least one (every
    entrance joins its territories); every cell for a spacing of one cell (exact with 4-connected moves). Why: a
    crossing d cells from where a best path crosses costs it at most a 2d-cell walk along the entrance, so n even
    crossings bound the detour by length / n, while a territory's fields cost its nodes times its cells: one per
    spacing made the build grow as the cube of the territories' side (a corridor's territory keeps rims tens of
    metres long inside the rooms along its walls). The square root keeps ``ceil(length / spacing)`` up to two
    spacings (doors) and a bound relative to the length, ``sqrt(spacing / length)``, that still shrinks."""
    if spacing <= 1:
        return length
    return max(1, math.ceil(math.sqrt(length / spacing)))


def crossings(territory: np.ndarray, spacing: int) -> list[tuple[int, int, int, int]]:
    """(u_row, u_col, v_row, v_col) crossings: orthogonal neighbours u, v in different territories. Each
    entrance (an 8-connected run of the n u-side cells facing one other territory) gets :func:`crossings_on`
    u cells at the middles of equal parts, each with every v it faces."""
    groups: dict[tuple[int, int], list] = {}
    for axis in (0, 1):
        a = territory[:-1, :] if axis == 0 else territory[:, :-1]
        b = territory[1:, :] if axis == 0 else territory[:, 1:]
        rows, cols = np.nonzero((a >= 0) & (b >= 0) & (a != b))
        for r, c in zip(rows.tolist(), cols.tolist(), strict=True):
            v = (r + 1, c) if axis == 0 else (r, c + 1)
            ta, tb = int(a[r, c]), int(b[r, c])
            u, v = ((r, c), v) if ta < tb else (v, (r, c))
            groups.setdefault((min(ta, tb), max(ta, tb)), []).append((u, v))
    out = []
    for crossing in groups.values():
        partner: dict = {}  # u -> its neighbours v across
        for u, v in crossing:
            partner.setdefault(u, []).append(v)
        seen: set = set()
        for start in sorted(partner):
            if start in seen:
                continue
            run, stack = [], [start]
            seen.add(start)
            while stack:  # 8-connected run of u cells
                r, c = stack.pop()
                run.append((r, c))
                for dr in (-1, 0, 1):
                    for dc in (-1, 0, 1):
                        q = (r + dr, c + dc)
                        if q in partner and q not in seen:
                            seen.add(q)
                            stack.append(q)
            run.sort()
            n = crossings_on(len(run), spacing)
            for i in range(n):
                u = run[int((i + 0.5) * len(run) / n)]
                out += [(*u, *v) for v in partner[u]]
    return out


def abstract_nodes(
    node_cell: np.ndarray, pairs: list[tuple[int, int, int, int]], width: int
) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """``(cells, inter)``: the (A, 2) cells of the abstract nodes, the planning graph's nodes ``node_cell`` first
    then each new cell of a crossing ``pairs`` (one node per cell), and each crossing as a pair of node indices."""
    index: dict[int, int] = {}
    cells = [tuple(c) for c in np.asarray(node_cell, dtype=np.int64)]
    for n, (r, c) in enumerate(cells):
        index.setdefault(r * width + c, n)

    def node(r: int, c: int) -> int:
        key = r * width + c
        if key not in index:
            index[key] = len(cells)
            cells.append((r, c))
        return index[key]

    inter = [(node(ur, uc), node(vr, vc)) for ur, uc, vr, vc in pairs]
    return np.array(cells, dtype=np.int64).reshape(-1, 2), inter
