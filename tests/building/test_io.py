"""Building model folders: round trip; a plain model folder plus a manifest-checked building.json; every bad
building.json is one ModelError line (a fuzz of its fields with the manifest made to agree)."""

from __future__ import annotations

import contextlib
import copy
import json
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.building.io import BUILDING_JSON, is_building_model, load_building_model, save_building_model
from spcotmhp.building.learn import learn_building
from spcotmhp.building.synthetic import generate_building
from spcotmhp.errors import ModelError
from spcotmhp.persistence.folder import MANIFEST, manifest_of
from spcotmhp.persistence.io import load_model, save_model
from tests.helpers.strategies import document_paths


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bm = learn_building(generate_building(2, seed=5, n_rooms=4, events_per_room=4))
    return bm, save_building_model(bm, tmp_path_factory.mktemp("m") / "model")


def _rewrite(folder, doc):
    (folder / BUILDING_JSON).write_text(json.dumps(doc))
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and p.name != MANIFEST)
    (folder / MANIFEST).write_text(json.dumps(manifest_of(folder, names)))


def _copy(saved, tmp_path):
    import shutil

    out = tmp_path / "copy"
    shutil.copytree(saved[1], out)
    return out


def test_round_trip(saved):
    bm, folder = saved
    back = load_building_model(folder)
    assert is_building_model(folder)
    assert back.spec == bm.spec and back.layout == bm.layout
    assert np.array_equal(back.model.mu, bm.model.mu) and back.model.map == bm.model.map
    for i in bm.indices:
        assert back.floor_model(i).map == bm.floor_model(i).map
    plain = load_model(folder)  # a building model also loads as a plain (joint) model
    assert np.array_equal(plain.W, bm.model.W)


def test_a_plain_model_is_not_a_building(saved, tmp_path):
    bm, _ = saved
    plain = save_model(bm.model, tmp_path / "plain")
    assert not is_building_model(plain)
    with pytest.raises(ModelError, match="no building.json: it is a single-floor model"):
        load_building_model(plain)


def test_tampering_is_refused(saved, tmp_path):
    out = _copy(saved, tmp_path)
    text = (out / BUILDING_JSON).read_text().replace('"cost_m": ', '"cost_m": 1')
    (out / BUILDING_JSON).write_text(text)
    with pytest.raises(ModelError, match=r"manifest.json lists \d+: the model folder is torn or altered"):
        load_building_model(out)


@pytest.mark.parametrize(
    "change, words",
    [
        (lambda d: d.update(format_version=2), "reads spcotmhp-building-model version 1"),
        (lambda d: d.pop("layout"), "must be an object with format, format_version, spec and layout"),
        (lambda d: d["spec"]["connectors"][0].update(cost_m=-1), "connectors[0].cost_m must be"),
        (lambda d: d["layout"]["tiles"][1].update(col0=3), "layout tiles[1] must be"),
        (lambda d: d["layout"].update(gap=d["layout"]["gap"] + 1), "layout tiles[1] must be"),
        (lambda d: d["layout"]["tiles"][1]["shape"].__setitem__(1, 50), "is not the building's joint grid"),
        (lambda d: d["spec"]["floors"][1].update(index=5), "stops[1].floor must be one of the floors' indices (1, 5)"),
        (lambda d: d["layout"]["tiles"][1].update(index=3), "layout's floors [1, 3] are not the building's [1, 2]"),
        (lambda d: d["spec"]["connectors"][0]["stops"][0].update(x=-1000.0), "lies off that floor's map"),
    ],
)
def test_bad_fields_are_one_line(saved, tmp_path, change, words):
    out = _copy(saved, tmp_path)
    doc = json.loads((out / BUILDING_JSON).read_text())
    change(doc)
    _rewrite(out, doc)
    with pytest.raises(ModelError) as err:
        load_building_model(out)
    assert words in str(err.value) and "\n" not in str(err.value)


LEAVES = st.one_of(
    st.none(), st.booleans(), st.integers(-(10**9), 10**9), st.floats(), st.text(max_size=5), st.just([])
)


@given(data=st.data())
@settings(max_examples=80, deadline=None, suppress_health_check=list(HealthCheck))
def test_fuzzed_building_json(saved, tmp_path_factory, data):
    out = tmp_path_factory.mktemp("fuzz") / "m"
    import shutil

    shutil.copytree(saved[1], out)
    doc = json.loads((out / BUILDING_JSON).read_text())
    paths = list(document_paths(doc))[1:]
    edited = copy.deepcopy(doc)
    for path in data.draw(st.lists(st.sampled_from(paths), min_size=1, max_size=3)):
        node = edited
        try:
            for k in path[:-1]:
                node = node[k]
            node[path[-1]] = data.draw(LEAVES)
        except (KeyError, IndexError, TypeError):
            continue
    with contextlib.suppress(ValueError):  # NaN / inf: JSON writes them, the loader must refuse them
        _rewrite(out, edited)
    try:
        load_building_model(out)
    except ModelError as exc:
        assert "\n" not in str(exc)
    shutil.rmtree(out.parent)
