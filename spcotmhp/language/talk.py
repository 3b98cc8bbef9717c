"""Talk around an instruction, passed over by a stated rule: what people say with a request that carries no
navigation meaning ("we're about to eat", "the baby's asleep", "I'm hungry", "mom says"; 宅配来るから, ありがとう).

Only a sentence the grammar has no derivation for is looked at (a sentence it reads is read as it is), and the
talk is cut out only where every word of it is shown to carry no navigation meaning; what is left is read by the
grammar, or refused naming its own words. The classes (``talk`` in ``grammars/<lang>.json``, with their sources):

English, a *run* of tokens none of which is a place, a length of time, a floor, or a word class other than the
table's ``neutral`` ones (those carry meaning only with a place, and talk holds none), each of its other words an
English word of lemminflect's dictionary (the dictionary its noun lemmas already come from) that is no number and
none of the table's ``meaning`` words (time, manner, quantity, order, side, position and motion words no class
holds), is talk when it is a statement: it opens with a subject (a word of ``subjects``, or a noun) and holds a
verb (lemminflect's VERB or AUX, a contraction of one, or the IS class). A "to" in it must be followed by a verb
("about to eat": a purpose, not a place), and a motion verb by no "to" or "in" ("we're going to the garage" says
where someone goes: it stays in the instruction). Connectors and motion words at its edges belong to the instruction
next to it ("I'm cooking, come to the kitchen": "come to" is the instruction's); a run whose verb takes the place
after it ("I know you just got to the kitchen") is no talk. A time of day (``times_in_statements``: "tonight",
"earlier") may stand in a statement that is a sentence of its own, closed by a full stop ("It's freezing
tonight. Go to the bath."): its time is the statement's; said with the instruction ("go to the bath tonight") it
stays, to be refused.

Japanese: :mod:`spcotmhp.language.talk_ja`.
"""

from __future__ import annotations

from collections.abc import Sequence

from spcotmhp.language import english_words as ew
from spcotmhp.language.addressed import before_the_address
from spcotmhp.language.english_words import infinitive, known, pos
from spcotmhp.language.placewords import Token
from spcotmhp.language.rewrite_en import NUMBERS
from spcotmhp.language.table import WordTable
from spcotmhp.language.talk_ja import pass_over_ja, without

_EDGE = ("GO", "TO", "AT", "AND", "LINK", "OF", "THAT", "IS", "ONE_OF", "ALL", "IT")
"""Neutral classes a run may not start or end with where an instruction is next to it: they belong to it."""
_DETERMINERS = frozenset(
    ["the", "a", "an", "my", "our", "your", "his", "her", "their", "this", "that", "these", "those", "some"]
)
_POSSESSIVES = frozenset({"my", "our", "his", "her", "their"})
"""Possessives a statement may hold before a thing ("he wants to show his mates"); before a place they pick it."""
_NUMBER_WORDS = (frozenset(NUMBERS) - {"a", "an"}) | frozenset(
    "zero thirteen fourteen sixteen seventeen eighteen nineteen seventy eighty hundred thousand half quarter dozen "  # noqa: SIM905
    "couple".split()
)
"""Words that say a number or a quantity: they keep a run in the instruction ("at six")."""


def pass_over(
    toks: Sequence[Token], table: WordTable, units: Sequence[str] = (), people: frozenset[str] = frozenset()
) -> tuple[list[Token], list[str]] | None:
    """``toks`` without the talk in them, and the talk as said (for the explanation); None when there is none or
    nothing would be left to read (module docstring). ``units``: the sentence's units, fillers included (a
    token's ``start`` indexes them), which show a determiner before a noun ("the baby"); ``people``: the names of
    the map's owners ("bob" of "bob's room"), subjects as the table's are ("bob says go to his room"). Talk said
    to someone else before the robot's name goes first (:mod:`spcotmhp.language.addressed`)."""
    addressed = before_the_address(toks, table, units)
    if addressed is None:
        return _pass_over(toks, table, units, people)
    kept, said = addressed
    more = _pass_over(kept, table, units, people)
    return (more[0], [*said, *more[1]]) if more is not None else (kept, said)


def _pass_over(
    toks: Sequence[Token], table: WordTable, units: Sequence[str], people: frozenset[str]
) -> tuple[list[Token], list[str]] | None:
    if table.by_character:
        return pass_over_ja(toks, table, "".join(units))
    if not table.talk:
        return None
    neutral = frozenset(table.talk.get("neutral", ()))
    meaning = frozenset(table.talk.get("meaning", ()))
    subjects = frozenset(table.talk.get("subjects", ())) | frozenset(table.talk.get("kin", ())) | people
    ok = [admissible(t, neutral, meaning, subjects) for t in toks]
    for k in range(len(toks)):  # "his mates"; "his room": a possessive before a place (or a word of one) picks it
        if toks[k].kind == "MODIFIER":
            ok[k] = ok[k] and k + 1 < len(toks) and toks[k + 1].kind == "WORD" and ok[k + 1]
        elif k and toks[k - 1].kind in ("AT", "IS") and _located(toks[k]):
            ok[k] = True  # "someone's at the door", "the taxi's here": where someone is (_statement, _elsewhere)
        elif k and toks[k - 1].surface in _TITLES and toks[k].kind == "WORD" and toks[k].surface.isalpha():
            ok[k] = True  # "Mr Ortiz is using his walker": a title's name (no dictionary word)
    times = frozenset(table.talk.get("times_in_statements", ()))
    for a, b in [*_sentences(toks), *_closing_its(toks)]:  # "It's freezing tonight.", "..., it's late"
        loose = [ok[k] or toks[k].kind == "WORD" and ew.base(toks[k].surface) in times for k in range(a, b)]
        if not all(ok[a:b]) and all(loose) and _statement(toks[a:b], subjects, False):
            ok[a:b] = [True] * (b - a)
    cut: set[int] = set()
    said: list[str] = []
    i = 0
    while i < len(toks):
        if not ok[i]:
            i += 1
            continue
        j = i
        while j < len(toks) and ok[j]:
            j += 1
        a, b = _trimmed(toks, i, j)
        if b < j and toks[b].kind in ("TO", "AT"):
            i = j  # "I know you just got | to the kitchen": the place is the talk's, not the instruction's: kept
            continue
        if a < b < len(toks) and toks[b].kind == "PLACE" and _takes_the_place(toks[a:b], toks[b], subjects):
            i = j  # "Bobby's room", "the cleaner needs the dining room": the place is the run's: kept, to be refused
            continue
        if any(t.kind == "AT" for t in toks[a:b]) and _referred_back(toks[b:]):
            i = j
            continue
        if a < b and _statement(
            toks[a:b], subjects, 0 < toks[a].start <= len(units) and units[toks[a].start - 1] in _DETERMINERS
        ):
            cut.update(range(a, b))
            said.append(" ".join(t.surface for t in toks[a:b]))
        i = j
    return without(toks, cut, said)


def _takes_the_place(run: Sequence[Token], place: Token, subjects: frozenset[str]) -> bool:
    """Whether the run before a place makes the place its own, so that the run is no talk around it: a possessive
    ("Bobby's room": whose place), or a statement of someone other than the robot ending in a verb that takes the
    place, named as such, as its object ("the cleaner needs the dining room"), or of the robot doing something
    where it stands ("you're blocking the hall": never a place to go; "after you've checked the toilet" visits it)."""
    last = run[-1]
    if last.kind != "WORD":
        return False
    if last.surface.endswith(("'s", "s'")):
        return True
    named = all(w in place.surface for w in place.words)  # not a room told by its contents ("the laundry")
    someone = run[0].kind == "WORD" and not run[0].surface.startswith(("you", "u"))
    doing = last.surface.endswith("ing")  # "you're blocking the hall": where the robot stands, never where to go
    verb = "VERB" in pos(last.surface) and "AUX" not in pos(last.surface)
    return named and (someone or doing) and verb and len(run) > 1 and _statement(run, subjects, True)


_TITLES = frozenset({"mr", "mrs", "ms", "miss", "dr", "mx"})
_POSITIONS = frozenset({"door", "doorway", "corner", "end", "middle", "front", "back", "side", "window", "outside"})
"""Nouns of a position (the talk table's meaning words) that say where someone is after "at" or "in"."""


def _located(tok: Token) -> bool:
    """A word saying where someone is after "at" / "is": "here", or a position noun ("at the door")."""
    return tok.kind == "HERE" or tok.kind == "WORD" and tok.surface in _POSITIONS


def _place_of(tok: Token, before: Token) -> bool:
    """Whether ``tok`` after ``before`` ("at", "in"; "is") names a location: a word after "at", or "here"."""
    return tok.kind == "HERE" or before.kind == "AT" and tok.kind == "WORD"


def _referred_back(rest: Sequence[Token]) -> bool:
    """Whether a "there" or "here" after a statement's location may refer back to it: no place said before it
    ("dad's in the garage, go there": the garage)."""
    for t in rest:
        if t.kind == "PLACE":
            return False
        if t.kind in ("THERE", "HERE"):
            return True
    return False


def _elsewhere(run: Sequence[Token], at: int) -> bool:
    """Whether the location after ``run[at]`` is where the statement's subject is, not the robot: the subject is
    someone else and the robot is not in the clause ("grandad's asleep on the couch", "mum is at work"; not "I need
    you in the garage", "I want it in the garage"). A motion before it makes it a destination (``_statement``)."""
    robot = {"you", "u", "yourself", "ya", "robot"}
    if any(t.surface in robot or t.surface.startswith(("you'", "u'")) for t in run):
        return False
    return not any(t.kind == "IT" or t.surface in ("it", "this") for t in run[1:at])


def _sentences(toks: Sequence[Token]) -> list[tuple[int, int]]:
    """The spans of the sentences of ``toks`` (between full stops), all but the last closed by one."""
    spans, a = [], 0
    for k, t in enumerate(toks):
        if t.kind == "_STOP":
            spans.append((a, k))
            a = k + 1
    return spans


def _closing_its(toks: Sequence[Token]) -> list[tuple[int, int]]:
    """The span of a clause after a comma that closes its sentence and opens with "it's" ("go to the bedroom, it's
    late", "..., it's dinner time"): a statement about the time, as one of its own sentence is (:func:`_sentences`),
    never a time of the instruction (that has no subject: "go to the bedroom at six"; or says what the instruction is
    for: "it's for tonight", refused). Its words after "it's" are words of no class."""
    spans = []
    for k, t in enumerate(toks[:-1]):
        if t.kind == "COMMA" and toks[k + 1].surface in ("it's", "its"):
            end = next((j for j in range(k + 1, len(toks)) if toks[j].kind in ("COMMA", "_STOP")), len(toks))
            words = all(x.kind == "WORD" for x in toks[k + 2 : end])  # "it's for tonight": the instruction's time
            if words and (end == len(toks) or toks[end].kind == "_STOP"):
                spans.append((k + 1, end))
    return spans


def admissible(tok: Token, neutral: frozenset[str], meaning: frozenset[str], subjects: frozenset[str]) -> bool:
    """Whether a token may be part of talk: a neutral class, or a word that is a subject or a known word that is no
    number and carries none of the ``meaning`` (checked on the word and on it without its contraction)."""
    if tok.kind != "WORD":
        return tok.kind in neutral or tok.kind == "MODIFIER" and tok.surface in _POSSESSIVES
    word = tok.surface
    base = ew.base(word)
    if word in subjects or base in subjects:  # "grandad's asleep": a subject with a contraction
        return True
    if {word, base} & meaning or any(w[:1].isdigit() or w in _NUMBER_WORDS for w in (word, base)):
        return False
    return known(base)


def _trimmed(toks: Sequence[Token], i: int, j: int) -> tuple[int, int]:
    """The run toks[i:j] without the neutral words at its edges that belong to the instruction next to it: at its
    end when an instruction word follows it (not the end of a sentence or a comma), at its start "and" / "that"."""
    end_of_clause = j == len(toks) or toks[j].kind in ("_STOP", "COMMA")
    while not end_of_clause and j > i and toks[j - 1].kind in _EDGE:
        j -= 1
    while i < j and toks[i].kind in ("AND", "THAT", "LINK"):
        i += 1
    return i, j


def _statement(run: Sequence[Token], subjects: frozenset[str], after_determiner: bool) -> bool:
    """Whether a run opens with a subject and holds a verb, with every "to" followed by a verb. A subject: a word
    of ``subjects``, a word with a contraction ("baby's"), a noun after a determiner ("the baby"), or a noun that
    is not also a verb's base form ("mom", "kids"; "say" may open an order: "say dinner is ready")."""
    if len(run) > 1 and run[0].kind == "MODIFIER" and run[0].surface in _POSSESSIVES:
        run, after_determiner = run[1:], True  # "my mum is at work"
    first = run[0]
    if first.kind != "WORD":
        return False
    word, base = first.surface, ew.base(first.surface)
    noun = "NOUN" in pos(base)
    opens = word in subjects or word != base or (noun and (after_determiner or not infinitive(word)))
    if not opens:
        return False
    verb = False
    for k, t in enumerate(run):
        if t.kind in ("IS", "GO"):
            if t.kind == "GO" and k + 1 < len(run) and run[k + 1].kind in ("TO", "AT"):
                return False  # "we're going to the garage": a motion somewhere stays in the instruction
            verb = True
        elif t.kind == "TO":
            nxt = run[k + 1] if k + 1 < len(run) else None
            if nxt is None or nxt.kind != "WORD" or not infinitive(nxt.surface):
                return False
        elif t.kind in ("AT", "IS") and k + 1 < len(run) and _place_of(run[k + 1], t) and not _elsewhere(run, k):
            return False  # "I need you in the garage": a location stays in the instruction
        elif t.kind == "WORD" and k == 0 and t.surface in ("you", "me", "us"):
            return False  # "you go to the garage": an order, not a statement
        elif t.kind == "WORD" and (t.surface != ew.base(t.surface) or {"VERB", "AUX"} & set(pos(t.surface))):
            verb = verb or k > 0 or t.surface != ew.base(t.surface)
    return verb
