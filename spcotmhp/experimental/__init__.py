"""Research variants of the learner that the model study measured and did not adopt (docs/experimental.md,
docs/learning-model-study.md).  They plug into spcotmhp.learning from outside, through its hooks
(``SpCoTMHP(variant=...)``, ``MultiRunSelector(criterion=<run score>)``, the ``extra`` terms of the log
joint); nothing in the default paths imports this package.

* :mod:`~spcotmhp.experimental.split_merge`: split-merge moves of the concepts (``SplitMergeMoves``);
* :mod:`~spcotmhp.experimental.off_name`: the off-name term (``Hyperparameters.off_name``, ``OffName``);
* :mod:`~spcotmhp.experimental.selection`, :mod:`~spcotmhp.experimental.run_scores`,
  :mod:`~spcotmhp.experimental.switch_marginal`: the run-selection criteria that handle the background-word
  switches.

:func:`research_learner` and :func:`fit_runs` take the settings by name (``split_merge=True``,
``hyper=Hyperparameters(off_name=1.0)``, ``criterion="log_joint_switch_mode"``) as the learner took them before
the variants moved here.
"""

from __future__ import annotations

from typing import Any

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.experimental.off_name import OffName
from spcotmhp.experimental.selection import criterion as named_criterion
from spcotmhp.experimental.split_merge import SplitMergeMoves
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.init import SweepVariant
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.selection import MultiRunSelector


def variant_for(hyper: Hyperparameters | None, split_merge: bool | str = False) -> SweepVariant | None:
    """The sampler variant these settings select: split-merge moves (``split_merge`` True or "auto"; they refuse
    an opt-in term), else the off-name term when ``hyper.off_name`` is set, else None (the paper's sampler)."""
    if split_merge is not False:
        return SplitMergeMoves(split_merge)
    if hyper is not None and hyper.off_name is not None:
        return OffName()
    return None


def research_learner(split_merge: bool | str = False, **params: Any) -> SpCoTMHP:
    """``SpCoTMHP(**params)`` with the variant of ``variant_for(params["hyper"], split_merge)``."""
    return SpCoTMHP(variant=variant_for(params.get("hyper"), split_merge), **params)


def fit_runs(
    dataset: Dataset,
    runs: int = 10,
    criterion: str = "auto",
    n_jobs: int = 1,
    split_merge: bool | str = False,
    **params: Any,
) -> MultiRunSelector:
    """``selection.fit_runs`` with the research settings by name: the criterion (experimental/selection.py) and
    the sampler variant (``research_learner``)."""
    est = research_learner(split_merge, **params)
    return MultiRunSelector(est, runs=runs, criterion=named_criterion(criterion), n_jobs=n_jobs).fit(dataset)


__all__ = ["OffName", "SplitMergeMoves", "fit_runs", "research_learner", "variant_for"]
