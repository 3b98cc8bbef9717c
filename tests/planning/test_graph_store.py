"""The planning graph saved with its model (:mod:`spcotmhp.planning.graph_store`): loaded, not rebuilt, with the
same plans; rebuilt (and said) when stale, damaged or hostile; its save atomic."""

from __future__ import annotations

import json
import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest

from spcotmhp import safe_write
from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence import folder as model_folder
from spcotmhp.persistence.folder import manifest_of
from spcotmhp.persistence.io import load_model, save_model
from spcotmhp.planning import _tree_codes, graph_store
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_settings import GraphSettings
from spcotmhp.planning.graph_store import graph_writers, save_graph
from spcotmhp.planning.planner import HierarchicalPlanner

PORTAL = {"max_dense_bytes": 0}  # the portal graph (building scale) on a small map
QUERIES = ["go to the office", "go to the office via the corridor", "go to the meeting room avoiding the corridor"]


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A model folder with its portal graph saved, and the model as learned."""
    ds = generate_environment("office", seed=1, n_rooms=14, size=240)
    model = fit_supervised(ds, adjacency="given")
    root = tmp_path_factory.mktemp("store") / "model"
    save_model(model, root, files=graph_writers(PlanningGraph.build(model, GraphSettings(**PORTAL))))
    return root, model


def _copy(saved, tmp_path: Path) -> Path:
    out = tmp_path / "copy"
    shutil.copytree(saved[0], out)
    return out


def _starts(planner: HierarchicalPlanner, n: int = 6) -> np.ndarray:
    free = np.argwhere(planner.graph.main)
    cells = free[np.random.default_rng(0).choice(len(free), n, replace=False)]
    return planner.model.require_map().cell_to_world(planner.graph.to_map(cells))


def _plans(planner: HierarchicalPlanner) -> list:
    out = []
    for start in _starts(planner):
        for query in QUERIES:
            try:
                plan = planner.plan(query, start)
                out.append((query, plan.log_prob, plan.cells.tolist(), plan.explanation))
            except Exception as exc:  # noqa: BLE001 - the same refusal either way is part of "the same plans"
                out.append((query, type(exc).__name__, str(exc)))
    return out


@pytest.mark.parametrize("settings", [PORTAL, {}], ids=["portal", "dense"])
def test_a_saved_graph_loads_and_plans_as_the_rebuilt_one(saved, tmp_path, settings):
    root, learned = saved
    if settings != PORTAL:
        root = _copy(saved, tmp_path)
        save_graph(root, PlanningGraph.build(learned, GraphSettings(**settings)), overwrite=True)
    loaded = HierarchicalPlanner(load_model(root), **settings)
    assert loaded.graph.info["graph_source"].startswith("loaded")
    rebuilt = HierarchicalPlanner(learned, **settings)
    assert rebuilt.graph.info["graph_source"] == "built"
    assert (loaded.graph.hier is None) == (settings != PORTAL)
    for name in ("w_hat", "w_hat_metric", "log_transition", "log_transition_all", "end_term", "node_cell"):
        assert np.array_equal(getattr(loaded.graph, name), getattr(rebuilt.graph, name)), name
    assert np.array_equal(loaded.graph.map_cost, rebuilt.graph.map_cost)
    assert _plans(loaded) == _plans(rebuilt)


def test_the_tree_codes_give_the_search_s_costs_bit_for_bit(saved):
    # the cost to go is summed along the stored tree; it must be the search's own value, not a near one
    from spcotmhp.metric import _grid_kernels as _k
    from spcotmhp.metric.grid_search import SQRT2

    graph = PlanningGraph.build(saved[1], GraphSettings(**PORTAL))
    h = graph.hier
    for a in range(0, len(h.cells), 7):
        r0, c0, r1, c1 = h.win[h.terr[a]]
        sub = np.where(h.territory[r0:r1, c0:c1] == h.terr[a], h.cost[r0:r1, c0:c1], np.inf)
        src = (h.cells[a] - [r0, c0])[None].astype(np.int64)
        dist, _, _ = _k.grid_search(
            np.ascontiguousarray(sub),
            src,
            np.empty((0, 2), np.int64),
            8,
            SQRT2,
            _k.CORNER_NO_SQUEEZE,
            True,
            _k.MODE_FIELD,
            0.0,
        )
        codes = h.fcode[h.off[a] : h.off[a + 1]]
        for flat in np.flatnonzero(np.isfinite(dist))[::5]:
            r, c = divmod(int(flat), c1 - c0)
            got = _tree_codes.chain_cost(codes, r1 - r0, c1 - c0, r, c, *src[0], h.cost, r0, c0, SQRT2)
            assert got == dist[flat]


def test_a_changed_map_or_settings_rebuilds_and_says_so(saved):
    model = load_model(saved[0])
    other = HierarchicalPlanner(model, **PORTAL, portal_spacing=2.0)
    assert other.graph.info["graph_source"].startswith("rebuilt")
    assert "other graph settings" in other.graph.info["graph_source"]
    assert "spcotmhp precompute" in other.graph.info["graph_source"]
    free = np.argwhere(model.map.data == 0)
    model.map.data[tuple(free[len(free) // 2])] = 100  # one cell of the map made an obstacle
    moved = HierarchicalPlanner(model, **PORTAL)
    assert "another model or map" in moved.graph.info["graph_source"]
    assert moved.graph.key != other.graph.key


def _rewrite(root: Path, name: str, data: bytes) -> None:
    """Replace one file of the folder and its manifest entry (as an editor who also fixes the manifest)."""
    (root / name).write_bytes(data)
    names = [p.name for p in sorted(root.iterdir()) if p.is_file() and p.name != model_folder.MANIFEST]
    (root / model_folder.MANIFEST).write_text(json.dumps(manifest_of(root, names)))


def _source(root: Path) -> str:
    return HierarchicalPlanner(load_model(root), **PORTAL).graph.info["graph_source"]


def test_a_truncated_graph_is_rebuilt_with_the_reason(saved, tmp_path):
    root = _copy(saved, tmp_path)
    data = (root / "graph.npz").read_bytes()
    (root / "graph.npz").write_bytes(data[: len(data) // 2])  # torn: the manifest's size no longer matches
    note = _source(root)
    assert note.startswith("rebuilt") and "graph.npz" in note and "--overwrite" in note


def _damage(root: Path, member: str, from_end: int) -> None:
    """Flip a byte of ``member``'s data, ``from_end`` bytes before its end."""
    data = bytearray((root / "graph.npz").read_bytes())
    with zipfile.ZipFile(root / "graph.npz") as archive:
        info = archive.getinfo(member)
    data[info.header_offset + 30 + len(info.filename) + info.file_size - 1 - from_end] ^= 0x5A
    _rewrite(root, "graph.npz", bytes(data))


def test_a_damaged_array_is_found_by_its_checksum(saved, tmp_path):
    root = _copy(saved, tmp_path)
    _damage(root, "g0.territory.npy", 1000)
    note = _source(root)
    assert note.startswith("rebuilt") and "checksum" in note and "g0.territory" in note


def test_damaged_tree_codes_are_found_when_first_read(saved, tmp_path):
    # the codes are checked node by node as plans read them: the damaged node's block is refused, others serve
    root = _copy(saved, tmp_path)
    _damage(root, "g0.hier.fcode.npy", 10)  # in the last abstract node's block
    graph = HierarchicalPlanner(load_model(root), **PORTAL).graph
    assert graph.info["graph_source"].startswith("loaded")
    h, last = graph.hier, len(graph.hier.cells) - 1
    assert h.local(0, h.cells[0]) == 0.0  # another node's block: checked, served
    with pytest.raises(graph_store.ModelError, match=f"abstract node {last} does not match its checksum"):
        h.local(last, h.cells[last])


def test_a_graph_json_describing_huge_arrays_is_refused_before_reading(saved, tmp_path):
    root = _copy(saved, tmp_path)
    doc = json.loads((root / "graph.json").read_text())
    doc["graphs"][0]["hier"]["codes"] = 10**15  # 1 PB of tree codes
    _rewrite(root, "graph.json", json.dumps(doc).encode())
    note = _source(root)
    assert note.startswith("rebuilt") and "hier.codes" in note


def test_a_member_header_claiming_a_huge_shape_is_refused_before_mapping(saved, tmp_path):
    root = _copy(saved, tmp_path)
    with zipfile.ZipFile(root / "graph.npz") as archive:
        members = {info.filename: archive.read(info) for info in archive.infolist()}
    header = np.lib.format.header_data_from_array_1_0(np.zeros(1, dtype=np.int8))
    header["shape"] = (2**40,)  # a terabyte, in a member of a few bytes
    fake = bytearray()
    import io

    buffer = io.BytesIO()
    np.lib.format.write_array_header_1_0(buffer, header)
    fake += buffer.getvalue() + b"\0" * 16
    members["g0.hier.fcode.npy"] = bytes(fake)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_STORED) as archive:
        for name, content in members.items():
            archive.writestr(name, content)
    _rewrite(root, "graph.npz", out.getvalue())
    note = _source(root)
    assert note.startswith("rebuilt") and "shape" in note and "g0.hier.fcode" in note


def test_a_compressed_member_is_refused(saved, tmp_path):
    root = _copy(saved, tmp_path)
    out = tmp_path / "z.npz"
    with zipfile.ZipFile(root / "graph.npz") as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            dst.writestr(info.filename, src.read(info))
    _rewrite(root, "graph.npz", out.read_bytes())
    assert "compressed" in _source(root)


class Interrupted(BaseException):
    """A crash in the middle of a save (not an Exception: nothing may swallow it)."""


def test_an_interrupted_save_leaves_the_folder_as_it_was(saved, tmp_path, monkeypatch):
    root = _copy(saved, tmp_path)
    for name in ("graph.json", "graph.npz"):
        (root / name).unlink()
    names = [p.name for p in sorted(root.iterdir()) if p.is_file() and p.name != model_folder.MANIFEST]
    (root / model_folder.MANIFEST).write_text(json.dumps(manifest_of(root, names)))  # a folder without a graph
    before = {p.name: p.read_bytes() for p in root.iterdir()}
    graph = PlanningGraph.build(saved[1], GraphSettings(**PORTAL))
    steps = [(np, "savez"), (model_folder, "manifest_of"), (safe_write, "swap_folder"), (shutil, "copyfile")]
    for point in range(12):
        calls = {"n": 0}

        def wrap(fn, calls=calls, point=point):
            def step(*args, **kwargs):
                calls["n"] += 1
                if calls["n"] == point + 1:
                    raise Interrupted
                return fn(*args, **kwargs)

            return step

        with monkeypatch.context() as patch:
            for owner, name in steps:
                patch.setattr(owner, name, wrap(getattr(owner, name)))
            try:
                save_graph(root, graph)
                done = True
            except Interrupted:
                done = False
        if done:
            break
        assert {p.name: p.read_bytes() for p in root.iterdir()} == before  # untouched, and no staging left
        assert _source(root).startswith("built")  # the model loads; no graph, said
    assert done and _source(root).startswith("loaded")


def test_precompute_refuses_to_replace_a_graph_without_overwrite(saved, tmp_path):
    root = _copy(saved, tmp_path)
    graph = PlanningGraph.build(saved[1], GraphSettings(**PORTAL, portal_spacing=2.0))
    with pytest.raises(graph_store.ModelError, match="--overwrite"):
        save_graph(root, graph)
    save_graph(root, graph, overwrite=True)
    assert (
        HierarchicalPlanner(load_model(root), **PORTAL, portal_spacing=2.0)
        .graph.info["graph_source"]
        .startswith("loaded")
    )


def test_the_size_bound_counts_tree_codes_at_one_byte(saved):
    # a 16-megapixel office's 2 GB of one-byte codes fit MAX_GRAPH_BYTES; counted at 8 bytes they did not
    from spcotmhp.limits import MAX_GRAPH_BYTES
    from spcotmhp.planning import graph_arrays

    root, model = saved
    metas = json.loads((root / "graph.json").read_text())["graphs"]
    metas[0]["hier"]["codes"] = MAX_GRAPH_BYTES // 2
    assert graph_arrays.expected_arrays(metas, model)["g0.hier.fcode"][0] == (MAX_GRAPH_BYTES // 2,)
    metas[0]["hier"]["codes"] = MAX_GRAPH_BYTES + 1
    with pytest.raises(graph_store.ModelError, match="at most"):
        graph_arrays.expected_arrays(metas, model)
