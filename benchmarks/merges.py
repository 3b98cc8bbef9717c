"""How often the default learner keeps a merge, before and after the taught-merge split (issue 35, item 5).

A *merge* is a taught name without a place of its own (``spcotmhp.learning.merges``). For every home and learner
seed, the default learner (``learn``'s settings: 10 runs of 100 sweeps, the run of highest log joint kept) is fitted
once; "paper" is its kept model, "split" the same model after the post-step (``learning.taught_split``), so the
two columns differ only by the departure. Per seed, over the homes of a family: merges per home and the share of
homes with at least one merge; then mean ± sd over the seeds. Splits are checked against the truth: a split is
*right* when the moved events and the events left at the place belong to different true rooms in the majority.
"kept: open (corridors) / few": merges the post-step left because no wall or door separates the names (in
brackets those of two corridor names: the battery's west and east corridor places share an open boundary by
construction) / a name was taught fewer than 3 times there.
"silent": pairs of differently named true rooms learned into one place (their events'
majority place) with neither name reported, paper / split (the report's blind spot; 0 is the acceptance).

Families: generated battery homes (``battery_home``: three bedrooms named alike, two-word corridor names, doors
0.6-1.0 m, a strip taught in unknown space), taught ``--teaches`` times per room (the issue's 4-6: 5 by default)
and 15 times; the bundled SIGVerse homes (15 teaches per place) and the same thinned to their first 5 teaches per
place; albert-b (real robot data, about 6 teaches per place).

    python benchmarks/merges.py --homes 0-11 --seeds 0-2
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _args import parse_seeds  # noqa: E402


def thinned(data, per_place: int):
    """``data`` with only the first ``per_place`` teaches of each true place (the event order kept)."""
    keep, seen = [], {}
    for e, p in enumerate(data.truth_place):
        seen[int(p)] = seen.get(int(p), 0) + 1
        if seen[int(p)] <= per_place:
            keep.append(e)
    idx = np.array(keep)
    return replace(
        data,
        name=f"{data.name}-{per_place}",
        positions=data.positions[idx],
        tokens=[data.tokens[e] for e in idx],
        features=None if data.features is None else data.features[idx],
        trajectory=None,
        event_steps=None,
        truth_place=data.truth_place[idx],
        truth_concept=None if data.truth_concept is None else data.truth_concept[idx],
    )


def families(homes: list[int], teaches: int) -> dict[str, list]:
    """Name -> list of zero-argument dataset makers."""
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.datasets.synthetic_battery import battery_home

    fams: dict[str, list] = {
        f"battery, {teaches} teaches/room": [lambda h=h: battery_home(h, events_per_room=teaches) for h in homes],
        "battery, 15 teaches/room": [lambda h=h: battery_home(h, events_per_room=15) for h in homes],
    }
    sig = ["3LDK_01", "3LDK_05", "3LDK_06"]
    fams["SIGVerse 3LDK (15/place)"] = [lambda n=n: load_bundled(n) for n in sig]
    fams["SIGVerse 3LDK thinned (5/place)"] = [lambda n=n: thinned(load_bundled(n), 5) for n in sig]
    fams["albert-b (real, ~6/place)"] = [lambda: load_bundled("albert-b", "ja")]
    return fams


def right_split(model_before, model_after, data) -> tuple[int, int]:
    """(right, made) splits of the post-step: right when the moved events' majority true room differs from
    the majority true room of the events left at the place."""
    right = made = 0
    before = np.asarray(model_before.learner["arrays"]["place"])
    after = np.asarray(model_after.learner["arrays"]["place"])
    for s in model_after.info.get("taught_split", {}).get("splits", []):
        moved = (before == s["place"]) & (after == s["new_place"])
        stayed = (before == s["place"]) & (after == s["place"])
        if data.truth_place is None or not moved.any() or not stayed.any():
            continue
        made += 1
        top = [int(np.bincount(data.truth_place[m]).argmax()) for m in (moved, stayed)]
        right += top[0] != top[1]
    return right, made


def silent_merges(model, data, found) -> int:
    """Pairs of differently named true rooms whose events' majority place is one place, with neither name
    reported (``found``): the merges nobody is told about."""
    if data.truth_place is None or data.place_names is None:
        return 0
    place = np.asarray(model.learner["arrays"]["place"])
    rooms = np.unique(data.truth_place)
    home = {int(r): int(np.bincount(place[data.truth_place == r]).argmax()) for r in rooms}
    said = {m.name for m in found} | {m.other for m in found}
    count = 0
    for i, a in enumerate(rooms):
        for b in rooms[i + 1 :]:
            na, nb = data.place_names[int(a)], data.place_names[int(b)]
            if home[int(a)] == home[int(b)] and na != nb and not ({na, nb} & said):
                count += 1
    return count


def run_one(make, seed: int) -> dict:
    """One home, one learner seed: merges before and after, splits made and right, post-step seconds."""
    import copy

    from spcotmhp.learning.selection import fit_runs
    from spcotmhp.learning.taught_split import split_selected
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
    from spcotmhp.teaching.questions import name_vocabulary, said_merges

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the bundled data's known warnings, saturated truncations
        data = make()
        sel = fit_runs(data, runs=10, seed=seed)
    before = copy.deepcopy(sel.model_)
    t0 = time.perf_counter()
    words, labels = name_vocabulary(before), place_labels(before, place_vocabulary(before))
    outcome = split_selected(sel, data, words, labels)
    seconds = time.perf_counter() - t0
    right, made = right_split(before, sel.model_, data)
    found_before, found_after = said_merges(before), said_merges(sel.model_)
    return {
        "before": len(found_before),
        "after": len(found_after),
        "silent_before": silent_merges(before, data, found_before),
        "silent_after": silent_merges(sel.model_, data, found_after),
        "no_wall": sum("no wall" in why for _, why in outcome.kept),
        "corridors": sum(
            "no wall" in why and "corridor" in m.name and "corridor" in m.other for m, why in outcome.kept
        ),
        "few": sum("fewer than" in why for _, why in outcome.kept),
        "splits": len(outcome.splits),
        "right": right,
        "checked": made,
        "walls": sum(s.between == "wall" for s in outcome.splits),
        "seconds": seconds,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--homes", default="0-11", help="battery home seeds, e.g. 0-11")
    ap.add_argument("--seeds", default="0-2", help="learner seeds, e.g. 0-2")
    ap.add_argument("--teaches", type=int, default=5, help="teaches per room of the first battery family")
    ap.add_argument("--only", default=None, help="run only the families whose name contains this text")
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    print(f"learner seeds {args.seeds}; default learner: 10 runs x 100 sweeps, log joint selection\n")
    head = (
        f"{'family':<34} {'homes':>5} {'merges/home paper':>18} {'split':>12} {'homes w/ merge paper':>21} "
        f"{'split':>12} {'splits':>6} {'right':>7} {'walls':>5} {'kept: open (corr.) / few':>25} {'silent':>7} "
        f"{'post-step s':>11}"
    )
    print(head)
    print("-" * len(head))
    for name, makers in families(parse_seeds(args.homes), args.teaches).items():
        if args.only and args.only not in name:
            continue
        per_seed = []
        for seed in seeds:
            rows = [run_one(make, seed) for make in makers]
            per_seed.append(rows)
        _print_row(name, len(makers), per_seed)
        sys.stdout.flush()


def _ms(values) -> str:
    v = np.asarray(values, dtype=float)
    return f"{v.mean():.2f} ± {v.std(ddof=1) if len(v) > 1 else 0.0:.2f}"


def _print_row(name: str, n: int, per_seed: list[list[dict]]) -> None:
    def per(key, share=False):
        return [np.mean([(r[key] > 0) if share else r[key] for r in rows]) for rows in per_seed]

    flat = [r for rows in per_seed for r in rows]
    print(
        f"{name:<34} {n:>5} {_ms(per('before')):>18} {_ms(per('after')):>12} {_ms(per('before', True)):>21} "
        f"{_ms(per('after', True)):>12} {sum(r['splits'] for r in flat):>6} "
        f"{sum(r['right'] for r in flat):>3}/{sum(r['checked'] for r in flat):<3} {sum(r['walls'] for r in flat):>5} "
        f"{sum(r['no_wall'] for r in flat):>5} ({sum(r['corridors'] for r in flat):>2}) / "
        f"{sum(r['few'] for r in flat):<4} "
        f"{sum(r['silent_before'] for r in flat):>3}/{sum(r['silent_after'] for r in flat):<3} "
        f"{max(r['seconds'] for r in flat):>11.2f}"
    )


if __name__ == "__main__":
    main()
