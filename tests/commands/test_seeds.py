"""Every --seed option takes only non-negative integers (numpy rejects negative seeds with a traceback), and the
seeding helpers of the library raise clear errors for them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.datasets.synthetic_plan import seeded_rng
from spcotmhp.errors import DatasetError, ModelError
from spcotmhp.learning.gibbs import make_rng


@pytest.mark.parametrize(
    "args",
    [
        ["learn", "3LDK_01", "--out", "unused", "--seed", "-1"],
        ["evaluate-learning", "albert-b", "--seed", "-5"],
        ["synth", "flat", "--out", "unused", "--seed", "-1"],
        ["evaluate", "3LDK_01", "--seed", "-1"],
        ["demo", "--seed", "-1"],
        ["plan", "unused-model", "go to the kitchen", "--start", "0", "0", "--seed", "-1"],
    ],
)
def test_negative_seed_is_a_usage_error(args):
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 2, res.output
    assert "Invalid value for '--seed'" in res.output and "greater than or equal to 0" in res.output
    assert res.exception is None or isinstance(res.exception, SystemExit)


@pytest.mark.parametrize("seed", [-1, 1.5, "3", True])
def test_make_rng_rejects_bad_seeds(seed):
    with pytest.raises(ModelError, match=r"seed must be a non-negative integer \(or a numpy SeedSequence\), got "):
        make_rng(seed)


def test_make_rng_rejects_a_negative_run_and_accepts_numpy_integers():
    with pytest.raises(ModelError, match="run must be a non-negative integer or None, got -2"):
        make_rng(0, run=-2)
    assert make_rng(np.int64(3), run=np.int32(1)).random() == make_rng(3, run=1).random()


@pytest.mark.parametrize("seed", [-1, 2.0, None])
def test_synthetic_seed_errors(seed):
    with pytest.raises(DatasetError, match=r"seed must be a non-negative integer or a numpy Generator, got "):
        generate_environment("flat", seed=seed)
    with pytest.raises(DatasetError, match="seed must be a non-negative integer"):
        seeded_rng(seed)


@pytest.mark.parametrize(
    "args, option",
    [
        (["learn", "3LDK_06", "--out", "unused", "--runs", "1000000000"], "--runs"),
        (["learn", "3LDK_06", "--out", "unused", "--max-places", "100000000"], "--max-places"),
        (["learn", "3LDK_06", "--out", "unused", "--max-concepts", "100000000"], "--max-concepts"),
        (["learn", "3LDK_06", "--out", "unused", "--iterations", "1000000000"], "--iterations"),
        (["learn", "3LDK_06", "--out", "unused", "--jobs", "100000"], "--jobs"),
        (["evaluate-learning", "albert-b", "--seeds", "100000"], "--seeds"),
        (["evaluate", "3LDK_01", "--seeds", "100000"], "--seeds"),
        (["evaluate", "3LDK_01", "--workers", "100000"], "--workers"),
        (["demo", "--runs", "1000000000"], "--runs"),
        (["synth", "office", "--out", "unused", "--rooms", "100000"], "--rooms"),
        (
            ["plan", "unused-model", "go", "--start", "0", "0", "--candidates", "10000000"],
            "--candidates",
        ),
        (
            ["plan", "unused-model", "go", "--start", "0", "0", "--max-steps", "1000000000"],
            "--max-steps",
        ),
    ],
)
def test_counts_have_upper_bounds(args, option):
    """Audit items 4 and 5: every count option has an upper bound (spcotmhp/limits.py), refused as a usage
    error before anything is loaded or allocated."""
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 2, res.output
    assert f"Invalid value for '{option}'" in res.output and "less than or equal to" in res.output
    assert not Path("unused").exists()
