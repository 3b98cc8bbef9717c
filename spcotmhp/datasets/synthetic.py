"""Synthetic environments for tests and scale: a seeded floor plan plus a teaching walk, and the dataset folder.

    >>> import tempfile
    >>> from spcotmhp.datasets.synthetic import generate_environment, write_dataset
    >>> data = generate_environment("house", seed=3)
    >>> data.n_events, len(data.place_names)
    (165, 11)
    >>> folder = write_dataset(data, tempfile.mkdtemp() + "/house-3")  # a folder load_dataset reads back
    >>> sorted(p.name for p in folder.iterdir())
    ['adjacency.csv', 'map.pgm', 'map.yaml', 'places.csv', 'teaching.csv', 'trajectory.csv', 'truth.csv']

The plan (``synthetic_plan``, layouts in ``synthetic_layouts``) and the walk (``synthetic_walk``) are documented
in their modules; this one joins them and writes the dataset folder layout of ``spcotmhp/data/README.md``.
"""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.synthetic_plan import Door, FloorPlan, Room, generate_floor_plan, seeded_rng
from spcotmhp.datasets.synthetic_walk import check_events_per_room, teaching_walk
from spcotmhp.errors import DatasetError, MapError
from spcotmhp.metric.map_io import save_map
from spcotmhp.safe_write import fresh_sibling, swap_folder

DATASET_FILES = (
    "map.yaml",
    "map.pgm",
    "map.png",
    "map.bmp",
    "teaching.csv",
    "trajectory.csv",
    "truth.csv",
    "places.csv",
    "adjacency.csv",
    "costmap_ros.csv",
    "image_features_places365.csv",
)
"""The files a dataset folder may hold (spcotmhp/data/README.md); a folder with others is never replaced."""

__all__ = [
    "Door",
    "FloorPlan",
    "Room",
    "generate_environment",
    "generate_floor_plan",
    "teaching_walk",
    "write_dataset",
]


def generate_environment(
    kind: str = "flat",
    seed: int = 0,
    n_rooms: int | None = None,
    size: int | tuple[int, int] | None = None,
    resolution: float = 0.1,
    events_per_room: int = 15,
    step_m: float = 0.1,
    word_noise: float = 0.0,
    insert_noise: float = 0.0,
    door_m: float = 1.0,
) -> Dataset:
    """A floor plan and a teaching walk through it, both drawn from one ``np.random.default_rng(seed)``.

    See ``generate_floor_plan`` (kind, n_rooms, size, resolution, door_m) and ``teaching_walk``
    (events_per_room, step_m, word_noise, insert_noise). The dataset is named ``synthetic-<kind>-<seed>``.
    """
    check_events_per_room(events_per_room)  # before the floor plan is drawn
    rng = seeded_rng(seed)
    plan = generate_floor_plan(kind, n_rooms=n_rooms, size=size, resolution=resolution, seed=rng, door_m=door_m)
    data = teaching_walk(
        plan,
        events_per_room=events_per_room,
        step_m=step_m,
        word_noise=word_noise,
        insert_noise=insert_noise,
        seed=rng,
    )
    data.name = f"synthetic-{kind}-{seed}"
    return data


def write_dataset(dataset: Dataset, folder: str | Path, overwrite: bool = True) -> Path:
    """Write ``dataset`` as a dataset folder and return its path.

    The folder is built beside ``folder`` and swapped into place (:func:`spcotmhp.safe_write.swap_folder`):
    readers see the old dataset or the new one, and no file of an old dataset (a stale costmap_ros.csv) is
    left behind. ``folder`` must be absent, empty, or (with ``overwrite``) a dataset folder holding only the
    files of :data:`DATASET_FILES`; anything else is a DatasetError and is left untouched.

    Files: map.yaml + map.pgm (Nav2 map_saver, trinary); teaching.csv ``event,x,y,words_ja,words_en[,step]``
    (tokens joined by spaces, the same words, those of ``dataset.lang``, in both words columns: synthetic
    utterances are English, so loading with lang="ja" gives the English words too); and, when the dataset has them,
    trajectory.csv ``step,x,y``, truth.csv ``event,place[,concept]``, places.csv ``place,name_ja,name_en`` (the
    same name in both columns) and adjacency.csv (a 0/1 matrix, no header). Coordinates are written with
    Python's shortest round-trip repr, so ``load_dataset`` reads back exactly the same numbers.
    """
    out = Path(folder)
    check_dataset_target(out, overwrite)
    n = dataset.n_events
    if len(dataset.tokens) != n:
        raise DatasetError(f"dataset {dataset.name!r} has {n} positions but {len(dataset.tokens)} token lists")
    staging = None
    try:
        staging = fresh_sibling(out, "new")
        _write_files(dataset, staging)
        swap_folder(staging, out)
    except (OSError, MapError) as exc:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)
        reason = exc.strerror or exc if isinstance(exc, OSError) else exc
        raise DatasetError(f"cannot write the dataset to {out}: {reason}") from None
    except BaseException:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)
        raise
    return out


def check_dataset_target(out: Path, overwrite: bool) -> None:
    """DatasetError unless ``out`` is absent, an empty folder, or (with ``overwrite``) a dataset folder."""
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise DatasetError(f"cannot write a dataset to {out}: it exists and is not a folder")
    present = sorted(p.name for p in out.iterdir()) if out.is_dir() else []
    if not present:
        return
    others = [name for name in present if name not in DATASET_FILES]
    if others or "teaching.csv" not in present:
        listed = ", ".join((others or present)[:5])
        raise DatasetError(
            f"cannot write a dataset to {out}: the folder holds files that are not a dataset's "
            f"({listed}); choose an empty or new folder"
        )
    if not overwrite:
        raise DatasetError(f"{out} already holds a dataset; give --overwrite to replace it, or choose another folder")


def _write_files(dataset: Dataset, out: Path) -> None:
    """The files of ``write_dataset`` (OSError propagates)."""
    save_map(dataset.map, out / "map.yaml")
    words = [" ".join(tokens) for tokens in dataset.tokens]
    header = ["event", "x", "y", "words_ja", "words_en"]
    steps = dataset.event_steps if dataset.trajectory is not None else None
    rows = [[e, _num(x), _num(y), w, w] for e, ((x, y), w) in enumerate(zip(dataset.positions, words, strict=False))]
    if steps is not None:
        header.append("step")
        rows = [row + [int(s)] for row, s in zip(rows, steps, strict=False)]
    _write_csv(out / "teaching.csv", header, rows)
    if dataset.trajectory is not None:
        _write_csv(
            out / "trajectory.csv",
            ["step", "x", "y"],
            [[t, _num(x), _num(y)] for t, (x, y) in enumerate(dataset.trajectory)],
        )
    if dataset.truth_place is not None:
        concept = dataset.truth_concept
        _write_csv(
            out / "truth.csv",
            ["event", "place"] + (["concept"] if concept is not None else []),
            [
                [e, int(p)] + ([int(concept[e])] if concept is not None else [])
                for e, p in enumerate(dataset.truth_place)
            ],
        )
    if dataset.place_names is not None:
        _write_csv(
            out / "places.csv",
            ["place", "name_ja", "name_en"],
            [[i, name, name] for i, name in enumerate(dataset.place_names)],
        )
    if dataset.adjacency is not None:
        _write_csv(out / "adjacency.csv", None, np.asarray(dataset.adjacency, dtype=np.int64).tolist())


def _num(value: float) -> str:
    return repr(float(value))


def _write_csv(path: Path, header: list[str] | None, rows: list[list]) -> None:
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f, lineterminator="\n")
        if header is not None:
            writer.writerow(header)
        writer.writerows(rows)
