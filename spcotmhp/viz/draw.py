"""Pictures: the map, the places as Gaussian ellipses with names, the topological edges and a planned path.

Plotting stays at the edge: these functions take arrays and dataclasses and draw on matplotlib axes (Agg canvas,
no display needed). Thread safety (the HTTP service draws from worker threads): figures are
:class:`matplotlib.figure.Figure` objects with their own Agg canvas, never pyplot's global figure manager, and
:func:`render` and :func:`map_image` hold one module-wide lock, because matplotlib's rcParams (the font family
set for a picture) and its text caches are process-wide. :func:`render` writes the framed figure of the CLI (axes in
metres, legend, title);
:func:`map_image` the frameless, georeferenced picture of the HTTP service, whose pixels map linearly onto its
``extent`` so that a client can convert clicks to map coordinates.
"""

from __future__ import annotations

import io
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, overload

import matplotlib
import matplotlib.patheffects as pe
import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Ellipse
from matplotlib.text import Annotation

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.viz.labels import arrange_labels, drawable, font_families, place_display_labels

# Saturated, mutually distinct place colours; no red (the path's colour) and no grey/black (walls, unknown).
PALETTE = [
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
    "#393b79",
    "#1b9e77",
    "#e6ab02",
    "#e7298a",
    "#66a61e",
    "#7570b3",
    "#a6761d",
    "#0b6e4f",
]
PATH_COLOUR = "#d00000"
MARK_STYLE = {"start": ("s", "#00a651"), "waypoint": ("D", "#6a3d9a"), "goal": ("*", PATH_COLOUR)}
_DRAW_LOCK = threading.Lock()  # one picture at a time (module docstring)


def _figure(figsize: tuple[float, float], dpi: float | None = None) -> Figure:
    """A figure with its own Agg canvas (no pyplot)."""
    fig = Figure(figsize=figsize, dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


def place_colours(n: int) -> list[str]:
    """n place colours (the palette repeats beyond 16 places)."""
    return [PALETTE[i % len(PALETTE)] for i in range(n)]


def map_extent(occ_map: OccupancyMap) -> tuple[float, float, float, float]:
    """(left, right, bottom, top) in metres for imshow with origin='lower'."""
    x0, y0 = occ_map.origin[0], occ_map.origin[1]
    return (x0, x0 + occ_map.width * occ_map.resolution, y0, y0 + occ_map.height * occ_map.resolution)


def draw_map(ax: Axes, occ_map: OccupancyMap) -> None:
    """Occupancy grid: free white, occupied black, unknown grey (OccupancyGrid order -> origin='lower')."""
    img = np.full(occ_map.shape, 0.8)
    img[occ_map.free] = 1.0
    img[occ_map.occupied] = 0.0
    ax.imshow(img, cmap="gray", vmin=0, vmax=1, origin="lower", extent=map_extent(occ_map), interpolation="nearest")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")


def used_extent(
    occ_map: OccupancyMap, margin_m: float = 1.0, focus: np.ndarray | None = None
) -> tuple[float, float, float, float]:
    """Bounding box (x0, x1, y0, y1) in metres of the known (non-unknown) part of the map plus a margin; with
    ``focus`` points (n, 2), cut down to their bounding box plus the margin (real maps such as albert-b carry
    laser rays far beyond the building, which would shrink the places to a corner of the picture)."""
    full = map_extent(occ_map)
    known = ~occ_map.unknown
    box = full
    if known.any():
        rows = np.flatnonzero(known.any(axis=1))
        cols = np.flatnonzero(known.any(axis=0))
        lo = occ_map.cell_to_world(np.array([rows[0], cols[0]]))
        hi = occ_map.cell_to_world(np.array([rows[-1], cols[-1]]))
        box = (lo[0] - margin_m, hi[0] + margin_m, lo[1] - margin_m, hi[1] + margin_m)
    if focus is not None and len(focus):
        f = np.asarray(focus, dtype=float).reshape(-1, 2)
        fb = (
            f[:, 0].min() - margin_m,
            f[:, 0].max() + margin_m,
            f[:, 1].min() - margin_m,
            f[:, 1].max() + margin_m,
        )
        cut = (max(box[0], fb[0]), min(box[1], fb[1]), max(box[2], fb[2]), min(box[3], fb[3]))
        if cut[0] < cut[1] and cut[2] < cut[3]:
            box = cut
    return (max(full[0], box[0]), min(full[1], box[1]), max(full[2], box[2]), min(full[3], box[3]))


def focus_points(
    model: SpatialConceptModel | None, path_xy: np.ndarray | None = None, n_std: float = 2.5
) -> np.ndarray | None:
    """Points a picture must show: the corners of each active place's n_std-sigma box and the path."""
    pts = []
    if model is not None:
        act = np.asarray(model.active_places, dtype=bool)
        sd = np.sqrt(np.stack([model.Sigma[act, 0, 0], model.Sigma[act, 1, 1]], axis=1))
        pts += [model.mu[act] - n_std * sd, model.mu[act] + n_std * sd]
    if path_xy is not None and len(path_xy):
        pts.append(np.asarray(path_xy, dtype=float).reshape(-1, 2))
    return np.vstack(pts) if pts else None


def topological_edges(model: SpatialConceptModel) -> list[tuple[int, int]]:
    """Undirected edges as in the paper's Figure 3, (psi_ab + psi_ba) / 2 >= 1 / K between active places: the
    very place graph the planner moves on (:func:`spcotmhp.planning.places.connected_places`)."""
    from spcotmhp.planning.places import connected_places

    conn = np.triu(connected_places(model), k=1)
    return [(int(a), int(b)) for a, b in zip(*np.nonzero(conn), strict=False)]


def draw_places(
    ax: Axes,
    model: SpatialConceptModel,
    names: Sequence[str] | None = None,
    n_std: float = 2.0,
    edges: bool = True,
    fontsize: float = 8.0,
) -> list[Annotation]:
    """Each active place's Gaussian as an n_std-sigma ellipse labelled with its name (default: the planner's
    labels, :func:`place_display_labels`), plus the edges; returns the label annotations (for
    :func:`arrange_labels`)."""
    names = drawable(list(names) if names is not None else place_display_labels(model))
    act = np.flatnonzero(model.active_places)
    colours = place_colours(len(act))
    if edges:
        for a, b in topological_edges(model):
            ax.plot(*zip(model.mu[a], model.mu[b], strict=False), color="#555555", lw=1.2, alpha=0.8, zorder=2)
    labels = []
    for c, k in zip(colours, act, strict=False):
        vals, vecs = np.linalg.eigh(model.Sigma[k])
        vals = np.clip(vals, 1e-12, None)
        angle = float(np.degrees(np.arctan2(vecs[1, 1], vecs[0, 1])))
        width, height = 2 * n_std * np.sqrt(vals[1]), 2 * n_std * np.sqrt(vals[0])
        ax.add_patch(
            Ellipse(model.mu[k], width, height, angle=angle, facecolor=c, edgecolor="none", alpha=0.18, zorder=3)
        )
        ax.add_patch(Ellipse(model.mu[k], width, height, angle=angle, fill=False, edgecolor=c, lw=1.6, zorder=3))
        ax.plot(*model.mu[k], "o", color=c, ms=4.5, mec="white", mew=0.8, zorder=4)
        labels.append(
            ax.annotate(
                names[k],
                model.mu[k],
                xytext=(5, 5),
                textcoords="offset points",
                fontsize=fontsize,
                family=list(font_families()),
                color="#111111",
                zorder=8,
                annotation_clip=False,
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": c, "lw": 1.2, "alpha": 0.9},
            )
        )
    return labels


def draw_path(ax: Axes, path_xy: np.ndarray, marks: Sequence[tuple[np.ndarray, str, str]] = ()) -> np.ndarray:
    """A world path (n, 2) and labelled marks [(xy, label, role)] with role in start / waypoint / goal; returns
    the marks' points (m, 2)."""
    path_xy = np.asarray(path_xy, dtype=float)
    if len(path_xy):
        ax.plot(
            path_xy[:, 0],
            path_xy[:, 1],
            "-",
            color=PATH_COLOUR,
            lw=2.4,
            zorder=5,
            label="path",
            path_effects=[pe.Stroke(linewidth=4.5, foreground="white"), pe.Normal()],
        )
    for xy, label, role in marks:
        m, c = MARK_STYLE.get(role, ("o", "k"))
        ax.plot(
            *xy,
            m,
            color=c,
            ms=15 if role == "goal" else 10,
            mec="white",
            mew=1.4,
            zorder=7,
            label=f"{role}: {label}",
        )
    return np.array([xy for xy, _, _ in marks], dtype=float).reshape(-1, 2)


def _centres(model: SpatialConceptModel | None) -> np.ndarray:
    return np.empty((0, 2)) if model is None else model.mu[np.asarray(model.active_places, dtype=bool)]


@overload
def render(
    occ_map: OccupancyMap,
    out: str | Path,
    model: SpatialConceptModel | None = ...,
    names: Sequence[str] | None = ...,
    path_xy: np.ndarray | None = ...,
    marks: Sequence[tuple[np.ndarray, str, str]] = ...,
    title: str | None = ...,
    dpi: int = ...,
) -> Path: ...


@overload
def render(
    occ_map: OccupancyMap,
    out: BinaryIO,
    model: SpatialConceptModel | None = ...,
    names: Sequence[str] | None = ...,
    path_xy: np.ndarray | None = ...,
    marks: Sequence[tuple[np.ndarray, str, str]] = ...,
    title: str | None = ...,
    dpi: int = ...,
) -> BinaryIO: ...


def render(
    occ_map: OccupancyMap,
    out: str | Path | BinaryIO,
    model: SpatialConceptModel | None = None,
    names: Sequence[str] | None = None,
    path_xy: np.ndarray | None = None,
    marks: Sequence[tuple[np.ndarray, str, str]] = (),
    title: str | None = None,
    dpi: int = 150,
) -> Path | BinaryIO:
    """Draw the map (+ places, edges, path) with axes in metres and write a PNG to a file (its folder is
    created) or a binary stream; returns ``out`` (as a Path when it is a file name)."""
    if isinstance(out, (str, Path)):
        out = Path(out)
        out.parent.mkdir(parents=True, exist_ok=True)
    x0, x1, y0, y1 = used_extent(occ_map, focus=focus_points(model, path_xy))
    aspect = (y1 - y0) / max(x1 - x0, 1e-9)
    with _DRAW_LOCK, matplotlib.rc_context({"font.family": list(font_families())}):
        _render(occ_map, out, model, names, path_xy, marks, title, dpi, (x0, x1, y0, y1), aspect)
    return out


def _render(
    occ_map: OccupancyMap,
    out: Path | BinaryIO,
    model: SpatialConceptModel | None,
    names: Sequence[str] | None,
    path_xy: np.ndarray | None,
    marks: Sequence[tuple[np.ndarray, str, str]],
    title: str | None,
    dpi: int,
    extent: tuple[float, float, float, float],
    aspect: float,
) -> None:
    x0, x1, y0, y1 = extent
    fig = _figure((8, max(4.0, min(12.0, 8 * aspect)) + 0.6))
    ax = fig.subplots()
    draw_map(ax, occ_map)
    labels = draw_places(ax, model, names) if model is not None else []
    points = _centres(model)
    if path_xy is not None:
        points = np.vstack([points, draw_path(ax, path_xy, marks)])
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=True)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    if title:
        ax.set_title(title, fontsize=10, wrap=True)
    fig.tight_layout()
    arrange_labels(ax, labels, points)
    fig.savefig(out, format="png", dpi=dpi, bbox_inches="tight")


@dataclass(frozen=True)
class MapImage:
    """A frameless map picture: PNG bytes whose pixel (0, 0) is the top-left corner (x0, y1) of ``extent``
    = (x0, x1, y0, y1) metres and whose pixel (width, height) is the bottom-right corner (x1, y0)."""

    png: bytes
    extent: tuple[float, float, float, float]
    width: int
    height: int

    def to_world(self, px: float, py: float) -> tuple[float, float]:
        """Map-frame metres of image pixel coordinates (px right, py down)."""
        x0, x1, y0, y1 = self.extent
        return (x0 + px / self.width * (x1 - x0), y1 - py / self.height * (y1 - y0))


def map_image(model: SpatialConceptModel, px_per_m: float = 60.0, dpi: int = 100) -> MapImage:
    """The learned map (places, names, edges) without axes, georeferenced by its extent (see :class:`MapImage`)."""
    occ = model.require_map()
    x0, x1, y0, y1 = used_extent(occ, focus=focus_points(model))
    width, height = max(1, round((x1 - x0) * px_per_m)), max(1, round((y1 - y0) * px_per_m))
    with _DRAW_LOCK:
        fig = _figure((width / dpi, height / dpi), dpi)
        ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
        draw_map(ax, occ)
        labels = draw_places(ax, model, fontsize=9.0)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("auto")
        ax.set_axis_off()
        arrange_labels(ax, labels, _centres(model))
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi)
    return MapImage(buf.getvalue(), (float(x0), float(x1), float(y0), float(y1)), width, height)
