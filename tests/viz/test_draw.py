"""Pictures: place labels, Figure 3 edges, label placement, the georeferenced service image and plan figures."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

from spcotmhp.datasets import load_bundled
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.viz.draw import (
    PALETTE,
    PATH_COLOUR,
    map_image,
    place_colours,
    render,
    topological_edges,
    used_extent,
)
from spcotmhp.viz.labels import arrange_labels, drawable, font_families, place_display_labels
from spcotmhp.viz.plan import draw_plan, plan_marks
from tests.helpers.graphs import GRAPHS
from tests.helpers.planning import home_log_p, home_model, world


@pytest.fixture(scope="module")
def home():
    model = home_model()
    return model, HierarchicalPlanner(model, log_p=home_log_p(model.map), cache=GRAPHS)


def test_labels_number_places_that_share_a_name(home):
    model, _ = home
    # ORDER = L (bedroom), M (corridor), K (kitchen), R (bedroom): the bedrooms are #1 and #2 in id order
    assert place_display_labels(model) == ["bedroom #1", "corridor", "kitchen", "bedroom #2"]
    assert place_display_labels(model, ids=True) == [
        "bedroom #1 (0)",
        "corridor (1)",
        "kitchen (2)",
        "bedroom #2 (3)",
    ]


def test_labels_of_inactive_places_are_empty():
    m = home_model()
    m.active_places = np.array([True, True, True, False])
    assert place_display_labels(m) == ["bedroom", "corridor", "kitchen", ""]


def test_labels_agree_with_the_plan(home):
    model, planner = home
    plan = planner.plan("go to the bedroom via the corridor", world(model.map, 9, 15))  # in the kitchen
    labels = place_display_labels(model)
    # kitchen -> bedroom #2 -> corridor (waypoint) -> bedroom #1: the kitchen's only door opens into bedroom #2
    assert [p.id for p in plan.places] == [2, 3, 1, 0]
    assert [labels[p.id] for p in plan.places] == [p.label for p in plan.places]
    assert "bedroom #2 -> corridor (waypoint) -> bedroom #1" in plan.explanation


def test_labels_no_font_can_draw_become_place_ids():
    # U+0378 is unassigned in Unicode: no font has it. Plain text and spaces are kept.
    assert drawable(["bedroom #1", "\u0378\u0378", "living room"]) == ["bedroom #1", "place 1", "living room"]
    assert font_families()[0] == "DejaVu Sans"


def test_edges_are_the_figure_3_rule_on_the_planners_graph(home):
    model, _ = home
    # psi = (A + 0.1) / row sums with doors L-M, M-R, K-R; 1/K = 0.25. L-M: (1.1/2.4 + 1.1/3.4) / 2 = 0.39 is an
    # edge, L-K: (0.1/2.4 + 0.1/2.3) / 2 = 0.043 is not
    assert topological_edges(model) == [(0, 1), (1, 3), (2, 3)]
    sym = (model.psi + model.psi.T) / 2
    assert sym[0, 1] == pytest.approx((1.1 / 2.4 + 1.1 / 3.4) / 2)


def test_edges_skip_inactive_places():
    m = home_model()
    m.active_places = np.array([True, True, True, False])
    assert topological_edges(m) == [(0, 1)]


def test_place_colours_are_distinct_and_never_the_path_colour():
    cols = place_colours(16)
    assert len(set(cols)) == 16
    assert PATH_COLOUR not in PALETTE
    assert place_colours(17)[16] == cols[0]


def _boxes(fig, anns):
    renderer = fig.canvas.get_renderer()
    return [a.get_window_extent(renderer) for a in anns]


def test_arrange_labels_separates_labels_on_one_anchor_and_keeps_them_inside():
    fig, ax = plt.subplots(figsize=(4, 4), dpi=100)
    try:
        ax.set_xlim(0, 10)
        ax.set_ylim(0, 10)
        anns = [
            ax.annotate(t, (5, 5), xytext=(5, 5), textcoords="offset points", fontsize=9)
            for t in ("bedroom #1", "bedroom #2", "corridor", "kitchen")
        ]
        edge = ax.annotate("a long label at the edge", (9.9, 9.9), xytext=(5, 5), textcoords="offset points")
        arrange_labels(ax, anns + [edge])
        boxes = _boxes(fig, anns + [edge])
        frame = ax.get_window_extent(fig.canvas.get_renderer())
        for i, a in enumerate(boxes):
            assert frame.x0 <= a.x0 and a.x1 <= frame.x1 and frame.y0 <= a.y0 and a.y1 <= frame.y1
            for b in boxes[i + 1 :]:
                assert not a.overlaps(b)
    finally:
        plt.close(fig)


def test_arrange_labels_avoids_obstacle_points():
    fig, ax = plt.subplots(figsize=(4, 4), dpi=100)
    try:
        ax.set_xlim(0, 10)
        ax.set_ylim(0, 10)
        ann = ax.annotate("goal", (5, 5), xytext=(5, 5), textcoords="offset points")
        obstacle = np.array([[5.6, 5.4]])  # just north-east of the anchor, where the label would go
        arrange_labels(ax, [ann], obstacle)
        box = _boxes(fig, [ann])[0]
        px, py = ax.transData.transform(obstacle[0])
        assert not (box.x0 <= px <= box.x1 and box.y0 <= py <= box.y1)
    finally:
        plt.close(fig)


def test_map_image_is_georeferenced(home):
    model, _ = home
    img = map_image(model, px_per_m=20.0)
    pil = Image.open(io.BytesIO(img.png))
    assert pil.size == (img.width, img.height)
    assert img.extent == pytest.approx(used_extent(model.map))
    x0, x1, y0, y1 = img.extent
    assert img.to_world(0, 0) == pytest.approx((x0, y1))
    assert img.to_world(img.width, img.height) == pytest.approx((x1, y0))
    assert (img.width, img.height) == (round((x1 - x0) * 20), round((y1 - y0) * 20))
    rgb = np.asarray(pil.convert("RGB")).astype(int)

    def pixel(xy):
        px = (xy[0] - x0) / (x1 - x0) * img.width
        py = (y1 - xy[1]) / (y1 - y0) * img.height
        return rgb[int(py), int(px)]

    assert pixel(world(model.map, 0, 15)).max() < 60  # the bottom wall (row 0) is black
    assert pixel(world(model.map, 12, 5)).max() < 60  # the top wall
    assert pixel(world(model.map, 6, 20)).max() < 60  # the wall between corridor/kitchen and bedroom #2
    assert pixel(world(model.map, 3, 20)).min() > 150  # the door M-R at col 20 rows 2-4 is light


def test_render_writes_a_framed_png_to_a_file_or_a_stream(home, tmp_path):
    model, _ = home
    out = render(model.map, tmp_path / "sub" / "map.png", model=model, title="learned map")
    assert out == tmp_path / "sub" / "map.png" and Image.open(out).format == "PNG"
    buf = io.BytesIO()
    assert render(model.map, buf, model=model) is buf
    assert Image.open(io.BytesIO(buf.getvalue())).size[0] > 400


def test_plan_figure_marks_start_waypoint_and_goal(home, tmp_path):
    model, planner = home
    plan = planner.plan("go to the bedroom via the corridor", world(model.map, 9, 15))
    marks = plan_marks(plan)
    assert [role for _, _, role in marks] == ["start", "waypoint", "goal"]
    assert [label for _, label, _ in marks] == ["kitchen", "corridor", "bedroom #1"]
    np.testing.assert_allclose(marks[0][0], plan.path[0])
    np.testing.assert_allclose(marks[2][0], plan.goal.point)
    out = draw_plan(plan, model, tmp_path / "plan.png", dpi=60)
    assert Image.open(out).format == "PNG"


def test_japanese_names_are_drawn_with_the_bundled_font(tmp_path):
    """matplotlib-fontja (a dependency) ships IPAexGothic: Japanese place names are drawn, not replaced."""
    import warnings

    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.viz.draw import render

    assert "IPAexGothic" in font_families()
    names = ["きゅうけいじょ", "しろいたな #2"]
    assert drawable(names) == names
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("albert-b", lang="ja"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        render(model.map, tmp_path / "ja.png", model=model, title="しろいたな を とおって きゅうけいじょ")
    missing = [str(w.message) for w in caught if "missing from font" in str(w.message)]
    assert missing == []
    assert (tmp_path / "ja.png").stat().st_size > 10_000


def test_picture_is_cropped_to_the_places_not_the_laser_rays():
    """albert-b's map has free laser rays far beyond the building; the picture keeps to the places."""
    import warnings

    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.viz.draw import focus_points, used_extent

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("albert-b", lang="ja"))
    known = used_extent(model.map)
    focused = used_extent(model.map, focus=focus_points(model))
    assert focused[1] - focused[0] < known[1] - known[0]
    act = model.active_places
    assert focused[0] <= model.mu[act, 0].min() and model.mu[act, 0].max() <= focused[1]
    assert focused[2] <= model.mu[act, 1].min() and model.mu[act, 1].max() <= focused[3]
