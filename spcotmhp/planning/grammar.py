"""Grammar words of navigation instructions, one small table per language (``grammars/<lang>.json``).

The place words of an instruction are whatever the learned vocabulary holds (on-site names, any language); this
module only lists the closed-class words that say what role a named place plays and in which order places are
visited:

* ``goal``: where the robot must end ("to", "into", "return to", "on the way to"; へ, に行って, に戻って).
* ``waypoint``: a place to pass on the way ("via", "through", "pass", "stop at", "swing by"; を通って, に寄って).
* ``avoid``: a place the path must not enter ("avoiding", "without passing", "not through", and negations of going
  there: "don't go to", "never pass"; を避けて, を通らずに, に行かないで, は通らないで). A negation followed by
  other markers with only fillers between ("I don't want to go to the kitchen") keeps the avoid role.
* ``not_goal``: a place that must not be the goal but may be passed ("instead of", "rather than"; ではなく,
  の代わりに). "Go to the bedroom instead of the kitchen" corrects the destination; nothing in it forbids
  driving through the kitchen, so the kitchen is not avoided, only never chosen as the goal.
* ``from``: the place the robot starts in ("from"; から). The start is the pose given to the planner, not a place,
  so such a phrase is refused naming the word (a から after a marker, キッチンに行ってから, only sequences).

``order`` words say when a place is visited (:mod:`spcotmhp.planning.sequence` applies them):
``first`` ("first", まず), ``last`` ("finally", 最後に), ``before`` ("before the bedroom, visit the toilet";
寝室に行く前に), ``after`` ("go to the bedroom after the kitchen"; キッチンの後で), ``before_that`` ("but before
that the kitchen"; その前に) and ``on_the_way`` ("on the way", 途中で: the place is a waypoint, not the goal).
``sequencers`` ("then", "after that"; それから) are connectors that also start a new step when a new marker follows.

Three kinds of phrases are recognised only to be refused (the parser raises
:class:`~spcotmhp.errors.UnsupportedPhrase` naming them rather than guessing): ``alternatives`` ("or", "either";
または) leave the choice of a place open, ``relations`` ("next to", "near"; の隣) describe a place by a spatial
relation to another, and ``modifiers`` ("second", "on the left", "big"; 二番目, 左の) pick one of several places
by a property the map does not hold. "the first" / "the last" before a place are modifiers too. ``refused`` lists
further phrases refused where they ask for something (leaving a place, self-corrections, conditions, a way back,
waivers: :mod:`spcotmhp.planning.refusals`), and ``containment`` the words that put a place inside another. Every
word of an instruction must be a place word or a word of these tables: the filler list is explicit, and a word in
none of them is refused, never skipped.

``attach`` says on which side of its place phrase a marker stands: English markers are prepositions (``prefix``:
"via the corridor"), Japanese ones are postpositions (``postfix``: 廊下を通って). ``connectors`` ("and", "then", と)
let the next phrase share a role ("avoiding the living and the kitchen"; トイレとダイニングを経由して).
English is matched on lower-cased word tokens, Japanese on characters (no spaces needed); the longest table
entry wins, and a place word wins over a grammar word of the same length.

The tables are package data, ``spcotmhp/planning/grammars/<lang>.json`` (one file per language: add a language by
adding a file), read once at import with :func:`json.loads` and checked by :func:`grammar_from_json`: every
:class:`Grammar` field by name, ``markers`` and ``order`` as ``{role or kind: [phrases]}``, word sets as lists.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from importlib import resources
from types import MappingProxyType
from typing import Any

from spcotmhp.errors import InstructionError

ROLES = ("goal", "waypoint", "avoid", "not_goal", "from")
ORDERS = ("first", "last", "before", "after", "before_that", "on_the_way")
REFUSALS = (
    "leave",
    "correction",
    "late_correction",
    "mid_correction",
    "cancel",
    "conditional",
    "back",
    "round_trip",
    "waiver",
)


@dataclass(frozen=True, eq=False)
class Grammar:
    """The grammar words of one language (read-only; equal and hashed by identity, so that a compiled lexicon can
    be kept per grammar: :mod:`spcotmhp.planning.scan`).

    Attributes:
        lang: language code ("en", "ja").
        attach: "prefix" (marker before its place phrase) or "postfix" (marker after it). Order words follow
            the same side, except ``backward_order`` ones (Japanese 前に, 後で stand after their place).
        markers: phrase -> role, phrases as written (English: space-separated words).
        connectors: phrases that continue the previous role.
        sequencers: the connectors that put what follows after what precedes ("then"; module docstring).
        order: phrase -> one of :data:`ORDERS`.
        backward_order: order kinds whose phrase stands after the place it orders (Japanese before/after).
        soft_connectors: the connectors that are only punctuation (",", 、) or "but": unknown words after them
            are reported only when they follow a determiner ("go to the kitchen, thanks" is fine, "go to the
            kitchen, the attic" is not).
        determiners: fillers that open a noun phrase ("the", "my"); "the first" / "the last" are modifiers.
        alternatives: phrases offering a choice between places ("or"), refused.
        relations: spatial relations between places ("next to"), refused.
        modifiers: words that pick one of several places by order, side or size ("second", "left"), refused.
        between_places: short words that mean something only when they stand alone between two place
            phrases (Japanese: の joins them into one name, 玄関の廊下; か offers alternatives, キッチンかトイレ):
            word -> "join" or "alternative". Elsewhere they are ordinary characters of other words.
        fillers: words and phrases that carry no meaning for the parse (politeness, verbs of motion, "wait").
            Never reported as "not understood"; never place words unless a place is named so.
        nouns: generic nouns among the fillers ("room", "area"): skipped after a place word ("the living room")
            but, unlike the other fillers, allowed as words of a place's name ("alice's room").
        refused: phrase -> one of :data:`REFUSALS`, what the planner cannot honour (refused naming the phrase,
            :mod:`spcotmhp.planning.refusals` says when and why): leaving a place ("leave", "get out of"),
            a self-correction ("no wait", "I mean", やっぱり; harmless before any place is named unless a place
            follows at once, "no kitchen"; "instead" only after two places, "wait" only between two places),
            a cancellation ("never mind", "forget", やめて), a condition ("if", "unless", なら, たら),
            a way back to the start (``back``: "and come back", harmless right before a goal, "go back into
            the kitchen"; ``round_trip``: always, "round trip", 往復) and a waiver ("no need to", 避けなくていい).
        containment: words that put one place inside another ("the toilet in the corridor", 廊下にあるトイレ),
            refused when they stand between two place phrases; elsewhere fillers (or the marker they also are).
        final_markers: goal markers that also put their place last ("end at", "finish in"), as "finally" does.
        honorifics: prefixes glued to a place word that do not change it (Japanese お, ご: お風呂 is 風呂).
        hiragana_places: a place word written in katakana of three or more characters is also matched as
            written in hiragana (キッチン, きっちん; トイレ, といれ): the two scripts spell the same sounds, and a
            recogniser or a person may write either (unless a place is called by the hiragana spelling).
        by_character: match on characters (Japanese) instead of whitespace/punctuation-separated words.
    """

    lang: str
    attach: str
    markers: dict[str, str]
    connectors: frozenset[str]
    fillers: frozenset[str] = frozenset()
    by_character: bool = False
    soft_connectors: frozenset[str] = frozenset()
    determiners: frozenset[str] = frozenset()
    alternatives: frozenset[str] = frozenset()
    relations: frozenset[str] = frozenset()
    between_places: dict[str, str] = field(default_factory=dict)
    sequencers: frozenset[str] = frozenset()
    order: dict[str, str] = field(default_factory=dict)
    backward_order: frozenset[str] = frozenset()
    modifiers: frozenset[str] = frozenset()
    nouns: frozenset[str] = frozenset()
    refused: dict[str, str] = field(default_factory=dict)
    containment: frozenset[str] = frozenset()
    final_markers: frozenset[str] = frozenset()
    honorifics: frozenset[str] = frozenset()
    hiragana_places: bool = False

    @property
    def function_words(self) -> frozenset[str]:
        """Every grammar and filler word (never a place word), generic nouns excepted, and the refused phrases
        except those of leaving a place (a site may have a place called "exit")."""
        return (
            (self.fillers - self.nouns)
            | self.connectors
            | set(self.markers)
            | set(self.order)
            | self.determiners
            | self.alternatives
            | {p for p, kind in self.refused.items() if kind != "leave"}
        )


def grammar_from_json(text: str, source: str = "grammar") -> Grammar:
    """The :class:`Grammar` of a JSON table (module docstring); a malformed table raises
    :class:`~spcotmhp.errors.InstructionError` naming ``source`` and the field."""
    try:
        table = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InstructionError(f"{source}: not JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(table, dict):
        raise InstructionError(f"{source}: the table must be a JSON object of Grammar fields")
    known = {f.name: f for f in fields(Grammar)}
    unknown = sorted(set(table) - set(known))
    missing = sorted(f.name for f in known.values() if f.name not in table and f.name in _REQUIRED)
    if unknown or missing:
        raise InstructionError(f"{source}: unknown field(s) {unknown}, missing field(s) {missing}")
    values: dict[str, Any] = {}
    for name, value in table.items():
        if name in ("markers", "order", "refused"):
            kinds = {"markers": ROLES, "order": ORDERS, "refused": REFUSALS}[name]
            values[name] = _grouped(value, kinds, f"{source}: {name}")
        elif name == "between_places":
            values[name] = _phrases(value, f"{source}: {name}", mapping=True)
        elif name in ("lang", "attach"):
            values[name] = _text(value, f"{source}: {name}")
        elif name in ("by_character", "hiragana_places"):
            if not isinstance(value, bool):
                raise InstructionError(f"{source}: {name} must be true or false")
            values[name] = value
        else:
            values[name] = frozenset(_phrases(value, f"{source}: {name}"))
    if values["attach"] not in ("prefix", "postfix"):
        raise InstructionError(f"{source}: attach must be 'prefix' or 'postfix', got {values['attach']!r}")
    return Grammar(**values)


_REQUIRED = ("lang", "attach", "markers", "connectors")


def _text(value: object, where: str) -> str:
    if not isinstance(value, str) or not value:
        raise InstructionError(f"{where} must be a non-empty string, got {value!r}")
    return value


def _phrases(value: object, where: str, mapping: bool = False) -> Any:
    """A list of phrases (or, with ``mapping``, an object phrase -> kind), every entry a non-empty string."""
    if mapping:
        if not isinstance(value, dict):
            raise InstructionError(f"{where} must be an object of phrase -> kind")
        return {_text(k, where): _text(v, where) for k, v in value.items()}
    if not isinstance(value, list):
        raise InstructionError(f"{where} must be a list of phrases")
    return [_text(v, where) for v in value]


def _grouped(value: object, kinds: tuple[str, ...], where: str) -> dict[str, str]:
    """``{kind: [phrases]}`` -> phrase -> kind; kinds must be among ``kinds``."""
    if not isinstance(value, dict):
        raise InstructionError(f"{where} must be an object of kind -> [phrases]")
    bad = sorted(set(value) - set(kinds))
    if bad:
        raise InstructionError(f"{where}: unknown kind(s) {bad}; known: {', '.join(kinds)}")
    return {phrase: kind for kind, phrases in value.items() for phrase in _phrases(phrases, f"{where}.{kind}")}


def _load_grammars() -> dict[str, Grammar]:
    folder = resources.files("spcotmhp.planning") / "grammars"
    out = {}
    for item in sorted(folder.iterdir(), key=lambda f: f.name):
        if item.name.endswith(".json"):
            grammar = grammar_from_json(item.read_text(encoding="utf-8"), f"grammars/{item.name}")
            if f"{grammar.lang}.json" != item.name:
                raise InstructionError(
                    f"grammars/{item.name} holds language {grammar.lang!r}; name it {grammar.lang}.json"
                )
            out[grammar.lang] = grammar
    return out


GRAMMARS: Mapping[str, Grammar] = MappingProxyType(_load_grammars())
"""The grammar of each supported language, read once from ``grammars/*.json`` (read-only); add a language by
adding a file."""
ENGLISH = GRAMMARS["en"]
JAPANESE = GRAMMARS["ja"]
