"""The frozen blind corpora (tests/data/blind*/): sentences by writers who read nothing of the project, committed
before the changes they were measured on and never edited (issue 34; docs/instructions.md gives each corpus's
first-sight figure). Kept as regression: no sentence is read otherwise than labelled except the label disagreements
each corpus's disagreements.csv states with its reason, and at least as many are read as labelled as when this
test was written (the floors only ever go up). Rows whose label a later issue's rule changed are read from
relabelled.csv (tests/helpers/corpus.py)."""

from __future__ import annotations

from collections import Counter

import pytest

from tests.helpers.corpus import DATA, corpus_rows, rows, verdict

FLOORS = {
    "blind": 308, "blind2": 376, "blind3": 287, "blind4": 268, "blind5": 240, "blind6": 186, "blind7": 181,
    "blind8": 238, "blind9": 256, "blind10": 176, "blind11": 159, "blind12": 266, "blind13": 264, "blind14": 182,
    "blind15": 179, "blind16": 284, "blind17": 288, "blind18": 193, "blind19": 196, "blind20": 271, "blind21": 279,
    "blind22": 184, "blind23": 182, "blind24": 283, "blind25": 249, "blind26": 188, "blind27": 183, "blind28": 284,
    "blind29": 281, "blind31": 190, "blind30": 161, "blind32": 259, "blind33": 266, "blind34": 185, "blind35": 177,
    "blind36": 261, "blind37": 273, "blind38": 165, "blind39": 177, "blind40": 234,
    "blind41": 239, "blind42": 128, "blind43": 169, "blind44": 253, "blind45": 261, "blind46": 169, "blind47": 151,
    "blind48": 249, "blind49": 230, "blind50": 163, "blind51": 167, "blind52": 233, "blind53": 254, "blind54": 175,
    "blind55": 169, "blind56": 255, "blind57": 256, "blind58": 156,
    "blind59": 152,
}  # fmt: skip
"""Sentences read as labelled at the commit that wrote this test (English and Japanese together)."""


def _disagreements(corpus: str) -> set[str]:
    path = DATA / corpus / "disagreements.csv"
    return {r["text"] for r in rows(path)} if path.exists() else set()


@pytest.fixture(scope="module", params=sorted(FLOORS))
def measured(request) -> tuple[str, list[tuple[dict, str, str]]]:
    corpus = request.param
    return corpus, [(row, *verdict(row)) for row in corpus_rows(DATA / corpus)]


def test_nothing_is_silently_misread_but_the_stated_disagreements(measured):
    corpus, verdicts = measured
    wrong = {row["text"] for row, kind, _ in verdicts if kind == "wrong"}
    assert wrong <= _disagreements(corpus), sorted(wrong - _disagreements(corpus))


def test_no_fewer_read_as_labelled_than_before(measured):
    corpus, verdicts = measured
    counts = Counter(kind for _, kind, _ in verdicts)
    assert counts["right"] >= FLOORS[corpus], counts
