"""Saving and loading a learned model as a folder: model.json + arrays.npz (+ map.yaml and its image).

* ``model.json``: format name and version, sizes, vocabulary, hyper-parameters, cost map settings, info.
* ``arrays.npz``: mu, Sigma, psi, pi, phi, W, active_places, active_concepts and (when present) theta and
  psi_learned, written with ``np.savez`` and read with ``allow_pickle=False``: loading a model executes nothing.
* ``map.yaml`` + ``map.pgm``: the occupancy map in the ROS map_server format (``metric.map_io``).

Every problem on loading (missing file, corrupt JSON or npz, unknown version, arrays that disagree with each
other or with the vocabulary, probabilities that are not distributions, sizes below 1, a repeated word,
hyper-parameters or cost map settings that are unknown, not numbers, negative or not finite, an
``info.feature_weight`` that is not a positive number or null, a map outside the model folder) raises
``ModelError`` naming the file, the field and what is wrong.
"""

from __future__ import annotations

import json
import math
import tempfile
import zipfile
from dataclasses import asdict, fields
from pathlib import Path

import numpy as np

from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.metric.costmap import CostMapSettings
from spcotmhp.metric.map_io import load_map, read_map_yaml, save_map

FORMAT = "spcotmhp-model"
FORMAT_VERSION = 1
ARRAYS = ("mu", "Sigma", "psi", "pi", "phi", "W", "active_places", "active_concepts")
OPTIONAL_ARRAYS = ("theta", "psi_learned")
POSITIVE_HYPER = ("alpha", "gamma", "beta", "chi", "omega", "kappa0")
PROB_TOL = 1e-6


def save_model(model: SpatialConceptModel, folder: str | Path) -> Path:
    """Write ``model`` to ``folder`` (created if needed; existing model files are replaced); returns the folder."""
    out = prepare_model_folder(folder)
    arrays = {name: np.asarray(getattr(model, name)) for name in ARRAYS}
    for name in OPTIONAL_ARRAYS:
        if getattr(model, name) is not None:
            arrays[name] = np.asarray(getattr(model, name))
    meta = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "K": model.K, "L": model.L, "V": len(model.vocabulary),
        "D": None if model.theta is None else int(model.theta.shape[1]),
        "vocabulary": list(model.vocabulary),
        "hyper": asdict(model.hyper),
        "costmap": dict(model.costmap),
        "map": None if model.map is None else "map.yaml",
        "info": model.info,
    }
    try:
        np.savez(out / "arrays.npz", **arrays)
        (out / "model.json").write_text(json.dumps(meta, indent=1, ensure_ascii=False, default=_json_default),
                                        encoding="utf-8")
        if model.map is not None:
            values = np.unique(model.map.data)
            mode = "trinary" if np.isin(values, (-1, 0, 100)).all() else "raw"
            save_map(model.map, out / "map.yaml", mode=mode)
    except OSError as exc:
        raise ModelError(f"cannot save the model to {out}: {exc}") from None
    return out


def prepare_model_folder(folder: str | Path) -> Path:
    """Create ``folder`` (and its parents) if needed and check that files can be written in it, so that a
    command can refuse a bad ``--out`` before a long fit; raises ModelError naming the folder and the reason."""
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise ModelError(f"cannot save the model to {out}: it exists and is not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out):
            pass
    except OSError as exc:
        raise ModelError(f"cannot save the model to {out}: {exc.strerror or exc}") from None
    return out


def load_model(folder: str | Path) -> SpatialConceptModel:
    """Read a model folder written by ``save_model``; raises ModelError with specifics on any problem."""
    root = Path(folder)
    if not root.is_dir():
        raise ModelError(f"model folder {root} does not exist" if not root.exists()
                         else f"{root} is not a folder (a model is a folder with model.json and arrays.npz)")
    meta = _read_meta(root / "model.json")
    arrays = _read_arrays(root / "arrays.npz", meta.get("D") is not None)
    model = _assemble(root, meta, arrays)
    if meta.get("map") is not None:
        yaml_path = _inside(root, meta["map"], "\"map\"")
        try:
            _inside(root, read_map_yaml(yaml_path).image, f"the image of {meta['map']}")
            model.map = load_map(yaml_path)
        except SpcotmhpError as exc:
            raise ModelError(f"{root}: the model's map cannot be loaded: {exc}") from None
    return model


def _inside(root: Path, name: object, what: str) -> Path:
    """``root / name`` when it is a file name inside the model folder ``root``; ModelError otherwise."""
    if not isinstance(name, (str, Path)) or not str(name).strip():
        raise ModelError(f"{root / 'model.json'}: {what} must be a file name, got {name!r}")
    path = root / name
    if not path.resolve().is_relative_to(root.resolve()):
        raise ModelError(f"{root / 'model.json'}: {what} must be a file inside the model folder {root}, "
                         f"got {str(name)!r}")
    return path


def _json_default(obj: object) -> object:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


def _read_meta(path: Path) -> dict:
    if not path.is_file():
        raise ModelError(f"{path} is missing (a model folder holds model.json and arrays.npz)")
    try:
        meta = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"{path} is not valid JSON: {exc}") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ModelError(f"{path} is not a spcotmhp model (its \"format\" is not {FORMAT!r})")
    version = meta.get("format_version")
    if version != FORMAT_VERSION:
        raise ModelError(f"{path} has format version {version!r}; this spcotmhp reads version {FORMAT_VERSION}")
    for key, kind in (("K", int), ("L", int), ("V", int), ("vocabulary", list), ("hyper", dict),
                      ("costmap", dict), ("info", dict)):
        if not isinstance(meta.get(key), kind) or isinstance(meta.get(key), bool):
            raise ModelError(f"{path}: \"{key}\" is missing or not a {kind.__name__}")
    if meta.get("D") is not None and (not isinstance(meta["D"], int) or isinstance(meta["D"], bool)):
        raise ModelError(f"{path}: \"D\" must be an integer or null")
    for key in ("K", "L") + (("D",) if meta.get("D") is not None else ()):
        if meta[key] < 1:
            raise ModelError(f"{path}: \"{key}\" must be >= 1, got {meta[key]} (a model has at least one place, "
                             "one concept and, with features, one feature dimension)")
    if not all(isinstance(w, str) for w in meta["vocabulary"]) or len(meta["vocabulary"]) != meta["V"]:
        raise ModelError(f"{path}: \"vocabulary\" must list V = {meta['V']} words (strings)")
    seen: set[str] = set()
    for j, word in enumerate(meta["vocabulary"]):
        if word in seen:
            raise ModelError(f"{path}: \"vocabulary\" lists {word!r} twice (again at index {j}); each word must "
                             "be listed once (it names one column of W)")
        seen.add(word)
    _check_costmap(path, meta["costmap"])
    weight = meta["info"].get("feature_weight")
    if weight is not None and not _positive(weight):
        raise ModelError(f"{path}: \"info.feature_weight\" must be a positive number, or null for the authors' "
                         f"counts, got {weight!r}")
    return meta


def _positive(value: object) -> bool:
    """A finite number > 0 (booleans are not numbers here)."""
    return _number(value) and value > 0


def _number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _check_costmap(path: Path, raw: dict) -> None:
    """The cost map settings must be fields of CostMapSettings: flags true/false, distances and the scaling
    factor finite numbers >= 0."""
    known = {f.name: f for f in fields(CostMapSettings)}
    unknown = sorted(set(raw) - set(known))
    if unknown:
        raise ModelError(f"{path}: unknown cost map setting(s) {', '.join(unknown)} in \"costmap\" (known: "
                         f"{', '.join(known)})")
    for key, value in raw.items():
        if isinstance(known[key].default, bool):
            if not isinstance(value, bool):
                raise ModelError(f"{path}: \"costmap.{key}\" must be true or false, got {value!r}")
        elif not (_number(value) and value >= 0):
            raise ModelError(f"{path}: \"costmap.{key}\" must be a finite number >= 0, got {value!r}")


def _read_arrays(path: Path, with_theta: bool) -> dict[str, np.ndarray]:
    if not path.is_file():
        raise ModelError(f"{path} is missing (a model folder holds model.json and arrays.npz)")
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {name: npz[name] for name in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ModelError(f"{path} cannot be read as a numpy .npz archive of plain arrays: {exc}") from None
    needed = ARRAYS + (("theta",) if with_theta else ())
    extra = sorted(set(arrays) - set(ARRAYS) - set(OPTIONAL_ARRAYS))
    if extra:
        raise ModelError(f"{path} holds unknown array(s) {', '.join(extra)}")
    missing = [name for name in needed if name not in arrays]
    if missing:
        raise ModelError(f"{path} lacks the array(s) {', '.join(missing)}")
    return arrays


def _assemble(root: Path, meta: dict, arrays: dict[str, np.ndarray]) -> SpatialConceptModel:
    K, L, V, D = meta["K"], meta["L"], meta["V"], meta.get("D")
    where = root / "arrays.npz"
    shapes = {"mu": (K, 2), "Sigma": (K, 2, 2), "psi": (K, K), "pi": (L,), "phi": (L, K), "W": (L, V),
              "active_places": (K,), "active_concepts": (L,)}
    if D is not None:
        shapes["theta"] = (L, D)
    if "psi_learned" in arrays:
        shapes["psi_learned"] = (K, K)
    out = {}
    for name, shape in shapes.items():
        a = arrays[name]
        if a.shape != shape:
            raise ModelError(f"{where}: {name} has shape {a.shape}, but model.json (K={K}, L={L}, V={V}, D={D}) "
                             f"needs {shape}")
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
    det = out["Sigma"][:, 0, 0] * out["Sigma"][:, 1, 1] - out["Sigma"][:, 0, 1] * out["Sigma"][:, 1, 0]
    if (out["Sigma"][:, 0, 0] <= 0).any() or (det <= 0).any():
        k = int(np.flatnonzero((out["Sigma"][:, 0, 0] <= 0) | (det <= 0))[0])
        raise ModelError(f"{where}: Sigma[{k}] is not positive definite")
    return SpatialConceptModel(
        mu=out["mu"], Sigma=out["Sigma"], psi=out["psi"], pi=out["pi"], phi=out["phi"], W=out["W"],
        vocabulary=list(meta["vocabulary"]), theta=out.get("theta"), active_places=out["active_places"],
        active_concepts=out["active_concepts"], hyper=_hyper(root / "model.json", meta["hyper"]),
        costmap=dict(meta["costmap"]), info=dict(meta["info"]), psi_learned=out.get("psi_learned"))


def _hyper(path: Path, raw: dict) -> Hyperparameters:
    """Hyper-parameters from model.json: known names only, L and K integers >= 1, concentrations and kappa0
    finite numbers > 0, nu0 > 1, m0 two finite numbers, V0 a symmetric positive definite 2 x 2 matrix."""
    known = {f.name for f in fields(Hyperparameters)}
    unknown = sorted(set(raw) - known)
    if unknown:
        raise ModelError(f"{path}: unknown hyper-parameter(s) {', '.join(unknown)}")
    values = dict(raw)
    for name in ("L", "K"):
        if name in values and not (isinstance(values[name], int) and not isinstance(values[name], bool)
                                   and values[name] >= 1):
            raise ModelError(f"{path}: hyper-parameter {name} must be an integer >= 1, got {values[name]!r}")
    for name in POSITIVE_HYPER:
        if name in values and not _positive(values[name]):
            raise ModelError(f"{path}: hyper-parameter {name} must be a finite number > 0, got {values[name]!r}")
    if "nu0" in values and not (_number(values["nu0"]) and values["nu0"] > 1):
        raise ModelError(f"{path}: hyper-parameter nu0 must be a finite number > 1 (the inverse-Wishart degrees "
                         f"of freedom in 2-D), got {values['nu0']!r}")
    if "m0" in values:
        m0 = values["m0"]
        if not (isinstance(m0, list) and len(m0) == 2 and all(_number(v) for v in m0)):
            raise ModelError(f"{path}: hyper-parameter m0 must be two finite numbers, got {m0!r}")
        values["m0"] = tuple(float(v) for v in m0)
    if "V0" in values:
        V0 = values["V0"]
        ok = (isinstance(V0, list) and len(V0) == 2
              and all(isinstance(r, list) and len(r) == 2 and all(_number(v) for v in r) for r in V0))
        if not ok or V0[0][1] != V0[1][0] or V0[0][0] <= 0 or V0[0][0] * V0[1][1] - V0[0][1] ** 2 <= 0:
            raise ModelError(f"{path}: hyper-parameter V0 must be a symmetric positive definite 2 x 2 matrix of "
                             f"finite numbers, got {V0!r}")
        values["V0"] = tuple(tuple(float(v) for v in row) for row in V0)
    try:
        return Hyperparameters(**values)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{path}: bad hyper-parameters: {exc}") from None
