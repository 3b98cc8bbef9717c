"""A planner's memo of what a place phrase denotes: its word term of Eq. 28 and the places it names.

Both are functions of the model, the planner's settings and the phrase's bags of words alone (not of the start,
the other phrases of the instruction or the free region), and a robot hears the same few place names again and
again, so a planner keeps them per phrase instead of recomputing them for every instruction
(:meth:`~spcotmhp.planning.planner.HierarchicalPlanner.phrase_terms`). The memo is bounded (emptied when full)
and keeps read-only arrays, so a caller cannot change what a later instruction reads.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable

import numpy as np

from spcotmhp.planning.query import PlaceQuery

PHRASES_KEPT = 1024
"""Most place phrases a planner keeps (a phrase is a few words; the memo is emptied when it is full)."""


def phrase_key(query: PlaceQuery, stage: bool) -> tuple | None:
    """What a phrase's terms depend on: its bags (in their order), ``every``, its floor, its instance number and
    whether it is a stage (a place to visit is checked for naming one place); None when a bag cannot be a key (then
    nothing is kept).
    The label and the relation are not part of it: the label only words refusals, which are never kept, and a
    relation is resolved after (in the start's free region)."""
    try:
        bags = (tuple(query.words.items()), tuple(tuple(a.items()) for a in query.alternatives))
        key = (*bags, query.every, query.floor, query.number, stage)
        hash(key)
    except TypeError:
        return None
    return key


class PhraseMemo:
    """``(word term, places named)`` per phrase key, for one owner (settings object): a lookup under another
    owner empties it first."""

    def __init__(self, limit: int = PHRASES_KEPT) -> None:
        self.limit = limit
        self._kept: dict[Hashable, tuple[np.ndarray, np.ndarray]] = {}
        self._owner: object = None

    def get(
        self,
        key: Hashable | None,
        owner: object,
        compute: Callable[[], tuple[np.ndarray, np.ndarray]],
    ) -> tuple[np.ndarray, np.ndarray]:
        """The arrays kept for ``key``, else ``compute()``'s, made read-only and kept (unless ``key`` is None)."""
        if owner is not self._owner:
            self._kept = {}
            self._owner = owner
        got = self._kept.get(key) if key is not None else None
        if got is None:
            got = compute()
            for a in got:
                a.setflags(write=False)
            if key is not None:
                if len(self._kept) >= self.limit:
                    self._kept = {}
                self._kept[key] = got
        return got
