"""Why answered questions do not split a merged place (issue 24): the paper's model, as the judge, against the split.

For each generated home (``synthetic_battery.battery_home``, learned with the battery's learned parameters): the
largest learned place that holds the events of two true places a and b, and the change of the collapsed log target
(``online_split_merge.log_target``: Eqs. 5-17 marginals, Eq. 9's rescaling; token switches at their local mode)
when that place is split as the truth splits it (b's events to a new place; to a new concept too when a and b
have different names), term by term (``log_target_terms``), after 0, 1 and 3 answers (the true names at teaching
positions of a, b, a drawn with the seed, each taught with ``teaching.teach.teach`` as an ordinary teach; an
answer at b moves with b). A negative total: the model prefers the merge, so no answer taught as one more event,
and no move judged by the model, splits it.

    python benchmarks/questions_why.py --seeds 9,10,32,36,50,55,65,70
"""

from __future__ import annotations

import argparse
import copy
import json
import warnings

import numpy as np


def split_gain(model, a_events: np.ndarray, b_events: np.ndarray, same_name: bool) -> dict[str, float]:
    """log_target terms of the truth split minus those of ``model``'s state (module docstring)."""
    from spcotmhp.learning.learner_state import state_of_member
    from spcotmhp.learning.online import log_new_place_density
    from spcotmhp.learning.online_split_merge import log_target_terms

    st = state_of_member(model.learner, model)
    st.log_new_place = log_new_place_density(model.map)
    merged = copy.deepcopy(st)
    merged.switch_mode()
    new_k = int(np.flatnonzero(st.n_k <= 0)[0])
    new_l = None if same_name else int(np.flatnonzero(st.n_l <= 0)[0])
    for j in b_events:
        j = int(j)
        concept = int(st.concept[j]) if new_l is None else new_l
        st.move(j, -1.0)
        st.place[j], st.concept[j] = new_k, concept
        st.move(j, 1.0)
    st.switch_mode()
    before, after = log_target_terms(merged), log_target_terms(st)
    out = {t: float(after[t] - before[t]) for t in before}
    out["total"] = sum(out.values())
    return out


def run_home(seed: int) -> dict | None:
    from spcotmhp.datasets.synthetic_battery import battery_home
    from spcotmhp.evaluation.context import build_context
    from spcotmhp.teaching.teach import teach

    data = battery_home(seed)
    model = build_context(data, "learned", 0).model
    place = np.asarray(model.learner["arrays"]["place"])
    truth = np.asarray(data.truth_place)
    best = None
    for k in np.unique(place):
        counts = np.bincount(truth[place == k], minlength=len(data.place_names))
        top = np.argsort(-counts)[:2]
        if counts[top[1]] >= 3 and (best is None or counts[top].sum() > best[0]):
            best = (counts[top].sum(), int(k), int(top[0]), int(top[1]))
    if best is None:
        return None
    _, k, a, b = best
    names = (str(data.place_names[a]), str(data.place_names[b]))
    rng = np.random.default_rng(seed)
    row = {"home": data.name, "place": k, "true places": names, "events": int(best[0]), "after answers": {}}
    answered: list[int] = []
    for n_answers in (0, 1, 3):
        while len(answered) < n_answers:
            t = (a, b, a)[len(answered)]
            j = int(rng.choice(np.flatnonzero(truth == t)))
            x, y = data.positions[j]
            model = teach(model, [{"x": x, "y": y, "utterance": f"this is the {data.place_names[t]}"}]).model
            answered.append(t)
        place = np.asarray(model.learner["arrays"]["place"])
        owner = np.concatenate([truth, answered])
        in_k = place == place[np.flatnonzero(truth == a)[0]]
        a_events, b_events = np.flatnonzero(in_k & (owner == a)), np.flatnonzero(in_k & (owner == b))
        row["after answers"][n_answers] = {
            t: round(v, 1) for t, v in split_gain(model, a_events, b_events, names[0] == names[1]).items()
        }
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="9,10,32,36,50,55,65,70")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rows = []
    for s in (int(v) for v in args.seeds.split(",")):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            row = run_home(s)
        if row is None:
            continue
        rows.append(row)
        if not args.json:
            terms = row["after answers"]
            print(
                f"{row['home']:12s} {' + '.join(row['true places']):28s} {row['events']:3d} events; split - merged "
                f"(nats) after 0/1/3 answers: {terms[0]['total']:+.1f} / {terms[1]['total']:+.1f} / "
                f"{terms[3]['total']:+.1f}; after 3: "
                + ", ".join(f"{t} {v:+.1f}" for t, v in terms[3].items() if t != "total" and abs(v) >= 0.05),
                flush=True,
            )
    if args.json:
        print(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
