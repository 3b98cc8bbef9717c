"""Reading a derivation of the Japanese grammar (``grammars/ja.lark``) into mentions (:mod:`spcotmhp.language.walk`).

The rules a reader needs besides the grammar:

* Roles: a group of places takes the role of the marker after it (へ / に / まで: to go to; を通って,
  経由で: to pass; に寄って: to stop at; を避けて, を通らずに, に行かないで: to avoid; じゃなくて, の代わりに:
  not the goal); a group with no marker is a place to go to; の順に visits a group's places in the order said.
* Order: まず / 最初に, 最後に, 途中で / ついでに, その前に apply to the next phrase that names a place;
  それから / 次に, and markers that go on (に寄ってから, に行ったら) start a new step; "Rの後で X" puts R
  before X and "Rの前に X" (寝室に行く前に) puts R after X, X being the next place said (chains:
  トイレの後でキッチンの後で寝室: toilet, kitchen, bedroom; mixing 前に and 後で is refused).
* Waits: "そこで待って", "待ってて" wait at the place the robot is going to at that point; "洗面所で2分待って" names it.
* Choosing: "Xにして" (make it X) says which place is chosen; said after a place to go to, it replaces it, as a
  correction does (寝間へ行くんだが、風呂場に近いほうの寝間にしてくれ: the bedroom closest to the bath).
* Waiting at a place said right after a correction (玄関、じゃなくて、廊下で待ってて) takes the role of the place
  corrected, as a bare place does: the robot goes to the corridor instead, and waits there.
* Stopping: 止まって with no length at the place the robot ends at says where it stops, which is where it ends
  (そこで止まって, ホールのところで止まっておいて: no wait until the next instruction; 止まってて, 待って and
  待機して ask for one). On the way it stays refused, as any wait with no length is there.
* Refused: places listed with 、 under a marker to pass or stop at when no place is the goal (風呂、キッチン経由:
  which is the goal?).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from lark import Tree

from spcotmhp.errors import UnsupportedPhrase
from spcotmhp.language.meaning import PlaceRef, Reading, Relation
from spcotmhp.language.walk import VISIT_ROLES, Mention, Walk, subtrees, tok, tokens_of, tree
from spcotmhp.language.wording import excerpt

_ROLES = {
    "goal": "goal", "goal_then": "goal", "goal_on_the_way": "goal", "in_order": "goal", "via": "via",
    "via_then": "via", "stop": "stop", "stop_then": "stop", "avoid": "avoid", "not_goal": "not_goal",
}  # fmt: skip
_FORWARD = ("first", "last", "on_the_way", "before_that")
_STOPS = frozenset({"止まって", "とまって"})
"""WAIT words that say stopping, not staying (止まってて, 待って: staying)."""


@dataclass
class JapaneseWalk(Walk):
    """Reads ``start -> sentence -> items`` trees (module docstring)."""

    pending: list[str] = field(default_factory=list)  # forward order words for the next phrase with places
    backward: list[tuple[str, list[int], int, str]] = field(default_factory=list)  # (kind, R, sentence, word)
    lists: list[tuple[list[Mention], str, str]] = field(default_factory=list)  # 、 lists: (mentions, 、, marker)

    def read(self, root: Tree) -> Reading:
        for sentence in subtrees(root):
            for item in subtrees(sentence):
                self._item(item)
            self.sentence += 1
        self.corrected(end=True)
        self._resolve_backward()
        self._refuse_lists()
        reading = self.result()
        goal = len(reading.visit) - 1
        if reading.waits and reading.waits[-1] == (goal, None) and self._stopped(reading.visit[goal]):
            return replace(reading, waits=reading.waits[:-1])
        return reading

    def _stopped(self, goal: PlaceRef) -> bool:
        """Whether the wait at the goal was said as a stop with no length (module docstring)."""
        at = [m for m in self.mentions if m.ref == goal and not m.dropped and m.wait is None]
        return bool(at) and all(m.wait_word in _STOPS for m in at)

    def _item(self, item: Tree) -> None:
        kind, kids, toks = item.data, subtrees(item), tokens_of(item)
        if kind == "correction":
            self.correcting(self.word(toks[0]))
            return
        if kind in _FORWARD:
            self.pending.append(kind)
        elif kind == "then":
            self.step += 1
        elif kind in ("slow", "fast"):
            self.speeds.append(kind)
            self.corrected()
        elif kind == "wait":
            k = self.destination()
            if k is None:
                said = excerpt(self.word(toks[-1]))
                raise UnsupportedPhrase(f"{said} says no place to wait at: say where (寝室で待って)")
            self.wait_at(self.mentions[k], toks)
        elif kind == "bare":
            self._group(tree(kids[0]), "goal", bare=True)
        elif kind in _ROLES:
            marker = self.word(toks[-1]) if toks else ""
            if kind == "goal" and marker.startswith("にし") and any(m.role == "goal" for m in self.mentions):
                self.correcting(marker)  # 寝間へ行くんだが、風呂場に近いほうの寝間にして: the choice made again
            mentions = self._group(tree(kids[0]), _ROLES[kind])
            if any(t.type == "COMMA" for t in tokens_of(tree(kids[0]))) and _ROLES[kind] in ("via", "stop"):
                self.lists.append((mentions, "、", marker))
            if kind.endswith("_then"):
                self.step += 1
        elif kind in ("before", "after"):
            word = self.word(toks[-1])
            role = "goal" if word[:1] in "にへ" else "via" if word.startswith("を通") else "visit"
            mentions = self._group(tree(kids[0]), role)
            for m in mentions:
                m.tied, m.order_kind = True, kind
            self.backward.append((kind, [self.mentions.index(m) for m in mentions], self.sentence, word))
        elif kind == "wait_at":
            refs = self._refs(tree(kids[0]))
            alone = len(refs) == 1 and not self.pending  # an order word makes it a place of its own
            if alone and self.correction is not None:  # 玄関、じゃなくて、廊下で待って: the place corrected, waited at
                waiting = self._group(tree(kids[0]), "goal", bare=True)
            else:
                waiting = [self.waiting_place(refs[0])] if alone else self._group(tree(kids[0]), "stop")
            for m in waiting:
                self.wait_at(m, toks)

    def _group(self, group: Tree, role: str, bare: bool = False) -> list[Mention]:
        """The mentions of a group's places, with the forward order words said before it; a bare group right after a
        correction word takes the role of the place said before it (リビングを通って、いや、廊下), unless places were
        said again after the word first (廊下通ってトイレ、いや、廊下通って風呂: the bare place ends the
        restatement)."""
        if bare and self.correction is not None and self.correction[1] == len(self.mentions):
            said = [m for m in self.mentions if not m.dropped]
            role = said[-1].role if said else role
        out = [self.mention(ref, role) for ref in self._refs(group)]
        start = self.mentions.index(out[0]) if out else len(self.mentions)
        self.apply_orders(self.pending, out, start)
        self.pending = []
        self.corrected()
        return out

    def _refs(self, group: Tree) -> list[PlaceRef]:
        nps = [self._np(n) for n in subtrees(group)]
        if group.data != "between":
            return nps
        if len(nps) != 2 or any(n.relation is not None for n in nps):
            raise UnsupportedPhrase("の間の needs exactly two places before it (キッチンと風呂の間の寝室)")
        return [self.place(tokens_of(group)[-1], Relation("between", (nps[0], nps[1])))]

    def _np(self, np: Tree) -> PlaceRef:
        return self.on_floor(self._said(np), np.children)  # 2階の寝室

    def _said(self, np: Tree) -> PlaceRef:
        place = [t for t in tokens_of(np) if t.type == "PLACE"][-1]
        if np.data == "every":
            ref = self.place(place)
            return PlaceRef(ref.words, self.word(np.children[0]) + ref.label, every=True)
        if np.data in ("largest", "smallest"):
            return self.place(place, Relation(np.data))
        if np.data in ("closest", "farthest", "next_to"):
            arg = self.place(tok(tree(np.children[0]).children[0]))
            return self.place(place, Relation(np.data, (arg,)))
        return self.place(place)

    def _resolve_backward(self) -> None:
        """ "Rの後で X" / "Rの前に X": X is the next place said after R in its sentence (module docstring)."""
        for kind, rs, sentence, word in self.backward:
            after_r = [k for k in range(max(rs) + 1, len(self.mentions)) if self.mentions[k].sentence == sentence]
            if not after_r:
                label = self.mentions[rs[0]].ref.label
                raise UnsupportedPhrase(
                    f"{excerpt(word)} orders {excerpt(label)} against no other place to visit; name both places "
                    "(キッチンの後で寝室へ)"
                )
            x = after_r[0]
            mx = self.mentions[x]
            if mx.role not in VISIT_ROLES:
                raise UnsupportedPhrase(
                    f"{excerpt(word)} orders a place against {excerpt(mx.ref.label)}, a place to avoid"
                )
            if mx.order_kind and mx.order_kind != kind:
                raise UnsupportedPhrase(
                    f"{excerpt(word)} orders a place against {excerpt(mx.ref.label)}, itself ordered the other way: a "
                    "chain mixing before and after leaves the order open; say the order with まず and それから"
                )
            self.pairs += [(r, x) if kind == "after" else (x, r) for r in rs]

    def _refuse_lists(self) -> None:
        """Places listed with 、 under a marker to pass or stop at, when no place is the goal."""
        if any(m.role == "goal" for m in self.mentions):
            return
        for mentions, comma, marker in self.lists:
            if len(mentions) >= 2:
                a, b = mentions[0].ref.label, mentions[1].ref.label
                raise UnsupportedPhrase(
                    f"'{comma}' lists {excerpt(a)} with {excerpt(b)} under {excerpt(marker)}, and no place is the "
                    f"goal: say where to end with its own word (e.g. {a}へ、{b}{marker})"
                )
