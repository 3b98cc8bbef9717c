"""Answers to the robot's questions: how a teach given in reply to a question enters the model (issue 24).

The paper has no questions: every teach is an event of the robot's walk, drawn from its place's Gaussian, with a
psi transition from the event before it (Eqs. 3-9). Taught that way, answers do not split a place the learner
merged (docs/teaching.md, "Why answers do not fix these homes"): the answers at the two halves of a merged place
are events of the stream, so the hops between them count as transitions the robot never made against the split,
and single-site steps cannot move a room's events at once.

The departures, each for answers only (an event marked ``TeachingEvent.answer``); everything else, batch learning
and online learning of what the robot records, is the paper's model:

* ``alone``: an answer is a segment of its own, with no psi transition into or out of it (the events before and
  after it are linked as if it were not there). Reason: the robot did not walk to the spot because of the place it
  was in; it went there to ask, and the person's reply is not a step of its walk.
* ``weight``: an answer enters every count as ``weight`` events (its position, its name, its place and concept
  counts) and its conditional to that power. Reason: a reply to a question is said on purpose, about the spot the
  robot stands on, where an overheard utterance may be about somewhere else; ``weight`` is how many overheard
  teaches one answer is worth. Measured, not chosen (docs/teaching.md).
* ``split``: after an answer, a block move splits the answer's place in two (and its concept with it when the two
  are one room), the answer in one half and the place's event farthest from it in the other, the rest allocated
  by the collapsed conditional (``online_split_merge.allocate``), and the split is kept when the collapsed joint
  (``online_split_merge.log_target``, with the two departures above in its counts) is higher: the mode of the two,
  as ``online_split_merge.settle_name``. Reason: a question is asked where the model is unsure, and single-site
  steps cannot move a room's events at once.
* ``walk``: a split at an answer is judged with the robot's walk as unlabelled position evidence too: the
  dataset's trajectory, one pose per ``WALK_SPACING_M`` travelled, each pose in the place under which it is most
  probable (``walk_owner``), enters every place's NIW marginal (Eqs. 5-6; ``walk_gain``). The paper's HSMM has the
  robot's position at every step of a segment, x_{t_e .. t'_e} (Eq. 3); the event model the paper's code and ours
  learn keeps only x at the events, so two adjoining rooms of one name, 15 events each, gain 6-17 nats of
  positions from a split and pay about 26 of phi (the name on two places); with their walk they gain 25-60 (a
  diagnostic on battery-9, -10, -32, -36). Only this move uses the walk (the online learner's Gibbs steps and
  split-merge moves, and batch learning, do not), and only where the model keeps one (``attach_walk``: ``learn``
  on a dataset with a trajectory); elsewhere the split is judged by the events alone. With it the robot asks
  first where its walk says a place is two (``split_gain``, ``teaching.questions``).

* ``concepts``: at an answer, two block moves on the concepts, each kept when the collapsed joint is higher (the
  mode of the two, as ``split``): the concepts derived again from the places (``concepts_from_places``: grammar
  words in the background, one concept per place, then iterated conditional modes), then a concept of its own for
  each place, the answer's first (``own_concepts``). Reason: in a learned model whose word switches collapsed
  (four in five tokens concept words, the background holding little but "the"), concepts gather by the
  sentence's frame ("we are in the X", "this place is called X") and not by place; the paper's model itself
  prefers the true concepts, with the frame words in the background, by 9-58 nats on the generated homes where
  this happened (docs/teaching.md), but single-site Gibbs steps cannot leave the collapsed switches, and an
  answer taught as one more event cannot either. These moves use no word of the answer: the answer is when the
  learner looks again. Measured without any answer as well (docs/teaching.md). ``joint``: the iterated
  conditional modes of the first move choose each event's place as well as its concept (the default).

``ANSWER_MODELS`` names the combinations measured; ``DEFAULT_ANSWERS`` is the one chosen (docs/teaching.md: on
which homes, and the paper's variant beside it); ``"paper"`` learns an answer as any teach.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from spcotmhp.errors import TeachingError
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.online_split_merge import (
    _label,
    _member,
    _pseudo,
    _pure,
    _relabel,
    _restore,
    _save,
    allocate,
    log_target,
)

WALK_SPACING_M = 0.5
"""One pose of the walk per this much travel (metres): poses closer than the robot's footprint (0.5 m across) are
the same position seen twice, not more evidence of it."""
ICM_SWEEPS = 20
"""At most this many sweeps of iterated conditional modes in ``concepts_from_places`` (each raises the joint; it
stops at the first sweep that changes no assignment)."""
SPLIT_TRIES = 4
"""Allocations drawn per kind of split; the best is compared with the merge (a few: each costs one conditional
per event of the place)."""


@dataclass(frozen=True)
class AnswerModel:
    """How answers enter the model (module docstring)."""

    alone: bool = False
    weight: float = 1.0
    split: bool = False
    walk: bool = False
    concepts: bool = False
    joint: bool = False

    def learner_settings(self) -> dict:
        """Keyword settings of ``OnlineSpCoTMHP`` for this answer model."""
        split = (walk_split_at_answer if self.walk else split_at_answer) if self.split else None
        concepts = self.concepts
        joint = self.joint

        def after(st: CollapsedState, e: int, rng: np.random.Generator) -> None:
            if concepts:
                concepts_from_places(st, joint=joint)
                own_concepts(st, e)
            if split is not None:
                split(st, e, rng)

        return {
            "answer_alone": self.alone,
            "answer_weight": self.weight,
            "after_answer": after if (split or concepts) else None,
        }


ANSWER_MODELS = {
    "paper": AnswerModel(),
    "alone": AnswerModel(alone=True),
    "split": AnswerModel(split=True),
    "alone+split": AnswerModel(alone=True, split=True),
    "alone+split+w3": AnswerModel(alone=True, weight=3.0, split=True),
    "alone+split+w10": AnswerModel(alone=True, weight=10.0, split=True),
    "split+walk": AnswerModel(split=True, walk=True),
    "alone+split+walk": AnswerModel(alone=True, split=True, walk=True),
    "alone+split+walk+concepts": AnswerModel(alone=True, split=True, walk=True, concepts=True),
    "alone+split+walk+joint": AnswerModel(alone=True, split=True, walk=True, concepts=True, joint=True),
}
DEFAULT_ANSWERS = "alone+split+walk+joint"


def answer_model(name: str | None) -> AnswerModel:
    """The answer model called ``name`` (None: the default); TeachingError naming the accepted ones otherwise."""
    name = DEFAULT_ANSWERS if name is None else name
    if name not in ANSWER_MODELS:
        raise TeachingError(f"answers must be one of {', '.join(ANSWER_MODELS)}, got {name!r}")
    return ANSWER_MODELS[name]


def walk_poses(trajectory: np.ndarray) -> np.ndarray:
    """(P, 2) the trajectory thinned to one pose per ``WALK_SPACING_M`` travelled (module docstring, ``walk``)."""
    traj = np.asarray(trajectory, dtype=float).reshape(-1, 2)
    if len(traj) < 2:
        return traj.copy()
    travelled = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(traj, axis=0).T))])
    keep = np.flatnonzero(np.diff(np.floor(travelled / WALK_SPACING_M), prepend=-1.0) > 0)
    return traj[keep]


def attach_walk(model, trajectory: np.ndarray | None) -> bool:
    """Keep the walk's poses (``walk_poses``) in ``model``'s learner member; returns whether it could (a
    trajectory and a learner member)."""
    member = getattr(model, "learner", None)
    if member is None or trajectory is None:
        return False
    member["arrays"]["walk_X"] = walk_poses(trajectory)
    return True


def walk_gain(st: CollapsedState) -> float:
    """log p(events and walk poses of each place) - log p(events of each place), NIW marginals (Eqs. 5-6): what
    the walk adds to ``log_target``'s positions term (0 without a walk)."""
    if st.walk_X is None or not len(st.walk_X):
        return 0.0
    from spcotmhp.learning.distributions import GaussianStats
    from spcotmhp.learning.posterior import Priors

    gauss = Priors.build(st.hyper, st.K, st.L, st.V, st.D).gauss
    owner = walk_owner(st)
    walk = GaussianStats.from_assignments(st.walk_X, owner, st.K)
    both = GaussianStats(st.n_k + walk.n, st.sx + walk.sx, st.sxx + walk.sxx)
    return gauss.log_marginal(both) - gauss.log_marginal(GaussianStats(st.n_k, st.sx, st.sxx))


def walk_owner(st: CollapsedState) -> np.ndarray:
    """The place of each walk pose as unlabelled evidence: the active place under which it is most probable,
    argmax_k n_k t(x | place k) (the events' NIW predictives)."""
    used = np.flatnonzero(st.n_k > 0)
    poses = np.zeros((0, 2)) if st.walk_X is None else st.walk_X
    if not len(poses) or not len(used):
        return np.zeros(len(poses), dtype=np.int64)
    scores = st.log_predictive(poses)[:, used] + np.log(st.n_k[used])[None, :]
    return used[np.argmax(scores, axis=1)]


def walk_target(st: CollapsedState) -> float:
    """``log_target`` with the walk's poses as position evidence (module docstring, ``walk``)."""
    return log_target(st) + walk_gain(st)


def walk_split_at_answer(st: CollapsedState, e: int, rng: np.random.Generator) -> bool:
    """``split_at_answer`` judged by ``walk_target``."""
    return split_at_answer(st, e, rng, walk_target)


def split_at_answer(
    st: CollapsedState, e: int, rng: np.random.Generator, target: Callable[[CollapsedState], float] = log_target
) -> bool:
    """The ``split`` block move at answer e (module docstring), judged by ``target``; returns whether the place
    was split."""
    kept = False
    for kind in ("both", "place"):
        label = _label(st, kind, e)
        if kind == "both" and not _pure(st, label):
            continue
        members = np.flatnonzero(_member(st, kind, label))
        empties = [np.flatnonzero(st.n_k <= 0)] + ([np.flatnonzero(st.n_l <= 0)] if kind == "both" else [])
        if len(members) < 4 or not all(len(x) for x in empties):
            continue
        far = members[np.argmax(np.linalg.norm(st.X[members] - st.X[e], axis=1))]
        rest = np.array([j for j in members if j != e and j != far], dtype=np.int64)
        near = np.minimum(*(np.linalg.norm(st.X[rest] - st.X[x], axis=1) for x in (e, far)))
        order = rest[np.argsort(near, kind="stable")]
        new = int(empties[0][0]) if kind == "place" else (int(empties[0][0]), int(empties[1][0]))
        saved, best, best_state = _save(st), target(st), None
        for _ in range(SPLIT_TRIES):
            allocate(st, kind, e, int(far), new, order, rng)
            score = target(st)
            if score > best:
                best, best_state = score, _save(st)
            _restore(st, saved)
        if best_state is not None:
            _restore(st, best_state)
            kept = True
            break
    return kept


def concepts_from_places(
    st: CollapsedState, target: Callable[[CollapsedState], float] = log_target, joint: bool = False
) -> bool:
    """The ``concepts`` block move (module docstring): the concepts derived again from the places, kept when
    ``target`` is higher than the current state's with its word switches at their mode (the mode of the two). The
    proposal: every grammar word a background token and every other word a concept token (the ``language`` tables'
    function words: a closed class that names no place), one concept per active place, then iterated conditional
    modes over each event's concept (the collapsed conditional of Eqs. 5-17, its place held; with ``joint``, its
    place and concept together, so that an event whose words say another place can move there) and the switches,
    until a sweep changes nothing. Returns whether it was kept."""
    from spcotmhp.planning.vocabulary import FUNCTION_WORDS

    used = np.flatnonzero(st.n_k > 0)
    if st.words is None or not len(used) or len(used) > st.L or _pseudo(st):
        return False
    grammar = np.zeros(st.V, dtype=bool)
    grammar[: len(st.words)] = [w in FUNCTION_WORDS for w in st.words]
    return _mode_of_two(st, lambda: _rederive(st, used, grammar, joint), target)


def _rederive(st: CollapsedState, used: np.ndarray, grammar: np.ndarray, joint: bool) -> None:
    """``concepts_from_places``' proposal, made in ``st``."""
    places, own = st.place.copy(), np.full(st.K, -1, dtype=np.int64)
    own[used] = np.arange(len(used))
    for e in range(st.E):
        st.move(e, -1.0)
    for e in range(st.E):
        if not st.is_named(e):
            st.z[e][:] = ~grammar[st.tokens[e]]
        st.place[e], st.concept[e] = places[e], own[places[e]]
        st.move(e, 1.0)
    for _ in range(ICM_SWEEPS):
        st.switch_mode()
        changed = 0
        for e in range(st.E):
            k, was = int(st.place[e]), (int(st.place[e]), int(st.concept[e]))
            st.move(e, -1.0)
            if joint:
                logp = st.log_conditional(e)
                best = int(np.argmax(logp))
                st.place[e], st.concept[e] = best // logp.shape[1], best % logp.shape[1]
            else:
                st.place[e], st.concept[e] = k, int(np.argmax(st.log_conditional(e)[k]))
            st.move(e, 1.0)
            changed += int((int(st.place[e]), int(st.concept[e])) != was)
        if not changed:
            break


def own_concept(st: CollapsedState, k: int, target: Callable[[CollapsedState], float] = log_target) -> bool:
    """The ``concepts`` move's second part for place k: every event of the place to one new concept, the word
    switches of the concepts it touches at their mode before and after, kept when ``target`` is higher (the mode of
    the two); returns whether it was kept."""
    members = np.flatnonzero(st.place == k)
    concepts = np.unique(st.concept[members])
    empty = np.flatnonzero(st.n_l <= 0)
    if not len(members) or not len(empty) or (len(concepts) == 1 and st.n_l[concepts[0]] <= len(members) + 1e-9):
        return False
    touched = np.flatnonzero(np.isin(st.concept, concepts))
    return _mode_of_two(st, lambda: _relabel(st, "concept", members, int(empty[0])), target, touched)


def _mode_of_two(
    st: CollapsedState,
    propose: Callable[[], object],
    target: Callable[[CollapsedState], float],
    switches: np.ndarray | None = None,
) -> bool:
    """Keep the proposal ``propose()`` makes in ``st`` when ``target`` is higher there than in the current state,
    each with the word switches (of the events ``switches``, all when None) at their mode; otherwise put the state,
    counts and switches, back as it was. Returns whether the proposal was kept."""
    saved, z = _save(st), [a.copy() for a in st.z]
    st.switch_mode(events=switches)
    before = target(st)
    propose()
    st.switch_mode(events=switches)
    if target(st) > before:
        return True
    _restore(st, saved)
    st.z = z
    return False


def own_concepts(st: CollapsedState, e: int) -> int:
    """``own_concept`` at every active place, answer e's first, each judged on the state the one before left;
    returns how many were kept."""
    first = int(st.place[e])
    return sum(own_concept(st, k) for k in [first, *(int(k) for k in np.flatnonzero(st.n_k > 0) if k != first)])


def split_gain(model) -> list[tuple[float, np.ndarray]]:
    """Where the walk says a place is two: for each active place of ``model``'s learner state with a walk, the
    gain of ``walk_target`` when the place is split as an answer at its event farthest from its mean would split
    it (``split_at_answer``), and that event's position; the places with a positive gain, largest first."""
    from spcotmhp.learning.gibbs import make_rng
    from spcotmhp.learning.learner_state import state_of_member

    if model.learner is None or "walk_X" not in model.learner["arrays"]:
        return []
    st = state_of_member(model.learner, model)
    if model.map is not None:
        from spcotmhp.learning.online import log_new_place_density

        st.log_new_place = log_new_place_density(model.map)
    out = []
    base = walk_target(st)
    for k in np.flatnonzero(st.n_k > 0):
        members = np.flatnonzero(st.place == k)
        if len(members) < 4:
            continue
        askable = members[on_free_cells(model, st.X[members])]  # a question is asked where the robot can stand
        if not len(askable):
            continue
        end = int(askable[np.argmax(np.linalg.norm(st.X[askable] - st.sx[k] / st.n_k[k], axis=1))])
        saved = _save(st)
        if split_at_answer(st, end, make_rng(0, int(k)), walk_target):
            out.append((walk_target(st) - base, st.X[end].copy()))
        _restore(st, saved)
    return sorted(out, key=lambda g: -g[0])


def on_free_cells(model, xy: np.ndarray) -> np.ndarray:
    """Mask of the positions ``xy`` on known free cells of the model's map (all of them without a map)."""
    occ = model.map
    if occ is None or not len(xy):
        return np.ones(len(xy), dtype=bool)
    cells = occ.world_to_cell(xy)
    inside = np.array([occ.in_bounds(c) for c in cells], dtype=bool)
    ok = np.zeros(len(xy), dtype=bool)
    rows, cols = cells[inside, 0], cells[inside, 1]
    ok[inside] = ~occ.unknown[rows, cols] & ~occ.occupied[rows, cols]
    return ok
