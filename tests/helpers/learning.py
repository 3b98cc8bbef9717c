"""A dataset drawn from the SpCoTMHP generative model with known parameters (shared by the learning tests)."""

from __future__ import annotations

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.metric.maps import OccupancyMap

PLANTED_MU = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 6.0], [0.0, 6.0]])
PLANTED_SIGMA = np.array(
    [
        [[0.30, 0.10], [0.10, 0.20]],
        [[0.15, 0.0], [0.0, 0.40]],
        [[0.25, -0.08], [-0.08, 0.25]],
        [[0.40, 0.0], [0.0, 0.15]],
    ]
)
# a ring 0 - 1 - 2 - 3 - 0, sticky; symmetric, so reverse replay does not bias it
PLANTED_PSI = np.array([[0.6, 0.2, 0.0, 0.2], [0.2, 0.6, 0.2, 0.0], [0.0, 0.2, 0.6, 0.2], [0.2, 0.0, 0.2, 0.6]])
NAMES = ["kitchen", "bedroom", "bath", "toilet"]
CONCEPT_OF_PLACE = np.array([0, 1, 2, 3])


def planted_dataset(E: int = 300, seed: int = 7) -> Dataset:
    """Events drawn from the generative model: i_e ~ psi[i_{e-1}], x_e ~ N(mu, Sigma), C_e from phi (here a
    deterministic place -> concept map), 3 tokens from W_C (the name with p 0.5, function words otherwise)."""
    rng = np.random.default_rng(seed)
    places = [0]
    for _ in range(E - 1):
        places.append(int(rng.choice(4, p=PLANTED_PSI[places[-1]])))
    places = np.array(places)
    X = np.array([rng.multivariate_normal(PLANTED_MU[k], PLANTED_SIGMA[k]) for k in places])
    concepts = CONCEPT_OF_PLACE[places]
    function = ["this", "is", "the", "here"]
    tokens = [[NAMES[c] if rng.random() < 0.5 else function[rng.integers(4)] for _ in range(3)] for c in concepts]
    for c, toks in zip(concepts, tokens, strict=False):
        if NAMES[c] not in toks:
            toks[0] = NAMES[c]
    grid = OccupancyMap(data=np.zeros((100, 100), np.int8), resolution=0.1, origin=(-2.0, -2.0, 0.0))
    return Dataset(name="planted", map=grid, positions=X, tokens=tokens, truth_place=places, truth_concept=concepts)
