"""Questions where the map is unsure: the spots where an answer ("this is the kitchen") would tell the model most
about what a place is called (issue 24).

The measure is the model's own: at a position x, the name the model expects to hear is

    p(n | x) = sum_k p(k | x) p(n | k),   p(k | x) of Eq. 3 (the place posterior),
                                         p(n | k) = sum_l p(l | k) W_l(n) over the place words n (Eqs. 10-17)

and an answer (the true name, a teach at x) removes its uncertainty, so the expected information an answer gives
about the name at x is the entropy H[p(n | x)] in nats (the expected change of the name's posterior there, with the
model's own p(n | x) as the distribution of answers; the names are the active places' labels, a name's p(n | k)
the geometric mean of its words' p(w | k)). It is high where a place's words belong to two names, where two places
with different names share the position, and where a place's few events leave its words spread over concepts; it
is zero where one name is certain. It does not see two rooms of one name merged into one place (both answers
would be the same name); with an answer model that judges a split by the robot's walk (``teaching.answers``,
the default), the places the walk says are two are asked about first (``answers.split_gain``). Before all of
these come the taught names that no longer name a place of their own (``learning.merges``, issue 35): one
question per such name, at its teaching point nearest the mean of its points at the shared place. The candidate
positions are the teaching events' positions (the learner state's; else the places' means), on known free
cells, best first, each at least ``SPACING_M`` from the ones before (one question per spot). ``why`` says which
of those causes applies, read off the same quantities.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.learning.merges import Merge, merges, taught_names
from spcotmhp.learning.model import SpatialConceptModel

SPACING_M = 2.0
"""Questions are at least this far apart (metres): two spots closer than a room's half-width ask the same thing."""
MIN_ENTROPY = 0.1
"""Spots whose name entropy is below this (nats; p = 0.98 on one name) are not asked about."""
ASK = {"en": "What is this place called?", "ja": "ここは何という場所ですか？"}


def name_distribution(model: SpatialConceptModel, xy: np.ndarray, names: list[str], words: list[str]) -> np.ndarray:
    """(N, len(names)) p(n | x) at the positions ``xy`` (module docstring), over the places' names ``names`` (their
    labels, each one or more of the place words ``words``): a name is said with all its words, so p(n | k) is the
    geometric mean of its words' p(w | k), normalised over the names."""
    from spcotmhp.learning.merges import name_given_place

    p_name = name_given_place(model, [tuple(n.split()) for n in names])  # (K, names) p(n | k)
    act = np.asarray(model.active_places, dtype=bool)
    post = model.place_posterior(np.asarray(xy, dtype=float)) * act[None, :]
    post /= np.maximum(post.sum(axis=1, keepdims=True), 1e-300)
    p = post @ p_name
    return p / np.maximum(p.sum(axis=1, keepdims=True), 1e-300)


def questions(
    model: SpatialConceptModel, max_questions: int = 5, lang: str | None = None, answers: str | None = None
) -> list[dict]:
    """The questions, best first (module docstring): {x, y, ask, candidates, why, information}. With an answer
    model that judges splits by the robot's walk (``teaching.answers``, ``answers``: its name, None the default),
    the places the walk says are two are asked about first (``answers.split_gain``: information is that gain)."""
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
    from spcotmhp.teaching.answers import answer_model, on_free_cells, split_gain

    if max_questions < 1:
        return []
    said = name_vocabulary(model)
    lang = lang or ("ja" if any(not w.isascii() for w in said) else "en")
    out: list[dict] = merge_questions(model, said, lang)[:max_questions]
    words = place_vocabulary(model)
    labels = place_labels(model, words)
    names = sorted({labels[k] for k in np.flatnonzero(model.active_places) if not labels[k].startswith("place ")})
    xy = _candidate_positions(model)
    if not words or not len(xy) or not names:
        return out
    p = name_distribution(model, xy, names, words)
    with np.errstate(divide="ignore", invalid="ignore"):
        entropy = -np.nansum(np.where(p > 0, p * np.log(p), 0.0), axis=1)
    post = model.place_posterior(np.asarray(xy, dtype=float))
    for gain, spot in split_gain(model) if answer_model(answers).walk else []:
        if len(out) < max_questions and on_free_cells(model, spot[None])[0]:
            k = int(np.argmax(model.place_posterior(spot[None])[0]))
            out.append(
                {
                    "x": round(float(spot[0]), 3),
                    "y": round(float(spot[1]), 3),
                    "ask": ASK.get(lang, ASK["en"]),
                    "candidates": [labels[k]],
                    "why": f"the robot's walk says the place here ('{labels[k]}') may be two",
                    "information": round(float(gain), 4),
                }
            )
    for i in np.argsort(-entropy, kind="stable"):
        if entropy[i] < MIN_ENTROPY or len(out) >= max_questions:
            break
        if any(np.hypot(q["x"] - xy[i, 0], q["y"] - xy[i, 1]) < SPACING_M for q in out):
            continue
        order = np.argsort(-p[i])
        candidates = [names[j] for j in order if p[i, j] >= 0.1][:4]
        out.append(
            {
                "x": round(float(xy[i, 0]), 3),
                "y": round(float(xy[i, 1]), 3),
                "ask": ASK.get(lang, ASK["en"]),
                "candidates": candidates,
                "why": _why(model, post[i], labels, candidates, names),
                "information": round(float(entropy[i]), 4),
            }
        )
    return out


def name_vocabulary(model: SpatialConceptModel) -> list[str]:
    """The words a taught name is made of (``learning.merges``), sorted: the place words (``place_vocabulary``)
    and every other word that the model's concepts say more often than its background does (the word switches
    of the learner state, concepts.py) and that is said with at most one place word; grammar and filler words
    never. The second part keeps a name the place vocabulary drops: in a concept that took in two rooms, a name
    taught less than 3/4 as often as the other is no place word (rule 1 there), so it could be neither asked for
    nor reported ("east" of "east corridor" where both corridors are one place). The last condition keeps out
    the frame words a template says with every name ("the name of this place is ..."): said with several names,
    they are no part of one."""
    from spcotmhp.planning.vocabulary import FUNCTION_WORDS, place_vocabulary

    words = place_vocabulary(model)
    if model.learner is None:
        return words
    a, V = model.learner["arrays"], len(model.vocabulary)
    tok, z = np.asarray(a["tok_word"], dtype=np.int64), np.asarray(a["tok_z"], dtype=bool)
    said = np.bincount(tok[z], minlength=V) > np.bincount(tok[~z], minlength=V)
    place = np.zeros(V, dtype=bool)
    place[[model.word_index[w] for w in words]] = True
    ptr = np.asarray(a["tok_ptr"], dtype=np.int64)
    with_names: dict[int, set[int]] = {}
    for e in range(len(ptr) - 1):
        event = set(tok[ptr[e] : ptr[e + 1]].tolist())
        names = {w for w in event if place[w]}
        for w in event:
            with_names.setdefault(w, set()).update(names)
    extra = {
        model.vocabulary[w]
        for w in np.flatnonzero(said & ~place)
        if model.vocabulary[w] not in FUNCTION_WORDS and len(with_names.get(int(w), ())) <= 1
    }
    return sorted(set(words) | extra)


def said_merges(model: SpatialConceptModel, words: list[str] | None = None) -> list[Merge]:
    """The taught names without a place of their own (``learning.merges.merges``) with the name words
    (``words``, default :func:`name_vocabulary`) and the places' labels: what ``learn``, ``show``, ``/places``
    and the questions report."""
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary

    words = name_vocabulary(model) if words is None else words
    return merges(model, words, place_labels(model, place_vocabulary(model)))


def merge_questions(model: SpatialConceptModel, words: list[str], lang: str) -> list[dict]:
    """One question per taught name without a place of its own (``learning.merges``; ``words``: the name words,
    :func:`name_vocabulary`), the first questions: at that name's teaching point nearest the mean of its teaching
    points at the shared place (on a known free cell; the mean itself when none is), with the two names as
    candidates; ``information`` is the entropy of p(n | x) over the two names there."""
    from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
    from spcotmhp.teaching.answers import on_free_cells

    out = []
    names = {n.text: n for n in taught_names(model, words, place_labels(model, place_vocabulary(model)))}
    X = np.asarray(model.learner["arrays"]["X"], dtype=float) if model.learner is not None else np.empty((0, 2))
    for m in said_merges(model, words):
        mean = np.array([m.x, m.y])
        points = X[names[m.name].events] if m.name in names else mean[None]
        points = points[on_free_cells(model, points)] if len(points) else points
        spot = points[np.argmin(np.linalg.norm(points - mean, axis=1))] if len(points) else mean
        p = name_distribution(model, spot[None], [m.name, m.other], words)[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            entropy = float(-np.nansum(np.where(p > 0, p * np.log(p), 0.0)))
        out.append(
            {
                "x": round(float(spot[0]), 3),
                "y": round(float(spot[1]), 3),
                "ask": ASK.get(lang, ASK["en"]),
                "candidates": [m.name, m.other],
                "why": f"{m.sentence}: '{m.name}' names no place of its own",
                "information": round(entropy, 4),
            }
        )
    return out


def _candidate_positions(model: SpatialConceptModel) -> np.ndarray:
    """Teaching events' positions (else the active places' means) on known free cells, one per 0.5 m cell."""
    learner = model.learner
    xy = np.asarray(learner["arrays"]["X"], dtype=float) if learner is not None else np.empty((0, 2))
    if not len(xy):
        xy = model.mu[np.asarray(model.active_places, dtype=bool)]
    from spcotmhp.teaching.answers import on_free_cells

    xy = xy[on_free_cells(model, xy)]
    _, first = np.unique(np.floor(xy / 0.5).astype(np.int64), axis=0, return_index=True)
    return xy[np.sort(first)]


def _why(model: SpatialConceptModel, post: np.ndarray, labels: list[str], candidates: list[str], names) -> str:
    """Which cause of the uncertainty applies here, from the same quantities."""
    k = int(np.argmax(post))
    reasons = []
    if labels[k] not in names:
        reasons.append(f"the place here is labelled '{labels[k]}', which no place's name is alone")
    second = np.argsort(-post)[1] if post.size > 1 else k
    if post[second] > 0.2 and labels[second] != labels[k]:
        reasons.append(f"two places meet here ('{labels[k]}' and '{labels[int(second)]}')")
    if model.learner is not None:
        events = int(np.sum(np.asarray(model.learner["arrays"]["place"]) == k))
        if events < 5:
            reasons.append(f"the place here holds {events} teaching event(s)")
    if not reasons:
        reasons.append("the names said here are spread over several concepts")
    return "; ".join(reasons) + f"; the model would expect {' or '.join(repr(c) for c in candidates) or 'no name'}"
