"""Online learning of spatial concepts: teaching events taken one at a time ("this is alice's room" at x, y).

Algorithm: incremental collapsed Gibbs sampling with fixed-lag and random rejuvenation, and split-merge moves.

* Each new event e gets its place i_e and concept C_e drawn from their collapsed conditional given every earlier
  assignment (``collapsed.py``: the NIW predictive of the position, the transition from i_{e-1} with psi
  integrated out, Eq. 9's unigram rescaling, pi, phi, theta and W integrated out, Eqs. 5-17), and its words'
  background switches are drawn.  New places and concepts appear when an empty weak-limit component explains
  the event best; new words extend the vocabulary (one more column of every count: the Dirichlet of W is over
  the words heard so far).
* Fixed-lag rejuvenation (SpCoSLAM 2.0: Taniguchi, Hagiwara, Taniguchi and Inamura, "Improved and scalable
  online learning of spatial concepts and language models with mapping", Autonomous Robots 44, 2020): the last
  ``lag`` events are resampled, in order, after each new one, so that an early assignment is revised once
  later events make it clear (the second "kitchen" turns a one-event place into the kitchen).
* Random rejuvenation (Canini, Shi and Griffiths, "Online inference of topics with latent Dirichlet
  allocation", AISTATS 2009, the incremental Gibbs sampler): ``rejuvenation`` events drawn uniformly from the
  older ones are resampled too, so old assignments keep moving toward the posterior of all the data.

* Split-merge moves (``online_split_merge``: Dahl's sequentially-allocated merge-split, Metropolis-Hastings on the
  collapsed log joint): ``split_merge`` proposals per event split a place, a concept or a room (a place with its
  one concept) in two, or merge two into one.  Single-site steps cannot undo a merge made early in a stream (two
  rooms in one place while each had a few events) nor gather a name spread over several concepts.

Each update costs O(lag + rejuvenation) Gibbs steps of O(K L + K^2) each and ``split_merge`` moves of at most
``split_merge_events`` conditionals each, independent of the number of events seen (apart from appending it to
the event arrays).

Where this departs from SpCoSLAM 2.0: one chain instead of a Rao-Blackwellised particle filter.  SpCoSLAM 2.0's
particles carry SLAM hypotheses (map and trajectory, weighted by the scan likelihood) with the concept
assignments; here positions are given in a fixed map, so the particles would carry assignments only, and their
diversity is what the rejuvenation steps provide (Canini et al. found incremental Gibbs with rejuvenation at
least as accurate as particle filters of the same cost).  Its fixed-lag step resamples the lag's events given
the particle's parameters; here every parameter is integrated out (the batch learner's collapsed concept step
extended to places).  Positions of the robot between events (the trajectory) are not used.

Starting from a batch-learned model: its ``learner`` member (the events, assignments and counts the batch
sampler ended with, kept in the model folder) becomes the state, so the first update continues from exactly
that sample; a model without it (a supervised fit, a folder saved before learner states existed) starts from
pseudo-counts that reproduce its posterior means (``learner_state.pseudo_state``), with no earlier events to
revise.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Iterable

import numpy as np

from spcotmhp.errors import TeachingError
from spcotmhp.language.text import is_japanese
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.gibbs import make_rng
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.observations import TeachingEvent, as_event
from spcotmhp.learning.online_split_merge import KINDS, propose, settle_name
from spcotmhp.learning.posterior import TruncationWarning
from spcotmhp.limits import MAX_CONCEPTS, MAX_ITERATIONS, MAX_PLACES, check_count
from spcotmhp.metric.maps import OccupancyMap


def log_new_place_density(occ: OccupancyMap) -> float:
    """log of 1 / (known area of ``occ``, m^2): the density of a position under a place with no events yet.

    >>> from spcotmhp.metric.maps import OccupancyMap
    >>> grid = np.zeros((4, 5), np.int8); grid[0, :] = -1  # 15 known cells of 0.5 m: 3.75 m^2
    >>> round(log_new_place_density(OccupancyMap(grid, 0.5)), 6) == round(-math.log(3.75), 6)
    True
    """
    known = ~occ.unknown
    return -float(np.log(max(int(known.sum()), 1) * occ.resolution**2))


class OnlineSpCoTMHP:
    """The online SpCoTMHP learner (scikit-learn style: settings in ``__init__``, ``partial_fit`` returns self).

    Args:
        K, L: initial truncations of the place and concept Dirichlet processes; each doubles when all its
            components hold events, up to ``max_K`` / ``max_L`` (then a TruncationWarning says so).
        lag: events resampled after each new one (fixed-lag rejuvenation); rejuvenation: older events drawn at
            random and resampled after each new one.
        split_merge: split-merge proposals after each new event (0: none); split_merge_events: a move is proposed
            only when its two places or concepts hold at most this many events (None: no bound), which bounds
            its time (docs/results.md gives the time per event moved); the bound applies to a split and to its
            reverse merge alike, so it does not bias the moves.
        replay, background_words: as the batch learner (``gibbs.SpCoTMHP``).
        use_features, feature_weight: image features of the events, each row rescaled to ``feature_weight``.
        connectivity: psi of the exported model: "auto" or "map" (places whose territories touch, when there is
            a map; ``connectivity.map_adjacency``) or "hmm" (the posterior mean of the event transitions).
        hyper: priors (default as the batch learner); init_model: a learned model to continue from (its
            hyper-parameters, map and cost map are kept); map: the map teaching positions are checked against
            and the exported model plans on (default: ``init_model.map``); its known area also gives the density
            of a position under a place with no events yet, 1 / area (the NIW prior's predictive otherwise);
            ``check_map=False`` checks positions only for being finite (streaming a recorded dataset).
        seed: the random stream; the update by event n (counting every event of the state) uses
            ``make_rng(seed, n)``, so a sequence of updates is reproducible however it is split into calls (and
            processes).
        answer_alone, answer_weight, after_answer: how an event marked ``answer`` is learned (the defaults: as
            any teach, the paper's model): a segment of its own (no psi transition in or out), entering the
            counts as ``answer_weight`` events (``collapsed.py``), and ``after_answer(state, e, rng)`` called
            once it is learned (a block move at the answer; :mod:`spcotmhp.teaching.answers`).

    Learned attributes: ``state_`` (``collapsed.CollapsedState``), ``vocabulary_``, ``places_`` / ``concepts_``
    (E,) the current i and C of every event taught, ``update_times_`` (seconds per event), ``last_places_``
    (the place of each event of the last ``partial_fit`` as it ended), ``model_`` (the posterior-mean model of
    the current state, exported on first access after an update).
    """

    def __init__(
        self,
        K: int = 20,
        L: int = 20,
        max_K: int = 200,
        max_L: int = 200,
        lag: int = 10,
        rejuvenation: int = 10,
        split_merge: int = 6,
        split_merge_events: int | None = 60,
        replay: bool = True,
        background_words: bool = True,
        use_features: bool = True,
        feature_weight: float | None = 1.0,
        connectivity: str = "auto",
        hyper: Hyperparameters | None = None,
        init_model: SpatialConceptModel | None = None,
        map: OccupancyMap | None = None,
        check_map: bool = True,
        seed: int = 0,
        answer_alone: bool = False,
        answer_weight: float = 1.0,
        after_answer: Callable[[CollapsedState, int, np.random.Generator], object] | None = None,
    ) -> None:
        self.K, self.L, self.max_K, self.max_L = K, L, max_K, max_L
        self.lag, self.rejuvenation = lag, rejuvenation
        self.split_merge, self.split_merge_events = split_merge, split_merge_events
        self.replay, self.background_words = replay, background_words
        self.use_features, self.feature_weight = use_features, feature_weight
        self.connectivity, self.hyper = connectivity, hyper
        self.init_model, self.map, self.check_map, self.seed = init_model, map, check_map, seed
        self.answer_alone, self.answer_weight, self.after_answer = answer_alone, answer_weight, after_answer

    # ---- public API ----------------------------------------------------------------------------------------
    def partial_fit(self, events: Iterable[object]) -> OnlineSpCoTMHP:
        """Learn from ``events`` (TeachingEvent, mapping or tuple each; ``as_event``), one at a time in order.
        Every event is checked first: on a TeachingError nothing has changed."""
        batch = [as_event(item) for item in events]
        if not hasattr(self, "state_"):
            self._start()
        for event in batch:
            self._check(event)
        first = self.state_.E
        for event in batch:
            t0 = time.perf_counter()
            self._update(event, make_rng(self.seed, self.state_.E))
            self.update_times_.append(time.perf_counter() - t0)
        self._model: SpatialConceptModel | None = None
        self.last_places_ = self.state_.place[first:].copy()
        return self

    @property
    def places_(self) -> np.ndarray:
        return self.state_.place.copy()

    @property
    def concepts_(self) -> np.ndarray:
        return self.state_.concept.copy()

    @property
    def model_(self) -> SpatialConceptModel:
        """The posterior-mean model of the current state (``learner_state.export_model``), cached until the next
        update."""
        from spcotmhp.learning.learner_state import export_model

        model = getattr(self, "_model", None)
        if model is None:
            model = self._model = export_model(self)
        return model

    # ---- state ---------------------------------------------------------------------------------------------
    def _start(self) -> None:
        from spcotmhp.learning.learner_state import state_of_model

        if self.connectivity not in ("auto", "map", "hmm"):
            raise TeachingError(f"connectivity must be auto, map or hmm, got {self.connectivity!r}")
        check_count(self.max_K, "max_K", 1, MAX_PLACES, TeachingError)
        check_count(self.max_L, "max_L", 1, MAX_CONCEPTS, TeachingError)
        for name in ("lag", "rejuvenation", "split_merge"):  # resamples per event: its time
            check_count(getattr(self, name), name, 0, MAX_ITERATIONS, TeachingError)
        if not (1 <= self.K <= self.max_K and 1 <= self.L <= self.max_L and self.lag >= 0 and self.rejuvenation >= 0):
            raise TeachingError(
                f"need 1 <= K <= max_K, 1 <= L <= max_L, lag >= 0 and rejuvenation >= 0, got "
                f"K={self.K}, L={self.L}, max_K={self.max_K}, max_L={self.max_L}, lag={self.lag}, "
                f"rejuvenation={self.rejuvenation}"
            )
        if not (isinstance(self.answer_weight, (int, float)) and 0 < self.answer_weight < math.inf):
            raise TeachingError(f"answer_weight must be a positive number, got {self.answer_weight!r}")
        model = self.init_model
        given = self.hyper if model is None else model.hyper
        for term in ("place_concepts", "off_name"):
            if given is not None and getattr(given, term) is not None:
                raise TeachingError(f"{term} is a term of the batch learner only; the online learner has none")
        self.map_ = self.map if self.map is not None else (None if model is None else model.map)
        if model is not None:
            self.state_, self.vocabulary_ = state_of_model(model, self.replay, self.background_words)
            if not self.use_features and self.state_.F_ld is not None:
                self.state_.F_ld, self.state_.D = None, None
        else:
            hyper = self.hyper or Hyperparameters()
            self.state_ = CollapsedState(self.K, self.L, 0, None, hyper, self.replay, self.background_words)
            self.vocabulary_ = []
        if self.map_ is not None:
            self.state_.log_new_place = log_new_place_density(self.map_)
        self.word_index_ = {w: j for j, w in enumerate(self.vocabulary_)}
        self.update_times_: list[float] = []
        self.truncation_saturated_: list[str] = []
        self._grow_if_saturated()  # a supervised fit uses every component: room for a new place first

    def _check(self, event: TeachingEvent) -> None:
        """TeachingError for a position that is not finite, off the map, in unknown space or in a wall, or features
        that do not fit the model."""
        x, y = event.x, event.y
        if not (math.isfinite(x) and math.isfinite(y)):
            raise TeachingError(f"the teaching position ({x}, {y}) is not finite")
        occ = self.map_
        if occ is not None and self.check_map:
            cell = occ.world_to_cell(np.array([x, y]))
            if not occ.in_bounds(cell):
                raise TeachingError(f"the teaching position ({x:g}, {y:g}) is off the map")
            if occ.unknown[cell[0], cell[1]]:
                raise TeachingError(
                    f"the teaching position ({x:g}, {y:g}) is in unknown space (a cell the map has not seen); "
                    "teach where the robot stands"
                )
            if occ.occupied[cell[0], cell[1]]:
                raise TeachingError(
                    f"the teaching position ({x:g}, {y:g}) is in a wall (an occupied cell of the "
                    "map); teach where the robot stands"
                )
        self._check_language(event)
        f = event.features
        if f is not None and self.use_features:
            f = np.asarray(f, dtype=float)
            D = self.state_.D if self.state_.D is not None else (f.shape[0] if self.state_.E == 0 else None)
            if D is None or f.ndim != 1 or f.shape[0] != D or not (np.isfinite(f).all() and (f >= 0).all()):
                raise TeachingError(
                    "the image features must be non-negative finite numbers of the model's "
                    f"dimension ({self.state_.D or 'none: the model has no image features'})"
                )

    def _check_language(self, event: TeachingEvent) -> None:
        """TeachingError for an utterance in another language than the model's words (most of its vocabulary;
        ``language.text.is_japanese``: Japanese when a word holds kana or kanji): "ここは書斎です" on an English
        model would become new words, never a place's name, and English on a Japanese model the same."""

        def detect_language(text: str) -> str:
            return "ja" if is_japanese(text) else "en"

        known = [detect_language(w) for w in self.vocabulary_]
        if not known:
            return
        model = "ja" if 2 * known.count("ja") > len(known) else "en"
        said = detect_language(" ".join(event.words))
        if said != model:
            name = {"en": "English", "ja": "Japanese"}
            raise TeachingError(
                f"the utterance {' '.join(event.words)[:40]!r} is {name[said]} but the model's words are "
                f"{name[model]}; teach in {name[model]}"
                + (
                    ", e.g. 'this is the study'"
                    if model == "en"
                    else ", words separated by spaces: 'ここ は 書斎 です'"
                )
            )

    def _update(self, event: TeachingEvent, rng: np.random.Generator) -> None:
        st = self.state_
        new_words = [w for w in dict.fromkeys(event.words) if w not in self.word_index_]
        if new_words:
            for w in new_words:
                self.word_index_[w] = len(self.vocabulary_)
                self.vocabulary_.append(w)
            st.grow(V=len(self.vocabulary_))
        feats = None
        if event.features is not None and self.use_features:
            feats = np.asarray(event.features, dtype=float)
            if st.D is None:
                st.D, st.F_ld = feats.shape[0], np.zeros((st.L, feats.shape[0]))
            total = feats.sum()
            if self.feature_weight is not None and total > 0:
                feats = feats * (self.feature_weight / total)
        tokens = np.array([self.word_index_[w] for w in event.words])
        asked, x = event.answer, np.array([event.x, event.y])
        alone, weight = asked and self.answer_alone, self.answer_weight if asked else 1.0
        e = st.append(x, tokens, feats, rng, event.named, alone, weight)
        for j in range(max(0, e - self.lag), e):
            st.step(j, rng)
        older = max(0, e - self.lag)
        if older and self.rejuvenation:
            for j in rng.integers(older, size=self.rejuvenation):
                st.step(int(j), rng)
        self._split_merge(e, rng)
        if event.named:
            settle_name(st, e)
        if asked and self.after_answer is not None:
            self._grow_if_saturated()  # room for the move's new place
            st.words = self.vocabulary_
            self.after_answer(st, e, rng)
        self._grow_if_saturated()

    def _split_merge(self, e: int, rng: np.random.Generator) -> None:
        """``split_merge`` split-merge proposals (``online_split_merge``) of the kinds in turn (places, concepts,
        rooms). Each pairs an event a with an event b != a drawn at random; a is the new event with probability
        1/2 (a split of the place or concept it just joined, or a merge into it) and otherwise an event drawn at
        random (as random rejuvenation: merges made earlier in the stream). The pairs do not depend on the
        assignments, as the moves' acceptance needs."""
        E = self.state_.E
        if E < 2:
            return
        log_pi = None  # the state's log_target, once a move has computed it
        for j in range(self.split_merge):
            a = e if rng.random() < 0.5 else int(rng.integers(E))
            b = int(rng.integers(E - 1))
            b += b >= a
            _, log_pi = propose(self.state_, KINDS[j % len(KINDS)], a, b, rng, self.split_merge_events, log_pi)

    def _grow_if_saturated(self) -> None:
        """Double a truncation whose every component holds events; warn once when it cannot grow further."""
        st = self.state_
        for what, used, size, cap in (
            ("places", (st.n_k > 0).sum(), st.K, self.max_K),
            ("concepts", (st.n_l > 0).sum(), st.L, self.max_L),
        ):
            if used < size:
                continue
            if size < cap:
                st.grow(**{"K" if what == "places" else "L": min(2 * size, cap)})
            elif what not in self.truncation_saturated_:
                self.truncation_saturated_.append(what)
                warnings.warn(
                    f"all {size} {what[:-1]} components hold events (the weak-limit truncation is "
                    f"saturated at its maximum, so {what} may be merged): use a larger "
                    f"{'max_K' if what == 'places' else 'max_L'}",
                    TruncationWarning,
                    stacklevel=4,
                )
