"""The online learner's state kept with a model (``SpatialConceptModel.learner``), and the model it implies.

A model folder saved with a learner state holds ``learner.json`` (sizes and settings) and ``learner.npz``:

* the counts behind every collapsed conditional (``collapsed.CollapsedState``): ``n_k``, ``sx``, ``sxx`` (place
  statistics), ``n_l``, ``n_lk`` (concepts, places per concept), ``W_lv``, ``bg_v``, ``z_tot`` (concept and
  background words), ``trans`` (event transitions), ``F_ld`` (image features, when the model has them);
* the events and their current assignments: ``X`` (E, 2), ``place``, ``concept`` (E,), the tokens as
  ``tok_ptr`` (E + 1,), ``tok_word``, ``tok_z`` (T,), and ``features`` (E, D) with ``has_features`` (E,);
  ``named`` (E,) marks the naming events (teaches, ``collapsed.py``), absent in folders without any.

The batch learner stores its final sample this way (``from_batch``), so teaching a batch-learned model continues
from that sample; its posterior means are unchanged by storing it. A model without a learner state (a supervised
fit, a folder written before this member existed) becomes a state of pseudo-counts that reproduce its posterior
means (``pseudo_state``): a Dirichlet posterior mean (c + n_m) / (M c + N) determines n given N, and N is taken
as the one that gives the least probable entry zero counts (exact whenever some entry had none; when every concept
is used, each concept's events are taken as its word count, one word per event); the Gaussians' counts follow
from phi's, and their sums from mu and Sigma.  Such a state has no events to revise.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.errors import TeachingError
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.connectivity import map_adjacency, psi_from_adjacency
from spcotmhp.learning.distributions import GaussianStats
from spcotmhp.learning.hmm import transition_counts
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.posterior import Priors, SufficientStats, posterior_mean_model

COUNTS = ("n_k", "sx", "sxx", "n_l", "n_lk", "W_lv", "bg_v", "z_tot", "trans")
EVENTS = ("X", "place", "concept", "tok_ptr", "tok_word", "tok_z")
STALE_INFO = ("log_joint", "mutual_information", "selected_run", "runs", "criterion")


# ---- the member ----------------------------------------------------------------------------------------------
def member_of(st: CollapsedState) -> dict:
    """The learner member of a model: settings and arrays (module docstring)."""
    arrays = {name: np.array(getattr(st, name)) for name in COUNTS + ("X", "place", "concept")}
    lengths = [len(t) for t in st.tokens]
    arrays["tok_ptr"] = np.concatenate(([0], np.cumsum(lengths))).astype(np.int64)
    arrays["tok_word"] = np.concatenate(st.tokens).astype(np.int64) if st.tokens else np.zeros(0, np.int64)
    arrays["tok_z"] = np.concatenate(st.z).astype(bool) if st.z else np.zeros(0, bool)
    if any(st.named):
        arrays["named"] = np.array([st.is_named(e) for e in range(st.E)], dtype=bool)
    if any(st.alone):
        arrays["alone"] = np.array([st.is_alone(e) for e in range(st.E)], dtype=bool)
    if st.walk_X is not None:
        arrays["walk_X"] = np.array(st.walk_X, dtype=float)
    if any(w != 1.0 for w in st.weight):
        arrays["weight"] = np.array([st.weight_of(e) for e in range(st.E)], dtype=float)
    if st.F_ld is not None and st.D is not None:
        arrays["F_ld"] = st.F_ld.copy()
        arrays["has_features"] = np.array([f is not None for f in st.features], dtype=bool)
        arrays["features"] = np.array([np.zeros(st.D) if f is None else f for f in st.features]).reshape(-1, st.D)
    return {"replay": bool(st.replay), "background": bool(st.background), "arrays": arrays}


def state_of_member(member: dict, model: SpatialConceptModel) -> CollapsedState:
    """The CollapsedState a model's learner member describes (arrays copied)."""
    a = member["arrays"]
    D = None if "F_ld" not in a else int(a["F_ld"].shape[1])
    st = CollapsedState(model.K, model.L, len(model.vocabulary), D, model.hyper, member["replay"], member["background"])
    for name in COUNTS + ("X",):
        setattr(st, name, np.array(a[name], dtype=float))
    st.place, st.concept = np.array(a["place"], dtype=np.int64), np.array(a["concept"], dtype=np.int64)
    ptr = a["tok_ptr"]
    st.tokens = [np.array(a["tok_word"][ptr[e] : ptr[e + 1]], dtype=np.int64) for e in range(len(st.place))]
    st.z = [np.array(a["tok_z"][ptr[e] : ptr[e + 1]], dtype=bool) for e in range(len(st.place))]
    st.features = [None] * len(st.place)
    st.named = [bool(v) for v in a["named"]] if "named" in a else [False] * len(st.place)
    st.alone = [bool(v) for v in a["alone"]] if "alone" in a else [False] * len(st.place)
    st.weight = [float(v) for v in a["weight"]] if "weight" in a else [1.0] * len(st.place)
    if "walk_X" in a:
        st.walk_X = np.array(a["walk_X"], dtype=float)
    if D is not None:
        st.F_ld = np.array(a["F_ld"], dtype=float)
        st.features = [
            np.array(f, dtype=float) if has else None for f, has in zip(a["features"], a["has_features"], strict=False)
        ]
    return st


def state_of_model(model: SpatialConceptModel, replay: bool, background: bool) -> tuple[CollapsedState, list[str]]:
    """The learner state a model continues from (its member, else pseudo-counts), and its vocabulary."""
    if model.learner is not None:
        return state_of_member(model.learner, model), list(model.vocabulary)
    return pseudo_state(model, replay, background), list(model.vocabulary)


# ---- from a batch sample or from posterior means -------------------------------------------------------------
def from_batch(
    obs,
    places: np.ndarray,
    concepts: np.ndarray,
    tok_ptr: np.ndarray,
    tok_word: np.ndarray,
    z: np.ndarray,
    K: int,
    L: int,
    hyper,
    replay: bool,
    background: bool,
) -> dict:
    """The learner member of a batch sample: events, assignments, switches, and the counts they imply."""
    D = None if obs.features is None else obs.features.shape[1]
    st = CollapsedState(K, L, len(obs.vocabulary), D, hyper, replay, background)
    st.X, st.place, st.concept = obs.X.copy(), places.astype(np.int64), concepts.astype(np.int64)
    st.tokens = [tok_word[tok_ptr[e] : tok_ptr[e + 1]].astype(np.int64) for e in range(obs.E)]
    st.z = [z[tok_ptr[e] : tok_ptr[e + 1]].astype(bool) for e in range(obs.E)]
    st.features = [None] * obs.E if D is None else [row.copy() for row in obs.features]
    st.named, st.alone, st.weight = [False] * obs.E, [False] * obs.E, [1.0] * obs.E
    g = GaussianStats.from_assignments(st.X, st.place, K)
    st.n_k, st.sx, st.sxx = g.n, g.sx, g.sxx
    st.n_l = np.bincount(st.concept, minlength=L).astype(float)
    np.add.at(st.n_lk, (st.concept, st.place), 1.0)
    ev = np.repeat(st.concept, np.diff(tok_ptr))
    zb = z.astype(bool)
    np.add.at(st.W_lv, (ev[zb], tok_word[zb]), 1.0)
    st.bg_v = np.bincount(tok_word[~zb], minlength=st.V).astype(float)
    st.z_tot = np.array([float((~zb).sum()), float(zb.sum())])
    if st.F_ld is not None and obs.features is not None:
        np.add.at(st.F_ld, st.concept, obs.features)
    st.trans = transition_counts(st.place, K, False)
    return member_of(st)


def _counts(p: np.ndarray, c: float, total: np.ndarray | None = None) -> np.ndarray:
    """Counts n of each row of Dirichlet posterior means p = (c + n) / (M c + N); N from ``total`` or, when
    None, the N that gives the row's least probable entry no counts."""
    M = p.shape[1]
    N = c / p.min(axis=1) - M * c if total is None else total
    return np.maximum(p * (M * c + np.maximum(N, 0.0))[:, None] - c, 0.0)


def pseudo_state(model: SpatialConceptModel, replay: bool, background: bool) -> CollapsedState:
    """Pseudo-counts that reproduce ``model``'s posterior means (module docstring)."""
    h, K, L = model.hyper, model.K, model.L
    act_k, act_l = np.asarray(model.active_places, bool), np.asarray(model.active_concepts, bool)
    D = None if model.theta is None else int(model.theta.shape[1])
    st = CollapsedState(K, L, len(model.vocabulary), D, h, replay, False)
    st.W_lv = _counts(model.W, h.beta) * act_l[:, None]
    st.n_l = _counts(model.pi[None], h.alpha)[0] * act_l
    if not (st.n_l[act_l] > 0).all():  # every concept used (pi has no empty entry): one token per event
        st.n_l = st.W_lv.sum(axis=1)
    st.n_lk = _counts(model.phi, h.gamma, st.n_l) * act_l[:, None] * act_k[None, :]
    st.n_k = st.n_lk.sum(axis=0)
    m0, V0 = np.asarray(h.m0, float), np.asarray(h.V0, float)
    kn, nun = h.kappa0 + st.n_k, h.nu0 + st.n_k
    st.sx = (kn[:, None] * model.mu - h.kappa0 * m0) * act_k[:, None]
    Vn = model.Sigma * np.where(nun > 3, nun - 3, nun + 3)[:, None, None]
    sxx = Vn - V0 - h.kappa0 * np.outer(m0, m0) + kn[:, None, None] * model.mu[:, :, None] * model.mu[:, None, :]
    st.sxx = sxx * act_k[:, None, None]
    st.z_tot = np.array([0.0, st.W_lv.sum()])
    if model.theta is not None:
        weight = model.info.get("feature_weight") or 1.0
        st.F_ld = _counts(model.theta, h.chi, st.n_l * weight) * act_l[:, None]
    psi = model.psi_learned if model.psi_learned is not None else model.psi
    R = _counts(psi, h.omega) * act_k[:, None] * act_k[None, :]
    st.trans = R / 2.0 if replay else R
    st.background = background
    return st


# ---- the model a state implies -------------------------------------------------------------------------------
def export_model(learner) -> SpatialConceptModel:
    """The posterior-mean model of an OnlineSpCoTMHP's state: Theta' given its counts (``posterior_mean_model``),
    psi from the map's territories (connectivity "auto" / "map", when there is a map) or from the transitions,
    the learner member attached, and the initial model's map, cost map and provenance kept."""
    st = learner.state_
    if st.E == 0 and learner.init_model is None:
        raise TeachingError("the online learner has no teaching event yet: teach one before asking for a model")
    priors = Priors.build(st.hyper, st.K, st.L, st.V, st.D)
    stats = SufficientStats(
        GaussianStats(st.n_k.copy(), st.sx.copy(), st.sxx.copy()),
        np.maximum(st.n_l, 0),
        np.maximum(st.n_lk, 0),
        None if st.F_ld is None else np.maximum(st.F_ld, 0),
        np.maximum(st.W_lv, 0),
        np.maximum(st.bg_v, 0) if st.background else None,
    )
    base = learner.init_model
    info = {k: v for k, v in (base.info if base is not None else {}).items() if k not in STALE_INFO}
    info.update(
        method="SpCoTMHP (online)",
        online={
            "events": st.E,
            "lag": learner.lag,
            "rejuvenation": learner.rejuvenation,
            "split_merge": learner.split_merge,
            "split_merge_events": learner.split_merge_events,
            "seed": learner.seed,
        },
        truncation_saturated=list(learner.truncation_saturated_),
        feature_weight=learner.feature_weight,
        reverse_replay=bool(st.replay),
        background_words=bool(st.background),
    )
    trans = st.trans + st.trans.T if st.replay else st.trans
    model = posterior_mean_model(priors, stats, np.maximum(trans, 0), learner.vocabulary_, st.hyper, info)
    model.psi_learned = model.psi.copy()
    model.map = learner.map_
    if base is not None:
        model.costmap = dict(base.costmap)
    model.info["psi_from"] = "hmm"
    if model.map is not None and learner.connectivity in ("auto", "map") and model.active_places.sum() > 1:
        model.psi = psi_from_adjacency(map_adjacency(model, model.map))
        model.info["psi_from"] = "map"
    model.learner = member_of(st)
    return model
