"""The optional files of a dataset folder (``spcotmhp/data/README.md`` describes them), each read and checked
for :func:`~spcotmhp.datasets.loader.load_dataset`: truth.csv (evaluation only), places.csv, adjacency.csv,
the image features and costmap_ros.csv. A missing file gives None; a malformed one a :class:`DatasetError` naming
the file and the 1-based line.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spcotmhp.datasets.tables import Table, present, read_matrix, read_table
from spcotmhp.errors import DatasetError
from spcotmhp.limits import MODEL_MAX_SIZES
from spcotmhp.metric.maps import OccupancyMap

FEATURES_FILE = "image_features_places365.csv"
MAX_FEATURE = 1e9  # image features are probabilities or counts; larger values are refused (they overflow counts)
MAX_LABEL = 9999  # place and concept ids in truth.csv (a dataset has at most 10,000 places or concepts)


def read_truth(folder: Path, teaching: Table, n_places: int | None) -> tuple[np.ndarray | None, np.ndarray | None]:
    """truth.csv (event,place[,concept]), one row per teaching event in any order, returned in event order;
    places must be below ``n_places`` (places.csv's count) when given."""
    path = folder / "truth.csv"
    if not present(path):
        return None, None
    table = read_table(path, "a header event,place[,concept] and one row per teaching event")
    table.require(["event", "place"], ["concept"])
    n_events = len(teaching.rows)
    events = table.ints("event")
    seen: dict[int, int] = {}
    for i, event in enumerate(events):
        if not 0 <= event < n_events:
            raise DatasetError(f"{table.where(i)}: event {event} is not in teaching.csv (events 0..{n_events - 1})")
        if event in seen:
            raise DatasetError(f"{table.where(i)}: event {event} appears twice (also on row {seen[event]})")
        seen[int(event)] = table.lines[i]
    missing = sorted(set(range(n_events)) - set(seen))
    if missing:
        listed = ", ".join(map(str, missing[:10])) + (" ..." if len(missing) > 10 else "")
        raise DatasetError(f"truth.csv has no row for {len(missing)} of teaching.csv's {n_events} events ({listed})")
    place = table.ints("place", minimum=0)
    concept = table.ints("concept", minimum=0) if table.has("concept") else None
    for column, ids in (("place", place), ("concept", concept)):
        if ids is not None and ids.max() > MAX_LABEL:
            i = int(np.argmax(ids > MAX_LABEL))
            raise DatasetError(f"{table.where(i)}: {column} {ids[i]} is too large (ids 0..{MAX_LABEL} are accepted)")
    if n_places is not None and place.max() >= n_places:
        i = int(np.argmax(place >= n_places))
        raise DatasetError(f"{table.where(i)}: place {place[i]} is not in places.csv (places 0..{n_places - 1})")
    order = np.argsort(events)
    place = place[order]
    concept = concept[order] if concept is not None else None
    return place, concept


def read_places(folder: Path, lang: str) -> list[str] | None:
    """places.csv (place,name_ja,name_en): the place names in ``lang``, index = place id."""
    path = folder / "places.csv"
    if not present(path):
        return None
    column = f"name_{lang}"
    table = read_table(path, "a header place,name_ja,name_en and one row per place")
    if not table.rows:
        raise DatasetError("places.csv has a header but no places")
    table.require(["place", column], [c for c in ("name_ja", "name_en") if c != column])
    table.sequence("place", "place ids")
    names = table.column(column)
    for i, text in enumerate(names):
        if not text:
            raise DatasetError(f"{table.where(i)}: {column} is blank")
    return names


def read_adjacency(folder: Path, n_places: int | None) -> np.ndarray | None:
    """adjacency.csv: a square, symmetric 0/1 matrix over the places with 1 on the diagonal (no header)."""
    path = folder / "adjacency.csv"
    if not present(path):
        return None
    values, lines = read_matrix(path, MODEL_MAX_SIZES["K"])  # a row per place: at most a model's places
    rows, cols = values.shape
    if rows != cols:
        raise DatasetError(f"adjacency.csv is {rows}x{cols}; it must be square (one row and column per place)")
    bad = np.argwhere((values != 0) & (values != 1))
    if len(bad):
        r, c = bad[0]
        raise DatasetError(f"adjacency.csv row {lines[r]} column {c + 1} is {values[r, c]:g}; entries must be 0 or 1")
    bad = np.argwhere(values != values.T)
    if len(bad):
        r, c = bad[0]
        raise DatasetError(
            f"adjacency.csv is not symmetric: row {lines[r]} column {c + 1} is {values[r, c]:g} "
            f"but row {lines[c]} column {r + 1} is {values[c, r]:g}"
        )
    off = np.flatnonzero(np.diag(values) != 1)
    if len(off):
        r = int(off[0])
        raise DatasetError(
            f"adjacency.csv row {lines[r]} column {r + 1} is 0; the diagonal must be 1 (a place is connected to itself)"
        )
    if n_places is not None and rows != n_places:
        source = "places.csv" if (folder / "places.csv").is_file() else "truth.csv"
        raise DatasetError(f"adjacency.csv is {rows}x{cols} but {source} has {n_places} places")
    return values.astype(np.int64)


def read_features(folder: Path, teaching: Table) -> np.ndarray | None:
    """image_features_places365.csv: one row of non-negative numbers per event (raw values kept)."""
    path = folder / FEATURES_FILE
    if not present(path):
        return None
    values, lines = read_matrix(path, MODEL_MAX_SIZES["D"], allow_header=True)  # a model's feature dimensions
    if len(values) != len(teaching.rows):
        raise DatasetError(
            f"{FEATURES_FILE} has {len(values)} rows but teaching.csv has {len(teaching.rows)} "
            "events (one row per event, in event order)"
        )
    bad = np.argwhere(values < 0)
    if len(bad):
        r, c = bad[0]
        raise DatasetError(
            f"{FEATURES_FILE} row {lines[r]} column {c + 1} is {values[r, c]:g}; features must be non-negative"
        )
    bad = np.argwhere(values > MAX_FEATURE)
    if len(bad):
        r, c = bad[0]
        raise DatasetError(
            f"{FEATURES_FILE} row {lines[r]} column {c + 1} is {values[r, c]:.4g}; "
            f"features must be at most {MAX_FEATURE:g}"
        )
    return values


def read_costmap(folder: Path, occupancy: OccupancyMap, image: str) -> np.ndarray | None:
    """costmap_ros.csv: integers -1..100 in OccupancyGrid row order, the map's size."""
    path = folder / "costmap_ros.csv"
    if not present(path):
        return None
    values, lines = read_matrix(path, occupancy.width)  # a row of the map
    if values.shape != occupancy.shape:
        raise DatasetError(
            f"costmap_ros.csv is {values.shape[0]}x{values.shape[1]} (rows x columns) but "
            f"{image} is {occupancy.height}x{occupancy.width}"
        )
    bad = np.argwhere((values != np.round(values)) | (values < -1) | (values > 100))
    if len(bad):
        r, c = bad[0]
        raise DatasetError(
            f"costmap_ros.csv row {lines[r]} column {c + 1} is {values[r, c]:g}; "
            "costs must be integers 0..100 (or -1 for unknown)"
        )
    return values.astype(np.int16)
