"""Saving and loading a learned model as a folder: model.json + arrays.npz (+ map.yaml and its image) + manifest.

* ``model.json``: format name and version, sizes, vocabulary, hyper-parameters, cost map settings, info.
* ``arrays.npz``: mu, Sigma, psi, pi, phi, W, active_places, active_concepts and (when present) theta and
  psi_learned, written with ``np.savez`` and read member by member without numpy's loader (sizes, dtypes and
  shapes checked before any data is read; :func:`spcotmhp.learning.model_folder.read_npz`): loading a model
  executes nothing and unpickles nothing.
* ``map.yaml`` + ``map.pgm``: the occupancy map in the ROS map_server format (``metric.map_io``).
* ``learner.json`` + ``learner.npz`` (optional): the state an online learner continues from
  (:mod:`spcotmhp.learning.learner_state`); folders without them load as before; spcotmhp versions that do not
  know them load the model (ignoring them) but refuse to overwrite the folder.
* ``manifest.json``: the format version and each file's size and SHA-256 (:mod:`spcotmhp.learning.model_folder`).

Saving builds the whole folder beside the target and swaps it into place, so the previous model stays loadable
until the new one is complete; a folder holding anything but a model's files is never replaced.

Loading checks the manifest first (a torn or altered folder is refused), then every field. Format version 2
(this one) requires the manifest; folders of version 1 (written before manifests existed) still load, with
every other check, and are upgraded by saving them again. Every problem on loading (missing file, a file
leading outside the folder, corrupt JSON or npz, unknown version, sizes over the limits below, arrays that
disagree with each other or with the vocabulary, probabilities that are not distributions, a Sigma that is
not symmetric positive definite, means or covariances beyond the limits, a repeated word, hyper-parameters or
cost map settings that are unknown, not numbers, out of range or not finite, an ``info.feature_weight`` that is
not a positive number or null) raises ``ModelError`` naming the file, the field and what is wrong.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, fields
from pathlib import Path
from typing import TypeGuard

import numpy as np

from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.model_folder import check_replaceable, inside, read_npz, verify_manifest, write_folder
from spcotmhp.metric.costmap import CostMapSettings
from spcotmhp.metric.map_io import load_map, read_map_yaml, save_map
from spcotmhp.safe_read import excerpt, finite_number, load_json
from spcotmhp.safe_write import fresh_sibling

FORMAT = "spcotmhp-model"
FORMAT_VERSION = 2
READABLE_VERSIONS = (1, 2)  # 1: before the manifest (still loaded; see the module docstring)
ARRAYS = ("mu", "Sigma", "psi", "pi", "phi", "W", "active_places", "active_concepts")
OPTIONAL_ARRAYS = ("theta", "psi_learned")
MODEL_FILES = (
    "model.json",
    "arrays.npz",
    "map.yaml",
    "map.pgm",
    "map.png",
    "map.bmp",
    "learner.json",
    "learner.npz",
)
POSITIVE_HYPER = ("alpha", "gamma", "beta", "chi", "omega", "kappa0")
PROB_TOL = 1e-6
SYMMETRY_TOL = 1e-9  # relative asymmetry of a Sigma accepted (and removed) on loading
MAX_JSON_BYTES = 16 * 1024 * 1024
MAX_SIZES = {"K": 10_000, "L": 10_000, "V": 1_000_000, "D": 100_000}
MAX_ELEMENTS = 32 * 1024 * 1024  # numbers in all arrays together (256 MiB of float64)
MAX_WORD_CHARS = 256
MAX_MEAN_M = 1e6  # |mu| in metres
MAX_VARIANCE_M2 = 1e12  # Sigma's diagonal in square metres
MAX_COSTMAP = {"inscribed_radius": 1e4, "inflation_radius": 1e4, "cost_scaling_factor": 1e6}


def save_model(model: SpatialConceptModel, folder: str | Path, *, overwrite: bool = True) -> Path:
    """Write ``model`` to ``folder`` atomically (module docstring) and return the folder.

    An existing model folder is replaced (with ``overwrite=False`` it is a ModelError); a folder that holds
    files other than a model's is never replaced. Raises ModelError naming the folder and the reason."""
    out = Path(folder)
    check_target(out, overwrite)
    arrays = {name: np.asarray(getattr(model, name)) for name in ARRAYS}
    for name in OPTIONAL_ARRAYS:
        if getattr(model, name) is not None:
            arrays[name] = np.asarray(getattr(model, name))
    meta = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "K": model.K,
        "L": model.L,
        "V": len(model.vocabulary),
        "D": None if model.theta is None else int(model.theta.shape[1]),
        "vocabulary": list(model.vocabulary),
        "hyper": asdict(model.hyper),
        "costmap": dict(model.costmap),
        "map": None if model.map is None else "map.yaml",
        "info": model.info,
    }
    text = json.dumps(meta, indent=1, ensure_ascii=False, default=_json_default)
    writers = {
        "arrays.npz": lambda path: np.savez(path, allow_pickle=False, **arrays),
        "model.json": lambda path: path.write_text(text, encoding="utf-8"),
    }
    if model.learner is not None:
        from spcotmhp.learning.learner_state import learner_writers

        writers.update(learner_writers(model.learner))
    occ = model.map
    if occ is not None:
        mode = "trinary" if np.isin(np.unique(occ.data), (-1, 0, 100)).all() else "raw"
        writers["map.yaml"] = lambda path: save_map(occ, path, mode=mode)
    return write_folder(out, writers, MODEL_FILES)


def check_target(folder: Path, overwrite: bool) -> None:
    """ModelError unless ``folder`` can receive a model: absent, empty, or (with ``overwrite``) a model folder."""
    check_replaceable(folder, MODEL_FILES)
    if not overwrite and (folder / "model.json").exists():
        raise ModelError(f"{folder} already holds a model; give --overwrite to replace it, or choose another folder")


def prepare_model_folder(folder: str | Path, overwrite: bool = True) -> Path:
    """Check that a model can be saved to ``folder`` (see :func:`save_model`) and that its parent folder is
    writable, so that a command can refuse a bad ``--out`` before a long fit; creates nothing but the parent."""
    out = Path(folder)
    check_target(out, overwrite)
    try:
        fresh_sibling(out, "check").rmdir()
    except OSError as exc:
        raise ModelError(f"cannot save the model to {out}: {exc.strerror or exc}") from None
    return out


def load_model(folder: str | Path) -> SpatialConceptModel:
    """Read a model folder written by ``save_model``; raises ModelError with specifics on any problem."""
    root = Path(folder)
    if not root.is_dir():
        raise ModelError(
            f"model folder {root} does not exist{_learn_hint(root)}"
            if not root.exists()
            else f"{root} is not a folder (a model is a folder with model.json and arrays.npz)"
        )
    if (root / "teaching.csv").is_file() and not (root / "model.json").exists():
        raise ModelError(f"{root} is a dataset folder, not a model{_learn_hint(root)}")
    listed = verify_manifest(root)
    meta = _read_meta(inside(root, "model.json", "model.json"))
    if listed is None and meta["format_version"] >= 2:
        raise ModelError(
            f"{root} has no manifest.json, which a model of format version {meta['format_version']} "
            "has: the folder is torn or was altered; save the model again"
        )
    arrays = read_npz(inside(root, "arrays.npz", "arrays.npz"), _specs(meta), ("psi_learned",))
    model = _assemble(root, meta, arrays)
    from spcotmhp.learning.learner_state import read_learner

    model.learner = read_learner(root, model)
    if meta.get("map") is not None:
        yaml_path = inside(root, meta["map"], '"map"')
        try:
            inside(root, os.path.relpath(read_map_yaml(yaml_path).image, root), f"the image of {meta['map']}")
            model.map = load_map(yaml_path)
        except SpcotmhpError as exc:
            raise ModelError(f"{root}: the model's map cannot be loaded: {exc}") from None
    return model


def _learn_hint(path: Path) -> str:
    """'; learn one from it first: spcotmhp learn ...' when ``path`` is a dataset folder or names a bundled
    dataset (a model is what `learn` writes), else ''."""
    from spcotmhp.datasets.bundled import list_bundled

    if (path / "teaching.csv").is_file():
        what = ""
    elif not path.exists() and str(path) in list_bundled():
        what = f" ({path} is the name of a bundled dataset)"
    else:
        return ""
    return f"{what}; learn a model from it first: spcotmhp learn {path} --out {path.name}-model"


def _specs(meta: dict) -> dict[str, tuple[tuple[int, ...], str]]:
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


def _json_default(obj: object) -> object:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


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


def _read_meta(path: Path) -> dict:
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


def _assemble(root: Path, meta: dict, arrays: dict[str, np.ndarray]) -> SpatialConceptModel:
    K, L, V, D = meta["K"], meta["L"], meta["V"], meta.get("D")
    where = root / "arrays.npz"
    # the same table read_npz checked the members against (psi_learned is optional)
    shapes = {name: shape for name, (shape, _) in _specs(meta).items() if name != "psi_learned" or name in arrays}
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
    out["Sigma"] = _check_gaussians(where, out["mu"], out["Sigma"])
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
        hyper=_hyper(root / "model.json", meta["hyper"]),
        costmap=dict(meta["costmap"]),
        info=dict(meta["info"]),
        psi_learned=out.get("psi_learned"),
    )


def _check_gaussians(where: Path, mu: np.ndarray, sigma: np.ndarray) -> np.ndarray:
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
            f"{eig[k, 1]:.3g}); a covariance must be"
        )
    return sym


def _hyper(path: Path, raw: dict) -> Hyperparameters:
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
    if values.get("place_size") is not None and not _positive(values["place_size"]):
        raise ModelError(
            f"{path}: hyper-parameter place_size must be a finite number > 0 or null, got {values['place_size']!r}"
        )
    try:
        return Hyperparameters(**values)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{path}: bad hyper-parameters: {exc}") from None
