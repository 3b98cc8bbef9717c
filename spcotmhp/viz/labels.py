"""Place labels for pictures: the names plans use ("bedroom #2"), placed so that they do not overlap.

The label of a place is the one its plans and explanations use (:func:`spcotmhp.planning.place_labels`, numbered
"#1", "#2", ... in place-id order when several active places share a name, as
:class:`~spcotmhp.planning.plan.PlanPlace` does), so a picture and an explanation always agree.

:func:`arrange_labels` is a small greedy placer: each label, in turn, takes the candidate offset around its anchor
that overlaps least with the labels already placed, the obstacles (place centres, path marks) and the outside of
the axes.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from typing import Literal

import numpy as np
from matplotlib.axes import Axes
from matplotlib.text import Annotation
from matplotlib.transforms import Bbox

from spcotmhp.learning.model import SpatialConceptModel

# candidate offsets in points (dx, dy) with the alignment that keeps the text on that side of the anchor,
# nearest first: NE, SE, NW, SW, N, S, E, W, then the same twice as far
_SIDES = [(1, 1), (1, -1), (-1, 1), (-1, -1), (0, 1.4), (0, -1.4), (1.4, 0), (-1.4, 0)]
_CANDIDATES = [(dx * r, dy * r) for r in (5.0, 12.0, 20.0) for dx, dy in _SIDES]


def place_display_labels(
    model: SpatialConceptModel, place_words: Sequence[str] | None = None, ids: bool = False
) -> list[str]:
    """One label per place (K,): the planner's name, "#n" when several active places share it, "" for an
    inactive place; ``ids`` appends the place id ("bedroom #2 (9)")."""
    from spcotmhp.language.said_names import shown_names
    from spcotmhp.planning.plan import PlanPlace
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary

    words = place_vocabulary(model) if place_words is None else list(place_words)
    names = place_labels(model, words)
    shown = shown_names(names, model)  # as taught (said_names rule 6)
    act = [int(k) for k in np.flatnonzero(model.active_places)]
    out = [""] * model.K
    for k in act:
        same = [j for j in act if names[j] == names[k]]
        label = PlanPlace(k, shown[k], "", same.index(k) + 1, len(same)).label
        out[k] = f"{label} ({k})" if ids else label
    return out


_CJK_FAMILIES = (
    "Noto Sans CJK JP",
    "Noto Sans JP",
    "IPAexGothic",
    "IPAGothic",
    "TakaoGothic",
    "Hiragino Sans",
    "Yu Gothic",
    "MS Gothic",
    "Droid Sans Fallback",
    "WenQuanYi Zen Hei",
)


@lru_cache(maxsize=1)
def font_families() -> tuple[str, ...]:
    """The fonts for every text in a picture, in fallback order: DejaVu Sans (matplotlib's own), then a Japanese
    font: IPAexGothic shipped by the ``matplotlib-fontja`` dependency (registered here), or any installed one."""
    from matplotlib import font_manager

    try:
        from matplotlib_fontja import get_font_ttf_path

        font_manager.fontManager.addfont(get_font_ttf_path())
    except (ImportError, OSError, RuntimeError):  # the dependency missing or its file unreadable: fall back
        pass
    installed = {f.name for f in font_manager.fontManager.ttflist}
    return ("DejaVu Sans",) + tuple(f for f in _CJK_FAMILIES if f in installed)


@lru_cache(maxsize=1)
def _fonts() -> tuple:
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    paths = {
        font_manager.findfont(font_manager.FontProperties(family=f), fallback_to_default=True) for f in font_families()
    }
    return tuple(FT2Font(p) for p in sorted(paths))


def drawable(labels: Sequence[str]) -> list[str]:
    """``labels`` with every label that no installed font can draw (e.g. Japanese names on a machine without a
    Japanese font) replaced by "place k", so a picture never shows empty boxes; the names stay in the JSON."""
    fonts = _fonts()
    return [
        lab if all(c.isspace() or any(f.get_char_index(ord(c)) for f in fonts) for c in lab) else f"place {k}"
        for k, lab in enumerate(labels)
    ]


def _alignment(dx: float, dy: float) -> tuple[Literal["left", "right", "center"], Literal["bottom", "top", "center"]]:
    ha: Literal["left", "right", "center"] = "left" if dx > 0 else "right" if dx < 0 else "center"
    va: Literal["bottom", "top", "center"] = "bottom" if dy > 0 else "top" if dy < 0 else "center"
    return ha, va


def _overlap(a: Bbox, b: Bbox) -> float:
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return max(w, 0.0) * max(h, 0.0)


def arrange_labels(
    ax: Axes, labels: Sequence[Annotation], obstacles: np.ndarray | None = None, pad_px: float = 3.0
) -> None:
    """Move each annotation (``textcoords="offset points"``) to its least crowded candidate offset.

    Cost of a candidate: overlap area (pixels^2) with the labels placed so far and with a small square around
    every obstacle point ((n, 2) data coordinates), plus 4x the area that falls outside the axes, plus a small
    distance term that prefers the nearest side. Call after the axes limits and layout are final.
    """
    fig = ax.figure
    # the Agg canvas (the only backend this package draws with) has get_renderer; the stub of the base class not
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    frame = ax.get_window_extent(renderer)
    dots = []
    if obstacles is not None and len(obstacles):
        pts = ax.transData.transform(np.asarray(obstacles, dtype=float).reshape(-1, 2))
        r = 4.0 * fig.dpi / 72.0
        dots = [Bbox.from_extents(x - r, y - r, x + r, y + r) for x, y in pts]
    placed: list[Bbox] = []
    for ann in labels:
        best = None
        for dx, dy in _CANDIDATES:
            ann.set_position((dx, dy))
            ann.set_horizontalalignment(_alignment(dx, dy)[0])
            ann.set_verticalalignment(_alignment(dx, dy)[1])
            box = ann.get_window_extent(renderer).padded(pad_px)
            inside = Bbox.intersection(box, frame)
            outside = box.width * box.height - (0.0 if inside is None else inside.width * inside.height)
            cost = (
                sum(_overlap(box, o) for o in placed)
                + sum(_overlap(box, d) for d in dots)
                + 4.0 * outside
                + 2.0 * np.hypot(dx, dy)
            )
            if best is None or cost < best[0]:
                best = (cost, dx, dy, box)
        assert best is not None  # _CANDIDATES is not empty
        _, dx, dy, box = best
        ann.set_position((dx, dy))
        ann.set_horizontalalignment(_alignment(dx, dy)[0])
        ann.set_verticalalignment(_alignment(dx, dy)[1])
        placed.append(box)
