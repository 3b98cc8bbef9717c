"""Unsupervised learning of SpCoTMHP by blocked Gibbs sampling (paper Section 3.2, Eq. 22).

One sweep, in the weak-limit truncation (K places, L concepts; Johnson and Willsky, 2013):

1. the place-level parameters from their conjugate posteriors given the assignments: mu_k, Sigma_k ~ NIW
   posterior (Eqs. 5-6); psi_k ~ Dir(omega + transition counts) (Eq. 7, weak-limit DP);
   phi_l ~ Dir(gamma + place counts of concept l) (Eq. 11);
2. the place sequence i_{1:E} jointly by forward filtering, backward sampling of the HMM over events with
   transitions psi and emissions N(x_e | mu_k, Sigma_k) phi[C_e, k] / sum_c phi[c, k] (Eqs. 3, 8-9);
3. every concept C_e from pi_l phi_l(i_e) theta_l(f_e) prod_b W_l(S_e,b) (Eqs. 14-17) with pi, phi, theta and W
   integrated out (direct assignment, Eqs. 10-13; see concepts.py, which also resamples the background-word
   switches).  phi is re-drawn in step 1 before its next use, so collapsing it here is a valid partially
   collapsed Gibbs sampler.

The exported model holds the posterior means of every parameter given the final sample's assignments.

Departures from the authors' code, each measured on albert-b (ten runs, SpCoTMHP with replay, means of
NMI C / NMI i / ARI C / ARI i): the defaults give 0.92 / 0.95 / 0.81 / 0.86.
* Background words (concepts.py): the unigram-rescaling denominator of Eq. 17 cancels in the conditional of
  C_e, so it cannot keep function phrases ("こちらが ... になります") from forming concepts; a shared background
  word distribution does.  Without it: 0.73 / 0.84 / 0.42 / 0.57.
* Image features enter with a total weight of 1 per image (``feature_weight``).  The authors' p * 10 + 1 counts
  (about 375 per image, 365 of them the "+1") make the exact feature marginal prefer a single concept by about
  3,000 nats: every run collapses to one concept (0.00 / 0.60 / 0.00 / 0.27).  Without features: 0.91 / 0.93 /
  0.79 / 0.82.
* Initialisation (init.py): places start over-segmented by k-means++ (empty weak-limit components are drawn
  from the broad prior, m0 = 0 and kappa0 = 1e-3, and are practically never re-used, so places can merge but not
  split); from uniformly random assignments: 0.85 / 0.87 / 0.65 / 0.66.

Transition counts come from the event sequence, plus (reverse replay, Section 3.2) the reversed sequence,
plus (when the dataset has a trajectory) the places visited along the trajectory: each pose is given its most
probable place under the current parameters (N(x_t | mu_k, Sigma_k) times the place's share of events, over the
places holding events), runs shorter than ``min_dwell`` poses are dropped as boundary flicker, consecutive
repeats collapse, and every remaining place change a -> b counts ``trajectory_weight`` (and b -> a as well under
reverse replay).  Each traversal of a doorway thus counts like one observed event transition.

psi of the exported model (``connectivity``, see connectivity.py): "hmm" keeps the posterior mean of the
transition counts above (the paper's psi); "walk" and "map" use psi[k] = mean of Dir(0.1 + A[k]) (the form of
the paper's Experiment I) for the adjacency A of the places visited one after the other along the trajectory,
or implied by the map's free space; "auto" is "walk" with a trajectory and "map" without (the order of the
utterances alone, e.g. fifteen per room taught room after room, says little about which rooms touch).  The
HMM psi's self-transitions (many utterances per room) outweigh the few doorway crossings, so under the planner's
edge rule (psi_ab + psi_ba) / 2 >= 1 / K it would show almost no edges; the adjacency form does not.

``transitions="none"`` is the SpCoSLAM baseline (a Gaussian mixture, no psi): the place term is then
Mult(i_e | phi_{C_e}) itself, without unigram rescaling, and the exported psi is uniform.
"""

from __future__ import annotations

import inspect
import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import ModelError
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.connectivity import SOURCES as CONNECTIVITY
from spcotmhp.learning.connectivity import apply_connectivity
from spcotmhp.learning.distributions import GaussianStats, logsumexp, sample_categorical_log
from spcotmhp.learning.hmm import ffbs, transition_counts, visited_places
from spcotmhp.learning.init import INITS, initial_assignments
from spcotmhp.learning.model import Hyperparameters, log_gaussian
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.posterior import (
    Priors,
    SufficientStats,
    log_joint,
    mutual_information,
    posterior_mean_model,
)

TRANSITIONS = ("hmm", "none")


def make_rng(seed: int | np.random.SeedSequence, run: int | None = None) -> np.random.Generator:
    """The generator of one run: run r of seed s uses the r-th child of SeedSequence(s) (what
    ``SeedSequence(s).spawn`` would give), independent of the others; ``run=None`` uses the seed itself.
    Raises ModelError for a seed or run that is not a non-negative integer."""
    if not isinstance(seed, np.random.SeedSequence) and not _is_count(seed):
        raise ModelError(f"seed must be a non-negative integer (or a numpy SeedSequence), got {seed!r}")
    if run is not None and not _is_count(run):
        raise ModelError(f"run must be a non-negative integer or None, got {run!r}")
    ss = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(int(seed))
    if run is not None:
        ss = np.random.SeedSequence(ss.entropy, spawn_key=tuple(ss.spawn_key) + (int(run),))
    return np.random.default_rng(ss)


class SpCoTMHP:
    """The SpCoTMHP learner (scikit-learn style: settings in ``__init__``, ``fit`` returns self).

    Args:
        L, K: truncation levels of the concept and place Dirichlet processes (paper: 20, 20).
        iterations: Gibbs sweeps (paper: 100).
        replay: count the reversed event sequence too (reverse replay, Section 3.2).
        transitions: "hmm" (SpCoTMHP) or "none" (the SpCoSLAM Gaussian-mixture baseline, same code).
        use_trajectory: learn transitions from the dataset's trajectory as well, when it has one.
        use_features: use the image features f_e when the dataset has them; ``feature_weight`` is the total
            count of one image (None: the authors' p * 10 + 1 counts; see ``Observations.from_dataset``).
        background_words: shared background word distribution for function words (concepts.py); False is the
            paper's plain bag of words.
        connectivity: psi of the exported model, "auto", "hmm", "walk" or "map" (module docstring).
        init: initial assignment, "kmeans" (over-segmented places, random concepts), "keyword" or "random"
            (init.py).
        trajectory_weight, min_dwell: weight of one place change along the trajectory, and the shortest stay
            (in poses) that counts as a visit.
        hyper: prior hyper-parameters (default: paper Section 5.1; its L and K are replaced by these L and K).
        seed, run: the random stream (run r of seed s; see ``make_rng``).

    Learned attributes: ``model_`` (SpatialConceptModel of posterior means given the final assignment),
    ``places_`` (E,) and ``concepts_`` (E,) the final i and C, ``log_joint_`` (collapsed log joint of the final
    assignment), ``mutual_information_`` (word-concept MI), ``log_joint_trace_`` (one value per sweep),
    ``fit_time_`` (seconds).
    """

    def __init__(self, L: int = 20, K: int = 20, iterations: int = 100, replay: bool = True,
                 transitions: str = "hmm", use_trajectory: bool = True, use_features: bool = True,
                 feature_weight: float | None = 1.0, background_words: bool = True, connectivity: str = "auto",
                 init: str = "kmeans", trajectory_weight: float = 1.0, min_dwell: int = 3,
                 hyper: Hyperparameters | None = None, seed: int | np.random.SeedSequence = 0,
                 run: int | None = None) -> None:
        self.L = L
        self.K = K
        self.iterations = iterations
        self.replay = replay
        self.transitions = transitions
        self.use_trajectory = use_trajectory
        self.use_features = use_features
        self.feature_weight = feature_weight
        self.background_words = background_words
        self.connectivity = connectivity
        self.init = init
        self.trajectory_weight = trajectory_weight
        self.min_dwell = min_dwell
        self.hyper = hyper
        self.seed = seed
        self.run = run

    def get_params(self) -> dict:
        """The constructor arguments (scikit-learn convention)."""
        names = inspect.signature(type(self).__init__).parameters
        return {name: getattr(self, name) for name in names if name != "self"}

    # ---- public API --------------------------------------------------------------------------------------
    def fit(self, dataset: Dataset, progress: Callable[[int], None] | None = None) -> SpCoTMHP:
        """Run the Gibbs sampler on ``dataset``; ``progress(sweep)`` is called after every sweep."""
        self._check_settings()
        t0 = time.perf_counter()
        hyper = replace(self.hyper or Hyperparameters(), L=self.L, K=self.K)
        obs = Observations.from_dataset(dataset, use_features=self.use_features,
                                        use_trajectory=self.use_trajectory, feature_weight=self.feature_weight)
        rng = make_rng(self.seed, self.run)
        D = None if obs.features is None else obs.features.shape[1]
        priors = Priors.build(hyper, self.K, self.L, len(obs.vocabulary), D)
        sampler = CollapsedConceptSampler(obs.words, obs.features, self.background_words, rng)
        places, concepts = initial_assignments(obs, self.K, self.L, self.init, rng)
        trace = []
        for sweep in range(self.iterations):
            stats = self._stats(obs, places, concepts, sampler)
            if sweep:
                trace.append(log_joint(priors, stats, self._event_transitions(places)))
            self._resample_parameters(priors, stats, self._transition_counts(priors, obs, places, stats), rng)
            places = self._sample_places(priors, obs, concepts, rng)
            concepts = sampler.sweep(concepts, places, self.L, self.K, hyper.alpha, hyper.gamma, hyper.beta,
                                     hyper.chi, rng)
            if progress is not None:
                progress(sweep + 1)
        stats = self._stats(obs, places, concepts, sampler)
        self.log_joint_ = log_joint(priors, stats, self._event_transitions(places))
        trace.append(self.log_joint_)
        info = {"method": "SpCoTMHP" if self.transitions == "hmm" else "SpCoSLAM (GMM)",
                "dataset": dataset.name, "seed": _seed_repr(self.seed), "run": self.run,
                "iterations": self.iterations, "reverse_replay": bool(self.replay),
                "transitions": self.transitions, "background_words": bool(self.background_words),
                "trajectory": obs.trajectory is not None, "features": obs.features is not None,
                "feature_weight": self.feature_weight}
        self.model_ = posterior_mean_model(priors, stats, self._transition_counts(priors, obs, places, stats),
                                           obs.vocabulary, hyper, info)
        self.model_.map = dataset.map
        self.places_ = places
        self.concepts_ = concepts
        self.log_joint_trace_ = np.asarray(trace)
        self.mutual_information_ = mutual_information(self.model_.pi, self.model_.W)
        self.model_.info.update(log_joint=self.log_joint_, mutual_information=self.mutual_information_)
        if self.transitions == "hmm":
            seen = dataset if obs.trajectory is not None else replace(dataset, trajectory=None, event_steps=None)
            apply_connectivity(self.model_, seen, self.connectivity, places)
        else:
            self.model_.info["psi_from"] = "uniform (no transitions)"
        self.fit_time_ = time.perf_counter() - t0
        return self

    # ---- one sweep ---------------------------------------------------------------------------------------
    def _check_settings(self) -> None:
        for name, value, allowed in (("transitions", self.transitions, TRANSITIONS),
                                     ("connectivity", self.connectivity, CONNECTIVITY),
                                     ("init", self.init, INITS)):
            if value not in allowed:
                raise ModelError(f"{name} must be one of {allowed}, got {value!r}")
        if self.K < 1 or self.L < 1 or self.iterations < 1:
            raise ModelError(f"K, L and iterations must be >= 1, got K={self.K}, L={self.L}, "
                             f"iterations={self.iterations}")

    def _stats(self, obs: Observations, places: np.ndarray, concepts: np.ndarray,
               sampler: CollapsedConceptSampler) -> SufficientStats:
        if not self.background_words:
            return SufficientStats.from_assignments(obs, places, concepts, self.K, self.L)
        return SufficientStats.from_assignments(obs, places, concepts, self.K, self.L, sampler.concept_words(),
                                                sampler.background_words())

    def _event_transitions(self, places: np.ndarray) -> np.ndarray | None:
        """Forward transition counts of the event sequence (the generative term of psi in the log joint)."""
        return None if self.transitions == "none" else transition_counts(places, self.K, False)

    def _transition_counts(self, priors: Priors, obs: Observations, places: np.ndarray,
                           stats: SufficientStats) -> np.ndarray | None:
        """Counts behind psi: event sequence (+ reversed) (+ trajectory place changes); None in GMM mode."""
        if self.transitions == "none":
            return None
        counts = transition_counts(places, self.K, self.replay)
        if obs.trajectory is not None:
            seq = self.trajectory_places(priors, obs.trajectory, stats.gauss)
            counts += self.trajectory_weight * transition_counts(seq, self.K, self.replay)
        return counts

    def trajectory_places(self, priors: Priors, trajectory: np.ndarray, gauss: GaussianStats) -> np.ndarray:
        """The places visited along ``trajectory`` under the current place parameters (module docstring)."""
        active = np.flatnonzero(gauss.n > 0)
        lp = (log_gaussian(trajectory, priors.gauss.mu[active], priors.gauss.Sigma[active])
              + np.log(gauss.n[active]))
        return active[visited_places(lp, self.min_dwell)]

    def _resample_parameters(self, priors: Priors, stats: SufficientStats, transitions: np.ndarray | None,
                             rng: np.random.Generator) -> None:
        priors.gauss.resample(stats.gauss, rng)
        priors.phi.resample(stats.place_given_concept, rng)
        if transitions is not None:
            priors.psi.resample(transitions, rng)

    def _sample_places(self, priors: Priors, obs: Observations, concepts: np.ndarray,
                       rng: np.random.Generator) -> np.ndarray:
        """i_{1:E} given C, x and the parameters (Eq. 9; FFBS, or independent draws in GMM mode)."""
        log_phi = priors.phi.log_probs
        log_emit = priors.gauss.log_likelihood(obs.X) + log_phi[concepts]
        if self.transitions == "none":
            return sample_categorical_log(rng, log_emit)
        log_emit = log_emit - logsumexp(log_phi, axis=0)           # unigram rescaling, Eq. 9
        log_init = np.full(self.K, -np.log(self.K))
        return ffbs(log_emit, priors.psi.log_probs, log_init, rng)


def _is_count(value: object) -> bool:
    """A non-negative integer (numpy integers included, booleans not)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= 0


def _seed_repr(seed: int | np.random.SeedSequence) -> int | str:
    return int(seed) if not isinstance(seed, np.random.SeedSequence) else str(seed.entropy)
