"""Labelled instruction corpora (tests/data/instruction_corpus.csv, tests/data/heldout/instructions.csv): their
vocabularies, how a row's expected reading is written, and how an instruction is read against it.

A reading is written as (goal, waypoints in order joined by ">", avoid joined by ";", not_goal joined by ";", speed,
waits joined by ";"): a place as its words, with a relation in braces (``bedroom{closest:bath}``,
``bedroom{between:kitchen+bath}``, ``bedroom{largest}``), an instance number after "#" (``bedroom#2``); a wait as
the place, with "@seconds" when it has a length. A phrase naming every place of a name ("both corridors") is
written as those places' names, and a phrase whose words name places of one name as that name ("alice's" as
"alice's room"). Place phrases
are checked against the places' names as the planner checks them (:func:`spcotmhp.planning.places.by_label`), with
the union of the bundled homes' names standing for one home's.
"""

from __future__ import annotations

import csv
import unicodedata
import warnings
from functools import cache
from pathlib import Path

import numpy as np

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.errors import ConflictingInstruction, InstructionError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning.instructions import Instruction, PlaceQuery, parse_text
from spcotmhp.planning.places import LabelIndex, by_label
from spcotmhp.planning.vocabulary import one_floor, place_labels, place_vocabulary

DATA = Path(__file__).parents[1] / "data"
HOMES = ("3LDK_01", "3LDK_05", "3LDK_06")
SYNTHETIC = ["east corridor", "south corridor", "alice's room", "bob's room", "kitchen"]
REPEATED = ("bedroom", "寝室")
"""The names several places of the corpora's homes share (the 3LDK homes' three bedrooms)."""


def rows(path: Path) -> list[dict]:
    with path.open(encoding="utf-8", newline="") as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def understood_heldout(vocabulary: str, words: list[str], lang: str) -> list[str]:
    """The held-out sentences of ``vocabulary`` that are labelled understood and that the reader reads (for
    property tests that insert words into understood sentences)."""
    from spcotmhp.language.reading import read as read_language

    out = []
    for row in rows(DATA / "heldout" / "instructions.csv"):
        if row["vocabulary"] == vocabulary and not row["refused"]:
            try:
                read_language(row["text"], words, lang)
            except InstructionError:
                continue
            out.append(row["text"])
    return out


def corpus_rows(folder: Path) -> list[dict]:
    """The rows of a frozen corpus (``folder/instructions.csv``), each row that ``folder/relabelled.csv`` holds (by
    its vocabulary and text) replaced by that file's row, marked ``relabelled``: a label an issue's later rule
    changed, the frozen row left as written."""
    path = folder / "relabelled.csv"
    relabelled = {(r["vocabulary"], r["text"]): r for r in rows(path)} if path.exists() else {}
    return [{**relabelled[key], "relabelled": "yes"} if (key := (r["vocabulary"], r["text"])) in relabelled else r
            for r in rows(folder / "instructions.csv")]  # fmt: skip


def synthetic_model() -> SpatialConceptModel:
    """Five places taught as "this is the <name>": east corridor, south corridor, alice's room, bob's room,
    kitchen (one concept each)."""
    vocab = sorted({"this", "is", "the", *(w for n in SYNTHETIC for w in n.split())})
    counts = np.zeros((len(SYNTHETIC), len(vocab)))
    for k, name in enumerate(SYNTHETIC):
        for w in ["this", "is", "the", *name.split()]:
            counts[k, vocab.index(w)] = 10
    W = (counts + 0.1) / (counts + 0.1).sum(axis=1, keepdims=True)
    K = len(SYNTHETIC)
    return SpatialConceptModel(
        mu=np.arange(2 * K, dtype=float).reshape(K, 2),
        Sigma=np.tile(np.eye(2), (K, 1, 1)),
        psi=np.full((K, K), 1 / K),
        pi=np.full(K, 1 / K),
        phi=(np.eye(K) * 15 + 0.1) / (15 + 0.1 * K),
        W=W,
        vocabulary=vocab,
    )


@cache
def vocabulary(name: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(place words, place names) of a corpus vocabulary: the bundled 3LDK homes' (union over the three,
    supervised fits) in a language, or the synthetic home's."""
    if name == "synthetic_en":
        model = synthetic_model()
        words = place_vocabulary(model)
        return tuple(words), tuple(place_labels(model, words))
    lang = name.rsplit("_", 1)[1]
    words: set[str] = set()
    names: set[str] = set()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for home in HOMES:
            model = fit_supervised(load_bundled(home, lang=lang))
            home_words = place_vocabulary(model)
            words |= set(home_words)
            names |= set(place_labels(model, home_words))
    return tuple(sorted(words)), tuple(sorted(names))


def read(text: str, name: str) -> Instruction:
    """``text`` read against vocabulary ``name``, its place phrases checked against the names."""
    words, names = vocabulary(name)
    ins = one_floor(parse_text(text, words))  # as the planner: the homes are one floor each
    index = LabelIndex(names)
    stages = [(q, by_label(index, q, stage=True)) for q in ins.stages]
    avoided = [(q, by_label(index, q)) for q in ins.avoid]
    excluded = [(q, by_label(index, q)) for q in ins.not_goal]
    # as the planner refuses a stage all of whose places are avoided, or a goal all of whose places are excluded
    # (ConflictingInstruction), for the same place said the same way (a relation may pick another instance)
    for q, named in stages:
        for a, gone in avoided:
            same = a.relation == q.relation and a.number == q.number  # "avoid bedroom 3, go to bedroom 1": no conflict
            if same and named.any() and not (named & ~gone).any():
                raise ConflictingInstruction(f"every place named '{q.label}' is also to be avoided")
    goal, named = stages[-1]
    for a, gone in excluded:
        same = a.relation == goal.relation and a.number == goal.number
        if same and named.any() and not (named & ~gone).any():
            raise ConflictingInstruction(f"every place named '{goal.label}' is one not to end in")
    return ins


def written(ins: Instruction, name: str) -> tuple[str, ...]:
    """An instruction written as a corpus row writes its reading (module docstring)."""
    index = LabelIndex(vocabulary(name)[1])

    def place(q: PlaceQuery) -> list[str]:
        named = sorted({index.labels[k] for k in np.flatnonzero(by_label(index, q))})
        if q.every:
            return named
        # the name the words stand for when they name places of one name ("alice's" is "alice's room")
        said = [w for w, c in q.words.items() for _ in range(int(c))]
        text = named[0] if len(named) == 1 and sorted(named[0].split()) != sorted(said) else " ".join(said)
        # "bedroom 2": the plan's "bedroom #2"; in the corpora's homes only the bedrooms repeat, so "the south one"
        # (a number 1 said of a name with one place) is that place
        repeated = any(n.split()[0] in REPEATED for n in named)
        text += "" if q.number is None or (q.number == 1 and not repeated) else f"#{q.number}"
        if q.relation is not None:
            args = "+".join(" ".join(a.words) for a in q.relation.args)
            text += "{" + q.relation.kind + (f":{args}" if args else "") + "}"
        return [text]

    stages = [p for q in ins.stages for p in place(q)]
    waits = [stages[s] + ("" if seconds is None else f"@{seconds:g}") for s, seconds in ins.waits]
    return (
        stages[-1],
        ">".join(stages[:-1]),
        ";".join(p for q in ins.avoid for p in place(q)),
        ";".join(p for q in ins.not_goal for p in place(q)),
        ins.speed or "",
        ";".join(waits),
    )


def expected(row: dict) -> tuple[str, ...]:
    """A row's expected reading, in the order of :func:`written` (missing columns read as empty). Notations of the
    corpora's writers read as :func:`written` writes them: avoided places and places not to end in joined by
    commas (the old corpus) or ">" (blind3) are a set joined by ";"; a wait "place@" (blind3: until told) is
    "place", several joined by ">" are joined by ";"."""
    out = []
    for key in ("goal", "waypoints", "avoid", "not_goal", "speed", "wait"):
        value = row.get(key) or ""
        if key in ("avoid", "not_goal"):
            value = value.replace(",", ";").replace(">", ";")
        elif key == "wait":
            value = ";".join(w.removesuffix("@") for w in value.replace(">", ";").split(";")) if value else ""
        out.append(value)
    return tuple(" ".join(x.split()) for x in out)


def normalised(text: str) -> str:
    """Width-folded and case-folded, as the readers normalise what they quote."""
    return unicodedata.normalize("NFKC", text).casefold()


def verdict(row: dict) -> tuple[str, str]:
    """A corpus row read as its label says ("right"), refused although the label reads it, or refused naming
    another word than the label's ("refused"), or read otherwise than labelled, or read where the label refuses
    ("wrong"); with what came out. A refusal is right only when it names the word the label names (compared
    width- and case-folded)."""
    try:
        got = written(read(row["text"], row["vocabulary"]), row["vocabulary"])
    except (InstructionError, ConflictingInstruction) as exc:
        if not row["refused"]:
            return "refused", f"{type(exc).__name__}: {exc}"
        named = not row["names"] or normalised(row["names"]) in normalised(str(exc))
        return ("right" if named else "refused"), str(exc)
    if row["refused"]:
        return "wrong", f"read {got}, but the label refuses"
    return ("right" if got == expected(row) else "wrong"), f"read {got}, labelled {expected(row)}"
