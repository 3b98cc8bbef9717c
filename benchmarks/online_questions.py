"""Online learning with answered questions (issue 24): does answering at most ``--questions`` of the model's own
questions bring albert-b's online learner within 0.05 NMI (C and i) of batch learning?

Per seed: albert-b's teaching events are streamed one at a time (``OnlineSpCoTMHP.partial_fit``, as
``evaluation.online_eval.evaluate_online``); then, up to ``--questions`` times, the model's best question
(``teaching.questions.questions``) is answered from the truth (the word said most often in the true place of the
teaching event nearest the asked point, as ``benchmarks/questions.py`` does) and learned by the same learner as a
naming event (its usual steps, rejuvenation and split-merge moves, follow). NMI and ARI of C and i are scored on
the dataset's own events (the answers left out) after each answer, beside batch learning
(``online_eval.evaluate_batch``, SpCoTMHP with reverse replay, one run per seed).

    python benchmarks/online_questions.py --seeds 5 --questions 5 [--no-batch]
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from questions import answer  # noqa: E402

from spcotmhp.datasets.bundled import load_bundled  # noqa: E402
from spcotmhp.evaluation.online_eval import SCORES, dataset_events, evaluate_batch  # noqa: E402
from spcotmhp.evaluation.table6 import score_run  # noqa: E402
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent  # noqa: E402
from spcotmhp.teaching.answers import answer_model, walk_poses  # noqa: E402
from spcotmhp.teaching.questions import questions  # noqa: E402


def run_seed(data, seed: int, n_questions: int, answers: str = "paper") -> list[dict]:
    """Scores after the stream and after each answer (index = answers so far); ``answers``: how answers enter
    the model (``teaching.answers.ANSWER_MODELS``)."""
    how = answer_model(answers)
    learner = OnlineSpCoTMHP(
        K=20, L=20, use_features=True, map=data.map, check_map=False, seed=seed, **how.learner_settings()
    )
    if data.trajectory is not None and how.walk:
        learner.partial_fit([])
        learner.state_.walk_X = walk_poses(data.trajectory)
    events = dataset_events(data)
    for event in events:
        learner.partial_fit([event])
    n = len(events)
    out = [score_run(data, learner.places_[:n], learner.concepts_[:n])]
    for _ in range(n_questions):
        offered = questions(learner.model_, 1, answers=answers)
        if not offered:
            break
        q = offered[0]
        said = (answer(data, q["x"], q["y"]),)
        learner.partial_fit([TeachingEvent(q["x"], q["y"], said, named=True, answer=True)])
        out.append(score_run(data, learner.places_[:n], learner.concepts_[:n]))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--questions", type=int, default=5)
    ap.add_argument("--no-batch", action="store_true")
    ap.add_argument("--answers", default="paper", help="how answers enter the model (teaching.answers)")
    args = ap.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled("albert-b", lang="ja")
        runs = [run_seed(data, s, args.questions, args.answers) for s in range(args.seeds)]
        batch = None if args.no_batch else evaluate_batch(data, args.seeds, 0, 100, 1, True, 20, 20)
    steps = max(len(r) for r in runs)
    table = []
    for a in range(steps):
        rows = [r[min(a, len(r) - 1)] for r in runs]
        table.append({k: (float(np.mean([x[k] for x in rows])), float(np.std([x[k] for x in rows]))) for k in SCORES})
    print("answers | " + " | ".join(f"{k} mean ± sd" for k in SCORES))
    for a, row in enumerate(table):
        print(f"{a} | " + " | ".join(f"{m:.3f} ± {s:.3f}" for m, s in row.values()))
    if batch is not None:
        print("batch | " + " | ".join(f"{batch[k]:.3f} ± {batch['std'][k]:.3f}" for k in SCORES))
    print(
        json.dumps(
            {"online": table, "batch": None if batch is None else {k: batch[k] for k in SCORES}, "per_seed": runs}
        )
    )


if __name__ == "__main__":
    main()
