"""Tables 4 and 5 of the paper (Experiment I) as markdown, the paper's row beside ours for every method.

The paper's numbers (Taniguchi, Ito and Taniguchi 2024, Tables 4-5; five SIGVerse homes, Python on an Intel
i7-6850K, ideal "supervised" parameters) are transcribed in :data:`PAPER`. Our rows come from
:func:`spcotmhp.evaluation.runner.overall` (tasks of all evaluated homes pooled).
"""

from __future__ import annotations

from collections.abc import Mapping

METHOD_LABELS = {
    "astar": "A*",
    "spconavi-viterbi": "SpCoNavi (Viterbi)",
    "spconavi-astar": "SpCoNavi (A* approximation)",
    "hpp1": "HPP-I (path cost)",
    "hpp2": "HPP-II (path distance)",
    "spcotmhp": "SpCoTMHP",
}

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
TITLES = {"basic": "Table 4: basic task", "advanced": "Table 5: advanced task"}


def fmt_time(seconds: float) -> str:
    """Seconds with 3 significant digits (milliseconds below 1 s; no exponent)."""
    if seconds < 1.0:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds:.3g} s" if seconds < 1000 else f"{seconds:,.0f} s"


def markdown_table(kind: str, ours: Mapping[str, Mapping[str, float]], title: str | None = None) -> str:
    """One table: for each method the paper's row (where the paper has one) and ours, with our success rate and
    median / 95th-percentile online time."""
    if kind not in COLUMNS:
        raise ValueError(f"kind must be 'basic' or 'advanced', got {kind!r}")
    cols = COLUMNS[kind]
    head = ["Method", "Source"] + [c for _, c in cols] + ["Success", "Time (median / p95)", "Tasks"]
    lines = [f"### {title or TITLES[kind]}", "", "| " + " | ".join(head) + " |",
             "|" + "|".join(["---"] * 2 + ["---:"] * (len(head) - 2)) + "|"]
    order = [m for m in METHOD_LABELS if m in ours or m in PAPER[kind]]
    for method in order:
        label = METHOD_LABELS[method]
        paper = PAPER[kind].get(method)
        if paper is not None:
            cells = [label, "paper"] + [f"{paper[k]:.3f}" for k, _ in cols] + ["", fmt_time(paper["time_s"]), ""]
            lines.append("| " + " | ".join(cells) + " |")
        mine = ours.get(method)
        if mine is not None:
            cells = ([label if paper is None else "", "ours"] + [f"{mine[k]:.3f}" for k, _ in cols]
                     + [f"{mine['success']:.3f}",
                        f"{fmt_time(mine['time_median_s'])} / {fmt_time(mine['time_p95_s'])}",
                        str(mine["n_tasks"])])
            lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def reproduce_markdown(basic: Mapping, advanced: Mapping) -> str:
    """The markdown report of ``spcotmhp reproduce``: Tables 4 and 5 (paper rows beside ours) and how they were
    measured. ``basic`` / ``advanced`` are :func:`spcotmhp.evaluation.runner.evaluate` results."""
    import os
    import platform

    homes = ", ".join(basic["homes"]) or "none"
    n_basic = basic["mean"].get("spcotmhp", next(iter(basic["mean"].values()), {})).get("n_tasks", 0)
    n_adv = advanced["mean"].get("spcotmhp", next(iter(advanced["mean"].values()), {})).get("n_tasks", 0)
    lines = [
        "## Experiment I: the paper's Tables 4 and 5 beside ours",
        "",
        (f"Homes: {homes} ({n_basic} basic, {n_adv} advanced tasks; the paper used five SIGVerse homes, 418 and "
         f"3526 tasks). Parameters: {basic['params']}; seed {basic['seed']}. Times are online planning only "
         f"(precomputation excluded, as in the paper), median / 95th percentile per task, measured on "
         f"{platform.processor() or platform.machine()} with {os.cpu_count()} logical CPUs, Python "
         f"{platform.python_version()}; the paper's are Python on an Intel i7-6850K."),
        "",
        markdown_table("basic", basic["mean"]),
        markdown_table("advanced", advanced["mean"]),
        "Per home (SPL / N-SPL basic; WN-SPL advanced):",
        "",
    ]
    for home in basic["homes"]:
        b, a = basic["homes"][home], advanced["homes"].get(home, {})
        row = ", ".join(f"{METHOD_LABELS.get(m, m)} {v['spl']:.3f} / {v['n_spl']:.3f}"
                        + (f" / {a[m]['wn_spl']:.3f}" if m in a else "") for m, v in b.items())
        note = basic["notes"].get(home, {})
        lines.append(f"- {home} (adjacency: {note.get('adjacency', '?')}): {row}")
    moves = basic.get("moves") or {}
    if moves:
        lines += ["", "Moves: " + "; ".join(f"{METHOD_LABELS.get(m, m)} {v}" for m, v in moves.items())
                  + ". SPL's reference length l is an 8-connected geodesic."]
    return "\n".join(lines) + "\n"
