"""What loading a model folder checks (:func:`spcotmhp.learning.io.load_model`): model.json's format, version,
sizes (within the limits below), vocabulary, cost map settings and hyper-parameters, then every array of
arrays.npz against them: shapes, dtypes, finite values, distributions whose rows sum to 1, means and covariances
within limits, every Sigma symmetric positive definite. Each problem raises one ``ModelError`` naming the file,
the field and what is wrong.
"""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path
from typing import TypeGuard

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.limits import MODEL_MAX_SIZES
from spcotmhp.metric.costmap import CostMapSettings
from spcotmhp.safe_read import excerpt, finite_number, load_json

FORMAT = "spcotmhp-model"
READABLE_VERSIONS = (1, 2)  # 1: before the manifest (still loaded; see spcotmhp.learning.io)
POSITIVE_HYPER = ("alpha", "gamma", "beta", "chi", "omega", "kappa0")
PROB_TOL = 1e-6
SYMMETRY_TOL = 1e-9  # relative asymmetry of a Sigma accepted (and removed) on loading
MAX_JSON_BYTES = 16 * 1024 * 1024
MAX_SIZES = MODEL_MAX_SIZES
MAX_ELEMENTS = 32 * 1024 * 1024  # numbers in all arrays together (256 MiB of float64)
MAX_WORD_CHARS = 256
MAX_MEAN_M = 1e6  # |mu| in metres
MAX_VARIANCE_M2 = 1e12  # Sigma's diagonal in square metres
MAX_COSTMAP = {"inscribed_radius": 1e4, "inflation_radius": 1e4, "cost_scaling_factor": 1e6}


def array_specs(meta: dict) -> dict[str, tuple[tuple[int, ...], str]]:
    """Expected shape and dtype kinds of every array of ``meta``'s sizes."""
    K, L, V, D = meta["K"], meta["L"], meta["V"], meta.get("D")
    specs = {
        "mu": (K, 2),
        "Sigma": (K, 2, 2),
        "psi": (K, K),
        "pi": (L,),
        "phi": (L, K),
        "W": (L, V),
        "active_places": (K,),
        "active_concepts": (L,),
        "psi_learned": (K, K),
    }
    if D is not None:
        specs["theta"] = (L, D)
    return {name: (shape, "b" if name.startswith("active") else "f") for name, shape in specs.items()}


def _check_vocabulary(path: Path, vocabulary: list, V: int) -> None:
    """V distinct words (strings) of at most MAX_WORD_CHARS characters; else a one-line ModelError."""
    if not all(isinstance(w, str) for w in vocabulary) or len(vocabulary) != V:
        raise ModelError(f'{path}: "vocabulary" must list V = {V} words (strings)')
    seen: set[str] = set()
    for j, word in enumerate(vocabulary):
        if word in seen:
            raise ModelError(
                f'{path}: "vocabulary" lists {excerpt(word)} twice (again at index {j}); each word '
                "must be listed once (it names one column of W)"
            )
        if len(word) > MAX_WORD_CHARS:
            raise ModelError(
                f'{path}: "vocabulary" word {j} has {len(word)} characters; at most {MAX_WORD_CHARS} are accepted'
            )
        seen.add(word)


def read_meta(path: Path) -> dict:
    if not path.is_file():
        raise ModelError(f"{path} is missing (a model folder holds model.json and arrays.npz)")
    meta = load_json(path, MAX_JSON_BYTES, "model file", ModelError)
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ModelError(f'{path} is not a spcotmhp model (its "format" is not {FORMAT!r})')
    version = meta.get("format_version")
    if version not in READABLE_VERSIONS or isinstance(version, bool):
        raise ModelError(
            f"{path} has format version {excerpt(version)}; this spcotmhp reads versions "
            f"{', '.join(map(str, READABLE_VERSIONS))}"
        )
    for key, kind in (
        ("K", int),
        ("L", int),
        ("V", int),
        ("vocabulary", list),
        ("hyper", dict),
        ("costmap", dict),
        ("info", dict),
    ):
        if not isinstance(meta.get(key), kind) or isinstance(meta.get(key), bool):
            raise ModelError(f'{path}: "{key}" is missing or not a {kind.__name__}')
    if meta.get("D") is not None and (not isinstance(meta["D"], int) or isinstance(meta["D"], bool)):
        raise ModelError(f'{path}: "D" must be an integer or null')
    for key in ("K", "L") + (("D",) if meta.get("D") is not None else ()):
        if meta[key] < 1:
            raise ModelError(
                f'{path}: "{key}" must be >= 1, got {meta[key]} (a model has at least one place, '
                "one concept and, with features, one feature dimension)"
            )
    for key, limit in MAX_SIZES.items():
        if meta.get(key) is not None and meta[key] > limit:
            raise ModelError(f'{path}: "{key}" is {meta[key]}; at most {limit} is accepted')
    K, L, V, D = meta["K"], meta["L"], meta["V"], meta.get("D") or 0
    elements = K * 6 + 2 * K * K + L * (2 + K + V + D)
    if elements > MAX_ELEMENTS:
        raise ModelError(
            f"{path}: sizes K={K}, L={L}, V={V}, D={D or None} need {elements} numbers in arrays.npz; "
            f"at most {MAX_ELEMENTS} are accepted"
        )
    _check_vocabulary(path, meta["vocabulary"], meta["V"])
    _check_costmap(path, meta["costmap"])
    weight = meta["info"].get("feature_weight")
    if weight is not None and not _positive(weight):
        raise ModelError(
            f'{path}: "info.feature_weight" must be a positive number, or null for the authors\' '
            f"counts, got {excerpt(weight)}"
        )
    return meta


def _positive(value: object) -> bool:
    """A finite number > 0 (booleans are not numbers here)."""
    return _number(value) and bool(value > 0)


def _number(value: object) -> TypeGuard[int | float | np.integer | np.floating]:
    return finite_number(value)


def _check_costmap(path: Path, raw: dict) -> None:
    """The cost map settings must be fields of CostMapSettings: flags true/false, distances and the scaling
    factor finite numbers >= 0 and at most ``MAX_COSTMAP`` (1e4 m, 1e6)."""
    known = {f.name: f for f in fields(CostMapSettings)}
    unknown = sorted(set(raw) - set(known))
    if unknown:
        raise ModelError(
            f'{path}: unknown cost map setting(s) {", ".join(unknown)} in "costmap" (known: {", ".join(known)})'
        )
    for key, value in raw.items():
        if isinstance(known[key].default, bool):
            if not isinstance(value, bool):
                raise ModelError(f'{path}: "costmap.{key}" must be true or false, got {excerpt(value)}')
        elif not (_number(value) and 0 <= value <= MAX_COSTMAP.get(key, 0)):
            raise ModelError(
                f'{path}: "costmap.{key}" must be a finite number in 0..{MAX_COSTMAP.get(key, 0):g}, '
                f"got {excerpt(value)}"
            )


def assemble(root: Path, meta: dict, arrays: dict[str, np.ndarray]) -> SpatialConceptModel:
    K, L, V, D = meta["K"], meta["L"], meta["V"], meta.get("D")
    where = root / "arrays.npz"
    # the same table read_npz checked the members against (psi_learned is optional)
    shapes = {name: shape for name, (shape, _) in array_specs(meta).items() if name != "psi_learned" or name in arrays}
    out = {}
    for name, shape in shapes.items():
        a = arrays[name]
        if a.shape != shape:
            raise ModelError(
                f"{where}: {name} has shape {a.shape}, but model.json (K={K}, L={L}, V={V}, D={D}) needs {shape}"
            )
        if name.startswith("active"):
            if a.dtype != bool:
                raise ModelError(f"{where}: {name} must be boolean, got {a.dtype}")
            out[name] = a
            continue
        if not np.issubdtype(a.dtype, np.floating) or not np.isfinite(a).all():
            raise ModelError(f"{where}: {name} must hold finite floating-point numbers")
        out[name] = a.astype(float)
    for name in ("psi", "pi", "phi", "W", "theta", "psi_learned"):
        if name in out:
            p = out[name]
            rows = np.atleast_2d(p)
            if (p < 0).any() or np.abs(rows.sum(axis=1) - 1.0).max() > PROB_TOL:
                raise ModelError(f"{where}: {name} must be non-negative with rows summing to 1")
    out["Sigma"] = check_gaussians(where, out["mu"], out["Sigma"])
    return SpatialConceptModel(
        mu=out["mu"],
        Sigma=out["Sigma"],
        psi=out["psi"],
        pi=out["pi"],
        phi=out["phi"],
        W=out["W"],
        vocabulary=list(meta["vocabulary"]),
        theta=out.get("theta"),
        active_places=out["active_places"],
        active_concepts=out["active_concepts"],
        hyper=read_hyper(root / "model.json", meta["hyper"]),
        costmap=dict(meta["costmap"]),
        info=dict(meta["info"]),
        psi_learned=out.get("psi_learned"),
    )


def check_gaussians(where: Path, mu: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """Means within +-MAX_MEAN_M; each Sigma symmetric (up to SYMMETRY_TOL relative, then made exactly so),
    its variances at most MAX_VARIANCE_M2 and positive definite with a condition number of at most 1e12
    (a covariance planning can invert). Returns the symmetrised Sigma."""
    if len(mu) and np.abs(mu).max() > MAX_MEAN_M:
        k = int(np.argmax(np.abs(mu).max(axis=1)))
        raise ModelError(f"{where}: mu[{k}] = {mu[k].tolist()} lies beyond +-{MAX_MEAN_M:g} m")
    scale = np.maximum(np.abs(sigma).max(axis=(1, 2)), np.finfo(float).tiny)
    asym = np.abs(sigma[:, 0, 1] - sigma[:, 1, 0]) / scale
    if (asym > SYMMETRY_TOL).any():
        k = int(np.argmax(asym))
        raise ModelError(
            f"{where}: Sigma[{k}] is not symmetric ({sigma[k, 0, 1]:.6g} above the diagonal, "
            f"{sigma[k, 1, 0]:.6g} below); a covariance must be symmetric"
        )
    sym = (sigma + np.swapaxes(sigma, 1, 2)) / 2.0
    if (np.diagonal(sym, axis1=1, axis2=2) > MAX_VARIANCE_M2).any():
        k = int(np.argmax(np.diagonal(sym, axis1=1, axis2=2).max(axis=1)))
        raise ModelError(f"{where}: Sigma[{k}] has a variance over {MAX_VARIANCE_M2:g} square metres")
    eig = np.linalg.eigvalsh(sym) if len(sym) else np.ones((0, 2))
    bad = (eig[:, 0] <= 0) | (eig[:, 0] < 1e-12 * eig[:, 1])
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ModelError(
            f"{where}: Sigma[{k}] is not positive definite (eigenvalues {eig[k, 0]:.3g}, "
            f"{eig[k, 1]:.3g}); a covariance must be positive definite, its smaller eigenvalue above 1e-12 times "
            "the larger"
        )
    return sym


def read_hyper(path: Path, raw: dict) -> Hyperparameters:
    """Hyper-parameters from model.json: known names only, L and K integers >= 1, concentrations and kappa0
    finite numbers > 0, nu0 > 1, m0 two finite numbers, V0 a symmetric positive definite 2 x 2 matrix."""
    known = {f.name for f in fields(Hyperparameters)}
    unknown = sorted(set(raw) - known)
    if unknown:
        raise ModelError(f"{path}: unknown hyper-parameter(s) {', '.join(unknown)}")
    values = dict(raw)
    for name in ("L", "K"):
        if name in values and not (
            isinstance(values[name], int) and not isinstance(values[name], bool) and values[name] >= 1
        ):
            raise ModelError(f"{path}: hyper-parameter {name} must be an integer >= 1, got {values[name]!r}")
    for name in POSITIVE_HYPER:
        if name in values and not _positive(values[name]):
            raise ModelError(f"{path}: hyper-parameter {name} must be a finite number > 0, got {values[name]!r}")
    if "nu0" in values and not (_number(values["nu0"]) and values["nu0"] > 1):
        raise ModelError(
            f"{path}: hyper-parameter nu0 must be a finite number > 1 (the inverse-Wishart degrees "
            f"of freedom in 2-D), got {values['nu0']!r}"
        )
    if "m0" in values:
        m0 = values["m0"]
        if not (isinstance(m0, list) and len(m0) == 2 and all(_number(v) for v in m0)):
            raise ModelError(f"{path}: hyper-parameter m0 must be two finite numbers, got {m0!r}")
        values["m0"] = tuple(float(v) for v in m0)
    if "V0" in values:
        V0 = values["V0"]
        ok = (
            isinstance(V0, list)
            and len(V0) == 2
            and all(isinstance(r, list) and len(r) == 2 and all(_number(v) for v in r) for r in V0)
        )
        if not ok or V0[0][1] != V0[1][0] or V0[0][0] <= 0 or V0[0][0] * V0[1][1] - V0[0][1] ** 2 <= 0:
            raise ModelError(
                f"{path}: hyper-parameter V0 must be a symmetric positive definite 2 x 2 matrix of "
                f"finite numbers, got {V0!r}"
            )
        values["V0"] = tuple(tuple(float(v) for v in row) for row in V0)
    for name in ("place_size", "place_concepts", "off_name"):
        if values.get(name) is not None and not _positive(values[name]):
            raise ModelError(
                f"{path}: hyper-parameter {name} must be a finite number > 0 or null, got {values[name]!r}"
            )
    try:
        return Hyperparameters(**values)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{path}: bad hyper-parameters: {exc}") from None
