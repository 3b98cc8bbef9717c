"""Hostile model folders behind valid checksums for tests/helpers/hostile_cases.py: the templates (a supervised
model of a generated flat, a fit with its learner state, the closed-door home) and the changes made to copies of
them (values, sizes, references), each resealed so that the checks under test are reached."""

from __future__ import annotations

import json
import os
import re
import shutil
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
GIB = 1 << 30
SPARSE = 8 * GIB


def child_env() -> dict:
    """This process's environment with this checkout first on PYTHONPATH (for the processes of the cases)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


# ---- templates ----------------------------------------------------------------------------------------------
def template_model(root: Path) -> Path:
    """A supervised model of a generated four-room flat (seed 1), saved once under ``root``."""
    folder = root / "template-model"
    if not (folder / "manifest.json").is_file():
        from spcotmhp.datasets.loader import load_dataset
        from spcotmhp.datasets.synthetic import generate_environment, write_dataset
        from spcotmhp.learning.supervised import fit_supervised
        from spcotmhp.persistence.io import save_model

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = write_dataset(generate_environment("flat", seed=1, n_rooms=4), root / "template-data")
            save_model(fit_supervised(load_dataset(data)), folder)
    return folder


def learner_model(root: Path) -> Path:
    """A 4-sweep SpCoTMHP fit of the template's dataset, with its learner state (learner.json, learner.npz)."""
    folder = root / "learner-model"
    if not (folder / "manifest.json").is_file():
        from spcotmhp.datasets.loader import load_dataset
        from spcotmhp.learning.gibbs import SpCoTMHP
        from spcotmhp.persistence.io import save_model

        template_model(root)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            save_model(SpCoTMHP(iterations=4, seed=4).fit(load_dataset(root / "template-data")).model_, folder)
    return folder


def learner_edited(change: Callable[[dict], None]) -> Callable[[Path], list[str]]:
    """The learner model with its learner.npz arrays changed by ``change(arrays)`` (resealed), then `teach`."""

    def build(root: Path) -> list[str]:
        from tests.helpers.learning import reseal

        folder = root / f"m-learner-{change.__name__}"
        shutil.rmtree(folder, ignore_errors=True)
        shutil.copytree(learner_model(root), folder)
        with np.load(folder / "learner.npz") as npz:
            arrays = {k: npz[k] for k in npz.files}
        change(arrays)
        np.savez(folder / "learner.npz", **arrays)
        reseal(folder)
        x, y = template_start(root)
        return ["teach", str(folder), "this is the kitchen", "--at", f"{x:.3f}", f"{y:.3f}"]

    return build


def _counts_zeroed(a: dict) -> None:
    for name in ("n_k", "n_l", "n_lk", "W_lv", "trans"):
        a[name][...] = 0


def _scatter_negative(a: dict) -> None:
    a["sxx"][...] = -1e6


def _scatter_huge(a: dict) -> None:
    a["sx"][...] = 1e300
    a["sxx"][...] = 1e300


def _events_far(a: dict) -> None:
    a["X"][...] = 1e300


def door_model(root: Path) -> Path:
    """The four-room home of tests/helpers/planning.py with the bedroom #1 - corridor door closed: bedroom #1
    alone (the smaller region) | corridor, kitchen, bedroom #2."""
    folder = root / "door-model"
    if not (folder / "manifest.json").is_file():
        from spcotmhp.persistence.io import save_model
        from tests.helpers.planning import DOORS, EDGES, NAMES, ROOMS, SHAPE, make_home

        save_model(make_home(ROOMS, DOORS[1:], NAMES, EDGES, SHAPE), folder)
    return folder


def door_plan(instruction: str, row: int, col: int) -> Callable[[Path], list[str]]:
    """`plan` on the closed-door home from the cell (row, col)."""

    def build(root: Path) -> list[str]:
        from spcotmhp.persistence.io import load_model

        x, y = load_model(door_model(root)).require_map().cell_to_world(np.array([row, col]))
        return ["plan", str(door_model(root)), instruction, "--start", f"{x:.3f}", f"{y:.3f}"]

    return build


def copy_model(root: Path, name: str) -> Path:
    folder = root / name
    if folder.exists():
        shutil.rmtree(folder)
    shutil.copytree(template_model(root), folder)
    return folder


def plan_args(folder: Path) -> list[str]:
    """`plan FOLDER "go to the <first word>" --start <a free cell of the template>`."""
    meta = json.loads((template_model(folder.parent) / "model.json").read_text(encoding="utf-8"))
    word = "kitchen" if "kitchen" in meta["vocabulary"] else meta["vocabulary"][0]
    x, y = template_start(folder.parent)
    return ["plan", str(folder), f"go to the {word}", "--start", f"{x:.3f}", f"{y:.3f}"]


def template_start(root: Path) -> tuple[float, float]:
    cache = root / "template-start.json"
    if not cache.is_file():
        from spcotmhp.persistence.io import load_model

        model = load_model(template_model(root))
        occ = model.require_map()
        rows, cols = np.nonzero(occ.data == 0)
        centre = np.array(occ.data.shape) / 2
        i = int(np.argmin((rows - centre[0]) ** 2 + (cols - centre[1]) ** 2))
        cache.write_text(json.dumps(occ.cell_to_world(np.array([rows[i], cols[i]])).tolist()), encoding="utf-8")
    x, y = json.loads(cache.read_text(encoding="utf-8"))
    return float(x), float(y)


def edited(*edits: tuple) -> Callable[[Path], list[str]]:
    """A model folder with ``edits`` (tests/helpers/strategies.py ``apply_edits``: resealed), then `plan`."""

    def build(root: Path) -> list[str]:
        from tests.helpers.strategies import apply_edits

        folder = copy_model(root, "m-" + re.sub(r"\W+", "-", str(edits))[:60])
        apply_edits(folder, list(edits))
        return plan_args(folder)

    return build


def rewritten(change: Callable[[Path], None]) -> Callable[[Path], list[str]]:
    """A model folder changed by ``change(folder)`` and resealed, then `plan`."""

    def build(root: Path) -> list[str]:
        from tests.helpers.learning import reseal

        folder = copy_model(root, "m-" + change.__name__)
        change(folder)
        reseal(folder)
        return plan_args(folder)

    return build


def _arrays(folder: Path) -> dict:
    with np.load(folder / "arrays.npz") as npz:
        return {k: npz[k] for k in npz.files}


def _meta(folder: Path, **changes) -> None:
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    for key, value in changes.items():
        where = meta
        *path, last = key.split("__")
        for part in path:
            where = where[part]
        where[last] = value
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def grown(name: str, size: int, list_size: bool) -> Callable[[Path], list[str]]:
    """The file ``name`` of a model folder grown (sparse) to ``size`` bytes; with ``list_size`` the manifest lists
    the new size (its checksum stale), so the size check itself, not the manifest's, must refuse it."""

    def build(root: Path) -> list[str]:
        folder = copy_model(root, f"m-grown-{name}-{list_size}")
        with open(folder / name, "r+b") as handle:
            handle.truncate(size)
        if list_size:
            manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
            manifest["files"][name]["bytes"] = size
            (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
        return plan_args(folder)

    return build


def learner_grown(root: Path) -> list[str]:
    """learner.json raised to its largest E and T (resealed), learner.npz grown to what they allow (sparse) and
    listed so: the bound the learner state allows, hashed."""
    from spcotmhp.persistence.learner import MAX_EVENTS, MAX_TOKENS
    from spcotmhp.persistence.model_checks import file_bound
    from tests.helpers.learning import reseal

    folder = copy_model(root, "m-learner-grown")
    if not (folder / "learner.json").is_file():
        (folder / "learner.json").write_text(
            json.dumps({"format": "spcotmhp-learner", "format_version": 1, "replay": True, "background": False}),
            encoding="utf-8",
        )
        (folder / "learner.npz").write_bytes(b"")
    learner = json.loads((folder / "learner.json").read_text(encoding="utf-8"))
    learner.update(E=MAX_EVENTS, T=MAX_TOKENS)
    (folder / "learner.json").write_text(json.dumps(learner), encoding="utf-8")
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    size, _ = file_bound("learner.npz", meta, learner)
    (folder / "learner.npz").write_bytes(b"")
    reseal(folder)  # the small files with real checksums; learner.npz listed by its size (a stale checksum)
    with open(folder / "learner.npz", "r+b") as handle:
        handle.truncate(size)
    manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    manifest["files"]["learner.npz"]["bytes"] = size
    (folder / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    return plan_args(folder)


def _mu_far(folder: Path) -> None:
    a = _arrays(folder)
    a["mu"][:] = 9.9e5
    np.savez(folder / "arrays.npz", **a)


def _sigma_not_pd(folder: Path) -> None:
    a = _arrays(folder)
    a["Sigma"][0] = [[1.0, 2.0], [2.0, 1.0]]
    np.savez(folder / "arrays.npz", **a)


def _phi_negative(folder: Path) -> None:
    a = _arrays(folder)
    a["phi"][0, 1] += a["phi"][0, 0] + 0.25
    a["phi"][0, 0] = -0.25
    np.savez(folder / "arrays.npz", **a)


def _no_active_places(folder: Path) -> None:
    a = _arrays(folder)
    a["active_places"][:] = False
    np.savez(folder / "arrays.npz", **a)


def _float16_mu(folder: Path) -> None:
    a = _arrays(folder)
    with np.errstate(over="ignore"):  # the overflow to inf is the point
        a["mu"] = a["mu"].astype(np.float16) * np.float16(60000)
    np.savez(folder / "arrays.npz", **a)


def _extra_member(folder: Path) -> None:
    a = _arrays(folder)
    a["../../evil"] = np.zeros(3)
    np.savez(folder / "arrays.npz", **a)


def _theta_without_D(folder: Path) -> None:
    a = _arrays(folder)
    a["theta"] = np.full((len(a["pi"]), 3), 1 / 3)
    np.savez(folder / "arrays.npz", **a)


def _empty_word(folder: Path) -> None:
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta["vocabulary"][-1] = ""
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def _space_word(folder: Path) -> None:
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta["vocabulary"][-1] = " \n\t"
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def _huge_int_K(folder: Path) -> None:
    text = (folder / "model.json").read_text(encoding="utf-8")
    (folder / "model.json").write_text(re.sub(r'"K": \d+', '"K": ' + "9" * 5000, text, count=1), encoding="utf-8")


def _deep_info(folder: Path) -> None:
    text = (folder / "model.json").read_text(encoding="utf-8")
    deep = '"info": {"x": ' + "[" * 100_000 + "]" * 100_000 + ", "
    (folder / "model.json").write_text(text.replace('"info": {', deep, 1), encoding="utf-8")


def _map_resolution(folder: Path) -> None:
    text = (folder / "map.yaml").read_text(encoding="utf-8")
    (folder / "map.yaml").write_text(re.sub(r"resolution: .*", "resolution: 1e-300", text), encoding="utf-8")


def _map_origin(folder: Path) -> None:
    text = (folder / "map.yaml").read_text(encoding="utf-8")
    (folder / "map.yaml").write_text(re.sub(r"origin: .*", "origin: [1e308, -1e308, 0.0]", text), encoding="utf-8")


def _map_is(target: str) -> Callable[[Path], None]:
    def change(folder: Path) -> None:
        _meta(folder, map=target)

    change.__name__ = "_map_is_" + re.sub(r"\W+", "_", target)
    return change


def _image_fifo(folder: Path) -> None:
    """map.yaml's image a named pipe (unlisted in the manifest): opening it for reading would block."""
    os.mkfifo(folder / "pipe.pgm")
    text = (folder / "map.yaml").read_text(encoding="utf-8")
    (folder / "map.yaml").write_text(re.sub(r"image: .*", "image: pipe.pgm", text), encoding="utf-8")


def _psi_identity(folder: Path) -> None:
    a = _arrays(folder)
    a["psi"] = np.eye(len(a["psi"]))
    np.savez(folder / "arrays.npz", **a)


def _W_one_word(folder: Path) -> None:
    a = _arrays(folder)
    a["W"][:] = 0.0
    a["W"][:, 0] = 1.0
    np.savez(folder / "arrays.npz", **a)
