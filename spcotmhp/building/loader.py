"""Load a building folder: building.yaml (:mod:`spcotmhp.building.spec`) and each floor's dataset folder.

    >>> import tempfile
    >>> from spcotmhp.building.synthetic import generate_building, write_building
    >>> folder = write_building(generate_building(2, seed=0, n_rooms=5, events_per_room=4), tempfile.mkdtemp() + "/b")
    >>> b = load_building(folder)
    >>> b.spec.indices, [c.kind for c in b.spec.connectors]
    ([1, 2], ['lift'])

Every floor loads with :func:`~spcotmhp.datasets.loader.load_dataset` (its errors keep their type and gain the
floor: "floor 2 (first, f2): teaching.csv row 4: ..."); then the building's own checks: the floors share a
language and a map resolution, each connector stop lies on a free cell of its floor's map, and the floors side by
side fit the map bounds (:class:`~spcotmhp.building.layout.Layout`). Each failure is one BuildingError line.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from spcotmhp.building.layout import Layout
from spcotmhp.building.spec import SPEC_FILE, BuildingSpec, read_spec
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.loader import available_languages, load_dataset
from spcotmhp.errors import BuildingError, DatasetError, SpcotmhpError
from spcotmhp.metric.maps import FREE, OccupancyMap


@dataclass
class Building:
    """A building: its spec and one :class:`~spcotmhp.datasets.dataset.Dataset` per floor (index -> dataset,
    in index order)."""

    spec: BuildingSpec
    floors: dict[int, Dataset]
    path: Path | None = field(default=None, compare=False)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def lang(self) -> str:
        return next(iter(self.floors.values())).lang

    def layout(self) -> Layout:
        """The joint frame of the floors' maps (:mod:`spcotmhp.building.layout`)."""
        return Layout.plan({i: d.map for i, d in self.floors.items()})


def is_building(path: str | Path) -> bool:
    """Whether ``path`` is a folder holding a building.yaml."""
    return (Path(path) / SPEC_FILE).is_file()


def load_building(path: str | Path, lang: str | None = None) -> Building:
    """Read a building folder (module docstring). ``lang`` None: "en" when the first floor's teaching.csv has
    English words, else "ja"."""
    root = Path(path)
    spec = read_spec(root)
    root = root.resolve()
    floors: dict[int, Dataset] = {}
    for f in spec.floors:
        folder = (root / f.dataset).resolve()
        if not folder.is_relative_to(root):
            raise BuildingError(f"{root / SPEC_FILE}: floor {f.index}'s dataset {f.dataset!r} leads outside {root}")
        if lang is None:
            langs = available_languages(folder) if (folder / "teaching.csv").is_file() else []
            lang = langs[0] if langs else "en"
        try:
            floors[f.index] = load_dataset(folder, lang=lang)
        except SpcotmhpError as exc:
            kind = type(exc) if isinstance(exc, DatasetError) else BuildingError
            raise kind(f"floor {f.index} ({f.name}, {f.dataset}): {exc}") from None
    building = Building(spec, floors, root)
    check_building(building)
    return building


def check_building(building: Building) -> None:
    """The building's own checks (module docstring): BuildingError on the first failure."""
    building.layout()  # one resolution, within the map bounds
    check_stops(building.spec, {i: d.map for i, d in building.floors.items()})


def check_stops(spec: BuildingSpec, maps: Mapping[int, OccupancyMap], error: type[Exception] = BuildingError) -> None:
    """``error`` naming the connector when one of its stops lies off its floor's map or on a cell that is not
    free."""
    for i, c in enumerate(spec.connectors):
        for s in c.stops:
            occ = maps[s.floor]
            cell = occ.world_to_cell(np.array([[s.x, s.y]]))
            where = f"{SPEC_FILE}: connectors[{i}] ({c.name}) stop on floor {s.floor} at ({s.x:.2f}, {s.y:.2f})"
            if not occ.in_bounds(cell)[0]:
                raise error(f"{where} lies off that floor's map")
            value = int(occ.data[cell[0, 0], cell[0, 1]])
            if value != FREE:
                what = {100: "an occupied", -1: "an unknown"}.get(value, "a non-free")
                raise error(f"{where} lies in {what} cell of that floor's map; a stop must be free")
