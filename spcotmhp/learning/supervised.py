"""The supervised ("ideal") fit: posterior means of every parameter given each event's true place and concept.

This is what the paper's Experiment I planned with (see shared/notes/reference-implementation.md): the place and
concept of every teaching event are the ground truth (concept = place when the dataset has no concept column,
L = K = number of places), mu and Sigma are Normal-inverse-Wishart posterior means (m0 = 0, kappa0 = 1e-3,
V0 = 2 I, nu0 = 3), pi, phi, theta and W Dirichlet posterior means (alpha = 1, gamma = 0.1, chi = 1, beta = 0.1),
and psi comes from the hand-made adjacency: psi[k] = mean of Dir(0.1 + adjacency[k]).

The other way round, :func:`predict_assignments`: the most probable place and concept of teaching events under a
learned model (e.g. a saved model on new data),

    (i_e, C_e) = argmax log pi_C + log phi_C(i) + log N(x_e | mu_i, Sigma_i) + sum_b log W_C(S_e,b) + log theta_C(f_e)

(Eqs. 3, 14-17 for one event, over the active places and concepts); words outside the model's vocabulary are
ignored, image features must have the model's dimension.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError, ModelError
from spcotmhp.language.said_names import record_dataset_names
from spcotmhp.learning.connectivity import (
    ADJACENCY_CONCENTRATION,
    apply_connectivity,
    psi_from_adjacency,
    trajectory_places,
)
from spcotmhp.learning.hmm import transition_counts
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel, log_multinomial
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.posterior import Priors, SufficientStats, posterior_mean_model

SUPERVISED_HYPER = Hyperparameters(alpha=1.0, gamma=0.1, beta=0.1, chi=1.0, omega=ADJACENCY_CONCENTRATION)
ADJACENCY_SOURCES = ("auto", "given", "transitions", "walk", "map")


def fit_supervised(
    dataset: Dataset,
    adjacency: str | np.ndarray = "auto",
    hyper: Hyperparameters | None = None,
    use_features: bool = True,
    feature_weight: float | None = 1.0,
    replay: bool = True,
    min_dwell: int = 3,
) -> SpatialConceptModel:
    """Posterior-mean model given the dataset's truth (truth_place, and truth_concept when present).

    Args:
        adjacency: where psi comes from. "given": the dataset's adjacency (psi[k] = mean of Dir(0.1 + A[k]));
            a (K, K) 0/1 array: that adjacency; "transitions": the posterior mean of Dir(0.1 + counts) of the
            place transitions of the truth event sequence (with reverse replay when ``replay``) plus the place
            changes along the trajectory when there is one; "walk": the adjacency of places visited one after
            the other (trajectory, else event order; ``connectivity.walk_adjacency``); "map": the adjacency
            implied by the map's free space (``connectivity.map_adjacency``); "auto": "given" when the dataset
            has an adjacency, else "walk" when it has a trajectory, else "map".
        hyper: priors (default ``SUPERVISED_HYPER``, the authors' Experiment I values).
        use_features, feature_weight: image features as in ``Observations.from_dataset``.
    """
    if dataset.truth_place is None:
        raise DatasetError(f"{dataset.name}: the supervised fit needs truth places (truth.csv)")
    hyper = hyper or SUPERVISED_HYPER
    obs = Observations.from_dataset(dataset, use_features=use_features, feature_weight=feature_weight)
    places, concepts, K, L = _truth_assignments(dataset, obs.E)
    hyper = hyper.resized(L, K)
    D = None if obs.features is None else obs.features.shape[1]
    priors = Priors.build(hyper, K, L, len(obs.vocabulary), D)
    stats = SufficientStats.from_assignments(obs, places, concepts, K, L)
    source = _adjacency_source(dataset, adjacency)
    model = posterior_mean_model(
        priors,
        stats,
        None,
        obs.vocabulary,
        hyper,
        {
            "method": "supervised",
            "dataset": dataset.name,
            "features": obs.features is not None,
            "feature_weight": feature_weight,
        },
    )
    model.map = dataset.map
    if source in ("given", "array"):
        model.psi = psi_from_adjacency(_place_adjacency(dataset, source, adjacency, K), hyper.omega)
        model.info["psi_from"] = "adjacency.csv" if source == "given" else "adjacency"
    elif source == "transitions":
        model.psi = priors.psi.posterior_mean(_place_transitions(model, places, K, obs, replay, min_dwell))
        model.info["psi_from"] = "transitions"
    else:
        apply_connectivity(model, dataset, source, places)
    record_dataset_names(model, dataset.tokens, dataset.lang, places)  # taught names (said_names.py)
    return model


def _truth_assignments(dataset: Dataset, E: int) -> tuple[np.ndarray, np.ndarray, int, int]:
    """The true place and concept of each of the E events (concept = place without truth concepts), the number
    of places K (also counting places.csv and adjacency.csv rows) and of concepts L."""
    assert dataset.truth_place is not None
    places = np.asarray(dataset.truth_place, dtype=np.int64)
    concepts = places if dataset.truth_concept is None else np.asarray(dataset.truth_concept, dtype=np.int64)
    if len(places) != E or len(concepts) != E:
        raise DatasetError(f"{dataset.name}: {len(places)} truth rows for {E} teaching events")
    K = max(
        int(places.max()) + 1,
        len(dataset.place_names or []),
        0 if dataset.adjacency is None else len(dataset.adjacency),
    )
    return places, concepts, K, int(concepts.max()) + 1


def _place_adjacency(dataset: Dataset, source: str, adjacency: str | np.ndarray, K: int) -> np.ndarray:
    """The (K, K) place adjacency psi comes from: the dataset's ("given") or the array passed ("array")."""
    A = np.asarray(dataset.adjacency if source == "given" else adjacency)
    if A.shape != (K, K):
        raise ModelError(f"adjacency must be {K}x{K} (one row per place), got {A.shape}")
    return A


def _place_transitions(
    model: SpatialConceptModel, places: np.ndarray, K: int, obs: Observations, replay: bool, min_dwell: int
) -> np.ndarray:
    """(K, K) place transition counts of the truth event sequence (reverse replay when ``replay``), plus the
    place changes along the trajectory (its positions assigned to ``model``'s places) when there is one."""
    counts = transition_counts(places, K, replay)
    if obs.trajectory is not None:
        counts += transition_counts(trajectory_places(model, obs.trajectory, min_dwell), K, replay)
    return counts


def _adjacency_source(dataset: Dataset, adjacency: str | np.ndarray) -> str:
    if isinstance(adjacency, np.ndarray):
        return "array"
    if adjacency not in ADJACENCY_SOURCES:
        raise ModelError(f"adjacency must be one of {ADJACENCY_SOURCES} or an array, got {adjacency!r}")
    if adjacency == "given" and dataset.adjacency is None:
        raise DatasetError(f"{dataset.name}: adjacency='given' but the dataset has no adjacency.csv")
    if adjacency != "auto":
        return adjacency
    if dataset.adjacency is not None:
        return "given"
    return "walk" if dataset.trajectory is not None else "map"


def predict_assignments(
    model: SpatialConceptModel, dataset: Dataset, use_features: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """(places (E,), concepts (E,)) of the dataset's events; features are scaled as when the model was learned
    (``model.info["feature_weight"]``)."""
    with_features = use_features and dataset.features is not None and model.theta is not None
    obs = Observations.from_dataset(
        dataset,
        use_features=with_features,
        use_trajectory=False,
        vocabulary=model.vocabulary,
        feature_weight=model.info.get("feature_weight", 1.0),
    )
    theta = model.theta if obs.features is not None else None
    if obs.features is not None and theta is not None and obs.features.shape[1] != theta.shape[1]:
        raise ModelError(
            f"{dataset.name}: the image features have {obs.features.shape[1]} dimensions but the "
            f"model was learned with {theta.shape[1]}"
        )
    with np.errstate(divide="ignore"):
        score_c = np.log(model.pi) + log_multinomial(np.log(model.W), obs.words)  # (E, L)
        if obs.features is not None and theta is not None:
            score_c = score_c + log_multinomial(np.log(theta), obs.features)
        score_c = np.where(model.active_concepts, score_c, -np.inf)
        place = np.where(model.active_places, model.log_place_density(obs.X), -np.inf)  # (E, K)
        joint = score_c[:, :, None] + np.log(model.phi)[None] + place[:, None, :]  # (E, L, K)
    flat = joint.reshape(obs.E, -1).argmax(axis=1)
    return flat % model.K, flat // model.K
