"""Why answers did not fix homes whose word switches collapsed, and what the concept moves do without any answer
(issue 24, docs/teaching.md "Concepts looked at again at an answer").

For each generated home (``synthetic_battery.battery_home``, learned without labels with the battery's learned
parameters, as ``benchmarks/questions.py``; ``--cache`` reuses its folders): the share of tokens that are concept
tokens, and the collapsed log target (``online_split_merge.log_target``, switches at their mode) of the true
concepts with the grammar words in the background, the learned places kept, minus that of the learned state. With
``--evaluate``: advanced WN-SPL via before and after the default answer model's concept moves
(``answers.concepts_from_places`` then ``answers.own_concepts``) applied with no answer at all.

    python benchmarks/concepts_why.py --seeds 52,124,131,197 --cache DIR --evaluate
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _args import parse_seeds  # noqa: E402
from questions import learned  # noqa: E402


def _assign(st, place: np.ndarray, concept: np.ndarray, concept_words: np.ndarray | None = None) -> None:
    """Put every event of ``st`` at (place, concept); with ``concept_words`` (per vocabulary word) its switches
    start there; then the switches at their mode."""
    for e in range(st.E):
        st.move(e, -1.0)
    for e in range(st.E):
        if concept_words is not None:
            st.z[e][:] = concept_words[st.tokens[e]]
        st.place[e], st.concept[e] = place[e], concept[e]
        st.move(e, 1.0)
    st.switch_mode()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="52,124,131,197")
    ap.add_argument("--cache", help="folder of learned models (benchmarks/questions.py --cache)")
    ap.add_argument("--evaluate", action="store_true", help="WN-SPL via after the concept moves, no answer")
    args = ap.parse_args()
    from spcotmhp.datasets.synthetic_battery import battery_home
    from spcotmhp.evaluation.battery import evaluate_home
    from spcotmhp.learning.learner_state import state_of_member
    from spcotmhp.learning.online import OnlineSpCoTMHP, log_new_place_density
    from spcotmhp.learning.online_split_merge import log_target
    from spcotmhp.planning.vocabulary import FUNCTION_WORDS
    from spcotmhp.teaching.answers import answer_model, concepts_from_places, own_concepts

    for seed in parse_seeds(args.seeds):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = battery_home(seed)
            model, before = learned(data, cache=args.cache)
            st = state_of_member(model.learner, model)
            st.log_new_place = log_new_place_density(model.map)
            place, concept = st.place.copy(), st.concept.copy()
            _assign(st, place, concept)
            share = float(np.concatenate(st.z).mean())
            learned_score = log_target(st)
            names = sorted(set(data.place_names))
            truth = np.array([names.index(data.place_names[data.truth_place[e]]) for e in range(st.E)])
            _assign(st, place, truth, np.array([w not in FUNCTION_WORDS for w in model.vocabulary]))
            line = (
                f"{data.name:14s} concept tokens {share:.2f}; true concepts, grammar words in the background, "
                f"minus learned: {log_target(st) - learned_score:+.1f} nats"
            )
            if args.evaluate:
                learner = OnlineSpCoTMHP(init_model=model).partial_fit([])
                state = learner.state_
                state.words = learner.vocabulary_
                again = concepts_from_places(state, joint=answer_model(None).joint)
                own = own_concepts(state, int(np.flatnonzero(state.n_k > 0)[0]))
                after = evaluate_home(data, "learned", 0, model=learner.model_).wn_spl_via
                line += f"; WN-SPL via {before:.3f} -> {after:.3f} (concepts again: {again}, own concepts: {own})"
        print(line, flush=True)


if __name__ == "__main__":
    main()
