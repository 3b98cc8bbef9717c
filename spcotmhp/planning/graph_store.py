"""The planning graph saved with its model: graph.json + graph.npz in the model folder, loaded instead of rebuilt.

Algorithm 1's offline part (the cost map, the free regions and territories, the candidate points, the portal
graph's local fields and abstract distances; :mod:`spcotmhp.planning.graph`) takes seconds to minutes on a big
map and depends only on the model, its map and the graph settings, so it is computed once and kept beside the
model:

* ``graph.json``: format, version, the graph's key (:func:`~spcotmhp.planning.graph_settings.fingerprint` of the
  model's parameters, its map, its cost map settings and the graph settings), the settings themselves and each
  free region's graph described by its sizes (:mod:`spcotmhp.planning.graph_arrays`);
* ``graph.npz``: the arrays, plain numbers only, uncompressed and mapped read-only on loading, each checked by
  its checksum listed in graph.json (:mod:`spcotmhp.planning.graph_file`; nothing is unpickled).

Both files are listed in the folder's manifest and written with it atomically
(:func:`spcotmhp.persistence.folder.write_folder`): ``learn`` writes them with the model; ``spcotmhp precompute
MODEL`` adds them to a folder that has none (and replaces a stale one only with ``--overwrite``). ``plan``,
``serve``, ``ros2`` and the library (:meth:`PlanningGraph.build` of a model loaded from a folder) read them and
never write: a folder without a graph, or with one made for another model, map or settings, gets its graph
built in memory and a note saying so and how to save it (:func:`load_saved`'s second value, kept in the graph's
``info["graph_source"]``).

Reading checks, in order, before anything large is allocated: the manifest's sizes of both files and the
SHA-256 of graph.json (the bytes hashed are the bytes then parsed; graph.npz's SHA-256 stays in the manifest for
a full check, but loading checks each array's checksum instead: hashing a big map's graph would take seconds per
command), graph.json's fields, its key against the model's and the
settings' (a mismatch is a rebuild, never a stale graph), every array's shape from graph.json's sizes checked
against the model's map (:func:`~spcotmhp.planning.graph_arrays.expected_arrays`) and every index within its
range (:func:`~spcotmhp.planning.graph_arrays.check_values`). A damaged or altered graph is a rebuild with the
reason said, never a traceback: the model itself loaded, and the graph can always be computed again.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import time
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.persistence.folder import MANIFEST, file_digest, read_manifest, write_folder
from spcotmhp.persistence.io import GRAPH_FILES, json_default
from spcotmhp.planning import graph_arrays as ga
from spcotmhp.planning.graph_file import BLOCKS, array_checksum, read_mapped
from spcotmhp.planning.graph_settings import GraphSettings
from spcotmhp.safe_read import excerpt, file_kind, parse_json

if TYPE_CHECKING:
    from spcotmhp.learning.model import SpatialConceptModel

PlanningGraph = Any  # spcotmhp.planning.graph's class, passed in (it imports this module: no import back)

GRAPH_JSON, GRAPH_NPZ = GRAPH_FILES
FORMAT = "spcotmhp-planning-graph"
FORMAT_VERSION = 2
"""2: the portal graph's entrances get ``ceil(sqrt(length / spacing))`` crossings
(:func:`~spcotmhp.planning._portals.crossings_on`); a version-1 graph (one crossing a spacing) is another graph
under the same key and settings, so it is rebuilt, saying so (:data:`EARLIER`)."""
EARLIER = {1: "made before the portal graph's crossings changed (one a spacing; now the square root rule)"}
MAX_GRAPH_JSON_BYTES = 16 * 1024 * 1024  # sizes and info of up to thousands of free regions' graphs


def save_hint(folder: Path | str, stale: bool) -> str:
    """How to save the graph of the model folder ``folder``."""
    return f"save it with: spcotmhp precompute {folder}" + (" --overwrite" if stale else "")


def graph_writers(graph: PlanningGraph) -> dict[str, Any]:
    """The writers of graph.json and graph.npz (file name -> write(path)) for
    :func:`~spcotmhp.persistence.folder.write_folder`."""
    arrays, metas = ga.to_arrays(graph)
    doc = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "key": graph.key,
        "settings": asdict(graph.settings),
        "checksums": {name: BLOCKS if name.endswith("hier.fcode") else array_checksum(a) for name, a in arrays.items()},
        "graphs": metas,
    }
    text = json.dumps(doc, indent=1, default=json_default)

    def write_npz(path: Path) -> None:
        with path.open("wb") as handle:
            np.savez(handle, allow_pickle=False, **arrays)

    return {GRAPH_JSON: lambda path: path.write_text(text, encoding="utf-8"), GRAPH_NPZ: write_npz}


def save_graph(folder: Path | str, graph: PlanningGraph, overwrite: bool = False) -> Path:
    """Add ``graph`` (of the model loaded from ``folder``) to the model folder ``folder``: every file of the folder
    copied as it is, graph.json and graph.npz written, the manifest rewritten, the whole swapped in atomically
    (:func:`~spcotmhp.persistence.folder.write_folder`). A graph already there is replaced only with
    ``overwrite`` (ModelError otherwise)."""
    root = Path(folder)
    entries = read_manifest(root, skip=GRAPH_FILES)
    if entries is None:
        raise ModelError(f"{root} has no manifest.json: save the model again (spcotmhp learn) before precomputing")
    present = [name for name in GRAPH_FILES if (root / name).exists()]
    if present and not overwrite:
        raise ModelError(
            f"{root} already holds a planning graph ({', '.join(present)}); give --overwrite to replace it"
        )
    writers: dict[str, Any] = {
        name: (lambda path, src=root / name: shutil.copyfile(src, path))
        for name in sorted(entries)
        if name not in GRAPH_FILES and name != MANIFEST
    }
    for name in writers:  # a copy of a torn folder is a torn folder
        size, sha = file_digest(root / name)
        if (size, sha) != entries[name]:
            raise ModelError(f"{root / name} does not match {MANIFEST}: the model folder is torn; save it again")
    writers.update(graph_writers(graph))
    from spcotmhp.persistence.io import MODEL_FILES

    return write_folder(root, writers, MODEL_FILES)


def load_saved(model: SpatialConceptModel, settings: GraphSettings, key: str, cls: type) -> tuple[Any, str]:
    """``(graph, note)``: the graph (a ``cls``, :class:`~spcotmhp.planning.graph.PlanningGraph`) saved in the
    folder ``model.folder`` when it was made for this model, map and settings (``key``), else ``(None, why)`` (no
    folder, no graph, a stale or damaged one: module docstring)."""
    root = getattr(model, "folder", None)
    if root is None:
        return None, "built (the model was not loaded from a folder)"
    root = Path(root)
    odd = [(name, kind) for name in GRAPH_FILES if (kind := file_kind(root / name)) is not None]
    if odd:  # a device, a pipe or a folder is never opened (reading /dev/zero never ends, a FIFO blocks)
        name, kind = odd[0]
        return None, f"rebuilt: {root / name} is {kind}, not a saved planning graph; {save_hint(root, True)}"
    if not all((root / name).is_file() for name in GRAPH_FILES):
        return None, f"built: {root} holds no saved planning graph; {save_hint(root, False)}"
    try:
        t0 = time.perf_counter()
        doc = _read_checked(root)
        if doc["key"] != key:
            what = "other graph settings" if doc.get("settings") != asdict(settings) else "another model or map"
            return None, f"rebuilt: the planning graph saved in {root} was made for {what}; {save_hint(root, True)}"
        graph = _from_file(root, doc, model, settings, key, cls)
    except ModelError as exc:
        return None, f"rebuilt: the planning graph saved in {root} cannot be used ({exc}); {save_hint(root, True)}"
    graph.info["load_s"] = time.perf_counter() - t0
    return graph, f"loaded from {root}"


def _read_checked(root: Path) -> dict:
    """graph.json, checked against the manifest (the sizes of graph.json and graph.npz, then the SHA-256 of the
    very bytes parsed)."""
    entries = read_manifest(root)
    if entries is None or any(name not in entries for name in GRAPH_FILES):
        raise ModelError(f"{MANIFEST} does not list {' and '.join(GRAPH_FILES)}")
    size, sha = entries[GRAPH_JSON]
    if size > MAX_GRAPH_JSON_BYTES:
        raise ModelError(f"{GRAPH_JSON} is {size} bytes; at most {MAX_GRAPH_JSON_BYTES} are accepted")
    with (root / GRAPH_JSON).open("rb") as handle:
        data = handle.read(size + 1)
    if len(data) != size or hashlib.sha256(data).hexdigest() != sha:
        raise ModelError(f"{GRAPH_JSON} does not match its checksum in {MANIFEST} (a torn or altered file)")
    doc = parse_json(data.decode("utf-8", errors="replace"), f"{root / GRAPH_JSON}", ModelError)
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise ModelError(f"{GRAPH_JSON} is not a spcotmhp planning graph (format {FORMAT!r})")
    if doc.get("format_version") != FORMAT_VERSION:
        version = doc.get("format_version")
        if type(version) is int and version in EARLIER:  # not a list (unhashable) nor True (== 1)
            raise ModelError(f"{GRAPH_JSON} has format version {version}, {EARLIER[version]}")
        raise ModelError(
            f"{GRAPH_JSON} has format version {excerpt(doc.get('format_version'))}; this spcotmhp reads "
            f"{FORMAT_VERSION}"
        )
    if not isinstance(doc.get("key"), str) or not isinstance(doc.get("checksums"), dict):
        raise ModelError(f'{GRAPH_JSON}: "key" must be a string and "checksums" an object')
    return doc


def _from_file(
    root: Path, doc: dict, model: SpatialConceptModel, settings: GraphSettings, key: str, cls: type
) -> PlanningGraph:
    """The graph of a checked graph.json + graph.npz (module docstring)."""
    metas = ga.check_meta(doc.get("graphs"), model)
    specs = ga.expected_arrays(metas, model)
    arrays = read_mapped(root / GRAPH_NPZ, specs, doc["checksums"], ())
    ga.check_values(arrays, metas, model)
    graphs = [_one(cls, arrays, i, meta, model, settings, key) for i, meta in enumerate(metas)]
    main = graphs[0]
    for meta, sub in zip(metas[1:], graphs[1:], strict=True):
        if not isinstance(meta.get("region"), int):
            raise ModelError(f'{GRAPH_JSON}: every graph but the first needs its "region" label')
        main.regions[int(meta["region"])] = sub
    return main


def _one(
    cls: type, arrays: dict, i: int, meta: dict, model: SpatialConceptModel, settings: GraphSettings, key: str
) -> PlanningGraph:
    """Graph ``i`` (the main one, or another free region's) of the arrays."""
    p = f"g{i}."
    log_p = arrays[p + "log_p"]
    boxes, masks = arrays[p + "grown_boxes"], arrays[p + "grown_masks"]
    ends = np.concatenate([[0], np.cumsum(boxes[:, 2] * boxes[:, 3])])
    grown = {
        int(k): (int(r), int(c), masks[ends[n] : ends[n + 1]].reshape(int(h), int(w)))
        for n, (k, (r, c, h, w)) in enumerate(zip(arrays[p + "grown_keys"], boxes, strict=True))
    }
    label = meta.get("region")
    graph = cls(
        model=model,
        settings=settings,
        key=key if i == 0 else f"{key}/region-{label}",
        offset=(int(meta["offset"][0]), int(meta["offset"][1])),
        log_p=log_p,
        traversable=arrays[p + "traversable"],
        node_place=arrays[p + "node_place"].astype(np.int64),
        node_cell=arrays[p + "node_cell"].astype(np.int64),
        dist=[],
        next_step=[],
        end_term=arrays[p + "end_term"].astype(float),
        w_hat=arrays[p + "w_hat"].astype(float),
        w_hat_metric=arrays[p + "w_hat_metric"].astype(float),
        log_transition=arrays[p + "log_transition"].astype(float),
        connected=arrays["connected"],
        time_precompute_s=float(meta.get("time_precompute_s", 0.0)),
        territory=arrays[p + "territory"],
        main=arrays[p + "main"],
        usable=arrays[p + "usable"],
        log_transition_all=arrays[p + "log_transition_all"].astype(float),
        _territories=grown,
        info=dict(meta["info"]),
        region=arrays[p + "region"] if i == 0 else None,
        plannable=arrays[p + "plannable"] if i == 0 else None,
        _map_cost=arrays[p + "map_cost"],
        _clearance=arrays[p + "clearance"],
    )
    if meta.get("hier") is not None:
        graph.hier = ga.hier_from_arrays(arrays, p + "hier.", meta, graph.map_cost, graph.territory, model.K)
    elif graph.n_nodes:  # dense fields (small maps, module docstring of graph_arrays): recomputed
        graph._fields(None)
    return graph
