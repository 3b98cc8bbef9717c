"""The recognition grammar (JSGF) of spoken navigation instructions.

Sentences are clauses such as "go to the bedroom", "via the corridor", "avoiding the living", joined by
connectors ("and then"), with an optional polite opening ("please", "could you"):

    <instruction> = [<polite>] <clause> <more>* [please];
    <clause>      = <verb> <goal> <place> | <marker> <place>;    "go to the kitchen", "through the corridor"
    <more>        = <connector> [<goal>] <place> | [<connector>] <clause>;
    <place>       = [<det>] <word> [<word>] [<kind>];          "the kitchen", "the entrance corridor"

A goal marker ("to") opens a clause only after a verb or a connector: a bare "to" mid-sentence is rarely said and,
allowed everywhere, it is what the decoder inserts into a badly heard place name. The markers and connectors are
a compact subset of the word classes of the instruction grammar (``spcotmhp/language/grammars/en.json``; each is
checked against them), so whatever the recogniser can hear the parser reads; the verbs, the article and the
place kind are words the parser reads as motion, a filler and a generic noun. ``<word>`` is any place word of the
learned vocabulary. Grammar phrases with a word that the pronunciation dictionary lacks are left out (and listed in
``InstructionGrammar.dropped``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from spcotmhp.language.lexicon import tokens, word_table
from spcotmhp.speech.lexicon import SPEAKABLE

# a compact subset of the parser's English markers and connectors: every alternative widens the search, and
# a grammar with all of them (about 70 phrases) recognises less accurately and several times more slowly
GOAL_MARKERS = ("to", "into", "towards")
MARKERS = (
    "via",
    "through",
    "passing",
    "passing by",
    "passing through",
    "by way of",
    "avoiding",
    "without passing",
    "without passing by",
    "without passing through",
    "without going through",
    "from",
)
CONNECTORS = ("and", "then", "and then", "after that")
VERBS = ("go", "take me", "bring me", "head", "move", "navigate", "guide me")
DETERMINERS = ("the",)
PLACE_KINDS = ("room",)
POLITE = ("please", "could you", "can you")


@dataclass(frozen=True)
class InstructionGrammar:
    """A JSGF grammar and the words it uses.

    Attributes:
        jsgf: the grammar text (top rule ``<instruction>``).
        place_words: the place words it accepts.
        grammar_words: every other word it uses.
        dropped: grammar phrases left out because a word has no pronunciation.
    """

    jsgf: str
    place_words: tuple[str, ...]
    grammar_words: tuple[str, ...]
    dropped: tuple[str, ...]


def instruction_grammar(place_words: Iterable[str], pronounceable: Callable[[str], bool]) -> InstructionGrammar:
    """Build the grammar for ``place_words`` (each must match ``SPEAKABLE`` and be pronounceable).

    ``pronounceable(word)`` says whether the recogniser has a pronunciation for a grammar word.
    """
    places = tuple(sorted(set(place_words)))
    if not places:
        raise ValueError("the grammar needs at least one place word")
    bad = [w for w in places if not SPEAKABLE.fullmatch(w)]
    if bad:
        raise ValueError(f"place words must be lower-case a-z words: {bad}")
    dropped: list[str] = []

    def usable(phrases: Iterable[str]) -> list[str]:
        keep = []
        for phrase in phrases:
            words = phrase.split()
            if all(SPEAKABLE.fullmatch(w) and pronounceable(w) for w in words):
                keep.append(phrase)
            elif all(SPEAKABLE.fullmatch(w) for w in words):
                dropped.append(phrase)
        return sorted(set(keep))

    goals = usable(m for m in GOAL_MARKERS if _classes(m) == ["TO"])
    markers = usable(m for m in MARKERS if _classes(m) and "WORD" not in _classes(m) and "TO" not in _classes(m))
    connectors = usable(c for c in CONNECTORS if _classes(c) and set(_classes(c)) <= {"AND", "THEN"})
    verbs, dets, kinds, polite = (usable(x) for x in (VERBS, DETERMINERS, PLACE_KINDS, POLITE))
    rules = {
        "goal": goals,
        "marker": markers,
        "connector": connectors,
        "verb": verbs,
        "det": dets,
        "kind": kinds,
        "polite": polite,
        "word": list(places),
    }
    lines = [
        "#JSGF V1.0;",
        "grammar instruction;",
        "public <instruction> = [<polite>] <clause> <more>* [please];",
        "<clause> = <verb> <goal> <place> | <marker> <place>;",
        "<more> = <connector> [<goal>] <place> | [<connector>] <clause>;",
        "<place> = [<det>] <word> [<word>] [<kind>];",
    ]
    lines += [f"<{name}> = {' | '.join(alts)};" for name, alts in rules.items()]
    words = {w for name, alts in rules.items() if name != "word" for a in alts for w in a.split()}
    return InstructionGrammar(
        jsgf="\n".join(lines) + "\n",
        place_words=places,
        grammar_words=tuple(sorted(words - set(places))),
        dropped=tuple(sorted(dropped)),
    )


def _classes(phrase: str) -> list[str]:
    """The word classes of the instruction grammar a phrase is read as ("via" -> ["VIA"]; an unknown word: "WORD")."""
    return [t.kind for t in tokens(phrase, word_table("en"), ())]
