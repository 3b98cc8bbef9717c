"""How often psi changes a plan: every task of a home planned with the model's psi and with a uniform psi.

psi enters planning twice: as Eq. 28's transition factor Mult(i_e | psi_{i_{e-1}}) of every step, and, on the
paper's graph (``adjacent_only``), as Figure 3's edges (places are connected when (psi_ab + psi_ba) / 2 >= 1 / K).
The uniform psi (:func:`uniform_psi`: every active place equally likely after every place) keeps neither: its
factor is the same for every step, and it connects every two active places. So a plan that differs between the two
is one that psi decided. :func:`psi_effect` counts, per planner variant
(:data:`~spcotmhp.evaluation.context.VARIANTS`), the plans whose cells differ and those that end in another cell,
over the basic tasks and a seeded subset of the advanced ones; a refusal counts as a plan (two refusals are equal).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import SpcotmhpError
from spcotmhp.evaluation.context import VARIANTS, fit_params, place_adjacency
from spcotmhp.evaluation.methods import task_instruction
from spcotmhp.evaluation.tasks import Task, build_places, make_tasks, subset
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.costmap import inflate
from spcotmhp.planning.planner import HierarchicalPlanner

VARIANT_LABELS = {"ours": "SpCoTMHP (ours)", "paper": "SpCoTMHP as in the paper"}


@dataclass
class PsiEffect:
    """One home, one kind of parameters, one planner variant: plans made, plans that differ, plans that end
    elsewhere, and where psi came from."""

    home: str
    params: str
    variant: str
    psi_from: str
    plans: int = 0
    differ: int = 0
    end_elsewhere: int = 0

    def to_dict(self) -> dict:
        return asdict(self)


def uniform_psi(model: SpatialConceptModel) -> SpatialConceptModel:
    """A copy of ``model`` whose psi is uniform over the active places in every row (module docstring)."""
    out = copy.copy(model)
    active = np.asarray(model.active_places, dtype=bool)
    out.psi = np.tile(active / active.sum(), (model.K, 1))
    out.info = {**model.info, "psi_from": "uniform"}
    return out


def psi_effect(
    dataset: Dataset,
    params: str,
    seed: int = 0,
    variants: Sequence[str] = ("ours", "paper"),
    max_advanced: int | None = 60,
    model: SpatialConceptModel | None = None,
) -> list[PsiEffect]:
    """Plan every basic task and a seeded subset of ``max_advanced`` advanced tasks of ``dataset`` with each
    planner variant, under the model's psi and under :func:`uniform_psi`, and count the differences (module
    docstring). ``params``: "supervised" or "learned" (fitted with ``seed``), unless ``model`` is given."""
    places = build_places(dataset)
    adjacency, source = place_adjacency(dataset)
    if model is None:
        model = fit_params(dataset, params, adjacency, seed)
    if model.map is None:
        model.map = dataset.map
    log_p = inflate(dataset.map, **model.costmap).log_p
    tasks = make_tasks(dataset, "basic", adjacency, source, places).tasks
    tasks += subset(make_tasks(dataset, "advanced", adjacency, source, places).tasks, max_advanced, seed)
    flat = uniform_psi(model)
    out = []
    for variant in variants:
        mine = HierarchicalPlanner(model, log_p=log_p, **VARIANTS[variant])
        even = HierarchicalPlanner(flat, log_p=log_p, **VARIANTS[variant])
        row = PsiEffect(dataset.name, params, variant, str(model.info.get("psi_from", "?")))
        for task in tasks:
            a, b = _cells(mine, task, dataset.lang), _cells(even, task, dataset.lang)
            row.plans += 1
            row.differ += int(not _same(a, b))
            row.end_elsewhere += int(not _same(a if a is None else a[-1:], b if b is None else b[-1:]))
        out.append(row)
    return out


def _cells(planner: HierarchicalPlanner, task: Task, lang: str) -> np.ndarray | None:
    """The plan's map cells, or None when the planner refuses the task."""
    try:
        return planner.plan(task_instruction(task, lang), task.start_xy).cells
    except SpcotmhpError:
        return None


def _same(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    return (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))


def markdown(rows: Sequence[PsiEffect]) -> str:
    """One table row per (parameters, variant, psi source): homes, plans, the share that differ and the share
    that end elsewhere, and the homes with the most differences."""
    lines = [
        "| parameters | planner | psi from | homes | plans | differ | end elsewhere | most in one home |",
        "|---|---|---|---|---|---:|---:|---|",
    ]
    groups: dict[tuple[str, str, str], list[PsiEffect]] = {}
    for r in rows:
        groups.setdefault((r.params, r.variant, r.psi_from), []).append(r)
    for (params, variant, psi_from), rs in groups.items():
        plans, differ, ends = (sum(getattr(r, k) for r in rs) for k in ("plans", "differ", "end_elsewhere"))
        worst = max(rs, key=lambda r: r.differ / max(r.plans, 1))
        lines.append(
            f"| {params} | {VARIANT_LABELS.get(variant, variant)} | {psi_from} | {len(rs)} | {plans} | "
            f"{differ} ({differ / max(plans, 1):.1%}) | {ends} ({ends / max(plans, 1):.1%}) | "
            f"{worst.home}: {worst.differ} of {worst.plans} |"
        )
    return "\n".join(lines) + "\n"
