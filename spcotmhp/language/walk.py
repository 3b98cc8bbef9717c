"""What the two languages' derivations share: the places said so far (mentions, with their roles, ranks, steps
and waits), the place phrases with their relations, and the final :class:`~spcotmhp.language.meaning.Reading`
with its checks. :mod:`spcotmhp.language.walk_en` and :mod:`spcotmhp.language.walk_ja` read the derivations."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace

from lark import Token as LarkToken
from lark import Tree

from spcotmhp.errors import EmptyInstruction, InstructionTooLarge, UnsupportedPhrase
from spcotmhp.language.floors import FloorValue
from spcotmhp.language.lexicon import MAX_WAIT_S
from spcotmhp.language.meaning import PlaceRef, Reading, Relation
from spcotmhp.language.order import Visit, visiting_order
from spcotmhp.language.placewords import Token
from spcotmhp.language.table import WordTable
from spcotmhp.language.wording import excerpt

VISIT_ROLES = ("goal", "via", "stop", "visit")
"""Roles of places to visit: to go to, to pass, to stop at, ordered by an order word only."""
_ROLE_WORDS = {"goal": "to go to", "via": "to pass", "stop": "to stop at", "visit": "to visit", "avoid": "to avoid",
               "not_goal": "not to end in"}  # fmt: skip


@dataclass
class Mention:
    """A place said, with what the sentence says about it."""

    ref: PlaceRef
    role: str  # goal, via, stop, visit, avoid, not_goal
    sentence: int
    step: int
    rank: int = 1  # first 0, finally 2
    tied: bool = False  # the object of an order word (never the free destination: order.py rule 4)
    wait: float | None | bool = False  # False: no wait; None: until the next instruction; seconds
    contrast: bool = False  # a negated bare name ("not the bath")
    inherited: bool = False  # a bare name after a connector, with the role of the place before it
    order_kind: str = ""  # "before" / "after" when an order word introduced it
    wait_word: str = "wait"  # the word that asked for the wait
    wait_said: str = ""  # the length as said ("2 hours", 2時間), quoted when it is too long
    clause: int = 0  # the clause it was said in (order.py rule 4)
    dropped: bool = False  # replaced by a later self-correction ("the kitchen, no wait, the bath")


def _too_long(seconds: float, said: str = "") -> InstructionTooLarge:
    """A wait longer than :data:`MAX_WAIT_S`, quoting the length as said when known ("'two hours': ...")."""
    if said:
        return InstructionTooLarge(
            f"{excerpt(said)} asks for a wait of {seconds:.0f} s, longer than the {MAX_WAIT_S:.0f} s accepted"
        )
    return InstructionTooLarge(f"a wait of {seconds:.0f} s is longer than the {MAX_WAIT_S:.0f} s accepted")


def _same(a: PlaceRef, b: PlaceRef) -> bool:
    """Whether two place phrases name the same place, however said ("寝室のいちばん", "一番の寝室")."""
    return (a.words, a.relation, a.every, a.floor, a.number) == (b.words, b.relation, b.every, b.floor, b.number)


def _fresh(before: list[Mention], said: list[Mention]) -> list[Mention]:
    """The mentions ``said`` after a correction from the first that is not a place of ``before`` said again with the
    same role (contrasts left out): a restatement's start corrects nothing ("A via B, no, via B to C": C corrects A)."""
    new = [m for m in said if not m.contrast]
    k = 0
    while k < len(new) and any(b.role == new[k].role and _same(b.ref, new[k].ref) for b in before):
        k += 1
    return new[k:]


def tree(node: object) -> Tree:
    """``node`` as a subtree (the grammar puts one there)."""
    assert isinstance(node, Tree), node
    return node


def tok(node: object) -> LarkToken:
    """``node`` as a token (the grammar puts one there)."""
    assert isinstance(node, LarkToken), node
    return node


def subtrees(node: Tree) -> list[Tree]:
    return [c for c in node.children if isinstance(c, Tree)]


def tokens_of(node: Tree) -> list[LarkToken]:
    return [c for c in node.children if isinstance(c, LarkToken)]


@dataclass
class Walk:
    """The state of reading one derivation (subclasses read the trees of one language)."""

    toks: list[Token]
    text: str
    table: WordTable
    mentions: list[Mention] = field(default_factory=list)
    pairs: list[tuple[int, int]] = field(default_factory=list)  # (a, b): mention a before mention b
    speeds: list[str] = field(default_factory=list)
    said: list[PlaceRef] = field(default_factory=list)  # every place name read, relations' places too, in order
    sentence: int = 0
    step: int = 0
    clause: int = 0
    heard: list[str] = field(default_factory=list)  # what the reading did beyond the grammar (corrections)
    correction: tuple[str, int, int] | None = None  # a correction word said, the mentions and speeds before it
    restated: list[int] = field(default_factory=list)  # where an applied correction's phrase begins (mentions)

    # ---- mentions ----------------------------------------------------------------------------------------
    def mention(self, ref: PlaceRef, role: str) -> Mention:
        """A new mention, or the last one again when "there" / "it" points back to it, or the same place is said
        again right after it in the same role ("the bedroom near the hall, go there", "the washroom? go to the
        washroom": one visit; "go to the bedroom via the bedroom" is two)."""
        last = next((m for m in reversed(self.mentions) if not m.contrast), None)  # "X. Not Y, X": X once
        again = last is not None and (last.ref is ref or (_same(last.ref, ref) and last.role == role))
        if again and last is not None and last.role in VISIT_ROLES and role in VISIT_ROLES:
            if role == "goal":  # "there" / "it", or a place to go to said twice in a row: one visit
                last.role = "goal"
            return last
        m = Mention(ref, role, self.sentence, self.step, clause=self.clause)
        self.mentions.append(m)
        return m

    def waiting_place(self, ref: PlaceRef) -> Mention:
        """Where "wait in the X" / Xで待って waits: the place to visit said last when it is the X ("go to the kitchen
        and wait in the kitchen": one visit), else a new stop."""
        k = self.last_visit()
        return self.mentions[k] if k is not None and self.mentions[k].ref == ref else self.mention(ref, "stop")

    def last_visit(self, before: int | None = None) -> int | None:
        """Index of the last mention of a place to visit before index ``before`` (default: all)."""
        end = len(self.mentions) if before is None else before
        return next((k for k in range(end - 1, -1, -1) if self.mentions[k].role in VISIT_ROLES), None)

    def last_goal(self, before: int) -> int | None:
        """Index of the last place to go to said before index ``before``: the destination a place passed "on the
        way" is on the way to."""
        return next((k for k in range(before - 1, -1, -1) if self.mentions[k].role == "goal"), None)

    def destination(self) -> int | None:
        """Index of the place the robot is going to at this point ("wait there"): the last place to go to of the
        current step, else of the step before it (where that step ends: "go to the washroom via the bath, and then
        wait there" waits at the washroom, passed after the bath), else the last place to visit."""
        for step in (self.step, self.step - 1):
            goals = [k for k, m in enumerate(self.mentions) if m.role == "goal" and m.step == step]
            if goals:
                return goals[-1]
            if any(m.step == step for m in self.mentions):
                break  # "then go through the hall and wait there": the place of this step
        return self.last_visit()

    def apply_orders(self, orders: list[str], mine: list[Mention], start: int) -> None:
        """Order words on the mentions they apply to: "first" / まず rank them first, "finally" / 最後に last, "on
        the way" / 途中で make a place to go to one to pass (unless the clause passes one itself), passed before
        the place to go to said before them ("toilet next, and pass through the kitchen on the way": on the way to
        the toilet), "before that" / その前に puts them right before the place said before index ``start``."""
        passed = any(m.role == "via" for m in mine)  # "go to the kitchen passing the hall on the way": the hall
        for order in orders:
            for m in mine:
                if order == "first":
                    m.rank = 0
                elif order == "last":
                    m.rank = 2
                elif order == "on_the_way":
                    m.role = "via" if m.role == "goal" and not passed else m.role
                    target = self.last_goal(start)
                    if m.role == "via" and target is not None:  # "toilet next, and pass the kitchen on the way"
                        m.tied, m.step = True, self.mentions[target].step  # on the way there: that step's
                        self.pairs.append((self.mentions.index(m), target))
                elif order == "before_that":
                    target = self.last_visit(start)
                    if target is not None:
                        m.tied = True
                        self.pairs.append((self.mentions.index(m), target))

    def last_ref(self, word: str) -> PlaceRef:
        """The place said last ("there", "it"); refused when none was."""
        if not self.mentions:
            raise UnsupportedPhrase(f"{excerpt(word)} names no place said before it: say the place's name")
        return self.mentions[-1].ref

    def word(self, node: object) -> str:
        """The words of token ``node`` as said (a derivation's leaves carry only their index: reading.py)."""
        return self.toks[tok(node).start_pos or 0].surface

    def place(self, node: LarkToken, relation: Relation | None = None, every: bool = False) -> PlaceRef:
        """The :class:`PlaceRef` of a PLACE token."""
        t = self.toks[node.start_pos or 0]
        ref = PlaceRef(t.words, t.surface, relation, every, number=t.number)
        self.said.append(ref)
        return ref

    def floor(self, nodes: Iterable[object]) -> tuple[FloorValue | None, str]:
        """The floor of the FLOOR (or FLOOR_TO) token among ``nodes`` and its words, if any."""
        for node in nodes:
            if isinstance(node, LarkToken) and node.type in ("FLOOR", "FLOOR_TO"):
                t = self.toks[node.start_pos or 0]
                return t.floor, t.surface
        return None, ""

    def on_floor(self, ref: PlaceRef, nodes: Iterable[object]) -> PlaceRef:
        """``ref`` on the floor a FLOOR token among ``nodes`` says ("go upstairs to the bedroom on the first floor":
        two floors, refused)."""
        floor, said = self.floor(nodes)
        if floor is None or floor == ref.floor:
            return ref
        if ref.floor is not None:
            raise UnsupportedPhrase(f"{excerpt(ref.label)} is given two floors ({ref.floor_said}, {said}); say one")
        return replace(ref, floor=floor, floor_said=said)

    def seconds(self, nodes: Iterable[object]) -> float | None:
        """The seconds of the DURATION token among ``nodes``, if any; two lengths for one wait are refused ("wait
        30 seconds 1 minute": which?)."""
        said = [self.toks[n.start_pos or 0] for n in nodes if isinstance(n, LarkToken) and n.type == "DURATION"]
        if len(said) > 1:
            lengths = " and ".join(excerpt(t.surface) for t in said)
            raise UnsupportedPhrase(f"{lengths} are two lengths for one wait; say one ('wait 1 minute 30 seconds')")
        if said and said[0].seconds > MAX_WAIT_S:
            raise _too_long(said[0].seconds, said[0].surface)
        return said[0].seconds if said else None

    def wait_at(self, m: Mention, toks: list[LarkToken]) -> None:
        """``m`` waits for the DURATION among ``toks`` (or until the next instruction), as the WAIT token said."""
        m.wait = self.seconds(toks)
        m.wait_word = next((self.word(t) for t in toks if t.type == "WAIT"), m.wait_word)
        m.wait_said = next((self.word(t) for t in toks if t.type == "DURATION"), m.wait_said)

    def replaces_again(self, x: Mention, y: Mention) -> bool:
        """Whether ``y``, the place ``x`` said again with another role after a correction, replaces it: the later
        role is what is meant (キッチン通って、いや、キッチンは通らないで; "via the kitchen, no, avoid the kitchen");
        English keeps two readings refused (:meth:`~spcotmhp.language.walk_en.EnglishWalk.replaces_again`)."""
        return True

    def correcting(self, word: str) -> None:
        """A correction word was said: it applies to what is said next (:meth:`corrected`)."""
        if self.correction is None:
            self.correction = (word, len(self.mentions), len(self.speeds))

    def corrected(self, end: bool = False) -> None:
        """Apply a pending correction once something it may replace was said after it (a place to visit, avoid or
        not end in, or a speed; a negated name alone waits for the place meant instead), or at the ``end`` (then
        refused when something was said before it but nothing after)."""
        if self.correction is None:
            return
        word, start, speeds = self.correction
        before = [m for m in self.mentions[:start] if not m.dropped]
        new = bool(_fresh(before, self.mentions[start:])) or len(self.speeds) > speeds
        if new or end:
            self.correction = None
            self.correct(word, start, speeds)

    def correct(self, word: str, start: int, speeds: int) -> None:
        """A self-correction ("X, no wait, Y", "X sorry I meant Y", X、いや、Y), applied once the phrase after it is
        read (its mentions from index ``start``, its speeds from ``speeds``). The rule: the first place the phrase
        names to visit, avoid or not end in (a negated name, "not the bedroom", only says what is not meant; places
        said again with their roles first start a restatement: :func:`_fresh`) replaces the nearest place of the
        same role said before the correction; a bare place after it takes the role of the place said just before it
        (walk_en.py, walk_ja.py), so "go to the kitchen via the hall, sorry, the corridor" passes the corridor. A
        phrase naming no place but a speed replaces the speed said before. With nothing before it to correct (it
        opens the instruction: "Actually, go to the kitchen") it corrects nothing; a place said again with another
        role replaces its first mention (:meth:`replaces_again`); refused when the phrase after it names nothing, or
        no place of that role was said before."""
        before = [m for m in self.mentions[:start] if not m.dropped]
        if not before and speeds == 0:
            return
        new = [m for m in self.mentions[start:] if not m.contrast]
        if new:
            y = next(iter(_fresh(before, new)), new[0])
            x = next((m for m in reversed(before) if m.role == y.role), None)
            if x is None and y.role != "not_goal":  # キッチン通って、いや、キッチンは通らないで
                x = next((m for m in reversed(before) if m.ref == y.ref and self.replaces_again(m, y)), None)
            if x is None:
                raise UnsupportedPhrase(
                    f"{excerpt(word)} corrects what was said before it, but no place {_ROLE_WORDS[y.role]} was said "
                    f"before {excerpt(y.ref.label)}; say the instruction again as meant"
                )
            rel = x.ref.relation
            if rel is not None and rel.args and y.ref.relation is None and set(y.ref.words).isdisjoint(x.ref.words):
                raise UnsupportedPhrase(  # "the bedroom closest to the bath, I mean the toilet": which is replaced?
                    f"{excerpt(word)} {excerpt(y.ref.label)} may replace {excerpt(x.ref.label)} or the "
                    f"{excerpt(rel.args[-1].label)} it is picked by; say the place again whole"
                )
            x.dropped = True
            self.restated.append(start)
            if x.role != y.role:  # the same place, another role
                said = f"{y.ref.describe()} {_ROLE_WORDS[y.role]} said instead of {_ROLE_WORDS[x.role]}"
                self.heard.append(said)
            else:
                self.heard.append(f"{y.ref.describe()} said instead of {x.ref.describe()}")
            return
        if len(self.speeds) > speeds:
            del self.speeds[:speeds]
            self.heard.append(f"{self.speeds[-1]} said instead of the speed before")
            return
        raise UnsupportedPhrase(
            f"{excerpt(word)} corrects what was said before it, but names nothing after it; say the instruction again "
            "as meant"
        )

    # ---- the reading ---------------------------------------------------------------------------------------
    def result(self) -> Reading:
        """The :class:`Reading` of the mentions, or the refusal of what cannot be honoured."""
        for start in self.restated:  # "A via B, no, C via B": the instruction said again after a correction; its
            for z in self.mentions[start:]:  # places named before it with the same role are said once, here
                for m in self.mentions[:start]:
                    if not z.dropped and not z.contrast and m.role == z.role and _same(m.ref, z.ref):
                        m.dropped = True
        visits = [k for k, m in enumerate(self.mentions) if m.role in VISIT_ROLES and not m.dropped]
        avoid = list(dict.fromkeys(m.ref for m in self.mentions if m.role == "avoid" and not m.dropped))
        not_goal = list(dict.fromkeys(m.ref for m in self.mentions if m.role == "not_goal" and not m.dropped))
        if not visits:
            what = "places to avoid or not to end in" if avoid or not_goal else "no place"
            raise EmptyInstruction(f"{excerpt(self.text)} names no place to go to, only {what}; say where to go")
        last = self.mentions[visits[-1]]
        if all(self.mentions[k].role == "via" for k in visits) and last.inherited and len(visits) > 1:
            last.role = "goal"  # "go through the corridor and then the bedroom": the last place is where to go
        if all(self.mentions[k].role == "via" for k in visits):
            passed = ", ".join(self.mentions[k].ref.label for k in visits)
            raise UnsupportedPhrase(
                f"{excerpt(self.text)} names only places to pass ({passed}) and no destination: say where to go"
            )
        order = visiting_order(
            [Visit(k, m.rank, m.step, m.role, m.tied, m.clause) for k, m in ((k, self.mentions[k]) for k in visits)],
            [(visits.index(a), visits.index(b)) for a, b in self.pairs if a in visits and b in visits],
        )
        ordered = self._once([self.mentions[visits[i]] for i in order])
        self._check(ordered, avoid, not_goal)
        waits = tuple((i, m.wait) for i, m in enumerate(ordered) if m.wait is not False)
        for i, wait in waits:
            if wait is None and i < len(ordered) - 1:
                raise UnsupportedPhrase(
                    f"{excerpt(ordered[i].wait_word)} between two places (at {excerpt(ordered[i].ref.label)}, on the "
                    "way) is a correction or a stop with no length; say how long ('wait there for 2 minutes, then ...')"
                )
            if isinstance(wait, float) and wait > MAX_WAIT_S:
                raise _too_long(wait, ordered[i].wait_said)
        speeds = sorted(set(self.speeds))
        if len(speeds) > 1:
            raise UnsupportedPhrase(f"{excerpt(self.text)} asks for two speeds ({' and '.join(speeds)}): say one")
        return Reading(
            tuple(m.ref for m in ordered),
            tuple(avoid),
            tuple(not_goal),
            speeds[0] if speeds else None,
            tuple((i, w if isinstance(w, float) else None) for i, w in waits),
            tuple(self.heard),
        )

    def _once(self, ordered: list[Mention]) -> list[Mention]:
        """A place to visit said again right after itself, with no wait at the first saying ("ダイニングに行って。
        キッチンじゃないよ、ダイニング。", "go to the kitchen, the kitchen I said"), is one visit: going from a place
        to itself is no way through it, and read as two the plan would name it a waypoint nobody asked for."""
        out: list[Mention] = []
        for m in ordered:
            if out and out[-1].wait is False and _same(out[-1].ref, m.ref):
                self.heard.append(f"{m.ref.describe()} said again: one visit")
                out[-1] = m
            else:
                out.append(m)
        return out

    def _check(self, ordered: list[Mention], avoid: list[PlaceRef], not_goal: list[PlaceRef]) -> None:
        for m in ordered:
            if m.ref.every:
                raise UnsupportedPhrase(
                    f"{excerpt(m.ref.label)} asks for every place of that name, but a plan goes to one place for "
                    "each waypoint and one goal: name them one by one"
                )
        # a place both to visit and to avoid (or not to end in) is refused by the planner, which knows its
        # instances (ConflictingInstruction): "the bedroom, avoiding the bedroom next to the bath" is no conflict
