"""Reading an instruction: its tokens (:mod:`spcotmhp.language.lexicon`) parsed by the grammar of its language
(``grammars/<lang>.lark``, LALR(1) with no conflict: one derivation per sentence), and the derivation read into a
:class:`~spcotmhp.language.meaning.Reading`.

What the derivation means (the rules a reader of the grammar needs besides it):

* Roles. "to" / "into" / a bare name: a place to go to (goal); "via", "through", "past": a place to pass; "stop
  at", "visit", "swing by": a place to stop at; "avoid", "stay out of", "don't go through", "without": a place to
  avoid. A name after a connector ("and", a comma, "then") with no marker of its own shares the role of the place
  said before it in its sentence ("avoiding the living room and the kitchen"). A negated bare name ("not the
  bath", "instead of the bath") contrasts with the place said before it: not the goal after a goal, avoided after
  a place to pass.
* Order (:mod:`spcotmhp.language.order`): "first", "finally", "on the way" apply to the places of their clause (or
  of the next clause that names one); "X after Y" puts Y before X, "X before Y" puts Y after X (X: the place said
  right before the order word; at the start of a sentence, the places after it); "before that" puts the places
  of its clause before the place said before it; "then" followed by a marker starts a new step.
* Waits and speeds: "wait (there)" waits at the place the robot is going to at that point; "wait in the hall",
  "stop at the kitchen for a minute" name the place; without a length of time the robot waits until the next
  instruction, which only the goal may do. One speed per instruction ("slowly", "hurry").
* Anaphora: "there" and "it" name the place said last; "the one" repeats the name said last.

Refusals (each an :class:`~spcotmhp.errors.InstructionError` naming the words): a WORD (no class, no place)
anywhere; a refusal class of the word table where the grammar does not accept it (its stated reason); any other
token the grammar does not accept there; contradictions (a place to visit and to avoid; two speeds); a relation
followed by "and" and another place ("closest to the kitchen and the bath": one relation of two places, or two
places?); only places to pass and no destination; every place of a name to visit; a wait on the way with no
length.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import resources

from lark import Lark, Token as LarkToken, Tree
from lark.exceptions import UnexpectedInput

from spcotmhp.errors import EmptyInstruction, InstructionTooLarge, UnsupportedPhrase
from spcotmhp.language.errors import refusal
from spcotmhp.language.lexicon import MAX_WAIT_S, Token, tokens, word_table
from spcotmhp.language.meaning import SPEEDS, PlaceRef, Reading, Relation
from spcotmhp.language.order import Visit, visiting_order
from spcotmhp.language.wording import excerpt

VISIT_ROLES = ("goal", "via", "stop", "visit")


@functools.cache
def grammar(lang: str) -> Lark:
    """The LALR(1) parser of ``grammars/<lang>.lark`` (built once per process; Lark raises on any conflict but
    shift/reduce, which ``tests/language/test_grammar.py`` checks for)."""
    text = (resources.files("spcotmhp.language") / "grammars" / f"{lang}.lark").read_text(encoding="utf-8")
    return Lark(text, parser="lalr", lexer="basic", maybe_placeholders=False)


def read(text: str, place_words: Sequence[str], lang: str) -> Reading:
    """The meaning of ``text`` (module docstring); raises an InstructionError saying what was not understood."""
    if not text.strip():
        raise EmptyInstruction("the instruction is empty; say where to go, e.g. 'go to the kitchen'")
    toks = tokens(text, word_table(lang), place_words)
    interactive = grammar(lang).parse_interactive("")
    try:
        for i, tok in enumerate(toks):
            interactive.feed_token(LarkToken(tok.kind, tok.surface, start_pos=i))
        tree = interactive.feed_eof()
    except UnexpectedInput as exc:
        raise refusal(toks, getattr(exc, "token", None), word_table(lang), place_words, text) from None
    return _Walk(toks, text, lang).reading(tree)


@dataclass
class _Mention:
    ref: PlaceRef
    role: str
    sentence: int
    clause: int
    step: int
    rank: int = 1
    tied: bool = False
    wait: float | None | bool = False  # False: no wait; None: until the next instruction; seconds
    contrast: bool = False  # a negated bare name ("not the bath")
    inherited: bool = False  # a bare name after a connector, with the role of the place before it
    order_kind: str = ""  # "before" / "after" when an order word introduced it


@dataclass
class _Walk:
    toks: list[Token]
    text: str
    lang: str
    mentions: list[_Mention] = field(default_factory=list)
    pairs: list[tuple[int, int]] = field(default_factory=list)
    speeds: list[str] = field(default_factory=list)
    sentence: int = 0
    clause: int = 0
    step: int = 0
    pending: list[str] = field(default_factory=list)  # first / last / on_the_way / before_that for the next clause
    later: list[tuple[str, int, int, str]] = field(default_factory=list)  # (kind, mention, sentence, word) with no X
    joint: Tree | None = None
    related_end: str | None = None  # the clause before ended with a relation of another place
    waited: bool = False  # the clause before holds a wait
    halted: str = ""  # a "stop" was said: no place may follow it

    # ---- the tree ---------------------------------------------------------------------------------------
    def reading(self, tree: Tree) -> Reading:
        for sentence in tree.children:
            self._sentence(sentence)
            self.sentence += 1
        return self._result()

    def _sentence(self, sentence: Tree) -> None:
        self.joint, self.related_end, self.waited = None, None, False
        for child in sentence.children:
            if child.data == "lead" and self.mentions:
                word = child.children[0]
                raise UnsupportedPhrase(f"{excerpt(word.value)} {word_table(self.lang).reasons['CORRECTION']}")
            if child.data == "joint":
                self.joint = child
            elif child.data == "clause":
                self._clause(child)
                self.joint = None

    def _clause(self, clause: Tree) -> None:
        joint_words = {t.type for t in self.joint.children} if self.joint is not None else set()
        first = clause.children[0]
        if "THEN" in joint_words and first.data != "bare":
            self.step += 1
        if self.related_end is not None and "AND" in joint_words and "THEN" not in joint_words and first.data == "bare":
            raise UnsupportedPhrase(
                f"'and' after {excerpt(self.related_end)} could add a place to the relation or name another "
                "place to go to: say 'then' for another place, or name one place in the relation"
            )
        start = len(self.mentions)
        orders: list[str] = []
        self.waited = self.waited and bool(self.joint is not None)
        for k, item in enumerate(clause.children):
            self._item(item, orders, first_item=k == 0)
        self.related_end = _ends_with_relation(clause)
        self.waited = any(isinstance(c, Tree) and c.data == "wait" for c in clause.children)
        mine = [m for m in self.mentions[start:] if m.role in VISIT_ROLES]
        if mine:
            self._apply(self.pending + orders, mine, start)
            self.pending = []
        else:
            self.pending += orders
        self.clause += 1

    def _apply(self, orders: list[str], mine: list[_Mention], start: int) -> None:
        for order in orders:
            for m in mine:
                if order == "first":
                    m.rank = 0
                elif order == "last":
                    m.rank = 2
                elif order == "on_the_way" and m.role == "goal":
                    m.role = "via"
                elif order == "before_that":
                    target = self._last_visit(start)
                    if target is not None:
                        m.tied = True
                        self.pairs.append((self.mentions.index(m), target))

    def _item(self, item: Tree, orders: list[str], first_item: bool) -> None:
        kind = item.data
        kids = [c for c in item.children if isinstance(c, Tree)]
        toks = [c for c in item.children if isinstance(c, LarkToken)]
        seconds = next((self.toks[t.start_pos].seconds for t in toks if t.type == "DURATION"), None)
        if kind == "bare":
            role = self._inherited_role(first_item)
            m = self._mention(self._ref(kids[0]), role)
            m.inherited = first_item and self.joint is not None
        elif kind in ("goal", "goal_last", "goal_on_the_way", "via", "stop", "avoid", "hurry_goal"):
            role = {"goal_last": "goal", "goal_on_the_way": "goal", "hurry_goal": "goal"}.get(kind, kind)
            ref = self._ref(kids[0]) if kids else self._there(toks)
            m = self._mention(ref, role)
            if kind == "goal_last":
                m.rank = 2
            if kind == "hurry_goal":
                self.speeds.append("fast")
            if seconds is not None:
                m.wait = seconds
        elif kind in ("negated", "negated_marker"):
            ref = self._ref(kids[0]) if kids else self._there(toks)
            m = self._mention(ref, "avoid" if kind == "negated_marker" else self._contrast())
            m.contrast = kind == "negated"
        elif kind in ("before", "after"):
            self._ordered(kind, kids, toks)
        elif kind in ("first", "last", "on_the_way", "before_that"):
            orders.append(kind)
        elif kind == "instead":
            self._instead(toks[0].value)
        elif kind == "halt":
            self.halted = toks[0].value
        elif kind in ("slow", "fast", "hurry"):
            self.speeds.append("fast" if kind == "hurry" else kind)
        elif kind == "wait":
            self._wait(kids, toks, seconds)

    # ---- places -------------------------------------------------------------------------------------------
    def _instead(self, word: str) -> None:
        """ "instead" after two places with no negation before it replaces one of them: which is a guess."""
        visits = [m for m in self.mentions if m.role in VISIT_ROLES]
        if len(visits) >= 2 and not any(m.role in ("avoid", "not_goal") for m in self.mentions):
            table = word_table(self.lang)
            raise UnsupportedPhrase(f"{excerpt(word)} {table.misplaced['INSTEAD'].split(' ', 1)[1]}")

    def _mention(self, ref: PlaceRef, role: str) -> _Mention:
        if self.halted:
            table = word_table(self.lang)
            raise UnsupportedPhrase(f"{excerpt(self.halted)} {table.misplaced['HALT'].split(' ', 1)[1]}")
        again = self._again(ref, role)
        if again is not None:
            return again
        m = _Mention(ref, role, self.sentence, self.clause, self.step)
        self.mentions.append(m)
        return m

    def _inherited_role(self, first_item: bool) -> str:
        """A bare name right after a connector shares the role of the place said before it in its sentence; after
        a contrast and a comma it is the place meant instead ("not the kitchen, the dining room")."""
        if first_item and self.joint is not None:
            joint = {t.type for t in self.joint.children}
            before = [m for m in self.mentions if m.sentence == self.sentence]
            if self.waited and "THEN" not in joint:
                raise UnsupportedPhrase(
                    "'wait' between two places could correct the place before or be a stop on the way: say 'then' "
                    "before the next place, or leave 'wait' out"
                )
            if before:
                if before[-1].role == "not_goal" and before[-1].contrast and joint == {"COMMA"}:
                    return "goal"
                return before[-1].role
        return "goal"

    def _contrast(self) -> str:
        before = self.mentions[-1].role if self.mentions else "goal"
        return "avoid" if before in ("via", "stop", "avoid") else "not_goal"

    def _last_visit(self, before: int) -> int | None:
        return next((k for k in range(before - 1, -1, -1) if self.mentions[k].role in VISIT_ROLES), None)

    def _last_ref(self, word: str) -> PlaceRef:
        if not self.mentions:
            raise UnsupportedPhrase(f"{excerpt(word)} names no place said before it: say the place's name")
        return self.mentions[-1].ref

    def _there(self, toks: list[LarkToken]) -> PlaceRef:
        word = next((t.value for t in toks if t.type == "THERE"), "there")
        return self._last_ref(word)

    def _again(self, ref: PlaceRef, role: str) -> _Mention | None:
        """The mention "there" / "it" points back to, when both are places to visit ("the bedroom near the hall,
        go there": one visit)."""
        last = self.mentions[-1] if self.mentions else None
        if last is not None and last.ref is ref and last.role in VISIT_ROLES and role in VISIT_ROLES:
            if role == "goal":
                last.role = "goal"
            return last
        return None

    def _ref(self, np: Tree) -> PlaceRef:
        """The :class:`PlaceRef` of an ``np`` subtree."""
        if np.data == "it":
            return self._last_ref(np.children[0].value)
        if np.data == "one":
            last = self._last_ref(np.children[0].value)
            return PlaceRef(last.words, last.label, self._relation(np.children[1]))
        name = np.children[0]
        ref = self._name(name)
        if np.data == "related":
            relation = self._relation(np.children[1])
            if relation is not None and ref.relation is not None:
                raise UnsupportedPhrase(f"{excerpt(ref.label)} is given two relations; say one")
            return PlaceRef(ref.words, ref.label, relation or ref.relation, ref.every)
        return ref

    def _name(self, name: Tree) -> PlaceRef:
        place = next(c for c in name.children if isinstance(c, LarkToken) and c.type == "PLACE")
        tok = self.toks[place.start_pos]
        relation = Relation(name.data) if name.data in ("largest", "smallest") else None
        if name.data == "every":
            return PlaceRef(tok.words, f"{name.children[0].value} {tok.surface}", every=True)
        return PlaceRef(tok.words, tok.surface, relation)

    def _relation(self, relation: Tree) -> Relation | None:
        rel = relation.children[-1]
        if rel.data == "nearest":  # "whichever bedroom is closest": the planner's default
            return None
        kind = {"largest_is": "largest", "smallest_is": "smallest"}.get(rel.data, rel.data)
        args = tuple(self._argument(a) for a in rel.children if isinstance(a, Tree))
        return Relation(kind, args)

    def _argument(self, arg: Tree) -> PlaceRef:
        if arg.data in ("it", "there"):
            return self._last_ref(arg.children[0].value)
        tok = self.toks[arg.children[0].start_pos]
        return PlaceRef(tok.words, tok.surface)

    def _ordered(self, kind: str, kids: list[Tree], toks: list[LarkToken]) -> None:
        """ "X after R" / "X before R" (module docstring)."""
        word = next(t.value for t in toks if t.type in ("BEFORE", "AFTER"))
        marker = next((t.type for t in toks if t.type in ("TO", "VIA", "STOP_AT", "ENTER")), "")
        role = {"TO": "goal", "ENTER": "goal", "VIA": "via", "STOP_AT": "stop"}.get(marker, "visit")
        ref = self._ref(kids[0])
        x = len(self.mentions) - 1 if self.mentions and self.mentions[-1].sentence == self.sentence else None
        if x is not None and self.mentions[x].role not in VISIT_ROLES:
            raise UnsupportedPhrase(
                f"{excerpt(word)} orders {excerpt(self.mentions[x].ref.label)}, a place "
                f"{'to avoid' if self.mentions[x].role == 'avoid' else 'not to end in'}; such a place is kept out of "
                "the whole plan, so say it without before / after"
            )
        same = [k for k, m in enumerate(self.mentions) if m.ref == ref and m.role in VISIT_ROLES]
        r = same[0] if same else len(self.mentions)
        if not same:
            self._mention(ref, role)
        self.mentions[r].tied = True
        self.mentions[r].order_kind = kind
        if x is None or x == r:
            self.later.append((kind, r, self.sentence, word))
            return
        if self.mentions[x].order_kind and self.mentions[x].order_kind != kind:
            raise UnsupportedPhrase(
                f"{excerpt(word)} orders a place against {excerpt(self.mentions[x].ref.label)}, itself ordered the "
                "other way: a chain mixing before and after leaves the order open; say the order with 'first' and "
                "'then'"
            )
        self.pairs.append((r, x) if kind == "after" else (x, r))

    def _wait(self, kids: list[Tree], toks: list[LarkToken], seconds: float | None) -> None:
        if kids:
            m = self._mention(self._ref(kids[0]), "stop")
        else:
            k = self._last_visit(len(self.mentions))
            if k is None:
                raise UnsupportedPhrase("'wait' says no place to wait at: say where ('wait in the kitchen')")
            m = self.mentions[k]
        m.wait = seconds

    # ---- the reading ------------------------------------------------------------------------------------------
    def _result(self) -> Reading:
        self._resolve_pending()
        visits = [k for k, m in enumerate(self.mentions) if m.role in VISIT_ROLES]
        avoid = list(dict.fromkeys(m.ref for m in self.mentions if m.role == "avoid"))
        not_goal = list(dict.fromkeys(m.ref for m in self.mentions if m.role == "not_goal"))
        if not visits:
            what = "places to avoid or not to end in" if avoid or not_goal else "no place"
            raise EmptyInstruction(f"{excerpt(self.text)} names no place to go to, only {what}; say where to go")
        last = self.mentions[visits[-1]]
        if all(self.mentions[k].role == "via" for k in visits) and last.inherited and len(visits) > 1:
            last.role = "goal"  # "go through the corridor and then the bedroom": the last place is where to go
        if all(self.mentions[k].role == "via" for k in visits):
            raise UnsupportedPhrase(
                f"{excerpt(self.text)} names only places to pass ({', '.join(self.mentions[k].ref.label for k in visits)}) "
                "and no destination: say where to go ('to the kitchen')"
            )
        order = visiting_order(
            [Visit(k, m.rank, m.step, m.role, m.tied) for k, m in ((k, self.mentions[k]) for k in visits)],
            [(visits.index(a), visits.index(b)) for a, b in self.pairs if a in visits and b in visits],
        )
        ordered = [self.mentions[visits[i]] for i in order]
        self._check(ordered, avoid, not_goal)
        waits = tuple((i, m.wait) for i, m in enumerate(ordered) if m.wait is not False)
        for i, wait in waits:
            if wait is None and i < len(ordered) - 1:
                raise UnsupportedPhrase(
                    f"'wait' between two places (at {excerpt(ordered[i].ref.label)}, on the way) is a correction or a "
                    "stop with no length; say how long ('wait there for 2 minutes, then ...')"
                )
            if wait is not None and wait > MAX_WAIT_S:
                raise InstructionTooLarge(f"a wait of {wait:.0f} s is longer than the {MAX_WAIT_S:.0f} s accepted")
        speeds = set(self.speeds)
        if len(speeds) > 1:
            raise UnsupportedPhrase(f"{excerpt(self.text)} asks for two speeds ({' and '.join(sorted(speeds))}): say one")
        speed = speeds.pop() if speeds else None
        assert speed is None or speed in SPEEDS
        return Reading(tuple(m.ref for m in ordered), tuple(avoid), tuple(not_goal), speed, waits)

    def _resolve_pending(self) -> None:
        """ "After the kitchen, go to the bath": R before (after) the places said after it in its sentence that no
        order word introduced (those are the chain's own: "after the kitchen after the toilet go to the bath")."""
        for kind, r, sentence, word in self.later:
            later = [
                k
                for k in range(r + 1, len(self.mentions))
                if self.mentions[k].role in VISIT_ROLES and self.mentions[k].sentence == sentence
                and not self.mentions[k].order_kind
            ]
            if not later:
                raise UnsupportedPhrase(
                    f"{excerpt(word)} orders {excerpt(self.mentions[r].ref.label)} against no other place to visit; "
                    "name both places (e.g. 'go to the bedroom after the kitchen')"
                )
            for k in later:
                self.pairs.append((r, k) if kind == "after" else (k, r))

    def _check(self, ordered: list[_Mention], avoid: list[PlaceRef], not_goal: list[PlaceRef]) -> None:
        for m in ordered:
            if m.ref.every:
                raise UnsupportedPhrase(
                    f"{excerpt(m.ref.label)} asks for every place of that name, but a plan goes to one place for "
                    "each waypoint and one goal: name them one by one"
                )
            if m.ref in avoid:
                raise UnsupportedPhrase(f"{excerpt(m.ref.label)} is both a place to visit and a place to avoid")
        if ordered[-1].ref in not_goal:
            raise UnsupportedPhrase(f"{excerpt(ordered[-1].ref.label)} is both the goal and a place not to end in")


def _ends_with_relation(clause: Tree) -> str | None:
    """The words of the relation-carrying place a clause ends with ("bedroom closest to kitchen"), if any."""
    last = clause.children[-1]
    nps = [c for c in last.children if isinstance(c, Tree)]
    if not nps or nps[-1].data != "related":
        return None
    rel = nps[-1].children[1].children[-1]
    if not any(isinstance(c, Tree) for c in rel.children):
        return None
    return " ".join(str(v) for v in nps[-1].scan_values(lambda v: isinstance(v, LarkToken)))
