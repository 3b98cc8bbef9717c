"""Model folders: save/load round trip, and clear errors for missing, corrupt or mismatched files."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.errors import ModelError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.persistence.io import load_model, save_model
from tests.helpers.learning import reseal

pytestmark = pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")
FIELDS = ("mu", "Sigma", "psi", "pi", "phi", "W", "theta", "active_places", "active_concepts")


@pytest.fixture(scope="module")
def model():
    m = fit_supervised(load_bundled("albert-b", lang="ja"), adjacency="map")  # has features (theta)
    m.info["note"] = "ひらがな ok"
    return m


@pytest.fixture()
def saved(model, tmp_path):
    return save_model(model, tmp_path / "model")


def test_round_trip(model, saved):
    assert sorted(p.name for p in saved.iterdir()) == [
        "arrays.npz",
        "manifest.json",
        "map.pgm",
        "map.yaml",
        "model.json",
    ]
    back = load_model(saved)
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(back, name), getattr(model, name))
    assert back.vocabulary == model.vocabulary
    assert back.hyper == model.hyper
    assert back.costmap == model.costmap
    assert back.info == json.loads(json.dumps(model.info))
    np.testing.assert_array_equal(back.map.data, model.map.data)
    assert back.map.resolution == model.map.resolution and back.map.origin == model.map.origin
    np.testing.assert_allclose(
        back.log_word_likelihood(["きゅうけいじょ"]), model.log_word_likelihood(["きゅうけいじょ"])
    )


def test_model_without_features_or_map(model, tmp_path):
    bare = fit_supervised(load_bundled("3LDK_05", lang="en"))
    bare.map = None
    back = load_model(save_model(bare, tmp_path / "bare"))
    assert back.theta is None and back.map is None
    np.testing.assert_array_equal(back.psi, bare.psi)


_reseal = reseal


def _rewrite_json(folder, **changes):
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta.update(changes)
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")
    _reseal(folder)


def _rewrite_npz(folder, **arrays):
    with np.load(folder / "arrays.npz") as npz:
        data = {k: npz[k] for k in npz.files}
    data.update(arrays)
    for k in [k for k, v in arrays.items() if v is None]:
        del data[k]
    np.savez(folder / "arrays.npz", **data)
    _reseal(folder)


def test_missing_folder_and_files(saved, tmp_path):
    with pytest.raises(ModelError, match="does not exist"):
        load_model(tmp_path / "nowhere")
    (saved / "arrays.npz").unlink()
    with pytest.raises(ModelError, match=r"arrays.npz is listed in manifest.json but missing \(a torn"):
        load_model(saved)
    _reseal(saved)
    with pytest.raises(ModelError, match=r"arrays.npz is missing"):
        load_model(saved)
    (saved / "model.json").unlink()
    _reseal(saved)
    with pytest.raises(ModelError, match=r"model.json is missing"):
        load_model(saved)


@pytest.mark.parametrize(
    "text,message",
    [
        ("{not json", "is not valid JSON"),
        ('{"format": "something-else"}', "is not a spcotmhp model"),
        (
            '{"format": "spcotmhp-model", "format_version": 99}',
            "format version 99; this spcotmhp reads versions 1, 2",
        ),
    ],
)
def test_corrupt_or_foreign_json(saved, text, message):
    (saved / "model.json").write_text(text, encoding="utf-8")
    _reseal(saved)
    with pytest.raises(ModelError, match=message):
        load_model(saved)


def test_json_fields_checked(saved):
    _rewrite_json(saved, vocabulary=["only", "two"])
    with pytest.raises(ModelError, match=r"\"vocabulary\" must list V = \d+ words"):
        load_model(saved)


def test_unknown_hyper_parameter(saved):
    meta = json.loads((saved / "model.json").read_text(encoding="utf-8"))
    _rewrite_json(saved, hyper={**meta["hyper"], "temperature": 3})
    with pytest.raises(ModelError, match="unknown hyper-parameter"):
        load_model(saved)


def test_truncated_npz(saved):
    data = (saved / "arrays.npz").read_bytes()
    (saved / "arrays.npz").write_bytes(data[: len(data) // 2])
    _reseal(saved)
    with pytest.raises(ModelError, match="cannot be read as a numpy .npz archive"):
        load_model(saved)


def test_pickled_object_array_is_refused_not_executed(saved, tmp_path):
    marker = tmp_path / "executed"

    class Evil:
        def __reduce__(self):
            return (marker.write_text, ("pwned",))

    _rewrite_npz(saved, W=np.array([Evil()], dtype=object))
    with pytest.raises(ModelError, match="W has dtype object; expected floating-point numbers"):
        load_model(saved)
    assert not marker.exists()


def test_missing_array(saved):
    _rewrite_npz(saved, theta=None)
    with pytest.raises(ModelError, match="lacks the array"):
        load_model(saved)


@pytest.mark.parametrize(
    "name,value,message",
    [
        ("psi", lambda m: m.psi[:, :-1], r"psi has shape \(\d+, \d+\), but model.json"),
        (
            "theta",
            lambda m: m.theta[:, :10],
            r"theta has shape \(\d+, 10\), but model.json needs \(\d+, 365\)",
        ),
        ("pi", lambda m: m.pi * 2, "pi must be non-negative with rows summing to 1"),
        ("mu", lambda m: np.full_like(m.mu, np.nan), "mu must hold finite floating-point numbers"),
        (
            "Sigma",
            lambda m: -m.Sigma,
            r"arrays.npz: Sigma\[0\] is not positive definite within the usable range \(eigenvalues -[\d.e-]+, "
            r"-[\d.e-]+\); a covariance must be positive definite, its smaller eigenvalue at least 1e-10 square "
            r"metres and above 1e-12 times the larger$",
        ),
        (  # issue 26: a covariance scaled by 1e-300 loaded, then planning crashed on its zero determinant
            "Sigma",
            lambda m: m.Sigma * 1e-300,
            r"arrays.npz: Sigma\[0\] is not positive definite within the usable range \(eigenvalues [\d.]+e-30\d",
        ),
        ("psi", lambda m: np.full_like(m.psi, 0.0), r"arrays.npz: psi must be non-negative with rows summing to 1"),
        (
            "active_places",
            lambda m: m.active_places.astype(float),
            ("active_places has dtype float64; expected booleans"),
        ),
    ],
)
def test_mismatched_arrays(model, saved, name, value, message):
    _rewrite_npz(saved, **{name: value(model)})
    with pytest.raises(ModelError, match=message):
        load_model(saved)


def test_broken_map(saved):
    (saved / "map.pgm").write_bytes(b"P5 garbage")
    _reseal(saved)
    with pytest.raises(ModelError, match="the model's map cannot be loaded"):
        load_model(saved)


def test_save_onto_a_file(model, tmp_path):
    target = tmp_path / "file"
    target.write_text("x")
    with pytest.raises(ModelError, match="exists and is not a folder"):
        save_model(model, target)
    assert zipfile.is_zipfile(save_model(model, tmp_path / "ok") / "arrays.npz")


def test_saved_model_predicts_the_events_it_was_fitted_on(model, saved):
    from sklearn.metrics import normalized_mutual_info_score

    from spcotmhp.learning.supervised import predict_assignments

    data = load_bundled("albert-b", lang="ja")
    places, concepts = predict_assignments(load_model(saved), data)
    assert normalized_mutual_info_score(data.truth_place, places) > 0.9
    assert normalized_mutual_info_score(data.truth_concept, concepts) > 0.9


def test_features_of_another_dimension_are_refused(saved):
    from spcotmhp.learning.supervised import predict_assignments

    data = load_bundled("albert-b", lang="ja")
    data.features = data.features[:, :100]
    with pytest.raises(ModelError, match="image features have 100 dimensions but the model was learned with 365"):
        predict_assignments(load_model(saved), data)


def _meta(folder):
    return json.loads((folder / "model.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize(
    "changes,message",
    [
        ({"K": 0}, r"\"K\" must be >= 1, got 0"),
        ({"L": 0}, r"\"L\" must be >= 1, got 0"),
        ({"D": 0}, r"\"D\" must be >= 1, got 0"),
    ],
)
def test_empty_sizes_are_refused(saved, changes, message):
    _rewrite_json(saved, **changes)
    with pytest.raises(ModelError, match=message):
        load_model(saved)


def test_a_model_with_no_place_is_refused_not_a_traceback(saved):
    # K = 0 with arrays of matching (empty) shapes used to fail inside numpy (max of an empty array)
    meta = _meta(saved)
    _rewrite_json(saved, K=0)
    _rewrite_npz(
        saved,
        mu=np.zeros((0, 2)),
        Sigma=np.zeros((0, 2, 2)),
        psi=np.zeros((0, 0)),
        phi=np.zeros((meta["L"], 0)),
        active_places=np.zeros(0, dtype=bool),
    )
    with pytest.raises(ModelError, match=r"model.json: \"K\" must be >= 1, got 0"):
        load_model(saved)


def test_repeated_word_is_refused(saved):
    vocab = _meta(saved)["vocabulary"]
    _rewrite_json(saved, vocabulary=vocab[:-1] + [vocab[0]])
    with pytest.raises(
        ModelError,
        match=rf"\"vocabulary\" lists {vocab[0]!r} twice \(again at index "
        rf"{len(vocab) - 1}\)",
    ):
        load_model(saved)


@pytest.mark.parametrize(
    "costmap,message",
    [
        (
            {"inflation_radius": 1.0, "robot_size": 3},
            r"unknown cost map setting\(s\) robot_size in \"costmap\" \(known: inscribed_radius, inflation_radius",
        ),
        (
            {"inflation_radius": -1.0},
            r"\"costmap.inflation_radius\" must be a finite number in 0..10000, got -1.0",
        ),
        (
            {"inflation_radius": 1e308},
            r"\"costmap.inflation_radius\" must be a finite number in 0..10000, got 1e\+308",
        ),
        (
            {"cost_scaling_factor": "steep"},
            (
                r"\"costmap.cost_scaling_factor\" must be a finite number in 0..1e\+06, "
                r"got 'steep'"
            ),
        ),
        (
            {"inscribed_radius": True},
            r"\"costmap.inscribed_radius\" must be a finite number in 0..10000, got True",
        ),
        ({"track_unknown_space": 1}, r"\"costmap.track_unknown_space\" must be true or false, got 1"),
    ],
)
def test_cost_map_settings_are_checked(saved, costmap, message):
    _rewrite_json(saved, costmap=costmap)
    with pytest.raises(ModelError, match=message):
        load_model(saved)


def test_non_finite_cost_map_setting(saved):
    (saved / "model.json").write_text(
        (saved / "model.json")
        .read_text(encoding="utf-8")
        .replace('"inflation_radius": 1.0', '"inflation_radius": Infinity'),
        encoding="utf-8",
    )
    _reseal(saved)
    with pytest.raises(ModelError, match=r"model.json is not accepted: Infinity is not a number JSON accepts"):
        load_model(saved)


@pytest.mark.parametrize(
    "name,value,message",
    [
        ("alpha", "big", r"model.json: hyper-parameter alpha must be a finite number in \[1e-06, 1e\+06\], got 'big'"),
        ("gamma", -0.1, r"hyper-parameter gamma must be a finite number in \[1e-06, 1e\+06\], got -0.1"),
        ("beta", 0, r"hyper-parameter beta must be a finite number in \[1e-06, 1e\+06\], got 0"),
        ("omega", None, r"hyper-parameter omega must be a finite number in \[1e-06, 1e\+06\], got None"),
        ("kappa0", 1e400, r"model.json is not accepted: Infinity is not a number JSON accepts"),
        ("kappa0", 1e300, r"hyper-parameter kappa0 must be a finite number in \[1e-06, 1e\+06\], got 1e\+300"),
        ("nu0", 1, r"hyper-parameter nu0 must be a finite number in \(1, 1e\+06\], got 1"),
        ("L", 2.5, r"hyper-parameter L must be an integer in \[1, 10000\], got 2.5"),
        ("m0", [0, "x"], r"hyper-parameter m0 must be two finite numbers within \+-1e\+06 m, got \(0, 'x'\)"),
        ("V0", [[1, 2], [2, 1]], r"hyper-parameter V0 is not positive definite within the usable range"),
        ("V0", [[1, 0], [0, 1e-300]], r"hyper-parameter V0 is not positive definite within the usable range"),
        ("place_size", -2, r"hyper-parameter place_size must be a finite number of metres in \[0.001, 100000\]"),
        ("place_size", 1e308, r"hyper-parameter place_size must be a finite number of metres in .*, got 1e\+308"),
    ],
)
def test_bad_hyper_parameters_are_refused(saved, name, value, message):
    _rewrite_json(saved, hyper={**_meta(saved)["hyper"], name: value})
    with pytest.raises(ModelError, match=message):
        load_model(saved)


@pytest.mark.parametrize("weight", ["1", 0, -2.0, True, [1]])
def test_feature_weight_must_be_a_positive_number_or_null(saved, weight):
    _rewrite_json(saved, info={**_meta(saved)["info"], "feature_weight": weight})
    with pytest.raises(
        ModelError,
        match=r"\"info.feature_weight\" must be a positive number, or null for the "
        r"authors' counts, got ",
    ):
        load_model(saved)


def test_feature_weight_null_and_numbers_load(saved):
    for weight in (None, 2, 0.5):
        _rewrite_json(saved, info={**_meta(saved)["info"], "feature_weight": weight})
        assert load_model(saved).info["feature_weight"] == weight


def test_map_outside_the_model_folder_is_refused(saved, tmp_path):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    for name in ("map.yaml", "map.pgm"):
        (outside / name).write_bytes((saved / name).read_bytes())
    _rewrite_json(saved, map="../elsewhere/map.yaml")
    with pytest.raises(
        ModelError,
        match=r"\"map\" must be a file inside the model folder .*, got "
        r"'../elsewhere/map.yaml'",
    ):
        load_model(saved)
    _rewrite_json(saved, map=str(outside / "map.yaml"))  # an absolute path is outside too
    with pytest.raises(ModelError, match=r"\"map\" must be a file inside the model folder"):
        load_model(saved)


def test_map_image_outside_the_model_folder_is_refused(saved, tmp_path):
    (tmp_path / "secret.pgm").write_bytes((saved / "map.pgm").read_bytes())
    yaml_text = (saved / "map.yaml").read_text(encoding="utf-8").replace("image: map.pgm", "image: ../secret.pgm")
    (saved / "map.yaml").write_text(yaml_text, encoding="utf-8")
    _reseal(saved)
    with pytest.raises(ModelError, match=r"the image of map.yaml must be a file inside the model folder"):
        load_model(saved)


def test_psi_learned_round_trip_and_checks(model, tmp_path):
    m = fit_supervised(load_bundled("3LDK_05", lang="en"))
    assert m.psi_learned is None
    assert "psi_learned" not in np.load(save_model(m, tmp_path / "none") / "arrays.npz").files
    assert load_model(tmp_path / "none").psi_learned is None
    m.psi_learned = np.full((m.K, m.K), 1.0 / m.K)
    back = load_model(save_model(m, tmp_path / "with"))
    np.testing.assert_array_equal(back.psi_learned, m.psi_learned)
    _rewrite_npz(tmp_path / "with", psi_learned=np.ones((m.K, m.K)))
    with pytest.raises(ModelError, match="psi_learned must be non-negative with rows summing to 1"):
        load_model(tmp_path / "with")
    _rewrite_npz(tmp_path / "with", psi_learned=np.eye(m.K)[:, :2])
    with pytest.raises(ModelError, match=r"psi_learned has shape \(\d+, 2\), but model.json"):
        load_model(tmp_path / "with")
    _rewrite_npz(tmp_path / "with", psi_learned=None, surprise=np.zeros(3))
    with pytest.raises(ModelError, match=r"holds an unknown member 'surprise.npy'"):
        load_model(tmp_path / "with")


def test_unwritable_model_folder_is_a_model_error(model, tmp_path):
    from spcotmhp.persistence.io import prepare_model_folder

    with pytest.raises(ModelError, match=r"cannot save the model to /proc/nope/m: "):
        prepare_model_folder("/proc/nope/m")
    with pytest.raises(ModelError, match=r"cannot save the model to /proc/nope/m: "):
        save_model(model, "/proc/nope/m")
    assert prepare_model_folder(tmp_path / "a" / "b") == tmp_path / "a" / "b"  # checked, not created
    assert (tmp_path / "a").is_dir() and not (tmp_path / "a" / "b").exists()


def test_predict_assignments_with_a_zero_in_w_and_the_one_word_likelihood():
    # a saved model may hold W_l(w) = 0: words absent from an utterance add nothing (no NaN), a word said that a
    # concept never says rules that concept out; the same function serves the model, the planner and prediction
    import numpy as np

    from spcotmhp.datasets.dataset import Dataset
    from spcotmhp.learning.model import SpatialConceptModel, log_multinomial
    from spcotmhp.learning.supervised import predict_assignments
    from spcotmhp.metric.maps import OccupancyMap

    W = np.array([[1.0, 0.0], [0.0, 1.0]])  # concept 0 says only "a", concept 1 only "b"
    model = SpatialConceptModel(
        mu=np.array([[1.0, 1.0], [3.0, 1.0]]),
        Sigma=np.tile(np.eye(2) * 0.25, (2, 1, 1)),
        psi=np.full((2, 2), 0.5),
        pi=np.array([0.5, 0.5]),
        phi=np.eye(2) * 0.98 + 0.01,
        W=W,
        vocabulary=["a", "b"],
    )
    data = Dataset(
        name="z",
        map=OccupancyMap(data=np.zeros((20, 40), np.int8), resolution=0.1),
        positions=np.array([[1.0, 1.0], [3.0, 1.0], [1.0, 1.0]]),
        tokens=[["a"], ["b"], ["b"]],
    )
    places, concepts = predict_assignments(model, data, use_features=False)
    assert concepts.tolist() == [0, 1, 1] and places.tolist() == [0, 1, 0]
    with np.errstate(divide="ignore"):
        lw = log_multinomial(np.log(W), np.array([[2.0, 0.0], [0.0, 0.0], [1.0, 1.0]]))
    assert lw.tolist() == [[0.0, -np.inf], [0.0, 0.0], [-np.inf, -np.inf]]
    assert model.log_word_likelihood(["a", "a"]).tolist() == [0.0, -np.inf]


@pytest.mark.parametrize("given, shown", [(None, "NoneType"), (3, "int"), (["m06"], "list")])
def test_load_model_takes_a_folder(given, shown):
    """Audit item 13: load_model(None) raised a bare TypeError from Path(None)."""
    with pytest.raises(ModelError) as info:
        load_model(given)
    assert str(info.value) == f"load_model takes a model folder (a str or a path), got {shown}"


def _grow_sparse(path, size: int) -> None:
    with open(path, "r+b") as handle:
        handle.truncate(size)


@pytest.mark.parametrize("resealed", [False, True])
def test_a_huge_sparse_arrays_npz_is_refused_before_it_is_hashed(saved, resealed):
    """Issue 26: arrays.npz grown to 8 GiB (sparse) was hashed in full (12 s) before it was refused. The size is
    now checked against the manifest, and against what K, L, V and D allow, before any byte is hashed: with
    the manifest resealed to the new size (its SHA-256 left stale), the refusal must name the bound, which it
    could not if the file had been hashed first (that would be a checksum mismatch)."""
    _grow_sparse(saved / "arrays.npz", 8 * 2**30)
    if resealed:
        manifest = json.loads((saved / "manifest.json").read_text(encoding="utf-8"))
        manifest["files"]["arrays.npz"]["bytes"] = 8 * 2**30
        (saved / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
        message = r"arrays.npz is 8589934592 bytes; a model of K=\d+, L=\d+, V=\d+, D=365 has at most \d+"
    else:
        message = r"arrays.npz is 8589934592 bytes, but manifest.json lists \d+: the model folder is torn or altered"
    with pytest.raises(ModelError, match=message) as info:
        load_model(saved)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "name, size, message",
    [
        ("model.json", 2**34, r"model.json is 17179869184 bytes; at most 16777216 are accepted"),
        ("map.yaml", 2**30, r"map.yaml is 1073741824 bytes; at most 65536 are accepted"),
        ("map.pgm", 2**36, r"map.pgm is 68719476736 bytes; a map image of at most 16000000 pixels has at most \d+"),
    ],
)
def test_every_file_has_a_bound_checked_before_it_is_read(saved, name, size, message):
    _grow_sparse(saved / name, size)
    manifest = json.loads((saved / "manifest.json").read_text(encoding="utf-8"))
    manifest["files"][name]["bytes"] = size
    (saved / "manifest.json").write_text(json.dumps(manifest), encoding="utf-8")
    with pytest.raises(ModelError, match=message):
        load_model(saved)
