"""Fuzzing the file boundaries: hostile map, dataset and model folders (tests/helpers/hardening_corpus.py) must load or
give one typed one-line error, within 5 s each and without a memory blow-up; plus the cases named in issue 10."""

from __future__ import annotations

import random
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from spcotmhp.datasets.loader import load_dataset
from spcotmhp.datasets.synthetic import generate_environment, write_dataset
from spcotmhp.errors import DatasetError, MapError, ModelError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.map_io import load_map
from spcotmhp.persistence.io import load_model, save_model
from tests.helpers.hardening_corpus import dataset_case, map_case, model_case, run_case
from tests.helpers.strategies import apply_edits, apply_learner_edits, learner_edits, model_edits, pnm_files

pytestmark = pytest.mark.filterwarnings("ignore")
FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
CASE_SECONDS = 5.0
CASE_PEAK_MIB = 512  # one hostile folder: the caps allow a few copies of a 16 M-pixel map (128 MiB as float64)


@pytest.fixture(scope="module")
def templates(tmp_path_factory):
    root = tmp_path_factory.mktemp("templates")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = write_dataset(generate_environment("flat", seed=1, n_rooms=4), root / "data")
        model = save_model(fit_supervised(load_dataset(data)), root / "model")
    return data, model


def _check(outcome: tuple[str, float, str, float]) -> None:
    kind, seconds, message, peak_mib = outcome
    assert kind != "traceback", message
    assert seconds < CASE_SECONDS, message
    assert peak_mib < CASE_PEAK_MIB, f"{message}: held {peak_mib:.0f} MiB"


@given(seed=st.integers(0, 2**32 - 1))
@FUZZ
def test_fuzzed_map_folders(tmp_path_factory, seed):
    folder = tmp_path_factory.mktemp("map")
    label = map_case(random.Random(seed), folder)
    _check(run_case(lambda: load_map(folder / "map.yaml"), label))
    shutil.rmtree(folder)


@given(seed=st.integers(0, 2**32 - 1))
@FUZZ
def test_fuzzed_dataset_folders(templates, tmp_path_factory, seed):
    folder = tmp_path_factory.mktemp("data")
    label = dataset_case(random.Random(seed), folder, templates[0])
    _check(run_case(lambda: load_dataset(folder), label))
    shutil.rmtree(folder)


@given(seed=st.integers(0, 2**32 - 1))
@FUZZ
def test_fuzzed_model_folders(templates, tmp_path_factory, seed):
    folder = tmp_path_factory.mktemp("model") / "m"
    label = model_case(random.Random(seed), folder, templates[1])
    _check(run_case(lambda: load_model(folder), label))
    shutil.rmtree(folder.parent)


# ---- the cases of issue 10, one by one --------------------------------------------------------------------
BASE = "resolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"


@pytest.mark.parametrize(
    "yaml_text,image,message",
    [
        (
            BASE.replace("0.05", "1" + "0" * 400) + "image: m.pgm\n",
            None,
            r"an integer of 401 digits is too large",
        ),
        (
            "image: m.pgm\n" + BASE + "x: " + "[" * 5000 + "]" * 5000 + "\n",
            None,
            r"nested deeper than 32 levels",
        ),
        (
            'a: &a ["lol","lol"]\nb: [*a,*a]\n' + BASE + "image: m.pgm\n",
            None,
            r"anchors and aliases .* not accepted",
        ),
        (BASE + "image: m.pgm\n", b"P5\n100000 100000\n255\n", r"m\.pgm has more than \d+ pixels \(the cap"),
        (BASE + 'image: "a\\0b.pgm"\n', None, r"key 'image' must not contain control characters"),
        (BASE + "image: " + "a" * 5000 + ".pgm\n", None, r"key 'image' is a file name of 5004 characters"),
        (
            BASE + "image: m.pgm\n",
            b"%!PS-Adobe-3.0 EPSF-3.0\n%%BoundingBox: 0 0 1 1\n",
            r"cannot be read as PGM/PPM, PNG",
        ),
        (  # issue 26: a 50 MB comment took costmap 22 s to skip
            BASE + "image: m.pgm\n",
            b"P5\n#" + b"x" * 50_000_000 + b"\n2 2\n255\n" + bytes(4),
            r"m\.pgm: its PGM/PPM header \(with comments\) is longer than 65536 bytes; at most 65536 are accepted",
        ),
        (  # issue 26: 1 x 16,000,000 (inside the pixel cap) took costmap 22.7 s and 813 MiB
            BASE + "image: m.pgm\n",
            b"P5\n1 16000000\n255\n",
            r"m\.pgm is 1 x 16000000 pixels, longer than 1000 times its width or height",
        ),
        (BASE + "image: m.pgm\n", b"P2 # c\n# c\n2001 2 255\n", r"2001 x 2 pixels, longer than 1000 times"),
    ],
)
def test_issue_map_cases(tmp_path, yaml_text, image, message):
    (tmp_path / "m.pgm").write_bytes(image or b"P5\n2 2\n255\n" + bytes(4))
    (tmp_path / "map.yaml").write_text(yaml_text, encoding="utf-8")
    with pytest.raises(MapError, match=message) as info:
        load_map(tmp_path / "map.yaml")
    assert "\n" not in str(info.value) and len(str(info.value)) < 400


def test_big_png_over_the_cap_and_a_corrupt_chunk(tmp_path, monkeypatch):
    from PIL import Image

    Image.fromarray(np.zeros((300, 300), np.uint8)).save(tmp_path / "m.png")
    (tmp_path / "map.yaml").write_text(BASE + "image: m.png\n", encoding="utf-8")
    monkeypatch.setenv("SPCOTMHP_MAX_MAP_PIXELS", "50000")
    with pytest.raises(MapError, match=r"300 x 300 = 90000 pixels, over the cap of 50000 \(set SPCOTMHP_MAX"):
        load_map(tmp_path / "map.yaml")
    monkeypatch.delenv("SPCOTMHP_MAX_MAP_PIXELS")
    assert load_map(tmp_path / "map.yaml").shape == (300, 300)
    data = bytearray((tmp_path / "m.png").read_bytes())
    data[-20] ^= 0xFF  # inside the image data chunk: a CRC mismatch
    (tmp_path / "m.png").write_bytes(bytes(data))
    with pytest.raises(MapError, match=r"m\.png cannot be read as PGM/PPM, PNG, BMP"):
        load_map(tmp_path / "map.yaml")


@pytest.mark.parametrize(
    "column,value,message",
    [
        ("event", "1e20", r"teaching.csv row 2: event is '1e20', out of range"),
        ("x", "1e308", r"teaching.csv row 2: \(x, y\) = \(1e\+308, .*\) lies far outside the map"),
        ("y", "-1e308", r"lies far outside the map"),
        ("x", "1" + "0" * 400, r"teaching.csv row 2: x is '1000.*not a finite number"),
    ],
)
def test_issue_dataset_cases(templates, tmp_path, column, value, message):
    folder = tmp_path / "d"
    shutil.copytree(templates[0], folder)
    lines = (folder / "teaching.csv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    cells = lines[1].split(",")
    cells[header.index(column)] = value
    lines[1] = ",".join(cells)
    (folder / "teaching.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(DatasetError, match=message) as info:
        load_dataset(folder)
    assert len(str(info.value)) < 400


def test_issue_model_cases(templates, tmp_path):
    folder = tmp_path / "m"
    shutil.copytree(templates[1], folder)
    # a flipped byte: the manifest catches it
    data = bytearray((folder / "arrays.npz").read_bytes())
    data[len(data) // 2] ^= 0x10
    (folder / "arrays.npz").write_bytes(bytes(data))
    with pytest.raises(ModelError, match=r"arrays.npz does not match its checksum in manifest.json"):
        load_model(folder)
    # a symlink out of the folder
    shutil.rmtree(folder)
    shutil.copytree(templates[1], folder)
    (tmp_path / "elsewhere.json").write_bytes((folder / "model.json").read_bytes())
    (folder / "model.json").unlink()
    (folder / "model.json").symlink_to(tmp_path / "elsewhere.json")
    with pytest.raises(ModelError, match=r"'model.json' must be a file inside the model folder .* leads outside it"):
        load_model(folder)


def _reseal(folder: Path) -> None:
    import json

    from spcotmhp.persistence.folder import MANIFEST, manifest_of

    names = sorted(p.name for p in folder.iterdir() if p.is_file() and p.name != MANIFEST)
    (folder / MANIFEST).write_text(json.dumps(manifest_of(folder, names)), encoding="utf-8")


@pytest.mark.parametrize(
    "damage,message",
    [
        ("bomb", r"mu.npy unpacks to \d+ bytes, more than its shape"),
        ("bare", r"arrays.npz cannot be read as a numpy .npz archive"),
        ("asymmetric", r"Sigma\[0\] is not symmetric"),
        ("legacy-torn", r"has no manifest.json, which a model of format version 2 has"),
    ],
)
def test_issue_npz_cases(templates, tmp_path, damage, message):
    import zipfile

    folder = tmp_path / "m"
    shutil.copytree(templates[1], folder)
    if damage == "bomb":
        with zipfile.ZipFile(folder / "arrays.npz", "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("mu.npy", b"0" * (20 * 1024 * 1024))
    elif damage == "bare":
        np.save(folder / "x.npy", np.zeros(4))
        (folder / "x.npy").replace(folder / "arrays.npz")
    elif damage == "asymmetric":
        with np.load(folder / "arrays.npz") as npz:
            arrays = {k: npz[k] for k in npz.files}
        arrays["Sigma"][0, 0, 1] += 0.5
        np.savez(folder / "arrays.npz", **arrays)
    if damage == "legacy-torn":
        (folder / "manifest.json").unlink()
    else:
        _reseal(folder)
    with pytest.raises(ModelError, match=message):
        load_model(folder)


def test_version_1_folders_without_a_manifest_still_load(templates, tmp_path):
    import json

    folder = tmp_path / "old"
    shutil.copytree(templates[1], folder)
    (folder / "manifest.json").unlink()
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta["format_version"] = 1
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")
    model = load_model(folder)
    save_model(model, folder, overwrite=True)  # upgraded in place: now with a manifest
    assert (folder / "manifest.json").is_file()
    assert json.loads((folder / "model.json").read_text(encoding="utf-8"))["format_version"] == 2


def test_a_case_peak_is_the_case_s_own():
    """The memory bound reads what one case held, not the process's lifetime peak: an earlier 300 MiB array
    does not count against a small case, and a 200 MiB array in the case does."""
    from tests.helpers.hardening_corpus import case_peak

    big = np.ones(300 * 2**20 // 8)
    del big
    with case_peak() as small:
        np.zeros(1000).sum()
    with case_peak() as large:
        held = np.ones(200 * 2**20 // 8)
        del held
    assert small[0] < 50
    assert 150 < large[0] < 400


# ---- issue 26: hostile values behind valid checksums, hostile map headers ----------------------------------
@given(edits=model_edits())
@example(edits=[("hyper", "place_size", 1e308)])  # the cases of issue 26
@example(edits=[("hyper", "place_size", 1e308), ("hyper", "nu0", 5.0)])
@example(edits=[("array", "Sigma", "scale", 1e-300)])
@example(edits=[("array", "Sigma", "scale", 1e-150)])
@example(edits=[("array", "W", "zero-column", 0.0)])  # found from the outside: a word no concept uses
@example(edits=[("vocabulary", 0, "")])  # ... and a word nobody can say
@FUZZ
def test_fuzzed_model_values_load_and_plan_or_are_refused(templates, tmp_path_factory, edits):
    """A model folder whose values were changed and resealed loads and plans (finite paths) or is refused with
    one line: never a traceback or a numpy warning (the command line prints it: more than one line) in loading
    or planning (issue 26: place_size 1e308, covariances x 1e-300)."""
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.planning import HierarchicalPlanner

    folder = tmp_path_factory.mktemp("values") / "m"
    shutil.copytree(templates[1], folder)
    label = apply_edits(folder, edits)

    @_no_runtime_warning
    def load_and_plan() -> None:
        model = load_model(folder)
        planner = HierarchicalPlanner(model)
        starts = [model.mu[k] for k in range(model.K)] + [model.require_map().cell_to_world(np.array([40, 40]))]
        for start in starts:
            try:
                plan = planner.plan("go to the kitchen", start)
            except SpcotmhpError:
                continue
            assert np.isfinite(plan.path).all() and np.isfinite(plan.length_m), label

    _check(run_case(load_and_plan, label))
    shutil.rmtree(folder.parent)


def _no_runtime_warning(call):
    """``call`` with numpy's RuntimeWarnings (overflow, invalid value, division by zero) raised as errors."""

    def wrapped() -> None:
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            call()

    return wrapped


@pytest.fixture(scope="module")
def learner_template(templates, tmp_path_factory):
    """A 4-sweep SpCoTMHP fit of the template dataset, saved with its learner state."""
    from spcotmhp.learning.gibbs import SpCoTMHP

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = SpCoTMHP(iterations=4, seed=4).fit(load_dataset(templates[0])).model_
    return save_model(model, tmp_path_factory.mktemp("learner") / "m")


@given(edits=learner_edits())
@example(edits=[("n_k", "zero", 0.0)])  # found from the outside: counts below their events'
@example(edits=[("sxx", "scale", -1e6)])  # a scatter that gives no covariance
@example(edits=[("X", "row", 1e300)])  # an event 1e300 m away
@FUZZ
def test_fuzzed_learner_states_load_and_teach_or_are_refused(templates, learner_template, tmp_path_factory, edits):
    """A learner state whose counts, scatters or positions were changed and resealed loads and is taught, or is
    refused with one line: never a traceback or a numpy warning (the learner's values behind a valid checksum)."""
    from spcotmhp.teaching.teach import teach

    folder = tmp_path_factory.mktemp("learner-values") / "m"
    shutil.copytree(learner_template, folder)
    label = apply_learner_edits(folder, edits)
    model = load_model(templates[1])
    x, y = model.mu[int(np.flatnonzero(model.active_places)[0])]

    @_no_runtime_warning
    def load_and_teach() -> None:
        teach(load_model(folder), [(float(x), float(y), "this is the kitchen")])

    _check(run_case(load_and_teach, label))
    shutil.rmtree(folder.parent)


@given(image=pnm_files())
@example(image=b"P5\n#" + b"x" * 50_000_000 + b"\n2 2\n255\n" + bytes(4))  # the cases of issue 26
@example(image=b"P5\n1 16000000\n255\n" + bytes([254]) * 16_000_000)
@example(image=b"P5 16000000 1 255 " + bytes([254]) * 16_000_000)
@FUZZ
def test_fuzzed_pgm_headers(tmp_path_factory, image):
    """PGM/PPM headers with comments up to past the 64 KiB bound, sizes from 0 to 10^12 and strips longer than
    1000:1 load or give one MapError, in bounded time and memory (issue 26: a 50 MB comment, 1 x 16,000,000);
    a map that loads keeps the stated bounds (pixel cap, aspect ratio)."""
    from spcotmhp.safe_read import MAX_MAP_ASPECT, max_map_pixels

    folder = tmp_path_factory.mktemp("pnm")
    (folder / "m.pgm").write_bytes(image)
    (folder / "map.yaml").write_text(BASE + "image: m.pgm\n", encoding="utf-8")

    def load() -> None:
        height, width = load_map(folder / "map.yaml").shape
        assert height * width <= max_map_pixels() and max(height, width) <= MAX_MAP_ASPECT * min(height, width)

    _check(run_case(load, f"{image[:40]!r} ({len(image)} bytes)"))
    shutil.rmtree(folder)


@pytest.mark.parametrize(
    "magic,side,body",
    [(b"P2", 1415, b"254\n"), (b"P3", 817, b"254 254 254\n"), (b"P1", 1415, b"0 ")],
)
def test_plain_pnm_files_beyond_two_million_values_are_refused_before_decoding(tmp_path, magic, side, body):
    """Found from the outside: a plain (ASCII) PGM at the pixel cap took 5 s of Pillow's Python decoding. Plain
    files hold at most MAX_PLAIN_PNM_VALUES sample values; one side fewer loads."""
    from spcotmhp.safe_read import MAX_PLAIN_PNM_VALUES

    for n, refused in ((side, True), (side - 1, False)):
        values = n * n * (3 if magic == b"P3" else 1)
        assert (values > MAX_PLAIN_PNM_VALUES) == refused
        maxval = b"" if magic == b"P1" else b"255\n"
        (tmp_path / "m.pgm").write_bytes(magic + b"\n# a comment\n%d %d\n" % (n, n) + maxval + body * (n * n))
        (tmp_path / "map.yaml").write_text(BASE + "image: m.pgm\n", encoding="utf-8")
        if refused:
            with pytest.raises(MapError, match=r"plain \(ASCII\) P\d file of \d+ x \d+ pixels.*binary PGM \(P5\)"):
                load_map(tmp_path / "map.yaml")
        else:
            assert load_map(tmp_path / "map.yaml").shape == (n, n)
