"""Load a dataset folder (map.yaml + image, teaching.csv and optional extras) into a :class:`Dataset`.

The optional files (truth.csv, places.csv, adjacency.csv, image features, costmap_ros.csv) are read by
:mod:`spcotmhp.datasets.extras`.

The layout is described in ``spcotmhp/data/README.md``. Fatal problems raise :class:`DatasetError`;
recoverable ones (teaching points in walls, empty utterances, ...) emit a :class:`DatasetWarning`. Every
message names the file and the 1-based line number in it.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path
from types import FrameType

import numpy as np

from spcotmhp.datasets.alignment import align_events
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.extras import read_adjacency, read_costmap, read_features, read_places, read_truth
from spcotmhp.datasets.tables import Table, present, read_table
from spcotmhp.errors import DatasetError
from spcotmhp.language.text import words
from spcotmhp.metric.map_io import load_map, read_map_yaml
from spcotmhp.metric.maps import OCCUPIED, OccupancyMap
from spcotmhp.safe_read import require_regular_file

LANGS = ("en", "ja")
TRAJECTORY_TOLERANCE_M = 1.0  # an event further than this from its trajectory pose gets a warning
MAX_ROW_WARNINGS = 20  # per kind of problem; the rest are summarised in one warning


class DatasetWarning(UserWarning):
    """A recoverable problem in a dataset folder (the data loads, but may not be what was meant)."""


def _warn(message: str) -> None:
    """Emit a DatasetWarning attributed to the first caller outside spcotmhp.datasets."""
    frame: FrameType | None = sys._getframe(1)
    level = 2
    while frame is not None and frame.f_globals.get("__name__", "").startswith("spcotmhp.datasets"):
        frame, level = frame.f_back, level + 1
    warnings.warn(DatasetWarning(message), stacklevel=level)


def tokenize_en(text: str) -> list[str]:
    """Lower-cased words split on whitespace and punctuation ("This is the Kitchen!" -> this is the kitchen);
    an apostrophe inside a word is kept ("kitchen's"); full-width letters are letters
    (:func:`spcotmhp.language.text.words`)."""
    return words(text, "en")


def tokenize_ja(text: str) -> list[str]:
    """Japanese tokens as given: the utterances are already phrase-segmented with spaces (ASCII or U+3000); widths
    are normalised (ｷｯﾁﾝ is キッチン)."""
    return words(text, "ja", segment=False)


def features_to_counts(probabilities: np.ndarray, scale: float = 10) -> np.ndarray:
    """Image features as multinomial counts for learning: int(p * scale + 1), as the authors did with
    Places365 probabilities (scale 10), so every class has a count of at least 1."""
    p = np.asarray(probabilities, dtype=float)
    if not np.isfinite(p).all() or (p < 0).any():
        raise DatasetError("features_to_counts needs finite, non-negative probabilities")
    return (p * scale + 1).astype(np.int64)


def available_languages(path: str | Path) -> list[str]:
    """The languages ("en", "ja") that a folder's teaching.csv has words for."""
    table = read_table(Path(path) / "teaching.csv", "a header row")
    return [lang for lang in LANGS if table.has(f"words_{lang}")]


def _check_folder(folder: Path) -> Path:
    """``folder``, if it is a folder holding the two required files; else a DatasetError saying what is wrong."""
    if not folder.exists():
        raise DatasetError(f"dataset folder {folder} does not exist")
    if not folder.is_dir():
        raise DatasetError(f"{folder} is not a folder (a dataset is a folder with map.yaml and teaching.csv)")
    for required, what in (("map.yaml", "the ROS map_server YAML"), ("teaching.csv", "the teaching events")):
        require_regular_file(folder / required, f"{what} file", DatasetError)
        if not (folder / required).is_file():
            raise DatasetError(f"dataset folder {folder} has no {required} ({what})")
    return folder


def load_dataset(path: str | Path, lang: str = "en") -> Dataset:
    """Read a dataset folder.

    Args:
        path: a folder with map.yaml (+ image) and teaching.csv; optional truth.csv, places.csv,
            adjacency.csv, costmap_ros.csv, image_features_places365.csv, trajectory.csv.
        lang: "en" (tokens from words_en, lower-cased, split on whitespace and punctuation) or "ja"
            (tokens from words_ja, split on whitespace only).

    Raises:
        DatasetError: a missing folder or required file, or a file that does not parse or does not agree
            with the others (the message names the file and row). MapError: a bad map.yaml or image.
    """
    if lang not in LANGS:
        raise DatasetError(f"lang must be 'en' or 'ja', got {lang!r}")
    folder = _check_folder(Path(path))
    name = folder.resolve().name
    occupancy, image = _read_map(folder / "map.yaml")

    teaching = read_table(
        folder / "teaching.csv",
        "a header x,y,words_en (or words_ja, or both; optional event, step) and one row per teaching event",
    )
    if not teaching.rows:
        raise DatasetError("teaching.csv has a header but no teaching events")
    teaching.require(["x", "y", ("words_ja", "words_en")], ["event", "step"])
    if teaching.has("event"):  # optional: the events are the rows in file order; if given, it must agree
        teaching.sequence("event", "event ids")
    positions = np.stack([teaching.floats("x"), teaching.floats("y")], axis=1)
    _check_extent(teaching, occupancy, positions, image)
    tokens = _tokens(teaching, lang, name)
    _report_cells(teaching, occupancy, positions, image)

    trajectory, event_steps = _trajectory(folder, teaching, positions, occupancy, image)
    place_names = read_places(folder, lang)
    n_places = len(place_names) if place_names is not None else None
    truth_place, truth_concept = read_truth(folder, teaching, n_places)
    if n_places is None and truth_place is not None:
        n_places = int(truth_place.max()) + 1
    return Dataset(
        name=name,
        map=occupancy,
        positions=positions,
        tokens=tokens,
        lang=lang,
        features=read_features(folder, teaching),
        trajectory=trajectory,
        event_steps=event_steps,
        truth_place=truth_place,
        truth_concept=truth_concept,
        adjacency=read_adjacency(folder, n_places),
        place_names=place_names,
        costmap_ros=read_costmap(folder, occupancy, image),
        path=folder,
    )


def _read_map(yaml_path: Path) -> tuple[OccupancyMap, str]:
    """The map and its image's file name (for messages: "lies in an occupied cell of map.pgm")."""
    occupancy = load_map(yaml_path)
    return occupancy, read_map_yaml(yaml_path).image.name


def _tokens(teaching: Table, lang: str, name: str) -> list[list[str]]:
    column = f"words_{lang}"
    if not teaching.has(column):
        other = "ja" if lang == "en" else "en"
        hint = f"; use lang='{other}'" if teaching.has(f"words_{other}") else ""
        raise DatasetError(f"{name} has no {column} column (teaching.csv has {', '.join(teaching.header)}){hint}")
    split = tokenize_en if lang == "en" else tokenize_ja
    tokens = [split(text) for text in teaching.column(column)]
    empty = [i for i, t in enumerate(tokens) if not t]
    for i in empty[:MAX_ROW_WARNINGS]:
        text = teaching.rows[i][teaching.header.index(column)]
        _warn(f"{teaching.where(i)}: empty utterance ({column} is {text!r}); the event has no words")
    if len(empty) > MAX_ROW_WARNINGS:
        _warn(f"teaching.csv: {len(empty) - MAX_ROW_WARNINGS} more empty utterances")
    return tokens


def _report_cells(table: Table, occupancy: OccupancyMap, xy: np.ndarray, image: str, summary: bool = False):
    """Warn about points off the map or in occupied / unknown cells: one warning per row (up to
    MAX_ROW_WARNINGS of each kind), or with ``summary`` one warning per kind."""
    cells = occupancy.world_to_cell(xy)
    inside = occupancy.in_bounds(cells)
    value = np.zeros(len(xy), dtype=int)
    value[inside] = occupancy.data[cells[inside, 0], cells[inside, 1]]
    x0, y0 = occupancy.origin[0], occupancy.origin[1]
    x1, y1 = x0 + occupancy.width * occupancy.resolution, y0 + occupancy.height * occupancy.resolution
    kinds = (
        (~inside, f"off the map ({image} covers x {x0:.2f}..{x1:.2f}, y {y0:.2f}..{y1:.2f})"),
        (inside & (value >= OCCUPIED), f"in an occupied cell of {image}"),
        (inside & (value < 0), f"in an unknown cell of {image}"),
    )
    for mask, where in kinds:
        rows = np.flatnonzero(mask)
        if summary and len(rows):
            _warn(f"{table.name}: {len(rows)} of {len(xy)} points lie {where} (first on row {table.lines[rows[0]]})")
            continue
        for i in rows[:MAX_ROW_WARNINGS]:
            _warn(f"{table.where(i)}: (x, y) = ({xy[i, 0]:.2f}, {xy[i, 1]:.2f}) lies {where}")
        if len(rows) > MAX_ROW_WARNINGS:
            more = ", ".join(str(table.lines[i]) for i in rows[MAX_ROW_WARNINGS:])
            _warn(f"{table.name}: {len(rows) - MAX_ROW_WARNINGS} more points lie {where} (rows {more})")


def _check_extent(table: Table, occupancy: OccupancyMap, xy: np.ndarray, image: str) -> None:
    """Refuse points more than one map size beyond the map (a slightly-off point only gets a warning from
    :func:`_report_cells`): a coordinate of 1e308 is a corrupt row, and it would overflow the learner."""
    x0, y0 = occupancy.origin[0], occupancy.origin[1]
    x1, y1 = x0 + occupancy.width * occupancy.resolution, y0 + occupancy.height * occupancy.resolution
    margin = max(x1 - x0, y1 - y0, 1.0)
    far = (xy[:, 0] < x0 - margin) | (xy[:, 0] > x1 + margin) | (xy[:, 1] < y0 - margin) | (xy[:, 1] > y1 + margin)
    if far.any():
        i = int(np.flatnonzero(far)[0])
        raise DatasetError(
            f"{table.where(i)}: (x, y) = ({xy[i, 0]:.4g}, {xy[i, 1]:.4g}) lies far outside the map "
            f"({image} covers x {x0:.2f}..{x1:.2f}, y {y0:.2f}..{y1:.2f}; points more than "
            f"{margin:.4g} m beyond it are refused)"
        )


def _trajectory(
    folder: Path, teaching: Table, positions: np.ndarray, occupancy: OccupancyMap, image: str
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """trajectory.csv (step,x,y) and each event's step: teaching.csv's step column, else the nearest poses
    in walking order (:func:`align_events`)."""
    path = folder / "trajectory.csv"
    if not present(path):
        if teaching.has("step"):
            raise DatasetError("teaching.csv has a step column but the folder has no trajectory.csv")
        return None, None
    table = read_table(path, "a header step,x,y and one row per pose")
    if not table.rows:
        raise DatasetError("trajectory.csv has a header but no poses")
    table.require(["step", "x", "y"])
    table.sequence("step", "steps")
    trajectory = np.stack([table.floats("x"), table.floats("y")], axis=1)
    _check_extent(table, occupancy, trajectory, image)
    _report_cells(table, occupancy, trajectory, image, summary=True)
    if teaching.has("step"):
        steps = teaching.ints("step", minimum=0)
        for i in range(len(steps)):
            if steps[i] >= len(trajectory):
                raise DatasetError(
                    f"{teaching.where(i)}: step {steps[i]} is beyond trajectory.csv's last step {len(trajectory) - 1}"
                )
            if i and steps[i] < steps[i - 1]:
                raise DatasetError(
                    f"{teaching.where(i)}: step {steps[i]} is before the previous event's step "
                    f"{steps[i - 1]}; steps must not decrease"
                )
        how = "its trajectory pose"
    else:
        steps = align_events(positions, trajectory)
        how = "the nearest trajectory pose in walking order"
    gap = np.hypot(*(positions - trajectory[steps]).T)
    far = np.flatnonzero(gap > TRAJECTORY_TOLERANCE_M)
    for i in far[:MAX_ROW_WARNINGS]:
        _warn(
            f"{teaching.where(i)}: (x, y) is {gap[i]:.2f} m from {how} (step {steps[i]}, "
            f"trajectory.csv row {table.lines[steps[i]]})"
        )
    if len(far) > MAX_ROW_WARNINGS:
        _warn(
            f"teaching.csv: {len(far) - MAX_ROW_WARNINGS} more events lie over "
            f"{TRAJECTORY_TOLERANCE_M} m from their trajectory pose"
        )
    return trajectory, steps
