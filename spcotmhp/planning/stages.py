"""The places of each stage of an instruction: which places may complete it, its word term, and what the
instruction's relations and avoided places leave of them (Algorithm 1, lines 9-11; the planner's half that reads
the model's names, :class:`~spcotmhp.planning.planner.HierarchicalPlanner` the other).

Every stage ends at one of its instances (:meth:`StagePlaces.instances`): the stage constraint, a departure from
Eq. 28 stated in the planner's module docstring. Relations ("the bedroom closest to the bath") narrow a stage to
the instance they pick (:mod:`spcotmhp.planning.relations`), measured in the start's free region; avoided places
leave every stage and block their territories (:mod:`spcotmhp.planning.avoid`).
"""

from __future__ import annotations

import numpy as np

from spcotmhp.errors import ConflictingInstruction, PlaceCutOff, StartInAvoidedPlace, UnknownPlaceWord
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.grid_search import cost_to_go, path_from_field
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_settings import PlannerSettings
from spcotmhp.planning.instructions import Instruction, PlaceQuery
from spcotmhp.planning.phrases import PhraseMemo, phrase_key
from spcotmhp.planning.places import LabelIndex, by_label
from spcotmhp.planning.relations import PlaceGeometry, place_geometry, resolve
from spcotmhp.planning.terms import ModelTerms


class StagePlaces:
    """The stage-reading half of :class:`~spcotmhp.planning.planner.HierarchicalPlanner`, which sets the
    attributes below in its constructor."""

    model: SpatialConceptModel
    settings: PlannerSettings
    graph: PlanningGraph
    terms: ModelTerms
    names: list[str]
    shown: list[str]
    label_index: LabelIndex
    numbering: dict[int, tuple[int, int]]
    planned: np.ndarray  # (K,) places with a candidate point in some free region
    resolution: float
    diameter_cells: float
    _main_has_all: bool
    _geometries: dict[int, PlaceGeometry]
    _phrases: PhraseMemo

    def geometry_of(self, region: PlanningGraph) -> PlaceGeometry:
        """What relations measure in a free region's graph (:mod:`spcotmhp.planning.relations`), built on first use
        (a plan naming no relation never pays for it) and kept per region (a dict assignment: a race between
        threads at worst builds one twice)."""
        key = id(region)
        if key not in self._geometries:
            self._geometries[key] = place_geometry(region, self.resolution, self.diameter_cells * self.resolution)
        return self._geometries[key]

    def instance_label(self, k: int) -> str:
        """How place k is called in plans and messages: "bedroom #2" among three bedrooms, else its name."""
        number, count = self.numbering.get(int(k), (1, 1))
        return f"{self.shown[k]} #{number}" if count > 1 else self.shown[k]

    # ---- the places of each stage -------------------------------------------------------------------
    def instances(self, query: PlaceQuery, likely: np.ndarray | None = None, stage: bool = False) -> np.ndarray:
        """(K,) the places a query names: p(i | S) within ``instance_ratio`` of the best
        (:func:`~spcotmhp.planning.places.instance_places`; ``likely``, when already computed) and, when some
        place's name carries all the words of the query (or of one of its N-best alternatives), only such places
        (:func:`~spcotmhp.planning.places.named_places`; names of active places only). Two or more words that
        each belong to some place's name but name no place together ("the kitchen bedroom") are refused;
        otherwise, when some word is in no name (a learned model's labels may leave a word out), p(i | S) alone
        decides."""
        if not self.settings.stage_constraint:  # Eq. 28 as written: any place may complete any stage
            return np.asarray(self.model.active_places, dtype=bool).copy()
        if likely is None:  # instance_places of log p(i | S), in the kernel of the stages' terms
            likely = self.terms.stage_terms([query.words], self.settings.instance_ratio)[1][0]
        named = by_label(self.label_index, query, stage)
        if named.any():
            if query.every:
                return named
            both = named & likely
            return self.numbered(query, both if both.any() else named)
        return self.numbered(query, likely)

    def numbered(self, query: PlaceQuery, places: np.ndarray) -> np.ndarray:
        """The one of ``places`` that a query's instance number names, as plans number the places of one name
        ("bedroom 2" is the place shown as "bedroom #2"; :meth:`instance_label`); all of them without a number.

        Raises:
            UnknownPlaceWord: no place of that name has that number.
        """
        if query.number is None:
            return places
        hit = [int(k) for k in np.flatnonzero(places) if self.numbering.get(int(k), (1, 1))[0] == query.number]
        if len(hit) != 1:
            shown = ", ".join(self.instance_label(int(k)) for k in np.flatnonzero(places)) or "none"
            raise UnknownPlaceWord(f"no place is shown as {query.label!r} (#{query.number}); the places of that "
                                   f"name are: {shown}")  # fmt: skip
        out = np.zeros_like(places)
        out[hit[0]] = True
        return out

    def phrase_terms(self, query: PlaceQuery, stage: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """(K,) the word term of Eq. 28 of a place query (:meth:`~spcotmhp.planning.terms.ModelTerms.stage_terms`)
        and (K,) the places it names (:meth:`instances`, before its relation), read-only, kept per phrase
        (:mod:`spcotmhp.planning.phrases`)."""

        def compute() -> tuple[np.ndarray, np.ndarray]:
            semantic, likely = self.terms.stage_terms([query.words], self.settings.instance_ratio)
            return semantic[0], self.instances(query, likely[0], stage)

        return self._phrases.get(phrase_key(query, stage), self.settings, compute)

    def stage_instances(
        self, ins: Instruction, chosen: dict[int, str] | None = None, region: PlanningGraph | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """(S, K) the word term of Eq. 28 for each stage and (S, K) the instances that may complete it
        (:meth:`instances` of its words), without, for the goal, the places the instruction says not to end
        in ("instead of the kitchen": they may be passed); a relation narrows a stage to the instance it picks
        (:meth:`related`)."""
        stages = ins.stages
        chosen = {} if chosen is None else chosen
        terms = [self.phrase_terms(q, stage=True) for q in stages]
        semantic = np.array([t[0] for t in terms])
        inst = np.array([t[1] for t in terms])
        for s, q in enumerate(stages):
            if q.relation is not None:
                inst[s] = self.related(q, inst[s], chosen, region)
        for q in ins.not_goal:
            inst[-1] &= ~self.related(q, self.phrase_terms(q)[1], chosen, region)
            if not inst[-1].any():
                raise ConflictingInstruction(
                    f"every place named '{ins.goal.label}' is one the instruction says not to end in ('{q.label}')"
                )
        return semantic, inst

    def related(
        self, query: PlaceQuery, candidates: np.ndarray, chosen: dict[int, str], region: PlanningGraph | None = None
    ) -> np.ndarray:
        """The instances among ``candidates`` that the query's relation picks (all of them without one; the tied
        ones on a tie), measured in the start's free ``region``; what the explanation says of each goes into
        ``chosen`` (place -> "the one closest to the bath")."""
        if query.relation is None or not candidates.any():
            return candidates
        others = [self.instances(PlaceQuery.of(arg)) for arg in query.relation.args]
        geometry = self.geometry_of(region if region is not None else self.graph)
        mask, said = resolve(query.relation, candidates, others, geometry, self.instance_label)
        chosen.update(said)
        return mask

    def _check_region(self, region: PlanningGraph, ins: Instruction, inst: np.ndarray, x0: np.ndarray) -> None:
        """:class:`~spcotmhp.errors.PlaceCutOff` when a stage's instances all lie in free regions other than the
        start's ``region`` (each has candidate points, none in this region: :mod:`spcotmhp.planning.regions`).
        A stage whose instances have no candidate point anywhere is left to the search's reason
        (:func:`~spcotmhp.planning.search.why_no_plan`)."""
        if region is self.graph and self._main_has_all:
            return  # every place with a candidate point has one in the start's (main) region
        here = np.zeros(self.model.K, dtype=bool)
        here[region.node_place] = True
        for s, q in enumerate(ins.stages):
            if not (inst[s] & here).any() and (inst[s] & self.planned).any():
                raise PlaceCutOff(
                    f"the {q.label} is not reachable from here ({x0[0]:.2f}, {x0[1]:.2f}): the free space is cut "
                    "(a closed door or a gap in the map) between the start and every place of that name"
                )

    def _avoid(
        self,
        region: PlanningGraph,
        ins: Instruction,
        inst: np.ndarray,
        x0: np.ndarray,
        cell: np.ndarray,
        escape: np.ndarray,
        chosen: dict[int, str],
    ) -> tuple[PlanningGraph, np.ndarray, np.ndarray]:
        """The graph to search (the start's free ``region``'s), the (K,) avoided places, and the way out of them:
        the avoided places leave ``inst`` (in place) and the graph becomes its avoidance view (their nodes removed,
        their territories blocked). A start inside an avoided place (or whose escape run crosses one) leaves it by
        the shortest footprint-safe way (:meth:`_leave`: crop cells, the last the cell planning starts from; empty
        otherwise), and the plan never comes back (issue 34). Raises when a stage has only avoided instances, no way
        out is free, or a stage's places all lie in other free regions (:meth:`_check_region`)."""
        self._check_region(region, ins, inst, x0)
        avoided = np.zeros(self.model.K, dtype=bool)
        way_out = np.empty((0, 2), dtype=np.int64)
        if not ins.avoid:
            return region, avoided, way_out
        for q in ins.avoid:
            avoided |= self.related(q, self.phrase_terms(q)[1], chosen, region)
        if not avoided.any():
            return region, avoided, way_out
        inst &= ~avoided
        for s, q in enumerate(ins.stages):
            if not inst[s].any():
                raise ConflictingInstruction(f"every place named '{q.label}' is also to be avoided")
        graph = avoided_view(region, tuple(np.flatnonzero(avoided).tolist()))
        blocked = graph.blocked
        assert blocked is not None  # an avoidance view has its blocked cells
        esc = graph.to_crop(escape) if len(escape) else escape
        esc = esc[(esc >= 0).all(axis=1) & (esc < np.array(blocked.shape)).all(axis=1)] if len(esc) else esc
        if blocked[cell[0], cell[1]] or (len(esc) and blocked[esc[:, 0], esc[:, 1]].any()):
            way_out = self._leave(region, blocked, cell, x0, avoided, inst)
        return graph, avoided, way_out

    def _leave(
        self,
        region: PlanningGraph,
        blocked: np.ndarray,
        cell: np.ndarray,
        x0: np.ndarray,
        avoided: np.ndarray,
        inst: np.ndarray,
    ) -> np.ndarray:
        """The shortest way (by the map's step cost, Eq. 26's map term: footprint-safe cells only) from the start's
        ``cell`` out of the avoided territories, into the free space outside them from which every stage's places
        can be reached (``inst``: (S, K); a room with two doors is left by the one that leads on): crop cells from
        ``cell`` to the first cell outside.

        Raises:
            StartInAvoidedPlace: no such cell is reachable.
        """
        from scipy import ndimage  # only when a start lies inside a place to avoid

        outside = region.traversable & ~blocked
        labels, _ = ndimage.label(outside, structure=np.ones((3, 3), dtype=bool))
        node_label = labels[region.node_cell[:, 0], region.node_cell[:, 1]]
        leads_on = None
        for stage in inst:
            here = set(node_label[np.isin(region.node_place, np.flatnonzero(stage & ~avoided))].tolist()) - {0}
            leads_on = here if leads_on is None else leads_on & here
        targets = outside & np.isin(labels, sorted(leads_on)) if leads_on else outside
        sources = np.argwhere(targets)
        if len(sources):
            field, step = cost_to_go(region.map_cost, sources, region.settings.connectivity)  # may cross avoided cells
            path = path_from_field(field, step, (int(cell[0]), int(cell[1])))
            if path is not None:
                return np.asarray(path.cells, dtype=np.int64)
        inside = [self.shown[k] for k in np.flatnonzero(avoided)]
        raise StartInAvoidedPlace(
            f"the start ({x0[0]:.2f}, {x0[1]:.2f}) lies inside a place to avoid ({', '.join(sorted(set(inside)))}) "
            "with no free way out of it"
        )
