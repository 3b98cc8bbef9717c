"""Splitting a place where the teaching itself says it is two: a post-step after the paper's Gibbs sampler and
a stated DEPARTURE from the paper (issue 35, item 5; measured in docs/learning.md, ``benchmarks/merges.py``).

Why. The sampler (gibbs.py, unchanged) can end with two differently named rooms in one place: on a SLAM house
taught 4-6 times per room the default ``learn`` kept bedroom and playroom as one place, and teaching "this is the
playroom" twice more then renamed that place, so "go to the bedroom" ended in the playroom. Single-site Gibbs
moves cannot undo such a merge (the first event moved out is a place of one event, far less probable than
staying), and ``--runs`` does not help when every run keeps it. The paper's model has no notion that two names
taught in two rooms are two places; this step adds that one, and only where the map agrees.

The rule. After learning, for each taught name without a place of its own (:func:`spcotmhp.learning.merges.
merges`: its home place is called by another name), the name is split off its home place k when

1. both names were taught at least ``MIN_TEACHES`` = 3 times at k: a name heard once or twice may be a
   misrecognised word or a slip of the tongue (speech recognisers substitute words; the generated homes'
   ``word_noise`` does the same), and three teaches at their own spots are the fewest whose mean moves by at most
   a third of a stray teach's offset; the issue's rooms were taught 4-6 times;
2. and the occupancy grid puts a wall or a door between the two names' teaching points at k
   (:mod:`spcotmhp.learning.separation`). Without one (one open room taught with two names: a kitchen-diner) the
   place is kept as the sampler learned it and the merge is only reported.

Several names of one place are grouped, the most taught first: a name joins the first group (the place's own
name first) whose points it is not separated from, else starts a group; every group but the first becomes a new
place. The moved events are those of the group's names assigned to k; they take the lowest empty place label,
and, when their concept also explains events of other names that stay, the lowest empty concept label too
(otherwise the new place would still say the staying name as much as its own). Nothing is random: the result is
a function of the sampler's final sample, so of the seed. The model is then re-exported from the new assignment
exactly as the sampler exports its own (posterior means, learner state, psi; ``refit``).
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass, field

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.learner_state import from_batch
from spcotmhp.learning.merges import Merge, TaughtName, merges, taught_names
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.posterior import (
    Priors,
    SufficientStats,
    TruncationWarning,
    log_joint,
    mutual_information,
    posterior_mean_model,
    record_truncation,
)
from spcotmhp.learning.selection import MultiRunSelector
from spcotmhp.learning.separation import Separation

MIN_TEACHES = 3
"""Teaches of each of the two names at the place before a split (module docstring, rule 1)."""


@dataclass(frozen=True)
class Split:
    """One name split off a place: ``name`` (with the names grouped with it) left place ``place``, called by
    ``other``, for the new place ``new_place``; ``between``: "wall" or "door"."""

    name: str
    other: str
    place: int
    new_place: int
    taught: int
    other_taught: int
    apart_m: float
    between: str
    names: tuple[str, ...] = ()

    @property
    def sentence(self) -> str:
        return (
            f"{self.name} split from {self.other} (place {self.place} -> new place {self.new_place}): taught "
            f"{self.taught} and {self.other_taught} times, {self.apart_m:.1f} m apart, a {self.between} between"
        )

    def as_dict(self) -> dict:
        return {**asdict(self), "names": list(self.names), "apart_m": round(self.apart_m, 3), "sentence": self.sentence}


@dataclass
class SplitOutcome:
    """What the post-step did: the splits made and, for every merge it left, why (``kept``: merge, reason)."""

    splits: list[Split] = field(default_factory=list)
    kept: list[tuple[Merge, str]] = field(default_factory=list)

    def lines(self, found: list[Merge]) -> list[str]:
        """The lines of ``learn``'s summary: the splits made, then every merge the split model still has
        (``found``), with the reason it was kept where the post-step gave one."""
        why = {m.name: reason for m, reason in self.kept}
        out = [f"split: {s.sentence} (a departure from the paper: docs/learning.md)" for s in self.splits]
        for m in found:
            out.append(f"merged: {m.sentence}" + (f" (kept: {why[m.name]})" if m.name in why else ""))
        return out

    def info(self) -> dict:
        """The record kept in ``model.info["taught_split"]``."""
        return {
            "rule": f"names taught >= {MIN_TEACHES} times, a wall or door between (learning/taught_split.py)",
            "splits": [s.as_dict() for s in self.splits],
        }


@dataclass
class _Group:
    """Names of one place that stay together, their events at the place and the separation from the first."""

    names: list[TaughtName]
    events: np.ndarray
    between: str = ""


def split_taught_merges(
    est: SpCoTMHP,
    dataset: Dataset,
    place_words: list[str],
    labels: list[str] | None = None,
    min_teaches: int = MIN_TEACHES,
) -> SplitOutcome:
    """Apply the post-step (module docstring) to a fitted SpCoTMHP ``est`` learned on ``dataset``: its
    ``places_``, ``concepts_``, ``model_`` and log joint are replaced when a place is split. ``place_words``,
    ``labels``: the model's place vocabulary and labels (``merges.taught_names``). Returns what it did;
    ``est.model_.info["taught_split"]`` records it."""
    model = est.model_
    found = merges(model, place_words, labels)
    outcome = SplitOutcome()
    if not found or model.learner is None:
        return _record(est, outcome)
    names = {n.text: n for n in taught_names(model, place_words, labels)}
    places, concepts = est.places_.astype(np.int64).copy(), est.concepts_.astype(np.int64).copy()
    sep = Separation(dataset.map)
    moves: list[tuple[int, _Group, Merge]] = []
    for k in sorted({m.place for m in found}):
        here = [m for m in found if m.place == k]
        own = names[here[0].other]
        groups = [_Group([own], _events_at(own, places, k))]
        for m in here:
            name = names[m.name]
            events = _events_at(name, places, k)
            if min(len(events), len(groups[0].events)) < min_teaches:
                outcome.kept.append((m, f"a name taught fewer than {min_teaches} times there"))
                continue
            joined = _join(groups, name, events, dataset.positions, sep)
            if joined == 0:
                outcome.kept.append((m, "one open space: no wall or door between the two names' teaching points"))
        for g in groups[1:]:
            moves.append((k, g, next(m for m in here if m.name == g.names[0].text)))
    split_events = _apply(moves, places, concepts, est.K, est.L, names, outcome)
    if split_events:
        refit(est, dataset, places, concepts)
    return _record(est, outcome)


def _events_at(name: TaughtName, places: np.ndarray, k: int) -> np.ndarray:
    return name.events[places[name.events] == k]


def _join(groups: list[_Group], name: TaughtName, events: np.ndarray, X: np.ndarray, sep: Separation) -> int:
    """Put ``name`` into the first group it is not separated from, else a new group; returns the group's index."""
    for i, g in enumerate(groups):
        if sep.between(X[events], X[g.events]) is None:
            g.names.append(name)
            g.events = np.concatenate([g.events, events])
            return i
    groups.append(_Group([name], events, sep.between(X[events], X[groups[0].events]) or "wall"))
    return len(groups) - 1


def _apply(
    moves: list[tuple[int, _Group, Merge]],
    places: np.ndarray,
    concepts: np.ndarray,
    K: int,
    L: int,
    names: dict[str, TaughtName],
    outcome: SplitOutcome,
) -> int:
    """Move the events of every new group to an empty place (and concept, module docstring) in ``places`` and
    ``concepts``; returns how many events moved. A group with no empty label left is kept and says so."""
    name_of = np.full(len(places), -1, dtype=np.int64)
    for j, n in enumerate(names.values()):
        name_of[n.events] = j
    index = {text: j for j, text in enumerate(names)}
    moved = 0
    for k, g, m in moves:
        free_k = np.flatnonzero(np.bincount(places, minlength=K) == 0)
        mine = np.isin(name_of, [index[n.text] for n in g.names])
        shared = [int(l) for l in np.unique(concepts[g.events]) if ((concepts == l) & ~mine & (name_of >= 0)).any()]
        free_l = np.flatnonzero(np.bincount(concepts, minlength=L) == 0)
        if not len(free_k) or (shared and not len(free_l)):
            full = "places (--max-places)" if not len(free_k) else "concepts (--max-concepts)"
            outcome.kept.append((m, f"no empty component of the truncation left: learn with more {full}"))
            continue
        new_k = int(free_k[0])
        if shared:
            concepts[g.events[np.isin(concepts[g.events], shared)]] = int(free_l[0])
        places[g.events] = new_k
        moved += len(g.events)
        outcome.splits.append(
            Split(
                m.name,
                m.other,
                k,
                new_k,
                m.taught,
                m.other_taught,
                m.apart_m,
                g.between,
                tuple(n.text for n in g.names),
            )
        )
    return moved


def _record(est: SpCoTMHP, outcome: SplitOutcome) -> SplitOutcome:
    est.model_.info["taught_split"] = outcome.info()
    return outcome


def refit(est: SpCoTMHP, dataset: Dataset, places: np.ndarray, concepts: np.ndarray) -> SpCoTMHP:
    """Re-export ``est``'s model from the assignment (``places``, ``concepts``) with the word switches of its
    final sample, as ``SpCoTMHP.fit`` exports its own final sample: posterior means, learner state, log joint,
    mutual information, truncation record and psi (the transitions labelled anew; ``est.connectivity``). The
    provenance in ``model.info`` is kept."""
    old = est.model_
    assert old.learner is not None
    obs = Observations.from_dataset(
        dataset, use_features=est.use_features, use_trajectory=est.use_trajectory, feature_weight=est.feature_weight
    )
    a = old.learner["arrays"]
    ptr, tok, z = np.asarray(a["tok_ptr"]), np.asarray(a["tok_word"]), np.asarray(a["tok_z"], dtype=bool)
    D = None if obs.features is None else obs.features.shape[1]
    priors = Priors.build(old.hyper, est.K, est.L, len(obs.vocabulary), D)
    background = np.bincount(tok[~z], minlength=len(obs.vocabulary)).astype(float) if est.background_words else None
    concept_words = None
    if est.background_words:
        concept_words = np.zeros((obs.E, len(obs.vocabulary)))
        np.add.at(concept_words, (np.repeat(np.arange(obs.E), np.diff(ptr))[z], tok[z]), 1.0)
    stats = SufficientStats.from_assignments(obs, places, concepts, est.K, est.L, concept_words, background)
    run = getattr(est, "variant_run_", None)
    est.log_joint_ = log_joint(priors, stats, est._event_transitions(places), None if run is None else run.log_terms)
    model = posterior_mean_model(priors, stats, None, obs.vocabulary, old.hyper, old.info)
    model.map, model.costmap = dataset.map, dict(old.costmap)
    model.learner = from_batch(
        obs, places, concepts, ptr, tok, z, est.K, est.L, old.hyper, est.replay, est.background_words
    )
    est.mutual_information_ = mutual_information(model.pi, model.W)
    model.info.update(log_joint=est.log_joint_, mutual_information=est.mutual_information_)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)  # the fit reported its own already
        record_truncation(model, est.K, est.L)
    est._export_psi(model, priors, dataset, obs, places)  # the sampler's own export of psi
    est.model_, est.places_, est.concepts_ = model, places, concepts
    return est


def split_selected(
    sel: MultiRunSelector,
    dataset: Dataset,
    place_words: list[str],
    labels: list[str] | None = None,
    min_teaches: int = MIN_TEACHES,
) -> SplitOutcome:
    """The post-step on the run a :class:`MultiRunSelector` kept (the runs and their selection are the paper's):
    ``sel.model_`` becomes the split model, with the selector's connectivity applied again."""
    outcome = split_taught_merges(sel.best_, dataset, place_words, labels, min_teaches)
    if outcome.splits:
        sel.keep(sel.best_index_)
    return outcome
