"""The online learner's state in a model folder (learner.json, learner.npz): its format, the writers
(:func:`learner_writers`), the reader (:func:`read_learner`), and what loading checks beyond shapes and indices
(:func:`check_member`): the values a checksum cannot judge and that teaching would otherwise crash or warn on.
The state itself and the model it implies live in :mod:`spcotmhp.learning.learner_state`.

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
from spcotmhp.learning.learner_state import COUNTS
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
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


def check_member(member: dict, K: int, L: int, V: int, D: int | None, where: str) -> None:
    """ModelError unless a learner member read from a folder fits the model's sizes and holds valid counts."""
    a = member["arrays"]
    E, T = len(a["place"]), len(a["tok_word"])
    bad = next(
        (
            n
            for n in COUNTS + ("X",) + (("F_ld", "features") if D is not None else ())
            if not (np.isfinite(a[n]).all() and (n in ("sx", "sxx", "X") or (a[n] >= 0).all()))
        ),
        None,
    )
    if bad:
        raise ModelError(f"{where}: {bad} must hold finite non-negative numbers")
    if "walk_X" in a and not np.isfinite(a["walk_X"]).all():
        raise ModelError(f"{where}: the walk's poses (walk_X) must be finite")
    if "weight" in a and not (np.isfinite(a["weight"]).all() and (a["weight"] > 0).all()):
        raise ModelError(f"{where}: weight must hold finite positive numbers (the evidence weight of each event)")
    ptr = a["tok_ptr"]
    ok = (
        ptr[0] == 0
        and ptr[-1] == T
        and (np.diff(ptr) >= 0).all()
        and (a["tok_word"] < V).all()
        and (a["tok_word"] >= 0).all()
        and ((a["place"] >= 0) & (a["place"] < K)).all()
        and ((a["concept"] >= 0) & (a["concept"] < L)).all()
        and len(a["concept"]) == E
    )
    if not ok:
        raise ModelError(f"{where}: the events' places, concepts or tokens do not fit the model (K={K}, L={L}, V={V})")


# ---- in the model folder -------------------------------------------------------------------------------------
LEARNER_FORMAT = "spcotmhp-learner"
LEARNER_VERSION = 1
MAX_EVENTS = 1_000_000
MAX_TOKENS = 50_000_000
MAX_WALK = 10_000_000
LEARNER_JSON_BYTES = 4096


def learner_writers(member: dict) -> dict:
    """Writers of learner.json and learner.npz for :func:`spcotmhp.persistence.io.save_model`."""
    import json

    a = member["arrays"]
    meta = {
        "format": LEARNER_FORMAT,
        "format_version": LEARNER_VERSION,
        "E": len(a["place"]),
        "T": len(a["tok_word"]),
        "replay": member["replay"],
        "background": member["background"],
    }
    if "walk_X" in a:
        meta["P"] = len(a["walk_X"])
    L, K = a["n_lk"].shape
    D = a["F_ld"].shape[1] if "F_ld" in a else None
    if meta["E"] > MAX_EVENTS or meta["T"] > MAX_TOKENS:
        raise ModelError(
            f"the learner state holds {meta['E']} events and {meta['T']} tokens; a model folder holds at most "
            f"{MAX_EVENTS} and {MAX_TOKENS} (learn from fewer events)"
        )
    check_learner_size(learner_specs(meta, K, L, a["W_lv"].shape[1], D)[0], meta["E"], meta["T"], "the model")
    return {
        "learner.json": lambda path: path.write_text(json.dumps(meta), encoding="utf-8"),
        "learner.npz": lambda path: np.savez(path, **a),
    }


def read_learner_meta(root) -> dict | None:
    """learner.json of the model folder ``root`` (None when it has none): format, version, E events and T tokens
    within MAX_EVENTS / MAX_TOKENS, replay and background flags; ModelError otherwise."""
    from spcotmhp.persistence.folder import inside
    from spcotmhp.safe_read import load_json

    if not (root / "learner.json").exists():
        return None
    path = inside(root, "learner.json", "learner.json")
    meta = load_json(path, LEARNER_JSON_BYTES, "learner state", ModelError)
    ok = (
        isinstance(meta, dict)
        and meta.get("format") == LEARNER_FORMAT
        and meta.get("format_version") == LEARNER_VERSION
        and all(isinstance(meta.get(k), int) and not isinstance(meta.get(k), bool) for k in ("E", "T"))
        and all(isinstance(meta.get(k), bool) for k in ("replay", "background"))
    )
    P = meta.get("P", 0) if ok else 0  # walk poses (teaching.answers.walk_poses), absent in most folders
    ok = ok and isinstance(P, int) and not isinstance(P, bool) and 0 <= P <= MAX_WALK
    if not ok or not (0 <= meta["E"] <= MAX_EVENTS and 0 <= meta["T"] <= MAX_TOKENS):
        raise ModelError(
            f"{path} is not a spcotmhp learner state of format version {LEARNER_VERSION} (format, "
            "format_version, E, T, replay, background)"
        )
    return meta


def learner_specs(meta: dict, K: int, L: int, V: int, D: int | None) -> tuple[dict, tuple[str, ...]]:
    """The arrays of learner.npz (name -> (shape, dtype kinds)) for a learner state ``meta`` of a model of sizes
    K, L, V, D, and the names that may be absent."""
    E, T = meta["E"], meta["T"]
    specs = {
        "n_k": (K,),
        "sx": (K, 2),
        "sxx": (K, 2, 2),
        "n_l": (L,),
        "n_lk": (L, K),
        "W_lv": (L, V),
        "bg_v": (V,),
        "z_tot": (2,),
        "trans": (K, K),
        "X": (E, 2),
        "place": (E,),
        "concept": (E,),
        "tok_ptr": (E + 1,),
        "tok_word": (T,),
        "tok_z": (T,),
    }
    specs.update(named=(E,), alone=(E,), weight=(E,), walk_X=(meta.get("P", 0), 2))  # answers: teaching/answers.py
    kinds = {
        "place": "iu",
        "concept": "iu",
        "tok_ptr": "iu",
        "tok_word": "iu",
        "tok_z": "b",
        "named": "b",
        "alone": "b",
    }
    optional: tuple[str, ...] = ("named", "alone", "weight", "walk_X")
    if D is not None:
        specs.update(F_ld=(L, D), features=(E, D), has_features=(E,))
        kinds["has_features"] = "b"
        optional = (*optional, "F_ld", "features", "has_features")
    return {n: (shape, kinds.get(n, "f")) for n, shape in specs.items()}, optional


def read_learner(root, model: SpatialConceptModel) -> dict | None:
    """The learner member of the model folder ``root`` (None when it has none); ModelError on any problem."""
    from spcotmhp.persistence.folder import inside, read_npz

    meta = read_learner_meta(root)
    if meta is None:
        return None
    D = None if model.theta is None else int(model.theta.shape[1])
    specs, optional = learner_specs(meta, model.K, model.L, len(model.vocabulary), D)
    arrays = read_npz(inside(root, "learner.npz", "learner.npz"), specs, optional)
    features = ("F_ld", "features", "has_features")
    if D is not None and not all(n in arrays for n in features):
        for n in features:
            arrays.pop(n, None)
    member = {"replay": meta["replay"], "background": meta["background"], "arrays": arrays}
    V, found_D = len(model.vocabulary), D if "F_ld" in arrays else None
    where = str(root / "learner.npz")
    check_member(member, model.K, model.L, V, found_D, where)
    check_counts_cover_events(arrays, model.K, model.L, V, where)
    check_place_posteriors(arrays, model.hyper, where)
    return member
