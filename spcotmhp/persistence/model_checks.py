"""What loading a model folder checks (:func:`spcotmhp.persistence.io.load_model`): model.json's format, version and
sizes (within the limits below), the JSON types of its fields, then the model's values through the checks that
constructing a model runs (:mod:`spcotmhp.learning.model_values`: finite values, distributions whose rows sum
to 1, means and covariances within their ranges, every Sigma symmetric positive definite and well-conditioned,
hyper-parameters and cost map settings in their documented ranges). Each problem raises one ``ModelError``
naming the file, the field and what is wrong.
"""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np

from spcotmhp.errors import ModelError, ModelValueError
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.model_values import CONCENTRATION
from spcotmhp.limits import MODEL_MAX_ELEMENTS, MODEL_MAX_SIZES
from spcotmhp.safe_read import excerpt, finite_number, load_json

FORMAT = "spcotmhp-model"
READABLE_VERSIONS = (1, 2)  # 1: before the manifest (still loaded; see spcotmhp.persistence.io)
REQUIRED_HYPER = ("alpha", "gamma", "beta", "chi", "omega")  # null in a file is refused (not "derive it")
MAX_JSON_BYTES = 16 * 1024 * 1024
MAX_SIZES = MODEL_MAX_SIZES
MAX_ELEMENTS = MODEL_MAX_ELEMENTS  # numbers in all arrays together (256 MiB of float64)
IN_MODEL_JSON = ("hyper", "costmap", "vocabulary")  # keys of model values (model_values) kept in model.json


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


IMAGE_SUFFIXES = (".pgm", ".ppm", ".pnm", ".png", ".bmp")


def file_bound(name: str, meta: dict | None = None, learner: dict | None = None) -> tuple[int, str]:
    """(bytes, why) the file ``name`` of a model folder may take, checked before it is hashed or read: JSON
    files ``MAX_JSON_BYTES`` (learner.json 4 KiB), YAML files the map YAML's 64 KiB, map images
    ``safe_read.max_image_bytes()`` (8 bytes a pixel of the pixel cap + 1 MiB), arrays.npz and learner.npz what
    their arrays need at model.json's K, L, V, D (and learner.json's E, T) (``model_folder.npz_bound``); any
    other file ``MAX_JSON_BYTES``. ``meta`` / ``learner`` (model.json, learner.json) are needed for the .npz
    files only."""
    from spcotmhp.metric.map_io import MAX_YAML_BYTES
    from spcotmhp.persistence.folder import npz_bound
    from spcotmhp.persistence.learner import LEARNER_JSON_BYTES, learner_specs
    from spcotmhp.safe_read import max_image_bytes, max_map_pixels

    if name == "learner.json":
        return LEARNER_JSON_BYTES, ""
    if name.endswith((".yaml", ".yml")):
        return MAX_YAML_BYTES, ""
    if name.lower().endswith(IMAGE_SUFFIXES):
        return max_image_bytes(), f"a map image of at most {max_map_pixels()} pixels has at most"
    if name in ("arrays.npz", "learner.npz") and meta is not None:
        K, L, V, D = meta["K"], meta["L"], meta["V"], meta.get("D")
        sizes = f"K={K}, L={L}, V={V}, D={D}"
        if name == "arrays.npz":
            return npz_bound(array_specs(meta)), f"a model of {sizes} has at most"
        if learner is not None:
            specs, _ = learner_specs(learner, K, L, V, D)
            what = f"the learner state of {learner['E']} events and {learner['T']} words ({sizes})"
            return npz_bound(specs), f"{what} has at most"
    return MAX_JSON_BYTES, ""


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
    if len(meta["vocabulary"]) != V:
        raise ModelError(f'{path}: "vocabulary" must list V = {V} words (strings)')
    weight = meta["info"].get("feature_weight")
    if weight is not None and not (finite_number(weight) and weight > 0):
        raise ModelError(
            f'{path}: "info.feature_weight" must be a positive number, or null for the authors\' '
            f"counts, got {excerpt(weight)}"
        )
    return meta


def assemble(root: Path, meta: dict, arrays: dict[str, np.ndarray]) -> SpatialConceptModel:
    """The model of ``meta`` (model.json) and ``arrays`` (arrays.npz, shapes and dtypes already checked by
    ``read_npz``); the values are checked by the model's construction (:mod:`spcotmhp.learning.model_values`),
    and a value out of range is a ModelValueError naming the file it came from."""
    hyper = read_hyper(root / "model.json", meta["hyper"])
    try:
        return SpatialConceptModel(
            mu=arrays["mu"],
            Sigma=arrays["Sigma"],
            psi=arrays["psi"],
            pi=arrays["pi"],
            phi=arrays["phi"],
            W=arrays["W"],
            vocabulary=list(meta["vocabulary"]),
            theta=arrays.get("theta"),
            active_places=arrays["active_places"],
            active_concepts=arrays["active_concepts"],
            hyper=hyper,
            costmap=dict(meta["costmap"]),
            info=dict(meta["info"]),
            psi_learned=arrays.get("psi_learned"),
        )
    except ModelValueError as exc:
        key = str(getattr(exc, "key", ""))
        where = root / ("model.json" if key.split(".")[0] in IN_MODEL_JSON else "arrays.npz")
        raise ModelValueError(f"{where}: {exc}") from None


def read_hyper(path: Path, raw: dict) -> Hyperparameters:
    """Hyper-parameters from model.json: known names only, JSON lists made tuples, and the values a saved
    model always holds not null; their ranges are checked by ``Hyperparameters`` itself (model_values.py)."""
    known = {f.name for f in fields(Hyperparameters)}
    unknown = sorted(set(raw) - known)
    if unknown:
        raise ModelError(f"{path}: unknown hyper-parameter(s) {', '.join(unknown)}")
    values = dict(raw)
    for name in REQUIRED_HYPER:
        if name in values and values[name] is None:
            low, high = CONCENTRATION
            raise ModelError(f"{path}: hyper-parameter {name} must be a finite number in [{low:g}, {high:g}], got None")
    for name in ("m0", "V0"):
        if isinstance(values.get(name), list):
            values[name] = tuple(tuple(v) if isinstance(v, list) else v for v in values[name])
    try:
        return Hyperparameters(**values)
    except ModelValueError as exc:
        raise ModelValueError(f"{path}: hyper-parameter {exc}") from None
