"""Several independent Gibbs runs and the choice of one (paper Section 5.1: ten runs, one kept).

Criteria:

* ``"auto"`` (default): ``"mutual_information"`` when the runs used image features, else ``"log_joint"``.
* ``"mutual_information"`` (the authors' choice): the run whose word-concept mutual information I(C; S) is
  highest, i.e. whose concepts are most clearly told apart by their words.
* ``"log_joint"``: the run with the highest collapsed log joint probability log p(x, S, f, i, C | h), the
  model's own posterior.
* a :class:`RunScore`: any score of a fitted run, higher is better.  The research criteria that handle the
  background-word switches (``"log_joint_switch_mode"``, ...) are such scores, in
  :mod:`spcotmhp.experimental.selection` (docs/experimental.md): none is the default, each keeps runs the log
  joint does not, and on the generated battery none both passes every home and keeps the held-out homes' figures
  (docs/learning-model-study.md, sections 4 and 6).

Why ``"auto"``: the log joint is the principled choice (the most probable run under the model), and it picks the
best runs on words-only data; but with image features the high-dimensional feature term dominates the joint and
prefers fewer, merged concepts (the rooms of one building look alike), so with features the mutual information
is kept (measured on albert-b, the data of Table 6). On words-only data the mutual information can reward
concepts built from the teaching templates' function words ("we are in the ..."), which merge differently named
places (measured on generated homes; on the SIGVerse homes both pick runs of equal NMI). docs/results.md and the
README give the measurements.

Run r uses the r-th independent child stream of ``seed`` (``gibbs.make_rng``); runs can go to a process pool.
"""

from __future__ import annotations

import multiprocessing as mp
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import ModelError
from spcotmhp.learning.connectivity import apply_connectivity
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.limits import MAX_JOBS, MAX_RUNS, check_count

CRITERIA = ("auto", "mutual_information", "log_joint")


class RunScore(Protocol):
    """A run-selection criterion beyond ``CRITERIA``: ``name`` (kept as ``criterion_`` and in model.info) and the
    score of a fitted run, higher is better (spcotmhp.experimental.selection has the research ones)."""

    @property
    def name(self) -> str: ...

    def __call__(self, run: SpCoTMHP, /) -> float: ...


def check_criterion(criterion: str | RunScore, allowed: tuple[str, ...] = CRITERIA) -> None:
    """ModelError for a criterion that is neither one of ``allowed`` nor a RunScore."""
    if isinstance(criterion, str) and criterion not in allowed:
        raise ModelError(f"criterion must be one of {allowed}, got {criterion!r}")
    if not isinstance(criterion, str) and not (
        callable(criterion) and isinstance(getattr(criterion, "name", None), str)
    ):
        raise ModelError(f"criterion must be one of {allowed} or a named run score, got {criterion!r}")


@dataclass
class RunSummary:
    """One run: its index, criteria, size and times (wall and CPU seconds)."""

    run: int
    log_joint: float
    mutual_information: float
    n_places: int
    n_concepts: int
    fit_time: float
    cpu_time: float  # CPU seconds of the run in its process (on a shared machine, the work itself)


class MultiRunSelector:
    """Fit ``runs`` independent copies of ``estimator`` (run r = r-th child seed) and keep one.

    Learned attributes: ``estimators_`` (all fitted runs), ``summaries_`` (RunSummary per run),
    ``best_index_``, ``best_`` (the chosen SpCoTMHP), ``model_`` (its model, with the connectivity of
    ``estimator.connectivity`` applied once, to the chosen run only), ``fit_time_``.
    """

    def __init__(
        self,
        estimator: SpCoTMHP | None = None,
        runs: int = 10,
        criterion: str | RunScore = "auto",
        n_jobs: int = 1,
    ) -> None:
        self.estimator = estimator
        self.runs = runs
        self.criterion = criterion
        self.n_jobs = n_jobs

    def fit(self, dataset: Dataset, progress: Callable[[int], None] | None = None) -> MultiRunSelector:
        """Run everything; ``progress(n)`` is called with the number of sweeps just completed."""
        check_criterion(self.criterion)
        check_count(self.runs, "runs", 1, MAX_RUNS, ModelError)
        check_count(self.n_jobs, "n_jobs", 1, MAX_JOBS, ModelError)
        t0 = time.perf_counter()
        base = self.estimator or SpCoTMHP()
        params = base.get_params()
        connectivity = params.pop("connectivity")
        params.pop("run")
        jobs = [dict(params, run=r, connectivity="hmm") for r in range(self.runs)]
        if self.n_jobs > 1 and self.runs > 1:
            self.estimators_ = _fit_pool(dataset, jobs, self.n_jobs, progress)
        else:
            self.estimators_ = []
            for job in jobs:
                step = None if progress is None else (lambda _sweep: progress(1))
                self.estimators_.append(SpCoTMHP(**job).fit(dataset, progress=step))
        self.summaries_ = [
            RunSummary(
                r,
                e.log_joint_,
                e.mutual_information_,
                int(e.model_.active_places.sum()),
                int(e.model_.active_concepts.sum()),
                e.fit_time_,
                e.fit_cpu_time_,
            )
            for r, e in enumerate(self.estimators_)
        ]
        self._dataset, self._connectivity, self._use_trajectory = dataset, connectivity, base.use_trajectory
        self.choose(self.criterion)
        self.fit_time_ = time.perf_counter() - t0
        return self

    def scores(self, criterion: str | RunScore) -> list[float]:
        """Every fitted run's score under ``criterion`` (not "auto"; higher is better)."""
        check_criterion(criterion, CRITERIA[1:])
        if criterion == "mutual_information":
            return [s.mutual_information for s in self.summaries_]
        if isinstance(criterion, str):  # "log_joint"
            return [s.log_joint for s in self.summaries_]
        return [criterion(e) for e in self.estimators_]

    def choose(self, criterion: str | RunScore) -> MultiRunSelector:
        """Keep the fitted run of highest score under ``criterion`` ("auto": module docstring): sets
        ``criterion_`` (its name), ``best_index_``, ``best_`` and ``model_`` (with the connectivity applied)."""
        check_criterion(criterion)
        if criterion == "auto":
            criterion = "mutual_information" if self.estimators_[0].model_.info.get("features") else "log_joint"
        self.criterion_ = criterion if isinstance(criterion, str) else criterion.name
        return self.keep(int(np.argmax(self.scores(criterion))))

    def keep(self, index: int) -> MultiRunSelector:
        """Keep fitted run ``index``: sets ``best_index_``, ``best_`` and ``model_`` (its model, with the
        connectivity applied). ``choose`` calls it; a post-step that changed the kept run's model calls it again
        (``taught_split.split_selected``)."""
        self.best_index_ = index
        self.best_ = self.estimators_[self.best_index_]
        self.model_: SpatialConceptModel = self.best_.model_
        self.model_.info.update(selected_run=self.best_index_, runs=self.runs, criterion=self.criterion_)
        if self.best_.transitions == "hmm":
            data = self._dataset
            seen = data if self._use_trajectory else replace(data, trajectory=None, event_steps=None)
            apply_connectivity(self.model_, seen, self._connectivity, self.best_.places_)
        return self


def fit_runs(
    dataset: Dataset,
    runs: int = 10,
    criterion: str | RunScore = "auto",
    n_jobs: int = 1,
    progress: Callable[[int], None] | None = None,
    **params,
) -> MultiRunSelector:
    """``MultiRunSelector(SpCoTMHP(**params), runs, criterion, n_jobs).fit(dataset, progress)``."""
    return MultiRunSelector(SpCoTMHP(**params), runs=runs, criterion=criterion, n_jobs=n_jobs).fit(
        dataset, progress=progress
    )


def _fit_one(dataset: Dataset, job: dict) -> SpCoTMHP:
    return SpCoTMHP(**job).fit(dataset)


def _fit_pool(
    dataset: Dataset, jobs: list[dict], n_jobs: int, progress: Callable[[int], None] | None
) -> list[SpCoTMHP]:
    """Runs in worker processes (fork where the platform has it: no re-import, numba caches shared)."""
    method = "fork" if "fork" in mp.get_all_start_methods() else "spawn"
    with ProcessPoolExecutor(max_workers=min(n_jobs, len(jobs)), mp_context=mp.get_context(method)) as pool:
        futures = [pool.submit(_fit_one, dataset, job) for job in jobs]
        out = []
        for job, fut in zip(jobs, futures, strict=False):
            out.append(fut.result())
            if progress is not None:
                progress(job["iterations"])
        return out
