"""Saving and loading a building's model: an ordinary model folder (:mod:`spcotmhp.persistence.io`: the joint model,
its joint grid as map.yaml, the learner state, the manifest) plus ``building.json``::

    {"format": "spcotmhp-building-model", "format_version": 1,
     "spec": {"name": ..., "floors": [{index, name, dataset}], "connectors": [...]},   # building.yaml's fields
     "layout": {"resolution": ..., "gap": ..., "tiles": [{index, origin, shape, col0}]}}

building.json is listed in the folder's manifest (its size and SHA-256 checked before it is read, at most the
model folder's JSON bound); ``spec`` is checked as building.yaml is (:func:`~spcotmhp.building.spec.parse_spec`),
the layout field by field, then against the model: the joint grid is the layout's, and every connector stop lies
on a free cell of its floor's map. Any problem is one ModelError line. Nothing is unpickled; a building model
folder also loads as a plain model (:func:`~spcotmhp.persistence.io.load_model` ignores building.json).

The robot's body (``learn``'s ``--nav2-params``, ``--robot-radius``, ...) is the joint model's cost map settings
and ``info["body"]``, saved with it as for one floor; every floor's view (:meth:`~spcotmhp.building.model.
BuildingModel.floor_model`) keeps them, so every floor plans for that body. ``plan``, ``serve`` and ``ros2`` given a
body load the folder with it (:func:`load_building_model`'s ``body``).
"""

from __future__ import annotations

import json
from pathlib import Path

from spcotmhp.building.layout import Layout
from spcotmhp.building.loader import check_stops
from spcotmhp.building.model import BuildingModel
from spcotmhp.building.spec import parse_spec
from spcotmhp.errors import BuildingError, ModelError
from spcotmhp.metric.body import RobotBody
from spcotmhp.persistence.folder import read_manifest
from spcotmhp.persistence.io import load_model, save_model
from spcotmhp.persistence.model_checks import MAX_JSON_BYTES
from spcotmhp.planning.body import with_body
from spcotmhp.safe_read import excerpt, load_json

BUILDING_JSON = "building.json"
FORMAT = "spcotmhp-building-model"
FORMAT_VERSION = 1


def is_building_model(folder: str | Path) -> bool:
    """Whether ``folder`` holds a building model (model.json and building.json)."""
    return (Path(folder) / BUILDING_JSON).is_file() and (Path(folder) / "model.json").is_file()


def save_building_model(bm: BuildingModel, folder: str | Path, *, overwrite: bool = False) -> Path:
    """Write ``bm`` to ``folder`` (module docstring), atomically as every model folder; returns the folder."""
    doc = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "spec": bm.spec.to_dict(),
        "layout": bm.layout.to_dict(),
    }
    text = json.dumps(doc, indent=1, ensure_ascii=False)
    return save_model(bm.model, folder, overwrite=overwrite, extra={BUILDING_JSON: text})


def load_building_model(folder: str | Path, body: RobotBody | None = None) -> BuildingModel:
    """Read a building model folder (module docstring); ModelError naming the file and field on any problem.
    ``body``: plan every floor for that robot body instead of the one stored (:func:`~spcotmhp.planning.body.
    with_body` on the joint model, whose cost map settings every floor's view keeps), nothing learned again."""
    root = Path(folder)
    model = with_body(load_model(root), body)
    path = root / BUILDING_JSON
    if not path.is_file():
        raise ModelError(f"{root} holds a model but no {BUILDING_JSON}: it is a single-floor model, not a building's")
    if BUILDING_JSON not in (read_manifest(root) or {}):
        raise ModelError(f"{path} is not listed in the folder's manifest.json: the folder was altered; save it again")
    doc = load_json(path, MAX_JSON_BYTES, "building model file", ModelError)
    if not isinstance(doc, dict) or set(doc) != {"format", "format_version", "spec", "layout"}:
        raise ModelError(f"{path} must be an object with format, format_version, spec and layout")
    if doc["format"] != FORMAT or doc["format_version"] != FORMAT_VERSION:
        raise ModelError(
            f"{path} is format {excerpt(doc['format'])} version {excerpt(doc['format_version'])}; this spcotmhp "
            f"reads {FORMAT} version {FORMAT_VERSION}"
        )
    try:
        spec = parse_spec(doc["spec"], root.name, f"{path} spec")
    except BuildingError as exc:
        raise ModelError(str(exc)) from None
    layout = Layout.from_dict(doc["layout"], str(path), ModelError)
    bm = BuildingModel(model, layout, spec)
    check_stops(spec, {i: layout.crop(model.require_map(), i) for i in layout.indices}, ModelError)
    return bm
