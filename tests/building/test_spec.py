"""building.yaml: what is accepted, what is refused (one BuildingError line naming the field), and a fuzz of the
reader over mutated documents (never a traceback, never anything but a BuildingError)."""

from __future__ import annotations

import copy

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.building.spec import MAX_CONNECTORS, MAX_FLOORS, BuildingSpec, Connector, Stop, parse_spec, read_spec
from spcotmhp.errors import BuildingError
from tests.helpers.strategies import document_paths

GOOD = {
    "name": "office",
    "floors": [
        {"index": 2, "name": "first", "dataset": "f2"},
        {"index": 1, "name": "ground", "dataset": "floors/f1"},
    ],
    "connectors": [
        {"name": "stairs", "from": {"floor": 1, "x": 1.0, "y": 2}, "to": {"floor": 2, "x": 3, "y": 4}, "cost_m": 8},
        {"name": "lift", "stops": [{"floor": 1, "x": 0, "y": 0}, {"floor": 2, "x": 0, "y": 0}], "cost_m": 12.5},
    ],
}


def test_a_good_document():
    spec = parse_spec(GOOD, "folder")
    assert spec.name == "office"
    assert spec.indices == [1, 2]  # ordered by index whatever the file's order
    assert spec.floor(1).dataset == "floors/f1"
    stairs, lift = spec.connectors
    assert stairs == Connector("stairs", "stairs", (Stop(1, 1.0, 2.0), Stop(2, 3.0, 4.0)), 8.0)
    assert lift.kind == "lift" and len(lift.rides()) == 2
    assert parse_spec(spec.to_dict(), "x") == spec  # to_dict round-trips
    assert parse_spec({"floors": [{"index": 0, "name": "g", "dataset": "a"}]}, "home").name == "home"


def test_a_lift_joins_several_floors():
    doc = {
        "floors": [{"index": i, "name": f"f{i}", "dataset": f"d{i}"} for i in (-1, 0, 1, 2)],
        "connectors": [{"name": "lift", "stops": [{"floor": i, "x": 0, "y": 0} for i in (-1, 0, 2)], "cost_m": 5}],
    }
    (lift,) = parse_spec(doc, "b").connectors
    assert [s.floor for s in lift.stops] == [-1, 0, 2]
    assert len(lift.rides()) == 6


def _with(path: str, value) -> dict:
    doc = copy.deepcopy(GOOD)
    *keys, last = path.split(".")
    node = doc
    for k in keys:
        node = node[int(k)] if isinstance(node, list) else node[k]
    if value is KeyError:
        del node[last]
    elif isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value
    return doc


@pytest.mark.parametrize(
    "path, value, words",
    [
        ("floors", [], "floors lists 0 items; 1 to 64"),
        ("floors", "f1", "floors must be a list"),
        ("floors.0.index", 1, "floors[0] and floors[1] have the same index 1"),
        ("floors.0.name", "GROUND", "same name 'ground'"),
        ("floors.0.dataset", "floors/f1", "same dataset"),
        ("floors.0.index", True, "floors[0].index must be an integer"),
        ("floors.0.index", 10**6, "floors[0].index must be an integer in [-99, 999]"),
        ("floors.0.name", "", "floors[0].name must be a name"),
        ("floors.0.dataset", "../elsewhere", "floors[0].dataset must be a folder inside"),
        ("floors.0.dataset", "/abs", "floors[0].dataset must be a folder inside"),
        ("floors.0.extra", 1, "floors[0] has unknown key(s) 'extra'"),
        ("floors.0.dataset", KeyError, "floors[0] has no dataset"),
        ("connectors.0.cost_m", 0, "connectors[0].cost_m must be a finite number > 0"),
        ("connectors.0.cost_m", float("inf"), "connectors[0].cost_m must be a finite number"),
        ("connectors.0.cost_m", "8", "connectors[0].cost_m must be a finite number"),
        ("connectors.0.to.floor", 3, "connectors[0].to.floor must be one of the floors' indices (1, 2)"),
        ("connectors.0.to.floor", 1, "stops twice on one floor"),
        ("connectors.0.to.x", float("nan"), "connectors[0].to.x must be a finite number"),
        ("connectors.0.to", KeyError, "needs either from and to, or stops"),
        ("connectors.0.kind", "escalator", "connectors[0].kind must be stairs or lift"),
        ("connectors.1.stops", [{"floor": 1, "x": 0, "y": 0}], "connectors[1].stops lists 1 items; 2 to"),
        ("connectors.1.kind", "stairs", None),  # stairs with two stops given as a list: accepted
        ("unknown", 1, "the document has unknown key(s) 'unknown'"),
    ],
)
def test_refusals_name_the_field(path, value, words):
    if words is None:
        parse_spec(_with(path, value), "b")
        return
    with pytest.raises(BuildingError) as err:
        parse_spec(_with(path, value), "b")
    message = str(err.value)
    assert words in message and "\n" not in message and message.startswith("building.yaml: ")


def test_stairs_join_two_floors_only():
    doc = {
        "floors": [{"index": i, "name": f"f{i}", "dataset": f"d{i}"} for i in (1, 2, 3)],
        "connectors": [{"name": "s", "kind": "stairs", "stops": [{"floor": i, "x": 0, "y": 0} for i in (1, 2, 3)],
                        "cost_m": 5}],
    }  # fmt: skip
    with pytest.raises(BuildingError, match="stairs with 3 stops; stairs join two floors"):
        parse_spec(doc, "b")


def test_sizes_are_bounded():
    floors = [{"index": i, "name": f"f{i}", "dataset": f"d{i}"} for i in range(MAX_FLOORS + 1)]
    with pytest.raises(BuildingError, match=f"floors lists {MAX_FLOORS + 1} items"):
        parse_spec({"floors": floors}, "b")
    one = {"name": "s", "from": {"floor": 1, "x": 0, "y": 0}, "to": {"floor": 2, "x": 0, "y": 0}, "cost_m": 1}
    with pytest.raises(BuildingError, match=f"connectors lists {MAX_CONNECTORS + 1} items"):
        parse_spec(_with("connectors", [one] * (MAX_CONNECTORS + 1)), "b")


def test_read_spec_files(tmp_path):
    with pytest.raises(BuildingError, match="does not exist"):
        read_spec(tmp_path / "none")
    with pytest.raises(BuildingError, match="has no building.yaml"):
        read_spec(tmp_path)
    (tmp_path / "building.yaml").write_text("floors: [&a {index: 1}]\n")
    with pytest.raises(BuildingError, match="anchors and aliases"):
        read_spec(tmp_path)
    (tmp_path / "building.yaml").write_text("floors: [\n")
    with pytest.raises(BuildingError, match="does not parse"):
        read_spec(tmp_path)
    (tmp_path / "building.yaml").write_text(yaml.safe_dump(GOOD))
    assert isinstance(read_spec(tmp_path / "building.yaml"), BuildingSpec)


VALUES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**12), 10**12),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
    st.lists(st.integers(-3, 3), max_size=3),
    st.dictionaries(st.sampled_from(["floor", "x", "y", "index"]), st.integers(-3, 3), max_size=3),
)


ALL_PATHS = list(document_paths(GOOD))[1:]


@given(edits=st.lists(st.tuples(st.sampled_from(ALL_PATHS), VALUES, st.booleans()), min_size=1, max_size=4))
@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
def test_fuzzed_documents_parse_or_give_one_line(edits):
    doc = copy.deepcopy(GOOD)
    for path, value, delete in edits:
        node = doc
        try:
            for k in path[:-1]:
                node = node[k]
            if delete and isinstance(node, dict):
                node.pop(path[-1], None)
            else:
                node[path[-1]] = value
        except (KeyError, IndexError, TypeError):
            continue
    try:
        spec = parse_spec(doc, "b")
    except BuildingError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 400
    else:
        assert spec.floors and all(c.cost_m > 0 for c in spec.connectors)
