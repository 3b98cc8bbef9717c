"""A model save interrupted at any point leaves the folder loading the old model or the new one, never a mixture:
an exception raised at every file-system step of save_model in turn, and a saving process killed at random times.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from spcotmhp import safe_write
from spcotmhp.datasets import load_bundled
from spcotmhp.errors import ModelError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric import map_io
from spcotmhp.persistence import folder as model_folder
from spcotmhp.persistence.io import load_model, save_model

pytestmark = pytest.mark.filterwarnings("ignore")


class Interrupted(BaseException):
    """Stands for a crash or a signal in the middle of a save (not an Exception: nothing may swallow it)."""


@pytest.fixture(scope="module")
def old_and_new():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        old = fit_supervised(load_bundled("3LDK_05", lang="en"))
        new = fit_supervised(load_bundled("3LDK_06", lang="en"))
    return old, new


def _which(folder: Path, old, new) -> str:
    model = load_model(folder)
    for name, reference in (("old", old), ("new", new)):
        same = (
            model.mu.shape == reference.mu.shape
            and np.array_equal(model.mu, reference.mu)
            and model.vocabulary == reference.vocabulary
            and np.array_equal(model.map.data, reference.map.data)
        )
        if same:
            return name
    raise AssertionError(f"{folder} loads a mixture of the old and the new model")


# every step that touches the disk while saving, in the modules that do it
STEPS = [
    (safe_write, "fresh_sibling"),
    (model_folder, "manifest_of"),
    (safe_write, "swap_folder"),
    (map_io, "atomic_write"),
    (np, "savez"),
    (Path, "write_text"),
    (os, "rename"),
    (os, "replace"),
    (shutil, "rmtree"),
    (os, "fsync"),
]


def test_a_save_interrupted_at_every_step_leaves_the_old_or_the_new_model(old_and_new, tmp_path, monkeypatch):
    old, new = old_and_new
    seen = []
    for point in range(40):
        folder = tmp_path / f"m{point}"
        save_model(old, folder)
        calls = {"n": 0}

        def wrap(fn, name, calls=calls, point=point):
            def step(*args, **kwargs):
                calls["n"] += 1
                if calls["n"] == point + 1:
                    raise Interrupted(name)
                return fn(*args, **kwargs)

            return step

        with monkeypatch.context() as patch:
            for owner, name in STEPS:
                patch.setattr(owner, name, wrap(getattr(owner, name), name))
            try:
                save_model(new, folder, overwrite=True)
                finished = True
            except Interrupted:
                finished = False
        seen.append(_which(folder, old, new))
        if finished:
            assert seen[-1] == "new"
            break
    assert "old" in seen and seen[-1] == "new"  # interrupted early: old; past the swap or done: new


SAVER = """
import sys, warnings, pickle
warnings.simplefilter("ignore")
from spcotmhp.persistence.io import save_model
old, new = pickle.load(open(sys.argv[2], "rb"))
print("ready", flush=True)
while True:
    save_model(new, sys.argv[1], overwrite=True)
    save_model(old, sys.argv[1], overwrite=True)
"""


def test_a_saving_process_killed_at_random_times(old_and_new, tmp_path):
    import pickle
    import random

    old, new = old_and_new
    blob = tmp_path / "models.pickle"  # the test's own objects, written and read by this test only
    blob.write_bytes(pickle.dumps((old, new)))
    rng = random.Random(0)
    outcomes = []
    for i in range(6):
        folder = tmp_path / f"k{i}"
        save_model(old, folder)
        proc = subprocess.Popen(
            [sys.executable, "-c", SAVER, str(folder), str(blob)],
            stdout=subprocess.PIPE,
            env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        )
        assert proc.stdout.readline().strip() == b"ready"
        time.sleep(rng.uniform(0.0, 1.5))
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
        assert proc.returncode == -signal.SIGKILL  # killed while saving, not stopped by an error
        outcomes.append(_which(folder, old, new))  # never a mixture (raises otherwise)
    assert len(outcomes) == 6
    # issue 26: the staging folders killed saves leave are removed by the next save, in a process started
    # after them (one is planted, so that there is one whatever the kills left); other hidden folders stay
    planted = tmp_path / ".k0.new-deadbeef"
    planted.mkdir()
    (planted / "arrays.npz").write_bytes(b"half")
    (tmp_path / ".k0.backup").mkdir()
    (tmp_path / ".other.new-12345678").mkdir()
    long_ago = time.time() - 60  # as if killed a minute before the next process starts (the clock's 1 s grain)
    for hidden in tmp_path.glob(".*"):
        for path in [*hidden.iterdir(), hidden]:
            os.utime(path, (long_ago, long_ago))
    resave = (
        "import sys, pickle\nfrom spcotmhp.persistence.io import save_model\n"
        "old, _ = pickle.load(open(sys.argv[1], 'rb'))\nfor f in sys.argv[2:]: save_model(old, f, overwrite=True)"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    command = [sys.executable, "-W", "ignore", "-c", resave, str(blob), *(str(tmp_path / f"k{i}") for i in range(6))]
    subprocess.run(command, env=env, check=True, timeout=300)
    hidden = sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("."))
    assert hidden == [".k0.backup", ".other.new-12345678"]


def test_the_previous_model_stays_while_the_new_one_is_written(old_and_new, tmp_path, monkeypatch):
    old, new = old_and_new
    folder = save_model(old, tmp_path / "m")
    swap = safe_write.swap_folder

    def check_then_swap(staging, target):
        assert _which(target, old, new) == "old"  # still whole just before the swap
        swap(staging, target)

    monkeypatch.setattr(safe_write, "swap_folder", check_then_swap)
    save_model(new, folder, overwrite=True)
    assert _which(folder, old, new) == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m"]  # no staging or old folder left


def test_save_never_replaces_a_folder_that_is_not_a_model(old_and_new, tmp_path):
    folder = tmp_path / "data"
    folder.mkdir()
    (folder / "teaching.csv").write_text("event,x,y,words_en\n")
    with pytest.raises(ModelError, match=r"the folder holds files that are not a model's \(teaching.csv\)"):
        save_model(old_and_new[0], folder)
    assert sorted(p.name for p in folder.iterdir()) == ["teaching.csv"]
    model = save_model(old_and_new[0], tmp_path / "m")
    with pytest.raises(ModelError, match=r"already holds a model; give --overwrite"):
        save_model(old_and_new[1], model)  # overwrite=False by default, as the CLI
