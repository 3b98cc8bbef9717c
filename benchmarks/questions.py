"""Questions where the map is unsure (issue 24): does answering them fix the homes where the learner merges places?

For each home: learn it without labels (the battery's learned parameters, ``evaluation.context.build_context``),
score the battery's tasks (advanced WN-SPL via, ``evaluation.battery.evaluate_home``), then ask the model's best
question (``teaching.questions.questions``), answer it from the truth (the true name of the teaching event nearest
the asked point, as "this is the NAME"; on albert-b, whose names are its own hiragana words, the word as a naming
event), teach it (``teaching.teach.teach``), and score again,
up to ``--questions`` answers, stopping once the home reaches ``--target``. Homes: the battery's seeds (only those
below the target before any question count toward the acceptance; ``--all`` reports the others too) and,
with ``--albert``, albert-b. Prints one line per home and a table (JSON with ``--json``).

    python benchmarks/questions.py --seeds 0-49 --questions 3
    python benchmarks/questions.py --seeds 0-199 --albert --json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _args import parse_seeds  # noqa: E402


def answer(data, x: float, y: float) -> str:
    """The true name at (x, y): that of the true place of the teaching event nearest it (a dataset without place
    names, albert-b: the word said most often in that place's events, grammar words left out)."""
    from collections import Counter

    from spcotmhp.planning.vocabulary import FUNCTION_WORDS

    j = int(np.argmin(np.hypot(data.positions[:, 0] - x, data.positions[:, 1] - y)))
    place = int(data.truth_place[j])
    if data.place_names is not None:
        return str(data.place_names[place])
    said = Counter(
        w for e in np.flatnonzero(data.truth_place == place) for w in data.tokens[e] if w not in FUNCTION_WORDS
    )
    return said.most_common(1)[0][0]


def learned(data, params: str = "learned", cache: str | None = None):
    """(the model learned without labels, its advanced WN-SPL via): from ``cache``/<home> when that folder holds
    them (written by an earlier run: the learned model does not depend on how answers are taught), else learned
    and scored (and written there when ``cache`` is given)."""

    from spcotmhp.evaluation.battery import evaluate_home
    from spcotmhp.evaluation.context import build_context
    from spcotmhp.persistence.io import load_model, save_model

    folder = None if cache is None else Path(cache) / data.name
    if folder is not None and (folder / "before.json").is_file():
        return load_model(folder / "model"), json.loads((folder / "before.json").read_text())["before"]
    model = build_context(data, params, 0).model
    before = evaluate_home(data, params, 0, model=model).wn_spl_via
    if folder is not None:
        folder.mkdir(parents=True, exist_ok=True)
        save_model(model, folder / "model", overwrite=True)
        (folder / "before.json").write_text(json.dumps({"before": before}))
    return model, before


def run_home(
    data,
    lang: str,
    questions_max: int,
    target: float,
    params: str = "learned",
    cache: str | None = None,
    answers: str = "paper",
) -> dict:
    from spcotmhp.evaluation.battery import evaluate_home
    from spcotmhp.learning.online import TeachingEvent
    from spcotmhp.teaching.answers import attach_walk
    from spcotmhp.teaching.questions import questions
    from spcotmhp.teaching.teach import teach

    t0 = time.perf_counter()
    model, before = learned(data, params, cache)
    attach_walk(model, data.trajectory)
    row = {"home": data.name, "before": before, "after": before, "asked": 0, "answers": []}
    for _ in range(questions_max):
        if row["after"] >= target:
            break
        asked = questions(model, 1, answers=answers)
        if not asked:
            break
        q = asked[0]
        name = answer(data, q["x"], q["y"])
        if lang == "ja":  # albert-b's names are its own words (hiragana, which janome may cut): taught as that word
            event: object = TeachingEvent(q["x"], q["y"], (name,), named=True, answer=True)
        else:
            event = {"x": q["x"], "y": q["y"], "utterance": f"this is the {name}", "answer": True}
        model = teach(model, [event], answers=answers).model
        row["asked"] += 1
        row["answers"].append({"x": q["x"], "y": q["y"], "candidates": q["candidates"], "answer": name})
        row["after"] = evaluate_home(data, params, 0, model=model).wn_spl_via
    row["seconds"] = round(time.perf_counter() - t0, 1)
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="0-49", help="battery seeds, e.g. 0-49 or 7,21,42")
    ap.add_argument("--questions", type=int, default=3)
    ap.add_argument("--target", type=float, default=0.93)
    ap.add_argument("--albert", action="store_true", help="also albert-b (Japanese)")
    ap.add_argument("--all", action="store_true", help="ask on homes already at the target too")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--cache", help="folder of learned models and their scores before any question (reused)")
    ap.add_argument("--only-learn", action="store_true", help="fill --cache and stop (no question asked)")
    ap.add_argument("--answers", default="paper", help="how answers enter the model (online.ANSWER_MODELS)")
    args = ap.parse_args()
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.datasets.synthetic_battery import battery_home

    homes = [(battery_home(s), "en") for s in parse_seeds(args.seeds)]
    if args.albert:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            homes.append((load_bundled("albert-b", lang="ja"), "ja"))
    rows = []
    for data, lang in homes:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if args.only_learn:
                learned(data, cache=args.cache)
                continue
            row = run_home(data, lang, args.questions, args.target, cache=args.cache, answers=args.answers)
        row["failing"] = row["before"] < args.target
        rows.append(row)
        if not args.json:
            print(
                f"{row['home']:24s} via {row['before']:.3f} -> {row['after']:.3f} after {row['asked']} question(s)"
                f"{'' if row['failing'] else ' (at the target before)'}; {row['seconds']} s",
                flush=True,
            )
    failing = [r for r in rows if r["failing"]]
    summary = {
        "homes": len(rows),
        "failing_before": len(failing),
        "failing_fixed": sum(r["after"] >= args.target for r in failing),
        "lower_after": sum(r["after"] < r["before"] - 1e-9 for r in rows),
        "questions_used": [r["asked"] for r in failing],
    }
    if args.json:
        print(json.dumps({"rows": rows, "summary": summary}, indent=1))
    else:
        print(json.dumps(summary))


if __name__ == "__main__":
    main()
