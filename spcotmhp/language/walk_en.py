"""Reading a derivation of the English grammar (``grammars/en.lark``) into mentions (:mod:`spcotmhp.language.walk`).

The rules a reader needs besides the grammar:

* Roles: "to", "into", a bare name: a place to go to; "via", "through", "past": a place to pass; "stop at", "visit":
  a place to stop at; "avoid", "don't go through", "without": a place to avoid. A bare name first in a clause after
  a connector ("and", a comma, "then") shares the role of the place said before it in its sentence ("avoiding the
  living room and the kitchen"); after a negated name and a comma it is the place meant instead ("not the
  kitchen, the dining room"). A negated bare name ("not the bath", "instead of the bath") contrasts with the place
  said before it: not the goal after a place to go to, avoided after a place to pass or stop at.
* Order: "first", "finally", "on the way", "before that" apply to the places of their clause, or of the next
  clause that names one; "X after R" puts R before X, "X before R" puts R after X (X: the place said right before
  the order word in its sentence; at the start of a sentence, the places said after it that no order word
  introduced); "then" followed by a marker starts a new step.
* Waits: "wait (there)" waits at the place the robot is going to at that point; "wait in the hall", "stop at the
  kitchen for a minute" name the place.
* Refused: a place right after "wait" with no "then" (a correction or the next place?); "instead" after two
  places with nothing negated; a place after "stop"; "and" after a relation's place followed by another name
  ("closest to the kitchen and the bath": the relation of both, or another place?).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

from lark import Token as LarkToken
from lark import Tree

from spcotmhp.errors import UnsupportedPhrase
from spcotmhp.language.meaning import PlaceRef, Relation
from spcotmhp.language.walk import VISIT_ROLES, Mention, Walk, subtrees, tok, tokens_of, tree
from spcotmhp.language.wording import excerpt

_ROLES = {"goal": "goal", "goal_last": "goal", "goal_on_the_way": "goal", "hurry_goal": "goal", "via": "via",
          "stop": "stop", "avoid": "avoid"}  # fmt: skip
_MARKER_ROLES = {"TO": "goal", "ENTER": "goal", "VIA": "via", "STOP_AT": "stop"}


_PERMISSION = re.compile(r"\b(?:you can|you may|feel free to|you're allowed to|it's ok to|it's okay to)\b")
_SKIP = re.compile(r"\bskip(?:ping)?\b")


@dataclass
class EnglishWalk(Walk):
    """Reads ``start -> sentence -> (lead | joint | clause)`` trees (module docstring)."""

    pending: list[str] = field(default_factory=list)  # first / last / on_the_way / before_that for the next clause
    later: list[tuple[str, int, int, str]] = field(default_factory=list)  # (kind, mention, sentence, word): no X
    joint: set[str] = field(default_factory=set)  # the connectors before the clause being read
    related_end: str | None = None  # the clause before ended with a relation of another place
    waited: str = ""  # the clause before holds a wait: its word
    halted: str = ""  # "stop" was said: no place may follow it

    def replaces_again(self, x: Mention, y: Mention) -> bool:
        """A place said again after a correction with another role replaces it ("via the kitchen, no, avoid the
        kitchen"; "avoid the bath, actually it's fine, go through it"), but not where the words leave two readings:
        "you can go through it" lifts an avoidance (a permission, not a place to pass) and "skip the corridor" drops
        a place to pass (not one to avoid): those stay refused."""
        text = self.text.lower()
        if x.role == "avoid" and y.role in VISIT_ROLES:
            return _PERMISSION.search(text) is None
        return not (y.role == "avoid" and _SKIP.search(text))

    def read(self, root: Tree):
        for sentence in subtrees(root):
            self.joint, self.related_end, self.waited = set(), None, ""
            if sentence.data == "duration":  # "Kitchen. Wait there. Two minutes.": how long the wait lasts
                self._length(sentence)
                self.sentence += 1
                continue
            for child in subtrees(sentence):
                if child.data == "joint":
                    joint = tokens_of(child)
                    self.joint = {t.type for t in joint}
                    said = [self.word(t) for t in joint if t.type in ("CORRECTION", "NO")]
                    if joint[-1].type == "NO" and not self.mentions:  # "no kitchen, ...": not a correction
                        raise UnsupportedPhrase(f"{excerpt(said[-1])} {self.table.misplaced['NO'].split(' ', 1)[1]}")
                    if said:
                        self.correcting(" ".join(said))
                elif child.data == "clause":
                    self._clause(child)
                    self.joint = set()
            self.sentence += 1
        self.corrected(end=True)
        self._resolve_later()
        return self.result()

    def _length(self, sentence: Tree) -> None:
        waiting = [m for m in self.mentions if m.wait is not False]
        if not waiting or waiting[-1].wait is not None:
            raise UnsupportedPhrase(
                f"{excerpt(self.word(sentence.children[0]))} says how long, but no wait before it is waiting for "
                "a length: say 'wait there for 2 minutes'"
            )
        waiting[-1].wait = self.seconds(sentence.children)

    def _clause(self, clause: Tree) -> None:
        self.clause += 1
        items = subtrees(clause)
        first = items[0]
        if "OR" in self.joint and self.correction is None:
            self._or(first)
        if "THEN" in self.joint and first.data != "bare":
            self.step += 1
        if self.related_end and "AND" in self.joint and "THEN" not in self.joint and first.data == "bare":
            raise UnsupportedPhrase(
                f"'and' after {excerpt(self.related_end)} could add a place to the relation or name another place to "
                "go to: say 'then' before another place, or name one place in the relation"
            )
        contrast = "BUT" in self.joint and not self.joint & {"CORRECTION", "NO", "THEN", "AND"}
        contrast = contrast and len(items) == 1 and first.data == "bare" and bool(self.mentions)
        start = len(self.mentions)
        orders: list[str] = []
        for k, item in enumerate(items):
            self._item(item, orders, first_item=k == 0)
        if contrast and len(self.mentions) > start:
            raise UnsupportedPhrase(  # "go to the kitchen but the bath": a contrast, not a second stop
                f"'but' before {excerpt(self.mentions[start].ref.label)} sets it against what was said before, as "
                "neither a stop on the way nor a correction: say 'then' to go there next, or 'no, ...' to correct"
            )
        self.related_end = _ends_with_relation(items[-1])
        self.waited = next((self.word(tokens_of(i)[0]) for i in items if i.data == "wait"), "")
        mine = [m for m in self.mentions[start:] if m.role in VISIT_ROLES]
        if mine:
            self.apply_orders(self.pending + orders, mine, start)
            self.pending = []
        else:
            self.pending += orders
        self.corrected()

    def _or(self, first: Tree) -> None:
        """ "or" joins places to avoid ("without going through the dining room or the kitchen": neither); anywhere
        else it leaves a choice open, which is refused."""
        before = [m for m in self.mentions if m.sentence == self.sentence]
        if before and before[-1].role == "avoid" and first.data == "bare":
            return
        around = [before[-1].ref.label] if before else []
        if first.data == "bare":
            around.append(self._ref(subtrees(first)[0]).label)
        choice = f" ({' or '.join(around)})" if around else ""
        raise UnsupportedPhrase(
            f"'or' leaves the choice of a place open{choice}; the planner needs one place for each waypoint and one "
            "goal: say which one"
        )

    def _item(self, item: Tree, orders: list[str], first_item: bool) -> None:
        kind, kids, toks = item.data, subtrees(item), tokens_of(item)
        if kind == "bare":
            if self._apposition(kids[0], first_item):
                return
            m = self.mention(self._ref(kids[0]), self._inherited_role(first_item))
            m.inherited = first_item and bool(self.joint)
        elif kind in _ROLES:
            ref = self._ref(kids[0]) if kids else self._there(toks)
            m = self.mention(self.on_floor(ref, toks), _ROLES[kind])  # "go upstairs to the bedroom"
            m.rank = 2 if kind == "goal_last" else m.rank
            self.speeds += ["fast"] if kind == "hurry_goal" else []
            seconds = self.seconds(toks)
            if seconds is not None:
                m.wait = seconds
        elif kind in ("negated", "negated_marker", "instead_of_via"):
            ref = self._ref(kids[0]) if kids else self._there(toks)
            if kind != "negated":  # "don't go through the kitchen", "rather than through it"
                role = "avoid"
            elif any(t.type == "INSTEAD_OF" for t in toks):  # "instead of (going to) the kitchen"
                role = "not_goal"
            else:  # "not the kitchen": contrasts with the place said before it
                role = self._contrast()
            m = self.mention(ref, role)
            m.contrast = kind == "negated"
        elif kind in ("before", "after"):
            self._ordered(kind, kids, toks)
        elif kind in ("first", "last", "on_the_way", "before_that"):
            orders.append(kind)
        elif kind == "instead":
            self._instead(self.word(toks[0]))
        elif kind == "halt":
            self.halted = self.word(toks[0])
        elif kind in ("slow", "fast", "hurry"):
            self.speeds.append("fast" if kind == "hurry" else kind)
        elif kind == "wait":
            self._wait(kids, toks)

    # ---- places ------------------------------------------------------------------------------------------
    def mention(self, ref: PlaceRef, role: str) -> Mention:
        if self.halted:  # "go to the kitchen, stop, go to the bath": a correction or a stop on the way
            raise UnsupportedPhrase(f"{excerpt(self.halted)} {self.table.misplaced['HALT'].split(' ', 1)[1]}")
        return super().mention(ref, role)

    def _apposition(self, np: Tree, first_item: bool) -> bool:
        """ "the bedroom, the one next to the washroom": "the one" with a relation right after a place of that name
        with none says which it is (the same place, not another one)."""
        if np.data != "one" or not first_item or self.joint != {"COMMA"} or not self.mentions:
            return False
        last = self.mentions[-1]
        if last.ref.relation is not None or last.sentence != self.sentence:
            return False
        last.ref = self._ref(np)
        return True

    def _inherited_role(self, first_item: bool) -> str:
        if not (first_item and self.joint):
            return "goal"
        if {"CORRECTION", "NO"} & self.joint:  # "the kitchen, no, the bath": the role of the place corrected
            said = [m for m in self.mentions if not m.dropped]
            return said[-1].role if said else "goal"
        if self.waited and "THEN" not in self.joint:
            raise UnsupportedPhrase(
                f"{excerpt(self.waited)} between two places could correct the place before or be a stop on the way: "
                "say 'then' before the next place, or leave it out"
            )
        before = [m for m in self.mentions if m.sentence == self.sentence]
        if not before:
            return "goal"
        if before[-1].role == "not_goal" and before[-1].contrast and self.joint == {"COMMA"}:
            return "goal"
        return before[-1].role

    def _contrast(self) -> str:
        before = self.mentions[-1].role if self.mentions else "goal"
        return "avoid" if before in ("via", "stop", "avoid") else "not_goal"

    def _there(self, toks: list[LarkToken]) -> PlaceRef:
        return self.last_ref(next((self.word(t) for t in toks if t.type == "THERE"), "there"))

    def _ref(self, np: Tree) -> PlaceRef:
        """The :class:`PlaceRef` of an ``np`` (or ``_target``) subtree."""
        if np.data == "it":
            return self.last_ref(self.word(np.children[0]))
        if np.data == "one":
            last = self.last_ref(self.word(np.children[0]))
            return replace(last, relation=self._relation(tree(np.children[1]), last), every=False)
        ref = self._name(tree(np.children[0]))
        if np.data == "related":
            relation = self._relation(tree(np.children[1]), ref)
            if relation is not None and ref.relation is not None:
                raise UnsupportedPhrase(f"{excerpt(ref.label)} is given two relations; say one")
            return replace(ref, relation=relation or ref.relation)
        return ref

    def _name(self, name: Tree) -> PlaceRef:
        if name.data in ("largest_elided", "smallest_elided"):  # "the smallest bedroom, not the biggest"
            last = self.last_ref(self.word(name.children[0]))
            return replace(last, relation=Relation(name.data.split("_")[0]), every=False)
        place = next(t for t in tokens_of(name) if t.type == "PLACE")
        if name.data == "every":
            ref = self.place(place, every=True)
            ref = PlaceRef(ref.words, f"{self.word(name.children[0])} {ref.label}", every=True)
        else:
            ref = self.place(place, Relation(name.data) if name.data in ("largest", "smallest") else None)
        return self.on_floor(ref, name.children)

    def _relation(self, relation: Tree, head: PlaceRef) -> Relation | None:
        rel = tree(relation.children[-1])
        if rel.data == "nearest":  # "whichever bedroom is closest": the planner's default
            return None
        kind = {"largest_is": "largest", "smallest_is": "smallest"}.get(rel.data, rel.data)
        return Relation(kind, tuple(self._argument(a, head) for a in subtrees(rel)))

    def _argument(self, arg: Tree, head: PlaceRef) -> PlaceRef:
        """A relation's place; "it" / "there" is the last place said by another name than the place the relation
        picks ("the bedroom farthest from the bath, not the one nearest it": the bath), refused when there is none."""
        word = self.word(arg.children[0])
        if arg.data not in ("it", "there"):
            return self.place(tok(arg.children[0]))
        other = next((r for r in reversed(self.said) if r.words != head.words), None)
        if other is None:
            raise UnsupportedPhrase(f"{excerpt(word)} names no place said before it but {excerpt(head.label)}: say "
                                    "the place's name")  # fmt: skip
        return PlaceRef(other.words, other.label)

    def _ordered(self, kind: str, kids: list[Tree], toks: list[LarkToken]) -> None:
        """ "X after R" / "X before R" (module docstring)."""
        word = next(self.word(t) for t in toks if t.type in ("BEFORE", "AFTER"))
        role = next((_MARKER_ROLES[t.type] for t in toks if t.type in _MARKER_ROLES), "visit")
        ref = self._ref(kids[0])
        x = len(self.mentions) - 1 if self.mentions and self.mentions[-1].sentence == self.sentence else None
        if x is not None and self.mentions[x].role not in VISIT_ROLES:
            what = "to avoid" if self.mentions[x].role == "avoid" else "not to end in"
            raise UnsupportedPhrase(
                f"{excerpt(word)} orders {excerpt(self.mentions[x].ref.label)}, a place {what}; such a place is kept "
                "out of the whole plan, so say it without before / after"
            )
        same = [k for k, m in enumerate(self.mentions) if m.ref == ref and m.role in VISIT_ROLES]
        r = same[0] if same else len(self.mentions)
        if not same:
            self.mention(ref, role)
        self.mentions[r].tied, self.mentions[r].order_kind = True, kind
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

    def _resolve_later(self) -> None:
        """ "After the kitchen, go to the bath": R before (after) the places said after it in its sentence that no
        order word introduced (those belong to the chain: "after the kitchen after the toilet go to the bath")."""
        for kind, r, sentence, word in self.later:
            later = [
                k
                for k in range(r + 1, len(self.mentions))
                if self.mentions[k].role in VISIT_ROLES
                and self.mentions[k].sentence == sentence
                and not self.mentions[k].order_kind
            ]
            if not later:
                raise UnsupportedPhrase(
                    f"{excerpt(word)} orders {excerpt(self.mentions[r].ref.label)} against no other place to visit; "
                    "name both places (e.g. 'go to the bedroom after the kitchen')"
                )
            self.pairs += [(r, k) if kind == "after" else (k, r) for k in later]

    def _wait(self, kids: list[Tree], toks: list[LarkToken]) -> None:
        """ "wait (there)": at the place being gone to; "wait in the X": :meth:`waiting_place`."""
        if kids:
            m = self.waiting_place(self._ref(kids[0]))
        elif any(t.type == "THERE" for t in toks) or self.mentions:
            k = self.destination()
            if k is None:
                raise UnsupportedPhrase("'wait' says no place to wait at: say where ('wait in the kitchen')")
            m = self.mentions[k]
        else:
            raise UnsupportedPhrase("'wait' says no place to wait at: say where ('wait in the kitchen')")
        self.wait_at(m, toks)

    def _instead(self, word: str) -> None:
        """ "instead" after two places with no negation before it replaces one of them: which is a guess."""
        visits = [m for m in self.mentions if m.role in VISIT_ROLES]
        if len(visits) >= 2 and not any(m.role in ("avoid", "not_goal") for m in self.mentions):
            raise UnsupportedPhrase(f"{excerpt(word)} {self.table.misplaced['INSTEAD'].split(' ', 1)[1]}")


def _ends_with_relation(item: Tree) -> str | None:
    """The words of the relation-carrying place an item ends with ("bedroom closest to kitchen"), if any."""
    nps = subtrees(item)
    if not nps or nps[-1].data != "related":
        return None
    rel = tree(tree(nps[-1].children[1]).children[-1])
    if not subtrees(rel):
        return None
    return " ".join(str(v) for v in nps[-1].scan_values(lambda v: isinstance(v, LarkToken)))
