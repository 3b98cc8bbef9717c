"""The sentence grammar of instructions: a text -> place phrases, each with its role (goal, waypoint, avoid,
not_goal, from) and its order words, or an :class:`~spcotmhp.errors.InstructionError` saying what was not
understood.

The grammar words of each language are tables in :mod:`spcotmhp.planning.grammar`; the place words are the
model's. Rule 1 (cutting the text into items) is :mod:`spcotmhp.planning.scan`; :mod:`spcotmhp.planning.sequence`
puts the phrases in visiting order (rules 4-5).

Parse rules (documented behaviour, tested; the corpus in tests/data/instruction_corpus.csv exercises them):
1. The text is cut into place phrases (maximal runs of adjacent place words, so multi-word names such as
   "entrance corridor" or "alice's room" form one phrase; in Japanese also two names joined by a lone の,
   玄関の廊下), grammar markers, order words, connectors, alternatives, relations, modifiers, fillers and other
   words. "the first" / "the last" before a place are modifiers, elsewhere "first" / "last" are order words.
2. Refused outright with :class:`~spcotmhp.errors.UnsupportedPhrase` naming the words: an alternative ("or",
   または, a lone か between two places: the choice is the user's to make), a spatial relation ("next to",
   の隣) and a modifier that picks one of several places ("second", "on the left", 二番目): the map holds
   none of these, and dropping them would send the robot somewhere else than asked.
2b. Refused too, naming the words (:mod:`spcotmhp.planning.refusals` says when and why): leaving a place, a
   self-correction, a condition, a way back to the start, a waiver or negated avoidance ("do not avoid"), a place
   inside another ("the toilet in the corridor"), English places with only fillers between them, and a start
   place ("from the bath").
3. A phrase takes the role of its marker (English: the last marker before it; Japanese: the first marker after
   it). A phrase with only a connector takes its neighbour's role (English: the previous phrase's; Japanese:
   the next phrase's). A phrase with no marker at all is a goal. A negation ("don't", "never", "instead of")
   followed, through fillers only, by another marker keeps its own role: "I don't want to go to the kitchen"
   avoids the kitchen.
6. Words where a place word is expected must be place words (:class:`~spcotmhp.errors.UnknownPlaceWord`,
   with "did you mean" near misses): other words between a marker, a before / after word or a connector and
   the next grammar word with no place word there ("go to the garage via the kitchen"; ガレージへ行って), and
   other words right next to a place phrase, which would modify it ("the big kitchen", 大きいキッチン). Not
   counted: words after a marker that the next marker of the same role takes over ("want to quickly go to"),
   and words after a punctuation connector unless they follow a determiner ("go to the kitchen, thanks" is
   fine; "go to the kitchen, the attic" is not). Japanese places must be joined by a connector (と, や) or an
   order word, or belong to different markers.
7. A waypoint, avoid or not_goal marker with no place word, or a goal marker ending the sentence, is an error
   (:class:`~spcotmhp.errors.UnknownPlaceWord` naming the words not understood, or
   :class:`~spcotmhp.errors.MalformedInstruction` when there are none).
8. Chains (English): a before / after right after a phrase that an earlier before / after orders continues the
   chain (:func:`_chained`; :mod:`spcotmhp.planning.sequence` rule 4f). Goal markers of ``final_markers`` ("end at")
   order their place last.
9. Any word left that is neither a place word nor a grammar word is an
   :class:`~spcotmhp.errors.UnknownPlaceWord` naming it, wherever it stands: nothing is dropped silently.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise

from spcotmhp.errors import MalformedInstruction, UnknownPlaceWord, UnsupportedPhrase
from spcotmhp.planning.grammar import Grammar
from spcotmhp.planning.refusals import (
    refuse_double_negation,
    refuse_list_without_goal,
    refuse_start_place,
    refuse_unjoined,
    refuse_unknown,
    refuse_unsupported,
)
from spcotmhp.planning.scan import Item, merge_phrases, scan
from spcotmhp.language.wording import excerpt, known_words, named, not_understood, unknown_tail


@dataclass
class Phrase:
    """A place phrase of the sentence with what the grammar says about it.

    Attributes:
        item: the scanned phrase (its words and surface form).
        role: "goal", "waypoint", "avoid", "not_goal" or "from".
        source: index of the marker that gave the role (-1: none, a goal by default).
        clause: index of its clause (clauses are separated by connectors).
        index: its position among the scanned items.
        orders: the order words that apply to it, by kind ("first", "after", ...).
        after_sequencer: a sequencer ("then") stands between it and the previous phrase.
        chain: its sort key in a chain of order words of one kind ("the bath after the kitchen after the
            toilet": kitchen 0, toilet -1, so toilet comes first); 0 outside chains.
    """

    item: Item
    role: str
    source: int
    clause: int
    index: int
    orders: dict[str, Item] = field(default_factory=dict)
    after_sequencer: bool = False
    chain: int = 0


def read_sentence(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[Phrase]:
    """The place phrases of ``text`` in order, each with its role and order words (rules 1-3, 6-7).

    Raises:
        UnknownPlaceWord: no known place word, or an unknown word where a place word is expected.
        UnsupportedPhrase: an alternative, a spatial relation or a modifier.
        MalformedInstruction: a marker with nothing after it; Japanese places not joined.
    """
    items = merge_phrases(scan(text, grammar, place_words), grammar)
    places = [i for i, it in enumerate(items) if it.kind == "place"]
    if not places:
        others = [it.surface for it in items if it.kind == "other"]
        words = [it.surface for it in items if it.kind == "other" or it.surface in grammar.nouns]
        raise UnknownPlaceWord(
            f"no known place word in {excerpt(text)}{not_understood(others)}{unknown_tail(words, place_words)}"
        )
    refuse_unsupported(items, grammar)
    _refuse(items, grammar, place_words)
    refuse_unjoined(items, grammar)
    _check_place_positions(items, grammar, place_words)
    roles = _prefix_roles(items, place_words) if grammar.attach == "prefix" else _postfix_roles(items, grammar)
    _check_modifiers(items, grammar, place_words)
    refuse_unknown(items, place_words)
    refuse_list_without_goal(items, places, roles, grammar)
    for idx, (role, source) in zip(places, roles, strict=True):
        if role == "from":
            raise refuse_start_place(items[source], items[idx])
    return _phrases(items, places, roles, grammar)


_ANCHORS = ("place", "marker", "connector", "order", "alternative", "relation", "modifier")


def _neighbour_place(items: list[Item], idx: int, step: int) -> Item | None:
    """The place phrase next to ``items[idx]`` in direction ``step`` with only fillers/other words between."""
    j = idx + step
    while 0 <= j < len(items) and items[j].kind in ("filler", "other"):
        j += step
    return items[j] if 0 <= j < len(items) and items[j].kind == "place" else None


def _refuse(items: list[Item], grammar: Grammar, place_words: Sequence[str]) -> None:
    """Rule 2: alternatives, spatial relations and modifiers are errors, not guesses."""
    step = 1 if grammar.attach == "prefix" else -1
    for idx, it in enumerate(items):
        if it.kind not in ("alternative", "relation", "modifier"):
            continue
        word = excerpt(it.surface)
        if it.kind == "alternative":
            around = [p.surface for p in (_neighbour_place(items, idx, -1), _neighbour_place(items, idx, 1)) if p]
            choice = f" ({' or '.join(around)})" if around else ""
            raise UnsupportedPhrase(
                f"{word} leaves the choice of a place open{choice}; the planner needs one "
                "place for each waypoint and one goal: say which one"
            )
        if it.kind == "relation":
            other = _neighbour_place(items, idx, step)
            what = f" ({other.surface})" if other else ""
            raise UnsupportedPhrase(
                f"{word} describes a place by where it lies relative to another{what}; the "
                "map does not model spatial relations between places: name the place itself; "
                f"{known_words(place_words)}"
            )
        if it.kind == "modifier":
            place = _neighbour_place(items, idx, 1) or _neighbour_place(items, idx, -1)
            which = f" {place.surface}" if place else " place"
            raise UnsupportedPhrase(
                f"{word} picks one{which} by order, side or size, which the map does not "
                f"hold; say the place's name alone (the planner goes to the closest place "
                f"with that name)"
            )


def _expects_place(it: Item) -> bool:
    return (
        (it.kind == "marker" and it.value != "from")
        or it.kind == "connector"
        or (it.kind == "order" and it.value in ("before", "after"))
    )


def _check_place_positions(items: list[Item], grammar: Grammar, place_words: Sequence[str]) -> None:
    """Rule 6, first part: other words where a place word is expected are an error naming them."""
    anchors = [i for i, it in enumerate(items) if it.kind in _ANCHORS]
    prefix = grammar.attach == "prefix"
    for a, idx in enumerate(anchors):
        it = items[idx]
        if not _expects_place(it) or (it.kind == "order" and prefix != (it.value not in grammar.backward_order)):
            continue
        if prefix:
            end = anchors[a + 1] if a + 1 < len(anchors) else len(items)
            run, neighbour = items[idx + 1 : end], (items[end] if end < len(items) else None)
        else:
            begin = anchors[a - 1] if a > 0 else -1
            run, neighbour = items[begin + 1 : idx], (items[begin] if begin >= 0 else None)
        if neighbour is not None and neighbour.kind == "place":
            continue  # a marker and its place (words right next to the place: _check_modifiers)
        if it.kind == "marker" and neighbour is not None and neighbour.kind == "marker" and neighbour.value == it.value:
            continue  # taken over by the next (English) / previous (Japanese) marker of the same role
        if it.kind == "connector" and it.surface in grammar.soft_connectors:
            first = next((k for k, x in enumerate(run) if x.kind == "other"), None)
            if first is None or not any(x.surface in grammar.determiners for x in run[:first]):
                continue
        others = [x.surface for x in run if x.kind == "other"]
        if others:
            where = "after" if prefix else "before"
            verb = "is not a known place word" if len(others) == 1 else "are not known place words"
            raise UnknownPlaceWord(
                f"{named(others)} ({where} {excerpt(it.surface)}) {verb}{unknown_tail(others, place_words)}"
            )


def _check_modifiers(items: list[Item], grammar: Grammar, place_words: Sequence[str]) -> None:
    """Rule 6, second part: an other word right next to a place phrase would modify it ("the big kitchen",
    "alices room", 大きいキッチン): refused, never dropped."""
    for idx, it in enumerate(items):
        if it.kind != "place":
            continue
        for j, where in ((idx - 1, "before"), (idx + 1, "after")):
            if 0 <= j < len(items) and items[j].kind == "other":
                word = items[j].surface
                pair = [word, it.surface] if j < idx else [it.surface, word]
                raise UnknownPlaceWord(
                    f"{named([word])} ({where} {excerpt(it.surface)}) is not a known place "
                    f"word{unknown_tail(pair, place_words)}"
                )


def _prefix_roles(items: list[Item], place_words: Sequence[str]) -> list[tuple[str, int]]:
    roles: list[tuple[str, int]] = []
    role, source, dangling = None, -1, None
    for idx, it in enumerate(items):
        if it.kind == "marker":
            if dangling is not None:
                d = items[dangling]
                only_fillers = all(
                    x.kind == "filler" or (x.kind == "marker" and x.value != "from") for x in items[dangling + 1 : idx]
                )
                if d.value == "avoid" and it.value == "avoid" and only_fillers:
                    raise refuse_double_negation(d, it)
                if d.value in ("avoid", "not_goal") and it.value != "from" and only_fillers:
                    continue  # a negation governs the marker after it ("don't want to go to the kitchen")
                if d.value != "goal":
                    _check_dangling(dangling, items, idx, place_words)
            role, source, dangling = it.value, idx, (idx if it.value != "from" else None)
        elif it.kind == "place":
            roles.append((role or "goal", source))
            dangling = None
    _check_dangling(dangling, items, len(items), place_words)
    return roles


def _postfix_roles(items: list[Item], grammar: Grammar) -> list[tuple[str, int]]:
    """The first marker after a phrase decides; connectors defer to the next phrase; a backward order word
    (キッチンの後で) closes its phrases as places to visit."""
    roles: list[tuple[str, int]] = []
    pending: list[int] = []  # phrase indices waiting for a role
    since_phrase = True  # no marker yet after the last phrase
    last_place = -1
    for idx, it in enumerate(items):
        if it.kind == "place":
            between = items[last_place + 1 : idx]
            if pending and not any(x.kind in ("connector", "order") for x in between):
                others = [x.surface for x in between if x.kind == "other"]
                raise (UnknownPlaceWord if others else MalformedInstruction)(
                    f"{excerpt(items[last_place].surface)} and {excerpt(it.surface)} are not joined by a connector "
                    f"or a marker{not_understood(others)}; join places with と or give each its own marker"
                )
            roles.append(("", -1))
            pending.append(len(roles) - 1)
            since_phrase = True
            last_place = idx
        elif it.kind == "order" and it.value in grammar.backward_order and pending and since_phrase:
            for p in pending:
                roles[p] = ("goal", -1)
            pending, since_phrase = [], False
        elif it.kind == "marker":
            if pending and since_phrase:
                for p in pending:
                    roles[p] = (it.value, idx)
                pending = []
            elif it.value in ("waypoint", "avoid", "not_goal"):
                last = max((j for j in range(idx) if items[j].kind in ("place", "marker", "order")), default=-1)
                unread = [x.surface for x in items[last + 1 : idx] if x.kind == "other"]
                err = UnknownPlaceWord if unread else MalformedInstruction
                raise err(f"{excerpt(it.surface)} follows no known place word{not_understood(unread)}")
            since_phrase = False
    for p in pending:
        roles[p] = ("goal", -1)
    return roles


def _check_dangling(dangling: int | None, items: list[Item], end: int, place_words) -> None:
    if dangling is None:
        return
    between = [x.surface for x in items[dangling + 1 : end] if x.kind == "other"]
    if between:
        raise UnknownPlaceWord(
            f"{excerpt(items[dangling].surface)} is followed by no known place word"
            f"{not_understood(between)}{unknown_tail(between, place_words)}"
        )
    raise MalformedInstruction(
        f"{excerpt(items[dangling].surface)} is followed by no known place word; say "
        "which place, e.g. 'avoiding the kitchen'"
    )


def _phrases(items: list[Item], places: list[int], roles: list[tuple[str, int]], grammar: Grammar) -> list[Phrase]:
    """Phrases with their clause, the order words that apply to them and the sequencers before them."""
    clause, clauses = 0, []
    for it in items:
        clause += it.kind == "connector"
        clauses.append(clause)
    out = [Phrase(items[i], role, src, clauses[i], i) for i, (role, src) in zip(places, roles, strict=False)]
    for prev, p in pairwise(out):
        p.after_sequencer = any(x.kind == "connector" and x.value == "seq" for x in items[prev.index + 1 : p.index])
    for p in out:
        if p.source >= 0 and items[p.source].surface in grammar.final_markers:  # "end at the toilet"
            p.orders["last"] = items[p.source]
    for idx, it in enumerate(items):
        if it.kind == "order":
            targets = _ordered_by(idx, it, out, items, clauses, grammar)
            if not targets and it.value in ("before", "after", "before_that"):
                raise MalformedInstruction(
                    f"{excerpt(it.surface)} is followed by no known place word; say which "
                    "place, e.g. 'go to the bedroom after the kitchen'"
                )
            chain = _chained(idx, it, targets, out, items, grammar) if targets else 0
            for n in targets:
                out[n].orders.setdefault(it.value, it)
                out[n].chain = chain
    return out


def _chained(idx: int, it: Item, targets: list[int], phrases: list[Phrase], items: list[Item], grammar: Grammar) -> int:
    """Rule 8: a before / after that continues a chain gets its place one link further, as a sort key of
    :mod:`spcotmhp.planning.sequence` (0 outside chains). English: the word stands right after a phrase that an
    earlier before / after orders, through fillers ("the bath after the kitchen after the toilet": toilet, kitchen,
    bath; "before ... before": forwards). Japanese: its place comes right after another before / after word,
    through fillers and markers (トイレの後でキッチンの後で寝室: toilet, kitchen, bedroom;
    寝室に行く前にトイレに行く前にキッチン: kitchen, toilet, bedroom). A chain mixing before and after
    leaves the order open and is refused."""
    if it.value not in ("before", "after"):
        return 0
    prefix = grammar.attach == "prefix"
    j = (idx if prefix else min(phrases[n].index for n in targets)) - 1
    while j >= 0 and (items[j].kind == "filler" or (not prefix and items[j].kind == "marker")):
        j -= 1
    if prefix:
        prev = next((p for p in phrases if p.index == j), None)
    elif j >= 0 and items[j].kind == "order":
        prev = next((p for p in phrases if items[j] in p.orders.values()), None)
    else:
        prev = None
    timed = [o for o in ("before", "after") if prev is not None and o in prev.orders]
    if prev is None or not timed:
        return 0
    if timed[0] != it.value:
        raise UnsupportedPhrase(
            f"{excerpt(it.surface)} orders a place against {excerpt(prev.item.surface)}, itself ordered by "
            f"{excerpt(prev.orders[timed[0]].surface)}: a chain mixing before and after leaves the order open; "
            "say the order with 'first' and 'then'"
        )
    return prev.chain + (1 if (it.value == "before") == prefix else -1)


def _ordered_by(
    idx: int, it: Item, phrases: list[Phrase], items: list[Item], clauses: list[int], grammar: Grammar
) -> list[int]:
    """Indices of the phrases an order word applies to.

    before / after / before_that: the next phrase (Japanese 前に, 後で: the previous one) and the phrases joined
    to it by "and" / と with the same role ("after the kitchen and the toilet"). first / last / on_the_way: in
    English, every phrase of the order word's clause, or of the next clause with a phrase when its own has
    none ("first, go to the kitchen"); in Japanese, the next phrase and its joined phrases (まずキッチンに行って).
    """
    if grammar.attach == "prefix" and it.value in ("first", "last", "on_the_way"):
        mine = [n for n, p in enumerate(phrases) if p.clause == clauses[idx]]
        if mine:
            return mine
        later = [p.clause for p in phrases if p.index > idx]
        return [n for n, p in enumerate(phrases) if later and p.clause == later[0]]
    backward = it.value in grammar.backward_order
    if backward:
        start = max((n for n, p in enumerate(phrases) if p.index < idx), default=None)
    else:
        start = next((n for n, p in enumerate(phrases) if p.index > idx), None)
    if start is None:
        return []
    step = -1 if backward else 1
    out, n = [start], start
    while 0 <= n + step < len(phrases):
        a, b = sorted((phrases[n], phrases[n + step]), key=lambda p: p.index)
        between = items[a.index + 1 : b.index]
        joined = any(x.kind == "connector" and x.surface not in grammar.soft_connectors for x in between) and all(
            x.kind in ("connector", "filler") for x in between
        )
        if not joined or a.role != b.role or a.source != b.source or b.after_sequencer:
            break
        n += step
        out.append(n)
    return out
