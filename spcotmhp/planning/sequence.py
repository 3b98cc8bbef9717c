"""Visiting order: the place phrases of a sentence (:mod:`spcotmhp.planning.sentence`) -> ordered waypoints, the
goal, places to avoid and places not to end in.

Rules (continuing the numbering of :mod:`spcotmhp.planning.sentence`):

4. Places to visit (goal and waypoint roles) are put in order by these general rules, in this order:

   a. "on the way" (途中で) makes a goal-role phrase of its clause a waypoint ("go to the bedroom and the
      kitchen on the way").
   b. Steps. A sequencer ("then", "after that"; それから) followed by a new marker starts a new step ("go to the
      toilet and then to the kitchen via the corridor": [toilet] then [kitchen via corridor]); steps keep the
      spoken order. A sequencer inside a list ("passing by the toilet and then the dining") does not.
   c. Inside a step, the destination (its last goal-role phrase not ordered by before / after) comes after the
      other places ("go to the bedroom via the corridor": corridor, bedroom); the others keep the spoken order.
      "after X" puts X (and places joined to it by "and") before the rest of its step ("go to the bedroom after
      the kitchen", キッチンの後で寝室へ), "before X" puts X after the rest of its step ("before the bedroom,
      visit the toilet", 寝室に行く前にトイレに寄って).
   d. "first" (まず) places come before everything else, "finally" (最後に) places after everything else; each
      group ordered by b-c within itself ("go to the toilet, but first the kitchen").
   e. "before that" (その前に) puts its place right before the place spoken just before it ("go to the
      bedroom, but before that the kitchen").
   f. Chains: "the bath after the kitchen after the toilet" is toilet, kitchen, bath, and "the bath before the
      kitchen before the toilet" is bath, kitchen, toilet (each before / after orders the place spoken right
      before it); トイレの後でキッチンの後で寝室 is toilet, kitchen, bedroom, and
      寝室に行く前にトイレに行く前にキッチンに寄って kitchen, toilet, bedroom; a chain mixing the two is
      refused. Goal markers that end the plan ("end at", "finish in") order their place as "finally" does;
      "start with" as "first".

   The last place is the goal, the others are the waypoints in that order. Nothing else reorders places.
   "before" / "after" with no other place to order against, or applied to a place to avoid, is refused
   (:class:`~spcotmhp.errors.UnsupportedPhrase`): the planner cannot honour a time order on an avoided place.
5. "from" phrases are dropped (the start is the pose given to the planner). A sentence naming no place to visit
   (only places to avoid, not to end in or to start from) is an :class:`~spcotmhp.errors.EmptyInstruction`.
"""

from __future__ import annotations

from collections.abc import Sequence

from spcotmhp.errors import EmptyInstruction, UnsupportedPhrase
from spcotmhp.planning.sentence import Phrase
from spcotmhp.language.wording import excerpt, known_words

_VISIT = ("goal", "waypoint")
_RANK = {"first": 0, "last": 2}
_GROUP = {"after": 0, "before": 3}


def visiting_order(phrases: list[Phrase], text: str, place_words: Sequence[str]) -> dict[str, list[Phrase]]:
    """``{"visit": [...], "avoid": [...], "not_goal": [...]}``: the places to visit in order (the last is the
    goal), the places to avoid and the places not to end in, each in spoken order (rules 4-5).

    Raises:
        EmptyInstruction: no place to visit.
        UnsupportedPhrase: a before / after order that cannot be honoured.
    """
    kept = [p for p in phrases if p.role != "from"]
    for p in kept:
        if p.role in _VISIT and "on_the_way" in p.orders:
            p.role = "waypoint"
        timed = [o for o in ("before", "after") if o in p.orders]
        if timed and p.role not in _VISIT:
            raise UnsupportedPhrase(
                f"{excerpt(p.orders[timed[0]].surface)} orders {excerpt(p.item.surface)}, "
                f"a place {'to avoid' if p.role == 'avoid' else 'not to end in'}; such a "
                "place is kept out of the whole plan, so say it without before / after"
            )
    visit = [p for p in kept if p.role in _VISIT]
    if not visit:
        raise EmptyInstruction(
            f"{excerpt(text)} names no place to go to, only places to avoid, not to end in or "
            f"to start from; {known_words(place_words)}"
        )
    if len(visit) == 1:
        order_words = [visit[0].orders[o] for o in ("before", "after") if o in visit[0].orders]
        if order_words:
            raise UnsupportedPhrase(
                f"{excerpt(order_words[0].surface)} orders {excerpt(visit[0].item.surface)} against "
                "no other place to visit; name both places (e.g. 'go to the bedroom after "
                "the kitchen')"
            )
    return {
        "visit": _order(visit),
        "avoid": [p for p in kept if p.role == "avoid"],
        "not_goal": [p for p in kept if p.role == "not_goal"],
    }


def _order(visit: list[Phrase]) -> list[Phrase]:
    if not any(p.orders or p.after_sequencer for p in visit):  # one step, no order words: rule c alone
        goals = [n for n, p in enumerate(visit) if p.role == "goal"]
        return visit if not goals else [*visit[: goals[-1]], *visit[goals[-1] + 1 :], visit[goals[-1]]]
    step, steps = 0, []
    for prev, p in zip([None, *visit], visit, strict=False):
        step += prev is not None and p.after_sequencer and p.source != prev.source
        steps.append(step)
    rank = [min((_RANK[o] for o in p.orders if o in _RANK), default=1) for p in visit]
    group = [next((_GROUP[o] for o in ("after", "before") if o in p.orders), 1) for p in visit]
    for part in {(r, s) for r, s in zip(rank, steps, strict=False)}:
        members = [n for n in range(len(visit)) if (rank[n], steps[n]) == part]
        free = [
            n for n in members if visit[n].role == "goal" and group[n] == 1 and "before_that" not in visit[n].orders
        ]
        if free:
            group[free[-1]] = 2  # the step's destination comes after its other places
    order = sorted(range(len(visit)), key=lambda n: (rank[n], steps[n], group[n], visit[n].chain, n))  # rule f
    for n in range(len(visit)):  # "before that": right before the place spoken before it
        if "before_that" in visit[n].orders and n > 0:
            order.remove(n)
            order.insert(order.index(n - 1), n)
    return [visit[n] for n in order]
