"""Public names of a package imported on first use, so that importing one of its modules stays light."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any


def lazy_exports(package: str, exports: dict[str, str]) -> Callable[[str], Any]:
    """The module ``__getattr__`` of ``package`` that imports ``exports[name]`` (a submodule) on first use of a
    public ``name``; any other name is an AttributeError as for a plain module.

    >>> getattr_ = lazy_exports("spcotmhp.persistence", {"load_model": "io"})
    >>> getattr_("load_model").__module__
    'spcotmhp.persistence.io'
    """

    def __getattr__(name: str) -> Any:
        if name in exports:
            return getattr(importlib.import_module(f"{package}.{exports[name]}"), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
