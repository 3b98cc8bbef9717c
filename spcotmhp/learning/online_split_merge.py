"""Split-merge moves for the online learner: Metropolis-Hastings proposals that split one place, concept or room
in two, or merge two into one, in a single step.

Why: the online learner's Gibbs steps (``collapsed.py``) move one event at a time.  When two rooms were put in
one place early in a stream (few events, a broad Gaussian covering both), moving a single event out costs more
than it gains, so the merge stays however long the stream runs; a name spread over several concepts needs many
unlikely single steps to gather.

Algorithm: the sequentially-allocated merge-split sampler (Dahl, "Sequentially-allocated merge-split sampler for
conjugate and nonconjugate Dirichlet process mixture models", tech. report, Texas A&M, 2005), the one-pass variant
of Jain and Neal's restricted-Gibbs split-merge ("A split-merge Markov chain Monte Carlo procedure for the
Dirichlet process mixture model", JCGS 13, 2004).  One move has a ``kind`` and two events a != b chosen without
looking at the assignments.  Kinds: "place" (the places i; concepts and word switches held fixed), "concept" (C;
places held fixed) and "both" (a room: a place and a concept that hold exactly the same events, split or merged
together: when two rooms share one place and one concept, a place split alone leaves one concept over two places,
which can be less probable than either end, so the split is not accepted: two rooms of 3LDK_06 that the learner
without these moves put in one place and concept (seed 4), split along the true rooms, lose 5.7 nats of log pi
as a place split and gain 6.2 as a room split).

* a and b share a label c: **split**.  Every other event of c and b are taken out of the counts, b goes to a
  label c' drawn uniformly from the m labels that hold nothing (for "both", a place and a concept), a stays in c,
  and the others are put back one at a time, each in c or c' with the learner's own collapsed conditional
  (Eqs. 5-17, ``CollapsedState.log_conditional``) restricted to the two given the events put back so far; q is
  the product of those probabilities.  Accepted with probability min(1, pi(split) / pi(now) * m / q).
* a has c and b has d != c: **merge** of d's events into c.  q of the reverse split (the allocation above, from
  the merged state, giving exactly the current two groups) is computed by replaying it; accepted with probability
  min(1, pi(merged) / pi(now) * q / m'), m' the number of empty labels after the merge.

The events are put back nearest first (by the distance to the nearer of a and b), not in Dahl's random order:
a place is a region, so the first events sort themselves around the two anchors and the groups then pull the rest
their way.  Any order that depends only on the data and on (a, b) keeps the move exact.  That reason, not a
measurement, chose it (a small comparison on albert-b found the two orders within the spread of seeds:
docs/results.md).

pi is ``log_target``: the collapsed log joint the batch learner selects runs by (``posterior.log_joint``: the NIW
marginal of each place's positions and the Dirichlet-multinomial marginals of C, i given C, the words, the image
features, the background words and switches, and the forward transitions of the event sequence; reverse replay
changes how psi is drawn, not the data) times the two factors the online learner's Gibbs step has beyond it, so
that both kinds of step aim at one distribution: Eq. 9's unigram rescaling, 1 / sum_c phi_c(i_e) per event with
phi at its posterior mean, and, when the learner has a map, a place's first position counted at 1 / (known area)
instead of the NIW prior predictive (``CollapsedState.log_new_place``; the predictive is taken at the place's
mean, since a partition has no first event; with kappa0 = 1e-3 it is nearly flat over a home, so this is close).

The labels of the weak-limit truncation are exchangeable, so moves act on labelled states: the 1/m choice of the
new label and the label a merge keeps (a's) give every move a reverse of known probability.  No move is made on a
state with pseudo-counts (a model loaded without its events: ``learner_state``), whose labels hold counts that no
event carries, nor, for "both", on a place and concept that are not each other's only ones (the condition holds
before and after any such move, so each move's reverse is available).  A move touches only the events of the two
labels (``max_events`` bounds them, for a split and for its reverse merge alike, so the bound does not bias pi) and
costs one conditional per event plus one or two evaluations of pi, O(K L + L V + L D + K^2), whatever the number
of events.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.distributions import GaussianStats
from spcotmhp.learning.posterior import Priors, SufficientStats, log_joint_terms

KINDS = ("place", "concept", "both")
_SAVED = ("n_k", "sx", "sxx", "n_l", "n_lk", "W_lv", "bg_v", "z_tot", "trans", "F_ld", "place", "concept")


def log_target(st: CollapsedState) -> float:
    """log pi of the state's assignments up to a constant (module docstring): the sum of ``log_target_terms``."""
    return float(sum(log_target_terms(st).values()))


def state_stats(st: CollapsedState) -> SufficientStats:
    """The sufficient statistics a learner state holds (its count arrays, not copies)."""
    return SufficientStats(
        GaussianStats(st.n_k, st.sx, st.sxx), st.n_l, st.n_lk, st.F_ld, st.W_lv, st.bg_v if st.background else None
    )


def log_target_terms(st: CollapsedState) -> dict[str, float]:
    """The terms of ``log_target``: those of ``posterior.log_joint_terms`` ("positions" with a place's first
    position counted at the map's density when the state has one), plus "rescaling" (Eq. 9's unigram rescaling)."""
    priors = Priors.build(st.hyper, st.K, st.L, st.V, st.D)
    terms = log_joint_terms(priors, state_stats(st), st.trans)
    phi = priors.phi.posterior_mean(st.n_lk)
    terms["rescaling"] = -float(st.n_k @ np.log(phi.sum(axis=0)))  # Eq. 9 rescaling
    used = st.n_k > 0
    if st.log_new_place is not None and used.any():
        mean = st.sx[used] / st.n_k[used, None]
        one = GaussianStats(np.ones(len(mean)), mean, mean[:, :, None] * mean[:, None, :])
        terms["positions"] += used.sum() * st.log_new_place - priors.gauss.log_marginal(one)
    return terms


def propose(
    st: CollapsedState,
    kind: str,
    a: int,
    b: int,
    rng: np.random.Generator,
    max_events: int | None = None,
    log_pi: float | None = None,
) -> tuple[bool | None, float | None]:
    """One split-merge move of ``kind`` for events a != b (module docstring); ``log_pi``: ``log_target(st)`` when
    the caller knows it. Returns whether the move was accepted (None when no move applies: no empty label for a
    split; pseudo-counts; for "both", a place and concept that are not each other's only ones; more than
    ``max_events`` events in the two labels) and ``log_target`` of the state it leaves (None if not computed)."""
    if _pseudo(st):
        return None, log_pi
    c, d = _label(st, kind, a), _label(st, kind, b)
    if kind == "both" and not (_pure(st, c) and _pure(st, d) and (c == d or (c[0] != d[0] and c[1] != d[1]))):
        return None, log_pi
    group = np.flatnonzero(_member(st, kind, c) | _member(st, kind, d))
    if max_events is not None and len(group) > max_events:
        return None, log_pi
    empties = [np.flatnonzero(counts <= 0) for counts in _counts(st, kind)]
    if c == d:
        if not all(len(x) for x in empties):
            return None, log_pi
        picks = tuple(int(x[rng.integers(len(x))]) for x in empties)
        new = picks[0] if kind != "both" else picks
        log_ratio_q = sum(np.log(len(x)) for x in empties)
    else:
        new = d
        log_ratio_q = -sum(np.log(len(x) + 1) for x in empties)  # the merged state's empty labels, d's among them
    rest = np.array([e for e in group if e != a and e != b], dtype=np.int64)
    near = np.minimum(*(np.linalg.norm(st.X[rest] - st.X[x], axis=1) for x in (a, b)))
    order = rest[np.argsort(near, kind="stable")]
    saved = _save(st)
    before = log_target(st) if log_pi is None else log_pi
    log_u = np.log(rng.random())
    if c == d:
        log_ratio_q -= allocate(st, kind, a, b, new, order, rng)
        after = log_target(st)
    else:
        _relabel(st, kind, np.flatnonzero(_member(st, kind, d)), c)
        after = log_target(st)
        # q <= 1, so a merge whose ratio is below log_u without q is rejected whatever q is: skip computing it
        if after - before + log_ratio_q >= log_u:
            merged = _save(st)
            _restore(st, saved)
            log_ratio_q += allocate(st, kind, a, b, new, order, None)
            _restore(st, merged)
        else:
            log_ratio_q = -np.inf
    if log_u < after - before + log_ratio_q:
        return True, after
    _restore(st, saved)
    return False, before


def allocate(
    st: CollapsedState,
    kind: str,
    a: int,
    b: int,
    new,
    order: np.ndarray,
    rng: np.random.Generator | None,
) -> float:
    """The sequential allocation of a split: events ``order`` and b taken out, b put in ``new``, then each event
    of ``order`` put in a's label or ``new`` by its collapsed conditional restricted to the two; returns log q.
    With ``rng`` the labels are drawn; without, each event gets back the label it had (the probability of the
    current split, for the reverse of a merge)."""
    c = _label(st, kind, a)
    kept = {int(e): (int(st.place[e]), int(st.concept[e])) for e in (b, *order)}
    for e in kept:
        st.move(e, -1.0)
    _put(st, kind, b, kept[b], new)
    log_q = 0.0
    for e in order:
        e = int(e)
        cells = [_assigned(kind, kept[e], label) for label in (c, new)]
        cols = sorted({cells[0][1], cells[1][1]})  # one column when the concept is fixed
        cond = st.log_conditional(e, concepts=np.asarray(cols))
        two = np.array([cond[k, cols.index(l)] for k, l in cells])
        two -= np.logaddexp(two[0], two[1])
        if rng is not None:
            pick = int(rng.random() >= np.exp(two[0]))
        else:
            pick = int(kept[e] == cells[1])
        log_q += float(two[pick])
        _put(st, kind, e, kept[e], (c, new)[pick])
    return log_q


# ---- labels of a kind ----------------------------------------------------------------------------------------
def _label(st: CollapsedState, kind: str, e: int):
    """Event e's label: its place, its concept or, for "both", the pair."""
    return {"place": int(st.place[e]), "concept": int(st.concept[e])}.get(kind, (int(st.place[e]), int(st.concept[e])))


def _member(st: CollapsedState, kind: str, label) -> np.ndarray:
    """Mask of the events with ``label``."""
    if kind == "both":
        return (st.place == label[0]) & (st.concept == label[1])
    return (st.place if kind == "place" else st.concept) == label


def _counts(st: CollapsedState, kind: str) -> tuple[np.ndarray, ...]:
    """The event counts per label that a split's new label is drawn among (those that hold nothing)."""
    return {"place": (st.n_k,), "concept": (st.n_l,)}.get(kind, (st.n_k, st.n_l))


def _pure(st: CollapsedState, label: tuple[int, int]) -> bool:
    """Whether the place and concept of ``label`` hold exactly the same events (a room and its one name)."""
    k, l = label
    return bool(st.n_k[k] == st.n_l[l] == st.n_lk[l, k])


def _assigned(kind: str, kept: tuple[int, int], label) -> tuple[int, int]:
    """(place, concept) of an event whose fixed part is ``kept`` and whose ``kind`` label is ``label``."""
    return {"place": (label, kept[1]), "concept": (kept[0], label)}.get(kind, label)


def _put(st: CollapsedState, kind: str, e: int, kept: tuple[int, int], label) -> None:
    """Put event e (out of the counts) back with its fixed assignment and ``label`` for ``kind``."""
    st.place[e], st.concept[e] = _assigned(kind, kept, label)
    st.move(e, 1.0)


def _relabel(st: CollapsedState, kind: str, events: np.ndarray, label) -> None:
    """Give ``events`` the ``kind`` label ``label`` (their other label kept)."""
    for e in events:
        kept = (int(st.place[e]), int(st.concept[e]))
        st.move(int(e), -1.0)
        _put(st, kind, int(e), kept, label)


def _save(st: CollapsedState) -> dict:
    """Copies of the counts and assignments a move changes."""
    return {name: np.copy(getattr(st, name)) for name in _SAVED if getattr(st, name) is not None}


def _restore(st: CollapsedState, saved: dict) -> None:
    for name, value in saved.items():
        setattr(st, name, np.copy(value))


def _pseudo(st: CollapsedState) -> bool:
    """Whether the counts hold more than the events (pseudo-counts of a model loaded without its events)."""
    events = sum(st.weight_of(e) for e in range(st.E))  # an event of weight w counts as w (``collapsed.py``)
    tokens = sum(len(t) * st.weight_of(e) for e, t in enumerate(st.tokens))
    return not (
        np.isclose(st.n_k.sum(), events) and np.isclose(st.n_l.sum(), events) and np.isclose(st.z_tot.sum(), tokens)
    )


def settle_name(st: CollapsedState, e: int) -> bool:
    """A block step for the concept of naming event e (``collapsed.py``): when that concept holds naming events
    only, all at one place that holds other events too, move them together to a new place if that raises
    ``log_target`` (the mode of the two). Single-site steps cannot: the first event alone in a new place is less
    probable than in the place around it, while the name's events together, one name said at one spot several
    times, make a place of their own. Returns whether they moved."""
    l = st.concept[e]
    members = np.flatnonzero(st.concept == l)
    empty = np.flatnonzero(st.n_k <= 0)
    if not len(empty) or not all(st.is_named(int(j)) for j in members) or len(set(st.place[members])) != 1:
        return False
    k = int(st.place[members[0]])
    if st.n_k[k] <= len(members) + 1e-9:
        return False
    before = log_target(st)
    _relabel_block(st, members, int(empty[0]), int(l))
    if log_target(st) > before:
        return True
    _relabel_block(st, members, k, int(l))
    return False


def _relabel_block(st: CollapsedState, members: np.ndarray, place: int, concept: int) -> None:
    for j in members:
        st.move(int(j), -1.0)
        st.place[j], st.concept[j] = place, concept
        st.move(int(j), 1.0)
