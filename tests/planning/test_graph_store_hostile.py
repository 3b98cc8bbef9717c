"""A saved planning graph altered by someone who also fixed its checksums (graph.json's per-array ones and the
folder's manifest): every such file is a rebuild with the reason said, or a typed one-line error, never a crash
in a compiled kernel, a NaN in the search or a loop without end (issue 37, fifth round). Warnings are errors."""

from __future__ import annotations

import io
import json
import os
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.errors import ModelError, SpcotmhpError
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_arrays import NO_HOP
from spcotmhp.planning.graph_file import array_checksum
from spcotmhp.planning.graph_settings import GraphSettings
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.planning import test_graph_store as store
from tests.planning.test_graph_store import PORTAL, QUERIES, _copy, _rewrite, _starts

saved = store.saved  # the module's fixture: a small office's model folder with its portal graph

pytestmark = pytest.mark.filterwarnings("error")


def _arrays(root: Path) -> dict[str, np.ndarray]:
    with zipfile.ZipFile(root / "graph.npz") as archive:
        return {i.filename[:-4]: np.lib.format.read_array(io.BytesIO(archive.read(i))) for i in archive.infolist()}


def _forge(root: Path, arrays: dict[str, np.ndarray], fortran: tuple[str, ...] = (), meta=None) -> None:
    """graph.npz of ``arrays`` (stored, as np.savez writes), graph.json's checksums of them, the manifest fixed."""
    doc = json.loads((root / "graph.json").read_text())
    if meta is not None:
        meta(doc)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_STORED) as archive:
        for name, a in arrays.items():
            a = np.asfortranarray(a) if name in fortran else a
            buffer = io.BytesIO()
            np.lib.format.write_array(buffer, a, allow_pickle=False)
            archive.writestr(name + ".npy", buffer.getvalue())
            if doc["checksums"].get(name) != "per-node":
                doc["checksums"][name] = array_checksum(a)
    (root / "graph.npz").write_bytes(out.getvalue())
    _rewrite(root, "graph.json", json.dumps(doc).encode())


def _half(a: np.ndarray, value) -> np.ndarray:
    out = a.copy()
    out.flat[: max(1, out.size // 2)] = value
    return out


def _planned(root: Path) -> tuple[str, list[str]]:
    """The graph's source note and, for a few plans, "ok" or the typed error's class."""
    planner = HierarchicalPlanner(load_model(root), **PORTAL)
    results = []
    for start in _starts(planner, 2):
        for query in QUERIES[:2]:
            try:
                planner.plan(query, start)
                results.append("ok")
            except SpcotmhpError as exc:
                assert "\n" not in str(exc)
                results.append(type(exc).__name__)
    return planner.graph.info["graph_source"], results


FLOATS = ["g0.map_cost", "g0.end_term", "g0.log_transition_all", "g0.hier.portal_cost", "g0.hier.weight", "g0.w_hat"]


@pytest.mark.parametrize("name", FLOATS)
def test_nan_in_any_float_array_is_a_rebuild(saved, tmp_path, name):
    """Before: 'ValueError: log weights must not be NaN' from the search (map_cost, end_term, ...)."""
    root = _copy(saved, tmp_path)
    arrays = _arrays(root)
    _forge(root, {**arrays, name: _half(arrays[name], np.nan)})
    note, results = _planned(root)
    assert note.startswith("rebuilt") and f"{name} holds NaN" in note and set(results) <= {"ok"}, note


@pytest.mark.parametrize(
    "change, expect",
    [
        (lambda a: {k: v.astype(v.dtype.newbyteorder(">")) for k, v in a.items()}, "is stored as >"),
        (lambda a: {k: v.astype(np.float16) if v.dtype.kind == "f" else v for k, v in a.items()}, "dtype float16"),
        (lambda a: {k: v.astype(np.float64) if v.dtype.kind in "iu" else v for k, v in a.items()}, "has dtype float64"),
    ],
    ids=["big-endian (numba: Unsupported array dtype >f8)", "float16 (numba: NotImplementedError)", "ints as floats"],
)
def test_an_array_of_another_byte_order_or_width_is_a_rebuild(saved, tmp_path, change, expect):
    root = _copy(saved, tmp_path)
    _forge(root, change(_arrays(root)))
    note, results = _planned(root)
    assert note.startswith("rebuilt") and expect in note and set(results) <= {"ok"}, note


def test_an_array_in_fortran_order_is_a_rebuild(saved, tmp_path):
    root = _copy(saved, tmp_path)
    arrays = _arrays(root)
    _forge(root, arrays, fortran=tuple(k for k, v in arrays.items() if v.ndim == 2 and min(v.shape) > 1))
    note, _ = _planned(root)
    assert note.startswith("rebuilt") and "in Fortran order" in note, note


def test_negative_next_hops_other_than_none_are_a_rebuild(saved, tmp_path):
    """Before: hop -1 (Python's last node) sent the portal path round a cycle for ever, its pieces growing."""
    root = _copy(saved, tmp_path)
    arrays = _arrays(root)
    _forge(root, {**arrays, "g0.hier.hop": _half(arrays["g0.hier.hop"], -1)})
    note, _ = _planned(root)
    assert note.startswith("rebuilt") and f"negative hops other than {NO_HOP}" in note, note


def test_a_cycle_of_next_hops_is_a_typed_error_not_a_hang(saved):
    """Hops in range can still go round (a -> b -> a): the path follows at most one hop per abstract node."""
    graph = PlanningGraph.build(saved[1], GraphSettings(**PORTAL))
    h = graph.hier
    j = h.n_nodes - 1  # a plan's way into node j, from any cell of node 0's territory
    h.portal_cost = np.zeros_like(h.portal_cost)  # every abstract node reaches j ...
    h.hop = np.zeros_like(h.hop)
    h.hop[0, j] = 1  # ... by 0 -> 1 -> 0 -> ...
    with pytest.raises(ModelError, match="go round a cycle"):
        h.path(h.cells[0], j)


@pytest.mark.parametrize(
    "field, value, expect",
    [
        ("time_precompute_s", "x", "time_precompute_s must be seconds >= 0"),
        ("time_precompute_s", -1.0, "time_precompute_s must be seconds >= 0"),
        ("region", "x", "region must be an integer"),
        ("region", 10**20, "region must be an integer"),
    ],
)
def test_a_graph_json_field_of_the_wrong_kind_is_a_rebuild(saved, tmp_path, field, value, expect):
    """Before: 'ValueError: could not convert string to float' from time_precompute_s."""
    root = _copy(saved, tmp_path)
    _forge(root, _arrays(root), meta=lambda doc: doc["graphs"][0].update({field: value}))
    note, _ = _planned(root)
    assert note.startswith("rebuilt") and expect in note, note


def test_a_graph_npz_that_is_a_pipe_is_named_and_never_opened(saved, tmp_path):
    root = _copy(saved, tmp_path)
    (root / "graph.npz").unlink()
    os.mkfifo(root / "graph.npz")  # opening it would block until a writer came
    note, results = _planned(root)
    assert note.startswith("rebuilt") and "graph.npz is a named pipe (FIFO)" in note and set(results) <= {"ok"}


@pytest.mark.parametrize("version, expect", [(1, "before the portal graph's crossings changed"), (99, "reads 2")])
def test_a_graph_of_another_format_version_is_a_rebuild_saying_why(saved, tmp_path, version, expect):
    """A version-1 graph (one crossing a spacing) has the same key and settings as today's: its version, not its
    key, makes it a rebuild, and the note says what changed; an unknown version says what is read."""
    root = _copy(saved, tmp_path)
    _forge(root, _arrays(root), meta=lambda doc: doc.update(format_version=version))
    note, results = _planned(root)
    assert note.startswith("rebuilt") and expect in note and "precompute" in note, note
    assert set(results) == {"ok"}


# Fuzzing (issue 37: "keep fuzzing your own boundaries (hypothesis) for ... the saved planning graph"): any forged
# graph.npz or graph.json (checksums and manifest fixed, as a careful editor would) plans or refuses in one line.
ODD_FLOATS = st.sampled_from([np.nan, np.inf, -np.inf, -0.0, 1e308, -1e308, 5e-324, -1.0]) | st.floats(-1e6, 1e6)
DTYPES = [np.int8, np.int32, np.int64, np.uint64, np.float32, np.float64, np.bool_, np.complex128]
JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-(2**70), 2**70) | st.floats() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3),
    max_leaves=6,
)


def _value(data, a: np.ndarray):
    """A hostile value for an element of ``a``: odd floats for floats, any integer of its type, a bool."""
    if a.dtype.kind == "f":
        return data.draw(ODD_FLOATS)
    if a.dtype.kind in "iu":
        info = np.iinfo(a.dtype)
        values = st.sampled_from([NO_HOP, -1, 0, int(info.max), int(info.min)]) | st.integers(-5, 10**6)
        return data.draw(values.filter(lambda v: info.min <= v <= info.max))
    return data.draw(st.booleans())


def _mutated(data, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``arrays`` with one drawn change: elements set to hostile values, a shape cut or flattened, another dtype,
    an array dropped or one added."""
    name = data.draw(st.sampled_from(sorted(arrays)))
    a = arrays[name].copy()
    kind = data.draw(st.sampled_from(["values", "values", "shape", "dtype", "drop", "extra"]))
    if kind == "values" and a.size:
        for i in data.draw(st.lists(st.integers(0, a.size - 1), min_size=1, max_size=12)):
            with np.errstate(all="ignore"):
                a.flat[i] = _value(data, a)
    elif kind == "shape" and a.size:
        a = a.reshape(-1) if data.draw(st.booleans()) else a[: data.draw(st.integers(0, max(a.shape[0] - 1, 0)))]
    elif kind == "dtype":
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a cast that loses values is the point
            a = a.astype(data.draw(st.sampled_from(DTYPES)))
    elif kind == "drop":
        return {k: v for k, v in arrays.items() if k != name}
    elif kind == "extra":
        return {**arrays, data.draw(st.sampled_from(["g0.extra", "g9.map_cost", name + "x"])): a}
    return {**arrays, name: a}


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                  HealthCheck.too_slow])  # fmt: skip
@given(data=st.data())
def test_a_fuzzed_graph_npz_plans_or_refuses_in_one_line(saved, tmp_path_factory, data):
    root = _copy(saved, tmp_path_factory.mktemp("fuzz"))
    _forge(root, _mutated(data, _arrays(root)))
    note, results = _planned(root)  # any other exception, a warning (an error here) or a hang fails
    assert isinstance(note, str) and len(results) == 4, (note, results)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                  HealthCheck.too_slow])  # fmt: skip
@given(data=st.data())
def test_a_fuzzed_graph_json_plans_or_refuses_in_one_line(saved, tmp_path_factory, data):
    root = _copy(saved, tmp_path_factory.mktemp("fuzz"))
    doc = json.loads((root / "graph.json").read_text())
    where = data.draw(st.sampled_from(["top", "graph"]))
    fields = doc if where == "top" else doc["graphs"][0]
    field = data.draw(st.sampled_from(sorted(fields)) | st.text(min_size=1, max_size=6))
    value = data.draw(JSON_VALUES)

    def change(d: dict) -> None:
        (d if where == "top" else d["graphs"][0])[field] = value

    try:
        _forge(root, _arrays(root), meta=change)
    except (TypeError, KeyError, AttributeError):
        return  # the forger itself needs "checksums" as it was: not the loader's case
    note, results = _planned(root)
    assert isinstance(note, str) and len(results) == 4, (note, results)
