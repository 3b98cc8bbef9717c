"""Synthetic environments for tests and scale: a seeded floor plan plus a teaching walk, and the dataset folder.

    >>> from spcotmhp.datasets.synthetic import generate_environment, write_dataset
    >>> data = generate_environment("house", seed=3)          # 11 places, 165 teaching events
    >>> write_dataset(data, "/tmp/house-3")                   # a folder load_dataset reads back

The plan (``synthetic_plan``, layouts in ``synthetic_layouts``) and the walk (``synthetic_walk``) are documented
in their modules; this one joins them and writes the dataset folder layout of ``spcotmhp/data/README.md``.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.synthetic_plan import Door, FloorPlan, Room, generate_floor_plan, seeded_rng
from spcotmhp.datasets.synthetic_walk import teaching_walk
from spcotmhp.errors import DatasetError, MapError
from spcotmhp.metric.map_io import save_map

__all__ = ["Door", "FloorPlan", "Room", "generate_environment", "generate_floor_plan", "teaching_walk",
           "write_dataset"]


def generate_environment(kind: str = "flat", seed: int = 0, n_rooms: int | None = None,
                         size: int | tuple[int, int] | None = None, resolution: float = 0.1,
                         events_per_room: int = 15, step_m: float = 0.1, word_noise: float = 0.0,
                         insert_noise: float = 0.0, door_m: float = 1.0) -> Dataset:
    """A floor plan and a teaching walk through it, both drawn from one ``np.random.default_rng(seed)``.

    See ``generate_floor_plan`` (kind, n_rooms, size, resolution, door_m) and ``teaching_walk``
    (events_per_room, step_m, word_noise, insert_noise). The dataset is named ``synthetic-<kind>-<seed>``.
    """
    rng = seeded_rng(seed)
    plan = generate_floor_plan(kind, n_rooms=n_rooms, size=size, resolution=resolution, seed=rng, door_m=door_m)
    data = teaching_walk(plan, events_per_room=events_per_room, step_m=step_m, word_noise=word_noise,
                         insert_noise=insert_noise, seed=rng)
    data.name = f"synthetic-{kind}-{seed}"
    return data


def write_dataset(dataset: Dataset, folder: str | Path) -> Path:
    """Write ``dataset`` as a dataset folder and return its path.

    Files: map.yaml + map.pgm (Nav2 map_saver, trinary); teaching.csv ``event,x,y,words_ja,words_en[,step]``
    (tokens joined by spaces, the same words, those of ``dataset.lang``, in both words columns: synthetic
    utterances are English, so loading with lang="ja" gives the English words too); and, when the dataset has them,
    trajectory.csv ``step,x,y``, truth.csv ``event,place[,concept]``, places.csv ``place,name_ja,name_en`` (the
    same name in both columns) and adjacency.csv (a 0/1 matrix, no header). Coordinates are written with
    Python's shortest round-trip repr, so ``load_dataset`` reads back exactly the same numbers.
    """
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise DatasetError(f"cannot write a dataset to {out}: it exists and is not a folder")
    n = dataset.n_events
    if len(dataset.tokens) != n:
        raise DatasetError(f"dataset {dataset.name!r} has {n} positions but {len(dataset.tokens)} token lists")
    try:
        out.mkdir(parents=True, exist_ok=True)
        _write_files(dataset, out)
    except OSError as exc:
        raise DatasetError(f"cannot write the dataset to {out}: {exc.strerror or exc}") from None
    except MapError as exc:
        raise DatasetError(f"cannot write the dataset to {out}: {exc}") from None
    return out


def _write_files(dataset: Dataset, out: Path) -> None:
    """The files of ``write_dataset`` (OSError propagates)."""
    save_map(dataset.map, out / "map.yaml")
    words = [" ".join(tokens) for tokens in dataset.tokens]
    header = ["event", "x", "y", "words_ja", "words_en"]
    has_steps = dataset.trajectory is not None and dataset.event_steps is not None
    rows = [[e, _num(x), _num(y), w, w] for e, ((x, y), w) in enumerate(zip(dataset.positions, words))]
    if has_steps:
        header.append("step")
        rows = [row + [int(s)] for row, s in zip(rows, dataset.event_steps)]
    _write_csv(out / "teaching.csv", header, rows)
    if dataset.trajectory is not None:
        _write_csv(out / "trajectory.csv", ["step", "x", "y"],
                   [[t, _num(x), _num(y)] for t, (x, y) in enumerate(dataset.trajectory)])
    if dataset.truth_place is not None:
        concept = dataset.truth_concept
        _write_csv(out / "truth.csv", ["event", "place"] + (["concept"] if concept is not None else []),
                   [[e, int(p)] + ([int(concept[e])] if concept is not None else [])
                    for e, p in enumerate(dataset.truth_place)])
    if dataset.place_names is not None:
        _write_csv(out / "places.csv", ["place", "name_ja", "name_en"],
                   [[i, name, name] for i, name in enumerate(dataset.place_names)])
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
