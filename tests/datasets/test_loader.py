"""load_dataset: every validation message (tmp folders with a small hand-made map), tokens, features,
trajectories; the bundled datasets; bundled-data access."""

from __future__ import annotations

import itertools
import re
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from spcotmhp.datasets import (
    DatasetWarning,
    bundled_path,
    features_to_counts,
    list_bundled,
    load_bundled,
    load_dataset,
)
from spcotmhp.datasets.alignment import align_events
from spcotmhp.datasets.loader import tokenize_en, tokenize_ja
from spcotmhp.errors import DatasetError, SpcotmhpError
from tests.helpers.vocabulary import PLACE_WORDS_EN

# --- a 20 x 30 map at 0.1 m, origin (-1, -1): border walls, an unknown block at x 1.0..1.5, y 0.0..0.5 ---
HEIGHT, WIDTH = 20, 30
YAML = (
    "image: map.pgm\nresolution: 0.1\norigin: [-1.0, -1.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
)
TEACHING = (
    "event,x,y,words_ja,words_en\n"
    "0,0.25,0.25,台所,This is the Kitchen!\n"
    "1,0.35,0.15,台所 です,kitchen\n"
    '2,-0.45,0.55,寝室,"the bedroom, upstairs"\n'
)


def grid() -> np.ndarray:
    """OccupancyGrid order (row 0 = bottom): 0 free, 100 occupied, -1 unknown."""
    g = np.zeros((HEIGHT, WIDTH), dtype=np.int8)
    g[[0, -1], :] = 100
    g[:, [0, -1]] = 100
    g[10:15, 20:25] = -1
    return g


def make(tmp_path: Path, **files: str | None) -> Path:
    """A dataset folder 'home' with the map, TEACHING and ``files`` (name with '.' as '_': text, None = absent)."""
    folder = tmp_path / "home"
    folder.mkdir(parents=True)
    g = grid()
    image = np.where(g == 0, 254, np.where(g == 100, 0, 205)).astype(np.uint8)[::-1]
    Image.fromarray(image).save(folder / "map.pgm")
    contents = {"map.yaml": YAML, "teaching.csv": TEACHING}
    contents.update({k.replace("_csv", ".csv").replace("_yaml", ".yaml"): v for k, v in files.items()})
    for name, text in contents.items():
        if text is not None:
            (folder / name).write_text(text, encoding="utf-8")
    return folder


def raises(message: str):
    return pytest.raises(DatasetError, match=re.escape(message))


def load_warned(folder: Path, lang: str = "en"):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        d = load_dataset(folder, lang=lang)
    return d, [str(w.message) for w in caught if issubclass(w.category, DatasetWarning)]


# --- a good folder ---------------------------------------------------------------------------------
def test_minimal_folder_loads(tmp_path):
    d, caught = load_warned(make(tmp_path))
    assert caught == []
    assert d.name == "home" and d.n_events == 3 and d.lang == "en"
    np.testing.assert_allclose(d.positions, [[0.25, 0.25], [0.35, 0.15], [-0.45, 0.55]])
    assert d.tokens == [["this", "is", "the", "kitchen"], ["kitchen"], ["the", "bedroom", "upstairs"]]
    assert d.map.shape == (HEIGHT, WIDTH)
    assert d.features is d.truth_place is d.adjacency is d.trajectory is d.costmap_ros is None
    ja = load_dataset(make(tmp_path / "j"), lang="ja")
    assert ja.tokens == [["台所"], ["台所", "です"], ["寝室"]]


def test_tokenisers():
    assert tokenize_en("This is the Kitchen!") == ["this", "is", "the", "kitchen"]
    assert tokenize_en("  the kitchen's door;hall-way...  ") == ["the", "kitchen's", "door", "hall", "way"]
    assert tokenize_en("!!! ...") == []
    assert tokenize_ja("ここが\u3000きょうゆうせき  だよ") == ["ここが", "きょうゆうせき", "だよ"]


def test_features_to_counts_as_the_authors_did():
    np.testing.assert_array_equal(features_to_counts(np.array([0.0, 0.05, 0.15, 0.999, 1.0])), [1, 1, 2, 10, 11])
    np.testing.assert_array_equal(features_to_counts(np.array([[0.5, 0.26]]), scale=100), [[51, 27]])
    with raises("finite, non-negative"):
        features_to_counts(np.array([0.1, -0.2]))


# --- fatal errors ----------------------------------------------------------------------------------
def test_missing_folder_and_files(tmp_path):
    with raises(f"dataset folder {tmp_path / 'nope'} does not exist"):
        load_dataset(tmp_path / "nope")
    (tmp_path / "file.txt").write_text("x")
    with raises("is not a folder"):
        load_dataset(tmp_path / "file.txt")
    with raises("has no map.yaml (the ROS map_server YAML)"):
        load_dataset(make(tmp_path / "a", map_yaml=None))
    with raises("has no teaching.csv (the teaching events)"):
        load_dataset(make(tmp_path / "b", teaching_csv=None))


def test_bad_lang(tmp_path):
    with raises("lang must be 'en' or 'ja', got 'fr'"):
        load_dataset(make(tmp_path), lang="fr")


def test_empty_teaching(tmp_path):
    with raises("teaching.csv is empty (expected a header x,y,words_en (or words_ja, or both; optional event, step)"):
        load_dataset(make(tmp_path / "a", teaching_csv=""))
    with raises("teaching.csv has a header but no teaching events"):
        load_dataset(make(tmp_path / "b", teaching_csv="event,x,y,words_ja\n\n"))


def test_event_column_optional(tmp_path):
    """Without an event column the events are the rows in file order; truth.csv refers to them by that index."""
    folder = make(tmp_path, teaching_csv="x,y,words_en\n0.2,0.2,This is the Hall\n0.3,0.2,the hall\n")
    (folder / "truth.csv").write_text("event,place\n1,0\n0,0\n")
    d = load_dataset(folder)
    assert d.n_events == 2 and d.tokens == [["this", "is", "the", "hall"], ["the", "hall"]]
    assert d.truth_place.tolist() == [0, 0]
    with raises("teaching.csv row 3: event 0 appears twice (also on row 2)"):  # given, it must count 0, 1, ...
        load_dataset(make(tmp_path / "b", teaching_csv="event,x,y,words_en\n0,0.2,0.2,a\n0,0.3,0.2,b\n"))


def test_missing_columns_lists_found_and_accepted(tmp_path):
    with raises(
        "teaching.csv: missing column(s) x; found event, xpos, y, words_ja; "
        "accepted: x, y, words_ja and/or words_en, [event], [step]"
    ):
        load_dataset(make(tmp_path / "a", teaching_csv="event,xpos,y,words_ja\n0,1,2,a\n"), lang="ja")
    with raises("teaching.csv: missing column(s) words_ja or words_en; found event, x, y, words; "):
        load_dataset(make(tmp_path / "b", teaching_csv="event,x,y,words\n0,1,2,a\n"), lang="ja")


def test_english_only_teaching(tmp_path):
    folder = make(tmp_path, teaching_csv="event,x,y,words_en\n0,0.2,0.2,This is the Hall\n")
    assert load_dataset(folder).tokens == [["this", "is", "the", "hall"]]
    with raises("home has no words_ja column (teaching.csv has event, x, y, words_en); use lang='en'"):
        load_dataset(folder, lang="ja")


def test_no_english_words(tmp_path):
    folder = make(tmp_path, teaching_csv="event,x,y,words_ja\n0,0.2,0.2,台所\n")
    with raises("home has no words_en column (teaching.csv has event, x, y, words_ja); use lang='ja'"):
        load_dataset(folder, lang="en")
    assert load_dataset(folder, lang="ja").tokens == [["台所"]]


@pytest.mark.parametrize(
    "row, message",
    [
        ("1,abc,0.2,w,w", "teaching.csv row 3: x is 'abc', not a number"),
        ("1,0.2,nan,w,w", "teaching.csv row 3: y is 'nan', not a finite number"),
        ("1,inf,0.2,w,w", "teaching.csv row 3: x is 'inf', not a finite number"),
        ("1,0.2,0.2,w", "teaching.csv row 3: 4 fields, expected 5 (event,x,y,words_ja,words_en)"),
        ("one,0.2,0.2,w,w", "teaching.csv row 3: event is 'one', not a number"),
        ("1.5,0.2,0.2,w,w", "teaching.csv row 3: event is '1.5', not an integer"),
        (
            "0,0.2,0.2,w,w",
            "teaching.csv row 3: event 0 appears twice (also on row 2); event ids must be 0, 1, 2",
        ),
        (
            "3,0.2,0.2,w,w",
            "teaching.csv row 3: event 3 follows 0; event ids must be 0, 1, 2, ... in file order",
        ),
    ],
)
def test_bad_teaching_rows(tmp_path, row, message):
    text = f"event,x,y,words_ja,words_en\n0,0.2,0.2,w,w\n{row}\n"
    with raises(message):
        load_dataset(make(tmp_path, teaching_csv=text))


def test_event_ids_must_start_at_zero(tmp_path):
    with raises("teaching.csv row 2: event 1 is the first; event ids must be 0, 1, 2"):
        load_dataset(make(tmp_path, teaching_csv="event,x,y,words_ja\n1,0.2,0.2,w\n"), lang="ja")


def test_file_that_is_not_utf8(tmp_path):
    folder = make(tmp_path)
    (folder / "teaching.csv").write_bytes("event,x,y,words_ja\n0,0.2,0.2,台所\n".encode("shift_jis"))
    with raises("teaching.csv is not UTF-8 text"):
        load_dataset(folder, lang="ja")


def test_line_numbers_count_blank_lines_and_quoted_newlines(tmp_path):
    text = 'event,x,y,words_ja\n\n0,0.2,0.2,"a\nb"\n1,0.2,bad,c\n'
    with raises("teaching.csv row 5: y is 'bad', not a number"):
        load_dataset(make(tmp_path, teaching_csv=text), lang="ja")


@pytest.mark.parametrize(
    "truth, message",
    [
        ("event,place\n0,0\n1,0\n7,1\n", "truth.csv row 4: event 7 is not in teaching.csv (events 0..2)"),
        ("event,place\n0,0\n1,0\n", "truth.csv has no row for 1 of teaching.csv's 3 events (2)"),
        ("event,place\n0,0\n1,0\n1,0\n2,0\n", "truth.csv row 4: event 1 appears twice (also on row 3)"),
        ("event,place\n0,0\n1,-1\n2,0\n", "truth.csv row 3: place is -1, must be >= 0"),
        (
            "event,where\n0,0\n",
            "truth.csv: missing column(s) place; found event, where; accepted: event, place, [concept]",
        ),
    ],
)
def test_bad_truth(tmp_path, truth, message):
    with raises(message):
        load_dataset(make(tmp_path, truth_csv=truth))


def test_truth_in_any_order_and_concepts(tmp_path):
    d = load_dataset(make(tmp_path, truth_csv="event,place,concept\n2,1,0\n0,0,1\n1,0,1\n"))
    np.testing.assert_array_equal(d.truth_place, [0, 0, 1])
    np.testing.assert_array_equal(d.truth_concept, [1, 1, 0])


PLACES = "place,name_ja,name_en\n0,台所,kitchen\n1,寝室,bedroom\n"


def test_places_and_adjacency(tmp_path):
    d = load_dataset(
        make(tmp_path, places_csv=PLACES, adjacency_csv="1,1\n1,1\n", truth_csv="event,place\n0,0\n1,0\n2,1\n")
    )
    assert d.place_names == ["kitchen", "bedroom"]
    np.testing.assert_array_equal(d.adjacency, [[1, 1], [1, 1]])
    assert load_dataset(make(tmp_path / "j", places_csv=PLACES), lang="ja").place_names == ["台所", "寝室"]


@pytest.mark.parametrize(
    "files, message",
    [
        (
            {"places_csv": "place,name_ja\n0,台所\n"},
            "places.csv: missing column(s) name_en; found place, name_ja",
        ),
        (
            {"places_csv": "place,name_ja,name_en\n0,a,b\n2,c,d\n"},
            "places.csv row 3: place 2 follows 0; place ids",
        ),
        ({"places_csv": "place,name_ja,name_en\n0,a,\n"}, "places.csv row 2: name_en is blank"),
        (
            {"places_csv": PLACES, "truth_csv": "event,place\n0,0\n1,0\n2,5\n"},
            "truth.csv row 4: place 5 is not in places.csv (places 0..1)",
        ),
        ({"adjacency_csv": "1,1,0\n1,1,0\n"}, "adjacency.csv is 2x3; it must be square"),
        ({"adjacency_csv": "1,0.5\n0.5,1\n"}, "adjacency.csv row 1 column 2 is 0.5; entries must be 0 or 1"),
        (
            {"adjacency_csv": "1,1\n0,1\n"},
            "adjacency.csv is not symmetric: row 1 column 2 is 1 but row 2 column 1 is 0",
        ),
        ({"adjacency_csv": "1,x\nx,1\n"}, "adjacency.csv row 1 column 2 is 'x', not a number"),
        (
            {"adjacency_csv": "1,1\n1,0\n"},
            "adjacency.csv row 2 column 2 is 0; the diagonal must be 1 (a place is connected to itself)",
        ),
        (
            {"adjacency_csv": "1,1,0\n1,1,1\n0,1,1\n", "places_csv": PLACES},
            "adjacency.csv is 3x3 but places.csv has 2 places",
        ),
        (
            {"adjacency_csv": "1,1,0\n1,1,1\n0,1,1\n", "truth_csv": "event,place\n0,0\n1,0\n2,1\n"},
            "adjacency.csv is 3x3 but truth.csv has 2 places",
        ),
    ],
)
def test_bad_places_and_adjacency(tmp_path, files, message):
    with raises(message):
        load_dataset(make(tmp_path, **files))


def test_features_raw_values_kept_and_header_allowed(tmp_path):
    rows = "0.5,0.5\n0.1,0.9\n1e-9,1\n"
    d = load_dataset(make(tmp_path / "a", image_features_places365_csv=rows))
    np.testing.assert_allclose(d.features, [[0.5, 0.5], [0.1, 0.9], [1e-9, 1]])
    d = load_dataset(make(tmp_path / "b", image_features_places365_csv="f0,f1\n" + rows))
    assert d.features.shape == (3, 2)


@pytest.mark.parametrize(
    "rows, message",
    [
        ("0.5,0.5\n0.1,0.9\n", "image_features_places365.csv has 2 rows but teaching.csv has 3 events"),
        (
            "0.5,0.5\n0.1,-0.9\n0,1\n",
            "image_features_places365.csv row 2 column 2 is -0.9; features must be non-negative",
        ),
        (
            "0.5,0.5\n0.1,nan\n0,1\n",
            "image_features_places365.csv row 2 column 2 is 'nan', not a finite number",
        ),
        ("0.5,0.5\n0.1,0.9,0\n0,1\n", "image_features_places365.csv row 2: 3 values, expected 2 as on row 1"),
        ("", "image_features_places365.csv is empty"),
    ],
)
def test_bad_features(tmp_path, rows, message):
    with raises(message):
        load_dataset(make(tmp_path, image_features_places365_csv=rows))


def test_costmap(tmp_path):
    costs = np.zeros((HEIGHT, WIDTH), dtype=int)
    costs[0, :] = 100
    text = "\n".join(",".join(map(str, r)) for r in costs) + "\n"
    d = load_dataset(make(tmp_path / "a", costmap_ros_csv=text))
    np.testing.assert_array_equal(d.costmap_ros, costs)
    short = "\n".join(text.splitlines()[:-1]) + "\n"
    with raises(f"costmap_ros.csv is {HEIGHT - 1}x{WIDTH} (rows x columns) but map.pgm is {HEIGHT}x{WIDTH}"):
        load_dataset(make(tmp_path / "b", costmap_ros_csv=short))
    bad = text.replace("100,100", "100,101", 1)
    with raises("costmap_ros.csv row 1 column 2 is 101; costs must be integers 0..100"):
        load_dataset(make(tmp_path / "c", costmap_ros_csv=bad))


# --- warnings --------------------------------------------------------------------------------------
def test_points_in_walls_unknown_and_off_map_warn(tmp_path):
    text = "event,x,y,words_ja\n0,0.2,0.2,a\n1,-0.95,0.05,b\n2,1.25,0.25,c\n3,5.0,0.0,d\n"
    d, caught = load_warned(make(tmp_path, teaching_csv=text), lang="ja")
    assert d.n_events == 4
    assert caught == [
        "teaching.csv row 5: (x, y) = (5.00, 0.00) lies off the map (map.pgm covers x -1.00..2.00, y -1.00..1.00)",
        "teaching.csv row 3: (x, y) = (-0.95, 0.05) lies in an occupied cell of map.pgm",
        "teaching.csv row 4: (x, y) = (1.25, 0.25) lies in an unknown cell of map.pgm",
    ]


def test_many_points_in_walls_are_summarised(tmp_path):
    rows = "".join(f"{i},-0.95,0.05,w\n" for i in range(25))
    _, caught = load_warned(make(tmp_path, teaching_csv="event,x,y,words_ja\n" + rows), lang="ja")
    assert len(caught) == 21
    assert caught[-1].startswith("teaching.csv: 5 more points lie in an occupied cell of map.pgm (rows 22, 23, 24")


def test_empty_utterances_warn(tmp_path):
    text = "event,x,y,words_ja,words_en\n0,0.2,0.2,台所,kitchen\n1,0.2,0.2,,...\n"
    d, caught = load_warned(make(tmp_path / "a", teaching_csv=text), lang="en")
    assert d.tokens == [["kitchen"], []]
    assert caught == ["teaching.csv row 3: empty utterance (words_en is '...'); the event has no words"]
    _, caught = load_warned(make(tmp_path / "b", teaching_csv=text), lang="ja")
    assert caught == ["teaching.csv row 3: empty utterance (words_ja is ''); the event has no words"]


# --- trajectories ----------------------------------------------------------------------------------
def _walk() -> str:
    """Out along y = 0.25 from x = -0.5 to 0.8 (steps 0..13), then back to -0.5 (steps 14..26)."""
    xs = list(np.round(np.arange(-0.5, 0.85, 0.1), 2)) + list(np.round(np.arange(0.7, -0.55, -0.1), 2))
    return "step,x,y\n" + "".join(f"{i},{x:.2f},0.25\n" for i, x in enumerate(xs))


def test_trajectory_with_step_column(tmp_path):
    text = "event,x,y,words_ja,step\n0,0.0,0.25,a,5\n1,0.8,0.25,b,13\n2,0.0,0.25,c,21\n"
    d, caught = load_warned(make(tmp_path, teaching_csv=text, trajectory_csv=_walk()), lang="ja")
    assert caught == []
    assert d.trajectory.shape == (27, 2)
    np.testing.assert_array_equal(d.event_steps, [5, 13, 21])


def test_trajectory_without_step_column_keeps_walking_order(tmp_path):
    # the third event is at the spot passed at steps 5 and 21; walking order says 21
    text = "event,x,y,words_ja\n0,0.0,0.25,a\n1,0.8,0.25,b\n2,0.0,0.3,c\n"
    d, caught = load_warned(make(tmp_path, teaching_csv=text, trajectory_csv=_walk()), lang="ja")
    assert caught == []
    np.testing.assert_array_equal(d.event_steps, [5, 13, 21])


def test_align_events_matches_brute_force():
    rng = np.random.default_rng(0)
    for _ in range(30):
        traj, pos = rng.uniform(0, 3, (7, 2)), rng.uniform(0, 3, (3, 2))
        dist = np.hypot(*(pos[:, None, :] - traj[None, :, :]).transpose(2, 0, 1))
        best = min(
            sum(dist[e, t] for e, t in enumerate(c)) for c in itertools.combinations_with_replacement(range(7), 3)
        )
        steps = align_events(pos, traj)
        assert np.all(np.diff(steps) >= 0)
        assert dist[np.arange(3), steps].sum() == pytest.approx(best)


@pytest.mark.parametrize(
    "teaching, trajectory, message",
    [
        (
            "event,x,y,words_ja,step\n0,0.0,0.25,a,5\n",
            None,
            "teaching.csv has a step column but the folder has no trajectory.csv",
        ),
        (
            "event,x,y,words_ja,step\n0,0.0,0.25,a,27\n",
            _walk(),
            "teaching.csv row 2: step 27 is beyond trajectory.csv's last step 26",
        ),
        (
            "event,x,y,words_ja,step\n0,0.0,0.25,a,5\n1,0.0,0.25,a,4\n",
            _walk(),
            "teaching.csv row 3: step 4 is before the previous event's step 5; steps must not decrease",
        ),
        (
            "event,x,y,words_ja,step\n0,0.0,0.25,a,-1\n",
            _walk(),
            "teaching.csv row 2: step is -1, must be >= 0",
        ),
        (
            "event,x,y,words_ja\n0,0.0,0.25,a\n",
            "step,x,y\n0,0,0\n2,0,0\n",
            "trajectory.csv row 3: step 2 follows 0; steps must be 0, 1, 2, ... in file order",
        ),
        ("event,x,y,words_ja\n0,0.0,0.25,a\n", "step,x\n0,0\n", "trajectory.csv: missing column(s) y"),
        ("event,x,y,words_ja\n0,0.0,0.25,a\n", "step,x,y\n", "trajectory.csv has a header but no poses"),
        (
            "event,x,y,words_ja\n0,0.0,0.25,a\n",
            "step,x,y\n0,0,inf\n",
            "trajectory.csv row 2: y is 'inf', not a finite",
        ),
    ],
)
def test_bad_trajectories(tmp_path, teaching, trajectory, message):
    with raises(message):
        load_dataset(make(tmp_path, teaching_csv=teaching, trajectory_csv=trajectory), lang="ja")


def test_trajectory_warnings(tmp_path):
    teaching = "event,x,y,words_ja,step\n0,0.0,0.25,a,5\n1,0.0,-0.5,b,13\n"
    walk = _walk().replace("13,0.80,0.25", "13,1.25,0.25")  # into the unknown block
    _, caught = load_warned(make(tmp_path, teaching_csv=teaching, trajectory_csv=walk), lang="ja")
    assert caught == [
        "trajectory.csv: 1 of 27 points lie in an unknown cell of map.pgm (first on row 15)",
        "teaching.csv row 3: (x, y) is 1.46 m from its trajectory pose (step 13, trajectory.csv row 15)",
    ]


# --- robustness: arbitrary text never gives a traceback --------------------------------------------
GARBAGE = st.text(alphabet='event,xywords_japlacestp0123456789.-\n"einfa 台', max_size=80)


@pytest.mark.parametrize(
    "name, header",
    [
        ("teaching_csv", "event,x,y,words_ja\n"),
        ("truth_csv", "event,place\n"),
        ("places_csv", "place,name_ja\n"),
        ("trajectory_csv", "step,x,y\n"),
        ("adjacency_csv", ""),
        ("image_features_places365_csv", ""),
        ("costmap_ros_csv", ""),
    ],
)
@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(body=GARBAGE)
def test_garbage_files_never_traceback(name, header, body):
    """Garbage gives a one-line library error, or a dataset that keeps every invariant of ``Dataset``."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = make(Path(tmp), **{name: header + body})
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DatasetWarning)
                d = load_dataset(folder, lang="ja")
        except SpcotmhpError as e:
            assert str(e) and "\n" not in str(e)
            return
    assert_consistent(d)


def assert_consistent(d) -> None:
    """The invariants every loaded dataset keeps (what the learner and the evaluation rely on)."""
    e = d.n_events
    assert e >= 1 and d.positions.shape == (e, 2) and np.isfinite(d.positions).all()
    assert len(d.tokens) == e and all(isinstance(t, str) and t for ts in d.tokens for t in ts)
    if d.features is not None:
        assert d.features.shape[0] == e and (d.features >= 0).all()
    if d.trajectory is not None:
        assert d.trajectory.ndim == 2 and d.trajectory.shape[1] == 2 and np.isfinite(d.trajectory).all()
    if d.event_steps is not None:
        assert d.trajectory is not None and d.event_steps.shape == (e,)
        assert (np.diff(d.event_steps) >= 0).all() and 0 <= d.event_steps.min() <= d.event_steps.max() < len(
            d.trajectory
        )
    if d.truth_place is not None:
        assert d.truth_place.shape == (e,) and d.truth_place.min() >= 0
        if d.place_names is not None:
            assert d.truth_place.max() < len(d.place_names)
    if d.adjacency is not None:
        a = d.adjacency
        assert a.shape[0] == a.shape[1] and (a == a.T).all() and set(np.unique(a)) <= {0, 1} and (np.diag(a) == 1).all()
    if d.costmap_ros is not None:
        assert d.costmap_ros.shape == d.map.data.shape


def test_the_consistency_check_rejects_a_broken_dataset(tmp_path):
    """``assert_consistent`` is not vacuous: a loaded dataset passes it, the same with a token list short fails it."""
    d, _ = load_warned(make(tmp_path))
    assert_consistent(d)
    d.tokens = d.tokens[:-1]
    with pytest.raises(AssertionError):
        assert_consistent(d)


# --- bundled data ----------------------------------------------------------------------------------
SIGVERSE = ["3LDK_01", "3LDK_05", "3LDK_06"]
EN_WORDS = {*PLACE_WORDS_EN, "east", "south"}  # the place words, and the direction words of two names
# teaching events whose recorded position is not on a free cell of its map (0-based event ids); each is
# within 0.1-0.32 m of free space (see spcotmhp/data/README.md)
OFF_FREE = {
    "3LDK_01": {65, 101, 102, 103, 104},
    "3LDK_05": {39, 50, 57, 61, 62, 63, 72, 91, 93, 94, 118},
    "3LDK_06": {130, 131, 164},
    "albert-b": set(),
}


def test_bundled_names_and_paths():
    assert list_bundled() == ["3LDK_01", "3LDK_05", "3LDK_06", "albert-b"]
    assert bundled_path("sigverse-3ldk/3LDK_01") == bundled_path("3LDK_01")
    assert (bundled_path("albert-b") / "teaching.csv").is_file()
    with raises("no bundled dataset named 'kitchen'; known: 3LDK_01, 3LDK_05, 3LDK_06, albert-b"):
        bundled_path("kitchen")


@pytest.mark.parametrize("name", SIGVERSE)
def test_bundled_sigverse(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DatasetWarning)
        en, ja = load_bundled(name, lang="en"), load_bundled(name, lang="ja")
    assert en.n_events == ja.n_events == 165
    assert en.map.shape == (192, 192) and en.map.resolution == pytest.approx(0.1)
    assert len(en.place_names) == 11 and len(np.unique(en.truth_place)) == 11
    assert np.bincount(en.truth_place).tolist() == [15] * 11
    assert set(en.vocabulary) <= EN_WORDS and "bedroom" in en.vocabulary
    assert en.place_names.count("bedroom") == 3 and ja.place_names.count("寝室") == 3
    assert all(len(t) >= 1 for t in en.tokens) and all(len(t) >= 1 for t in ja.tokens)
    assert all(re.fullmatch(r"[a-z]+", w) for w in en.vocabulary)
    assert not any(re.search(r"[a-z]", w) for w in ja.vocabulary)
    assert en.adjacency.shape == (11, 11) and (np.diag(en.adjacency) == 1).all()
    assert en.costmap_ros.shape == (192, 192)


def test_bundled_albert_b():
    with raises("albert-b has no words_en column (teaching.csv has event, x, y, words_ja); use lang='ja'"):
        load_bundled("albert-b", lang="en")
    d = load_bundled("albert-b", lang="ja")
    assert d.n_events == 70 and d.features.shape == (70, 365)
    assert len(np.unique(d.truth_place)) == 12 and len(np.unique(d.truth_concept)) == 11
    assert d.map.resolution == pytest.approx(0.05)
    assert d.tokens[1] == ["ここが", "きょうゆうせき"]
    assert "しろいたな" in d.vocabulary and "きゅうけいじょ" in d.vocabulary
    np.testing.assert_allclose(d.features.sum(axis=1), 1.0, atol=1e-3)  # Places365 probabilities


@pytest.mark.parametrize("name", list(OFF_FREE))
def test_bundled_teaching_points_on_free_cells(name):
    """Every teaching point not on a free cell is warned about, and these are exactly the known ones."""
    lang = "ja" if name == "albert-b" else "en"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        d = load_dataset(bundled_path(name), lang=lang)
    rc = d.map.world_to_cell(d.positions)
    assert d.map.in_bounds(rc).all()
    off = set(np.flatnonzero(d.map.data[rc[:, 0], rc[:, 1]] != 0).tolist())
    warned = {int(re.match(r"teaching.csv row (\d+):", str(w.message)).group(1)) - 2 for w in caught}
    assert warned == off == OFF_FREE[name]


def test_load_bundled_says_its_known_warnings_once(monkeypatch):
    """load_bundled summarises the bundled data's known warnings in one line, the first time in a process."""
    from spcotmhp.datasets import bundled

    monkeypatch.setattr(bundled, "_ANNOUNCED", set())
    for expected in (1, 0):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            load_bundled("3LDK_05")
        assert len(caught) == expected
    monkeypatch.setattr(bundled, "_ANNOUNCED", set())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_bundled("3LDK_05")
    assert [str(w.message) for w in caught] == [
        (
            "3LDK_05: 11 known warning(s) of the bundled data (teaching points recorded at the edge of a wall; "
            "spcotmhp/data/README.md); `spcotmhp check-dataset 3LDK_05` lists them"
        )
    ]


def test_bad_map_is_a_map_error_naming_the_image(tmp_path):
    folder = make(tmp_path)
    (folder / "map.pgm").unlink()
    with pytest.raises(SpcotmhpError, match=r"map\.pgm does not exist"):
        load_dataset(folder)
