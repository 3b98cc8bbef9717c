"""The range of every value a model can use, checked in one place: when a model folder is loaded
(:mod:`spcotmhp.persistence.model_checks`) and when a :class:`~spcotmhp.learning.model.SpatialConceptModel` or its
:class:`~spcotmhp.learning.model.Hyperparameters` is constructed. A value outside its range raises one
:class:`~spcotmhp.errors.ModelValueError` naming the key (``exc.key``: "Sigma", "hyper.place_size",
"costmap.inflation_radius", ...) and the accepted range; a checksum cannot judge these, a plan would crash on them.

The ranges and why:

* ``mu``: finite, within +-``MAX_MEAN_M`` = 1e6 m (a map's origin lies within +-1e6 m too).
* ``Sigma``, and the prior scale ``V0``: symmetric (up to ``SYMMETRY_TOL`` relative, then made exactly so), both
  eigenvalues in [``MIN_VARIANCE_M2``, ``MAX_VARIANCE_M2``] = [1e-10, 1e12] m^2 (a spread from 10 um to 1000 km)
  and a condition number (larger / smaller eigenvalue) of at most ``MAX_CONDITION`` = 1e12: Eqs. 3, 9 and 26
  take the determinant and the inverse in closed form (:func:`~spcotmhp.logspace.log_gaussian`), which
  within these bounds stay positive and accurate to 1e-4 relative; a covariance scaled by 1e-300 underflows
  its determinant to 0.
* ``psi``, ``pi``, ``phi``, ``W``, ``theta``, ``psi_learned``: finite, non-negative, every row summing to 1 within
  ``PROB_TOL`` = 1e-6 (categorical distributions, Eqs. 7-17).
* ``active_places`` / ``active_concepts``: K / L booleans; ``vocabulary``: V distinct strings of at most
  ``MAX_WORD_CHARS`` characters, each non-empty, without leading or trailing spaces or control characters (a
  word of the vocabulary is one that was said; an empty word or a line break cannot be, and would name a place
  nobody can ask for).
* Hyper-parameters (``HYPER_RANGES``): L and K integers in 1..``MODEL_MAX_SIZES``; the Dirichlet concentrations
  alpha, gamma, beta, chi, omega and kappa0 in [1e-6, 1e6] (pseudo-observations: below 1e-6 a log-space
  Dirichlet draw loses every outcome but one to -inf, above 1e6 the prior outweighs a million observations);
  nu0 in (1, 1e6] (the 2-D inverse-Wishart needs nu0 > 1); m0 two finite numbers within +-``MAX_MEAN_M``;
  place_size in [1e-3, 1e5] m (a place's spread from a millimetre to 100 km; it sets V0 = 2 s^2 I, which then
  satisfies the covariance rule); place_concepts in [1e-6, 1e6] (a concentration); off_name in (0, 1e6] nats.
* ``costmap``: the fields of :class:`~spcotmhp.metric.costmap.CostMapSettings`, flags true or false, distances
  and the scaling factor finite numbers in 0..``MAX_COSTMAP``.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Iterable, Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from spcotmhp.errors import ModelValueError
from spcotmhp.limits import MODEL_MAX_SIZES
from spcotmhp.safe_read import excerpt, finite_number

PROB_TOL = 1e-6
SYMMETRY_TOL = 1e-9
MAX_MEAN_M = 1e6
MIN_VARIANCE_M2 = 1e-10
MAX_VARIANCE_M2 = 1e12
MAX_CONDITION = 1e12
MAX_WORD_CHARS = 256
MAX_COSTMAP = {
    "inscribed_radius": 1e4,
    "inflation_radius": 1e4,
    "cost_scaling_factor": 1e6,
    "circumscribed_radius": 1e4,
}
CONCENTRATION = (1e-6, 1e6)
# name -> (low, high, low excluded, unit): the documented range of each numeric hyper-parameter
HYPER_RANGES: dict[str, tuple[float, float, bool, str]] = {
    **{name: (*CONCENTRATION, False, "") for name in ("alpha", "gamma", "beta", "chi", "omega", "kappa0")},
    "nu0": (1.0, 1e6, True, ""),
    "place_size": (1e-3, 1e5, False, " of metres"),
    "place_concepts": (*CONCENTRATION, False, ""),
    "off_name": (0.0, 1e6, True, " of nats"),
}
OPTIONAL_HYPER = ("place_size", "place_concepts", "off_name")  # None: off
DISTRIBUTIONS = ("psi", "pi", "phi", "W", "theta", "psi_learned")


def refuse(key: str, message: str) -> ModelValueError:
    """A ModelValueError for ``key`` (kept as ``exc.key``, so that a loader can name the file it came from)."""
    exc = ModelValueError(message)
    exc.key = key  # type: ignore[attr-defined]
    return exc


def in_range(name: str, value: object, bounds: tuple[float, float, bool, str], key: str | None = None) -> float:
    """``value`` as a float when it is a finite number (not a boolean) within ``bounds`` = (low, high, low
    excluded, unit); else a ModelValueError naming ``name`` and the range."""
    low, high, open_low, unit = bounds
    if not (finite_number(value) and (low < value if open_low else low <= value) and value <= high):
        shown = f"{'(' if open_low else '['}{low:g}, {high:g}]"
        raise refuse(key or name, f"{name} must be a finite number{unit} in {shown}, got {excerpt(value)}")
    return float(value)


# ---- hyper-parameters ---------------------------------------------------------------------------------------
def check_truncation(h: Any) -> None:
    """L and K of hyper-parameters ``h``: integers in 1..MODEL_MAX_SIZES (the scaled priors derive from them)."""
    for name in ("L", "K"):
        value, high = getattr(h, name), MODEL_MAX_SIZES[name]
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= high:
            raise refuse(f"hyper.{name}", f"{name} must be an integer in [1, {high}], got {excerpt(value)}")


def check_hyper(h: Any) -> None:
    """The ranges of a :class:`~spcotmhp.learning.model.Hyperparameters` (module docstring), after its scaled
    priors were derived; ModelValueError (key "hyper.NAME") naming the first value out of range."""
    check_truncation(h)
    for name, bounds in HYPER_RANGES.items():
        value = getattr(h, name)
        if not (name in OPTIONAL_HYPER and value is None):
            in_range(name, value, bounds, f"hyper.{name}")
    m0 = h.m0
    ok = isinstance(m0, (tuple, list, np.ndarray)) and len(m0) == 2
    if not (ok and all(finite_number(v) and abs(float(v)) <= MAX_MEAN_M for v in m0)):
        raise refuse("hyper.m0", f"m0 must be two finite numbers within +-{MAX_MEAN_M:g} m, got {excerpt(m0)}")
    try:
        v0 = np.asarray(h.V0, dtype=float)
    except (TypeError, ValueError, OverflowError):
        v0 = np.full((1,), np.nan)
    if v0.shape != (2, 2) or not np.isfinite(v0).all():
        raise refuse("hyper.V0", f"V0 must be a 2 x 2 matrix of finite numbers, got {excerpt(h.V0)}")
    check_covariances(v0[None], "V0", "hyper.V0", indexed=False)


# ---- arrays -------------------------------------------------------------------------------------------------
def float_array(name: str, value: object, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as a float64 array of ``shape`` with finite entries; else a ModelValueError naming ``name``."""
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):
        a = np.empty(0, dtype=object)
    if a.shape != shape:
        raise refuse(name, f"{name} has shape {a.shape}, but the model's sizes need {shape}")
    if a.dtype.kind not in "fiu":
        raise refuse(name, f"{name} must hold finite floating-point numbers, got dtype {a.dtype}")
    a = a.astype(float, copy=False)
    if not np.isfinite(a).all():
        raise refuse(name, f"{name} must hold finite floating-point numbers")
    return a


def bool_array(name: str, value: object, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as a boolean array of ``shape``; else a ModelValueError naming ``name``."""
    a = np.asarray(value)
    if a.shape != shape or a.dtype != bool:
        raise refuse(name, f"{name} must be {shape[0]} booleans, got shape {a.shape} of {a.dtype}")
    return a


def check_distribution(name: str, p: np.ndarray) -> None:
    """Non-negative rows summing to 1 within PROB_TOL (``p`` already finite)."""
    rows = np.atleast_2d(p)
    if not rows.size:
        return
    off = np.abs(rows.sum(axis=1) - 1.0)
    if (rows < 0).any() or off.max() > PROB_TOL:
        r = int(np.argmax((rows < 0).any(axis=1) | (off > PROB_TOL)))
        raise refuse(
            name,
            f"{name} must be non-negative with rows summing to 1 (row {r} sums to {rows[r].sum():.6g}, "
            f"smallest entry {rows[r].min():.3g})",
        )


def check_means(mu: np.ndarray) -> None:
    """Means within +-MAX_MEAN_M metres."""
    beyond = (np.abs(mu) > MAX_MEAN_M).any(axis=1)
    if beyond.any():
        k = int(np.argmax(beyond))
        raise refuse("mu", f"mu[{k}] = {mu[k].tolist()} lies beyond +-{MAX_MEAN_M:g} m")


def check_covariances(sigma: np.ndarray, name: str = "Sigma", key: str = "Sigma", indexed: bool = True) -> np.ndarray:
    """Each 2 x 2 matrix of ``sigma`` (n, 2, 2) symmetric and positive definite within the module docstring's
    bounds; returns them made exactly symmetric."""
    scale = np.maximum(np.abs(sigma).max(axis=(1, 2)), np.finfo(float).tiny)
    asym = np.abs(sigma[:, 0, 1] - sigma[:, 1, 0]) / scale
    label = (lambda k: f"{name}[{k}]") if indexed else (lambda k: name)
    if (asym > SYMMETRY_TOL).any():
        k = int(np.argmax(asym))
        raise refuse(
            key,
            f"{label(k)} is not symmetric ({sigma[k, 0, 1]:.6g} above the diagonal, {sigma[k, 1, 0]:.6g} below); "
            "a covariance must be symmetric",
        )
    sym = (sigma + np.swapaxes(sigma, 1, 2)) / 2.0
    if not len(sym):
        return sym
    eig = np.linalg.eigvalsh(sym)
    if (eig[:, 1] > MAX_VARIANCE_M2).any():
        k = int(np.argmax(eig[:, 1]))
        raise refuse(key, f"{label(k)} has a variance of {eig[k, 1]:.3g}, over {MAX_VARIANCE_M2:g} square metres")
    bad = (eig[:, 0] < MIN_VARIANCE_M2) | (eig[:, 0] * MAX_CONDITION < eig[:, 1])
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise refuse(
            key,
            f"{label(k)} is not positive definite within the usable range (eigenvalues {eig[k, 0]:.3g}, "
            f"{eig[k, 1]:.3g}); a covariance must be positive definite, its smaller eigenvalue at least "
            f"{MIN_VARIANCE_M2:g} square metres and above {1 / MAX_CONDITION:g} times the larger",
        )
    return sym


def check_vocabulary(vocabulary: Iterable[object]) -> list[str]:
    """Distinct strings of at most MAX_WORD_CHARS characters (each names one column of W)."""
    words: list[str] = []
    seen: set[str] = set()
    for j, word in enumerate(vocabulary):
        if not isinstance(word, str):
            raise refuse("vocabulary", f'"vocabulary" word {j} must be a string, got {excerpt(word)}')
        if word in seen:
            raise refuse(
                "vocabulary",
                f'"vocabulary" lists {excerpt(word)} twice (again at index {j}); each word must be listed once '
                "(it names one column of W)",
            )
        if not word.strip() or word != word.strip() or any(unicodedata.category(c) == "Cc" for c in word):
            raise refuse(
                "vocabulary",
                f'"vocabulary" word {j} is {excerpt(word)}; a word must be non-empty text without leading or '
                "trailing spaces or control characters (it must be something that can be said)",
            )
        if len(word) > MAX_WORD_CHARS:
            raise refuse(
                "vocabulary",
                f'"vocabulary" word {j} has {len(word)} characters; at most {MAX_WORD_CHARS} are accepted',
            )
        seen.add(word)
        words.append(word)
    return words


def check_costmap(raw: Mapping[str, object]) -> None:
    """Cost map settings: fields of CostMapSettings, flags true/false, numbers finite in 0..MAX_COSTMAP."""
    from spcotmhp.metric.costmap import CostMapSettings

    if not isinstance(raw, Mapping):
        raise refuse("costmap", f'"costmap" must be a mapping of cost map settings, got {excerpt(raw)}')
    known = {f.name: f for f in fields(CostMapSettings)}
    unknown = sorted(str(k) for k in set(raw) - set(known))
    if unknown:
        raise refuse(
            "costmap", f'unknown cost map setting(s) {", ".join(unknown)} in "costmap" (known: {", ".join(known)})'
        )
    for key, value in raw.items():
        high = MAX_COSTMAP.get(key, 0.0)
        if isinstance(known[key].default, bool):
            if not isinstance(value, bool):
                raise refuse(f"costmap.{key}", f'"costmap.{key}" must be true or false, got {excerpt(value)}')
        elif not (finite_number(value) and 0 <= value <= high):
            raise refuse(
                f"costmap.{key}", f'"costmap.{key}" must be a finite number in 0..{high:g}, got {excerpt(value)}'
            )


def check_model(m: Any) -> None:
    """Every value of a :class:`~spcotmhp.learning.model.SpatialConceptModel` (module docstring); converts its
    arrays to float64 / bool in place and makes Sigma exactly symmetric. ModelValueError on the first problem."""
    K, L = _size(m.mu, "mu", 0), _size(m.pi, "pi", 0)
    m.vocabulary = check_vocabulary(m.vocabulary)
    V = len(m.vocabulary)
    shapes = {"mu": (K, 2), "Sigma": (K, 2, 2), "psi": (K, K), "pi": (L,), "phi": (L, K), "W": (L, V)}
    if m.theta is not None:
        shapes["theta"] = (L, _size(m.theta, "theta", 1))
    if m.psi_learned is not None:
        shapes["psi_learned"] = (K, K)
    for name, shape in shapes.items():
        setattr(m, name, float_array(name, getattr(m, name), shape))
    m.active_places = bool_array("active_places", m.active_places, (K,))
    m.active_concepts = bool_array("active_concepts", m.active_concepts, (L,))
    for name in DISTRIBUTIONS:
        if name in shapes:
            check_distribution(name, getattr(m, name))
    check_means(m.mu)
    m.Sigma = check_covariances(m.Sigma)
    check_costmap(m.costmap)


def _size(value: Any, name: str, axis: int) -> int:
    try:
        shape = np.shape(value)
    except ValueError:  # a ragged list
        shape = ()
    if len(shape) <= axis:
        raise refuse(name, f"{name} must be an array with at least {axis + 1} dimension(s), got shape {shape}")
    return int(shape[axis])
