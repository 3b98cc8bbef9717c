"""Building folders: a generated one loads as written; every refusal is one typed line naming the floor or the
connector; a fuzz of building.yaml's text over a real folder never gives a traceback."""

from __future__ import annotations

import random
import shutil
import warnings

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.building.loader import is_building, load_building
from spcotmhp.building.synthetic import generate_building, write_building
from spcotmhp.errors import BuildingError, DatasetError, SpcotmhpError
from spcotmhp.metric.map_io import load_map, save_map


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    made = generate_building(3, seed=4, n_rooms=5, events_per_room=4)
    return write_building(made, tmp_path_factory.mktemp("b") / "b")


def _copy(folder, tmp_path):
    out = tmp_path / "copy"
    shutil.copytree(folder, out)
    return out


def _edit(out, change):
    doc = yaml.safe_load((out / "building.yaml").read_text())
    change(doc)
    (out / "building.yaml").write_text(yaml.safe_dump(doc))


def test_loads_as_generated(folder):
    made = generate_building(3, seed=4, n_rooms=5, events_per_room=4)
    b = load_building(folder)
    assert is_building(folder) and not is_building(folder / "f1")
    assert b.spec == made.spec and b.lang == "en"
    for i, d in b.floors.items():
        assert d.map == made.floors[i].map
        assert np.array_equal(d.positions, made.floors[i].positions)
        assert d.place_names == made.floors[i].place_names


def test_a_floor_error_keeps_its_type_and_names_the_floor(folder, tmp_path):
    out = _copy(folder, tmp_path)
    (out / "f2" / "teaching.csv").write_text("event,x,y,words_en\n0,zz,1,kitchen\n")
    with pytest.raises(DatasetError) as err:
        load_building(out)
    assert str(err.value).startswith("floor 2 (first, f2): teaching.csv row 2")
    shutil.copytree(folder / "f2", out / "f2", dirs_exist_ok=True)
    shutil.rmtree(out / "f3")
    with pytest.raises(DatasetError, match=r"floor 3 \(second, f3\): dataset folder .* does not exist"):
        load_building(out)


def test_a_stop_must_be_free(folder, tmp_path):
    out = _copy(folder, tmp_path)
    _edit(out, lambda d: d["connectors"][0]["stops"][1].update(x=-50.0))
    with pytest.raises(BuildingError, match=r"connectors\[0\] \(lift\) stop on floor 2 at \(-50.00, .*off that floor"):
        load_building(out)
    _edit(out, lambda d: d["connectors"][0]["stops"][1].update(x=0.0, y=0.0))
    with pytest.raises(BuildingError, match="lies in an unknown cell of that floor's map; a stop must be free"):
        load_building(out)


def test_floors_share_a_resolution(folder, tmp_path):
    out = _copy(folder, tmp_path)
    occ = load_map(out / "f2" / "map.yaml")
    occ.resolution = 0.05
    save_map(occ, out / "f2" / "map.yaml")
    with pytest.raises(BuildingError, match="share one resolution"):
        load_building(out)


def test_datasets_stay_inside_the_building(folder, tmp_path):
    out = _copy(folder, tmp_path)
    (out / "link").symlink_to(folder)
    _edit(out, lambda d: d["floors"][0].update(dataset="link/f1"))
    with pytest.raises(BuildingError, match="leads outside"):
        load_building(out)


@given(seed=st.integers(0, 2**32 - 1))
@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
def test_fuzzed_building_files(folder, tmp_path_factory, seed):
    """Random byte edits of building.yaml: a building, or one typed error line."""
    out = tmp_path_factory.mktemp("fuzz") / "b"
    shutil.copytree(folder, out)
    rnd = random.Random(seed)
    text = bytearray((out / "building.yaml").read_bytes())
    for _ in range(rnd.randint(1, 6)):
        i = rnd.randrange(len(text))
        op = rnd.random()
        if op < 0.4:
            text[i] = rnd.choice(b"-0123456789.:,[]{} abcxyz\n\x00\xff")
        elif op < 0.7:
            del text[i : i + rnd.randint(1, 8)]
        else:
            text[i:i] = bytes(rnd.choice(b"9e-[]{}:, ") for _ in range(rnd.randint(1, 6)))
    (out / "building.yaml").write_bytes(bytes(text))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            b = load_building(out)
        except SpcotmhpError as exc:
            assert "\n" not in str(exc)
        else:
            assert set(b.floors) == set(b.spec.indices)
    shutil.rmtree(out.parent)
