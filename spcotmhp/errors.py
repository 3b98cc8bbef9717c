"""Exceptions raised for bad input, one class per cause (in the spirit of Nav2's planner exceptions).

The CLI turns any :class:`SpcotmhpError` into a one-line ``error: ...`` message and exit status 2; the HTTP
service answers with the class's ``http_status`` and the message as ``detail``. Callers can catch a whole family
(``except PlanningError``) or one cause (``except StartBlocked``).
"""

from __future__ import annotations


class SpcotmhpError(Exception):
    """Base class of every error the library raises on purpose (bad files, bad arguments, impossible plans)."""

    http_status: int = 422


class MapError(SpcotmhpError):
    """A ROS map_server YAML or image is missing, malformed or unsupported."""


class RobotBodyError(MapError):
    """The robot's body (radius, footprint polygon, inflation settings, a Nav2 params file) is malformed or out
    of range (:mod:`spcotmhp.metric.body`), or a recorded costmap_ros.csv contradicts it."""


class DatasetError(SpcotmhpError):
    """A dataset folder is missing a file, or a file has rows that do not parse."""


class BuildingError(DatasetError):
    """A building folder's building.yaml is missing or malformed, or disagrees with its floors (a floor's dataset,
    a connector off its floor's free space, floors of different resolutions); the message names the field."""


class ModelError(SpcotmhpError):
    """A model folder is missing, corrupt, or from an incompatible format version."""


class ModelValueError(ModelError, ValueError):
    """A model value (an array entry, a hyper-parameter) lies outside the range the model can use: not finite,
    not a distribution, a covariance that is not positive definite or too ill-conditioned to invert, a
    hyper-parameter outside its documented range (:mod:`spcotmhp.learning.model_values`). Raised on loading a
    model folder and on constructing a model or its hyper-parameters; also a ``ValueError``."""


# ---- instructions -----------------------------------------------------------------------------------------
class InstructionError(SpcotmhpError):
    """An instruction cannot be understood (base class of the causes below)."""


class EmptyInstruction(InstructionError):
    """The instruction (text, structured form or N-best list) holds nothing to plan for."""


class UnknownPlaceWord(InstructionError):
    """A word is used as a place but no place of the map carries it (the message suggests near misses)."""


class NotUnderstood(UnknownPlaceWord):
    """A word the grammar has no class for, said where no place is expected ("open the fridge"), and not talk that
    could be passed over (:mod:`spcotmhp.language.talk`): the message names the words, not as unknown places. A
    subclass of :class:`UnknownPlaceWord` (what such words were reported as before), so callers that catch that
    one catch both."""


class UnsupportedPhrase(InstructionError):
    """The instruction asks for something the planner cannot honour yet ("the second bedroom", "or",
    "next to", "on the left", "wait"); the message names the words."""


class AmbiguousPlace(InstructionError):
    """A word that may name places of different kinds ("bathroom" beside a bath, a toilet and a washroom): the
    message lists what it may name. (A word several names share, "the corridor" beside an east and a south
    corridor, names them all since issue 34: the closest is meant.)"""


class UnresolvedRelation(InstructionError):
    """A relation ("the bedroom closest to the bath") picks no place, or several about equally; the message names
    the candidates and their measures."""


class MalformedInstruction(InstructionError):
    """A structured instruction or an N-best list does not have the accepted shape or values."""


class InstructionTooLarge(InstructionError):
    """The instruction is longer, or names more waypoints or avoided places, than the configured limits."""

    http_status = 413


class UnknownFloor(InstructionError):
    """An instruction or a start names a floor the building does not have ("upstairs" on the top floor, floor 7
    of five); the message lists the floors."""


class PlaceNotOnFloor(InstructionError):
    """An instruction names a place on a floor where no place of that name is; the message says on which floors
    places of that name are."""


class UnsupportedLanguage(InstructionError):
    """No grammar (or recogniser) for the requested language."""


# ---- planning ---------------------------------------------------------------------------------------------
class PlanningError(SpcotmhpError):
    """No plan can be made (base class of the causes below)."""


class InvalidSettings(PlanningError):
    """A planner or graph setting is out of range."""


class StartOutsideMap(PlanningError):
    """The start pose lies outside the map's bounds, or is not two finite numbers (x, y)."""


class StartBlocked(PlanningError):
    """The start pose is in an occupied or unknown cell, or cut off from every place."""


class PoseRejected(PlanningError):
    """A robot pose message cannot be planned from: in another frame, not finite, or off the map (the ROS 2
    node; the pose is dropped and instructions wait for a valid one)."""


class TransformUnavailable(PoseRejected):
    """A pose's frame has no chain of transforms to the map frame (spcotmhp.ros.tf_tree): no frame of that name
    was heard on /tf or /tf_static, or it is in another tree, within the lookup's timeout."""


class NoValidPose(PlanningError):
    """No robot pose to plan from: none has arrived yet, or the latest was rejected (:class:`PoseRejected`);
    an earlier pose is never used in its place."""


class StartInAvoidedPlace(PlanningError):
    """The start pose lies inside a place the instruction says to avoid."""


class ConflictingInstruction(PlanningError):
    """Every place that could end a stage is excluded by the instruction itself (avoided, or "not the ...")."""


class NoReachablePlace(PlanningError):
    """No free path for the robot reaches a place carrying the requested words."""

    http_status = 409


class PlaceCutOff(NoReachablePlace):
    """A place the instruction names lies only in free space the start cannot reach: the robot's free space is
    cut (a closed door, a gap in the map, furniture) between them."""


class FloorUnreachable(NoReachablePlace):
    """No connector route (stairs, lifts) from the start's floor reaches the floor a stage must end on."""


class HorizonTooShort(PlanningError):
    """A plan exists only with more place-to-place steps than the topological horizon E allows."""


class PlanningTimeout(PlanningError):
    """Planning did not finish within the time budget."""

    http_status = 503


class TeachingError(SpcotmhpError):
    """A teaching event cannot be learned from: an empty or over-long utterance, a position that is not finite,
    off the map, in unknown space or in a wall, or image features that do not fit the model (the model is left
    unchanged)."""


class NotANaming(TeachingError):
    """A teaching utterance that names no place: a greeting, a question, a negation, an instruction
    (:mod:`spcotmhp.language.naming`); nothing is learned."""


class TeachingBusy(TeachingError):
    """Too many teaches are queued for this model (or from this client), or one did not finish within the time
    budget; try again shortly (HTTP 503 with Retry-After)."""

    http_status = 503


class DriveError(SpcotmhpError):
    """The ROS 2 node could not have Nav2 drive a plan (spcotmhp.ros.drive); the plan itself was made."""


class Nav2Unavailable(DriveError):
    """No Nav2 action server answers (FollowPath on controller_server, NavigateThroughPoses on bt_navigator)."""


class Nav2Rejected(DriveError):
    """Nav2 rejected the goal (for example, not yet active, or the goal's frame unknown to it)."""


class Nav2Failed(DriveError):
    """Nav2 aborted the goal (its error code and message say why: no progress, no valid control, a tf error...)."""


class SpeechBusy(InstructionError):
    """The ROS 2 node's recogniser has as many utterances waiting or being recognised as it takes
    (spcotmhp.ros.hearing); say it again shortly."""

    http_status = 503
