"""Saving and loading a learned model as a folder: model.json + arrays.npz (+ map.yaml and its image) + manifest.

* ``model.json``: format name and version, sizes, vocabulary, hyper-parameters, cost map settings, info.
* ``arrays.npz``: mu, Sigma, psi, pi, phi, W, active_places, active_concepts and (when present) theta and
  psi_learned, written with ``np.savez`` and read member by member without numpy's loader (sizes, dtypes and
  shapes checked before any data is read; :func:`spcotmhp.persistence.folder.read_npz`): loading a model
  executes nothing and unpickles nothing.
* ``map.yaml`` + ``map.pgm``: the occupancy map in the ROS map_server format (``metric.map_io``).
* ``learner.json`` + ``learner.npz`` (optional): the state an online learner continues from
  (:mod:`spcotmhp.learning.learner_state`); folders without them load as before; spcotmhp versions that do not
  know them load the model (ignoring them) but refuse to overwrite the folder.
* ``manifest.json``: the format version and each file's size and SHA-256 (:mod:`spcotmhp.persistence.folder`).

Saving builds the whole folder beside the target and swaps it into place, so the previous model stays loadable
until the new one is complete; a folder holding anything but a model's files is never replaced.

Loading checks the manifest first (a torn or altered folder is refused), then every field. Format version 2
(this one) requires the manifest; folders of version 1 (written before manifests existed) still load, with
every other check, and are upgraded by saving them again. Every problem on loading (missing file, a file
leading outside the folder, corrupt JSON or npz, unknown version, sizes over the limits below, arrays that
disagree with each other or with the vocabulary, probabilities that are not distributions, a Sigma that is
not symmetric positive definite, means or covariances beyond the limits, a repeated word, hyper-parameters or
cost map settings that are unknown, not numbers, out of range or not finite, an ``info.feature_weight`` that is
not a positive number or null) raises ``ModelError`` naming the file, the field and what is wrong
(:mod:`spcotmhp.persistence.model_checks`).
"""

from __future__ import annotations

import functools
import json
import os
from collections.abc import Callable, Mapping
from dataclasses import asdict
from pathlib import Path

import numpy as np

from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.map_io import load_map, read_map_yaml, save_map
from spcotmhp.persistence.folder import (
    check_replaceable,
    check_sizes,
    inside,
    read_manifest,
    read_npz,
    verify_digests,
    write_folder,
)
from spcotmhp.persistence.model_checks import FORMAT, array_specs, assemble, file_bound, read_meta
from spcotmhp.safe_write import fresh_sibling

FORMAT_VERSION = 2
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
    "building.json",
    "graph.json",
    "graph.npz",
)
GRAPH_FILES = ("graph.json", "graph.npz")
"""The saved planning graph (:mod:`spcotmhp.planning.graph_store`): checked when a planner loads it, not by
``load_model`` (a damaged graph is rebuilt with a note; the model still loads)."""
EXTRA_FILES = ("building.json",)
"""JSON files a caller may save beside the model (``save_model(extra=...)``): a building model's floors and
connectors (:mod:`spcotmhp.building.io`). ``load_model`` checks them against the manifest and ignores them."""


def save_model(
    model: SpatialConceptModel,
    folder: str | Path,
    *,
    overwrite: bool = False,
    extra: dict[str, str] | None = None,
    files: Mapping[str, Callable[[Path], object]] | None = None,
) -> Path:
    """Write ``model`` to ``folder`` atomically (module docstring) and return the folder; ``extra``: the texts of
    further files of :data:`EXTRA_FILES` to write with it (listed in the manifest); ``files``: the writers of the
    model's planning graph (:data:`GRAPH_FILES`: :func:`spcotmhp.planning.graph_store.graph_writers`).

    An existing model folder is replaced only with ``overwrite=True`` (else a ModelError, as the CLI refuses
    without --overwrite); a folder that holds files other than a model's is never replaced. Raises ModelError
    naming the folder and the reason."""
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
    text = json.dumps(meta, indent=1, ensure_ascii=False, default=json_default)
    writers = {
        "arrays.npz": lambda path: np.savez(path, allow_pickle=False, **arrays),
        "model.json": lambda path: path.write_text(text, encoding="utf-8"),
    }
    if model.learner is not None:
        from spcotmhp.persistence.learner import learner_writers

        writers.update(learner_writers(model.learner))
    for name, content in (extra or {}).items():
        if name not in EXTRA_FILES:
            raise ModelError(f"save_model: {name!r} is not a file a model folder holds beside the model")
        writers[name] = functools.partial(_write_text, text=content)
    for name, write in (files or {}).items():
        if name not in GRAPH_FILES:
            raise ModelError(f"save_model: {name!r} is not a planning graph's file ({', '.join(GRAPH_FILES)})")
        writers[name] = write
    occ = model.map
    if occ is not None:
        mode = "trinary" if np.isin(np.unique(occ.data), (-1, 0, 100)).all() else "raw"
        writers["map.yaml"] = lambda path: save_map(occ, path, mode=mode)
    return write_folder(out, writers, MODEL_FILES)


def check_target(folder: Path, overwrite: bool, advice: str = "choose an empty or new folder") -> None:
    """ModelError unless ``folder`` can receive a model: absent, empty, or (with ``overwrite``) a model folder;
    ``advice`` ends the message about a folder holding other files."""
    check_replaceable(folder, MODEL_FILES, advice)
    if not overwrite and (folder / "model.json").exists():
        raise ModelError(
            f"{folder} already holds a model; give --overwrite (overwrite=True) to replace it, or choose another folder"
        )


def prepare_model_folder(folder: str | Path, overwrite: bool = False) -> Path:
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
    if not isinstance(folder, (str, os.PathLike)):
        raise ModelError(f"load_model takes a model folder (a str or a path), got {type(folder).__name__}")
    root = Path(folder)
    if not root.is_dir():
        raise ModelError(
            f"model folder {root} does not exist{_learn_hint(root)}"
            if not root.exists()
            else f"{root} is not a folder (a model is a folder with model.json and arrays.npz)"
        )
    if (root / "teaching.csv").is_file() and not (root / "model.json").exists():
        raise ModelError(f"{root} is a dataset folder, not a model{_learn_hint(root)}")
    meta = _verified_meta(root)
    arrays = read_npz(inside(root, "arrays.npz", "arrays.npz"), array_specs(meta), ("psi_learned",))
    model = assemble(root, meta, arrays)
    from spcotmhp.persistence.learner import read_learner

    model.learner = read_learner(root, model)
    if meta.get("map") is not None:
        yaml_path = inside(root, meta["map"], '"map"')
        try:
            inside(root, os.path.relpath(read_map_yaml(yaml_path).image, root), f"the image of {meta['map']}")
            model.map = load_map(yaml_path)
        except SpcotmhpError as exc:
            raise ModelError(f"{root}: the model's map cannot be loaded: {exc}") from None
    model.folder = root  # where a saved planning graph is looked up (spcotmhp.planning.graph_store)
    return model


def _verified_meta(root: Path) -> dict:
    """model.json of ``root`` after the manifest's checks, sizes first (:mod:`~spcotmhp.persistence.folder`):
    every listed file's size against the manifest (a stat), the small files' sizes against their bounds, their
    checksums, model.json read; then the other files' sizes against what model.json's sizes allow, and their
    checksums. Nothing large is read before its size is known to fit."""
    from spcotmhp.persistence.learner import read_learner_meta

    entries = read_manifest(root, skip=GRAPH_FILES)
    names = sorted(entries) if entries is not None else [n for n in MODEL_FILES if (root / n).is_file()]
    names = [n for n in names if n not in GRAPH_FILES]  # checked when a planner loads the graph
    small = [n for n in names if n.endswith((".json", ".yaml", ".yml"))]
    check_sizes(root, small, file_bound)
    if entries is not None:
        verify_digests(root, entries, small)
    meta = read_meta(inside(root, "model.json", "model.json"))
    if entries is None and meta["format_version"] >= 2:
        raise ModelError(
            f"{root} has no manifest.json, which a model of format version {meta['format_version']} "
            "has: the folder is torn or was altered; save the model again"
        )
    learner = read_learner_meta(root)
    if learner is not None:
        from spcotmhp.persistence.learner import check_learner_size, learner_specs

        specs, _ = learner_specs(learner, meta["K"], meta["L"], meta["V"], meta.get("D"))
        check_learner_size(specs, learner["E"], learner["T"], str(root / "learner.json"))
    large = [n for n in names if n not in small]
    check_sizes(root, large, lambda name: file_bound(name, meta, learner))
    if entries is not None:
        verify_digests(root, entries, large)
    return meta


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


def _write_text(path: Path, text: str) -> None:
    path.write_text(text, encoding="utf-8")


def json_default(obj: object) -> object:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")
