"""Lazily exported public names (spcotmhp/lazy.py): every name a package lists resolves to its object (a name
left behind when a module moved, as learning's `evaluate_learning` once was, fails here), and any other name is
an AttributeError."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import spcotmhp

PACKAGES = sorted(
    m.name for m in pkgutil.iter_modules(spcotmhp.__path__, "spcotmhp.") if m.ispkg and m.name != "spcotmhp.data"
)


@pytest.mark.parametrize("name", PACKAGES)
def test_every_public_name_of_a_package_resolves(name):
    package = importlib.import_module(name)
    for public in getattr(package, "__all__", []):
        assert getattr(package, public) is not None, f"{name}.{public}"


@pytest.mark.parametrize("name", ["spcotmhp.learning", "spcotmhp.persistence"])
def test_a_name_not_exported_is_an_attribute_error(name):
    package = importlib.import_module(name)
    with pytest.raises(AttributeError, match="has no attribute 'nothing_here'"):
        package.nothing_here  # noqa: B018
    assert package.__getattr__("save_model" if name.endswith("persistence") else "SpCoTMHP").__name__
