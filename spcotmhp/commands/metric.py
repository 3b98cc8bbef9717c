"""CLI commands of the metric level (maps and cost maps)."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    """Add the metric-level commands to ``app``."""
