"""Recorded teaching applied to the model it was said against (issue 24).

``spcotmhp ros2 MODEL --record DIR`` appends every utterance taught at the robot's pose to the dataset folder DIR
(:mod:`spcotmhp.ros.teaching_log`) and writes ``DIR/recorded.json`` naming MODEL. Those utterances were said to a
robot that already had a map and places: learning DIR alone (``spcotmhp learn DIR``) would give a model of the
recorded utterances only, so ``learn`` refuses such a folder and points to ``spcotmhp teach MODEL --from DIR``,
which applies each recorded row to MODEL as the node did (:func:`spcotmhp.teaching.teach.teach`: naming events
on MODEL's learner state, its map and earlier data kept).

Applying is idempotent: the model keeps, per recording folder (resolved path), how many of its rows it has
learned (``info["recordings"]``), and a later ``teach --from`` applies only the rows added since.
"""

from __future__ import annotations

import json
from pathlib import Path

from spcotmhp.errors import DatasetError, TeachingError
from spcotmhp.learning.model import SpatialConceptModel

MARKER = "recorded.json"
FORMAT = "spcotmhp-recording"


def write_marker(folder: Path, model_dir: Path | None) -> None:
    """Write ``folder/recorded.json`` naming the model folder the teaching is recorded against."""
    from spcotmhp.safe_write import atomic_write_text

    text = json.dumps({"format": FORMAT, "model": None if model_dir is None else str(Path(model_dir).resolve())})
    atomic_write_text(folder / MARKER, text + "\n", DatasetError)


def read_marker(folder: Path) -> dict | None:
    """``recorded.json`` of a folder (None when it has none); DatasetError when it is not one of ours."""
    from spcotmhp.datasets.tables import present
    from spcotmhp.safe_read import load_json

    path = Path(folder) / MARKER
    if not present(path):
        return None
    meta = load_json(path, 4096, "recording marker", DatasetError)
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise DatasetError(f"{path} is not a spcotmhp recording marker (format {FORMAT})")
    return meta


def refuse_learning_alone(folder: Path) -> None:
    """DatasetError when ``folder`` holds teaching recorded against a model (module docstring)."""
    meta = read_marker(folder)
    if meta is None:
        return
    model = meta.get("model") or "MODEL"
    raise DatasetError(
        f"{folder} holds teaching recorded against the model {model} (spcotmhp ros2 --record); learned alone it "
        f"would be a model of those utterances only: apply them to that model with "
        f"'spcotmhp teach {model} --from {folder}'"
    )


def recorded_utterances(folder: Path, model: SpatialConceptModel) -> list[dict]:
    """Every row of ``folder/teaching.csv`` as a teach {"x", "y", "utterance"}, in order; DatasetError when the
    folder's map is not the model's (the teaching was said on another map) or a row has no utterance."""
    from spcotmhp.datasets.tables import present, read_table
    from spcotmhp.metric.map_io import load_map

    folder = Path(folder)
    if not present(folder / "teaching.csv"):
        raise DatasetError(f"{folder} has no teaching.csv: record one with 'spcotmhp ros2 MODEL --record {folder}'")
    if not (folder / "map.yaml").is_file() or load_map(folder / "map.yaml") != model.require_map():
        raise DatasetError(f"{folder}: its map is not the model's; teaching recorded on another map cannot be applied")
    table = read_table(folder / "teaching.csv", "a header event,x,y,words_ja,words_en")
    table.require(["x", "y", ("words_ja", "words_en")])
    xs, ys = table.floats("x"), table.floats("y")
    columns = [c for c in ("words_en", "words_ja") if table.has(c)]
    out = []
    for i in range(len(table.rows)):
        said = next((t for c in columns if (t := table.column(c)[i].strip())), "")
        if not said:
            raise DatasetError(f"{table.where(i)}: no utterance in {' or '.join(columns)}")
        out.append({"x": float(xs[i]), "y": float(ys[i]), "utterance": said, "where": table.where(i)})
    return out


def apply_recording(model: SpatialConceptModel, folder: Path):
    """(the taught result or None when nothing is new, rows applied now, rows in the recording): the rows of
    ``folder`` that ``model`` has not learned yet, taught in order (module docstring). Nothing is learned when a
    row is refused (TeachingError naming the row)."""
    from spcotmhp.teaching.teach import naming_event, teach

    rows = recorded_utterances(folder, model)
    key = str(Path(folder).resolve())
    done = dict((model.info or {}).get("recordings") or {})
    start = int(done.get(key, 0))
    new = rows[start:]
    if not new:
        return None, 0, len(rows)
    for row in new:
        try:
            naming_event(row)
        except TeachingError as exc:
            raise type(exc)(f"{row['where']}: {exc}") from None
    taught = teach(model, [{k: row[k] for k in ("x", "y", "utterance")} for row in new])
    taught.model.info["recordings"] = {**done, key: len(rows)}
    return taught, len(new), len(rows)
