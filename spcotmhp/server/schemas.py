"""Request and response bodies of the HTTP service (pydantic; they also make its OpenAPI schema)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, StrictBool, field_validator, model_validator

from spcotmhp.errors import TeachingError
from spcotmhp.learning.model_values import MAX_WORD_CHARS
from spcotmhp.learning.observations import MAX_UTTERANCE_CHARS, utterance_words
from spcotmhp.planning.instructions import MAX_CHARS, MAX_HYPOTHESES

Finite = Annotated[float, Field(allow_inf_nan=False)]
# a number a client sends: a JSON number, never true/false (read as 1/0) nor a string of digits
Number = Annotated[float, Field(allow_inf_nan=False, strict=True)]
# a place word of a structured instruction: as long as a model's vocabulary word may be (model_values)
Word = Annotated[str, Field(min_length=1, max_length=MAX_WORD_CHARS)]
Point = tuple[Finite, Finite]

# a size guard only: the planner's own limits (spcotmhp.planning.instructions.MAX_CHARS, MAX_WAYPOINTS, ...)
# decide what is too large to plan and answer it with InstructionTooLarge (413), one rule in one place
MAX_TEXT = 16 * MAX_CHARS


class Hypothesis(BaseModel):
    """One recogniser hypothesis of an N-best list (Eq. 25): its text and score (a log-likelihood or a
    probability; the planner normalises them)."""

    model_config = ConfigDict(extra="forbid")
    text: str = Field(min_length=1, max_length=MAX_TEXT)
    score: Number


Words = Annotated[list[Word], Field(min_length=1, max_length=20)]


class RelatedPlace(BaseModel):
    """A place that a relation picks among the places of its name ("the bedroom closest to the bath")."""

    model_config = ConfigDict(extra="forbid")
    words: Words
    relation: Literal["closest", "farthest", "next_to", "between", "largest", "smallest"] | None = None
    of: list[Words] = Field(default=[], max_length=2, description="The relation's other places (two for 'between').")
    floor: int | Annotated[str, Field(min_length=1, max_length=64)] | None = Field(
        None, description="A building's model only: the floor of this place (index, name, upstairs, downstairs)."
    )


Place = Words | RelatedPlace


class StructuredInstruction(BaseModel):
    """An instruction already understood: the goal's words, each waypoint's words in order, places to avoid,
    places not to end in; a place may pick one instance of its name by a relation; a speed and waits."""

    model_config = ConfigDict(extra="forbid")
    goal: Place
    waypoints: list[Place] = Field(default=[], max_length=20)
    avoid: list[Place] = Field(default=[], max_length=20)
    not_goal: list[Place] = Field(
        default=[], max_length=20, description="Places that must not be the goal (they may be passed)."
    )
    speed: Literal["slow", "fast"] | None = None
    waits: list[tuple[int, Finite | None]] = Field(
        default=[], max_length=21, description="[stage, seconds or null]: stages are the waypoints, then the goal."
    )


class PlanRequest(BaseModel):
    """``POST /plan``: exactly one of ``instruction``, ``nbest`` or ``structured``, and the start pose."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{"instruction": "go to the bedroom via the corridor", "start": [-3.9, -3.5]}]},
    )
    instruction: str | None = Field(
        None,
        min_length=1,
        max_length=MAX_TEXT,
        description='A sentence, e.g. "go to the bedroom via the corridor".',
    )
    nbest: list[Hypothesis] | None = Field(
        None,
        min_length=1,
        max_length=MAX_HYPOTHESES,
        description="Recogniser hypotheses, weighed as bags of words (Eq. 25).",
    )
    structured: StructuredInstruction | None = None
    start: tuple[Number, Number] = Field(description="Start pose [x, y] in metres, map frame.")
    model: str | None = Field(None, max_length=200, description="Served model name (default: the first).")
    lang: Literal["en", "ja"] | None = Field(None, description="Instruction language (default: detected).")
    floor: int | str | None = Field(
        None,
        description="A building's model only: the start's floor (its index or name); ``start`` is in that floor's "
        "map frame. Places of a structured instruction may carry a floor too (index, name, upstairs, downstairs).",
    )

    @model_validator(mode="after")
    def _one_instruction(self) -> PlanRequest:
        given = [k for k in ("instruction", "nbest", "structured") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                "give exactly one of 'instruction', 'nbest' or 'structured'"
                + (f" (got {', '.join(given)})" if given else "")
            )
        return self

    def source(self) -> str | list[tuple[str, float]] | dict:
        """What the planner takes (a sentence, [(text, score)] or a structured mapping)."""
        if self.nbest is not None:
            return [(h.text, h.score) for h in self.nbest]
        if self.structured is not None:
            return self.structured.model_dump(exclude_defaults=True)
        return str(self.instruction)


class TeachRequest(BaseModel):
    """``POST /teach``: what a place is called (an utterance said there) and where, in the map frame."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={"examples": [{"utterance": "this is alice's room", "x": -3.45, "y": 5.65}]},
    )
    utterance: str = Field(min_length=1, max_length=MAX_UTTERANCE_CHARS, description='e.g. "this is alice\'s room".')
    x: Number
    y: Number
    model: str | None = Field(None, max_length=200, description="Served model name (default: the first).")
    floor: int | Annotated[str, Field(min_length=1, max_length=64)] | None = Field(
        None, description="A building's model only (required there): the floor taught on; x, y in its map frame."
    )
    answer: StrictBool = Field(
        False, description="The utterance answers one of GET /questions (learned as docs/teaching.md says)."
    )

    @field_validator("utterance")
    @classmethod
    def _learnable(cls, utterance: str) -> str:
        """The learner's own limits (``observations.utterance_words``: its words' lengths), a 422 naming the field
        rather than a ModelValueError from the model's vocabulary check."""
        try:
            utterance_words(utterance)
        except TeachingError as exc:
            raise ValueError(str(exc)) from None
        return utterance


class TeachResponse(BaseModel):
    """The place the utterance was assigned to, its label and place words, and the times of the update."""

    model: str
    place: int
    label: str
    names: list[str]
    new_place: bool
    name: str | None = Field(None, description="The name the utterance taught, as read.")
    outcome: Literal["new place", "joined place"] = Field(..., description="Whether the teach made a new place.")
    named: bool = Field(..., description="Whether the name now names that place (its label carries it).")
    message: str = Field(..., description="What happened, in one line.")
    places: int
    place_words: list[str]
    time_update_s: float
    time_export_s: float
    time_planner_s: float


class Question(BaseModel):
    x: float
    y: float
    ask: str
    candidates: list[str] = Field(..., description="The names the model expects there, most probable first.")
    why: str
    information: float = Field(..., description="Entropy of the name expected there (nats): what an answer tells.")


class QuestionsResponse(BaseModel):
    """Where an answer would help the model most, best first; answer with POST /teach at (x, y)."""

    model: str
    questions: list[Question]


class PlanPlaceOut(BaseModel):
    id: int
    name: str
    role: Literal["start", "via", "waypoint", "goal"]
    label: str
    point: Point | None
    chosen_by: str | None = Field(None, description='The relation that picked it, e.g. "the one closest to the bath".')


class InstructionOut(BaseModel):
    text: str | None
    goal: dict[str, float]
    waypoints: list[dict[str, float]]
    avoid: list[dict[str, float]]
    not_goal: list[dict[str, float]] = []
    relations: dict[str, str] = {}
    understood: str = Field("", description="What was understood, in words.")
    heard: list[str] = Field(
        [], description="What reading the sentence did beyond its grammar: a self-correction, talk passed over."
    )


class WaitOut(BaseModel):
    id: int
    label: str
    seconds: float | None = Field(description="How long to wait there; null: until the next instruction.")


class GoalOptionOut(BaseModel):
    id: int
    label: str
    length_m: float
    log_prob: float


class PlanResponse(BaseModel):
    """A plan (``Plan.to_dict()``) and the model that made it."""

    model: str
    path: list[Point] = Field(description="[x, y] metres from the start to the goal.")
    places: list[PlanPlaceOut]
    length_m: float
    log_prob: float
    time_online_s: float
    time_precompute_s: float
    explanation: str
    instruction: InstructionOut
    goal_options: list[GoalOptionOut]
    speed: Literal["slow", "fast"] | None = Field(None, description="The speed asked for, for the controller.")
    waits: list[WaitOut] = Field(default=[], description="Where to wait and how long, for the controller.")
    notes: list[str] = []


class BuildingPlaceOut(PlanPlaceOut):
    floor: int


class BuildingGoalOptionOut(GoalOptionOut):
    floor: int
    route_m: float = Field(description="Metres walked plus the connectors' cost_m.")


class SegmentOut(BaseModel):
    floor: int
    path: list[Point] = Field(description="[x, y] metres in that floor's map frame.")
    length_m: float


class StopOut(BaseModel):
    floor: int
    x: float
    y: float


class RideOut(BaseModel):
    model_config = ConfigDict(populate_by_name=True)
    name: str
    kind: Literal["stairs", "lift"]
    from_: StopOut = Field(alias="from")
    to: StopOut
    cost_m: float


class BuildingPlanResponse(PlanResponse):
    """A plan in a building (``BuildingPlan.to_dict()``): the single-floor keys (``path``: the first segment's)
    and one segment per floor, in order, with the connector ridden between consecutive segments."""

    places: list[BuildingPlaceOut]  # type: ignore[assignment]  # the single floor's places, with their floor
    goal_options: list[BuildingGoalOptionOut]  # type: ignore[assignment]  # likewise
    floor: int = Field(description="The start's floor.")
    goal_floor: int
    segments: list[SegmentOut]
    rides: list[RideOut]
    route_m: float


AnyPlanResponse = Annotated[BuildingPlanResponse | PlanResponse, Field(union_mode="left_to_right")]
"""What ``POST /plan`` returns: a building's plan (with segments) or a single floor's."""


class AudioPlanResponse(PlanResponse):
    """A plan from speech, with the recognised hypotheses it was planned from."""

    hypotheses: list[Hypothesis]


class AudioBuildingPlanResponse(BuildingPlanResponse):
    """A plan in a building from speech, with the recognised hypotheses it was planned from."""

    hypotheses: list[Hypothesis]


AnyAudioPlanResponse = Annotated[AudioBuildingPlanResponse | AudioPlanResponse, Field(union_mode="left_to_right")]
"""What ``POST /plan/audio`` returns."""


class PlaceOut(BaseModel):
    id: int
    name: str
    label: str = Field(description='Unique display label, e.g. "bedroom #2".')
    mean: Point
    covariance: tuple[Point, Point]
    colour: str


class MergeOut(BaseModel):
    """A taught name without a place of its own (spcotmhp/learning/merges.py)."""

    name: str
    other: str = Field(description="The name the shared place is called by.")
    place: int
    taught: int = Field(description="Teaches of `name` at the place.")
    other_taught: int = Field(description="Teaches of `other` at the place.")
    apart_m: float = Field(description="Distance between the means of the two names' teaching points there.")
    x: float = Field(description="Mean of `name`'s teaching points there (where the first question asks).")
    y: float
    sentence: str


class PlacesResponse(BaseModel):
    model: str
    places: list[PlaceOut]
    edges: list[tuple[int, int]] = Field(description="Place pairs with (psi_ab + psi_ba) / 2 >= 1/K (Fig. 3).")
    place_words: list[str]
    merges: list[MergeOut] = Field(
        default_factory=list,
        description="Every taught name that no longer names a place of its own, e.g. 'playroom and bedroom share "
        "place 3; taught 5 and 6 times, 4.1 m apart'.",
    )


class MapInfo(BaseModel):
    """How ``GET /map.png`` maps onto the map frame: pixel (0, 0) is (x0, y1), pixel (width, height) is (x1, y0)."""

    model: str
    image: str
    extent: tuple[float, float, float, float] = Field(description="[x0, x1, y0, y1] metres.")
    width: int
    height: int
    resolution: float


class ModelOut(BaseModel):
    """A served model as ``GET /models`` lists it (its folder is not disclosed)."""

    name: str
    places: int
    place_words: list[str]
    time_precompute_s: float


class ModelsResponse(BaseModel):
    default: str
    models: list[ModelOut]


class Health(BaseModel):
    status: Literal["ok"]
    models: list[str]


class ErrorResponse(BaseModel):
    """Every 4xx/5xx answer: a one-line message, plus details where useful (known place words, models)."""

    model_config = ConfigDict(extra="allow")
    detail: str
