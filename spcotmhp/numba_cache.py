"""Where numba keeps its compiled kernels (module docstring of :mod:`spcotmhp.warmup`): set before numba is
imported, so it lives at the bottom of the package, below every module that compiles a kernel."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["cache_dir_default"]


def cache_dir_default() -> str | None:
    """Set ``NUMBA_CACHE_DIR`` to a user cache folder when the package folder is not writable and the variable
    is unset (call before numba is imported); returns the folder numba will use, None for its default."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return os.environ["NUMBA_CACHE_DIR"]
    package = Path(__file__).resolve().parent
    if os.access(package, os.W_OK):
        return None
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    folder = base / "spcotmhp" / "numba"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    return str(folder)
