"""The real datasets shipped inside the package (spcotmhp/data/): SIGVerse homes 3LDK_01/05/06 and albert-b.

A bundled dataset is any folder under spcotmhp/data/ holding a teaching.csv; it is named by its folder name
("3LDK_01") or by its path under data/ ("sigverse-3ldk/3LDK_01").
"""

from __future__ import annotations

import warnings
from importlib import resources
from pathlib import Path

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.loader import DatasetWarning, load_dataset
from spcotmhp.errors import DatasetError

# Per-process state, by design (as the warnings module's own registry): the bundled datasets whose known warnings
# this process has already summarised, so that a session is told once. Only add() is used (safe under the GIL).
_ANNOUNCED: set[str] = set()


def data_root() -> Path:
    """The package's data folder on the file system."""
    root = resources.files("spcotmhp") / "data"
    if not isinstance(root, Path):  # e.g. imported from a zip file
        raise DatasetError(f"the bundled data is not on the file system ({root}); install spcotmhp unzipped")
    return root


def _folders() -> dict[str, Path]:
    """Relative path under data/ -> folder, for every bundled dataset (not the example inputs under examples/: the
    floors of the example building are read through its building.yaml)."""
    root = data_root()
    found = sorted(p for p in root.rglob("teaching.csv") if p.relative_to(root).parts[0] != "examples")
    return {p.parent.relative_to(root).as_posix(): p.parent for p in found}


def list_bundled() -> list[str]:
    """Names of the bundled datasets, e.g. ["3LDK_01", "3LDK_05", "3LDK_06", "albert-b"]."""
    return sorted((Path(rel).name for rel in _folders()), key=str.lower)


def bundled_path(name: str) -> Path:
    """The folder of a bundled dataset, by name ("3LDK_01") or path under data/ ("sigverse-3ldk/3LDK_01");
    case-insensitive."""
    folders = _folders()
    wanted = name.strip().strip("/").lower()
    for rel, folder in folders.items():
        if wanted in (rel.lower(), folder.name.lower()):
            return folder
    known = ", ".join(list_bundled())
    raise DatasetError(f"no bundled dataset named {name!r}; known: {known}")


def load_bundled(name: str, lang: str = "en") -> Dataset:
    """:func:`load_dataset` on a bundled dataset (albert-b has Japanese words only: use lang="ja").

    The bundled data's known warnings (teaching points recorded at the edge of a wall, listed in
    spcotmhp/data/README.md) are summarised in one DatasetWarning, the first time each dataset is loaded in a
    process; ``spcotmhp check-dataset NAME`` lists them."""
    path = bundled_path(name)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DatasetWarning)
        data = load_dataset(path, lang=lang)
    known = 0
    for w in caught:
        if issubclass(w.category, DatasetWarning):
            known += 1
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if known and path.name not in _ANNOUNCED:
        _ANNOUNCED.add(path.name)
        warnings.warn(DatasetWarning(known_warnings_note(path.name, known)), stacklevel=2)
    return data


def known_warnings_note(name: str, count: int) -> str:
    """The one line that stands for a bundled dataset's ``count`` known warnings."""
    return (
        f"{name}: {count} known warning(s) of the bundled data (teaching points recorded at the edge of a wall; "
        f"spcotmhp/data/README.md); `spcotmhp check-dataset {name}` lists them"
    )
