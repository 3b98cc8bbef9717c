"""Taught names that lost their place: which names the teaching gave, where each one lives, and which ones share
a place with another name (issue 35, item 5: "merges said out loud").

**Taught names.** A teaching event's name is the set of place words among its words (``place_vocabulary``: the
words the planner can be asked for; grammar and filler words are never place words; the callers, in the layers
above, give them: ``teaching.questions.said_merges``), read from the learner
state the model keeps (``model.learner``: every event, its position, words and place, batch or taught at run
time). A name's words are shown in the order of the first place label that holds them all (``place_labels``,
the one rule of how names are shown), else as that rule orders a label it has no spoken order for: a word in
more names later (the head of a compound name comes last: "east corridor", "west corridor").

**p(n | k)**, the one term by which a place says a name: a name is said with all its words, so p(n | k) is the
geometric mean of its words' p(w | k) = sum_l p(l | k) W_l(w) (Eqs. 10-17, ``word_given_place``), normalised
over the taught names. The questions (``teaching.questions``) use the same term.

**The rule.** A taught name *names a place of its own* when it is the most probable taught name, by p(n | k), of
at least one active place. Otherwise it is reported: its *home* is the active place that gives it its highest
p(n | k), and the place is called by that place's most probable name. The sentence gives the teaches of each
name at that place (the learner state's assignment; all its teaches when none is there) and the distance between
the means of those teaching points, e.g. "playroom and bedroom share place 3; taught 5 and 6 times, 4.1 m apart".
Three bedrooms taught as "bedroom" are one name: it names a place of its own as long as one place is called by
it, and a storeroom learned into one of them is reported (the storeroom is that bedroom's second name).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from spcotmhp.language.said_names import said_names
from spcotmhp.learning.model import SpatialConceptModel


@dataclass(frozen=True)
class TaughtName:
    """One taught name: its words (shown in spoken order) and the learner-state events that said it."""

    words: tuple[str, ...]
    events: np.ndarray
    written: str = ""

    @property
    def text(self) -> str:
        """The name as shown: as taught where it was written otherwise (said_names rule 6: 東の廊下), else its
        words joined by spaces."""
        return self.written or " ".join(self.words)


@dataclass(frozen=True)
class Merge:
    """A taught name without a place of its own (module docstring): ``name`` shares place ``place`` with
    ``other``, the name that place is called by; ``taught`` and ``other_taught`` count their teaches there and
    ``apart_m`` is the distance between the means of those teaching points."""

    name: str
    other: str
    place: int
    taught: int
    other_taught: int
    apart_m: float
    x: float
    y: float

    @property
    def sentence(self) -> str:
        times = f"{self.taught} and {self.other_taught} times"
        return f"{self.name} and {self.other} share place {self.place}; taught {times}, {self.apart_m:.1f} m apart"

    def as_dict(self) -> dict:
        """JSON form: the fields and the sentence (``x``, ``y``: the mean of ``name``'s teaching points there)."""
        return {**asdict(self), "apart_m": round(self.apart_m, 3), "sentence": self.sentence}


def taught_names(
    model: SpatialConceptModel, place_words: list[str], labels: list[str] | None = None
) -> list[TaughtName]:
    """The distinct names of the learner state's events (module docstring), most taught first; empty for a
    model without a learner state (a supervised fit) or without place words. ``place_words``: the model's
    place vocabulary (``planning.vocabulary.place_vocabulary``, a layer above this one: callers give it);
    ``labels``: the places' labels (``place_labels``), whose word order a name's words are shown in."""
    learner = model.learner
    if learner is None or not place_words:
        return []
    a = learner["arrays"]
    is_place = np.zeros(len(model.vocabulary), dtype=bool)
    is_place[[model.word_index[w] for w in place_words]] = True
    ptr, tok = np.asarray(a["tok_ptr"]), np.asarray(a["tok_word"])
    by_name: dict[tuple[int, ...], list[int]] = {}
    for e in range(len(ptr) - 1):
        said = tok[ptr[e] : ptr[e + 1]]
        key = tuple(sorted({int(w) for w in said if is_place[w]}))
        if key:
            by_name.setdefault(key, []).append(e)
    split_labels = [label.split() for label in labels or ()]
    written = {s.words: s.text for s in said_names(model) if s.text}
    shared = {w: sum(w in key for key in by_name) for w in {w for key in by_name for w in key}}
    out = []
    for key, events in by_name.items():
        plain = [model.vocabulary[w] for w in sorted(key, key=lambda w: (shared[w], model.vocabulary[w]))]
        shown = next((label for label in split_labels if set(plain) <= set(label)), plain)
        order = tuple(sorted(plain, key=lambda w: shown.index(w) if w in shown else len(shown)))
        out.append(TaughtName(order, np.array(events, dtype=np.int64), written.get(order, "")))
    return sorted(out, key=lambda n: (-len(n.events), n.text))


def log_name_given_place(model: SpatialConceptModel, names: list[tuple[str, ...]]) -> np.ndarray:
    """(K, N) log p(n | k) up to a constant per place: the mean of log p(w | k) over the words of each name
    (module docstring); normalise over the names with a softmax along axis 1."""
    said = model.word_given_place()
    with np.errstate(divide="ignore"):
        log_said = np.log(said)
    index = model.word_index
    return np.stack([log_said[:, [index[w] for w in n]].mean(axis=1) for n in names], axis=1)


def name_given_place(model: SpatialConceptModel, names: list[tuple[str, ...]]) -> np.ndarray:
    """(K, N) p(n | k), normalised over ``names`` (module docstring)."""
    log_name = log_name_given_place(model, names)
    p = np.exp(log_name - log_name.max(axis=1, keepdims=True))
    return p / p.sum(axis=1, keepdims=True)


def merges(model: SpatialConceptModel, place_words: list[str], labels: list[str] | None = None) -> list[Merge]:
    """Every taught name without a place of its own (module docstring), the most taught first (``place_words``,
    ``labels``: as :func:`taught_names` takes them)."""
    names = taught_names(model, place_words, labels)
    act = np.flatnonzero(model.active_places)
    if len(names) < 2 or not len(act):
        return []
    log_p = log_name_given_place(model, [n.words for n in names])[act]  # (active K, N)
    X = np.asarray(model.learner["arrays"]["X"], dtype=float) if model.learner is not None else np.empty((0, 2))
    place = np.asarray(model.learner["arrays"]["place"], dtype=np.int64) if model.learner is not None else None
    top = _called_by(log_p, names, place, act)  # the name each active place is called by
    owned = set(int(j) for j in top)
    out = []
    for j, name in enumerate(names):
        if j in owned:
            continue
        row = int(np.argmax(log_p[:, j]))
        k, other = int(act[row]), names[int(top[row])]
        mine, theirs = (_at(n.events, place, k) for n in (name, other))
        a, b = X[mine].mean(axis=0), X[theirs].mean(axis=0)
        out.append(
            Merge(name.text, other.text, k, len(mine), len(theirs), float(np.hypot(*(a - b))), float(a[0]), float(a[1]))
        )
    return sorted(out, key=lambda m: (-min(m.taught, m.other_taught), m.name))


TIE_LOG = 1e-6
"""Two names' log p(n | k) closer than this are a tie (floating-point noise of one number): two places whose events
one concept explains say that concept's names equally, so the word term cannot tell them apart."""


def _called_by(log_p: np.ndarray, names: list[TaughtName], place: np.ndarray | None, act: np.ndarray) -> np.ndarray:
    """(active K,) the name each active place is called by: the most probable by p(n | k), a tie (:data:`TIE_LOG`)
    broken by the events of each name the learner assigned to that place, then by the first name. Without the
    tie-break, two places sharing one concept ("first bay" and "bay 3" each a place, their words one concept's)
    were both called by the same name and the other reported as merged."""
    best = log_p.max(axis=1, keepdims=True)
    tied = log_p >= best - TIE_LOG
    if place is None:
        return np.argmax(log_p, axis=1)
    counts = np.array([[np.count_nonzero(place[n.events] == k) for n in names] for k in act], dtype=float)
    return np.argmax(np.where(tied, counts + 1.0, 0.0), axis=1)


def _at(events: np.ndarray, place: np.ndarray | None, k: int) -> np.ndarray:
    """The events of ``events`` assigned to place k (all of them when none is)."""
    there = events[place[events] == k] if place is not None else events[:0]
    return there if len(there) else events


def merge_lines(found: list[Merge]) -> list[str]:
    """The report lines of ``learn`` and ``show``: one per merge, or none."""
    return [f"merged: {m.sentence}" for m in found]
