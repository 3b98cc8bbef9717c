"""``spcotmhp reproduce``: every results table of the README regenerated into one markdown document, with the
total run time.

Sections: Table 6 (learning, albert-b, and the SIGVerse homes on words alone), Tables 4 and 5 with supervised
("ideal", the paper's Experiment I) and with learned parameters (with how close each home's learned partition is
to the truth), learned against supervised parameters on generated homes where learning is not perfect, how often
psi changes a plan, planning on albert-b with psi from the HMM against psi from the map, and the planning and scale
benchmarks (``benchmarks/planning.py`` and ``benchmarks/scale.py`` of a source checkout, run as they are; skipped
with a note when the package is installed without them). Spread: mean ± sd over seeds where seeds change the
result, a bootstrap interval over tasks where they do not (:mod:`spcotmhp.evaluation.spread`); ``quick`` runs
fewer seeds, homes, tasks and queries (for a first look: the README's figures come from the full run).
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from spcotmhp.evaluation.tables import SAME, experiment_markdown, machine

TABLE_METHODS = (
    "astar",
    "spconavi-viterbi",
    "spconavi-astar",
    "hpp1",
    "hpp1-smoothed",
    "hpp2",
    "hpp2-smoothed",
    "spcotmhp-paper",
    "spcotmhp-paper-ma",
    "spcotmhp-unsmoothed",
    "spcotmhp-ma",
    "spcotmhp",
)
PSI_METHODS = ("hpp2", "spcotmhp-paper", "spcotmhp-unsmoothed", "spcotmhp")
GENERATED_METHODS = {"spcotmhp": "SpCoTMHP (ours)", "spcotmhp-paper": "as in the paper"}
LEARNING_HARD = (21, 42)
"""Battery homes where the learner merges places (docs/results.md, split-merge moves), added to the first ones."""
LEARNER = (
    "10 runs x 100 Gibbs sweeps per seed, one run kept by `--criterion auto`: the highest word-concept mutual "
    "information where there are image features (the authors' criterion), the highest collapsed log joint "
    "where there are none; the learner's departures from the paper (a shared background word distribution, "
    "k-means++ start, run selection; feature weight 1 where there are image features) were chosen by "
    "measuring NMI/ARI on albert-b, the log joint for words-only data on the generated battery homes"
)


@dataclass(frozen=True)
class Plan:
    """What one reproduce run does."""

    seeds: int = 5
    learned_seeds: int = 3
    max_tasks: int | None = None
    albert_tasks: int | None = 300
    queries: int = 300
    scale_queries: int = 40
    workers: int | None = None
    generated_homes: int = 10
    generated_tasks: int = 60

    @classmethod
    def quick(cls, workers: int | None = None) -> Plan:
        return cls(
            seeds=2,
            learned_seeds=2,
            max_tasks=30,
            albert_tasks=30,
            queries=30,
            scale_queries=5,
            workers=workers,
            generated_homes=3,
            generated_tasks=20,
        )


def table6_section(plan: Plan, say: Callable[[str], None]) -> str:
    import warnings

    from spcotmhp.datasets import load_bundled
    from spcotmhp.evaluation import table6
    from spcotmhp.learning.posterior import TruncationWarning

    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)
        say("Table 6 on albert-b")
        t0 = time.perf_counter()
        res = table6.evaluate_seeds(load_bundled("albert-b", lang="ja"), seeds=plan.seeds)
        out.append(
            table6.markdown(
                res,
                (
                    f"### Table 6: learning on albert-b\n\nJapanese words + Places365 image features; {LEARNER} "
                    f"(the data "
                    f"of this table). Mean ± sd over seeds 0..{plan.seeds - 1} of the means over each seed's 10 "
                    f"runs; our "
                    f"time is for the 10 runs of one seed after numba compilation, on {machine()} "
                    f"({time.perf_counter() - t0:.0f} s for this table); the paper's is Python on an Intel i7-6850K."
                ),
            )
        )
        rows = []
        for home in ("3LDK_01", "3LDK_05", "3LDK_06"):
            say(f"Table 6 on {home}")
            r = table6.evaluate_seeds(load_bundled(home, lang="en"), seeds=plan.seeds, methods=("tmhp_replay", "gmm"))
            rows.append(
                f"| {home} | "
                + " | ".join(
                    f"{r[m][k]:.3f} ± {r[m][k + '_sd']:.3f}"
                    for m in ("tmhp_replay", "gmm")
                    for k in ("nmi_c", "nmi_i", "ari_c", "ari_i")
                )
                + " |"
            )
    out += [
        f"SIGVerse homes, English words only (no image features), the same learner, mean ± sd over {plan.seeds} seeds:",
        "",
        (
            "| home | replay NMI C | replay NMI i | replay ARI C | replay ARI i | GMM NMI C | GMM NMI i | GMM ARI C "
            "| GMM ARI i |"
        ),
        "|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
    ]
    return "\n".join(out)


def planning_section(plan: Plan, params: str, say: Callable[[str], None]) -> str:
    from spcotmhp.datasets import list_bundled, load_bundled
    from spcotmhp.evaluation.runner import evaluate

    homes = [load_bundled(n, lang="en") for n in list_bundled() if n.upper().startswith("3LDK")]
    seeds = plan.seeds if params == "supervised" else plan.learned_seeds
    say(f"Tables 4 and 5, {params} parameters")
    res = [
        evaluate(homes, kind, TABLE_METHODS, params, 0, plan.workers, plan.max_tasks, seeds=seeds)
        for kind in ("basic", "advanced")
    ]
    if params == "supervised":
        heading = 'Tables 4 and 5, supervised ("ideal") parameters, as the paper\'s Experiment I'
        about = (
            "Parameters fitted from the truth labels, psi from each home's hand-made adjacency.csv (as the "
            "paper's Experiment I); only the methods that draw at random change with the seed."
        )
    else:
        heading = "Tables 4 and 5, learned parameters (fully unsupervised; beyond the paper)"
        about = (
            f"Parameters learned from the English words alone ({LEARNER}); no bundled home has a "
            "trajectory, so psi comes from the map (places whose territories touch), not from the HMM, whose "
            "psi on these homes has 0-2 edges. Each seed learns again. How close the kept run's partition is to "
            f"the truth, per home: {vs_truth(res[0])}; where learning recovers the true places (ARI 1) the rows "
            "equal the supervised ones, so the next section adds generated homes where it does not."
        )
    basic, advanced = res
    return experiment_markdown(basic, advanced, heading, about)


def vs_truth(result: dict) -> str:
    """Per home: ARI of the kept run's places and concepts against the truth (mean and range over the seeds)."""

    def span(values: list[float]) -> str:
        return f"{np.mean(values):.3f}" + (f" ({min(values):.3f}-{max(values):.3f})" if len(values) > 1 else "")

    parts = []
    for home, note in result["notes"].items():
        scores = note.get("vs_truth") or []
        if scores:
            parts.append(
                f"{home} ARI places {span([s['ari_i'] for s in scores])}, concepts {span([s['ari_c'] for s in scores])}"
            )
    return "; ".join(parts) or "not measured"


def generated_section(plan: Plan, say: Callable[[str], None]) -> str:
    """Learned against supervised parameters on the first ``plan.generated_homes`` battery homes and those of
    :data:`LEARNING_HARD`, per home with the ARI of its learned places and concepts."""
    from spcotmhp.datasets.synthetic_battery import battery_home
    from spcotmhp.evaluation.runner import evaluate
    from spcotmhp.evaluation.tables import success_rule

    seeds = [*range(plan.generated_homes), *(s for s in LEARNING_HARD if s >= plan.generated_homes)]
    homes = [battery_home(seed) for seed in seeds]
    say(f"learned against supervised parameters on {len(homes)} generated homes")
    res = {
        (params, kind): evaluate(
            homes,
            kind,
            list(GENERATED_METHODS),
            params,
            0,
            plan.workers,
            plan.generated_tasks,
            seeds=1 if params == "supervised" else plan.learned_seeds,
        )
        for params in ("supervised", "learned")
        for kind in ("basic", "advanced")
    }
    lines = [
        "### Learned against supervised parameters on generated homes",
        "",
        (
            f"The first {plan.generated_homes} homes of `spcotmhp battery` and homes "
            f"{', '.join(map(str, LEARNING_HARD))} (where docs/results.md found the learner merging places), a "
            f"seeded subset of {plan.generated_tasks} tasks per kind and home; supervised parameters "
            f"(truth labels, the doors' adjacency) against learned ones ({LEARNER}; psi from the teaching walk and "
            f"the map), seeds 0..{plan.learned_seeds - 1}, each learning again. {success_rule(spread=False)} "
            "ARI: the kept run's places (i) and concepts (C) against the truth, mean over the seeds."
        ),
        "",
        "| home | ARI i | ARI C | "
        + " | ".join(
            f"{label}: {col}"
            for label in GENERATED_METHODS.values()
            for col in ("basic SPL sup. / learned", "adv. WN-SPL (via) sup. / learned")
        )
        + " |",
        "|---|---:|---:|" + "---:|" * 2 * len(GENERATED_METHODS),
    ]
    return "\n".join(lines + _generated_rows([h.name for h in homes], res)) + "\n"


def _generated_rows(homes: list[str], res: dict) -> list[str]:
    """The rows of :func:`generated_section`: per home the learned ARI and, per method, supervised / learned
    figures; then the pooled tasks (an interval where the seeds changed nothing, else ± sd over seeds)."""
    from spcotmhp.evaluation.spread import pm

    learned = res["learned", "basic"]["notes"]
    figures = [
        (m, kind, key) for m in GENERATED_METHODS for kind, key in (("basic", "spl"), ("advanced", "wn_spl_via"))
    ]
    rows = []
    for home in homes:
        scores = learned.get(home, {}).get("vs_truth") or []
        cells = [f"{np.mean([s['ari_i'] for s in scores]):.3f}", f"{np.mean([s['ari_c'] for s in scores]):.3f}"]
        for m, kind, key in figures:
            sup = res["supervised", kind]["homes"].get(home, {}).get(m)
            got = res["learned", kind]["homes"].get(home, {}).get(m)
            cells.append(f"{sup[key]:.3f} / {got[key]:.3f}" if sup and got else "")
        rows.append(f"| {home} | " + " | ".join(cells) + " |")
    pooled = []
    for m, kind, key in figures:
        sup, got = res["supervised", kind]["mean"][m], res["learned", kind]["mean"][m]
        pooled.append(f"{pm(sup, key, interval=True)} / {pm(got, key, interval=got.get(f'{key}_sd', 0.0) <= SAME)}")
    return rows + ["| all (pooled tasks) | | | " + " | ".join(pooled) + " |"]


def psi_effect_section(plan: Plan, say: Callable[[str], None]) -> str:
    """How often psi changes a plan (:mod:`spcotmhp.evaluation.psi_effect`) on the bundled SIGVerse homes and the
    generated homes of :func:`generated_section`, with supervised and learned parameters."""
    from spcotmhp.datasets import load_bundled
    from spcotmhp.datasets.synthetic_battery import battery_home
    from spcotmhp.evaluation.psi_effect import markdown, psi_effect

    homes = [load_bundled(n, lang="en") for n in ("3LDK_01", "3LDK_05", "3LDK_06")]
    homes += [battery_home(seed) for seed in [*range(plan.generated_homes), *LEARNING_HARD]]
    say(f"how often psi changes a plan, {len(homes)} homes")
    rows = [
        row
        for home in homes
        for params in ("supervised", "learned")
        for row in psi_effect(home, params, 0, max_advanced=plan.generated_tasks)
    ]
    return (
        "### How often psi changes a plan\n\n"
        f"Every basic task and a seeded subset of {plan.generated_tasks} advanced tasks per home (3LDK_01/05/06 and "
        f"the generated homes above), each planned with the model's psi and with a uniform psi "
        "(every active place equally likely after every place), seed 0; a plan differs when its cells do, ends "
        "elsewhere when its last cell does. psi from: adjacency (supervised: the homes' adjacency.csv or the "
        "doors), map or walk+map (learned).\n\n" + markdown(rows)
    )


def psi_section(plan: Plan, say: Callable[[str], None]) -> str:
    from spcotmhp.datasets import load_bundled
    from spcotmhp.evaluation.runner import evaluate
    from spcotmhp.evaluation.spread import pm
    from spcotmhp.evaluation.tables import METHOD_LABELS, success_rule

    home = load_bundled("albert-b", lang="ja")
    lines = [
        "### Planning on albert-b: psi from the HMM against psi from the map",
        "",
        (
            f"Learned parameters ({LEARNER}), mean ± sd over seeds 0..{plan.learned_seeds - 1}, a seeded subset "
            f"of {plan.albert_tasks or 'all'} tasks per kind (the same tasks for both psi). albert-b has no "
            "adjacency.csv: tasks are over the true places with the map's connectivity. Place names are the "
            "most specific word of each true place."
        ),
        "",
        success_rule(),
        "",
        "| psi | Method | basic SPL | basic N-SPL | advanced SPL | advanced WN-SPL | advanced WN-SPL (via) |",
        "|---|---|---|---|---|---|---|",
    ]
    for conn, label in (("hmm", "HMM (the walk of teaching events, reverse replay)"), ("map", "the map")):
        say(f"albert-b planning, psi from {conn}")
        b, a = (
            evaluate(
                [home],
                kind,
                PSI_METHODS,
                "learned",
                0,
                plan.workers,
                plan.albert_tasks,
                seeds=plan.learned_seeds,
                connectivity=conn,
                quiet=False,
            )
            for kind in ("basic", "advanced")
        )
        for m in PSI_METHODS:
            lines.append(
                f"| {label} | {METHOD_LABELS[m]} | {pm(b['mean'][m], 'spl')} | {pm(b['mean'][m], 'n_spl')} "
                f"| {pm(a['mean'][m], 'spl')} | {pm(a['mean'][m], 'wn_spl')} | "
                f"{pm(a['mean'][m], 'wn_spl_via')} |"
            )
    return "\n".join(lines) + "\n"


def benchmark_section(plan: Plan, say: Callable[[str], None]) -> str:
    root = Path(__file__).resolve().parents[2] / "benchmarks"
    runs = [
        ("Planning speed", "planning.py", ["--queries", str(plan.queries)]),
        ("Scale", "scale.py", ["--queries", str(plan.scale_queries)]),
    ]
    out = []
    for title, script, args in runs:
        path = root / script
        out += [f"### {title} (`python benchmarks/{script} {' '.join(args)}`)", ""]
        if not path.is_file():
            out += [f"(skipped: {path} is not here; run reproduce from a source checkout)", ""]
            continue
        say(f"benchmark {script}")
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, str(path), *args], capture_output=True, text=True, check=False)
        text = proc.stdout.strip() if proc.returncode == 0 else f"(failed: {proc.stderr.strip().splitlines()[-1:]})"
        out += [text, "", f"({time.perf_counter() - t0:.0f} s, on {machine()})", ""]
    return "\n".join(out)


def reproduce(plan: Plan, say: Callable[[str], None] = lambda _: None) -> str:
    """The whole document (module docstring), ending with its total run time."""
    import warnings

    from spcotmhp.datasets import DatasetWarning

    with warnings.catch_warnings():  # the homes' known teaching points in walls: check-dataset lists them
        warnings.simplefilter("ignore", DatasetWarning)
        return _reproduce(plan, say)


def _reproduce(plan: Plan, say: Callable[[str], None]) -> str:
    t0 = time.perf_counter()
    parts = [
        "## Results reproduced by `spcotmhp reproduce`" + (" --quick" if plan == Plan.quick(plan.workers) else ""),
        "",
        table6_section(plan, say),
        planning_section(plan, "supervised", say),
        planning_section(plan, "learned", say),
        generated_section(plan, say),
        psi_effect_section(plan, say),
        psi_section(plan, say),
        benchmark_section(plan, say),
    ]
    total = time.perf_counter() - t0
    parts.append(f"Total run time of `spcotmhp reproduce`: {total / 60:.1f} min on {machine()}.")
    return "\n".join(parts) + "\n"
