"""Most probable place and concept of teaching events under a learned model (e.g. a saved model on new data).

(i_e, C_e) = argmax log pi_C + log phi_C(i) + log N(x_e | mu_i, Sigma_i) + sum_b log W_C(S_e,b) + log theta_C(f_e)
(Eqs. 3, 14-17 for one event, over the active places and concepts); words outside the model's vocabulary are
ignored, image features must have the model's dimension.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import ModelError
from spcotmhp.learning.model import SpatialConceptModel, log_multinomial
from spcotmhp.learning.observations import Observations


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
