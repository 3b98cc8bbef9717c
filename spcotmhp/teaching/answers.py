"""Answers to the robot's questions: how a teach given in reply to a question enters the model (issue 24).

The paper has no questions: every teach is an event of the robot's walk, drawn from its place's Gaussian, with a
psi transition from the event before it (Eqs. 3-9). Taught that way, answers do not split a place the learner
merged (docs/teaching.md, "Why answers do not fix these homes"): the answers at the two halves of a merged place
are events of the stream, so the hops between them count as transitions the robot never made against the split,
and single-site steps cannot move a room's events at once.

The departures, each for answers only (an event marked ``TeachingEvent.answer``); everything else, batch learning
and online learning of what the robot records, is the paper's model:

* ``alone``: an answer is a segment of its own, with no psi transition into or out of it (the events before and
  after it are linked as if it were not there). Reason: the robot did not walk to the spot because of the place it
  was in; it went there to ask, and the person's reply is not a step of its walk.
* ``weight``: an answer enters every count as ``weight`` events (its position, its name, its place and concept
  counts) and its conditional to that power. Reason: a reply to a question is said on purpose, about the spot the
  robot stands on, where an overheard utterance may be about somewhere else; ``weight`` is how many overheard
  teaches one answer is worth.
* ``split``: after an answer, a block move splits the answer's place in two (and its concept with it when the two
  are one room), the answer in one half and the place's event farthest from it in the other, the rest allocated
  by the collapsed conditional (``online_split_merge.allocate``), and the split is kept when the collapsed joint
  (``online_split_merge.log_target``, with the two departures above in its counts) is higher: the mode of the two,
  as ``online_split_merge.settle_name``. Reason: a question is asked where the model is unsure, and single-site
  steps cannot move a room's events at once.

``ANSWER_MODELS`` names the combinations measured; ``DEFAULT_ANSWERS`` is the one chosen (docs/teaching.md: on
which homes, and the paper's variant beside it); ``"paper"`` learns an answer as any teach.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spcotmhp.errors import TeachingError
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.online_split_merge import _label, _member, _pure, _restore, _save, allocate, log_target

SPLIT_TRIES = 4
DEBUG = False
"""Allocations drawn per kind of split; the best is compared with the merge (a few: each costs one conditional
per event of the place)."""


@dataclass(frozen=True)
class AnswerModel:
    """How answers enter the model (module docstring)."""

    alone: bool = False
    weight: float = 1.0
    split: bool = False

    def learner_settings(self) -> dict:
        """Keyword settings of ``OnlineSpCoTMHP`` for this answer model."""
        return {
            "answer_alone": self.alone,
            "answer_weight": self.weight,
            "after_answer": split_at_answer if self.split else None,
        }


ANSWER_MODELS = {
    "paper": AnswerModel(),
    "alone": AnswerModel(alone=True),
    "split": AnswerModel(split=True),
    "alone+split": AnswerModel(alone=True, split=True),
    "alone+split+w3": AnswerModel(alone=True, weight=3.0, split=True),
    "alone+split+w10": AnswerModel(alone=True, weight=10.0, split=True),
}
DEFAULT_ANSWERS = "paper"


def answer_model(name: str | None) -> AnswerModel:
    """The answer model called ``name`` (None: the default); TeachingError naming the accepted ones otherwise."""
    name = DEFAULT_ANSWERS if name is None else name
    if name not in ANSWER_MODELS:
        raise TeachingError(f"answers must be one of {', '.join(ANSWER_MODELS)}, got {name!r}")
    return ANSWER_MODELS[name]


def split_at_answer(st: CollapsedState, e: int, rng: np.random.Generator) -> bool:
    """The ``split`` block move at answer e (module docstring); returns whether the place was split."""
    kept = False
    for kind in ("both", "place"):
        label = _label(st, kind, e)
        if kind == "both" and not _pure(st, label):
            continue
        members = np.flatnonzero(_member(st, kind, label))
        empties = [np.flatnonzero(st.n_k <= 0)] + ([np.flatnonzero(st.n_l <= 0)] if kind == "both" else [])
        if len(members) < 4 or not all(len(x) for x in empties):
            continue
        far = members[np.argmax(np.linalg.norm(st.X[members] - st.X[e], axis=1))]
        rest = np.array([j for j in members if j != e and j != far], dtype=np.int64)
        near = np.minimum(*(np.linalg.norm(st.X[rest] - st.X[x], axis=1) for x in (e, far)))
        order = rest[np.argsort(near, kind="stable")]
        new = int(empties[0][0]) if kind == "place" else (int(empties[0][0]), int(empties[1][0]))
        saved, best, best_state = _save(st), log_target(st), None
        for _ in range(SPLIT_TRIES):
            allocate(st, kind, e, int(far), new, order, rng)
            score = log_target(st)
            if score > best:
                best, best_state = score, _save(st)
            _restore(st, saved)
            if DEBUG:
                print(f"    {kind} try: {score - log_target(st):.1f}")
        if best_state is not None:
            _restore(st, best_state)
            kept = True
            break
    return kept
