"""Unsupervised learning of SpCoTMHP by Gibbs sampling (paper Section 3.2, Eq. 22).

One sweep, in the weak-limit truncation (K places, L concepts; Johnson and Willsky, 2013), each step given the
current value of everything else:

1. mu_k, Sigma_k ~ NIW posterior given the positions of the events in place k (Eqs. 5-6), and
   phi_l ~ Dir(gamma + place counts of concept l) (Eq. 11);
2. (with a trajectory) the places visited along it, labelled with the Gaussians just drawn and the place prior
   of the current counts (``hmm.trajectory_places``, below): a deterministic function of the state;
3. psi_k ~ Dir(omega + transition counts) (Eq. 7, weak-limit DP): the event sequence, its reversal (reverse
   replay), and the place changes of step 2;
4. the place sequence i_{1:E} jointly by forward filtering, backward sampling of the HMM over events with
   transitions psi and emissions N(x_e | mu_k, Sigma_k) phi[C_e, k] / sum_c phi[c, k] (Eqs. 3, 8-9);
5. every concept C_e from pi_l phi_l(i_e) theta_l(f_e) prod_b W_l(S_e,b) (Eqs. 14-17) with pi, phi, theta and W
   integrated out (direct assignment, Eqs. 10-13; see concepts.py, which also resamples the background-word
   switches).

One opt-in term departs from the paper (docs/learning-model-study.md, section 8): ``Hyperparameters.place_concepts``
= eta: step 1 also draws eta_i ~ Dir(eta / L + n_{i,.}), step 4's emission at k gains log eta_{k, C_e} (the FFBS stays
exact), step 5 integrates eta_i out (C_e = l gains log(eta / L + n_{l, i_e}), counts without e).  The log joint
carries it (posterior.py); the sampler after the first ``term_from`` of the sweeps (None: half).  Off, no random
number is drawn for it and every step is the paper's, bit for bit.

Research variants the model study measured and did not adopt (docs/experimental.md) plug in from
:mod:`spcotmhp.experimental` through ``variant`` (``init.SweepVariant``): a step-4 correction of the FFBS draw, a
step-5 term of the concept conditional, moves after step 5, terms of the log joint; None is the paper's sampler.

Steps 1-3 come before step 4 so that psi is drawn with the trajectory labelled by the very Gaussians that step 4
uses (in the first sweep, by Gaussians drawn from the initial assignment rather than all at the prior mode).

What kind of sampler this is: the steps are not the conditionals of one joint distribution.  Step 4 uses
Eq. 9's place term phi[C_e, k] / sum_c phi[c, k] (unigram rescaling, itself an approximation: a product of
experts whose normaliser is dropped), while step 5 uses the plain mixture term phi_l(i_e) of Eq. 17; reverse
replay and the trajectory place changes are pseudo-observations that enter psi's conditional only (and the
trajectory labels depend on mu and Sigma without feeding back into their conditional).  So the chain is a
Gibbs-style stochastic search over assignments, as in the authors' code, not an exact sampler of one
posterior; runs are compared through their final assignment (collapsed log joint or word-concept mutual
information, selection.py).  In GMM mode (``transitions="none"``: no psi, no rescaling) the same steps form a
partially collapsed Gibbs sampler: phi is drawn in step 1 before its one use in step 4 and integrated out in
step 5.

The exported model holds the posterior means of every parameter given the final sample's assignments.

Departures from the authors' code, each measured on albert-b (NMI and ARI of C and i with and without it:
docs/results.md, "Figures moved here from code docstrings"):
* Background words (concepts.py): the unigram-rescaling denominator of Eq. 17 cancels in the conditional of
  C_e, so it cannot keep function phrases ("こちらが ... になります") from forming concepts; a shared background
  word distribution does.
* Image features enter with a total weight of 1 per image (``feature_weight``).  The authors' p * 10 + 1 counts
  (about 375 per image, 365 of them the "+1") make the exact feature marginal prefer a single concept by about
  3,000 nats, so every run collapses to one concept.
* Initialisation (init.py): places start over-segmented by k-means++ (empty weak-limit components are drawn
  from the broad prior, m0 = 0 and kappa0 = 1e-3, and are practically never re-used, so places can merge but not
  split), not from uniformly random assignments.

Transition counts (reverse replay, the trajectory's place changes, ``trajectory_weight``): :mod:`spcotmhp.learning.
hmm`.

psi of the exported model (``connectivity``: "hmm", "walk", "map", "auto"; :func:`~spcotmhp.learning.connectivity.
apply_connectivity` says what each keeps): "hmm" is the posterior mean of the transition counts above (the paper's
psi); the HMM's psi is kept as ``model.psi_learned`` in every case.

When every place (or concept) component holds events, the truncation K (or L) may be too small for the home:
``fit`` then warns (``TruncationWarning``) and lists "places" / "concepts" in ``model.info["truncation_saturated"]``.

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
from spcotmhp.language.said_names import record_dataset_names
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.connectivity import SOURCES as CONNECTIVITY
from spcotmhp.learning.connectivity import apply_connectivity
from spcotmhp.learning.distributions import sample_categorical_log
from spcotmhp.learning.hmm import trajectory_places, transition_counts
from spcotmhp.learning.init import INITS, SweepVariant, VariantRun, initial_assignments, make_rng, seed_repr
from spcotmhp.learning.learner_state import from_batch
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.place_ffbs import sample_places
from spcotmhp.learning.posterior import (
    Priors,
    SufficientStats,
    log_joint,
    log_place_prior,
    mutual_information,
    posterior_mean_model,
    record_truncation,
)
from spcotmhp.limits import MAX_CONCEPTS, MAX_ITERATIONS, MAX_PLACES, check_count, check_event_places

TRANSITIONS = ("hmm", "none")
PLACE_CONCEPTS_FROM = 0.5  # place_concepts enters after half the sweeps (docs/learning-model-study.md, section 8)


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
        term_from: with ``hyper.place_concepts`` or a variant's term (module docstring), the fraction of the
            sweeps run on the paper's conditionals before the term enters steps 1, 4 and 5 (the log joint carries
            it throughout); None: the term's own (0.5 for place_concepts, ``VariantRun.term_from``).
        variant: a research variant (:class:`SweepVariant`, spcotmhp.experimental, docs/experimental.md), e.g.
            split-merge moves of the concepts or the off-name term; None: the paper's sampler.
        hyper: prior hyper-parameters (default: paper Section 5.1); its L and K are replaced by these L and K,
            and its alpha, gamma, omega follow them unless given (``Hyperparameters.resized``: 10 / L, 1 / K,
            10 / K, the paper's 0.5, 0.05, 0.5 at L = K = 20).
        seed, run: the random stream (run r of seed s; see ``make_rng``).

    Learned attributes: ``model_`` (SpatialConceptModel of posterior means given the final assignment),
    ``places_`` (E,) and ``concepts_`` (E,) the final i and C, ``log_joint_`` (collapsed log joint of the final
    assignment), ``mutual_information_`` (word-concept MI), ``log_joint_trace_`` (one value per sweep),
    ``fit_time_`` (seconds), ``fit_cpu_time_`` (CPU seconds of this process during ``fit``).
    """

    def __init__(
        self,
        L: int = 20,
        K: int = 20,
        iterations: int = 100,
        replay: bool = True,
        transitions: str = "hmm",
        use_trajectory: bool = True,
        use_features: bool = True,
        feature_weight: float | None = 1.0,
        background_words: bool = True,
        connectivity: str = "auto",
        init: str = "kmeans",
        trajectory_weight: float = 1.0,
        min_dwell: int = 3,
        term_from: float | None = None,
        variant: SweepVariant | None = None,
        hyper: Hyperparameters | None = None,
        seed: int | np.random.SeedSequence = 0,
        run: int | None = None,
    ) -> None:
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
        self.term_from = term_from
        self.variant = variant
        self.hyper = hyper
        self.seed = seed
        self.run = run

    def get_params(self) -> dict:
        """The constructor arguments (scikit-learn convention)."""
        names = inspect.signature(type(self).__init__).parameters
        return {name: getattr(self, name) for name in names if name != "self"}

    # ---- public API --------------------------------------------------------------------------------------
    def fit(self, dataset: Dataset, progress: Callable[[int], None] | None = None) -> SpCoTMHP:
        """Run the Gibbs sampler on ``dataset``; ``progress(sweep)`` is called after every sweep.

        BLAS runs on one thread meanwhile (``threadpoolctl``): the sampler's matrix products are small, and more
        BLAS threads spend CPU time spinning without making them faster, the more so with runs in parallel worker
        processes (selection.py; docs/results.md, "Learning speed"). One thread also gives the same sums whatever
        the number of cores."""
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):
            return self._fit(dataset, progress)

    def _fit(self, dataset: Dataset, progress: Callable[[int], None] | None) -> SpCoTMHP:
        self._check_settings(dataset.n_events)
        t0, c0 = time.perf_counter(), time.process_time()
        hyper = (self.hyper or Hyperparameters()).resized(self.L, self.K)
        obs = Observations.from_dataset(
            dataset,
            use_features=self.use_features,
            use_trajectory=self.use_trajectory,
            feature_weight=self.feature_weight,
        )
        rng = make_rng(self.seed, self.run)
        D = None if obs.features is None else obs.features.shape[1]
        priors = Priors.build(hyper, self.K, self.L, len(obs.vocabulary), D)
        sampler = CollapsedConceptSampler(obs.words, obs.features, self.background_words, rng)
        places, concepts = initial_assignments(obs, self.K, self.L, self.init, rng)
        run, start = self._start_variant(sampler, hyper, D is not None)
        extra = None if run is None else run.log_terms
        trace = []
        for sweep in range(self.iterations):
            stats = self._stats(obs, places, concepts, sampler)
            if sweep:
                trace.append(log_joint(priors, stats, self._event_transitions(places), extra))
            on = sweep >= start * self.iterations
            places, concepts = self._sweep(obs, priors, stats, hyper, sampler, run, places, concepts, rng, on)
            if progress is not None:
                progress(sweep + 1)
        stats = self._stats(obs, places, concepts, sampler)
        self.log_joint_ = log_joint(priors, stats, self._event_transitions(places), extra)
        trace.append(self.log_joint_)
        info = self._run_info(dataset, obs)
        model = posterior_mean_model(priors, stats, None, obs.vocabulary, hyper, info)
        model.map = dataset.map
        model.learner = from_batch(
            obs,
            places,
            concepts,
            sampler.t_ptr,
            sampler.t_word,
            sampler.z,
            self.K,
            self.L,
            hyper,
            self.replay,
            self.background_words,
        )
        self.model_ = model
        self.places_ = places
        self.concepts_ = concepts
        self.log_joint_trace_ = np.asarray(trace)
        self.mutual_information_ = mutual_information(model.pi, model.W)
        self.variant_run_ = run
        model.info.update(log_joint=self.log_joint_, mutual_information=self.mutual_information_)
        if run is not None:
            model.info.update(run.info())
        record_truncation(model, self.K, self.L)
        record_dataset_names(model, dataset.tokens, dataset.lang, places)  # taught names (said_names.py)
        self._export_psi(model, priors, dataset, obs, places)
        self.fit_time_ = time.perf_counter() - t0
        self.fit_cpu_time_ = time.process_time() - c0
        return self

    def _start_variant(
        self, sampler: CollapsedConceptSampler, hyper: Hyperparameters, features: bool
    ) -> tuple[VariantRun | None, float]:
        """The hooks of ``variant`` for this fit (None: the paper's sampler, which refuses a variant's term) and the
        fraction of the sweeps before an opt-in term enters the sampler (``term_from``, else the term's own)."""
        if self.variant is None and hyper.off_name is not None:
            raise ModelError(
                "hyper.off_name is a research variant's term: fit with variant=spcotmhp.experimental.OffName() "
                "(or spcotmhp.experimental.research_learner; docs/experimental.md)"
            )
        run = None if self.variant is None else self.variant.start(sampler, hyper, self.K, self.L, features)
        own = None if run is None else run.term_from
        start = self.term_from if self.term_from is not None else own if own is not None else PLACE_CONCEPTS_FROM
        return run, start

    def _run_info(self, dataset: Dataset, obs: Observations) -> dict:
        """The settings of this run and what the data held, for ``model.info``."""
        return {
            "method": "SpCoTMHP" if self.transitions == "hmm" else "SpCoSLAM (GMM)",
            "dataset": dataset.name,
            "seed": seed_repr(self.seed),
            "run": self.run,
            "iterations": self.iterations,
            "reverse_replay": bool(self.replay),
            "transitions": self.transitions,
            "background_words": bool(self.background_words),
            "split_merge": False,  # spcotmhp.experimental.split_merge's moves; a variant's info() says when on
            "trajectory": obs.trajectory is not None,
            "features": obs.features is not None,
            "feature_weight": self.feature_weight,
        }

    def _export_psi(
        self, model: SpatialConceptModel, priors: Priors, dataset: Dataset, obs: Observations, places: np.ndarray
    ) -> None:
        """psi of the exported model: with transitions, the posterior mean of the counts labelled with the
        exported means (kept as ``psi_learned``), then ``connectivity``'s choice; without, uniform."""
        if self.transitions != "hmm":
            model.info["psi_from"] = "uniform (no transitions)"
            return
        counts = self._transition_counts(obs, places, model.mu, model.Sigma, model.log_place_prior())
        model.psi = priors.psi.posterior_mean(counts)
        model.psi_learned = model.psi.copy()
        seen = dataset if obs.trajectory is not None else replace(dataset, trajectory=None, event_steps=None)
        apply_connectivity(model, seen, self.connectivity, places)

    # ---- one sweep ---------------------------------------------------------------------------------------
    def _sweep(
        self,
        obs: Observations,
        priors: Priors,
        stats: SufficientStats,
        hyper: Hyperparameters,
        sampler: CollapsedConceptSampler,
        run: VariantRun | None,
        places: np.ndarray,
        concepts: np.ndarray,
        rng: np.random.Generator,
        term: bool = True,
    ) -> tuple[np.ndarray, np.ndarray]:
        """One Gibbs sweep, steps 1-5 of the module docstring, from the current assignments and their ``stats``:
        the parameters in ``priors`` are redrawn in place; returns the new places and concepts.  ``term``: whether
        the opt-in term (place_concepts, or the variant's step-4 and step-5 hooks) enters this sweep; ``run``: a
        research variant's hooks (None: the paper's sweep)."""
        h, place_concepts = hyper, priors.place_concepts if term else None
        priors.gauss.resample(stats.gauss, rng)  # step 1
        priors.phi.resample(stats.place_given_concept, rng)
        if place_concepts is not None:  # eta_i ~ Dir(eta / L + n_{i,.}), opt-in (module docstring)
            place_concepts.resample(stats.place_given_concept.T, rng)
        if self.transitions == "hmm":  # steps 2 and 3
            counts = self._transition_counts(
                obs, places, priors.gauss.mu, priors.gauss.Sigma, log_place_prior(priors, stats)
            )
            priors.psi.resample(counts, rng)
        log_eta = None if place_concepts is None else place_concepts.log_probs
        proposal = self._sample_places(priors, obs, concepts, rng, log_eta)  # step 4
        on = run if term else None
        places = proposal if on is None else on.places(places, proposal, concepts, rng)
        eta = None if place_concepts is None else h.place_concepts  # step 5
        extra = None if on is None else on.concept_term
        concepts = sampler.sweep(concepts, places, self.L, self.K, h.alpha, h.gamma, h.beta, h.chi, rng, eta, extra)
        if run is not None:  # a variant's moves after step 5
            concepts = run.concepts(concepts, places, rng)
        return places, concepts

    def _check_settings(self, n_events: int) -> None:
        """ModelError for a setting out of range, or sizes past spcotmhp/limits.py (before any allocation)."""
        for name, value, allowed in (
            ("transitions", self.transitions, TRANSITIONS),
            ("connectivity", self.connectivity, CONNECTIVITY),
            ("init", self.init, INITS),
        ):
            if value not in allowed:
                raise ModelError(f"{name} must be one of {allowed}, got {value!r}")
        start = self.term_from
        if start is not None and (
            isinstance(start, bool) or not isinstance(start, (int, float)) or not 0 <= start <= 1
        ):
            raise ModelError(f"term_from must be a fraction in [0, 1] or None, got {self.term_from!r}")
        check_count(self.K, "K (the place truncation)", 1, MAX_PLACES, ModelError)
        check_count(self.L, "L (the concept truncation)", 1, MAX_CONCEPTS, ModelError)
        check_count(self.iterations, "iterations", 1, MAX_ITERATIONS, ModelError)
        check_event_places(n_events, self.K, ModelError)

    def _stats(
        self, obs: Observations, places: np.ndarray, concepts: np.ndarray, sampler: CollapsedConceptSampler
    ) -> SufficientStats:
        if not self.background_words:
            return SufficientStats.from_assignments(obs, places, concepts, self.K, self.L)
        return SufficientStats.from_assignments(
            obs, places, concepts, self.K, self.L, sampler.concept_words(), sampler.background_words()
        )

    def _event_transitions(self, places: np.ndarray) -> np.ndarray | None:
        """Forward transition counts of the event sequence (the generative term of psi in the log joint)."""
        return None if self.transitions == "none" else transition_counts(places, self.K, False)

    def _transition_counts(
        self, obs: Observations, places: np.ndarray, mu: np.ndarray, Sigma: np.ndarray, log_prior: np.ndarray
    ) -> np.ndarray:
        """Counts behind psi: the event sequence (+ reversed), plus the place changes along the trajectory
        labelled with the Gaussians (mu, Sigma) and the place prior ``log_prior`` (module docstring)."""
        counts = transition_counts(places, self.K, self.replay)
        if obs.trajectory is not None:
            seq = trajectory_places(obs.trajectory, mu, Sigma, log_prior, self.min_dwell)
            counts += self.trajectory_weight * transition_counts(seq, self.K, self.replay)
        return counts

    def _sample_places(
        self,
        priors: Priors,
        obs: Observations,
        concepts: np.ndarray,
        rng: np.random.Generator,
        log_eta: np.ndarray | None = None,
    ) -> np.ndarray:
        """i_{1:E} given C, x and the parameters (Eq. 9; FFBS, or independent draws in GMM mode); ``log_eta``
        (K, L) adds log eta[i_e, C_e] (``Hyperparameters.place_concepts``)."""
        log_phi = priors.phi.log_probs
        if self.transitions == "none":
            extra = 0.0 if log_eta is None else log_eta.T[concepts]
            return sample_categorical_log(rng, priors.gauss.log_likelihood(obs.X) + log_phi[concepts] + extra)
        log_init = np.full(self.K, -np.log(self.K))  # FFBS with the unigram-rescaled emissions of Eq. 9
        return sample_places(
            obs.X, concepts, priors.gauss.mu, priors.gauss.Sigma, log_phi, priors.psi.log_probs, log_init, rng, log_eta
        )
