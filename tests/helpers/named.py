"""Generated buildings whose rooms carry names of several words, numbers among them (issue 35: "aisle one", "room
101", "the second bedroom", 2号室, 東の廊下): a seeded office from :mod:`spcotmhp.datasets.synthetic` with each room
taught by its new name through teaching sentences of several frames, one concept per name."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.loader import tokenize_en, tokenize_ja
from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.supervised import fit_supervised

EN_FRAMES = ("this is the {}", "{}", "we are in {}", "this is {}", "you are in the {}")
"""English teaching sentences a name is said in (the frames naming.py reads)."""
JA_FRAMES = ("ここ は {} です", "{}", "{} だ よ")
"""Japanese ones, phrase-segmented as dataset rows are."""


def warehouse_names(names: Sequence[str]) -> list[str]:
    """The generated office's rooms renamed as a warehouse and office would call them: corridors "aisle one", "aisle
    two", ...; offices "room 101", "room 102", ...; meeting rooms "loading dock", "south corridor", "storage hall",
    "second bedroom", ...; the printer room "bay 3" (the rest keep their one-word names: two labs, a kitchen, a
    toilet). Numbers run against the places' order (the last corridor is "aisle one"), so that a number read as the
    screen's instance number ("aisle #1": the first corridor) is not the taught one by chance."""
    aisles = iter(f"aisle {w}" for w in ("one", "two", "three", "four", "five", "six", "seven", "eight"))
    rooms = iter(f"room {n}" for n in range(101, 200))
    others = iter(("loading dock", "south corridor", "storage hall", "second bedroom", "print shop", "tool crib"))
    out = list(names)
    for k in reversed(range(len(names))):
        if names[k] == "corridor":
            out[k] = next(aisles)
        elif names[k] == "office":
            out[k] = next(rooms)
    for k, name in enumerate(names):
        if name == "meeting":
            out[k] = next(others)
        elif name == "printer":
            out[k] = "bay 3"
    return out


def japanese_names(names: Sequence[str]) -> list[str]:
    """The office in Japanese: corridors 東 の 廊下, 西 の 廊下, ... (phrase-segmented), offices 2号室, 3号室, ...
    (numbered against the places' order, as :func:`warehouse_names`)."""
    sides = iter(f"{s} の 廊下" for s in ("東", "西", "南", "北", "中央", "奥", "表", "裏"))
    rooms = iter(f"{n}号室" for n in range(2, 100))
    plain = {"kitchen": "台所", "toilet": "トイレ", "lab": "実験室", "printer": "印刷室", "meeting": "会議室"}
    out = [plain.get(n, n) for n in names]
    for k in reversed(range(len(names))):
        if names[k] == "corridor":
            out[k] = next(sides)
        elif names[k] == "office":
            out[k] = next(rooms)
    return out


def named_office(
    rename: Callable[[Sequence[str]], list[str]] = warehouse_names, seed: int = 1, lang: str = "en"
) -> Dataset:
    """The seeded office with its rooms renamed by ``rename`` and every event's words those of a teaching sentence
    saying the new name (frames in turn); the truth concepts are one per name."""
    data = generate_environment("office", seed=seed)
    names = rename(list(data.place_names or []))
    frames, split = (JA_FRAMES, tokenize_ja) if lang == "ja" else (EN_FRAMES, tokenize_en)
    truth = np.asarray(data.truth_place)
    data.tokens = [split(frames[e % len(frames)].format(names[int(k)])) for e, k in enumerate(truth)]
    data.lang = lang
    data.place_names = names
    distinct = sorted(set(names))
    data.truth_concept = np.array([distinct.index(names[int(k)]) for k in truth])
    return data


def named_model(dataset: Dataset) -> SpatialConceptModel:
    """The supervised fit of ``dataset`` (its truth-count warnings silenced)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_supervised(dataset)
