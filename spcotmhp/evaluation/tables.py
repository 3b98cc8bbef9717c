"""Tables 4 and 5 of the paper (Experiment I) as markdown, the paper's row beside ours for every method. Our rows
give mean ± standard deviation over seeds where seeds change the result, and mean [95% bootstrap interval over
tasks] for the methods they do not change (:mod:`spcotmhp.evaluation.spread`); beside, the same rows under the
paper's strict success rule. Every table states its success rule (:data:`~spcotmhp.evaluation.metrics.SUCCESS_RULE`).

The paper's numbers (Taniguchi, Ito and Taniguchi 2024, Tables 4-5; five SIGVerse homes, Python on an Intel
i7-6850K, ideal "supervised" parameters) are transcribed in :data:`PAPER`. Our rows come from
:func:`spcotmhp.evaluation.runner.evaluate` (tasks of all evaluated homes pooled, then mean ± sd over seeds). A
paper row stands before the first of our rows of the same method (:data:`PAPER_ROW`): SpCoTMHP's variants and
HPP's smoothed rows share it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from spcotmhp.evaluation.metrics import SUCCESS_RULE
from spcotmhp.evaluation.spread import CI_LEVEL, pm
from spcotmhp.evaluation.tasks import ROBOT_RADIUS_M

METHOD_LABELS = {
    "astar": "A*",
    "spconavi-viterbi": "SpCoNavi (Viterbi)",
    "spconavi-astar": "SpCoNavi (A* approximation)",
    "hpp1": "HPP-I (path cost)",
    "hpp1-smoothed": "HPP-I + our smoothing",
    "hpp2": "HPP-II (path distance)",
    "hpp2-smoothed": "HPP-II + our smoothing",
    "spcotmhp-nostage-unsmoothed": "SpCoTMHP, Eq. 28 alone (no stage constraint), unsmoothed",
    "spcotmhp-nostage-ma": "SpCoTMHP, Eq. 28 alone (no stage constraint), moving average",
    "spcotmhp-nostage": "SpCoTMHP, Eq. 28 alone (no stage constraint), our smoothing",
    "spcotmhp-paper": "SpCoTMHP as in the paper (Eq. 24 at every step, connected places only), unsmoothed",
    "spcotmhp-paper-ma": "SpCoTMHP as in the paper (Eq. 24 at every step, connected places only), moving average",
    "spcotmhp-unsmoothed": "SpCoTMHP, unsmoothed (the paper's line 13 off)",
    "spcotmhp-ma": "SpCoTMHP, the paper's moving average (window 5)",
    "spcotmhp": "SpCoTMHP (ours: our smoothing)",
}
PAPER_ROW = {m: ("spcotmhp" if m.startswith("spcotmhp") else m.split("-smoothed")[0]) for m in METHOD_LABELS}
"""The paper's row each of our methods is compared with."""

PAPER: dict[str, dict[str, dict[str, float]]] = {
    "basic": {  # Table 4
        "astar": {"spl": 0.570, "n_spl": 0.463, "time_s": 9.47},
        "spconavi-viterbi": {"spl": 0.976, "n_spl": 0.965, "time_s": 2.68e3},
        "spconavi-astar": {"spl": 0.404, "n_spl": 0.388, "time_s": 5.42e1},
        "hpp1": {"spl": 0.723, "n_spl": 0.605, "time_s": 7.56},
        "hpp2": {"spl": 0.714, "n_spl": 0.571, "time_s": 7.96},
        "spcotmhp": {"spl": 0.861, "n_spl": 0.812, "time_s": 4.79},
    },
    "advanced": {  # Table 5 (no SpCoNavi Viterbi row in the paper)
        "astar": {"spl": 0.312, "w_spl": 0.449, "n_spl": 0.233, "wn_spl": 0.034, "time_s": 9.44},
        "spconavi-astar": {"spl": 0.266, "w_spl": 0.308, "n_spl": 0.252, "wn_spl": 0.013, "time_s": 5.53e1},
        "hpp1": {"spl": 0.917, "w_spl": 0.248, "n_spl": 0.773, "wn_spl": 0.191, "time_s": 7.53},
        "hpp2": {"spl": 0.902, "w_spl": 0.250, "n_spl": 0.729, "wn_spl": 0.183, "time_s": 8.03},
        "spcotmhp": {"spl": 0.922, "w_spl": 0.906, "n_spl": 0.794, "wn_spl": 0.781, "time_s": 0.39},
    },
}

COLUMNS = {
    "basic": [("spl", "SPL"), ("n_spl", "N-SPL")],
    "advanced": [("spl", "SPL"), ("w_spl", "W-SPL"), ("n_spl", "N-SPL"), ("wn_spl", "WN-SPL")],
}
VIA_COLUMNS = [("n_spl_via", "N-SPL (via)"), ("wn_spl_via", "WN-SPL (via)")]
"""Our variant of N (closest instance via the waypoint), advanced tasks only, never in the paper's rows."""
STRICT_COLUMNS = {
    "basic": ["spl", "n_spl", "success"],
    "advanced": ["spl", "w_spl", "n_spl", "wn_spl", "wn_spl_via", "success"],
}
"""The figures of the strict column (the paper's success rule), in its order."""


def success_rule(spread: bool = True) -> str:
    """The success rule every table states (:data:`~spcotmhp.evaluation.metrics.SUCCESS_RULE`) and, with
    ``spread``, how its spread reads."""
    text = SUCCESS_RULE.format(radius=ROBOT_RADIUS_M)
    if spread:
        text += (
            f" Spread: mean [{CI_LEVEL:.0%} bootstrap interval over tasks, 2000 resamples within each home] for "
            "the rows the seeds did not change (deterministic methods with supervised parameters, and learned "
            "parameters when every seed learned alike); mean ± sd over seeds for the others."
        )
    return text


TITLES = {"basic": "Table 4: basic task", "advanced": "Table 5: advanced task"}
SAME = 1e-9
"""An sd over seeds at most this is rounding of equal figures (the mean of equal floats need not be exact)."""


def fmt_time(seconds: float) -> str:
    """Seconds with 3 significant digits (milliseconds below 1 s; no exponent)."""
    if seconds < 1.0:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds:.3g} s" if seconds < 1000 else f"{seconds:,.0f} s"


def markdown_table(
    kind: str, ours: Mapping[str, Mapping[str, float]], title: str | None = None, deterministic: Sequence[str] = ()
) -> str:
    """One table: for each method the paper's row (where the paper has one, before the first of our rows it is
    compared with) and ours (mean [bootstrap interval] for the ``deterministic`` methods, mean ± sd over seeds
    for the others), with our success rate, the strict rule's figures when present, median / 95th-percentile
    online time (means over seeds) and the number of tasks; advanced tables add our N-SPL (via) and WN-SPL (via).
    The success rule stands under the title."""
    if kind not in COLUMNS:
        raise ValueError(f"kind must be 'basic' or 'advanced', got {kind!r}")
    cols = COLUMNS[kind]
    via = VIA_COLUMNS if kind == "advanced" and any("n_spl_via" in m for m in ours.values()) else []
    strict = [k for k in STRICT_COLUMNS[kind] if any(f"strict_{k}" in m for m in ours.values())]
    strict_head = ["Strict: " + " / ".join(_short(k) for k in strict)] if strict else []
    head = (
        ["Method", "Source"]
        + [c for _, c in cols + via]
        + ["Success"]
        + strict_head
        + ["Collides", "Time (median / p95)", "Tasks"]
    )
    lines = [
        f"### {title or TITLES[kind]}",
        "",
        success_rule(),
        "",
        "| " + " | ".join(head) + " |",
        "|" + "|".join(["---"] * 2 + ["---:"] * (len(head) - 2)) + "|",
    ]
    order = [
        m for m in METHOD_LABELS if m in ours or (m in PAPER[kind] and not any(PAPER_ROW.get(o) == m for o in ours))
    ]
    order += [m for m in ours if m not in order]
    shown: set[str] = set()
    for method in order:
        paper = PAPER[kind].get(PAPER_ROW.get(method, method))
        if paper is not None and PAPER_ROW.get(method, method) not in shown:
            shown.add(PAPER_ROW.get(method, method))
            name = METHOD_LABELS[PAPER_ROW.get(method, method)].split(" (ours")[0]
            cells = (
                [name, "paper"]
                + [f"{paper[k]:.3f}" for k, _ in cols]
                + [""] * (len(via) + 1 + len(strict_head))
                + ["", fmt_time(paper["time_s"]), ""]
            )
            lines.append("| " + " | ".join(cells) + " |")
        if method in ours:
            lines.append(_our_row(method, ours[method], [k for k, _ in cols + via], strict, deterministic))
    return "\n".join(lines) + "\n"


def _our_row(
    method: str, mine: Mapping[str, float], keys: Sequence[str], strict: Sequence[str], deterministic: Sequence[str]
) -> str:
    """One of our rows of :func:`markdown_table`: an interval where the seeds changed nothing (a deterministic
    method, or learned parameters every seed learned alike), mean ± sd otherwise; the strict figures when given."""
    fixed = method in deterministic or all(mine.get(f"{k}_sd", 0.0) <= SAME for k in keys)
    cells = (
        [METHOD_LABELS.get(method, method), "ours"]
        + [pm(mine, k, interval=fixed) if k in mine else "" for k in keys]
        + [pm(mine, "success", interval=fixed)]
        + ([" / ".join(f"{mine[f'strict_{k}']:.3f}" for k in strict)] if strict else [])
        + [
            f"{mine.get('collides', 0.0):.3f}",
            f"{fmt_time(mine['time_median_s'])} / {fmt_time(mine['time_p95_s'])}",
            str(mine["n_tasks"]),
        ]
    )
    return "| " + " | ".join(cells) + " |"


def _short(key: str) -> str:
    """A figure's name in the strict column's heading."""
    names = dict(COLUMNS["advanced"] + VIA_COLUMNS)
    return {"success": "Success", "wn_spl_via": "WN-SPL (via)"}.get(key, names.get(key, key))


DEPARTURES = (
    'Departures from the paper in every SpCoTMHP row but those "as in the paper": w-hat observes optimality at '
    "each leg's end (the paper's Eq. 24: at every step), steps of Eq. 28 go between any two candidate points (the "
    "paper: between connected places only), and our smoothing (tube re-planning and line-of-sight shortcuts, "
    "developed on these same homes; rows unsmoothed or with the paper's moving average replace it). In every "
    "SpCoTMHP row, those as in the paper included: the stage constraint (every stage ends at a place whose p(i|S) "
    "is at least 1/4 of the best and whose name carries the words; the ratio 4 was chosen by measuring these same "
    "homes; the paper gives no rule for where a stage ends, and Eq. 28 alone ends at the nearest place whatever its "
    "name: method spcotmhp-nostage, docs/results.md), p(x|m) = 0 on inscribed cells, the start place marginalised "
    'over p(i_0 | x_0), and a metric route when no place sequence satisfies the instruction. "+ our smoothing" '
    "HPP rows get exactly SpCoTMHP's smoothing. The paper's moving average has no collision check: the Collides "
    "column counts paths with a pose on an occupied or unknown cell."
)


def machine() -> str:
    """Processor, logical CPUs and Python version of this machine."""
    import os
    import platform

    return (
        f"{platform.processor() or platform.machine()} with {os.cpu_count()} logical CPUs, Python "
        f"{platform.python_version()}"
    )


def psi_sources(result: Mapping) -> str:
    """Where each home's psi came from (per home, over the seeds)."""
    return "; ".join(f"{home}: {', '.join(note.get('psi') or ['?'])}" for home, note in result["notes"].items())


def experiment_markdown(basic: Mapping, advanced: Mapping, heading: str, about: str) -> str:
    """Tables 4 and 5 (paper rows beside ours) with their caption: ``about`` (where the parameters came from and
    which of their choices were made on the same data), then the tasks, the tasks set apart, seeds, psi,
    departures, machine and run time from the results, and the tasks whose start lies in a waypoint. ``basic`` /
    ``advanced`` are :func:`spcotmhp.evaluation.runner.evaluate` results."""
    lines = [
        f"### {heading}",
        "",
        _caption(basic, advanced, about),
        "",
        markdown_table("basic", basic["mean"], "Table 4: basic task", basic.get("deterministic", ())),
        markdown_table("advanced", advanced["mean"], "Table 5: advanced task", advanced.get("deterministic", ())),
    ]
    apart = advanced.get("start_in_waypoint") or {}
    if apart:
        lines += [
            markdown_table(
                "advanced",
                apart,
                "Table 5, tasks whose start lies inside a waypoint-named place (set apart)",
                advanced.get("deterministic", ()),
            ),
            "",
        ]
    lines += ["Per home (SPL / N-SPL basic; WN-SPL advanced; strict rule in brackets; means over seeds):", ""]
    for home in basic["homes"]:
        b, a = basic["homes"][home], advanced["homes"].get(home, {})
        row = ", ".join(
            f"{METHOD_LABELS.get(m, m)} {_pair(v, 'spl')} / {_pair(v, 'n_spl')}"
            + (f" / {_pair(a[m], 'wn_spl')}" if m in a else "")
            for m, v in b.items()
        )
        lines.append(f"- {home} (adjacency: {basic['notes'].get(home, {}).get('adjacency', '?')}): {row}")
    moves = basic.get("moves") or {}
    if moves:
        lines += [
            "",
            "Moves: "
            + "; ".join(f"{METHOD_LABELS.get(m, m)} {v}" for m, v in moves.items())
            + ". SPL's reference length l is an 8-connected geodesic.",
        ]
    return "\n".join(lines) + "\n"


def _caption(basic: Mapping, advanced: Mapping, about: str) -> str:
    """The caption of :func:`experiment_markdown`: ``about``, the homes and tasks, those left out and set apart,
    psi, seeds, the departures, the machine and the run time."""

    def count(result: Mapping, key: str) -> int:
        return sum(len(v) if isinstance(v := n.get(key, 0), list) else int(v or 0) for n in result["notes"].values())

    def n_tasks(result: Mapping) -> int:
        first: Mapping = next(iter(result["mean"].values()), {})
        return first.get("n_tasks", 0)

    seeds = basic.get("seeds", 1)
    return (
        f"{about} Homes: {', '.join(basic['homes']) or 'none'}: {n_tasks(basic)} basic and {n_tasks(advanced)} "
        f"advanced tasks (the paper: five homes, 418 and 3526). Left out: {count(basic, 'zero_length')} basic and "
        f"{count(advanced, 'zero_length')} advanced tasks whose reference length l is 0 (the start is already a "
        f"goal instance); {count(basic, 'no_safe_path')} basic and {count(advanced, 'no_safe_path')} advanced "
        "tasks with no footprint-safe path (no cell where the robot's centre fits within its radius of the goal's "
        f"or waypoint's box is reachable), {count(basic, 'dropped')} and {count(advanced, 'dropped')} with no "
        f"path at all; {count(advanced, 'start_in_waypoint')} advanced tasks whose start lies inside a "
        f"waypoint-named place are reported apart below. psi: {psi_sources(basic)}. Seeds {basic['seed']}.."
        f"{basic['seed'] + seeds - 1} ({seeds}). {DEPARTURES} Times: online planning only (precomputation and "
        f"numba compilation excluded), median / p95 per task, means over seeds, on {machine()}; both tables took "
        f"{basic.get('time_s', 0) + advanced.get('time_s', 0):.0f} s. The paper's times are Python on an Intel "
        "i7-6850K."
    )


def _pair(metrics: Mapping, key: str) -> str:
    """``0.976 (0.975)``: a figure and, when scored, its strict reading."""
    strict = metrics.get(f"strict_{key}")
    return f"{metrics[key]:.3f}" + ("" if strict is None else f" ({strict:.3f})")
