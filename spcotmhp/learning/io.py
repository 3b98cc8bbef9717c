"""Saving and loading a learned model as a folder: model.json + arrays.npz (+ map.yaml and its image).

* ``model.json``: format name and version, sizes, vocabulary, hyper-parameters, cost map settings, info.
* ``arrays.npz``: mu, Sigma, psi, pi, phi, W, active_places, active_concepts and (when present) theta, written
  with ``np.savez`` and read with ``allow_pickle=False``: loading a model executes nothing.
* ``map.yaml`` + ``map.pgm``: the occupancy map in the ROS map_server format (``metric.map_io``).

Every problem on loading (missing file, corrupt JSON or npz, unknown version, arrays that disagree with each
other or with the vocabulary, probabilities that are not distributions) raises ``ModelError`` naming the file
and what is wrong.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import asdict, fields
from pathlib import Path

import numpy as np

from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.metric.map_io import load_map, save_map

FORMAT = "spcotmhp-model"
FORMAT_VERSION = 1
ARRAYS = ("mu", "Sigma", "psi", "pi", "phi", "W", "active_places", "active_concepts")
PROB_TOL = 1e-6


def save_model(model: SpatialConceptModel, folder: str | Path) -> Path:
    """Write ``model`` to ``folder`` (created if needed; existing model files are replaced); returns the folder."""
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise ModelError(f"cannot save the model to {out}: it exists and is not a folder")
    out.mkdir(parents=True, exist_ok=True)
    arrays = {name: np.asarray(getattr(model, name)) for name in ARRAYS}
    if model.theta is not None:
        arrays["theta"] = np.asarray(model.theta)
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
        try:
            model.map = load_map(root / str(meta["map"]))
        except SpcotmhpError as exc:
            raise ModelError(f"{root}: the model's map cannot be loaded: {exc}") from None
    return model


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
    if not all(isinstance(w, str) for w in meta["vocabulary"]) or len(meta["vocabulary"]) != meta["V"]:
        raise ModelError(f"{path}: \"vocabulary\" must list V = {meta['V']} words (strings)")
    return meta


def _read_arrays(path: Path, with_theta: bool) -> dict[str, np.ndarray]:
    if not path.is_file():
        raise ModelError(f"{path} is missing (a model folder holds model.json and arrays.npz)")
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {name: npz[name] for name in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ModelError(f"{path} cannot be read as a numpy .npz archive of plain arrays: {exc}") from None
    needed = ARRAYS + (("theta",) if with_theta else ())
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
    for name in ("psi", "pi", "phi", "W", "theta"):
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
        costmap=dict(meta["costmap"]), info=dict(meta["info"]))


def _hyper(path: Path, raw: dict) -> Hyperparameters:
    known = {f.name for f in fields(Hyperparameters)}
    unknown = sorted(set(raw) - known)
    if unknown:
        raise ModelError(f"{path}: unknown hyper-parameter(s) {', '.join(unknown)}")
    try:
        values = dict(raw)
        if "m0" in values:
            values["m0"] = tuple(float(v) for v in values["m0"])
        if "V0" in values:
            values["V0"] = tuple(tuple(float(v) for v in row) for row in values["V0"])
        return Hyperparameters(**values)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{path}: bad hyper-parameters: {exc}") from None
