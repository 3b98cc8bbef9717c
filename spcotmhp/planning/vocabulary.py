"""Which words of a learned vocabulary name places, and what to call each place.

The instruction parser matches place words against the model's vocabulary; these functions decide which
vocabulary words count as place words (on-site names in any language, never function words) and give each place
a readable label, its whole name ("alice's room", "east corridor"), for plans and explanations.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from spcotmhp.language.numbers import numbered_labels
from spcotmhp.language.reading import LANGUAGES
from spcotmhp.language.said_names import SaidName, place_names, said_names, spoken_order, taught_numbers
from spcotmhp.language.table import word_table

INSTANCE_RATIO = 4.0
"""The planner's default ``instance_ratio`` (:class:`~spcotmhp.planning.planner.PlannerSettings`)."""

PLACE_WORD_RATIO = 0.75
"""A word is a place word when, for some active place, its score is >= this fraction of that place's best
word's score (see :func:`place_vocabulary`); the words of a place's label are chosen the same way."""


FUNCTION_WORDS = frozenset().union(*(word_table(lang).function_words for lang in LANGUAGES))
"""Grammar and filler words of every supported language (never place words); generic nouns such as "room" are
not among them, so that "alice's room" keeps its "room"."""


def place_vocabulary(model: Any, ratio: float = PLACE_WORD_RATIO, instance_ratio: float = INSTANCE_RATIO) -> list[str]:
    """The words of ``model.vocabulary`` that name places, sorted.

    Two scores of word w for place k: how often it is said there, p(w | k) = sum_l p(l | k) W_l(w)
    (:meth:`SpatialConceptModel.word_given_place`), and the label score, its unigram-rescaled form
    sum_l p(l | k) W_l(w) / sum_c W_c(w) that :meth:`SpatialConceptModel.place_names` ranks by
    (:meth:`SpatialConceptModel.label_scores`). Rescaling
    singles out the words said at few places: a function word spread over the concepts ("this", です) scores
    about 1/(number of concepts using it), a name of its own near 1. A word is kept when

    1. it is a *core* name word of some active place (rescaled score at least ``ratio`` times that place's best
       one among the words that are not grammar words of rule 3, which would otherwise set the bar: "this is
       the" said with a name taught at a small place outscored its old name and its new one alike; every word of
       a multi-word name that only this place has, and 1/3 for each of three bedrooms with a concept each,
       which is then also the best score of those places), or it is said at some active place
       at least ``ratio`` times as often as that place's core name words: a word shared by differently named
       places ("corridor" in "east corridor" and "south corridor", "room" in "alice's room") is part of both
       names although its rescaled score is only 1/2;
    2. and, with more than one active place, it does not name every active place: p(w | i) is below
       1/``instance_ratio`` of its maximum for some place (the likelihood, not the joint p(i, w) of Eq. 28's
       semantic term: a name taught only a few times, at a place visited rarely, is still a name), with the
       planner's own instance ratio (4, :func:`~spcotmhp.planning.places.instance_places`): with a few
       utterances per place a real name is only 5-10 times likelier at its place than elsewhere;
    3. and it is not a grammar or filler word of a supported language ("here", "called", "the", です): said with
       every name ("this is the kitchen"), such words would pass rule 1, and rule 2 removes them only where
       they are said at every place. A site whose name is such a word cannot be named in instructions. A number
       word ("one", "first") that a taught name holds with another word ("aisle one", "the first aisle";
       ``model.info["said_names"]``, :mod:`spcotmhp.language.said_names`) is a place word: instructions match it
       only inside that name.

    A word of the name taught most often at an active place (:func:`~spcotmhp.language.said_names.place_names`)
    passes rule 1 (rules 2 and 3 still apply): "the east corridor" taught at a new place whose events the concept
    of "corridor" explains says "east" far less than "corridor", and yet "east" is what names that place.
    4. and, for a word taught at run time (:func:`taught_counts`), the label (:func:`place_labels`) of some active
       place carries it: one teach at a spot whose events a large place's concept explains makes the word
       likely only within that concept (so it passes rule 1) without making it that place's name, and the
       planner would otherwise send "go to the study" wherever p(i | S) happens to peak. Such a word is
       refused (:meth:`~spcotmhp.planning.planner.HierarchicalPlanner.plan` says how often it was taught) until
       more teaches there make it a place's name.
    """
    if not len(model.vocabulary):
        return []
    act = np.asarray(model.active_places, dtype=bool)
    said, rescaled = model.word_given_place()[act], model.label_scores()[act]
    grammar_words = FUNCTION_WORDS - taught_numbers(said_names(model))  # rule 3's exception: "aisle one"
    grammar = np.array([w in grammar_words for w in model.vocabulary], dtype=bool)
    best = np.where(grammar, 0.0, rescaled).max(axis=1, keepdims=True)  # rule 3's words set no bar
    core = (rescaled >= ratio * best) & ~grammar
    core_said = np.where(core, said, np.inf).min(axis=1, keepdims=True)
    keep = (core | (said >= ratio * core_said)).any(axis=0)
    keep |= np.isin(model.vocabulary, sorted(own_name_words(model, act)))  # rule 1's exception: "east corridor"
    if act.sum() > 1:
        keep &= ~(said >= said.max(axis=0) / instance_ratio).all(axis=0)
    words = sorted(w for w, k in zip(model.vocabulary, keep, strict=False) if k and w not in grammar_words)
    taught = taught_counts(model)
    if any(w in taught for w in words):  # rule 4: a word taught at run time names a place once a label carries it
        labels = place_labels(model, words)
        carried = {w for k in np.flatnonzero(act) for w in labels[k].split()}
        words = [w for w in words if w not in taught or w in carried]
    return words


def own_name_words(model: Any, active: np.ndarray) -> set[str]:
    """The words of the names taught most at the ``active`` places (:func:`place_vocabulary`'s exception)."""
    names = said_names(model)
    if not names:
        return set()
    own = place_names(names)
    return {w for k in np.flatnonzero(active) if int(k) in own for w in own[int(k)].words}


def taught_counts(model: Any) -> dict[str, int]:
    """{word: how many teaches said it} (``model.info["taught"]``, kept by :func:`spcotmhp.teaching.teach.
    teach`); empty for a model never taught at run time."""
    info = getattr(model, "info", None)
    taught = info.get("taught") if isinstance(info, dict) else None
    if not isinstance(taught, dict):
        return {}
    return {w: int(n) for w, n in taught.items() if isinstance(w, str) and isinstance(n, int)}


def place_labels(
    model: Any,
    place_words: Sequence[str],
    names: Sequence[str] | None = None,
    ratio: float = PLACE_WORD_RATIO,
) -> list[str]:
    """A name per place, whole ("alice's room", "entrance corridor"): the place words said there at least
    ``ratio`` times as often as its most said place word (p(w | k) over ``place_words``; function words are
    already out, so no rescaling is needed, and a name shared by many places is not beaten by a rare noise
    word), joined by spaces; ``model.place_names()`` where no place word is known. A word joins a label only if
    the place says it more often than chance, p(w | k) > 1 / (vocabulary size), the p(w | k) of a place whose
    concepts hold no words: a place whose events carry no place word (a new place taught "this is the"), its
    p(l | k) spread over every concept, said every name about equally and was labelled with all of them; such a
    place is "place k". Likewise a word joins an active place's label only if a concept with events at the place
    says it more often than chance (:func:`_said_by_own_concepts`): a place of one taught event otherwise carried
    the names of the largest concepts besides its own ("study bedroom"), whose prior mass alone puts them there.

    The name taught most at a place (by the events the learner assigned there, ``model.info["said_names"]``)
    is its label where it holds every word so chosen and only place words: "east corridor" taught at a place whose
    events a "corridor" concept explains (:func:`spcotmhp.language.said_names.place_names`).

    Word order. A model keeps bags of words, not their order (Eq. 17). The words are ordered as people taught
    them (the names kept with the model, :func:`spcotmhp.language.said_names.spoken_order`: "aisle one", "room
    101", "second bedroom"), else as in ``names`` (names in spoken order, e.g. a dataset's ``place_names``; by
    default ``model.info["place_names"]`` when the model holds them) where one of these names holds exactly the
    label's words; otherwise (a model folder written before names were kept) a word shared by more places comes
    later (the head of a compound name comes last in English and Japanese: "east corridor", "alice's room"), ties
    in alphabetical order.
    """
    fallback = model.place_names()
    if not place_words:
        return fallback
    idx = [model.word_index[w] for w in place_words]
    said = model.word_given_place()[:, idx]  # (K, |place_words|)
    act = np.asarray(model.active_places, dtype=bool)
    chance = 1.0 / len(model.vocabulary)  # p(w | k) where the place's concepts hold no words (uniform W)
    chosen = (said >= ratio * said.max(axis=1, keepdims=True)) & (said > chance)
    chosen &= _said_by_own_concepts(model, idx, chance) | ~act[:, None]
    shared = chosen[act].sum(axis=0)
    spoken = _given_orders(model, names)
    taught, known = said_names(model), set(place_words)
    own = place_names(taught)
    labels = []
    for k in range(len(chosen)):
        words = [place_words[int(j)] for j in np.flatnonzero(chosen[k])]
        if not words:
            labels.append(f"place {k}")
            continue
        order = _taught_order(words, own.get(k), taught, known) if taught and act[k] else None
        if order is None:
            order = spoken.get(frozenset(words))
        if order is None or len(order) < len(words):
            order = sorted(words, key=lambda w: (shared[place_words.index(w)], w))
        labels.append(" ".join(order))
    return labels


def _given_orders(model: Any, names: Sequence[str] | None) -> dict[frozenset[str], list[str]]:
    """{word set: words in order} of ``names`` (default ``model.info["place_names"]``; :func:`place_labels`)."""
    if names is None:
        info = getattr(model, "info", None) or {}
        names = info.get("place_names") if isinstance(info.get("place_names"), list) else None
    spoken: dict[frozenset[str], list[str]] = {}
    for name in names or ():
        if isinstance(name, str):
            spoken.setdefault(frozenset(name.split()), name.split())
    return spoken


def _taught_order(
    words: list[str], own: SaidName | None, taught: Sequence[SaidName], known: set[str]
) -> list[str] | None:
    """A place's label from the taught names (:mod:`spcotmhp.language.said_names`, rule 3): ``own``, the name taught
    most there, when it holds ``words`` and only ``known`` words, else ``words`` in taught order; None: no taught
    name orders them."""
    if own is not None and set(words) <= set(own.words) <= known:
        return list(own.words)
    return spoken_order(words, taught)


def _said_by_own_concepts(model: Any, idx: list[int], chance: float) -> np.ndarray:
    """(K, len(idx)) bool: some concept with events at the place says the word more often than chance. A concept
    l has events at place k when phi_l(k) is above its least entry (for a Dirichlet posterior mean the least entry
    is gamma / (N_l + K gamma), the prior alone, at the places none of l's events is at)."""
    phi = np.asarray(model.phi, dtype=float)
    own = phi > phi.min(axis=1, keepdims=True) * (1.0 + 1e-9)  # (L, K)
    says = np.asarray(model.W, dtype=float)[:, idx] > chance  # (L, words)
    return (own.T.astype(np.int64) @ says.astype(np.int64)) > 0


def said_words(place_words: Sequence[str], names: Sequence[str], active: Sequence[bool] | np.ndarray) -> list[str]:
    """The words instructions are read with: ``place_words`` and the labels of active places that hold a number
    ("aisle one", "room 101"; :func:`~spcotmhp.language.numbers.numbered_labels`), which the lexicon matches
    whole in their spoken variants ("aisle 1", "aisle number one")."""
    return [*place_words, *numbered_labels(n for n, a in zip(names, active, strict=True) if a)]


def parse_instruction(
    instruction: Any, model: Any, place_words: Sequence[str], lang: str | None = None, *, floors: bool = False
) -> Any:
    """``to_instruction(instruction, place_words, lang)`` with no floor said (:func:`one_floor`; ``floors``: a
    building's planner, which honours them); an
    UnknownPlaceWord for a word taught at run time that names no place yet (rule 4 of :func:`place_vocabulary`)
    says so and how often it was taught, rather than that the word is unknown."""
    from spcotmhp.errors import UnknownPlaceWord
    from spcotmhp.planning.instructions import to_instruction

    try:
        ins = to_instruction(instruction, place_words, lang)
        return ins if floors else one_floor(ins)
    except UnknownPlaceWord:
        taught = taught_counts(model)
        said = {w.lower() for w in str(instruction).replace("'", " ").split()} if taught else set()
        pending = [w for w in taught if w not in place_words and (w in said or w in str(instruction))]
        if not pending:
            raise
        word = max(pending, key=len)
        times = {1: "once", 2: "twice"}.get(taught[word], f"{taught[word]} times")
        raise UnknownPlaceWord(
            f"'{word}' was taught {times} but names no place yet: the teaches there do not yet outweigh the "
            "place's other names; teach it again where that place is"
        ) from None


def one_floor(ins: Any) -> Any:
    """``ins`` when none of its places says a floor; else UnsupportedPhrase: one map is one floor, and a floor said
    ("the bedroom upstairs") cannot be honoured on it, so it is refused rather than dropped."""
    said = [q for q in (*ins.waypoints, ins.goal, *ins.avoid, *ins.not_goal) if q.floor is not None]
    if said:
        from spcotmhp.errors import UnsupportedPhrase
        from spcotmhp.language.wording import excerpt

        raise UnsupportedPhrase(
            f"{excerpt(said[0].floor_said or str(said[0].floor))} gives the floor of {excerpt(said[0].label)}, but "
            "this model is one floor: a building's model plans across floors ('spcotmhp learn BUILDING_DIR'); here say "
            "the place's name alone"
        )
    return ins
