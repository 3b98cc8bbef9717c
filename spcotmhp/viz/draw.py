"""Pictures: the map, the places as Gaussian ellipses with names, the topological edges and a planned path.

Plotting stays at the edge: these functions take arrays and dataclasses and draw on matplotlib axes (Agg backend,
no display needed).
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402

from spcotmhp.learning.model import SpatialConceptModel  # noqa: E402
from spcotmhp.metric.maps import OccupancyMap  # noqa: E402

# Distinct, colour-blind-friendly colours (Okabe-Ito, then tab20 for more places).
_BASE_COLOURS = ["#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#F0E442", "#000000"]


def place_colours(n: int) -> list:
    """n distinct colours for places."""
    if n <= len(_BASE_COLOURS):
        return _BASE_COLOURS[:n]
    cmap = plt.get_cmap("tab20")
    return [cmap(i % 20) for i in range(n)]


def map_extent(occ_map: OccupancyMap) -> tuple[float, float, float, float]:
    """(left, right, bottom, top) in metres for imshow with origin='lower'."""
    x0, y0 = occ_map.origin[0], occ_map.origin[1]
    return (x0, x0 + occ_map.width * occ_map.resolution, y0, y0 + occ_map.height * occ_map.resolution)


def draw_map(ax: Axes, occ_map: OccupancyMap) -> None:
    """Occupancy grid: free white, occupied black, unknown grey (OccupancyGrid order -> origin='lower')."""
    img = np.full(occ_map.shape, 0.8)
    img[occ_map.free] = 1.0
    img[occ_map.occupied] = 0.0
    ax.imshow(img, cmap="gray", vmin=0, vmax=1, origin="lower", extent=map_extent(occ_map),
              interpolation="nearest")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")


def used_extent(occ_map: OccupancyMap, margin_m: float = 1.0) -> tuple[float, float, float, float]:
    """Bounding box (x0, x1, y0, y1) of the known (non-unknown) part of the map plus a margin, in metres."""
    known = ~occ_map.unknown
    if not known.any():
        return map_extent(occ_map)
    rows = np.flatnonzero(known.any(axis=1))
    cols = np.flatnonzero(known.any(axis=0))
    lo = occ_map.cell_to_world(np.array([rows[0], cols[0]]))
    hi = occ_map.cell_to_world(np.array([rows[-1], cols[-1]]))
    full = map_extent(occ_map)
    return (max(full[0], lo[0] - margin_m), min(full[1], hi[0] + margin_m),
            max(full[2], lo[1] - margin_m), min(full[3], hi[1] + margin_m))


def topological_edges(model: SpatialConceptModel) -> list[tuple[int, int]]:
    """Undirected edges drawn as in the paper's Figure 3: (psi_ab + psi_ba) / 2 > 1 / K, active places only."""
    act = np.flatnonzero(model.active_places)
    sym = (model.psi + model.psi.T) / 2.0
    thresh = 1.0 / model.K
    return [(int(a), int(b)) for i, a in enumerate(act) for b in act[i + 1:] if sym[a, b] > thresh]


def draw_places(ax: Axes, model: SpatialConceptModel, names: Sequence[str] | None = None,
                n_std: float = 2.0, edges: bool = True) -> None:
    """Each active place's Gaussian as an n_std-sigma ellipse labelled with its name, plus the edges."""
    names = list(names) if names is not None else model.place_names()
    act = np.flatnonzero(model.active_places)
    colours = place_colours(len(act))
    if edges:
        for a, b in topological_edges(model):
            ax.plot(*zip(model.mu[a], model.mu[b]), color="#555555", lw=1.2, alpha=0.8, zorder=2)
    for c, k in zip(colours, act):
        vals, vecs = np.linalg.eigh(model.Sigma[k])
        vals = np.clip(vals, 1e-12, None)
        angle = float(np.degrees(np.arctan2(vecs[1, 1], vecs[0, 1])))
        ell = Ellipse(model.mu[k], 2 * n_std * np.sqrt(vals[1]), 2 * n_std * np.sqrt(vals[0]), angle=angle,
                      facecolor=c, edgecolor=c, alpha=0.25, lw=1.5, zorder=3)
        ax.add_patch(ell)
        ax.add_patch(Ellipse(model.mu[k], ell.width, ell.height, angle=angle, fill=False, edgecolor=c,
                             lw=1.5, zorder=3))
        ax.plot(*model.mu[k], "o", color=c, ms=4, zorder=4)
        ax.annotate(f"{names[k]} ({k})", model.mu[k], xytext=(4, 4), textcoords="offset points", fontsize=8,
                    zorder=6, bbox=dict(boxstyle="round,pad=0.2", fc="white", ec=c, alpha=0.85))


def draw_path(ax: Axes, path_xy: np.ndarray, marks: Sequence[tuple[np.ndarray, str, str]] = ()) -> None:
    """A world path (n, 2) and labelled marks [(xy, label, role)] with role in start / waypoint / goal."""
    path_xy = np.asarray(path_xy, dtype=float)
    if len(path_xy):
        ax.plot(path_xy[:, 0], path_xy[:, 1], "-", color="#D00000", lw=2.2, zorder=5, label="path")
    style = {"start": ("s", "#1B9E77"), "waypoint": ("D", "#7570B3"), "goal": ("*", "#D00000")}
    for xy, label, role in marks:
        m, c = style.get(role, ("o", "k"))
        ax.plot(*xy, m, color=c, ms=12 if role == "goal" else 9, mec="white", mew=1.2, zorder=7,
                label=f"{role}: {label}")


def render(occ_map: OccupancyMap, out: str | Path, model: SpatialConceptModel | None = None,
           names: Sequence[str] | None = None, path_xy: np.ndarray | None = None,
           marks: Sequence[tuple[np.ndarray, str, str]] = (), title: str | None = None,
           dpi: int = 150) -> Path:
    """Draw the map (+ places, edges, path) and write a PNG; returns the path written."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    x0, x1, y0, y1 = used_extent(occ_map)
    aspect = (y1 - y0) / max(x1 - x0, 1e-9)
    fig, ax = plt.subplots(figsize=(8, max(4.0, min(12.0, 8 * aspect)) + 0.6))
    try:
        draw_map(ax, occ_map)
        if model is not None:
            draw_places(ax, model, names)
        if path_xy is not None:
            draw_path(ax, path_xy, marks)
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=True)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        if title:
            ax.set_title(title, fontsize=10, wrap=True)
        fig.tight_layout()
        fig.savefig(out, dpi=dpi, bbox_inches="tight")
    finally:
        plt.close(fig)
    return out
