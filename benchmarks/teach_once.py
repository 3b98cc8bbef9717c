"""Teaching once is enough (issue 24, item 2): one teach of a new name, then "go to NAME" ends where it was taught.

For each generated home (``generate_environment``, kinds flat / house / office in turn, seeds ``--seeds``) the
supervised fit, then ``--spots`` free robot cells (finite inflated cost) drawn from a seeded stream outside every
active place's 2-sigma ellipse; at each, "this is the study" is taught once (``teaching.teach.teach``, from the
fit each time) and "go to the study" planned from the first true place's position. Counted: a new place, the
plan's end within 1 m of the spot, and the distances of the others. With ``--bundled`` also 3LDK_06 taught inside
its places (spots inside some active place's 2-sigma ellipse).

    python benchmarks/teach_once.py --seeds 0-29 --spots 4 --bundled
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _args import parse_seeds  # noqa: E402

KINDS = ("flat", "house", "office")


def spots(model, n: int, seed: int, inside: bool = False) -> np.ndarray:
    """``n`` robot cells (finite inflated cost) outside (``inside``: inside) every active place's 2-sigma ellipse,
    drawn from a seeded stream."""
    from spcotmhp.metric.costmap import inflate
    from spcotmhp.planning.places import mahalanobis2

    safe = np.argwhere(np.isfinite(inflate(model.map, **model.costmap).log_p))
    xy = model.map.cell_to_world(safe)
    act = np.flatnonzero(model.active_places)
    d2 = mahalanobis2(xy, model.mu[act], model.Sigma[act]).min(axis=1)
    ok = np.flatnonzero(d2 <= 4.0) if inside else np.flatnonzero(d2 > 4.0)
    if not len(ok):
        return np.empty((0, 2))
    pick = np.random.default_rng(seed).choice(ok, size=min(n, len(ok)), replace=False)
    return xy[pick]


def teach_at(model, start, xy) -> dict:
    """Teach "this is the study" once at ``xy`` and plan "go to the study" from ``start``."""
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.teaching.teach import planner_for, teach

    taught = teach(model, [{"x": float(xy[0]), "y": float(xy[1]), "utterance": "this is the study"}])
    reply = taught.summary()
    planner, _ = planner_for(taught.model)
    try:
        end = planner.plan("go to the study", start).path[-1]
        dist = float(np.hypot(*(end - np.asarray(xy))))
    except SpcotmhpError as exc:
        dist, reply["refused"] = float("inf"), str(exc)
    return {
        "x": float(xy[0]),
        "y": float(xy[1]),
        "new_place": reply["new_place"],
        "named": reply["named"],
        "distance": dist,
        "reply": reply["message"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="0-29")
    ap.add_argument("--spots", type=int, default=4)
    ap.add_argument("--bundled", action="store_true", help="also 3LDK_06, taught inside its places")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.datasets.synthetic import generate_environment
    from spcotmhp.learning.supervised import fit_supervised

    rows = []
    homes = [(generate_environment(KINDS[s % 3], seed=s), s, False) for s in parse_seeds(args.seeds)]
    if args.bundled:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            homes.append((load_bundled("3LDK_06"), 0, True))
    for data, seed, inside in homes:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fit_supervised(data)
            model.map = data.map
            truth0 = data.positions[data.truth_place == data.truth_place[0]].mean(axis=0)
            from spcotmhp.metric.costmap import inflate
            from spcotmhp.metric.snap import snap

            free = np.isfinite(inflate(model.map, **model.costmap).log_p)
            start = model.map.cell_to_world(snap(free, model.map.world_to_cell(truth0[None]))[0])
            taught = spots(model, args.spots, seed, inside)
            if inside:  # the audit's spot (tests/teaching/test_teach.py: STUDY), in a bedroom, first
                taught = np.vstack([[5.5, -4.0], taught])
            for xy in taught:
                row = teach_at(model, start, xy)
                row["home"] = data.name + (" (inside a place)" if inside else "")
                rows.append(row)
                if not args.json:
                    print(
                        f"{row['home']:28s} ({row['x']:7.2f}, {row['y']:7.2f}) new place {row['new_place']!s:5s}"
                        f" end {row['distance']:.2f} m from the spot; {row['reply']}",
                        flush=True,
                    )
    for group, sel in (
        ("generated", [r for r in rows if "inside" not in r["home"]]),
        ("3LDK_06 inside", [r for r in rows if "inside" in r["home"]]),
    ):
        if not sel:
            continue
        far = sorted(r["distance"] for r in sel if r["distance"] > 1.0)
        summary = {
            "group": group,
            "spots": len(sel),
            "new_place": sum(r["new_place"] for r in sel),
            "joined_not_naming": sum(not r["new_place"] and not r["named"] for r in sel),
            "within_1m": sum(r["distance"] <= 1.0 for r in sel),
            "farther_m": [round(d, 2) for d in far],
            "farther_naming_m": [round(r["distance"], 2) for r in sel if r["distance"] > 1.0 and r["named"]],
        }
        print(json.dumps(summary))
    if args.json:
        print(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
