"""What loading a model folder checks in its learner state (learner.json, learner.npz) beyond shapes, indices and
finite non-negative counts (:func:`spcotmhp.learning.learner_state.check_member`): the values a checksum cannot
judge and that teaching would otherwise crash or warn on.

* Size (:func:`check_learner_size`, before learner.npz is hashed): the numbers learner.json's E events and T
  tokens ask for, at the model's K, L, V, D, at most ``MAX_ELEMENTS`` (32 Mi numbers, 256 MiB, the bound of
  arrays.npz), so that an inflated learner.npz is refused by a stat, not hashed; checked on saving too, so that
  every saved folder loads.
* Counts cover the events (:func:`check_counts_cover_events`): the sampler removes an event's share from every
  count before it re-draws the event (``CollapsedState.move``), so each count must hold at least what the events
  give: n_k per place, n_l and n_lk per concept, W_lv and bg_v per word, z_tot per switch, trans per pair of
  consecutive places, F_ld per concept's features. A learner's counts are the events' plus pseudo-counts
  (``pseudo_state``, >= 0), never fewer; fewer would go negative and give log(negative) in the next teach.
* Place posteriors (:func:`check_place_posteriors`): the Normal-inverse-Wishart posterior of every place given
  n_k, sx, sxx (Murphy 2007, Eqs. 251-254; the Student-t predictive of Eq. 258 that teaching evaluates) has a
  mean within +-``MAX_MEAN_M`` and a scale that is a usable covariance (``model_values.check_covariances``:
  positive definite, eigenvalues in [1e-10, 1e12] m^2, condition number at most 1e12); the events' positions
  X lie within +-``MAX_MEAN_M`` too.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from spcotmhp.errors import ModelError, ModelValueError
from spcotmhp.learning.hmm import transition_counts
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.model_values import MAX_MEAN_M, check_covariances
from spcotmhp.limits import MODEL_MAX_ELEMENTS

COUNT_TOL = 1e-6  # relative: counts are sums of ones, stored as float64


def check_learner_size(specs: Mapping[str, tuple[tuple[int, ...], str]], E: int, T: int, where: str) -> None:
    """ModelError unless the arrays ``specs`` (``learner_specs``) of E events and T tokens hold at most
    MODEL_MAX_ELEMENTS numbers."""
    n = sum(int(np.prod(shape, dtype=np.int64)) for shape, _ in specs.values())
    if n > MODEL_MAX_ELEMENTS:
        raise ModelError(
            f"{where}: a learner state of E={E} events and T={T} tokens needs {n} numbers in learner.npz; at most "
            f"{MODEL_MAX_ELEMENTS} are accepted"
        )


def check_counts_cover_events(a: Mapping[str, np.ndarray], K: int, L: int, V: int, where: str) -> None:
    """ModelError unless every count of the learner arrays ``a`` is at least what its events give (module
    docstring); ``a``'s indices are already checked to fit K, L, V."""
    place, concept = a["place"].astype(np.int64), a["concept"].astype(np.int64)
    words, z = a["tok_word"].astype(np.int64), a["tok_z"].astype(bool)
    lengths: np.ndarray = np.diff(a["tok_ptr"].astype(np.int64)).astype(np.int64)
    of_token = np.repeat(concept, lengths)
    # an answer may weigh w events and be a segment of its own (``collapsed.py``): w in every count but trans,
    # and the walk's transitions skip it
    w = np.asarray(a["weight"], dtype=float) if "weight" in a else np.ones(len(place))
    alone = np.asarray(a["alone"], dtype=bool) if "alone" in a else np.zeros(len(place), dtype=bool)
    w_token = np.repeat(w, lengths)
    need = {
        "n_k": np.bincount(place, weights=w, minlength=K).astype(float),
        "n_l": np.bincount(concept, weights=w, minlength=L).astype(float),
        "n_lk": np.zeros((L, K)),
        "W_lv": np.zeros((L, V)),
        "bg_v": np.bincount(words[~z], weights=w_token[~z], minlength=V).astype(float),
        "z_tot": np.array([float(w_token[~z].sum()), float(w_token[z].sum())]),
        "trans": transition_counts(place[~alone], K, False),
    }
    np.add.at(need["n_lk"], (concept, place), w)
    np.add.at(need["W_lv"], (of_token[z], words[z]), w_token[z])
    if "F_ld" in a and "features" in a and "has_features" in a:
        has = a["has_features"].astype(bool)
        need["F_ld"] = np.zeros(a["F_ld"].shape)
        np.add.at(need["F_ld"], concept[has], a["features"][has] * w[has, None])
    for name, n in need.items():
        short = a[name] < n - COUNT_TOL * (1.0 + n)
        if short.any():
            at = tuple(int(i) for i in np.argwhere(short)[0])
            raise ModelError(
                f"{where}: {name}{list(at)} is {float(a[name][at]):.6g}, fewer than the {float(n[at]):.6g} its "
                "events give; a learner's counts include every event's (the learner state is corrupt or altered)"
            )


def check_place_posteriors(a: Mapping[str, np.ndarray], hyper: Hyperparameters, where: str) -> None:
    """ModelError unless X and every place's NIW posterior are usable (module docstring): the posterior of the
    counts less their events' share (the prior and pseudo-counts) and of the counts as they are. Every state
    the sampler visits adds some of the events back to the first, and adding an event to a NIW posterior adds
    a positive semi-definite term to its scale matrix, so none of them is worse."""
    X, place = a["X"], a["place"].astype(np.int64)
    if len(X) and not (np.abs(X) <= MAX_MEAN_M).all():
        e = int(np.argmax(~(np.abs(X) <= MAX_MEAN_M).all(axis=1)))
        raise ModelError(f"{where}: event {e} lies at {X[e].tolist()}, beyond +-{MAX_MEAN_M:g} m")
    K = len(a["n_k"])
    n_e, sx_e, sxx_e = np.bincount(place, minlength=K).astype(float), np.zeros((K, 2)), np.zeros((K, 2, 2))
    np.add.at(sx_e, place, X)
    np.add.at(sxx_e, place, X[:, :, None] * X[:, None, :])
    for what, n, sx, sxx in (
        ("less their events' share", a["n_k"] - n_e, a["sx"] - sx_e, a["sxx"] - sxx_e),
        ("as they are", a["n_k"], a["sx"], a["sxx"]),
    ):
        _check_posterior(np.maximum(n, 0.0), sx, sxx, hyper, f"{where}: n_k, sx, sxx {what}")


def _check_posterior(n: np.ndarray, sx: np.ndarray, sxx: np.ndarray, hyper: Hyperparameters, where: str) -> None:
    """The posterior mean within +-MAX_MEAN_M and the Student-t scale a usable covariance, for every place."""
    m0, V0 = np.asarray(hyper.m0, dtype=float), np.asarray(hyper.V0, dtype=float)
    kn, dof = hyper.kappa0 + n, hyper.nu0 + n - 1.0
    with np.errstate(all="ignore"):
        mn = (hyper.kappa0 * m0 + sx) / kn[:, None]
        Vn = V0 + sxx + hyper.kappa0 * np.outer(m0, m0) - kn[:, None, None] * mn[:, :, None] * mn[:, None, :]
        scale = Vn * ((kn + 1.0) / (kn * dof))[:, None, None]
    far = ~(np.abs(mn) <= MAX_MEAN_M).all(axis=1)
    if far.any():
        k = int(np.argmax(far))
        raise ModelError(
            f"{where} give place {k} a posterior mean of {mn[k].tolist()}, beyond +-{MAX_MEAN_M:g} m (the learner "
            "state is corrupt or altered)"
        )
    try:
        bad = ~np.isfinite(scale).all(axis=(1, 2))
        if bad.any():
            raise ModelValueError(f"Sigma_n[{int(np.argmax(bad))}] is not finite")
        check_covariances(scale, "Sigma_n", "learner.sxx")
    except ModelValueError as exc:
        raise ModelError(
            f"{where} do not give every place a usable posterior (Sigma_n, the scale of its Student-t "
            f"predictive): {exc}"
        ) from None
