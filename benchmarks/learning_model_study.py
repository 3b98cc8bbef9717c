"""The learning-model study (docs/learning-model-study.md): how the model prices places, and what candidate
priors do to the battery (issue 9) and to online against batch learning (issue 15).

    python benchmarks/learning_model_study.py probes battery-7 battery-21 battery-42 albert-b
    python benchmarks/learning_model_study.py concentrations battery-7 albert-b
    python benchmarks/learning_model_study.py battery --variant size1 7 21 42 0 1 2 > size1.jsonl
    python benchmarks/learning_model_study.py learning --variant size1 albert-b 3LDK_01 > size1_learning.jsonl
    python benchmarks/learning_model_study.py criteria --cache fits 3 9 21 42 > criteria.jsonl

* ``probes``: for the true assignment and every pair of adjacent true places, the change of each term of the
  collapsed log target (``online_split_merge.log_target_terms``) when the two are merged (a room merge: the place
  and, when each holds its own name, the concept): positive totals are merges the model prefers to the truth.
  Word switches: a word heard in the events of more than half the true concepts is a background token.
* ``concentrations``: the posterior of the three Dirichlet-process concentrations (totals over the weak-limit
  truncation K = L = 20) given the true assignment, on a grid, prior Gamma(1, rate 1 / the paper's value): what
  resampling them (Escobar and West 1995; Teh et al. 2006) would move toward near the truth.
* ``battery``: learned advanced WN-SPL (via) per home (one JSON line each): a number is the seed of a generated
  home, a name a dataset (the bundled homes, seed 0 as ``spcotmhp battery 3LDK_01`` uses).
* ``learning``: ``online_eval.evaluate_online`` (5 seeds, online and batch) per home (one JSON line each).
* ``runs``: the learned fit of the battery (10 runs, ``experimental.fit_runs``) per home: each run's ARI of
  concepts and places and collapsed log joint, and the run kept, to tell a better sampler from a luckier choice.
* ``criteria``: the learned fit of the battery per home, once, and every run-selection criterion of
  ``experimental.selection.CRITERIA`` applied to its runs (docs/learning-model-study.md, section 6): each run's ARI and
  scores, the run each criterion keeps, and the battery's counts of every kept run (one JSON line per home;
  ``--cache DIR`` keeps the fitted runs, so that a second pass only scores and plans).
* ``table6``: Table 6's SpCoTMHP row (reverse replay; ``table6.evaluate_seeds``: 5 seeds x 10 runs x 100 sweeps,
  the means over each seed's runs, mean and sd over seeds) per home.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import types
import warnings

import numpy as np
from scipy.special import gammaln

from spcotmhp.commands.datasets import load_dataset_arg
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.evaluation.battery import evaluate_home
from spcotmhp.evaluation.context import place_adjacency
from spcotmhp.evaluation.online_eval import evaluate_online
from spcotmhp.evaluation.table6 import concept_truth, evaluate_seeds, score_run
from spcotmhp.experimental import fit_runs, variant_for
from spcotmhp.experimental import selection as research
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.hmm import transition_counts
from spcotmhp.learning.learner_state import from_batch, state_of_member
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.online import log_new_place_density
from spcotmhp.learning.online_split_merge import log_target_terms
from spcotmhp.learning.selection import MultiRunSelector

# name: (priors, settings of the batch learner's fit, research ones by name: spcotmhp.experimental.fit_runs); the
# online learner has its moves in every variant
SWITCH_MODE = {"criterion": "log_joint_switch_mode"}
VARIANTS: dict[str, tuple[dict, dict]] = {
    "paper": ({}, {}),
    "paper+sm": ({}, {"split_merge": True}),
    "paper+switch-mode": ({}, SWITCH_MODE),
    "paper+switch-marginal": ({}, {"criterion": "log_joint_switch_marginal"}),
    "paper+tail-mean": ({}, {"criterion": "log_joint_tail_mean"}),
    "paper+held-out": ({}, {"criterion": "held_out_words"}),
    "size1": ({"place_size": 1.0}, {}),
    "size1+sm": ({"place_size": 1.0}, {"split_merge": True}),
    "size1+switch-mode": ({"place_size": 1.0}, SWITCH_MODE),
    "size0.75": ({"place_size": 0.75}, {}),
    "size1.5": ({"place_size": 1.5}, {}),
    # section 8: the opt-in "one place, one name" term, eta = 1 (stated before measuring), 0.1 and 10 (sensitivity)
    "onename1": ({"place_concepts": 1.0}, {}),
    "onename0.1": ({"place_concepts": 0.1}, {}),
    "onename10": ({"place_concepts": 10.0}, {}),
    "onename1-from0": ({"place_concepts": 1.0}, {"term_from": 0.0}),  # the term from the first sweep
    "onename1-select": ({"place_concepts": 1.0}, {"term_from": 1.0}),  # the log joint only
    # section 9: the opt-in off-name term, lambda = 1 (stated before measuring), 0.5 and 2 (sensitivity)
    "offname1": ({"off_name": 1.0}, {}),
    "offname0.5": ({"off_name": 0.5}, {}),
    "offname2": ({"off_name": 2.0}, {}),
    "offname1-from0.5": ({"off_name": 1.0}, {"term_from": 0.5}),  # the term after half the sweeps
    "offname1-select": ({"off_name": 1.0}, {"term_from": 1.0}),  # the log joint only
}
PAPER_TOTALS = {"alpha": 10.0, "gamma": 1.0, "omega": 10.0}


def load(name: str) -> Dataset:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return battery_home(int(name.split("-")[1])) if name.startswith("battery-") else load_dataset_arg(name, None)


def truth(data: Dataset) -> tuple[np.ndarray, np.ndarray]:
    """The true places and concepts, relabelled 0, 1, ..."""
    return (
        np.unique(np.asarray(data.truth_place), return_inverse=True)[1],
        np.unique(concept_truth(data), return_inverse=True)[1],
    )


def background_words(obs: Observations, concepts: np.ndarray) -> np.ndarray:
    """(V,) the words heard in the events of more than half the (true) concepts."""
    C = int(concepts.max()) + 1
    heard = np.zeros((C, obs.words.shape[1]))
    np.add.at(heard, concepts, obs.words > 0)
    return (heard > 0).sum(axis=0) > C / 2


def state_of(
    data: Dataset, obs: Observations, places, concepts, hyper: Hyperparameters, background: np.ndarray
) -> CollapsedState:
    """The collapsed state of an assignment (K = L = 20), ``background`` words as background tokens, the map's
    density for a place's first position."""
    tokens = CollapsedConceptSampler(obs.words, obs.features, False, np.random.default_rng(0))
    member = from_batch(
        obs, places, concepts, tokens.t_ptr, tokens.t_word, ~background[tokens.t_word], 20, 20, hyper, True, True
    )
    st = state_of_member(member, types.SimpleNamespace(K=20, L=20, vocabulary=obs.vocabulary, hyper=hyper))
    st.log_new_place = log_new_place_density(data.map)
    return st


def probes(name: str, hyper: Hyperparameters) -> dict:
    """Room merges of adjacent true places against the truth: the change of each log-target term."""
    data = load(name)
    obs = Observations.from_dataset(data)
    tp, tc = truth(data)
    bg = background_words(obs, tc)
    base = log_target_terms(state_of(data, obs, tp, tc, hyper, bg))
    adjacency, _ = place_adjacency(data)
    names = data.place_names or [str(k) for k in range(tp.max() + 1)]
    rows = []
    for a in range(tp.max() + 1):
        for b in range(a + 1, tp.max() + 1):
            if not adjacency[a, b]:
                continue
            ca, cb = tc[tp == a][0], tc[tp == b][0]
            own = ca != cb and (tp[tc == ca] == a).all() and (tp[tc == cb] == b).all()
            merged = log_target_terms(
                state_of(data, obs, np.where(tp == b, a, tp), np.where(tc == cb, ca, tc) if own else tc, hyper, bg)
            )
            delta = {k: merged[k] - base[k] for k in base}
            rows.append({"pair": f"{names[a]} + {names[b]}", "total": float(sum(delta.values())), **delta})
    rows.sort(key=lambda r: -r["total"])
    return {"home": name, "pairs": len(rows), "preferred": int(sum(r["total"] > 0 for r in rows)), "rows": rows}


def concentrations(name: str) -> dict:
    """MAP and posterior mean of each concentration total given the true assignment (module docstring)."""
    data = load(name)
    tp, tc = truth(data)
    K = L = 20
    counts = {
        "alpha": np.bincount(tc, minlength=L)[None].astype(float),
        "gamma": np.zeros((L, K)),
        "omega": transition_counts(tp, K, False).astype(float),
    }
    np.add.at(counts["gamma"], (tc, tp), 1.0)
    grid = np.exp(np.linspace(np.log(0.01), np.log(1000.0), 400))
    out = {"home": name}
    for what, n in counts.items():
        m = n.shape[1]
        lp = np.array(
            [
                np.sum(gammaln(a) - gammaln(a + n.sum(axis=1))) + np.sum(gammaln(a / m + n) - gammaln(a / m))
                for a in grid
            ]
        )
        lp -= grid / PAPER_TOTALS[what]
        w = np.exp(lp - lp.max())
        out[what] = {"paper": PAPER_TOTALS[what], "map": float(grid[np.argmax(lp)]), "mean": float(w @ grid / w.sum())}
    return out


def runs(home: str, hyper: Hyperparameters, fit: dict) -> dict:
    """Every run of the learned fit of a home (module docstring)."""
    data, seed = (battery_home(int(home)), int(home)) if home.isdigit() else (load(home), 0)
    return run_rows(data, fit_runs(data, seed=seed, hyper=hyper, **fit))


def battery(home: str, hyper: Hyperparameters, fit: dict) -> dict:
    """The battery of a home's learned fit (``evaluate_home``'s own fit, the same runs), with every run's ARI."""
    data, seed = (battery_home(int(home)), int(home)) if home.isdigit() else (load(home), 0)
    sel = fit_runs(data, seed=seed, hyper=hyper, **fit)
    row = evaluate_home(data, "learned", seed, model=sel.model_).to_dict()
    row["runs"] = run_rows(data, sel)
    return row


def run_rows(data: Dataset, sel: MultiRunSelector) -> dict:
    """Each run's concept and place ARI and log joint, and the index of the kept run."""
    scores = [score_run(data, e.places_, e.concepts_) for e in sel.estimators_]
    return {
        "home": data.name,
        "kept": sel.best_index_,
        "ari_c": [s["ari_c"] for s in scores],
        "ari_i": [s["ari_i"] for s in scores],
        "log_joint": [float(e.log_joint_) for e in sel.estimators_],
        "acceptance": [e.model_.info.get("off_name_acceptance") for e in sel.estimators_],
    }


def criteria(home: str, hyper: Hyperparameters, fit: dict, cache: str | None) -> dict:
    """Every criterion on one learned fit of a home (module docstring)."""
    import pickle
    from pathlib import Path

    data, seed = (battery_home(int(home)), int(home)) if home.isdigit() else (load(home), 0)
    path = None if cache is None else Path(cache) / f"{data.name}.pkl"
    if path is not None and path.exists():
        sel: MultiRunSelector = pickle.loads(path.read_bytes())
    else:
        sel = fit_runs(data, seed=seed, hyper=hyper, **fit)
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(pickle.dumps(sel))
    scores = [score_run(data, e.places_, e.concepts_) for e in sel.estimators_]
    out: dict = {"home": data.name, "ari_c": [s["ari_c"] for s in scores], "ari_i": [s["ari_i"] for s in scores]}
    out["scores"] = {c: [float(v) for v in research.scores(sel, c)] for c in research.CRITERIA[1:]}
    out["kept"] = {c: int(np.argmax(v)) for c, v in out["scores"].items()}
    out["battery"] = {}
    for c, r in out["kept"].items():
        if str(r) not in out["battery"]:
            sel.choose(research.criterion(c))
            out["battery"][str(r)] = evaluate_home(data, "learned", seed, model=sel.model_).to_dict()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=("probes", "concentrations", "battery", "runs", "criteria", "learning", "table6"))
    ap.add_argument("homes", nargs="+", help="battery seeds (battery) or dataset names")
    ap.add_argument("--variant", default="paper", choices=tuple(VARIANTS))
    ap.add_argument("--cache", default=None, help="criteria: folder of the fitted runs (pickles)")
    args = ap.parse_args()
    priors, fit = VARIANTS[args.variant]
    hyper = Hyperparameters(**priors)
    variant = variant_for(hyper, fit.get("split_merge", False))  # the sampler variant, spcotmhp.experimental
    warnings.simplefilter("ignore")
    for home in args.homes:
        t0 = time.perf_counter()
        if args.what == "probes":
            row = probes(home, hyper)
        elif args.what == "concentrations":
            row = concentrations(home)
        elif args.what == "battery":
            row = battery(home, hyper, fit)
        elif args.what == "runs":
            row = runs(home, hyper, fit)
        elif args.what == "criteria":
            row = criteria(home, hyper, fit, args.cache)
        elif args.what == "table6":
            start = {"term_from": fit["term_from"]} if "term_from" in fit else {}
            row = evaluate_seeds(load(home), methods=("tmhp_replay",), hyper=hyper, variant=variant, **start)
            row = row["tmhp_replay"]
        else:
            row = evaluate_online(load(home), seeds=5, hyper=hyper, batch_params={"variant": variant})
        row.update(variant=args.variant, seconds=time.perf_counter() - t0)
        sys.stdout.write(json.dumps(row) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
