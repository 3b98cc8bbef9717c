"""Teaching a learned model at run time: one call shared by the CLI (``spcotmhp teach``), the HTTP service
(``POST /teach``) and the ROS 2 node (``/spcotmhp/teach``).

``teach(model, events)`` continues the online learner from ``model`` (its learner state, else pseudo-counts;
:mod:`spcotmhp.learning.online`) and returns the updated model and what each event was assigned to;

What one teach does (the rule). An utterance is read for the name it teaches (:mod:`spcotmhp.language.naming`;
one that names nothing, "hello" or "is this the kitchen?", is refused with NotANaming and nothing is learned),
and the name's words are learned as a *naming event* (:mod:`spcotmhp.learning.collapsed`): its concept is one that
already holds a word of the name or a new one, and (i_e, C_e) is the mode of the online learner's collapsed
conditional, Eqs. 8-17 with every parameter integrated out,

    p(i_e = k, C_e = l | x_e, S_e, rest)  proportional to  t(x_e | place k) / sum_c phi_c(k)
                                                            * (n_l + alpha) (n_lk + gamma) / (n_l + K gamma)
                                                            * DirMult(S_e | beta + W_l)

(a place with no events has t = 1 / known area). So a word no place carries, taught far from every place (where
t(x_e | k) of every place is below the density of a new one, after Eq. 9's rescaling), makes a new place and a
new concept holding the word: the place's label is the word, and it is plannable at once. Taught inside a place,
the new concept joins that place; it becomes one of the place's names (its label) when the posterior says so,
p(w | k) >= ``vocabulary.PLACE_WORD_RATIO`` times the place's most said name, which one teach against many earlier
events does not reach. The reply (:meth:`Taught.summary`) says which happened.

``planner_for(model)`` gives the planner of the updated model (the previous planner's graph updated
incrementally, kept in the graph cache the caller passes or the previous planner's own).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.observations import check_word_lengths
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent, as_event

if TYPE_CHECKING:
    from spcotmhp.language.naming import Naming


@dataclass
class Taught:
    """The result of a teach: the updated model, the place of each event (index and label), its place words,
    whether the place is new, and the times of the update and of exporting the model (seconds)."""

    model: SpatialConceptModel
    places: list[int]
    labels: list[str]
    new_places: list[bool]
    place_words: list[str]
    time_update_s: float
    time_export_s: float
    names: list[Naming | None] = dataclasses.field(default_factory=list)
    shown: list[str] = dataclasses.field(default_factory=list)  # the labels as taught (said_names rule 6)

    def label(self, k: int = -1) -> str:
        """Event ``k``'s place label as shown: written as taught ("東の廊下"), else the label."""
        return self.shown[k] if self.shown else self.labels[k]

    def outcome(self, k: int = -1) -> tuple[str, bool, str]:
        """(what happened to event ``k``: "new place" or "joined place", whether its name now names that place,
        a one-line message) (module docstring)."""
        label, place = self.label(k), self.places[k]
        naming = self.names[k] if self.names else None
        kind = "new place" if self.new_places[k] else "joined place"
        if naming is None:
            return kind, False, f"learned at place {place} '{label}'"
        names = all(w in self.labels[k].split() for w in naming.words)
        said = f"'{naming.name}'"
        if self.new_places[k]:
            return kind, names, f"{said} is a new place (place {place}, '{label}')"
        if names:
            return kind, True, f"{said} joined place {place} and is one of its names ('{label}')"
        return (
            kind,
            False,
            (
                f"{said} joined place {place} '{label}' but does not name it yet: the place's other names outweigh "
                "this teach (teach it again there, or teach it where no place is)"
            ),
        )

    def summary(self, k: int = -1) -> dict:
        """JSON-ready: the place of event ``k`` (default the last), its label and words, and what happened
        (:meth:`outcome`)."""
        kind, named, message = self.outcome(k)
        naming = self.names[k] if self.names else None
        return {
            "place": self.places[k],
            "label": self.label(k),
            "names": [w for w in self.labels[k].split() if w in self.place_words],
            "new_place": self.new_places[k],
            "name": None if naming is None else naming.name,
            "outcome": kind,
            "named": named,
            "message": message,
            "places": int(self.model.active_places.sum()),
            "time_update_s": self.time_update_s,
            "time_export_s": self.time_export_s,
        }


def teach(model: SpatialConceptModel, events: Iterable[object], answers: str | None = None) -> Taught:
    """Learn ``events`` (``online.as_event`` forms) into ``model``; the model given is not modified. Raises
    TeachingError (nothing learned) for a bad event. The random stream is the model's online seed (0 unless an
    online learner set one) at the model's event count, so teaching is reproducible. Events marked as answers
    to the robot's questions are learned as the answer model ``answers`` says (``teaching.answers``; None: its
    default)."""
    from spcotmhp.language.said_names import keep_said_names, shown_names
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
    from spcotmhp.teaching.answers import answer_model

    how = answer_model(answers)
    seed = (model.info.get("online") or {}).get("seed", 0) if isinstance(model.info, dict) else 0
    learner = OnlineSpCoTMHP(init_model=model, seed=int(seed) if isinstance(seed, int) else 0, **how.learner_settings())
    before = {int(k) for k in model.active_places.nonzero()[0]}
    t0 = time.perf_counter()
    read = [naming_event(item) for item in events]
    batch = [event for event, _ in read]
    learner.partial_fit(batch)
    t1 = time.perf_counter()
    updated = learner.model_
    updated.info["taught"] = count_taught(model, batch)
    namings = [tuple(naming.words) if naming else None for _, naming in read]
    texts = [n.name if n and n.name != " ".join(n.words) else None for _, n in read]  # 東の廊下 (said_names rule 6)
    keep_said_names(updated, namings, [int(k) for k in learner.last_places_], texts)  # names as taught
    t2 = time.perf_counter()
    words = place_vocabulary(updated)
    labels = place_labels(updated, words)
    places = [int(k) for k in learner.last_places_]
    return Taught(
        updated,
        places,
        [labels[k] for k in places],
        [k not in before for k in places],
        words,
        t1 - t0,
        t2 - t1,
        [naming for _, naming in read],
        shown_names([labels[k] for k in places], updated),
    )


def naming_event(item: object) -> tuple[TeachingEvent, Naming | None]:
    """A teaching event (``online.as_event`` forms) and, for one given as an utterance (text), the name it teaches
    (:func:`spcotmhp.language.naming.read_naming`): the event's words are then the name's, as a naming event. Events
    given as words are learned as they are. NotANaming (a TeachingError) for an utterance that names nothing."""
    from spcotmhp.language.naming import read_naming

    event = as_event(item)
    said = None
    if isinstance(item, Mapping):
        said = item.get("utterance")
    elif isinstance(item, (tuple, list)) and len(item) >= 3:
        said = item[2]
    if not isinstance(said, str):
        return event, None
    naming = read_naming(said)
    check_word_lengths(naming.words, "the name taught")  # a name's words may join the utterance's (Japanese)
    return dataclasses.replace(event, words=naming.words, named=True), naming


def count_taught(model: SpatialConceptModel, batch: list[TeachingEvent]) -> dict[str, int]:
    """{word: teaches that said it}: ``model``'s count (``vocabulary.taught_counts``) plus the words of ``batch``
    (grammar and filler words left out). A word taught at run time is a place word only once some place's label
    carries it (rule 4 of ``vocabulary.place_vocabulary``); until then the planner refuses it saying how often
    it was taught.

    >>> from spcotmhp.learning.online import TeachingEvent
    >>> m = SpatialConceptModel.__new__(SpatialConceptModel); m.info = {"taught": {"study": 1}}
    >>> count_taught(m, [TeachingEvent.from_utterance("this is the study", 0, 0)])
    {'study': 2}
    """
    from spcotmhp.planning.vocabulary import FUNCTION_WORDS, taught_counts

    counts = taught_counts(model)
    for event in batch:
        for w in dict.fromkeys(event.words):
            if w not in FUNCTION_WORDS:
                counts[w] = counts.get(w, 0) + 1
    return counts


def planner_for(model: SpatialConceptModel, settings=None, previous=None, cache=None):
    """(HierarchicalPlanner of ``model``, seconds it took), so that a plan right after a teach uses the new
    place. With ``previous`` (the planner before the teach) its planning graph is updated incrementally
    (``PlanningGraph.update``: territory-local fields whose territory did not change are kept); otherwise it is
    built (``PlanningGraph.build``). Both go through ``cache`` (a :class:`~spcotmhp.planning.graph_cache.
    GraphCache`; default: ``previous``'s cache, else a new one), where the new planner finds the graph."""
    from spcotmhp.planning.graph_cache import GraphCache
    from spcotmhp.planning.planner import HierarchicalPlanner

    t0 = time.perf_counter()
    if cache is None:
        cache = previous.cache if previous is not None else GraphCache()
    if (
        previous is not None
        and previous.graph.model.map is not None
        and model.map is not None
        and previous.graph.model.map.shape == model.map.shape
    ):
        previous.graph.update(model, cache=cache)  # cached under the new model's fingerprint, found just below
    planner = HierarchicalPlanner(model, settings, cache=cache)
    return planner, time.perf_counter() - t0
