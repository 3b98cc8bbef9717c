"""The research run-selection criteria (docs/experimental.md; docs/learning-model-study.md, sections 4 and 6):
scores of a fitted run that handle the background-word switches z in their own way (run_scores.py gives each
one's reason and bias), as :class:`~spcotmhp.learning.selection.RunScore` objects for ``MultiRunSelector``.

* ``"log_joint_switch_mode"``, ``"log_joint_switch_marginal"``, ``"log_joint_switch_plugin"``,
  ``"log_joint_tail_mean"``, ``"held_out_words"``: the joint with the switches at a local mode, summed out
  (Chib's estimate), summed per token at the posterior means, averaged over the last quarter of the sweeps, and
  the leave-one-out predictive of each event's words from its position.  The last draw of the switches moves a
  run's joint by tens of nats (on generated homes, resampling the switches of the true assignment lowered it by
  about 90), which is noise when runs are compared by their places and concepts.  None is the default: each
  keeps runs the log joint does not, and on the generated battery none both passes every home and keeps the
  held-out homes' figures.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from spcotmhp.errors import ModelError
from spcotmhp.experimental.run_scores import (
    held_out_words,
    switch_marginal_log_joint,
    switch_mode_log_joint,
    switch_plugin_log_joint,
    tail_mean_log_joint,
)
from spcotmhp.learning import selection
from spcotmhp.learning.gibbs import SpCoTMHP


@dataclass(frozen=True)
class NamedScore:
    """A run score with its criterion's name (``selection.RunScore``)."""

    name: str
    score: Callable[[SpCoTMHP], float]

    def __call__(self, run: SpCoTMHP, /) -> float:
        return self.score(run)


SCORES: dict[str, Callable[[SpCoTMHP], float]] = {
    "log_joint_switch_mode": switch_mode_log_joint,
    "log_joint_switch_marginal": switch_marginal_log_joint,
    "log_joint_switch_plugin": switch_plugin_log_joint,
    "log_joint_tail_mean": tail_mean_log_joint,
    "held_out_words": held_out_words,
}
CRITERIA = (*selection.CRITERIA, *SCORES)


def criterion(name: str) -> str | NamedScore:
    """The criterion called ``name``: the core's own names as they are, a research one as its run score;
    ModelError for any other."""
    if name in selection.CRITERIA:
        return name
    if name not in SCORES:
        raise ModelError(f"criterion must be one of {CRITERIA}, got {name!r}")
    return NamedScore(name, SCORES[name])


def scores(selector: selection.MultiRunSelector, name: str) -> list[float]:
    """Every fitted run's score under the criterion called ``name`` (not "auto")."""
    return selector.scores(criterion(name))
