"""Names as people say them: the word order and the numbers of taught names, kept beside the paper's bag of words.

The model's word term stays the paper's bag of words (Eq. 17: Mult(S | W_C), no order). What a place is *called*
(explanations, ``show``, the web page, the Nav2 route graph; and what an instruction matches) is its label, the
place words the place says most (:func:`spcotmhp.planning.vocabulary.place_labels`), written in the order people
said them. The rules:

1. **The name an event teaches.** English: the name :func:`~spcotmhp.language.naming.read_naming` reads from the
   utterance (frame words such as "this is the" left out; numbers kept: "aisle one", "room 101", "second
   bedroom"); an utterance that names nothing teaches no name. Japanese: the utterance's words that are not
   grammar words, in their order (a dataset row is given phrase-segmented: "東 の 廊下" is 東, 廊下); a name read at
   run time is its words (a number glued to the word after it: 2号室).
2. **One order per name** (per word set, not per place: the places "bedroom" share one, and a place learned from
   two names shows the one its label's words make). For each set of words, the sequence taught most often, ties
   by the first taught; kept in the model (``model.info["said_names"]``: ``[{"words": [...], "taught": n}]``, the
   :data:`MAX_SAID_NAMES` most taught), written by ``learn`` and updated by every teach.
3. **A label in taught order.** A place's label is the name taught most often at it (by the events the learner
   assigned there) where that name holds every word the bag rule chose and every word of it is a place word: "the
   east corridor" taught where the concept of "corridor" explains the words, or "the second bedroom" where the
   learner shares one concept among the bedrooms, is that place's name, not "corridor" or "bedroom". Otherwise the
   label's words are in the order of the name with exactly those words; else of the most taught name holding them
   all; else of the taught names that together hold them (a place the learner made of two rooms: "room 101
   loading dock"); else today's rule (a word shared by more places later). A model folder without ``said_names``
   (written before) keeps today's rule.
4. **Numbers are part of a taught name.** A number word, digits or an ordinal ("one", "101", "first") is a grammar
   word of instructions ("the one nearest", "first go to"), so alone it is no place word; it is one where a taught
   name holds it (:func:`~spcotmhp.planning.vocabulary.place_vocabulary`), and it is matched only inside that name
   (:func:`~spcotmhp.language.numbers.said_variants`), so that "bedroom 2" of untaught-numbered bedrooms keeps
   naming the screen's "bedroom #2".
5. **Said back in its common variants.** A cardinal of a taught name may be said as a word, in digits, with
   "number" or "#" before it ("aisle one", "aisle 1", "aisle #1", "aisle number one" for a taught "aisle one");
   an ordinal as a word or in digits with its suffix ("second bedroom", "2nd bedroom"). A cardinal is never said
   as an ordinal nor the other way round: "the first aisle" names a taught "first aisle", while beside a taught
   "aisle one" it keeps its meaning of the instruction grammar.
6. **Written as taught.** A Japanese name is written as it was said: the event's tokens from the name's first word
   to its last, particles kept, without spaces ("東 の 廊下" -> 東の廊下, "2 号室" -> 2号室; a name read at run time,
   :func:`~spcotmhp.language.naming.read_naming`'s ``name``); per word order, the text said most often (kept as
   the name's ``text``). The label a place's plans and explanations, ``show``, the web page and the Nav2 graph
   show is that text where the label's words are exactly that name's words in its order (:func:`shown_names`);
   instructions are still matched by the words ("東の廊下に行って" says 東 and 廊下). An English name is its words
   joined by spaces.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from spcotmhp.language.numbers import number_word

MAX_TEXT = 200
"""Longest kept text of a name (rule 6), in characters: a name longer than this is no name people say; an entry of
a model folder longer than this is read as written without it."""

MAX_SAID_NAMES = 1000
"""Most names kept with a model (the most taught): a home or a warehouse has far fewer; an unbounded list of
every utterance's name would grow the model folder with the teaching."""


@dataclass(frozen=True)
class SaidName:
    """A taught name: its words in the order said (the most taught order of this word set), how many events
    taught this word set, at which places ((place, events), most first) as the learner assigned them, and the
    name as written when it differs from its words joined by spaces (rule 6: a Japanese name's particles)."""

    words: tuple[str, ...]
    taught: int
    places: tuple[tuple[int, int], ...] = ()
    text: str = ""

    @property
    def said(self) -> str:
        """The name written as taught (rule 6): its ``text`` where one was kept ("東の廊下", "2号室"), else its
        words joined by spaces ("aisle one")."""
        return self.text or " ".join(self.words)

    @functools.cached_property
    def word_set(self) -> frozenset[str]:
        """The name's words as a set (rule 2's key), made once."""
        return frozenset(self.words)


def event_name(tokens: Sequence[str], lang: str) -> tuple[str, ...] | None:
    """The name one teaching event teaches, as words (rule 1), or None."""
    return _event_name(tuple(tokens), lang)


@functools.lru_cache(maxsize=4096)
def _event_name(tokens: tuple[str, ...], lang: str) -> tuple[str, ...] | None:
    """:func:`event_name`, read once per distinct utterance (a dataset repeats a few templates; a multi-run
    ``learn`` reads the same events in every run): a bounded cache of a pure function."""
    from spcotmhp.errors import NotANaming
    from spcotmhp.language.naming import read_naming

    if not tokens:
        return None
    if lang == "ja":
        grammar = _grammar_words()
        kept = tuple(dict.fromkeys(w for w in tokens if w not in grammar and not _ja_grammar(w)))
        return kept or None
    try:
        return read_naming(" ".join(tokens), "en").words or None
    except NotANaming:
        return None


def event_text(tokens: Sequence[str], lang: str) -> str | None:
    """How one teaching event writes its name (rule 6): Japanese, the tokens from the name's first word to its last,
    particles kept, without spaces ("ここ は 東 の 廊下 です" -> 東の廊下); None where the name is its words joined by
    spaces (English) or the event names nothing."""
    name = event_name(tokens, lang)
    if lang != "ja" or not name:
        return None
    at = [i for i, w in enumerate(tokens) if w in name]
    text = "".join(tokens[at[0] : at[-1] + 1])
    return None if text == " ".join(name) else text


def _grammar_words() -> frozenset[str]:
    """The grammar and filler words of every language's instruction table (never a name's words)."""
    from spcotmhp.language.reading import LANGUAGES
    from spcotmhp.language.table import word_table

    return frozenset().union(*(word_table(lang).function_words for lang in LANGUAGES))


def _ja_grammar(word: str) -> bool:
    from spcotmhp.language.text import japanese_function_word

    return japanese_function_word(word)


def count_names(
    names: Iterable[tuple[str, ...] | None],
    earlier: Sequence[SaidName] = (),
    places: Iterable[int | None] | None = None,
    texts: Iterable[str | None] | None = None,
) -> list[SaidName]:
    """Rule 2: per word set, the sequence said most often (ties: the first said; ``earlier`` names count first,
    each as its ``taught`` events), with the events per place when ``places`` gives each event's place and (rule
    6) the text that order was written with most often when ``texts`` gives each event's (:func:`event_text`), the
    :data:`MAX_SAID_NAMES` most taught, most taught first."""
    per_set: dict[frozenset[str], dict[tuple[str, ...], int]] = {}
    at: dict[frozenset[str], dict[int, int]] = {}
    written: dict[tuple[str, ...], dict[str, int]] = {}
    for said in earlier:
        per_set.setdefault(frozenset(said.words), {})[said.words] = said.taught
        at.setdefault(frozenset(said.words), {}).update(dict(said.places))
        if said.text:
            written.setdefault(said.words, {})[said.text] = said.taught
    for name, place, text in zip(names, _each(places), _each(texts), strict=False):
        if name:
            key = frozenset(name)
            orders = per_set.setdefault(key, {})
            orders[name] = orders.get(name, 0) + 1
            if place is not None and place >= 0:
                counts = at.setdefault(key, {})
                counts[int(place)] = counts.get(int(place), 0) + 1
            if text and len(text) <= MAX_TEXT:
                forms = written.setdefault(name, {})
                forms[text] = forms.get(text, 0) + 1
    out = []
    for key, orders in per_set.items():
        where = sorted(at.get(key, {}).items(), key=lambda kv: (-kv[1], kv[0]))
        words = max(orders, key=orders.__getitem__)
        forms = written.get(words, {})
        text = max(forms, key=forms.__getitem__) if forms else ""
        out.append(SaidName(words, sum(orders.values()), tuple(where), text))
    out.sort(key=lambda s: (-s.taught, s.words))
    return out[:MAX_SAID_NAMES]


def _each(values: Iterable[Any] | None) -> Iterable[Any]:
    """``values``, or None for every event when not given."""
    return itertools.repeat(None) if values is None else values


def said_names(model: Any) -> list[SaidName]:
    """The names kept with ``model`` (``model.info["said_names"]``), entries of the wrong form left out; empty for
    a model written before names were kept (rule 3: today's order)."""
    info = getattr(model, "info", None)
    raw = info.get("said_names") if isinstance(info, dict) else None
    if not isinstance(raw, list):
        return []
    out = []
    for entry in raw[:MAX_SAID_NAMES]:
        words = entry.get("words") if isinstance(entry, Mapping) else None
        taught = entry.get("taught") if isinstance(entry, Mapping) else None
        said = bool(words) and all(isinstance(w, str) and w for w in words) if isinstance(words, list) else False
        if isinstance(words, list) and said and isinstance(taught, int) and _count(taught):
            text = entry.get("text")
            written = text if isinstance(text, str) and len(text) <= MAX_TEXT else ""
            out.append(SaidName(tuple(words), taught, _places(entry.get("places")), written))
    return out


def _count(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value > 0


def _places(raw: object) -> tuple[tuple[int, int], ...]:
    """The ``[[place, events], ...]`` of a kept name, entries of the wrong form left out."""
    if not isinstance(raw, list):
        return ()
    pairs = [p for p in raw if isinstance(p, list) and len(p) == 2 and _count(p[1])]
    return tuple((p[0], p[1]) for p in pairs if isinstance(p[0], int) and not isinstance(p[0], bool) and p[0] >= 0)


def keep_said_names(
    model: Any,
    names: Iterable[tuple[str, ...] | None],
    places: Iterable[int | None] | None = None,
    texts: Iterable[str | None] | None = None,
) -> None:
    """Count ``names`` (one per event, None for an event that teaches none; ``places``: each event's place;
    ``texts``: how each event wrote its name, rule 6) into ``model.info["said_names"]``."""
    counted = count_names(names, said_names(model), places, texts)
    model.info["said_names"] = [
        {"words": list(s.words), "taught": s.taught, "places": [list(p) for p in s.places]}
        | ({"text": s.text} if s.text else {})
        for s in counted
    ]


def record_dataset_names(
    model: Any, tokens: Sequence[Sequence[str]], lang: str, places: Sequence[int] | np.ndarray | None = None
) -> None:
    """``learn``'s part of rule 2: the names a dataset's events teach (``places``: the place each event was learned
    at), kept with the model it learned."""
    model.info["said_names"] = []
    keep_said_names(
        model,
        (event_name(t, lang) for t in tokens),
        None if places is None else [int(k) for k in places],
        (event_text(t, lang) for t in tokens),
    )


def shown_names(labels: Sequence[str], model: Any) -> list[str]:
    """Rule 6 for places' labels (:func:`~spcotmhp.planning.vocabulary.place_labels`, words joined by spaces, the
    form instructions are matched with): each label as written by the taught name with exactly its words in its
    order ("東 廊下" shown 東の廊下), a numbered instance's " #2" kept; the label itself where no such name
    was written otherwise."""
    written = {s.words: s.text for s in said_names(model) if s.text}
    if not written:
        return list(labels)
    out = []
    for label in labels:
        base, mark, number = label.partition(" #")
        text = written.get(tuple(base.split()))
        out.append(f"{text}{mark}{number}" if text else label)
    return out


def place_names(names: Sequence[SaidName]) -> dict[int, SaidName]:
    """Rule 3's name of each place: the name taught most often at it (ties: more words, then the most taught
    overall); a place where no event taught a name has none. One pass over the names' places."""
    best: dict[int, tuple[tuple[int, int, int], SaidName]] = {}
    for said in names:
        for k, events in said.places:
            rank = (events, len(said.words), said.taught)
            if k not in best or rank > best[k][0]:
                best[k] = (rank, said)
    return {k: said for k, (_, said) in best.items()}


def spoken_order(words: Sequence[str], names: Sequence[SaidName]) -> list[str] | None:
    """Rule 3: ``words`` in the order of the taught name with exactly these words, else of the most taught name
    holding them all, else as taught names cover them (a place learned from two names, "room 101" and "loading
    dock": each name in its order, the most taught first, longer names before the names inside them); None when
    some word is in no taught name that fits."""
    wanted = set(words)
    exact = [s for s in names if s.word_set == wanted]
    holding = exact or [s for s in names if wanted <= s.word_set]
    if holding:
        best = max(holding, key=lambda s: s.taught)
        return list(dict.fromkeys(w for w in best.words if w in wanted))
    left, groups = set(wanted), []
    for said in sorted(names, key=lambda s: (-len(s.words), -s.taught)):
        if len(said.words) > 1 and said.word_set <= left:
            groups.append(said)
            left -= said.word_set
    if not groups:
        return None
    groups += [s for s in names if len(s.words) == 1 and s.words[0] in left]
    if sum(len(g.words) for g in groups) != len(wanted):
        return None
    return [w for g in sorted(groups, key=lambda s: -s.taught) for w in g.words]


def taught_numbers(names: Sequence[SaidName]) -> frozenset[str]:
    """The number words that taught names hold (rule 4), only in names with another word: a number alone is no
    name."""
    return frozenset(
        w for s in names if any(number_word(v) is None for v in s.words) for w in s.words if number_word(w) is not None
    )
