"""The range of every model value (learning/model_values.py), checked when a model or its hyper-parameters are
constructed: hand-made boundary cases, the cases of issue 26, and a property: whatever the checks accept, the
place densities of Eqs. 3, 9 and 26 are finite; whatever would make them fail, the checks refuse."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.errors import ModelValueError
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.model_values import HYPER_RANGES, MAX_CONDITION, MIN_VARIANCE_M2
from spcotmhp.logspace import log_gaussian
from tests.helpers.learning import PLANTED_MU, PLANTED_PSI, PLANTED_SIGMA


def _model(**changes) -> SpatialConceptModel:
    K, L, V = 4, 2, 3
    values = {
        "mu": PLANTED_MU.copy(),
        "Sigma": PLANTED_SIGMA.copy(),
        "psi": PLANTED_PSI.copy(),
        "pi": np.full(L, 1 / L),
        "phi": np.full((L, K), 1 / K),
        "W": np.full((L, V), 1 / V),
        "vocabulary": ["a", "b", "c"],
    }
    values.update(changes)
    return SpatialConceptModel(**values)


def test_a_valid_model_is_kept_and_made_float():
    m = _model(pi=[0.5, 0.5])
    assert m.pi.dtype == float and m.K == 4 and m.L == 2 and m.active_places.all()


@pytest.mark.parametrize(
    "changes, key, message",
    [
        ({"Sigma": PLANTED_SIGMA * 1e-300}, "Sigma", r"Sigma\[0\] is not positive definite within the usable range"),
        ({"Sigma": -PLANTED_SIGMA}, "Sigma", r"Sigma\[0\] is not positive definite"),
        (
            {"Sigma": np.array([np.diag([1.0, 1e-13])] * 4)},
            "Sigma",
            r"smaller eigenvalue at least 1e-10 square metres and above 1e-12 times the larger",
        ),
        ({"Sigma": np.array([np.diag([1e13, 1e13])] * 4)}, "Sigma", r"Sigma\[0\] has a variance of 1e\+13, over"),
        ({"mu": PLANTED_MU + 2e6}, "mu", r"mu\[0\] = .* lies beyond \+-1e\+06 m"),
        ({"mu": np.full((4, 2), np.nan)}, "mu", "mu must hold finite floating-point numbers"),
        ({"mu": [["1", "2"]] * 4}, "mu", r"mu must hold finite floating-point numbers, got dtype <U1"),
        ({"psi": PLANTED_PSI * 2}, "psi", r"psi must be non-negative with rows summing to 1 \(row 0 sums to 2"),
        ({"pi": np.array([1.5, -0.5])}, "pi", r"pi must be non-negative .* smallest entry -0.5"),
        ({"W": np.full((2, 2), 0.5)}, "W", r"W has shape \(2, 2\), but the model's sizes need \(2, 3\)"),
        ({"vocabulary": ["a", "a", "c"]}, "vocabulary", r"\"vocabulary\" lists 'a' twice"),
        ({"active_places": np.ones(4)}, "active_places", "active_places must be 4 booleans"),
        ({"costmap": {"inflation_radius": 1e308}}, "costmap.inflation_radius", r"in 0..10000, got 1e\+308"),
        ({"costmap": {"robot": 1}}, "costmap", r"unknown cost map setting\(s\) robot"),
    ],
)
def test_values_out_of_range_are_refused_naming_the_key(changes, key, message):
    with pytest.raises(ModelValueError, match=message) as info:
        _model(**changes)
    assert info.value.key == key and "\n" not in str(info.value)


def test_the_covariance_bounds_are_inclusive_where_stated():
    edge = np.array([np.diag([MIN_VARIANCE_M2 * MAX_CONDITION, MIN_VARIANCE_M2])] * 4)
    assert np.isfinite(log_gaussian(PLANTED_MU, PLANTED_MU, _model(Sigma=edge).Sigma)).all()
    with pytest.raises(ModelValueError):
        _model(Sigma=edge * np.array([1.0, 0.999])[:, None])


@pytest.mark.parametrize("name", sorted(HYPER_RANGES))
def test_every_hyper_parameter_has_its_documented_range(name):
    low, high, open_low, _ = HYPER_RANGES[name]
    extra = {"place_size": {}, "off_name": {}}.get(name, {})
    inside = [high] + ([] if open_low else [low])
    for value in inside:
        h = Hyperparameters(**{name: value}, **extra)
        assert getattr(h, name) == value or name == "place_size"
    outside = [high * 2, float("inf"), float("nan") if name not in ("alpha", "gamma", "omega") else -1.0, "1", True]
    outside.append(low if open_low else low / 2)
    for value in outside:
        with pytest.raises(ModelValueError, match=rf"^{name} must be a finite number") as info:
            Hyperparameters(**{name: value})
        assert info.value.key == f"hyper.{name}"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"L": 0}, r"L must be an integer in \[1, 10000\], got 0"),
        ({"K": 10_001}, r"K must be an integer in \[1, 10000\], got 10001"),
        ({"K": 2.0}, r"K must be an integer"),
        ({"m0": (0.0, 1e7)}, r"m0 must be two finite numbers within \+-1e\+06 m"),
        ({"V0": ((1.0, 0.0), (0.0, 1e-300))}, r"V0 is not positive definite within the usable range"),
        ({"V0": ((1.0, 2.0), (2.0, 1.0))}, r"V0 is not positive definite"),
        ({"V0": ((1.0, "x"), (0.0, 1.0))}, r"V0 must be a 2 x 2 matrix of finite numbers"),
        ({"place_size": 1.0, "nu0": "x"}, r"place_size sets nu0 and V0"),
    ],
)
def test_hyper_parameters_of_other_kinds(kwargs, message):
    with pytest.raises(ModelValueError, match=message):
        Hyperparameters(**kwargs)


FLOATS = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([1e-300, 1e300, 1e-12, 1e12, 0.0, -1.0])


@given(
    a=FLOATS,
    d=FLOATS,
    b=FLOATS,
    scale=st.sampled_from([1.0, 1e-300, 1e-150, 1e150, 1e-6, 1e6]),
)
@settings(max_examples=300, deadline=None)
def test_accepted_covariances_give_finite_densities(a, d, b, scale):
    sigma = PLANTED_SIGMA.copy()
    with np.errstate(all="ignore"):
        sigma[2] = np.array([[a, b], [b, d]]) * scale
    try:
        model = _model(Sigma=sigma)
    except ModelValueError:
        return
    x = np.vstack([PLANTED_MU, PLANTED_MU + 1.0, [[1e6, -1e6]]])
    assert np.isfinite(model.log_place_density(x)).all()
    assert np.isfinite(model.place_posterior(x)).all()
