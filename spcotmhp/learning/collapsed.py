"""The online learner's state: teaching events, their assignments (i_e, C_e, background switches) and the
sufficient statistics behind every conditional of Eqs. 5-17, with every parameter integrated out.

One Gibbs step for event e (``CollapsedState.step``) removes it from the counts and draws (i_e, C_e) jointly from

    p(i_e = k, C_e = l | rest) proportional to
        t(x_e | place k)                                        NIW posterior predictive (Eqs. 3, 5-6)
      * (R[i_{e-1}, k] + omega) / (R[i_{e-1}] + K omega)        psi integrated out (Eqs. 7-9, first factor)
      * (R[k, i_{e+1}] + omega) / (R[k] + K omega)              the same for the next event, when there is one
      / sum_c phi_c(k)                                          unigram rescaling (Eq. 9), phi_c its posterior mean
      * (n_l + alpha) (n_{l,k} + gamma) / (n_l + K gamma)       pi, phi integrated out (Eqs. 10-11, 14)
      * DirMult(f_e | chi + F_l) DirMult(S_e | beta + W_l)     theta, W integrated out (Eqs. 12-13, 15-17)

then resamples the background switch of each of its tokens (as ``concepts.py`` does in batch).

A *naming* event (a teach, :func:`spcotmhp.teaching.teach.teach`: its tokens are the name a person said for the
place where the robot stands) is conditioned on that act: its tokens are concept tokens (a name is not a
background word), and its concept is one that already holds one of its words or a concept with no events yet,
so that the name is a name of the concept it joins, not a stray token of an unrelated one; among those (i_e, C_e)
is set to the mode of the conditional above (``log_conditional(..., concepts=...)``), which makes a teach's
outcome a function of the model and the position (``teach`` says which it was) rather than of a draw. R holds the
transition counts of the event sequence plus, with reverse replay (Section 3.2), their transpose.

Answers (a departure from the paper, taken only for teaches given in reply to the robot's question;
:mod:`spcotmhp.teaching.answers` says which and why): an event may be *alone*, a segment of its own, so that no
transition into or out of it is counted (the events before and after it are linked as if it were not there: it
is not a step of the robot's walk), and may carry a *weight* w, entering every count as w events and its
conditional to the power w. Events the robot records as it goes are neither (alone False, weight 1): the paper's
model. This is the
batch sampler's step 4 (Eq. 9's place term) and step 5 (the collapsed concept step) drawn as one block, with
mu, Sigma and psi integrated out instead of drawn: a single-site collapsed Gibbs step. Counts may be fractional
(pseudo-counts of a model loaded without its events; ``online_init``).
"""

from __future__ import annotations

import numpy as np

from spcotmhp.learning.model import Hyperparameters

SWITCH_PRIOR = 1.0  # Beta(1, 1) prior of the concept / background switch (as concepts.py)


class CollapsedState:
    """Counts and events of one learner (K places, L concepts, V words, D feature dimensions or None)."""

    def __init__(
        self,
        K: int,
        L: int,
        V: int,
        D: int | None,
        hyper: Hyperparameters,
        replay: bool = True,
        background: bool = True,
    ) -> None:
        self.K, self.L, self.V, self.D = K, L, V, D
        self.hyper = hyper.resized(L, K)
        self.replay, self.background = replay, background
        self.log_new_place: float | None = None  # log density of a position under an empty place (None: NIW)
        self.n_k, self.sx, self.sxx = np.zeros(K), np.zeros((K, 2)), np.zeros((K, 2, 2))
        self.n_l, self.n_lk = np.zeros(L), np.zeros((L, K))
        self.W_lv, self.bg_v, self.z_tot = (
            np.zeros((L, V)),
            np.zeros(V),
            np.zeros(2),
        )  # z_tot: background, concept
        self.F_ld = None if D is None else np.zeros((L, D))
        self.trans = np.zeros((K, K))  # forward transitions of the event sequence
        self.X = np.zeros((0, 2))
        self.place = np.zeros(0, dtype=np.int64)
        self.concept = np.zeros(0, dtype=np.int64)
        self.tokens: list[np.ndarray] = []  # word indices of each event
        self.z: list[np.ndarray] = []  # True: concept token, False: background token
        self.features: list[np.ndarray | None] = []
        self.named: list[bool] = []  # naming events (module docstring)
        self.alone: list[bool] = []  # events that are a segment of their own (answers; module docstring)
        self.walk_X: np.ndarray | None = None  # the robot's poses along its walk (teaching.answers.walk_poses)
        self.weight: list[float] = []  # evidence weight of each event (1: the paper's; module docstring)
        self.words: list[str] | None = None  # the vocabulary, word j of the tokens' index j (set by the learner)

    # ---- sizes ---------------------------------------------------------------------------------------------
    @property
    def E(self) -> int:
        return len(self.place)

    def grow(self, K: int | None = None, L: int | None = None, V: int | None = None) -> None:
        """Larger truncations K, L (weak-limit components with no data) or vocabulary V (new words)."""
        K, L, V = K or self.K, L or self.L, V or self.V
        dk, dl, dv = K - self.K, L - self.L, V - self.V
        self.n_k, self.sx, self.sxx = _pad(self.n_k, dk), _pad(self.sx, dk), _pad(self.sxx, dk)
        self.trans = _pad(_pad(self.trans, dk), dk, axis=1)
        self.n_l, self.n_lk = _pad(self.n_l, dl), _pad(_pad(self.n_lk, dl), dk, axis=1)
        self.W_lv, self.bg_v = _pad(_pad(self.W_lv, dl), dv, axis=1), _pad(self.bg_v, dv)
        if self.F_ld is not None:
            self.F_ld = _pad(self.F_ld, dl)
        self.K, self.L, self.V = K, L, V
        self.hyper = self.hyper.resized(L, K)

    # ---- events --------------------------------------------------------------------------------------------
    def append(
        self,
        x: np.ndarray,
        tokens: np.ndarray,
        features: np.ndarray | None,
        rng: np.random.Generator,
        named: bool = False,
        alone: bool = False,
        weight: float = 1.0,
    ) -> int:
        """Add a new event and draw its place, concept and switches (a naming event: set to the mode, module
        docstring); returns its index.

        The first draw leaves out the transition factors, and its tokens start as concept tokens. Teaching comes
        in runs at one place (15 consecutive events per room in the bundled homes), so the self-transition
        counts of the previous place outweigh a position a room away; with them the first event of a new room
        usually joined the previous place, and single-site steps could not split it off again (3LDK_01, 5
        seeds: place ARI 0.75 with them, 0.93 without). The lag steps that follow include them. Tokens that
        start as background tokens (a fair coin, as in batch) made new place names vanish into the
        background when the background held few tokens (concept ARI 0.60 against 0.92).
        """
        self.X = np.vstack([self.X, np.asarray(x, dtype=float)[None]])
        self.place = np.append(self.place, -1)
        self.concept = np.append(self.concept, -1)
        self.tokens.append(np.asarray(tokens, dtype=np.int64))
        self.z.append(np.ones(len(tokens), dtype=bool))  # concept tokens first; switches resampled after C_e
        self.features.append(features)
        self.named.append(bool(named))
        self.alone.append(bool(alone))
        self.weight.append(float(weight))
        e = self.E - 1
        self.draw(e, rng, transitions=False)
        return e

    def step(self, e: int, rng: np.random.Generator) -> None:
        """One collapsed Gibbs step for event e (module docstring)."""
        self.move(e, -1.0)
        self.draw(e, rng)

    def draw(self, e: int, rng: np.random.Generator, transitions: bool = True) -> None:
        """Draw (i_e, C_e) for an event not in the counts, add it, then resample its token switches (a naming
        event: the mode among the concepts that can hold its name, its tokens concept tokens; module docstring)."""
        if self.is_named(e):
            cols = self.naming_concepts(e)
            logp = self.log_conditional(e, transitions, cols)
            k, c = np.unravel_index(int(np.argmax(logp)), logp.shape)
            self.place[e], self.concept[e] = int(k), int(cols[c])
            self.move(e, 1.0)
            return
        logp = self.log_conditional(e, transitions)
        flat = int(np.argmax(logp.ravel() + rng.gumbel(size=logp.size)))
        self.place[e], self.concept[e] = flat // self.L, flat % self.L
        self.move(e, 1.0)
        if self.background:
            self._switches(e, rng)

    def is_named(self, e: int) -> bool:
        return e < len(self.named) and self.named[e]

    def is_alone(self, e: int) -> bool:
        return e < len(self.alone) and self.alone[e]

    def weight_of(self, e: int) -> float:
        return self.weight[e] if e < len(self.weight) else 1.0

    def neighbours(self, e: int) -> tuple[int, int]:
        """The events before and after e in the robot's walk (-1: none): the nearest that are not alone; an alone
        event has none (module docstring)."""
        if self.is_alone(e):
            return -1, -1
        prev, nxt = e - 1, e + 1
        while prev >= 0 and self.is_alone(prev):
            prev -= 1
        while nxt < self.E and self.is_alone(nxt):
            nxt += 1
        return prev, (nxt if nxt < self.E else -1)

    def naming_concepts(self, e: int) -> np.ndarray:
        """The concepts a naming event may join (event e out of the counts): those whose concept tokens hold one
        of its words, and the first concept with no events (all empty ones are alike)."""
        holding = self.W_lv[:, np.unique(self.tokens[e])].sum(axis=1) > 0
        empty = np.flatnonzero(self.n_l <= 0)
        return np.union1d(np.flatnonzero(holding), empty[:1]).astype(np.int64)

    # ---- the conditional -----------------------------------------------------------------------------------
    def log_conditional(self, e: int, transitions: bool = True, concepts: np.ndarray | None = None) -> np.ndarray:
        """(K, L) log p(i_e = k, C_e = l | everything else) up to a constant; event e must be out of the counts.
        Without ``transitions`` the psi factors are left out (the first draw of a new event: ``append``); with
        ``concepts`` only those columns are computed ((K, len(concepts)); the split-merge moves need one or two).
        """
        h = self.hyper
        place = self.log_predictive(self.X[e])
        R = self.trans + self.trans.T if self.replay else self.trans
        row = R.sum(axis=1) + self.K * h.omega
        before, after = self.neighbours(e)
        prev, nxt = (self.place[before] if before >= 0 else -1), (self.place[after] if after >= 0 else -1)
        if prev >= 0 and transitions:
            place = place + np.log(R[prev] + h.omega) - np.log(row[prev])
        if nxt >= 0 and transitions:
            place = place + np.log(R[:, nxt] + h.omega) - np.log(row)
        phi = (self.n_lk + h.gamma) / (self.n_l + self.K * h.gamma)[:, None]
        place = place - np.log(phi.sum(axis=0))  # Eq. 9 rescaling
        cols = np.arange(self.L) if concepts is None else np.asarray(concepts)
        concept = np.log(self.n_l[cols] + h.alpha) + self._log_words(e, cols) + self._log_features(e, cols)
        joint = np.log(phi.T[:, cols]) + concept[None, :]  # (K, L)
        w = self.weight_of(e)
        return joint + place[:, None] if w == 1.0 else w * (joint + place[:, None])

    def log_predictive(self, x: np.ndarray) -> np.ndarray:
        """log t(x | NIW posterior of place k) for every place (the Student-t posterior predictive; Murphy 2007,
        Eq. 258): (K,), or (P, K) for P positions x (P, 2)."""
        h = self.hyper
        m0, V0 = np.asarray(h.m0, dtype=float), np.asarray(h.V0, dtype=float)
        kn, nun = h.kappa0 + self.n_k, h.nu0 + self.n_k
        mn = (h.kappa0 * m0 + self.sx) / kn[:, None]
        Vn = V0 + self.sxx + h.kappa0 * np.outer(m0, m0) - kn[:, None, None] * mn[:, :, None] * mn[:, None, :]
        dof = nun - 1.0
        S = Vn * ((kn + 1.0) / (kn * dof))[:, None, None]
        a, b, d = S[:, 0, 0], 0.5 * (S[:, 0, 1] + S[:, 1, 0]), S[:, 1, 1]
        det = np.maximum(a * d - b * b, 1e-300)
        dx, dy = x[..., 0, None] - mn[:, 0], x[..., 1, None] - mn[:, 1]
        maha = (d * dx * dx - 2.0 * b * dx * dy + a * dy * dy) / det
        from scipy.special import gammaln  # here, not at import: loading a model for planning reads this module

        out = (
            gammaln((dof + 2.0) / 2.0)
            - gammaln(dof / 2.0)
            - np.log(dof * np.pi)
            - 0.5 * np.log(det)
            - (dof + 2.0) / 2.0 * np.log1p(maha / dof)
        )
        if self.log_new_place is not None:
            out[..., self.n_k <= 0] = self.log_new_place
        return out

    def _log_words(self, e: int, cols: np.ndarray) -> np.ndarray:
        """log DirMult of event e's concept tokens under each concept of ``cols`` (the counts without e)."""
        beta, W = self.hyper.beta, self.W_lv[cols]
        out = np.zeros(len(cols))
        seen: dict[int, int] = {}
        total = W.sum(axis=1) + self.V * beta
        for j, v in enumerate(self.tokens[e][self.z[e]]):
            rep = seen.get(int(v), 0)
            out += np.log(W[:, v] + beta + rep) - np.log(total + j)
            seen[int(v)] = rep + 1
        return out

    def _log_features(self, e: int, cols: np.ndarray) -> np.ndarray:
        """log DirMult(f_e | chi + F_l) for each concept l of ``cols`` (Eq. 15 with theta integrated out)."""
        f = self.features[e]
        if f is None or self.F_ld is None or self.D is None:
            return np.zeros(len(cols))
        chi, nz, F = self.hyper.chi, np.flatnonzero(f), self.F_ld[cols]
        a = chi + F[:, nz]
        tot = self.D * chi + F.sum(axis=1)
        from scipy.special import gammaln  # here, not at import: loading a model for planning reads this module

        return (gammaln(a + f[nz]) - gammaln(a)).sum(axis=1) + gammaln(tot) - gammaln(tot + f.sum())

    # ---- counts --------------------------------------------------------------------------------------------
    def move(self, e: int, sign: float) -> None:
        """Add (sign 1) or remove (-1) event e's contribution to every count (its place and concept set; a removed
        event gets place and concept -1)."""
        k, l, x = self.place[e], self.concept[e], self.X[e]
        before, after = self.neighbours(e)
        sign *= self.weight_of(e)
        self.n_k[k] += sign
        self.sx[k] += sign * x
        self.sxx[k] += sign * np.outer(x, x)
        self.n_l[l] += sign
        self.n_lk[l, k] += sign
        toks, z = self.tokens[e], self.z[e]
        np.add.at(self.W_lv[l], toks[z], sign)
        np.add.at(self.bg_v, toks[~z], sign)
        self.z_tot += sign * np.array([(~z).sum(), z.sum()])
        f = self.features[e]
        if self.F_ld is not None and f is not None:
            self.F_ld[l] += sign * f
        step = 1.0 if sign > 0 else -1.0  # a transition is one step of the walk, whatever the weight
        if before >= 0 and self.place[before] >= 0:
            self.trans[self.place[before], k] += step
        if after >= 0 and self.place[after] >= 0:
            self.trans[k, self.place[after]] += step
        if sign < 0:
            self.place[e] = self.concept[e] = -1

    def _switches(self, e: int, rng: np.random.Generator | None) -> int:
        """Resample each token's background switch z_eb given the rest (concepts.py's step, one event); without
        ``rng`` set each to its more probable value instead (one step of iterated conditional modes). Returns
        the number of switches changed."""
        l, beta, V = self.concept[e], self.hyper.beta, self.V
        changed = 0
        if self.is_named(e):
            return 0
        for j, v in enumerate(self.tokens[e]):
            was = on = self.z[e][j]
            (self.W_lv[l] if on else self.bg_v)[v] -= 1.0
            self.z_tot[int(on)] -= 1.0
            p1 = (self.z_tot[1] + SWITCH_PRIOR) * (self.W_lv[l, v] + beta) / (self.W_lv[l].sum() + V * beta)
            p0 = (self.z_tot[0] + SWITCH_PRIOR) * (self.bg_v[v] + beta) / (self.bg_v.sum() + V * beta)
            on = bool(p1 > p0) if rng is None else bool(rng.random() * (p0 + p1) < p1)
            self.z[e][j] = on
            changed += on != was
            (self.W_lv[l] if on else self.bg_v)[v] += 1.0
            self.z_tot[int(on)] += 1.0
        return changed

    def switch_mode(self, sweeps: int = 50, events: np.ndarray | None = None) -> None:
        """Iterated conditional modes on the token switches (of ``events`` only, when given), the places and
        concepts held: every switch set to its more probable value given the others, in event order, until a sweep
        changes none (at most ``sweeps``). A deterministic function of the state, which raises the collapsed joint
        at every change."""
        if not self.background:
            return
        order = range(self.E) if events is None else [int(e) for e in events]
        for _ in range(sweeps):
            if not sum(self._switches(e, None) for e in order):
                return


def _pad(a: np.ndarray, extra: int, axis: int = 0) -> np.ndarray:
    """``a`` with ``extra`` zero rows appended along ``axis``."""
    if extra <= 0:
        return a
    shape = list(a.shape)
    shape[axis] = extra
    return np.concatenate([a, np.zeros(shape, dtype=a.dtype)], axis=axis)
