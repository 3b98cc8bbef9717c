"""Generated buildings: seeded, repeated names across floors, one floor reached by the lift only, stops a robot can
stand on in its floor's main free space; the bundled example is what the generator writes; ``synth building``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage
from typer.testing import CliRunner

from spcotmhp.building.loader import load_building
from spcotmhp.building.synthetic import (
    MAX_SYNTH_FLOORS,
    example_building,
    example_path,
    generate_building,
    lift_only_floor,
)
from spcotmhp.cli import app
from spcotmhp.errors import BuildingError
from spcotmhp.metric.costmap import inflate

SPCOTMHP = str(Path(sys.executable).parent / "spcotmhp")


@pytest.mark.parametrize("floors", [2, 3, 5])
def test_buildings_have_the_promised_shape(floors):
    b = generate_building(floors, seed=floors)
    spec = b.spec
    assert spec.indices == list(range(1, floors + 1))
    names = [set(d.place_names) for d in b.floors.values()]
    assert set.intersection(*names) >= {"kitchen", "corridor"}  # names repeat across floors
    only = lift_only_floor(spec)
    assert only is not None
    stairs = [c for c in spec.connectors if c.kind == "stairs"]
    assert all(only not in {s.floor for s in c.stops} for c in stairs)
    (lift,) = [c for c in spec.connectors if c.kind == "lift"]
    assert [s.floor for s in lift.stops] == spec.indices
    # the floors other than the lift-only one are chained by stairs
    assert len(stairs) == floors - 2
    assert all(c.cost_m > 0 for c in spec.connectors)
    assert len({d.map.shape for d in b.floors.values()}) == 1  # one footprint


def test_stops_stand_in_the_robot_free_space():
    for seed in range(4):
        b = generate_building(4, seed=seed, n_rooms=6)
        for c in b.spec.connectors:
            for s in c.stops:
                occ = b.floors[s.floor].map
                free = np.isfinite(inflate(occ).log_p)
                labels, _ = ndimage.label(free, structure=np.ones((3, 3)))
                main = np.argmax(np.bincount(labels[free]))
                r, col = occ.world_to_cell(np.array([[s.x, s.y]]))[0]
                assert labels[r, col] == main, (seed, c.name, s)


def test_seeded():
    a, b = generate_building(3, seed=7, n_rooms=5), generate_building(3, seed=7, n_rooms=5)
    assert a.spec == b.spec
    assert all(np.array_equal(a.floors[i].positions, b.floors[i].positions) for i in a.floors)
    assert generate_building(3, seed=8, n_rooms=5).spec != a.spec
    assert lift_only_floor(generate_building(3, seed=7, lift_only=False).spec) is None


def test_bounds():
    with pytest.raises(BuildingError, match=rf"floors must be an integer in \[1, {MAX_SYNTH_FLOORS}\]"):
        generate_building(0)
    one = generate_building(1, seed=0, n_rooms=4)
    assert one.spec.connectors == ()


def test_the_bundled_example_is_the_generated_one():
    made, bundled = example_building(), load_building(example_path())
    assert bundled.spec == made.spec and len(bundled.spec.floors) == 2
    assert {c.kind for c in bundled.spec.connectors} == {"stairs", "lift"}
    for i in made.floors:
        assert bundled.floors[i].map == made.floors[i].map
        assert np.array_equal(bundled.floors[i].positions, made.floors[i].positions)
        assert bundled.floors[i].tokens == made.floors[i].tokens


def test_synth_building_command(tmp_path):
    out = tmp_path / "b"
    res = CliRunner().invoke(app, ["synth", "building", "--floors", "3", "--rooms", "5", "--seed", "1",
                                   "--events-per-room", "3", "--out", str(out)])  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "3 floors" in res.output and "is reached by the lift only" in res.output
    assert load_building(out).spec == generate_building(3, seed=1, n_rooms=5, events_per_room=3).spec
    again = subprocess.run([SPCOTMHP, "synth", "building", "--floors", "3", "--out", str(out)], capture_output=True,
                           text=True, timeout=120)  # fmt: skip
    assert again.returncode == 2
    told = "already holds a building; give --overwrite to replace it, or choose another folder"
    assert again.stderr == f"error: {out} {told}\n"
    size = CliRunner().invoke(app, ["synth", "building", "--size", "100", "--out", str(tmp_path / "c")])
    assert isinstance(size.exception, BuildingError)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "notes.txt").write_text("mine")
    other = CliRunner().invoke(app, ["synth", "building", "--out", str(tmp_path / "d")])
    assert isinstance(other.exception, BuildingError) and (tmp_path / "d" / "notes.txt").read_text() == "mine"
