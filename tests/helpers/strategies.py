"""Hypothesis strategies of hostile values behind valid files (issue 26), for tests/test_safe_read_fuzz.py:

* ``model_edits()``: changes to a model folder that its checksum cannot judge: a hyper-parameter, cost map
  setting or ``info.feature_weight`` set to a hostile number or JSON value, or an array of arrays.npz scaled,
  poked or broken (an entry, a row, a covariance's symmetry), applied by :func:`apply_edits` (which reseals the
  manifest, so the value checks are what is tested).
* ``learner_edits()``: changes to a learner state (learner.npz) behind a valid checksum: a count scaled,
  zeroed or poked, a scatter or position set to a hostile number (:func:`apply_learner_edits`, resealed).
* ``pnm_files()``: PGM/PPM/PBM files with hostile headers: magic numbers, sizes (0, huge, long strips),
  comments up to past the header bound, separators, maxvals, and bodies short, exact or missing.
"""

from __future__ import annotations

import json
from dataclasses import fields
from pathlib import Path

import numpy as np
from hypothesis import strategies as st

from spcotmhp.learning.model import Hyperparameters
from spcotmhp.metric.costmap import CostMapSettings
from tests.helpers.learning import reseal

EDGES = [0.0, -0.0, -1.0, 4.9e-324, 1e-320, 1e-300, 1e-13, 1e-12, 1e-10, 1e-6, 0.5, 1.0, 1e6, 1e12, 1e13, 1e300]
EDGES += [1e308, -1e308, 1e5, 1e-3, 1e4]
HOSTILE_NUMBERS = st.sampled_from(EDGES) | st.floats(allow_nan=True, allow_infinity=True)
HOSTILE_JSON = st.sampled_from([None, True, False, "1", "abc", [], {}, [1.0, 2.0], [[1.0, 0.0], [0.0, 1.0]]])
HOSTILE_INTS = st.sampled_from([0, -1, 1, 2, 10**4, 10**4 + 1, 10**20, 2**63])
VALUES = HOSTILE_NUMBERS | HOSTILE_JSON | HOSTILE_INTS
# the values of issue 26 and their kin, for the random corpus (hardening_corpus.model_case)
ISSUE_26_VALUES = [
    ("hyper", "place_size", 1e308),
    ("hyper", "kappa0", 1e300),
    ("hyper", "alpha", 1e-300),
    ("hyper", "V0", [[1e-300, 0.0], [0.0, 1e-300]]),
    ("array", "Sigma", "scale", 1e-300),
    ("array", "Sigma", "scale", 1e150),
    ("array", "psi", "zero-column", 0.0),
    ("array", "phi", "row", 1e308),
    ("costmap", "inflation_radius", 1e308),
]
ARRAYS = ("mu", "Sigma", "psi", "pi", "phi", "W")
# words a vocabulary must not hold (empty, spaces around, control characters), and a few it may
WORDS = st.sampled_from(
    ["", " ", "\n", "kitchen ", " kitchen", "a\x00b", "tab\there", "x" * 257, "東京", "living room"]
)
ARRAY_OPS = ("scale", "entry", "row", "asymmetric", "zero-column")


@st.composite
def model_edits(draw) -> list[tuple]:
    """One to three edits: ("hyper" | "costmap" | "info", key, value) or ("array", name, op, number)."""
    edits = []
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["hyper", "hyper", "costmap", "info", "vocabulary", "array", "array", "array"]))
        if kind == "vocabulary":
            edits.append(("vocabulary", draw(st.integers(0, 3)), draw(WORDS)))
        elif kind == "hyper":
            edits.append(("hyper", draw(st.sampled_from([f.name for f in fields(Hyperparameters)])), draw(VALUES)))
        elif kind == "costmap":
            edits.append(("costmap", draw(st.sampled_from([f.name for f in fields(CostMapSettings)])), draw(VALUES)))
        elif kind == "info":
            edits.append(("info", "feature_weight", draw(VALUES)))
        else:
            edits.append(
                ("array", draw(st.sampled_from(ARRAYS)), draw(st.sampled_from(ARRAY_OPS)), draw(HOSTILE_NUMBERS))
            )
    return edits


def _edit_array(a: np.ndarray, op: str, x: float) -> np.ndarray:
    a = a.astype(float).copy()
    with np.errstate(all="ignore"):
        if op == "scale":
            a = a * x
        elif op == "entry":
            a.reshape(-1)[a.size // 2] = x
        elif op == "row":
            a[0] = x
        elif op == "asymmetric" and a.ndim == 3:
            a[0, 0, 1] += x
        elif op == "zero-column" and a.ndim == 2:
            a[:, 0] = 0.0
        else:
            a.reshape(-1)[0] = x
    return a


def apply_edits(folder: Path, edits: list[tuple]) -> str:
    """Apply ``edits`` (``model_edits``) to the model folder ``folder``, reseal its manifest; a short label."""
    meta = json.loads((folder / "model.json").read_text(encoding="utf-8"))
    with np.load(folder / "arrays.npz") as npz:
        arrays = {k: npz[k] for k in npz.files}
    for edit in edits:
        if edit[0] == "array":
            _, name, op, x = edit
            arrays[name] = _edit_array(arrays[name], op, x)
        elif edit[0] == "vocabulary":
            meta["vocabulary"][edit[1] % len(meta["vocabulary"])] = edit[2]
        else:
            meta[edit[0]][edit[1]] = edit[2]
    (folder / "model.json").write_text(json.dumps(meta), encoding="utf-8")  # NaN / Infinity as JSON writes them
    np.savez(folder / "arrays.npz", **arrays)
    reseal(folder)
    return "; ".join(" ".join(str(v)[:24] for v in edit) for edit in edits)


LEARNER_ARRAYS = ("n_k", "sx", "sxx", "n_l", "n_lk", "W_lv", "bg_v", "z_tot", "trans", "X")


@st.composite
def learner_edits(draw) -> list[tuple]:
    """One to three (array of learner.npz, op of ``_edit_array`` or "zero", number) edits."""
    ops = st.sampled_from(ARRAY_OPS + ("zero",))
    return [
        (draw(st.sampled_from(LEARNER_ARRAYS)), draw(ops), draw(HOSTILE_NUMBERS))
        for _ in range(draw(st.integers(1, 3)))
    ]


def apply_learner_edits(folder: Path, edits: list[tuple]) -> str:
    """Apply ``edits`` (``learner_edits``) to learner.npz of ``folder``, reseal its manifest; a short label."""
    with np.load(folder / "learner.npz") as npz:
        arrays = {k: npz[k] for k in npz.files}
    for name, op, x in edits:
        arrays[name] = np.zeros_like(arrays[name], dtype=float) if op == "zero" else _edit_array(arrays[name], op, x)
    np.savez(folder / "learner.npz", **arrays)
    reseal(folder)
    return "; ".join(" ".join(str(v)[:24] for v in edit) for edit in edits)


SIDES = st.sampled_from([0, 1, 2, 3, 17, 1000, 1001, 2000, 4000, 16_000_000, 10**9, 10**12]) | st.integers(0, 60)


@st.composite
def pnm_files(draw) -> bytes:
    """A PGM/PPM/PBM file with a hostile header (module docstring)."""
    magic = draw(st.sampled_from([b"P1", b"P2", b"P3", b"P4", b"P5", b"P6", b"Pf", b"P7", b"P0CMYK", b"PyP", b"P"]))
    width, height = draw(SIDES), draw(SIDES)
    sep = draw(st.sampled_from([b"\n", b" ", b"\t", b"\r\n", b"\r", b"\x0b", b"  \n "]))
    length = draw(st.sampled_from([0, 1, 40, 65_000, 65_530, 65_536, 65_540, 70_000, 2_000_000]))
    where = draw(st.sampled_from(["magic", "width", "height", "maxval", "none"]))
    ending = draw(st.sampled_from([b"\n", b"\r", b""]))
    comment = b"#" + b"c" * max(length - 1, 0) + ending if length else b""
    maxval = draw(st.sampled_from([b"255", b"65535", b"1", b"0", b"70000", b"-1", b"x"]))
    parts = [magic, str(width).encode(), str(height).encode(), maxval]
    fields_ = {"magic": 1, "width": 2, "height": 3, "maxval": 4}
    if where in fields_:
        parts.insert(fields_[where], comment)
    header = sep.join(parts) + sep
    pixels = width * height
    body_kind = draw(st.sampled_from(["exact", "short", "none", "double"]))
    if pixels > 200_000 or body_kind == "none":
        body = b""
    else:
        n = {"exact": pixels, "short": pixels // 2, "double": 2 * pixels}[body_kind]
        body = bytes([draw(st.sampled_from([0, 205, 254, 255]))]) * n
    return header + body


def document_paths(node: object, prefix: tuple = ()):
    """Every path (a tuple of keys and indices) to a value of a JSON/YAML document, the root's () first."""
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from document_paths(v, (*prefix, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from document_paths(v, (*prefix, i))
