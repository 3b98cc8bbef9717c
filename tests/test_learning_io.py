"""Model folders: save/load round trip, and clear errors for missing, corrupt or mismatched files."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.errors import ModelError
from spcotmhp.learning.io import load_model, save_model
from spcotmhp.learning.supervised import fit_supervised

pytestmark = pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")
FIELDS = ("mu", "Sigma", "psi", "pi", "phi", "W", "theta", "active_places", "active_concepts")


@pytest.fixture(scope="module")
def model():
    m = fit_supervised(load_bundled("albert-b", lang="ja"), adjacency="map")   # has features (theta)
    m.info["note"] = "ひらがな ok"
    return m


@pytest.fixture()
def saved(model, tmp_path):
    return save_model(model, tmp_path / "model")


def test_round_trip(model, saved):
    assert sorted(p.name for p in saved.iterdir()) == ["arrays.npz", "map.pgm", "map.yaml", "model.json"]
    back = load_model(saved)
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(back, name), getattr(model, name))
    assert back.vocabulary == model.vocabulary
    assert back.hyper == model.hyper
    assert back.costmap == model.costmap
    assert back.info == json.loads(json.dumps(model.info))
    np.testing.assert_array_equal(back.map.data, model.map.data)
    assert back.map.resolution == model.map.resolution and back.map.origin == model.map.origin
    np.testing.assert_allclose(back.log_word_likelihood(["きゅうけいじょ"]), model.log_word_likelihood(["きゅうけいじょ"]))


def test_model_without_features_or_map(model, tmp_path):
    bare = fit_supervised(load_bundled("3LDK_05", lang="en"))
    bare.map = None
    back = load_model(save_model(bare, tmp_path / "bare"))
    assert back.theta is None and back.map is None
    np.testing.assert_array_equal(back.psi, bare.psi)


def _rewrite_json(folder, **changes):
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    meta.update(changes)
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")


def _rewrite_npz(folder, **arrays):
    with np.load(folder / "arrays.npz") as npz:
        data = {k: npz[k] for k in npz.files}
    data.update(arrays)
    for k in [k for k, v in arrays.items() if v is None]:
        del data[k]
    np.savez(folder / "arrays.npz", **data)


def test_missing_folder_and_files(saved, tmp_path):
    with pytest.raises(ModelError, match="does not exist"):
        load_model(tmp_path / "nowhere")
    (saved / "arrays.npz").unlink()
    with pytest.raises(ModelError, match=r"arrays.npz is missing"):
        load_model(saved)
    (saved / "model.json").unlink()
    with pytest.raises(ModelError, match=r"model.json is missing"):
        load_model(saved)


@pytest.mark.parametrize("text,message", [
    ("{not json", "is not valid JSON"),
    ('{"format": "something-else"}', "is not a spcotmhp model"),
    ('{"format": "spcotmhp-model", "format_version": 99}', "format version 99; this spcotmhp reads version 1"),
])
def test_corrupt_or_foreign_json(saved, text, message):
    (saved / "model.json").write_text(text, encoding="utf-8")
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
    with pytest.raises(ModelError, match="cannot be read as a numpy .npz archive"):
        load_model(saved)


def test_pickled_object_array_is_refused_not_executed(saved, tmp_path):
    marker = tmp_path / "executed"

    class Evil:
        def __reduce__(self):
            return (marker.write_text, ("pwned",))

    _rewrite_npz(saved, W=np.array([Evil()], dtype=object))
    with pytest.raises(ModelError, match="cannot be read as a numpy .npz archive of plain arrays"):
        load_model(saved)
    assert not marker.exists()


def test_missing_array(saved):
    _rewrite_npz(saved, theta=None)
    with pytest.raises(ModelError, match="lacks the array"):
        load_model(saved)


@pytest.mark.parametrize("name,value,message", [
    ("psi", lambda m: m.psi[:, :-1], r"psi has shape \(\d+, \d+\), but model.json"),
    ("theta", lambda m: m.theta[:, :10], r"theta has shape .* D=365"),
    ("pi", lambda m: m.pi * 2, "pi must be non-negative with rows summing to 1"),
    ("mu", lambda m: np.full_like(m.mu, np.nan), "mu must hold finite floating-point numbers"),
    ("Sigma", lambda m: -m.Sigma, r"Sigma\[0\] is not positive definite"),
    ("active_places", lambda m: m.active_places.astype(float), "active_places must be boolean"),
])
def test_mismatched_arrays(model, saved, name, value, message):
    _rewrite_npz(saved, **{name: value(model)})
    with pytest.raises(ModelError, match=message):
        load_model(saved)


def test_broken_map(saved):
    (saved / "map.pgm").write_bytes(b"P5 garbage")
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

    from spcotmhp.learning.predict import predict_assignments

    data = load_bundled("albert-b", lang="ja")
    places, concepts = predict_assignments(load_model(saved), data)
    assert normalized_mutual_info_score(data.truth_place, places) > 0.9
    assert normalized_mutual_info_score(data.truth_concept, concepts) > 0.9


def test_features_of_another_dimension_are_refused(saved):
    from spcotmhp.learning.predict import predict_assignments

    data = load_bundled("albert-b", lang="ja")
    data.features = data.features[:, :100]
    with pytest.raises(ModelError, match="image features have 100 dimensions but the model was learned with 365"):
        predict_assignments(load_model(saved), data)
