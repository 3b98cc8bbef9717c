"""Split-merge moves of the online learner (issue 15): the target against a brute-force computation, the moves'
stationary distribution against exact enumeration on tiny cases, merges that single-site steps cannot undo."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.special import gammaln

from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent
from spcotmhp.learning.online_split_merge import log_target, propose

X4 = np.array([[0.0, 0.0], [0.6, 0.1], [2.0, 0.3], [2.3, -0.2]])
WORDS4 = [[0, 1], [0], [2, 1], [2]]
FEATS4 = np.array([[1.0, 0.0, 2.0], [0.5, 0.5, 1.0], [0.0, 3.0, 0.0], [0.0, 1.0, 1.0]])


def state(places, concepts, K=4, L=4, features=True, new_place=None) -> CollapsedState:
    """A state of the four tiny events with the given assignments (events added one by one)."""
    st = CollapsedState(K, L, 3, 3 if features else None, Hyperparameters(kappa0=0.05, V0=((0.5, 0), (0, 0.5))))
    st.background = False
    st.log_new_place = new_place
    for e, (x, words) in enumerate(zip(X4, WORDS4, strict=True)):
        st.X = np.vstack([st.X, x[None]])
        st.place, st.concept = np.append(st.place, places[e]), np.append(st.concept, concepts[e])
        st.tokens.append(np.array(words))
        st.z.append(np.ones(len(words), dtype=bool))
        st.features.append(FEATS4[e] if features else None)
        st.move(e, 1.0)
    return st


def polya(seq, M, c) -> float:
    """log probability of an ordered sequence of outcomes under a Dirichlet(c)-categorical, by the urn: each
    draw's predictive given the draws before it."""
    out, counts = 0.0, np.zeros(M)
    for m in seq:
        out += math.log((c + counts[m]) / (M * c + counts.sum()))
        counts[m] += 1
    return out


def brute_target(places, concepts, K=4, L=4, new_place=None) -> float:
    """log_target by the chain rule: positions by each place's Student-t predictive given its earlier points,
    every Dirichlet term by the urn, Eq. 9's rescaling and the new-place factor written out."""
    h = Hyperparameters(kappa0=0.05, V0=((0.5, 0), (0, 0.5))).resized(L, K)
    out = 0.0
    for k in set(places):
        pts = [e for e in range(4) if places[e] == k]
        one = CollapsedState(1, 1, 1, None, h)
        for e in pts:
            out += one.log_predictive(X4[e])[0]
            one.n_k[0] += 1
            one.sx[0] += X4[e]
            one.sxx[0] += np.outer(X4[e], X4[e])
        if new_place is not None:
            empty = CollapsedState(1, 1, 1, None, h)
            out += new_place - empty.log_predictive(X4[pts].mean(axis=0))[0]
    out += polya(list(concepts), L, h.alpha)
    for c in range(L):
        out += polya([places[e] for e in range(4) if concepts[e] == c], K, h.gamma)
        out += polya([w for e in range(4) if concepts[e] == c for w in WORDS4[e]], 3, h.beta)
    for c in range(L):  # image features: each event's counts in one go (theta integrated out, Eq. 15)
        F = np.zeros(3)
        for e in (e for e in range(4) if concepts[e] == c):
            f = FEATS4[e]
            out += (gammaln(h.chi + F + f) - gammaln(h.chi + F)).sum()
            out -= gammaln(3 * h.chi + F.sum() + f.sum()) - gammaln(3 * h.chi + F.sum())
            F += f
    for k in range(K):  # transitions: one urn per row
        out += polya([places[e + 1] for e in range(3) if places[e] == k], K, h.omega)
    n_lk = np.zeros((L, K))
    for e in range(4):
        n_lk[concepts[e], places[e]] += 1
    phi = (n_lk + h.gamma) / (n_lk.sum(axis=1) + K * h.gamma)[:, None]
    out -= sum(np.log(phi[:, places[e]].sum()) for e in range(4))
    return out


@pytest.mark.parametrize("new_place", [None, -3.0])
def test_target_is_the_brute_force_joint(new_place):
    """Differences of log_target between assignments equal the chain-rule computation (constants cancel)."""
    cases = [((0, 0, 1, 1), (0, 0, 1, 1)), ((0, 0, 0, 0), (2, 2, 2, 2)), ((3, 1, 1, 0), (0, 1, 1, 0))]
    got = [log_target(state(p, c, new_place=new_place)) for p, c in cases]
    want = [brute_target(p, c, new_place=new_place) for p, c in cases]
    assert np.allclose(np.diff(got), np.diff(want), rtol=0, atol=1e-8), (got, want)


def canonical(labels) -> tuple:
    """The partition of a labelling, as labels renumbered in order of first appearance."""
    first: dict = {}
    return tuple(first.setdefault(v, len(first)) for v in labels)


def exact_partitions(kind: str, fixed) -> dict:
    """pi over partitions of ``kind``'s labels (the other assignment ``fixed``) by enumerating every labelling:
    the weak-limit labels are exchangeable, so a partition's mass sums its labellings."""
    mass: dict = {}
    for labels in itertools.product(range(4), repeat=4):
        key = canonical(labels)
        if kind == "place":
            lp = log_target(state(labels, fixed))
        elif kind == "concept":
            lp = log_target(state(fixed, labels))
        elif labels != key:
            continue
        else:  # rooms: place and concept partitions equal; the (4!/(4-k)!)^2 labellings of k rooms weigh alike
            k = len(set(key))
            lp = log_target(state(key, key)) + 2 * math.log(math.factorial(4) / math.factorial(4 - k))
        mass[key] = np.logaddexp(mass.get(key, -np.inf), lp)
    total = np.logaddexp.reduce(list(mass.values()))
    return {k: float(np.exp(v - total)) for k, v in mass.items()}


@pytest.mark.parametrize("kind", ["place", "concept", "both"])
def test_moves_leave_the_target_invariant(kind):
    """Split-merge moves alone (uniform pairs) visit the partitions with the frequencies of the exact target
    (brute force over every labelling). A wrong proposal probability (the allocation's q, the 1/m choice of the
    new label) shifts mass between partitions of different sizes by a factor of 2 or more."""
    rng = np.random.default_rng(7)
    fixed = {"place": (0, 0, 1, 1), "concept": (0, 1, 1, 2), "both": None}[kind]
    exact = exact_partitions(kind, fixed)
    st = {"place": lambda: state((0, 0, 0, 0), fixed), "concept": lambda: state(fixed, (0, 0, 0, 0))}.get(
        kind, lambda: state((0, 0, 0, 0), (2, 2, 2, 2))
    )()
    seen: dict = {}
    n = 4000
    for _ in range(n):
        a, b = rng.choice(4, size=2, replace=False)
        propose(st, kind, int(a), int(b), rng)
        key = canonical(st.concept if kind == "concept" else st.place)
        seen[key] = seen.get(key, 0) + 1
    tv = 0.5 * sum(abs(seen.get(k, 0) / n - p) for k, p in exact.items())
    assert tv < 0.06, (tv, exact, seen)


def test_allocation_probability_is_that_of_the_sampler():
    """The probability a merge's reverse split is given (the allocation evaluated on the split state) sums to one
    over every split of the group and matches how often the allocation draws each split."""
    import copy

    from spcotmhp.learning.online_split_merge import allocate

    merged = state((0, 0, 0, 0), (0, 0, 1, 1))
    a, b, new, order = 0, 3, 2, np.array([2, 1])
    q = {}
    for labels in itertools.product((0, new), repeat=2):
        places = [0, 0, 0, new]
        places[2], places[1] = labels
        q[labels] = math.exp(allocate(state(places, (0, 0, 1, 1)), "place", a, b, new, order, None))
    assert sum(q.values()) == pytest.approx(1.0, abs=1e-12)
    rng, n, seen = np.random.default_rng(3), 3000, dict.fromkeys(q, 0)
    for _ in range(n):
        st = copy.deepcopy(merged)
        allocate(st, "place", a, b, new, order, rng)
        seen[(int(st.place[2]), int(st.place[1]))] += 1
    assert all(abs(seen[k] / n - p) < 0.03 for k, p in q.items()), (q, seen)


def two_rooms(n: int = 12, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """n events in a room at (0, 0), then n in a room at (3, 0) (0.3 m spread), and the room of each."""
    rng = np.random.default_rng(seed)
    room = np.repeat([0, 1], n)
    return np.array([[0.0, 0.0], [3.0, 0.0]])[room] + rng.normal(0.0, 0.3, (2 * n, 2)), room


def test_a_merged_place_stays_merged_under_single_site_steps_and_splits_by_a_move():
    """Two rooms in one place (as an early merge leaves them): 30 sweeps of single-site Gibbs steps keep them
    merged; 100 split-merge moves split them along the rooms."""
    X, room = two_rooms()
    st = CollapsedState(20, 20, 1, None, Hyperparameters())
    st.log_new_place = -math.log(100.0)  # a home of 100 m2
    for e, x in enumerate(X):
        st.X = np.vstack([st.X, x[None]])
        st.place, st.concept = np.append(st.place, 0), np.append(st.concept, 0)
        st.tokens.append(np.array([0]))
        st.z.append(np.ones(1, dtype=bool))
        st.features.append(None)
        st.move(e, 1.0)
    rng = np.random.default_rng(0)
    for _ in range(30):
        for e in range(st.E):
            st.step(e, rng)
    assert (st.n_k > 0).sum() == 1
    for _ in range(100):
        a, b = rng.choice(st.E, size=2, replace=False)
        propose(st, "place", int(a), int(b), rng)
    # no place holds events of both rooms, and each room is one place but for a straggler at most
    assert not set(st.place[room == 0]) & set(st.place[room == 1])
    assert all(np.bincount(st.place[room == r]).max() >= (room == r).sum() - 1 for r in (0, 1))


def test_a_name_split_over_concepts_by_the_stream_is_merged_by_the_moves():
    """One name taught in two rooms, each visited twice: single-site steps leave it spread over several
    concepts (each of 5 seeds); with split-merge moves the learner keeps the two places and ends with one concept
    (4 of the 5 seeds; the fifth keeps three events of 40 apart, which more moves merge)."""
    X, _ = two_rooms(20)
    order = np.concatenate([np.arange(10), np.arange(20, 30), np.arange(10, 20), np.arange(30, 40)])
    events = [TeachingEvent(*X[e], ("this", "is", "the", "hall")) for e in order]
    one = 0
    for seed in range(5):
        single = OnlineSpCoTMHP(seed=seed, split_merge=0).partial_fit(events)
        moves = OnlineSpCoTMHP(seed=seed).partial_fit(events)
        assert len(set(single.concepts_)) > 1 and len(set(moves.places_)) == 2
        one += len(set(moves.concepts_)) == 1
    assert one >= 4


def test_target_terms_add_up_to_the_target():
    """``log_target_terms`` is the target by term: they sum to ``log_target`` and name every model term."""
    from spcotmhp.learning.online_split_merge import log_target_terms

    st = state((0, 0, 1, 1), (0, 0, 1, 1), new_place=-2.0)
    terms = log_target_terms(st)
    assert set(terms) == {"positions", "pi", "phi", "W", "theta", "psi", "rescaling"}
    assert sum(terms.values()) == pytest.approx(log_target(st), rel=1e-12)
