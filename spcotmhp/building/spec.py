"""building.yaml: the floors of a building (each an ordinary dataset folder) and the connectors between them.

::

    name: office-3                      # optional (default: the folder's name)
    floors:
      - {index: 1, name: ground, dataset: f1}      # a dataset folder, relative to building.yaml, inside its folder
      - {index: 2, name: first, dataset: f2}
    connectors:
      - {name: stairs, from: {floor: 1, x: 3.2, y: 1.0}, to: {floor: 2, x: 3.2, y: 1.0}, cost_m: 8.0}
      - {name: lift, kind: lift, stops: [{floor: 1, x: 9, y: 2}, {floor: 2, x: 9, y: 2}], cost_m: 12.0}

* ``index``: an integer in [MIN_FLOOR_INDEX, MAX_FLOOR_INDEX], distinct; it is the floor's number in
  instructions ("floor 2", "the second floor", 2階 name the floor of index 2) and in ``--floor``; floors are
  ordered by it ("upstairs" is the next index up). ``name``: a word or two ("ground"), distinct.
* A connector joins the floors of its stops: ``from`` + ``to`` (stairs, the default kind), or ``stops`` (a lift,
  the default kind with ``stops``: two or more floors, each at most once). x, y are metres in the frame of that
  floor's map. ``cost_m`` (> 0, at most MAX_CONNECTOR_M) is what using it costs, in metres of free floor: a ride
  between any two of its stops costs ``cost_m`` (stairs: the walk up; a lift: its wait and ride).

Everything is checked when read (:func:`read_spec`); each problem is one :class:`~spcotmhp.errors.BuildingError`
naming the file and the field ("building.yaml: connectors[2].cost_m must be ..."). Sizes are bounded
(MAX_FLOORS, MAX_CONNECTORS, the file's bytes) before anything is allocated.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Any

from spcotmhp.errors import BuildingError
from spcotmhp.safe_read import check_file_name, excerpt, finite_number, load_yaml

SPEC_FILE = "building.yaml"
MAX_SPEC_BYTES = 1 << 20
MAX_FLOORS = 64
MAX_CONNECTORS = 1_000
MIN_FLOOR_INDEX = -99
MAX_FLOOR_INDEX = 999
MAX_NAME_CHARS = 64
MAX_CONNECTOR_M = 10_000.0
MAX_COORDINATE_M = 1e6
KINDS = ("stairs", "lift")
TOP_KEYS = ("name", "floors", "connectors")
FLOOR_KEYS = ("index", "name", "dataset")
CONNECTOR_KEYS = ("name", "kind", "from", "to", "stops", "cost_m")
STOP_KEYS = ("floor", "x", "y")


@dataclass(frozen=True)
class FloorSpec:
    """One floor: its number (``index``), its name and its dataset folder (relative to building.yaml)."""

    index: int
    name: str
    dataset: str


@dataclass(frozen=True)
class Stop:
    """Where a connector meets floor ``floor``: (x, y) in metres in that floor's map frame."""

    floor: int
    x: float
    y: float


@dataclass(frozen=True)
class Connector:
    """Stairs or a lift: its stops (two for stairs) and the cost of a ride between any two of them, in metres."""

    name: str
    kind: str
    stops: tuple[Stop, ...]
    cost_m: float

    def rides(self) -> list[tuple[Stop, Stop]]:
        """Every ordered pair of its stops (a ride from one to the other)."""
        return list(itertools.permutations(self.stops, 2))


@dataclass(frozen=True)
class BuildingSpec:
    """A parsed building.yaml: floors in index order, connectors as given."""

    name: str
    floors: tuple[FloorSpec, ...]
    connectors: tuple[Connector, ...] = ()

    @property
    def indices(self) -> list[int]:
        return [f.index for f in self.floors]

    def floor(self, index: int) -> FloorSpec:
        for f in self.floors:
            if f.index == index:
                return f
        raise KeyError(index)

    def describe_floors(self) -> str:
        """'1 (ground), 2 (first)' for messages."""
        return ", ".join(f"{f.index} ({f.name})" for f in self.floors)

    def to_dict(self) -> dict:
        """The YAML document (stairs with from/to, lifts with stops)."""

        def stop(s: Stop) -> dict:
            return {"floor": s.floor, "x": s.x, "y": s.y}

        connectors = []
        for c in self.connectors:
            where = (
                {"from": stop(c.stops[0]), "to": stop(c.stops[1])}
                if c.kind == "stairs"
                else {"stops": [stop(s) for s in c.stops]}
            )
            connectors.append({"name": c.name, "kind": c.kind, **where, "cost_m": c.cost_m})
        floors = [{"index": f.index, "name": f.name, "dataset": f.dataset} for f in self.floors]
        return {"name": self.name, "floors": floors, "connectors": connectors}


def read_spec(path: str | Path) -> BuildingSpec:
    """The building.yaml at ``path`` (a file, or the building folder holding it), checked (module docstring)."""
    path = Path(path)
    if path.is_dir() or path.suffix.lower() not in (".yaml", ".yml"):
        path = path / SPEC_FILE
    if not path.is_file():
        folder = path.parent
        what = "does not exist" if not folder.exists() else f"has no {SPEC_FILE}"
        raise BuildingError(f"building folder {folder} {what} (a building is a folder with {SPEC_FILE})")
    doc = load_yaml(path, MAX_SPEC_BYTES, "building file", BuildingError)
    return parse_spec(doc, path.parent.resolve().name, str(path))


def parse_spec(doc: Any, default_name: str, where: str = SPEC_FILE) -> BuildingSpec:
    """A :class:`BuildingSpec` from the parsed YAML document ``doc`` (BuildingError naming ``where`` and the
    field)."""
    check = _Checker(where)
    top = check.mapping(doc, "the document", TOP_KEYS, required=("floors",))
    name = check.name(top.get("name", default_name), "name") if "name" in top else default_name[:MAX_NAME_CHARS]
    raw_floors = check.sequence(top["floors"], "floors", 1, MAX_FLOORS)
    given = [check.floor(f, f"floors[{i}]") for i, f in enumerate(raw_floors)]
    for field in ("index", "name", "dataset"):
        seen: dict[Any, int] = {}
        for i, f in enumerate(given):
            value = getattr(f, field)
            key = value.lower() if isinstance(value, str) else value
            if key in seen:
                raise BuildingError(f"{where}: floors[{seen[key]}] and floors[{i}] have the same {field} {value!r}")
            seen[key] = i
    floors = tuple(sorted(given, key=lambda f: f.index))
    known = {f.index for f in floors}
    raw_connectors = check.sequence(top.get("connectors", []), "connectors", 0, MAX_CONNECTORS)
    connectors = tuple(check.connector(c, f"connectors[{i}]", known) for i, c in enumerate(raw_connectors))
    return BuildingSpec(name, floors, connectors)


class _Checker:
    """The field checks of :func:`parse_spec`; every failure is one BuildingError line naming the field."""

    def __init__(self, where: str) -> None:
        self.where = where

    def fail(self, field: str, what: str, value: Any) -> BuildingError:
        return BuildingError(f"{self.where}: {field} must be {what}, got {excerpt(value)}")

    def mapping(self, value: Any, field: str, keys: tuple[str, ...], required: tuple[str, ...] = ()) -> Mapping:
        if not isinstance(value, Mapping):
            raise self.fail(field, f"a mapping with keys {', '.join(keys)}", value)
        unknown = [k for k in value if k not in keys]
        if unknown:
            raise BuildingError(
                f"{self.where}: {field} has unknown key(s) {', '.join(excerpt(k, 30) for k in unknown[:5])}; "
                f"accepted: {', '.join(keys)}"
            )
        missing = [k for k in required if k not in value]
        if missing:
            raise BuildingError(f"{self.where}: {field} has no {', '.join(missing)}")
        return value

    def sequence(self, value: Any, field: str, low: int, high: int) -> list:
        if not isinstance(value, list):
            raise self.fail(field, "a list", value)
        if not low <= len(value) <= high:
            raise BuildingError(f"{self.where}: {field} lists {len(value)} items; {low} to {high} are accepted")
        return value

    def name(self, value: Any, field: str) -> str:
        ok = isinstance(value, str) and value.strip() and len(value) <= MAX_NAME_CHARS
        if not ok or any(ord(c) < 32 or ord(c) == 127 for c in value):
            raise self.fail(field, f"a name of 1 to {MAX_NAME_CHARS} characters without control characters", value)
        return value.strip()

    def integer(self, value: Any, field: str, low: int, high: int) -> int:
        if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
            raise self.fail(field, f"an integer in [{low}, {high}]", value)
        return value

    def number(self, value: Any, field: str, low: float, high: float, open_low: bool = False) -> float:
        ok = finite_number(value) and not isinstance(value, bool)
        ok = ok and (low < float(value) if open_low else low <= float(value)) and float(value) <= high
        if not ok:
            bound = f"> {low:g}" if open_low else f">= {low:g}"
            raise self.fail(field, f"a finite number {bound} and <= {high:g}", value)
        return float(value)

    def floor(self, value: Any, field: str) -> FloorSpec:
        f = self.mapping(value, field, FLOOR_KEYS, required=FLOOR_KEYS)
        index = self.integer(f["index"], f"{field}.index", MIN_FLOOR_INDEX, MAX_FLOOR_INDEX)
        name = self.name(f["name"], f"{field}.name")
        dataset = check_file_name(f["dataset"], f"{self.where}: {field}.dataset", BuildingError)
        parts = PurePosixPath(dataset.replace("\\", "/")).parts
        if dataset.startswith(("/", "\\")) or ":" in dataset or ".." in parts or not parts or parts == (".",):
            raise self.fail(f"{field}.dataset", "a folder inside the building's folder (a relative path)", dataset)
        return FloorSpec(index, name, "/".join(p for p in parts if p != "."))

    def stop(self, value: Any, field: str, known: set[int]) -> Stop:
        s = self.mapping(value, field, STOP_KEYS, required=STOP_KEYS)
        floor = self.integer(s["floor"], f"{field}.floor", MIN_FLOOR_INDEX, MAX_FLOOR_INDEX)
        if floor not in known:
            listed = ", ".join(map(str, sorted(known)))
            raise self.fail(f"{field}.floor", f"one of the floors' indices ({listed})", floor)
        x = self.number(s["x"], f"{field}.x", -MAX_COORDINATE_M, MAX_COORDINATE_M)
        return Stop(floor, x, self.number(s["y"], f"{field}.y", -MAX_COORDINATE_M, MAX_COORDINATE_M))

    def connector(self, value: Any, field: str, known: set[int]) -> Connector:
        c = self.mapping(value, field, CONNECTOR_KEYS, required=("name", "cost_m"))
        name = self.name(c["name"], f"{field}.name")
        if ("stops" in c) == ("from" in c or "to" in c) or ("from" in c) != ("to" in c):
            raise BuildingError(f"{self.where}: {field} needs either from and to, or stops (a list of two or more)")
        kind = c.get("kind", "lift" if "stops" in c else "stairs")
        if kind not in KINDS:
            raise self.fail(f"{field}.kind", " or ".join(KINDS), kind)
        if "stops" in c:
            raw = self.sequence(c["stops"], f"{field}.stops", 2, MAX_FLOORS)
            stops = tuple(self.stop(s, f"{field}.stops[{i}]", known) for i, s in enumerate(raw))
        else:
            stops = (self.stop(c["from"], f"{field}.from", known), self.stop(c["to"], f"{field}.to", known))
        floors = [s.floor for s in stops]
        if len(set(floors)) != len(floors):
            raise BuildingError(f"{self.where}: {field} stops twice on one floor (floors {floors}); each floor once")
        if kind == "stairs" and len(stops) != 2:
            raise BuildingError(f"{self.where}: {field} is stairs with {len(stops)} stops; stairs join two floors")
        cost = self.number(c["cost_m"], f"{field}.cost_m", 0.0, MAX_CONNECTOR_M, open_low=True)
        return Connector(name, kind, stops, cost)
