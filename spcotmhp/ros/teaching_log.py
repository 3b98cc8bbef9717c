"""Teaching while driving: utterances taught at the robot's pose, appended to a dataset folder in the project's
layout (``spcotmhp/data/README.md``) that ``spcotmhp learn`` and :func:`spcotmhp.datasets.load_dataset` read.

The folder gets ``recorded.json`` naming the model folder (:mod:`spcotmhp.teaching.recorded`: ``spcotmhp teach
MODEL --from DIR`` applies the recording to that model; ``spcotmhp learn DIR`` refuses it), the model's map
(``map.yaml`` + ``map.pgm``, as Nav2's map_saver writes it) when it is created,
and ``teaching.csv`` (``event,x,y,words_ja,words_en``) from the first utterance on; each utterance goes into the
column of its language (kana or kanji: ``words_ja``, cut into words and spaced as dataset rows are read, else
``words_en``). Every change rewrites the file
atomically (:mod:`spcotmhp.safe_write`): a reader, or a crash, sees the file before or after an utterance,
never half of one. An existing dataset folder is appended to when its map agrees with the model's.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from spcotmhp.datasets.tables import present, read_table
from spcotmhp.errors import DatasetError
from spcotmhp.language.text import is_japanese, words
from spcotmhp.learning.observations import MAX_UTTERANCE_CHARS
from spcotmhp.metric.map_io import load_map, save_map
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.ros.shapes import map_mismatches
from spcotmhp.safe_write import atomic_write_text, build_folder

HEADER = ("event", "x", "y", "words_ja", "words_en")


class TeachingLog:
    """A dataset folder that teaching events are appended to (module docstring)."""

    def __init__(self, folder: str | Path, occ: OccupancyMap, model_dir: str | Path | None = None) -> None:
        """``model_dir``: the model folder the teaching is said against, named in ``recorded.json`` (so that
        ``spcotmhp learn`` refuses the folder and ``spcotmhp teach MODEL --from`` applies it to that model)."""
        from spcotmhp.teaching.recorded import write_marker

        self.folder = Path(folder)
        self.teaching = self.folder / "teaching.csv"
        self.n_events = 0
        self.header: list[str] = list(HEADER)
        if self.folder.is_dir() and any(self.folder.iterdir()):
            self._adopt(occ)
        elif self.folder.exists() and not self.folder.is_dir():
            raise DatasetError(f"--record {self.folder} is a file; give a folder for the dataset")
        else:
            self._create(occ)
        if model_dir is not None:
            write_marker(self.folder, Path(model_dir))

    def _create(self, occ: OccupancyMap) -> None:
        if not self.folder.parent.is_dir():
            raise DatasetError(f"--record {self.folder}: the folder {self.folder.parent} does not exist")
        if self.folder.is_dir():  # an empty folder: fill it in place
            save_map(occ, self.folder / "map")
            return
        build_folder(self.folder, lambda new: save_map(occ, new / "map"), DatasetError)

    def _adopt(self, occ: OccupancyMap) -> None:
        """Append to an existing dataset folder: its map must agree with the model's; its teaching.csv (if any)
        must have event, x, y and a words column and no step column (steps index a trajectory not recorded)."""
        if not (self.folder / "map.yaml").is_file():
            raise DatasetError(
                f"--record {self.folder} is a folder with files but no map.yaml; give a new or "
                "empty folder, or a dataset folder to append to"
            )
        theirs = load_map(self.folder / "map.yaml")
        differ = map_mismatches(theirs.width, theirs.height, theirs.resolution, theirs.origin, occ)
        if differ:
            raise DatasetError(f"--record {self.folder}: its map differs from the model's ({'; '.join(differ)})")
        if not present(self.teaching):  # a symlink to /dev/zero is named as what it is, not taken as absent
            return
        table = read_table(self.teaching, "a header event,x,y,words_ja,words_en")
        table.require(["event", "x", "y", ("words_ja", "words_en")])
        if table.has("step"):
            raise DatasetError(
                f"{self.teaching} has a step column (events aligned to a trajectory); record into a new folder"
            )
        self.header = table.header
        self.n_events = len(table.rows)

    def append(self, x: float, y: float, utterance: str) -> int:
        """Record ``utterance`` taught at (x, y) (map frame, metres); returns its event id."""
        text = " ".join(str(utterance).split())
        if not text:
            raise DatasetError("the utterance is empty; say the place's name, e.g. 'this is the kitchen'")
        if len(text) > MAX_UTTERANCE_CHARS:
            raise DatasetError(
                f"the utterance has {len(text)} characters, more than the {MAX_UTTERANCE_CHARS} accepted"
            )
        if not (math.isfinite(x) and math.isfinite(y)):
            raise DatasetError(f"the pose ({x}, {y}) is not finite")
        column = "words_ja" if is_japanese(text) else "words_en"
        if column == "words_ja":  # recorded as the words the node taught, spaced as dataset rows are read
            text = " ".join(words(text, "ja"))
        if column not in self.header:
            raise DatasetError(f"{self.teaching} has no {column} column for {text[:40]!r}")
        values = {"event": str(self.n_events), "x": f"{x:.4f}", "y": f"{y:.4f}", column: text}
        old = self.teaching.read_text(encoding="utf-8-sig") if self.teaching.is_file() else ""
        if old and not old.endswith("\n"):
            old += "\n"
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        if not old:
            writer.writerow(self.header)
        writer.writerow([values.get(name, "") for name in self.header])
        atomic_write_text(self.teaching, old + buffer.getvalue(), DatasetError)
        self.n_events += 1
        return self.n_events - 1
