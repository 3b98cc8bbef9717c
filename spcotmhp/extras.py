"""How to install an optional extra, said so that the command works where the user is: from a clone (an
editable install: ``.venv/bin/python -m pip install -e '.[server]'``) or from an installed package (the
extra's own packages, which are on PyPI: ``python -m pip install 'fastapi>=0.110' ...``), with the pip of the
interpreter that is running."""

from __future__ import annotations

import os
import re
import sys
from importlib import metadata
from pathlib import Path

EXTRAS = ("server", "speech", "ros", "dist", "dev")


def _shown(path: Path) -> str:
    """``path`` relative to the working folder when it lies inside it, else absolute."""
    try:
        rel = os.path.relpath(path)
    except ValueError:  # pragma: no cover - another drive (Windows)
        return str(path)
    return str(path) if rel.startswith("..") else rel


def source_tree() -> Path | None:
    """The source checkout this package runs from (a folder holding pyproject.toml beside ``spcotmhp/``), or
    None for an installed copy."""
    root = Path(__file__).resolve().parent.parent
    return root if (root / "pyproject.toml").is_file() and (root / "spcotmhp").is_dir() else None


def extra_requirements(extra: str) -> list[str]:
    """The requirements of ``extra`` from the installed metadata (``fastapi>=0.110``, ...); [] when unknown."""
    try:
        requires = metadata.requires("spcotmhp") or []
    except metadata.PackageNotFoundError:
        return []
    out = []
    for line in requires:
        requirement, _, marker = line.partition(";")
        if re.search(rf"""extra\s*==\s*["']{re.escape(extra)}["']""", marker):
            out.append(requirement.strip())
    return out


def install_hint(extra: str) -> str:
    """A command that installs ``extra`` for the running interpreter, runnable as typed from here."""
    pip = f"{_shown(Path(sys.executable))} -m pip install"
    root = source_tree()
    if root is not None:
        target = "." if _shown(root) == "." else _shown(root)
        return f"{pip} -e '{target}[{extra}]'"
    requirements = extra_requirements(extra)
    if not requirements:
        return f"{pip} 'spcotmhp[{extra}]'"
    return f"{pip} " + " ".join(f"'{r}'" for r in requirements)


def missing_extra(what: str, extra: str) -> str:
    """'<what> needs the extra 'server': <install command>'."""
    return f"{what} needs the extra '{extra}': {install_hint(extra)}"


def command_prefix() -> str:
    """How to call the ``spcotmhp`` command from here: ``spcotmhp`` when that name on the PATH is this
    installation's script, else the script's path (``.venv/bin/spcotmhp``: no activation needed), else
    ``python -m spcotmhp`` with this interpreter."""
    import shutil

    script = Path(sys.executable).parent / "spcotmhp"
    found = shutil.which("spcotmhp")
    if found and script.exists() and Path(found).resolve() == script.resolve():
        return "spcotmhp"
    if script.exists():
        return _shown(script) if "/" in _shown(script) else f"./{_shown(script)}"
    return f"{_shown(Path(sys.executable))} -m spcotmhp"
