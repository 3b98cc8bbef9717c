"""Issue 37, fifth round: the inputs this round's issues added, fuzzed (hypothesis) and hand-made, with warnings as
errors: Nav2 params files and the robot-body options (non-finite, huge, negative numbers, deep nesting, aliases,
Python tags, duplicate keys, binary files, devices, bad footprints), and the taught names kept with a model
(``info.said_names``: numbers of thousands of digits, wrong forms). Each refusal is one line of a typed error (the
commands: ``error:`` and exit 2), within the test's timeout, nothing written, nothing executed. The saved
planning graph's cases are in tests/planning/test_graph_store_hostile.py, the service's overload promise in
tests/server/test_overload.py."""

from __future__ import annotations

import copy
import math
import os
import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.errors import MapError, RobotBodyError, SpcotmhpError
from spcotmhp.language.numbers import MAX_NUMBER_DIGITS, number_word, said_variants
from spcotmhp.language.said_names import said_names
from spcotmhp.metric.body import MAX_BODY_M, MAX_FOOTPRINT_POINTS
from spcotmhp.metric.map_io import read_map_yaml
from spcotmhp.metric.nav2_params import resolve_body
from spcotmhp.persistence.io import load_model
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.helpers.graphs import GRAPHS
from tests.helpers.server import start_near, supervised_model_dir
from tests.test_hostile_round4 import HOME, refused, spcotmhp

pytestmark = [pytest.mark.filterwarnings("error")]

G = "global_costmap:\n  global_costmap:\n    ros__parameters:\n"
RING = ",".join(
    f"[{0.3 * math.cos(i * 2 * math.pi / 2000):.4f},{0.3 * math.sin(i * 2 * math.pi / 2000):.4f}]" for i in range(2000)
)
HOSTILE_PARAMS = {
    "nan radius": (G + "      robot_radius: .nan\n", r"robot_radius must be a number in \(0, 100\] m, got nan"),
    "inf radius": (G + "      robot_radius: .inf\n", r"robot_radius must be a number in \(0, 100\] m, got inf"),
    "1e308 radius": (G + "      robot_radius: 1e308\n", r"robot_radius must be a number in \(0, 100\] m, got 1e\+308"),
    "20-digit radius": (G + "      robot_radius: 99999999999999999999\n", "robot_radius must be a number in"),
    "negative radius": (G + "      robot_radius: -0.3\n", "robot_radius must be a number in"),
    "date radius": (G + "      robot_radius: 2001-12-14\n", "got datetime.date"),
    "python tag": (G + "      robot_radius: !!python/object/apply:os.system ['touch pwned']\n", "does not parse"),
    "python name": ("!!python/name:os.system\n", "does not parse"),
    "billion laughs": ("a: &a [x,x,x,x]\nb: &b [*a,*a,*a]\nglobal_costmap: *b\n", "anchors and aliases"),
    "merge alias": ("base: &b {robot_radius: 0.3}\nglobal_costmap:\n  <<: *b\n", "anchors and aliases"),
    "deep lists": ("global_costmap: " + "[" * 5000 + "]" * 5000 + "\n", "nested deeper than 32 levels"),
    "deep maps": ("global_costmap: " + "{a: " * 3000 + "1" + "}" * 3000 + "\n", "nested deeper than 32 levels"),
    "duplicate key": (
        G + "      robot_radius: 0.3\n      robot_radius: 50\n",
        r"'robot_radius' is given twice \(lines 4 and 5\)",
    ),
    "duplicate section": (G + "      robot_radius: 0.3\nglobal_costmap: {}\n", "'global_costmap' is given twice"),
    "duplicate in flow": (G + "      inflation_layer: {inflation_radius: 1, inflation_radius: 2}\n", "given twice"),
    "NUL": (G + "      robot_radius: 0.3\x00\n", "does not parse"),
    "2000-point ring": (
        G + f"      footprint: '[{RING}]'\n",
        f"has 2000 points; it must have 3 to {MAX_FOOTPRINT_POINTS}",
    ),
    "self-intersecting": (G + "      footprint: '[[0.3,0.3],[-0.3,-0.3],[0.3,-0.3],[-0.3,0.3]]'\n", "must lie inside"),
    "degenerate": (G + "      footprint: '[[0.3,0],[0.3,0],[0.3,0]]'\n", "must lie inside its footprint"),
    "collinear": (G + "      footprint: '[[-0.3,0],[0.3,0],[0,0]]'\n", "must lie inside its footprint"),
    "nan point": (G + "      footprint: '[[nan,0.2],[0.3,-0.2],[-0.3,-0.2]]'\n", r"\[nan,0.2\] is not two numbers"),
    "1e400 point": (G + "      footprint: '[[1e400,0.2],[0.3,-0.2],[-0.3,-0.2]]'\n", "within \\+-100 m, got \\[inf"),
    "underscore number": (G + "      footprint: '[[0_3,0.2],[0.3,-0.2],[-0.3,-0.2]]'\n", r"\[0_3,0.2\] is not two"),
    "bool point": (G + "      footprint: [[true,0.2],[0.3,-0.2],[-0.3,-0.2]]\n", "got \\[True, 0.2\\]"),
    "nested point": (G + "      footprint: '[[[0.3,0.2]],[0.3,-0.2],[-0.3,-0.2]]'\n", "must be a string"),
    "three values": (G + "      footprint: '[[0.3,0.2,1],[0.3,-0.2],[-0.3,-0.2]]'\n", "must be \\[x, y\\]"),
    "binary tag": (G + "      footprint: !!binary aGVsbG8=\n", "got b'hello'"),
    "set tag": (G + "      footprint: !!set {a, b}\n", "the footprint must be a list"),
    "400k brackets": (G + "      footprint: '" + "[" * 400_000 + "'\n", "must be a string"),
    "unhashable plugin": (
        G + "      robot_radius: 0.3\n      plugins: [[a]]\n",
        r"plugins must be a list of layer names, got \['a'\]",
    ),
    "unhashable name": ("global_costmap:\n  plugins: [{name: [a], type: x}]\n  robot_radius: 0.3\n", "layer names"),
    "layer a list": (
        G + "      robot_radius: 0.3\n      inflation_layer: [1, 2]\n",
        "inflation_layer must be a mapping",
    ),
    "parameters a number": (G.replace("ros__parameters:", "ros__parameters: 5"), "ros__parameters must be a mapping"),
    "enabled a string": (
        G + "      robot_radius: 0.3\n      plugins: [inflation_layer]\n"
        "      inflation_layer: {plugin: nav2_costmap_2d::InflationLayer, enabled: 'false'}\n",
        "inflation_layer.enabled must be true or false, got 'false'",
    ),
    "nan inflation": (G + "      robot_radius: 0.3\n      inflation_layer: {inflation_radius: .nan}\n", "got nan"),
    "inf scaling": (G + "      robot_radius: 0.3\n      inflation_layer: {cost_scaling_factor: .inf}\n", "got inf"),
    "nan padding": (G + "      robot_radius: 0.3\n      footprint_padding: .nan\n", "footprint_padding must be"),
    "two documents": ("a: 1\n---\nb: 2\n", "does not parse"),
    "a list": ("- 1\n- 2\n", "must hold a mapping"),
}


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("text, expect", HOSTILE_PARAMS.values(), ids=HOSTILE_PARAMS.keys())
def test_a_hostile_params_file_is_one_body_error_line(tmp_path, text, expect):
    with pytest.raises(RobotBodyError, match=expect) as info:
        resolve_body(_write(tmp_path / "nav2.yaml", text))
    assert "\n" not in str(info.value) and len(str(info.value)) < 600
    assert sorted(p.name for p in tmp_path.iterdir()) == ["nav2.yaml"]  # nothing executed or written


@pytest.mark.parametrize(
    "make, expect",
    [
        (lambda p: p.symlink_to("/dev/zero"), "is a symlink to /dev/zero, a character device, not a regular file"),
        (os.mkfifo, "is a named pipe (FIFO)"),
        (lambda p: p.write_bytes(bytes(range(256)) * 20), "is not UTF-8 text"),
        (lambda p: p.write_bytes("robot_radius: 0.3\n".encode("utf-16")), "is not UTF-8 text"),
        (lambda p: os.truncate(_write(p, ""), 3 * 2**30), "is 3221225472 bytes; at most 1048576 are accepted"),
        (lambda p: p.symlink_to(p.with_name("gone.yaml")), "does not exist"),
    ],
    ids=["/dev/zero", "FIFO", "binary", "UTF-16", "3 GiB sparse", "broken link"],
)
def test_a_params_file_that_is_no_text_file_is_named_as_what_it_is(tmp_path, make, expect):
    path = tmp_path / "nav2.yaml"
    make(path)
    with pytest.raises(RobotBodyError, match=re.escape(expect)):
        resolve_body(path)


def test_exponent_floats_are_numbers_as_ros_reads_them(tmp_path):
    """YAML 1.1 (PyYAML) reads 3e-1 as a string; ROS 2's parameter parser and yaml-cpp read a number."""
    for text in ("3e-1", "3.0e-1", "0.3E0", ".3e0"):
        body = resolve_body(_write(tmp_path / "nav2.yaml", G + f"      robot_radius: {text}\n"))
        assert body == resolve_body(_write(tmp_path / "nav2.yaml", G + "      robot_radius: 0.3\n")), text


def test_a_map_yaml_with_a_duplicate_key_is_refused_and_exponents_read(tmp_path):
    text = (HOME / "map.yaml").read_text(encoding="utf-8")
    (tmp_path / "map.pgm").write_bytes((HOME / "map.pgm").read_bytes())
    resolution = next(line for line in text.splitlines() if line.startswith("resolution:"))
    value = float(resolution.split(":")[1])
    exp = _write(tmp_path / "exp.yaml", text.replace(resolution, f"resolution: {value * 10:g}e-1"))
    assert read_map_yaml(exp).resolution == pytest.approx(value)
    twice = _write(tmp_path / "twice.yaml", text + "resolution: 5.0\n")
    with pytest.raises(MapError, match="'resolution' is given twice"):
        read_map_yaml(twice)


OPTION_VALUES = [math.nan, math.inf, -math.inf, -1.0, 0.0, 1e308, 5e-324, MAX_BODY_M, MAX_BODY_M * (1 + 1e-15)]


@pytest.mark.parametrize("value", OPTION_VALUES)
def test_every_numeric_body_option_is_checked(value):
    """--robot-radius, --inflation-radius, --cost-scaling-factor as typer parses them (floats, NaN and inf too)."""
    for kwargs in ({"robot_radius": value}, {"inflation_radius": value}, {"cost_scaling_factor": value}):
        try:
            body = resolve_body(**kwargs)
        except RobotBodyError as exc:
            assert "\n" not in str(exc)
            continue
        assert body is not None and all(math.isfinite(v) for v in body.costmap().values())


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.text(alphabet="[]-+,. 0123456789eEnaif_x", max_size=120))
def test_fuzzed_footprint_strings_give_a_body_or_one_error_line(text):
    try:
        body = resolve_body(footprint=text)
    except RobotBodyError as exc:
        assert "\n" not in str(exc)
    else:
        assert body is not None and 0 < body.inscribed_radius <= body.circumscribed_radius <= MAX_BODY_M * 1.5


SCALARS = (
    st.floats(allow_nan=True, allow_infinity=True)
    .map(repr)
    .map(lambda r: {"nan": ".nan", "inf": ".inf", "-inf": "-.inf"}.get(r, r))
    | st.sampled_from(
        ["0.3", "-1", "1e308", "99999999999999999999", "true", "null", "''", "[]", "{}", "'[[1,1],[1,-1],[-1,0]]'"]
    )
    | st.integers(-(10**25), 10**25).map(str)
)
KEYS = st.sampled_from(
    ["robot_radius", "footprint", "footprint_padding", "plugins", "inflation_layer", "ros__parameters", "x"]
)


@settings(max_examples=200, deadline=None, suppress_health_check=list(HealthCheck))
@given(
    st.dictionaries(
        KEYS,
        SCALARS
        | st.dictionaries(
            st.sampled_from(["inflation_radius", "cost_scaling_factor", "enabled", "plugin"]), SCALARS, max_size=3
        ).map(lambda d: "{" + ", ".join(f"{k}: {v}" for k, v in d.items()) + "}"),
        max_size=5,
    )
)
def test_fuzzed_params_files_give_a_body_or_one_error_line(tmp_path_factory, params):
    lines = "".join(f"      {k}: {v}\n" for k, v in params.items())
    path = tmp_path_factory.mktemp("p") / "nav2.yaml"
    try:
        body = resolve_body(_write(path, G + lines))
    except RobotBodyError as exc:
        assert "\n" not in str(exc)
    else:
        assert body is not None and math.isfinite(body.inflation_radius) and body.inscribed_radius > 0


def test_the_commands_refuse_a_hostile_params_file_in_one_line(tmp_path):
    """costmap (its output not written) and ros2 (before a node starts): ``error:``, exit 2."""
    bombs = {
        "laughs.yaml": HOSTILE_PARAMS["billion laughs"][0],
        "tag.yaml": HOSTILE_PARAMS["python tag"][0],
        "twice.yaml": HOSTILE_PARAMS["duplicate key"][0],
        "plugins.yaml": HOSTILE_PARAMS["unhashable plugin"][0],
    }
    for name, text in bombs.items():
        _write(tmp_path / name, text)
    (tmp_path / "zero.yaml").symlink_to("/dev/zero")
    out = tmp_path / "costmap.csv"
    for name, expect in [("laughs.yaml", "anchors"), ("tag.yaml", "does not parse"), ("zero.yaml", "/dev/zero")]:
        done = spcotmhp("costmap", str(HOME / "map.yaml"), "--out", str(out), "--nav2-params", name, cwd=tmp_path)
        refused(done, expect)
    done = spcotmhp("costmap", str(HOME / "map.yaml"), "--out", str(out), "--robot-radius", "nan", cwd=tmp_path)
    refused(done, "inscribed_radius must be a finite number, got nan")
    assert not out.exists() and not (tmp_path / "pwned").exists()


def test_serve_refuses_a_hostile_params_file_before_taking_its_port(tmp_path, model_dir):
    _write(tmp_path / "laughs.yaml", HOSTILE_PARAMS["billion laughs"][0])
    done = spcotmhp("serve", str(model_dir), "--nav2-params", "laughs.yaml", "--port", "1", cwd=tmp_path)
    refused(done, "anchors and aliases")


def test_the_ros2_node_refuses_a_hostile_params_file_before_starting(tmp_path, model_dir, monkeypatch):
    pytest.importorskip("rclpy")
    _write(tmp_path / "twice.yaml", HOSTILE_PARAMS["duplicate key"][0])
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    monkeypatch.setenv("ROS_DOMAIN_ID", "137")
    monkeypatch.setenv("ROS_LOG_DIR", str(tmp_path / "log"))
    done = spcotmhp("ros2", str(model_dir), "--nav2-params", "twice.yaml", cwd=tmp_path)
    refused(done, "'robot_radius' is given twice")


# ---- taught names (info.said_names of a model folder) and their numbers -------------------------------------
@pytest.fixture(scope="module")
def model_dir(tmp_path_factory):
    return supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("m") / "3LDK_06")


@pytest.fixture(scope="module")
def model(model_dir):
    return load_model(model_dir)


@settings(max_examples=400, deadline=None)
@given(st.text(max_size=40) | st.from_regex(r"[0-9]{1,6000}(st|nd|rd|th)?", fullmatch=True))
def test_number_word_reads_any_word_without_an_error(word):
    """Python refuses int() of over 4,300 digits: a number of a name is at most MAX_NUMBER_DIGITS digits."""
    said = number_word(word)
    if said is not None:
        assert said[0] in ("cardinal", "ordinal") and 0 <= said[1] < 10 ** (MAX_NUMBER_DIGITS + 1)
    assert len(said_variants(["room", word])) <= 64


def test_a_number_of_thousands_of_digits_is_a_plain_word():
    assert number_word("1" * 5000) is None and number_word("9" * 5000 + "th") is None
    assert number_word("9" * MAX_NUMBER_DIGITS) == ("cardinal", int("9" * MAX_NUMBER_DIGITS))
    assert number_word("9" * (MAX_NUMBER_DIGITS + 1)) is None


HOSTILE_NAMES = {
    "5000 digits": [{"words": ["room", "1" * 5000], "taught": 5, "places": [[0, 5]]}],
    "ordinal of 5000 digits": [{"words": ["bedroom", "9" * 5000 + "th"], "taught": 5, "places": [[1, 5]]}],
    "place 1e20": [{"words": ["bedroom", "one"], "taught": 5, "places": [[10**20, 5]]}],
    "taught 1e30": [{"words": ["bedroom", "one"], "taught": 10**30, "places": [[1, 10**30]]}],
    "wrong forms": [1, "x", None, [1], {"words": "bedroom", "taught": 1}, {"words": [1], "taught": 1.5}],
    "bad places": [{"words": ["bedroom", "two"], "taught": 5, "places": [[True, 5], [-1, 5], ["a", 1], [1, 0], [1]]}],
    "20,000 words": [{"words": [f"w{i}" for i in range(20_000)] + ["bedroom"], "taught": 5, "places": [[1, 5]]}],
    "5,000 names": [{"words": ["bedroom", str(i)], "taught": 5, "places": [[i % 11, 5]]} for i in range(5000)],
    "100,000 places": [{"words": ["bedroom", "one"], "taught": 5, "places": [[k % 11, k + 1] for k in range(100_000)]}],
    "control characters": [{"words": ["bed\x00room", "\u202e", "٣", "①"], "taught": 5, "places": [[1, 5]]}],
    "not a list": {"words": ["bedroom"]},
}


@pytest.mark.parametrize("names", HOSTILE_NAMES.values(), ids=HOSTILE_NAMES.keys())
def test_hostile_taught_names_in_a_model_plan_or_refuse_in_one_line(model, names):
    hostile = copy.copy(model)
    hostile.info = {**model.info, "said_names": names}
    assert len(said_names(hostile)) <= 1000
    planner = HierarchicalPlanner(hostile, cache=GRAPHS)
    start = planner.model.map.cell_to_world(planner.graph.to_map(planner.graph.node_cell[0]))
    for instruction in ("go to the bedroom", "go to room 1", "go to bedroom one", "go to room " + "1" * 400):
        try:
            assert planner.plan(instruction, start).path is not None
        except SpcotmhpError as exc:
            assert "\n" not in str(exc)


def test_a_model_folder_with_hostile_names_plans_from_the_command_line(tmp_path, model_dir):
    """The names reach plan through model.json (its checksum made to match, as an editor would)."""
    import json
    import shutil

    from spcotmhp.persistence.folder import MANIFEST, manifest_of

    folder = tmp_path / "model"
    shutil.copytree(model_dir, folder)
    doc = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    doc.setdefault("info", {})["said_names"] = HOSTILE_NAMES["5000 digits"] + HOSTILE_NAMES["bad places"]
    (folder / "model.json").write_text(json.dumps(doc), encoding="utf-8")
    names = [p.name for p in sorted(folder.iterdir()) if p.is_file() and p.name != MANIFEST]
    (folder / MANIFEST).write_text(json.dumps(manifest_of(folder, names)), encoding="utf-8")
    x, y = start_near(load_model(model_dir))
    done = spcotmhp("plan", str(folder), "go to the bedroom", "--start", str(x), str(y), cwd=tmp_path)
    assert done.returncode in (0, 2) and "Traceback" not in done.stderr and "Warning" not in done.stderr, done.stderr
    if done.returncode == 2:
        assert len(done.stderr.strip().splitlines()) == 1 and done.stderr.startswith("error: ")


# Fuzzing the taught names' order (issue 37: "name orders"): any list of names, of any words in any order, well
# formed or not, read with a model; instructions saying those words in any order plan or refuse in one line.
NAME_WORDS = st.sampled_from(
    ["bedroom", "kitchen", "room", "aisle", "one", "two", "1", "101", "second", "first", "east", "the", "of", "2号室",
     "東", "廊下", "9" * 40, "", " ", "-", "#1"]
) | st.text(max_size=6)  # fmt: skip
NAME = st.fixed_dictionaries(
    {
        "words": st.lists(NAME_WORDS, max_size=5) | NAME_WORDS,
        "taught": st.integers(-2, 10**6) | st.floats() | st.none(),
        "places": st.lists(st.lists(st.integers(-2, 12) | st.booleans() | st.text(max_size=2), max_size=3), max_size=4),
    }
)
NAMES = st.lists(NAME | st.none() | st.integers() | st.text(max_size=5), max_size=8) | NAME


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(NAMES, st.randoms(use_true_random=False))
def test_fuzzed_taught_names_in_any_order_plan_or_refuse_in_one_line(model, names, rng):
    hostile = copy.copy(model)
    hostile.info = {**model.info, "said_names": names}
    read = said_names(hostile)
    assert len(read) <= 1000
    planner = HierarchicalPlanner(hostile, cache=GRAPHS)
    start = planner.model.map.cell_to_world(planner.graph.to_map(planner.graph.node_cell[0]))
    said = [w for n in (names if isinstance(names, list) else [names]) if isinstance(n, dict)
            for w in (n["words"] if isinstance(n["words"], list) else [n["words"]])]  # fmt: skip
    rng.shuffle(said)
    for instruction in ("go to the " + " ".join(said), "go to the bedroom " + " ".join(said[:2]), "go to the bedroom"):
        try:
            assert planner.plan(instruction, start).path is not None
        except SpcotmhpError as exc:
            assert "\n" not in str(exc)
