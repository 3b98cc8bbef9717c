"""The Eq. 28 dynamic programme on given arrays: hand-computed cases and a brute-force check."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.planning.search import SearchProblem, search

X = -np.inf


def chain_problem(max_steps: int) -> SearchProblem:
    # nodes 0 - 1 - 2, plus a costly shortcut 0 -> 2; the goal is node 2
    transition = np.array([[X, -1.0, -10.0], [X, X, -1.0], [X, X, X]])
    return SearchProblem(
        transition=transition,
        start=np.array([-1.0, -5.0, -9.0]),
        word=np.array([[-0.5, -0.5, -0.1]]),
        completes=np.array([[False, False, True]]),
        max_steps=max_steps,
    )


@pytest.mark.parametrize(
    "max_steps, nodes, log_prob",
    [
        (1, [2], -9.0 - 0.1),  # start -> 2
        (2, [1, 2], (-5.0 - 0.5) + (-1.0 - 0.1)),  # start -> 1 -> 2 = -6.6 beats start -> 0 -> 2 = -11.6
        (3, [0, 1, 2], 3 * -1.0 + 2 * -0.5 - 0.1),  # -4.1
        (10, [0, 1, 2], -4.1),
    ],
)
def test_chain_by_hand(max_steps, nodes, log_prob):
    result = search(chain_problem(max_steps))
    assert result.nodes.tolist() == nodes
    assert result.log_prob == pytest.approx(log_prob)
    assert result.completed[-1] == (0,)
    assert all(c == () for c in result.completed[:-1])


def test_waypoint_and_goal_instance_chosen_jointly():
    # nodes: 0 waypoint W, 1 goal G1 (next to the start), 2 goal G2 (next to W), 3 a second waypoint instance W'
    # start -> G1 is cheap, but start -> W -> G1 costs -1 -3 = -4 while start -> W -> G2 costs -1 -1 = -2;
    # start -> W' -> G1 costs -3 -0.5 = -3.5. Leg by leg (nearest waypoint, then nearest goal) gives W -> G1.
    t = np.full((4, 4), X)
    t[0, 1], t[0, 2], t[3, 1], t[3, 2] = -3.0, -1.0, -0.5, -6.0
    word = np.array(
        [
            [-0.1, -5.0, -5.0, -0.1],  # stage 0: the waypoint word
            [-5.0, -0.2, -0.2, -5.0],
        ]
    )  # stage 1: the goal word
    completes = np.array([[True, False, False, True], [False, True, True, False]])
    problem = SearchProblem(t, np.array([-1.0, -0.5, X, -3.0]), word, completes, max_steps=5)
    result = search(problem)
    assert result.nodes.tolist() == [0, 2]
    assert result.stages.tolist() == [0, 1]
    assert result.completed == ((0,), (1,))
    assert result.log_prob == pytest.approx(-1.0 - 0.1 - 1.0 - 0.2)
    # the best plan ending at G1 goes through W' (-3 - 0.1 - 0.5 - 0.2), not through W (-1 - 0.1 - 3 - 0.2)
    alt = result.ending_at(1)
    assert alt.nodes.tolist() == [3, 1]
    assert alt.log_prob == pytest.approx(-3.8)
    assert result.terminal[1] == pytest.approx(-3.8)


def test_goal_reached_before_the_waypoint_does_not_count():
    # start -> goal (node 1) is free, but the waypoint (node 0) must come first: start -> 1 -> 0 -> 1
    t = np.full((2, 2), X)
    t[0, 1], t[1, 0] = -2.0, -2.0
    word = np.zeros((2, 2))
    completes = np.array([[True, False], [False, True]])
    result = search(SearchProblem(t, np.array([-10.0, 0.0]), word, completes, max_steps=3))
    assert result.nodes.tolist() == [1, 0, 1]
    assert result.log_prob == pytest.approx(-4.0)
    assert result.completed == ((), (0,), (1,))
    assert search(SearchProblem(t, np.array([-10.0, 0.0]), word, completes, max_steps=2)).nodes.tolist() == [
        0,
        1,
    ]
    assert search(SearchProblem(t, np.array([X, 0.0]), word, completes, max_steps=2)) is None


def test_one_node_can_complete_consecutive_stages():
    t = np.full((2, 2), X)
    t[0, 1] = -1.0
    completes = np.array([[False, True], [False, True]])  # "go to B via B"
    result = search(SearchProblem(t, np.array([0.0, -5.0]), np.zeros((2, 2)), completes, max_steps=3))
    assert result.nodes.tolist() == [0, 1]
    assert result.completed == ((), (0, 1))


def test_positive_terms_are_handled_exactly():
    # a positive cycle 0 <-> 1 is worth walking around until the horizon, then finishing at node 2
    t = np.full((3, 3), X)
    t[0, 1], t[1, 0], t[1, 2] = 1.0, 1.0, 0.0
    completes = np.array([[False, False, True]])
    result = search(SearchProblem(t, np.array([0.0, X, X]), np.zeros((1, 3)), completes, max_steps=6))
    assert result.nodes.tolist() == [0, 1, 0, 1, 2]  # three positive steps fit in six; a fourth would not
    assert result.log_prob == pytest.approx(3.0)


def brute_force(problem: SearchProblem) -> float:
    S, M = problem.word.shape
    best = -np.inf
    for e in range(1, problem.max_steps + 1):
        for nodes in itertools.product(range(M), repeat=e):
            for stages in itertools.product(range(S), repeat=e):
                if stages[0] != 0 or any(b < a for a, b in itertools.pairwise(stages)):
                    continue
                # advancing from stage a to b at node n needs n to complete a..b-1; finishing needs S-1 done
                ok = all(problem.completes[s, nodes[t]] for t in range(e - 1) for s in range(stages[t], stages[t + 1]))
                ok = ok and all(problem.completes[s, nodes[-1]] for s in range(stages[-1], S))
                if not ok:
                    continue
                score = problem.start[nodes[0]] + problem.word[stages[0], nodes[0]]
                for t in range(1, e):
                    score += problem.transition[nodes[t - 1], nodes[t]] + problem.word[stages[t], nodes[t]]
                best = max(best, score)
    return best


@st.composite
def problems(draw):
    M = draw(st.integers(2, 4))
    S = draw(st.integers(1, 2))
    E = draw(st.integers(1, 4 if M < 4 else 3))
    weights = st.one_of(st.just(-np.inf), st.floats(-5, 2, allow_nan=False))

    def arr(shape):
        return np.array(draw(st.lists(weights, min_size=int(np.prod(shape)), max_size=int(np.prod(shape))))).reshape(
            shape
        )

    completes = np.array(draw(st.lists(st.booleans(), min_size=S * M, max_size=S * M))).reshape(S, M)
    return SearchProblem(arr((M, M)), arr((M,)), arr((S, M)), completes, E)


@settings(max_examples=120, deadline=None, derandomize=True)
@given(problems())
def test_matches_brute_force(problem):
    result = search(problem)
    expected = brute_force(problem)
    if not np.isfinite(expected):
        assert result is None
        return
    assert result.log_prob == pytest.approx(expected)
    # the returned sequence scores what it claims and respects the stages
    nodes, stages = result.nodes, result.stages
    score = problem.start[nodes[0]] + problem.word[stages[0], nodes[0]]
    for t in range(1, len(nodes)):
        score += problem.transition[nodes[t - 1], nodes[t]] + problem.word[stages[t], nodes[t]]
    assert score == pytest.approx(expected)
    done = [s for c in result.completed for s in c]
    assert done == list(range(problem.word.shape[0]))
    for t, c in enumerate(result.completed):
        assert all(problem.completes[s, nodes[t]] for s in c)


def test_rejects_bad_shapes():
    with pytest.raises(ValueError, match="transition must be"):
        SearchProblem(np.zeros((2, 3)), np.zeros(2), np.zeros((1, 2)), np.ones((1, 2), bool), 3)
    with pytest.raises(ValueError, match="NaN"):
        SearchProblem(np.full((2, 2), np.nan), np.zeros(2), np.zeros((1, 2)), np.ones((1, 2), bool), 3)
