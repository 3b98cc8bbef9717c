"""A seeded teaching walk through a synthetic floor plan: a continuous trajectory and utterances at some poses.

The robot starts in the entrance (else the living room, else room 0) and visits every room depth-first, always
taking the nearest door that leads to a room it has not seen, and backtracking through the door it came in by.
On its first visit to a room it stops at ``events_per_room`` random poses and hears an utterance at each (the
teaching events); later visits only pass through. Collision-free by construction: each room's free interior is a
rectangle, so straight moves between points of the rectangle shrunk by ``clearance_m`` (not shrunk on the open
boundary between two corridor places) stay clear of the walls, and a door is crossed along the line through its
centre, perpendicular to the wall, from a point ``clearance_m`` before it to a point ``clearance_m`` after it.
Door-to-door moves in a corridor follow its centre line.

Utterances are English templates such as "this is the kitchen" or "you are in the corridor" (function words
shared by every place). ``word_noise`` is the probability that the place word is replaced by another place name
(drawn uniformly from ``PLACE_VOCABULARY``); ``insert_noise`` the probability that one extra random word is
inserted. Every random choice comes from one ``np.random.default_rng(seed)``.
"""

from __future__ import annotations

import math

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.synthetic_plan import Door, FloorPlan, seeded_rng
from spcotmhp.datasets.synthetic_vocab import ALL_WORDS, LIVING, PLACE_VOCABULARY, TEMPLATES
from spcotmhp.errors import DatasetError
from spcotmhp.limits import MAX_SYNTH_EVENTS, check_count

COORD_DECIMALS = 3  # poses are rounded to the millimetre (so they write to CSV exactly)


def check_events_per_room(events_per_room: object, n_rooms: int = 1) -> int:
    """``events_per_room`` as an int: an integer >= 1 whose walk through ``n_rooms`` rooms teaches at most
    ``MAX_SYNTH_EVENTS`` events in all, else DatasetError."""
    most = max(1, MAX_SYNTH_EVENTS // max(n_rooms, 1))
    where = f" ({n_rooms} rooms x events_per_room is at most {MAX_SYNTH_EVENTS} events)" if n_rooms > 1 else ""
    return check_count(events_per_room, "events_per_room" + where, 1, most, DatasetError)


def teaching_walk(
    plan: FloorPlan,
    events_per_room: int = 15,
    step_m: float = 0.1,
    word_noise: float = 0.0,
    lang: str = "en",
    seed: int | np.random.Generator = 0,
    insert_noise: float = 0.0,
    clearance_m: float = 0.4,
) -> Dataset:
    """Walk through every room of ``plan`` and teach each one ``events_per_room`` times.

    Args:
        plan: a floor plan from ``generate_floor_plan``.
        events_per_room: teaching events (utterances) on the first visit to each room.
        step_m: largest distance between consecutive trajectory poses (0 < step_m <= 0.5).
        word_noise: probability that an utterance's place word is replaced by another place name.
        lang: "en" (the only language of the templates).
        seed: an int or a numpy Generator; the same seed gives the same walk.
        insert_noise: probability that an utterance gets one extra random word.
        clearance_m: least distance kept from walls (>= 0.25 m, at most half the narrowest door).

    Returns:
        A Dataset with trajectory (T, 2), event_steps (E,), positions = trajectory[event_steps], tokens,
        truth_place = room index, truth_concept = index of the room's name in ``plan.distinct_names``, the
        plan's adjacency and room names; features None.
    """
    if lang != "en":
        raise DatasetError(f"synthetic teaching utterances exist in English only; got lang={lang!r}, use 'en'")
    check_events_per_room(events_per_room, len(plan.rooms))
    if not 0 < step_m <= 0.5:
        raise DatasetError(f"step_m must be in (0, 0.5] metres, got {step_m}")
    for label, p in (("word_noise", word_noise), ("insert_noise", insert_noise)):
        if not 0.0 <= p <= 1.0:
            raise DatasetError(f"{label} is a probability in [0, 1], got {p}")
    narrowest = min((d.hi - d.lo for d in plan.doors if d.w1 > d.w0), default=math.inf) * plan.map.resolution
    if not 0.25 <= clearance_m <= narrowest / 2:
        raise DatasetError(
            f"clearance_m must be in [0.25, {narrowest / 2:g}] m (half the narrowest door), got {clearance_m}"
        )
    rng = seeded_rng(seed)
    walker = _Walker(plan, clearance_m / plan.map.resolution, int(events_per_room), rng)
    walker.run()
    trajectory, event_steps = _densify(np.array(walker.points), walker.event_points, plan, step_m)
    rooms = np.array(walker.event_rooms, dtype=np.int64)
    concepts = {name: k for k, name in enumerate(plan.distinct_names)}
    return Dataset(
        name=f"synthetic-{plan.kind}",
        map=plan.map,
        positions=trajectory[event_steps].copy(),
        tokens=utterances([plan.rooms[r].name for r in rooms], word_noise, insert_noise, rng),
        lang="en",
        trajectory=trajectory,
        event_steps=event_steps,
        truth_place=rooms,
        truth_concept=np.array([concepts[plan.rooms[r].name] for r in rooms], dtype=np.int64),
        adjacency=plan.adjacency.copy(),
        place_names=plan.names,
    )


def utterances(names: list[str], word_noise: float, insert_noise: float, rng: np.random.Generator) -> list[list[str]]:
    """One templated utterance (token list) per place name, with substitution and insertion noise.

    All random numbers are drawn for every utterance whatever the noise levels, so one seed gives the same
    templates at every noise level and a higher level only changes more of the words.
    """
    n = len(names)
    template = rng.integers(len(TEMPLATES), size=n)
    substitute = rng.random(n) < word_noise
    other = rng.integers(len(PLACE_VOCABULARY) - 1, size=n)
    insert = rng.random(n) < insert_noise
    extra = rng.integers(len(ALL_WORDS), size=n)
    where = rng.random(n)
    out = []
    for i, name in enumerate(names):
        if substitute[i]:
            choices = [w for w in PLACE_VOCABULARY if w != name]
            name = choices[other[i] % len(choices)]
        tokens = TEMPLATES[template[i]].format(name).split()
        if insert[i]:
            tokens.insert(int(where[i] * (len(tokens) + 1)), ALL_WORDS[extra[i]])
        out.append(tokens)
    return out


class _Walker:
    """Builds the waypoint list (continuous (row, col) cell coordinates) of the depth-first walk."""

    def __init__(self, plan: FloorPlan, clearance: float, events: int, rng: np.random.Generator) -> None:
        self.plan, self.events, self.rng = plan, events, rng
        self.safe = [_safe_rect(plan, i, clearance) for i in range(len(plan.rooms))]
        self.clearance = clearance
        self.links: list[list[tuple[int, Door]]] = [[] for _ in plan.rooms]
        for d in plan.doors:
            a, b = d.rooms
            self.links[a].append((b, d))
            self.links[b].append((a, d))
        self.points: list[np.ndarray] = []
        self.event_points: list[int] = []
        self.event_rooms: list[int] = []

    def run(self) -> None:
        names = self.plan.names
        start = names.index("entrance") if "entrance" in names else names.index(LIVING) if LIVING in names else 0
        lo, hi = self.safe[start]
        self.points.append((lo + hi) / 2)
        seen = {start}
        stack: list[tuple[int, Door | None]] = [(start, None)]
        self._teach(start)
        while len(seen) < len(self.plan.rooms):
            if not stack:
                missing = sorted(set(range(len(self.plan.rooms))) - seen)
                raise DatasetError(f"rooms {missing} cannot be reached through the plan's doors")
            room, came_by = stack[-1]
            options = [
                (float(np.hypot(*(self._approach(d, room) - self.points[-1]))), k, nb, d)
                for k, (nb, d) in enumerate(self.links[room])
                if nb not in seen
            ]
            if options:
                _, _, nb, door = min(options, key=lambda o: (o[0], o[1]))
                self._cross(room, nb, door)
                seen.add(nb)
                stack.append((nb, door))
                self._teach(nb)
            else:
                stack.pop()
                if stack:  # only the start came by no door, and it is the last on the stack
                    assert came_by is not None
                    self._cross(room, stack[-1][0], came_by)

    def _teach(self, room: int) -> None:
        """Stop at random poses in ``room`` (nearest first) and record an event at each."""
        lo, hi = self.safe[room]
        todo = list(lo + (hi - lo) * self.rng.random((self.events, 2)))
        while todo:
            k = int(np.argmin([np.hypot(*(p - self.points[-1])) for p in todo]))
            self.points.append(todo.pop(k))
            self.event_points.append(len(self.points) - 1)
            self.event_rooms.append(room)

    def _approach(self, door: Door, room: int) -> np.ndarray:
        """The point ``clearance`` before ``door`` on ``room``'s side, on the line through the door's centre."""
        centre = np.array(door.centre)
        box = self.plan.rooms[room].box
        below = box[2] <= door.w0 if door.axis == 0 else box[3] <= door.w0
        centre[door.axis] = door.w0 - self.clearance if below else door.w1 + self.clearance
        return centre

    def _cross(self, room: int, to: int, door: Door) -> None:
        """Move inside ``room`` to ``door`` (along the centre line in a corridor) and through it into ``to``."""
        target = self._approach(door, room)
        if self.plan.rooms[room].is_corridor:
            r0, c0, r1, c1 = self.plan.rooms[room].box
            axis = 0 if r1 - r0 < c1 - c0 else 1  # the coordinate fixed on the centre line
            middle = ((r0 + r1) if axis == 0 else (c0 + c1)) / 2
            for p in (self.points[-1], target):
                q = p.copy()
                q[axis] = middle
                self.points.append(q)
        self.points += [target, self._approach(door, to)]


def _safe_rect(plan: FloorPlan, room: int, clearance: float) -> tuple[np.ndarray, np.ndarray]:
    """Corners (row, col) of the room's interior shrunk by ``clearance`` cells on every side but the open ones."""
    r0, c0, r1, c1 = plan.rooms[room].box
    shrink = np.full(4, clearance)  # bottom, left, top, right
    for d in plan.doors:
        if room not in d.rooms or d.w0 != d.w1:
            continue
        if d.axis == 0 and d.lo <= c0 and d.hi >= c1:
            shrink[0 if d.w0 == r0 else 2] = 0.0
        if d.axis == 1 and d.lo <= r0 and d.hi >= r1:
            shrink[1 if d.w0 == c0 else 3] = 0.0
    lo = np.array([r0 + shrink[0], c0 + shrink[1]])
    hi = np.array([r1 - shrink[2], c1 - shrink[3]])
    if np.any(hi < lo):
        raise DatasetError(
            f"room {room} ({plan.rooms[room].name}) is narrower than twice the clearance "
            f"{clearance * plan.map.resolution:g} m"
        )
    return lo, hi


def _densify(
    points: np.ndarray, event_points: list[int], plan: FloorPlan, step_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """World poses (x, y) at most ``step_m`` apart along the waypoints, and each event's pose index."""
    res = plan.map.resolution
    gaps = np.hypot(*np.diff(points, axis=0).T) * res
    n = np.ceil(gaps / step_m - 1e-9).astype(np.int64)
    ends = np.concatenate([[0], np.cumsum(n)])  # pose index of each waypoint
    seg = np.repeat(np.arange(len(n)), n)
    frac = (np.arange(len(seg)) - ends[seg] + 1) / n[seg]
    rc = np.concatenate([points[:1], points[seg] + (points[seg + 1] - points[seg]) * frac[:, None]])
    xy = np.stack([plan.map.origin[0] + rc[:, 1] * res, plan.map.origin[1] + rc[:, 0] * res], axis=1)
    return np.round(xy, COORD_DECIMALS), ends[np.array(event_points, dtype=np.int64)]
