"""The learned parameters Theta' = {mu, Sigma, psi, pi, phi, theta, W} and the model terms built from them.

Every term is returned in log space. Equation numbers refer to Taniguchi, Ito and Taniguchi (2024).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np
from numba import njit

from spcotmhp.errors import ModelError
from spcotmhp.learning.model_values import HYPER_RANGES, check_hyper, check_model, check_truncation, in_range, refuse
from spcotmhp.logspace import log_gaussian, logsumexp, logsumexp_vector
from spcotmhp.metric.costmap import default_costmap
from spcotmhp.metric.maps import OccupancyMap

# Total concentrations of the weak-limit Dirichlet priors (the authors' code: alpha = 10 / L, gamma = 1 / K,
# omega = 10 / K, i.e. the weak-limit approximation Dir(a0 / M, ..., a0 / M) of a DP(a0) over M components).
ALPHA_TOTAL = 10.0
GAMMA_TOTAL = 1.0
OMEGA_TOTAL = 10.0
SCALED_PRIORS = ("alpha", "gamma", "omega")
# The paper's place prior: Sigma_k ~ IW(V0 = 2 I, nu0 = 3), whose mean V0 / (nu0 - 3) does not exist in 2-D.
PAPER_NU0 = 3.0
PAPER_V0 = ((2.0, 0.0), (0.0, 2.0))
# ``place_size``'s prior: nu0 - 3 = 2 pseudo-observations of the stated spread, so that V0 = 2 s^2 I (the paper's
# V0 at s = 1 m) and E[Sigma] = V0 / (nu0 - 3) = s^2 I.
PLACE_SIZE_NU0 = 5.0
DERIVED = float("nan")  # the default of alpha, gamma and omega: derived from the truncation in __post_init__


def _unset(value: float | None) -> bool:
    """A scaled prior left to be derived: the default ``DERIVED`` (NaN) or None."""
    return value is None or value != value


@dataclass
class Hyperparameters:
    """Prior hyper-parameters (paper Section 5.1; reference-implementation notes for Experiment II).

    alpha: pi ~ DP(alpha) (weak limit: Dir(alpha/L... given per component)); gamma: phi_l ~ DP(gamma);
    beta: W_l ~ Dir(beta); chi: theta_l ~ Dir(chi); omega: psi_k ~ DP(omega); NIW (m0, kappa0, V0, nu0).
    The values are per-component Dirichlet parameters as the authors used them.

    place_size (metres, default None: the paper's nu0 = 3, V0 = 2 I, under which E[Sigma] = V0 / (nu0 - 3) is
    infinite in 2-D): the expected standard deviation s of one place's teaching positions along each axis.  Given,
    it sets nu0 = 5 and V0 = 2 s^2 I, so that E[Sigma_k] = s^2 I (Eq. 6 with a finite prior mean; the prior
    weighs like two observations of that spread).  nu0 and V0 must then be left at the paper's values (or equal
    the derived ones, as a saved model gives them back).  A research setting (docs/experimental.md), kept here
    because a model folder records it.

    place_concepts (default None: off, the paper's model): eta, the total concentration of an opt-in prior that a
    place holds one name, a DEPARTURE from the paper.  Each place i draws its own concept distribution
    eta_i ~ Dir(eta / L, ..., eta / L), and the concept of an event is scored by eta_{i_e, C_e} besides Eq. 17's
    pi phi theta W: the joint of Eqs. 5-17 gains the factor prod_e eta_{i_e, C_e}, i.e. prod_i DirMult(n_{i,.} |
    eta / L) with the eta_i integrated out (n_{i,l}: the events at place i with concept l), a product of experts
    on the pair (i, C) beside phi (gibbs.py, posterior.py).  Batch learner only; the online learner refuses it.

    off_name (default None: off, the paper's model): lambda, the cost in nats of every event whose concept is not
    its place's majority concept, another opt-in DEPARTURE from the paper: the joint gains the energy factor
    log g(i, C) = -lambda sum_i (n_i - max_l n_{i,l}), which charges a second name in a place without charging
    a place for its first.  A research variant (spcotmhp/experimental/off_name.py; the batch learner fits with it
    given ``variant=OffName()`` and refuses it otherwise); not combined with place_concepts.

    alpha, gamma and omega left unset (``DERIVED``; None is accepted too) follow the truncation: alpha = 10 / L,
    gamma = 1 / K, omega = 10 / K (the authors' code), which gives the paper's 0.5, 0.05 and 0.5 at L = K = 20
    and keeps the total prior mass of each Dirichlet process fixed when --max-places / --max-concepts change.
    ``resized(L, K)`` re-derives the ones that were derived (``dataclasses.replace`` would keep their old values);
    given values are kept.

    Every value must lie in its documented range (``model_values.HYPER_RANGES``, the module docstring of
    :mod:`spcotmhp.learning.model_values`: L, K in 1..10,000, concentrations and kappa0 in [1e-6, 1e6], nu0 in
    (1, 1e6], place_size in [1e-3, 1e5] m, off_name in (0, 1e6]); else a one-line ModelValueError (a ValueError).
    """

    L: int = 20
    K: int = 20
    alpha: float = DERIVED
    gamma: float = DERIVED
    beta: float = 0.1
    chi: float = 1.0
    omega: float = DERIVED
    m0: tuple[float, float] = (0.0, 0.0)
    kappa0: float = 1e-3
    V0: tuple[tuple[float, float], tuple[float, float]] = PAPER_V0
    nu0: float = PAPER_NU0
    place_size: float | None = None
    place_concepts: float | None = None
    off_name: float | None = None

    def __post_init__(self) -> None:
        check_truncation(self)
        if self.place_concepts is not None and self.off_name is not None:
            raise refuse(
                "hyper.off_name", "place_concepts and off_name are two answers to one question: set one or the other"
            )
        if self.place_size is not None:
            self.nu0, self.V0 = place_size_prior(self.place_size, self.nu0, self.V0)
        self._derived = tuple(name for name in SCALED_PRIORS if _unset(getattr(self, name)))
        if _unset(self.alpha):
            self.alpha = ALPHA_TOTAL / self.L
        if _unset(self.gamma):
            self.gamma = GAMMA_TOTAL / self.K
        if _unset(self.omega):
            self.omega = OMEGA_TOTAL / self.K
        check_hyper(self)  # every value in its documented range (model_values.py)

    def resized(self, L: int, K: int) -> Hyperparameters:
        """These priors for truncation levels L and K: alpha, gamma, omega that were derived from the old L and
        K are derived again, values given explicitly are kept."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(L=L, K=K, **{name: DERIVED for name in getattr(self, "_derived", ())})
        return Hyperparameters(**values)


def place_size_prior(
    size: float, nu0: float, V0: tuple[tuple[float, float], tuple[float, float]]
) -> tuple[float, tuple[tuple[float, float], tuple[float, float]]]:
    """(nu0, V0) of the inverse-Wishart place prior whose mean is size^2 I (``Hyperparameters.place_size``);
    ModelValueError (a ValueError) for a size outside its range (``model_values.HYPER_RANGES``: 1e-3 to 1e5 m),
    or when ``nu0`` / ``V0`` were given other values.

    >>> place_size_prior(1.5, 3.0, ((2.0, 0.0), (0.0, 2.0)))
    (5.0, ((4.5, 0.0), (0.0, 4.5)))
    """
    v = (PLACE_SIZE_NU0 - 3.0) * in_range("place_size", size, HYPER_RANGES["place_size"], "hyper.place_size") ** 2
    derived = (PLACE_SIZE_NU0, ((v, 0.0), (0.0, v)))
    try:
        given: object = (float(nu0), tuple(tuple(float(x) for x in row) for row in V0))
    except (TypeError, ValueError, OverflowError):
        given = None  # not numbers: neither the paper's values nor the derived ones
    if given not in ((PAPER_NU0, PAPER_V0), derived):
        raise refuse(
            "hyper.place_size", f"place_size sets nu0 and V0 (to {derived[0]:g} and {v:g} I): give one or the other"
        )
    return derived


@dataclass
class SpatialConceptModel:
    """Learned spatial concepts and places.

    Attributes:
        mu: (K, 2) place means (topological nodes).  Sigma: (K, 2, 2) place covariances.
        psi: (K, K) place transitions, psi[a, b] = p(i_e = b | i_{e-1} = a) (rows sum to 1).
        pi: (L,) concept weights.  phi: (L, K) place given concept.  W: (L, V) word given concept.
        theta: (L, D) image feature distribution given concept, or None when no features were used.
        vocabulary: the V words, index = column of W.
        active_places / active_concepts: boolean masks of the components that hold data (weak-limit truncation
            leaves the others at prior draws; planning ignores them).
        hyper: the hyper-parameters used.
        map: the occupancy map the model was learned on (kept with the model for planning).
        costmap: cost map settings (inscribed_radius, inflation_radius, cost_scaling_factor and, for a footprint,
            circumscribed_radius): the robot's body (:mod:`spcotmhp.metric.body`).
        info: free-form provenance (dataset, seed, iterations, selection criterion, ...), JSON-serialisable.
        psi_learned: (K, K) the transitions the HMM learned (posterior mean), kept when ``psi`` was replaced by
            an adjacency-based psi for planning (connectivity "walk" / "map"); None when nothing was learned.
        learner: the state an online learner continues from (the events, their assignments and the counts;
            :mod:`spcotmhp.learning.learner_state`), or None.
        folder: the model folder it was loaded from (set by ``load_model``), where a planner looks for the saved
            planning graph (:mod:`spcotmhp.planning.graph_store`); None for a model made in memory.
    """

    mu: np.ndarray
    Sigma: np.ndarray
    psi: np.ndarray
    pi: np.ndarray
    phi: np.ndarray
    W: np.ndarray
    vocabulary: list[str]
    theta: np.ndarray | None = None
    active_places: np.ndarray = field(default_factory=lambda: np.ones(0, dtype=bool))  # all K active when unset
    active_concepts: np.ndarray = field(default_factory=lambda: np.ones(0, dtype=bool))  # all L active when unset
    hyper: Hyperparameters = field(default_factory=Hyperparameters)
    map: OccupancyMap | None = None
    costmap: dict = field(default_factory=default_costmap)  # the default body (metric.costmap)
    info: dict = field(default_factory=dict)
    psi_learned: np.ndarray | None = None
    learner: dict | None = field(default=None, repr=False, compare=False)
    folder: Path | None = field(default=None, repr=False, compare=False)  # the folder it was loaded from

    def __post_init__(self) -> None:
        if self.active_places is None or np.size(self.active_places) == 0:
            self.active_places = np.ones(np.shape(self.mu)[0] if np.ndim(self.mu) else 0, dtype=bool)
        if self.active_concepts is None or np.size(self.active_concepts) == 0:
            self.active_concepts = np.ones(np.shape(self.pi)[0] if np.ndim(self.pi) else 0, dtype=bool)
        check_model(self)  # every value in the range planning can use (model_values.py): ModelValueError

    def require_map(self) -> OccupancyMap:
        """The occupancy map the model was learned on; a one-line ModelError when the model has none."""
        if self.map is None:
            raise ModelError("the model has no map; planning needs the occupancy map it was learned on")
        return self.map

    # ---- sizes -------------------------------------------------------------------------------------------
    @property
    def K(self) -> int:
        return int(self.mu.shape[0])

    @property
    def L(self) -> int:
        return int(self.pi.shape[0])

    @property
    def word_index(self) -> dict[str, int]:
        return {w: i for i, w in enumerate(self.vocabulary)}

    # ---- metric / topological terms ----------------------------------------------------------------------
    def log_place_density(self, x: np.ndarray) -> np.ndarray:
        """log N(x | mu_k, Sigma_k) for every place k: x (..., 2) -> (..., K) (Eqs. 3, 9, 26)."""
        return log_gaussian(np.asarray(x, dtype=float), self.mu, self.Sigma)

    def log_place_prior(self) -> np.ndarray:
        """log p(i = k) = log sum_l pi_l phi_l(k), the marginal place prior (Eqs. 9, 14); -inf on inactive places."""
        lp = logsumexp(log_concept_place(self.pi, self.phi), axis=0)
        return np.where(self.active_places, lp, -np.inf)

    def place_posterior(self, x: np.ndarray) -> np.ndarray:
        """p(i_0 = k | x_0) proportional to N(x_0 | mu_k, Sigma_k) p(k), over active places; x (..., 2) -> (..., K)."""
        lp = self.log_place_density(x) + self.log_place_prior()
        return np.exp(lp - logsumexp(lp, axis=-1, keepdims=True))

    def log_psi(self) -> np.ndarray:
        """log psi[a, b] = log Mult(i_e = b | psi_a) (Eq. 9, first factor)."""
        with np.errstate(divide="ignore"):
            return np.log(self.psi)

    def log_unigram_rescaling(self) -> np.ndarray:
        """log sum_c Mult(i | phi_c), the denominator of the unigram rescaling in Eqs. 9 and 28: (K,)."""
        with np.errstate(divide="ignore"):
            return logsumexp(np.log(self.phi), axis=0)

    # ---- semantic terms ----------------------------------------------------------------------------------
    def bag_vector(self, bag: Mapping[str, float] | list[str]) -> np.ndarray:
        """A weighted bag of words (word -> weight, or a token list) as a length-V count vector; unknown words
        are dropped."""
        return bag_counts(bag, self.word_index, len(self.vocabulary))

    def log_word_likelihood(self, bag: Mapping[str, float] | list[str]) -> np.ndarray:
        """log Mult(S | W_l) for every concept l, up to the multinomial coefficient: (L,) (Eqs. 17, 28;
        :func:`log_multinomial`)."""
        with np.errstate(divide="ignore"):
            return log_multinomial(np.log(self.W), self.bag_vector(bag))

    def log_concept_given_place(self) -> np.ndarray:
        """log p(C = l | i = k), (L, K): :func:`log_concept_given_place` of this model's pi and phi."""
        return log_concept_given_place(self.pi, self.phi)

    def word_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(log W with 0 where W = 0, where W > 0, log pi, log phi): the arguments :func:`log_word_term` takes
        after the bag (the planner's terms compute them once per model)."""
        with np.errstate(divide="ignore"):
            log_W, log_pi, log_phi = np.log(self.W), np.log(self.pi), np.log(self.phi)
        finite = np.isfinite(log_W)
        return np.ascontiguousarray(np.where(finite, log_W, 0.0)), finite, log_pi, log_phi

    def log_semantic(self, bag: Mapping[str, float] | list[str]) -> np.ndarray:
        """log sum_C Mult(i | phi_C) Mult(S | W_C) Mult(C | pi) for every place i: (K,) (Eq. 28, last factor;
        :func:`log_word_term`)."""
        return log_word_term(*bag_indices(bag, self.word_index), *self.word_arrays())

    def log_place_given_words(self, bag: Mapping[str, float] | list[str]) -> np.ndarray:
        """log p(i | S) over active places (normalised), used by the goal-sampling baselines: (K,)
        (:func:`normalise_places` of :meth:`log_semantic`)."""
        return normalise_places(self.log_semantic(bag), np.asarray(self.active_places, dtype=np.bool_))

    def unigram_rescaled_W(self) -> np.ndarray:
        """W_l(w) / sum_c W_c(w), (L, V): how much of word w's use concept l has (Eq. 17's unigram rescaling);
        0 for a word no concept uses (a column of zeros is a valid W: such a word is never said)."""
        total = self.W.sum(axis=0, keepdims=True)
        return np.divide(self.W, total, out=np.zeros_like(self.W), where=total > 0)

    def word_given_place(self) -> np.ndarray:
        """p(w | k) = sum_l p(l | k) W_l(w), (K, V): how often word w is said at place k (Eqs. 13, 14 and 9)."""
        return np.exp(self.log_concept_given_place()).T @ self.W

    def label_scores(self) -> np.ndarray:
        """The label score of word w for place k, (K, V): sum_l p(l | k) W_l(w) / sum_c W_c(w), i.e.
        :meth:`word_given_place` with W unigram-rescaled as in Eq. 17 (rescaling suppresses function words such
        as "this", said with every concept). The one score that names a place (:meth:`place_names`,
        :func:`~spcotmhp.planning.vocabulary.place_vocabulary`)."""
        return np.exp(self.log_concept_given_place()).T @ self.unigram_rescaled_W()

    def place_names(self) -> list[str]:
        """A readable name per place: the word with the highest :meth:`label_scores`."""
        return [
            self.vocabulary[int(j)] if len(self.vocabulary) else f"place {k}"
            for k, j in enumerate(np.argmax(self.label_scores(), axis=1))
        ]


def log_multinomial(log_W: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """log Mult(S | W_l) up to the multinomial coefficient, sum_w n_w log W_l(w), for count vectors ``counts``
    (..., V) and every row l of ``log_W`` (L, V): (..., L) (words: Eqs. 17, 28; image features: Eq. 15). The one
    implementation every caller uses (the model, the planner's terms, the baselines, prediction). Entries absent
    from S contribute nothing, even where W_l(w) = 0 (a saved model may hold zeros), rather than 0 * log 0 =
    NaN; an entry of S with W_l(w) = 0 gives -inf."""
    counts = np.asarray(counts, dtype=float)
    finite = np.isfinite(log_W)
    out = counts @ np.where(finite, log_W, 0.0).T
    impossible = (counts > 0).astype(float) @ (~finite).T.astype(float) > 0
    return np.where(impossible, -np.inf, out)


def bag_counts(bag: Mapping[str, float] | list[str], index: Mapping[str, int], size: int) -> np.ndarray:
    """A weighted bag of words (word -> weight, or a token list, each token weighing 1) as a length-``size``
    count vector whose column of word w is ``index[w]``; words outside ``index`` are dropped."""
    vec = np.zeros(size)
    items = bag.items() if isinstance(bag, Mapping) else ((w, 1.0) for w in bag)
    for w, c in items:
        if w in index:
            vec[index[w]] += float(c)
    return vec


def bag_indices(bag: Mapping[str, float] | list[str], index: Mapping[str, int]) -> tuple[np.ndarray, np.ndarray]:
    """A weighted bag of words (word -> weight, or a token list, each token weighing 1) as (column indices,
    weights) of its words in ``index``, the sparse form of :func:`bag_counts` that :func:`log_word_term` takes;
    words outside ``index`` are dropped."""
    items = bag.items() if isinstance(bag, Mapping) else ((w, 1.0) for w in bag)
    known = [(index[w], float(c)) for w, c in items if w in index]
    return np.array([i for i, _ in known], dtype=np.int64), np.array([c for _, c in known], dtype=np.float64)


def log_concept_place(pi: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """log p(C = l, i = k) = log pi_l + log phi_l(k), (L, K): Eq. 14's Mult(C | pi) times Eq. 9's category term
    Mult(i | phi_C) (before its unigram rescaling); log 0 = -inf. Its sum over l is the place prior
    (:meth:`SpatialConceptModel.log_place_prior`), over l with the words Eq. 28's word term."""
    with np.errstate(divide="ignore"):
        return np.log(pi)[:, None] + np.log(phi)


def log_concept_given_place(pi: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """log p(C = l | i = k) = log pi_l phi_l(k) - log sum_c pi_c phi_c(k), (L, K): Bayes' rule on
    :func:`log_concept_place` (Eqs. 14 and 9), normalised over l; the concepts a place's words come from.

    >>> np.exp(log_concept_given_place(np.array([0.5, 0.5]), np.array([[0.9, 0.1], [0.3, 0.7]]))).round(3)
    array([[0.75 , 0.125],
           [0.25 , 0.875]])
    """
    joint = log_concept_place(pi, phi)
    return joint - logsumexp(joint, axis=0, keepdims=True)


@njit(cache=True)
def log_word_term(idx, weight, log_W0, finite_W, log_pi, log_phi):  # pragma: no cover - numba
    """Eq. 28's word term for every place i, (K,): log sum_C Mult(i | phi_C) Mult(S | W_C) Mult(C | pi), with
    log Mult(S | W_C) = sum_w n_w log W_C(w) up to the multinomial coefficient (:func:`log_multinomial`'s
    arithmetic on the sparse bag ``idx``, ``weight`` of :func:`bag_indices`: a word of S with W_C(w) = 0 makes
    C impossible, an absent word adds nothing). ``log_W0, finite_W, log_pi, log_phi``: as
    :meth:`SpatialConceptModel.word_arrays` gives them. The one implementation, for the model's numpy callers
    (:meth:`SpatialConceptModel.log_semantic`) and the planner's kernels (:mod:`spcotmhp.planning.terms`)."""
    L, K = log_phi.shape
    lw = np.empty(L)
    for c in range(L):
        total = 0.0
        for j in range(idx.shape[0]):
            if weight[j] > 0 and not finite_W[c, idx[j]]:
                total = -np.inf
                break
            total += weight[j] * log_W0[c, idx[j]]
        lw[c] = total + log_pi[c]
    out = np.empty(K)
    col = np.empty(L)
    for i in range(K):
        for c in range(L):
            col[c] = lw[c] + log_phi[c, i]
        out[i] = logsumexp_vector(col)
    return out


@njit(cache=True)
def normalise_places(log_semantic, active):  # pragma: no cover - numba
    """log p(i | S) = Eq. 28's word term normalised over the active places (-inf elsewhere), (K,)."""
    ls = np.where(active, log_semantic, -np.inf)
    return ls - logsumexp_vector(ls)
