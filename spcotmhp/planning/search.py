"""The exact joint topological search of Eq. 28 (Algorithm 1, line 11): max-product dynamic programming.

Eq. 28 of Taniguchi et al. (2024) scores a sequence of candidate points n_1..n_E (each in place i_e) by

    prod_e  Mult(i_e | psi_{i_{e-1}}) / sum_c' Mult(i_e | phi_c')          (transition, unigram rescaling)
            * w-hat[n_{e-1}, n_e]                                          (partial-path likelihood, Eq. 27)
            * sum_C Mult(i_e | phi_C) Mult(S_e | W_C) Mult(C | pi)         (word term of the bag S_e)

In log space this is a sum of per-step terms. With waypoints, the bag S_e is the one of the *stage* being
pursued (each waypoint in order, then the goal), so we search the product of the candidate graph with the
stages: a state is (stage s, node j). Entering node j while pursuing stage s adds ``word[s, j]``; if node j is an
instance of stage s (``completes[s, j]``) the stage may be completed there at no cost, moving to (s + 1, j) at
the same step (stages with the same instances can be completed together). Completing the last stage ends the
plan. The maximum over all sequences of 1..E steps is found by the Viterbi recursion over e (max-product), which
is exact whatever the sign of the terms, and jointly chooses the waypoint instances and the goal instance (the
reference implementation planned leg by leg to a sampled goal). Because a stage can only be completed at one of
its instances, every returned sequence passes the waypoints in order and ends at a goal instance, however the
word terms (a few nats) compare with w-hat (tens to hundreds of nats).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from spcotmhp.errors import HorizonTooShort, NoReachablePlace, StartBlocked

if TYPE_CHECKING:
    from spcotmhp.planning.instructions import Instruction

NEG_INF = -np.inf


@dataclass(frozen=True)
class SearchProblem:
    """Eq. 28 on M candidate nodes and S stages, every term a log weight (-inf = impossible).

    Attributes:
        transition: (M, M) log weight of a step from node i to node j without the word term:
            log psi[i_a, i_b] - log sum_c phi_c(i_b) + w-hat[i, j].
        start: (M,) the same for the first step, from the start pose x_0 to node j.
        word: (S, M) log word term of entering node j while pursuing stage s.
        completes: (S, M) bool, node j is an instance of stage s.
        max_steps: the topological horizon E (steps e = 1..E).
    """

    transition: np.ndarray
    start: np.ndarray
    word: np.ndarray
    completes: np.ndarray
    max_steps: int

    def __post_init__(self) -> None:
        M = self.start.shape[0]
        if self.transition.shape != (M, M):
            raise ValueError(f"transition must be ({M}, {M}), got {self.transition.shape}")
        if self.word.ndim != 2 or self.word.shape[1] != M or self.completes.shape != self.word.shape:
            raise ValueError(f"word and completes must be (S, {M}), got {self.word.shape}, {self.completes.shape}")
        if self.word.shape[0] < 1 or self.max_steps < 1:
            raise ValueError("need at least one stage and max_steps >= 1")
        if np.isnan(self.transition).any() or np.isnan(self.start).any() or np.isnan(self.word).any():
            raise ValueError("log weights must not be NaN")


@dataclass(frozen=True)
class SearchResult:
    """The best sequence: ``nodes[e]`` entered at step e + 1 while pursuing ``stages[e]``; ``completed[e]`` lists
    the stages completed on arriving there. ``terminal[j]`` is the best log weight of a plan ending at node j.
    """

    nodes: np.ndarray
    stages: np.ndarray
    completed: tuple[tuple[int, ...], ...]
    log_prob: float
    terminal: np.ndarray
    _pred: np.ndarray = field(repr=False)
    _from_stage: np.ndarray = field(repr=False)
    _terminal_step: np.ndarray = field(repr=False)

    def ending_at(self, node: int) -> SearchResult:
        """The best sequence that ends at ``node`` (for comparing goal instances); raises if there is none."""
        if not np.isfinite(self.terminal[node]):
            raise ValueError(f"no plan ends at node {node}")
        nodes, stages, completed = _backtrack(
            self._pred, self._from_stage, int(self._terminal_step[node]), node, self.completes_last
        )
        return SearchResult(
            nodes,
            stages,
            completed,
            float(self.terminal[node]),
            self.terminal,
            self._pred,
            self._from_stage,
            self._terminal_step,
        )

    def anchor_octiles(self, ends: np.ndarray, node_cell: np.ndarray, cell: np.ndarray) -> np.ndarray:
        """(len(ends),) for each node of ``ends`` (each with a finite ``terminal``), the octile length in cells
        (:func:`octile`, summed in path order) from crop ``cell`` through the cells
        ``node_cell`` of the nodes of :meth:`ending_at` where a stage completes: what ``ending_at`` would give,
        read in one compiled pass instead of one :class:`SearchResult` per node."""
        return _anchor_octiles(
            self._pred,
            self._from_stage,
            self._terminal_step,
            np.ascontiguousarray(ends, dtype=np.int64),
            self.completes_last,
            np.ascontiguousarray(node_cell, dtype=np.int64),
            int(cell[0]),
            int(cell[1]),
        )

    @property
    def completes_last(self) -> int:
        return self._from_stage.shape[1] - 1


def search(problem: SearchProblem) -> SearchResult | None:
    """Maximise Eq. 28 over sequences of 1..E steps (module docstring); None if no sequence completes every
    stage within E steps. The recursion and the read-back run in one compiled kernel (:func:`_viterbi`)."""
    M = problem.start.shape[0]
    return solve(
        np.ascontiguousarray(problem.transition, dtype=np.float64),
        np.ascontiguousarray(problem.start, dtype=np.float64),
        np.ascontiguousarray(problem.word, dtype=np.float64),
        np.ascontiguousarray(problem.completes, dtype=np.bool_),
        np.arange(M, dtype=np.int64),
        int(problem.max_steps),
    )


def solve(
    transition: np.ndarray,
    start: np.ndarray,
    word: np.ndarray,
    completes: np.ndarray,
    columns: np.ndarray,
    max_steps: int,
) -> SearchResult | None:
    """:func:`search` on arrays as the planner builds them, with the word term and the instances given per
    column: node j reads ``word[:, columns[j]]`` and ``completes[:, columns[j]]`` (the planner passes its (S, K)
    place terms and each node's place, so no (S, M) copy is made; :func:`search` passes 0..M-1). The arrays
    must be C-contiguous float64 (``completes`` bool, ``columns`` int64) of the shapes of :class:`SearchProblem`;
    their shapes are not checked again (the planner builds them), but a NaN in a log weight is still refused."""
    tables, terminal, terminal_step, trace, ok = _viterbi(transition, start, word, completes, columns, max_steps)
    if not ok:
        raise ValueError("log weights must not be NaN")
    if not trace.shape[1]:
        return None
    nodes, stages, completed = _read_trace(trace)
    return SearchResult(
        nodes, stages, completed, float(terminal[nodes[-1]]), terminal, tables[0], tables[1], terminal_step
    )


@njit(cache=True)
def _viterbi(transition, start, word, completes, columns, E):  # pragma: no cover - numba
    """The max-product recursion over steps e = 1..E on states (stage, node), node j reading the word term and
    the instances of column ``columns[j]``; ties go to the lowest index. Stage completion at each step, in place:
    (s, j) -> (s + 1, j) where j is an instance of stage s, optional (the states stay, so a plan may pass one goal
    instance on its way to a better one). Returns the predecessor and completed-stage tables, the best log weight
    of finishing at each node and its step, the best sequence read back (:func:`_trace`; empty when no
    sequence completes every stage), and False instead of a search when a log weight it reads is NaN. The
    predecessor and completed-stage tables are one array (2, E + 1, S, M) and the sequence one array (2 + S,
    n): fewer arrays to hand back to Python."""
    S = word.shape[0]
    M = start.shape[0]
    tables = np.full((2, E + 1, S, M), -1, dtype=np.int64)
    pred = tables[0]  # previous node (-1: the start pose)
    from_stage = tables[1]  # >= 0: reached by completing that stage here
    best_terminal = np.full(M, NEG_INF)
    terminal_step = np.full(M, -1, dtype=np.int64)
    if _has_nan(transition, start, word, columns):
        return tables, best_terminal, terminal_step, _trace(pred, from_stage, 0, 0, S - 1), False
    value = np.full((S, M), NEG_INF)
    best = np.empty(M)
    arg = np.empty(M, dtype=np.int64)
    for j in range(M):
        value[0, j] = start[j] + word[0, columns[j]]
    for e in range(1, E + 1):
        if e > 1:
            for s in range(S):
                _step(value[s], transition, best, arg)
                for j in range(M):
                    pred[e, s, j] = arg[j]
                    value[s, j] = best[j] + word[s, columns[j]]
        for s in range(S - 1):
            for j in range(M):
                if completes[s, columns[j]] and value[s, j] > value[s + 1, j]:
                    value[s + 1, j] = value[s, j]
                    from_stage[e, s + 1, j] = s
        alive = False
        for j in range(M):
            t = value[S - 1, j] if completes[S - 1, columns[j]] else NEG_INF
            if t > best_terminal[j]:
                best_terminal[j] = t
                terminal_step[j] = e
            for s in range(S):
                if value[s, j] > NEG_INF:
                    alive = True
        if not alive:
            break
    found = False
    end = 0  # the first node of the best terminal value (np.argmax's tie rule), when one is finite
    for j in range(M):
        found = found or np.isfinite(best_terminal[j])
        if best_terminal[j] > best_terminal[end]:
            end = j
    trace = _trace(pred, from_stage, terminal_step[end] if found else 0, end, S - 1)
    return tables, best_terminal, terminal_step, trace, True


@njit(cache=True)
def _step(value, transition, best, arg):  # pragma: no cover - numba
    """``best[j] = max_i value[i] + transition[i, j]`` and ``arg[j]`` its lowest i (0 when every term is -inf), the
    row-major order of the recursion's inner loop (each row of ``transition`` read once, in memory order; the
    terms of each j are compared in the same order, i ascending, so the maxima and their ties are the same as
    a column at a time). A row of ``value`` -inf adds only -inf terms, which never beat ``best``: skipped."""
    M = value.shape[0]
    best[:] = NEG_INF
    arg[:] = 0
    for i in range(M):
        vi = value[i]
        if vi == NEG_INF:
            continue
        row = transition[i]
        for j in range(M):
            v = vi + row[j]
            if v > best[j]:
                best[j] = v
                arg[j] = i


@njit(cache=True)
def _has_nan(transition, start, word, columns):  # pragma: no cover - numba
    """Whether a log weight the search reads is NaN (SearchProblem refuses them)."""
    M = start.shape[0]
    for i in range(M):
        if np.isnan(start[i]):
            return True
        for j in range(M):
            if np.isnan(transition[i, j]):
                return True
    for s in range(word.shape[0]):
        for j in range(M):
            if np.isnan(word[s, columns[j]]):
                return True
    return False


def _backtrack(pred: np.ndarray, from_stage: np.ndarray, step: int, node: int, stage: int):
    """The sequence that reaches ``node`` at ``step`` having completed ``stage``: its nodes, the stage pursued
    at each and the stages completed on arriving at each (read back through the tables of :func:`_viterbi`)."""
    return _read_trace(_trace(pred, from_stage, step, node, stage))


def _read_trace(trace: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[tuple[int, ...], ...]]:
    """(nodes, stages, completed) of :func:`_trace`'s array: its first two rows, and per column the stages whose
    flag (rows 2..) is set."""
    completed = tuple(tuple(s for s, flag in enumerate(col) if flag) for col in trace[2:].T.tolist())
    return trace[0], trace[1], completed


@njit(cache=True)
def _trace(pred, from_stage, step, node, stage):  # pragma: no cover - numba
    """:func:`_backtrack` in compiled code, as one (2 + S, n) array: the nodes, the stages pursued, then per stage s
    (row 2 + s) 1 where stage s is completed on arriving at the node."""
    S = from_stage.shape[1]
    out = np.zeros((2 + S, step), np.int64)  # filled from its last column back
    k = step
    pending = np.zeros(S, np.bool_)  # the stages completed at the node being read back
    pending[stage] = True
    e, s, j = step, stage, node
    while e >= 1:
        prev_stage = from_stage[e, s, j]
        if prev_stage >= 0:  # stage prev_stage was completed at node j on this same step
            pending[prev_stage] = True
            s = prev_stage
            continue
        k -= 1
        out[0, k] = j
        out[1, k] = s
        for t in range(S):
            out[2 + t, k] = pending[t]
        pending[:] = False
        j = pred[e, s, j]
        e -= 1
    return out[:, k:].copy()


@njit(cache=True)
def _anchor_octiles(pred, from_stage, terminal_step, ends, stage, node_cell, r0, c0):  # pragma: no cover - numba
    """:meth:`SearchResult.anchor_octiles`: :func:`_trace`'s walk back from each end, keeping the nodes where a
    stage completes, then the octile lengths between them summed from the start (the order of Python's sum)."""
    S = from_stage.shape[1]
    out = np.empty(ends.shape[0])
    keep = np.empty(from_stage.shape[0] + 1, np.int64)
    pending = np.zeros(S, np.bool_)
    for q in range(ends.shape[0]):
        n = 0
        pending[:] = False
        pending[stage] = True
        e, s, j = terminal_step[ends[q]], stage, ends[q]
        while e >= 1:
            prev_stage = from_stage[e, s, j]
            if prev_stage >= 0:
                pending[prev_stage] = True
                s = prev_stage
                continue
            if pending.any():
                keep[n] = j
                n += 1
            pending[:] = False
            j = pred[e, s, j]
            e -= 1
        total, ar, ac = 0.0, r0, c0
        for m in range(n - 1, -1, -1):
            br, bc = node_cell[keep[m], 0], node_cell[keep[m], 1]
            total += octile(ar, ac, br, bc)
            ar, ac = br, bc
        out[q] = total
    return out


@njit(cache=True)
def octile(ar, ac, br, bc):  # pragma: no cover - numba
    """The shortest 8-connected length between cells (ar, ac) and (br, bc), in cells (a lower bound of any path's
    length)."""
    dr, dc = abs(ar - br), abs(ac - bc)
    return max(dr, dc) + (np.sqrt(2.0) - 1.0) * min(dr, dc)


def reachable(problem: SearchProblem) -> np.ndarray:
    """(M,) the nodes some sequence from the start reaches (breadth-first over finite steps of ``problem``)."""
    reach = np.isfinite(problem.start)
    frontier = reach.copy()
    step = np.isfinite(problem.transition)
    while frontier.any():
        new = step[frontier].any(axis=0) & ~reach
        reach |= new
        frontier = new
    return reach


def why_no_plan(
    problem: SearchProblem, ins: Instruction, x0: np.ndarray, avoiding: bool, unreachable: list[str]
) -> Exception:
    """The typed error (one line) saying why ``problem`` (the metric fallback of instruction ``ins`` from the start
    pose ``x0``) has no solution: the start reaches no node, or no node completing some stage, or (every stage
    reachable) the horizon is too short. ``unreachable``: names of the places with no node (no free cell the
    robot fits in), given as a hint."""
    where = f"from ({x0[0]:.2f}, {x0[1]:.2f})"
    tail = " without entering the places to avoid" if avoiding else ""
    reach = reachable(problem)
    if not reach.any():
        return StartBlocked(f"no place can be reached {where}{tail} (the start is cut off from every place)")
    for s, q in enumerate(ins.stages):
        if not (reach & problem.completes[s]).any():
            role = "goal" if s == len(ins.stages) - 1 else f"waypoint {s + 1}"
            hint = f" (no free cell the robot fits in: {', '.join(sorted(set(unreachable)))})" if unreachable else ""
            return NoReachablePlace(f"no free path {where} reaches a place named '{q.label}' ({role}){tail}{hint}")
    return HorizonTooShort(
        f"no sequence of at most {problem.max_steps} place-to-place steps {where} "
        f"satisfies '{ins.describe()}'{tail}; raise max_steps"
    )
