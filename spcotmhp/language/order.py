"""The visiting order of the places an instruction names: precedence constraints, then one topological order.

Each place to visit is a :class:`Visit` with its spoken position, its rank ("first": 0, none: 1, "finally" / "end
at": 2), its step (a sequencer such as "then" followed by a new marker starts a new step) and its role. The order
satisfies:

1. rank: every place ranked lower comes before every place ranked higher;
2. steps: inside one rank, every place of an earlier step comes before every place of a later one;
3. the pairs the order words give ("the bath after the kitchen": kitchen, bath; "before that"; chains such as
   "the bath after the kitchen after the toilet");
4. the destination: inside one rank and step, the last place with a goal marker ("to", "into", a bare name) that
   is not itself the object of an order word comes after every other place of that rank and step ("go to the
   bedroom via the corridor": corridor, bedroom), except where rule 3 already puts it first ("go to the kitchen
   before the bedroom": kitchen, bedroom), and except, when places of a higher rank or a later step follow (the
   destination is a stop on the way), the places said in a later clause than it: a narrative keeps its order
   ("go to the kitchen, pass through the corridor and end at the entrance": kitchen, corridor, entrance; "go to
   the kitchen via the corridor and end at the entrance": corridor, kitchen, entrance).

Of the orders that satisfy all of them, the one closest to the spoken order is taken (Kahn's algorithm, always
taking the earliest-spoken place that is free): the spoken order decides whatever the words leave open. Pairs that
contradict each other have no order and are refused (:class:`~spcotmhp.errors.UnsupportedPhrase`).

>>> visits = [Visit(0, role="goal"), Visit(1, role="via")]          # "go to the bedroom via the corridor"
>>> visiting_order(visits, [])
[1, 0]
>>> visits = [Visit(0, role="goal"), Visit(1, role="visit"), Visit(2, role="visit")]
>>> visiting_order(visits, [(2, 1), (1, 0)])                           # "the bath after the kitchen after the toilet"
[2, 1, 0]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from spcotmhp.errors import UnsupportedPhrase


@dataclass
class Visit:
    """A place to visit as the order sees it: its spoken position, rank, step, role, whether an order word
    ties it to another place (``tied``: it is then never the free destination of rule 3) and the clause it was
    said in (rule 4)."""

    spoken: int
    rank: int = 1
    step: int = 0
    role: str = "goal"
    tied: bool = False
    clause: int = 0


def visiting_order(visits: Sequence[Visit], pairs: Sequence[tuple[int, int]]) -> list[int]:
    """Positions (indices into ``visits``) in visiting order; ``pairs``: (a, b) = a before b (rule 4).

    Raises:
        UnsupportedPhrase: the pairs contradict each other (or rules 1-3).
    """
    if not any(a != b for a, b in pairs):  # rules 1, 2 and 4 alone (most instructions): a sort
        return _sorted_order(visits)
    return _constrained_order(visits, pairs)


def _sorted_order(visits: Sequence[Visit]) -> list[int]:
    """The order of rules 1, 2 and 4 without pairs, as a sort: by rank, then step, then the destination of its rank
    and step last, then spoken order (what Kahn's algorithm of :func:`_constrained_order` takes without pairs)."""
    dest = _destinations(visits)

    def phase(k: int) -> int:  # 0: before its group's destination, 1: the destination, 2: after it (rule 4)
        d = dest.get((visits[k].rank, visits[k].step))
        return 0 if d is None else 1 if d == k else 2 if _narrated(visits, d, k) else 0

    return sorted(range(len(visits)), key=lambda k: (visits[k].rank, visits[k].step, phase(k), visits[k].spoken))


def _destinations(visits: Sequence[Visit]) -> dict[tuple[int, int], int]:
    """(rank, step) -> the destination of rule 4: its last place with a goal marker that no order word ties."""
    dest: dict[tuple[int, int], int] = {}
    for k, v in enumerate(visits):
        if v.role == "goal" and not v.tied:
            group = (v.rank, v.step)
            if group not in dest or v.spoken > visits[dest[group]].spoken:
                dest[group] = k
    return dest


def _narrated(visits: Sequence[Visit], d: int, k: int) -> bool:
    """Whether place ``k`` keeps its spoken place after destination ``d`` (rule 4's exception): said in a later
    clause than ``d``, whose group is followed by a higher rank or a later step."""
    last = max((v.rank, v.step) for v in visits)
    later = visits[k].clause > visits[d].clause and visits[k].spoken > visits[d].spoken
    return later and (visits[d].rank, visits[d].step) < last


def _constrained_order(visits: Sequence[Visit], pairs: Sequence[tuple[int, int]]) -> list[int]:
    """Rules 1-4 as precedence constraints, then Kahn's algorithm (module docstring)."""
    n = len(visits)
    before: list[set[int]] = [set() for _ in range(n)]  # before[b]: what must come before b
    for a in range(n):
        for b in range(n):
            va, vb = visits[a], visits[b]
            if va.rank < vb.rank or (va.rank == vb.rank and va.step < vb.step):
                before[b].add(a)
    groups: dict[tuple[int, int], list[int]] = {}
    for k, v in enumerate(visits):
        groups.setdefault((v.rank, v.step), []).append(k)
    for a, b in pairs:
        if a != b:
            before[b].add(a)
    _topological(visits, before)  # rules 1-3 must agree
    for members in groups.values():
        free = [k for k in members if visits[k].role == "goal" and not visits[k].tied]
        if free:
            dest = max(free, key=lambda k: visits[k].spoken)
            for k in members:
                if k != dest and not _precedes(dest, k, before) and not _narrated(visits, dest, k):
                    before[dest].add(k)
    return _topological(visits, before)


def _precedes(a: int, b: int, before: list[set[int]]) -> bool:
    """Whether the constraints put ``a`` before ``b`` (transitively)."""
    seen, stack = set(), [b]
    while stack:
        k = stack.pop()
        for p in before[k]:
            if p == a:
                return True
            if p not in seen:
                seen.add(p)
                stack.append(p)
    return False


def _topological(visits: Sequence[Visit], before: list[set[int]]) -> list[int]:
    """Kahn's algorithm, always taking the earliest-spoken free place."""
    done: list[int] = []
    left = set(range(len(visits)))
    while left:
        free = [k for k in left if not (before[k] & left)]
        if not free:
            raise UnsupportedPhrase(
                "the order words contradict each other (each place would come before the other); say the order "
                "with 'first' and 'then'"
            )
        k = min(free, key=lambda k: visits[k].spoken)
        done.append(k)
        left.remove(k)
    return done
